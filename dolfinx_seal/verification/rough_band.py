"""A 2D cavitating film on a rough band: a finite-volume reference, numpy/scipy only.

Written apart from the FEM code, to check the leakage of its mass-conserving (JFO)
film on a resolved rough band (the lip sector's two-scale band) against a
different discretisation that is monotone by construction.

The band ``0 <= x <= L`` (sliding direction, periodic with period ``L``),
``0 <= y <= W`` (across the band: the sealed pressure ``p_oil`` on ``y = 0``,
``p_air`` on ``y = W``), rigid walls with the gap ``h(x, y)`` of a
:class:`BandGap`, the counter-surface sliding along ``x`` at ``U`` (mean speed
``U_m = U / 2``).  Steady JFO (Elrod-Adams):

    div( -h^3 / (12 eta) grad p + U_m h theta e_x ) = 0,
    p >= 0,  0 <= theta <= 1,  p (1 - theta) = 0

(gauge pressures above the cavitation pressure).  The leakage is the net flow
through ``y = W`` per period ``L`` [m^3/s].

Scheme (:func:`fv_jfo_band`): vertex-centred finite volumes on a uniform grid,
``nx`` nodes per period by ``ny + 1`` rows.  The face fluxes are

    F_x = -k_f (p_E - p_P) / dx + U_m h_f theta_up,   F_y = -k_f (p_N - p_P) / dy,

with ``h_f`` the gap at the face midpoint, ``k_f = h_f^3 / (12 eta)`` and
``theta_up`` the film fraction of the upwind node: the first-order upwind
Elrod-Adams scheme (Giacopini et al., J. Tribol. 132, 2010; Almqvist et al.,
Tribol. Int. 2014, in 1D), whose Jacobian is an M-matrix for every active set.
In Elrod's variable ``phi`` (``p = max(phi, 0)``, ``theta = 1 + min(phi, 0) / p_s``)
the balances are a piecewise-linear M-function, and the semismooth Newton (on a
fixed set, one linear solve) stops when its set repeats (Brugnano and Casulli,
SIAM J. Sci. Comput. 30, 2008).  It starts from the full film of a coarser grid
(nested grids).  The leakage, the inflow through ``y = 0`` and their difference
(the mass balance, exact up to the linear solve) come out of the same face fluxes.
First order: the error falls like ``dx`` near cavitation fronts, so the
reference at a given grid is extrapolated from two (:func:`richardson`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.params import check_int_range, check_nonnegative, check_positive, check_range


@dataclass(frozen=True)
class BandGap:
    """Gap ``h(x, y)`` [m] of a rough band: a macro profile across the band, and
    roughness periodic along it.

    ``h = h_c + (y - y_c)^2 / (2 R) - sum_k a_k cos(2 pi (m_k x / L + n_k y / W) + phi_k)``

    Attributes:
        length: Period ``L`` along the sliding direction [m].
        width: Band width ``W`` [m].
        h_centre: Macro gap ``h_c`` at ``y_c`` [m].
        y_centre: Position ``y_c`` of the macro minimum across the band [m].
        radius: Radius ``R`` of the macro profile across the band [m].
        modes: Roughness modes ``(m, n, a, phi)``: integer wave numbers along
            (``m``, any sign) and across (``n``) the band, amplitude ``a`` [m],
            phase [rad].
    """

    length: float
    width: float
    h_centre: float
    y_centre: float
    radius: float
    modes: tuple[tuple[int, int, float, float], ...] = field(default=())

    def __post_init__(self) -> None:
        check_positive("length", self.length, "m")
        check_positive("width", self.width, "m")
        check_positive("h_centre", self.h_centre, "m")
        check_range("y_centre", self.y_centre, 0.0, self.width, unit="m")
        check_positive("radius", self.radius, "m")
        for m, n, a, _ in self.modes:
            if int(m) != m or int(n) != n:
                raise ParameterError(f"modes: wave numbers ({m}, {n}) must be integers")
            check_nonnegative("modes.amplitude", a, "m")
        X, Y = np.meshgrid(np.linspace(0.0, self.length, 513), np.linspace(0.0, self.width, 513))
        h = self(X, Y)
        if h.min() <= 0.0:
            k = np.argmin(h)
            raise ParameterError(
                f"h_centre = {self.h_centre:g} m: the gap closes (h = {h.flat[k]:.3g} m at "
                f"x = {X.flat[k]:.3g}, y = {Y.flat[k]:.3g} m); raise h_centre"
            )

    def macro(self, y: np.ndarray) -> np.ndarray:
        return self.h_centre + (y - self.y_centre) ** 2 / (2.0 * self.radius)

    def __call__(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        x, y = np.asarray(x, float), np.asarray(y, float)
        h = self.macro(y)
        for m, n, a, phi in self.modes:
            h = h - a * np.cos(2.0 * math.pi * (m * x / self.length + n * y / self.width) + phi)
        return h

    def ufl(self, x: Sequence[object]) -> object:
        """The same gap as a UFL expression of the coordinates ``x[0], x[1]``."""
        import ufl

        h = self.h_centre + (x[1] - self.y_centre) ** 2 / (2.0 * self.radius)
        for m, n, a, phi in self.modes:
            h = h - a * ufl.cos(2.0 * math.pi * (m * x[0] / self.length + n * x[1] / self.width)
                                + phi)  # fmt: skip
        return h


@dataclass(frozen=True)
class BandOperating:
    """Operating conditions of the band.

    Attributes:
        speed: Sliding speed ``U`` of the counter-surface along ``x`` [m/s]
            (mean speed ``U / 2``), non-zero.
        viscosity: Dynamic viscosity [Pa s].
        p_oil: Pressure on ``y = 0`` [Pa] (gauge, above cavitation).
        p_air: Pressure on ``y = W`` [Pa].
    """

    speed: float
    viscosity: float = 0.1
    p_oil: float = 0.0
    p_air: float = 0.0

    def __post_init__(self) -> None:
        if self.speed == 0.0 or not math.isfinite(self.speed):
            raise ParameterError(f"speed = {self.speed!r} m/s: must be finite and non-zero")
        check_positive("viscosity", self.viscosity, "Pa s")
        check_nonnegative("p_oil", self.p_oil, "Pa")
        check_nonnegative("p_air", self.p_air, "Pa")


@dataclass(frozen=True)
class BandSolution:
    """A solved band: nodal fields on the ``(ny + 1) x nx`` grid and the flows.

    ``leakage`` [m^3/s per period]: the flow out through ``y = W``; ``inflow``: in
    through ``y = 0``; ``load`` [N per period]: integral of ``p``;
    ``cavitation_fraction``: share of the band's area with ``theta < 1``;
    ``newton``: semismooth Newton steps over all grids.
    """

    x: np.ndarray
    y: np.ndarray
    p: np.ndarray
    theta: np.ndarray
    leakage: float
    inflow: float
    load: float
    cavitation_fraction: float
    newton: int

    @property
    def mass_balance_error(self) -> float:
        return abs(self.inflow - self.leakage) / max(abs(self.inflow), abs(self.leakage))


class _Grid:
    """Face coefficients and the linear balances ``A_p p + A_t theta + b`` of the
    interior rows (``j = 1 .. ny - 1``, node ``k = (j - 1) nx + i``)."""

    def __init__(self, gap: BandGap, op: BandOperating, nx: int, ny: int) -> None:
        self.nx, self.ny = nx, ny
        L, W = gap.length, gap.width
        self.dx, self.dy = L / nx, W / ny
        self.x = np.arange(nx) * self.dx
        self.y = np.arange(ny + 1) * self.dy
        eta, um = op.viscosity, 0.5 * op.speed
        dx, dy = self.dx, self.dy
        n = nx * (ny - 1)
        idx = np.arange(n).reshape(ny - 1, nx)
        east = np.roll(idx, -1, axis=1)
        # x faces i + 1/2 of the interior rows: Poiseuille and Couette
        X, Y = np.meshgrid(self.x + 0.5 * dx, self.y[1:-1])
        hx = gap(X, Y)
        kx = hx**3 / (12.0 * eta) * dy / dx
        cx = um * hx * dy
        P, E = idx.ravel(), east.ravel()
        kx, cx = kx.ravel(), cx.ravel()
        # y faces j + 1/2, j = 0 .. ny - 1
        X, Y = np.meshgrid(self.x, self.y[:-1] + 0.5 * dy)
        self.ky = gap(X, Y) ** 3 / (12.0 * eta) * dx / dy  # (ny, nx)
        rows, cols, vals = [], [], []

        def add(r, c, v):
            rows.append(r)
            cols.append(c)
            vals.append(v)

        # outflow of P through its east face, inflow of E through its west face
        add(P, P, kx)
        add(P, E, -kx)
        add(E, E, kx)
        add(E, P, -kx)
        for j in range(ny - 1):  # y faces between interior rows
            lo, hi, k = idx[j], idx[j + 1] if j + 1 < ny - 1 else None, self.ky[j + 1]
            add(lo, lo, k)
            if hi is not None:
                add(lo, hi, -k)
                add(hi, hi, k)
                add(hi, lo, -k)
        # the face below the first interior row (to the oil row)
        add(idx[0], idx[0], self.ky[0])
        self.A_p = sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
        )
        up = P if um > 0 else E
        # Couette flux U_m h_f theta_up out of P through its east face, into E
        self.A_t = sp.csr_matrix(
            (np.concatenate([cx, -cx]), (np.concatenate([P, E]), np.concatenate([up, up]))),
            shape=(n, n),
        )
        b = np.zeros((ny - 1, nx))
        b[0] -= self.ky[0] * op.p_oil
        b[-1] -= self.ky[-1] * op.p_air
        self.b = b.ravel()
        self.op = op

    def flows(self, p_int: np.ndarray) -> tuple[float, float]:
        """Inflow through ``y = 0`` and outflow through ``y = W`` [m^3/s per period]."""
        p = p_int.reshape(self.ny - 1, self.nx)
        inflow = float(np.sum(self.ky[0] * (self.op.p_oil - p[0])))
        outflow = float(np.sum(self.ky[-1] * (p[-1] - self.op.p_air)))
        return inflow, outflow


def _solve_grid(grid: _Grid, phi: np.ndarray, p_s: float, max_iter: int) -> tuple[np.ndarray, int]:
    """Semismooth Newton in Elrod's variable on one grid, from ``phi``."""
    film = phi > 0.0
    for it in range(1, max_iter + 1):
        # on a fixed set the balances are linear in phi: one solve
        J = grid.A_p @ sp.diags(film.astype(float)) + grid.A_t @ sp.diags((~film) / p_s)
        rhs = -grid.b - grid.A_t @ np.ones(film.size)
        phi = spla.spsolve(J.tocsc(), rhs)
        if not np.all(np.isfinite(phi)):
            raise SolverError("the finite-volume band film's linear solve gave NaN",
                              f"fv_jfo_band, {grid.nx} x {grid.ny} grid, step {it}")  # fmt: skip
        new = phi > 0.0
        if np.array_equal(new, film):
            return phi, it
        film = new
    raise SolverError(
        f"the finite-volume band film's active set did not settle in {max_iter} steps",
        f"fv_jfo_band, {grid.nx} x {grid.ny} grid",
    )


def _prolong(phi: np.ndarray, coarse: _Grid, fine: _Grid) -> np.ndarray:
    """Bilinear interpolation of the interior ``phi`` (periodic in x)."""
    from scipy.interpolate import RegularGridInterpolator

    nxc, nyc = coarse.nx, coarse.ny
    full = np.zeros((nyc + 1, nxc + 1))
    full[1:-1, :-1] = phi.reshape(nyc - 1, nxc)
    full[0, :-1] = coarse.op.p_oil
    full[-1, :-1] = coarse.op.p_air
    full[:, -1] = full[:, 0]
    xs = np.append(coarse.x, coarse.x[-1] + coarse.dx)
    f = RegularGridInterpolator((coarse.y, xs), full)
    Y, X = np.meshgrid(fine.y[1:-1], fine.x, indexing="ij")
    return f(np.stack([Y.ravel(), X.ravel()], axis=1))


def fv_jfo_band(
    gap: BandGap, op: BandOperating, nx: int, ny: int, max_iter: int = 200
) -> BandSolution:
    """The JFO band film on an ``nx`` (per period) by ``ny`` (across) cell grid."""
    check_int_range("nx", nx, 8)
    check_int_range("ny", ny, 4)
    # pressure scale of theta in Elrod's variable: any positive value gives the
    # same solution; one of the film's own pressures keeps the system balanced
    p_s = max(op.p_oil, op.p_air, 6.0 * op.viscosity * abs(op.speed) * gap.length
              / gap.h_centre**2)  # fmt: skip
    levels = [(nx, ny)]
    while levels[-1][0] % 2 == 0 and levels[-1][1] % 2 == 0 and levels[-1][0] > 32:
        levels.append((levels[-1][0] // 2, levels[-1][1] // 2))
    levels.reverse()
    prev, phi, steps = None, None, 0
    for gx, gy in levels:
        grid = _Grid(gap, op, gx, gy)
        if prev is None:  # the full film (no cavitation) of the coarsest grid
            phi = spla.spsolve(grid.A_p.tocsc(), -grid.b - grid.A_t @ np.ones(gx * (gy - 1)))
        else:
            phi = _prolong(phi, prev, grid)
        phi, it = _solve_grid(grid, phi, p_s, max_iter)
        steps += it
        prev = grid
    p = np.maximum(phi, 0.0)
    theta = 1.0 + np.minimum(phi, 0.0) / p_s
    inflow, outflow = prev.flows(p)
    P = np.zeros((ny + 1, nx))
    T = np.ones((ny + 1, nx))
    P[0], P[-1] = op.p_oil, op.p_air
    P[1:-1] = p.reshape(ny - 1, nx)
    T[1:-1] = theta.reshape(ny - 1, nx)
    # nodal areas: the boundary rows are half cells
    w = np.full(ny + 1, prev.dy)
    w[0] = w[-1] = 0.5 * prev.dy
    area = np.broadcast_to(w[:, None] * prev.dx, P.shape)
    load = float(np.sum(P * area))
    cav = float(np.sum(area * (T < 1.0)) / np.sum(area))
    return BandSolution(prev.x, prev.y, P, T, outflow, inflow, load, cav, steps)


def rough_band_case(speed: float) -> tuple[BandGap, BandOperating]:
    """Own case (not from the literature), scaled to the lip sector's band.

    One period ``L = 200 um`` (S0's ``lambda_0``), band ``W = 240 um``, a macro
    gap of radius 5 mm with its minimum 1.95 um at ``y = 132 um``, and six
    roughness modes of wavelengths 50-200 um along the band, most of them oblique
    (so that sliding pumps oil across the band), amplitudes 0.25-0.6 um: the gap
    runs from 0.17 um at the tightest crest to about 6 um.  Oil (0.05 MPa, S0's
    sealed pressure) on ``y = 0``, air on ``y = W``, ``eta = 0.1 Pa s``.  The
    leakage falls with speed (sliding pumps oil back) from 4.3e-13 m^3/s per
    period at 0.01 m/s to 2.4e-14 at 1 m/s, with 13 % to 76 % of the band cavitated.
    """
    modes = (
        (1, 0, 0.60e-6, 0.5381), (2, 1, 0.50e-6, 1.4879), (3, -1, 0.40e-6, 5.0346),
        (1, 2, 0.50e-6, 3.6578), (2, -2, 0.30e-6, 0.5914), (4, 1, 0.25e-6, 2.7214),
    )  # fmt: skip
    gap = BandGap(200e-6, 240e-6, h_centre=1.95e-6, y_centre=132e-6, radius=5e-3, modes=modes)
    return gap, BandOperating(speed=speed, viscosity=0.1, p_oil=0.05e6, p_air=0.0)


def richardson(coarse: float, fine: float, ratio: float = 2.0, order: float = 1.0) -> float:
    """Richardson extrapolation of two values on grids ``ratio`` apart."""
    return fine + (fine - coarse) / (ratio**order - 1.0)


__all__ = [
    "BandGap",
    "BandOperating",
    "BandSolution",
    "fv_jfo_band",
    "richardson",
    "rough_band_case",
]
