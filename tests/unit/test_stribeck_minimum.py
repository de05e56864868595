"""Location of a Stribeck minimum from samples (no FEM)."""

from __future__ import annotations

import numpy as np
import pytest

from dolfinx_seal.coupled.sweep import stribeck_minimum


def test_vertex_of_a_log_parabola_is_found_exactly():
    # log10 mu = -2 + 0.8 (log10 eta_v + 2.3)^2: minimum mu = 0.01 at eta_v = 10^-2.3
    ev = np.array([1e-1, 10**-1.5, 1e-2, 10**-2.5, 1e-3])
    mu = 10 ** (-2.0 + 0.8 * (np.log10(ev) + 2.3) ** 2)
    e, m, bracketed = stribeck_minimum(ev[::-1], mu[::-1])  # any order
    assert bracketed
    assert e == pytest.approx(10**-2.3, rel=1e-10) and m == pytest.approx(0.01, rel=1e-10)


def test_minimum_at_the_end_is_not_bracketed():
    ev = np.array([1e-3, 1e-2, 1e-1])
    e, m, bracketed = stribeck_minimum(ev, np.array([0.05, 0.03, 0.02]))
    assert not bracketed and (e, m) == (1e-1, 0.02)
