"""Run a validated case: the registry of model types, contact types and analyses.

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
  lengths, DOF numbers) and raises :class:`~fricdamp.errors.CaseError`.

``schema`` is a pydantic model (derive from :class:`fricdamp.case.Section` for the strict
rules); the ``type`` key is removed from the table before it is validated.

A run computes every analysis first and writes only then, each file atomically, so a failed
run leaves no half-written result behind.
"""

from __future__ import annotations

import datetime as _dt
import logging
import time
from collections.abc import Callable, Mapping
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
    ForcedResponse,
    FreeDecay,
    Hysteresis,
    JenkinsContact,
    MatricesModel,
    SolverSettings,
    parse_case,
    read_case_file,
)
from fricdamp.errors import CaseError, ConvergenceError, ModelError

log = logging.getLogger(__name__)

__all__ = [
    "REGISTRY",
    "AnalysisOutput",
    "Entry",
    "BuildContext",
    "Registry",
    "RunContext",
    "RunOutcome",
    "attachment_projection",
    "build_system",
    "describe_system",
    "coulomb_loop_energy",
    "jenkins_loop_energy",
    "load_builtin_case",
    "load_case",
    "register_analysis",
    "register_closed_form",
    "register_contact",
    "register_model",
    "register_table",
    "run_case",
    "run_forced_response",
    "run_free_decay",
    "run_hysteresis",
]


# ================================================================================ registry
#: Top-level keys of summary.json besides the analyses' sections.
RESERVED_SUMMARY_KEYS = frozenset({"fricdamp_version", "case", "created", "runtime_s",
                                   "energy_balance_error", "model", "notes", "files"})


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
    """

    summary: dict
    arrays: dict = field(default_factory=dict)
    figures: list | Callable = field(default_factory=list)
    headline: str = ""
    notes: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class RunOutcome:
    """Result of :func:`run_case`: the output folder, summary and the files written."""

    out_dir: Path
    summary: dict
    files: dict
    outputs: dict

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
def run_case(case: Case, out_dir: str | Path, *, registry: Registry | None = None,
             progress: bool = False, results_format: str = "nc",
             echo: Callable[[str], None] | None = None) -> RunOutcome:
    """Run every analysis of ``case`` and write the results into ``out_dir``.

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
    """
    from fricdamp.iofiles import combine_results, save_figure, write_json, write_results
    from fricdamp.report import write_report

    if results_format not in ("nc", "npz"):
        raise CaseError(f"results format must be 'nc' or 'npz', got {results_format!r}")
    reg = registry or REGISTRY
    echo = echo or (lambda line: None)
    start = time.perf_counter()
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise CaseError(f"the output folder {str(out_dir)!r} is a file; choose another --out")
    system = build_system(case, reg)
    ctx = RunContext(case=case, solver=case.solver, progress=progress)

    outputs: dict[str, AnalysisOutput] = {}
    for name, spec in case.analyses.items():
        t_a = time.perf_counter()
        try:
            out = reg.analyses[name].fn(system, spec, ctx)
        except ConvergenceError as exc:
            raise ConvergenceError(f"[analysis.{name}] {exc}") from exc
        except ModelError as exc:
            raise CaseError(f"[analysis.{name}] {exc}") from exc
        out.summary.setdefault("runtime_s", time.perf_counter() - t_a)
        outputs[name] = out
        echo(f"  {name}: {out.headline}" if out.headline else f"  {name}: done")
        for note in out.notes:
            echo(f"  {name}: note: {note}")

    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CaseError(f"cannot create the output folder {str(out_dir)!r}: {exc}") from None
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
            save_figure(fig, out_dir / filename)
            figures[name].append((filename, title))

    ebe = [o.summary["energy_balance_error"] for o in outputs.values()
           if o.summary.get("energy_balance_error") is not None]
    summary = {
        "fricdamp_version": __version__,
        "case": case.to_dict(),
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "runtime_s": None,
        "energy_balance_error": max(ebe) if ebe else None,
        "model": describe_system(system),
    }
    for name, out in outputs.items():
        summary[name] = out.summary
    notes = [f"{name}: {n}" for name, out in outputs.items() for n in out.notes]
    if notes:
        summary["notes"] = notes
    files = {"summary": "summary.json", "results": results_name, "report": "report.html",
             "figures": [f for figs in figures.values() for f, _ in figs]}
    summary["files"] = files

    ds = combine_results({n: o.arrays for n, o in outputs.items()},
                         attrs={"fricdamp_version": __version__, "case_name": case.name,
                                "case_toml": case.text})
    write_results(out_dir / results_name, ds)
    summary["runtime_s"] = time.perf_counter() - start
    write_json(out_dir / "summary.json", summary)
    write_report(out_dir / "report.html", summary=summary, case_text=case.text,
                 figures=figures)
    return RunOutcome(out_dir=out_dir, summary=summary, files=files, outputs=outputs)


def describe_system(system) -> dict:
    """Key numbers of a system: DOFs, contacts and linear natural frequencies.

    ``natural_frequencies_stuck_hz`` adds each contact's tangent stiffness in its virgin state
    (all contacts stuck); ``natural_frequencies_free_hz`` leaves the contacts out (all sliding
    freely). Computed for models up to 500 DOFs (dense generalised eigenproblem).
    """
    import scipy.linalg as sla
    import scipy.sparse as sp

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


def _build_matrices(spec: MatricesModel, ctx: BuildContext):
    from fricdamp.structure import from_matrices
    from fricdamp.structure.io import read_matrix

    mats = {}
    for key in ("mass", "stiffness", "damping"):
        rel = getattr(spec, key)
        if rel is None:
            continue
        path = Path(rel) if Path(rel).is_absolute() else ctx.base_dir / rel
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
register_contact("contact3d", Contact3DContact, _build_contact3d,
                 description="unilateral normal penalty with 2D friction (3 directions)")


# ========================================================================== closed forms
#: Closed-form loop energies per law class, used by the hysteresis analysis.
_CLOSED_FORMS: dict[type, Callable] = {}


def register_closed_form(law_class: type, fn: Callable) -> None:
    """Register ``fn(law, amplitudes) -> (n_contacts, n_amplitudes)`` energy per cycle [J]
    for ``u = A sin(theta)``; shown next to the numerical loops of ``[analysis.hysteresis]``."""
    _CLOSED_FORMS[law_class] = fn


def jenkins_loop_energy(law, amplitudes) -> np.ndarray:
    """Energy per cycle of Jenkins elements, ``W = 4 F_s (A - F_s/k_t)`` for ``A > F_s/k_t``.

    Closed form of den Hartog / Iwan (docs REFERENCES.md, "Jenkins element"); 0 while stuck.
    Returns shape (n_contacts, n_amplitudes) [J].
    """
    A = np.asarray(amplitudes, float)[None, :]
    fs = law.slip_force[:, None]
    a_slip = fs / law.stiffness[:, None]
    return np.where(A > a_slip, 4.0 * fs * (A - a_slip), 0.0)


def coulomb_loop_energy(law, amplitudes) -> np.ndarray | None:
    """Energy per cycle of static/kinetic Coulomb sliders with constant sliding coefficient.

    Derived here for ``u = A sin(theta)`` (steady cycle): a reversal re-sticks the slider at
    ``+mu_d N``; it breaks away again after the travel ``L = (mu_s + mu_d) N / k_t`` at
    ``-mu_s N`` and slides at ``-mu_d N``. Integrating ``f du`` over both branches::

        W = 4 mu_d N A - (mu_s + mu_d)(3 mu_d - mu_s) N^2 / k_t    for A > mu_s N / k_t

    and 0 below (never breaks away). With mu_s = mu_d it is the Jenkins form
    ``4 mu N (A - mu N / k_t)``. Returns None when a contact has ``decay > 0``
    (velocity-dependent coefficient: no closed form), else (n_contacts, n_amplitudes) [J].
    """
    if np.any(law.decay > 0):
        return None
    A = np.asarray(amplitudes, float)[None, :]
    N, kt = law.normal_load[:, None], law.stiffness[:, None]
    mus, mud = law.mu_static[:, None], law.mu_sliding[:, None]
    W = 4 * mud * N * A - (mus + mud) * (3 * mud - mus) * N**2 / kt
    return np.where(A > mus * N / kt, W, 0.0)


def _register_default_closed_forms() -> None:
    from fricdamp.contact import Jenkins
    from fricdamp.contact.coulomb import Coulomb

    register_closed_form(Jenkins, jenkins_loop_energy)
    register_closed_form(Coulomb, coulomb_loop_energy)


_register_default_closed_forms()


# ================================================================================ analyses
def _contact_labels(system) -> list[tuple[int, int, str]]:
    """(element index, contact index, label) for every single contact of the system."""
    out = []
    for e, c in enumerate(system.contacts):
        for k in range(c.n_contacts):
            out.append((e, k, c.name if c.n_contacts == 1 else f"{c.name}[{k + 1}]"))
    return out


def _check_vector(values, n_dof: int, key: str) -> None:
    if values is not None and len(values) != n_dof:
        raise CaseError(f"{key} must have one entry per DOF ({n_dof}), got {len(values)}")


def _check_dof(dof, n_dof: int, key: str) -> None:
    if dof is not None and dof > n_dof:
        raise CaseError(f"{key} = {dof}: the model has {n_dof} DOFs, numbered 1 to {n_dof}")


# ------------------------------------------------------------------------- free decay
def _check_free_decay(system, spec: FreeDecay) -> None:
    n = system.n_dof
    _check_vector(spec.initial_displacement_m, n, "initial_displacement_m")
    _check_vector(spec.initial_velocity_m_per_s, n, "initial_velocity_m_per_s")
    _check_dof(spec.response_dof, n, "response_dof")


def _mechanical_energy(energy: Mapping) -> np.ndarray:
    return energy["kinetic"] + energy["strain"] + energy["contact_stored"]


def run_free_decay(system, spec: FreeDecay, ctx: RunContext) -> AnalysisOutput:
    """Free decay by time stepping; damping ratio and frequency vs amplitude from the peaks.

    The decay of ``response_dof`` is analysed by
    :func:`fricdamp.analysis.decay.decay_damping` (peak method). The energy balance error is
    the time integrator's (:attr:`TimeResult.energy_balance_error`).
    """
    import xarray as xr

    from fricdamp.solvers.timestep import simulate

    n = system.n_dof
    q0 = np.zeros(n) if spec.initial_displacement_m is None else np.asarray(
        spec.initial_displacement_m, float)
    v0 = np.zeros(n) if spec.initial_velocity_m_per_s is None else np.asarray(
        spec.initial_velocity_m_per_s, float)
    if spec.response_dof is not None:
        dof = spec.response_dof - 1
    else:
        dof = int(np.argmax(np.abs(q0))) if np.any(q0) else int(np.argmax(np.abs(v0)))
    res = simulate(system.with_loads(), spec.duration_s, spec.time_step_s, q0=q0, v0=v0,
                   save_every=spec.save_every, **ctx.simulate_kwargs())
    if not res.success:
        raise ConvergenceError(res.message)

    notes = []
    x = res.q[:, dof]
    try:
        decay, center = _identify_decay(res.t, x)
        amp = np.asarray(decay.amplitude, float)
        zeta = np.asarray(decay.damping_ratio, float)
        freq = np.asarray(decay.frequency_hz, float)
    except ModelError as exc:
        notes.append(f"no damping could be identified from the decay of "
                     f"{system.names[dof]}: {exc}")
        decay, center = None, 0.0
        amp = zeta = freq = np.zeros(0)

    e = res.energy
    mech = _mechanical_energy(e)
    summary = {
        "response_dof": dof + 1,
        "response_dof_name": system.names[dof],
        "amplitude_m": amp,
        "damping_ratio": zeta,
        "frequency_hz": freq,
        "max_damping_ratio": float(np.nanmax(zeta)) if zeta.size else None,
        "amplitude_at_max_damping_m": float(amp[np.nanargmax(zeta)]) if zeta.size else None,
        "mean_damping_ratio": float(decay.mean_damping_ratio) if decay is not None else None,
        "envelope_model": decay.model if decay is not None else None,
        "oscillation_center_m": float(center),
        "initial_energy_J": float(mech[0]),
        "final_energy_J": float(mech[-1]),
        "contact_dissipation_J": float(e["contact_dissipation"][-1] - e["contact_dissipation"][0]),
        "viscous_dissipation_J": float(e["viscous_dissipation"][-1] - e["viscous_dissipation"][0]),
        "energy_balance_error": float(res.energy_balance_error),
        "n_steps": int(res.n_steps),
        "solver_runtime_s": float(res.runtime_s),
    }
    decay_ds = xr.Dataset(
        {"amplitude": ("peak", amp, {"units": "m"}),
         "damping_ratio": ("peak", zeta, {"units": "1"}),
         "frequency": ("peak", freq, {"units": "Hz"})},
        attrs={"response_dof": dof + 1, "method": "peaks"})
    arrays = {"response": res.to_xarray(), "decay": decay_ds}
    headline = (f"{res.n_steps} steps in {res.runtime_s:.2f} s; "
                + (f"largest damping ratio {100 * summary['max_damping_ratio']:.3g} % at "
                   f"amplitude {summary['amplitude_at_max_damping_m']:.3g} m; " if zeta.size
                   else "")
                + f"energy balance error {res.energy_balance_error:.2e}")

    def figures():
        from fricdamp import plot

        names = list(system.names)
        figs = [("free_decay_response.png", "Free decay: displacement of each DOF",
                 plot.time_histories(res.t, res.q, names, title="Free decay")),
                ("free_decay_energy.png", "Free decay: energy balance",
                 plot.energy_partition(res.t, e, title="Free decay: where the energy goes"))]
        if zeta.size:
            figs.insert(1, ("free_decay_damping.png",
                            f"Free decay: damping ratio and frequency vs amplitude of "
                            f"{names[dof]}",
                            plot.damping_vs_amplitude(amp, zeta, freq,
                                                      title=f"Free decay of {names[dof]}")))
        loops = _loops_of(system, res.contact_displacement, res.contact_force, slice(None))
        if loops:
            figs.append(("free_decay_contacts.png", "Free decay: contact force vs relative "
                         "displacement", plot.hysteresis_loops(
                             loops, title="Contacts during the free decay")))
        return figs

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes)


def _identify_decay(t, x):
    """Decay identification about the equilibrium the oscillation settles to.

    A friction contact that sticks leaves the structure oscillating about a shifted
    equilibrium (the slider stays where it stopped). Measured from zero, alternate half-cycle
    peaks then differ by twice that offset and the half-cycle decrements alternate in sign.
    When the record ends in a nearly stationary oscillation (last two envelope points within
    5 %), the decay is analysed again about the level ``((p1 + p3) / 2 + p2) / 2`` of its last
    three extrema (alternating maxima and minima; averaging the outer two cancels a linear
    decay of the amplitude). Returns (DecayResult, center [m]).
    """
    from fricdamp.analysis.decay import decay_damping, find_peaks

    decay = decay_damping(t, x, method="peaks", kind="auto")
    env = decay.envelope.amplitude
    if env.size >= 3 and abs(env[-1] - env[-2]) < 0.05 * env[-1]:
        pk = find_peaks(t, x, negative=True)
        v, sg = pk.value[-3:], pk.sign[-3:]
        if v.size == 3 and sg[0] == sg[2] != sg[1]:
            center = 0.5 * (0.5 * (v[0] + v[2]) + v[1])
            if center != 0.0:
                return decay_damping(t, x, method="peaks", kind="auto", center=center), center
    return decay, 0.0


def _plot_direction(n_dir: int) -> int:
    """Direction drawn in loop plots: the only one, or the first tangential (index 1)."""
    return 0 if n_dir == 1 else 1


def _loops_of(system, cu, cf, sl: slice) -> list[tuple[str, np.ndarray, np.ndarray]]:
    loops = []
    for e, k, label in _contact_labels(system):
        d = _plot_direction(system.contacts[e].n_dir)
        loops.append((label, cu[e][sl, k, d], cf[e][sl, k, d]))
    return loops


# --------------------------------------------------------------------- forced response
def _check_forced(system, spec: ForcedResponse) -> None:
    _check_vector(spec.force_amplitude_N, system.n_dof, "force_amplitude_N")


def run_forced_response(system, spec: ForcedResponse, ctx: RunContext) -> AnalysisOutput:
    """Harmonic force ``F cos(2 pi f t)`` from rest, time stepping to a steady state.

    The last excitation period is taken as the steady state: amplitude per DOF (half the
    peak-to-peak), each contact's hysteresis loop and its area (energy dissipated per cycle,
    summed over the contact's directions), the input work per cycle and the viscous
    dissipation per cycle. ``cycle_energy_balance_error`` is
    ``|W_in - W_viscous - W_contacts - dE_mech| / W_in`` over that period (0 for an exact
    integration), ``steady_state_change`` the relative change of the amplitudes between the
    last two periods (small once the transient has died out).
    """
    import xarray as xr

    from fricdamp.analysis.energy import loop_area
    from fricdamp.solvers.timestep import simulate
    from fricdamp.structure import HarmonicLoad

    f_hz = spec.frequency_hz
    N = spec.steps_per_period
    period = 1.0 / f_hz
    load = HarmonicLoad(np.asarray(spec.force_amplitude_N, float), 2 * np.pi * f_hz)
    res = simulate(system.with_loads(load), spec.periods * period, period / N,
                   **ctx.simulate_kwargs())
    if not res.success:
        raise ConvergenceError(res.message)

    n_t = res.t.size
    last = slice(n_t - N - 1, n_t)  # N + 1 samples: one full period, both ends
    prev = slice(n_t - 2 * N - 1, n_t - N)
    q_last, q_prev = res.q[last], res.q[prev]
    amp = 0.5 * (q_last.max(axis=0) - q_last.min(axis=0))
    amp_prev = 0.5 * (q_prev.max(axis=0) - q_prev.min(axis=0))
    change = float(np.max(np.abs(amp - amp_prev)) / max(np.max(amp), 1e-300))

    e = res.energy
    mech = _mechanical_energy(e)

    def per_cycle(arr):
        return float(arr[-1] - arr[-N - 1])

    w_in = per_cycle(e["input_work"])
    w_visc = per_cycle(e["viscous_dissipation"])
    w_cont = per_cycle(e["contact_dissipation"])
    d_mech = per_cycle(mech)
    cycle_err = abs(w_in - w_visc - w_cont - d_mech) / abs(w_in) if w_in else None

    contacts = {}
    for el, k, label in _contact_labels(system):
        u = res.contact_displacement[el][last, k, :]
        f = res.contact_force[el][last, k, :]
        area = sum(loop_area(u[:, d], f[:, d]) for d in range(u.shape[1]))
        dd = _plot_direction(u.shape[1])
        contacts[label] = {
            "dissipated_energy_per_cycle_J": float(area),
            "relative_displacement_amplitude_m": float(0.5 * np.ptp(u[:, dd])),
            "force_amplitude_N": float(0.5 * np.ptp(f[:, dd])),
        }

    # energy per period over the whole run (convergence to the steady state)
    idx = np.arange(0, n_t, N)
    w_in_k = np.diff(e["input_work"][idx])
    w_d_k = np.diff(e["viscous_dissipation"][idx] + e["contact_dissipation"][idx])

    summary = {
        "frequency_hz": f_hz,
        "dof_names": list(system.names),
        "amplitude_m": amp,
        "steady_state_change": change,
        "input_work_per_cycle_J": w_in,
        "viscous_dissipation_per_cycle_J": w_visc,
        "contact_dissipation_per_cycle_J": w_cont,
        "cycle_energy_balance_error": cycle_err,
        "contacts": contacts,
        "energy_balance_error": float(res.energy_balance_error),
        "n_steps": int(res.n_steps),
        "solver_runtime_s": float(res.runtime_s),
    }
    notes = []
    if change > 1e-2:
        notes.append(f"the response is not yet steady (amplitudes changed by {100 * change:.2g} "
                     "% over the last period); increase periods")
    names = list(system.names)
    arrays = {
        "response": res.to_xarray(),
        "steady_state": xr.Dataset(
            {"amplitude": ("dof", amp, {"units": "m", "long_name": "amplitude, last period"})},
            coords={"dof": names}),
        "cycles": xr.Dataset(
            {"input_work": ("period", w_in_k, {"units": "J"}),
             "dissipated_energy": ("period", w_d_k, {"units": "J"})},
            coords={"period": np.arange(1, w_in_k.size + 1)}),
    }
    i_max = int(np.argmax(amp))
    headline = (f"{res.n_steps} steps in {res.runtime_s:.2f} s; amplitude of {names[i_max]} "
                f"{amp[i_max]:.3g} m at {f_hz:g} Hz; input work per cycle {w_in:.3g} J; "
                f"energy balance error {res.energy_balance_error:.2e}")

    def figures():
        from fricdamp import plot

        figs = [("forced_response_time.png",
                 f"Forced response at {f_hz:g} Hz: displacement of each DOF",
                 plot.time_histories(res.t, res.q, names, title=f"Forced response at "
                                     f"{f_hz:g} Hz"))]
        loops = _loops_of(system, res.contact_displacement, res.contact_force, last)
        if loops:
            figs.append(("forced_response_loops.png",
                         "Forced response: hysteresis loop of each contact over the last period",
                         plot.hysteresis_loops(loops, title="Contacts over the last period")))
        figs.append(("forced_response_energy.png",
                     "Forced response: input work and dissipated energy per period",
                     plot.cycle_energy(np.arange(1, w_in_k.size + 1), w_in_k, w_d_k,
                                       title="Energy per excitation period")))
        return figs

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes)


# -------------------------------------------------------------------------- hysteresis
def _hysteresis_elements(system, spec: Hysteresis):
    """The contacts to drive: those named in ``contacts``, or every one-directional one."""
    names = [c.name for c in system.contacts]
    if spec.contacts is not None:
        for n in spec.contacts:
            if n not in names:
                raise CaseError(f"contacts: there is no contact named {n!r}; the case has "
                                f"{', '.join(repr(x) for x in names) or 'no contacts'}")
        chosen = [c for c in system.contacts if c.name in spec.contacts]
        multi = [c for c in chosen if c.n_dir != 1]
        if multi:
            raise CaseError(f"contacts: {multi[0].name!r} has {multi[0].n_dir} directions; the "
                            "hysteresis analysis drives one-directional laws only")
        return chosen
    chosen = [c for c in system.contacts if c.n_dir == 1]
    if not chosen:
        raise CaseError("needs at least one one-directional contact (jenkins, coulomb) to "
                        "drive; the case has " + (", ".join(repr(x) for x in names) or "none"))
    return chosen


def _check_hysteresis(system, spec: Hysteresis) -> None:
    _hysteresis_elements(system, spec)


def run_hysteresis(system, spec: Hysteresis, ctx: RunContext) -> AnalysisOutput:
    """Drive each contact law with ``u = A sin(2 pi f t)``; loop energy vs amplitude.

    Each amplitude starts from the virgin state and runs ``cycles`` cycles; the last cycle
    is the loop, its area (:func:`fricdamp.analysis.energy.loop_area`) the energy dissipated
    per cycle. Where a closed form is registered for the law (Jenkins:
    ``W = 4 F_s (A - F_s/k_t)``), it is given alongside with the largest deviation relative
    to the largest closed-form energy.
    """
    import xarray as xr

    from fricdamp.analysis.energy import loop_area

    elements = _hysteresis_elements(system, spec)
    A = np.asarray(spec.amplitudes_m, float)
    n_s = spec.samples_per_cycle
    omega = 2 * np.pi * spec.frequency_hz
    t = np.arange(spec.cycles * n_s + 1) / (n_s * spec.frequency_hz)
    last = slice(t.size - n_s - 1, t.size)
    labels, energies, closed, loops_f = [], [], [], []
    for c in elements:
        law = c.law
        nc = c.n_contacts
        W = np.empty((nc, A.size))
        fu = np.empty((nc, A.size, n_s + 1))
        for j, a in enumerate(A):
            u = np.broadcast_to((a * np.sin(omega * t))[:, None, None], (t.size, nc, 1))
            v = np.broadcast_to((a * omega * np.cos(omega * t))[:, None, None], u.shape)
            f = law.drive(np.array(u), np.array(v))
            for k in range(nc):
                W[k, j] = loop_area(u[last, k, 0], f[last, k, 0])
                fu[k, j] = f[last, k, 0]
        cf = _closed_form(law, A)
        for k in range(nc):
            labels.append(c.name if nc == 1 else f"{c.name}[{k + 1}]")
            energies.append(W[k])
            closed.append(None if cf is None else cf[k])
            loops_f.append(fu[k])

    contacts = {}
    errors = []
    for label, W, Wc in zip(labels, energies, closed, strict=True):
        entry = {"loop_energy_J": W}
        if Wc is not None:
            scale = np.max(np.abs(Wc))
            err = float(np.max(np.abs(W - Wc)) / scale) if scale > 0 else float(np.max(np.abs(W)))
            entry.update(closed_form_J=Wc, closed_form_error=err)
            errors.append(err)
        contacts[label] = entry
    summary = {"amplitude_m": A, "frequency_hz": spec.frequency_hz, "cycles": spec.cycles,
               "samples_per_cycle": n_s, "contacts": contacts,
               "max_closed_form_error": max(errors) if errors else None}
    u_last = A[:, None] * np.sin(omega * t[last])[None, :]
    arrays = {"loops": xr.Dataset(
        {"u": (("amplitude", "sample"), u_last, {"units": "m"}),
         "force": (("contact", "amplitude", "sample"), np.array(loops_f), {"units": "N"}),
         "loop_energy": (("contact", "amplitude"), np.array(energies), {"units": "J"})},
        coords={"contact": labels, "amplitude": A})}
    if any(c is not None for c in closed):
        arrays["loops"]["closed_form_energy"] = (
            ("contact", "amplitude"),
            np.array([np.full(A.size, np.nan) if c is None else c for c in closed]),
            {"units": "J"})
    headline = f"{len(labels)} contact(s) x {A.size} amplitudes" + (
        f"; largest deviation from the closed form {max(errors):.2e}" if errors else "")

    def figures():
        from fricdamp import plot

        loops = [(f"A = {plot.format_si(a, 'm')}", u_last[j], loops_f[i][j])
                 for i, label in enumerate(labels) for j, a in enumerate(A)]
        return [
            ("hysteresis_loops.png", "Hysteresis: force vs imposed relative displacement",
             plot.hysteresis_loops(loops, title="Contact laws driven at each amplitude",
                                   group=[lab for lab in labels for _ in A])),
            ("hysteresis_energy.png", "Hysteresis: dissipated energy per cycle vs amplitude",
             plot.loop_energy_vs_amplitude(A, dict(zip(labels, energies, strict=True)),
                                           _closed_form_curves(elements, A),
                                           title="Energy dissipated per cycle")),
        ]

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline)


def _closed_form_curves(elements, A) -> dict:
    """Closed-form energy on a fine amplitude grid for each contact label (or None)."""
    a_fine = np.geomspace(A.min(), A.max(), 400) if A.size > 1 else A
    curves = {}
    for c in elements:
        cf = _closed_form(c.law, a_fine)
        for k in range(c.n_contacts):
            label = c.name if c.n_contacts == 1 else f"{c.name}[{k + 1}]"
            curves[label] = None if cf is None else (a_fine, cf[k])
    return curves


def _closed_form(law, amplitudes):
    for cls in type(law).__mro__:
        if cls in _CLOSED_FORMS:
            return _CLOSED_FORMS[cls](law, amplitudes)
    return None


register_analysis("free_decay", FreeDecay, run_free_decay, check=_check_free_decay,
                  description="release from initial conditions; damping ratio vs amplitude")
register_analysis("forced_response", ForcedResponse, run_forced_response, check=_check_forced,
                  description="harmonic force to a steady state; loops and energy per cycle")
register_analysis("hysteresis", Hysteresis, run_hysteresis, check=_check_hysteresis,
                  description="contact laws driven by a sine; loop energy vs amplitude")
