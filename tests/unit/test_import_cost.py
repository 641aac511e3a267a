"""Import cost of the solvers (issue 13, item 3: a fast start).

Target: ``import fricdamp.solvers`` plus the harmonic-balance entry points cost at most
0.15 s of CPU on top of numpy, SciPy (sparse, linalg) and numba, measured when those took
0.42 s on the reference machine. On a shared machine absolute times drift with the load, so
the test compares CPU times measured in the same fresh interpreter (best of three
processes), with the bytecode cache allowed (``PYTHONDONTWRITEBYTECODE`` removed, one
process first to write it: compiling fricdamp's sources costs another ~0.06 s, which an
installed package never pays).

Figures of 2026-11-28 (shared 2-core VM, load 2-6): the fricdamp part 0.032-0.041 s against
0.59-0.74 s for numpy + SciPy + numba, ratio 0.055 (0.13-0.15 when the sources are compiled
at every import); the eager imports that the lazy ``__getattr__`` replaced cost ~0.25 s
(ratio ~0.9). The test asserts the measured figure with a margin for the load, ratio <=
:data:`RATIO_BUDGET` = 0.12 (2.2x the measured 0.055), well inside the target's 0.36.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

#: The issue's target (0.15 s on 0.42 s) and the regression budget actually asserted.
TARGET_RATIO = 0.15 / 0.42
RATIO_BUDGET = 0.12

_PROBE = r"""
import json, sys, time
t0 = time.process_time()
import numpy, scipy.sparse, scipy.sparse.linalg, scipy.linalg, numba
t1 = time.process_time()
import fricdamp.solvers
from fricdamp.solvers import frequency_response, harmonic_balance, solve_and_continue
t2 = time.process_time()
heavy = [m for m in ("scipy.integrate", "scipy.optimize", "scipy.io", "matplotlib", "dask",
                     "xarray", "pandas", "fricdamp.solvers.event", "fricdamp.solvers.timestep",
                     "fricdamp.contact.mindlin", "fricdamp.structure.beam3d",
                     ) if m in sys.modules]
print(json.dumps({"base": t1 - t0, "fricdamp": t2 - t1, "heavy": heavy}))
"""


def _probe() -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               NUMBA_NUM_THREADS="1")
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    out = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                         env=env, check=True, timeout=120)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_solvers_import_cost_within_budget():
    first = _probe()                # writes the bytecode cache if the sources changed
    assert first["heavy"] == [], f"the HB import path loads {first['heavy']}"
    runs = [_probe() for _ in range(3)]
    ratio = min(r["fricdamp"] / r["base"] for r in runs)
    assert RATIO_BUDGET < TARGET_RATIO
    assert ratio <= RATIO_BUDGET, (
        f"fricdamp.solvers import costs {ratio:.3f} x numpy+SciPy+numba (budget "
        f"{RATIO_BUDGET:.2f}, measured 0.055 at the change): {runs}")
