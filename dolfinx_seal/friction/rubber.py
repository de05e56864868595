"""Persson's hysteretic rubber friction ``mu(v)`` (S3 eqs 30-34).

For rubber (modulus ``E(omega)``, Poisson ratio ``nu``) sliding at speed ``v``
on a hard surface with spectrum ``C(q)`` under nominal pressure ``sigma_0``:

    mu = 1/2 int_{q_L}^{q_1} dq q^3 C(q) P(q) S(q),    S = int_0^{2 pi} dphi cos(phi)
         Im E(q v cos phi) / ((1 - nu^2) sigma_0)                          (S3 eq 30)
    P(q) = (2/pi) int_0^inf dx sin(x)/x exp(-x^2 G(q)) = erf(1 / (2 G^{1/2}))  (eq 31)
    P(q) ~= (1 + (pi G)^{3/2})^{-1/3}                                        (eq 34)
    G(q) = 1/8 int_{q_L}^{q} dq q^3 C int_0^{2 pi} dphi |E(q v cos phi)|^2 / ((1-nu^2) sigma_0)^2

The closed form of eq 31 follows from ``int_0^inf sin(a x)/x exp(-x^2 G) dx =
(pi/2) erf(a / (2 G^{1/2}))``; the tests check it against direct quadrature.
Assumptions (S3): isothermal (no flash temperature: ``E`` is taken at the bulk
temperature at every length scale), no adhesion, elastic contact (the
elastoplastic variant of S3 appendix C is in :mod:`dolfinx_seal.contact`),
frequency-independent ``nu``.

Numerics: ``phi`` integrals use ``int_0^{2 pi} = 4 int_0^{pi/2}`` (both
integrands are even in ``cos phi`` because ``E(-omega) = conj E(omega)``) on
8-point Gauss panels graded geometrically towards ``phi = pi/2``, where the
loss peak sits at ``cos phi = (1 + a) / (q v tau)`` for fast sliding; ``q``
integrals are trapezoidal in ``ln q`` (cumulative for ``G``) with nodes at
every node of the spectrum.  Everything is vectorised over velocities.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import minimize_scalar
from scipy.special import erf

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.friction.modulus import Modulus, check_poisson
from dolfinx_seal.params import check_choice, check_int_range, check_positive
from dolfinx_seal.roughness.psd import PowerSpectrum

FloatArray = NDArray[np.float64]


def _phi_nodes() -> tuple[FloatArray, FloatArray]:
    """Nodes ``cos(phi)`` and weights on ``[0, pi/2]`` graded towards ``phi = pi/2``."""
    t, w = np.polynomial.legendre.leggauss(8)
    edges = np.concatenate(([0.0], np.geomspace(1e-7, 0.1, 7), [0.35, 0.75, 1.15, math.pi / 2]))
    psi = (0.5 * (edges[1:, None] + edges[:-1, None]) + 0.5 * np.diff(edges)[:, None] * t).ravel()
    wt = (0.5 * np.diff(edges)[:, None] * w).ravel()
    return np.sin(psi), wt  # cos(phi) = sin(psi), psi = pi/2 - phi


def contact_function_exact(g: ArrayLike) -> FloatArray:
    """S3 eq 31: ``P = erf(1 / (2 G^{1/2}))`` (``P = 1`` at ``G = 0``)."""
    ga = np.asarray(g, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(ga > 0, erf(0.5 / np.sqrt(np.maximum(ga, 1e-300))), 1.0)


def contact_function_interpolated(g: ArrayLike) -> FloatArray:
    """S3 eq 34: ``P = (1 + (pi G)^{3/2})^{-1/3}``."""
    ga = np.asarray(g, dtype=float)
    return (1.0 + (math.pi * ga) ** 1.5) ** (-1.0 / 3.0)


class RubberFriction:
    """Viscoelastic (hysteretic) friction of rubber on a rough hard surface.

    Args:
        psd: Substrate spectrum; the integrals run over its support ``[q_L, q_1]``.
        modulus: ``E(omega)`` of the rubber (:mod:`dolfinx_seal.friction.modulus`).
        sigma0: Nominal pressure [Pa].
        nu: Poisson ratio of the rubber, ``0 <= nu <= 0.5``.
        contact: ``"exact"`` (eq 31) or ``"interpolated"`` (eq 34).
        points_per_decade: ``q`` nodes per decade.
    """

    def __init__(
        self,
        psd: PowerSpectrum,
        modulus: Modulus,
        sigma0: float,
        nu: float = 0.5,
        contact: str = "exact",
        points_per_decade: int = 60,
    ) -> None:
        self.psd = psd
        self.modulus = modulus
        self.sigma0 = check_positive("sigma0", sigma0, "Pa")
        self.nu = check_poisson(nu)
        self.contact = check_choice("contact", contact, ("exact", "interpolated"))
        check_int_range("points_per_decade", points_per_decade, 4)
        # First segment: ln(q/q_L) = T t^4 with t uniform.  G grows linearly from
        # 0 at q_L, so P ~ (pi G)^(-1/2) ~ t^-2 beyond a boundary layer that can be
        # far thinner than any grid (fast sliding, E glassy); with the Jacobian
        # 4 T t^3 the integrand is then ~ t, which the trapezoid rule integrates
        # with second-order accuracy.  Further segments (roll-off kinks) are
        # uniform in ln q.
        lq, jl, jr, ds = [np.array([math.log(psd.q_min)])], [], [], []
        for k, (a, b) in enumerate(zip(psd.q_nodes[:-1], psd.q_nodes[1:], strict=True)):
            span = math.log(b / a)
            n = max(4, math.ceil(math.log10(b / a) * points_per_decade * (4 if k == 0 else 1)))
            t = np.linspace(0.0, 1.0, n + 1)
            jac = 4.0 * span * t**3 if k == 0 else np.full(t.size, span)
            lq.append(math.log(a) + span * (t[1:] ** 4 if k == 0 else t[1:]))
            jl.append(jac[:-1])
            jr.append(jac[1:])
            ds.append(np.full(n, 1.0 / n))
        self.q = np.exp(np.concatenate(lq))
        # trapezoid in each segment's parameter: increment = (F_l J_l + F_r J_r) ds / 2
        self._jl, self._jr, self._ds = np.concatenate(jl), np.concatenate(jr), np.concatenate(ds)
        self._q4c = self.q**4 * psd(self.q)  # q^3 C dq = q^4 C dln q
        self._x, self._wx = _phi_nodes()
        self._scale = 1.0 / ((1.0 - self.nu**2) * self.sigma0)

    # ---------------------------------------------------------- phi integrals
    def angular_integrals(self, v: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(S_loss, S_abs)`` [Pa, Pa^2] on the ``q`` nodes for each speed, shape ``(nv, nq)``.

        ``S_loss = int_0^{2 pi} cos(phi) Im E(q v cos phi) dphi`` and
        ``S_abs = int_0^{2 pi} |E(q v cos phi)|^2 dphi``.
        """
        va = np.atleast_1d(np.asarray(v, dtype=float))
        if np.any(~np.isfinite(va)) or np.any(va <= 0):
            raise ParameterError("velocity must be finite and > 0 (m/s)")
        omega = va[:, None, None] * self.q[None, :, None] * self._x[None, None, :]
        e = self.modulus(omega)
        s_loss = 4.0 * (np.imag(e) * self._x) @ self._wx
        s_abs = 4.0 * (np.real(e) ** 2 + np.imag(e) ** 2) @ self._wx
        return s_loss, s_abs

    def _cumtrapz(self, f: FloatArray) -> FloatArray:
        """Cumulative ``int f dln q`` from ``q_L`` along the last axis (trapezoid per segment)."""
        inc = 0.5 * (f[..., :-1] * self._jl + f[..., 1:] * self._jr) * self._ds
        return np.concatenate((np.zeros((*f.shape[:-1], 1)), np.cumsum(inc, axis=-1)), axis=-1)

    def _evaluate(self, v: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(G, P, dmu/dln q)`` on the ``q`` nodes, shape ``(nv, nq)``."""
        s_loss, s_abs = self.angular_integrals(v)
        g = 0.125 * self._cumtrapz(self._q4c * s_abs * self._scale**2)
        p = (
            contact_function_exact(g)
            if self.contact == "exact"
            else contact_function_interpolated(g)
        )
        dmu = 0.5 * self._q4c * p * s_loss * self._scale
        return g, p, dmu

    # ------------------------------------------------------------- results
    def mu(self, v: ArrayLike, chunk: int = 64) -> FloatArray:
        """Friction coefficient ``mu(v)`` [-] for sliding speeds ``v > 0`` [m/s] (vectorised)."""
        va = np.asarray(v, dtype=float)
        flat = va.ravel()
        if np.any(~np.isfinite(flat)) or np.any(flat <= 0):
            raise ParameterError("velocity must be finite and > 0 (m/s)")
        out = np.empty(flat.size)
        for s in range(0, flat.size, chunk):
            _, _, dmu = self._evaluate(flat[s : s + chunk])
            out[s : s + chunk] = self._cumtrapz(dmu)[:, -1]
        return out.reshape(va.shape)

    def contact_function(self, v: float) -> tuple[FloatArray, FloatArray]:
        """``(zeta, P(zeta))``: relative contact area against magnification ``zeta = q/q_L``."""
        vv = check_positive("velocity", v, "m/s")
        _, p, _ = self._evaluate(np.array([vv]))
        return self.q / self.q[0], p[0]

    def g_function(self, v: float) -> FloatArray:
        """``G(q)`` of S3 eq 32 on the ``q`` nodes [-]."""
        vv = check_positive("velocity", v, "m/s")
        return self._evaluate(np.array([vv]))[0][0]

    def peak(self, v_lo: float = 1e-8, v_hi: float = 1e4, n: int = 121) -> tuple[float, float]:
        """``(v_peak [m/s], mu_peak)``: the maximum of ``mu(v)`` on ``[v_lo, v_hi]``.

        A log-spaced scan followed by a bounded refinement in ``ln v``.
        """
        check_positive("v_lo", v_lo, "m/s")
        if not v_hi > v_lo:
            raise ParameterError(f"v_hi = {v_hi!r} must exceed v_lo = {v_lo!r}")
        lv = np.linspace(math.log(v_lo), math.log(v_hi), n)
        m = self.mu(np.exp(lv))
        i = int(np.argmax(m))
        a, b = lv[max(i - 1, 0)], lv[min(i + 1, n - 1)]
        res = minimize_scalar(
            lambda x: -float(self.mu(np.array([math.exp(x)]))[0]),
            bounds=(a, b), method="bounded", options={"xatol": 1e-6},
        )  # fmt: skip
        return math.exp(res.x), -float(res.fun)
