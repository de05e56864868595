"""The CLI entry point."""

from __future__ import annotations

import subprocess
import sys

import pytest

from dolfinx_seal.cli import main
from dolfinx_seal.mpi import COMM_WORLD


@pytest.mark.skip_in_parallel
def test_versions_prints_dolfinx_09():
    out = subprocess.run(
        [sys.executable, "-m", "dolfinx_seal.cli", "versions"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    line = next(ln for ln in out.splitlines() if ln.startswith("dolfinx "))
    major, minor = (int(v) for v in line.split()[1].split(".")[:2])
    assert (major, minor) >= (0, 9)
    for name in ("petsc4py", "mpi4py", "gmsh", "dolfinx_seal"):
        assert any(ln.startswith(name) for ln in out.splitlines())


def test_psd_of_a_height_map(mpi_tmp_path):
    """``dolfinx-seal psd``: the spectrum of a written height map and its moments."""
    import numpy as np

    from dolfinx_seal.cli import main
    from dolfinx_seal.mpi import COMM_WORLD
    from dolfinx_seal.roughness.topography import write_height_map

    path = mpi_tmp_path / "map.txt"
    if COMM_WORLD.rank == 0:
        h = 1e-7 * np.random.default_rng(1).normal(size=(64, 64))
        write_height_map(path, h, 1e-6)
    COMM_WORLD.barrier()
    assert main(["psd", str(path), "--out", str(mpi_tmp_path / "psd")]) == 0
    COMM_WORLD.barrier()
    table = np.loadtxt(mpi_tmp_path / "psd" / "psd.csv", delimiter=",", skiprows=1, ndmin=2)
    assert table.shape[1] == 2 and np.all(table[:, 1] > 0)
    assert (mpi_tmp_path / "psd" / "psd.png").stat().st_size > 1000


def test_an_out_that_is_a_file_is_refused_with_one_line(mpi_tmp_path, capsys):
    """``--out`` naming a file: exit 2 with a message, no traceback (force or not)."""
    path = mpi_tmp_path / "a-file"
    if COMM_WORLD.rank == 0:
        path.write_text("not a folder\n")
    COMM_WORLD.barrier()
    for extra in ([], ["--force"]):
        argv = ["run", "flat", "--set", "points_per_decade=8", "--out", str(path), *extra]
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert "is a file, not a folder" in err and "Traceback" not in err
