"""Continuation in speed for lubricated contacts (Stribeck sweeps).

Newton steps per point stay bounded when each point starts from the previous
converged state and the speed changes by a bounded factor (docs/design.md,
solver strategy).  :func:`speed_sweep` walks the requested speeds in log steps of at
most :attr:`SpeedStepping.max_decades`; a failed step restores the last
converged state and halves the step; below :attr:`SpeedStepping.min_decades`
the target point is recorded as failed and the sweep goes on to the next one
from the last good state.  Every converged target is handed to ``on_point``
at once, so finished points are never lost.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from mpi4py import MPI

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.output import progress_step
from dolfinx_seal.params import check_int_range, check_nonnegative, check_positive, check_range
from dolfinx_seal.solvers.adaptive import AdaptiveWalk, StepControl, TimeBudget

#: The first step [decades] of a target's second walk without the Newton limit
#: (:func:`speed_sweep`).  The first second walk of the S1 ball on a/10 began with the
#: full step to its target, from 0.019 to 0.01 m/s: 60 Newton steps, 4.5 minutes, failed.
RETRY_DECADES = 0.02


@dataclass(frozen=True)
class SpeedStepping:
    """Speed continuation options.

    Attributes:
        max_decades: Largest speed change of one continuation step [decades].
        min_decades: Smallest step before a target is given up [decades].
        grow: Step growth after an easy step.
        easy: Newton steps counted as easy.
        predictor: Start each step from the secant extrapolation (in log speed)
            of the last two converged states.
        max_newton: Newton steps allowed to one continuation step (0: the
            solver's own limit); a step that needs more is cut like a failed
            one.  With the exact Jacobian a step converges in 3-5; a doomed one
            otherwise runs to the solver's limit (60 on the lubricated scenes).
        stall_steps: A continuation step also fails once this many consecutive
            Newton steps have each lowered the residual by less than 1 % (0:
            never; :meth:`~dolfinx_seal.solvers.NonlinearSolver.newton_limit`).
            A converging step lowers it by decades a step; one stuck at a
            residual plateau otherwise runs on to ``max_newton``.
        tangent: With ``predictor``, start each step from the tangent of the
            solution path instead (:func:`tangent_predictor`; also on the first
            step, where no secant exists yet): two residuals and one linear solve,
            by the last factorisation of the converged solve where the solver
            keeps one (the reduced-space VI through the full pattern), else with
            a new Jacobian and LU.
        max_failures: Stop a sweep after this many consecutive targets not
            reached (0: never); the remaining targets are recorded as not attempted.
            Walking down into boundary lubrication, the next lower target fails
            too and costs as much again.
        film_presolve: Before each coupled step, solve the film and the counter
            position on the predicted (frozen) shape (:func:`film_presolve`).  The
            reduced-space VI frees one bound node per Newton step, so a cavitation
            front that must move n nodes costs n coupled steps, and n grows as the
            mesh is refined; the film-only steps that move it here cost about a
            twentieth of a coupled step.
        time_budget: Wall time of one sweep's walk [s] (0: none); once spent, the
            walk stops before its next continuation step: the target under way is
            recorded as failed ("stopped at ... m/s: the time budget ... was
            spent") and the targets not yet walked to as not attempted.
    """

    max_decades: float = 0.5
    min_decades: float = 0.005
    grow: float = 1.5
    easy: int = 8
    predictor: bool = True
    max_newton: int = 0
    stall_steps: int = 0
    tangent: bool = True
    max_failures: int = 0
    film_presolve: bool = True
    time_budget: float = 0.0

    def __post_init__(self) -> None:
        check_range("max_decades", self.max_decades, 0.0, 3.0, lo_open=True)
        check_positive("min_decades", self.min_decades)
        check_range("grow", self.grow, 1.0, 4.0)
        check_int_range("easy", self.easy, 1)
        check_int_range("max_failures", self.max_failures, 0)
        check_int_range("max_newton", self.max_newton, 0)
        check_int_range("stall_steps", self.stall_steps, 0)
        check_nonnegative("time_budget", self.time_budget, unit="s")

    def control(self) -> StepControl:
        """The step control of the walk in log10 |speed| (a failed target resets the
        step to :attr:`max_decades`)."""
        return StepControl(
            first=self.max_decades, grow=self.grow, easy=self.easy, cut=0.5,
            min_step=self.min_decades, max_step=self.max_decades, reset_step=self.max_decades,
        )  # fmt: skip


@dataclass
class SweepRecord:
    """What happened on the way to one target speed."""

    speed: float
    converged: bool
    newton_iterations: int = 0
    film_iterations: int = 0
    steps: int = 0
    wall_time_s: float = 0.0
    error: str = ""
    intermediate: list[float] = field(default_factory=list)


def speed_sweep(
    prob: Any,
    speeds: Sequence[float],
    on_point: Callable[[float, dict[str, Any]], None],
    results: Callable[[], dict[str, Any]],
    stepping: SpeedStepping | None = None,
    on_failure: Callable[[SweepRecord], None] | None = None,
) -> list[SweepRecord]:
    """Solve ``prob`` (with a film) at each speed of ``speeds`` in the given order.

    The problem must hold a converged state at its current speed.  Returns one
    record per target; ``on_point(speed, results())`` is called for each
    converged target, ``on_failure(record)`` (if given) for each target not reached.
    """
    st = stepping or SpeedStepping()
    for target in speeds:
        if not (math.isfinite(target) and target != 0.0):
            raise ParameterError(f"film.speed = {target!r} m/s: a sweep target must be non-zero")
    # a chain keeps one sign (a rod's out-stroke or in-stroke): steps in log |speed|
    signs = {math.copysign(1.0, float(t)) for t in speeds} | {
        math.copysign(1.0, float(prob.film.speed.value))
    }
    if len(signs) > 1:
        raise ParameterError(
            "film.speed: a continuation chain cannot change the sliding direction; "
            "sweep each direction from its own start"
        )
    presolver = FilmPresolver(prob) if st.film_presolve else None
    try:
        return _walk(prob, speeds, on_point, results, st, presolver, signs.pop(), on_failure)
    finally:
        if presolver is not None:
            presolver.destroy()


def _walk(
    prob: Any,
    speeds: Sequence[float],
    on_point: Callable[[float, dict[str, Any]], None],
    results: Callable[[], dict[str, Any]],
    st: SpeedStepping,
    presolver: FilmPresolver | None,
    sign: float,
    on_failure: Callable[[SweepRecord], None] | None = None,
) -> list[SweepRecord]:
    """The target loop of :func:`speed_sweep`: one adaptive walk in log10 |speed|
    (:class:`~dolfinx_seal.solvers.adaptive.AdaptiveWalk`) carried from target to target."""
    film = prob.film
    log = get_logger()
    records: list[SweepRecord] = []
    rec = SweepRecord(speed=0.0, converged=False)

    step_options = [st]  # the Newton limit is lifted for a target's second walk

    def solve(speed: float) -> int:
        return _coupled_step(prob, walker.history, speed, step_options[0], presolver,
                             rec).newton_iterations  # fmt: skip

    walker = AdaptiveWalk(
        st.control(), film.set_speed, solve, prob.state, prob.restore,
        coordinate=AdaptiveWalk.log_speed(sign), name=f"{prob.name} speed continuation",
        on_accept=lambda v, _its: progress_step(f"{prob.name} speed [m/s]", v),
    )  # fmt: skip
    failures = 0
    spent = TimeBudget(st.time_budget, prob.mesh.comm if st.time_budget else None).spent

    for i, target in enumerate(speeds):
        note = ""
        if st.max_failures and failures >= st.max_failures:
            note = f"not attempted: stopped after {failures} consecutive failed target(s)"
        elif why := spent():
            note = f"not attempted: {why}"
        if note:
            records += [
                SweepRecord(speed=float(t), converged=False, error=note) for t in speeds[i:]
            ]
            log.error("sweep stopped at %.4g m/s: %s", float(film.speed.value), note)
            break
        rec = SweepRecord(speed=float(target), converged=False)
        t0 = time.perf_counter()
        res = walker.walk(float(film.speed.value), float(target), stop=spent)
        its, steps, accepted = res.newton_iterations, res.steps, list(res.accepted)
        if not res.converged and not res.stopped and (st.max_newton or st.stall_steps):
            # the Newton limit buys speed on easy steps; a target it stalls is walked
            # once more from where the walk stopped, with the solver's own limit
            # (and no stall rule)
            log.info("speed %.4g m/s not reached with %d Newton steps a step (%s); again "
                     "from %.4g m/s with the solver's own limit", target, st.max_newton,
                     res.last_error.what if res.last_error else "", float(film.speed.value))  # fmt: skip
            step_options[0] = dataclasses.replace(st, max_newton=0, stall_steps=0)
            # from a short step: the walk has just shown that long ones do not converge,
            # and each failure now costs the solver's full limit
            walker.step = max(RETRY_DECADES, 2.0 * st.min_decades)
            try:
                res = walker.walk(float(film.speed.value), float(target), stop=spent)
            finally:
                step_options[0] = st
            its, steps = its + res.newton_iterations, steps + res.steps
            accepted += list(res.accepted)
        rec.converged = res.converged
        rec.newton_iterations = its
        rec.steps = steps
        rec.intermediate = [a.value for a in accepted if a.value != float(target)]
        if res.stopped:
            rec.error = f"stopped at {float(film.speed.value):.4g} m/s: {res.error}"
        elif not res.converged and res.last_error is not None:
            rec.error = f"{res.last_error.what} ({res.last_error.where})"
        rec.wall_time_s = time.perf_counter() - t0
        records.append(rec)
        failures = 0 if rec.converged else failures + 1
        if rec.converged:
            out = results()
            out.update(
                newton_iterations=rec.newton_iterations,
                film_presolve_iterations=rec.film_iterations,
                continuation_steps=rec.steps,
                wall_time_s=rec.wall_time_s,
                converged=True,
            )
            on_point(float(target), out)
        else:
            log.error("speed %.4g m/s not reached: %s; going on from %.4g m/s",
                      target, rec.error, float(film.speed.value))  # fmt: skip
            if on_failure is not None:
                on_failure(rec)
    return records


def _coupled_step(
    prob: Any,
    history: Sequence[tuple[float, list[Any]]],
    speed: float,
    st: SpeedStepping,
    presolver: FilmPresolver | None,
    rec: SweepRecord,
) -> Any:
    """One continuation step to ``speed`` from the last converged state (the last of
    ``history``): the predictor, the film presolve (if any), the coupled Newton.  A
    coupled solve that fails after the film presolve is retried once from the
    predictor alone (on the S1 ball the presolved film is a state the coupled Newton
    cannot start from).  Returns the solve history; raises :class:`SolverError` if
    the step failed."""
    with prob.solver.newton_limit(st.max_newton, st.stall_steps):
        return _step(prob, history, speed, st, presolver, rec)


def _step(prob: Any, history: Sequence[tuple[float, list[Any]]], speed: float,
          st: SpeedStepping, presolver: FilmPresolver | None, rec: SweepRecord) -> Any:  # fmt: skip
    """:func:`_coupled_step` under its Newton limit."""
    where = f"{prob.name} at speed {speed:.4g} m/s"
    tangent = None
    if st.predictor and st.tangent and history:  # at the last converged speed
        tangent = path_tangent(prob, math.copysign(10.0 ** history[-1][0], speed))
    _predict(prob, history, speed, st, tangent)
    try:
        if presolver is None:
            return prob.solver.solve(where=where)
        rec.film_iterations += presolver.solve(where)
        try:
            return prob.solver.solve(where=where)
        except SolverError as e:
            get_logger().info("step to %.4g m/s after the film presolve failed (%s); "
                              "again without it", speed, e.what)  # fmt: skip
            prob.restore(history[-1][1])
            _predict(prob, history, speed, st, tangent)
            return prob.solver.solve(where=where)
    finally:
        if tangent is not None:
            tangent[1].destroy()


def _predict(prob: Any, history: Sequence[tuple[float, list[Any]]], speed: float,
             st: SpeedStepping, tangent: tuple[float, Any] | None) -> None:  # fmt: skip
    """The predictor of a continuation step from the last converged state (the
    current one): the tangent's if computed, else the secant's when two states
    are known, else none."""
    if tangent is not None:
        tangent_predictor(prob, tangent, speed)
    elif st.predictor and len(history) == 2:
        secant_predictor(prob, history, speed)


TANGENT_DELTA = 1e-4  # relative speed change of the residual's finite difference


def path_tangent(prob: Any, speed: float) -> tuple[float, Any]:
    """``(speed, t)``: the tangent ``t = dx / d ln|U|`` of the solution path at the
    current state, converged at ``speed`` U [m/s] (:meth:`NonlinearSolver.tangent
    <dolfinx_seal.solvers.NonlinearSolver.tangent>`), with the residual's derivative
    from a one-sided difference in ``ln|U|`` (:data:`TANGENT_DELTA`; the residual is
    linear in U but for the film rows' speed-dependent weight, whose derivative
    multiplies the converged residual).  The film's speed is left as it was (the
    step's target).  The caller destroys ``t``."""
    film, solver = prob.film, prob.solver
    current = float(film.speed.value)
    try:
        film.set_speed(speed)
        F0 = solver.residual()
        film.set_speed(speed * (1.0 + TANGENT_DELTA))
        dF = solver.residual()
        film.set_speed(speed)
        # the Jacobian of the tangent is assembled by tangent() at this speed
        dF.axpy(-1.0, F0)
        dF.scale(1.0 / math.log1p(TANGENT_DELTA))
        F0.destroy()
        try:
            return speed, solver.tangent(dF)
        finally:
            dF.destroy()
    finally:
        film.set_speed(current)


def tangent_predictor(prob: Any, tangent: tuple[float, Any], speed: float) -> None:
    """Set ``prob``'s state to the first-order prediction ``x + ln(|speed| / |U|) t``
    from the converged state at ``U`` along its :func:`path_tangent`, shortened to
    the problem's gap-closure rule like :func:`secant_predictor`."""
    v0, t = tangent
    saved = prob.state()
    prob.solver.add_to_unknowns(t, math.log(abs(speed) / abs(v0)))
    pred = prob.state()
    closure = prob.limits.max_gap_closure
    if closure:
        pred = _safeguard_predictor(prob, saved, pred, closure)
    prob.restore(pred)


def secant_predictor(prob: Any, history: Sequence[tuple[float, list[Any]]], speed: float) -> None:
    """Set ``prob``'s state to the secant extrapolation, in log10 speed, of the two
    converged ``(log10 speed, state)`` in ``history`` to ``speed`` [m/s] (the current
    state is the last of them).  With a Newton gap-closure rule on the problem the
    predictor is shortened to obey it (:func:`_safeguard_predictor`)."""
    (la, sa), (lb, sb) = history
    r = (math.log10(abs(speed)) - lb) / (lb - la)
    pred = [b + r * (b - a) for a, b in zip(sa, sb, strict=True)]
    closure = prob.limits.max_gap_closure
    if closure:
        pred = _safeguard_predictor(prob, prob.state(), pred, closure)
    prob.restore(pred)


def _safeguard_predictor(
    prob: Any, saved: list[Any], pred: list[Any], closure: float, tries: int = 6
) -> list[Any]:
    """Shorten a secant predictor until every film gap obeys the rule of the problem's
    Newton step limiter: it shrinks by at most the fraction ``closure`` and grows by at
    most the factor ``1 / (1 - closure)``, or changes by at most ``max_gap_step``.
    A straight extrapolation of the state closes the thin exit film of the 3D ball
    (its gap halves per half decade of speed) and leaves Newton a residual 1e4
    times the converged one."""
    g0 = np.maximum(prob.film.owned_gaps(), 0.0)
    allowed = np.maximum(closure * g0, prob.limits.max_gap_step or 0.0)
    grown = np.maximum(closure / (1.0 - closure) * g0, allowed)
    comm = prob.mesh.comm
    scale = 1.0
    for _ in range(tries):
        trial = [s + scale * (p - s) for s, p in zip(saved, pred, strict=True)]
        prob.restore(trial)
        dg = prob.film.owned_gaps() - g0
        ok = bool(np.all((-dg <= allowed) & (dg <= grown)))
        if comm.allreduce(ok, op=MPI.LAND):
            return trial
        scale *= 0.5
    return saved


def reynolds_presolve(prob: Any, where: str = "") -> int:
    """For a JFO or full-Sommerfeld film: solve the problem with the film fraction
    (JFO) frozen at 1 and the Reynolds condition ``p >= 0`` (``vinewtonrsls``), a
    start for the mass-conserving solve (the semismooth JFO Newton fails from a
    dry state) or the one without cavitation.  Returns the Newton steps."""
    from dolfinx_seal.solvers import NonlinearSolver, with_snes_type

    film = prob.film
    theta = film.theta_fn if film.has_theta else None
    if theta is not None:
        theta.x.array[:] = 1.0
    blocks = [b for b in prob.blocks if b[1] is not theta]
    lower = [0.0 if b[1] is film.P else None for b in blocks]
    bcs = [bc for bc in prob.bcs if all(bc is not o for o in film.bcs[1:])]
    opts = with_snes_type(prob.solver.options, "vinewtonrsls")
    # the step limits for this block layout (without theta: the counter position's
    # index moves; the problem's own limiter read past the end of the vector)
    limiter = prob.step_limiter(blocks) if prob.bulk and prob.limits.any else None
    pre = NonlinearSolver(
        [b[0] for b in blocks], [b[1] for b in blocks], bcs, lower=lower, options=opts,
        name=f"{prob.name} Reynolds-condition start", step_limiter=limiter,
    )  # fmt: skip
    try:
        return pre.solve(where=where or f"{prob.name}: Reynolds-condition start").newton_iterations
    finally:
        pre.destroy()


START_MAX_IT = 300  # Newton steps allowed for the first coupled solve from the dry shape


def boundary_start_speed(h_rms: float, viscosity: float, half_width: float, p_mean: float) -> float:
    """A speed of boundary lubrication [m/s], where a coupled Newton can start from the
    dry (Hertz) shape: S1's film estimate (after fig 15) ``u = (0.2 eta v a / p_mean)^(1/2)``
    set equal to ``h_rms / 30``, i.e. ``v = (h_rms / 30)^2 p_mean / (0.2 eta a)``.

    Args:
        h_rms: Rms roughness [m].
        viscosity: eta [Pa s].
        half_width: Contact half-width (radius) a [m].
        p_mean: Mean contact pressure [Pa].
    """
    return (h_rms / 30.0) ** 2 * p_mean / (0.2 * viscosity * half_width)


def start_coupled(
    prob: Any,
    target: float,
    v_start: float,
    stepping: SpeedStepping,
    where: str,
    *,
    pressure_guess: Any = None,
    peak_gap: float = 0.0,
    film_guess: bool = False,
) -> dict[str, Any]:
    """Bring a coupled (film + body) problem to its first converged state at ``target``.

    With ``pressure_guess`` (UFL, [Pa]) the body is first deformed under it
    (:meth:`~dolfinx_seal.solid.problem.SolidContactProblem.warm_start`, lowest
    point at the gap ``peak_gap``); with ``film_guess`` (a hydrodynamic start)
    the fluid pressure starts from it too and is then solved, with the counter
    position, on the frozen deformed shape (:func:`film_presolve`).  Then one
    coupled Newton solve at
    ``min(target, v_start)`` (boundary lubrication: the film carries little and
    the dry shape is a good start; up to :data:`START_MAX_IT` steps, since the
    contact and cavitation active sets may move one node per step from there,
    docs/design.md, solver strategy), a Reynolds-condition presolve first for JFO, and speed
    continuation up to ``target``.  Returns solver figures; raises
    :class:`~dolfinx_seal.errors.SolverError` (with the speed reached) on failure.
    """
    t0 = time.perf_counter()
    its = 0
    if pressure_guess is not None:
        its += prob.warm_start(pressure_guess, peak_gap)
        if film_guess:
            prob.film.set_pressure(pressure_guess)
    v0 = min(target, v_start) if target > 0 else target
    if v0 < target:
        prob.film.set_speed(v0)
    if film_guess:
        prob.set_fraction(1.0)
        its += film_presolve(prob, where)
    if prob.film.params.cavitation != "reynolds":
        prob.set_fraction(1.0)
        its += reynolds_presolve(prob)
    film_start = 0
    snes = prob.solver.snes
    max_it = snes.getTolerances()[3]
    snes.setTolerances(max_it=START_MAX_IT)
    ramp_flow = prob.film.params.flow_factor != "none"
    if ramp_flow:  # start on smooth-wall flow, then bring the flow factor in
        prob.film.flow_factor_weight.value = 0.0
    start = f"{where} at speed {v0:.3g} m/s (start)"
    try:
        if stepping.film_presolve:  # loose coupled solve, film on that shape, then the rest
            its += _loose_start(prob, start)
            loose = prob.state()
            pre = FilmPresolver(prob)
            try:
                film_start = pre.solve(f"{where} start")
            finally:
                pre.destroy()
            try:
                its += prob.solve_at(1.0, where=start)
            except SolverError as e:  # the film moved somewhere the coupled Newton
                get_logger().info(  # cannot start from: finish from the loose state
                    "start after the film presolve failed (%s); going on from the loose state",
                    e.what,
                )
                its += e.history.newton_iterations
                prob.restore(loose)
                its += prob.solve_at(1.0, where=start)
        else:
            its += prob.solve_at(1.0, where=start)
    finally:
        prob.solver.snes.setTolerances(max_it=max_it)
    if ramp_flow:
        its += _ramp_flow_factor(prob, where)
    strategy = "direct"
    film_its = film_start
    if v0 < target:
        recs = speed_sweep(prob, [target], lambda *_: None, dict, stepping)
        if not recs[-1].converged:
            raise SolverError(
                f"coupled solve did not reach film.speed = {target:g} m/s: {recs[-1].error}",
                where=f"{where} start",
                partial={"speed": float(prob.film.speed.value)},
            )
        its += recs[-1].newton_iterations
        film_its += recs[-1].film_iterations
        strategy = f"start at {v0:.3g} m/s, speed continuation ({recs[-1].steps} steps)"
    return {
        "newton_iterations": its,
        "film_presolve_iterations": film_its,
        "solve_time_s": time.perf_counter() - t0,
        "strategy": strategy,
    }


FILM_PRESOLVE_MAX_IT = 300  # film-only steps: the front may move one node per step


class FilmPresolver:
    """The film (and, under force control, the counter position) solved on the
    frozen shape of a coupled problem, the solver kept for repeated use
    (:attr:`SpeedStepping.film_presolve`)."""

    def __init__(self, prob: Any) -> None:
        self.prob = prob
        opts = dataclasses.replace(prob.solver.options, max_it=FILM_PRESOLVE_MAX_IT)
        self.solver = _film_solver(prob, opts, f"{prob.name} film on the predicted shape")

    def solve(self, where: str) -> int:
        """Solve from the current state; returns the Newton steps.  A failure
        restores the state it started from (the coupled solve then starts there)."""
        saved = self.prob.state()
        try:
            return self.solver.solve(
                where=f"{where}: film on the predicted shape"
            ).newton_iterations
        except SolverError as e:
            self.prob.restore(saved)
            get_logger().info("film presolve failed (%s); coupled solve from the predictor", e.what)
            return 0

    def destroy(self) -> None:
        self.solver.destroy()


START_LOOSE_RTOL = 1e-4  # relative residual of the first, loose coupled solve of a start


def _loose_start(prob: Any, where: str) -> int:
    """The start's coupled solve stopped at :data:`START_LOOSE_RTOL`; returns its steps.

    From the dry shape the coupled Newton converges in a few steps to a residual
    of ~1e-5 of the first, then the film's cavitation front creeps one node per
    step (measured on the S1 cylinder: 15 more steps at 5 um).  Stopping there and
    moving the front with the film-only solve on the shape reached
    (:class:`FilmPresolver`) leaves the final coupled solve 2-3 steps."""
    with prob.solver.switched(rtol=START_LOOSE_RTOL):
        return prob.solve_at(1.0, where=f"{where}, loose")


def film_presolve(prob: Any, where: str) -> int:
    """Solve the film (and the counter position, under force control) on the frozen
    deformed shape: the first half-step of the partitioned scheme.  Returns the
    Newton steps.

    From a Hertz-deformed body with the Hertz pressure as fluid pressure, the
    first coupled Newton step of the 3D ball moves the inlet rim by hundreds of
    micrometres (the linearisation is far off), and a limited step then creeps;
    after this presolve the coupled Newton converges in 13-17 steps (measured on
    a/15 and a/20 meshes of the S1 ball).

    A JFO or full-Sommerfeld film is solved here under the Reynolds condition
    (``p >= 0``, the film fraction frozen at 1): on the frozen, Hertz-deformed
    start shape of the ball, the JFO film stalled at a residual of 6e-2 of the
    first (DIVERGED_LINE_SEARCH) and the full-Sommerfeld one converged only
    linearly, its antisymmetric pressure carrying almost none of the load
    equation's load (docs/stability.md)."""
    reynolds = prob.film.params.cavitation != "reynolds"
    options = prob.solver.options
    if reynolds:
        from dolfinx_seal.solvers import with_snes_type

        if prob.film.has_theta:
            prob.film.theta_fn.x.array[:] = 1.0
        options = with_snes_type(options, "vinewtonrsls")
    solver = _film_solver(prob, options, f"{prob.name} film start", reynolds_condition=reynolds)
    try:
        return solver.solve(where=f"{where}: film on the start shape").newton_iterations
    finally:
        solver.destroy()


def _film_solver(prob: Any, options: Any, name: str, reynolds_condition: bool = False) -> Any:
    """A solver on the film unknowns and, under force control, the counter position,
    with the body's shape frozen (``reynolds_condition``: see
    :meth:`~dolfinx_seal.film.surface.SurfaceFilm.make_solver`)."""
    pos = [b for b in prob.blocks if prob.control == "force" and b[1] is prob.position]
    return prob.film.make_solver(options, pos, name=name, reynolds_condition=reynolds_condition)


def _ramp_flow_factor(prob: Any, where: str, min_step: float = 1.0 / 64) -> int:
    """Bring the film's pressure flow factor in from smooth-wall flow (weight 0 -> 1),
    halving the weight step on a failed solve.  Returns the Newton steps.

    From the dry shape the Newton step with the full factor overshoots (the
    factor cuts the Poiseuille conductivity 5-10x at boundary-lubrication gaps)."""
    w = prob.film.flow_factor_weight
    control = StepControl(first=0.25, grow=2.0, easy=None, cut=0.5, min_step=min_step,
                          max_step=0.5)  # fmt: skip

    def apply(weight: float) -> None:
        w.value = weight

    walk = AdaptiveWalk(
        control, apply,
        lambda t: prob.solve_at(1.0, where=f"{where}: flow factor weight {t:.3g}"),
        prob.state, prob.restore, name=f"{prob.name} flow-factor homotopy",
    )  # fmt: skip
    res = walk.walk(0.0, 1.0)
    if not res.converged:
        raise SolverError(
            f"flow factor could not be brought in beyond weight {res.reached:.3g}: "
            f"{res.last_error.what if res.last_error else res.error}",
            where=where,
            partial={"flow_factor_weight": res.reached},
        ) from res.last_error
    return res.newton_iterations


def order_speeds(values: Sequence[float], order: str) -> list[float]:
    """Speeds for a sweep: ``up`` (ascending), ``down`` (descending), ``up-down``
    (ascending then back down, for hysteresis), or ``given``."""
    v = sorted(float(x) for x in values)
    if order == "up":
        return v
    if order == "down":
        return v[::-1]
    if order == "up-down":
        return v + v[-2::-1]
    return [float(x) for x in values]


__all__ = [
    "START_MAX_IT",
    "SpeedStepping",
    "SweepRecord",
    "boundary_start_speed",
    "film_presolve",
    "order_speeds",
    "path_tangent",
    "reynolds_presolve",
    "secant_predictor",
    "speed_sweep",
    "start_coupled",
    "tangent_predictor",
]
