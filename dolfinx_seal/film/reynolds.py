"""The Reynolds thin-film equation, built from named flux terms.

Steady, incompressible, isoviscous film between two surfaces with gap ``h``
moving with mean tangential velocity ``U_m`` (S1 eq 20, S0 eqs 9-11)::

    div( poiseuille_conductivity * grad p ) = div( U_m h theta )

The weak residual used everywhere is, for a test function ``q``::

    R(p; q) = integral( (conductivity * grad p - couette_flux) . grad q )

so that the volumetric flux is ``couette_flux - conductivity * grad p``
(:func:`flux`).  The natural boundary term vanishes where ``q = 0`` (Dirichlet
pressure on the boundary of the lubricated zone).

With the Reynolds cavitation condition the problem becomes the VI ``p >= 0``,
``R >= 0`` on the active set, ``p R = 0``: for a rigid geometry it is the
minimisation of ``1/2 int c |grad p|^2 - int couette . grad p`` over ``p >= 0``.
"""

from __future__ import annotations

from typing import Any

import ufl


def poiseuille_conductivity(h: Any, eta: Any, phi_p: Any = 1.0) -> Any:
    """Pressure-flow conductivity ``phi_p h^3 / (12 eta)`` [m^3 / (Pa s)].

    Args:
        h: Film thickness (gap) [m].
        eta: Dynamic viscosity [Pa s].
        phi_p: Pressure flow factor of the homogenized roughness [-].
    """
    return phi_p * h**3 / (12.0 * eta)


def couette_flux(h: Any, U_m: Any, theta: Any = 1.0) -> Any:
    """Shear-driven volumetric flux per unit width ``U_m h theta`` [m^2/s] (a vector).

    Args:
        h: Film thickness [m].
        U_m: Mean surface velocity vector ``(U_1 + U_2)/2`` [m/s].
        theta: Film fraction (1 in full film; JFO cavitation) [-].
    """
    return U_m * h * theta


def flux(p: Any, h: Any, conductivity: Any, couette: Any) -> Any:
    """Total volumetric flux per unit width ``couette - conductivity grad p`` [m^2/s]."""
    return couette - conductivity * ufl.grad(p)


def reynolds_residual(p: Any, q: Any, conductivity: Any, couette: Any, dx: Any) -> Any:
    """Weak Reynolds residual ``int (conductivity grad p - couette) . grad q dx``."""
    return ufl.inner(conductivity * ufl.grad(p) - couette, ufl.grad(q)) * dx
