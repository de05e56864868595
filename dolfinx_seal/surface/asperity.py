"""Asperity contact laws in UFL: ``p_cont(gap)`` as a nonlinear boundary traction.

The numpy contact laws of :mod:`dolfinx_seal.contact` are brought into the
forms as smooth closed forms, so that ``ufl.derivative`` gives the exact
Jacobian (quadratic Newton convergence):

* :class:`~dolfinx_seal.contact.persson.PerssonExponentialLaw` -- exactly
  ``beta E* exp(-alpha g / h_rms)``;
* :class:`~dolfinx_seal.contact.persson.ClosedFormPersson` -- the closed form of
  the full Persson relation (its fit error against the tabulated relation is
  ``law.max_rel_error``, about 2-3 %, reported by the scenes).

Newton iterates can visit gaps far outside the physical range (docs/design.md,
known traps: an 80 um penetration on a first step overflowed ``exp``).  Both
forms are therefore continued C^1 outside a safe window, keeping ``p`` finite,
positive and monotone:

* below ``x_min = u_min / h_rms`` (and for any negative gap) ``ln p`` continues
  linearly in ``x`` with the slope it has at ``x_min``;
* above ``p_cap = CAP_FACTOR E*`` (10 E*: a nominal pressure no rubber contact
  reaches; far beyond it the exact law would also give absurd stiffness) the
  pressure continues linearly in ``ln p`` (``p = p_cap (1 + ln p - ln p_cap)``).
  A higher cap made the Newton matrices so ill-conditioned (contact stiffness
  1e13 times the physical one) that their solutions were meaningless.

Inside the window the expressions are the laws themselves.

:class:`LawHomotopy` blends two laws, ``(1 - w) p_start + w p_end`` with a
weight ``w`` (a Constant) walked from 0 to 1: a path from a state solved with
one law to the same body with another (the two-scale lip sector goes from the
whole spectrum homogenised to its part above ``q_th``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import ufl

from dolfinx_seal.contact.persson import ClosedFormPersson, PerssonExponentialLaw
from dolfinx_seal.errors import ParameterError

#: The pressure is continued linearly in ``ln p`` above ``CAP_FACTOR * E*``.
CAP_FACTOR = 10.0


def _capped_exp(lnp: Any, ln_cap: float) -> Any:
    """``exp(lnp)``, continued linearly (C^1) above ``ln_cap``."""
    # the exponent is bounded in both branches: generated code may evaluate the
    # branch not taken, and exp overflowing to inf there turns 0 * inf into NaN
    return ufl.conditional(
        ufl.lt(lnp, ln_cap),
        ufl.exp(ufl.min_value(lnp, ln_cap)),
        math.exp(ln_cap) * (1.0 + lnp - ln_cap),
    )


@dataclass(frozen=True)
class LawHomotopy:
    """The blend ``(1 - w) p_start(g) + w p_end(g)`` of two laws (each positive and
    decreasing in ``g``, so is the blend).  Every other attribute (``name``,
    ``h_rms``, ``alpha``, ``rms_slope``, ...) is the end law's: at ``w = 1`` this is
    the end law.

    Attributes:
        start, end: Laws with a UFL form (as :func:`contact_pressure` takes them).
        weight: The weight ``w`` (a ``dolfinx.fem.Constant``, 0 to 1).
    """

    start: Any
    end: Any
    weight: Any

    def __getattr__(self, name: str) -> Any:
        if name in ("start", "end", "weight") or name.startswith("__"):
            raise AttributeError(name)
        return getattr(self.end, name)


def contact_pressure(law: Any, gap: Any, u_min: float = 1e-3, scale: Any = 1.0) -> Any:
    """UFL expression of the asperity contact pressure [Pa] at gap ``gap`` [m].

    Args:
        law: A :class:`PerssonExponentialLaw`, :class:`ClosedFormPersson` or a
            :class:`LawHomotopy` of two of them.
        gap: UFL expression of the mean separation [m].
        u_min: Lower end of the window, in units of ``h_rms`` (closed form only).
        scale: Amplitude scale ``s`` of the roughness (a float or a UFL
            ``Constant``): the law of the surface whose heights are ``s`` times
            the law's, ``p_s(u) = s p(u / s)``.  Linear-elastic contact of a
            surface scaled in height by ``s`` has displacements scaled by ``s``
            and stresses by ``s``, so this is exact for Persson's relation (its
            fitted ``beta`` is proportional to ``h_rms`` at a fixed spectrum shape,
            to 0.2 %); it is the homotopy that installs a smooth surface from a
            rough one (:meth:`~dolfinx_seal.solid.problem.SolidContactProblem.walk_roughness`).
    """
    if isinstance(law, LawHomotopy):
        w = law.weight
        return (1.0 - w) * contact_pressure(law.start, gap, u_min, scale) + w * contact_pressure(
            law.end, gap, u_min, scale
        )
    ln_s = math.log(scale) if isinstance(scale, int | float) else ufl.ln(scale)
    if isinstance(law, PerssonExponentialLaw):
        ln0 = math.log(law.beta * law.e_star) + ln_s
        lnp = ln0 - law.alpha * gap / (law.h_rms * scale)
        return _capped_exp(lnp, math.log(CAP_FACTOR * law.e_star))
    if isinstance(law, ClosedFormPersson):
        ln0 = math.log(law.beta * law.e_star) + ln_s
        x = gap / (law.h_rms * scale)
        xm = float(u_min)

        def lnp_of(xx: Any) -> Any:
            return (
                ln0
                - law.alpha * xx
                + law.m * ufl.ln(1.0 + law.c / xx)
                - law.a * ufl.exp(-law.b * xx * xx)
            )

        lnp_m = (
            ln0
            - law.alpha * xm
            + law.m * math.log(1.0 + law.c / xm)
            - law.a * math.exp(-law.b * xm * xm)
        )
        slope_m = (
            -law.alpha
            - law.m * law.c / (xm * (xm + law.c))
            + 2.0 * law.a * law.b * xm * math.exp(-law.b * xm * xm)
        )
        x_safe = ufl.max_value(x, xm)  # keeps ln(1 + c/x) defined on both branches
        lnp = ufl.conditional(ufl.ge(x, xm), lnp_of(x_safe), lnp_m + slope_m * (x - xm))
        return _capped_exp(lnp, math.log(CAP_FACTOR * law.e_star))
    raise ParameterError(
        f"contact law {getattr(law, 'name', type(law).__name__)!r} has no UFL form; "
        "use PerssonExponentialLaw or PerssonLaw.closed_form()"
    )


def area_fraction(p: Any, e_star: float, rms_slope: float, scale: Any = 1.0) -> Any:
    """Persson's real contact area ``A/A0 = erf(sqrt(2) p / (E* <|grad h|^2>^(1/2)))`` in UFL.

    Args:
        p: Nominal asperity pressure [Pa] (UFL).
        e_star: ``E*`` [Pa].
        rms_slope: ``<|grad h|^2>^(1/2)`` of the (homogenized) roughness [-].
        scale: Amplitude scale of the roughness (float or UFL ``Constant``; see
            :func:`contact_pressure`): the slope is ``scale * rms_slope``.
    """
    if not (math.isfinite(rms_slope) and rms_slope > 0):
        raise ParameterError(f"rms_slope = {rms_slope!r} must be positive for the contact area")
    return ufl.erf(math.sqrt(2.0) * p / (e_star * rms_slope * scale))
