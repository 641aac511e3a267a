"""Campbell diagram of a solid wheel (fricdamp.models.tieboss_wheel.solid_campbell) on
the shipped coarse sector (16k DOFs, tet10).

References, independent of the Rayleigh-Ritz branches:

* a direct shift-invert eigen-solution of the unreduced sector with ``K + Omega^2 K_1`` at a
  speed between the ends of the range (the Ritz basis holds the exact modes of the ends
  only): the first family agrees to 1e-6 (measured 2e-10);
* the zero-ND centrifugal prestress is in static equilibrium with the centrifugal load on
  the cyclic sector: ``T^T (K u_1 - f_c) = 0`` (1e-9 of the load);
* the critical speeds solve 003 (1) ``f_nd(n) = p o n / 60`` with a directly computed
  ``f_nd`` (1e-6), and lie within 3 % of the paper's 334 and 123 rpm (the coarse mesh's
  open-contact frequencies are within 3 % of Table 1, and n scales with f).
"""

from pathlib import Path

import meshio
import numpy as np
import pytest

from fricdamp.models.contact_wheel import sector_from_solid
from fricdamp.models.tieboss_wheel.solid_campbell import (
    _at_speed,
    campbell_solid,
    critical_speeds_solid,
    rotation_terms,
)
from fricdamp.structure.cyclic import nodal_diameter_modes
from fricdamp.structure.solid import assemble_solid, mesh_from_meshio

MESH = Path(__file__).resolve().parents[2] / "examples" / "meshes" / "tieboss_sector_coarse.msh"


@pytest.fixture(scope="module")
def wheel():
    solid = assemble_solid(mesh_from_meshio(meshio.read(MESH)), youngs_modulus=2.1e11,
                           poisson_ratio=0.3, density=7850.0,
                           materials={"tipmass": {"density": 24250.0}})
    ws = sector_from_solid(solid, n_sectors=30, youngs_modulus=2.1e11,
                           probe_direction=[0, 1, 1])
    return ws, rotation_terms(ws, solid)


def test_ritz_branches_equal_direct_solutions_between_the_ends(wheel):
    ws, rot = wheel
    c = campbell_solid(ws, rot, [0.0, 200.0, 450.0], nds=[0, 2, 6, 15])
    direct = [nodal_diameter_modes(_at_speed(ws.cyclic, rot, 200 * np.pi / 30), nd,
                                   1).frequencies[0] for nd in (0, 2, 6, 15)]
    np.testing.assert_allclose(c.frequency_hz[1], direct, rtol=1e-6)
    # the blades stiffen with speed (stress stiffening beats spin softening)
    assert np.all(np.diff(c.frequency_hz, axis=0) > 0)
    # prestress equilibrium on the cyclic sector
    T = ws.cyclic.cyclic_transform(0)
    f = rot.centrifugal_load
    import scipy.sparse.linalg as spla

    u = T @ spla.spsolve((T.T @ ws.cyclic.K @ T).tocsc(), T.T @ f)
    assert np.abs(T.T @ (ws.cyclic.K @ u - f)).max() < 1e-9 * np.abs(T.T @ f).max()


def test_critical_speeds_solve_the_paper_relation(wheel):
    ws, rot = wheel
    crit = critical_speeds_solid(ws, rot, orders=[(1, 2), (3, 6)])
    for c, paper in zip(crit, (334.0, 123.0), strict=True):
        f = nodal_diameter_modes(_at_speed(ws.cyclic, rot, c["rpm"] * np.pi / 30), c["nd"],
                                 1).frequencies[0]
        assert f == pytest.approx(8 * c["order"] * c["rpm"] / 60, rel=1e-6)
        assert c["rpm"] == pytest.approx(paper, rel=0.03)
