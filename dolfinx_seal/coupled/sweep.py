"""Stribeck rows of lubricated sweeps: the curve's plot and its minimum.

The sweep itself (speed continuation, incremental output) is
:meth:`dolfinx_seal.scenes.lubricated.LubricatedScene.sweep`; these act on the
rows it returns (``eta_v``, ``mu`` and its parts, the load split, film thickness).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np


def plot_sweep(rows: list[dict[str, Any]], out_dir: Path, name: str) -> None:
    """Stribeck curve mu(eta v) with its parts, the load split and the film
    thickness (``sweep.png``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = sorted(rows, key=lambda r: float(r["eta_v"]))
    ev = np.array([float(r["eta_v"]) for r in rows])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    ax1.loglog(ev, [float(r["mu"]) for r in rows], "ko-", ms=3, label="mu")
    for k, st in (("mu_asperity", "s--"), ("mu_couette", "^--"), ("mu_poiseuille", "v--")):
        if k in rows[0]:
            y = np.array([float(r[k]) for r in rows])
            ax1.loglog(ev[y > 0], y[y > 0], st, ms=3, label=k)
    ax1.set_xlabel("eta v [Pa m]")
    ax1.set_ylabel("friction coefficient")
    # parts far below the total (asperity friction in full film, 1e-11) would hide mu
    ax1.set_ylim(bottom=1e-2 * min(float(r["mu"]) for r in rows))
    ax1.legend(frameon=False, fontsize=8)
    ax2.semilogx(ev, [float(r["fluid_load_fraction"]) for r in rows], "bo-", ms=3, label="fluid")
    ax2.semilogx(
        ev, [1 - float(r["fluid_load_fraction"]) for r in rows], "rs-", ms=3, label="asperities"
    )
    ax2.set_xlabel("eta v [Pa m]")
    ax2.set_ylabel("load fraction")
    ax2.legend(frameon=False, loc="center left")
    ax3 = ax2.twinx()
    ax3.loglog(ev, [float(r["h_min"]) * 1e6 for r in rows], "g^:", ms=3, label="h_min")
    if "h_central" in rows[0]:
        ax3.loglog(ev, [float(r["h_central"]) * 1e6 for r in rows], "gv-", ms=3, label="h_central")
        ax3.legend(frameon=False, loc="lower right", fontsize=8)
    ax3.set_ylabel("film thickness [um] (green)")
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "sweep.png", dpi=120)
    plt.close(fig)


def stribeck_minimum(eta_v: Any, mu: Any) -> tuple[float, float, bool]:
    """(eta v, mu) of the minimum of a sampled Stribeck curve and whether it is
    bracketed (a neighbour on each side): the vertex of the parabola in
    (log eta v, log mu) through the smallest sample and its neighbours, else the
    smallest sample itself."""
    ev, m = np.asarray(eta_v, dtype=float), np.asarray(mu, dtype=float)
    order = np.argsort(ev)
    x, y = np.log10(ev[order]), np.log10(m[order])
    i = int(np.argmin(y))
    if i == 0 or i == len(x) - 1:
        return float(ev[order][i]), float(m[order][i]), False
    c2, c1, c0 = np.polyfit(x[i - 1 : i + 2], y[i - 1 : i + 2], 2)
    xv = -c1 / (2.0 * c2)
    return float(10**xv), float(10 ** (c0 + c1 * xv + c2 * xv * xv)), True


__all__ = ["plot_sweep", "stribeck_minimum"]
