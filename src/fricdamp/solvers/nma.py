"""Nonlinear modal analysis of friction-damped structures: extended periodic motion concept.

The extended periodic motion concept (EPMC, Krack 2015) makes the damped, autonomous
motion of a nonlinear mode periodic by adding the artificial negative mass-proportional
damping term ``-xi M q'``::

    M q'' + (D - xi M) q' + K q + P^T f(P q) = F_static.

Harmonic balance with AFT (:mod:`fricdamp.solvers.hb`) for the periodic motion ``q(tau)``,
``tau = omega t``, with the frequency omega and xi as extra unknowns, closed by

* amplitude: the fundamental harmonic's mass-weighted norm equals the modal amplitude a,
  ``a1^T M a1 + b1^T M b1 = a^2`` (or, with ``amplitude_dof=i``, ``a1_i^2 + b1_i^2 = A^2``);
* phase: the sine part of the fundamental is orthogonal to the linearised mode phi,
  ``phi^T M b1 = 0``.

At each amplitude the nonlinear natural frequency is omega and the modal damping ratio is
``zeta = xi / (2 omega)``: for a linear mode with modal damping ``2 zeta_0 omega_0`` the
method returns exactly ``xi = 2 zeta_0 omega_0``; for a friction contact it returns the ratio
for which the energy fed in by ``xi`` over a period equals the energy dissipated, so that
``zeta = E_diss / (2 pi omega^2 a^2)`` with one harmonic (``a`` the modal amplitude,
``E_diss = xi omega pi a^2``). The approximation is that of a slowly decaying motion:
validated against free-decay time integration identified by the logarithmic decrement
(tests/validation/test_nma.py).

References
----------
Krack (2015), Nonlinear modal analysis of nonconservative systems: extension of the
periodic motion concept, Computers & Structures 154, 59-71.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.results import ResultMixin
from fricdamp.solvers.continuation import blas_threads, newton
from fricdamp.solvers.hb import _balance_error, _dense, _Full, _postprocess, _Setup
from fricdamp.structure.system import MechanicalSystem

__all__ = ["NonlinearModes", "nonlinear_modes"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False, repr=False)
class NonlinearModes(ResultMixin):
    """Amplitude-dependent frequency and damping of one nonlinear mode.

    Attributes
    ----------
    amplitude : ndarray, shape (n_points,)
        Requested amplitudes that converged: modal amplitude a [sqrt(kg) m] (mass
        normalised fundamental), or the fundamental amplitude of ``amplitude_dof`` [m].
    frequency : ndarray, shape (n_points,)
        Nonlinear natural angular frequency omega [rad/s]. Kept for compatibility (its
        name does not say rad/s): prefer ``frequency_hz`` [Hz] or ``frequency_rad_s``.
    damping_ratio : ndarray, shape (n_points,)
        Modal damping ratio ``xi / (2 omega)`` [-] (viscous + friction).
    coefficients : ndarray, shape (n_points, n_dof, 2H+1)
        Harmonic coefficients of the periodic motion [m].
    dof_amplitude : ndarray, shape (n_points, n_dof)
        Largest excursion of each DOF from its mean [m].
    dissipated_energy : ndarray, shape (n_points, n_contacts)
        Energy dissipated per cycle by each contact [J].
    viscous_dissipation : ndarray, shape (n_points,)
        Energy dissipated per cycle by D [J].
    energy_balance_error : ndarray, shape (n_points,)
        ``|W_xi - W_visc - sum W_contact| / W_xi`` (W_xi: work of the negative damping).
    linear_frequency : float
        Frequency of the mode linearised at the virgin contact state [rad/s] (kept for
        compatibility: ``linear_frequency_hz`` [Hz], ``linear_frequency_rad_s``).
    linear_damping_ratio : float
        Its viscous modal damping ratio [-].
    mode : int
        Mode index (0 = lowest).
    status : int
        0 all amplitudes converged; 2 stalled (the converged ones are returned); -1 none.
    message : str
    harmonics, samples : int
    dof_names, contact_names : tuple of str
    amplitude_dof : int or None
        The DOF whose fundamental amplitude is ``amplitude`` [m]; None: modal amplitude.
    """

    amplitude: np.ndarray
    frequency: np.ndarray
    damping_ratio: np.ndarray
    coefficients: np.ndarray
    dof_amplitude: np.ndarray
    dissipated_energy: np.ndarray
    viscous_dissipation: np.ndarray
    energy_balance_error: np.ndarray
    linear_frequency: float
    linear_damping_ratio: float
    mode: int
    status: int
    message: str
    harmonics: int
    samples: int
    dof_names: tuple[str, ...] = ()
    contact_names: tuple[str, ...] = ()
    amplitude_dof: int | None = None

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def frequency_hz(self) -> np.ndarray:
        """Nonlinear natural frequency [Hz], shape (n_points,)."""
        return self.frequency / (2 * np.pi)

    @property
    def frequency_rad_s(self) -> np.ndarray:
        """Nonlinear natural angular frequency [rad/s] (the same as ``frequency``)."""
        return self.frequency

    @property
    def linear_frequency_hz(self) -> float:
        """Frequency of the linearised (stuck) mode [Hz]."""
        return float(self.linear_frequency) / (2 * np.pi)

    @property
    def linear_frequency_rad_s(self) -> float:
        """Angular frequency of the linearised (stuck) mode [rad/s]."""
        return float(self.linear_frequency)

    def _judge(self):
        """``failed`` when no amplitude converged; ``unreliable`` when the continuation
        stalled before the last amplitude (status 2) or the energy balance of a point exceeds
        its limit."""
        from fricdamp.results import status_verdict

        est = {}
        if self.energy_balance_error.size and np.any(np.isfinite(self.energy_balance_error)):
            est["energy_balance_error"] = float(np.nanmax(self.energy_balance_error))
        reasons = ()
        if self.status == 2:
            reasons = (f"only {self.amplitude.size} amplitudes converged ({self.message}): "
                       "use smaller amplitude steps or more harmonics",)
        return status_verdict(self.status != -1 and self.amplitude.size > 0, self.message, est,
                              reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset`` over the amplitude dimension (``frequency_hz`` [Hz]; the
        historical ``frequency`` variable is in rad/s, as its units attribute says)."""
        import xarray as xr

        dofs = list(self.dof_names) or [f"q{i + 1}" for i in range(self.coefficients.shape[1])]
        contacts = list(self.contact_names) or [
            f"c{i}" for i in range(self.dissipated_energy.shape[1])]
        amp_units = "m" if self.amplitude_dof is not None else "sqrt(kg) m"
        return xr.Dataset(
            {
                "frequency_hz": (("amplitude",), self.frequency_hz, {"units": "Hz"}),
                "frequency": (("amplitude",), self.frequency, {"units": "rad/s"}),
                "damping_ratio": (("amplitude",), self.damping_ratio, {"units": "1"}),
                "dof_amplitude": (("amplitude", "dof"), self.dof_amplitude, {"units": "m"}),
                "dissipated_energy": (("amplitude", "contact"), self.dissipated_energy,
                                      {"units": "J"}),
                "viscous_dissipation": (("amplitude",), self.viscous_dissipation,
                                        {"units": "J"}),
                "energy_balance_error": (("amplitude",), self.energy_balance_error,
                                         {"units": "1"}),
            },
            coords={"amplitude": ("amplitude", self.amplitude, {"units": amp_units}),
                    "dof": dofs, "contact": contacts},
            attrs={"mode_index": self.mode, "linear_frequency": self.linear_frequency,
                   "linear_frequency_hz": self.linear_frequency_hz,
                   "linear_damping_ratio": self.linear_damping_ratio, "status": self.status,
                   "message": self.message, "harmonics": self.harmonics},
        )

    def plot(self, axes=None):
        """Frequency [Hz] and damping ratio [%] vs amplitude (log x, so that the micro-slip
        range shows); returns the two axes."""
        import matplotlib.pyplot as plt

        if axes is None:
            _, axes = plt.subplots(2, 1, sharex=True, figsize=(6, 5), layout="constrained")
        axes[0].semilogx(self.amplitude, self.frequency_hz, "o-", ms=3)
        axes[0].axhline(self.linear_frequency_hz, color="0.6", lw=0.8, ls=":",
                        label="linear, stuck")
        axes[0].set_ylabel("frequency [Hz]")
        axes[0].legend(fontsize="small")
        axes[1].semilogx(self.amplitude, 100 * self.damping_ratio, "o-", ms=3)
        axes[1].set_ylabel("damping ratio [%]")
        axes[1].set_xlabel("modal amplitude [sqrt(kg) m]" if
                           self.amplitude_dof is None else "amplitude [m]")
        for ax in axes:
            ax.grid(alpha=0.3, which="both")
        return axes


def _linear_mode(s: _Setup, mode: int):
    """Mode ``mode`` of (K + contact tangent, M): omega0, mass-normalised phi, static X0."""
    Kc = s.tangent_contact_stiffness()
    Kl = (s.K + Kc).tocsr() if sp.issparse(s.K) else s.K + Kc.toarray()
    if sp.issparse(Kl) and s.n > 2000:
        import scipy.sparse.linalg as spla

        w2, Phi = spla.eigsh(sp.csc_matrix(Kl), k=mode + 1, M=sp.csc_matrix(s.M), sigma=0.0)
        order = np.argsort(w2)
        w2, Phi = w2[order], Phi[:, order]
    else:
        w2, Phi = sla.eigh(_dense(Kl), _dense(s.M))
    if mode >= w2.size:
        raise ModelError(f"mode must be < {w2.size} (the number of DOFs), got {mode}")
    if w2[mode] <= 0:
        raise ModelError(f"mode {mode} of the linearised system has omega^2 = {w2[mode]:.3g} "
                         "<= 0 (a rigid-body mode): choose an elastic mode")
    phi = Phi[:, mode]
    phi = phi / np.sqrt(phi @ (s.M @ phi))
    X0 = np.zeros(s.n)
    if np.any(s.F_ex[:, 0]):
        if sp.issparse(Kl):
            import scipy.sparse.linalg as spla

            X0 = spla.spsolve(sp.csc_matrix(Kl), s.F_ex[:, 0])
        else:
            X0 = np.linalg.solve(_dense(Kl), s.F_ex[:, 0])
    c = float(phi @ (s.D @ phi))
    return float(np.sqrt(w2[mode])), phi, X0, c


def nonlinear_modes(system: MechanicalSystem, mode: int, amplitudes, *, harmonics: int = 5,
                    samples: int | None = None, amplitude_dof: int | None = None,
                    tol: float = 1e-9, max_iter: int = 40, max_substeps: int = 6,
                    blas: int | None = 1, throw: bool = False) -> NonlinearModes:
    """Amplitude-dependent frequency and damping ratio of a nonlinear mode (EPMC).

    Parameters
    ----------
    system : MechanicalSystem
        Structure with contacts; harmonic loads are ignored (free motion), the static load
        is kept (preloads).
    mode : int
        Index of the mode (0 = lowest) of the system linearised with the contacts' virgin
        tangent stiffness (stuck friction contacts).
    amplitudes : array_like, shape (n_points,)
        Increasing amplitudes, > 0: modal amplitudes a [sqrt(kg) m] by default, or the
        fundamental-harmonic amplitude of DOF ``amplitude_dof`` [m].
    harmonics : int
        Highest harmonic H.
    samples : int, optional
        AFT samples per period (default the power of two >= 16 H).
    amplitude_dof : int, optional
        Measure the amplitude at this DOF instead of modally.
    tol : float
        Newton tolerance on the scaled residual.
    max_iter : int
        Newton iterations per amplitude.
    max_substeps : int
        Bisections of an amplitude step whose Newton solve fails before giving up.
    blas : int or None
        BLAS threads (default 1).
    throw : bool
        Raise ConvergenceError instead of returning a partial result.

    Returns
    -------
    NonlinearModes
    """
    if not isinstance(mode, (int, np.integer)) or mode < 0:
        raise ModelError(f"mode must be an integer >= 0, got {mode!r}")
    amps = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    if amps.ndim != 1 or amps.size == 0 or not np.all(np.isfinite(amps)) or np.any(amps <= 0):
        raise ModelError(f"amplitudes must be a non-empty 1-D array of values > 0, got "
                         f"{amplitudes!r}")
    if np.any(np.diff(amps) <= 0):
        raise ModelError("amplitudes must be strictly increasing")
    s = _Setup(system.with_loads(), harmonics, samples)
    s.F_ex = s.F_ex.copy()
    if amplitude_dof is not None and not 0 <= int(amplitude_dof) < s.n:
        raise ModelError(f"amplitude_dof must lie in [0, {s.n - 1}], got {amplitude_dof!r}")
    nh, n = s.nh, s.n
    with blas_threads(blas):
        form = _Full(s, nma=True)
        w0, phi, X0, c0 = _linear_mode(s, int(mode))
        Mphi = np.asarray(s.M @ phi).ravel()
        if amplitude_dof is None:
            W = s.M
        else:
            W = sp.csr_matrix(([1.0], ([int(amplitude_dof)], [int(amplitude_dof)])),
                              shape=(n, n))
        rscale = 1.0 / (w0**2 * max(np.abs(Mphi).max(), 1e-300))
        ia = np.arange(n) * nh + 1
        ib = ia + 1

        def make_fun(a):
            def fun(z):
                psi = z[: n * nh]
                om, xi = z[-2] * w0, z[-1] * w0
                r, J, dom, dxi, _ = form.evaluate(psi, om, xi=xi, scale=rscale / a, x_scale=a,
                                                  load_scale=0.0)
                P = psi.reshape(n, nh)
                Wa = np.asarray(W @ P[:, 1]).ravel()
                Wb = np.asarray(W @ P[:, 2]).ravel()
                g1 = P[:, 1] @ Wa + P[:, 2] @ Wb - 1.0
                g2 = Mphi @ P[:, 2]
                rr = np.concatenate([r, [g1, g2]])
                gx1 = np.zeros(n * nh)
                gx1[ia] = 2 * Wa
                gx1[ib] = 2 * Wb
                gx2 = np.zeros(n * nh)
                gx2[ib] = Mphi
                cols = np.column_stack([dom * w0, dxi * w0])
                if sp.issparse(J):
                    JJ = sp.bmat([[J, sp.csc_matrix(cols)],
                                  [sp.csr_matrix(np.vstack([gx1, gx2])), None]], format="csc")
                else:
                    JJ = np.block([[J, cols], [np.vstack([gx1, gx2]), np.zeros((2, 2))]])
                return rr, JJ
            return fun

        # starting point: linear mode at the first amplitude
        a_first = amps[0]
        if amplitude_dof is not None:
            scale_phi = abs(phi[int(amplitude_dof)])
            if scale_phi < 1e-12 * np.abs(phi).max():
                raise ModelError(f"amplitude_dof {amplitude_dof} does not move in mode {mode}")
        else:
            scale_phi = 1.0
        psi0 = np.zeros((n, nh))
        psi0[:, 1] = phi / scale_phi
        psi0[:, 0] = X0 / a_first
        z = np.concatenate([psi0.ravel(), [1.0, c0 / w0]])

        sols, done = [], []
        status, msg = 0, "all amplitudes converged"
        prev: list[tuple[float, np.ndarray]] = []   # (log a, z) for the secant predictor
        a_prev = None
        for a in amps:
            targets = [float(a)]
            failures = 0
            while targets:
                at = targets[0]
                guess = z.copy()
                if len(prev) >= 2:
                    (l1, z1), (l2, z2) = prev[-2], prev[-1]
                    guess = z2 + (np.log(at) - l2) / (l2 - l1) * (z2 - z1)
                if a_prev is not None:   # the static part of psi = X / a scales with 1 / a
                    g = guess[: n * nh].reshape(n, nh)
                    g[:, 0] = z[: n * nh].reshape(n, nh)[:, 0] * (a_prev / at)
                res = newton(make_fun(at), guess, tol=tol, max_iter=max_iter)
                if res.success:
                    z = res.x
                    prev = [*prev[-1:], (float(np.log(at)), z.copy())]
                    a_prev = at
                    targets.pop(0)
                    continue
                failures += 1
                if failures > max_substeps:
                    status = 2
                    msg = (f"Newton failed at amplitude {at:.4g} ({res.message}) after "
                           f"{max_substeps} step bisections; converged amplitudes returned")
                    break
                lo = a_prev if a_prev is not None else at / 4.0
                targets.insert(0, float(np.sqrt(lo * at)))
            if status != 0:
                break
            sols.append(z.copy())
            done.append(float(a))
    if not sols:
        out_status = -1
    else:
        out_status = status
    k = len(sols)
    Z = np.array(sols) if k else np.zeros((0, n * nh + 2))
    A = np.array(done, dtype=float)
    X = Z[:, : n * nh].reshape(k, n, nh) * A[:, None, None] if k else np.zeros((0, n, nh))
    om = Z[:, -2] * w0 if k else np.zeros(0)
    xi = Z[:, -1] * w0 if k else np.zeros(0)
    pp = _postprocess(s, X, om, xi=xi)
    Wc, W_visc, amp_dof = pp["W_contact"], pp["W_visc"], pp["amp"]
    err = _balance_error(pp["W_neg"], W_visc + Wc.sum(axis=1), pp["E_kin"])
    if out_status == -1:
        msg = f"no nonlinear mode found at the first amplitude: {msg}"
    result = NonlinearModes(A, om, xi / (2 * om) if k else np.zeros(0), X, amp_dof, Wc,
                            W_visc, err, w0, c0 / (2 * w0), int(mode), out_status, msg, s.H,
                            s.basis.samples, system.names, s.contact_names,
                            None if amplitude_dof is None else int(amplitude_dof))
    if throw and not result.success:
        raise ConvergenceError(msg)
    return result
