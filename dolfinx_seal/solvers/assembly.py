"""Assembly strategies of :class:`~dolfinx_seal.solvers.NonlinearSolver`: the assembly seam.

The SNES wrapper does not assemble anything itself: an :class:`Assembly` creates the
PETSc matrix and vectors, assembles the residual ``F(x)`` and the Jacobian, copies
between the PETSc vector and the unknown :class:`dolfinx.fem.Function` (s), and says
which dofs are not free unknowns (multi-point-constraint slaves).  Two strategies:

* :class:`PlainAssembly` (the default): DOLFINx assembly, single field or blocked
  (a monolithic block vector/matrix, e.g. a field plus a real unknown);
* :class:`MPCAssembly`: dolfinx_mpc assembly with multi-point constraints
  (periodicity, periodicity with rotation of a vector field, slip, ...), one
  constraint for a single field or one per block (``None`` for a block without
  constraints).  The unknowns must live on ``mpc.function_space`` (the space the
  constraint builds when it is finalized: same owned dofs, more ghosts).

MPC convention (dolfinx_mpc 0.9, ``python/tests/test_nonlinear_assembly.py``): the
system is ``K^T F(K x)`` with ``K`` the constraint's prolongation from masters to
all dofs; slave rows of the Jacobian hold ``1`` on the diagonal and slave rows of
the residual are zero, so the Newton update vanishes on the slaves.  The slaves
are recovered by ``mpc.backsubstitution`` each time the PETSc vector is copied into
the functions (before every residual and Jacobian, and at the end), and the
update is homogenised (slave entries set to zero) in the line-search pre-check.
Bounds of a variational inequality live on the masters: the solver sets the
slaves' bounds to ``-inf, +inf`` (:meth:`Assembly.constrained_dofs`), so the VI
never freezes a slave, and a slave equal to its master (periodicity) satisfies
the master's bound.

:func:`add_rotational_periodic_constraint` adds ``u(x_s) = R u(x_m)`` for a vector
field on a sector (the slave displacement is the master one rotated by the sector
angle), built from dolfinx_mpc's periodic search per component.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from typing import Any

import dolfinx
import dolfinx.fem.petsc as fem_petsc
import numpy as np
from petsc4py import PETSc

from dolfinx_seal import compat
from dolfinx_seal.errors import ParameterError


class Assembly(ABC):
    """The strategy protocol (and the common part of both strategies).

    The solver calls :meth:`setup` once with the compiled forms, the unknown(s)
    and the Dirichlet conditions; then :meth:`create_vector`,
    :meth:`create_matrix`; and at each Newton step :meth:`to_functions`,
    :meth:`residual`, :meth:`jacobian`, :meth:`homogenize`.
    """

    blocked: bool = False

    def trial_space(self, F: Any, u: Any) -> Any:
        """Space of the trial function of the default Jacobian ``dF/du`` (UFL form ``F``)."""
        return u.function_space

    def setup(self, L: Any, a: Any, u: Any, bcs: Sequence[Any]) -> None:
        """Take the compiled residual form(s) ``L``, Jacobian form(s) ``a``, unknown(s), bcs."""
        self.L, self.a, self.u, self.bcs = L, a, u, list(bcs)
        self.blocked = isinstance(L, list | tuple)
        self.comm = (self.u[0] if self.blocked else self.u).function_space.mesh.comm

    def set_bcs(self, bcs: Sequence[Any]) -> None:
        """Replace the Dirichlet conditions (same spaces; the matrix keeps its pattern:
        a Dirichlet row only loses entries)."""
        self.bcs = list(bcs)

    @abstractmethod
    def create_vector(self) -> PETSc.Vec:
        """A residual vector (the solution vector is a duplicate)."""

    @abstractmethod
    def create_matrix(self) -> PETSc.Mat:
        """The Jacobian matrix, with its sparsity pattern."""

    @abstractmethod
    def residual(self, x: PETSc.Vec, b: PETSc.Vec) -> None:
        """``b = F(x)`` (the functions already hold ``x``); Dirichlet rows hold ``x - g``."""

    @abstractmethod
    def jacobian(self, A: PETSc.Mat) -> None:
        """``A = dF/dx`` at the functions' values (zeroed first, ``1`` on bc rows)."""

    @abstractmethod
    def assemble_linear(self, forms: Any, b: PETSc.Vec) -> None:
        """Assemble linear form(s) (one per block) into ``b`` without bcs (e.g. lumped mass)."""

    def to_functions(self, x: PETSc.Vec) -> None:
        """Copy the solution vector into the unknown function(s), ghosts included."""
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        if self.blocked:
            compat.block_to_functions(x, self.u)
        else:
            x.copy(self.u.x.petsc_vec)
            self.u.x.scatter_forward()

    def from_functions(self, x: PETSc.Vec) -> None:
        """Copy the unknown function(s)' owned values into the solution vector."""
        if self.blocked:
            compat.functions_to_block(self.u, x)
        else:
            self.u.x.petsc_vec.copy(x)

    def constrained_dofs(self) -> np.ndarray:
        """Owned indices into the solution vector that are not free unknowns (MPC slaves)."""
        return np.zeros(0, dtype=np.int32)

    def homogenize(self, dx: np.ndarray) -> None:
        """Zero the update ``dx`` (owned array of the solution vector) on constrained dofs."""
        dx[self.constrained_dofs()] = 0.0

    def destroy(self) -> None:  # noqa: B027 - optional hook: the plain strategy owns nothing
        """Free PETSc objects owned by the strategy (collective)."""


class PlainAssembly(Assembly):
    """DOLFINx assembly: single field, or blocked with a monolithic block layout."""

    def create_vector(self) -> PETSc.Vec:
        if self.blocked:
            return compat.create_vector_block(self.L)
        return fem_petsc.create_vector(self.L)

    def create_matrix(self) -> PETSc.Mat:
        if self.blocked:
            return compat.create_matrix_block(self.a)
        return fem_petsc.create_matrix(self.a)

    def residual(self, x: PETSc.Vec, b: PETSc.Vec) -> None:
        if self.blocked:
            compat.assemble_residual_block(b, self.L, self.a, self.bcs, x)
            return
        with b.localForm() as bl:
            bl.set(0.0)
        fem_petsc.assemble_vector(b, self.L)
        fem_petsc.apply_lifting(b, [self.a], bcs=[self.bcs], x0=[x], alpha=-1.0)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(b, self.bcs, x, -1.0)

    def jacobian(self, A: PETSc.Mat) -> None:
        if self.blocked:
            compat.assemble_jacobian_block(A, self.a, self.bcs)
            return
        A.zeroEntries()
        fem_petsc.assemble_matrix(A, self.a, bcs=self.bcs)
        A.assemble()

    def assemble_linear(self, forms: Any, b: PETSc.Vec) -> None:
        if self.blocked:
            funcs = []
            for f, ui in zip(forms, self.u, strict=True):
                m = dolfinx.fem.Function(ui.function_space)
                fem_petsc.assemble_vector(m.x.petsc_vec, f)
                m.x.petsc_vec.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
                funcs.append(m)
            compat.functions_to_block(funcs, b)
            return
        with b.localForm() as bl:
            bl.set(0.0)
        fem_petsc.assemble_vector(b, forms)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)


class MPCAssembly(Assembly):
    """dolfinx_mpc assembly with multi-point constraints.

    Args:
        constraints: A finalized ``dolfinx_mpc.MultiPointConstraint`` (single-field
            problem; the field may live in a mixed space, the constraint on a
            sub-space of it), or for a blocked problem a list with one entry per
            block: a finalized constraint or ``None`` (no constraint on that block,
            e.g. a real-space unknown).  Each unknown must be a Function on its
            constraint's ``function_space``; the forms' test functions (and the
            trial functions of a Jacobian given explicitly) are on the space ``V``
            the constraint was created on.

    A blocked problem is assembled block by block (dolfinx_mpc 0.9 assembles MPC
    blocks only as separate matrices, its "nest" layout) and copied into a
    monolithic AIJ matrix and block vector, the layout that the VI solvers
    (which read the vectors as arrays) and LU factorisations need.
    """

    def __init__(self, constraints: Any) -> None:
        self._given = constraints  # one strategy object per solver: setup() binds it

    def trial_space(self, F: Any, u: Any) -> Any:
        """The test space of ``F`` (the unconstrained space ``V``): dolfinx_mpc assembles
        square forms on ``V`` while the unknown lives on ``mpc.function_space``."""
        return F.arguments()[0].ufl_function_space()

    def setup(self, L: Any, a: Any, u: Any, bcs: Sequence[Any]) -> None:
        import dolfinx_mpc

        super().setup(L, a, u, bcs)
        self._mpc = dolfinx_mpc
        us = list(u) if self.blocked else [u]
        given = self._given
        if self.blocked:
            if not isinstance(given, list | tuple) or len(given) != len(us):
                raise ParameterError(
                    "MPCAssembly.constraints: a blocked problem needs a list with one "
                    f"constraint (or None) per block, {len(us)} blocks; got {given!r}"
                )
            given = list(given)
        else:
            if isinstance(given, list | tuple):
                raise ParameterError(
                    "MPCAssembly.constraints: a single-field problem takes one constraint, "
                    f"got a list of {len(given)}"
                )
            given = [given]
        mpcs = []
        for i, (c, ui) in enumerate(zip(given, us, strict=True)):
            if c is None:
                c = dolfinx_mpc.MultiPointConstraint(ui.function_space)
                c.finalize()
            elif not c.finalized:
                raise ParameterError(f"MPCAssembly.constraints[{i}]: finalize() the constraint")
            V, W = c.function_space, ui.function_space
            im, jm = V.dofmap.index_map, W.dofmap.index_map
            if (im.size_local, im.num_ghosts, V.dofmap.index_map_bs) != (
                jm.size_local,
                jm.num_ghosts,
                W.dofmap.index_map_bs,
            ):
                raise ParameterError(
                    f"MPCAssembly.constraints[{i}]: the unknown must be a Function on the "
                    "constraint's function_space (mpc.function_space, which ghosts the masters)"
                )
            mpcs.append(c)
        self.mpcs = mpcs
        self._maps = [
            (c.function_space.dofmap.index_map, c.function_space.dofmap.index_map_bs) for c in mpcs
        ]
        owned = []
        offset = 0
        for c, (im, bs) in zip(mpcs, self._maps, strict=True):
            n = im.size_local * bs
            s = np.asarray(c.slaves, dtype=np.int64)
            owned.append(offset + s[s < n])
            offset += n
        self._slaves = np.unique(np.concatenate(owned)).astype(np.int32)
        self._nest: PETSc.Mat | None = None
        self._bvecs: list[PETSc.Vec] = []

    # ------------------------------------------------------------ objects
    def _block_vec(self, i: int) -> PETSc.Vec:
        im, bs = self._maps[i]
        return dolfinx.la.create_petsc_vector(im, bs)

    def create_vector(self) -> PETSc.Vec:
        if not self.blocked:
            return self._block_vec(0)
        self._bvecs = [self._block_vec(i) for i in range(len(self.mpcs))]
        return compat.create_vector_block_from_maps(self._maps)

    def create_matrix(self) -> PETSc.Mat:
        create = self._mpc.cpp.mpc.create_matrix
        if not self.blocked:
            m = self.mpcs[0]._cpp_object
            return create(self.a._cpp_object, m, m)
        n = len(self.mpcs)
        blocks = [
            [
                None
                if self.a[i][j] is None
                else create(
                    self.a[i][j]._cpp_object, self.mpcs[i]._cpp_object, self.mpcs[j]._cpp_object
                )
                for j in range(n)
            ]
            for i in range(n)
        ]
        self._nest = PETSc.Mat().createNest(blocks, comm=self.comm)
        # the blocks must be assembled with values before the nest is assembled or
        # converted: assembling an empty block squeezes out its preallocated pattern,
        # and later values are then dropped silently
        self._assemble_blocks()
        return self._nest.convert("aij", out=PETSc.Mat())  # a new matrix, not in place

    def _assemble_blocks(self) -> None:
        n = len(self.mpcs)
        for i in range(n):
            for j in range(n):
                if self.a[i][j] is not None:
                    Aij = self._nest.getNestSubMatrix(i, j)
                    self._mpc.assemble_matrix(
                        self.a[i][j], (self.mpcs[i], self.mpcs[j]), bcs=self.bcs, A=Aij
                    )
        self._nest.assemble()

    # ----------------------------------------------------------- assembly
    def _bcs_on(self, V: Any) -> list[Any]:
        return [bc for bc in self.bcs if V.contains(bc.function_space)]

    def _residual_block(self, i: int, b: PETSc.Vec) -> None:
        mpc = self._mpc
        L = self.L[i] if self.blocked else self.L
        row = self.a[i] if self.blocked else [self.a]
        us = self.u if self.blocked else [self.u]
        mpc.assemble_vector(L, self.mpcs[i], b=b)  # zeroes b's local form first
        forms, bcs1, x0 = [], [], []
        for j, aij in enumerate(row):
            if aij is None:
                continue
            bj = self._bcs_on(aij.function_spaces[1])
            if bj:
                forms.append(aij)
                bcs1.append(bj)
                x0.append(us[j].x.petsc_vec)
        if forms:
            mpc.apply_lifting(
                b, forms, bcs=bcs1, constraint=self.mpcs[i], x0=x0, scale=np.float64(-1.0)
            )
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(b, self._bcs_on(L.function_spaces[0]), us[i].x.petsc_vec, -1.0)

    def residual(self, x: PETSc.Vec, b: PETSc.Vec) -> None:
        if not self.blocked:
            self._residual_block(0, b)
            return
        for i, bi in enumerate(self._bvecs):
            self._residual_block(i, bi)
        self._scatter_blocks(self._bvecs, b)

    def _scatter_blocks(self, parts: Sequence[PETSc.Vec], b: PETSc.Vec) -> None:
        """Owned values of the per-block vectors into the block vector (owned blocks in order)."""
        arr = b.getArray(readonly=False)
        start = 0
        for p in parts:
            owned = p.getArray(readonly=True)
            arr[start : start + owned.size] = owned
            start += owned.size
        del arr
        b.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)

    def jacobian(self, A: PETSc.Mat) -> None:
        mpc = self._mpc
        if not self.blocked:
            A.zeroEntries()
            mpc.assemble_matrix(self.a, self.mpcs[0], bcs=self.bcs, A=A)  # assembles A
            return
        self._assemble_blocks()
        self._nest.convert("aij", out=A)
        A.assemble()

    def assemble_linear(self, forms: Any, b: PETSc.Vec) -> None:
        if not self.blocked:
            self._mpc.assemble_vector(forms, self.mpcs[0], b=b)
            b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            return
        for f, c, bi in zip(forms, self.mpcs, self._bvecs, strict=True):
            self._mpc.assemble_vector(f, c, b=bi)
            bi.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self._scatter_blocks(self._bvecs, b)

    # ----------------------------------------------------------- unknowns
    def to_functions(self, x: PETSc.Vec) -> None:
        super().to_functions(x)
        for c, ui in zip(self.mpcs, self.u if self.blocked else [self.u], strict=True):
            c.backsubstitution(ui)  # slaves from the masters (and scatter_forward)

    def constrained_dofs(self) -> np.ndarray:
        return self._slaves

    def destroy(self) -> None:
        for v in self._bvecs:
            v.destroy()
        if self._nest is not None:
            self._nest.destroy()


#: relative size below which a master weight is round-off (:class:`ProjectedMPCAssembly`)
WEIGHT_FLOOR = 1e-10


class ProjectedMPCAssembly(MPCAssembly):
    """The system of :class:`MPCAssembly`, with the Jacobian assembled plainly and projected.

    ``J = P^T A P + D``: ``A`` the Jacobian assembled by DOLFINx without the
    constraints (Dirichlet rows and columns as usual), ``P`` the prolongation of
    the constraints in the solution vector's layout (identity on every dof but the
    slaves, whose rows hold their masters' weights; slave columns are zero), ``D``
    the identity on the slave rows; the product by PETSc's ``MatPtAP``, its
    pattern computed once.  That is dolfinx_mpc's matrix: the derivative of
    ``P^T F(P x)`` (the residual stays dolfinx_mpc's, :meth:`MPCAssembly.residual`).

    Why: dolfinx_mpc 0.9 condenses the constraint cell by cell, about ten times the
    plain assembly per cell that touches a slave; on a thin periodic sector
    (the lip sector is one roughness period wide) nearly every cell touches a
    periodic face (measured on a 5,080-cell lip sector, vector P2 + P1 mixed
    volume form: 7.4 s with dolfinx_mpc, 0.80 s plain).

    Requires that no master is a Dirichlet dof (a slave of a Dirichlet master would
    add its row to the Dirichlet row): checked at set-up.  Master weights below
    ``WEIGHT_FLOOR`` times the slave's largest are left out of ``P``: on matching
    periodic faces the point search of dolfinx_mpc returns the weights 1 and, for
    the other nodes of the cell it located the point in, round-off (about 1e-13;
    on the lip sector some of those nodes lie on the Dirichlet cut).  The
    Jacobian then differs from the exact one by that round-off.  Blocks without a
    constraint (``None``) take an identity ``P`` block.
    """

    def setup(self, L: Any, a: Any, u: Any, bcs: Sequence[Any]) -> None:
        super().setup(L, a, u, bcs)
        self._plain = PlainAssembly()
        self._plain.setup(L, a, u, bcs)
        self._P: PETSc.Mat | None = None
        self._pinned_slaves = self._slave_conditions()
        self._P = self._prolongation()
        self._D = self._slave_diagonal()
        self._check_masters()
        self._A: PETSc.Mat | None = None
        self._C: PETSc.Mat | None = None

    def set_bcs(self, bcs: Sequence[Any]) -> None:
        """New Dirichlet conditions (e.g. a film zone restricted after set-up).

        A slave may now carry a condition, with its master (a node on both cut
        faces of the new edge of the zone): its ``P`` row is zeroed (kept in the
        pattern), so its master's row is the master's own Dirichlet row (the
        residual's: dolfinx_mpc moves the slave's row into the master's, whose
        condition then overwrites it) and the slave holds its own condition.  A
        slave with a condition and a free master, or the reverse, has no
        consistent projected row: refused.
        """
        super().set_bcs(bcs)
        self._plain.set_bcs(bcs)
        self._pinned_slaves = self._slave_conditions()
        if self._P is not None:
            self._P.destroy()
        self._P = self._prolongation()
        self._check_masters()
        if self._C is not None:  # the product of the new P (the same pattern)
            self._C.destroy()
            self._C = self._A.PtAP(self._P)

    # ------------------------------------------------------------ layout
    def _global_indices(self) -> list[Callable[[np.ndarray], np.ndarray]]:
        """Per block: local dof indices (owned and ghosts of the constraint's space)
        -> global indices of the monolithic (DOLFINx block) layout."""
        comm = self.comm
        ranges = comm.allgather([im.local_range for im, _ in self._maps])
        bss = [bs for _, bs in self._maps]
        nb = len(self._maps)
        sizes = np.array([[(r[b][1] - r[b][0]) * bss[b] for b in range(nb)] for r in ranges])
        offset = np.concatenate(([0], np.cumsum(sizes.sum(axis=1))))[:-1]
        within = np.cumsum(np.hstack([np.zeros((sizes.shape[0], 1), dtype=int), sizes]), axis=1)
        starts = np.array([[r[b][0] for b in range(nb)] for r in ranges])
        me = comm.rank
        out = []
        for b, (im, bs) in enumerate(self._maps):
            ghosts = np.asarray(im.ghosts, dtype=np.int64)
            owners = np.asarray(im.owners, dtype=np.int64)
            n_own = im.size_local

            def to_global(loc: np.ndarray, b: int = b, bs: int = bs, n_own: int = n_own,
                          ghosts: np.ndarray = ghosts, owners: np.ndarray = owners) -> np.ndarray:  # fmt: skip
                loc = np.asarray(loc, dtype=np.int64)
                node, comp = loc // bs, loc % bs
                ghost = node >= n_own
                q = np.full(loc.shape, me, dtype=np.int64)
                g = starts[me, b] + node
                q[ghost] = owners[node[ghost] - n_own]
                g[ghost] = ghosts[node[ghost] - n_own]
                return offset[q] + within[q, b] + (g - starts[q, b]) * bs + comp

            out.append(to_global)
        return out

    def _prolongation(self) -> PETSc.Mat:
        """``P`` (owned rows, global columns); the rows of slaves that carry a Dirichlet
        condition hold explicit zeros (the same pattern whatever the conditions, so
        that the product's symbolic pattern stays valid)."""
        to_global = self._global_indices()
        rows, cols, vals = [], [], []
        odd = 0  # slaves whose condition differs from their master's
        for b, (c, (im, bs)) in enumerate(zip(self.mpcs, self._maps, strict=True)):
            n = im.size_local * bs
            pinned = self._pinned_local(b)
            slaves = np.asarray(c.slaves, dtype=np.int64)
            own = slaves < n
            free = np.setdiff1d(np.arange(n, dtype=np.int64), slaves[own])
            g = to_global[b](free)
            rows.append(g)
            cols.append(g)
            vals.append(np.ones(free.size))
            # both indexed by the local dof: the masters and weights of slave dof s
            masters = c.masters
            coeffs, offsets = c.coefficients()
            for sl in slaves[own]:
                m = np.asarray(masters.links(int(sl)), dtype=np.int64)
                w = np.asarray(coeffs[offsets[sl] : offsets[sl + 1]])
                keep = np.abs(w) > WEIGHT_FLOOR * np.abs(w).max(initial=0.0)
                rows.append(np.full(int(keep.sum()), to_global[b](np.array([sl]))[0]))
                cols.append(to_global[b](m[keep]))
                if pinned[sl]:
                    odd += int(not pinned[m[np.argmax(np.abs(w))]])
                    w = 0.0 * w
                vals.append(w[keep])
        r = np.concatenate(rows)
        cc = np.concatenate(cols)
        v = np.concatenate(vals)
        n_loc = sum(im.size_local * bs for im, bs in self._maps)
        start = self.comm.exscan(n_loc) or 0
        nnz = np.bincount(r - start, minlength=n_loc).astype(np.int32)
        P = PETSc.Mat().createAIJ(((n_loc, None), (n_loc, None)), nnz=(nnz, nnz), comm=self.comm)
        P.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
        for i in range(r.size):
            P.setValue(int(r[i]), int(cc[i]), float(v[i]), addv=PETSc.InsertMode.ADD_VALUES)
        P.assemble()
        if self.comm.allreduce(odd):
            P.destroy()
            raise ParameterError(
                "ProjectedMPCAssembly: a slave carries a Dirichlet condition that its master "
                "does not; pin a periodic node on both faces or on neither"
            )
        return P

    def _slave_conditions(self) -> list[list[tuple[np.ndarray, Any]]]:
        """Per block: ``(local slave dofs, condition)`` for the slaves that carry it."""
        forms = self.L if self.blocked else [self.L]
        out = []
        for c, L in zip(self.mpcs, forms, strict=True):
            slaves = np.asarray(c.slaves, dtype=np.int64)
            here = []
            for bc in self._bcs_on(L.function_spaces[0]):
                idx = np.intersect1d(slaves, np.asarray(bc.dof_indices()[0], dtype=np.int64))
                if idx.size:
                    here.append((idx, bc))
            out.append(here)
        return out

    def to_functions(self, x: PETSc.Vec) -> None:
        """As :meth:`MPCAssembly.to_functions`; then a slave that carries a condition
        takes its condition's value (the backsubstitution adds its round-off master
        weights, ~1e-13 of the other nodes of the master's cell: a pinned value off
        by that, which the lifting turned into a flux in its neighbours' rows)."""
        super().to_functions(x)
        for ui, fixed in zip(
            self.u if self.blocked else [self.u], self._pinned_slaves, strict=True
        ):
            for idx, bc in fixed:
                g = bc.g
                ui.x.array[idx] = g.x.array[idx] if hasattr(g, "x") else float(g.value)

    def _pinned_local(self, b: int) -> np.ndarray:
        """Block ``b``'s local dofs (owned and ghosts of the constraint's space) that
        carry a Dirichlet condition.

        The conditions index the form's space, whose ghosts are a subset of the
        constraint's: dolfinx_mpc's index map appends the masters owned elsewhere
        (at two ranks 583 local entries against 581).  The owned flags are exact;
        the ghosts take their owner's flag by a forward scatter, so a master that is
        one of the appended ghosts counts as pinned when its owner pins it."""
        im, bs = self._maps[b]
        n_own = im.size_local * bs
        flags = dolfinx.fem.Function(self.mpcs[b].function_space)
        forms = self.L if self.blocked else [self.L]
        for bc in self._bcs_on(forms[b].function_spaces[0]):
            idx = np.asarray(bc.dof_indices()[0], dtype=np.int64)
            flags.x.array[idx[idx < n_own]] = 1.0
        flags.x.scatter_forward()
        return flags.x.array > 0.5

    def _slave_diagonal(self) -> PETSc.Mat:
        """``D``: 1 on the owned slave rows (in the solution vector's layout)."""
        n_loc = self._P.getLocalSize()[0]
        D = PETSc.Mat().createAIJ(((n_loc, None), (n_loc, None)), nnz=(1, 0), comm=self.comm)
        start = D.getOwnershipRange()[0]
        for i in self._slaves:
            D.setValue(int(start + i), int(start + i), 1.0)
        D.assemble()
        return D

    def _check_masters(self) -> None:
        x = self._P.createVecRight()
        y = self._P.createVecLeft()
        arr = x.getArray(readonly=False)
        arr[:] = 0.0
        for i in self._bc_rows():
            arr[i] = 1.0
        del arr
        self._P.mult(x, y)
        bad = np.abs(y.getArray(readonly=True)[self._slaves]).max(initial=0.0)
        if self.comm.allreduce(float(bad), op=_mpi_max()) > 0.0:
            raise ParameterError(
                "ProjectedMPCAssembly: a constraint's master carries a Dirichlet condition; "
                "use MPCAssembly"
            )
        x.destroy()
        y.destroy()

    def _bc_rows(self) -> np.ndarray:
        """Owned Dirichlet dofs in the solution vector's layout (block offsets added)."""
        out = []
        offset = 0
        spaces = [ui.function_space for ui in (self.u if self.blocked else [self.u])]
        forms = self.L if self.blocked else [self.L]
        for (im, bs), L in zip(self._maps, forms, strict=True):
            n = im.size_local * bs
            for bc in self._bcs_on(L.function_spaces[0]):
                idx = np.asarray(bc.dof_indices()[0], dtype=np.int64)
                out.append(offset + idx[idx < n])
            offset += n
        del spaces
        return np.concatenate(out) if out else np.zeros(0, dtype=np.int64)

    # ------------------------------------------------------------ matrix
    def create_matrix(self) -> PETSc.Mat:
        self._A = self._plain.create_matrix()
        self._plain.jacobian(self._A)
        self._C = self._A.PtAP(self._P)
        J = self._C.duplicate(copy=True)
        J.axpy(1.0, self._D, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        J.assemble()
        return J

    def jacobian(self, A: PETSc.Mat) -> None:
        self._plain.jacobian(self._A)
        self._A.PtAP(self._P, result=self._C)
        A.zeroEntries()
        A.axpy(1.0, self._C, structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
        A.axpy(1.0, self._D, structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
        A.assemble()

    def destroy(self) -> None:
        super().destroy()
        for m in (self._A, self._C, self._P, self._D):
            if m is not None:
                m.destroy()


def _mpi_max() -> Any:
    from mpi4py import MPI

    return MPI.MAX


def add_rotational_periodic_constraint(
    mpc: Any,
    V: Any,
    indicator: Callable[[np.ndarray], np.ndarray],
    relation: Callable[[np.ndarray], np.ndarray],
    rotation: np.ndarray,
    bcs: Sequence[Any] = (),
) -> None:
    """Add ``u(x_s) = rotation @ u(relation(x_s))`` for the vector field on ``V`` to ``mpc``.

    For a sector of a body of revolution: ``indicator`` marks the slave side,
    ``relation`` maps a slave point to its master point (the rotation by minus the
    sector angle about the axis) and ``rotation`` is the ``gdim x gdim`` matrix of
    the rotation by plus the sector angle, so the slave displacement is the master
    one rotated.  ``V`` is the constraint's space when it is a vector space, or a
    vector sub-space of a mixed space (``W.sub(0)``).

    dolfinx_mpc's periodic search (parallel, possibly non-matching: several masters
    with interpolation weights) is run on each component sub-space ``V.sub(c)``; it
    pairs the slave dof of component ``c`` with the master dof(s) of component
    ``c``.  The slave of component ``c`` then takes the masters of all components
    ``d`` at its node (found as the masters of the slave of component ``d`` at the
    same node) with weights ``rotation[c, d] * w``.
    """
    import dolfinx_mpc

    if mpc.finalized:
        raise ParameterError("add_rotational_periodic_constraint: the constraint is finalized")
    R = np.asarray(rotation, dtype=np.float64)
    ncomp = V.num_sub_spaces
    if ncomp == 0 or R.shape != (ncomp, ncomp):
        raise ParameterError(
            f"add_rotational_periodic_constraint: rotation must be {ncomp}x{ncomp} for a "
            f"vector space with {ncomp} components, got shape {R.shape}"
        )
    bcs_ = [bc._cpp_object for bc in bcs]
    # parent dof of component c <-> parent dof of component 0 at the same node
    comp_dofs = [np.asarray(V.sub(c).collapse()[1], dtype=np.int64) for c in range(ncomp)]
    data = []
    for c in range(ncomp):
        d = dolfinx_mpc.cpp.mpc.create_periodic_constraint_geometrical(
            V.sub(c)._cpp_object, indicator, relation, bcs_, 1.0, True
        )
        data.append(d)
    n_parent = max(int(cd.max(initial=-1)) for cd in comp_dofs) + 1
    node_of = np.full(n_parent, -1, dtype=np.int64)
    for cd in comp_dofs:
        node_of[cd] = np.arange(cd.size)
    # masters (and weights, owners) of the slave at (node, component)
    by_node: list[dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]] = []
    for c in range(ncomp):
        d = data[c]
        slaves = np.asarray(d.slaves)
        off = np.asarray(d.offsets)
        m, w, o = np.asarray(d.masters), np.asarray(d.coeffs), np.asarray(d.owners)
        by_node.append(
            {
                int(node_of[s]): (
                    m[off[k] : off[k + 1]],
                    w[off[k] : off[k + 1]],
                    o[off[k] : off[k + 1]],
                )
                for k, s in enumerate(slaves)
            }
        )
    slaves_out, masters, coeffs, owners, offsets = [], [], [], [], [0]
    for c in range(ncomp):
        for node, (_m, w_c, _o) in sorted(by_node[c].items()):
            entries = [by_node[dd].get(node) for dd in range(ncomp)]
            if any(e is None for e in entries):
                raise ParameterError(
                    "add_rotational_periodic_constraint: a slave node is constrained in some "
                    "components only (a Dirichlet condition on part of the components there?)"
                )
            slaves_out.append(int(comp_dofs[c][node]))
            for dd in range(ncomp):
                m_d, w_d, o_d = entries[dd]
                if m_d.size != w_c.size or not np.allclose(w_d, w_c, rtol=0.0, atol=1e-12):
                    raise ParameterError(
                        "add_rotational_periodic_constraint: the components' periodic "
                        "searches found different master points"
                    )
                if R[c, dd] == 0.0:
                    continue
                masters.extend(m_d.tolist())
                coeffs.extend((R[c, dd] * w_d).tolist())
                owners.extend(o_d.tolist())
            offsets.append(len(masters))
    mpc.add_constraint(
        mpc.V,
        np.asarray(slaves_out, dtype=np.int32),
        np.asarray(masters, dtype=np.int64),
        np.asarray(coeffs, dtype=dolfinx.default_scalar_type),
        np.asarray(owners, dtype=np.int32),
        np.asarray(offsets, dtype=np.int32),
    )


def owned_block_offsets(unknowns: Sequence[Any]) -> np.ndarray:
    """Offsets of each unknown's owned entries in this rank's part of a blocked
    (DOLFINx block layout) vector: ``[0, n_0, n_0 + n_1, ...]``, ``n_i`` the owned
    dofs of ``unknowns[i]`` times its block size."""
    sizes = [
        u.function_space.dofmap.index_map.size_local * u.function_space.dofmap.index_map_bs
        for u in unknowns
    ]
    return np.concatenate(([0], np.cumsum(sizes))).astype(np.int64)


__all__ = [
    "Assembly",
    "MPCAssembly",
    "PlainAssembly",
    "ProjectedMPCAssembly",
    "add_rotational_periodic_constraint",
    "owned_block_offsets",
]
