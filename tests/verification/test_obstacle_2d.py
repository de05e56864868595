"""2D obstacle VI against the exact radial solution (r* = 0.6979651482)."""

from __future__ import annotations

import math

from mpi4py import MPI

from demos.obstacle import run
from dolfinx_seal.verification.obstacle import free_boundary_radius


def test_literature_free_boundary_radius():
    assert abs(free_boundary_radius() - 0.697965148223374) < 1e-12


def test_obstacle_converges_to_exact_solution():
    res = {n: run(n, "nested") for n in (32, 128)}
    # L2 error of P1 for an obstacle problem with a C^1 (not C^2) solution:
    # O(h^2) up to the free-boundary layer; observed 4.8e-3 -> 1.9e-4 (order 2.3)
    order = math.log(res[32]["l2_error"] / res[128]["l2_error"], 4)
    assert order > 1.5, order
    assert res[128]["l2_error"] < 3e-4
    # the contact set is resolved to within two cells (h = 4/128)
    assert abs(res[128]["contact_radius"] - free_boundary_radius()) < 2 * 4 / 128
    assert res[128]["complementarity"] < 1e-8
    # nested start: Newton steps on the finest level stay small
    assert res[128]["newton_iterations_finest"] <= 4


def test_obstacle_same_on_one_and_all_ranks():
    a = run(32, "cold", MPI.COMM_WORLD)
    b = run(32, "cold", MPI.COMM_SELF)
    assert abs(a["l2_error"] - b["l2_error"]) < 1e-10
    assert abs(a["max_error"] - b["max_error"]) < 1e-10
