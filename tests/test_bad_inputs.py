"""A catalogue of bad inputs: each gets a ParameterError naming the full dotted
parameter, the value and the allowed range, before anything is assembled, and
no traceback.

Every case goes through one of the three ways in:

* ``set``: ``dolfinx-seal run SCENE --set ...`` (``cli.main`` in-process);
* ``toml``: a scene file written to ``tmp_path`` and ``run SCENE --scene-file``;
* ``cli``: any other command line (``sweep``, ``psd``);
* ``api``: the Python API (``make_parameters``, the parameter dataclasses,
  ``set_parameter``, ``run_scene``, ``sweep_scene``).

"Before anything is assembled" is enforced, not assumed: every scene's ``run``
and ``sweep`` (where all meshing, form compilation and solving happen) are
replaced by a function that fails the test, so a case passes only if it is
refused while the parameters are read.  The CLI must exit with status 2 and
print exactly one line, ``dolfinx-seal: parameter error: ...``, on stderr.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from dolfinx_seal import scenes
from dolfinx_seal.cli import main
from dolfinx_seal.errors import ParameterError

PREFIX = "dolfinx-seal: parameter error: "


@dataclass(frozen=True)
class Case:
    """One bad input.

    Attributes:
        via: ``set``, ``toml``, ``cli`` or ``api``.
        scene: Scene of ``set`` / ``toml`` cases.
        args: ``--set`` items (``set``), the TOML text (``toml``, one string) or the
            argv (``cli``); ``{tmp}`` is replaced by the test's folder.
        call: ``api``: ``call(tmp_path)`` must raise.
        files: Files written to the test's folder first (name -> text or bytes).
        expect: Substrings the message must hold (the full dotted name, the value,
            the allowed range or what is expected instead).
    """

    via: str
    expect: tuple[str, ...]
    scene: str = ""
    args: tuple[str, ...] = ()
    call: Callable[[Path], Any] | None = None
    files: dict[str, str | bytes] = field(default_factory=dict)


def _cyl(**values: Any) -> Any:
    return scenes.make_parameters("cylinder", values=values)


def _api_cylinder_direct(**kw: Any) -> Callable[[Path], Any]:
    from dolfinx_seal.scenes.cylinder import CylinderParameters

    return lambda _tmp: CylinderParameters(**kw)


def _api_ball_direct(**kw: Any) -> Callable[[Path], Any]:
    from dolfinx_seal.scenes.ball import BallParameters

    return lambda _tmp: BallParameters(**kw)


def _api_film(**kw: Any) -> Callable[[Path], Any]:
    from dolfinx_seal.film.surface import FilmParams

    return lambda _tmp: FilmParams(**kw)


def _api_material_in_ball(_tmp: Path) -> Any:
    from dolfinx_seal.film.surface import FilmParams
    from dolfinx_seal.scenes.ball import BallParameters

    return BallParameters(material=FilmParams())


PSD_OK = "# q [1/m], C [m^4]\n1e4, 1e-20\n1e6, 1e-26\n1e8, 1e-32\n"
MAP_ROWS = "\n".join(
    " ".join(f"{1e-6 * math.sin(i + 2 * j):.3e}" for j in range(16)) for i in range(16)
)


def _ragged_map() -> str:
    rows = MAP_ROWS.splitlines()
    rows[4] = " ".join(rows[4].split()[:-1])  # line 5 lacks its last height
    return "\n".join(rows) + "\n"


def _map_with(bad: str) -> str:
    rows = [r.split() for r in MAP_ROWS.splitlines()]
    rows[2][3] = bad  # line 3, column 4
    return "\n".join(" ".join(r) for r in rows) + "\n"


CASES: dict[str, Case] = {
    # ------------------------------------------------ unknown and misspelt keys
    "unknown-key-suggests": Case("set", ("'radus'", "'0.02'", "did you mean 'radius'"),
                                 "cylinder", ("radus=0.02",)),
    "misspelt-nested-key": Case("set", ("'film.viscocity'", "did you mean 'film.viscosity'",
                                        "allowed of film"), "cylinder", ("film.viscocity=0.1",)),
    "misspelt-lip-key": Case("set", ("'lip.interferance'", "did you mean 'lip.interference'"),
                             "lip-install", ("lip.interferance=3e-4",)),
    "unknown-key-no-near-name": Case("set", ("'material.colour'", "'black'", "E, c01_ratio"),
                                     "ball", ("material.colour=black",)),
    "flat-unknown-key": Case("set", ("'frobnicate'", "allowed are"), "flat", ("frobnicate=1",)),
    # --------------------------------------------------------------- wrong types
    "word-for-float": Case("set", ("radius", "'ten'", "(0, inf) m"), "cylinder", ("radius=ten",)),
    "word-for-int": Case("set", ("degree", "'two'", "integer in [1, 3]"), "cylinder",
                         ("degree=two",)),
    "fraction-for-int": Case("set", ("degree", "'1.5'", "integer in [1, 3]"), "ball",
                             ("degree=1.5",)),
    "word-for-bool": Case("set", ("lubricated", "'perhaps'", "true or false"), "cylinder",
                          ("lubricated=perhaps",)),
    "value-for-table": Case("set", ("film is a table", "speed", "'fast'"), "cylinder",
                            ("film=fast",)),
    "table-for-value": Case("set", ("radius is a value", "'x'", "(0, inf) m"), "cylinder",
                            ("radius.x=1",)),
    "value-and-table": Case("set", ("'material'", "a value and a table"), "cylinder",
                            ("material=soft", "material.E=1e6")),
    "set-without-equals": Case("set", ("--set expects key=value", "'radius'"), "cylinder",
                               ("radius",)),
    "set-bad-name": Case("set", ("'film..speed'", "not a (dotted) parameter name"), "cylinder",
                         ("film..speed=1",)),
    # -------------------------------------------------------------- NaN and inf
    "nan-nested": Case("set", ("material.nu", "nan", "(-1, 0.5]"), "cylinder",
                       ("material.nu=nan",)),
    "inf-nested": Case("set", ("material.E", "inf", "(0, inf) Pa"), "ball", ("material.E=inf",)),
    "minus-inf": Case("set", ("film.viscosity", "-inf", "(0, inf) Pa s"), "cylinder",
                      ("film.viscosity=-inf",)),
    "nan-int": Case("set", ("degree", "'nan'", "integer in [1, 3]"), "lip", ("degree=nan",)),
    # ------------------------------------------------------ zero and negative sizes
    "zero-radius": Case("set", ("radius = 0.0 m", "(0, inf)"), "cylinder", ("radius=0",)),
    "negative-mesh-size": Case("set", ("h_contact = -1e-05 m", "(0, "), "ball",
                               ("h_contact=-1e-5",)),
    "negative-roughness": Case("set", ("roughness.h_rms = -1e-06 m", "(0, inf)"), "cylinder",
                               ("roughness.h_rms=-1e-6",)),
    "negative-interference": Case("set", ("lip.interference = -0.0001 m", "(0, inf)"),
                                  "lip-install", ("lip.interference=-1e-4",)),
    "zero-stroke": Case("set", ("stroke_length = 0.0 m", "(0, inf)"), "lip",
                        ("stroke_length=0",)),
    # --------------------------------------------------------- out-of-range values
    "poisson-above-half": Case("set", ("material.nu = 0.7", "(-1, 0.5]"), "cylinder",
                               ("material.nu=0.7",)),
    "unknown-choice": Case("set", ("film.cavitation = 'elrod'", "'reynolds', 'jfo'"), "cylinder",
                           ("film.cavitation=elrod",)),
    "unknown-material-model": Case("set", ("material.model = 'ogden'", "'neo-hookean'"), "ball",
                                   ("material.model=ogden",)),
    "oil-pressure-too-high": Case("set", ("oil_pressure = 6000000.0 Pa", "[0, 5e+06]"), "lip",
                                  ("oil_pressure=6e6",)),
    "interference-too-deep": Case("set", ("lip.interference = 0.002 m", "(0, 0.0015)"),
                                  "lip-install", ("lip.interference=2e-3",)),
    "sector-q-th-below-q-min": Case("set", ("roughness.q_th = 100000.0 1/m", "[300000, 1e+08)"),
                                    "lip-static", ("roughness.q_th=1e5",)),
    "sector-taller-than-lip": Case("set", ("sector.height = 0.001 m", "(0.000113815, 0.00080032)"),
                                   "lip-static", ("sector.height=1e-3",)),
    "sector-sliding-at-rest": Case("set", ("film.speed = 0.0 m/s", "(0, 100]", "lip-static"),
                                   "lip-dynamic", ("film.speed=0",)),
    "sector-sliding-feedback": Case("set", ("feedback", "true or false"),
                                    "lip-dynamic", ("feedback=2",)),
    "sector-sliding-lift": Case("set", ("lift", "true or false"), "lip-dynamic", ("lift=2",)),
    "lip-angle": Case("set", ("lip.oil_angle = 85.0 deg", "(10, 80)"), "lip-install",
                      ("lip.oil_angle=85",)),
    "stepping-growth": Case("set", ("stepping.grow = 0.5", "[1, 4]"), "cylinder",
                            ("stepping.grow=0.5",)),
    "hurst-flat": Case("set", ("roughness.hurst = 1.5", "(0, 1)"), "flat",
                       ("roughness.hurst=1.5",)),
    "flat-table-size": Case("set", ("n_pressures = 4", "[8, inf)"), "flat", ("n_pressures=4",)),
    "cut-offs-crossed": Case("set", ("roughness.q1 = 1000.0 1/m (> q0)", "(10000, inf)"),
                             "ball", ("roughness.q1=1e3",)),
    # ----------------------------------------------------- contradictory combinations
    "incompressible-compressible": Case("set", ("material.nu = 0.5", "material.formulation = "
                                                "'mixed'", "(-1, 0.5)"), "cylinder",
                                        ("material.formulation=compressible",)),
    "rigid-and-dry": Case("set", ("bulk = false", "lubricated = true"), "cylinder",
                          ("lubricated=false", "bulk=false")),
    "nothing-carries-load": Case("set", ("film.speed = 0", "contact.model = 'none'"), "cylinder",
                                 ("film.speed=0", "contact.model=none")),
    "flow-factor-needs-roughness": Case("set", ("film.flow_factor = 'persson'",
                                                "contact.model = 'persson' or 'exponential'"),
                                        "lip", ("contact.model=stiff",)),
    "two-measured-roughnesses": Case("set", ("roughness.topography_file = 'm.npy'",
                                             "roughness.psd_file = 'c.txt'", "exclusive"),
                                     "cylinder", ("roughness.topography_file=m.npy",
                                                  "roughness.pixel_size=1e-6",
                                                  "roughness.psd_file=c.txt")),
    "map-without-pixel": Case("set", ("roughness.pixel_size = 0.0 m", "(0, inf)"), "ball",
                              ("roughness.topography_file=m.npy",)),
    # ----------------------------------------- meshes too coarse, loads/speeds outside
    "cylinder-mesh-coarser-than-hertz": Case("set", ("h_contact = 0.0001 m (<= a_Hertz/4)",
                                                     "(0, 7.72548e-05]"), "cylinder",
                                             ("h_contact=1e-4",)),
    "ball-mesh-coarser-than-hertz": Case("set", ("h_contact = 0.001 m (<= a_Hertz/4)", "(0, "),
                                         "ball", ("h_contact=1e-3",)),
    "ball-rim-coarser-than-contact": Case("set", ("rim_refinement = 0.5", "[1, 4]"), "ball",
                                          ("rim_refinement=0.5",)),
    "lip-mesh-too-coarse": Case("set", ("lip.h_contact = 0.0001 m", "(0, 5e-05]"),
                                "lip-install", ("lip.h_contact=1e-4",)),
    "cylinder-load-beyond-small-contact": Case("set", ("load = 10000000.0 N/m", "0.3 R",
                                                       "allowed range (0, "), "cylinder",
                                               ("load=1e7",)),
    "ball-load-beyond-small-contact": Case("set", ("load = 10000.0 N", "0.4 R",
                                                   "allowed range (0, "), "ball", ("load=1e4",)),
    "speed-beyond-range": Case("set", ("film.speed = 2000.0 m/s", "[-1000, 1000]"), "cylinder",
                               ("film.speed=2e3",)),
    "rotary-speed-negative": Case("set", ("film.speed = -1.0 m/s", ">= 0"), "lip",
                                  ("film.speed=-1",)),
    # ten times the S1 load: a = 0.39 R, and the default film cap of 3 a would leave the ball
    "ball-film-cap-beyond-the-ball": Case("set", ("film_extent = 3.0 Hertz radii", "0.9 R",
                                                  "[1.5, 2.287"), "ball", ("load=13",)),
    "ball-film-at-rest": Case("set", ("film.speed = 0 m/s", "film.speed > 0"), "ball",
                              ("film.speed=0",)),
    # ------------------------------------------------------------------ sweeps (CLI)
    "sweep-misspelt-parameter": Case("cli", ("'film.sped'", "did you mean 'film.speed'"),
                                     args=("sweep", "cylinder", "--over", "film.sped",
                                           "--values", "0.1,0.2", "--out", "{tmp}/o")),
    "sweep-value-out-of-range": Case("cli", ("film.speed = 2000.0 m/s", "[-1000, 1000]"),
                                     args=("sweep", "cylinder", "--over", "film.speed",
                                           "--values", "0.01,2000", "--out", "{tmp}/o")),
    "sweep-value-word": Case("cli", ("--values", "'fast' is not a number"),
                             args=("sweep", "cylinder", "--over", "film.speed", "--values",
                                   "0.01,fast", "--out", "{tmp}/o")),
    "sweep-range-word": Case("cli", ("--values", "'x' is not a number"),
                             args=("sweep", "ball", "--over", "film.speed", "--values",
                                   "0.01:0.1:x", "--out", "{tmp}/o")),
    "sweep-no-values": Case("cli", ("--values", "gives no values"),
                            args=("sweep", "cylinder", "--over", "film.speed", "--values", ",",
                                  "--out", "{tmp}/o")),
    "sweep-zero-points": Case("cli", ("--values n = 0", "[1, inf)"),
                              args=("sweep", "cylinder", "--over", "film.speed", "--values",
                                    "0.01:0.1:0", "--out", "{tmp}/o")),
    "sweep-over-a-table": Case("cli", ("film is a table", "e.g. film.viscosity"),
                               args=("sweep", "cylinder", "--over", "film", "--values", "1",
                                     "--out", "{tmp}/o")),
    # --------------------------------------------------------------------- TOML files
    "toml-malformed": Case("toml", ("bad.toml", "not valid TOML", "line 2"), "cylinder",
                           ("[parameters]\nradius = = 0.01\n",)),
    "toml-parameters-not-a-table": Case("toml", ("parameters = 3", "must be a table"),
                                        "cylinder", ("parameters = 3\n",)),
    "toml-word-for-float": Case("toml", ("radius", "'big'", "(0, inf) m"), "cylinder",
                                ('[parameters]\nradius = "big"\n',)),
    "toml-bool-for-float": Case("toml", ("material.nu", "True", "(-1, 0.5]"), "cylinder",
                                ("[parameters.material]\nnu = true\n",)),
    "toml-nan": Case("toml", ("film.speed", "nan", "[-1000, 1000] m/s"), "cylinder",
                     ("[parameters.film]\nspeed = nan\n",)),
    "toml-unknown-nested": Case("toml", ("'film.sped'", "did you mean 'film.speed'"), "ball",
                                ("[parameters.film]\nsped = 0.1\n",)),
    "toml-table-for-value": Case("toml", ("load is a value", "(0, inf) N/m"), "cylinder",
                                 ("[parameters.load]\nvalue = 100\n",)),
    "toml-other-scene": Case("toml", ("scene file is for scene 'ball'", "'cylinder'"),
                             "cylinder", ('scene = "ball"\n[parameters]\nradius = 0.01\n',)),
    "toml-not-utf8": Case("toml", ("bad.toml", "not UTF-8 text", "byte 0xff"), "cylinder",
                          (b"radius = 0.01\n\xff\xfe\n",)),
    "toml-missing": Case("cli", ("scene file", "none.toml", "does not exist"),
                         args=("run", "cylinder", "--scene-file", "{tmp}/none.toml")),
    "toml-is-a-folder": Case("cli", ("scene file", "is not a file"),
                             args=("run", "cylinder", "--scene-file", "{tmp}")),
    # ------------------------------------------- PSD and topography files (psd FILE)
    "psd-missing-map": Case("cli", ("topography_file", "nowhere.txt", "does not exist"),
                            args=("psd", "{tmp}/nowhere.txt", "--pixel-size", "1e-6", "--out",
                                  "{tmp}/psd")),
    "psd-ragged-map": Case("cli", ("map.txt:5", "row has 15 values, expected 16"),
                           args=("psd", "{tmp}/map.txt", "--pixel-size", "1e-6", "--out",
                                 "{tmp}/psd"), files={"map.txt": _ragged_map()}),
    "psd-word-in-map": Case("cli", ("map.txt:3", "column 4", "'x' is not a number"),
                            args=("psd", "{tmp}/map.txt", "--pixel-size", "1e-6", "--out",
                                  "{tmp}/psd"), files={"map.txt": _map_with("x")}),
    "psd-nan-in-map": Case("cli", ("map.txt:3", "column 4", "'nan' is not finite"),
                           args=("psd", "{tmp}/map.txt", "--pixel-size", "1e-6", "--out",
                                 "{tmp}/psd"), files={"map.txt": _map_with("nan")}),
    "psd-negative-pixel": Case("cli", ("pixel_size = -1.0 m", "(0, inf)"),
                               args=("psd", "{tmp}/map.txt", "--pixel-size", "-1", "--out",
                                     "{tmp}/psd"), files={"map.txt": MAP_ROWS + "\n"}),
    "psd-no-pixel-size": Case("cli", ("pixel_size (m)", "map.txt", "is required"),
                              args=("psd", "{tmp}/map.txt", "--out", "{tmp}/psd"),
                              files={"map.txt": MAP_ROWS + "\n"}),
    # ------------------------------------------- roughness tables given to a scene
    "psd-table-word": Case("set", ("roughness.psd_file", "c.txt:3", "not numbers", "'1e6, x'"),
                           "cylinder", ("roughness.psd_file={tmp}/c.txt",),
                           files={"c.txt": "# q C\n1e4, 1e-20\n1e6, x\n"}),
    "psd-table-decreasing-q": Case("set", ("roughness.psd_file", "c.txt:4", "q = 1e5",
                                           "strictly increasing"), "ball",
                                   ("roughness.psd_file={tmp}/c.txt",),
                                   files={"c.txt": PSD_OK.replace("1e8", "1e5")}),
    "psd-table-negative-c": Case("set", ("roughness.psd_file", "c.txt:3", "C = -1e-26",
                                         "(0, inf)"), "lip-install",
                                 ("roughness.psd_file={tmp}/c.txt",),
                                 files={"c.txt": PSD_OK.replace("1e-26", "-1e-26")}),
    "psd-table-one-row": Case("set", ("roughness.psd_file", "at least two rows, got 1"),
                              "cylinder", ("roughness.psd_file={tmp}/c.txt",),
                              files={"c.txt": "1e4 1e-20\n"}),
    "psd-table-missing": Case("set", ("roughness.psd_file", "none.txt", "does not exist"),
                              "cylinder", ("roughness.psd_file={tmp}/none.txt",)),
    "psd-table-binary": Case("set", ("roughness.psd_file", "c.txt", "not a text table"),
                             "cylinder", ("roughness.psd_file={tmp}/c.txt",),
                             files={"c.txt": b"\x89PNG\r\n\x1a\n\xff\xfe"}),
    "topography-ragged": Case("set", ("roughness.topography_file", "map.txt:5", "row has 15"),
                              "cylinder", ("roughness.topography_file={tmp}/map.txt",
                                           "roughness.pixel_size=1e-6"),
                              files={"map.txt": _ragged_map()}),
    "topography-missing": Case("set", ("roughness.topography_file", "none.npy",
                                       "does not exist"), "lip",
                               ("roughness.topography_file={tmp}/none.npy",
                                "roughness.pixel_size=1e-6")),
    # ------------------------------------------------------------------ Python API
    "api-values-nan": Case("api", ("material.nu", "nan", "(-1, 0.5]"),
                           call=lambda _t: _cyl(material={"nu": math.nan})),
    "api-values-misspelt": Case("api", ("'film.sped'", "did you mean 'film.speed'"),
                                call=lambda _t: _cyl(film={"sped": 0.1})),
    "api-string-for-bool": Case("api", ("lubricated", "'no'", "true or false"),
                                call=_api_cylinder_direct(lubricated="no")),
    "api-string-for-float": Case("api", ("radius", "'0.01'", "(0, inf) m"),
                                 call=_api_cylinder_direct(radius="0.01")),
    "api-bool-for-float": Case("api", ("load", "True", "(0, inf) N/m"),
                               call=_api_cylinder_direct(load=True)),
    "api-wrong-table-class": Case("api", ("material", "MaterialParams", "FilmParams("),
                                  call=_api_material_in_ball),
    "api-film-inf": Case("api", ("film.speed", "inf", "[-1000, 1000] m/s"),
                         call=_api_film(speed=math.inf)),
    "api-ball-numpy-nan": Case("api", ("radius", "nan", "(0, inf) m"),
                               call=_api_ball_direct(radius=np.float64("nan"))),
    "api-set-parameter-nested": Case("api", ("material.nu = 0.6", "(-1, 0.5]"),
                                     call=lambda _t: scenes.set_parameter(_cyl(), "material.nu",
                                                                          0.6)),
    "api-set-parameter-lip": Case("api", ("lip.interference = 0.01 m", "(0, 0.0015)"),
                                  call=lambda _t: scenes.set_parameter(
                                      scenes.make_parameters("lip-install"),
                                      "lip.interference", 0.01)),
    "api-set-parameter-deep-unknown": Case("api", ("'lip.roughness'", "lip"),
                                           call=lambda _t: scenes.set_parameter(
                                               scenes.make_parameters("lip"),
                                               "lip.roughness.h_rms", 1e-6)),
    "api-unknown-scene": Case("api", ("unknown scene 'cilinder'", "cylinder"),
                              call=lambda t: scenes.run_scene("cilinder", _cyl(), t / "o")),
    "api-sweep-nan-value": Case("api", ("film.speed", "nan", "[-1000, 1000] m/s"),
                                call=lambda t: scenes.sweep_scene(
                                    "cylinder", _cyl(), t / "o", "film.speed", [0.01, math.nan])),
    "api-sweep-unknown-parameter": Case("api", ("'material.poisson'", "nu"),
                                        call=lambda t: scenes.sweep_scene(
                                            "cylinder", _cyl(), t / "o", "material.poisson",
                                            [0.3])),
}  # fmt: skip


def _forbidden(*_a: Any, **_k: Any) -> Any:
    raise AssertionError("a bad input reached the scene's run/sweep (meshing, assembly)")


@pytest.fixture
def nothing_assembled(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every scene's run/sweep fails the test: bad input must stop before them."""
    get = scenes.get

    def guarded(name: str) -> scenes.Scene:
        return dataclasses.replace(get(name), run=_forbidden, sweep=_forbidden)

    monkeypatch.setattr(scenes, "get", guarded)


def _fill(text: str, tmp: Path) -> str:
    return text.replace("{tmp}", str(tmp))


def test_the_catalogue_is_large_and_covers_every_way_in():
    kinds = {c.via for c in CASES.values()}
    assert len(CASES) >= 40 and kinds == {"set", "toml", "cli", "api"}
    assert {c.scene for c in CASES.values() if c.scene} == set(scenes.available()) - {
        "rubber-friction"
    }


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_input(name, tmp_path, capsys, nothing_assembled):
    case = CASES[name]
    for fname, content in case.files.items():
        content = _fill(content, tmp_path) if isinstance(content, str) else content
        (tmp_path / fname).write_bytes(content.encode() if isinstance(content, str) else content)
    if case.via == "api":
        with pytest.raises(ParameterError) as info:
            case.call(tmp_path)
        message = str(info.value)
    else:
        if case.via == "set":
            argv = ["run", case.scene, "--out", str(tmp_path / "out")]
            for item in case.args:
                argv += ["--set", _fill(item, tmp_path)]
        elif case.via == "toml":
            path = tmp_path / "bad.toml"
            text = case.args[0]
            path.write_bytes(text if isinstance(text, bytes) else _fill(text, tmp_path).encode())
            argv = ["run", case.scene, "--scene-file", str(path), "--out", str(tmp_path / "out")]
        else:
            argv = [_fill(a, tmp_path) for a in case.args]
        capsys.readouterr()
        rc = main(argv)
        out, err = capsys.readouterr()
        assert rc == 2, (rc, out, err)
        assert "Traceback" not in err + out
        lines = err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith(PREFIX), err
        message = lines[0][len(PREFIX) :]
        assert not (tmp_path / "out").exists()  # nothing written either
    for part in case.expect:
        assert _fill(part, tmp_path) in message, (part, message)


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root reads any file")
def test_unreadable_scene_file(tmp_path, capsys, nothing_assembled):
    path = tmp_path / "locked.toml"
    path.write_text("[parameters]\nradius = 0.01\n")
    path.chmod(0)
    try:
        rc = main(["run", "cylinder", "--scene-file", str(path), "--out", str(tmp_path / "o")])
    finally:
        path.chmod(0o600)
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith(PREFIX) and "cannot be read" in err and "locked" in err
