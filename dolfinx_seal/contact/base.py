"""The contact-law interface and shared numerical helpers.

A contact law maps the mean interfacial separation ``u`` [m] to the nominal
asperity contact pressure ``p(u)`` [Pa], with its exact derivative, the
relative contact area as a function of pressure and, where it exists, the
inverse ``u(p)``.  All methods take and return numpy arrays of any shape
(vectorised, so a FEM assembly can evaluate them on quadrature-point arrays).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from dolfinx_seal.errors import ParameterError

FloatArray = NDArray[np.float64]


def as_array(
    name: str, value: ArrayLike, lo: float | None = None, lo_open: bool = True
) -> FloatArray:
    """``value`` as a float array, finite and (optionally) above ``lo``; else ParameterError."""
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must be finite (got a NaN or inf)")
    if lo is not None:
        bad = a <= lo if lo_open else a < lo
        if np.any(bad):
            rel = ">" if lo_open else ">="
            raise ParameterError(
                f"{name} = {a[bad].ravel()[0]!r} is outside the allowed range: {name} {rel} {lo:g}"
            )
    return a


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
    (Greenwood-Williamson, Greenwood-Tripp).
    """

    def area_fraction(self, p: ArrayLike) -> FloatArray:
        """``A/A0`` at nominal pressure ``p`` [Pa]."""
        pa = as_array("p", p, 0.0, lo_open=False)
        out = np.zeros_like(pa)
        pos = pa > 0
        out[pos] = self.area_fraction_at(self.separation(pa[pos]))  # type: ignore[attr-defined]
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
