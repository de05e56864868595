"""Smooth soft EHL: the full-film start (issue 19) and an independent reference.

A smooth rubber cylinder (``contact.model = "none"``) has nothing to carry the
load at low speed, so its start walks down from the rigid-isoviscous regime
(Moes M = 1, :func:`dolfinx_seal.scenes.cylinder.start_speed`) instead of up
from boundary lubrication (where it failed: ``DIVERGED_LINEAR_SOLVE after 2
Newton steps at 2.91e-05 m/s``).

The reference is the numpy line-EHL solver (:mod:`dolfinx_seal.verification.line_ehl`:
finite volumes on a linear-elastic half-space with exact influence
coefficients), which shares no code with the FEM scene (finite-strain
neo-Hookean body of finite size, P2/P1 mixed, the film on the deformed
surface).  Measured, FEM at the default 10 um mesh against the reference at
1600 cells, from 1 to 0.01 m/s (M 1.1 to 11): mu +0.07 to +0.36 %, h_min -0.09
to +0.17 %, h_central -0.12 to +0.24 %; the reference itself moves by at most
1e-3 between 800 and 1600 cells.  The 1 % tolerance is about three times the
largest difference, and well below what a wrong start (another branch) or a
wrong film would give (the rigid Martin film at 0.01 m/s is 4.9 eta U R / (2 F)
= 0.25 um against 0.92 um).
"""

from __future__ import annotations

import pytest

from dolfinx_seal.output import read_csv
from dolfinx_seal.scenes import make_parameters, run_scene, sweep_scene
from dolfinx_seal.scenes.cylinder import moes_load, start_speed
from dolfinx_seal.verification.line_ehl import for_cylinder, speed_continuation

SMOOTH = ["contact.model=none", "sweep_order=down"]
SPEEDS = [1.0, 0.1, 0.01]  # two decades, M 1.1 to 11
KEYS = ("mu", "h_min", "h_central")
RTOL = 1e-2


@pytest.fixture(scope="module")
def reference():
    p = make_parameters("cylinder", overrides=SMOOTH)
    speeds = [*SPEEDS[:2], 0.02, SPEEDS[2]]
    return {r.speed: r for r in speed_continuation(for_cylinder(p, n_cells=800), speeds)}


def test_the_smooth_cylinder_starts_in_full_film_and_walks_down():
    p = make_parameters("cylinder", overrides=[*SMOOTH, "film.speed=0.02"])
    assert moes_load(p, start_speed(p)) == pytest.approx(1.0, rel=1e-12)
    assert moes_load(p, 0.02) == pytest.approx(6.1, rel=1e-2)
    fast = make_parameters("cylinder", overrides=[*SMOOTH, "film.speed=3"])
    assert start_speed(fast) == 3.0  # already rigid-isoviscous: starts where it is asked


def test_smooth_cylinder_stribeck_matches_the_half_space_reference(reference, mpi_tmp_path):
    p = make_parameters("cylinder", overrides=SMOOTH)
    sweep_scene("cylinder", p, mpi_tmp_path, "film.speed", SPEEDS)
    rows = read_csv(mpi_tmp_path / "sweep.csv")
    assert [float(r["film.speed"]) for r in rows] == SPEEDS
    for r in rows:
        ref = reference[float(r["film.speed"])]
        for k in KEYS:
            assert float(r[k]) == pytest.approx(getattr(ref, k), rel=RTOL), (r["film.speed"], k)
        assert float(r["fluid_load_fraction"]) == 1.0
        assert float(r["load_balance_error"]) < 1e-9
        assert float(r["mass_balance_error"]) < 1e-6


@pytest.mark.parametrize("model", ["neo-hookean", "linear"])
def test_the_failing_start_of_the_issue_converges(model, mpi_tmp_path, reference):
    """``run cylinder --set contact.model=none --set film.speed=0.02`` (it stopped
    at its start), neo-Hookean and linear, against the reference at 0.02 m/s."""
    p = make_parameters("cylinder", overrides=["contact.model=none", "film.speed=0.02",
                                                f"material.model={model}"])  # fmt: skip
    r = run_scene("cylinder", p, mpi_tmp_path)
    assert r["converged"] and "full-film start" in r["strategy"]
    for k in KEYS:
        assert r[k] == pytest.approx(getattr(reference[0.02], k), rel=RTOL), k


def test_a_fine_finish_starts_rigid_isoviscous_and_meets_the_smooth_reference(reference):
    """A rough cylinder with h_rms 0.1 um: its boundary start stopped (DIVERGED_MAX_IT
    after 300 Newton steps), and the full-film start at 4 h_rms (4.2 mm/s, Moes M 13)
    diverged from the Hertz shape; the full-film start falls back to the smooth
    cylinder's rigid-isoviscous start (M = 1, 0.75 m/s) and walks down.  At 0.1 m/s
    the film is about 40 h_rms, where the asperities carry nothing and the rough
    contact is the smooth one: the half-space reference to the smooth test's 1 %."""
    from dolfinx_seal.coupled.results import lubricated_results
    from dolfinx_seal.scenes import cylinder

    p = make_parameters("cylinder", overrides=["roughness.h_rms=1e-7", "film.speed=0.1"])
    prob, _ = cylinder.CYLINDER.build_lubricated(p)
    try:
        s = cylinder.scales(p)
        info = cylinder.full_film_start(prob, p, s)
        r = lubricated_results(prob, symmetry_factor=s.symmetry_factor,
                               nominal_area=s.nominal_area)  # fmt: skip
    finally:
        prob.destroy()
    assert "rigid-isoviscous start at 0.75 m/s" in info["strategy"], info["strategy"]
    assert r["fluid_load_fraction"] > 1.0 - 1e-6
    for k in KEYS:
        assert r[k] == pytest.approx(getattr(reference[0.1], k), rel=RTOL), k
