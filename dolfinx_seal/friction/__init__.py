"""Viscoelastic rubber friction (numpy only).

* :mod:`~dolfinx_seal.friction.modulus` -- complex moduli ``E(omega)``:
  :class:`StandardLinearSolid` (S3 eq 38), :class:`PronySeries`,
  :class:`MasterCurve` with :func:`shift_factor` (WLF / Arrhenius).
* :mod:`~dolfinx_seal.friction.rubber` -- :class:`RubberFriction`, Persson's
  ``mu(v)`` and contact function ``P(q)`` (S3 eqs 30-34).
"""

from dolfinx_seal.friction.modulus import (
    MasterCurve,
    Modulus,
    PronySeries,
    StandardLinearSolid,
    shift_factor,
)
from dolfinx_seal.friction.rubber import (
    RubberFriction,
    contact_function_exact,
    contact_function_interpolated,
)

__all__ = [
    "MasterCurve",
    "Modulus",
    "PronySeries",
    "RubberFriction",
    "StandardLinearSolid",
    "contact_function_exact",
    "contact_function_interpolated",
    "shift_factor",
]
