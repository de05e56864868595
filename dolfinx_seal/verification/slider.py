"""1D steady slider bearings with cavitation: a semi-analytic reference, numpy/scipy only.

Written apart from the FEM code, to verify its mass-conserving (JFO / Elrod-Adams)
and Reynolds-condition (Swift-Stieber) film solvers.

Model (SI units: x [m], h [m], p [Pa], U_m [m/s], eta [Pa s], Q [m^2/s]).  With the
mean entrainment speed ``U_m = (u_1 + u_2)/2`` the volume flux per unit width is

    Q(x) = U_m h(x) theta(x) - h(x)^3 / (12 eta) p'(x),

and steady mass conservation makes ``Q`` piecewise constant.  In a full-film zone
``theta = 1``, ``p >= 0`` and ``p' = 12 eta (U_m h - Q) / h^3``; in a cavitated zone
``p = 0`` (pressures are gauge pressures above the cavitation pressure) and
``theta = Q / (U_m h)`` in ``[0, 1)``.  Boundary conditions: a flooded inlet with
``p(0) = p_in >= 0`` and ``p(L) = p_out >= 0``.

All pressures follow from two integrals of the gap,
``C2(x) = int_0^x h^-2`` and ``C3(x) = int_0^x h^-3``: in a zone that starts at
``x0`` with pressure ``p0`` and carries the flux ``Q``,

    p(x) = p0 + 12 eta (U_m [C2(x) - C2(x0)] - Q [C3(x) - C3(x0)]).

The gap is a callable plus its breakpoints (jumps of h or h'); ``C2, C3`` are
tabulated piecewise with 16-point Gauss-Legendre on 512 sub-intervals of every smooth
piece (machine precision for the smooth pieces used here), and loads are integrated
with ``scipy.integrate.quad`` on each smooth piece.

Free boundaries.  Two flux functions organise everything:

* ``Q_l(x) = (p_in + 12 eta U_m C2(x)) / (12 eta C3(x))``: the flux of a full film
  from ``p(0) = p_in`` to ``p(x) = 0``.  On the inlet zone ``p = 12 eta C3 (Q_l - Q)``,
  and ``Q_l' ~ (U_m h - Q_l)``, so the film ruptures at a *local minimum* of ``Q_l``
  that is a running minimum from the left: at a smooth point ``U_m h(x_c) = Q`` and
  ``p'(x_c) = 0``; at a divergent step ``U_m h(x_c^-) <= Q <= U_m h(x_c^+)``.
* ``Q_r(s) = (12 eta U_m [C2(L) - C2(s)] - p_out) / (12 eta [C3(L) - C3(s)])``: the
  flux of a full film from ``p(s) = 0`` to ``p(L) = p_out``; on that zone
  ``p = 12 eta [C3(L) - C3] (Q - Q_r)`` and ``Q_r' ~ (Q_r - U_m h)``.

JFO (:func:`jfo_solution`).  One flux ``Q`` everywhere.  The inlet zone fixes
``Q = Q_l(x_c)``; the cavity carries ``theta = Q / (U_m h) <= 1`` (so it may not extend
past a point where ``U_m h < Q``); the film re-forms at ``x_r`` with ``p(x_r) = 0``
and ``Q_r(x_r) = Q`` (a reformation front: theta jumps to 1, p' jumps from 0 to
``12 eta U_m h (1 - theta^-) / h^3 >= 0``).  ``Q_r(s) - Q`` is monotone in the cavity,
so ``x_r`` is a Brent root.  If ``p_out = 0`` the cavity may instead run to the outlet.

Reynolds condition (:func:`reynolds_condition_solution`).  The minimiser of
``int h^3 p'^2 / (24 eta) - U_m h p'`` over ``p >= 0`` (an obstacle problem, unique):
``p = p' = 0`` at a smooth free boundary, the weak residual ``d/dx (U_m h - h^3 p'/12 eta)``
is a non-negative measure where ``p = 0`` (so cavities only where ``h' >= 0``, and a
flux *increase* ``Q_2 >= Q_1`` across a zero-pressure point is allowed: mass is not
conserved).  The inlet zone is the same as for JFO; the outlet zone starts at a local
maximum of ``Q_r`` that is a running maximum from the right, with ``Q_2 = Q_r(x_r)``.
At a divergent step the cavity can have zero length (``x_r = x_c``): the film is at
``p = 0`` at that single point and the flux jumps from ``Q_1`` to ``Q_2``.

Scope: no cavity or one cavitated zone (rupture then reformation, or cavitation to
the outlet when ``p_out = 0``); otherwise :class:`~dolfinx_seal.errors.SolverError`.
Every candidate is checked against all complementarity conditions before it is
returned.

Independent cross-check: :func:`fv_jfo_lcp` and :func:`fv_reynolds_lcp` solve the same
problems by a cell-midpoint finite-volume discretisation (upwind Couette flux for JFO,
the p-theta complementarity of Giacopini et al. 2010 / Almqvist et al. 2014) with a
primal-dual active-set method on 1e4-1e6 cells; no quadrature, no free-boundary
logic is shared with the semi-analytic solution.

Benchmark: :func:`pocket_slider_benchmark` (the pocketed pad of Almqvist et al. 2014,
incompressible limit) and :func:`textured_slider_case` (own case).

References:
    M. Giacopini, M. T. Fowell, D. Dini, A. Strozzi, "A mass-conserving
    complementarity formulation to study lubricant films in the presence of
    cavitation", J. Tribol. 132(4) 041702 (2010).
    A. Almqvist, J. Fabricius, R. Larsson, P. Wall, "A new approach for studying
    cavitation in lubrication", J. Tribol. 136(1) 011706 (2014); the accompanying
    MATLAB script: A. Almqvist, "A cavitation algorithm", MATLAB Central File
    Exchange 41484 (2013, rev. 2016).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import quad
from scipy.linalg import solve_banded
from scipy.optimize import brentq

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.params import check_int_range, check_nonnegative, check_positive, check_range

GapFunction = Callable[[np.ndarray], np.ndarray]

_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
_SUB = 512  # tabulation sub-intervals per smooth piece
_SCAN = 256  # scan points per smooth piece when bracketing free boundaries


# ------------------------------------------------------------------ geometry
@dataclass(frozen=True)
class Gap:
    """Film thickness ``h(x)`` on ``[0, length]``.

    Attributes:
        length: Bearing length ``L`` [m].
        h: Vectorised callable ``x [m] -> h [m]``, positive; smooth between breakpoints.
        breakpoints: Interior points where ``h`` or ``h'`` jumps [m] (sorted on init).
        name: Label.
    """

    length: float
    h: GapFunction
    breakpoints: tuple[float, ...] = ()
    name: str = "gap"

    def __post_init__(self) -> None:
        check_positive("length", self.length, "m")
        bps = tuple(sorted(float(b) for b in self.breakpoints))
        for b in bps:
            check_range("breakpoints", b, 0.0, self.length, lo_open=True, hi_open=True, unit="m")
        if len(set(bps)) != len(bps):
            raise ParameterError(f"breakpoints must be distinct, got {bps}")
        object.__setattr__(self, "breakpoints", bps)
        for k in range(len(self.edges) - 1):
            hv = self.on_piece(np.linspace(*self.edges[k : k + 2], 65), k)
            if not np.all(np.isfinite(hv)) or np.any(hv <= 0.0):
                raise ParameterError(f"h(x) of gap {self.name!r} must be positive and finite")

    @property
    def edges(self) -> tuple[float, ...]:
        """``(0, *breakpoints, L)`` [m]."""
        return (0.0, *self.breakpoints, float(self.length))

    def __call__(self, x: np.ndarray | float) -> np.ndarray:
        """``h(x)`` [m] (at a breakpoint: whatever the callable returns there)."""
        x = np.asarray(x, dtype=float)
        return np.broadcast_to(np.asarray(self.h(x), dtype=float), x.shape).copy()

    def on_piece(self, x: np.ndarray | float, k: int) -> np.ndarray:
        """``h`` of smooth piece ``k`` at ``x`` (clipped into the open piece, so that
        piece ends give the one-sided limits) [m]."""
        a, b = self.edges[k], self.edges[k + 1]
        eps = 1e-12 * self.length
        return self(np.clip(np.asarray(x, dtype=float), a + eps, b - eps))

    def piece_of(self, x: np.ndarray) -> np.ndarray:
        """Index of the smooth piece holding ``x`` (a breakpoint belongs to the right)."""
        k = np.searchsorted(np.asarray(self.breakpoints), np.asarray(x), side="right")
        return np.asarray(k, dtype=int)


def linear_gap(length: float, h_inlet: float, h_outlet: float) -> Gap:
    """Plane slider ``h = h_inlet + (h_outlet - h_inlet) x / L`` [m]."""
    check_positive("h_inlet", h_inlet, "m")
    check_positive("h_outlet", h_outlet, "m")
    L, h0, h1 = float(length), float(h_inlet), float(h_outlet)
    return Gap(L, lambda x: h0 + (h1 - h0) * np.asarray(x) / L, name="linear")


def parabolic_gap(length: float, h_min: float, radius: float, x_min: float) -> Gap:
    """Convergent-divergent gap ``h = h_min + (x - x_min)^2 / (2 R)`` (a cylinder of
    radius ``R`` [m] near a plane), minimum ``h_min`` [m] at ``x_min`` in ``(0, L)``."""
    check_positive("length", length, "m")
    check_positive("h_min", h_min, "m")
    check_positive("radius", radius, "m")
    check_range("x_min", x_min, 0.0, length, lo_open=True, hi_open=True, unit="m")
    hm, R, xm = float(h_min), float(radius), float(x_min)
    return Gap(
        float(length), lambda x: hm + (np.asarray(x) - xm) ** 2 / (2.0 * R), name="parabolic"
    )


def textured_gap(
    length: float,
    h_inlet: float,
    h_outlet: float,
    pockets: Sequence[tuple[float, float]],
    depth: float,
) -> Gap:
    """Plane (parallel or converging) slider with rectangular pockets.

    Args:
        length: ``L`` [m].
        h_inlet: Land gap at ``x = 0`` [m].
        h_outlet: Land gap at ``x = L`` [m] (lands are linear in between).
        pockets: ``(x_start, x_end)`` of each pocket [m], inside ``(0, L)``, disjoint.
        depth: Pocket depth added to the land gap [m].
    """
    check_positive("h_inlet", h_inlet, "m")
    check_positive("h_outlet", h_outlet, "m")
    check_positive("depth", depth, "m")
    L = check_positive("length", length, "m")
    pk = sorted((float(a), float(b)) for a, b in pockets)
    last = 0.0
    for a, b in pk:
        check_range("pockets.x_start", a, last, L, lo_open=True, hi_open=True, unit="m")
        check_range("pockets.x_end", b, a, L, lo_open=True, hi_open=True, unit="m")
        last = b
    h0, h1, d = float(h_inlet), float(h_outlet), float(depth)
    starts = np.array([a for a, _ in pk])
    ends = np.array([b for _, b in pk])

    def h(x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        inside = np.zeros(x.shape, dtype=bool)
        for a, b in zip(starts, ends, strict=True):
            inside |= (x > a) & (x < b)
        return h0 + (h1 - h0) * x / L + d * inside

    bps = tuple(v for ab in pk for v in ab)
    return Gap(L, h, bps, name="textured")


# --------------------------------------------------------------- parameters
@dataclass(frozen=True)
class SliderOperating:
    """Operating conditions.

    Attributes:
        speed: Mean entrainment speed ``U_m = (u_1 + u_2)/2`` [m/s], > 0.
        viscosity: Dynamic viscosity ``eta`` [Pa s], > 0.
        p_inlet: Supply pressure at ``x = 0`` (gauge, above cavitation) [Pa], >= 0.
        p_outlet: Pressure at ``x = L`` [Pa], >= 0.
    """

    speed: float = 0.5
    viscosity: float = 0.1
    p_inlet: float = 0.0
    p_outlet: float = 0.0

    def __post_init__(self) -> None:
        check_positive("speed", self.speed, "m/s")
        check_positive("viscosity", self.viscosity, "Pa s")
        check_nonnegative("p_inlet", self.p_inlet, "Pa")
        check_nonnegative("p_outlet", self.p_outlet, "Pa")


# --------------------------------------------------------------- integrals
class _Integrals:
    """``C2(x) = int_0^x h^-2``, ``C3(x) = int_0^x h^-3`` [m^-1, m^-2], tabulated."""

    def __init__(self, gap: Gap) -> None:
        self.gap = gap
        self.edges = np.asarray(gap.edges)
        self.grids: list[np.ndarray] = []
        self.tables: list[tuple[np.ndarray, np.ndarray]] = []
        c2 = c3 = 0.0
        for k in range(len(self.edges) - 1):
            g = np.linspace(self.edges[k], self.edges[k + 1], _SUB + 1)
            i2, i3 = self._gl(g[:-1], g[1:], k)
            t2 = c2 + np.concatenate(([0.0], np.cumsum(i2)))
            t3 = c3 + np.concatenate(([0.0], np.cumsum(i3)))
            self.grids.append(g)
            self.tables.append((t2, t3))
            c2, c3 = t2[-1], t3[-1]
        self.c2_total, self.c3_total = c2, c3

    def _gl(self, a: np.ndarray, b: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
        half = 0.5 * (b - a)
        xs = 0.5 * (a + b)[..., None] + half[..., None] * _GL_X
        h = self.gap.on_piece(xs, k)
        return (half * (h**-2 @ _GL_W), half * (h**-3 @ _GL_W))

    def __call__(self, x: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        x = np.clip(np.asarray(x, dtype=float), 0.0, self.gap.length)
        flat = x.ravel()
        c2 = np.empty_like(flat)
        c3 = np.empty_like(flat)
        piece = np.minimum(self.gap.piece_of(flat), len(self.grids) - 1)
        for k in np.unique(piece):
            sel = piece == k
            g = self.grids[k]
            j = np.clip(np.searchsorted(g, flat[sel], side="right") - 1, 0, _SUB - 1)
            i2, i3 = self._gl(g[j], flat[sel], k)
            c2[sel] = self.tables[k][0][j] + i2
            c3[sel] = self.tables[k][1][j] + i3
        return c2.reshape(x.shape), c3.reshape(x.shape)

    def scalar(self, x: float) -> tuple[float, float]:
        c2, c3 = self(np.array([x]))
        return float(c2[0]), float(c3[0])


# ---------------------------------------------------------------- solutions
@dataclass(frozen=True)
class FilmZone:
    """A full-film zone ``[x_start, x_end]`` [m] with flux ``flux`` [m^2/s] and
    ``p(x_start) = p_start`` [Pa]."""

    x_start: float
    x_end: float
    flux: float
    p_start: float


@dataclass(frozen=True, eq=False)
class SliderSolution:
    """Semi-analytic solution.

    Attributes:
        model: ``"jfo"`` or ``"reynolds"``.
        gap: The geometry.
        operating: The operating conditions.
        zones: Full-film zones, in order; ``p = 0`` elsewhere.
        flux: Flux of the inlet zone ``Q`` [m^2/s] (for JFO: the flux everywhere).
        x_rupture: Film rupture (start of the cavity) [m], ``None`` without cavitation.
        x_reformation: Film reformation [m]; ``None`` without cavitation or if the
            cavity runs to the outlet; equal to ``x_rupture`` for a zero-length
            cavity (Reynolds condition at a divergent step).
        load: ``int_0^L p dx`` [N/m].
        p_max: Maximum pressure [Pa].
        x_p_max: Its position [m].
    """

    model: str
    gap: Gap
    operating: SliderOperating
    zones: tuple[FilmZone, ...]
    flux: float
    x_rupture: float | None
    x_reformation: float | None
    load: float
    p_max: float
    x_p_max: float
    _c: _Integrals = field(repr=False)

    @property
    def fluxes(self) -> tuple[float, ...]:
        """Flux of each full-film zone [m^2/s] (all equal for JFO)."""
        return tuple(z.flux for z in self.zones)

    def _zone_index(self, x: np.ndarray) -> np.ndarray:
        idx = np.full(x.shape, -1, dtype=int)
        for i, z in enumerate(self.zones):
            idx[(x >= z.x_start) & (x <= z.x_end)] = i
        return idx

    def pressure(self, x: np.ndarray | float) -> np.ndarray:
        """``p(x)`` [Pa]."""
        x = np.asarray(x, dtype=float)
        p = np.zeros(x.shape)
        c2, c3 = self._c(x)
        idx = self._zone_index(x)
        k = 12.0 * self.operating.viscosity
        for i, z in enumerate(self.zones):
            sel = idx == i
            a2, a3 = self._c.scalar(z.x_start)
            p[sel] = z.p_start + k * (
                self.operating.speed * (c2[sel] - a2) - z.flux * (c3[sel] - a3)
            )
        return np.maximum(p, 0.0)

    def dpdx(self, x: np.ndarray | float) -> np.ndarray:
        """``p'(x)`` [Pa/m] (0 in cavities; at a breakpoint: the value of ``h(x)``)."""
        x = np.asarray(x, dtype=float)
        h = self.gap(x)
        out = np.zeros(x.shape)
        idx = self._zone_index(x)
        for i, z in enumerate(self.zones):
            sel = idx == i
            out[sel] = 12.0 * self.operating.viscosity * (self.operating.speed * h[sel] - z.flux)
            out[sel] /= h[sel] ** 3
        return out

    def theta(self, x: np.ndarray | float) -> np.ndarray:
        """Film fraction ``theta(x)`` [-]: 1 in full film, ``Q / (U_m h)`` in a cavity
        with ``Q`` the flux of the zone upstream (for the Reynolds model this is only a
        diagnostic: the model does not conserve mass)."""
        x = np.asarray(x, dtype=float)
        idx = self._zone_index(x)
        th = np.ones(x.shape)
        cav = idx < 0
        if np.any(cav):
            ends = np.array([z.x_end for z in self.zones])
            up = np.searchsorted(ends, x[cav], side="right") - 1
            q = np.array([self.zones[max(u, 0)].flux for u in up])
            th[cav] = q / (self.operating.speed * self.gap(x[cav]))
        return th

    def sample(self, n: int = 2001) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(x, p, theta)`` on ``n`` uniform points [m, Pa, -]."""
        x = np.linspace(0.0, self.gap.length, n)
        return x, self.pressure(x), self.theta(x)


# ------------------------------------------------------------ the machinery
class _Slider:
    """Flux functions, scans and checks for one (gap, operating) pair."""

    def __init__(self, gap: Gap, op: SliderOperating) -> None:
        self.gap, self.op = gap, op
        self.c = _Integrals(gap)
        self.k = 12.0 * op.viscosity
        self.um = op.speed
        L = gap.length
        hmin = min(float(np.min(gap.on_piece(g, k))) for k, g in enumerate(self.c.grids))
        self.hmin = hmin
        self.p_scale = op.p_inlet + op.p_outlet + self.k * self.um * L / hmin**2
        self.q_scale = self.um * hmin
        self.L = L

    # flux functions (vectorised)
    def q_left(self, x: np.ndarray) -> np.ndarray:
        c2, c3 = self.c(x)
        return (self.op.p_inlet + self.k * self.um * c2) / (self.k * c3)

    def q_right(self, s: np.ndarray) -> np.ndarray:
        c2, c3 = self.c(s)
        a = self.k * self.um * (self.c.c2_total - c2) - self.op.p_outlet
        return a / (self.k * (self.c.c3_total - c3))

    def zone_p(self, x: np.ndarray, x0: float, p0: float, q: float) -> np.ndarray:
        c2, c3 = self.c(x)
        a2, a3 = self.c.scalar(x0)
        return p0 + self.k * (self.um * (c2 - a2) - q * (c3 - a3))

    # scans
    def _pieces(self, lo: float, hi: float):
        """(k, a, b) of the smooth pieces overlapping ``[lo, hi]``."""
        e = self.gap.edges
        for k in range(len(e) - 1):
            a, b = max(e[k], lo), min(e[k + 1], hi)
            if b > a:
                yield k, a, b

    def sign_changes(
        self,
        f: Callable[[np.ndarray, int], np.ndarray],
        lo: float,
        hi: float,
        direction: int,
        *,
        breakpoints: bool = True,
    ) -> list[float]:
        """Points in ``[lo, hi]`` where ``f`` changes sign, ``direction = +1``: - to +,
        ``-1``: + to -; inside smooth pieces (Brent) and at breakpoints (one-sided
        values).  ``f(x, k)`` evaluates on piece ``k``."""
        out: list[float] = []
        span = hi - lo
        for k, a, b in self._pieces(lo, hi):
            xs = np.linspace(a, b, _SCAN + 1)
            if a == 0.0:
                xs = xs[1:]  # flux functions are singular at x = 0
            if b == self.L:
                xs = xs[:-1]
            if xs.size < 2:
                continue
            v = direction * f(xs, k)
            for j in np.nonzero((v[:-1] < 0.0) & (v[1:] >= 0.0))[0]:
                if v[j + 1] == 0.0 and j + 1 == xs.size - 1:
                    continue  # at the piece end: handled as a breakpoint
                r = brentq(
                    lambda t, k=k: float(f(np.array([t]), k)[0]),
                    xs[j],
                    xs[j + 1],
                    xtol=1e-15 * span,
                    rtol=1e-15,
                )
                out.append(r)
        if breakpoints:
            for i, bp in enumerate(self.gap.breakpoints):
                if lo <= bp <= hi:
                    left = direction * float(f(np.array([bp]), i)[0])
                    right = direction * float(f(np.array([bp]), i + 1)[0])
                    if left <= 0.0 <= right and not (left == 0.0 and right == 0.0):
                        out.append(bp)
        return sorted(set(out))

    def dense(self, lo: float, hi: float) -> np.ndarray:
        pts = [np.linspace(a, b, _SCAN + 1) for _, a, b in self._pieces(lo, hi)]
        return np.unique(np.concatenate(pts)) if pts else np.array([lo, hi])

    def zone_extrema(self, z: FilmZone) -> tuple[float, float, float]:
        """``(min p, max p, x of max p)`` of a zone [Pa, Pa, m]: at its ends, its
        breakpoints and where ``U_m h = Q`` (``p' = 0``)."""
        pts = [z.x_start, z.x_end]
        if z.x_end > z.x_start:

            def f(x: np.ndarray, k: int) -> np.ndarray:
                return self.um * self.gap.on_piece(x, k) - z.flux

            for direction in (+1, -1):
                pts += self.sign_changes(f, z.x_start, z.x_end, direction, breakpoints=False)
            pts += [b for b in self.gap.breakpoints if z.x_start < b < z.x_end]
        xs = np.array(sorted(set(pts)))
        p = self.zone_p(xs, z.x_start, z.p_start, z.flux)
        i = int(np.argmax(p))
        return float(np.min(p)), float(p[i]), float(xs[i])

    def zone_load(self, z: FilmZone) -> float:
        """``int p`` over a zone [N/m]: ``p0 (x1 - x0) + 12 eta int (x1 - s)(U_m h^-2 - Q h^-3)``,
        by ``scipy.integrate.quad`` on each smooth piece."""
        tot = z.p_start * (z.x_end - z.x_start)
        for k, a, b in self._pieces(z.x_start, z.x_end):

            def f(s: float, k: int = k) -> float:
                h = float(self.gap.on_piece(s, k))
                return (z.x_end - s) * (self.um / h**2 - z.flux / h**3)

            val, _ = quad(f, a, b, epsabs=0.0, epsrel=1e-12, limit=200)
            tot += self.k * val
        return tot

    def rupture_candidates(self) -> list[float]:
        """Local minima of ``Q_l`` that are running minima from the left."""
        cands = self.sign_changes(
            lambda x, k: self.um * self.gap.on_piece(x, k) - self.q_left(x), 0.0, self.L, +1
        )
        out = []
        for xc in cands:
            if xc >= self.L:
                continue
            ql = float(self.q_left(np.array([xc]))[0])
            left = self.dense(0.0, xc)
            left = left[(left > 0.0) & (left < xc)]
            if left.size and np.min(self.q_left(left)) < ql * (1.0 - 1e-12):
                continue
            out.append(xc)
        return out

    def full_film(self) -> FilmZone:
        q = (self.op.p_inlet - self.op.p_outlet + self.k * self.um * self.c.c2_total) / (
            self.k * self.c.c3_total
        )
        return FilmZone(0.0, self.L, q, self.op.p_inlet)

    def ok(self, z: FilmZone) -> bool:
        return self.zone_extrema(z)[0] >= -1e-10 * self.p_scale

    def finish(
        self, model: str, zones: list[FilmZone], xc: float | None, xr: float | None
    ) -> SliderSolution:
        load = sum(self.zone_load(z) for z in zones)
        best = max((self.zone_extrema(z)[1:3] for z in zones), default=(0.0, 0.0))
        return SliderSolution(
            model=model,
            gap=self.gap,
            operating=self.op,
            zones=tuple(zones),
            flux=zones[0].flux,
            x_rupture=xc,
            x_reformation=xr,
            load=load,
            p_max=best[0],
            x_p_max=best[1],
            _c=self.c,
        )


def _outlet_zone(s: _Slider, xr: float, q: float) -> FilmZone:
    return FilmZone(xr, s.L, q, 0.0)


def jfo_solution(gap: Gap, operating: SliderOperating) -> SliderSolution:
    """Mass-conserving (JFO / Elrod-Adams) steady solution, semi-analytic.

    Raises:
        SolverError: if no solution with at most one cavitated zone exists.
    """
    s = _Slider(gap, operating)
    ff = s.full_film()
    if s.ok(ff):
        return s.finish("jfo", [ff], None, None)
    tol_q = 1e-12 * s.q_scale
    for xc in s.rupture_candidates():
        q = float(s.q_left(np.array([xc]))[0])
        z1 = FilmZone(0.0, xc, q, operating.p_inlet)
        if not s.ok(z1):
            continue
        # the cavity cannot pass a point with U_m h < Q (theta would exceed 1)
        ends = s.sign_changes(lambda x, k, q=q: s.um * gap.on_piece(x, k) - q + tol_q, xc, s.L, -1)
        ends = [e for e in ends if e > xc]
        x_max = ends[0] if ends else s.L
        if x_max >= s.L and operating.p_outlet <= 1e-12 * s.p_scale:
            return s.finish("jfo", [z1], xc, None)

        def mismatch(xr: float, q: float = q) -> float:
            # p(L) - p_out of a film that re-forms at xr with flux q
            return float(s.zone_p(np.array([s.L]), xr, 0.0, q)[0]) - operating.p_outlet

        lo, hi = mismatch(xc), mismatch(x_max)
        if lo < -1e-10 * s.p_scale or hi > 1e-10 * s.p_scale:
            continue
        if lo <= 0.0:
            xr = xc
        elif hi >= 0.0:
            xr = x_max
        else:
            xr = brentq(mismatch, xc, x_max, xtol=1e-15 * s.L, rtol=1e-15)
        z2 = _outlet_zone(s, xr, q)
        if xr < s.L and not s.ok(z2):
            continue
        return s.finish("jfo", [z1, z2] if xr < s.L else [z1], xc, xr)
    raise SolverError(
        "no steady JFO solution with at most one cavitated zone",
        where=f"slider gap {gap.name!r}",
    )


def reynolds_condition_solution(gap: Gap, operating: SliderOperating) -> SliderSolution:
    """Reynolds-condition (Swift-Stieber) solution: the obstacle problem ``p >= 0``,
    semi-analytic; each full-film zone has its own flux (no mass conservation across
    the cavity).

    Raises:
        SolverError: if no solution with at most one cavitated zone exists.
    """
    s = _Slider(gap, operating)
    ff = s.full_film()
    if s.ok(ff):
        return s.finish("reynolds", [ff], None, None)

    def psi(x: np.ndarray, k: int) -> np.ndarray:
        return s.q_right(x) - s.um * gap.on_piece(x, k)

    maxima = s.sign_changes(psi, 0.0, s.L, -1)

    def cavity_admissible(a: float, b: float) -> bool:
        """``h`` non-decreasing on ``[a, b]`` (the residual ``U_m h'`` is >= 0)."""
        for k, lo, hi in s._pieces(a, b):
            hv = gap.on_piece(np.linspace(lo, hi, _SCAN + 1), k)
            if np.any(np.diff(hv) < -1e-12 * s.hmin):
                return False
        for i, bp in enumerate(gap.breakpoints):
            if a < bp < b and gap.on_piece(bp, i + 1) < gap.on_piece(bp, i) * (1 - 1e-12):
                return False
        return True

    for xc in s.rupture_candidates():
        q1 = float(s.q_left(np.array([xc]))[0])
        z1 = FilmZone(0.0, xc, q1, operating.p_inlet)
        if not s.ok(z1):
            continue
        if operating.p_outlet <= 1e-12 * s.p_scale and cavity_admissible(xc, s.L):
            return s.finish("reynolds", [z1], xc, None)
        for xr in [xc, *[m for m in maxima if m > xc]]:
            q2 = float(s.q_right(np.array([xr]))[0])
            if q2 < q1 * (1.0 - 1e-12):  # the flux may only increase (residual >= 0)
                continue
            k_r = int(gap.piece_of(np.array([xr]))[0])
            if s.um * float(gap.on_piece(xr, k_r)) < q2 * (1.0 - 1e-12):
                continue  # p'(xr+) < 0
            if xr > xc and not cavity_admissible(xc, xr):
                continue
            z2 = _outlet_zone(s, xr, q2)
            if not s.ok(z2):
                continue
            return s.finish("reynolds", [z1, z2], xc, xr)
    raise SolverError(
        "no Reynolds-condition solution with at most one cavitated zone",
        where=f"slider gap {gap.name!r}",
    )


# ------------------------------------------------- finite-volume cross-check
@dataclass(frozen=True, eq=False)
class FVSolution:
    """Fine finite-volume LCP solution.

    Attributes:
        model: ``"jfo"`` or ``"reynolds"``.
        x: Nodes [m] (``n_cells + 1``).
        p: Nodal pressure [Pa].
        theta: Nodal film fraction [-] (Reynolds: 1 in film, upstream flux / (U_m h)
            in cavities, a diagnostic).
        flux: Flux through each cell [m^2/s].
        load: Trapezoidal ``int p`` [N/m].
        x_rupture: First cavitated node [m] or ``None``.
        x_reformation: First film node after it [m] or ``None``.
        iterations: Active-set iterations.
    """

    model: str
    x: np.ndarray
    p: np.ndarray
    theta: np.ndarray
    flux: np.ndarray
    load: float
    x_rupture: float | None
    x_reformation: float | None
    iterations: int


def _fv_setup(gap: Gap, op: SliderOperating, n: int):
    x = np.linspace(0.0, gap.length, n + 1)
    dx = gap.length / n
    h = gap(0.5 * (x[:-1] + x[1:]))  # cell midpoints
    kc = h**3 / (12.0 * op.viscosity * dx)  # Poiseuille conductance of each cell
    cc = op.speed * h  # Couette flux of each cell per unit film fraction
    return x, kc, cc


def _levels(n_cells: int) -> list[int]:
    """Nested grids ``n_cells, n_cells/4, ...`` down to ~100 cells, coarsest first."""
    n = check_int_range("n_cells", n_cells, 4)
    out = [n]
    while out[-1] >= 400:
        out.append(out[-1] // 4)
    return out[::-1]


def _prolong(mask: np.ndarray | None, n_coarse: int, n_fine: int) -> np.ndarray:
    """Interior-node mask of the coarse grid, sampled at the interior fine nodes."""
    if mask is None:
        return np.zeros(n_fine - 1, dtype=bool)
    full = np.concatenate(([False], mask, [False]))
    j = np.rint(np.arange(1, n_fine) * n_coarse / n_fine).astype(int)
    return full[j]


def _fronts(x: np.ndarray, cav: np.ndarray) -> tuple[float | None, float | None]:
    idx = np.nonzero(cav)[0]
    if idx.size == 0:
        return None, None
    i0 = idx[0]
    after = np.nonzero(~cav[i0:])[0]
    xr = float(x[i0 + after[0]]) if after.size and i0 + after[0] < x.size - 1 else None
    return float(x[i0]), xr


def _pdas_reynolds(
    gap: Gap, op: SliderOperating, n: int, active: np.ndarray, max_iter: int
) -> tuple[np.ndarray, np.ndarray, int]:
    _, kc, cc = _fv_setup(gap, op, n)
    diag = kc[1:] + kc[:-1]
    off = -kc[1:-1]
    q = cc[1:] - cc[:-1]
    q[0] -= kc[0] * op.p_inlet
    q[-1] -= kc[-1] * op.p_outlet
    for it in range(1, max_iter + 1):
        ab = np.zeros((3, n - 1))
        ab[1] = np.where(active, 1.0, diag)
        ab[0, 1:] = np.where(active[:-1], 0.0, off)
        ab[2, :-1] = np.where(active[1:], 0.0, off)
        p = solve_banded((1, 1), ab, np.where(active, 0.0, -q))
        w = diag * p + q
        w[:-1] += off * p[1:]
        w[1:] += off * p[:-1]
        # settled when complementarity holds to rounding (degenerate nodes with
        # p = w = 0, e.g. in a flat pocket, would otherwise flip back and forth)
        tol_p = 1e-9 * max(float(np.max(np.abs(p))), op.p_inlet, op.p_outlet)
        tol_w = 1e-9 * float(np.max(cc))
        if np.all(p[~active] >= -tol_p) and np.all(w[active] >= -tol_w):
            return np.maximum(p, 0.0), active, it
        active = p - w / diag <= 0.0
    raise SolverError("FV Reynolds LCP: active set did not settle", where=f"{n} cells")


def fv_reynolds_lcp(
    gap: Gap, operating: SliderOperating, n_cells: int = 100_000, max_iter: int = 200
) -> FVSolution:
    """Reynolds-condition reference by finite volumes.

    The LCP ``p >= 0``, ``w = M p + q >= 0``, ``p w = 0`` at the interior nodes, ``M``
    the symmetric M-matrix of the cell conductances ``h^3 / (12 eta dx)`` (gap at cell
    midpoints), ``q`` the differences of the Couette fluxes ``U_m h``, solved by a
    primal-dual active-set method (banded solves) on nested grids (each level starts
    from the previous level's active set).
    """
    levels = _levels(n_cells)
    active, its, prev = None, 0, levels[0]
    for n in levels:
        p, active, it = _pdas_reynolds(gap, operating, n, _prolong(active, prev, n), max_iter)
        its += it
        prev = n
    x, kc, cc = _fv_setup(gap, operating, levels[-1])
    pf = np.concatenate(([operating.p_inlet], np.where(active, 0.0, p), [operating.p_outlet]))
    flux = cc - kc * np.diff(pf)
    cav = np.concatenate(([False], active, [False]))
    theta = np.ones(x.size)
    theta[cav] = flux[np.nonzero(cav)[0] - 1] / (operating.speed * gap(x[cav]))
    xc, xr = _fronts(x, cav)
    return FVSolution("reynolds", x, pf, theta, flux, float(np.trapezoid(pf, x)), xc, xr, its)


def _pdas_jfo(
    gap: Gap, op: SliderOperating, n: int, cav: np.ndarray, max_iter: int
) -> tuple[np.ndarray, np.ndarray, int]:
    _, kc, cc = _fv_setup(gap, op, n)
    i = np.arange(1, n)  # interior nodes
    for it in range(1, max_iter + 1):
        film = ~cav
        prev_film = np.concatenate(([True], film[:-1]))  # node i-1 (the inlet is film)
        next_film = np.concatenate((film[1:], [False]))  # node i+1 (outlet: known p)
        ab = np.zeros((3, n - 1))
        # c_i theta_i - k_i (p_{i+1} - p_i) - c_{i-1} theta_{i-1} + k_{i-1} (p_i - p_{i-1}) = 0
        ab[1] = np.where(film, kc[i] + kc[i - 1], cc[i])
        ab[2, :-1] = np.where(prev_film, -kc[i - 1], -cc[i - 1])[1:]
        ab[0, 1:] = np.where(next_film, -kc[i], 0.0)[:-1]
        rhs = np.where(film, -cc[i], 0.0) + np.where(prev_film, cc[i - 1], 0.0)
        rhs[0] += kc[0] * op.p_inlet
        rhs[-1] += kc[n - 1] * op.p_outlet
        z = solve_banded((1, 1), ab, rhs)
        tol_p = 1e-9 * max(float(np.max(np.abs(np.where(film, z, 0.0)))), op.p_inlet, op.p_outlet)
        to_cav = film & (z < -tol_p)
        to_film = cav & (z > 1.0 + 1e-9)
        if not (np.any(to_cav) or np.any(to_film)):
            return np.where(film, np.maximum(z, 0.0), z), cav, it
        cav = (cav | to_cav) & ~to_film
    raise SolverError("FV JFO LCP: active set did not settle", where=f"{n} cells")


def fv_jfo_lcp(
    gap: Gap, operating: SliderOperating, n_cells: int = 100_000, max_iter: int = 200
) -> FVSolution:
    """Mass-conserving (JFO) reference by finite volumes.

    Node balances ``F_i - F_{i-1} = 0`` with the cell fluxes
    ``F_j = U_m h_j theta_j - h_j^3 / (12 eta dx) (p_{j+1} - p_j)`` (upwind film
    fraction, gap at cell midpoints), ``p >= 0``, ``theta <= 1``, ``p (1 - theta) = 0``
    (the p-theta complementarity of Giacopini et al. 2010 and Almqvist et al. 2014).
    Each interior node is film (unknown ``p``, ``theta = 1``) or cavity (unknown
    ``theta``, ``p = 0``); for a given choice the system is tridiagonal.  The choice is
    updated (film with ``p < 0`` -> cavity, cavity with ``theta > 1`` -> film) until it
    settles, on nested grids as for :func:`fv_reynolds_lcp`.
    """
    levels = _levels(n_cells)
    cav, its, prev = None, 0, levels[0]
    for n in levels:
        z, cav, it = _pdas_jfo(gap, operating, n, _prolong(cav, prev, n), max_iter)
        its += it
        prev = n
    x, kc, cc = _fv_setup(gap, operating, levels[-1])
    p = np.concatenate(([operating.p_inlet], np.where(cav, 0.0, z), [operating.p_outlet]))
    th = np.concatenate(([1.0], np.where(cav, z, 1.0), [1.0]))
    flux = cc * th[:-1] - kc * np.diff(p)
    cavn = np.concatenate(([False], cav, [False]))
    xc, xr = _fronts(x, cavn)
    return FVSolution("jfo", x, p, th, flux, float(np.trapezoid(p, x)), xc, xr, its)


# ---------------------------------------------------------------- benchmarks
def pocket_slider_benchmark() -> tuple[Gap, SliderOperating]:
    """The pocketed pad of Almqvist, Fabricius, Larsson & Wall (J. Tribol. 2014), as
    set up in Almqvist's script "A cavitation algorithm" (MATLAB Central File
    Exchange 41484), incompressible limit.

    Parallel lands ``h0 = 1 um``, one pocket ``h1 = 10 um`` on ``a < x < a + b`` with
    ``a = 2 mm``, ``b = 3 mm``; ``L = 20 mm``; sliding speed ``V = 1 m/s`` with the
    other surface at rest (Couette flux ``h V / 2``, so ``U_m = 0.5 m/s``);
    ``mu = 0.01 Pa s``; cavitation pressure 50 kPa and boundary pressures 100 kPa
    (absolute), i.e. gauge ``p_in = p_out = 50 kPa`` here.  The published model is
    compressible (bulk modulus 0.5 GPa); the incompressible limit used here differs
    from it by O(p / beta) ~ 0.3 %.  No tabulated positions or loads were found in the
    accessible sources, so the values below are this module's (checked by hand, and
    against the finite-volume LCP to 1e-8):

    * JFO: ``Q = U_m h0 + h0^3 p_in / (12 mu a) = 5.0020833e-7 m^2/s``, rupture at the
      pocket's leading edge ``x_c = 2 mm``, starved pocket ``theta = 0.10004``,
      reformation ``x_r = 4.2129265 mm``, ``p_max = 425 kPa`` at 5 mm,
      load 3779.753 N/m.
    * Reynolds condition: same inlet zone (``Q_1 = 5.0020833e-7``), ``p = 0`` only at
      ``x = 2 mm``, pocket fully pressurised (``Q_2 = 5.0087205e-7``),
      ``p_max = 1.6196861 MPa`` at 5 mm, load 15002.17 N/m.
    """
    gap = textured_gap(20e-3, 1e-6, 1e-6, [(2e-3, 5e-3)], 9e-6)
    return gap, SliderOperating(speed=0.5, viscosity=0.01, p_inlet=50e3, p_outlet=50e3)


def textured_slider_case() -> tuple[Gap, SliderOperating]:
    """Own case (not from the literature): a slightly converging textured slider.

    ``L = 5 mm``, land gap 5.1 um at the inlet to 5.0 um at the outlet, one pocket of
    depth 5 um on ``1 mm < x < 2.5 mm``, ``U_m = 0.5 m/s``, ``eta = 0.1 Pa s``, supply
    pressure ``p_in = 0.2 MPa``, ``p_out = 0``.  The film ruptures at the pocket's
    divergent edge; JFO re-forms it inside the pocket (a starved pocket, about a
    quarter of the load), the Reynolds condition re-pressurises the whole pocket:

    * JFO: ``Q = 2.5669687e-6 m^2/s``, ``x_c = 1 mm``, ``theta = 0.5093`` after the
      edge, ``x_r = 2.0560949 mm``, ``p_max = 1.289369 MPa`` at 2.5 mm,
      load 2136.793 N/m.
    * Reynolds: ``Q_1 = 2.5669687e-6``, ``x_c = x_r = 1 mm``, ``Q_2 = 2.6875176e-6``,
      ``p_max = 4.139717 MPa`` at 2.5 mm, load 8534.786 N/m.
    """
    gap = textured_gap(5e-3, 5.1e-6, 5.0e-6, [(1.0e-3, 2.5e-3)], 5e-6)
    return gap, SliderOperating(speed=0.5, viscosity=0.1, p_inlet=0.2e6, p_outlet=0.0)
