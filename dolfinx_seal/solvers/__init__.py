"""Nonlinear solvers: one PETSc SNES wrapper, its assembly strategies, continuation drivers."""

from dolfinx_seal.solvers.assembly import (
    Assembly,
    MPCAssembly,
    PlainAssembly,
    ProjectedMPCAssembly,
    add_rotational_periodic_constraint,
    owned_block_offsets,
)
from dolfinx_seal.solvers.periodic import RotationalPeriodicity, TranslationalPeriodicity
from dolfinx_seal.solvers.snes import (
    NonlinearSolver,
    SNESOptions,
    bounds_function,
    extra_petsc_options,
    solver_session,
    with_snes_type,
)

__all__ = [
    "Assembly",
    "MPCAssembly",
    "NonlinearSolver",
    "PlainAssembly",
    "ProjectedMPCAssembly",
    "RotationalPeriodicity",
    "SNESOptions",
    "TranslationalPeriodicity",
    "add_rotational_periodic_constraint",
    "bounds_function",
    "extra_petsc_options",
    "owned_block_offsets",
    "solver_session",
    "with_snes_type",
]
