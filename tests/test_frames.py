"""rpo.runtime.frames: quaternion conventions against SciPy and the frames against the generated orbit."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rpo.runtime import frames as fr

RNG = np.random.default_rng(20240611)
N = 200


def random_quats(n=N):
    return Rotation.random(n, random_state=RNG).as_quat()


def same_rotation(a, b, tol=1e-12):
    """q and -q are the same rotation."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    d = np.minimum(np.linalg.norm(a - b, axis=-1), np.linalg.norm(a + b, axis=-1))
    return np.all(d < tol)


def rotate(q, v):
    """v_A = q v_B q* with the Hamilton product, written without SciPy."""
    qv = np.concatenate([v, np.zeros(v.shape[:-1] + (1,))], axis=-1)
    return fr.quat_multiply(fr.quat_multiply(q, qv), fr.quat_conjugate(q))[..., :3]


# --------------------------------------------------------------------------- algebra


def test_scalar_order_against_scipy_and_round_trip():
    q = random_quats()
    first = fr.scalar_last_to_first(q)
    np.testing.assert_allclose(first, Rotation.from_quat(q).as_quat(scalar_first=True, canonical=False), atol=1e-15)
    np.testing.assert_array_equal(first[:, 0], q[:, 3])
    np.testing.assert_array_equal(fr.scalar_first_to_last(first), q)
    np.testing.assert_allclose(Rotation.from_quat(first, scalar_first=True).as_matrix(),
                               Rotation.from_quat(q).as_matrix(), atol=1e-14)
    # single quaternion
    np.testing.assert_array_equal(fr.scalar_last_to_first([1, 2, 3, 4]), [4, 1, 2, 3])
    np.testing.assert_array_equal(fr.scalar_first_to_last([4, 1, 2, 3]), [1, 2, 3, 4])


def test_hamilton_product_matches_scipy_composition():
    a, b = random_quats(), random_quats()
    ab = fr.quat_multiply(a, b)
    assert same_rotation(ab, (Rotation.from_quat(a) * Rotation.from_quat(b)).as_quat())
    # not commutative: the order matters and is tested
    assert not same_rotation(ab, fr.quat_multiply(b, a), tol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(ab, axis=-1), 1.0, atol=1e-14)


def test_dcm_is_C_A_from_B_for_q_B_A():
    q = random_quats()
    v = RNG.standard_normal((N, 3))
    C = fr.dcm_from_quat(q)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", C, v), rotate(q, v), atol=1e-12)
    np.testing.assert_allclose(C, Rotation.from_quat(q).as_matrix(), atol=1e-15)
    # composition q_C_A = q_B_A ⊗ q_C_B  <=>  C_{A<-C} = C_{A<-B} C_{B<-C}
    q2 = random_quats()
    np.testing.assert_allclose(fr.dcm_from_quat(fr.quat_multiply(q, q2)), C @ fr.dcm_from_quat(q2), atol=1e-12)


def test_quat_from_dcm_round_trip_and_inverse():
    q = random_quats()
    back = fr.quat_from_dcm(fr.dcm_from_quat(q))
    assert np.all(back[:, 3] >= 0)
    assert same_rotation(back, q)
    ident = fr.quat_multiply(q, fr.quat_conjugate(q))
    np.testing.assert_allclose(ident, np.tile([0, 0, 0, 1.0], (N, 1)), atol=1e-14)


def test_rotation_angle_and_euler_helpers():
    q = random_quats()
    np.testing.assert_allclose(fr.rotation_angle(q), Rotation.from_quat(q).magnitude(), atol=1e-7)
    np.testing.assert_allclose(fr.rotation_angle(-q), fr.rotation_angle(q))
    assert fr.rotation_angle([0, 0, 0, 1]) == 0.0
    np.testing.assert_allclose(fr.rotation_angle([1, 0, 0, 0]), np.pi)
    angles = fr.euler_from_quat(q, "ZYX", degrees=True)
    assert same_rotation(fr.quat_from_euler("ZYX", angles, degrees=True), q, tol=1e-10)
    # a 90 deg yaw maps X to Y
    q_yaw = fr.quat_from_euler("ZYX", [90, 0, 0])
    np.testing.assert_allclose(fr.dcm_from_quat(q_yaw) @ [1, 0, 0], [0, 1, 0], atol=1e-15)


def test_normalise_rejects_zero():
    np.testing.assert_allclose(fr.quat_normalize([0, 0, 0, 2]), [0, 0, 0, 1])
    with pytest.raises(ValueError):
        fr.quat_normalize([0, 0, 0, 0])
    with pytest.raises(ValueError):
        fr.quat_multiply([1, 0, 0], [0, 0, 0, 1])


# --------------------------------------------------------------------------- the orbit frame R


def test_orbit_frame_axes_in_lvlh():
    C = fr.DCM_LVLH_FROM_ORBIT
    X_R, Y_R, Z_R = C.T  # columns: R axes in LVLH
    np.testing.assert_array_equal(X_R, [0, 1, 0])   # along-track = Y_L
    np.testing.assert_array_equal(Z_R, [-1, 0, 0])  # nadir = -X_L (radial)
    np.testing.assert_array_equal(Y_R, np.cross(Z_R, X_R))  # completes the right-handed system
    np.testing.assert_array_equal(Y_R, [0, 0, -1])  # = minus the orbit normal Z_L
    assert np.linalg.det(C) == pytest.approx(1.0)
    np.testing.assert_allclose(fr.dcm_from_quat(fr.Q_LVLH_ORBIT), C, atol=1e-15)


# --------------------------------------------------------------------------- against the generated orbit


@pytest.fixture(scope="module")
def model():
    from rpo.runtime.model.loader import load_model
    return load_model()


def orbit_at(model, t=0.0, **p):
    pv = model.vector("p", p)
    nu, r, r_dot, n, n_dot, r_eci, v_eci, q_IL = model.functions["target_orbit"](t, pv)
    return dict(nu=float(nu[0]), r=float(r[0]), r_dot=float(r_dot[0]), n=float(n[0]),
                r_eci=np.ravel(r_eci), v_eci=np.ravel(v_eci), q_IL=np.ravel(q_IL))


ELLIPTIC = dict(orbit_e=0.138, orbit_inc=np.radians(55), orbit_raan=np.radians(30), orbit_argp=np.radians(270))


@pytest.mark.parametrize("t", [0.0, 1234.5])
def test_q_IL_is_the_lvlh_attitude_of_target_orbit(model, t):
    o = orbit_at(model, t, **ELLIPTIC)
    C_IL = fr.dcm_from_quat(o["q_IL"])
    np.testing.assert_allclose(C_IL @ [o["r"], 0, 0], o["r_eci"], rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(C_IL @ [o["r_dot"], o["r"] * o["n"], 0], o["v_eci"], rtol=1e-12, atol=1e-9)
    h = np.cross(o["r_eci"], o["v_eci"])
    np.testing.assert_allclose(C_IL[:, 2], h / np.linalg.norm(h), atol=1e-12)


def test_identity_in_lvlh_and_orbit_frames(model):
    o = orbit_at(model, 0.0, **ELLIPTIC)  # at perigee: velocity is horizontal
    q_IL = o["q_IL"]
    assert same_rotation(fr.attitude_to_eci([0, 0, 0, 1], "lvlh", q_IL), q_IL)
    assert same_rotation(fr.attitude_to_eci([0, 0, 0, 1], "eci", q_IL), [0, 0, 0, 1])
    C_IB = fr.dcm_from_quat(fr.attitude_to_eci([0, 0, 0, 1], "orbit", q_IL))
    np.testing.assert_allclose(C_IB[:, 0], o["v_eci"] / np.linalg.norm(o["v_eci"]), atol=1e-12)  # X_R along v
    np.testing.assert_allclose(C_IB[:, 2], -o["r_eci"] / np.linalg.norm(o["r_eci"]), atol=1e-12)  # Z_R nadir


def test_orbit_frame_is_horizontal_away_from_perigee(model):
    o = orbit_at(model, 0.0, orbit_nu0=1.0, **ELLIPTIC)
    assert abs(o["r_dot"]) > 100  # flight-path angle is not zero here
    C_IB = fr.dcm_from_quat(fr.attitude_to_eci([0, 0, 0, 1], "orbit", o["q_IL"]))
    assert abs(C_IB[:, 0] @ o["r_eci"]) < 1e-6 * o["r"]  # X_R is the local horizontal


@pytest.mark.parametrize("frame", fr.FRAMES)
def test_round_trip_and_relative_attitude_is_frame_independent(model, frame):
    q_IL = orbit_at(model, 500.0, **ELLIPTIC)["q_IL"]
    qa, qb = random_quats(), random_quats()
    ea, eb = fr.attitude_to_eci(qa, frame, q_IL), fr.attitude_to_eci(qb, frame, q_IL)
    assert same_rotation(fr.attitude_from_eci(ea, frame, q_IL), qa, tol=1e-12)
    rel_eci = fr.quat_multiply(fr.quat_conjugate(ea), eb)
    rel_frame = fr.quat_multiply(fr.quat_conjugate(qa), qb)
    assert same_rotation(rel_eci, rel_frame, tol=1e-12)
    if frame != "eci":
        assert not same_rotation(ea, qa, tol=1e-3)


def test_frame_rates(model):
    o = orbit_at(model, 0.0, **ELLIPTIC)
    q_IL, n = o["q_IL"], o["n"]
    np.testing.assert_allclose(fr.frame_rate_eci("eci", q_IL, n), 0.0)
    # a body fixed in LVLH turns at n about Z_L; in R axes that is -n about Y_R
    for frame, expect in (("lvlh", [0, 0, n]), ("orbit", [0, -n, 0])):
        q_IB = fr.attitude_to_eci([0, 0, 0, 1], frame, q_IL)
        np.testing.assert_allclose(fr.body_rate_eci(np.zeros(3), q_IB, frame, q_IL, n), expect, atol=1e-18)
    # the rate is the LVLH rate of the generated orbit: finite-difference q_IL
    h = 1e-3
    q0, q1 = orbit_at(model, -h, **ELLIPTIC)["q_IL"], orbit_at(model, h, **ELLIPTIC)["q_IL"]
    dq = fr.quat_multiply(fr.quat_conjugate(q0), q1)  # rotation over 2h in LVLH axes
    w_L = Rotation.from_quat(dq).as_rotvec() / (2 * h)
    np.testing.assert_allclose(w_L, [0, 0, n], rtol=1e-6, atol=1e-12)
    with pytest.raises(ValueError):
        fr.frame_attitude("body", q_IL)


def test_dcm_from_quat_matches_scipy_bit_for_bit():
    """One quaternion is converted without a Rotation object: the same bits as SciPy's, normalised
    or not, and a zero quaternion still refused."""
    rng = np.random.default_rng(7)
    for i in range(20000):
        q = rng.normal(size=4) * rng.uniform(0.1, 10.0)
        if i % 5 == 0:
            q = q / np.linalg.norm(q)
        if i % 7 == 0:
            q[rng.integers(4)] = 0.0
        assert fr.dcm_from_quat(q).tobytes() == Rotation.from_quat(q).as_matrix().tobytes()
    qs = rng.normal(size=(5, 4))
    assert fr.dcm_from_quat(qs).tobytes() == Rotation.from_quat(qs).as_matrix().tobytes()
    with pytest.raises(ValueError):
        fr.dcm_from_quat([0.0, 0.0, 0.0, 0.0])


def test_quat_normalize_of_one_matches_the_array_path():
    """One quaternion is normalised with math.sqrt: the same bits as np.linalg.norm over rows,
    over magnitudes from 1e-8 to 1e8, signed zeros included; a zero quaternion still refused."""
    rng = np.random.default_rng(11)
    qs = rng.normal(size=(20000, 4)) * 10.0 ** rng.integers(-8, 9, size=(20000, 4))
    qs[::7, 2] = 0.0
    qs[::11, 0] = -0.0
    rows = fr.quat_normalize(qs)
    assert all(fr.quat_normalize(q).tobytes() == r.tobytes() for q, r in zip(qs, rows, strict=True))
    with pytest.raises(ValueError):
        fr.quat_normalize([0.0, 0.0, 0.0, 0.0])


def test_quat_multiply_of_two_matches_the_array_path():
    """Two single quaternions are multiplied in Python floats: the same bits as the broadcasting
    numpy path over rows, signed zeros included (a zero vector part, -0.0 components)."""
    rng = np.random.default_rng(13)
    n = 20000
    A = rng.normal(size=(n, 4)) * 10.0 ** rng.integers(-6, 7, size=(n, 4))
    B = rng.normal(size=(n, 4)) * 10.0 ** rng.integers(-6, 7, size=(n, 4))
    A[::5, 1] = 0.0
    B[::7, 2] = -0.0
    A[::13, :3] = 0.0
    B[::17] = [-0.0, 0.0, -0.0, 1.0]
    rows = fr.quat_multiply(A, B)
    assert all(fr.quat_multiply(a, b).tobytes() == r.tobytes() for a, b, r in zip(A, B, rows, strict=True))
