"""Case texts shared by the command-line tests."""

#: One mass on a spring with a Jenkins contact to ground: m = 1 kg, k = 1e4 N/m,
#: k_t = 1e4 N/m, F_s = 1 N. Stuck natural frequency sqrt(2e4 / 1) / (2 pi) = 22.508 Hz.
BASE_CASE = """\
name = "one_dof"

[model]
type = "chain"
masses_kg = [1.0]
springs_N_per_m = [1.0e4]

[[contacts]]
type = "jenkins"
name = "slider"
dofs = [1]
stiffness_N_per_m = 1.0e4
slip_force_N = 1.0

[analysis.free_decay]
initial_displacement_m = [1.0e-3]
duration_s = 0.5
time_step_s = 5.0e-4
"""

