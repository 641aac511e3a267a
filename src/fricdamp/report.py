"""HTML report of a run: the case, the key numbers and the figures.

The page is self-contained (inline CSS, no scripts, no web fonts); figures are ``<img>``
elements pointing at the PNG files written next to it, so the folder can be zipped, mailed
or served as is. Numbers come from the run's summary (the same dict as ``summary.json``):
scalars go into a key-number table, lists of equal length (damping ratio vs amplitude, ...)
into a column table, per-contact dicts into a table with one row per contact.

Presentation rules: engineering results come first in every table, solver diagnostics
(energy balance, iterations, counters, run times) after them; damping ratios are shown in %
(as in the figures); in a list or a column, values below ``1e-12`` of the largest are
round-off and shown as 0 (a closed-form zero computed as 1.7e-21).
"""

from __future__ import annotations

import html
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

from fricdamp.case import unit_of

__all__ = ["render_report", "write_report"]

_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 2rem auto;
       max-width: 68rem; padding: 0 1rem; color: #1d2327; line-height: 1.45; }
h1 { font-size: 1.6rem; margin-bottom: 0.2rem; }
h2 { font-size: 1.25rem; border-bottom: 1px solid #ccd; padding-bottom: 0.2rem; margin-top: 2rem; }
h3 { font-size: 1.05rem; margin-bottom: 0.3rem; }
.meta { color: #566; font-size: 0.9rem; }
table { border-collapse: collapse; margin: 0.5rem 0 1rem; font-size: 0.92rem; }
th, td { border: 1px solid #d5d9de; padding: 0.25rem 0.6rem; text-align: left;
         vertical-align: top; }
th { background: #f2f4f7; font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
figure { margin: 1rem 0 1.5rem; }
figure img { max-width: 100%; border: 1px solid #e3e6ea; }
figcaption { font-size: 0.9rem; color: #445; margin-top: 0.3rem; }
pre { background: #f6f8fa; border: 1px solid #e3e6ea; padding: 0.8rem; overflow-x: auto;
      font-size: 0.85rem; }
.note { background: #fff7e0; border-left: 4px solid #e0a800; padding: 0.4rem 0.8rem; }
.small { font-size: 0.85rem; color: #566; }
.verdict { font-size: 1.1rem; padding: 0.5rem 0.9rem; border-left: 6px solid; margin: 0.8rem 0; }
.verdict-ok { background: #e9f7ee; border-color: #2e8b57; }
.verdict-unreliable { background: #fff4e0; border-color: #e08a00; }
.verdict-failed { background: #fde8e8; border-color: #c62828; }
"""

#: What each overall verdict means, and the exit code of ``fricdamp run``.
_VERDICT_TEXT = {
    "ok": "ok: every error estimate is within its limit (exit code 0)",
    "unreliable": "unreliable: computed, but an error estimate exceeds its limit; do not use "
                  "the numbers below without reading the reasons (exit code 3)",
    "failed": "failed: a solver did not finish what was asked; the numbers below are what "
              "was computed before it stopped (exit code 1)",
}


def _verdict_html(verdict: Mapping) -> str:
    """The verdict block at the top of the report: overall, then one row per analysis."""
    overall = str(verdict.get("overall", "ok"))
    out = [f'<p class="verdict verdict-{_esc(overall)}"><strong>Verdict: '
           f"{_esc(_VERDICT_TEXT.get(overall, overall))}</strong></p>"]
    rows = []
    for name, v in verdict.get("analyses", {}).items():
        reasons = "; ".join(v.get("reasons", [])) or "—"
        est = ", ".join(f"{label(k)} {_num(x)}" for k, x in v.get("estimates", {}).items()
                        if _is_num(x) and x is not None)
        rows.append(f"<tr><td>{_esc(name)}</td><td>{_esc(v.get('verdict'))}</td>"
                    f"<td>{_esc(reasons)}</td><td class=\"small\">{_esc(est)}</td></tr>")
    if rows:
        out.append("<table><tr><th>analysis</th><th>verdict</th><th>reasons</th>"
                   "<th>error estimates</th></tr>" + "".join(rows) + "</table>")
    return "\n".join(out)


_MAX_ROWS = 15
_INLINE = 8


def _esc(x) -> str:
    return html.escape(str(x), quote=True)


#: Keys holding a damping ratio (a fraction in summary.json, shown in % like the figures).
_PERCENT = re.compile(r"(^|_)(damping_ratios?|zeta)(_|$)")

#: Keys of solver diagnostics, listed after the engineering results.
_DIAGNOSTIC = re.compile(
    r"(energy_balance|error|residual|iteration|newton|^n_(?!dof|mode|contact|sector|node)|_count$|runtime|wall_time|cpu_s|"
    r"setup_s|^status|message|method|^harmonics$|^samples$|steps|evaluations|"
    r"factori[sz]ations|restarts|converged|verdict|tolerance|^tol$)")

#: Relative size below which an entry of a list is round-off of a zero.
_ROUNDOFF = 1e-12


def _is_percent(key: str) -> bool:
    return bool(_PERCENT.search(key))


def _is_diagnostic(key: str) -> bool:
    return bool(_DIAGNOSTIC.search(key))


def _engineering_first(keys: Sequence[str]) -> list[str]:
    """Engineering results first, solver diagnostics after (order kept within each)."""
    return ([k for k in keys if not _is_diagnostic(k)]
            + [k for k in keys if _is_diagnostic(k)])


def _scaled(key: str, v):
    """A damping ratio in %; other values unchanged (lists element-wise)."""
    if not _is_percent(key) or not _numeric(v):
        return v
    if isinstance(v, (list, tuple)):
        return [100.0 * x if _is_num(x) and x is not None else x for x in v]
    if _is_num(v) and v is not None:
        return 100.0 * v
    return v


def _clean(values: Sequence) -> list:
    """Entries below _ROUNDOFF of the largest |entry| set to 0 (round-off of a zero)."""
    finite = [abs(x) for x in values if _is_num(x) and x is not None
              and math.isfinite(float(x))]
    big = max(finite, default=0.0)
    if big == 0:
        return list(values)
    return [0 if (_is_num(x) and x is not None and isinstance(x, float)
                  and abs(x) < _ROUNDOFF * big) else x for x in values]


def _numeric(v) -> bool:
    return _is_num(v) or _is_numlist(v)


def label(key: str, value=0.0) -> str:
    """``"amplitude_m"`` -> ``"amplitude [m]"``; ``"energy_balance_error"`` -> words;
    a damping ratio (a number or list of numbers) -> ``"damping ratio [%]"``."""
    if _is_percent(key) and _numeric(value):
        return f"{key.replace('_', ' ')} [%]"
    unit = unit_of(key)
    base = key
    if unit:
        for suffix in ("_m_per_s", "_Ns_per_m", "_N_per_m", "_s_per_m", "_per_s", "_kg", "_hz",
                       "_deg", "_N", "_J", "_m", "_s"):
            if key.endswith(suffix):
                base = key[: -len(suffix)]
                break
    text = base.replace("_", " ")
    return f"{text} [{unit}]" if unit else text


def _num(x) -> str:
    if x is None:
        return "n/a"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            return "n/a"
        return f"{x:.4g}"
    return str(x)


def _is_num(x) -> bool:
    return x is None or (isinstance(x, (int, float)) and not isinstance(x, bool))


def _is_numlist(v) -> bool:
    return isinstance(v, (list, tuple)) and all(_is_num(x) for x in v)


def _inline_list(v: Sequence) -> str:
    items = [_num(x) if _is_num(x) else str(x) for x in _clean(v)]
    if len(items) > _INLINE:
        items = items[:4] + ["…"] + items[-2:]
        return "[" + ", ".join(items) + f"] ({len(v)} values)"
    return "[" + ", ".join(items) + "]"


def _cell(v) -> str:
    if isinstance(v, (list, tuple)):
        return _esc(_inline_list(v))
    if isinstance(v, Mapping):
        return _esc(", ".join(f"{k}: {_num(x)}" for k, x in v.items()))
    return _esc(_num(v))


def _rows(first_column: Sequence) -> list[int]:
    """At most _MAX_ROWS row indices spread evenly over the range of the first column.

    A free decay spends most of its peaks at small amplitude; picking rows evenly in the
    first column's value (amplitude) rather than in the index shows the whole curve.
    """
    n = len(first_column)
    if n <= _MAX_ROWS:
        return list(range(n))
    x = [math.nan if v is None else float(v) for v in first_column]
    finite = [v for v in x if math.isfinite(v)]
    if not finite or max(finite) == min(finite):
        step = (n - 1) / (_MAX_ROWS - 1)
        return sorted({round(i * step) for i in range(_MAX_ROWS)})
    lo, hi = min(finite), max(finite)
    picks = set()
    for i in range(_MAX_ROWS):
        target = lo + (hi - lo) * i / (_MAX_ROWS - 1)
        picks.add(min((j for j in range(n) if math.isfinite(x[j])),
                      key=lambda j: abs(x[j] - target)))
    return sorted(picks)


def _dict_table(key: str, items: Mapping[str, Mapping]) -> str:
    """One row per item (contact), one column per key of the items."""
    cols = list(dict.fromkeys(c for x in items.values() for c in x))
    cols = _engineering_first(cols)
    out = [f"<h3>{_esc(label(key, items))}</h3><table><tr><th>name</th>"
           + "".join(f"<th>{_esc(label(c))}</th>" for c in cols) + "</tr>"]
    for name, x in items.items():
        out.append(f"<tr><td>{_esc(name)}</td>" + "".join(
            f'<td class="num">{_cell(_scaled(c, x.get(c)))}</td>' for c in cols) + "</tr>")
    out.append("</table>")
    return "".join(out)


def _section_tables(section: Mapping) -> str:
    """Tables of one summary section: scalars, column groups, per-item dicts."""
    scalars, groups, dicts = [], {}, []
    for key, v in section.items():
        if _is_numlist(v) and len(v) >= 3:
            groups.setdefault(len(v), []).append(key)
        elif isinstance(v, Mapping):
            dicts.append(key)
        else:
            scalars.append(key)
    # a list alone in its length group is shown inline
    for n, keys in list(groups.items()):
        if len(keys) == 1:
            scalars.append(keys[0])
            del groups[n]
    out = []
    scalars = _engineering_first(scalars)
    if scalars:
        out.append("<table><tr><th>quantity</th><th>value</th></tr>")
        for key in scalars:
            v = _scaled(key, section[key])
            cls = ' class="num"' if _is_num(v) else ""
            out.append(f"<tr><td>{_esc(label(key, section[key]))}</td><td{cls}>{_cell(v)}"
                       "</td></tr>")
        out.append("</table>")
    for n, keys in groups.items():
        rows = _rows(section[keys[0]])
        keys = [keys[0], *_engineering_first(keys[1:])]
        cols = {k: _clean(_scaled(k, section[k])) for k in keys}
        out.append("<table><tr>" + "".join(f"<th>{_esc(label(k))}</th>" for k in keys)
                   + "</tr>")
        for i in rows:
            out.append("<tr>" + "".join(f'<td class="num">{_esc(_num(cols[k][i]))}</td>'
                                        for k in keys) + "</tr>")
        out.append("</table>")
        if len(rows) < n:
            out.append(f'<p class="small">{len(rows)} of {n} rows shown; all are in '
                       "summary.json and the results file.</p>")
    for key in _engineering_first(dicts):
        v = section[key]
        if all(isinstance(x, Mapping) for x in v.values()):
            out.append(_dict_table(key, v))
        else:
            out.append(f"<h3>{_esc(label(key, v))}</h3>" + _section_tables(v))
    return "\n".join(out)


def render_report(*, summary: Mapping, case_text: str,
                  figures: Mapping[str, Sequence[tuple[str, str]]]) -> str:
    """HTML text of the report.

    Parameters
    ----------
    summary : mapping
        The run summary (as written to summary.json): ``fricdamp_version``, ``case``,
        ``runtime_s``, ``model``, ``verdict`` (shown first), one section per analysis,
        optional ``notes`` and ``files``.
    case_text : str
        The case file's TOML text, shown verbatim.
    figures : mapping analysis name -> list of (PNG file name, caption)
        Figures written next to the report.
    """
    case = summary.get("case", {})
    name = case.get("name", "case")
    analyses = [k for k in figures] + [k for k in case.get("analysis", {}) if k not in figures]
    files = summary.get("files", {})
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>fricdamp report: {_esc(name)}</title>",
        f"<style>{_CSS}</style></head><body>",
        f"<h1>fricdamp report: {_esc(name)}</h1>",
    ]
    if isinstance(summary.get("verdict"), Mapping):   # the verdict comes first
        parts.append(_verdict_html(summary["verdict"]))
    if case.get("description"):
        parts.append(f"<p>{_esc(case['description'])}</p>")
    meta = [f"fricdamp {_esc(summary.get('fricdamp_version', '?'))}"]
    if summary.get("created"):
        meta.append(f"run {_esc(summary['created'])}")
    if summary.get("runtime_s") is not None:
        meta.append(f"run time {_num(summary['runtime_s'])} s")
    if case.get("file"):
        meta.append(f"case file {_esc(case['file'])}")
    parts.append(f'<p class="meta">{" · ".join(meta)}</p>')
    for note in summary.get("notes", []):
        parts.append(f'<p class="note">{_esc(note)}</p>')

    parts.append("<h2>Key numbers</h2>")
    model = dict(summary.get("model", {}))
    contacts = model.pop("contacts", [])
    overview = {**model, "energy_balance_error": summary.get("energy_balance_error")}
    parts.append(_section_tables(overview))
    if contacts:
        parts.append(_dict_table("contacts", {c["name"]: {k: v for k, v in c.items()
                                                          if k != "name"} for c in contacts}))

    for a in analyses:
        section = summary.get(a)
        parts.append(f'<h2 id="{_esc(a)}">{_esc(a.replace("_", " ").capitalize())}</h2>')
        if isinstance(section, Mapping):
            parts.append(_section_tables(section))
        for filename, caption in figures.get(a, []):
            parts.append(f'<figure><img src="{_esc(filename)}" alt="{_esc(caption)}">'
                         f"<figcaption>{_esc(caption)} ({_esc(filename)})</figcaption></figure>")

    parts.append("<h2>Case file</h2>")
    parts.append(f"<pre>{_esc(case_text)}</pre>")
    if files:
        links = [files.get("summary"), files.get("results")]
        parts.append("<h2>Files</h2><ul>" + "".join(
            f'<li><a href="{_esc(f)}">{_esc(f)}</a></li>' for f in links if f) + "</ul>")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def write_report(path: str | Path, *, summary: Mapping, case_text: str,
                 figures: Mapping[str, Sequence[tuple[str, str]]]) -> Path:
    """Render the report and write it atomically to ``path``; return the path."""
    from fricdamp.iofiles import to_jsonable, write_text

    text = render_report(summary=to_jsonable(summary), case_text=case_text, figures=figures)
    return write_text(path, text)
