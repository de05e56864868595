"""Classic asperity contact laws (S2 section 4): GW, Greenwood-Tripp, Bush-Gibson-Thomas.

Separations ``u`` are measured from the mean plane of the summit heights (GW,
GT) or of the surface heights (BGT), in metres; ``lambda = u / sigma``.

* Greenwood-Williamson (S2 eqs 18-29): summit density ``eta_s`` [1/m^2], summit
  radius ``R`` [m], summit-height standard deviation ``sigma`` [m]:
  ``A/A0 = pi eta_s R sigma F_1(lambda)``, ``p = (4/3) eta_s E* R^{1/2} sigma^{3/2}
  F_{3/2}(lambda)`` for Gaussian summits, and ``exp(-lambda)`` in place of
  ``F_n`` with the prefactor ``sqrt(pi)`` for exponential summits (S2 eqs 23-25).
  S2 eq 28 prints ``sqrt(pi)`` also for the Gaussian case; that contradicts its
  own eqs 22 and 29 (which give ``4/3``, as in GW 1966), so ``4/3`` is used.
* Greenwood-Tripp (S2 eq 31): ``p = (16 sqrt 2 / 15) pi (eta beta sigma)^2 E*
  (sigma/beta)^{1/2} F_{5/2}(lambda)``; area ``pi^2 (eta beta sigma)^2 F_2``
  (Greenwood & Tripp 1970, not printed in S2).
* Bush-Gibson-Thomas (S2 eq 33, ``A ~ erfc(lambda/sqrt 2)``), in its
  high-separation asymptotic form derived from Nayak's summit statistics with
  Hertzian (spherical in the limit) summits: ``A/A0 = erfc(lambda/sqrt 2)/4`` --
  half the bearing area -- and ``p = E* (m2/pi)^{1/2} A/A0``, i.e. ``A/A0 =
  kappa p / (E* <|grad h|^2>^{1/2})`` with ``kappa = (2 pi)^{1/2}``, the BGT
  constant (derivation in docs of :class:`BushGibsonThomas`).

``F_n(lambda) = (2 pi)^{-1/2} int_lambda^inf (s - lambda)^n exp(-s^2/2) ds`` (S2
eq 29) is evaluated with Jedynak's closed form (S2 eq 30), ``F_n = Gamma(n+1)
(2 pi)^{-1/2} exp(-lambda^2/4) D_{-n-1}(lambda)`` (``U(n + 1/2, x) = D_{-n-1}(x)``),
and ``dF_n/dlambda = -n F_{n-1}`` gives exact derivatives.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.special import erfc, erfcinv, gamma, pbdv

from dolfinx_seal.contact.base import (
    AreaFromSeparation,
    ContactLaw,
    FloatArray,
    as_array,
    invert_decreasing,
)
from dolfinx_seal.params import check_choice, check_positive, check_range
from dolfinx_seal.roughness.psd import PowerSpectrum

_SQ2PI = math.sqrt(2.0 * math.pi)
_GH = np.polynomial.hermite_e.hermegauss(80)


def gw_function(n: float, lam: ArrayLike) -> FloatArray:
    """``F_n(lambda)`` of Greenwood-Williamson (S2 eq 29), ``n > -1``, any real ``lambda``.

    Jedynak's parabolic-cylinder form for ``lambda >= -30``; below, where
    ``D_{-n-1}`` would overflow, ``F_n = E[(Z - lambda)^n]`` (the Gaussian mass
    below ``lambda`` is < 1e-196) by 80-point Gauss-Hermite quadrature.
    """
    check_range("n", n, -1.0, 50.0, lo_open=True)
    x = as_array("lambda", lam)
    out = np.empty_like(x, dtype=float)
    ok = x >= -30.0
    if np.any(ok):
        d, _ = pbdv(-n - 1.0, x[ok])
        out[ok] = gamma(n + 1.0) / _SQ2PI * np.exp(-0.25 * x[ok] ** 2) * d
    if np.any(~ok):
        z, w = _GH
        out[~ok] = ((z[None, :] - x[~ok][:, None]) ** n) @ w / _SQ2PI
    return out


def gw_function_derivative(n: float, lam: ArrayLike) -> FloatArray:
    """``dF_n/dlambda = -n F_{n-1}`` (``n > 0``), ``-exp(-lambda^2/2)/sqrt(2 pi)`` for n = 0."""
    x = as_array("lambda", lam)
    if n == 0:
        return -np.exp(-0.5 * x * x) / _SQ2PI
    return -n * gw_function(n - 1.0, x)


class GreenwoodWilliamson(AreaFromSeparation, ContactLaw):
    """Greenwood-Williamson law with Gaussian (default) or exponential summit heights.

    Args:
        summit_density: ``eta_s`` [1/m^2].
        summit_radius: ``R`` [m].
        sigma: Standard deviation of the summit heights [m].
        e_star: ``E*`` [Pa].
        distribution: ``"gaussian"`` or ``"exponential"``.
    """

    def __init__(
        self,
        summit_density: float,
        summit_radius: float,
        sigma: float,
        e_star: float,
        distribution: str = "gaussian",
    ) -> None:
        self.eta = check_positive("summit_density", summit_density, "1/m^2")
        self.radius = check_positive("summit_radius", summit_radius, "m")
        self.sigma = check_positive("sigma", sigma, "m")
        self.e_star = check_positive("e_star", e_star, "Pa")
        self.distribution = check_choice("distribution", distribution, ("gaussian", "exponential"))
        self.name = f"gw-{distribution}"
        root = math.sqrt(self.radius) * self.sigma**1.5
        if distribution == "gaussian":
            self._pk = 4.0 / 3.0 * self.eta * self.e_star * root
        else:
            self._pk = math.sqrt(math.pi) * self.eta * self.e_star * root
        self._ak = math.pi * self.eta * self.radius * self.sigma

    def _lam(self, u: ArrayLike) -> FloatArray:
        return as_array("u", u) / self.sigma

    def pressure(self, u: ArrayLike) -> FloatArray:
        """Nominal asperity pressure [Pa] at separation ``u`` [m] (any real ``u``)."""
        lam = self._lam(u)
        if self.distribution == "gaussian":
            return self._pk * gw_function(1.5, lam)
        return self._pk * np.exp(np.minimum(-lam, 700.0))

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact ``dp/du`` [Pa/m]."""
        lam = self._lam(u)
        if self.distribution == "gaussian":
            return self._pk * gw_function_derivative(1.5, lam) / self.sigma
        return -self.pressure(u) / self.sigma

    def area_fraction_at(self, u: ArrayLike) -> FloatArray:
        """``A/A0`` at separation ``u`` (S2 eqs 24, 27)."""
        lam = self._lam(u)
        if self.distribution == "gaussian":
            return self._ak * gw_function(1.0, lam)
        return self._ak * np.exp(np.minimum(-lam, 700.0))

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m], ``p > 0`` (closed form for exponential summits)."""
        pa = as_array("p", p, 0.0)
        if self.distribution == "exponential":
            return self.sigma * np.log(self._pk / pa)
        return invert_decreasing(
            self.pressure, self.dpressure_du, pa, -3 * self.sigma, 3 * self.sigma
        )

    @classmethod
    def from_psd(
        cls, psd: PowerSpectrum, e_star: float, distribution: str = "gaussian"
    ) -> GreenwoodWilliamson:
        """Summit parameters from Nayak's moments (McCool 1986, for bandwidth ``alpha > 0.9``).

        ``eta_s = m4 / (6 pi sqrt 3 m2)``, ``R = 0.375 (pi / m4)^{1/2}``,
        ``sigma_s = (1 - 0.8968 / alpha)^{1/2} m0^{1/2}`` with ``alpha = m0 m4 / m2^2``.
        """
        m0, m2, m4 = psd.nayak_moments()
        alpha = m0 * m4 / m2**2
        check_range("Nayak bandwidth alpha", alpha, 0.8968, math.inf, lo_open=True)
        eta = m4 / (6.0 * math.pi * math.sqrt(3.0) * m2)
        radius = 0.375 * math.sqrt(math.pi / m4)
        sigma = math.sqrt((1.0 - 0.8968 / alpha) * m0)
        return cls(eta, radius, sigma, e_star, distribution)


class GreenwoodTripp(AreaFromSeparation, ContactLaw):
    """Greenwood-Tripp two-rough-surface law (S2 eq 31).

    Args:
        summit_density: ``eta`` [1/m^2].
        summit_radius: ``beta`` [m].
        sigma: Combined rms roughness [m].
        e_star: ``E*`` [Pa].
    """

    name = "greenwood-tripp"

    def __init__(
        self, summit_density: float, summit_radius: float, sigma: float, e_star: float
    ) -> None:
        self.eta = check_positive("summit_density", summit_density, "1/m^2")
        self.radius = check_positive("summit_radius", summit_radius, "m")
        self.sigma = check_positive("sigma", sigma, "m")
        self.e_star = check_positive("e_star", e_star, "Pa")
        ebs = self.eta * self.radius * self.sigma
        self._pk = (
            16.0 * math.sqrt(2.0) / 15.0 * math.pi * ebs**2 * self.e_star
            * math.sqrt(self.sigma / self.radius)
        )  # fmt: skip
        self._ak = math.pi**2 * ebs**2

    def pressure(self, u: ArrayLike) -> FloatArray:
        """Asperity pressure [Pa] at mean-plane separation ``u`` [m]."""
        return self._pk * gw_function(2.5, as_array("u", u) / self.sigma)

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact derivative [Pa/m] (``F'_{5/2} = -(5/2) F_{3/2}``)."""
        return self._pk * gw_function_derivative(2.5, as_array("u", u) / self.sigma) / self.sigma

    def area_fraction_at(self, u: ArrayLike) -> FloatArray:
        """``A/A0 = pi^2 (eta beta sigma)^2 F_2(u/sigma)``."""
        return self._ak * gw_function(2.0, as_array("u", u) / self.sigma)

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m], ``p > 0``."""
        pa = as_array("p", p, 0.0)
        return invert_decreasing(
            self.pressure, self.dpressure_du, pa, -3 * self.sigma, 3 * self.sigma
        )


class BushGibsonThomas(ContactLaw):
    """Bush-Gibson-Thomas law in its high-separation (asymptotic) form.

    With Nayak's density of summits at height ``z sigma`` for large ``z``,
    ``n(z) = (m2/m0) (2 pi)^{-3/2} z^2 e^{-z^2/2}``, and their curvature
    ``m2 z / sigma`` (so radius ``R = sigma/(m2 z)``), Hertz gives per summit
    area ``pi R delta`` and load ``(4/3) E* R^{1/2} delta^{3/2}``,
    ``delta = (z - lambda) sigma``.  The area integral is exact:
    ``A/A0 = (1/4) erfc(lambda/sqrt 2)``; the load integral's leading term gives
    ``p = E* (m2/pi)^{1/2} A/A0`` (``kappa = (2 pi)^{1/2}``).  Valid for
    ``lambda >~ 1.5``, the regime of S2 Table 2.

    Args:
        sigma: rms height [m].
        m2: Profile slope variance ``<h_x^2>`` [-] (``<|grad h|^2>/2``).
        e_star: ``E*`` [Pa].
    """

    name = "bush-gibson-thomas"

    def __init__(self, sigma: float, m2: float, e_star: float) -> None:
        self.sigma = check_positive("sigma", sigma, "m")
        self.m2 = check_positive("m2", m2)
        self.e_star = check_positive("e_star", e_star, "Pa")
        self._pa = self.e_star * math.sqrt(self.m2 / math.pi)

    @classmethod
    def from_psd(cls, psd: PowerSpectrum, e_star: float) -> BushGibsonThomas:
        """``sigma = h_rms``, ``m2 = <|grad h|^2>/2`` of the spectrum."""
        m0, m2, _ = psd.nayak_moments()
        return cls(math.sqrt(m0), m2, e_star)

    def area_fraction_at(self, u: ArrayLike) -> FloatArray:
        """``A/A0 = erfc(u / (sqrt 2 sigma)) / 4``."""
        return 0.25 * erfc(as_array("u", u) / (math.sqrt(2.0) * self.sigma))

    def pressure(self, u: ArrayLike) -> FloatArray:
        """``p = E* (m2/pi)^{1/2} erfc(u/(sqrt 2 sigma)) / 4`` [Pa]."""
        return self._pa * self.area_fraction_at(u)

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact derivative [Pa/m]."""
        x = as_array("u", u) / self.sigma
        return -self._pa * 0.25 * math.sqrt(2.0 / math.pi) / self.sigma * np.exp(-0.5 * x * x)

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """``A/A0 = p / (E* (m2/pi)^{1/2})`` (linear in the load)."""
        return as_array("p", p, 0.0, lo_open=False) / self._pa

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m] for ``0 < p < E* (m2/pi)^{1/2} / 2``."""
        pa = as_array("p", p, 0.0)
        check_range(
            "p / (E* (m2/pi)^(1/2) / 2)",
            float(np.max(pa)) / (0.5 * self._pa),
            0.0,
            1.0,
            hi_open=True,
        )
        return math.sqrt(2.0) * self.sigma * erfcinv(4.0 * pa / self._pa)
