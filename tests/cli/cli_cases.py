"""Case texts shared by the command-line tests, and helpers for the tables of invalid cases."""

import pytest

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



def replace_once(text: str, old: str, new: str) -> str:
    """``text`` with the first ``old`` replaced by ``new`` (``old`` must occur: a test whose
    substitution silently does nothing would test the valid case)."""
    assert old in text, old
    return text.replace(old, new, 1)


#: A valid ``[[contacts]]`` table (a Jenkins slider on DOF 1), for the models that refuse one.
JENKINS_CONTACT = """\
[[contacts]]
type = "jenkins"
dofs = [1]
stiffness_N_per_m = 1.0e4
slip_force_N = 1.0
"""


def contacts_refused(section: str, model_type: str) -> tuple:
    """The entry of a table of invalid cases that adds :data:`JENKINS_CONTACT` before
    ``section`` of a paper's model, whose contacts are part of the model (exit code 2)."""
    return ("contacts_refused", (section, f"{JENKINS_CONTACT}\n{section}"),
            ["[[contacts]] cannot be added", f"'{model_type}'"])


def bad_params(table) -> list:
    """pytest parameters ``(old_new, expected)``, with ids, of a table of invalid cases: rows
    ``(id, (old, new), expected substrings of the error line)``."""
    return [pytest.param(old_new, expected, id=ident) for ident, old_new, expected in table]
