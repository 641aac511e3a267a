"""Peers that install from the package registries, run in their own environments.

A peer whose dependencies clash with the project's environment (pyHarm pins ``pandas<3`` and
pulls JAX and Jupyter) runs from a virtual environment that this module creates from the
pinned ``peers/requirements-<name>.txt`` (reproducible from the repository alone), under
``$FRICDAMP_PEERS_DIR`` (default ``~/.cache/fricdamp/peers``). Its driver script in ``peers/``
builds the same problem as the fricdamp benchmark, times itself with ``time.process_time``
and ``time.perf_counter`` (one BLAS thread, as here) and prints one JSON line.

Set ``FRICDAMP_BENCH_PEERS=0`` to skip the peers (their figures are then reported as not
run, never replaced by constants).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ONE_THREAD = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "NUMBA_NUM_THREADS": "1",
              "XLA_FLAGS": "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1"}


def enabled() -> bool:
    return os.environ.get("FRICDAMP_BENCH_PEERS", "1") != "0"


def environment(name: str) -> Path:
    """Python of the peer's environment, created on first use (minutes: downloads)."""
    req = HERE / "peers" / f"requirements-{name}.txt"
    root = Path(os.environ.get("FRICDAMP_PEERS_DIR", Path.home() / ".cache/fricdamp/peers"))
    pins = [ln for ln in req.read_text().splitlines() if ln and not ln.startswith("#")]
    version = next((ln.split("==")[1] for ln in pins if ln.lower().startswith(name)), "x")
    venv = root / f"{name}-{version}"
    python = venv / "bin" / "python"
    done = venv / ".fricdamp-complete"   # written last: an interrupted install is redone
    if not done.exists():
        print(f"creating the {name} environment in {venv} (once; a few minutes)",
              file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", "--clear", str(venv)], check=True)
        subprocess.run([str(python), "-m", "pip", "install", "-q", "-r", str(req)],
                       check=True)
        done.write_text(req.read_text())
    return python


def run(name: str, script: str, *args, timeout: float = 900.0) -> dict:
    """Run ``peers/<script>`` in the peer's environment; its JSON line, or {"error": ...}."""
    if not enabled():
        return {"error": "peers disabled (FRICDAMP_BENCH_PEERS=0)"}
    try:
        python = environment(name)
        out = subprocess.run([str(python), str(HERE / "peers" / script), *map(str, args)],
                             capture_output=True, text=True, timeout=timeout,
                             env={**os.environ, **ONE_THREAD}, cwd=str(HERE / "peers"))
    except (OSError, subprocess.SubprocessError) as exc:
        return {"error": f"{type(exc).__name__}: {exc}"}
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
    if out.returncode != 0 or not lines:
        tail = (out.stderr or out.stdout).strip().splitlines()[-3:]
        return {"error": f"exit {out.returncode}: {' | '.join(tail)}"}
    return json.loads(lines[-1])
