"""Soak: resident memory and live PETSc objects over a long run of the lubricated cylinder.

Two modes, each recording per point the resident set size (``VmRSS`` of
``/proc/self/status``, on every rank), the live PETSc objects (creations minus
destructions of PETSc's log, rank 0), the entries of the PETSc options database
and the Python objects tracked by the garbage collector:

``sweep`` (default)
    One coupled problem (``dolfinx-seal sweep cylinder``'s code path,
    :func:`dolfinx_seal.scenes.cylinder.sweep`, ``sweep_order = "given"``) walked
    up and down a speed range by continuation, repeated until ``--points``
    points; every point computes the results and writes its film profile.
``rebuild``
    ``--points`` independent :func:`dolfinx_seal.scenes.run_scene` calls: each
    builds the mesh, the forms and the solvers, starts from the dry state and
    writes ``results.json`` (the path where leaks in building or destroying
    problems would show).

After ``--warmup`` points (matplotlib's text-metrics cache, an LRU of 4096
entries keyed per renderer, fills over the first ~95 saved figures: about
2 MB) the growth rate is the slope of a least-squares line through memory
against point number [kB/point] (the largest rank's RSS).  The run fails (exit
status 1) if it exceeds ``--bound`` kB/point beyond the result rows the sweep
keeps by design (their measured size, ``results_kept_kB``), or if the live
PETSc objects grow at all after the warm-up.

``--trim`` calls glibc's ``malloc_trim(0)`` before every reading, so the RSS
counts the C heap in use and not the free pages the allocator keeps (on 2 ranks
rank 0's untrimmed RSS grew in steps of 4-388 kB that trimming removes; the
files get ``_trim`` appended).  ``python_blocks_max`` is Python's allocated
blocks (``sys.getallocatedblocks``, the largest rank).

Writes ``soak.csv`` / ``soak.png`` (sweep) or ``soak_rebuild.csv`` /
``soak_rebuild.png`` into ``--out`` (``_np<N>`` appended under ``mpirun -n N``).

Run:  scripts/dx python3 bench/soak.py [--points 240] [--h-contact 60e-6] [--trim]
      scripts/dx mpirun -n 2 python3 bench/soak.py
      scripts/dx python3 bench/soak.py --mode rebuild --points 40 --warmup 5
"""

from __future__ import annotations

import argparse
import csv
import gc
import math
import re
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from petsc4py import PETSc

PETSc.Log.begin()  # before any PETSc object: creations and destructions are counted

import numpy as np  # noqa: E402

from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0  # noqa: E402
from dolfinx_seal.output import SweepWriter  # noqa: E402
from dolfinx_seal.scenes import make_parameters, parse_values, run_scene  # noqa: E402
from dolfinx_seal.scenes.cylinder import sweep  # noqa: E402


def rss_kb() -> int:
    """Resident set size of this process [kB] (``VmRSS``)."""
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS in /proc/self/status")


def malloc_trim() -> None:
    """Hand the C heap's free pages back to the system (glibc ``malloc_trim(0)``), so
    the RSS that follows counts memory in use, not freed memory the allocator keeps."""
    import ctypes

    ctypes.CDLL("libc.so.6").malloc_trim(0)


_OBJ_LINE = re.compile(r"^\s*(\S.*?)\s+(\d+)\s+(\d+)\s*$", re.M)


def petsc_census(scratch: Path) -> tuple[dict[str, int], int]:
    """Live PETSc objects per class (rank 0's log) and options database entries.

    Reads PETSc's own log summary (``PETSc.Log.view``, collective): the table
    "Object Type / Creations / Destructions" and the option table.
    """
    viewer = PETSc.Viewer().createASCII(str(scratch), comm=COMM_WORLD)
    PETSc.Log.view(viewer)
    viewer.destroy()
    alive: dict[str, int] = {}
    options = 0
    if COMM_WORLD.rank == 0:
        text = scratch.read_text()
        table = text.split("Object Type", 1)[1].split("=====", 1)[0]
        for m in _OBJ_LINE.finditer(table):
            alive[m.group(1)] = alive.get(m.group(1), 0) + int(m.group(2)) - int(m.group(3))
        a, b = text.find("#PETSc Option Table entries"), text.find("#End of PETSc Option Table")
        if a >= 0 and b > a:
            options = sum(1 for ln in text[a:b].splitlines() if ln.startswith("-"))
    return COMM_WORLD.bcast(alive, root=0), COMM_WORLD.bcast(options, root=0)


def deep_size(d: dict[str, Any]) -> int:
    """Bytes of a flat result dict: the dict, its keys and its values [B]."""
    return sys.getsizeof(d) + sum(sys.getsizeof(k) + sys.getsizeof(v) for k, v in d.items())


def mpl_text_cache() -> int:
    """Entries of matplotlib's text-metrics cache (an LRU of 4096 entries keyed per
    renderer: every saved figure adds its texts until it is full), 0 before any plot."""
    text = sys.modules.get("matplotlib.text")
    cache = getattr(text, "_get_text_metrics_with_cache_impl", None)
    return int(cache.cache_info().currsize) if cache is not None else 0


def growth(points: np.ndarray, values: np.ndarray, warmup: int) -> tuple[float, float]:
    """Slope [unit/point] and intercept of the least-squares line after ``warmup`` points."""
    keep = points >= warmup
    if keep.sum() < 2:
        return math.nan, math.nan
    slope, icpt = np.polyfit(points[keep], values[keep], 1)
    return float(slope), float(icpt)


def speed_cycle(speeds: list[float], n: int) -> list[float]:
    """``n`` speeds walking up and down ``speeds`` (sorted), no speed twice in a row."""
    v = sorted(speeds)
    if len(v) < 2:
        raise SystemExit("--speeds needs at least two values")
    period = v + v[-2:0:-1]
    return [period[i % len(period)] for i in range(n)]


class Recorder:
    """Per-point memory census, written to a CSV row at once."""

    def __init__(self, out: Path, name: str, h_contact: float, keeps_results: bool,
                 trim: bool = False) -> None:  # fmt: skip
        self.out = out
        self.trim = trim
        self.keeps_results = keeps_results  # a sweep returns its rows; run_scene keeps none
        self.h_contact = h_contact
        self.scratch = out / f".{name}_petsc_log.txt"
        self.writer = SweepWriter(out, f"{name}.csv")
        self.rows: list[dict[str, Any]] = []
        self.t0 = time.perf_counter()
        self.kept = 0

    def point(self, speed: float, r: dict[str, Any]) -> bool:
        if self.keeps_results:  # the sweep keeps its result rows (by design)
            self.kept += deep_size(r)
        gc.collect()
        if self.trim:
            malloc_trim()
        rss = COMM_WORLD.allgather(rss_kb())
        blocks = COMM_WORLD.allgather(sys.getallocatedblocks())
        alive, options = petsc_census(self.scratch)
        row = {
            "point": len(self.rows), "speed": speed, "mu": float(r["mu"]),
            "newton_iterations": int(r.get("newton_iterations", 0) or 0),
            "rss_rank0_kB": rss[0], "rss_max_kB": max(rss), "rss_sum_kB": sum(rss),
            "petsc_objects": sum(alive.values()), "petsc_options": options,
            "python_objects": len(gc.get_objects()), "python_blocks_max": max(blocks),
            "results_kept_kB": 0.0, "mpl_text_cache": mpl_text_cache(),
            "time_s": time.perf_counter() - self.t0,
            "ranks": COMM_WORLD.size, "h_contact": self.h_contact,
            **{f"petsc_{k.lower().replace(' ', '_')}": n for k, n in sorted(alive.items())},
        }  # fmt: skip
        self.kept += deep_size(row)
        row["results_kept_kB"] = self.kept / 1024.0
        if self.rows:  # PETSc classes first seen later (e.g. a viewer) get no new column
            row = {k: row.get(k, 0) for k in self.rows[0]}
        self.rows.append(row)
        self.writer.append(row)
        print0(
            f"point {row['point']:4d}  U = {speed:.3e} m/s  mu = {row['mu']:.5f}  "
            f"Newton {row['newton_iterations']:3d}  RSS {row['rss_max_kB'] / 1024:8.1f} MB  "
            f"PETSc objects {row['petsc_objects']:6d}  options {options:5d}  "
            f"Python objects {row['python_objects']:8d}  t = {row['time_s']:7.1f} s",
            flush=True,
        )
        return True  # the sweep writes every point's map, as a user's does by default


def plot(rows: list[dict[str, Any]], path: Path, warmup: int, title: str) -> dict[str, float]:
    """Memory and PETSc objects against point number, the fitted growth; returns the fits."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = np.array([r["point"] for r in rows], dtype=float)
    rss = np.array([r["rss_max_kB"] for r in rows], dtype=float)
    obj = np.array([r["petsc_objects"] for r in rows], dtype=float)
    s_rss, c_rss = growth(n, rss, warmup)
    s_obj, _ = growth(n, obj, warmup)
    fig, ax = plt.subplots(figsize=(8, 4.2))
    ax.plot(n, rss / 1024.0, "k.-", ms=3, lw=0.8, label="RSS (largest rank)")
    if math.isfinite(s_rss):
        nn = n[n >= warmup]
        ax.plot(nn, (c_rss + s_rss * nn) / 1024.0, "r-", lw=1.5,
                label=f"fit after {warmup} points: {s_rss:+.2f} kB/point")  # fmt: skip
    ax.axvline(warmup, color="0.6", ls=":", lw=1)
    ax.set_xlabel("point")
    ax.set_ylabel("resident memory [MB]")
    ax2 = ax.twinx()
    ax2.plot(n, obj, "b-", lw=1, label=f"live PETSc objects ({s_obj:+.3f}/point)")
    ax2.set_ylabel("live PETSc objects (rank 0)", color="b")
    ax2.set_ylim(bottom=0, top=max(1.0, 1.3 * obj.max()))
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, frameon=False, loc="lower right", fontsize=8)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return {"rss_slope_kB_per_point": s_rss, "petsc_objects_per_point": s_obj}


def _title(mode: str, h_contact: float, speeds: list[float], ranks: int) -> str:
    if mode == "sweep":
        return (f"cylinder sweep, h_contact = {h_contact * 1e6:g} um, speeds "
                f"{min(speeds):g}..{max(speeds):g} m/s up and down, {ranks} rank(s)")  # fmt: skip
    return (f"cylinder run_scene repeated, h_contact = {h_contact * 1e6:g} um, "
            f"U = {speeds[0]:g} m/s, {ranks} rank(s)")  # fmt: skip


def report(rows: list[dict[str, Any]], png: Path, warmup: int, bound: float, title: str) -> bool:
    """Plot, print the summary table and check the bound (rank 0 decides, all return it)."""
    ok = False
    if COMM_WORLD.rank == 0:
        fit = plot(rows, png, warmup, title)
        first, warm, last = rows[0], rows[warmup], rows[-1]
        slope = fit["rss_slope_kB_per_point"]
        n = np.array([r["point"] for r in rows], dtype=float)
        kept_col = np.array([r.get("results_kept_kB", 0.0) for r in rows], dtype=float)
        kept, _ = growth(n, kept_col, warmup)
        allowed = bound + kept
        print(f"| ranks | points | RSS first / after warm-up / last [MB] | growth after {warmup} "
              "points [kB/point] | PETSc objects after warm-up / last | PETSc options after "
              "warm-up / last | Python objects after warm-up / last |")  # fmt: skip
        print("|---:|---:|---|---:|---|---|---|")
        print(f"| {last['ranks']} | {len(rows)} | {first['rss_max_kB'] / 1024:.1f} / "
              f"{warm['rss_max_kB'] / 1024:.1f} / {last['rss_max_kB'] / 1024:.1f} | {slope:+.2f} | "
              f"{warm['petsc_objects']} / {last['petsc_objects']} | {warm['petsc_options']} / "
              f"{last['petsc_options']} | {warm['python_objects']} / {last['python_objects']} |")  # fmt: skip
        ok = bool(slope <= allowed and last["petsc_objects"] <= warm["petsc_objects"])
        print(f"results kept by the sweep: {kept:.2f} kB/point; bound {bound:g} kB/point beyond "
              f"them ({allowed:.2f} kB/point) and no PETSc object added after the warm-up: "
              f"{'PASS' if ok else 'FAIL'}", flush=True)  # fmt: skip
    return bool(COMM_WORLD.bcast(ok, root=0))


def _read_rows(path: Path) -> list[dict[str, Any]]:
    """Rows of a soak CSV with numbers as numbers."""
    with path.open() as fh:
        rows = list(csv.DictReader(fh))
    return [{k: (float(v) if "." in v or "e" in v else int(v)) for k, v in r.items()} for r in rows]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mode", choices=("sweep", "rebuild"), default="sweep")
    parser.add_argument("--points", type=int, default=240, help="points to run")
    parser.add_argument("--warmup", type=int, default=100, help="points left out of the fit")
    parser.add_argument("--h-contact", type=float, default=60e-6, help="contact element size [m]")
    parser.add_argument("--speeds", default="1e-2:1e-1:5:log",
                        help="speeds walked up and down (sweep) [m/s]")  # fmt: skip
    parser.add_argument("--speed", type=float, default=1e-2, help="speed of each rebuild [m/s]")
    parser.add_argument("--bound", type=float, default=1.0, help="allowed growth [kB/point]")
    parser.add_argument("--trim", action="store_true",
                        help="malloc_trim(0) before each RSS reading: count the C heap in use, "
                        "not freed pages glibc keeps (writes soak*_trim.csv)")  # fmt: skip
    parser.add_argument("--replot", action="store_true",
                        help="only fit and plot the CSV of an earlier run (same --mode, --out)")  # fmt: skip
    parser.add_argument("--out", default="bench/results")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    suffix = "" if COMM_WORLD.size == 1 else f"_np{COMM_WORLD.size}"
    name = (
        ("soak" if args.mode == "sweep" else "soak_rebuild")
        + suffix
        + ("_trim" if args.trim else "")
    )
    if args.replot:
        rows = _read_rows(out / f"{name}.csv") if COMM_WORLD.rank == 0 else []
        rows = COMM_WORLD.bcast(rows, root=0)
        if len(rows) <= args.warmup + 1:
            raise SystemExit(f"{len(rows)} points: --warmup must leave at least two")
        title = _title(args.mode, rows[0].get("h_contact", args.h_contact), [r["speed"] for r in rows],
                       int(rows[0]["ranks"]))  # fmt: skip
        return 0 if report(rows, out / f"{name}.png", args.warmup, args.bound, title) else 1
    if args.points <= args.warmup + 1:
        raise SystemExit("--points must exceed --warmup + 1")
    work = out / f"{name}_runs"
    rec = Recorder(out, name, args.h_contact, keeps_results=args.mode == "sweep", trim=args.trim)
    print0(f"soak ({args.mode}): {args.points} points, h_contact = {args.h_contact:g} m, "
           f"ranks: {COMM_WORLD.size}")  # fmt: skip
    if args.mode == "sweep":
        speeds = speed_cycle(parse_values(args.speeds), args.points)
        p = make_parameters(
            "cylinder", values={"h_contact": args.h_contact, "sweep_order": "given"}
        )
        sweep(p, work, "film.speed", speeds, rec.point)
    else:
        speeds = [args.speed]
        for _ in range(args.points):
            p = make_parameters("cylinder", values={"h_contact": args.h_contact,
                                                    "film": {"speed": args.speed}})  # fmt: skip
            rec.point(args.speed, run_scene("cylinder", p, work, force=True))
    rows = rec.rows
    if len(rows) < args.points:
        print0(f"only {len(rows)} of {args.points} points converged")
        return 1
    title = _title(args.mode, args.h_contact, speeds, COMM_WORLD.size)
    return 0 if report(rows, out / f"{name}.png", args.warmup, args.bound, title) else 1


if __name__ == "__main__":
    sys.exit(main())
