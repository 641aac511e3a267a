"""Harmonic-balance results: :class:`SteadyState`, :class:`FrequencyResponse` and the
post-processing that fills them (contact forces, energy balance per cycle, peak amplitudes).

Used by the drivers of :mod:`fricdamp.solvers.hb`, which re-exports the public names.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numba import njit

from fricdamp.results import ResultMixin
from fricdamp.solvers._hb_formulations import _Setup
from fricdamp.solvers.aft import _synthesis, aft, cycle_work


def _dofs_times(A, X: np.ndarray) -> np.ndarray:
    """``A @ X[p]`` for every point p of X (n_p, n, nh), as one sparse (or dense) product."""
    n_p, n, nh = X.shape
    Y = A @ X.transpose(1, 0, 2).reshape(n, n_p * nh)
    return np.asarray(Y).reshape(-1, n_p, nh).transpose(1, 0, 2)


def _contact_forces(s: _Setup, U: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """Harmonics of the contact forces (n_p, n_rows, nh) of the points U (n_p, n_rows, nh).

    Elements whose law has a compiled AFT step
    (:meth:`fricdamp.contact.base.ContactLaw.harmonic_response`, rate independent) are
    evaluated for all points in one call (the points as a leading batch axis); the others
    point by point through :func:`aft`.
    """
    from fricdamp.solvers.aft import element_rows

    n_p = U.shape[0]
    Fn = np.zeros_like(U)
    if not s.n_rows or not n_p:
        return Fn
    for c, rows in zip(s.contacts, element_rows(s.contacts), strict=True):
        nc, nd = c.n_contacts, c.n_dir
        hr = None
        if not c.law.velocity_dependent:
            hr = c.law.harmonic_response(U[:, rows].reshape(n_p, nc, nd, s.nh),
                                         s.basis.synthesis, s.basis.analysis, jacobian=False)
        if hr is not None:
            Fn[:, rows] = hr.force.reshape(n_p, nc * nd, s.nh)
            continue
        for p in range(n_p):
            Fn[p, rows] = aft((c,), U[p, rows], float(omega[p]), s.basis,
                              jacobian=False).force
    return Fn


def _postprocess(s: _Setup, X: np.ndarray, omega: np.ndarray, xi=None, load_scale=None):
    """Contact forces, energies and amplitudes of steady states X (n_p, n, nh)."""
    n_p = X.shape[0]
    U = _dofs_times(s.P, X) if n_p else np.zeros((0, s.n_rows, s.nh))
    Fn = _contact_forces(s, U, omega)
    Wrow = cycle_work(U, Fn)                                         # (n_p, n_rows)
    Wc = np.zeros((n_p, s.n_contacts))
    if s.n_rows:
        np.add.at(Wc.T, s.contact_of_row, Wrow.T)
    W_ext = cycle_work(X, np.broadcast_to(s.F_ex, X.shape)).sum(axis=1)
    if load_scale is not None:     # the work of the static load over a cycle is zero
        W_ext = W_ext * np.asarray(load_scale, dtype=float)
    # viscous: Omega * pi * sum_k k^2 (a^T D a + b^T D b)
    Dd = s.D
    dX = X @ s.basis.d_dtau.T                                       # coefficients of dq/dtau
    DdX = _dofs_times(Dd, dX) if n_p else dX
    W_visc = omega * np.pi * np.einsum("pnh,pnh->p", dX[:, :, 1:], DdX[:, :, 1:])
    MdX = _dofs_times(s.M, dX) if n_p else dX
    # 2 pi x mean kinetic energy over the cycle [J]: the floor of the balance error
    E_kin = omega**2 * np.pi * np.einsum("pnh,pnh->p", dX[:, :, 1:], MdX[:, :, 1:])
    W_neg = None if xi is None else xi / omega * E_kin
    amp = peak_amplitude(X)
    return dict(U=U, F=Fn, W_contact=Wc, W_ext=W_ext, W_visc=W_visc, W_neg=W_neg, amp=amp,
                E_kin=E_kin)


def peak_amplitude(X: np.ndarray, n_grid: int = 128) -> np.ndarray:
    """``max_tau |x(tau) - c0|`` of signals with coefficients X (..., 2H+1), shape (...).

    Grid search on ``n_grid`` phases, then three Newton steps on dx/dtau = 0 from the best
    sample (the extremum of a trigonometric polynomial to machine precision); compiled
    (:func:`_peak_kernel`), one pass per signal.
    """
    X = np.asarray(X, dtype=float)
    shape = X.shape[:-1]
    C = np.ascontiguousarray(X.reshape(-1, X.shape[-1]))
    H = (C.shape[1] - 1) // 2
    if C.shape[0] == 0:
        return np.zeros(shape)
    out = np.empty(C.shape[0])
    _peak_kernel(C, _fine_synthesis(H, n_grid), out)
    return out.reshape(shape)


@njit(cache=True, nogil=True)
def _peak_kernel(C, S, out):  # pragma: no cover - compiled
    """:func:`peak_amplitude` of the rows of C (m, 2H+1) with the grid synthesis S."""
    m, nc = C.shape
    H = (nc - 1) // 2
    n_grid = S.shape[0]
    for j in range(m):
        best = -1.0
        ib = 0
        xb = 0.0
        for i in range(n_grid):
            v = 0.0
            for h in range(1, nc):
                v += C[j, h] * S[i, h]
            a = abs(v)
            if a > best:
                best = a
                ib = i
                xb = v
        sgn = 1.0 if xb > 0 else (-1.0 if xb < 0 else 0.0)
        tau = 2.0 * np.pi * ib / n_grid
        for _ in range(3):
            d1 = 0.0
            d2 = 0.0
            for k in range(1, H + 1):
                c = np.cos(k * tau)
                s = np.sin(k * tau)
                a = C[j, 2 * k - 1]
                b = C[j, 2 * k]
                d1 += k * (-a * s + b * c)
                d2 += -(k * k) * (a * c + b * s)
            if d2 * sgn < 0:
                tau = tau - d1 / d2
        v = 0.0
        for k in range(1, H + 1):
            v += C[j, 2 * k - 1] * np.cos(k * tau) + C[j, 2 * k] * np.sin(k * tau)
        out[j] = max(abs(v), best)


_FINE: dict[int, np.ndarray] = {}


def _fine_synthesis(H: int, n_t: int = 256) -> np.ndarray:
    key = (H, n_t)
    if key not in _FINE:
        _FINE[key] = _synthesis(H, n_t)
    return _FINE[key]


def _balance_error(W_in, W_out, E_ref):
    """|W_in - W_out| / max(|W_in|, |W_out|, 1e-8 E_ref): 0 for a conservative cycle."""
    den = np.maximum(np.maximum(np.abs(W_in), np.abs(W_out)), 1e-8 * np.abs(E_ref))
    return np.abs(W_in - W_out) / np.maximum(den, 1e-300)


@dataclass(frozen=True, eq=False, repr=False)
class SteadyState(ResultMixin):
    """One periodic steady state from :func:`harmonic_balance`.

    Attributes
    ----------
    omega : float
        Excitation (fundamental) angular frequency [rad/s]; the same as ``omega_rad_s``
        (``frequency_hz`` in Hz). The name ``omega`` is kept for compatibility.
    coefficients : ndarray, shape (n_dof, 2H+1)
        Real harmonic coefficients ``[c0, a1, b1, ..., aH, bH]`` of every DOF [m].
    amplitude : ndarray, shape (n_dof,)
        Largest excursion from the mean over the period, ``max_t |q(t) - c0|`` [m].
    contact_displacement, contact_force : ndarray, shape (n_rows, 2H+1)
        Harmonics of the local relative displacements [m] and contact forces [N].
    dissipated_energy : ndarray, shape (n_contacts,)
        ``oint f . du`` per contact per cycle [J].
    external_work, viscous_dissipation : float
        Work of the loads and of the viscous damping per cycle [J].
    energy_balance_error : float
        ``|W_ext - W_visc - sum W_contact| / max(...)``.
    success : bool
    status : int
        0 converged; 1 Newton failed: every array is then NaN (no solution is returned).
    message : str
    iterations : int
    residual_norm : float
        Max-norm of the scaled residual.
    harmonics, samples : int
    method : str
    """

    omega: float
    coefficients: np.ndarray
    amplitude: np.ndarray
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    dissipated_energy: np.ndarray
    external_work: float
    viscous_dissipation: float
    energy_balance_error: float
    success: bool
    status: int
    message: str
    iterations: int
    residual_norm: float
    harmonics: int
    samples: int
    method: str
    dof_names: tuple[str, ...] = ()
    contact_names: tuple[str, ...] = ()
    system: object = field(default=None, repr=False, compare=False)

    @property
    def verdict(self):
        """:class:`fricdamp.verdict.Verdict`, judged on first access: ``failed`` if Newton
        did not converge; else the energy balance and, when the result knows its system
        (:func:`harmonic_balance` sets it), the harmonic truncation and AFT sampling error of
        :func:`fricdamp.verdict.harmonic_truncation` (the point solved again with more
        harmonics and twice the samples: "H too small" is ``unreliable``)."""
        cached = self.__dict__.get("_verdict")
        if cached is None:
            cached = _hb_verdict(self.system, self.success, self.message,
                                 float(self.energy_balance_error), float(self.omega),
                                 self.coefficients, self.harmonics, self.samples)
            object.__setattr__(self, "_verdict", cached)
        return cached

    @property
    def frequency_hz(self) -> float:
        """Excitation frequency [Hz]."""
        return float(self.omega) / (2 * np.pi)

    @property
    def omega_rad_s(self) -> float:
        """Excitation angular frequency [rad/s] (the same as ``omega``)."""
        return float(self.omega)

    def time_history(self, n_samples: int = 256) -> tuple[np.ndarray, np.ndarray]:
        """One period: times t [s] shape (n_samples,) and q(t) shape (n_samples, n_dof)."""
        S = _fine_synthesis(self.harmonics, int(n_samples))
        t = 2 * np.pi * np.arange(n_samples) / n_samples / self.omega
        return t, S @ self.coefficients.T

    def to_xarray(self):
        """``xarray.Dataset``: harmonic coefficients and one period of every DOF, contact
        harmonics and the energies per cycle; ``frequency_hz`` in the attributes."""
        import xarray as xr

        H = self.harmonics
        coef = ["c0"] + [f"{ab}{k}" for k in range(1, H + 1) for ab in ("a", "b")]
        dofs = list(self.dof_names) or [f"q{i + 1}" for i in range(self.coefficients.shape[0])]
        t, q = self.time_history()
        return xr.Dataset(
            {"coefficients": (("dof", "coefficient"), self.coefficients, {"units": "m"}),
             "amplitude": (("dof",), self.amplitude, {"units": "m"}),
             "q": (("time", "dof"), q, {"units": "m", "long_name": "displacement"}),
             "contact_displacement": (("row", "coefficient"), self.contact_displacement,
                                      {"units": "m"}),
             "contact_force": (("row", "coefficient"), self.contact_force, {"units": "N"}),
             "dissipated_energy": (("contact",), np.atleast_1d(self.dissipated_energy),
                                   {"units": "J", "long_name": "per cycle"})},
            coords={"time": ("time", t, {"units": "s"}), "dof": dofs, "coefficient": coef},
            attrs={"frequency_hz": self.frequency_hz, "omega_rad_s": self.omega_rad_s,
                   "external_work_J": float(self.external_work),
                   "viscous_dissipation_J": float(self.viscous_dissipation),
                   "energy_balance_error": float(self.energy_balance_error),
                   "harmonics": H, "samples": self.samples, "status": self.status,
                   "message": self.message, "method": self.method})

    def plot(self, dofs=None, ax=None):
        """One period of the chosen DOFs (indices, default all); returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 3.5), layout="constrained")
        t, q = self.time_history()
        names = list(self.dof_names) or [f"q{i + 1}" for i in range(q.shape[1])]
        for i in (range(q.shape[1]) if dofs is None else dofs):
            ax.plot(1e3 * t, q[:, i], lw=1, label=names[i])
        ax.set_xlabel("time over one period [ms]")
        ax.set_ylabel("displacement [m]")
        ax.set_title(f"steady state at {self.frequency_hz:.4g} Hz", fontsize="small")
        ax.legend(loc="upper right", fontsize="small")
        return ax


@dataclass(frozen=True, eq=False)
class Bifurcation:
    """A bifurcation located on a harmonic-balance branch
    (:mod:`fricdamp.solvers.hb_stability`).

    Attributes
    ----------
    type : str
        "fold" (turning point), "branch_point", "neimark_sacker" or "period_doubling".
    omega : float
        Excitation angular frequency [rad/s] at the bifurcation (``frequency_hz`` in Hz).
    load_scale : float
        Factor on the harmonic loads there (1 on a frequency response).
    amplitude : ndarray, shape (n_dof,)
        ``max_t |q(t) - mean|`` of each DOF [m].
    coefficients : ndarray, shape (n_dof, 2H+1)
        Harmonic coefficients of the solution at the bifurcation [m].
    after_point : int
        Index of the branch point after which it lies (between it and the next).
    multiplier : complex
        The critical Floquet multiplier there (on the unit circle up to the location
        accuracy: +1 at folds and branch points, -1 at period doubling, e^{+-i theta} at
        Neimark-Sacker points).
    located : bool
        Located by regula falsi to the corrector tolerance; False: the nearer of the two
        bracketing points is reported.
    """

    type: str
    omega: float
    load_scale: float
    amplitude: np.ndarray
    coefficients: np.ndarray
    after_point: int
    multiplier: complex
    located: bool

    @property
    def frequency_hz(self) -> float:
        """Excitation frequency at the bifurcation [Hz]."""
        return float(self.omega) / (2 * np.pi)

    def as_dict(self, dof: int | None = None) -> dict:
        """JSON-ready record; ``amplitude_m`` is that of ``dof`` if given, else per DOF."""
        amp = (float(self.amplitude[dof]) if dof is not None
               else [float(a) for a in self.amplitude])
        return {"type": self.type, "omega_rad_s": float(self.omega),
                "frequency_hz": float(self.omega / (2 * np.pi)), "amplitude_m": amp,
                "load_scale": float(self.load_scale), "after_point": int(self.after_point),
                "floquet_multiplier_abs": float(abs(self.multiplier)),
                "floquet_multiplier_angle_rad": float(np.angle(self.multiplier)),
                "located": bool(self.located)}


@dataclass(frozen=True, eq=False, repr=False)
class FrequencyResponse(ResultMixin):
    """Frequency response curve from :func:`frequency_response` (converged points only).

    Attributes
    ----------
    omega : ndarray, shape (n_points,)
        Excitation angular frequency [rad/s] along the path (not monotone past folds). Kept
        for compatibility: prefer ``frequency_hz`` [Hz] or ``omega_rad_s`` [rad/s].
    coefficients : ndarray, shape (n_points, n_dof, 2H+1)
        Harmonic coefficients of the DOFs [m] (see :mod:`fricdamp.solvers.aft`).
    amplitude : ndarray, shape (n_points, n_dof)
        ``max_t |q(t) - mean|`` [m].
    fundamental : ndarray, shape (n_points, n_dof)
        Amplitude of the first harmonic ``sqrt(a1^2 + b1^2)`` [m].
    contact_displacement, contact_force : ndarray, shape (n_points, n_rows, 2H+1)
        Harmonics of the contact relative displacements [m] and forces [N].
    dissipated_energy : ndarray, shape (n_points, n_contacts)
        Energy dissipated per cycle by each contact [J].
    external_work, viscous_dissipation : ndarray, shape (n_points,)
        Per cycle [J].
    energy_balance_error : ndarray, shape (n_points,)
        Relative energy balance error of each point.
    iterations : ndarray, shape (n_points,)
        Newton iterations per point.
    turning_points : tuple of int
        Indices of points after which Omega turns back (folds).
    status : int
        0 success; 1 max points; 2 stalled; 3 turned back; 4 callback; -1 no start point.
    message : str
    harmonics, samples : int
    method : str
        Formulation used ("full-dense", "full-sparse", "condensed-modal", ...).
    wall_time : float
        Seconds spent in the continuation.
    n_evaluations, n_factorizations : int
    dof_names, contact_names : tuple of str
    load_scale : ndarray, shape (n_points,)
        Factor on the harmonic loads (1 for a frequency response; the continued parameter
        of :func:`load_response`).
    parameter : str
        The continued parameter: "omega" or "load".
    stable : ndarray of bool, shape (n_points,), optional
        Hill stability of each point (``stability=True`` only; else None).
    floquet_exponents : ndarray, shape (n_points, 2 n_dof), complex, optional
        Retained Floquet exponents [1/s] of each point, by decreasing real part.
    bifurcations : tuple of Bifurcation
        Folds, branch points, Neimark-Sacker and period-doubling points located along the
        branch (``stability=True`` only).
    stability_error : float
        Largest change [1/s] of the retained exponents when the checked points are re-solved
        with H + 1 harmonics (NaN without stability).
    stability_converged : bool or None
        The H + 1 check gives the same verdicts at the checked points.

    Notes
    -----
    ``amplitude``, ``contact_displacement``, ``contact_force``, ``dissipated_energy``,
    ``external_work``, ``viscous_dissipation`` and ``energy_balance_error`` are computed
    together when one of them is first read (then kept): a caller that needs only the
    coefficients does not pay for them.
    """

    omega: np.ndarray
    coefficients: np.ndarray
    amplitude: np.ndarray
    fundamental: np.ndarray
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    dissipated_energy: np.ndarray
    external_work: np.ndarray
    viscous_dissipation: np.ndarray
    energy_balance_error: np.ndarray
    iterations: np.ndarray
    turning_points: tuple[int, ...]
    status: int
    message: str
    harmonics: int
    samples: int
    method: str
    wall_time: float
    n_evaluations: int
    n_factorizations: int
    dof_names: tuple[str, ...] = ()
    contact_names: tuple[str, ...] = ()
    load_scale: np.ndarray | None = None
    parameter: str = "omega"
    stable: np.ndarray | None = None
    floquet_exponents: np.ndarray | None = None
    bifurcations: tuple[Bifurcation, ...] = ()
    stability_error: float = float("nan")
    stability_converged: bool | None = None
    system: object = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        if self.parameter == "omega" and self.system is not None:
            _require_harmonic_load(self.system)
        post = self.__dict__.get("amplitude")
        if isinstance(post, _Pending):
            # post-processed fields computed on first access (see _Pending): removed from
            # the instance so that attribute lookup falls through to __getattr__
            for name in _Pending.FIELDS:
                object.__delattr__(self, name)
            object.__setattr__(self, "_pending", post)

    def __getattr__(self, name):
        # only reached for attributes not (yet) in the instance: the pending post-processed
        # fields, computed all at once and then kept like the other fields
        pending = self.__dict__.get("_pending")
        if pending is None or name not in _Pending.FIELDS:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        for key, value in pending.compute().items():
            object.__setattr__(self, key, value)
        object.__delattr__(self, "_pending")
        return self.__dict__[name]

    def __getstate__(self):
        if "_pending" in self.__dict__:       # pickled with its values, not the set-up
            self.amplitude  # noqa: B018 - computes the pending fields
        return dict(self.__dict__)

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def n_points(self) -> int:
        return int(self.omega.size)

    @property
    def frequency_hz(self) -> np.ndarray:
        """Excitation frequency [Hz] along the path, shape (n_points,)."""
        return self.omega / (2 * np.pi)

    @property
    def omega_rad_s(self) -> np.ndarray:
        """Excitation angular frequency [rad/s] (the same as ``omega``), shape (n_points,)."""
        return self.omega

    def peak_hz(self, dof: int = 0, *, refine: bool = True) -> tuple[float, float]:
        """(frequency [Hz], amplitude [m]) of the largest response of ``dof`` (see
        :meth:`peak`)."""
        w, a = self.peak(dof, refine=refine)
        return w / (2 * np.pi), a

    @property
    def peak_truncated(self) -> bool:
        """The largest amplitude (of any DOF) lies at an end of the computed curve: it is
        not a resonance peak."""
        if self.n_points < 3:
            return True
        i = int(np.argmax(np.max(self.amplitude, axis=1)))
        return i in (0, self.n_points - 1)

    @property
    def verdict(self):
        """:class:`fricdamp.verdict.Verdict` from what the curve itself knows: ``failed`` if
        the continuation did not reach its end (``status != 0``), ``unreliable`` if the energy
        balance exceeds its limit. With the system (set by :func:`frequency_response` for a
        frequency curve) the harmonic truncation and AFT sampling error of
        :func:`fricdamp.verdict.harmonic_truncation` at the largest response are judged too
        (computed on first access, then kept)."""
        cached = self.__dict__.get("_verdict")
        if cached is not None:
            return cached
        ebe = float(np.max(self.energy_balance_error)) if self.n_points else float("nan")
        failed = None if self.success else (
            f"the continuation stopped (status {self.status}): {self.message}")
        system = self.system if getattr(self, "parameter", "omega") == "omega" else None
        ipk = int(np.argmax(np.max(self.amplitude, axis=1))) if self.n_points else 0
        cached = _hb_verdict(system, failed is None, failed, ebe,
                             float(self.omega[ipk]) if self.n_points else float("nan"),
                             self.coefficients[ipk] if self.n_points else None,
                             self.harmonics, self.samples,
                             extra={"peak_truncated": self.peak_truncated})
        object.__setattr__(self, "_verdict", cached)
        return cached

    def steady_state(self, i: int) -> SteadyState:
        """Point ``i`` as a :class:`SteadyState`."""
        return SteadyState(float(self.omega[i]), self.coefficients[i], self.amplitude[i],
                           self.contact_displacement[i], self.contact_force[i],
                           self.dissipated_energy[i], float(self.external_work[i]),
                           float(self.viscous_dissipation[i]),
                           float(self.energy_balance_error[i]), True, 0, "converged",
                           int(self.iterations[i]), 0.0, self.harmonics, self.samples,
                           self.method, self.dof_names, self.contact_names,
                           system=self.system if self.parameter == "omega" else None)

    def peak(self, dof: int = 0, *, refine: bool = True) -> tuple[float, float]:
        """(Omega [rad/s], amplitude [m]) of the largest ``amplitude`` of ``dof``.

        With ``refine`` the vertex of the parabola through the largest point and its two
        neighbours (when they bracket it in Omega) is returned instead of the point itself.
        """
        A = self.amplitude[:, dof]
        i = int(np.argmax(A))
        w, a = float(self.omega[i]), float(A[i])
        if refine and 0 < i < A.size - 1:
            x = self.omega[i - 1: i + 2]
            y = A[i - 1: i + 2]
            if (x[1] - x[0]) * (x[2] - x[1]) > 0:
                c2, c1, c0 = np.polyfit(x - x[1], y, 2)
                if c2 < 0:
                    xv = -c1 / (2 * c2)
                    if min(x[0], x[2]) - x[1] <= xv <= max(x[0], x[2]) - x[1]:
                        w, a = float(x[1] + xv), float(c0 - c1**2 / (4 * c2))
        return w, a

    def to_xarray(self):
        """``xarray.Dataset`` with dimensions point, dof, coefficient, row, contact."""
        import xarray as xr

        H = self.harmonics
        coef = ["c0"] + [f"{ab}{k}" for k in range(1, H + 1) for ab in ("a", "b")]
        dofs = list(self.dof_names) or [f"q{i + 1}" for i in range(self.coefficients.shape[1])]
        contacts = list(self.contact_names) or [
            f"c{i}" for i in range(self.dissipated_energy.shape[1])]
        ds = xr.Dataset(
            {
                "coefficients": (("point", "dof", "coefficient"), self.coefficients,
                                 {"units": "m"}),
                "amplitude": (("point", "dof"), self.amplitude, {"units": "m"}),
                "fundamental": (("point", "dof"), self.fundamental, {"units": "m"}),
                "contact_displacement": (("point", "row", "coefficient"),
                                         self.contact_displacement, {"units": "m"}),
                "contact_force": (("point", "row", "coefficient"), self.contact_force,
                                  {"units": "N"}),
                "dissipated_energy": (("point", "contact"), self.dissipated_energy,
                                      {"units": "J"}),
                "external_work": (("point",), self.external_work, {"units": "J"}),
                "viscous_dissipation": (("point",), self.viscous_dissipation, {"units": "J"}),
                "energy_balance_error": (("point",), self.energy_balance_error,
                                         {"units": "1"}),
                "iterations": (("point",), self.iterations),
                "load_scale": (("point",), np.ones(self.omega.size) if self.load_scale is None
                               else self.load_scale, {"units": "1"}),
            },
            coords={"omega": (("point",), self.omega, {"units": "rad/s"}),
                    "frequency": (("point",), self.frequency_hz,
                                  {"units": "Hz", "long_name": "excitation frequency"}),
                    "dof": dofs, "coefficient": coef, "contact": contacts},
            attrs={"harmonics": H, "samples": self.samples, "status": self.status,
                   "message": self.message, "method": self.method},
        )
        if self.stable is not None:
            ds["stable"] = (("point",), self.stable.astype(np.int8),
                            {"description": "1 stable, 0 unstable (Hill)"})
            ds["floquet_exponent_real"] = (("point", "exponent"),
                                           self.floquet_exponents.real, {"units": "1/s"})
            ds["floquet_exponent_imag"] = (("point", "exponent"),
                                           self.floquet_exponents.imag, {"units": "1/s"})
            ds.attrs["stability_error_per_s"] = self.stability_error
        return ds

    def plot(self, dof: int = 0, ax=None, **kwargs):
        """Amplitude of ``dof`` vs excitation frequency [Hz] (or load scale); returns axes.

        With stability computed, unstable parts are dashed and bifurcations circled."""
        import matplotlib.pyplot as plt

        from fricdamp.plot import dof_label

        if ax is None:
            _, ax = plt.subplots(layout="constrained")
        name = dof_label(self.dof_names[dof]) if self.dof_names else f"q{dof + 1}"
        if self.parameter == "load":
            x = self.load_scale
            ax.set_xlabel("load scale [-]")
        else:
            x = self.omega / (2 * np.pi)
            ax.set_xlabel("excitation frequency [Hz]")
        if self.stable is None:
            ax.plot(x, self.amplitude[:, dof], **kwargs)
        else:
            from fricdamp.plot import stability_line

            stability_line(ax, x, self.amplitude[:, dof], self.stable, **kwargs)
            for b in self.bifurcations:
                bx = b.load_scale if self.parameter == "load" else b.omega / (2 * np.pi)
                ax.plot(bx, b.amplitude[dof], "o", ms=4, mfc="none", color="k")
        ax.set_ylabel(f"amplitude of {name} [m]")
        if not self.success:
            ax.set_title(f"incomplete: {self.message}", fontsize="small")
        return ax


class _Pending:
    """The post-processed fields of a :class:`FrequencyResponse`, computed when first read.

    The contact forces, energies per cycle and peak amplitudes of every point (every DOF,
    128 phases each) cost as much as a tenth of the continuation on the ring of 30 or 480
    Jenkins contacts; a curve whose caller reads only the coefficients or one DOF's peak
    pays nothing for them, and any other caller gets the same values on first access
    (``compute`` is the former eager post-processing, with the same BLAS thread limit).
    Passed as the ``amplitude`` argument; the other pending fields are passed as None.
    """

    FIELDS = ("amplitude", "contact_displacement", "contact_force", "dissipated_energy",
              "external_work", "viscous_dissipation", "energy_balance_error")

    __slots__ = ("fn",)

    def __init__(self, fn):
        self.fn = fn

    def compute(self) -> dict:
        """Values of :data:`FIELDS` (calls ``fn() -> dict``)."""
        out = self.fn()
        return {k: out[k] for k in self.FIELDS}


def _require_harmonic_load(system) -> None:
    """A frequency response needs a harmonic load: without one the response is zero at
    every frequency (raise a ModelError saying what to do)."""
    from fricdamp.errors import ModelError
    from fricdamp.structure.system import HarmonicLoad

    for ld in getattr(system, "loads", ()):
        if isinstance(ld, HarmonicLoad) and ld.harmonic >= 1 and np.any(ld.amplitude != 0):
            return
    raise ModelError("frequency_response: the system has no harmonic load (system.loads holds "
                     "none with harmonic >= 1 and a nonzero amplitude), so its response is zero "
                     "at every frequency: add one, e.g. system.with_loads(HarmonicLoad("
                     "amplitude)); for the resonances of the free system use modes() or "
                     "nonlinear_modes()")


def _hb_verdict(system, success: bool, message, energy_balance_error: float, omega: float,
                coefficients, harmonics: int, samples: int, extra: dict | None = None):
    """Verdict of an HB result: failed, or the energy balance and -- with the system -- the
    harmonic truncation and AFT sampling error at ``omega`` (see the results' ``verdict``)."""
    from fricdamp.verdict import harmonic_truncation, judge

    est = {"energy_balance_error": energy_balance_error, **(extra or {})}
    if not success:
        return judge(est, failed=message)
    if system is not None and coefficients is not None and np.all(np.isfinite(coefficients)):
        trunc = harmonic_truncation(system, omega, coefficients, harmonics=harmonics,
                                    samples=samples)
        est["harmonic_truncation"] = trunc.get("harmonic_truncation")
        est["aft_sampling_error"] = trunc.get("aft_sampling_error")
    return judge(est)
