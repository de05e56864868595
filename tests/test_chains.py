"""Sweep chains (``dolfinx-seal sweep ... --chains K``): K independent speed
chains at once, each on its share of the ranks.

The reference is the same sweep as one chain on all ranks.  A chain walks every
K-th speed of the walk order from its own start, so it reaches each point by
another path of Newton iterates: the merged rows must hold the reference's speeds
in the reference's order, each once, with the same values to the solver
tolerance (``RTOL`` 1e-6 as in tests/test_resume.py: the lubricated cylinder's
coupled solves stop at a relative residual of 1e-11; a point solved from the
wrong state or speed is off by whole percent).  Each chain's solves must run on
its own ranks only (the ``ranks`` each point reports).  Under ``mpirun -n 3`` two
chains split the ranks unevenly (2 + 1).
"""

from __future__ import annotations

import json

import pytest

from dolfinx_seal import scenes
from dolfinx_seal.cli import main
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD, using_comm, world
from dolfinx_seal.output import read_csv

#: The rigid lubricated cylinder of tests/test_resume.py: a few hundred film unknowns.
RIGID = [
    "h_contact=20e-6", "bulk=false", "contact.model=none", "load=1000", "film.speed=0.05",
    "film.cavitation=reynolds", "film.upstream=3", "film.downstream=2",
]  # fmt: skip
SPEEDS = [0.02, 0.05, 0.1, 0.2, 0.5]
KEYS = ("mu", "h_min", "load_fluid", "load_contact", "normal_load")
RTOL = 1e-6


def test_chain_values_deal_every_kth_value_of_the_walk():
    v = [0.1, 1.0, 0.01, 0.3, 0.03]
    assert scenes.chain_values(v, 2, "down") == [[1.0, 0.1, 0.01], [0.3, 0.03]]
    assert scenes.chain_values(v, 2, "up") == [[0.01, 0.1, 1.0], [0.03, 0.3]]
    assert scenes.chain_values(v, 3, "given") == [[0.1, 0.3], [1.0, 0.03], [0.01]]
    assert [c[0] for c in scenes.chain_values(v, 5, "down")] == sorted(v, reverse=True)
    with pytest.raises(ParameterError, match="sweep_order"):
        scenes.chain_values(v, 2, "up-down")


def test_more_chains_than_ranks_are_refused(mpi_tmp_path):
    p = scenes.make_parameters("cylinder", overrides=RIGID)
    k = COMM_WORLD.size + 1
    with pytest.raises(ParameterError, match=rf"--chains = {k}: .*{COMM_WORLD.size} rank"):
        scenes.sweep_chains("cylinder", p, mpi_tmp_path / "x", "film.speed", SPEEDS, k)


def test_using_comm_is_the_package_communicator_in_its_block():
    assert world() is COMM_WORLD
    sub = COMM_WORLD.Split(COMM_WORLD.rank % 2, key=COMM_WORLD.rank)
    try:
        with using_comm(sub):
            assert world() is sub
        assert world() is COMM_WORLD
    finally:
        sub.Free()


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") if COMM_WORLD.rank == 0 else None
    out = COMM_WORLD.bcast(str(out) if out else None, root=0)
    p = scenes.make_parameters("cylinder", overrides=RIGID)
    scenes.sweep_scene("cylinder", p, out, "film.speed", SPEEDS)
    return read_csv(f"{out}/sweep.csv")


@pytest.mark.parametrize("chains", sorted({1, min(2, COMM_WORLD.size)}))
def test_chains_give_the_one_chain_sweep(chains, reference, mpi_tmp_path):
    out = mpi_tmp_path / f"chains{chains}"
    p = scenes.make_parameters("cylinder", overrides=RIGID)
    rows = scenes.sweep_chains("cylinder", p, out, "film.speed", SPEEDS, chains)
    merged = read_csv(out / "sweep.csv")
    assert len(rows) == len(merged) == len(SPEEDS)
    assert [float(r["film.speed"]) for r in merged] == [float(r["film.speed"]) for r in reference]
    for r, q in zip(merged, reference, strict=True):
        for key in KEYS:
            assert float(r[key]) == pytest.approx(float(q[key]), rel=RTOL, abs=0.0), (key, r)
    summary = json.loads((out / "results.json").read_text())
    assert summary["points_finished"] == len(SPEEDS) and summary["failed_points"] == []
    assert [c["chain"] for c in summary["chains"]] == list(range(1, chains + 1))
    assert sum(c["ranks"] for c in summary["chains"]) == COMM_WORLD.size
    for c in summary["chains"]:
        assert c["points_finished"] == len(c["values"])
        own = read_csv(out / f"chain-{c['chain']}" / "sweep.csv")
        assert [float(r["film.speed"]) for r in own] == pytest.approx(c["values"], rel=1e-15)
        assert {int(r["ranks"]) for r in own} == {c["ranks"]}  # solved on the chain's ranks only
    assert (out / "sweep.png").is_file()


def test_point_files_picks_the_points_whose_folders_are_written():
    """``--point-files K``: the first point, every K-th after it and the last value."""
    chosen = [n for n in range(1, 8) if scenes.writes_point_files(n, 7, 3)]
    assert chosen == [1, 4, 7]
    assert [n for n in range(1, 9) if scenes.writes_point_files(n, 8, 3)] == [1, 4, 7, 8]
    assert all(scenes.writes_point_files(n, 5, 1) for n in range(1, 6))
    assert not any(scenes.writes_point_files(n, 5, 0) for n in range(1, 6))


@pytest.mark.parametrize("every, cli", [(3, False), (0, True)])
def test_point_files_leave_the_rows_and_write_the_chosen_folders(every, cli, reference,
                                                                 mpi_tmp_path):  # fmt: skip
    """The rigid cylinder's sweep with ``point_files`` (through the CLI's
    ``--point-files`` for 0): the reference sweep's rows (it wrote every point's
    files), and profile folders only at the chosen speeds (first, every K-th,
    last; none for 0)."""
    out = mpi_tmp_path / f"files{every}"
    if cli:
        args = ["sweep", "cylinder", *(a for kv in RIGID for a in ("--set", kv)), "--over",
                "film.speed", "--values", ",".join(map(str, SPEEDS)), "--out", str(out)]  # fmt: skip
        assert main([*args, "--point-files", str(every)]) == 0
    else:
        p = scenes.make_parameters("cylinder", overrides=RIGID)
        scenes.sweep_scene("cylinder", p, out, "film.speed", SPEEDS, point_files=every)
    rows = read_csv(out / "sweep.csv")
    assert [float(r["film.speed"]) for r in rows] == [float(r["film.speed"]) for r in reference]
    for r, q in zip(rows, reference, strict=True):
        for key in KEYS:  # the files take nothing from the solve
            assert float(r[key]) == pytest.approx(float(q[key]), rel=1e-12, abs=0.0), key
    written = sorted(float(d.name.removeprefix("speed_")) for d in out.glob("speed_*"))
    expected = [] if every == 0 else [SPEEDS[0], SPEEDS[3], SPEEDS[4]]
    assert written == pytest.approx(expected, rel=1e-3)
    for d in out.glob("speed_*"):
        assert (d / "film.png").stat().st_size > 1000 and (d / "film.csv").is_file()
    assert (out / "sweep.png").is_file()


def test_negative_point_files_are_refused(mpi_tmp_path):
    p = scenes.make_parameters("cylinder", overrides=RIGID)
    with pytest.raises(ParameterError, match=r"--point-files = -1 .*\[0, inf\)"):
        scenes.sweep_scene("cylinder", p, mpi_tmp_path / "bad", "film.speed", SPEEDS,
                           point_files=-1)  # fmt: skip
