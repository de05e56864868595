"""Rigid counter-surfaces and the gap to the deformed rubber surface.

The gap is measured at each material point of the rubber surface from its
current position ``x = X + u`` to the rigid surface, along the surface normal
of the rigid body (pointing into the rubber):

* :class:`Flat` -- the plane ``x[axis] = position`` with the rubber above it
  (``gap = x[axis] - position``); ``position`` may be a global unknown (the rigid
  approach under force control).
* :class:`Shaft` -- a cylinder of radius ``radius`` around the z axis in
  axisymmetric (r, z) coordinates with the rubber outside it
  (``gap = r - radius``); the interference fit is applied by growing the radius.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import ufl


@dataclass(frozen=True)
class Flat:
    """The rigid plane ``x[axis] = position`` below the rubber.

    Attributes:
        axis: Index of the coordinate normal to the plane (1 in 2D, 2 in 3D).
    """

    axis: int

    def gap(self, x: Any, position: Any) -> Any:
        """Gap [m] of current positions ``x`` (UFL vector) to the plane."""
        return x[self.axis] - position

    def normal(self, gdim: int) -> Any:
        """Unit normal of the plane pointing into the rubber (a 3-vector)."""
        return ufl.as_vector([1.0 if i == self.axis else 0.0 for i in range(3)])


SHAFT_MOTIONS = ("rotary", "axial")


@dataclass(frozen=True)
class Shaft:
    """A rigid shaft (axisymmetric, radial coordinate ``x[0]``), rubber outside.

    Attributes:
        motion: How the shaft surface slides under the rubber: ``rotary`` (it
            turns: sliding along the circumference, the hoop direction, which no
            surface gradient of an axisymmetric field has, so the sliding shears
            the film but transports no fluid axially) or ``axial`` (a rod
            stroking along z: the film is carried along the axis).
    """

    motion: str = "rotary"

    def __post_init__(self) -> None:
        if self.motion not in SHAFT_MOTIONS:
            from dolfinx_seal.errors import ParameterError

            raise ParameterError(f"motion = {self.motion!r} must be one of {SHAFT_MOTIONS}")

    def gap(self, x: Any, radius: Any) -> Any:
        """Gap [m] between current radius and the shaft surface."""
        return x[0] - radius

    def normal(self, gdim: int) -> Any:
        """Outward radial unit vector (into the rubber)."""
        return ufl.as_vector([1.0, 0.0, 0.0])

    def sliding_direction(self) -> Any:
        """Unit sliding direction of the shaft surface in (r, z, theta) (a 3-vector)."""
        return ufl.as_vector([0.0, 0.0, 1.0] if self.motion == "rotary" else [0.0, 1.0, 0.0])

    def edge_axis(self) -> tuple[float, float, float]:
        """The axis that orders the edges of a film under the lip: oil side (z < 0)
        low, air side high."""
        return (0.0, 1.0, 0.0)

    @property
    def transports(self) -> bool:
        """Whether the sliding carries fluid across the (axisymmetric) film."""
        return self.motion == "axial"
