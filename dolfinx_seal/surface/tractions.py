"""Boundary tractions on the current (deformed) surface, as UFL virtual-work terms.

A pressure ``p`` [Pa] acting on the deformed surface exerts the force
``-p n da`` which, with Nanson's formula ``n da = J F^-T N dA``, becomes a
follower load on the reference surface:

    W_p = - int p J F^-T N . v  w dA

(``w`` is the kinematic weight: 1, or ``2 pi r`` in axisymmetry).  A shear
traction ``tau`` [Pa] along a unit direction ``t`` of the deformed surface acts
per current area ``da = J |F^-T N| dA``.  Residuals built from these terms are
differentiated with ``ufl.derivative`` as a whole, so the geometric stiffness of
the follower loads is in the Jacobian.
"""

from __future__ import annotations

from typing import Any

import ufl


def nanson_normal(F: Any, N: Any) -> Any:
    """``J F^-T N``: the current area-weighted normal per reference area (3-vectors)."""
    return ufl.det(F) * ufl.inv(F).T * N


def area_ratio(F: Any, N: Any) -> Any:
    """``da / dA = J |F^-T N|``."""
    return ufl.sqrt(ufl.dot(nanson_normal(F, N), nanson_normal(F, N)))


def pressure_work(p: Any, F: Any, N: Any, v3: Any, weight: Any, ds: Any) -> Any:
    """Virtual work of a pressure on the current surface: ``-int p J F^-T N . v w dA``."""
    return -p * ufl.dot(nanson_normal(F, N), v3) * weight * ds


def shear_work(tau: Any, direction: Any, F: Any, N: Any, v3: Any, weight: Any, ds: Any) -> Any:
    """Virtual work of a shear stress ``tau`` [Pa] along ``direction`` on the current surface."""
    return tau * ufl.dot(direction, v3) * area_ratio(F, N) * weight * ds


def normal_force(p: Any, F: Any, N: Any, e: Any, weight: Any, ds: Any) -> Any:
    """Force of a pressure on the body along ``e``: ``-int p J F^-T N . e w dA`` [N or N/m]."""
    return -p * ufl.dot(nanson_normal(F, N), e) * weight * ds
