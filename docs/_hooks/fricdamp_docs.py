"""MkDocs hooks of the fricdamp documentation (``hooks:`` in ``mkdocs.yml``).

Three kinds of pages are generated at build time, in memory (nothing is written into the
source tree):

* ``api/<subpackage>.md`` -- the API reference of each public subpackage: one mkdocstrings
  entry per name of its ``__all__``, pointing at the module that defines it, so the pages
  follow the code when modules move (the public import paths are re-exported).
* ``validation.md`` -- the table of references and tolerances of ``tests/validation``
  (:mod:`validation_table`).
* ``gallery/*.md`` -- every ``docs/gallery/*.py`` script is executed; its code cells
  (separated by ``# %%`` lines), printed output and matplotlib figures make its page. A
  script that raises (its ``assert`` checks included) fails the build.
"""

from __future__ import annotations

import ast
import contextlib
import importlib
import io
import logging
import re
import time
from pathlib import Path

from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File

log = logging.getLogger("mkdocs.hooks.fricdamp")

ROOT = Path(__file__).resolve().parents[2]


def _load_validation_table():
    """The sibling script ``validation_table.py`` (hooks are not on ``sys.path``)."""
    import importlib.util

    path = Path(__file__).resolve().with_name("validation_table.py")
    spec = importlib.util.spec_from_file_location("fricdamp_docs_validation_table", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module

#: Public subpackages in the API reference: (module, page title, one-line summary).
API_PACKAGES = [
    ("fricdamp.contact", "contact", "friction and contact laws"),
    ("fricdamp.structure", "structure",
     "mechanical systems, builders, beams, solids, cyclic symmetry"),
    ("fricdamp.solvers", "solvers",
     "time stepping, event-driven stick-slip, HB, continuation, modes"),
    ("fricdamp.signals", "signals", "loops, energy, damping, signals, identification"),
    ("fricdamp.studies", "studies", "sweeps and optimisation, serial or on Dask"),
    ("fricdamp.models", "models", "the papers' systems"),
]


# ----------------------------------------------------------------------------- API pages
def _public_names(module) -> list[str]:
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in getattr(module, "_LAZY", {}) if not n.startswith("_")]
    return list(names)


#: Short and public names -> identifier of the rendered object (filled by the API pages),
#: used to turn the docstrings' Sphinx roles into links.
IDENTIFIERS: dict[str, str] = {}


def _defining_module(module, name: str) -> str:
    obj = getattr(module, name)
    where = getattr(obj, "__module__", None)
    if not where or not where.startswith("fricdamp"):
        where = module.__name__
    # a name re-exported by its defining module's package keeps the defining module
    return where


def api_page(package: str, title: str, summary: str) -> str:
    module = importlib.import_module(package)
    lines = [
        f"# `{package}`",
        "",
        f"*{summary.capitalize()}.*",
        "",
        f"::: {package}",
        "    options:",
        "      members: false",
        "      show_root_heading: false",
        "      show_root_toc_entry: false",
        "",
    ]
    entries = sorted(_public_names(module), key=lambda n: (not n[:1].isupper(), n.lower()))
    for name in entries:
        ident = f"{_defining_module(module, name)}.{name}"
        for alias in (name, f"{package}.{name}", ident):
            IDENTIFIERS.setdefault(alias, ident)
        lines += [f"::: {ident}", "    options:",
                  "      heading_level: 2", "      show_root_full_path: false", ""]
    if package in MODULE_PACKAGES:
        lines += ["## Modules", "",
                  "Each public module of the subpackage, with its description; the names it "
                  "defines are imported from the module itself.", ""]
        for sub in _public_submodules(module):
            lines += [f"::: {sub}", "    options:", "      members: false",
                      "      heading_level: 3", "      show_root_full_path: true", ""]
    return "\n".join(lines)


#: Subpackages whose public modules are listed too (the papers' systems: most of their API
#: is reached through their modules, not through the subpackage's ``__all__``).
MODULE_PACKAGES = {"fricdamp.models"}


def _public_submodules(module) -> list[str]:
    import pkgutil

    found = []
    for info in pkgutil.walk_packages(module.__path__, prefix=f"{module.__name__}."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            found.append(info.name)
    return sorted(found)


def api_index() -> str:
    lines = ["# API reference", "",
             "Generated from the numpydoc docstrings of the public subpackages (their "
             "`__all__`). Import the names from the subpackage, e.g. "
             "`from fricdamp.solvers import simulate_events`; the heading of each entry shows "
             "the module that defines it.", "",
             "| subpackage | what it holds |", "|---|---|"]
    for package, title, summary in API_PACKAGES:
        lines.append(f"| [`{package}`]({title}.md) | {summary} |")
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------- gallery
def _cells(source: str) -> tuple[str, str, list[str]]:
    """Title, description (the module docstring) and code cells of a gallery script."""
    tree = ast.parse(source)
    doc = ast.get_docstring(tree) or ""
    body = source
    if tree.body and isinstance(tree.body[0], ast.Expr) and doc:
        body = "\n".join(source.splitlines()[tree.body[0].end_lineno:])
    title, _, rest = doc.partition("\n")
    rest = rest.lstrip("=\n")
    cells, current, comments = [], [], []
    for line in body.splitlines():
        if line.strip().startswith("# %%"):
            cells.append(("\n".join(current).strip("\n"), "\n".join(comments)))
            current, comments = [], []
            continue
        if not current and line.startswith("# ") and (comments or not "".join(current)):
            comments.append(line[2:])
            continue
        current.append(line)
    cells.append(("\n".join(current).strip("\n"), "\n".join(comments)))
    return title.strip(), rest.strip(), cells


def run_gallery_script(path: Path, image_prefix: str):
    """Execute one script cell by cell; return its Markdown and its figures (name, png)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    source = path.read_text(encoding="utf-8")
    title, description, cells = _cells(source)
    namespace = {"__name__": "__main__", "__file__": str(path)}
    md = [f"# {title}", "", description, "",
          f"[Download the script]({path.name}) · run it with `python {path.name}`.", ""]
    images = []
    t0 = time.perf_counter()
    plt.close("all")
    for code, comment in cells:
        if comment:
            md += [comment, ""]
        if not code.strip():
            continue
        out = io.StringIO()
        try:
            with contextlib.redirect_stdout(out):
                exec(compile(code, str(path), "exec"), namespace)  # noqa: S102
        except Exception as exc:
            raise PluginError(f"gallery script {path.name} failed: "
                              f"{type(exc).__name__}: {exc}") from exc
        md += ["```python", code, "```", ""]
        if out.getvalue().strip():
            md += ["```text", out.getvalue().rstrip(), "```", ""]
        for num in plt.get_fignums():
            fig = plt.figure(num)
            buf = io.BytesIO()
            fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
            name = f"{image_prefix}_{len(images) + 1}.png"
            images.append((name, buf.getvalue()))
            md += [f"![{title}, figure {len(images)}](images/{name})", ""]
        plt.close("all")
    elapsed = time.perf_counter() - t0
    md += [f"*Executed when the documentation was built, in {elapsed:.1f} s.*", ""]
    return title, "\n".join(md), images


def gallery_pages(config, files) -> None:
    folder = Path(config["docs_dir"]) / "gallery"
    scripts = sorted(folder.glob("[0-9]*.py"))
    index = ["# Gallery", "",
             "Short scripts, each executed when the documentation is built: the output and "
             "figures below come from that run, and every script checks one number against "
             "its closed form or its energy balance (a failing check fails the build). "
             "Download a script from its page and run it as it is.", ""]
    for path in scripts:
        stem = path.stem
        title, md, images = run_gallery_script(path, stem)
        files.append(File.generated(config, f"gallery/{stem}.md", content=md))
        for name, png in images:
            files.append(File.generated(config, f"gallery/images/{name}", content=png))
        index += [f"## [{title}]({stem}.md)", ""]
        if images:
            index += [f"[![{title}](images/{images[0][0]}){{ width=\"360\" }}]({stem}.md)", ""]
        log.info("gallery: %s executed", path.name)
    files.append(File.generated(config, "gallery/index.md", content="\n".join(index) + "\n"))


# ----------------------------------------------------------------------------- roles
#: Sphinx roles as they come out of a numpydoc docstring rendered by mkdocstrings
#: (``:func:`name``` -> ``:func:<code>name</code>``).
_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|attr|data|exc|obj):<code>(~?)([^<]+?)</code>")


def _role_link(match: re.Match) -> str:
    """An optional autorefs cross-reference: a link where the target is rendered, else
    plain code (no warning)."""
    tilde, target = match.group(1), match.group(2).strip()
    name = target.rstrip("()")
    title = name.rsplit(".", 1)[-1] if tilde else name
    head, _, rest = name.partition(".")
    ident = IDENTIFIERS.get(name) or (                 # Class.method -> module.Class.method
        f"{IDENTIFIERS[head]}.{rest}" if rest and head in IDENTIFIERS else name)
    return f'<autoref identifier="{ident}" optional><code>{title}</code></autoref>'


def on_page_content(html, page, config, files):
    """Docstrings use Sphinx roles (``:func:`simulate```); render them as links."""
    return _ROLE.sub(_role_link, html)


# ----------------------------------------------------------------------------- hooks
def on_files(files, config):
    build_table = _load_validation_table().build_table
    files.append(File.generated(config, "api/index.md", content=api_index()))
    for package, title, summary in API_PACKAGES:
        files.append(File.generated(config, f"api/{title}.md",
                                    content=api_page(package, title, summary)))
    files.append(File.generated(config, "validation.md", content=build_table()))
    gallery_pages(config, files)
    return files
