"""Every search domain of the verification report has SI units: each domain symbol of each claim's statements
has a unit in its controller's ``UNITS`` (``symbolic/lyapunov/<controller>/common.py``), and the report prints it."""

from __future__ import annotations

import pytest
import sympy as sp

from rpo.symbolic import lyapunov
from rpo.symbolic.lyapunov.core import Claim, Statement
from rpo.symbolic.lyapunov.domains import ball, box, fixed, unit_quaternion
from rpo.symbolic.lyapunov.report import domain_text
from rpo.symbolic.lyapunov.units import MissingUnit, candidates, declare, missing, unit_of, units_text


@pytest.mark.parametrize("controller", lyapunov.controllers())
def test_every_domain_symbol_has_a_unit(controller):
    """Builds each statement of the controller (about 20 s for all four) and names every claim and symbol
    without a declared unit."""
    units = lyapunov.module(controller).UNITS
    lacking = []
    for cl in lyapunov.claims(controller):
        for tag in ("paper", "corrected"):
            build = getattr(cl, tag)
            if build is not None:
                lacking += [f"{cl.id} ({tag}): {s}" for s in missing(cl, build().domain, units)]
    assert not lacking, "no unit declared for:\n" + "\n".join(sorted(set(lacking)))


def _claim(controller="c004", part="position", name="position.test"):
    return Claim(f"{controller}.{name}", controller, part, "abstract", "-", "-", None)


def test_lookup_strips_vector_indices_and_prefers_the_most_specific_name():
    assert candidates("r_e_1") == ["r_e_1", "r_e"]
    assert candidates("omega_c1") == ["omega_c1", "omega_c"]
    assert candidates("h_hat_xx") == ["h_hat_xx", "h_hat"]
    assert candidates("acc_dx") == ["acc_dx", "acc_d"]
    units = {"a": "1", "a_3": "1/(kg m^2)"}
    cl = _claim()
    assert unit_of(cl, sp.Symbol("a_3"), units) == "1/(kg m^2)"
    assert unit_of(cl, sp.Symbol("a_2"), units) == "1"
    assert unit_of(cl, sp.Symbol("b_2"), units) is None


def test_a_name_with_two_meanings_takes_the_claims_context():
    units = {"b": {"attitude": "1/(kg m^2)", "translation": "1/kg"},
             "u_M": {"": "N", "gains.kappa1_varpi1": "N m"}}
    b = sp.Symbol("b")
    assert unit_of(_claim("c000", "attitude", "attitude.V_definite"), b, units) == "1/(kg m^2)"
    assert unit_of(_claim("c000", "translation x", "translation_x.V_definite"), b, units) == "1/kg"
    assert unit_of(_claim("c000", "boundary layer", "convergence"), b, units) is None
    u = sp.Symbol("u_M")
    assert unit_of(_claim("c002", "auxiliary system", "gains.kappa1_varpi1"), u, units) == "N m"
    assert unit_of(_claim("c002", "auxiliary system", "gains.kappa2_varpi2"), u, units) == "N"


def test_units_are_declared_once():
    with pytest.raises(ValueError, match="declared twice.*k0"):
        declare({"k0": "N/m"}, {"k0": "N/m", "m": "kg"})


def test_domain_text_prints_the_units():
    r, v, q = sp.symbols("r_e_1:4"), sp.symbols("v_e_1:4"), sp.symbols("q_1:5")
    m, d, s = sp.Symbol("m"), sp.symbols("d_f_1:4"), sp.symbols("s_1_1:4")
    units = {"r_e": "m", "v_e": "m/s", "q": "1", "m": "kg", "d_f": "N", "s_1": "m/s", "s_2": "rad/s"}
    cl = _claim()
    st = Statement(sp.S.Zero, "==", sp.S.Zero, [box(r, -40, 40), box(v, -2, 2), unit_quaternion(q), fixed(m, [50]),
                                                ball(d, 1.0), ball(s, m)], assumptions=["m > 0"])
    texts = [units_text(cl, var, units) for var in st.domain]
    assert texts == [" m", " m/s", "", " (kg)", " N", " (m/s)"]
    mixed = box([*s[:1], sp.Symbol("s_2_1"), q[0]], -2, 2)
    assert units_text(cl, mixed, units) == " (s_1_1: m/s; s_2_1: rad/s; q_1: dimensionless)"
    with pytest.raises(MissingUnit, match=r"c004\.position\.test: no unit declared for the domain symbol w"):
        units_text(cl, box(sp.Symbol("w"), 0, 1), units)
    assert domain_text(st) == ("r_e_1, r_e_2, r_e_3: in [-40, 40]; v_e_1, v_e_2, v_e_3: in [-2, 2]; q_1, q_2, q_3, "
                               "q_4: unit quaternion; m: fixed; d_f_1, d_f_2, d_f_3: |.| <= 1.0; s_1_1, s_1_2, "
                               "s_1_3: |.| <= m (assumptions: m > 0)")


def test_the_report_prints_a_claims_search_domain_with_units():
    cl = next(c for c in lyapunov.claims("c004") if c.id == "c004.position.V1_definite")
    text = domain_text(cl.paper(), cl)
    assert "r_e_1, r_e_2, r_e_3: in [-30, 30] m;" in text
    assert "m: in [20, 100] kg" in text and "k_0: in [0.01, 1] N/m" in text


def test_a_ball_with_a_computed_radius_prints_its_docstring_not_its_repr():
    """The report's text is reproducible: no memory address of a radius function in it."""
    def radius(env):
        """alpha1 |w| + alpha2 (eq. 99)"""

    x = sp.symbols("x_1:3")
    assert ball(x, radius).describe == "|.| <= alpha1 |w| + alpha2 (eq. 99)"
    assert ball(x, lambda env: 1.0).describe == "|.| <= <lambda>(...)"
    assert ball(x, sp.Symbol("D")).describe == "|.| <= D"
