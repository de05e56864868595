"""A rigid rough band solved with the surface-film code (the lip sector's film alone).

The JFO film of :mod:`dolfinx_seal.film.surface` on the bottom face of a one-cell
thick box ``[0, L] x [0, W] x [0, dz]`` (rigid: no displacement unknowns),
periodic along the sliding direction ``x`` (dolfinx_mpc, as the lip sector's
film), the sealed pressures on ``y = 0`` and ``y = W``, with the gap of a
:class:`~dolfinx_seal.verification.rough_band.BandGap` as a UFL expression of
the coordinates.  The band is a Delaunay triangulation of a jittered
triangular lattice turned to the sliding direction, so that its edges run in
every direction as on the lip sector's gmsh band.

It is the test bed of the film's transport schemes (``film.upwind``,
``film.discrete_upwinding``) against the finite-volume reference of
:mod:`dolfinx_seal.verification.rough_band`, which is independent of this code.
"""

from __future__ import annotations

from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.errors import SolverError
from dolfinx_seal.film.pseudo_time import pseudo_transient_solve
from dolfinx_seal.film.surface import FilmParams, FilmScales, SurfaceFilm
from dolfinx_seal.film.upwinding import attach_discrete_upwinding, release_discrete_upwinding
from dolfinx_seal.params import check_range
from dolfinx_seal.solvers import SNESOptions
from dolfinx_seal.solvers.periodic import TranslationalPeriodicity
from dolfinx_seal.surface.state import SurfaceState

CONTACT, MASTER_FACE, SLAVE_FACE = 1, 2, 3

#: Newton options of the film solve: the semismooth Newton ends on its own
#: convergence test (an exact step on a settled active set).
BAND_SNES = SNESOptions(snes_type="semismooth", rtol=1e-20, atol=1e-300, dtol=1e300, max_it=150)


def _lattice_points(L: float, W: float, size: float, angle: float, jitter: float,
                    rng: np.random.Generator) -> np.ndarray:  # fmt: skip
    """Nodes of an irregular band triangulation: a triangular lattice of spacing
    ``size`` turned by ``angle`` and jittered, inside the band, and equally spaced
    nodes on its edges (the same ``y`` on ``x = 0`` and ``x = L``)."""
    ny_e = max(2, round(W / size))
    nx_e = max(4, round(L / size))
    ys = np.linspace(0.0, W, ny_e + 1)
    xs = np.linspace(0.0, L, nx_e + 1)[1:-1]
    edge = [np.column_stack([np.zeros_like(ys), ys]), np.column_stack([np.full_like(ys, L), ys]),
            np.column_stack([xs, np.zeros_like(xs)]), np.column_stack([xs, np.full_like(xs, W)])]  # fmt: skip
    r = 2.0 * max(L, W)
    k = np.arange(-int(r / size) - 1, int(r / size) + 2)
    a, b = np.meshgrid(k, k)
    lat = np.column_stack([(a + 0.5 * (b % 2)).ravel() * size, b.ravel() * size * np.sqrt(0.75)])
    c, s = np.cos(angle), np.sin(angle)
    lat = lat @ np.array([[c, s], [-s, c]]) + [0.5 * L, 0.5 * W]
    lat += rng.uniform(-jitter, jitter, lat.shape) * size
    margin = 0.5 * size
    keep = (lat[:, 0] > margin) & (lat[:, 0] < L - margin)
    keep &= (lat[:, 1] > margin) & (lat[:, 1] < W - margin)
    return np.concatenate([*edge, lat[keep]])


def _band_mesh(L: float, W: float, size: float, angle: float, jitter: float, seed: int,
               comm: MPI.Comm) -> tuple[dolfinx.mesh.Mesh, dolfinx.mesh.MeshTags]:  # fmt: skip
    """One layer of tetrahedra over a Delaunay triangulation of the band: each
    prism over a triangle split into three tetrahedra by its vertices' global
    order, which makes neighbouring prisms' splits conform."""
    import basix.ufl
    from scipy.spatial import Delaunay

    if comm.rank == 0:
        pts = _lattice_points(L, W, size, angle, jitter, np.random.default_rng(seed))
        tri = np.sort(Delaunay(pts).simplices, axis=1)
        n = pts.shape[0]
        x = np.vstack([np.column_stack([pts, np.zeros(n)]),
                       np.column_stack([pts, np.full(n, size)])])  # fmt: skip
        a, b, c = tri.T
        cells = np.vstack([np.column_stack([a, b, c, c + n]),
                           np.column_stack([a, b, b + n, c + n]),
                           np.column_stack([a, a + n, b + n, c + n])]).astype(np.int64)  # fmt: skip
    else:
        x, cells = np.zeros((0, 3)), np.zeros((0, 4), np.int64)
    domain = ufl.Mesh(basix.ufl.element("Lagrange", "tetrahedron", 1, shape=(3,)))
    mesh = dolfinx.mesh.create_mesh(comm, cells, x, domain)
    fdim = mesh.topology.dim - 1
    found = [
        (CONTACT, lambda p: np.isclose(p[2], 0.0)),
        (MASTER_FACE, lambda p: np.isclose(p[0], 0.0)),
        (SLAVE_FACE, lambda p: np.isclose(p[0], L)),
    ]
    facets, values = [], []
    for tag, where in found:
        f = dolfinx.mesh.locate_entities_boundary(mesh, fdim, where)
        facets.append(f)
        values.append(np.full(f.size, tag, np.int32))
    facets_all = np.concatenate(facets)
    order = np.argsort(facets_all)
    tags = dolfinx.mesh.meshtags(
        mesh, fdim, facets_all[order].astype(np.int32), np.concatenate(values)[order]
    )
    return mesh, tags


class RigidBandFilm:
    """The JFO film of a rigid rough band sliding at ``op``.

    Args:
        gap: :class:`~dolfinx_seal.verification.rough_band.BandGap` [m].
        op: :class:`~dolfinx_seal.verification.rough_band.BandOperating`.
        size: Element size [m] (the spacing of the triangular lattice the
            band's nodes come from).
        angle: Angle [rad] of the lattice to the sliding direction.
        jitter: Largest node offset, in elements, in [0, 0.3].
        upwind: ``film.upwind`` (``fraction``, ``film``, ``none``).
        discrete_upwinding: ``film.discrete_upwinding``.
        release_upwinding: ``film.release_upwinding``.
        seed: Seed of the jitter.
    """

    def __init__(
        self,
        gap: Any,
        op: Any,
        size: float,
        *,
        angle: float = 0.3,
        jitter: float = 0.25,
        upwind: str = "film",
        discrete_upwinding: bool = True,
        release_upwinding: bool = False,
        seed: int = 0,
        comm: MPI.Comm = MPI.COMM_WORLD,
    ) -> None:
        check_range("size", size, 0.0, 0.25 * min(gap.length, gap.width), lo_open=True,
                    unit="m")  # fmt: skip
        check_range("jitter", jitter, 0.0, 0.3)
        self.gap_def, self.op = gap, op
        L, W = gap.length, gap.width
        self.mesh, tags = _band_mesh(L, W, size, angle, jitter, seed, comm)
        self.params = FilmParams(
            viscosity=op.viscosity, speed=op.speed, cavitation="jfo",
            inlet_pressure=op.p_oil, outlet_pressure=op.p_air, gap_floor=1e-6,
            upwind=upwind, discrete_upwinding=discrete_upwinding,
            release_upwinding=release_upwinding,
        )  # fmt: skip
        p_ref = max(op.p_oil, op.p_air, 6.0 * op.viscosity * abs(op.speed) * L / gap.h_centre**2)
        dx = size
        self.film = SurfaceFilm(
            self.params, FilmScales(pressure=p_ref, length=W, gap=gap.h_centre, element=dx),
            h_rms=gap.h_centre, no_flux_tags=(MASTER_FACE, SLAVE_FACE),
            allow_discrete_upwinding=True,
        )  # fmt: skip
        x = ufl.SpatialCoordinate(self.mesh)
        ctx = SurfaceState(
            mesh=self.mesh, facet_tags=tags, contact_tag=CONTACT, x=x, F=ufl.Identity(3),
            N3=ufl.as_vector([0.0, 0.0, -1.0]), weight=1.0, gap=gap.ufl(x),
            vector3=lambda v: v, e_n=ufl.as_vector([0.0, 0.0, 1.0]),
            sliding=ufl.as_vector([1.0, 0.0, 0.0]), edge_axis=(0.0, 1.0, 0.0),
            periodic=TranslationalPeriodicity(L, tolerance=1e-6 * dx),
        )  # fmt: skip
        self.film.attach(ctx)
        self.solver = self.film.make_solver(BAND_SNES, name="rough band film")
        self.path = ""
        #: weight of the discrete upwinding term in the film solved (0: released)
        self.upwinding_weight = 1.0 if discrete_upwinding else 0.0

    def solve(self) -> int:
        """Solve from a full film at rest (``theta = 1``, ``p = 0``): a semismooth
        Newton, and if that fails, pseudo-time steps from the same start
        (:func:`~dolfinx_seal.film.pseudo_time.pseudo_transient_solve`); with
        ``release_upwinding``, then the discrete upwinding's weight walked to 0.
        Returns the Newton steps; :attr:`path` says which solved it."""
        its = self._solve()
        if self.params.release_upwinding:
            film = self.film
            n, self.upwinding_weight = release_discrete_upwinding(
                self.solver, [film.P, film.theta_fn], "rough band: release"
            )
            its += n
            self.path += ", released" if self.upwinding_weight == 0.0 else " (partly)"
        return its

    def _solve(self) -> int:
        film = self.film
        film.P.x.array[:] = 0.0
        film.theta_fn.x.array[:] = 1.0
        if self.params.discrete_upwinding:  # the gap is fixed: one term per solve
            attach_discrete_upwinding(self.solver)
        try:
            self.path = "semismooth"
            return self.solver.solve(where="rough band: semismooth").newton_iterations
        except SolverError as e:
            its = e.history.newton_iterations
        film.P.x.array[:] = 0.0
        film.theta_fn.x.array[:] = 1.0
        self.path = "pseudo-time"
        return its + pseudo_transient_solve(film, self.solver, "rough band: pseudo-time")

    def quantities(self) -> dict[str, float]:
        """Leakage and inflow [m^3/s per period] (out through ``y = W``, in through
        ``y = 0``), load [N per period], cavitated area fraction, smallest film
        fraction and pressure [Pa] of the free nodes."""
        film, comm = self.film, self.mesh.comm
        q_oil, q_air = film.edge_flows()

        def integral(expr: Any) -> float:
            value = dolfinx.fem.assemble_scalar(dolfinx.fem.form(expr * film.ds))
            return comm.allreduce(value, op=MPI.SUM)

        cavitated = ufl.conditional(ufl.lt(film.theta_fn, 1.0 - 1e-9), 1.0, 0.0)
        area = self.gap_def.length * self.gap_def.width
        mine = film.film_dofs_local
        p = film.scales.pressure * film.P.x.array[mine]
        theta = film.theta_fn.x.array[mine]
        return {
            "leakage": q_air,
            "inflow": -q_oil,
            "load": integral(film.p),
            "cavitation_fraction": integral(cavitated) / area,
            "theta_min": comm.allreduce(float(theta.min(initial=1.0)), op=MPI.MIN),
            "p_min": comm.allreduce(float(p.min(initial=0.0)), op=MPI.MIN),
        }


__all__ = ["RigidBandFilm"]
