"""Nonlinear solvers: one PETSc SNES wrapper, and continuation drivers."""

from dolfinx_seal.solvers.snes import NonlinearSolver, SNESOptions, bounds_function

__all__ = ["NonlinearSolver", "SNESOptions", "bounds_function"]
