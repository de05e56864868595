r"""Independent references for the axisymmetric lubricated lip (numpy only).

**Static leakage in the homogenised limit.**  With no axial sliding, the steady
1D Reynolds equation along the sealing band has a constant volumetric flow
``Q`` [m^3/s] through every section of the surface of revolution::

    Q = -2 pi r(s) k(u(s)) dp/ds,   k(u) = phi_p(u) u^3 / (12 eta)

so that, integrating ``dp/ds`` from the oil end to the air end of the band,

    Q = (p_oil - p_air) / int_band ds / (2 pi r(s) k(u(s)))

(the axial resistance of the band; critical-junction and percolation theories
give the same limit when the flow factor is the effective-medium one).
:func:`static_leakage` evaluates that integral on a given separation profile,
apart from the finite elements: the profile is taken piecewise linear between
the nodes of a quadratic finite element surface (the separation field of the
FEM's own P2 displacement, so the reference and the film see the same gap), and
each element is integrated with a Gauss-Legendre rule: the exact resistance of
that profile up to the rule's error (checked by doubling it), where the film's
P1 pressure sees element averages of the conductance and converges to it.

**Inverse hydrodynamic lubrication (IHL) of a reciprocating rod seal.**  For a
soft seal in full film the pressure is close to the dry contact pressure
(Blok; Muller & Nau, *Fluid Sealing Technology*, 1998, reciprocating seals):
the film at the point of largest pressure gradient ``w = |dp/dz|_max`` on the
inlet side carries ``h* = sqrt(8 eta U / (9 w))``, and the film left on the
rod behind the seal is ``h*/2`` per unit area: the out-stroke carries
``Q_out = pi R U h*_out`` out (``w`` on the oil side) and the in-stroke can
bring ``pi R U h*_in`` back (``w`` on the air side).  :func:`ihl_film` returns
``h*`` from a contact pressure profile.  :func:`ihl_solution` goes on to the
whole inverse solution: with the flow ``q = U h*/2`` per unit circumference
fixed, the Reynolds flux ``q = U h/2 - h^3 p'/(12 eta)`` is a cubic in the film
``h(z)`` at every point of the pressure profile (its larger positive root on
the inlet side of the largest gradient, where the film comes down from the
wide inlet, its smaller one from there to the pressure peak, the only positive
one on the outlet side), and the shear on the rod ``eta U/h + (h/2) p'`` gives
the friction force of the full film.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from dolfinx_seal.errors import ParameterError

FloatArray = np.ndarray


def static_leakage(
    r: FloatArray,
    z: FloatArray,
    u: FloatArray,
    pressure_drop: float,
    viscosity: float,
    flow_factor: Callable[[FloatArray], FloatArray] | None = None,
    points: int = 16,
) -> float:
    """Axial flow [m^3/s] of a static band: ``dp / int ds / (2 pi r k(u))``.

    The band is given as the nodes of quadratic elements along the current
    surface, ordered from the oil to the air end: vertex, mid-side node,
    vertex, ... (an odd number of nodes; the P2 nodes of a finite element
    surface).  On each element ``r``, ``z`` and ``u`` are the quadratics through
    its three nodes in the element parameter, and the resistance is integrated
    with ``points`` Gauss-Legendre points (``|dx/dt| dt`` the arc length).

    Args:
        r, z: Current radius and axial position of the nodes [m].
        u: Mean separation at the nodes [m] (> 0).
        pressure_drop: ``p_oil - p_air`` [Pa].
        viscosity: Dynamic viscosity [Pa s].
        flow_factor: Pressure flow factor ``phi_p(u)`` (numpy); None: 1 (smooth walls).
        points: Gauss-Legendre points per element.
    """
    r, z, u = (np.asarray(a, dtype=float) for a in (r, z, u))
    n = r.size
    if not (r.ndim == z.ndim == u.ndim == 1 and z.size == u.size == n >= 3 and n % 2 == 1):
        raise ParameterError(
            "static_leakage: r, z, u must be 1D arrays of one odd length >= 3 "
            "(vertex, mid-side node, vertex, ...)"
        )
    if np.any(u <= 0) or not np.all(np.isfinite(u)):
        raise ParameterError(
            f"static_leakage: separations must be finite and > 0 (min {u.min():.3g} m)"
        )
    if viscosity <= 0:
        raise ParameterError(f"viscosity = {viscosity!r} Pa s must be > 0")
    rr, uu, jac, w = _quadratic_band(r, z, u, points)
    if np.any(uu <= 0):
        raise ParameterError("static_leakage: the quadratic separation profile dips below 0")
    phi = np.ones_like(uu) if flow_factor is None else np.asarray(flow_factor(uu.ravel()))
    k = phi.reshape(uu.shape) * uu**3 / (12.0 * viscosity)
    resistance = float(np.sum(w[None, :] * jac / (2.0 * math.pi * rr * k)))
    return pressure_drop / resistance


def _quadratic_band(
    r: FloatArray, z: FloatArray, u: FloatArray, points: int
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Radius, separation and ``|dx/dt|`` at the Gauss points of every quadratic
    element (vertex, mid, vertex, ...), and the Gauss weights on (0, 1)."""
    xg, wg = np.polynomial.legendre.leggauss(int(points))
    t = 0.5 * (xg + 1.0)
    # quadratic Lagrange basis on (0, 1) with nodes 0, 1/2, 1 and its derivative
    N = np.stack([2 * (t - 0.5) * (t - 1), -4 * t * (t - 1), 2 * t * (t - 0.5)])
    dN = np.stack([4 * t - 3, -8 * t + 4, 4 * t - 1])

    def per_element(a: FloatArray, basis: FloatArray) -> FloatArray:
        e = np.stack([a[0:-1:2], a[1::2], a[2::2]], axis=1)  # (elements, 3)
        return e @ basis

    jac = np.hypot(per_element(r, dN), per_element(z, dN))
    return per_element(r, N), per_element(u, N), jac, 0.5 * wg


def hoop_shear_force(
    r: FloatArray,
    z: FloatArray,
    u: FloatArray,
    shear: Callable[[FloatArray], FloatArray],
    points: int = 16,
) -> float:
    """``int 2 pi r tau(u) ds`` [N] over a band of quadratic elements (as
    :func:`static_leakage`): the hoop friction force of a shear ``tau(u)`` [Pa]
    (times the shaft radius: the friction torque)."""
    r, z, u = (np.asarray(a, dtype=float) for a in (r, z, u))
    rr, uu, jac, w = _quadratic_band(r, z, u, points)
    tau = np.asarray(shear(uu.ravel())).reshape(uu.shape)
    return float(np.sum(w[None, :] * jac * 2.0 * math.pi * rr * tau))


def ihl_film(z: FloatArray, p: FloatArray, viscosity: float, speed: float) -> float:
    """IHL film thickness ``h* = sqrt(8 eta |U| / (9 w))`` [m] at the inlet side.

    ``w`` is the largest pressure gradient on the inlet side of the peak of the
    contact pressure profile ``p(z)`` (z increasing from oil to air): the oil
    side for ``speed > 0`` (out-stroke), the air side for ``speed < 0``.
    """
    z, p = np.asarray(z, float), np.asarray(p, float)
    if speed == 0.0:
        raise ParameterError("ihl_film: speed must be non-zero")
    i = int(np.argmax(p))
    grad = np.gradient(p, z)
    w = float(grad[: i + 1].max()) if speed > 0 else float(-grad[i:].min())
    if w <= 0:
        raise ParameterError("ihl_film: the pressure profile has no rising inlet side")
    return math.sqrt(8.0 * viscosity * abs(speed) / (9.0 * w))


def ihl_solution(
    z: FloatArray, p: FloatArray, viscosity: float, speed: float, radius: float
) -> dict[str, FloatArray | float]:
    """The inverse hydrodynamic film and friction of a rod sliding under ``p(z)``.

    Args:
        z: Axial positions [m], increasing from the oil to the air side.
        p: The contact pressure there [Pa] (the dry installed pressure).
        viscosity: eta [Pa s].
        speed: Rod speed U [m/s], positive towards the air side (out-stroke).
        radius: Rod radius R [m].

    Returns ``h_star`` (the film at the pressure peak) [m], ``flow`` ``2 pi R q``
    [m^3/s] (signed with U: out through the air end on the out-stroke),
    ``transport_film_thickness`` ``q/U = h*/2`` [m], ``film`` ``h(z)`` on the
    band where ``p > 0`` (``nan`` elsewhere) and ``friction_force`` [N]: ``sign(U)
    2 pi R int (eta U / h + (h/2) p') dz`` over that band, the drag opposing the
    rod (the FEM's sign convention: couette plus Poiseuille parts).
    """
    z, p = np.asarray(z, float), np.asarray(p, float)
    if speed == 0.0:
        raise ParameterError("ihl_solution: speed must be non-zero")
    sign = math.copysign(1.0, speed)
    # the flow runs along +x: x = z on the out-stroke, x = -z on the in-stroke
    x, pp = (z, p) if sign > 0 else (-z[::-1], p[::-1])
    u = abs(speed)
    h_star = ihl_film(x, pp, viscosity, u)
    q = 0.5 * u * h_star
    dp = np.gradient(pp, x)
    i_peak = int(np.argmax(pp))
    i_w = int(np.argmax(dp[: i_peak + 1]))
    h = np.full(x.size, np.nan)
    for j in np.flatnonzero(pp > 0.0):
        a = dp[j] / (12.0 * viscosity)
        if abs(a) * h_star**2 < 1e-12 * u:  # p' = 0: the film of the flow alone
            h[j] = 2.0 * q / u
            continue
        roots = np.roots([a, 0.0, -0.5 * u, q])
        pos = np.sort(roots[(np.abs(roots.imag) < 1e-9 * h_star) & (roots.real > 0)].real)
        if pos.size == 0:  # past the largest gradient (round-off): the double root
            h[j] = 3.0 * q / u
        elif a > 0.0 and j < i_w:
            h[j] = pos[-1]  # from the wide inlet down to the largest gradient
        else:
            h[j] = pos[0]
    band = np.isfinite(h)
    tau = viscosity * u / h + 0.5 * h * dp  # shear on the rod along the flow [Pa]
    integrand = np.where(band, tau, 0.0)
    force = 2.0 * math.pi * radius * float(np.trapezoid(integrand, x))
    film = h if sign > 0 else h[::-1]
    return {
        "h_star": h_star,
        "flow": sign * 2.0 * math.pi * radius * q,
        "transport_film_thickness": 0.5 * h_star,
        "film": film,
        "friction_force": force,
    }


__all__ = ["hoop_shear_force", "ihl_film", "ihl_solution", "static_leakage"]
