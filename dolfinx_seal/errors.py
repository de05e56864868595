"""Typed errors of dolfinx_seal.

Every error a user can trigger is one of these, so scripts can catch them and
tests can assert on them:

* :class:`ParameterError` -- bad input; raised before any assembly, names the
  parameter, its value and the allowed range.
* :class:`SolverError` -- a nonlinear solve did not converge; carries the
  diagnostics (what diverged, where, the iteration history) and whatever was
  already computed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


class ParameterError(ValueError):
    """An input parameter is outside its allowed range (or of the wrong kind).

    Attributes:
        parameter: The (dotted) name of the parameter the message is about, when
            one parameter is at fault (``None`` otherwise); the checks of
            :mod:`dolfinx_seal.params` set it, and building nested parameters
            rewrites it (and the message) to the full dotted name.
    """

    def __init__(self, message: str, parameter: str | None = None) -> None:
        super().__init__(message)
        self.parameter = parameter


@dataclass
class SolveHistory:
    """Iteration history of one nonlinear solve.

    Attributes:
        residual_norms: Residual 2-norm at each Newton iterate (scaled units).
        linear_iterations: Krylov iterations of each Newton step.
        reason: PETSc converged/diverged reason (integer, PETSc.SNES.ConvergedReason).
        reason_name: Its name, e.g. ``"CONVERGED_FNORM_RELATIVE"``.
        complementarity: 2-norm of the natural residual ``x - clip(x - F(x), lower,
            upper)`` at the end, ``nan`` for problems without bounds.
    """

    residual_norms: list[float] = field(default_factory=list)
    linear_iterations: list[int] = field(default_factory=list)
    reason: int = 0
    reason_name: str = ""
    complementarity: float = float("nan")

    @property
    def newton_iterations(self) -> int:
        """Number of Newton steps taken."""
        return max(len(self.residual_norms) - 1, 0)


class SolverError(RuntimeError):
    """A nonlinear solve failed.

    Attributes:
        what: Short description of what diverged (e.g. ``"SNES 'reynolds_' DIVERGED_MAX_IT"``).
        where: Where it happened (problem name, sweep point, continuation step).
        history: The :class:`SolveHistory` of the failed solve.
        partial: Results computed before the failure (e.g. finished sweep points).
    """

    def __init__(
        self,
        what: str,
        where: str = "",
        history: SolveHistory | None = None,
        partial: Any = None,
    ) -> None:
        self.what = what
        self.where = where
        self.history = history if history is not None else SolveHistory()
        self.partial = partial
        msg = what if not where else f"{what} (at {where})"
        if self.history.residual_norms:
            tail = ", ".join(f"{r:.3e}" for r in self.history.residual_norms[-5:])
            msg += f"; last residual norms: [{tail}]"
        super().__init__(msg)
