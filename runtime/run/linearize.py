"""Linearisation of the generated model: the plant's A, B and the closed-loop step's Jacobian.

Two functions taking the :class:`~rpo.runtime.model.loader.Model` (functions, not methods, so that
``compiled.py`` stays the loader only):

* :func:`plant_jacobians` -- continuous-time ``A = df/dx``, ``B = df/du`` of ``plant_rhs`` at
  (x, u, t), in the raw coordinates of the layouts ``x`` and ``u`` (the generated ``plant_jac``,
  itself CasADi AD of ``plant_rhs``);
* :func:`linearize` -- the Jacobian ``d xi_{k+1} / d xi_k`` of one closed-loop step
  ``step_<ctrl>: (z, t, p, k, w) -> (z_next, y)`` in reduced coordinates ``xi``.

The step Jacobian is CasADi's algorithmic differentiation of the serialised step
(``generated/step_<ctrl>.casadi.gz``, the same expressions the C code was generated from; its
sha256 is checked against the manifest), evaluated in CasADi's virtual machine.  No C is generated
or compiled for it, so the build and its edit loop are unchanged.  Building the derivative takes
about 2 s per controller (cached for the process), each evaluation about 30 ms.

Reduced coordinates: :mod:`rpo.runtime.run.coordinates` (``docs/linearization.md``).

The goal (:func:`goal_state`): the controller's own error diagnostics ``q_err`` (vector part),
``rate_err``, ``pos_err`` and ``vel_err`` (every paper controller logs them) are driven to zero by
Newton's method over the chaser's attitude, rate, relative position and velocity, with the target
and time as given, the delay line holding the goal's wheel command, the PWPF at rest and the
controller states started from the goal's measurement as a run would.
"""

from __future__ import annotations

import cmath
import gzip
import hashlib
import math
import time
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.loader import Model
from rpo.runtime.model.manifest import ControllerSpec, generated_dir, read_manifest
from rpo.runtime.run.coordinates import (  # noqa: F401  (re-exported: the maps users call from here)
    GROUP_ORDER,
    QUATERNIONS,
    RIGID_GROUPS,
    Coordinates,
    left_matrix,
    local,
    local_tangent,
    quat_exp,
    quat_log,
    retract,
    retract_tangent,
)
from rpo.runtime.run.stability import stability_summary, summary_lines

#: The diagnostics that define the goal (vector part of q_err, then the rest), all zero there.
GOAL_ERRORS = ("q_err", "rate_err", "pos_err", "vel_err")
#: The z fields the goal search moves (the chaser's pose and rates relative to the target's).
GOAL_UNKNOWNS = ("q_c", "w_c", "r", "v")
#: |lambda| below this counts as a deadbeat mode (a delay slot, a thruster on-level).
DEADBEAT = 1e-10


def coordinates(model: Model, controller: str) -> Coordinates:
    """The reduced coordinates of ``z_<controller>``."""
    return Coordinates(model.layouts[_entry(model, controller).z_layout].fields)


# --------------------------------------------------------------------------- AD of the step


def _entry(model: Model, controller: str) -> ControllerSpec:
    return model.manifest.controller(controller)


@lru_cache(maxsize=8)
def _step_derivative(path: str, digest: str):
    """CasADi function (z, t, p, k, w) -> (z_next, y, dz_next/dz, dy/dz): AD of the serialised step."""
    import casadi as ca

    data = Path(path).read_bytes()
    if hashlib.sha256(data).hexdigest() != digest:
        raise ModelError(f"{path} does not match manifest.json (edited by hand or being rewritten): "
                         "run `python build.py`")
    f = ca.Function.deserialize(gzip.decompress(data).decode())
    args = [ca.MX.sym(f.name_in(i), f.size1_in(i)) for i in range(f.n_in())]
    zn, y = f(*args)
    z = args[0]
    return ca.Function(f"{f.name()}_jac", args, [zn, y, ca.jacobian(zn, z), ca.jacobian(y, z)],
                       [f.name_in(i) for i in range(f.n_in())], ["z_next", "y", "dz_next_dz", "dy_dz"])


def step_derivative(model: Model, controller: str, gen_dir: Path | None = None):
    """The CasADi AD function of ``step_<controller>`` (built once per process, ~2 s)."""
    step = _entry(model, controller).step
    name = f"{step}.casadi.gz"
    digest = model.manifest.files.get(name)
    if digest is None:
        raise ModelError(f"manifest.json lists no {name}: run `python build.py`")
    path = (generated_dir() if gen_dir is None else Path(gen_dir)) / name
    if not path.exists():
        raise ModelError(f"{path} is missing: run `python build.py`")
    return _step_derivative(str(path), digest)


def _eval(model: Model, controller: str, z: np.ndarray, t: float, p: np.ndarray, k: np.ndarray,
          w: np.ndarray | None):
    fn = step_derivative(model, controller)
    w = np.zeros(model.layout_size("w")) if w is None else np.asarray(w, float)
    zn, y, jz, jy = fn(np.asarray(z, float), float(t), np.asarray(p, float), np.asarray(k, float), w)
    return (np.asarray(zn).ravel(), np.asarray(y).ravel(), np.asarray(jz.full()), np.asarray(jy.full()))


# --------------------------------------------------------------------------- results


@dataclass
class Mode:
    """One eigenvalue of the reduced step Jacobian and its continuous-time equivalent s = log(lam)/dt."""

    lam: complex
    s: complex | None                  # None for a deadbeat mode (lam = 0)
    group: str                         # the group with the largest participation
    state: str                         # the reduced coordinate with the largest participation
    participation: dict[str, float]    # per group, summing to 1
    block: str = ""                    # the groups of its diagonal block of A (see Linearization.modes)

    @property
    def tau(self) -> float | None:
        """Time constant -1/Re(s) [s] (negative: growing; None: deadbeat or Re(s) = 0)."""
        if self.s is None or self.s.real == 0:
            return None
        return -1.0 / self.s.real

    @property
    def wn(self) -> float | None:
        """Natural frequency |s| [rad/s]."""
        return None if self.s is None else abs(self.s)

    @property
    def zeta(self) -> float | None:
        """Damping ratio -Re(s)/|s| (complex modes only)."""
        if self.s is None or abs(self.s.imag) == 0 or abs(self.s) == 0:
            return None
        return -self.s.real / abs(self.s)

    def to_json(self) -> dict[str, Any]:
        return {"lambda": [self.lam.real, self.lam.imag], "abs": abs(self.lam),
                "s": None if self.s is None else [self.s.real, self.s.imag], "tau_s": self.tau, "wn_rad_s": self.wn,
                "zeta": self.zeta, "group": self.group, "state": self.state,
                "participation": self.participation, "block": self.block}


@dataclass
class Linearization:
    """The closed-loop step's Jacobian in reduced coordinates: ``xi_{k+1} = A xi_k`` to first order.

    ``A[i, j]`` = d xi_next[i] / d xi[j]; ``labels``, ``units`` and ``groups`` (name -> slice)
    describe both its rows and columns.  ``jacobian`` is the raw d z_next / d z (nz x nz) and
    ``P_in``/``P_out`` the tangent maps with ``A = P_out @ jacobian @ P_in``.
    """

    A: np.ndarray
    labels: list[str]
    units: list[str]
    groups: dict[str, slice]
    controller: str
    t: float
    dt: float
    z: np.ndarray
    z_next: np.ndarray
    y: np.ndarray
    jacobian: np.ndarray
    P_in: np.ndarray
    P_out: np.ndarray
    coords: Coordinates
    seconds: float = 0.0

    def block(self, rows: str, cols: str | None = None) -> np.ndarray:
        """The block of A from the group ``cols`` (default: ``rows``) to the group ``rows``."""
        return self.A[self.groups[rows], self.groups[cols or rows]]

    def modes(self) -> list[Mode]:
        """Eigenvalues with s = log(lam)/dt, sorted by |lam|, largest first.

        A is block-triangular after a permutation: the strongly connected components of its
        dependency graph (A[i, j] != 0: state j drives state i) are independent diagonal blocks,
        and the eigenvalues of A are those of the blocks.  Each mode is computed in its block (so a
        target or filter mode is attributed exactly) and, inside the block, attributed by
        participation factors |w_i v_i| (left and right eigenvectors; |v_i|^2 where the block is
        defective, e.g. an open double integrator).
        """
        from scipy.sparse.csgraph import connected_components

        n_comp, comp = connected_components(self.A != 0, directed=True, connection="strong")
        out = []
        for c in range(n_comp):
            idx = np.flatnonzero(comp == c)
            lam, V = np.linalg.eig(self.A[np.ix_(idx, idx)])
            if np.linalg.cond(V) < 1e8:
                part = np.abs(np.linalg.inv(V).T * V)  # part[i, m]: state i in mode m
            else:
                part = np.abs(V) ** 2
            part = part / np.maximum(part.sum(axis=0, keepdims=True), 1e-300)
            groups = {self.coords.group_of(int(i)) for i in idx}
            block = "+".join(g for g in GROUP_ORDER if g in groups)
            for m in range(lam.size):
                lm = complex(lam[m])
                s = None if abs(lm) < DEADBEAT else cmath.log(lm) / self.dt
                pg: dict[str, float] = {}
                for i, pi in zip(idx, part[:, m], strict=True):
                    g = self.coords.group_of(int(i))
                    pg[g] = pg.get(g, 0.0) + float(pi)
                i_max = int(idx[int(np.argmax(part[:, m]))])
                out.append(Mode(lm, s, max(pg, key=lambda g: pg[g]), self.labels[i_max], pg, block))
        out.sort(key=lambda md: (-abs(md.lam), -md.lam.imag))
        return out

    def to_json(self) -> dict[str, Any]:
        return {"controller": self.controller, "t": self.t, "dt": self.dt, "labels": self.labels,
                "units": self.units, "groups": {g: [s.start, s.stop] for g, s in self.groups.items()},
                "A": self.A.tolist(), "modes": [m.to_json() for m in self.modes()],
                "summary": stability_summary(self.modes()), "seconds": self.seconds}


def linearize(model: Model, controller: str, z: np.ndarray, t: float, p: np.ndarray, k: np.ndarray,
              w: np.ndarray | None = None) -> Linearization:
    """The Jacobian of ``step_<controller>`` at (z, t, p, k, w) by CasADi AD, in reduced coordinates.

    ``w`` (noise and random-torque inputs) defaults to zero.
    """
    t0 = time.perf_counter()
    coords = coordinates(model, controller)
    z = np.asarray(z, float)
    if z.size != coords.nz:
        raise ModelError(f"z_{controller} needs {coords.nz} values, got {z.size}")
    for q in QUATERNIONS:
        n = float(np.linalg.norm(z[model.offsets(f"z_{controller}")[q]]))
        if abs(n - 1) > 1e-6:
            raise ModelError(f"{q} must be a unit quaternion to linearise at (|q| = {n:.9g})")
    zn, y, jz, _jy = _eval(model, controller, z, t, p, k, w)
    if not (np.all(np.isfinite(jz)) and np.all(np.isfinite(zn))):
        zl = model.labels(f"z_{controller}")
        cols = [zl[j] for j in np.flatnonzero(~np.isfinite(jz).all(axis=0))]
        raise ModelError(f"the step's Jacobian is not finite at this state (d z_next / d {', '.join(cols[:4])}"
                         f"{' ...' if len(cols) > 4 else ''}): a point where the law has an infinite derivative "
                         "(e.g. a super-twisting |e|^(1/2) at e = 0); linearise elsewhere (--at)")
    P_in, P_out = coords.tangent_in(z), coords.tangent_out(zn)
    dt = float(np.asarray(p)[model.offsets("p")["dt"]][0])
    return Linearization(P_out @ jz @ P_in, coords.labels, coords.units, coords.groups, controller, float(t), dt, z,
                         zn, y, jz, P_in, P_out, coords, time.perf_counter() - t0)


@dataclass
class PlantJacobians:
    """Continuous-time A = df/dx (nx x nx) and B = df/du (nx x nu) of ``plant_rhs``, raw coordinates."""

    A: np.ndarray
    B: np.ndarray
    x_labels: list[str]
    u_labels: list[str]


def plant_jacobians(model: Model, x: np.ndarray, u: np.ndarray, t: float, p: np.ndarray,
                    w: np.ndarray | None = None) -> PlantJacobians:
    """A, B of the plant at (x, u, t) from the generated ``plant_jac`` (CasADi AD of ``plant_rhs``),
    in the layouts' own coordinates (quaternions as 4 components)."""
    w = np.zeros(model.layout_size("w")) if w is None else w
    A, B = model.function("plant_jac")(x, u, t, p, w)
    return PlantJacobians(np.asarray(A), np.asarray(B), model.labels("x"), model.labels("u"))


# --------------------------------------------------------------------------- the goal


@dataclass
class Goal:
    """The goal state found by :func:`goal_state` and how it was found."""

    z: np.ndarray
    iterations: int
    residual: float


def _y_index(model: Model, controller: str, names) -> list[int]:
    offs = model.offsets(f"y_{controller}")
    missing = [n for n in names if f"ctrl_{n}" not in offs]
    if missing:
        raise ModelError(f"controller {controller} logs no {', '.join(missing)} diagnostics, which define its goal; "
                         "linearise at the initial state instead (--at initial)")
    out: list[int] = []
    for n in names:
        sl = offs[f"ctrl_{n}"]
        out += list(range(sl.start, sl.start + 3))  # q_err: its vector part
    return out


def settle_actuators(model: Model, controller: str, z: np.ndarray, y: np.ndarray) -> np.ndarray:
    """z with the delay line holding the wheel command of y (as after a long steady hold) and the
    PWPF at rest (prefilters 0, thrusters off)."""
    z = np.array(z, float)
    zo, yo = model.offsets(f"z_{controller}"), model.offsets(f"y_{controller}")
    cmd = y[yo["wheel_cmd"]]
    for name, sl in zo.items():
        if name.startswith("wheel_cmd_"):
            z[sl] = cmd
        elif name in ("pwpf_f", "pwpf_on"):
            z[sl] = 0.0
    return z


def goal_state(model: Model, controller: str, z_start: np.ndarray, t: float, p: np.ndarray, k: np.ndarray,
               xc0=None, tol: float = 1e-11, max_iter: int = 30) -> Goal:
    """The state the controller regulates to, near ``z_start``: its ``q_err`` vector part,
    ``rate_err``, ``pos_err`` and ``vel_err`` are zero (Newton in reduced coordinates over the
    chaser's attitude, rate, relative position and velocity; the target, wheels and time as given).

    ``xc0(z) -> z``: restarts the controller states from the goal's measurement (as a run does);
    the delay line is then filled with the goal's wheel command (:func:`settle_actuators`).
    """
    coords = coordinates(model, controller)
    rows = _y_index(model, controller, GOAL_ERRORS)
    cols = coords.indices(*GOAL_UNKNOWNS)
    z = np.array(z_start, float)
    res = math.inf
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 (the count is reported)
        _zn, y, _jz, jy = _eval(model, controller, z, t, p, k, None)
        e = y[rows]
        res = float(np.max(np.abs(e)))
        if not np.isfinite(res):
            raise ModelError(f"the goal search reached a state where {controller}'s errors are not finite")
        if res < tol:
            break
        J = (jy @ coords.tangent_in(z))[rows][:, cols]
        step = np.linalg.lstsq(J, -e, rcond=None)[0]
        xi = np.zeros(coords.n)
        xi[cols] = step
        z = coords.to_z(z, xi)
    else:
        raise ModelError(f"the goal search for {controller} did not converge ({max_iter} Newton steps, "
                         f"largest error {res:.3g})")
    if xc0 is not None:
        z = xc0(z)
    _zn, y, _jz, _jy = _eval(model, controller, z, t, p, k, None)
    z = settle_actuators(model, controller, z, y)
    e = _eval(model, controller, z, t, p, k, None)[1][rows]
    return Goal(z, it, float(np.max(np.abs(e))))


# --------------------------------------------------------------------------- from a scenario


@dataclass
class ScenarioLinearization:
    """:func:`linearize_scenario`'s result: the linearisation and where it was taken."""

    lin: Linearization
    scenario: str
    at: str
    goal: Goal | None
    plant: str
    meta: dict = field(default_factory=dict)


def linearize_scenario(path: Any, model: Model | None = None, controller: str | None = None,
                       plant: str | None = None, at: str = "goal", t: float = 0.0,
                       log=None) -> ScenarioLinearization:
    """Linearise the closed loop of a scenario at its goal (default) or its initial state, at time t
    (the target's attitude and rate at the start of the scenario; noise zero)."""
    from rpo.runtime.model.loader import load_model
    from rpo.runtime.run.simulate import Simulation
    from rpo.runtime.scenario import load_scenario

    if at not in ("goal", "initial"):
        raise ModelError(f"at must be 'goal' or 'initial', got {at!r}")
    base = load_scenario(path, model.manifest if model is not None else read_manifest())
    sc = base.with_overrides(controller=controller, plant=plant)
    ctrl = sc.simulation.controller
    model = load_model(controllers=[ctrl], log=log) if model is None else model
    inputs = sc.to_run(model)
    sim = Simulation(model, ctrl, params=inputs.params, gains=inputs.gains)
    z0 = sim.initial_state(inputs.plant)
    goal = None
    if at == "goal":
        offs = model.offsets(f"z_{ctrl}")

        def restart(z: np.ndarray) -> np.ndarray:
            plant_state = {n: z[offs[n]] for n in ("q_c", "w_c", "h_w", "q_t", "w_t", "r", "v", "m_prop")}
            return sim.initial_state(plant_state)

        goal = goal_state(model, ctrl, z0, t, sim.p, sim.k, xc0=restart)
        z0 = goal.z
    lin = linearize(model, ctrl, z0, t, sim.p, sim.k)
    po, ko, yo = model.offsets("p"), model.offsets(f"k_{ctrl}"), model.offsets(f"y_{ctrl}")
    meta: dict[str, Any] = {"ideal": bool(sim.p[po["actuators_ideal"]][0]),
                            "wheel_limit": float(sim.p[po["wheel_torque_max"]][0]),
                            "wheel_cmd": lin.y[yo["wheel_cmd"]].tolist()}
    meta["nonsmooth"] = nonsmooth_columns(model, lin, sim.p, sim.k)
    if "acc_d" in ko and "acc_d_on" in ko:
        meta["acc_d"] = (sim.k[ko["acc_d"]] * sim.k[ko["acc_d_on"]][0]).tolist()
    return ScenarioLinearization(lin, sc.name, at, goal, plant or "paper", meta)


def central_differences(model: Model, lin: Linearization, p: np.ndarray, k: np.ndarray, h: float = 1e-6,
                        w: np.ndarray | None = None) -> np.ndarray:
    """Central differences of the compiled ``step_<ctrl>`` in the reduced coordinates of ``lin``
    (step h * max(1, |z_j|) per coordinate, and h * max(1, |z_field|) for the plant's vectors,
    |z_field| the norm of the field: their components are a frame's, and a component near 0 of a
    large vector, such as the z velocity of an orbit, would otherwise get a step whose effect on the
    next state drowns in that state's round-off): a check of the AD Jacobian, and of where the point
    sits on a discontinuity (a sign law on its switching surface) or a kink (|s| at s = 0)."""
    step = model.function(model.manifest.controllers[lin.controller].step)
    c = lin.coords
    w = np.zeros(model.layout_size("w")) if w is None else w
    scale = np.ones(c.n)
    plant_fields = {f.name for f in model.layouts["x"] if f.size > 1}
    for name, zs, xs in c.blocks:
        if name not in QUATERNIONS:
            if name in plant_fields:
                scale[xs] = max(1.0, float(np.linalg.norm(lin.z[zs])))
            else:
                scale[xs] = np.maximum(1.0, np.abs(lin.z[zs]))
    zn0 = step(lin.z, lin.t, p, k, w)[0]
    J = np.zeros((c.n, c.n))
    for j in range(c.n):
        e = np.zeros(c.n)
        e[j] = h * scale[j]
        zp = step(c.to_z(lin.z, e), lin.t, p, k, w)[0]
        zm = step(c.to_z(lin.z, -e), lin.t, p, k, w)[0]
        J[:, j] = (c.to_xi(zn0, zp) - c.to_xi(zn0, zm)) / (2 * e[j])
    return J


def nonsmooth_columns(model: Model, lin: Linearization, p: np.ndarray, k: np.ndarray) -> list[str]:
    """The reduced coordinates whose perturbation by 1e-6 (relative) changes the step by far more
    than the AD Jacobian predicts: the point is on a discontinuity or kink of the step there."""
    J = central_differences(model, lin, p, k)
    bad = np.abs(J - lin.A) > 1e-3 * (1 + np.abs(lin.A))
    return [lin.labels[j] for j in np.flatnonzero(bad.any(axis=0))]


def format_report(res: ScenarioLinearization) -> str:
    """The text ``rpo linearize`` prints."""
    lin = res.lin
    c = lin.coords
    zo = {name: zs for name, zs, _xs in c.blocks}
    z = lin.z
    lines = [f"{res.scenario}: closed-loop step_{lin.controller} linearised at the {res.at} state, t = {lin.t:g} s, "
             f"dt = {lin.dt:g} s, plant {res.plant}"]
    if res.goal is not None:
        lines.append(f"  goal        Newton on {lin.controller}'s q_err, rate_err, pos_err, vel_err: "
                     f"{res.goal.iterations} iterations, largest error {res.goal.residual:.2g}")
    fmt = lambda v: "[" + ", ".join(f"{x:.6g}" for x in v) + "]"  # noqa: E731
    lines.append(f"  state       r = {fmt(z[zo['r']])} m, v = {fmt(z[zo['v']])} m/s, w_c = {fmt(z[zo['w_c']])} rad/s, "
                 f"w_t = {fmt(z[zo['w_t']])} rad/s")
    lines.append(f"              q_c = {fmt(z[zo['q_c']])}, q_t = {fmt(z[zo['q_t']])} (ECI, scalar last)")
    lines.append(f"  coordinates {c.n} reduced states: " +
                 ", ".join(f"{g} {s.stop - s.start}" for g, s in lin.groups.items()) +
                 " (attitudes as rotation vectors q = q0 ⊗ exp(dth), docs/linearization.md)")
    lines.append(f"  Jacobian    CasADi AD of step_{lin.controller}, {lin.seconds:.2g} s")
    lines += _notes(res)
    modes = lin.modes()
    dead = [m for m in modes if m.s is None]
    live = [m for m in modes if m.s is not None]
    rows: list[tuple[Mode, int]] = []   # equal eigenvalues of the same block on one row
    for m in live:
        if rows and rows[-1][0].block == m.block and abs(rows[-1][0].lam - m.lam) < 1e-12:
            rows[-1] = (rows[-1][0], rows[-1][1] + 1)
        else:
            rows.append((m, 1))
    lines.append(f"  eigenvalues of A: {len(live)} (equal ones of one block on one row; s = ln(lambda)/dt, "
                 f"tau = -1/Re s, zeta where complex), and {len(dead)} deadbeat (lambda = 0: " +
                 (", ".join(f"{g} {n}" for g, n in _count(m.state.rsplit('_', 1)[0] for m in dead)) or "none") + ")")
    lines.append(f"  {'#':>3s} {'|lambda|':>12s} {'lambda':>28s} {'s [1/s]':>24s} {'tau [s]':>10s} {'zeta':>6s} "
                 f"{'n':>3s}  block: dominant state")
    for i, (m, count) in enumerate(rows, 1):
        s = m.s
        assert s is not None
        lam = f"{m.lam.real:+.9f} {m.lam.imag:+.3e}j"
        ss = f"{s.real:+.4e} {s.imag:+.3e}j"
        tau = "inf" if m.tau is None else f"{m.tau:.4g}"
        zeta = "" if m.zeta is None else f"{m.zeta:.3f}"
        lines.append(f"  {i:>3d} {abs(m.lam):>12.9f} {lam:>28s} {ss:>24s} {tau:>10s} {zeta:>6s} {count:>3d}  "
                     f"{m.block}: {m.state}")
    lines += summary_lines(stability_summary(modes))
    return "\n".join(lines)


def _notes(res: ScenarioLinearization) -> list[str]:
    """Where the point of linearisation sits on a non-smooth branch (its derivative there is zero)."""
    lin = res.lin
    c = lin.controller
    out = []
    meta = res.meta
    if meta.get("wheel_limit") is not None:
        y_cmd = meta["wheel_cmd"]
        sat = [str(i + 1) for i, v in enumerate(y_cmd) if abs(v) >= meta["wheel_limit"] * (1 - 1e-9)]
        if sat and not meta.get("ideal"):
            out.append(f"  note        wheel{'s' * (len(sat) > 1)} {', '.join(sat)} at the torque limit "
                       f"{meta['wheel_limit']:g} N m here: saturated, so its command has no derivative")
    if not meta.get("ideal"):
        out.append("  note        PWPF thrusters: the Schmitt trigger's on-levels have zero derivative, so the thrust "
                   "does not depend on the state in A (translation is open loop here; see docs/linearization.md)")
    if meta.get("nonsmooth"):
        cols = meta["nonsmooth"]
        out.append(f"  note        non-smooth here (central differences of the compiled step disagree with AD) in "
                   f"{len(cols)} coordinate{'s' * (len(cols) > 1)}: {', '.join(cols[:8])}{' ...' * (len(cols) > 8)}; "
                   "e.g. a sign(s) law on its switching surface s = 0, whose derivative AD takes as 0")
    if np.any(np.abs(meta.get("acc_d", 0.0)) > 0):
        acc = [round(float(a), 6) for a in np.ravel(meta["acc_d"])]
        out.append(f"  note        {c} commands a desired acceleration acc_d = {acc} m/s^2 "
                   "(acc_d_on = 1): the goal is not an equilibrium")
    return out


def _count(items) -> list[tuple[str, int]]:
    out: dict[str, int] = {}
    for it in items:
        out[it] = out.get(it, 0) + 1
    return list(out.items())
