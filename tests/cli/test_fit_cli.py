"""``fricdamp fit``: loop CSV files and identify folders in, fit.json and fit.png out; the
numbers are the library's (fit_joint on the same loops), unreliable fits exit 3, bad input
exits 2 with one line."""

import json

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.contact.rough import RoughRotationalJoint
from fricdamp.signals.fit import fit_joint, read_fit_input


def _loop_csv(path, law, amp, *, n=160, noise=0.01, seed=0, rotational=False,
              head="time [s],displacement [m],force [N]"):
    rng = np.random.default_rng(seed)
    cyc = amp * np.cos(2 * np.pi * np.arange(n) / n)
    u = np.concatenate((amp * np.sin(np.linspace(0, np.pi / 2, 40)), cyc, cyc))
    f = law.drive(u)[-n:]
    f = f + noise * 0.5 * np.ptp(f) * rng.standard_normal(n)
    t = np.arange(n) / (30.0 * n)
    path.write_text(head + "\n" + "\n".join(f"{a:.9e},{b:.12e},{c:.12e}"
                                            for a, b, c in zip(t, cyc, f, strict=True)))
    return path


@pytest.fixture
def jenkins_loops(tmp_path):
    law = Jenkins(1e6, 10.0)
    return [_loop_csv(tmp_path / f"loop{i}.csv", law, a, seed=i)
            for i, a in enumerate((5e-6, 1e-5, 2e-5, 4e-5))]


def test_fit_jenkins_writes_the_library_numbers(cli, tmp_path, jenkins_loops):
    out = tmp_path / "out"
    code, stdout, _ = cli("fit", *jenkins_loops, "--model", "jenkins", "--out", out)
    assert code == 0
    d = json.loads((out / "fit.json").read_text())
    loops = [lp for p in jenkins_loops for lp in read_fit_input(p)]
    ref = fit_joint(loops, model="jenkins")
    for name in ("stiffness_N_per_m", "slip_force_N"):
        assert d["parameters"][name] == pytest.approx(ref.parameters[name], rel=1e-9)
        lo, hi = d["confidence_95"][name]
        assert lo < d["parameters"][name] < hi
    assert d["parameters"]["slip_force_N"] == pytest.approx(10.0, rel=0.01)
    assert d["residual"]["rms_relative"] < 0.02 and d["status"] == "ok"
    assert d["exit_code"] == 0 and (out / "fit.png").stat().st_size > 1000
    assert "slip_force_N" in stdout


def test_fit_identify_folder_with_the_rough_model_exits_3(cli, tmp_path):
    """An identify output folder (loop.csv) holding one gross-slip loop sampled at 64 points
    per period: mu is found, but the stiffness and sigma rest on the few samples of the stick
    phase at the reversals, so the fit is flagged (exit 3) with fit.json written."""
    folder = tmp_path / "identify-run"
    folder.mkdir()
    joint = RoughRotationalJoint.paper_002(n_cells=(7, 5))
    _loop_csv(folder / "loop.csv", joint, 3e-3, n=64, rotational=True,
              head="phase [-],rotation [rad],torque [N m]")
    out = tmp_path / "rough"
    code, _, err = cli("fit", folder, "--model", "rough", "--out", out, "--fixed",
                       "joint_cells=7,5", "--preload", "100")
    assert code == 3
    d = json.loads((out / "fit.json").read_text())
    assert d["status"] == "unreliable" and d["exit_code"] == 3
    assert d["parameters"]["mu"] == pytest.approx(0.15, rel=0.02)
    assert "rests on" in err and d["fixed"]["joint_cells"] == [7, 5]
    assert d["conditioning"]["raw_condition_number"] > 1e6


@pytest.mark.parametrize("extra, message", [
    (["--model", "jenkins", "--fixed", "preload_N=100"], "apply to the rough model"),
    (["--model", "jenkins", "--initial", "slip_force_N"], "--initial must be KEY=VALUE"),
    (["--model", "jenkins", "--initial", "stiffness=3"], "unknown parameter"),
    (["--model", "rough"], "rotational joint"),
])
def test_bad_input_exits_2_with_one_line(cli, tmp_path, jenkins_loops, extra, message):
    code, _, err = cli("fit", jenkins_loops[0], "--out", tmp_path / "x", *extra)
    assert code == 2
    assert message in err and err.count("\n") == 1


def test_unreadable_loops_exit_2(cli, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("time [s],speed [m/s]\n0,1\n1,2\n")
    code, _, err = cli("fit", bad, "--model", "jenkins", "--out", tmp_path / "x")
    assert code == 2 and "needs a displacement" in err
    code, _, err = cli("fit", tmp_path / "none.csv", "--model", "jenkins")
    assert code == 2 and "does not exist" in err


def test_fit_json_carries_the_verdict_and_ends_with_it(cli, tmp_path, jenkins_loops):
    """Issue 15's results contract for fit: fit.json's verdict {overall, analyses: {fit}},
    'verdict: ok' as the last line of a good fit; the output folder is checked before the
    fit (an --out that is a file: exit 1, one line)."""
    out = tmp_path / "out"
    code, stdout, _ = cli("fit", *jenkins_loops, "--model", "jenkins", "--out", out)
    assert code == 0 and stdout.strip().splitlines()[-1] == "verdict: ok"
    v = json.loads((out / "fit.json").read_text())["verdict"]
    assert v["overall"] == "ok" and v["analyses"]["fit"]["reasons"] == []
    assert v["analyses"]["fit"]["estimates"]["rms_relative"] < 0.02
    blocker = tmp_path / "afile"
    blocker.write_text("x")
    code, stdout, err = cli("fit", *jenkins_loops, "--model", "jenkins", "--out", blocker)
    assert code == 1 and err.count("\n") == 1 and "is a file; choose another --out" in err
    assert "slip_force_N" not in stdout                    # nothing was fitted


def test_unreliable_fit_ends_with_its_verdict(cli, tmp_path):
    folder = tmp_path / "identify-run"
    folder.mkdir()
    joint = RoughRotationalJoint.paper_002(n_cells=(7, 5))
    _loop_csv(folder / "loop.csv", joint, 3e-3, n=64, rotational=True,
              head="phase [-],rotation [rad],torque [N m]")
    out = tmp_path / "rough"
    code, _, err = cli("fit", folder, "--model", "rough", "--out", out, "--fixed",
                       "joint_cells=7,5", "--preload", "100")
    assert code == 3
    assert err.strip().splitlines()[-1].startswith("fricdamp: warning: verdict: unreliable "
                                                   "(fit): ")
    v = json.loads((out / "fit.json").read_text())["verdict"]
    assert v["overall"] == "unreliable" and any("rests on" in r
                                                for r in v["analyses"]["fit"]["reasons"])


def test_loop_file_that_is_a_device_is_refused_at_once(cli, tmp_path):
    code, _, err = cli("fit", "/dev/zero", "--model", "jenkins", "--out", tmp_path / "x")
    assert code == 2 and err.count("\n") == 1
    assert "loop file '/dev/zero' is not a regular file" in err
