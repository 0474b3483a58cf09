"""Code generation: SymPy model -> CasADi functions -> C sources and manifest in ``generated/``.

Called by ``build.py``.  Output is deterministic (same sources and tool versions give
byte-identical files), which is what lets ``build.py --check`` detect a stale ``generated/``.
"""

from __future__ import annotations

import gzip
import hashlib
import importlib
import json
import os
import platform
import tempfile
from pathlib import Path
from types import SimpleNamespace

import casadi as ca
import sympy as sp

from . import closed_loop as cl
from .controllers.baseline import Baseline
from .orbit import eccentric_anomaly
from .plant import make_plant
from .relative_attitude import attitude_error_rate, rate_error_dynamics
from .to_casadi import sympy_function

SYMBOLIC_DIR = Path(__file__).resolve().parent
MODULE = "rpo_model"
#: Bump when the layout of generated files or the manifest schema changes.
FORMAT_VERSION = 1


def source_hash(root: Path = SYMBOLIC_DIR) -> str:
    """sha256 over every Python source of ``symbolic/`` the generated code is built from (relative path
    and bytes, sorted).  ``symbolic/lyapunov/`` is left out: it only reads the model to check the proofs,
    so editing a claim must not make generated/ stale."""
    h = hashlib.sha256()
    for f in sorted(root.rglob("*.py")):
        if "__pycache__" in f.parts or f.relative_to(root).parts[0] == "lyapunov":
            continue
        h.update(f.relative_to(root).as_posix().encode() + b"\0")
        h.update(f.read_bytes() + b"\0")
    return h.hexdigest()


def tool_versions() -> dict[str, str]:
    return {"casadi": ca.__version__, "sympy": sp.__version__}


CASADI_OPS = SimpleNamespace(
    vcat=ca.vertcat,
    floor=ca.floor,
    fmax=ca.fmax,
    sqrt=ca.sqrt,
    if_else=ca.if_else,
    zeros=lambda n: ca.MX.zeros(n, 1),
)


def controllers():
    """Controller designs to generate a closed-loop step for: the baseline, then every module of
    ``symbolic/controllers/`` that exposes ``DESIGN`` (sorted by module name)."""
    found = [Baseline()]
    pkg = SYMBOLIC_DIR / "controllers"
    for path in sorted(pkg.glob("*.py")):
        if path.stem.startswith("_") or path.stem == "baseline":
            continue
        mod = importlib.import_module(f"{__package__}.controllers.{path.stem}")
        if hasattr(mod, "DESIGN"):
            found.append(mod.DESIGN())
    return found


def sources(P=None, ctrls=None) -> tuple[dict[str, cl.Piece], dict]:
    """The SymPy source of every generated function except the composed steps, by name.

    Tests evaluate these same expressions with NumPy (``sympy.lambdify``) and compare them with
    the compiled functions; :func:`build_functions` translates them to CasADi.
    """
    P = make_plant() if P is None else P
    ctrls = controllers() if ctrls is None else ctrls
    pieces: dict[str, cl.Piece] = {}
    for ctrl in ctrls:
        for name, pc in cl.model_pieces(P, ctrl).items():
            pieces.setdefault(name, pc)
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
    return pieces, {"plant": P, "controllers": ctrls}


#: Manifest layout names of each source function's inputs and outputs, and its description.
_SIGNATURES = {
    "plant_rhs": (["x", "u", None, "p", "w"], ["x"], "plant right-hand side dx/dt (000 eqs. 6, 10, 24, 30, 45-47)"),
    "measure": (["x", None, "p", "w"], ["meas"], "truth + sensor noise -> what the controllers read"),
    "ideal_actuators": ([None, None, "p"], [None, None], "ideal actuators: per-axis saturated force and torque"),
    "env_outputs": (["x", "u", None, "p", "w"], ["env"], "environment/actuator diagnostics"),
    "wheel_alloc": ([None, "p"], [None], "pyramid wheel allocation with saturation (inverse of 000 eq. 46)"),
    "thruster_alloc": ([None, None, "p"], [None], "thruster duty allocation"),
    "pwpf": ([None, None, None, "p"], [None], "PWPF Schmitt trigger"),
    "pwpf_filter": ([None, None, None, "p"], [None], "PWPF prefilter update over dt"),
    "target_orbit": ([None, "p"], [None] * 8, "target orbit at t (000 eqs. 31-36, corrected LVLH rate)"),
    "kepler": ([None, None], [None], "eccentric anomaly from Kepler's equation (000 eq. 32)"),
    "relative_attitude_rhs": (["x", "u", None, "p", "w", None], [None],
                              "relative attitude model (000 eqs. 24-29) driven by the plant state, for checks"),
}


def build_functions():
    """All CasADi functions to generate, plus their manifest descriptions."""
    pieces, ctx = sources()
    P = ctx["plant"]
    layouts = {"p": P.p, "x": P.x, "u": P.u, "w": P.w, "meas": P.meas, "env": P.env}
    funcs: list[ca.Function] = []
    desc: dict[str, dict] = {}

    def add(fn: ca.Function, in_layouts, out_layouts, doc: str):
        funcs.append(fn)
        desc[fn.name()] = {
            "doc": doc,
            "inputs": [{"name": fn.name_in(i), "shape": list(fn.size_in(i)), "layout": in_layouts[i]}
                       for i in range(fn.n_in())],
            "outputs": [{"name": fn.name_out(i), "shape": list(fn.size_out(i)), "layout": out_layouts[i]}
                        for i in range(fn.n_out())],
        }

    cas = {name: sympy_function(pc.name, pc.inputs, pc.outputs) for name, pc in pieces.items()}
    for name in ("plant_rhs",):
        add(cas[name], *_SIGNATURES[name])
    rhs = cas["plant_rhs"]
    xs, us = ca.SX.sym("x", P.x.size), ca.SX.sym("u", P.u.size)
    ts, ps, ws = ca.SX.sym("t"), ca.SX.sym("p", P.p.size), ca.SX.sym("w", P.w.size)
    xdot = rhs(xs, us, ts, ps, ws)
    jac = ca.Function("plant_jac", [xs, us, ts, ps, ws],
                      [ca.densify(ca.jacobian(xdot, xs)), ca.densify(ca.jacobian(xdot, us))],
                      ["x", "u", "t", "p", "w"], ["dfdx", "dfdu"])
    add(jac, ["x", "u", None, "p", "w"], [None, None], "Jacobians of plant_rhs w.r.t. x and u (CasADi AD)")
    for name in ("measure", "env_outputs", "ideal_actuators", "wheel_alloc", "thruster_alloc", "pwpf",
                 "pwpf_filter"):
        add(cas[name], *_SIGNATURES[name])

    ctrl_entries = {}
    for ctrl in ctx["controllers"]:
        law = cas[f"law_{ctrl.name}"]
        klay = f"k_{ctrl.name}"
        layouts[klay] = ctrl.k
        layouts[f"xc_{ctrl.name}"] = ctrl.xc
        layouts[f"diag_{ctrl.name}"] = ctrl.diag
        add(law, ["meas", f"xc_{ctrl.name}", None, "p", klay], [None, None, f"diag_{ctrl.name}"],
            f"control law of {ctrl.name}")
        zl, yl = cl.state_layout(P, ctrl), cl.output_layout(P, ctrl)
        layouts[f"z_{ctrl.name}"], layouts[f"y_{ctrl.name}"] = zl, yl
        stepf = casadi_step(cas, P, ctrl)
        add(stepf, [f"z_{ctrl.name}", None, "p", klay, "w"], [f"z_{ctrl.name}", f"y_{ctrl.name}"],
            f"one closed-loop step (plant + {ctrl.name} + actuators), RK4 over dt")
        ctrl_entries[ctrl.name] = {"step": stepf.name(), "law": law.name(), "gains": klay}
        if f"xc0_{ctrl.name}" in cas:
            add(cas[f"xc0_{ctrl.name}"], ["meas", "p", klay], [f"xc_{ctrl.name}"],
                f"initial state of {ctrl.name} from the first measurement")
            ctrl_entries[ctrl.name]["xc0"] = f"xc0_{ctrl.name}"

    for name in ("target_orbit", "kepler", "relative_attitude_rhs"):
        add(cas[name], *_SIGNATURES[name])

    manifest_layouts = {name: lay.describe() for name, lay in layouts.items()}
    extra = {
        "delay_slots": cl.DELAY_SLOTS,
        "controllers": ctrl_entries,
        "quaternion_convention": "scalar-last [x, y, z, w], Hamilton product, q_B_A: v_A = q v_B q*",
    }
    return funcs, desc, manifest_layouts, extra


def _caller(f: ca.Function):
    """Call a CasADi Function on a list of MX arguments, returning its outputs as a list."""
    return lambda *a: f.call(list(a))


def casadi_step(cas: dict[str, ca.Function], P, ctrl) -> ca.Function:
    """The closed-loop step composed (:func:`closed_loop.step`) from the CasADi pieces, expanded to SX."""
    zl = cl.state_layout(P, ctrl)
    z = ca.MX.sym("z", zl.size)
    t = ca.MX.sym("t")
    p = ca.MX.sym("p", P.p.size)
    k = ca.MX.sym("k", ctrl.k.size)
    w = ca.MX.sym("w", P.w.size)
    names = ("plant_rhs", "measure", "env_outputs", "ideal_actuators", "wheel_alloc", "thruster_alloc", "pwpf",
             "pwpf_filter")
    fn = {name: cas[name] for name in names}
    fn["law"] = cas[f"law_{ctrl.name}"]
    fn = {name: _caller(f) for name, f in fn.items()}
    z_next, y = cl.step(CASADI_OPS, fn, cl.step_indices(P, ctrl), z, t, p, k, w)
    stepf = ca.Function(f"step_{ctrl.name}", [z, t, p, k, w], [z_next, y],
                        ["z", "t", "p", "k", "w"], ["z_next", "y"]).expand()
    # common-subexpression elimination across RK4 stages: stages at equal times share the orbit
    # (Kepler) and every other time-only term
    syms = [ca.SX.sym(n, stepf.size1_in(i)) for i, n in enumerate("ztpkw")]
    outs = stepf(*syms)
    return ca.Function(stepf.name(), syms, [ca.cse(o) for o in outs], ["z", "t", "p", "k", "w"], ["z_next", "y"])


def _header(src_hash: str) -> str:
    return (
        "/* GENERATED FILE - DO NOT EDIT.\n"
        " * Produced by `python build.py` from the SymPy model in symbolic/\n"
        f" * (source hash {src_hash}).  Edit symbolic/ and rebuild instead.\n"
        " */\n"
    )


def generate(out_dir: Path) -> dict:
    """Write the C sources and manifest into ``out_dir`` (which must exist); return the manifest."""
    src_hash = source_hash()
    funcs, desc, layouts, extra = build_functions()
    with tempfile.TemporaryDirectory() as tmp:
        cwd = os.getcwd()
        os.chdir(tmp)
        try:
            cg = ca.CodeGenerator(f"{MODULE}.c", {"with_header": True, "casadi_int": "long long int"})
            for f in funcs:
                cg.add(f)
            cg.generate()
            files = {}
            for name in (f"{MODULE}.c", f"{MODULE}.h"):
                text = Path(tmp, name).read_text()
                files[name] = _header(src_hash) + text
        finally:
            os.chdir(cwd)
    # serialized CasADi functions for the explicit no-compiler fallback (backend "casadi")
    blob = json.dumps({f.name(): f.serialize() for f in funcs}, sort_keys=True).encode()
    files_bytes = {name: text.encode() for name, text in files.items()}
    files_bytes[f"{MODULE}.casadi.gz"] = gzip.compress(blob, compresslevel=9, mtime=0)
    for name, data in files_bytes.items():
        (out_dir / name).write_bytes(data)
    manifest = {
        "format_version": FORMAT_VERSION,
        "generator": "build.py",
        "module": MODULE,
        "source_hash": src_hash,
        "tools": tool_versions(),
        "files": {name: hashlib.sha256(data).hexdigest() for name, data in sorted(files_bytes.items())},
        "functions": desc,
        "layouts": layouts,
        **extra,
    }
    manifest["manifest_hash"] = manifest_hash(manifest)
    (out_dir / "manifest.json").write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest


def manifest_hash(manifest: dict) -> str:
    """sha256 of the manifest's canonical JSON without its own ``manifest_hash`` field.

    The runtime recomputes it at load (a hand-edited layout, unit or default is refused) and
    includes it in the library cache key.  The same definition lives in
    ``rpo.runtime.compiled.manifest_hash``; ``tests/test_build.py`` checks that they agree.
    """
    body = {k: v for k, v in manifest.items() if k != "manifest_hash"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def python_info() -> str:
    return f"{platform.python_implementation()} {platform.python_version()}"
