"""The smooth FEM ball against an independent soft-EHL point-contact reference over
two decades of speed (issue 19).

The reference is :mod:`dolfinx_seal.verification.point_ehl` (finite volumes on an
elastic half-space with exact influence coefficients, numpy only), which shares no
code with the FEM scene (finite-strain neo-Hookean ball of finite size, P2/P1
mixed, curved second-order mesh, the film on the deformed surface).  Both are
incompressible: the FEM bulk has nu = 0.5 (mixed form), the reference assumes it
(shear tractions do not move the surface normally), and both take E* = E / (1 -
nu^2) = 1.6 MPa from the scene's ``material`` (``for_ball``).

The system: the S1 figure-18 ball at a tenth of its load (0.13 N: a_H = 0.85 mm
= 0.085 R, so the finite ball stays close to the half-space), no asperity contact,
Reynolds condition, lubricated disc of 2 Hertz radii in both, 1 -> 0.1 -> 0.01 m/s
(Moes M 9.2 / 52 / 291).  The reference value is the Richardson extrapolation of
20 and 30 cells per Hertz radius (second order).  Tolerances and why: see
:func:`test_smooth_ball_matches_the_point_contact_reference`.
"""

from __future__ import annotations

import pytest

from dolfinx_seal.scenes import make_parameters, sweep_scene
from dolfinx_seal.verification.point_ehl import for_ball, richardson, speed_continuation

SMOOTH_BALL = ["contact.model=none", "load=0.13", "film_extent=2.0", "sweep_order=down"]
SPEEDS = [1.0, 0.1, 0.01]  # compared: two decades, Moes M 9.2 to 291
WALK = [1.0, 0.3, 0.1, 0.03, 0.01]  # the FEM sweep's points (as the bench's)
KEYS = ("mu", "h_central", "h_min", "contact_radius")
#: relative tolerance per (speed, quantity): 2 % unless listed
RTOL = {(0.01, "h_min"): 0.04}


@pytest.fixture(scope="module")
def ball_reference():
    p = make_parameters("ball", overrides=SMOOTH_BALL)
    coarse, fine = (speed_continuation(for_ball(p, cells_per_radius=n), SPEEDS) for n in (20, 30))
    return {
        c.speed: richardson(c, f, ratio=1.5, keys=KEYS) for c, f in zip(coarse, fine, strict=True)
    }


@pytest.mark.slow
def test_smooth_ball_matches_the_point_contact_reference(ball_reference, mpi_tmp_path):
    """FEM at the default mesh (a/20, the rim band at a/60) walking down 1 -> 0.3 ->
    0.1 -> 0.03 -> 0.01 m/s, compared at 1, 0.1 and 0.01 m/s.  (Asked for 1, 0.1, 0.01 m/s only, this test's
    sweep once reached 0.316 m/s and then failed every step towards 0.1 m/s, the
    last with a PETSc error -1 in the linear solve after 0 Newton steps at
    0.311 m/s; ``dolfinx-seal sweep ball`` over 1, 0.1 m/s with the same parameters
    then converged, 13 Newton steps to 0.1 m/s with the bench's values: not
    reproduced, an open question of the continuation, not of the comparison.)

    Measured (bench/ball_point_ehl_reference.py, also at 0.3 and 0.03 m/s, 2 ranks,
    5 December), FEM against the reference at 1 / 0.1 / 0.01 m/s: mu +0.29 / +0.28 /
    +1.05 %, h_central +0.31 / +0.25 / -1.06 %, contact radius -0.11 / +0.19 /
    +0.28 %, h_min +0.28 / +0.38 / -1.35 %.  2 %: the two sides' uncertainties
    added at 1 and 0.1 m/s (the reference's Richardson value within 0.5 % of its
    finest grid, the FEM's headline outputs within 0.64 % of a/30 at the default,
    docs/scenes/ball.md), kept at 0.01 m/s, where both are less certain (the
    reference's Richardson values of the grid pairs 15/20 and 20/30 differ by up to
    1.9 %) but the measured differences stay below 1.4 %.  h_min at 0.01 m/s (M =
    291) sits in the narrowest exit constriction: 4 %, the reference's 1.9 % plus
    the FEM's distance to its own limit (1.2-1.9 % at 0.1 m/s, where that was
    extrapolated).  Without the rim zone, h_min was -6.61 % there and the bound 9 %."""
    p = make_parameters("ball", overrides=SMOOTH_BALL)
    rows = sweep_scene("ball", p, mpi_tmp_path, "film.speed", WALK)
    assert [float(r["speed"]) for r in rows] == WALK
    for r in rows:
        v = float(r["speed"])
        assert float(r["fluid_load_fraction"]) == 1.0
        assert float(r["load_balance_error"]) < 1e-9
        assert float(r["mass_balance_error"]) < 1e-8
        if v not in SPEEDS:
            continue
        for k in KEYS:
            rtol = RTOL.get((v, k), 0.02)
            assert float(r[k]) == pytest.approx(ball_reference[v][k], rel=rtol), (v, k)
