"""The functions rpo generates, grouped into families for incremental code generation.

* family ``plant``: everything that does not depend on a controller: ``plant_rhs`` and its
  Jacobians ``plant_jac``, ``measure``, ``env_outputs``, the actuator pieces, ``target_orbit``,
  ``kepler``, ``relative_attitude_rhs``, plus the layouts p, x, u, w, meas, env;
* family ``controller_<name>``, one per module ``symbolic/controllers/<name>.py`` (discovered):
  ``law_<name>``, ``step_<name>`` (plant + law + actuators, RK4 over dt) and, if the design has
  one, ``xc0_<name>``, plus the layouts ``k_<name>``, ``xc_<name>``, ``diag_<name>``,
  ``z_<name>``, ``y_<name>`` and the manifest entry ``controllers.<name>``.

A controller family depends on the plant family: its step is composed from the plant's CasADi
functions, which :mod:`rpo.symbolic.codegen.codegen` deserialises from ``generated/`` when the plant is
unchanged, so editing a controller never re-derives the plant.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from types import SimpleNamespace

from .codegen import Family, FamilyOutput, Generated, ModelDefinitionError
from .specialisation import VARIANTS, specialised, zero_fields, zero_indices

# Heavy imports (SymPy, CasADi, the model) happen inside the builders: listing the families and
# hashing their sources must not import them, so that a build with nothing to do takes well under 1 s.

CODEGEN_DIR = Path(__file__).resolve().parent
SYMBOLIC_DIR = CODEGEN_DIR.parent
PHYSICS_DIR = SYMBOLIC_DIR / "physics"
CONTROLLERS_DIR = SYMBOLIC_DIR / "controllers"
#: ``rpo.symbolic``, the package of ``symbolic/`` (this module is in its ``codegen`` subpackage)
SYMBOLIC_PACKAGE = __package__.rpartition(".")[0]

#: Manifest layout names of each plant function's inputs and outputs, and its description.
_SIGNATURES = {
    "plant_rhs": (["x", "u", None, "p", "w"], ["x"], "plant right-hand side dx/dt (000 eqs. 6, 10, 24, 30, 45-47)"),
    "plant_jac": (["x", "u", None, "p", "w"], [None, None], "Jacobians of plant_rhs w.r.t. x and u (CasADi AD)"),
    "measure": (["x", "hold", None, "p", "w"], ["meas", "hold"],
                "truth + sensor noise, bias and faults -> what the controllers read; the sensor hold after it"),
    "env_outputs": (["x", "u", None, "p", "w"], ["env"], "environment/actuator diagnostics"),
    "ideal_actuators": ([None, None, "p"], [None, None], "ideal actuators: per-axis saturated force and torque"),
    "wheel_alloc": ([None, None, "p"], [None], "pyramid wheel allocation with saturation (inverse of 000 eq. 46), "
                    "nominal or over the healthy wheels"),
    "thruster_alloc": ([None, None, None, "p"], [None], "thruster duty allocation, nominal or over the healthy "
                       "thrusters"),
    "wheel_faults": ([None, None, "p"], [None, None], "motor torques the wheels deliver, which are locked (faults)"),
    "thruster_faults": ([None, None, "p"], [None], "thrust levels the thrusters deliver (faults)"),
    "pwpf": ([None, None, None, "p"], [None], "PWPF Schmitt trigger"),
    "pwpf_filter": ([None, None, None, "p"], [None], "PWPF prefilter update over dt"),
    "target_orbit": ([None, "p"], [None] * 8, "target orbit at t (000 eqs. 31-36, corrected LVLH rate)"),
    "kepler": ([None, None], [None], "eccentric anomaly from Kepler's equation (000 eq. 32)"),
    "relative_attitude_rhs": (["x", "u", None, "p", "w", None], [None],
                              "relative attitude model (000 eqs. 24-29) driven by the plant state, for checks"),
}

QUATERNION_CONVENTION = "scalar-last [x, y, z, w], Hamilton product, q_B_A: v_A = q v_B q*"


# --------------------------------------------------------------------------- discovery


def controller_names(directory: Path = CONTROLLERS_DIR) -> list[str]:
    """Every controller module of ``symbolic/controllers/`` (``<name>.py``, not ``_private.py``), sorted.

    Found from the file names alone, without importing anything, so a no-op build stays fast.
    """
    return sorted(p.stem for p in directory.glob("*.py") if not p.stem.startswith("_"))


def load_controller(name: str):
    """An instance of the design ``DESIGN`` of ``symbolic/controllers/<name>.py``, named after the module
    (so a copy of a module under a new name is a new controller)."""
    mod = importlib.import_module(f"{SYMBOLIC_PACKAGE}.controllers.{name}")
    design = getattr(mod, "DESIGN", None)
    if design is None:
        raise ModelDefinitionError(f"symbolic/controllers/{name}.py defines no DESIGN "
                                   "(the controller class to generate)")
    ctrl = design()
    ctrl.name = name
    return ctrl


def controllers() -> list:
    """Instances of every discovered controller design, sorted by module name."""
    return [load_controller(n) for n in controller_names()]


# --------------------------------------------------------------------------- SymPy sources


def plant_sources(P) -> dict:
    """The SymPy source of every plant-family function except the Jacobian (taken by CasADi AD)."""
    import sympy as sp

    from ..physics import closed_loop as cl
    from ..physics.orbit import eccentric_anomaly
    from ..physics.relative_attitude import attitude_error_rate, rate_error_dynamics

    pieces = cl.plant_pieces(P)
    o = P.orbit()
    pieces["target_orbit"] = cl.Piece("target_orbit", [("t", P.t), ("p", P.p.vector())], [
        ("nu", o["nu"]), ("r", o["r"]), ("r_dot", o["r_dot"]), ("n", o["n"]), ("n_dot", o["n_dot"]),
        ("r_eci", o["r_eci"]), ("v_eci", o["v_eci"]), ("q_IL", P.lvlh_attitude(o)),
    ])
    M, e = sp.symbols("M e", real=True)
    pieces["kepler"] = cl.Piece("kepler", [("M", M), ("e", e)], [("E", eccentric_anomaly(M, e))])
    tq = P.torques()
    rel = sp.Matrix(sp.symbols("qe_x qe_y qe_z qe_w we_x we_y we_z", real=True))
    q_e, w_e = sp.Matrix(rel[0:4]), sp.Matrix(rel[4:7])
    rel_dot = sp.Matrix.vstack(
        attitude_error_rate(q_e, w_e),
        rate_error_dynamics(q_e, w_e, P.x["w_c"], tq["h_rw"], tq["I_c"], tq["I_t"], tq["T_c"], tq["M_c"],
                            tq["M_t"]),
    )
    pieces["relative_attitude_rhs"] = cl.Piece(
        "relative_attitude_rhs",
        [("x", P.x.vector()), ("u", P.u.vector()), ("t", P.t), ("p", P.p.vector()), ("w", P.w.vector()),
         ("rel", rel)], [("rel_dot", rel_dot)])
    return pieces


def sources(P=None, ctrls=None) -> tuple[dict, dict]:
    """The SymPy source of every generated function except the Jacobian and the composed steps.

    Tests evaluate these same expressions with NumPy (``sympy.lambdify``) and compare them with
    the compiled functions; the families below translate them to CasADi.
    """
    from ..physics import closed_loop as cl
    from ..physics.plant import make_plant

    P = make_plant() if P is None else P
    ctrls = controllers() if ctrls is None else ctrls
    pieces = plant_sources(P)
    for ctrl in ctrls:
        pieces.update(cl.controller_pieces(P, ctrl))
    return pieces, {"plant": P, "controllers": ctrls}


# --------------------------------------------------------------------------- families


def _build_plant(_resolve) -> FamilyOutput:
    import casadi as ca

    from ..physics import closed_loop as cl
    from ..physics import faults as flt
    from ..physics.plant import make_plant
    from .to_casadi import sympy_function

    P = make_plant()
    cas = {name: sympy_function(pc.name, pc.inputs, pc.outputs) for name, pc in plant_sources(P).items()}
    xs, us = ca.SX.sym("x", P.x.size), ca.SX.sym("u", P.u.size)
    ts, ps, ws = ca.SX.sym("t"), ca.SX.sym("p", P.p.size), ca.SX.sym("w", P.w.size)
    xdot = cas["plant_rhs"](xs, us, ts, ps, ws)
    cas["plant_jac"] = ca.Function("plant_jac", [xs, us, ts, ps, ws],
                                   [ca.densify(ca.jacobian(xdot, xs)), ca.densify(ca.jacobian(xdot, us))],
                                   ["x", "u", "t", "p", "w"], ["dfdx", "dfdu"])
    funcs = [Generated(_lean(cas[name]), *_SIGNATURES[name]) for name in _SIGNATURES]
    advance = casadi_plant_advance(cas, P)
    funcs.append(Generated(advance, ["zp", None, "p", "w", None], ["zp", None],
                           "plant half of a step: actuators, delay line, PWPF, RK4 of plant_rhs over dt"))
    general = {g.fn.name(): g for g in funcs}
    variants: dict[str, list[dict]] = {}
    for base, vs in VARIANTS.items():
        g = general[base]
        for v in vs:
            name = f"{base}_{v.suffix}"
            fn = specialised(g.fn, list(g.fn.name_in()).index("p"), zero_indices(P.p, v), name)
            funcs.append(Generated(fn, g.inputs, g.outputs, f"{base} specialised: {v.doc}"))
            variants.setdefault(base, []).append({"function": name, "zero": zero_fields(P.p, v)})
    layouts = {name: lay.describe() for name, lay in
               (("p", P.p), ("x", P.x), ("u", P.u), ("w", P.w), ("meas", P.meas), ("env", P.env), ("hold", P.hold),
                ("zp", cl.state_layout(P)))}
    return FamilyOutput(funcs, layouts, {"delay_slots": cl.DELAY_SLOTS,
                                         "quaternion_convention": QUATERNION_CONVENTION,
                                         "faults": flt.vocabulary(),
                                         "specialised": variants})


def _lean(fn):
    """An SX function with its repeated divisors' reciprocals shared (:mod:`.reciprocals`)."""
    from .reciprocals import share_reciprocals

    return share_reciprocals(fn) if fn.is_a("SXFunction") else fn


def _casadi_ops():
    import casadi as ca

    return SimpleNamespace(vcat=ca.vertcat, floor=ca.floor, fmax=ca.fmax, sqrt=ca.sqrt, if_else=ca.if_else,
                           zeros=lambda n: ca.MX.zeros(n, 1))


def _caller(f):
    """Call a CasADi Function on a list of MX arguments, returning its outputs as a list."""
    return lambda *a: f.call(list(a))


def _expanded(name: str, inputs: list, outputs: list, in_names: list[str], out_names: list[str]):
    """An MX composition expanded to one SX function and common-subexpression-eliminated, so that
    e.g. RK4 stages at equal times share the orbit (Kepler) and every other time-only term."""
    import casadi as ca

    f = ca.Function(name, inputs, outputs, in_names, out_names).expand()
    syms = [ca.SX.sym(n, f.size1_in(i)) for i, n in enumerate(in_names)]
    outs = f(*syms)
    outs = outs if isinstance(outs, (list, tuple)) else [outs]
    # one elimination over all outputs: per output, a subexpression two outputs share (the
    # environment outputs and the first RK4 stage at (x, t)) would be computed twice
    return _lean(ca.Function(name, syms, ca.cse(list(outs)), in_names, out_names))


def casadi_plant_advance(cas: dict, P):
    """:func:`closed_loop.plant_advance` composed from the plant's CasADi pieces (actuators, delay
    line, PWPF, two RK4 sub-steps of the plant, renormalisation, environment outputs)."""
    import casadi as ca

    from ..physics import closed_loop as cl

    zp = ca.MX.sym("zp", cl.state_layout(P).size)
    t, p = ca.MX.sym("t"), ca.MX.sym("p", P.p.size)
    w, cmd = ca.MX.sym("w", P.w.size), ca.MX.sym("cmd", 9)
    calls = {name: _caller(cas[name]) for name in cl.PLANT_PIECES}
    zp_next, y_plant = cl.plant_advance(_casadi_ops(), calls, cl.step_indices(P), zp, t, p, w, cmd)
    return _expanded("plant_advance", [zp, t, p, w, cmd], [zp_next, y_plant], ["zp", "t", "p", "w", "cmd"],
                     ["zp_next", "y_plant"])


def casadi_control(cas: dict, P, ctrl):
    """:func:`closed_loop.controller_update` of ``ctrl``: the command, the controller state after
    one RK4 step with the measurement held, and the diagnostics."""
    import casadi as ca

    from ..physics import closed_loop as cl

    meas, xc = ca.MX.sym("meas", P.meas.size), ca.MX.sym("xc", ctrl.xc.size)
    t, p, k = ca.MX.sym("t"), ca.MX.sym("p", P.p.size), ca.MX.sym("k", ctrl.k.size)
    dt = p[P.p.offsets()["dt"][0]]
    cmd, xc_next, diag = cl.controller_update(_casadi_ops(), _caller(cas[f"law_{ctrl.name}"]), meas, xc, t, p, k, dt,
                                              ctrl.xc.size)
    return _expanded(f"control_{ctrl.name}", [meas, xc, t, p, k], [cmd, xc_next, diag],
                     ["meas", "xc", "t", "p", "k"], ["cmd", "xc_next", "diag"])


def composed_step(cas: dict, P, ctrl) -> Generated:
    """``step_<name>`` = measure -> control_<name> -> plant_advance (:func:`closed_loop.step`): C glue
    calling the three generated functions, and the same composition as a CasADi function for the
    fallback backend."""
    import casadi as ca

    from ..physics import closed_loop as cl
    from .c_composition import Call, Callee, composed_c

    name = ctrl.name
    idx = cl.step_indices(P, ctrl)
    nzp, nh, nc, nx = idx["nzp"], idx["nh"], idx["nc"], idx["nx"]
    measure, control, advance = cas["measure"], cas[f"control_{name}"], cas["plant_advance"]
    z = ca.MX.sym("z", nzp + nh + nc)
    t, p = ca.MX.sym("t"), ca.MX.sym("p", P.p.size)
    k, w = ca.MX.sym("k", ctrl.k.size), ca.MX.sym("w", P.w.size)
    meas, hold_next = measure(z[0:nx], z[nzp:nzp + nh], t, p, w)
    cmd, xc_next, diag = control(meas, z[nzp + nh:nzp + nh + nc], t, p, k)
    zp_next, y_plant = advance(z[0:nzp], t, p, w, cmd)
    fn = ca.Function(f"step_{name}", [z, t, p, k, w], [ca.vertcat(zp_next, hold_next, xc_next),
                                                       ca.vertcat(meas, cmd, y_plant, diag)],
                     ["z", "t", "p", "k", "w"], ["z_next", "y"])
    n_meas, n_diag, n_yp = P.meas.size, ctrl.diag.size, advance.size1_out(1)

    def variants(base: str) -> list:
        return [(Callee.of(cas[f"{base}_{v.suffix}"]), zero_indices(P.p, v)) for v in VARIANTS[base]]

    c_code = composed_c(
        f"step_{name}", [("z", nzp + nh + nc), ("t", 1), ("p", P.p.size), ("k", ctrl.k.size), ("w", P.w.size)],
        [("z_next", ["zp_next", "hold_next", "xc_next"]), ("y", ["meas", "cmd", "y_plant", "diag"])],
        [("meas", n_meas), ("hold_next", nh), ("cmd", 9), ("xc_next", nc), ("diag", n_diag), ("zp_next", nzp),
         ("y_plant", n_yp)],
        [Call(Callee.of(measure), [("z", 0), ("z", nzp), ("t", 0), ("p", 0), ("w", 0)], ["meas", "hold_next"],
              variants=variants("measure")),
         Call(Callee.of(control), [("meas", 0), ("z", nzp + nh), ("t", 0), ("p", 0), ("k", 0)],
              ["cmd", "xc_next", "diag"]),
         Call(Callee.of(advance), [("z", 0), ("t", 0), ("p", 0), ("w", 0), ("cmd", 0)], ["zp_next", "y_plant"],
              variants=variants("plant_advance"))])
    ops = sum(int(f.n_instructions()) for f in (measure, control, advance))
    zlay, ylay, klay = f"z_{name}", f"y_{name}", f"k_{name}"
    return Generated(fn, [zlay, None, "p", klay, "w"], [zlay, ylay],
                     f"one closed-loop step (plant + {name} + actuators), RK4 over dt: measure, control_{name}, "
                     "plant_advance", c_code=c_code, ops=ops)


def _controller_family(name: str) -> Family:
    def build(resolve) -> FamilyOutput:
        from ..physics import closed_loop as cl
        from ..physics.plant import make_plant
        from .to_casadi import sympy_function

        P = make_plant()
        ctrl = load_controller(name)
        cas = {n: sympy_function(pc.name, pc.inputs, pc.outputs)
               for n, pc in cl.controller_pieces(P, ctrl).items()}
        for piece in ("measure", "plant_advance", *(f"{b}_{v.suffix}" for b, vs in VARIANTS.items() for v in vs)):
            cas[piece] = resolve(piece)
        cas[f"control_{name}"] = casadi_control(cas, P, ctrl)
        klay, xlay, dlay, zlay, ylay = (f"{pre}_{name}" for pre in ("k", "xc", "diag", "z", "y"))
        funcs = [Generated(_lean(cas[f"law_{name}"]), ["meas", xlay, None, "p", klay], [None, None, dlay],
                           f"control law of {name}"),
                 Generated(cas[f"control_{name}"], ["meas", xlay, None, "p", klay], [None, xlay, dlay],
                           f"controller half of a step of {name}: command, controller state after RK4 over dt"),
                 composed_step(cas, P, ctrl)]
        entry = {"step": f"step_{name}", "law": f"law_{name}", "control": f"control_{name}", "gains": klay}
        if f"xc0_{name}" in cas:
            funcs.append(Generated(_lean(cas[f"xc0_{name}"]), ["meas", "p", klay], [xlay],
                                   f"initial state of {name} from the first measurement"))
            entry["xc0"] = f"xc0_{name}"
        layouts = {klay: ctrl.k.describe(), xlay: ctrl.xc.describe(), dlay: ctrl.diag.describe(),
                   zlay: cl.state_layout(P, ctrl).describe(), ylay: cl.output_layout(P, ctrl).describe()}
        return FamilyOutput(funcs, layouts, {"controllers": {name: entry}})

    return Family(f"controller_{name}", (CONTROLLERS_DIR / f"{name}.py", Path(__file__)), build, ("plant",))


def families() -> list[Family]:
    """rpo's model: the plant family, then one family per controller module."""
    plant = Family("plant", (Path(__file__), PHYSICS_DIR / "closed_loop.py", PHYSICS_DIR / "plant.py",
                             CODEGEN_DIR / "to_casadi.py"),
                   _build_plant)
    return [plant, *(_controller_family(n) for n in controller_names())]
