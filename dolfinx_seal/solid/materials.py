"""Rubber material models: one small validated dataclass each, returning UFL energy.

Each model exposes

* ``strain_energy(F, p=None)`` -- the strain energy density per reference volume
  [J/m^3] of the 3x3 deformation gradient ``F``.  With ``p=None`` the model is
  compressible (volumetric penalty with the bulk modulus ``K``); with a pressure
  field ``p`` it is the perturbed-Lagrangian mixed form
  ``psi_iso(F) + p (J - 1) - p^2 / (2 K)`` which stays locking-free as
  ``nu -> 0.5`` (``1/K -> 0``; ``nu = 0.5`` is allowed only in this form);
* ``E``, ``nu``, ``mu``, ``K``, ``E_star`` (plane-strain modulus ``E/(1-nu^2)``) [Pa].

:class:`LinearElastic` is the small-strain model (energy of the small-strain
tensor, for linear comparisons); :class:`NeoHookean` and :class:`MooneyRivlin`
are hyperelastic.  Mooney-Rivlin (S0 section 3.1): ``psi = C10 (I1_bar - 3) +
C01 (I2_bar - 3) + U(J)`` with the small-strain shear modulus ``mu = 2 (C10 + C01)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import ufl

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_choice, check_positive, check_range


def _check_nu(nu: float, formulation: str) -> None:
    check_range("nu", nu, -1.0, 0.5, lo_open=True)
    if nu == 0.5 and formulation != "mixed":
        raise ParameterError(
            "nu = 0.5 (incompressible) needs formulation = 'mixed'; a compressible model "
            "needs nu in (-1, 0.5)"
        )


@dataclass(frozen=True)
class _Elastic:
    E: float = 10e6
    nu: float = 0.49
    formulation: str = "mixed"

    def __post_init__(self) -> None:
        check_positive("E", self.E, "Pa")
        check_choice("formulation", self.formulation, ("compressible", "mixed"))
        _check_nu(self.nu, self.formulation)

    @property
    def mu(self) -> float:
        """Shear modulus [Pa]."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def K(self) -> float:
        """Bulk modulus [Pa] (``inf`` for nu = 0.5)."""
        return math.inf if self.nu == 0.5 else self.E / (3.0 * (1.0 - 2.0 * self.nu))

    @property
    def inv_K(self) -> float:
        """``1/K`` [1/Pa] (0 for nu = 0.5)."""
        return 3.0 * (1.0 - 2.0 * self.nu) / self.E

    @property
    def E_star(self) -> float:
        """Plane-strain (Hertz) modulus ``E / (1 - nu^2)`` of the rubber on a rigid body [Pa]."""
        return self.E / (1.0 - self.nu**2)

    @property
    def mixed(self) -> bool:
        """True for the displacement-pressure formulation."""
        return self.formulation == "mixed"


def _volumetric(J: Any, p: Any, K: float, inv_K: float) -> Any:
    """Volumetric energy: penalty ``K/2 (ln J)^2`` or mixed ``p (J - 1) - p^2/(2K)``."""
    if p is None:
        return 0.5 * K * ufl.ln(J) ** 2
    return p * (J - 1.0) - 0.5 * inv_K * p**2


@dataclass(frozen=True)
class LinearElastic(_Elastic):
    """Small-strain isotropic elasticity (for comparisons with linear theory)."""

    name: str = "linear"

    def small_strain_energy(self, eps: Any, p: Any = None) -> Any:
        """``mu dev(e):dev(e) + K/2 tr(e)^2``, or mixed ``... + p tr(e) - p^2/(2K)`` [J/m^3]."""
        tr = ufl.tr(eps)
        dev = eps - tr / 3.0 * ufl.Identity(3)
        w = self.mu * ufl.inner(dev, dev)
        if p is None:
            return w + 0.5 * self.K * tr**2
        return w + p * tr - 0.5 * self.inv_K * p**2


@dataclass(frozen=True)
class NeoHookean(_Elastic):
    """Neo-Hookean: ``psi = mu/2 (I1_bar - 3) + U(J)`` (isochoric split)."""

    name: str = "neo-hookean"

    def strain_energy(self, F: Any, p: Any = None) -> Any:
        """Strain energy density [J/m^3]."""
        J = ufl.det(F)
        I1b = J ** (-2.0 / 3.0) * ufl.tr(F.T * F)
        return 0.5 * self.mu * (I1b - 3.0) + _volumetric(J, p, self.K, self.inv_K)


@dataclass(frozen=True)
class MooneyRivlin(_Elastic):
    """Mooney-Rivlin: ``psi = C10 (I1_bar - 3) + C01 (I2_bar - 3) + U(J)``.

    ``C10`` and ``C01`` follow from ``E``, ``nu`` and the split ``c01_ratio =
    C01 / (C10 + C01)`` (default 0.2, a common rubber value), so that the
    small-strain shear modulus is ``mu = 2 (C10 + C01)`` as for the other models.
    """

    c01_ratio: float = 0.2
    name: str = "mooney-rivlin"

    def __post_init__(self) -> None:
        super().__post_init__()
        check_range("c01_ratio", self.c01_ratio, 0.0, 1.0, hi_open=True)

    @property
    def C10(self) -> float:
        """[Pa]."""
        return 0.5 * self.mu * (1.0 - self.c01_ratio)

    @property
    def C01(self) -> float:
        """[Pa]."""
        return 0.5 * self.mu * self.c01_ratio

    def strain_energy(self, F: Any, p: Any = None) -> Any:
        """Strain energy density [J/m^3]."""
        J = ufl.det(F)
        C = F.T * F
        I1b = J ** (-2.0 / 3.0) * ufl.tr(C)
        I2b = J ** (-4.0 / 3.0) * 0.5 * (ufl.tr(C) ** 2 - ufl.tr(C * C))
        iso = self.C10 * (I1b - 3.0) + self.C01 * (I2b - 3.0)
        return iso + _volumetric(J, p, self.K, self.inv_K)


MATERIALS = {"linear": LinearElastic, "neo-hookean": NeoHookean, "mooney-rivlin": MooneyRivlin}


def make_material(model: str, **kw: Any) -> _Elastic:
    """Material by name (``linear``, ``neo-hookean``, ``mooney-rivlin``)."""
    check_choice("material", model, tuple(MATERIALS))
    return MATERIALS[model](**kw)
