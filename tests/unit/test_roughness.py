"""Roughness spectra, moments and synthetic surfaces (dolfinx_seal.roughness)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import quad

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.roughness import (
    PowerSpectrum,
    RoughnessParams,
    SelfAffinePSD,
    TwoScaleSplit,
    radial_psd,
    read_psd_table,
    read_topography,
)

Q0, Q1, H = 1.0e4, 7.8e9, 0.8


def closed_moments(c0: float, q0: float, q1: float, hurst: float, qr: float | None = None):
    """<h^2>, <|grad h|^2>, <(lap h)^2> of C = C0 (q/q0)^(-2(H+1)) on [q0, q1] (+ plateau)."""
    z = q1 / q0
    m0 = math.pi * c0 * q0**2 / hurst * (1.0 - z ** (-2 * hurst))
    m2 = math.pi * c0 * q0**4 / (1.0 - hurst) * (z ** (2 - 2 * hurst) - 1.0)
    m4 = math.pi * c0 * q0**6 / (2.0 - hurst) * (z ** (4 - 2 * hurst) - 1.0)
    if qr is not None:  # 2 pi C0 int_qr^q0 q^(1, 3, 5) dq
        m0 += math.pi * c0 * (q0**2 - qr**2)
        m2 += 0.5 * math.pi * c0 * (q0**4 - qr**4)
        m4 += math.pi / 3.0 * c0 * (q0**6 - qr**6)
    return m0, m2, m4


@pytest.mark.parametrize("qr", [None, 2.0e3])
def test_moments_match_closed_forms(qr):
    psd = SelfAffinePSD(Q0, Q1, H, h_rms=1e-6, q_r=qr)
    m0, m2, m4 = closed_moments(psd.c0, Q0, Q1, H, qr)
    # exact piecewise integration: only rounding error is left
    assert psd.h_rms() ** 2 == pytest.approx(m0, rel=1e-12)
    assert psd.h_rms() == pytest.approx(1e-6, rel=1e-12)
    assert psd.rms_slope() ** 2 == pytest.approx(m2, rel=1e-12)
    assert psd.rms_curvature() ** 2 == pytest.approx(m4, rel=1e-12)
    n0, n2, n4 = psd.nayak_moments()
    assert (n0, n2, n4) == pytest.approx((m0, m2 / 2, 3 * m4 / 8), rel=1e-12)


def test_band_limited_rms_footnote4():
    psd = SelfAffinePSD(Q0, Q1, H, h_rms=1e-6)
    zeta = np.array([1.0, 10.0, 1e3, 1e5])
    # S1 footnote 4: h_rms(zeta)^2 = 2 pi int_{zeta q0}^{q1} q C dq, closed form
    ref = np.sqrt(math.pi * psd.c0 * Q0**2 / H * (zeta ** (-2 * H) - (Q1 / Q0) ** (-2 * H)))
    np.testing.assert_allclose(psd.h_rms_band(zeta), ref, rtol=1e-10)


def test_tabulated_psd_against_quadrature(tmp_path):
    q = np.array([1e3, 3e3, 1e4, 1e5, 1e6])
    c = np.array([1e-20, 2e-20, 1e-21, 1e-25, 3e-29])
    f = tmp_path / "psd.txt"
    f.write_text(
        "# q [1/m], C [m^4]\n" + "\n".join(f"{a:.6e}, {b:.6e}" for a, b in zip(q, c, strict=True))
    )
    psd = read_psd_table(f)
    np.testing.assert_allclose(psd(q), c, rtol=1e-6)
    for m in (1.0, 3.0, 5.0):
        # independent: adaptive quadrature of the log-log interpolant, per interval
        ref = sum(
            quad(lambda x, m=m: x**m * np.exp(np.interp(np.log(x), np.log(q), np.log(c))), a, b,
                 epsabs=0, epsrel=1e-12, limit=200)[0]
            for a, b in itertools.pairwise(q)
        )  # fmt: skip
        assert psd.integral(m) == pytest.approx(ref, rel=1e-8)
    assert psd(np.array([5e2, 2e6])).tolist() == [0.0, 0.0]


@pytest.mark.parametrize(
    ("text", "match"),
    [("1 2\n", "at least two"), ("1 1e-20\n1 2e-20\n", "strictly increasing"),
     ("1 1e-20\n2 -1\n", "positive"), ("1 1e-20\nx y\n", "not numbers")],
)  # fmt: skip
def test_psd_table_errors(tmp_path, text, match):
    f = tmp_path / "bad.txt"
    f.write_text(text)
    with pytest.raises(ParameterError, match=match):
        read_psd_table(f)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [({"q0": 1e4, "q1": 1e4, "hurst": 0.8, "h_rms": 1e-6}, "q1"),
     ({"q0": -1.0, "q1": 1e4, "hurst": 0.8, "h_rms": 1e-6}, "q0"),
     ({"q0": 1e4, "q1": 1e6, "hurst": 1.0, "h_rms": 1e-6}, "hurst"),
     ({"q0": 1e4, "q1": 1e6, "hurst": 0.8, "h_rms": 0.0}, "h_rms"),
     ({"q0": 1e4, "q1": 1e6, "hurst": 0.8, "h_rms": 1e-6, "q_r": 2e4}, "q_r")],
)  # fmt: skip
def test_validation_names_parameter(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        SelfAffinePSD(**kwargs)


def test_roughness_params_validation_and_build():
    with pytest.raises(ParameterError, match=r"roughness\.q1"):
        RoughnessParams(q0=1e5, q1=1e4)
    with pytest.raises(ParameterError, match=r"roughness\.hurst"):
        RoughnessParams(hurst=0.0)
    assert RoughnessParams().build().h_rms() == pytest.approx(1e-6, rel=1e-12)


def test_s3_normalisation():
    # S3: <h^2> = h0^2/2 for q1 -> inf with C0 = (h0/q0)^2 H/(2 pi)
    psd = SelfAffinePSD.from_q0h0(2000.0, 2000.0 * 1e6, 0.85, 1.0)
    h0 = 1.0 / 2000.0
    assert psd.h_rms() ** 2 == pytest.approx(h0**2 / 2 * (1 - 1e6 ** (-1.7)), rel=1e-12)


# ------------------------------------------------------------ synthesis
def split(period_factor: float = 1.0, q_r: float | None = 2e3) -> TwoScaleSplit:
    psd = SelfAffinePSD(1e4, 1e7, 0.8, h_rms=1e-6, q_r=q_r)
    return TwoScaleSplit(psd, q_th=4e4, period=period_factor * 2 * math.pi / psd.q_min)


def test_surface_reproducible_and_real():
    s = split()
    a, b, c = s.deterministic_surface(7), s.deterministic_surface(7), s.deterministic_surface(8)
    np.testing.assert_array_equal(a.grid(64), b.grid(64))
    assert not np.allclose(a.grid(64), c.grid(64))
    h = a.grid(64)
    assert h.dtype == np.float64 and np.all(np.isfinite(h))
    x = np.arange(64) * a.period / 64
    np.testing.assert_allclose(a.evaluate(x[:, None], x[None, :]), h, atol=1e-12 * np.abs(h).max())
    assert abs(h.mean()) < 1e-12 * h.std()  # no q = 0 mode


def test_fixed_amplitude_rms_slope_psd_exact():
    s = split()
    for seed in range(3):
        surf = s.deterministic_surface(seed)
        h = surf.grid(64)
        # S0 eq 21: |a_k| fixed, so rms and slope are the lattice values for every seed
        assert h.std() == pytest.approx(s.lattice_h_rms(), rel=1e-10)
        assert surf.rms_slope() == pytest.approx(s.lattice_rms_slope(), rel=1e-12)
        gx, _gy = surf.gradient(
            *np.meshgrid(np.arange(64) * s.period / 64, [0.3e-3], indexing="ij")
        )
        # spectral derivative of the grid, independent of FourierSurface.gradient
        k = 2 * math.pi / s.period * np.fft.fftfreq(64, d=1 / 64)
        row = surf.evaluate(np.arange(64) * s.period / 64, np.full(64, 0.3e-3))
        dh = np.real(np.fft.ifft(1j * k * np.fft.fft(row)))
        np.testing.assert_allclose(gx.ravel(), dh, atol=1e-9 * np.abs(dh).max())
        # PSD of the synthesised surface equals C(q_k) at every lattice point
        a = np.fft.fft2(h) / 64**2
        kk = np.fft.fftfreq(64, d=1 / 64)
        q = 2 * math.pi / s.period * np.hypot(*np.meshgrid(kk, kk, indexing="ij"))
        live = (q > 0) & (q <= s.q_th)
        dq = 2 * math.pi / s.period
        np.testing.assert_allclose(np.abs(a[live]) ** 2 / dq**2, s.psd(q[live]), rtol=1e-9)
        assert np.all(np.abs(a[q > s.q_th]) < 1e-15 * np.abs(a).max())


def test_gaussian_amplitudes_statistics_over_seeds():
    s = split()
    ms = s.mean_square_amplitudes()
    c = 2.0 * ms  # contribution of each half-plane mode to <h^2>; Exp(1) multipliers
    mean, sd = c.sum(), math.sqrt(np.sum(c**2))
    q2 = (2 * math.pi / s.period) ** 2 * (s._kx**2 + s._ky**2)
    smean, ssd = np.sum(c * q2), math.sqrt(np.sum((c * q2) ** 2))
    n = 20
    h2 = np.array([s.deterministic_surface(k, "gaussian").h_rms() ** 2 for k in range(n)])
    g2 = np.array([s.deterministic_surface(k, "gaussian").rms_slope() ** 2 for k in range(n)])
    # each realisation: sum of independent exponentials -> mean `mean`, std `sd`;
    # 5 sigma per seed, 4 sigma / sqrt(n) for the average over seeds
    assert np.all(np.abs(h2 - mean) < 5 * sd)
    assert abs(h2.mean() - mean) < 4 * sd / math.sqrt(n)
    assert np.all(np.abs(g2 - smean) < 5 * ssd)
    assert abs(g2.mean() - smean) < 4 * ssd / math.sqrt(n)
    # PSD per ring: |a|^2 / <|a|^2> ~ Exp(1), ring means within 4/sqrt(count)
    ratios = np.concatenate(
        [s.deterministic_surface(k, "gaussian").amplitude ** 2 / ms for k in range(n)]
    )
    qk = np.tile(np.sqrt(q2), n)
    edges = np.geomspace(qk.min() * 0.999, qk.max() * 1.001, 6)
    for lo, hi in itertools.pairwise(edges):
        sel = (qk >= lo) & (qk < hi)
        assert abs(ratios[sel].mean() - 1.0) < 4.0 / math.sqrt(sel.sum())


def test_radial_psd_estimate_matches_model():
    s = split()
    h = s.deterministic_surface(3).grid(128)
    q, c = radial_psd(h, s.period, nbins=12)
    inside = q < 0.8 * s.q_th
    # ring averages of C(q_k) vs C at the ring's mean q: C varies by < 15 % across a
    # ring of this width for the q^-3.6 law, so 20 % bounds the binning bias
    ratio = c[inside] / s.psd(q[inside])
    assert np.all(np.abs(ratio - 1) < 0.2)


def test_split_identity_and_lattice_convergence():
    s = split()
    total = s.psd.h_rms() ** 2
    assert s.continuum_h_rms() ** 2 + s.stochastic_psd.h_rms() ** 2 == pytest.approx(
        total, rel=1e-12
    )
    assert s.stochastic_psd.q_min == pytest.approx(s.q_th)
    # the lattice sum of S0 eq 18 approaches the continuum integral as the period grows
    err = [abs(split(f).lattice_h_rms() / split(f).continuum_h_rms() - 1) for f in (1, 2)]
    assert err[1] < 0.5 * err[0]
    assert err[0] < 0.02


def test_split_validation():
    psd = SelfAffinePSD(1e4, 1e7, 0.8, h_rms=1e-6)
    with pytest.raises(ParameterError, match="q_th"):
        TwoScaleSplit(psd, q_th=1e8)
    with pytest.raises(ParameterError, match="amplitude"):
        TwoScaleSplit(psd, q_th=1e5).deterministic_surface(0, amplitude="uniform")
    with pytest.raises(ParameterError, match=r"n = "):
        TwoScaleSplit(psd, q_th=1e5).deterministic_surface(0).grid(8)


def test_read_topography_message():
    pytest.importorskip("numpy")
    try:
        import SurfaceTopography  # noqa: F401
    except ImportError:
        with pytest.raises(ParameterError, match="SurfaceTopography"):
            read_topography("surface.txt")
    else:  # pragma: no cover - optional dependency installed
        pytest.skip("SurfaceTopography is installed")


def test_powerspectrum_rejects_bad_nodes():
    with pytest.raises(ParameterError):
        PowerSpectrum([1.0, 1.0], [1.0, 2.0])
    with pytest.raises(ParameterError):
        PowerSpectrum([1.0, 2.0], [1.0, np.nan])
