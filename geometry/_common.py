"""Plumbing shared by the Gmsh builders.

* :func:`gmsh_session` -- initialise and finalise Gmsh safely (nested use is fine);
* :class:`Line`, :class:`Arc` and :func:`loop_moments` -- exact 2D profiles made of
  straight and circular pieces, their area and first moments (Green's theorem,
  Gauss quadrature exact to round-off), and :func:`add_loop` to turn them into
  OpenCASCADE curves;
* :func:`classify` -- assign entities to physical groups by geometry (points sampled
  on the entity, tested against boxes, planes and circles), never by the order
  in which Gmsh returns them;
* size fields (:func:`size_field_expressions`, :func:`distance_threshold`);
* :class:`MeshInfo`, :func:`finish` (groups, mesh, statistics), :func:`save`
  (``.msh`` + ``info.json``) and :func:`cli_main` (the builders' ``__main__``).

Only gmsh, numpy and the standard library are imported (plus the pure-Python
parameter helpers of :mod:`dolfinx_seal.params`), so the builders run anywhere.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import datetime
import json
import math
import platform
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import gmsh
import numpy as np

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import from_mapping, parse_overrides, to_dict
from geometry import tags as _tags

Point2 = tuple[float, float]


# ------------------------------------------------------------------ session
@contextlib.contextmanager
def gmsh_session(verbose: bool = False) -> Iterator[Any]:
    """Initialise Gmsh for the duration of a ``with`` block.

    Gmsh is initialised with ``interruptible=False`` (no signal handler, safe
    under MPI and pytest) and finalised at exit, unless it was already
    initialised by the caller, in which case it is left running.

    Args:
        verbose: Print Gmsh's own log to the terminal.

    Yields:
        The ``gmsh`` module.
    """
    started = not gmsh.isInitialized()
    if started:
        gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
        gmsh.option.setNumber("General.Verbosity", 5 if verbose else 2)
        yield gmsh
    finally:
        if started:
            gmsh.finalize()


# ---------------------------------------------------------- exact profiles
@dataclass(frozen=True)
class Line:
    """Straight segment from ``p`` to ``q`` (2D, metres)."""

    p: Point2
    q: Point2

    def length(self) -> float:
        """Length (m)."""
        return math.dist(self.p, self.q)

    def at(self, t: np.ndarray) -> np.ndarray:
        """Points at parameters ``t`` in [0, 1], shape ``(len(t), 2)``."""
        p, q = np.asarray(self.p), np.asarray(self.q)
        return p[None, :] + np.asarray(t)[:, None] * (q - p)[None, :]

    def velocity(self, t: np.ndarray) -> np.ndarray:
        """d(point)/dt at ``t``."""
        d = np.asarray(self.q) - np.asarray(self.p)
        return np.repeat(d[None, :], len(np.atleast_1d(t)), axis=0)


@dataclass(frozen=True)
class Arc:
    """Circular arc from ``p`` to ``q`` about ``c``, the short way round (< pi)."""

    p: Point2
    q: Point2
    c: Point2

    @property
    def radius(self) -> float:
        """Radius (m)."""
        return math.dist(self.p, self.c)

    @property
    def angles(self) -> tuple[float, float]:
        """Start angle and signed span (radians, |span| < pi)."""
        a0 = math.atan2(self.p[1] - self.c[1], self.p[0] - self.c[0])
        a1 = math.atan2(self.q[1] - self.c[1], self.q[0] - self.c[0])
        span = (a1 - a0 + math.pi) % (2.0 * math.pi) - math.pi
        return a0, span

    def length(self) -> float:
        """Arc length (m)."""
        return self.radius * abs(self.angles[1])

    def at(self, t: np.ndarray) -> np.ndarray:
        """Points at parameters ``t`` in [0, 1]."""
        a0, span = self.angles
        a = a0 + np.asarray(t) * span
        r = self.radius
        return np.column_stack([self.c[0] + r * np.cos(a), self.c[1] + r * np.sin(a)])

    def velocity(self, t: np.ndarray) -> np.ndarray:
        """d(point)/dt at ``t``."""
        a0, span = self.angles
        a = a0 + np.asarray(t) * span
        r = self.radius
        return np.column_stack([-r * span * np.sin(a), r * span * np.cos(a)])


Segment = Line | Arc

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(24)
_GAUSS_T = 0.5 * (_GAUSS_X + 1.0)
_GAUSS_W = 0.5 * _GAUSS_W


def loop_moments(segments: Sequence[Segment]) -> dict[str, float]:
    """Area and first moments of the region bounded by a closed loop of segments.

    Green's theorem: ``A = 1/2 ∮ (x dy - y dx)``, ``∫ x dA = 1/2 ∮ x² dy``,
    ``∫ y dA = -1/2 ∮ y² dx``; 24-point Gauss quadrature per segment is exact for
    lines and exact to round-off for arcs (span < pi).  The loop may run either
    way round.

    Returns:
        ``{"area": m², "mx": ∫x dA (m³), "my": ∫y dA (m³), "cx": m, "cy": m}``.
    """
    area = mx = my = 0.0
    for s in segments:
        xy = s.at(_GAUSS_T)
        dxy = s.velocity(_GAUSS_T)
        x, y, dx, dy = xy[:, 0], xy[:, 1], dxy[:, 0], dxy[:, 1]
        area += 0.5 * float(np.sum(_GAUSS_W * (x * dy - y * dx)))
        mx += 0.5 * float(np.sum(_GAUSS_W * x * x * dy))
        my += -0.5 * float(np.sum(_GAUSS_W * y * y * dx))
    if area < 0.0:
        area, mx, my = -area, -mx, -my
    return {"area": area, "mx": mx, "my": my, "cx": mx / area, "cy": my / area}


def path_moments(segments: Sequence[Segment]) -> dict[str, float]:
    """Length and first moment ``∫ x ds`` of an open path (for Pappus surface areas)."""
    length = mx = 0.0
    for s in segments:
        xy = s.at(_GAUSS_T)
        speed = np.hypot(*s.velocity(_GAUSS_T).T)
        length += float(np.sum(_GAUSS_W * speed))
        mx += float(np.sum(_GAUSS_W * xy[:, 0] * speed))
    return {"length": length, "mx": mx}


def add_loop(segments: Sequence[Segment], plane: str = "xy") -> tuple[int, list[int]]:
    """Create an OpenCASCADE plane surface bounded by ``segments`` (a closed loop).

    Args:
        segments: Consecutive segments, the end of each the start of the next.
        plane: ``"xy"`` maps profile coordinates (u, v) to (u, v, 0); ``"xz"`` to (u, 0, v).

    Returns:
        The surface tag and the curve tag of each segment, in order.
    """
    occ = gmsh.model.occ
    scale = max(max(abs(c) for c in s.p) for s in segments) or 1.0
    pts: list[tuple[Point2, int]] = []

    def point(p: Point2) -> int:
        for q, tag in pts:
            if math.dist(p, q) <= 1e-12 * scale:
                return tag
        x, y, z = (p[0], p[1], 0.0) if plane == "xy" else (p[0], 0.0, p[1])
        tag = occ.addPoint(x, y, z)
        pts.append((p, tag))
        return tag

    curves, ends, centres = [], set(), set()
    for s in segments:
        p, q = point(s.p), point(s.q)
        ends |= {p, q}
        if isinstance(s, Line):
            curves.append(occ.addLine(p, q))
        else:
            c = point(s.c)
            centres.add(c)
            curves.append(occ.addCircleArc(p, c, q))
    surface = occ.addPlaneSurface([occ.addCurveLoop(curves)])
    # arc centres are construction points only: left in, they would become orphan mesh nodes
    occ.remove([(0, c) for c in sorted(centres - ends)])
    return surface, curves


# ---------------------------------------------------------- classification
def entity_points(dim: int, tag: int, n: int = 9) -> np.ndarray:
    """Points on a model entity, for geometric classification (shape ``(k, 3)``).

    Curves: ``n`` points evenly spaced in the parameter.  Surfaces: points sampled
    on every bounding curve plus the projection of the centre of mass onto the
    surface.  Volumes: the centre of mass.
    """
    model = gmsh.model
    if dim == 0:
        return np.asarray(model.getValue(0, tag, []), dtype=float).reshape(1, 3)
    if dim == 1:
        lo, hi = model.getParametrizationBounds(1, tag)
        t = np.linspace(lo[0], hi[0], n)
        return np.asarray(model.getValue(1, tag, t), dtype=float).reshape(-1, 3)
    com = np.asarray(gmsh.model.occ.getCenterOfMass(dim, tag), dtype=float)
    if dim == 3:
        return com.reshape(1, 3)
    pts = [entity_points(1, abs(c), n) for _, c in model.getBoundary([(2, tag)], oriented=False)]
    closest = np.asarray(model.getClosestPoint(2, tag, com)[0], dtype=float).reshape(1, 3)
    return np.vstack([*pts, closest])


def classify(
    dim: int,
    entities: Sequence[int],
    rules: Sequence[tuple[str, Callable[[np.ndarray], bool]]],
    default: str | Callable[[np.ndarray], str] | None = None,
) -> dict[str, list[int]]:
    """Sort entities into named groups by geometry.

    Args:
        dim: Dimension of the entities.
        entities: Entity tags.
        rules: Ordered ``(group name, predicate)`` pairs; a predicate gets the
            entity's sample points (:func:`entity_points`); the first rule that
            holds wins.
        default: Group of an entity no rule claims (a name, or a function of the
            points returning a name); ``None`` makes an unclaimed entity an error.

    Returns:
        Group name -> sorted entity tags (groups without entities are absent).
    """
    out: dict[str, list[int]] = {}
    for e in entities:
        pts = entity_points(dim, e)
        name = next((n for n, pred in rules if pred(pts)), None)
        if name is None:
            if default is None:
                raise RuntimeError(f"entity ({dim}, {e}) matches no group; points {pts.tolist()}")
            name = default(pts) if callable(default) else default
        out.setdefault(name, []).append(e)
    return {k: sorted(v) for k, v in out.items()}


def boundary_entities(dim: int) -> list[int]:
    """Tags of the entities of dimension ``dim - 1`` on the exterior boundary of the model."""
    ents = gmsh.model.getEntities(dim)
    bnd = gmsh.model.getBoundary(ents, combined=True, oriented=False, recursive=False)
    return sorted({abs(t) for _, t in bnd})


# -------------------------------------------------------------- size fields
def _num(v: float) -> str:
    return f"{float(v):.17g}"


def pos(expr: str) -> str:
    """MathEval expression for ``max(expr, 0)``."""
    return f"0.5*(({expr}) + Abs({expr}))"


def size_field_expressions(expressions: Sequence[str]) -> int:
    """A ``Min`` field of ``MathEval`` fields (Gmsh syntax in x, y, z; metres).

    Returns:
        Tag of the ``Min`` field (not yet set as background).
    """
    fields = []
    for e in expressions:
        f = gmsh.model.mesh.field.add("MathEval")
        gmsh.model.mesh.field.setString(f, "F", e)
        fields.append(f)
    fmin = gmsh.model.mesh.field.add("Min")
    gmsh.model.mesh.field.setNumbers(fmin, "FieldsList", fields)
    return fmin


def linear_size(h0: float, growth: float, distance: str) -> str:
    """MathEval expression ``h0 + growth * distance``."""
    return f"{_num(h0)} + {_num(growth)}*({distance})"


def distance_threshold(
    dim: int,
    entities: Sequence[int],
    sampling: int,
    h_min: float,
    h_max: float,
    growth: float,
) -> int:
    """Threshold field: ``h_min`` on the entities, growing by ``growth`` per unit distance.

    Args:
        dim: 1 (curves) or 2 (surfaces).
        entities: Entity tags the distance is measured from.
        sampling: Points per curve (or per parametric direction of a surface).
        h_min: Size on the entities (m).
        h_max: Size cap (m).
        growth: Size increase per unit distance (dimensionless).

    Returns:
        Tag of the ``Threshold`` field.
    """
    fd = gmsh.model.mesh.field.add("Distance")
    key = "CurvesList" if dim == 1 else "SurfacesList"
    gmsh.model.mesh.field.setNumbers(fd, key, list(entities))
    gmsh.model.mesh.field.setNumber(fd, "Sampling", int(sampling))
    ft = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(ft, "InField", fd)
    gmsh.model.mesh.field.setNumber(ft, "SizeMin", h_min)
    gmsh.model.mesh.field.setNumber(ft, "SizeMax", h_max)
    gmsh.model.mesh.field.setNumber(ft, "DistMin", 0.0)
    gmsh.model.mesh.field.setNumber(ft, "DistMax", (h_max - h_min) / growth)
    return ft


def mesh_options(h_min: float, h_max: float, background: int) -> None:
    """Let the background field alone decide the element size, within ``[h_min, h_max]``."""
    opt = gmsh.option.setNumber
    opt("Mesh.MeshSizeFromPoints", 0)
    opt("Mesh.MeshSizeFromCurvature", 0)
    opt("Mesh.MeshSizeExtendFromBoundary", 0)
    opt("Mesh.MeshSizeMin", 0.5 * h_min)
    opt("Mesh.MeshSizeMax", h_max)
    opt("Mesh.Algorithm", 6)  # Frontal-Delaunay (2D)
    opt("Mesh.Algorithm3D", 1)  # Delaunay (3D)
    opt("Mesh.SecondOrderLinear", 0)  # second-order nodes on the exact geometry
    gmsh.model.mesh.field.setAsBackgroundMesh(background)


# -------------------------------------------------------------- mesh info
@dataclass
class MeshInfo:
    """What a builder made: the parameters, the groups and a few numbers.

    Attributes:
        kind: ``"cylinder"``, ``"ball"``, ``"lip"`` or ``"lip-sector"``.
        params: The parameter dataclass the mesh was built from.
        gdim: Geometric dimension to give DOLFINx (2 or 3).
        tdim: Topological dimension of the cells.
        cell_groups: Cell-group name -> number (see :mod:`geometry.tags`).
        facet_groups: Facet-group name -> number, only groups present in this mesh.
        entities: Group name -> Gmsh entity tags (dimension ``tdim`` or ``tdim - 1``).
        num_nodes: Mesh nodes (including second-order nodes).
        num_cells: Cells.
        num_facets: Boundary elements per facet group.
        build_time_s: Wall time of geometry and meshing (s).
        reference: Closed-form quantities of the exact geometry (SI), e.g.
            ``volume``, ``area``, ``area_contact``; keys name what they are.
        extra: Builder-specific data (e.g. the sector angle and the periodic transform).
    """

    kind: str
    params: Any
    gdim: int
    tdim: int
    cell_groups: dict[str, int]
    facet_groups: dict[str, int]
    entities: dict[str, list[int]]
    num_nodes: int = 0
    num_cells: int = 0
    num_facets: dict[str, int] = field(default_factory=dict)
    build_time_s: float = 0.0
    reference: dict[str, float] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (the body of ``info.json``)."""
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        d["params"] = to_dict(self.params)
        return d


def finish(
    kind: str,
    params: Any,
    tdim: int,
    gdim: int,
    facet_entities: dict[str, list[int]],
    order: int,
    t_start: float,
    reference: dict[str, float],
    extra: dict[str, Any] | None = None,
) -> MeshInfo:
    """Add the physical groups (numbers AND names), generate the mesh, gather statistics.

    Every facet group handed in must be non-empty, and every boundary entity must
    belong to exactly one group.

    Raises:
        RuntimeError: If a group is empty or the groups do not partition the boundary.
    """
    model = gmsh.model
    cells = [t for _, t in model.getEntities(tdim)]
    claimed = [e for ents in facet_entities.values() for e in ents]
    bnd = boundary_entities(tdim)
    if sorted(claimed) != bnd:
        raise RuntimeError(f"{kind}: facet groups {facet_entities} do not partition {bnd}")
    model.addPhysicalGroup(tdim, cells, _tags.BODY, name="body")
    for name, ents in facet_entities.items():
        if not ents:
            raise RuntimeError(f"{kind}: facet group {name!r} is empty")
        model.addPhysicalGroup(tdim - 1, ents, _tags.number(name), name=name)

    model.mesh.generate(tdim)
    if order == 2:
        model.mesh.setOrder(2)

    def count(dim: int, ents: Sequence[int]) -> int:
        n = 0
        for e in ents:
            _, etags, _ = model.mesh.getElements(dim, e)
            n += sum(len(t) for t in etags)
        return n

    info = MeshInfo(
        kind=kind,
        params=params,
        gdim=gdim,
        tdim=tdim,
        cell_groups={"body": _tags.BODY},
        facet_groups={n: _tags.number(n) for n in facet_entities},
        entities={"body": cells, **facet_entities},
        num_nodes=len(model.mesh.getNodes()[0]),
        num_cells=count(tdim, cells),
        num_facets={n: count(tdim - 1, e) for n, e in facet_entities.items()},
        reference=reference,
        extra=extra or {},
    )
    for name, n in info.num_facets.items():
        if n == 0:
            raise RuntimeError(f"{kind}: facet group {name!r} has no elements")
    info.build_time_s = time.perf_counter() - t_start
    return info


# ------------------------------------------------------------ mesh arrays
def mesh_arrays(info: MeshInfo) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Nodes and corner connectivity of every group of the current model (numpy).

    Returns:
        ``(x, groups)``: ``x`` the node coordinates ``(N, 3)``, ``groups`` maps each
        group name to its elements as 0-based rows into ``x`` (corner nodes only,
        so second-order elements appear as their linear sub-simplex).
    """
    tags_, coords, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(tags_)
    tags_sorted = tags_[order]
    x = coords.reshape(-1, 3)[order]
    groups: dict[str, np.ndarray] = {}
    for name, ents in info.entities.items():
        dim = info.tdim if name in info.cell_groups else info.tdim - 1
        ncorner = dim + 1
        blocks = []
        for e in ents:
            types, _, nodes = gmsh.model.mesh.getElements(dim, e)
            for et, nd in zip(types, nodes, strict=True):
                nper = gmsh.model.mesh.getElementProperties(et)[3]
                conn = np.asarray(nd, dtype=np.int64).reshape(-1, nper)[:, :ncorner]
                blocks.append(np.searchsorted(tags_sorted, conn))
        groups[name] = np.vstack(blocks) if blocks else np.zeros((0, ncorner), dtype=np.int64)
    return x, groups


# -------------------------------------------------------------- provenance
def versions() -> dict[str, str]:
    """Versions that matter for a mesh (no DOLFINx import)."""
    out = {
        "python": platform.python_version(),
        "gmsh": str(gmsh.__version__),
        "numpy": np.__version__,
        "platform": platform.platform(),
    }
    try:
        from importlib.metadata import version

        out["dolfinx_seal"] = version("dolfinx_seal")
    except Exception:  # pragma: no cover - only when the project is not installed
        out["dolfinx_seal"] = "not installed"
    return out


def save(info: MeshInfo, out_dir: str | Path, name: str | None = None) -> Path:
    """Write the current model's mesh (``NAME.msh``, MSH 4.1) and ``info.json`` beside it.

    One mesh per folder: ``info.json`` describes the mesh just written.  Call on
    one process only (rank 0 under MPI).

    Returns:
        Path of the ``.msh`` file.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{name or info.kind}.msh"
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.write(str(path))
    data = {
        "mesh": path.name,
        "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "units": "SI (metres)",
        **info.to_dict(),
        "versions": versions(),
    }
    (out / "info.json").write_text(json.dumps(data, indent=2) + "\n")
    return path


# ---------------------------------------------------------------------- CLI
def cli_main(
    kind: str,
    params_cls: type,
    build: Callable[..., MeshInfo],
    argv: Sequence[str] | None = None,
) -> int:
    """``python -m geometry.KIND --out DIR --set key=value ...``: write ``KIND.msh`` + ``info.json``."""
    ap = argparse.ArgumentParser(prog=f"python -m geometry.{kind.replace('-', '_')}")
    ap.add_argument("--out", default=f"results/meshes/{kind}", help="output folder")
    ap.add_argument("--name", default=None, help=f"mesh file stem (default {kind})")
    ap.add_argument(
        "--set", action="append", default=[], metavar="KEY=VALUE",
        help="override a parameter (dotted keys for nested ones); repeatable",
    )  # fmt: skip
    ap.add_argument("-v", "--verbose", action="store_true", help="show Gmsh's log")
    args = ap.parse_args(argv)
    try:
        params = from_mapping(params_cls, parse_overrides(args.set))
        with gmsh_session(args.verbose):
            info = build(params)
            path = save(info, args.out, args.name)
    except ParameterError as e:
        print(f"{kind}: parameter error: {e}", file=sys.stderr)
        return 2
    print(
        f"{path}: {info.num_cells} cells, {info.num_nodes} nodes, "
        f"built in {info.build_time_s:.2f} s; groups {', '.join(info.facet_groups)}"
    )
    return 0
