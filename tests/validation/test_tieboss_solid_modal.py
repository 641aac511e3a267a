"""Solid tie-boss sector vs paper 003 Table 1: open-contact first family by nodal diameter.

Reference: paper 003 section 2.2, Table 1 (FEM column; the pair means are the targets, the
pairs being the split double modes of the slightly mistuned ANSYS model) and the text: the
frequencies "monotonously increase with a number of ND" and converge to 50.3 Hz at 15 ND.
Tolerance 1 % (issue 12; the paper's FE pairs themselves differ by up to 0.25 %, the model's
mesh error is ~0.2 %, see the coarse-mesh bound below).
"""

import numpy as np
import pytest

from fricdamp.models.tieboss_wheel.model import table1_targets
from fricdamp.models.tieboss_wheel.solid import (
    SolidWheelParameters,
    build_solid_sector,
    first_family_frequencies,
)

pytest.importorskip("gmsh")
pytest.importorskip("skfem")

NDS = (2, 3, 4, 5, 6, 15)
COARSE = SolidWheelParameters(mesh_size_m=0.012)
#: Largest relative difference of the first-family frequencies (2-6 and 15 ND) between the
#: coarse mesh (12 mm) and the default mesh (6 mm), observed on the tuned wheel (the coarse
#: tet10 mesh is stiffer); the coarse check allows it on top of the 1 % tolerance.
COARSE_MESH_SHIFT = 0.005


@pytest.fixture(scope="module")
def coarse_frequencies():
    return first_family_frequencies(build_solid_sector(COARSE), NDS)


@pytest.fixture(scope="module")
def default_frequencies():
    return first_family_frequencies(build_solid_sector(), NDS)


def test_coarse_mesh_table1(coarse_frequencies):
    """Coarse mesh: Table 1 within 1 % plus the observed coarse-to-default mesh shift."""
    targets = table1_targets()
    err = {nd: coarse_frequencies[nd] / targets[nd] - 1.0 for nd in NDS}
    assert max(abs(e) for e in err.values()) < 0.01 + COARSE_MESH_SHIFT, err
    f = [coarse_frequencies[nd] for nd in NDS]
    assert np.all(np.diff(f) > 0)


@pytest.mark.slow
def test_default_mesh_table1(default_frequencies):
    """Default mesh: pair means of Table 1 (FEM) within 1 % at 2-6 ND."""
    targets = table1_targets()
    for nd in (2, 3, 4, 5, 6):
        assert default_frequencies[nd] == pytest.approx(targets[nd], rel=0.01), nd


@pytest.mark.slow
def test_default_mesh_15nd_limit(default_frequencies):
    """003 section 2.2: the family converges to 50.3 Hz at 15 ND (within 1 %)."""
    assert default_frequencies[15] == pytest.approx(50.3, rel=0.01)


@pytest.mark.slow
def test_default_mesh_rises_with_nd(default_frequencies):
    """003: the open-contact frequencies increase monotonically with ND."""
    f = [default_frequencies[nd] for nd in NDS]
    assert np.all(np.diff(f) > 0)


@pytest.mark.slow
def test_coarse_mesh_shift_bound(coarse_frequencies, default_frequencies):
    """The coarse-mesh tolerance above is the observed mesh convergence."""
    shift = max(abs(coarse_frequencies[nd] / default_frequencies[nd] - 1.0) for nd in NDS)
    assert shift <= COARSE_MESH_SHIFT


def test_tuning_the_tip_mass_hits_a_target():
    """tune_solid_parameters on the coarse mesh: the tip-mass density alone (assembled
    parts re-used) moves the 15 ND frequency onto 50.0 Hz."""
    from fricdamp.models.tieboss_wheel.solid import tune_solid_parameters

    tuned, report = tune_solid_parameters(COARSE, names=("tipmass_density_kg_m3",),
                                          targets={15: 50.0}, max_evaluations=8)
    assert report["model_hz"][0] == pytest.approx(50.0, rel=2e-3)
    assert tuned.tipmass_density_kg_m3 > COARSE.tipmass_density_kg_m3   # 50.26 Hz before
    assert tuned.disk_thickness_m == COARSE.disk_thickness_m
