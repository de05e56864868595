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

Both follow :class:`CounterSurface`, the protocol the contact problem relies on:
a new counter-surface (a shaft seen from a rotated periodic 3D sector, whose
normal and sliding direction vary over the surface) implements the same five
members and needs no change in the problem.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import ufl


class CounterSurface(Protocol):
    """What the contact problem needs from a rigid counter-surface.

    ``x`` is the current position of rubber surface points (a UFL gdim vector);
    vectors returned are 3-vectors (axisymmetric: (r, z, theta)).
    """

    def gap(self, x: Any, position: Any) -> Any:
        """Gap [m] from ``x`` to the surface at the rigid ``position`` [m]."""

    def normal(self, x: Any) -> Any:
        """Unit normal at ``x`` pointing into the rubber."""

    def sliding_direction(self, x: Any) -> Any:
        """Unit direction of the sliding of the surface at ``x``."""

    def edge_axis(self) -> tuple[float, float, float] | None:
        """Direction ordering the edges of a film (inlet low, outlet high); None: the sliding."""

    @property
    def normal_axis(self) -> int:
        """Coordinate along which the normal step limit acts (the normal of a flat or
        axisymmetric surface)."""

    @property
    def transports(self) -> bool:
        """Whether the sliding carries fluid across the film (a Couette flux)."""


@dataclass(frozen=True)
class Flat:
    """The rigid plane ``x[axis] = position`` below the rubber.

    Attributes:
        axis: Index of the coordinate normal to the plane (1 in 2D, 2 in 3D).
        sliding_axis: Index of the coordinate along which the plane slides.
    """

    axis: int
    sliding_axis: int = 0

    def __post_init__(self) -> None:
        if (
            not (0 <= self.axis <= 2 and 0 <= self.sliding_axis <= 2)
            or self.axis == self.sliding_axis
        ):
            from dolfinx_seal.errors import ParameterError

            raise ParameterError(
                f"Flat(axis={self.axis}, sliding_axis={self.sliding_axis}): two different "
                "coordinate indices in 0-2"
            )

    def gap(self, x: Any, position: Any) -> Any:
        """Gap [m] of current positions ``x`` (UFL vector) to the plane."""
        return x[self.axis] - position

    def normal(self, x: Any) -> Any:
        """Unit normal of the plane pointing into the rubber (a 3-vector)."""
        return _unit(self.axis)

    def sliding_direction(self, x: Any) -> Any:
        """The sliding coordinate direction (a 3-vector)."""
        return _unit(self.sliding_axis)

    def edge_axis(self) -> None:
        """The film's edges are ordered along the sliding direction."""
        return None

    @property
    def normal_axis(self) -> int:
        return self.axis

    @property
    def transports(self) -> bool:
        return True


def _unit(axis: int) -> Any:
    return ufl.as_vector([1.0 if i == axis else 0.0 for i in range(3)])


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

    def normal(self, x: Any) -> Any:
        """Outward radial unit vector (into the rubber)."""
        return ufl.as_vector([1.0, 0.0, 0.0])

    @property
    def normal_axis(self) -> int:
        return 0

    def sliding_direction(self, x: Any) -> Any:
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
