"""Surface roughness: isotropic power spectra, moments, synthetic surfaces (numpy only).

* :class:`PowerSpectrum` -- piecewise power-law ``C(q)`` with exact moments;
  :class:`SelfAffinePSD` (cut-offs, optional roll-off), :func:`read_psd_table`
  (measured ``(q, C)`` table), :class:`RoughnessParams` (scene parameters).
* :class:`TwoScaleSplit` -- deterministic random-phase Fourier surface below
  ``q_th`` (:class:`FourierSurface`) and the statistical remainder ``C_sto``.
* :func:`radial_psd` -- PSD estimate of a periodic height map;
  :func:`read_topography` -- measured maps through SurfaceTopography (optional).
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

__all__ = [
    "FourierSurface",
    "PowerSpectrum",
    "RoughnessParams",
    "SelfAffinePSD",
    "TwoScaleSplit",
    "radial_psd",
    "read_psd_table",
    "read_topography",
]
