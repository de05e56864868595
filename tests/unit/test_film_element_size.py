"""The film's element size for its streamline upwinding (SurfaceFilm._element_size).

On an affine mesh it is UFL's ``FacetArea`` (the facet length in 2D, ``sqrt(2 area)``
in 3D); FFCx 0.9 cannot integrate ``FacetArea`` on a curved mesh (the ball's
``mesh_order = 2``: a JFO ball failed to compile, "Not handled: FacetArea"), where
the size comes from the straight facet through the vertices.  On an affine mesh
the two must agree to round-off, facet by facet (checked through the integral of
the size squared, weighted by the facet's position, over a tagged boundary)."""

from __future__ import annotations

import dolfinx
import numpy as np
import pytest
import ufl
from mpi4py import MPI

from dolfinx_seal.film.surface import SurfaceFilm


def _tagged(mesh):
    fdim = mesh.topology.dim - 1
    facets = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], 0.0))
    tags = dolfinx.mesh.meshtags(mesh, fdim, facets, np.full(len(facets), 7, dtype=np.int32))
    return facets, ufl.Measure("ds", domain=mesh, subdomain_data=tags, subdomain_id=7,
                               metadata={"quadrature_degree": 1})  # fmt: skip


@pytest.mark.parametrize("dim", [2, 3])
def test_the_vertex_size_is_the_facet_area_on_an_affine_mesh(dim):
    comm = MPI.COMM_WORLD
    if dim == 2:
        mesh = dolfinx.mesh.create_unit_square(comm, 7, 5, dolfinx.mesh.CellType.triangle)
    else:
        mesh = dolfinx.mesh.create_unit_cube(comm, 4, 3, 5)
    # a non-uniform affine mesh: facet sizes vary along the boundary
    mesh.geometry.x[:, 0] = mesh.geometry.x[:, 0] ** 2
    facets, ds = _tagged(mesh)
    x = ufl.SpatialCoordinate(mesh)
    vals = []
    for from_vertices in (False, True):
        h = SurfaceFilm._element_size(mesh, facets, from_vertices=from_vertices)
        form = dolfinx.fem.form(h * h * (1.0 + x[0]) * ds)
        vals.append(comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM))
    assert vals[0] > 0.0
    assert vals[1] == pytest.approx(vals[0], rel=1e-12, abs=0)


def test_a_curved_mesh_gets_a_size_ffcx_can_integrate():
    """The ball's second-order mesh: the size compiles and integrates, and its mean
    over the contact cap lies between the contact element and the cap's largest."""
    from dolfinx_seal.meshing import create_mesh

    a, h = 0.4e-3, 0.08e-3
    tm = create_mesh("ball", comm=MPI.COMM_WORLD, radius=0.01, shape="half", contact_radius=a,
                     h_contact=h, h_cap=2 * h, h_far=1e-3, order=2, cap_extent=2.0,
                     fine_extent=1.5)  # fmt: skip
    mesh = tm.mesh
    assert mesh.geometry.cmap.degree == 2
    facets = tm.facet_tags.find(tm.tag("contact"))
    size = SurfaceFilm._element_size(mesh, facets)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tm.facet_tags,
                     subdomain_id=tm.tag("contact"), metadata={"quadrature_degree": 1})  # fmt: skip
    comm = mesh.comm
    area = comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * ds)), op=MPI.SUM)
    mean = comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(size * ds)),
                          op=MPI.SUM) / area  # fmt: skip
    assert 0.5 * h < mean < 2.0 * (2 * h), mean
