"""den Hartog's Coulomb oscillator: exact event-driven stick-slip vs regularised Radau.

``x'' + x + beta sgn(x') = cos(r t)`` (m = k = F0 = 1), r = 0.8, beta = F_f/F0 = 0.3, started
on den Hartog's exact steady state (x = X, x' = 0 at r t = phi). The reference is den
Hartog's closed form X = sqrt(V^2 - beta^2 U^2) (REFERENCES.md); the amplitude of a run is the
largest |x| over its last forcing period.

* event-driven: :func:`fricdamp.solvers.event.simulate_events` (exact phases), 100 periods;
* regularised: ``beta tanh(x'/eps)`` with SciPy's Radau (analytic Jacobian); the cheapest of
  a few (eps, rtol) settings that reaches <= 1e-3 relative amplitude error is the one timed.

Figure: speed ratio (Radau time / event-driven time) for 100 periods; target >= 20 with an
event-driven error >= 1000x smaller. Also printed: the time of 200 periods (target <= 0.5 s at
<= 1e-6 error). Siconos is quoted, not run (no wheels on PyPI for this Python): Moreau-Jean
at h = 1e-3, 14 s for 200 periods at 2e-4 error (DESIGN.md "Performance targets"; an earlier
figure of 10.5 s appears in issue 13), measured by an earlier session, not reproducible here;
it is never part of a printed ratio.
Both solvers run in this process with one BLAS thread; times are the best of ``repeats``
process CPU times (``time.process_time``: robust on a shared machine; equal to wall-clock
time on an idle one).
"""

from __future__ import annotations

import time

import numpy as np

R, BETA = 0.8, 0.3


def den_hartog(r: float, beta: float) -> tuple[float, float]:
    """Exact non-stop amplitude X/(F0/k) and phase lag phi [rad] (REFERENCES.md)."""
    V = 1.0 / (1.0 - r**2)
    U = np.tan(np.pi / (2 * r)) / r
    X = np.sqrt(V**2 - beta**2 * U**2)
    return X, float(np.arctan2(-beta * U / V, X / V))


def _event_run(n_periods: int):
    from fricdamp.solvers.event import CoulombSystem, simulate_events
    from fricdamp.structure.system import HarmonicLoad, MechanicalSystem

    X, phi = den_hartog(R, BETA)
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], R),))
    cs = CoulombSystem(s, directions=[1.0], normal_load=BETA, mu_static=1.0)
    T = 2 * np.pi / R
    t0 = phi / R
    t1 = t0 + n_periods * T
    tic = time.process_time()
    res = simulate_events(cs, (t0, t1), [X, 0.0], t_eval=np.linspace(t1 - T, t1, 65))
    el = time.process_time() - tic
    last = res.t >= t1 - T * (1 + 1e-12)
    amp = float(np.max(np.abs(res.q[last, 0])))
    return el, abs(amp / X - 1.0), res


def _radau_run(n_periods: int, eps: float, rtol: float):
    from scipy.integrate import solve_ivp
    from scipy.optimize import minimize_scalar

    X, phi = den_hartog(R, BETA)
    T = 2 * np.pi / R
    t0 = phi / R
    t1 = t0 + n_periods * T

    def f(t, y):
        return [y[1], np.cos(R * t) - y[0] - BETA * np.tanh(y[1] / eps)]

    def jac(t, y):
        ch = np.cosh(min(abs(y[1] / eps), 350.0))
        return [[0.0, 1.0], [-1.0, -BETA / eps / ch**2]]

    tic = time.process_time()
    sol = solve_ivp(f, (t0, t1), [X, 0.0], method="Radau", rtol=rtol, atol=1e-2 * rtol,
                    jac=jac, dense_output=True)
    el = time.process_time() - tic
    ts = np.linspace(t1 - T, t1, 2001)
    xs = np.abs(sol.sol(ts)[0])
    k = int(np.argmax(xs))
    lo, hi = ts[max(k - 1, 0)], ts[min(k + 1, ts.size - 1)]
    opt = minimize_scalar(lambda t: -abs(sol.sol(t)[0]), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-10})
    amp = max(xs[k], -opt.fun)
    return el, abs(amp / X - 1.0), sol.nfev


def run(repeats: int = 3, verbose: bool = True) -> dict:
    """Measure both solvers; return the headline figure (speed ratio at 1e-3 error)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):
        _event_run(2)  # warm up (numba cache load)
        ev_times, ev_err = [], None
        for _ in range(repeats):
            el, ev_err, res = _event_run(100)
            ev_times.append(el)
        t_ev = min(ev_times)
        t200 = min(_event_run(200)[0] for _ in range(repeats))
        err200 = _event_run(200)[1]

        settings = [(0.03, 1e-3), (0.03, 1e-4), (0.01, 1e-3), (0.01, 1e-4)]
        best = None
        table = []
        for eps, rtol in settings:
            el, err, nfev = _radau_run(100, eps, rtol)
            table.append((eps, rtol, el, err, nfev))
            if err <= 1e-3 and (best is None or el < best[2]):
                best = (eps, rtol, el, err, nfev)
        if best is not None:
            eps, rtol = best[0], best[1]
            t_rad = min([best[2]] + [_radau_run(100, eps, rtol)[0] for _ in range(repeats - 1)])
            err_rad = best[3]
        else:
            t_rad, err_rad = np.nan, np.nan

    ratio = t_rad / t_ev
    err_ratio = err_rad / max(ev_err, 1e-16)
    passed = bool(ratio >= 20 and err_ratio >= 1000 and t200 <= 0.5 and err200 <= 1e-6)
    if verbose:
        print("den Hartog r = 0.8, beta = 0.3, 100 periods")
        for eps, rtol, el, err, nfev in table:
            print(f"  Radau tanh eps = {eps:g}, rtol = {rtol:g}: {el:7.3f} s, error "
                  f"{err:.2e}, {nfev} f-evals")
        print(f"  event-driven (exact phases): {t_ev:.4f} s, error {ev_err:.2e}, "
              f"{res.n_events} events")
        print(f"  Radau (cheapest at <= 1e-3): {t_rad:.3f} s, error {err_rad:.2e}")
        print(f"  speed ratio {ratio:.1f}x (target >= 20x), error ratio {err_ratio:.1e} "
              "(target >= 1e3)")
        print(f"  200 periods: {t200:.4f} s at error {err200:.2e} (target <= 0.5 s at 1e-6)")
    return {
        "name": "den Hartog oscillator, event-driven vs regularised Radau (100 periods)",
        "figure": "speed ratio at 1e-3 amplitude error",
        "value": float(ratio),
        "target": 20.0,
        "passed": passed,
        "event_time_s": t_ev,
        "event_error": ev_err,
        "radau_time_s": t_rad,
        "radau_error": err_rad,
        "error_ratio": err_ratio,
        "time_200_periods_s": t200,
        "error_200_periods": err200,
    }


if __name__ == "__main__":
    run()
