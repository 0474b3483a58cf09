"""001, Proposition 2 on the spacecraft layer: the artificial potential of eqs. 51-56."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c001 as c
from ...physics.rotations import dq_conj, dq_mul
from ..core import (
    Statement,
    claim_factory,
)
from ..domains import (
    box,
    custom,
    unit_vector,
)
from .common import (
    APF,
    Q_D,
    R_D,
    RHO_MAX,
    _admissible_var,
    _desired_dq,
    _dq_rows,
    _nostep,
    _paper_apf,
    _six,
)
from .pose import _Loop, _o

claim = claim_factory(__name__)

# ---- spacecraft layer: the APF of eqs. 51-55

def _gradient_statement(printed: bool) -> Statement:
    """Eqs. 54-55 against the derivatives of eqs. 53, 46, 48 (three blocks, see the claim)."""
    L = _Loop(apf=True)
    q, e, qD = L.q, L.e, L.qD
    gF = sp.Matrix(sp.symbols("gFOV_1:9", real=True))
    gC = sp.Matrix(sp.symbols("gCA_1:9", real=True))
    E = [sp.Function(f"DQ_{i + 1}")(*q) for i in range(8)]
    BF, BC = sp.Function("B_FOV")(*q), sp.Function("B_CA")(*q)
    Vp = c.apf(sp.Matrix(E), L.k_a, L.k_r, BF, BC)
    rep = {}
    for qi, a, b in zip(q, gF, gC, strict=True):
        rep[sp.Derivative(BF, qi)], rep[sp.Derivative(BC, qi)] = a, b
        for Ei, di in zip(E, L.dq_err, strict=True):
            rep[sp.Derivative(Ei, qi)] = sp.diff(di, qi)
    dVp = sp.Matrix([sp.diff(Vp, qi) for qi in q]).xreplace(rep).xreplace(
        {BF: L.bF, BC: L.bC, **dict(zip(E, e, strict=True))})
    bF_full = c.beta_fov_dq(q, L.K_u, L.theta, L.z_Np)
    dbF = sp.Matrix([_nostep(sp.diff(bF_full, qi)) for qi in q])
    dbC = sp.Matrix([sp.diff(L.bC_q, qi) for qi in q])
    if printed:
        # eq. 54: 2 V_p/(Dq o Dq) [q_D*]^T Dq - k_r (Dq o Dq)(grad b_F / b_F^2 + grad b_C / b_C^2)
        x = sp.Matrix(sp.symbols("_x0:8", real=True))
        Lm = dq_mul(dq_conj(qD), x).jacobian(x)
        ee = _o(e, e)
        g54 = 2 * c.apf(e, L.k_a, L.k_r, L.bF, L.bC) / ee * (Lm.T * e) - L.k_r * ee * (gF / L.bF**2 + gC / L.bC**2)
        # eq. 55: grad b_F = -2 K_u q + cot^2(theta) (4 q - 2 b_T K_u q) / (b_F + b_T + z_N'), grad b_C = 8 q
        bT = (q.T * L.K_u * q)[0]
        g55F = -2 * L.K_u * q + (4 * q - 2 * bT * L.K_u * q) / sp.tan(L.theta)**2 / (L.bF_q + bT + L.z_Np)
        g55C = 8 * q
    else:
        g54 = c.apf_gradient(e, qD, L.k_a, L.k_r, L.bF, L.bC, gF, gC)
        g55F = _nostep(c.grad_beta_fov(q, L.K_u, L.theta, 0))
        g55C = c.grad_beta_ca(q)
    lhs = sp.Matrix.vstack(dVp, dbF, dbC)
    rhs = sp.Matrix.vstack(g54, g55F, g55C)
    dom = [d for d in L.domain() if not (set(d.symbols) & {L.eps})] + [box(gF, -10, 10), box(gC, -10, 10)]
    dom = [d for d in dom if set(d.symbols) & (lhs.free_symbols | rhs.free_symbols)]
    return Statement(lhs, "==", rhs, dom,
                     assumptions=["off the camera axis (|U r| > 0, where eq. 46 is differentiable)",
                                  "Delta q != 0 for the printed 2 V_p/(Dq o Dq)"])


def _vdot_apf(corrected: bool) -> Statement:
    """Eqs. 53-63 with the APF: V-dot along the loop under eq. 57 with the coded gradient."""
    if not corrected:
        L = _Loop(apf=True, eps=0)
        return Statement(L.Vdot, "==", L.eq63, [d for d in L.domain() if L.eps not in d.symbols],
                         assumptions=["eqs. 54-55 exact (fov_eps = 0)", "Delta d = d^S - d_hat^S"])
    L = _Loop(apf=True, eps=None)
    q = L.q
    bT = (q.T * L.K_u * q)[0]
    s = 4 * (_o(q, q) - 1) - bT**2                           # eq. 45: |U r|^2
    sdot = sum((sp.diff(s, qi) * qd for qi, qd in zip(q, L.qdot, strict=True)), sp.S.Zero)
    R_eps = (L.k_p * L.k_r / sp.tan(L.theta) * _o(L.e, L.e) / L.bF**2
             * (1 / sp.sqrt(s) - 1 / sp.sqrt(s + L.eps**2)) * sdot)
    return Statement(L.Vdot, "==", L.eq63 + R_eps, L.domain(),
                     assumptions=["rpo's eq. 55: 1/sqrt(s) -> 1/sqrt(s + fov_eps^2)", "Delta d = d^S - d_hat^S"])


def _convex() -> Statement:
    """Eq. 56: the Hessian of V_p (eq. 53) is positive definite on the admissible set (k_a >> k_r)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    v = sp.Matrix(sp.symbols("v_1:9", real=True))
    t = sp.Symbol("t", real=True)
    Vp, _, _ = _paper_apf(q)
    d2 = sp.diff(Vp.xreplace(dict(zip(q, q + t * v, strict=True))), t, 2).subs(t, 0)   # v^T (grad^2 V_p) v
    return Statement(d2, ">", 0, [_admissible_var(q, 1e-3), unit_vector(v)], symbolic=False,
                     zero_at=list(v), trials=3000,
                     assumptions=["k_a = 0.75, k_r = 2.5e-5, theta = 45 deg, z_N = 1.2 m, R_S = 2.1 m, R_T = 1.5 m,"
                                  " q_D/T, r_D/T of sec. 7", "admissible pose, off the camera axis"])


def _critical_points(q, crit, dq_err) -> np.ndarray:
    """Roots of vec(q* (E grad V_p)) (rpo's gradient, fov_eps) on the unit dual quaternions, found from
    the desired pose and from its antipode -q_D (same physical pose, other sign of the quaternion)."""
    from scipy.optimize import least_squares
    from scipy.spatial.transform import Rotation

    f = sp.lambdify(list(q), list(crit), "numpy")
    qD = _desired_dq()

    def pose(x, sign):
        qr = sign * (Rotation.from_quat(np.array(Q_D)) * Rotation.from_rotvec(x[:3])).as_quat()
        return _dq_rows(qr[None, :], (np.array(R_D) + x[3:])[None, :])[0]

    out = []
    for sign in (1.0, -1.0):
        res = least_squares(lambda x, s=sign: np.array(f(*pose(x, s)), dtype=float), np.zeros(6),
                            xtol=1e-15, ftol=1e-15, gtol=1e-15)
        p = pose(res.x, sign)
        if float(np.max(np.abs(f(*p)))) > 1e-10:
            raise RuntimeError("critical point of V_p not found")
        out.append(p)
    assert np.allclose(out[0], qD, atol=1e-9)
    return np.array(out)


def _unique_minimum() -> Statement:
    """End of the proof of Prop. 2: vec(q* (E grad V_p)) = 0 only at q_S/T = q_D/T (Dq = 0)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    _, dq_err, grad = _paper_apf(q, on_axis=True)
    crit = _six(c.dq_vec(dq_mul(dq_conj(q), c.dq_swap(grad))))
    pts = _critical_points(q, crit, dq_err)

    def draw(z, env):
        return np.where(z[:, :1] < 0.0, pts[0][None, :], pts[1][None, :])

    dom = [custom(list(q), 1, draw, "critical points of V_p on the unit dual quaternions (roots of "
                                    "vec(q* (E grad V_p)) to 1e-10, scipy least_squares from q_D and -q_D)")]
    return Statement(c.circle(dq_err, dq_err), "==", 0, dom, symbolic=False, trials=20,
                     assumptions=["rpo's gradient (fov_eps = 1e-3 m), the paper's gains and desired pose"])


def _convex_far() -> Statement:
    """Eq. 56 on part of the admissible set: |r| in [40, 300] m, the target 20-80 % of the cone off the axis."""
    st = _convex()
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    st.domain[0] = _admissible_var(q, 0.2, 0.8, 40.0, RHO_MAX)
    st.assumptions = st.assumptions[:1] + ["40 m <= |r| <= 300 m, off-axis angle 20-80 % of the cone"]
    st.trials = 800
    return st


CLAIMS = [
    claim("apf.gradient", APF, "spacecraft", "53-55",
        "the gradient of eq. 54 with eq. 55 is the derivative of V_p (eq. 53) with eqs. 46, 48",
        lambda: _gradient_statement(True), corrected=lambda: _gradient_statement(False),
        correction="rpo writes eq. 54 without the 0/0 division (2 (k_a + k_r (1/b_F + 1/b_C)) [q_D*]^T Dq) and "
                   "eq. 55 as -2 K_u q - cot(theta)(4 q - 2 b_T K_u q)/sqrt(s) (same value); with fov_eps > 0 "
                   "the denominator is sqrt(s + fov_eps^2): see c001.pose.Vdot_apf",
        note="Signs as reconstructed (the extraction lost them); the printed forms equal the derivative off the "
             "camera axis (s = |U r|^2 > 0) and away from the goal (Delta q != 0)."),
    claim("pose.Vdot_apf", APF, "spacecraft", "53-63",
        "V-dot along the loop with the APF and the coded gradient: eq. 63 (plus rpo's fov_eps term)",
        lambda: _vdot_apf(False), corrected=lambda: _vdot_apf(True),
        correction="rpo's law (fov_eps > 0): V-dot = eq. 63 + R_eps, R_eps = k_p k_r cot(theta) (Dq o Dq)/b_F^2 "
                   "(1/sqrt(s) - 1/sqrt(s + eps^2)) s-dot, s = |U r|^2",
        note="With the exact gradient (fov_eps = 0, the paper) eq. 63 holds for the APF.  rpo's regularisation "
             "makes the law the gradient of nothing: R_eps is sign-indefinite, vanishes for |U r| >> fov_eps = 1 mm "
             "(relative size eps^2/(2 s)) and is bounded near the camera axis; the proof does not cover it."),
    claim("apf.convex", APF, "spacecraft", "56", "the Hessian of V_p is positive definite on the admissible set "
        "(k_a >> k_r)", _convex, about="paper",
        note="Eq. 56 is not implemented in rpo (it serves only this argument); the Hessian here is SymPy's, of the "
             "coded eq. 53.  Its indefinite terms are unbounded on the admissible set: v^T (grad^2 V_p) v = -1.6e6 "
             "3.8 m from the target with the target 1.5 cm off the camera axis (terms ~ 1/|U r|; on the axis, "
             "where the paper starts and ends, V_p is not twice differentiable), and -3.5e4 at 49 m with "
             "beta_FOV = 1e-4 m (terms ~ 1/beta^2), so no ratio k_a/k_r makes it positive definite.  The proof used "
             "convexity only for a unique minimum, i.e. that vec(q* (E grad V_p)) = 0 forces q_S/T = q_D/T; see "
             "c001.apf.unique_minimum (convexity in R^8 would not give that on the unit dual quaternions anyway).  "
             "Not only near the boundary: v^T (grad^2 V_p) v = -0.052 at |r| = 10 m with the target 10-90 % of the "
             "cone off-axis (review); on |r| in [40, 300] m, 20-80 % of the cone it held (c001.apf.convex_far)."),
    claim("apf.convex_far", APF, "spacecraft", "56", "the Hessian of V_p is positive definite for |r| in [40, 300] m, "
        "20-80 % of the cone off-axis", _convex_far, about="paper",
        note="The region where eq. 56 was not disproved (review: min 2.2e-3); see c001.apf.convex for where it fails."),
    claim("apf.unique_minimum", APF, "spacecraft", "53, end of the proof of Prop. 2",
        "vec(q* (E grad V_p)) = 0 only at q_S/T = q_D/T", _unique_minimum, about="paper",
        note="q_S/T = -q_D/T (the same physical pose, the other sign of the dual quaternion) shifted ~1e-7 m "
             "radially is also a critical point: Delta q = q_E - 1 is not sign-invariant, V_p ~ 4 k_a there "
             "(a maximum along the attitude directions).  It is an equilibrium of the closed loop with Delta d = 0, "
             "so the convergence to q_D/T is not global; from q_E,w < 0 the loop heads for q_E = +1, the long way "
             "round (unwinding).  rpo: the scenario starts at q_E,w = 0.76 (docs/controllers/c001.md)."),
]
