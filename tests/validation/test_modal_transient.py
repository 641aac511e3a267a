"""The modal contact transient (solvers/modal_transient.py) against the compiled fast path.

Both integrate the same discrete equations (Newmark average acceleration condensed on the
contacts), so on a model both can run -- the Craig-Bampton reduced beam wheel of paper 003
with its 30 tie-boss contacts -- the histories agree to the Newton tolerance. The chord and
the Newton-Krylov strategies stop on the same residual test, so they agree as well.
"""

import numpy as np
import pytest
import scipy.linalg as sla

from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.model import build_wheel
from fricdamp.models.tieboss_wheel.studies import initial_deformation
from fricdamp.solvers.fast_transient import _stack_projection, integrate_contact3d, solve_static
from fricdamp.solvers.modal_transient import ModalBasis, integrate_modal, solve_static_modal


@pytest.fixture(scope="module")
def wheel_basis():
    w = build_wheel(n_modes=4)
    s = w.system
    M, K, D = (np.asarray(A.toarray() if hasattr(A, "toarray") else A)
               for A in (s.M, s.K, s.D))
    lam, Phi = sla.eigh(K, M)
    cd = np.diag(Phi.T @ D @ Phi)
    P = _stack_projection(s)
    probe = w.group_dofs("probe", 0)
    basis = ModalBasis(lam, cd, np.asarray(P @ Phi), Phi[probe], groups=(("tieboss", 30),))
    init = initial_deformation(w, 2, 5e-4)
    return w, basis, Phi, M, probe, init


def test_static_solution_equals_the_physical_one(wheel_basis):
    w, basis, Phi, M, probe, init = wheel_basis
    st = solve_static_modal(basis, [w.law], Phi.T @ init.force)
    # tolerance: both solve to 1e-10 relative on the contact unknowns
    assert np.abs(Phi @ st.eta - init.q0).max() < 1e-9 * np.abs(init.q0).max()
    ref = solve_static(w.system, init.force)
    f_ref = ref.contact_force[0]
    assert np.abs(st.f - f_ref).max() < 1e-8 * np.abs(f_ref).max()


@pytest.mark.parametrize("chord", [True, False])
def test_modal_transient_equals_the_fast_path(wheel_basis, chord):
    w, basis, Phi, M, probe, init = wheel_basis
    st0 = init.states0[0]
    ref = integrate_contact3d(w.system, 0.01, 1e-5, q0=init.q0, states0=init.states0,
                              output_dofs=probe)
    res = integrate_modal(basis, [w.law], 0.01, 1e-5, eta0=Phi.T @ (M @ init.q0),
                          states0=(st0[:, :2], st0[:, 2]), chord=chord, progress=False)
    scale = np.abs(ref.q).max()
    # Newton tolerance 1e-10 per step, accumulated over 1000 steps: 1e-6 of the amplitude
    assert np.abs(ref.q - res.output).max() < 1e-6 * scale
    assert np.mean(ref.contact_status != res.contact_status) < 1e-3
    assert abs(ref.energy_balance_error - res.energy_balance_error) < 1e-6
    assert res.energy_balance_error < 1e-3
    if not chord:
        assert res.n_krylov == res.n_iterations > 0


def test_bad_input_is_named(wheel_basis):
    w, basis, *_ = wheel_basis
    with pytest.raises(ModelError, match="dt"):
        integrate_modal(basis, [w.law], 0.01, -1.0)
    with pytest.raises(ModelError, match="omega2"):
        ModalBasis([0.0, 1.0], 0.0, np.zeros((3, 2)), np.zeros((1, 2)))
    with pytest.raises(ModelError, match="eta0"):
        integrate_modal(basis, [w.law], 0.01, 1e-5, eta0=np.zeros(3))
