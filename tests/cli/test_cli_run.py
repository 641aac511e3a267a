"""``fricdamp run``: the output contract, atomic files, formats and the physics of a small case.

The case is one mass m = 1 kg on a spring k = 1e4 N/m with a Jenkins contact to ground
(k_t = 1e4 N/m, F_s = 1 N): the closed forms below are exact for it.
"""

from __future__ import annotations

import html.parser
import json
import math

import numpy as np
import pytest
import xarray as xr
from cli_cases import BASE_CASE

from fricdamp.cli.app import _progress_wanted

EXTRA = """
[analysis.forced_response]
force_amplitude_N = [3.0]
frequency_hz = 10.0
periods = 30
steps_per_period = 64

[analysis.hysteresis]
amplitudes_m = [5.0e-5, 2.0e-4, 1.0e-3]
"""

HYSTERESIS_ONLY = """\
name = "loops_only"

[model]
type = "chain"
masses_kg = [1.0]
springs_N_per_m = [1.0e4]

[[contacts]]
type = "coulomb"
dofs = [1]
stiffness_N_per_m = 1.0e4
normal_load_N = 10.0
mu_static = 0.3
mu_sliding = 0.2

[analysis.hysteresis]
amplitudes_m = [2.0e-4, 1.0e-3, 5.0e-3]
samples_per_cycle = 2000
"""


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    """Run the one-DOF case with all three analyses once; return (out dir, stdout, stderr)."""
    from fricdamp.cli.app import main

    d = tmp_path_factory.mktemp("run")
    case = d / "one_dof.toml"
    case.write_text(BASE_CASE + EXTRA, encoding="utf-8")
    import contextlib
    import io

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["run", str(case), "--out", str(d / "out")])
    assert code == 0, err.getvalue()
    return d / "out", out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def summary(run_dir):
    return json.loads((run_dir[0] / "summary.json").read_text())


def test_contract_keys_and_files(run_dir, summary):
    out, stdout, stderr = run_dir
    for key in ("fricdamp_version", "case", "runtime_s", "energy_balance_error", "model",
                "free_decay", "forced_response", "hysteresis", "files"):
        assert key in summary, key
    assert summary["case"]["name"] == "one_dof"
    assert summary["case"]["analysis"]["forced_response"]["periods"] == 30
    assert summary["runtime_s"] > 0
    # the top-level error is the largest of the analyses' errors
    assert summary["energy_balance_error"] == max(
        summary["free_decay"]["energy_balance_error"],
        summary["forced_response"]["energy_balance_error"])
    files = summary["files"]
    assert files["results"] == "results.nc" and files["report"] == "report.html"
    for name in [files["summary"], files["results"], files["report"], *files["figures"]]:
        assert (out / name).is_file(), name
    assert len(files["figures"]) >= 7
    # atomic writes leave no temporary files behind
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]
    assert f"report: {(out / 'report.html').resolve()}" in stdout
    assert stderr == ""  # not a terminal: no progress bar, no warnings


def test_initial_energy_closed_form(summary):
    """q0 = 1 mm loads the contact past its slip limit (k_t q0 = 10 N > F_s = 1 N): the spring
    stores k q0^2/2 = 5e-3 J and the contact F_s^2/(2 k_t) = 5e-5 J. Exact up to round-off."""
    assert summary["free_decay"]["initial_energy_J"] == pytest.approx(5.05e-3, rel=1e-12)


def test_free_decay_sticks_at_the_stuck_frequency(summary):
    """Once the slider sticks the oscillator is linear with k + k_t: f = sqrt(2e4)/(2 pi).

    Newmark's period error is (w h)^2/12 = 4e-5 at h = 5e-4 s; tolerance 1e-3.
    """
    fd = summary["free_decay"]
    f_stuck = math.sqrt(2.0e4) / (2 * math.pi)
    assert fd["frequency_hz"][-1] == pytest.approx(f_stuck, rel=1e-3)
    assert summary["model"]["natural_frequencies_stuck_hz"][0] == pytest.approx(f_stuck,
                                                                                rel=1e-12)
    # no viscous damping: no decay once stuck. The decay ends with the contact force amplitude
    # at the slip limit, where reversals still slip by round-off amounts: |zeta| < 1e-4, four
    # orders below the friction damping of the slipping phase.
    assert max(fd["damping_ratio"]) > 0.05
    assert max(abs(z) for z in fd["damping_ratio"][-5:]) < 1e-4
    # the energy that left the structure went into the contact, to within the balance error
    # the integrator reports (relative to the energy of the run, here the initial energy)
    assert fd["energy_balance_error"] < 1e-3
    lost = fd["initial_energy_J"] - fd["final_energy_J"]
    assert abs(fd["contact_dissipation_J"] - lost) <= (
        1.0001 * fd["energy_balance_error"] * fd["initial_energy_J"])


def test_forced_loop_matches_jenkins_closed_form(summary):
    """Steady loop of the contact: W = 4 F_s (A - F_s/k_t) at its measured amplitude A.

    Discretisation: the slip onset falls between samples (64 per period), an O(1/64^2)
    error on the corner; tolerance 1 %. Excitation at 10 Hz, below the slipping (15.9 Hz) and
    stuck (22.5 Hz) resonances, so the response is steady after 30 periods.
    """
    fr = summary["forced_response"]
    c = fr["contacts"]["slider"]
    A = c["relative_displacement_amplitude_m"]
    assert A > 1e-4  # slips
    assert c["dissipated_energy_per_cycle_J"] == pytest.approx(4 * 1.0 * (A - 1e-4), rel=1e-2)
    assert c["force_amplitude_N"] == pytest.approx(1.0, rel=1e-9)
    # steady state: input work per cycle = dissipation per cycle
    assert fr["steady_state_change"] < 1e-6
    assert fr["cycle_energy_balance_error"] < 1e-2
    assert fr["input_work_per_cycle_J"] == pytest.approx(
        fr["contact_dissipation_per_cycle_J"] + fr["viscous_dissipation_per_cycle_J"], rel=1e-2)


def test_hysteresis_closed_form(summary):
    """Jenkins W = 4 F_s (A - F_s/k_t), 0 below A = F_s/k_t = 1e-4 m (REFERENCES.md)."""
    h = summary["hysteresis"]["contacts"]["slider"]
    A = np.array(summary["hysteresis"]["amplitude_m"])
    expected = np.where(A > 1e-4, 4 * (A - 1e-4), 0.0)
    np.testing.assert_allclose(h["loop_energy_J"], expected, rtol=1e-4, atol=1e-12)
    assert h["closed_form_error"] < 1e-4


def test_results_file(run_dir, summary):
    out = run_dir[0]
    with xr.open_dataset(out / "results.nc", engine="scipy") as ds:
        q = ds["free_decay__q"]
        assert q.dims == ("free_decay__time", "free_decay__dof")
        assert q.shape == (summary["free_decay"]["n_steps"] + 1, 1)
        assert q.attrs["units"] == "m"
        assert float(q[0, 0]) == 1.0e-3
        np.testing.assert_allclose(ds["free_decay__damping_ratio"].values,
                                   summary["free_decay"]["damping_ratio"], rtol=1e-12)
        assert "forced_response__slider_f" in ds
        assert ds["hysteresis__loop_energy"].dims == ("hysteresis__contact",
                                                      "hysteresis__amplitude")
        assert "[[contacts]]" in ds.attrs["case_toml"]


class _TagChecker(html.parser.HTMLParser):
    VOID = {"meta", "img", "br", "hr", "link", "input"}

    def __init__(self):
        super().__init__()
        self.stack, self.errors, self.images = [], [], []

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.images.append(dict(attrs))
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"unexpected </{tag}> with open {self.stack[-3:]}")
        else:
            self.stack.pop()


def test_report_html(run_dir, summary):
    out = run_dir[0]
    text = (out / "report.html").read_text(encoding="utf-8")
    checker = _TagChecker()
    checker.feed(text)
    assert not checker.errors and not checker.stack, (checker.errors, checker.stack)
    srcs = [img["src"] for img in checker.images]
    assert srcs == summary["files"]["figures"]
    assert all(img["alt"] for img in checker.images)
    # the case file is shown verbatim (escaped), the key numbers are there
    assert "[[contacts]]" in text and "name = &quot;one_dof&quot;" in text
    assert "natural frequencies stuck [Hz]" in text
    assert "dissipated energy per cycle [J]" in text


def test_npz_format_and_default_out_dir(cli, write_case, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = cli("run", write_case(HYSTERESIS_ONLY), "--format", "npz")
    assert code == 0, err
    out_dir = tmp_path / "fricdamp-out" / "loops_only"
    summary = json.loads((out_dir / "summary.json").read_text())
    assert summary["files"]["results"] == "results.npz"
    from fricdamp.iofiles import read_results

    ds = read_results(out_dir / "results.npz")
    np.testing.assert_allclose(ds["hysteresis__loop_energy"].values[0],
                               summary["hysteresis"]["contacts"]["contact1"]["loop_energy_J"])
    # static/kinetic Coulomb closed form (runner.coulomb_loop_energy, checked against the law
    # in test_cli_registry): the sampled break-away drop costs O(1/2000) relative
    assert summary["hysteresis"]["max_closed_form_error"] < 2e-3


def test_solver_failure_exit_1_writes_nothing(cli, write_case, base_case, tmp_path):
    """One Newton iteration per step cannot follow the stick-slip transition."""
    path = write_case(base_case + "\n[solver]\nmax_iter = 1\n")
    code, out, err = cli("run", path, "--out", tmp_path / "out")
    assert code == 1
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert "the solver failed: [analysis.free_decay] Newton did not converge" in err
    assert not (tmp_path / "out").exists()


def test_progress_only_on_a_terminal_outside_ci(monkeypatch):
    import sys

    monkeypatch.delenv("CI", raising=False)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    assert _progress_wanted(False) is True
    assert _progress_wanted(True) is False  # --no-progress
    monkeypatch.setenv("CI", "true")
    assert _progress_wanted(False) is False
    monkeypatch.delenv("CI")
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False, raising=False)
    assert _progress_wanted(False) is False
