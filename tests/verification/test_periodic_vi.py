"""The assembly seam: a periodic variational inequality solved with the dolfinx_mpc
assembly equals the same problem on a long non-periodic strip with the plain assembly.

Obstacle problem on the periodic cell ``(0, 1) x (0, 1)`` (period 1 in ``x``):
``-div(grad u) = f``, ``u = 0`` at ``y = 0, 1``, ``u >= psi``, with ``f`` and ``psi``
periodic in ``x`` and without mirror symmetry (so a Neumann cell would not do).
The periodic solution is also the solution, on ``0 <= x <= 1``, of the problem on
the long strip ``(-K, 1 + K) x (0, 1)`` with natural conditions at the far ends,
up to the end effect, which decays like ``exp(-pi d)`` at a distance ``d`` from the
ends (the slowest mode ``sin(pi y)`` of the Laplacian with ``u = 0`` at ``y = 0, 1``;
measured below).  Both meshes have the same vertices on ``[0, 1]``, so the two
discrete solutions agree there to solver tolerance plus ``exp(-pi K) max|u|``.
"""

from __future__ import annotations

import dolfinx
import numpy as np
import pytest
import ufl
from mpi4py import MPI

from dolfinx_seal.solvers import MPCAssembly, NonlinearSolver, SNESOptions

dolfinx_mpc = pytest.importorskip("dolfinx_mpc")

#: solver options of both solves: exact VI to round-off
OPTS = dict(rtol=1e-12, atol=1e-13, max_it=60)


def _load(x):
    """The load f (UFL), periodic in x with period 1, no mirror symmetry."""
    return -12.0 + 4.0 * ufl.sin(2 * np.pi * x[0] + 0.7)


def _bump(x, c, w):
    """Periodic bump around x = c (period 1), height 1, width about w."""
    return np.exp((np.cos(2 * np.pi * (x - c)) - 1.0) / w**2)


def _psi(x):
    """Obstacle: two isolated patches, one astride the periodic seam x = 0 = 1."""
    s = np.sin(np.pi * x[1]) ** 4
    return -1.0 + s * (0.9 * _bump(x[0], 0.35, 0.6) + 0.8 * _bump(x[0], 0.97, 0.5))


def _strip(comm, x0, x1, n, degree):
    nx = round((x1 - x0) * n)
    mesh = dolfinx.mesh.create_rectangle(
        comm, [[x0, 0.0], [x1, 1.0]], [nx, n], dolfinx.mesh.CellType.quadrilateral
    )
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree))
    dofs = dolfinx.fem.locate_dofs_geometrical(
        V, lambda x: np.isclose(x[1], 0.0) | np.isclose(x[1], 1.0)
    )
    bc = dolfinx.fem.dirichletbc(0.0, dofs, V)
    return V, bc


def _obstacle(V, bc, u, assembly=None, snes_type="vinewtonrsls"):
    mesh = V.mesh
    v = ufl.TestFunction(V)
    f = _load(ufl.SpatialCoordinate(mesh))
    F = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx - f * v * ufl.dx
    lower = dolfinx.fem.Function(u.function_space)
    lower.interpolate(_psi)
    return NonlinearSolver(
        F,
        u,
        [bc],
        lower=lower,
        options=SNESOptions(snes_type=snes_type, **OPTS),
        assembly=assembly,
        name="obstacle",
    )


def _periodic(comm, n, degree, snes_type="vinewtonrsls"):
    V, bc = _strip(comm, 0.0, 1.0, n, degree)
    mpc = dolfinx_mpc.MultiPointConstraint(V)
    mpc.create_periodic_constraint_geometrical(
        V,
        lambda x: np.isclose(x[0], 1.0),
        lambda x: np.vstack((x[0] - 1.0, x[1], x[2])),
        [bc],
    )
    mpc.finalize()
    u = dolfinx.fem.Function(mpc.function_space)
    solver = _obstacle(V, bc, u, assembly=MPCAssembly(mpc), snes_type=snes_type)
    return solver, u, mpc


def _long(comm, n, degree, K):
    V, bc = _strip(comm, -K, 1.0 + K, n, degree)
    u = dolfinx.fem.Function(V)
    return _obstacle(V, bc, u), u


def _nodal(u, lo=0.0, hi=1.0):
    """{(x, y) rounded: value} of the dofs with lo <= x <= hi, gathered on every rank."""
    V = u.function_space
    n = V.dofmap.index_map.size_local
    X = V.tabulate_dof_coordinates()[:n, :2]
    keep = (X[:, 0] >= lo - 1e-12) & (X[:, 0] <= hi + 1e-12)
    parts = V.mesh.comm.allgather((X[keep], u.x.array[:n][keep].copy()))
    out = {}
    for xs, vs in parts:
        for p, val in zip(np.round(xs, 9), vs, strict=True):
            out[(p[0] + 0.0, p[1] + 0.0)] = val
    return out


def _max_diff(a, b):
    assert a.keys() == b.keys()
    return max(abs(a[k] - b[k]) for k in a)


def _active_fraction(u):
    """Fraction of the dofs off the Dirichlet rows that lie on the obstacle (bound active)."""
    V = u.function_space
    n = V.dofmap.index_map.size_local
    psi = dolfinx.fem.Function(V)
    psi.interpolate(_psi)
    X = V.tabulate_dof_coordinates()[:n]
    interior = (X[:, 1] > 1e-9) & (X[:, 1] < 1 - 1e-9)
    on = np.abs(u.x.array[:n] - psi.x.array[:n]) < 1e-10
    comm = V.mesh.comm
    return comm.allreduce(int(np.sum(on & interior))) / comm.allreduce(int(np.sum(interior)))


def _compare(n, degree, K, snes_type="vinewtonrsls", penalty=False):
    comm = MPI.COMM_WORLD
    sp, up, _ = _periodic(comm, n, degree, snes_type)
    hp = sp.solve_penalty()[-1] if penalty else sp.solve()
    sl, ul = _long(comm, n, degree, K)
    hl = sl.solve()
    assert hp.reason > 0 and hl.reason > 0
    assert hp.complementarity < 1e-10 and hl.complementarity < 1e-10
    a, b = _nodal(up), _nodal(ul)
    frac = _active_fraction(up)
    # the slaves (x = 1) equal their masters (x = 0) after backsubstitution
    per = max(abs(a[(1.0, y)] - a[(0.0, y)]) for (x, y) in a if x == 0.0)
    # the slaves are not frozen by the VI: they follow their masters onto the obstacle
    on_slave = sum(1 for (x, y) in a if x == 1.0 and abs(a[(x, y)] - _psi_at(1.0, y)) < 1e-10)
    on_master = sum(1 for (x, y) in a if x == 0.0 and abs(a[(x, y)] - _psi_at(0.0, y)) < 1e-10)
    umax = max(abs(v) for v in a.values())
    out = dict(diff=_max_diff(a, b), per=per, frac=frac, umax=umax, its=hp.newton_iterations)
    out.update(on_slave=on_slave, on_master=on_master)
    for s in (sp, sl):
        s.destroy()
    return out


def _psi_at(x, y):
    return float(_psi(np.array([[x], [y], [0.0]]))[0])


def _check(r):
    assert 0.03 < r["frac"] < 0.5, r  # the bound is active on part of the cell
    # contact astride the seam: the slaves (x = 1) lie on the obstacle where their
    # masters (x = 0) do, i.e. the VI neither freezes nor releases them by itself
    assert r["on_master"] >= 2 and r["on_slave"] == r["on_master"], r
    assert r["per"] <= 1e-13 * r["umax"], r  # backsubstitution: slave = master
    # Solver tolerance: both VIs end with a Newton step on the final active set (a
    # linear solve) after rtol = 1e-12 on the residual; the nodal error bound is
    # cond(J) rtol max|u| ~ 1e2 * 1e-12 (Q1/Q2, n <= 32).  The end effect of the long
    # strip is far below: measured (Q1, n = 16) 8.7e-5, 1.1e-7, 1.9e-13 max|u| at
    # K = 1, 2, 4, a factor >= 700 per unit length, so < 1e-17 at K = 6.
    # Measured difference: 6e-16 (Q1, n = 16), 4e-15 (Q2, n = 32).
    assert r["diff"] <= 1e-10 * r["umax"], r


@pytest.mark.parametrize(
    ("snes_type", "penalty"),
    [("vinewtonrsls", False), ("vinewtonssls", False), ("vinewtonrsls", True)],
    ids=["rsls", "ssls", "penalty_then_rsls"],
)
def test_periodic_obstacle_mpc_equals_long_strip(snes_type, penalty):
    """Reduced-space and semi-smooth VI (the JFO film uses the latter), and the
    penalty warm start (lumped mass through the MPC assembly) before the exact VI."""
    _check(_compare(16, 1, K=6, snes_type=snes_type, penalty=penalty))


@pytest.mark.slow
def test_periodic_obstacle_mpc_equals_long_strip_p2():
    _check(_compare(32, 2, K=6))


def test_periodicity_matters():
    """The same cell with natural (Neumann) ends, plain assembly, differs by O(1):
    the comparison above can fail."""
    comm = MPI.COMM_WORLD
    V, bc = _strip(comm, 0.0, 1.0, 16, 1)
    un = dolfinx.fem.Function(V)
    sn = _obstacle(V, bc, un)
    sn.solve()
    sp, up, _ = _periodic(comm, 16, 1)
    sp.solve()
    a, b = _nodal(up), _nodal(un)
    assert _max_diff(a, b) > 1e-3 * max(abs(v) for v in a.values())
    sn.destroy()
    sp.destroy()


# ------------------------------------------------------- blocked, force control
#: prescribed mean of u over the cell (force control: the mean load is unknown)
U_MEAN = -0.4


def _blocked(V, bc, u, cell_marker, assembly=None):
    """Blocked VI: u (bounded) and a scifem real unknown lam, the mean load, such that
    the mean of u over the cell (weighted by ``cell_marker``) is ``U_MEAN``."""
    import scifem

    mesh = V.mesh
    R = scifem.create_real_functionspace(mesh)
    lam = dolfinx.fem.Function(R)
    v, mu = ufl.TestFunction(V), ufl.TestFunction(R)
    x = ufl.SpatialCoordinate(mesh)
    f = lam + 4.0 * ufl.sin(2 * np.pi * x[0] + 0.7)
    F0 = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx - f * v * ufl.dx
    F1 = cell_marker * (u - U_MEAN) * mu * ufl.dx
    lower = dolfinx.fem.Function(u.function_space)
    lower.interpolate(_psi)
    lam.x.array[:] = -10.0
    solver = NonlinearSolver(
        [F0, F1], [u, lam], [bc], lower=[lower, None], options=SNESOptions(**OPTS),
        assembly=assembly, name="obstacle, force control",
    )  # fmt: skip
    return solver, lam


def _real_value(lam):
    comm = lam.function_space.mesh.comm
    return comm.allreduce(float(lam.x.array[0]) if lam.x.array.size else -np.inf, op=MPI.MAX)


def test_blocked_periodic_obstacle_with_real_unknown():
    """One constraint per block (None for the real unknown): the MPC blocks are
    assembled separately and copied into one AIJ matrix; same answer as the long
    strip with the plain block assembly, whose mean is taken over the middle cell."""
    comm = MPI.COMM_WORLD
    V, bc = _strip(comm, 0.0, 1.0, 16, 1)
    mpc = dolfinx_mpc.MultiPointConstraint(V)
    mpc.create_periodic_constraint_geometrical(
        V, lambda x: np.isclose(x[0], 1.0), lambda x: np.vstack((x[0] - 1.0, x[1], x[2])), [bc]
    )
    mpc.finalize()
    up = dolfinx.fem.Function(mpc.function_space)
    sp, lp = _blocked(V, bc, up, 1.0, assembly=MPCAssembly([mpc, None]))
    hp = sp.solve()
    K = 6
    Vl, bcl = _strip(comm, -K, 1.0 + K, 16, 1)
    ul = dolfinx.fem.Function(Vl)
    Q = dolfinx.fem.functionspace(Vl.mesh, ("DG", 0))
    marker = dolfinx.fem.Function(Q)
    marker.interpolate(lambda x: ((x[0] > 0.0) & (x[0] < 1.0)).astype(np.float64))
    sl, ll = _blocked(Vl, bcl, ul, marker)
    hl = sl.solve()
    assert hp.reason > 0 and hl.reason > 0 and hp.complementarity < 1e-10
    a, b = _nodal(up), _nodal(ul)
    umax = max(abs(v) for v in a.values())
    assert _active_fraction(up) > 0.03
    assert max(abs(a[(1.0, y)] - a[(0.0, y)]) for (x, y) in a if x == 0.0) <= 1e-13 * umax
    # tolerance as in _check (solver tolerance; end effect < 1e-17 at K = 6)
    assert _max_diff(a, b) <= 1e-10 * umax
    lam_p, lam_l = _real_value(lp), _real_value(ll)
    assert -20.0 < lam_p < -5.0  # a load pressing u onto the obstacle
    assert abs(lam_p - lam_l) <= 1e-10 * abs(lam_p)
    sp.destroy()
    sl.destroy()


# ----------------------------------------- vector periodicity with rotation (sector)
N_SECTORS = 6
ALPHA = 2 * np.pi / N_SECTORS
R0, R1 = 1.0, 2.0


#: height of the hollow cylinder (3D case)
HEIGHT = 0.5


def _rotation(angle, dim=2):
    """Rotation by ``angle`` about the z axis (``dim x dim``)."""
    c, s = np.cos(angle), np.sin(angle)
    R = np.eye(dim)
    R[:2, :2] = [[c, -s], [s, c]]
    return R


def _annulus(comm, n_r, n_t, sectors, n_z=0):
    """Structured mesh of ``sectors`` sectors (of ``N_SECTORS``) of the annulus
    ``R0 < r < R1`` (quadrilaterals), or with ``n_z > 0`` of the hollow cylinder of
    height HEIGHT (hexahedra); ``n_t`` cells per sector in angle.  The full ring
    (``sectors = N_SECTORS``) closes on itself; its cells are rotated copies of the
    cells of one sector, so the two discrete problems match."""
    import basix.ufl

    full = sectors == N_SECTORS
    nt = sectors * n_t
    nodes_t = nt if full else nt + 1
    dim = 3 if n_z else 2
    nv = 2**dim
    if comm.rank == 0:
        r = np.linspace(R0, R1, n_r + 1)
        t = np.arange(nodes_t) * (ALPHA / n_t)
        z = np.linspace(0.0, HEIGHT, n_z + 1)
        kk, rr, tt = np.meshgrid(z, r, t, indexing="ij")  # node (k, i, j)
        x = np.column_stack((rr.ravel() * np.cos(tt.ravel()), rr.ravel() * np.sin(tt.ravel())))
        if dim == 3:
            x = np.column_stack((x, kk.ravel()))

        def node(k, i, j):
            return (k * (n_r + 1) + i) * nodes_t + (j % nodes_t)

        def quad(k, i, j):
            return [node(k, i, j), node(k, i + 1, j), node(k, i, j + 1), node(k, i + 1, j + 1)]

        cells = np.array(
            [
                quad(k, i, j) + (quad(k + 1, i, j) if dim == 3 else [])
                for k in range(max(n_z, 1))
                for i in range(n_r)
                for j in range(nt)
            ],
            dtype=np.int64,
        )
    else:
        x, cells = np.zeros((0, dim)), np.zeros((0, nv), dtype=np.int64)
    cell = "hexahedron" if dim == 3 else "quadrilateral"
    domain = ufl.Mesh(basix.ufl.element("Lagrange", cell, 1, shape=(dim,)))
    return dolfinx.mesh.create_mesh(comm, cells, x, domain)


def _elasticity(mesh, assembly_of=None, mixed=False):
    """Linear elasticity, clamped at r = R0, body force periodic with period ALPHA in
    angle (radial and tangential parts, no mirror symmetry).  ``mixed``: the
    displacement-pressure form (Taylor-Hood Q2/Q1, ``p = lambda div u``) in one
    mixed space, as for nearly incompressible rubber."""
    import basix.ufl

    cell = mesh.basix_cell()
    dim = mesh.geometry.dim
    el_u = basix.ufl.element("Lagrange", cell, 2, shape=(dim,))
    if mixed:
        el_p = basix.ufl.element("Lagrange", cell, 1)
        W = dolfinx.fem.functionspace(mesh, basix.ufl.mixed_element([el_u, el_p]))
        Vu = W.sub(0)
    else:
        W = Vu = dolfinx.fem.functionspace(mesh, el_u)
    inner_ring = lambda x: np.isclose(np.hypot(x[0], x[1]), R0)  # noqa: E731
    if mixed:
        V0 = Vu.collapse()[0]
        dofs = dolfinx.fem.locate_dofs_geometrical((Vu, V0), inner_ring)
        bc = dolfinx.fem.dirichletbc(dolfinx.fem.Function(V0), dofs, Vu)
    else:
        dofs = dolfinx.fem.locate_dofs_geometrical(Vu, inner_ring)
        bc = dolfinx.fem.dirichletbc(np.zeros(dim), dofs, Vu)
    assembly, Wu = (None, W) if assembly_of is None else assembly_of(W, bc)
    w = dolfinx.fem.Function(Wu)
    x = ufl.SpatialCoordinate(mesh)
    r = ufl.sqrt(x[0] ** 2 + x[1] ** 2)
    th = ufl.atan2(x[1], x[0])
    e_r = ufl.as_vector((x[0] / r, x[1] / r) + (0,) * (dim - 2))
    e_t = ufl.as_vector((-x[1] / r, x[0] / r) + (0,) * (dim - 2))
    f = (1.0 + 0.5 * ufl.cos(N_SECTORS * th)) * e_r + (
        0.7 + ufl.sin(N_SECTORS * th + 0.3) * r
    ) * e_t
    if dim == 3:  # axial load varying in angle and height
        f = f + (0.4 * ufl.cos(N_SECTORS * th - 0.5) * x[2]) * ufl.as_vector((0, 0, 1))
    lmbda, mu = 1.5, 1.0
    if mixed:
        u, p = ufl.split(w)
        v, q = ufl.TestFunctions(W)
    else:
        u, v = w, ufl.TestFunction(W)
        p = lmbda * ufl.div(u)
    eps = ufl.sym(ufl.grad(u))
    sigma = 2 * mu * eps + p * ufl.Identity(dim)
    F = ufl.inner(sigma, ufl.sym(ufl.grad(v))) * ufl.dx - ufl.inner(f, v) * ufl.dx
    if mixed:
        F = F + (ufl.div(u) - p / lmbda) * q * ufl.dx
    solver = NonlinearSolver(F, w, [bc], options=SNESOptions(**OPTS), assembly=assembly)
    return solver, w


def _sector_assembly(rotation, mixed=False):
    from dolfinx_seal.solvers import add_rotational_periodic_constraint

    def slave_side(x):
        return np.isclose(np.arctan2(x[1], x[0]), ALPHA)

    def to_master(x):
        return np.vstack((_rotation(-ALPHA) @ x[:2], x[2]))  # about the z axis

    def make(W, bc):
        mpc = dolfinx_mpc.MultiPointConstraint(W)
        Vu = W.sub(0) if mixed else W
        add_rotational_periodic_constraint(mpc, Vu, slave_side, to_master, rotation, [bc])
        if mixed:  # the pressure, a scalar, is plainly periodic
            mpc.create_periodic_constraint_geometrical(W.sub(1), slave_side, to_master, [bc])
        mpc.finalize()
        return MPCAssembly(mpc), mpc.function_space

    return make


def _vector_nodal(w, mixed=False):
    """{point rounded: displacement} over the owned displacement dofs, on every rank."""
    u = w.sub(0).collapse() if mixed else w
    V = u.function_space
    dim = V.mesh.geometry.dim
    n = V.dofmap.index_map.size_local
    X = V.tabulate_dof_coordinates()[:n, :dim]
    vals = u.x.array.reshape(-1, dim)[:n]
    out = {}
    for xs, vs in V.mesh.comm.allgather((X, vals.copy())):
        for p, val in zip(np.round(xs, 9), vs, strict=True):
            out[tuple(float(c) + 0.0 for c in p)] = val
    return out


def _sector_vs_full(rotation, mixed=False, n_r=4, n_t=4, n_z=0):
    comm = MPI.COMM_WORLD
    mesh_s = _annulus(comm, n_r, n_t, 1, n_z)
    ss, us = _elasticity(mesh_s, _sector_assembly(rotation, mixed), mixed=mixed)
    hs = ss.solve()
    sf, uf = _elasticity(_annulus(comm, n_r, n_t, N_SECTORS, n_z), mixed=mixed)
    hf = sf.solve()
    assert hs.reason > 0 and hf.reason > 0
    a, b = _vector_nodal(us, mixed), _vector_nodal(uf, mixed)
    assert a.keys() <= b.keys()
    diff = max(np.abs(a[k] - b[k]).max() for k in a)
    umax = max(np.abs(v).max() for v in a.values())
    # the slave side (angle ALPHA) is the master side (angle 0) rotated
    Rm = _rotation(ALPHA, len(rotation))
    on_master = [k for k in a if abs(k[1]) < 1e-12 and k[0] > R0 + 1e-9]
    seam = max(
        np.abs(a[tuple(np.round(Rm @ np.array(k), 9) + 0.0)] - Rm @ a[k]).max() for k in on_master
    )
    ss.destroy()
    sf.destroy()
    return diff, umax, seam, len(on_master)


@pytest.mark.parametrize("mixed", [False, True], ids=["vector", "mixed_u_p"])
def test_rotational_periodic_sector_equals_full_annulus(mixed):
    """One sector of an annulus with ``u(R x) = R u(x)`` on the cut (dolfinx_mpc,
    :func:`add_rotational_periodic_constraint`; in the mixed space also ``p`` periodic)
    equals the full annulus (plain assembly).

    Linear problem: one Newton step, so both solutions are LU solutions of the same
    discrete problem (the full mesh is rotated copies of the sector mesh); their
    difference is round-off, cond(K) eps ~ 1e4 * 1e-16 of max|u| (measured 2.2e-15
    (vector) and 2.0e-15 (mixed) on one rank, 1.7e-15 and 2.1e-15 on two, where all
    the masters are owned by the other rank)."""
    diff, umax, seam, n_master = _sector_vs_full(_rotation(ALPHA), mixed)
    assert n_master > 0
    assert seam <= 1e-13 * umax
    assert diff <= 1e-11 * umax, (diff, umax)
    if not mixed:  # without the rotation (plain periodicity) the answer is wrong
        diff_plain, umax_plain, _, _ = _sector_vs_full(np.eye(2))
        assert diff_plain > 1e-2 * umax_plain


def test_rotational_periodic_sector_3d():
    """A 60 degree sector of a hollow cylinder (vector Q2 on hexahedra, clamped inside,
    radial, tangential and axial loads) with the slave displacement the master one
    rotated about the axis: equals the full cylinder to round-off, as in 2D (measured
    3.1e-15 max|u| on one rank, 2.9e-15 on two)."""
    diff, umax, seam, n_master = _sector_vs_full(_rotation(ALPHA, 3), n_r=2, n_t=2, n_z=2)
    assert n_master > 0
    assert seam <= 1e-13 * umax
    assert diff <= 1e-11 * umax, (diff, umax)
