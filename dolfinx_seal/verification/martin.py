"""Rigid cylinder on a plane, isoviscous Reynolds film with the Reynolds cavitation
condition (Martin 1916; the classical "half-Sommerfeld with Reynolds exit"
solution), computed independently of the FEM code.

Dimensionless form: gap ``H = 1 + X^2`` with ``X = x / sqrt(2 R h0)``, pressure
``P = p / p_ref`` with ``p_ref = 24 eta R U_m / (h0 sqrt(2 R h0))``, so that

    d/dX ( H^3 dP/dX ) = dH/dX,   P(-X_in) = 0,   P(X_c) = P'(X_c) = 0.

In the full film the flux ``H - H^3 P'`` is constant and equals ``H_c = 1 + X_c^2``
(since ``P'(X_c) = 0``), hence ``P(X) = int_{-X_in}^X (H - H_c)/H^3``.  With the
closed-form antiderivatives of ``(1+X^2)^-2`` and ``(1+X^2)^-3`` the condition
``P(X_c) = 0`` is a scalar equation solved by Brent's method to machine
precision, and the load ``W = int P dX`` by adaptive quadrature.

For an infinitely long inlet the classical values are ``X_c = 0.4751`` and
``w = 4.896 eta U_m R / h0`` per unit length (``W = 0.2040``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

from scipy.integrate import quad
from scipy.optimize import brentq

from dolfinx_seal.params import check_positive


def _i2(x: float) -> float:
    """Antiderivative of (1 + x^2)^-2 that vanishes at -inf.

    ``atan(x) + pi/2`` is written ``atan2(1, -x)``, exact also for large negative x,
    so that differences of antiderivatives in the far inlet keep their digits.
    """
    return x / (2.0 * (1.0 + x * x)) + 0.5 * math.atan2(1.0, -x)


def _i3(x: float) -> float:
    """Antiderivative of (1 + x^2)^-3 that vanishes at -inf."""
    s = 1.0 + x * x
    return x / (4.0 * s * s) + 3.0 * x / (8.0 * s) + 3.0 / 8.0 * math.atan2(1.0, -x)


def pressure(x: float, x_in: float, x_c: float) -> float:
    """Dimensionless full-film pressure ``P(X)`` for an inlet at ``-x_in`` and exit ``x_c``."""
    h_c = 1.0 + x_c * x_c
    return (_i2(x) - _i2(-x_in)) - h_c * (_i3(x) - _i3(-x_in))


@dataclass(frozen=True)
class MartinSolution:
    """Reference solution.

    Attributes:
        x_in: Inlet distance (the inlet is at ``X = -x_in``) [-].
        x_cavitation: Film rupture position ``X_c`` [-].
        load: Dimensionless load ``W = int P dX`` [-].
        flux: Dimensionless flux ``H_c = 1 + X_c^2`` [-].
        p_max: Maximum dimensionless pressure [-].
        x_p_max: Its position (``X = -X_c`` by symmetry of ``H - H_c``) [-].
    """

    x_in: float
    x_cavitation: float
    load: float
    flux: float
    p_max: float
    x_p_max: float


def martin_solution(x_in: float = math.inf) -> MartinSolution:
    """The rigid-cylinder Reynolds-condition solution for an inlet at ``-x_in``."""
    if not math.isinf(x_in):
        check_positive("x_in", x_in)
    xin = 1e12 if math.isinf(x_in) else float(x_in)
    # P(x_c) as a function of x_c: negative for x_c -> 0+, positive for large x_c.
    x_c = brentq(lambda xc: pressure(xc, xin, xc), 1e-6, 5.0, xtol=1e-15, rtol=1e-15)
    # Near field [-min(x_in, 50), x_c] split at the pressure peak (X = -X_c, where
    # H = H_c) and at 0; the far inlet tail [-x_in, -50] in s = ln(-X), where the
    # integrand P(-e^s) e^s is smooth and decays like e^(-2s).
    load = 0.0
    edges = [-min(xin, 50.0), -x_c, 0.0, x_c]
    for a, b in itertools.pairwise(edges):
        val, _ = quad(pressure, a, b, args=(xin, x_c), epsabs=1e-15, epsrel=1e-13, limit=400)
        load += val
    if xin > 50.0:
        tail, _ = quad(
            lambda s: pressure(-math.exp(s), xin, x_c) * math.exp(s),
            math.log(50.0), math.log(xin), epsabs=1e-15, epsrel=1e-12, limit=400,
        )  # fmt: skip
        load += tail
    return MartinSolution(
        x_in=float(x_in),
        x_cavitation=x_c,
        load=load,
        flux=1.0 + x_c * x_c,
        p_max=pressure(-x_c, xin, x_c),
        x_p_max=-x_c,
    )
