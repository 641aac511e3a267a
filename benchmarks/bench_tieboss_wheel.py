"""0.1 s of free decay of the 30-blade tie-boss wheel with all 30 friction contacts (003).

The paper needed ~40,000 core-hours of ANSYS on a supercomputer for 0.1 s of the free
attenuation of its 3D FE wheel (89,000 elements, 20,000 Newmark steps). Here, in one
process on one core (one BLAS thread):

* **reduced**: the Craig-Bampton wheel (10 fixed-interface modes per sector; cuts, contact
  nodes and tie-boss kept: 750 DOFs) with the compiled Contact3D path
  (:func:`fricdamp.solvers.fast_transient.integrate_contact3d`), at the paper's time step
  5e-6 s (20,000 steps) and at 1e-5 s (10,000 steps, the ratios change by < 0.1 %);
* **full order**: the 2880-DOF assembled wheel with the general solver
  (:func:`fricdamp.solvers.timestep.simulate`, sparse LU, Newton on the 90 contact unknowns),
  at 1e-5 s.

Both start from the paper's strategy (2ND modal forces at the tie-bosses, static solution
with the prestressed contacts, release from 0.5 mm) and give the damping ratio from the
logarithmic decrement of the probe's envelope. Figure: the reduced run time for 0.1 s at the
paper's step (target <= 60 s), the full / reduced time ratio at 1e-5 s (``value``, target
>= 10) and the relative difference of the damping ratios (target <= 5 %). Times are the
wall-clock time of the time loops (the modal transformation, ~0.3 s, and the one-off numba
compilation, cached on disk, are excluded; the set-up time is printed too).
"""

from __future__ import annotations

import time

from fricdamp.models.tieboss_wheel.model import build_sector, build_wheel
from fricdamp.models.tieboss_wheel.studies import free_decay, initial_deformation
from fricdamp.solvers.fast_transient import integrate_contact3d

TARGET_RATIO = 10.0
TARGET_SECONDS = 60.0
TARGET_DIFFERENCE = 0.05
ND, AMPLITUDE, DURATION = 2, 5e-4, 0.1


def run(verbose: bool = False) -> dict:
    tic = time.perf_counter()
    sector = build_sector(rotation=False)
    full = build_wheel(sector)
    red = build_wheel(sector, n_modes=10)
    build_s = time.perf_counter() - tic
    # warm-up: load (or compile) the kernels
    integrate_contact3d(red.system, 1e-4, 1e-5, output_dofs=[0])
    init_red = initial_deformation(red, ND, AMPLITUDE)
    init_full = initial_deformation(full, ND, AMPLITUDE)
    r_paper = free_decay(red, ND, duration_s=DURATION, dt=5e-6, initial=init_red)
    r_red = free_decay(red, ND, duration_s=DURATION, dt=1e-5, initial=init_red)
    r_full = free_decay(full, ND, duration_s=DURATION, dt=1e-5, initial=init_full,
                        solver="simulate")
    ratio = r_full.runtime_s / r_red.runtime_s
    diff = abs(r_red.damping_ratio / r_full.damping_ratio - 1.0)
    passed = (ratio >= TARGET_RATIO and r_paper.runtime_s <= TARGET_SECONDS
              and diff <= TARGET_DIFFERENCE)
    figure = (f"0.1 s decay, 30 blades x 30 contacts: reduced ({red.n_dof} DOF) "
              f"{r_paper.runtime_s:.2f} s at dt 5e-6 (paper: ~40,000 core-h), "
              f"{r_red.runtime_s:.2f} s at 1e-5 vs full order ({full.n_dof} DOF, simulate) "
              f"{r_full.runtime_s:.1f} s: ratio {ratio:.0f}x; zeta {100 * r_red.damping_ratio:.3f}"
              f" % vs {100 * r_full.damping_ratio:.3f} % (difference {100 * diff:.2f} %)")
    details = {
        "reduced_dof": red.n_dof, "full_dof": full.n_dof, "n_contacts": red.law.n_contacts,
        "reduced_runtime_paper_dt_s": r_paper.runtime_s,
        "reduced_runtime_s": r_red.runtime_s, "reduced_setup_s": r_red.meta["setup_s"],
        "full_runtime_s": r_full.runtime_s, "speed_ratio": ratio,
        "damping_ratio_reduced": r_red.damping_ratio,
        "damping_ratio_reduced_paper_dt": r_paper.damping_ratio,
        "damping_ratio_full": r_full.damping_ratio, "damping_ratio_difference": diff,
        "newton_iterations_reduced": r_red.meta["n_newton"],
        "newton_iterations_full": r_full.meta["n_newton"],
        "build_s": build_s, "wall_s": time.perf_counter() - tic,
    }
    if verbose:
        print(figure)
        for k, v in details.items():
            print(f"  {k}: {v}")
    return {"name": "tieboss_wheel", "figure": figure, "value": ratio,
            "target": TARGET_RATIO, "unit": "x", "passed": bool(passed), "details": details}


if __name__ == "__main__":
    res = run(verbose=True)
    print("PASS" if res["passed"] else "MISS")
