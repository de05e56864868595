"""Resumed sweeps (``dolfinx-seal sweep ... --resume``): nothing lost, nothing twice.

The reference is the same sweep run without interruption.  A sweep is
interrupted three ways:

* SIGKILL of a ``dolfinx-seal sweep`` process after a random number of
  finished points and a random delay into the next one (serial: the test
  spawns the process);
* an exception raised on every rank as a point is handed on (1 and 2 ranks);
* the checkpoint deleted as well, so the resumed sweep must start the points
  left afresh from the scene's own start.

What must hold: the resumed ``sweep.csv`` has the reference's speeds in the
reference's order, each once, and the same values to solver tolerance; the
summary counts every point.  The lubricated cylinder's coupled solves stop at
a relative residual of 1e-11 (``film_snes``); a point reached from the
checkpoint by another path of Newton iterates (no secant predictor on the
first step after the restart) differs from the reference by the Newton
tolerance amplified by the conditioning: ``RTOL`` 1e-6 on mu, h_min and the
load split (measured, serial: 6.3e-11 on the rigid cylinder from the
checkpoint and afresh, 1.5e-12 / 1.8e-13 on the deformable one; a resume that
restarted from the wrong state or speed is off by whole percent).
"""

from __future__ import annotations

import json
import math
import os
import random
import signal
import subprocess
import sys
import time
from contextlib import contextmanager, suppress
from pathlib import Path

import pytest

from dolfinx_seal import checkpoint, scenes
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import OutputFolderError, SweepWriter, read_csv
from dolfinx_seal.scenes.cylinder import CYLINDER
from dolfinx_seal.scenes.flat import SCENE as FLAT

#: The rigid lubricated cylinder (as tests/test_fault_injection.py): a few hundred film unknowns.
RIGID = [
    "h_contact=20e-6", "bulk=false", "contact.model=none", "load=1000", "film.speed=0.05",
    "film.cavitation=reynolds", "film.upstream=3", "film.downstream=2",
]  # fmt: skip
#: The deformable rough cylinder on a coarse mesh (rubber, asperities and film).
DEFORMABLE = ["h_contact=40e-6", "film.speed=0.01"]
SPEEDS = [0.02, 0.05, 0.1, 0.2, 0.5, 1.0]
KEYS = ("mu", "h_min", "load_fluid", "load_contact", "normal_load")
RTOL = 1e-6


def _sweep(sets, out, values=SPEEDS, resume=False):
    p = scenes.make_parameters("cylinder", overrides=sets)
    return scenes.sweep_scene("cylinder", p, out, "film.speed", values, resume=resume)


def _same(rows, ref):
    """Same speeds in the same order, each once, and the same values to RTOL."""
    speeds = [float(r["film.speed"]) for r in rows]
    assert speeds == [float(r["film.speed"]) for r in ref], speeds
    assert len(set(speeds)) == len(speeds)
    for r, q in zip(rows, ref, strict=True):
        for k in KEYS:
            a, b = float(r[k]), float(q[k])
            assert a == pytest.approx(b, rel=RTOL, abs=0.0), (k, r["film.speed"], a, b)


class Interrupt(Exception):
    """Stands for a kill at a point boundary (raised on every rank)."""


@pytest.fixture
def interrupt_after(monkeypatch):
    """``interrupt_after(k)``: the sweep stops as its ``k+1``-th point is handed on
    (after that point's checkpoint, before its row); ``interrupt_after(None)`` undoes it."""
    append = SweepWriter.append

    def install(k: int | None) -> None:
        if k is None:
            monkeypatch.setattr(SweepWriter, "append", append)
            return
        count = [0]

        def interrupted(self, row):
            count[0] += 1
            if count[0] > k:
                raise Interrupt(f"interrupted after {k} points")
            return append(self, row)

        monkeypatch.setattr(SweepWriter, "append", interrupted)

    return install


@contextmanager
def counting(scene, hook):
    """Replace ``scene.<hook>`` (a frozen dataclass field) by a wrapper recording its
    calls' third argument or, for a sweep, its values; yields the record."""
    calls: list = []
    real = getattr(scene, hook)

    def wrapper(*args, **kw):
        calls.append(args[3] if hook == "sweep" else args[1])
        return real(*args, **kw)

    object.__setattr__(scene, hook, wrapper)
    try:
        yield calls
    finally:
        object.__setattr__(scene, hook, real)


@pytest.fixture(scope="module")
def rigid_reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") if COMM_WORLD.rank == 0 else None
    out = Path(COMM_WORLD.bcast(str(out) if out else None, root=0))
    _sweep(RIGID, out)
    return read_csv(out / "sweep.csv")


@pytest.mark.parametrize("k", [1, 4])
def test_a_resumed_sweep_goes_on_from_its_checkpoint(
    k, rigid_reference, interrupt_after, mpi_tmp_path
):
    out = mpi_tmp_path / "sweep"
    interrupt_after(k)
    with pytest.raises(Interrupt):
        _sweep(RIGID, out)
    assert len(read_csv(out / "sweep.csv")) == k
    meta = checkpoint.read_meta(out)
    assert meta is not None and meta["rows"] == k + 1  # the point after the last row
    assert meta["speed"] == SPEEDS[k]
    interrupt_after(None)
    with counting(CYLINDER, "start") as starts:
        rows = _sweep(RIGID, out, resume=True)
    assert not starts, "the resumed sweep started afresh instead of from its checkpoint"
    _same(read_csv(out / "sweep.csv"), rigid_reference)
    assert len(rows) == len(SPEEDS)
    summary = json.loads((out / "results.json").read_text())
    assert summary["points_finished"] == len(SPEEDS) and summary["failed_points"] == []
    assert not (out / checkpoint.FOLDER).exists()  # removed once the sweep is done


def test_without_a_checkpoint_the_points_left_start_afresh(
    rigid_reference, interrupt_after, mpi_tmp_path
):
    out = mpi_tmp_path / "sweep"
    interrupt_after(3)
    with pytest.raises(Interrupt):
        _sweep(RIGID, out)
    checkpoint.remove(out)
    interrupt_after(None)
    with counting(CYLINDER, "start") as starts:
        _sweep(RIGID, out, resume=True)
    assert [p.film.speed for p in starts] == [SPEEDS[3]]  # afresh, at the first point left
    _same(read_csv(out / "sweep.csv"), rigid_reference)


def test_the_deformable_cylinder_resumes_with_its_rubber_state(interrupt_after, mpi_tmp_path):
    values = SPEEDS[:4]
    ref = mpi_tmp_path / "ref"
    _sweep(DEFORMABLE, ref, values)
    out = mpi_tmp_path / "sweep"
    interrupt_after(2)
    with pytest.raises(Interrupt):
        _sweep(DEFORMABLE, out, values)
    interrupt_after(None)
    _sweep(DEFORMABLE, out, values, resume=True)
    _same(read_csv(out / "sweep.csv"), read_csv(ref / "sweep.csv"))


def test_a_finished_sweep_resumes_to_itself(rigid_reference, mpi_tmp_path):
    out = mpi_tmp_path / "sweep"
    _sweep(RIGID, out, SPEEDS[:2])
    before = (out / "sweep.csv").read_bytes()
    rows = _sweep(RIGID, out, SPEEDS[:2], resume=True)
    assert len(rows) == 2 and (out / "sweep.csv").read_bytes() == before


def test_resume_refuses_another_sweep_or_none(mpi_tmp_path):
    out = mpi_tmp_path / "sweep"
    with pytest.raises(ParameterError, match=r"--resume: .* holds no sweep to resume"):
        _sweep(RIGID, out, SPEEDS[:2], resume=True)
    flat = scenes.make_parameters("flat")
    scenes.sweep_scene("flat", flat, out, "film.speed", [1e-3, 1e-2])
    with pytest.raises(OutputFolderError, match=r"scene 'flat', not of scene 'cylinder'"):
        _sweep(RIGID, out, SPEEDS[:2], resume=True)
    other = scenes.make_parameters("flat", overrides=["material.E=3e6"])
    with pytest.raises(OutputFolderError, match=r"material\.E = .* there, 3000000\.0 now"):
        scenes.sweep_scene("flat", other, out, "film.speed", [1e-3, 1e-2], resume=True)
    with pytest.raises(OutputFolderError, match=r"sweep values"):
        scenes.sweep_scene("flat", flat, out, "film.speed", [1e-3, 2e-2], resume=True)


def test_a_scene_without_continuation_solves_only_the_points_left(mpi_tmp_path):
    """``flat`` points are independent: the resumed sweep solves the rows missing
    (and a part of a row cut by the kill is dropped), the values are the same bits."""
    values = [1e-4, 1e-3, 1e-2, 1e-1]
    flat = scenes.make_parameters("flat")
    ref, out = mpi_tmp_path / "ref", mpi_tmp_path / "sweep"
    scenes.sweep_scene("flat", flat, ref, "film.speed", values)
    scenes.sweep_scene("flat", flat, out, "film.speed", values)
    if COMM_WORLD.rank == 0:  # a kill in the third row: two whole rows and a part
        lines = (out / "sweep.csv").read_bytes().splitlines(keepends=True)
        (out / "sweep.csv").write_bytes(b"".join(lines[:3]) + lines[3][:17])
        (out / "results.json").unlink()
    COMM_WORLD.barrier()
    with counting(FLAT, "sweep") as solved:
        rows = scenes.sweep_scene("flat", flat, out, "film.speed", values, resume=True)
    assert solved == [values[2:]]
    assert len(rows) == 4
    assert (out / "sweep.csv").read_bytes() == (ref / "sweep.csv").read_bytes()


def _descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (from /proc), children first."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    out: list[int] = []
    todo = list(children.get(pid, []))
    while todo:
        p = todo.pop()
        out.append(p)
        todo += children.get(p, [])
    return out


def _kill_tree(pid: int) -> list[int]:
    """SIGKILL ``pid`` and all its descendants at once (a SIGKILL of mpirun alone
    leaves its ranks running); returns the processes killed."""
    tree = [*_descendants(pid), pid]
    for p in tree:
        with suppress(ProcessLookupError):
            os.kill(p, signal.SIGKILL)
    return tree


def _alive(pids: list[int]) -> list[int]:
    """Those of ``pids`` still running (zombies count as gone)."""
    out = []
    for p in pids:
        try:
            state = Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state != "Z":
            out.append(p)
    return out


@pytest.mark.skipif(COMM_WORLD.size > 1, reason="spawns its own dolfinx-seal processes")
@pytest.mark.parametrize("ranks", [1, 2], ids=["serial", "killed-on-2-resumed-on-1"])
def test_sigkill_at_a_random_point_then_resume(ranks, rigid_reference, tmp_path):
    """The process is killed at a random moment after a random number of rows (the
    seed is in the message of a failure); the resume runs serially, so the 2-rank
    case resumes on another partition and number of ranks."""
    seed = int.from_bytes(os.urandom(4), "little")
    rng = random.Random(seed)
    k = rng.randint(1, len(SPEEDS) - 2)  # rows finished before the kill
    out = tmp_path / "sweep"
    argv = [
        "sweep",
        "cylinder",
        *[a for s in RIGID for a in ("--set", s)],
        "--over",
        "film.speed",
        "--values",
        ",".join(map(str, SPEEDS)),
        "--out",
        str(out),
    ]
    cmd = [sys.executable, "-c", "import sys; from dolfinx_seal.cli import main; "
           "sys.exit(main(sys.argv[1:]))", *argv]  # fmt: skip
    mpi = ["mpirun", "-n", str(ranks)] if ranks > 1 else []
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    proc = subprocess.Popen([*mpi, *cmd], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE)  # fmt: skip
    csv_path, t0 = out / "sweep.csv", time.monotonic()
    delay, killed = math.nan, []
    try:
        while not (csv_path.is_file() and csv_path.read_bytes().count(b"\n") >= k + 1):
            assert proc.poll() is None, proc.stderr.read().decode()
            assert time.monotonic() - t0 < 300, f"no {k} rows after 300 s"
            time.sleep(0.01)
        t_row = (time.monotonic() - t0) / k
        delay = rng.uniform(0.0, 0.8) * t_row  # into the next point (its solve, checkpoint or row)
        time.sleep(delay)
        killed = _kill_tree(proc.pid)  # mpirun and its ranks, as a scheduler kills a job
        proc.wait(60)
    finally:
        if proc.poll() is None:
            _kill_tree(proc.pid)
    assert proc.returncode == -signal.SIGKILL
    t_kill = time.monotonic()
    while _alive(killed) and time.monotonic() - t_kill < 10:
        time.sleep(0.05)
    assert not _alive(killed), f"still running after SIGKILL: {_alive(killed)}"
    kept = read_csv(csv_path)
    where = f"seed {seed}: killed {delay:.3f} s after row {k} ({len(kept)} rows kept)"
    assert k <= len(kept) < len(SPEEDS), where
    done = subprocess.run([*cmd, "--resume"], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"{where}: {done.stderr}"
    assert "Traceback" not in done.stderr
    assert "resuming from the checkpoint of" in done.stderr, f"{where}: {done.stderr}"
    _same(read_csv(csv_path), rigid_reference)
    summary = json.loads((out / "results.json").read_text())
    assert summary["points_finished"] == len(SPEEDS), where


def test_resume_and_force_together_are_refused(capsys, mpi_tmp_path):
    from dolfinx_seal.cli import main

    rc = main(["sweep", "flat", "--over", "film.speed", "--values", "1e-3,1e-2",
               "--out", str(mpi_tmp_path / "s"), "--resume", "--force"])  # fmt: skip
    assert rc == 2
    assert "--resume and --force" in capsys.readouterr().err


def test_a_value_swept_twice_is_matched_row_by_row():
    """An ``up-down`` walk lists speeds twice: each row takes off the first
    occurrence of its value, so the points left are the later ones, in order."""
    values = [0.1, 0.3, 1.0, 0.3, 0.1]
    state = scenes.Resume(rows=3, done={0.1: 1, 0.3: 1, 1.0: 1})
    assert state.positions(values) == [3, 4]
    assert state.remaining(values) == [0.3, 0.1]
    assert scenes.Resume(rows=0, done={}).positions(values) == [0, 1, 2, 3, 4]
    assert scenes.Resume(rows=5, done={0.1: 2, 0.3: 2, 1.0: 1}).remaining(values) == []
