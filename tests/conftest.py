"""Test-suite settings shared by every test.

The suite runs in parallel (``pytest -n auto``, pytest-xdist, one process per core), so each
process keeps BLAS and numba to one thread: the small dense algebra of the tests gains nothing
from threads, and two processes with two threads each on two cores would oversubscribe the
machine. Set before numpy is imported (matplotlib imports it); a variable the caller already
set is kept.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
