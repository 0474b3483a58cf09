"""One closed-loop step: measurement, controller, actuators, and fixed-step RK4 of the plant.

The *pieces* (plant right-hand side, measurement, control law, allocations, PWPF) are SymPy
expressions defined once in :func:`plant_pieces` and :func:`controller_pieces`.  :func:`step`
composes them over an array backend (``ops``): with CasADi for the generated C, with NumPy
for the reference baseline of ``benchmarks/`` and the tests.  The composition is written once
here, so both run the same algorithm.

Timing within a step of length dt starting at t_k (zero-order hold):

1. the controller reads the measurement of x(t_k) and outputs a command held over the step;
2. the wheel command enters a transport-delay line: the wheels apply the command from
   ``n + 1`` steps ago during [t_k, t_k + delta) and from ``n`` steps ago during
   [t_k + delta, t_k + dt), with delay = n dt + delta, 0 <= delta < dt (exact, two RK4 sub-steps);
3. each thruster's Schmitt trigger switches on the PWPF prefilter state at t_k, the on/off level
   is held over the step, and the prefilter is advanced exactly over dt;
4. quaternions are renormalised after the step; controller states are advanced by RK4 with the
   measurement held;
5. fault windows (:mod:`.faults`) are evaluated at t_k and held over the step: the wheels and
   thrusters deliver what their faults let them (``wheel_faults``, ``thruster_faults``), the
   allocations are fault-aware when ``fdir_allocation`` = 1, and a frozen sensor repeats the value
   it gave at the previous step (the step state's sensor hold).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..controllers import command_layout
from . import actuators as act
from . import faults as flt
from .layout import Layout
from .plant import THRUSTERS, WHEELS, Plant

#: Wheel-command history length: delays up to NB * dt - epsilon are represented exactly.
DELAY_SLOTS = 4


def actuator_layout() -> Layout:
    a = Layout("xa")
    for j in range(DELAY_SLOTS):
        a.add(f"wheel_cmd_{j + 1}", 4, "N m", f"wheel torque command issued {j + 1} step(s) ago", WHEELS)
    a.add("pwpf_f", 16, "-", "PWPF prefilter states", THRUSTERS)
    a.add("pwpf_on", 16, "-", "thruster on-levels of the previous step", THRUSTERS)
    return a


@dataclass
class Piece:
    """A named SymPy function: inputs (name, symbols) and outputs (name, expression)."""

    name: str
    inputs: list[tuple[str, sp.Basic]]
    outputs: list[tuple[str, sp.Basic]]


#: The controller-independent pieces a step is composed of (the keys of :func:`plant_pieces`).
PLANT_PIECES = ("plant_rhs", "measure", "env_outputs", "ideal_actuators", "wheel_alloc", "thruster_alloc", "pwpf",
                "pwpf_filter", "wheel_faults", "thruster_faults")


def plant_pieces(plant: Plant) -> dict[str, Piece]:
    """The SymPy pieces of a closed-loop step that do not depend on the controller (each defined
    once, here or in the modules it calls): plant, measurement, environment, actuators."""
    P = plant
    x, u, t, p, w = P.x.vector(), P.u.vector(), P.t, P.p.vector(), P.w.vector()
    pr = P.p
    tau_w = sp.Matrix(sp.symbols("tau_x tau_y tau_z", real=True))
    F_c = sp.Matrix(sp.symbols("F_x F_y F_z", real=True))
    tau_t = sp.Matrix(sp.symbols("taut_x taut_y taut_z", real=True))
    f = sp.Matrix(sp.symbols("f_0:16", real=True))
    on = sp.Matrix(sp.symbols("on_0:16", real=True))
    duty = sp.Matrix(sp.symbols("d_0:16", real=True))
    tau4 = sp.Matrix(sp.symbols("Tw_1:5", real=True))
    hold = P.hold.vector()
    meas = P.measurement()
    wf, tf = flt.wheel_flags(t, pr), flt.thruster_flags(t, pr)
    fdir = pr["fdir_allocation"]
    wheel_ok = [(1 - wf["off"][i]) * (1 - wf["stuck"][i]) for i in range(4)]
    thr_ok = [(1 - tf["off"][j]) * (1 - tf["stuck_on"][j]) for j in range(16)]
    T_nominal = act.allocate_wheel_torques(pr["wheel_beta"], tau_w, pr["wheel_torque_max"])
    T_aware = act.allocate_wheel_torques_healthy(pr["wheel_beta"], tau_w, pr["wheel_torque_max"], wheel_ok,
                                                 wf["limit"])
    d_nominal = act.allocate_thrusters(F_c, tau_t, pr["thruster_force"])
    d_aware = act.allocate_thrusters_healthy(F_c, tau_t, pr["thruster_force"], thr_ok, tf["thrust"],
                                             tf["stuck_on"])
    return {
        "plant_rhs": Piece("plant_rhs", [("x", x), ("u", u), ("t", t), ("p", p), ("w", w)],
                           [("xdot", P.rhs())]),
        "measure": Piece("measure", [("x", x), ("hold", hold), ("t", t), ("p", p), ("w", w)],
                         [("meas", meas), ("hold_next", P.sensor_hold_next(meas))]),
        "env_outputs": Piece("env_outputs", [("x", x), ("u", u), ("t", t), ("p", p), ("w", w)],
                             [("env", P.env_outputs())]),
        "ideal_actuators": Piece("ideal_actuators", [("F", F_c), ("tau", tau_w), ("p", p)], list(zip(
            ("F_applied", "tau_applied"), act.ideal_wrench(F_c, tau_w, pr["force_max"], pr["torque_max"]),
            strict=True))),
        # the fault-aware allocation (fdir_allocation = 1) or the nominal one, exactly, when 0
        "wheel_alloc": Piece("wheel_alloc", [("tau", tau_w), ("t", t), ("p", p)],
                             [("T_w", fdir * T_aware + (1 - fdir) * T_nominal)]),
        "thruster_alloc": Piece("thruster_alloc", [("F", F_c), ("tau", tau_t), ("t", t), ("p", p)],
                                [("duty", fdir * d_aware + (1 - fdir) * d_nominal)]),
        "wheel_faults": Piece("wheel_faults", [("T_w", tau4), ("t", t), ("p", p)], [
            ("T_applied", flt.faulty_wheel_torques(tau4, t, pr, pr["wheel_torque_max"])),
            ("locked", wf["stuck"])]),
        "thruster_faults": Piece("thruster_faults", [("on", on), ("t", t), ("p", p)],
                                 [("level", flt.faulty_thruster_levels(on, t, pr))]),
        "pwpf": Piece("pwpf", [("f", f), ("on_prev", on), ("duty", duty), ("p", p)], [
            ("on", sp.Matrix([act.schmitt_trigger(f[i], on[i], pr["pwpf_uon"], pr["pwpf_uoff"])
                              for i in range(16)])),
        ]),
        "pwpf_filter": Piece("pwpf_filter", [("f", f), ("duty", duty), ("on", on), ("p", p)], [
            ("f_next", sp.Matrix([act.pwpf_filter_step(f[i], duty[i], on[i], pr["pwpf_km"],
                                                       pr["pwpf_tm"], pr["dt"]) for i in range(16)])),
        ]),
    }


def controller_pieces(plant: Plant, ctrl) -> dict[str, Piece]:
    """The SymPy pieces of one controller: its law ``law_<name>`` and, if it has one, the initial
    state ``xc0_<name>`` from the first measurement (e.g. an observer started there)."""
    P = plant
    t, p = P.t, P.p.vector()
    meas = P.meas.vector()
    cmd, xc_dot, diag = ctrl.law(P.meas, t, P.p)
    k = ctrl.k.vector()
    out = {f"law_{ctrl.name}": Piece(
        f"law_{ctrl.name}",
        [("meas", meas), ("xc", ctrl.xc.vector()), ("t", t), ("p", p), ("k", k)],
        [("cmd", cmd), ("xc_dot", xc_dot), ("diag", diag)])}
    if hasattr(ctrl, "xc0"):
        out[f"xc0_{ctrl.name}"] = Piece(f"xc0_{ctrl.name}", [("meas", meas), ("p", p), ("k", k)],
                                        [("xc0", ctrl.xc0(P.meas, P.p))])
    return out


def output_layout(plant: Plant, ctrl) -> Layout:
    """Per-step logged outputs y of the closed-loop step (values at t_k)."""
    y = Layout("y")
    for lay, prefix in ((plant.meas, "meas"), (command_layout(), "cmd")):
        for fl in lay.fields:
            y.add(f"{prefix}_{fl.name}", fl.size, fl.unit, fl.doc, fl.components)
    y.add("wheel_cmd", 4, "N m", "allocated, saturated wheel torque command", WHEELS)
    y.add("wheel_applied", 4, "N m", "motor torque the wheels deliver after t_k + delta (delayed command, faults)",
          WHEELS)
    y.add("thr_duty", 16, "-", "thruster duty demand (PWPF input)", THRUSTERS)
    y.add("thr_on", 16, "-", "thrust level over the step (PWPF on-level after faults; fraction of the thrust)",
          THRUSTERS)
    for fl in plant.env.fields:
        y.add(f"env_{fl.name}", fl.size, fl.unit, fl.doc, fl.components)
    for fl in ctrl.diag.fields:
        y.add(f"ctrl_{fl.name}", fl.size, fl.unit, fl.doc, fl.components)
    return y


def state_layout(plant: Plant, ctrl=None) -> Layout:
    """The packed step state z = [plant x, actuator states, sensor hold, controller states]
    (``ctrl`` None: the plant's part zp, which :func:`plant_advance` advances)."""
    z = Layout("z")
    blocks = [(plant.x, ""), (actuator_layout(), "")]
    if ctrl is not None:
        blocks += [(plant.hold, ""), (ctrl.xc, "xc_")]
    for lay, prefix in blocks:
        for fl in lay.fields:
            z.add(prefix + fl.name, fl.size, fl.unit, fl.doc, fl.components)
    return z


def rk4(f, x, t, h, t_end=None):
    """One classical Runge-Kutta step of dx/dt = f(x, t) over h.

    Each stage time is formed once (and ``t_end`` may be passed in) so that stages at equal
    times share their time-only terms after common-subexpression elimination.
    """
    t_half = t + h / 2
    t_end = t + h if t_end is None else t_end
    k1 = f(x, t)
    k2 = f(x + h / 2 * k1, t_half)
    k3 = f(x + h / 2 * k2, t_half)
    k4 = f(x + h * k3, t_end)
    return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def controller_update(ops, law, meas, xc, t, p, k, dt, nc):
    """The controller's half of a step: ``(cmd, xc_next, diag)`` from the measurement at t_k.

    ``law(meas, xc, t, p, k) -> (cmd, xc_dot, diag)``; the command is held over the step and the
    controller state advanced by RK4 with the measurement held (timing item 4).
    """
    cmd, _, diag = law(meas, xc, t, p, k)
    if nc:
        xc_next = rk4(lambda xx, tt: law(meas, xx, tt, p, k)[1], xc, t, dt, t + dt)
    else:
        xc_next = xc
    return cmd, xc_next, diag


def plant_advance(ops, fn, idx, zp, t, p, w, cmd):
    """The plant's half of a step: actuators and RK4 of the plant over dt under the held command.

    ``zp`` = [plant x, actuator states] (the step state without the controller's); returns
    ``(zp_next, y_plant)`` with y_plant = [wheel_cmd, wheel_applied, thr_duty, thr_on, env] at t_k.
    ``fn``: callables for the plant pieces of :func:`plant_pieces`; ``idx``: :func:`step_indices`.
    """
    nx = idx["nx"]
    x = zp[0:nx]
    o = nx
    hist = []
    for _ in range(DELAY_SLOTS):
        hist.append(zp[o:o + 4])
        o += 4
    f = zp[o:o + 16]
    on_prev = zp[o + 16:o + 32]
    dt = p[idx["dt"]]
    delay = p[idx["wheel_delay"]]

    # actuator model switch (0/1): wheels and PWPF thrusters, or the papers' ideal actuators
    ideal = p[idx["actuators_ideal"]]
    real = 1 - ideal
    T_new = real * fn["wheel_alloc"](cmd[0:3], t, p)[0]
    F_ideal, tau_ideal = fn["ideal_actuators"](cmd[3:6], cmd[0:3] + cmd[6:9], p)
    F_ideal, tau_ideal = ideal * F_ideal, ideal * tau_ideal

    # transport delay: delay = n dt + delta, 0 <= delta < dt
    n = ops.floor(delay / dt)
    delta = ops.fmax(delay - n * dt, 0)
    cands = [T_new] + hist  # cands[j] = command issued j steps ago

    def pick(j_sym):
        out = ops.zeros(4)
        for j, c in enumerate(cands):
            out = out + ops.if_else(j_sym == j, c, ops.zeros(4))
        return out

    # what the wheels deliver (faults.py: failed, weak, locked), from the delayed commands
    T_late, locked = fn["wheel_faults"](pick(n), t, p)   # applied during [t + delta, t + dt)
    T_early = fn["wheel_faults"](pick(n + 1), t, p)[0]   # applied during [t, t + delta)

    duty = real * fn["thruster_alloc"](cmd[3:6], cmd[6:9], t, p)[0]
    on = fn["pwpf"](f, on_prev, duty, p)[0]
    f_next = fn["pwpf_filter"](f, duty, on, p)[0]  # the modulator's feedback is its own output
    level = fn["thruster_faults"](on, t, p)[0]     # what the thrusters deliver

    def plant_with(Tw):
        u = ops.vcat(Tw, level, F_ideal, tau_ideal, locked)
        return lambda xx, tt: fn["plant_rhs"](xx, u, tt, p, w)[0]

    t_delta, t_next = t + delta, t + dt
    x1 = rk4(plant_with(T_early), x, t, delta, t_delta)
    x2 = rk4(plant_with(T_late), x1, t_delta, dt - delta, t_next)
    # renormalise the quaternions (RK4 does not preserve the unit norm exactly)
    parts = []
    last = 0
    for a in idx["quats"]:
        parts.append(x2[last:a])
        q = x2[a:a + 4]
        parts.append(q / ops.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]))
        last = a + 4
    parts.append(x2[last:nx])
    x_next = ops.vcat(*parts)

    zp_next = ops.vcat(x_next, T_new, *hist[:-1], f_next, on)
    env = fn["env_outputs"](x, ops.vcat(T_late, level, F_ideal, tau_ideal, locked), t, p, w)[0]
    return zp_next, ops.vcat(T_new, T_late, duty, level, env)


def step(ops, fn, idx, z, t, p, k, w):
    """Advance the packed state z by one step dt; return (z_next, y).

    The composition of the measurement, :func:`controller_update` and :func:`plant_advance`
    (the generated C composes the same three generated functions the same way).
    ``ops``: array backend (``vcat``, ``floor``, ``if_else``, ``sqrt``, ``fmax``, ``zeros``);
    ``fn``: callables for the pieces of :data:`PLANT_PIECES` plus ``law`` (the controller's),
    each returning a tuple of outputs; ``idx``: offsets from :func:`step_indices`.
    """
    nzp, nh, nc = idx["nzp"], idx["nh"], idx["nc"]
    zp, hold, xc = z[0:nzp], z[nzp:nzp + nh], z[nzp + nh:nzp + nh + nc]
    meas, hold_next = fn["measure"](zp[0:idx["nx"]], hold, t, p, w)
    cmd, xc_next, diag = controller_update(ops, fn["law"], meas, xc, t, p, k, p[idx["dt"]], nc)
    zp_next, y_plant = plant_advance(ops, fn, idx, zp, t, p, w, cmd)
    return ops.vcat(zp_next, hold_next, xc_next), ops.vcat(meas, cmd, y_plant, diag)


def step_indices(plant: Plant, ctrl=None) -> dict:
    """Integer offsets :func:`step` and :func:`plant_advance` need, from the layouts."""
    xo = plant.x.offsets()
    po = plant.p.offsets()
    return {
        "nx": plant.x.size,
        "nzp": plant.x.size + actuator_layout().size,
        "nh": plant.hold.size,
        "nc": ctrl.xc.size if ctrl is not None else 0,
        "dt": po["dt"][0],
        "wheel_delay": po["wheel_delay"][0],
        "actuators_ideal": po["actuators_ideal"][0],
        "quats": [xo["q_c"][0], xo["q_t"][0]],
    }
