"""Persson contact laws as vectorised objects for the film and FEM solvers.

* :class:`PerssonLaw` -- the full relation ``p(u)`` (Yang-Persson, S1 section 4),
  computed by quadrature once per spectrum and ``E*``, then evaluated through a
  monotone interpolant (PCHIP of ``ln p`` against ``ln u``) whose derivative is
  exact for the interpolant.  Beyond the table it continues C1-smoothly: as
  ``beta E* exp(-alpha u / h_rms)`` with the table's end slope at large ``u``,
  and as ``ln p = A + (1/2) ln ln(c/u)`` at small ``u`` -- the form of the exact
  relation when every ``w p/E* >> 1`` (``u ~ exp(-w^2 p^2/E*^2) / p^2``), which
  diverges as ``u -> 0``.  Finite and positive for every ``u > 0``.
* :class:`PerssonExponentialLaw` -- the asymptote ``beta E* exp(-alpha u/h_rms)``
  alone (S1 eq 4, S0 eq 7), with ``alpha``, ``beta`` from the spectrum.
* :class:`ClosedFormPersson` -- a UFL-friendly closed form
  ``p = beta E* exp(-alpha u/h) (1 + c h/u)^m`` fitted to the full relation,
  with its maximum relative error over the fit window recorded.

Contact area (S0 eq 5, S1 section 4): ``A/A0 = erf(sqrt(2) p / (E* <|grad
h|^2>^{1/2}))``; with a yield stress, ``P_el + P_pl`` of S3 appendix C.

Domains (see :mod:`~dolfinx_seal.contact.base`): the area laws hold for every
``p >= 0`` and give ``0 <= A/A0 <= 1``; ``PerssonLaw`` and ``ClosedFormPersson``
take ``u > 0`` and give finite ``p > 0`` (``p >= 0`` for the closed form, whose
exponential may underflow far from contact); ``PerssonExponentialLaw.pressure``
takes any real ``u``.  The inverses ``separation(p)`` return ``u >= 0`` or raise
ParameterError: ``PerssonLaw`` for ``0 < p <= p_max`` (the pressure at the
smallest normal double separation, of order ``E*``), ``PerssonExponentialLaw``
for ``0 < p <= beta E*`` (where its ``u`` reaches 0).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator
from scipy.optimize import least_squares
from scipy.special import erf, erfinv

from dolfinx_seal.contact.base import (
    ContactLaw,
    FloatArray,
    as_array,
    check_at_most,
    finite_slope,
)
from dolfinx_seal.contact.persson_theory import PerssonTheory, elastoplastic_fractions
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_nonnegative, check_positive, check_range
from dolfinx_seal.roughness.psd import PowerSpectrum

#: Largest exponent passed to ``exp`` (``exp(700) ~ 1e304``); see PerssonExponentialLaw.
_EXP_CAP = 700.0
#: ``ln`` of the smallest normal double: floor of ``ln p`` so ``p(u) > 0`` for every ``u``.
_TINY = float(np.finfo(float).tiny)
_LN_TINY = math.log(_TINY)


class _AreaMixin:
    """``A/A0`` from the erf law, optionally elastoplastic (S3 appendix C)."""

    name: str
    e_star: float
    rms_slope: float
    yield_stress: float | None
    _g_full: float  # G(q1) [Pa^2]

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """``A/A0`` at nominal contact pressure ``p >= 0`` [Pa].

        Elastic: ``erf(sqrt 2 p / (E* slope))``.  With ``yield_stress``:
        ``P_el + P_pl`` (S3 eqs C9-C10); ``p >= yield_stress`` gives 1.  Where
        ``g = G/p^2`` overflows (``p`` below ~1e-150 Pa) both fractions are linear
        in ``p`` (to rounding), and ``A/A0`` is scaled from ``p_ref = 1e-100
        min(yield_stress, G^{1/2})``.
        """
        pa = as_array("p", p, 0.0, lo_open=False, law=self.name, unit="Pa")
        if self.yield_stress is None:
            return erf(math.sqrt(2.0) * pa / (self.e_star * self.rms_slope))
        out = np.ones_like(pa)
        ok = (pa > 0) & (pa < self.yield_stress)
        out[pa == 0] = 0.0
        with np.errstate(over="ignore", divide="ignore"):
            g = self._g_full / np.where(ok, pa, 1.0) ** 2
        lin = ok & ~np.isfinite(g)
        ok &= np.isfinite(g)
        if np.any(ok):
            pel, ppl, _ = elastoplastic_fractions(g[ok], pa[ok] / self.yield_stress)
            out[ok] = pel + ppl
        if np.any(lin):
            p_ref = 1e-100 * min(self.yield_stress, math.sqrt(self._g_full))
            g_ref = self._g_full / p_ref**2
            pel, ppl, _ = elastoplastic_fractions(g_ref, p_ref / self.yield_stress)
            out[lin] = float(pel + ppl) * (pa[lin] / p_ref)
        return out

    def pressure_from_area(self, a: ArrayLike) -> FloatArray:
        """Inverse of the elastic erf law: ``p = E* slope erfinv(a) / sqrt 2`` [Pa].

        Raises ParameterError for ``a`` outside ``[0, 1)``: full contact needs an
        infinite pressure in Persson's theory (``erfinv(1) = inf``).
        """
        aa = as_array("area fraction", a, 0.0, lo_open=False, law=self.name)
        if np.any(aa >= 1.0):
            first = float(aa[aa >= 1.0].ravel()[0])
            raise ParameterError(
                f"contact law {self.name!r}: area fraction = {first!r} is outside the allowed "
                "range [0, 1): it must be < 1 (full contact needs infinite pressure)"
            )
        return self.e_star * self.rms_slope * erfinv(aa) / math.sqrt(2.0)


class PerssonLaw(_AreaMixin, ContactLaw):
    """The full Persson relation ``p(u)`` for a spectrum and effective modulus.

    Args:
        psd: Spectrum of the combined roughness (the stochastic part ``C_sto`` in a
            two-scale model).
        e_star: ``E* = E/(1 - nu^2)`` [Pa].
        gamma: Yang-Persson factor (S1: 0.4).
        yield_stress: Optional yield stress [Pa] for the elastoplastic area (S3 app. C).
        n_table: Number of table pressures (log-spaced).

    Attributes:
        alpha, beta: Analytic asymptote ``p -> beta E* exp(-alpha u/h_rms)`` (small p).
        alpha_fit, beta_fit: The same fitted by least squares to the table where
            ``1e-10 <= p/E* <= 1e-6`` (reported; they agree with the analytic ones).
        h_rms, rms_slope: Of ``psd`` [m], [-].
        u_table, p_table: The tabulated relation (increasing ``u``).
        p_max: Largest pressure [Pa] :meth:`separation` accepts, ``p`` at the smallest
            normal double separation (2.2e-308 m): 0.81, 3.6 and 39 ``E*`` for
            H = 0.95, 0.8 and 0.6 on the S1 spectrum (q1/q0 = 7.8e5).
    """

    name = "persson"

    def __init__(
        self,
        psd: PowerSpectrum,
        e_star: float,
        gamma: float = 0.4,
        yield_stress: float | None = None,
        n_table: int = 240,
    ) -> None:
        self.theory = PerssonTheory(psd, e_star, gamma)
        self.e_star = self.theory.e_star
        self.h_rms = psd.h_rms()
        self.rms_slope = psd.rms_slope()
        self.yield_stress = (
            None if yield_stress is None else check_positive("yield_stress", yield_stress, "Pa")
        )
        self._g_full = float(self.theory.g_function(self.theory.zeta_max))
        self.alpha, self.beta = self.theory.asymptote()
        p = self.e_star * np.geomspace(1e-14, 1e2, n_table)
        u = self.theory.mean_separation(p)
        keep = u > 1e-6 * self.h_rms
        p, u = p[keep][::-1], u[keep][::-1]
        if np.any(np.diff(u) <= 0) or np.any(np.diff(p) >= 0):
            raise ParameterError("the computed Persson relation is not monotone; check the PSD")
        self.u_table, self.p_table = u, p
        self._lu, self._lp = np.log(u), np.log(p)
        self._fwd = PchipInterpolator(self._lu, self._lp, extrapolate=False)
        self._dfwd = self._fwd.derivative()
        # small-u continuation ln p = A + 0.5 ln ln(c/u), C1 at u_min
        d0 = float(self._dfwd(self._lu[0]))  # d ln p / d ln u < 0
        self._lnc_small = self._lu[0] + (-1.0 / (2.0 * d0))  # ln(c/u_min) = -1/(2 d0)
        self._a_small = self._lp[0] - 0.5 * math.log(-1.0 / (2.0 * d0))
        # large-u continuation ln p = lp_end + s (u - u_end), s = d ln p / du at u_end
        self._s_large = float(self._dfwd(self._lu[-1])) / u[-1]
        sel = (p >= 1e-10 * self.e_star) & (p <= 1e-6 * self.e_star)
        slope, icpt = np.polyfit(u[sel] / self.h_rms, np.log(p[sel] / self.e_star), 1)
        self.alpha_fit, self.beta_fit = float(-slope), float(math.exp(icpt))
        self.p_max = float(self.pressure(np.array(_TINY)))

    # ---------------------------------------------------------------- p(u)
    def _ln_p(self, u: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``ln p`` and ``d ln p / du`` on the three pieces."""
        lu = np.log(u)
        lnp = np.empty_like(u)
        dln = np.empty_like(u)
        small = lu < self._lu[0]
        large = lu > self._lu[-1]
        mid = ~(small | large)
        lnp[mid] = self._fwd(lu[mid])
        dln[mid] = self._dfwd(lu[mid]) / u[mid]
        if np.any(small):
            ll = self._lnc_small - lu[small]  # ln(c/u) > 0
            lnp[small] = self._a_small + 0.5 * np.log(ll)
            dln[small] = -0.5 / (ll * u[small])
        if np.any(large):
            lnp[large] = self._lp[-1] + self._s_large * (u[large] - self.u_table[-1])
            dln[large] = self._s_large
        return lnp, dln

    def pressure(self, u: ArrayLike) -> FloatArray:
        """``p(u)`` [Pa] for ``u > 0`` [m]; diverges as ``u -> 0``.

        ``ln p`` is floored at ``ln`` of the smallest normal double so ``p`` stays
        positive instead of underflowing to 0 (only for ``u`` beyond ~300 h_rms).
        """
        ua = as_array("u", u, 0.0, law=self.name, unit="m")
        with np.errstate(over="ignore", divide="ignore"):  # the unused slope at denormal u
            lnp, _ = self._ln_p(ua.ravel())
        return np.exp(np.maximum(lnp, _LN_TINY)).reshape(ua.shape)

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact derivative of :meth:`pressure` [Pa/m] (negative; finite, see
        :func:`~dolfinx_seal.contact.base.finite_slope`)."""
        ua = as_array("u", u, 0.0, law=self.name, unit="m")
        with np.errstate(over="ignore", divide="ignore"):
            lnp, dln = self._ln_p(ua.ravel())
            d = np.exp(np.maximum(lnp, _LN_TINY)) * dln
        return finite_slope(d).reshape(ua.shape)

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m] of :meth:`pressure` (to rounding), ``0 < p <= p_max`` [Pa].

        Above ``p_max`` (of order ``E*``) the separation would be below the smallest
        normal double, outside the domain ``u > 0`` of :meth:`pressure` once
        rounded: ParameterError.
        """
        pa = as_array("p", p, 0.0, law=self.name, unit="Pa")
        check_at_most(
            self.name, "p", pa, self.p_max,
            f"0 < p <= p_max = {self.p_max:.6g} Pa = {self.p_max / self.e_star:.3g} E*", "Pa",
            f"above p_max the separation is below {_TINY:.3g} m",
        )  # fmt: skip
        lp = np.log(pa.ravel())
        # initial guess from the table (monotone in reverse), then Newton on ln p(u)
        lu = np.interp(-lp, -self._lp, self._lu)
        big = lp > self._lp[0]
        lu[big] = self._lnc_small - np.exp(2.0 * (lp[big] - self._a_small))
        lo = lp < self._lp[-1]
        lu[lo] = np.log(self.u_table[-1] + (lp[lo] - self._lp[-1]) / self._s_large)
        u = np.exp(lu)
        for _ in range(30):
            f, d = self._ln_p(u)
            step = (f - lp) / d
            un = np.where(u - step > 0, u - step, 0.5 * u)
            if np.all(np.abs(un - u) <= 1e-14 * un):
                u = un
                break
            u = un
        return u.reshape(pa.shape)

    # --------------------------------------------------------- derived laws
    def exponential(self) -> PerssonExponentialLaw:
        """The asymptotic law with this law's analytic ``alpha``, ``beta``."""
        return PerssonExponentialLaw(
            self.alpha, self.beta, self.e_star, self.h_rms, self.rms_slope, self.yield_stress
        )

    def closed_form(self, u_min: float = 0.05) -> ClosedFormPersson:
        """Fit the closed form of :class:`ClosedFormPersson` for ``u >= u_min h_rms``.

        ``alpha``, ``beta`` are the analytic asymptote (so the large-u limit is
        exact); ``m, c, a, b`` minimise the relative error of ``p`` on
        ``u_min h_rms <= u <= 12 h_rms`` (about 2-3 % for self-affine spectra with
        0.6 <= H <= 0.95 and u_min = 0.05).
        """
        check_range("u_min", u_min, 0.0, 5.0, lo_open=True)
        x = np.geomspace(u_min, 12.0, 400)
        target = np.log(self.pressure(x * self.h_rms) / (self.beta * self.e_star)) + self.alpha * x

        def resid(z: FloatArray) -> FloatArray:
            m, c, a, b = np.exp(z)
            return m * np.log1p(c / x) - a * np.exp(-b * x * x) - target

        sol = least_squares(resid, x0=np.log([0.7, 0.06, 0.6, 0.66]), method="lm")
        m, c, a, b = (float(v) for v in np.exp(sol.x))
        law = ClosedFormPersson(self.alpha, self.beta, m, c, a, b, self.e_star, self.h_rms)
        law.max_rel_error = float(np.max(np.abs(np.expm1(resid(sol.x)))))
        law.window = (u_min * self.h_rms, 12.0 * self.h_rms)
        law.rms_slope = self.rms_slope
        return law

    def summary(self) -> dict[str, float]:
        """Scalars for ``results.json``: asymptote, fit, roughness moments."""
        return {
            "alpha": self.alpha,
            "beta": self.beta,
            "alpha_fit": self.alpha_fit,
            "beta_fit": self.beta_fit,
            "h_rms": self.h_rms,
            "rms_slope": self.rms_slope,
        }


class PerssonExponentialLaw(_AreaMixin, ContactLaw):
    """``p(u) = beta E* exp(-alpha u / h_rms)`` (S1 eq 4, S0 eq 7).

    :meth:`pressure` is defined for every real ``u`` (a Newton iterate may
    overshoot to ``u < 0``); ``ln p`` is capped at 700 (``p ~ 1e304`` Pa, a
    penetration of hundreds of ``h_rms``, far beyond any physical state) so ``p``
    stays finite instead of overflowing.  :meth:`separation` inverts it only on
    ``0 < p <= beta E*``, where ``u >= 0`` (see there).

    Args:
        alpha, beta: Dimensionless parameters (``>0``).
        e_star: ``E*`` [Pa].
        h_rms: rms roughness [m].
        rms_slope: ``<|grad h|^2>^{1/2}`` for :meth:`area_fraction` (optional).
        yield_stress: Optional yield stress [Pa] (elastoplastic area).
    """

    name = "persson-exponential"

    def __init__(
        self,
        alpha: float,
        beta: float,
        e_star: float,
        h_rms: float,
        rms_slope: float | None = None,
        yield_stress: float | None = None,
    ) -> None:
        self.alpha = check_positive("alpha", alpha)
        self.beta = check_positive("beta", beta)
        self.e_star = check_positive("e_star", e_star, "Pa")
        self.h_rms = check_positive("h_rms", h_rms, "m")
        self.rms_slope = (
            float("nan") if rms_slope is None else check_positive("rms_slope", rms_slope)
        )
        self.yield_stress = (
            None if yield_stress is None else check_positive("yield_stress", yield_stress, "Pa")
        )
        self._g_full = (self.e_star * self.rms_slope) ** 2 / 8.0  # G(q1) = E*^2 slope^2 / 8

    @classmethod
    def from_psd(
        cls, psd: PowerSpectrum, e_star: float, gamma: float = 0.4
    ) -> PerssonExponentialLaw:
        """``alpha``, ``beta`` from the analytic small-pressure asymptote of the full relation."""
        a, b = PerssonTheory(psd, e_star, gamma).asymptote()
        return cls(a, b, e_star, psd.h_rms(), psd.rms_slope())

    def pressure(self, u: ArrayLike) -> FloatArray:
        """``beta E* exp(-alpha u/h_rms)`` [Pa], any real ``u`` [m]."""
        ua = as_array("u", u, law=self.name, unit="m")
        with np.errstate(over="ignore"):  # |alpha u/h_rms| = inf: p = exp(700) or 0
            lnp = math.log(self.beta * self.e_star) - self.alpha * ua / self.h_rms
        return np.exp(np.minimum(lnp, _EXP_CAP))

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """``-alpha/h_rms p(u)`` [Pa/m] (finite, see
        :func:`~dolfinx_seal.contact.base.finite_slope`)."""
        with np.errstate(over="ignore"):
            return finite_slope(-self.alpha / self.h_rms * self.pressure(u))

    def separation(self, p: ArrayLike) -> FloatArray:
        """``u = (h_rms/alpha) ln(beta E*/p)`` [m] for ``0 < p <= beta E*`` [Pa].

        The inverted asymptote reaches ``u = 0`` at ``p = beta E*`` and is negative
        above, which no mean separation can be; such pressures raise
        ParameterError (naming the pressure, ``p/E*`` and the bound ``beta E*``)
        rather than returning a value.  A clamped ``u = 0`` was not chosen: it
        is not the inverse (``pressure(0) = beta E* != p``) and would hide that
        the law is used far outside its validity -- it is the small-pressure
        asymptote (``p << beta E*``) of the full relation; for high pressures use
        :class:`PerssonLaw`, whose ``separation`` is positive up to its ``p_max``
        (of order ``E*``).
        The extension of :meth:`pressure` to ``u < 0`` (for Newton overshoots) is
        deliberately not inverted.
        """
        pa = as_array("p", p, 0.0, law=self.name, unit="Pa")
        p_top = self.beta * self.e_star
        bad = pa > p_top
        if np.any(bad):
            first = float(pa[bad].ravel()[0])
            u_neg = math.log(p_top / first) / self.alpha  # in units of h_rms
            raise ParameterError(
                f"contact law {self.name!r}: p = {first:.6g} Pa (p/E* = {first / self.e_star:.3g})"
                f" is outside the allowed range 0 < p <= beta E* = {p_top:.6g} Pa of separation"
                f" (beta = {self.beta:.4g}): the inverted asymptote u = (h_rms/alpha)"
                f" ln(beta E*/p) would be negative ({u_neg:.3g} h_rms); use the full"
                " PerssonLaw at such pressures"
            )
        # p <= beta E* gives beta E*/p >= 1 exactly in floating point, so u >= 0
        with np.errstate(over="ignore"):
            u = np.array(self.h_rms / self.alpha * np.log(p_top / pa), dtype=float)
        big = ~np.isfinite(u)  # beta E*/p overflows for denormal p
        u[big] = self.h_rms / self.alpha * (math.log(p_top) - np.log(pa[big]))
        return u if u.ndim else u[()]

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """``A/A0`` at nominal contact pressure ``p >= 0`` [Pa] (needs ``rms_slope``)."""
        if not math.isfinite(self.rms_slope):
            raise ParameterError(
                f"contact law {self.name!r}: area_fraction needs rms_slope "
                "(construct with rms_slope=...)"
            )
        return super().area_fraction(p)


@dataclass
class ClosedFormPersson(ContactLaw):
    """Closed form of the full relation, for UFL forms:

    ``p(u) = beta E* exp(-alpha x + m ln(1 + c/x) - a exp(-b x^2))``, ``x = u/h_rms``.

    ``alpha``, ``beta`` are the exact small-pressure asymptote; ``m ln(1 + c/x)``
    makes ``p`` diverge as ``u -> 0`` (as ``u^-m``; the exact relation diverges
    more slowly, which matters only far below the fit window) and the Gaussian
    term reproduces the dip of the exact relation below its asymptote near
    ``u ~ 0.3 h_rms``.  ``d ln p/dx = -alpha - m c/(x (x + c)) + 2 a b x exp(-b x^2)``
    stays negative when ``a (2 b)^{1/2} e^{-1/2} < alpha`` (checked in the tests).
    :meth:`formula` builds the expression from any ``exp``/``ln`` (``ufl.exp``, ``ufl.ln``).

    Attributes:
        alpha, beta, m, c, a, b: Parameters (dimensionless).
        e_star: ``E*`` [Pa].
        h_rms: [m].
        max_rel_error: Max ``|p_cf/p - 1|`` over ``window`` (set by the fit).
        window: ``(u_lo, u_hi)`` [m] of the fit.
        rms_slope: ``<|grad h|^2>^{1/2}`` of the roughness [-], for
            :meth:`area_fraction` (nan: no contact-area relation).
    """

    alpha: float
    beta: float
    m: float
    c: float
    a: float
    b: float
    e_star: float
    h_rms: float
    max_rel_error: float = float("nan")
    window: tuple[float, float] = (float("nan"), float("nan"))
    name: str = "persson-closed-form"
    rms_slope: float = float("nan")

    def __post_init__(self) -> None:
        # p > 0 and finite for every u > 0 needs these signs (c >= 0: ln(1 + c/x) real)
        for key in ("alpha", "beta", "e_star", "h_rms"):
            setattr(self, key, check_positive(key, getattr(self, key)))
        for key in ("m", "c", "a", "b"):
            setattr(self, key, check_nonnegative(key, getattr(self, key)))

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """``A/A0 = erf(sqrt 2 p / (E* slope))`` at nominal pressure ``p >= 0`` [Pa],
        the relation the FEM forms use (:func:`~dolfinx_seal.surface.asperity.area_fraction`)."""
        if not (math.isfinite(self.rms_slope) and self.rms_slope > 0):
            return super().area_fraction(p)
        pa = as_array("p", p, 0.0, lo_open=False, law=self.name, unit="Pa")
        return erf(math.sqrt(2.0) * pa / (self.e_star * self.rms_slope))

    def formula(
        self, u: Any, exp: Callable[[Any], Any] = np.exp, ln: Callable[[Any], Any] = np.log
    ) -> Any:
        """``p(u)`` built from the given ``exp``/``ln`` (numpy by default, or UFL's)."""
        x = u / self.h_rms
        expo = -self.alpha * x + self.m * ln(1.0 + self.c / x) - self.a * exp(-self.b * x * x)
        return self.beta * self.e_star * exp(expo)

    def pressure(self, u: ArrayLike) -> FloatArray:
        """``p(u)`` [Pa], ``u > 0`` [m]: :meth:`formula`, finite for every ``u > 0``.

        Where the formula overflows (``u`` below ~1e-300 h_rms, denormal
        separations) ``ln p`` is evaluated as ``... + m (ln(x + c) - ln x)`` and
        capped at 700 (``p ~ 1e304`` Pa), as in :class:`PerssonExponentialLaw`.
        Far from contact ``p`` may underflow to 0.
        """
        ua = as_array("u", u, 0.0, law=self.name, unit="m")
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            p = np.array(self.formula(ua), dtype=float)
        bad = ~np.isfinite(p)
        if np.any(bad):
            x = ua[bad] / self.h_rms
            lnp = (
                math.log(self.beta * self.e_star)
                - self.alpha * x
                + self.m * (np.log(x + self.c) - np.log(x))
                - self.a * np.exp(-self.b * x * x)
            )
            p[bad] = np.exp(np.minimum(lnp, _EXP_CAP))
        return p if p.ndim else p[()]

    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact derivative [Pa/m], ``u > 0`` [m] (finite, see
        :func:`~dolfinx_seal.contact.base.finite_slope`)."""
        ua = as_array("u", u, 0.0, law=self.name, unit="m")
        x = ua / self.h_rms
        with np.errstate(over="ignore", divide="ignore", under="ignore"):
            dlog = (
                -self.alpha
                - self.m * self.c / (x * (x + self.c))
                + 2.0 * self.a * self.b * x * np.exp(-self.b * x * x)
            )
            return finite_slope(self.pressure(ua) * dlog / self.h_rms)
