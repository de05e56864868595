"""Persson's contact mechanics on a rough spectrum: contact area and mean separation.

Notation (S1 section 4, S3 section V, appendices B-C; SI units):

* ``q_L`` is the lowest wavevector of the spectrum (``q0``, or the roll-off end
  ``q_r``) and the magnification ``zeta = q / q_L``.
* ``G(q) = (pi/4) E*^2 int_{q_L}^{q} q'^3 C(q') dq'`` [Pa^2] (S1, after eq 35;
  S3 eq 32 divided by ``sigma_0^-2`` for a frequency-independent modulus).
* Apparent contact area at magnification ``zeta`` under nominal pressure ``p``:
  ``A/A0 = erf(p / (2 G^{1/2}))`` (S1; S0 eq 5 is the same at ``q = q1`` since
  ``2 G^{1/2} = E* <|grad h|^2>^{1/2} / sqrt 2``).
* Mean separation (Yang-Persson, S1 section 4 with ``q_L -> zeta q_L``):
  ``u(zeta, P) = sqrt(pi) int_{zeta q_L}^{q1} dq q^2 C w F(w P / E*)`` with
  ``w(q, zeta) = (pi int_{zeta q_L}^{q} q'^3 C dq')^{-1/2}`` and, substituting
  ``x = w p'/E*`` in the inner pressure integral,
  ``F(x0) = int_{x0}^inf dx/x [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2)
  = gamma E1(x0^2)/2 + 3 (1 - gamma) J(x0)``, ``J(x0) = int_{x0}^inf erf^2 e^{-x^2}/x dx``.
  ``P`` is the pressure in the apparent contact regions (``p0`` at ``zeta = 1``).

  S1 prints the lower limit of the ``p'`` integral as ``p(zeta')`` with
  ``zeta' = q/q0``; we use ``p(zeta)``, the pressure at the magnification being
  observed, because at ``zeta = 1`` the formula must reduce to the Yang-Persson
  relation ``u(p0)`` that S1 section 2 uses (refs [19, 23] there), whose lower
  limit is ``p0`` for every ``q``.

The ``q`` integral has an integrable ``(q - zeta q_L)^{-1/2}`` singularity of
``w`` at its lower end ``q_lo = zeta q_L``.  On the first interval ``[q_lo,
q_a]``, ``q_a = min(2 q_lo, next spectrum node, q1)``, it is removed by the
substitution ``q = q_lo + (q_a - q_lo) tau^6`` (``_TAU_POWER = 6``; ``n_tau``
Gauss-Legendre points in ``tau`` on ``[0, 1]``, ``dq = 6 (q_a - q_lo) tau^5
dtau``), with the inner integral ``int_{q_lo}^{q} q'^3 C dq'`` of ``w`` evaluated
in closed form for the local power law.  Then ``w ~ tau^-3`` and the integrand
in ``tau`` behaves at worst as ``tau^2 ln tau`` (the ``ln w`` of ``F`` in the
``p -> 0`` asymptote; for ``p > 0``, ``F(w p/E*)`` decays as ``w`` grows), smooth
enough for Gauss points (``tau^2`` would leave a ``ln tau`` singularity).
The rest is integrated in ``ln q`` with composite Gauss-Legendre panels that
break at every node of the piecewise power-law spectrum.

Domains: :meth:`PerssonTheory.area_fraction` takes ``p >= 0`` and gives
``0 <= A/A0 <= 1``; :meth:`PerssonTheory.mean_separation` takes ``p > 0`` and
gives finite ``u >= 0`` (0 once it underflows: from about 1.6, 6.3 and 63 ``E*`` for
H = 0.95, 0.8 and 0.6 on the S1 spectrum);
other inputs raise ParameterError naming the quantity, the value and the range.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline
from scipy.special import erf, erfc, exp1

from dolfinx_seal.contact.base import as_array
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range
from dolfinx_seal.roughness.psd import PowerSpectrum

FloatArray = NDArray[np.float64]

#: ``J(0) = int_0^inf erf(x)^2 exp(-x^2) / x dx`` (checked against quad in the tests).
_J_XMAX = 6.5
#: Power of the substitution ``q = q_lo + (q_a - q_lo) tau^m`` on the singular interval:
#: the integrand behaves as ``tau^(m/2 - 1) ln tau`` there, smooth enough for Gauss
#: points when m = 6.
_TAU_POWER = 6
#: Below this ``x0``, ``x0^2`` underflows: :func:`separation_kernel` uses the series of E1.
_X_SMALL = math.sqrt(np.finfo(float).tiny)


@lru_cache(maxsize=1)
def _j_spline() -> CubicSpline:
    """Spline of ``ln J(x)`` on ``[0, 6.5]``; above, ``J = E1(x^2)/2`` to < 1e-19 relative."""
    edges = np.linspace(0.0, _J_XMAX, 651)
    t, wt = np.polynomial.legendre.leggauss(12)
    a, b = edges[:-1, None], edges[1:, None]
    x = 0.5 * (a + b) + 0.5 * (b - a) * t
    fx = erf(x) ** 2 * np.exp(-x * x) / x
    panel = 0.5 * (edges[1:] - edges[:-1]) * (fx @ wt)
    tail = 0.5 * exp1(_J_XMAX**2)
    j = tail + np.concatenate((np.cumsum(panel[::-1])[::-1], [0.0]))
    return CubicSpline(edges, np.log(j))


def j_integral(x0: ArrayLike) -> FloatArray:
    """``J(x0) = int_{x0}^inf erf(x)^2 exp(-x^2) / x dx`` (``x0 >= 0``)."""
    x = np.asarray(x0, dtype=float)
    spl = _j_spline()
    big = x > _J_XMAX
    out = np.empty_like(x)
    out[~big] = np.exp(spl(np.maximum(x[~big], 0.0)))
    with np.errstate(over="ignore"):  # x^2 = inf: J = 0
        out[big] = 0.5 * exp1(x[big] ** 2)
    return out


def separation_kernel(x0: ArrayLike, gamma: float, ln_x0: ArrayLike | None = None) -> FloatArray:
    """``F(x0) = gamma E1(x0^2)/2 + 3 (1 - gamma) J(x0)`` (see the module docstring).

    Where ``x0^2`` would underflow (``x0 < 1.5e-154``, pressures below ~1e-140
    Pa) the exact small-argument form ``E1(y) = -gamma_E - ln y`` (the next term,
    ``y``, is below rounding) keeps ``F`` finite, with ``ln x0`` from ``ln_x0``
    when given (``x0`` itself may have underflowed to 0); else ``F(0) = inf``.
    """
    x = np.asarray(x0, dtype=float)
    with np.errstate(over="ignore"):
        e1 = 0.5 * exp1(np.maximum(x, _X_SMALL) ** 2)
    small = x < _X_SMALL
    if np.any(small):
        with np.errstate(divide="ignore"):
            lx = np.log(np.maximum(x, 0.0)) if ln_x0 is None else np.asarray(ln_x0, float)
        e1 = np.where(small, -0.5 * np.euler_gamma - lx, e1)
    return gamma * e1 + 3.0 * (1.0 - gamma) * j_integral(x)


def elastoplastic_fractions(
    g: ArrayLike, ratio: ArrayLike, method: str = "auto"
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(P_el, P_pl, P_non)`` of S3 appendix C (eqs C9-C10) for a yield stress.

    Args:
        g: ``G(q) / sigma_0^2`` [-] (S3 eq C11), ``>= 0``.
        ratio: ``sigma_0 / sigma_Y``, ``0 < ratio < 1`` (broadcast against ``g``).
        method: ``"auto"`` (below), or force ``"fourier"`` / ``"images"`` (for tests).

    The Fourier series C9-C10 are summed with their closed-form limits
    ``sum sin(n t)/n = (pi - t)/2`` and ``sum (-1)^n sin(n t)/n = -t/2`` (``t =
    pi ratio``) so only the decaying ``exp(-n^2 t^2 g)`` terms are summed; where
    ``t^2 g < 1e-3`` that needs too many terms and the equivalent image series of
    the diffusion problem (absorbing walls at 0 and ``sigma_Y``) is used,
    ``P_non = sum_k sgn(c_k) erfc(|c_k| / (2 g^{1/2}))``, ``c_k = 1 + 2 k / ratio``
    (and ``c_k = 1/ratio - 1 + 2 k / ratio`` for ``P_pl``).
    """
    ga, ra = np.broadcast_arrays(np.asarray(g, dtype=float), np.asarray(ratio, dtype=float))
    if np.any(~np.isfinite(ga)) or np.any(ga < 0):
        raise ParameterError("g = G/sigma_0^2 must be finite and >= 0")
    if np.any(~np.isfinite(ra)) or np.any(ra <= 0) or np.any(ra >= 1):
        raise ParameterError("sigma_0/sigma_Y is outside the allowed range (0, 1)")
    ga, ra = ga.ravel(), ra.ravel()
    t = math.pi * ra
    p_non = np.zeros_like(ga)
    p_pl = np.zeros_like(ga)
    check_choice("method", method, ("auto", "fourier", "images"))
    four = ga * t * t >= 1e-3 if method == "auto" else np.full(ga.shape, method == "fourier")
    if method == "fourier" and np.any(ga * t * t < 1e-6):
        raise ParameterError("method='fourier' needs g (pi ratio)^2 >= 1e-6 (else use images)")
    if np.any(four):
        gg, tt = ga[four], t[four]
        nmax = math.ceil(math.sqrt(45.0 / np.min(tt * tt * gg))) + 1
        n = np.arange(1, nmax + 1)[None, :]
        dec = np.exp(-gg[:, None] * (n * tt[:, None]) ** 2)
        s = np.sin(n * tt[:, None]) / n
        p_non[four] = 1.0 - tt / math.pi - (2.0 / math.pi) * np.sum(dec * s, axis=1)
        p_pl[four] = tt / math.pi + (2.0 / math.pi) * np.sum(dec * s * (-1.0) ** n, axis=1)
    img = ~four
    if np.any(img):
        sg = 2.0 * np.sqrt(ga[img])[:, None]
        r = ra[img][:, None]
        k = np.arange(-6, 7)[None, :]
        c_non = 1.0 + 2.0 * k / r
        c_pl = (1.0 / r - 1.0) + 2.0 * k / r
        with np.errstate(divide="ignore"):
            p_non[img] = np.sum(np.sign(c_non) * erfc(np.abs(c_non) / sg), axis=1)
            p_pl[img] = np.sum(np.sign(c_pl) * erfc(np.abs(c_pl) / sg), axis=1)
    shape = np.broadcast_shapes(np.shape(g), np.shape(ratio))
    p_non = np.clip(p_non, 0.0, 1.0).reshape(shape)
    p_pl = np.clip(p_pl, 0.0, 1.0).reshape(shape)
    return np.clip(1.0 - p_non - p_pl, 0.0, 1.0), p_pl, p_non


@dataclass(frozen=True)
class MagnificationProfile:
    """Persson quantities against magnification for a set of nominal pressures.

    Attributes:
        zeta: Magnification nodes, shape ``(nz,)``.
        pressure: Nominal pressures [Pa], shape ``(np,)``.
        area: ``A(zeta)/A0`` at the nodes, ``(nz, np)``.
        mean_separation: ``u(zeta)`` at the nodes [m], ``(nz, np)``.
        zeta_mid: Geometric midpoints of the node intervals, ``(nz - 1,)``.
        u1: ``u1(zeta) = u + u' A/A'`` at the midpoints [m], ``(nz - 1, np)``.
        area_drop: ``A_i - A_{i+1}`` (area leaving contact per interval), ``(nz - 1, np)``.
        h_band: ``h_rms(zeta_mid)`` of S1 footnote 4 [m], ``(nz - 1,)``.
    """

    zeta: FloatArray
    pressure: FloatArray
    area: FloatArray
    mean_separation: FloatArray
    zeta_mid: FloatArray
    u1: FloatArray
    area_drop: FloatArray
    h_band: FloatArray


class PerssonTheory:
    """Contact area and mean separation of Persson's theory for one spectrum and ``E*``.

    Args:
        psd: Roughness spectrum of the combined surface.
        e_star: Effective modulus ``E* = E / (1 - nu^2)`` [Pa].
        gamma: Yang-Persson energy correction factor, ``0 < gamma <= 1`` (S1 uses 0.4).
        n_tau: Gauss points on the first, singular interval of the ``q`` integral.
        panels_per_decade: Gauss-Legendre panels (8 points each) per decade of ``q``.
    """

    def __init__(
        self,
        psd: PowerSpectrum,
        e_star: float,
        gamma: float = 0.4,
        n_tau: int = 48,
        panels_per_decade: int = 4,
    ) -> None:
        self.psd = psd
        self.e_star = check_positive("e_star", e_star, "Pa")
        self.gamma = check_range("gamma", gamma, 0.0, 1.0, lo_open=True)
        self.n_tau = check_int_range("n_tau", n_tau, 4)
        self.panels_per_decade = check_int_range("panels_per_decade", panels_per_decade, 1)
        self.q_lo = psd.q_min
        self.zeta_max = psd.q_max / psd.q_min
        self._tau = np.polynomial.legendre.leggauss(self.n_tau)
        self._gl8 = np.polynomial.legendre.leggauss(8)

    # ------------------------------------------------------------------ area
    def _zeta(self, zeta: ArrayLike) -> FloatArray:
        z = np.asarray(zeta, dtype=float)
        if np.any(~np.isfinite(z)) or np.any(z < 1.0) or np.any(z > self.zeta_max * (1 + 1e-12)):
            raise ParameterError(f"zeta must lie in [1, zeta_max = {self.zeta_max:g}]")
        return z

    def g_function(self, zeta: ArrayLike) -> FloatArray:
        """``G(zeta q_L)`` [Pa^2], ``1 <= zeta <= zeta_max``."""
        z = self._zeta(zeta)
        return 0.25 * math.pi * self.e_star**2 * self.psd.cumulative(3.0, z * self.q_lo)

    def dg_dzeta(self, zeta: ArrayLike) -> FloatArray:
        """``dG/dzeta = (pi/4) E*^2 q^3 C(q) q_L`` at ``q = zeta q_L`` [Pa^2]."""
        q = self._zeta(zeta) * self.q_lo
        return 0.25 * math.pi * self.e_star**2 * q**3 * self.psd(q) * self.q_lo

    def area_fraction(self, p: ArrayLike, zeta: ArrayLike | None = None) -> FloatArray:
        """``A(zeta)/A0 = erf(p / (2 G^{1/2}))`` for nominal pressure ``p`` [Pa] (default q = q1)."""
        pa = as_array("p", p, 0.0, lo_open=False, law="persson-theory", unit="Pa")
        g = self.g_function(self.zeta_max if zeta is None else zeta)
        with np.errstate(divide="ignore"):
            return erf(pa / (2.0 * np.sqrt(g)))

    def contact_pressure_in_area(self, p: ArrayLike, zeta: ArrayLike) -> FloatArray:
        """``p(zeta) = p A0 / A(zeta)`` [Pa], the mean pressure in the apparent contact area.

        For ``p << G^{1/2}`` the ratio tends to ``(pi G)^{1/2}``; that limit is used
        where ``erf`` would lose its digits.
        """
        pa, g = np.broadcast_arrays(np.asarray(p, float), self.g_function(zeta))
        x = pa / (2.0 * np.sqrt(np.maximum(g, 1e-300)))
        small = x < 1e-6
        out = np.empty_like(x)
        out[small] = np.sqrt(math.pi * g[small]) / (1.0 - x[small] ** 2 / 3.0)
        out[~small] = pa[~small] / erf(x[~small])
        return out

    # ------------------------------------------------------------ separation
    def _nodes(self, zeta: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Quadrature nodes ``q``, weights and ``w(q, zeta)`` for the separation integral."""
        psd = self.psd
        q_lo = zeta * self.q_lo
        q_hi = psd.q_max
        nxt = psd.q_nodes[psd.q_nodes > q_lo * (1.0 + 1e-12)]
        q_a = min(2.0 * q_lo, float(nxt[0]) if nxt.size else q_hi, q_hi)
        # singular interval: q = q_lo + (q_a - q_lo) tau^m (m = _TAU_POWER = 6),
        # tau in [0, 1]; w from the exact local int q^3 C of the power-law segment
        t, wt = self._tau
        tau = 0.5 * (t + 1.0)
        m = _TAU_POWER
        delta = (q_a - q_lo) * tau**m
        qa = q_lo + delta
        wa = 0.5 * wt * m * (q_a - q_lo) * tau ** (m - 1)
        seg = min(int(np.searchsorted(psd.q_nodes, q_lo, side="right")) - 1, psd.exponents.size - 1)
        k = 4.0 + psd.exponents[seg]
        lr = np.log1p(delta / q_lo)  # ln(q / q_lo), exact even where q_lo + delta rounds to q_lo
        x = k * lr
        local = (
            psd(np.array([q_lo]))[0]
            * q_lo**4
            * np.where(
                np.abs(x) < 1e-12, lr * (1.0 + 0.5 * x), np.expm1(x) / (k if k != 0 else 1.0)
            )
        )
        ww = [1.0 / np.sqrt(math.pi * local)]
        qs, ws = [qa], [wa]
        if q_a < q_hi * (1.0 - 1e-12):
            brk = np.concatenate(([q_a], nxt[(nxt > q_a) & (nxt < q_hi)], [q_hi]))
            t8, w8 = self._gl8
            base = psd.cumulative(3.0, q_lo)
            for a, b in itertools.pairwise(brk):
                npan = max(1, math.ceil(math.log10(b / a) * self.panels_per_decade))
                e = np.linspace(math.log(a), math.log(b), npan + 1)
                la = 0.5 * (e[:-1, None] + e[1:, None]) + 0.5 * (e[1:, None] - e[:-1, None]) * t8
                qb = np.exp(la).ravel()
                wb = (0.5 * (e[1:, None] - e[:-1, None]) * w8).ravel() * qb
                wint = psd.cumulative(3.0, qb) - base
                qs.append(qb)
                ws.append(wb)
                ww.append(1.0 / np.sqrt(math.pi * wint))
        q = np.concatenate(qs)
        return q, np.concatenate(ws) * q**2 * psd(q), np.concatenate(ww)

    def _ln_x0(self, x0: FloatArray, p: FloatArray, w: FloatArray) -> FloatArray | None:
        """``ln(w p / E*)`` without underflow, where ``x0`` is tiny (else None)."""
        if np.min(x0) >= _X_SMALL:
            return None
        return np.log(p)[:, None] - math.log(self.e_star) + np.log(w)[None, :]

    def mean_separation(self, pressure: ArrayLike, zeta: float = 1.0) -> FloatArray:
        """Mean separation ``u(zeta, P)`` [m] in the apparent contact area at magnification zeta.

        Args:
            pressure: ``P`` [Pa], the pressure in the apparent contact regions
                (the nominal pressure ``p0`` at ``zeta = 1``); any shape, ``> 0``.
            zeta: Magnification ``1 <= zeta < zeta_max``.
        """
        pa = as_array("pressure", pressure, 0.0, law="persson-theory", unit="Pa")
        z = check_range("zeta", zeta, 1.0, self.zeta_max, hi_open=True)
        q, wq, w = self._nodes(z)
        out = np.empty(pa.size)
        flat = pa.ravel()
        step = max(1, 2_000_000 // q.size)
        for s in range(0, flat.size, step):
            chunk = flat[s : s + step]
            x0 = np.outer(chunk / self.e_star, w)
            kern = separation_kernel(x0, self.gamma, self._ln_x0(x0, chunk, w))
            out[s : s + step] = kern @ (wq * w)
        return math.sqrt(math.pi) * out.reshape(pa.shape)

    def separation_rows(self, zetas: ArrayLike, pressures: ArrayLike) -> FloatArray:
        """``u(zeta_i, P_ij)`` [m] for a row of pressures per magnification.

        Args:
            zetas: Magnifications, shape ``(nz,)``, each in ``[1, zeta_max)``.
            pressures: ``P`` [Pa], shape ``(nz, np)`` (or broadcastable), ``> 0``.
        """
        z = np.asarray(zetas, dtype=float).ravel()
        pa = np.broadcast_to(np.asarray(pressures, dtype=float), (z.size, np.shape(pressures)[-1]))
        as_array("pressure", pa, 0.0, law="persson-theory", unit="Pa")
        out = np.empty(pa.shape)
        for i, zi in enumerate(z):
            _q, wq, w = self._nodes(float(zi))
            x0 = np.outer(pa[i] / self.e_star, w)
            out[i] = separation_kernel(x0, self.gamma, self._ln_x0(x0, pa[i], w)) @ (wq * w)
        return math.sqrt(math.pi) * out

    def profile(self, pressures: ArrayLike, zetas: ArrayLike) -> MagnificationProfile:
        """Area, mean separation and ``u1`` against magnification for nominal pressures.

        Args:
            pressures: Nominal (asperity) pressures ``p`` [Pa], shape ``(np,)``.
            zetas: Increasing magnifications from 1 to ``< zeta_max``, shape ``(nz,)``.
        """
        p = np.asarray(pressures, dtype=float).ravel()
        z = np.asarray(zetas, dtype=float).ravel()
        if z[0] < 1.0 or np.any(np.diff(z) <= 0) or z[-1] >= self.zeta_max:
            raise ParameterError("zetas must increase from >= 1 to below zeta_max")
        g = self.g_function(z)[:, None]
        x = p[None, :] / (2.0 * np.sqrt(np.maximum(g, 1e-300)))
        b = erfc(x)  # 1 - A/A0, accurate where A ~ 1
        ubar = self.separation_rows(z, self.contact_pressure_in_area(p[None, :], z[:, None]))
        da = b[1:] - b[:-1]  # A_i - A_{i+1} >= 0
        a_mid = 1.0 - 0.5 * (b[1:] + b[:-1])
        u_mid = 0.5 * (ubar[1:] + ubar[:-1])
        # u1 = u + u' A / A' (S1 section 4), with u' A/A' >= 0 so u1 >= u.  Where
        # almost no area leaves contact (da < 1e-12, A ~ 1 at low magnification)
        # the quotient is rounding noise and u1 is undefined: those intervals carry
        # no weight, and u1 is set to 1 m (no hydrodynamic excess, never "in contact").
        ok = da > 1e-12
        ratio = np.where(ok, (ubar[:-1] - ubar[1:]) / np.where(ok, da, 1.0), 0.0)
        u1 = np.where(ok, np.clip(u_mid + ratio * a_mid, u_mid, 1.0), 1.0)
        zm = np.sqrt(z[1:] * z[:-1])
        return MagnificationProfile(z, p, 1.0 - b, ubar, zm, u1, da, self.psd.h_rms_band(zm))

    def asymptote(self) -> tuple[float, float]:
        """``(alpha, beta)`` of ``p = beta E* exp(-alpha u / h_rms)`` as ``p -> 0`` (analytic).

        From ``F(x0) = -gamma ln x0 + K + o(1)``, ``K = -gamma gamma_E/2 + 3 (1-gamma) J(0)``:
        ``h_rms/alpha = sqrt(pi) gamma I1`` and ``ln beta = int q^2 C w (K - gamma ln w) dq /
        (gamma I1)`` with ``I1 = int q^2 C w dq``.
        """
        _q, wq, w = self._nodes(1.0)
        i1 = float(np.sum(wq * w))
        kk = -self.gamma * np.euler_gamma / 2.0 + 3.0 * (1.0 - self.gamma) * float(j_integral(0.0))
        i2 = float(np.sum(wq * w * (kk - self.gamma * np.log(w))))
        alpha = self.psd.h_rms() / (math.sqrt(math.pi) * self.gamma * i1)
        beta = math.exp(i2 / (self.gamma * i1))
        return alpha, beta
