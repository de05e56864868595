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
* :class:`Shaft3D` -- the same shaft in 3D Cartesian coordinates (a periodic
  sector of a lip around it): ``gap = (x^2 + y^2)^(1/2) - radius``, whose normal
  (radial) and sliding direction (circumferential) vary over the surface.
* :class:`WithSurfaceHeight` -- any of them seen from a body whose surface
  carries a resolved roughness height ``h(X)`` (S0 eq 1): the gap grows by ``h``.

All follow :class:`CounterSurface`, the protocol the contact problem relies on.
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


@dataclass(frozen=True)
class Shaft3D:
    """A rigid shaft about the z axis in 3D Cartesian coordinates, rubber outside.

    The position is the shaft radius [m].  The shaft turns: its surface slides
    along the circumference, ``e_theta = (-y, x, 0) / r`` (counter-clockwise about
    +z for a positive speed), which carries fluid across a film whose gap varies
    along the circumference (a rough band), so :attr:`transports` is true.

    ``normal_axis`` is 0 (x): the Newton step limit on the normal component
    (:class:`~dolfinx_seal.solid.step_limits.StepLimits`) acts on ``u_x``, which
    is the radial component to within ``1 - cos(theta/2)`` on a narrow sector
    centred on the x axis (3e-6 for the lip sector of one 200 um period on an
    80 mm shaft).
    """

    def gap(self, x: Any, radius: Any) -> Any:
        """Gap [m] between the current radius of ``x`` and the shaft surface."""
        return ufl.sqrt(x[0] ** 2 + x[1] ** 2) - radius

    def normal(self, x: Any) -> Any:
        """Radial unit vector at ``x`` (into the rubber)."""
        r = ufl.sqrt(x[0] ** 2 + x[1] ** 2)
        return ufl.as_vector([x[0] / r, x[1] / r, 0.0])

    def sliding_direction(self, x: Any) -> Any:
        """Circumferential unit vector ``e_theta`` at ``x``."""
        r = ufl.sqrt(x[0] ** 2 + x[1] ** 2)
        return ufl.as_vector([-x[1] / r, x[0] / r, 0.0])

    def edge_axis(self) -> tuple[float, float, float]:
        """The shaft axis orders the film's edges: oil side (z < 0) low, air side high."""
        return (0.0, 0.0, 1.0)

    @property
    def normal_axis(self) -> int:
        return 0

    @property
    def transports(self) -> bool:
        return True


@dataclass(frozen=True)
class WithSurfaceHeight:
    """A counter-surface seen from a body whose surface carries a resolved height.

    S0 eq 1: the mean separation is ``u_r + h_r + w_3``, the macroscopic shape
    and the displacement (here the current position ``x``) plus the
    deterministic roughness ``h_r`` of the rubber surface, a field of its
    reference (material) coordinates that rides with the surface.  ``height`` is
    that field as UFL [m]; positive opens the gap (a valley of the rubber
    surface).  Everything else is the wrapped counter-surface's.

    Attributes:
        base: The counter-surface (:class:`CounterSurface`).
        height: ``h_r(X)`` [m] (UFL, of the reference coordinates).
    """

    base: Any
    height: Any

    def gap(self, x: Any, position: Any) -> Any:
        """The base gap [m] plus the surface height."""
        return self.base.gap(x, position) + self.height

    def normal(self, x: Any) -> Any:
        return self.base.normal(x)

    def sliding_direction(self, x: Any) -> Any:
        return self.base.sliding_direction(x)

    def edge_axis(self) -> tuple[float, float, float] | None:
        return self.base.edge_axis()

    @property
    def normal_axis(self) -> int:
        return self.base.normal_axis

    @property
    def transports(self) -> bool:
        return self.base.transports
