"""The reproduction report's tables and its markdown: the papers' published values next to rpo's runs, the
comparison of the controllers, the fault study."""

from __future__ import annotations

import math

import numpy as np

from rpo.runtime.jobs.reproduction_runs import FAULT_CASES, RAD2DEG, Notes, Paper, PlannedRun, RunList
from rpo.runtime.scenario.reproduction import Claim

# --------------------------------------------------------------------------- rendering

_CONVERT = {("rad", "deg"): RAD2DEG, ("rad/s", "deg/s"): RAD2DEG, ("rad/s", "rpm"): 60 / (2 * math.pi)}


def _num(v: float | None, fmt: str = ".4g") -> str:
    return "-" if v is None else format(v, fmt)


def metric_cell(r: PlannedRun | None, metric: str, unit: str | None = None, with_unit: bool = False) -> str:
    """A run's metric as table text: the value, or why there is none."""
    from rpo.runtime.outputs.metrics import UNITS

    if r is None:
        return "not run (no run declared)"
    if r.status in ("not run", "error", "refused"):
        return f"{r.status} ({r.reason})" if r.status == "not run" else f"{r.status} (see run list)"
    m = r.metrics or {}
    if metric not in m:
        return f"unknown metric {metric}"
    v = m[metric]
    if v is None:
        if metric in m.get("unavailable", {}):
            return "n/a (not logged)"
        return "not settled" if metric.endswith("settling_time_s") else "-"
    if isinstance(v, bool):
        text = "yes" if v else "no"
    else:
        base = UNITS.get(metric)
        scale = _CONVERT.get((base or "", unit), 1.0) if unit else 1.0
        text = _num(float(v) * scale) + (f" {unit or base}" if with_unit and (unit or base) else "")
    return text + (" (diverged)" if r.status == "diverged" else "")


def _find(runs: list[PlannedRun], paper: str, case: str, plant: str, controller: str | None) -> PlannedRun | None:
    cands = [r for r in runs if r.paper == paper and r.case == case and r.plant == plant]
    if controller:
        cands = [r for r in cands if (r.controller_used or r.controller) == controller]
    return cands[0] if cands else None


def _published(c: Claim) -> str:
    if c.published_text:
        return c.published_text
    return "-" if c.published is None else f"{c.published:g}" + (f" {c.unit}" if c.unit else "")


def paper_rows(runs: list[PlannedRun], pid: str, paper: Paper) -> list[dict]:
    rows = []
    for c in paper.claim:
        cells: dict[str, str | None] = {}
        for plant in ("paper", "full"):
            r = _find(runs, pid, c.case, plant, paper.controller)
            cells[plant] = metric_cell(r, c.metric, c.unit, with_unit=True)
            cells[f"{plant}_label"] = None if r is None else r.label
        rows.append({"case": c.case, "what": c.what, "metric": c.metric, "published": _published(c),
                     "published_value": c.published, "ours_paper": cells["paper"], "ours_full": cells["full"],
                     "run_paper": cells["paper_label"], "run_full": cells["full_label"]})
    return rows


def _vec(v, scale=1.0) -> str:
    return "-" if v is None else "(" + ", ".join(f"{x * scale:.3g}" for x in v) + ")"


def table2_rows(runs: list[PlannedRun], pid: str, paper: Paper) -> list[dict]:
    t2 = paper.table2
    if t2 is None:
        return []
    rows = []
    ours = {}
    for plant in ("paper", "full"):
        r = _find(runs, pid, t2.case, plant, paper.controller)
        at = {}
        if r is not None and r.metrics:
            at = {round(e["t"], 6): e for e in r.metrics.get("errors_at", [])}
        ours[plant] = (r, at)

    def cell(plant, t, key, scale=1.0):
        r, at = ours[plant]
        if r is None:
            return "not run (no run declared)"
        if r.status in ("not run", "error", "refused"):
            return f"{r.status} ({r.reason})"
        e = at.get(round(t, 6))
        if e is None:
            return "n/a (time not recorded)"
        v = e.get(key)
        if v is None:
            return "n/a (not logged or run ended)"
        if key == "q" and t2.q_columns:  # the paper's difference of quaternions, sign-aligned to the reference
            d = e.get("diag") or {}
            if not all(c in d for c in t2.q_columns):
                return "n/a (not logged)"
            q = np.array([d[c] for c in t2.q_columns])
            ref = np.array(t2.q_reference)
            q = q if q @ ref >= 0 else -q
            return _vec(list(q - ref), scale)
        if key == "q":  # ours as (scalar, x, y, z), the published order
            v = [v[3], v[0], v[1], v[2]]
        return _vec(v, scale)

    q_name = "attitude quaternion " + ("q - q_D " if t2.q_columns else "") + "(scalar, x, y, z)"
    for name, key, pub, scale, unit in ((q_name, "q", t2.q, 1.0, "-"),
                                        ("position", "pos_m", t2.pos, 1.0, "m"),
                                        ("angular rate", "rate_rad_s", t2.rate_deg_s, RAD2DEG, "deg/s"),
                                        ("velocity", "vel_m_s", t2.vel, 1.0, "m/s")):
        for i, t in enumerate(t2.times):
            rows.append({"quantity": f"{name} [{unit}]", "t": t, "published": _vec(pub[i] if i < len(pub) else None),
                         "ours_paper": cell("paper", t, key, scale), "ours_full": cell("full", t, key, scale)})
    for name, metric, unit in (("min beta_FOV", "beta_fov_min_m", "m"), ("min beta_CA", "beta_ca_min_m2", "m^2")):
        rows.append({"quantity": f"{name} [{unit}]", "t": None, "published": t2.constraints_text,
                     "ours_paper": metric_cell(ours["paper"][0], metric),
                     "ours_full": metric_cell(ours["full"][0], metric)})
    return rows


COMPARISON_COLUMNS = (("converged", None, "converges"), ("att_settling_time_s", None, "att. settling [s]"),
                      ("pos_settling_time_s", None, "pos. settling [s]"), ("propellant_kg", None, "propellant [kg]"),
                      ("wheel_momentum_peak_N_m_s", None, "peak wheel momentum [N m s]"),
                      ("beta_fov_min_m", None, "min beta_FOV [m]"), ("beta_ca_min_m2", None, "min beta_CA [m^2]"))


def comparison_rows(runs: list[PlannedRun]) -> list[dict]:
    rows = []
    for r in runs:
        if not r.compare:
            continue
        cases = r.extra.get("comparison_cases") or [r.case]
        for case in cases:
            row = {"case": case, "plant": r.plant, "controller": r.controller_used or r.controller, "run": r.label,
                   "status": r.status if r.status != "not run" else f"not run ({r.reason})"}
            for metric, unit, _head in COMPARISON_COLUMNS:
                row[metric] = metric_cell(r, metric, unit) if r.status in ("ok", "diverged") else "-"
            rows.append(row)
    rows.sort(key=lambda x: (x["case"], x["plant"] != "paper", x["plant"], x["controller"] or ""))
    return rows


def _md_table(head: list[str], rows: list[list[str]]) -> str:
    esc = [[str(c).replace("|", "\\|").replace("\n", " ") for c in row] for row in rows]
    lines = ["| " + " | ".join(head) + " |", "| " + " | ".join("---" for _ in head) + " |"]
    lines += ["| " + " | ".join(row) + " |" for row in esc]
    return "\n".join(lines)


def build_tables(runs: list[PlannedRun], run_list: RunList) -> dict:
    papers = {}
    for pid, paper in run_list.paper.items():
        papers[pid] = {"title": paper.title, "controller": paper.controller, "claims": paper_rows(runs, pid, paper),
                       "table2": table2_rows(runs, pid, paper) if paper.table2 else None}
    return {"papers": papers, "comparison": comparison_rows(runs), "faults": fault_rows(runs)}


def _fault_cell(r: PlannedRun | None) -> str:
    """Attitude and position settling (or final errors), the propellant; or why there is none."""
    if r is None:
        return "-"
    if r.status not in ("ok", "diverged"):
        return r.status
    m = r.metrics or {}

    def goal(q: str, unit: str, scale: float) -> str:
        st, fin = m.get(f"{q}_settling_time_s"), m.get(f"{q}_err_final_{'rad' if q == 'att' else 'm'}")
        if fin is None:
            return f"{q} n/a"
        return f"{q} {st:.0f} s" if st is not None else f"{q} off {fin * scale:.3g} {unit}"

    text = f"{goal('att', 'deg', RAD2DEG)}, {goal('pos', 'm', 1.0)}, {_num(m.get('propellant_kg'), '.3g')} kg"
    return ("DIVERGED; " + text) if r.status == "diverged" else text


def fault_rows(runs: list[PlannedRun]) -> list[dict]:
    """The fault study: one row per (scenario, plant, controller), one cell per case."""
    rows: dict[tuple, dict] = {}
    for r in runs:
        if r.faults is None:
            continue
        key = (r.scenario.name, r.plant, r.controller_used or r.controller)
        row = rows.setdefault(key, {"scenario": key[0], "plant": key[1], "controller": key[2], "cells": {}})
        row["cells"][r.case] = _fault_cell(r)
    return list(rows.values())


def render_markdown(tables: dict, runs: list[PlannedRun], notes: Notes, info: dict) -> str:
    from rpo.runtime.outputs.metrics import DEFAULT_THRESHOLDS

    out = ["# Reproduction of the papers' results", "",
           f"Generated by `rpo report` on {info['created_utc']} (model source hash {info['model_source_hash']}); "
           f"run folders under `{info['runs_dir']}`. Do not edit: the numbers come from the runs, the published "
           f"values and runs from {info['origin']}, the text from `{info['notes']}`.", "",
           "Metric definitions: `rpo.runtime.outputs.metrics` (module docstring). Settling time: the first time after "
           f"which the error stays below its threshold (default {DEFAULT_THRESHOLDS['att_deg']:g} deg, "
           f"{DEFAULT_THRESHOLDS['pos_m']:g} m) until the end of the run; \"not settled\" if it ends above. "
           "\"n/a (not logged)\": the controller does not log that error.", ""]
    if notes.intro.strip():
        out += [notes.intro.strip(), ""]
    for pid, p in tables["papers"].items():
        out += [f"## {pid}" + (f": {p['title']}" if p["title"] else ""), ""]
        if p["controller"]:
            out += [f"Controller: `{p['controller']}`.", ""]
        if p["claims"]:
            out += [_md_table(["case", "claim", "published", "ours (paper plant)", "ours (full plant)"],
                              [[c["case"], c["what"], c["published"], c["ours_paper"], c["ours_full"]]
                               for c in p["claims"]]), ""]
        if p["table2"]:
            out += ["Errors at given times (Table 2 layout):", "",
                    _md_table(["quantity", "t [s]", "published", "ours (paper plant)", "ours (full plant)"],
                              [[row["quantity"], "-" if row["t"] is None else f"{row['t']:g}", row["published"],
                                row["ours_paper"], row["ours_full"]] for row in p["table2"]]), ""]
        text = notes.paper.get(pid, "").strip()
        if text:
            out += [text, ""]
    if tables["comparison"]:
        out += ["## All controllers on common scenarios", ""]
        head = ["case", "plant", "controller", "status"] + [h for _m, _u, h in COMPARISON_COLUMNS]
        out += [_md_table(head, [[row["case"], row["plant"], row["controller"], row["status"]]
                                 + [row[m] for m, _u, _h in COMPARISON_COLUMNS] for row in tables["comparison"]]), ""]
        if notes.comparison.strip():
            out += [notes.comparison.strip(), ""]
    if tables.get("faults"):
        cases = [c for c, _f in FAULT_CASES]
        out += ["## Faults", "",
                "Every controller with one reaction wheel failed (no torque) and with one thruster stuck on, "
                "both from 30 s (`runtime/jobs/reproduction.py` FAULT_CASES; the fault model and the fault-aware "
                "allocation (\"FDIR\", rpo's, not the papers') in `docs/faults.md`). Scenario 001 flies the "
                "full plant here: its own model has ideal actuators, which have no units to fail. Each cell: "
                "attitude and position settling time (or the final error), propellant used.", "",
                _md_table(["scenario", "plant", "controller", *cases],
                          [[row["scenario"], row["plant"], row["controller"],
                            *[row["cells"].get(c, "-") for c in cases]] for row in tables["faults"]]), ""]
        if notes.faults.strip():
            out += [notes.faults.strip(), ""]
    out += ["## Runs", "",
            _md_table(["label", "scenario", "controller", "plant", "ran to [s]", "status", "folder"],
                      [[r.label, r.scenario.name, r.controller_used or r.controller or "-", r.plant,
                        "-" if r.metrics is None else _num(r.metrics.get("t_end_s")),
                        r.status + (f": {r.reason}" if r.reason else ""), r.folder or "-"] for r in runs]), ""]
    return "\n".join(out)


def summary_line(r: PlannedRun) -> str:
    """One line per finished run for the console."""
    m = r.metrics or {}
    if r.status in ("not run", "error", "refused"):
        return f"{r.label}: {r.status}: {r.reason}"
    def st(key):
        return metric_cell(r, key, with_unit=True)
    return f"{r.label}: {r.status}, attitude {st('att_settling_time_s')}, position {st('pos_settling_time_s')}, " \
           f"propellant {_num(m.get('propellant_kg'))} kg"

