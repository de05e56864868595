"""An axisymmetric solution as a field of 3D points: the solid of revolution.

A 2D axisymmetric solution on the (r, z) section (``x[0] = r``, ``x[1] = z``;
:class:`~dolfinx_seal.solid.kinematics.Axisymmetric`) is, in 3D Cartesian
coordinates about the z axis, the field

    u(x, y, z) = u_r(r, z) e_r(phi) + u_z(r, z) e_z,   p(x, y, z) = p(r, z)

with ``r = (x^2 + y^2)^(1/2)`` and ``e_r = (x, y, 0) / r`` (no torsion).
:class:`RevolvedState` evaluates that field at arbitrary 3D points, as the
callables ``f(x) -> values`` that :meth:`dolfinx.fem.Function.interpolate` takes
(the installed lip imposed on the cut of a periodic sector and used as its
first iterate, :mod:`dolfinx_seal.scenes.lip_sector`).

Parallel: the distributed section is copied, dof by dof, onto a serial copy of
its mesh on every rank (the Gmsh builder is deterministic, so the meshes are the
same; :func:`~dolfinx_seal.verification.parallel.copy_by_coordinates`), and the
points of each rank are located in that copy: no point search across ranks.  A
point that falls outside the section by the chord sag of its curved boundary
(the 3D nodes lie on the true surface of revolution, the section's boundary
facets are straight) is evaluated on the nearest cell, whose polynomial is
continued there.
"""

from __future__ import annotations

from typing import Any

import dolfinx
import dolfinx.geometry
import numpy as np
from mpi4py import MPI

import dolfinx_seal.compat  # noqa: F401  (the quiet JIT, before any DOLFINx use)
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.verification.parallel import copy_by_coordinates


class RevolvedState:
    """A 2D axisymmetric displacement (and pressure) as fields of 3D points.

    Args:
        section: The (r, z) mesh of the serial copy (on ``MPI.COMM_SELF``), the same
            mesh as that of ``W`` (same builder and parameters).
        W: The distributed space of the axisymmetric solution: a vector space of
            ``(u_r, u_z)`` or a mixed space whose ``sub(0)`` is that vector space and
            ``sub(1)`` a scalar pressure.
        w: The solution on ``W`` (any communicator).
        max_outside: Largest distance [m] of a point outside the section that is
            still evaluated on its nearest cell (beyond it: an error).
    """

    def __init__(self, section: Any, W: Any, w: Any, max_outside: float) -> None:
        self.mixed = W.num_sub_spaces == 2 and W.sub(0).num_sub_spaces == 2
        cell = section.basix_cell()
        el_u = W.sub(0).ufl_element() if self.mixed else W.ufl_element()
        import basix.ufl

        Vu = dolfinx.fem.functionspace(
            section, basix.ufl.element("Lagrange", cell, el_u.degree, shape=(2,))
        )
        self.u = dolfinx.fem.Function(Vu, name="axisymmetric_displacement")
        copy_by_coordinates(W.sub(0) if self.mixed else W, w, Vu, self.u)
        self.p: Any = None
        if self.mixed:
            deg = W.sub(1).ufl_element().degree
            Q = dolfinx.fem.functionspace(section, ("Lagrange", deg))
            self.p = dolfinx.fem.Function(Q, name="axisymmetric_pressure")
            copy_by_coordinates(W.sub(1), w, Q, self.p)
        self.section = section
        self.max_outside = float(max_outside)
        tdim = section.topology.dim
        self._tree = dolfinx.geometry.bb_tree(section, tdim)
        n = section.topology.index_map(tdim).size_local
        self._midpoints = dolfinx.geometry.create_midpoint_tree(
            section, tdim, np.arange(n, dtype=np.int32)
        )

    @staticmethod
    def rz(x: np.ndarray) -> np.ndarray:
        """The (r, z, 0) section points (n x 3) of 3D points ``x`` (3 x n)."""
        return np.column_stack([np.hypot(x[0], x[1]), x[2], np.zeros(x.shape[1])])

    def _cells(self, pts: np.ndarray) -> np.ndarray:
        """A cell of the section holding each point, or the nearest one."""
        cand = dolfinx.geometry.compute_collisions_points(self._tree, pts)
        hits = dolfinx.geometry.compute_colliding_cells(self.section, cand, pts)
        cells = np.full(pts.shape[0], -1, dtype=np.int32)
        for i in range(pts.shape[0]):
            links = hits.links(i)
            if links.size:
                cells[i] = links[0]
        out = np.flatnonzero(cells < 0)
        if out.size:
            near = dolfinx.geometry.compute_closest_entity(
                self._tree, self._midpoints, self.section, pts[out]
            )
            dist = np.sqrt(
                [
                    dolfinx.geometry.squared_distance(self.section, 2, np.array([c]), pts[i][None])[
                        0
                    ]
                    for i, c in zip(out, near, strict=True)
                ]
            )
            if dist.max(initial=0.0) > self.max_outside:
                i = int(out[np.argmax(dist)])
                raise ParameterError(
                    f"a point (r, z) = ({pts[i, 0]:.6g}, {pts[i, 1]:.6g}) m lies "
                    f"{dist.max():.3g} m outside the axisymmetric section (at most "
                    f"{self.max_outside:.3g} m allowed): the 3D body is not inside the section"
                )
            cells[out] = near
        return cells

    def displacement(self, x: np.ndarray) -> np.ndarray:
        """``u`` (3 x n) [m] at the 3D points ``x`` (3 x n): ``u_r e_r + u_z e_z``."""
        pts = self.rz(x)
        if pts.shape[0] == 0:
            return np.zeros((3, 0))
        v = self.u.eval(pts, self._cells(pts))  # (n, 2): u_r, u_z
        r = np.maximum(pts[:, 0], 1e-300)
        return np.vstack([v[:, 0] * x[0] / r, v[:, 0] * x[1] / r, v[:, 1]])

    def pressure(self, x: np.ndarray) -> np.ndarray:
        """The mixed pressure (n,) [Pa] at the 3D points ``x`` (3 x n)."""
        if self.p is None:
            raise ParameterError("the axisymmetric solution has no mixed pressure")
        pts = self.rz(x)
        if pts.shape[0] == 0:
            return np.zeros(0)
        return self.p.eval(pts, self._cells(pts))[:, 0]


def serial_copy(mesh_kind: str, params: Any) -> Any:
    """The mesh of builder ``mesh_kind`` with ``params`` on ``MPI.COMM_SELF`` (every rank
    runs Gmsh on its own copy)."""
    from dolfinx_seal.meshing import create_mesh

    return create_mesh(mesh_kind, params, comm=MPI.COMM_SELF).mesh


__all__ = ["RevolvedState", "serial_copy"]
