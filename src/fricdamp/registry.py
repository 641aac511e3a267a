"""The registry of model types, contact types and analyses, and the run of a case.

Case-file sections register themselves here; :mod:`fricdamp.runner` imports the
built-in ones (use that module to run cases).

The command line knows nothing about models or analyses: it asks this module to load, check
and run a case. What a case may contain is the :data:`REGISTRY`:

* ``register_model(type, schema, builder)``: ``[model] type = ...``; ``builder(spec, ctx)``
  returns a :class:`~fricdamp.structure.MechanicalSystem` (``ctx`` is a :class:`BuildContext`
  with the case folder).
* ``register_contact(type, schema, builder)``: ``[[contacts]] type = ...``;
  ``builder(spec, ctx)`` returns a :class:`~fricdamp.structure.ContactElement` (``ctx.n_dof``
  is the number of DOFs, ``ctx.name`` the default name).
* ``register_analysis(name, schema, run_fn, check=None)``: ``[analysis.<name>]``;
  ``run_fn(system, spec, ctx)`` returns an :class:`AnalysisOutput` (``ctx`` is a
  :class:`RunContext`); ``check(system, spec)`` validates what depends on the model (vector
  lengths, DOF numbers) and raises :class:`~fricdamp.errors.CaseError`. An analysis judges
  its own numbers by setting ``AnalysisOutput.verdict`` (a :class:`fricdamp.verdict.Verdict`,
  e.g. ``judge({"energy_balance_error": e, ...}, reasons=[...], failed=...)``); without one it
  gets :func:`default_verdict`. The verdicts go to summary.json's ``verdict`` and set the exit
  code of ``fricdamp run`` (0 ok, 3 unreliable, 1 failed).

``schema`` is a pydantic model (derive from :class:`fricdamp.case.Section` for the strict
rules); the ``type`` key is removed from the table before it is validated.

A run computes every analysis first (:func:`compute_case`, which the design studies call at
each point) and writes only then, each file atomically, so a failed run leaves no
half-written result behind.
"""

from __future__ import annotations

import datetime as _dt
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from fricdamp._version import __version__
from fricdamp.case import (
    Attachment,
    Case,
    ChainModel,
    Contact3DContact,
    CoulombContact,
    CubicSpringContact,
    IwanContact,
    JenkinsContact,
    MatricesModel,
    SolverSettings,
    parse_case,
    read_case_file,
)
from fricdamp.errors import CaseError, ConvergenceError, ModelError
from fricdamp.errors import OutputError as FricdampOutputError
from fricdamp.verdict import Verdict, combine, judge

log = logging.getLogger(__name__)

__all__ = [
    "REGISTRY",
    "ModelObject",
    "NotAMechanicalSystemError",
    "AnalysisOutput",
    "Entry",
    "BuildContext",
    "Registry",
    "RunContext",
    "RunOutcome",
    "attachment_projection",
    "ComputedCase",
    "default_verdict",
    "verdict_summary",
    "build_system",
    "compute_case",
    "describe_system",
    "load_builtin_case",
    "load_case",
    "register_analysis",
    "register_contact",
    "register_model",
    "register_table",
    "run_case",
]


# ================================================================================ registry
#: Top-level keys of summary.json besides the analyses' sections.
RESERVED_SUMMARY_KEYS = frozenset({"fricdamp_version", "case", "created", "runtime_s",
                                   "energy_balance_error", "model", "notes", "files",
                                   "verdict"})


@dataclass(frozen=True)
class Entry:
    """One registered model type, contact type or analysis."""

    name: str
    schema: type
    fn: Callable
    check: Callable | None = None
    description: str = ""


class Registry:
    """Model types, contact types and analyses a case file may use (see the module doc)."""

    def __init__(self):
        self.models: dict[str, Entry] = {}
        self.contacts: dict[str, Entry] = {}
        self.analyses: dict[str, Entry] = {}
        #: Other top-level tables a case may hold for other commands (name -> schema or None).
        self.tables: dict[str, type | None] = {}

    @staticmethod
    def _add(table: dict, name: str, entry: Entry, replace: bool, what: str) -> None:
        if not isinstance(name, str) or not name.isidentifier():
            raise ValueError(f"{what} name must be an identifier, got {name!r}")
        if not (isinstance(entry.schema, type) and hasattr(entry.schema, "model_validate")):
            raise TypeError(f"{what} {name!r}: schema must be a pydantic model class")
        if name in table and not replace:
            raise ValueError(f"{what} {name!r} is already registered (pass replace=True)")
        table[name] = entry

    def register_model(self, type: str, schema: type, builder: Callable, *,
                       description: str = "", replace: bool = False) -> None:
        """Register ``[model] type = "<type>"``: ``builder(spec, BuildContext) -> system``."""
        self._add(self.models, type, Entry(type, schema, builder, None, description),
                  replace, "model type")

    def register_contact(self, type: str, schema: type, builder: Callable, *,
                         description: str = "", replace: bool = False) -> None:
        """Register ``[[contacts]] type = "<type>"``: ``builder(spec, BuildContext)``
        returns a ContactElement."""
        self._add(self.contacts, type, Entry(type, schema, builder, None, description),
                  replace, "contact type")

    def register_table(self, name: str, schema: type | None = None, *,
                       replace: bool = False) -> None:
        """Allow a top-level ``[name]`` table that ``fricdamp run`` does not use (it belongs to
        another command, e.g. ``[sweep]``); validated with ``schema`` if given."""
        if not isinstance(name, str) or not name.isidentifier():
            raise ValueError(f"table name must be an identifier, got {name!r}")
        if schema is not None and not hasattr(schema, "model_validate"):
            raise TypeError(f"table {name!r}: schema must be a pydantic model class or None")
        if name in self.tables and not replace:
            raise ValueError(f"table {name!r} is already registered (pass replace=True)")
        self.tables[name] = schema

    def register_analysis(self, name: str, schema: type, run_fn: Callable, *,
                          check: Callable | None = None, description: str = "",
                          replace: bool = False) -> None:
        """Register ``[analysis.<name>]``: ``run_fn(system, spec, RunContext)`` returns an
        AnalysisOutput; ``check(system, spec)`` raises CaseError for model-dependent errors.

        The name becomes a section of summary.json, so it may not be one of the summary's
        own keys (``case``, ``model``, ``files``, ...)."""
        if name in RESERVED_SUMMARY_KEYS:
            raise ValueError(f"analysis name {name!r} is reserved (summary.json uses it)")
        self._add(self.analyses, name, Entry(name, schema, run_fn, check, description),
                  replace, "analysis")


#: The registry used by the command line.
REGISTRY = Registry()
register_model = REGISTRY.register_model
register_contact = REGISTRY.register_contact
register_analysis = REGISTRY.register_analysis
register_table = REGISTRY.register_table
# tables of the design-study commands (fricdamp sweep / optimize check them themselves)
register_table("sweep")
register_table("optimize")


class NotAMechanicalSystemError(CaseError, AttributeError):
    """An analysis asked a paper's model object for what only a MechanicalSystem has."""


class ModelObject:
    """Base of the model objects of the papers' systems (``[model]`` builders may return one).

    A model object has ``n_dof``, ``names`` and ``describe() -> dict`` (shown under
    ``model`` in summary.json); its contacts are part of the model. The generic analyses,
    which need a MechanicalSystem, get a :class:`NotAMechanicalSystemError` naming the
    analyses that do apply (``MODEL_DESCRIPTION`` and ``MODEL_ANALYSES``), i.e. exit code 2.
    """

    MODEL_TYPE = "model"
    MODEL_DESCRIPTION = "a paper's model"
    MODEL_ANALYSES = ""

    def __getattr__(self, name: str):
        # only called for attributes that do not exist: the generic analyses asking for a
        # MechanicalSystem's (with_loads, contacts, M, ...)
        if name.startswith("_"):
            raise AttributeError(name)
        raise NotAMechanicalSystemError(
            f"the {self.MODEL_TYPE!r} model is {self.MODEL_DESCRIPTION}, not a MechanicalSystem "
            f"(it has no {name!r}): its analyses are {self.MODEL_ANALYSES}")


@dataclass(frozen=True)
class BuildContext:
    """What a model or contact builder may need besides its table.

    Attributes
    ----------
    base_dir : Path
        Folder of the case file (relative paths are resolved against it).
    n_dof : int or None
        Number of DOFs of the model (contact builders only).
    index : int
        1-based position of the table among ``[[contacts]]`` (contact builders only).
    name : str
        Default name of the contact (``contact<index>``) when the table has none.
    """

    base_dir: Path
    n_dof: int | None = None
    index: int = 0
    name: str = ""


@dataclass(frozen=True)
class RunContext:
    """What an analysis may need besides the system and its table."""

    case: Case
    solver: SolverSettings
    progress: bool = False

    def simulate_kwargs(self) -> dict:
        """Keyword arguments of :func:`fricdamp.solvers.timestep.simulate` from ``[solver]``."""
        s = self.solver
        return {"method": s.method, "alpha": s.alpha, "tol": s.tol, "max_iter": s.max_iter,
                "progress": self.progress}


@dataclass
class AnalysisOutput:
    """What an analysis returns.

    Attributes
    ----------
    summary : dict
        JSON-able key numbers (written to summary.json under the analysis name). Keys carry
        their unit (``amplitude_m``); an ``energy_balance_error`` key enters the top-level
        maximum.
    arrays : dict of str -> xarray.DataArray or xarray.Dataset
        Full arrays for the results file (names are prefixed with the analysis name there).
    figures : list of (filename, title, Figure), or a callable returning that list
        PNG figures (the callable is called only when writing, so matplotlib is imported
        only then).
    headline : str
        One line for the terminal.
    notes : list of str
        Warnings for the user (shown on the terminal, in the report and in summary.json).
    top_level : dict
        JSON-able keys written at the top level of summary.json, next to the sections (a
        paper's results contract: ``n_dof``, a list of sweeps). A key may not be one of the
        summary's own keys nor the name of an analysis of the case; two analyses may give the
        same key only with the same value.
    verdict : fricdamp.verdict.Verdict, optional
        Whether the numbers can be trusted (``ok``, ``unreliable`` with reasons, ``failed``)
        and the error estimates behind it. An analysis that knows its errors sets it
        (:func:`fricdamp.verdict.judge` turns estimates into one); when it is None the runner
        gives :func:`default_verdict`. It goes into summary.json under
        ``verdict.analyses.<name>`` and decides the exit code of ``fricdamp run``.
    """

    summary: dict
    arrays: dict = field(default_factory=dict)
    figures: list | Callable = field(default_factory=list)
    headline: str = ""
    notes: list[str] = field(default_factory=list)
    top_level: dict = field(default_factory=dict)
    verdict: Verdict | None = None


def default_verdict(out: AnalysisOutput) -> Verdict:
    """The verdict of an analysis that gives none: from what its summary reports.

    ``failed`` if the summary says ``success = false``, else ``ok``. The summary's
    ``energy_balance_error`` (if any) is recorded as an estimate; above the limit of
    :data:`fricdamp.verdict.THRESHOLDS` it is flagged in the estimates
    (``energy_balance_over_limit``) and in a note, but it does not change the verdict: an
    analysis that knows what its energy balance means for its numbers sets its own verdict.
    """
    from fricdamp.verdict import THRESHOLDS

    est = {}
    ebe = out.summary.get("energy_balance_error")
    if isinstance(ebe, (int, float)) and not isinstance(ebe, bool):
        est["energy_balance_error"] = float(ebe)
        if float(ebe) > THRESHOLDS["energy_balance_error"]:
            est["energy_balance_over_limit"] = True
            note = (f"energy balance error {float(ebe):.3g} exceeds the limit "
                    f"{THRESHOLDS['energy_balance_error']:g} (this analysis does not judge "
                    "its own results yet: check the time step)")
            if note not in out.notes:
                out.notes.append(note)
    failed = None
    if out.summary.get("success") is False:
        failed = str(out.summary.get("message") or "the analysis reports success = false")
    return judge({}, failed=failed).with_estimates(**est)


@dataclass(frozen=True)
class RunOutcome:
    """Result of :func:`run_case`: the output folder, summary and the files written."""

    out_dir: Path
    summary: dict
    files: dict
    outputs: dict

    @property
    def verdict(self) -> str:
        """Overall verdict of the run: "ok", "unreliable" or "failed"."""
        return self.summary["verdict"]["overall"]

    @property
    def report(self) -> Path:
        return self.out_dir / self.files["report"]


# ================================================================================ loading
def load_case(path: str | Path, registry: Registry | None = None) -> Case:
    """Read and validate a TOML case file (raises CaseError with one clear message)."""
    path = Path(path)
    data, text = read_case_file(path)
    return parse_case(data, registry or REGISTRY, text=text, source=path.resolve(),
                      default_name=path.stem)


def load_builtin_case(name: str = "demo", registry: Registry | None = None) -> Case:
    """A case shipped with fricdamp (``src/fricdamp/data/<name>.toml``)."""
    import tomllib

    res = resources.files("fricdamp") / "data" / f"{name}.toml"
    if not res.is_file():
        raise CaseError(f"no built-in case named {name!r}")
    text = res.read_text(encoding="utf-8")
    return parse_case(tomllib.loads(text), registry or REGISTRY, text=text, source=None,
                      default_name=name)


def build_system(case: Case, registry: Registry | None = None):
    """Build the MechanicalSystem of a case and run every analysis's model checks.

    This is all of ``fricdamp check``: after it, a run can fail only in a solver.

    Raises
    ------
    CaseError
        Naming the table and key for anything the model rejects (singular or non-symmetric
        mass matrix, a DOF number beyond the model, a vector of the wrong length, ...).
    """
    reg = registry or REGISTRY
    ctx = BuildContext(base_dir=case.base_dir)
    try:
        system = reg.models[case.model_type].fn(case.model, ctx)
    except ModelError as exc:
        raise CaseError(f"[model] ({case.model_type}): {exc}") from None
    from fricdamp.structure.system import MechanicalSystem

    if not isinstance(system, MechanicalSystem):
        # a paper's model object (its contacts are part of the model): see describe_system
        if case.contacts:
            raise CaseError(f"[[contacts]] cannot be added to a {case.model_type!r} model: its "
                            "contacts are part of the model (set them in [model])")
        for name, spec in case.analyses.items():
            check = reg.analyses[name].check
            if check is not None:
                try:
                    check(system, spec)
                except (CaseError, ModelError) as exc:
                    raise CaseError(f"[analysis.{name}] {exc}") from None
        return system
    elements = []
    for i, (ctype, spec) in enumerate(case.contacts, start=1):
        where = f"[[contacts]] #{i} ({ctype})"
        cctx = BuildContext(base_dir=case.base_dir, n_dof=system.n_dof, index=i,
                            name=f"contact{i}")
        try:
            elements.append(reg.contacts[ctype].fn(spec, cctx))
        except (ModelError, CaseError) as exc:
            raise CaseError(f"{where}: {exc}") from None
    names = [e.name for e in elements]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise CaseError(f"[[contacts]]: the name {dup[0]!r} is used twice; give each contact "
                        "a different name")
    try:
        system = system.with_contacts(*elements)
    except ModelError as exc:
        raise CaseError(f"[[contacts]]: {exc}") from None
    for name, spec in case.analyses.items():
        check = reg.analyses[name].check
        if check is None:
            continue
        try:
            check(system, spec)
        except (CaseError, ModelError) as exc:
            raise CaseError(f"[analysis.{name}] {exc}") from None
    return system


# ================================================================================ running
@dataclass(frozen=True)
class ComputedCase:
    """Result of :func:`compute_case`: the model and every analysis's output, nothing written.

    Attributes
    ----------
    system : MechanicalSystem or ModelObject
        What the ``[model]`` builder returned, with the ``[[contacts]]`` added.
    outputs : dict of str -> AnalysisOutput
        One output per ``[analysis.<name>]``, in the order of the case. Their summaries are
        as the analyses returned them (:func:`run_case` adds ``runtime_s``).
    runtimes_s : dict of str -> float
        Wall-clock time of each analysis, s.
    """

    system: object
    outputs: dict
    runtimes_s: dict


def compute_case(case: Case, *, registry: Registry | None = None, progress: bool = False,
                 echo: Callable[[str], None] | None = None) -> ComputedCase:
    """Build the model of ``case`` and run every analysis, in memory.

    The computing half of :func:`run_case` (which writes the files) and the function a design
    study evaluates at each point (:class:`fricdamp.cli.studies.CasePoint`).

    Parameters
    ----------
    case : Case
        A validated case (:func:`load_case`).
    registry : Registry, optional
        Default :data:`REGISTRY`.
    progress : bool
        Show progress bars of the solvers.
    echo : callable, optional
        Receives one line per analysis as it finishes, then one per note.

    Returns
    -------
    ComputedCase

    Raises
    ------
    CaseError
        Invalid case or model (a ModelError of an analysis is reported as one, naming it).
    ConvergenceError
        A solver failed (the message names the analysis).
    """
    reg = registry or REGISTRY
    system = build_system(case, reg)
    ctx = RunContext(case=case, solver=case.solver, progress=progress)
    outputs: dict[str, AnalysisOutput] = {}
    runtimes: dict[str, float] = {}
    for name, spec in case.analyses.items():
        t_a = time.perf_counter()
        try:
            out = reg.analyses[name].fn(system, spec, ctx)
        except ConvergenceError as exc:
            raise ConvergenceError(f"[analysis.{name}] {exc}") from exc
        except ModelError as exc:
            raise CaseError(f"[analysis.{name}] {exc}") from exc
        runtimes[name] = time.perf_counter() - t_a
        if out.verdict is None:
            out.verdict = default_verdict(out)
        outputs[name] = out
        if echo is not None:
            echo(f"  {name}: {out.headline}" if out.headline else f"  {name}: done")
            for note in out.notes:
                echo(f"  {name}: note: {note}")
            if not out.verdict.ok:
                for reason in out.verdict.reasons:
                    echo(f"  {name}: {out.verdict.status.upper()}: {reason}")
    return ComputedCase(system=system, outputs=outputs, runtimes_s=runtimes)


def run_case(case: Case, out_dir: str | Path, *, registry: Registry | None = None,
             progress: bool = False, results_format: str = "nc",
             echo: Callable[[str], None] | None = None) -> RunOutcome:
    """Run every analysis of ``case`` and write the results into ``out_dir``.

    The analyses are computed by :func:`compute_case`; each summary gets a ``runtime_s`` (s)
    unless the analysis gave one.

    Parameters
    ----------
    case : Case
        A validated case (:func:`load_case`).
    out_dir : path
        Output folder (created if needed). Written there, each file atomically:
        ``summary.json``, ``results.nc`` (or ``results.npz``), one PNG per figure and
        ``report.html``.
    registry : Registry, optional
        Default :data:`REGISTRY`.
    progress : bool
        Show progress bars of the solvers.
    results_format : {"nc", "npz"}
        Format of the results file.
    echo : callable, optional
        Receives one line per analysis as it finishes (the CLI prints them).

    Returns
    -------
    RunOutcome

    Raises
    ------
    CaseError
        Invalid case (exit code 2 on the command line).
    ConvergenceError
        A solver failed (exit code 1); nothing is written.
    OutputError
        The folder cannot be created or written (checked before computing), another run
        holds it, or a file could not be written (disk full): the message names the file.

    A run whose analyses finish but are judged ``unreliable`` or ``failed`` (their
    :class:`~fricdamp.verdict.Verdict`) is written as usual; ``summary.json["verdict"]`` and
    :attr:`RunOutcome.verdict` say so, and the command line exits with 3 or 1.
    """
    from fricdamp.iofiles import OutputLock, prepare_output_folder

    if results_format not in ("nc", "npz"):
        raise CaseError(f"results format must be 'nc' or 'npz', got {results_format!r}")
    reg = registry or REGISTRY
    start = time.perf_counter()
    out_dir = Path(out_dir)
    # the folder is created and write-tested before anything is computed, and locked
    # against a second run into it
    created = not out_dir.exists()
    prepare_output_folder(out_dir)
    try:
        with OutputLock(out_dir, "run"):
            computed = compute_case(case, registry=reg, progress=progress, echo=echo)
            return _write_case(case, computed, out_dir, results_format, start)
    except BaseException:
        # a run that fails before writing leaves no trace: remove the folder it created
        if created:
            import contextlib

            with contextlib.suppress(OSError):
                out_dir.rmdir()   # only if empty
        raise


def verdict_summary(outputs: dict) -> dict:
    """``{"overall": ..., "analyses": {name: {"verdict", "reasons", "estimates"}}}`` of the
    analyses' outputs (summary.json's ``verdict``)."""
    verdicts = {name: (out.verdict or default_verdict(out)) for name, out in outputs.items()}
    return {"overall": combine(verdicts.values()),
            "analyses": {name: v.to_dict() for name, v in verdicts.items()}}


def _write_case(case: Case, computed: ComputedCase, out_dir: Path, results_format: str,
                start: float) -> RunOutcome:
    """Write the files of a computed case (each atomically); OutputError names the file."""
    from fricdamp.iofiles import (
        combine_results,
        output_error,
        save_figure,
        write_json,
        write_results,
    )
    from fricdamp.report import write_report

    system, outputs = computed.system, computed.outputs
    for name, out in outputs.items():
        out.summary.setdefault("runtime_s", computed.runtimes_s[name])
    top_level = _top_level_keys(outputs)

    def writing(path, write):
        """``write()`` the file ``path``; an OSError (disk full, permission) names it."""
        try:
            return write()
        except FricdampOutputError:
            raise
        except OSError as exc:
            raise output_error(path, exc) from None

    results_name = f"results.{results_format}"
    figures: dict[str, list[tuple[str, str]]] = {}
    for name, out in outputs.items():
        figs = out.figures() if callable(out.figures) else out.figures
        figures[name] = []
        for filename, title, fig in figs:
            if Path(filename).name != filename or not filename.endswith(".png"):
                raise ValueError(f"analysis {name!r}: figure file name {filename!r} must be a "
                                 "plain '<name>.png'")
            if any(filename == f for figs_ in figures.values() for f, _ in figs_):
                raise ValueError(f"analysis {name!r}: figure {filename!r} is written twice")
            writing(out_dir / filename,
                    lambda f=fig, p=out_dir / filename: save_figure(f, p))
            figures[name].append((filename, title))

    ebe = [o.summary["energy_balance_error"] for o in outputs.values()
           if o.summary.get("energy_balance_error") is not None]
    summary = {
        "fricdamp_version": __version__,
        "case": case.to_dict(),
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "runtime_s": None,
        "energy_balance_error": max(ebe) if ebe else None,
        "verdict": verdict_summary(outputs),
        "model": describe_system(system),
    }
    for name, out in outputs.items():
        summary[name] = out.summary
    summary.update(top_level)
    notes = [f"{name}: {n}" for name, out in outputs.items() for n in out.notes]
    if notes:
        summary["notes"] = notes
    files = {"summary": "summary.json", "results": results_name, "report": "report.html",
             "figures": [f for figs in figures.values() for f, _ in figs]}
    summary["files"] = files

    ds = combine_results({n: o.arrays for n, o in outputs.items()},
                         attrs={"fricdamp_version": __version__, "case_name": case.name,
                                "case_toml": case.text})
    writing(out_dir / results_name, lambda: write_results(out_dir / results_name, ds))
    summary["runtime_s"] = time.perf_counter() - start
    writing(out_dir / "summary.json", lambda: write_json(out_dir / "summary.json", summary))
    writing(out_dir / "report.html", lambda: write_report(out_dir / "report.html",
                                                          summary=summary, case_text=case.text,
                                                          figures=figures))
    return RunOutcome(out_dir=out_dir, summary=summary, files=files, outputs=outputs)


def _top_level_keys(outputs: dict) -> dict:
    """The analyses' ``top_level`` keys merged (ValueError for a reserved or clashing key)."""
    from fricdamp.iofiles import to_jsonable

    merged: dict = {}
    for name, out in outputs.items():
        for key, value in out.top_level.items():
            if key in RESERVED_SUMMARY_KEYS or key in outputs:
                raise ValueError(f"analysis {name!r}: top-level summary key {key!r} is "
                                 "reserved (summary.json or an analysis section uses it)")
            value = to_jsonable(value)
            if key in merged and merged[key] != value:
                raise ValueError(f"analysis {name!r}: top-level summary key {key!r} is set "
                                 "by another analysis to a different value")
            merged[key] = value
    return merged


def describe_system(system) -> dict:
    """Key numbers of a system: DOFs, contacts and linear natural frequencies.

    ``natural_frequencies_stuck_hz`` adds each contact's tangent stiffness in its virgin state
    (all contacts stuck); ``natural_frequencies_free_hz`` leaves the contacts out (all sliding
    freely). Computed for models up to 500 DOFs (dense generalised eigenproblem).
    """
    import scipy.linalg as sla
    import scipy.sparse as sp

    from fricdamp.structure.system import MechanicalSystem

    if not isinstance(system, MechanicalSystem):
        # model objects of the papers' systems describe themselves
        info = dict(system.describe()) if hasattr(system, "describe") else {}
        info.setdefault("n_dof", int(getattr(system, "n_dof", 0)))
        info.setdefault("contacts", [])
        return info
    info = {"n_dof": system.n_dof, "dof_names": list(system.names),
            "contacts": [{"name": c.name, "law": type(c.law).__name__,
                          "n_contacts": c.n_contacts, "n_dir": c.n_dir}
                         for c in system.contacts]}
    if system.n_dof > 500:
        return info

    def dense(A):
        return A.toarray() if sp.issparse(A) else np.asarray(A, float)

    M, K = dense(system.M), dense(system.K)
    Kc = K.copy()
    for c in system.contacts:
        st = c.law.initial_state()
        kt = c.law.step(st, np.zeros((c.n_contacts, c.n_dir))).stiffness  # (nc, nd, nd)
        P = dense(c.projection)
        blk = sla.block_diag(*kt) if c.n_contacts > 1 else kt[0]
        Kc += P.T @ blk @ P

    def freqs(Kx):
        lam = sla.eigh(0.5 * (Kx + Kx.T), M, eigvals_only=True)
        return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)

    info["natural_frequencies_stuck_hz"] = freqs(Kc).tolist()
    if system.contacts:
        info["natural_frequencies_free_hz"] = freqs(K).tolist()
    return info


# ================================================================================ builders
def attachment_projection(spec: Attachment, n_dof: int) -> np.ndarray:
    """Projection rows of a 1D contact from ``dofs`` / ``between`` (1-based DOF numbers).

    Returns
    -------
    ndarray, shape (n_contacts, n_dof)
        ``dofs = [i, ...]``: one row ``e_i`` per DOF; ``between = [i, j]``: ``e_i - e_j``.

    Raises
    ------
    CaseError
        If a DOF number exceeds ``n_dof``.
    """
    key, nums = ("dofs", spec.dofs) if spec.dofs is not None else ("between", spec.between)
    bad = [d for d in nums if d > n_dof]
    if bad:
        raise CaseError(f"{key} = {nums}: DOF {bad[0]} does not exist; the model has {n_dof} "
                        f"DOF{'s' if n_dof > 1 else ''}, numbered 1 to {n_dof}")
    if spec.dofs is not None:
        P = np.zeros((len(nums), n_dof))
        P[np.arange(len(nums)), np.asarray(nums) - 1] = 1.0
        return P
    P = np.zeros((1, n_dof))
    P[0, nums[0] - 1] = 1.0
    P[0, nums[1] - 1] = -1.0
    return P


def _build_chain(spec: ChainModel, ctx: BuildContext):
    from fricdamp.structure import chain

    return chain(spec.masses_kg, spec.springs_N_per_m, dampers=spec.dampers_Ns_per_m,
                 ground=spec.ground, dof_names=spec.dof_names)


#: Largest matrix file read by ``[model] type = "matrices"`` (a dense 10,000 x 10,000 matrix
#: in Matrix Market text is about 2.5 GB; a sector's sparse matrices are far smaller).
MAX_MATRIX_FILE_BYTES = 4 * 2**30


def _check_matrix_file(path: Path, key: str, rel: str) -> None:
    """A matrix file must be an existing regular file of sensible size (ModelError)."""
    import stat

    if str(rel).strip() in ("", ".", ".."):
        raise ModelError(f"{key} = {rel!r} is not a file name: give the path of a Matrix "
                         "Market (.mtx) or ANSYS (.full) file, relative to the case file")
    try:
        st = path.stat()
    except FileNotFoundError:
        raise ModelError(f"{key} = {rel!r}: the file {str(path)!r} does not exist") from None
    except OSError as exc:
        raise ModelError(f"{key} = {rel!r}: cannot read {str(path)!r} ({exc.strerror})") from None
    if stat.S_ISDIR(st.st_mode):
        raise ModelError(f"{key} = {rel!r} is a folder ({str(path)!r}), not a matrix file")
    if not stat.S_ISREG(st.st_mode):
        raise ModelError(f"{key} = {rel!r} is not a regular file (a device or pipe)")
    if st.st_size > MAX_MATRIX_FILE_BYTES:
        raise ModelError(f"{key} = {rel!r} is {st.st_size / 2**30:.1f} GiB; matrix files may "
                         f"be at most {MAX_MATRIX_FILE_BYTES / 2**30:.0f} GiB")


def _build_matrices(spec: MatricesModel, ctx: BuildContext):
    from fricdamp.structure import from_matrices
    from fricdamp.structure.io import read_matrix

    mats = {}
    for key in ("mass", "stiffness", "damping"):
        rel = getattr(spec, key)
        if rel is None:
            continue
        path = Path(rel) if Path(rel).is_absolute() else ctx.base_dir / rel
        _check_matrix_file(path, key, rel)
        try:
            mats[key] = read_matrix(path, key)
        except ModelError as exc:
            raise ModelError(f"{key} = {rel!r}: {exc}") from None
    rayleigh = None
    if spec.rayleigh_alpha_per_s is not None or spec.rayleigh_beta_s is not None:
        rayleigh = (spec.rayleigh_alpha_per_s or 0.0, spec.rayleigh_beta_s or 0.0)
    try:
        return from_matrices(mats["mass"], mats["stiffness"], mats.get("damping"),
                             rayleigh=rayleigh, dof_names=spec.dof_names)
    except ModelError as exc:
        raise ModelError(f"mass = {spec.mass!r}, stiffness = {spec.stiffness!r}: {exc}") from None


def _build_jenkins(spec: JenkinsContact, ctx: BuildContext):
    from fricdamp.contact import Jenkins
    from fricdamp.structure import ContactElement

    P = attachment_projection(spec, ctx.n_dof)
    law = Jenkins(spec.stiffness_N_per_m, spec.slip_force, n_contacts=P.shape[0])
    return ContactElement(law, P, name=spec.name or ctx.name)


def _build_coulomb(spec: CoulombContact, ctx: BuildContext):
    from fricdamp.contact.coulomb import Coulomb
    from fricdamp.structure import ContactElement

    P = attachment_projection(spec, ctx.n_dof)
    law = Coulomb(spec.stiffness_N_per_m, spec.normal_load_N, spec.mu_static, spec.mu_sliding,
                  spec.decay_s_per_m, n_contacts=P.shape[0])
    return ContactElement(law, P, name=spec.name or ctx.name)


def _build_cubic_spring(spec: CubicSpringContact, ctx: BuildContext):
    from fricdamp.contact.cubic import CubicSpring
    from fricdamp.structure import ContactElement

    P = attachment_projection(spec, ctx.n_dof)
    law = CubicSpring(spec.k3_N_per_m3, n_contacts=P.shape[0])
    return ContactElement(law, P, name=spec.name or ctx.name)


def _build_iwan(spec: IwanContact, ctx: BuildContext):
    from fricdamp.contact.iwan import Iwan
    from fricdamp.structure import ContactElement

    P = attachment_projection(spec, ctx.n_dof)
    law = Iwan(spec.stiffness_N_per_m, spec.slip_force_N, spec.chi, spec.beta,
               n_elements=spec.n_elements, min_ratio=spec.min_ratio, n_contacts=P.shape[0])
    return ContactElement(law, P, name=spec.name or ctx.name)


def _direction_row(dofs: list[int], n_dof: int, key: str) -> np.ndarray:
    bad = [d for d in dofs if d > n_dof]
    if bad:
        raise CaseError(f"{key} = {dofs}: DOF {bad[0]} does not exist; the model has {n_dof} "
                        f"DOFs, numbered 1 to {n_dof}")
    row = np.zeros(n_dof)
    row[dofs[0] - 1] = 1.0
    if len(dofs) == 2:
        row[dofs[1] - 1] = -1.0
    return row


def _build_contact3d(spec: Contact3DContact, ctx: BuildContext):
    from fricdamp.contact.element3d import Contact3D
    from fricdamp.structure import ContactElement

    n = ctx.n_dof
    rows = [_direction_row(spec.normal, n, "normal")]
    rows += [_direction_row(d, n, f"tangential entry {i + 1}")
             for i, d in enumerate(spec.tangential)]
    if len(rows) == 2:  # one tangential direction: the second stays zero
        rows.append(np.zeros(n))
    if spec.preload_N is not None:
        law = Contact3D.from_preload(spec.normal_stiffness_N_per_m, spec.preload_N,
                                     spec.tangential_stiffness_N_per_m, spec.mu)
    else:
        law = Contact3D(spec.normal_stiffness_N_per_m, spec.tangential_stiffness_N_per_m,
                        spec.mu, spec.offset_m or 0.0)
    return ContactElement(law, np.array(rows), name=spec.name or ctx.name)


register_model("chain", ChainModel, _build_chain,
               description="lumped masses, springs and dashpots in a chain")
register_model("matrices", MatricesModel, _build_matrices,
               description="mass, stiffness (and damping) matrices from Matrix Market files")
register_contact("jenkins", JenkinsContact, _build_jenkins,
                 description="spring in series with a Coulomb slider (1D)")
register_contact("coulomb", CoulombContact, _build_coulomb,
                 description="penalty spring and slider with static/kinetic mu(v) (1D)")
register_contact("cubic_spring", CubicSpringContact, _build_cubic_spring,
                 description="cubic spring f = k3 u^3, the Duffing nonlinearity (1D)")
register_contact("iwan", IwanContact, _build_iwan,
                 description="four-parameter Iwan joint (Segalman): parallel Jenkins "
                             "elements with a power-law slip density (1D)")
register_contact("contact3d", Contact3DContact, _build_contact3d,
                 description="unilateral normal penalty with 2D friction (3 directions)")
