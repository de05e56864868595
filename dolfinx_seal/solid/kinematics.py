"""Kinematics: the 3x3 deformation gradient and the reference measure weight.

Three settings share one interface so that materials and tractions are written
once, in 3D form:

* :class:`PlaneStrain` -- 2D (x, y) displacement, ``F_zz = 1``; quantities per
  unit length out of plane [1/m].
* :class:`Solid3D` -- 3D.
* :class:`Axisymmetric` -- (r, z) with r = x[0]; hoop stretch
  ``F_tt = 1 + u_r / r``; integrals carry the weight ``2 pi r`` so that they are
  totals over the revolution (e.g. a radial load in N, not N/m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import ufl
from ufl.domain import extract_unique_domain


@dataclass(frozen=True)
class PlaneStrain:
    """2D plane strain."""

    name: str = "plane-strain"
    gdim: int = 2

    def F(self, u: Any) -> Any:
        """3x3 deformation gradient of the 2D displacement ``u``."""
        g = ufl.grad(u)
        return ufl.as_matrix([[1 + g[0, 0], g[0, 1], 0], [g[1, 0], 1 + g[1, 1], 0], [0, 0, 1]])

    def eps(self, u: Any) -> Any:
        """3x3 small-strain tensor."""
        g = ufl.grad(u)
        e = ufl.sym(g)
        return ufl.as_matrix([[e[0, 0], e[0, 1], 0], [e[1, 0], e[1, 1], 0], [0, 0, 0]])

    def weight(self, x: Any) -> Any:
        """Reference measure weight (1: per unit length out of plane)."""
        return 1.0

    def vector3(self, v: Any) -> Any:
        """Embed a 2D vector in 3D."""
        return ufl.as_vector([v[0], v[1], 0])


@dataclass(frozen=True)
class Solid3D:
    """Full 3D."""

    name: str = "3d"
    gdim: int = 3

    def F(self, u: Any) -> Any:
        """Deformation gradient."""
        return ufl.Identity(3) + ufl.grad(u)

    def eps(self, u: Any) -> Any:
        """Small-strain tensor."""
        return ufl.sym(ufl.grad(u))

    def weight(self, x: Any) -> Any:
        """Reference measure weight (1)."""
        return 1.0

    def vector3(self, v: Any) -> Any:
        """Identity (already 3D)."""
        return v


@dataclass(frozen=True)
class Axisymmetric:
    """Axisymmetric (r, z), r = x[0] > 0, no torsion."""

    name: str = "axisymmetric"
    gdim: int = 2

    def F(self, u: Any) -> Any:
        """3x3 deformation gradient in (r, z, theta) with the hoop stretch."""
        x = ufl.SpatialCoordinate(extract_unique_domain(u))
        g = ufl.grad(u)
        return ufl.as_matrix(
            [[1 + g[0, 0], g[0, 1], 0], [g[1, 0], 1 + g[1, 1], 0], [0, 0, 1 + u[0] / x[0]]]
        )

    def eps(self, u: Any) -> Any:
        """3x3 small strain with the hoop strain ``u_r / r``."""
        x = ufl.SpatialCoordinate(extract_unique_domain(u))
        e = ufl.sym(ufl.grad(u))
        return ufl.as_matrix([[e[0, 0], e[0, 1], 0], [e[1, 0], e[1, 1], 0], [0, 0, u[0] / x[0]]])

    def weight(self, x: Any) -> Any:
        """``2 pi r``: integrals are totals over the revolution."""
        return 2.0 * math.pi * x[0]

    def vector3(self, v: Any) -> Any:
        """Embed an (r, z) vector in 3D."""
        return ufl.as_vector([v[0], v[1], 0])


KINEMATICS = {"plane-strain": PlaneStrain(), "3d": Solid3D(), "axisymmetric": Axisymmetric()}
