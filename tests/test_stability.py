"""The summary rpo linearize ends with, on modes whose answers are known."""

from __future__ import annotations

import cmath
import math

import pytest

from rpo.runtime.run.linearize import Mode
from rpo.runtime.run.stability import MARGIN, stability_summary, summary_lines

DT = 0.1


def mode(s: complex, state: str = "r_x", block: str = "translation") -> Mode:
    return Mode(lam=cmath.exp(s * DT), s=s, group=block, state=state, participation={block: 1.0}, block=block)


def test_a_stable_loop_names_its_slowest_and_least_damped_modes():
    wn, zeta = 0.5, 0.05
    pair = complex(-zeta * wn, wn * math.sqrt(1 - zeta**2))
    modes = [mode(-2.0), mode(-0.01, "v_y"), mode(pair), mode(pair.conjugate()), mode(complex(-1.0, 1.0))]
    sm = stability_summary(modes)
    assert sm["stable"] and sm["verdict"] == "stable" and sm["unstable_modes"] == 0
    assert sm["slowest_stable"]["state"] == "v_y" and sm["slowest_stable"]["tau_s"] == pytest.approx(100.0)
    assert sm["least_damped"]["zeta"] == pytest.approx(zeta)
    assert sm["least_damped"]["period_s"] == pytest.approx(2 * math.pi / pair.imag)
    assert summary_lines(sm)[0].startswith("  summary     closed loop stable")


def test_an_unstable_loop_names_its_fastest_growing_mode_and_keeps_the_target_apart():
    modes = [mode(-1.0), mode(1 / 37.0, "h_w_1", "actuators"), mode(1 / 500.0, "r_x"),
             mode(1.0, "r_T_x", "actuators"), mode(0.0, "m_prop", "actuators")]
    sm = stability_summary(modes)
    assert not sm["stable"] and sm["verdict"] == "unstable" and sm["unstable_modes"] == 2
    assert sm["fastest_growing"]["state"] == "h_w_1" and sm["fastest_growing"]["tau_s"] == pytest.approx(-37.0)
    assert sm["marginal_modes"] == 1 and sm["target_modes"] == 1
    assert sm["target_growing"]["state"] == "r_T_x"  # the target's own orbit: listed apart, not counted
    text = "\n".join(summary_lines(sm))
    assert "UNSTABLE: 2 modes" in text and "tau = -37 s" in text and "apart: 1 modes" in text


def test_marginal_within_the_tolerance_only():
    sm = stability_summary([mode(-1.0), mode(0.5 * MARGIN / DT)])
    assert sm["verdict"] == "marginally stable" and not sm["stable"]
    sm = stability_summary([mode(-1.0), mode(5 * MARGIN / DT)])
    assert sm["verdict"] == "unstable"


def test_rpo_linearize_ends_with_its_summary():
    from tests.test_cli import III, rpo

    res = rpo("linearize", III, timeout=300)
    assert res.returncode == 0, res.stderr
    tail = res.stdout.strip().splitlines()
    first = next(i for i, ln in enumerate(tail) if ln.startswith("  summary"))
    assert all(ln.startswith("              ") for ln in tail[first + 1:])
    assert "closed loop" in tail[first]
