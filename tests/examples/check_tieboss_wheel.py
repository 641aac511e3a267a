"""Physical check of examples/cases/tieboss_wheel.toml (paper 003, issue 7).

References computed here, independently of the case's analyses:

* Paper 003 Table 1 (FEM column, typed in below from the paper): the open-contact first
  family by nodal diameter (ND) within 1 % of each pair's mean (the model is tuned to it).
* The assembled full wheel (2880 DOFs, contacts open), solved here by ARPACK
  (``scipy.sparse.linalg.eigsh``, shift-invert) with the ND of each mode found by a discrete
  Fourier transform of the probe displacement over the 30 blades: the same frequencies as the
  case's cyclic-symmetry analysis of one sector (a different path: no complex cyclic
  constraint), to 1e-6.
* The same wheel with every contact closed and stuck (the penalties ``k_n, k_t, k_t`` in the
  contact frames added through the contacts' projection): the frequency of a friction-damped
  free decay lies between the open (slipping, separating) and the stuck frequencies of its ND.
* 003 (1): ``s = 60 f / (p o)`` recomputed from each reported frequency; Table 2's measured
  critical speeds (334 rpm for o = 1, 2ND; 123 rpm for o = 3, 6ND) within 2 %; and each
  critical frequency on its ND branch of the Campbell diagram.
* Southwell: stress stiffening and spin softening both scale with Omega^2, so every branch
  rises with speed and ``f^2`` is (to first order) linear in ``Omega^2``.
* The log decrement recomputed from the reported envelope peaks,
  ``delta = ln(A_first / A_last) / cycles``, ``zeta = delta / sqrt(4 pi^2 + delta^2)``.
* Paper 003 section 3.2: 6ND damped more than 2ND; ratios "1.2 % for 2ND and 2.2 % for 6ND"
  (compared to within a factor 1.5: our beam model is tuned to Table 1 only, the paper's
  89,000-element model and rig are not published); an almost linear (Coulomb-like) decay;
  contacts in slip and near-contact (open) states (Figs 17-18); prestress 2.4 N from the
  offset 1e-5 m (section 2.4).
* DOF counts from the mesh of the case: (n_hub_elements + n_blade_elements + 4) free nodes of
  6 DOFs per sector, less the 6 of the right cut; Craig-Bampton keeps 15 per sector (left cut
  6, two contact nodes and the tie-boss, 3 each) plus the modes.
"""

from __future__ import annotations

import math
from dataclasses import fields

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

#: 003 Table 1, FEM column [Hz] (split pairs), and the limit quoted for 15ND.
TABLE1_FEM = {2: (44.32, 44.39), 3: (46.14, 46.20), 4: (47.37, 47.42), 5: (48.10, 48.22),
              6: (48.54, 48.58), 15: (50.3,)}
#: 003 Table 2: critical speed [rpm] and resonance frequency [Hz] by (order, ND).
TABLE2 = {(1, 2): (334.0, 44.53), (3, 6): (123.0, 49.20)}
#: 003 section 3.2: damping ratios from the log decrement of the FEM envelopes.
PAPER_ZETA = {2: 0.012, 6: 0.022}


def _wheel(model: dict):
    """The full wheel of the case's [model] table (every default filled in)."""
    from fricdamp.models.tieboss_wheel import TiebossWheelParameters, build_sector, build_wheel

    kw = {f.name: model[f.name] for f in fields(TiebossWheelParameters)}
    kw["damping_band_hz"] = tuple(kw["damping_band_hz"])
    return build_wheel(build_sector(TiebossWheelParameters(**kw), rotation=False))


def _frequencies_by_nd(wheel, K, n_modes: int) -> dict[int, float]:
    """Lowest frequency [Hz] of each ND of (K, M) on the assembled wheel: eigsh, then the ND
    of each mode from the DFT over the blades of the probe displacement."""
    M = wheel.system.M
    lam, X = eigsh(sp.csc_matrix(K), k=n_modes, M=sp.csc_matrix(M), sigma=0.0, which="LM")
    N = wheel.n_blades
    probes = np.stack([wheel.group_dofs("probe", j) for j in range(N)])      # (N, 3)
    d = wheel.sector.flexural_direction
    out: dict[int, float] = {}
    for i in np.argsort(lam):
        x = X[probes, i] @ d                                                  # (N,)
        power = np.abs(np.fft.fft(x)) ** 2
        folded = [power[k] + (power[N - k] if 0 < k < N - k else 0.0) for k in range(N // 2 + 1)]
        nd = int(np.argmax(folded))
        assert folded[nd] > 0.99 * sum(folded), (i, folded)                  # one ND per mode
        out.setdefault(nd, math.sqrt(lam[i]) / (2 * math.pi))
    return out


def check(summary: dict, case: dict) -> None:
    """Assert the Table 1 frequencies, the critical speeds, the decays and the reduction."""
    mc = summary["case"]["model"]
    N = mc["n_blades"]
    wheel = _wheel(mc)
    p = wheel.parameters

    # ---- modal (contract): ND 0..15 and the first family
    modal = summary["modal"]
    assert modal["nd"] == list(range(N // 2 + 1)) == list(range(16))
    f_open = np.asarray(modal["frequency_hz"])
    assert f_open.shape == (16,)
    for nd, pair in TABLE1_FEM.items():                   # 003 Table 1, 1 % (issue 7)
        assert f_open[nd] == pytest.approx(np.mean(pair), rel=0.01), nd
    # the assembled wheel, solved directly: same frequencies (ARPACK tolerance ~1e-10; 1e-6)
    full_open = _frequencies_by_nd(wheel, wheel.system.K, 2 * N + 4)
    assert sorted(full_open) == modal["nd"]
    np.testing.assert_allclose([full_open[k] for k in modal["nd"]], f_open, rtol=1e-6)
    # the first family rises with the ND towards the blade-alone limit (Table 1's trend)
    assert np.all(np.diff(f_open) > 0)

    # ---- stuck contacts: the penalties in the contact frames through the projection
    c = wheel.system.contacts[0]
    P = sp.csr_matrix(c.projection)
    kc = sp.diags(np.tile([p.normal_stiffness_N_per_m, p.tangential_stiffness,
                           p.tangential_stiffness], c.n_contacts))
    stuck = _frequencies_by_nd(wheel, wheel.system.K + P.T @ kc @ P, 2 * N + 4)

    # ---- Campbell and critical speeds, 003 (1)
    camp = summary["campbell_by_nd"]
    rpm = np.asarray(camp["rpm"])
    F = np.asarray(camp["frequency_hz"])                  # (nd, speed)
    assert np.all(np.diff(F, axis=1) > 0)                 # stress stiffening wins
    w2 = (rpm * np.pi / 30) ** 2
    # Southwell: f^2 linear in Omega^2 to first order. The second-order term (the mode
    # changing with speed) is ~ the f^2 rise over the gap to the second family, 0.07 / 3 ~
    # 2 % of the rise; a quadratic fitted by a line leaves 1/8 of it: tolerance 3e-3
    for row in F:
        fit = np.polyfit(w2, row ** 2, 1)
        assert np.max(np.abs(np.polyval(fit, w2) - row ** 2)) < 3e-3 * np.ptp(row ** 2)
    crit = summary["critical_speeds_rpm"]
    pulses = case["analysis"]["campbell_by_nd"]["pulses"]
    assert {(e["order"], e["nd"]) for e in crit} == set(TABLE2)
    for e in crit:
        o, f, s = e["order"], e["frequency_hz"], e["rpm"]
        assert s == pytest.approx(60.0 * f / (pulses * o), rel=1e-12)          # 003 (1)
        # on its branch: linear interpolation between speeds ~10 rpm apart, the branch's
        # curvature (~1.5 Hz over 390 rpm, quadratic) errs by < 1e-4 Hz; tolerance 1e-3 Hz
        assert f == pytest.approx(np.interp(s, rpm, F[e["nd"]]), abs=1e-3)
        s_paper, f_paper = TABLE2[(o, e["nd"])]
        # 003 Table 2 (measured on the rig): the model is tuned to the FEM column of Table 1
        # (2ND 0.4 % below the rotating test's 44.53 Hz): 2 %
        assert s == pytest.approx(s_paper, rel=0.02), e
        assert e["paper_rpm"] == s_paper

    # ---- free attenuations (contract)
    fa = case["analysis"]["free_attenuation"]
    decay = summary["decay"]
    assert [d["nd"] for d in decay] == fa["nodal_diameters"] == [2, 6]
    zeta = {}
    for d in decay:
        nd = d["nd"]
        assert {"damping_ratio", "initial_amplitude_m", "runtime_s"} <= set(d)
        # the secant iteration of the static solution holds the amplitude to 1 %
        assert d["initial_amplitude_m"] == pytest.approx(fa["amplitude_m"], rel=0.01)
        # the log decrement, recomputed from the envelope (same numbers: 1e-10)
        a, cyc = np.asarray(d["envelope_m"]), np.asarray(d["envelope_cycles"])
        tt = np.asarray(d["envelope_time_s"])
        delta = math.log(a[0] / a[-1]) / (cyc[-1] - cyc[0])
        assert d["damping_ratio"] == pytest.approx(delta / math.hypot(2 * math.pi, delta),
                                                   rel=1e-10)
        assert d["frequency_hz"] == pytest.approx((cyc[-1] - cyc[0]) / (tt[-1] - tt[0]),
                                                  rel=1e-10)
        # friction-damped: between the open and the stuck frequencies of the ND
        assert full_open[nd] < d["frequency_hz"] < stuck[nd], (nd, d["frequency_hz"])
        # 003 Table 2 resonances with prestressed contacts (44.53, 49.20 Hz): 2 %
        f_r = {2: TABLE2[(1, 2)][1], 6: TABLE2[(3, 6)][1]}[nd]
        assert d["frequency_hz"] == pytest.approx(f_r, rel=0.02)
        # friction, not the 0.1 % material damping, is what damps (factor 5)
        assert d["damping_ratio"] > 5 * mc["damping_ratio"]
        # 003 section 3.2 "to the order" (module doc): factor 1.5
        assert PAPER_ZETA[nd] / 1.5 < d["damping_ratio"] < 1.5 * PAPER_ZETA[nd], d
        assert d["envelope_model"] == "coulomb"           # almost linear decay (003 Fig. 19)
        fr = d["state_fractions"]
        assert sum(fr.values()) == pytest.approx(1.0, abs=1e-12)
        assert fr["slip"] > 0.3 and fr["open"] > 0.05 and fr["stick"] > 0.01   # Figs 17-18
        assert d["normal_force_rest_N"] == pytest.approx(2.4, rel=0.01)        # 003 sec. 2.4
        assert d["energy_balance_error"] < 1e-3
        zeta[nd] = (d["damping_ratio"], d["damping_ratio_modal_forcing"])
    # 003: "a higher damping effect ... on the mode with a higher number of ND", whatever the
    # start (the paper's tie-boss forces or a pure-mode start)
    assert zeta[6][0] > 1.5 * zeta[2][0] and zeta[6][1] > 1.5 * zeta[2][1]
    assert summary["model"]["prestress_normal_force_N"] == pytest.approx(2.4, rel=0.01)

    # ---- full order vs Craig-Bampton (contract)
    red = summary["reduction"]
    per_sector = (mc["n_hub_elements"] + mc["n_blade_elements"] + 4) * 6 - 6
    n_modes = case["analysis"]["reduction_comparison"]["n_modes"]
    assert red["full_dof"] == N * per_sector == wheel.n_dof == 2880
    assert red["reduced_dof"] == N * (15 + n_modes)
    # CB with 10 fixed-interface modes keeps the first family to ~1e-4 (tests of the
    # reduction); the friction decays then agree far better than the 5 %: 1 %
    assert red["damping_ratio_difference"] <= 0.01
    assert red["max_signal_difference"] < 0.01
    assert red["damping_ratio_full"] == pytest.approx(
        next(d for d in decay if d["nd"] == red["nd"])["damping_ratio"], rel=0.01)
    assert red["speed_ratio"] > 3.0
