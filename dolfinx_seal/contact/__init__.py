"""Asperity contact laws, flow factors and Persson's contact mechanics (numpy only).

Contact-law objects share the :class:`ContactLaw` interface (vectorised
``pressure(u)``, ``dpressure_du(u)``, ``area_fraction(p)``, ``separation(p)``):

* :class:`PerssonLaw` -- the full Persson relation (Yang-Persson), tabulated once
  per spectrum and ``E*``; :class:`PerssonExponentialLaw` -- its asymptote
  ``beta E* exp(-alpha u/h_rms)``; :class:`ClosedFormPersson` -- a UFL-friendly
  closed form fitted to it.
* :class:`GreenwoodWilliamson` (Gaussian / exponential summits),
  :class:`GreenwoodTripp`, :class:`BushGibsonThomas`; :func:`gw_function` is
  ``F_n(lambda)``.
* :mod:`~dolfinx_seal.contact.load_fraction` -- ``X(lambda)`` laws of S2 eqs 35-41.
* :class:`PatirCheng`, :class:`BruggemanFlowFactor` -- flow factors.
* :class:`PerssonTheory` -- ``G``, ``A(zeta)``, ``u(zeta)``, ``u1(zeta)``;
  :func:`elastoplastic_fractions` (S3 appendix C); :class:`FlatOnFlat` --
  viscous hydroplaning (S1 section 4).
"""

from dolfinx_seal.contact import load_fraction
from dolfinx_seal.contact.base import ContactLaw
from dolfinx_seal.contact.classic import (
    BushGibsonThomas,
    GreenwoodTripp,
    GreenwoodWilliamson,
    gw_function,
    gw_function_derivative,
)
from dolfinx_seal.contact.flow_factors import BruggemanFlowFactor, PatirCheng
from dolfinx_seal.contact.hydroplaning import FlatOnFlat, HydroplaningResult
from dolfinx_seal.contact.persson import ClosedFormPersson, PerssonExponentialLaw, PerssonLaw
from dolfinx_seal.contact.persson_theory import (
    MagnificationProfile,
    PerssonTheory,
    elastoplastic_fractions,
)

__all__ = [
    "BruggemanFlowFactor",
    "BushGibsonThomas",
    "ClosedFormPersson",
    "ContactLaw",
    "FlatOnFlat",
    "GreenwoodTripp",
    "GreenwoodWilliamson",
    "HydroplaningResult",
    "MagnificationProfile",
    "PatirCheng",
    "PerssonExponentialLaw",
    "PerssonLaw",
    "PerssonTheory",
    "elastoplastic_fractions",
    "gw_function",
    "gw_function_derivative",
    "load_fraction",
]
