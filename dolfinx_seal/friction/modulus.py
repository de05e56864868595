"""Complex viscoelastic moduli ``E(omega)`` of rubber.

Sign convention: ``E(omega) = E'(omega) + i E''(omega)`` with the loss modulus
``E'' >= 0`` for ``omega > 0`` (stress ``sigma(t) = Re[E eps_0 exp(i omega t)]``)
and ``E(-omega) = conj(E(omega))``.  S3 writes its time dependence as
``exp(-i omega t)``, so its eq 38, ``E = E1 (1 - i omega tau) / (1 + a - i omega
tau)``, is the complex conjugate of :class:`StandardLinearSolid` here; the
friction formula (S3 eq 30) then uses ``Im E >= 0`` and ``mu >= 0`` directly.

Models: the S3 eq 38 standard linear solid, a Prony series, and a tabulated
master curve shifted in temperature by WLF or Arrhenius.  All are
isothermal: no flash temperature (the rubber temperature is the bulk
temperature ``T`` at every length scale and sliding speed).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_choice, check_positive, check_range

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]

#: Gas constant [J/(mol K)] for the Arrhenius shift.
R_GAS = 8.314462618


class Modulus(ABC):
    """A complex modulus ``E(omega)`` [Pa] of angular frequency ``omega`` [rad/s]."""

    @abstractmethod
    def __call__(self, omega: ArrayLike) -> ComplexArray:
        """``E(omega)`` for any real ``omega`` (``E(-omega) = conj E(omega)``)."""

    def storage(self, omega: ArrayLike) -> FloatArray:
        """``E'(omega)`` [Pa]."""
        return np.real(self(omega))

    def loss(self, omega: ArrayLike) -> FloatArray:
        """``E''(omega)`` [Pa]."""
        return np.imag(self(omega))


class StandardLinearSolid(Modulus):
    """S3 eq 38 (in this module's sign convention): ``E = E1 (1 + i w t)/(1 + a + i w t)``.

    ``E(0) = E1/(1 + a)`` (rubbery), ``E(inf) = E1`` (glassy), loss peak at
    ``omega tau = 1 + a``.

    Args:
        e1: Glassy modulus ``E1`` [Pa] (S3: 1e9).
        a: ``E(inf)/E(0) - 1`` (S3: 1000).
        tau: Relaxation time [s] (S3: 1e-3).
    """

    def __init__(self, e1: float = 1e9, a: float = 1000.0, tau: float = 1e-3) -> None:
        self.e1 = check_positive("e1", e1, "Pa")
        self.a = check_positive("a", a)
        self.tau = check_positive("tau", tau, "s")

    def __call__(self, omega: ArrayLike) -> ComplexArray:
        wt = 1j * np.asarray(omega, dtype=float) * self.tau
        return self.e1 * (1.0 + wt) / (1.0 + self.a + wt)


class PronySeries(Modulus):
    """``E(omega) = E_inf + sum_k E_k i omega tau_k / (1 + i omega tau_k)``.

    Args:
        e_inf: Long-time (rubbery) modulus [Pa], ``> 0``.
        e_k: Prony moduli [Pa], ``>= 0``.
        tau_k: Relaxation times [s], ``> 0``.
    """

    def __init__(self, e_inf: float, e_k: ArrayLike, tau_k: ArrayLike) -> None:
        self.e_inf = check_positive("e_inf", e_inf, "Pa")
        self.e_k = np.asarray(e_k, dtype=float).ravel()
        self.tau_k = np.asarray(tau_k, dtype=float).ravel()
        if self.e_k.size == 0 or self.e_k.size != self.tau_k.size:
            raise ParameterError("e_k and tau_k must be non-empty and of equal length")
        if np.any(~np.isfinite(self.e_k)) or np.any(self.e_k < 0):
            raise ParameterError("Prony moduli e_k must be finite and >= 0 (Pa)")
        if np.any(~np.isfinite(self.tau_k)) or np.any(self.tau_k <= 0):
            raise ParameterError("Prony times tau_k must be finite and > 0 (s)")

    def __call__(self, omega: ArrayLike) -> ComplexArray:
        w = np.asarray(omega, dtype=float)
        wt = 1j * w[..., None] * self.tau_k
        return self.e_inf + np.sum(self.e_k * wt / (1.0 + wt), axis=-1)


def shift_factor(
    temperature: float, t_ref: float, kind: str = "wlf", c1: float = 17.44, c2: float = 51.6,
    activation_energy: float = 1.0e5,
) -> float:  # fmt: skip
    """Time-temperature shift factor ``a_T`` (``E(omega, T) = E_ref(a_T omega)``).

    Args:
        temperature: ``T`` [K].
        t_ref: Reference temperature of the master curve [K].
        kind: ``"wlf"``: ``log10 a_T = -c1 (T - T_ref)/(c2 + T - T_ref)`` (``c2`` in K);
            ``"arrhenius"``: ``ln a_T = (E_a / R)(1/T - 1/T_ref)``.
        c1, c2: WLF constants (defaults: the "universal" 17.44, 51.6 K).
        activation_energy: ``E_a`` [J/mol] for Arrhenius.
    """
    t = check_positive("temperature", temperature, "K")
    tr = check_positive("t_ref", t_ref, "K")
    check_choice("shift", kind, ("wlf", "arrhenius"))
    if kind == "wlf":
        check_positive("c1", c1)
        check_positive("c2", c2, "K")
        if c2 + t - tr <= 0:
            raise ParameterError(
                f"temperature = {t:g} K is outside the WLF range T > T_ref - c2 = {tr - c2:g} K"
            )
        return 10.0 ** (-c1 * (t - tr) / (c2 + t - tr))
    check_positive("activation_energy", activation_energy, "J/mol")
    return math.exp(activation_energy / R_GAS * (1.0 / t - 1.0 / tr))


class MasterCurve(Modulus):
    """Tabulated master curve ``E'(omega), E''(omega)`` at ``T_ref``, shifted to ``T``.

    Log-log interpolation in ``omega``; outside the table the end values are
    held (a master curve says nothing beyond its measured range; holding the
    plateau values is the usual rubbery/glassy assumption), and
    :attr:`coverage` reports the shifted frequency range for checking.

    Args:
        omega: Angular frequencies [rad/s], strictly increasing, ``> 0``.
        storage: ``E'`` [Pa], ``> 0``.
        loss: ``E''`` [Pa], ``> 0``.
        t_ref: Reference temperature [K].
        temperature: Evaluation temperature [K] (default ``t_ref``).
        shift: ``"wlf"`` or ``"arrhenius"`` (see :func:`shift_factor`).
        c1, c2, activation_energy: Shift constants.
    """

    def __init__(
        self,
        omega: ArrayLike,
        storage: ArrayLike,
        loss: ArrayLike,
        t_ref: float = 293.15,
        temperature: float | None = None,
        shift: str = "wlf",
        c1: float = 17.44,
        c2: float = 51.6,
        activation_energy: float = 1.0e5,
    ) -> None:
        w = np.asarray(omega, float).ravel()
        e1 = np.asarray(storage, float).ravel()
        e2 = np.asarray(loss, float).ravel()
        if w.size < 2 or not (w.size == e1.size == e2.size):
            raise ParameterError("master curve needs >= 2 rows of equal length (omega, E', E'')")
        if np.any(~np.isfinite(np.concatenate((w, e1, e2)))):
            raise ParameterError("master curve values must be finite")
        if w[0] <= 0 or np.any(np.diff(w) <= 0):
            raise ParameterError("master curve omega must be > 0 and strictly increasing (rad/s)")
        if np.any(e1 <= 0) or np.any(e2 <= 0):
            raise ParameterError("master curve E' and E'' must be > 0 (Pa)")
        self._lw, self._l1, self._l2 = np.log(w), np.log(e1), np.log(e2)
        self.t_ref = check_positive("t_ref", t_ref, "K")
        self.temperature = self.t_ref if temperature is None else float(temperature)
        self.a_t = shift_factor(self.temperature, self.t_ref, shift, c1, c2, activation_energy)
        self.coverage = (float(w[0] / self.a_t), float(w[-1] / self.a_t))

    @classmethod
    def from_file(cls, path: str | Path, **kwargs: float | str | None) -> MasterCurve:
        """Read three columns ``omega [rad/s], E' [Pa], E'' [Pa]`` (``#`` comments, , or spaces)."""
        p = Path(path)
        if not p.is_file():
            raise ParameterError(f"modulus_file {str(p)!r} does not exist")
        rows = []
        for n, line in enumerate(p.read_text().splitlines(), start=1):
            s = line.split("#", 1)[0].replace(",", " ").split()
            if not s:
                continue
            if len(s) < 3:
                raise ParameterError(f"{p}:{n}: expected omega, E', E'' columns")
            try:
                rows.append([float(x) for x in s[:3]])
            except ValueError:
                raise ParameterError(f"{p}:{n}: not numbers: {line!r}") from None
        if not rows:
            raise ParameterError(f"{p}: no data rows")
        w, e1, e2 = np.array(rows).T
        return cls(w, e1, e2, **kwargs)  # type: ignore[arg-type]

    def __call__(self, omega: ArrayLike) -> ComplexArray:
        w = np.asarray(omega, dtype=float)
        lw = np.log(np.maximum(np.abs(w) * self.a_t, 1e-300))
        e1 = np.exp(np.interp(lw, self._lw, self._l1))
        e2 = np.exp(np.interp(lw, self._lw, self._l2))
        e2 = np.where(w == 0, 0.0, np.sign(w) * e2)
        return e1 + 1j * e2


def check_poisson(nu: float) -> float:
    """Poisson ratio in ``[0, 0.5]`` (rubber: 0.5)."""
    return check_range("nu", nu, 0.0, 0.5)
