"""Results of a lubricated contact point (docs/design.md, results contract), from a solved problem.

Friction: the force needed to slide the counter-surface, ``F_t = int (sigma_1
A/A0 + eta U theta / g + (g/2) dp/ds) da`` (S1 eq 29), split into its
asperity, Couette and Poiseuille parts; ``mu = F_t / F_N`` with ``F_N`` the
normal load (fluid + asperities).  Per unit length in 2D (N/m), N in 3D.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import ufl

from dolfinx_seal.mpi import world
from dolfinx_seal.surface.asperity import area_fraction


def lubricated_results(
    prob: Any, symmetry_factor: float = 1.0, nominal_area: float | None = None
) -> dict[str, Any]:
    """Scalars of a solved lubricated point (SI; keys of the results contract).

    Args:
        prob: A solved :class:`~dolfinx_seal.solid.problem.SolidContactProblem`
            with a film.
        symmetry_factor: Multiplies integrals over a symmetric half model.
        nominal_area: Nominal contact area (length in 2D) [m^2 or m] for
            ``contact_area_fraction`` (e.g. the Hertz ``2 a``); None: not reported.
    """
    film = prob.film
    ds = prob.ds_c
    sf = symmetry_factor
    load_fluid = sf * prob.integrate(film.normal_force_integrand(), ds)
    load_contact = 0.0
    if prob.p_cont is not None:
        load_contact = sf * prob.integrate(prob.asperity_force_integrand(), ds)
    normal = load_fluid + load_contact
    parts = {k: sf * prob.integrate(v, ds) for k, v in film.friction_parts().items()}
    friction = sum(parts.values())
    vals = film.film_values()
    gap, p, theta = vals["gap"], vals["p"], vals["theta"]
    xc = vals["x"][:, 0]
    out: dict[str, Any] = {
        "normal_load": normal,
        "load_fluid": load_fluid,
        "load_contact": load_contact,
        "fluid_load_fraction": load_fluid / normal if normal else math.nan,
        "friction_force": friction,
        "mu": friction / normal if normal else math.nan,
        "max_fluid_pressure": float(p.max()),
        "load_balance_error": abs(normal / sf - prob.target) / prob.target
        if prob.control == "force"
        else math.nan,
        "mass_balance_error": film.mass_balance_error(),
        "counter_position": prob.counter_position(),
        "speed": float(film.speed.value),
        "eta_v": film.params.viscosity * float(film.speed.value),
    }
    for k, v in parts.items():
        out[f"mu_{k}"] = v / normal if normal else math.nan
    if prob.control != "force":
        del out["load_balance_error"]
    X = vals["X"]
    out.update(_film_thickness(prob, gap))
    out.update(_contact_size(prob))
    if prob.mesh.geometry.dim == 2:
        line = np.arange(xc.size)
        cav = _cavitated(film.params.cavitation, p, theta)
        dx = np.gradient(xc)
        out["cavitation_fraction"] = float(dx[cav].sum() / dx.sum())
    else:  # 3D: centre line y = 0 (the symmetry plane of a half model)
        cav_ind = _cavitated(film.params.cavitation, film.P, film.theta_fn, ufl_form=True)
        area = prob.integrate(film.da, ds)
        out["cavitation_fraction"] = prob.integrate(cav_ind * film.da, ds) / area
        line = np.flatnonzero(np.abs(X[:, 1]) <= 1e-9 * np.abs(X[:, 0]).max())
        line = line[np.argsort(X[line, 0])]
    xl, pl = xc[line], p[line]
    cavl = _cavitated(film.params.cavitation, pl, theta[line])
    i = int(np.argmax(pl))
    after = np.flatnonzero(cavl[i:])
    if after.size:
        out["x_cavitation"] = float(xl[i + after[0]])
    if prob.p_cont is not None:
        _, pc = prob.surface_values(prob.p_cont, average=True)
        out["max_contact_pressure"] = float(pc.max())
        if nominal_area and math.isfinite(film.rms_slope):
            A = area_fraction(prob.p_cont, film.e_star, film.rms_slope)
            real = sf * prob.integrate(A * film.da, ds)
            out["real_contact_area"] = real
            out["contact_area_fraction"] = real / nominal_area
    out.update(complementarity_of(prob))
    return out


def _film_thickness(prob: Any, film_gap: np.ndarray) -> dict[str, float]:
    """``h_min`` and ``h_central`` [m] of the gap on the lubricated surface.

    Sampled at the nodes of the displacement (P2: vertices and edge midpoints) where
    the body has them, not only at the film's P1 nodes: the exit constriction of a
    soft EHL film is a few elements wide, and sampling it at twice the density halves
    the distance to its true minimum.  ``h_central``: the gap interpolated at the
    contact centre (in 2D at the current x = 0, below the axis of the counter-surface;
    in 3D at the reference x = y = 0, a half model mirrored about y = 0).
    ``film_gap`` (the gap at the film nodes) is used by a rigid body."""
    if prob.bulk:
        X, gap = prob.surface_values(prob.gap)
        X = X[:, : prob.mesh.geometry.dim]
    else:
        X, gap = prob.film.film_values()["X"], film_gap
    out = {"h_min": float(np.min(gap))}
    if prob.mesh.geometry.dim == 2:
        xc = prob.surface_values(prob.x[0])[1] if prob.bulk else X[:, 0]
        order = np.argsort(xc)
        out["h_central"] = float(np.interp(0.0, xc[order], gap[order]))
    else:
        out["h_central"] = _central_value(X, gap)
    return out


def _contact_size(prob: Any) -> dict[str, float]:
    """The size of the loaded zone from the second moment of the normal force (fluid
    and asperities) about the contact centre: ``contact_half_width = 2 <x^2>^(1/2)``
    (line contact) or ``contact_radius = (5 <r^2> / 2)^(1/2)`` (point contact), both
    exact for a Hertz pressure (as for the dry contact)."""
    fn = prob.normal_force_integrand()
    x = prob.x
    line = prob.mesh.geometry.dim == 2
    r2 = x[0] ** 2 if line else x[0] ** 2 + x[1] ** 2
    m0 = prob.integrate(fn, prob.ds_c)
    m2 = prob.integrate(fn * r2, prob.ds_c)
    if not (m0 > 0 and m2 >= 0):
        return {}
    if line:
        return {"contact_half_width": 2.0 * math.sqrt(m2 / m0)}
    return {"contact_radius": math.sqrt(2.5 * m2 / m0)}


def complementarity_of(prob: Any) -> dict[str, float]:
    """``{"complementarity_error": c}``: the 2-norm of the VI's natural residual
    ``x - clip(x - F(x), lower, upper)`` that the last solve of ``prob``'s coupled
    solver checked, relative to the residual scale ``|F(0)|`` of its tolerances
    (collective); empty when that solve had no bounds (or there was none)."""
    solver = getattr(prob, "solver", None)
    c = getattr(getattr(solver, "history", None), "complementarity", math.nan)
    if not math.isfinite(c):
        return {}
    scale = solver.residual_scale()
    return {"complementarity_error": float(c) / scale if scale > 0 else float(c)}


def _cavitated(model: str, p: Any, theta: Any, ufl_form: bool = False) -> Any:
    """Cavitated nodes: ``theta < 1`` (JFO), ``p <= 0`` (Reynolds), ``p < 0`` (none).

    With ``ufl_form`` (``p`` and ``theta`` functions): the UFL indicator (1 where cavitated).
    """
    if ufl_form:
        if model == "jfo":
            return ufl.conditional(ufl.lt(theta, 1.0 - 1e-8), 1.0, 0.0)
        if model == "reynolds":
            return ufl.conditional(ufl.le(p, 0.0), 1.0, 0.0)
        return ufl.conditional(ufl.lt(p, 0.0), 1.0, 0.0)
    if model == "jfo":
        return theta < 1.0 - 1e-8
    if model == "reynolds":
        return p <= 0.0
    return p < 0.0


def _central_value(X: np.ndarray, values: np.ndarray) -> float:
    """Linear interpolation of nodal ``values`` on the surface nodes ``X`` (3D) at the
    contact centre ``x = y = 0`` (the half model is mirrored about ``y = 0``)."""
    from scipy.interpolate import LinearNDInterpolator

    r = np.hypot(X[:, 0], X[:, 1])
    near = r <= np.sort(r)[min(r.size - 1, 200)]
    xy = X[near][:, :2]
    v = values[near]
    off = xy[:, 1] > 1e-9 * np.abs(xy).max()
    xy = np.vstack([xy, xy[off] * [1.0, -1.0]])
    return float(LinearNDInterpolator(xy, np.concatenate([v, v[off]]))(0.0, 0.0))


def write_film_profile(out: Path, prob: Any, title: str) -> None:
    """``film.csv`` and ``film.png``: fluid and asperity pressure, gap, film fraction
    along the lubricated line (2D scenes), on rank 0."""
    film = prob.film
    vals = film.film_values()
    pc = np.zeros_like(vals["p"])
    if prob.p_cont is not None:
        Xs, pcs = prob.surface_values(prob.p_cont, average=True)
        pc = np.interp(vals["X"][:, 0], Xs[:, 0], pcs)
    if world().rank != 0:
        return
    out.mkdir(parents=True, exist_ok=True)
    x = vals["x"][:, 0]
    cols = {
        "x_m": x,
        "X_m": vals["X"][:, 0],
        "p_fluid_Pa": vals["p"],
        "p_contact_Pa": pc,
        "gap_m": vals["gap"],
        "theta": vals["theta"],
    }
    data = np.column_stack(list(cols.values()))
    np.savetxt(out / "film.csv", data, delimiter=",", header=",".join(cols), comments="")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.0), sharex=True)
    ax1.plot(x * 1e3, vals["p"] / 1e6, label="fluid")
    ax1.plot(x * 1e3, pc / 1e6, label="asperity")
    ax1.plot(x * 1e3, (vals["p"] + pc) / 1e6, "k:", label="total")
    ax1.set_ylabel("pressure [MPa]")
    ax1.legend(frameon=False)
    ax1.set_title(title)
    ax2.semilogy(x * 1e3, vals["gap"] * 1e6, label="gap [um]")
    if film.has_theta:
        ax2.semilogy(x * 1e3, np.maximum(vals["theta"], 1e-3), label="film fraction")
    ax2.set_xlabel("x [mm]")
    ax2.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(out / "film.png", dpi=120)
    plt.close(fig)


def write_film_map(out: Path, prob: Any, title: str, extent: float | None = None) -> None:
    """``film_map.csv`` and ``film_map.png`` of a 3D film (collective; files on rank 0).

    Maps over the current contact plane ``(x, y)`` of the fluid pressure, the
    asperity pressure (left out for smooth surfaces), the gap (log scale) and
    the cavitated zone (film fraction for JFO, ``p = 0`` for the Reynolds condition).  A half model
    (``y >= 0``) is mirrored about ``y = 0``.  ``extent``: half-size of the
    plotted window [m] (default: the whole lubricated zone).
    """
    film = prob.film
    vals = film.film_values()
    X = vals["X"]
    pc = np.zeros_like(vals["p"])
    if prob.p_cont is not None:
        from scipy.spatial import cKDTree

        Xs, pcs = prob.surface_values(prob.p_cont, average=True)
        _, idx = cKDTree(Xs).query(X)
        pc = pcs[idx]
    if world().rank != 0:
        return
    out.mkdir(parents=True, exist_ok=True)
    x, y = vals["x"][:, 0], vals["x"][:, 1]
    cav = _cavitated(film.params.cavitation, vals["p"], vals["theta"])
    contact = prob.p_cont is not None  # smooth surfaces: no asperity column or panel
    cols = {"x_m": x, "y_m": y, "X_m": X[:, 0], "Y_m": X[:, 1], "p_fluid_Pa": vals["p"],
            "p_contact_Pa": pc, "gap_m": vals["gap"], "theta": vals["theta"],
            "cavitated": cav.astype(float)}  # fmt: skip
    if not contact:
        del cols["p_contact_Pa"]
    data = np.column_stack(list(cols.values()))
    np.savetxt(out / "film_map.csv", data, delimiter=",", header=",".join(cols), comments="")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri

    half = X[:, 1].min() >= -1e-12 * np.abs(X).max()
    off = y > 1e-12 * np.abs(X).max()
    xs = np.concatenate([x, x[off]]) if half else x
    ys = np.concatenate([y, -y[off]]) if half else y

    def mirrored(v: np.ndarray) -> np.ndarray:
        return np.concatenate([v, v[off]]) if half else v

    tri = mtri.Triangulation(xs * 1e3, ys * 1e3)
    panels = [
        ("fluid pressure [MPa]", mirrored(vals["p"]) / 1e6, "viridis", False),
        ("asperity pressure [MPa]", mirrored(pc) / 1e6, "magma", False),
        ("log10 gap [um]", np.log10(np.maximum(mirrored(vals["gap"]), 1e-12) * 1e6), "cividis", False),
        (
            "film fraction (JFO)" if film.has_theta else "cavitated (p = 0)",
            mirrored(vals["theta"]) if film.has_theta else mirrored(cav.astype(float)),
            "Blues_r" if film.has_theta else "Greys",
            True,
        ),
    ]  # fmt: skip
    if not contact:
        del panels[1]
    fig, axes = (
        plt.subplots(2, 2, figsize=(10, 8.6)) if contact else plt.subplots(1, 3, figsize=(14, 4.6))
    )
    for ax, (label, v, cmap, bounded) in zip(axes.flat, panels, strict=True):
        # fields in [0, 1]: the levels straddle both ends, else contourf leaves the
        # nodes at exactly 1 (cavitated, or full film) unfilled (white)
        levels = np.linspace(-0.05, 1.05, 12) if bounded else 24
        cs = ax.tricontourf(tri, v, levels=levels, cmap=cmap)
        fig.colorbar(cs, ax=ax, shrink=0.85)
        ax.set_title(label, fontsize=10)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm] (sliding)")
        ax.set_ylabel("y [mm]")
        if extent:
            ax.set_xlim(-extent * 1e3, extent * 1e3)
            ax.set_ylim(-extent * 1e3, extent * 1e3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out / "film_map.png", dpi=110)
    plt.close(fig)


def cauchy_stress(material: Any, F: Any, p: Any = None, eps: Any = None) -> Any:
    """Cauchy stress (UFL, 3x3) [Pa] of ``material`` at the deformation gradient ``F``.

    Hyperelastic models: ``sigma = (1/J) dpsi/dF F^T`` from the same strain
    energy the problem minimises (``p``: the mixed pressure, or None).  The
    small-strain model (no ``strain_energy``): ``sigma = dpsi/deps`` at the
    small-strain tensor ``eps``.  Components in the kinematics' 3x3 frame:
    (x, y, z) in 3D and plane strain, (r, z, theta) in axisymmetry.
    """
    if hasattr(material, "strain_energy"):
        Fv = ufl.variable(F)
        P = ufl.diff(material.strain_energy(Fv, p), Fv)
        return P * Fv.T / ufl.det(Fv)
    if eps is None:
        raise ValueError("cauchy_stress: the small-strain model needs eps")
    ev = ufl.variable(eps)
    return ufl.diff(material.small_strain_energy(ev, p), ev)


def von_mises(sigma: Any) -> Any:
    """Von Mises equivalent stress ``sqrt(3/2 s:s)``, ``s`` the deviator of ``sigma`` (UFL) [Pa]."""
    s = sigma - ufl.tr(sigma) / 3.0 * ufl.Identity(3)
    return ufl.sqrt(1.5 * ufl.inner(s, s))


def write_fields(
    out: Path,
    prob: Any,
    name: str = "fields",
    extra: dict[str, Any] | None = None,
    png: bool | None = None,
) -> Path:
    """Write ``NAME.xdmf`` (+ ``NAME.h5``) for ParaView (collective); returns its path.

    Fields, where the problem has them (SI):

    * ``displacement`` [m] (vector, at the nodes; Lagrange of the geometry's degree,
      P1 on straight-sided meshes, as every nodal field below);
    * ``cauchy_stress`` [Pa] (3x3 tensor, one value per cell: (x, y, z), or
      (r, z, theta) in axisymmetry) and ``von_mises_stress`` [Pa] (per cell), from
      the problem's strain energy (:func:`cauchy_stress`);
    * ``contact_pressure`` [Pa] (asperity law at the gap) and ``gap`` [m] (distance
      to the counter-surface along its normal), on all nodes, meaningful on the
      contact surface;
    * ``fluid_pressure`` [Pa] and ``film_fraction`` [-] (JFO films only) of the film;
    * each UFL expression of ``extra`` (name -> expression) as a nodal field; an extra
      replaces the field of the same name or the same expression (e.g. the gap
      written as ``separation``).

    With ``png`` (default: on for 3D meshes) rank 0 also draws ``NAME.png``, the
    deformed body coloured by the von Mises stress and the contact face by the
    contact and fluid pressure, off screen (:func:`~dolfinx_seal.output.render_fields_png`;
    skipped with a one-line notice when no renderer is available).
    """
    import dolfinx
    import dolfinx.io

    from dolfinx_seal.compat import interpolation_points

    mesh = prob.mesh
    out = Path(out)
    if mesh.comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    mesh.comm.barrier()
    deg = mesh.geometry.cmap.degree  # XDMF writes Lagrange fields of the geometry's degree
    V1 = dolfinx.fem.functionspace(mesh, ("Lagrange", deg, (mesh.geometry.dim,)))
    S1 = dolfinx.fem.functionspace(mesh, ("Lagrange", deg))
    extra = dict(extra or {})
    given = [id(e) for e in extra.values()]

    def interpolate(space: Any, key: str, expr: Any) -> Any:
        f = dolfinx.fem.Function(space, name=key)
        f.interpolate(dolfinx.fem.Expression(expr, interpolation_points(space.element)))
        return f

    fields = []
    if prob.bulk:
        fields.append(interpolate(V1, "displacement", prob.u))
        eps = prob.kin.eps(prob.u) if not hasattr(prob.material, "strain_energy") else None
        sigma = cauchy_stress(prob.material, prob.F, prob.p_mix, eps)
        T0 = dolfinx.fem.functionspace(mesh, ("DG", 0, (3, 3)))
        D0 = dolfinx.fem.functionspace(mesh, ("DG", 0))
        fields.append(interpolate(T0, "cauchy_stress", sigma))
        fields.append(interpolate(D0, "von_mises_stress", von_mises(sigma)))
    surface = {"contact_pressure": prob.p_cont, "gap": prob.gap}
    for key, expr in surface.items():
        if expr is not None and key not in extra and id(expr) not in given:
            fields.append(interpolate(S1, key, expr))
    if prob.film is not None:
        p = dolfinx.fem.Function(S1, name="fluid_pressure")
        p.interpolate(prob.film.P)
        p.x.array[:] *= prob.film.scales.pressure
        fields.append(p)
        if prob.film.has_theta:
            t = dolfinx.fem.Function(S1, name="film_fraction")
            t.interpolate(prob.film.theta_fn)
            fields.append(t)
    fields = [f for f in fields if f.name not in extra]
    fields += [interpolate(S1, key, expr) for key, expr in extra.items()]
    path = out / f"{name}.xdmf"
    with dolfinx.io.XDMFFile(mesh.comm, str(path), "w") as xdmf:
        xdmf.write_mesh(mesh)
        for f in fields:
            xdmf.write_function(f)
    if png if png is not None else mesh.geometry.dim == 3:
        from dolfinx_seal.output import render_fields_png

        if mesh.comm.rank == 0:
            render_fields_png(path, out / f"{name}.png")
        mesh.comm.barrier()
    return path


__all__ = [
    "cauchy_stress",
    "complementarity_of",
    "lubricated_results",
    "von_mises",
    "write_fields",
    "write_film_map",
    "write_film_profile",
]
