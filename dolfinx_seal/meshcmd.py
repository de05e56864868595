"""``dolfinx-seal mesh KIND``: build a mesh with Gmsh, write ``.msh``, ``info.json`` and a PNG.

::

    dolfinx-seal mesh lip --out results/meshes/lip
    dolfinx-seal mesh lip-sector --set lip.interference=0.4e-3 --set elements_per_wavelength=6
    dolfinx-seal mesh ball --set shape=full --set h_contact=0.08e-3 --out results/meshes/ball-full
    dolfinx-seal mesh cylinder --params          # print the resolved parameters and stop

Parameters are the fields of the kind's dataclass (:mod:`geometry`), changed with
``--set key=value`` (dotted keys for nested ones).  Gmsh runs on rank 0 only;
under ``mpirun`` the other ranks wait.  Gmsh and matplotlib are imported only
when the command runs, so the rest of the CLI stays light.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import print0, world
from dolfinx_seal.params import from_mapping, parse_overrides, to_dict
from geometry import KINDS
from geometry import load as load_builder

#: Colour of each facet group in the pictures.
COLOURS: dict[str, str] = {
    "contact": "#d62728",
    "load": "#1f77b4",
    "symmetry": "#2ca02c",
    "clamped": "#111111",
    "oil_side": "#ff7f0e",
    "air_side": "#17becf",
    "spring_groove": "#9467bd",
    "periodic_left": "#bcbd22",
    "periodic_right": "#8c564b",
    "cut": "#7f7f7f",
    "free": "#aec7e8",
}


def add_parser(subparsers: Any) -> None:
    """Register the ``mesh`` sub-command on the CLI's sub-parsers."""
    sp = subparsers.add_parser(
        "mesh",
        help="build a mesh with Gmsh: KIND.msh, info.json and KIND.png",
        description="Build a mesh with Gmsh (rank 0) and write KIND.msh, info.json "
        "(parameters, versions, time) and KIND.png into --out.  --params lists the "
        "parameters of KIND and their values.",
    )
    sp.add_argument("kind", choices=list(KINDS), help="geometry to build")
    sp.add_argument(
        "--set", action="append", default=[], metavar="KEY=VALUE",
        help="override a parameter (dotted keys for nested ones, e.g. lip.interference); "
        "repeatable",
    )  # fmt: skip
    sp.add_argument("--out", default=None, help="output folder (default results/meshes/KIND)")
    sp.add_argument("--name", default=None, help="file stem (default KIND)")
    sp.add_argument("--no-png", action="store_true", help="do not draw the PNG")
    sp.add_argument("--params", action="store_true", help="print the parameters and stop")
    sp.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the ``mesh`` sub-command (the parameters are validated on every rank)."""
    mod = load_builder(args.kind)
    params = from_mapping(mod.PARAMS, parse_overrides(args.set))
    if args.params:
        print0(json.dumps(to_dict(params), indent=2))
        return 0
    out = Path(args.out or f"results/meshes/{args.kind}")
    name = args.name or args.kind
    status: tuple[str, str] = ("ok", "")
    if world().rank == 0:
        try:
            status = ("ok", _build_and_write(mod, params, out, name, args))
        except ParameterError as e:
            status = ("parameter", str(e))
        except Exception as e:
            status = ("error", f"{type(e).__name__}: {e}")
    status = world().bcast(status, root=0)
    if status[0] == "parameter":
        raise ParameterError(status[1])
    if status[0] == "error":
        print0(
            f"dolfinx-seal mesh {args.kind}: mesh generation failed: {status[1]}", file=sys.stderr
        )
        return 1
    print0(status[1])
    return 0


def _build_and_write(mod: Any, params: Any, out: Path, name: str, args: argparse.Namespace) -> str:
    from geometry._common import gmsh_session, save

    with gmsh_session(bool(getattr(args, "verbose", False))):
        info = mod.BUILD(params)
        path = save(info, out, name)
        groups = ", ".join(
            f"{k}={v} ({info.num_facets[k]} facets)" for k, v in info.facet_groups.items()
        )
        lines = [
            f"{path}: {info.num_cells} cells, {info.num_nodes} nodes, "
            f"built in {info.build_time_s:.2f} s",
            f"facet groups: {groups}",
            f"info: {out / 'info.json'}",
        ]
        if not args.no_png:
            lines.append(f"picture: {plot_mesh(info, out / f'{name}.png')}")
    return "\n".join(lines)


# ------------------------------------------------------------------ pictures
def plot_mesh(info: Any, path: str | Path) -> Path:
    """Draw the current Gmsh model's mesh into a PNG, boundaries coloured by group.

    2D meshes: the whole section and a zoom on the contact.  3D meshes: the
    boundary in perspective and a flat view of the contact cap (ball) or of the
    periodic face (lip sector).

    Args:
        info: The builder's :class:`geometry.MeshInfo` (its model must be current).
        path: PNG file to write.

    Returns:
        The path written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from geometry._common import mesh_arrays

    x, groups = mesh_arrays(info)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig = plt.figure(figsize=(12, 5.2), dpi=110)
    if info.tdim == 2:
        _plot_2d(fig, info, x, groups)
    else:
        _plot_3d(fig, info, x, groups)
    p = info.params
    fig.suptitle(
        f"{info.kind}: {info.num_cells} cells, {info.num_nodes} nodes (order {p.order})",
        fontsize=11,
    )
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _edges_2d(ax: Any, x: Any, groups: dict[str, Any], swap: bool, scale: float) -> None:
    from matplotlib.collections import LineCollection

    i, j = (1, 0) if swap else (0, 1)
    tri = groups["body"]
    ax.triplot(x[:, i] * scale, x[:, j] * scale, tri, color="0.6", lw=0.15)
    for name, e in groups.items():
        if name == "body" or len(e) == 0:
            continue
        segs = x[e][:, :, [i, j]] * scale
        ax.add_collection(LineCollection(segs, colors=COLOURS.get(name, "k"), lw=1.8, label=name))
    ax.set_aspect("equal")


def _plot_2d(fig: Any, info: Any, x: Any, groups: dict[str, Any]) -> None:
    p = info.params
    gs = fig.add_gridspec(1, 2, width_ratios=[1.0, 1.6] if info.kind == "lip" else [1.0, 1.0])
    ax1, ax2 = fig.add_subplot(gs[0]), fig.add_subplot(gs[1])
    mm = 1e3
    if info.kind == "lip":
        # axial direction horizontal, radial upwards: the usual seal drawing
        r0, rs = info.extra["tip_r"], p.shaft_radius
        for ax in (ax1, ax2):
            _edges_2d(ax, x, groups, True, mm)
            ax.axhline(rs * mm, color="k", ls="--", lw=0.8, label="shaft surface")
            ax.set_xlabel("z (axial) [mm]")
            ax.set_ylabel("r [mm]")
        ax1.set_title("axisymmetric section (oil side left, air side right)")
        zlo, zhi = -p.band_oil - 0.5e-3, p.band_air + 0.5e-3
        ax2.set_xlim(zlo * mm, zhi * mm)
        ax2.set_ylim((r0 - 0.1e-3) * mm, (r0 + 0.5 * (zhi - zlo)) * mm)
        ax2.set_title(
            f"lip tip: interference {p.interference * mm:g} mm, band h = {p.h_contact * 1e6:g} um"
        )
        ax1.autoscale_view()
    else:
        a = p.contact_half_width
        x0, x1 = info.extra["arc_ends"]
        for ax in (ax1, ax2):
            _edges_2d(ax, x, groups, False, mm)
            ax.axhline(0.0, color="k", lw=0.8, label="flat")
            ax.set_xlabel("x (sliding) [mm]")
            ax.set_ylabel("y [mm]")
        ax1.set_title(f"cylinder section ({p.shape})")
        ax1.autoscale_view()
        ax2.set_xlim((x0 - 2 * a) * mm, (x1 + 2 * a) * mm)
        ax2.set_ylim(-0.3 * a * mm, 0.35 * (x1 - x0 + 4 * a) * mm)
        ax2.set_title(f"contact arc: a = {a * mm:g} mm, h = {p.h_contact * 1e6:g} um")
    ax2.legend(loc="upper right", fontsize=7, framealpha=0.9)


def _plot_3d(fig: Any, info: Any, x: Any, groups: dict[str, Any]) -> None:
    import numpy as np
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    mm = 1e3
    ax1 = fig.add_subplot(1, 2, 1, projection="3d")
    for name, e in groups.items():
        if name == "body" or len(e) == 0:
            continue
        poly = Poly3DCollection(
            x[e] * mm, facecolors=COLOURS.get(name, "0.5"), edgecolors="0.25", linewidths=0.05
        )
        poly.set_label(name)
        ax1.add_collection3d(poly)
    lo, hi = x.min(axis=0) * mm, x.max(axis=0) * mm
    ax1.set_xlim(lo[0], hi[0])
    ax1.set_ylim(lo[1], hi[1])
    ax1.set_zlim(lo[2], hi[2])
    ax1.set_box_aspect(np.maximum(hi - lo, 1e-3 * (hi - lo).max()))
    ax1.set_xlabel("x [mm]")
    ax1.set_ylabel("y [mm]")
    ax1.set_zlabel("z [mm]")
    handles = [
        matplotlib_patch(COLOURS.get(n, "0.5"), n) for n in groups if n != "body" and len(groups[n])
    ]
    ax1.legend(handles=handles, loc="upper left", fontsize=7)
    ax2 = fig.add_subplot(1, 2, 2)
    if info.kind == "ball":
        ax1.view_init(elev=-30, azim=-110)
        e = groups["contact"]
        ax2.triplot(x[:, 0] * mm, x[:, 1] * mm, e, color=COLOURS["contact"], lw=0.25)
        ax2.set_title("contact cap seen from the flat")
        ax2.set_xlabel("x (sliding) [mm]")
        ax2.set_ylabel("y [mm]")
    else:
        ax1.view_init(elev=12, azim=-160)
        e = groups["periodic_left"]
        r = np.hypot(x[:, 0], x[:, 1])
        ax2.triplot(x[:, 2] * mm, r * mm, e, color="0.4", lw=0.2)
        band = groups["contact"]
        # the band's trace on the periodic face
        th = np.arctan2(x[:, 1], x[:, 0])
        nodes = np.unique(band)
        nodes = nodes[abs(th[nodes] + 0.5 * info.extra["angle"]) < 1e-9]
        nodes = nodes[np.argsort(x[nodes, 2])]
        ax2.plot(x[nodes, 2] * mm, r[nodes] * mm, color=COLOURS["contact"], lw=2, label="contact")
        ax2.legend(loc="upper right", fontsize=7)
        ax2.set_title(
            f"periodic face (r, z); sector angle {info.extra['angle'] * 1e3:.3g} mrad, "
            f"band h = {info.extra['h_band'] * 1e6:.3g} um, {len(band)} band triangles"
        )
        ax2.set_xlabel("z (axial) [mm]")
        ax2.set_ylabel("r [mm]")
    ax2.set_aspect("equal")


def matplotlib_patch(colour: str, label: str) -> Any:
    """A legend patch."""
    from matplotlib.patches import Patch

    return Patch(facecolor=colour, edgecolor="0.3", label=label)
