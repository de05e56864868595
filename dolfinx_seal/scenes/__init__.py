"""Scenes: named, documented sets of physics switches and parameters.

A scene module defines a parameter dataclass (its single source of defaults)
and a :class:`Scene` object named ``SCENE``.  The registry below maps scene
names to modules, imported lazily so that ``dolfinx-seal versions`` or a
pure-numpy scene never imports DOLFINx.

The generic drivers :func:`run_scene` and :func:`sweep_scene` write the
results contract (``results.json``, ``sweep.csv``; a sweep also its manifest
``sweep.json``) for every scene.  Before writing anything they refuse an output
folder that holds another scene's or another parameter set's results unless
``force=True`` (:func:`dolfinx_seal.output.check_out_dir`).
"""

from __future__ import annotations

import importlib
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from dolfinx_seal import params as _params
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import COMM_SELF, get_logger, using_comm, world
from dolfinx_seal.output import (
    Progress,
    SweepWriter,
    check_out_dir,
    parse_cell,
    read_csv,
    resume_rows,
    write_results,
    write_sweep_failures,
    write_sweep_manifest,
)
from dolfinx_seal.params import set_parameter as set_parameter  # part of the scenes API

#: scene name -> module that defines ``SCENE``.
REGISTRY: dict[str, str] = {
    "rubber-friction": "dolfinx_seal.scenes.rubber_friction",
    "flat": "dolfinx_seal.scenes.flat",
    "cylinder": "dolfinx_seal.scenes.cylinder",
    "ball": "dolfinx_seal.scenes.ball",
    "lip-install": "dolfinx_seal.scenes.lip_install",
    "lip": "dolfinx_seal.scenes.lip",
    "lip-static": "dolfinx_seal.scenes.lip_sector",
    "lip-dynamic": "dolfinx_seal.scenes.lip_dynamic",
}

#: A point callback of a sweep: receives the sweep value and the results of the point,
#: and returns whether the scene writes that point's own files (its ``speed_<U>/`` or
#: ``oil_pressure_<p>/`` folder: film maps, profiles, their CSV; ``--point-files``).
PointCallback = Callable[[float, Mapping[str, Any]], bool]


@dataclass(frozen=True)
class Scene:
    """A scene.

    Attributes:
        name: Registry name (CLI ``dolfinx-seal run NAME``).
        summary: One line for ``dolfinx-seal scenes``.
        parameters: Parameter dataclass; its defaults are the scene defaults.
        run: ``run(params, out_dir) -> results`` computes one point, writes the
            scene's fields/plots into ``out_dir`` and returns the scalar results
            (SI; keys of the results contract plus scene-specific ones).
        sweep: Optional ``sweep(params, out_dir, name, values, on_point) -> rows``
            with continuation; it calls ``on_point(value, results)`` as each point
            finishes, writes that point's own files when the call returns true
            (:func:`writes_point_files`), and raises :class:`SolverError` (with ``partial`` = finished
            rows) if it cannot go on.  Without it, points are run independently.
        plot_sweep: Optional ``plot_sweep(rows, out_dir, name)`` drawing the sweep PNG.
        resumable: ``sweep`` takes ``resume=`` (a :class:`Resume`, or None) and
            goes on from its own checkpoint; otherwise a resumed sweep is handed
            the values not finished yet, and the scene starts them afresh.
    """

    name: str
    summary: str
    parameters: type
    run: Callable[[Any, Path], dict[str, Any]]
    sweep: Callable[..., list[dict[str, Any]]] | None = None
    plot_sweep: Callable[[list[dict[str, Any]], Path, str], None] | None = None
    resumable: bool = False


@dataclass(frozen=True)
class Resume:
    """What a resumed sweep finds in its folder (handed to a resumable scene's sweep).

    Attributes:
        rows: Number of rows in ``sweep.csv``.
        done: How often each sweep value has a row there.
    """

    rows: int
    done: Mapping[float, int]

    def positions(self, values: Sequence[float]) -> list[int]:
        """Positions in ``values`` of the points not finished (each row takes off the
        first occurrence of its value)."""
        left = dict(self.done)
        out = []
        for i, v in enumerate(values):
            if left.get(float(v), 0) > 0:
                left[float(v)] -= 1
            else:
                out.append(i)
        return out

    def remaining(self, values: Sequence[float]) -> list[float]:
        """``values`` without the finished ones, in their order."""
        return [values[i] for i in self.positions(values)]


def available() -> list[str]:
    """Names of the registered scenes."""
    return sorted(REGISTRY)


def get(name: str) -> Scene:
    """The :class:`Scene` called ``name``."""
    if name not in REGISTRY:
        raise ParameterError(f"unknown scene {name!r}; available: {', '.join(available())}")
    return importlib.import_module(REGISTRY[name]).SCENE


def make_parameters(
    name: str,
    scene_file: str | Path | None = None,
    overrides: Sequence[str] = (),
    values: Mapping[str, Any] | None = None,
) -> Any:
    """Resolve a scene's parameters: defaults < TOML file < ``values`` < ``--set`` overrides."""
    scene = get(name)
    data: dict[str, Any] = {}
    if scene_file is not None:
        data = _params.load_toml(scene_file)
        file_scene = data.pop("scene", name)
        if file_scene != name:
            raise ParameterError(f"scene file is for scene {file_scene!r}, not {name!r}")
        data = dict(data.pop("parameters", data))
    if values:
        data = _params.merge(data, values)
    data = _params.merge(data, _params.parse_overrides(overrides))
    return _params.from_mapping(scene.parameters, data)


def _scalars(results: Mapping[str, Any]) -> dict[str, Any]:
    return {
        k: v
        for k, v in results.items()
        if isinstance(v, int | float | bool | str) and k not in ("scene",)
    }


def run_scene(
    name: str, parameters: Any, out_dir: str | Path, force: bool = False
) -> dict[str, Any]:
    """Run one point of scene ``name`` and write ``results.json`` into ``out_dir``.

    ``out_dir`` may hold this run's own results (a rerun overwrites them); one
    holding another scene's, a sweep's or other parameters' results is refused
    with :class:`~dolfinx_seal.output.OutputFolderError` (a :class:`ParameterError`)
    before anything is written, unless ``force``.
    """
    scene = get(name)
    out = Path(out_dir)
    check_out_dir(out, name, _params.to_dict(parameters), force=force)
    if world().rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    world().barrier()
    t0 = time.perf_counter()
    results = scene.run(parameters, out)
    results.setdefault("wall_time_s", time.perf_counter() - t0)
    full = {"scene": name, "parameters": _params.to_dict(parameters), **results}
    write_results(out, full)
    return full


def sweep_scene(
    name: str,
    parameters: Any,
    out_dir: str | Path,
    over: str,
    values: Sequence[float],
    force: bool = False,
    progress: Progress | None = None,
    resume: bool = False,
    point_files: int = 1,
) -> list[dict[str, Any]]:
    """Sweep scene ``name`` over parameter ``over`` (dotted path allowed).

    Each finished point is appended to ``sweep.csv`` at once.  A point that fails
    is recorded in ``results.json`` (``failed_points``) and, for scenes without
    their own continuation, the sweep goes on with the next value.  Returns the
    finished rows.

    Before the first point the folder is checked (the same sweep again is
    allowed; another scene's, a single run's or other parameters' or values'
    results are refused unless ``force``, as in :func:`run_scene`) and the
    manifest ``sweep.json`` (scene, parameters, ``sweep_parameter``,
    ``sweep_values``) is written.

    ``progress``: a :class:`~dolfinx_seal.output.Progress` told of every finished
    or failed point (the scene modules need not know it).

    ``resume``: go on with the sweep of the same scene, parameters and values in
    ``out_dir`` (a killed or failed one; :func:`~dolfinx_seal.output.resume_rows`
    refuses anything else): its ``sweep.csv`` rows are kept, the points not
    finished are solved and appended, and the returned rows are the old and the
    new ones.  A resumable scene (:attr:`Scene.resumable`) goes on from the
    checkpoint of its last converged point; the others start each remaining
    point afresh.

    ``point_files`` (``--point-files K``): which finished points get their own
    files from a scene that writes them (:func:`writes_point_files`).
    """
    point_files = _params.check_int_range("--point-files", point_files, 0)
    scene = get(name)
    out = Path(out_dir)
    set_parameter(parameters, over, _params.get_dotted(parameters, over))  # unknown names stop here
    for v in values:  # and values outside the parameter's range, before any point is run
        set_parameter(parameters, over, v)
    record = _params.to_dict(parameters)
    previous: list[dict[str, Any]] = []
    if resume:
        previous = resume_rows(out, name, record, over, list(values))
    else:
        check_out_dir(out, name, record, over=over, values=list(values), force=force)
    write_sweep_manifest(out, name, record, over, list(values))
    writer = SweepWriter(out, resume=resume)
    done: dict[float, int] = {}
    for r in previous:
        done[float(r[over])] = done.get(float(r[over]), 0) + 1
    state = Resume(rows=len(previous), done=done) if resume else None
    todo = list(values) if state is None else state.remaining(values)
    rows: list[dict[str, Any]] = list(previous)
    failed: list[dict[str, Any]] = []
    log = get_logger()
    if resume:
        log.info("resuming %s: %d of %d points finished before", out, len(previous), len(values))
        if progress is not None:
            progress.skip(len(values) - len(todo))
    t0 = time.perf_counter()

    def on_point(value: float, results: Mapping[str, Any]) -> bool:
        row = {over: value, **_scalars(results)}
        rows.append(row)
        writer.append(row)
        if progress is not None:
            progress.point(value, row)
        return writes_point_files(len(rows), len(values), point_files)

    if scene.sweep is not None and (todo or scene.resumable):
        try:
            if scene.resumable:
                scene.sweep(parameters, out, over, list(values), on_point, resume=state)
            else:
                scene.sweep(parameters, out, over, todo, on_point)
        except SolverError as e:
            failed.append({"error": str(e), "where": e.where})
            log.error("sweep stopped: %s", e)
    elif scene.sweep is None:
        for v in todo:
            p = set_parameter(parameters, over, v)
            pt0 = time.perf_counter()
            try:
                res = scene.run(p, out)
            except SolverError as e:
                failed.append({over: v, "error": str(e)})
                if progress is not None:
                    progress.failed(v, e.what)
                log.error("sweep point %s=%g failed: %s", over, v, e)
                continue
            res.setdefault("wall_time_s", time.perf_counter() - pt0)
            on_point(v, res)
    if scene.plot_sweep is not None and rows and world().rank == 0:
        scene.plot_sweep(rows, out, over)
    summary = {
        "scene": name,
        "parameters": _params.to_dict(parameters),
        "sweep_parameter": over,
        "sweep_values": list(values),
        "points_finished": len(rows),
        "failed_points": failed,
        "wall_time_s": time.perf_counter() - t0,
    }
    write_results(out, summary)
    return rows


def writes_point_files(finished: int, values: int, every: int) -> bool:
    """Whether a sweep's ``finished``-th point (from 1, resumed rows counted) of
    ``values`` gets its own files, with ``--point-files`` = ``every``.

    ``every`` = 1 (default): every point; ``K`` > 1: the first point, every K-th
    after it (1, 1 + K, 1 + 2K, ...) and the last value's (the ``values``-th
    finished point: every point before it finished); 0: none.  The sweep's own
    files (``sweep.csv``, ``sweep.png``, ``results.json``) are always written.  A
    film map costs about 1 s on rank 0 while the other ranks wait
    (docs/performance.md), which a Stribeck curve of many speeds need not pay at
    every speed.
    """
    if every == 0:
        return False
    return (finished - 1) % every == 0 or finished == values


def chain_values(values: Sequence[float], chains: int, order: str = "given") -> list[list[float]]:
    """The sweep values of each of ``chains`` chains: every ``chains``-th value of the
    walk order (``order``: ``up``, ``down`` or ``given``), so that every chain starts
    at the same end of the sweep (a lubricated sweep's start is cheapest there) and
    walks the whole range in ``chains`` times longer steps."""
    if order == "up-down":
        raise ParameterError(
            "--chains with sweep_order = 'up-down': a hysteresis loop is one chain "
            "(run it with --chains 1)",
            "sweep_order",
        )
    if order in ("up", "down"):
        walk = sorted(float(v) for v in values)
        walk = walk if order == "up" else walk[::-1]
    else:
        walk = [float(v) for v in values]
    return [walk[k::chains] for k in range(chains)]


def sweep_chains(
    name: str,
    parameters: Any,
    out_dir: str | Path,
    over: str,
    values: Sequence[float],
    chains: int,
    force: bool = False,
    resume: bool = False,
    unit: str = "",
    point_files: int = 1,
) -> list[dict[str, Any]]:
    """:func:`sweep_scene` as ``chains`` independent chains run at once, each on its
    own share of the ranks of :func:`~dolfinx_seal.mpi.world` (``mpirun -n N`` with
    ``chains = N``: one rank per chain).

    The values are dealt out by :func:`chain_values`; chain ``k`` (from 1) sweeps its
    values into ``out_dir/chain-k`` with its own start (its own ``results.json``,
    ``sweep.csv``, failures, checkpoint; ``resume`` goes on with each chain
    there), shows its progress as plain lines prefixed ``chain k/K``, and a chain
    that stops keeps its finished points.  When every chain has ended, ``out_dir``
    gets the merged ``sweep.csv`` (in the walk order), ``sweep_failures.csv``,
    the scene's sweep plot and ``results.json`` (``failed_points``, and per
    chain its ranks, values, points finished and wall time).  Returns the merged
    rows (values as written in the chains' CSV files) on every rank.
    ``point_files``: as in :func:`sweep_scene`, counted in each chain.
    """
    comm = world()
    chains = _params.check_int_range("--chains", chains, 1)
    if chains > comm.size:
        raise ParameterError(
            f"--chains = {chains}: at most one chain per rank, and there are "
            f"{comm.size} rank(s) (run under mpirun -n {chains} or more)",
            "--chains",
        )
    scene = get(name)
    out = Path(out_dir)
    set_parameter(parameters, over, _params.get_dotted(parameters, over))
    for v in values:
        set_parameter(parameters, over, v)
    lubricated_speed = scene.sweep is not None and over in ("speed", "film.speed")
    order = str(getattr(parameters, "sweep_order", "given")) if lubricated_speed else "given"
    shares = chain_values(values, chains, order)
    record = _params.to_dict(parameters)
    check_out_dir(out, name, record, over=over, values=list(values), force=force)
    write_sweep_manifest(out, name, record, over, list(values))
    color = comm.rank * chains // comm.size
    # never freed: PETSc objects of the chain's solves, collected later, keep using it
    sub = comm.Split(color, key=comm.rank)
    k = color + 1
    folder = out / f"chain-{k}"
    t0 = time.perf_counter()
    with using_comm(sub):
        go_on = resume and sub.bcast((folder / "sweep.json").is_file(), root=0)
        progress = Progress(len(shares[color]), over, unit, comm=sub, tty=False,
                            prefix=f"chain {k}/{chains}: ")  # fmt: skip
        with progress:
            sweep_scene(name, parameters, folder, over, shares[color], force=force,
                        progress=progress, resume=go_on, point_files=point_files)  # fmt: skip
    wall = time.perf_counter() - t0
    leader = sub.rank == 0
    info = comm.gather(
        {"chain": k, "ranks": comm.size // chains + (1 if color < comm.size % chains else 0),
         "values": shares[color], "wall_time_s": wall} if leader else None,
        root=0,
    )  # fmt: skip
    merged: list[dict[str, Any]] = []
    if comm.rank == 0:  # rank 0 alone merges what the chains wrote
        per_chain = [c for c in info if c is not None]
        failed: list[dict[str, Any]] = []
        not_reached: list[dict[str, Any]] = []
        for c in per_chain:
            got, lost, missed = _chain_output(out / f"chain-{c['chain']}")
            merged += got
            failed += [{**f, "chain": c["chain"]} for f in lost]
            not_reached += missed
            c["points_finished"] = len(got)
        position = {v: i for i, v in enumerate(chain_values(values, 1, order)[0])}
        merged.sort(key=lambda r: position.get(float(r[over]), len(position)))
        with using_comm(COMM_SELF):
            writer = SweepWriter(out)
            for r in merged:
                writer.append(r)
            write_sweep_failures(out, not_reached)
            if scene.plot_sweep is not None and merged:
                scene.plot_sweep(merged, out, over)
        summary_all = {
            "scene": name,
            "parameters": record,
            "sweep_parameter": over,
            "sweep_values": list(values),
            "points_finished": len(merged),
            "failed_points": failed,
            "chains": per_chain,
            "wall_time_s": time.perf_counter() - t0,
        }
        write_results(out, summary_all, comm=COMM_SELF)
    return comm.bcast(merged, root=0)


def _chain_output(folder: Path) -> tuple[list[dict[str, Any]], list[Any], list[dict[str, Any]]]:
    """What one chain of :func:`sweep_chains` left in ``folder``: its ``sweep.csv``
    rows (cells parsed), its failed points (``results.json``) and its continuation
    targets not reached (``sweep_failures.csv``)."""
    import json

    rows: list[dict[str, Any]] = []
    if (folder / "sweep.csv").is_file():
        rows = [{k: parse_cell(v) for k, v in r.items()} for r in read_csv(folder / "sweep.csv")]
    failed: list[Any] = []
    if (folder / "results.json").is_file():
        failed = json.loads((folder / "results.json").read_text()).get("failed_points", [])
    missed: list[dict[str, Any]] = []
    if (folder / "sweep_failures.csv").is_file():
        missed = [{"speed": float(r["speed"]), "error": r["error"]}
                  for r in read_csv(folder / "sweep_failures.csv")]  # fmt: skip
    return rows, failed, missed


def parse_values(spec: str) -> list[float]:
    """Sweep values from ``"a,b,c"`` or a range ``"start:stop:n"`` / ``"start:stop:n:log"``.

    Raises :class:`ParameterError` for anything else (no values, words, a bad range).
    """

    def number(text: str) -> float:
        try:
            return float(text)
        except ValueError:
            raise ParameterError(
                f"--values {spec!r}: {text.strip()!r} is not a number "
                "(give a,b,c or start:stop:n[:log])",
                "--values",
            ) from None

    if ":" in spec:
        parts = spec.split(":")
        if len(parts) not in (3, 4) or (len(parts) == 4 and parts[3] not in ("log", "lin")):
            raise ParameterError(f"--values range must be start:stop:n[:log], got {spec!r}")
        a, b = number(parts[0]), number(parts[1])
        n = _params.check_int_range("--values n", number(parts[2]), 1)
        if len(parts) == 4 and parts[3] == "log":
            if a <= 0 or b <= 0:
                raise ParameterError(f"--values log range needs positive ends, got {spec!r}")
            if n == 1:
                return [a]
            return [
                math.exp(math.log(a) + i * (math.log(b) - math.log(a)) / (n - 1)) for i in range(n)
            ]
        if n == 1:
            return [a]
        return [a + i * (b - a) / (n - 1) for i in range(n)]
    values = [number(s) for s in spec.split(",") if s.strip()]
    if not values:
        raise ParameterError(f"--values {spec!r} gives no values (a,b,c or start:stop:n[:log])")
    return values
