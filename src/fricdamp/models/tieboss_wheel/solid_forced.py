"""Forced response of the solid wheel by cyclic harmonic balance, every node pair in the AFT.

The beam wheel's forced response (:mod:`fricdamp.models.tieboss_wheel.forced`) runs unchanged on
the solid wheel: :class:`~fricdamp.solvers.cyclic_hb.CyclicHarmonicBalance` works on the
*reduced* solid sector (cyclic Craig-Bampton of :func:`~fricdamp.models.contact_wheel.
build_contact_wheel`: contact faces kept, cut interface reduced) with one Contact3D law over
all node pairs of the contact patch between sector 0 and sector 1 (003 (2): penalty
``k_n = factor E A / h`` per pair, interference offset for the prestress, separation, 2D
Coulomb with mu(v)). The unknowns are the ``3 n_pairs (2H + 1)`` harmonics of the pairs'
relative displacements (3,675 for the default mesh's 49 pairs at H = 12; 525 at H = 3 on
the coarse one), whatever the size of the sector.

Contact rows (the same relative displacement as the transient's, :func:`~fricdamp.models.
contact_wheel.cyclic_contact_rows`): pair p of sector 0's patch joins its right-face node to
node ``partner(p)`` of sector 1's left face::

    u_p = Lambda_p (u_right^(0)[p] - R u_left^(1)[partner(p)])

with sector 1's displacements in its own frame and R the rotation by the sector angle; so
the projection has ``Lambda_p`` on sector 0's right-face DOFs and ``-Lambda_p R`` on sector
1's left-face DOFs (:class:`~fricdamp.solvers.cyclic_hb.CyclicHarmonicBalance` takes sector
1's columns in its own frame rotated into sector 0's components).

Load: ``force_N`` per blade, split equally over the sector's ``load`` nodes, along the
probe direction (the blade's flexural direction), travelling as an ``nd`` wave (003's
electromagnets in the standing wheel's frame; speed terms are not included: the response
is that of the standing wheel, see docs/cases_tieboss_wheel_solid.md).

Validation (tests/validation/test_solid_forced.py): below the slip threshold the HB
response equals the linear response of the wheel linearised about its static state (closed
pairs stuck, open pairs free) by a direct solve of the reduced sector's cyclic equations;
the energy per period balances (external work = viscous + contact dissipation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError, check_positive

__all__ = ["SolidForcedResponse", "probe_amplitude", "reduced_rotation_stiffness",
           "solid_cyclic_problem", "solid_forced_response", "solve_point"]


def _face_dofs(named, name: str, order) -> np.ndarray:
    return np.asarray(named[name]).reshape(-1, 3)[np.asarray(order)]


def contact_projection(wheel) -> sp.csr_matrix:
    """Rows ``(3 n_pairs, 2 n)`` of the patch between sector 0 and sector 1 on the reduced
    sector's DOFs (module docstring)."""
    sec = wheel.reduced.sector
    patch = wheel.sector.patch
    n = sec.n_dof
    iR = _face_dofs(sec.named_dofs, "contact_right", patch.right)     # (P, 3)
    iL = _face_dofs(sec.named_dofs, "contact_left", patch.left)
    lam = patch.frames                                                 # (P, 3, 3)
    lamR = np.einsum("pab,bc->pac", lam, patch.rotation)
    P = patch.n_pairs
    rows = np.repeat(np.arange(3 * P).reshape(P, 3), 3, axis=1).reshape(P, 3, 3)
    cols_a = np.broadcast_to(iR[:, None, :], (P, 3, 3))
    cols_b = n + np.broadcast_to(iL[:, None, :], (P, 3, 3))
    data = np.concatenate([lam.ravel(), -lamR.ravel()])
    return sp.csr_matrix((data, (np.concatenate([rows.ravel(), rows.ravel()]),
                                 np.concatenate([cols_a.ravel(), cols_b.ravel()]))),
                         shape=(3 * P, 2 * n))


def load_phasor(wheel, force_N: float) -> np.ndarray:
    """``force_N`` [N] per blade over the ``load`` nodes along the probe direction."""
    sec = wheel.reduced.sector
    if "load" not in sec.named_dofs:
        raise ModelError("the sector has no 'load' node set: name the nodes the forces act on")
    idx = np.asarray(sec.named_dofs["load"]).reshape(-1, 3)
    f = np.zeros(sec.n_dof, complex)
    f[idx] = float(force_N) / idx.shape[0] * np.asarray(wheel.sector.probe_direction)
    return f


def reduced_rotation_stiffness(wheel, rotation) -> np.ndarray:
    """``E^T (K_sigma - K_d) E`` per (rad/s)^2 on the reduced sector (E: the reduction's
    ``expansion``), from :class:`~fricdamp.structure.system.RotationTerms` on the sector's
    DOFs (e.g. :func:`fricdamp.models.tieboss_wheel.solid_campbell.rotation_terms`), symmetrised."""
    Kr = sp.csr_matrix(rotation.stress_stiffening) - sp.csr_matrix(rotation.spin_softening)
    E = np.asarray(wheel.reduced.expansion)
    if Kr.shape != (E.shape[0], E.shape[0]):
        raise ModelError(f"rotation terms must be {E.shape[0]} x {E.shape[0]} (the sector's "
                         f"DOFs), got {Kr.shape}")
    A = E.T @ (Kr @ E)
    return 0.5 * (A + A.T)


def solid_cyclic_problem(wheel, nd: int, *, settings=None, offset: float | None = None,
                         force_N: float = 1.0, harmonics: int = 3,
                         samples: int | None = None, rotation=None,
                         excitations_per_rev: float | None = None):
    """The cyclic HB problem of a reduced solid wheel for a forward ``nd`` wave.

    Parameters
    ----------
    wheel : ContactWheel
        From :func:`~fricdamp.models.contact_wheel.build_contact_wheel`.
    nd : int
        Nodal diameter of the travelling wave (negative: backward).
    settings : ContactSettings, optional
        Contact parameters (default 003's).
    offset : float, optional
        Interference [m]; default calibrated to ``settings.prestress_N`` per contact.
    force_N : float
        Force amplitude per blade [N].
    harmonics, samples : int
        H and the AFT samples (default: a multiple of 30 >= 16 H, so that the full
        wheel's AFT is shift-invariant for N = 30).
    rotation : RotationTerms, optional
        Stress stiffening and spin softening per (rad/s)^2 on the sector's DOFs
        (:func:`fricdamp.models.tieboss_wheel.solid_campbell.rotation_terms`); with
        ``excitations_per_rev`` E (= pulses x order) the response is speed-locked: at
        excitation frequency Omega the wheel turns at Omega / E and its stiffness is
        ``K + (Omega / E)^2 K_rot``. The centrifugal *load* is not applied: the contact
        prestress is the calibrated one (as for the beam wheel).
    excitations_per_rev : float, optional
        Needed with ``rotation``.

    Returns
    -------
    problem : CyclicHarmonicBalance
    offset : float
    """
    from fricdamp.models.contact_wheel import ContactSettings
    from fricdamp.solvers.cyclic_hb import CyclicHarmonicBalance
    from fricdamp.structure.system import ContactElement

    settings = ContactSettings() if settings is None else settings
    check_positive("force_N", force_N, unit="N")
    if offset is None:
        offset, _ = wheel.calibrate_offset(settings)
    law = wheel.sector.patch.law(
        youngs_modulus=wheel.sector.youngs_modulus, penalty_factor=settings.penalty_factor,
        offset=offset, mu_static=settings.mu_static, mu_sliding=settings.mu_sliding,
        decay=settings.decay_s_per_m, tangential_ratio=settings.tangential_ratio,
        n_sectors=1)
    sec = wheel.reduced.sector
    if sec.D is None:
        a, b = wheel.sector.rayleigh
        from dataclasses import replace

        sec = replace(sec, D=a * sec.M + b * sec.K)
    if samples is None:
        N = wheel.n_sectors
        samples = N * int(np.ceil(16 * harmonics / N))
    kw = {}
    if rotation is not None:
        if excitations_per_rev is None:
            raise ModelError("rotation needs excitations_per_rev > 0 (pulses x order)")
        kw = {"rotation_stiffness": reduced_rotation_stiffness(wheel, rotation),
              "excitations_per_rev": float(excitations_per_rev)}
    pb = CyclicHarmonicBalance(sec, [ContactElement(law, contact_projection(wheel),
                                                    name="tieboss")],
                               int(nd), load_phasor(wheel, force_N), harmonics=harmonics,
                               samples=samples, **kw)
    return pb, float(offset)


@dataclass(frozen=True)
class SolidForcedResponse:
    """Forced response of the solid wheel around one ND resonance.

    Attributes
    ----------
    nd : int
    frequency_hz : ndarray, shape (n_p,)
    amplitude_m : ndarray, shape (n_p,)
        Probe amplitude of blade 0 along the probe direction [m].
    dissipated_energy_J : ndarray, shape (n_p,)
        Contact dissipation per period and sector [J].
    damping_ratio : ndarray, shape (n_p,)
        ``(W_visc + W_contact) / (4 pi E_max)`` [-].
    energy_balance_error : float
        Largest over the curve.
    peak_hz, peak_amplitude_m : float
    cpu_s_per_point, wall_s_per_point : float
    unknowns : int
        Real HB unknowns (contact rows x harmonic coefficients).
    response : CyclicForcedResponse
    """

    nd: int
    frequency_hz: np.ndarray
    amplitude_m: np.ndarray
    dissipated_energy_J: np.ndarray
    damping_ratio: np.ndarray
    energy_balance_error: float
    peak_hz: float
    peak_amplitude_m: float
    cpu_s_per_point: float
    wall_s_per_point: float
    unknowns: int
    response: object

    def summary(self) -> dict:
        return {"nd": self.nd, "frequency_hz": self.frequency_hz.tolist(),
                "amplitude_m": self.amplitude_m.tolist(),
                "dissipated_energy_J": self.dissipated_energy_J.tolist(),
                "damping_ratio": self.damping_ratio.tolist(),
                "energy_balance_error": self.energy_balance_error, "peak_hz": self.peak_hz,
                "peak_amplitude_m": self.peak_amplitude_m,
                "cpu_s_per_point": self.cpu_s_per_point,
                "wall_s_per_point": self.wall_s_per_point, "unknowns": self.unknowns,
                "status": int(self.response.status)}


def probe_amplitude(wheel, response) -> np.ndarray:
    """Blade 0's probe amplitude [m] at every point of a cyclic response."""
    sec = wheel.reduced.sector
    probe = np.asarray(sec.named_dofs["probe"]).reshape(-1)[:3]
    return response.amplitude(probe, wheel.sector.probe_direction)


def solve_point(wheel, problem, frequency_hz: float, *, tol: float = 1e-9,
                y0=None) -> tuple[float, np.ndarray]:
    """One steady state at a fixed frequency by Newton from the linear response with the
    contacts' virgin tangent (or from ``y0``, contact-row coefficients (m, 2H + 1) [m]).

    Returns
    -------
    amplitude_m : float
        Blade 0's probe amplitude [m].
    y : ndarray, shape (m, 2H + 1)
        The contact-row coefficients [m].
    """
    from fricdamp.errors import ConvergenceError
    from fricdamp.solvers.continuation import blas_threads, newton

    w = 2 * np.pi * float(check_positive("frequency_hz", frequency_hz, unit="Hz"))
    x_ref = problem.displacement_scale([w])
    start = problem.stuck_response(w) if y0 is None else np.asarray(y0, float)
    with blas_threads(1):
        sol = newton(lambda x: problem.evaluate(x, w, scale=1 / x_ref, x_scale=x_ref)[:2],
                     start.ravel() / x_ref, tol=tol)
    if not sol.success:
        raise ConvergenceError(f"cyclic HB did not converge at {frequency_hz:g} Hz "
                               f"(residual {sol.residual_norm:.3g})")
    X, Y, _ = problem.sector_harmonics(sol.x, w, x_scale=x_ref)
    sec = wheel.reduced.sector
    probe = np.asarray(sec.named_dofs["probe"]).reshape(-1)[:3]
    H = problem.H
    tau = 2 * np.pi * np.arange(256) / 256
    E = np.exp(1j * np.outer(np.arange(1, H + 1), tau))
    sig = np.real((X[1:, probe] @ np.asarray(wheel.sector.probe_direction)) @ E)
    return float(np.abs(sig).max()), Y


def solid_forced_response(wheel, nd: int, f_start_hz: float, f_end_hz: float, *,
                          force_N: float = 1.0, settings=None, offset: float | None = None,
                          harmonics: int = 3, samples: int | None = None,
                          step: float = 0.02, max_points: int = 300,
                          tol: float = 1e-9, rotation=None,
                          excitations_per_rev: float | None = None) -> SolidForcedResponse:
    """Continuation of the ``nd`` travelling-wave response from ``f_start_hz`` to
    ``f_end_hz`` (see :func:`solid_cyclic_problem` for the other parameters and
    :func:`~fricdamp.solvers.cyclic_hb.cyclic_frequency_response` for ``step``,
    ``max_points`` and ``tol``)."""
    from fricdamp.solvers.cyclic_hb import cyclic_frequency_response

    for name, v in (("f_start_hz", f_start_hz), ("f_end_hz", f_end_hz)):
        check_positive(name, v, unit="Hz")
    pb, _ = solid_cyclic_problem(wheel, nd, settings=settings, offset=offset,
                                 force_N=force_N, harmonics=harmonics, samples=samples,
                                 rotation=rotation, excitations_per_rev=excitations_per_rev)
    res = cyclic_frequency_response(pb, 2 * np.pi * f_start_hz, 2 * np.pi * f_end_hz,
                                    step=step, max_points=max_points, tol=tol)
    amp = probe_amplitude(wheel, res)
    i = int(np.argmax(amp))
    n = max(res.n_points, 1)
    return SolidForcedResponse(
        nd=int(nd), frequency_hz=res.omega / (2 * np.pi), amplitude_m=amp,
        dissipated_energy_J=np.asarray(res.work_contact),
        damping_ratio=np.asarray(res.damping_ratio),
        energy_balance_error=float(np.max(res.energy_balance_error)),
        peak_hz=float(res.omega[i] / (2 * np.pi)), peak_amplitude_m=float(amp[i]),
        cpu_s_per_point=res.cpu_s / n, wall_s_per_point=res.runtime_s / n,
        unknowns=int(pb.N_unknowns), response=res)
