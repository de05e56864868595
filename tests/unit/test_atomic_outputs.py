"""Atomic outputs and the output-folder guard (issue 21, point 2).

Whole files go to a temporary name and are renamed; ``sweep.csv`` rows are whole
lines; a folder holding another scene's or other parameters' results is refused
unless ``force``.  Pure numpy (``rubber-friction``); rank-agnostic (2 ranks too).
"""

from __future__ import annotations

import csv
import io
import json
import logging
import os
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI

from dolfinx_seal import output, scenes
from dolfinx_seal.cli import main
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import (
    OutputFolderError,
    SweepWriter,
    atomic_open,
    atomic_path,
    read_csv,
    read_sweep_manifest,
    write_results,
    write_text_atomic,
)

SMALL_RF = {"points_per_decade": 10, "n_curve": 21, "roughness": {"q1": 2.0e5}}
SMALL_RF_CLI = ["--set", "points_per_decade=10", "--set", "n_curve=21", "--set", "roughness.q1=2e5"]


def rf(**values):
    return scenes.make_parameters("rubber-friction", values={**SMALL_RF, **values})


def own_dir(base: Path) -> Path:
    """A folder of this rank only (for the non-collective helpers)."""
    d = base / f"rank{COMM_WORLD.rank}"
    d.mkdir(parents=True, exist_ok=True)
    return d


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(output.TMP_PREFIX))


def read_json(path: Path) -> dict:
    return json.loads(path.read_text())


# ------------------------------------------------------------------ atomic files
def test_interrupted_write_keeps_the_old_file_and_no_temporary(mpi_tmp_path):
    d = own_dir(mpi_tmp_path)
    target = d / "data.txt"
    target.write_text("old\n")
    with pytest.raises(RuntimeError, match="killed"), atomic_path(target) as tmp:
        tmp.write_text("new, but only half")
        raise RuntimeError("killed half way")
    assert target.read_text() == "old\n" and leftovers(d) == []
    with pytest.raises(KeyboardInterrupt), atomic_open(target) as fh:
        fh.write("partial")
        raise KeyboardInterrupt
    assert target.read_text() == "old\n" and leftovers(d) == []
    write_text_atomic(target, "new\n")
    assert target.read_text() == "new\n" and leftovers(d) == []
    # the normal permissions of a new file (not the 0600 of a mkstemp file)
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask


def test_atomic_path_keeps_the_extension_for_numpy_and_matplotlib(mpi_tmp_path):
    d = own_dir(mpi_tmp_path)
    data = np.arange(6.0).reshape(3, 2)
    with atomic_path(d / "table.csv.gz") as tmp:
        assert tmp.parent == d and tmp.name.endswith("table.csv.gz")
        np.savetxt(tmp, data, delimiter=",")  # .gz: compressed by name
    np.testing.assert_array_equal(np.loadtxt(d / "table.csv.gz", delimiter=","), data)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    with atomic_path(d / "plot.png") as tmp:
        fig.savefig(tmp)
    plt.close(fig)
    assert (d / "plot.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(FileNotFoundError, match="nothing was written"), atomic_path(d / "x.txt"):
        pass
    assert not (d / "x.txt").exists() and leftovers(d) == []


def test_results_json_round_trips_and_a_failed_write_keeps_the_old_one(mpi_tmp_path, monkeypatch):
    d = own_dir(mpi_tmp_path)
    results = {
        "scene": "x", "parameters": {"a": 1, "inner": {"b": (1.5, 2.5), "path": Path("p/q")}},
        "mu": np.float64(0.125), "n": np.int64(3), "profile": np.array([1.0, 2.0]),
        "converged": True, "versions": {"python": "3"},
    }  # fmt: skip
    path = write_results(d, results, comm=MPI.COMM_SELF)
    expect = {
        "scene": "x", "parameters": {"a": 1, "inner": {"b": [1.5, 2.5], "path": "p/q"}},
        "mu": 0.125, "n": 3, "profile": [1.0, 2.0], "converged": True, "versions": {"python": "3"},
    }  # fmt: skip
    assert read_json(path) == expect
    before = path.read_bytes()

    def die(_path):  # the data is in the temporary file; the process dies before the rename
        raise KeyboardInterrupt

    monkeypatch.setattr(output, "_fsync_path", die)
    with pytest.raises(KeyboardInterrupt):
        write_results(d, {**results, "mu": 0.5}, comm=MPI.COMM_SELF)
    monkeypatch.undo()
    assert path.read_bytes() == before and leftovers(d) == []


def test_write_results_error_is_raised_on_every_rank(mpi_tmp_path):
    with pytest.raises(ValueError, match="non-finite"):
        write_results(mpi_tmp_path, {"scene": "x", "parameters": {}, "mu": float("nan")})
    assert not (mpi_tmp_path / "results.json").exists()


# --------------------------------------------------------------------- sweep.csv
def _old_format(rows: list[dict], fields: list[str]) -> bytes:
    """What the previous SweepWriter wrote (csv module, excel dialect)."""
    buf = io.StringIO(newline="")
    w = csv.writer(buf)
    w.writerow(fields)
    for r in rows:
        w.writerow([repr(v) if isinstance(v, float) else v for v in (r.get(k, "") for k in fields)])
    return buf.getvalue().encode()


def test_sweep_rows_are_whole_lines_in_the_same_format(mpi_tmp_path, monkeypatch):
    folder = mpi_tmp_path / "s"
    rows = [
        {"speed": 0.1, "mu": 1 / 3, "note": 'a, "quoted" one', "ok": True},
        {"speed": 0.2, "mu": 0.25, "note": "no comma"},  # omits a key: empty cell
        {"speed": 0.3, "mu": 1e-300, "note": "", "ok": False},
    ]
    w = SweepWriter(folder)
    calls = []
    real_write = os.write
    monkeypatch.setattr(output.os, "write", lambda fd, b: calls.append(len(b)) or real_write(fd, b))
    for r in rows:
        w.append(r)
    monkeypatch.undo()
    COMM_WORLD.barrier()
    if COMM_WORLD.rank == 0:  # rows are written on rank 0 only
        raw = (folder / "sweep.csv").read_bytes()
        assert raw == _old_format(rows, ["speed", "mu", "note", "ok"])
        assert raw.endswith(b"\r\n") and raw.count(b"\r\n") == 4
        assert len(calls) == 2  # one write per appended row (the first comes with the header)
        table = read_csv(folder / "sweep.csv")
        assert [r["note"] for r in table] == ['a, "quoted" one', "no comma", ""]
        assert table[1]["ok"] == "" and float(table[0]["mu"]) == 1 / 3
    else:
        assert calls == []
    # a new writer on the same folder starts a new file
    w2 = SweepWriter(folder)
    w2.append({"x": 1.0})
    COMM_WORLD.barrier()
    assert read_csv(folder / "sweep.csv") == [{"x": "1.0"}]
    assert leftovers(folder) == []


# ----------------------------------------------------------------- folder guard
def test_rerun_with_the_same_parameters_is_allowed(mpi_tmp_path):
    out = mpi_tmp_path / "rf"
    first = scenes.run_scene("rubber-friction", rf(), out)
    again = scenes.run_scene("rubber-friction", rf(), out)
    assert again["mu"] == first["mu"]
    assert read_json(out / "results.json")["parameters"]["speed"] == rf().speed


def test_other_parameters_are_refused_naming_the_dotted_parameter(mpi_tmp_path):
    out = mpi_tmp_path / "rf"
    scenes.run_scene("rubber-friction", rf(), out)
    COMM_WORLD.barrier()
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    COMM_WORLD.barrier()
    with pytest.raises(OutputFolderError) as e:
        scenes.run_scene("rubber-friction", rf(speed=0.5, material={"tau": 1e-2}), out)
    msg = str(e.value)
    assert isinstance(e.value, ParameterError)
    assert f"output folder {str(out)!r}: its results.json holds a single run of scene " in msg
    assert "speed = 1.0 there, 0.5 now" in msg
    assert "material.tau = 0.001 there, 0.01 now" in msg
    assert "--force" in msg and "--out" in msg
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before  # nothing written


def test_another_scene_is_refused(mpi_tmp_path):
    out = mpi_tmp_path / "mixed"
    scenes.run_scene("rubber-friction", rf(), out)
    flat = scenes.make_parameters("flat", values={"points_per_decade": 10, "n_pressures": 16})
    with pytest.raises(OutputFolderError, match="scene 'rubber-friction', not of scene 'flat'"):
        scenes.run_scene("flat", flat, out)


def test_many_differences_are_cut_short(mpi_tmp_path):
    out = mpi_tmp_path / "many"
    scenes.run_scene("rubber-friction", rf(), out)
    other = rf(
        speed=0.5, material={"nu": 0.4}, points_per_decade=12, n_curve=25, roughness={"q1": 4e5}
    )
    with pytest.raises(OutputFolderError, match=r"; and 1 more\. Refusing"):
        scenes.run_scene("rubber-friction", other, out)


def test_force_writes_into_the_folder_and_says_so(mpi_tmp_path, caplog):
    out = mpi_tmp_path / "rf"
    scenes.run_scene("rubber-friction", rf(), out)
    with caplog.at_level(logging.WARNING, logger="dolfinx_seal"):
        scenes.run_scene("rubber-friction", rf(speed=0.5), out, force=True)
    forced = [r for r in caplog.records if "writing into it anyway" in r.getMessage()]
    assert len(forced) == (1 if COMM_WORLD.rank == 0 else 0)
    if forced:
        assert "speed = 1.0 there, 0.5 now" in forced[0].getMessage()
    assert read_json(out / "results.json")["parameters"]["speed"] == 0.5


def test_sweep_manifest_and_sweep_guard(mpi_tmp_path):
    out = mpi_tmp_path / "sweep"
    values = [1e-3, 1e-1, 10.0]
    rows = scenes.sweep_scene("rubber-friction", rf(), out, "speed", values)
    assert len(rows) == 3
    manifest = read_sweep_manifest(out)
    assert tuple(manifest) == output.MANIFEST_KEYS
    assert manifest["scene"] == "rubber-friction" and manifest["manifest"] == "dolfinx_seal sweep"
    assert manifest["sweep_parameter"] == "speed" and manifest["sweep_values"] == values
    assert manifest["parameters"] == read_json(out / "results.json")["parameters"]
    # the same sweep again: allowed
    assert len(scenes.sweep_scene("rubber-friction", rf(), out, "speed", values)) == 3
    with pytest.raises(OutputFolderError, match=r"sweep values \[0\.001, 0\.1, 10\.0\] there"):
        scenes.sweep_scene("rubber-friction", rf(), out, "speed", [1.0, 2.0])
    with pytest.raises(OutputFolderError, match=r"over 'speed', not over 'material.nu'"):
        scenes.sweep_scene("rubber-friction", rf(), out, "material.nu", [0.4, 0.45])
    with pytest.raises(OutputFolderError, match=r"roughness\.q1 = 200000\.0 there, 100000\.0 now"):
        scenes.sweep_scene("rubber-friction", rf(roughness={"q1": 1e5}), out, "speed", values)
    with pytest.raises(
        OutputFolderError,
        match=r"a sweep of scene 'rubber-friction' over 'speed', not a single run",
    ):
        scenes.run_scene("rubber-friction", rf(), out)
    rows = scenes.sweep_scene("rubber-friction", rf(), out, "speed", [1.0, 2.0], force=True)
    assert len(rows) == 2 and read_sweep_manifest(out)["sweep_values"] == [1.0, 2.0]
    assert len(read_csv(out / "sweep.csv")) == 2


def test_a_sweep_into_a_run_folder_is_refused(mpi_tmp_path):
    out = mpi_tmp_path / "run"
    scenes.run_scene("rubber-friction", rf(), out)
    with pytest.raises(
        OutputFolderError, match=r"a single run of scene 'rubber-friction', not a sweep"
    ):
        scenes.sweep_scene("rubber-friction", rf(), out, "speed", [1.0])
    assert not (out / "sweep.json").exists() and not (out / "sweep.csv").exists()


def test_unknown_sweep_parameter_stops_before_writing(mpi_tmp_path):
    out = mpi_tmp_path / "bad"
    with pytest.raises(
        ParameterError, match=r"unknown parameter 'film'; the names allowed are: .*speed"
    ):
        scenes.sweep_scene("rubber-friction", rf(), out, "film.speed", [1.0])  # dry: no film
    assert not out.exists()


def test_a_manifest_without_results_holds_nothing(mpi_tmp_path):
    """A sweep stopped before its first point leaves only sweep.json: no results to mix."""
    out = mpi_tmp_path / "stopped"
    output.write_sweep_manifest(out, "flat", {"film": {"speed": 1.0}}, "film.speed", [1.0])
    scenes.run_scene("rubber-friction", rf(), out)
    scenes.run_scene("rubber-friction", rf(), out)  # and the rerun is not refused by it either


def test_unknown_or_unreadable_contents_are_refused(mpi_tmp_path):
    out = mpi_tmp_path / "odd"
    if COMM_WORLD.rank == 0:
        out.mkdir()
        (out / "sweep.csv").write_text("speed,mu\r\n1.0,0.5\r\n")
    COMM_WORLD.barrier()
    with pytest.raises(OutputFolderError, match=r"sweep\.csv with neither sweep\.json"):
        scenes.run_scene("rubber-friction", rf(), out)
    if COMM_WORLD.rank == 0:
        (out / "sweep.csv").unlink()
        (out / "results.json").write_text('{"scene": "rubber-fr')  # killed while writing
    COMM_WORLD.barrier()
    with pytest.raises(OutputFolderError, match=r"its results\.json cannot be read"):
        scenes.run_scene("rubber-friction", rf(), out)
    scenes.run_scene("rubber-friction", rf(), out, force=True)
    assert read_json(out / "results.json")["scene"] == "rubber-friction"


# ------------------------------------------------------------------------- CLI
def test_cli_refuses_a_mixed_folder_and_force_overrides(mpi_tmp_path, capsys):
    out = str(mpi_tmp_path / "cli")
    run = ["run", "rubber-friction", *SMALL_RF_CLI, "--out", out]
    assert main(run) == 0
    assert main(run) == 0  # the same run again
    capsys.readouterr()
    assert main([*run, "--set", "material.tau=1e-2"]) == 2
    err = capsys.readouterr().err
    assert "parameter error" in err and "material.tau = 0.001 there, 0.01 now" in err
    assert f"'{out}'" in err and "--force" in err
    assert main([*run, "--set", "material.tau=1e-2", "--force"]) == 0
    assert read_json(Path(out) / "results.json")["parameters"]["material"]["tau"] == 0.01
    sweep = ["sweep", "rubber-friction", *SMALL_RF_CLI, "--over", "speed", "--values", "1,2"]
    assert main([*sweep, "--out", out]) == 2
    assert "not a sweep" in capsys.readouterr().err
    assert main([*sweep, "--out", out, "--force"]) == 0
    assert main([*sweep, "--out", out]) == 0  # the same sweep again
    assert read_sweep_manifest(out)["sweep_values"] == [1.0, 2.0]
