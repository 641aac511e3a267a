"""Atomic writers, JSON conversion and results files (fricdamp.iofiles)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from fricdamp.iofiles import (
    atomic_path,
    combine_results,
    read_results,
    to_jsonable,
    write_json,
    write_results,
    write_text,
)


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "summary.json"
    write_text(target, "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half writ")
        raise RuntimeError("disk full")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]


def test_atomic_path_writes_next_to_the_target(tmp_path):
    with atomic_path(tmp_path / "a.txt") as tmp:
        assert tmp.parent == tmp_path and tmp.name.startswith(".a.txt.")
        tmp.write_text("x")
    assert (tmp_path / "a.txt").read_text() == "x"


def test_json_numpy_and_non_finite(tmp_path):
    obj = {"a": np.float32(1.5), "b": np.arange(3), "c": [np.nan, np.inf, 2.0],
           "d": np.bool_(True), "e": 1 + 2j, 3: (np.int64(7),), "f": tmp_path}
    path = write_json(tmp_path / "s.json", obj)
    back = json.loads(path.read_text())
    assert back == {"a": 1.5, "b": [0, 1, 2], "c": [None, None, 2.0], "d": True,
                    "e": {"real": 1.0, "imag": 2.0}, "3": [7], "f": str(tmp_path)}
    with pytest.raises(TypeError, match="cannot convert"):
        to_jsonable(object())


def _dataset():
    t = np.linspace(0.0, 1.0, 5)
    return xr.Dataset(
        {"q": (("time", "dof"), np.c_[t, 2 * t], {"units": "m"}),
         "n": ("time", np.arange(5, dtype=np.int64)),
         "flag": ("time", t > 0.5),
         "z": ("time", t + 1j * t)},
        coords={"time": t, "dof": ["blade", "platform"]},
        attrs={"meta": {"a": 1}, "ok": True, "name": "x"})


@pytest.mark.parametrize("suffix", [".nc", ".npz"])
def test_results_round_trip(tmp_path, suffix):
    ds = _dataset()
    path = write_results(tmp_path / f"results{suffix}", ds)
    back = read_results(path)
    np.testing.assert_array_equal(back["q"].values, ds["q"].values)
    assert back["q"].attrs["units"] == "m"
    assert list(back["dof"].values) == ["blade", "platform"]
    np.testing.assert_array_equal(back["n"].values, np.arange(5))
    if suffix == ".nc":  # netCDF-3 has no complex numbers and no booleans
        np.testing.assert_array_equal(back["z_real"].values, ds["z"].values.real)
        np.testing.assert_array_equal(back["z_imag"].values, ds["z"].values.imag)
        np.testing.assert_array_equal(back["flag"].values.astype(bool), ds["flag"].values)
        assert json.loads(back.attrs["meta"]) == {"a": 1}
    else:
        np.testing.assert_array_equal(back["z"].values, ds["z"].values)


def test_results_suffix_checked(tmp_path):
    with pytest.raises(ValueError, match=r"\.nc"):
        write_results(tmp_path / "r.h5", _dataset())


def test_combine_results_prefixes_and_separates_dimensions():
    t1, t2 = np.arange(4.0), np.arange(6.0)
    a = xr.Dataset({"q": ("time", t1)}, coords={"time": t1})
    b = xr.Dataset({"e": ("time", t2)}, coords={"time": t2})   # same dim name, other size
    c = xr.DataArray(np.ones(3), dims="peak", name="whatever")
    ds = combine_results({"free_decay": {"response": a, "other": b, "ratio": c},
                          "forced_response": {"response": a}}, attrs={"k": 1})
    assert ds["free_decay__q"].dims == ("free_decay__time",)
    assert ds["free_decay__e"].dims == ("free_decay__other__time",)
    assert ds["free_decay__ratio"].dims == ("free_decay__peak",)
    assert ds["forced_response__q"].dims == ("forced_response__time",)
    assert ds.attrs["k"] == 1
    with pytest.raises(ValueError, match="twice"):
        combine_results({"a": {"x": a, "y": a.rename({"time": "t"})}})
    with pytest.raises(TypeError, match="DataArray or Dataset"):
        combine_results({"a": {"x": np.ones(3)}})


def test_netcdf_int64_out_of_range_is_an_error(tmp_path):
    ds = xr.Dataset({"n": ("i", np.array([2**40], dtype=np.int64))})
    with pytest.raises(ValueError, match="int32"):
        write_results(tmp_path / "r.nc", ds)
    assert not list(tmp_path.iterdir())


def test_nan_survives_netcdf(tmp_path):
    ds = xr.Dataset({"x": ("i", np.array([1.0, math.nan]))})
    back = read_results(write_results(tmp_path / "r.nc", ds))
    assert np.isnan(back["x"].values[1])
