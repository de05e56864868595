"""Maps of the lip sector on the unrolled contact band, and its fields for ParaView.

The band is unrolled on its reference coordinates: ``x_1 = R_shaft phi`` along
the circumference (``phi = atan2(Y, X)``, the sliding direction of a turning
shaft) and ``x_2 = z`` along the axis (oil side ``z < 0``).  At the P1 nodes of
the band (lumped L2 projections of the surface quantities, as
:meth:`~dolfinx_seal.solid.problem.SolidContactProblem.surface_values` gives
them), ``band.csv`` holds, SI:

* ``x1``, ``z`` [m]; ``separation`` u [m] (S0 fig 4);
* ``contact_pressure`` sigma_s3 and ``fluid_pressure`` sigma_f3 [Pa] (fig 5);
* ``area_fraction`` A/A0 [-] (figs 7a, 8);
* ``flux_circumferential``, ``flux_axial`` [m^2/s]: the volumetric flux per unit
  width of the current surface, ``-phi_p u^3 / (12 eta) grad_s p + U_m u theta``,
  along ``e_theta`` and ``e_z`` (figs 7b, 9: flux lines; fig 12: axial flux,
  counter-gradient where it runs from the air side to the oil side, ``< 0``);
* ``area_change`` ``da/dA - 1`` [-]: the in-plane area change of the surface, whose
  linearisation on a flat surface is S0's ``dw1/dx1 + dw2/dx2`` (fig 10; negative:
  shrinking);
* ``film_fraction`` theta [-] (fig 11: cavitated where ``theta < 1``).

``maps.png`` draws them over the lubricated zone, with a profile along
``x_1 = 0`` (fig 6): separation, asperity, fluid and total pressure.
``fields.xdmf`` holds the displacement, the von Mises stress, the contact and
fluid pressure, the gap, A/A0, the film fraction and the roughness height
(P1, meaningful on the band) for ParaView.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import ufl

from dolfinx_seal.mpi import world
from dolfinx_seal.surface.asperity import area_fraction


def band_quantities(lub: Any) -> dict[str, Any]:
    """UFL expressions of the band's quantities (the keys of ``band.csv`` after
    ``x1, z``), on the sector problem ``lub.problem``."""
    prob = lub.problem
    film = prob.film
    e_theta = prob.counter.sliding_direction(prob.x)
    e_z = ufl.as_vector([0.0, 0.0, 1.0])
    flux = -film.conductivity * film.surface_grad(film.p)
    if film.has_transport:
        flux = flux + film.g * film.theta * film.U_m
    out = {
        "separation": prob.gap,
        "contact_pressure": prob.p_cont,
        "fluid_pressure": film.p,
        "area_fraction": area_fraction(prob.p_cont, film.e_star, film.rms_slope),
        "flux_circumferential": ufl.dot(flux, e_theta),
        "flux_axial": ufl.dot(flux, e_z),
        "area_change": film.da - 1.0,
    }
    if film.has_theta:
        out["film_fraction"] = film.theta_fn
    return out


def band_values(lub: Any) -> dict[str, np.ndarray]:
    """The band's nodal values (gathered on every rank, one order): ``x1``, ``z``
    and the quantities of :func:`band_quantities`; ``film_fraction`` 1 without JFO;
    ``triangles`` (n x 3 row indices): the band's own facets."""
    from scipy.spatial import cKDTree

    prob = lub.problem
    R_s = float(prob.counter_position())
    out: dict[str, np.ndarray] = {}
    X = None
    for key, expr in band_quantities(lub).items():
        Xk, v = prob.surface_values(expr, average=True)
        if X is None:
            X = Xk
        out[key] = v
    assert X is not None
    out = {"x1": R_s * np.arctan2(X[:, 1], X[:, 0]), "z": X[:, 2], **out}
    out.setdefault("film_fraction", np.ones(X.shape[0]))
    tri = band_facets(lub)
    out["triangles"] = cKDTree(X).query(tri.reshape(-1, 3))[1].reshape(-1, 3)
    return out


def band_facets(lub: Any) -> np.ndarray:
    """Vertex coordinates (n x 3 x 3) of the band's facets, gathered on every rank."""
    import dolfinx

    tm = lub.mesh
    mesh = tm.mesh
    fdim = mesh.topology.dim - 1
    facets = tm.facet_tags.find(tm.tag("contact"))
    facets = facets[facets < mesh.topology.index_map(fdim).size_local]
    mesh.topology.create_connectivity(fdim, 0)
    nodes = dolfinx.mesh.entities_to_geometry(mesh, fdim, facets, False)
    x = mesh.geometry.x[nodes.reshape(-1)].reshape(-1, 3, 3)
    parts = mesh.comm.allgather(x)
    return np.concatenate(parts) if parts else x


def zone(lub: Any) -> tuple[float, float]:
    """The z-range [m] of the lubricated zone (free film nodes)."""
    film = lub.problem.film
    X = film.S.tabulate_dof_coordinates()[film.film_dofs_local]
    comm = lub.mesh.comm
    lo = comm.allreduce(float(X[:, 2].min(initial=np.inf)), op=_min())
    hi = comm.allreduce(float(X[:, 2].max(initial=-np.inf)), op=_max())
    return lo, hi


def _min() -> Any:
    from mpi4py import MPI

    return MPI.MIN


def _max() -> Any:
    from mpi4py import MPI

    return MPI.MAX


def write_band_csv(out: Path, vals: dict[str, np.ndarray]) -> None:
    """``band.csv`` (rank 0)."""
    if world().rank != 0:
        return
    out.mkdir(parents=True, exist_ok=True)
    keys = [k for k in vals if k != "triangles"]
    np.savetxt(out / "band.csv", np.column_stack([vals[k] for k in keys]), delimiter=",",
               header=",".join(keys), comments="", fmt="%.10g")  # fmt: skip


def plot_maps(out: Path, vals: dict[str, np.ndarray], window: tuple[float, float], title: str,
              h_rms: float) -> None:  # fmt: skip
    """``maps.png``: the band maps over the z-range ``window`` and the profile at
    ``x_1 = 0`` (rank 0)."""
    if world().rank != 0:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import LinearTriInterpolator, Triangulation

    lo, hi = window
    v = {k: a for k, a in vals.items() if k != "triangles"}
    zz, ss = v["z"] * 1e6, v["x1"] * 1e6
    tri = Triangulation(zz, ss, triangles=vals["triangles"])
    inside = (zz[vals["triangles"]].min(axis=1) >= lo * 1e6 - 1e-6) & (
        zz[vals["triangles"]].max(axis=1) <= hi * 1e6 + 1e-6
    )
    tri.set_mask(~inside)
    panels = [
        ("separation u / h_rms (S0 fig 4)", v["separation"] / h_rms, "viridis"),
        ("asperity pressure [MPa] (fig 5a)", v["contact_pressure"] / 1e6, "inferno"),
        ("fluid pressure [MPa] (fig 5b)", v["fluid_pressure"] / 1e6, "plasma"),
        ("A/A0 (figs 7a, 8)", v["area_fraction"], "Greys"),
        ("|flux| [mm^2/s] and flux lines (fig 7b)",
         np.hypot(v["flux_axial"], v["flux_circumferential"]) * 1e6, "Blues"),
        ("axial flux [mm^2/s], < 0: counter-gradient (fig 12)", v["flux_axial"] * 1e6, "RdBu_r"),
        ("in-plane area change da/dA - 1 (fig 10)", v["area_change"], "coolwarm"),
        ("film fraction theta, < 1 cavitated (fig 11)", v["film_fraction"], "gray"),
    ]  # fmt: skip
    fig, axes = plt.subplots(3, 3, figsize=(15, 10.5))
    for ax, (name, data, cmap) in zip(axes.flat, panels, strict=False):
        kw: dict[str, Any] = {}
        if cmap in ("RdBu_r", "coolwarm"):
            m = float(np.abs(data).max()) or 1.0
            kw = {"vmin": -m, "vmax": m}
        im = ax.tripcolor(tri, data, shading="gouraud", cmap=cmap, **kw)
        fig.colorbar(im, ax=ax, shrink=0.85)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("z [um] (oil side left)")
        ax.set_ylabel("x1 = R phi [um]")
        if name.startswith("|flux|"):
            _flux_lines(ax, tri, v, LinearTriInterpolator, (lo * 1e6, hi * 1e6))
    ax = axes.flat[-1]
    _profile(ax, tri, v, LinearTriInterpolator, h_rms, (lo * 1e6, hi * 1e6))
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "maps.png", dpi=110)
    plt.close(fig)


def _flux_lines(ax: Any, tri: Any, v: dict[str, np.ndarray], interp: Any,
                zr: tuple[float, float]) -> None:  # fmt: skip
    zs = np.linspace(max(zr[0], tri.x.min()), min(zr[1], tri.x.max()), 120)
    ss = np.linspace(tri.y.min(), tri.y.max(), 40)
    Z, S = np.meshgrid(zs, ss)
    qz = interp(tri, v["flux_axial"])(Z, S)
    qs = interp(tri, v["flux_circumferential"])(Z, S)
    if np.ma.count(qz) < 4 or not np.isfinite(np.ma.filled(qz, np.nan)).any():
        return
    ax.streamplot(Z, S, np.ma.filled(qz, 0.0), np.ma.filled(qs, 0.0), color="r",
                  linewidth=0.6, density=1.2, arrowsize=0.6)  # fmt: skip


def _profile(ax: Any, tri: Any, v: dict[str, np.ndarray], interp: Any, h_rms: float,
             zr: tuple[float, float]) -> None:  # fmt: skip
    """S0 fig 6: along x_1 = 0, separation and the pressures."""
    zs = np.linspace(max(zr[0], tri.x.min()), min(zr[1], tri.x.max()), 400)
    s0 = np.zeros_like(zs)
    pc = np.ma.filled(interp(tri, v["contact_pressure"])(zs, s0), np.nan) / 1e6
    pf = np.ma.filled(interp(tri, v["fluid_pressure"])(zs, s0), np.nan) / 1e6
    u = np.ma.filled(interp(tri, v["separation"])(zs, s0), np.nan) / h_rms
    ax.plot(zs, pc, "g-", lw=1.5, label="asperity pressure")
    ax.plot(zs, pf, "r-", lw=1.5, label="fluid pressure")
    ax.plot(zs, pc + pf, "b--", lw=1.0, label="total")
    ax.set_xlabel("z [um] at x1 = 0 (fig 6)")
    ax.set_ylabel("pressure [MPa]")
    ax2 = ax.twinx()
    ax2.semilogy(zs, u, "k-", lw=1.0, label="separation / h_rms")
    ax2.set_ylabel("separation / h_rms")
    ax.legend(frameon=False, fontsize=7, loc="upper left")


def write_fields(out: Path, lub: Any, name: str = "fields") -> Path:
    """``NAME.xdmf`` (+ ``.h5``) for ParaView (collective): P1 displacement, von Mises
    stress (per cell), and on the band contact and fluid pressure, gap, A/A0, film
    fraction and the roughness height (P1 interpolation of the UFL expressions, so
    the periodic unknowns' extra ghosts do not matter)."""
    import dolfinx
    import dolfinx.io

    from dolfinx_seal.compat import interpolation_points
    from dolfinx_seal.coupled.results import cauchy_stress, von_mises

    prob = lub.problem
    film = prob.film
    mesh = prob.mesh
    out = Path(out)
    if mesh.comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    mesh.comm.barrier()
    V1 = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    S1 = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    D0 = dolfinx.fem.functionspace(mesh, ("DG", 0))

    def interpolate(space: Any, key: str, expr: Any) -> Any:
        f = dolfinx.fem.Function(space, name=key)
        f.interpolate(dolfinx.fem.Expression(expr, interpolation_points(space.element)))
        return f

    sigma = cauchy_stress(prob.material, prob.F, prob.p_mix,
                          prob.kin.eps(prob.u) if not hasattr(prob.material, "strain_energy")
                          else None)  # fmt: skip
    fields = [
        interpolate(V1, "displacement", prob.u),
        interpolate(D0, "von_mises_stress", von_mises(sigma)),
        interpolate(S1, "contact_pressure", prob.p_cont),
        interpolate(S1, "fluid_pressure", film.p),
        interpolate(S1, "gap", prob.gap),
        interpolate(S1, "area_fraction", area_fraction(prob.p_cont, film.e_star, film.rms_slope)),
    ]
    if film.has_theta:
        fields.append(interpolate(S1, "film_fraction", film.theta_fn))
    counter = prob.counter
    if hasattr(counter, "height"):
        fields.append(interpolate(S1, "roughness_height", counter.height))
    path = out / f"{name}.xdmf"
    with dolfinx.io.XDMFFile(mesh.comm, str(path), "w") as xdmf:
        xdmf.write_mesh(mesh)
        for f in fields:
            xdmf.write_function(f)
    return path


def write_maps(out: Path, lub: Any, params: Any, fields: bool = True) -> None:
    """``band.csv``, ``maps.png`` and (``fields``) ``fields.xdmf`` of a solved point."""
    out = Path(out)
    vals = band_values(lub)
    write_band_csv(out, vals)
    lo, hi = zone(lub)
    pad = 0.1 * (hi - lo)
    speed = float(params.film.speed)
    title = (f"{params.scene_name}: oil {params.oil_pressure / 1e6:.3g} MPa, shaft "
             f"{speed:.3g} m/s, h_rms {params.roughness.h_rms * 1e6:g} um, q_th / q_min = "
             f"{params.roughness.q_th * lub.roughness.period / (2 * math.pi):.3g}, "
             f"{params.material.model}")  # fmt: skip
    plot_maps(out, vals, (lo - pad, hi + pad), title, params.roughness.h_rms)
    if fields:
        write_fields(out, lub)


__all__ = ["band_quantities", "band_values", "plot_maps", "write_fields", "write_maps", "zone"]
