"""Parameters, results contract and CLI plumbing (no DOLFINx)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import pytest

from dolfinx_seal import params
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.output import SweepWriter, read_csv, write_results
from dolfinx_seal.scenes import parse_values


@dataclass
class Inner:
    h_rms: float = 1e-6

    def __post_init__(self) -> None:
        params.check_positive("h_rms", self.h_rms, "m")


@dataclass
class Outer:
    speed: float = 1.0
    cells: int = 10
    model: str = "reynolds"
    rough: Inner = field(default_factory=Inner)

    def __post_init__(self) -> None:
        params.check_choice("model", self.model, ("reynolds", "jfo"))


def test_check_range_names_parameter_and_range():
    with pytest.raises(ParameterError, match=r"nu = 0.6 is outside the allowed range \(-1, 0.5\)"):
        params.check_range("nu", 0.6, -1, 0.5, lo_open=True, hi_open=True)
    assert params.check_range("nu", 0.3, -1, 0.5, lo_open=True, hi_open=True) == 0.3
    with pytest.raises(ParameterError, match="E must be finite"):
        params.check_positive("E", math.nan)


def test_from_mapping_nested_and_unknown_keys():
    o = params.from_mapping(Outer, {"speed": "2.5", "cells": "4", "rough": {"h_rms": "3e-6"}})
    assert o.speed == 2.5 and o.cells == 4 and o.rough.h_rms == 3e-6
    with pytest.raises(ParameterError, match=r"unknown parameter 'rough\.hrms'"):
        params.from_mapping(Outer, {"rough": {"hrms": 1}})
    with pytest.raises(ParameterError, match="cells must be an integer"):
        params.from_mapping(Outer, {"cells": "2.5"})
    with pytest.raises(ParameterError, match="h_rms"):
        params.from_mapping(Outer, params.parse_overrides(["rough.h_rms=-1"]))


def test_overrides_merge_over_file_values():
    data = params.merge(
        {"speed": 1.0, "rough": {"h_rms": 1e-6}}, params.parse_overrides(["rough.h_rms=2e-6"])
    )
    o = params.from_mapping(Outer, data)
    assert o.rough.h_rms == 2e-6 and o.speed == 1.0
    assert params.to_dict(o) == {
        "speed": 1.0,
        "cells": 10,
        "model": "reynolds",
        "rough": {"h_rms": 2e-6},
    }


def test_a_nested_table_keeps_the_scene_defaults_it_does_not_name():
    # the ball's film default is FilmParams(speed=0.01), not FilmParams()'s speed 0
    from dolfinx_seal.scenes import make_parameters

    p = make_parameters("ball", overrides=["film.viscosity=0.05"])
    assert p.film.viscosity == 0.05 and p.film.speed == 0.01
    p = make_parameters("ball", values={"film": {"asperity_shear": 0.0}})
    assert p.film.asperity_shear == 0.0 and p.film.speed == 0.01


def test_parse_values():
    assert parse_values("1,2,3") == [1.0, 2.0, 3.0]
    v = parse_values("1e-3:1e1:5:log")
    assert len(v) == 5 and v[0] == pytest.approx(1e-3) and v[-1] == pytest.approx(10.0)
    assert v[2] == pytest.approx(0.1)
    with pytest.raises(ParameterError):
        parse_values("0:1:3:log")


def test_results_refuse_nan(mpi_tmp_path):
    from mpi4py import MPI

    # only rank 0 writes (and validates); use a serial communicator per rank
    with pytest.raises(ValueError, match="non-finite"):
        write_results(
            mpi_tmp_path / f"a{MPI.COMM_WORLD.rank}",
            {"scene": "x", "parameters": {}, "mu": math.nan},
            comm=MPI.COMM_SELF,
        )


def test_sweep_writer_appends_rows(mpi_tmp_path):
    w = SweepWriter(mpi_tmp_path / "s")
    w.append({"speed": 1.0, "mu": 0.1})
    w.append({"speed": 2.0, "mu": 0.2})
    from dolfinx_seal.mpi import COMM_WORLD

    COMM_WORLD.barrier()
    rows = read_csv(mpi_tmp_path / "s" / "sweep.csv")
    assert [float(r["mu"]) for r in rows] == [0.1, 0.2]
    p = write_results(mpi_tmp_path / "s", {"scene": "x", "parameters": {"a": 1}, "mu": 0.2})
    data = json.loads(p.read_text())
    assert data["mu"] == 0.2 and "versions" in data


def test_a_row_with_a_new_key_extends_the_header_and_keeps_every_value(mpi_tmp_path):
    """A point that reports a key the first did not (e.g. a flag raised at one speed)
    must not stop the sweep (it raised on rank 0 alone before, and lost the point):
    the header grows, earlier rows get an empty cell."""
    from dolfinx_seal.mpi import COMM_WORLD

    w = SweepWriter(mpi_tmp_path / "n")
    w.append({"speed": 1.0, "mu": 0.1})
    w.append({"speed": 2.0, "mu": 0.2, "flag": True})
    w.append({"speed": 3.0, "mu": 0.3})
    COMM_WORLD.barrier()
    rows = read_csv(mpi_tmp_path / "n" / "sweep.csv")
    assert [float(r["speed"]) for r in rows] == [1.0, 2.0, 3.0]
    assert [float(r["mu"]) for r in rows] == [0.1, 0.2, 0.3]
    assert [r["flag"] for r in rows] == ["", "True", ""]
