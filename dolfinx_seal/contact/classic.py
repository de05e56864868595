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

Domains (see :mod:`~dolfinx_seal.contact.base`): ``pressure(u)`` is defined,
finite and ``>= 0`` for every real ``u`` (a Newton iterate may overshoot); ``u``
is the signed distance from the summit (GW, GT) or surface (BGT) mean plane, so
``separation(p)`` may return ``u < 0``.  The GW and GT summit areas add up to
``A/A0 = 1`` at a finite pressure ``p_full`` (separation ``u_full``): the area
functions raise ParameterError beyond it, since the independent-summit model
has no meaning once the summit contacts would cover more than the nominal area.
The BGT pressure is bounded by ``E* (m2/pi)^{1/2} / 2`` (``A/A0 -> 1/2`` as
``u -> -inf``), the upper end of the domain of its ``separation`` and
``area_fraction``.
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
    check_at_most,
    domain_error,
    finite_slope,
    invert_decreasing,
)
from dolfinx_seal.params import check_choice, check_positive, check_range
from dolfinx_seal.roughness.psd import PowerSpectrum

_SQ2PI = math.sqrt(2.0 * math.pi)
_GH = np.polynomial.hermite_e.hermegauss(80)
#: Above this ``lambda``, ``F_n(lambda) < exp(-lambda^2/2) <= exp(-800)`` underflows to 0
#: for every allowed order (and ``pbdv`` returns NaN for very large arguments).
_LAM_ZERO = 40.0
#: Floor of ``lambda = u/sigma`` in the GW/GT pressures: ``F_{5/2}(-1e100) ~ 1e250`` keeps
#: ``p`` finite for any real ``u`` (a penetration of 1e100 sigma is far beyond any state).
_LAM_FLOOR = -1e100
#: Largest ``ln`` of a pressure, as in PerssonExponentialLaw (``exp(700) ~ 1e304``).
_EXP_CAP = 700.0


def gw_function(n: float, lam: ArrayLike) -> FloatArray:
    """``F_n(lambda)`` of Greenwood-Williamson (S2 eq 29), ``n > -1``, any real ``lambda``.

    Jedynak's parabolic-cylinder form for ``-30 <= lambda <= 40``; below, where
    ``D_{-n-1}`` would overflow, ``F_n = E[(Z - lambda)^n]`` (the Gaussian mass
    below ``lambda`` is < 1e-196) by 80-point Gauss-Hermite quadrature; above 40,
    0 (``F_n`` is below the smallest double there).
    """
    check_range("n", n, -1.0, 50.0, lo_open=True)
    x = as_array("lambda", lam)
    out = np.zeros_like(x, dtype=float)
    ok = (x >= -30.0) & (x <= _LAM_ZERO)
    if np.any(ok):
        d, _ = pbdv(-n - 1.0, x[ok])
        out[ok] = gamma(n + 1.0) / _SQ2PI * np.exp(-0.25 * x[ok] ** 2) * d
    neg = x < -30.0
    if np.any(neg):
        z, w = _GH
        out[neg] = ((z[None, :] - x[neg][:, None]) ** n) @ w / _SQ2PI
    return out


def gw_function_derivative(n: float, lam: ArrayLike) -> FloatArray:
    """``dF_n/dlambda = -n F_{n-1}`` (``n > 0``), ``-exp(-lambda^2/2)/sqrt(2 pi)`` for n = 0."""
    x = as_array("lambda", lam)
    if n == 0:
        return -np.exp(-0.5 * x * x) / _SQ2PI
    return -n * gw_function(n - 1.0, x)


class GreenwoodWilliamson(AreaFromSeparation, ContactLaw):
    """Greenwood-Williamson law with Gaussian (default) or exponential summit heights.

    ``u`` [m] is the signed distance of the flat from the mean plane of the
    summit heights.  ``pressure(u)`` is finite and ``>= 0`` for every real ``u``;
    ``separation(p)`` is its inverse for ``0 < p <= p_max`` (``u < 0`` at high
    load).  The summit areas reach ``A/A0 = 1`` at ``u_full`` [m] / ``p_full``
    [Pa]; the area functions raise ParameterError beyond.

    Attributes:
        u_full, p_full: Separation [m] and pressure [Pa] where ``A/A0 = 1``.
        p_max: Largest pressure of the law [Pa] (``lambda`` at its floor -1e100, or
            ``p = exp(700)`` Pa for exponential summits).

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
        # exp(-lambda) capped so that p = pk exp(-lambda) stays below exp(700) Pa
        self._cap = _EXP_CAP - max(math.log(self._pk), 0.0)
        if distribution == "gaussian":
            lam_full = float(
                invert_decreasing(
                    lambda x: gw_function(1.0, x),
                    lambda x: gw_function_derivative(1.0, x),
                    np.array([1.0 / self._ak]), -3.0, 3.0,
                )[0]
            )  # fmt: skip
            self.p_max = float(self._pk * gw_function(1.5, np.array(_LAM_FLOOR)))
        else:
            lam_full = math.log(self._ak)
            self.p_max = self._pk * math.exp(self._cap)
        self.u_full = lam_full * self.sigma
        self.p_full = float(self.pressure(np.array(self.u_full)))

    def _lam(self, u: ArrayLike) -> FloatArray:
        return as_array("u", u, law=self.name, unit="m") / self.sigma

    def pressure(self, u: ArrayLike) -> FloatArray:
        """Nominal asperity pressure [Pa] at separation ``u`` [m] (any real ``u``).

        Finite for every ``u``: ``lambda`` is floored at -1e100 (Gaussian) and the
        exponential's ``p`` capped at ``exp(700)`` Pa, far beyond any state.
        """
        lam = self._lam(u)
        if self.distribution == "gaussian":
            return self._pk * gw_function(1.5, np.maximum(lam, _LAM_FLOOR))
        return self._pk * np.exp(np.minimum(-lam, self._cap))

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact ``dp/du`` [Pa/m]."""
        lam = self._lam(u)
        if self.distribution == "gaussian":
            return self._pk * gw_function_derivative(1.5, np.maximum(lam, _LAM_FLOOR)) / self.sigma
        with np.errstate(over="ignore"):
            return finite_slope(-self.pressure(u) / self.sigma)

    def _area_at(self, u: FloatArray) -> FloatArray:
        """Sum of the summit areas (S2 eqs 24, 27), unbounded as ``u -> -inf``."""
        lam = np.maximum(u / self.sigma, _LAM_FLOOR)
        if self.distribution == "gaussian":
            return self._ak * gw_function(1.0, lam)
        return self._ak * np.exp(np.minimum(-lam, _EXP_CAP))

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m] of :meth:`pressure`, ``p > 0`` [Pa] (closed form for
        exponential summits); ``u < 0`` above ``p(0)``."""
        pa = as_array("p", p, 0.0, law=self.name, unit="Pa")
        check_at_most(
            self.name, "p", pa, self.p_max, f"0 < p <= {self.p_max:.6g} Pa", "Pa",
            "the largest pressure of the law, at a penetration of 1e100 sigma",
        )  # fmt: skip
        if self.distribution == "exponential":
            with np.errstate(over="ignore"):
                u = np.array(self.sigma * np.log(self._pk / pa), dtype=float)
            big = ~np.isfinite(u)  # pk/p overflows for denormal p
            u[big] = self.sigma * (math.log(self._pk) - np.log(pa[big]))
            return u if u.ndim else u[()]
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

    Domains as for :class:`GreenwoodWilliamson`: ``u`` [m] is signed (mean
    plane of the summits), ``pressure`` finite for every real ``u``,
    ``separation`` its inverse for ``0 < p <= p_max``; the area functions raise
    ParameterError beyond ``u_full`` / ``p_full`` where ``A/A0 = 1`` (attributes
    as there).

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
        lam_full = float(
            invert_decreasing(
                lambda x: gw_function(2.0, x),
                lambda x: gw_function_derivative(2.0, x),
                np.array([1.0 / self._ak]), -3.0, 3.0,
            )[0]
        )  # fmt: skip
        self.p_max = float(self._pk * gw_function(2.5, np.array(_LAM_FLOOR)))
        self.u_full = lam_full * self.sigma
        self.p_full = float(self.pressure(np.array(self.u_full)))

    def _lam(self, u: ArrayLike) -> FloatArray:
        lam = as_array("u", u, law=self.name, unit="m") / self.sigma
        return np.maximum(lam, _LAM_FLOOR)

    def pressure(self, u: ArrayLike) -> FloatArray:
        """Asperity pressure [Pa] at mean-plane separation ``u`` [m] (any real ``u``;
        ``lambda`` floored at -1e100 so ``p`` stays finite)."""
        return self._pk * gw_function(2.5, self._lam(u))

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact derivative [Pa/m] (``F'_{5/2} = -(5/2) F_{3/2}``)."""
        return self._pk * gw_function_derivative(2.5, self._lam(u)) / self.sigma

    def _area_at(self, u: FloatArray) -> FloatArray:
        """``A/A0 = pi^2 (eta beta sigma)^2 F_2(u/sigma)`` (unbounded as ``u -> -inf``)."""
        return self._ak * gw_function(2.0, np.maximum(u / self.sigma, _LAM_FLOOR))

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m] of :meth:`pressure`, ``p > 0`` [Pa]."""
        pa = as_array("p", p, 0.0, law=self.name, unit="Pa")
        check_at_most(
            self.name, "p", pa, self.p_max, f"0 < p <= {self.p_max:.6g} Pa", "Pa",
            "the largest pressure of the law, at a penetration of 1e100 sigma",
        )  # fmt: skip
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

    ``pressure(u)`` is finite for every real ``u`` and bounded by ``p_max = E*
    (m2/pi)^{1/2} / 2`` [Pa] (``A/A0 -> 1/2`` as ``u -> -inf``); ``separation`` and
    ``area_fraction`` take ``0 < p < p_max`` and ``0 <= p <= p_max`` and raise
    ParameterError above.

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
        #: Supremum of the pressure [Pa] (``u -> -inf``, ``A/A0 -> 1/2``).
        self.p_max = 0.5 * self._pa

    @classmethod
    def from_psd(cls, psd: PowerSpectrum, e_star: float) -> BushGibsonThomas:
        """``sigma = h_rms``, ``m2 = <|grad h|^2>/2`` of the spectrum."""
        m0, m2, _ = psd.nayak_moments()
        return cls(math.sqrt(m0), m2, e_star)

    def area_fraction_at(self, u: ArrayLike) -> FloatArray:
        """``A/A0 = erfc(u / (sqrt 2 sigma)) / 4``."""
        ua = as_array("u", u, law=self.name, unit="m")
        return 0.25 * erfc(ua / (math.sqrt(2.0) * self.sigma))

    def pressure(self, u: ArrayLike) -> FloatArray:
        """``p = E* (m2/pi)^{1/2} erfc(u/(sqrt 2 sigma)) / 4`` [Pa]."""
        return self._pa * self.area_fraction_at(u)

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact derivative [Pa/m]."""
        x = as_array("u", u, law=self.name, unit="m") / self.sigma
        with np.errstate(over="ignore"):  # x^2 = inf far out: slope 0
            g = np.exp(-0.5 * x * x)
        return -self._pa * 0.25 * math.sqrt(2.0 / math.pi) / self.sigma * g

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """``A/A0 = p / (E* (m2/pi)^{1/2})`` (linear in the load), ``0 <= p <= p_max`` [Pa]."""
        pa = as_array("p", p, 0.0, lo_open=False, law=self.name, unit="Pa")
        check_at_most(
            self.name, "p", pa, self.p_max,
            f"0 <= p <= p_max = E* (m2/pi)^(1/2) / 2 = {self.p_max:.6g} Pa", "Pa",
            "the largest pressure of the law, where A/A0 = 1/2",
        )  # fmt: skip
        return pa / self._pa

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m] for ``0 < p < p_max = E* (m2/pi)^{1/2} / 2`` [Pa]."""
        pa = as_array("p", p, 0.0, law=self.name, unit="Pa")
        bad = pa >= self.p_max
        if np.any(bad):
            raise domain_error(
                self.name, "p", float(pa[bad].ravel()[0]),
                f"0 < p < p_max = E* (m2/pi)^(1/2) / 2 = {self.p_max:.6g} Pa", "Pa",
                f"p/p_max = {float(pa[bad].ravel()[0]) / self.p_max:.6g}; p_max is reached "
                "only as u -> -inf",
            )  # fmt: skip
        # floor at the smallest normal double (u ~ 37.5 sigma): erfcinv is inf for
        # denormal arguments, which 4 p / (E* (m2/pi)^(1/2)) becomes for p below ~1e-300 Pa
        y = np.maximum(4.0 * pa / self._pa, np.finfo(float).tiny)
        return math.sqrt(2.0) * self.sigma * erfcinv(y)
