"""Serial = parallel checks: copy a distributed solution into a one-rank problem.

A problem built by Gmsh on rank 0 has the same mesh on any communicator, so a
field solved on ``COMM_WORLD`` can be copied dof by dof (matched by the dof
coordinates) into the same problem built on ``COMM_SELF``; a Newton solve
there must then stop at once if the parallel solution solves the same
discrete problem.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def copy_coupled_state(src: Any, dst: Any) -> None:
    """Copy the displacement, mixed pressure and fluid pressure of the coupled
    problem ``src`` (any communicator) into ``dst`` (the same problem, e.g. built on
    one rank with the counter held at ``src``'s position)."""
    for i in range(2):  # displacement, mixed pressure
        copy_by_coordinates(src.W.sub(i), src.w, dst.W.sub(i), dst.w)
    copy_by_coordinates(src.film.S, src.film.P, dst.film.S, dst.film.P)


def copy_by_coordinates(V_src: Any, f_src: Any, V_dst: Any, f_dst: Any, tol: float = 1e-12) -> None:
    """Copy the values of (sub-)space ``V_src`` of ``f_src`` (any communicator) into
    ``V_dst`` of ``f_dst`` by matching dof coordinates (collective on ``f_src``'s
    communicator).

    Raises:
        ValueError: A destination dof has no source dof within ``tol`` [m].
    """
    from scipy.spatial import cKDTree

    def table(V: Any, f: Any) -> tuple[np.ndarray, np.ndarray]:
        try:
            Vc, dofs = V.collapse()
        except RuntimeError:  # not a sub-space
            Vc, dofs = V, np.arange(f.x.array.size)
        bs = Vc.dofmap.index_map_bs
        n = Vc.dofmap.index_map.size_local
        X = Vc.tabulate_dof_coordinates()[:n]
        dofs = np.asarray(dofs).reshape(-1, bs)[:n]
        return X, dofs

    Xs, ds = table(V_src, f_src)
    vals = f_src.x.array[ds]
    comm = f_src.function_space.mesh.comm
    Xs = np.concatenate(comm.allgather(Xs))
    vals = np.concatenate(comm.allgather(vals))
    Xd, dd = table(V_dst, f_dst)
    dist, idx = cKDTree(Xs).query(Xd)
    if dist.size and dist.max() > tol:
        raise ValueError(f"dof coordinates differ by {dist.max():.3g} m (> tol = {tol:g} m)")
    f_dst.x.array[dd] = vals[idx]
    f_dst.x.scatter_forward()
