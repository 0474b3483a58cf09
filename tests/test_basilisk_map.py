"""tests/basilisk_map.py: each rpo <-> Basilisk conversion against an independent route.

No Basilisk needed (default run): SciPy's ``Rotation`` for quaternions and DCMs, the textbook
MRP definition (tan of a quarter of the angle), round trips, the shadow-set switch, rpo's own
generated ``env_outputs`` for the wheel speeds, and a finite difference for the LVLH rate.  The
checks against Basilisk's own ``RigidBodyKinematics`` and momentum are in test_xcheck_basilisk.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rpo.runtime.scenario.initial_state import _wheel_momentum

import basilisk_map as bmap
from conftest import ZERO_GAINS, quiet_params, target_state

RNG = np.random.default_rng(20261201)
QS = [q / np.linalg.norm(q) for q in RNG.normal(size=(200, 4))]


def _hamilton(a, b):
    """Hamilton product of scalar-last quaternions, written out (the textbook formula)."""
    av, aw, bv, bw = a[:3], a[3], b[:3], b[3]
    return np.concatenate([aw * bv + bw * av + np.cross(av, bv), [aw * bw - av @ bv]])


@pytest.mark.parametrize("i", range(0, 200, 20))
def test_dcm_and_quaternion_match_scipy_and_the_hamilton_product(i):
    q = QS[i]
    C = bmap.dcm_from_quat(q)
    np.testing.assert_allclose(C, Rotation.from_quat(q).as_matrix(), atol=1e-15)
    np.testing.assert_allclose(bmap.quat_from_dcm(C), q * np.sign(q[3]), atol=1e-14)
    v = RNG.normal(size=3)  # v_A = q v_B q*: C_{A<-B} v_B
    rotated = _hamilton(_hamilton(q, np.concatenate([v, [0.0]])), q * np.array([-1, -1, -1, 1]))
    np.testing.assert_allclose(C @ v, rotated[:3], atol=1e-14)


def test_quat_from_dcm_every_branch():
    """Shepperd's four branches (largest of w, x, y, z) all agree with SciPy."""
    for axis in np.eye(3):
        for ang in (0.1, 2.0, 3.1, np.pi):
            C = Rotation.from_rotvec(ang * axis).as_matrix()
            q = Rotation.from_matrix(C).as_quat()
            np.testing.assert_allclose(bmap.quat_from_dcm(C), q * (1 if q[3] >= 0 else -1), atol=1e-15)


def test_euler_parameters_are_the_quaternion_reordered():
    for q in QS[:20]:
        beta = bmap.quat_to_ep(q)
        np.testing.assert_allclose(beta, [q[3], q[0], q[1], q[2]], atol=1e-15)
        np.testing.assert_allclose(bmap.ep_to_quat(beta), q, atol=1e-15)
        # Schaub's [BN](beta) = C_{B<-N}: the transpose of rpo's C_{N<-B}
        b0, b1, b2, b3 = beta
        BN = np.array([[b0**2 + b1**2 - b2**2 - b3**2, 2 * (b1 * b2 + b0 * b3), 2 * (b1 * b3 - b0 * b2)],
                       [2 * (b1 * b2 - b0 * b3), b0**2 - b1**2 + b2**2 - b3**2, 2 * (b2 * b3 + b0 * b1)],
                       [2 * (b1 * b3 + b0 * b2), 2 * (b2 * b3 - b0 * b1), b0**2 - b1**2 - b2**2 + b3**2]])
        np.testing.assert_allclose(BN, Rotation.from_quat(q).as_matrix().T, atol=1e-15)


def test_mrp_is_tan_quarter_angle_and_round_trips():
    for q in QS:
        sigma = bmap.quat_to_mrp(q)
        rv = Rotation.from_quat(q).as_rotvec()  # angle in [0, pi]
        ang = np.linalg.norm(rv)
        np.testing.assert_allclose(sigma, np.tan(ang / 4) * rv / ang, atol=1e-14)
        assert np.linalg.norm(sigma) <= 1 + 1e-15
        q_back = bmap.mrp_to_quat(sigma)
        assert bmap.attitude_error(q_back, q) < 1e-14
        np.testing.assert_allclose(q_back, q * np.sign(q[3]), atol=1e-15)


def test_shadow_set_is_the_same_attitude_and_switch_at_one():
    for q in QS[:50]:
        s = bmap.quat_to_mrp(q)
        sh = bmap.mrp_shadow(s)
        assert np.linalg.norm(sh) >= 1 - 1e-15  # |sigma| <= 1 <=> |shadow| >= 1
        q_sh = bmap.mrp_to_quat(sh)
        np.testing.assert_allclose(q_sh, -bmap.mrp_to_quat(s), atol=1e-14)  # the other hemisphere
        assert bmap.attitude_error(q_sh, q) < 1e-14
        np.testing.assert_allclose(bmap.mrp_shadow(sh), s, atol=1e-15)
    # at 180 deg |sigma| = 1: both sets have unit norm and are each other's negative
    s = bmap.quat_to_mrp([0.0, 0.0, 1.0, 0.0])
    np.testing.assert_allclose(s, [0, 0, 1], atol=1e-16)
    np.testing.assert_allclose(bmap.mrp_shadow(s), -s)
    # a quaternion with w < 0 still gives the short set
    assert np.linalg.norm(bmap.quat_to_mrp(-QS[0])) <= 1


def test_attitude_error_small_angles_and_sign():
    q = QS[3]
    for ang in (1e-12, 1e-9, 1e-6, 0.3, 3.0):
        dq = Rotation.from_rotvec(ang * np.array([0.6, 0.0, 0.8])).as_quat()
        q2 = (Rotation.from_quat(q) * Rotation.from_quat(dq)).as_quat()
        assert bmap.attitude_error(q, q2) == pytest.approx(ang, rel=1e-6, abs=1e-15)
        assert bmap.attitude_error(q, -q2) == pytest.approx(ang, rel=1e-6, abs=1e-15)
    np.testing.assert_allclose(bmap.attitude_error(np.array(QS[:5]), np.array(QS[:5])), 0.0, atol=1e-15)


def test_wheel_speed_and_momentum_round_trip():
    A = bmap.pyramid_axes(0.5235987755982988)
    np.testing.assert_allclose(np.linalg.norm(A, axis=0), 1.0, atol=1e-15)
    w = np.radians([3.0, -2.0, 4.0])
    Om = np.array([1000.0, -500.0, 300.0, 2000.0]) * bmap.RPM
    h = bmap.wheel_momenta(Om, 0.001364, A, w)
    np.testing.assert_allclose(bmap.wheel_speeds(h, 0.001364, A, w), Om, rtol=1e-15, atol=1e-12)
    # total momentum: rpo's I_c w + A h is Basilisk's hub (I_c + J A A^T) w + J A Omega
    I_c = bmap.inertia_tensor([11.0, 14.0, 13.0, -0.09, -0.4, -0.08])
    inert = bmap.basilisk_inertias(I_c, 0.001364, A)
    np.testing.assert_allclose(bmap.angular_momentum(I_c, A, h, w), inert["hub"] @ w + inert["Js"] * A @ Om,
                               rtol=1e-14)
    assert inert["Jt"] == inert["Jg"] == 0.0
    np.testing.assert_array_equal(bmap.basilisk_inertias(I_c, 0.0, A)["hub"], I_c)
    np.testing.assert_array_equal(I_c, I_c.T)
    assert I_c[0, 2] == -0.4 and I_c[1, 2] == -0.08  # [xx, yy, zz, xy, xz, yz]


def test_wheel_momenta_match_rpo_s_generated_wheel_speeds(model):
    """rpo's own route (the scenario reader's _wheel_momentum, through the generated env_outputs)."""
    from rpo.runtime.run.simulate import Simulation

    sim = Simulation(model, params=quiet_params(), gains=ZERO_GAINS)
    w = np.radians([3.0, -2.0, 4.0])
    q = QS[0]
    Om = np.array([1000.0, -500.0, 300.0, 2000.0]) * bmap.RPM
    plant = {"q_c": q, "w_c": w, "q_t": QS[1], "w_t": np.zeros(3), "r": np.array([60.0, 0, 25]), "v": np.zeros(3),
             **target_state(model, sim.p)}
    h_rpo = _wheel_momentum(model, sim.p, plant, Om)
    p = model.vector("p", quiet_params())
    J = float(p[model.offsets("p")["wheel_inertia"]][0])
    beta = float(p[model.offsets("p")["wheel_beta"]][0])
    np.testing.assert_allclose(bmap.wheel_momenta(Om, J, bmap.pyramid_axes(beta), w), h_rpo, rtol=1e-13, atol=1e-16)


def _two_body(r, v, mu=3.986004418e14):
    return -mu * r / np.linalg.norm(r) ** 3


def test_lvlh_frame_and_rate_by_finite_differences():
    """C_IL's axes, and omega_L (with a perturbing normal acceleration) from d C_IL / dt."""
    r = np.array([6.8e6, 1.0e5, -2.0e5])
    v = np.array([-100.0, 5.9e3, 4.8e3])
    a_p = np.array([2e-3, -5e-3, 7e-3])  # a made-up perturbation (J2-sized)
    C = bmap.lvlh_dcm(r, v)
    np.testing.assert_allclose(C.T @ C, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(np.cross(C[:, 2], C[:, 0]), C[:, 1], atol=1e-15)
    assert C[:, 0] @ r > 0 and C[:, 2] @ np.cross(r, v) > 0
    dt = 1e-3

    def state(t):  # Taylor to second order is enough for a central difference of C
        a = _two_body(r, v) + a_p
        return r + v * t + 0.5 * a * t * t, v + a * t

    Cp, Cm = bmap.lvlh_dcm(*state(dt)), bmap.lvlh_dcm(*state(-dt))
    W = C.T @ (Cp - Cm) / (2 * dt)  # skew(omega_L) in L axes
    w_fd = np.array([W[2, 1], W[0, 2], W[1, 0]])
    np.testing.assert_allclose(bmap.lvlh_rate(r, v, a_p), w_fd, rtol=1e-5, atol=1e-12)
    assert abs(bmap.lvlh_rate(r, v, a_p)[0]) > 1e-7  # the perturbation's rate about X is really there
    assert bmap.lvlh_rate(r, v)[0] == 0.0


def test_relative_state_round_trip_and_transport_theorem():
    r_t = np.array([6.8e6, 1.0e5, -2.0e5])
    v_t = np.array([-100.0, 5.9e3, 4.8e3])
    a_p = np.array([2e-3, -5e-3, 7e-3])
    r_e, v_e = np.array([60.0, 0.0, 25.0]), np.array([3.0, -0.5, 5.0])
    r_c, v_c = bmap.relative_to_inertial(r_t, v_t, r_e, v_e, a_p)
    r2, v2 = bmap.inertial_to_relative(r_t, v_t, r_c, v_c, a_p)
    np.testing.assert_allclose(r2, r_e, atol=1e-8)
    np.testing.assert_allclose(v2, v_e, atol=1e-11)
    # v_e is the L-frame derivative of r_e: a central difference of C_IL^T (r_c - r_t) gives it
    dt = 1e-3
    a_t = _two_body(r_t, v_t) + a_p
    a_c = _two_body(r_c, v_c) + a_p

    def rel(t):
        rt, vt = r_t + v_t * t + 0.5 * a_t * t * t, v_t + a_t * t
        rc = r_c + v_c * t + 0.5 * a_c * t * t
        return bmap.lvlh_dcm(rt, vt).T @ (rc - rt)

    np.testing.assert_allclose((rel(dt) - rel(-dt)) / (2 * dt), v_e, atol=1e-6)
