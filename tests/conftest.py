"""Test configuration, after DOLFINx's own conftest.

* garbage collection and a barrier after every test (PETSc destructors are
  collective, so objects must die at the same time on every rank);
* ``skip_in_parallel`` marker;
* ``mpi_tmp_path``: a temporary directory made on rank 0 and shared by all ranks.
"""

from __future__ import annotations

import gc
import sys
from pathlib import Path

import pytest

from dolfinx_seal.mpi import COMM_WORLD

# demos/ are importable examples (tests run them at tiny sizes)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


@pytest.fixture(autouse=True)
def _collective_cleanup():
    yield
    gc.collect()
    COMM_WORLD.barrier()


def pytest_runtest_setup(item: pytest.Item) -> None:
    if item.get_closest_marker("skip_in_parallel") and COMM_WORLD.size > 1:
        pytest.skip("only meaningful on one MPI rank")


@pytest.fixture
def mpi_tmp_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A temporary directory shared by all ranks."""
    name = str(tmp_path_factory.mktemp("mpi")) if COMM_WORLD.rank == 0 else None
    return Path(COMM_WORLD.bcast(name, root=0))
