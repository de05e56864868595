"""Gmsh geometry builders for the dolfinx_seal scenes (gmsh + numpy only; no DOLFINx).

=============  ======================  =============================================
kind           module                  what
=============  ======================  =============================================
``cylinder``   :mod:`geometry.cylinder`    2D plane-strain cylinder on a flat (S1 sec. 2)
``ball``       :mod:`geometry.ball`        3D half (or full) ball on a flat (S1 sec. 3)
``lip``        :mod:`geometry.lip`         axisymmetric radial lip seal section (S0 fig. 3)
``lip-sector`` :mod:`geometry.lip_sector`  3D periodic sector of the lip tip (S0 sec. 3)
=============  ======================  =============================================

Each module has one parameter dataclass (the single source of defaults, validated
in ``__post_init__``), a builder ``build_KIND(params=None, **overrides) -> MeshInfo``
that creates a new Gmsh model with named and numbered physical groups
(:mod:`geometry.tags`) and meshes it, and a ``__main__`` writing ``KIND.msh`` and
``info.json``.  Builders need an initialised Gmsh (:func:`gmsh_session`).  Modules
are imported lazily, so importing this package does not import Gmsh::

    from geometry import gmsh_session, load, save
    mod = load("lip")
    with gmsh_session():
        info = mod.BUILD(mod.PARAMS(interference=0.3e-3))
        save(info, "results/meshes/lip")

DOLFINx meshes: :func:`dolfinx_seal.meshing.create_mesh`.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

#: Mesh kind -> builder module.
KINDS: dict[str, str] = {
    "cylinder": "geometry.cylinder",
    "ball": "geometry.ball",
    "lip": "geometry.lip",
    "lip-sector": "geometry.lip_sector",
}

_LAZY = {
    "gmsh_session": "geometry._common",
    "save": "geometry._common",
    "mesh_arrays": "geometry._common",
    "MeshInfo": "geometry._common",
    "CylinderParams": "geometry.cylinder",
    "build_cylinder": "geometry.cylinder",
    "BallParams": "geometry.ball",
    "build_ball": "geometry.ball",
    "LipSealParams": "geometry.lip",
    "build_lip": "geometry.lip",
    "LipSectorParams": "geometry.lip_sector",
    "build_lip_sector": "geometry.lip_sector",
}

__all__ = ["KINDS", "load", *_LAZY]


def load(kind: str) -> ModuleType:
    """The builder module of a mesh kind (it has ``KIND``, ``PARAMS``, ``BUILD``, ``main``).

    Raises:
        ParameterError: If ``kind`` is not one of :data:`KINDS`.
    """
    if kind not in KINDS:
        from dolfinx_seal.errors import ParameterError

        raise ParameterError(f"unknown mesh kind {kind!r}; available: {', '.join(KINDS)}")
    return importlib.import_module(KINDS[kind])


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'geometry' has no attribute {name!r}")
