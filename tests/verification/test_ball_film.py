"""The lubricated ball (S1 section 3): balances, what is assembled, serial = parallel,
a short sweep, and (slow) the Hamrock-Dowson isoviscous-elastic film."""

from __future__ import annotations

import numpy as np
import pytest
from mpi4py import MPI

from dolfinx_seal.contact.hertz import hertz_point
from dolfinx_seal.coupled.results import lubricated_results
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import column, read_csv
from dolfinx_seal.scenes import make_parameters, run_scene, sweep_scene
from dolfinx_seal.scenes.ball import build_lubricated, start_lubricated
from dolfinx_seal.verification.ehl import IsoviscousElasticFilm
from dolfinx_seal.verification.parallel import copy_coupled_state

A_H, P_H = hertz_point(1.3, 0.01, 1.2e6 / 0.75)  # S1 fig 18 ball: 1.83 mm, 0.186 MPa
#: The meshes of these tests have no rim zone (``rim_refinement`` 1, as when their
#: figures were measured): they check balances, starts and references, not h_min's
#: resolution, which ``test_h_min_follows_the_rim_element_size`` checks.
NO_RIM = {"rim_refinement": 1.0}
COARSE = {"h_contact": A_H / 8, **NO_RIM}  # ~36k unknowns; a sweep 0.3 -> 0.1 m/s about 1 min


def test_full_film_point_balances_and_splits_the_load(mpi_tmp_path):
    p = make_parameters("ball", values={**COARSE, "film": {"speed": 0.3}})
    r = run_scene("ball", p, mpi_tmp_path)
    assert r["dof_counts"].keys() == {"displacement", "fluid_pressure", "position"}
    assert r["normal_load"] == pytest.approx(1.3, rel=1e-9)  # twice the half model
    assert r["load_balance_error"] < 1e-9
    assert r["mass_balance_error"] < 1e-8
    assert r["fluid_load_fraction"] > 0.99  # full film at U = 0.3 m/s (h_c ~ 10 h_rms)
    parts = r["mu_couette"] + r["mu_poiseuille"] + r["mu_asperity"]
    assert parts == pytest.approx(r["mu"], rel=1e-12)
    assert 0 < r["h_min"] < r["h_central"]
    assert r["x_cavitation"] > 0  # rupture downstream of the centre
    assert 0 < r["cavitation_fraction"] < 1
    if COMM_WORLD.rank == 0:
        table = np.loadtxt(mpi_tmp_path / "film_map.csv", delimiter=",", skiprows=1)
        assert np.all(table[:, 4] >= 0)  # p_fluid >= 0 (Reynolds condition)
        assert (mpi_tmp_path / "film_map.png").stat().st_size > 1000
        xdmf = (mpi_tmp_path / "fields.xdmf").read_text()
        assert "fluid_pressure" in xdmf


def test_dry_ball_has_no_film_unknowns():
    p = make_parameters("ball", values={**COARSE, "lubricated": False})
    from dolfinx_seal.scenes.ball import build_dry

    prob = build_dry(p)[0]
    assert prob.film is None and set(prob.dof_counts()) == {"displacement", "position"}


def test_parallel_equals_serial_copy():
    """The 2-rank force-controlled point solves the same discrete problem as one rank:
    its fields, copied dof by dof into a one-rank build of the same mesh with the flat
    held where the 2 ranks put it, leave Newton nothing to do (at most 2 steps) and
    give the same load, mu and film.  (A one-rank force-controlled build inside a
    2-rank job aborts in MPI with MPI_ERR_ARG; run separately, 1 and 2 ranks give
    mu and h_central equal to 3e-14, README.)"""
    if COMM_WORLD.size == 1:
        pytest.skip("compares 2 ranks with a serial copy")
    p = make_parameters("ball", values={**COARSE, "film": {"speed": 0.3}})
    prob, info = build_lubricated(p)
    start_lubricated(prob, p)
    par = lubricated_results(prob, symmetry_factor=2.0, nominal_area=info["nominal_area"])
    serial, _ = build_lubricated(p, comm=MPI.COMM_SELF, position=par["counter_position"])
    serial.set_fraction(1.0)
    copy_coupled_state(prob, serial)
    its = serial.solver.solve(where="serial copy").newton_iterations
    assert its <= 2
    ser = lubricated_results(serial, symmetry_factor=2.0, nominal_area=info["nominal_area"])
    assert ser["normal_load"] == pytest.approx(par["normal_load"], rel=1e-6)
    for k in ("mu", "load_fluid", "h_min", "h_central", "max_fluid_pressure"):
        assert ser[k] == pytest.approx(par[k], rel=1e-6), k


def test_short_sweep_down_keeps_every_point(mpi_tmp_path):
    p = make_parameters("ball", values=COARSE)
    speeds = [0.3, 0.1]
    rows = sweep_scene("ball", p, mpi_tmp_path, "film.speed", speeds)
    assert len(rows) == 2
    COMM_WORLD.barrier()
    table = read_csv(mpi_tmp_path / "sweep.csv")
    assert column(table, "film.speed") == speeds  # the ball sweeps downwards by default
    h_c, mu = column(table, "h_central"), column(table, "mu")
    assert h_c[1] < h_c[0] and mu[1] < mu[0]  # the hydrodynamic branch
    assert min(column(table, "fluid_load_fraction")) > 0.99
    assert max(column(table, "load_balance_error")) < 1e-9
    assert max(column(table, "mass_balance_error")) < 1e-8
    if COMM_WORLD.rank == 0:
        assert (mpi_tmp_path / "sweep.png").stat().st_size > 1000
        assert (mpi_tmp_path / "speed_1.000e-01" / "film_map.png").exists()


@pytest.mark.slow
def test_smooth_full_film_follows_hamrock_dowson(mpi_tmp_path):
    """Smooth ball (no asperity contact), S1 figure-18 system, a/20 elements, sweep
    0.3 -> 0.1 m/s (about 2 min).

    Measured (bench/ball_hamrock_dowson.py): h_min +1.9 % / -2.2 % against the
    Hamrock-Dowson regression, h_central +6.8 % / +10.4 %, and the speed exponent of
    h_central 0.61 (regression 0.64).  h_central converges under refinement to about
    +14 % at 0.1 m/s (a/10 ... a/30 study in the README): an offset from the 1978
    regression that this test does not hide, so it checks h_min (5 %, the fit is over
    17 cases of 1970s grids) and the speed exponent (0.05), not h_central's level."""
    p = make_parameters(
        "ball", values={"h_contact": A_H / 20, "contact": {"model": "none"}, **NO_RIM}
    )
    rows = sweep_scene("ball", p, mpi_tmp_path, "film.speed", [0.3, 0.1])
    assert len(rows) == 2
    hd = IsoviscousElasticFilm(0.01, 1.2e6 / 0.75, 0.1, 1.3)
    for r in rows:
        v = float(r["speed"])
        assert r["h_min"] == pytest.approx(hd.h_min(v / 2), rel=0.05), v
        assert r["mass_balance_error"] < 1e-8 and r["load_balance_error"] < 1e-9
    exponent = np.log(rows[0]["h_central"] / rows[1]["h_central"]) / np.log(3.0)
    assert exponent == pytest.approx(0.64, abs=0.05)


@pytest.mark.slow
def test_smooth_ball_starts_at_one_metre_per_second(mpi_tmp_path):
    """``run ball --set contact.model=none --set film.speed=1.0`` (Moes M about 90)
    stopped at its start (``DIVERGED_LINE_SEARCH after 8 Newton steps``, scaled
    residual stalled at 2.5e-2: the film rows were scaled at h_rms = 1 um under a
    22 um film).  With the film rows scaled at the film (``ball.film_gap``) it
    converges on the default mesh (a/7, about 2 min): measured 36 Newton steps,
    h_central 20.77 um against Hamrock-Dowson's 21.55 um (-3.6 %).  The 10 % bound
    is the regression's scatter at these meshes (+2 to +15 % at a/20, bench table),
    not a mesh-converged check."""
    p = make_parameters(
        "ball", values={"contact": {"model": "none"}, "film": {"speed": 1.0}, **NO_RIM}
    )
    r = run_scene("ball", p, mpi_tmp_path)
    assert r["converged"]
    hd = IsoviscousElasticFilm(0.01, 1.2e6 / 0.75, 0.1, 1.3)
    assert r["h_central"] == pytest.approx(hd.h_central(0.5), rel=0.10)
    assert r["fluid_load_fraction"] == 1.0
    assert r["mass_balance_error"] < 1e-8 and r["load_balance_error"] < 1e-9


@pytest.mark.slow
def test_rough_ball_walks_into_boundary_lubrication(mpi_tmp_path):
    """h_rms 3.6 um, a/12, sweep down to 0.01 and 1 mm/s (S1 figs 23-24 trend): the
    asperities take over load from the fluid while the total pressure stays Hertz-like.

    Reference: Hertz.  The dry ball with this roughness is itself Hertz-like (contact
    radius +1.2 %, peak -2.1 %, bench/ball_low_speed.py), and the lubricated total
    pressure was measured within 2.6 / 3.6 % rms of p_H of Hertz at these speeds on
    a/15; 5 % leaves room for the coarser mesh."""
    p = make_parameters(
        "ball", values={"h_contact": A_H / 12, "roughness": {"h_rms": 3.6e-6}, **NO_RIM}
    )
    speeds = [0.01, 1e-3]
    rows = sweep_scene("ball", p, mpi_tmp_path, "film.speed", speeds)
    assert [float(r["speed"]) for r in rows] == speeds
    fluid = [float(r["fluid_load_fraction"]) for r in rows]
    assert 1.0 > fluid[0] > fluid[1] > 0.0  # load moves from the fluid to the asperities
    for r in rows:
        assert r["load_balance_error"] < 1e-9 and r["mass_balance_error"] < 1e-8
        assert r["normal_load"] == pytest.approx(1.3, rel=1e-9)
    if COMM_WORLD.rank == 0:
        for v in speeds:
            table = np.loadtxt(mpi_tmp_path / f"speed_{v:.3e}" / "film_map.csv", delimiter=",",
                               skiprows=1)  # fmt: skip
            X, Y, p_fluid, p_cont = table[:, 2], table[:, 3], table[:, 4], table[:, 5]
            assert p_fluid.min() >= 0.0 and p_cont.min() >= 0.0
            r = np.hypot(X, Y)
            hertz = P_H * np.sqrt(np.clip(1.0 - (r / A_H) ** 2, 0.0, None))
            near = r < 1.5 * A_H
            rms = np.sqrt(np.mean((p_fluid + p_cont - hertz)[near] ** 2)) / P_H
            assert rms < 0.05, v


@pytest.mark.slow
def test_the_three_cavitation_models_start_and_share_the_inlet_film(mpi_tmp_path):
    """The default rough ball at 1 m/s (a/10, about 1 min each) under the Reynolds
    condition, JFO and no cavitation.  JFO and full Sommerfeld did not start before
    (JFO: the film presolve stalled at 6e-2 of its residual; no cavitation: linear
    convergence to the solver's limit, 22 min in all); both now start from the
    Reynolds-condition film and coupled state (docs/design.md).

    References: conservation (JFO and the full-Sommerfeld film create no oil:
    measured mass balance 2e-16 and 1e-16 at 1 m/s; 1e-10 leaves round-off room
    over 2 ranks), the sign conditions of each model on the film map, and the
    inlet: the central film is set upstream of the outlet, where the models differ
    (EHL's outlet condition hardly moves h_central; measured here within 0.6 %),
    so 2 % from the Reynolds-condition film."""
    rows = {}
    for model in ("reynolds", "jfo", "none"):
        p = make_parameters("ball", values={"h_contact": A_H / 10,
                                            "film": {"speed": 1.0, "cavitation": model}, **NO_RIM})  # fmt: skip
        out = mpi_tmp_path / model
        r = rows[model] = run_scene("ball", p, out)
        assert r["converged"] and r["load_balance_error"] < 1e-9, model
        if COMM_WORLD.rank == 0:
            table = np.loadtxt(out / "film_map.csv", delimiter=",", skiprows=1)
            p_min, p_max = table[:, 4].min(), r["max_fluid_pressure"]
            # a negative lobe downstream without cavitation; p >= 0 under the Reynolds
            # condition (a bound); under JFO p >= 0 only through the film fraction's
            # complementarity, whose rows are areas times pressures (measured -0.07 Pa
            # against a peak of 0.18 MPa, at a complementarity residual of 3e-16)
            floor = {"reynolds": 0.0, "jfo": -1e-6 * p_max}
            if model == "none":
                assert p_min < -0.01 * p_max, p_min
            else:
                assert p_min >= floor[model], (model, p_min)
    for model in ("jfo", "none"):
        assert rows[model]["mass_balance_error"] < 1e-10, model
        assert rows[model]["h_central"] == pytest.approx(rows["reynolds"]["h_central"], rel=0.02)


@pytest.mark.slow
def test_h_min_follows_the_rim_element_size(mpi_tmp_path):
    """h_min sits in the side lobes of the exit constriction (r = 0.96-0.97 a_Hertz at
    0.3 and 0.1 m/s), inside the rim band 0.8-1.1 a_Hertz: a/10 with the rim at a/20
    (``rim_refinement`` 2) gives the h_min of the uniform a/20 mesh with a third fewer
    unknowns.  Measured on 2 ranks: -0.28 % and +0.24 %; a uniform a/15 is 2.1 % below
    a/20 at both speeds (docs/scenes/ball.md), so 0.5 % fails a misplaced band."""
    speeds = [0.3, 0.1]
    rows = {}
    for name, ce, rr in (("rim", 10.0, 2.0), ("uniform", 20.0, 1.0)):
        p = make_parameters("ball", values={"contact_elements": ce, "rim_refinement": rr})
        rows[name] = sweep_scene("ball", p, mpi_tmp_path / name, "film.speed", speeds)
    assert int(rows["rim"][0]["dofs"]) < 0.75 * int(rows["uniform"][0]["dofs"])
    for r, u in zip(rows["rim"], rows["uniform"], strict=True):
        assert float(r["h_min"]) == pytest.approx(float(u["h_min"]), rel=5e-3)
        assert float(r["mu"]) == pytest.approx(float(u["mu"]), rel=5e-3)


@pytest.mark.slow
def test_the_default_ball_walks_into_mixed_lubrication(mpi_tmp_path):
    """The default ball on its default mesh (a/20, rim a/60), walked down from full
    film to 0.003 m/s: every point converges with its load and mass balanced, the
    asperities take a growing share of the load and mu rises as the speed falls
    (the mixed branch of the Stribeck curve, below its minimum near 0.03 m/s),
    and the side-lobe film stays a continuum film.  On the a/20 rim of the
    stability table the same walk stopped at 6.39 mm/s, where that film had
    collapsed to 0.04 h_rms (docs/scenes/ball.md, "Mixed lubrication").  Measured
    on one rank: h_min 726, 470, 342 nm, mu 0.0383, 0.0803, 0.1218, asperity
    share 0.95 %, 2.3 %, 3.6 %; an a/80 rim gives h_min within 1.0 % and mu
    within 0.23 %."""
    p = make_parameters("ball")
    speeds = [0.01, 0.005, 0.003]
    rows = sweep_scene("ball", p, mpi_tmp_path, "film.speed", speeds)
    assert [float(r["speed"]) for r in rows] == speeds
    mu = [float(r["mu"]) for r in rows]
    fluid = [float(r["fluid_load_fraction"]) for r in rows]
    assert mu[0] < mu[1] < mu[2]
    assert 1.0 > fluid[0] > fluid[1] > fluid[2] > 0.9
    for r in rows:
        assert float(r["h_min"]) > 0.1 * p.roughness.h_rms, r["speed"]
        assert float(r["load_balance_error"]) < 1e-9
        assert float(r["mass_balance_error"]) < 1e-8


def test_zero_speed_is_refused_with_the_way_out():
    from dolfinx_seal.errors import ParameterError

    with pytest.raises(ParameterError, match=r"film.speed = 0 .*lubricated = false"):
        make_parameters("ball", values={"film": {"speed": 0.0}})


def test_s1_appendix_d_scene_file_is_the_stated_system():
    """The scene file of S1 appendix D (figs D.3-D.4): E* = 5.45 MPa, R = 0.95 cm,
    F = 3 N, eta U = 1 Pa m, smooth, lubricated cap covering [-4 a_H, 1.5 a_H]."""
    from pathlib import Path

    import dolfinx_seal

    toml = Path(dolfinx_seal.__file__).parent / "scenes" / "ball-s1-appendix-d.toml"
    p = make_parameters("ball", scene_file=toml)
    a_h, _ = hertz_point(p.load, p.radius, p.material.E_star)
    assert p.material.E_star == pytest.approx(5.45e6, rel=1e-12)
    assert (p.radius, p.load, p.contact.model) == (0.0095, 3.0, "none")
    assert p.film.viscosity * p.film.speed == pytest.approx(1.0, rel=1e-12)
    assert p.film_extent >= 4.0 and p.h_contact == pytest.approx(a_h / 20, rel=2e-3)
