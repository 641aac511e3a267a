"""List the import cycles between the modules of a package (default: ``src/fricdamp``).

Builds the module import graph with :mod:`ast` from every ``import``/``from ... import`` in the
package's sources. Imports at module level (including inside ``if``/``try`` at module level, but
not under ``if TYPE_CHECKING:``) and imports inside functions or methods are counted separately:
a cycle of module-level imports can break the import of a module, a cycle through a function-level
import only ties the modules together.

``from pkg import name`` counts as an import of ``pkg.name`` when that is a module, else of
``pkg``; importing ``a.b.c`` also imports the packages ``a`` and ``a.b`` (their ``__init__``),
which are edges too, except for a package's own ``__init__`` reaching its submodules (the usual
re-export, a cycle only if the submodule imports the package back at module level, which counts).

Usage: ``python tools/import_cycles.py [src/fricdamp] [--function]``; prints each cycle
(strongly connected component, and one shortest cycle through it) and exits 1 if a module-level
cycle exists (``--function``: also list cycles that need function-level imports).
"""

from __future__ import annotations

import argparse
import ast
import sys
from pathlib import Path


def module_names(root: Path) -> dict[str, Path]:
    """Dotted module name → source file, for every ``.py`` under the package ``root``."""
    base = root.parent
    out = {}
    for path in sorted(root.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        parts = list(path.relative_to(base).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _imports(tree: ast.Module):
    """Yield (node, at_module_level) for every import statement of a module."""
    def walk(node, level_module: bool):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.Import, ast.ImportFrom)):
                yield child, level_module
            elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                yield from walk(child, False)
            elif isinstance(child, ast.If) and _is_type_checking(child.test):
                for sub in child.orelse:
                    yield from walk(ast.Module(body=[sub], type_ignores=[]), level_module)
            else:
                yield from walk(child, level_module)
    yield from walk(tree, True)


def _resolve(name: str, module: str, is_pkg: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    parts = module.split(".")
    if not is_pkg:
        parts = parts[:-1]
    if node.level > 1:
        parts = parts[: len(parts) - (node.level - 1)]
    return ".".join(parts + ([node.module] if node.module else []))


def import_graph(root: Path) -> tuple[dict[str, set[str]], dict[str, set[str]]]:
    """(module-level edges, function-level edges) between the modules of the package ``root``."""
    mods = module_names(root)
    top = root.name
    module_edges: dict[str, set[str]] = {m: set() for m in mods}
    function_edges: dict[str, set[str]] = {m: set() for m in mods}

    def targets(name: str) -> list[str]:
        # the module itself plus the packages it lives in
        out = []
        parts = name.split(".")
        for i in range(1, len(parts) + 1):
            cand = ".".join(parts[:i])
            if cand in mods:
                out.append(cand)
        return out

    for mod, path in mods.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        is_pkg = path.name == "__init__.py"
        for node, at_top in _imports(tree):
            names: list[str] = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                base = _resolve(node.module or "", mod, is_pkg, node)
                for alias in node.names:
                    sub = f"{base}.{alias.name}" if base else alias.name
                    names.append(sub if sub in mods else base)
            for name in names:
                if not (name == top or name.startswith(top + ".")):
                    continue
                for tgt in targets(name):
                    if tgt == mod or mod.startswith(tgt + "."):
                        continue  # a module's own packages are imported first anyway
                    (module_edges if at_top else function_edges)[mod].add(tgt)
    return module_edges, function_edges


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components with more than one module (or a self-loop)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    comps: list[list[str]] = []
    counter = [0]
    sys.setrecursionlimit(max(10000, sys.getrecursionlimit()))

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in graph.get(v, ()):
                comps.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(comps)


def shortest_cycle(graph: dict[str, set[str]], comp: list[str]) -> list[str]:
    """One shortest cycle inside a strongly connected component (breadth-first from each node)."""
    members = set(comp)
    best: list[str] = []
    for start in comp:
        prev = {start: None}
        queue = [start]
        found = None
        while queue and found is None:
            nxt = []
            for v in queue:
                for w in sorted(graph.get(v, ())):
                    if w == start:
                        found = v
                        break
                    if w in members and w not in prev:
                        prev[w] = v
                        nxt.append(w)
                if found is not None:
                    break
            queue = nxt
        if found is not None:
            path = [found]
            while prev[path[-1]] is not None:
                path.append(prev[path[-1]])
            path.reverse()
            if not best or len(path) < len(best):
                best = path
    return best + best[:1]


def cycles(root: Path, function_level: bool = False) -> list[list[str]]:
    """Module-level cycles (or, with ``function_level``, cycles using any import) as paths."""
    module_edges, function_edges = import_graph(root)
    graph = module_edges
    if function_level:
        graph = {m: module_edges[m] | function_edges[m] for m in module_edges}
    return [shortest_cycle(graph, comp) for comp in strongly_connected(graph)]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("root", nargs="?", default="src/fricdamp")
    ap.add_argument("--function", action="store_true",
                    help="also list cycles closed by imports inside functions")
    args = ap.parse_args(argv)
    root = Path(args.root)
    module_edges, function_edges = import_graph(root)
    n_mod = sum(len(v) for v in module_edges.values())
    n_fun = sum(len(v) for v in function_edges.values())
    print(f"{len(module_edges)} modules, {n_mod} module-level and {n_fun} function-level imports")
    status = 0
    mod_cycles = [shortest_cycle(module_edges, c) for c in strongly_connected(module_edges)]
    print(f"module-level cycles: {len(mod_cycles)}")
    for cyc in mod_cycles:
        print("  " + " -> ".join(cyc))
        status = 1
    if args.function:
        both = {m: module_edges[m] | function_edges[m] for m in module_edges}
        comps = strongly_connected(both)
        print(f"cycles with function-level imports: {len(comps)} strongly connected groups")
        for comp in comps:
            print(f"  [{len(comp)} modules] " + " -> ".join(shortest_cycle(both, comp)))
    return status


if __name__ == "__main__":
    sys.exit(main())
