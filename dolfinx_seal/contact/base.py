"""The contact-law interface and shared numerical helpers.

A contact law maps the mean interfacial separation ``u`` [m] to the nominal
asperity contact pressure ``p(u)`` [Pa], with its exact derivative, the
relative contact area as a function of pressure and, where it exists, the
inverse ``u(p)``.  All methods take and return numpy arrays of any shape
(vectorised, so a FEM assembly can evaluate them on quadrature-point arrays).

Domain contract: every method either returns finite values in the physical
range -- pressures ``p >= 0``, ``0 <= A/A0 <= 1``, separations as each law
defines them (non-negative mean-plane separations for the Persson laws, the
signed summit-plane coordinate of Greenwood-Williamson and Greenwood-Tripp) --
or raises :class:`~dolfinx_seal.errors.ParameterError` whose message names the
law, the quantity, its value and the allowed range (:func:`domain_error`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from dolfinx_seal.errors import ParameterError

FloatArray = NDArray[np.float64]


def _prefix(law: str) -> str:
    return f"contact law {law!r}: " if law else ""


def as_array(
    name: str,
    value: ArrayLike,
    lo: float | None = None,
    lo_open: bool = True,
    law: str = "",
    unit: str = "",
) -> FloatArray:
    """``value`` as a float array, finite and (optionally) above ``lo``; else ParameterError.

    The error names the law (when ``law`` is given), the quantity, the first
    offending value (with ``unit``) and the allowed range, e.g.
    ``contact law 'persson': u = 0.0 m is outside the allowed range: u > 0``.
    """
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ParameterError(f"{_prefix(law)}{name} must be finite (got a NaN or inf)")
    if lo is not None:
        bad = a <= lo if lo_open else a < lo
        if np.any(bad):
            rel = ">" if lo_open else ">="
            u = f" {unit}" if unit else ""
            raise ParameterError(
                f"{_prefix(law)}{name} = {float(a[bad].ravel()[0])!r}{u} is outside the allowed "
                f"range: {name} {rel} {lo:g}"
            )
    return a


def finite_slope(d: FloatArray) -> FloatArray:
    """``d`` with ``-inf`` replaced by the most negative double (``dp/du <= 0``).

    The slope of a law overflows only where the pressure is itself near the top
    of the double range or the separation is denormal (e.g. ``p ~ 1e304`` Pa
    times ``alpha/h_rms``); a finite value keeps a Newton Jacobian free of inf/NaN.
    """
    return np.maximum(d, -np.finfo(float).max)


def domain_error(
    law: str, quantity: str, value: float, allowed: str, unit: str = "", why: str = ""
) -> ParameterError:
    """The ParameterError of a contact law evaluated outside its domain.

    The message names the law, the quantity, its value and the allowed range,
    e.g. ``contact law 'persson-exponential': p = 4.27e+06 Pa is outside the
    allowed range 0 < p <= beta E* = 3.48e+05 Pa (...)``.
    """
    u = f" {unit}" if unit else ""
    msg = f"{_prefix(law)}{quantity} = {value:.6g}{u} is outside the allowed range {allowed}"
    return ParameterError(f"{msg} ({why})" if why else msg)


def check_at_most(
    law: str, quantity: str, a: FloatArray, hi: float, allowed: str, unit: str = "", why: str = ""
) -> None:
    """Raise :func:`domain_error` (first offending value) unless every ``a <= hi``."""
    bad = a > hi
    if np.any(bad):
        raise domain_error(law, quantity, float(a[bad].ravel()[0]), allowed, unit, why)


class ContactLaw(ABC):
    """Asperity contact law ``p(u)`` (nominal pressure [Pa] vs mean separation [m])."""

    #: Short name used in results and plots.
    name: str = "contact law"

    @abstractmethod
    def pressure(self, u: ArrayLike) -> FloatArray:
        """Nominal contact pressure ``p(u)`` [Pa] (vectorised)."""

    @abstractmethod
    def dpressure_du(self, u: ArrayLike) -> FloatArray:
        """Exact derivative ``dp/du`` [Pa/m] (vectorised, negative)."""

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """Relative real contact area ``A/A0`` at nominal contact pressure ``p`` [Pa]."""
        raise ParameterError(
            f"contact law {self.name!r} has no contact-area relation; use a Persson or "
            "Greenwood-Williamson law for A/A0"
        )

    def separation(self, p: ArrayLike) -> FloatArray:
        """Inverse ``u(p)`` [m] (vectorised)."""
        raise ParameterError(f"contact law {self.name!r} has no inverse u(p)")

    def area_fraction_at(self, u: ArrayLike) -> FloatArray:
        """``A/A0`` as a function of the separation, ``area_fraction(pressure(u))``."""
        return self.area_fraction(self.pressure(u))


class AreaFromSeparation:
    """``area_fraction(p)`` for laws whose area is known as a function of the separation.

    ``A/A0 (p) = area_fraction_at(separation(p))`` for ``p > 0`` and 0 at ``p = 0``
    (Greenwood-Williamson, Greenwood-Tripp).  The summit areas of these models
    add up to ``A/A0 = 1`` at a finite pressure ``p_full`` [Pa] (separation
    ``u_full`` [m]) and beyond it to more than the nominal area, which no
    contact can have: the subclass provides the raw sum ``_area_at(u)`` and the
    attributes ``name``, ``u_full``, ``p_full``; pressures above ``p_full``
    (separations below ``u_full``) raise ParameterError.
    """

    name: str
    u_full: float
    p_full: float

    def _area_at(self, u: FloatArray) -> FloatArray:  # pragma: no cover - abstract
        raise NotImplementedError

    def area_fraction_at(self, u: ArrayLike) -> FloatArray:
        """``A/A0`` [-] at separation ``u`` [m], ``u >= u_full`` (where ``A/A0 <= 1``)."""
        ua = as_array("u", u, law=self.name, unit="m")
        bad = ua < self.u_full
        if np.any(bad):
            first = ua[bad].ravel()[:1]
            raise domain_error(
                self.name, "u", float(first[0]), f"u >= u_full = {self.u_full:.6g} m", "m",
                f"the summit contact areas add up to A/A0 = {self._area_at(first)[0]:.6g} > 1",
            )  # fmt: skip
        # A/A0 decreases with u and is 1 at u_full: <= 1 up to rounding
        return np.minimum(self._area_at(ua), 1.0)

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """``A/A0`` [-] at nominal pressure ``0 <= p <= p_full`` [Pa]."""
        pa = as_array("p", p, 0.0, lo_open=False, law=self.name, unit="Pa")
        check_at_most(
            self.name, "p", pa, self.p_full, f"0 <= p <= p_full = {self.p_full:.6g} Pa", "Pa",
            "at p_full the summit contact areas add up to A/A0 = 1",
        )  # fmt: skip
        out = np.zeros_like(pa)
        pos = pa > 0
        u = self.separation(pa[pos])  # type: ignore[attr-defined]
        # p <= p_full, so A/A0 <= 1 up to the rounding of the inverse
        out[pos] = np.minimum(self._area_at(u), 1.0)
        return out


def invert_decreasing(
    f: Callable[[FloatArray], FloatArray],
    df: Callable[[FloatArray], FloatArray],
    target: FloatArray,
    lo: float,
    hi: float,
    rtol: float = 1e-13,
    max_iter: int = 200,
) -> FloatArray:
    """Solve ``f(u) = target`` for a decreasing ``f`` on ``[lo, hi]`` (vectorised).

    Newton steps in ``ln f`` safeguarded by bisection; the bracket is expanded
    (doubling its width) until it contains every root.  Raises ParameterError if
    a target lies outside the range of ``f`` reachable from the bracket.
    """
    t = np.asarray(target, dtype=float)
    a = np.full(t.shape, float(lo))
    b = np.full(t.shape, float(hi))
    for _ in range(200):
        fa, fb = f(a), f(b)
        grow_a, grow_b = fa < t, fb > t
        if not (np.any(grow_a) or np.any(grow_b)):
            break
        w = b - a
        a = np.where(grow_a, a - w, a)
        b = np.where(grow_b, b + w, b)
    else:  # pragma: no cover - only for targets beyond any finite separation
        raise ParameterError("pressure outside the range of the contact law")
    u = 0.5 * (a + b)
    for _ in range(max_iter):
        fu = f(u)
        hi_side = fu > t  # root lies at larger u
        a = np.where(hi_side, u, a)
        b = np.where(hi_side, b, u)
        d = df(u)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = (np.log(fu) - np.log(t)) * fu / d  # Newton on ln f
        un = u - step
        bad = ~np.isfinite(un) | (un <= a) | (un >= b)
        un = np.where(bad, 0.5 * (a + b), un)
        if np.all(np.abs(un - u) <= rtol * np.maximum(np.abs(un), 1e-300) + 1e-300):
            return un
        u = un
    return u
