"""Report tables: engineering results before solver diagnostics, damping ratios in % (as in
the figures), round-off of a zero shown as 0."""

from __future__ import annotations

import re

from fricdamp.report import render_report

SUMMARY = {
    "case": {"name": "x", "analysis": {"free_decay": {}}},
    "energy_balance_error": 1e-9,
    "model": {"n_dof": 2, "natural_frequencies_stuck_hz": [1.0, 2.0]},
    "free_decay": {
        "energy_balance_error": 1e-8, "n_steps": 100, "mean_damping_ratio": 0.0123,
        "damping_ratio_definition": "log decrement",
        "amplitude_m": [1e-3, 5e-4, 2e-4, 1e-4], "damping_ratio": [0.01, 0.012, 0.013, 0.014],
        "contact_work_J": [1.0, 1.694e-21, 0.5, 0.2]},
}


def _text(html: str) -> str:
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))


def test_engineering_first_percent_and_roundoff():
    text = _text(render_report(summary=SUMMARY, case_text="", figures={}))
    key = text[text.index("Key numbers"):text.index("Free decay")]
    # the model before the solver's energy balance
    assert key.index("natural frequencies stuck [Hz]") < key.index("energy balance error")
    assert key.index("n dof") < key.index("energy balance error")
    decay = text[text.index("Free decay"):]
    assert decay.index("mean damping ratio [%] 1.23 ") < decay.index("energy balance error")
    assert decay.index("damping ratio definition log decrement") < decay.index("n steps")
    assert "damping ratio definition [%]" not in decay        # a text, not a ratio
    # the column table: ratios in %, the round-off of a zero as 0
    assert "damping ratio [%]" in decay and " 1.2 " in decay and " 1.4 " in decay
    assert "e-21" not in decay and " 0.0005 1.2 0 " in decay


def test_damping_vs_amplitude_uses_a_log_axis_over_decades():
    """Amplitudes over three decades (a nonlinear mode from micro-slip to gross slip): log
    amplitude axis; over a factor 2 (a short decay): linear."""
    import numpy as np

    from fricdamp import plot

    zeta, f = np.linspace(0.01, 0.1, 10), np.linspace(100.0, 90.0, 10)
    fig = plot.damping_vs_amplitude(np.geomspace(1e-6, 1e-3, 10), zeta, f)
    assert [ax.get_xscale() for ax in fig.axes] == ["log", "log"]
    fig = plot.damping_vs_amplitude(np.linspace(1e-3, 2e-3, 10), zeta, f)
    assert fig.axes[0].get_xscale() == "linear"
    assert fig.axes[0].get_ylabel() == "damping ratio [%]"


def test_beam_dof_names_are_spelled_out_in_labels():
    from fricdamp.plot import dof_label

    assert dof_label("w8") == "w8 (z-displacement of node 8)"
    assert dof_label("theta3") == "theta3 (rotation about y of node 3)"
    assert dof_label("blade 1") == "blade 1" and dof_label("q1") == "q1"
