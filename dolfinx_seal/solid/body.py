"""The rubber body of a contact problem and how it is controlled.

* :class:`Body` -- kinematics, material, displacement conditions and
  discretisation (``material = None``: a rigid body, no displacement unknowns);
* :class:`ForceControl` / :class:`PositionControl` -- what drives the contact:
  a normal load (the counter-surface position is then a global unknown) or a
  prescribed counter-surface position.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_finite, check_int_range, check_positive


@dataclass
class Dirichlet:
    """A displacement condition on a tagged boundary.

    Attributes:
        tag: Facet tag.
        component: Displacement component (``None``: all components).
        value: Prescribed displacement [m]: a number, or a field given as a callable
            ``f(x) -> values`` of the points ``x`` (3 x n) as
            :meth:`dolfinx.fem.Function.interpolate` takes it (``gdim x n`` values for
            all components, ``n`` for one), e.g. an installed state imposed on a cut.
    """

    tag: int
    component: int | None = None
    value: float | Callable[[Any], Any] = 0.0


@dataclass(frozen=True)
class Body:
    """The deformable (or rigid) body.

    Attributes:
        kinematics: :mod:`~dolfinx_seal.solid.kinematics` object (plane strain,
            axisymmetric, 3D).
        material: :mod:`~dolfinx_seal.solid.materials` object; None: a rigid body
            (no displacement unknowns; ``dirichlet`` is then unused).
        dirichlet: Displacement conditions.
        degree: Displacement degree (the mixed pressure is one lower).
        quadrature_degree: Quadrature degree of the strain energy (default: see
            :func:`energy_quadrature`, ``2 * degree - 1`` on tetrahedra and ``2 *
            degree`` on triangles).  UFL's estimate for the neo-Hookean Jacobian
            is 13 (the ``J^(-2/3)`` factors count as polynomials of high degree),
            which made 3D assembly ~10x slower for no accuracy gain measurable
            against Hertz.  A degree given here uses the cell's default rule.
        surface_quadrature_degree: Quadrature degree of the contact-surface
            integrals (asperity pressure, film), the same for the residual and its
            Jacobian (UFL estimates the two separately).  Default ``4 * degree + 2``
            on lines (2D: 10 for P2; mu and h_min of the 10 um cylinder at 1e-3 m/s
            are unchanged to 1e-15, and 6 made its start diverge) and ``2 *
            degree + 2`` on triangles (3D, where the estimate for ``g^3`` and the
            exponential laws asked for rules of 1e5 points).
    """

    kinematics: Any
    material: Any | None
    dirichlet: Sequence[Dirichlet] = field(default_factory=tuple)
    degree: int = 2
    quadrature_degree: int | None = None
    surface_quadrature_degree: int | None = None

    def __post_init__(self) -> None:
        check_int_range("degree", self.degree, 1, 3)
        if self.quadrature_degree is not None:
            check_int_range("quadrature_degree", self.quadrature_degree, 1, 20)
        if self.surface_quadrature_degree is not None:
            check_int_range("surface_quadrature_degree", self.surface_quadrature_degree, 1, 30)
        if self.material is not None and self.material.mixed and self.degree < 2:
            raise ParameterError("the mixed formulation needs degree >= 2 (Taylor-Hood)")

    @property
    def deformable(self) -> bool:
        return self.material is not None


@dataclass(frozen=True)
class ForceControl:
    """A prescribed normal load; the counter-surface position is an unknown.

    Attributes:
        load: Normal force on the body [N, or N/m in plane strain].
        position0: Counter position at zero load [m] (the touching position).
        held: The counter-surface starts held at ``position0`` (the load equation
            replaced by ``position = position0``, as under position control) until
            :meth:`~dolfinx_seal.solid.problem.SolidContactProblem.release_position`
            frees it at the load it then carries: a body installed at a position
            that then floats at that load (the sliding lip sector, which the film
            lifts).
    """

    load: float
    position0: float = 0.0
    held: bool = False

    kind = "force"

    def __post_init__(self) -> None:
        check_positive("load", self.load, "N")
        check_finite("position0", self.position0)

    @property
    def target(self) -> float:
        return float(self.load)


@dataclass(frozen=True)
class PositionControl:
    """A prescribed counter-surface position, reached from ``position0``.

    Attributes:
        target: Final counter position [m].
        position0: Counter position at the start (fraction 0) [m].
    """

    target: float
    position0: float = 0.0

    kind = "position"

    def __post_init__(self) -> None:
        check_finite("target", self.target)
        check_finite("position0", self.position0)


def energy_quadrature(degree: int, cell: str, quadrature_degree: int | None = None) -> dict:
    """Quadrature metadata (UFL ``dx`` metadata) of the strain energy of a body of
    displacement degree ``degree`` on cells ``cell`` (``"triangle"``, ``"tetrahedron"``).

    A given ``quadrature_degree`` is used with the cell's default rule.  The
    default integrates the linearised stiffness of affine cells exactly (its
    integrand has degree ``2 * degree - 2``, one more with the axisymmetric
    weight ``r``), the condition for the optimal order of a degree-``degree``
    element with quadrature (Ciarlet and Raviart):

    * tetrahedra: degree ``2 * degree - 1`` on the Xiao-Gimbutas rule (6 points
      for P2, all weights positive; basix's default degree-3 rule has 5 points
      and a negative weight, a risk for an energy), against 14 points of the
      degree-4 rule used before 7 December 2026.  The ball's 3D Jacobian takes
      a third less time at one rank.  Over its 30-speed sweep, mu and h_central
      moved by at most 5e-6 and h_min by at most 1e-3 (at 0.01 m/s, where it is
      24 nm).  See docs/performance.md, "The strain energy's quadrature";
    * other cells (triangles): degree ``2 * degree`` (6 points for P2 on
      triangles, as many as a degree-3 rule, so nothing to gain).
    """
    if quadrature_degree is not None:
        return {"quadrature_degree": quadrature_degree}
    if cell == "tetrahedron":
        return {"quadrature_degree": max(2 * degree - 1, 1), "quadrature_rule": "xiao_gimbutas"}
    return {"quadrature_degree": 2 * degree}


__all__ = ["Body", "Dirichlet", "ForceControl", "PositionControl", "energy_quadrature"]
