"""Demos run at tiny sizes (they are importable functions with a CLI), and they
are literate scripts (Jupytext percent format)."""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from demos import ball_stribeck, cylinder_stribeck, obstacle, reynolds_1d

DEMOS = sorted((Path(__file__).resolve().parents[1] / "demos").glob("[!_]*.py"))


@pytest.mark.parametrize("path", DEMOS, ids=lambda p: p.name)
def test_demo_is_a_literate_script(path):
    """Percent format: a Markdown cell with the title first, prose cells between the
    code cells, at least one equation, no module docstring left over."""
    text = path.read_text()
    assert text.startswith("# %% [markdown]\n# # "), "starts with a Markdown title cell"
    cells = re.findall(r"^# %%( \[markdown\])?$", text, flags=re.M)
    prose = sum(1 for c in cells if c)
    assert prose >= 3 and len(cells) - prose >= 3, f"{prose} prose, {len(cells) - prose} code cells"
    assert re.search(r"^# .*\$[^$]+\$", text, flags=re.M), "an equation in the prose"
    assert ast.get_docstring(ast.parse(text)) is None, "the prose lives in Markdown cells"


@pytest.mark.skip_in_parallel
def test_demo_runs_as_a_script():
    """``python3 demos/obstacle.py``: the percent cells are plain comments to Python."""
    demo = Path(__file__).resolve().parents[1] / "demos" / "obstacle.py"
    r = subprocess.run([sys.executable, str(demo), "--cells", "8"], capture_output=True,
                       text=True, timeout=300, check=True)  # fmt: skip
    assert "exact contact radius r* = 0.697965" in r.stdout
    assert len(re.findall(r"^\s+8\s+(cold|nested)\s", r.stdout, flags=re.M)) == 2


def test_reynolds_demo_tiny(mpi_tmp_path):
    out = mpi_tmp_path / "demo"
    assert reynolds_1d.main(["--sizes", "600", "--out", str(out)]) == 0
    from dolfinx_seal.mpi import COMM_WORLD

    COMM_WORLD.barrier()
    res = json.loads((out / "results.json").read_text())
    assert abs(res["x_cavitation"] - res["reference_x_cavitation"]) < 1e-4
    assert (out / "pressure.png").stat().st_size > 1000
    assert (out / "solver_table.csv").read_text().count("\n") == 4  # header + 3 strategies


def test_obstacle_demo_tiny():
    obstacle.main(["--cells", "8"])


def test_ball_demo_tiny(mpi_tmp_path):
    """The main demo at one speed on a coarse mesh (a/8): the sweep files and the
    Hamrock-Dowson table are written."""
    out = mpi_tmp_path / "ball"
    assert (
        ball_stribeck.main(["--speeds", "0.3", "--elements-per-radius", "8", "--out", str(out)])
        == 0
    )
    from dolfinx_seal.mpi import COMM_WORLD

    COMM_WORLD.barrier()
    assert (out / "sweep.csv").read_text().count("\n") == 2  # header + one speed
    assert (out / "hamrock_dowson.csv").read_text().count("\n") == 2
    assert (out / "speed_3.000e-01" / "film_map.png").stat().st_size > 1000


def test_lip_demo_tiny(mpi_tmp_path):
    """The main demo (the lip seal) on a coarse band (20 um), one pressure and two
    speeds: the section, the leakage line, the torque curve and the fields."""
    from demos import lip_seal

    out = mpi_tmp_path / "lip"
    argv = ["--h-contact", "20e-6", "--pressures", "0.05", "--speeds", "1", "10", "--out", str(out)]
    assert lip_seal.main(argv) == 0
    from dolfinx_seal.mpi import COMM_WORLD

    COMM_WORLD.barrier()
    assert (out / "leakage.csv").read_text().count("\n") == 2  # header + one pressure
    assert (out / "torque.csv").read_text().count("\n") == 3
    for name in ("section.png", "leakage.png", "torque.png", "film.png", "fields.xdmf"):
        assert (out / name).stat().st_size > 500, name
    # the ParaView file names the fields it holds (read back from its XML)
    import xml.etree.ElementTree as ET

    names = {a.get("Name") for a in ET.parse(out / "fields.xdmf").iter("Attribute")}
    assert {"displacement", "fluid_pressure", "max_principal_strain", "contact_pressure",
            "separation"} <= names  # fmt: skip


def test_lip_sector_demo_tiny(mpi_tmp_path):
    """The sector demo on the tests' small open sector (q_th = q0, 10.5 um band
    elements, frozen lip), two speeds: the static maps, the sweep and its plot."""
    pytest.importorskip("dolfinx_mpc")
    from demos import lip_sector as demo

    out = mpi_tmp_path / "sector"
    sets = ["roughness.q0=3e5", "roughness.q_th=3e5", "roughness.h_rms=1e-6",
            "sector.height=0.3e-3", "sector.band_oil=0.3e-3", "sector.band_air=0.6e-3",
            "lip.h_contact=20e-6", "feedback=false"]  # fmt: skip
    argv = ["--speeds", "1e-3", "0.1", "--out", str(out)]
    assert demo.main(argv + [a for s in sets for a in ("--set", s)]) == 0
    from dolfinx_seal.mpi import COMM_WORLD

    COMM_WORLD.barrier()
    assert (out / "static.csv").read_text().count("\n") == 2
    assert (out / "dynamic" / "sweep.csv").read_text().count("\n") == 3
    for name in ("static/maps.png", "static/fields.xdmf", "dynamic/speed_1.000e-01/maps.png",
                 "cavitation.png"):  # fmt: skip
        assert (out / name).stat().st_size > 500, name


def test_cylinder_demo_tiny(mpi_tmp_path):
    """The cylinder Stribeck demo: one curve, two speeds, 8 elements per half-width."""
    out = mpi_tmp_path / "stribeck"
    argv = ["--curves", "h1um", "--speeds", "1e-2,1e-1", "--elements", "8", "--out", str(out)]
    cylinder_stribeck.main(argv)
    from dolfinx_seal.mpi import COMM_WORLD

    COMM_WORLD.barrier()
    assert (out / "h1um" / "sweep.csv").read_text().count("\n") == 3  # header + two speeds
    assert (out / "minima.csv").read_text().count("\n") == 2
    assert (out / "stribeck.png").stat().st_size > 1000
