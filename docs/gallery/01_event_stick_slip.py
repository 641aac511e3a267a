"""Event-driven stick-slip: den Hartog's Coulomb oscillator
=========================================================

A mass on a spring slides on a Coulomb contact under harmonic forcing,
``x'' + x + F_f sgn(x') = cos(0.8 t)`` (m = k = F0 = 1). The event-driven solver splits the
motion into smooth stick and slip phases, integrates each phase in closed form and locates
every switch to round-off: no regularisation, no time step.

After the transient the amplitude is den Hartog's (1931) closed form
``X = sqrt(V^2 - beta^2 U^2)`` with ``V = 1/(1 - r^2)`` and ``U = tan(pi/(2r))/r``.
"""

import numpy as np

from fricdamp.solvers import CoulombSystem, simulate_events
from fricdamp.structure import HarmonicLoad, MechanicalSystem

r, beta = 0.8, 0.3                                  # frequency ratio, F_f / F0
structure = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], r),))
system = CoulombSystem(structure, directions=[1.0], normal_load=beta, mu_static=1.0)

period = 2 * np.pi / r
t = np.linspace(0.0, 150 * period, 30001)
res = simulate_events(system, (0.0, t[-1]), y0=[0.0, 0.0], t_eval=t)

last = res.t >= t[-1] - period                      # the last forcing period
amplitude = np.abs(res.q[last, 0]).max()
V, U = 1 / (1 - r**2), np.tan(np.pi / (2 * r)) / r
closed_form = np.sqrt(V**2 - beta**2 * U**2)
print(f"{res.n_events} events, energy balance error {res.energy_balance_error:.1e}")
print(f"amplitude {amplitude:.9f}, den Hartog {closed_form:.9f}")
assert abs(amplitude / closed_form - 1) < 1e-6

# %%
# In this non-stop regime the mass never sticks. At a lower frequency and with a larger
# friction force (r = 0.5, beta = 0.5) it sticks at every reversal: the stick phases last
# until the spring and the load overcome the static friction. The energy balance (input
# work = friction dissipation + change of stored energy) holds to round-off because every
# phase is exact.
slow = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], 0.5),))
stuck = CoulombSystem(slow, directions=[1.0], normal_load=0.5, mu_static=1.0)
period = 2 * np.pi / 0.5
t = np.linspace(0.0, 40 * period, 8001)
res = simulate_events(stuck, (0.0, t[-1]), y0=[0.0, 0.0], t_eval=t)
n_stick = len(res.event_times(to_mode="stick"))
print(f"{n_stick} stick phases, energy balance error {res.energy_balance_error:.1e}")
assert n_stick > 0 and res.energy_balance_error < 1e-9
axes = res.plot()
for ax in axes:
    ax.set_xlim(t[-1] - 3 * period, t[-1])
