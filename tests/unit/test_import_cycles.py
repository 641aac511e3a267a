"""No import cycle between fricdamp's modules at module level
(tools/import_cycles.py), and every module path moved by tools/relayout.py still imports, as
the new module itself."""

import importlib
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _tool(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "tools" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_no_module_level_import_cycle():
    cycles = _tool("import_cycles").cycles(ROOT / "src" / "fricdamp")
    assert cycles == [], "\n".join(" -> ".join(c) for c in cycles)


def test_the_checker_finds_a_planted_cycle(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from pkg.b import x\ny = 1\n")
    (pkg / "b.py").write_text("import pkg.c\nx = 1\n")
    (pkg / "c.py").write_text("def f():\n    from pkg.a import y\n")
    tool = _tool("import_cycles")
    assert tool.cycles(pkg) == []                   # closed only inside a function
    assert tool.cycles(pkg, function_level=True) == [["pkg.a", "pkg.b", "pkg.c", "pkg.a"]]
    (pkg / "c.py").write_text("from pkg import a\n")
    assert tool.cycles(pkg) == [["pkg.a", "pkg.b", "pkg.c", "pkg.a"]]


def _moved():
    from fricdamp._moved import MOVED

    return sorted(MOVED.items())


@pytest.mark.parametrize(("old", "new"), _moved())
def test_old_module_path_is_the_new_module(old, new):
    module = importlib.import_module(old)
    assert module is importlib.import_module(new)
    assert module.__name__ == new and module.__spec__.name == new
