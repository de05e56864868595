"""Physical-group numbers and names shared by every geometry builder.

The FEM code imports these constants instead of repeating numbers::

    from geometry import tags
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
    traction_on_load = ufl.dot(t, v) * ds(tags.LOAD)

Cell groups and facet groups use disjoint numbers so that a tag alone says
what it is.  A group appears in a mesh only if the geometry has that
boundary (a full disc has no symmetry line); :attr:`geometry.MeshInfo.facet_groups`
lists the groups a mesh actually has.
"""

from __future__ import annotations

#: The solid (all cells).
BODY = 1

#: Boundary that may touch the counter-surface (flat or shaft) and carries the film.
CONTACT = 11
#: Boundary where the load (force or rigid displacement) is applied.
LOAD = 12
#: Symmetry plane or line (zero normal displacement).
SYMMETRY = 13
#: Boundary bonded to the rigid seal case (fixed).
CLAMPED = 14
#: Free surface of the lip wetted by the sealed oil.
OIL_SIDE = 15
#: Free surface of the lip on the air (environment) side.
AIR_SIDE = 16
#: Seat of the garter spring on the outer side of the lip head.
SPRING_GROOVE = 17
#: Circumferential face of the lip sector at theta = -angle/2 (the master of the periodic pair).
PERIODIC_LEFT = 18
#: Circumferential face of the lip sector at theta = +angle/2 (image of PERIODIC_LEFT).
PERIODIC_RIGHT = 19
#: Faces where the sector is cut out of the lip; the axisymmetric solution is imposed there.
CUT = 20
#: Traction-free boundary of the cylinder and ball outside the contact zone.
FREE = 21

#: Cell-group names and numbers.
CELL_GROUPS: dict[str, int] = {"body": BODY}

#: Facet-group names and numbers.
FACET_GROUPS: dict[str, int] = {
    "contact": CONTACT,
    "load": LOAD,
    "symmetry": SYMMETRY,
    "clamped": CLAMPED,
    "oil_side": OIL_SIDE,
    "air_side": AIR_SIDE,
    "spring_groove": SPRING_GROOVE,
    "periodic_left": PERIODIC_LEFT,
    "periodic_right": PERIODIC_RIGHT,
    "cut": CUT,
    "free": FREE,
}

#: Every group, name -> number.
ALL: dict[str, int] = {**CELL_GROUPS, **FACET_GROUPS}

#: Number -> name.
NAMES: dict[int, str] = {v: k for k, v in ALL.items()}


def number(name: str) -> int:
    """The number of the physical group called ``name``.

    Raises:
        KeyError: If ``name`` is not a group of this project (the message lists them).
    """
    try:
        return ALL[name]
    except KeyError:
        raise KeyError(f"unknown physical group {name!r}; known: {', '.join(ALL)}") from None
