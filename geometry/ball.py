"""Rubber ball on a flat, 3D (S1 section 3).

The ball of radius ``R`` touches the flat ``z = 0`` at the origin; its centre is
``(0, 0, R)``.  Sliding is along ``x``, so ``y = 0`` is a plane of symmetry of
the lubricated problem and the default model is the half ball ``y >= 0``.

The ball is truncated by the plane ``z = H`` (``H = height_ratio * R``); the flat
top is the ``load`` surface (a rigid plate).  ``height_ratio = 2`` keeps the
whole ball, and the ``load`` surface is then its upper hemisphere.  Truncation
changes the far field only.  Measured (linear elasticity, Hertz pressure on the
default ball, load surface clamped; ``tests/test_meshing.py``, slow): the
indentation shape ``u_z(0) - u_z(a)`` differs from that of the whole ball by
0.1 % at ``H = R`` (the default), 0.6 % at ``H = 0.75 R`` and 2 % at ``H = 0.5 R``,
and from the half-space Hertz value by less than 1 %.  Only the rigid approach
of the load surface depends on ``H``.

Groups: ``body`` (cells), ``contact`` (the spherical cap ``x² + y² <= r_cap²``
around the contact, ``r_cap = cap_extent * a``, where the 2D Reynolds film
lives), ``load``, ``free`` (the rest of the sphere) and, for the half ball,
``symmetry`` (``y = 0``).  The cap is cut off the ball by the plane
``z = z_cap``, so the body is made of two (or three) conforming volumes, all in
``body``.

Mesh size: ``h_contact`` for ``sqrt(x² + y²) <= fine_extent * a`` on the
surface, at most ``h_cap`` on the rest of the cap, growing inwards by
``growth`` per unit distance up to ``h_far``; optionally ``h_rim`` on the rim
band ``rim_inner a <= sqrt(x² + y²) <= rim_outer a``, where the side lobes
of a soft EHL film's exit constriction (and its minimum) sit.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Literal

import gmsh

from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range
from geometry._common import (
    MeshInfo,
    boundary_entities,
    classify,
    cli_main,
    finish,
    linear_size,
    mesh_options,
    pos,
    size_field_expressions,
)

KIND = "ball"


@dataclass(frozen=True)
class BallParams:
    """Ball geometry and mesh (SI units: metres).

    Defaults: the S1 section 3 ball (R = 1 cm, F = 1.3 N, E* = 1.6 MPa), whose
    Hertz contact radius is ``a = (3 F R / (4 E*))^(1/3) ~ 1.8 mm``.

    Attributes:
        radius: Ball radius R (m).
        shape: ``"half"`` (``y >= 0``, symmetry plane ``y = 0``) or ``"full"``.
        height_ratio: Height H of the flat top over the flat in units of R, in
            (0, 2]; 2 keeps the whole ball.
        contact_radius: Expected contact radius a (m).
        cap_extent: Radius of the ``contact`` cap in units of a.
        fine_extent: Radius of the finest zone in units of a (< cap_extent).
        h_contact: Element size in the finest zone (m); at most a / 4.
        h_cap: Largest element size on the contact cap (m).
        h_far: Largest element size (m); at most R / 3.
        h_rim: Element size on the rim band (m), at most ``h_contact``; None: no
            rim zone.
        rim_inner: Inner radius of the rim band in units of a.
        rim_outer: Outer radius of the rim band in units of a (< fine_extent).
        growth: Size increase per unit distance away from the surface zones (0 < growth <= 2).
        order: Geometry order of the elements, 1 or 2.
    """

    radius: float = 0.01
    shape: Literal["half", "full"] = "half"
    height_ratio: float = 1.0
    contact_radius: float = 1.8e-3
    cap_extent: float = 3.0
    fine_extent: float = 1.5
    h_contact: float = 0.1e-3
    h_cap: float = 0.3e-3
    h_far: float = 1.0e-3
    h_rim: float | None = None
    rim_inner: float = 0.8
    rim_outer: float = 1.1
    growth: float = 0.2
    order: int = 1

    def __post_init__(self) -> None:
        R = check_positive("radius", self.radius, "m")
        check_choice("shape", self.shape, ("half", "full"))
        check_range("height_ratio", self.height_ratio, 0.0, 2.0, lo_open=True)
        a = check_range("contact_radius", self.contact_radius, 0.0, 0.5 * R, lo_open=True, unit="m")
        rcap_max = 0.9 * R
        if self.height_ratio < 1.0:
            rcap_max = 0.9 * math.sqrt(R * R - (R - self.height) ** 2)
        check_range("cap_extent", self.cap_extent, 0.0, rcap_max / a, lo_open=True)
        check_range("fine_extent", self.fine_extent, 0.0, self.cap_extent, lo_open=True)
        check_range("h_contact", self.h_contact, 0.0, a / 4.0, lo_open=True, unit="m")
        check_range("h_cap", self.h_cap, self.h_contact, self.h_far, unit="m")
        check_range("h_far", self.h_far, self.h_contact, R / 3.0, unit="m")
        if self.h_rim is not None:
            check_range("h_rim", self.h_rim, 0.0, self.h_contact, lo_open=True, unit="m")
        check_range("rim_inner", self.rim_inner, 0.0, self.fine_extent, lo_open=True)
        check_range("rim_outer", self.rim_outer, self.rim_inner, self.fine_extent, lo_open=True)
        check_range("growth", self.growth, 0.0, 2.0, lo_open=True)
        check_int_range("order", self.order, 1, 2)

    @property
    def height(self) -> float:
        """Height H of the flat top (m)."""
        return self.height_ratio * self.radius

    @property
    def cap_radius(self) -> float:
        """Radius of the contact cap ``r_cap`` (m)."""
        return self.cap_extent * self.contact_radius

    @property
    def cap_height(self) -> float:
        """Height ``z_cap`` of the plane that bounds the contact cap (m)."""
        R, r = self.radius, self.cap_radius
        return R - math.sqrt(R * R - r * r)


def reference(p: BallParams) -> dict[str, float]:
    """Closed forms: volume and the area of each boundary group (SI)."""
    R, H, zc = p.radius, p.height, p.cap_height
    f = 0.5 if p.shape == "half" else 1.0
    whole = p.height_ratio == 2.0
    out = {
        "volume": f * math.pi * H * H * (3 * R - H) / 3.0,
        "area_contact": f * 2 * math.pi * R * zc,
        "area_load": f * (2 * math.pi * R * R if whole else math.pi * (R * R - (R - H) ** 2)),
        "area_free": f * 2 * math.pi * R * ((R if whole else H) - zc),
    }
    if p.shape == "half":
        d = R - H
        out["area_symmetry"] = R * R * math.acos(d / R) - d * math.sqrt(max(R * R - d * d, 0.0))
    return out


def _split(body: list[tuple[int, int]], heights: list[float], size: float) -> None:
    """Cut the body by the planes ``z = h`` (conforming volumes), dropping the leftovers."""
    occ = gmsh.model.occ
    disks = [(2, occ.addDisk(0.0, 0.0, h, size, size)) for h in heights]
    occ.fragment(body, disks)
    occ.synchronize()
    for _, s in gmsh.model.getEntities(2):
        up, _ = gmsh.model.getAdjacencies(2, s)
        if len(up) == 0:
            occ.remove([(2, s)], recursive=True)
    occ.synchronize()


def build_ball(params: BallParams | None = None, **overrides: object) -> MeshInfo:
    """Build the ball model and mesh in a new Gmsh model (Gmsh must be initialised).

    Args:
        params: Parameters (defaults if ``None``).
        **overrides: Fields of :class:`BallParams` to change.

    Returns:
        What was built (groups, statistics, closed-form reference values).
    """
    t0 = time.perf_counter()
    p = params if params is not None else BallParams()
    if overrides:
        p = dataclasses.replace(p, **overrides)
    R, H, a = p.radius, p.height, p.contact_radius
    zc, rc = p.cap_height, p.cap_radius
    whole = p.height_ratio == 2.0
    gmsh.model.add(KIND)
    occ = gmsh.model.occ
    body = [(3, occ.addSphere(0.0, 0.0, R, R))]
    if p.shape == "half" or not whole:
        y0 = 0.0 if p.shape == "half" else -2 * R
        box = occ.addBox(-2 * R, y0, -R, 4 * R, 2 * R - y0, H + R if not whole else 4 * R)
        body, _ = occ.intersect(body, [(3, box)])
    _split(body, [zc, R] if whole else [zc], 2.0 * R)

    tol = 1e-7 * R
    rules = []
    if p.shape == "half":
        rules.append(("symmetry", lambda q: bool(abs(q[:, 1]).max() < tol)))
    if whole:
        rules.append(("load", lambda q: bool(q[:, 2].min() > R - tol)))
    else:
        rules.append(("load", lambda q: bool(abs(q[:, 2] - H).max() < tol)))
    rules.append(("contact", lambda q: bool(q[:, 2].max() < zc + tol)))
    groups = classify(2, boundary_entities(3), rules, default="free")

    depth = pos(f"{R!r} - Sqrt(x^2 + y^2 + (z - {R!r})^2)")
    rho = "Sqrt(x^2 + y^2)"
    rf = p.fine_extent * a
    zf = R - math.sqrt(R * R - rf * rf)
    fine = linear_size(
        p.h_contact, p.growth, f"{depth} + {pos(f'{rho} - {rf!r}')} + {pos(f'z - {zf!r}')}"
    )
    cap = linear_size(
        p.h_cap, p.growth, f"{depth} + {pos(f'{rho} - {rc!r}')} + {pos(f'z - {zc!r}')}"
    )
    sizes = [fine, cap]
    if p.h_rim is not None:
        r_in, r_out = p.rim_inner * a, p.rim_outer * a
        sizes.append(linear_size(p.h_rim, p.growth,
                                 f"{depth} + {pos(f'{rho} - {r_out!r}')} + {pos(f'{r_in!r} - {rho}')}"))  # fmt: skip
    mesh_options(p.h_rim or p.h_contact, p.h_far, size_field_expressions(sizes))
    extra = {"cap_radius": rc, "cap_height": zc}
    return finish(KIND, p, 3, 3, groups, p.order, t0, reference(p), extra)


PARAMS = BallParams
BUILD = build_ball


def main(argv: list[str] | None = None) -> int:
    """CLI: ``python -m geometry.ball --out DIR --set shape=full``."""
    return cli_main(KIND, BallParams, build_ball, argv)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
