"""The registry: new analyses, model types and contact laws without touching the CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.linalg as sla

from fricdamp.case import Section
from fricdamp.contact.coulomb import Coulomb
from fricdamp.runner import (
    REGISTRY,
    AnalysisOutput,
    Registry,
    coulomb_loop_energy,
    jenkins_loop_energy,
)


class Modes(Section):
    count: int = 1


def run_modes(system, spec, ctx):
    """Undamped natural frequencies of the linear part (contacts left out)."""
    import xarray as xr

    M, K = np.asarray(system.M), np.asarray(system.K)
    f = np.sqrt(sla.eigh(K, M, eigvals_only=True)) / (2 * np.pi)
    f = f[: spec.count]

    def figures():
        from fricdamp import plot

        fig, axes = plot.new_figure(title="modes")
        axes[0, 0].plot(np.arange(f.size), f, "o")
        return [("modes.png", "natural frequencies", fig)]

    return AnalysisOutput(summary={"frequencies_hz": f},
                          arrays={"frequency": xr.DataArray(f, dims="mode")},
                          figures=figures, headline=f"{f.size} modes")


PLUGIN_CASE = """\
[model]
type = "chain"
masses_kg = [1.0, 1.0]
springs_N_per_m = [100.0, 100.0]

[analysis.modes]
count = 2
"""


@pytest.fixture
def with_modes(monkeypatch):
    monkeypatch.setattr(REGISTRY, "analyses", dict(REGISTRY.analyses))
    REGISTRY.register_analysis("modes", Modes, run_modes)


def test_plugin_analysis_runs_through_the_cli(with_modes, cli, write_case, tmp_path):
    path = write_case(PLUGIN_CASE)
    code, out, err = cli("run", path, "--out", tmp_path / "out")
    assert code == 0, err
    assert "modes: 2 modes" in out
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    # chain of two unit masses and springs: w^2 = (3 -+ sqrt 5)/2 * k/m
    w2 = np.array([(3 - 5**0.5) / 2, (3 + 5**0.5) / 2]) * 100.0
    np.testing.assert_allclose(summary["modes"]["frequencies_hz"], np.sqrt(w2) / (2 * np.pi),
                               rtol=1e-12)
    assert summary["energy_balance_error"] is None  # no analysis reports one
    assert (tmp_path / "out" / "modes.png").is_file()
    # the plugin's schema is strict like the built-in ones
    code, _, err = cli("check", write_case(PLUGIN_CASE.replace("count", "cuont")))
    assert code == 2 and "unknown key 'cuont' in [analysis.modes]" in err


def test_registration_rules():
    reg = Registry()
    reg.register_analysis("modes", Modes, run_modes)
    with pytest.raises(ValueError, match="already registered"):
        reg.register_analysis("modes", Modes, run_modes)
    reg.register_analysis("modes", Modes, run_modes, replace=True)
    with pytest.raises(ValueError, match="identifier"):
        reg.register_model("my model", Modes, run_modes)
    with pytest.raises(TypeError, match="pydantic"):
        reg.register_contact("law", dict, run_modes)
    with pytest.raises(ValueError, match="reserved"):
        reg.register_analysis("model", Modes, run_modes)


def test_other_commands_tables_are_ignored_by_run(cli, write_case, base_case):
    """[sweep] and [optimize] belong to fricdamp sweep / optimize; run and check accept them."""
    text = base_case + '\n[sweep.grid]\nmu = [0.1, 0.2]\n\n[optimize]\nminimize = "x"\n'
    code, out, err = cli("check", write_case(text))
    assert code == 0, err


@pytest.mark.parametrize("mus, mud", [(0.3, 0.3), (0.3, 0.2), (0.4, 0.1)])
def test_coulomb_closed_form_against_the_law(mus, mud):
    """Closed form of the static/kinetic slider (runner.coulomb_loop_energy, derived there)
    against the law's own loop at 8000 samples per cycle. The break-away drop from mu_s N
    to mu_d N falls between samples: a first-order error of at most
    (mu_s - mu_d) N du / W with du = 2 pi A / 8000; tolerance 2e-3. mu_s = mu_d must equal
    the Jenkins form to round-off."""
    from fricdamp.contact import Jenkins
    from fricdamp.signals.energy import loop_area

    kt, N = 1.0e5, 10.0
    law = Coulomb(kt, N, mus, mud)
    A = np.array([2e-5, 4e-5, 1e-4, 1e-3])
    n = 8000
    theta = np.linspace(0.0, 4 * np.pi, 2 * n + 1)
    W = np.array([loop_area((a * np.sin(theta))[n:], law.drive(a * np.sin(theta))[n:])
                  for a in A])
    Wc = coulomb_loop_energy(law, A)[0]
    np.testing.assert_allclose(W, Wc, rtol=2e-3, atol=1e-12)
    if mus == mud:
        np.testing.assert_allclose(Wc, jenkins_loop_energy(Jenkins(kt, mus * N), A)[0],
                                   rtol=1e-12)
    assert coulomb_loop_energy(Coulomb(kt, N, mus, mud, decay=1.0), A) is None


CONTACT3D_CASE = """\
[model]
type = "chain"
masses_kg = [1.0, 1.0]
springs_N_per_m = [1.0e4, 1.0e4]

[[contacts]]
type = "contact3d"
name = "tip"
normal = [1]
tangential = [[2, 1]]
normal_stiffness_N_per_m = 2.0e4
tangential_stiffness_N_per_m = 5.0e3
mu = 0.5
preload_N = 4.0

[analysis.hysteresis]
amplitudes_m = [1.0e-3]
"""


def test_contact3d_projection_and_stuck_stiffness(cli, write_case):
    """Stuck contact3d adds k_n e_n e_n^T + k_t e_t e_t^T with e_n = e_1, e_t = e_2 - e_1."""
    from fricdamp.runner import build_system, load_case

    text = CONTACT3D_CASE.replace("[analysis.hysteresis]\namplitudes_m = [1.0e-3]\n",
                                  "[analysis.free_decay]\ninitial_displacement_m = [0.0, 1e-3]"
                                  "\nduration_s = 0.1\ntime_step_s = 1e-3\n")
    system = build_system(load_case(write_case(text)))
    P = np.asarray(system.contacts[0].projection)
    np.testing.assert_array_equal(P, [[1, 0], [-1, 1], [0, 0]])
    from fricdamp.runner import describe_system

    K = np.array([[2e4, -1e4], [-1e4, 1e4]])
    Kc = K + 2e4 * np.outer([1, 0], [1, 0]) + 5e3 * np.outer([-1, 1], [-1, 1])
    f = np.sqrt(sla.eigh(Kc, np.eye(2), eigvals_only=True)) / (2 * np.pi)
    np.testing.assert_allclose(describe_system(system)["natural_frequencies_stuck_hz"], f,
                               rtol=1e-12)
    # the hysteresis analysis drives one-directional laws only, and says so
    code, _, err = cli("check", write_case(CONTACT3D_CASE))
    assert code == 2
    assert "one-directional contact" in err
    code, _, err = cli("check", write_case(CONTACT3D_CASE + 'contacts = ["tip"]\n'))
    assert code == 2 and "'tip' has 3 directions" in err
