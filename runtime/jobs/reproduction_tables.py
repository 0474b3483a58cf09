"""The reproduction report's tables and its markdown: the papers' published values next to rpo's runs, the
comparison of the controllers, the fault study."""

from __future__ import annotations

import math

import numpy as np

from rpo.runtime.jobs import reproduction_prose as prose
from rpo.runtime.jobs.reproduction_roundoff import fraction_text, outcome
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


def _goal(metric: str) -> str | None:
    """The goal (``att``, ``pos``) whose settling time ``metric`` is; None for another metric."""
    q = metric.removesuffix("_settling_time_s")
    return q if q != metric and q in ("att", "pos") else None


def _final_text(m: dict | None, q: str) -> str | None:
    """The final error of goal ``q`` as text (deg or m)."""
    v = (m or {}).get("att_err_final_rad" if q == "att" else "pos_err_final_m")
    return None if v is None else (f"{v * RAD2DEG:.3g} deg" if q == "att" else f"{v:.3g} m")


def paper_rows(runs: list[PlannedRun], pid: str, paper: Paper) -> list[dict]:
    """One row per claim: the published value, each plant's cell, and (``plants``) what the
    sentences need: the run, its status, the metric's value, the goal's final error and outcome."""
    rows = []
    for c in paper.claim:
        q = _goal(c.metric)
        plants: dict[str, dict] = {}
        for plant in ("paper", "full"):
            r = _find(runs, pid, c.case, plant, paper.controller)
            flown = r is not None and r.status in ("ok", "diverged")
            m = r.metrics if flown and r is not None else None
            o = outcome(m, r.roundoff, q) if q and flown and r is not None else None
            plants[plant] = {"run": None if r is None else r.label, "status": None if r is None else r.status,
                             "cell": metric_cell(r, c.metric, c.unit, with_unit=True),
                             "value": None if m is None else m.get(c.metric),
                             "final": _final_text(m, q) if q else None, "outcome": o}
        rows.append({"case": c.case, "what": c.what, "metric": c.metric, "published": _published(c),
                     "published_value": c.published, "ours_paper": plants["paper"]["cell"],
                     "ours_full": plants["full"]["cell"], "run_paper": plants["paper"]["run"],
                     "run_full": plants["full"]["run"], "settling": q is not None, "goal": q,
                     **{f"perturbed_{k}": fraction_text(v["outcome"]) if v["outcome"] else "-"
                        for k, v in plants.items()},
                     "plants": plants})
    return rows


def _vec(v, scale=1.0) -> str:
    return "-" if v is None else "(" + ", ".join(f"{x * scale:.3g}" for x in v) + ")"


def table2_rows(runs: list[PlannedRun], pid: str, paper: Paper) -> list[dict]:
    """Table 2's layout: a row per quantity and time, the published vector and each plant's (as text,
    and as numbers in ``values`` for the sentences), then the constraints' minima."""
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

    def cell(plant, t, key, scale=1.0) -> tuple[str, list[float] | None]:
        r, at = ours[plant]
        if r is None:
            return "not run (no run declared)", None
        if r.status in ("not run", "error", "refused"):
            return f"{r.status} ({r.reason})", None
        e = at.get(round(t, 6))
        if e is None:
            return "n/a (time not recorded)", None
        v = e.get(key)
        if v is None:
            return "n/a (not logged or run ended)", None
        if key == "q" and t2.q_columns:  # the paper's difference of quaternions, sign-aligned to the reference
            d = e.get("diag") or {}
            if not all(c in d for c in t2.q_columns):
                return "n/a (not logged)", None
            q = np.array([d[c] for c in t2.q_columns])
            ref = np.array(t2.q_reference)
            q = q if q @ ref >= 0 else -q
            v = list(q - ref)
        elif key == "q":  # ours as (scalar, x, y, z), the published order
            v = [v[3], v[0], v[1], v[2]]
        vals = [float(x) * scale for x in v]
        return _vec(vals), vals

    q_name = "attitude quaternion " + ("q - q_D " if t2.q_columns else "") + "(scalar, x, y, z)"
    for name, key, pub, scale, unit in ((q_name, "q", t2.q, 1.0, "-"),
                                        ("position", "pos_m", t2.pos, 1.0, "m"),
                                        ("angular rate", "rate_rad_s", t2.rate_deg_s, RAD2DEG, "deg/s"),
                                        ("velocity", "vel_m_s", t2.vel, 1.0, "m/s")):
        for i, t in enumerate(t2.times):
            pv = [float(x) for x in pub[i]] if i < len(pub) else None
            (tp, vp), (tf, vf) = cell("paper", t, key, scale), cell("full", t, key, scale)
            rows.append({"quantity": f"{name} [{unit}]", "t": t, "published": _vec(pv), "ours_paper": tp,
                         "ours_full": tf, "published_values": pv, "values": {"paper": vp, "full": vf}})
    for name, metric, unit in (("min beta_FOV", "beta_fov_min_m", "m"), ("min beta_CA", "beta_ca_min_m2", "m^2")):
        vals = {}
        for plant in ("paper", "full"):
            r = ours[plant][0]
            ok = r is not None and r.status in ("ok", "diverged") and r.metrics
            vals[plant] = r.metrics.get(metric) if ok and r is not None and r.metrics else None
        rows.append({"quantity": f"{name} [{unit}]", "t": None, "published": t2.constraints_text,
                     "ours_paper": metric_cell(ours["paper"][0], metric),
                     "ours_full": metric_cell(ours["full"][0], metric), "metric": metric, "values": vals})
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
            flown = r.status in ("ok", "diverged")
            for metric, unit, _head in COMPARISON_COLUMNS:
                row[metric] = metric_cell(r, metric, unit) if flown else "-"
            row["outcome"] = outcome(r.metrics, r.roundoff, "both") if flown else None
            row["perturbed"] = fraction_text(row["outcome"]) if flown else "-"
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
    """Attitude and position settling (or final errors) with the perturbed runs reaching each goal
    (``[k/N]``), the propellant; or why there is none."""
    if r is None:
        return "-"
    if r.status not in ("ok", "diverged"):
        return r.status
    m = r.metrics or {}

    def goal(q: str, unit: str, scale: float) -> str:
        st, fin = m.get(f"{q}_settling_time_s"), m.get(f"{q}_err_final_{'rad' if q == 'att' else 'm'}")
        if fin is None:
            return f"{q} n/a"
        o = outcome(m, r.roundoff, q)
        k = f" [{fraction_text(o)}]" if o["k"] is not None else ""
        return (f"{q} {st:.0f} s" if st is not None else f"{q} off {fin * scale:.3g} {unit}") + k

    text = f"{goal('att', 'deg', RAD2DEG)}, {goal('pos', 'm', 1.0)}, {_num(m.get('propellant_kg'), '.3g')} kg"
    return ("DIVERGED; " + text) if r.status == "diverged" else text


def fault_rows(runs: list[PlannedRun]) -> list[dict]:
    """The fault study: one row per (scenario, plant, controller), one cell per case."""
    rows: dict[tuple, dict] = {}
    for r in runs:
        if r.faults is None:
            continue
        key = (r.scenario.name, r.plant, r.controller_used or r.controller)
        row = rows.setdefault(key, {"scenario": key[0], "plant": key[1], "controller": key[2], "cells": {},
                                    "outcomes": {}})
        row["cells"][r.case] = _fault_cell(r)
        if r.status in ("ok", "diverged"):
            row["outcomes"][r.case] = {"run": r.label, **{q: outcome(r.metrics, r.roundoff, q) for q in ("att", "pos")}}
    return list(rows.values())


def render_markdown(tables: dict, runs: list[PlannedRun], notes: Notes, info: dict) -> str:
    """The report: every number and every outcome from ``tables`` and ``runs`` (the sentences from
    :mod:`.reproduction_prose`), the explanations from ``notes``."""
    from rpo.runtime.outputs.metrics import DEFAULT_THRESHOLDS

    out = ["# Reproduction of the papers' results", "",
           f"Generated by `rpo report` on {info['created_utc']} (model source hash {info['model_source_hash']}); "
           f"run folders under `{info['runs_dir']}`. Do not edit: the numbers and every sentence that states an "
           f"outcome come from the runs (`docs/reproduction.json`), the published values and runs from "
           f"{info['origin']}, the explanations from `{info['notes']}`. The papers: `docs/papers.md`.", "",
           "Metric definitions: `rpo.runtime.outputs.metrics` (module docstring). Settling time: the first time after "
           f"which the error stays below its threshold (default {DEFAULT_THRESHOLDS['att_deg']:g} deg, "
           f"{DEFAULT_THRESHOLDS['pos_m']:g} m) until the end of the run; \"not settled\" if it ends above. A goal "
           "is reached when its settling time exists (the rule of the verdict, `docs/verdict.md`). Compared with a "
           f"published time P, a settling time T is \"as published\" when P/{prose.AS_PUBLISHED:g} <= T <= "
           f"{prose.AS_PUBLISHED:g} P, else later or earlier than published. \"n/a (not logged)\": the controller "
           "does not log that error. \"k/N\", \"[k/N]\": k of N copies of the run, perturbed at round-off level, "
           "reach the goal (\"Round-off sensitivity\").", ""]
    if notes.intro.strip():
        out += [notes.intro.strip(), ""]
    summary = prose.summary_lines(tables)
    if summary:
        out += ["## Summary", "", "What the runs below show, per paper (generated from the tables):", "", *summary, ""]
    for pid, p in tables["papers"].items():
        out += [f"## {pid}" + (f": {p['title']}" if p["title"] else ""), ""]
        if p["controller"]:
            out += [f"Controller: `{p['controller']}`.", ""]
        if p["claims"]:
            out += [_md_table(["case", "claim", "published", "ours (paper plant)", "ours (full plant)",
                               "perturbed runs reaching it (paper, full)"],
                              [[c["case"], c["what"], c["published"], c["ours_paper"], c["ours_full"],
                                "-" if not c.get("settling") else
                                f"{c.get('perturbed_paper', '-')}, {c.get('perturbed_full', '-')}"]
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
        head = ["case", "plant", "controller", "status"] + [h for _m, _u, h in COMPARISON_COLUMNS] + \
            ["perturbed runs converging"]
        out += [_md_table(head, [[row["case"], row["plant"], row["controller"], row["status"]]
                                 + [row[m] for m, _u, _h in COMPARISON_COLUMNS] + [row.get("perturbed", "-")]
                                 for row in tables["comparison"]]), ""]
        out += ["\"converges\": both goals the controller logs are reached (yes) or not (no). Per scenario and "
                "plant (generated from the table; [k/N]: perturbed runs reaching both goals):", "",
                *prose.comparison_lines(tables["comparison"]), ""]
        if notes.comparison.strip():
            out += [notes.comparison.strip(), ""]
    if tables.get("faults"):
        cases = [c for c, _f in FAULT_CASES]
        out += ["## Faults", "",
                "Every controller with one reaction wheel failed (no torque) and with one thruster stuck on, "
                "both from 30 s (`runtime/jobs/reproduction_runs.py` FAULT_CASES; the fault model and the fault-aware "
                "allocation (\"FDIR\", rpo's, not the papers') in `docs/faults.md`). Each controller flies with its "
                "default gains (the comparison's per-controller gains are not applied, so a \"nominal\" cell may "
                "differ from the comparison's row). Scenario 001 flies the full plant here: its own model has ideal "
                "actuators, which have no units to fail. Each cell: attitude and position settling time (or the "
                "final error) with [k/N] perturbed runs reaching the goal, propellant used.", "",
                _md_table(["scenario", "plant", "controller", *cases],
                          [[row["scenario"], row["plant"], row["controller"],
                            *[row["cells"].get(c, "-") for c in cases]] for row in tables["faults"]]), ""]
        lines = prose.fault_lines(tables["faults"])
        if lines:
            out += [*lines, ""]
        if notes.faults.strip():
            out += [notes.faults.strip(), ""]
    out += prose.roundoff_lines(tables, runs)
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

