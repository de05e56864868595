"""Stribeck sweeps of lubricated scenes: speed continuation, incremental output, plots.

A scene supplies how to build its coupled problem, how to start it and how to
write one point; :func:`lubricated_sweep` does the rest the same way for every
scene (cylinder, ball): start at the first speed of the ordered list, walk the
others with :func:`~dolfinx_seal.coupled.continuation.speed_sweep`, hand each
converged point to ``on_point`` at once (``sweep.csv``), record failed targets
in ``sweep_failures.csv`` and go on from the last good point.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from dolfinx_seal.coupled.continuation import order_speeds, speed_sweep
from dolfinx_seal.coupled.results import lubricated_results
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import set_parameter


@dataclass(frozen=True)
class SweepHooks:
    """What a scene supplies to :func:`lubricated_sweep`.

    Attributes:
        build: ``params -> (problem, info)``; ``info["nominal_area"]`` is the
            nominal contact area (length in 2D) [m^2 or m].
        start: ``(problem, params) -> solver figures``: first converged state.
        write_point: ``(out_dir, problem, params)``: per-point profiles/maps.
        symmetry_factor: Multiplies integrals over a symmetric half model.
    """

    build: Callable[[Any], tuple[Any, dict[str, Any]]]
    start: Callable[[Any, Any], dict[str, Any]]
    write_point: Callable[[Path, Any, Any], None]
    symmetry_factor: float = 1.0


def lubricated_sweep(
    params: Any, out: Path, name: str, values: list[float], on_point: Any, hooks: SweepHooks
) -> list[dict[str, Any]]:
    """Stribeck sweep of ``params`` over ``film.speed`` (``--over speed`` or ``film.speed``).

    Speeds are ordered by ``params.sweep_order``; the continuation options are
    ``params.stepping``.  Returns the rows of the converged points; a target the
    continuation cannot reach is recorded (``sweep_failures.csv``) and skipped.  A
    failure it cannot absorb (the start, or outside the continuation steps) raises
    :class:`SolverError` with ``partial`` = the finished rows (``name`` added).
    """
    if name not in ("speed", "film.speed"):
        raise ParameterError(f"lubricated sweeps run over film.speed (got --over {name!r})")
    if not params.lubricated:
        raise ParameterError("lubricated = false: a speed sweep needs the film")
    speeds = order_speeds(values, params.sweep_order)
    p0 = set_parameter(params, "film.speed", speeds[0])
    prob, info = hooks.build(p0)
    rows: list[dict[str, Any]] = []

    def results() -> dict[str, Any]:
        r = lubricated_results(
            prob, symmetry_factor=hooks.symmetry_factor, nominal_area=info["nominal_area"]
        )
        r.update(dofs=prob.dofs, ranks=COMM_WORLD.size)
        return r

    done: list[float] = []  # the speed of each row

    def point(v: float, r: dict[str, Any]) -> None:
        rows.append(r)
        done.append(v)
        on_point(v, r)
        hooks.write_point(out / f"speed_{v:.3e}", prob, set_parameter(params, "film.speed", v))

    t0 = time.perf_counter()
    try:
        start = hooks.start(prob, p0)
        r0 = results()
        r0.update(newton_iterations=start["newton_iterations"], continuation_steps=1,
                  film_presolve_iterations=start.get("film_presolve_iterations", 0),
                  wall_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
        point(speeds[0], r0)
        recs = speed_sweep(prob, speeds[1:], point, results, params.stepping)
    except SolverError as e:  # the sweep cannot go on: hand back the finished rows
        if e.partial is None:
            e.partial = [{name: s, **r} for s, r in zip(done, rows, strict=True)]
        raise
    failed = [r for r in recs if not r.converged]
    if failed and COMM_WORLD.rank == 0:
        with (out / "sweep_failures.csv").open("w") as fh:
            fh.write("speed,error\n")
            for r in failed:
                fh.write(f'{r.speed!r},"{r.error}"\n')
    return rows


def plot_sweep(rows: list[dict[str, Any]], out_dir: Path, name: str) -> None:
    """Stribeck curve mu(eta v) with its parts, the load split and the film
    thickness (``sweep.png``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = sorted(rows, key=lambda r: float(r["eta_v"]))
    ev = np.array([float(r["eta_v"]) for r in rows])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    ax1.loglog(ev, [float(r["mu"]) for r in rows], "ko-", ms=3, label="mu")
    for k, st in (("mu_asperity", "s--"), ("mu_couette", "^--"), ("mu_poiseuille", "v--")):
        if k in rows[0]:
            y = np.array([float(r[k]) for r in rows])
            ax1.loglog(ev[y > 0], y[y > 0], st, ms=3, label=k)
    ax1.set_xlabel("eta v [Pa m]")
    ax1.set_ylabel("friction coefficient")
    # parts far below the total (asperity friction in full film, 1e-11) would hide mu
    ax1.set_ylim(bottom=1e-2 * min(float(r["mu"]) for r in rows))
    ax1.legend(frameon=False, fontsize=8)
    ax2.semilogx(ev, [float(r["fluid_load_fraction"]) for r in rows], "bo-", ms=3, label="fluid")
    ax2.semilogx(
        ev, [1 - float(r["fluid_load_fraction"]) for r in rows], "rs-", ms=3, label="asperities"
    )
    ax2.set_xlabel("eta v [Pa m]")
    ax2.set_ylabel("load fraction")
    ax2.legend(frameon=False, loc="center left")
    ax3 = ax2.twinx()
    ax3.loglog(ev, [float(r["h_min"]) * 1e6 for r in rows], "g^:", ms=3, label="h_min")
    if "h_central" in rows[0]:
        ax3.loglog(ev, [float(r["h_central"]) * 1e6 for r in rows], "gv-", ms=3, label="h_central")
        ax3.legend(frameon=False, loc="lower right", fontsize=8)
    ax3.set_ylabel("film thickness [um] (green)")
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "sweep.png", dpi=120)
    plt.close(fig)


def stribeck_minimum(eta_v: Any, mu: Any) -> tuple[float, float, bool]:
    """(eta v, mu) of the minimum of a sampled Stribeck curve and whether it is
    bracketed (a neighbour on each side): the vertex of the parabola in
    (log eta v, log mu) through the smallest sample and its neighbours, else the
    smallest sample itself."""
    ev, m = np.asarray(eta_v, dtype=float), np.asarray(mu, dtype=float)
    order = np.argsort(ev)
    x, y = np.log10(ev[order]), np.log10(m[order])
    i = int(np.argmin(y))
    if i == 0 or i == len(x) - 1:
        return float(ev[order][i]), float(m[order][i]), False
    c2, c1, c0 = np.polyfit(x[i - 1 : i + 2], y[i - 1 : i + 2], 2)
    xv = -c1 / (2.0 * c2)
    return float(10**xv), float(10 ** (c0 + c1 * xv + c2 * xv * xv)), True


__all__ = ["SweepHooks", "lubricated_sweep", "plot_sweep", "stribeck_minimum"]
