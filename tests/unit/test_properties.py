"""Property-based tests (hypothesis, issue 15): contact laws and the case schema.

* Passivity: driven from the virgin state along any closed displacement path, a friction law
  absorbs a non-negative net work ``W = sum f du`` (trapezoidal, the time integrator's own
  bookkeeping). From the virgin state ``W = E_stored(end) + D >= 0`` with ``D >= 0`` the
  dissipation; the trapezoidal rule commits an error of order ``k_t du^2`` per step at a
  stick/slip corner, so the tolerance is ``1e-9`` of the path's energy scale ``F_s * travel``
  plus that corner error. The laws' own dissipation per step must be >= 0 (round-off
  tolerance 1e-12 of ``F_s * |du|``).
* Tangent: the consistent tangent of a return-map step equals the central finite difference
  of the force over ``u`` from the same state, where the two one-sided differences agree (no
  stick/slip switch inside the difference step); tolerance 1e-6 relative to ``k_t``.
* Case schema: any single mutation of a valid case (a key removed, a value replaced by a
  value of another type, a NaN, a huge number, an unknown key) is either valid or rejected
  with a CaseError / ModelError, never another exception.

Sizes are kept small (``max_examples``, short paths) so the file runs in a few seconds.
"""

from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from fricdamp.contact import Jenkins  # noqa: E402
from fricdamp.contact.coulomb import Coulomb  # noqa: E402
from fricdamp.contact.element3d import Contact3D  # noqa: E402
from fricdamp.contact.iwan import Iwan  # noqa: E402
from fricdamp.errors import CaseError, ModelError  # noqa: E402

FAST = settings(max_examples=40, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow])


def _law(kind: str, k: float, fs: float):
    if kind == "jenkins":
        return Jenkins(k, fs)
    if kind == "coulomb":   # static > sliding coefficient, constant sliding value
        return Coulomb(k, fs / 0.3, 0.4, 0.3, 0.0)
    if kind == "iwan":
        return Iwan(k, fs, -0.5, 0.1, n_elements=20)
    if kind == "contact3d":
        return Contact3D.from_preload(10 * k, fs / 0.3, k, 0.3)
    raise AssertionError(kind)


LAWS = ["jenkins", "coulomb", "iwan", "contact3d"]


def _closed_path(steps: list[float], n_dir: int, scale: float) -> np.ndarray:
    """A path starting at 0 through the given increments and back to 0 (closed)."""
    inc = np.asarray(steps, float) * scale
    u = np.concatenate([[0.0], np.cumsum(inc)])
    back = np.linspace(u[-1], 0.0, 8)[1:]
    u = np.concatenate([u, back])
    if n_dir == 1:
        return u[:, None, None]
    path = np.zeros((u.size, 1, n_dir))
    path[:, 0, 1] = u            # tangential direction 1
    path[:, 0, 2] = 0.5 * np.sin(np.linspace(0, 2 * np.pi, u.size)) * scale   # closes too
    return path


@FAST
@given(kind=st.sampled_from(LAWS),
       k=st.floats(1e3, 1e8), fs=st.floats(0.1, 100.0),
       steps=st.lists(st.floats(-5.0, 5.0), min_size=2, max_size=40))
def test_net_work_over_a_closed_path_is_not_negative(kind, k, fs, steps):
    law = _law(kind, k, fs)
    scale = fs / k                     # increments up to 5 slip displacements
    u = _closed_path(steps, law.n_dir, scale)
    st_ = law.initial_state()
    f_prev = law.step(st_, u[0]).force
    work, diss, corner = 0.0, 0.0, 0.0
    for i in range(1, u.shape[0]):
        r = law.step(st_, u[i])
        du = u[i] - u[i - 1]
        work += float(np.sum(0.5 * (f_prev + r.force) * du))
        d = law.dissipation(st_, r.state, r.force)
        if d is not None:
            assert float(np.min(d)) >= -1e-12 * fs * float(np.sum(np.abs(du))) - 1e-300
            diss += float(np.sum(d))
        corner += 10 * k * float(np.sum(du**2))
        st_, f_prev = r.state, r.force
    travel = float(np.sum(np.abs(np.diff(u, axis=0))))
    assert work >= -(1e-9 * fs * travel + corner), (work, corner)


@FAST
@given(kind=st.sampled_from(["jenkins", "coulomb", "iwan"]),
       k=st.floats(1e3, 1e7), fs=st.floats(0.1, 100.0),
       history=st.lists(st.floats(-3.0, 3.0), min_size=1, max_size=10),
       target=st.floats(-4.0, 4.0))
def test_tangent_equals_finite_difference(kind, k, fs, history, target):
    law = _law(kind, k, fs)
    scale = fs / k
    st_ = law.initial_state()
    for x in history:                  # a state with a loading history
        st_ = law.step(st_, np.array([[x * scale]])).state
    u = np.array([[target * scale]])
    h = 1e-7 * scale
    r = law.step(st_, u)
    fp = law.step(st_, u + h).force
    fm = law.step(st_, u - h).force
    right = float((fp - r.force)[0, 0]) / h
    left = float((r.force - fm)[0, 0]) / h
    if abs(right - left) > 1e-6 * k:   # a stick/slip switch inside the step: no test
        return
    fd = 0.5 * (right + left)
    assert float(r.stiffness[0, 0, 0]) == pytest.approx(fd, abs=1e-6 * k)


@FAST
@given(k=st.floats(1e3, 1e8), fs=st.floats(0.1, 100.0),
       bad=st.sampled_from([math.nan, math.inf, -math.inf]), where=st.integers(0, 9))
def test_nan_and_inf_are_refused_at_the_law_boundary(k, fs, bad, where):
    from fricdamp.signals.energy import loop_area

    u = np.linspace(0.0, 1e-3, 10)
    u[where] = bad
    with pytest.raises(ModelError, match=f"entry {where + 1} "):
        Jenkins(k, fs).drive(u)
    with pytest.raises(ModelError, match="must be finite"):
        loop_area(u, np.ones(10))
    with pytest.raises(ModelError, match="stiffness must be finite"):
        Jenkins(bad, fs)


# ------------------------------------------------------------------------- case schema
BASE = """\
name = "prop"
[model]
type = "chain"
masses_kg = [1.0, 0.5]
springs_N_per_m = [1.0e4, 2.0e4]
dampers_Ns_per_m = [0.1, 0.1]
[[contacts]]
type = "jenkins"
dofs = [2]
stiffness_N_per_m = 1.0e4
slip_force_N = 1.0
[analysis.free_decay]
initial_displacement_m = [1.0e-3, 1.0e-3]
duration_s = 0.1
time_step_s = 1.0e-4
[analysis.forced_response]
force_amplitude_N = [1.0, 0.0]
frequency_hz = 20.0
periods = 5
steps_per_period = 32
[analysis.frf]
force_amplitude_N = [1.0, 0.0]
frequency_start_hz = 10.0
frequency_end_hz = 30.0
harmonics = 3
[solver]
method = "hht"
alpha = -0.1
"""

VALUES = st.one_of(
    st.none(), st.booleans(), st.integers(-10**12, 10**12),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=8),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
    st.lists(st.integers(-5, 5), max_size=4), st.dictionaries(st.text(max_size=4),
                                                              st.integers(), max_size=2),
    st.sampled_from([".", "/dev/zero", "hht", "newmark", "both", "first", 0, -1, 1e300]))


def _paths(node, prefix=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield (*prefix, k)
            yield from _paths(v, (*prefix, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield (*prefix, i)
            yield from _paths(v, (*prefix, i))


BASE_3D = """\
name = "prop3d"
[model]
type = "chain"
masses_kg = [1.0, 1.0, 1.0]
springs_N_per_m = [1.0e4, 1.0e4, 1.0e4]
ground = "first"
[[contacts]]
type = "contact3d"
normal = [1]
tangential = [[2], [3]]
normal_stiffness_N_per_m = 1.0e6
tangential_stiffness_N_per_m = 1.0e5
mu = 0.3
preload_N = 10.0
[[contacts]]
type = "coulomb"
between = [2, 3]
stiffness_N_per_m = 1.0e4
normal_load_N = 5.0
mu_static = 0.4
mu_sliding = 0.3
[[contacts]]
type = "cubic_spring"
dofs = [1]
k3_N_per_m3 = 1.0e9
[analysis.hysteresis]
amplitudes_m = [1.0e-5, 1.0e-4]
contacts = ["contact2"]
[analysis.nma]
amplitude_dof = 1
amplitudes_m = [1.0e-5, 1.0e-4]
"""

_BASES = {name: tomllib.loads(text) for name, text in (("1d", BASE), ("3d", BASE_3D))}
_PATHS = [(name, p) for name, data in _BASES.items() for p in _paths(data)]


def _mutate(data, path, op, value):
    parent = data
    for p in path[:-1]:
        parent = parent[p]
    last = path[-1]
    if op == "delete":
        if isinstance(parent, list):
            parent.pop(last)
        else:
            parent.pop(last)
    elif op == "add" and isinstance(parent, dict):
        parent[f"{last}_typo"] = value
    else:
        parent[last] = value
    return data


def _none_free(v):
    """TOML has no null: a None stands for a removed value."""
    return v is not None


@settings(max_examples=200, deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(path=st.sampled_from(_PATHS), op=st.sampled_from(["replace", "delete", "add"]),
       value=VALUES.filter(_none_free))
def test_a_mutated_case_is_valid_or_a_clean_case_error(path, op, value):
    from fricdamp.case import parse_case
    from fricdamp.runner import REGISTRY, build_system

    base, path = path
    data = _mutate(copy.deepcopy(_BASES[base]), path, op, value)
    try:
        case = parse_case(data, REGISTRY, text=BASE, default_name="prop")
        build_system(case, REGISTRY)
    except (CaseError, ModelError) as exc:
        msg = str(exc)
        assert msg and "\n" not in msg and "Traceback" not in msg
        assert len(msg) < 2000
