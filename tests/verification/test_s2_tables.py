"""S2 (Taylor 2022) Table 1 (GW/GT functions F_n) and Table 2 (load fractions X(lambda)).

Every printed entry is checked to half a unit of its last printed digit.  Four
entries disagree with the formulas printed next to them in the same paper; each
is listed with the independent evidence and checked against that instead.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erfc, gamma

from dolfinx_seal.contact import gw_function, load_fraction

TABLE1 = """
0.0 0.50000 0.41109 0.39894 0.43002 0.50000 0.61664
0.5 0.30854 0.22534 0.19780 0.19520 0.20964 0.24024
1.0 0.15865 0.10415 0.08332 0.07567 0.07534 0.08056
1.5 0.06681 0.03988 0.02931 0.02464 0.02285 0.02286
2.0 0.02275 0.01248 0.00849 0.00665 0.00577 0.00542
2.5 0.00621 0.00316 0.00200 0.00147 0.00120 0.00106
3.0 0.00135 0.00064 0.00038 0.00026 0.00020 0.00017
3.5 0.00023 0.00010 0.00006 0.00004 0.00003 0.00002
4.0 0.00003 0.00001 0.00001 0.00000 0.00000 0.00000
"""
ORDERS = (0.0, 0.5, 1.0, 1.5, 2.0, 2.5)

#: (lambda, n) -> (printed, correct value, evidence)
TABLE1_MISPRINTS = {
    (0.0, 2.5): (0.61664, 2**0.75 * gamma(1.75) / math.sqrt(2 * math.pi),
                 "closed form 2^(3/4) Gamma(7/4) / sqrt(2 pi) = 0.616634"),
    (0.5, 2.5): (0.24024, None, "quadrature of S2 eq 29 gives 0.240402 (digits transposed)"),
    (1.0, 0.0): (0.15865, 0.5 * erfc(1 / math.sqrt(2)),
                 "F_0 = erfc(lambda/sqrt 2)/2 = 0.1586553, i.e. 0.15866 (printed truncated)"),
}  # fmt: skip


def f_quad(n: float, lam: float) -> float:
    return quad(lambda s: (s - lam) ** n * math.exp(-s * s / 2) / math.sqrt(2 * math.pi),
                lam, lam + 40, epsabs=0, epsrel=1e-13, limit=200)[0]  # fmt: skip


def table1_rows():
    for line in TABLE1.strip().splitlines():
        lam, *vals = (float(x) for x in line.split())
        for n, v in zip(ORDERS, vals, strict=True):
            yield lam, n, v


@pytest.mark.parametrize(("lam", "n", "printed"), list(table1_rows()))
def test_table1(lam, n, printed):
    ours = float(gw_function(n, np.array(lam)))
    if (lam, n) in TABLE1_MISPRINTS:
        _, correct, _why = TABLE1_MISPRINTS[(lam, n)]
        correct = f_quad(n, lam) if correct is None else correct
        assert ours == pytest.approx(correct, rel=1e-10)
        assert abs(ours - printed) > 0.5e-5  # the printed value is indeed off
        return
    assert abs(ours - printed) <= 0.5e-5 + 1e-12


TABLE2 = {  # lambda: (power fit, exp, linear, Olver-Spikes, Greenwood-Tripp, BGT)
    3.0: (0.0879, 0.0498, 0.0, 0.0625, 0.00028, 0.0027),
    2.0: (0.167, 0.135, 0.333, 0.111, 0.0088, 0.0455),
    1.0: (0.397, 0.368, 0.667, 0.25, 0.131, 0.317),
    0.5: (0.668, 0.607, 0.833, 0.444, 0.390, 0.617),
    0.2: (0.892, 0.819, 0.933, 0.694, 0.698, 0.895),
    0.1: (0.959, 0.905, 0.967, 0.826, 0.838, 0.920),
}
LAWS = (
    "power_fit",
    "exponential",
    "linear",
    "olver_spikes",
    "greenwood_tripp",
    "bush_gibson_thomas",
)


def decimals(x: float) -> float:
    """Half a unit of the last printed digit (three significant figures or 4 decimals)."""
    s = f"{x}"
    d = len(s.split(".")[1]) if "." in s else 0
    return 0.5 * 10.0 ** (-d)


@pytest.mark.parametrize("lam", sorted(TABLE2))
@pytest.mark.parametrize("k", range(6))
def test_table2(lam, k):
    printed = TABLE2[lam][k]
    ours = float(load_fraction.LAWS[LAWS[k]](np.array(lam)))
    if LAWS[k] == "bush_gibson_thomas" and lam == 0.2:
        # printed 0.895, but S2's own eq 41 gives erfc(0.2/sqrt 2) = 0.8415; the
        # neighbouring entries (0.920 at 0.1, 0.617 at 0.5) follow eq 41 exactly
        assert ours == pytest.approx(math.erfc(0.2 / math.sqrt(2)), rel=1e-14)
        assert abs(ours - printed) > 0.05
        return
    tol = decimals(printed) if printed != 0.0 else 1e-15
    assert abs(ours - printed) <= tol + 1e-12


def test_jedynak_closed_form_is_eq29():
    """S2 eq 30 (parabolic cylinder) against direct quadrature of eq 29, off the table."""
    for n in (1.5, 2.5, 0.75):
        for lam in (-2.0, 0.25, 3.3, 6.0):
            assert float(gw_function(n, np.array(lam))) == pytest.approx(f_quad(n, lam), rel=1e-10)


def test_mixed_friction_eq3():
    lam = np.array([0.0, 1.0, 5.0])
    f = load_fraction.mixed_friction(lam, mu_asp=0.12, mu_fluid=0.01, law="olver_spikes")
    x = 1 / (1 + lam) ** 2
    np.testing.assert_allclose(f, 0.12 * x + 0.01 * (1 - x), rtol=1e-15)
    with pytest.raises(ValueError, match="lambda"):
        load_fraction.olver_spikes(np.array([-0.1]))
