"""Contact-law kernels: compiled march vs a pure-Python loop over the same return map.

30 contacts x 1e5 time steps through ``Jenkins.march`` and ``Contact3D.march`` (numba,
one core), against a straightforward pure-Python double loop (time x contacts, float
arithmetic on lists) timed on the first ``N_PYTHON_STEPS`` steps and scaled per
contact-step. Both run in this process; the compiled kernels are warmed up first so that
numba compilation is excluded, and each timing is the best of ``REPEAT`` runs. The Python
loop's forces are checked against the kernel's before any number is reported.

Target (DESIGN.md, contact layer): >= 20 million contact-steps per second for Jenkins.
"""

from __future__ import annotations

import math
import time

import numpy as np

from fricdamp.contact import Jenkins
from fricdamp.contact.element3d import Contact3D

N_CONTACTS = 30
N_STEPS = 100_000
N_PYTHON_STEPS = 10_000
REPEAT = 3
TARGET = 20e6   # contact-steps/s, Jenkins, one core


def _histories(rng):
    """Multi-harmonic relative displacements: every contact sticks and slips."""
    t = np.arange(N_STEPS) / 2000.0                       # 2 kHz sampling, 50 s
    freqs = rng.uniform(5.0, 40.0, size=(3, N_CONTACTS))
    amps = rng.uniform(0.5e-3, 3e-3, size=(3, N_CONTACTS))
    ph = rng.uniform(0, 2 * np.pi, size=(3, N_CONTACTS))
    s = np.zeros((N_STEPS, N_CONTACTS, 3))
    for d in range(3):
        s[:, :, d] = amps[d] * np.sin(2 * np.pi * freqs[d] * t[:, None] + ph[d])
    s[:, :, 0] *= 0.05                                    # normal motion: mostly closed
    return s


def _best(fn, repeat=REPEAT):
    best = math.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


# ----------------------------------------------------------------- pure-Python references
def jenkins_python(u, kt, fs):
    """Jenkins return map, plain Python: u is a list (n_t) of lists (n_c)."""
    w = [0.0] * len(kt)
    out = []
    for row in u:
        frow = []
        for j, uj in enumerate(row):
            f = kt[j] * (uj - w[j])
            if f > fs[j]:
                f = fs[j]
                w[j] = uj - fs[j] / kt[j]
            elif f < -fs[j]:
                f = -fs[j]
                w[j] = uj + fs[j] / kt[j]
            frow.append(f)
        out.append(frow)
    return out


def contact3d_python(u, kn, kt, mu, g0):
    """3D contact return map, plain Python: u is a list (n_t) of lists (n_c) of 3-lists."""
    w = [[0.0, 0.0] for _ in kt]
    out = []
    for row in u:
        frow = []
        for j, (un, u1, u2) in enumerate(row):
            gap = un + g0[j]
            if gap <= 0.0:
                w[j] = [u1, u2]
                frow.append((0.0, 0.0, 0.0))
                continue
            nf = kn[j] * gap
            f1 = kt[j] * (u1 - w[j][0])
            f2 = kt[j] * (u2 - w[j][1])
            nrm = math.sqrt(f1 * f1 + f2 * f2)
            lim = mu[j] * nf
            if nrm > lim:
                scale = lim / nrm
                f1 *= scale
                f2 *= scale
                w[j] = [u1 - f1 / kt[j], u2 - f2 / kt[j]]
            frow.append((nf, f1, f2))
        out.append(frow)
    return out


def _compare(name, compiled, python):
    ref = np.asarray(python, dtype=float).reshape(compiled.shape)
    err = float(np.max(np.abs(compiled - ref)))
    scale = float(np.max(np.abs(ref)))
    if err > 1e-12 * scale:
        raise RuntimeError(f"{name}: compiled kernel and Python loop disagree by {err:g} N")


def run() -> dict:
    rng = np.random.default_rng(2024)
    s = _histories(rng)
    cs = N_CONTACTS * N_STEPS
    cs_py = N_CONTACTS * N_PYTHON_STEPS

    # ---- Jenkins (fricdamp.contact.Jenkins.march)
    kt = rng.uniform(0.5e3, 2e3, N_CONTACTS)
    fs = kt * rng.uniform(0.2e-3, 2e-3, N_CONTACTS)   # slip displacement vs 0.5-3 mm motion
    jen = Jenkins(kt, fs)
    uj = np.ascontiguousarray(s[:, :, 1:2])
    jen.march(uj[:10])                                 # warm-up: compile / load the cache
    t_j, (fj, _) = _best(lambda: jen.march(uj))
    uj_list = uj[:N_PYTHON_STEPS, :, 0].tolist()
    t_jp, fj_py = _best(lambda: jenkins_python(uj_list, kt.tolist(), fs.tolist()))
    _compare("Jenkins", fj[:N_PYTHON_STEPS, :, 0], fj_py)
    slip_j = float(np.mean(np.abs(np.abs(fj[:, :, 0]) - fs) < 1e-12 * fs))

    # ---- Contact3D
    kn = rng.uniform(1e5, 3e5, N_CONTACTS)
    law3 = Contact3D(kn, kt, 0.3, offset=1.2e-4 / 3)   # opens now and then (|u_n| <= 1.5e-4)
    law3.march(s[:10])
    t_3, (f3, _) = _best(lambda: law3.march(s))
    s_list = s[:N_PYTHON_STEPS].tolist()
    t_3p, f3_py = _best(lambda: contact3d_python(s_list, kn.tolist(), kt.tolist(),
                                                 law3.mu.tolist(), law3.offset.tolist()))
    _compare("Contact3D", f3[:N_PYTHON_STEPS], f3_py)
    open_3 = float(np.mean(f3[:, :, 0] == 0.0))

    rate_j, rate_jp = cs / t_j, cs_py / t_jp
    rate_3, rate_3p = cs / t_3, cs_py / t_3p
    passed = rate_j >= TARGET
    figure = (f"Jenkins {rate_j:.3g} contact-steps/s (ratio {rate_j / rate_jp:.0f}x vs Python "
              f"{rate_jp:.3g}); Contact3D {rate_3:.3g} (ratio {rate_3 / rate_3p:.0f}x vs "
              f"{rate_3p:.3g})")
    return {
        "name": "contact_kernel",
        "figure": figure,
        "value": rate_j,
        "target": TARGET,
        "unit": "contact-steps/s (Jenkins, one core)",
        "passed": bool(passed),
        "details": {
            "n_contacts": N_CONTACTS, "n_steps": N_STEPS, "python_steps": N_PYTHON_STEPS,
            "jenkins_rate": rate_j, "jenkins_python_rate": rate_jp,
            "jenkins_ratio": rate_j / rate_jp, "jenkins_slip_fraction": slip_j,
            "contact3d_rate": rate_3, "contact3d_python_rate": rate_3p,
            "contact3d_ratio": rate_3 / rate_3p, "contact3d_open_fraction": open_3,
        },
    }


if __name__ == "__main__":
    res = run()
    print(("PASS" if res["passed"] else "MISS"), res["name"], res["figure"])
    for k, v in res["details"].items():
        print(f"  {k}: {v:.4g}" if isinstance(v, float) else f"  {k}: {v}")
