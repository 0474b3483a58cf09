"""Which columns of a run are written: channel names and glob patterns over the layouts.

A run records the state ``z_<controller>`` and the outputs ``y_<controller>`` (layouts of
``generated/manifest.json``; ``rpo info`` lists them).  A *channel* entry of the scenario's
``[output] channels`` is

* a layout field name (``"r"``, ``"env_wheel_speed"``): all its columns (``r_x``, ``r_y``, ``r_z``);
* a column label (``"r_x"``, ``"meas_q_e_w"``): that column;
* a glob pattern (``fnmatch``, case-sensitive: ``"ctrl_*"``, ``"env_M_gg_?"``, ``"thr_*"``) over
  both the field names and the labels;
* ``"default"``: :data:`DEFAULT_CHANNELS`.

An entry that matches nothing is an error naming the close matches.  Columns are written in
layout order (z first, then y) whatever the order of the entries; ``t`` is always written.

This module is pure Python (no NumPy), so the scenario schema can use it.
"""

from __future__ import annotations

import difflib
import fnmatch
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rpo.runtime.model.manifest import LayoutField

#: What the figures and the metrics use, plus the physical state (attitudes, rates, wheel
#: momenta, relative position and velocity, propellant).  Fields a controller does not log are
#: skipped (``ctrl_*`` differs per controller).  Left out by default: the delay line and the PWPF
#: filter states (``wheel_cmd_1..4``, ``pwpf_*``), the controller's own states ``xc_*`` (logged
#: again as ``ctrl_*`` diagnostics where they matter), the raw measurements ``meas_*`` other than the
#: errors, and the environment's internals (gravity-gradient, magnetic, drag terms).
DEFAULT_CHANNELS: tuple[str, ...] = (
    "q_c", "w_c", "h_w", "q_t", "w_t", "r", "v", "m_prop",
    "meas_q_e", "meas_w_e", "cmd_*", "wheel_applied", "thr_duty", "thr_on",
    "env_m_c", "env_wheel_speed", "env_tau_applied", "env_F_applied", "env_beta_fov", "env_beta_ca",
    "ctrl_*",
)

DEFAULT_TOKEN = "default"


class ChannelError(ValueError):
    """An entry of ``[output] channels`` that matches no column; ``entry`` is the entry."""

    def __init__(self, entry: str, message: str):
        super().__init__(message)
        self.entry = entry


@dataclass(frozen=True)
class Selection:
    """The columns chosen: labels of z and of y, in layout order."""

    z: tuple[str, ...]
    y: tuple[str, ...]

    @property
    def labels(self) -> tuple[str, ...]:
        return self.z + self.y


def _is_pattern(entry: str) -> bool:
    return any(c in entry for c in "*?[")


def close_matches(entry: str, candidates: Sequence[str], n: int = 4) -> list[str]:
    """The candidates nearest to ``entry`` (a glob's literal part is compared for a pattern)."""
    key = entry.replace("*", "").replace("?", "")
    found = difflib.get_close_matches(entry, candidates, n=n, cutoff=0.6)
    if key and len(found) < n:
        found += [c for c in candidates if key in c and c not in found][: n - len(found)]
    return found


def select(entries: Iterable[str] | None, z_layout: Iterable[LayoutField], y_layout: Iterable[LayoutField], *,
           where: str = "z/y", strict: bool | None = None) -> Selection:
    """The columns of ``entries`` (None: :data:`DEFAULT_CHANNELS`).  With ``strict`` (default: when
    ``entries`` are given) an entry that matches nothing raises :class:`ChannelError` (``where``
    names the layouts in the message); otherwise it is skipped, as are the entries of the default
    set that a controller does not log."""
    strict = entries is not None if strict is None else strict
    explicit = list(DEFAULT_CHANNELS if entries is None else entries)
    chosen: set[str] = set()
    z_fields, y_fields = tuple(z_layout), tuple(y_layout)
    names = [f.name for f in (*z_fields, *y_fields)]
    labels = [lbl for f in (*z_fields, *y_fields) for lbl in f.labels]

    def match(entry: str) -> set[str]:
        out: set[str] = set()
        for f in (*z_fields, *y_fields):
            if fnmatch.fnmatchcase(f.name, entry):
                out.update(f.labels)
            else:
                out.update(lbl for lbl in f.labels if fnmatch.fnmatchcase(lbl, entry))
        return out

    for entry in explicit:
        if entry == DEFAULT_TOKEN and DEFAULT_TOKEN not in names:
            for d in DEFAULT_CHANNELS:
                chosen |= match(d)
            continue
        got = match(entry)
        if not got and strict:
            near = close_matches(entry, sorted(set(names)) + labels)
            hint = f"close matches: {', '.join(near)}" if near else "no close match"
            kind = "pattern" if _is_pattern(entry) else "channel"
            raise ChannelError(entry, f"unknown {kind} {entry!r}: matches no field or column of {where} ({hint}; "
                                      f"`rpo info` lists the layouts; allowed: field names, column labels, glob "
                                      f"patterns, or \"{DEFAULT_TOKEN}\")")
        chosen |= got
    z = tuple(lbl for f in z_fields for lbl in f.labels if lbl in chosen)
    y = tuple(lbl for f in y_fields for lbl in f.labels if lbl in chosen)
    return Selection(z, y)
