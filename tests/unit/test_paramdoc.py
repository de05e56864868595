"""``dolfinx-seal params`` and ``docs/parameters.md``: the parameter reference read off
the dataclasses (docstrings for meaning and unit, the checks for the allowed range)."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from dolfinx_seal import paramdoc, scenes
from dolfinx_seal.cli import main
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import (
    check_choice,
    check_int_range,
    check_positive,
    check_range,
    from_mapping,
    recording_checks,
)

DOCS = Path(__file__).resolve().parents[2] / "docs" / "parameters.md"

#: Fields whose class docstring does not document them yet (the list may only shrink).
KNOWN_UNDOCUMENTED: dict[str, set[str]] = {}
#: Parameters whose check names them otherwise: ``make_material`` checks ``material``.
ERROR_NAMES = {"material.model": "material"}


# ------------------------------------------------------------ a toy scene
@dataclass(frozen=True)
class Inner:
    """Inner table.

    Attributes:
        length: A length [m] (extra words).
        count: How many.
        angle: An angle (deg); between the two faces.
        mode: ``fast`` or ``slow``.
        t_lo, t_hi: Lower and upper temperature [K].
    """

    length: float = 2.0
    count: int = 3
    angle: float = 30.0
    mode: str = "fast"
    t_lo: float = 250.0
    t_hi: float = 300.0
    hidden: float = 1.0

    def __post_init__(self) -> None:
        check_positive("inner.length", self.length, "m")
        check_int_range("count", self.count, 1, 9)
        check_range("angle", self.angle, 0.0, 90.0, lo_open=True, hi_open=True, unit="deg")
        check_range("angle", self.angle, 10.0, 180.0)  # intersected: [10, 90)
        check_choice("mode", self.mode, ("fast", "slow"))
        check_positive("t_lo", self.t_lo, "K")
        check_range("t_hi", self.t_hi, self.t_lo, math.inf, lo_open=True, unit="K (> t_lo)")
        check_positive("length", 99.0)  # an internal quantity of the same name: ignored


@dataclass(frozen=True)
class Toy:
    """Toy scene (SI units).

    Attributes:
        radius: Radius R (m). More text that is not the first sentence.
        inner: The inner table.
        size: Element size [m], e.g. at most radius / 4.
        flag: Whether to do it.
    """

    radius: float = 1.0
    inner: Inner = field(default_factory=Inner)
    size: float = 0.1
    flag: bool = True

    def __post_init__(self) -> None:
        check_positive("radius", self.radius, "m")
        check_range("size", self.size, 0.0, self.radius / 4, lo_open=True, unit="m (<= radius/4)")


def _by_name(rows):
    return {r.name: r for r in rows}


def test_toy_rows_come_from_docstrings_and_checks():
    with recording_checks() as records:
        toy = Toy(radius=2.0)
    rows = _by_name(paramdoc.describe(toy, records))
    assert list(rows) == [
        "radius", "inner.length", "inner.count", "inner.angle", "inner.mode", "inner.t_lo",
        "inner.t_hi", "inner.hidden", "size", "flag",
    ]  # fmt: skip
    r = rows["radius"]
    assert (r.value, r.unit, r.allowed, r.meaning) == (2.0, "m", "(0, inf)", "Radius R.")
    assert rows["inner.length"].unit == "m" and rows["inner.length"].allowed == "(0, inf)"
    assert rows["inner.length"].meaning == "A length (extra words)."
    assert rows["inner.count"].allowed == "[1, 9] integer" and rows["inner.count"].unit == "-"
    assert rows["inner.angle"].allowed == "[10, 90)" and rows["inner.angle"].unit == "deg"
    assert rows["inner.angle"].meaning == "An angle; between the two faces."
    assert rows["inner.mode"].allowed == "one of: fast, slow" and rows["inner.mode"].unit == ""
    assert rows["inner.mode"].meaning == "`fast` or `slow`."
    assert rows["inner.t_lo"].unit == rows["inner.t_hi"].unit == "K"
    assert rows["inner.t_hi"].allowed == "(250, inf) (> t_lo)"
    assert rows["inner.hidden"].unit == "?" and not rows["inner.hidden"].documented
    assert rows["inner.hidden"].meaning == paramdoc.UNDOCUMENTED
    # a bound depending on another parameter is evaluated at its value, with the rule
    assert rows["size"].allowed == "(0, 0.5] (<= radius/4)"
    assert rows["size"].meaning == "Element size, e.g. at most radius / 4."
    assert rows["flag"].unit == "" and rows["flag"].allowed == ""
    assert rows["size"].range.hi == 0.5 and not rows["size"].range.hi_open


def test_describe_without_records_validates_again():
    """An instance built outside the recording (e.g. a shared default) is re-checked."""
    rows = _by_name(paramdoc.describe(Toy()))
    assert rows["size"].allowed == "(0, 0.25] (<= radius/4)"
    assert rows["inner.angle"].allowed == "[10, 90)"


def test_nothing_is_recorded_outside_the_block():
    with recording_checks() as records:
        pass
    Toy()
    assert records == []
    with recording_checks() as records:
        Inner()
    assert {r.name for r in records} >= {"inner.length", "count", "mode"}
    assert all(isinstance(r.owners[0], Inner) for r in records)


def test_nested_errors_name_the_full_dotted_parameter():
    @dataclass(frozen=True)
    class Outer:
        """Outer.

        Attributes:
            toy: A toy.
        """

        toy: Toy = field(default_factory=Toy)

    with pytest.raises(ParameterError, match=r"^toy\.inner\.count = 0 is outside"):
        from_mapping(Outer, {"toy": {"inner": {"count": 0}}})
    with pytest.raises(ParameterError, match=r"^toy\.inner\.length = -1\.0 m is outside"):
        from_mapping(Outer, {"toy": {"inner": {"length": -1.0}}})  # checked as "inner.length"
    with pytest.raises(ParameterError, match=r"^toy\.radius = "):
        from_mapping(Outer, {"toy": {"radius": -1}})


# ------------------------------------------------------- the real scenes
def _leaves(obj, prefix=""):
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if dataclasses.is_dataclass(v):
            yield from _leaves(v, f"{prefix}{f.name}.")
        else:
            yield f"{prefix}{f.name}", v


@pytest.mark.parametrize("scene", scenes.available())
def test_every_parameter_of_every_scene_is_listed(scene):
    defaults = dict(_leaves(scenes.make_parameters(scene)))
    rows = paramdoc.scene_parameters(scene)
    assert [r.name for r in rows] == list(defaults)
    for r in rows:
        assert r.value == defaults[r.name], r.name
        if r.kind in ("float", "int"):
            assert r.unit, f"{scene}: {r.name} has no unit"
    undocumented = {r.name for r in rows if not r.documented}
    assert undocumented <= KNOWN_UNDOCUMENTED.get(scene, set()), (
        f"{scene}: document these in the 'Attributes:' section of their dataclass: "
        f"{sorted(undocumented - KNOWN_UNDOCUMENTED.get(scene, set()))}"
    )
    assert sum(bool(r.allowed) for r in rows) > len(rows) / 2


def test_headline_parameters_have_units_and_ranges():
    cyl = _by_name(paramdoc.scene_parameters("cylinder"))
    assert (cyl["material.E"].unit, cyl["material.E"].allowed) == ("Pa", "(0, inf)")
    assert cyl["film.speed"].unit == "m/s" and cyl["film.speed"].allowed.endswith(", 1000]")
    assert cyl["material.model"].allowed == "one of: linear, neo-hookean, mooney-rivlin"
    p = scenes.make_parameters("cylinder")
    a = math.sqrt(4 * p.load * p.radius / (math.pi * p.material.E_star))
    assert cyl["contact_elements"].allowed == "[4, 1000]"
    # h_contact is None by default (a / contact_elements): its range shows once it is set
    cyl_h = _by_name(paramdoc.scene_parameters("cylinder", overrides=["h_contact=1e-5"]))
    assert cyl_h["h_contact"].range.hi == pytest.approx(a / 4, rel=1e-12, abs=0)
    assert "a_Hertz/4" in cyl_h["h_contact"].allowed
    lip = _by_name(paramdoc.scene_parameters("lip-install"))
    lp = scenes.make_parameters("lip-install").lip
    r = lip["lip.interference"]
    assert r.unit == "m" and r.range.lo == 0 and r.range.lo_open
    assert r.range.hi == min(lp.oil_face_height, 0.25 * lp.shaft_radius)
    assert r.meaning.startswith("Radial overlap of the undeformed lip tip")


def _outside(r):
    """Values just outside the allowed range of row ``r`` (none for open-ended sides)."""
    a = r.range
    if a.choices:
        return ["no-such-choice"]
    out = []
    for bound, is_open, sign in ((a.lo, a.lo_open, -1), (a.hi, a.hi_open, 1)):
        if math.isinf(bound):
            continue
        if a.integer:
            out.append(int(bound) + (0 if is_open else sign))
        else:
            out.append(bound if is_open else bound + sign * max(abs(bound), 1e-300) * 1e-6)
    return out


@pytest.mark.parametrize("scene", scenes.available())
def test_the_listed_ranges_are_the_enforced_ones(scene):
    """Just outside each listed bound the scene's parameters are rejected, naming the parameter."""
    tried = 0
    for r in paramdoc.scene_parameters(scene):
        if r.kind not in ("float", "int", "str") or not r.allowed:
            continue
        for v in _outside(r):
            with pytest.raises(ParameterError) as err:
                scenes.make_parameters(scene, overrides=[f"{r.name}={v}"])
            assert ERROR_NAMES.get(r.name, r.name) in str(err.value), (r.name, v, str(err.value))
            tried += 1
    assert tried >= 5


def test_docs_parameters_md_is_up_to_date():
    text = paramdoc.markdown()
    committed = DOCS.read_text() if DOCS.exists() else ""
    assert committed == text, (
        f"docs/parameters.md is out of date with the parameter dataclasses; regenerate it with "
        f"`{paramdoc.REGENERATE}`"
    )


# ----------------------------------------------------------------- the CLI
def test_params_command_prints_the_table(capsys):
    assert main(["params", "cylinder"]) == 0
    out = capsys.readouterr().out
    if COMM_WORLD.rank == 0:
        lines = {ln.split()[0]: ln for ln in out.splitlines() if ln.strip()}
        head = ["parameter", "default", "unit", "allowed", "meaning"]
        assert lines["parameter"].split()[:5] == head
        assert lines["material.E"].split()[1:4] == ["1e+07", "Pa", "(0,"]
        assert " m/s " in lines["film.speed"]
    assert main(["params", "lip-install", "--set", "lip.shaft_radius=4e-3"]) == 0
    out = capsys.readouterr().out
    if COMM_WORLD.rank == 0:
        line = next(ln for ln in out.splitlines() if ln.startswith("lip.interference"))
        # the value column is headed "value" and the dependent bound follows the override
        assert "(0, 0.001]" in line and out.splitlines()[1].split()[1] == "value"


def test_params_command_errors(capsys):
    assert main(["params"]) == 2
    assert main(["params", "flat", "--set", "material.nu=0.7"]) == 2
    err = capsys.readouterr().err
    if COMM_WORLD.rank == 0:
        assert "give one SCENE or --all" in err and "material.nu = 0.7" in err


def test_params_markdown_file(mpi_tmp_path, capsys):
    out = mpi_tmp_path / "parameters.md"
    assert main(["params", "--all", "--markdown", "--output", str(out)]) == 0
    COMM_WORLD.barrier()
    assert out.read_text() == paramdoc.markdown()
    text = out.read_text()
    for name in scenes.available():
        assert f"## `{name}`" in text
    assert "| `material.E` | `1e+07` | Pa | (0, inf) | Young's modulus. |" in text


@pytest.mark.skip_in_parallel
def test_params_of_numpy_scenes_do_not_import_dolfinx():
    code = (
        "import sys\n"
        "from dolfinx_seal.cli import main\n"
        "assert main(['params', 'flat']) == 0 and main(['params', 'rubber-friction']) == 0\n"
        "bad = [m for m in sys.modules if m.split('.')[0] in ('dolfinx', 'ufl', 'ffcx', 'basix')]\n"
        "assert not bad, bad\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "film.speed" in out.stdout and "material.model" in out.stdout
