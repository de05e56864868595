"""The outputs' compiled forms and interpolations (``dolfinx_seal.compiled``).

A kept form must give what a fresh one gives: for an expression built afresh
but equal (the same functions), after the functions' values changed; and an
expression that differs only in which function it reads (the same element,
another object) must not be taken for a kept one.  Checked against the exact
integrals and nodal values of linear functions on the unit square."""

from __future__ import annotations

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.compiled import CompiledCache


def _setup():
    mesh = dolfinx.mesh.create_unit_square(MPI.COMM_WORLD, 6, 4)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    f, g = dolfinx.fem.Function(V), dolfinx.fem.Function(V)
    f.interpolate(lambda x: x[0])
    g.interpolate(lambda x: 1.0 + x[1])
    return mesh, V, f, g


def _integral(mesh, compiled):
    return mesh.comm.allreduce(dolfinx.fem.assemble_scalar(compiled), op=MPI.SUM)


def test_a_kept_form_reads_the_current_values_of_its_own_functions():
    mesh, _V, f, g = _setup()
    cache = CompiledCache()
    dx = ufl.Measure("dx", domain=mesh)
    x = ufl.SpatialCoordinate(mesh)
    a = cache.form(2.0 * f * x[1], dx)
    assert np.isclose(_integral(mesh, a), 0.5)  # int 2 x y = 1/2
    assert cache.form(2.0 * f * x[1], dx) is a  # built afresh, equal: kept
    f.interpolate(lambda x: x[1])
    assert np.isclose(_integral(mesh, cache.form(2.0 * f * x[1], dx)), 2.0 / 3.0)
    b = cache.form(2.0 * g * x[1], dx)  # another function of the same space
    assert b is not a
    assert np.isclose(_integral(mesh, b), 2.0 * (0.5 + 1.0 / 3.0))
    ds = ufl.Measure("ds", domain=mesh)
    assert np.isclose(_integral(mesh, cache.form(f, ds)), 2.0)  # int y over the boundary


def test_a_kept_interpolation_is_refreshed_at_each_call():
    mesh, V, f, g = _setup()
    cache = CompiledCache()
    x = ufl.SpatialCoordinate(mesh)
    X = V.tabulate_dof_coordinates()[:, 0]
    n = V.dofmap.index_map.size_local
    h = cache.interpolate(f + x[0], V)
    assert np.allclose(h.x.array[:n], 2.0 * X[:n])
    f.x.array[:] = 0.0
    h2 = cache.interpolate(f + x[0], V)
    assert h2 is h
    assert np.allclose(h2.x.array[:n], X[:n])
    k = cache.interpolate(g + x[0], V)
    assert k is not h
    assert np.allclose(k.x.array[:n], 1.0 + V.tabulate_dof_coordinates()[:n, 1] + X[:n])


def test_a_changing_number_enters_as_a_kept_constant():
    """The centred second moment of x about its mean (as the lip's contact width
    takes it): exact for two means, with one kept form."""
    mesh, _V, _f, _g = _setup()
    cache = CompiledCache()
    dx = ufl.Measure("dx", domain=mesh)
    x = ufl.SpatialCoordinate(mesh)
    kept = set()
    for mean in (0.5, 0.25):
        c = cache.constant(mesh, "centre", mean)
        a = cache.form((x[0] - c) ** 2, dx)
        kept.add(id(a))
        assert np.isclose(_integral(mesh, a), 1.0 / 3.0 - mean + mean**2)  # int (x - m)^2
    assert len(kept) == 1


def test_the_least_recently_used_entry_goes_first(monkeypatch):
    from dolfinx_seal import compiled

    monkeypatch.setattr(compiled, "MAX_ENTRIES", 2)
    mesh, _V, f, g = _setup()
    cache = CompiledCache()
    dx = ufl.Measure("dx", domain=mesh)
    a = cache.form(f, dx)
    b = cache.form(g, dx)
    assert cache.form(f, dx) is a  # f used last: g is the oldest
    cache.form(f * g, dx)
    assert cache.form(f, dx) is a
    assert cache.form(g, dx) is not b  # g was dropped and made again
