"""Studies: error against run time over a sequence of discretisations.

``convergence_study`` runs one scene at several values of a resolution
parameter (e.g. ``h_contact``), records the wall time and the chosen scalar
results, and measures their error against

* ``reference="hertz"``: the analytical values the scene reports alongside
  (``hertz_peak_pressure``, ``hertz_half_width``, ``hertz_contact_radius``),
  meaningful with a nearly smooth contact law;
* ``reference="finest"``: the finest level (self-convergence; the finest
  level itself is then left out of the error columns);

and the observed order from successive differences.  It writes ``study.csv``
(one row per level, appended as each level finishes), ``results.json`` and a
log-log PNG of error against wall time.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from dolfinx_seal import scenes
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import world
from dolfinx_seal.output import Progress, SweepWriter, write_results
from dolfinx_seal.params import check_choice, set_parameter, to_dict

#: result key -> key of its analytical reference
HERTZ_KEYS = {
    "max_contact_pressure": "hertz_peak_pressure",
    "contact_half_width": "hertz_half_width",
    "contact_radius": "hertz_contact_radius",
}


def convergence_study(
    scene: str,
    parameters: Any,
    out: str | Path,
    over: str,
    values: Sequence[float],
    quantities: Sequence[str],
    reference: str = "hertz",
    progress: Progress | None = None,
) -> list[dict[str, Any]]:
    """Run ``scene`` at each value of ``over`` (coarse to fine) and tabulate errors and times.

    ``progress``: a :class:`~dolfinx_seal.output.Progress` told of every finished
    level (use ``growth=True``: finer levels take longer).
    """
    check_choice("reference", reference, ("hertz", "finest"))
    if len(values) < 2:
        raise ParameterError("a convergence study needs at least two levels (--values)")
    out = Path(out)
    writer = SweepWriter(out, "study.csv")
    rows: list[dict[str, Any]] = []
    t_all = time.perf_counter()
    for i, v in enumerate(values):
        p = set_parameter(parameters, over, v)
        res = scenes.get(scene).run(p, out / f"level{i}")
        row: dict[str, Any] = {over: v, "wall_time_s": res["wall_time_s"], "dofs": res.get("dofs", 0),
                               "newton_iterations": res.get("newton_iterations", 0)}  # fmt: skip
        for q in quantities:
            if q not in res:
                raise ParameterError(f"scene {scene!r} does not report {q!r}")
            row[q] = res[q]
            if reference == "hertz":
                if HERTZ_KEYS.get(q) not in res:
                    raise ParameterError(f"{q!r} has no analytical reference; use reference=finest")
                row[f"{q}_error"] = abs(res[q] / res[HERTZ_KEYS[q]] - 1.0)
        rows.append(row)
        writer.append(row)
        if progress is not None:
            progress.point(v, res)
    if reference == "finest":
        for q in quantities:
            ref = rows[-1][q]
            for r in rows:
                r[f"{q}_error"] = abs(r[q] / ref - 1.0) if r is not rows[-1] else float("nan")
    orders = {}
    for q in quantities:
        vals = [r[q] for r in rows]
        if len(vals) >= 3 and vals[-1] != vals[-2] and vals[-2] != vals[-3]:
            ratio = abs(vals[-3] - vals[-2]) / abs(vals[-2] - vals[-1])
            step = values[-3] / values[-2]
            orders[f"{q}_observed_order"] = math.log(ratio) / math.log(step)
    summary = {
        "scene": scene, "study": "convergence", "parameters": to_dict(parameters),
        "over": over, "values": list(values), "reference": reference,
        "wall_time_s": time.perf_counter() - t_all, **orders,
        "levels": [{k: (None if isinstance(x, float) and not math.isfinite(x) else x)
                    for k, x in r.items()} for r in rows],
    }  # fmt: skip
    write_results(out, summary)
    if world().rank == 0:
        _plot(rows, quantities, out / "error_vs_time.png", scene, reference)
    return rows


def _plot(
    rows: list[dict[str, Any]], quantities: Sequence[str], path: Path, scene: str, ref: str
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for q in quantities:
        pts = [
            (r["wall_time_s"], r[f"{q}_error"])
            for r in rows
            if math.isfinite(r[f"{q}_error"]) and r[f"{q}_error"] > 0
        ]
        if pts:
            t, e = zip(*pts, strict=True)
            ax.loglog(t, e, "o-", label=q)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel(f"relative error vs {ref}")
    ax.set_title(f"{scene}: error against run time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
