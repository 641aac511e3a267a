"""Universal File Format reader (fricdamp.signals.uff): files written with pyuff itself.

Round trips are exact for binary datasets and to the 12 significant digits of the ASCII
format (tolerance 1e-11 relative) otherwise.
"""

import numpy as np
import pytest

pyuff = pytest.importorskip("pyuff")

from fricdamp.errors import ModelError  # noqa: E402
from fricdamp.signals.identify import (  # noqa: E402
    JointRigGeometry,
    identify_from_table,
    identify_joint,
)
from fricdamp.signals.uff import read_signals_uff  # noqa: E402

F0 = 30.0
GEOM = JointRigGeometry(sensor_a=-0.09, sensor_b=0.0, joint_arm1=0.091, sensor_c=0.09,
                        joint_arm2=0.091, beam2_mass=0.44, beam2_inertia=1.55e-3)


def _readings(t):
    """Three accelerations [m/s^2] of a periodic motion (any consistent set will do)."""
    w = 2 * np.pi * F0
    th1 = -w * w * (1e-3 * np.sin(w * t) + 1e-4 * np.sin(3 * w * t + 0.3))
    th2 = -w * w * 0.8e-3 * np.sin(w * t - 0.2)
    x1 = -w * w * 1e-4 * np.sin(w * t + 0.4)
    return (x1 + GEOM.sensor_a * th1, x1 + GEOM.sensor_b * th1,
            x1 + GEOM.joint_arm1 * th1 + (GEOM.sensor_c + GEOM.joint_arm2) * th2)


def _series(name, node, data, t, *, binary=0, unit="m/s^2", time_unit="s", func_type=1):
    kw = dict(binary=binary, func_type=func_type, rsp_node=node, rsp_dir=1, ref_node=0,
              ref_dir=0, data=data, x=t, id1=name, rsp_ent_name="rig", ref_ent_name="rig",
              abscissa_spacing=1, abscissa_spec_data_type=17 if func_type == 1 else 18,
              ordinate_spec_data_type=12, orddenom_spec_data_type=0,
              abscissa_axis_units_lab=time_unit)
    if unit:
        kw["ordinate_axis_units_lab"] = unit
    return pyuff.prepare_58(**kw)


def _write(path, sets):
    u = pyuff.UFF(str(path))
    for ds in sets:
        u.write_sets(ds, mode="add")  # a fresh file (pyuff's "overwrite" mangles 58b)


@pytest.fixture
def signals():
    n_per, spp = 4, 200
    t = np.arange(n_per * spp) / (F0 * spp)
    return t, _readings(t)


def test_round_trip_and_identification(tmp_path, signals):
    t, (ga, gb, gc) = signals
    frf = pyuff.prepare_58(binary=0, func_type=4, rsp_node=9, rsp_dir=1, ref_node=1, ref_dir=1,
                           data=np.ones(5) + 1j, x=np.arange(5.0), id1="H",
                           abscissa_spacing=1, abscissa_spec_data_type=18,
                           ordinate_spec_data_type=12, orddenom_spec_data_type=13)
    path = tmp_path / "rig.uff"
    _write(path, [_series("acc A", 1, ga, t), _series("acc B", 2, gb / 9.80665, t, binary=1,
                                                      unit="g"),
                  frf, _series("acc C", 3, gc, t)])
    tab = read_signals_uff(path)
    assert list(tab) == ["time", "acc A", "acc B", "acc C"]  # the FRF is skipped
    assert tab.units == {"time": "s", "acc A": "m/s^2", "acc B": "g", "acc C": "m/s^2"}
    assert tab.channel_info["acc C"]["node"] == 3
    np.testing.assert_allclose(tab["time"], t, rtol=1e-11, atol=1e-15)
    np.testing.assert_allclose(tab["acc A"], ga, rtol=1e-11, atol=1e-11 * np.abs(ga).max())
    np.testing.assert_array_equal(tab["acc B"], gb / 9.80665)  # binary: bit for bit
    ref = identify_joint(t, ga, gb, gc, GEOM, frequency_hz=F0)
    got = identify_from_table(tab, GEOM, channels={"A": "acc A", "B": "acc B", "C": "acc C"},
                              frequency_hz=F0)
    assert got.dissipated_energy == pytest.approx(ref.dissipated_energy, rel=1e-8)
    assert not got.resampled  # the 6-digit increment was snapped back to 6000 Hz
    assert got.source == str(path)


def test_units_from_dataset_164_and_node_names(tmp_path, signals):
    """No unit label, millimetre units (length factor 1000): values in SI are the file's
    divided by 1000 (UFF 164). Duplicate ID lines: channels named by node and direction."""
    t, (ga, _, _) = signals
    units = pyuff.prepare_164(units_code=2, units_description="mm", temp_mode=1,
                              length=1000.0, force=1.0, temp=1.0, temp_offset=273.15)
    path = tmp_path / "mm.uff"
    _write(path, [units, _series("acc", 4, 1000 * ga, t, unit=""),
                  _series("acc", 5, 2000 * ga, t, unit="", binary=1)])
    tab = read_signals_uff(path)
    assert list(tab) == ["time", "node4+X", "node5+X"]
    assert tab.units["node4+X"] == "m/s^2"
    np.testing.assert_allclose(tab["node5+X"], 2 * ga, rtol=1e-12)


def test_time_in_milliseconds(tmp_path, signals):
    t, (ga, _, _) = signals
    path = tmp_path / "ms.uff"
    _write(path, [_series("a", 1, ga, 1e3 * t, time_unit="ms")])
    np.testing.assert_allclose(read_signals_uff(path)["time"], t, rtol=1e-11, atol=1e-15)


def test_errors(tmp_path, signals):
    t, (ga, gb, _) = signals
    with pytest.raises(ModelError, match="does not exist"):
        read_signals_uff(tmp_path / "missing.uff")
    junk = tmp_path / "junk.uff"
    junk.write_text("this is not a universal file\n")
    with pytest.raises(ModelError, match="no time series|not a readable"):
        read_signals_uff(junk)
    only_frf = tmp_path / "frf.uff"
    _write(only_frf, [pyuff.prepare_58(binary=0, func_type=4, rsp_node=1, rsp_dir=1,
                                       ref_node=1, ref_dir=1, data=np.ones(4) + 0j,
                                       x=np.arange(4.0), abscissa_spacing=1,
                                       abscissa_spec_data_type=18, ordinate_spec_data_type=12,
                                       orddenom_spec_data_type=13)])
    with pytest.raises(ModelError, match="no time series"):
        read_signals_uff(only_frf)
    mixed = tmp_path / "mixed.uff"
    _write(mixed, [_series("a", 1, ga, t), _series("b", 2, gb[:-10], t[:-10])])
    with pytest.raises(ModelError, match="one time base"):
        read_signals_uff(mixed)
