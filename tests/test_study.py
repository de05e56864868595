"""The error-against-run-time study driver (dolfinx-seal study)."""

from __future__ import annotations

import json
import math

import pytest

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import column, read_csv
from dolfinx_seal.scenes import make_parameters
from dolfinx_seal.studies import convergence_study


def test_cylinder_study_writes_table_plot_and_orders(mpi_tmp_path):
    p = make_parameters("cylinder", values={"contact": {"model": "stiff"}, "lubricated": False})
    rows = convergence_study(
        "cylinder", p, mpi_tmp_path, "h_contact", [20e-6, 10e-6, 5e-6],
        ["max_contact_pressure", "contact_half_width"], reference="finest",
    )  # fmt: skip
    assert len(rows) == 3
    assert math.isnan(rows[-1]["max_contact_pressure_error"])  # the reference itself
    assert rows[0]["max_contact_pressure_error"] > rows[1]["max_contact_pressure_error"]
    COMM_WORLD.barrier()
    table = read_csv(mpi_tmp_path / "study.csv")
    assert column(table, "h_contact") == [20e-6, 10e-6, 5e-6]
    res = json.loads((mpi_tmp_path / "results.json").read_text())
    assert res["max_contact_pressure_observed_order"] > 1.5  # measured 2.2-2.8
    if COMM_WORLD.rank == 0:
        assert (mpi_tmp_path / "error_vs_time.png").stat().st_size > 1000


def test_study_needs_two_levels_and_a_reference(mpi_tmp_path):
    p = make_parameters("cylinder")
    with pytest.raises(ParameterError, match="at least two levels"):
        convergence_study("cylinder", p, mpi_tmp_path, "h_contact", [1e-5], ["mu"])
    with pytest.raises(ParameterError, match="reference"):
        convergence_study("cylinder", p, mpi_tmp_path, "h_contact", [2e-5, 1e-5], ["mu"], "exact")
