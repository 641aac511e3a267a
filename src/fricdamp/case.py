"""TOML case files: the pydantic schema of each section and the validation of a whole case.

A case file has a ``[model]`` table (with ``type``), any number of ``[[contacts]]`` tables (each
with ``type``), one ``[analysis.<name>]`` table per analysis to run, an optional ``[solver]``
table, and optional top-level ``name`` and ``description``. The schema of each table is a
pydantic model registered by type or name in :mod:`fricdamp.runner`, so new model types, contact
laws and analyses are added without touching this module or the command line. The keys are
documented one by one on the "Case files" page of the fricdamp documentation.

Validation is strict: unknown keys (typos) are rejected with a "did you mean" hint, numbers must
be numbers (``"1.0"`` is not), NaN and inf are rejected everywhere, and every range violation is
reported as one :class:`~fricdamp.errors.CaseError` naming the table, the key, the allowed range
with its unit (read from the key name: ``masses_kg`` is in kg) and the value received.

DOF numbers in case files are 1-based, as engineers count them (``dofs = [1]`` is the first DOF).
"""

from __future__ import annotations

import difflib
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from fricdamp.errors import CaseError

__all__ = [
    "Attachment",
    "Case",
    "ChainModel",
    "Contact3DContact",
    "CoulombContact",
    "CubicSpringContact",
    "ForcedResponse",
    "FreeDecay",
    "Hysteresis",
    "IwanContact",
    "JenkinsContact",
    "MatricesModel",
    "Section",
    "SolverSettings",
    "parse_case",
    "read_case_file",
    "unit_of",
    "validate_section",
]

#: Longest run a case may ask for (time steps); above this the arrays would not fit in memory.
MAX_STEPS = 20_000_000


class Section(BaseModel):
    """Base of every case-file table: unknown keys rejected, strict types, no NaN or inf."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True)


#: Names of cases and contacts: they become folder and netCDF variable names.
NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.-]*$"

Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
DofNumber = Annotated[int, Field(ge=1)]


def _entries(n: int) -> str:
    return f"{n} entr{'y' if n == 1 else 'ies'}"


# ------------------------------------------------------------------------------- models
class ChainModel(Section):
    """``[model] type = "chain"``: lumped masses connected by springs and dashpots."""

    masses_kg: list[Positive] = Field(min_length=1, description="masses, one per DOF")
    springs_N_per_m: list[Positive] = Field(
        description="spring stiffnesses: ground-m1, m1-m2, ... (see ground)")
    dampers_Ns_per_m: list[NonNegative] | None = Field(
        None, description="dashpots in parallel with the springs (default none)")
    ground: Literal["first", "both", "none"] = Field(
        "first", description="where the chain is tied to the ground")
    dof_names: list[str] | None = Field(None, description="labels of the DOFs")

    @model_validator(mode="after")
    def _lengths(self):
        n = len(self.masses_kg)
        need = {"first": n, "both": n + 1, "none": n - 1}[self.ground]
        if len(self.springs_N_per_m) != need:
            raise ValueError(
                f"springs_N_per_m must have {_entries(need)} for {n} mass"
                f"{'es' if n > 1 else ''} with ground = {self.ground!r}, got "
                f"{len(self.springs_N_per_m)}")
        if self.dampers_Ns_per_m is not None and len(self.dampers_Ns_per_m) != need:
            raise ValueError(
                f"dampers_Ns_per_m must have as many entries as springs_N_per_m ({need}), "
                f"got {len(self.dampers_Ns_per_m)}")
        if self.dof_names is not None and len(self.dof_names) != n:
            raise ValueError(f"dof_names must have {n} entries (one per mass), "
                             f"got {len(self.dof_names)}")
        return self


class MatricesModel(Section):
    """``[model] type = "matrices"``: user matrices in Matrix Market files."""

    mass: str = Field(description="Matrix Market file of the mass matrix [kg], relative to the "
                                  "case file")
    stiffness: str = Field(description="Matrix Market file of the stiffness matrix [N/m]")
    damping: str | None = Field(None, description="Matrix Market file of the damping matrix "
                                                  "[N s/m]")
    rayleigh_alpha_per_s: NonNegative | None = Field(
        None, description="Rayleigh damping D = alpha M + beta K: alpha")
    rayleigh_beta_s: NonNegative | None = Field(None, description="Rayleigh damping: beta")
    dof_names: list[str] | None = Field(None, description="labels of the DOFs")

    @model_validator(mode="after")
    def _damping(self):
        rayleigh = self.rayleigh_alpha_per_s is not None or self.rayleigh_beta_s is not None
        if self.damping is not None and rayleigh:
            raise ValueError("give either damping (a matrix file) or rayleigh_alpha_per_s / "
                             "rayleigh_beta_s, not both")
        return self


# ----------------------------------------------------------------------------- contacts
class Attachment(Section):
    """Where a 1D contact acts: ``dofs = [i, ...]`` (each to ground) or ``between = [i, j]``.

    The relative displacement is ``u = q_i`` for each DOF of ``dofs`` (one contact per DOF) or
    ``u = q_i - q_j`` for ``between``. DOF numbers are 1-based.
    """

    name: str | None = Field(None, pattern=NAME_PATTERN, max_length=64,
                             description="label in results and plots")
    dofs: list[DofNumber] | None = Field(None, min_length=1,
                                         description="DOFs tied to the ground (1-based)")
    between: list[DofNumber] | None = Field(None, min_length=2, max_length=2,
                                            description="two DOFs [i, j]: u = q_i - q_j")

    @model_validator(mode="after")
    def _where(self):
        if (self.dofs is None) == (self.between is None):
            raise ValueError("give exactly one of dofs = [i] (contact to the ground) or "
                             "between = [i, j] (u = q_i - q_j); DOF numbers start at 1")
        if self.between is not None and self.between[0] == self.between[1]:
            raise ValueError(f"between must name two different DOFs, got {self.between}")
        if self.dofs is not None and len(set(self.dofs)) != len(self.dofs):
            raise ValueError(f"dofs lists a DOF twice: {self.dofs}")
        return self


class JenkinsContact(Attachment):
    """``[[contacts]] type = "jenkins"``: spring in series with a Coulomb slider."""

    stiffness_N_per_m: Positive = Field(description="tangential contact stiffness k_t")
    slip_force_N: NonNegative | None = Field(None, description="slip limit F_s")
    mu: NonNegative | None = Field(None, description="friction coefficient (with normal_load_N)")
    normal_load_N: NonNegative | None = Field(None, description="normal load N: F_s = mu N")

    @model_validator(mode="after")
    def _slip(self):
        by_mu = self.mu is not None or self.normal_load_N is not None
        if self.slip_force_N is not None and by_mu:
            raise ValueError("give either slip_force_N or mu with normal_load_N, not both")
        if self.slip_force_N is None and (self.mu is None or self.normal_load_N is None):
            raise ValueError("give slip_force_N, or both mu and normal_load_N "
                             "(slip force = mu * normal_load_N)")
        return self

    @property
    def slip_force(self) -> float:
        """Slip limit [N]."""
        if self.slip_force_N is not None:
            return self.slip_force_N
        return self.mu * self.normal_load_N


class CoulombContact(Attachment):
    """``[[contacts]] type = "coulomb"``: penalty spring and a slider with static/kinetic
    friction and the velocity-dependent coefficient of paper 003 eq. (2)."""

    stiffness_N_per_m: Positive = Field(description="tangential penalty (stick) stiffness k_t")
    normal_load_N: NonNegative = Field(description="normal load N")
    mu_static: NonNegative = Field(description="static friction coefficient mu_s")
    mu_sliding: NonNegative | None = Field(
        None, description="sliding coefficient mu_d <= mu_s (default mu_s)")
    decay_s_per_m: NonNegative = Field(
        0.0, description="decay coefficient DC of mu(v) = mu_d + (mu_s - mu_d) exp(-DC |v|); "
                         "0: constant mu_d while sliding")

    @model_validator(mode="after")
    def _mu(self):
        if self.mu_sliding is not None and self.mu_sliding > self.mu_static:
            raise ValueError(f"mu_sliding ({self.mu_sliding:g}) must be <= mu_static "
                             f"({self.mu_static:g})")
        return self


class CubicSpringContact(Attachment):
    """``[[contacts]] type = "cubic_spring"``: cubic spring f = k3 u^3 (the Duffing
    nonlinearity), conservative and memoryless."""

    k3_N_per_m3: float = Field(description="cubic stiffness k3 (> 0 hardening, < 0 softening)")


class IwanContact(Attachment):
    """``[[contacts]] type = "iwan"``: four-parameter Iwan joint (Segalman 2005), a
    continuum of Jenkins elements with a power-law slip density and a Dirac at its cut
    (:class:`fricdamp.contact.iwan.Iwan`)."""

    stiffness_N_per_m: Positive = Field(description="stiffness K_T of the stuck joint")
    slip_force_N: Positive = Field(description="force of macro-slip F_S")
    chi: float = Field(gt=-1.0, le=1.0, description="exponent of the slip density: the "
                                                    "micro-slip energy grows as A^(3 + chi) "
                                                    "(Segalman: -1 < chi <= 0)")
    beta: NonNegative = Field(description="weight of the Dirac at phi_max relative to the "
                                          "power-law part's stiffness")
    n_elements: int = Field(100, ge=2, le=10_000, description="Jenkins elements of the "
                                                              "power-law part (+1 for the Dirac)")
    min_ratio: float = Field(1e-4, gt=0.0, lt=1.0, description="smallest slip displacement "
                                                               "of the discretisation / phi_max")


DirectionDofs = Annotated[list[DofNumber], Field(min_length=1, max_length=2)]


class Contact3DContact(Section):
    """``[[contacts]] type = "contact3d"``: unilateral normal penalty with preload or gap and
    isotropic 2D friction (one contact; local directions built from DOFs)."""

    name: str | None = Field(None, pattern=NAME_PATTERN, max_length=64,
                             description="label in results and plots")
    normal: DirectionDofs = Field(
        description="normal approach: [i] (u_n = q_i) or [i, j] (u_n = q_i - q_j)")
    tangential: list[DirectionDofs] = Field(
        min_length=1, max_length=2, description="one or two tangential directions, each [i] "
                                                "or [i, j]")
    normal_stiffness_N_per_m: Positive = Field(description="normal penalty stiffness k_n")
    tangential_stiffness_N_per_m: Positive = Field(description="tangential stiffness k_t")
    mu: NonNegative = Field(description="friction coefficient")
    offset_m: float | None = Field(None, description="normal offset g0: > 0 interference, "
                                                     "< 0 gap (default 0)")
    preload_N: NonNegative | None = Field(None, description="normal force at u_n = 0 "
                                                            "(offset = preload / k_n)")

    @model_validator(mode="after")
    def _offset(self):
        if self.offset_m is not None and self.preload_N is not None:
            raise ValueError("give either offset_m or preload_N, not both")
        for key, dofs in [("normal", self.normal)] + [("tangential", d) for d in
                                                      self.tangential]:
            if len(dofs) == 2 and dofs[0] == dofs[1]:
                raise ValueError(f"{key} = {dofs} must name two different DOFs")
        return self


# ----------------------------------------------------------------------------- analyses
def _check_steps(n_steps: float, what: str) -> None:
    if n_steps > MAX_STEPS:
        raise ValueError(f"{what} asks for {n_steps:.3g} time steps; at most {MAX_STEPS:.0e} "
                         "are allowed (increase the time step or shorten the run)")


class FreeDecay(Section):
    """``[analysis.free_decay]``: release from initial conditions, identify damping vs amplitude."""

    initial_displacement_m: list[float] | None = Field(
        None, min_length=1, description="q(0), one entry per DOF (default 0)")
    initial_velocity_m_per_s: list[float] | None = Field(
        None, min_length=1, description="q'(0), one entry per DOF (default 0)")
    duration_s: Positive = Field(description="length of the simulation")
    time_step_s: Positive = Field(description="time step")
    response_dof: DofNumber | None = Field(
        None, description="DOF whose decay is analysed (default: the largest initial "
                          "displacement, or velocity)")
    save_every: int = Field(1, ge=1, description="keep every n-th step in the results")

    @model_validator(mode="after")
    def _steps(self):
        if self.time_step_s >= self.duration_s:
            raise ValueError(f"time_step_s ({self.time_step_s:g} s) must be smaller than "
                             f"duration_s ({self.duration_s:g} s)")
        _check_steps(self.duration_s / self.time_step_s, "duration_s / time_step_s")
        moved = [x for x in (self.initial_displacement_m or []) + (
            self.initial_velocity_m_per_s or []) if x != 0]
        if not moved:
            raise ValueError("initial_displacement_m or initial_velocity_m_per_s must have a "
                             "non-zero entry (the structure starts at rest: nothing to decay)")
        return self


class ForcedResponse(Section):
    """``[analysis.forced_response]``: harmonic force, time stepping to a steady state."""

    force_amplitude_N: list[float] = Field(
        min_length=1, description="amplitude F of F cos(2 pi f t), one entry per DOF")
    frequency_hz: Positive = Field(description="excitation frequency f")
    periods: int = Field(50, ge=2, description="number of excitation periods simulated")
    steps_per_period: int = Field(200, ge=16, description="time steps per period")

    @model_validator(mode="after")
    def _force(self):
        if not any(self.force_amplitude_N):
            raise ValueError("force_amplitude_N must have a non-zero entry")
        _check_steps(self.periods * self.steps_per_period, "periods * steps_per_period")
        return self


class Hysteresis(Section):
    """``[analysis.hysteresis]``: drive each contact law with u = A sin(2 pi f t)."""

    amplitudes_m: list[Positive] = Field(min_length=1,
                                         description="relative displacement amplitudes A")
    cycles: int = Field(2, ge=2, le=1000, description="cycles driven; the last one is the loop")
    samples_per_cycle: int = Field(400, ge=16, le=1_000_000, description="samples per cycle")
    frequency_hz: Positive = Field(1.0, description="drive frequency (matters only for "
                                                    "velocity-dependent laws)")
    contacts: list[str] | None = Field(None, min_length=1,
                                       description="names of the contacts to drive (default all)")


class SolverSettings(Section):
    """``[solver]``: settings of the time integration used by the time-domain analyses."""

    method: Literal["newmark", "hht"] = Field(
        "newmark", description="newmark (average acceleration, no numerical damping) or hht "
                               "(HHT-alpha, damps unresolved high modes)")
    alpha: float = Field(-0.05, ge=-1 / 3, le=0, description="HHT-alpha parameter")
    tol: Positive = Field(1e-10, lt=1e-2, description="Newton tolerance (relative)")
    max_iter: int = Field(30, ge=1, le=1000, description="Newton iterations per step")


class _CaseFile(Section):
    name: str | None = Field(None, pattern=NAME_PATTERN, max_length=100)
    description: str = ""
    model: dict[str, Any]
    contacts: list[dict[str, Any]] = Field(default_factory=list)
    analysis: dict[str, dict[str, Any]] = Field(min_length=1)
    solver: SolverSettings = Field(default_factory=SolverSettings)


# ------------------------------------------------------------------------- the case
@dataclass(frozen=True)
class Case:
    """A validated case file.

    Attributes
    ----------
    name : str
        Case name (the ``name`` key, or the file name without ``.toml``).
    description : str
        Free text.
    model_type : str
        ``[model] type``.
    model : Section
        The validated ``[model]`` table (without ``type``).
    contacts : tuple of (str, Section)
        Contact type and validated table, in file order.
    analyses : dict of str -> Section
        Validated ``[analysis.<name>]`` tables, in file order.
    solver : SolverSettings
        ``[solver]`` settings (defaults if absent).
    source : Path or None
        The case file.
    text : str
        The TOML text as read (shown in the report).
    tables : dict
        Other top-level tables registered for other commands (``[sweep]``, ``[optimize]``),
        validated by their schema when one is registered, ignored by ``fricdamp run``.
    """

    name: str
    description: str
    model_type: str
    model: Section
    contacts: tuple[tuple[str, Section], ...]
    analyses: dict[str, Section]
    solver: SolverSettings
    source: Path | None = None
    text: str = ""
    tables: dict = field(default_factory=dict, compare=False)

    @property
    def base_dir(self) -> Path:
        """Folder that relative paths in the case are resolved against."""
        return self.source.parent if self.source is not None else Path.cwd()

    def to_dict(self) -> dict:
        """The validated case as plain data (every default filled in) for summary.json."""
        return {
            "name": self.name,
            "description": self.description,
            "file": str(self.source) if self.source is not None else None,
            "model": {"type": self.model_type, **self.model.model_dump()},
            "contacts": [{"type": t, **c.model_dump()} for t, c in self.contacts],
            "analysis": {k: v.model_dump() for k, v in self.analyses.items()},
            "solver": self.solver.model_dump(),
        }


def read_case_file(path: str | Path) -> tuple[dict, str]:
    """Read a TOML case file; return (data, text). Raise CaseError if unreadable or not TOML.

    Only regular files of at most 16 MiB are read (a device such as ``/dev/zero`` or a pipe
    is refused at once instead of being read for ever)."""
    from fricdamp.iofiles import read_regular_file

    path = Path(path)
    raw = read_regular_file(path, what="case file")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise CaseError(f"cannot read case file {str(path)!r}: it is not UTF-8 text "
                        f"(byte {exc.start})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{path.name} is not valid TOML: {exc}") from None
    return data, text


def parse_case(data: Mapping, registry, *, text: str = "", source: str | Path | None = None,
               default_name: str = "case") -> Case:
    """Validate a case (the dict read from TOML) against the registered schemas.

    Parameters
    ----------
    data : mapping
        The parsed TOML document.
    registry : fricdamp.runner.Registry
        Schemas of the model types, contact types and analyses.
    text : str
        The TOML text (kept for the report).
    source : path, optional
        The case file (relative paths in the case are resolved against its folder).
    default_name : str
        Case name when the file has no ``name`` key.

    Raises
    ------
    CaseError
        With one message naming the table, the key, what is allowed and what was given.
    """
    if not isinstance(data, Mapping):
        raise CaseError(f"a case must be a TOML table, got {data!r}")
    data = dict(data)
    tables = {}
    for name, schema in getattr(registry, "tables", {}).items():
        if name in data:
            table = data.pop(name)
            tables[name] = table if schema is None else validate_section(schema, table,
                                                                         f"[{name}]")
    root = validate_section(_CaseFile, data, "")
    model_table = dict(root.model)
    mtype = _pop_type(model_table, "[model]", registry.models)
    model = validate_section(registry.models[mtype].schema, model_table, "[model]")

    contacts = []
    for i, table in enumerate(root.contacts, start=1):
        where = f"[[contacts]] #{i}"
        table = dict(table)
        ctype = _pop_type(table, where, registry.contacts)
        contacts.append((ctype, validate_section(registry.contacts[ctype].schema, table,
                                                 f"{where} ({ctype})")))

    analyses = {}
    for name, table in root.analysis.items():
        if name not in registry.analyses:
            raise CaseError(f"unknown analysis [analysis.{name}]; available: "
                            f"{_listing(registry.analyses)}"
                            f"{_did_you_mean(name, registry.analyses)}")
        analyses[name] = validate_section(registry.analyses[name].schema, table,
                                          f"[analysis.{name}]")

    src = Path(source) if source is not None else None
    return Case(name=root.name or default_name, description=root.description, model_type=mtype,
                model=model, contacts=tuple(contacts), analyses=analyses, solver=root.solver,
                source=src, text=text, tables=tables)


def _pop_type(table: dict, where: str, known: Mapping) -> str:
    if "type" not in table:
        raise CaseError(f"{where} needs a 'type' key: one of {_listing(known)}")
    t = table.pop("type")
    if not isinstance(t, str) or t not in known:
        raise CaseError(f"{where} type = {t!r} is not known; allowed: {_listing(known)}"
                        f"{_did_you_mean(str(t), known)}")
    return t


def _listing(names) -> str:
    return ", ".join(repr(n) for n in names)


def _did_you_mean(word: str, choices) -> str:
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


# --------------------------------------------------------------------- error messages
_UNITS = (  # longest suffix first
    ("_m_per_s", "m/s"), ("_s_per_m", "s/m"), ("_Ns_per_m", "N s/m"), ("_N_per_m", "N/m"),
    ("_per_s", "1/s"),
    ("_kg", "kg"), ("_hz", "Hz"), ("_deg", "deg"), ("_N", "N"), ("_J", "J"), ("_m", "m"),
    ("_s", "s"),
)


def unit_of(key: str) -> str:
    """Unit implied by a key name (``masses_kg`` -> ``"kg"``), ``""`` if none."""
    for suffix, unit in _UNITS:
        if key.endswith(suffix):
            return unit
    return ""


def validate_section(schema: type[BaseModel], table: Mapping, where: str) -> BaseModel:
    """Validate one table against ``schema``; turn the first problem into a CaseError.

    ``where`` names the table in messages (``"[model]"``, ``"[[contacts]] #2 (jenkins)"``,
    ``""`` for the top level).
    """
    if not isinstance(table, Mapping):
        raise CaseError(f"{where or 'the case'} must be a table, got {table!r}")
    try:
        return schema.model_validate(dict(table))
    except ValidationError as exc:
        # a typo'd key also makes the intended key "missing": report the typo first
        errors = sorted(exc.errors(include_url=False),
                        key=lambda e: e.get("type") != "extra_forbidden")
        msg = _describe(errors[0], schema, where)
        others = [e for e in errors[1:] if not (
            errors[0].get("type") == "extra_forbidden" and e.get("type") == "missing")]
        if others:
            msg += f" (and {len(others)} more problem{'s' if len(others) > 1 else ''})"
        raise CaseError(msg) from None


def _key_path(loc: tuple, where: str) -> tuple[str, str]:
    """(key as the user wrote it, last string key) from a pydantic location."""
    parts, last = [], ""
    for i, item in enumerate(loc):
        if isinstance(item, int):
            parts.append(f" entry {item + 1}")
        else:
            parts.append(("." if i else "") + str(item))
            last = str(item)
    key = "".join(parts).strip()
    prefix = f"{where} " if where else ""
    return prefix + key, last


def _fmt(value) -> str:
    if isinstance(value, float) and math.isfinite(value):
        return f"{value:g}"
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, Mapping):
        return "a table"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _type_name(value) -> str:
    names = {bool: "a boolean", str: "a string", int: "an integer", float: "a number",
             list: "a list", dict: "a table"}
    return names.get(type(value), type(value).__name__)


def _constraints(schema: type[BaseModel], name: str) -> str:
    """Allowed values of a field from its bounds and its unit: ``"> 0 kg"``, ``"in s"``."""
    info = schema.model_fields.get(name)
    if info is None:
        return ""
    bounds = []
    for meta in _all_metadata(info):
        for attr, op in (("gt", ">"), ("ge", ">="), ("lt", "<"), ("le", "<=")):
            v = getattr(meta, attr, None)
            if isinstance(v, (int, float)):
                bounds.append(f"{op} {v:g}")
    unit = unit_of(name)
    if bounds:
        return " and ".join(dict.fromkeys(bounds)) + (f" {unit}" if unit else "")
    return f"in {unit}" if unit else ""


def _all_metadata(info):
    """Constraint objects of a field, including those of list items (``list[Positive]``)."""
    stack = list(info.metadata) + [info.annotation]
    while stack:
        item = stack.pop()
        if hasattr(item, "__metadata__"):  # Annotated[...]
            stack.extend(item.__metadata__)
        if hasattr(item, "metadata") and isinstance(item.metadata, list):  # FieldInfo
            stack.extend(item.metadata)
        args = getattr(item, "__args__", None)
        if args:
            stack.extend(a for a in args if a is not type(None))
        yield item


def _describe(err: dict, schema: type[BaseModel], where: str) -> str:
    loc = tuple(err.get("loc", ()))
    if not where and len(loc) > 1 and isinstance(loc[0], str) and isinstance(loc[1], str):
        # a sub-table validated with the top level ([solver]): name it like a table
        sub = schema.model_fields.get(loc[0])
        sub_schema = getattr(sub, "annotation", None) if sub is not None else None
        where, loc = f"[{loc[0]}]", loc[1:]
        if isinstance(sub_schema, type) and issubclass(sub_schema, BaseModel):
            schema = sub_schema
        err = {**err, "loc": loc}
    typ = err.get("type", "")
    ctx = err.get("ctx") or {}
    value = err.get("input")
    key, last = _key_path(loc, where)
    unit = unit_of(last)
    u = f" {unit}" if unit else ""
    table = where or "the top level of the case"

    if typ == "extra_forbidden":
        allowed = list(schema.model_fields)
        return (f"unknown key {last!r} in {table}{_did_you_mean(last, allowed)}; allowed keys: "
                f"{', '.join(allowed)}")
    if typ == "missing":
        if not where and last in ("model", "analysis"):
            return (f"the case has no [{last}] table; it is required (see the \"Case files\" "
                    f"page of the fricdamp documentation, or `fricdamp demo` for an annotated "
                    f"case)")
        allowed = _constraints(schema, last)
        return f"{table} is missing the required key {last!r}" + (
            f" ({allowed})" if allowed else "")
    if typ in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        op, bound = {"greater_than": (">", "gt"), "greater_than_equal": (">=", "ge"),
                     "less_than": ("<", "lt"), "less_than_equal": ("<=", "le")}[typ]
        return f"{key} must be {op} {_fmt(ctx.get(bound, '?'))}{u}, got {_fmt(value)}"
    if typ == "finite_number":
        return f"{key} must be a finite number (nan and inf are not allowed), got {_fmt(value)}"
    if typ in ("float_type", "float_parsing", "int_type", "int_parsing", "int_from_float",
               "bool_type", "string_type"):
        want = {"float_type": "a number", "float_parsing": "a number",
                "int_type": "an integer", "int_parsing": "an integer",
                "int_from_float": "an integer", "bool_type": "true or false",
                "string_type": "a string"}[typ]
        rng = _constraints(schema, last)
        rng = f" ({rng})" if rng else ""
        return f"{key} must be {want}{rng}, got {_fmt(value)} ({_type_name(value)})"
    if typ in ("list_type", "tuple_type"):
        return f"{key} must be a list like [1.0, 2.0], got {_fmt(value)} ({_type_name(value)})"
    if typ in ("dict_type", "model_type"):
        return f"{key} must be a table, got {_fmt(value)} ({_type_name(value)})"
    if typ == "literal_error":
        return f"{key} must be one of {ctx.get('expected', '?')}, got {_fmt(value)}"
    if typ == "too_short":
        return (f"{key} must have at least {ctx.get('min_length')} entr"
                f"{'y' if ctx.get('min_length') == 1 else 'ies'}, got {ctx.get('actual_length')}")
    if typ == "too_long":
        return (f"{key} must have at most {ctx.get('max_length')} entries, "
                f"got {ctx.get('actual_length')}")
    if typ == "string_pattern_mismatch":
        return (f"{key} must contain only letters, digits, '_', '.', '-' (and start with a "
                f"letter or digit), got {_fmt(value)}")
    if typ == "value_error":
        msg = str(err.get("msg", "")).removeprefix("Value error, ")
        return f"{table}: {msg}" if not loc else f"{key}: {msg}"
    return f"{key}: {err.get('msg', 'invalid value')}, got {_fmt(value)}"
