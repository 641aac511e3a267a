"""Campbell diagram and critical speeds of a solid FE wheel (stress stiffening, spin softening).

:func:`rotation_terms` gives the rotation matrices of a :class:`WheelSector` built from a
solid (:mod:`fricdamp.structure.solid_rotation`) on the sector's DOFs, per ``Omega^2``:
the centrifugal prestress is the zero-ND (axisymmetric) static response of the sector with
its cyclic cuts and supports, ``K_0 u_1 = T_0^T f_c``, so the wheel's stiffness at speed is

    K(Omega) = K + Omega^2 (K_sigma(u_1) - M_P)

(linear prestress; Coriolis neglected, as for the beam wheel's
:func:`~fricdamp.models.tieboss_wheel.studies.campbell_by_nd`).

:func:`campbell_solid` evaluates the frequencies by ND over a speed range without an
eigen-solution of the ~10^4-10^5-DOF sector at every speed: for each ND the lowest modes at
the lowest and the highest speed span a Rayleigh-Ritz basis (exact at both ends: both sets of
modes are in the span), and each speed costs a 2m x 2m eigenproblem. The test
(tests/validation/test_solid_campbell.py) checks the mid-range speed against a direct
solution (1e-6). Critical speeds 003 (1) solve ``f_nd(n) = p o n / 60`` by Brent's method on
the same reduced branch.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.studies import CampbellByND
from fricdamp.structure.cyclic import nodal_diameter_modes
from fricdamp.structure.system import RotationTerms

__all__ = ["campbell_solid", "critical_speeds_solid", "rotation_terms"]


def rotation_terms(sector, solid) -> RotationTerms:
    """Stress stiffening, spin softening and centrifugal load per ``Omega^2`` on the DOFs of
    ``sector`` (a :class:`~fricdamp.models.contact_wheel.WheelSector` made by
    :func:`~fricdamp.models.contact_wheel.sector_from_solid` from ``solid``).

    Returns
    -------
    RotationTerms
        ``stress_stiffening`` [N/m per (rad/s)^2], ``spin_softening`` [kg],
        ``centrifugal_load`` [N s^2], all on the sector's DOFs; ``gyroscopic`` None.
    """
    from fricdamp.structure.solid_rotation import (
        centrifugal_load,
        geometric_stiffness,
        spin_softening,
    )

    dofs = getattr(sector, "solid_dofs", None)
    if dofs is None:
        raise ModelError("rotation terms need a sector built from a solid model "
                         "(sector_from_solid); matrix-only sectors need stress_stiffening "
                         "and spin_softening matrices of their own")
    cyc = sector.cyclic
    if cyc.frame != "cartesian":
        raise ModelError("rotation terms of solid sectors need Cartesian DOF frames")
    if solid.n_dof <= int(np.max(dofs)):
        raise ModelError("the solid model does not match the sector's DOFs")
    MP_full = spin_softening(solid, cyc.axis)
    f_full = centrifugal_load(solid, cyc.axis)
    MP = MP_full[dofs][:, dofs].tocsr()
    f = f_full[dofs]
    T = cyc.cyclic_transform(0)
    K0 = (T.T @ cyc.K @ T).tocsc()
    u = np.asarray(T @ spla.spsolve(K0, T.T @ f))
    u_full = np.zeros(solid.n_dof)
    u_full[dofs] = u
    Kg = geometric_stiffness(solid, u_full)[dofs][:, dofs].tocsr()
    return RotationTerms(spin_softening=MP, stress_stiffening=Kg, centrifugal_load=f)


def _at_speed(cyc, rot: RotationTerms, omega: float):
    K = cyc.K + omega ** 2 * (rot.stress_stiffening - rot.spin_softening)
    return replace(cyc, K=sp.csr_matrix(0.5 * (K + K.T)))


@dataclass(frozen=True)
class _Branch:
    """Rayleigh-Ritz model of one ND: ``(K0 + Omega^2 K1) x = w^2 M x`` in 2m coordinates."""

    nd: int
    K0: np.ndarray
    K1: np.ndarray

    def frequencies(self, omega: float) -> np.ndarray:
        lam = sla.eigh(self.K0 + omega ** 2 * self.K1, eigvals_only=True)
        return np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)


def _branch(cyc, rot: RotationTerms, nd: int, omega_max: float, n_ritz: int) -> _Branch:
    T = cyc.cyclic_transform(nd)
    TH = T.conj().T
    ind = cyc.independent
    X = [nodal_diameter_modes(cyc, nd, n_ritz).shapes[ind]]
    if omega_max > 0:
        X.append(nodal_diameter_modes(_at_speed(cyc, rot, omega_max), nd,
                                      n_ritz).shapes[ind])
    V = np.hstack(X)

    def red(A):
        return np.asarray(V.conj().T @ (TH @ (A @ (T @ V))))

    Mr = red(cyc.M)
    Mr = 0.5 * (Mr + Mr.conj().T)
    # M-orthonormal basis of the span, dropping directions the two mode sets share
    w, Q = np.linalg.eigh(Mr)
    keep = w > 1e-10 * w.max()
    B = Q[:, keep] / np.sqrt(w[keep])

    def sym(A):
        A = B.conj().T @ red(A) @ B
        return 0.5 * (A + A.conj().T)

    K1 = rot.stress_stiffening - rot.spin_softening
    return _Branch(nd=int(nd), K0=sym(cyc.K), K1=sym(K1))


def campbell_solid(sector, rotation: RotationTerms, rpm, nds=None, *,
                   n_ritz: int = 3) -> CampbellByND:
    """First-family frequencies by ND of the rotating solid wheel (contacts open).

    Parameters
    ----------
    sector : WheelSector
    rotation : RotationTerms
        From :func:`rotation_terms`.
    rpm : array_like
        Speeds [rpm] >= 0.
    nds : sequence of int, optional
        Nodal diameters (default all).
    n_ritz : int
        Modes per end speed in the Ritz basis (default 3: the first family is exact at the
        ends and within 1e-6 between; more if families cross).

    Returns
    -------
    CampbellByND
        ``frequency_hz`` (n_speeds, n_nd) in the rotating frame.
    """
    cyc = sector.cyclic
    rpm = np.atleast_1d(np.asarray(rpm, dtype=float))
    if rpm.ndim != 1 or rpm.size == 0 or not np.all(np.isfinite(rpm)) or np.any(rpm < 0):
        raise ModelError(f"rpm must be a non-empty list of finite speeds >= 0, got {rpm!r}")
    nds = cyc.nodal_diameters if nds is None else np.asarray(
        [cyc._check_nd(nd) for nd in np.atleast_1d(nds)])
    omega = rpm * np.pi / 30.0
    F = np.empty((rpm.size, len(nds)))
    for j, nd in enumerate(nds):
        br = _branch(cyc, rotation, int(nd), float(omega.max()), n_ritz)
        F[:, j] = [br.frequencies(w)[0] for w in omega]
    return CampbellByND(rpm=rpm, nd=np.asarray(nds, dtype=int), frequency_hz=F)


def critical_speeds_solid(sector, rotation: RotationTerms, *, orders, pulses: int = 8,
                          rpm_range=(60.0, 450.0), n_ritz: int = 3) -> list[dict]:
    """Critical speeds 003 (1) of the solid wheel: ``f_nd(n) = p o n / 60`` for each
    ``(o, nd)`` of ``orders``, by Brent's method on the Ritz branch of :func:`campbell_solid`.

    Returns
    -------
    list of dict
        ``order``, ``nd``, ``pulses``, ``frequency_hz`` and ``rpm`` (None when the branch does
        not meet the line in ``rpm_range``).
    """
    from scipy.optimize import brentq

    lo, hi = (float(v) for v in rpm_range)
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo < hi):
        raise ModelError(f"rpm_range must be (low, high) with 0 <= low < high, got "
                         f"{rpm_range!r}")
    cyc = sector.cyclic
    out = []
    branches = {}
    for o, nd in orders:
        nd = cyc._check_nd(int(nd))
        if nd not in branches:
            branches[nd] = _branch(cyc, rotation, nd, hi * np.pi / 30.0, n_ritz)
        br = branches[nd]

        def g(n, o=o, br=br):
            return br.frequencies(n * np.pi / 30.0)[0] - pulses * o * n / 60.0

        entry = {"order": int(o), "nd": int(nd), "pulses": int(pulses)}
        if g(lo) * g(hi) > 0:
            entry.update(frequency_hz=None, rpm=None)
        else:
            n = brentq(g, lo, hi, xtol=1e-9)
            entry.update(frequency_hz=float(br.frequencies(n * np.pi / 30.0)[0]),
                         rpm=float(n))
        out.append(entry)
    return out
