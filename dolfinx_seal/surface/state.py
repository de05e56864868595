"""The state of a contact surface: what a film and the surface tractions need from the body.

The solid builds it from its kinematics (:mod:`dolfinx_seal.solid.problem`), the
film consumes it (:meth:`dolfinx_seal.film.surface.SurfaceFilm.attach`); neither
imports the other.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # annotations only: the module builds no forms
    import dolfinx


@dataclass
class SurfaceState:
    """The lubricated surface of a body as the film and the surface tractions see it (UFL objects).

    Attributes:
        mesh, facet_tags, contact_tag: The body and its lubricated surface.
        x: Current position of the surface points (gdim vector).
        F: 3x3 deformation gradient (identity for a rigid body).
        N3: Reference outward normal as a 3-vector.
        weight: Reference measure weight (1 in plane strain and 3D).
        gap: Gap to the counter-surface [m].
        vector3: Map of a gdim vector to a 3-vector.
        e_n: Unit normal of the counter-surface pointing into the body (3-vector).
        sliding: Unit sliding direction of the counter-surface (3-vector).
        quadrature_degree: Quadrature degree of the film integrals (None: UFL's estimate).
        edge_axis: Direction (3-vector of floats) that orders the edges of the
            lubricated zone: ``inlet_pressure`` acts on the edge at its low end,
            ``outlet_pressure`` on the high end (None: the sliding direction).  A
            seal's film has its oil side low and its air side high along the
            axis, whichever way the shaft moves.
        roughness_scale: Amplitude scale of the homogenised roughness (a float or a
            UFL ``Constant``; 1: as given): the asperity law, the flow factor, the
            gap floor and the real contact area all follow it (a homotopy from a
            rough to a smooth surface, exact for Persson's laws: ``p_s(u) = s p(u/s)``,
            ``A_s(u) = A(u/s)``, ``phi_s(u) = phi(u/s)``).
        transport: Whether the sliding moves fluid across the lubricated zone (the
            Couette flux in the Reynolds equation).  False where the sliding is
            normal to every surface gradient (a turning shaft under an
            axisymmetric lip): the Couette shear still acts, the flux term is not
            assembled.
        periodic: The periodicity of a sector (e.g.
            :class:`~dolfinx_seal.solvers.periodic.RotationalPeriodicity`: its
            ``scalar(V, bcs)`` gives a field's constraint), or None: the film's
            unknowns are then constrained to be periodic too.
    """

    mesh: dolfinx.mesh.Mesh
    facet_tags: dolfinx.mesh.MeshTags
    contact_tag: int
    x: Any
    F: Any
    N3: Any
    weight: Any
    gap: Any
    vector3: Any
    e_n: Any
    sliding: Any
    quadrature_degree: int | None = None
    edge_axis: Any = None
    transport: bool = True
    roughness_scale: Any = 1.0
    periodic: Any = None


__all__ = ["SurfaceState"]
