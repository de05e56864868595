"""Gmsh builders (gmsh + numpy only): groups, closed-form measures, sizes, periodicity.

Measures are compared with closed forms (disc segment, spherical cap, Green's
theorem on the exact lip profile, Pappus for revolved bodies).  The meshes are
linear, with every boundary node on the exact geometry, so the only difference
is the polygonal approximation of curved boundaries, which the tests bound
explicitly: a chord of length l on a circle of radius rho misses the circular
segment ``rho²/2 (theta - sin theta)``, ``theta = 2 asin(l / 2 rho)`` (about
``l³ / 12 rho``), and a triangle inscribed in a surface of curvature kappa with
circumradius c misses at most ``area * kappa c² / 2`` of volume.  2D areas are
then checked to round-off after adding the segments back; 3D volumes within
the bound.

All tests run on one rank (Gmsh runs on rank 0 only in this project).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import gmsh
import numpy as np
import pytest

from dolfinx_seal.errors import ParameterError
from geometry import gmsh_session, mesh_arrays, tags
from geometry._common import Arc, Line, loop_moments
from geometry.ball import BallParams, build_ball
from geometry.cylinder import CylinderParams, build_cylinder
from geometry.lip import LipGeometry, LipSealParams, build_lip
from geometry.lip_sector import LipSectorParams, build_lip_sector

pytestmark = pytest.mark.skip_in_parallel

BUILDERS = {
    "cylinder": build_cylinder,
    "ball": build_ball,
    "lip": build_lip,
    "lip-sector": build_lip_sector,
}

# small meshes for the tests
SMALL: dict[str, dict[str, Any]] = {
    "cylinder": {"h_contact": 30e-6, "h_arc": 100e-6, "h_far": 2e-3},
    "ball": {"h_contact": 0.3e-3, "h_cap": 0.6e-3, "h_far": 2.5e-3, "growth": 0.4},
    "lip": {"h_contact": 10e-6, "h_far": 0.4e-3},
    "lip-sector": {"elements_per_wavelength": 2.0, "h_far": 100e-6, "growth": 0.5},
}


@dataclass
class Built:
    info: Any
    x: np.ndarray
    groups: dict[str, np.ndarray]
    names: dict[tuple[int, int], str]
    periodic: tuple[np.ndarray, np.ndarray] | None = None


@lru_cache(maxsize=32)
def _build(kind: str, items: tuple[tuple[str, Any], ...]) -> Built:
    with gmsh_session():
        info = BUILDERS[kind](**dict(items))
        x, groups = mesh_arrays(info)
        names = {
            (d, t): gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()
        }
        periodic = None
        if kind == "lip-sector":
            (right,) = info.entities["periodic_right"]
            _, slave, master, _ = gmsh.model.mesh.getPeriodicNodes(2, right, True)
            tags_, coords, _ = gmsh.model.mesh.getNodes()
            lookup = dict(zip(tags_.tolist(), coords.reshape(-1, 3), strict=True))
            periodic = (
                np.array([lookup[t] for t in slave.tolist()]),
                np.array([lookup[t] for t in master.tolist()]),
            )
    return Built(info, x, groups, names, periodic)


def build(kind: str, **overrides: Any) -> Built:
    """Build (cached) a small mesh of ``kind`` with ``overrides`` on top of :data:`SMALL`."""
    kw = {**SMALL[kind], **overrides}
    return _build(kind, tuple(sorted(kw.items())))


# ------------------------------------------------------------------ helpers
def tri_areas(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    return 0.5 * np.linalg.norm(np.cross(x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]), axis=1)


def tet_volumes(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    a, b, c = (x[t[:, i]] - x[t[:, 0]] for i in (1, 2, 3))
    return abs(np.einsum("ij,ij->i", np.cross(a, b), c)) / 6.0


def edge_lengths(x: np.ndarray, e: np.ndarray) -> np.ndarray:
    """Lengths of segments (k, 2) or of the three edges of triangles (k, 3)."""
    if e.shape[1] == 2:
        return np.linalg.norm(x[e[:, 1]] - x[e[:, 0]], axis=1)
    return np.linalg.norm(x[e[:, [1, 2, 0]]] - x[e], axis=2).ravel()


def arc_edges(x: np.ndarray, e: np.ndarray, centre: Any, radius: float) -> np.ndarray:
    """The segments of ``e`` whose two ends lie on the circle (centre, radius)."""
    c = np.asarray(centre, dtype=float)
    d = np.linalg.norm(x[e][:, :, : len(c)] - c, axis=2)
    return e[np.all(abs(d - radius) < 1e-9 * radius, axis=1)]


def boundary_edges(t: np.ndarray) -> np.ndarray:
    """Edges of a triangle set that belong to one triangle only."""
    e = np.sort(np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    return uniq[count == 1]


def segment_sag(x: np.ndarray, e: np.ndarray, radius: float) -> np.ndarray:
    """Area between each chord and its circular arc."""
    theta = 2 * np.arcsin(np.clip(edge_lengths(x, e) / (2 * radius), 0, 1))
    return 0.5 * radius**2 * (theta - np.sin(theta))


def circumradius(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    a, b, c = (np.linalg.norm(x[t[:, i]] - x[t[:, j]], axis=1) for i, j in ((0, 1), (1, 2), (2, 0)))
    return a * b * c / (4 * tri_areas(x, t))


def facet_measure(b: Built, name: str) -> float:
    e = b.groups[name]
    return float(edge_lengths(b.x, e).sum() if b.info.tdim == 2 else tri_areas(b.x, e).sum())


def cell_measure(b: Built) -> float:
    t = b.groups["body"]
    return float(tri_areas(b.x, t).sum() if b.info.tdim == 2 else tet_volumes(b.x, t).sum())


# ------------------------------------------------------------ groups exist
EXPECTED = [
    ("cylinder", {"shape": "segment"}, {"contact", "load", "free"}),
    ("cylinder", {"shape": "disc"}, {"contact", "load", "free"}),
    ("cylinder", {"shape": "half"}, {"contact", "load", "free", "symmetry"}),
    ("ball", {}, {"contact", "load", "free", "symmetry"}),
    ("ball", {"shape": "full"}, {"contact", "load", "free"}),
    ("ball", {"height_ratio": 2.0}, {"contact", "load", "free", "symmetry"}),
    ("lip", {}, {"contact", "oil_side", "air_side", "spring_groove", "clamped"}),
    (
        "lip-sector",
        {},
        {"contact", "oil_side", "air_side", "cut", "periodic_left", "periodic_right"},
    ),
]


@pytest.mark.parametrize(("kind", "kw", "expected"), EXPECTED)
def test_every_group_exists_named_and_non_empty(kind, kw, expected):
    b = build(kind, **kw)
    assert set(b.info.facet_groups) == expected
    td = b.info.tdim
    assert b.names[(td, tags.BODY)] == "body"
    assert len(b.groups["body"]) == b.info.num_cells > 0
    # every node belongs to a cell (no orphan construction points)
    assert len(np.unique(b.groups["body"])) == len(b.x) == b.info.num_nodes
    for name in expected:
        number = tags.FACET_GROUPS[name]
        assert b.info.facet_groups[name] == number
        assert b.names[(td - 1, number)] == name, "physical group must carry its name"
        assert len(b.groups[name]) == b.info.num_facets[name] > 0


def test_tag_numbers_are_unique_and_named():
    assert len(set(tags.ALL.values())) == len(tags.ALL)
    assert all(tags.NAMES[tags.number(n)] == n for n in tags.ALL)
    with pytest.raises(KeyError, match="unknown physical group"):
        tags.number("nope")


# ---------------------------------------------------- geometric classification
def test_cylinder_groups_follow_the_geometry():
    b = build("cylinder", shape="half")
    p, x = b.info.params, b.info.extra
    R, H = p.radius, p.height
    on_circle = lambda n: np.allclose(np.hypot(b.x[n, 0], b.x[n, 1] - R), R, atol=1e-9 * R)  # noqa: E731
    c = np.unique(b.groups["contact"])
    assert on_circle(c)
    assert b.x[c, 0].min() >= -1e-12 and b.x[c, 0].max() <= x["arc_ends"][1] * (1 + 1e-9)
    assert np.allclose(b.x[np.unique(b.groups["load"]), 1], H)
    assert np.allclose(b.x[np.unique(b.groups["symmetry"]), 0], 0.0, atol=1e-12)
    assert on_circle(np.unique(b.groups["free"]))


def test_ball_groups_follow_the_geometry():
    b = build("ball")
    p = b.info.params
    R = p.radius
    c = np.unique(b.groups["contact"])
    assert np.allclose(np.linalg.norm(b.x[c] - [0, 0, R], axis=1), R, rtol=1e-9)
    assert np.hypot(b.x[c, 0], b.x[c, 1]).max() <= p.cap_radius * (1 + 1e-9)
    assert np.allclose(b.x[np.unique(b.groups["symmetry"]), 1], 0.0, atol=1e-12)
    assert np.allclose(b.x[np.unique(b.groups["load"]), 2], p.height)
    assert b.x[:, 1].min() >= -1e-12, "half ball is y >= 0"


def test_lip_groups_follow_the_geometry():
    b = build("lip")
    p = b.info.params
    g = LipGeometry(p)
    r, z = b.x[:, 0], b.x[:, 1]
    c = np.unique(b.groups["contact"])
    assert z[c].min() == pytest.approx(-p.band_oil) and z[c].max() == pytest.approx(p.band_air)
    r0 = p.shaft_radius - p.interference  # the innermost point, a node or not
    assert r0 * (1 - 1e-14) <= r[c].min() <= r0 + p.h_contact**2 / p.tip_radius
    assert np.allclose(r[np.unique(b.groups["clamped"])], p.outer_radius)
    s = np.unique(b.groups["spring_groove"])
    assert np.allclose(np.hypot(r[s] - g.Gc[0], z[s] - g.Gc[1]), p.groove_radius, rtol=1e-9)
    # oil side below the lip midline, air side above (edge midpoints)
    for name, sign in (("oil_side", -1), ("air_side", 1)):
        mid = 0.5 * (b.x[b.groups[name][:, 0]] + b.x[b.groups[name][:, 1]])
        assert np.all(sign * (mid[:, 1] - g.midline_z(mid[:, 0])) > 0), name


def test_sector_groups_follow_the_geometry():
    b = build("lip-sector")
    p, th = b.info.params, b.info.extra["angle"]
    r = np.hypot(b.x[:, 0], b.x[:, 1])
    phi = np.arctan2(b.x[:, 1], b.x[:, 0])
    assert np.allclose(phi[np.unique(b.groups["periodic_left"])], -th / 2, atol=1e-12)
    assert np.allclose(phi[np.unique(b.groups["periodic_right"])], th / 2, atol=1e-12)
    assert np.allclose(r[np.unique(b.groups["cut"])], p.cut_radius, rtol=1e-12)
    c = np.unique(b.groups["contact"])
    z = b.x[c, 2]
    assert z.min() == pytest.approx(-p.lip.band_oil) and z.max() == pytest.approx(p.lip.band_air)
    assert th == pytest.approx(p.roughness_wavelength / p.lip.shaft_radius)


# ----------------------------------------------------------- closed forms
def test_loop_moments_of_simple_shapes():
    disc = [
        Arc((1.0, 0.0), (0.0, 1.0), (0.0, 0.0)),
        Arc((0.0, 1.0), (-1.0, 0.0), (0.0, 0.0)),
        Arc((-1.0, 0.0), (0.0, -1.0), (0.0, 0.0)),
        Arc((0.0, -1.0), (1.0, 0.0), (0.0, 0.0)),
    ]
    m = loop_moments(disc)
    assert m["area"] == pytest.approx(math.pi, rel=1e-14)
    assert abs(m["cx"]) < 1e-14 and abs(m["cy"]) < 1e-14
    rect = [Line((1, 0), (3, 0)), Line((3, 0), (3, 2)), Line((3, 2), (1, 2)), Line((1, 2), (1, 0))]
    m = loop_moments(rect[::-1])  # either orientation
    assert m["area"] == pytest.approx(4.0) and m["cx"] == pytest.approx(2.0)
    # Pappus: torus of minor radius 1 about an axis 3 away has volume 2 pi 3 * pi
    shifted = [Arc((a.p[0] + 3, a.p[1]), (a.q[0] + 3, a.q[1]), (3.0, 0.0)) for a in disc]
    assert 2 * math.pi * loop_moments(shifted)["mx"] == pytest.approx(6 * math.pi**2)


@pytest.mark.parametrize(
    ("shape", "height_ratio"),
    [("disc", 1.0), *((s, h) for s in ("segment", "half") for h in (0.6, 1.0, 1.5))],
)
def test_cylinder_area_against_disc_segment(shape, height_ratio):
    b = build("cylinder", shape=shape, height_ratio=height_ratio)
    p, R = b.info.params, b.info.params.radius
    H = p.height
    d = R - H
    exact = (
        math.pi * R * R
        if shape == "disc"
        else R * R * math.acos(d / R) - d * math.sqrt(R * R - d * d)
    )
    if shape == "half":
        exact /= 2
    assert b.info.reference["area"] == pytest.approx(exact, rel=1e-14)
    arcs = np.vstack([b.groups[n] for n in ("contact", "free", "load") if n in b.groups])
    arcs = arc_edges(b.x, arcs, (0.0, R), R)
    sag = segment_sag(b.x, arcs, R).sum()
    area = cell_measure(b)
    assert 0 < exact - area < 1.0001 * sag  # polygon inscribed in the circle
    assert area + sag == pytest.approx(exact, rel=1e-11)
    # contact arc length: chords -> arcs exactly
    e = b.groups["contact"]
    arc_len = (2 * R * np.arcsin(edge_lengths(b.x, e) / (2 * R))).sum()
    assert arc_len == pytest.approx(b.info.reference["length_contact"], rel=1e-11, abs=0)


@pytest.mark.parametrize(
    ("kw", "exact"),
    [
        ({"height_ratio": 2.0}, 2 / 3 * math.pi),  # half ball: 2/3 pi R^3
        ({"height_ratio": 1.0}, 1 / 3 * math.pi),  # quarter ball (half of a hemisphere)
        ({"height_ratio": 1.0, "shape": "full"}, 2 / 3 * math.pi),  # hemisphere
        ({"height_ratio": 0.6}, math.pi * 0.36 * 2.4 / 6),  # half of the cap pi H^2 (3R - H) / 3
    ],
)
def test_ball_volume_against_closed_form(kw, exact):
    b = build("ball", **kw)
    R = b.info.params.radius
    exact *= R**3
    assert b.info.reference["volume"] == pytest.approx(exact, rel=1e-14)
    sphere = np.vstack([b.groups["contact"], b.groups["free"]])
    if b.info.params.height_ratio == 2.0:
        sphere = np.vstack([sphere, b.groups["load"]])
    c = circumradius(b.x, sphere)
    a = tri_areas(b.x, sphere)
    bound = (a * c**2 / (2 * R)).sum()  # max sag kappa c^2 / 2, kappa = 1 / R
    estimate = (a * 3 * c**2 / (8 * R)).sum()  # mean sag over an equilateral triangle
    deficit = exact - cell_measure(b)
    assert 0.3 * estimate < deficit < 1.2 * bound


def test_ball_flat_faces_against_closed_forms():
    b = build("ball", height_ratio=0.8)
    p, R, H = b.info.params, b.info.params.radius, b.info.params.height
    ref = b.info.reference
    # symmetry face: circle segment of height H in y = 0; load face: half disc of radius w
    w = math.sqrt(R * R - (R - H) ** 2)
    for name, centre, radius in (("symmetry", (0, 0, R), R), ("load", (0, 0, H), w)):
        rim = arc_edges(b.x, boundary_edges(b.groups[name]), centre, radius)
        sag = segment_sag(b.x, rim, radius).sum()
        assert facet_measure(b, name) + sag == pytest.approx(ref[f"area_{name}"], rel=1e-10)
    assert ref["area_load"] == pytest.approx(0.5 * math.pi * w * w)
    assert ref["area_contact"] == pytest.approx(math.pi * R * p.cap_height)


def test_lip_area_and_pappus_volume():
    b = build("lip")
    p = b.info.params
    g = LipGeometry(p)
    ref = b.info.reference
    tri = b.groups["body"]
    a = tri_areas(b.x, tri)
    area = a.sum()
    first_moment = (a * b.x[tri, 0].mean(axis=1)).sum()  # ∫ r dA, exact per triangle
    edges = np.vstack([b.groups["contact"], b.groups["spring_groove"]])
    tip = arc_edges(b.x, edges, g.C, p.tip_radius)
    groove = arc_edges(b.x, edges, g.Gc, p.groove_radius)
    assert len(tip) > 10 and len(groove) == len(b.groups["spring_groove"])
    s_tip, s_groove = segment_sag(b.x, tip, p.tip_radius), segment_sag(b.x, groove, p.groove_radius)
    # tip arc is convex (mesh misses area), the groove concave (mesh has extra area)
    assert area + s_tip.sum() - s_groove.sum() == pytest.approx(ref["area"], rel=1e-11)
    r_tip = b.x[tip, 0].mean(axis=1)
    r_gr = b.x[groove, 0].mean(axis=1)
    corrected = first_moment + (s_tip * r_tip).sum() - (s_groove * r_gr).sum()
    slack = (s_tip * edge_lengths(b.x, tip)).sum() + (s_groove * edge_lengths(b.x, groove)).sum()
    assert abs(corrected - ref["first_moment_r"]) <= slack + 1e-12 * ref["first_moment_r"]
    # Pappus: revolved volume = 2 pi * centroid radius * area
    assert ref["volume_revolved"] == pytest.approx(2 * math.pi * ref["centroid_r"] * ref["area"])
    # group lengths: straight groups exact, arcs up to the chord-arc difference
    for name in ("clamped", "oil_side", "air_side"):
        assert facet_measure(b, name) == pytest.approx(ref[f"length_{name}"], rel=1e-12)


def test_sector_volume_by_pappus_and_faces():
    b = build("lip-sector")
    p, th = b.info.params, b.info.extra["angle"]
    ref = b.info.reference
    g = LipGeometry(p.lip)
    # volume = angle * ∫ r dA of the section (Pappus), up to the polygonal error
    tri = np.vstack([b.groups[n] for n in ("contact", "oil_side", "air_side", "cut")])
    kappa = np.full(len(tri), 1.0 / g.r0)  # revolved lines: curvature <= 1 / r
    xy = b.x[tri]
    rz = np.column_stack([np.hypot(xy[..., 0], xy[..., 1]).ravel(), xy[..., 2].ravel()])
    on_tip = np.all(
        (abs(np.hypot(rz[:, 0] - g.C[0], rz[:, 1] - g.C[1]) - p.lip.tip_radius) < 1e-9).reshape(
            -1, 3
        ),
        axis=1,
    )
    kappa[on_tip] = 1.0 / p.lip.tip_radius
    bound = (tri_areas(b.x, tri) * kappa * circumradius(b.x, tri) ** 2 / 2).sum()
    assert ref["volume"] == pytest.approx(th * ref["centroid_r"] * ref["area_section"], rel=1e-13)
    assert abs(cell_measure(b) - ref["volume"]) < 1.2 * bound
    assert bound < 1e-3 * ref["volume"]
    # the periodic faces are plane: their area is exact once the tip segments are added
    for name in ("periodic_left", "periodic_right"):
        edges = boundary_edges(b.groups[name])
        e_rz = np.stack([np.hypot(b.x[edges, 0], b.x[edges, 1]), b.x[edges, 2]], axis=-1)
        d = np.hypot(e_rz[..., 0] - g.C[0], e_rz[..., 1] - g.C[1])
        tip = edges[np.all(abs(d - p.lip.tip_radius) < 1e-9 * p.lip.tip_radius, axis=1)]
        sag = segment_sag(b.x, tip, p.lip.tip_radius).sum()
        assert facet_measure(b, name) + sag == pytest.approx(ref["area_section"], rel=1e-10)


# ------------------------------------------------------------ element sizes
def test_cylinder_contact_element_size():
    b = build("cylinder")
    p = b.info.params
    e = b.groups["contact"]
    ell = edge_lengths(b.x, e)
    xm = abs(b.x[e, 0].mean(axis=1))
    fine = ell[xm < p.fine_extent * p.contact_half_width - p.h_contact]
    assert len(fine) >= 2 * p.fine_extent * p.contact_half_width / p.h_contact * 0.9
    assert fine.mean() == pytest.approx(p.h_contact, rel=0.1)
    assert fine.max() < 1.25 * p.h_contact
    assert ell.max() < 1.25 * p.h_arc


def test_lip_contact_element_size():
    b = build("lip")
    p = b.info.params
    ell = edge_lengths(b.x, b.groups["contact"])
    assert ell.mean() == pytest.approx(p.h_contact, rel=0.1)
    assert ell.max() < 1.25 * p.h_contact
    assert edge_lengths(b.x, b.groups["clamped"]).max() < 1.25 * p.h_far


def test_ball_contact_element_size():
    b = build("ball")
    p = b.info.params
    t = b.groups["contact"]
    rho = np.hypot(*b.x[t].mean(axis=1)[:, :2].T)
    fine = edge_lengths(b.x, t[rho < 0.8 * p.fine_extent * p.contact_radius])
    assert fine.mean() == pytest.approx(p.h_contact, rel=0.2)
    assert np.percentile(fine, 95) < 1.5 * p.h_contact
    assert np.percentile(edge_lengths(b.x, t), 95) < 1.5 * p.h_cap


def test_ball_rim_band_is_refined_and_the_rest_is_not():
    base = build("ball")
    b = build("ball", h_rim=0.15e-3)
    p = b.info.params
    a = p.contact_radius

    def sizes(built, lo, hi):
        t = built.groups["contact"]
        rho = np.hypot(*built.x[t].mean(axis=1)[:, :2].T) / a
        return edge_lengths(built.x, t[(rho > lo) & (rho < hi)])

    # inside the band, away from its edges (the size grows by `growth` outside it)
    rim = sizes(b, p.rim_inner + 0.05, p.rim_outer - 0.05)
    assert rim.mean() == pytest.approx(p.h_rim, rel=0.2)
    assert sizes(base, p.rim_inner + 0.05, p.rim_outer - 0.05).mean() == pytest.approx(
        p.h_contact, rel=0.2
    )
    # the centre keeps h_contact
    assert sizes(b, 0.0, 0.5).mean() == pytest.approx(p.h_contact, rel=0.2)


def test_sector_band_element_size():
    b = build("lip-sector")
    h = b.info.extra["h_band"]
    ell = edge_lengths(b.x, b.groups["contact"])
    assert ell.mean() == pytest.approx(h, rel=0.2)
    assert np.percentile(ell, 95) < 1.5 * h
    # the band resolves the shortest deterministic wavelength
    p = b.info.params
    assert h == pytest.approx(p.roughness_wavelength / p.q_ratio / p.elements_per_wavelength)


@pytest.mark.parametrize(
    ("kind", "name", "kw"),
    [("cylinder", "h_contact", {}), ("lip", "h_contact", {}), ("ball", "h_contact", {})],
)
def test_mesh_size_halves_with_the_parameter(kind, name, kw):
    def fine_edges(b: Built) -> np.ndarray:
        p = b.info.params
        e = b.groups["contact"]
        if kind == "cylinder":
            keep = abs(b.x[e, 0].mean(axis=1)) < p.fine_extent * p.contact_half_width
        elif kind == "ball":
            keep = np.hypot(*b.x[e].mean(axis=1)[:, :2].T) < 0.8 * p.fine_extent * p.contact_radius
        else:
            keep = np.ones(len(e), dtype=bool)
        return edge_lengths(b.x, e[keep])

    h = SMALL[kind][name]
    coarse, fine = build(kind, **{name: h}), build(kind, **{name: h / 2})
    ratio = fine_edges(fine).mean() / fine_edges(coarse).mean()
    assert ratio == pytest.approx(0.5, abs=0.05)


def test_sector_band_size_halves_with_the_wavelength_resolution():
    coarse = build("lip-sector")
    fine = build("lip-sector", elements_per_wavelength=4.0)
    ratio = (
        edge_lengths(fine.x, fine.groups["contact"]).mean()
        / edge_lengths(coarse.x, coarse.groups["contact"]).mean()
    )
    assert ratio == pytest.approx(0.5, abs=0.06)


# ------------------------------------------------------------- periodicity
@pytest.mark.parametrize("order", [1, 2])
def test_sector_periodic_faces_match_node_to_node(order):
    b = build("lip-sector", order=order)
    th = b.info.extra["angle"]
    T = np.asarray(b.info.extra["periodic_transform"]).reshape(4, 4)
    left = b.x[np.unique(b.groups["periodic_left"])]
    right = b.x[np.unique(b.groups["periodic_right"])]
    assert len(left) == len(right) > 0
    rotated = left @ T[:3, :3].T
    assert np.allclose(
        T[:3, :3], [[math.cos(th), -math.sin(th), 0], [math.sin(th), math.cos(th), 0], [0, 0, 1]]
    )
    # nearest right node of every rotated left node: a bijection at round-off distance
    d2 = ((rotated[:, None, :] - right[None, :, :]) ** 2).sum(axis=2)
    nearest = d2.argmin(axis=1)
    assert len(np.unique(nearest)) == len(right)
    assert np.sqrt(d2.min(axis=1)).max() < 1e-9 * b.info.extra["h_band"]
    # Gmsh's own periodic map (all nodes, including second-order ones) agrees
    slave, master = b.periodic
    assert np.allclose(slave, master @ T[:3, :3].T, rtol=0, atol=1e-9 * b.info.extra["h_band"])
    assert np.allclose(np.arctan2(slave[:, 1], slave[:, 0]), th / 2, atol=1e-12)


# -------------------------------------------------------------- validation
@pytest.mark.parametrize(
    ("cls", "kw", "name"),
    [
        (CylinderParams, {"radius": -1.0}, "radius"),
        (CylinderParams, {"shape": "square"}, "shape"),
        (CylinderParams, {"h_contact": 0.2e-3}, "h_contact"),
        (CylinderParams, {"contact_upstream": 40.0}, "contact_upstream"),
        (CylinderParams, {"order": 3}, "order"),
        (BallParams, {"cap_extent": 10.0}, "cap_extent"),
        (BallParams, {"height_ratio": 2.5}, "height_ratio"),
        (BallParams, {"h_far": 5e-3}, "h_far"),
        (BallParams, {"h_rim": 0.2e-3}, "h_rim"),
        (BallParams, {"rim_inner": 1.2, "rim_outer": 1.1}, "rim_outer"),
        (BallParams, {"rim_outer": 2.0}, "rim_outer"),
        (LipSealParams, {"interference": 2e-3}, "interference"),
        (LipSealParams, {"oil_angle": 95.0}, "oil_angle"),
        (LipSealParams, {"air_angle": 0.0}, "air_angle"),
        (LipSealParams, {"tip_radius": 0.0}, "tip_radius"),
        (LipSealParams, {"h_contact": 0.2e-3}, "h_contact"),
        (LipSealParams, {"h_far": 0.8e-3}, "h_far"),
        (LipSealParams, {"spring_offset": 2.5e-3}, "spring_offset"),
        (LipSealParams, {"groove_depth": 2.0e-3}, "groove"),
        (LipSealParams, {"band_air": 5e-3}, "band_air"),
        (LipSealParams, {"housing_width": 3e-3}, "housing_width"),
        (LipSectorParams, {"sector_height": 5e-3}, "sector_height"),
        (LipSectorParams, {"elements_per_wavelength": 1.0}, "elements_per_wavelength"),
        (LipSectorParams, {"h_far": 1e-3}, "h_far"),
    ],
)
def test_bad_parameters_are_named(cls, kw, name):
    with pytest.raises(ParameterError, match=name):
        cls(**kw)


# ------------------------------------------------------- files and the CLI
def test_main_writes_msh_and_info(tmp_path):
    from geometry import cylinder

    rc = cylinder.main(["--out", str(tmp_path), "--set", "h_far=2e-3", "--set", "shape=half"])
    assert rc == 0
    info = json.loads((tmp_path / "info.json").read_text())
    assert info["mesh"] == "cylinder.msh" and info["kind"] == "cylinder"
    assert info["params"]["shape"] == "half" and info["params"]["h_far"] == 2e-3
    assert info["facet_groups"]["symmetry"] == tags.SYMMETRY
    assert {"gmsh", "numpy", "python", "dolfinx_seal"} <= set(info["versions"])
    assert "created" in info and info["num_cells"] > 0
    with gmsh_session():
        gmsh.open(str(tmp_path / "cylinder.msh"))
        names = {gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
    assert names == {"body", "contact", "load", "free", "symmetry"}
    assert cylinder.main(["--out", str(tmp_path), "--set", "radius=-1"]) == 2


def test_lip_sector_nested_override_from_the_cli():
    from dolfinx_seal.params import from_mapping, parse_overrides

    p = from_mapping(LipSectorParams, parse_overrides(["lip.interference=0.4e-3", "periods=2"]))
    assert p.lip.interference == 0.4e-3 and p.angle == pytest.approx(2 * 200e-6 / 40e-3)


def test_geometry_imports_without_dolfinx():
    code = (
        "import sys, geometry, geometry.tags, geometry.cylinder, geometry.ball, geometry.lip, "
        "geometry.lip_sector\n"
        "bad = [m for m in sys.modules if m.split('.')[0] in ('dolfinx', 'petsc4py', 'ufl')]\n"
        "assert not bad, bad"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
