"""Engine-order forcing of a tuned cyclic chain with friction between neighbours.

Ring of N unit oscillators (k = 1, coupling 0.05, dashpot 0.005 to ground), a Jenkins
contact between each pair of neighbours, travelling-wave (engine order EO) forcing.

1. Cyclic symmetry: the tuned assembly under a travelling wave responds with a travelling
   wave, ``q_j(tau) = q_0(tau - 2 pi EO j / N)``, so harmonic k of sector j is harmonic k of
   sector 0 rotated by ``k 2 pi EO j / N``. The solver is given no symmetry (the full sparse
   formulation); the property holds to the Newton tolerance (1e-9 relative) when the AFT
   samples are shift-invariant (see the test).
2. Stuck limit: with slip forces far above any contact force the contacts are linear springs
   k_t and the response is the linear one, ``(K + k_t L - w^2 M + i w D)^-1 F`` (1e-10).
3. Energy balance of every continued point <= 0.1 %.
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.contact import Jenkins
from fricdamp.solvers.hb import engine_order_load, frequency_response, harmonic_balance
from fricdamp.structure import ContactElement, MechanicalSystem


def ring(n=12, kt=0.5, fs=0.02, eo=3, force=0.01):
    K = sp.lil_matrix((n, n))
    P = sp.lil_matrix((n, n))
    for i in range(n):
        j = (i + 1) % n
        K[i, i] += 1.0 + 0.1
        K[i, j] -= 0.05
        K[j, i] -= 0.05
        P[i, i] = -1.0
        P[i, j] = 1.0
    return MechanicalSystem(M=sp.identity(n, format="csr"), K=K.tocsr(),
                            D=0.005 * sp.identity(n, format="csr"),
                            contacts=(ContactElement(Jenkins(kt, fs, n_contacts=n),
                                                     P.tocsr()),),
                            loads=(engine_order_load(n, eo, force),))


@pytest.mark.parametrize("n, omega, samples, method", [(12, 1.4, 64, "full-dense"),
                                                      (30, 1.05, 160, "full-sparse")])
def test_travelling_wave_symmetry(n, omega, samples, method):
    """The inter-sector phase 2 pi EO j / N must be a whole number of AFT samples for the
    discrete AFT to be shift invariant (N_s = 12, EO 3: 16 of 64 samples; N_s = 30: 16 of
    160). With N = 64 for 30 sectors the symmetry holds only to the sampling error (~1 %)."""
    eo, H = 3, 5
    ss = harmonic_balance(ring(n, eo=eo), omega, harmonics=H, samples=samples)
    assert ss.success and ss.method == method
    assert ss.dissipated_energy.min() > 1e-6       # the contacts slip
    C = ss.coefficients
    ref = C[0, 1::2] - 1j * C[0, 2::2]                 # phasors of sector 0, k = 1..H
    k = np.arange(1, H + 1)
    for j in range(n):
        rot = ref * np.exp(-1j * k * 2 * np.pi * eo * j / n)
        got = C[j, 1::2] - 1j * C[j, 2::2]
        np.testing.assert_allclose(got, rot, atol=1e-9 * np.abs(ref).max())
    np.testing.assert_allclose(C[:, 0], 0.0, atol=1e-12)
    # every contact dissipates the same energy
    np.testing.assert_allclose(ss.dissipated_energy, ss.dissipated_energy.mean(), rtol=1e-8)
    assert ss.energy_balance_error < 1e-6


def test_stuck_limit_is_linear():
    n, kt, w = 12, 0.5, 1.1
    sysm = ring(n, kt=kt, fs=1e3)
    ss = harmonic_balance(sysm, w, harmonics=3, samples=32)
    P = sysm.contacts[0].projection.toarray()
    Z = (sysm.K.toarray() + kt * P.T @ P - w**2 * sysm.M.toarray()
         + 1j * w * sysm.D.toarray())
    Q = np.linalg.solve(Z, sysm.loads[0].amplitude)
    np.testing.assert_allclose(ss.coefficients[:, 1] - 1j * ss.coefficients[:, 2], Q,
                               atol=1e-10 * np.abs(Q).max())
    np.testing.assert_allclose(ss.dissipated_energy, 0.0, atol=1e-15)


def test_frequency_response_through_resonance():
    fr = frequency_response(ring(12), 0.9, 1.3, harmonics=5, samples=64)
    assert fr.success, fr.message
    assert np.all(fr.energy_balance_error < 1e-3)
    w_pk, a_pk = fr.peak(0)
    # the friction-damped EO3 resonance lies between the slipping (contacts free) and the
    # stuck linear EO3 frequencies: sqrt(1 + 2 (c + s kt)(1 - cos(2 pi 3/12))), s = 0 or 1
    lo = np.sqrt(1 + 2 * 0.05 * (1 - np.cos(2 * np.pi * 3 / 12)))
    hi = np.sqrt(1 + 2 * 0.55 * (1 - np.cos(2 * np.pi * 3 / 12)))
    assert lo < w_pk < hi
    # friction limits the peak far below the undamped-slip resonance F / (c w) = 2
    assert a_pk < 0.5
    assert fr.omega[-1] == pytest.approx(1.3)
