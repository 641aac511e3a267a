"""Harmonic balance: frequency response through a friction resonance
===================================================================

A 2-DOF chain (a blade and its under-platform damper) with a Jenkins friction contact
between the second mass and the ground, forced harmonically on the second mass. Harmonic
balance with the alternating frequency-time (AFT) method and arclength continuation traces
the response curve through resonance; every point carries its energy balance (work of the
load = viscous + friction dissipation per cycle).
"""

import numpy as np

from fricdamp.contact import Jenkins
from fricdamp.solvers import frequency_response, nonlinear_modes
from fricdamp.structure import ContactElement, HarmonicLoad, chain

system = chain([1.0, 0.5], [1e3, 5e2], dampers=[0.5, 0.2],
               contacts=[ContactElement(Jenkins(800.0, 2.0), [[0.0, 1.0]], "damper")])
forced = system.with_loads(HarmonicLoad([0.0, 3.0], 20.0))
frf = frequency_response(forced, 20.0, 60.0, harmonics=7)

omega_peak, amplitude_peak = frf.peak(dof=1)
print(f"{frf.n_points} points, {frf.message}")
print(f"peak of DOF 1: {amplitude_peak * 1e3:.3f} mm at {omega_peak / (2 * np.pi):.3f} Hz")
print(f"largest energy balance error {frf.energy_balance_error.max():.1e}")
assert frf.success
assert frf.energy_balance_error.max() < 1e-3

# %%
# The nonlinear mode of the same system (free motion, amplitude-dependent frequency and
# damping) is the backbone of the response: the resonance peak lies on it. The figure shows
# the response of DOF 1 against the excitation frequency, with the backbone.
nm = nonlinear_modes(system, 0, np.geomspace(1e-3, 0.2, 25), harmonics=7, amplitude_dof=1)
backbone_at_peak = np.interp(amplitude_peak, nm.amplitude, nm.frequency)
print(f"backbone at the peak amplitude: {backbone_at_peak / (2 * np.pi):.3f} Hz")
assert abs(backbone_at_peak / omega_peak - 1) < 0.01
ax = frf.plot(dof=1)
ax.plot(nm.frequency / (2 * np.pi), nm.amplitude, "k--", lw=1, label="nonlinear mode")
ax.legend()
