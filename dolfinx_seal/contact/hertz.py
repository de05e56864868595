"""Hertz contact sizes and the separation of a contact law at a pressure.

Closed forms used to scale meshes and to guess starting states (the dry contact
of a smooth elastic body, Johnson, *Contact Mechanics*, 1985, sections 4.2-4.3).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def hertz_line(load_per_length: float, radius: float, e_star: float) -> tuple[float, float]:
    """Hertz line contact: half-width ``a`` [m] and peak pressure ``p0`` [Pa]."""
    a = math.sqrt(4.0 * load_per_length * radius / (math.pi * e_star))
    return a, 2.0 * load_per_length / (math.pi * a)


def hertz_point(load: float, radius: float, e_star: float) -> tuple[float, float]:
    """Hertz point contact: radius ``a`` [m] and peak pressure ``p0`` [Pa]."""
    a = (3.0 * load * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return a, 3.0 * load / (2.0 * math.pi * a * a)


def separation_of(law: Any, p: float) -> float:
    """Mean separation [m] of ``law`` at pressure ``p`` (the full relation if known)."""
    inv = getattr(law, "full", law)
    return float(np.asarray(inv.separation(p)))


__all__ = ["hertz_line", "hertz_point", "separation_of"]
