"""Cyclic harmonic balance: forced response of a tuned wheel with friction on ONE sector.

A wheel of ``N`` identical sectors with contacts between neighbouring sectors, forced by a
travelling wave of ``nd`` nodal diameters (an engine order), has a steady state in which
every sector repeats sector 0's motion with a time lag. This module solves for that steady
state with multi-harmonic balance and AFT on one sector only, the neighbour's contact
displacements expressed through the inter-sector phase of each harmonic.

Derivation (ours; the relations are standard in blade-damper codes but written here in the
project's conventions, those of :func:`fricdamp.solvers.hb.engine_order_load` and
:class:`fricdamp.structure.cyclic.CyclicSector`)
------------------------------------------------------------------------------------
Excitation: sector ``j`` (0-based, each in its own rotated frame) carries
``f_j(t) = Re(f~ exp(i (Omega t - j phi)))``, ``phi = 2 pi nd / N``: a wave travelling
forwards (towards increasing ``j``) for ``nd > 0``. Because the wheel is invariant under the
shift ``j -> j + 1`` and the load is invariant under the shift combined with the time lag
``phi / Omega``, the periodic state that this symmetry maps onto itself (the one continued
here; symmetry-breaking bifurcations of the full wheel are not looked for) satisfies::

    q_j(tau) = q_0(tau - j phi),   tau = Omega t        =>   Q_{j,h} = Q_{0,h} exp(-i h j phi)

for the phasor ``Q_{j,h}`` of harmonic ``h`` (``q = Re sum_h Q_h e^{i h tau}``). So harmonic
``h`` of sector 0 obeys the cyclic constraint of the harmonic index ``nd_h = -h nd (mod N)``:
``u_R = exp(-i h phi) R u_L`` with ``T_h = CyclicSector.cyclic_transform(nd_h)`` (the static
term ``h = 0`` is the 0ND, real, constraint).

Contact between sector 0 (its own DOFs, columns ``P_a``) and sector 1 (``P_b``)::

    u(tau) = P_a q_0(tau) + P_b q_1(tau)   =>   U_h = (P_a + exp(-i h phi) P_b) T_h Q~_h
                                                   =: C_h Q~_h

The same contact, seen from sector 0, is also the one between sectors -1 and 0, whose force
harmonics are ``F_{-1,h} = exp(+i h phi) F_h``. Sector 0's independent DOFs therefore
receive ``T_h^H (P_a^T F_h + exp(+i h phi) P_b^T F_h) = C_h^H F_h``: the contact enters the
sector equations through the Hermitian transpose of its own projection (a Galerkin
projection of the full-wheel equations onto the travelling-wave subspace, which is why the
sector and full-wheel solutions coincide to the Newton tolerance,
tests/validation/test_cyclic_hb.py). Per harmonic::

    Z_h(Omega) Q~_h + C_h^H F_h(U) = T_h^H f~_h,
    Z_h = T_h^H (K(Omega) - h^2 Omega^2 M + i h Omega D) T_h

and, condensed to the contact coordinates (as the "condensed" HB formulation of
:mod:`fricdamp.solvers.hb`), the residual solved by Newton is::

    U_h - u_lin,h(Omega) + R_h(Omega) F_h(U) = 0,
    R_h = C_h Z_h^{-1} C_h^H,   u_lin,h = C_h Z_h^{-1} T_h^H f~_h

with the forces ``F_h(U)`` of the contact laws from the project's AFT
(:func:`fricdamp.solvers.aft.aft`: the same laws, periodic marches and Jacobians as the
full-wheel HB). The unknowns are the ``m (2H + 1)`` real harmonics of one sector's contact
rows (45 for one 3D contact and H = 7) whatever the wheel size. Continuation in Omega (or
in the rotation speed, with ``K(Omega) = K + (Omega / E)^2 K_rot`` for an excitation
``E`` times per revolution) uses :func:`fricdamp.solvers.continuation.solve_and_continue`.

Sign conventions: the brief's ``exp(+i h 2 pi k / N)`` corresponds to a wave of ``-k`` here
(backward in ``j``); both are offered through the sign of ``nd``.

Energy: per sector and period, ``W_ext = W_visc + W_contact`` (the discrete identities of
:func:`fricdamp.solvers.aft.cycle_work` make it hold to the Newton tolerance); the
equivalent damping ratio of a resonant state is ``zeta = W_d / (4 pi E_max)`` with
``W_d = W_visc + W_contact`` and ``E_max = Omega^2 Q~_1^H M~ Q~_1 / 2`` (exact for a
viscous modal response at its natural frequency).

References
----------
Petrov & Ewins (2003), J. Turbomach. 125, 364-371 (friction HB, cyclic sectors).
Krack, Panning-von Scheidt & Wallaschek (2013), J. Sound Vib. 332, 6798-6814.
Thomas (1979), Int. J. Numer. Meth. Eng. 14, 81-102 (cyclic symmetry).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from fricdamp.errors import ModelError
from fricdamp.results import ResultMixin
from fricdamp.solvers.aft import HarmonicBasis, aft, cycle_work
from fricdamp.solvers.continuation import blas_threads, newton, solve_and_continue
from fricdamp.structure.cyclic import CyclicSector
from fricdamp.structure.system import ContactElement

__all__ = ["CyclicForcedResponse", "CyclicHarmonicBalance", "cyclic_frequency_response"]

log = logging.getLogger(__name__)


def _dense(A) -> np.ndarray:
    return A.toarray() if sp.issparse(A) else np.asarray(A)


def _phasors(Y: np.ndarray, H: int) -> np.ndarray:
    """(rows, 2H+1) real coefficients -> (H+1, rows) phasors (a - i b)."""
    C = np.empty((H + 1, Y.shape[0]), complex)
    C[0] = Y[:, 0]
    C[1:] = (Y[:, 1::2] - 1j * Y[:, 2::2]).T
    return C


def _real(C: np.ndarray) -> np.ndarray:
    """(H+1, rows) phasors -> (rows, 2H+1) real coefficients."""
    H = C.shape[0] - 1
    Y = np.empty((C.shape[1], 2 * H + 1))
    Y[:, 0] = C[0].real
    Y[:, 1::2] = C[1:].real.T
    Y[:, 2::2] = -C[1:].imag.T
    return Y


class CyclicHarmonicBalance:
    """The condensed cyclic HB problem of one sector (module docstring).

    Parameters
    ----------
    sector : CyclicSector
        The sector (M, K, D; cuts; ``n_sectors`` N). D defaults to zero.
    contacts : sequence of ContactElement
        Contacts of sector 0 with sector 1, each with a projection of shape
        ``(n_contacts * n_dir, 2 n)``: columns ``0..n-1`` on sector 0's DOFs, ``n..2n-1`` on
        sector 1's DOFs in its own frame rotated into sector 0's components (as
        :meth:`CyclicSector.contact_projection` takes them).
    nd : int
        Travelling-wave index of the fundamental (forward for ``nd > 0``; any integer, taken
        modulo N).
    force : array_like, shape (n,), complex
        Phasor ``f~`` [N] of the harmonic-1 load on sector 0's DOFs (sector j carries
        ``Re(f~ exp(i (Omega t - j phi)))``).
    harmonics : int
        Highest harmonic H.
    samples : int, optional
        AFT samples per period (default: the power of two >= 16 H).
    rotation_stiffness : array_like or sparse, shape (n, n), optional
        ``K_rot = K_sigma - K_d`` per (rad/s)^2 of spin: with ``excitations_per_rev`` E the
        stiffness at excitation frequency Omega is ``K + (Omega / E)^2 K_rot`` (continuation
        along the speed, the excitation locked to it).
    excitations_per_rev : float, optional
        E: excitation frequency / rotation frequency (required with rotation_stiffness).
    """

    def __init__(self, sector: CyclicSector, contacts: Sequence[ContactElement], nd: int,
                 force, *, harmonics: int = 5, samples: int | None = None,
                 rotation_stiffness=None, excitations_per_rev: float | None = None):
        if not isinstance(sector, CyclicSector):
            raise ModelError(f"sector must be a CyclicSector, got {type(sector).__name__}")
        if int(nd) != nd:
            raise ModelError(f"nd must be an integer, got {nd!r}")
        self.sector = sector
        self.N = sector.n_sectors
        self.nd = int(nd)
        n = sector.n_dof
        self.n = n
        self.basis = HarmonicBasis.create(harmonics, samples)
        self.H = H = self.basis.harmonics
        self.nh = self.basis.n_coeff
        f = np.asarray(force, dtype=complex).reshape(-1)
        if f.size != n:
            raise ModelError(f"force must have one entry per sector DOF ({n}), got {f.size}")
        self.force = f
        self.contacts = tuple(contacts)
        if not self.contacts:
            raise ModelError("cyclic HB needs at least one contact element")
        blocks = []
        for c in self.contacts:
            P = sp.csr_matrix(c.projection) if sp.issparse(c.projection) else \
                sp.csr_matrix(np.asarray(c.projection, float))
            if P.shape[1] != 2 * n:
                raise ModelError(f"contact {c.name!r}: projection must have 2 n = {2 * n} "
                                 f"columns (sector 0, sector 1), got {P.shape}")
            blocks.append(P)
        P = sp.vstack(blocks).tocsr()
        self.m = P.shape[0]
        self.N_unknowns = self.m * self.nh
        Pa, Pb = _dense(P[:, :n]), _dense(P[:, n:])
        self.phi = 2.0 * np.pi * self.nd / self.N
        Kd, Md = _dense(sector.K), _dense(sector.M)
        Dd = np.zeros_like(Kd) if sector.D is None else _dense(sector.D)
        if rotation_stiffness is not None:
            if excitations_per_rev is None or not excitations_per_rev > 0:
                raise ModelError("rotation_stiffness needs excitations_per_rev > 0 (the "
                                 "excitation frequency over the rotation frequency)")
            Kr = _dense(rotation_stiffness)
            if Kr.shape != Kd.shape:
                raise ModelError(f"rotation_stiffness must be ({n}, {n}), got {Kr.shape}")
            self.E = float(excitations_per_rev)
        else:
            Kr, self.E = None, None
        # per harmonic: T_h, projected matrices, C_h and the projected force
        self.Kt, self.Mt, self.Dt, self.Krt, self.C, self.ft = [], [], [], [], [], []
        cache = {}
        for h in range(H + 1):
            ndh = (-h * self.nd) % self.N
            if ndh not in cache:
                T = sector.cyclic_transform(ndh).toarray().astype(complex)
                TH = T.conj().T
                cache[ndh] = (T, TH @ Kd @ T, TH @ Md @ T, TH @ Dd @ T,
                              None if Kr is None else TH @ Kr @ T)
            T, Kt, Mt, Dt, Krt = cache[ndh]
            self.Kt.append(Kt)
            self.Mt.append(Mt)
            self.Dt.append(Dt)
            self.Krt.append(Krt)
            self.C.append((Pa + np.exp(-1j * h * self.phi) * Pb) @ T)
            self.ft.append(T.conj().T @ f if h == 1 else np.zeros(T.shape[1], complex))
        self.T = [cache[(-h * self.nd) % self.N][0] for h in range(H + 1)]
        self.ia = 2 * np.arange(1, H + 1) - 1
        self.ib = self.ia + 1

    # ------------------------------------------------------------------ dynamic stiffness
    def _Z(self, h: int, omega: float):
        Z = self.Kt[h] - (h * omega) ** 2 * self.Mt[h] + 1j * h * omega * self.Dt[h]
        dZ = -2.0 * h**2 * omega * self.Mt[h] + 1j * h * self.Dt[h]
        if self.E is not None:
            Z = Z + (omega / self.E) ** 2 * self.Krt[h]
            dZ = dZ + (2.0 * omega / self.E**2) * self.Krt[h]
        return Z, dZ

    def compliance(self, omega: float):
        """R_h (H+1, m, m), dR_h/dOmega, u_lin (H+1, m), du_lin/dOmega (complex)."""
        H, m = self.H, self.m
        R = np.empty((H + 1, m, m), complex)
        dR = np.empty_like(R)
        u = np.empty((H + 1, m), complex)
        du = np.empty_like(u)
        for h in range(H + 1):
            Z, dZ = self._Z(h, omega)
            C = self.C[h]
            rhs = np.concatenate([C.conj().T, self.ft[h][:, None]], axis=1)
            lu = sla.lu_factor(Z, check_finite=False)
            G = sla.lu_solve(lu, rhs, check_finite=False)
            W = sla.lu_solve(lu, dZ @ G, check_finite=False)
            CG, CW = C @ G, C @ W
            R[h], u[h] = CG[:, :m], CG[:, m]
            dR[h], du[h] = -CW[:, :m], -CW[:, m]
        return R, dR, u, du

    def _real_blocks(self, R):
        nh, m = self.nh, self.m
        T = np.zeros((nh, nh, m, m))
        T[0, 0] = R[0].real
        Rr, Ri = R[1:].real, R[1:].imag
        T[self.ia, self.ia] = Rr
        T[self.ia, self.ib] = Ri
        T[self.ib, self.ia] = -Ri
        T[self.ib, self.ib] = Rr
        return T.transpose(2, 0, 3, 1).reshape(m * nh, m * nh)

    def contact_stiffness(self) -> np.ndarray:
        """Tangent stiffness (m, m) of the contacts at zero displacement (virgin state)."""
        blocks = []
        for c in self.contacts:
            st = c.law.initial_state()
            z = np.zeros((c.n_contacts, c.n_dir))
            k = c.law.step(st, z, z if c.law.velocity_dependent else None).stiffness
            blocks.extend(np.asarray(k, float))
        return sla.block_diag(*blocks)

    def displacement_scale(self, omegas) -> float:
        """Typical contact displacement [m]: the larger of the largest linear response with
        stuck contacts and the median one with free contacts over ``omegas`` (as the
        full-wheel HB scales its unknowns)."""
        Kc = self.contact_stiffness()
        stuck, free = [], []
        for w in omegas:
            R, _, ul, _ = self.compliance(float(w))
            free.append(np.abs(ul).max())
            us = [np.linalg.solve(np.eye(self.m) + R[h] @ Kc, ul[h]) for h in range(self.H + 1)]
            stuck.append(np.abs(np.array(us)).max())
        return float(max(np.max(stuck), np.median(free)))

    def stuck_response(self, omega: float, load_scale: float = 1.0) -> np.ndarray:
        """Contact-row coefficients (m, 2H+1) of the linear response with the contacts'
        virgin tangent stiffness (the first guess of Newton, as the full-wheel HB's)."""
        Kc = self.contact_stiffness()
        R, _, ul, _ = self.compliance(float(omega))
        U = np.array([np.linalg.solve(np.eye(self.m) + R[h] @ Kc, load_scale * ul[h])
                      for h in range(self.H + 1)])
        return _real(U)

    # ------------------------------------------------------------------ residual
    def evaluate(self, y, omega, *, scale: float = 1.0, x_scale: float = 1.0,
                 load_scale: float = 1.0, jacobian: bool = True):
        """Residual (N_unknowns,) [m * scale], Jacobian, dr/dOmega for scaled unknowns y."""
        Y = (np.asarray(y) * x_scale).reshape(self.m, self.nh)
        R, dR, ul, dul = self.compliance(omega)
        if load_scale != 1.0:
            ul = ul * load_scale
            dul = dul * load_scale
        res = aft(self.contacts, Y, omega, self.basis, jacobian=jacobian)
        Fc = _phasors(res.force, self.H)
        r = Y + _real((R @ Fc[:, :, None])[:, :, 0] - ul)
        dr = _real((dR @ Fc[:, :, None])[:, :, 0] - dul)
        J = None
        if jacobian or res.d_omega is not None:
            Rr = self._real_blocks(R)
        if res.d_omega is not None:
            dr = dr + (Rr @ res.d_omega.ravel()).reshape(dr.shape)
        if jacobian:
            from scipy.linalg import block_diag

            Jnl = block_diag(*[b for blk in res.jacobian for b in blk])
            J = (np.eye(self.N_unknowns) + Rr @ Jnl) * (scale * x_scale)
        return r.ravel() * scale, J, dr.ravel() * scale

    def sector_harmonics(self, y, omega, *, x_scale: float = 1.0,
                         load_scale: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Sector-0 DOF phasors ``x_h = T_h Q~_h`` (H+1, n), contact U (m, nh), F (m, nh)."""
        Y = (np.asarray(y) * x_scale).reshape(self.m, self.nh)
        res = aft(self.contacts, Y, omega, self.basis, jacobian=False)
        Fc = _phasors(res.force, self.H)
        X = np.empty((self.H + 1, self.n), complex)
        for h in range(self.H + 1):
            Z, _ = self._Z(h, omega)
            rhs = load_scale * self.ft[h] - self.C[h].conj().T @ Fc[h]
            X[h] = self.T[h] @ np.linalg.solve(Z, rhs)
        return X, Y, res.force

    def energies(self, X, U, F, omega, load_scale: float = 1.0) -> dict:
        """Per-sector work per period: external, viscous, contact [J]; kinetic energy E_max."""
        H = self.H
        D = self.sector.D
        Dd = np.zeros((self.n, self.n)) if D is None else _dense(D)
        Md = _dense(self.sector.M)
        h = np.arange(H + 1)
        # oint (D dx/dt) . dx = pi sum_h h^2 Omega x_h^H D x_h
        w_visc = float(np.pi * omega * np.sum(h**2 * np.real(np.einsum(
            "hi,ij,hj->h", X.conj(), Dd, X))))
        # oint f dx = pi Im(x_1^H f~) for x = Re(x_1 e^{i tau}), f = Re(f~ e^{i tau})
        w_ext = float(np.pi * np.imag(np.vdot(X[1], load_scale * self.force)))
        w_c = float(np.sum(cycle_work(U, F)))
        e_max = 0.5 * omega**2 * float(np.real(np.vdot(X[1], Md @ X[1])))
        return {"W_ext": w_ext, "W_visc": w_visc, "W_contact": w_c, "E_max": e_max}


@dataclass(frozen=True, repr=False)
class CyclicForcedResponse(ResultMixin):
    """Forced response of a tuned wheel by cyclic HB (per sector, along the continuation).

    Attributes
    ----------
    omega : ndarray, shape (n_p,)
        Excitation angular frequency [rad/s] (kept for compatibility: ``frequency_hz``
        [Hz], ``omega_rad_s``).
    sector_harmonics : ndarray, shape (n_p, H+1, n), complex
        Sector-0 DOF phasors ``x_h`` [m] (sector j: ``x_h exp(-i h j phi)``).
    contact_displacement, contact_force : ndarray, shape (n_p, m, 2H+1)
        Real harmonic coefficients of sector 0's contact rows [m], [N].
    work_external, work_viscous, work_contact : ndarray, shape (n_p,)
        Work per period and sector [J].
    kinetic_energy : ndarray, shape (n_p,)
        ``Omega^2 x_1^H M x_1 / 2`` [J] (E_max of the fundamental).
    energy_balance_error : ndarray, shape (n_p,)
        ``|W_ext - W_visc - W_contact| / max(|W_ext|, tiny)``.
    nd : int
    harmonics, samples : int
    status : int
    message : str
    runtime_s : float
        Wall time of the continuation [s] (CPU time in ``cpu_s``).
    cpu_s : float
    n_evaluations : int
    n_restarts : int
        Natural-parameter restarts after the arclength corrector stalled at a kink of the
        friction residual (each a small step in Omega by damped Newton, as a slow sweep).
    """

    omega: np.ndarray
    sector_harmonics: np.ndarray
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    work_external: np.ndarray
    work_viscous: np.ndarray
    work_contact: np.ndarray
    kinetic_energy: np.ndarray
    energy_balance_error: np.ndarray
    nd: int
    harmonics: int
    samples: int
    status: int
    message: str
    runtime_s: float
    cpu_s: float
    n_evaluations: int
    n_restarts: int = 0

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def n_points(self) -> int:
        return int(self.omega.size)

    @property
    def frequency_hz(self) -> np.ndarray:
        """Excitation frequency [Hz], shape (n_p,)."""
        return self.omega / (2 * np.pi)

    @property
    def omega_rad_s(self) -> np.ndarray:
        """Excitation angular frequency [rad/s] (the same as ``omega``), shape (n_p,)."""
        return self.omega

    def to_xarray(self):
        """``xarray.Dataset`` over the continuation points: sector-0 DOF phasors (real and
        imaginary parts), contact harmonics, works per period and sector, damping ratio."""
        import xarray as xr

        H = self.harmonics
        coef = ["c0"] + [f"{ab}{k}" for k in range(1, H + 1) for ab in ("a", "b")]
        X = self.sector_harmonics
        return xr.Dataset(
            {"harmonics_real": (("point", "harmonic", "dof"), X.real, {"units": "m"}),
             "harmonics_imag": (("point", "harmonic", "dof"), X.imag, {"units": "m"}),
             "contact_displacement": (("point", "row", "coefficient"),
                                      self.contact_displacement, {"units": "m"}),
             "contact_force": (("point", "row", "coefficient"), self.contact_force,
                               {"units": "N"}),
             "work_external": (("point",), self.work_external, {"units": "J"}),
             "work_viscous": (("point",), self.work_viscous, {"units": "J"}),
             "work_contact": (("point",), self.work_contact, {"units": "J"}),
             "kinetic_energy": (("point",), self.kinetic_energy, {"units": "J"}),
             "damping_ratio": (("point",), self.damping_ratio, {"units": "1"}),
             "energy_balance_error": (("point",), self.energy_balance_error, {"units": "1"})},
            coords={"frequency": ("point", self.frequency_hz, {"units": "Hz"}),
                    "omega": ("point", self.omega, {"units": "rad/s"}),
                    "harmonic": np.arange(H + 1), "coefficient": coef},
            attrs={"nd": self.nd, "harmonics": H, "samples": self.samples,
                   "status": self.status, "message": self.message})

    def plot(self, dofs=(0,), ax=None, **kwargs):
        """Peak-to-mean amplitude of sector 0's ``dofs`` [m] vs excitation frequency [Hz];
        returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4), layout="constrained")
        ax.plot(self.frequency_hz, self.amplitude(dofs), **kwargs)
        ax.set_xlabel("excitation frequency [Hz]")
        ax.set_ylabel(f"amplitude of sector-0 DOF {list(np.atleast_1d(dofs))} [m]")
        ax.set_title(f"cyclic HB, {self.nd} ND" + ("" if self.success else
                                                   f" (incomplete: {self.message})"),
                     fontsize="small")
        ax.grid(alpha=0.3)
        return ax

    @property
    def damping_ratio(self) -> np.ndarray:
        """Equivalent ratio ``(W_visc + W_contact) / (4 pi E_max)`` at each point [-]."""
        return (self.work_viscous + self.work_contact) / (4 * np.pi * self.kinetic_energy)

    def amplitude(self, dofs, direction=None, samples: int = 256) -> np.ndarray:
        """Peak-to-mean amplitude [m] of sector 0's ``dofs`` (projected on ``direction``)
        over one period, shape (n_p,)."""
        d = np.atleast_1d(np.asarray(dofs))
        X = self.sector_harmonics[:, 1:, d]                   # (n_p, H, k)
        w = np.ones(d.size) if direction is None else np.asarray(direction, float)
        X = X @ w
        tau = 2 * np.pi * np.arange(samples) / samples
        E = np.exp(1j * np.outer(np.arange(1, self.harmonics + 1), tau))   # (H, s)
        return np.abs(np.real(X @ E)).max(axis=1)


def cyclic_frequency_response(problem: CyclicHarmonicBalance, omega_start: float,
                              omega_end: float, *, step: float = 0.02,
                              min_step: float | None = None, max_step: float | None = None,
                              max_points: int = 500, tol: float = 1e-9,
                              load_scale: float = 1.0, max_angle_deg: float = 25.0,
                              max_iter: int = 20, max_jumps: int = 20,
                              blas: int | None = 1) -> CyclicForcedResponse:
    """Frequency (or speed) response of the travelling-wave steady state by continuation.

    Parameters
    ----------
    problem : CyclicHarmonicBalance
    omega_start, omega_end : float
        Excitation angular frequency interval [rad/s] (> 0, either direction); with a
        ``rotation_stiffness`` the speed is ``omega / excitations_per_rev``.
    step, min_step, max_step, max_points, tol, max_angle_deg
        As :func:`fricdamp.solvers.hb.frequency_response` (scaled arclength; Newton
        tolerance on the contact displacement residual over its typical size), except
        ``max_step`` whose default is ``40 step``: the unknowns are scaled by the small
        stuck-contact response, so a resonance with slipping contacts is many scales high.
    load_scale : float
        Multiplies the load.
    max_iter : int
        Corrector iterations per step.
    max_jumps : int
        Largest number of natural-parameter restarts when the arclength corrector stalls
        (the static/kinetic friction law makes the residual discontinuous): Newton with
        backtracking at ``Omega_last + (1e-4 .. 3e-2) (omega_end - omega_start)``.
    blas : int or None
        BLAS threads (default 1).

    Returns
    -------
    CyclicForcedResponse
        Converged points only; ``status`` 0 when ``omega_end`` was reached.
    """
    for name, v in (("omega_start", omega_start), ("omega_end", omega_end)):
        if not (np.isfinite(v) and v > 0):
            raise ModelError(f"{name} must be > 0 rad/s, got {v!r}")
    if omega_start == omega_end:
        raise ModelError("omega_start and omega_end must differ")
    pb = problem
    max_step = 40.0 * step if max_step is None else max_step
    t0, c0 = time.perf_counter(), time.process_time()
    with blas_threads(blas):
        x_ref = pb.displacement_scale(np.linspace(omega_start, omega_end, 17)) * abs(
            load_scale)
        x_ref = x_ref if x_ref > 0 and np.isfinite(x_ref) else 1.0
        scale = 1.0 / x_ref

        def residual(x, lam):
            return pb.evaluate(x, lam, scale=scale, x_scale=x_ref, load_scale=load_scale)

        start = None
        for g in (np.zeros((pb.m, pb.nh)), pb.stuck_response(omega_start, load_scale)):
            start = newton(lambda x: residual(x, omega_start)[:2], g.ravel() / x_ref,
                           tol=tol, max_iter=100)
            if start.success:
                break
        xs, lams, n_ev, jumps = [], [], 0, 0
        lam0, xstart = omega_start, start.x
        span = omega_end - omega_start
        while True:
            cres = solve_and_continue(
                xstart, residual, lam0, omega_end, step,
                ds_min=min_step if min_step is not None else step / 1000.0,
                ds_max=max_step, x_scale=1.0, lam_scale=abs(span), tol=tol,
                max_iter=max_iter, max_steps=max(max_points - len(lams), 2),
                max_angle_deg=max_angle_deg, blas=None)
            xs.extend(cres.x)
            lams.extend(cres.lam)
            n_ev += cres.n_evaluations
            if cres.status != 2 or not cres.n_points or jumps >= max_jumps \
                    or len(lams) >= max_points:
                break
            # the arclength corrector stalled (a kink of the friction residual): step on in
            # the natural parameter with damped Newton from the last point, as a slow sweep
            # would (a fold passed this way is a jump, counted in the message)
            xl, ll = cres.x[-1], cres.lam[-1]
            for frac in (1e-4, 1e-3, 3e-3, 1e-2, 3e-2):
                lam_try = ll + frac * span
                if (lam_try - omega_end) * np.sign(span) > 0:
                    lam_try = omega_end
                nr = newton(lambda x, lt=lam_try: residual(x, lt)[:2], xl, tol=tol,
                            max_iter=50)
                if nr.success:
                    break
            if not nr.success:
                break
            jumps += 1
            lam0, xstart = lam_try, nr.x
            if lam_try == omega_end:
                xs.append(nr.x)
                lams.append(lam_try)
                cres = type(cres)(cres.x, cres.lam, cres.iterations, (), 0,
                                  "reached the end of the parameter interval", 0, 0)
                break
        Xs, Us, Fs, we, wv, wc, ek = [], [], [], [], [], [], []
        for x, w in zip(xs, lams, strict=True):
            X, U, F = pb.sector_harmonics(x, w, x_scale=x_ref, load_scale=load_scale)
            e = pb.energies(X, U, F, w, load_scale)
            Xs.append(X)
            Us.append(U)
            Fs.append(F)
            we.append(e["W_ext"])
            wv.append(e["W_visc"])
            wc.append(e["W_contact"])
            ek.append(e["E_max"])
    we, wv, wc = np.array(we), np.array(wv), np.array(wc)
    err = np.abs(we - wv - wc) / np.maximum(np.abs(we), 1e-300)
    n_p = len(lams)
    shape = (0, pb.H + 1, pb.n)
    msg = cres.message + (f"; {jumps} natural-parameter restart(s) after corrector stalls"
                          if jumps else "")
    return CyclicForcedResponse(
        omega=np.asarray(lams, float),
        sector_harmonics=np.array(Xs) if n_p else np.zeros(shape, complex),
        contact_displacement=np.array(Us) if n_p else np.zeros((0, pb.m, pb.nh)),
        contact_force=np.array(Fs) if n_p else np.zeros((0, pb.m, pb.nh)),
        work_external=we, work_viscous=wv, work_contact=wc, kinetic_energy=np.array(ek),
        energy_balance_error=err, nd=pb.nd, harmonics=pb.H, samples=pb.basis.samples,
        status=int(cres.status), message=msg,
        runtime_s=time.perf_counter() - t0, cpu_s=time.process_time() - c0,
        n_evaluations=int(n_ev), n_restarts=jumps)
