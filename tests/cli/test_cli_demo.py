"""``fricdamp demo``, the command's surface, import hygiene and the case documentation."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla

from fricdamp import case as case_module
from fricdamp.runner import REGISTRY, load_builtin_case

ROOT = Path(__file__).resolve().parents[2]


def test_demo_runs_and_prints_the_report(cli, tmp_path):
    """The demo: two identical blades (m = 0.2 kg, k = 1e5 N/m to ground, 2e3 N/m between
    them) with a Jenkins damper (k_t = 5e4 N/m, F_s = 2 N) on q1 - q2, released out of phase.

    Once the damper sticks the out-of-phase mode has w^2 = (k + 2 k_c + 2 k_t) / m and the
    modal damping of the dashpots c = 0.2 N s/m to ground, zeta = c / (2 m w). Checks: the
    last decay frequency against w / (2 pi) (Newmark period error (w h)^2/12 = 1.3e-4:
    tolerance 1e-3) and the last damping ratios against zeta (the peak interpolation and the
    equilibrium estimate are good to ~1 % of this tiny 0.05 %: tolerance 3 %).
    """
    out = tmp_path / "demo"
    code, stdout, err = cli("demo", "--out", out)
    assert code == 0, err
    assert f"report: {(out / 'report.html').resolve()}" in stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["case"]["name"] == "demo"
    m, k, kc, kt, c = 0.2, 1.0e5, 2.0e3, 5.0e4, 0.2
    w = math.sqrt((k + 2 * kc + 2 * kt) / m)
    fd = summary["free_decay"]
    assert fd["frequency_hz"][-1] == pytest.approx(w / (2 * math.pi), rel=1e-3)
    np.testing.assert_allclose(fd["damping_ratio"][-6:], c / (2 * m * w), rtol=3e-2)
    assert fd["max_damping_ratio"] > 0.1  # friction damping of the slipping phase
    assert summary["forced_response"]["steady_state_change"] < 1e-3
    assert summary["hysteresis"]["max_closed_form_error"] < 1e-4
    # harmonic balance FRF (H = 7) of the same 2 N out-of-phase load: at 125 Hz it agrees
    # with the time-domain forced response (Newmark, 64 steps per period: period error 8e-4;
    # tolerance 1 %); its nonlinear mode 2 starts at the stuck frequency w / (2 pi) (linear
    # while stuck: 1e-9) and passes through the FRF peak (phase resonance of a lightly
    # viscous system: 1 %)
    frf = summary["frf"]
    a_hb = np.interp(125.0, frf["frequency_hz"], frf["amplitude_m"])
    assert a_hb == pytest.approx(summary["forced_response"]["amplitude_m"][0], rel=1e-2)
    assert frf["backbone_frequency_hz"][0] == pytest.approx(w / (2 * math.pi), rel=1e-9)
    assert frf["backbone_frequency_at_peak_hz"] == pytest.approx(frf["peak_frequency_hz"],
                                                                 rel=1e-2)
    # stuck and free natural frequencies reported for the model
    M = np.diag([m, m])
    K = np.array([[k + kc, -kc], [-kc, k + kc]])
    f_free = np.sqrt(sla.eigh(K, M, eigvals_only=True)) / (2 * math.pi)
    np.testing.assert_allclose(summary["model"]["natural_frequencies_free_hz"], f_free,
                               rtol=1e-12)


def test_demo_case_is_packaged_and_valid():
    case = load_builtin_case("demo")
    assert set(case.analyses) == {"free_decay", "forced_response", "hysteresis", "frf"}
    assert "between = [1, 2]" in case.text


def test_version_help_and_usage_errors(cli):
    code, out, _ = cli("--version")
    assert code == 0 and out.startswith("fricdamp ")
    code, out, _ = cli("run", "--help")
    assert code == 0 and "--out" in out
    code, _, err = cli()
    assert code == 2 and "COMMAND" in err
    code, _, err = cli("run")
    assert code == 2 and "case" in err and "Traceback" not in err
    code, _, err = cli("frobnicate")
    assert code == 2 and "invalid choice" in err


def test_import_fricdamp_does_not_import_matplotlib():
    code = ("import sys, fricdamp, fricdamp.cli.app, fricdamp.runner, fricdamp.case, "
            "fricdamp.report, fricdamp.iofiles; fricdamp.cli.app._parser(); "
            "bad = [m for m in ('matplotlib', 'dask', 'xarray') if m in sys.modules]; "
            "assert not bad, bad")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_console_script_entry_point():
    from importlib.metadata import entry_points

    eps = [ep for ep in entry_points(group="console_scripts") if ep.name == "fricdamp"]
    assert eps and eps[0].value == "fricdamp.cli:main"


def _schemas():
    yield case_module.SolverSettings
    for table in (REGISTRY.models, REGISTRY.contacts, REGISTRY.analyses):
        for entry in table.values():
            if entry.schema is not None and entry.schema.__module__.startswith("fricdamp."):
                yield entry.schema


def test_docs_cover_every_key():
    """docs/cases.md documents every key of every built-in table (guards against drift)."""
    # docs/cases.md, plus one docs/cases_<model>.md per paper model
    text = "\n".join(p.read_text(encoding="utf-8")
                     for p in sorted((ROOT / "docs").glob("cases*.md")))
    missing = [f"{schema.__name__}.{key}" for schema in _schemas()
               for key in schema.model_fields if f"`{key}`" not in text]
    assert not missing, missing
    for name in list(REGISTRY.models) + list(REGISTRY.contacts):
        assert f'type = "{name}"' in text, name
    for name in REGISTRY.analyses:
        assert f"[analysis.{name}]" in text, name
