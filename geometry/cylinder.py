"""Rubber cylinder on a flat, 2D plane strain (S1 section 2).

The cylinder of radius ``R`` rests on the flat ``y = 0`` at the origin; its
centre is ``(0, R)``.  Sliding is along ``x``; the contact arc is tagged from
``x = -contact_upstream * a`` to ``x = +contact_downstream * a`` (``a`` the
expected contact half-width), so that a 1D Reynolds film on it starts well
upstream of the contact (docs/design.md, known traps: the inlet must be several
half-widths away).  Upstream is ``-x``: the inlet for surfaces moving in ``+x``.

Shapes (``shape``):

* ``"segment"`` (default): the part of the disc below ``y = H`` (``H =
  height_ratio * R``; ``H = R`` is the lower half disc).  The flat top is
  ``load`` (a rigid plate pushes it down).  Not symmetric in ``x``: fit for sliding.
* ``"disc"``: the full disc; ``load`` is the upper half of the circle.
* ``"half"``: the ``x >= 0`` half of the segment with ``symmetry`` on ``x = 0``,
  for static (Hertz) checks only: sliding breaks the symmetry.

Groups: ``body`` (cells), ``contact``, ``load``, ``free`` (rest of the circle)
and, for ``half``, ``symmetry``.

Mesh size: ``h_contact`` on the arc within ``|x| <= fine_extent * a``, at most
``h_arc`` on the rest of the contact arc, growing inwards by ``growth`` per unit
distance up to ``h_far``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Literal

import gmsh

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range
from geometry._common import (
    Arc,
    Line,
    MeshInfo,
    add_loop,
    classify,
    cli_main,
    finish,
    linear_size,
    loop_moments,
    mesh_options,
    pos,
    size_field_expressions,
)

KIND = "cylinder"


@dataclass(frozen=True)
class CylinderParams:
    """Cylinder geometry and mesh (SI units: metres).

    Defaults: the S1 section 2 cylinder (R = 1 cm, E = 10 MPa, F/L = 100 N/m,
    nu = 0.5), whose Hertz half-width is ``a = sqrt(4 F' R / (pi E*)) ~ 0.31 mm``.

    Attributes:
        radius: Cylinder radius R (m).
        shape: ``"segment"``, ``"disc"`` or ``"half"`` (see the module docstring).
        height_ratio: Height of the flat top over the flat, in units of R, in
            (0.2, 2) (``segment`` and ``half``; 1 = half disc).
        contact_half_width: Expected contact half-width a (m); sets the contact arc
            and the checks on the element sizes.
        contact_upstream: Extent of the contact arc towards ``-x``, in units of a.
        contact_downstream: Extent of the contact arc towards ``+x``, in units of a.
        fine_extent: Half-width of the finest zone ``|x| <= fine_extent * a``, in units of a.
        h_contact: Element size in the finest zone (m); at most a / 4.
        h_arc: Largest element size on the contact arc (m).
        h_far: Largest element size (m); at most R / 4.
        growth: Size increase per unit distance away from the contact (0 < growth <= 2).
        order: Geometry order of the elements, 1 or 2 (2 puts mid-edge nodes on the circle).
    """

    radius: float = 0.01
    shape: Literal["segment", "disc", "half"] = "segment"
    height_ratio: float = 1.0
    contact_half_width: float = 0.3e-3
    contact_upstream: float = 10.0
    contact_downstream: float = 6.0
    fine_extent: float = 2.0
    h_contact: float = 15e-6
    h_arc: float = 60e-6
    h_far: float = 1.0e-3
    growth: float = 0.2
    order: int = 1

    def __post_init__(self) -> None:
        R = check_positive("radius", self.radius, "m")
        check_choice("shape", self.shape, ("segment", "disc", "half"))
        check_range("height_ratio", self.height_ratio, 0.2, 2.0, lo_open=True, hi_open=True)
        a = check_positive("contact_half_width", self.contact_half_width, "m")
        check_range("contact_half_width", a, 0.0, 0.5 * R, lo_open=True, unit="m")
        check_positive("contact_upstream", self.contact_upstream)
        check_positive("contact_downstream", self.contact_downstream)
        check_positive("fine_extent", self.fine_extent)
        check_range("h_contact", self.h_contact, 0.0, a / 4.0, lo_open=True, unit="m")
        check_range("h_arc", self.h_arc, self.h_contact, self.h_far, unit="m")
        check_range("h_far", self.h_far, self.h_contact, R / 4.0, unit="m")
        check_range("growth", self.growth, 0.0, 2.0, lo_open=True)
        check_int_range("order", self.order, 1, 2)
        top = self.height if self.shape != "disc" else R
        for name, ext in (
            ("contact_upstream", self.contact_upstream),
            ("contact_downstream", self.contact_downstream),
        ):
            if name == "contact_upstream" and self.shape == "half":
                continue
            x = ext * a
            if x >= R or R - math.sqrt(R * R - x * x) > 0.9 * top:
                raise ParameterError(
                    f"{name} = {ext!r} puts the contact arc end at |x| = {x:g} m, beyond the "
                    f"lower part of the cylinder (allowed: arc end below 0.9 * "
                    f"min(R, H) = {0.9 * top:g} m)"
                )
            if self.fine_extent * a > x:
                raise ParameterError(
                    f"fine_extent = {self.fine_extent!r} exceeds {name} = {ext!r}: the finest "
                    "zone must lie inside the contact arc"
                )

    @property
    def height(self) -> float:
        """Height H of the flat top above the flat (m)."""
        return self.height_ratio * self.radius

    @property
    def arc_ends(self) -> tuple[float, float]:
        """x of the two ends of the contact arc (m); the first is 0 for ``half``."""
        a = self.contact_half_width
        x0 = 0.0 if self.shape == "half" else -self.contact_upstream * a
        return x0, self.contact_downstream * a


def _circle_point(R: float, x: float, upper: bool = False) -> tuple[float, float]:
    s = math.sqrt(max(R * R - x * x, 0.0))
    return (x, R + s) if upper else (x, R - s)


def profile(p: CylinderParams) -> list[Line | Arc]:
    """Closed boundary loop of the cylinder section (exact lines and arcs)."""
    R, H = p.radius, p.height
    c = (0.0, R)
    x0, x1 = p.arc_ends
    P0, P1 = _circle_point(R, x0), _circle_point(R, x1)
    if p.shape == "disc":
        left, right, top = (-R, R), (R, R), (0.0, 2 * R)
        return [Arc(top, left, c), Arc(left, P0, c), Arc(P0, P1, c), Arc(P1, right, c),
                Arc(right, top, c)]  # fmt: skip
    w = math.sqrt(R * R - (H - R) ** 2)
    tl, tr = (-w, H), (w, H)
    if p.shape == "half":
        return [Arc(P0, P1, c), Arc(P1, tr, c), Line(tr, (0.0, H)), Line((0.0, H), P0)]
    return [Arc(tl, P0, c), Arc(P0, P1, c), Arc(P1, tr, c), Line(tr, tl)]


def reference(p: CylinderParams) -> dict[str, float]:
    """Closed forms: section area, contact-arc length, load length, symmetry length (SI)."""
    R, H = p.radius, p.height
    x0, x1 = p.arc_ends
    arc = R * (math.asin(x1 / R) - math.asin(x0 / R))
    if p.shape == "disc":
        return {"area": math.pi * R * R, "length_contact": arc, "length_load": math.pi * R}
    d = R - H  # signed distance from the centre to the chord y = H
    seg = R * R * math.acos(d / R) - d * math.sqrt(R * R - d * d)  # segment below the chord
    w = math.sqrt(R * R - d * d)
    out = {"area": seg, "length_contact": arc, "length_load": 2 * w}
    if p.shape == "half":
        out.update(area=seg / 2, length_load=w, length_symmetry=H)
    moments = loop_moments(profile(p))
    out["centroid_y"] = moments["cy"]
    return out


def build_cylinder(params: CylinderParams | None = None, **overrides: object) -> MeshInfo:
    """Build the cylinder model and mesh in a new Gmsh model (Gmsh must be initialised).

    Args:
        params: Parameters (defaults if ``None``).
        **overrides: Fields of :class:`CylinderParams` to change.

    Returns:
        What was built (groups, statistics, closed-form reference values).
    """
    t0 = time.perf_counter()
    p = params if params is not None else CylinderParams()
    if overrides:
        p = dataclasses.replace(p, **overrides)
    R, H = p.radius, p.height
    a = p.contact_half_width
    x0, x1 = p.arc_ends
    gmsh.model.add(KIND)
    add_loop(profile(p))
    gmsh.model.occ.synchronize()

    tol = 1e-7 * R
    y_arc = max(R - math.sqrt(R * R - x * x) for x in (x0, x1))
    rules = []
    if p.shape == "half":
        rules.append(("symmetry", lambda q: bool(abs(q[:, 0]).max() < tol)))
    if p.shape == "disc":
        rules.append(("load", lambda q: bool(q[:, 1].min() > R - tol)))
    else:
        rules.append(("load", lambda q: bool(abs(q[:, 1] - H).max() < tol)))
    rules.append(
        (
            "contact",
            lambda q: bool(
                q[:, 0].min() > x0 - tol
                and q[:, 0].max() < x1 + tol
                and q[:, 1].max() < y_arc + tol
            ),
        )
    )
    curves = [t for _, t in gmsh.model.getEntities(1)]
    groups = classify(1, curves, rules, default="free")

    # distance-like measures from the fine zone and from the contact arc (exact on the
    # circle, an upper bound inside): depth below the circle + excess beyond the ends
    depth = pos(f"{R!r} - Sqrt(x^2 + (y - {R!r})^2)")
    xf = p.fine_extent * a
    yf = R - math.sqrt(R * R - xf * xf)
    fine = linear_size(
        p.h_contact, p.growth, f"{depth} + {pos(f'Abs(x) - {xf!r}')} + {pos(f'y - {yf!r}')}"
    )
    arc = linear_size(
        p.h_arc,
        p.growth,
        f"{depth} + {pos(f'{x0!r} - x')} + {pos(f'x - {x1!r}')} + {pos(f'y - {y_arc!r}')}",
    )
    mesh_options(p.h_contact, p.h_far, size_field_expressions([fine, arc]))
    return finish(KIND, p, 2, 2, groups, p.order, t0, reference(p), {"arc_ends": [x0, x1]})


PARAMS = CylinderParams
BUILD = build_cylinder


def main(argv: list[str] | None = None) -> int:
    """CLI: ``python -m geometry.cylinder --out DIR --set h_contact=1e-5``."""
    return cli_main(KIND, CylinderParams, build_cylinder, argv)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
