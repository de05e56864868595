"""Gmsh builders -> distributed DOLFINx meshes with cell and facet tags.

Gmsh runs on one rank (``rank``, default 0); the mesh is partitioned and
distributed by DOLFINx (:func:`dolfinx_seal.compat.model_to_mesh`).  Parameters
are validated on every rank before anything is built, so a bad parameter raises
:class:`ParameterError` everywhere instead of hanging the others.

Example::

    from mpi4py import MPI
    import ufl
    from geometry import tags
    from dolfinx_seal.meshing import create_mesh, measure

    tm = create_mesh("cylinder", comm=MPI.COMM_WORLD, h_contact=10e-6)
    ds = ufl.Measure("ds", domain=tm.mesh, subdomain_data=tm.facet_tags)
    contact_length = measure(tm, "contact")      # same value at any number of ranks
    # ... ufl.inner(p * n, v) * ds(tags.CONTACT) ...
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI
from ufl.core.expr import Expr

from dolfinx_seal.compat import model_to_mesh
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import world
from geometry import load as _load_builder
from geometry import tags as _tags


@dataclass
class TaggedMesh:
    """A distributed mesh with its tags and the description of how it was built.

    Attributes:
        mesh: The DOLFINx mesh (``mesh.name`` is the geometry kind).
        cell_tags: Cell tags (``body`` = :data:`geometry.tags.BODY`).
        facet_tags: Facet tags, numbers from :mod:`geometry.tags`.
        info: The builder's :class:`geometry.MeshInfo` as a dictionary (``kind``,
            ``params``, ``facet_groups``, ``reference`` closed forms, ``extra``, counts),
            identical on every rank.
    """

    mesh: Any
    cell_tags: Any
    facet_tags: Any
    info: dict[str, Any]

    @property
    def comm(self) -> Any:
        """The mesh communicator."""
        return self.mesh.comm

    def tag(self, name: str) -> int:
        """Number of the group ``name``; raises ``KeyError`` if this mesh does not have it."""
        groups = {**self.info["cell_groups"], **self.info["facet_groups"]}
        if name not in groups:
            raise KeyError(f"{self.info['kind']} mesh has no group {name!r}; it has {list(groups)}")
        return int(groups[name])

    def dx(self) -> ufl.Measure:
        """Cell measure with the cell tags as subdomain data."""
        return ufl.Measure("dx", domain=self.mesh, subdomain_data=self.cell_tags)

    def ds(self) -> ufl.Measure:
        """Exterior-facet measure with the facet tags as subdomain data."""
        return ufl.Measure("ds", domain=self.mesh, subdomain_data=self.facet_tags)


def _finish(mesh: Any, ct: Any, ft: Any, info: dict[str, Any]) -> TaggedMesh:
    mesh.name = str(info.get("kind", "mesh"))
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)
    return TaggedMesh(mesh, ct, ft, info)


# --------------------------------------------------------------- partitioning
def weighted_bisection(points: np.ndarray, weights: np.ndarray, nparts: int) -> np.ndarray:
    """Destination part (0 to ``nparts - 1``) of each point, by recursive coordinate
    bisection with weights: each set is cut across its longest extent, at the
    weighted quantile that gives each side its share of the parts.  Deterministic
    (a stable sort), so the same mesh is distributed the same way in every run.

    Args:
        points: Coordinates, shape ``(n, d)`` [m].
        weights: Non-negative cost of each point [-].
        nparts: Number of parts.
    """
    dest = np.zeros(len(points), dtype=np.int32)

    def cut(idx: np.ndarray, first: int, n: int) -> None:
        if n == 1 or idx.size == 0:
            dest[idx] = first
            return
        axis = int(np.argmax(np.ptp(points[idx], axis=0)))
        order = idx[np.argsort(points[idx, axis], kind="stable")]
        total = np.cumsum(weights[order])
        left = n // 2
        k = int(np.searchsorted(total, total[-1] * left / n))
        cut(order[:k], first, left)
        cut(order[k:], first + left, n - left)

    cut(np.arange(len(points)), 0, nparts)
    return dest


def surface_weighted_partition(model: Any, tdim: int, balance: dict[str, float]) -> Any:
    """A partition for :func:`~dolfinx_seal.compat.model_to_mesh` that balances the
    cells' cost, a cell touching facet group ``g`` (``tdim`` of its vertices on it)
    costing ``1 + balance[g]`` cells (:func:`weighted_bisection` of the cell
    centroids).  Call on the rank holding the Gmsh model.

    Why: the surface integrals (contact law, film, their tractions) cost several
    cell integrals per facet, and DOLFINx's graph partitioner balances cells
    alone; on the ball's demo mesh at 2 ranks it left 2,527 of the 3,065 contact
    facets on one rank, which the other waited for at every assembly
    (docs/performance.md, "Balancing the contact surface").
    """
    tags, coords, _ = model.mesh.getNodes()
    x = np.zeros((int(tags.max()), 3))
    x[tags.astype(np.int64) - 1] = coords.reshape(-1, 3)
    groups = {model.getPhysicalName(d, t): t for d, t in model.getPhysicalGroups(tdim - 1)}
    masks = []
    for group, weight in balance.items():  # the groups checked by _check_balance
        nodes = model.mesh.getNodesForPhysicalGroup(tdim - 1, groups[group])[0]
        on = np.zeros(len(x), dtype=bool)
        on[nodes.astype(np.int64) - 1] = True
        masks.append((on, float(weight)))

    def partition(vertices: np.ndarray, nparts: int) -> np.ndarray:
        if vertices.size == 0:
            return np.zeros(0, dtype=np.int32)
        weights = np.ones(len(vertices))
        for on, weight in masks:
            weights += weight * (on[vertices].sum(axis=1) >= tdim)
        return weighted_bisection(x[vertices].mean(axis=1), weights, nparts)

    return partition


def from_builder(
    build: Any,
    params: Any,
    comm: Any = None,
    rank: int = 0,
    *,
    out_dir: str | Path | None = None,
    name: str | None = None,
    verbose: bool = False,
    balance: dict[str, float] | None = None,
) -> TaggedMesh:
    """Run a Gmsh builder on ``rank`` and distribute its mesh over ``comm``.

    Args:
        build: A builder ``build(params) -> MeshInfo`` (e.g. :func:`geometry.lip.build_lip`).
        params: Its (validated) parameter dataclass.
        comm: MPI communicator (default :func:`dolfinx_seal.mpi.world`: ``COMM_WORLD``, or a sweep chain's own).
        rank: Rank that runs Gmsh.
        out_dir: If given, ``rank`` also writes ``NAME.msh`` and ``info.json`` there.
        name: Mesh file stem (default the kind).
        verbose: Show Gmsh's log.
        balance: None: DOLFINx's graph partitioner (balances the cells); else
            ``{facet group: extra cost}``: the cells on those facet groups count
            ``1 + cost`` cells (:func:`surface_weighted_partition`).

    Returns:
        The distributed mesh and tags.

    Raises:
        ParameterError: On every rank, if the builder rejects the parameters.
        RuntimeError: On every rank, if Gmsh fails.
    """
    from geometry._common import gmsh_session, save

    comm = comm or world()
    if comm.rank == rank:
        import gmsh

        with gmsh_session(verbose):
            try:
                info = build(params)
                if out_dir is not None:
                    save(info, out_dir, name)
                status: tuple[str, Any] = ("ok", info.to_dict())
            except ParameterError as e:
                status = ("parameter", str(e))
            except Exception as e:
                status = ("error", f"{type(e).__name__}: {e}")
            comm.bcast(status, root=rank)
            if status[0] != "ok":
                _raise(status, rank)
            info_d = status[1]
            _check_balance(balance, info_d)
            partition = None
            if balance and comm.size > 1:
                partition = surface_weighted_partition(gmsh.model, int(info_d["tdim"]), balance)
            mesh, ct, ft = model_to_mesh(gmsh.model, comm, rank, int(info_d["gdim"]), partition)
    else:
        status = comm.bcast(None, root=rank)
        if status[0] != "ok":
            _raise(status, rank)
        info_d = status[1]
        _check_balance(balance, info_d)
        # the other ranks hold no cells; they take part in the partitioner's call
        partition = (lambda v, n: np.zeros(0, dtype=np.int32)) if balance else None
        mesh, ct, ft = model_to_mesh(None, comm, rank, int(info_d["gdim"]), partition)
    return _finish(mesh, ct, ft, info_d)


def _check_balance(balance: dict[str, float] | None, info: dict[str, Any]) -> None:
    """The partition's facet groups exist and their costs are >= 0 (every rank)."""
    for group, cost in (balance or {}).items():
        if group not in info["facet_groups"]:
            raise ParameterError(f"balance: the {info['kind']} mesh has no facet group "
                                 f"{group!r} (it has {sorted(info['facet_groups'])})")  # fmt: skip
        if not cost >= 0.0:
            raise ParameterError(f"balance[{group!r}] = {cost!r} is outside the allowed "
                                 "range [0, inf)")  # fmt: skip


def _raise(status: tuple[str, Any], rank: int) -> None:
    kind, msg = status
    if kind == "parameter":
        raise ParameterError(msg)
    raise RuntimeError(f"mesh generation failed on rank {rank}: {msg}")


def create_mesh(
    kind: str,
    params: Any = None,
    comm: Any = None,
    rank: int = 0,
    *,
    out_dir: str | Path | None = None,
    name: str | None = None,
    verbose: bool = False,
    balance: dict[str, float] | None = None,
    **overrides: Any,
) -> TaggedMesh:
    """Build a ``cylinder``, ``ball``, ``lip`` or ``lip-sector`` mesh and distribute it.

    Args:
        kind: Geometry kind (:data:`geometry.KINDS`).
        params: The kind's parameter dataclass (defaults if ``None``).
        comm: MPI communicator (default :func:`dolfinx_seal.mpi.world`: ``COMM_WORLD``, or a sweep chain's own).
        rank: Rank that runs Gmsh.
        out_dir: If given, also write ``NAME.msh`` and ``info.json`` there (from ``rank``).
        name: Mesh file stem (default the kind).
        verbose: Show Gmsh's log.
        balance: The partition's extra cost of the cells on facet groups
            (:func:`from_builder`).
        **overrides: Parameter fields to change (validated on every rank).

    Returns:
        The distributed mesh and tags.
    """
    mod = _load_builder(kind)
    p = params if params is not None else mod.PARAMS()
    if overrides:
        p = dataclasses.replace(p, **overrides)
    return from_builder(mod.BUILD, p, comm, rank, out_dir=out_dir, name=name, verbose=verbose,
                        balance=balance)  # fmt: skip


def read_mesh(path: str | Path, comm: Any = None, rank: int = 0) -> TaggedMesh:
    """Read a ``.msh`` written by a builder (with the ``info.json`` beside it, if any).

    Without ``info.json`` the geometric dimension is 2 if every node has ``z = 0``,
    and the groups are those of :mod:`geometry.tags` found in the file.
    """
    import gmsh

    from geometry._common import gmsh_session

    comm = comm or world()
    path = Path(path)
    if comm.rank == rank:
        with gmsh_session():
            if not path.is_file():
                comm.bcast(("error", f"no mesh file {str(path)!r}"), root=rank)
                _raise(("parameter", f"no mesh file {str(path)!r}"), rank)
            gmsh.open(str(path))
            info_path = path.parent / "info.json"
            info: dict[str, Any] = {}
            if info_path.is_file():
                info = json.loads(info_path.read_text())
                if info.get("mesh") != path.name:
                    info = {}
            if not info:
                x = gmsh.model.mesh.getNodes()[1].reshape(-1, 3)
                gdim = 2 if np.allclose(x[:, 2], 0.0) else 3
                groups = {
                    gmsh.model.getPhysicalName(d, t) or _tags.NAMES.get(t, str(t)): (d, t)
                    for d, t in gmsh.model.getPhysicalGroups()
                }
                tdim = max(d for d, _ in groups.values())
                info = {
                    "kind": path.stem,
                    "gdim": gdim,
                    "tdim": tdim,
                    "cell_groups": {n: t for n, (d, t) in groups.items() if d == tdim},
                    "facet_groups": {n: t for n, (d, t) in groups.items() if d == tdim - 1},
                }
            comm.bcast(("ok", info), root=rank)
            mesh, ct, ft = model_to_mesh(gmsh.model, comm, rank, int(info["gdim"]))
    else:
        status = comm.bcast(None, root=rank)
        if status[0] != "ok":
            _raise(("parameter", status[1]), rank)
        info = status[1]
        mesh, ct, ft = model_to_mesh(None, comm, rank, int(info["gdim"]))
    return _finish(mesh, ct, ft, info)


# ------------------------------------------------------------------ integrals
def integrate(tm: TaggedMesh, integrand: Any = 1.0, name: str | None = None) -> float:
    """Global integral of ``integrand`` over the cells (``name`` None or a cell group)
    or over the facets of a facet group.

    Args:
        tm: The mesh.
        integrand: A UFL expression or a number.
        name: ``None`` (all cells), a cell-group name, or a facet-group name.

    Returns:
        The integral, summed over ranks (same value on every rank).
    """
    mesh = tm.mesh
    if not isinstance(integrand, Expr):
        integrand = dolfinx.fem.Constant(mesh, dolfinx.default_scalar_type(integrand))
    if name is None:
        form = integrand * tm.dx()
    elif name in tm.info["cell_groups"]:
        form = integrand * tm.dx()(tm.tag(name))
    else:
        form = integrand * tm.ds()(tm.tag(name))
    local = dolfinx.fem.assemble_scalar(dolfinx.fem.form(form))
    return float(mesh.comm.allreduce(local, op=MPI.SUM))


def measure(tm: TaggedMesh, name: str | None = None) -> float:
    """Volume (area in 2D) of the mesh or of a cell group, or area (length) of a facet group."""
    return integrate(tm, 1.0, name)


def tagged_measures(tm: TaggedMesh) -> dict[str, float]:
    """Measure of the body and of every facet group of the mesh (global values)."""
    out = {"body": measure(tm)}
    for name in tm.info["facet_groups"]:
        out[name] = measure(tm, name)
    return out


def facet_coordinates(tm: TaggedMesh, name: str) -> np.ndarray:
    """Coordinates of the mesh vertices on a facet group, gathered on every rank.

    Vertices shared by ranks appear once per rank that owns a facet holding them;
    use ``np.unique(..., axis=0)`` for a set.  Meant for checks on small meshes
    (e.g. that the periodic faces of the lip sector match).
    """
    mesh = tm.mesh
    tdim = mesh.topology.dim
    facets = tm.facet_tags.find(tm.tag(name))
    nfacets_local = mesh.topology.index_map(tdim - 1).size_local
    facets = facets[facets < nfacets_local]
    mesh.topology.create_connectivity(tdim - 1, 0)
    mesh.topology.create_connectivity(0, tdim)
    verts = dolfinx.mesh.compute_incident_entities(mesh.topology, facets, tdim - 1, 0)
    nodes = dolfinx.mesh.entities_to_geometry(mesh, 0, verts, False).reshape(-1)
    x = mesh.geometry.x[nodes]
    parts = mesh.comm.allgather(x)
    return np.vstack(parts) if parts else np.zeros((0, 3))
