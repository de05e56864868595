"""3D periodic sector of the lip tip (S0 section 3).

The tip region of the lip section (:mod:`geometry.lip`) below the radial cut
``r = r_cut = r0 + sector_height`` is revolved about the shaft axis through the
angle ``theta = periods * roughness_wavelength / shaft_radius``: one period of
the deterministic roughness measured on the shaft, as in S0 (lambda_0 = 200 um,
the largest deterministic wavelength, and ``q_th = 5 q_0``).  In the undeformed
lip the arc length at the tip is ``theta * r0``, slightly less than lambda_0;
after installation the lip tip sits on the shaft and the period is exact.

Coordinates: ``z`` is the shaft axis (axial, oil side ``z < 0``), the sector is
centred on the ``x`` axis, so ``x ~ r`` (radial) and ``y ~ r theta``
(circumferential, the sliding direction) near the tip.  Angles run from
``-theta/2`` to ``+theta/2``.

Groups: ``body`` (cells); facets ``periodic_left`` (``-theta/2``, master),
``periodic_right`` (``+theta/2``, its image by the rotation ``+theta`` about
``z``; the two surface meshes match node for node, as periodic constraints
need), ``cut`` (the cylinder ``r = r_cut`` where the axisymmetric solution is
imposed), ``contact`` (the revolved contact band), ``oil_side`` and
``air_side`` (the rest of the lip faces).

Mesh size: ``h_band = lambda_th / elements_per_wavelength`` on the contact band,
with ``lambda_th = roughness_wavelength / q_ratio`` the shortest deterministic
wavelength, growing by ``growth`` per unit distance up to ``h_far``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import gmsh
import numpy as np

from dolfinx_seal.params import check_int_range, check_positive, check_range
from geometry._common import (
    Line,
    MeshInfo,
    Segment,
    add_loop,
    classify,
    cli_main,
    distance_threshold,
    finish,
    loop_moments,
    mesh_options,
    path_moments,
)
from geometry.lip import LipGeometry, LipSealParams

KIND = "lip-sector"


@dataclass(frozen=True)
class LipSectorParams:
    """Periodic sector of the lip tip (SI units: metres).

    Attributes:
        lip: The lip seal (the sector is cut out of its tip; its contact band is
            the sector's contact band; its mesh sizes are not used).
        roughness_wavelength: lambda_0, the longest deterministic roughness
            wavelength (m); S0 section 3.1: q_0 = 2 pi / 200 um.
        q_ratio: q_th / q_0, the shortest deterministic wavelength is lambda_0 /
            q_ratio (S0: q_th = 5 q_0).
        elements_per_wavelength: Elements per shortest deterministic wavelength on
            the contact band (>= 2; P2 fields need about 4-6).
        periods: Roughness periods in the sector (>= 1).
        sector_height: Radial extent of the sector above the tip, r_cut - r0 (m).
        h_far: Largest element size (m).
        growth: Size increase per unit distance from the band (0 < growth <= 2).
        order: Geometry order of the elements, 1 or 2.
    """

    lip: LipSealParams = field(default_factory=LipSealParams)
    roughness_wavelength: float = 200e-6
    q_ratio: float = 5.0
    elements_per_wavelength: float = 5.0
    periods: int = 1
    sector_height: float = 0.8e-3
    h_far: float = 60e-6
    growth: float = 0.3
    order: int = 1

    def __post_init__(self) -> None:
        if not isinstance(self.lip, LipSealParams):
            raise TypeError("lip must be a LipSealParams")
        lam = check_positive("roughness_wavelength", self.roughness_wavelength, "m")
        check_range("roughness_wavelength", lam, 0.0, 0.05 * self.lip.shaft_radius, unit="m")
        check_range("q_ratio", self.q_ratio, 1.0, 1e3)
        check_range("elements_per_wavelength", self.elements_per_wavelength, 2.0, 100.0)
        check_int_range("periods", self.periods, 1, 100)
        check_range("angle (periods * roughness_wavelength / shaft_radius)", self.angle, 0.0,
                    0.5, lo_open=True, unit="rad")  # fmt: skip
        check_range("growth", self.growth, 0.0, 2.0, lo_open=True)
        check_int_range("order", self.order, 1, 2)
        g = LipGeometry(self.lip)
        lo = g.r_band - g.r0 + 2 * self.h_band
        hi = min(g.O1[0], g.A1[0], g.Gb[0]) - g.r0
        check_range("sector_height", self.sector_height, lo, hi, lo_open=True, hi_open=True,
                    unit="m")  # fmt: skip
        check_range("h_band (roughness_wavelength / q_ratio / elements_per_wavelength)",
                    self.h_band, 0.0, 0.5 * self.lip.tip_radius, lo_open=True, unit="m")  # fmt: skip
        check_range("h_far", self.h_far, self.h_band, 0.5 * self.sector_height, unit="m")

    @property
    def angle(self) -> float:
        """Sector angle theta (rad)."""
        return self.periods * self.roughness_wavelength / self.lip.shaft_radius

    @property
    def h_band(self) -> float:
        """Element size on the contact band (m)."""
        return self.roughness_wavelength / self.q_ratio / self.elements_per_wavelength

    @property
    def cut_radius(self) -> float:
        """Radius of the cut face (m)."""
        return self.lip.tip_r + self.sector_height


def section(p: LipSectorParams) -> tuple[LipGeometry, list[Segment]]:
    """The lip geometry and the closed loop of the tip region below ``r_cut`` (r, z)."""
    g = LipGeometry(p.lip)
    oc, ac = g.oil_at_r(p.cut_radius), g.air_at_r(p.cut_radius)
    band = g.tip_band()  # Ob -> To -> Ta -> Ab
    loop = [Line(g.Ab, ac), Line(ac, oc), Line(oc, g.Ob), *band]
    return g, loop


def rotation(angle: float) -> list[float]:
    """Row-major 4x4 affine matrix of the rotation by ``angle`` about ``z`` (Gmsh layout)."""
    c, s = math.cos(angle), math.sin(angle)
    return [c, -s, 0.0, 0.0, s, c, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]


def reference(p: LipSectorParams) -> dict[str, float]:
    """Closed forms: volume and group areas by Pappus (volume = angle * ∫ r dA).

    Keys: ``volume``, ``area_section`` (each periodic face), ``area_<group>`` for
    ``contact``, ``cut``, ``oil_side``, ``air_side`` (m², m³).
    """
    g, loop = section(p)
    th = p.angle
    m = loop_moments(loop)
    oc, ac = g.oil_at_r(p.cut_radius), g.air_at_r(p.cut_radius)
    paths = {
        "contact": g.tip_band(),
        "cut": [Line(ac, oc)],
        "oil_side": [Line(oc, g.Ob)],
        "air_side": [Line(g.Ab, ac)],
    }
    out = {"volume": th * m["mx"], "area_section": m["area"], "centroid_r": m["cx"]}
    out.update({f"area_{k}": th * path_moments(v)["mx"] for k, v in paths.items()})
    return out


def build_lip_sector(params: LipSectorParams | None = None, **overrides: object) -> MeshInfo:
    """Build the periodic sector model and mesh in a new Gmsh model (Gmsh must be initialised).

    Args:
        params: Parameters (defaults if ``None``).
        **overrides: Fields of :class:`LipSectorParams` to change.

    Returns:
        What was built; ``extra`` holds ``angle`` (rad), ``periodic_transform`` (the
        row-major 4x4 matrix mapping ``periodic_left`` onto ``periodic_right``),
        ``h_band`` and ``cut_radius`` (m).
    """
    t0 = time.perf_counter()
    p = params if params is not None else LipSectorParams()
    if overrides:
        p = dataclasses.replace(p, **overrides)
    g, loop = section(p)
    th, r_cut = p.angle, p.cut_radius
    gmsh.model.add(KIND)
    occ = gmsh.model.occ
    surf, _ = add_loop(loop, plane="xz")
    occ.rotate([(2, surf)], 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, -0.5 * th)
    occ.revolve([(2, surf)], 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, th)
    occ.synchronize()

    tol = 1e-3 * p.h_band

    def on_plane(phi: float) -> Callable[[np.ndarray], bool]:
        n = np.array([-math.sin(phi), math.cos(phi), 0.0])
        return lambda q: bool(abs(q @ n).max() < tol)

    def rz(q: np.ndarray) -> np.ndarray:
        return np.column_stack([np.hypot(q[:, 0], q[:, 1]), q[:, 2]])

    rules = [
        ("periodic_left", on_plane(-0.5 * th)),
        ("periodic_right", on_plane(0.5 * th)),
        ("cut", lambda q: bool(abs(np.hypot(q[:, 0], q[:, 1]) - r_cut).max() < tol)),
    ]
    rules += [(n, lambda q, f=f: f(rz(q))) for n, f in g.rules(tol) if n == "contact"]
    faces = [t for _, t in gmsh.model.getEntities(2)]
    groups = classify(2, faces, rules, default=lambda q: g.side(rz(q)))
    (left,), (right,) = groups["periodic_left"], groups["periodic_right"]
    transform = rotation(th)
    gmsh.model.mesh.setPeriodic(2, [right], [left], transform)

    band_len = max(s.length() for s in g.tip_band())
    n = int(min(max(2 * max(band_len, th * r_cut) / p.h_band + 1, 20), 400))
    fld = distance_threshold(2, groups["contact"], n, p.h_band, p.h_far, p.growth)
    mesh_options(p.h_band, p.h_far, fld)
    extra = {
        "angle": th,
        "periodic_transform": transform,
        "h_band": p.h_band,
        "cut_radius": r_cut,
        "tip_r": g.r0,
    }
    return finish(KIND, p, 3, 3, groups, p.order, t0, reference(p), extra)


PARAMS = LipSectorParams
BUILD = build_lip_sector


def main(argv: list[str] | None = None) -> int:
    """CLI: ``python -m geometry.lip_sector --out DIR --set lip.interference=0.4e-3``."""
    return cli_main(KIND, LipSectorParams, build_lip_sector, argv)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
