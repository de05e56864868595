"""Newton step limits of the contact problem: pre-checks that scale a step down.

A stiff contact law (exponential in the gap) or a film (conductance ~ g^3)
makes a full Newton step from a poor state overshoot by decades; these
pre-checks (``step_limiter`` of :class:`~dolfinx_seal.solvers.NonlinearSolver`)
shorten a step so that no displacement dof, no normal displacement and no
contact gap changes by more than its limit (docs/design.md, solver strategy).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import dolfinx
import numpy as np

import dolfinx_seal.compat  # noqa: F401  (the quiet JIT, before any DOLFINx use)
from dolfinx_seal.params import check_positive, check_range
from dolfinx_seal.solvers.assembly import owned_block_offsets


@dataclass(frozen=True)
class StepLimits:
    """Largest changes of one Newton step (None: no limit).

    Attributes:
        max_step: Largest displacement change of any dof [m]: a step driven by
            the stiff contact law cannot invert elements.
        max_normal_step: Largest change of the displacement component along the
            counter-surface normal [m] (with a larger ``max_step``): the normal
            motion is what the stiff contact law drives and what can invert the
            thin contact elements, while friction shears a lubricated body
            sideways as a whole (the S1 cylinder by 14 um at its start), a smooth
            motion that a mesh-sized ``max_step`` would spread over more steps the
            finer the mesh.
        max_gap_step: Largest change of the gap at a contact node [m] (normal
            displacement minus counter-surface motion).  A few decay lengths of
            the contact law keep Newton on an exponential law from overshooting by
            decades of pressure.
        max_gap_closure: Largest fraction f (0-1) of its current value by which a
            contact gap may close in one step; it may open by at most the factor
            1/(1 - f).  For films, whose conductance goes as g^3: it keeps a step
            from a poor start from closing (or blowing open) the film, without
            slowing the far, wide gaps (which a fixed ``max_gap_step`` does).
            With both, a gap may always change by ``max_gap_step``.
    """

    max_step: float | None = None
    max_normal_step: float | None = None
    max_gap_step: float | None = None
    max_gap_closure: float | None = None

    def __post_init__(self) -> None:
        for name in ("max_step", "max_normal_step", "max_gap_step"):
            if getattr(self, name) is not None:
                check_positive(name, getattr(self, name), "m")
        if self.max_gap_closure is not None:
            check_range("max_gap_closure", self.max_gap_closure, 0.0, 1.0, lo_open=True,
                        hi_open=True)  # fmt: skip

    @property
    def any(self) -> bool:
        """Whether a displacement limit is set (max_step, max_gap_step or max_gap_closure)."""
        return bool(self.max_step or self.max_gap_step or self.max_gap_closure)


def displacement_limiter(
    prob: Any,
    max_step: float | None,
    max_gap_step: float | None,
    blocks: Sequence[Any] | None = None,
    closure: float | None = None,
) -> Callable[[np.ndarray, np.ndarray], float]:
    """Pre-check scaling a Newton step so that no displacement dof moves more than
    ``max_step``, no contact gap changes by more than ``max_gap_step`` and none
    closes by more than the fraction ``closure`` of itprob.

    ``blocks``: the block layout of the solver it serves (default the
    problem's); the counter position counts when it is the last block.

    The displacement dofs come first in the (block) vector, so their local
    indices are those of the collapsed displacement sub-space (owned part);
    the counter position (force control) follows the field block.
    """
    Vu = prob.W.sub(0) if prob.material.mixed else prob.W
    n_own = prob.W.dofmap.index_map.size_local * prob.W.dofmap.index_map_bs
    if prob.material.mixed:
        _, dofs = Vu.collapse()
        dofs = np.asarray(dofs)
    else:
        dofs = np.arange(n_own)
    dofs = dofs[dofs < n_own]
    max_normal = prob.limits.max_normal_step
    axis = prob.counter.normal_axis
    normal_dofs = np.asarray(Vu.sub(axis).collapse()[1])
    normal_dofs = normal_dofs[normal_dofs < n_own]
    fdim = prob.mesh.topology.dim - 1
    sub = Vu.sub(axis)
    collapsed, _ = sub.collapse()
    ndofs, cdofs = dolfinx.fem.locate_dofs_topological(
        (sub, collapsed), fdim, prob.facet_tags.find(prob.contact_tag)
    )
    owned = ndofs < n_own
    ndofs = ndofs[owned]
    # reference coordinate normal to the counter-surface of those dofs [m]
    Xn = collapsed.tabulate_dof_coordinates()[cdofs[owned], axis]
    if max_step:
        check_positive("max_step", max_step, "m")
    if max_gap_step:
        check_positive("max_gap_step", max_gap_step, "m")
    comm = prob.mesh.comm
    blocks = prob.blocks if blocks is None else blocks
    position_free = prob.control == "force" and blocks[-1][1] is prob.position
    pos_index = int(owned_block_offsets([b[1] for b in blocks])[-2])

    def limit(x: np.ndarray, dx: np.ndarray) -> float:
        s = 1.0
        if max_step:
            big = float(np.abs(dx[dofs]).max(initial=0.0))
            if big > max_step:
                s = min(s, max_step / big)
        if max_step and max_normal:
            big = float(np.abs(dx[normal_dofs]).max(initial=0.0))
            if big > max_normal:
                s = min(s, max_normal / big)
        if max_gap_step or closure:
            # PETSc steps x -> x - dx: the gap changes by -(dx_n - dx_position)
            dpos = 0.0
            if position_free:  # the position dof is the last block
                mine = (float(x[pos_index]), float(dx[pos_index])) if prob._owns_position else None
                pos, dpos = comm.bcast(mine, root=prob._pos_root)
            elif closure:
                pos = prob.counter_position()
            dg = dpos - dx[ndofs]
        if max_gap_step and not closure:
            dgap = np.abs(dg).max(initial=0.0)
            if dgap > max_gap_step:
                s = min(s, max_gap_step / dgap)
        if closure:  # g_new / g in [1 - closure, 1 / (1 - closure)], or |dg| <= max_gap_step
            gap = np.maximum(Xn + x[ndofs] - pos, 0.0)
            floor = max_gap_step or 0.0
            allowed = np.where(dg < 0.0, closure, closure / (1.0 - closure)) * gap
            allowed = np.maximum(allowed, floor)
            moving = np.abs(dg) > allowed
            if moving.any():
                s = min(s, float((allowed[moving] / np.abs(dg[moving])).min()))
        return s

    return limit


class SurfaceGapLimiter:
    """Pre-check limiting how much a Newton step closes the contact gaps, with the gap
    and the counter normal evaluated from the problem itself (``prob.gap`` and
    ``prob.counter.normal``), for counter-surfaces whose normal is no coordinate
    axis and gaps that carry a resolved roughness (:class:`~dolfinx_seal.solid.counter_surface.Shaft3D`,
    :class:`~dolfinx_seal.solid.counter_surface.WithSurfaceHeight`), where
    :func:`displacement_limiter`'s ``closure`` (a coordinate minus the position)
    does not apply.

    At each contact node of the displacement (fixed counter position) the step
    changes the gap by ``dg = n . du``; it may close a positive gap by at most the
    fraction ``closure`` of itself and open it by at most ``1 / (1 - closure)``, or
    change it by :attr:`floor` [m], whichever is larger, but take no positive gap
    more than :attr:`crossing` [m] below zero, nor close one at or below zero by
    more than that; a gap at or below zero may open freely.
    The current state is the one the problem's functions hold (the solver
    evaluated its residual and Jacobian there before the step).

    Attributes:
        floor: The change [m] every gap may make whatever its size: it lets
            Newton close many small gaps at once.
        crossing: How far past zero [m] one step may close a gap (``inf``: no
            limit); settable between solves (:meth:`crossing_set`).  A resolved
            crest near zero separation is then not driven through it, by up to
            the floor, into the contact law's steep continuation below its
            window.
    """

    def __init__(self, prob: Any, closure: float, floor: float) -> None:
        import dolfinx.fem as fem
        import dolfinx.mesh as dmesh

        from dolfinx_seal.compat import interpolation_points

        check_range("closure", closure, 0.0, 1.0, lo_open=True, hi_open=True)
        check_positive("floor", floor, "m")
        self.closure, self.floor = float(closure), float(floor)
        self.crossing = math.inf
        Vu = prob.W.sub(0) if prob.material.mixed else prob.W
        n_own = prob.W.dofmap.index_map.size_local * prob.W.dofmap.index_map_bs
        self._gdim = gdim = prob.mesh.geometry.dim
        fdim = prob.mesh.topology.dim - 1
        facets = prob.facet_tags.find(prob.contact_tag)
        parents, nodes = [], None
        for c in range(gdim):
            sub = Vu.sub(c)
            collapsed, _ = sub.collapse()
            parent, cd = fem.locate_dofs_topological((sub, collapsed), fdim, facets)
            keep = parent < n_own
            parents.append(np.asarray(parent[keep]))
            if nodes is None:
                S, nodes = collapsed, np.asarray(cd[keep])
        self._parents, self._nodes = parents, nodes
        prob.mesh.topology.create_connectivity(fdim, prob.mesh.topology.dim)
        self._cells = dmesh.compute_incident_entities(prob.mesh.topology, facets, fdim, fdim + 1)
        pts = interpolation_points(S.element)
        normal = prob.counter.normal(prob.x)
        self._comm = comm = prob.mesh.comm
        self._exprs = [
            fem.Expression(e, pts, comm=comm) for e in (prob.gap, *(normal[c] for c in range(gdim)))
        ]
        self._funcs = [fem.Function(S) for _ in self._exprs]
        # force control: the counter position (the last block) moves too, and the gap
        # (coordinate along the normal minus the position) with it
        self._prob = prob
        self._pos_index = _position_index(prob) if prob.control == "force" else None

    @contextmanager
    def crossing_set(self, crossing: float) -> Iterator[None]:
        """:attr:`crossing` [m] inside the block, restored on leaving it (also on error)."""
        check_positive("crossing", crossing, "m")
        saved, self.crossing = self.crossing, float(crossing)
        try:
            yield
        finally:
            self.crossing = saved

    @property
    def contact_dofs(self) -> tuple[np.ndarray, ...]:
        """Per displacement component, the owned dofs of the contact nodes in the
        solver's vector (the order of :meth:`nodal_gap`'s values)."""
        return tuple(self._parents)

    def nodal_gap(self) -> tuple[np.ndarray, np.ndarray]:
        """The gap [m] and the counter normal (one row per component) at the owned
        contact nodes, evaluated from the state the problem's functions hold."""
        for f, e in zip(self._funcs, self._exprs, strict=True):
            f.interpolate(e, cells0=self._cells)
        nodes = self._nodes
        normal = np.array([self._funcs[1 + c].x.array[nodes] for c in range(self._gdim)])
        return self._funcs[0].x.array[nodes].copy(), normal

    def __call__(self, x: np.ndarray, dx: np.ndarray) -> float:
        g, normal = self.nodal_gap()
        # PETSc steps x -> x - dx: the surface moves by -dx, the gap by n . (-dx)
        dg = -sum(normal[c] * dx[self._parents[c]] for c in range(self._gdim))
        prob = self._prob
        if self._pos_index is not None:  # and the position by -dx: the gap by +dx
            mine = float(dx[self._pos_index]) if prob._owns_position else None
            dg = dg + self._comm.bcast(mine, root=prob._pos_root)
        closure = self.closure
        gp = np.maximum(g, 0.0)
        floor = np.minimum(self.floor, gp + self.crossing)  # closing: not past -crossing
        allowed = np.where(dg < 0.0, np.maximum(closure * gp, floor),
                           np.maximum(closure / (1.0 - closure) * gp, self.floor))  # fmt: skip
        allowed[(g <= 0.0) & (dg > 0.0)] = np.inf
        moving = np.abs(dg) > allowed
        if not moving.any():
            return 1.0
        return float((allowed[moving] / np.abs(dg[moving])).min())


def _position_index(prob: Any) -> int:
    """Local index of the counter position (the last block, force control) in the
    solver's vector on its owning rank: after the owned entries of the other blocks."""
    return int(owned_block_offsets([b[1] for b in prob.blocks])[-2])


def rigid_gap_limiter(prob: Any) -> Callable[[np.ndarray, np.ndarray], float]:
    """Pre-check for a rigid body under force control: one Newton step may change
    the smallest gap by at most half of itself (the film conductance ~ g^3
    makes a full step from a poor guess overshoot by decades)."""
    _, xn = prob.surface_values(prob.counter.gap(prob.X, 0.0))
    lowest = float(xn.min())
    comm = prob.mesh.comm
    pos_index = _position_index(prob)

    def limit(x: np.ndarray, dx: np.ndarray) -> float:
        mine = (float(x[pos_index]), float(dx[pos_index])) if prob._owns_position else None
        pos, dpos = comm.bcast(mine, root=prob._pos_root)
        gap0 = lowest - pos
        # the gap changes by dpos: at most half of itself per step, either way
        if gap0 > 0 and abs(dpos) > 0.5 * gap0:
            return 0.5 * gap0 / abs(dpos)
        return 1.0

    return limit


__all__ = ["StepLimits", "SurfaceGapLimiter", "displacement_limiter", "rigid_gap_limiter"]
