"""Build the validation table from the docstrings of ``tests/validation/*.py``.

Every validation test names its reference and its tolerance in its docstrings (the module
docstring for the whole file, the function docstring for one check). This script collects
them into one Markdown page, so the table cannot drift from the tests::

    python docs/_hooks/validation_table.py > validation.md

The docs build calls :func:`build_table` (``docs/_hooks/fricdamp_docs.py``).
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Numbers that read as tolerances: 1e-5, 1e-9, 0.1 %, 2e-3, 5 %.
_TOL = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?e-\d+|\d+(?:\.\d+)? ?%)")


def _cell(text: str | None) -> str:
    """One table cell: a docstring on one line, pipes escaped."""
    if not text:
        return "—"
    text = " ".join(text.split())
    return text.replace("|", "\\|")


def _tolerances(*texts: str | None) -> str:
    found: list[str] = []
    for text in texts:
        for m in _TOL.findall(text or ""):
            m = m.replace(" %", "%")
            if m not in found:
                found.append(m)
    return ", ".join(found) if found else "—"


def collect(folder: Path | None = None) -> list[dict]:
    """One entry per validation file: module docstring and its tests' docstrings."""
    folder = folder or ROOT / "tests" / "validation"
    files = []
    for path in sorted(folder.glob("test_*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        tests = []
        for node in tree.body:
            cls_tests = [node] if isinstance(node, ast.FunctionDef) else (
                [n for n in node.body if isinstance(n, ast.FunctionDef)]
                if isinstance(node, ast.ClassDef) else [])
            for fn in cls_tests:
                if fn.name.startswith("test"):
                    name = fn.name if fn is node else f"{node.name}.{fn.name}"
                    tests.append((name, ast.get_docstring(fn)))
        files.append({"path": path.relative_to(ROOT).as_posix(),
                      "doc": ast.get_docstring(tree), "tests": tests})
    return files


def build_table(folder: Path | None = None) -> str:
    """Markdown page: a summary table of the files, then each file's tests."""
    files = collect(folder)
    n_tests = sum(len(f["tests"]) for f in files)
    out = [
        "# Validation",
        "",
        "Every model and solver is checked against a closed form, a conservation law or a "
        "paper's stated result, with a stated and justified tolerance. This page is built from "
        "the docstrings of `tests/validation/*.py` when the documentation is built "
        "(`docs/_hooks/validation_table.py`): what you read here is what the tests check. "
        f"{len(files)} files, {n_tests} tests. Run them with "
        "`python -m pytest tests/validation` (`-m 'not slow'` leaves out the long cases).",
        "",
        "The *tolerances* column lists the numbers of the docstrings that read as tolerances "
        "(`1e-6`, `0.1 %`); the text says which applies to what and why.",
        "",
        "| file | reference and tolerance (module docstring, first paragraph) | tests | "
        "tolerances |",
        "|---|---|---|---|",
    ]
    for f in files:
        first = (f["doc"] or "").split("\n\n")[0]
        tols = _tolerances(f["doc"], *(d for _, d in f["tests"]))
        anchor = Path(f["path"]).stem.replace("_", "-")
        out.append(f"| [`{Path(f['path']).name}`](#{anchor}) | {_cell(first)} | "
                   f"{len(f['tests'])} | {tols} |")
    for f in files:
        name = Path(f["path"]).stem
        out += ["", f"## {name} {{ #{name.replace('_', '-')} }}", "",
                f"`{f['path']}`", ""]
        if f["doc"]:
            out += ["```text", f["doc"].replace("```", "'''"), "```", ""]
        out += ["| test | what it checks, reference and tolerance | tolerances |",
                "|---|---|---|"]
        for test, doc in f["tests"]:
            out.append(f"| `{test}` | {_cell(doc)} | {_tolerances(doc)} |")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    sys.stdout.write(build_table(Path(sys.argv[1]) if len(sys.argv) > 1 else None))
