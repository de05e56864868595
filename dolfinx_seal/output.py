"""Results contract: ``results.json``, ``sweep.csv``, versions, the terminal summary.

Every run writes, into its output folder, ``results.json`` (scalars, SI units,
keys a scene does not compute are absent) and, for sweeps, ``sweep.csv`` with
one row appended as each point finishes.  Files are written by rank 0.

:data:`RESULTS` is the results contract: the keys every scene uses for the same
quantity, with their units.  The terminal shows only those (a short table for
a run, one line per finished sweep point: :func:`results_table`,
:func:`sweep_point_line`); everything else stays in ``results.json``.
"""

from __future__ import annotations

import csv
import importlib
import json
import math
import platform
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from dolfinx_seal.mpi import COMM_WORLD

_FORCE = "N (N/m in plane strain)"

#: The results contract: key -> (unit, meaning, brief), in the order they are shown.
#: Forces are per unit length in the plane-strain scenes (``N/m``), totals otherwise;
#: ``brief`` keys make up the one-line summary of a sweep point.
RESULTS: dict[str, tuple[str, str, bool]] = {
    "normal_load": (_FORCE, "normal load carried (fluid + asperities)", False),
    "friction_force": (_FORCE, "force needed to slide the counter-surface", False),
    "mu": ("-", "friction coefficient friction_force / normal_load", True),
    "load_fluid": (_FORCE, "normal load carried by the fluid film", False),
    "load_contact": (_FORCE, "normal load carried by asperity contact", False),
    "fluid_load_fraction": ("-", "share of the normal load carried by the fluid", True),
    "h_min": ("m", "smallest film gap", True),
    "h_central": ("m", "film gap at the contact centre", False),
    "contact_area_fraction": ("-", "real over nominal contact area", False),
    "real_contact_area": ("m^2 (m in plane strain)", "real (asperity) contact area", False),
    "cavitation_fraction": ("-", "cavitated fraction of the lubricated zone", False),
    "max_fluid_pressure": ("Pa", "peak fluid pressure", False),
    "max_contact_pressure": ("Pa", "peak asperity contact pressure", True),
    "leakage_rate": ("m^3/s", "volume flow through the seal", True),
    "friction_torque": ("N m", "friction torque on the shaft", True),
    "x_cavitation": ("m", "cavitation front position downstream of the pressure peak", False),
    "contact_half_width": ("m", "contact half-width (line contact)", True),
    "contact_radius": ("m", "contact radius (point contact)", True),
    "radial_load": ("N/m", "radial contact force per unit circumference", True),
    "contact_width": ("m", "axial width of the contact band (lip seals)", True),
    "dofs": ("", "number of unknowns", False),
    "ranks": ("", "MPI processes", False),
    "newton_iterations": ("", "Newton steps", False),
    "linear_iterations": ("", "Krylov iterations", False),
    "wall_time_s": ("s", "wall time", True),
    "load_balance_error": ("-", "relative error of the load balance", False),
    "mass_balance_error": ("-", "relative error of the film's mass balance", False),
    "converged": ("", "whether the solve converged", False),
}  # fmt: skip

#: Scalar keys of the results contract, in the order they are written.
RESULT_KEYS: tuple[str, ...] = tuple(RESULTS)


def format_scalar(value: Any) -> str:
    """A result scalar for the terminal: 6 significant digits, ``true``/``false``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def results_table(results: Mapping[str, Any], path: str | Path | None = None) -> str:
    """The results-contract scalars present in ``results``, one per line with units.

    The other keys are counted, not shown (they are in ``results.json`` at ``path``).
    """
    shown = [k for k in RESULTS if k in results and _is_scalar(results[k])]
    rest = [
        k for k, v in results.items() if k not in RESULTS and _is_scalar(v) and k not in ("scene",)
    ]
    lines = []
    if shown:
        width = max(len(k) for k in shown)
        vals = {k: format_scalar(results[k]) for k in shown}
        vwidth = max(len(v) for v in vals.values())
        for k in shown:
            lines.append(f"  {k:<{width}}  {vals[k]:>{vwidth}}  {RESULTS[k][0]}".rstrip())
    where = f" in {path}" if path is not None else ""
    if rest:
        lines.append(f"  ({len(rest)} more scalars{where})")
    return "\n".join(lines)


def sweep_point_line(row: Mapping[str, Any], over: str, over_unit: str = "") -> str:
    """One line for a finished sweep point: the swept value and the brief contract keys."""
    u = f" {over_unit}" if over_unit else ""
    head = f"{over} = {format_scalar(row.get(over))}{u}"
    parts = []
    for k, (unit, _, brief) in RESULTS.items():
        if brief and k in row and _is_scalar(row[k]):
            u = f" {unit}" if unit and unit != "-" else ""
            parts.append(f"{k} {format_scalar(row[k])}{u}")
    return head + (": " + ", ".join(parts) if parts else "")


def _is_scalar(v: Any) -> bool:
    return isinstance(v, bool | int | float | str)


_ROW_LISTENERS: list[tuple[Path, Callable[[Mapping[str, Any]], None]]] = []


@contextmanager
def on_sweep_row(path: str | Path, callback: Callable[[Mapping[str, Any]], None]) -> Iterator[None]:
    """Call ``callback(row)`` as each row is appended to the CSV file ``path`` in the block.

    Rows are written by rank 0 only, so the callback runs there only.
    """
    entry = (Path(path).resolve(), callback)
    _ROW_LISTENERS.append(entry)
    try:
        yield
    finally:
        _ROW_LISTENERS.remove(entry)


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
        if _ROW_LISTENERS:
            here = self.path.resolve()
            for path, callback in list(_ROW_LISTENERS):
                if path == here:
                    callback(row)


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
