"""Mixed-lubrication load fraction ``X(lambda)`` (S2 section 7, eqs 35-41, Table 2).

``X = W_asp / W_total`` is the fraction of the load carried by the asperities
at the film-thickness ratio ``lambda = h / sigma`` (``h`` the separation of the
mean planes, ``sigma`` the combined rms roughness); the friction coefficient is
then ``f = mu_asp X + mu_fluid (1 - X)`` (S2 eq 3).  For the asperity models
``X = W(lambda) / W(0)`` (S2 section 7).

Domain: every law takes ``lambda >= 0`` (finite) and returns ``0 <= X <= 1``;
``lambda < 0`` raises ParameterError naming the law, the value and the range.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.special import erfc

from dolfinx_seal.contact.base import FloatArray, as_array
from dolfinx_seal.contact.classic import gw_function
from dolfinx_seal.params import check_choice, check_nonnegative, check_positive


def _lam(lam: ArrayLike, law: str) -> FloatArray:
    return as_array("lambda", lam, 0.0, lo_open=False, law=f"{law} load fraction")


def olver_spikes(lam: ArrayLike) -> FloatArray:
    """``X = (1 + lambda)^-2`` (S2 eq 36)."""
    x = _lam(lam, "olver_spikes")
    with np.errstate(over="ignore"):  # (1 + lambda)^2 = inf gives X = 0
        return 1.0 / (1.0 + x) ** 2


def power_fit(lam: ArrayLike, k: float = 1.5, a: float = 4.0 / 3.0) -> FloatArray:
    """``X = (1 + lambda^k)^-a`` (S2 eq 37, experimental fit ``k = 3/2``, ``a = 4/3``)."""
    check_positive("k", k)
    check_positive("a", a)
    x = _lam(lam, "power_fit")
    with np.errstate(over="ignore", under="ignore"):  # lambda^k = inf gives X = 0
        return (1.0 + x**k) ** (-a)


def coy_linear(lam: ArrayLike) -> FloatArray:
    """``X = 1 - lambda/3`` for ``lambda <= 3``, 0 beyond (S2 eq 38)."""
    return np.clip(1.0 - _lam(lam, "linear") / 3.0, 0.0, 1.0)


def gw_exponential(lam: ArrayLike, c: float = 1.0) -> FloatArray:
    """``X = exp(-c lambda)`` (S2 eq 39, GW with exponential summits)."""
    check_positive("c", c)
    return np.exp(-c * _lam(lam, "exponential"))


def greenwood_tripp(lam: ArrayLike, c: float = 1.0) -> FloatArray:
    """``X = F_{5/2}(c lambda) / F_{5/2}(0)`` (S2 eq 40)."""
    check_positive("c", c)
    return gw_function(2.5, c * _lam(lam, "greenwood_tripp")) / gw_function(2.5, np.array(0.0))


def bush_gibson_thomas(lam: ArrayLike) -> FloatArray:
    """``X = erfc(lambda / sqrt 2)`` (S2 eq 41)."""
    return erfc(_lam(lam, "bush_gibson_thomas") / math.sqrt(2.0))


#: The laws of S2 Table 2, by column.
LAWS = {
    "power_fit": power_fit,
    "exponential": gw_exponential,
    "linear": coy_linear,
    "olver_spikes": olver_spikes,
    "greenwood_tripp": greenwood_tripp,
    "bush_gibson_thomas": bush_gibson_thomas,
}


def mixed_friction(
    lam: ArrayLike, mu_asp: float, mu_fluid: float, law: str = "power_fit"
) -> FloatArray:
    """``f = mu_asp X + mu_fluid (1 - X)`` (S2 eq 3) with the named ``X(lambda)`` law."""
    check_choice("law", law, LAWS)
    check_nonnegative("mu_asp", mu_asp)
    check_nonnegative("mu_fluid", mu_fluid)
    x = LAWS[law](lam)
    return mu_asp * x + mu_fluid * (1.0 - x)
