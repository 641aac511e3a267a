"""Paper 003's solid wheel at the default mesh, stage by stage, and how it scales (issue 12).

The paper's 3D FE wheel (89,000 hexahedra, 30 tie-boss contact pairs) took **~40,000
core-hours of ANSYS on the Salomon supercomputer for 0.1 s of free attenuation** (003
section 3; quoted, not run). Here the same pipeline on the tet10 sector of
:mod:`fricdamp.models.tieboss_wheel.solid` with every node pair of every contact patch, in one
process with one BLAS/OpenMP thread, stage by stage:

========================  ===================================================================
meshing                   gmsh (:func:`~fricdamp.models.tieboss_wheel.solid.build_sector_mesh`,
                          not cached: each size runs in a fresh process) and the conversion
                          to a SolidMesh
assembly                  tet10 stiffness and mass (scikit-fem basis)
pairing                   clamp, cyclic cuts and contact faces paired
                          (:func:`~fricdamp.models.contact_wheel.sector_from_solid`)
modal by ND               first open-contact mode of every ND 0..15 of the *unreduced* sparse
                          sector (:func:`~fricdamp.models.tieboss_wheel.studies.modal_by_nd`)
reduction                 cyclic Craig-Bampton with the cut reduced (``reduce_sector``; its
                          sub-stages are its own wall-clock ``timings``)
wheel modes               every mode of the reduced wheel by ND (``wheel_modes``)
contact rows              the rest of ``build_contact_wheel`` (contact rows, modal basis)
offset calibration        ``ContactWheel.calibrate_offset`` (2.4 N per tie-boss)
decay                     ``ContactWheel.free_decay`` of the 2ND mode from 0.5 mm: initial
                          static solution, condensed compliance and the Newmark time loop
                          (the loop's own wall/CPU time is printed too)
========================  ===================================================================

Each stage reports wall time (``time.perf_counter``), CPU time (``time.process_time``) and
the **process peak resident memory after it** (``resource.getrusage(RUSAGE_SELF).ru_maxrss``:
the peak of the whole process so far, numpy/scipy/gmsh/SuperLU allocations included, which
tracemalloc would miss). Every size runs in a fresh subprocess so that the peak is per size
and the gmsh mesh cache is cold.

Targets (issue 12): the default mesh in **<= 10 minutes in all** and **<= 8 GiB peak**. The
issue allows 2 cores; this benchmark runs on one (``OMP_NUM_THREADS=1``,
``OPENBLAS_NUM_THREADS=1``, ``MKL_NUM_THREADS=1``, ``NUMBA_NUM_THREADS=1``), so the verdict is
conservative. Then a scaling table over sectors of about 10k, 30k and 100k DOF with the
exponent ``p`` of each stage's CPU time ``t ~ DOF^p`` (least squares in log-log). The decay's
cost does not depend on the mesh (the reduced wheel's size is set by the contact faces and
the mode counts), so the scaling rows time 0.02 s of it and extrapolate per step to 0.1 s;
for the largest sector ``modal_by_nd`` is timed on ND 0 and ND 2 and extrapolated to all
NDs. Extrapolated numbers are marked ``*``.

Usage::

    python benchmarks/bench_solid_wheel.py            # default mesh + scaling table (~15 min)
    python benchmarks/bench_solid_wheel.py --quick    # coarse mesh, short decay (< 2 min)
    python benchmarks/bench_solid_wheel.py --no-scaling
    python benchmarks/run.py --only solid_wheel [--quick]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
               "NUMBA_NUM_THREADS")
TARGET_SECONDS = 600.0
TARGET_GIB = 8.0
PAPER = ("ANSYS on the Salomon supercomputer, ~40,000 core-hours for 0.1 s of free "
         "attenuation (89,000 hexahedra), 003 section 3 -- quoted, not run")
ND, AMPLITUDE_M, DURATION_S, DT_S = 2, 5e-4, 0.1, 2e-5
N_MODES, N_INTERFACE_MODES = 30, 60
# mesh_size_m for sectors of about 10k, 30k and 100k DOF (default mesh 6 mm: ~42k)
# (label, mesh_size_m, decay window [s], NDs timed or None for all): the decay's cost does
# not depend on the mesh (the reduced wheel's size is set by the contact faces and the
# mode counts), so the scaling rows time 0.02 s of it and extrapolate per step
SCALING = (("10k", 0.017, 0.02, None), ("30k", 0.0075, 0.02, None),
           ("100k", 0.0038, 0.02, [0, 2]))
QUICK = {"mesh_size_m": 0.025, "duration_s": 0.005}
QUICK_SCALING = (("7k", 0.030, 0.002, None), ("10k", 0.017, 0.002, [0, 2]))
STAGES = ("meshing", "assembly", "pairing", "modal_by_nd", "reduction", "wheel_modes",
          "contact_rows", "calibration", "decay")
MARK = "@@RESULT@@"


# ================================================================================ measuring
def _peak_gib() -> float:
    """Peak resident memory of this process so far [GiB] (Linux: ru_maxrss in KiB)."""
    kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return kib / (1024.0**2 if sys.platform != "darwin" else 1024.0**3)


class _Clock:
    """Wall, CPU and peak memory of named stages (a stage entered again from inside
    itself, e.g. a wrapped function calling another wrapped one, is counted once)."""

    def __init__(self):
        self.stages: dict[str, dict] = {}
        self._active: set[str] = set()

    @contextlib.contextmanager
    def stage(self, name: str):
        if name in self._active:
            yield
            return
        self._active.add(name)
        w0, c0 = time.perf_counter(), time.process_time()
        try:
            yield
        finally:
            self._active.discard(name)
        self.add(name, time.perf_counter() - w0, time.process_time() - c0)

    def add(self, name: str, wall: float, cpu: float):
        s = self.stages.setdefault(name, {"wall_s": 0.0, "cpu_s": 0.0, "calls": 0})
        s["wall_s"] += wall
        s["cpu_s"] += cpu
        s["calls"] += 1
        s["peak_gib"] = _peak_gib()

    def wrap(self, name: str, fn):
        def timed(*args, **kwargs):
            with self.stage(name):
                return fn(*args, **kwargs)
        return timed


@contextlib.contextmanager
def _instrumented(clock: _Clock, stages: dict):
    """Replace library functions by timed wrappers for the duration.

    ``stages`` maps a stage name to a function; every name bound to that function in a
    loaded ``fricdamp`` module is replaced (whether the caller imported it at module level
    or at call time), so the real entry points are measured unchanged. Raises if a stage
    was never entered.
    """
    by_id = {id(fn): (name, clock.wrap(name, fn)) for name, fn in stages.items()}
    saved = []
    try:
        for mod_name, module in list(sys.modules.items()):
            if mod_name != "fricdamp" and not mod_name.startswith("fricdamp."):
                continue
            for attr, value in list(vars(module).items()):
                if id(value) in by_id:
                    saved.append((module, attr, value))
                    setattr(module, attr, by_id[id(value)][1])
        yield
    finally:
        for module, attr, value in saved:
            setattr(module, attr, value)
    missing = [name for name in stages if name not in clock.stages]
    if missing:
        raise RuntimeError(f"stages {missing} were never entered: the pipeline no longer calls "
                           f"{[stages[m].__qualname__ for m in missing]}; update "
                           "bench_solid_wheel.measure")


def _vm_peak_gib() -> float:
    """Peak virtual size of this process [GiB] (Linux /proc; NaN elsewhere)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmPeak:"):
                    return int(line.split()[1]) / 1024.0**2
    except OSError:
        pass
    return float("nan")


def measure(mesh_size_m: float | None = None, *, duration_s: float = DURATION_S,
            dt: float = DT_S, contact_divisions: int | None = None,
            n_modes: int = N_MODES, n_interface_modes: int = N_INTERFACE_MODES,
            modal_nds: list[int] | None = None) -> dict:
    """Run the whole pipeline once in this process; stage times, peaks and checks.

    ``modal_nds``: time only these NDs (a real one, 0 or N/2, and a complex one) and
    extrapolate the modal stage to all NDs (labelled); default: ``modal_by_nd`` itself.
    """
    import numpy as np

    import fricdamp.models.contact_wheel as cw
    import fricdamp.models.tieboss_wheel.solid as ts
    import fricdamp.structure.cyclic_reduction as cr
    import fricdamp.structure.solid as so
    from fricdamp.models.contact_wheel import ContactSettings, build_contact_wheel
    from fricdamp.models.tieboss_wheel.case_solid import paper_wheel_sector
    from fricdamp.models.tieboss_wheel.solid import SolidWheelParameters
    from fricdamp.models.tieboss_wheel.studies import modal_by_nd
    from fricdamp.structure.cyclic import nodal_diameter_modes

    peak_import = _peak_gib()
    p = SolidWheelParameters()
    changes = {k: v for k, v in (("mesh_size_m", mesh_size_m),
                                 ("contact_divisions", contact_divisions)) if v is not None}
    p = p.with_(**changes)
    clock = _Clock()
    w_all, c_all = time.perf_counter(), time.process_time()

    # -- sector: meshing, assembly, pairing (the real paper_wheel_sector, instrumented)
    with _instrumented(clock, {"meshing": ts.build_sector_mesh,
                               "assembly": so.assemble_solid,
                               "pairing": cw.sector_from_solid}):
        ws, solid = paper_wheel_sector(p)
    del solid
    # -- open-contact frequencies by ND of the unreduced sector
    all_nds = [int(k) for k in ws.cyclic.nodal_diameters]
    per_nd: dict[int, tuple[float, float]] = {}
    modal_extrapolated = modal_nds is not None
    with clock.stage("modal_by_nd"):
        if not modal_extrapolated:
            modal = modal_by_nd(cyclic=ws.cyclic, n_modes=1)
        else:
            nds = sorted({int(k) for k in modal_nds})
            f = []
            for nd in nds:
                w0, c0 = time.perf_counter(), time.process_time()
                f.append(nodal_diameter_modes(ws.cyclic, nd, 1).frequencies[0])
                per_nd[nd] = (time.perf_counter() - w0, time.process_time() - c0)
            modal = {"nd": nds, "frequency_hz": f, "max_table1_error": None}
    # -- reduced wheel: reduction, its modes, the contact rows (the rest)
    w0, c0 = time.perf_counter(), time.process_time()
    with _instrumented(clock, {"reduction": cr.reduce_sector, "wheel_modes": cr.wheel_modes}):
        wheel = build_contact_wheel(ws, n_modes=n_modes, n_interface_modes=n_interface_modes)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    clock.add("contact_rows", wall - clock.stages["reduction"]["wall_s"]
              - clock.stages["wheel_modes"]["wall_s"],
              cpu - clock.stages["reduction"]["cpu_s"] - clock.stages["wheel_modes"]["cpu_s"])
    # -- prestress and the 2ND free decay with every contact patch
    settings = ContactSettings()
    with clock.stage("calibration"):
        offset, rest = wheel.calibrate_offset(settings)
    with clock.stage("decay"):
        run = wheel.free_decay(ND, amplitude_m=AMPLITUDE_M, duration_s=duration_s, dt=dt,
                               settings=settings, offset=offset, save_every=2, progress=False)
    total_wall = time.perf_counter() - w_all
    total_cpu = time.process_time() - c_all

    # the modal stage over all NDs: as measured, or extrapolated from the timed NDs
    # (the real NDs 0 and N/2 cost like ND 0, the complex ones like the mean of those timed)
    N = ws.cyclic.n_sectors
    if modal_extrapolated:
        real = [k for k in per_nd if 2 * k % N == 0]
        cplx = [k for k in per_nd if 2 * k % N != 0]
        if not real or not cplx:
            raise ValueError("modal_nds must hold a real ND (0) and a complex one")
        n_real = sum(1 for k in all_nds if 2 * k % N == 0)
        modal_all = {key: n_real * np.mean([per_nd[k][i] for k in real])
                     + (len(all_nds) - n_real) * np.mean([per_nd[k][i] for k in cplx])
                     for i, key in ((0, "wall_s"), (1, "cpu_s"))}
    else:
        modal_all = {"wall_s": clock.stages["modal_by_nd"]["wall_s"],
                     "cpu_s": clock.stages["modal_by_nd"]["cpu_s"]}
    modal_all["extrapolated"] = modal_extrapolated

    # checks: the reduced wheel reproduces the unreduced first family, the decay is sane
    f_full = np.asarray(modal["frequency_hz"])
    om, nd_of = np.asarray(wheel.modes.omega), np.asarray(wheel.modes.nd)
    f_red = np.array([om[nd_of == k].min() / (2 * np.pi) for k in modal["nd"]])
    n_steps = int(round(duration_s / dt))
    info = ws.info
    return {
        "mesh_size_m": p.mesh_size_m, "contact_divisions": p.contact_divisions,
        "sector_dof": int(info["sector_dof"]), "wheel_dof": int(info["wheel_dof"]),
        "n_elements_sector": int(info["n_elements_sector"]),
        "cut_dof": int(info["cut_dof"]),
        "contact_pairs_per_tieboss": int(info["contact_pairs_per_tieboss"]),
        "reduced_sector_dof": int(wheel.reduced.sector.n_dof),
        "reduced_dof": int(wheel.reduced_dof),
        "contact_unknowns": int(3 * wheel.n_pairs * wheel.n_sectors),
        "stages": clock.stages, "modal_all_nds": modal_all,
        "modal_per_nd": {str(k): v for k, v in sorted(per_nd.items())},
        "reduction_timings": dict(wheel.reduced.timings),
        "total_wall_s": total_wall, "total_cpu_s": total_cpu,
        "peak_gib": _peak_gib(), "peak_after_import_gib": peak_import,
        "vm_peak_gib": _vm_peak_gib(),
        "max_table1_error": modal.get("max_table1_error"),
        "reduction_max_error": float(np.max(np.abs(f_red / f_full - 1.0))),
        "frequency_2nd_hz": float(f_full[list(modal["nd"]).index(ND)])
        if ND in modal["nd"] else None,
        "offset_m": float(offset),
        "normal_force_rest_N": float(np.mean(wheel.normal_force_per_contact(rest))),
        "decay": {"duration_s": duration_s, "dt_s": dt, "n_steps": n_steps,
                  "loop_wall_s": float(run.runtime_s), "loop_cpu_s": float(run.cpu_s),
                  "setup_s": float(run.meta.get("setup_s", float("nan"))),
                  "damping_ratio": float(run.damping_ratio),
                  "initial_amplitude_m": float(run.initial_amplitude_m),
                  "energy_balance_error": float(run.energy_balance_error),
                  "state_fractions": {k: float(v) for k, v in run.state_fractions.items()},
                  "n_iterations": int(run.meta.get("n_iterations", -1)),
                  "n_krylov": int(run.meta.get("n_krylov", -1)),
                  "success": bool(run.meta.get("success", True))},
    }


def extrapolate_decay(res: dict, duration_s: float = DURATION_S) -> dict:
    """Decay stage scaled to ``duration_s``: the non-loop part as measured, the time loop
    per step (labelled extrapolated when the measured window was shorter)."""
    st, d = res["stages"]["decay"], res["decay"]
    factor = duration_s / d["duration_s"]
    if abs(factor - 1.0) < 1e-9:
        return {"wall_s": st["wall_s"], "cpu_s": st["cpu_s"], "extrapolated": False}
    return {"wall_s": st["wall_s"] + (factor - 1.0) * d["loop_wall_s"],
            "cpu_s": st["cpu_s"] + (factor - 1.0) * d["loop_cpu_s"], "extrapolated": True}


def measure_in_subprocess(timeout_s: float = 3600.0, memory_cap_gib: float | None = None,
                          **kwargs) -> dict:
    """:func:`measure` in a fresh interpreter with one thread (peak memory per size).

    ``memory_cap_gib`` caps the worker's address space (RLIMIT_AS) so that a size too big
    for the machine fails with MemoryError instead of waking the OOM killer on a shared
    machine. Returns ``{"failed": message}`` when the worker fails.
    """
    env = dict(os.environ)
    env.update({v: "1" for v in THREAD_VARS})
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", json.dumps(kwargs)]
    if memory_cap_gib:
        cmd += ["--memory-cap-gib", str(memory_cap_gib)]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout_s)
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith(MARK)]
    if proc.returncode != 0 or not lines:
        tail = proc.stderr.strip().splitlines()[-1:] or [f"exit status {proc.returncode}"]
        return {"failed": tail[0], "stderr": proc.stderr[-4000:], **kwargs}
    return json.loads(lines[-1][len(MARK):])


# ================================================================================ reporting
def _scale(res: dict) -> dict:
    """Stage times over the full pipeline (all NDs, 0.1 s of decay), measured or
    extrapolated; ``res["scaled"][stage] = {"wall_s", "cpu_s", "extrapolated"}``."""
    scaled = {k: {"wall_s": v["wall_s"], "cpu_s": v["cpu_s"], "extrapolated": False}
              for k, v in res["stages"].items()}
    scaled["modal_by_nd"] = dict(res["modal_all_nds"])
    scaled["decay"] = extrapolate_decay(res)
    # the measured total (glue between the stages included) plus what was extrapolated
    scaled["total"] = {k: res[f"total_{k}"] + sum(scaled[s][k] - res["stages"][s][k]
                                                   for s in STAGES)
                       for k in ("wall_s", "cpu_s")}
    scaled["total"]["extrapolated"] = any(scaled[s]["extrapolated"] for s in STAGES)
    cm = res["reduction_timings"].get("constraint_modes", float("nan"))
    scaled["constraint_modes"] = {"wall_s": cm, "cpu_s": cm, "extrapolated": False}
    res["scaled"] = scaled
    return res


def exponents(rows: list[dict]) -> dict:
    """Least-squares slope of log(CPU time) against log(sector DOF) for every stage, and
    of the peak memory."""
    import numpy as np

    if len(rows) < 2:
        return {}
    x = np.log([r["sector_dof"] for r in rows])

    def slope(y):
        return float(np.polyfit(x, np.log(np.maximum(y, 1e-4)), 1)[0])

    out = {k: slope([r["scaled"][k]["cpu_s"] for r in rows])
           for k in (*STAGES, "constraint_modes", "total")}
    out["peak_memory"] = slope([r["peak_gib"] for r in rows])
    return out


def _cell(entry: dict, key: str = "cpu_s", fmt: str = "{:.1f}") -> str:
    return fmt.format(entry[key]) + ("*" if entry["extrapolated"] else "")


def stage_table(res: dict) -> str:
    """Stage, wall, CPU and process peak after the stage (the pipeline as measured)."""
    lines = [f"{'stage':<26}{'wall s':>9}{'CPU s':>9}{'peak GiB':>10}"]
    for name in STAGES:
        s = res["stages"][name]
        lines.append(f"{name:<26}{s['wall_s']:>9.2f}{s['cpu_s']:>9.2f}{s['peak_gib']:>10.2f}")
        if name == "reduction":
            for k, v in res["reduction_timings"].items():
                lines.append(f"  {k:<24}{v:>9.2f}{'(wall)':>9}")
        if name == "decay":
            d = res["decay"]
            lines.append(f"  {'time loop':<24}{d['loop_wall_s']:>9.2f}{d['loop_cpu_s']:>9.2f}")
    lines.append(f"{'total':<26}{res['total_wall_s']:>9.2f}{res['total_cpu_s']:>9.2f}"
                 f"{res['peak_gib']:>10.2f}")
    if res["scaled"]["total"]["extrapolated"]:
        t = res["scaled"]["total"]
        lines.append(f"{'total, extrapolated':<26}{t['wall_s']:>9.2f}{t['cpu_s']:>9.2f}"
                     "   (all NDs, 0.1 s of decay)")
    return "\n".join(lines)


def scaling_table(rows: list[dict], slopes: dict) -> str:
    """Rows: stages; columns: sector sizes; last column: exponent of CPU time vs DOF."""
    w = 14
    lines = [f"{'CPU s':<18}" + "".join(f"{r['label']:>{w}}" for r in rows)
             + f"{'exponent':>10}",
             f"{'sector DOF':<18}" + "".join(f"{r['sector_dof']:>{w}d}" for r in rows)]
    for name in (*STAGES, "total"):
        lines.append(f"{name:<18}" + "".join(f"{_cell(r['scaled'][name]):>{w}}" for r in rows)
                     + f"{slopes.get(name, float('nan')):>10.2f}")
        if name == "reduction":
            lines.append(f"{'  constraint (w)':<18}" + "".join(
                f"{_cell(r['scaled']['constraint_modes']):>{w}}" for r in rows)
                + f"{slopes.get('constraint_modes', float('nan')):>10.2f}")
    lines.append(f"{'total wall s':<18}" + "".join(
        f"{_cell(r['scaled']['total'], 'wall_s'):>{w}}" for r in rows))
    lines.append(f"{'peak GiB':<18}" + "".join(f"{r['peak_gib']:>{w}.2f}" for r in rows)
                 + f"{slopes.get('peak_memory', float('nan')):>10.2f}")
    for key, label, fmt in (("mesh_size_m", "mesh_size_m", "{:.4g}"),
                            ("n_elements_sector", "tet10 / sector", "{:d}"),
                            ("cut_dof", "cut DOF", "{:d}"),
                            ("reduced_dof", "reduced wheel DOF", "{:d}")):
        lines.append(f"{label:<18}" + "".join(f"{fmt.format(r[key]):>{w}}" for r in rows))
    lines.append(f"{'decay window s':<18}" + "".join(
        f"{r['decay']['duration_s']:>{w}.3g}" for r in rows))
    lines.append(f"{'decay ms/step':<18}" + "".join(
        f"{1e3 * r['decay']['loop_cpu_s'] / r['decay']['n_steps']:>{w}.1f}" for r in rows))
    if any(r["scaled"]["total"]["extrapolated"] for r in rows):
        lines.append("* extrapolated: modal_by_nd from the NDs timed (real NDs like ND 0, "
                     "complex ones like their mean), decay to 0.1 s per time step (set-up as "
                     "measured)")
    lines.append("(w): wall time, reduce_sector's own sub-stage timing")
    return "\n".join(lines)


def run(quick: bool = False, scaling: bool = True, verbose: bool = False,
        memory_cap_gib: float | None = 14.0) -> dict:
    """The benchmark (module docstring); ``quick``: coarse mesh and short decay."""
    say = print if verbose else (lambda *a, **k: None)
    kw = dict(QUICK) if quick else {}
    res = measure_in_subprocess(memory_cap_gib=memory_cap_gib, **kw)
    if "failed" in res:
        raise RuntimeError(f"the default-mesh run failed: {res['failed']}\n{res['stderr']}")
    rows, failed = [], []
    if scaling:
        for lab, h, dur, nds in (QUICK_SCALING if quick else SCALING):
            r = measure_in_subprocess(memory_cap_gib=memory_cap_gib, mesh_size_m=h,
                                      duration_s=dur, modal_nds=nds)
            if "failed" in r:
                failed.append([lab, h, r["failed"]])
                say(f"  scaling: {lab} (mesh_size_m {h}) FAILED: {r['failed']}", flush=True)
                continue
            r["label"] = lab
            rows.append(r)
            say(f"  scaling: {lab}: {r['sector_dof']} DOF measured in "
                f"{r['total_wall_s']:.0f} s wall", flush=True)
    return summarise(res, rows, quick=quick, failed=failed, say=say)


def summarise(res: dict, rows: list[dict], *, quick: bool = False, failed=(),
              say=print) -> dict:
    """Verdicts, tables and the ``run()`` result from the measured dicts (also used by
    ``--report`` to print a saved ``--json`` again)."""
    res = _scale(res)
    rows = [_scale(r) for r in rows]
    tot = res["scaled"]["total"]
    ok_time = tot["wall_s"] <= TARGET_SECONDS
    ok_mem = res["peak_gib"] <= TARGET_GIB
    d = res["decay"]
    label = "quick (coarse mesh, short decay)" if quick else "default mesh"
    say(f"solid wheel, {label}: mesh_size_m {res['mesh_size_m']}, sector "
        f"{res['sector_dof']} DOF ({res['n_elements_sector']} tet10, {res['cut_dof']} DOF per "
        f"cut), wheel {res['wheel_dof']} DOF, reduced wheel {res['reduced_dof']} DOF, "
        f"{res['contact_pairs_per_tieboss']} node pairs x 30 contacts "
        f"({res['contact_unknowns']} contact unknowns); one thread")
    say(stage_table(res))
    per_step = d["loop_cpu_s"] / d["n_steps"]
    say(f"decay: {d['duration_s']} s at dt {d['dt_s']} ({d['n_steps']} steps, "
        f"{1e3 * per_step:.1f} ms CPU/step), zeta(2ND) "
        f"{100 * d['damping_ratio']:.3f} %, energy balance error "
        f"{d['energy_balance_error']:.2e}, states "
        + ", ".join(f"{k} {v:.3f}" for k, v in d["state_fractions"].items())
        + f"; {d['n_iterations']} iterations ({d['n_krylov']} Newton-Krylov); at the paper's "
        f"dt 5e-6 s (4x the steps at this cost per step) the loop would take "
        f"~{per_step * DURATION_S / 5e-6:.0f} s CPU")
    t1 = res["max_table1_error"]
    say(f"checks: Table 1 max error {'-' if t1 is None else f'{100 * t1:.2f} %'}, reduced "
        f"vs unreduced first family max {100 * res['reduction_max_error']:.2e} %, prestress "
        f"{res['normal_force_rest_N']:.3f} N per contact")
    extra = " (extrapolated)" if tot["extrapolated"] else ""
    say(f"{'MET ' if ok_time else 'MISS'} time   {tot['wall_s']:.1f} s wall, "
        f"{tot['cpu_s']:.1f} s CPU, one core{extra}  [target <= {TARGET_SECONDS:.0f} s in all, "
        f"2 cores allowed]")
    say(f"{'MET ' if ok_mem else 'MISS'} memory {res['peak_gib']:.2f} GiB process peak "
        f"(ru_maxrss; virtual peak {res['vm_peak_gib']:.2f} GiB)  [target <= "
        f"{TARGET_GIB:.0f} GiB]")
    say(f"paper (quoted, not run): {PAPER}; here {tot['wall_s'] / 3600:.3f} core-hours")
    slopes = exponents(rows)
    if rows:
        say("scaling (CPU s per stage on one thread; exponent p of t ~ DOF^p):\n"
            + scaling_table(rows, slopes))
    for lab, h, msg in failed:
        say(f"scaling: {lab} (mesh_size_m {h}) failed: {msg}")
    figure = (f"{label}, {res['sector_dof']}-DOF sector: {tot['wall_s']:.0f} s wall "
              f"({tot['cpu_s']:.0f} s CPU, one core), peak {res['peak_gib']:.2f} GiB; zeta(2ND) "
              f"{100 * d['damping_ratio']:.2f} % (paper: ~40,000 core-h, quoted)")
    details = {"sector_dof": res["sector_dof"], "reduced_dof": res["reduced_dof"],
               "total_wall_s": tot["wall_s"], "total_cpu_s": tot["cpu_s"],
               "peak_gib": res["peak_gib"]}
    details.update({f"{k}_cpu_s": v["cpu_s"] for k, v in res["scaled"].items()})
    details.update({f"exponent_{k}": v for k, v in slopes.items()})
    return {"name": "solid_wheel", "figure": figure, "value": tot["wall_s"],
            "target": TARGET_SECONDS, "unit": "s", "passed": bool(ok_time and ok_mem),
            "details": details, "quick": quick, "default": res, "scaling": rows,
            "exponents": slopes, "failed": list(failed)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarse mesh, short decay (< 2 min)")
    ap.add_argument("--no-scaling", action="store_true", help="default mesh only")
    ap.add_argument("--json", type=Path, metavar="PATH", help="write every number to PATH")
    ap.add_argument("--report", type=Path, metavar="PATH",
                    help="print the tables of a saved --json again, without measuring")
    ap.add_argument("--memory-cap-gib", type=float, default=14.0,
                    help="address-space cap of each worker [GiB] (0: none)")
    ap.add_argument("--worker", metavar="JSON", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker is not None:
        if args.memory_cap_gib:
            cap = int(args.memory_cap_gib * 1024**3)
            resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
        print(MARK + json.dumps(measure(**json.loads(args.worker))), flush=True)
        return 0
    if args.report is not None:
        saved = json.loads(args.report.read_text())
        res = summarise(saved["default"], saved["scaling"], quick=saved.get("quick", False),
                        failed=saved.get("failed", ()))
    else:
        res = run(quick=args.quick, scaling=not args.no_scaling, verbose=True,
                  memory_cap_gib=args.memory_cap_gib or None)
    if args.json:
        args.json.write_text(json.dumps(res, indent=2, default=str))
    print("PASS" if res["passed"] else "MISS")
    return 0 if res["passed"] else 1


if __name__ == "__main__":
    sys.exit(main())
