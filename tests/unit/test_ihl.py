"""Inverse hydrodynamic lubrication (verification/seal_leakage.py): the film that
carries a given pressure profile, from the cubic of the Reynolds flux."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dolfinx_seal.verification.seal_leakage import ihl_film, ihl_solution

ETA, R = 0.04, 0.04


def _profile() -> tuple[np.ndarray, np.ndarray]:
    """An asymmetric seal-like pressure: steep on the oil side (z < 0), gentle on the
    air side, peak 2 MPa, about 0.15 mm wide."""
    z = np.linspace(-60e-6, 140e-6, 4001)
    p = np.where(z < 0, 2e6 * np.exp(-((z / 25e-6) ** 2)), 2e6 * np.exp(-((z / 60e-6) ** 2)))
    return z, p - p.min()


@pytest.mark.parametrize("speed", [0.3, -0.3, 3.0])
def test_the_film_carries_the_profile_with_one_flow(speed):
    z, p = _profile()
    s = ihl_solution(z, p, ETA, speed, R)
    h = s["film"]
    band = np.isfinite(h)
    u = abs(speed)
    q = s["flow"] / (2 * math.pi * R) * math.copysign(1.0, speed)  # along the flow
    dpdx = np.gradient(p, z) * math.copysign(1.0, speed)
    flux = 0.5 * u * h[band] - h[band] ** 3 * dpdx[band] / (12 * ETA)
    # every point of the band passes the same flow (the Reynolds flux), to round-off
    assert np.max(np.abs(flux / q - 1.0)) < 1e-9
    # h* is Blok's formula, the film at the peak, and the layer left on the rod h*/2
    assert s["h_star"] == pytest.approx(ihl_film(z, p, ETA, speed))
    # (at the sampled peak p' is a central difference of the grid, 50 nm: not 0)
    assert h[np.argmax(p)] == pytest.approx(s["h_star"], rel=1e-3)
    assert s["transport_film_thickness"] == pytest.approx(0.5 * s["h_star"])
    # the film is continuous (the root branch switches only at the double root)
    hb = h[band]
    assert np.max(np.abs(np.diff(hb)) / hb[1:]) < 0.02
    # the steeper oil side leaves the thinner film on the out-stroke
    assert s["friction_force"] > 0


def test_the_out_stroke_film_is_thinner_and_films_grow_as_root_speed():
    z, p = _profile()
    out, back = ihl_solution(z, p, ETA, 1.0, R), ihl_solution(z, p, ETA, -1.0, R)
    assert out["h_star"] < back["h_star"]  # the oil side is the steeper
    assert out["flow"] > 0 > back["flow"]
    fast = ihl_solution(z, p, ETA, 4.0, R)
    assert fast["h_star"] == pytest.approx(2.0 * out["h_star"], rel=1e-12)
