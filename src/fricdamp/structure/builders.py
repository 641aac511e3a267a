"""Builders of MechanicalSystem from lumped parameters and from user matrices."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from fricdamp.errors import ModelError, check_positive
from fricdamp.structure.system import MechanicalSystem


def chain(masses: Sequence[float], springs: Sequence[float], *,
          dampers: Sequence[float] | None = None, ground: str = "first",
          **kwargs) -> MechanicalSystem:
    """Lumped chain of masses connected by springs (and dashpots).

    Parameters
    ----------
    masses : sequence of float, length n
        Masses [kg], > 0.
    springs : sequence of float
        Spring stiffnesses [N/m], >= 0. With ``ground="first"`` there are n springs:
        ground-m1, m1-m2, ..., m(n-1)-mn. With ``ground="both"`` there are n + 1 (the last
        ties mn to ground). With ``ground="none"`` there are n - 1.
    dampers : sequence of float, optional
        Dashpot coefficients [N s/m] in parallel with the springs, same length; >= 0.
    ground : {"first", "both", "none"}
        Where the chain is tied to the ground.
    **kwargs
        Passed to :class:`MechanicalSystem` (contacts, loads, static_load, dof_names, name).

    Examples
    --------
    >>> sys = chain([1.0, 1.0], [100.0, 50.0])
    >>> sys.K.tolist()
    [[150.0, -50.0], [-50.0, 50.0]]
    """
    m = check_positive("masses", np.atleast_1d(np.asarray(masses, float)), unit="kg")
    n = m.size
    if n == 0:
        raise ModelError("masses must have at least one entry (one mass [kg] per DOF), got none")
    expected = {"first": n, "both": n + 1, "none": n - 1}
    if ground not in expected:
        raise ModelError(f"ground must be 'first', 'both' or 'none', got {ground!r}")
    k = check_positive("springs", np.atleast_1d(np.asarray(springs, float)), unit="N/m",
                       allow_zero=True)
    if k.size != expected[ground]:
        raise ModelError(f"springs must have {expected[ground]} entries for {n} masses with "
                         f"ground={ground!r}, got {k.size}")
    c = np.zeros_like(k) if dampers is None else check_positive(
        "dampers", np.atleast_1d(np.asarray(dampers, float)), unit="N s/m", allow_zero=True)
    if c.size != k.size:
        raise ModelError(f"dampers must have as many entries as springs ({k.size}), got {c.size}")

    def assemble(vals):
        A = np.zeros((n, n))
        off = 0
        if ground in ("first", "both"):
            A[0, 0] += vals[0]
            off = 1
        for i in range(n - 1):
            v = vals[off + i]
            A[i, i] += v
            A[i + 1, i + 1] += v
            A[i, i + 1] -= v
            A[i + 1, i] -= v
        if ground == "both":
            A[n - 1, n - 1] += vals[-1]
        return A

    return MechanicalSystem(M=np.diag(m), K=assemble(k), D=assemble(c), **kwargs)


def from_matrices(M, K, D=None, *, rayleigh: tuple[float, float] | None = None,
                  **kwargs) -> MechanicalSystem:
    """System from user matrices (dense, sparse, or paths to Matrix Market ``.mtx`` files).

    Parameters
    ----------
    M, K : array_like, sparse or path
        Mass [kg] and stiffness [N/m] matrices.
    D : array_like, sparse or path, optional
        Viscous damping [N s/m]. Mutually exclusive with ``rayleigh``.
    rayleigh : (alpha, beta), optional
        Rayleigh damping ``D = alpha M + beta K`` with alpha [1/s], beta [s], both >= 0.
    """
    from fricdamp.structure.io import read_matrix

    M = read_matrix(M, "M")
    K = read_matrix(K, "K")
    if D is not None and rayleigh is not None:
        raise ModelError("give either D or rayleigh, not both")
    if D is not None:
        D = read_matrix(D, "D")
    elif rayleigh is not None:
        a, b = rayleigh
        check_positive("rayleigh alpha", a, unit="1/s", allow_zero=True)
        check_positive("rayleigh beta", b, unit="s", allow_zero=True)
        D = a * M + b * K
    return MechanicalSystem(M=M, K=K, D=D, **kwargs)
