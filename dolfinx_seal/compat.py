"""Every DOLFINx version difference, in one place, decided by feature detection.

Supported: DOLFINx 0.9 (Debian 13).  Written to be ready for 0.10, which
changes ``gmshio.model_to_mesh`` (returns a MeshData object), removes the
``*_block`` assembly functions (replaced by ``kind="mpi"`` arguments) and makes
``interpolation_points`` a property.  No other module may test versions.

Importing this module also makes form compilation quiet (:func:`quiet_jit`):
every module of the package that compiles forms imports it.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Sequence
from typing import Any

import dolfinx
import dolfinx.fem.petsc as _fem_petsc
import dolfinx.jit
import numpy as np
from dolfinx.io import gmshio
from petsc4py import PETSc

DOLFINX_VERSION: tuple[int, ...] = tuple(int(x) for x in dolfinx.__version__.split(".")[:2])

_HAS_BLOCK = hasattr(_fem_petsc, "assemble_vector_block")


# ------------------------------------------------------------------ quiet JIT
#: Set this environment variable to 1 to see the C compiler's warnings again.
JIT_WARNINGS_ENV = "DOLFINX_SEAL_JIT_WARNINGS"


def quiet_jit() -> None:
    """Compile every form and expression without C compiler warnings (idempotent).

    FFCx hands the generated C to CFFI, whose compiler runs with Python's build
    flags (``-Wall``) and writes its warnings (``-Wunused-variable`` in
    ``libffcx_forms_*.c`` and the like) straight to the process's stderr; FFCx
    only captures CFFI's own log.  This wraps :func:`dolfinx.jit.get_options`
    (which every DOLFINx JIT compilation calls) so that the compiler arguments
    always end with ``-w``, whatever the caller's ``jit_options`` or the user's
    ``dolfinx_jit_options.json`` say.  ``-w`` suppresses warnings only: a failing
    compilation still prints the compiler's error and raises.  The arguments are
    part of FFCx's cache key, so quiet modules do not mix with others in the cache.
    With ``DOLFINX_SEAL_JIT_WARNINGS=1`` (read at each compilation) nothing is added.
    """
    if getattr(dolfinx.jit.get_options, "_dolfinx_seal_quiet", False):
        return
    original = dolfinx.jit.get_options

    @functools.wraps(original)
    def get_options(priority_options: dict | None = None) -> dict:
        options = original(priority_options)
        if os.environ.get(JIT_WARNINGS_ENV, "0") in ("", "0"):
            args = list(options.get("cffi_extra_compile_args") or [])
            if "-w" not in args:
                args.append("-w")
            options["cffi_extra_compile_args"] = args
        return options

    get_options._dolfinx_seal_quiet = True  # type: ignore[attr-defined]
    dolfinx.jit.get_options = get_options


quiet_jit()


# ------------------------------------------------------------------ quadrature
def check_quadrature_rules(form: Any, name: str = "form") -> None:
    """Refuse a UFL form that FFCx 0.9 would compile with the wrong quadrature.

    FFCx 0.9.0 (Debian 13) can integrate every integrand of a group of integrals of
    one type on one subdomain with the one-point rule when the group holds a
    degree-1 integral beside one of another degree: ``exp(u) v ds(degree=8) +
    u^3 v ds(degree=1)`` is assembled as both one-point, in either order (1.3 %
    off on a unit square); with other integrands it was right, and two degrees
    above 1 always were (``tests/test_compat.py``).  A residual built that way is one-point while its
    Jacobian blocks without the degree-1 term keep their own rule: the film rows'
    Jacobian was 0.26 % off finite differences and Newton converged linearly.
    Every form the solvers compile passes this check: a group with a degree-1
    integral has no integral of another rule.

    Raises:
        ValueError: naming the form, the integral type, the subdomain and the rules.
    """
    groups: dict[tuple[Any, ...], set[tuple[Any, Any]]] = {}
    for it in form.integrals():
        md = it.metadata()
        key = (it.integral_type(), it.subdomain_id(), id(it.ufl_domain()))
        rule = (md.get("quadrature_degree"), md.get("quadrature_rule", "default"))
        groups.setdefault(key, set()).add(rule)
    for (kind, sub, _), rules in groups.items():
        if len(rules) > 1 and any(deg == 1 for deg, _ in rules):
            shown = ", ".join(f"degree {d if d is not None else 'estimated'} ({r})"
                              for d, r in sorted(rules, key=str))  # fmt: skip
            raise ValueError(
                f"{name}: the {kind} integrals on subdomain {sub} mix a one-point rule "
                f"with others ({shown}); FFCx 0.9 would integrate them all one-point. "
                "Give them one rule (or split the form)"
            )


# ------------------------------------------------------------------ real space
def real_functionspace(mesh: Any) -> Any:
    """The space of one real number on ``mesh`` (a global unknown, e.g. the
    counter-surface position under force control), on ``mesh.comm``.

    Every cell's single dof is the same global dof, owned by rank 0 of ``mesh.comm``
    and a ghost on the others: the layout of scifem's ``create_real_functionspace``,
    which builds its index map on ``MPI_COMM_WORLD`` whatever the mesh's
    communicator (so a problem on a sub-communicator, a sweep chain, fails in
    the first block vector with MPI_ERR_ARG).  Built here from DOLFINx 0.9's C++
    constructors (``IndexMap``, ``ElementDofLayout``, ``DofMap``,
    ``FiniteElement_float64``, ``FunctionSpace_float64``)."""
    import basix.ufl
    from dolfinx import cpp as _cpp

    if mesh.geometry.x.dtype != np.float64:
        raise TypeError("real_functionspace: float64 meshes only")
    element = basix.ufl.element("P", mesh.basix_cell(), 0, discontinuous=True)
    owner = mesh.comm.rank == 0
    ghosts = np.zeros(0 if owner else 1, dtype=np.int64)  # global dof 0, owned by rank 0
    imap = _cpp.common.IndexMap(
        mesh.comm, 1 if owner else 0, ghosts, np.zeros(ghosts.size, np.int32)
    )
    e = element.basix_element._e
    layout = _cpp.fem.ElementDofLayout(1, e.entity_dofs, e.entity_closure_dofs, [], [])
    cells = mesh.topology.index_map(mesh.topology.dim)
    n = cells.size_local + cells.num_ghosts
    dofs = _cpp.graph.AdjacencyList_int32(np.zeros((n, 1), dtype=np.int32))
    dofmap = _cpp.fem.DofMap(layout, imap, 1, dofs, 1)
    cpp_element = _cpp.fem.FiniteElement_float64(e, 1, False)
    space = _cpp.fem.FunctionSpace_float64(mesh._cpp_object, cpp_element, dofmap, [])
    return dolfinx.fem.FunctionSpace(mesh, element, space)


# ---------------------------------------------------------------- gmsh -> mesh
def model_to_mesh(
    model: Any, comm: Any, rank: int = 0, gdim: int = 3, partition: Any = None
) -> tuple[Any, Any, Any]:
    """``(mesh, cell_tags, facet_tags)`` from a Gmsh model living on ``rank``.

    ``partition``: None (DOLFINx's graph partitioner), or ``partition(vertices,
    nparts) -> destinations``: ``vertices`` the cells' vertex node indices into
    Gmsh's node list ordered by tag, shape ``(cells, vertices per cell)``, as the
    rank holding them sees them (``rank`` holds them all); one destination rank
    per cell (no ghost layer: DOLFINx adds the shared facets' cells)."""
    partitioner = None
    if partition is not None and comm.size > 1:

        def partitioner(_comm: Any, nparts: int, cell_types: Any, cells: Any) -> Any:
            # 0.9: (comm, nparts, [cell type], [flat vertex indices]), one cell type
            nv = dolfinx.cpp.mesh.cell_num_vertices(cell_types[0])
            vertices = np.asarray(cells[0], dtype=np.int64).reshape(-1, nv)
            dest = np.asarray(partition(vertices, nparts), dtype=np.int32)
            return dolfinx.graph.adjacencylist(dest)

    out = gmshio.model_to_mesh(model, comm, rank, gdim=gdim, partitioner=partitioner)
    if isinstance(out, tuple):  # 0.9
        return out[0], out[1], out[2]
    return out.mesh, out.cell_tags, out.facet_tags  # 0.10: MeshData


def interpolation_points(element: Any) -> np.ndarray:
    """Reference interpolation points of a (basix/dolfinx) element."""
    pts = element.interpolation_points
    return pts() if callable(pts) else pts


# ------------------------------------------------------------ block assembly
def create_vector_block(L: Sequence[Any]) -> PETSc.Vec:
    """Monolithic (non-nested) PETSc vector for a list of linear forms."""
    if _HAS_BLOCK:
        return _fem_petsc.create_vector_block(list(L))
    return _fem_petsc.create_vector(list(L), kind="mpi")  # pragma: no cover - 0.10


def create_matrix_block(a: Sequence[Sequence[Any]]) -> PETSc.Mat:
    """Monolithic PETSc matrix for a block of bilinear forms."""
    if _HAS_BLOCK:
        return _fem_petsc.create_matrix_block([list(r) for r in a])
    return _fem_petsc.create_matrix([list(r) for r in a], kind="mpi")  # pragma: no cover


def assemble_residual_block(
    b: PETSc.Vec, L: Sequence[Any], a: Sequence[Sequence[Any]], bcs: Sequence[Any], x: PETSc.Vec
) -> None:
    """Assemble the block residual ``F(x)`` into ``b``; Dirichlet rows hold ``x - g``.

    Same convention as the single-field ``NonlinearProblem.F`` of DOLFINx 0.9:
    lifting with ``alpha = -1`` and ``x0 = x``, so a Newton step restores ``g``.
    """
    with b.localForm() as bl:
        bl.set(0.0)
    a_ = [list(r) for r in a]
    if _HAS_BLOCK:
        _fem_petsc.assemble_vector_block(b, list(L), a_, bcs=list(bcs), x0=x, alpha=-1.0)
        return
    # DOLFINx >= 0.10: written against its API, not run here (only 0.9 is installed)
    from dolfinx.fem import bcs_by_block, extract_function_spaces  # pragma: no cover

    _fem_petsc.assemble_vector(b, list(L))  # pragma: no cover
    bcs1 = bcs_by_block(extract_function_spaces(a_, 1), list(bcs))  # pragma: no cover
    _fem_petsc.apply_lifting(b, a_, bcs=bcs1, x0=x, alpha=-1.0)  # pragma: no cover
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)  # pragma: no cover
    bcs0 = bcs_by_block(extract_function_spaces(list(L)), list(bcs))  # pragma: no cover
    _fem_petsc.set_bc(b, bcs0, x0=x, alpha=-1.0)  # pragma: no cover


def assemble_jacobian_block(A: PETSc.Mat, a: Sequence[Sequence[Any]], bcs: Sequence[Any]) -> None:
    """Assemble a block Jacobian into ``A`` (zeroed first, diagonal 1 on bc rows)."""
    A.zeroEntries()
    if _HAS_BLOCK:
        _fem_petsc.assemble_matrix_block(A, [list(r) for r in a], bcs=list(bcs))
    else:  # pragma: no cover - 0.10
        _fem_petsc.assemble_matrix(A, [list(r) for r in a], bcs=list(bcs))
    A.assemble()


def create_vector_block_from_maps(maps: Sequence[tuple[Any, int]]) -> PETSc.Vec:
    """Monolithic (non-nested) ghosted PETSc vector for blocks laid out by ``maps``.

    ``maps`` holds ``(index_map, block size)`` per block, e.g. the spaces of
    dolfinx_mpc constraints, whose index maps ghost the masters.
    """
    if _HAS_BLOCK:
        from dolfinx.cpp.fem.petsc import create_vector_block

        return create_vector_block(list(maps))
    from dolfinx.la.petsc import create_vector  # pragma: no cover - 0.10

    return create_vector(list(maps))  # pragma: no cover


def block_maps(spaces: Sequence[Any]) -> list[tuple[Any, int]]:
    """(index_map, block size) of each space, the layout of a block vector."""
    return [(V.dofmap.index_map, V.dofmap.index_map_bs) for V in spaces]


def block_to_functions(x: PETSc.Vec, functions: Sequence[Any]) -> None:
    """Copy a block vector into the functions (owned and ghost values)."""
    maps = block_maps([u.function_space for u in functions])
    if _HAS_BLOCK:
        from dolfinx.cpp.la.petsc import get_local_vectors

        for u, xl in zip(functions, get_local_vectors(x, maps), strict=True):
            u.x.array[:] = xl
    else:  # pragma: no cover - 0.10
        _fem_petsc.assign(x, list(functions))
    for u in functions:
        u.x.scatter_forward()


def functions_to_block(functions: Sequence[Any], x: PETSc.Vec) -> None:
    """Copy the functions' owned values into a block vector."""
    maps = block_maps([u.function_space for u in functions])
    if _HAS_BLOCK:
        from dolfinx.cpp.la.petsc import scatter_local_vectors

        scatter_local_vectors(x, [u.x.array for u in functions], maps)
    else:  # pragma: no cover - 0.10
        _fem_petsc.assign(list(functions), x)
    x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)


# ------------------------------------------------------------- interpolation
def interpolate_nonmatching(u_to: Any, u_from: Any, padding: float = 1e-8) -> None:
    """Interpolate ``u_from`` (another mesh) into ``u_to``.

    ``padding`` (in mesh length units) must exceed the chord sag of curved
    boundaries; points found in no cell are set to zero by DOLFINx, so callers
    must check coverage (see :func:`dolfinx_seal.solvers.continuation.transfer`).
    """
    V_to = u_to.function_space
    mesh = V_to.mesh
    tdim = mesh.topology.dim
    cmap = mesh.topology.index_map(tdim)
    cells = np.arange(cmap.size_local + cmap.num_ghosts, dtype=np.int32)
    data = dolfinx.fem.create_interpolation_data(
        V_to, u_from.function_space, cells, padding=padding
    )
    u_to.interpolate_nonmatching(u_from, cells, data)
    u_to.x.scatter_forward()
