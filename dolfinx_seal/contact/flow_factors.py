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
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq
from scipy.special import erfinv

from dolfinx_seal.contact.base import FloatArray, as_array
from dolfinx_seal.contact.persson_theory import PerssonTheory
from dolfinx_seal.params import check_int_range, check_positive
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
        return as_array("u", u, 0.0) / self.sigma

    def pressure_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_p(u) = 1 - 0.9 exp(-0.56 u/sigma)`` [-], ``u > 0`` [m]."""
        return 1.0 - _PC_C * np.exp(-_PC_R * self._h(u))

    def dpressure_factor_du(self, u: ArrayLike) -> FloatArray:
        """``d phi_p / du`` [1/m]."""
        return _PC_C * _PC_R / self.sigma * np.exp(-_PC_R * self._h(u))

    def shear_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_s(u)`` [-] for one rough surface."""
        h = self._h(u)
        low = _PC_A1 * h**_PC_A1E * np.exp(-_PC_A2E * h + _PC_A3E * h * h)
        return np.where(h <= 5.0, low, _PC_A2 * np.exp(-0.25 * h))

    def dshear_factor_du(self, u: ArrayLike) -> FloatArray:
        """``d phi_s / du`` [1/m]."""
        h = self._h(u)
        low = self.shear_factor(u) * (_PC_A1E / h - _PC_A2E + 2.0 * _PC_A3E * h)
        high = -0.25 * _PC_A2 * np.exp(-0.25 * h)
        return np.where(h <= 5.0, low, high) / self.sigma


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
        self.u_table, self.phi_table = ubar, phi[::-1]
        self.percolation_separation = float(ubar[0])
        self._interp = PchipInterpolator(ubar, self.phi_table, extrapolate=False)
        self._dinterp = self._interp.derivative()
        self._c_tail = (1.0 - self.phi_table[-1]) * (ubar[-1] / self.h_rms) ** 2

    def pressure_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_p(u)`` [-], ``u > 0`` [m]."""
        ua = as_array("u", u, 0.0)
        out = np.zeros_like(ua)
        mid = (ua >= self.u_table[0]) & (ua <= self.u_table[-1])
        out[mid] = self._interp(ua[mid])
        big = ua > self.u_table[-1]
        out[big] = 1.0 - self._c_tail * (self.h_rms / ua[big]) ** 2
        return out

    def dpressure_factor_du(self, u: ArrayLike) -> FloatArray:
        """``d phi_p / du`` [1/m] (of the interpolant)."""
        ua = as_array("u", u, 0.0)
        out = np.zeros_like(ua)
        mid = (ua >= self.u_table[0]) & (ua <= self.u_table[-1])
        out[mid] = self._dinterp(ua[mid])
        big = ua > self.u_table[-1]
        out[big] = 2.0 * self._c_tail * self.h_rms**2 / ua[big] ** 3
        return out

    def shear_factor(self, u: ArrayLike) -> FloatArray:
        """``phi_s = 0`` (S0's choice, see the module docstring)."""
        return np.zeros_like(as_array("u", u, 0.0))
