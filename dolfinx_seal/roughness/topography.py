"""Measured roughness: the isotropic PSD ``C(q)`` of a height map, its moments and plot.

A height map is a rectangular grid of heights ``h[i, j]`` [m] at ``x = i a``,
``y = j a`` with one square pixel size ``a`` [m] (index ``[i_x, i_y]``: one text
row per ``x`` position).  It is read from

* plain text: rows of heights in metres separated by whitespace or commas,
  ``#`` starting a comment; a comment line ``# pixel_size = 1e-6`` (metres, an
  optional trailing ``m``) gives the pixel size when the caller does not;
* NumPy ``.npy`` (a 2D float array in metres; the pixel size is an argument);
* any other format through the optional package SurfaceTopography, when it is
  installed (heights and sizes converted from the file's unit to metres).

The spectrum follows the convention of :mod:`dolfinx_seal.roughness.psd` (S1,
S0 eq 16): ``C(q) = (2 pi)^-2 int d^2x <h(x) h(0)> exp(-i q.x)`` [m^4], so that
``<h^2> = 2 pi int q C dq``.  For a map of ``nx x ny`` pixels, side ``L_x = nx a``,
``L_y = ny a``, with Fourier coefficients ``a_k = (nx ny)^-1 sum h exp(-i q_k.x)``
on the lattice ``q_k = 2 pi (k_x / L_x, k_y / L_y)``, a periodic surface has
``<|a_k|^2> = C(q_k) dq_x dq_y`` (:mod:`~dolfinx_seal.roughness.surface`), hence
the periodogram ``C_k = |a_k|^2 L_x L_y / (2 pi)^2``.  The estimate:

1. detrend: subtract the least-squares plane (``"plane"``, the default with a
   window) or the mean (``"mean"``, the default without: a periodic map has no
   tilt);
2. window (``"hann"``, default, for non-periodic measured maps; ``"none"`` for
   one period of a periodic surface): multiply by the separable Hann window
   ``w`` after removing the ``w``-weighted mean, and divide the periodogram by
   ``mean(w^2)`` (power correction), so ``<C_k>`` is ``C`` smoothed over the
   window's main lobe (about +- 2 lattice cells) instead of a leakage-dominated
   sum: the edges of a non-periodic map act as steps whose ``q^-2`` tail
   exceeds a self-affine ``q^-2(1+H)`` spectrum at large ``q``;
3. radial average: the mean of ``C_k`` over the lattice points in log-spaced
   rings between ``q_lo = 2 pi / min(L_x, L_y)`` and the Nyquist wavevector
   ``q_hi = pi / a`` (``bins_per_decade`` rings per decade; empty rings dropped).

The rings become the nodes ``(q*, mean C_k)`` of a
:class:`~dolfinx_seal.roughness.psd.PowerSpectrum` (log-log interpolation, as
:func:`~dolfinx_seal.roughness.read_psd_table` builds one), ``q*`` the
wavevector at which the local power law of the ring means equals the ring's
mean (not the mean ``|q|``, which a steep spectrum's mean over the ring
overshoots by a few %), extended over the half rings at both ends to ``[q_lo,
q_hi]`` by the power law of the end segment, so every consumer of a spectrum
(Persson laws, flow factors, scenes) takes it.  Its moments are the continuum
form of the lattice sums: on a periodic map without a window they match the
map's own (Parseval) to about 1 % for ``h_rms``, dominated by the few lattice
points of the lowest rings, and better for the slope.
Each ring mean averages ``n/2`` independent modes (``a_{-k} = conj(a_k)``):
for a Gaussian surface its relative scatter is ``(n/2)^{-1/2}``
(:attr:`MapSpectrum.counts` holds ``n``).
"""

from __future__ import annotations

import functools
import io
import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range
from dolfinx_seal.roughness.psd import PowerSpectrum, read_text

FloatArray = NDArray[np.float64]

#: Smallest number of pixels along each side of a height map.
MIN_PIXELS = 16
#: File suffixes read as plain text without SurfaceTopography ("" = no suffix).
TEXT_SUFFIXES = ("", ".txt", ".dat", ".csv", ".asc")
#: File suffixes read as NumPy arrays without SurfaceTopography.
NUMPY_SUFFIXES = (".npy",)
#: Length units SurfaceTopography may report, in metres.
_UNITS = {
    "m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "nm": 1e-9,
    "pm": 1e-12, "A": 1e-10, "Å": 1e-10,
}  # fmt: skip
_PIXEL_HEADER = re.compile(
    r"^\s*#\s*pixel[_ ]size\s*[=:]\s*([-+0-9.eE]+|nan|inf)\s*(?:\[?\s*m\s*\]?)?\s*$", re.I
)


def _supported_formats() -> str:
    return (
        "plain text (" + ", ".join(s or "no suffix" for s in TEXT_SUFFIXES) + ": rows of "
        "heights in metres) and NumPy (" + ", ".join(NUMPY_SUFFIXES) + ")"
    )


# ------------------------------------------------------------------ the map
@dataclass(frozen=True)
class HeightMap:
    """A validated height map on a grid of square pixels (SI units).

    Args:
        heights: 2D array ``h[i_x, i_y]`` [m], finite, at least
            ``MIN_PIXELS x MIN_PIXELS``.
        pixel_size: Side ``a`` of a pixel [m], ``> 0``.
        source: Where the map came from (a path, or a description), for messages.

    Attributes:
        heights, pixel_size, source: As given (``heights`` as a float64 array).
    """

    heights: FloatArray
    pixel_size: float
    source: str = "height map"

    def __post_init__(self) -> None:
        src = self.source
        try:
            h = np.asarray(self.heights, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError(f"{src}: heights must be numbers (m)") from None
        if h.ndim != 2:
            raise ParameterError(
                f"{src}: a height map must be a 2D array of heights (m), got shape {h.shape}"
            )
        check_int_range(f"{src}: number of rows (x positions)", h.shape[0], MIN_PIXELS)
        check_int_range(f"{src}: number of columns (y positions)", h.shape[1], MIN_PIXELS)
        bad = np.argwhere(~np.isfinite(h))
        if bad.size:
            i, j = (int(v) for v in bad[0])
            raise ParameterError(
                f"{src}: height at row {i + 1}, column {j + 1} is {float(h[i, j])!r}; every "
                f"height must be a finite number (m) ({len(bad)} are not): fill or crop "
                f"missing points"
            )
        object.__setattr__(self, "heights", h)
        object.__setattr__(
            self, "pixel_size", check_positive(f"{src}: pixel_size", self.pixel_size, "m")
        )

    @property
    def shape(self) -> tuple[int, int]:
        """``(nx, ny)``: pixels along x (rows) and y (columns)."""
        return (int(self.heights.shape[0]), int(self.heights.shape[1]))

    @property
    def size(self) -> tuple[float, float]:
        """``(L_x, L_y) = (nx a, ny a)`` [m]."""
        nx, ny = self.shape
        return (nx * self.pixel_size, ny * self.pixel_size)


def _parse_text(p: Path, name: str) -> tuple[FloatArray, float | None]:
    """Rows of numbers of a text height map, and the pixel size of its header (or None)."""
    text = read_text(
        p, name, f"is not a text file; supported without SurfaceTopography: {_supported_formats()}"
    )
    header: float | None = None
    for n, line in enumerate(text.splitlines(), start=1):
        if not line.lstrip().startswith("#") or not re.search(r"pixel[_ ]size", line, re.I):
            continue
        if not (m := _PIXEL_HEADER.match(line)):
            raise ParameterError(
                f"{p}:{n}: cannot read the pixel size from {line.strip()!r}; write it in "
                f"metres, e.g. '# pixel_size = 1e-06'"
            )
        header = check_positive(f"{p}:{n}: pixel_size", float(m.group(1)), "m")
        break
    try:  # fast path (numpy's C parser); any problem: the slow parser names it
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            h = np.loadtxt(io.StringIO(text.replace(",", " ")), dtype=float, ndmin=2)
        if h.size and np.all(np.isfinite(h)):
            return h, header
    except (ValueError, UserWarning):  # ragged or non-numeric rows; no data
        pass
    return _parse_text_slowly(p, name, text), header


def _parse_text_slowly(p: Path, name: str, text: str) -> FloatArray:
    """The rows of a text map line by line, naming the first line that is wrong."""
    tokens: list[str] = []
    first: tuple[int, int] | None = None  # (line, columns) of the first data row
    line_of_row: list[int] = []
    for n, line in enumerate(text.splitlines(), start=1):
        s = line.split("#", 1)[0].strip()
        if not s:
            continue
        parts = s.replace(",", " ").split()
        if first is None:
            first = (n, len(parts))
        elif len(parts) != first[1]:
            raise ParameterError(
                f"{p}:{n}: row has {len(parts)} values, expected {first[1]} like the first "
                f"row (line {first[0]}); a height map needs rows of equal length"
            )
        tokens.extend(parts)
        line_of_row.append(n)
    if first is None:
        raise ParameterError(f"{name} {str(p)!r} holds no heights (only comments or blank lines)")
    try:
        values = np.array(tokens, dtype=float)
    except ValueError:
        for k, t in enumerate(tokens):
            try:
                float(t)
            except ValueError:
                r, c = divmod(k, first[1])
                raise ParameterError(
                    f"{p}:{line_of_row[r]}: column {c + 1}: {t!r} is not a number; heights "
                    f"must be numbers in metres"
                ) from None
        raise  # pragma: no cover - numpy rejected a list that float() accepts
    h = values.reshape(len(line_of_row), first[1])
    bad = np.argwhere(~np.isfinite(h))
    if bad.size:
        r, c = (int(v) for v in bad[0])
        raise ParameterError(
            f"{p}:{line_of_row[r]}: column {c + 1}: height {tokens[r * first[1] + c]!r} is not "
            f"finite; every height must be a finite number (m): fill or crop missing points"
        )
    return h


def _read_surface_topography(p: Path, pixel_size: float | None, name: str) -> HeightMap:
    """A map in any other format, through SurfaceTopography (heights and sizes to metres).

    A file without a physical size takes ``pixel_size``; one without a length unit
    is read as metres.  Not exercised by the tests (the package is optional).
    """
    try:
        import SurfaceTopography  # type: ignore[import-not-found]
    except ImportError:
        raise ParameterError(
            f"{name} {str(p)!r}: the format {p.suffix!r} needs the optional Python package "
            f"SurfaceTopography, which is not installed; supported without it: "
            f"{_supported_formats()}"
        ) from None
    try:  # pragma: no cover - optional dependency, not installed in the test environment
        with SurfaceTopography.open_topography(str(p)) as reader:
            channel = reader.default_channel
            unit = channel.unit if channel.unit is not None else "m"
            if unit not in _UNITS:
                raise ParameterError(
                    f"{name} {str(p)!r}: unknown length unit {unit!r}; known: {', '.join(_UNITS)}"
                )
            kwargs: dict[str, Any] = {} if channel.unit is not None else {"unit": "m"}
            sized = channel.physical_sizes is not None
            if not sized:
                if pixel_size is None:
                    raise ParameterError(
                        f"{name} {str(p)!r} gives no physical size: pass pixel_size (m)"
                    )
                kwargs["physical_sizes"] = tuple(
                    n * pixel_size / _UNITS[unit] for n in channel.nb_grid_pts
                )
            topo = reader.topography(**kwargs)
    except ParameterError:  # pragma: no cover
        raise
    except Exception as e:  # pragma: no cover - the reader's own errors, reported as ours
        raise ParameterError(f"{name} {str(p)!r}: SurfaceTopography cannot read it: {e}") from None
    if topo.dim != 2 or not topo.is_uniform:  # pragma: no cover
        raise ParameterError(f"{name} {str(p)!r}: not a uniform 2D map (dim {topo.dim})")
    f = _UNITS[unit]  # pragma: no cover
    nx, ny = topo.nb_grid_pts  # pragma: no cover
    sx, sy = (s * f for s in topo.physical_sizes)  # pragma: no cover
    if not math.isclose(sx / nx, sy / ny, rel_tol=1e-6):  # pragma: no cover
        raise ParameterError(
            f"{name} {str(p)!r}: pixels are not square ({sx / nx:g} m x {sy / ny:g} m)"
        )
    if pixel_size is not None and sized:  # pragma: no cover
        _same_pixel(p, pixel_size, sx / nx, "the file's physical size")
    return HeightMap(np.asarray(topo.heights(), float) * f, sx / nx, str(p))  # pragma: no cover


def _same_pixel(p: Path, given: float, found: float, what: str) -> None:
    if not math.isclose(given, found, rel_tol=1e-9):
        raise ParameterError(
            f"pixel_size = {given!r} m disagrees with {what} ({found!r} m) of {str(p)!r}; "
            f"give one or make them equal"
        )


def read_height_map(
    path: str | Path, pixel_size: float | None = None, *, name: str = "topography_file"
) -> HeightMap:
    """Read and validate a height map (see the module docstring for the formats).

    Args:
        path: The file: plain text (``.txt``, ``.dat``, ``.csv``, ``.asc`` or no
            suffix), ``.npy``, or another format read through SurfaceTopography.
        pixel_size: Pixel size [m], ``> 0``; may be omitted for a text file with a
            ``# pixel_size = ...`` header line (both given: they must agree).
        name: Name of the parameter holding ``path``, used in error messages
            (e.g. ``"roughness.topography_file"``).

    Raises:
        ParameterError: Missing or unreadable file, ragged rows, non-numeric or
            non-finite heights (naming the line and column), fewer than
            ``MIN_PIXELS`` pixels along a side, a missing or non-positive pixel size.
    """
    p = Path(path)
    if pixel_size is not None:
        pixel_size = check_positive("pixel_size", pixel_size, "m")
    if not p.exists():
        raise ParameterError(f"{name} {str(p)!r} does not exist", name)
    if not p.is_file():
        raise ParameterError(f"{name} {str(p)!r} is not a file", name)
    suffix = p.suffix.lower()
    if suffix in NUMPY_SUFFIXES:
        try:
            h = np.load(p, allow_pickle=False)
        except (ValueError, OSError, EOFError) as e:
            raise ParameterError(f"{name} {str(p)!r} is not a readable .npy array: {e}") from None
        if not (np.issubdtype(h.dtype, np.floating) or np.issubdtype(h.dtype, np.integer)):
            raise ParameterError(
                f"{name} {str(p)!r}: heights must be real numbers (m), got dtype {h.dtype}"
            )
        header = None
    elif suffix in TEXT_SUFFIXES:
        h, header = _parse_text(p, name)
    else:
        return _read_surface_topography(p, pixel_size, name)
    if pixel_size is None and header is None:
        raise ParameterError(
            f"pixel_size (m) of {str(p)!r} is required: pass it"
            + (", or add a header line '# pixel_size = <metres>'" if suffix != ".npy" else "")
        )
    if pixel_size is not None and header is not None:
        _same_pixel(p, pixel_size, header, "the '# pixel_size' header")
    a = pixel_size if pixel_size is not None else header
    return HeightMap(np.asarray(h, dtype=float), float(a), str(p))  # type: ignore[arg-type]


def write_height_map(path: str | Path, heights: ArrayLike, pixel_size: float) -> Path:
    """Write ``heights`` [m] as a plain-text map with a ``# pixel_size`` header [m].

    Full double precision (17 significant digits), one row per x position.
    """
    hm = HeightMap(np.asarray(heights, dtype=float), pixel_size, str(path))
    p = Path(path)
    with p.open("w") as fh:
        fh.write(f"# height map [m], rows = x positions\n# pixel_size = {hm.pixel_size!r} m\n")
        np.savetxt(fh, hm.heights, fmt="%.17g")
    return p


# ------------------------------------------------------------- the spectrum
def detrended(h: ArrayLike, detrend: str = "plane") -> FloatArray:
    """``h`` [m] minus its mean (``"mean"``) or its least-squares plane (``"plane"``)."""
    check_choice("detrend", detrend, ("plane", "mean"))
    ha = np.asarray(h, dtype=float)
    out = ha - ha.mean()
    if detrend == "plane":
        nx, ny = ha.shape
        x = np.arange(nx) - 0.5 * (nx - 1)  # centred: the three columns are orthogonal
        y = np.arange(ny) - 0.5 * (ny - 1)
        bx = np.einsum("ij,i->", out, x) / (ny * np.sum(x * x))
        by = np.einsum("ij,j->", out, y) / (nx * np.sum(y * y))
        out = out - bx * x[:, None] - by * y[None, :]
    return out


def _hann(n: int) -> FloatArray:
    """The periodic ("DFT-even") Hann window ``0.5 - 0.5 cos(2 pi i / n)``, ``i < n``."""
    return 0.5 - 0.5 * np.cos(2.0 * math.pi * np.arange(n) / n)


def resolve_detrend(window: str, detrend: str | None) -> str:
    """``detrend``, or by default ``"plane"`` with a window and ``"mean"`` without.

    One period of a periodic surface (``window="none"``) has no tilt to remove: a
    plane fitted to it takes part of the longest wavelengths (and breaks the
    periodicity); a measured map is levelled by removing its plane.
    """
    if detrend is None:
        return "plane" if window != "none" else "mean"
    return check_choice("detrend", detrend, ("plane", "mean"))


def periodogram(
    hmap: HeightMap, window: str = "hann", detrend: str | None = None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The 2D estimate ``C_k`` [m^4] on the half lattice of ``numpy.fft.rfft2``.

    Returns:
        ``(|q_k| [1/m], C_k [m^4], weight)`` as flat arrays over the half lattice
        (``k_y >= 0``); ``weight`` is 2 for a mode standing also for its mirror
        ``-k`` and 1 for the self-conjugate ones, so weighted sums are sums over
        the full lattice.  With ``window="none"`` and a periodic map
        ``sum(weight C_k) dq_x dq_y`` is the mean square of the detrended map
        (Parseval), exactly.  ``detrend``: as in :func:`map_spectrum`.
    """
    check_choice("window", window, ("hann", "none"))
    h = detrended(hmap.heights, resolve_detrend(window, detrend))
    nx, ny = hmap.shape
    a = hmap.pixel_size
    if window == "hann":
        w = np.outer(_hann(nx), _hann(ny))
        h = w * (h - np.sum(w * h) / np.sum(w))  # zero mean after windowing
        power = float(np.mean(w * w))
    else:
        power = 1.0
    f = np.fft.rfft2(h)
    c = np.abs(f) ** 2 * (a * a) / (4.0 * math.pi**2 * nx * ny * power)
    qx = 2.0 * math.pi * np.fft.fftfreq(nx, d=a)
    qy = 2.0 * math.pi * np.fft.rfftfreq(ny, d=a)
    q = np.hypot(qx[:, None], qy[None, :])
    wt = np.full(q.shape, 2.0)
    wt[:, 0] = 1.0
    if ny % 2 == 0:
        wt[:, -1] = 1.0
    return q.ravel(), c.ravel(), wt.ravel()


@dataclass(frozen=True)
class MapSpectrum:
    """The radially averaged spectrum of a height map.

    Attributes:
        psd: The :class:`PowerSpectrum` built from the rings (support ``[q_lo, q_hi]``).
        q: Effective wavevector of each non-empty ring [1/m]: where the local power
            law of the ring means takes the ring's mean value (within the ring).
        c: Mean ``C_k`` of each ring [m^4].
        counts: Number of lattice points (full plane) in each ring.
        edges: All ring edges [1/m], from ``q_lo = 2 pi / min(L_x, L_y)`` to
            ``q_hi = pi / a`` (``len(edges) - 1`` rings, empty ones not in ``q``).
        window, detrend: The options used.
        hmap: The height map.
    """

    psd: PowerSpectrum
    q: FloatArray
    c: FloatArray
    counts: NDArray[np.int64]
    edges: FloatArray
    window: str
    detrend: str
    hmap: HeightMap = field(repr=False)


def ring_edges(hmap: HeightMap, bins_per_decade: float = 10.0) -> FloatArray:
    """Log-spaced ring edges [1/m] from ``2 pi / min(L_x, L_y)`` to ``pi / a``."""
    check_range("bins_per_decade", bins_per_decade, 1.0, 100.0)
    q_lo = 2.0 * math.pi / min(hmap.size)
    q_hi = math.pi / hmap.pixel_size
    n = max(1, math.ceil(math.log10(q_hi / q_lo) * bins_per_decade - 1e-9))
    return np.geomspace(q_lo, q_hi, n + 1)


def ring_index(q: ArrayLike, edges: FloatArray) -> NDArray[np.int64]:
    """Ring of each ``|q|`` [1/m] (-1 outside ``[edges[0], edges[-1]]``, 1e-9 relative slack)."""
    qa = np.asarray(q, dtype=float)
    idx = np.clip(np.searchsorted(edges, qa, side="right") - 1, 0, edges.size - 2)
    inside = (qa >= edges[0] * (1 - 1e-9)) & (qa <= edges[-1] * (1 + 1e-9))
    return np.where(inside, idx, -1)


def map_spectrum(
    hmap: HeightMap,
    window: str = "hann",
    detrend: str | None = None,
    bins_per_decade: float = 10.0,
) -> MapSpectrum:
    """Isotropic PSD of a height map (module docstring: convention, window, rings).

    Args:
        hmap: The map (:func:`read_height_map`, or :class:`HeightMap` of an array).
        window: ``"hann"`` (default; measured, non-periodic maps) or ``"none"``
            (one period of a periodic surface).
        detrend: ``"plane"`` or ``"mean"``; default ``"plane"`` with the Hann
            window, ``"mean"`` without (:func:`resolve_detrend`).
        bins_per_decade: Rings per decade of ``q``, in ``[1, 100]``.

    Raises:
        ParameterError: The detrended map is flat (no roughness to describe).
    """
    detrend = resolve_detrend(window, detrend)
    q, c, wt = periodogram(hmap, window, detrend)
    edges = ring_edges(hmap, bins_per_decade)
    idx = ring_index(q, edges)
    live = idx >= 0
    nb = edges.size - 1
    cnt = np.bincount(idx[live], weights=wt[live], minlength=nb)
    sc = np.bincount(idx[live], weights=(wt * c)[live], minlength=nb)
    sq = np.bincount(idx[live], weights=(wt * q)[live], minlength=nb)
    ok = (cnt > 0) & (sc > 0)
    if np.count_nonzero(ok) < 2:
        raise ParameterError(
            f"{hmap.source}: the detrended height map is flat (no power in at least two "
            f"rings of q); there is no roughness spectrum to compute"
        )
    rings = np.flatnonzero(ok)
    qm, cm, n = sq[ok] / cnt[ok], sc[ok] / cnt[ok], np.rint(cnt[ok]).astype(np.int64)
    qe = _effective_q(q[live], wt[live], idx[live], rings, qm, cm)
    qn, cn = _extend(qe, cm, edges[0], edges[-1])
    return MapSpectrum(PowerSpectrum(qn, cn), qe, cm, n, edges, window, detrend, hmap)


def _effective_q(
    q: FloatArray,
    wt: FloatArray,
    idx: NDArray[np.int64],
    rings: NDArray[np.int64],
    qm: FloatArray,
    cm: FloatArray,
) -> FloatArray:
    """The wavevector at which each ring mean is the local power law's value.

    A ring mean of ``C ~ q^e`` is ``mean_k(q_k^e)``, which exceeds ``C`` at the mean
    ``|q|`` (convexity: by 3.7 % for ``e = -3.6`` and 10 rings per decade), so the
    ring is placed at ``q* = mean_k(q_k^e)^(1/e)``, ``e`` the log-log slope of the
    ring means about it (the geometric mean of ``|q_k|`` when ``e = 0``), kept
    between the smallest and largest ``|q_k|`` of the ring.
    """
    if qm.size < 2:  # pragma: no cover - map_spectrum needs two rings
        return qm
    lq, lc = np.log(qm), np.log(cm)
    e = np.gradient(lc, lq)
    pos = np.full(int(idx.max()) + 1, -1)
    pos[rings] = np.arange(rings.size)
    r = pos[idx]
    sel = r >= 0
    q, wt, r = q[sel], wt[sel], r[sel]
    ek = e[r]
    lnq = np.log(q / qm[r])  # relative to the ring's mean: no overflow of q^e
    small = np.abs(e) < 1e-8
    w = np.bincount(r, weights=wt, minlength=rings.size)
    geo = np.bincount(r, weights=wt * lnq, minlength=rings.size) / w
    mom = np.bincount(r, weights=wt * np.exp(ek * lnq), minlength=rings.size) / w
    safe_e = np.where(small, 1.0, e)
    rel = np.where(small, geo, np.log(mom) / safe_e)
    lo = np.full(rings.size, np.inf)
    hi = np.full(rings.size, -np.inf)
    np.minimum.at(lo, r, lnq)
    np.maximum.at(hi, r, lnq)
    return qm * np.exp(np.clip(rel, lo, hi))


def _extend(
    q: FloatArray, c: FloatArray, q_lo: float, q_hi: float
) -> tuple[FloatArray, FloatArray]:
    """Nodes ``(q, c)`` continued to ``q_lo`` and ``q_hi`` by the end segments' power laws."""
    lq, lc = np.log(q), np.log(c)
    if q[0] > q_lo * (1 + 1e-9):
        e = (lc[1] - lc[0]) / (lq[1] - lq[0])
        lq = np.concatenate(([math.log(q_lo)], lq))
        lc = np.concatenate(([lc[0] + e * (lq[0] - lq[1])], lc))
    if q[-1] < q_hi * (1 - 1e-9):
        e = (lc[-1] - lc[-2]) / (lq[-1] - lq[-2])
        lq = np.concatenate((lq, [math.log(q_hi)]))
        lc = np.concatenate((lc, [lc[-1] + e * (lq[-1] - lq[-2])]))
    return np.exp(lq), np.exp(lc)


# ----------------------------------------------------------------- Hurst fit
@dataclass(frozen=True)
class HurstFit:
    """A least-squares power law ``C = c_ref (q / q_a)^{-2(1+H)}`` on ``[q_a, q_b]``.

    Attributes:
        hurst: The Hurst exponent ``H`` [-] (``-(exponent)/2 - 1``).
        exponent: The fitted log-log slope of ``C(q)`` [-].
        c_ref: The fitted ``C`` at ``q_a`` [m^4].
        q_a, q_b: The fitted range [1/m] (centres of the first and last ring used).
        n_rings: Number of rings fitted.
        rms_log_residual: Root-mean-square of ``ln C - fit`` over the rings [-].
        automatic: Whether the range was chosen automatically (knee search).
    """

    hurst: float
    exponent: float
    c_ref: float
    q_a: float
    q_b: float
    n_rings: int
    rms_log_residual: float
    automatic: bool

    def __call__(self, q: ArrayLike) -> FloatArray:
        """The fitted ``C(q)`` [m^4]."""
        return self.c_ref * (np.asarray(q, dtype=float) / self.q_a) ** self.exponent


def fit_hurst(
    q: ArrayLike,
    c: ArrayLike,
    q_range: tuple[float, float] | None = None,
    q_start: float | None = None,
    min_rings: int = 5,
) -> HurstFit:
    """Fit the self-affine range of a ring spectrum ``(q, c)`` by least squares in log-log.

    Args:
        q, c: Ring wavevectors [1/m] and mean ``C`` [m^4] (:class:`MapSpectrum`).
        q_range: The self-affine range ``(q_a, q_b)`` [1/m]; ``None`` chooses it:
            the upper end is the last ring, the lower end the knee of the best
            (least-squares) "plateau, then power law" fit among the rings above
            ``q_start``, so a roll-off below the knee is left out.
        q_start: Lowest ring considered by the automatic choice [1/m]; default the
            4th lattice wavevector ``4 q[0]``: the window and the few modes of the
            lowest rings bias them.
        min_rings: Fewest rings in the fitted range (>= 3).

    Raises:
        ParameterError: Fewer than ``min_rings`` rings in the range.
    """
    check_int_range("min_rings", min_rings, 3)
    qa, ca = np.asarray(q, dtype=float), np.asarray(c, dtype=float)
    x, y = np.log(qa), np.log(ca)
    if q_range is not None:
        lo, hi = (float(v) for v in q_range)
        check_positive("q_range[0]", lo, "1/m")
        check_range("q_range[1]", hi, lo, math.inf, lo_open=True, unit="1/m (> q_range[0])")
        sel = (qa >= lo * (1 - 1e-9)) & (qa <= hi * (1 + 1e-9))
        automatic = False
    else:
        start = 4.0 * qa[0] if q_start is None else check_positive("q_start", q_start, "1/m")
        cand = np.flatnonzero(qa >= start * (1 - 1e-9))
        if cand.size < min_rings:
            raise ParameterError(
                f"the automatic Hurst fit needs at least {min_rings} rings above q_start = "
                f"{start:g} 1/m, got {cand.size}; give q_range"
            )
        xs, ys = x[cand], y[cand]
        best, knee = math.inf, 0
        for j in range(cand.size - min_rings + 1):
            a = np.column_stack((np.ones_like(xs), np.maximum(xs - xs[j], 0.0)))
            coef, *_ = np.linalg.lstsq(a, ys, rcond=None)
            sse = float(np.sum((a @ coef - ys) ** 2))
            if sse < best * (1 - 1e-12):
                best, knee = sse, j
        sel = np.zeros(qa.size, dtype=bool)
        sel[cand[knee:]] = True
        automatic = True
    n = int(np.count_nonzero(sel))
    if n < min_rings:
        raise ParameterError(f"the Hurst fit needs at least {min_rings} rings in q_range, got {n}")
    slope, icpt = np.polyfit(x[sel], y[sel], 1)
    res = y[sel] - (icpt + slope * x[sel])
    q_a, q_b = float(qa[sel][0]), float(qa[sel][-1])
    return HurstFit(
        hurst=float(-slope / 2.0 - 1.0),
        exponent=float(slope),
        c_ref=float(math.exp(icpt + slope * math.log(q_a))),
        q_a=q_a,
        q_b=q_b,
        n_rings=n,
        rms_log_residual=float(np.sqrt(np.mean(res**2))),
        automatic=automatic,
    )


# ------------------------------------------------------------------ moments
def map_moments(spec: MapSpectrum, fit: HurstFit | None = None) -> dict[str, Any]:
    """Moments of a height map, from the map itself and from its spectrum.

    From the (detrended) map: ``h_rms_map`` [m] and ``rms_slope_map`` [-], the
    latter from forward differences along x and y,
    ``(<(dh/dx)^2> + <(dh/dy)^2>)^(1/2)`` (a difference sees a mode of wavevector
    ``q_x`` as ``2 sin(q_x a/2)/a``: 0.64 of ``q_x`` at Nyquist, so for a spectrum
    reaching Nyquist it is below the spectral value).  From the spectrum
    ``C(q)``: ``h_rms_psd``, ``rms_slope_psd`` (``(2 pi int q^3 C dq)^(1/2)``),
    ``rms_curvature_psd`` [1/m] and Nayak's profile moments ``m0`` [m^2],
    ``m2`` [-], ``m4`` [1/m^2] (:meth:`PowerSpectrum.nayak_moments`).  With a
    ``fit``: ``hurst`` and its range ``hurst_q_a``, ``hurst_q_b`` [1/m].
    """
    hm = spec.hmap
    h = detrended(hm.heights, spec.detrend)
    a = hm.pixel_size
    gx = np.diff(h, axis=0) / a
    gy = np.diff(h, axis=1) / a
    psd = spec.psd
    m0, m2, m4 = psd.nayak_moments()
    out: dict[str, Any] = {
        "source": hm.source,
        "nx": hm.shape[0],
        "ny": hm.shape[1],
        "pixel_size": hm.pixel_size,
        "size_x": hm.size[0],
        "size_y": hm.size[1],
        "window": spec.window,
        "detrend": spec.detrend,
        "q_min": psd.q_min,
        "q_max": psd.q_max,
        "h_rms_map": float(np.sqrt(np.mean(h * h))),
        "h_rms_psd": psd.h_rms(),
        "rms_slope_map": float(np.sqrt(np.mean(gx * gx) + np.mean(gy * gy))),
        "rms_slope_psd": psd.rms_slope(),
        "rms_curvature_psd": psd.rms_curvature(),
        "m0": m0,
        "m2": m2,
        "m4": m4,
    }
    if fit is not None:
        out.update(hurst=fit.hurst, hurst_q_a=fit.q_a, hurst_q_b=fit.q_b)
    return out


# --------------------------------------------------------------------- plot
def plot_map_spectrum(spec: MapSpectrum, path: str | Path, fit: HurstFit | None = None) -> Path:
    """Write a log-log PNG of ``C(q)``: the rings, the spectrum's nodes and the Hurst fit.

    Drawn with matplotlib's Agg canvas directly (no pyplot, no display needed).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import LogFormatter, NullFormatter

    p = Path(path)
    fig = Figure(figsize=(6.0, 4.2))
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    ax.loglog(spec.psd.q_nodes, spec.psd.c_nodes, "-", color="0.6", lw=1, label="PowerSpectrum")
    ax.loglog(spec.q, spec.c, "o", ms=3.5, color="C0", label=f"rings ({spec.window} window)")
    if fit is not None:
        qf = np.geomspace(fit.q_a, fit.q_b, 50)
        ax.loglog(qf, fit(qf), "--", color="C3", lw=1.5,
                  label=f"fit: H = {fit.hurst:.3f} on [{fit.q_a:.3g}, {fit.q_b:.3g}] 1/m")  # fmt: skip
    hm = spec.hmap
    ax.set_xlabel("wavevector q [1/m]")
    ax.set_ylabel("C(q) [m⁴]")
    ax.set_title(
        f"{Path(hm.source).name}: {hm.shape[0]} x {hm.shape[1]} px, a = {hm.pixel_size:.3g} m, "
        f"h_rms(PSD) = {spec.psd.h_rms():.3g} m",
        fontsize=9,
    )
    for axis in (ax.xaxis, ax.yaxis):  # plain "1e+04" labels: no mathtext parser to build
        axis.set_major_formatter(LogFormatter(labelOnlyBase=True))
        axis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(frameon=False, fontsize=8)
    fig.tight_layout()
    fig.savefig(p, dpi=120)
    return p


# ------------------------------------------------------------ entry points
def topography_psd(
    path: str | Path,
    pixel_size: float | None = None,
    *,
    window: str = "hann",
    detrend: str | None = None,
    bins_per_decade: float = 10.0,
    name: str = "topography_file",
) -> PowerSpectrum:
    """The :class:`PowerSpectrum` of the height map in ``path`` (pixel size [m]).

    The result is cached by file (path, size and modification time) and options,
    so a scene that builds its roughness several times reads the map once.
    """
    p = Path(path)
    try:
        st = p.stat()
        stamp: tuple[Any, ...] = (str(p), str(p.resolve()), st.st_size, st.st_mtime_ns)
    except OSError:
        stamp = (str(p), None, None, None)  # read_height_map reports the missing file
    return _cached_psd(stamp, pixel_size, window, detrend, float(bins_per_decade), name)


@functools.lru_cache(maxsize=8)
def _cached_psd(
    stamp: tuple[Any, ...],
    pixel_size: float | None,
    window: str,
    detrend: str | None,
    bins_per_decade: float,
    name: str,
) -> PowerSpectrum:
    hm = read_height_map(stamp[0], pixel_size, name=name)
    return map_spectrum(hm, window, detrend, bins_per_decade).psd


def topography_report(
    path: str | Path,
    pixel_size: float | None,
    out_dir: str | Path,
    *,
    window: str = "hann",
    detrend: str | None = None,
    bins_per_decade: float = 10.0,
    q_range: tuple[float, float] | None = None,
) -> dict[str, Any]:
    """Write ``psd.csv`` and ``psd.png`` of a height map to ``out_dir``; return its moments.

    ``psd.csv`` holds the nodes of the spectrum, ``q`` [1/m], ``C`` [m^4], in the
    two-column format of :func:`~dolfinx_seal.roughness.read_psd_table`, so it can
    be a scene's ``roughness.psd_file``.  The returned dict is :func:`map_moments`
    with the Hurst fit (``q_range`` as in :func:`fit_hurst`) and the paths written.
    """
    hm = read_height_map(path, pixel_size)
    spec = map_spectrum(hm, window, detrend, bins_per_decade)
    fit = fit_hurst(spec.q, spec.c, q_range)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    csv = out / "psd.csv"
    with csv.open("w") as fh:
        fh.write(
            f"# isotropic PSD of {hm.source} ({hm.shape[0]} x {hm.shape[1]} px, pixel "
            f"{hm.pixel_size!r} m, {window} window, {spec.detrend} detrend)\n"
            "# convention: <h^2> = 2 pi int q C(q) dq\n# q [1/m], C [m^4]\n"
        )
        for qq, cc in zip(spec.psd.q_nodes, spec.psd.c_nodes, strict=True):
            fh.write(f"{float(qq)!r}, {float(cc)!r}\n")
    png = plot_map_spectrum(spec, out / "psd.png", fit)
    moments = map_moments(spec, fit)
    moments.update(psd_csv=str(csv), psd_png=str(png))
    return moments
