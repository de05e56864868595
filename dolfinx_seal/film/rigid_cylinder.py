"""Rigid cylinder on a plane: the 1D dimensionless Reynolds problem with cavitation.

The bulk is off (rigid), so the only unknown is the dimensionless pressure
``P(X)`` on ``[-x_in, x_out]`` with gap ``H = 1 + X^2`` (see
:mod:`dolfinx_seal.verification.martin` for the scaling and the independent
reference).  Cavitation models: ``"reynolds"`` (the VI ``P >= 0``) or ``"none"``
(full Sommerfeld: negative pressures allowed).

It is the smallest free-boundary problem of the project and the test bed of
the solver strategies (cold start, nested meshes, penalty continuation).

Discrete mass conservation: with P1 elements and exact quadrature the
Galerkin equation at an inactive node says that the cell-averaged flux
``q_e = (1/|e|) int_e (H - H^3 P')`` is the same in the two cells around it,
so in the full-film zone all ``q_e`` agree to solver tolerance; their spread
is reported as ``mass_balance_error``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.film.reynolds import reynolds_residual
from dolfinx_seal.params import check_choice, check_int_range, check_positive
from dolfinx_seal.solvers.snes import NonlinearSolver, SNESOptions


@dataclass
class RigidCylinderParameters:
    """Parameters of the dimensionless rigid-cylinder film.

    Attributes:
        x_in: Inlet distance upstream, in units of ``sqrt(2 R h0)`` [-].
        x_out: Outlet distance downstream [-].
        cells: Number of (uniform) cells.
        cavitation: ``"reynolds"`` (P >= 0 as a VI) or ``"none"``.
    """

    x_in: float = 10.0
    x_out: float = 2.0
    cells: int = 1000
    cavitation: str = "reynolds"
    snes: SNESOptions = field(default_factory=SNESOptions)

    def __post_init__(self) -> None:
        check_positive("x_in", self.x_in)
        check_positive("x_out", self.x_out)
        check_int_range("cells", self.cells, 4)
        check_choice("cavitation", self.cavitation, ("reynolds", "none"))


class RigidCylinderFilm:
    """The FEM problem (P1 pressure on an interval mesh) and its solver."""

    def __init__(self, params: RigidCylinderParameters, comm: MPI.Comm = MPI.COMM_WORLD) -> None:
        self.params = params
        self.mesh = dolfinx.mesh.create_interval(comm, params.cells, [-params.x_in, params.x_out])
        self.V = dolfinx.fem.functionspace(self.mesh, ("Lagrange", 1))
        self.p = dolfinx.fem.Function(self.V, name="P")
        q = ufl.TestFunction(self.V)
        X = ufl.SpatialCoordinate(self.mesh)[0]
        self.H = 1.0 + X**2
        # degree 7 integrates H^3 P' q' (degree 6) and H q' exactly
        self.dx = ufl.Measure("dx", domain=self.mesh, metadata={"quadrature_degree": 7})
        residual = reynolds_residual(self.p, q, self.H**3, ufl.as_vector([self.H]), self.dx)
        fdim = 0
        facets = dolfinx.mesh.locate_entities_boundary(
            self.mesh,
            fdim,
            lambda x: np.isclose(x[0], -params.x_in) | np.isclose(x[0], params.x_out),
        )
        dofs = dolfinx.fem.locate_dofs_topological(self.V, fdim, facets)
        bc = dolfinx.fem.dirichletbc(0.0, dofs, self.V)
        lower = 0.0 if params.cavitation == "reynolds" else None
        self.solver = NonlinearSolver(
            residual, self.p, [bc], lower=lower, options=params.snes, name="rigid-cylinder Reynolds"
        )
        self._flux_form = dolfinx.fem.form(
            (self.H - self.H**3 * self.p.dx(0))
            * ufl.TestFunction(dolfinx.fem.functionspace(self.mesh, ("DG", 0)))
            * self.dx
        )

    def quantities(self) -> dict[str, Any]:
        """Cavitation point, load, peak pressure and discrete mass balance.

        ``x_cavitation`` is taken from the flux (``X_c = sqrt(q - 1)``, since
        ``P' = 0`` at the Reynolds exit), which converges faster than the node
        position of the free boundary (``x_cavitation_node``, first zero node
        after the peak: O(h)).
        """
        comm = self.mesh.comm
        # cell fluxes (DG0 integrals / cell length)
        flux_vec = dolfinx.fem.assemble_vector(self._flux_form)
        V0 = dolfinx.fem.functionspace(self.mesh, ("DG", 0))
        n_own = V0.dofmap.index_map.size_local
        h = (self.params.x_in + self.params.x_out) / self.params.cells
        q_cell = flux_vec.array[:n_own] / h
        # P at the cell ends, to select full-film cells (both nodes pressurised)
        pv = self.p.x.array
        n_dof_own = self.V.dofmap.index_map.size_local
        xd = self.V.tabulate_dof_coordinates()[:, 0]
        pmax = comm.allreduce(float(pv[:n_dof_own].max(initial=-np.inf)), op=MPI.MAX)
        tol = 1e-10 * max(pmax, 1e-300)
        c2v = self.V.dofmap.list[:n_own]
        full = np.all(pv[c2v] > tol, axis=1)
        qs = q_cell[full]
        qmin = comm.allreduce(float(qs.min(initial=np.inf)), op=MPI.MIN)
        qmaxv = comm.allreduce(float(qs.max(initial=-np.inf)), op=MPI.MAX)
        qsum = comm.allreduce(float(qs.sum()), op=MPI.SUM)
        qn = comm.allreduce(int(qs.size), op=MPI.SUM)
        q_mean = qsum / max(qn, 1)
        load = comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form(self.p * self.dx)), op=MPI.SUM
        )
        # first zero node after the peak (owned dofs; global min of positions)
        own = slice(0, n_dof_own)
        x_peak = _argmax_x(comm, pv[own], xd[own])
        zero_after = xd[own][(xd[own] > x_peak) & (pv[own] <= tol)]
        x_node = comm.allreduce(float(zero_after.min(initial=np.inf)), op=MPI.MIN)
        out = {
            "load": float(load),
            "p_max": pmax,
            "x_p_max": float(x_peak),
            "flux": q_mean,
            "x_cavitation": float(np.sqrt(max(q_mean - 1.0, 0.0))),
            "x_cavitation_node": x_node,
            "mass_balance_error": (qmaxv - qmin) / abs(q_mean) if qn else 0.0,
        }
        return out


def _argmax_x(comm: MPI.Comm, values: np.ndarray, coords: np.ndarray) -> float:
    """Coordinate of the global maximum of ``values`` (ties: smallest coordinate)."""
    if values.size:
        i = int(np.argmax(values))
        local = (float(values[i]), -float(coords[i]))
    else:
        local = (-np.inf, 0.0)
    allv = comm.allgather(local)
    best = max(allv)
    return -best[1]
