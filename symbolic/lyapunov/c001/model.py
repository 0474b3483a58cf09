"""001, the model the proof rests on (eqs. 12-20, reconstructed signs) and the constraint forms (eqs. 41-48)."""

from __future__ import annotations

import sympy as sp

from ...controllers import c001 as c
from ...physics.special import Step
from ..core import (
    Statement,
    claim_factory,
    lie_derivative,
)
from ..domains import (
    box,
)
from .common import CONS, MODEL, R_T, THETA, Z_N, _pv, _six, _unit_dq_var

claim = claim_factory(__name__)

def _relative_velocity_rate() -> Statement:
    """Eqs. 17, 19-20: d/dt omega_S/T^S (eq. 14) along the pose kinematics (eq. 15) and the inertial dynamics of
    S (eq. 17) and T (any omega_T/I-dot^T) is eq. 20 (signs reconstructed)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    WSI, wsi6 = _pv("omegaSI")
    WT, wt6 = _pv("omegaTI")
    WDT, wdt6 = _pv("omegadotTI")
    FG, fg6 = _pv("fG")
    FD, fd6 = _pv("fD")
    FC, fc6 = _pv("fC")
    m = sp.Symbol("m", positive=True)
    Mi = sp.Matrix(sp.symbols("M_1:4", positive=True))
    J = c.dual_inertia(m, Mi)
    W = c.relative_dual_velocity(WSI, WT, q)                                               # eq. 14
    states = list(q) + list(wsi6) + list(wt6)
    rates = list(c.pose_rate(q, W)) + list(_six(c.inertial_dual_acceleration(J, WSI, FG + FD + FC))) + list(wdt6)
    lhs = sp.Matrix([lie_derivative(Wi, states, rates) for Wi in W])
    rhs = c.relative_dual_acceleration(J, FG, FD, FC, WSI, W, q, WDT)                      # eq. 20
    dom = [_unit_dq_var(q), box(wsi6[0:3, :], -0.01, 0.01), box(wsi6[3:6, :], -8000, 8000),
           box(wt6[0:3, :], -0.01, 0.01), box(wt6[3:6, :], -8000, 8000), box(wdt6, -10, 10),
           box(fg6, -600, 600), box(fd6, -1, 1), box(fc6, -1, 1), box(m, 30, 100), box(Mi, 5, 30)]
    return Statement(lhs, "==", rhs, dom, assumptions=["omega_T/I^T pure, its rate any pure dual vector"])


def _unit_dq_constraints(q):
    return [sum((q[i] ** 2 for i in range(4)), sp.S.Zero) - 1, sum((q[i] * q[4 + i] for i in range(4)), sp.S.Zero)]


def _pose_kinematics() -> Statement:
    """Eqs. 12-15: d/dt q_S/T (eq. 13) along q_T/I-dot = q_T/I omega_T/I^T / 2 and q_S/I-dot = q_S/I omega_S/I^S / 2
    is pose_rate(q_S/T, omega_S/T^S) with omega_S/T^S of eq. 14."""
    qT = sp.Matrix(sp.symbols("qT_1:9", real=True))
    qS = sp.Matrix(sp.symbols("qS_1:9", real=True))
    WT, wt6 = _pv("omegaTI")
    WSI, wsi6 = _pv("omegaSI")
    q = c.relative_pose(qT, qS)
    rates = list(c.pose_rate(qT, WT)) + list(c.pose_rate(qS, WSI))
    lhs = sp.Matrix([lie_derivative(qi, list(qT) + list(qS), rates) for qi in q])
    rhs = c.pose_rate(q, c.relative_dual_velocity(WSI, WT, q))
    dom = [_unit_dq_var(qT, 7e6), _unit_dq_var(qS, 7e6), box(wt6[0:3, :], -0.01, 0.01),
           box(wt6[3:6, :], -8000, 8000), box(wsi6[0:3, :], -0.01, 0.01), box(wsi6[3:6, :], -8000, 8000)]
    # the residual is exactly (q q* - 1) omega_T/I^T q / 2: zero modulo the constraints (output by output, ~10 s)
    return Statement(lhs, "==", rhs, dom, constraints=_unit_dq_constraints(qT) + _unit_dq_constraints(qS),
                     assumptions=["q_T/I, q_S/I unit dual quaternions (q_r o q_r = 1, q_r o q_d = 0)"])


def _constraint_dq_forms() -> Statement:
    """Eqs. 42-45, 47-48: beta_T = q o (K_u q) = u . r^S, |U r^S|^2 = eq. 45, eq. 48 = eq. 47, with
    r^S = 2 q_r* q_d (eq. 7) and u = +z_S (as ``apf_terms``)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    RS, RT = sp.symbols("R_S R_T", positive=True)
    K_u = c.camera_axis_matrix(sp.Matrix([0, 0, 1]))
    _, r = c.position_from_dq(q)
    bT = c.beta_T(q, K_u)
    lhs = sp.Matrix([bT, c.off_axis_sq(q, bT), c.beta_ca_dq(q, RS, RT)])
    rhs = sp.Matrix([r[2], r[0] ** 2 + r[1] ** 2, c.beta_ca_vector(r, RS, RT)])
    return Statement(lhs, "==", rhs, [_unit_dq_var(q), box([RS, RT], 0.5, 5)], constraints=_unit_dq_constraints(q),
                     assumptions=["q_r o q_r = 1, q_r o q_d = 0"])


def _fov_dq_form() -> Statement:
    """Eq. 46 = eq. 41 at r^S = 2 q_r* q_d: the radicands agree modulo the unit-dual-quaternion constraints, and
    the case split on eq. 46's max(., 0) finds its negative branch empty (the radicand equals |U r|^2 >= 0)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    K_u = c.camera_axis_matrix(sp.Matrix([0, 0, 1]))
    z_Np = c.fov_vertex_offset(Z_N, R_T, THETA)
    _, r = c.position_from_dq(q)
    lhs = c.beta_fov_dq(q, K_u, THETA, z_Np).replace(Step, lambda a: sp.Heaviside(a, 1))
    return Statement(lhs, "==", c.beta_fov_vector(r, THETA, z_Np), [_unit_dq_var(q)],
                     constraints=_unit_dq_constraints(q),
                     assumptions=["unit dual quaternion", "theta, z_N, R_T of sec. 7"])


CLAIMS = [
    claim("model.pose_kinematics", MODEL, "spacecraft", "12-15",
        "d/dt (q_T/I* q_S/I) = q_S/T omega_S/T^S / 2 with omega_S/T^S of eq. 14", _pose_kinematics,
        note="Identity modulo the unit-dual-quaternion constraints (residual (q q* - 1) omega_T/I^T q / 2)."),
    claim("model.relative_acceleration", MODEL, "spacecraft", "14, 17, 19-20",
        "d/dt omega_S/T^S (eq. 14) along eqs. 15, 17 (S) and any omega_T/I-dot^T is eq. 20", _relative_velocity_rate,
        note="Proves the reconstructed signs of eqs. 19-20 (- q* omega_T/I-dot q, + omega_S/T x omega_S/I)."),
    claim("constraints.dq_forms", CONS, "spacecraft", "42-45, 47-48",
        "beta_T = q o (K_u q) = u . r^S, |U r^S|^2 = eq. 45, eq. 48 = eq. 47 (r^S = 2 q_r* q_d)",
        _constraint_dq_forms),
    claim("constraints.fov_dq_form", CONS, "spacecraft", "41, 46", "eq. 46 = eq. 41 (sign of u . r as reconstructed)",
        _fov_dq_form),
]
