"""blas_threads: the BLAS pools limited inside the context and restored after it, with the
threadpoolctl controller kept between runs (found again after new imports)."""

import sys

from threadpoolctl import threadpool_info

from fricdamp.solvers import continuation


def _blas_threads():
    return [d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas"]


def test_limits_and_restores():
    before = _blas_threads()
    assert before, "no BLAS library found"
    with continuation.blas_threads(2):
        assert _blas_threads() == [2] * len(before)
    assert _blas_threads() == before
    with continuation.blas_threads(None):
        assert _blas_threads() == before


def test_controller_kept_until_new_imports(tmp_path, monkeypatch):
    with continuation.blas_threads(1):
        pass
    first = continuation._BLAS_CONTROLLER[0]
    with continuation.blas_threads(1):
        pass
    assert continuation._BLAS_CONTROLLER[0] is first          # no imports: reused
    (tmp_path / "fricdamp_probe_module_xyz.py").write_text("X = 1\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import fricdamp_probe_module_xyz  # noqa: F401

    try:
        with continuation.blas_threads(1):
            pass
        assert continuation._BLAS_CONTROLLER[0] is not first  # new module: found again
    finally:
        sys.modules.pop("fricdamp_probe_module_xyz", None)
