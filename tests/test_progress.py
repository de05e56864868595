"""Progress on long work (:class:`dolfinx_seal.output.Progress`): rank 0 only, a bar
on a terminal and plain lines otherwise, an estimate of the time left."""

from __future__ import annotations

import io
import re
import shutil
import subprocess
import sys

import pytest

from dolfinx_seal.output import Progress, active_progress, progress_step


class _Clock:
    """A settable clock for the reporter (seconds)."""

    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def _reporter(total: int, **kw) -> tuple[Progress, io.StringIO, _Clock]:
    stream = io.StringIO()
    p = Progress(total, "film.speed", "m/s", stream=stream, tty=False, comm=_Rank(0), **kw)
    clock = _Clock()
    p._clock = clock
    p._t_last = 0.0
    return p, stream, clock


class _Rank:
    """A communicator stub: these unit tests act as the given rank on any run."""

    size = 2

    def __init__(self, rank: int) -> None:
        self.rank = rank


def test_plain_lines_count_newton_steps_and_time_left():
    p, stream, clock = _reporter(4)
    for i, t in enumerate((2.0, 4.0, 6.0)):  # 2 s per point
        clock.t = t
        p.point(10.0**-i, {"newton_iterations": 5 + i})
    lines = stream.getvalue().splitlines()
    assert len(lines) == 3
    assert lines[0] == "[1/4] film.speed = 1 m/s: 5 Newton steps, 2 s; about 6 s left"
    assert lines[2] == "[3/4] film.speed = 0.01 m/s: 7 Newton steps, 2 s; about 2 s left"
    clock.t = 9.0
    p.point(1e-3, {})
    assert stream.getvalue().splitlines()[-1] == "[4/4] film.speed = 0.001 m/s: 3 s; done"
    assert p.eta() == 0.0


def test_growth_estimate_for_refinement_studies():
    """Each next level ``r`` times the last: 1 s, 3 s done, two left -> 9 + 27 s."""
    p, _, clock = _reporter(4, growth=True, what="level")
    clock.t = 1.0
    p.point(1.0)
    clock.t = 4.0
    p.point(0.5)
    assert p.eta() == pytest.approx(9.0 + 27.0, rel=1e-12)


def test_sub_steps_are_throttled_unless_verbose():
    p, stream, clock = _reporter(2, min_interval=10.0)
    for k in range(5):
        clock.t = float(k)  # 5 steps within 4 s: only the first is shown
        p.step(f"load step {k + 1}", 0.2 * (k + 1))
    assert stream.getvalue().splitlines() == ["  [1/2] load step 1 0.2"]
    v, vstream, _ = _reporter(2, verbose=True)
    with v:
        assert active_progress() is v
        for k in range(5):
            progress_step("continuation", 0.1 * k)  # through the active reporter
    assert active_progress() is None
    assert len(vstream.getvalue().splitlines()) == 5
    progress_step("nobody listens", 1.0)  # no active reporter: nothing happens


def test_other_ranks_print_nothing():
    stream = io.StringIO()
    p = Progress(2, "x", stream=stream, tty=False, comm=_Rank(1))
    p.point(1.0, {"newton_iterations": 3})
    p.step("load step", 0.5)
    p.failed(2.0, "diverged")
    p.write("result line")
    assert stream.getvalue() == ""
    assert p.done == 2


def test_bar_on_a_terminal(monkeypatch):
    """``tty``: a tqdm bar redrawn in place (carriage returns), with the time left.

    tqdm sizes a bar on a stream without a terminal from ``COLUMNS`` and ``LINES``;
    an 80-column default (a pytest-xdist worker) cut the time left off the line."""
    monkeypatch.setenv("COLUMNS", "200")
    monkeypatch.setenv("LINES", "50")
    stream = io.StringIO()
    with Progress(3, "velocity", "m/s", stream=stream, tty=True, comm=_Rank(0)) as p:
        assert p._bar is not None
        p.point(1e-3, {"newton_iterations": 4})
        p.step("load step 2", 0.5)
        p.point(1e-2, {"newton_iterations": 2})
    text = stream.getvalue()
    assert "\r" in text
    last = text.split("\r")[-1]
    assert "3/3" not in last and "2/3" in last  # two of three points done
    assert "velocity = 0.01 m/s, 2 Newton steps" in text
    assert re.search(r"about [0-9.]+ s left", text)


@pytest.mark.skip_in_parallel
@pytest.mark.skipif(shutil.which("mpirun") is None, reason="no mpirun")
def test_cli_sweep_on_two_ranks_reports_from_rank_0_only(tmp_path):
    """``mpirun -n 2 dolfinx-seal sweep flat``: one progress line per point on stderr
    (not a terminal here), one result line per point on stdout, nothing twice."""
    n = 4
    cmd = ["mpirun", "-n", "2", sys.executable, "-m", "dolfinx_seal.cli", "sweep", "flat",
           "--over", "film.speed", "--values", f"1e-6:1e-2:{n}:log", "--out", str(tmp_path / "s")]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    progress = [ln for ln in r.stderr.splitlines() if re.match(r"\[\d+/\d+\] film\.speed = ", ln)]
    assert [ln.split("]")[0] for ln in progress] == [f"[{i}/{n}" for i in range(1, n + 1)]
    assert all(re.search(r"about .* left$", ln) for ln in progress[:-1])
    assert progress[-1].endswith("; done")
    assert "\r" not in r.stderr  # plain lines, no bar
    out = r.stdout.splitlines()
    assert len(out) == n + 1  # the default output stays short: a line per point and a summary
    assert out[-1].startswith(f"{n} of {n} points finished")


@pytest.mark.skip_in_parallel
def test_run_has_a_reporter_for_sub_steps(tmp_path, monkeypatch, capsys):
    """``dolfinx-seal run``: sub-steps reported deep in a scene reach stderr (plain
    line, not a terminal); the results table stays on stdout."""
    from dolfinx_seal import cli

    def fake_run(name, params, out, force=False):
        progress_step("load step 1", 0.5)
        return {"scene": name, "mu": 0.25, "converged": True}

    monkeypatch.setattr(cli._scenes, "run_scene", fake_run)
    assert cli.main(["run", "flat", "--out", str(tmp_path / "r")]) == 0
    captured = capsys.readouterr()
    assert "  [1/1] load step 1 0.5" in captured.err.splitlines()
    assert "mu" in captured.out and "load step" not in captured.out
    assert active_progress() is None
