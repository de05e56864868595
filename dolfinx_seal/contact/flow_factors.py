"""Flow factors of the homogenised (average) Reynolds equation.

The averaged film flux (S0 eqs 8-9, Patir & Cheng) is

    q = -phi_p u^3 / (12 eta) grad p + U_m u + (U_rel / 2) sigma phi_s

with ``u`` the mean separation, ``phi_p`` the pressure flow factor and
``phi_s`` the shear flow factor (transport by roughness when one rough
surface slides; ``U_rel`` the velocity of the rough surface relative to the
smooth one).  Two models:

* :class:`PatirCheng` -- Patir & Cheng, ASME J. Lubr. Technol. 100 (1978) 12
  and 101 (1979) 220, isotropic roughness (``gamma = 1``):
  ``phi_p = 1 - 0.90 exp(-0.56 H)`` and ``phi_s = 1.899 H^0.98 exp(-0.92 H +
  0.05 H^2)`` for ``H = u/sigma <= 5``, ``1.126 exp(-0.25 H)`` above
  (one rough surface; the two pieces meet to 0.1 % at ``H = 5``).  Fitted for
  ``H > 0.5``; below that the fits are extrapolated (finite, positive).
* :class:`BruggemanFlowFactor` -- Persson-type effective-medium factor built
  from Persson's contact mechanics (S0 text after eq 9 and its refs [7, 9, 34]:
  Lorenz & Persson, Eur. Phys. J. E 31 (2010) 159; Persson, J. Phys.: Condens.
  Matter 22 (2010) 265004).  The interface is a 2D random mixture of local
  flow conductivities ``sigma(u) = u^3 / (12 eta)`` with the Persson
  distribution of separations

      P(u) = A1 delta(u) + int_1^zeta1 dzeta (-A'(zeta)) [N(u - u1, h) + N(u + u1, h)]

  (``N`` the normal density, ``u1(zeta)`` of S1 section 4 and ``h = h_rms(zeta)``
  of S1 footnote 4; Almqvist, Campana, Prodanov & Persson, J. Mech. Phys.
  Solids 59 (2011) 2355), and the 2D Bruggeman condition
  ``int P(u) (s - sigma(u)) / (s + sigma(u)) du = 0`` fixes the effective
  conductivity ``s``; ``phi_p = s / sigma(u_mean)``.  Its limits: ``phi_p -> 1 -
  (3/2)(h_rms/u)^2`` for ``u >> h_rms`` (Tripp's perturbation result) and
  ``phi_p = 0`` once ``A1/A0 >= 1/2`` (the 2D percolation threshold of EMT).
  The shear flow factor is taken as ``phi_s = 0`` (no roughness transport term)
  -- S0 sets ``sigma'_eff = u`` after eq 9, i.e. the plain Couette flux -- so
  :meth:`BruggemanFlowFactor.shear_factor` returns zeros.

Domains: every factor takes ``u > 0`` [m] (finite) and returns finite values,
``0 <= phi_p <= 1`` and ``phi_s >= 0``; other ``u`` raise ParameterError naming
the factor, the value and the range.  :class:`LogHermiteTable` checks at
construction that its interpolant stays in ``[0, 1]``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq
from scipy.special import erfinv

from dolfinx_seal.contact.base import FloatArray, as_array
from dolfinx_seal.contact.persson_theory import PerssonTheory
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_int_range, check_positive, check_range
from dolfinx_seal.roughness.psd import PowerSpectrum

_PC_C, _PC_R = 0.90, 0.56
_PC_A1, _PC_A1E, _PC_A2E, _PC_A3E, _PC_A2 = 1.899, 0.98, 0.92, 0.05, 1.126


class PatirCheng:
    """Patir-Cheng flow factors for isotropic roughness (see the module docstring).

    Args:
        sigma: Combined rms roughness [m].
    """

    name = "patir-cheng"

    def __init__(self, sigma: float) -> None:
        self.sigma = check_positive("sigma", sigma, "m")

    def _h(self, u: ArrayLike) -> FloatArray:
        return as_array("u", u, 0.0, law=self.name, unit="m") / self.sigma

    def pressure_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_p(u) = 1 - 0.9 exp(-0.56 u/sigma)`` [-], ``u > 0`` [m]."""
        return 1.0 - _PC_C * np.exp(-_PC_R * self._h(u))

    def dpressure_factor_du(self, u: ArrayLike) -> FloatArray:
        """``d phi_p / du`` [1/m]."""
        return _PC_C * _PC_R / self.sigma * np.exp(-_PC_R * self._h(u))

    def shear_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_s(u)`` [-] for one rough surface (each fit evaluated on its own range)."""
        h = self._h(u)
        out = np.empty_like(h)
        low = h <= 5.0
        hl = h[low]
        out[low] = _PC_A1 * hl**_PC_A1E * np.exp(-_PC_A2E * hl + _PC_A3E * hl * hl)
        out[~low] = _PC_A2 * np.exp(-0.25 * h[~low])
        return out

    def dshear_factor_du(self, u: ArrayLike) -> FloatArray:
        """``d phi_s / du`` [1/m], finite for every ``u > 0``.

        On the low fit ``phi_s (A1E/H - A2E + 2 A3E H)``, with ``phi_s / H`` written
        as ``A1 H^(A1E - 1) exp(...)`` where ``phi_s`` underflows (``H`` below ~1e-300).
        """
        h = self._h(u)
        out = np.empty_like(h)
        low = h <= 5.0
        hl = h[low]
        phi = self.shear_factor(u)[low]
        with np.errstate(over="ignore"):  # A1E / H = inf for denormal H: redone below
            d = phi * (_PC_A1E / hl - _PC_A2E + 2.0 * _PC_A3E * hl)
        tiny = ~np.isfinite(d) | (phi == 0.0)
        if np.any(tiny):
            ht = hl[tiny]
            e = np.exp(-_PC_A2E * ht + _PC_A3E * ht * ht)
            d[tiny] = (
                _PC_A1
                * e
                * (_PC_A1E * ht ** (_PC_A1E - 1.0) + ht**_PC_A1E * (-_PC_A2E + 2.0 * _PC_A3E * ht))
            )
        out[low] = d
        out[~low] = -0.25 * _PC_A2 * np.exp(-0.25 * h[~low])
        return out / self.sigma


class LogHermiteTable:
    """A flow factor as a piecewise cubic Hermite interpolant in ``s = ln(u / h_rms)``.

    The form the FEM film evaluates in UFL
    (:func:`dolfinx_seal.film.surface.pressure_flow_factor`): node values and
    slopes of a tabulated factor (C1, exact derivative for Newton).  Below the
    first node ``phi = phi_0 (H/H_0)^k`` with ``k`` matching the slope (-> 0 at
    contact); above the last ``phi = 1 - c/H^2`` with ``c = (1 - phi_N) H_N^2``
    (Tripp's tail).  :meth:`__call__` is the same function in numpy.

    The table must describe a flow factor, ``0 <= phi <= 1`` for every ``u > 0``:
    the constructor checks that ``dphi/ds >= 0`` at the first node (else the
    power law below it would grow without bound as ``u -> 0``) and that every
    cubic segment stays in ``[0, 1]`` (at its ends and interior extrema), and
    raises ParameterError otherwise.

    Args:
        s: Nodes ``ln(u/h_rms)`` (increasing).
        phi: Values at the nodes.
        dphi_ds: Slopes ``d phi / d s`` at the nodes.
        h_rms: Rms roughness [m].
    """

    name = "log-hermite-table"

    def __init__(self, s: ArrayLike, phi: ArrayLike, dphi_ds: ArrayLike, h_rms: float) -> None:
        self.s = np.asarray(s, dtype=float)
        self.phi = np.asarray(phi, dtype=float)
        self.dphi = np.asarray(dphi_ds, dtype=float)
        self.h_rms = check_positive("h_rms", h_rms, "m")
        if not (np.all(np.diff(self.s) > 0) and self.phi[0] > 0 and self.phi[-1] < 1):
            raise ParameterError("LogHermiteTable: nodes must increase and 0 < phi < 1 at the ends")
        if not (np.all(np.isfinite(self.phi)) and np.all(np.isfinite(self.dphi))):
            raise ParameterError("LogHermiteTable: phi and dphi_ds must be finite")
        if self.dphi[0] < 0:
            raise ParameterError(
                f"LogHermiteTable: dphi/ds = {self.dphi[0]:.6g} at the first node is outside "
                "the allowed range dphi/ds >= 0 (phi_0 (H/H_0)^k below it would grow without "
                "bound as u -> 0)"
            )
        for j in range(self.s.size - 1):
            t, v = self._segment_extrema(j)
            k = int(np.argmin(v)) if v.min() < 0.0 else int(np.argmax(v))
            if v[k] < 0.0 or v[k] > 1.0:
                sk = self.s[j] + t[k] * (self.s[j + 1] - self.s[j])
                raise ParameterError(
                    f"LogHermiteTable: the interpolant reaches phi = {v[k]:.6g} at u/h_rms = "
                    f"{math.exp(sk):.6g}, outside the allowed range [0, 1] of a flow factor"
                )
        self.k_low = self.dphi[0] / self.phi[0]
        self.c_tail = (1.0 - self.phi[-1]) * math.exp(2.0 * self.s[-1])

    def _segment_extrema(self, j: int) -> tuple[FloatArray, FloatArray]:
        """Local coordinates ``t in [0, 1]`` of the ends and interior extrema of segment
        ``j`` and the values there."""
        h = float(self.s[j + 1] - self.s[j])
        p0, p1 = float(self.phi[j]), float(self.phi[j + 1])
        d0, d1 = float(self.dphi[j]) * h, float(self.dphi[j + 1]) * h
        c1, c2, c3 = d0, -3 * p0 - 2 * d0 + 3 * p1 - d1, 2 * p0 + d0 - 2 * p1 + d1
        roots = np.roots([3 * c3, 2 * c2, c1]) if (c3 or c2) else np.array([])
        r = roots.real[(np.abs(roots.imag) < 1e-12) & (roots.real > 0) & (roots.real < 1)]
        t = np.concatenate(([0.0, 1.0], r))
        return t, np.array(self.segment(j, self.s[j] + t * h), dtype=float)

    def segment(self, j: int, s: Any) -> Any:
        """Cubic Hermite polynomial of interval ``j`` at ``s`` (numpy or UFL)."""
        s0, h = float(self.s[j]), float(self.s[j + 1] - self.s[j])
        p0, p1 = float(self.phi[j]), float(self.phi[j + 1])
        d0, d1 = float(self.dphi[j]) * h, float(self.dphi[j + 1]) * h
        t = (s - s0) / h
        t2, t3 = t * t, t * t * t
        return (
            (2 * t3 - 3 * t2 + 1) * p0
            + (t3 - 2 * t2 + t) * d0
            + (-2 * t3 + 3 * t2) * p1
            + (t3 - t2) * d1
        )

    def __call__(self, u: ArrayLike) -> FloatArray:
        """``phi(u)`` [-] at separations ``u`` [m] (numpy)."""
        ua = as_array("u", u, 0.0, law=self.name, unit="m")
        H = np.maximum(ua / self.h_rms, 1e-300)
        s = np.log(H)
        out = np.empty_like(H)
        lo, hi = s < self.s[0], s > self.s[-1]
        out[lo] = self.phi[0] * np.exp(self.k_low * (s[lo] - self.s[0]))
        with np.errstate(over="ignore"):  # H^2 = inf: phi = 1
            out[hi] = 1.0 - self.c_tail / H[hi] ** 2
        mid = ~(lo | hi)
        j = np.clip(np.searchsorted(self.s, s[mid], side="right") - 1, 0, self.s.size - 2)
        out[mid] = [self.segment(int(jj), ss) for jj, ss in zip(j, s[mid], strict=True)]
        return out


def bruggeman_conductivity(
    contact: float, weights: ArrayLike, separations: ArrayLike, gh_weights: ArrayLike
) -> float:
    """Effective conductivity ``s`` (in units of ``u^3``) of the 2D Bruggeman condition.

    Args:
        contact: Weight of ``u = 0`` (the contact area ``A1/A0``).
        weights: Weights of the separation classes, shape ``(n,)``.
        separations: Separations of each class at its quadrature nodes [m], ``(n, k)``.
        gh_weights: Quadrature weights over the nodes (summing to 1), ``(k,)``.

    Returns:
        ``s`` [m^3]; 0 when ``contact >= 1/2`` (percolated contact, no flow).
    """
    w = np.asarray(weights, float)
    lu3 = 3.0 * np.log(np.maximum(np.asarray(separations, float), 1e-300))  # ln u^3
    gw = np.asarray(gh_weights, float)
    total = contact + float(np.sum(w))
    if contact >= 0.5 * total:
        return 0.0

    def g(ls: float) -> float:
        # (s - u^3)/(s + u^3) = -tanh((ln u^3 - ln s)/2), stable for any magnitude
        return contact + float(w @ (-np.tanh(0.5 * (lu3 - ls)) @ gw))

    hi = float(np.max(lu3)) + 1.0  # g(hi) > 0: every class conducts less than s
    lo = hi - 10.0
    while g(lo) > 0:
        lo -= 10.0
    return math.exp(brentq(g, lo, hi, xtol=1e-13, rtol=1e-13))


class BruggemanFlowFactor:
    """Persson-type effective-medium pressure flow factor ``phi_p(u)`` (module docstring).

    Computed once on a table of nominal pressures, then evaluated by a monotone
    interpolant in the mean separation; ``phi_p = 0`` below the percolation
    separation and ``1 - c (h_rms/u)^2`` (``c`` matched to the table end) above it.

    Args:
        psd: Roughness spectrum (the stochastic part in a two-scale model).
        e_star: ``E*`` [Pa].
        gamma: Yang-Persson factor.
        n_pressures: Table size.
        points_per_decade: Magnification nodes per decade.
    """

    name = "persson-bruggeman"

    def __init__(
        self,
        psd: PowerSpectrum,
        e_star: float,
        gamma: float = 0.4,
        n_pressures: int = 40,
        points_per_decade: int = 30,
    ) -> None:
        check_int_range("n_pressures", n_pressures, 8)
        check_int_range("points_per_decade", points_per_decade, 5)
        th = PerssonTheory(psd, e_star, gamma)
        self.theory = th
        self.h_rms = psd.h_rms()
        p_perc = th.e_star * psd.rms_slope() * float(erfinv(0.5)) / math.sqrt(2.0)
        p = np.geomspace(1e-11 * th.e_star, 0.995 * p_perc, n_pressures)
        nz = max(8, math.ceil(math.log10(th.zeta_max) * points_per_decade))
        z = np.geomspace(1.0, th.zeta_max * (1.0 - 1e-6), nz)
        prof = th.profile(p, z)
        zk, wk = np.polynomial.hermite_e.hermegauss(24)
        wk = wk / wk.sum()
        phi = np.empty(p.size)
        for j in range(p.size):
            u = np.abs(prof.u1[:, j, None] + prof.h_band[:, None] * zk[None, :])
            s = bruggeman_conductivity(prof.area[-1, j], prof.area_drop[:, j], u, wk)
            phi[j] = s / prof.mean_separation[0, j] ** 3
        ubar = prof.mean_separation[0][::-1]
        if not (np.all(np.isfinite(phi)) and np.all((phi >= 0.0) & (phi < 1.0))):
            raise ParameterError(
                f"{self.name}: the computed pressure flow factor leaves the allowed range "
                f"[0, 1) (min {np.min(phi):.6g}, max {np.max(phi):.6g}); check the PSD"
            )
        self.u_table, self.phi_table = ubar, phi[::-1]
        self.percolation_separation = float(ubar[0])
        self._interp = PchipInterpolator(ubar, self.phi_table, extrapolate=False)
        self._dinterp = self._interp.derivative()
        self._c_tail = (1.0 - self.phi_table[-1]) * (ubar[-1] / self.h_rms) ** 2

    def pressure_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_p(u)`` [-], ``u > 0`` [m]."""
        ua = as_array("u", u, 0.0, law=self.name, unit="m")
        out = np.zeros_like(ua)
        mid = (ua >= self.u_table[0]) & (ua <= self.u_table[-1])
        out[mid] = self._interp(ua[mid])
        big = ua > self.u_table[-1]
        with np.errstate(under="ignore"):
            out[big] = 1.0 - self._c_tail * (self.h_rms / ua[big]) ** 2
        return out

    def dpressure_factor_du(self, u: ArrayLike) -> FloatArray:
        """``d phi_p / du`` [1/m] (of the interpolant)."""
        ua = as_array("u", u, 0.0, law=self.name, unit="m")
        out = np.zeros_like(ua)
        mid = (ua >= self.u_table[0]) & (ua <= self.u_table[-1])
        out[mid] = self._dinterp(ua[mid])
        big = ua > self.u_table[-1]
        with np.errstate(over="ignore"):  # u^3 = inf: slope 0
            out[big] = 2.0 * self._c_tail * self.h_rms**2 / ua[big] ** 3
        return out

    def hermite_table(
        self, n: int = 25, h_min: float = 0.05, h_max: float = 12.0
    ) -> LogHermiteTable:
        """The piecewise cubic Hermite form of :meth:`pressure_factor` in ``ln(u/h_rms)``
        on ``n`` nodes in ``[h_min, h_max] h_rms`` (for the FEM film; see
        :class:`LogHermiteTable`).

        Where the film stops percolating above ``h_min h_rms`` (a narrow spectrum,
        e.g. the homogenised part of a two-scale split far above ``q0``: its
        percolation separation reaches 0.056 h_rms on the default lip sector with
        ``q_th = 4 q0``), ``phi_p`` vanishes at ``h_min`` and no table can start
        there: the first node is then the table's first separation above the
        percolation one, and the power law below it is the continuation towards
        contact, as below ``h_min`` otherwise."""
        check_int_range("n", n, 4)
        check_range("h_min", h_min, 0.0, 1.0, lo_open=True, unit="h_rms")
        check_range("h_max", h_max, 2.0, 1e3, unit="h_rms")
        lo = h_min if h_min * self.h_rms > self.u_table[0] else self.u_table[1] / self.h_rms
        H = np.geomspace(lo, h_max, n)
        u = H * self.h_rms
        phi = self.pressure_factor(u)
        dphi_ds = self.dpressure_factor_du(u) * u  # d phi / d ln u
        return LogHermiteTable(np.log(H), phi, dphi_ds, self.h_rms)

    def shear_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_s = 0`` (S0's choice, see the module docstring)."""
        return np.zeros_like(as_array("u", u, 0.0, law=self.name, unit="m"))
