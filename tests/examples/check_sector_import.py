"""Physical check of examples/cases/sector_import.toml (issue 12: bring your own sector).

References computed here, independently of the case's analyses:

* the mesh file read with meshio: the sector's DOF count is 3 x (its tet10 nodes) less the
  clamped ones, and the wheel's 30 x (sector DOFs - one cut face);
* the open-contact first family rises with the nodal diameter from 2ND on (the disk's
  out-of-plane stiffness grows with ND; the blades' own frequency bounds it);
* the prestress of every tie-boss is the requested 2.4 N;
* the Campbell diagram from the mesh's own rotation terms: the blades stiffen with speed,
  and each critical speed solves f = p o n / 60 with a Ritz error below 1e-6;
* friction damps far more than the 0.1 % of the material, and the contact node pairs are
  open, stuck or slipping at every instant (fractions sum to one).
"""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np
import pytest


def check(summary: dict, case: dict) -> None:
    root = Path(__file__).resolve().parents[2] / "examples" / "cases"
    mesh = meshio.read(root / case["model"]["mesh"])
    n_nodes = len({int(i) for c in mesh.cells if c.type == "tetra10" for i in c.data.ravel()})
    clamp = mesh.cell_sets_dict["clamp"]
    clamped = {int(i) for typ, idx in clamp.items()
               for i in mesh.cells_dict[typ][idx].ravel()}
    m = summary["model"]
    assert m["sector_dof"] == 3 * (n_nodes - len(clamped))
    assert m["wheel_dof"] == 30 * (m["sector_dof"] - m["cut_dof"])
    assert m["prestress_normal_force_N"] == pytest.approx(2.4, rel=1e-3)
    f = np.asarray(summary["modal"]["frequency_hz"])
    assert np.all(np.diff(f[2:]) > 0)
    (e,) = summary["decay"]
    assert e["nd"] == 6
    assert e["damping_ratio"] > 5e-3
    fr = e["state_fractions"]
    assert fr["open"] + fr["stick"] + fr["slip"] == pytest.approx(1.0)
    assert fr["slip"] > 0
    camp = summary["campbell_by_nd"]
    assert camp["ritz_error"] < 1e-6
    assert np.all(np.asarray(camp["frequency_change_hz"]) > 0)
    for c in summary["critical_speeds_rpm"]:
        assert c["frequency_hz"] == pytest.approx(8 * c["order"] * c["rpm"] / 60, rel=1e-8)
