"""The summary a linearisation ends with: stable or not, the slowest mode, the least damped one.

The step map is discrete: a mode with eigenvalue lambda grows when |lambda| > 1.  Its continuous-time
equivalent s = ln(lambda)/dt gives the time constant tau = -1/Re(s) [s] (negative: growing) and, for
a complex mode, the damping ratio zeta = -Re(s)/|s| and the period 2 pi/|Im(s)| [s].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Protocol

#: The states of the target's own motion (its orbit in ECI, its attitude and rate): no law acts on them,
#: so their modes (e.g. the tidal stretching of the orbit in ECI, s = sqrt(2 mu / r^3)) are listed apart
#: and do not decide whether the closed loop is stable
TARGET_STATES = ("r_T_", "v_T_", "dth_t_", "w_t_")

#: |lambda| within this of 1 is marginal (a conserved quantity or an integrator of the plant, e.g. the
#: target's free attitude or the mass used, which no law acts on)
MARGIN = 1e-9


class _Mode(Protocol):
    lam: complex
    s: complex | None
    block: str
    state: str

    @property
    def tau(self) -> float | None: ...

    @property
    def zeta(self) -> float | None: ...


def _where(m: _Mode) -> str:
    return f"{m.block}: {m.state}"


def _describe(m: _Mode) -> dict[str, Any]:
    s = m.s
    period = None if s is None or s.imag == 0 else 2 * math.pi / abs(s.imag)
    return {"abs_lambda": abs(m.lam), "tau_s": m.tau, "zeta": m.zeta, "period_s": period, "block": m.block,
            "state": m.state}


def stability_summary(modes: Sequence[_Mode]) -> dict[str, Any]:
    """Over the closed loop's modes (the target's own motion apart, :data:`TARGET_STATES`): ``stable``
    (every |lambda| < 1 - MARGIN), the counts of unstable and marginal modes, and the
    fastest-growing, slowest stable and least-damped modes (None where there is none); SI units."""
    every = [m for m in modes if m.s is not None]
    live = [m for m in every if not m.state.startswith(TARGET_STATES)]
    target = [m for m in every if m.state.startswith(TARGET_STATES)]
    unstable = [m for m in live if abs(m.lam) > 1 + MARGIN]
    marginal = [m for m in live if abs(abs(m.lam) - 1) <= MARGIN]
    stable = [m for m in live if abs(m.lam) < 1 - MARGIN]
    oscillating = [m for m in stable + unstable if m.zeta is not None]
    return {
        "stable": not unstable and not marginal,
        "verdict": "unstable" if unstable else "marginally stable" if marginal else "stable",
        "margin": MARGIN,
        "unstable_modes": len(unstable),
        "marginal_modes": len(marginal),
        "fastest_growing": _describe(max(unstable, key=lambda m: abs(m.lam))) if unstable else None,
        "slowest_stable": _describe(max(stable, key=lambda m: abs(m.lam))) if stable else None,
        "least_damped": _describe(min(oscillating, key=lambda m: m.zeta or 0.0)) if oscillating else None,
        "marginal_blocks": sorted({_where(m) for m in marginal}),
        "target_modes": len(target),
        "target_growing": _describe(max(target, key=lambda m: abs(m.lam))) if target and
        max(abs(m.lam) for m in target) > 1 + MARGIN else None,
    }


def summary_lines(sm: dict[str, Any]) -> list[str]:
    """The summary as ``rpo linearize`` prints it (last lines of its report)."""
    def mode(d: dict[str, Any]) -> str:
        tau = "inf" if d["tau_s"] is None else f"{d['tau_s']:.4g} s"
        return f"|lambda| = {d['abs_lambda']:.9f}, tau = {tau} ({d['block']}: {d['state']})"

    n_u, n_m = sm["unstable_modes"], sm["marginal_modes"]
    head = {"unstable": f"UNSTABLE: {n_u} mode{'s' * (n_u != 1)} with |lambda| > 1",
            "marginally stable": f"marginally stable: no |lambda| > 1, {n_m} within {sm['margin']:g} of 1",
            "stable": "stable: every |lambda| < 1"}[sm["verdict"]]
    out = [f"  summary     closed loop {head} (tolerance {sm['margin']:g})"]
    if sm["fastest_growing"] is not None:
        out.append(f"              fastest growing: {mode(sm['fastest_growing'])}")
    if sm["slowest_stable"] is not None:
        out.append(f"              slowest decaying: {mode(sm['slowest_stable'])}")
    if sm["least_damped"] is not None:
        d = sm["least_damped"]
        out.append(f"              least damped: zeta = {d['zeta']:.3g}, period {d['period_s']:.4g} s, {mode(d)}")
    if sm["target_modes"]:
        grow = sm["target_growing"]
        out.append(f"              apart: {sm['target_modes']} modes of the target's own motion (orbit, attitude), "
                   "which no law acts on" + (f"; largest {mode(grow)}" if grow is not None else ""))
    if n_m:
        out.append(f"              marginal ({n_m}, |lambda| = 1 within {sm['margin']:g}): "
                   + "; ".join(sm["marginal_blocks"][:4]) + (" ..." if len(sm["marginal_blocks"]) > 4 else ""))
    return out
