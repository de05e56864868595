"""The template of the lubricated-contact scenes (``cylinder``, ``ball``): one
implementation of the lubricated point, the dry point, the Stribeck sweep, their
results and their plots, over a few hooks that say what differs.

A scene module is its parameter dataclass plus the hooks of a
:class:`LubricatedScene`:

``scales(p) -> Scales``
    The Hertz sizes of the contact: half-width or radius ``a``, peak pressure,
    nominal area, Hertz approach, the symmetry factor of a half model, and the
    scalars the scene reports about them (``hertz_half_width``, ...).
``mesh(p, scales, comm) -> TaggedMesh``
    The mesh, with the groups ``contact`` and ``load`` (and ``symmetry`` for a
    half model: the film gets no flux across it).
``problem(p, mesh, scales, law, film, control) -> SolidContactProblem``
    The body, counter-surface, boundary conditions, Newton options and step
    limits; ``film`` is None for the dry problem.  The template builds the
    contact law (from ``p.contact``), the film (from ``p.film``, the Hertz
    scales and the roughness) and the control (:class:`~dolfinx_seal.solid.body.ForceControl`: ``p.load``
    over the symmetry factor; ``PositionControl``: given) and passes them in.
``start(problem, p, scales) -> solver figures``
    The first converged coupled state at ``p.film.speed`` (each scene has its
    own path there: boundary lubrication for the cylinder, full film for the ball).
``write_point(out, problem, p)``
    The per-point film profile or map.
``write_dry(out, problem, p, scales) -> extra results``
    The dry pressure profile (and any scalar only this scene reports).
``start_speed(p) -> speed`` (optional)
    Where the partitioned baseline starts (``p.solver = "partitioned"``).
``film_gap(p) -> gap`` (optional)
    The gap scale [m] of the film's rows and unknowns (default ``h_rms``): the
    film thickness the scene expects at its start, where that is far above
    ``h_rms`` (a smooth contact in full film).
``first_speed(p) -> speed`` (optional)
    The signed speed [m/s] at which the scene's ``start`` makes its first coupled
    solve for these parameters (it may differ from ``p.film.speed``: the start
    then walks there); the fallback chain of a failed start
    (:meth:`LubricatedScene.first_state`) uses it to try speeds where the start
    really begins elsewhere.  Without it, a failed start goes straight to load
    stepping.
``other_start(problem, p, scales) -> solver figures`` (optional)
    A start in another regime, walked to ``p.film.speed`` (the cylinder's full-film
    start, where its own begins in boundary lubrication): the fallback chain's
    second attempt.  It raises :class:`~dolfinx_seal.errors.ParameterError` where it
    does not apply.

What the template does with them, the same way for every scene: the parameters
must have ``load``, ``element_size`` (the contact element [m]), ``material``, ``roughness``, ``contact``,
``lubricated``, ``film``, ``sweep_order`` and ``stepping``; :meth:`run` picks the
lubricated or the dry point; the lubricated point reports
:func:`~dolfinx_seal.coupled.results.lubricated_results` with the Hertz and
law scalars and writes ``fields.xdmf``; the dry point starts from the Hertz
pressure (:func:`~dolfinx_seal.scenes.common.solve_dry`) and reports
:func:`dry_results`; the sweep walks ``film.speed`` with continuation.

The law and the film are built here, not in the ``problem`` hook, because
they are the same for every client (the law from ``p.contact`` at the Hertz
approach; the film scaled by the Hertz pressure and size, ``h_rms`` and the
contact element, with the roughness spectrum for the Persson flow factor); the
dry profile is a hook because the cylinder plots every contact node and the
ball the x axis only.  Why a dataclass of functions and not a base class: a scene then reads as
module-level functions with plain signatures (tests and benchmarks call
``build_lubricated`` / ``start_lubricated`` of a scene module, a benchmark may
patch the module's ``create_mesh``), and the template's own steps stay in one
place, not spread over ``super()`` calls.  The lubricated lip seal
(:mod:`dolfinx_seal.scenes.lip`) is not a client yet: its ``mesh`` step is the
dry installation and its scales come from the installed contact, its results
(leakage, torque) replace the Stribeck ones and it sweeps the oil pressure too;
docs/adding-a-scene.md says what the template would need for it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import ufl

from dolfinx_seal import checkpoint
from dolfinx_seal.contact.hertz import separation_of
from dolfinx_seal.coupled.continuation import order_speeds, speed_sweep
from dolfinx_seal.coupled.results import lubricated_results, write_fields
from dolfinx_seal.coupled.sweep import plot_sweep
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.film.surface import FilmParams, FilmScales, SurfaceFilm
from dolfinx_seal.meshing import TaggedMesh
from dolfinx_seal.mpi import get_logger, world
from dolfinx_seal.output import write_sweep_failures
from dolfinx_seal.params import set_parameter
from dolfinx_seal.scenes import PointCallback, Resume, Scene
from dolfinx_seal.scenes.common import solve_dry, write_profile
from dolfinx_seal.solid.body import ForceControl, PositionControl
from dolfinx_seal.solid.problem import SolidContactProblem
from dolfinx_seal.solvers import SNESOptions
from dolfinx_seal.solvers.adaptive import TimeBudget
from dolfinx_seal.surface import tractions

Results = dict[str, Any]


#: How the counter-surface is held (a load, or a position).
Control = ForceControl | PositionControl


@dataclass(frozen=True)
class Scales:
    """The Hertz sizes of a contact (SI).

    Attributes:
        length: Hertz half-width (line contact) or radius (point contact) a [m].
        pressure: Hertz peak pressure p_H [Pa].
        nominal_area: Nominal contact area: ``2 a`` per unit length [m] or
            ``pi a^2`` [m^2] (for ``contact_area_fraction``).
        approach: Hertz approach ``a^2 / R`` [m] (the ``stiff`` law's decay length).
        line: Line contact (the pressure depends on x only) or point contact.
        symmetry_factor: The model carries ``load / symmetry_factor`` (2: a half model).
        report: The scalars the scene reports about these sizes (results keys).
    """

    length: float
    pressure: float
    nominal_area: float
    approach: float
    line: bool
    symmetry_factor: float = 1.0
    report: Mapping[str, float] = field(default_factory=dict)

    def hertz_pressure(self, X: Any) -> Any:
        """The Hertz pressure [Pa] as UFL on the reference coordinates ``X``."""
        a, p = self.length, self.pressure
        if self.line:
            return p * ufl.sqrt(ufl.max_value(1.0 - (X[0] / a) ** 2, 0.0))
        return p * ufl.sqrt(ufl.max_value(1.0 - (X[0] ** 2 + X[1] ** 2) / a**2, 0.0))

    def hertz_profile(self, x: np.ndarray) -> np.ndarray:
        """The Hertz pressure [Pa] along the sliding axis at ``x`` [m]."""
        return self.pressure * (1.0 - (x / self.length) ** 2).clip(min=0.0) ** 0.5

    def peak_gap(self, law: Any, h_rms: float) -> float:
        """The separation [m] of ``law`` at the Hertz peak (``h_rms`` without a law)."""
        return separation_of(law, self.pressure) if law is not None else h_rms


def _time_budget(p: Any) -> TimeBudget:
    """The budget ``p.stepping.time_budget`` [s] (none for a scene without it), on
    the world's ranks, started now."""
    seconds = float(getattr(getattr(p, "stepping", None), "time_budget", 0.0) or 0.0)
    return TimeBudget(seconds, world() if seconds else None)


def film_snes(film: FilmParams, **options: Any) -> SNESOptions:
    """Newton options of a coupled film problem, by the cavitation model: the
    reduced-space VI for ``p >= 0``; for JFO's complementarity this project's
    fixed-pattern semismooth Newton with its steps projected onto the bounds
    (``SNESOptions.project_step``) and full steps (``line_search`` is ignored).

    Measured with PETSc's ``vinewtonssls`` before: the cylinder's JFO stability
    case took 870 Newton steps over eight decades of speed (610 at 1e-7 m/s, by a
    fallback start), the projected Newton 71, to the same mu and h_min; the
    ball's JFO start at 1 m/s converged only linearly (0.9 per step) with
    ``vinewtonssls`` and stalled with backtracking (docs/design.md)."""
    if film.cavitation == "jfo":
        options.update(snes_type="semismooth", project_step=True, line_search="basic")
    else:
        options.setdefault("snes_type", "vinewtonrsls")
    return SNESOptions(max_it=60, dtol=1e12, rtol=1e-11, **options)


def half_decades(start: float, target: float) -> list[float]:
    """Speeds [m/s] from ``min(start, target)`` up to ``target`` in steps of half a decade."""
    speeds = [min(target, start)]
    while speeds[-1] < target * (1 - 1e-12):
        speeds.append(min(target, speeds[-1] * 10**0.5))
    return speeds


@dataclass(frozen=True, repr=False)
class LubricatedScene:
    """A lubricated-contact scene: its name and parameters, and the hooks of the
    module docstring."""

    name: str
    summary: str
    parameters: type
    scales: Callable[[Any], Scales]
    mesh: Callable[[Any, Scales, Any], TaggedMesh]
    problem: Callable[..., SolidContactProblem]
    start: Callable[[SolidContactProblem, Any, Scales], Results]
    write_point: Callable[[Path, SolidContactProblem, Any], None]
    write_dry: Callable[[Path, SolidContactProblem, Any, Scales], Results]
    start_speed: Callable[[Any], float] | None = None
    film_gap: Callable[[Any], float] | None = None
    first_speed: Callable[[Any], float] | None = None
    other_start: Callable[[SolidContactProblem, Any, Scales], Results] | None = None

    def __repr__(self) -> str:
        return f"LubricatedScene({self.name!r})"

    @property
    def scene(self) -> Scene:
        """The :class:`~dolfinx_seal.scenes.Scene` of the registry."""
        return Scene(name=self.name, summary=self.summary, parameters=self.parameters,
                     run=self.run, sweep=self.sweep, plot_sweep=plot_sweep,
                     resumable=True)  # fmt: skip

    # ------------------------------------------------------------ building
    def _law(self, p: Any, s: Scales) -> tuple[Any, Results]:
        return p.contact.build(p.roughness, p.material.E_star, approach=s.approach)

    def _info(self, s: Scales, law: Any, law_info: Results) -> Results:
        return {**s.report, "contact_law": law.name if law is not None else "none", **law_info}

    def film(self, p: Any, tm: TaggedMesh, s: Scales, law: Any) -> SurfaceFilm:
        """The film on the contact group, scaled by the Hertz contact; a ``symmetry``
        group of the mesh is a no-flux edge."""
        h_rms = p.roughness.h_rms
        gap = self.film_gap(p) if self.film_gap is not None else h_rms
        sym = (tm.tag("symmetry"),) if "symmetry" in tm.info["facet_groups"] else ()
        return SurfaceFilm(
            p.film, FilmScales(pressure=s.pressure, length=s.length, gap=gap, element=p.element_size),
            h_rms=h_rms, rms_slope=getattr(law, "rms_slope", math.nan) if law is not None else math.nan,
            e_star=p.material.E_star, no_flux_tags=sym,
            psd=p.roughness.build() if p.film.flow_factor == "persson" else None,
        )  # fmt: skip

    def build_lubricated(
        self,
        p: Any,
        comm: Any = None,
        position: float | None = None,
        position0: float | None = None,
    ) -> tuple[SolidContactProblem, Results]:
        """The coupled problem (film on) and the scalars describing it.

        Args:
            p: Scene parameters.
            comm: Communicator (default :func:`dolfinx_seal.mpi.world`).
            position: None: force control (the counter-surface's position is an
                unknown); otherwise its final position [m] (position control, e.g.
                to check a parallel solution on one rank).
            position0: Start of the position ramp (default ``position``).
        """
        s = self.scales(p)
        law, law_info = self._law(p, s)
        tm = self.mesh(p, s, comm or world())
        if position is None:
            control: Control = ForceControl(p.load / s.symmetry_factor)
        else:
            control = PositionControl(position, position if position0 is None else position0)
        prob = self.problem(p, tm, s, law, self.film(p, tm, s, law), control)
        return prob, self._info(s, law, law_info)

    def build_dry(self, p: Any, comm: Any = None) -> tuple[SolidContactProblem, Results]:
        """The dry problem (no film unknowns, force control) and the scalars describing it."""
        s = self.scales(p)
        law, law_info = self._law(p, s)
        tm = self.mesh(p, s, comm or world())
        prob = self.problem(p, tm, s, law, None, ForceControl(p.load / s.symmetry_factor))
        return prob, self._info(s, law, law_info)

    def start_lubricated(self, prob: SolidContactProblem, p: Any) -> Results:
        """The first converged state at ``p.film.speed``: the scene's ``start`` hook,
        retried along the fallback chain (:meth:`first_state`)."""
        return self.first_state(prob, p, self.scales(p))

    def fallback_speeds(self, p: Any) -> list[float]:
        """Where a failed start is tried again [m/s], in order: the speeds a decade
        and two decades below and above the speed the scene's start begins at
        (:attr:`first_speed`), keeping only those at which the scene's start would
        begin somewhere it has not been tried (a rough cylinder starts at most at
        its boundary-lubrication speed, a smooth one at least at Moes M = 1, so half
        of them coincide).  None at zero speed, or for a scene without
        :attr:`first_speed`."""
        target = float(p.film.speed)
        if target == 0.0 or self.first_speed is None:  # at rest: no speed to continue from
            return []
        tried = [float(self.first_speed(p))]
        out: list[float] = []
        for k in (-1, 1, -2, 2):
            v = tried[0] * 10.0**k
            try:
                begins = float(self.first_speed(set_parameter(p, "film.speed", v)))
            except ParameterError:  # a speed the scene refuses
                continue
            if all(abs(begins / w - 1.0) > 1e-2 for w in tried):
                tried.append(begins)
                out.append(v)
        return out

    def first_state(self, prob: SolidContactProblem, p: Any, s: Scales) -> Results:
        """The scene's start, retried along the fallback chain before a failure is
        reported (docs/design.md, "Starts and their fallback chain"):

        1. the scene's ``start`` at the target speed ``p.film.speed``;
        2. the scene's :attr:`other_start` (a start in another regime, e.g. full
           film for a start that begins in boundary lubrication), if it has one;
        3. the scene's ``start`` from each of :meth:`fallback_speeds` (other speeds
           to begin at), then speed continuation to the target;
        4. adaptive load stepping from no load to the full load at the target
           speed, from the undeformed body (no Hertz guess).

        Each attempt starts from the state the problem was built with; once
        ``p.stepping.time_budget`` (if set) is spent, no further attempt is made,
        and the load stepping under way stops before its next step.  The
        returned record's ``strategy`` says which attempt converged, and
        ``start_attempts`` how many were made; if none converges, the
        :class:`SolverError` names what diverged in the first attempt, then lists
        every fallback attempt and why it failed."""
        target = float(p.film.speed)
        initial = prob.state()
        failures: list[tuple[str, SolverError]] = []
        t0 = time.perf_counter()
        spent = _time_budget(p).spent

        def reset(speed: float) -> None:
            prob.restore(initial)
            prob.film.set_speed(speed)
            prob.film.flow_factor_weight.value = 1.0
            prob.set_fraction(1.0)

        def done(info: Results, strategy: str | None = None) -> Results:
            info = dict(info)
            if strategy is not None:
                info["strategy"] = strategy
                info["newton_iterations"] = info.get("newton_iterations", 0) + sum(
                    e.history.newton_iterations for _, e in failures
                )
            info["start_attempts"] = len(failures) + 1
            info["solve_time_s"] = time.perf_counter() - t0
            return info

        try:
            return done(self.start(prob, p, s))
        except SolverError as e:
            failures.append((f"start at {target:g} m/s", e))
            get_logger().warning("%s: the start failed (%s); trying the fallback chain",
                                 self.name, e.what)  # fmt: skip

        if self.other_start is not None and not spent():
            reset(target)
            try:
                info = self.other_start(prob, p, s)
                return done(info, f"fallback: {info.get('strategy', 'other start')}")
            except ParameterError:  # not for these parameters
                pass
            except SolverError as e:
                failures.append((self.other_start.__name__.replace("_", " "), e))
        for v in self.fallback_speeds(p):
            if spent():
                break
            reset(v)
            try:
                info = self.start(prob, set_parameter(p, "film.speed", v), s)
                recs = speed_sweep(prob, [target], lambda *_: None, dict, p.stepping)
            except SolverError as e:
                failures.append((f"start at {v:g} m/s", e))
                continue
            if recs[-1].converged:
                info["newton_iterations"] += recs[-1].newton_iterations
                return done(info, f"fallback: start at {v:.3g} m/s, speed continuation to "
                            f"{target:.3g} m/s ({recs[-1].steps} steps)")  # fmt: skip
            failures.append((f"continuation from {v:g} m/s",
                             SolverError(recs[-1].error, where=f"{self.name} start")))  # fmt: skip
        reset(target)
        try:
            if why := spent():
                raise SolverError(f"not attempted: {why}")
            prob.steps.clear()
            prob.ramp(stop=spent)
            its = sum(r.newton_iterations for r in prob.steps)
            return done({"newton_iterations": its}, f"fallback: load stepping at {target:.3g} "
                        f"m/s ({len(prob.steps)} steps)")  # fmt: skip
        except SolverError as e:
            failures.append(("load stepping", e))
        reset(target)
        first = failures[0][1]
        raise SolverError(
            f"{first.what}, and no fallback start converged either ({len(failures) - 1} "
            "more attempts: "
            + "; ".join(f"({i}) {how}: {e}" for i, (how, e) in enumerate(failures[1:], 2))
            + ")",
            where=f"{self.name} start at {target:g} m/s",
            history=first.history,
        )

    def partitioned_start(self, prob: SolidContactProblem, p: Any, s: Scales) -> Results:
        """The seeds' partitioned scheme from the Hertz-deformed shape, half a decade
        per step from the scene's start speed (:func:`~dolfinx_seal.coupled.partitioned.partitioned_start`)."""
        from dolfinx_seal.coupled.partitioned import partitioned_start

        if self.start_speed is None:
            raise ParameterError(f"solver = 'partitioned': scene {self.name!r} has no start speed")
        guess = s.hertz_pressure(prob.X)
        gap = s.peak_gap(prob.law, p.roughness.h_rms)
        speeds = half_decades(self.start_speed(p), p.film.speed)
        return partitioned_start(prob, guess, gap, speeds, p.relaxation)

    # ------------------------------------------------------------ points
    def run(self, p: Any, out: Path) -> Results:
        """Solve one point (lubricated or dry); write its files; return the results."""
        return self.run_lubricated(p, out) if p.lubricated else self.run_dry(p, out)

    def run_lubricated(self, p: Any, out: Path) -> Results:
        """One lubricated point at ``film.speed``: results, the scene's profile or map,
        ``fields.xdmf``."""
        t0 = time.perf_counter()
        s = self.scales(p)
        prob, info = self.build_lubricated(p)
        try:
            if getattr(p, "solver", "monolithic") == "partitioned":
                solve_info = self.partitioned_start(prob, p, s)
            else:
                solve_info = self.first_state(prob, p, s)
            res = lubricated_results(prob, symmetry_factor=s.symmetry_factor,
                                     nominal_area=s.nominal_area)  # fmt: skip
            res.update(info)
            res.update(solve_info)
            res.update(dofs=prob.dofs, dof_counts=prob.dof_counts(), ranks=world().size,
                       wall_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
            self.write_point(out, prob, p)
            write_fields(out, prob)
        finally:
            prob.destroy()
        return res

    def run_dry(self, p: Any, out: Path) -> Results:
        """The dry point: Hertz warm start, then load stepping if needed
        (:func:`~dolfinx_seal.scenes.common.solve_dry`); the scene's pressure profile."""
        t0 = time.perf_counter()
        s = self.scales(p)
        prob, info = self.build_dry(p)
        try:
            solve_info = solve_dry(prob, s.hertz_pressure(prob.X), s.pressure)
            res = dry_results(prob, prob.target, line=s.line, symmetry_factor=s.symmetry_factor)
            res.update(solve_info)
            res.update(info)
            res.update(dofs=prob.dofs, ranks=world().size,
                       wall_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
            res.update(self.write_dry(out, prob, p, s))
            write_fields(out, prob)
        finally:
            prob.destroy()
        return res

    # ------------------------------------------------------------ sweep
    def sweep(
        self,
        p: Any,
        out: Path,
        name: str,
        values: list[float],
        on_point: PointCallback,
        resume: Resume | None = None,
    ) -> list[Results]:
        """Stribeck sweep over ``film.speed`` (``--over speed`` or ``film.speed``).

        Start at the first speed of the list ordered by ``p.sweep_order``, walk
        the others with :func:`~dolfinx_seal.coupled.continuation.speed_sweep`
        (options ``p.stepping``), hand each converged point to ``on_point`` at once
        (``sweep.csv``) and write its profile into ``speed_<U>/`` when that returns
        true (``--point-files``); failed targets
        go to ``sweep_failures.csv`` and the walk goes on from the last good point.
        Returns the rows of the converged points.  A failure the continuation
        cannot absorb (the start) raises :class:`SolverError` with ``partial`` = the
        finished rows (``name`` added).

        Each converged state is checkpointed (:mod:`dolfinx_seal.checkpoint`)
        before its row is written.  With ``resume`` (the rows already in
        ``sweep.csv``), the walk goes on from the checkpoint of the last
        converged point; without a usable one (none, other ranks or mesh), the
        targets not finished are walked afresh from the scene's start.  The
        checkpoint is removed when the sweep ends.
        """
        if name not in ("speed", "film.speed"):
            raise ParameterError(f"lubricated sweeps run over film.speed (got --over {name!r})")
        if not p.lubricated:
            raise ParameterError("lubricated = false: a speed sweep needs the film")
        ordered = order_speeds(values, p.sweep_order)
        walk = _Walk(self, p, out, ordered, on_point)
        try:
            if resume is not None and walk.from_checkpoint(resume):
                walk.go_on()
            else:
                todo = list(range(len(ordered))) if resume is None else resume.positions(ordered)
                if todo:
                    walk.from_start(todo)
        except SolverError as e:  # the sweep cannot go on: hand back the finished rows
            if e.partial is None:
                e.partial = [{name: v, **r} for v, r in zip(walk.done, walk.rows, strict=True)]
            raise
        finally:
            walk.close()
        walk.write_failures()
        checkpoint.remove(out)
        return walk.rows


class _Walk:
    """One speed-continuation chain of :meth:`LubricatedScene.sweep`: its problem,
    rows, failures and checkpoints."""

    def __init__(self, scene: LubricatedScene, p: Any, out: Path, ordered: list[float],
                 on_point: PointCallback) -> None:  # fmt: skip
        self.scene, self.p, self.out, self.ordered, self.on_point = scene, p, out, ordered, on_point
        self.prob: SolidContactProblem | None = None
        self.s: Scales | None = None
        self.rows: list[Results] = []
        self.done: list[float] = []
        self.failed: list[dict[str, Any]] = []  # {"speed", "error"}
        self.index = -1  # position in ``ordered`` of the last point handed on
        self.pending: list[int] = []  # positions in ``ordered`` still to walk, in order
        self.csv_rows = 0  # rows in sweep.csv (before this run, and written since)
        self.first_error = ""  # why the start at the walk's first target failed, if it did
        self.first_target = math.nan  # that target [m/s]
        self.reverse = False  # walking the targets from the last to the first

    def build(self, speed: float) -> SolidContactProblem:
        p0 = set_parameter(self.p, "film.speed", speed)
        self.s = self.scene.scales(p0)
        self.prob, _ = self.scene.build_lubricated(p0)
        return self.prob

    def results(self) -> Results:
        assert self.prob is not None and self.s is not None
        r = lubricated_results(self.prob, symmetry_factor=self.s.symmetry_factor,
                               nominal_area=self.s.nominal_area)  # fmt: skip
        r.update(dofs=self.prob.dofs, ranks=world().size)
        return r

    @property
    def unknowns(self) -> list[Any]:
        assert self.prob is not None
        return [b[1] for b in self.prob.blocks]

    def point(self, v: float, r: Results) -> None:
        """A converged target: checkpoint, then the row, then its profile."""
        assert self.prob is not None
        while self.ordered[self.pending[0]] != v:  # targets passed over: not reached
            self.pending.pop(0)
        self.index = self.pending.pop(0)
        self.csv_rows += 1
        meta = {"serial": self.csv_rows, "rows": self.csv_rows, "index": self.index,
                "speed": v, "failed": self.failed, "reverse": self.reverse,
                "first_error": self.first_error, "first_target": self.first_target}  # fmt: skip
        checkpoint.save(self.out, self.unknowns, meta)
        self.rows.append(r)
        self.done.append(v)
        if self.on_point(v, r):
            self.scene.write_point(self.out / f"speed_{v:.3e}", self.prob,
                                   set_parameter(self.p, "film.speed", v))  # fmt: skip

    def failure(self, rec: Any) -> None:
        self.failed.append({"speed": rec.speed, "error": self._why(rec)})

    def _why(self, rec: Any) -> str:
        """A target's failure, with the failed start's error for the walk's first
        target when the walk came back to it from the other end."""
        if self.first_error and rec.speed == self.first_target:
            return f"{rec.error} (from the other end; before that, {self.first_error})"
        return str(rec.error)

    def from_start(self, todo: list[int]) -> None:
        """The scene's start at the first target of ``todo`` (positions in the walk),
        then the others.

        If that start fails along the scene's whole fallback chain and there are
        other targets, the walk starts again from its other end (the last target of
        ``todo``) and walks the targets in reverse order, the first one last: a
        sweep that cannot begin at one end of its range (a very soft or a very
        smooth contact at boundary-lubrication speeds) still delivers every point
        the other end reaches, and the first target is recorded as not reached,
        with the start's error, unless the reverse walk gets there.  Both starts
        failing raises :class:`SolverError` naming both; so does a first start
        that spent ``stepping.time_budget``, without trying the other end."""
        spent = _time_budget(self.p).spent
        try:
            self._start_at(todo)
            self.go_on()
            return
        except SolverError as e:
            if len(todo) < 2 or self.rows:  # the start converged: a failure of the walk
                raise
            first = e
        v0, v1 = self.ordered[todo[0]], self.ordered[todo[-1]]
        if why := spent():
            raise SolverError(
                f"{first.what}; the start at the other end, {v1:g} m/s, was not attempted: {why}",
                where=f"{self.scene.name} sweep start at {v0:g} m/s",
                history=first.history,
            ) from first
        get_logger().warning(
            "%s sweep: the start at %g m/s failed (%s); starting from the other end, %g m/s, "
            "and walking back", self.scene.name, v0, first.what, v1,
        )  # fmt: skip
        self.close()
        self.prob = None
        self.first_error = f"the start at {v0:g} m/s failed: {first}"
        self.first_target = v0
        self.reverse = True
        try:
            self._start_at(todo[::-1])
        except SolverError as e:
            if self.rows:
                raise
            raise SolverError(
                f"the start failed at both ends of the sweep: at {v0:g} m/s: {first}; "
                f"at {v1:g} m/s: {e}",
                where=f"{self.scene.name} sweep start",
                history=first.history,
            ) from e
        self.go_on()

    def _start_at(self, todo: list[int]) -> None:
        """The scene's start at the first target of ``todo``, its point handed on."""
        v0 = self.ordered[todo[0]]
        prob = self.build(v0)
        p0 = set_parameter(self.p, "film.speed", v0)
        t0 = time.perf_counter()
        start = self.scene.first_state(prob, p0, self.scales)
        r0 = self.results()
        r0.update(newton_iterations=start["newton_iterations"], continuation_steps=1,
                  film_presolve_iterations=start.get("film_presolve_iterations", 0),
                  start_attempts=start.get("start_attempts", 1),
                  strategy=start.get("strategy", ""),
                  wall_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
        self.pending = list(todo)
        self.point(v0, r0)

    @property
    def scales(self) -> Scales:
        assert self.s is not None
        return self.s

    def from_checkpoint(self, resume: Resume) -> bool:
        """Restore the last converged state of the run being resumed; False if there
        is no usable checkpoint (the caller then starts afresh)."""
        meta = checkpoint.read_meta(self.out)
        if meta is None:
            return False
        idx, rows = int(meta["index"]), int(meta["rows"])
        if not (0 <= idx < len(self.ordered) and self.ordered[idx] == float(meta["speed"])
                and resume.rows in (rows, rows - 1)):  # fmt: skip
            get_logger().warning(
                "checkpoint not used: it is of point %d at %g m/s with %d rows, sweep.csv has "
                "%d rows", idx, float(meta["speed"]), rows, resume.rows,
            )  # fmt: skip
            return False
        prob = self.build(self.ordered[idx])
        if checkpoint.load(self.out, self.unknowns) is None:
            prob.destroy()
            self.prob = None
            return False
        prob.set_fraction(1.0)
        prob.film.flow_factor_weight.value = 1.0
        prob.film.set_speed(self.ordered[idx])
        self.failed = list(meta.get("failed", []))
        self.csv_rows = resume.rows
        self.reverse = bool(meta.get("reverse", False))
        self.first_error = str(meta.get("first_error", ""))
        self.first_target = float(meta.get("first_target", math.nan))
        if self.reverse:  # the walk went from the last target back to the first
            self.index = idx + 1 if resume.rows < rows else idx
            self.pending = list(range(self.index - 1, -1, -1))
        else:
            self.index = idx - 1 if resume.rows < rows else idx
            self.pending = list(range(self.index + 1, len(self.ordered)))
        get_logger().info("resuming from the checkpoint of %g m/s (point %d of %d)",
                          self.ordered[idx], idx + 1, len(self.ordered))  # fmt: skip
        return True

    def go_on(self) -> None:
        """Walk the remaining targets from the current converged state."""
        assert self.prob is not None
        targets = [self.ordered[i] for i in self.pending]
        recs = speed_sweep(self.prob, targets, self.point, self.results, self.p.stepping,
                           on_failure=self.failure)  # fmt: skip
        self.failed += [{"speed": r.speed, "error": self._why(r)} for r in recs
                        if not r.converged and r.error.startswith("not attempted")]  # fmt: skip

    def close(self) -> None:
        if self.prob is not None:
            self.prob.destroy()

    def write_failures(self) -> None:
        """``sweep_failures.csv``: the targets not reached (this run and the one resumed)."""
        write_sweep_failures(self.out, self.failed)


def write_dry_profile(
    out: Path, s: Scales, title: str, x: np.ndarray, p_contact: np.ndarray, **columns: np.ndarray
) -> None:
    """``pressure.csv`` (``x_m``, ``p_contact_Pa``, ``columns``, ``p_hertz_Pa``) and
    ``pressure.png``: the dry contact pressure [Pa] along the sliding axis ``x`` [m]
    against Hertz."""
    hz = s.hertz_profile(x)
    write_profile(
        out, "pressure", {"x_m": x, "p_contact_Pa": p_contact, **columns, "p_hertz_Pa": hz},
        title=title, xlabel="x [mm]", ylabel="contact pressure [MPa]",
        curves={"FEM": (x * 1e3, p_contact / 1e6), "Hertz": (x * 1e3, hz / 1e6)},
    )  # fmt: skip


def dry_results(
    prob: SolidContactProblem, target: float, line: bool, symmetry_factor: float = 1.0
) -> Results:
    """Load, moment-based contact size, peak pressure and load balance of a dry solve.

    The size is exact for a Hertz distribution: the half-width ``a = 2 <x^2>^(1/2)``
    (line) or the radius ``a = (5 <r^2> / 2)^(1/2)`` (point), moments of the
    contact force.  ``symmetry_factor`` multiplies integrals over a symmetric half
    model; ``target`` is the model's load [N/m or N].
    """
    fn = -prob.p_cont * ufl.dot(tractions.nanson_normal(prob.F, prob.N3), prob.e_n) * prob.weight
    M0 = prob.integrate(fn, prob.ds_c)
    x = prob.x
    r2 = x[0] ** 2 if line else x[0] ** 2 + x[1] ** 2
    M2 = prob.integrate(fn * r2, prob.ds_c)
    _, p = prob.surface_values(prob.p_cont, average=True)
    load = symmetry_factor * M0
    out = {
        "normal_load": load,
        "load_contact": load,
        "max_contact_pressure": float(p.max()),
        "load_balance_error": abs(M0 - target) / target,
        "counter_position": prob.counter_position(),
    }
    if line:
        out["contact_half_width"] = 2.0 * math.sqrt(M2 / M0)  # Hertz: <x^2> = a^2/4
    else:
        out["contact_radius"] = math.sqrt(2.5 * M2 / M0)  # Hertz: <r^2> = 2 a^2 / 5
    return out


__all__ = [
    "Control",
    "LubricatedScene",
    "Scales",
    "dry_results",
    "film_snes",
    "half_decades",
    "write_dry_profile",
]
