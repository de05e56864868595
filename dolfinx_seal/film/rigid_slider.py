"""A rigid 1D slider (textured or smooth) solved with the surface-film code.

The film of :mod:`dolfinx_seal.film.surface` on the bottom edge of a one-cell
thick strip ``[0, L] x [0, L/cells]`` (rigid: no displacement unknowns), with a
prescribed gap ``h(x)`` from :class:`dolfinx_seal.verification.slider.Gap`.
It is the mass-conservation test bed of the cavitation models: the
semi-analytic references of :mod:`dolfinx_seal.verification.slider` are
independent of this code.

The gap is interpolated into discontinuous P1 on cells whose vertices include
the gap's breakpoints (pocket edges), so a piecewise-linear textured gap is
represented exactly.
"""

from __future__ import annotations

from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.film.surface import FilmParams, FilmScales, SurfaceFilm
from dolfinx_seal.params import check_int_range
from dolfinx_seal.solvers import NonlinearSolver, SNESOptions
from dolfinx_seal.surface.state import SurfaceState

CONTACT = 1


class RigidSliderFilm:
    """The film under a rigid slider of gap ``gap`` sliding at ``op``.

    Args:
        gap: :class:`~dolfinx_seal.verification.slider.Gap` [m].
        op: :class:`~dolfinx_seal.verification.slider.SliderOperating`
            (``speed`` is the mean velocity ``U_m``; the sliding speed is ``2 U_m``).
        cells: Number of cells along the slider (breakpoints must fall on nodes).
        cavitation: ``none``, ``reynolds`` or ``jfo``.
        snes: Newton options.
    """

    def __init__(
        self,
        gap: Any,
        op: Any,
        cells: int,
        cavitation: str = "jfo",
        snes: SNESOptions | None = None,
        comm: MPI.Comm = MPI.COMM_WORLD,
    ) -> None:
        check_int_range("cells", cells, 4)
        L = gap.length
        dx = L / cells
        for b in gap.breakpoints:
            k = b / dx
            if abs(k - round(k)) > 1e-6:
                raise ParameterError(
                    f"cells = {cells}: the gap breakpoint x = {b:g} m is not on a node "
                    f"(use a multiple of {L:g} / gcd of the breakpoints)"
                )
        self.gap_def, self.op = gap, op
        mesh = dolfinx.mesh.create_rectangle(comm, [[0.0, 0.0], [L, dx]], [cells, 1])
        fdim = mesh.topology.dim - 1
        facets = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], 0.0))
        tags = dolfinx.mesh.meshtags(
            mesh, fdim, np.sort(facets).astype(np.int32), np.full(facets.size, CONTACT, np.int32)
        )
        D = dolfinx.fem.functionspace(mesh, ("DG", 1))
        self.h = dolfinx.fem.Function(D, name="gap")
        # interpolate cell by cell from the piece of the gap the cell lies on
        tdim = mesh.topology.dim
        imap = mesh.topology.index_map(tdim)
        all_cells = np.arange(imap.size_local + imap.num_ghosts, dtype=np.int32)
        centres = dolfinx.mesh.compute_midpoints(mesh, tdim, all_cells)
        pieces = gap.piece_of(centres[:, 0])
        for k in np.unique(pieces):
            cells_k = np.flatnonzero(pieces == k).astype(np.int32)
            self.h.interpolate(lambda x, k=k: gap.on_piece(x[0], int(k)), cells0=cells_k)
        h_ref = float(np.min(gap(np.linspace(0.0, L, 1001))))
        p_ref = 6.0 * op.viscosity * 2.0 * op.speed * L / h_ref**2  # Reynolds' slider scale
        self.params = FilmParams(
            viscosity=op.viscosity, speed=2.0 * op.speed, cavitation=cavitation,
            inlet_pressure=op.p_inlet, outlet_pressure=op.p_outlet,
            gap_floor=1e-6,
        )  # fmt: skip
        self.film = SurfaceFilm(
            self.params, FilmScales(pressure=p_ref, length=L, gap=h_ref, element=dx), h_rms=h_ref
        )
        e0 = ufl.as_vector([1.0, 0.0, 0.0])
        ctx = SurfaceState(
            mesh=mesh, facet_tags=tags, contact_tag=CONTACT, x=ufl.SpatialCoordinate(mesh),
            F=ufl.Identity(3), N3=ufl.as_vector([0.0, -1.0, 0.0]), weight=1.0, gap=self.h,
            vector3=lambda v: ufl.as_vector([v[0], v[1], 0.0]),
            e_n=ufl.as_vector([0.0, 1.0, 0.0]), sliding=e0,
        )  # fmt: skip
        self.film.attach(ctx)
        self.mesh = mesh
        blocks = self.film.blocks
        opts = snes or SNESOptions(
            max_it=200, snes_type="vinewtonssls" if cavitation == "jfo" else "vinewtonrsls"
        )
        lower = [b[2] for b in blocks]
        upper = [b[3] for b in blocks]
        bounded = any(v is not None for v in lower + upper)
        if len(blocks) == 1:
            self.solver = NonlinearSolver(
                blocks[0][0], blocks[0][1], self.film.bcs, options=opts, name="slider",
                lower=lower[0] if bounded else None, upper=upper[0] if bounded else None,
            )  # fmt: skip
        else:
            self.solver = NonlinearSolver(
                [b[0] for b in blocks], [b[1] for b in blocks], self.film.bcs, options=opts,
                name="slider", lower=lower, upper=upper,
            )  # fmt: skip

    def solve(self) -> int:
        """Solve; returns the Newton steps."""
        return self.solver.solve().newton_iterations

    def quantities(self) -> dict[str, float]:
        """Load [N/m], fluxes [m^2/s], rupture and reformation positions [m], mass balance."""
        v = self.film.film_values()
        x, p, th = v["X"][:, 0], v["p"], v["theta"]
        comm = self.mesh.comm
        load = comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form(self.film.p * self.film.ds)), op=MPI.SUM
        )
        # cell fluxes of the discrete scheme: -k p' + U_m h theta_upwind (1-point rule)
        xm = 0.5 * (x[1:] + x[:-1])
        piece = self.gap_def.piece_of(xm)
        ha = np.array(
            [self.gap_def.on_piece(a, int(k)) for a, k in zip(x[:-1], piece, strict=True)]
        )
        hb = np.array([self.gap_def.on_piece(b, int(k)) for b, k in zip(x[1:], piece, strict=True)])
        hm = 0.5 * (ha + hb)
        U_m = self.op.speed
        # exact cell mean of h^3 for a linear h
        k = (ha + hb) * (ha**2 + hb**2) / 4.0 / (12.0 * self.op.viscosity)
        q = -k * np.diff(p) / np.diff(x) + U_m * hm * th[:-1]
        out = {
            "load": float(load),
            "flux_mean": float(q.mean()),
            "flux_spread": float((q.max() - q.min()) / abs(q.mean())),
            "p_max": float(p.max()),
            "mass_balance_error": self.film.mass_balance_error(),
        }
        if self.params.cavitation == "jfo":
            cav = th < 1.0 - 1e-8
        else:
            cav = p <= 0.0
        idx = np.flatnonzero(cav[1:-1]) + 1
        if idx.size:
            out["x_rupture"] = float(x[idx[0] - 1])
            out["x_reformation"] = float(x[idx[-1] + 1])
        out["theta_min"] = float(th.min())
        return out


__all__ = ["RigidSliderFilm"]
