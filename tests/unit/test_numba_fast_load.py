"""Cached numba kernels load without numba's registry refresh (fricdamp._numba_cache).

The refresh imports ~200 modules of numba's registries (random generators, typed
containers, unicode, jitclass) and cost ~0.45 s of CPU per process on the reference VM; the
kernels of harmonic balance need none of them once compiled. Checked in fresh processes:
a kernel compiled through :func:`fricdamp._numba_cache.njit` (cache miss: numba's ordinary
compilation) and then loaded from its cache in another process gives the same values and
the same exception, and the loading process never imports the registries; an HB curve from
a warm cache does not import them either.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import pytest

#: Modules that only numba's registry refresh imports (none of them is on the HB path).
REGISTRY_ONLY = ("numba.typed.typeddict", "numba.np.random.generator_core",
                 "numba.typed.typedlist", "numba.experimental.jitclass.base")

_KERNEL = textwrap.dedent('''
    import numpy as np
    from fricdamp._numba_cache import njit

    @njit(nogil=True)
    def kernel(x, n):
        if n < 0:
            raise ValueError("n must be >= 0")
        out = np.empty(n)
        for i in range(n):
            out[i] = np.sin(x[i % x.size]) * (i + 1)
        return out, np.sum(out)
''')

_RUN = textwrap.dedent('''
    import json, sys
    sys.path.insert(0, sys.argv[1])
    import numpy as np
    import kernel_mod
    out, total = kernel_mod.kernel(np.linspace(0.0, 1.0, 7), 11)
    try:
        kernel_mod.kernel(np.ones(2), -1)
        err = None
    except ValueError as exc:
        err = str(exc)
    hits = sum(kernel_mod.kernel.stats.cache_hits.values())
    print(json.dumps({"out": out.tolist(), "total": total, "err": err, "hits": hits,
                      "registries": [m for m in __REGISTRIES__ if m in sys.modules]}))
''').replace("__REGISTRIES__", repr(REGISTRY_ONLY))


def _run(code: str, *args: str, env: dict | None = None) -> dict:
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                         env=env, check=True, timeout=300)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_compiled_then_cached_kernel_same_values_without_registries(tmp_path):
    (tmp_path / "kernel_mod.py").write_text(_KERNEL)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    first = _run(_RUN, str(tmp_path), env=env)           # compiles (cache miss), saves
    second = _run(_RUN, str(tmp_path), env=env)          # loads from the cache
    assert first["hits"] == 0
    assert second["hits"] >= 1, "the second process did not load the kernel from its cache"
    assert second["out"] == first["out"] and second["total"] == first["total"]
    assert first["err"] == second["err"] == "n must be >= 0"
    assert second["registries"] == [], f"cache load refreshed numba: {second['registries']}"
    # the compiling process does need them (the fast path only skips the load's refresh)
    assert first["registries"] != []


_HB = textwrap.dedent('''
    import json, sys
    import numpy as np, scipy.sparse as sp
    from fricdamp.contact import Jenkins
    from fricdamp.solvers import frequency_response
    from fricdamp.solvers.hb import engine_order_load
    from fricdamp.structure import ContactElement, MechanicalSystem
    n = 6
    K = sp.diags([1.1] * n) - 0.05 * (sp.eye(n, k=1) + sp.eye(n, k=-1))
    P = -sp.eye(n) + sp.eye(n, k=1, format="lil")
    P = sp.lil_matrix(P); P[n - 1, 0] = 1.0
    sysm = MechanicalSystem(M=sp.identity(n, format="csr"), K=sp.csr_matrix(K),
                            D=0.005 * sp.identity(n, format="csr"),
                            contacts=(ContactElement(Jenkins(0.5, 0.02, n_contacts=n),
                                                     P.tocsr(), name="j"),),
                            loads=(engine_order_load(n, 1, 0.01),))
    fr = frequency_response(sysm, 0.9, 1.3, harmonics=3, samples=32, max_points=20)
    print(json.dumps({"ok": bool(fr.n_points > 5),
                      "registries": [m for m in __REGISTRIES__ if m in sys.modules]}))
''').replace("__REGISTRIES__", repr(REGISTRY_ONLY))


@pytest.mark.filterwarnings("ignore")
def test_hb_curve_from_warm_cache_skips_numba_registries():
    _run(_HB)                      # fills the cache if the sources changed
    out = _run(_HB)
    assert out["ok"]
    assert out["registries"] == [], f"the HB path refreshed numba: {out['registries']}"
