"""The documentation builds without a warning, and its code really runs.

* ``mkdocs build --strict`` (the configuration in ``mkdocs.yml``, warnings as errors) into a
  temporary folder: the API reference from the docstrings, the validation table from
  ``tests/validation``, and the gallery, whose scripts are executed by the build and check
  their own numbers (a failing ``assert`` fails the build). Any line of the build's log at
  WARNING level or above fails the test, even one that strict mode would let through.
* Every ```` ```python ```` block of the README and of the hand-written pages (front page,
  getting started, user guide, periodic orbits) runs: the blocks of one page in order, in
  one namespace, as a user pasting them into one script would. Illustrations that must not
  run are fenced as ``text`` or ``pycon``.

Needs the ``[docs]`` extra (``pip install -e ".[docs]"``).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"

#: Pages whose python blocks are executed (the case-file pages hold sketches and runs of
#: minutes, which their own tests cover).
_BLOCK = re.compile(r"^```python[^\n]*\n(.*?)^```", re.S | re.M)
SNIPPET_PAGES = sorted(
    p for p in [ROOT / "README.md", DOCS / "index.md", DOCS / "getting-started.md",
                DOCS / "periodic_orbits.md", *(DOCS / "guide").glob("*.md")]
    if _BLOCK.search(p.read_text(encoding="utf-8")))


def _env() -> dict:
    env = dict(os.environ)
    env.update(MPLBACKEND="Agg", NO_MKDOCS_2_WARNING="1", OMP_NUM_THREADS="1",
               OPENBLAS_NUM_THREADS="1", PYTHONWARNINGS="default")
    return env


def test_docs_build_strict(tmp_path):
    pytest.importorskip("mkdocs", reason='the docs tools: pip install -e ".[docs]"')
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir",
         str(tmp_path / "site"), "--config-file", str(ROOT / "mkdocs.yml")],
        cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=600)
    log = proc.stdout + proc.stderr
    warnings = [ln for ln in log.splitlines() if re.match(r"^(WARNING|ERROR)\b", ln.strip())]
    assert proc.returncode == 0 and not warnings, (
        f"mkdocs build --strict failed (exit {proc.returncode}):\n" + "\n".join(warnings)
        + "\n--- log tail ---\n" + log[-4000:])
    site = tmp_path / "site"
    # what the build must have produced: API pages, validation table, executed gallery
    for page in ("api/solvers/index.html", "validation/index.html", "gallery/index.html"):
        assert (site / page).is_file(), page
    assert list((site / "gallery" / "images").glob("*.png")), "the gallery drew no figure"
    validation = (site / "validation" / "index.html").read_text(encoding="utf-8")
    for test_file in (ROOT / "tests" / "validation").glob("test_*.py"):
        assert test_file.name in validation, f"{test_file.name} missing from the table"


@pytest.mark.parametrize("page", SNIPPET_PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_page_snippets_run(page, tmp_path):
    blocks = _BLOCK.findall(page.read_text(encoding="utf-8"))
    source = "\n\n".join(textwrap.dedent(b) for b in blocks)
    script = tmp_path / "snippets.py"
    script.write_text(source, encoding="utf-8")
    # exec under ``python -c`` (no __main__ file): Dask's spawned workers do not re-run the
    # page, and functions defined in it are pickled by value, as from a user's script.
    runner = (f"src = open({str(script)!r}, encoding='utf-8').read()\n"
              f"exec(compile(src, {page.name!r}, 'exec'), {{'__name__': '__main__'}})")
    proc = subprocess.run([sys.executable, "-c", runner], cwd=tmp_path, env=_env(),
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, (f"{page.relative_to(ROOT)}: a python block failed\n"
                                  + proc.stdout[-2000:] + proc.stderr[-4000:])
