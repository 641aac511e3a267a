"""``fricdamp sweep`` / ``fricdamp optimize`` on a real case: outputs, physics, resume, errors.

The handlers are called through :func:`fricdamp.cli.studies.main` (the same argparse
subcommands the ``fricdamp`` command mounts). The case is one mass m = 1 kg on a spring
k = 1e4 N/m with a Jenkins contact to ground (stiffness k_t, slip force F_s), released from
x0 at rest, without viscous damping. Closed forms used:

* initial energy ``E0 = (k + k_t) x0^2 / 2`` (spring and stuck contact both stretched by x0);
* when the contact never slips (``k_t x0 < F_s``) the system is linear and undamped: the
  average-acceleration Newmark scheme conserves its energy exactly, so the final energy equals
  E0 to round-off and the contact dissipates nothing;
* in every case energy is conserved: ``E0 = E_final + W_contact``.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from fricdamp.cli.studies import main

CASE = """\
name = "one_dof"

[model]
type = "chain"
masses_kg = [1.0]
springs_N_per_m = [1.0e4]

[[contacts]]
type = "jenkins"
name = "slider"
dofs = [1]
stiffness_N_per_m = 1.0e4
slip_force_N = 100.0

[analysis.free_decay]
initial_displacement_m = [1.0e-3]
duration_s = {duration}
time_step_s = 1.0e-3
"""


@pytest.fixture
def case(tmp_path):
    def _write(extra: str = "", duration: float = 0.05):
        path = tmp_path / "one_dof.toml"
        path.write_text(CASE.format(duration=duration) + extra, encoding="utf-8")
        return path
    return _write


@pytest.fixture
def run(capsys):
    def _run(*args):
        code = main([str(a) for a in args])
        out = capsys.readouterr()
        return code, out.out, out.err
    return _run


def test_sweep_writes_results_that_obey_the_closed_forms(case, run, tmp_path):
    import xarray as xr

    out = tmp_path / "out"
    path = case()
    code, stdout, stderr = run("sweep", path, "--grid", "stiffness_N_per_m=1e3:1e4:3",
                               "--grid", "initial_displacement_m.1=1e-3,2e-3", "--serial",
                               "--out", out)
    assert code == 0, stderr
    assert "6 points: 6 computed, 0 reused, 0 failed" in stdout
    assert stdout.strip().splitlines()[-1] == "verdict: ok"      # last, as for fricdamp run
    with xr.open_dataset(out / "sweep.nc", engine="scipy") as ds:
        ds = ds.load()
    assert ds["free_decay__initial_energy_J"].dims == ("stiffness_N_per_m",
                                                       "initial_displacement_m.1")
    kt = ds["stiffness_N_per_m"].values[:, None]
    x0 = ds["initial_displacement_m.1"].values[None, :]
    e0 = 0.5 * (1.0e4 + kt) * x0 ** 2
    # E0 is computed from the same numbers: round-off only
    np.testing.assert_allclose(ds["free_decay__initial_energy_J"].values, e0, rtol=1e-12)
    # k_t x0 <= 20 N < F_s = 100 N: no slip, linear undamped, energy conserved by the
    # trapezoidal rule to its Newton tolerance (1e-10 relative)
    np.testing.assert_allclose(ds["free_decay__final_energy_J"].values, e0, rtol=1e-9)
    np.testing.assert_array_equal(ds["free_decay__contact_dissipation_J"].values, 0.0)
    assert (ds["wall_time_s"].values > 0).all() and not ds["failed"].values.any()
    summary = json.loads((out / "summary.json").read_text())
    assert (summary["points_total"], summary["points_computed"], summary["points_reused"],
            summary["points_failed"]) == (6, 6, 0, [])
    assert (out / "sweep_free_decay__initial_energy_J.png").exists()
    assert "| points | 6 |" in (out / "report.md").read_text()
    assert "sweep_free_decay__initial_energy_J.png" in (out / "report.html").read_text()
    assert len(list((out / "points").glob("*.json"))) == 6

    # the same command again: everything reused, nothing computed
    code, stdout, _ = run("sweep", path, "--grid", "stiffness_N_per_m=1e3:1e4:3",
                          "--grid", "initial_displacement_m.1=1e-3,2e-3", "--serial",
                          "--out", out, "--no-figures")
    assert code == 0 and "6 points: 0 computed, 6 reused, 0 failed" in stdout
    # a changed case (another mass) must not reuse a single point
    path.write_text(path.read_text().replace("masses_kg = [1.0]", "masses_kg = [2.0]"))
    code, stdout, _ = run("sweep", path, "--grid", "stiffness_N_per_m=1e3:1e4:3",
                          "--grid", "initial_displacement_m.1=1e-3,2e-3", "--serial",
                          "--out", out, "--no-figures")
    assert code == 0 and "6 points: 6 computed, 0 reused" in stdout


def test_grid_from_the_case_file_and_energy_balance_with_slip(case, run, tmp_path):
    import xarray as xr

    extra = ('\n[sweep.grid]\nslip_force_N = [2.0, 5.0]\ninitial_displacement_m = "2e-3:4e-3:2"'
             '\ntime_step_s = 1e-4\n')
    code, _, err = run("sweep", case(extra), "--serial", "--out", tmp_path / "o")
    assert code == 2 and "names a list" in err  # a list key is not a number: say which entry
    # a dotted key is a nested table in TOML; both spellings name the first entry
    extra = extra.replace("initial_displacement_m =", "initial_displacement_m.1 =")
    code, stdout, err = run("sweep", case(extra), "--serial", "--out", tmp_path / "o")
    assert code == 0, err
    with xr.open_dataset(tmp_path / "o" / "sweep.nc", engine="scipy") as ds:
        ds = ds.load()
    assert list(ds.sizes.items()) == [("slip_force_N", 2), ("initial_displacement_m.1", 2),
                                      ("time_step_s", 1)]
    ds = ds.isel(time_step_s=0)
    fs = ds["slip_force_N"].values[:, None]
    x0 = ds["initial_displacement_m.1"].values[None, :]
    # k_t x0 = 20..40 N > F_s: the contact starts at its slip limit, storing F_s^2 / (2 k_t)
    e0 = 0.5 * 1.0e4 * x0 ** 2 + fs ** 2 / (2 * 1.0e4)
    np.testing.assert_allclose(ds["free_decay__initial_energy_J"].values, e0, rtol=1e-12)
    w = ds["free_decay__contact_dissipation_J"].values
    assert (w > 0).all()
    # energy conservation E0 = E_final + W_contact; the trapezoidal rule closes it to O(h^2)
    # with slip events inside steps: 1.6e-5 relative observed at h = 1e-4 s, bound 1e-4
    np.testing.assert_allclose(ds["free_decay__final_energy_J"].values + w, e0, rtol=1e-4)


@pytest.mark.parametrize("grid, words", [
    ("stifness_N_per_m=1e3:1e4:3", ["unknown grid parameter 'stifness_N_per_m'",
                                    "did you mean 'stiffness_N_per_m'"]),
    ("stiffness_N_per_m=1e3:1e4:0", ["empty range"]),
    ("stiffness_N_per_m=1e3,abc", ["'abc'", "not a number"]),
    ("stiffness_N_per_m=-1e3,1e3", ["at stiffness_N_per_m=-1000", "stiffness_N_per_m",
                                    "> 0"]),
    ("masses_kg=1,2", ["names a list", "model.masses_kg.1"]),
    ("time_step_s=1e-3,0.1", ["at time_step_s=0.1", "smaller than duration_s"]),
])
def test_bad_grids_exit_2_with_a_clear_message(case, run, tmp_path, grid, words):
    code, stdout, stderr = run("sweep", case(), "--grid", grid, "--serial", "--out",
                               tmp_path / "o")
    assert code == 2
    assert "Traceback" not in stderr and stderr.startswith("fricdamp: error: ")
    for w in words:
        assert w in stderr, (w, stderr)
    assert not (tmp_path / "o").exists()  # nothing ran, nothing written


def test_study_tables_are_checked(case, run, tmp_path):
    code, _, err = run("sweep", case(), "--serial", "--out", tmp_path / "o")
    assert code == 2 and "no grid" in err
    code, _, err = run("sweep", case("\n[sweep]\ngrids = {a = 1}\n"), "--serial")
    assert code == 2 and "unknown key 'grids' in [sweep]" in err
    code, _, err = run("sweep", case(), "--grid", "mu=1", "--serial", "--scheduler", "tcp://x")
    assert code == 2  # argparse: --serial and --scheduler exclude each other


def test_optimize_finds_the_corner_minimum_of_the_initial_energy(case, run, tmp_path):
    out = tmp_path / "opt"
    code, stdout, err = run("optimize", case(), "--minimize", "initial_energy_J", "--over",
                            "stiffness_N_per_m=1e3:1e4,initial_displacement_m.1=1e-3:2e-3",
                            "--method", "nelder-mead", "--out", out)
    assert code == 0, err
    assert stdout.strip().splitlines()[-1] == "verdict: ok"      # last, as for fricdamp run
    opt = json.loads((out / "optimum.json").read_text())
    assert opt["objective"] == "free_decay__initial_energy_J"  # the bare key was resolved
    # E0 = (k + k_t) x0^2 / 2 is smallest at the corner k_t = 1e3, x0 = 1e-3: 5.5e-3 J;
    # Nelder-Mead stops within xatol = 0.01 of the unit box, i.e. 1 % of each range
    assert opt["x"]["stiffness_N_per_m"] == pytest.approx(1e3, abs=0.01 * 9e3)
    assert opt["x"]["initial_displacement_m.1"] == pytest.approx(1e-3, abs=0.01 * 1e-3)
    assert opt["value"] == pytest.approx(5.5e-3, rel=0.03)
    assert opt["n_evaluations"] == len((out / "history.csv").read_text().splitlines()) - 1
    # rerun: every evaluation is replayed from the store
    code, stdout, _ = run("optimize", case(), "--minimize", "initial_energy_J", "--over",
                          "stiffness_N_per_m=1e3:1e4,initial_displacement_m.1=1e-3:2e-3",
                          "--method", "nelder-mead", "--out", out, "--no-figures")
    assert code == 0 and " 0 computed" in stdout
    code, _, err = run("optimize", case(), "--minimize", "energy", "--over",
                       "stiffness_N_per_m=1e3:1e4", "--serial", "--out", out)
    assert code == 2 and "no result 'energy'" in err


def test_terminated_cli_sweep_resumes_without_losing_or_recomputing(case, tmp_path):
    """SIGTERM mid-study: exit 130 with a summary; the same command then finishes the rest."""
    path = case(duration=0.4)  # 400 steps: a few tenths of a second per point
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "fricdamp.cli.studies", "sweep", str(path), "--grid",
           "stiffness_N_per_m=1e3:1e4:10", "--serial", "--out", str(out), "--no-figures"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 90
        while len(list((out / "points").glob("*.json"))) < 3:
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline
            time.sleep(0.05)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert "run it again" in err
    stopped = json.loads((out / "summary.json").read_text())
    stored = len(list((out / "points").glob("*.json")))
    assert stopped["interrupted"] is True and 3 <= stored < 10
    assert stopped["points_computed"] == stored  # every finished point was stored
    assert main(cmd[3:]) == 0  # the same command again (in this process)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is False
    assert summary["points_reused"] == stored
    assert summary["points_computed"] == 10 - stored
    assert summary["points_failed"] == []
