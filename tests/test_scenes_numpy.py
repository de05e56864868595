"""The two pure-numpy scenes, ``rubber-friction`` and ``flat``: CLI, Python and TOML runs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from dolfinx_seal import scenes
from dolfinx_seal.cli import main
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import column, read_csv
from dolfinx_seal.scenes.rubber_friction import s3_h_rms

SCENE_DIR = Path(scenes.__file__).parent
SMALL_RF = ["--set", "points_per_decade=10", "--set", "n_curve=21", "--set", "roughness.q1=2e5"]
SMALL_FLAT = ["--set", "points_per_decade=10", "--set", "n_pressures=16"]


def load(path: Path) -> dict:
    return json.loads((path / "results.json").read_text())


def test_registered():
    assert {"rubber-friction", "flat"} <= set(scenes.available())
    assert scenes.get("flat").summary and scenes.get("rubber-friction").summary


def test_rubber_friction_cli_run(mpi_tmp_path):
    out = mpi_tmp_path / "rf"
    assert main(["run", "rubber-friction", *SMALL_RF, "--set", "speed=0.5", "--out", str(out)]) == 0
    res = load(out)
    assert res["scene"] == "rubber-friction"
    assert res["parameters"]["speed"] == 0.5 and res["parameters"]["material"]["model"] == "sls"
    assert res["speed"] == 0.5 and 1e-8 < res["speed_peak"] < 1e4
    assert res["mu"] > 0 and res["mu"] <= res["mu_peak"] * (1 + 1e-9)
    assert 0 < res["contact_area_fraction"] < 1 and res["converged"] is True
    assert "versions" in res and res["wall_time_s"] > 0
    for key in ("normal_load", "friction_force", "h_min"):  # not computed -> absent
        assert key not in res
    for f in ("rubber_friction.png", "mu_curve.csv", "contact_function.csv"):
        assert (out / f).stat().st_size > 0
    curve = np.loadtxt(out / "mu_curve.csv", delimiter=",", skiprows=1)
    assert curve.shape == (21, 2) and np.all(curve[:, 1] >= 0)
    assert res["mu_peak"] >= curve[:, 1].max() * (1 - 1e-12)  # the refined maximum


def test_rubber_friction_speed_sweep(mpi_tmp_path):
    out = mpi_tmp_path / "rf_sweep"
    args = [
        "sweep",
        "rubber-friction",
        *SMALL_RF,
        "--over",
        "speed",
        "--values",
        "1e-4:1e2:7:log",
    ]
    assert main([*args, "--out", str(out)]) == 0
    rows = read_csv(out / "sweep.csv")
    assert len(rows) == 7
    v, mu = column(rows, "speed"), column(rows, "mu")
    np.testing.assert_allclose(v, np.geomspace(1e-4, 1e2, 7), rtol=1e-12)
    # the vectorised sweep equals independent single runs
    p = scenes.make_parameters("rubber-friction", overrides=SMALL_RF[1::2])
    ref = p.model().mu(np.array(v))
    np.testing.assert_allclose(mu, ref, rtol=1e-12)
    assert (out / "sweep.png").exists()
    assert load(out)["points_finished"] == 7


def test_rubber_friction_toml_and_python(mpi_tmp_path):
    toml = SCENE_DIR / "rubber-friction.toml"
    p = scenes.make_parameters("rubber-friction", toml, ["points_per_decade=10", "n_curve=21"])
    assert p.roughness.q1 == 1000.0 * p.roughness.q0 and p.material.tau == 1e-3
    # S3's q0 h0 = 1 at zeta_max = 1000, written as h_rms in the file
    assert p.roughness.h_rms == pytest.approx(s3_h_rms(2000.0, 2e6, 0.85), rel=1e-15)
    res = scenes.run_scene("rubber-friction", p, mpi_tmp_path / "rf_toml")
    assert res["mu"] == pytest.approx(float(p.model().mu(np.array([1.0]))[0]), rel=1e-12)
    # a sweep over a nested parameter goes through the per-point path
    rows = scenes.sweep_scene("rubber-friction", p, mpi_tmp_path / "rf_tau", "material.tau",
                              [1e-3, 1e-2])  # fmt: skip
    # mu depends on v tau only: tau x10 at the same v is mu at 10 v
    assert rows[1]["mu"] == pytest.approx(float(p.model().mu(np.array([10.0]))[0]), rel=1e-9)


def test_flat_cli_run_and_toml(mpi_tmp_path):
    out = mpi_tmp_path / "flat"
    toml = SCENE_DIR / "flat.toml"
    argv = ["run", "flat", "--scene-file", str(toml), *SMALL_FLAT, "--set", "film.speed=2e-5"]
    assert main([*argv, "--out", str(out)]) == 0
    res = load(out)
    assert res["parameters"]["roughness"]["hurst"] == 0.8
    assert res["mu"] == pytest.approx(
        (res["sigma_contact"] + res["sigma_fluid"]) / 0.1618e6, rel=1e-12
    )
    assert res["p_contact"] + res["p_fluid"] == pytest.approx(0.1618e6, rel=1e-12)
    assert res["hydroplaning"] is False and res["zeta1"] > 1
    assert (out / "flat.png").exists() and (out / "profile.csv").exists()
    prof = np.loadtxt(out / "profile.csv", delimiter=",", skiprows=1)
    assert prof.shape[1] == 4 and np.all(np.diff(prof[:, 1]) <= 1e-15)


def test_flat_sweep_shows_the_drop(mpi_tmp_path):
    out = mpi_tmp_path / "flat_sweep"
    argv = ["sweep", "flat", *SMALL_FLAT, "--over", "film.speed", "--values", "1e-6:1e-2:9:log"]
    assert main([*argv, "--out", str(out)]) == 0
    rows = read_csv(out / "sweep.csv")
    mu, hp = column(rows, "mu"), [r["hydroplaning"] == "True" for r in rows]
    assert len(rows) == 9 and hp[0] is False and hp[-1] is True
    assert max(mu[:3]) > 30 * min(mu[5:])  # the viscous-hydroplaning drop
    assert (out / "sweep.png").exists()


def test_flat_python_api_equals_cli(mpi_tmp_path):
    p = scenes.make_parameters(
        "flat", values={"film": {"speed": 2e-5}, "points_per_decade": 10, "n_pressures": 16}
    )
    res = scenes.run_scene("flat", p, mpi_tmp_path / "flat_py")
    direct = p.model().solve(p.film.viscosity * p.film.speed)
    assert res["mu"] == pytest.approx(direct.mu, rel=1e-12)
    assert math.isfinite(res["alpha"]) and res["alpha"] > 0


def test_flat_full_contact_and_zero_speed(mpi_tmp_path):
    """p0 above E* slope: no area leaves contact; v = 0: dry contact, no fluid load."""
    p = scenes.make_parameters(
        "flat", overrides=["nominal_pressure=1e7", "film.speed=0", *SMALL_FLAT[1::2]]
    )
    res = scenes.run_scene("flat", p, mpi_tmp_path / "flat_full")
    assert res["contact_area_fraction"] > 0.99 and res["hydroplaning"] is False
    assert res["p_fluid"] == 0.0 and res["sigma_fluid"] == 0.0
    assert res["mu"] == pytest.approx(1e6 * res["contact_area_fraction"] / 1e7, rel=1e-12)


@pytest.mark.parametrize(
    ("scene", "setting", "name"),
    [("flat", "roughness.hurst=1.5", "roughness.hurst"), ("flat", "film.speed=-1", "film.speed"),
     ("rubber-friction", "material.nu=0.7", "material.nu"),
     ("rubber-friction", "material.model=maxwell", "material.model"),
     ("flat", "viscosity=1", "viscosity")],
)  # fmt: skip
def test_bad_parameters(scene, setting, name, capsys):
    with pytest.raises(ParameterError, match=name.replace(".", r"\.")):
        scenes.make_parameters(scene, overrides=[setting])
    assert main(["run", scene, "--set", setting, "--out", "unused"]) == 2
    if COMM_WORLD.rank == 0:
        assert name in capsys.readouterr().err
