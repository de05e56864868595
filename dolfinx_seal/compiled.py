"""Compiled forms and interpolations of the outputs, kept for the next point.

A sweep asks for the same results at every point (loads, friction parts, the
gap and pressures at the surface nodes), each a UFL expression built afresh.
``dolfinx.fem.form`` and ``dolfinx.fem.Expression`` then find the compiled code
in the JIT cache, but still process the UFL and look the module up (tens of ms
each; on the ball's 30-speed sweep about 0.7 s a point, 8 % of a point's time).
:class:`CompiledCache` keeps them, keyed by the expression itself: UFL compares
expressions structurally, terminals by identity (a coefficient is equal only to
itself), so an expression equal to a kept one reads the same functions and
constants, and the kept compiled object gives the same numbers.
"""

from __future__ import annotations

from typing import Any

import dolfinx
import ufl

from dolfinx_seal.compat import interpolation_points


class CompiledCache:
    """Compiled forms and interpolation expressions by their UFL expression."""

    def __init__(self) -> None:
        self._forms: dict[tuple[Any, Any], dolfinx.fem.Form] = {}
        # by (expression, id of the space): the entry holds the space (its id stays its own)
        self._interpolants: dict[tuple[Any, int], tuple[dolfinx.fem.Expression, Any]] = {}

    def form(self, integrand: Any, measure: ufl.Measure) -> dolfinx.fem.Form:
        """The compiled form ``integrand * measure``."""
        key = (integrand, measure)
        compiled = self._forms.get(key)
        if compiled is None:
            compiled = self._forms[key] = dolfinx.fem.form(integrand * measure)
        return compiled

    def interpolate(self, expr: Any, V: dolfinx.fem.FunctionSpace) -> dolfinx.fem.Function:
        """A function of ``V`` holding ``expr`` interpolated now.  The function is
        kept and overwritten at the next call with an equal ``expr``: copy what
        is to be kept."""
        key = (expr, id(V))
        entry = self._interpolants.get(key)
        if entry is None:
            # the function holds V, so id(V) is not reused while the entry lives
            entry = (
                dolfinx.fem.Expression(expr, interpolation_points(V.element)),
                dolfinx.fem.Function(V),
            )
            self._interpolants[key] = entry
        compiled, f = entry
        f.interpolate(compiled)
        return f


__all__ = ["CompiledCache"]
