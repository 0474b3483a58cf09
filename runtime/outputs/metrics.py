"""Performance metrics of one run, from its recorded columns (pure NumPy; no SymPy, no model).

``compute_metrics(t, columns, thresholds)`` takes the recorded time ``t`` [s] and a mapping from
column label (``r_x``, ``ctrl_att_err``, ``env_F_applied_y``...) to a 1-D array of the same
length, and returns a flat, JSON-ready dict.  Keys carry their unit (``_s``, ``_m``, ``_rad``...;
``units`` gives each scalar's: the JSON rule of :mod:`rpo.runtime.outputs.jsonunits`).
A metric whose input columns are absent is ``None``, with the reason in ``unavailable[key]``;
``sources[quantity]`` names the columns each error was computed from.  Rows where a signal is
not finite are ignored (e.g. the outputs of a diverged step).

Error signals (first available source wins):

* attitude ``att``  [rad]: ``ctrl_att_err`` (angle to the controller's desired attitude), else
  the rotation angle of ``ctrl_q_err_{x,y,z,w}``, else of ``meas_q_e_*`` (000's interface frame);
* position ``pos``  [m]: ``|ctrl_pos_err_{x,y,z}|``, else ``|r - goal|`` when ``goal`` is given;
* rate ``rate``     [rad/s]: ``|ctrl_rate_err_*|``, else ``|meas_w_e_*|`` (000 eq. 17);
* velocity ``vel``  [m/s]: ``|ctrl_vel_err_*|``, else ``|v|`` when ``goal`` is given (goal at rest).

Definitions (``t_end`` = last time with finite data; ``T = t_end - t[0]``):

* ``<q>_settling_time_s``: the first time after which the error stays below its threshold until
  ``t_end`` (``att_deg`` = 1 deg, ``pos_m`` = 0.5 m by default).  The crossing is interpolated
  linearly between the last sample above and the first below.  ``t[0]`` if it never exceeds the
  threshold; ``None`` ("not settled") if the last sample is at or above it.
* ``<q>_err_final_*``: the error at ``t_end``.
* ``<q>_err_ss_rms_*``: steady-state error, the RMS of the error over the last 10 %
  (``steady_fraction``) of the run, ``t >= t_end - 0.1 T``.
* ``torque_effort_N_m_s`` = integral of ``|env_tau_applied|`` dt, ``force_effort_N_s`` = integral
  of ``|env_F_applied|`` dt (Euclidean norms, zero-order hold: sample i holds over
  ``[t_i, t_{i+1})``, which is what the step applies when ``record_every = 1``).
* ``delta_v_m_s`` = integral of ``|env_F_applied| / env_m_c`` dt, the same way.
* ``propellant_kg``: final ``m_prop`` (propellant used since t = 0).
* ``wheel_momentum_peak_N_m_s`` = max over time and wheels of ``|h_w_i|``;
  ``wheel_speed_peak_rad_s`` = max of ``|env_wheel_speed_i|`` (relative to the body).
* ``beta_fov_min_m`` / ``beta_ca_min_m2``: minimum of ``env_beta_fov`` / ``env_beta_ca`` (001's
  margins, > 0 = satisfied), with the time of the minimum in ``*_min_t_s``.
* chattering, per command group ``g`` in ``cmd_tau_w`` (wheel torque command, body), ``cmd_F``
  (force command) and ``cmd_tau_thr`` (thruster torque command):
  ``chatter_<g>_tv_per_s`` = total variation ``sum_i sum_axes |u[i+1] - u[i]|`` divided by ``T``
  (N m/s or N/s), and ``chatter_<g>_sign_changes_per_s`` = number of sign changes between
  consecutive samples, summed over the axes, divided by ``T`` (samples with
  ``|u| <= chatter_deadband`` x the group's max |u| are skipped, so noise around zero does not count).
  Both depend on the recording step (``record_every``): they are per recorded sample.

Per-unit actuator use (``per_wheel``, ``per_thruster``: one entry per unit, named by ``wheel`` /
``thruster`` (``"1"``, ``"07"``), from the columns of
what the units delivered, ``wheel_applied_<i>`` [N m], ``env_wheel_speed_<i>`` [rad/s] and
``thr_on_<j>`` [-], the thrust level in [0, 1]; time fractions and integrals weight sample i by
``t_{i+1} - t_i`` as above, so they are exact when ``record_every = 1``):

* per wheel ``i``: ``torque_peak_N_m`` = max ``|wheel_applied_i|``; ``torque_rms_N_m`` = the
  time-weighted RMS of ``wheel_applied_i``; ``speed_peak_rad_s`` = max ``|env_wheel_speed_i|``;
  ``torque_limit_fraction``: fraction of the run with ``|wheel_applied_i| >= (1 - 1e-6)
  wheel_torque_max``; ``speed_limit_fraction``: with ``|env_wheel_speed_i| >= 0.99
  wheel_speed_max`` (a wheel held at its limit hovers within ~0.1 % of it: one step of full torque
  changes its speed by ``T dt / I_w``, and the body rate moves it by ``a_i . omega``).  The limits
  are the parameters ``wheel_torque_max``, ``wheel_speed_max`` (nominal, the same for every wheel);
  without ``params`` the two fractions are ``None``;
* per thruster ``j``: ``on_time_s`` = time with ``thr_on_j > 0``; ``firings`` = number of
  off-to-on transitions between recorded samples (on at the first sample counts as one; the
  final sample, which holds over no time, starts none);
  ``propellant_kg`` = integral of ``thr_on_j F / (Isp g0)`` dt (parameters ``thruster_force``,
  ``thruster_isp``, ``g0``; ``None`` without ``params``); ``propellant_share`` = the unit's
  integral of ``thr_on_j`` over the sum of all units' (``None`` when nothing fired).
* Both are ``None`` (reason in ``unavailable``) when the run flies the ideal actuators
  (``actuators_ideal = 1``: no wheel or thruster exists) or the columns are not recorded.

``errors_at(t, columns, times)`` returns the error components at given times (the latest recorded
sample at or before each time), e.g. 001's Table 2 at 3000/4000/5000 s.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

XYZ = ("x", "y", "z")
QUAT = ("x", "y", "z", "w")

DEFAULT_THRESHOLDS = {
    "att_deg": 1.0,          # attitude settling threshold [deg]
    "pos_m": 0.5,            # position settling threshold [m]
    "steady_fraction": 0.1,  # the steady state is the last 10 % of the run
    "chatter_deadband": 1e-6,  # relative to the group's max |u|
}

#: Unit of each scalar metric (the report and the printed table use these).
UNITS = {
    "t_end_s": "s",
    "att_settling_time_s": "s", "pos_settling_time_s": "s",
    "att_err_final_rad": "rad", "att_err_ss_rms_rad": "rad",
    "pos_err_final_m": "m", "pos_err_ss_rms_m": "m",
    "rate_err_final_rad_s": "rad/s", "rate_err_ss_rms_rad_s": "rad/s",
    "vel_err_final_m_s": "m/s", "vel_err_ss_rms_m_s": "m/s",
    "torque_effort_N_m_s": "N m s", "force_effort_N_s": "N s", "delta_v_m_s": "m/s",
    "propellant_kg": "kg", "wheel_momentum_peak_N_m_s": "N m s", "wheel_speed_peak_rad_s": "rad/s",
    "beta_fov_min_m": "m", "beta_fov_min_t_s": "s", "beta_ca_min_m2": "m^2", "beta_ca_min_t_s": "s",
}
CHATTER_GROUPS = {"cmd_tau_w": "N m", "cmd_F": "N", "cmd_tau_thr": "N m"}
for _g, _u in CHATTER_GROUPS.items():
    UNITS[f"chatter_{_g}_tv_per_s"] = f"{_u}/s"
    UNITS[f"chatter_{_g}_sign_changes_per_s"] = "1/s"

ERROR_QUANTITIES = {"att": "rad", "pos": "m", "rate": "rad/s", "vel": "m/s"}
_SUFFIX = {"att": "rad", "pos": "m", "rate": "rad_s", "vel": "m_s"}
#: error quantity -> its metrics: (final, steady-state RMS[, settling time])
_ERROR_KEYS = {q: (f"{q}_err_final_{_SUFFIX[q]}", f"{q}_err_ss_rms_{_SUFFIX[q]}")
               + ((f"{q}_settling_time_s",) if q in ("att", "pos") else ()) for q in ERROR_QUANTITIES}


def quat_angle(q: np.ndarray) -> np.ndarray:
    """Rotation angle [rad] in [0, pi] of quaternions (rows, scalar last; need not be unit)."""
    q = np.atleast_2d(q)
    return 2.0 * np.arctan2(np.linalg.norm(q[:, :3], axis=1), np.abs(q[:, 3]))


def norm_rows(*components: np.ndarray) -> np.ndarray:
    """Euclidean norm per sample of a vector given as its component series (same unit as they).

    The squares are summed in component order, which is what ``np.linalg.norm(np.column_stack(
    components), axis=1)`` does, to the last bit (tests/test_metrics.py checks it), without
    stacking the block and for a fraction of the calls."""
    total = components[0] * components[0]
    for c in components[1:]:
        total = total + c * c
    return np.sqrt(total)


def stack_columns(series: list[np.ndarray]) -> np.ndarray:
    """The 1-D series as the columns of a C-ordered (samples, len(series)) block: what
    ``np.column_stack`` gives, built in fewer calls."""
    out = np.empty((len(series[0]), len(series)))
    for i, x in enumerate(series):
        out[:, i] = x
    return out


#: (prefix, component names) -> (the named labels, the numbered labels ``prefix_0..n-1``)
_BLOCK_LABELS: dict[tuple[str, tuple[str, ...]], tuple[tuple[str, ...], tuple[str, ...]]] = {}


def _block_labels(columns: Mapping, prefix: str, comps: tuple[str, ...]) -> tuple[str, ...] | None:
    """The labels of the columns ``prefix_<comp>``, or ``prefix_0..n-1`` (a field declared without
    component names), whichever are all present; None if neither are."""
    key = (prefix, comps)
    both = _BLOCK_LABELS.get(key)
    if both is None:
        both = _BLOCK_LABELS[key] = (tuple(f"{prefix}_{c}" for c in comps),
                                     tuple(f"{prefix}_{i}" for i in range(len(comps))))
    for labels in both:
        if all(lbl in columns for lbl in labels):
            return labels
    return None


def _series(columns: Mapping, labels: tuple[str, ...]) -> list[np.ndarray]:
    return [np.asarray(columns[lbl], float) for lbl in labels]


def _quat_angle_of(x: np.ndarray, y: np.ndarray, z: np.ndarray, w: np.ndarray) -> np.ndarray:
    """:func:`quat_angle` [rad] of the quaternion series given by component (the same bits)."""
    return 2.0 * np.arctan2(norm_rows(x, y, z), np.abs(w))


def error_signals(columns: Mapping[str, np.ndarray], goal: ArrayLike | None = None, *,
                  components: bool = True) -> tuple[dict, dict, dict]:
    """(signals, components, sources): each error as a scalar time series (angle or norm), its
    components (or None), and a text naming the columns used; absent quantities are left out.
    ``components=False`` leaves the components dict empty (a campaign's row needs the signals only)."""
    sig, comp, src = {}, {}, {}
    if "ctrl_att_err" in columns:
        sig["att"], src["att"] = np.asarray(columns["ctrl_att_err"], float), "ctrl_att_err"
    labels = _block_labels(columns, "ctrl_q_err", QUAT) if components or "att" not in sig else None
    if labels is not None:
        q = _series(columns, labels)
        if components:
            comp["q"] = stack_columns(q)
        if "att" not in sig:
            sig["att"], src["att"] = _quat_angle_of(*q), "rotation angle of ctrl_q_err"
    if "att" not in sig:
        labels = _block_labels(columns, "meas_q_e", QUAT)
        if labels is not None:
            q = _series(columns, labels)
            sig["att"], src["att"] = _quat_angle_of(*q), "rotation angle of meas_q_e (000 interface frame)"
            if components:
                comp.setdefault("q", stack_columns(q))
    goal = None if goal is None else np.ravel(np.asarray(goal, float))
    for name, prefix, fallback, fb_text in (
            ("pos", "ctrl_pos_err", "r", "r - goal"),
            ("rate", "ctrl_rate_err", "meas_w_e", "meas_w_e (000 eq. 17)"),
            ("vel", "ctrl_vel_err", "v", "v (goal at rest)")):
        labels = _block_labels(columns, prefix, XYZ)
        if labels is not None:
            src[name] = f"|{prefix}|"
            b = _series(columns, labels)
        else:
            labels = _block_labels(columns, fallback, XYZ)
            if labels is None or (fallback in ("r", "v") and goal is None):
                continue
            b = _series(columns, labels)
            if fallback == "r" and goal is not None:  # (goal is given: checked above)
                b = [x - g for x, g in zip(b, np.broadcast_to(goal, (len(b),)), strict=True)]
            src[name] = f"|{fb_text}| (the controller logs no {prefix})"
        if components:
            comp[name] = stack_columns(b)
        sig[name] = norm_rows(*b)
    return sig, comp, src


def settling_time(t: np.ndarray, err: np.ndarray, threshold: float) -> float | None:
    """First time after which ``err < threshold`` until the last finite sample (interpolated);
    ``None`` if the last finite sample is not below it."""
    tf, ef = _finite(t, err)
    return _settling_time_finite(tf, ef, threshold)


def _settling_time_finite(t: np.ndarray, err: np.ndarray, threshold: float) -> float | None:
    """:func:`settling_time` of samples that are all finite."""
    if len(t) == 0 or not err[-1] < threshold:
        return None
    above = np.nonzero(err >= threshold)[0]
    if len(above) == 0:
        return float(t[0])
    k = above[-1]  # last sample at or above; k + 1 is below and stays below
    e0, e1 = err[k], err[k + 1]
    frac = (e0 - threshold) / (e0 - e1) if e0 != e1 else 1.0
    return float(t[k] + frac * (t[k + 1] - t[k]))


def _finite(t, x):
    """(t, x) at the samples (rows of a 2-D x) where x is finite; the arrays themselves when all are."""
    x = np.asarray(x, float)
    t = np.asarray(t, float)
    ok = np.isfinite(x)
    if ok.all():  # the usual case: a run's columns are finite (a diverged step's outputs are not)
        return t, x
    if x.ndim > 1:
        ok = np.all(ok, axis=1)
    return t[ok], x[ok]


def _nanmax(x: np.ndarray) -> float:
    """``np.nanmax(x)`` as a float; the plain maximum when no entry is NaN (the same value, a
    fraction of the time)."""
    return float(x.max() if x.size and not np.isnan(x).any() else np.nanmax(x))


def _rms_tail_finite(t, x, fraction):
    """RMS of the finite samples ``x`` over the last ``fraction`` of their time span ``t``."""
    if len(t) == 0:
        return None
    tail = x[t >= t[-1] - fraction * (t[-1] - t[0])]
    squares = tail ** 2
    return float(np.sqrt(np.add.reduce(squares) / squares.size))  # np.mean's sum and division


def _zoh_integral(t, x, dt: np.ndarray | None = None) -> float | None:
    """Integral of the sample-and-hold signal x (sample i over [t_i, t_{i+1}); NaN samples hold 0);
    ``dt``: ``np.diff(t)`` when the caller has it already."""
    t = np.asarray(t, float)
    if len(t) < 2:
        return None
    x = np.asarray(x, float)[:-1]
    if not np.isfinite(x).all():  # (nan_to_num also maps +-inf to the largest finite floats)
        x = np.nan_to_num(x, nan=0.0)
    return float(np.sum(x * (np.diff(t) if dt is None else dt)))


#: "at the torque limit": |torque| >= (1 - TORQUE_LIMIT_TOL) x limit (the allocation scales onto it)
TORQUE_LIMIT_TOL = 1e-6
#: "at the speed limit": |speed| >= (1 - SPEED_LIMIT_TOL) x limit (see the module docstring)
SPEED_LIMIT_TOL = 0.01


def hold_weights(t: ArrayLike) -> np.ndarray:
    """Sample-and-hold weights [s]: sample i holds over ``[t_i, t_{i+1})``, the last sample over 0."""
    t = np.asarray(t, float)
    w = np.zeros(len(t))
    np.subtract(t[1:], t[:-1], out=w[:-1])  # np.diff(t), with the final 0 in place
    return w


def time_fraction(t: ArrayLike, flag: ArrayLike) -> float | None:
    """Fraction of the run ``[t_0, t_end]`` during which the held boolean ``flag`` is true."""
    w = hold_weights(t)
    return held_fraction(w, float(np.sum(w)), flag)


def held_fraction(w: np.ndarray, total: float, flag: ArrayLike) -> float | None:
    """:func:`time_fraction` from the run's :func:`hold_weights` ``w`` [s] and their sum ``total``
    [s] (computed once for all the flags of a run)."""
    return None if total <= 0 else float((w * np.asarray(flag, bool)).sum()) / total


def unit_columns(columns: Mapping[str, Any], prefix: str) -> list[tuple[str, np.ndarray]]:
    """``[(unit, column)]`` of the columns ``<prefix>_<digits>`` (``wheel_applied_1``,
    ``thr_on_07``), in unit order."""
    return [(u, np.asarray(columns[k], float)) for u, k in _unit_labels(tuple(columns), prefix)]


#: (the columns' labels, prefix) -> [(unit, label)]: a campaign's runs all have the same labels
_UNIT_LABELS: dict[tuple[tuple[str, ...], str], list[tuple[str, str]]] = {}


def _unit_labels(labels: tuple[str, ...], prefix: str) -> list[tuple[str, str]]:
    key = (labels, prefix)
    hit = _UNIT_LABELS.get(key)
    if hit is None:
        found = [(k[len(prefix) + 1:], k) for k in labels
                 if k.startswith(prefix + "_") and k[len(prefix) + 1:].isdigit()]
        hit = sorted(found, key=lambda x: int(x[0]))
        if len(_UNIT_LABELS) >= 64:  # a bounded memo (runs with other labels: another model, a test)
            _UNIT_LABELS.clear()
        _UNIT_LABELS[key] = hit
    return hit


def param(params: Mapping[str, Any] | None, name: str) -> float | None:
    """A scalar parameter [SI] from a run's parameter mapping (arrays of one value), or None."""
    if params is None or name not in params:
        return None
    return float(np.asarray(params[name], float).reshape(-1)[0])


def unit_use(t: ArrayLike, columns: Mapping[str, Any], params: Mapping[str, Any] | None = None
             ) -> tuple[list[dict] | None, list[dict] | None, dict[str, str]]:
    """(per_wheel, per_thruster, unavailable): the per-unit use of the module docstring."""
    t = np.asarray(t, float)
    w = hold_weights(t)
    span = float(np.sum(w))
    unavailable: dict[str, str] = {}
    if param(params, "actuators_ideal") == 1.0:
        why = "the run flies the ideal force/torque actuators (actuators_ideal = 1): no wheel or thruster"
        return None, None, {"per_wheel": why, "per_thruster": why}

    def fin(x):
        return np.nan_to_num(x, nan=0.0, posinf=0.0, neginf=0.0)

    wheels: list[dict] | None = None
    applied = unit_columns(columns, "wheel_applied")
    speeds = dict(unit_columns(columns, "env_wheel_speed"))
    if not applied:
        unavailable["per_wheel"] = "columns wheel_applied_* not recorded"
    else:
        t_max, s_max = param(params, "wheel_torque_max"), param(params, "wheel_speed_max")
        wheels = []
        for u, tq in applied:
            sp_ = speeds.get(u)
            a = np.abs(tq)
            e: dict[str, Any] = {
                "wheel": u,
                "torque_peak_N_m": float(np.nanmax(a)) if np.isfinite(a).any() else None,
                "torque_rms_N_m": float(np.sqrt(np.sum(w * fin(tq) ** 2) / span)) if span > 0 else None,
                "speed_peak_rad_s": (float(np.nanmax(np.abs(sp_))) if sp_ is not None and np.isfinite(sp_).any()
                                     else None),
                "torque_limit_fraction": None if t_max is None else
                time_fraction(t, a >= (1 - TORQUE_LIMIT_TOL) * t_max),
                "speed_limit_fraction": None if s_max is None or sp_ is None else
                time_fraction(t, np.abs(sp_) >= (1 - SPEED_LIMIT_TOL) * s_max),
            }
            wheels.append(e)

    thrusters: list[dict] | None = None
    on = unit_columns(columns, "thr_on")
    if not on:
        unavailable["per_thruster"] = "columns thr_on_* not recorded"
    else:
        F, isp, g0 = (param(params, k) for k in ("thruster_force", "thruster_isp", "g0"))
        level = {u: fin(x) for u, x in on}
        used = {u: float(np.sum(w * x)) for u, x in level.items()}  # s at full thrust
        total = sum(used.values())
        thrusters = []
        for u, x in level.items():
            firing = x > 0
            # a firing starts at a sample that holds over time (the final sample holds over none)
            rising = firing & (w > 0) & ~np.concatenate([[False], firing[:-1]])
            starts = int(np.count_nonzero(rising))
            thrusters.append({
                "thruster": u,
                "on_time_s": float(np.sum(w * firing)),
                "firings": starts,
                "propellant_kg": None if None in (F, isp, g0) else used[u] * F / (isp * g0),  # type: ignore[operator]
                "propellant_share": used[u] / total if total > 0 else None,
            })
    return wheels, thrusters, unavailable


def chatter(t: np.ndarray, u: np.ndarray, deadband: float = 0.0) -> tuple[float, float]:
    """(total variation per second, sign changes per second) of the command block ``u`` (rows =
    samples, columns = axes), summed over axes; see the module docstring."""
    return _chatter_axes(t, np.atleast_2d(np.asarray(u, float).T), deadband)


def _chatter_axes(t: ArrayLike, u_axes: np.ndarray, deadband: float) -> tuple[float, float]:
    """:func:`chatter` of the command given axis by axis (rows = axes, columns = samples)."""
    t = np.asarray(t, float)
    ok = np.isfinite(u_axes)
    if not ok.all():  # drop the samples where any axis is not finite
        finite = np.all(ok, axis=0)
        t, u_axes = t[finite], u_axes[:, finite]
    span = t[-1] - t[0] if len(t) > 1 else 0.0
    if span <= 0:
        return 0.0, 0.0
    # summed in the order of the (samples, axes) block: sample after sample, the axes of each
    u = np.ascontiguousarray(u_axes.T)
    tv = float(np.abs(u[1:] - u[:-1]).sum())  # (u[1:] - u[:-1] is np.diff(u, axis=0))
    # axis after axis: the samples above the deadband, their signs, and a sign change wherever two
    # consecutive kept samples of the same axis differ in sign
    mag = np.abs(u_axes)
    tol = deadband * float(mag.max()) if u_axes.size else 0.0
    kept = mag > tol
    kept_axis = kept.nonzero()[0]
    s = np.sign(u_axes[kept])
    changes = int(np.count_nonzero((s[1:] != s[:-1]) & (kept_axis[1:] == kept_axis[:-1])))
    return tv / span, changes / span


def compute_metrics(t: ArrayLike, columns: Mapping[str, np.ndarray], thresholds: Mapping[str, float] | None = None, *,
                    goal: ArrayLike | None = None, error_times: Iterable[float] = (),
                    params: Mapping[str, Any] | None = None, per_unit: bool = True,
                    signals: tuple[dict, dict, dict] | None = None) -> dict[str, Any]:
    """All metrics of one run (see the module docstring); ``goal`` is the goal position [m] used
    when the controller logs no ``ctrl_pos_err``; ``error_times`` adds ``errors_at``; ``params``
    (the run's parameters by name, SI) give the actuator limits of the per-unit use;
    ``per_unit=False`` leaves ``per_wheel`` / ``per_thruster`` None (a campaign's summary keeps
    the scalar metrics only, and the per-unit lists are a fifth of the time)."""
    th = {**DEFAULT_THRESHOLDS, **(thresholds or {})}
    t = np.asarray(t, float)
    m: dict = dict.fromkeys(UNITS)
    unavailable: dict[str, str] = {}
    # ``signals``: error_signals(columns, goal) when the caller has them already (a campaign's row)
    sig, _comp, sources = error_signals(columns, goal, components=False) if signals is None else signals
    # the run's end (the last state); error values are taken at the last sample where they are
    # finite (the controller's outputs have no row for the final state)
    m["t_end_s"] = float(t[-1]) if len(t) else None

    for q, keys in _ERROR_KEYS.items():
        if q not in sig:
            for k in keys:
                unavailable[k] = f"no {q} error columns (ctrl_{q}_err*) in this run"
            continue
        tf, xf = _finite(t, sig[q])
        if len(tf) == 0:
            continue
        m[keys[0]] = float(xf[-1])
        m[keys[1]] = _rms_tail_finite(tf, xf, th["steady_fraction"])
        if q == "att":
            m["att_settling_time_s"] = _settling_time_finite(tf, xf, np.radians(th["att_deg"]))
        elif q == "pos":
            m["pos_settling_time_s"] = _settling_time_finite(tf, xf, th["pos_m"])

    def need(key: str, prefix: str, comps: tuple[str, ...] = ()) -> list[np.ndarray] | None:
        """The series of the block ``prefix_<comp>`` (``comps``) or the column ``prefix``; None,
        with the reason in ``unavailable[key]``, when not recorded."""
        if comps:
            labels = _block_labels(columns, prefix, comps)
            if labels is not None:
                return _series(columns, labels)
        elif prefix in columns:
            return [np.asarray(columns[prefix], float)]
        unavailable[key] = f"column(s) {prefix}{'_*' if comps else ''} not recorded"
        return None

    dt = np.diff(t)
    if (b := need("torque_effort_N_m_s", "env_tau_applied", XYZ)) is not None:
        m["torque_effort_N_m_s"] = _zoh_integral(t, norm_rows(*b), dt)
    force = None
    if (b := need("force_effort_N_s", "env_F_applied", XYZ)) is not None:
        force = norm_rows(*b)  # |env_F_applied| [N]
        m["force_effort_N_s"] = _zoh_integral(t, force, dt)
    if force is None:
        unavailable["delta_v_m_s"] = unavailable["force_effort_N_s"]
    elif (b := need("delta_v_m_s", "env_m_c")) is not None:
        m["delta_v_m_s"] = _zoh_integral(t, force / b[0], dt)
    if (b := need("propellant_kg", "m_prop")) is not None:
        _, mp = _finite(t, b[0])
        m["propellant_kg"] = float(mp[-1]) if len(mp) else None
    for key, prefix in (("wheel_momentum_peak_N_m_s", "h_w"), ("wheel_speed_peak_rad_s", "env_wheel_speed")):
        if (b := need(key, prefix, ("1", "2", "3", "4"))) is not None:
            m[key] = _nanmax(np.abs(np.array(b)))  # over time and wheels
    for col, key in (("env_beta_fov", "beta_fov_min_m"), ("env_beta_ca", "beta_ca_min_m2")):
        if (b := need(key, col)) is not None:
            tf, x = _finite(t, b[0])
            if len(x):
                i = int(np.argmin(x))
                m[key], m[key.rsplit("_", 1)[0] + "_t_s"] = float(x[i]), float(tf[i])
    for g in CHATTER_GROUPS:
        if (b := need(f"chatter_{g}_tv_per_s", g, XYZ)) is not None:
            tv, sc = _chatter_axes(t, np.array(b), th["chatter_deadband"])
            m[f"chatter_{g}_tv_per_s"], m[f"chatter_{g}_sign_changes_per_s"] = tv, sc
        else:
            unavailable[f"chatter_{g}_sign_changes_per_s"] = unavailable[f"chatter_{g}_tv_per_s"]

    if per_unit:
        m["per_wheel"], m["per_thruster"], why = unit_use(t, columns, params)
        unavailable.update(why)
    else:
        m["per_wheel"] = m["per_thruster"] = None

    settled = [m[f"{q}_settling_time_s"] for q in ("att", "pos") if q in sig]
    m["converged"] = bool(settled) and all(s is not None for s in settled)
    m["thresholds"] = dict(th)
    m["sources"] = sources
    m["unavailable"] = unavailable
    m["units"] = dict(UNITS)
    if error_times:
        m["errors_at"] = errors_at(t, columns, error_times, goal=goal)
    return m


def errors_at(t: ArrayLike, columns: Mapping[str, np.ndarray], times: Iterable[float],
              goal: ArrayLike | None = None) -> list[dict[str, Any]]:
    """Error components at each of ``times`` [s]: the latest finite sample at or before the time.

    Each entry: ``t`` (requested), ``t_sample`` (used), ``att_rad``, ``q`` (``[x, y, z, w]`` of the
    error quaternion), ``pos_m``, ``rate_rad_s``, ``vel_m_s`` (components, the same sources as
    :func:`compute_metrics`); ``None`` where absent or when the run ended before that time; and
    ``diag``: every ``ctrl_*`` column at that sample (a paper's table may need a logged variable
    other than the standard errors, e.g. 001's q_S/T).
    """
    t = np.asarray(t, float)
    sig, comp, _ = error_signals(columns, goal)
    out = []
    for tq in times:
        entry: dict[str, Any] = {"t": float(tq), "t_sample": None, "att_rad": None, "q": None, "pos_m": None,
                                 "rate_rad_s": None, "vel_m_s": None}
        for key, series in (("att_rad", sig.get("att")), ("q", comp.get("q")), ("pos_m", comp.get("pos")),
                            ("rate_rad_s", comp.get("rate")), ("vel_m_s", comp.get("vel"))):
            if series is None:
                continue
            tf, xf = _finite(t, series)
            eps = 1e-9 * max(1.0, abs(tq))
            i = int(np.searchsorted(tf, tq + eps, side="right")) - 1
            if i < 0 or tq > tf[-1] + _gap(tf) + eps:  # before the start, or after the run ended
                continue
            entry[key] = float(xf[i]) if xf.ndim == 1 else [float(v) for v in xf[i]]
            entry["t_sample"] = float(tf[i])
        if entry["t_sample"] is not None:
            row = int(np.flatnonzero(t == entry["t_sample"])[0])
            entry["diag"] = {k: float(np.asarray(v)[row]) for k, v in columns.items() if k.startswith("ctrl_")}
        out.append(entry)
    return out


def _gap(tf: np.ndarray) -> float:
    """One sample interval (a query up to one step after the last finite sample still uses it)."""
    return float(tf[-1] - tf[-2]) if len(tf) > 1 else 0.0


def result_columns(result: Any) -> dict[str, np.ndarray]:
    """The columns of a :class:`~rpo.runtime.run.result.RunResult` (or a loaded npz) by label."""
    cols = {lbl: result.z[:, i] for i, lbl in enumerate(result.z_labels)}
    cols.update({lbl: result.y[:, i] for i, lbl in enumerate(result.y_labels)})
    return cols


def format_table(m: dict, ideal_actuators: bool = False) -> str:
    """A short human table of the main metrics (degrees); ``ideal_actuators``: no wheel line."""
    def f(v, scale=1.0, fmt=".4g", none="-"):
        return none if v is None else format(v * scale, fmt)

    deg = 180.0 / np.pi
    settle = lambda v: "not settled" if v is None else f"settled at {v:.4g} s"  # noqa: E731
    rows = [
        ("attitude", f"{settle(m['att_settling_time_s']) if m['att_err_final_rad'] is not None else '-'}"
                     f" (< {m['thresholds']['att_deg']:g} deg), final {f(m['att_err_final_rad'], deg)} deg, "
                     f"steady RMS {f(m['att_err_ss_rms_rad'], deg)} deg"),
        ("position", f"{settle(m['pos_settling_time_s']) if m['pos_err_final_m'] is not None else '-'}"
                     f" (< {m['thresholds']['pos_m']:g} m), final {f(m['pos_err_final_m'])} m, "
                     f"steady RMS {f(m['pos_err_ss_rms_m'])} m"),
        ("rate, velocity", f"final {f(m['rate_err_final_rad_s'], deg)} deg/s, {f(m['vel_err_final_m_s'])} m/s"),
        ("effort", f"torque {f(m['torque_effort_N_m_s'])} N m s, force {f(m['force_effort_N_s'])} N s, "
                   f"delta-v {f(m['delta_v_m_s'])} m/s, propellant {f(m['propellant_kg'])} kg"),
        ("wheels", "none: ideal force and torque actuators" if ideal_actuators else  # no wheel exists
                   f"peak |h_w| {f(m['wheel_momentum_peak_N_m_s'])} N m s, peak speed "
                   f"{f(m['wheel_speed_peak_rad_s'], 60 / (2 * np.pi))} rpm"),
        ("constraints", f"min beta_FOV {f(m['beta_fov_min_m'])} m, min beta_CA {f(m['beta_ca_min_m2'])} m^2"),
        ("chattering", ", ".join(f"{g} {f(m[f'chatter_{g}_tv_per_s'])} {CHATTER_GROUPS[g]}/s, "
                                 f"{f(m[f'chatter_{g}_sign_changes_per_s'])} sign changes/s" for g in CHATTER_GROUPS)),
    ]
    rpm = 60 / (2 * np.pi)
    pct = lambda v: "-" if v is None else f"{100 * v:.3g} %"  # noqa: E731
    for e in m.get("per_wheel") or []:
        rows.append((f"wheel {e['wheel']}", f"torque peak {f(e['torque_peak_N_m'])} N m, RMS {f(e['torque_rms_N_m'])} "
                     f"N m; speed peak {f(e['speed_peak_rad_s'], rpm)} rpm; at the torque limit "
                     f"{pct(e['torque_limit_fraction'])}, at the speed limit {pct(e['speed_limit_fraction'])}"))
    if m.get("per_thruster"):
        thr = m["per_thruster"]
        rows.append(("thrusters", f"{sum(e['firings'] for e in thr)} firings, {f(sum(e['on_time_s'] for e in thr))} s "
                     "on in all; per unit on-time s/firings/propellant share: "
                     + ", ".join(f"{e['thruster']} {f(e['on_time_s'], fmt='.3g')}/{e['firings']}/"
                                 f"{pct(e['propellant_share'])}" for e in thr)))
    lines = [f"  {k:<15s} {v}" for k, v in rows]
    missing = [q for q in ERROR_QUANTITIES if f"{q}_err_final_{_SUFFIX[q]}" in m["unavailable"]]
    if missing:
        lines.append(f"  (not logged by this controller: {', '.join(missing)} errors)")
    return "\n".join(lines)
