"""Multi-harmonic balance with AFT contact forces, frequency response by continuation.

The steady periodic response of ``M q'' + D q' + K q + P^T f(P q) = F_static + F(t)`` at
excitation frequency Omega is sought as ``q(tau) = Q_0 + sum_{k=1..H} a_k cos k tau +
b_k sin k tau`` (``tau = Omega t``, real coefficients ``[c0, a1, b1, ..., aH, bH]``, see
:mod:`fricdamp.solvers.aft`). Galerkin projection onto the harmonics gives, per harmonic k,

    (K - k^2 Omega^2 M) a_k + k Omega D b_k + F^nl_{a,k} = F_{a,k}
    (K - k^2 Omega^2 M) b_k - k Omega D a_k + F^nl_{b,k} = F_{b,k}

(and ``K Q_0 + F^nl_0 = F_static`` for the static term), with the contact-force harmonics
``F^nl`` from the AFT step. Two equivalent formulations are solved:

* ``"full"``: unknowns are the harmonics of all DOFs; the Jacobian ``S(Omega) + (P^T x I)
  J_nl (P x I)`` is assembled into a fixed sparsity pattern (dense below ~200 unknowns) —
  one sparse LU per Newton step; this is the choice when every DOF carries a contact (ring
  of oscillators) or K is singular (a structure held only by its contacts).
* ``"condensed"``: the linear DOFs are eliminated harmonic by harmonic through the dynamic
  compliance ``R_k(Omega) = P Z_k^{-1} P^T`` with ``Z_k = K - k^2 Omega^2 M + i k Omega D``
  (exactly, by modal superposition when D is classically damped, else by direct solves);
  the unknowns are the contact relative-displacement harmonics u and the residual
  ``u - u_lin(Omega) + R(Omega) F^nl(u) = 0`` [m]. It pays whenever the contacts see fewer
  coordinates than the structure has DOFs (``method="auto"`` picks it then).

Frequency response curves (:func:`frequency_response`) are continued in Omega, and
response-vs-load curves (:func:`load_response`) in the excitation level, by the
problem-agnostic :func:`fricdamp.solvers.continuation.solve_and_continue`. Every steady
state carries its energy balance over one period: work of the external force = viscous
dissipation + dissipation of each contact (``oint f du``); with converged harmonic balance
this identity holds to the Newton tolerance (a consistency check of residual and
post-processing, not an accuracy estimate: for that compare harmonics H and 2H).

Accuracy and limits: the AFT samples the force at N instants, so a stick-slip transition is
located to within one sample (force error ~(2 pi / N)^2 for Jenkins kinks; on a cyclic
assembly the discrete AFT is shift invariant only if the inter-sector phase is a whole number
of samples). Laws with a discontinuous return map (static > kinetic friction) make the
residual discontinuous; Newton may then stall, and the result says so.

Layout: this module holds the drivers (:func:`harmonic_balance`, :func:`frequency_response`,
:func:`load_response`, :func:`engine_order_load`); the formulations (residuals and Jacobians)
are in :mod:`fricdamp.solvers._hb_formulations` and the result objects and post-processing in
:mod:`fricdamp.solvers._hb_results`. Their names are importable from here as before.

References
----------
Cameron & Griffin (1989), J. Appl. Mech. 56, 149-154 (AFT).
Krack & Gross (2019), *Harmonic Balance for Nonlinear Vibration Problems*, Springer.
Petrov & Ewins (2003), J. Turbomach. 125, 364-371 (analytic Jacobians for friction HB).
"""

from __future__ import annotations

import logging
import os
import sys
import time

import numpy as np

from fricdamp import _numba_cache
from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.solvers import _hb_results
from fricdamp.solvers._hb_formulations import (
    DENSE_LIMIT,  # noqa: F401 - re-exported
    _choose,
    _Condensed,
    _dense,  # noqa: F401 - re-exported (fricdamp.solvers.nma)
    _Full,
    _is_symmetric,  # noqa: F401 - re-exported
    _Setup,
    _static_only,  # noqa: F401 - re-exported
    excitation_coefficients,  # noqa: F401 - re-exported
)
from fricdamp.solvers._hb_results import (
    _FINE,  # noqa: F401 - re-exported
    Bifurcation,
    FrequencyResponse,
    SteadyState,
    _balance_error,
    _fine_synthesis,  # noqa: F401 - re-exported
    _postprocess,
    peak_amplitude,  # noqa: F401 - re-exported
)
from fricdamp.solvers.continuation import blas_threads, newton, solve_and_continue
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem

# the curve's post-processing kernel loads its numba cache without the registry refresh
# (fricdamp._numba_cache), like the kernels of the residual and the block LU
_numba_cache.fast_load(getattr(_hb_results, "_peak_kernel", None))

__all__ = [
    "Bifurcation",
    "FrequencyResponse",
    "SteadyState",
    "engine_order_load",
    "frequency_response",
    "harmonic_balance",
    "load_response",
]

logger = logging.getLogger(__name__)

#: Chord steps in the continuation corrector (see :func:`solve_and_continue`); a module
#: switch so that benchmarks and tests can run the Newton corrector as the reference path.
REUSE_FACTORIZATION = False
#: Factorise the sparse full Jacobian by dense DOF blocks (2H+1 harmonics) with the symbolic
#: analysis kept (:mod:`fricdamp.solvers._sparse_lu`); False: SuperLU at every step (the
#: reference path of the tests).
BLOCK_LU = True


# ============================================================================ drivers
def _scales(s: _Setup, form, omegas) -> tuple[float, float]:
    """Typical unknown magnitude (from linear stuck / free responses) and force scale."""
    Kc = s.tangent_contact_stiffness()
    stuck, free = [], []
    for w in omegas:
        Xs = s.linear_response(w, Kc)
        if Xs is not None:
            stuck.append(np.abs(s.P @ Xs).max() if isinstance(form, _Condensed)
                         else np.abs(Xs).max())
        Xf = s.linear_response(w)
        if Xf is not None:
            free.append(np.abs(s.P @ Xf).max() if isinstance(form, _Condensed)
                        else np.abs(Xf).max())
    cand = [np.max(stuck) if stuck else 0.0, np.median(free) if free else 0.0]
    x_ref = max(cand)
    if not np.isfinite(x_ref) or x_ref <= 0:
        x_ref = 1.0
    f_ref = float(np.abs(s.F_ex).max())
    if f_ref <= 0:
        f_ref = 1.0
    return float(x_ref), f_ref


def _initial_guess(s: _Setup, form, omega, initial_guess):
    """Candidate starting points (unscaled unknowns of ``form``)."""
    if initial_guess is not None:
        g = np.asarray(initial_guess, dtype=float)
        if g.shape == (s.n, s.nh):
            return [g.ravel() if isinstance(form, _Full) else (s.P @ g).ravel()]
        if g.size == form.N:
            return [g.ravel()]
        raise ModelError(f"initial_guess must have shape (n_dof, 2H+1) = ({s.n}, {s.nh}), got "
                         f"{g.shape}")
    out = []
    for Kx in (s.tangent_contact_stiffness(), None):
        X = s.linear_response(omega, Kx)
        if X is not None:
            out.append(X.ravel() if isinstance(form, _Full) else (s.P @ X).ravel())
    out.append(np.zeros(form.N))
    return out


def _check_size(system, harmonics, samples) -> None:
    """Refuse (CheckError naming the parameter) a size that does not fit in memory."""
    from fricdamp.limits import check_harmonics_memory

    if isinstance(harmonics, int) and not isinstance(harmonics, bool) and harmonics >= 1 and (
            samples is None or (isinstance(samples, int) and samples >= 1)):
        rows = sum(c.n_contacts * c.n_dir for c in getattr(system, "contacts", ()))
        check_harmonics_memory(harmonics, samples, int(getattr(system, "n_dof", 1)), rows)


def _block_size(form) -> int | None:
    """Dense blocks of the sparse full Jacobian: the 2H+1 coefficients of a DOF."""
    if isinstance(form, _Full) and not form.dense and BLOCK_LU:
        return form.s.nh
    return None


def _method_name(form) -> str:
    if isinstance(form, _Full):
        return "full-dense" if form.dense else "full-sparse"
    return f"condensed-{form.kind}"


def harmonic_balance(system: MechanicalSystem, omega: float, *, harmonics: int = 5,
                     samples: int | None = None, initial_guess=None, method: str = "auto",
                     tol: float = 1e-10, max_iter: int = 100, blas: int | None = 1,
                     throw: bool = False) -> SteadyState:
    """Periodic steady state at one excitation frequency by harmonic balance with AFT.

    Parameters
    ----------
    system : MechanicalSystem
        Structure with contacts; loads must be :class:`HarmonicLoad` (their ``omega`` is
        replaced by ``omega``) plus the static load.
    omega : float
        Excitation angular frequency Omega [rad/s], > 0.
    harmonics : int
        Highest harmonic H (>= 1; >= 7 for friction responses to ~1 %).
    samples : int, optional
        AFT time samples N per period (>= 2H + 1; default the power of two >= 16 H).
    initial_guess : ndarray, shape (n_dof, 2H+1), optional
        Starting coefficients; by default the linear responses with stuck, then free,
        contacts and zero are tried in turn.
    method : {"auto", "full", "condensed"}
        Formulation (see the module docstring).
    tol : float
        Newton tolerance on the max-norm of the residual scaled by the load (full) or by
        the typical contact displacement (condensed).
    max_iter : int
        Newton iterations (with backtracking) per starting guess.
    blas : int or None
        BLAS threads during the solve (default 1; None leaves the pools alone).
    throw : bool
        Raise ConvergenceError when Newton fails instead of returning ``success=False``.

    Returns
    -------
    SteadyState

    Examples
    --------
    >>> import numpy as np
    >>> from fricdamp.contact import Jenkins
    >>> from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem
    >>> sys = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
    ...     contacts=(ContactElement(Jenkins(1.0, 0.05), [[1.0]]),),
    ...     loads=(HarmonicLoad([0.1], omega=1.0),))
    >>> ss = harmonic_balance(sys, 1.2, harmonics=7)
    >>> bool(ss.success), ss.energy_balance_error < 1e-6
    (True, True)
    """
    if not (np.isfinite(omega) and omega > 0):
        raise ModelError(f"omega must be > 0 rad/s, got {omega!r}")
    _check_size(system, harmonics, samples)
    s = _Setup(system, harmonics, samples)
    with blas_threads(blas):
        form = _choose(s, method)
        x_ref, f_ref = _scales(s, form, [omega])
        scale = 1.0 / (f_ref if isinstance(form, _Full) else x_ref)

        def fun(x):
            r, J, _, _, _ = form.evaluate(x, omega, scale=scale, x_scale=x_ref,
                                          aft_result=False)
            return r, J

        block = _block_size(form)

        best = None
        for g in _initial_guess(s, form, omega, initial_guess):
            res = newton(fun, g / x_ref, tol=tol, max_iter=max_iter, block_size=block)
            if best is None or res.residual_norm < best.residual_norm:
                best = res
            if res.success:
                break
        X = form.to_dofs(best.x, omega, x_ref) if best.success else None
    if not best.success:
        msg = (f"Newton failed at omega = {omega:g} rad/s: {best.message} (residual "
               f"{best.residual_norm:.3g}); no solution is returned (NaN): try another "
               "initial_guess, more samples, or frequency_response to approach it by "
               "continuation")
        if throw:
            raise ConvergenceError(msg)
        nan = np.full
        return SteadyState(float(omega), nan((s.n, s.nh), np.nan), nan(s.n, np.nan),
                           nan((s.n_rows, s.nh), np.nan), nan((s.n_rows, s.nh), np.nan),
                           nan(s.n_contacts, np.nan), np.nan, np.nan, np.nan, False, 1, msg,
                           best.iterations, best.residual_norm, s.H, s.basis.samples,
                           _method_name(form), system.names, s.contact_names)
    pp = _postprocess(s, X[None], np.array([omega]))
    err = _balance_error(pp["W_ext"], pp["W_visc"] + pp["W_contact"].sum(axis=1), pp["E_kin"])
    return SteadyState(float(omega), X, pp["amp"][0], pp["U"][0], pp["F"][0],
                       pp["W_contact"][0], float(pp["W_ext"][0]), float(pp["W_visc"][0]),
                       float(err[0]), True, 0, best.message, best.iterations,
                       best.residual_norm, s.H, s.basis.samples, _method_name(form),
                       system.names, s.contact_names, system=system)


def frequency_response(system: MechanicalSystem, omega_start: float, omega_end: float, *,
                       harmonics: int = 5, samples: int | None = None, step: float = 0.02,
                       min_step: float | None = None, max_step: float | None = None,
                       max_points: int = 2000, method: str = "auto", tol: float = 1e-9,
                       initial_guess=None, max_angle_deg: float = 25.0,
                       stability: bool = False, sorting: str = "eigenvector",
                       blas: int | None = 1, throw: bool = False,
                       progress: bool | None = None) -> FrequencyResponse:
    """Frequency response curve through resonance by HB-AFT and arclength continuation.

    Parameters
    ----------
    system : MechanicalSystem
        Structure, contacts and harmonic loads (their ``omega`` is the continued Omega).
        For engine-order forcing of a cyclic assembly use :func:`engine_order_load`.
    omega_start, omega_end : float
        Excitation frequency interval [rad/s] (either direction), > 0.
    harmonics : int
        Highest harmonic H.
    samples : int, optional
        AFT samples N per period (default the power of two >= 16 H).
    step : float
        Initial arclength step in scaled variables: Omega is scaled by
        ``|omega_end - omega_start|`` and the unknowns by the largest linear (stuck
        contacts) response over the interval, so 0.02 is about 1/50 of the interval.
    min_step, max_step : float, optional
        Step bounds (default ``step / 1000`` and ``5 * step``).
    max_points : int
        Largest number of points.
    method : {"auto", "full", "condensed"}
        Formulation (see the module docstring).
    tol : float
        Newton tolerance (scaled residual, see :func:`harmonic_balance`).
    initial_guess : ndarray, shape (n_dof, 2H+1), optional
        Starting coefficients at ``omega_start``.
    max_angle_deg : float
        Steps whose tangent turns more than this are refined.
    stability : bool
        Also compute the Floquet exponents of every point by Hill's method, the ``stable``
        flags, and detect and locate folds, branch points, Neimark-Sacker and
        period-doubling points (:mod:`fricdamp.solvers.hb_stability`). Opt-in: it solves one
        dense eigenproblem of size 2 n_dof (2H+1) per point (1-DOF Duffing, H = 5: ~0.2 ms;
        16-DOF beam, H = 7: ~0.2 s per point), plus H + 1 re-solves at a few points.
    sorting : {"eigenvector", "imaginary"}
        Choice of the retained Floquet exponents (see :func:`hb_stability.hill_stability`).
    blas : int or None
        BLAS threads (default 1: faster for these small factorisations).
    throw : bool
        Raise ConvergenceError if the curve could not be completed.
    progress : bool, optional
        Show a tqdm progress bar of the continuation (share of the interval covered,
        points, current Omega); default: only when stderr is a terminal and outside CI.

    Returns
    -------
    FrequencyResponse
        Converged points only; ``status``/``message`` say whether ``omega_end`` was
        reached and, if not, why. With ``stability``: ``stable``, ``floquet_exponents``,
        ``bifurcations``, ``stability_error``.

    Examples
    --------
    A Duffing oscillator through its hardening resonance: two folds, the middle branch
    unstable.

    >>> from fricdamp.contact import CubicSpring
    >>> from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem
    >>> duffing = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
    ...     contacts=(ContactElement(CubicSpring(0.5), [[1.0]]),),
    ...     loads=(HarmonicLoad([0.03], omega=1.0),))
    >>> fr = frequency_response(duffing, 0.8, 1.6, harmonics=3, stability=True)
    >>> [b.type for b in fr.bifurcations], bool(fr.stable.all())
    (['fold', 'fold'], False)
    """
    for name, v in (("omega_start", omega_start), ("omega_end", omega_end)):
        if not (np.isfinite(v) and v > 0):
            raise ModelError(f"{name} must be > 0 rad/s, got {v!r}")
    if omega_start == omega_end:
        raise ModelError("omega_start and omega_end must differ")
    out = _curve(system, harmonics, samples, method, "omega", omega_start, omega_end,
                 omega_start, 1.0, step, min_step, max_step, max_points, tol, initial_guess,
                 max_angle_deg, blas, stability, sorting, progress)
    if throw and not out.success:
        raise ConvergenceError(f"frequency response incomplete: {out.message}")
    return out


def load_response(system: MechanicalSystem, omega: float, scale_start: float,
                  scale_end: float, *, harmonics: int = 5, samples: int | None = None,
                  step: float = 0.02, min_step: float | None = None,
                  max_step: float | None = None, max_points: int = 2000,
                  method: str = "auto", tol: float = 1e-9, initial_guess=None,
                  max_angle_deg: float = 25.0, stability: bool = False,
                  sorting: str = "eigenvector", blas: int | None = 1,
                  throw: bool = False, progress: bool | None = None) -> FrequencyResponse:
    """Steady response vs excitation level at fixed frequency (continuation in the load).

    The harmonic loads (harmonics k >= 1) are multiplied by the continued factor
    ``load_scale`` from ``scale_start`` to ``scale_end`` (the static load is kept): the
    classic friction-damper curve of response against excitation level, through its
    stick-slip transition. Parameters as :func:`frequency_response` (``stability`` too), with
    ``omega`` the fixed excitation frequency [rad/s] and the scale factors [-]
    (``scale_start`` >= 0).

    Returns
    -------
    FrequencyResponse
        With constant ``omega`` and the continued factor in ``load_scale``.
    """
    if not (np.isfinite(omega) and omega > 0):
        raise ModelError(f"omega must be > 0 rad/s, got {omega!r}")
    for name, v in (("scale_start", scale_start), ("scale_end", scale_end)):
        if not (np.isfinite(v) and v >= 0):
            raise ModelError(f"{name} must be >= 0, got {v!r}")
    if scale_start == scale_end:
        raise ModelError("scale_start and scale_end must differ")
    out = _curve(system, harmonics, samples, method, "load", scale_start, scale_end,
                 float(omega), scale_start, step, min_step, max_step, max_points, tol,
                 initial_guess, max_angle_deg, blas, stability, sorting, progress)
    if throw and not out.success:
        raise ConvergenceError(f"load response incomplete: {out.message}")
    return out


def _progress_default() -> bool:
    return bool(sys.stderr.isatty()) and not os.environ.get("CI")


class _Progress:
    """tqdm bar of a continuation: the share of [lam0, lam1] covered so far (it does not
    go back at turning points), the points and the current parameter. tqdm is imported
    only when the bar is shown."""

    def __init__(self, lam0, lam1, name):
        from tqdm.auto import tqdm

        self.lam0, self.span, self.name = lam0, lam1 - lam0, name
        self.points = 0
        self.bar = tqdm(total=100, desc="HB continuation", unit="%", leave=False,
                        file=sys.stderr, bar_format="{desc}: {percentage:3.0f}%|{bar}| "
                        "[{elapsed}<{remaining}{postfix}]")

    def __call__(self, x, lam, points=None):
        self.points = self.points + 1 if points is None else points
        done = int(100 * min(max((lam - self.lam0) / self.span, 0.0), 1.0))
        if done > self.bar.n:
            self.bar.update(done - self.bar.n)
        self.bar.set_postfix_str(f"{self.points} points, {self.name} = {lam:.6g}",
                                 refresh=False)
        return False

    def close(self, out=None):
        if out is not None and out.n_points:      # the final state, shown once
            lam = out.omega[-1] if out.parameter == "omega" else out.load_scale[-1]
            self(None, float(lam), out.n_points)
            self.bar.refresh()
        self.bar.close()


def _curve(system, harmonics, samples, method, param, lam0, lam1, omega0, scale0, step,
           min_step, max_step, max_points, tol, initial_guess, max_angle_deg, blas,
           stability=False, sorting="eigenvector", progress=None):
    """Continue the HB solution in Omega (param "omega") or in the load scale ("load")."""
    show = _progress_default() if progress is None else bool(progress)
    bar = _Progress(lam0, lam1, "Omega" if param == "omega" else "load scale") if show \
        else None
    out = None
    try:
        out = _curve_run(system, harmonics, samples, method, param, lam0, lam1, omega0,
                         scale0, step, min_step, max_step, max_points, tol, initial_guess,
                         max_angle_deg, blas, stability, sorting, bar)
        return out
    finally:
        if bar is not None:
            bar.close(out)


def _curve_run(system, harmonics, samples, method, param, lam0, lam1, omega0, scale0, step,
               min_step, max_step, max_points, tol, initial_guess, max_angle_deg, blas,
               stability, sorting, bar):
    if sorting not in ("eigenvector", "imaginary"):
        raise ModelError(f"sorting must be 'eigenvector' or 'imaginary', got {sorting!r}")
    _check_size(system, harmonics, samples)
    s = _Setup(system, harmonics, samples)
    t0 = time.perf_counter()
    with blas_threads(blas):
        form = _choose(s, method)
        if param == "omega":
            grid = np.linspace(lam0, lam1, 17)
            s_grid = None
        else:
            grid = [omega0]
            s_grid = max(abs(lam0), abs(lam1))
        x_ref, f_ref = _scales(s, form, grid)
        if s_grid is not None:      # linear estimates were made at load scale 1
            x_ref *= max(s_grid, 1e-12) if np.any(s.F_ex[:, 1:]) else 1.0
            f_ref *= max(s_grid, 1e-12) if not np.any(s.F_ex[:, 0]) else 1.0
        scale = 1.0 / (f_ref if isinstance(form, _Full) else x_ref)
        d_load = None
        if param == "load":
            if isinstance(form, _Full):
                d_load = np.zeros_like(s.F_ex)
                d_load[:, 1:] = -s.F_ex[:, 1:]
                d_load = d_load.ravel() * scale
            else:
                _, _, ul, _ = form.compliance(omega0)
                ul = ul.copy()
                ul[0] = 0.0
                d_load = -form._to_real(ul).ravel() * scale

        def residual(x, lam, deferred=False):
            if param == "omega":
                r, J, dr, _, _ = form.evaluate(x, lam, scale=scale, x_scale=x_ref,
                                               aft_result=False, deferred=deferred)
                return r, J, dr
            r, J, _, _, _ = form.evaluate(x, omega0, scale=scale, x_scale=x_ref,
                                          load_scale=lam, aft_result=False, deferred=deferred)
            return r, J, d_load

        def residual_deferred(x, lam):
            # Jacobians assembled only where the corrector factorises
            # (continuation.jacobian_of; same values)
            return residual(x, lam, deferred=True)

        guesses = _initial_guess(s, form, omega0, initial_guess)
        if param == "load":
            guesses = [g * scale0 if np.any(s.F_ex[:, 1:]) else g for g in guesses]
        x0 = guesses[0] / x_ref
        for g in guesses:
            res = newton(lambda x: residual_deferred(x, lam0)[:2], g / x_ref, tol=tol,
                         max_iter=100, block_size=_block_size(form))
            if res.success:
                x0 = res.x
                break
        cres = solve_and_continue(
            x0, residual_deferred, lam0, lam1, step,
            ds_min=min_step if min_step is not None else step / 1000.0,
            ds_max=max_step if max_step is not None else 5.0 * step,
            x_scale=1.0, lam_scale=abs(lam1 - lam0), tol=tol,
            max_steps=max_points, max_angle_deg=max_angle_deg, test_functions=stability,
            reuse_factorization=REUSE_FACTORIZATION, blas=None, block_size=_block_size(form),
            callback=bar)
        n_p = cres.n_points
        omegas = cres.lam if param == "omega" else np.full(n_p, omega0)
        scales = np.ones(n_p) if param == "omega" else cres.lam.copy()
        if not n_p:
            X = np.zeros((0, s.n, s.nh))
        elif type(form).to_dofs is _Full.to_dofs:       # all points in one product
            X = (cres.x * x_ref).reshape(n_p, s.n, s.nh)
        else:
            X = np.stack([form.to_dofs(x, w, x_ref, load_scale=ls) for x, w, ls in
                          zip(cres.x, omegas, scales, strict=True)])
        stab = {}
        if stability and n_p:
            from fricdamp.solvers.hb_stability import branch_stability

            bs = branch_stability(system, s, form, residual, cres, X, omegas, scales, param,
                                  x_ref=x_ref, sorting=sorting, corrector_tol=tol)
            stab = dict(stable=bs.stable, floquet_exponents=bs.exponents,
                        bifurcations=bs.bifurcations, stability_error=bs.exponent_error,
                        stability_converged=bs.verdict_agrees)
        wall = time.perf_counter() - t0
    fund = np.hypot(X[:, :, 1], X[:, :, 2])
    # contact forces, energies and peak amplitudes of every point: computed when first read
    # (FrequencyResponse, _hb_results._Pending), with the same BLAS thread limit
    pending = _hb_results._Pending(lambda: _curve_postprocess(s, X, omegas, scales, blas))
    return FrequencyResponse(
        omegas, X, pending, fund, None, None, None, None, None, None, cres.iterations,
        cres.turning_points, cres.status, cres.message, s.H, s.basis.samples,
        _method_name(form), wall, cres.n_evaluations, cres.n_factorizations, system.names,
        s.contact_names, scales, param, **stab, system=system)


def _curve_postprocess(s: _Setup, X, omegas, scales, blas) -> dict:
    """The post-processed fields of a curve (:class:`FrequencyResponse` names)."""
    with blas_threads(blas):
        pp = _postprocess_in_blocks(s, X, omegas, scales)
    err = _balance_error(pp["W_ext"], pp["W_visc"] + pp["W_contact"].sum(axis=1), pp["E_kin"])
    return dict(amplitude=pp["amp"], contact_displacement=pp["U"], contact_force=pp["F"],
                dissipated_energy=pp["W_contact"], external_work=pp["W_ext"],
                viscous_dissipation=pp["W_visc"], energy_balance_error=err)


def _postprocess_in_blocks(s: _Setup, X, omegas, scales, max_bytes: float = 16e6):
    """:func:`_postprocess` of a curve, a block of points at a time.

    The peak amplitudes are searched on a 128-phase grid of every DOF of every point: for
    the ring of 480 contacts and its 670 points that grid alone is 330 MB at once; blocks of
    at most ``max_bytes`` keep it in cache and bound the memory (same results).
    """
    n_p = X.shape[0]
    per_point = 8.0 * 128 * max(X.shape[1], 1) * 2
    block = max(1, int(max_bytes // per_point))
    if n_p <= block:
        return _postprocess(s, X, omegas, load_scale=scales)
    parts = [_postprocess(s, X[i:i + block], omegas[i:i + block],
                          load_scale=scales[i:i + block]) for i in range(0, n_p, block)]
    return {k: (None if parts[0][k] is None else np.concatenate([p[k] for p in parts]))
            for k in parts[0]}


def engine_order_load(n_sectors: int, engine_order: int, amplitude: float, *,
                      dofs_per_sector: int = 1, dof: int = 0, harmonic: int = 1,
                      omega: float = 1.0) -> HarmonicLoad:
    """Travelling-wave (engine-order) excitation of a cyclic assembly.

    Sector j (0-based) is loaded at DOF ``j * dofs_per_sector + dof`` by
    ``amplitude * cos(harmonic Omega t - 2 pi engine_order j / n_sectors)`` [N], i.e. a
    forward wave of ``engine_order`` nodal diameters.

    Parameters
    ----------
    n_sectors : int
        Number of sectors N_s >= 1.
    engine_order : int
        Engine order (integer; its alias modulo N_s sets the nodal diameter).
    amplitude : float
        Force amplitude per sector [N].
    dofs_per_sector : int
        DOFs of each sector (sector-major numbering).
    dof : int
        Loaded DOF within the sector.
    harmonic : int
        Harmonic of the load (1 = at Omega).
    omega : float
        Nominal angular frequency [rad/s] stored in the load (HB replaces it).

    Returns
    -------
    HarmonicLoad
    """
    if int(n_sectors) != n_sectors or n_sectors < 1:
        raise ModelError(f"n_sectors must be an integer >= 1, got {n_sectors!r}")
    if int(dofs_per_sector) != dofs_per_sector or dofs_per_sector < 1:
        raise ModelError(f"dofs_per_sector must be an integer >= 1, got {dofs_per_sector!r}")
    if not 0 <= dof < dofs_per_sector:
        raise ModelError(f"dof is a Python index of the sector's DOFs and must lie in "
                         f"[0, {dofs_per_sector - 1}] (DOF numbers 1 to {dofs_per_sector}), "
                         f"got {dof!r}")
    if int(engine_order) != engine_order:
        raise ModelError(f"engine_order must be an integer, got {engine_order!r}")
    a = np.zeros(int(n_sectors) * int(dofs_per_sector), complex)
    j = np.arange(int(n_sectors))
    a[j * dofs_per_sector + dof] = amplitude * np.exp(-2j * np.pi * engine_order * j / n_sectors)
    return HarmonicLoad(a, omega=omega, harmonic=harmonic)
