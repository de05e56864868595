r"""Radial lip seal, axisymmetric cross-section (S0 figure 3).

The section lives in the (r, z) half-plane, meshed as the Gmsh/DOLFINx plane
``x = r`` (radial), ``y = z`` (axial); the shaft axis is ``x = 0``.  The lip
tip, rounded with ``tip_radius``, is the innermost point of the undeformed seal
at ``(r0, 0)`` with ``r0 = shaft_radius - interference``: the undeformed lip
overlaps the shaft (``r = shaft_radius``) by the radial interference.  The oil
side is ``z < 0``, the air side ``z > 0``.

Profile (letters as in :class:`LipGeometry`; r upwards, z to the right)::

    r
    ^  K0 +-----------------------------------+ K1   clamped (bonded to the metal case)
    |     |             housing               |
    |  B0 +-------------+ B1     B2 +---------+ B3
    |                   |   flex    |
    |  O2 +--- G1   G2 -+ F1        |                head top, spring groove G1..G2
    |     |      \_Gb_/             |
    |  O1 +                         + A1
    |      \  oil face             /   air face
    |    Ob +                  Ab +                  contact band Ob..Ab
    |        \______ tip _______/
    +------------------------------------------------> z (axial)
                 shaft surface r = shaft_radius

Groups: ``body`` (cells); facets ``contact`` (the band from ``z = -band_oil``
to ``z = band_air`` round the tip), ``spring_groove``, ``clamped`` (outer face
``r = r_out``, bonded to the rigid metal case), ``oil_side`` and ``air_side``
(the remaining free surface on either side of the lip).

Defaults describe a standard 80 x 100 x 10 mm radial shaft seal (ISO 6194-1 /
DIN 3760 type A nominal size: shaft diameter 80 mm, bore 100 mm).  The lip
proportions are typical textbook values, not one manufacturer's drawing:
oil-side contact angle 40-60 deg and air-side angle 20-35 deg, the spring
seat offset by a few tenths of a millimetre towards the air side (the
"R-value", which makes the contact pressure peak on the oil side and gives the
pumping action), a sharp moulded or trimmed edge of 0.1 mm radius or less, and
a radial interference of a few tenths of a millimetre (H. K. Muller and B. S.
Nau, *Fluid Sealing Technology: Principles and Applications*, Marcel Dekker,
1998, chapter on rotary lip seals; the SKF and Freudenberg sealing handbooks
give the same ranges).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import gmsh
import numpy as np

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_int_range, check_positive, check_range
from geometry._common import (
    Arc,
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

KIND = "lip"

Point2 = tuple[float, float]


@dataclass(frozen=True)
class LipSealParams:
    """Radial lip seal section and its mesh (SI units: metres, angles in degrees).

    Attributes:
        shaft_radius: Shaft radius R_s (m); default a 80 mm shaft.
        interference: Radial overlap of the undeformed lip tip with the shaft (m).
        oil_angle: Angle between the oil-side face and the shaft axis (deg), in (10, 80).
        air_angle: Angle between the air-side face and the shaft axis (deg), in (5, 80).
        tip_radius: Radius of the rounded lip edge (m).
        oil_face_height: Radial height of the oil-side cone above the tip (m).
        head_height: Radial height of the lip head (tip to the head top) (m).
        head_length: Axial distance from the tip to the air-side back face of the
            head and flex section (m).
        lip_height: Radial distance from the tip to the underside of the housing portion (m).
        lip_thickness: Axial thickness of the flex section (membrane) (m).
        spring_offset: Axial position of the spring-groove centre, from the tip
            towards the air side (the R-value) (m); may be negative.
        groove_radius: Radius of the spring groove (about the spring coil radius) (m).
        groove_depth: Depth of the groove below the head top (m), below 2 * groove_radius.
        housing_height: Radial thickness of the housing portion (m).
        housing_width: Axial width of the housing portion (m).
        housing_offset: Axial position of its oil-side face relative to the tip (m).
        band_oil: Axial extent of the contact band on the oil side of the tip (m).
        band_air: Axial extent of the contact band on the air side of the tip (m).
        h_contact: Element size on the contact band (m); at most tip_radius / 2.
        h_far: Largest element size (m); at most lip_thickness / 2.
        growth: Size increase per unit distance from the band (0 < growth <= 2).
        order: Geometry order of the elements, 1 or 2.
    """

    shaft_radius: float = 40e-3
    interference: float = 0.3e-3
    oil_angle: float = 45.0
    air_angle: float = 25.0
    tip_radius: float = 0.1e-3
    oil_face_height: float = 1.5e-3
    head_height: float = 3.0e-3
    head_length: float = 3.0e-3
    lip_height: float = 6.8e-3
    lip_thickness: float = 1.0e-3
    spring_offset: float = 0.5e-3
    groove_radius: float = 1.2e-3
    groove_depth: float = 0.8e-3
    housing_height: float = 3.5e-3
    housing_width: float = 8.0e-3
    housing_offset: float = -2.0e-3
    band_oil: float = 0.3e-3
    band_air: float = 0.6e-3
    h_contact: float = 5e-6
    h_far: float = 0.3e-3
    growth: float = 0.2
    order: int = 1

    def __post_init__(self) -> None:
        for name in (
            "shaft_radius", "interference", "tip_radius", "oil_face_height", "head_height",
            "head_length", "lip_height", "lip_thickness", "groove_radius", "groove_depth",
            "housing_height", "housing_width", "band_oil", "band_air", "h_contact", "h_far",
        ):  # fmt: skip
            check_positive(name, getattr(self, name), "m")
        check_range("oil_angle", self.oil_angle, 10.0, 80.0, lo_open=True, hi_open=True, unit="deg")
        check_range("air_angle", self.air_angle, 5.0, 80.0, lo_open=True, hi_open=True, unit="deg")
        check_range("growth", self.growth, 0.0, 2.0, lo_open=True)
        check_int_range("order", self.order, 1, 2)
        check_range("oil_face_height", self.oil_face_height, 0.0, self.head_height, lo_open=True,
                    hi_open=True, unit="m")  # fmt: skip
        check_range("interference", self.interference, 0.0, self.oil_face_height, lo_open=True,
                    hi_open=True, unit="m")  # fmt: skip
        check_range("interference", self.interference, 0.0, 0.25 * self.shaft_radius, unit="m")
        check_range("lip_height", self.lip_height, self.head_height, math.inf, lo_open=True,
                    unit="m")  # fmt: skip
        g = LipGeometry(self)
        rho = self.tip_radius
        check_range("band_oil", self.band_oil, rho * math.sin(g.alpha), -g.O1[1], lo_open=True,
                    hi_open=True, unit="m")  # fmt: skip
        hl_max = g.Ta[1] + (g.r_top - g.Ta[0]) / math.tan(g.beta)
        check_range("head_length", self.head_length, 0.0, hl_max, lo_open=True, hi_open=True,
                    unit="m")  # fmt: skip
        check_range("band_air", self.band_air, rho * math.sin(g.beta), self.head_length,
                    lo_open=True, hi_open=True, unit="m")  # fmt: skip
        check_range("lip_thickness", self.lip_thickness, 0.0, self.head_length - g.O1[1],
                    lo_open=True, hi_open=True, unit="m")  # fmt: skip
        check_range("groove_depth", self.groove_depth, 0.0, 2 * self.groove_radius, lo_open=True,
                    hi_open=True, unit="m")  # fmt: skip
        w = g.groove_half_chord
        check_range("spring_offset", self.spring_offset, g.O1[1] + w, g.z_flex0 - w,
                    lo_open=True, hi_open=True, unit="m")  # fmt: skip
        for what, d in (
            ("the oil-side face", g.distance_to_oil_face(g.Gc)),
            ("the air-side face", g.distance_to_air_face(g.Gc)),
            ("the lip midline (tip to flex section)", _distance_to_segment(g.Gc, g.C, g.P2)),
        ):
            if d <= self.groove_radius:
                raise ParameterError(
                    f"groove_depth = {self.groove_depth!r} m with groove_radius = "
                    f"{self.groove_radius!r} m and spring_offset = {self.spring_offset!r} m: the "
                    f"spring groove reaches {what} (centre {d:g} m away, radius larger); make "
                    "the groove shallower or smaller"
                )
        check_range("housing_offset", self.housing_offset, -math.inf, g.z_flex0, hi_open=True,
                    unit="m")  # fmt: skip
        check_range("housing_width", self.housing_width, self.head_length - self.housing_offset,
                    math.inf, lo_open=True, unit="m")  # fmt: skip
        check_range("h_contact", self.h_contact, 0.0, 0.5 * rho, lo_open=True, unit="m")
        check_range("h_far", self.h_far, self.h_contact,
                    0.5 * min(self.lip_thickness, self.groove_radius), unit="m")  # fmt: skip

    @property
    def tip_r(self) -> float:
        """Radius r0 of the undeformed lip tip (m)."""
        return self.shaft_radius - self.interference

    @property
    def outer_radius(self) -> float:
        """Radius of the clamped outer face (m)."""
        return self.tip_r + self.lip_height + self.housing_height


def _distance_to_segment(x: Point2, a: Point2, b: Point2) -> float:
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    t = min(max(((x[0] - ax) * dx + (x[1] - ay) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
    return math.hypot(x[0] - ax - t * dx, x[1] - ay - t * dy)


class LipGeometry:
    """Named points of the lip profile (r, z), derived from :class:`LipSealParams`.

    See the module docstring for the letters.  ``C`` is the centre of the tip
    arc, ``To``/``Ta`` its tangent points on the oil/air faces, ``Ob``/``Ab`` the
    ends of the contact band, ``Gc`` the groove centre, ``P2`` the point where the
    lip midline (used to tell the oil side from the air side) enters the flex section.
    """

    def __init__(self, p: LipSealParams) -> None:
        self.p = p
        a, b, rho = math.radians(p.oil_angle), math.radians(p.air_angle), p.tip_radius
        self.alpha, self.beta = a, b
        r0 = p.tip_r
        self.r0 = r0
        self.C = (r0 + rho, 0.0)
        self.To = (r0 + rho - rho * math.cos(a), -rho * math.sin(a))
        self.Ta = (r0 + rho - rho * math.cos(b), rho * math.sin(b))
        self.r_top = r0 + p.head_height
        self.O1 = self.oil_at_r(r0 + p.oil_face_height)
        self.O2 = (self.r_top, self.O1[1])
        self.Ob = self.oil_at_z(-p.band_oil)
        self.Ab = self.air_at_z(p.band_air)
        self.A1 = self.air_at_z(p.head_length)
        self.z_back = p.head_length
        self.z_flex0 = p.head_length - p.lip_thickness
        self.z_mid = p.head_length - 0.5 * p.lip_thickness
        rg = p.groove_radius
        d = rg - p.groove_depth  # centre above the head top by d
        self.Gc = (self.r_top + d, p.spring_offset)
        self.groove_half_chord = math.sqrt(max(rg * rg - d * d, 0.0))
        w = self.groove_half_chord
        self.G1 = (self.r_top, p.spring_offset - w)
        self.G2 = (self.r_top, p.spring_offset + w)
        self.Gb = (self.Gc[0] - rg, p.spring_offset)
        self.F1 = (self.r_top, self.z_flex0)
        self.r_b = r0 + p.lip_height
        self.r_out = p.outer_radius
        zh0, zh1 = p.housing_offset, p.housing_offset + p.housing_width
        self.B1, self.B0 = (self.r_b, self.z_flex0), (self.r_b, zh0)
        self.K0, self.K1 = (self.r_out, zh0), (self.r_out, zh1)
        self.B3, self.B2 = (self.r_b, zh1), (self.r_b, self.z_back)
        self.P2 = (self.r_top, self.z_mid)
        self.r_band = max(self.Ob[0], self.Ab[0])

    # faces as functions of r or z
    def oil_at_z(self, z: float) -> Point2:
        """Point of the oil-side face line at axial position ``z``."""
        s = (self.To[1] - z) / math.cos(self.alpha)
        return (self.To[0] + s * math.sin(self.alpha), z)

    def oil_at_r(self, r: float) -> Point2:
        """Point of the oil-side face line at radius ``r``."""
        s = (r - self.To[0]) / math.sin(self.alpha)
        return (r, self.To[1] - s * math.cos(self.alpha))

    def air_at_z(self, z: float) -> Point2:
        """Point of the air-side face line at axial position ``z``."""
        s = (z - self.Ta[1]) / math.cos(self.beta)
        return (self.Ta[0] + s * math.sin(self.beta), z)

    def air_at_r(self, r: float) -> Point2:
        """Point of the air-side face line at radius ``r``."""
        s = (r - self.Ta[0]) / math.sin(self.beta)
        return (r, self.Ta[1] + s * math.cos(self.beta))

    def distance_to_oil_face(self, x: Point2) -> float:
        """Distance from ``x`` to the (infinite) oil-side face line."""
        n = (-math.cos(self.alpha), -math.sin(self.alpha))
        return abs((x[0] - self.To[0]) * n[0] + (x[1] - self.To[1]) * n[1])

    def distance_to_air_face(self, x: Point2) -> float:
        """Distance from ``x`` to the (infinite) air-side face line."""
        n = (-math.cos(self.beta), math.sin(self.beta))
        return abs((x[0] - self.Ta[0]) * n[0] + (x[1] - self.Ta[1]) * n[1])

    # profile pieces
    def tip_band(self) -> list[Segment]:
        """The contact band, from the oil-side end over the tip to the air-side end."""
        return [Line(self.Ob, self.To), Arc(self.To, self.Ta, self.C), Line(self.Ta, self.Ab)]

    def profile(self) -> list[Segment]:
        """The closed boundary of the section (lines and circular arcs)."""
        return [
            Line(self.To, self.Ob), Line(self.Ob, self.O1), Line(self.O1, self.O2),
            Line(self.O2, self.G1), Arc(self.G1, self.Gb, self.Gc), Arc(self.Gb, self.G2, self.Gc),
            Line(self.G2, self.F1), Line(self.F1, self.B1), Line(self.B1, self.B0),
            Line(self.B0, self.K0), Line(self.K0, self.K1), Line(self.K1, self.B3),
            Line(self.B3, self.B2), Line(self.B2, self.A1), Line(self.A1, self.Ab),
            Line(self.Ab, self.Ta), Arc(self.Ta, self.To, self.C),
        ]  # fmt: skip

    def midline_z(self, r: np.ndarray) -> np.ndarray:
        """Axial position of the lip midline at radius ``r``: oil side below, air side above.

        The midline runs from the tip-arc centre to the middle of the flex section
        at the head top, then radially out through the flex and housing.
        """
        rr = [self.C[0] - 1.0, self.C[0], self.P2[0], self.r_out + 1.0]
        zz = [0.0, 0.0, self.z_mid, self.z_mid]
        return np.interp(r, rr, zz)

    # geometric classification, shared by the mesh and the closed forms
    def rules(self, tol: float) -> list[tuple[str, Callable[[np.ndarray], bool]]]:
        """Ordered (group, predicate) rules on (r, z) points (first match wins)."""
        p = self.p

        def contact(q: np.ndarray) -> bool:
            return bool(
                q[:, 0].max() < self.r_band + tol
                and q[:, 1].min() > -p.band_oil - tol
                and q[:, 1].max() < p.band_air + tol
            )

        def clamped(q: np.ndarray) -> bool:
            return bool(q[:, 0].min() > self.r_out - tol)

        def groove(q: np.ndarray) -> bool:
            d = np.hypot(q[:, 0] - self.Gc[0], q[:, 1] - self.Gc[1])
            return bool(abs(d - p.groove_radius).max() < tol)

        return [("contact", contact), ("clamped", clamped), ("spring_groove", groove)]

    def side(self, q: np.ndarray) -> str:
        """``"oil_side"`` or ``"air_side"`` for the points of a free-surface entity."""
        mid = q[len(q) // 2]
        return "oil_side" if mid[1] < float(self.midline_z(mid[0])) else "air_side"


def classify_segments(g: LipGeometry, segments: list[Segment], tol: float) -> dict[str, list]:
    """Sort exact profile segments into groups with the same rules as the mesh entities."""
    out: dict[str, list] = {}
    for s in segments:
        q = s.at(np.linspace(0.0, 1.0, 9))
        name = next((n for n, pred in g.rules(tol) if pred(q)), None) or g.side(q)
        out.setdefault(name, []).append(s)
    return out


def reference(p: LipSealParams) -> dict[str, float]:
    """Closed forms (Green's theorem on the exact profile; Pappus for revolved measures).

    Keys: ``area`` (section, m²), ``first_moment_r`` (∫ r dA, m³), ``centroid_r`` (m),
    ``volume_revolved`` (2 pi ∫ r dA, m³), and per facet group ``length_<group>``
    (m) and ``area_revolved_<group>`` (2 pi ∫ r ds, m²).
    """
    g = LipGeometry(p)
    m = loop_moments(g.profile())
    out = {
        "area": m["area"],
        "first_moment_r": m["mx"],
        "centroid_r": m["cx"],
        "volume_revolved": 2 * math.pi * m["mx"],
    }
    for name, segs in classify_segments(g, g.profile(), 1e-9 * p.shaft_radius).items():
        pm = path_moments(segs)
        out[f"length_{name}"] = pm["length"]
        out[f"area_revolved_{name}"] = 2 * math.pi * pm["mx"]
    return out


def build_lip(params: LipSealParams | None = None, **overrides: object) -> MeshInfo:
    """Build the lip section model and mesh in a new Gmsh model (Gmsh must be initialised).

    Args:
        params: Parameters (defaults if ``None``).
        **overrides: Fields of :class:`LipSealParams` to change.

    Returns:
        What was built (groups, statistics, closed-form reference values).
    """
    t0 = time.perf_counter()
    p = params if params is not None else LipSealParams()
    if overrides:
        p = dataclasses.replace(p, **overrides)
    g = LipGeometry(p)
    gmsh.model.add(KIND)
    add_loop(g.profile(), plane="xy")
    gmsh.model.occ.synchronize()

    tol = 1e-3 * p.h_contact
    rules = [(n, lambda q, f=f: f(q[:, :2])) for n, f in g.rules(tol)]
    curves = [t for _, t in gmsh.model.getEntities(1)]
    groups = classify(1, curves, rules, default=lambda q: g.side(q[:, :2]))

    band_len = path_moments(g.tip_band())["length"]
    sampling = int(min(max(4 * band_len / p.h_contact, 50), 20000))
    field = distance_threshold(1, groups["contact"], sampling, p.h_contact, p.h_far, p.growth)
    mesh_options(p.h_contact, p.h_far, field)
    extra = {"tip_r": g.r0, "outer_radius": g.r_out, "groove_centre": list(g.Gc)}
    return finish(KIND, p, 2, 2, groups, p.order, t0, reference(p), extra)


PARAMS = LipSealParams
BUILD = build_lip


def main(argv: list[str] | None = None) -> int:
    """CLI: ``python -m geometry.lip --out DIR --set interference=0.4e-3``."""
    return cli_main(KIND, LipSealParams, build_lip, argv)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
