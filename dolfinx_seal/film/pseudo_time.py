"""Pseudo-transient continuation of the mass-conserving (JFO) film.

The steady JFO film is a complementarity problem (``p >= 0``, ``0 <= theta <= 1``,
``p (1 - theta) = 0``) solved by an active-set (semismooth) Newton.  Where the
cavitated zones must move far, e.g. a pressure difference brought across a
sliding rough band, the active set can cycle: on the two-scale lip sector at
1 m/s the oil pressure could not be raised past 10 % of 0.05 MPa in steps down
to 0.1 % of it (every step 60 Newton steps, DIVERGED_MAX_IT).

The remedy is the film's own time: the transient Reynolds equation

    d(g theta)/dt + div_s( -phi_p g^3 / (12 eta) grad_s p + U_m g theta ) = 0

by implicit Euler in a pseudo-time ``t`` (the film storage term of
:class:`~dolfinx_seal.film.surface.SurfaceFilm`, ``inv_dt``, ``theta_old``).  A
step of length ``dt`` lets the film fraction move by about ``U_m dt`` along the
band, so each step changes the active set only near the cavitation fronts; the
step grows geometrically once easy (an adaptive walk in ``log10 dt``) until the
storage term is negligible, and a last solve with ``1/dt = 0`` gives the steady
film exactly (the same discrete equations as a direct solve).  This is
pseudo-transient continuation (Kelley and Keyes, SIAM J. Numer. Anal. 35, 1998)
on the film's physical transient; the lubrication literature uses the same idea
for cavitating films (e.g. Elrod's algorithm marched in time).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.params import check_positive, check_range
from dolfinx_seal.solvers.adaptive import AdaptiveWalk, StepControl, log10_abs


@dataclass(frozen=True)
class PseudoTimeOptions:
    """Pseudo-time stepping of the JFO film.

    Times are in units of the element transit time ``t_e = h_e / |U_m|`` (the film
    element size over the mean surface speed).

    Attributes:
        first: First pseudo-time step [t_e].  The storage term shares the film
            row's one-point rule (FFCx 0.9 cannot mix a lumped, vertex-rule term
            into it), so its matrix is not lumped and is singular for the
            node-to-node oscillation of ``theta``: where it dominates the
            upwinded transport (``dt`` below a few ``t_e``) that mode shows.
            Measured on the pocketed slider (1000 cells) from a full film: first
            steps of 10 to 1e5 ``t_e`` converge (63-70 Newton steps), 1 ``t_e``
            does not.
        last: Pseudo-time step after which the steady film is solved [t_e]: the
            storage term is then ``t_e / last`` of the transport term.
        first_decades: First growth of the step [decades of dt].
        max_decades: Largest growth of the step in one pseudo-time step [decades].
        min_decades: Smallest growth before the stepping is given up [decades].
        easy: Newton steps of a pseudo-time step counted as easy (the step then
            grows).
    """

    first: float = 10.0
    last: float = 1e6
    first_decades: float = 0.25
    max_decades: float = 1.0
    min_decades: float = 0.01
    easy: int = 8

    def __post_init__(self) -> None:
        check_positive("first", self.first)
        check_range("last", self.last, self.first, math.inf, lo_open=True)
        check_positive("first_decades", self.first_decades)
        check_positive("max_decades", self.max_decades)
        check_positive("min_decades", self.min_decades)


def element_transit_time(film: Any) -> float:
    """``h_e / |U_m|`` [s]: the time the mean surface speed takes over one film element."""
    speed = abs(float(film.speed.value))
    if speed == 0.0:
        raise ParameterError("film.speed = 0 m/s: the pseudo-time of the JFO film needs sliding")
    return film.scales.element / (0.5 * speed)


def pseudo_transient_solve(
    film: Any,
    solver: Any,
    where: str,
    options: PseudoTimeOptions | None = None,
    unknowns: Sequence[Any] | None = None,
) -> int:
    """Solve the steady JFO film from its current state by pseudo-time steps.

    ``film`` is a :class:`~dolfinx_seal.film.surface.SurfaceFilm` built with JFO and
    transport (it carries ``inv_dt`` and ``theta_old``); ``solver`` solves its
    unknowns (e.g. ``film.make_solver``, geometry frozen), or the film with the body
    (a coupled solver; then pass its ``unknowns``, the functions a failed step
    restores: default the film's ``P`` and ``theta``).  Each step starts from
    the last accepted state, which is also its ``theta_old``; a failed step is
    retried shorter.  Returns the Newton steps of the accepted steps and of the
    final steady solve.  Raises :class:`SolverError` naming the pseudo-time reached
    if the steps shrink below ``min_decades`` or the steady solve fails; the film
    is then left at the last accepted pseudo-time state.
    """
    if not getattr(film, "has_theta", False) or not hasattr(film, "inv_dt"):
        raise ParameterError(
            "film.cavitation: pseudo-time stepping needs the JFO film with sliding "
            "(cavitation = 'jfo', film.speed != 0)"
        )
    opt = options or PseudoTimeOptions()
    t_e = element_transit_time(film)
    unknowns = list(unknowns) if unknowns is not None else [film.P, film.theta_fn]

    def save() -> list[Any]:
        return [u.x.array.copy() for u in unknowns]

    def restore(state: list[Any]) -> None:
        for u, arr in zip(unknowns, state, strict=True):
            u.x.array[:] = arr

    def apply(dt: float) -> None:
        film.inv_dt.value = 1.0 / dt
        film.accept_step()  # the last accepted state is the old film (and gap)

    def solve(dt: float) -> int:
        return solver.solve(where=f"{where}: pseudo-time step {dt / t_e:.3g} t_e").newton_iterations

    control = StepControl(
        first=opt.first_decades, grow=2.0, easy=opt.easy, cut=0.5,
        min_step=opt.min_decades, max_step=opt.max_decades,
    )  # fmt: skip
    walk = AdaptiveWalk(
        control, apply, solve, save, restore,
        coordinate=(log10_abs, lambda c: 10.0**c), name=f"{where}: pseudo-time",
    )  # fmt: skip
    start = opt.first * t_e / 10.0**opt.first_decades
    try:
        res = walk.walk(start, opt.last * t_e)
        if not res.converged:
            raise SolverError(
                f"pseudo-time stepping of the JFO film stopped at dt = {res.reached / t_e:.3g} "
                f"t_e: {res.error}",
                where=where,
                history=res.last_error.history if res.last_error else None,
            )
        film.inv_dt.value = 0.0
        its = (
            res.newton_iterations
            + solver.solve(where=f"{where}: steady after pseudo-time").newton_iterations
        )
    finally:
        film.inv_dt.value = 0.0
    get_logger().info("%s: steady JFO film after %d pseudo-time steps, %d Newton steps",
                      where, res.steps, its)  # fmt: skip
    return its


__all__ = ["PseudoTimeOptions", "element_transit_time", "pseudo_transient_solve"]
