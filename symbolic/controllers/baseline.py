"""Baseline PD pose controller: closes the loop for the toolchain, not a paper design.

Attitude: tau = -sat(k_p sgn(q_e4) q_ev) - k_d omega_e on the error to the interface frame (000
eqs. 17, 22); the sign picks the shorter rotation, and the proportional term is clipped per axis at
``tau_p_max`` (a slew-rate limit: a large error then commands at most a relative rate of about
tau_p_max / k_d).  Translation: F_L = -k_pr (r - r_goal) - k_dr v in LVLH, rotated into the chaser
body for the thrusters.  Momentum management (rpo's, for the reference design,
docs/reference_design.md): the thrusters apply tau_thr = -sat(k_dump h_rw) (the measured wheel
momentum, clipped per axis at ``tau_dump_max``) and the wheels tau - tau_thr, so the body still
gets tau while the wheels unload at the rate k_dump.  With the defaults (k_dump = 0, the clips at
1e3 N m) the law is the plain PD, bit for bit.  No controller states.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..physics.layout import XYZ, Bounds, Layout
from ..physics.rotations import quat_to_dcm, quat_vec
from . import command_layout


@dataclass
class Baseline:
    name: str = "baseline"
    k: Layout = field(default_factory=lambda: Layout("k"))
    xc: Layout = field(default_factory=lambda: Layout("xc"))
    diag: Layout = field(default_factory=lambda: Layout("diag"))

    def __post_init__(self):
        k = self.k
        k.add("kp_att", 1, "N m", "attitude proportional gain",
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"), default=0.28)
        k.add("kd_att", 1, "N m s", "attitude rate gain", default=2.0,
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("kp_pos", 1, "N/m", "position proportional gain", default=0.25,
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("kd_pos", 1, "N s/m", "velocity gain", default=7.0,
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("tau_p_max", 1, "N m", "per-axis clip of the attitude proportional torque (slew-rate limit "
              "tau_p_max / kd_att)", default=1e3,
              bounds=Bounds(0.0, 1e4, why="a torque magnitude: >= 0 (0 leaves only the rate damping)"))
        k.add("k_dump", 1, "1/s", "momentum management: thruster torque -k_dump h_rw unloads the wheels",
              default=0.0, bounds=Bounds(0.0, 10.0, why="a feedback rate: >= 0 (a negative one loads the wheels)"))
        k.add("tau_dump_max", 1, "N m", "per-axis clip of the momentum-management thruster torque", default=1e3,
              bounds=Bounds(0.0, 1e4, why="a torque magnitude: >= 0"))
        k.add("r_goal", 3, "m", "goal relative position, LVLH", XYZ, default=(0, 0, 0),
              bounds=Bounds(-1e5, 1e5, why="a position, either sign, within 100 km"))
        self.diag.add("att_err", 1, "rad", "rotation angle to the interface frame")

    def law(self, meas, t, p):
        """(cmd, xc_dot, diag) as SymPy expressions of the measurement ``meas`` (a Layout)."""
        k = self.k
        q_e, w_e = meas["q_e"], meas["w_e"]
        sgn = sp.Piecewise((-1, q_e[3] < 0), (1, True))
        tau_p = _clip(k["kp_att"] * sgn * quat_vec(q_e), k["tau_p_max"])
        tau = -tau_p - k["kd_att"] * w_e
        F_L = -k["kp_pos"] * (meas["r"] - k["r_goal"]) - k["kd_pos"] * meas["v"]
        F_body = quat_to_dcm(meas["q_cL"]).T * F_L
        # momentum management: an external (thruster) torque against the wheels' momentum, and the
        # wheels given the opposite, so the body torque stays tau and dh_rw/dt gains -k_dump h_rw
        tau_thr = -_clip(k["k_dump"] * meas["h_rw"], k["tau_dump_max"])
        cmd = command_layout().pack({"tau_w": tau - tau_thr, "F": F_body, "tau_thr": tau_thr})
        att_err = 2 * sp.acos(sp.Min(1, sp.Abs(q_e[3])))
        return cmd, sp.zeros(0, 1), sp.Matrix([att_err])


def _clip(v, limit):
    """v clipped per component to [-limit, limit]: each component exactly itself when inside."""
    return sp.Matrix([sp.Max(-limit, sp.Min(limit, vi, evaluate=False), evaluate=False) for vi in v])


DESIGN = Baseline
