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

A number that changes from call to call (a centroid, a mean) must enter as a
kept :meth:`CompiledCache.constant`, not as a Python float: a float is a literal
of the generated code, so each new value was a new kernel, compiled by FFCx and
the C compiler (seconds) and added to the JIT cache.  Each table holds at most
:data:`MAX_ENTRIES` entries, the least recently used going first.
"""

from __future__ import annotations

from collections import OrderedDict
from typing import Any

import dolfinx
import ufl

from dolfinx_seal.compat import interpolation_points

#: entries kept per table (forms, interpolations)
MAX_ENTRIES = 256


def _kept(table: OrderedDict, key: Any, make: Any) -> Any:
    """``table[key]``, made by ``make()`` if absent; the oldest entry goes beyond
    :data:`MAX_ENTRIES`."""
    if key in table:
        table.move_to_end(key)
        return table[key]
    table[key] = value = make()
    if len(table) > MAX_ENTRIES:
        table.popitem(last=False)
    return value


class CompiledCache:
    """Compiled forms and interpolation expressions by their UFL expression."""

    def __init__(self) -> None:
        self._forms: OrderedDict[tuple[Any, Any], dolfinx.fem.Form] = OrderedDict()
        # by (expression, id of the space): the entry holds the space (its id stays its own)
        self._interpolants: OrderedDict[tuple[Any, int], tuple[Any, Any]] = OrderedDict()
        self._constants: dict[tuple[int, str], tuple[Any, dolfinx.fem.Constant]] = {}

    def form(self, integrand: Any, measure: ufl.Measure) -> dolfinx.fem.Form:
        """The compiled form ``integrand * measure``."""
        return _kept(self._forms, (integrand, measure),
                     lambda: dolfinx.fem.form(integrand * measure))  # fmt: skip

    def constant(self, mesh: Any, name: str, value: float) -> dolfinx.fem.Constant:
        """The kept scalar constant ``name`` on ``mesh``, set to ``value`` (for a
        number that changes from call to call; see the module docstring)."""
        key = (id(mesh), name)
        if key not in self._constants:  # the entry holds the mesh (its id stays its own)
            self._constants[key] = (mesh, dolfinx.fem.Constant(mesh, 0.0))
        c = self._constants[key][1]
        c.value = value
        return c

    def interpolate(self, expr: Any, V: dolfinx.fem.FunctionSpace) -> dolfinx.fem.Function:
        """A function of ``V`` holding ``expr`` interpolated now.  The function is
        kept and overwritten at the next call with an equal ``expr``: copy what
        is to be kept."""
        # the function holds V, so id(V) is not reused while the entry lives
        compiled, f = _kept(
            self._interpolants,
            (expr, id(V)),
            lambda: (
                dolfinx.fem.Expression(expr, interpolation_points(V.element)),
                dolfinx.fem.Function(V),
            ),
        )
        f.interpolate(compiled)
        return f


__all__ = ["MAX_ENTRIES", "CompiledCache"]
