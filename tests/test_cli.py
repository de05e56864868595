"""The CLI entry point."""

from __future__ import annotations

import subprocess
import sys

import pytest


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
