"""Periodicity of a sector of a body of revolution, or of a flat band (dolfinx_mpc constraints).

A sector of angle ``angle`` about the z axis, centred on the plane at the angle
``centre`` (its two cut faces at ``centre - angle/2``, the master side, and
``centre + angle/2``, the slave side, e.g. the lip sector of
:mod:`geometry.lip_sector`), repeats by the rotation ``R`` through ``angle``
about z.  A field on it is periodic when its value at a slave point ``x_s`` is
that at the master point ``R^-1 x_s``, with a vector field rotated with the
sector (``u(x_s) = R u(R^-1 x_s)``; :func:`~dolfinx_seal.solvers.assembly.add_rotational_periodic_constraint`)
and a scalar field equal.

:class:`RotationalPeriodicity` builds the finalized constraints that the
assembly seam (:class:`~dolfinx_seal.solvers.assembly.MPCAssembly`) takes: one
for a body (its displacement, and the pressure of a mixed u-p space) and one per
scalar field (a film pressure, a film fraction).  Dofs with a Dirichlet
condition in ``bcs`` never become slaves (dolfinx_mpc skips them): pass every
condition of the field, so that a node on both a cut face and a Dirichlet
boundary keeps its condition.  :class:`TranslationalPeriodicity` is the same
for a flat band periodic along x (the rigid rough band of
:mod:`dolfinx_seal.film.rigid_band`), scalar fields only.  Geometry only: numpy and dolfinx_mpc.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from dolfinx_seal.params import check_positive, check_range
from dolfinx_seal.solvers.assembly import add_rotational_periodic_constraint


def _scalar_constraint(V: Any, slave_side: Any, to_master: Any, bcs: Sequence[Any]) -> Any:
    import dolfinx_mpc

    mpc = dolfinx_mpc.MultiPointConstraint(V)
    mpc.create_periodic_constraint_geometrical(V, slave_side, to_master, list(bcs))
    mpc.finalize()
    return mpc


@dataclass(frozen=True)
class RotationalPeriodicity:
    """The periodicity of a sector about the z axis.

    Attributes:
        angle: Sector angle [rad], in (0, pi].
        centre: Angle of the sector's mid-plane [rad] (its faces at ``centre +- angle/2``).
        tolerance: Largest distance [m] of a slave dof from the slave face plane.
    """

    angle: float
    centre: float = 0.0
    tolerance: float = 1e-9

    def __post_init__(self) -> None:
        check_range("angle", self.angle, 0.0, math.pi, lo_open=True, unit="rad")
        check_range("centre", self.centre, -math.pi, math.pi, unit="rad")
        check_positive("tolerance", self.tolerance, "m")

    def rotation(self, dim: int = 3) -> np.ndarray:
        """``dim x dim`` matrix of the rotation through ``angle`` about z (master -> slave)."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        R = np.eye(dim)
        R[:2, :2] = [[c, -s], [s, c]]
        return R

    def slave_side(self, x: np.ndarray) -> np.ndarray:
        """Points ``x`` (3 x n) on the slave face (the plane at ``centre + angle/2``)."""
        phi = self.centre + 0.5 * self.angle
        c, s = math.cos(phi), math.sin(phi)
        off_plane = np.abs(-s * x[0] + c * x[1])
        return (off_plane < self.tolerance) & (c * x[0] + s * x[1] > 0.0)

    def to_master(self, x: np.ndarray) -> np.ndarray:
        """The master points ``R^-1 x`` of slave points ``x`` (3 x n)."""
        R = self.rotation(3).T
        return R @ np.asarray(x)

    def body(self, W: Any, mixed: bool, bcs: Sequence[Any] = ()) -> Any:
        """Finalized constraint of a body's unknowns on ``W``: the displacement
        (``W`` or, mixed, ``W.sub(0)``) rotated with the sector, and, mixed, the
        pressure ``W.sub(1)`` periodic."""
        import dolfinx_mpc

        mpc = dolfinx_mpc.MultiPointConstraint(W)
        Vu = W.sub(0) if mixed else W
        dim = Vu.num_sub_spaces
        add_rotational_periodic_constraint(
            mpc, Vu, self.slave_side, self.to_master, self.rotation(dim), list(bcs)
        )
        if mixed:
            mpc.create_periodic_constraint_geometrical(
                W.sub(1), self.slave_side, self.to_master, list(bcs)
            )
        mpc.finalize()
        return mpc

    def scalar(self, V: Any, bcs: Sequence[Any] = ()) -> Any:
        """Finalized constraint of a scalar field on ``V``: equal at slave and master."""
        return _scalar_constraint(V, self.slave_side, self.to_master, bcs)


@dataclass(frozen=True)
class TranslationalPeriodicity:
    """Periodicity along the x axis with period ``length`` (a flat band, e.g. the
    rough band of :mod:`dolfinx_seal.film.rigid_band`): the slave face ``x = length``,
    its master ``x = 0``.

    Attributes:
        length: Period [m].
        tolerance: Largest distance [m] of a slave dof from the plane ``x = length``.
    """

    length: float
    tolerance: float = 1e-9

    def __post_init__(self) -> None:
        check_positive("length", self.length, "m")
        check_positive("tolerance", self.tolerance, "m")

    def slave_side(self, x: np.ndarray) -> np.ndarray:
        """Points ``x`` (3 x n) on the slave face."""
        return np.abs(x[0] - self.length) < self.tolerance

    def to_master(self, x: np.ndarray) -> np.ndarray:
        """The master points of slave points ``x`` (3 x n)."""
        out = np.array(x, copy=True)
        out[0] -= self.length
        return out

    def scalar(self, V: Any, bcs: Sequence[Any] = ()) -> Any:
        """Finalized constraint of a scalar field on ``V``: equal at slave and master."""
        return _scalar_constraint(V, self.slave_side, self.to_master, bcs)


__all__ = ["RotationalPeriodicity", "TranslationalPeriodicity"]
