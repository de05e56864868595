"""The stability study (``dolfinx-seal study stability SCENE``).

* The shipped tables (``studies/stability/*.toml``) parse, every case resolves
  to valid parameters, and together they span the extremes the study must cover
  (the list of issue 19: moduli, near-incompressibility in both forms, eight
  decades of speed, roughness, zero speed, smooth and rough, the three cavitation
  models, a high sealed pressure, large strain, a tenth and ten times the load).
* A bad table stops before anything runs, naming the file, the case and the
  dotted parameter.
* A run on the cheap rigid cylinder records every point of every case with the
  right status and reason: converged, failed (an injected fault), not attempted
  (after ``max_failures``, and once the time budget is spent), refused, and a
  one-point case; the CSV, Markdown, PNG and ``results.json`` agree with the
  returned rows.
"""

from __future__ import annotations

import json
import math
import re

import pytest
from test_fault_injection import REASON, RIGID, inject  # noqa: F401 (fixture)

from dolfinx_seal import stability
from dolfinx_seal.cli import main
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import read_csv
from dolfinx_seal.params import get_dotted

SCENES = ("cylinder", "lip-install", "lip", "ball", "lip-static", "lip-dynamic")


def _tables() -> list[stability.Table]:
    return [stability.read_table(stability.table_path(s)) for s in SCENES]


def test_the_shipped_tables_span_the_extremes():
    tables = _tables()
    cases = [(t, c) for t in tables for c in t.cases]
    assert len(cases) >= 24
    seen: dict[str, set] = {}
    speeds: list[float] = []
    for t, c in cases:
        if c.expect == "refused":
            continue
        p = stability.case_parameters(t, c)
        for key in ("material.E", "material.nu", "material.formulation", "roughness.h_rms",
                    "contact.model", "film.cavitation", "film.speed"):  # fmt: skip
            if get_dotted(p, key) is not None:
                seen.setdefault(key, set()).add(get_dotted(p, key))
        if c.over == "film.speed":
            speeds += [abs(v) for v in c.values]
        if t.scene == "lip" and c.over == "oil_pressure":
            seen.setdefault("oil_pressure", set()).update(c.values)
        if t.scene == "lip-install" and "lip.tip_radius" in c.settings:
            seen.setdefault("sharp edge", set()).add(c.settings["lip.tip_radius"])
    assert min(seen["material.E"]) <= 1e6 and max(seen["material.E"]) >= 1e9
    nearly = {c.settings.get("material.formulation", "mixed") for _, c in cases
              if c.settings.get("material.nu") == 0.4999}  # fmt: skip
    assert nearly == {"mixed", "compressible"}
    assert min(speeds) <= 1e-7 and max(speeds) >= 10.0
    assert 0.0 in seen["film.speed"]  # a zero-speed case that runs
    assert {0.1e-6, 10e-6} <= seen["roughness.h_rms"]
    assert {"none", "persson"} <= seen["contact.model"]
    assert {"none", "reynolds", "jfo"} <= seen["film.cavitation"]
    assert max(seen["oil_pressure"]) >= 0.5e6
    assert min(seen["sharp edge"]) <= 20e-6
    loads = {(t.scene, c.settings["load"]) for t, c in cases if "load" in c.settings}
    default = {t.scene: get_dotted(stability.case_parameters(t, t.cases[0]), "load")
               for t in tables if t.scene in ("cylinder", "ball")}  # fmt: skip
    ratios = {v / default[s] for s, v in loads}
    assert min(ratios) <= 0.1 + 1e-12 and max(ratios) >= 10.0 - 1e-12
    assert any(c.expect == "refused" for _, c in cases)


@pytest.mark.parametrize(
    "text, needles",
    [
        ('scene = "cylinder"\nspeed = 1\n[[case]]\nname = "a"\n', ["unknown key", "speed"]),
        ('scene = "cylinder"\n[[case]]\nname = "a"\nsett = {}\n', ["case 1 ('a')", "sett"]),
        ('scene = "nope"\n[[case]]\nname = "a"\n', ["scene = 'nope'"]),
        ('scene = "cylinder"\n[[case]]\nname = "soft"\nset = { "material.nu" = 0.7 }\n',
         ["case 'soft'", "material.nu = 0.7", "(-1, 0.5]"]),
        ('scene = "cylinder"\n[[case]]\nname = "s"\nset = { material = { E = -1.0 } }\n',
         ["case 's'", "material.E = -1.0"]),
        ('scene = "cylinder"\nover = "film.speed"\nvalues = [0.1]\n[[case]]\nname = "a"\n'
         '[[case]]\nname = "A"\n', ["unique"]),
        ('scene = "cylinder"\nover = "film.speed"\n[[case]]\nname = "a"\n', ["needs values"]),
        ('scene = "cylinder"\nover = "film.speed"\nvalues = [0.1, -2e9]\n[[case]]\nname = "a"\n',
         ["case 'a'", "film.speed = -2000000000.0"]),
        ('scene = "cylinder"\n[[case]]\nname = "a"\nexpect = "fail"\n', ["expect = 'fail'"]),
        ('scene = "cylinder"\n[[case]]\nname = "a"\ntime_budget = -1\n', ["time_budget = -1"]),
        ('scene = "cylinder"\n', ["no [[case]]"]),
        ('scene = "cylinder\n', ["not valid TOML"]),
    ],
)  # fmt: skip
def test_a_bad_table_names_the_file_the_case_and_the_parameter(mpi_tmp_path, text, needles):
    path = mpi_tmp_path / "bad.toml"
    if COMM_WORLD.rank == 0:
        path.write_text(text)
    COMM_WORLD.barrier()
    with pytest.raises(ParameterError) as info:
        stability.read_table(path)
    msg = str(info.value)
    assert str(path) in msg, msg
    for n in needles:
        assert n in msg, msg


def _rigid_table() -> str:
    """The rigid cylinder of the fault-injection tests, five cases."""
    lines = ['scene = "cylinder"', 'over = "film.speed"', "values = [0.05, 0.1]", "[parameters]"]
    for k, v in _flat(RIGID).items():
        lines.append(f'"{k}" = {json.dumps(v)}')
    lines += [
        '[[case]]', 'name = "plain"', 'about = "two points, both converge"',
        '[[case]]', 'name = "faulty"', 'about = "a fault above 0.15 m/s"',
        "values = [0.05, 0.1, 0.2, 0.4]", 'set = { "stepping.max_failures" = 1 }',
        '[[case]]', 'name = "hurried"', "time_budget = 1e-9", "values = [0.05, 0.1, 0.2]",
        '[[case]]', 'name = "at rest"', 'set = { "film.speed" = 0.0 }', 'over = ""',
        'expect = "refused"',
        '[[case]]', 'name = "one point"', 'set = { "film.speed" = 0.08 }', 'over = ""',
    ]  # fmt: skip
    return "\n".join(lines) + "\n"


def _flat(d, prefix=""):
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(_flat(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


def test_a_stability_run_records_every_point(mpi_tmp_path, inject, capsys):  # noqa: F811
    table = mpi_tmp_path / "rigid.toml"
    if COMM_WORLD.rank == 0:
        table.write_text(_rigid_table())
    COMM_WORLD.barrier()
    fault = inject("nan", above=0.15)
    out = mpi_tmp_path / "stability"
    rc = main(["study", "stability", "cylinder", "--table", str(table), "--out", str(out)])
    assert rc == 0
    assert fault.fired > 0
    rows = read_csv(out / "stability.csv")
    got = [(r["case"], r["value"], r["status"]) for r in rows]
    assert got == [
        ("plain", "0.05", "converged"), ("plain", "0.1", "converged"),
        ("faulty", "0.05", "converged"), ("faulty", "0.1", "converged"),
        ("faulty", "0.2", "failed"), ("faulty", "0.4", "not attempted"),
        ("hurried", "0.05", "converged"), ("hurried", "0.1", "not attempted"),
        ("hurried", "0.2", "not attempted"),
        ("at rest", "", "refused"), ("one point", "", "converged"),
    ]  # fmt: skip
    by = {(r["case"], r["value"]): r for r in rows}
    assert re.search(REASON["nan"], by["faulty", "0.2"]["error"])
    assert "at speed" in by["faulty", "0.2"]["error"]
    assert "1 consecutive failed target" in by["faulty", "0.4"]["error"]
    assert "time budget" in by["hurried", "0.1"]["error"]
    assert "nothing would carry the load" in by["at rest", ""]["error"]
    for r in rows:
        if r["status"] == "converged":  # the residuals of a converged point are on file
            assert int(r["newton_iterations"]) >= 0 and r["error"] == ""
            for k in ("load_balance_error", "mass_balance_error", "mu", "h_min"):
                assert math.isfinite(float(r[k])), (r["case"], k)
            assert float(r["load_balance_error"]) < 1e-8
            assert float(r["mass_balance_error"]) < 1e-6
            assert float(r["complementarity_error"]) >= 0.0  # Reynolds: a VI solve
    summary = json.loads((out / "results.json").read_text())
    assert summary["counts"] == {"converged": 6, "suspect": 0, "failed": 1, "stopped": 0,
                                 "not attempted": 3, "refused": 1, "nan": 0}  # fmt: skip
    md = (out / "stability.md").read_text()
    for name in ("plain", "faulty", "hurried", "at rest", "one point"):
        assert f"## {name}" in md
    assert "| faulty | a fault above 0.15 m/s | film.speed | 2 | 1 | 1 | 0 |" in md
    assert (out / "stability.png").stat().st_size > 0
    printed = capsys.readouterr().out  # print0: the summary line is rank 0's
    assert ("converged: 6, suspect: 0, failed: 1" in printed) == (COMM_WORLD.rank == 0)
    # the report again from the files alone: the same rows and counts
    before = (out / "stability.md").read_text()
    rc = main(["study", "stability", "cylinder", "--table", str(table), "--out", str(out),
               "--report-only"])  # fmt: skip
    assert rc == 0
    again = read_csv(out / "stability.csv")
    assert [(r["case"], r["value"], r["status"]) for r in again] == got
    assert [r["error"] for r in again] == [r["error"] for r in rows]
    assert (out / "stability.md").read_text() == before
    assert json.loads((out / "results.json").read_text())["counts"] == summary["counts"]


def test_select_and_the_command_line_refuse_what_is_not_there(mpi_tmp_path):
    t = stability.read_table(stability.table_path("cylinder"))
    assert [c.name for c in t.select(["E 1 GPa", "default"])] == ["default", "E 1 GPa"]
    assert [c.name for c in t.select(["e-1-gpa"])] == ["E 1 GPa"]  # by folder slug
    with pytest.raises(ParameterError, match="not a case of"):
        t.select(["E 2 GPa"])
    assert main(["study", "stability", "nope-scene"]) == 2
    assert main(["study", "stability", "cylinder", "--set", "load=3"]) == 2
    assert main(["study", "stability", "cylinder", "--table",
                 str(stability.table_path("ball"))]) == 2  # fmt: skip
    assert main(["study", "cylinder"]) == 2  # the convergence study needs --values


def test_the_fallback_speeds_begin_where_the_start_has_not_been():
    """A rough cylinder starts at most at its boundary speed (the speeds above it
    would begin there again), a smooth one at least at Moes M = 1."""
    from dolfinx_seal.scenes import cylinder, make_parameters

    rough = make_parameters("cylinder", values={"film": {"speed": 1e-3}})
    v0 = cylinder.first_speed(rough)
    assert v0 == pytest.approx(cylinder.start_speed(rough), rel=1e-12) and v0 < 1e-3
    got = cylinder.CYLINDER.fallback_speeds(rough)
    assert got == pytest.approx([v0 / 10, v0 / 100], rel=1e-12)
    smooth = make_parameters("cylinder", values={"contact": {"model": "none"},
                                                 "film": {"speed": 1e-3}})  # fmt: skip
    v0 = cylinder.first_speed(smooth)
    assert v0 > 1e-3
    assert cylinder.CYLINDER.fallback_speeds(smooth) == pytest.approx([v0 * 10, v0 * 100])
    at_rest = make_parameters("cylinder", values={"film": {"speed": 0.0}})
    assert cylinder.CYLINDER.fallback_speeds(at_rest) == []


def test_a_ball_starts_at_most_at_its_moes_cap():
    """A ball whose target (or rough start) lies above ``max_start_moes`` starts where
    Moes' M equals the cap, in full film, and walks down: h_rms 0.1 um at 0.01 m/s
    (M = 2907) begins at M = 500, not where it is asked (which failed after 2 Newton
    steps); the rough 1 um, 0.1 m/s and smooth fast balls are below the cap and keep
    their starts."""
    from dolfinx_seal.scenes import ball, make_parameters

    fine = make_parameters("ball", values={"roughness": {"h_rms": 1e-7}})
    assert ball.moes_load(fine, fine.film.speed) == pytest.approx(2907, rel=1e-3)
    v0 = ball.start_speed(fine)
    assert v0 > 10 * fine.film.speed
    assert ball.moes_load(fine, v0) == pytest.approx(fine.max_start_moes, rel=1e-12)
    # the round trip of the estimate, and the cap's direction (M falls as U rises)
    hd = ball.film_estimate(fine)
    assert hd.moes_load(hd.mean_speed_for_moes(123.0)) == pytest.approx(123.0, rel=1e-12)
    assert ball.moes_load(fine, 2 * v0) < fine.max_start_moes
    # the fallback chain then tries only speeds where the start really begins elsewhere
    assert all(v > v0 for v in ball.BALL.fallback_speeds(fine))
    smooth_fast = make_parameters("ball", values={"contact": {"model": "none"},
                                                  "film": {"speed": 1.0}})  # fmt: skip
    assert ball.start_speed(smooth_fast) == 1.0  # M = 92: starts where it is asked
    rough = make_parameters("ball", values={"roughness": {"h_rms": 1e-5}})
    assert ball.moes_load(rough, ball.start_speed(rough)) == pytest.approx(44.5, rel=1e-2)
    capped = make_parameters("ball", values={"roughness": {"h_rms": 1e-7},
                                             "max_start_moes": 5000.0})  # fmt: skip
    assert ball.start_speed(capped) == pytest.approx(capped.film.speed, rel=1e-12)
    with pytest.raises(ParameterError, match="max_start_moes"):
        make_parameters("ball", values={"max_start_moes": 1.0})


#: A representative subset of the shipped tables (slow): per scene, cases that
#: must converge at every point, and one refused by the input checks.
SUBSET = {
    "cylinder": ["default", "JFO cavitation", "E 1 GPa", "nu 0.4999 displacement",
                 "rough, zero speed", "smooth, zero speed"],
    "lip-install": ["nu 0.4999 displacement", "h_rms 0.1 um"],
    "lip": ["rotary, zero speed", "h_rms 10 um"],
    "ball": ["zero speed", "E 100 MPa"],
}  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize("scene", list(SUBSET))
def test_a_subset_of_the_shipped_tables_converges(scene, mpi_tmp_path):
    """Eight decades of speed for the default and the JFO cylinder (the JFO start at
    1e-7 m/s needs the fallback chain), a stiff and a nearly incompressible
    displacement-form body, zero speed; the lip installed in the displacement form
    and with a fine finish; the lip at rest and with a coarse finish; the stiff ball
    (E 100 MPa, 10 to 1 m/s: 3 points, 72 s on one rank with two other jobs).  Every point
    converges with small residuals, or (a case marked so) is refused."""
    table = stability.read_table(stability.table_path(scene))
    rows = stability.stability_study(table, mpi_tmp_path / scene, SUBSET[scene])
    cases = {c.name: c for c in table.cases}
    assert {r["case"] for r in rows} == set(SUBSET[scene])
    for r in rows:
        want = "refused" if cases[r["case"]].expect == "refused" else "converged"
        assert r["status"] == want, (r["case"], r["value"], r["status"], r["error"])
        if want == "converged":
            assert r["load_balance_error"] < 1e-6, r
            # the lip's leakage is ~1e-14 m^3/s; its relative mass balance measured
            # 7.6e-4 and 2.1e-3 at 2 ranks (the film rows' round-off floor)
            assert r.get("mass_balance_error", 0.0) < (1e-2 if scene == "lip" else 1e-6), r


def test_a_converged_point_that_is_not_finite_or_physical_is_flagged():
    case = stability.Case(name="c", over="film.speed", values=(1.0,))
    ok = stability._point_row(case, 1.0, "converged", {"mu": 0.1, "h_min": 1e-7})
    nan = stability._point_row(case, 1.0, "converged", {"mu": math.nan, "h_min": 1e-7})
    neg = stability._point_row(case, 1.0, "converged", {"mu": 0.1, "h_min": -1.2e-9})
    thin = stability._point_row(case, 1.0, "converged", {"mu": 0.1, "h_min": 0.4e-9})
    assert (ok["status"], ok["error"]) == ("converged", "")
    assert nan["status"] == "nan" and "mu" in nan["error"]
    for r, h in ((neg, "-1.2e-09"), (thin, "4e-10")):  # below a continuum film (2 nm)
        assert r["status"] == "suspect" and "thinner than a continuum film" in r["error"]
        assert f"h_min = {h} m" in r["error"], r["error"]
    # a film released only in part is of neither scheme; 0 (released) and 1 (the
    # monotone scheme, asked for) are each a scheme's film
    for w, want in ((0.078125, "suspect"), (0.0, "converged"), (1.0, "converged")):
        r = stability._point_row(case, 1.0, "converged",
                                 {"mu": 0.1, "h_min": 1e-7, "discrete_upwinding_weight": w})  # fmt: skip
        assert r["status"] == want, (w, r)
        assert ("discrete_upwinding_weight = 0.0781" in r["error"]) == (want == "suspect")


def test_a_starved_film_that_pulls_is_flagged_with_every_reason():
    """A starved JFO film whose pressures below zero pull on the body with more than
    ``SUCTION_LIMIT`` of its push is suspect, and a point with two reasons names both
    (the fine shaft's sliding rows: a negative ``h_min`` and a pull of 42 % and more)."""
    case = stability.Case(name="c", over="film.speed", values=(1.0,))
    lim = stability.SUCTION_LIMIT
    for s, want in ((0.0, "converged"), (0.5 * lim, "converged"), (2.0 * lim, "suspect")):
        r = stability._point_row(case, 1.0, "converged",
                                 {"mu": 0.1, "h_min": 1e-7, "suction_load_fraction": s})  # fmt: skip
        assert r["status"] == want, (s, r)
        assert ("suction_load_fraction" in r["error"]) == (want == "suspect")
    both = stability._point_row(case, 1.0, "converged",
                                {"mu": 0.1, "h_min": -9.8e-9, "suction_load_fraction": 0.42})  # fmt: skip
    assert both["status"] == "suspect"
    assert "h_min = -9.8e-09 m" in both["error"] and "suction_load_fraction = 0.42" in both["error"]
    only = stability._point_row(case, 1.0, "converged",
                                {"mu": 0.1, "h_min": 1e-7, "suction_load_fraction": math.inf})  # fmt: skip
    assert only["status"] == "nan"  # a film that only pulls: not finite, flagged as such
