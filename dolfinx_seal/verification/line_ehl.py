"""Soft elastohydrodynamic line contact (Persson & Scaraggi 2009, S1 section 2), an
independent reference solver: finite volumes + half-space influence coefficients,
numpy/scipy only (no DOLFINx).

Written apart from the FEM cylinder scene (:mod:`dolfinx_seal.scenes.cylinder`),
with a different discretisation, to check it.  SI units throughout: x, h, u0 [m],
pressures [Pa], U [m/s], eta [Pa s], loads and friction forces per unit length
[N/m], fluxes per unit length [m^2/s].

Model
-----
* A rigid flat and an elastic cylinder of radius ``R``, the cylinder represented as
  a plane-strain elastic half-space of effective modulus ``E*``.  Rubber is
  incompressible (nu = 0.5), so tangential tractions do not move the surface
  normally: only the normal pressure ``p_fluid + p_cont`` enters the elasticity.
* Grid: ``N`` uniform cells on ``x in [-upstream L, downstream L]`` (``L`` = the
  Hertz half-width ``a_H = (4 F R / (pi E*))^(1/2)`` unless ``length_scale`` is
  given); pressures piecewise constant per cell, gaps at cell centres ``x_i``.
* Gap: ``h_i = u0 + x_i^2/(2R) + sum_j K_ij (p_fluid_j + p_cont_j)`` with the exact
  influence coefficients of a uniform pressure on cell ``j`` of a half-space in
  plane strain, ``w(x) = -(2/(pi E*)) int_cell ln(|x - s| / L) ds``; the
  antiderivative in ``t = s - x`` is ``t ln(|t|/L) - t``.  The reference length
  ``L`` only shifts ``w`` by a constant, which the unknown approach ``u0`` absorbs.
* Asperity contact: ``p_cont_i = law.pressure(h_i)`` for any object with numpy
  methods ``pressure(u)``, ``dpressure_du(u)`` and ``area_fraction(p)``
  (:class:`~dolfinx_seal.contact.base.ContactLaw`), or no asperity contact.
* Reynolds (steady, isoviscous, incompressible): the flat slides at ``U`` under
  the cylinder at rest, the mean surface velocity is ``U/2``, and the flux per
  unit length is ``q = -(h^3/(12 eta)) dp/dx + U h/2``; ``p = 0`` at both ends
  of the domain (flooded; pressures are gauge pressures above the cavitation
  pressure).  Finite volumes, conservative: the face conductivity is the
  *arithmetic* mean of ``h^3`` of the two neighbouring cells over ``12 eta``;
  the Couette face flux is *central*, ``U (h_L + h_R)/4`` (second order; the
  option ``couette="upwind"`` takes ``U h_L / 2``, first order).  On the two
  boundary half-faces the gap of the adjacent cell is used (the domain ends are
  far from the contact, where the pressure is a few Pa).
* Cavitation ``"none"`` (full Sommerfeld: the net outflow of every cell is zero,
  pressures may be negative) or ``"reynolds"``: the complementarity problem
  ``p_i >= 0, r_i >= 0, p_i r_i = 0`` with ``r_i = q_(i+1/2) - q_(i-1/2)`` the net
  outflow of cell ``i`` (``r >= 0`` where ``p = 0``: see :meth:`LineEHL.system`),
  solved as ``min(p_i, r_i/D_i) = 0`` by a semismooth Newton method.  ``D_i`` is
  ``d r_i/d p_i > 0`` frozen at the initial guess of each solve (Jacobi scaling:
  ``r_i/D_i`` is the pressure change that would balance the cell alone, so the two
  arguments of the min are comparable even where ``h^3`` is large, in the far inlet).
* Load: force control ``sum_i (p_fluid_i + p_cont_i) dx = F`` with ``u0`` the extra
  unknown, or a fixed ``u0`` (``fixed_approach``).
* Newton: unknowns ``(p_fluid/p_s, h/h_s, u0/h_s)``, a dense analytic Jacobian,
  a fraction-to-boundary rule (``h`` stays positive) and damping by the natural
  monotonicity test (the simplified Newton correction must decrease; a test on
  the residual norm stalled, see :meth:`LineEHL.solve`).  Scaled rows: film rows
  in units of ``p_s`` (``r_i/(D_i p_s)`` or ``p_i/p_s``), gap rows in units of
  ``h_s``, the load row in units of ``F``, so that one tolerance (on the max norm)
  is meaningful for all.  ``p_s = 2 F / (pi L)`` (the Hertz peak when ``L = a_H``),
  ``h_s`` the smallest gap of the initial guess.
* Friction on the moving flat, per unit length: with the flat (z = 0) moving at
  ``U`` and the cylinder (z = h) at rest, ``v(z) = U (1 - z/h) + (dp/dx) z (z - h)
  / (2 eta)``, and the force needed to drive the flat is ``-eta dv/dz (z = 0) =
  eta U / h + (h/2) dp/dx`` per unit area.  Hence ``friction = int [sigma_1
  A/A0(p_cont) + eta U / h + (h/2) dp/dx] dx`` (S1 eqs 13-16), with the full-film
  Couette shear ``eta U / h`` also in cavitated cells (S1's "flooded"
  assumption); the Poiseuille part is summed face by face,
  ``sum_f (h_f/2)(p_R - p_L)`` with ``p = 0`` beyond the ends.

Speed continuation (:func:`speed_continuation`): the first point starts from the
Hertz pressure at a low speed, each next point from the previous solution, with
the speed step halved (geometrically) when a solve fails.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import LinAlgError, lu_factor, lu_solve, solve_banded, toeplitz

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import (
    check_choice,
    check_int_range,
    check_nonnegative,
    check_positive,
    check_range,
)

FloatArray = NDArray[np.float64]

CAVITATION_MODELS = ("none", "reynolds")
COUETTE_SCHEMES = ("central", "upwind")


class ContactLawLike(Protocol):
    """What the solver needs of an asperity contact law (vectorised, SI)."""

    def pressure(self, u: ArrayLike) -> FloatArray:
        """Nominal contact pressure [Pa] at mean separation ``u`` [m]."""
        ...

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """``dp/du`` [Pa/m]."""
        ...

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """Relative real contact area ``A/A0`` [-] at nominal pressure ``p`` [Pa]."""
        ...


@dataclass(frozen=True)
class LineEHLParameters:
    """Parameters of the soft EHL line contact (SI units).

    Attributes:
        radius: Cylinder radius R [m].
        load: Normal load per unit length F [N/m] (also sets the Hertz scales).
        e_star: Effective modulus ``E* = E/(1 - nu^2)`` [Pa].
        viscosity: Dynamic viscosity eta [Pa s].
        asperity_shear: Frictional shear stress sigma_1 of the real contact area [Pa].
        cavitation: ``"none"`` (full Sommerfeld) or ``"reynolds"`` (p >= 0).
        couette: Couette face flux, ``"central"`` (2nd order) or ``"upwind"`` (1st order).
        n_cells: Number of uniform cells N [-].
        upstream: Domain extent upstream of x = 0 (x < 0, the inlet) in units of L [-].
        downstream: Domain extent downstream of x = 0 in units of L [-].
        length_scale: L [m]; 0 chooses the Hertz half-width a_H.
        fixed_approach: None: force control (u0 is an unknown); otherwise u0 [m] is
            fixed and the load is an output.
        tol: Newton tolerance on the max norm of the scaled residual [-].
        max_iter: Maximum number of Newton iterations per solve [-].
    """

    radius: float = 0.01
    load: float = 100.0
    e_star: float = 10e6 / 0.75
    viscosity: float = 0.1
    asperity_shear: float = 1.0e6
    cavitation: str = "reynolds"
    couette: str = "central"
    n_cells: int = 400
    upstream: float = 10.0
    downstream: float = 6.0
    length_scale: float = 0.0
    fixed_approach: float | None = None
    tol: float = 1e-9
    max_iter: int = 60

    def __post_init__(self) -> None:
        check_positive("radius", self.radius, "m")
        check_positive("load", self.load, "N/m")
        check_positive("e_star", self.e_star, "Pa")
        check_positive("viscosity", self.viscosity, "Pa s")
        check_range("asperity_shear", self.asperity_shear, 0.0, 1e10, unit="Pa")
        check_choice("cavitation", self.cavitation, CAVITATION_MODELS)
        check_choice("couette", self.couette, COUETTE_SCHEMES)
        check_int_range("n_cells", self.n_cells, 16, 3000)
        check_range("upstream", self.upstream, 1.0, 100.0)
        check_range("downstream", self.downstream, 1.0, 100.0)
        check_nonnegative("length_scale", self.length_scale, "m")
        if self.fixed_approach is not None:
            check_positive("fixed_approach", self.fixed_approach, "m")
        check_range("tol", self.tol, 1e-14, 1e-3)
        check_int_range("max_iter", self.max_iter, 1, 1000)

    @property
    def hertz_half_width(self) -> float:
        """Hertz line-contact half-width ``a_H = (4 F R / (pi E*))^(1/2)`` [m]."""
        return math.sqrt(4.0 * self.load * self.radius / (math.pi * self.e_star))

    @property
    def hertz_peak_pressure(self) -> float:
        """Hertz peak pressure ``p_H = 2 F / (pi a_H)`` [Pa]."""
        return 2.0 * self.load / (math.pi * self.hertz_half_width)


@dataclass(frozen=True, eq=False)
class LineEHLResult:
    """One converged point.  Arrays are per cell (cell centres ``x``).

    Attributes:
        speed: Sliding speed U [m/s].
        cavitation: Cavitation model.
        x: Cell centres [m].
        p_fluid: Fluid pressure [Pa].
        p_cont: Asperity contact pressure [Pa].
        h: Gap (mean separation) [m].
        u0: Approach (gap at x = 0 without the elastic deflection) [m].
        normal_load: ``int (p_fluid + p_cont) dx`` [N/m] (= F under force control).
        load_fluid, load_contact: Its fluid and asperity parts [N/m].
        fluid_load_fraction: ``load_fluid / normal_load`` [-].
        h_min: Smallest gap at the cell centres [m].
        h_central: Gap at x = 0 (linear interpolation) [m].
        max_fluid_pressure, min_fluid_pressure: [Pa].
        friction_asperity, friction_couette, friction_poiseuille: Friction parts on
            the moving flat [N/m]; ``friction`` their sum.
        mu, mu_asperity, mu_couette, mu_poiseuille: ``friction / normal_load`` [-].
        flux: Mean face flux of the full film [m^2/s] (nan at U = 0).
        mass_balance_error: ``max |q - q_mean| / |q_mean|`` over the faces that
            border a full-film cell [-] (nan at U = 0).
        x_cavitation: Film rupture position (right face of the last full-film cell
            of the pressure zone) [m]; nan without cavitation.
        cavitation_fraction: Length fraction of cavitated cells [-].
        newton_iterations: Newton iterations of this solve.
        residual_norm: Final max norm of the scaled residual [-].
    """

    speed: float
    cavitation: str
    x: FloatArray
    p_fluid: FloatArray
    p_cont: FloatArray
    h: FloatArray
    u0: float
    normal_load: float
    load_fluid: float
    load_contact: float
    fluid_load_fraction: float
    h_min: float
    h_central: float
    max_fluid_pressure: float
    min_fluid_pressure: float
    friction_asperity: float
    friction_couette: float
    friction_poiseuille: float
    friction: float
    mu: float
    mu_asperity: float
    mu_couette: float
    mu_poiseuille: float
    flux: float
    mass_balance_error: float
    x_cavitation: float
    cavitation_fraction: float
    newton_iterations: int
    residual_norm: float

    def summary(self) -> dict[str, float | int | str]:
        """The scalar outputs as a dict (for tables and JSON)."""
        skip = {"x", "p_fluid", "p_cont", "h"}
        return {k: v for k, v in self.__dict__.items() if k not in skip}


@dataclass
class _Faces:
    """Face fluxes and their derivatives w.r.t. the left/right cell unknowns.

    Face ``f`` (0..N) lies between cells ``f-1`` and ``f``; faces 0 and N are the
    domain ends (no left, resp. right, cell: the derivative there is 0).
    """

    q: FloatArray
    dq_dp_left: FloatArray
    dq_dp_right: FloatArray
    dq_dh_left: FloatArray
    dq_dh_right: FloatArray


@dataclass(frozen=True, eq=False)
class Scales:
    """Scales of one Newton solve (frozen at its initial guess).

    Attributes:
        gap: ``h_s`` [m], the unit of the gap unknowns and gap rows (smallest gap).
        film: ``D_i p_s`` [m^2/s] per cell, the unit of the film rows (``D_i = d r_i/d p_i``).
    """

    gap: float
    film: FloatArray


def _difference_matrix(d_left: FloatArray, d_right: FloatArray) -> FloatArray:
    """Dense ``d r_i / d y_j`` for ``r_i = q_(i+1) - q_i`` from face derivatives.

    ``d_left[f]`` (``d_right[f]``) is ``d q_f / d y`` of the cell left (right) of face ``f``.
    """
    n = d_left.size - 1
    m = np.zeros((n, n))
    idx = np.arange(n)
    m[idx, idx] = d_left[1:] - d_right[:-1]
    m[idx[:-1], idx[:-1] + 1] = d_right[1:n]
    m[idx[1:], idx[1:] - 1] = -d_left[1:n]
    return m


def _separation(law: ContactLawLike, p: FloatArray) -> FloatArray:
    """Inverse of a decreasing ``law.pressure`` by bisection in ``ln u`` [m] (u in [1e-15, 1])."""
    target = np.asarray(p, dtype=float)
    lo = np.full(target.shape, math.log(1e-15))
    hi = np.full(target.shape, 0.0)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        above = np.asarray(law.pressure(np.exp(mid))) > target  # root at larger u
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    return np.exp(0.5 * (lo + hi))


class LineEHL:
    """The discrete soft-EHL line contact for one parameter set and contact law.

    Args:
        params: The parameters.
        law: Asperity contact law (``pressure``, ``dpressure_du``, ``area_fraction``)
            or None (no asperity contact: the film carries the whole load).
    """

    def __init__(self, params: LineEHLParameters, law: ContactLawLike | None = None) -> None:
        self.params = params
        self.law = law
        pr = params
        self.length = pr.length_scale if pr.length_scale > 0 else pr.hertz_half_width
        self.n = pr.n_cells
        x_lo, x_hi = -pr.upstream * self.length, pr.downstream * self.length
        self.dx = (x_hi - x_lo) / self.n
        self.x = x_lo + (np.arange(self.n) + 0.5) * self.dx
        self.p_scale = 2.0 * pr.load / (math.pi * self.length)
        # influence coefficients: K_ij = -(2/(pi E*)) int_{x_j - dx/2}^{x_j + dx/2} ln(|x_i - s|/L) ds
        d = np.arange(self.n) * self.dx

        def antider(t: FloatArray) -> FloatArray:
            with np.errstate(divide="ignore", invalid="ignore"):
                v = t * np.log(np.abs(t) / self.length) - t
            return np.where(t == 0.0, 0.0, v)

        col = -(2.0 / (math.pi * pr.e_star)) * (
            antider(d + 0.5 * self.dx) - antider(d - 0.5 * self.dx)
        )
        self.kernel = toeplitz(col)
        self.rigid_gap = self.x**2 / (2.0 * pr.radius)

    # ------------------------------------------------------------ discrete model
    def _faces(self, p: FloatArray, h: FloatArray, speed: float) -> _Faces:
        """Face fluxes ``q = -(h^3/12 eta) dp/dx + U h / 2`` and their derivatives."""
        pr, dx, n = self.params, self.dx, self.n
        c = 1.0 / (12.0 * pr.viscosity)
        q = np.empty(n + 1)
        dpl, dpr_, dhl, dhr = (np.zeros(n + 1) for _ in range(4))
        # interior faces 1..N-1: arithmetic mean of h^3, central Couette flux
        hl, hr = h[:-1], h[1:]
        k = 0.5 * c * (hl**3 + hr**3)
        grad = (p[1:] - p[:-1]) / dx
        if pr.couette == "central":
            q[1:n] = -k * grad + 0.25 * speed * (hl + hr)
            dhl[1:n] = -1.5 * c * hl**2 * grad + 0.25 * speed
            dhr[1:n] = -1.5 * c * hr**2 * grad + 0.25 * speed
        else:  # upwind (U > 0: the left cell is upstream)
            q[1:n] = -k * grad + 0.5 * speed * hl
            dhl[1:n] = -1.5 * c * hl**2 * grad + 0.5 * speed
            dhr[1:n] = -1.5 * c * hr**2 * grad
        dpl[1:n] = k / dx
        dpr_[1:n] = -k / dx
        # boundary half-faces, p = 0 at the domain ends, gap of the adjacent cell
        k0, kn = c * h[0] ** 3, c * h[-1] ** 3
        g0, gn = p[0] / (0.5 * dx), -p[-1] / (0.5 * dx)
        q[0] = -k0 * g0 + 0.5 * speed * h[0]
        dpr_[0] = -k0 / (0.5 * dx)
        dhr[0] = -3.0 * c * h[0] ** 2 * g0 + 0.5 * speed
        q[n] = -kn * gn + 0.5 * speed * h[-1]
        dpl[n] = kn / (0.5 * dx)
        dhl[n] = -3.0 * c * h[-1] ** 2 * gn + 0.5 * speed
        return _Faces(q, dpl, dpr_, dhl, dhr)

    def _contact(self, h: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Asperity pressure [Pa] and ``dp/dh`` [Pa/m] (zeros without a law)."""
        if self.law is None:
            z = np.zeros_like(h)
            return z, z
        pc = np.asarray(self.law.pressure(h), dtype=float)
        dpc = np.asarray(self.law.dpressure_du(h), dtype=float)
        return pc, dpc

    def film_diagonal(self, h: FloatArray) -> FloatArray:
        """``D_i = d r_i / d p_i = (k_(i-1/2) + k_(i+1/2)) / dx`` [m^2/(s Pa)]: the net
        outflow of cell ``i`` per unit of its pressure, with the face conductivities
        ``k`` of :meth:`_faces` (a boundary half-face counts twice)."""
        c = 1.0 / (12.0 * self.params.viscosity * self.dx)
        h3 = h**3
        own = np.ones(self.n)
        own[[0, -1]] = 2.5  # half of two interior faces, or half of one and a boundary face
        d = c * own * h3
        d[1:] += 0.5 * c * h3[:-1]
        d[:-1] += 0.5 * c * h3[1:]
        return d

    def scales(self, h: FloatArray) -> Scales:
        """Scales of one Newton solve, frozen at the gap ``h`` [m] of its initial guess."""
        return Scales(gap=float(np.min(h)), film=self.film_diagonal(h) * self.p_scale)

    def unpack(self, z: FloatArray, gap_scale: float) -> tuple[FloatArray, FloatArray, float]:
        """``(p [Pa], h [m], u0 [m])`` from the scaled unknowns ``z``."""
        n = self.n
        return z[:n] * self.p_scale, z[n : 2 * n] * gap_scale, float(z[2 * n]) * gap_scale

    def pack(self, p: FloatArray, h: FloatArray, u0: float, gap_scale: float) -> FloatArray:
        """Scaled unknowns ``[p/p_s, h/h_s, u0/h_s]``."""
        return np.concatenate([p / self.p_scale, h / gap_scale, [u0 / gap_scale]])

    def system(
        self, z: FloatArray, speed: float, scales: Scales, jacobian: bool = True
    ) -> tuple[FloatArray, FloatArray | None]:
        """Scaled residual and (optionally) its dense Jacobian at the scaled unknowns ``z``.

        Rows: N film rows, N gap rows, one load (or fixed-approach) row.
        """
        pr, n, dx = self.params, self.n, self.dx
        h_s = scales.gap
        p, h, u0 = self.unpack(z, h_s)
        load_scale = pr.load if pr.fixed_approach is None else h_s
        pc, dpc = self._contact(h)
        res = np.empty(2 * n + 1)
        jac = np.zeros((2 * n + 1, 2 * n + 1)) if jacobian else None
        ps = self.p_scale
        fl, gp = slice(0, n), slice(n, 2 * n)
        # ---- film rows, Jacobi-scaled: rs_i = r_i / (D_i p_s), with D_i = d r_i/d p_i
        # frozen at the initial guess, is (near the guess) the change of p_i/p_s that
        # would balance cell i alone, comparable with p_i/p_s in the min below even
        # where h^3 is large (far inlet).  (D at the current h would make every film
        # row vanish as h -> infinity: a spurious minimum of the residual norm.)
        if speed > 0:
            faces = self._faces(p, h, speed)
            rs = (faces.q[1:] - faces.q[:-1]) / scales.film  # net outflow of each cell
            if pr.cavitation == "reynolds":
                # min(p_i/p_s, rs_i) = 0.  Sign of r: d r_i / d p_i = D_i > 0 (raising p_i
                # pushes fluid out of cell i), so a cell clamped at p_i = 0 with r_i > 0
                # is one whose unconstrained pressure would be negative: there the
                # Couette flux U h / 2 grows (diverging gap) and cannot be supplied
                # without a sub-cavity pressure.  r >= 0 is the multiplier of the
                # obstacle problem p >= 0 (Reynolds/Swift-Stieber condition).
                use_r = rs <= p / ps
                res[fl] = np.where(use_r, rs, p / ps)
            else:
                use_r = np.ones(n, dtype=bool)
                res[fl] = rs
            if jac is not None:
                w = 1.0 / scales.film
                jr_p = _difference_matrix(faces.dq_dp_left, faces.dq_dp_right) * (w * ps)[:, None]
                jr_h = _difference_matrix(faces.dq_dh_left, faces.dq_dh_right) * (w * h_s)[:, None]
                jac[fl, fl] = np.where(use_r[:, None], jr_p, np.eye(n))
                jac[fl, gp] = np.where(use_r[:, None], jr_h, 0.0)
        else:  # no sliding: no film pressure
            res[fl] = p / ps
            if jac is not None:
                jac[fl, fl] = np.eye(n)
        # ---- gap rows: h - u0 - x^2/2R - K (p + p_cont) = 0
        res[gp] = (h - u0 - self.rigid_gap - self.kernel @ (p + pc)) / h_s
        if jac is not None:
            jac[gp, fl] = -self.kernel * (ps / h_s)
            jac[gp, gp] = np.eye(n) - self.kernel * dpc[None, :]
            jac[gp, 2 * n] = -1.0
        # ---- load row
        if pr.fixed_approach is None:
            res[2 * n] = (dx * np.sum(p + pc) - pr.load) / load_scale
            if jac is not None:
                jac[2 * n, fl] = dx * ps / load_scale
                jac[2 * n, gp] = dx * dpc * h_s / load_scale
        else:
            res[2 * n] = (u0 - pr.fixed_approach) / load_scale
            if jac is not None:
                jac[2 * n, 2 * n] = 1.0
        return res, jac

    def full_film(
        self, p: FloatArray, h: FloatArray, speed: float, scales: Scales | None = None
    ) -> FloatArray:
        """Cells whose film row is the mass balance (all but the cavitated ones).

        With the Reynolds condition: the cells where ``min(p_i/p_s, r_i/(D_i p_s))``
        picks the mass balance, as in the Newton solve (``D`` from ``scales``, else at ``h``).
        """
        if self.params.cavitation != "reynolds" or speed == 0:
            return np.ones(self.n, dtype=bool)
        faces = self._faces(p, h, speed)
        film = self.scales(h).film if scales is None else scales.film
        return (faces.q[1:] - faces.q[:-1]) / film <= p / self.p_scale

    # ------------------------------------------------------------------ guesses
    def hertz_guess(self, speed: float) -> tuple[FloatArray, FloatArray, float]:
        """Initial ``(p_fluid, h, u0)`` from the Hertz pressure.

        The gap is that of the half-space under the Hertz (elliptical) pressure
        ``p_H (1 - x^2/a_H^2)^(1/2)``, shifted so that its minimum is the law's
        separation at the Hertz peak (with a contact law) or the rigid-cylinder
        Martin film thickness ``4.9 eta (U/2) R / F`` (without).  With a law the
        asperities carry the Hertz pressure (inside the contact the gap is
        ``max(half-space gap, u(p_Hertz))``, ``u`` the law's inverse) and the fluid
        pressure starts at 0; without, the fluid pressure starts as the film
        pressure of that gap (:meth:`film_pressure`).  With ``fixed_approach`` the
        gap is shifted to it.
        """
        pr = self.params
        a_h, p_h = pr.hertz_half_width, pr.hertz_peak_pressure
        p_hz = p_h * np.sqrt(np.clip(1.0 - (self.x / a_h) ** 2, 0.0, None))
        shape = self.rigid_gap + self.kernel @ p_hz
        if self.law is not None:
            h_start = float(_separation(self.law, np.array([p_h]))[0])
        else:
            h_start = 4.9 * pr.viscosity * 0.5 * max(speed, 1e-12) * pr.radius / pr.load
        u0 = h_start - float(shape.min())
        h = u0 + shape
        if self.law is not None:
            inside = p_hz > 1e-6 * p_h
            if np.any(inside):
                h[inside] = np.maximum(h[inside], _separation(self.law, p_hz[inside]))
            p = np.zeros(self.n)
        else:
            p = p_hz.copy()
        if pr.fixed_approach is not None:
            h += pr.fixed_approach - u0
            u0 = pr.fixed_approach
            h = np.maximum(h, 1e-3 * pr.fixed_approach)
        if self.law is None and speed > 0:
            # at p = 0 the flux does not depend on u0 (a uniform shift of h changes
            # every Couette flux alike), so the coupled Jacobian would be singular:
            # start from the film pressure of this gap instead
            p = self.film_pressure(h, speed, p)
        return p, h, u0

    def film_pressure(self, h: FloatArray, speed: float, p: FloatArray | None = None) -> FloatArray:
        """The film pressure [Pa] of the fixed gap ``h`` [m] at speed ``speed`` [m/s]
        (the film rows alone: linear, or a linear complementarity problem with the
        Reynolds condition, solved by semismooth Newton from ``p``)."""
        n = self.n
        sc = self.scales(h)
        z = self.pack(np.zeros(n) if p is None else p, h, 0.0, sc.gap)
        active = None
        for _ in range(100):
            res, jac = self.system(z, speed, sc)
            assert jac is not None
            # the active set (cells with the film row) of the linear complementarity
            # problem; once it repeats the last linear solve was exact
            new_active = self.full_film(z[:n] * self.p_scale, h, speed, sc)
            if active is not None and np.array_equal(active, new_active):
                break
            active = new_active
            a = jac[:n, :n]  # tridiagonal
            ab = np.zeros((3, n))
            ab[0, 1:] = np.diagonal(a, 1)
            ab[1] = np.diagonal(a)
            ab[2, :-1] = np.diagonal(a, -1)
            z[:n] -= solve_banded((1, 1), ab, res[:n])
        else:
            raise RuntimeError(f"film pressure at speed {speed:.4g} m/s: no convergence")
        return z[:n] * self.p_scale

    # ------------------------------------------------------------------- solve
    def solve(
        self,
        speed: float,
        guess: LineEHLResult | tuple[FloatArray, FloatArray, float] | None = None,
    ) -> LineEHLResult:
        """Solve at sliding speed ``speed`` [m/s] from ``guess`` (default: Hertz).

        Raises:
            ParameterError: Bad speed.
            RuntimeError: Newton did not converge (message: speed, iteration, residual).
        """
        pr, n = self.params, self.n
        speed = check_range("speed", speed, 0.0, 1e3, unit="m/s")
        if speed == 0.0 and self.law is None:
            raise ParameterError("speed = 0 needs a contact law (nothing would carry the load)")
        if guess is None:
            p, h, u0 = self.hertz_guess(speed)
        elif isinstance(guess, LineEHLResult):
            p, h, u0 = guess.p_fluid.copy(), guess.h.copy(), guess.u0
        else:
            p, h, u0 = (np.asarray(guess[0], float).copy(), np.asarray(guess[1], float).copy(),
                        float(guess[2]))  # fmt: skip
        if p.shape != (n,) or h.shape != (n,) or not np.all(h > 0):
            raise ParameterError("guess must have n_cells pressures and positive gaps")
        sc = self.scales(h)
        z = self.pack(p, h, u0, sc.gap)
        where = f"line EHL ({pr.cavitation}, N = {n}) at speed {speed:.4g} m/s"

        def evaluate(zz: FloatArray) -> FloatArray | None:
            try:
                with np.errstate(all="ignore"):
                    rr, _ = self.system(zz, speed, sc, jacobian=False)
            except (ParameterError, FloatingPointError, ValueError):
                return None
            return rr if np.all(np.isfinite(rr)) else None

        res, jac = self.system(z, speed, sc)
        if not np.all(np.isfinite(res)):
            raise RuntimeError(f"{where}: residual of the initial guess is not finite")
        norm = float(np.max(np.abs(res)))
        it = 0
        while norm > pr.tol:
            if it >= pr.max_iter:
                raise RuntimeError(
                    f"{where}: Newton did not converge in {it} iterations "
                    f"(scaled residual {norm:.3e} > tol {pr.tol:g})"
                )
            assert jac is not None
            try:
                lu = lu_factor(jac, check_finite=True)
                dz = -lu_solve(lu, res)
            except (LinAlgError, ValueError) as e:
                raise RuntimeError(
                    f"{where}: singular Jacobian at Newton iteration {it} "
                    f"(scaled residual {norm:.3e}): {e}"
                ) from None
            if not np.all(np.isfinite(dz)):
                raise RuntimeError(
                    f"{where}: non-finite Newton step at iteration {it} (residual {norm:.3e})"
                )
            # fraction to the boundary: the gap may shrink by at most 90 % per step
            dh = dz[n : 2 * n]
            hz = z[n : 2 * n]
            shrink = dh < 0
            alpha = min(1.0, float(np.min(0.9 * hz[shrink] / -dh[shrink]))) if shrink.any() else 1.0
            # damping by the natural monotonicity test (Deuflhard): the simplified
            # Newton correction -J^-1 F(z + alpha dz), with the Jacobian already
            # factorised, must be shorter than (1 - alpha/4) |dz|.  Unlike a test on
            # |F| it does not depend on the row scaling: with a soft solid a small
            # error in the asperity load is a large gap residual (K p), so |F| rose
            # after full steps that were good and the search crawled at alpha ~ 1/16.
            step = float(np.linalg.norm(dz))
            accepted = False
            for _ in range(40):
                z_trial = z + alpha * dz
                trial = evaluate(z_trial)
                if trial is not None:
                    simplified = float(np.linalg.norm(lu_solve(lu, trial)))
                    if simplified <= (1.0 - 0.25 * alpha) * step:
                        accepted = True
                        break
                alpha *= 0.5
            if not accepted:
                raise RuntimeError(
                    f"{where}: damping failed at Newton iteration {it} "
                    f"(scaled residual {norm:.3e}, no monotone step down to {alpha:.1e})"
                )
            z = z_trial
            it += 1
            res, jac = self.system(z, speed, sc)
            norm = float(np.max(np.abs(res)))
        return self._result(z, speed, sc, it, norm)

    # ----------------------------------------------------------------- outputs
    def _result(
        self, z: FloatArray, speed: float, scales: Scales, iterations: int, norm: float
    ) -> LineEHLResult:
        pr, n, dx, x = self.params, self.n, self.dx, self.x
        p, h, u0 = self.unpack(z, scales.gap)
        full = self.full_film(p, h, speed, scales)
        # p = 0 to rounding in cavitated cells (and everywhere without sliding): exact 0
        p = np.where(full, p, 0.0) if speed > 0 else np.zeros(n)
        pc, _ = self._contact(h)
        load_fluid = float(dx * p.sum())
        load_contact = float(dx * pc.sum())
        normal = load_fluid + load_contact
        if self.law is not None and pr.asperity_shear > 0:
            area = np.asarray(self.law.area_fraction(pc), dtype=float)
            f_asp = float(pr.asperity_shear * dx * area.sum())
        else:
            f_asp = 0.0
        f_cou = float(pr.viscosity * speed * dx * np.sum(1.0 / h))
        # Poiseuille part int (h/2) dp/dx dx, face by face (p = 0 beyond the ends)
        pe = np.concatenate([[0.0], p, [0.0]])
        he = np.concatenate([[h[0]], 0.5 * (h[:-1] + h[1:]), [h[-1]]])
        f_poi = float(np.sum(0.5 * he * np.diff(pe)))
        friction = f_asp + f_cou + f_poi
        flux = mass_err = math.nan
        if speed > 0:
            faces = self._faces(p, h, speed)
            border = np.zeros(n + 1, dtype=bool)
            border[:-1] |= full
            border[1:] |= full
            qf = faces.q[border]
            flux = float(qf.mean())
            mass_err = float(np.max(np.abs(qf - flux)) / abs(flux))
        x_cav = math.nan
        cav = ~full
        if pr.cavitation == "reynolds" and speed > 0 and np.any(cav):
            i_peak = int(np.argmax(p))
            after = np.nonzero(cav[i_peak:])[0]
            if after.size:
                x_cav = float(x[i_peak + after[0]] - 0.5 * dx)
        return LineEHLResult(
            speed=speed,
            cavitation=pr.cavitation,
            x=x.copy(),
            p_fluid=p,
            p_cont=pc,
            h=h,
            u0=u0,
            normal_load=normal,
            load_fluid=load_fluid,
            load_contact=load_contact,
            fluid_load_fraction=load_fluid / normal if normal else math.nan,
            h_min=float(h.min()),
            h_central=float(np.interp(0.0, x, h)),
            max_fluid_pressure=float(p.max()),
            min_fluid_pressure=float(p.min()),
            friction_asperity=f_asp,
            friction_couette=f_cou,
            friction_poiseuille=f_poi,
            friction=friction,
            mu=friction / normal if normal else math.nan,
            mu_asperity=f_asp / normal if normal else math.nan,
            mu_couette=f_cou / normal if normal else math.nan,
            mu_poiseuille=f_poi / normal if normal else math.nan,
            flux=flux,
            mass_balance_error=mass_err,
            x_cavitation=x_cav,
            cavitation_fraction=float(cav.sum()) / n,
            newton_iterations=iterations,
            residual_norm=norm,
        )

    def boundary_start_speed(self) -> float:
        """A low speed [m/s] where the film carries a negligible load, for the first solve.

        S1's film estimate ``u ~ (0.2 eta v a / p_mean)^(1/2)`` set to a thirtieth of
        the gap at the Hertz peak: ``v = (u_H/30)^2 p_mean / (0.2 eta a_H)``.
        """
        pr = self.params
        a_h, p_h = pr.hertz_half_width, pr.hertz_peak_pressure
        if self.law is None:
            raise ParameterError("boundary_start_speed needs a contact law")
        u_h = float(_separation(self.law, np.array([p_h]))[0])
        return (u_h / 30.0) ** 2 * (math.pi / 4.0 * p_h) / (0.2 * pr.viscosity * a_h)


def _midpoint(a: float, b: float) -> float:
    """Geometric mean of two positive speeds, arithmetic otherwise."""
    return math.sqrt(a * b) if a > 0 and b > 0 else 0.5 * (a + b)


def speed_continuation(
    model: LineEHL,
    speeds: Sequence[float],
    start_speed: float | None = None,
    max_halvings: int = 12,
    max_ratio: float = 10.0,
) -> list[LineEHLResult]:
    """Solve at each of ``speeds`` (increasing, decreasing or mixed) [m/s] by continuation.

    The walk starts at ``start_speed`` (default: the smaller of the first speed and
    :meth:`LineEHL.boundary_start_speed` with a contact law, else the first speed)
    from the Hertz guess, then goes to each listed speed in turn, each solve
    starting from the previous solution.  A step changes the speed by at most the
    factor ``max_ratio``; a failed step is halved (geometric mean of the speeds),
    after a success the step is doubled again (up to ``max_ratio``).

    Raises:
        RuntimeError: The start failed, or a step was halved ``max_halvings`` times in a row.
    """
    if len(speeds) == 0:
        raise ParameterError("speeds must not be empty")
    targets = [check_range("speeds", v, 0.0, 1e3, unit="m/s") for v in speeds]
    check_range("max_ratio", max_ratio, 1.0, math.inf, lo_open=True)
    if start_speed is None:
        v0 = targets[0]
        if model.law is not None:
            v0 = min(v0, model.boundary_start_speed()) if v0 > 0 else v0
    else:
        v0 = check_range("start_speed", start_speed, 0.0, 1e3, unit="m/s")
    state: LineEHLResult | None = None
    errors = []
    for _ in range(4):  # the start: lower the speed if the Hertz guess is too far off
        try:
            state = model.solve(v0, None)
            break
        except RuntimeError as e:
            errors.append(str(e))
            if model.law is None or v0 == 0.0:
                break
            v0 *= 0.1
    if state is None:
        raise RuntimeError("line EHL continuation: the start failed: " + " | ".join(errors))
    out: list[LineEHLResult] = []
    for target in targets:
        state = _walk(model, state, target, max_halvings, max_ratio)
        out.append(state)
    return out


def _next_trial(previous: float, current: float, target: float, max_ratio: float) -> float:
    """The next speed after a successful step ``previous -> current``: a step twice as
    long (in ``ln v`` for positive speeds), at most a factor ``max_ratio``, not
    beyond ``target``."""
    if previous > 0 and current > 0 and target > 0:
        nxt = current * (current / previous) ** 2
    else:
        nxt = current + 2.0 * (current - previous)
    return _limit(current, target if (target - current) * (target - nxt) <= 0 else nxt, max_ratio)


def _limit(current: float, trial: float, max_ratio: float) -> float:
    """``trial`` moved towards ``current`` so that their ratio is at most ``max_ratio``."""
    if current > 0 and trial > 0:
        return min(max(trial, current / max_ratio), current * max_ratio)
    return trial


def _walk(
    model: LineEHL, state: LineEHLResult, target: float, max_halvings: int, max_ratio: float
) -> LineEHLResult:
    """From the converged ``state`` to the ``target`` speed, halving failed steps."""
    trial = _limit(state.speed, target, max_ratio)
    halvings = 0
    while state.speed != target:
        try:
            new = model.solve(trial, state)
        except RuntimeError as e:
            halvings += 1
            if halvings > max_halvings:
                raise RuntimeError(
                    f"line EHL continuation stalled between {state.speed:.4g} and "
                    f"{trial:.4g} m/s (target {target:.4g}) after {max_halvings} "
                    f"halvings; last failure: {e}"
                ) from None
            trial = _midpoint(state.speed, trial)
            continue
        previous, state, halvings = state.speed, new, 0
        if trial != target:
            trial = _next_trial(previous, trial, target, max_ratio)
    return state


__all__ = [
    "CAVITATION_MODELS",
    "COUETTE_SCHEMES",
    "ContactLawLike",
    "LineEHL",
    "LineEHLParameters",
    "LineEHLResult",
    "Scales",
    "speed_continuation",
]


def for_cylinder(scene: Any, n_cells: int = 400) -> LineEHL:
    """The line-contact reference of a cylinder scene's parameters
    (:class:`~dolfinx_seal.scenes.cylinder.CylinderParameters`, duck-typed so this
    module needs no DOLFINx): the same radius, load, modulus, film and Persson law
    (built by the scene's own ``contact.build``) on ``n_cells`` cells."""
    e_star = scene.material.E_star
    params = LineEHLParameters(
        radius=scene.radius, load=scene.load, e_star=e_star, viscosity=scene.film.viscosity,
        asperity_shear=scene.film.asperity_shear, cavitation=scene.film.cavitation,
        n_cells=n_cells, upstream=scene.film.upstream, downstream=scene.film.downstream,
    )  # fmt: skip
    approach = params.hertz_half_width**2 / scene.radius
    law, _ = scene.contact.build(scene.roughness, e_star, approach=approach)
    return LineEHL(params, law)
