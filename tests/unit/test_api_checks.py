"""Issue 15, the Python API's checks: results that judge themselves, sizes refused before
allocating, empty models refused, DOFs counted from 1 in messages, non-numbers refused.

Each test reruns an item of the issue's "Why" list as written through the API.
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.contact import Contact3D, Jenkins
from fricdamp.errors import CheckError, ModelError
from fricdamp.solvers.fast_transient import integrate_contact3d
from fricdamp.solvers.timestep import simulate
from fricdamp.structure import ContactElement, MechanicalSystem, chain
from fricdamp.verdict import FAILED, OK, UNRELIABLE

ONE_HZ = chain([1.0], [4 * np.pi**2])


def test_simulate_result_carries_its_verdict():
    """Why: ``simulate(..., dt=0.1, throw=False)`` returned success=True with a final state
    of the wrong sign (1 Hz oscillator after 10 s: -0.37 instead of 1). The result's own
    verdict says unreliable: period error 3.2 % at 10 steps per period (limit 1 %)."""
    res = simulate(ONE_HZ, 10.0, 0.1, q0=[1.0], throw=False, progress=False)
    assert res.success and res.q[-1, 0] < 0          # the wrong answer, still "success"
    v = res.verdict
    assert v.status == UNRELIABLE
    assert v.estimates["period_error"] == pytest.approx(0.0321, abs=1e-4)
    assert any("period error" in r and "reduce the time step" in r for r in v.reasons)
    assert res.verdict is v                           # judged once
    fine = simulate(ONE_HZ, 1.0, 1e-3, q0=[1.0], progress=False)
    assert fine.verdict.status == OK and fine.verdict.estimates["period_error"] < 1e-5


def test_simulate_that_stopped_is_failed():
    s = chain([1.0], [1e4]).with_contacts(ContactElement(Jenkins(1e10, 10.0), [[1.0]]))
    res = simulate(s, 0.1, 3e-5, q0=[4.472e-3], max_iter=2, throw=False, progress=False)
    assert not res.success
    assert res.verdict.status == FAILED
    assert res.verdict.reasons[0].startswith("the integration stopped at t = ")


def test_simulate_refuses_a_tiny_dt_before_allocating():
    """Why: ``dt=1e-12`` ended in a MemoryError (7 TiB) deep inside numpy."""
    with pytest.raises(CheckError, match=r"^dt = 1e-12 would need about .* TiB .* increase "
                                         r"dt"):
        simulate(ONE_HZ, 10.0, 1e-12, q0=[1.0], progress=False)


def test_integrate_contact3d_refuses_a_tiny_dt_before_allocating():
    law = Contact3D(normal_stiffness=1e5, tangential_stiffness=1e5, mu=0.3)
    s = MechanicalSystem(M=np.eye(3), K=1e4 * np.eye(3),
                         contacts=(ContactElement(law, np.eye(3)),),
                         static_load=[-1.0, 0.0, 0.0])
    with pytest.raises(CheckError, match=r"^dt = 1e-12 would need about"):
        integrate_contact3d(s, 10.0, 1e-12)


@pytest.mark.parametrize("dt", ["abc", None, [1e-3]])
def test_simulate_refuses_a_time_step_that_is_not_a_number(dt):
    with pytest.raises(ModelError, match=r"^dt must be a number \[s\], got"):
        simulate(ONE_HZ, 1.0, dt)


def test_chain_without_masses_is_refused():
    """Why: ``chain([], [])`` raised an IndexError."""
    with pytest.raises(ModelError, match="masses must have at least one entry"):
        chain([], [])


def test_mass_matrix_message_counts_dofs_from_1():
    """Why: error messages counted DOFs from 0 while the product counts from 1."""
    with pytest.raises(ModelError, match=r"at DOF 2 \(counting from 1\) is 0 kg"):
        MechanicalSystem(M=np.diag([1.0, 0.0, 1.0]), K=np.eye(3))
    with pytest.raises(ModelError, match=r"at DOF 3 \(counting from 1\) is -1 kg"):
        chain([1.0, 1.0], [1.0, 1.0]).__class__(M=np.diag([1.0, 1.0, -1.0]), K=np.eye(3))


@pytest.mark.parametrize("name", ["run.nc", "run.npz"])
def test_time_result_save_on_a_full_disk_leaves_no_temporary_file(tmp_path, monkeypatch, name):
    """Why (faults): a full disk left temporary files behind. ``TimeResult.save`` writes
    through a temporary file that is removed when the write fails; the OSError names the
    disk-full reason to the caller."""
    import errno

    import xarray as xr

    def full(self, path, *a, **k):
        with open(path, "wb") as fh:      # a partial file, then the disk is full
            fh.write(b"CDF")
        raise OSError(errno.ENOSPC, "No space left on device")

    def full_npz(fh, *a, **k):
        fh.write(b"PK")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full)
    monkeypatch.setattr(np, "savez", full_npz)
    monkeypatch.setattr(np, "savez_compressed", full_npz)
    res = simulate(ONE_HZ, 0.1, 1e-2, q0=[1.0], progress=False)
    with pytest.raises(OSError, match="No space left"):
        res.save(tmp_path / name)
    assert list(tmp_path.iterdir()) == []
    monkeypatch.undo()
    res.save(tmp_path / name)
    assert [p.name for p in tmp_path.iterdir()] == [name]
