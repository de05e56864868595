"""The roughness-scale homotopy of the UFL asperity laws (surface/asperity.py).

Linear-elastic contact of a surface whose heights are scaled by ``s`` has its
displacements scaled by ``s`` and its stresses by ``s``: Persson's relation of
the scaled spectrum is ``p_s(u) = s p(u / s)`` and its real area ``A_s(u) =
A(u / s)``.  The UFL law of a smooth surface evaluated at ``scale = s`` must
therefore be the law fitted, independently, to the spectrum ``s`` times rougher
(to the closed form's fit error, 2-3 %), and at ``scale = 1`` the law itself.
"""

from __future__ import annotations

import math

import dolfinx
import numpy as np
import pytest
import ufl
from mpi4py import MPI

from dolfinx_seal.contact import PerssonLaw
from dolfinx_seal.roughness import SelfAffinePSD
from dolfinx_seal.surface.asperity import area_fraction, contact_pressure

E_STAR = 10.7e6  # Pa: the default lip's NBR


def _law(h_rms: float):
    psd = SelfAffinePSD(h_rms=h_rms, hurst=0.8, q0=3e5, q1=1e8)
    return PerssonLaw(psd, E_STAR, 0.4).closed_form()


def _evaluate(expr_of_gap, gaps: np.ndarray) -> np.ndarray:
    """Values of a UFL expression of a (Constant) gap, one per gap [m]."""
    mesh = dolfinx.mesh.create_unit_interval(MPI.COMM_SELF, 1)
    gap = dolfinx.fem.Constant(mesh, 0.0)
    form = dolfinx.fem.form(expr_of_gap(gap, mesh) * ufl.dx(domain=mesh))
    out = []
    for g in gaps:
        gap.value = g
        out.append(dolfinx.fem.assemble_scalar(form))
    return np.array(out)


@pytest.mark.parametrize("s", [2.0, 5.0])
def test_a_scaled_smooth_law_is_the_law_of_the_rougher_surface(s):
    smooth, rough = _law(0.1e-6), _law(0.1e-6 * s)
    u = np.geomspace(0.05, 6.0, 25) * rough.h_rms  # the rough law's fit window
    p_scaled = _evaluate(
        lambda g, mesh: contact_pressure(smooth, g, scale=dolfinx.fem.Constant(mesh, s)), u
    )
    # both closed forms fit the same exact relation to 2-3 %: their difference is
    # bounded by the sum of the two fit errors
    tol = smooth.max_rel_error + rough.max_rel_error
    assert np.max(np.abs(p_scaled / rough.pressure(u) - 1.0)) < tol
    # the real contact area follows with the slope scaled by s
    p = np.array([0.1e6, 1e6, 3e6])
    a_scaled = _evaluate(
        lambda g, mesh: area_fraction(
            g * 1e12, E_STAR, smooth.rms_slope, dolfinx.fem.Constant(mesh, s)
        ),
        p * 1e-12,
    )
    assert np.allclose(a_scaled, rough.area_fraction(p), rtol=1e-3)


def test_at_scale_one_the_law_is_unchanged():
    law = _law(0.1e-6)
    u = np.geomspace(1e-3, 10.0, 30) * law.h_rms
    one = _evaluate(
        lambda g, mesh: contact_pressure(law, g, scale=dolfinx.fem.Constant(mesh, 1.0)), u
    )
    assert np.allclose(one, law.pressure(u), rtol=1e-12)


def test_the_law_stays_finite_positive_and_monotone_to_negative_gaps():
    """Below the window (u < 1e-3 h_rms) and at negative gaps the law is continued
    C^1 linearly in ln p, so a converged state keeps a positive separation up to
    pressures far above any seal's (the window's end is 1e-3 h_rms)."""
    law = _law(0.1e-6)
    u = np.linspace(-0.01, 0.01, 41) * law.h_rms
    p = _evaluate(lambda g, mesh: contact_pressure(law, g), u)
    assert np.all(np.isfinite(p)) and np.all(p > 0) and np.all(np.diff(p) < 0)
    # the default seal's peak (1.9 MPa) is reached at a positive separation
    p_end = law.pressure(1e-3 * law.h_rms)
    assert p_end > 1.9e6 and math.isfinite(p_end)
