"""Random-phase Fourier surfaces and the two-scale split of a spectrum (S0 eqs 15-21).

The roughness is split at ``q_th``: wavelengths longer than ``lambda_th = 2 pi /
q_th`` are synthesised as a deterministic periodic surface that a mesh can
resolve, the rest enters the homogenised laws through ``C_sto(q) = C(q)`` for
``q > q_th``.

Synthesis (S0 eq 17): ``h_r(x) = sum_k a_k exp(i q_k . x)`` on the lattice
``q_k = (2 pi / L) (k_x, k_y)``, ``0 < |q_k| <= q_th``, with ``a_{-k} =
conj(a_k)`` (real surface), phases uniform in ``[0, 2 pi)`` and ``<|a_k|^2> =
C(q_k) (2 pi / L)^2`` (S0 eqs 18-20 with the delta function of eq 19 read as
the lattice cell area).  ``amplitude="fixed"`` uses ``|a_k| = <|a_k|^2>^(1/2)``
(S0 eq 21), so every realisation has exactly the lattice rms
:meth:`TwoScaleSplit.lattice_h_rms`; ``amplitude="gaussian"`` draws complex
Gaussian coefficients (Rayleigh moduli), the textbook Gaussian random field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_choice, check_int_range, check_positive
from dolfinx_seal.roughness.psd import PowerSpectrum

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class FourierSurface:
    """A real periodic surface ``h(x, y) = sum_half 2 |a_k| cos(q_k . x + phi_k)``.

    Only one mode of every ``(k, -k)`` pair is stored (``k_y > 0`` or ``k_y = 0,
    k_x > 0``); the sum over that half-plane with the factor 2 is the real form
    of S0 eq 17.

    Attributes:
        period: Side ``L`` of the periodic square [m].
        kx, ky: Integer lattice indices of the stored modes.
        amplitude: ``|a_k|`` [m].
        phase: ``phi_k`` [rad].
    """

    period: float
    kx: NDArray[np.int64]
    ky: NDArray[np.int64]
    amplitude: FloatArray
    phase: FloatArray

    @property
    def qx(self) -> FloatArray:
        """x-components of the mode wavevectors [1/m]."""
        return 2.0 * math.pi / self.period * self.kx

    @property
    def qy(self) -> FloatArray:
        """y-components of the mode wavevectors [1/m]."""
        return 2.0 * math.pi / self.period * self.ky

    def h_rms(self) -> float:
        """Exact rms height of this realisation [m] (Parseval)."""
        return float(np.sqrt(2.0 * np.sum(self.amplitude**2)))

    def rms_slope(self) -> float:
        """Exact ``<|grad h|^2>^(1/2)`` of this realisation [-] (Parseval)."""
        q2 = self.qx**2 + self.qy**2
        return float(np.sqrt(2.0 * np.sum(q2 * self.amplitude**2)))

    def evaluate(self, x: ArrayLike, y: ArrayLike, chunk: int = 4096) -> FloatArray:
        """Heights [m] at arbitrary points (e.g. mesh nodes), any array shape."""
        xa, ya = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        xf, yf = xa.ravel(), ya.ravel()
        out = np.empty_like(xf)
        for s in range(0, xf.size, chunk):
            arg = np.outer(xf[s : s + chunk], self.qx) + np.outer(yf[s : s + chunk], self.qy)
            out[s : s + chunk] = 2.0 * np.cos(arg + self.phase) @ self.amplitude
        return out.reshape(xa.shape)

    def gradient(self, x: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(dh/dx, dh/dy)`` [-] at arbitrary points."""
        xa, ya = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        arg = np.outer(xa.ravel(), self.qx) + np.outer(ya.ravel(), self.qy) + self.phase
        s = -2.0 * np.sin(arg)
        gx = s @ (self.amplitude * self.qx)
        gy = s @ (self.amplitude * self.qy)
        return gx.reshape(xa.shape), gy.reshape(xa.shape)

    def grid(self, n: int) -> FloatArray:
        """Heights on the ``n x n`` grid ``x_i = i L / n`` (index ``[i_x, i_y]``), by FFT.

        ``n`` must exceed twice the largest lattice index (no aliasing).
        """
        kmax = int(max(np.max(np.abs(self.kx), initial=0), np.max(np.abs(self.ky), initial=0)))
        check_int_range("n", n, 2 * kmax + 1)
        z = np.zeros((n, n), dtype=complex)
        a = self.amplitude * np.exp(1j * self.phase)
        z[self.kx % n, self.ky % n] += a
        z[(-self.kx) % n, (-self.ky) % n] += np.conj(a)
        return np.real(np.fft.ifft2(z)) * n * n


def radial_psd(h: ArrayLike, period: float, nbins: int = 30) -> tuple[FloatArray, FloatArray]:
    """Isotropic PSD estimate of a periodic height map, averaged in rings of ``|q|``.

    Args:
        h: Heights on an ``n x n`` periodic grid [m].
        period: Side of the grid [m].
        nbins: Number of logarithmic ``|q|`` bins.

    Returns:
        ``(q, C)``: bin centres [1/m] and mean ``|a_q|^2 / dq^2`` [m^4] of the
        lattice points in each non-empty bin.
    """
    ha = np.asarray(h, dtype=float)
    if ha.ndim != 2 or ha.shape[0] != ha.shape[1]:
        raise ParameterError(f"h must be a square 2D array, got shape {ha.shape}")
    check_positive("period", period, "m")
    n = ha.shape[0]
    dq = 2.0 * math.pi / period
    a = np.fft.fft2(ha) / (n * n)
    k = np.fft.fftfreq(n, d=1.0 / n)
    q = dq * np.hypot(*np.meshgrid(k, k, indexing="ij"))
    c = np.abs(a) ** 2 / dq**2
    mask = q > 0
    edges = np.geomspace(q[mask].min() * 0.999, q.max() * 1.001, nbins + 1)
    idx = np.digitize(q[mask], edges) - 1
    cnt = np.bincount(idx, minlength=nbins)
    sums = np.bincount(idx, weights=c[mask], minlength=nbins)
    qs = np.bincount(idx, weights=q[mask], minlength=nbins)
    ok = cnt > 0
    return qs[ok] / cnt[ok], sums[ok] / cnt[ok]


class TwoScaleSplit:
    """Split a spectrum at ``q_th`` into a deterministic and a statistical part.

    Args:
        psd: The full spectrum ``C(q)``.
        q_th: Threshold wavevector [1/m] (S0: ``q_th = 2 pi / lambda_th``),
            ``q_min < q_th < q_max``.
        period: Side ``L`` of the periodic synthesis domain [m]; default
            ``2 pi / q_min`` so the longest wavelength present fits once.
    """

    def __init__(self, psd: PowerSpectrum, q_th: float, period: float | None = None) -> None:
        if not (psd.q_min < q_th < psd.q_max):
            raise ParameterError(
                f"q_th = {q_th!r} 1/m is outside the allowed range "
                f"({psd.q_min:g}, {psd.q_max:g}) of the spectrum"
            )
        self.psd = psd
        self.q_th = float(q_th)
        self.period = 2.0 * math.pi / psd.q_min if period is None else float(period)
        check_positive("period", self.period, "m")
        dq = 2.0 * math.pi / self.period
        kmax = math.floor(self.q_th / dq)
        if kmax < 1:
            raise ParameterError(
                f"q_th = {q_th:g} 1/m is below the lattice spacing 2 pi / period = {dq:g} 1/m"
            )
        kk = np.arange(-kmax, kmax + 1)
        kx, ky = (a.ravel() for a in np.meshgrid(kk, kk, indexing="ij"))
        half = (ky > 0) | ((ky == 0) & (kx > 0))
        q = dq * np.hypot(kx, ky)
        keep = half & (q <= self.q_th) & (q > 0)
        self._kx, self._ky = kx[keep], ky[keep]
        self._mean_sq = psd(q[keep]) * dq**2  # <|a_k|^2>
        live = self._mean_sq > 0
        self._kx, self._ky, self._mean_sq = self._kx[live], self._ky[live], self._mean_sq[live]

    @property
    def stochastic_psd(self) -> PowerSpectrum:
        """``C_sto(q) = C(q)`` for ``q > q_th`` and 0 below (the homogenised part)."""
        return self.psd.restrict(self.q_th)

    @property
    def n_modes(self) -> int:
        """Number of independent (half-plane) Fourier modes of the deterministic part."""
        return int(self._kx.size)

    def lattice_h_rms(self) -> float:
        """Ensemble rms of the deterministic part, ``(sum_k <|a_k|^2>)^(1/2)`` [m]."""
        return float(np.sqrt(2.0 * np.sum(self._mean_sq)))

    def lattice_rms_slope(self) -> float:
        """Ensemble rms slope of the deterministic part [-]."""
        q2 = (2.0 * math.pi / self.period) ** 2 * (self._kx**2 + self._ky**2)
        return float(np.sqrt(2.0 * np.sum(q2 * self._mean_sq)))

    def continuum_h_rms(self) -> float:
        """``(2 pi int_{q_min}^{q_th} q C dq)^(1/2)`` [m], what the lattice sum approximates."""
        return self.psd.h_rms(self.psd.q_min, self.q_th)

    def mean_square_amplitudes(self) -> FloatArray:
        """``<|a_k|^2>`` of the stored half-plane modes [m^2] (S0 eqs 19-20)."""
        return self._mean_sq.copy()

    def deterministic_surface(self, seed: int, amplitude: str = "fixed") -> FourierSurface:
        """One realisation of the long-wavelength surface ``h_r`` (reproducible by ``seed``).

        Args:
            seed: Seed of ``numpy.random.default_rng``; the same seed gives the same surface.
            amplitude: ``"fixed"`` (S0 eq 21) or ``"gaussian"`` (Rayleigh moduli).
        """
        check_choice("amplitude", amplitude, ("fixed", "gaussian"))
        check_int_range("seed", seed, 0)
        rng = np.random.default_rng(seed)
        phase = rng.uniform(0.0, 2.0 * math.pi, size=self.n_modes)
        amp = np.sqrt(self._mean_sq)
        if amplitude == "gaussian":
            # |a| with <|a|^2> = mean_sq: modulus of a complex Gaussian (Rayleigh)
            amp = amp * np.sqrt(rng.exponential(1.0, size=self.n_modes))
        return FourierSurface(self.period, self._kx.copy(), self._ky.copy(), amp, phase)


def read_topography(path: str) -> tuple[FloatArray, tuple[float, ...]]:
    """Read a measured topography through the optional package SurfaceTopography.

    Returns:
        ``(heights [m], physical_sizes [m])`` as SurfaceTopography reports them;
        :func:`radial_psd` turns a periodic square map into ``(q, C)``.

    Raises:
        ParameterError: SurfaceTopography is not installed (the PSD-table route,
            :func:`dolfinx_seal.roughness.read_psd_table`, needs nothing extra).
    """
    try:
        import SurfaceTopography  # type: ignore[import-not-found]
    except ImportError:
        raise ParameterError(
            "reading measured topography files needs the optional Python package "
            "SurfaceTopography, which is not installed; install it in the project "
            "environment, or supply the spectrum as a two-column (q [1/m], C [m^4]) "
            "table to read_psd_table / roughness.psd_file"
        ) from None
    reader = SurfaceTopography.open_topography(path)
    topo = reader.topography()
    return np.asarray(topo.heights(), dtype=float), tuple(topo.physical_sizes)
