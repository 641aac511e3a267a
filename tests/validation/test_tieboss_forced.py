"""Tie-boss wheel forced-response helpers (models/tieboss_forced.py, models/tieboss_gap.py).

1. ``offset_for_prestress``: the offset it returns gives the requested prestress of the
   assembled wheel at rest (recomputed by ``prestress_normal_force``, an independent static
   solution) within 0.2 % for penalties 10x stiffer and softer than the calibrated one.
2. ``wheel_load`` and ``expand_to_wheel`` are the sector quantities repeated with the phase
   ``exp(-2 pi i nd j / N)`` of harmonic 1 and ``exp(-2 pi i h nd j / N)`` of harmonic h:
   checked entry by entry on blade 7 through ``group_dofs``.
3. Slow: halving the friction coefficient (constant mu_d instead of 003 (2)) lowers the
   damping ratio at 0.5 mm for both NDs (friction force, not the penalty, bounds the
   dissipation per cycle once the contacts slip).
"""

from dataclasses import replace

import numpy as np
import pytest

from fricdamp.models.tieboss_wheel.model import build_sector, build_wheel, prestress_normal_force


@pytest.mark.parametrize("factor", [0.1, 10.0])
def test_offset_for_prestress(factor):
    from fricdamp.models.tieboss_wheel.gap import offset_for_prestress

    sector = build_sector(rotation=False)
    p = sector.parameters
    kn = p.normal_stiffness_N_per_m * factor
    s = replace(sector, parameters=p.with_(normal_stiffness_N_per_m=kn,
                                           tangential_stiffness_N_per_m=kn))
    g0 = offset_for_prestress(s, 2.4)
    w = build_wheel(replace(s, parameters=s.parameters.with_(contact_offset_m=g0)), n_modes=4)
    assert prestress_normal_force(w) == pytest.approx(2.4, rel=2e-3)
    assert (g0 < p.contact_offset_m) == (factor > 1)


def test_wheel_load_and_expansion_phases():
    from fricdamp.models.tieboss_wheel.forced import (
        cyclic_problem,
        expand_to_wheel,
        wheel_load,
    )
    from fricdamp.solvers.cyclic_hb import cyclic_frequency_response

    sector = build_sector(rotation=False)
    pb, wheel = cyclic_problem(sector, 4, force_N=0.3, harmonics=2, samples=60)
    N, j = wheel.n_blades, 7
    ld = wheel_load(wheel, 4, 0.3)
    tb = wheel.group_dofs("tieboss", j)
    assert np.allclose(ld.amplitude[tb], 0.3 * sector.flexural_direction
                       * np.exp(-2j * np.pi * 4 * j / N), atol=1e-15)
    res = cyclic_frequency_response(pb, 2 * np.pi * 47.0, 2 * np.pi * 47.05, step=0.05)
    C = expand_to_wheel(res, wheel, 0)
    x = res.sector_harmonics[0][:, np.asarray(wheel.cyclic.named_dofs["tieboss"])]
    for h in (1, 2):
        ph = x[h] * np.exp(-2j * np.pi * h * 4 * j / N)
        assert np.allclose(C[tb, 2 * h - 1], ph.real, atol=1e-14)
        assert np.allclose(C[tb, 2 * h], -ph.imag, atol=1e-14)


@pytest.mark.slow
def test_lower_friction_lowers_damping_at_equal_amplitude():
    from fricdamp.models.tieboss_wheel.gap import damping_gap_study

    rows = damping_gap_study(build_sector(rotation=True), variants=["mu = 0.2"])
    base, low = rows[0]["zeta"], rows[1]["zeta"]
    for nd in ("2", "6"):
        assert low[nd] < 0.8 * base[nd], (nd, low, base)
