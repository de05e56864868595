"""Isotropic surface-roughness power spectra C(q) and their moments.

Every spectrum here is stored as a *piecewise power law*: nodes ``q_k`` with
values ``C_k`` and ``C(q) = C_k (q / q_k)^{e_k}`` on ``[q_k, q_{k+1}]``, zero
outside ``[q_min, q_max]``.  That covers the self-affine model with cut-offs and
an optional roll-off plateau (S0 eq 16, S1 section 4, S3 eq 35) exactly, and a
measured ``(q, C)`` table as log-log linear interpolation.  Integrals
``int q^m C(q) dq`` are then evaluated in closed form, segment by segment, so
moments and the cumulative integrals the contact theories need carry no
quadrature error.

Conventions (S1 eq after 35, S0 eq 16): ``C(q) = (2 pi)^-2 int d^2x <h(x) h(0)>
exp(-i q.x)`` [m^4], so ``<h^2> = 2 pi int q C dq``, ``<|grad h|^2> = 2 pi int
q^3 C dq`` and ``<(lap h)^2> = 2 pi int q^5 C dq``.  Wavevectors in 1/m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import (
    check_choice,
    check_nonnegative,
    check_positive,
    check_range,
    check_types,
)

FloatArray = NDArray[np.float64]


def _power_integral(k: FloatArray, log_ratio: FloatArray) -> FloatArray:
    """``int_1^r s^(k-1) ds = (r^k - 1)/k`` with ``r = exp(log_ratio)`` (``ln r`` when k = 0)."""
    k = np.asarray(k, dtype=float)
    x = k * log_ratio
    small = np.abs(x) < 1e-12
    safe_k = np.where(small, 1.0, k)
    return np.where(small, log_ratio * (1.0 + 0.5 * x), np.expm1(x) / safe_k)


class PowerSpectrum:
    """An isotropic power spectrum, piecewise power law between its nodes.

    Args:
        q_nodes: Strictly increasing wavevectors [1/m], at least two.
        c_nodes: ``C`` at the nodes [m^4], positive.

    Attributes:
        q_min, q_max: The support of ``C`` [1/m]; ``C = 0`` outside.
    """

    def __init__(self, q_nodes: ArrayLike, c_nodes: ArrayLike) -> None:
        q = np.asarray(q_nodes, dtype=float).ravel()
        c = np.asarray(c_nodes, dtype=float).ravel()
        if q.size < 2 or q.size != c.size:
            raise ParameterError(
                f"a power spectrum needs at least two (q, C) nodes of equal count, "
                f"got {q.size} q and {c.size} C values"
            )
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(c))):
            raise ParameterError("power spectrum nodes must be finite numbers")
        if q[0] <= 0 or np.any(np.diff(q) <= 0):
            raise ParameterError("power spectrum q nodes must be positive and strictly increasing")
        if np.any(c <= 0):
            raise ParameterError("power spectrum C values must be positive (m^4)")
        self.q_nodes = q
        self.c_nodes = c
        self._lq = np.log(q)
        self._lc = np.log(c)
        self.exponents = np.diff(self._lc) / np.diff(self._lq)
        self.q_min = float(q[0])
        self.q_max = float(q[-1])
        self._cum: dict[object, FloatArray] = {}

    # ------------------------------------------------------------------ values
    def __call__(self, q: ArrayLike) -> FloatArray:
        """``C(q)`` [m^4]; zero outside ``[q_min, q_max]``.

        The ends are matched with a relative tolerance of 1e-12 so that a grid
        built as ``exp(log(q_max))`` does not lose its last node to rounding.
        """
        qa = np.asarray(q, dtype=float)
        out = np.zeros_like(qa)
        inside = (qa >= self.q_min * (1.0 - 1e-12)) & (qa <= self.q_max * (1.0 + 1e-12))
        if np.any(inside):
            lq = np.clip(np.log(qa[inside]), self._lq[0], self._lq[-1])
            out[inside] = np.exp(np.interp(lq, self._lq, self._lc))
        return out

    # --------------------------------------------------------------- integrals
    def _segment_integrals(self, m: float) -> FloatArray:
        """``int_{q_k}^{q_{k+1}} q^m C dq`` for every segment."""
        k = m + self.exponents + 1.0
        base = self.c_nodes[:-1] * self.q_nodes[:-1] ** (m + 1.0)
        return base * _power_integral(k, np.diff(self._lq))

    def cumulative(self, m: float, q: ArrayLike) -> FloatArray:
        """``W_m(q) = int_{q_min}^{q} q'^m C(q') dq'`` (vectorised in ``q``, exact).

        ``q`` below ``q_min`` gives 0, above ``q_max`` the full integral.
        """
        if m not in self._cum:
            self._cum[m] = np.concatenate(([0.0], np.cumsum(self._segment_integrals(m))))
        cum = self._cum[m]
        qa = np.clip(np.asarray(q, dtype=float), self.q_min, self.q_max)
        idx = np.clip(np.searchsorted(self.q_nodes, qa, side="right") - 1, 0, self.q_nodes.size - 2)
        qk = self.q_nodes[idx]
        k = m + self.exponents[idx] + 1.0
        part = self.c_nodes[idx] * qk ** (m + 1.0) * _power_integral(k, np.log(qa / qk))
        return cum[idx] + part

    def tail(self, m: float, q: ArrayLike) -> FloatArray:
        """``int_{q}^{q_max} q'^m C(q') dq'`` (vectorised, exact, no cancellation)."""
        if ("tail", m) not in self._cum:
            seg = self._segment_integrals(m)
            self._cum[("tail", m)] = np.concatenate((np.cumsum(seg[::-1])[::-1], [0.0]))
        after = self._cum[("tail", m)]
        qa = np.clip(np.asarray(q, dtype=float), self.q_min, self.q_max)
        idx = np.clip(np.searchsorted(self.q_nodes, qa, side="right") - 1, 0, self.q_nodes.size - 2)
        k = m + self.exponents[idx] + 1.0
        cq = self.c_nodes[idx] * (qa / self.q_nodes[idx]) ** self.exponents[idx]
        part = cq * qa ** (m + 1.0) * _power_integral(k, np.log(self.q_nodes[idx + 1] / qa))
        return after[idx + 1] + part

    def integral(self, m: float, q_a: float | None = None, q_b: float | None = None) -> float:
        """``int_{q_a}^{q_b} q^m C(q) dq`` (defaults: the whole support), exact."""
        a = self.q_min if q_a is None else float(q_a)
        b = self.q_max if q_b is None else float(q_b)
        if b < a:
            raise ParameterError(f"integral bounds must satisfy q_a <= q_b, got {a:g} > {b:g}")
        # whichever of head/tail is smaller is computed without cancellation
        head = float(self.cumulative(m, b) - self.cumulative(m, a))
        tail = float(self.tail(m, a) - self.tail(m, b))
        return tail if self.tail(m, a) < self.cumulative(m, b) else head

    # ---------------------------------------------------------------- moments
    def h_rms(self, q_a: float | None = None, q_b: float | None = None) -> float:
        """Root-mean-square height [m] of the components with ``q_a <= q <= q_b``."""
        return math.sqrt(2.0 * math.pi * self.integral(1.0, q_a, q_b))

    def rms_slope(self, q_a: float | None = None, q_b: float | None = None) -> float:
        """``<|grad h|^2>^(1/2)`` [-] (both directions; a profile has 1/sqrt(2) of it)."""
        return math.sqrt(2.0 * math.pi * self.integral(3.0, q_a, q_b))

    def rms_curvature(self, q_a: float | None = None, q_b: float | None = None) -> float:
        """``<(lap h)^2>^(1/2)`` [1/m], the rms Laplacian (twice the mean curvature)."""
        return math.sqrt(2.0 * math.pi * self.integral(5.0, q_a, q_b))

    def nayak_moments(self) -> tuple[float, float, float]:
        """Profile spectral moments ``(m0, m2, m4)`` of Nayak (S2 eqs 10-12) [m^2, -, 1/m^2].

        For an isotropic surface ``m0 = <h^2>``, ``m2 = <h_x^2> = <|grad h|^2>/2`` and
        ``m4 = <h_xx^2> = (3/8) <(lap h)^2>``.
        """
        m0 = 2.0 * math.pi * self.integral(1.0)
        m2 = math.pi * self.integral(3.0)
        m4 = 0.75 * math.pi * self.integral(5.0)
        return m0, m2, m4

    def h_rms_band(self, zeta: ArrayLike) -> FloatArray:
        """``h_rms(zeta)`` of S1 footnote 4: rms of the components with ``q > zeta q_min`` [m]."""
        z = np.asarray(zeta, dtype=float)
        if np.any(z < 1.0):
            raise ParameterError(f"zeta must be >= 1 (magnification), got min {np.min(z):g}")
        return np.sqrt(2.0 * math.pi * self.tail(1.0, z * self.q_min))

    # ---------------------------------------------------------------- derived
    def restrict(self, q_a: float, q_b: float | None = None) -> PowerSpectrum:
        """The spectrum with ``C = 0`` outside ``[q_a, q_b]`` (e.g. ``C_sto`` above ``q_th``)."""
        b = self.q_max if q_b is None else float(q_b)
        a = float(q_a)
        if not (self.q_min <= a < b <= self.q_max):
            raise ParameterError(
                f"restriction [{a:g}, {b:g}] 1/m must lie inside the support "
                f"[{self.q_min:g}, {self.q_max:g}] 1/m with q_a < q_b"
            )
        inner = self.q_nodes[(self.q_nodes > a) & (self.q_nodes < b)]
        q = np.concatenate(([a], inner, [b]))
        return PowerSpectrum(q, self(q))

    def scaled(self, factor: float) -> PowerSpectrum:
        """``factor * C(q)`` (e.g. to renormalise ``h_rms``)."""
        check_positive("factor", factor)
        return PowerSpectrum(self.q_nodes, self.c_nodes * factor)

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}(q=[{self.q_min:.3g}, {self.q_max:.3g}] 1/m, "
            f"h_rms={self.h_rms():.3g} m, slope={self.rms_slope():.3g})"
        )


class SelfAffinePSD(PowerSpectrum):
    """Self-affine fractal spectrum with cut-offs and an optional roll-off plateau.

    ``C(q) = C0 (q/q0)^{-2(H+1)}`` for ``q0 <= q <= q1``, ``C = C0`` for
    ``q_r <= q < q0`` (roll-off, if ``q_r`` is given), zero elsewhere (S0 eq 16,
    S3 eq 35, D_f = 3 - H).

    Args:
        q0: Roll-off (or lower cut-off) wavevector [1/m].
        q1: Upper cut-off wavevector [1/m], ``q1 > q0``.
        hurst: Hurst exponent ``H``, ``0 < H < 1``.
        h_rms: Root-mean-square roughness [m] of the whole spectrum; sets ``C0``.
        c0: Alternatively ``C0`` itself [m^4] (exactly one of ``h_rms``, ``c0``).
        q_r: Lower end of the roll-off plateau [1/m], ``0 < q_r < q0``; ``None``
            for no plateau.
    """

    def __init__(
        self,
        q0: float,
        q1: float,
        hurst: float,
        h_rms: float | None = None,
        c0: float | None = None,
        q_r: float | None = None,
    ) -> None:
        q0 = check_positive("q0", q0, "1/m")
        q1 = check_range("q1", q1, q0, math.inf, lo_open=True, unit="1/m (must exceed q0)")
        hurst = check_range("hurst", hurst, 0.0, 1.0, lo_open=True, hi_open=True)
        if q_r is not None:
            q_r = check_range("q_r", q_r, 0.0, q0, lo_open=True, hi_open=True, unit="1/m")
        if (h_rms is None) == (c0 is None):
            raise ParameterError("give exactly one of h_rms (m) and c0 (m^4)")
        e = -2.0 * (hurst + 1.0)
        q_nodes = [q0, q1] if q_r is None else [q_r, q0, q1]
        c_unit = [1.0, (q1 / q0) ** e] if q_r is None else [1.0, 1.0, (q1 / q0) ** e]
        if c0 is None:
            check_positive("h_rms", h_rms, "m")  # type: ignore[arg-type]
            unit = PowerSpectrum(q_nodes, c_unit)
            c0 = float(h_rms) ** 2 / (2.0 * math.pi * unit.integral(1.0))  # type: ignore[arg-type]
        c0 = check_positive("c0", c0, "m^4")
        super().__init__(q_nodes, np.asarray(c_unit) * c0)
        self.q0, self.q1, self.hurst, self.c0, self.q_r = q0, q1, hurst, c0, q_r

    @classmethod
    def from_q0h0(cls, q0: float, q1: float, hurst: float, q0h0: float) -> SelfAffinePSD:
        """S3 normalisation: ``C0 = k = (h0/q0)^2 H / (2 pi)`` with ``<h^2> = h0^2/2`` for q1 -> inf.

        Args:
            q0, q1, hurst: As in the constructor.
            q0h0: The dimensionless product ``q0 h0`` of S3 (figure 11 uses 1).
        """
        check_positive("q0h0", q0h0)
        q0 = check_positive("q0", q0, "1/m")
        h0 = q0h0 / q0
        return cls(q0, q1, hurst, c0=(h0 / q0) ** 2 * hurst / (2.0 * math.pi))


def read_text(p: Path, name: str, not_text: str) -> str:
    """The text of file ``p``; unreadable, or not text (``not_text`` says what it must
    be): a :class:`ParameterError` naming the parameter ``name``."""
    try:
        return p.read_text()
    except OSError as e:
        raise ParameterError(f"{name} {str(p)!r} cannot be read: {e.strerror or e}", name) from None
    except UnicodeDecodeError:
        raise ParameterError(f"{name} {str(p)!r} {not_text}", name) from None


def read_psd_table(path: str | Path, *, name: str = "psd_file") -> PowerSpectrum:
    """Read a measured isotropic PSD: two columns ``q`` [1/m] and ``C`` [m^4].

    Whitespace- or comma-separated; lines starting with ``#`` are comments.  Rows
    must have strictly increasing ``q`` and positive ``C``.  Between rows the
    spectrum is interpolated log-log (a power law per interval).  ``name`` is the
    parameter holding ``path`` (e.g. ``"roughness.psd_file"``), for messages.
    """
    p = Path(path)
    if not p.exists():
        raise ParameterError(f"{name} {str(p)!r} does not exist", name)
    if not p.is_file():
        raise ParameterError(f"{name} {str(p)!r} is not a file", name)
    text = read_text(p, name, "is not a text table of q [1/m] and C [m^4]")
    rows: list[tuple[float, float]] = []
    for n, line in enumerate(text.splitlines(), start=1):
        s = line.split("#", 1)[0].strip()
        if not s:
            continue
        parts = s.replace(",", " ").split()
        if len(parts) < 2:
            raise ParameterError(
                f"{name} {p}:{n}: expected two columns q [1/m] and C [m^4], got {s!r}", name
            )
        try:
            qn, cn = float(parts[0]), float(parts[1])
        except ValueError:
            raise ParameterError(
                f"{name} {p}:{n}: not numbers: {s!r} (rows of q [1/m] > 0 and C [m^4] > 0)", name
            ) from None
        if not (math.isfinite(qn) and math.isfinite(cn) and qn > 0 and cn > 0):
            raise ParameterError(
                f"{name} {p}:{n}: q = {parts[0]}, C = {parts[1]}: both must be finite and "
                "positive (q [1/m] in (0, inf), C [m^4] in (0, inf))",
                name,
            )
        if rows and qn <= rows[-1][0]:
            raise ParameterError(
                f"{name} {p}:{n}: q = {parts[0]} 1/m is not above the previous row's "
                f"{rows[-1][0]!r}: q must be strictly increasing",
                name,
            )
        rows.append((qn, cn))
    if len(rows) < 2:
        raise ParameterError(
            f"{name} {p}: a PSD table needs at least two rows, got {len(rows)}", name
        )
    q, c = np.array(rows).T
    try:
        return PowerSpectrum(q, c)
    except ParameterError as e:
        raise ParameterError(f"{name} {p}: {e}", name) from None


@dataclass(frozen=True)
class RoughnessParams:
    """Roughness of a scene: a self-affine model, a measured PSD file or a height map (SI units).

    Attributes:
        h_rms: Root-mean-square roughness [m] (ignored when ``psd_file`` or
            ``topography_file`` is set).
        hurst: Hurst exponent ``H = 3 - D_f``, ``0 < H < 1``.
        q0: Roll-off / lower cut-off wavevector [1/m].
        q1: Upper cut-off wavevector [1/m].
        q_r: Lower end of a roll-off plateau [1/m]; 0 for none.
        psd_file: Optional path of a measured ``(q, C)`` table; when set it replaces
            the model (``h_rms``, ``hurst``, ``q0``, ``q1``, ``q_r`` are then unused).
        topography_file: Optional path of a measured height map (text rows of heights
            in metres, or ``.npy``; other formats through SurfaceTopography when it is
            installed); when set, its PSD replaces the model as ``psd_file`` does (the
            two are exclusive).
        pixel_size: Pixel size [m] of ``topography_file``; required (> 0) with it,
            ignored without it.
        topography_window: Window of the height map's PSD: ``hann`` (a measured,
            non-periodic map) or ``none`` (one period of a periodic surface).
    """

    h_rms: float = 1.0e-6
    hurst: float = 0.8
    q0: float = 1.0e4
    q1: float = 7.8e9
    q_r: float = 0.0
    psd_file: str = ""
    topography_file: str = ""
    pixel_size: float = 0.0
    topography_window: str = "hann"

    def __post_init__(self) -> None:
        check_types(self, "roughness.")
        check_positive("roughness.h_rms", self.h_rms, "m")
        check_range("roughness.hurst", self.hurst, 0.0, 1.0, lo_open=True, hi_open=True)
        check_positive("roughness.q0", self.q0, "1/m")
        check_range("roughness.q1", self.q1, self.q0, math.inf, lo_open=True, unit="1/m (> q0)")
        check_range("roughness.q_r", self.q_r, 0.0, self.q0, hi_open=True, unit="1/m (< q0)")
        check_nonnegative("roughness.pixel_size", self.pixel_size, "m")
        check_choice("roughness.topography_window", self.topography_window, ("hann", "none"))
        if self.topography_file:
            if self.psd_file:
                raise ParameterError(
                    f"roughness.topography_file = {self.topography_file!r} and "
                    f"roughness.psd_file = {self.psd_file!r} are exclusive: give one measured "
                    f"roughness (a height map or a PSD table)"
                )
            if self.pixel_size <= 0.0:
                raise ParameterError(
                    f"roughness.pixel_size = {self.pixel_size!r} m is outside the allowed range "
                    f"(0, inf) when roughness.topography_file is set: give the pixel size of "
                    f"{self.topography_file!r}"
                )
        if self.psd_file or self.topography_file:
            # a missing, unreadable or malformed file stops here, before anything is assembled
            name = "roughness.psd_file" if self.psd_file else "roughness.topography_file"
            try:
                self.build()
            except ParameterError as e:
                if str(e).startswith(name):
                    raise
                path = self.psd_file or self.topography_file
                raise ParameterError(f"{name} = {path!r}: {e}", name) from None

    def build(self) -> PowerSpectrum:
        """The :class:`PowerSpectrum` these parameters describe."""
        if self.psd_file:
            return read_psd_table(self.psd_file, name="roughness.psd_file")
        if self.topography_file:
            from dolfinx_seal.roughness.topography import topography_psd

            return topography_psd(
                self.topography_file,
                self.pixel_size,
                window=self.topography_window,
                name="roughness.topography_file",
            )
        return SelfAffinePSD(self.q0, self.q1, self.hurst, h_rms=self.h_rms, q_r=self.q_r or None)
