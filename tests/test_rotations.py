"""Check 3: rotation algebra (symbolic/physics/rotations.py) against scipy.spatial.transform.Rotation."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.spatial.transform import Rotation

from rpo.symbolic.physics import rotations as rot

rng = np.random.default_rng(42)
Q = sp.Matrix(sp.symbols("qx qy qz qw", real=True))
P = sp.Matrix(sp.symbols("px py pz pw", real=True))
V = sp.Matrix(sp.symbols("vx vy vz", real=True))


def f(args, expr):
    g = sp.lambdify(args, expr, "numpy")
    return lambda *a: np.asarray(g(*a), float).reshape(np.shape(expr) if hasattr(expr, "shape") else ())


quat_mul = f([list(P), list(Q)], rot.quat_mul(P, Q))
quat_dcm = f([list(Q)], rot.quat_to_dcm(Q))
quat_rotate = f([list(Q), list(V)], rot.quat_rotate(Q, V))
quat_rate = f([list(Q), list(V)], rot.quat_rate(Q, V))
mrp_from_quat = f([list(Q)], rot.mrp_from_quat(Q))
mrp_dcm = f([list(V)], rot.mrp_to_dcm(V))
quat_from_mrp = f([list(V)], rot.quat_from_mrp(V))
mrp_shadow = f([list(V)], rot.mrp_shadow(V))
mrp_rate = f([list(V), list(Q)[:3]], rot.mrp_rate(V, sp.Matrix(list(Q)[:3])))
ROTS = Rotation.random(50, random_state=7)


def same_rotation(q1, q2):
    return min(np.abs(q1 - q2).max(), np.abs(q1 + q2).max())


@pytest.mark.parametrize("i", range(50))
def test_dcm_product_and_rotation_against_scipy(i):
    r1, r2 = ROTS[i], ROTS[(i + 1) % 50]
    q1, q2 = r1.as_quat(), r2.as_quat()  # scipy default: scalar last
    v = rng.normal(size=3)
    assert np.allclose(quat_dcm(q1), r1.as_matrix(), atol=1e-14)
    assert same_rotation(quat_mul(q1, q2).ravel(), (r1 * r2).as_quat()) < 1e-14
    assert np.allclose(quat_rotate(q1, v).ravel(), r1.apply(v), atol=1e-13)
    # the papers' attitude matrix (000 eq. 20, Shuster) is the transpose, with the same 4 numbers
    assert np.allclose(quat_dcm(q1).T, r1.inv().as_matrix(), atol=1e-14)


@pytest.mark.parametrize("i", range(20))
def test_scalar_first_convention_against_scipy(i):
    r = ROTS[i]
    q_first = r.as_quat(scalar_first=True)
    q_last = np.roll(q_first, -1)
    assert np.allclose(quat_dcm(q_last), Rotation.from_quat(q_first, scalar_first=True).as_matrix(), atol=1e-14)


@pytest.mark.parametrize("i", range(20))
def test_quaternion_kinematics_against_scipy_composition(i):
    r, w, h = ROTS[i], rng.normal(size=3) * 0.3, 1e-6
    q = r.as_quat()
    # body rate w: R(t + h) = R(t) * exp(w h) (body-frame increment)
    q_next = (r * Rotation.from_rotvec(w * h)).as_quat()
    q_prev = (r * Rotation.from_rotvec(-w * h)).as_quat()
    q_next *= np.sign(q_next @ q)
    q_prev *= np.sign(q_prev @ q)
    assert np.allclose(quat_rate(q, w).ravel(), (q_next - q_prev) / (2 * h), atol=1e-9)


@pytest.mark.parametrize("i", range(20))
def test_mrp_against_scipy(i):
    r = ROTS[i]
    q = r.as_quat()
    q = q * np.sign(q[3])  # scipy's MRPs are the |sigma| <= 1 set (w >= 0)
    s = mrp_from_quat(q).ravel()
    assert np.allclose(s, r.as_mrp(), atol=1e-14)
    assert np.allclose(mrp_dcm(s), r.as_matrix(), atol=1e-13)
    assert same_rotation(quat_from_mrp(s).ravel(), q) < 1e-14
    sh = mrp_shadow(s).ravel()
    assert np.allclose(mrp_dcm(sh), r.as_matrix(), atol=1e-12)  # shadow set: same attitude
    assert np.isclose(np.linalg.norm(sh) * np.linalg.norm(s), 1.0)
    # kinematics against finite differences of the scipy rotation
    w, h = rng.normal(size=3) * 0.3, 1e-6
    sp_next = (r * Rotation.from_rotvec(w * h)).as_mrp()
    sp_prev = (r * Rotation.from_rotvec(-w * h)).as_mrp()
    assert np.allclose(mrp_rate(s, w).ravel(), (sp_next - sp_prev) / (2 * h), atol=1e-8)


def test_mrp_switch_picks_the_short_set():
    sw = f([list(V)], rot.mrp_switch(V))
    s = np.array([0.5, -0.6, 0.7])  # |s| = 1.049 (004's initial error): outside the unit ball
    out = sw(s).ravel()
    assert np.linalg.norm(out) < 1 and np.allclose(mrp_dcm(out), mrp_dcm(s), atol=1e-13)
    assert np.allclose(sw(s / 2).ravel(), s / 2)


@pytest.mark.parametrize("frame", ["A", "B"])
def test_dual_quaternion_pose_round_trip_and_composition(frame):
    T = sp.Matrix(sp.symbols("tx ty tz", real=True))
    dq_of = f([list(Q), list(T)], rot.dq_from_pose(Q, T, frame))
    D1 = sp.Matrix(sp.symbols("a0:8", real=True))
    D2 = sp.Matrix(sp.symbols("b0:8", real=True))
    dq_mul = f([list(D1), list(D2)], rot.dq_mul(D1, D2))
    q_of, t_of = rot.dq_to_pose(D1, frame)
    pose = f([list(D1)], sp.Matrix.vstack(q_of, t_of))
    for i in range(10):
        r1, r2 = ROTS[i], ROTS[i + 10]
        t1, t2 = rng.normal(size=3), rng.normal(size=3)
        d1 = dq_of(r1.as_quat(), t1).ravel()
        back = pose(d1).ravel()
        assert np.allclose(back[:4], r1.as_quat()) and np.allclose(back[4:], t1, atol=1e-14)
        # composition: pose of C in A = pose of B in A then pose of C in B
        d2 = dq_of(r2.as_quat(), t2).ravel()
        q12, t12 = pose(dq_mul(d1, d2).ravel()).ravel()[:4], pose(dq_mul(d1, d2).ravel()).ravel()[4:]
        assert same_rotation(q12, (r1 * r2).as_quat()) < 1e-14
        # position of C's origin in A: t1 + R1 t2 (frame A); in C's own axes for frame B
        tA = (t1 + r1.apply(t2)) if frame == "A" else None
        if frame == "A":
            assert np.allclose(t12, tA, atol=1e-13)
        else:
            tB_expected = (r1 * r2).inv().apply(r1.apply(t1) + r1.apply(r2.apply(t2)))
            assert np.allclose(t12, tB_expected, atol=1e-13)
