"""Results contract (DESIGN.md section 6): ``results.json``, ``sweep.csv``, versions.

Every run writes, into its output folder, ``results.json`` (scalars, SI units,
keys a scene does not compute are absent) and, for sweeps, ``sweep.csv`` with
one row appended as each point finishes.  Files are written by rank 0.
"""

from __future__ import annotations

import csv
import importlib
import json
import math
import platform
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from dolfinx_seal.mpi import COMM_WORLD

#: Scalar keys of the results contract, in the order they are written.
RESULT_KEYS: tuple[str, ...] = (
    "normal_load", "friction_force", "mu", "load_fluid", "load_contact",
    "h_min", "h_central", "contact_area_fraction", "cavitation_fraction",
    "max_fluid_pressure", "max_contact_pressure", "leakage_rate", "friction_torque",
    "x_cavitation", "contact_half_width", "contact_radius", "radial_load",
    "dofs", "ranks", "newton_iterations", "linear_iterations", "wall_time_s",
    "load_balance_error", "mass_balance_error", "converged",
)  # fmt: skip


def versions() -> dict[str, str]:
    """Versions of the stack (a package that does not import is reported as missing)."""
    out: dict[str, str] = {"python": platform.python_version()}
    try:
        from importlib.metadata import version

        out["dolfinx_seal"] = version("dolfinx_seal")
    except Exception:
        out["dolfinx_seal"] = "not installed"
    for mod, attr in (
        ("dolfinx", "__version__"),
        ("basix", "__version__"),
        ("ufl", "__version__"),
        ("ffcx", "__version__"),
        ("petsc4py", "__version__"),
        ("mpi4py", "__version__"),
        ("gmsh", "__version__"),
        ("dolfinx_mpc", "__version__"),
        ("scifem", "__version__"),
        ("numpy", "__version__"),
        ("scipy", "__version__"),
    ):
        try:
            m = importlib.import_module(mod)
            out[mod] = str(getattr(m, attr, None) or _dist_version(mod))
        except Exception:
            out[mod] = "missing"
    try:
        from petsc4py import PETSc

        out["petsc"] = ".".join(str(v) for v in PETSc.Sys.getVersion())
    except Exception:
        out["petsc"] = "missing"
    try:
        from mpi4py import MPI

        out["mpi"] = MPI.Get_library_version().splitlines()[0].strip()
    except Exception:
        out["mpi"] = "missing"
    return out


def _dist_version(module: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    for dist in (module, module.replace("_", "-"), f"fenics-{module}"):
        try:
            return version(dist)
        except PackageNotFoundError:
            continue
    return "unknown"


def _jsonable(v: Any) -> Any:
    if isinstance(v, Mapping):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_jsonable(x) for x in v]
    if isinstance(v, Path):
        return str(v)
    if hasattr(v, "item") and callable(v.item) and getattr(v, "ndim", 1) == 0:
        v = v.item()
    if hasattr(v, "tolist"):
        return v.tolist()
    if isinstance(v, float) and not math.isfinite(v):
        raise ValueError("non-finite value in results; refusing to write NaN/inf silently")
    return v


def write_results(out_dir: str | Path, results: Mapping[str, Any], comm: Any = None) -> Path:
    """Write ``results.json`` (rank 0) and return its path.

    ``results`` must hold ``scene`` and ``parameters``; ``versions`` is added.  A
    non-finite scalar is an error: nothing is silently NaN.
    """
    comm = comm or COMM_WORLD
    out = Path(out_dir)
    path = out / "results.json"
    # On every rank: versions() imports DOLFINx/petsc4py, whose initialisation is
    # collective; importing them on rank 0 alone deadlocks a pure-numpy run under MPI.
    vers = None if "versions" in results else versions()
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
        data = dict(results)
        if vers is not None:
            data["versions"] = vers
        for k, v in data.items():
            if isinstance(v, float) and not math.isfinite(v):
                raise ValueError(f"results[{k!r}] = {v}: non-finite result")
        path.write_text(json.dumps(_jsonable(data), indent=2, sort_keys=False) + "\n")
    comm.barrier()
    return path


class SweepWriter:
    """Append one CSV row per finished sweep point to ``sweep.csv`` (rank 0).

    The header is the union of the keys of the first row; later rows may omit
    keys (empty cell) but may not add new ones.  Each row is flushed at once so
    finished points survive a later failure.
    """

    def __init__(self, out_dir: str | Path, name: str = "sweep.csv", comm: Any = None) -> None:
        self.comm = comm or COMM_WORLD
        self.path = Path(out_dir) / name
        self.fields: list[str] | None = None
        if self.comm.rank == 0:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            if self.path.exists():
                self.path.unlink()

    def append(self, row: Mapping[str, Any]) -> None:
        """Write one row (scalar values only)."""
        if self.comm.rank != 0:
            return
        if self.fields is None:
            self.fields = list(row.keys())
            with self.path.open("w", newline="") as fh:
                csv.writer(fh).writerow(self.fields)
        extra = set(row) - set(self.fields)
        if extra:
            raise ValueError(f"sweep row has keys not in the header: {sorted(extra)}")
        with self.path.open("a", newline="") as fh:
            csv.writer(fh).writerow([_fmt(row.get(k, "")) for k in self.fields])


def _fmt(v: Any) -> Any:
    if isinstance(v, float):
        return repr(v)
    return v


def read_csv(path: str | Path) -> list[dict[str, str]]:
    """Read a CSV written by :class:`SweepWriter` (for tests and plots)."""
    with Path(path).open(newline="") as fh:
        return list(csv.DictReader(fh))


def column(rows: Sequence[Mapping[str, str]], key: str) -> list[float]:
    """Float column of CSV rows, skipping empty cells."""
    return [float(r[key]) for r in rows if r.get(key, "") != ""]
