"""Move fricdamp's modules to a layout by idea (issue 18, item 4); idempotent, run at the repo root.

``python tools/relayout.py [--dry-run] [--changelog]``

Why: three places were called "analysis" (``analysis/``: post-processing of signals;
``analyses/``: what a case file can ask for; ``models/*_analyses.py``: the papers' studies), a
paper's system was spread over three files in two folders, and the CLI was four sibling modules.

The layout (old -> new, module paths; the full table is :data:`MOVES`):

* ``fricdamp.analysis``  -> ``fricdamp.signals`` (measured and simulated signals: loops, energy,
  decay, damping, identification, fitting, UFF); its ``signals`` module, the records/CSV/FFT
  helpers, becomes ``fricdamp.signals.records`` (no ``signals.signals``).
* ``fricdamp.analyses.{timedomain,frequency,periodic}`` -> ``fricdamp.cases.*``: the case-file
  analyses that apply to any model.
* each paper's system is a subpackage ``fricdamp.models.<system>`` holding its model
  (``model``), its studies (``studies``, formerly ``models/<system>_analyses.py``), its case-file
  section (``case``, formerly ``analyses/<system>.py``) and their private helpers:
  ``blade_damper`` (paper 000), ``blade_pair`` (001), ``rotational_joint`` (002),
  ``tieboss_wheel`` (003, beam and solid wheel). The subpackage's ``__init__`` re-exports
  every name of its ``model`` module, so ``from fricdamp.models.blade_damper import X`` works
  as before. ``models/contact_wheel.py`` (generic FE-sector wheel) stays where it is.
* ``fricdamp.cli``, ``cli_studies``, ``cli_identify``, ``cli_fit`` -> package ``fricdamp.cli``:
  ``cli.app`` (parser, ``main``; ``run``, ``check``, ``demo``), ``cli.studies`` (``sweep``,
  ``optimize``), ``cli.identify``, ``cli.fit``; ``fricdamp.cli`` re-exports ``cli.app``
  (the console script ``fricdamp.cli:main`` is unchanged), ``python -m fricdamp.cli`` works.
* import circle ``runner`` <-> ``analyses.timedomain`` (the only module-level one): the
  registry and run machinery move down into ``fricdamp.registry`` (runner.py up to its
  "built-ins" part, i.e. up to ``def _import_analyses``); ``fricdamp.runner`` keeps every
  name (re-exported) and imports the built-in case-file sections (``fricdamp.cases.*`` and
  ``fricdamp.models.<system>.case*``). The case-file sections import ``fricdamp.registry``.

Every old module path keeps working: ``fricdamp/_moved.py`` (generated from :data:`MOVES`)
installs an import hook that maps each old dotted name to its new module (the same module
object, so ``isinstance`` and monkeypatching agree); ``fricdamp/__init__.py`` imports it.

What it does, in order (each step skipped when already done, so a re-run is a no-op):

1. ``git mv`` every file of :data:`MOVES` whose old file exists and new file does not;
   new package ``__init__`` files are written (``cli/__init__`` and ``cli/__main__``,
   ``models/<system>/__init__``, ``cases/__init__`` from ``analyses/__init__``).
2. splits ``runner.py`` into ``registry.py`` + ``runner.py`` (located with ``ast``).
3. rewrites every old dotted module path (``fricdamp.a.b``, also ``fricdamp/a/b.py`` file
   paths) in src/, tests/, examples/, benchmarks/, docs/, README.md, mkdocs.yml, with one
   anchored regex per old name (longest first; a name followed by ``.<child of its new
   package>`` or ``:`` is left alone, so re-runs do not rewrite twice), plus a few named
   textual fixes (:data:`TEXT_FIXES`), each reported when it does not apply.
4. writes ``fricdamp/_moved.py`` and prints the CHANGELOG "Moved" section (``--changelog``
   inserts it under ``## Unreleased`` of CHANGELOG.md, once).

It touches file contents only in import lines / dotted module paths and the named fixes, so
other edits to the moved files in the meantime do not matter.
"""

from __future__ import annotations

import argparse
import ast
import re
import subprocess
import sys
from pathlib import Path

PKG = Path("src/fricdamp")

#: old module (relative to fricdamp) -> new module. Packages are listed by their __init__.
MOVES: dict[str, str] = {
    # signal post-processing
    "analysis": "signals",
    "analysis._identify_core": "signals._identify_core",
    "analysis._identify_force": "signals._identify_force",
    "analysis._identify_trust": "signals._identify_trust",
    "analysis._identify_window": "signals._identify_window",
    "analysis.damping": "signals.damping",
    "analysis.decay": "signals.decay",
    "analysis.energy": "signals.energy",
    "analysis.fit": "signals.fit",
    "analysis.identify": "signals.identify",
    "analysis.signals": "signals.records",
    "analysis.uff": "signals.uff",
    # generic case-file analyses
    "analyses": "cases",
    "analyses.timedomain": "cases.timedomain",
    "analyses.frequency": "cases.frequency",
    "analyses.periodic": "cases.periodic",
    # paper 000
    "models.blade_damper": "models.blade_damper.model",
    "models._blade_damper_compiled": "models.blade_damper._compiled",
    "models._blade_damper_kinematics": "models.blade_damper._kinematics",
    "models.blade_damper_orbits": "models.blade_damper.orbits",
    "models.blade_damper_analyses": "models.blade_damper.studies",
    "analyses.blade_damper": "models.blade_damper.case",
    # paper 001
    "models.blade_pair": "models.blade_pair.model",
    "models.blade_pair_hb": "models.blade_pair.hb",
    "models.blade_pair_analyses": "models.blade_pair.studies",
    "analyses.blade_pair": "models.blade_pair.case",
    "analyses._blade_pair_figures": "models.blade_pair._case_figures",
    # paper 002
    "models.rotational_joint": "models.rotational_joint.model",
    "models._rotational_joint_curves": "models.rotational_joint._curves",
    "models._rotational_joint_dynamics": "models.rotational_joint._dynamics",
    "models._rotational_joint_rig": "models.rotational_joint._rig",
    "analyses.rotational_joint": "models.rotational_joint.case",
    # paper 003 (beam wheel and solid wheel)
    "models.tieboss_wheel": "models.tieboss_wheel.model",
    "models.tieboss_analyses": "models.tieboss_wheel.studies",
    "models.tieboss_excitation": "models.tieboss_wheel.excitation",
    "models.tieboss_forced": "models.tieboss_wheel.forced",
    "models.tieboss_gap": "models.tieboss_wheel.gap",
    "models.tieboss_solid": "models.tieboss_wheel.solid",
    "models._tieboss_solid_geometry": "models.tieboss_wheel._solid_geometry",
    "models.solid_campbell": "models.tieboss_wheel.solid_campbell",
    "models.solid_forced": "models.tieboss_wheel.solid_forced",
    "analyses.tieboss_wheel": "models.tieboss_wheel.case",
    "analyses.tieboss_wheel_solid": "models.tieboss_wheel.case_solid",
    "analyses._tieboss_figures": "models.tieboss_wheel._case_figures",
    "analyses._tieboss_forced": "models.tieboss_wheel._case_forced",
    "analyses._tieboss_spec": "models.tieboss_wheel._case_spec",
    # command line
    "cli": "cli.app",
    "cli_studies": "cli.studies",
    "cli_identify": "cli.identify",
    "cli_fit": "cli.fit",
}

#: The systems' subpackages (their __init__ re-exports their ``model`` module).
SYSTEMS = {
    "blade_damper": "paper 000, planar blade-damper stick-slip model",
    "blade_pair": "paper 001, two rotating shrouded blades with a wedge friction element",
    "rotational_joint": "paper 002, rotational friction joint test rig",
    "tieboss_wheel": "paper 003, bladed wheel with tie-boss friction contacts (beam and solid)",
}

#: Directories and top-level files whose text is rewritten.
TREES = ("src", "tests", "examples", "benchmarks", "docs", "tools")
FILES = ("README.md", "mkdocs.yml", "pyproject.toml", "CONTRIBUTING.md")
SUFFIXES = {".py", ".md", ".yml", ".yaml", ".toml", ".txt", ".cfg", ".ini", ".rst"}
SKIP = {"tools/relayout.py", "CHANGELOG.md"}

#: Named textual fixes: (file, old, new). Applied when ``old`` is found; reported when
#: neither ``old`` nor ``new`` is (the file changed: check by hand).
TEXT_FIXES: list[tuple[str, str, str]] = [
    ("src/fricdamp/cli/app.py", '("cli_studies", "cli_identify", "cli_fit")',
     '("cli.studies", "cli.identify", "cli.fit")'),
    ("mkdocs.yml", "- fricdamp.signals: api/analysis.md", "- fricdamp.signals: api/signals.md"),
    ("docs/_hooks/fricdamp_docs.py", '("fricdamp.signals", "analysis",',
     '("fricdamp.signals", "signals",'),
    ("src/fricdamp/__init__.py", '("analyses", "analysis", "contact", "models", "solvers",',
     '("analyses", "analysis", "cases", "cli", "contact", "models", "signals",\n'
     '                "solvers",'),
]


# lines the longer module paths push past 100 characters (checked by ruff after the rewrite)
TEXT_FIXES += [
    ("src/fricdamp/models/rotational_joint/_dynamics.py",
     "The\nequations and the integration scheme are written out in "
     ":mod:`fricdamp.models.rotational_joint.model`.",
     "The\nequations and the integration scheme are written out in\n"
     ":mod:`fricdamp.models.rotational_joint.model`."),
    ("src/fricdamp/models/rotational_joint/case.py",
     '"""The :class:`~fricdamp.models.rotational_joint.model.RotationalJointRig` with '
     '``rig_joint``."""',
     '"""The :class:`~fricdamp.models.rotational_joint.model.RotationalJointRig` with\n'
     '        ``rig_joint``."""'),
    ("src/fricdamp/models/tieboss_wheel/case_solid.py",
     "    solid, :mod:`fricdamp.models.tieboss_wheel.solid_campbell`) and the critical speeds "
     "003 (1); the same\n    summary keys as the beam wheel's ``campbell_by_nd``. Each critical "
     "speed is checked by a\n",
     "    solid, :mod:`fricdamp.models.tieboss_wheel.solid_campbell`) and the critical speeds\n"
     "    003 (1); the same summary keys as the beam wheel's ``campbell_by_nd``. Each critical\n"
     "    speed is checked by a\n"),
    ("tests/validation/test_solid_campbell.py",
     '"""Campbell diagram of a solid wheel (fricdamp.models.tieboss_wheel.solid_campbell) on '
     'the shipped coarse\nsector',
     '"""Campbell diagram of a solid wheel (fricdamp.models.tieboss_wheel.solid_campbell) on\n'
     'the shipped coarse sector'),
]


# the prose that names the folders (README's tree, the architecture page)
TEXT_FIXES += [
    ("README.md",
     "  analysis/    loop area and energy,", "  signals/     loop area and energy,"),
    ("README.md",
     "  models/      the papers' systems\n",
     "  models/      the papers' systems, one subpackage each: model, studies, "
     "case-file section\n"),
    ("README.md",
     "  analyses/    what a case file can ask for (each module registers its tables)\n"
     "  cli.py case.py runner.py report.py plot.py\n",
     "  cases/       the case-file analyses that apply to any model (each module registers "
     "its tables)\n"
     "  cli/         the fricdamp command, one module per group of sub-commands\n"
     "  case.py registry.py runner.py report.py plot.py\n"),
    ("docs/architecture.md", '    analysis["<b>analysis</b><br/>',
     '    signals["<b>signals</b><br/>'),
    ("docs/architecture.md", "    models --> analysis\n", "    models --> signals\n"),
    ("docs/architecture.md", "    analysis --> structure\n", "    signals --> structure\n"),
    ("docs/architecture.md", "**analysis** — post-processing", "**signals** — post-processing"),
    ("docs/architecture.md",
     "**models** — the papers' systems, ready to run, each a builder of a system and its studies\n"
     "(pull-off curves, Campbell diagrams, free-decay damping by nodal diameter, ...).",
     "**models** — the papers' systems, ready to run, one subpackage each "
     "(`models/<system>/`): the\nbuilder of the system (`model`), its studies (`studies`: "
     "pull-off curves, Campbell diagrams,\nfree-decay damping by nodal diameter, ...) and its "
     "case-file section (`case`)."),
    ("docs/architecture.md",
     "allowed range), a runner that calls the analyses a case asks for,",
     "allowed range), a registry of what a case may ask for (`fricdamp.registry`; the generic\n"
     "analyses are in `fricdamp.cases`, each system's in its `case` module), a runner that "
     "calls\nthe analyses a case asks for,"),
]


def log(msg: str) -> None:
    print(msg, flush=True)


def old_file(old: str) -> Path:
    """Source file of an old module (relative to fricdamp): a package by its __init__."""
    if old in ("analysis", "analyses"):
        return PKG / old / "__init__.py"
    return PKG.joinpath(*old.split(".")).with_suffix(".py")


def new_file(new: str) -> Path:
    if new in ("signals", "cases"):
        return PKG / new / "__init__.py"
    return PKG.joinpath(*new.split(".")).with_suffix(".py")


def git(*args: str, check: bool = True) -> str:
    return subprocess.run(["git", *args], check=check, capture_output=True, text=True).stdout


def tracked(path: Path) -> bool:
    return bool(git("ls-files", "--error-unmatch", str(path), check=False).strip())


# ------------------------------------------------------------------------------ 1. moves
def do_moves(dry: bool) -> set[str]:
    """git mv each pending move; return the old module names moved."""
    done = set()
    for old, new in MOVES.items():
        src, dst = old_file(old), new_file(new)
        if not src.is_file():
            continue
        if dst.is_file():
            log(f"  ! both {src} and {dst} exist: left alone (merge by hand)")
            continue
        log(f"git mv {src} {dst}")
        done.add(old)
        if dry:
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        if tracked(src):
            git("mv", str(src), str(dst))
        else:
            src.rename(dst)
    if not dry:
        for old in ("analysis", "analyses"):
            d = PKG / old
            if d.is_dir():
                left = [p for p in d.rglob("*") if p.is_file() and "__pycache__" not in p.parts]
                if left:
                    log(f"  ! {d} still holds {[str(p) for p in left]}: not in MOVES, move by hand")
                else:
                    for p in sorted(d.rglob("*"), reverse=True):
                        p.unlink() if p.is_file() else p.rmdir()
                    d.rmdir()
    return done


def write_new(path: Path, text: str, dry: bool) -> None:
    if path.is_file():
        return
    log(f"write {path}")
    if not dry:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        git("add", str(path))


def package_inits(dry: bool) -> None:
    for system, what in SYSTEMS.items():
        write_new(PKG / "models" / system / "__init__.py", (
            f'"""The {system.replace("_", "-")} system:\n{what}.\n\n'
            f"Its model is :mod:`fricdamp.models.{system}.model` (every name of it is available "
            "here,\nso ``from fricdamp.models."
            f"{system} import ...`` works as before the move); its\n"
            "studies, case-file section (``case``) and private helpers are the other modules.\n"
            '"""\n\n'
            "import importlib as _importlib\n\n\n"
            "def __getattr__(name: str):\n"
            "    # the model's names, imported on first use (the case-file section does not\n"
            "    # need the model to register itself)\n"
            "    model = _importlib.import_module(f\"{__name__}.model\")\n"
            "    try:\n"
            "        return getattr(model, name)\n"
            "    except AttributeError:\n"
            "        raise AttributeError(f\"module {__name__!r} has no attribute {name!r}\") "
            "from None\n"), dry)
    write_new(PKG / "cli" / "__init__.py", (
        '"""The ``fricdamp`` command: one module per group of sub-commands.\n\n'
        "* :mod:`fricdamp.cli.app` -- the parser, ``main``; ``run``, ``check``, ``demo``\n"
        "* :mod:`fricdamp.cli.studies` -- ``sweep``, ``optimize``\n"
        "* :mod:`fricdamp.cli.identify` -- ``identify``\n"
        "* :mod:`fricdamp.cli.fit` -- ``fit``\n\n"
        "Every name of :mod:`fricdamp.cli.app` is re-exported here (``fricdamp.cli:main`` is the\n"
        "console script).\n"
        '"""\n\n'
        "from fricdamp.cli import app as _app\n\n"
        "globals().update({_k: _v for _k, _v in vars(_app).items()\n"
        "                  if not (_k.startswith(\"__\") and _k.endswith(\"__\"))})\n"
        "del _app\n"), dry)
    write_new(PKG / "cli" / "__main__.py", (
        '"""``python -m fricdamp.cli``: the ``fricdamp`` command."""\n\n'
        "import sys\n\n"
        "from fricdamp.cli.app import main\n\n"
        'if __name__ == "__main__":\n'
        "    sys.exit(main())\n"), dry)


# ------------------------------------------------------------------- 2. runner -> registry
RUNNER_HEAD = '''"""Run a validated case: :mod:`fricdamp.registry` and the built-in analyses.

Importing this module registers every built-in case-file section: the generic analyses of
:mod:`fricdamp.cases` and the ``case``/``case_*`` modules of each system under
:mod:`fricdamp.models`. Every name of :mod:`fricdamp.registry` is available here too (the
registry, ``load_case``, ``run_case``, ...), so user code imports this module.
"""

from __future__ import annotations

import importlib as _importlib
import pkgutil as _pkgutil

import numpy as np

from fricdamp import registry as _registry
%%REGISTRY_IMPORT%%

# the registry's private names too (``fricdamp.runner._x`` as before the split)
globals().update({_k: _v for _k, _v in vars(_registry).items()
                  if not (_k.startswith("__") and _k.endswith("__"))})
__all__ = list(_registry.__all__)


def builtin_case_modules() -> list[str]:
    """The modules that register the built-in case-file sections, in registration order:
    every public module of :mod:`fricdamp.cases` and every ``case``/``case_*`` module of a
    system subpackage of :mod:`fricdamp.models` (ordered by ``<system><suffix>``, the order
    of the former analyses package)."""
    import fricdamp.cases as cases
    import fricdamp.models as models

    found = []
    for info in _pkgutil.iter_modules(cases.__path__):
        if not info.name.startswith("_"):
            found.append((info.name, f"fricdamp.cases.{info.name}"))
    for system in _pkgutil.iter_modules(models.__path__):
        if not system.ispkg or system.name.startswith("_"):
            continue
        pkg = _importlib.import_module(f"fricdamp.models.{system.name}")
        for info in _pkgutil.iter_modules(pkg.__path__):
            if info.name == "case" or info.name.startswith("case_"):
                found.append((system.name + info.name[4:],
                              f"fricdamp.models.{system.name}.{info.name}"))
    return [mod for _, mod in sorted(found)]


def _import_analyses() -> None:
    """Import every module of :func:`builtin_case_modules` (each registers its tables)."""
    for mod in builtin_case_modules():
        _importlib.import_module(mod)


'''


def split_runner(dry: bool) -> None:
    runner, registry = PKG / "runner.py", PKG / "registry.py"
    if registry.is_file():
        return
    text = runner.read_text(encoding="utf-8")
    tree = ast.parse(text)
    body = tree.body
    idx = next((i for i, n in enumerate(body)
                if isinstance(n, ast.FunctionDef) and n.name == "_import_analyses"), None)
    if idx is None:
        log("  ! runner.py has no `def _import_analyses`: split runner.py by hand")
        return
    lines = text.splitlines(keepends=True)
    fn = body[idx]
    start = (fn.decorator_list[0].lineno if fn.decorator_list else fn.lineno) - 1
    # the comment block just above the function goes with it
    cut = start
    while cut > 0 and (lines[cut - 1].startswith("#") or not lines[cut - 1].strip()):
        cut -= 1
    head, tail = "".join(lines[:cut]).rstrip() + "\n", lines[fn.end_lineno:]
    head = head.replace('"""Run a validated case: the registry of model types, contact types '
                        'and analyses.',
                        '"""The registry of model types, contact types and analyses, and the '
                        'run of a case.\n\n'
                        'Case-file sections register themselves here; :mod:`fricdamp.runner` '
                        'imports the\nbuilt-in ones (use that module to run cases).', 1)
    # __all__: the registry lists what it defines; the runner keeps the old list
    all_node = next((n for n in body if isinstance(n, ast.Assign)
                     and any(isinstance(t, ast.Name) and t.id == "__all__" for t in n.targets)),
                    None)
    runner_all = "list(_registry.__all__)"
    if all_node is not None and all_node.end_lineno <= cut:
        old_all = ast.literal_eval(all_node.value)
        defined = set()
        for n in body[:idx]:
            if isinstance(n, (ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef)):
                defined.add(n.name)
            elif isinstance(n, (ast.Assign, ast.AnnAssign)):
                for t in (n.targets if isinstance(n, ast.Assign) else [n.target]):
                    defined |= {x.id for x in ast.walk(t) if isinstance(x, ast.Name)}
            elif isinstance(n, (ast.Import, ast.ImportFrom)):
                defined |= {(a.asname or a.name).split(".")[0] for a in n.names}
        reg_all = [x for x in old_all if x in defined]
        seg_lines = lines[all_node.lineno - 1:all_node.end_lineno]
        seg = "".join(seg_lines)
        new_seg = "__all__ = [\n" + "".join(f'    "{x}",\n' for x in reg_all) + "]\n"
        head = head.replace(seg, new_seg, 1)
        runner_all = "[\n" + "".join(f'    "{x}",\n' for x in old_all) + "]"
    reg_import = "from fricdamp.registry import *  # noqa: F403"
    if all_node is not None and all_node.end_lineno <= cut:
        reg_import = ("from fricdamp.registry import (  # noqa: F401 (re-exported)\n"
                      + "".join(f"    {x},\n" for x in sorted(reg_all, key=str.lower)) + ")")
    new_runner = (RUNNER_HEAD.replace("list(_registry.__all__)", runner_all)
                  .replace("%%REGISTRY_IMPORT%%", reg_import)
                  + "".join(tail).lstrip("\n"))
    log("split runner.py -> registry.py (registry and run) + runner.py (built-in analyses)")
    if dry:
        return
    git("mv", str(runner), str(registry))
    registry.write_text(head, encoding="utf-8")
    runner.write_text(new_runner, encoding="utf-8")
    git("add", str(registry), str(runner))


# ------------------------------------------------------- 2b. shared pieces to lower modules
#: (source module, new lower module, names, docstring of the new module, modules whose
#: ``from <source> import ...`` lines naming only moved names now import the lower module)
SHARED: list[tuple[str, str, tuple[str, ...], str, tuple[str, ...]]] = [
    ("structure.reduction", "structure.eigen", ("_dof_array", "eigenpairs"),
     "Generalised symmetric eigen-solutions and DOF-index checks shared by the component-mode\n"
     "reduction (:mod:`fricdamp.structure.reduction`) and cyclic symmetry\n"
     "(:mod:`fricdamp.structure.cyclic`, :mod:`fricdamp.structure.cyclic_reduction`); both\n"
     "import them from here (``reduction`` re-exports them), so neither imports the other at\n"
     "module level.",
     ("structure.cyclic", "structure.cyclic_reduction", "solvers.modal")),
    ("models.blade_damper.studies", "models.blade_damper.configurations",
     ("CONFIGURATIONS", "configuration_codes", "_system"),
     "The blade damper's contact configurations (stick/slip of each contact) and the cached\n"
     "system of a parameter set, shared by its studies (:mod:`fricdamp.models.blade_damper."
     "studies`,\nwhich re-exports them) and its periodic orbits "
     "(:mod:`fricdamp.models.blade_damper.orbits`).",
     ("models.blade_damper.orbits",)),
]


def _top_names(node: ast.stmt) -> set[str]:
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
        return {node.name}
    if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
        targets = node.targets if isinstance(node, ast.Assign) else [node.target]
        return {x.id for t in targets for x in ast.walk(t) if isinstance(x, ast.Name)}
    return set()


def _span(lines: list[str], node: ast.stmt) -> tuple[int, int]:
    """0-based [start, end) lines of a top-level statement with its decorators and the
    comment lines right above it."""
    start = (node.decorator_list[0].lineno if getattr(node, "decorator_list", None)
             else node.lineno) - 1
    while start > 0 and lines[start - 1].lstrip().startswith("#"):
        start -= 1
    return start, node.end_lineno


def extract_shared(src_mod: str, dst_mod: str, names: tuple[str, ...], doc: str,
                   importers: tuple[str, ...], dry: bool) -> None:
    src = PKG.joinpath(*src_mod.split(".")).with_suffix(".py")
    dst = PKG.joinpath(*dst_mod.split(".")).with_suffix(".py")
    if dst.is_file() or not src.is_file():
        return
    text = src.read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    tree = ast.parse(text)
    defs = {}
    for node in tree.body:
        for name in _top_names(node):
            defs.setdefault(name, node)
    missing = [n for n in names if n not in defs]
    if missing:
        log(f"  ! {src}: {missing} not found: move the shared piece of {src_mod} by hand")
        return
    # the names and every top-level definition of the source they use
    todo, chosen = list(names), []
    while todo:
        node = defs[todo.pop()]
        if node in chosen:
            continue
        chosen.append(node)
        used = {x.id for x in ast.walk(node) if isinstance(x, ast.Name)}
        todo += [u for u in used if u in defs and defs[u] not in chosen]
    chosen.sort(key=lambda n: n.lineno)
    moved = sorted(set().union(*(_top_names(n) for n in chosen)), key=str.lower)
    imports = [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]
    head = "".join("".join(lines[n.lineno - 1:n.end_lineno]) for n in imports)
    body = "\n\n".join("".join(lines[a:b]).rstrip() + "\n"
                        for a, b in (_span(lines, n) for n in chosen))
    new_text = f'"""{doc}\n"""\n\n{head}\n\n{body}'
    # the source keeps the names (re-exported from the lower module)
    keep = lines[:]
    for n in reversed(chosen):
        a, b = _span(lines, n)
        del keep[a:b]
        while a < len(keep) and a > 0 and not keep[a].strip() and not keep[a - 1].strip():
            del keep[a]
    last_import = max(n.end_lineno for n in imports)
    reexport = (f"from fricdamp.{dst_mod} import (  # noqa: F401 (moved there, kept here)\n"
                + "".join(f"    {m},\n" for m in moved) + ")\n")
    keep.insert(last_import, reexport)
    log(f"move {moved} from {src} to {dst} (re-exported by {src_mod})")
    if dry:
        return
    dst.write_text(new_text, encoding="utf-8")
    src.write_text("".join(keep), encoding="utf-8")
    git("add", str(dst))
    ruff_run(["check", "--select", "F401,I", "--fix", "--quiet", str(dst)])
    ruff_run(["check", "--select", "F401,I", "--fix", "--quiet", str(src)])
    pat = re.compile(r"^(\s*)from fricdamp\." + re.escape(src_mod)
                     + r" import ([\w, ]+|\([\w,\s]+\))", re.M)
    for imp in importers:
        path = PKG.joinpath(*imp.split(".")).with_suffix(".py")
        t = path.read_text(encoding="utf-8")

        def repl(m: re.Match) -> str:
            got = {x.strip() for x in m[2].strip("()").split(",") if x.strip()}
            if got and got <= set(moved):
                return f"{m[1]}from fricdamp.{dst_mod} import {m[2]}"
            return m[0]

        t2 = pat.sub(repl, t)
        if t2 != t:
            log(f"rewrite {path}: imports {src_mod} -> {dst_mod}")
            path.write_text(t2, encoding="utf-8")
            ruff_run(["check", "--select", "I", "--fix", "--quiet", str(path)])


def ruff_run(args: list[str]):
    ruff = Path(sys.executable).with_name("ruff")
    cmd = [str(ruff)] if ruff.is_file() else [sys.executable, "-m", "ruff"]
    try:
        return subprocess.run([*cmd, *args], capture_output=True, text=True)
    except OSError:
        log(f"  ! ruff not found: run `ruff {' '.join(args)}` by hand")
        return None


#: Modules that register case-file sections import the registry, not the runner.
def registrant_files() -> list[Path]:
    out = sorted((PKG / "cases").glob("*.py"))
    for system in SYSTEMS:
        out += sorted((PKG / "models" / system).glob("*.py"))
    return [p for p in out if p.name != "__init__.py"]


RUNNER_IMPORT = re.compile(r"^(\s*)from fricdamp\.runner import\b", re.M)


def point_registrants_at_registry(dry: bool) -> None:
    if not (PKG / "registry.py").is_file() and not dry:
        return
    for path in registrant_files():
        text = path.read_text(encoding="utf-8")
        new = RUNNER_IMPORT.sub(r"\1from fricdamp.registry import", text)
        if new != text:
            log(f"rewrite {path}: fricdamp.runner -> fricdamp.registry")
            if not dry:
                path.write_text(new, encoding="utf-8")


# ----------------------------------------------------------------------- 3. rewrite paths
def children(new_pkg: str) -> set[str]:
    """Names of the modules under the new package ``new_pkg`` (per MOVES and on disk)."""
    names = {n[len(new_pkg) + 1:].split(".")[0] for n in MOVES.values()
             if n.startswith(new_pkg + ".")}
    d = PKG.joinpath(*new_pkg.split("."))
    if d.is_dir():
        names |= {p.stem for p in d.glob("*.py")} | {p.name for p in d.iterdir() if p.is_dir()}
    names.discard("__pycache__")
    return names


def build_rewrites(moved_now: set[str]) -> list[tuple[re.Pattern, str]]:
    """Regexes old path -> new path, longest old name first. An old module whose name is now
    a package (``models.blade_damper``, ``cli``) is rewritten only in the run that moves it:
    after the move that name is a valid path of its own."""
    rules = []
    for old, new in sorted(MOVES.items(), key=lambda kv: -len(kv[0])):
        if old == new:
            continue
        if new.startswith(old + ".") and old not in moved_now:
            continue
        guard = ""
        # old name that is now a package (or a prefix of its new name): leave `old.<child>`
        # and `old:` alone (already rewritten, or an entry point)
        if (PKG.joinpath(*old.split(".")).is_dir() or new.startswith(old + ".")
                or any(n.startswith(old + ".") for n in MOVES.values())):
            kids = children(old)
            if kids:
                guard = r"(?!\.(?:" + "|".join(sorted(map(re.escape, kids))) + r")\b)"
        guard += r"(?!:\w)"
        dotted = re.compile(r"(?<![\w.])fricdamp\." + re.escape(old) + r"(?![\w])" + guard)
        rules.append((dotted, "fricdamp." + new))
        # file paths: fricdamp/a/b.py and fricdamp/a/ (package folders)
        old_path = "fricdamp/" + old.replace(".", "/")
        new_path = "fricdamp/" + new.replace(".", "/")
        rules.append((re.compile(r"(?<![\w])" + re.escape(old_path) + r"\.py\b"),
                      new_path + ".py"))
        if old in ("analysis", "analyses"):
            rules.append((re.compile(r"(?<![\w])" + re.escape(old_path) + r"/(?![\w])"),
                          new_path + "/"))
    return rules


SENTINEL = "\x00"
FROM_IMPORT = re.compile(
    r"^(?P<ind>[ \t]*)from fricdamp\.(?P<pkg>[\w.]+) import (?P<name>\w+)"
    r"(?: as (?P<alias>\w+))?(?P<rest>[ \t]*(?:#[^\n]*)?)$", re.M)


def rewrite_from_imports(text: str) -> tuple[str, int]:
    """``from fricdamp.<old pkg> import <old module>`` -> ``from <new parent> import <new
    module> as <the name the code uses>`` (one name per statement, as the sources write it)."""
    count = 0

    def repl(m: re.Match) -> str:
        nonlocal count
        old = f"{m['pkg']}.{m['name']}"
        new = MOVES.get(old)
        if new is None or new == old:
            return m[0]
        parent, last = new.rsplit(".", 1)
        bound = m["alias"] or m["name"]
        count += 1
        alias = "" if last == bound else f" as {bound}"
        # the sentinel keeps the path rules off the new path (removed after them)
        return f"{m['ind']}from fricdamp{SENTINEL}.{parent} import {last}{alias}{m['rest']}"

    return FROM_IMPORT.sub(repl, text), count


def text_files() -> list[Path]:
    files = [Path(f) for f in FILES if Path(f).is_file()]
    for tree in TREES:
        for p in Path(tree).rglob("*"):
            if (p.is_file() and p.suffix in SUFFIXES and "__pycache__" not in p.parts
                    and ".ipynb_checkpoints" not in p.parts and p.as_posix() not in SKIP
                    and not p.as_posix().startswith("docs/site")):
                files.append(p)
    return sorted(set(files))


def rewrite_paths(dry: bool, moved_now: set[str]) -> list[str]:
    rules = build_rewrites(moved_now)
    changed = []
    for path in text_files():
        if path.as_posix() == "src/fricdamp/_moved.py":
            continue
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        new, count = rewrite_from_imports(text)
        for pat, repl in rules:
            new, n = pat.subn(repl, new)
            count += n
        new = new.replace("fricdamp" + SENTINEL + ".", "fricdamp.")
        if new != text:
            changed.append(str(path))
            log(f"rewrite {path}: {count} module path(s)")
            if not dry:
                path.write_text(new, encoding="utf-8")
    return changed


def text_fixes(dry: bool) -> None:
    for name, old, new in TEXT_FIXES:
        path = Path(name)
        text = path.read_text(encoding="utf-8") if path.is_file() else ""
        if old in text:
            log(f"fix {name}: {old!r} -> {new!r}")
            if not dry:
                path.write_text(text.replace(old, new), encoding="utf-8")
        elif new not in text:
            log(f"  ! {name}: neither {old!r} nor its replacement found: check by hand")


# ------------------------------------------------------------------------- 4. shims, log
MOVED_MODULE = '''"""Old module paths of fricdamp, kept working after the layout by idea (issue 18).

Generated by ``tools/relayout.py``. :data:`MOVED` maps each old dotted module name to its new
one; an import hook resolves an old name to the new module itself (the same object in
``sys.modules`` under both names), imported only when the old name is.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys

#: old module -> new module
MOVED: dict[str, str] = {
%s}


_KEPT = ("__name__", "__spec__", "__loader__", "__package__", "__path__", "__file__",
         "__cached__")


class _Alias(importlib.abc.Loader):
    """Loads an old name as the new module itself (its own attributes kept as they were)."""

    def __init__(self, target: str) -> None:
        self.target = target
        self.saved: dict = {}

    def create_module(self, spec):
        module = importlib.import_module(self.target)
        self.saved = {k: getattr(module, k) for k in _KEPT if hasattr(module, k)}
        return module

    def exec_module(self, module) -> None:
        # the import system set the old name's spec on the module: put the module's back
        for key in _KEPT:
            if key in self.saved:
                setattr(module, key, self.saved[key])
            elif hasattr(module, key):
                delattr(module, key)


class _MovedFinder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname, path=None, target=None):
        new = MOVED.get(fullname)
        if new is None:
            return None
        real = importlib.util.find_spec(new)
        spec = importlib.util.spec_from_loader(fullname, _Alias(new),
                                               is_package=real is not None
                                               and real.submodule_search_locations is not None)
        return spec


def install() -> None:
    """Put the finder on ``sys.meta_path`` once."""
    if not any(isinstance(f, _MovedFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, _MovedFinder())


install()
'''


def write_moved(dry: bool) -> None:
    path = PKG / "_moved.py"
    entries = "".join(f'    "fricdamp.{o}": "fricdamp.{n}",\n'
                      for o, n in MOVES.items() if not n.startswith(o + "."))
    text = MOVED_MODULE % entries
    old = path.read_text(encoding="utf-8") if path.is_file() else None
    if old != text:
        log(f"write {path} ({entries.count(chr(10))} old module paths)")
        if not dry:
            path.write_text(text, encoding="utf-8")
            git("add", str(path))
    init = PKG / "__init__.py"
    hook = "from fricdamp import _moved  # noqa: E402,F401  (old module paths, see _moved.py)\n"
    t = init.read_text(encoding="utf-8")
    if "import _moved" not in t:
        log(f"append the old-path hook import to {init}")
        if not dry:
            init.write_text(t.rstrip("\n") + "\n\n\n" + hook, encoding="utf-8")


def changelog_section() -> str:
    lines = ["### Moved", "",
             "Layout by idea (issue 18): each word means one thing. Every old import path keeps "
             "working (re-exported through `fricdamp._moved`).", ""]
    for old, new in MOVES.items():
        lines.append(f"- `fricdamp.{old}` → `fricdamp.{new}`")
    lines.append("- `fricdamp.runner` (registry and run of a case) → `fricdamp.registry`; "
                 "`fricdamp.runner` re-exports it and registers the built-in analyses")
    for src_mod, dst_mod, names, _doc, _imp in SHARED:
        lines.append(f"- `fricdamp.{src_mod}`: {', '.join(f'`{n}`' for n in names)} (and the "
                     f"helpers they use) → `fricdamp.{dst_mod}` (re-exported by "
                     f"`fricdamp.{src_mod}`)")
    lines.append("- the import circles runner ↔ analyses.timedomain, structure.cyclic ↔ "
                 "structure.reduction and blade_damper_analyses ↔ blade_damper_orbits are "
                 "broken (`tools/import_cycles.py`; `tests/unit/test_import_cycles.py` fails on "
                 "any module-level cycle)")
    return "\n".join(lines) + "\n"


def write_changelog(dry: bool) -> None:
    path = Path("CHANGELOG.md")
    text = path.read_text(encoding="utf-8")
    if "### Moved" in text:
        return
    m = re.search(r"^## Unreleased[^\n]*\n", text, re.M)
    if not m:
        log("  ! CHANGELOG.md has no '## Unreleased': add the Moved section by hand")
        return
    log("CHANGELOG.md: add the Moved section under ## Unreleased")
    if not dry:
        path.write_text(text[:m.end()] + "\n" + changelog_section() + text[m.end():],
                        encoding="utf-8")


def ruff_imports(files: list[str], dry: bool) -> None:
    """Sort the rewritten import blocks (``ruff check --select I --fix``) and list the lines
    the longer paths made too long (docstrings and comments: wrap by hand)."""
    ruff = Path(sys.executable).with_name("ruff")
    cmd = [str(ruff)] if ruff.is_file() else [sys.executable, "-m", "ruff"]
    py = [f for f in files if f.endswith(".py") and Path(f).is_file()]
    if dry or not py:
        return
    try:
        subprocess.run([*cmd, "check", "--select", "I", "--fix", "--quiet", *py],
                       capture_output=True, text=True)
        res = subprocess.run([*cmd, "check", "--select", "E501", "--output-format", "concise",
                              *py], capture_output=True, text=True)
    except OSError:
        log("  ! ruff not found: run `ruff check --select I --fix` on the rewritten files")
        return
    long_lines = [ln for ln in res.stdout.splitlines() if "E501" in ln]
    log(f"   imports sorted with ruff; {len(long_lines)} line(s) now longer than the limit")
    for ln in long_lines:
        log(f"  ! {ln}")


TEST_CYCLES = '''"""No import cycle between fricdamp's modules at module level
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
    assert cycles == [], "\\n".join(" -> ".join(c) for c in cycles)


def test_the_checker_finds_a_planted_cycle(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from pkg.b import x\\ny = 1\\n")
    (pkg / "b.py").write_text("import pkg.c\\nx = 1\\n")
    (pkg / "c.py").write_text("def f():\\n    from pkg.a import y\\n")
    tool = _tool("import_cycles")
    assert tool.cycles(pkg) == []                   # closed only inside a function
    assert tool.cycles(pkg, function_level=True) == [["pkg.a", "pkg.b", "pkg.c", "pkg.a"]]
    (pkg / "c.py").write_text("from pkg import a\\n")
    assert tool.cycles(pkg) == [["pkg.a", "pkg.b", "pkg.c", "pkg.a"]]


def _moved():
    from fricdamp._moved import MOVED

    return sorted(MOVED.items())


@pytest.mark.parametrize(("old", "new"), _moved())
def test_old_module_path_is_the_new_module(old, new):
    module = importlib.import_module(old)
    assert module is importlib.import_module(new)
    assert module.__name__ == new and module.__spec__.name == new
'''


def write_tests(dry: bool) -> None:
    write_new(Path("tests/unit/test_import_cycles.py"), TEST_CYCLES, dry)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dry-run", action="store_true", help="print what would be done")
    ap.add_argument("--changelog", action="store_true",
                    help="add the Moved section to CHANGELOG.md (else print it)")
    args = ap.parse_args(argv)
    if not PKG.is_dir():
        print("run at the repository root (src/fricdamp not found)", file=sys.stderr)
        return 2
    dry = args.dry_run
    log("== 1. moves")
    moved_now = do_moves(dry)
    log("== 2. import circles: shared pieces to lower modules")
    split_runner(dry)
    point_registrants_at_registry(dry)
    log("== 3. module paths")
    changed = rewrite_paths(dry, moved_now)
    log(f"   {len(changed)} file(s) rewritten")
    text_fixes(dry)
    package_inits(dry)  # after the rewrite: they already use the new paths
    for src_mod, dst_mod, names, doc, importers in SHARED:
        extract_shared(src_mod, dst_mod, names, doc, importers, dry)
    ruff_imports(changed + [str(PKG / "runner.py"), str(PKG / "registry.py")], dry)
    log("== 4. old-path hook, tests, CHANGELOG")
    write_moved(dry)
    write_tests(dry)
    if args.changelog:
        write_changelog(dry)
    else:
        print(changelog_section())
    return 0


if __name__ == "__main__":
    sys.exit(main())
