"""The per-cycle stroke summary of a reciprocating lip sweep (bookkeeping, no FEM)."""

from __future__ import annotations

import pytest

from dolfinx_seal.scenes.lip import stroke_summary


def _row(speed: float, q: float, f: float) -> dict:
    return {"speed": speed, "leakage_rate": q, "friction_force": f, "converged": True}


def test_net_transport_per_cycle():
    # out-stroke at 0.2 m/s carries 3e-9 m^3/s out, the in-stroke brings 2e-9 m^3/s back;
    # a 0.1 m stroke lasts 0.5 s: 1.5e-9 m^3 out, 1.0e-9 m^3 back, 0.5e-9 m^3 lost per cycle
    rows = [_row(0.2, 3e-9, 40.0), _row(-0.2, -2e-9, 30.0), _row(0.5, 1e-9, 45.0)]
    (s,) = stroke_summary(rows, 0.1)  # 0.5 m/s has no in-stroke: no cycle
    assert s["speed"] == 0.2
    assert s["out_stroke_volume"] == pytest.approx(1.5e-9, rel=1e-14, abs=0.0)
    assert s["in_stroke_volume"] == pytest.approx(1.0e-9, rel=1e-14, abs=0.0)
    assert s["net_leakage_per_cycle"] == pytest.approx(0.5e-9, rel=1e-12, abs=0.0)
    assert s["net_leakage_ml_per_1000_cycles"] == pytest.approx(0.5e-9 * 1e9, rel=1e-12)
    assert s["friction_work_per_cycle"] == pytest.approx(70.0 * 0.1, rel=1e-14)


def test_a_seal_that_returns_what_it_lets_out_loses_nothing():
    rows = [
        _row(u, q, 1.0) for u, q in ((0.01, 4e-10), (-0.01, -4e-10), (1.0, 7e-9), (-1.0, -7e-9))
    ]
    out = stroke_summary(rows, 0.05)
    assert [s["speed"] for s in out] == [0.01, 1.0]
    assert all(s["net_leakage_per_cycle"] == pytest.approx(0.0, abs=1e-24) for s in out)
    failed = [dict(rows[0]), dict(rows[1], converged=False)]
    assert stroke_summary(failed, 0.05) == []  # a failed in-stroke makes no cycle
