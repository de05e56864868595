"""Exact solution of a 2D obstacle problem (radially symmetric), numpy only.

Find ``u >= psi`` on ``[-2, 2]^2`` minimising ``1/2 int |grad u|^2`` with
``u = g`` on the boundary, where ``psi(r) = sqrt(1 - r^2)`` for ``r <= 1`` and
``-1`` beyond.  The solution (a classical benchmark, e.g. Bueler's obstacle
examples) is the hemisphere for ``r <= r*`` and the harmonic, C^1-matched
``-(r*)^2 ln(r / 2) / sqrt(1 - (r*)^2)`` outside; ``r* = 0.697965148...`` is
fixed by matching value and slope of the two branches (solved by Brent's
method).  ``g`` is the outer branch on the boundary.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def free_boundary_radius() -> float:
    """The contact radius ``r*`` (C^1 matching of hemisphere and log branch)."""

    def mismatch(r: float) -> float:
        # value match of sqrt(1-r^2) and a*ln(r/2) with slope match a = -r^2/sqrt(1-r^2)
        a = -(r**2) / np.sqrt(1.0 - r**2)
        return np.sqrt(1.0 - r**2) - a * np.log(r / 2.0)

    return float(brentq(mismatch, 0.1, 0.99, xtol=1e-15))


def obstacle(x: np.ndarray) -> np.ndarray:
    """``psi`` at points ``x`` (shape (gdim or 3, n))."""
    r2 = x[0] ** 2 + x[1] ** 2
    return np.where(r2 <= 1.0, np.sqrt(np.maximum(1.0 - r2, 0.0)), -1.0)


def exact(x: np.ndarray) -> np.ndarray:
    """Exact solution ``u`` at points ``x``."""
    rs = free_boundary_radius()
    r = np.sqrt(x[0] ** 2 + x[1] ** 2)
    a = rs**2 / np.sqrt(1.0 - rs**2)
    outer = -a * np.log(np.maximum(r, 1e-300) / 2.0)
    inner = np.sqrt(np.maximum(1.0 - r**2, 0.0))
    return np.where(r <= rs, inner, outer)
