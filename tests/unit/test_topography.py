"""Measured roughness from a height map (dolfinx_seal.roughness.topography).

The maps are synthesised with a known spectrum: ``TwoScaleSplit`` draws the
periodic random-phase surface ``h = sum_k a_k exp(i q_k.x)`` with ``<|a_k|^2> =
C(q_k) dq^2`` on the lattice of the map (S0 eqs 17-21), for the self-affine
``C`` of ``SelfAffinePSD`` (roll-off at ``q0 = 8 dq``, ``H = 0.8``, up to
Nyquist).  With ``"gaussian"`` amplitudes ``|a_k|^2 / <|a_k|^2>`` is Exp(1) and
independent over the half lattice, so a ring mean over ``n`` lattice points
(``n/2`` independent modes) has relative scatter ``(n/2)^-1/2``; with
``"fixed"`` amplitudes (S0 eq 21) there is no amplitude scatter at all.

The tolerances below were set from the spread over 20 seeds of the same
surfaces (noted at each assertion), not from the seeds used here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dolfinx_seal.contact.persson import PerssonLaw
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.roughness import (
    HeightMap,
    RoughnessParams,
    SelfAffinePSD,
    TwoScaleSplit,
    fit_hurst,
    map_moments,
    map_spectrum,
    read_height_map,
    read_psd_table,
    topography_report,
    write_height_map,
)
from dolfinx_seal.roughness import topography as topo

N = 512  # pixels per side
L = 1.0e-3  # side of the map [m]
A = L / N  # pixel size [m]
DQ = 2.0 * math.pi / L  # lattice spacing [1/m]
HURST = 0.8
Q0 = 8.0 * DQ  # roll-off [1/m]


def model(period: float = L, hurst: float = HURST) -> tuple[SelfAffinePSD, TwoScaleSplit]:
    """The prescribed spectrum (plateau from below the lattice to Q0, then q^-2(1+H) to
    Nyquist) and its synthesis on the lattice of a periodic square of side ``period``
    with pixels of side A: every mode with |q| below Nyquist minus half a cell, so the
    grid ``period / A`` holds them without aliasing."""
    dqp = 2.0 * math.pi / period
    psd = SelfAffinePSD(Q0, 1.001 * math.pi / A, hurst, h_rms=1e-6, q_r=0.5 * dqp)
    return psd, TwoScaleSplit(psd, q_th=math.pi / A - 0.5 * dqp, period=period)


def expected_rings(spec, psd: SelfAffinePSD, q_th: float) -> np.ndarray:
    """``<C_k>`` averaged over the same lattice points as each ring of ``spec``: the
    ensemble value of a ring mean (model zero above the synthesis cut-off ``q_th``)."""
    nx, ny = spec.hmap.shape
    qx = 2 * math.pi * np.fft.fftfreq(nx, d=A)
    qy = 2 * math.pi * np.fft.fftfreq(ny, d=A)
    q = np.hypot(qx[:, None], qy[None, :]).ravel()
    c = np.where(q <= q_th, psd(q), 0.0)
    idx = topo.ring_index(q, spec.edges)
    live = idx >= 0
    nb = spec.edges.size - 1
    cnt = np.bincount(idx[live], minlength=nb)
    tot = np.bincount(idx[live], weights=c[live], minlength=nb)
    ok = cnt > 0
    assert np.array_equal(cnt[ok], spec.counts)  # the same lattice points
    return tot[ok] / cnt[ok]


def fd_ratio(psd: SelfAffinePSD, q_th: float, n: int = N) -> float:
    """``<|grad h|^2>`` of forward differences over the spectral one, for the model on
    the lattice: a difference sees ``q_x`` as ``2 sin(q_x A/2)/A``."""
    qx = 2 * math.pi * np.fft.fftfreq(n, d=A)
    kx, ky = np.meshgrid(qx, qx, indexing="ij")
    q = np.hypot(kx, ky)
    c = np.where(q <= q_th, psd(q), 0.0)
    t = 4.0 / A**2 * (np.sin(kx * A / 2) ** 2 + np.sin(ky * A / 2) ** 2)
    return float(np.sum(t * c) / np.sum(q * q * c))


@pytest.fixture(scope="module")
def gaussian_map(tmp_path_factory):
    """A periodic Gaussian map and its model; the map as read back from a text file
    with a ``# pixel_size`` header (the spectra below are of that copy)."""
    psd, split = model()
    h = split.deterministic_surface(11, "gaussian").grid(N)
    txt = write_height_map(tmp_path_factory.mktemp("maps") / "map.txt", h, A)
    back = read_height_map(txt)
    assert back.pixel_size == A and np.array_equal(back.heights, h)  # 17 digits: exact
    return psd, split, back.heights, txt


@pytest.fixture(scope="module")
def cropped_map():
    """A non-periodic map: the N x N corner of a periodic 2N x 2N surface (side 2L)."""
    psd, split = model(period=2 * L)
    h = split.deterministic_surface(5, "gaussian").grid(2 * N)[:N, :N]
    return psd, split, h


# ------------------------------------------------------------ the convention
def test_convention_single_modes_and_parseval():
    """C_k = |a_k|^2 / dq^2 (psd.py: <h^2> = 2 pi int q C dq; on the lattice of a periodic
    map <|a_k|^2> = C(q_k) dq^2, as surface.py synthesises and radial_psd estimates)."""
    n, amp = 64, 2e-7
    x = np.arange(n) * A
    h = (
        amp * np.cos(2 * math.pi * 3 * x / (n * A))[:, None]
        + 0.5 * amp * np.sin(2 * math.pi * 5 * x / (n * A))[None, :]
    )
    hm = HeightMap(h, A)
    q, c, wt = topo.periodogram(hm, window="none", detrend="mean")
    dq = 2 * math.pi / (n * A)
    # a cosine of amplitude amp puts amp^2/4 at each of +-k: C = amp^2 / (4 dq^2)
    at = lambda k: c[np.isclose(q, k * dq) & (c > 1e-3 * c.max())]  # noqa: E731
    np.testing.assert_allclose(at(3), amp**2 / (4 * dq**2), rtol=1e-12)
    np.testing.assert_allclose(at(5), (0.5 * amp) ** 2 / (4 * dq**2), rtol=1e-12)
    # Parseval on the full lattice (the weights count the mirrored half)
    assert np.sum(wt * c) * dq**2 == pytest.approx(np.mean(h**2), rel=1e-12)
    # and the same values as surface.radial_psd (|a_q|^2 / dq^2) for a periodic map
    rng = np.random.default_rng(3)
    g = rng.normal(size=(n, n)) * 1e-7
    _q2, c2, wt2 = topo.periodogram(HeightMap(g, A), window="none")  # default: mean removal
    a = np.fft.fft2(g - g.mean()) / n**2
    ref = (np.abs(a) ** 2 / dq**2)[:, : n // 2 + 1].ravel()
    np.testing.assert_allclose(c2, ref, rtol=1e-10, atol=1e-12 * ref.max())
    assert np.sum(wt2 * c2) * dq**2 == pytest.approx(np.var(g), rel=1e-12)


def test_hann_power_correction_white_noise():
    """White noise sigma^2 has C = sigma^2 a^2 / (2 pi)^2 at every q, window or not."""
    n, sigma = 256, 1e-7
    g = np.random.default_rng(7).normal(size=(n, n)) * sigma
    level = sigma**2 * A**2 / (4 * math.pi**2)
    for window, inflation in (("none", 1.0), ("hann", 2.0)):
        spec = map_spectrum(HeightMap(g, A), window=window, detrend="mean")
        # all modes together: n^2/2 independent ones; the Hann window correlates
        # neighbours (adjacent-cell coherence 2/3 -> variance x 1.94^2 in 2D), hence
        # `inflation` on the standard deviation; 5 sigma
        mean = np.sum(spec.c * spec.counts) / np.sum(spec.counts)
        assert abs(mean / level - 1) < 5 * inflation / math.sqrt(np.sum(spec.counts) / 2)
        big = spec.counts >= 64
        dev = np.abs(spec.c[big] / level - 1) * np.sqrt(spec.counts[big] / 2) / inflation
        assert np.all(dev < 5), (window, dev.max())
    # without the power correction mean(w^2) = (3/8)^2 the Hann level would be 0.14 x
    assert np.mean(np.outer(topo._hann(n), topo._hann(n)) ** 2) == pytest.approx(9 / 64)


# ------------------------------------------------------------------ reading
def test_text_and_npy_round_trip(tmp_path, gaussian_map):
    _psd, _split, h, txt = gaussian_map
    assert txt.read_text().splitlines()[1] == f"# pixel_size = {A!r} m"
    h = h[:128, :96]  # rectangular
    comma = tmp_path / "map.csv"
    np.savetxt(comma, h, delimiter=", ", fmt="%.17g", header="heights [m]")
    hc = read_height_map(comma, A)
    assert np.array_equal(hc.heights, h)
    npy = tmp_path / "map.npy"
    np.save(npy, h)
    hn = read_height_map(npy, A)
    assert np.array_equal(hn.heights, h) and hn.shape == (128, 96)
    assert hn.size == pytest.approx((128 * A, 96 * A), rel=1e-15)
    with pytest.raises(ParameterError, match="disagrees with the '# pixel_size' header"):
        read_height_map(txt, 2 * A)
    with pytest.raises(ParameterError, match=r"pixel_size \(m\) of .*map\.npy' is required"):
        read_height_map(npy)


BAD_TEXT = {
    "ragged": ("1 2 3 4\n" * 3 + "1 2 3\n", r"bad\.txt:4: row has 3 values, expected 4"),
    "nan": ("1 2 3\n1 2 nan\n", r"bad\.txt:2: column 3: height 'nan' is not finite"),
    "inf": ("1,2,3\n1,-inf,3\n", r"bad\.txt:2: column 2: height '-inf' is not finite"),
    "text": ("# c\n1 2 3\n1 abc 3\n", r"bad\.txt:3: column 2: 'abc' is not a number"),
    "empty": ("# only a comment\n\n", r"holds no heights"),
    "small": ("1 2 3 4\n" * 8, r"number of rows \(x positions\) = 8 is outside the allowed range "
              r"\[16, inf\)"),
    "header": ("# pixel_size = -1e-6\n" + "1 2\n" * 20, r"bad\.txt:1: pixel_size = -1e-06 m "
               r"is outside the allowed range \(0, inf\)"),
    "unit": ("# map\n# Pixel size = 2 um\n" + "1 2\n" * 20, r"bad\.txt:2: cannot read the pixel "
             r"size from '# Pixel size = 2 um'; write it in metres"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(BAD_TEXT))
def test_bad_text_maps(tmp_path, case):
    text, match = BAD_TEXT[case]
    f = tmp_path / "bad.txt"
    f.write_text(text)
    with pytest.raises(ParameterError, match=match):
        read_height_map(f, None if case in ("header", "unit") else A)


def test_bad_maps_and_pixel_sizes(tmp_path):
    good = np.random.default_rng(0).normal(size=(20, 20)) * 1e-6
    f = tmp_path / "m.npy"
    np.save(f, good)
    with pytest.raises(ParameterError, match=r"topography_file '.*nowhere\.txt' does not exist"):
        read_height_map(tmp_path / "nowhere.txt", A)
    for bad in (0.0, -1e-6, float("nan")):
        with pytest.raises(ParameterError, match=r"pixel_size"):
            read_height_map(f, bad)
    with pytest.raises(ParameterError, match=r"pixel_size = 0\.0 m is outside .*\(0, inf\)"):
        read_height_map(f, 0.0)
    np.save(f, good[None])
    with pytest.raises(ParameterError, match=r"2D array .* got shape \(1, 20, 20\)"):
        read_height_map(f, A)
    bad = good.copy()
    bad[3, 7] = np.nan
    np.save(f, bad)
    with pytest.raises(ParameterError, match=r"row 4, column 8 is nan"):
        read_height_map(f, A)
    np.save(f, good[:, :15])
    with pytest.raises(ParameterError, match=r"columns \(y positions\) = 15 .* \[16, inf\)"):
        read_height_map(f, A)
    np.save(f, np.array([["a"] * 20] * 20))
    with pytest.raises(ParameterError, match=r"heights must be real numbers"):
        read_height_map(f, A)
    with pytest.raises(ParameterError, match="flat"):
        map_spectrum(HeightMap(np.ones((32, 32)), A))


def test_other_formats_need_surface_topography(tmp_path):
    try:
        import SurfaceTopography  # noqa: F401
    except ImportError:
        f = tmp_path / "scan.x3p"
        f.write_bytes(b"PK\x03\x04")
        with pytest.raises(ParameterError) as err:
            read_height_map(f, A)
        msg = str(err.value)
        assert "SurfaceTopography" in msg and "not installed" in msg
        assert "plain text" in msg and ".npy" in msg and "'.x3p'" in msg
    else:  # pragma: no cover - optional dependency installed
        pytest.skip("SurfaceTopography is installed")


# ---------------------------------------------------------------- spectrum
def test_psd_matches_prescribed_spectrum(tmp_path, gaussian_map):
    psd, split, h, _txt = gaussian_map
    npy = tmp_path / "map.npy"
    np.save(npy, h)
    for window, inflation, k_min in (("none", 1.0, 8.0), ("hann", 2.0, 16.0)):
        spec = map_spectrum(read_height_map(npy, A), window=window)
        expected = expected_rings(spec, psd, split.q_th)
        sel = spec.q >= k_min * DQ  # the self-affine range (hann: above its smoothing bias)
        # ring mean / ensemble: scatter (n/2)^-1/2 (x ~2 for the Hann window's
        # correlated neighbours); over 20 seeds the normalised scatter was 0.85-1.1
        # (none) and 1.2-2.2 (hann): 5 of those units. Hann smoothing bias ~ 2.2/k^2
        # (the curvature of q^-3.6 over the main lobe) is < 1 % above 16 dq.
        z = (spec.c[sel] / expected[sel] - 1) * np.sqrt(spec.counts[sel] / 2) / inflation
        assert np.all(np.abs(z) < 5), (window, z)
        # the spectrum's nodes pass through the rings at their effective wavevectors
        np.testing.assert_allclose(spec.psd(spec.q), spec.c, rtol=1e-10)
        assert spec.psd.q_min == pytest.approx(DQ) and spec.psd.q_max == pytest.approx(math.pi / A)


def test_window_removes_leakage_of_a_non_periodic_map(cropped_map):
    psd, split, h = cropped_map
    hm = HeightMap(h, A)
    hann = map_spectrum(hm, window="hann")
    none = map_spectrum(hm, window="none")
    e_h = expected_rings(hann, psd, split.q_th)
    sel = hann.q >= 16 * DQ
    z = (hann.c[sel] / e_h[sel] - 1) * np.sqrt(hann.counts[sel] / 2) / 2.0
    assert np.all(np.abs(z) < 5), z
    # without a window the edges of the map leak a q^-2 tail: the top rings are
    # high, far outside the same 5-unit band (which therefore can fail), and more so
    # the higher q (the tail decays slower than q^-3.6)
    e_n = expected_rings(none, psd, split.q_th)
    top = none.q >= 100 * DQ
    z_n = (none.c[top] / e_n[top] - 1) * np.sqrt(none.counts[top] / 2) / 2.0
    assert np.all(z_n > 5) and np.all(np.diff(none.c[top] / e_n[top]) > 0)
    f_h, f_n = fit_hurst(hann.q, hann.c), fit_hurst(none.q, none.c)
    # 20 seeds: hann 0.796 +- 0.018, none 0.754 +- 0.010 (biased by the leakage)
    assert abs(f_h.hurst - HURST) < 0.05
    assert abs(f_n.hurst - HURST) > abs(f_h.hurst - HURST)


@pytest.mark.parametrize("window", ["none", "hann"])
def test_hurst_fit_finds_the_self_affine_range(gaussian_map, window):
    _psd, _split, h, _txt = gaussian_map
    spec = map_spectrum(HeightMap(h, A), window=window)
    fit = fit_hurst(spec.q, spec.c)
    # 20 seeds: none 0.796 +- 0.011, hann 0.801 +- 0.017; the tolerance is 0.05
    assert abs(fit.hurst - HURST) < 0.05
    assert fit.automatic and fit.q_b == spec.q[-1]
    assert Q0 / 1.3 < fit.q_a < 1.3 * Q0  # the knee is the roll-off (one ring is 1.26 x)
    forced = fit_hurst(spec.q, spec.c, q_range=(2 * Q0, math.pi / A))
    assert not forced.automatic and abs(forced.hurst - HURST) < 0.05
    assert forced(forced.q_a) == pytest.approx(forced.c_ref)
    # a fit across the roll-off is visibly worse: the range matters
    low = fit_hurst(spec.q, spec.c, q_range=(spec.q[0], math.pi / A))
    assert low.hurst < HURST - 0.1
    with pytest.raises(ParameterError, match="at least 5 rings"):
        fit_hurst(spec.q, spec.c, q_range=(Q0, 1.5 * Q0))


def test_hurst_fit_other_exponent():
    _psd, split = model(hurst=0.5)
    h = split.deterministic_surface(2, "gaussian").grid(N)
    spec = map_spectrum(HeightMap(h, A), window="none")
    assert abs(fit_hurst(spec.q, spec.c).hurst - 0.5) < 0.05


# ----------------------------------------------------------------- moments
def test_h_rms_from_psd_and_from_map(gaussian_map, cropped_map):
    _psd, split, h, _txt = gaussian_map
    m = map_moments(map_spectrum(HeightMap(h, A), window="none"))
    assert m["detrend"] == "mean" and m["h_rms_map"] == pytest.approx(np.std(h), rel=1e-12)
    # periodic map, no window: the PSD integral is the continuum form of the lattice
    # (Parseval) sum; the few lattice points below ~10 dq (Gauss circle) and the
    # roll-off kink between two rings make it 0.9 % low for exact amplitudes (next
    # assertion); with Gaussian amplitudes 20 seeds gave -1.3 % +- 0.4 % (min -2.3 %)
    assert abs(m["h_rms_psd"] / m["h_rms_map"] - 1) < 0.03
    fixed = split.deterministic_surface(11, "fixed").grid(N)
    mf = map_moments(map_spectrum(HeightMap(fixed, A), window="none"))
    assert mf["h_rms_map"] == pytest.approx(split.lattice_h_rms(), rel=1e-3)
    assert abs(mf["h_rms_psd"] / mf["h_rms_map"] - 1) < 0.015
    # the Hann window weighs the centre of the map, so on a map spanning 8 roll-off
    # wavelengths its PSD estimates the ensemble, not this map: 20 seeds gave a
    # spread of 2.9 % (periodic) and 4.3 % (cropped) about the map's own rms
    mh = map_moments(map_spectrum(HeightMap(h, A)))
    assert abs(mh["h_rms_psd"] / mh["h_rms_map"] - 1) < 0.10
    _p, _s, hc = cropped_map
    mc = map_moments(map_spectrum(HeightMap(hc, A)))
    assert abs(mc["h_rms_psd"] / mc["h_rms_map"] - 1) < 0.15


def test_rms_slope_psd_against_finite_differences(gaussian_map, cropped_map):
    psd, split, h, _txt = gaussian_map
    ratio = math.sqrt(fd_ratio(psd, split.q_th))
    # forward differences see q_x as 2 sin(q_x a/2)/a: for this spectrum, whose
    # slope is dominated by the top decade, the FD slope is 6 % below the spectral one
    assert 0.92 < ratio < 0.96
    m = map_moments(map_spectrum(HeightMap(h, A), window="none"))
    # 20 seeds: FD / (PSD x ratio) = 0.9999 +- 0.0015 (periodic, no window),
    # 0.9999 +- 0.008 (cropped, Hann): tolerances 1 % and 3 %
    assert abs(m["rms_slope_map"] / (m["rms_slope_psd"] * ratio) - 1) < 0.01
    assert abs(m["rms_slope_map"] / m["rms_slope_psd"] - 1) > 0.03  # the correction matters
    # the spectral slope of this very map (Parseval) agrees with the PSD integral
    a = np.fft.fft2(h) / N**2
    qx = 2 * math.pi * np.fft.fftfreq(N, d=A)
    q2 = qx[:, None] ** 2 + qx[None, :] ** 2
    assert m["rms_slope_psd"] == pytest.approx(math.sqrt(np.sum(q2 * np.abs(a) ** 2)), rel=0.01)
    pc, sc, hc = cropped_map
    mc = map_moments(map_spectrum(HeightMap(hc, A)))
    rc = math.sqrt(fd_ratio(pc, sc.q_th))
    assert abs(mc["rms_slope_map"] / (mc["rms_slope_psd"] * rc) - 1) < 0.03
    # Nayak's moments are those of the spectrum
    n0, n2, n4 = map_spectrum(HeightMap(h, A), window="none").psd.nayak_moments()
    assert (m["m0"], m["m2"], m["m4"]) == (n0, n2, n4)
    assert m["m2"] == pytest.approx(m["rms_slope_psd"] ** 2 / 2, rel=1e-12)


# ------------------------------------------------------- scenes and report
def test_roughness_params_topography_file(tmp_path):
    # defaults and behaviour unchanged
    d = RoughnessParams()
    assert (d.topography_file, d.pixel_size, d.topography_window) == ("", 0.0, "hann")
    assert d.build().h_rms() == pytest.approx(1e-6, rel=1e-12)
    psd, split = model()
    h = split.deterministic_surface(4, "fixed").grid(N)
    f = tmp_path / "map.npy"
    np.save(f, h)
    r = RoughnessParams(topography_file=str(f), pixel_size=A, topography_window="none")
    measured = r.build()
    assert measured.q_min == pytest.approx(DQ) and measured.q_max == pytest.approx(math.pi / A)
    e_star, p = 1.0e7, 1.0e5
    u = float(PerssonLaw(measured, e_star).separation(p))
    ref = float(PerssonLaw(psd.restrict(DQ, math.pi / A), e_star).separation(p))
    # fixed amplitudes: the measured C is the model's to the lattice discreteness of
    # the lowest rings (h_rms -0.9 %); 10 phase seeds gave u / u_model = 0.991 +- 0.002
    assert abs(u / ref - 1) < 0.03
    # the default (Hann) spectrum works as well; it is cached per file and options
    default = RoughnessParams(topography_file=str(f), pixel_size=A)
    law = PerssonLaw(default.build(), e_star)
    assert 0 < float(law.separation(p)) < 5 * h.std()
    assert default.build() is default.build()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"topography_file": "m.npy"}, r"roughness\.pixel_size = 0\.0 m .*\(0, inf\) when "
      r"roughness\.topography_file is set"),
     ({"topography_file": "m.npy", "pixel_size": -1e-6}, r"roughness\.pixel_size = -1e-06 m"),
     ({"topography_file": "m.npy", "pixel_size": 1e-6, "psd_file": "c.txt"},
      r"roughness\.topography_file = 'm\.npy' and roughness\.psd_file = 'c\.txt' are exclusive"),
     ({"topography_window": "tukey"}, r"roughness\.topography_window = 'tukey' is not one of")],
)  # fmt: skip
def test_roughness_params_validation(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        RoughnessParams(**kwargs)


def test_roughness_params_missing_map_names_parameter(tmp_path):
    # the file is read when the parameters are built, before anything is assembled
    with pytest.raises(ParameterError, match=r"roughness\.topography_file '.*none\.npy' does not"):
        RoughnessParams(topography_file=str(tmp_path / "none.npy"), pixel_size=A)


def test_topography_report(tmp_path, gaussian_map):
    _psd, _split, h, _txt = gaussian_map
    f = write_height_map(tmp_path / "map.txt", h[:256, :256], A)
    m = topography_report(f, None, tmp_path / "out")
    csv, png = tmp_path / "out" / "psd.csv", tmp_path / "out" / "psd.png"
    assert m["psd_csv"] == str(csv) and m["psd_png"] == str(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    spec = map_spectrum(read_height_map(f))
    again = read_psd_table(csv)  # psd.csv is a valid roughness.psd_file
    assert np.array_equal(again.q_nodes, spec.psd.q_nodes)
    assert np.array_equal(again.c_nodes, spec.psd.c_nodes)
    assert m["h_rms_psd"] == spec.psd.h_rms() and m["h_rms_map"] > 0
    assert m["hurst"] == fit_hurst(spec.q, spec.c).hurst
    assert (m["nx"], m["ny"], m["pixel_size"], m["window"]) == (256, 256, A, "hann")
    for key in ("rms_slope_map", "rms_slope_psd", "rms_curvature_psd", "m0", "m2", "m4",
                "hurst_q_a", "hurst_q_b", "q_min", "q_max"):  # fmt: skip
        assert math.isfinite(m[key]) and m[key] > 0, key
