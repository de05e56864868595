"""Pieces shared by the FEM scenes: material and contact-law parameters, the
dry-contact solve with its warm start, and profile output.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from dolfinx_seal.contact.hertz import separation_of
from dolfinx_seal.contact.persson import PerssonExponentialLaw, PerssonLaw
from dolfinx_seal.errors import SolverError
from dolfinx_seal.mpi import get_logger, world
from dolfinx_seal.params import check_choice, check_range
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.solid.materials import MATERIALS, make_material


@dataclass(frozen=True)
class MaterialParams:
    """Rubber bulk.

    Attributes:
        model: ``linear`` (small strain), ``neo-hookean`` or ``mooney-rivlin``.
        E: Young's modulus [Pa].
        nu: Poisson ratio, in (-1, 0.5]; 0.5 only with ``formulation = "mixed"``.
        formulation: ``mixed`` (displacement-pressure, locking-free) or ``compressible``.
        c01_ratio: Mooney-Rivlin ``C01 / (C10 + C01)``, in [0, 1).
    """

    model: str = "neo-hookean"
    E: float = 10e6
    nu: float = 0.5
    formulation: str = "mixed"
    c01_ratio: float = 0.2

    def __post_init__(self) -> None:
        check_choice("model", self.model, tuple(MATERIALS))
        if self.model != "mooney-rivlin":  # unused then, but never a non-finite value
            check_range("c01_ratio", self.c01_ratio, 0.0, 1.0, hi_open=True)
        self.build()  # validates E, nu, formulation (and c01_ratio of mooney-rivlin)

    def build(self) -> Any:
        """The material object."""
        kw: dict[str, Any] = {"E": self.E, "nu": self.nu, "formulation": self.formulation}
        if self.model == "mooney-rivlin":
            kw["c01_ratio"] = self.c01_ratio
        return make_material(self.model, **kw)

    @property
    def E_star(self) -> float:
        """``E / (1 - nu^2)`` [Pa]."""
        return self.E / (1.0 - self.nu**2)


@dataclass(frozen=True)
class ContactLawParams:
    """Asperity contact law.

    Attributes:
        model: ``persson`` (closed form of the full Persson relation, diverging as
            u -> 0), ``exponential`` (its asymptote ``beta E* exp(-alpha u/h_rms)``)
            or ``stiff`` (``E* exp(-u/stiff_length)``: a nearly smooth surface, for
            Hertz checks); ``none``: no asperity contact (lubricated scenes only).
        gamma: Yang-Persson factor (S1: 0.4).
        stiff_length: Decay length of the ``stiff`` law [m]; 0 (default) chooses
            ``1e-3 a_H^2 / R``, a thousandth of the Hertz approach, which broadens
            the Hertz edges by about 0.5 % of the contact size (the gap opens as
            ``(a^2/R) ((x - a)/a)^(3/2)`` outside the contact).
    """

    model: str = "persson"
    gamma: float = 0.4
    stiff_length: float = 0.0

    def __post_init__(self) -> None:
        check_choice("contact.model", self.model, ("persson", "exponential", "stiff", "none"))
        check_range("contact.gamma", self.gamma, 0.0, 1.0, lo_open=True)
        check_range("contact.stiff_length", self.stiff_length, 0.0, 1e-3, unit="m (0 = automatic)")

    def build(
        self, roughness: RoughnessParams, e_star: float, approach: float = 1e-5, psd: Any = None
    ) -> tuple[Any, dict[str, float]]:
        """The contact law (with a UFL form) and scalars describing it.

        ``approach`` [m] is the Hertz approach ``a^2/R`` of the scene, which sets
        the automatic decay length of the ``stiff`` law.  ``psd``: the spectrum of
        the homogenised roughness when it is not the whole of ``roughness`` (the
        part above ``q_th`` of a two-scale scene, S0 eqs 15-21); default
        ``roughness.build()``.
        """
        if self.model == "none":
            return None, {}
        if self.model == "stiff":
            length = self.stiff_length or 1e-3 * approach
            return PerssonExponentialLaw(1.0, 1.0, e_star, length), {"stiff_length": length}
        psd = roughness.build() if psd is None else psd
        if self.model == "exponential":
            law = PerssonExponentialLaw.from_psd(psd, e_star, self.gamma)
            return law, {"alpha": law.alpha, "beta": law.beta}
        full = PerssonLaw(psd, e_star, self.gamma)
        cf = full.closed_form()
        info = {
            "alpha": full.alpha,
            "beta": full.beta,
            "closed_form_max_rel_error": cf.max_rel_error,
        }
        cf.full = full  # the tabulated relation (inverse for warm starts)
        return cf, info


def solve_dry(problem: Any, pressure_guess: Any, peak_guess: float) -> dict[str, Any]:
    """Warm start from a guessed pressure, one Newton solve at full load, and adaptive
    load stepping from the unloaded state if that fails.  Returns solver figures."""
    log = get_logger()
    t0 = time.perf_counter()
    saved = problem.w.x.array.copy()
    its = 0
    try:
        its += problem.warm_start(pressure_guess, separation_of(problem.law, peak_guess))
        its += problem.solve_at(1.0)
        strategy = "warm start"
    except SolverError as e:
        log.info("%s: warm start failed (%s); adaptive load stepping", problem.name, e.what)
        problem.w.x.array[:] = saved
        if problem.control == "force":
            problem.position.x.array[:] = problem.position0
        problem.ramp()
        its += sum(s.newton_iterations for s in problem.steps)
        strategy = f"load stepping ({len(problem.steps)} steps)"
    return {
        "newton_iterations": its,
        "solve_time_s": time.perf_counter() - t0,
        "strategy": strategy,
    }


def write_profile(out: Path, name: str, columns: dict[str, np.ndarray], title: str,
                  xlabel: str, ylabel: str, curves: dict[str, tuple[np.ndarray, np.ndarray]]) -> None:  # fmt: skip
    """Write ``NAME.csv`` (columns) and ``NAME.png`` (curves: label -> (x, y)) on rank 0."""
    if world().rank != 0:
        return
    out.mkdir(parents=True, exist_ok=True)
    keys = list(columns)
    data = np.column_stack([columns[k] for k in keys])
    np.savetxt(out / f"{name}.csv", data, delimiter=",", header=",".join(keys), comments="")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    for label, (x, y) in curves.items():
        style = "k--" if "Hertz" in label else "-"
        ax.plot(x, y, style, lw=1.2 if "Hertz" in label else 2, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(out / f"{name}.png", dpi=120)
    plt.close(fig)
