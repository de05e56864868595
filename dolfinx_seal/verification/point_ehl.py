"""Smooth soft elastohydrodynamic point contact (a ball sliding on a flat, S1
section 3), an independent reference solver: finite volumes + half-space influence
coefficients, numpy/scipy only (no DOLFINx).

Written apart from the FEM ball scene (:mod:`dolfinx_seal.scenes.ball`), with a
different discretisation, to check it; the point-contact twin of
:mod:`dolfinx_seal.verification.line_ehl`.  SI units throughout.

Model
-----
* A rigid flat and an elastic ball of radius ``R``, the ball represented as an
  elastic half-space of effective modulus ``E*`` (Boussinesq).  Rubber is
  incompressible (nu = 0.5), so the tangential (shear) tractions do not move the
  surface normally: only the fluid pressure enters the elasticity.  No asperity
  contact (smooth surfaces): the film carries the whole load.
* Undeformed gap: the sphere, ``R - (R^2 - r^2)^(1/2)`` (``sphere = True``, as the
  FEM mesh), or the paraboloid ``r^2 / (2 R)`` of Hertz theory.
* Grid: square cells of side ``d = a_H / cells_per_radius`` (``a_H`` the Hertz
  radius ``(3 F R / (4 E*))^(1/3)``) on the half plane ``y > 0`` (``y = 0`` is a
  plane of symmetry containing the sliding direction x); the lubricated zone is
  the disc ``r < extent a_H`` (the FEM ball's lubricated cap, ``film_extent``), made
  of the cells whose centres lie inside it.  Pressures are piecewise constant per
  cell, gaps taken at the cell centres.
* Gap: ``h_i = u0 + rigid_i + sum_j K_ij p_j`` with the exact influence
  coefficients of a uniform pressure on a rectangle of a half-space (Love 1929;
  Johnson, Contact Mechanics, eq 3.25), ``w = (1/(pi E*)) int p / |x - s| dA``,
  plus those of the mirror cells ``y -> -y``.
* Reynolds (steady, isoviscous, incompressible): the flat slides at ``U`` along x
  under the ball at rest, mean velocity ``U/2``; flux per unit width ``q =
  -(h^3/(12 eta)) grad p + (U h / 2) e_x``.  Conservative finite volumes: the face
  conductivity is the arithmetic mean of ``h^3`` of the two cells over ``12 eta``,
  the Couette face flux is second-order upwind, ``U (3 h_L - h_LL) / 4`` (``L`` the
  cell upstream of the face, ``LL`` the one before it; first order, ``U h_L / 2``,
  where there is none).  The central flux ``U (h_L + h_R) / 4`` of the line solver
  oscillates from cell to cell in the outlet of this contact (Moes M ~ 500 at
  0.15 m/s for the S1 ball: the gap alternated 6.0 / 6.5 / 5.2 / 7.9 / 1.1 um along
  the axis), the instability of central wedge terms at small ``h^3 / (12 eta)``
  known from EHL solvers (Venner & Lubrecht).  On a face to a cell outside the disc
  ``p = 0`` half a cell away, with the gap of the inner cell; no flux across ``y = 0``.
* Cavitation ``"reynolds"`` (``p >= 0``, ``min(p_i, r_i / D_i) = 0`` with ``r_i``
  the net outflow of cell ``i`` and ``D_i = d r_i / d p_i`` frozen at the start of
  the solve, as in the line solver) or ``"none"``.
* Load: ``2 sum_i p_i d^2 = F`` (the two halves), ``u0`` the extra unknown.
* Newton on ``(p / p_H, u0 / h_s)`` with the gap eliminated (``h`` is linear in
  them): a dense Jacobian ``dr/dp + (dr/dh) K``, LU; the gap may shrink by at most
  90 % per step; damping by the natural monotonicity test (Deuflhard).
* Friction on the moving flat: ``int [eta U / h + (h / 2) dp/dx] dA`` over the
  zone (S1 eq 29 without asperities), the Couette part also in cavitated cells
  (flooded), the Poiseuille part summed over the x faces.
* Outputs as the FEM's: ``h_min`` (smallest cell-centre gap), ``h_central`` (the
  gap at x = y = 0, interpolated with the mirror cells), ``mu``, the contact radius
  ``(5 <r^2> / 2)^(1/2)`` of the pressure, ``x_cavitation`` on the axis.

The cost grows as ``N^3`` with the ``N ~ 1.57 (extent cells_per_radius)^2`` cells
of the half disc (extent 2: 15 / 20 / 30 cells per radius give 1.4k / 2.5k / 5.7k
cells).  Measured on the S1 ball at a tenth of its load (F = 0.13 N, extent 2, 10
to 0.1 m/s, Moes M 1.7 to 53), the outputs converge at second order: h_central at
0.1 m/s 7.203 / 7.271 / 7.317 um on 15 / 20 / 30 cells per radius, mu 0.044216 /
0.043981 / 0.043832, h_min 5.347 / 5.395 / 5.390 um; the Richardson value of 15 and
20 (:func:`richardson`) is within 0.1 % of that of 20 and 30.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import LinAlgError, lu_factor, lu_solve
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.linalg import spsolve

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range

FloatArray = NDArray[np.float64]

CAVITATION_MODELS = ("none", "reynolds")


@dataclass(frozen=True)
class PointEHLParameters:
    """Parameters of the smooth soft-EHL point contact (SI units).

    Attributes:
        radius: Ball radius R [m].
        load: Normal load F [N] (the whole ball; the solver models the half y > 0).
        e_star: Effective modulus ``E* = E / (1 - nu^2)`` [Pa].
        viscosity: Dynamic viscosity eta [Pa s].
        cavitation: ``"none"`` (full Sommerfeld) or ``"reynolds"`` (p >= 0).
        cells_per_radius: Cells per Hertz radius [-].
        extent: Radius of the lubricated disc in Hertz radii [-].
        sphere: Undeformed gap of the sphere (True) or of the paraboloid ``r^2/(2R)``.
        tol: Newton tolerance on the max norm of the scaled residual [-].
        max_iter: Maximum Newton iterations per solve [-].
    """

    radius: float = 0.01
    load: float = 1.3
    e_star: float = 1.2e6 / 0.75
    viscosity: float = 0.1
    cavitation: str = "reynolds"
    cells_per_radius: int = 15
    extent: float = 3.0
    sphere: bool = True
    tol: float = 1e-9
    max_iter: int = 80

    def __post_init__(self) -> None:
        check_positive("radius", self.radius, "m")
        check_positive("load", self.load, "N")
        check_positive("e_star", self.e_star, "Pa")
        check_positive("viscosity", self.viscosity, "Pa s")
        check_choice("cavitation", self.cavitation, CAVITATION_MODELS)
        check_int_range("cells_per_radius", self.cells_per_radius, 4, 40)
        check_range("extent", self.extent, 1.5, 6.0)
        if self.extent * self.hertz_radius >= self.radius:
            raise ParameterError(
                f"extent = {self.extent!r}: the lubricated disc ({self.extent * self.hertz_radius:.3g}"
                f" m) must be smaller than the ball radius {self.radius!r} m", "extent",
            )  # fmt: skip
        check_range("tol", self.tol, 1e-14, 1e-3)
        check_int_range("max_iter", self.max_iter, 1, 1000)

    @property
    def hertz_radius(self) -> float:
        """Hertz contact radius ``a_H = (3 F R / (4 E*))^(1/3)`` [m]."""
        return (3.0 * self.load * self.radius / (4.0 * self.e_star)) ** (1.0 / 3.0)

    @property
    def hertz_peak_pressure(self) -> float:
        """Hertz peak pressure ``p_H = 3 F / (2 pi a_H^2)`` [Pa]."""
        return 1.5 * self.load / (math.pi * self.hertz_radius**2)


@dataclass(frozen=True, eq=False)
class PointEHLResult:
    """One converged point (arrays per cell of the half disc, centres ``x``, ``y``).

    Attributes:
        speed: Sliding speed U [m/s].
        x, y: Cell centres [m].
        p: Fluid pressure [Pa].
        h: Gap [m].
        u0: Approach (gap at the origin without the elastic deflection) [m].
        normal_load: ``2 int p dA`` [N].
        h_min, h_central: Smallest gap and the gap at x = y = 0 [m].
        max_pressure: [Pa].
        contact_radius: ``(5 <r^2> / 2)^(1/2)`` of the pressure [m] (Hertz: a_H).
        friction_couette, friction_poiseuille, friction: On the moving flat [N].
        mu, mu_couette, mu_poiseuille: ``friction / normal_load`` [-].
        x_cavitation: Film rupture on the axis (first cavitated cell face after the
            pressure peak of the row next to y = 0) [m]; nan without cavitation.
        cavitation_fraction: Area fraction of cavitated cells [-].
        mass_balance_error: Largest net outflow of a full-film cell over the Couette
            flux ``U h_min d / 2`` through one cell face [-].
        newton_iterations: Newton iterations of this solve.
    """

    speed: float
    x: FloatArray
    y: FloatArray
    p: FloatArray
    h: FloatArray
    u0: float
    normal_load: float
    h_min: float
    h_central: float
    max_pressure: float
    contact_radius: float
    friction_couette: float
    friction_poiseuille: float
    friction: float
    mu: float
    mu_couette: float
    mu_poiseuille: float
    x_cavitation: float
    cavitation_fraction: float
    mass_balance_error: float
    newton_iterations: int

    def summary(self) -> dict[str, float | int]:
        """The scalar outputs (for tables)."""
        return {k: v for k, v in self.__dict__.items() if k not in ("x", "y", "p", "h")}


def _love(x: FloatArray, y: FloatArray, a: float, b: float) -> FloatArray:
    """``pi E* w / p`` at ``(x, y)`` under a uniform pressure ``p`` on the rectangle
    ``|xi| <= a, |eta| <= b`` of a half-space (Johnson eq 3.25), vectorised."""

    def f(u: FloatArray, v: FloatArray) -> FloatArray:
        # the antiderivative of 1/r over the quadrant, u ln(v + r) + v ln(u + r)
        r = np.sqrt(u * u + v * v)
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = np.where(u == 0.0, 0.0, u * np.log(np.abs(v + r)))
            t2 = np.where(v == 0.0, 0.0, v * np.log(np.abs(u + r)))
        return t1 + t2

    return f(x + a, y + b) - f(x - a, y + b) - f(x + a, y - b) + f(x - a, y - b)


class PointEHL:
    """The discrete smooth soft-EHL point contact for one parameter set."""

    def __init__(self, params: PointEHLParameters) -> None:
        self.params = pr = params
        self.a = pr.hertz_radius
        self.p_scale = pr.hertz_peak_pressure
        self.d = d = self.a / pr.cells_per_radius
        rmax = pr.extent * self.a
        m = math.ceil(rmax / d)
        ix = np.arange(-m, m)  # cell i spans [i d, (i+1) d]: an even count across, x = 0 a face
        iy = np.arange(0, m)
        cx, cy = np.meshgrid((ix + 0.5) * d, (iy + 0.5) * d, indexing="ij")
        inside = cx**2 + cy**2 < rmax**2
        self.x, self.y = cx[inside], cy[inside]
        self.n = n = self.x.size
        index = -np.ones(cx.shape, dtype=np.int64)
        index[inside] = np.arange(n)
        self._index = index
        self.area = d * d
        r2 = self.x**2 + self.y**2
        if pr.sphere:
            self.rigid = pr.radius - np.sqrt(pr.radius**2 - r2)
        else:
            self.rigid = r2 / (2.0 * pr.radius)
        # influence coefficients with the mirror cells (y -> -y), from the lattice of
        # cell offsets: K_ij = L(ix_i - ix_j, iy_i - iy_j) + L(ix_i - ix_j, iy_i + iy_j + 1)
        gx, gy = (
            (ix[:, None] * np.ones_like(iy)[None, :])[inside],
            (iy[None, :] * np.ones_like(ix)[:, None])[inside],
        )
        ox = np.arange(-(2 * m - 1), 2 * m)
        oy = np.arange(-(m - 1), 2 * m)
        lat = _love(ox[:, None] * d, oy[None, :] * d, 0.5 * d, 0.5 * d) / (math.pi * pr.e_star)
        dxi = gx[:, None] - gx[None, :] + (2 * m - 1)
        self.kernel = lat[dxi, gy[:, None] - gy[None, :] + (m - 1)]
        self.kernel += lat[dxi, gy[:, None] + gy[None, :] + 1 + (m - 1)]
        self._faces()

    def _faces(self) -> None:
        """Face lists: x faces (left cell, right cell or -1 outside), y faces (lower,
        upper or -1 outside); no face at y = 0 (symmetry)."""
        idx = self._index
        left, right = idx[:-1, :], idx[1:, :]
        keep = (left >= 0) | (right >= 0)
        self.fx = (left[keep], right[keep])
        # the domain's ends in x (first and last column) border the outside
        first, last = idx[0, :], idx[-1, :]
        lleft = np.vstack([-np.ones((1, idx.shape[1]), np.int64), idx[:-2, :]])[keep]
        self.fx = (
            np.concatenate([self.fx[0], -np.ones(int((first >= 0).sum()), np.int64), last[last >= 0]]),
            np.concatenate([self.fx[1], first[first >= 0], -np.ones(int((last >= 0).sum()), np.int64)]),
        )  # fmt: skip
        # the cell upstream of each x face's left cell (-1: none), for the upwind flux
        n_end = int((first >= 0).sum()) + int((last >= 0).sum())
        self.fx_upstream = np.concatenate([lleft, -np.ones(n_end, np.int64)])
        low, up = idx[:, :-1], idx[:, 1:]
        keep = (low >= 0) | (up >= 0)
        top = idx[:, -1]
        self.fy = (
            np.concatenate([low[keep], top[top >= 0]]),
            np.concatenate([up[keep], -np.ones(int((top >= 0).sum()), np.int64)]),
        )

    # ------------------------------------------------------------ discrete model
    def gap(self, p: FloatArray, u0: float) -> FloatArray:
        """Gap [m] at the cell centres for pressures ``p`` [Pa] and approach ``u0`` [m]."""
        return u0 + self.rigid + self.kernel @ p

    def _fluxes(self, p: FloatArray, h: FloatArray, speed: float
                ) -> tuple[FloatArray, csr_matrix, csr_matrix]:  # fmt: skip
        """Net outflow ``r`` [m^3/s] of every cell and its sparse derivatives in p and h."""
        n, d = self.n, self.d
        c = 1.0 / (12.0 * self.params.viscosity)
        r = np.zeros(n)
        rows, cols, vp, vh = [], [], [], []

        def add(i: NDArray[np.int64], j: NDArray[np.int64], s: float, q: FloatArray,
                dq: dict[str, tuple[NDArray[np.int64], FloatArray, FloatArray]]) -> None:  # fmt: skip
            # face flux q (positive from i to j) leaves i and enters j, times the face length
            for cell, sign in ((i, 1.0), (j, -1.0)):
                ok = cell >= 0
                np.add.at(r, cell[ok], sign * s * q[ok])
                for who, dqp, dqh in dq.values():
                    both = ok & (who >= 0)
                    rows.append(cell[both])
                    cols.append(who[both])
                    vp.append(sign * s * dqp[both])
                    vh.append(sign * s * dqh[both])

        for faces, couette in ((self.fx, True), (self.fy, False)):
            i, j = faces
            both = (i >= 0) & (j >= 0)
            pi_ = np.where(i >= 0, p[np.maximum(i, 0)], 0.0)
            pj = np.where(j >= 0, p[np.maximum(j, 0)], 0.0)
            hi = np.where(i >= 0, h[np.maximum(i, 0)], h[np.maximum(j, 0)])
            hj = np.where(j >= 0, h[np.maximum(j, 0)], h[np.maximum(i, 0)])
            dist = np.where(both, d, 0.5 * d)
            k = np.where(both, 0.5 * c * (hi**3 + hj**3), c * np.where(i >= 0, hi, hj) ** 3)
            grad = (pj - pi_) / dist
            q = -k * grad
            # d q / d (p_i, p_j, h_i, h_j); an outside cell's gap is the inner cell's
            dk_i = np.where(both, 1.5 * c * hi**2, np.where(i >= 0, 3.0 * c * hi**2, 0.0))
            dk_j = np.where(both, 1.5 * c * hj**2, np.where(j >= 0, 3.0 * c * hj**2, 0.0))
            dq_dpi, dq_dpj = k / dist, -k / dist
            dq_dhi, dq_dhj = -dk_i * grad, -dk_j * grad
            dq = {}
            if couette and speed != 0.0:  # second-order upwind (U > 0: from the left)
                ll = self.fx_upstream
                two = both & (ll >= 0)
                hll = np.where(two, h[np.maximum(ll, 0)], 0.0)
                up = np.where(i >= 0, hi, hj)  # the inflow end takes its inner cell
                q = q + 0.5 * speed * np.where(two, 1.5 * hi - 0.5 * hll, up)
                dq_dhi = dq_dhi + 0.5 * speed * np.where(two, 1.5, np.where(i >= 0, 1.0, 0.0))
                dq_dhj = dq_dhj + 0.5 * speed * np.where(i >= 0, 0.0, 1.0)
                dq["ll"] = (
                    np.where(two, ll, -1),
                    np.zeros_like(q),
                    np.where(two, -0.25 * speed, 0.0),
                )
            dq.update(i=(i, dq_dpi, dq_dhi), j=(j, dq_dpj, dq_dhj))
            add(i, j, d, q, dq)
        rr, cc = np.concatenate(rows), np.concatenate(cols)
        a_p = coo_matrix((np.concatenate(vp), (rr, cc)), shape=(n, n)).tocsr()
        a_h = coo_matrix((np.concatenate(vh), (rr, cc)), shape=(n, n)).tocsr()
        return r, a_p, a_h

    def _system(self, z: FloatArray, speed: float, film: FloatArray, h_s: float,
                jacobian: bool = True) -> tuple[FloatArray, FloatArray | None, FloatArray]:  # fmt: skip
        """Scaled residual (film rows, load row), its Jacobian and the gap."""
        n, ps, pr = self.n, self.p_scale, self.params
        p, u0 = z[:n] * ps, float(z[n]) * h_s
        h = self.gap(p, u0)
        r, a_p, a_h = self._fluxes(p, h, speed)
        rs = r / film
        use_r = rs <= p / ps if pr.cavitation == "reynolds" else np.ones(n, dtype=bool)
        res = np.empty(n + 1)
        res[:n] = np.where(use_r, rs, p / ps)
        res[n] = (2.0 * self.area * p.sum() - pr.load) / pr.load
        if not jacobian:
            return res, None, h
        jac = np.zeros((n + 1, n + 1))
        jp = (a_p.toarray() + a_h @ self.kernel) * (ps / film)[:, None]
        ju = np.asarray(a_h.sum(axis=1)).ravel() * h_s / film
        jac[:n, :n] = np.where(use_r[:, None], jp, np.eye(n))
        jac[:n, n] = np.where(use_r, ju, 0.0)
        jac[n, :n] = 2.0 * self.area * ps / pr.load
        return res, jac, h

    def _film_diagonal(self, h: FloatArray, speed: float) -> FloatArray:
        """``D_i = d r_i / d p_i`` at the gap ``h`` [m^3/(s Pa)] (the row scales)."""
        _, a_p, _ = self._fluxes(np.zeros(self.n), h, speed)
        return a_p.diagonal()

    # ------------------------------------------------------------------ guesses
    def hertz_guess(self, speed: float) -> tuple[FloatArray, float]:
        """``(p, u0)``: the Hertz pressure, with the flat at the Hamrock-Dowson central
        film (isoviscous-elastic, ``u_m = U/2``) below the Hertz-deformed ball."""
        from dolfinx_seal.verification.ehl import IsoviscousElasticFilm

        pr = self.params
        r2 = (self.x**2 + self.y**2) / self.a**2
        p_hz = self.p_scale * np.sqrt(np.clip(1.0 - r2, 0.0, None))
        shape = self.rigid + self.kernel @ p_hz
        hd = IsoviscousElasticFilm(pr.radius, pr.e_star, pr.viscosity, pr.load)
        centre = float(shape[np.argmin(self.x**2 + self.y**2)])
        return p_hz, hd.h_central(0.5 * speed) - centre

    def film_pressure(self, h: FloatArray, speed: float) -> FloatArray:
        """The film pressure [Pa] of the fixed gap ``h`` (a linear complementarity
        problem with the Reynolds condition: active-set iteration)."""
        n = self.n
        p = np.zeros(n)
        film = self._film_diagonal(h, speed)
        active = np.zeros(n, dtype=bool)  # cells held at p = 0
        for _ in range(200):
            r, a_p, _ = self._fluxes(p, h, speed)
            free = ~active
            p_new = np.zeros(n)
            sub = a_p[free][:, free]
            p_new[free] = p[free] - spsolve(sub.tocsc(), r[free])
            r_new, _, _ = self._fluxes(p_new, h, speed)
            if self.params.cavitation != "reynolds":
                return p_new
            new_active = (p_new < 0.0) | (active & (r_new / film > 0.0))
            p = np.maximum(p_new, 0.0)
            if np.array_equal(new_active, active):
                return p
            active = new_active
        raise RuntimeError(f"point EHL film pressure at {speed:.4g} m/s: no convergence")

    # ------------------------------------------------------------------- solve
    def solve(self, speed: float, guess: PointEHLResult | None = None) -> PointEHLResult:
        """Solve at sliding speed ``speed`` [m/s] (> 0) from ``guess`` (default Hertz).

        Raises:
            RuntimeError: Newton did not converge.
        """
        pr, n = self.params, self.n
        speed = check_range("speed", speed, 0.0, 1e3, lo_open=True, unit="m/s")
        if guess is None:
            p, u0 = self.hertz_guess(speed)
        else:
            p, u0 = guess.p.copy(), guess.u0
        h = self.gap(p, u0)
        if not np.all(h > 0):
            raise RuntimeError(f"point EHL at {speed:.4g} m/s: the guess has a gap <= 0")
        h_s = float(h.min())
        film = self._film_diagonal(h, speed) * self.p_scale
        z = np.concatenate([p / self.p_scale, [u0 / h_s]])
        where = f"point EHL (N = {n}) at speed {speed:.4g} m/s"
        res, jac, h = self._system(z, speed, film, h_s)
        norm = float(np.max(np.abs(res)))
        it = 0
        while norm > pr.tol:
            if it >= pr.max_iter:
                raise RuntimeError(f"{where}: Newton did not converge in {it} iterations "
                                   f"(scaled residual {norm:.3e})")  # fmt: skip
            assert jac is not None
            try:
                lu = lu_factor(jac, check_finite=True)
                dz = -lu_solve(lu, res)
            except (LinAlgError, ValueError) as e:
                raise RuntimeError(f"{where}: singular Jacobian at iteration {it}: {e}") from None
            dh = self.kernel @ (dz[:n] * self.p_scale) + dz[n] * h_s
            shrink = dh < 0
            alpha = min(1.0, float(np.min(0.9 * h[shrink] / -dh[shrink]))) if shrink.any() else 1.0
            step = float(np.linalg.norm(dz))
            for _ in range(40):  # natural monotonicity test
                trial, _, h_t = self._system(z + alpha * dz, speed, film, h_s, jacobian=False)
                if np.all(np.isfinite(trial)) and np.all(h_t > 0):
                    if float(np.linalg.norm(lu_solve(lu, trial))) <= (1.0 - 0.25 * alpha) * step:
                        break
                alpha *= 0.5
            else:
                raise RuntimeError(f"{where}: damping failed at iteration {it} "
                                   f"(scaled residual {norm:.3e})")  # fmt: skip
            z = z + alpha * dz
            it += 1
            res, jac, h = self._system(z, speed, film, h_s)
            norm = float(np.max(np.abs(res)))
        return self._result(z, speed, film, h_s, it)

    # ----------------------------------------------------------------- outputs
    def _result(self, z: FloatArray, speed: float, film: FloatArray, h_s: float,
                iterations: int) -> PointEHLResult:  # fmt: skip
        pr, n, d = self.params, self.n, self.d
        p, u0 = z[:n] * self.p_scale, float(z[n]) * h_s
        h = self.gap(p, u0)
        r, _, _ = self._fluxes(p, h, speed)
        full = np.ones(n, dtype=bool)
        if pr.cavitation == "reynolds":
            full = r / film <= p / self.p_scale
            p = np.where(full, p, 0.0)
        load = 2.0 * self.area * float(p.sum())
        r2 = self.x**2 + self.y**2
        contact_radius = math.sqrt(2.5 * float((p * r2).sum()) / float(p.sum()))
        f_cou = 2.0 * pr.viscosity * speed * self.area * float(np.sum(1.0 / h))
        i, j = self.fx  # Poiseuille: (h/2) dp/dx per face, p = 0 outside
        pi_ = np.where(i >= 0, p[np.maximum(i, 0)], 0.0)
        pj = np.where(j >= 0, p[np.maximum(j, 0)], 0.0)
        hi = np.where(i >= 0, h[np.maximum(i, 0)], h[np.maximum(j, 0)])
        hj = np.where(j >= 0, h[np.maximum(j, 0)], h[np.maximum(i, 0)])
        f_poi = 2.0 * d * float(np.sum(0.25 * (hi + hj) * (pj - pi_)))
        friction = f_cou + f_poi
        # the net outflow of a full-film cell against the Couette flux through its face
        mass = float(np.abs(r[full]).max(initial=0.0)) / (0.5 * speed * float(h.min()) * d)
        # the centre: the four cells around x = y = 0 with their mirrors
        near = (np.abs(self.x) < d) & (self.y < d)
        row1 = (np.abs(self.x) < d) & (np.abs(self.y - 1.5 * d) < 0.5 * d)
        h_central = (9.0 * h[near].mean() - h[row1].mean()) / 8.0  # even in y: h(0) ~ (9 h1 - h2)/8
        axis = np.flatnonzero(np.abs(self.y - 0.5 * d) < 1e-9 * d)
        axis = axis[np.argsort(self.x[axis])]
        x_cav = math.nan
        if pr.cavitation == "reynolds":
            k = int(np.argmax(p[axis]))
            after = np.flatnonzero(~full[axis][k:])
            if after.size:
                x_cav = float(self.x[axis][k + after[0]] - 0.5 * d)
        return PointEHLResult(
            speed=speed, x=self.x.copy(), y=self.y.copy(), p=p, h=h, u0=u0, normal_load=load,
            h_min=float(h.min()), h_central=float(h_central), max_pressure=float(p.max()),
            contact_radius=contact_radius, friction_couette=f_cou, friction_poiseuille=f_poi,
            friction=friction, mu=friction / load, mu_couette=f_cou / load,
            mu_poiseuille=f_poi / load, x_cavitation=x_cav,
            cavitation_fraction=float((~full).sum()) / n, mass_balance_error=mass,
            newton_iterations=iterations,
        )  # fmt: skip


def speed_continuation(model: PointEHL, speeds: Sequence[float], max_halvings: int = 8
                       ) -> list[PointEHLResult]:  # fmt: skip
    """Solve at each of ``speeds`` [m/s] in the given order (walk down from the
    highest for a soft contact): the first from the Hertz guess, each next from the
    previous solution, a failed step halved in ``ln U``.

    Raises:
        RuntimeError: The start failed or a step was halved ``max_halvings`` times.
    """
    if len(speeds) == 0:
        raise ParameterError("speeds must not be empty")
    state = model.solve(float(speeds[0]))
    out = [state]
    for target in speeds[1:]:
        trial, halvings = float(target), 0
        while state.speed != target:
            try:
                state = model.solve(trial, state)
                trial = float(target)
            except RuntimeError as e:
                halvings += 1
                if halvings > max_halvings:
                    raise RuntimeError(f"point EHL continuation stalled towards {target:g} "
                                       f"m/s: {e}") from None  # fmt: skip
                trial = math.sqrt(state.speed * trial)
        out.append(state)
    return out


def richardson(coarse: PointEHLResult, fine: PointEHLResult, ratio: float,
               keys: Sequence[str] = ("mu", "h_central", "h_min", "contact_radius"),
               ) -> dict[str, float]:  # fmt: skip
    """Second-order Richardson extrapolation of ``keys`` from two grids whose cell
    sizes differ by ``ratio`` (> 1, coarse over fine): ``f + (f - c) / (ratio^2 - 1)``."""
    check_range("ratio", ratio, 1.0, math.inf, lo_open=True)
    out = {}
    for k in keys:
        c, f = float(getattr(coarse, k)), float(getattr(fine, k))
        out[k] = f + (f - c) / (ratio**2 - 1.0)
    return out


def for_ball(scene: Any, cells_per_radius: int = 15) -> PointEHL:
    """The reference of a smooth ball scene's parameters
    (:class:`~dolfinx_seal.scenes.ball.BallParameters`, duck-typed): the same radius,
    load, modulus, viscosity, cavitation and lubricated disc (``film_extent``)."""
    film = scene.film
    params = PointEHLParameters(
        radius=scene.radius, load=scene.load, e_star=scene.material.E_star,
        viscosity=film.viscosity, cavitation=film.cavitation,
        cells_per_radius=cells_per_radius, extent=scene.film_extent,
    )  # fmt: skip
    return PointEHL(params)


__all__ = [
    "PointEHL",
    "PointEHLParameters",
    "PointEHLResult",
    "for_ball",
    "richardson",
    "speed_continuation",
]
