"""Planar Euler-Bernoulli beam finite elements (bending in one plane).

Two DOFs per node, transverse deflection w [m] and rotation theta = dw/dx [rad]; cubic
Hermite shape functions, exact element stiffness and consistent mass::

    K_e = EI / l^3 [[ 12,  6l,  -12,  6l ],       M_e = rho A l / 420 [[156,  22l,  54, -13l ],
                    [ 6l,  4l^2, -6l,  2l^2],                            [22l,  4l^2, 13l, -3l^2],
                    [-12, -6l,   12, -6l ],                              [54,  13l, 156, -22l ],
                    [ 6l,  2l^2, -6l,  4l^2]]                            [-13l, -3l^2, -22l, 4l^2]]

Nodal displacements of a point-loaded beam are exact; eigenfrequencies converge as h^4
(tests/unit/test_beam.py against ``(beta_n L)^2 sqrt(EI / (rho A L^4)) / (2 pi)``).

References
----------
Przemieniecki (1968), *Theory of Matrix Structural Analysis*, ch. 5 and 11.
"""

from __future__ import annotations

import numpy as np

from fricdamp.errors import ModelError, check_positive
from fricdamp.structure.system import MechanicalSystem

__all__ = ["CANTILEVER_BETA_L", "cantilever_beam", "euler_bernoulli_matrices", "node_dof"]

#: Roots beta_n L of 1 + cos(bL) cosh(bL) = 0 (clamped-free), first five modes.
CANTILEVER_BETA_L = (1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349, 14.1371683910)


def euler_bernoulli_matrices(n_elements: int, length_m: float, E_Pa: float, rho_kg_m3: float,
                             area_m2: float, inertia_m4: float) -> tuple[np.ndarray, np.ndarray]:
    """Free-free mass and stiffness matrices of a uniform beam, 2 (n_elements + 1) DOFs.

    DOF order ``[w0, theta0, w1, theta1, ...]`` along x from 0 to ``length_m``.

    Parameters
    ----------
    n_elements : int
        Number of equal elements (>= 1).
    length_m : float
        Beam length L [m].
    E_Pa : float
        Young's modulus [Pa].
    rho_kg_m3 : float
        Density [kg/m^3].
    area_m2 : float
        Cross-section area A [m^2].
    inertia_m4 : float
        Second moment of area I about the bending axis [m^4].

    Returns
    -------
    M : ndarray, shape (2 n + 2, 2 n + 2)
        Consistent mass matrix [kg, kg m, kg m^2].
    K : ndarray, shape (2 n + 2, 2 n + 2)
        Stiffness matrix [N/m, N, N m].
    """
    if int(n_elements) != n_elements or n_elements < 1:
        raise ModelError(f"n_elements must be an integer >= 1, got {n_elements!r}")
    for name, v, unit in (("length_m", length_m, "m"), ("E_Pa", E_Pa, "Pa"),
                          ("rho_kg_m3", rho_kg_m3, "kg/m^3"), ("area_m2", area_m2, "m^2"),
                          ("inertia_m4", inertia_m4, "m^4")):
        check_positive(name, v, unit=unit)
    n = int(n_elements)
    le = float(length_m) / n
    EI = float(E_Pa) * float(inertia_m4)
    rA = float(rho_kg_m3) * float(area_m2)
    ke = EI / le**3 * np.array([[12, 6 * le, -12, 6 * le],
                                [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                                [-12, -6 * le, 12, -6 * le],
                                [6 * le, 2 * le**2, -6 * le, 4 * le**2]])
    me = rA * le / 420.0 * np.array([[156, 22 * le, 54, -13 * le],
                                     [22 * le, 4 * le**2, 13 * le, -3 * le**2],
                                     [54, 13 * le, 156, -22 * le],
                                     [-13 * le, -3 * le**2, -22 * le, 4 * le**2]])
    ndof = 2 * (n + 1)
    K = np.zeros((ndof, ndof))
    M = np.zeros((ndof, ndof))
    for e in range(n):
        idx = slice(2 * e, 2 * e + 4)
        K[idx, idx] += ke
        M[idx, idx] += me
    return M, K


def node_dof(node: int, kind: str = "w") -> int:
    """Index of DOF ``kind`` ("w" deflection or "theta" rotation) of free node ``node``.

    Nodes of :func:`cantilever_beam` are numbered 1..n_elements from the clamp (node 0,
    which has no DOFs) to the free tip.
    """
    if int(node) != node or node < 1:
        raise ModelError(f"node must be an integer >= 1 (node 0 is clamped), got {node!r}")
    if kind not in ("w", "theta"):
        raise ModelError(f"kind must be 'w' or 'theta', got {kind!r}")
    return 2 * (int(node) - 1) + (0 if kind == "w" else 1)


def cantilever_beam(n_elements: int, length_m: float, E_Pa: float, rho_kg_m3: float,
                    area_m2: float, inertia_m4: float, *,
                    rayleigh: tuple[float, float] | None = None,
                    **kwargs) -> MechanicalSystem:
    """Clamped-free Euler-Bernoulli beam: ``2 n_elements`` DOFs, clamp at x = 0.

    Parameters
    ----------
    n_elements : int
        Number of equal elements (>= 1); free nodes 1..n_elements (tip = n_elements).
    length_m, E_Pa, rho_kg_m3, area_m2, inertia_m4 : float
        Length [m], Young's modulus [Pa], density [kg/m^3], area [m^2] and second moment of
        area [m^4], all > 0.
    rayleigh : (alpha, beta), optional
        Rayleigh damping ``D = alpha M + beta K``, alpha [1/s] >= 0, beta [s] >= 0.
    **kwargs
        Passed to :class:`MechanicalSystem` (contacts, loads, static_load, name).

    Returns
    -------
    MechanicalSystem
        DOFs ``[w1, theta1, ..., wn, thetan]`` (see :func:`node_dof`);
        ``meta["x_nodes_m"]`` holds the node positions 0..L.

    Examples
    --------
    >>> import numpy as np, scipy.linalg
    >>> beam = cantilever_beam(8, 2.0, 185e9, 7830.0, 0.03, 2.5e-5)
    >>> beam.n_dof
    16
    >>> f1 = np.sqrt(scipy.linalg.eigvalsh(beam.K, beam.M)[0]) / (2 * np.pi)
    >>> exact = 1.8751040687**2 * np.sqrt(185e9 * 2.5e-5 / (7830.0 * 0.03 * 2.0**4)) / (2 * np.pi)
    >>> bool(abs(f1 / exact - 1) < 1e-5)
    True
    """
    M, K = euler_bernoulli_matrices(n_elements, length_m, E_Pa, rho_kg_m3, area_m2,
                                    inertia_m4)
    M, K = M[2:, 2:], K[2:, 2:]
    D = None
    if rayleigh is not None:
        try:
            a, b = rayleigh
        except (TypeError, ValueError):
            raise ModelError(f"rayleigh must be a pair (alpha [1/s], beta [s]), got "
                             f"{rayleigh!r}") from None
        check_positive("rayleigh alpha", a, unit="1/s", allow_zero=True)
        check_positive("rayleigh beta", b, unit="s", allow_zero=True)
        D = float(a) * M + float(b) * K
    n = int(n_elements)
    names = tuple(f"{k}{i}" for i in range(1, n + 1) for k in ("w", "theta"))
    meta = dict(kwargs.pop("meta", {}))
    meta.update(x_nodes_m=np.linspace(0.0, float(length_m), n + 1),
                EI_N_m2=float(E_Pa) * float(inertia_m4),
                rhoA_kg_m=float(rho_kg_m3) * float(area_m2), length_m=float(length_m))
    kwargs.setdefault("name", "cantilever beam")
    return MechanicalSystem(M=M, K=K, D=D, dof_names=names, meta=meta, **kwargs)
