"""Demos run at tiny sizes (they are importable functions with a CLI)."""

from __future__ import annotations

import json

from demos import ball_stribeck, obstacle, reynolds_1d


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
