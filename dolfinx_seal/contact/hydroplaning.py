"""Mean-field flat-on-flat sliding in a fluid: viscous hydroplaning (S1 section 4).

An elastic block with a nominally flat surface slides at speed ``v`` on a
rough rigid flat in a Newtonian fluid (viscosity ``eta``) under nominal
pressure ``p0``.  Observed at magnification ``zeta``, the load splits as
``p0 = p_cont(zeta) + p_fluid(zeta)`` (S1 eq 31); the area ``A(zeta) -
A(zeta + dzeta)`` that leaves contact carries, besides the mean fluid pressure
``p*`` of the non-contact region, the hydrodynamic excess ``kappa eta v
lambda(zeta) / u1(zeta)^2`` of a tilted junction (S1 eq 32, appendix C),
``lambda = L / zeta``.  With ``p_fluid = p* (1 - A/A0)`` the balance (S1 eq 33)
becomes

    dp*/dzeta = [-A'(zeta) / (A0 - A(zeta))] kappa eta v lambda(zeta) / u1(zeta)^2,

which integrates to S1 eq 34.  ``A(zeta)/A0 = erf(p_cont / (2 G^{1/2}))`` and
``u1(zeta)`` come from Persson's theory at the *reduced* load ``p_cont(zeta)``
(S1 text after eq 33), so ``A`` depends on the fluid load and each
magnification step is an implicit scalar equation.  With ``b = 1 - A/A0`` a
step from ``zeta_i`` to ``zeta_{i+1}`` applies S1 eq 33 as printed,

    p_fluid(b) = p_fluid,i + (b - b_i) (p*_i + K_i),    b = erfc((p0 - p_fluid(b)) / (2 G_{i+1}^{1/2})),

with ``p*_i = p_fluid,i / b_i`` and ``K_i = kappa eta v lambda / u1^2`` at the
interval midpoint (``u1`` at the load of the previous node).  The right side can fold over (the fluid load
lifts area out of contact, which raises the fluid load): the smallest root
``b >= b_i`` is the branch continuous with the dry contact, and when it
disappears the contact jumps -- at high enough ``eta v`` to ``A = 0`` at a
magnification below ``zeta_1``: viscous hydroplaning, the abrupt friction drop
of S1 figures 32-33.

Friction (S1 eq 35): ``sigma_f = sigma_1 A(zeta_1)/A0 + int_1^{zeta_1} dzeta
[-A'/A0] eta v / u1``, where ``zeta_1`` is where ``u1(zeta_1) = u_c`` (1 nm in
S1: the real contact is where the surfaces are closer than ``u_c``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq
from scipy.special import erfc

from dolfinx_seal.contact.persson_theory import PerssonTheory
from dolfinx_seal.params import check_int_range, check_nonnegative, check_positive
from dolfinx_seal.roughness.psd import PowerSpectrum

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class HydroplaningResult:
    """Solution of the flat-on-flat model at one ``eta v``.

    Attributes:
        eta_v: ``eta v`` [Pa m].
        zeta: Magnification nodes.
        area: ``A(zeta)/A0`` at the nodes.
        p_contact: ``p_cont(zeta)`` [Pa] at the nodes.
        p_fluid: ``p_fluid(zeta)`` [Pa] at the nodes.
        zeta_mid, u1: ``u1`` [m] at the interval midpoints (at the marched load).
        zeta1: Magnification where real contact ends: where ``u1 = u_c``, or where
            the contact area vanished when hydroplaning (the largest magnification
            when no area leaves contact at all).
        area1: ``A(zeta_1)/A0`` (0 when hydroplaning).
        p_contact1, p_fluid1: Load split at ``zeta_1`` [Pa].
        sigma_contact, sigma_fluid: Frictional shear stresses [Pa] (S1 eq 35).
        mu: ``(sigma_contact + sigma_fluid) / p0``.
        hydroplaning: True when the contact area vanished below ``zeta_1``.
    """

    eta_v: float
    zeta: FloatArray
    area: FloatArray
    p_contact: FloatArray
    p_fluid: FloatArray
    zeta_mid: FloatArray
    u1: FloatArray
    zeta1: float
    area1: float
    p_contact1: float
    p_fluid1: float
    sigma_contact: float
    sigma_fluid: float
    mu: float
    hydroplaning: bool


class FlatOnFlat:
    """S1 section 4 model for one roughness, modulus and nominal pressure.

    The Persson quantities ``u1(zeta, p_cont)`` are tabulated once (the costly
    part); :meth:`solve` is then cheap for any ``eta v``.

    Args:
        psd: Roughness spectrum of the rigid substrate.
        e_star: ``E*`` of the block [Pa].
        p0: Nominal pressure [Pa].
        sigma1: Frictional shear stress in the real contact area [Pa].
        kappa: Tilted-junction factor of S1 eq 32 (``~0.2``).
        gamma: Yang-Persson factor.
        u_contact: Separation ``u_c`` defining real contact [m] (S1: 1 nm).
        system_size: ``L`` in ``lambda = L/zeta`` [m]; default ``2 pi / q_L``.
        points_per_decade: Magnification nodes per decade.
        n_pressures: Table pressures between ``1e-8 p0`` and ``p0``.
    """

    def __init__(
        self,
        psd: PowerSpectrum,
        e_star: float,
        p0: float,
        sigma1: float = 1e6,
        kappa: float = 0.2,
        gamma: float = 0.4,
        u_contact: float = 1e-9,
        system_size: float | None = None,
        points_per_decade: int = 30,
        n_pressures: int = 48,
    ) -> None:
        self.theory = PerssonTheory(psd, e_star, gamma)
        self.p0 = check_positive("pressure", p0, "Pa")
        self.sigma1 = check_nonnegative("sigma1", sigma1, "Pa")
        self.kappa = check_positive("kappa", kappa)
        self.u_contact = check_positive("u_contact", u_contact, "m")
        self.system_size = (
            2.0 * math.pi / psd.q_min
            if not system_size
            else check_positive("system_size", system_size, "m")
        )
        check_int_range("points_per_decade", points_per_decade, 5)
        check_int_range("n_pressures", n_pressures, 8)
        th = self.theory
        nz = max(8, math.ceil(math.log10(th.zeta_max) * points_per_decade))
        self.zeta = np.geomspace(1.0, th.zeta_max * (1.0 - 1e-6), nz)
        self.zeta_mid = np.sqrt(self.zeta[1:] * self.zeta[:-1])
        self._sqrt_g = np.sqrt(th.g_function(self.zeta))
        self._table_p = np.geomspace(1e-8 * self.p0, self.p0, n_pressures)
        prof = th.profile(self._table_p, self.zeta)
        self._ln_u1 = np.log(np.maximum(prof.u1, 1e-300))  # (nz - 1, np)
        self._ln_tp = np.log(self._table_p)
        self.dry_area = prof.area[:, -1]

    def u1(self, i: int, p_cont: float) -> float:
        """``u1`` [m] at midpoint ``i`` for asperity load ``p_cont`` (log-log interpolation)."""
        lp = math.log(min(max(p_cont, self._table_p[0]), self.p0))
        return math.exp(float(np.interp(lp, self._ln_tp, self._ln_u1[i])))

    def solve(self, eta_v: float) -> HydroplaningResult:
        """March S1 eqs 31-35 in magnification for ``eta v`` [Pa m] (``>= 0``)."""
        ev = check_nonnegative("eta*velocity", eta_v, "Pa m")
        nz = self.zeta.size
        b = np.empty(nz)  # 1 - A/A0
        pf = np.empty(nz)  # p_fluid
        b[0] = float(erfc(self.p0 / (2.0 * max(self._sqrt_g[0], 1e-300))))
        pf[0] = 0.0
        u1 = np.empty(nz - 1)
        sig_f = np.zeros(nz - 1)
        lam = self.system_size / self.zeta_mid
        for i in range(nz - 1):
            u1[i] = self.u1(i, self.p0 - pf[i])
            kk = self.kappa * ev * lam[i] / u1[i] ** 2 if ev > 0 else 0.0
            b[i + 1], pf[i + 1] = self._step(b[i], pf[i], kk, self._sqrt_g[i + 1])
            sig_f[i] = (b[i + 1] - b[i]) * ev / u1[i]
            if u1[i] <= self.u_contact or b[i + 1] >= 1.0:
                # past zeta_1 (or no contact left): the rest does not enter eq 35
                b[i + 2 :], pf[i + 2 :], u1[i + 1 :] = b[i + 1], pf[i + 1], u1[i]
                break
        area = 1.0 - b
        p_fluid = pf
        p_cont = self.p0 - pf
        return self._finish(ev, area, p_cont, p_fluid, u1, sig_f)

    def _step(self, b_i: float, pf_i: float, kk: float, sg: float) -> tuple[float, float]:
        """Smallest root ``b >= b_i`` of the implicit step; returns ``(b, p_fluid)``."""
        if b_i >= 1.0:
            return 1.0, pf_i
        excess = (pf_i / b_i if b_i > 0 else 0.0) + kk  # p*_i + K_i

        def resid(bb: float) -> float:
            pc = self.p0 - pf_i - (bb - b_i) * excess
            return bb - float(erfc(max(pc, 0.0) / (2.0 * sg)))

        if resid(b_i) >= 0.0:
            return b_i, pf_i
        # scan upwards for the first sign change (the branch continuous with the
        # previous step), then refine; R(1) >= 0 always holds
        cand = b_i + (1.0 - b_i) * np.geomspace(1e-12, 1.0, 50)
        lo = b_i
        root = 1.0
        for c in cand:
            if resid(float(c)) >= 0.0:
                root = brentq(resid, lo, float(c), xtol=1e-300, rtol=1e-13)
                break
            lo = float(c)
        # the fluid cannot carry more than the whole load (jump to A = 0)
        return root, min(pf_i + (root - b_i) * excess, self.p0)

    def _finish(
        self,
        ev: float,
        area: FloatArray,
        p_cont: FloatArray,
        p_fluid: FloatArray,
        u1: FloatArray,
        sig_f: FloatArray,
    ) -> HydroplaningResult:
        lz, lzm = np.log(self.zeta), np.log(self.zeta_mid)
        below = np.nonzero(u1 <= self.u_contact)[0]
        lost = np.nonzero(area <= 0.0)[0]
        k_lost = int(lost[0]) if lost.size else None
        if (
            below.size
            and below[0] > 0
            and (k_lost is None or self.zeta[k_lost] > self.zeta_mid[below[0]])
        ):
            j = int(below[0])
            f = math.log(u1[j - 1] / self.u_contact) / math.log(u1[j - 1] / u1[j])
            lz1 = lzm[j - 1] + f * (lzm[j] - lzm[j - 1])
            area1 = float(np.interp(lz1, lz, area))
            pc1 = float(np.interp(lz1, lz, p_cont))
            sig_fluid = float(np.sum(sig_f[: j - 1]) + f * sig_f[j - 1])
            zeta1, hydro = math.exp(lz1), False
        elif k_lost is not None:
            area1, pc1, zeta1, hydro = 0.0, 0.0, float(self.zeta[k_lost]), True
            sig_fluid = float(np.sum(sig_f[:k_lost]))
        else:
            # no area leaves contact at any resolved magnification (p0 >~ E* slope):
            # contact everywhere up to q1
            area1, pc1, zeta1, hydro = (
                float(area[-1]),
                float(p_cont[-1]),
                float(self.zeta[-1]),
                False,
            )
            sig_fluid = float(np.sum(sig_f))
        sig_c = self.sigma1 * area1
        return HydroplaningResult(
            eta_v=ev, zeta=self.zeta, area=area, p_contact=p_cont, p_fluid=p_fluid,
            zeta_mid=self.zeta_mid, u1=u1, zeta1=zeta1, area1=area1, p_contact1=pc1,
            p_fluid1=self.p0 - pc1, sigma_contact=sig_c, sigma_fluid=sig_fluid,
            mu=(sig_c + sig_fluid) / self.p0, hydroplaning=hydro,
        )  # fmt: skip
