"""Check 2: torque-free conservation laws and the relative attitude model (000 eqs. 24-29)."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from rpo.runtime.run.simulate import Simulation

from conftest import DEG, Q_C0_III, Q_T0_III, ZERO_GAINS, quiet_params, unit

BETA = 30 * DEG
A_PYRAMID = np.array([  # 000 eq. 47, typed from the paper as an independent reference
    [np.cos(BETA), 0, -np.cos(BETA), 0],
    [0, np.cos(BETA), 0, -np.cos(BETA)],
    [np.sin(BETA), np.sin(BETA), np.sin(BETA), np.sin(BETA)],
])
I_C = np.array([[11, -0.09, -0.4], [-0.09, 14, -0.08], [-0.4, -0.08, 13]])
I_W = 0.001364


def test_torque_free_chaser_with_spinning_wheels_conserves_momentum_and_energy(model):
    sim = Simulation(model, params=quiet_params(), gains=ZERO_GAINS)
    h0 = np.array([0.3, -0.2, 0.25, 0.1])  # N m s: wheels spinning at ~200-2100 rpm
    z0 = sim.initial_state({"q_c": unit(Q_C0_III), "w_c": np.array([3, 1, 5]) * DEG, "h_w": h0,
                            "q_t": unit(Q_T0_III), "r": [60, 0, 25], "v": [0, 0, 0]})
    res = sim.run(z0, 300.0)
    assert res.ok and res.steps_done == 30000
    q = np.column_stack([res.column(f"q_c_{c}") for c in "xyzw"])
    w = np.column_stack([res.column(f"w_c_{c}") for c in "xyz"])
    h = np.column_stack([res.column(f"h_w_{c}") for c in "1234"])
    H_body = w @ I_C.T + h @ A_PYRAMID.T
    H_eci = Rotation.from_quat(q).apply(H_body)  # scipy: body -> ECI for q = attitude rel. ECI
    T_body = 0.5 * np.einsum("ij,jk,ik->i", w, I_C, w)
    T = T_body + 0.5 * np.sum(h**2, axis=1) / I_W
    dH = np.linalg.norm(H_eci - H_eci[0], axis=1).max() / np.linalg.norm(H_eci[0])
    # The wheels' energy (~73 J) is constant without motor torque and would hide any drift of the
    # body's ~0.07 J below one ulp, so the drift is measured against the body's rotational energy.
    dT = np.abs(T - T[0]).max() / T_body[0]
    assert np.abs(h - h0).max() == 0  # no motor torque: absolute wheel momenta are constant
    assert np.linalg.norm(w[-1] - w[0]) > 1e-3  # the body really tumbles (the check is not vacuous)
    assert dH < 1e-10, f"relative angular momentum drift {dH:.2e}"
    assert dT < 1e-10, f"relative energy drift {dT:.2e}"


def test_relative_attitude_model_matches_two_separate_bodies(model):
    """Integrate eqs. 24-29 alongside the two bodies (with gravity-gradient and magnetic torques and
    spinning wheels) and compare q_e, w_e with eqs. 17-22 evaluated on the separate attitudes."""
    params = quiet_params(gg_on=1, mag_on=1, mass_profile_on=0)
    sim = Simulation(model, params=params, gains=ZERO_GAINS)
    p = sim.p
    z0 = sim.initial_state({"q_c": unit(Q_C0_III), "w_c": np.array([3, 1, 5]) * DEG,
                            "h_w": [0.3, -0.2, 0.25, 0.1], "q_t": unit(Q_T0_III),
                            "w_t": [0.10876, 0.009113, 0.05468], "r": [60, 0, 25], "v": [3, -0.5, 5]})
    nx = model.layout_size("x")
    x = z0[:nx].copy()
    u = np.zeros(model.layout_size("u"))
    w_noise = np.zeros(model.layout_size("w"))
    meas_off = model.offsets("meas")
    m0 = model.measure(x, np.zeros(model.layout_size("hold")), 0.0, p, np.zeros(model.layout_size("w")))[0]
    rel = np.concatenate([m0[meas_off["q_e"]], m0[meas_off["w_e"]]])

    def f(X, t):
        xx, rr = X[:nx], X[nx:]
        return np.concatenate([model.plant_rhs(xx, u, t, p, w_noise)[0],
                               model.relative_attitude_rhs(xx, u, t, p, w_noise, rr)[0]])

    X, t, dt = np.concatenate([x, rel]), 0.0, 0.01
    worst_q = worst_w = 0.0
    for k in range(30000):  # 300 s, RK4 at 100 Hz on the augmented system
        k1 = f(X, t)
        k2 = f(X + dt / 2 * k1, t + dt / 2)
        k3 = f(X + dt / 2 * k2, t + dt / 2)
        k4 = f(X + dt * k3, t + dt)
        X = X + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        t = (k + 1) * dt
        if (k + 1) % 500 == 0:
            m = model.measure(X[:nx], np.zeros(model.layout_size("hold")), t, p, np.zeros(model.layout_size("w")))[0]
            q_sep, w_sep = m[meas_off["q_e"]], m[meas_off["w_e"]]
            q_rel = X[nx:nx + 4] / np.linalg.norm(X[nx:nx + 4])
            q_sep = q_sep / np.linalg.norm(q_sep)
            worst_q = max(worst_q, np.abs(q_rel - q_sep).max())
            worst_w = max(worst_w, np.abs(X[nx + 4:] - w_sep).max())
    assert np.abs(rel[4:]).max() > 0.05  # a large, changing rate error: the check is not vacuous
    assert worst_q < 1e-9, f"q_e mismatch {worst_q:.2e}"
    assert worst_w < 1e-9, f"w_e mismatch {worst_w:.2e} rad/s"
