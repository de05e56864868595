"""Results contract: ``results.json``, ``sweep.csv``, versions, the terminal summary.

Every run writes, into its output folder, ``results.json`` (scalars, SI units,
keys a scene does not compute are absent) and, for sweeps, ``sweep.csv`` with
one row appended as each point finishes.  Files are written by rank 0.

Atomic outputs: a whole file is written to a temporary name in its folder
(``.tmp-<token>-<name>``), flushed and fsynced, then renamed onto its name
(:func:`atomic_path`, :func:`atomic_open`, :func:`write_text_atomic`), so a kill
leaves the old file or the new one, never a truncated one (a kill before the
rename may leave the hidden temporary file behind).  A ``sweep.csv`` row is one
whole line written with one ``write`` call and fsynced.

Folder guard (:func:`check_out_dir`): before a run or sweep writes anything,
the folder's ``results.json`` and ``sweep.json`` are compared with what is about
to be written (scene; single run, sweep or study; the resolved parameters; the
swept parameter and values).  Other results are refused with a
:class:`OutputFolderError` unless ``force`` is given.  ``sweep.json`` is the
sweep manifest, written atomically before the first point (:data:`MANIFEST_KEYS`):
``manifest`` (``"dolfinx_seal sweep"``), ``format`` (1), ``scene``,
``parameters`` (the resolved parameters, as in ``results.json``),
``sweep_parameter`` (dotted name) and ``sweep_values``.

:data:`RESULTS` is the results contract: the keys every scene uses for the same
quantity, with their units.  The terminal shows only those (a short table for
a run, one line per finished sweep point: :func:`results_table`,
:func:`sweep_point_line`); everything else stays in ``results.json``.
"""

from __future__ import annotations

import csv
import importlib
import importlib.util
import io
import json
import math
import os
import pickle
import platform
import secrets
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import IO, Any

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import get_logger, world
from dolfinx_seal.params import flatten

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
    "floored_area_fraction": (
        "-", "share of the lubricated zone whose gap is at its floor (film.gap_floor)", False,
    ),
    "floored_fluid_load_fraction": (
        "-", "share of the fluid load carried where the gap is at its floor", False,
    ),
    "discrete_upwinding_weight": (
        "-", "weight of film.discrete_upwinding's term in the film (0: the default scheme's)", False,
    ),
    "suction_load_fraction": (
        "-", "pull of a starved JFO film's pressures below 0 (at theta = 0) over its push",
        False,
    ),
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
    "factor_memory_mb": (
        "MB", "MUMPS memory of the factorisations the solvers hold now, all ranks", False,
    ),
    "factor_memory_peak_mb": (
        "MB", "MUMPS memory of the largest factorisation of each solver, summed, all ranks",
        False,
    ),
    "factor_memory_peak_rank_mb": (
        "MB", "the same, each solver's largest rank", False,
    ),
    "newton_iterations": ("", "Newton steps", False),
    "linear_iterations": ("", "Krylov iterations", False),
    "wall_time_s": ("s", "wall time", True),
    "load_balance_error": ("-", "relative error of the load balance", False),
    "mass_balance_error": ("-", "relative error of the film's mass balance", False),
    "mass_imbalance": (
        "m^3/s", "net flow into the film, |oil-side inflow - leakage| (lip seals)", False,
    ),
    "nodal_mass_imbalance": ("m^3/s", "largest net flow into one film node (lip sector)", False),
    "complementarity_error": ("-", "VI natural residual of the last solve, relative to |F(0)|", False),
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


def _jsonable(v: Any, strict: bool = True) -> Any:
    if isinstance(v, Mapping):
        return {str(k): _jsonable(x, strict) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_jsonable(x, strict) for x in v]
    if isinstance(v, Path):
        return str(v)
    if hasattr(v, "item") and callable(v.item) and getattr(v, "ndim", 1) == 0:
        v = v.item()
    if hasattr(v, "tolist"):
        return v.tolist()
    if strict and isinstance(v, float) and not math.isfinite(v):
        raise ValueError("non-finite value in results; refusing to write NaN/inf silently")
    return v


# --------------------------------------------------------------- atomic writes
#: Prefix of the temporary files of :func:`atomic_path` (``.tmp-<token>-<name>``).
TMP_PREFIX = ".tmp-"


def _fsync_path(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_dir(folder: Path) -> None:
    """Make a rename in ``folder`` durable (best effort: not every file system allows it)."""
    with suppress(OSError):
        _fsync_path(folder)


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path next to ``path``, renamed onto ``path`` when the block succeeds.

    Write the whole file to the yielded path (``np.savetxt(tmp, ...)``,
    ``fig.savefig(tmp)``, ``open(tmp, "w")``); the name ends with ``path``'s own
    name, so writers that go by the extension (``.png``, ``.csv.gz``) see it.  On
    success the file is fsynced and renamed with :func:`os.replace` (atomic on
    POSIX): readers, and a kill at any moment, see the old file or the new one,
    never a part (a kill before the rename leaves the temporary file, whose
    name starts with :data:`TMP_PREFIX`).  On an exception (also ``KeyboardInterrupt``) the temporary
    file is removed and ``path`` is left as it was.  Not collective: call it on
    the rank that writes.
    """
    target = Path(path)
    tmp = target.with_name(f"{TMP_PREFIX}{os.getpid()}-{secrets.token_hex(4)}-{target.name}")
    try:
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(
                f"nothing was written to {tmp} (the temporary file of {target})"
            )
        _fsync_path(tmp)
        os.replace(tmp, target)
    except BaseException:
        with suppress(OSError):
            tmp.unlink()
        raise
    _fsync_dir(target.parent)


@contextmanager
def atomic_open(
    path: str | Path, mode: str = "w", encoding: str = "utf-8", newline: str | None = None
) -> Iterator[IO[Any]]:
    """``open(path, mode)`` for a whole file, written atomically (see :func:`atomic_path`).

    ``mode`` is ``"w"`` or ``"wb"``; the file is flushed and fsynced before the rename.
    """
    if mode not in ("w", "wt", "wb"):
        raise ValueError(f"atomic_open writes whole files: mode 'w' or 'wb', got {mode!r}")
    kw: dict[str, Any] = {} if "b" in mode else {"encoding": encoding, "newline": newline}
    with atomic_path(path) as tmp, open(tmp, mode.replace("w", "x"), **kw) as fh:
        yield fh
        fh.flush()
        os.fsync(fh.fileno())


def write_text_atomic(path: str | Path, text: str, newline: str | None = None) -> Path:
    """Write ``text`` to ``path`` atomically (UTF-8) and return the path."""
    with atomic_open(path, "w", newline=newline) as fh:
        fh.write(text)
    return Path(path)


def _append_line(path: Path, data: bytes) -> None:
    """Append ``data`` (whole lines) to ``path`` with one ``write`` call, then fsync."""
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
    try:
        view = memoryview(data)
        while view:  # one call for a regular file; the loop only guards a short write
            view = view[os.write(fd, view) :]
        os.fsync(fd)
    finally:
        os.close(fd)


def _csv_line(values: Sequence[Any]) -> str:
    buf = io.StringIO(newline="")
    csv.writer(buf).writerow(values)
    return buf.getvalue()


def _on_rank0(comm: Any, work: Callable[[], Any]) -> Any:
    """Run ``work()`` on rank 0 and return its value there; an exception is raised on all ranks."""
    value, err = None, None
    if comm.rank == 0:
        try:
            value = work()
        except Exception as e:
            err = e
    shared = err
    if comm.size > 1:
        if err is not None:
            try:
                pickle.dumps(err)
            except Exception:
                shared = RuntimeError(f"{type(err).__name__}: {err}")
        shared = comm.bcast(shared, root=0)
    if err is not None:
        raise err
    if shared is not None:
        raise shared
    return value


def write_results(out_dir: str | Path, results: Mapping[str, Any], comm: Any = None) -> Path:
    """Write ``results.json`` (rank 0, atomically) and return its path.

    ``results`` must hold ``scene`` and ``parameters``; ``versions`` is added.  A
    non-finite scalar is an error (raised on every rank): nothing is silently NaN.
    """
    comm = comm or world()
    out = Path(out_dir)
    path = out / "results.json"
    # On every rank: versions() imports DOLFINx/petsc4py, whose initialisation is
    # collective; importing them on rank 0 alone deadlocks a pure-numpy run under MPI.
    vers = None if "versions" in results else versions()

    def write() -> None:
        out.mkdir(parents=True, exist_ok=True)
        data = dict(results)
        if vers is not None:
            data["versions"] = vers
        for k, v in data.items():
            if isinstance(v, float) and not math.isfinite(v):
                raise ValueError(f"results[{k!r}] = {v}: non-finite result")
        write_text_atomic(path, json.dumps(_jsonable(data), indent=2, sort_keys=False) + "\n")

    _on_rank0(comm, write)  # collective: no rank goes on before the file is in place
    return path


class SweepWriter:
    """Append one CSV row per finished sweep point to ``sweep.csv`` (rank 0).

    The header is the keys of the first row; later rows may omit keys (empty
    cell), and a row with a new key extends the header: the file is rewritten
    whole (atomically) with the new column, empty in the earlier rows, so no
    value of any point is dropped.  The file appears with the first
    row (header and row written atomically); each later row is one whole line
    appended with one ``write`` call and fsynced, so finished points survive a
    later failure or a kill and the file never ends in a part of a row.
    """

    def __init__(
        self, out_dir: str | Path, name: str = "sweep.csv", comm: Any = None, resume: bool = False
    ) -> None:
        self.comm = comm or world()
        self.path = Path(out_dir) / name
        self.fields: list[str] | None = None
        if self.comm.rank == 0:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            if resume and self.path.is_file():  # go on appending under the header there
                with self.path.open(newline="") as fh:
                    self.fields = next(csv.reader(fh), None)
            elif self.path.exists():
                self.path.unlink()

    def append(self, row: Mapping[str, Any]) -> None:
        """Write one row (scalar values only)."""
        if self.comm.rank != 0:
            return
        first = self.fields is None
        if first:
            self.fields = list(row.keys())
        extra = [k for k in row if k not in self.fields]
        rewrite = first or bool(extra)
        body = ""
        if extra and self.path.is_file():  # earlier rows, under the extended header
            with self.path.open(newline="") as fh:
                old = list(csv.DictReader(fh))
            self.fields += extra
            body = "".join(_csv_line([r.get(k) or "" for k in self.fields]) for r in old)
        elif extra:
            self.fields += extra
        line = _csv_line([_fmt(row.get(k, "")) for k in self.fields])
        if rewrite:
            write_text_atomic(self.path, _csv_line(self.fields) + body + line, newline="")
        else:
            _append_line(self.path, line.encode("utf-8"))
        if _ROW_LISTENERS:
            here = self.path.resolve()
            for path, callback in list(_ROW_LISTENERS):
                if path == here:
                    callback(row)


def _fmt(v: Any) -> Any:
    if isinstance(v, float):
        return repr(v)
    return v


def write_sweep_failures(out_dir: str | Path, failed: Sequence[Mapping[str, Any]]) -> None:
    """``sweep_failures.csv`` (``speed,error``; rank 0, atomic): the continuation
    targets a sweep did not reach and why (``failed``: ``{"speed", "error"}``); no
    file when there are none."""
    if failed and world().rank == 0:
        lines = ["speed,error\n"] + [_csv_line([f["speed"], f["error"]]) for f in failed]
        Path(out_dir).mkdir(
            parents=True, exist_ok=True
        )  # a sweep that failed before its first point
        write_text_atomic(Path(out_dir) / "sweep_failures.csv", "".join(lines))


def repair_csv(path: str | Path) -> int:
    """Cut a trailing part of a row (a kill in the middle of a write) from a CSV
    file; returns the number of bytes cut (0 for a whole file)."""
    path = Path(path)
    data = path.read_bytes()
    if not data or data.endswith(b"\n"):
        return 0
    keep = data.rfind(b"\n") + 1
    with path.open("r+b") as fh:
        fh.truncate(keep)
        fh.flush()
        os.fsync(fh.fileno())
    return len(data) - keep


def parse_cell(text: str) -> Any:
    """A ``sweep.csv`` cell as the value written (float, int, bool, str; ``None`` if empty)."""
    if text == "":
        return None
    if text in ("True", "False"):
        return text == "True"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def read_csv(path: str | Path) -> list[dict[str, str]]:
    """Read a CSV written by :class:`SweepWriter` (for tests and plots)."""
    with Path(path).open(newline="") as fh:
        return list(csv.DictReader(fh))


def column(rows: Sequence[Mapping[str, str]], key: str) -> list[float]:
    """Float column of CSV rows, skipping empty cells."""
    return [float(r[key]) for r in rows if r.get(key, "") != ""]


# ---------------------------------------------------------------- folder guard
#: File name of the sweep manifest.
SWEEP_MANIFEST = "sweep.json"

#: Keys of the sweep manifest ``sweep.json`` (format 1).
MANIFEST_KEYS: tuple[str, ...] = (
    "manifest", "format", "scene", "parameters", "sweep_parameter", "sweep_values",
)  # fmt: skip

_MANIFEST_TAG = "dolfinx_seal sweep"
_MAX_DIFFS = 4


class OutputFolderError(ParameterError):
    """The output folder holds results this run would mix with (another scene or parameters)."""


def write_sweep_manifest(
    out_dir: str | Path,
    scene: str,
    parameters: Mapping[str, Any],
    over: str,
    values: Sequence[float],
    comm: Any = None,
) -> Path:
    """Write ``sweep.json`` (rank 0, atomically) before the first point and return its path.

    ``parameters`` is the resolved parameter record (``params.to_dict``); see the
    module docstring for the keys.
    """
    comm = comm or world()
    out = Path(out_dir)
    path = out / SWEEP_MANIFEST
    data = {
        "manifest": _MANIFEST_TAG, "format": 1, "scene": scene,
        "parameters": _jsonable(parameters, strict=False),
        "sweep_parameter": over, "sweep_values": _jsonable(list(values), strict=False),
    }  # fmt: skip

    def write() -> None:
        out.mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, json.dumps(data, indent=2) + "\n")

    _on_rank0(comm, write)
    return path


def read_sweep_manifest(out_dir: str | Path) -> dict[str, Any] | None:
    """The sweep manifest of ``out_dir`` (``None`` if there is none); not collective."""
    path = Path(out_dir) / SWEEP_MANIFEST
    if not path.is_file():
        return None
    return json.loads(path.read_text(encoding="utf-8"))


def check_out_dir(
    out_dir: str | Path,
    scene: str,
    parameters: Mapping[str, Any],
    over: str | None = None,
    values: Sequence[float] | None = None,
    force: bool = False,
    comm: Any = None,
) -> None:
    """Refuse to write a run (or, with ``over``, a sweep) into a folder holding other results.

    The folder's ``results.json`` and ``sweep.json`` (and a ``sweep.csv`` with
    neither) are compared with what is about to be written: scene; single run,
    sweep or study; the resolved ``parameters`` (``params.to_dict``); for sweeps
    the swept parameter and values.  The same results again (a rerun) are
    allowed and overwrite.  A ``sweep.json`` without ``sweep.csv`` or a sweep
    ``results.json`` (a sweep stopped before its first point) holds nothing and
    does not count.  Anything else raises
    :class:`OutputFolderError` naming the folder, what it holds (the differing
    dotted parameters with both values) and the ways out; with ``force`` one
    warning is logged instead.  Collective: decided on rank 0, raised on every rank.
    """
    comm = comm or world()
    new = {
        "scene": scene,
        "kind": "run" if over is None else "sweep",
        "parameters": _plain(parameters),
        "over": over,
        "values": None if values is None else _plain(list(values)),
    }
    out = Path(out_dir)
    if comm.bcast(out.exists() and not out.is_dir() if comm.rank == 0 else None, root=0):
        raise OutputFolderError(f"--out {out} is a file, not a folder: give a folder to write into")
    conflict = None
    if comm.rank == 0:
        try:
            conflict = _folder_conflict(Path(out_dir), new)
        except Exception as e:  # reading the folder failed: refuse rather than guess
            conflict = (
                f"output folder {str(out_dir)!r} could not be checked ({type(e).__name__}: {e})"
            )
    if comm.size > 1:
        conflict = comm.bcast(conflict, root=0)
    if conflict is None:
        return
    if force:
        if comm.rank == 0:
            get_logger().warning("force given: %s; writing into it anyway", conflict)
        return
    raise OutputFolderError(
        f"{conflict}. Refusing to mix results: choose another output folder "
        f"(--out DIR, or out_dir in Python), or overwrite with --force (force=True)"
    )


def resume_rows(
    out_dir: str | Path,
    scene: str,
    parameters: Mapping[str, Any],
    over: str,
    values: Sequence[float],
    comm: Any = None,
) -> list[dict[str, Any]]:
    """The finished rows of the sweep in ``out_dir`` that a resumed sweep goes on from.

    The folder must hold this sweep's manifest ``sweep.json`` (scene, the resolved
    ``parameters``, ``over``, ``values``) and nothing of another run (as
    :func:`check_out_dir`); else :class:`OutputFolderError` (or
    :class:`ParameterError` with no manifest) says what differs.  A trailing
    part of a row left by a kill is cut from ``sweep.csv`` first.  Returns the
    rows (values parsed with :func:`parse_cell`; none if the sweep had not
    finished a point).  Collective: read on rank 0, shared with every rank.
    """
    comm = comm or world()
    out = Path(out_dir)
    new = {"scene": scene, "kind": "sweep", "parameters": _plain(parameters), "over": over,
           "values": _plain(list(values))}  # fmt: skip

    def read() -> list[dict[str, Any]]:
        if not (out / SWEEP_MANIFEST).is_file():
            raise ParameterError(
                f"--resume: output folder {str(out)!r} holds no sweep to resume (no "
                f"{SWEEP_MANIFEST}); run the sweep without --resume"
            )
        where = f"--resume: output folder {str(out)!r}"
        data, bad = _read_json(out / SWEEP_MANIFEST)
        if bad:
            raise OutputFolderError(f"{where}: {bad}")
        differs = _differs(_record_of(data or {}, SWEEP_MANIFEST), new)
        if differs:
            raise OutputFolderError(
                f"{where}: its {SWEEP_MANIFEST} holds {differs}; resume with the same "
                "scene, parameters and values, or start a new sweep in another folder"
            )
        conflict = _folder_conflict(out, new)
        if conflict:
            raise OutputFolderError(f"--resume: {conflict}")
        csv_path = out / "sweep.csv"
        if not csv_path.is_file():
            return []
        cut = repair_csv(csv_path)
        if cut:
            get_logger().warning("--resume: cut %d bytes of a part row from %s", cut, csv_path)
        return [{k: parse_cell(v) for k, v in r.items()} for r in read_csv(csv_path)]

    return _on_rank0(comm, read) if comm.size == 1 else comm.bcast(_on_rank0(comm, read), root=0)


def _plain(v: Any) -> Any:
    """``v`` as it reads back from JSON (tuples become lists, paths strings)."""
    return json.loads(json.dumps(_jsonable(v, strict=False)))


def _read_json(path: Path) -> tuple[dict[str, Any] | None, str | None]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        return None, f"its {path.name} cannot be read ({type(e).__name__}: {e}; truncated?)"
    if not isinstance(data, dict):
        return None, f"its {path.name} is not a results record"
    return data, None


def _record_of(data: Mapping[str, Any], file: str) -> dict[str, Any]:
    if file == SWEEP_MANIFEST or "sweep_parameter" in data:
        kind = "sweep"
    elif "study" in data:
        kind = f"{data['study']} study"
    else:
        kind = "run"
    return {
        "file": file,
        "scene": data.get("scene"),
        "kind": kind,
        "parameters": data.get("parameters"),
        "over": data.get("sweep_parameter", data.get("over")),
        "values": data.get("sweep_values", data.get("values")),
    }


def _folder_conflict(out: Path, new: Mapping[str, Any]) -> str | None:
    """What in ``out`` conflicts with ``new`` (a sentence), or ``None``."""
    where = f"output folder {str(out)!r}"
    if not out.is_dir():
        return None
    results, manifest = out / "results.json", out / SWEEP_MANIFEST
    has_csv = (out / "sweep.csv").is_file()
    records = []
    if results.is_file():
        data, bad = _read_json(results)
        if bad:
            return f"{where}: {bad}"
        records.append(_record_of(data, results.name))
    if manifest.is_file() and (has_csv or any(r["kind"] == "sweep" for r in records)):
        data, bad = _read_json(manifest)
        if bad:
            return f"{where}: {bad}"
        records.append(_record_of(data, manifest.name))
    if has_csv and not any(r["kind"] == "sweep" for r in records):
        return (
            f"{where} holds sweep.csv with neither {SWEEP_MANIFEST} nor a sweep results.json: "
            f"its scene and parameters are unknown"
        )
    for old in records:
        why = _differs(old, new)
        if why:
            return f"{where}: its {old['file']} holds {why}"
    return None


def _what(rec: Mapping[str, Any]) -> str:
    if rec["kind"] == "run":
        return f"a single run of scene {rec['scene']!r}"
    if rec["kind"] == "sweep":
        return f"a sweep of scene {rec['scene']!r} over {rec['over']!r}"
    return f"a {rec['kind']} of scene {rec['scene']!r}"


def _differs(old: Mapping[str, Any], new: Mapping[str, Any]) -> str | None:
    if old["scene"] is None:
        return "results with no 'scene' record"
    if old["scene"] != new["scene"]:
        return f"results of scene {old['scene']!r}, not of scene {new['scene']!r}"
    if old["kind"] != new["kind"]:
        return f"{_what(old)}, not {_what(new)}"
    if not isinstance(old["parameters"], Mapping):
        return f"{_what(old)} with no 'parameters' record"
    diffs = _param_diffs(old["parameters"], new["parameters"])
    if new["kind"] == "sweep":
        if old["over"] != new["over"]:
            return f"{_what(old)}, not over {new['over']!r}"
        if old["values"] != new["values"]:
            diffs.append(
                f"sweep values {_fmt_values(old['values'])} there, {_fmt_values(new['values'])} now"
            )
    if not diffs:
        return None
    shown = "; ".join(diffs[:_MAX_DIFFS])
    more = f"; and {len(diffs) - _MAX_DIFFS} more" if len(diffs) > _MAX_DIFFS else ""
    return f"{_what(old)} with other parameters: {shown}{more}"


_ABSENT = object()


def _param_diffs(old: Mapping[str, Any], new: Mapping[str, Any]) -> list[str]:
    """``name = old there, new now`` for each dotted parameter that differs (new's order first)."""
    a, b = flatten(old), flatten(new)
    names = list(b) + [k for k in a if k not in b]
    out = []
    for k in names:
        x, y = a.get(k, _ABSENT), b.get(k, _ABSENT)
        if x != y:
            out.append(f"{k} = {_show(x)} there, {_show(y)} now")
    return out


def _show(v: Any) -> str:
    if v is _ABSENT:
        return "(absent)"
    if isinstance(v, str):
        return repr(v)
    if isinstance(v, list):
        return _fmt_values(v)
    if isinstance(v, float):
        return repr(v)  # exact: values that differ never read the same
    return format_scalar(v)


def _fmt_values(vals: Any) -> str:
    if not isinstance(vals, list):
        return _show(vals)
    items = [_show(v) for v in vals]
    if len(items) > 6:
        items = [*items[:3], "...", *items[-2:]]
        return f"[{', '.join(items)}] ({len(vals)} values)"
    return f"[{', '.join(items)}]"


# ------------------------------------------------------------ progress
_ACTIVE: list[Progress] = []


class Progress:
    """Progress of long work on rank 0: points done / total, the current value,
    Newton steps and time per point, an estimate of the time left.

    On a terminal (``stream.isatty()``) a tqdm bar on ``stream`` (default
    stderr) updated in place; otherwise one plain line per finished point::

        [3/10] film.speed = 0.001 m/s: 4 Newton steps, 1.2 s; about 8.4 s left

    Other ranks print nothing.  Feed it from the drivers:

    * :meth:`point` as each point (sweep value, study level) finishes;
    * :meth:`failed` for a point that did not converge;
    * :meth:`step` for sub-steps of the current point (load steps, continuation
      steps): shown on the bar, or as a plain line at most every
      ``min_interval`` seconds (every one with ``verbose``).

    Used as a context manager it is the *active* reporter for the block, which
    code far below the driver reaches through :func:`progress_step` without a
    reference to it.  Results lines (:meth:`write`) go to stdout without breaking
    the bar.

    Args:
        total: Number of points.
        over: Name of the swept quantity (``film.speed``).
        unit: Its unit (``m/s``), or ``""``.
        what: What a point is (``point``, ``level``).
        growth: Estimate the time left from the growth of the last two point
            times (each next point ``r`` times the last, ``1 <= r <= 16``: refinement
            studies) instead of the mean time per point (sweeps).
        verbose: Every sub-step as a plain line.
        stream: Where progress goes (default ``sys.stderr``).
        tty: Force bar (True) or plain lines (False); default ``stream.isatty()``.
        min_interval: Least time between two plain sub-step lines [s].
        comm: Communicator; only its rank 0 prints.
        leave: Keep the bar on the terminal when it closes (False: a single run's
            bar of sub-steps disappears).
        prefix: Put before every plain line (``"chain 2/4: "`` for a sweep chain).
    """

    def __init__(
        self,
        total: int,
        over: str = "",
        unit: str = "",
        what: str = "point",
        growth: bool = False,
        verbose: bool = False,
        stream: Any = None,
        tty: bool | None = None,
        min_interval: float = 10.0,
        comm: Any = None,
        leave: bool = True,
        prefix: str = "",
    ) -> None:
        import sys
        import time

        self.total, self.over, self.unit, self.what = int(total), over, unit, what
        self.growth, self.verbose, self.min_interval = growth, verbose, float(min_interval)
        self.prefix = prefix
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = (comm or world()).rank == 0
        if tty is None:
            isatty = getattr(self.stream, "isatty", None)
            tty = bool(isatty and isatty())
        self.tty = tty
        self.done = 0
        self.times: list[float] = []
        self._clock = time.perf_counter
        self._t_last = self._clock()
        self._t_step = -math.inf
        self._bar: Any = None
        self._redirect: Any = None
        if self.enabled and self.tty:
            try:
                from tqdm import tqdm
            except ImportError:  # tqdm is a Debian package of the environment
                self.tty = False
            else:
                self._bar = tqdm(total=self.total, file=self.stream, dynamic_ncols=True, leave=leave,
                                 bar_format="{desc} {n_fmt}/{total_fmt} |{bar}| {postfix}",
                                 desc=over or what)  # fmt: skip

    # -------------------------------------------------------------- feeding
    def _value(self, value: Any) -> str:
        u = f" {self.unit}" if self.unit else ""
        name = f"{self.over} = " if self.over else ""
        return f"{name}{format_scalar(value)}{u}"

    def eta(self) -> float:
        """Estimated time left [s] (nan before the first point)."""
        left = self.total - self.done
        if not self.times:
            return math.nan
        if left <= 0:
            return 0.0
        if self.growth and len(self.times) >= 2 and self.times[-2] > 0:
            r = min(max(self.times[-1] / self.times[-2], 1.0), 16.0)
            return float(sum(self.times[-1] * r**k for k in range(1, left + 1)))
        return left * sum(self.times) / len(self.times)

    def point(self, value: Any, results: Mapping[str, Any] | None = None) -> None:
        """A point finished at ``value`` (``results``: its record, for ``newton_iterations``)."""
        now = self._clock()
        dt, self._t_last = now - self._t_last, now
        self.done += 1
        self.times.append(dt)
        newton = (results or {}).get("newton_iterations")
        parts = [f"{newton} Newton steps"] if isinstance(newton, int) else []
        parts.append(f"{_duration(dt)}")
        left = self.eta()
        tail = f"about {_duration(left)} left" if self.done < self.total else "done"
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.set_postfix_str(
                f"{self._value(value)}, {', '.join(parts)}; {tail}", refresh=False
            )
            self._bar.update(1)
        else:
            self._print(
                f"[{self.done}/{self.total}] {self._value(value)}: {', '.join(parts)}; {tail}"
            )

    def skip(self, n: int) -> None:
        """``n`` points were finished before (a resumed sweep): counted as done, not timed."""
        if n <= 0:
            return
        self.done += n
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.update(n)
        else:
            self._print(f"[{self.done}/{self.total}] resumed: {n} point(s) finished before")

    def failed(self, value: Any, error: Any) -> None:
        """A point at ``value`` failed with ``error`` (counted as done)."""
        now = self._clock()
        self.times.append(now - self._t_last)
        self._t_last = now
        self.done += 1
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.set_postfix_str(f"{self._value(value)} failed", refresh=False)
            self._bar.update(1)
        else:
            self._print(f"[{self.done}/{self.total}] {self._value(value)}: failed ({error})")

    def step(self, label: str, value: Any = None) -> None:
        """A sub-step of the current point: ``label`` (``"load step 3"``) at ``value``
        (e.g. the load fraction, or the continuation speed; None: no value)."""
        if not self.enabled:
            return
        text = label if value is None else f"{label} {format_scalar(value)}"
        if self._bar is not None:
            self._bar.set_postfix_str(f"{self.what} {self.done + 1}: {text}")
            return
        now = self._clock()
        if self.verbose or now - self._t_step >= self.min_interval:
            self._t_step = now
            self._print(f"  [{self.done + 1}/{self.total}] {text}")

    def write(self, line: str) -> None:
        """Print a results line to stdout (rank 0) without breaking the bar."""
        if not self.enabled:
            return
        if self._bar is not None:
            import sys

            self._bar.write(line, file=sys.stdout)
        else:
            print(line, flush=True)

    def _print(self, line: str) -> None:
        print(self.prefix + line, file=self.stream, flush=True)

    def close(self) -> None:
        """End the bar (idempotent)."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> Progress:
        _ACTIVE.append(self)
        if self._bar is not None:
            from tqdm.contrib.logging import logging_redirect_tqdm

            self._redirect = logging_redirect_tqdm(loggers=[get_logger()])
            self._redirect.__enter__()
        return self

    def __exit__(self, *exc: Any) -> None:
        if self._redirect is not None:
            self._redirect.__exit__(*exc)
            self._redirect = None
        self.close()
        if self in _ACTIVE:
            _ACTIVE.remove(self)


def active_progress() -> Progress | None:
    """The innermost :class:`Progress` used as a context manager, or None."""
    return _ACTIVE[-1] if _ACTIVE else None


def progress_step(label: str, value: Any = None) -> None:
    """Report a sub-step (load step, continuation step) to the active :class:`Progress`
    (:meth:`Progress.step`); nothing without one.  Call it on every rank."""
    if _ACTIVE:
        _ACTIVE[-1].step(label, value)


def _duration(seconds: float) -> str:
    """``0.42 s``, ``12 s``, ``3 min 20 s``, ``1 h 05 min``."""
    if not math.isfinite(seconds):
        return "? s"
    if seconds < 10:
        return f"{seconds:.2g} s"
    if seconds < 60:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"
    return f"{int(seconds // 3600)} h {int(seconds % 3600 // 60):02d} min"


# ------------------------------------------------------------ fields for ParaView
#: VTK cell type of each XDMF topology written by DOLFINx (P1 geometry).
_VTK_CELLS = {
    "Triangle": 5,
    "Quadrilateral": 9,
    "Tetrahedron": 10,
    "Hexahedron": 12,
    "Triangle_6": 22,
    "Tetrahedron_10": 24,
}  # second-order geometry: VTK order


def read_fields(path: str | Path) -> dict[str, Any]:
    """Read back an XDMF file written by :func:`~dolfinx_seal.coupled.results.write_fields`.

    Parses the XDMF XML and reads its HDF5 data with ``h5py`` (serial, any rank).
    Returns ``{"points": (n, gdim), "cells": (m, k), "cell_type": "Tetrahedron", ...,
    "point_data": {name: array}, "cell_data": {name: array}}``; a vector or tensor
    field is an array of shape ``(n, components)`` (tensors flattened row by row,
    3x3).  The rows follow the file's geometry and topology.
    """
    import xml.etree.ElementTree as ET

    import h5py
    import numpy as np

    path = Path(path)
    root = ET.parse(path).getroot()

    def data(item: Any) -> Any:
        file, _, key = item.text.strip().partition(":")
        with h5py.File(path.parent / file, "r") as h5:
            return np.asarray(h5[key])

    grid = root.find(".//Grid[@GridType='Uniform']")
    if grid is None:
        raise ValueError(f"{path}: no mesh grid")
    topo = grid.find("Topology")
    out: dict[str, Any] = {
        "points": data(grid.find("Geometry/DataItem")),
        "cells": data(topo.find("DataItem")),
        "cell_type": topo.get("TopologyType"),
        "point_data": {},
        "cell_data": {},
    }
    for attr in root.iter("Attribute"):
        where = "point_data" if attr.get("Center") == "Node" else "cell_data"
        out[where][attr.get("Name")] = data(attr.find("DataItem"))
    return out


def png_renderer() -> tuple[list[str] | None, str]:
    """How to render off screen here: (command prefix, ``""``) or (None, why not).

    pyvista (VTK) draws through an X server: ``$DISPLAY`` if set, else a virtual
    one started by ``xvfb-run`` (Debian packages ``xvfb`` and ``xauth``).
    """
    import shutil

    if importlib.util.find_spec("pyvista") is None:
        return None, "pyvista is not installed"
    if os.environ.get("DISPLAY"):
        return [], ""
    xvfb = shutil.which("xvfb-run")
    if xvfb is None:
        return None, "no X display and no xvfb-run (Debian packages xvfb, xauth)"
    return [xvfb, "-a", "-s", "-screen 0 1600x1200x24"], ""


def render_fields_png(xdmf: str | Path, png: str | Path, timeout: float = 300.0) -> bool:
    """Draw ``png`` from the fields file ``xdmf`` off screen; True if it was written.

    Runs :func:`_draw_fields` in a child process (under ``xvfb-run`` when there is
    no display; MPI variables removed, so the child is a process of its own).
    Never raises: without a renderer, or if drawing fails, it logs one line and
    returns False.  Call it on one rank.
    """
    import subprocess
    import sys

    log = get_logger()
    prefix, why = png_renderer()
    if prefix is None:
        log.info("fields picture %s skipped: %s", Path(png).name, why)
        return False
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
    code = (
        "import sys, mpi4py; mpi4py.rc.initialize = False; "
        "from dolfinx_seal.output import _draw_fields; _draw_fields(sys.argv[1], sys.argv[2])"
    )
    cmd = [*prefix, sys.executable, "-c", code, str(xdmf), str(png)]
    try:
        r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    except (OSError, subprocess.TimeoutExpired) as e:
        log.info("fields picture %s skipped: %s", Path(png).name, e)
        return False
    if r.returncode != 0 or not Path(png).exists():
        last = (r.stderr.strip().splitlines() or ["no message"])[-1]
        log.info("fields picture %s skipped: the renderer failed (%s)", Path(png).name, last)
        return False
    return True


def _draw_fields(xdmf: str | Path, png: str | Path) -> None:
    """The picture of :func:`render_fields_png` (pyvista, in the child process).

    Left: the deformed body seen from -y (the symmetry plane of a half model)
    coloured by the von Mises stress [MPa].  Right: the loaded zone seen from
    the counter-surface (from -z) coloured by the contact plus fluid pressure [MPa].
    """
    import numpy as np
    import pyvista as pv

    f = read_fields(xdmf)
    pts = np.asarray(f["points"], dtype=float)
    if pts.shape[1] < 3:
        pts = np.hstack([pts, np.zeros((pts.shape[0], 3 - pts.shape[1]))])
    cells = np.asarray(f["cells"], dtype=np.int64)
    conn = np.hstack([np.full((cells.shape[0], 1), cells.shape[1]), cells]).ravel()
    types = np.full(cells.shape[0], _VTK_CELLS[f["cell_type"]], dtype=np.uint8)
    grid = pv.UnstructuredGrid(conn, types, pts)
    for k, v in f["point_data"].items():
        grid.point_data[k] = v
    for k, v in f["cell_data"].items():
        grid.cell_data[k] = v
    if "displacement" in grid.point_data:
        u = np.asarray(grid.point_data["displacement"], dtype=float)
        u3 = np.hstack([u, np.zeros((u.shape[0], 3 - u.shape[1]))]) if u.shape[1] < 3 else u
        grid.point_data["u3"] = u3
        grid = grid.warp_by_vector("u3", factor=1.0)
    pressure = np.zeros(grid.n_points)
    for k in ("contact_pressure", "fluid_pressure"):
        if k in grid.point_data:
            pressure = pressure + np.maximum(np.asarray(grid.point_data[k], dtype=float), 0.0)
    grid.point_data["pressure [MPa]"] = pressure / 1e6
    if "von_mises_stress" in grid.cell_data:
        grid.cell_data["von Mises stress [MPa]"] = grid.cell_data["von_mises_stress"] / 1e6
    surf = grid.extract_surface()
    pv.global_theme.font.color = "black"
    plot = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1600, 800), border=False)
    plot.set_background("white")
    bar = {"vertical": True, "position_x": 0.8, "position_y": 0.1, "height": 0.7,
           "title_font_size": 16, "label_font_size": 14}  # fmt: skip
    if "von Mises stress [MPa]" in surf.cell_data:
        plot.add_mesh(surf, scalars="von Mises stress [MPa]", cmap="viridis",
                      scalar_bar_args={**bar, "title": "von Mises [MPa]"})  # fmt: skip
    else:
        plot.add_mesh(surf, color="lightgrey")
    plot.add_text("deformed body: von Mises stress (seen from -y)", font_size=11)
    plot.view_vector((0.0, -1.0, 0.0), viewup=(0.0, 0.0, 1.0))
    plot.subplot(0, 1)
    face = surf
    p_surf = np.asarray(surf.point_data["pressure [MPa]"])
    if p_surf.max() > 0:  # zoom on the loaded zone: a box twice its size, the lower cap
        loaded = surf.points[p_surf > 1e-3 * p_surf.max()]
        lo, hi = loaded.min(axis=0), loaded.max(axis=0)
        mid, half = (lo + hi) / 2, np.maximum(hi - lo, 1e-9 * np.ptp(pts))
        c = surf.cell_centers().points
        near = np.flatnonzero(
            np.all(np.abs(c[:, :2] - mid[:2]) <= half[:2], axis=1) & (c[:, 2] <= hi[2] + half.max())
        )
        if near.size:
            face = surf.extract_cells(near)
    plot.add_mesh(face, scalars="pressure [MPa]", cmap="magma",
                  scalar_bar_args={**bar, "title": "pressure [MPa]"})  # fmt: skip
    plot.add_text("contact face: contact + fluid pressure (seen from -z)", font_size=11)
    plot.view_vector((0.0, 0.0, -1.0), viewup=(1.0, 0.0, 0.0))
    plot.reset_camera()
    with atomic_path(png) as tmp:
        plot.screenshot(str(tmp))
    plot.close()
