"""The contact-wheel pipeline (models/contact_wheel.py) against the beam wheel's own.

The beam sector of paper 003 is a WheelSector with one node pair per patch (a patch of
area A = 1 m^2 and element size h = 1 m with E = k_n, so factor E A / h is the beam's
calibrated penalty). Keeping every cut DOF as an interface mode, the reduced wheel is the
Craig-Bampton wheel of ``build_wheel(n_modes=10)``; its modes come sector by sector and
the transient from the modal engine, but the discrete equations are the same: the damping
signals agree to 1e-6 of the amplitude (Newton tolerance 1e-10 per step, accumulated) and
the damping ratios to 1e-4 (the envelope's interpolated peaks amplify the signal difference
~10x; the ratio itself is 0.68 %).
"""

from dataclasses import replace

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.contact_wheel import ContactSettings, WheelSector, build_contact_wheel
from fricdamp.models.tieboss_wheel.model import build_sector, build_wheel
from fricdamp.models.tieboss_wheel.studies import free_decay
from fricdamp.structure.contact_patch import ContactPatch


@pytest.fixture(scope="module")
def beam():
    sec = build_sector(rotation=False)
    p = sec.parameters
    named = dict(sec.cyclic.named_dofs)
    named.pop("tip", None)
    named["load"] = named.pop("tieboss")
    patch = ContactPatch(right=np.arange(1), left=np.arange(1), positions=np.zeros((1, 3)),
                         frames=sec.frame[None], areas=np.ones(1), element_size=1.0,
                         sector_angle=2 * np.pi / 30)
    ws = WheelSector(replace(sec.cyclic, named_dofs=named), patch, p.normal_stiffness_N_per_m,
                     sec.flexural_direction, rayleigh=p.rayleigh())
    settings = ContactSettings(tangential_ratio=p.tangential_stiffness
                               / p.normal_stiffness_N_per_m)
    return sec, ws, settings


def test_cyclic_rows_equal_the_dense_rows(beam):
    """Contact rows by harmonic (FFT over sectors) = the dense rows of the wheel modes."""
    sec, ws, settings = beam
    cw = build_contact_wheel(ws, n_modes=4, n_interface_modes=6)
    rows = cw.basis.rows
    G = cw.modes.group_shapes
    dense = ws.patch.wheel_rows(G("contact_right"), G("contact_left"))
    np.testing.assert_allclose(rows.dense(), dense, atol=1e-12 * np.abs(dense).max())
    rng = np.random.default_rng(0)
    f = rng.standard_normal(dense.shape[0])
    np.testing.assert_allclose(rows.rows_T(f), dense.T @ f, atol=1e-10 * np.abs(dense.T @ f).max())
    s = 1.0 / cw.basis.omega2
    C = rows.compliance(s)
    ref = (dense * s) @ dense.T
    np.testing.assert_allclose(C.dense(), ref, atol=1e-12 * np.abs(ref).max())
    np.testing.assert_allclose(C.diagonal_block(slice(0, 3)), ref[:3, :3],
                               atol=1e-12 * np.abs(ref).max())
    k = np.tile([1e5, 2e5, 3e5], 30)
    x = C.chord(k, 1.0)(f)
    np.testing.assert_allclose(x + ref @ (k * x), f, atol=1e-10)


def test_pipeline_equals_the_beam_wheel(beam):
    sec, ws, settings = beam
    cw = build_contact_wheel(ws, n_modes=10, n_interface_modes=sec.cyclic.left.size)
    assert cw.reduced_dof == 750
    # the calibrated offset recovers the paper's 1e-5 m for which k_n was calibrated (2.4 N)
    off, rest = cw.calibrate_offset(settings)
    assert off == pytest.approx(1e-5, rel=2e-3)
    np.testing.assert_allclose(cw.normal_force_per_contact(rest), 2.4, rtol=1e-3)
    run = cw.free_decay(2, amplitude_m=5e-4, duration_s=0.05, dt=1e-5, settings=settings,
                        offset=1e-5, save_every=5, progress=False)
    ref = free_decay(build_wheel(sec, n_modes=10), 2, amplitude_m=5e-4, duration_s=0.05,
                     dt=1e-5, save_every=5)
    assert run.damping_ratio == pytest.approx(ref.damping_ratio, rel=1e-4)
    n = min(ref.t.size, run.t.size)
    assert np.abs(ref.signal[:n] - run.signal[:n]).max() < 1e-6 * abs(ref.signal[0])
    assert run.energy_balance_error == pytest.approx(ref.energy_balance_error, abs=1e-6)
    assert sum(run.state_fractions.values()) == pytest.approx(1.0)
    assert run.status.shape[1:] == (30, 1)
    assert run.summary()["nd"] == 2


def test_damping_converges_with_the_interface_modes(beam):
    """Interface modes of the beam's cut (6 DOFs: a rim node's displacement and rotation):
    2 modes are 15-25 % off the 6-mode (= plain Craig-Bampton) damping, 4 modes within
    1 % (measured 0.3 %) for both NDs -- the cut's stiff modes (> 7 kHz) barely matter."""
    sec, ws, settings = beam
    kw = {"amplitude_m": 5e-4, "duration_s": 0.05, "dt": 2e-5, "settings": settings,
          "offset": 1e-5, "save_every": 2, "progress": False}
    z = {n: [build_contact_wheel(ws, n_modes=10, n_interface_modes=n).free_decay(nd, **kw)
             .damping_ratio for nd in (2, 6)] for n in (2, 4, 6)}
    err = {n: np.abs(np.asarray(z[n]) / np.asarray(z[6]) - 1.0) for n in (2, 4)}
    assert np.all(err[4] < 0.01)
    assert np.all(err[2] > err[4])


def test_bad_input(beam):
    sec, ws, settings = beam
    with pytest.raises(ModelError, match="penalty_factor"):
        ContactSettings(penalty_factor=0.0)
    with pytest.raises(ModelError, match="mu_sliding"):
        ContactSettings(mu_static=0.2, mu_sliding=0.4)
    bad = dict(ws.cyclic.named_dofs)
    bad.pop("probe")
    with pytest.raises(ModelError, match="probe"):
        WheelSector(replace(ws.cyclic, named_dofs=bad), ws.patch, 1.0, [0, 0, 1.0])
