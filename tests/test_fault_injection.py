"""Fault injection: solver failures are reported, never lost or silent.

Faults are injected at the Python level into the project's one nonlinear
solver (:class:`dolfinx_seal.solvers.NonlinearSolver`) on the cheapest coupled
scene, the rigid lubricated cylinder (no rubber unknowns, no asperities, 20 um
elements: a few hundred film unknowns):

* ``nan``: the residual is NaN (``SNES ... DIVERGED_FNORM_NAN``, or for the
  film's VI solver a "converged" solve whose complementarity residual is NaN);
* ``linear``: the Jacobian is all zeros, so its factorisation, i.e. the linear
  solve, fails;
* ``diverge``: the convergence test reports divergence after the first
  Newton step (``DIVERGED_DTOL``), a step that blows up.

A fault fires only while the film's speed is above a threshold, so in a sweep
the points below it finish and the ones above fail.  What must hold: the error
names what diverged (the SNES and its reason) and where (problem and speed);
the finished points stay in ``sweep.csv`` (and in the exception's ``partial``
when the scene's sweep cannot go on); the CLI exits with status 3 with a
one-line message as the last line of stderr (after the log records), no traceback.
"""

from __future__ import annotations

import csv
import json
import logging
import math
import re

import numpy as np
import pytest
from petsc4py import PETSc

from dolfinx_seal import scenes
from dolfinx_seal.cli import main
from dolfinx_seal.errors import SolverError
from dolfinx_seal.film.surface import SurfaceFilm
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.output import read_csv
from dolfinx_seal.solvers import NonlinearSolver

#: The rigid lubricated cylinder (as tests/verification/test_cylinder_film.py).
RIGID = {
    "h_contact": 20e-6, "bulk": False, "contact": {"model": "none"}, "load": 1000.0,
    "film": {"speed": 0.05, "cavitation": "reynolds", "upstream": 3.0, "downstream": 2.0},
    # a target is given up after two halvings of a 0.5-decade step
    "stepping": {"min_decades": 0.2},
}  # fmt: skip
RIGID_SET = [
    "h_contact=20e-6", "bulk=false", "contact.model=none", "load=1000", "film.speed=0.05",
    "film.cavitation=reynolds", "film.upstream=3", "film.downstream=2",
    "stepping.min_decades=0.2",
]  # fmt: skip
SET_ARGS = [a for s in RIGID_SET for a in ("--set", s)]
REASON = {
    # newtonls stops with DIVERGED_FNORM_NAN; the reduced-space VI of the film reports
    # CONVERGED_FNORM_ABS with |F| = 0 on an all-NaN residual, which the solver's
    # complementarity check then refuses ("... complementarity residual is nan")
    "nan": r"DIVERGED_FNORM_NAN|complementarity residual is nan",
    "linear": r"(?i)linear[ _]solve.*MUMPS INFOG\(1\) = -\d+",
    "diverge": "DIVERGED_DTOL",
}


class Fault:
    """A fault of ``kind`` that fires while the film speed is above ``above`` [m/s]."""

    def __init__(self, kind: str, above: float = -math.inf) -> None:
        self.kind = kind
        self.above = above
        self.speed = RIGID["film"]["speed"]
        self.fired = 0

    @property
    def armed(self) -> bool:
        return self.speed > self.above


@pytest.fixture
def inject(monkeypatch):
    """``inject(kind, above)`` installs a fault; returns it (``fired`` counts)."""

    def install(kind: str, above: float = -math.inf) -> Fault:
        fault = Fault(kind, above)
        set_speed = SurfaceFilm.set_speed

        def tracked(self, speed):
            fault.speed = float(speed)
            return set_speed(self, speed)

        monkeypatch.setattr(SurfaceFilm, "set_speed", tracked)
        residual, jacobian = NonlinearSolver._residual, NonlinearSolver._jacobian
        converged = NonlinearSolver._converged

        def nan_residual(self, snes, x, b):
            residual(self, snes, x, b)
            if fault.armed:
                fault.fired += 1
                b.set(np.nan)

        def zero_jacobian(self, snes, x, A, P):
            jacobian(self, snes, x, A, P)
            if fault.armed:
                fault.fired += 1
                A.zeroEntries()
                A.assemble()

        def diverging(self, snes, it, norms):
            reason = converged(self, snes, it, norms)
            if fault.armed and it >= 1:
                fault.fired += 1
                return PETSc.SNES.ConvergedReason.DIVERGED_DTOL
            return reason

        patch = {"nan": ("_residual", nan_residual), "linear": ("_jacobian", zero_jacobian),
                 "diverge": ("_converged", diverging)}[kind]  # fmt: skip
        monkeypatch.setattr(NonlinearSolver, *patch)
        return fault

    return install


LOG_RECORD = re.compile(r"^\d{4}-\d\d-\d\d [\d:,]+ (DEBUG|INFO|WARNING|ERROR) dolfinx_seal: ")
#: a progress line (output.Progress, plain mode): a point, or an indented sub-step
PROGRESS = re.compile(r"^\s*\[\d+/\d+\] ")


@pytest.fixture(autouse=True)
def _log_to_this_tests_stderr():
    """``main`` installs its log handler on the stream that is ``sys.stderr`` then;
    each test starts without one, so its records go to its own captured stderr."""
    logger = get_logger()
    saved = logger.handlers[:]
    logger.handlers = [h for h in saved if not getattr(h, "_dolfinx_seal", False)]
    yield
    logger.handlers = saved


def _one_line(err: str, prefix: str) -> str:
    """The CLI's message: the last line of stderr, after log records and progress lines only."""
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert lines and lines[-1].startswith(prefix), err
    assert all(LOG_RECORD.match(ln) or PROGRESS.match(ln) for ln in lines[:-1]), err
    return lines[-1][len(prefix) :]


@pytest.mark.parametrize("kind", ["nan", "linear"])
def test_a_failing_run_names_what_diverged_and_keeps_no_stale_results(
    kind, inject, mpi_tmp_path, capsys
):
    fault = inject(kind)
    p = scenes.make_parameters("cylinder", values=RIGID)
    with pytest.raises(SolverError) as info:
        scenes.run_scene("cylinder", p, mpi_tmp_path / "api")
    e = info.value
    assert fault.fired > 0
    assert re.search(REASON[kind], e.what), e.what
    assert e.what.startswith("SNES '") and "cylinder" in e.where, (e.what, e.where)
    assert e.history.reason_name  # the PETSc reason of the failed solve is kept
    assert not (mpi_tmp_path / "api" / "results.json").exists()

    capsys.readouterr()
    out = mpi_tmp_path / "cli"
    rc = main(["run", "cylinder", *SET_ARGS, "--out", str(out)])
    message = _one_line(capsys.readouterr().err, "dolfinx-seal: solver error: ")
    assert rc == 3
    assert re.search(REASON[kind], message) and "cylinder" in message, message
    assert not (out / "results.json").exists()


@pytest.mark.parametrize("kind", ["nan", "linear", "diverge"])
def test_a_fault_mid_sweep_keeps_the_finished_points(kind, inject, mpi_tmp_path, capsys):
    """Sweep 0.05, 0.1, 0.2, 0.4 m/s with the fault above 0.15 m/s: two points
    finish, the continuation gives up the other two, the CLI exits 3 naming them."""
    fault = inject(kind, above=0.15)
    out = mpi_tmp_path / "sweep"
    argv = ["sweep", "cylinder", *SET_ARGS,
            "--over", "film.speed", "--values", "0.05,0.1,0.2,0.4", "--out", str(out)]  # fmt: skip
    capsys.readouterr()
    rc = main(argv)
    captured = capsys.readouterr()
    message = _one_line(captured.err, "dolfinx-seal: solver error: ")
    assert rc == 3 and fault.fired > 0
    assert "2 of 4 points not finished (film.speed = 0.2, 0.4)" in message, message
    assert re.search(REASON[kind], message) and "cylinder at speed" in message, message
    assert f"{out}/sweep.csv" in message
    # the finished points are complete rows of sweep.csv, converged and finite
    rows = read_csv(out / "sweep.csv")
    assert [float(r["film.speed"]) for r in rows] == [0.05, 0.1]
    for r in rows:
        assert r["converged"] in ("True", "true", True, "1")
        assert all(math.isfinite(float(r[k])) for k in ("mu", "h_min", "load_fluid"))
    # what failed, and why, is on file
    with (out / "sweep_failures.csv").open(newline="") as fh:
        failed = list(csv.DictReader(fh))
    assert [float(f["speed"]) for f in failed] == [0.2, 0.4]
    assert all(re.search(REASON[kind], f["error"]) and "at speed" in f["error"] for f in failed)
    summary = json.loads((out / "results.json").read_text())
    assert summary["points_finished"] == 2


def test_a_sweep_that_cannot_go_on_hands_back_its_finished_points(mpi_tmp_path, monkeypatch):
    """A failure the continuation cannot absorb (here: computing the results of the
    third point raises) ends the scene's sweep with a SolverError whose ``partial``
    holds the rows already handed out; ``sweep_scene`` keeps them in ``sweep.csv``
    and records the failure in ``results.json``."""
    from dolfinx_seal.scenes import lubricated as coupled_sweep

    real = coupled_sweep.lubricated_results
    calls = [0]

    def results(*a, **k):
        calls[0] += 1
        if calls[0] == 3:
            raise SolverError("injected: the film of the third point is not finite",
                              where="cylinder results at speed 0.2 m/s")  # fmt: skip
        return real(*a, **k)

    monkeypatch.setattr(coupled_sweep, "lubricated_results", results)
    p = scenes.make_parameters("cylinder", values=RIGID)
    handed: list[float] = []
    with pytest.raises(SolverError) as info:
        scenes.get("cylinder").sweep(p, mpi_tmp_path / "raw", "film.speed", [0.05, 0.1, 0.2, 0.4],
                                     lambda v, r: handed.append(v))  # fmt: skip
    assert handed == [0.05, 0.1]
    assert [float(r["film.speed"]) for r in info.value.partial] == handed
    assert "third point" in info.value.what and "0.2 m/s" in info.value.where

    calls[0] = 0
    out = mpi_tmp_path / "driver"
    rows = scenes.sweep_scene("cylinder", p, out, "film.speed", [0.05, 0.1, 0.2, 0.4])
    assert [r["film.speed"] for r in rows] == [0.05, 0.1]
    assert [float(r["film.speed"]) for r in read_csv(out / "sweep.csv")] == [0.05, 0.1]
    summary = json.loads((out / "results.json").read_text())
    assert summary["points_finished"] == 2
    assert "third point" in summary["failed_points"][0]["error"]
    assert "0.2 m/s" in summary["failed_points"][0]["where"]


def test_a_sweep_whose_first_start_fails_starts_from_its_other_end(inject, mpi_tmp_path):
    """The walk 0.4 -> 0.1 -> 0.05 m/s with every solve above 0.15 m/s failing: the
    start at 0.4 m/s fails along the whole fallback chain, so the sweep starts at
    its other end (0.05 m/s), walks back, converges at 0.05 and 0.1 m/s and records
    0.4 m/s as not reached, with both the continuation's and the start's error."""
    fault = inject("nan", above=0.15)
    p = scenes.make_parameters("cylinder", values={**RIGID, "sweep_order": "given"})
    out = mpi_tmp_path / "reverse"
    handed: list[float] = []
    rows = scenes.get("cylinder").sweep(p, out, "film.speed", [0.4, 0.1, 0.05],
                                        lambda v, r: handed.append(v))  # fmt: skip
    assert fault.fired > 0
    assert handed == [0.05, 0.1]
    assert len(rows) == 2 and all(math.isfinite(r["mu"]) for r in rows)
    failures = read_csv(out / "sweep_failures.csv")
    assert [float(f["speed"]) for f in failures] == [0.4]
    why = failures[0]["error"]  # the start's error is kept across the resume
    assert "from the other end" in why and "the start at 0.4 m/s failed" in why, why
    why = failures[0]["error"]
    assert "from the other end" in why and "the start at 0.4 m/s failed" in why, why
    assert re.search(REASON["nan"], why), why
    # the two ends failing: one error naming both starts, nothing converged
    fault.above = 0.0
    with pytest.raises(SolverError, match="at both ends of the sweep") as info:
        scenes.get("cylinder").sweep(p, mpi_tmp_path / "none", "film.speed", [0.4, 0.05],
                                     lambda v, r: None)  # fmt: skip
    assert "0.4 m/s" in str(info.value) and "0.05 m/s" in str(info.value)
    # a first start that spent the time budget: the other end is not tried
    fault.above = 0.15
    hurried = scenes.make_parameters(
        "cylinder", values={**RIGID, "sweep_order": "given",
                            "stepping": {**RIGID["stepping"], "time_budget": 1e-9}},
    )  # fmt: skip
    with pytest.raises(SolverError, match=r"other end, 0\.05 m/s, was not attempted: the "
                                          "time budget") as info:  # fmt: skip
        scenes.get("cylinder").sweep(hurried, mpi_tmp_path / "hurried", "film.speed",
                                     [0.4, 0.1, 0.05], lambda v, r: None)  # fmt: skip
    assert re.search(REASON["nan"], str(info.value)), str(info.value)


def test_a_target_the_newton_limit_stalls_is_walked_again_without_it(monkeypatch, mpi_tmp_path):
    """``stepping.max_newton`` cuts a continuation step that needs more Newton steps;
    a target the cut walk gives up is walked once more with the solver's own limit.
    Here every solve is held back until its fourth Newton step, so with a limit of 3
    no continuation step can converge: the point converges on the second walk."""
    real = NonlinearSolver._converged

    def slow(self, snes, it, norms):
        reason = real(self, snes, it, norms)
        return PETSc.SNES.ConvergedReason.ITERATING if reason > 0 and it < 4 else reason

    monkeypatch.setattr(NonlinearSolver, "_converged", slow)
    records: list[str] = []
    handler = logging.Handler()
    handler.emit = lambda r: records.append(r.getMessage())
    get_logger().addHandler(handler)
    old_level = get_logger().level
    get_logger().setLevel(logging.INFO)
    try:
        p = scenes.make_parameters("cylinder", values={**RIGID, "stepping": {
            **RIGID["stepping"], "max_newton": 3}})  # fmt: skip
        rows = scenes.get("cylinder").sweep(p, mpi_tmp_path, "film.speed", [0.05, 0.1],
                                            lambda v, r: None)  # fmt: skip
    finally:
        get_logger().removeHandler(handler)
        get_logger().setLevel(old_level)
    assert [r["converged"] for r in rows] == [True, True]
    assert rows[1]["newton_iterations"] >= 4  # more than the limit: the second walk's
    stalled = [m for m in records if "not reached with 3 Newton steps a step" in m]
    assert len(stalled) == 1 and stalled[0].startswith("speed 0.1 m/s"), records
    assert not (mpi_tmp_path / "sweep_failures.csv").exists()


def test_a_reversed_sweep_resumes_in_its_own_direction(inject, monkeypatch, mpi_tmp_path):
    """The walk 0.4 -> 0.1 -> 0.05 -> 0.02 m/s with every solve above 0.15 m/s
    failing runs reversed (from 0.02 m/s); killed as its third point (0.1 m/s) is
    handed on, after that point's checkpoint, and resumed, it goes on from the
    checkpoint towards 0.4 m/s, not back towards 0.02: the same rows as the walk
    that was not interrupted (RTOL 1e-6, as tests/test_resume.py), each once, and
    0.4 m/s recorded as not reached, with the failed start's error."""
    from dolfinx_seal import checkpoint
    from dolfinx_seal.output import SweepWriter
    from dolfinx_seal.scenes.cylinder import CYLINDER

    inject("nan", above=0.15)
    p = scenes.make_parameters("cylinder", values={**RIGID, "sweep_order": "given"})
    speeds = [0.4, 0.1, 0.05, 0.02]
    ref_out = mpi_tmp_path / "reference"
    scenes.sweep_scene("cylinder", p, ref_out, "film.speed", speeds)
    ref = read_csv(ref_out / "sweep.csv")
    assert [float(r["film.speed"]) for r in ref] == [0.02, 0.05, 0.1]

    out = mpi_tmp_path / "resumed"
    append = SweepWriter.append

    def killed(self, row):
        if float(row["film.speed"]) == 0.1:
            raise KeyboardInterrupt("killed")
        return append(self, row)

    monkeypatch.setattr(SweepWriter, "append", killed)
    with pytest.raises(KeyboardInterrupt):
        scenes.sweep_scene("cylinder", p, out, "film.speed", speeds)
    meta = checkpoint.read_meta(out)
    assert meta is not None and meta["reverse"] and meta["speed"] == 0.1
    monkeypatch.setattr(SweepWriter, "append", append)
    starts: list[float] = []
    real = CYLINDER.start

    def counted(prob, q, s):
        starts.append(q.film.speed)
        return real(prob, q, s)

    object.__setattr__(CYLINDER, "start", counted)  # a frozen dataclass field
    try:
        scenes.sweep_scene("cylinder", p, out, "film.speed", speeds, resume=True)
    finally:
        object.__setattr__(CYLINDER, "start", real)
    assert not starts, "the resumed sweep started afresh instead of from its checkpoint"
    rows = read_csv(out / "sweep.csv")
    assert [float(r["film.speed"]) for r in rows] == [0.02, 0.05, 0.1]
    for r, q in zip(rows, ref, strict=True):
        for k in ("mu", "h_min", "load_fluid", "normal_load"):
            assert float(r[k]) == pytest.approx(float(q[k]), rel=1e-6, abs=0.0), (k, r)
    failures = read_csv(out / "sweep_failures.csv")
    assert [float(f["speed"]) for f in failures] == [0.4]
    why = failures[0]["error"]  # the start's error is kept across the resume
    assert "from the other end" in why and "the start at 0.4 m/s failed" in why, why
