"""Isoviscous-elastic (soft) EHL film thickness regressions for point contacts.

Hamrock & Dowson (1978), "Elastohydrodynamic lubrication of elliptical
contacts for materials of low elastic modulus I -- fully flooded
conjunction", J. Lubr. Technol. 100, 236-245 (also Hamrock, Schmid & Jacobson,
"Fundamentals of Fluid Film Lubrication", 2nd ed., eqs 19.9-19.10)::

    H_c   = h_c / R_x   = 7.32 (1 - 0.72 exp(-0.28 k)) U^0.64 W^-0.22
    H_min = h_min / R_x = 7.43 (1 - 0.85 exp(-0.31 k)) U^0.65 W^-0.21

with ``U = eta u_m / (E' R_x)``, ``W = F / (E' R_x^2)``, ``E' = 2 E*``
(``1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b``), ``u_m`` the mean
(entrainment) velocity of the two surfaces and ``k`` the ellipticity (1 for
a ball).  They are curve fits to the authors' own numerical solutions
(17 cases: ``k`` 1-12, speed and load each over one decade; the abstract
states no fit error), so an agreement of some per cent is what a comparison
can expect (h_min, on the side lobes of the horse-shoe, is the more sensitive
one).  The coefficient 8.70 found in some texts belongs to the later
``g_E`` form ``H_min = 8.70 g_E^0.67 (1 - 0.85 exp(-0.31 k))`` and must not
be used with U and W.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from dolfinx_seal.params import check_positive


@dataclass(frozen=True)
class IsoviscousElasticFilm:
    """Hamrock-Dowson isoviscous-elastic film thicknesses of a point contact (SI).

    Attributes:
        radius: Reduced radius R_x [m] (the ball radius on a flat).
        e_star: Effective modulus E* [Pa] (E' = 2 E*).
        viscosity: eta [Pa s].
        load: Normal load F [N].
        ellipticity: k = a / b (1 for a ball).
    """

    radius: float
    e_star: float
    viscosity: float
    load: float
    ellipticity: float = 1.0

    def __post_init__(self) -> None:
        check_positive("radius", self.radius, "m")
        check_positive("e_star", self.e_star, "Pa")
        check_positive("viscosity", self.viscosity, "Pa s")
        check_positive("load", self.load, "N")
        check_positive("ellipticity", self.ellipticity)

    def speed_parameter(self, u_mean: float) -> float:
        """``U = eta u_m / (E' R)`` [-] at the mean surface velocity ``u_mean`` [m/s]."""
        return self.viscosity * u_mean / (2.0 * self.e_star * self.radius)

    @property
    def load_parameter(self) -> float:
        """``W = F / (E' R^2)`` [-]."""
        return self.load / (2.0 * self.e_star * self.radius**2)

    def h_central(self, u_mean: float) -> float:
        """Central film thickness h_c [m]."""
        k = self.ellipticity
        c = 7.32 * (1.0 - 0.72 * math.exp(-0.28 * k))
        return self.radius * c * self.speed_parameter(u_mean) ** 0.64 * self.load_parameter**-0.22

    def h_min(self, u_mean: float) -> float:
        """Minimum film thickness h_min [m]."""
        k = self.ellipticity
        c = 7.43 * (1.0 - 0.85 * math.exp(-0.31 * k))
        return self.radius * c * self.speed_parameter(u_mean) ** 0.65 * self.load_parameter**-0.21

    def compare(self, sliding_speed: float, h_central: float, h_min: float) -> dict[str, float]:
        """A computed film against the regressions, for one surface sliding at
        ``sliding_speed`` [m/s] over a fixed one (u_m = U / 2).

        Returns ``speed``, ``h_central``, ``hd_h_central``, ``h_central_error``
        (relative), ``h_min``, ``hd_h_min``, ``h_min_error`` (lengths in m)."""
        u_m = 0.5 * sliding_speed
        hc, hm = self.h_central(u_m), self.h_min(u_m)
        return {
            "speed": sliding_speed, "h_central": h_central, "hd_h_central": hc,
            "h_central_error": h_central / hc - 1.0, "h_min": h_min, "hd_h_min": hm,
            "h_min_error": h_min / hm - 1.0,
        }  # fmt: skip

    def moes_load(self, u_mean: float) -> float:
        """Moes' dimensionless load of the point contact ``M = W U^(-3/4)`` [-] at the
        mean surface velocity ``u_mean`` [m/s] (``U``, ``W`` as above).  It grows as
        the speed falls: about 10 is the rigid-isoviscous end, hundreds and more the
        soft-EHL regime, where the film is a thin layer over a Hertz-like shape."""
        check_positive("u_mean", u_mean, "m/s")
        return self.load_parameter * self.speed_parameter(u_mean) ** -0.75

    def mean_speed_for_moes(self, moes: float) -> float:
        """The mean velocity u_m [m/s] at which Moes' ``M`` is ``moes`` [-]."""
        check_positive("moes", moes)
        u = (self.load_parameter / moes) ** (4.0 / 3.0)  # U = (W / M)^(4/3)
        return u * 2.0 * self.e_star * self.radius / self.viscosity

    def mean_speed_for_central(self, h_c: float) -> float:
        """The mean velocity u_m [m/s] at which the central film thickness is ``h_c`` [m]."""
        check_positive("h_c", h_c, "m")
        u1 = 1.0
        return u1 * (h_c / self.h_central(u1)) ** (1.0 / 0.64)


__all__ = ["IsoviscousElasticFilm"]
