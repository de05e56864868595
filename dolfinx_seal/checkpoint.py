"""Checkpoints of a continuation: the converged state of the last finished point,
so that a killed sweep resumes from it (``dolfinx-seal sweep ... --resume``).

A checkpoint is one file, ``<out>/checkpoint/state.npz``, written by rank 0
atomically (temporary name, fsync, rename: :func:`dolfinx_seal.output.atomic_path`)
after each converged point and before its ``sweep.csv`` row, so a kill leaves
the previous checkpoint or the new one.  It holds ``meta``, a JSON record of the
point (its index in the walk, sweep value, rows written with it, failed
targets so far), and every unknown as *(dof coordinates, component, value)* of
the owned dofs of every rank.

Why coordinates and not the local arrays: DOLFINx's only graph partitioner in
this build is PT-Scotch, whose partitions differ from one run to the next
(measured: the same 2-rank mesh built twice gave 749 and 745 local film dofs),
so local dof numbers do not survive a restart.  A dof is found again by its
position (and its component in a vector or mixed space), which is the same
for every partition and every number of ranks: a sweep may be resumed on
another number of ranks.  Spaces with a single global dof (the counter
position, a real space) are matched by component alone.

:func:`load` fills the functions only if every local dof, ghosts included,
finds a saved dof within :data:`MATCH_TOLERANCE` of the mesh extent; a
checkpoint of another mesh or problem is refused with the reason logged, and
the caller recomputes from the scene's own start.  Both are collective.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from dolfinx_seal.mpi import get_logger, world
from dolfinx_seal.output import atomic_path

#: Folder of the checkpoint inside a sweep's output folder.
FOLDER = "checkpoint"

#: The checkpoint file in :data:`FOLDER`.
FILE = "state.npz"

#: Format of the checkpoint file (bumped when its content changes).
FORMAT = 2

#: Largest distance between a dof and its saved twin, relative to the extent of
#: the dof coordinates (dof coordinates of one mesh agree to round-off, ~1e-16
#: relative; the closest two dofs of a mesh are an element size, >= 1e-6 of it).
MATCH_TOLERANCE = 1e-9


def _leaves(V: Any) -> list[tuple[np.ndarray, int, np.ndarray, bool]]:
    """(coordinates (n, 3), block size, parent dofs (n * bs), single) of each
    leaf space of ``V``: its collapsed scalar or blocked sub-spaces, recursively;
    ``parent dofs`` index ``V``'s local array (unrolled, ghosts included), and
    ``single`` marks a space with one global dof (matched without coordinates)."""
    bs = V.dofmap.index_map_bs
    if V.num_sub_spaces == 0 or bs > 1:
        im = V.dofmap.index_map
        n = im.size_local + im.num_ghosts
        coords = V.tabulate_dof_coordinates()[:n]
        return [(coords, bs, np.arange(n * bs, dtype=np.int64), im.size_global == 1)]
    out = []
    for i in range(V.num_sub_spaces):
        Vi, parent = V.sub(i).collapse()
        parent = np.asarray(parent, dtype=np.int64)
        out += [(c, b, parent[d], s) for c, b, d, s in _leaves(Vi)]
    return out


def _owned(V: Any) -> int:
    """Number of owned entries (unrolled) of ``V``'s local array."""
    return V.dofmap.index_map.size_local * V.dofmap.index_map_bs


def save(
    out_dir: str | Path, functions: Sequence[Any], meta: Mapping[str, Any], comm: Any = None
) -> Path:
    """Write the checkpoint of ``functions`` with the record ``meta`` (collective)."""
    comm = comm or world()
    path = Path(out_dir) / FOLDER / FILE
    payload: dict[str, np.ndarray] = {}
    for b, f in enumerate(functions):
        owned = _owned(f.function_space)
        for j, (coords, bs, dofs, _single) in enumerate(_leaves(f.function_space)):
            k = np.flatnonzero(dofs < owned)  # this rank's own entries
            parts = comm.gather(
                (np.repeat(coords, bs, axis=0)[k], (k % bs).astype(np.int8), f.x.array[dofs[k]]),
                root=0,
            )
            if comm.rank == 0:
                payload[f"x_{b}_{j}"] = np.concatenate([p[0] for p in parts])
                payload[f"c_{b}_{j}"] = np.concatenate([p[1] for p in parts])
                payload[f"v_{b}_{j}"] = np.concatenate([p[2] for p in parts])
    if comm.rank == 0:
        path.parent.mkdir(parents=True, exist_ok=True)
        record = json.dumps({"format": FORMAT, "blocks": len(functions), **meta})
        with atomic_path(path) as tmp, open(tmp, "xb") as fh:
            np.savez(fh, meta=np.array(record), **payload)
            fh.flush()
    comm.barrier()
    return path


def read_meta(out_dir: str | Path, comm: Any = None) -> dict[str, Any] | None:
    """The record of the checkpoint in ``out_dir`` (``None``, with the reason logged,
    if there is none or it cannot be read).  Collective: read on rank 0."""
    comm = comm or world()
    path = Path(out_dir) / FOLDER / FILE
    meta, why = None, None
    if comm.rank == 0:
        if not path.is_file():
            why = f"there is no {FOLDER}/{FILE}"
        else:
            try:
                with np.load(path, allow_pickle=False) as data:
                    meta = json.loads(str(data["meta"]))
            except Exception as e:  # not ours, or damaged by something other than a kill
                why = f"{path} cannot be read ({type(e).__name__}: {e})"
            if meta is not None and meta.get("format") != FORMAT:
                why, meta = f"{path} has format {meta.get('format')!r}, not {FORMAT}", None
        if why:
            get_logger().warning("checkpoint not used: %s", why)
    return comm.bcast(meta, root=0) if comm.size > 1 else meta


def load(out_dir: str | Path, functions: Sequence[Any], comm: Any = None) -> dict[str, Any] | None:
    """Fill ``functions`` (every local entry, ghosts included) from the checkpoint and
    return its record, or return ``None`` (functions untouched, reason logged) if
    there is none or it is not of these functions on this mesh.  Collective."""
    comm = comm or world()
    meta = read_meta(out_dir, comm)
    if meta is None:
        return None
    why = None
    if meta.get("blocks") != len(functions):
        why = f"it holds {meta.get('blocks')} unknowns, the problem has {len(functions)}"
    values: list[list[tuple[np.ndarray, np.ndarray]]] = []
    if why is None:
        with np.load(Path(out_dir) / FOLDER / FILE, allow_pickle=False) as data:
            for b, f in enumerate(functions):
                values.append([])
                for j, (coords, bs, dofs, single) in enumerate(_leaves(f.function_space)):
                    if f"x_{b}_{j}" not in data:
                        why = f"unknown {f.name!r} has more sub-spaces than the checkpoint's"
                        break
                    found = _match(data[f"x_{b}_{j}"], data[f"c_{b}_{j}"], data[f"v_{b}_{j}"],
                                   np.repeat(coords, bs, axis=0), np.arange(dofs.size) % bs,
                                   single)  # fmt: skip
                    if isinstance(found, str):
                        why = f"unknown {f.name!r}: {found}"
                        break
                    values[-1].append((dofs, found))
                if why:
                    break
    whys = comm.allgather(why)
    if any(whys):
        if comm.rank == 0:
            get_logger().warning(
                "checkpoint not used: it is not of this problem (%s)", next(w for w in whys if w)
            )
        return None
    for f, leaves in zip(functions, values, strict=True):
        for dofs, v in leaves:
            f.x.array[dofs] = v
    return meta


def _match(
    saved_x: np.ndarray, saved_c: np.ndarray, saved_v: np.ndarray,
    x: np.ndarray, comp: np.ndarray, single: bool,
) -> np.ndarray | str:  # fmt: skip
    """Values of the saved dofs at ``x`` (component ``comp``), or why they are not there."""
    out = np.empty(x.shape[0])
    extent = float(np.ptp(saved_x, axis=0).max()) if saved_x.size else 0.0
    tol = MATCH_TOLERANCE * max(extent, 1e-300)
    for c in np.unique(comp):
        mine, theirs = np.flatnonzero(comp == c), np.flatnonzero(saved_c == c)
        if single:
            if theirs.size != 1:
                return f"{theirs.size} saved dofs of a single-dof space"
            out[mine] = saved_v[theirs[0]]
            continue
        if theirs.size == 0:
            return f"no saved dofs of component {int(c)}"
        dist, at = cKDTree(saved_x[theirs]).query(x[mine])
        if mine.size and float(dist.max()) > tol:
            return f"a dof {float(dist.max()):.3g} m from the nearest saved one (another mesh)"
        out[mine] = saved_v[theirs[at]]
    return out


def remove(out_dir: str | Path, comm: Any = None) -> None:
    """Delete the checkpoint folder (rank 0; collective), once a sweep has finished."""
    comm = comm or world()
    comm.barrier()
    if comm.rank == 0:
        shutil.rmtree(Path(out_dir) / FOLDER, ignore_errors=True)
    comm.barrier()


__all__ = ["FILE", "FOLDER", "FORMAT", "MATCH_TOLERANCE", "load", "read_meta", "remove", "save"]
