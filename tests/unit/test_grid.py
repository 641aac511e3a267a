"""Grid parsing and validation, and the overriding of case keys by study parameters.

References: the grid syntax of the studies issue (``name=start:stop:num`` is numpy.linspace with
both ends included, ``name=v1,v2,v3`` the listed values) and the case-file conventions of
``fricdamp.case`` (strict types, 1-based list entries).
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from fricdamp.errors import CaseError
from fricdamp.studies.grid import (
    Grid,
    apply_overrides,
    parse_axis,
    parse_bounds,
    resolve_parameter,
)


# ----------------------------------------------------------------------------- axes
def test_range_is_linspace_with_both_ends():
    name, v = parse_axis("damper_mass_kg=0.5e-3:3e-3:11")
    assert name == "damper_mass_kg"
    # exactly numpy's linspace: the same values a user gets in Python, bit for bit
    np.testing.assert_array_equal(v, np.linspace(0.5e-3, 3e-3, 11))
    assert v[0] == 0.5e-3 and v[-1] == 3e-3


def test_descending_range_and_single_value():
    np.testing.assert_array_equal(parse_axis("g=70:40:4")[1], [70.0, 60.0, 50.0, 40.0])
    assert parse_axis("g=40:40:1")[1].tolist() == [40.0]
    assert parse_axis("g=42.5")[1].tolist() == [42.5]


def test_list_keeps_order_and_integer_type():
    name, v = parse_axis(" harmonics = 5, 1 ,3 ")
    assert name == "harmonics"
    assert v.dtype.kind == "i" and v.tolist() == [5, 1, 3]
    v = parse_axis("mu=0.1,2e-1,0.3")[1]
    assert v.dtype.kind == "f" and v.tolist() == [0.1, 0.2, 0.3]


@pytest.mark.parametrize("spec, words", [
    ("gamma_deg=40:70:0", ["empty range", "gamma_deg"]),
    ("gamma_deg=40:40:3", ["empty range", "start = stop"]),
    ("gamma_deg=40:70:-2", ["empty range"]),
    ("gamma_deg=", ["no values"]),
    ("gamma_deg=abc", ["'abc'", "not a number", "gamma_deg"]),
    ("gamma_deg=40:x:3", ["STOP", "'x'", "not a number"]),
    ("gamma_deg=40:70:2.5", ["NUM", "integer"]),
    ("gamma_deg=40:70", ["START:STOP:NUM"]),
    ("gamma_deg=40,,50", ["empty entry"]),
    ("gamma_deg=40,50,40", ["40", "twice"]),
    ("gamma_deg=nan", ["finite"]),
    ("gamma_deg=1:inf:3", ["finite"]),
    ("gamma_deg 40:70:3", ["NAME=START:STOP:NUM"]),
    ("2gamma=1,2", ["not valid"]),
    ("gamma-deg=1,2", ["not valid"]),
    ("g=1:2:1", ["ambiguous"]),
])
def test_bad_axes_get_clear_errors(spec, words):
    with pytest.raises(CaseError) as info:
        parse_axis(spec)
    for w in words:
        assert w in str(info.value), (w, str(info.value))


# ----------------------------------------------------------------------------- grids
def test_grid_points_first_axis_slowest():
    g = Grid.parse(["a=1:3:3", "b=10,20"])
    assert g.names == ("a", "b") and g.shape == (3, 2) and g.size == 6
    pts = list(g.points())
    assert pts == [{"a": 1.0, "b": 10}, {"a": 1.0, "b": 20}, {"a": 2.0, "b": 10},
                   {"a": 2.0, "b": 20}, {"a": 3.0, "b": 10}, {"a": 3.0, "b": 20}]
    # C order: point k sits at np.unravel_index(k, shape), which is how sweep fills arrays
    for k, p in enumerate(pts):
        i, j = np.unravel_index(k, g.shape)
        assert p == {"a": g["a"][i], "b": g["b"][j]}


def test_grid_from_case_table_forms():
    g = Grid.from_mapping({"m": "0.5e-3:3e-3:6", "gamma_deg": [40, 50, 60],
                           "mu": {"start": 0.1, "stop": 0.3, "num": 3}, "k": 2.0,
                           "c": {"values": [1.5, 2.5]}})
    assert g.shape == (6, 3, 3, 1, 2)
    np.testing.assert_array_equal(g["mu"], np.linspace(0.1, 0.3, 3))
    assert g["gamma_deg"].tolist() == [40, 50, 60]


@pytest.mark.parametrize("mapping, words", [
    ({}, ["empty"]),
    ({"mu": []}, ["no values"]),
    ({"mu": ["a", "b"]}, ["must be a number", "'a'"]),
    ({"mu": [True, False]}, ["must be a number"]),
    ({"mu": {"start": 0, "stop": 1}}, ["start, stop, num"]),
    ({"mu": {"start": 0, "stop": 1, "num": 0}}, ["empty range"]),
    ({"mu": "0.1:0.3:x"}, ["NUM", "integer"]),
])
def test_bad_case_grids(mapping, words):
    with pytest.raises(CaseError) as info:
        Grid.from_mapping(mapping)
    for w in words:
        assert w in str(info.value), (w, str(info.value))


def test_grid_rejects_repeated_names_and_huge_grids():
    with pytest.raises(CaseError, match="'a' is given twice"):
        Grid.parse(["a=1,2", "a=3,4"])
    with pytest.raises(CaseError, match="more than"):
        Grid.parse(["a=0:1:1001", "b=0:1:1001"])


def test_unknown_parameter_name_suggests_the_close_one():
    g = Grid.parse(["gama_deg=40,50"])
    with pytest.raises(CaseError) as info:
        g.check_names(["damper_mass_kg", "gamma_deg"], what="damper_design()")
    msg = str(info.value)
    assert "unknown grid parameter 'gama_deg'" in msg and "did you mean 'gamma_deg'" in msg


# ---------------------------------------------------------------------------- bounds
def test_bounds_parsing():
    b = parse_bounds("damper_mass_kg=0.5e-3:3e-3,gamma_deg=40:70")
    assert b == {"damper_mass_kg": (0.5e-3, 3e-3), "gamma_deg": (40.0, 70.0)}
    assert parse_bounds(["a=0:1", "b=2:3"]) == {"a": (0.0, 1.0), "b": (2.0, 3.0)}
    assert parse_bounds({"a": [0, 1], "b": "2:3"}) == {"a": (0.0, 1.0), "b": (2.0, 3.0)}


@pytest.mark.parametrize("spec, words", [
    ("a=1:1", ["LOW", "smaller than HIGH"]),
    ("a=2:1", ["smaller than HIGH"]),
    ("a=1", ["LOW:HIGH"]),
    ("a=x:1", ["'x'", "not a number"]),
    ("a=0:1,a=0:2", ["twice"]),
    ("", ["no parameters"]),
])
def test_bad_bounds(spec, words):
    with pytest.raises(CaseError) as info:
        parse_bounds(spec)
    for w in words:
        assert w in str(info.value), (w, str(info.value))


# ------------------------------------------------------------------------- overrides
CASE = {
    "name": "demo",
    "model": {"type": "chain", "masses_kg": [0.5, 0.1], "springs_N_per_m": [2e5, 8e5]},
    "contacts": [
        {"type": "jenkins", "name": "left", "dofs": [1], "stiffness_N_per_m": 1e5, "mu": 0.3,
         "normal_load_N": 20.0},
        {"type": "jenkins", "name": "right", "dofs": [2], "stiffness_N_per_m": 2e5,
         "slip_force_N": 6.0},
    ],
    "analysis": {"forced_response": {"force_amplitude_N": [4.0, 0.0], "frequency_hz": 100.0,
                                     "periods": 60}},
    "sweep": {"grid": {"mu": "0.1:0.5:3"}},
}


def test_resolve_unique_bare_key_and_paths():
    assert resolve_parameter(CASE, "mu") == ("contacts", 0, "mu")
    assert resolve_parameter(CASE, "frequency_hz") == ("analysis", "forced_response",
                                                       "frequency_hz")
    assert resolve_parameter(CASE, "contacts.2.stiffness_N_per_m") == (
        "contacts", 1, "stiffness_N_per_m")
    assert resolve_parameter(CASE, "contacts.right.slip_force_N") == (
        "contacts", 1, "slip_force_N")
    assert resolve_parameter(CASE, "model.masses_kg.2") == ("model", "masses_kg", 1)
    # the end of a unique full path
    assert resolve_parameter(CASE, "force_amplitude_N.1") == (
        "analysis", "forced_response", "force_amplitude_N", 0)
    # a key left at its schema default may be set by its full path
    assert resolve_parameter(CASE, "analysis.forced_response.steps_per_period") == (
        "analysis", "forced_response", "steps_per_period")


@pytest.mark.parametrize("name, words", [
    ("stiffness_N_per_m", ["ambiguous", "contacts.1.stiffness_N_per_m",
                           "contacts.2.stiffness_N_per_m"]),
    ("mu_static", ["unknown grid parameter 'mu_static'"]),
    ("frequncy_hz", ["unknown", "did you mean 'frequency_hz'"]),
    ("contacts.3.mu", ["2 entries", "numbered from 1"]),
    ("contacts.middle.mu", ["no entries named 'middle'"]),
    ("model.masses_kg", ["a list, not a number", "model.masses_kg.1"]),
    ("model", ["a table, not a number"]),
    ("masses_kg", ["names a list", "model.masses_kg.1"]),
    ("modl.masses_kg.1", ["unknown", "no table 'modl'"]),
    ("mu.1", ["unknown"]),
])
def test_resolve_errors(name, words):
    with pytest.raises(CaseError) as info:
        resolve_parameter(CASE, name)
    for w in words:
        assert w in str(info.value), (w, str(info.value))


def test_study_tables_are_not_parameters():
    # the [sweep] table holds strings, but even numbers there must never be overridden
    case = {**CASE, "optimize": {"maxiter": 10}}
    with pytest.raises(CaseError, match="unknown"):
        resolve_parameter(case, "maxiter")


def test_apply_overrides_copies_and_keeps_integer_types():
    before = copy.deepcopy(CASE)
    out = apply_overrides(CASE, {"mu": 0.45, "contacts.2.slip_force_N": 7, "periods": 80.0,
                                 "model.masses_kg.1": np.float64(0.25)})
    assert CASE == before  # the input is untouched
    assert out["contacts"][0]["mu"] == 0.45
    assert out["contacts"][1]["slip_force_N"] == 7.0
    assert isinstance(out["contacts"][1]["slip_force_N"], float)  # float key stays float
    assert out["analysis"]["forced_response"]["periods"] == 80
    assert type(out["analysis"]["forced_response"]["periods"]) is int  # strict int schema
    assert out["model"]["masses_kg"] == [0.25, 0.1]
    assert type(out["model"]["masses_kg"][0]) is float
    # a non-integral value for an integer key stays a float, so the schema reports it
    assert apply_overrides(CASE, {"periods": 2.5})["analysis"]["forced_response"][
        "periods"] == 2.5


def test_overridden_case_is_validated_by_the_case_schema():
    """An override out of range is reported exactly as a case-file value would be."""
    from fricdamp.case import parse_case
    from fricdamp.runner import REGISTRY

    case = {k: v for k, v in CASE.items() if k != "sweep"}
    parsed = parse_case(apply_overrides(case, {"mu": 0.45}), REGISTRY)
    assert parsed.contacts[0][1].mu == 0.45
    with pytest.raises(CaseError) as info:
        parse_case(apply_overrides(case, {"mu": -0.1}), REGISTRY)
    assert "mu" in str(info.value) and ">= 0" in str(info.value)
    with pytest.raises(CaseError, match="periods must be an integer"):
        parse_case(apply_overrides(case, {"periods": 2.5}), REGISTRY)


def test_unquoted_dotted_toml_keys_give_dotted_names():
    import tomllib

    table = tomllib.loads('contacts.1.mu = [0.1, 0.2]\n"model.masses_kg.2" = "1:2:2"\n'
                          'k = {start = 1, stop = 2, num = 2}\n')
    g = Grid.from_mapping(table)
    assert g.names == ("contacts.1.mu", "model.masses_kg.2", "k")
    assert g.shape == (2, 2, 2)
