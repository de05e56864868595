"""The terminal summary of a run or sweep: contract scalars with units, not the record."""

from __future__ import annotations

import json

from dolfinx_seal import output
from dolfinx_seal.cli import main
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import RESULTS, SweepWriter, on_sweep_row, results_table, sweep_point_line

SMALL_FLAT = ["--set", "points_per_decade=10", "--set", "n_pressures=16"]


def test_results_table_shows_contract_keys_with_units_only():
    res = {
        "scene": "x", "parameters": {"a": 1}, "zeta1": 3.0, "h_min": 1.25e-6, "mu": 0.0123456789,
        "converged": True, "dofs": 1200, "profile": [1.0, 2.0], "contact_law": "persson",
    }  # fmt: skip
    text = results_table(res, "results.json")
    lines = text.splitlines()
    # contract order (mu before h_min), units from the one table, values to 6 digits
    assert [ln.split()[0] for ln in lines[:-1]] == ["mu", "h_min", "dofs", "converged"]
    assert lines[0].split() == ["mu", "0.0123457", "-"]
    assert lines[1].split() == ["h_min", "1.25e-06", "m"]
    assert lines[2].split() == ["dofs", "1200"] and lines[3].split() == ["converged", "true"]
    assert lines[-1].strip() == "(2 more scalars in results.json)"  # zeta1, contact_law
    assert "zeta1" not in text and "parameters" not in text


def test_every_contract_key_has_a_unit_column_and_a_meaning():
    assert output.RESULT_KEYS == tuple(RESULTS)
    for key, (unit, meaning, brief) in RESULTS.items():
        assert isinstance(unit, str) and meaning and isinstance(brief, bool), key
    for key in ("normal_load", "mu", "h_min", "max_contact_pressure", "leakage_rate"):
        assert key in RESULTS


def test_sweep_point_line_is_one_short_line():
    row = {"speed": 0.01, "mu": 0.05, "h_min": 2e-7, "zeta1": 4.0, "dofs": 10, "normal_load": 1.0}
    line = sweep_point_line(row, "speed", "m/s")
    assert line == "speed = 0.01 m/s: mu 0.05, h_min 2e-07 m"


def test_sweep_rows_reach_the_listener_of_their_file_only(mpi_tmp_path):
    seen = []
    w = SweepWriter(mpi_tmp_path / "a")
    other = SweepWriter(mpi_tmp_path / "b")
    with on_sweep_row(mpi_tmp_path / "a" / "sweep.csv", seen.append):
        w.append({"x": 1.0})
        other.append({"x": 2.0})
    w.append({"x": 3.0})
    assert seen == ([{"x": 1.0}] if COMM_WORLD.rank == 0 else [])


def test_run_prints_a_short_table_not_the_record(mpi_tmp_path, capsys):
    out = mpi_tmp_path / "flat"
    assert main(["run", "flat", *SMALL_FLAT, "--out", str(out)]) == 0
    text = capsys.readouterr().out
    if COMM_WORLD.rank != 0:
        assert text == ""
        return
    record = json.loads((out / "results.json").read_text())
    lines = text.splitlines()
    assert lines[0] == "flat results:" and lines[-1] == f"results written to {out}/results.json"
    assert "{" not in text and '"' not in text
    shown = {ln.split()[0]: ln.split() for ln in lines[1:-2]}
    assert set(shown) == {k for k in RESULTS if k in record}
    assert shown["mu"] == ["mu", f"{record['mu']:.6g}", "-"]
    hidden = [k for k in record if k not in RESULTS and isinstance(record[k], int | float | str)]
    assert hidden and not any(k in text for k in hidden if k != "scene")
    assert lines[-2].strip() == f"({len(hidden) - 1} more scalars in results.json)"  # not "scene"


def test_sweep_prints_one_line_per_point(mpi_tmp_path, capsys):
    out = mpi_tmp_path / "flat_sweep"
    argv = ["sweep", "flat", *SMALL_FLAT, "--over", "film.speed", "--values", "1e-6:1e-4:3:log"]
    assert main([*argv, "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    if COMM_WORLD.rank != 0:
        assert lines == []
        return
    points = [ln for ln in lines if ln.startswith("[")]
    assert [p.split()[0] for p in points] == ["[1/3]", "[2/3]", "[3/3]"]
    assert points[0].startswith("[1/3] film.speed = 1e-06 m/s: mu ")
    assert lines[-1].startswith("3 of 3 points finished")
    assert len(lines) == 4
