"""Hysteresis loop of a Jenkins element and its dissipated energy
================================================================

A Jenkins element (tangential spring k_t in series with a Coulomb slider of limit F_s) is
driven through a harmonic relative displacement of amplitude A. The loop area is the energy
dissipated per cycle; for A > F_s / k_t the closed form is ``W = 4 F_s (A - F_s / k_t)``.
"""

import matplotlib.pyplot as plt
import numpy as np

from fricdamp.contact import Jenkins
from fricdamp.signals import loop_area

k_t, F_s, A = 1e6, 5.0, 1e-5                       # [N/m], [N], [m]
law = Jenkins(stiffness=k_t, slip_force=F_s)
theta = np.linspace(0.0, 4 * np.pi, 8001)
u = A * np.sin(theta)
f = law.drive(u)

second = theta >= 2 * np.pi                         # the steady (second) cycle
W = loop_area(u[second], f[second])
closed_form = 4 * F_s * (A - F_s / k_t)
print(f"loop area {W:.6e} J, closed form {closed_form:.6e} J")
assert abs(W / closed_form - 1) < 1e-5

# %%
fig, ax = plt.subplots(figsize=(5, 4))
ax.plot(u * 1e6, f, lw=1)
ax.set_xlabel("relative displacement [µm]")
ax.set_ylabel("friction force [N]")
ax.set_title(f"Jenkins loop: W = {W * 1e6:.2f} µJ per cycle")
ax.grid(alpha=0.3)
