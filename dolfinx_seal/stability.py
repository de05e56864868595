"""Stability study: a scene's stiff and extreme cases, run from a table.

``dolfinx-seal study stability SCENE`` (``make stability`` for every table) reads
``studies/stability/SCENE.toml`` (or ``--table FILE``), runs each case (a sweep
of one parameter, or one point) and records, for every point of every case,
whether it converged, failed, stopped or was not attempted, with the Newton
steps, the load, mass and complementarity residuals of a converged point and
the error of a failed one (the load residual of a lip installation, which has no
load control, is its radial balance ``|radial_balance_error|``).  Nothing is skipped silently: a case that raises
keeps its finished points, and a converged point with a value that is not a
finite number is reported as ``nan`` (a defect, not a result).

The table (TOML)::

    scene = "cylinder"               # the scene of every case
    over = "film.speed"              # the default swept parameter ("" : one point)
    values = [1e-7, 1e-4, 1e-1]      # its default values
    time_budget = 900                # [s] per case, passed to stepping.time_budget
    [parameters]                     # overrides common to every case
    h_contact = 20e-6
    [[case]]
    name = "E 1 GPa"                 # unique; also the case's folder name (slugged)
    about = "a stiff elastomer: thin film, sharp pressure peak"
    set = { "material.E" = 1e9 }     # dotted keys, or nested tables
    # over, values, time_budget: this case's own (optional)

Every case's parameters and values are checked before the first point runs, so a
bad table stops at once with the dotted parameter, the case and the file.

Point statuses:

``converged``
    the point's solve converged;
``failed``
    the scene tried the point and gave up (its continuation target not reached,
    or its own solve failed), with the reason;
``stopped``
    the case raised (typically its start failed) before the point was reached;
    the reason is the case's error;
``not attempted``
    skipped by design: after ``stepping.max_failures`` consecutive failures, or
    once the case's time budget was spent;
``suspect``
    converged, but to a state outside the model: a film thinner than a continuum
    film (``h_min`` below :data:`~dolfinx_seal.film.surface.CONTINUUM_FILM`, 2 nm,
    or negative), or a film of neither film scheme (``discrete_upwinding_weight``
    strictly between 0 and 1: the release of the discrete upwinding stopped
    short), or a starved film that pulls on the body (``suction_load_fraction``
    above :data:`SUCTION_LIMIT`), with the reasons;
``refused``
    the input checks refused the case before anything was assembled (a case
    marked ``expect = "refused"``: physics says there is no solution);
``nan``
    converged, but a reported value is not finite.

Writes into ``out``: ``stability.csv`` (one row per case and point, appended as
each case ends), ``stability.md`` (a table per case and a summary),
``stability.png`` (the case x value map: status colours, Newton steps written
in each cell), ``results.json`` (the counts) and the cases' own folders
(``cases/<slug>/``: their ``sweep.csv``, ``results.json``, profiles).
"""

from __future__ import annotations

import json
import math
import re
import time
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from dolfinx_seal import params as _params
from dolfinx_seal import scenes
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.film.surface import CONTINUUM_FILM
from dolfinx_seal.mpi import get_logger, world
from dolfinx_seal.output import Progress, SweepWriter, write_results, write_text_atomic
from dolfinx_seal.params import flatten

#: Where the tables of the scenes live (``studies/stability/SCENE.toml``).
TABLES = Path(__file__).resolve().parents[1] / "studies" / "stability"

STATUSES = ("converged", "suspect", "failed", "stopped", "not attempted", "refused", "nan")

#: A point is suspect when its starved film pulls on the body with more than this
#: fraction of the film's push (``suction_load_fraction``).
SUCTION_LIMIT = 0.01

#: Columns of ``stability.csv`` besides the headline results a point reports.
COLUMNS = (
    "case", "over", "value", "status", "newton_iterations", "continuation_steps",
    "wall_time_s", "load_balance_error", "mass_balance_error", "complementarity_error",
    "start_attempts",
)  # fmt: skip
#: Headline results copied into ``stability.csv`` when a point reports them.
HEADLINE = (
    "mu", "h_min", "h_central", "max_contact_pressure", "contact_half_width", "contact_radius",
    "contact_width", "radial_load", "leakage_rate", "friction_torque", "max_principal_strain",
)  # fmt: skip
_KNOWN = {"scene", "over", "values", "time_budget", "parameters", "case"}
_CASE_KNOWN = {"name", "about", "set", "over", "values", "time_budget", "expect"}


@dataclass(frozen=True)
class Case:
    """One case of a stability table.

    Attributes:
        name: Unique name (the report's row label).
        about: What the case tests, in words.
        settings: Dotted parameter name -> value, applied over the table's
            ``parameters``.
        over: Swept parameter (dotted), or ``""`` for one point.
        values: Its values (empty for one point).
        time_budget: Wall time allowed to the case [s] (0: none); passed to the
            scene's ``stepping.time_budget`` when it has one.
        expect: ``"refused"`` for a case the input checks must refuse (no
            solution exists, e.g. a smooth contact at zero speed): the table is
            not checked for it, and its refusal is its result; ``""`` otherwise.
    """

    name: str
    about: str = ""
    settings: dict[str, Any] = field(default_factory=dict)
    over: str = ""
    values: tuple[float, ...] = ()
    time_budget: float = 0.0
    expect: str = ""

    @property
    def slug(self) -> str:
        """The case's folder name: its name in lower-case letters, digits, ``.``, ``-``."""
        return re.sub(r"[^a-z0-9.]+", "-", self.name.lower()).strip("-") or "case"


@dataclass(frozen=True)
class Table:
    """A stability table: the scene, the common overrides and the cases."""

    scene: str
    path: Path
    parameters: dict[str, Any]
    cases: tuple[Case, ...]

    def select(self, names: Sequence[str] | None) -> list[Case]:
        """The cases called ``names`` (all when None), in the table's order."""
        if not names:
            return list(self.cases)
        known = {c.name: c for c in self.cases} | {c.slug: c for c in self.cases}
        bad = [n for n in names if n not in known]
        if bad:
            raise ParameterError(
                f"--cases {','.join(bad)}: not a case of {self.path} (cases: "
                f"{', '.join(c.name for c in self.cases)})",
                "--cases",
            )
        wanted = {known[n].name for n in names}
        return [c for c in self.cases if c.name in wanted]


def _values(where: str, v: Any) -> tuple[float, ...]:
    if isinstance(v, str):
        return tuple(scenes.parse_values(v)) if v.strip() else ()
    if not isinstance(v, list) or not all(
        isinstance(x, int | float) and not isinstance(x, bool) for x in v
    ):
        raise ParameterError(f"{where}: values must be a list of numbers or 'start:stop:n[:log]'")
    return tuple(float(x) for x in v)


def table_path(scene: str) -> Path:
    """``studies/stability/SCENE.toml``, relative to the working directory when it
    lies below it (so the messages and reports that name it read the same on
    every machine)."""
    path = TABLES / f"{scene}.toml"
    try:
        return path.relative_to(Path.cwd().resolve())
    except ValueError:
        return path


def read_table(path: str | Path) -> Table:
    """Read and check a stability table: every case's parameters and swept values
    are set on the scene's parameters (:func:`check_table`), so a bad table stops
    here with the file, the case and the dotted parameter."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except OSError as e:
        raise ParameterError(f"stability table {path}: {e.strerror}") from None
    except tomllib.TOMLDecodeError as e:
        raise ParameterError(f"stability table {path}: not valid TOML: {e}") from None
    unknown = set(data) - _KNOWN
    if unknown:
        raise ParameterError(f"{path}: unknown key(s) {sorted(unknown)} (allowed {sorted(_KNOWN)})")
    scene = data.get("scene")
    if scene not in scenes.available():
        raise ParameterError(f"{path}: scene = {scene!r} is not one of {scenes.available()}")
    over0 = str(data.get("over", ""))
    values0 = _values(f"{path}: values", data.get("values", []))
    budget0 = data.get("time_budget", 0.0)
    cases = []
    for i, c in enumerate(data.get("case", [])):
        where = f"{path}: case {i + 1} ({c.get('name', '?')!r})"
        if not isinstance(c, Mapping) or not isinstance(c.get("name"), str) or not c["name"]:
            raise ParameterError(f"{where}: every [[case]] needs a name")
        bad = set(c) - _CASE_KNOWN
        if bad:
            raise ParameterError(
                f"{where}: unknown key(s) {sorted(bad)} (allowed {sorted(_CASE_KNOWN)})"
            )
        budget = c.get("time_budget", budget0)
        if not isinstance(budget, int | float) or isinstance(budget, bool) or not budget >= 0:
            raise ParameterError(f"{where}: time_budget = {budget!r} s must be a number >= 0")
        over = str(c.get("over", over0))
        values = _values(f"{where}: values", c["values"]) if "values" in c else values0
        if over and not values:
            raise ParameterError(f"{where}: over = {over!r} needs values")
        expect = c.get("expect", "")
        if expect not in ("", "refused"):
            raise ParameterError(f"{where}: expect = {expect!r} is not one of ['', 'refused']")
        cases.append(Case(name=c["name"], about=str(c.get("about", "")),
                          settings=flatten(c.get("set", {})), over=over,
                          values=values if over else (), time_budget=float(budget),
                          expect=expect))  # fmt: skip
    if not cases:
        raise ParameterError(f"{path}: no [[case]]")
    names = [c.name for c in cases]
    slugs = [c.slug for c in cases]
    if len(set(names)) < len(names) or len(set(slugs)) < len(slugs):
        raise ParameterError(f"{path}: case names (and their folder slugs) must be unique")
    table = Table(scene=scene, path=path, parameters=flatten(data.get("parameters", {})),
                  cases=tuple(cases))  # fmt: skip
    check_table(table)
    return table


def case_parameters(table: Table, case: Case) -> Any:
    """The scene's parameters of ``case``: defaults, the table's ``parameters``, the
    case's ``set`` and, when the scene has ``stepping``, its time budget."""
    settings = {**table.parameters, **case.settings}
    if case.time_budget and _has(scenes.make_parameters(table.scene), "stepping.time_budget"):
        settings.setdefault("stepping.time_budget", case.time_budget)
    nested: dict[str, Any] = {}
    for key, v in settings.items():  # all at once: the checks see the case's final values
        *head, last = key.split(".")
        node = nested
        for part in head:
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise ParameterError(f"{table.path}: case {case.name!r}: {key} and {part} both set")
        node[last] = v
    try:
        return scenes.make_parameters(table.scene, values=nested)
    except ParameterError as e:
        raise ParameterError(f"{table.path}: case {case.name!r}: {e}", e.parameter) from None


def _has(p: Any, dotted: str) -> bool:
    return _params.get_dotted(p, dotted) is not None


def check_table(table: Table) -> None:
    """Every case's parameters resolve and every swept value is allowed."""
    for case in table.cases:
        if case.expect == "refused":
            continue
        p = case_parameters(table, case)
        for v in case.values:
            try:
                _params.set_parameter(p, case.over, v)
            except ParameterError as e:
                raise ParameterError(
                    f"{table.path}: case {case.name!r}: {case.over} = {v!r}: {e}", e.parameter
                ) from None


# ------------------------------------------------------------------ running
def _point_row(case: Case, value: Any, status: str, res: Mapping[str, Any] | None = None,
               error: str = "") -> dict[str, Any]:  # fmt: skip
    row: dict[str, Any] = {"case": case.name, "over": case.over, "value": value,
                           "status": status}  # fmt: skip
    for k in COLUMNS[4:] + HEADLINE:
        if (
            res is not None
            and isinstance(res.get(k), int | float)
            and not isinstance(res.get(k), bool)
        ):
            row[k] = res[k]
    if res is not None and int(res.get("start_attempts", 1) or 1) > 1:
        row["strategy"] = str(res.get("strategy", ""))
    if res is not None and "load_balance_error" not in row and "radial_balance_error" in res:
        row["load_balance_error"] = abs(float(res["radial_balance_error"]))  # the lip's
    if res is not None and status == "converged":
        bad = sorted(k for k, v in res.items() if isinstance(v, float) and not math.isfinite(v))
        if bad:
            row["status"] = "nan"
            error = f"not finite: {', '.join(bad)}"
        else:
            reasons = _suspect_reasons(res)
            if reasons:
                row["status"] = "suspect"
                error = "; ".join(reasons)
    row["error"] = " ".join(error.split())
    return row


def _suspect_reasons(res: dict[str, Any]) -> list[str]:
    """Why a converged point lies outside the model (empty: it does not)."""
    reasons = []
    if isinstance(res.get("h_min"), float) and res["h_min"] < CONTINUUM_FILM:
        reasons.append(f"converged to a film thinner than a continuum film ({CONTINUUM_FILM:.0e} "
                       f"m): h_min = {res['h_min']:.3g} m")  # fmt: skip
    if 0.0 < float(res.get("discrete_upwinding_weight", 0.0)) < 1.0:
        reasons.append(
            "converged to a film of neither scheme (the release of the discrete "
            f"upwinding stopped short): discrete_upwinding_weight = "
            f"{res['discrete_upwinding_weight']:.3g}"
        )
    suction = res.get("suction_load_fraction")
    if isinstance(suction, float) and suction > SUCTION_LIMIT:
        reasons.append(
            "a starved film pulls on the body (p < 0 where theta = 0, from a non-monotone "
            f"transport scheme): suction_load_fraction = {suction:.3g}; "
            "film.discrete_upwinding = true is monotone"
        )
    return reasons


def _read_failures(out: Path) -> dict[float, str]:
    """Speed -> reason, from a sweep's ``sweep_failures.csv``."""
    import csv

    reasons: dict[float, str] = {}
    try:
        with (out / "sweep_failures.csv").open(newline="") as fh:
            for r in csv.DictReader(fh):
                reasons.setdefault(float(r["speed"]), r["error"])
    except (OSError, ValueError, KeyError):
        pass
    return reasons


def _failed_points(out: Path, over: str) -> dict[float, str]:
    """Value -> reason, from a sweep's ``results.json`` ``failed_points`` (per-point
    scenes) -- the ones without a value are the sweep's own error."""
    try:
        summary = json.loads((out / "results.json").read_text())
    except (OSError, ValueError):
        return {}
    got = {}
    for f in summary.get("failed_points", []):
        if isinstance(f.get(over), int | float):
            got[float(f[over])] = str(f.get("error", ""))
    return got


def run_case(table: Table, case: Case, out: Path) -> list[dict[str, Any]]:
    """Run one case into ``out`` and return its point rows (one per value)."""
    log = get_logger()
    t0 = time.perf_counter()
    try:
        p = case_parameters(table, case)
        for v in case.values:
            _params.set_parameter(p, case.over, v)
    except ParameterError as e:
        if case.expect != "refused":
            raise
        return [_point_row(case, v, "refused", error=str(e)) for v in case.values or ("",)]
    if not case.over:
        try:
            res = scenes.run_scene(table.scene, p, out, force=True)
        except (SolverError, ParameterError) as e:
            return [_point_row(case, "", "failed", error=_why(e))]
        res.setdefault("wall_time_s", time.perf_counter() - t0)
        ok = res.get("converged", True)
        return [_point_row(case, "", "converged" if ok else "failed", res,
                           "" if ok else "the solve did not converge")]  # fmt: skip
    error = ""
    try:
        rows = scenes.sweep_scene(table.scene, p, out, case.over, list(case.values), force=True)
    except (SolverError, ParameterError) as e:  # the sweep itself stopped (a start)
        error = _why(e)
        rows = list(getattr(e, "partial", None) or [])
        log.error("stability case %r stopped: %s", case.name, error)
    if not error:  # sweep_scene catches a scene sweep's error into results.json
        try:
            summary = json.loads((out / "results.json").read_text())
            errs = [f["error"] for f in summary.get("failed_points", []) if case.over not in f]
            error = "; ".join(errs)
        except (OSError, ValueError):
            pass
    by_value: dict[float, dict[str, Any]] = {}
    for r in rows:
        v = r.get(case.over, r.get("speed"))
        if isinstance(v, int | float):
            by_value.setdefault(float(v), r)
    reasons = {**_failed_points(out, case.over), **_read_failures(out)}
    points = []
    for v in case.values:
        if v in by_value:
            points.append(_point_row(case, v, "converged", by_value[v]))
        elif v in reasons:
            why = reasons[v]
            status = "not attempted" if why.startswith("not attempted") else "failed"
            points.append(_point_row(case, v, status, error=why))
        elif error:
            points.append(_point_row(case, v, "stopped", error=error))
        else:
            points.append(_point_row(case, v, "failed", error="no result and no reason recorded"))
    return points


def _why(e: BaseException) -> str:
    kind = "refused" if isinstance(e, ParameterError) else "solver error"
    return f"{kind}: {' '.join(str(e).split())}"


def stability_study(
    table: Table,
    out: str | Path,
    cases: Sequence[str] | None = None,
    progress: Progress | None = None,
) -> list[dict[str, Any]]:
    """Run the cases of ``table`` (``cases``: their names; all when None) into
    ``out`` and write ``stability.csv``, ``stability.md``, ``stability.png`` and
    ``results.json``.  Returns every point row."""
    out = Path(out)
    selected = table.select(cases)
    if world().rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    world().barrier()
    writer = SweepWriter(out, "stability.csv")
    rows: list[dict[str, Any]] = []
    times: dict[str, float] = {}
    t_all = time.perf_counter()
    for case in selected:
        t0 = time.perf_counter()
        pts = run_case(table, case, out / "cases" / case.slug)
        times[case.name] = time.perf_counter() - t0
        for r in pts:
            writer.append({k: r.get(k, "") for k in (*COLUMNS, *HEADLINE, "strategy", "error")})
        rows += pts
        if progress is not None:
            progress.point(case.name, {"newton_iterations": sum(
                int(r.get("newton_iterations", 0)) for r in pts)})  # fmt: skip
    counts = {s: sum(r["status"] == s for r in rows) for s in STATUSES}
    summary = {
        "study": "stability", "scene": table.scene, "table": str(table.path),
        "cases": [c.name for c in selected], "points": len(rows), "counts": counts,
        "case_wall_time_s": times, "wall_time_s": time.perf_counter() - t_all,
        "ranks": world().size,
    }  # fmt: skip
    write_results(out, summary)
    if world().rank == 0:
        write_text_atomic(out / "stability.md", markdown(table, selected, rows, times))
        plot_map(table, selected, rows, out / "stability.png")
    world().barrier()
    return rows


def rewrite_report(table: Table, out: str | Path) -> list[dict[str, Any]]:
    """Classify the points of an earlier run in ``out`` again (its ``stability.csv``,
    with the checks of this version: ``nan``, ``suspect``) and write its
    ``stability.csv``, ``stability.md``, ``stability.png`` and the counts of
    ``results.json`` anew, without solving anything (``study stability SCENE
    --report-only``).  Returns the rows."""
    from dolfinx_seal.output import parse_cell, read_csv

    out = Path(out)
    summary = json.loads((out / "results.json").read_text())
    if summary.get("study") != "stability" or summary.get("scene") != table.scene:
        raise ParameterError(f"{out}: no stability study of {table.scene!r} to report on")
    cases = {c.name: c for c in table.cases}
    rows = []
    for raw in read_csv(out / "stability.csv"):
        r = {k: parse_cell(v) for k, v in raw.items() if v != ""}
        case = cases.get(str(raw["case"]))
        if case is None:
            raise ParameterError(f"{out}: case {raw['case']!r} is not in {table.path}")
        value = r.get("value", "")
        if r["status"] == "converged":
            row = _point_row(case, value, "converged", r)
            row["strategy"] = r.get("strategy", "")
        else:
            row = {**r, "case": case.name, "value": value, "error": str(r.get("error", ""))}
        rows.append(row)
    selected = [c for c in table.cases if any(r["case"] == c.name for r in rows)]
    counts = {s: sum(r["status"] == s for r in rows) for s in STATUSES}
    summary.update(counts=counts)
    times = summary.get("case_wall_time_s", {})
    write_results(out, summary)
    if world().rank == 0:
        cols = (*COLUMNS, *HEADLINE, "strategy", "error")
        text = ",".join(cols) + "\n" + "".join(_csv_row([r.get(k, "") for k in cols]) for r in rows)
        write_text_atomic(out / "stability.csv", text)
        write_text_atomic(out / "stability.md",
                          markdown(table, selected, rows, times, summary.get("ranks", 1)))  # fmt: skip
        plot_map(table, selected, rows, out / "stability.png")
    world().barrier()
    return rows


def _csv_row(values: Sequence[Any]) -> str:
    import csv
    import io

    buf = io.StringIO(newline="")
    csv.writer(buf, lineterminator="\n").writerow(values)
    return buf.getvalue()


# ------------------------------------------------------------------ report
def _cell(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.3g}"
    return "" if v is None else str(v)


def case_summary(case: Case, pts: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """One case's counts, largest residuals and first failure."""

    def worst(key: str) -> float | None:
        vals = [float(r[key]) for r in pts if r["status"] == "converged" and key in r]
        return max(vals) if vals else None

    first = next((r for r in pts if r["status"] != "converged"), None)
    return {
        "converged": sum(r["status"] == "converged" for r in pts),
        "failed": sum(r["status"] in ("failed", "stopped", "nan", "suspect") for r in pts),
        "not attempted": sum(r["status"] == "not attempted" for r in pts),
        "refused": sum(r["status"] == "refused" for r in pts),
        "newton": sum(int(r.get("newton_iterations", 0) or 0) for r in pts),
        "load": worst("load_balance_error"),
        "mass": worst("mass_balance_error"),
        "compl": worst("complementarity_error"),
        "first": ""
        if first is None
        else (f"{_cell(first['value'])}: " if first["value"] != "" else "") + first["error"],
    }


def markdown(table: Table, cases: Sequence[Case], rows: Sequence[Mapping[str, Any]],
             times: Mapping[str, float], ranks: int | None = None) -> str:  # fmt: skip
    """The report: a summary table (a line per case) and each case's points."""
    lines = [f"# Stability study: `{table.scene}`", "",
             f"Table `{table.path.name}`, {len(cases)} cases, {len(rows)} points, "
             f"{ranks or world().size} rank(s).  Status counts: "
             + ", ".join(f"{s} {sum(r['status'] == s for r in rows)}" for s in STATUSES) + ".",
             "", "| case | what it tests | over | converged | failed, stopped or suspect | not attempted | refused "
             "| Newton | max load res. | max mass res. | max compl. res. | time [s] "
             "| first failure |", "|---" * 13 + "|"]  # fmt: skip
    for c in cases:
        pts = [r for r in rows if r["case"] == c.name]
        s = case_summary(c, pts)
        lines.append(
            f"| {c.name} | {c.about} | {c.over or '(one point)'} | {s['converged']} | "
            f"{s['failed']} | {s['not attempted']} | {s['refused']} | {s['newton']} | "
            f"{_cell(s['load'])} | "
            f"{_cell(s['mass'])} | {_cell(s['compl'])} | {times.get(c.name, 0.0):.0f} | "
            f"{s['first'][:300]} |"
        )
    for c in cases:
        pts = [r for r in rows if r["case"] == c.name]
        settings = ", ".join(f"`{k} = {v}`" for k, v in c.settings.items()) or "defaults"
        lines += ["", f"## {c.name}", "", f"{c.about or c.name} ({settings}).", "",
                  "| value | status | Newton | load res. | mass res. | compl. res. | mu | h_min [m] "
                  "| time [s] | error (or the fallback start that converged) |",
                  "|---" * 10 + "|"]  # fmt: skip
        before = None
        for r in pts:
            why = r.get("error", "") or r.get("strategy", "")
            shown = "(as above)" if why and why == before else why  # a stopped case's one error
            before = why
            lines.append("| " + " | ".join(_cell(r.get(k)) for k in (
                "value", "status", "newton_iterations", "load_balance_error",
                "mass_balance_error", "complementarity_error", "mu", "h_min", "wall_time_s",
            )) + f" | {shown} |")  # fmt: skip
    return "\n".join(lines) + "\n"


_COLOURS = {"converged": "#4caf50", "suspect": "#fdd835", "failed": "#e53935", "stopped": "#fb8c00",
            "not attempted": "#bdbdbd", "refused": "#1e88e5", "nan": "#6a1b9a"}  # fmt: skip


def plot_map(table: Table, cases: Sequence[Case], rows: Sequence[Mapping[str, Any]],
             path: Path) -> None:  # fmt: skip
    """The case x value map: one row per case, one column per distinct swept value
    (one-point cases in a column of their own), coloured by status, with the
    Newton steps of each point."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    def key(v: float) -> float:  # "1e-7:10:9:log" and "1e-4:10:6:log" differ in the last bits
        return float(f"{v:.9g}")

    values = sorted({key(r["value"]) for r in rows if isinstance(r["value"], int | float)})
    cols = [_cell(v) for v in values] + (["point"] if any(not c.over for c in cases) else [])
    width = max(4.5, 2.6 + 0.55 * len(cols))
    fig, ax = plt.subplots(figsize=(width, 1.2 + 0.3 * len(cases)))
    for i, c in enumerate(cases):
        for r in (r for r in rows if r["case"] == c.name):
            num = isinstance(r["value"], int | float)
            j = values.index(key(r["value"])) if num else len(values)
            ax.add_patch(plt.Rectangle((j, i), 1, 1, color=_COLOURS[r["status"]], ec="white"))
            if r.get("newton_iterations") not in (None, ""):
                ax.text(j + 0.5, i + 0.5, str(int(r["newton_iterations"])), ha="center",
                        va="center", fontsize=6)  # fmt: skip
    ax.set_xlim(0, len(cols))
    ax.set_ylim(len(cases), 0)
    ax.set_xticks([j + 0.5 for j in range(len(cols))], cols, rotation=60, fontsize=7)
    ax.set_yticks([i + 0.5 for i in range(len(cases))], [c.name for c in cases], fontsize=7)
    overs = sorted({c.over for c in cases if c.over})
    ax.set_xlabel(", ".join(overs) or "case")
    ax.set_title(f"{table.scene}: stability (numbers: Newton steps)", fontsize=9)
    ax.legend(handles=[Patch(color=v, label=k) for k, v in _COLOURS.items()], fontsize=6,
              loc="upper left", bbox_to_anchor=(1.01, 1.0))  # fmt: skip
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


__all__ = [
    "STATUSES",
    "Case",
    "Table",
    "case_parameters",
    "markdown",
    "plot_map",
    "read_table",
    "rewrite_report",
    "run_case",
    "stability_study",
    "table_path",
]
