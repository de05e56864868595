"""Benchmark: is the default contact mesh of a lubricated scene resolved?

Runs one speed sweep of the scene per mesh level (``contact_elements``: elements
per Hertz radius or half-width, coarse to fine) with everything else at the
scene's defaults (or ``--set`` overrides), and compares the headline outputs of
every level with the finest one: mu, h_central, h_min and the contact size
(``contact_radius`` of the ball, ``contact_half_width`` of the cylinder; the
second moment of the normal pressure).  The default level passes where every
quantity at every speed is within ``--tolerance`` (2 %) of the finest level;
the change between the two finest levels is printed beside it as an estimate of
the finest level's own error (the levels are unstructured meshes, so the
differences need not be monotone and no order is fitted).

Writes into ``--out`` (default ``bench/results/mesh_defaults_<scene>``):
``levels.csv`` (one row per level and speed, appended as each point finishes),
``differences.csv`` (relative differences to the finest level), ``summary.md``
(the tables and the verdict) and ``differences.png``.

Run:  scripts/dx python3 bench/mesh_defaults.py ball [--levels 10 15 20 25 30 40] \\
          [--speeds 0.3 0.1 0.03 0.01] [--set contact.model=none] [--out DIR]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter, column, read_csv
from dolfinx_seal.params import set_parameter
from dolfinx_seal.scenes import make_parameters, sweep_scene

QUANTITIES = {
    "ball": ("mu", "h_central", "h_min", "contact_radius"),
    "cylinder": ("mu", "h_central", "h_min", "contact_half_width"),
}
DEFAULT_LEVELS = {"ball": [10, 15, 20, 25, 30, 40], "cylinder": [10, 15, 20, 30, 45, 60, 90]}
DEFAULT_SPEEDS = {"ball": [0.3, 0.1, 0.03, 0.01], "cylinder": [1e-6, 1e-4, 1e-3, 1e-2, 0.1, 1.0]}


def run_levels(scene: str, levels: list[float], speeds: list[float], overrides: list[str],
               out: Path) -> None:  # fmt: skip
    """One sweep per level; every finished point goes to ``levels.csv`` at once."""
    base = make_parameters(scene, overrides=overrides)
    writer = SweepWriter(out, "levels.csv")
    for n in levels:
        p = set_parameter(base, "contact_elements", float(n))
        t0 = time.perf_counter()
        rows = sweep_scene(scene, p, out / f"n{n:g}", "film.speed", speeds, force=True)
        for r in rows:
            row = {"contact_elements": float(n), "element_size": p.element_size,
                   "speed": float(r["speed"]), "dofs": int(r["dofs"]),
                   "newton_iterations": int(r["newton_iterations"]),
                   "wall_time_s": float(r["wall_time_s"])}  # fmt: skip
            row.update({q: float(r.get(q, math.nan)) for q in QUANTITIES[scene]})
            writer.append(row)
        print0(f"level {n:g}: {len(rows)} of {len(speeds)} speeds, "
               f"{time.perf_counter() - t0:.0f} s")  # fmt: skip


def compare(scene: str, out: Path, default: float, tolerance: float) -> bool:
    """``differences.csv``, ``summary.md`` and ``differences.png`` from ``levels.csv``;
    True if the default level is within ``tolerance`` of the finest everywhere."""
    COMM_WORLD.barrier()
    table = read_csv(out / "levels.csv")
    levels = sorted(set(column(table, "contact_elements")))
    speeds = sorted(set(column(table, "speed")), reverse=True)
    value = {(float(r["contact_elements"]), float(r["speed"])): r for r in table}
    finest, second = levels[-1], levels[-2] if len(levels) > 1 else None
    quantities = QUANTITIES[scene]
    diff_rows, ok = [], True
    lines = [f"# Mesh levels of `{scene}` against the finest ({finest:g} elements per Hertz "
             f"size)", "", f"Default: {default:g} elements; tolerance {tolerance:.0%}.", ""]  # fmt: skip
    for v in speeds:
        ref = value.get((finest, v))
        if ref is None:
            continue
        lines += [f"## {v:g} m/s", "",
                  "| elements | dofs | Newton | wall [s] | " + " | ".join(quantities) + " |",
                  "|---:|---:|---:|---:|" + "---:|" * len(quantities)]  # fmt: skip
        for n in levels:
            r = value.get((n, v))
            if r is None:
                lines.append(f"| {n:g} | not converged | | |" + " |" * len(quantities))
                if n == default:
                    ok = False
                continue
            d = {q: float(r[q]) / float(ref[q]) - 1.0 for q in quantities}
            diff_rows.append({"contact_elements": n, "speed": v, **d})
            if n == default and any(not abs(x) <= tolerance for x in d.values()):
                ok = False
            cells = " | ".join(f"{float(r[q]):.5g} ({d[q]:+.2%})" for q in quantities)
            lines.append(f"| {n:g} | {int(float(r['dofs']))} | {int(float(r['newton_iterations']))} "
                         f"| {float(r['wall_time_s']):.0f} | {cells} |")  # fmt: skip
        if second is not None and (second, v) in value:
            s2 = value[(second, v)]
            est = ", ".join(f"{q} {float(ref[q]) / float(s2[q]) - 1.0:+.2%}" for q in quantities)
            lines += ["", f"Finest against the next level ({second:g}): {est}."]
        lines.append("")
    verdict = "PASS" if ok else "FAIL"
    lines.append(f"**{verdict}**: the default ({default:g} elements) is "
                 f"{'' if ok else 'not '}within {tolerance:.0%} of the finest level "
                 "for every quantity and speed.")  # fmt: skip
    if COMM_WORLD.rank == 0:
        writer = SweepWriter(out, "differences.csv")
        for row in diff_rows:
            writer.append(row)
        (out / "summary.md").write_text("\n".join(lines) + "\n")
        _plot(out, diff_rows, quantities, speeds, scene, finest)
    print0("\n".join(lines))
    return ok


def _plot(out: Path, rows: list[dict[str, Any]], quantities: tuple[str, ...],
          speeds: list[float], scene: str, finest: float) -> None:  # fmt: skip
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(quantities), figsize=(3.2 * len(quantities), 3.2),
                             sharey=True)  # fmt: skip
    for ax, q in zip(axes, quantities, strict=True):
        for v in speeds:
            pts = [(r["contact_elements"], abs(r[q])) for r in rows
                   if r["speed"] == v and r["contact_elements"] != finest]  # fmt: skip
            if pts:
                n, d = zip(*pts, strict=True)
                ax.loglog(n, [max(x, 1e-6) for x in d], "o-", label=f"{v:g} m/s")
        ax.axhline(0.02, color="k", lw=0.8, ls=":")
        ax.set_title(q)
        ax.set_xlabel("elements per Hertz size")
    axes[0].set_ylabel(f"|difference to {finest:g}|")
    axes[-1].legend(frameon=False, fontsize=7)
    fig.suptitle(f"{scene}: mesh levels against the finest")
    fig.tight_layout()
    fig.savefig(out / "differences.png", dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", choices=sorted(QUANTITIES))
    parser.add_argument("--levels", type=float, nargs="+", help="elements per Hertz size")
    parser.add_argument("--speeds", type=float, nargs="+", help="[m/s]")
    parser.add_argument("--set", action="append", default=[], help="KEY=VALUE overrides")
    parser.add_argument("--tolerance", type=float, default=0.02)
    parser.add_argument("--report-only", action="store_true", help="compare levels.csv only")
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    scene = args.scene
    out = bcast_path(args.out or f"bench/results/mesh_defaults_{scene}")
    default = make_parameters(scene, overrides=args.set).contact_elements
    if not args.report_only:
        levels = sorted(args.levels or DEFAULT_LEVELS[scene])
        speeds = args.speeds or DEFAULT_SPEEDS[scene]
        run_levels(scene, levels, speeds, args.set, out)
    return 0 if compare(scene, out, default, args.tolerance) else 1


if __name__ == "__main__":
    sys.exit(main())
