"""Engine-order content of the electromagnet rig of paper 003 (models/tieboss_excitation).

References, independent of engine_order_content's 2D DFT:

1. Stationary pattern (magnets always on): blade j sees ``G(theta + j alpha)``, so each
   revolution harmonic n is a single wave of ND ``k = -n (mod N)`` whose amplitude is the
   harmonic G_n of blade 0's own force history (a 1D FFT): equal to 1e-12, and nothing at
   any other ND (the classical ZZENF rule: o = 1 -> 8ND, o = 3 -> 6ND for p = 8, N = 30).
2. Rotor-synchronous pulses (the rig): with opposite magnets paired, every pulse pulls the
   blades facing the firing pair, so the pattern repeats after 15 blades: odd-ND content
   vanishes (1e-12 of the largest) and only harmonics n = p o (p = 8) remain; with one
   trigger case per pair the pulse train is not 45-degree periodic and the odd harmonics
   appear (the closed-form sum over the four pulse instants).
3. Table 2 selection logic: with a branch function whose 2ND and 6ND frequencies are
   Table 2's (44.53 Hz, 49.2 Hz) the crossings are exactly 003 (1)'s 334 and 123 rpm.
"""

import numpy as np
import pytest

from fricdamp.models.tieboss_wheel.excitation import (
    ElectromagnetRig,
    engine_order_content,
    engine_order_map,
    stationary_alias_nd,
)


def test_stationary_pattern_is_the_zzenf_rule():
    rig = ElectromagnetRig(synchronous=False)
    f = rig.forces(720)
    c = engine_order_content(f)
    N = 30
    G = np.fft.fft(f[:, 0]) / f.shape[0]
    top = np.abs(c).max()
    for n in range(1, 40):
        k = (-n) % N
        assert abs(c[n, k] - G[n]) < 1e-12 * top
        others = np.delete(np.abs(c[n]), k)
        assert others.max() < 1e-12 * top
    assert [stationary_alias_nd(8 * o, N) for o in (1, 2, 3)] == [8, 14, 6]
    for e in engine_order_map(rig):
        assert e["excited_nds"] == [stationary_alias_nd(e["harmonic"], N)]


def test_synchronous_pulses_excite_even_nds_at_p_o_only():
    rig = ElectromagnetRig()
    assert rig.pulses_per_rev == 8
    c = np.abs(engine_order_content(rig.forces(1440)))
    top = c.max()
    assert c[:, 1::2].max() < 1e-12 * top                    # no odd ND
    for n in range(1, 60):
        if n % 8:
            assert c[n].max() < 1e-12 * top, n               # only n = 8 o
        else:
            assert c[n, 2] > 0.1 * c[n].max()
    # one case per pair ("15" only): 4 pulses at 0, 45, 90, 135 degrees, none in the other
    # half turn: sum_m exp(-i n m pi / 4) vanishes for even n not multiple of 8 and not for
    # odd n, so odd revolution harmonics appear; still even NDs only (blades 0 and 15)
    one_case = ElectromagnetRig(both_cases=False)
    c4 = np.abs(engine_order_content(one_case.forces(1440)))
    assert c4[1].max() > 0.1 * c4[8].max() and c4[4].max() < 1e-12 * c4.max()
    assert c4[:, 1::2].max() < 1e-12 * c4.max()


def test_table2_crossings_from_the_paper_frequencies():
    f = {2: 44.53, 6: 49.20}
    emap = engine_order_map(branch_hz=lambda k, rpm: f.get(k, 47.0 + 0.1 * k),
                            measured_rpm={1: 334.0, 3: 123.0}, orders=(1, 3))
    assert emap[0]["crossing_rpm"]["2"] == pytest.approx(60 * 44.53 / 8, rel=1e-9)
    assert emap[1]["crossing_rpm"]["6"] == pytest.approx(60 * 49.2 / 24, rel=1e-9)
    assert [e["nd"] for e in emap] == [2, 6]
