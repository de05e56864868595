"""MPI helpers: the package's communicator, rank-0 printing and logging,
collective temporary directories.

Every part of the package that needs a communicator and is not handed one takes
:func:`world`: ``COMM_WORLD``, or inside :func:`using_comm` the communicator of a
sweep chain (``dolfinx-seal sweep --chains K`` runs K speed chains at once, each
on its own share of the ranks).  Nothing in the package uses ``COMM_WORLD``
directly.

Imports mpi4py only (no DOLFINx), so pure-numpy modules can use it too.  When
mpi4py is not importable everything degrades to a single process.
"""

from __future__ import annotations

import logging
import shutil
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

try:  # mpi4py is a Debian package of the project environment
    from mpi4py import MPI

    COMM_WORLD: Any = MPI.COMM_WORLD
    COMM_SELF: Any = MPI.COMM_SELF
except ImportError:  # pragma: no cover - only outside the project environment
    MPI = None  # type: ignore[assignment]

    class _SerialComm:
        rank = 0
        size = 1

        def bcast(self, obj: Any, root: int = 0) -> Any:
            return obj

        def barrier(self) -> None:
            return None

        def allreduce(self, obj: Any, op: Any = None) -> Any:
            return obj

    COMM_WORLD = _SerialComm()
    COMM_SELF = COMM_WORLD


_STACK: list[Any] = []  # the communicators of the active using_comm blocks


def world() -> Any:
    """The communicator the package works on: ``COMM_WORLD``, or the innermost
    :func:`using_comm` block's (a sweep chain's ranks)."""
    return _STACK[-1] if _STACK else COMM_WORLD


@contextmanager
def using_comm(comm: Any) -> Iterator[Any]:
    """Make ``comm`` the package's communicator (:func:`world`) in the block: meshes,
    solvers, output folders and rank-0 writes of everything run inside it live on
    ``comm``'s ranks only."""
    _STACK.append(comm)
    try:
        yield comm
    finally:
        _STACK.pop()


def rank(comm: Any = None) -> int:
    """Rank of this process in ``comm`` (default :func:`world`)."""
    return (comm or world()).rank


def print0(*args: Any, comm: Any = None, **kwargs: Any) -> None:
    """``print`` on rank 0 only (flushes, so output interleaves sensibly with PETSc's)."""
    if rank(comm) == 0:
        kwargs.setdefault("flush", True)
        print(*args, **kwargs)


class Rank0Filter(logging.Filter):
    """Logging filter that lets records through on rank 0 only."""

    def __init__(self, comm: Any = None) -> None:
        super().__init__()
        self._rank = rank(comm)

    def filter(self, record: logging.LogRecord) -> bool:
        return self._rank == 0


def get_logger(name: str = "dolfinx_seal") -> logging.Logger:
    """The package logger.  Nothing is configured at import time; see :func:`setup_logging`."""
    return logging.getLogger(name)


class _StderrHandler(logging.StreamHandler):
    """A stream handler on the *current* ``sys.stderr`` (looked up at each record), so
    that a CLI called many times in one process (tests) never writes to a closed stream."""

    def __init__(self) -> None:
        super().__init__(sys.stderr)

    @property  # type: ignore[override]
    def stream(self) -> Any:
        return sys.stderr

    @stream.setter
    def stream(self, _value: Any) -> None:
        pass


def setup_logging(level: int | str = logging.INFO, comm: Any = None) -> None:
    """Send package log records to stderr from rank 0 only (called by the CLI and demos)."""
    logger = get_logger()
    logger.setLevel(level)
    if not any(getattr(h, "_dolfinx_seal", False) for h in logger.handlers):
        h = _StderrHandler()
        h.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
        h.addFilter(Rank0Filter(comm))
        h._dolfinx_seal = True  # type: ignore[attr-defined]
        logger.addHandler(h)


def bcast_path(path: str | Path | None, comm: Any = None) -> Path:
    """Broadcast rank 0's ``path`` to all ranks of ``comm`` (default :func:`world`) and create it (rank 0) before returning."""
    comm = comm or world()
    p = comm.bcast(str(path) if path is not None else None, root=0)
    if comm.rank == 0 and p is not None:
        Path(p).mkdir(parents=True, exist_ok=True)
    comm.barrier()
    return Path(p)


@contextmanager
def temporary_directory(comm: Any = None) -> Iterator[Path]:
    """A temporary directory made on rank 0, shared by all ranks, removed at exit."""
    comm = comm or world()
    name = tempfile.mkdtemp(prefix="dolfinx_seal_") if comm.rank == 0 else None
    path = Path(comm.bcast(name, root=0))
    try:
        yield path
    finally:
        comm.barrier()
        if comm.rank == 0:
            shutil.rmtree(path, ignore_errors=True)
