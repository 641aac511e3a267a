"""Cyclic HB (one sector) against full-wheel HB on paper 003's beam wheel, same points.

The wheel: 30 Craig-Bampton beam sectors (4 fixed-interface modes each; 570 DOFs, 30
tie-boss contacts with the paper's law), a forward 6ND wave of 2 N per blade at the
tie-bosses, H = 3, 120 AFT samples, 48.6 -> 49.4 Hz through the friction-damped resonance.

Figures, measured in one run (``time.process_time`` for CPU, ``time.perf_counter`` for
wall; one BLAS thread, the solvers' default):

* continuation: CPU and wall time per point of the cyclic continuation and of the
  full-wheel continuation (:func:`fricdamp.solvers.hb.frequency_response`, condensed-modal
  formulation) over the same interval, and their peaks (must agree within 0.5 % before
  any ratio is reported);
* same points: at every point of the cyclic path, the full-wheel Newton solve
  (:func:`fricdamp.solvers.hb.harmonic_balance`) from the cyclic solution expanded to the
  wheel and perturbed by 5 %, against the cyclic Newton solve from its own solution
  perturbed by 5 % (the same start, the same tolerance): the headline ratio, target >= 20;
  also the full-wheel same-point time over the cyclic *continuation* time per point (which
  includes the cyclic start from zero, ~15 damped Newton steps);
* the cyclic run again with the default BLAS pools (DESIGN.md: small dense solves);
* with ``full_order=True`` (not in ``--quick``): the same-point full-wheel solve on the
  full-order wheel (2880 DOFs, condensed-direct) at three points.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

TARGET_RATIO = 20.0
F_LO, F_HI = 48.6, 49.4
KW = dict(harmonics=3, samples=120)


def _amp(coeffs, d, H):
    from fricdamp.solvers.aft import HarmonicBasis

    sig = HarmonicBasis.create(H, 1024).synthesis @ (d @ coeffs)
    return float(np.abs(sig - (d @ coeffs)[0]).max())


def _peak(x, y):
    i = int(np.clip(np.argmax(y), 1, len(y) - 2))
    c = np.polyfit(x[i - 1:i + 2], y[i - 1:i + 2], 2)
    xm = -c[1] / (2 * c[0])
    return float(xm), float(np.polyval(c, xm))


def run(quick: bool = False, verbose: bool = False, full_order: bool = True) -> dict:
    from fricdamp.models.tieboss_wheel.forced import cyclic_problem, expand_to_wheel, wheel_load
    from fricdamp.models.tieboss_wheel.model import build_sector, build_wheel
    from fricdamp.solvers.continuation import blas_threads, newton
    from fricdamp.solvers.cyclic_hb import cyclic_frequency_response
    from fricdamp.solvers.hb import frequency_response, harmonic_balance

    sector = build_sector(rotation=False)
    d = sector.flexural_direction
    lo, hi = 2 * np.pi * F_LO, 2 * np.pi * F_HI
    pb, wheel = cyclic_problem(sector, 6, force_N=2.0, n_modes=4, **KW)
    cyclic_frequency_response(pb, lo, lo * 1.001, step=0.02)          # warm-up (numba, LAPACK)
    res = cyclic_frequency_response(pb, lo, hi, step=0.02)
    cyc_cpu = res.cpu_s / res.n_points
    cyc_wall = res.runtime_s / res.n_points
    amp_c = res.amplitude(wheel.cyclic.named_dofs["probe"], d, samples=1024)
    system = dataclasses.replace(wheel.system, loads=(wheel_load(wheel, 6, 2.0),))
    details = {"wheel_dof": wheel.n_dof, "sector_dof": wheel.cyclic.n_dof,
               "cyclic_unknowns": pb.N_unknowns, "cyclic_points": res.n_points,
               "cyclic_cpu_ms_per_point": 1e3 * cyc_cpu,
               "cyclic_wall_ms_per_point": 1e3 * cyc_wall}
    # same points: full-wheel Newton from the expanded, perturbed cyclic solution
    pts = range(res.n_points) if not quick else range(0, res.n_points, 4)
    c0, w0 = time.process_time(), time.perf_counter()
    dev, n_ok = 0.0, 0
    for i in pts:
        ss = harmonic_balance(system, res.omega[i], initial_guess=1.05 * expand_to_wheel(
            res, wheel, i), **KW)
        if ss.success:
            n_ok += 1
            a = _amp(ss.coefficients[wheel.group_dofs("probe", 0)], d, KW["harmonics"])
            dev = max(dev, abs(a / amp_c[i] - 1))
    n_pts = len(pts)
    full_cpu = (time.process_time() - c0) / n_pts
    full_wall = (time.perf_counter() - w0) / n_pts
    # the cyclic solve from the same kind of start (its own solution perturbed by 5 %)
    x_ref = pb.displacement_scale(np.linspace(lo, hi, 17))
    c0, w0 = time.process_time(), time.perf_counter()
    with blas_threads(1):
        for i in pts:
            y = res.contact_displacement[i].ravel() / x_ref
            newton(lambda x, w=res.omega[i]: pb.evaluate(x, w, scale=1 / x_ref,
                                                         x_scale=x_ref)[:2], 1.05 * y,
                   tol=1e-9)
    cyc_cpu_pt = (time.process_time() - c0) / n_pts
    cyc_wall_pt = (time.perf_counter() - w0) / n_pts
    details.update(cyclic_cpu_ms_per_point_same_points=1e3 * cyc_cpu_pt,
                   cyclic_wall_ms_per_point_same_points=1e3 * cyc_wall_pt,
                   ratio_cpu_continuation_vs_same_points=full_cpu / cyc_cpu)
    details.update(same_points=n_pts, same_points_converged=n_ok,
                   same_points_max_amplitude_difference=dev,
                   full_cpu_ms_per_point_same_points=1e3 * full_cpu,
                   full_wall_ms_per_point_same_points=1e3 * full_wall,
                   ratio_cpu_same_points=full_cpu / cyc_cpu_pt,
                   ratio_wall_same_points=full_wall / cyc_wall_pt)
    peaks_ok = True
    if not quick:
        c0, w0 = time.process_time(), time.perf_counter()
        fr = frequency_response(system, lo, hi, step=0.02, max_step=0.4, **KW)
        fc, fw = time.process_time() - c0, time.perf_counter() - w0
        a_f = np.array([_amp(x, d, KW["harmonics"])
                        for x in fr.coefficients[:, wheel.group_dofs("probe", 0)]])
        pc, pf = _peak(res.omega, amp_c), _peak(fr.omega, a_f)
        peaks_ok = abs(pc[0] / pf[0] - 1) < 5e-3 and abs(pc[1] / pf[1] - 1) < 5e-3
        details.update(full_points=len(fr.omega), full_status=fr.status,
                       full_cpu_ms_per_point=1e3 * fc / len(fr.omega),
                       full_wall_ms_per_point=1e3 * fw / len(fr.omega),
                       ratio_cpu_continuation=(fc / len(fr.omega)) / cyc_cpu,
                       peak_frequency_hz_cyclic=pc[0] / (2 * np.pi),
                       peak_frequency_hz_full=pf[0] / (2 * np.pi),
                       peak_amplitude_m_cyclic=pc[1], peak_amplitude_m_full=pf[1])
        # default BLAS pools
        r2 = cyclic_frequency_response(pb, lo, hi, step=0.02, blas=None)
        details["cyclic_cpu_ms_per_point_default_blas"] = 1e3 * r2.cpu_s / r2.n_points
        details["cyclic_wall_ms_per_point_default_blas"] = 1e3 * r2.runtime_s / r2.n_points
        if full_order:
            pf_, wf = cyclic_problem(sector, 6, force_N=2.0, n_modes=None, **KW)
            big = build_wheel(sector)
            rf = cyclic_frequency_response(pf_, lo, hi, step=0.02)
            sysb = dataclasses.replace(big.system, loads=(wheel_load(big, 6, 2.0),))
            sel = [rf.n_points // 4, rf.n_points // 2, 3 * rf.n_points // 4]
            c0, w0 = time.process_time(), time.perf_counter()
            ok = 0
            for i in sel:
                ss = harmonic_balance(sysb, rf.omega[i], initial_guess=1.05 * expand_to_wheel(
                    rf, wf, i), **KW)
                ok += bool(ss.success)
            details.update(
                full_order_wheel_dof=big.n_dof, full_order_same_points_converged=ok,
                full_order_cpu_ms_per_point=1e3 * (time.process_time() - c0) / len(sel),
                full_order_wall_ms_per_point=1e3 * (time.perf_counter() - w0) / len(sel),
                full_order_cyclic_cpu_ms_per_point=1e3 * rf.cpu_s / rf.n_points,
                full_order_ratio_cpu=((time.process_time() - c0) / len(sel))
                / (rf.cpu_s / rf.n_points))
    ratio = details["ratio_cpu_same_points"]
    passed = bool(ratio >= TARGET_RATIO and peaks_ok and dev < 1e-5 and n_ok == n_pts)
    figure = (f"cyclic HB {1e3 * cyc_cpu_pt:.3g} ms/point vs full wheel ({wheel.n_dof} DOFs) "
              f"{1e3 * full_cpu:.3g} ms/point on the same points (CPU): {ratio:.3g}x "
              f"(target >= {TARGET_RATIO:g}x); same states to {dev:.1e}")
    if verbose:
        print(figure)
        for k, v in details.items():
            print(f"  {k}: {v}")
    return {"name": "cyclic_hb", "figure": figure, "value": ratio, "target": TARGET_RATIO,
            "passed": passed, "unit": "x", "details": details}


if __name__ == "__main__":
    run(verbose=True)
