"""Fields for ParaView (:func:`dolfinx_seal.coupled.results.write_fields`), read back.

* The Cauchy stress of the writer against the closed-form neo-Hookean and
  linear stresses of a homogeneous deformation.
* A solved scene's ``fields.xdmf``, read back with h5py
  (:func:`dolfinx_seal.output.read_fields`): the gap equals ``X + u`` minus the
  counter position at every node, the pressures and the smallest gap equal the
  scene's results, the von Mises field is that of the stress tensor, and in plane
  strain of an incompressible rubber ``sigma_zz`` is the in-plane mean.
* The off-screen PNG of 3D fields (skipped when the machine has no renderer), and
  a run that cannot render only says so.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.output import png_renderer, read_fields, render_fields_png


def _homogeneous(dim: int, Fm: np.ndarray):
    """A unit square/cube with the affine displacement ``u = (F - I) X``."""
    import dolfinx
    from mpi4py import MPI

    if dim == 2:
        mesh = dolfinx.mesh.create_unit_square(MPI.COMM_WORLD, 2, 2)
    else:
        mesh = dolfinx.mesh.create_unit_cube(MPI.COMM_WORLD, 2, 2, 2)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (dim,)))
    u = dolfinx.fem.Function(V)
    G = Fm[:dim, :dim] - np.eye(dim)
    u.interpolate(lambda x: G @ x[:dim])
    return mesh, u


def _cell_values(mesh, expr, shape):
    import dolfinx

    from dolfinx_seal.compat import interpolation_points

    S = dolfinx.fem.functionspace(mesh, ("DG", 0, shape) if shape else ("DG", 0))
    f = dolfinx.fem.Function(S)
    f.interpolate(dolfinx.fem.Expression(expr, interpolation_points(S.element)))
    n = mesh.topology.index_map(mesh.topology.dim).size_local
    return f.x.array.reshape(-1, *shape)[:n] if shape else f.x.array[:n]


@pytest.mark.parametrize("dim", [2, 3])
def test_cauchy_stress_of_a_homogeneous_deformation(dim):
    """Neo-Hookean ``sigma = mu J^(-5/3) dev(b) + K ln(J)/J I`` (penalty) and ``+ p I``
    (mixed); linear ``2 mu dev(eps) + K tr(eps) I``; von Mises ``sqrt(3/2 s:s)``."""
    from dolfinx_seal.coupled.results import cauchy_stress, von_mises
    from dolfinx_seal.solid.kinematics import PlaneStrain, Solid3D
    from dolfinx_seal.solid.materials import LinearElastic, NeoHookean

    kin = PlaneStrain() if dim == 2 else Solid3D()
    Fm = np.eye(3)
    Fm[:dim, :dim] += np.array([[0.12, 0.05, 0.02], [-0.03, -0.08, 0.04], [0.01, 0.02, 0.1]])[
        :dim, :dim
    ]
    mesh, u = _homogeneous(dim, Fm)
    mat = NeoHookean(E=3e6, nu=0.45)
    J = np.linalg.det(Fm)
    b = Fm @ Fm.T
    dev_b = b - np.trace(b) / 3 * np.eye(3)
    expect = mat.mu * J ** (-5 / 3) * dev_b + mat.K * np.log(J) / J * np.eye(3)
    got = _cell_values(mesh, cauchy_stress(mat, kin.F(u)), (3, 3))
    assert np.abs(got - expect).max() <= 1e-10 * np.abs(expect).max()
    mixed = NeoHookean(E=3e6, nu=0.5, formulation="mixed")
    p = 1.7e5  # the mixed pressure enters as + p I
    expect_m = mixed.mu * J ** (-5 / 3) * dev_b + p * np.eye(3)
    got_m = _cell_values(mesh, cauchy_stress(mixed, kin.F(u), p), (3, 3))
    assert np.abs(got_m - expect_m).max() <= 1e-10 * np.abs(expect_m).max()
    s = expect - np.trace(expect) / 3 * np.eye(3)
    vm = _cell_values(mesh, von_mises(cauchy_stress(mat, kin.F(u))), ())
    assert vm == pytest.approx(np.sqrt(1.5 * np.sum(s * s)), rel=1e-10, abs=0.0)
    lin = LinearElastic(E=3e6, nu=0.3)
    eps = 0.5 * (Fm + Fm.T) - np.eye(3)
    if dim == 2:
        eps[2, :] = eps[:, 2] = 0.0
    expect_l = 2 * lin.mu * (eps - np.trace(eps) / 3 * np.eye(3)) + lin.K * np.trace(eps) * np.eye(
        3
    )
    got_l = _cell_values(mesh, cauchy_stress(lin, kin.F(u), eps=kin.eps(u)), (3, 3))
    assert np.abs(got_l - expect_l).max() <= 1e-10 * np.abs(expect_l).max()


def test_lubricated_cylinder_fields_read_back(mpi_tmp_path):
    """The cylinder's ``fields.xdmf`` (coarse 40 um contact elements), read back."""
    from dolfinx_seal.scenes import make_parameters, run_scene

    out = mpi_tmp_path / "cyl"
    p = make_parameters("cylinder", overrides=["h_contact=40e-6"])
    res = run_scene("cylinder", p, out)
    COMM_WORLD.barrier()
    f = read_fields(out / "fields.xdmf")
    pd, cd = f["point_data"], f["cell_data"]
    assert {"displacement", "contact_pressure", "gap", "fluid_pressure"} <= set(pd)
    assert {"cauchy_stress", "von_mises_stress"} <= set(cd)
    X, u = f["points"], pd["displacement"]
    assert X.shape[0] == u.shape[0] and f["cells"].shape[0] == cd["cauchy_stress"].shape[0]
    # the flat is y = position; gap = current height above it, at every node
    gap = pd["gap"][:, 0]
    assert np.abs(X[:, 1] + u[:, 1] - res["counter_position"] - gap).max() <= 1e-12 * X.max()
    assert gap.min() == pytest.approx(res["h_min"], rel=1e-9, abs=0.0)
    assert pd["fluid_pressure"].max() == pytest.approx(res["max_fluid_pressure"], rel=1e-9)
    assert pd["contact_pressure"].min() >= 0.0 and pd["contact_pressure"].max() > 0.0
    s = cd["cauchy_stress"].reshape(-1, 3, 3)
    smax = np.abs(s).max()
    assert np.abs(s - s.transpose(0, 2, 1)).max() <= 1e-9 * smax
    dev = s - np.trace(s, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)
    vm = np.sqrt(1.5 * np.einsum("kij,kij->k", dev, dev))
    assert np.abs(vm - cd["von_mises_stress"][:, 0]).max() <= 1e-9 * smax
    # plane strain, nu = 0.5: sigma_zz = (sigma_xx + sigma_yy) / 2 in the linear limit;
    # finite strain departs from it by the order of the strain, smax / mu
    assert res["parameters"]["material"]["nu"] == 0.5
    mu = p.material.E / 3.0
    mean = 0.5 * (s[:, 0, 0] + s[:, 1, 1])
    assert np.abs(s[:, 2, 2] - mean).max() <= (smax / mu) * smax


def _cube_fields(path):
    """``fields.xdmf`` of a unit cube with the fields the PNG draws (a pressed cube)."""
    import dolfinx
    import dolfinx.io
    from mpi4py import MPI

    mesh = dolfinx.mesh.create_unit_cube(MPI.COMM_WORLD, 4, 4, 4)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    S = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    D = dolfinx.fem.functionspace(mesh, ("DG", 0))
    u = dolfinx.fem.Function(V, name="displacement")
    u.interpolate(lambda x: np.vstack([0.05 * x[0], 0.05 * x[1], -0.1 * x[2]]))
    pc = dolfinx.fem.Function(S, name="contact_pressure")
    pc.interpolate(
        lambda x: 1e6 * np.exp(-20 * ((x[0] - 0.5) ** 2 + (x[1] - 0.5) ** 2)) * (x[2] < 1e-9)
    )
    vm = dolfinx.fem.Function(D, name="von_mises_stress")
    vm.interpolate(lambda x: 1e5 * (1.0 - x[2]))
    with dolfinx.io.XDMFFile(mesh.comm, str(path), "w") as xdmf:
        xdmf.write_mesh(mesh)
        for g in (u, pc, vm):
            xdmf.write_function(g)


def test_png_of_3d_fields(mpi_tmp_path):
    """Off screen, from rank 0 of the run (a child process under ``xvfb-run``): the PNG
    is drawn, has the requested size and is not blank."""
    if png_renderer()[0] is None:
        pytest.skip(f"no off-screen renderer here: {png_renderer()[1]}")
    _cube_fields(mpi_tmp_path / "fields.xdmf")  # collective
    png = mpi_tmp_path / "fields.png"
    drawn = render_fields_png(mpi_tmp_path / "fields.xdmf", png) if COMM_WORLD.rank == 0 else None
    assert COMM_WORLD.bcast(drawn, root=0)
    import matplotlib.image

    img = matplotlib.image.imread(png)
    assert img.shape[:2] == (800, 1600)
    colours = np.unique((img[..., :3] * 255).astype(np.uint8).reshape(-1, 3), axis=0)
    assert len(colours) > 50  # coloured fields, not a blank window


@pytest.mark.skip_in_parallel
def test_no_renderer_is_a_notice_not_an_error(tmp_path, monkeypatch, caplog):
    """Without a renderer (or a failing one) the PNG is skipped with one log line."""
    import dolfinx_seal.output as output

    _cube_fields(tmp_path / "fields.xdmf")
    monkeypatch.setattr(output, "png_renderer", lambda: (None, "no X display"))
    with caplog.at_level(logging.INFO, logger="dolfinx_seal"):
        assert not output.render_fields_png(tmp_path / "fields.xdmf", tmp_path / "a.png")
    assert [r.getMessage() for r in caplog.records] == [
        "fields picture a.png skipped: no X display"
    ]
    monkeypatch.setattr(output, "png_renderer", lambda: (["false"], ""))  # the renderer fails
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="dolfinx_seal"):
        assert not output.render_fields_png(tmp_path / "fields.xdmf", tmp_path / "b.png")
    assert len(caplog.records) == 1 and "renderer failed" in caplog.records[0].getMessage()
    assert not (tmp_path / "a.png").exists() and not (tmp_path / "b.png").exists()


@pytest.mark.slow
@pytest.mark.parametrize("scene", ["lip-install", "lip"])
def test_lip_fields_read_back(mpi_tmp_path, scene):
    """The installed (and lubricated) lip: its fields read back; the gap equals the
    distance of ``X + u`` to the shaft, the contact pressure is >= 0."""
    from dolfinx_seal.scenes import make_parameters, run_scene

    out = mpi_tmp_path / scene
    p = make_parameters(scene, values={"lip": {"h_contact": 20e-6}})
    res = run_scene(scene, p, out)
    COMM_WORLD.barrier()
    f = read_fields(out / "fields.xdmf")
    pd, cd = f["point_data"], f["cell_data"]
    need = {"displacement", "contact_pressure", "gap"} | (
        {"fluid_pressure"} if scene == "lip" else set()
    )
    assert need <= set(pd) and {"cauchy_stress", "von_mises_stress"} <= set(cd)
    r = f["points"][:, 0] + pd["displacement"][:, 0]
    shaft = res["parameters"]["lip"]["shaft_radius"]
    assert np.abs(r - shaft - pd["gap"][:, 0]).max() <= 1e-9 * shaft
    assert pd["contact_pressure"].min() >= 0.0 and pd["contact_pressure"].max() > 0.0


@pytest.mark.slow
def test_dry_ball_fields_and_png(mpi_tmp_path):
    """The 3D ball (dry, coarse): fields read back and the PNG drawn when it can be."""
    import ufl

    from dolfinx_seal.coupled.results import write_fields
    from dolfinx_seal.scenes import ball, make_parameters

    p = make_parameters("ball", overrides=["lubricated=false", "h_contact=0.45e-3"])
    prob, info = ball.build_dry(p)
    a, ph = info["hertz_contact_radius"], info["hertz_peak_pressure"]
    X = prob.X
    ball.solve_dry(
        prob, ph * ufl.sqrt(ufl.max_value(1.0 - (X[0] ** 2 + X[1] ** 2) / a**2, 0.0)), ph
    )
    out = mpi_tmp_path / "ball"
    write_fields(out, prob)
    COMM_WORLD.barrier()
    f = read_fields(out / "fields.xdmf")
    gap = f["point_data"]["gap"][:, 0]
    z = f["points"][:, 2] + f["point_data"]["displacement"][:, 2]
    assert np.abs(z - prob.counter_position() - gap).max() <= 1e-9 * p.radius
    assert f["cell_type"] == "Tetrahedron"
    if png_renderer()[0] is not None:
        assert (out / "fields.png").stat().st_size > 10_000
