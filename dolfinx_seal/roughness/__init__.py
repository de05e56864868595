"""Surface roughness: isotropic power spectra, moments, synthetic surfaces (numpy only).

* :class:`PowerSpectrum` -- piecewise power-law ``C(q)`` with exact moments;
  :class:`SelfAffinePSD` (cut-offs, optional roll-off), :func:`read_psd_table`
  (measured ``(q, C)`` table), :class:`RoughnessParams` (scene parameters).
* :class:`TwoScaleSplit` -- deterministic random-phase Fourier surface below
  ``q_th`` (:class:`FourierSurface`) and the statistical remainder ``C_sto``.
* :func:`radial_psd` -- PSD estimate of a periodic height map;
  :func:`read_topography` -- measured maps through SurfaceTopography (optional).
* :mod:`~dolfinx_seal.roughness.topography` -- measured roughness from a height
  map: :func:`read_height_map` (text, ``.npy``, SurfaceTopography formats),
  :func:`map_spectrum` (detrended, windowed, ring-averaged PSD as a
  :class:`PowerSpectrum`), :func:`fit_hurst`, :func:`map_moments`,
  :func:`plot_map_spectrum`, :func:`topography_psd` (what
  ``RoughnessParams(topography_file=...)`` builds), :func:`topography_report`
  (``psd.csv``, ``psd.png`` and the moments).
"""

from dolfinx_seal.roughness.psd import (
    PowerSpectrum,
    RoughnessParams,
    SelfAffinePSD,
    read_psd_table,
)
from dolfinx_seal.roughness.surface import (
    FourierSurface,
    TwoScaleSplit,
    radial_psd,
    read_topography,
)
from dolfinx_seal.roughness.topography import (
    HeightMap,
    HurstFit,
    MapSpectrum,
    fit_hurst,
    map_moments,
    map_spectrum,
    plot_map_spectrum,
    read_height_map,
    topography_psd,
    topography_report,
    write_height_map,
)

__all__ = [
    "FourierSurface",
    "HeightMap",
    "HurstFit",
    "MapSpectrum",
    "PowerSpectrum",
    "RoughnessParams",
    "SelfAffinePSD",
    "TwoScaleSplit",
    "fit_hurst",
    "map_moments",
    "map_spectrum",
    "plot_map_spectrum",
    "radial_psd",
    "read_height_map",
    "read_psd_table",
    "read_topography",
    "topography_psd",
    "topography_report",
    "write_height_map",
]
