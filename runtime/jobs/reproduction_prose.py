"""The sentences of the reproduction report that state an outcome, generated from its tables.

Every statement of docs/reproduction.md that a goal was reached or not, when, how that compares
with the paper, whether the copies of a run perturbed at round-off level agree, and which
controllers reach both goals, is written here from the same table rows that the report's tables
show (the JSON twin's ``tables``), never by hand: the hand-written notes
(``docs/reproduction_notes.toml``) explain, they do not report outcomes.  The functions take the
JSON-ready rows built by :mod:`.reproduction_tables` and return markdown lines.

Words, one meaning each:

* a goal is **reached** in a run when its settling time exists (the verdict's rule,
  :mod:`rpo.runtime.outputs.verdict`): the error stays below the threshold from then to the end;
* **both goals reached** (the comparison's "converges" = yes): every goal the controller logs;
* compared with a published time P, a settling time T is **as published** when P/1.2 <= T <= 1.2 P,
  else **later** or **earlier than published**;
* **k/N perturbed runs**: of N copies of the run with the initial state perturbed at round-off
  level (:mod:`.reproduction_roundoff`), k reach the goal; the outcome **depends on round-off**
  when the copies do not all agree with the run.
"""

from __future__ import annotations

from typing import Any

#: a settling time within this factor of the published one is "as published"
AS_PUBLISHED = 1.2
GOAL_WORDS = {"att": "attitude", "pos": "position", "both": "both goals"}


def compare_published(t: float, published: float | None) -> str:
    """How a settling time ``t`` [s] compares with the published one (empty without one)."""
    if published is None or published <= 0:
        return ""
    if t > AS_PUBLISHED * published:
        return "later than published"
    if t < published / AS_PUBLISHED:
        return "earlier than published"
    return f"as published (within {100 * (AS_PUBLISHED - 1):.0f} %)"


def roundoff_text(o: dict[str, Any] | None, what: str = "reach it") -> str:
    """``"k/N perturbed runs reach it"``, with ``": the outcome depends on round-off"`` when they
    disagree with the run; empty when no copies were flown."""
    if not o or o.get("k") is None:
        return ""
    text = f"{o['k']}/{o['n']} perturbed runs {what}"
    return text + (": the outcome depends on round-off" if o["depends"] else "")


def _plant_clause(d: dict[str, Any], published: float | None) -> str:
    """One plant's part of a settling claim's sentence."""
    o = d.get("outcome")
    if o is None or o.get("reached") is None:
        return d["cell"]
    if o["reached"]:
        text = f"reached at {d['value']:.4g} s"
        cmp = compare_published(d["value"], published)
        text += f", {cmp}" if cmp else ""
    else:
        text = "not reached" + (f" (final error {d['final']})" if d.get("final") else "")
    if d.get("status") == "diverged":
        text += ", the run diverged"
    r = roundoff_text(o)
    return text + (f", {r}" if r else "")


def claim_sentence(row: dict[str, Any]) -> str | None:
    """The sentence of a settling claim's row (None for a claim on another metric)."""
    if not row.get("settling"):
        return None
    parts = [f"on the {plant} plant {_plant_clause(row['plants'][plant], row.get('published_value'))}"
             for plant in ("paper", "full") if row["plants"][plant].get("run") is not None]
    if not parts:
        return None
    published = f"published {row['published']}; " if row.get("published") not in (None, "", "-") else ""
    return f"{row['case']}, {row['what']}: {published}" + "; ".join(parts) + "."


def table2_sentence(rows: list[dict[str, Any]], plant: str) -> str | None:
    """The Table 2 comparison of one plant: how many errors are at most the published ones, and
    the constraints; None when the plant has no run."""
    pairs = [(r["published_values"], r["values"][plant]) for r in rows
             if r.get("published_values") and r["values"].get(plant)]
    cons = {r["metric"]: r["values"].get(plant) for r in rows if r.get("metric")}
    if not pairs and all(v is None for v in cons.values()):
        return None
    def size(v):
        return max(abs(x) for x in v)

    n = len(pairs)
    le = sum(1 for pub, ours in pairs if size(ours) <= size(pub))
    ten = sum(1 for pub, ours in pairs if size(ours) <= 10 * size(pub))
    text = (f"Table 2, {plant} plant: of the {n} published errors (each quantity at each time, by its largest "
            f"component), ours is at most the published one in {le} and within ten times it in {ten}")
    fov, ca = cons.get("beta_fov_min_m"), cons.get("beta_ca_min_m2")
    if fov is not None and ca is not None:
        held = fov > 0 and ca > 0
        text += (f"; min beta_FOV {fov:.4g} m, min beta_CA {ca:.4g} m^2: "
                 + ("both constraints hold throughout" if held else
                    " and ".join(n for n, v in (("beta_FOV", fov), ("beta_CA", ca)) if v <= 0)
                    + " <= 0 at some time: violated"))
    return text + "."


def summary_lines(tables: dict[str, Any]) -> list[str]:
    """The report's summary: per paper, its outcome sentences; then the round-off count."""
    out = []
    for pid, p in tables["papers"].items():
        sentences = [s for row in p["claims"] if (s := claim_sentence(row))]
        if p.get("table2"):
            sentences += [s for plant in ("paper", "full") if (s := table2_sentence(p["table2"], plant))]
        if sentences:
            ctrl = f" (`{p['controller']}`)" if p.get("controller") else ""
            out += [f"- **{pid}**{ctrl}:", *(f"  - {s}" for s in sentences)]
    dep = dependent_outcomes(tables)
    total = sum(1 for _ in _all_outcomes(tables))
    if total and not dep:
        out.append(f"- **Round-off**: none of the {total} goal outcomes this report states depends on round-off: "
                   "every perturbed copy agrees with its run (\"Round-off sensitivity\").")
    elif total:
        out.append(f"- **Round-off**: {len(dep)} of the {total} goal outcomes this report states depend on "
                   "round-off (the perturbed copies disagree with the run shown); they are listed in "
                   "\"Round-off sensitivity\".")
    return out


def comparison_lines(rows: list[dict[str, Any]]) -> list[str]:
    """Per common scenario and plant: which controllers reach both goals, which do not, which did not
    fly; then the outcomes of the table that depend on round-off."""
    groups: dict[tuple[str, str], list[dict]] = {}
    for row in rows:
        groups.setdefault((row["case"], row["plant"]), []).append(row)
    out, dep = [], []
    for (case, plant), rs in groups.items():
        yes: list[str] = []
        no: list[str] = []
        other: list[str] = []
        for r in rs:
            o = r.get("outcome")
            if o is None or o.get("reached") is None:
                other.append(f"{r['controller']} ({r['status']})")
                continue
            tag = f"{r['controller']} [{o['k']}/{o['n']}]" if o.get("k") is not None else r["controller"]
            (yes if o["reached"] else no).append(tag)
            if o["depends"]:
                shown = "reached" if o["reached"] else "not reached"
                dep.append(f"{case}, {plant} plant, {r['controller']}: {shown} in the run shown, "
                           f"in {o['k']}/{o['n']} perturbed runs")
        if yes:
            parts = [f"both goals reached by {', '.join(yes)}"] + ([f"not by {', '.join(no)}"] if no else [])
        else:
            parts = ["both goals reached by none" + (f" ({', '.join(no)})" if no else "")]
        if other:
            parts.append(f"not flown: {', '.join(other)}")
        out.append(f"- {case}, {plant} plant: " + "; ".join(parts) + ".")
    if any(r.get("outcome") and r["outcome"].get("k") is not None for r in rows):
        out += ["", "Depends on round-off (the perturbed runs disagree with the run shown): " + "; ".join(dep) + "."
                if dep else "No outcome of this table depends on round-off: every perturbed run agrees with its run."]
    return out


def _all_outcomes(tables: dict[str, Any]):
    """(where, goal, outcome, run label) of every goal outcome the report states, with its copies."""
    seen = set()
    for p in tables["papers"].values():
        for row in p["claims"]:
            if not row.get("settling"):
                continue
            for plant in ("paper", "full"):
                d = row["plants"][plant]
                o = d.get("outcome")
                if o and o.get("k") is not None and (d["run"], row["goal"]) not in seen:
                    seen.add((d["run"], row["goal"]))
                    yield f"{row['case']} ({plant} plant), {GOAL_WORDS[row['goal']]}", row["goal"], o, d["run"]
    for row in tables["comparison"]:
        o = row.get("outcome")
        if o and o.get("k") is not None:
            yield (f"{row['case']} ({row['plant']} plant), {row['controller']}, both goals", "both", o, row["run"])
    for row in tables.get("faults", []):
        for case, goals in row.get("outcomes", {}).items():
            for q in ("att", "pos"):
                o = goals.get(q)
                if o and o.get("k") is not None:
                    yield (f"{row['scenario']} ({row['plant']} plant), {row['controller']}, {case}, "
                           f"{GOAL_WORDS[q]}", q, o, goals.get("run"))


def dependent_outcomes(tables: dict[str, Any]) -> list[tuple[str, str, dict, str | None]]:
    """The goal outcomes whose perturbed copies disagree with the run."""
    return [x for x in _all_outcomes(tables) if x[2]["depends"]]


def fault_lines(rows: list[dict[str, Any]]) -> list[str]:
    """The fault cells whose outcome depends on round-off."""
    cells = [(row, case, q, goals.get(q)) for row in rows for case, goals in row.get("outcomes", {}).items()
             for q in ("att", "pos")]
    dep = [f"{row['controller']} on {row['scenario']}, {case}: {GOAL_WORDS[q]} "
           + ("reached" if o["reached"] else "not reached") + f" in the run shown, in {o['k']}/{o['n']} perturbed runs"
           for row, case, q, o in cells if o and o["depends"]]
    flown = any(o and o.get("k") is not None for _row, _case, _q, o in cells)
    if not flown:
        return []
    if not dep:
        return ["In every cell, all perturbed runs agree with the run shown on whether each goal is reached."]
    return (["Cells whose outcome depends on round-off (the perturbed runs disagree with the run shown; read "
             "them as a fraction, not as reached or not):", ""] + [f"- {d}." for d in dep] + ["",
            "In every other cell, all perturbed runs agree with the run shown on whether each goal is reached."])


def roundoff_lines(tables: dict[str, Any], runs: list[Any]) -> list[str]:
    """The section on round-off sensitivity: the method, and every outcome that depends on it."""
    entry = next((r.roundoff for r in runs if getattr(r, "roundoff", None)), None)
    if entry is None:
        return []
    flown = sum(1 for r in runs if getattr(r, "roundoff", None))
    out = ["## Round-off sensitivity", "",
           f"Each of the {flown} runs that flew was flown again {entry['copies']} times, identical in everything "
           f"(scenario, parameters, gains, random-torque seed, duration, recording step) except the initial state: "
           f"each of its entries multiplied by 1 + {entry['rel']:g} n, n standard normal (a few units in the last "
           f"place; seed {entry['seed']}, the same on every invocation of `rpo report`). A goal counts as reached in "
           "a copy by the verdict's rule, as in the run (`runtime/jobs/reproduction_roundoff.py`). \"[k/N]\" and "
           "\"k/N perturbed runs\" in the tables and sentences above: k of the N copies reach the goal. An outcome "
           "depends on round-off when the copies do not all agree with the run shown: then the run's \"reached\" "
           "or \"not reached\" is a property of the last bits of its initial state (or of how a compiler orders "
           "the same arithmetic), and only the fraction is a result.", ""]
    dep = dependent_outcomes(tables)
    if not dep:
        return out + ["No outcome of this report depends on round-off: every copy agrees with its run.", ""]
    rows = [[where, "reached" if o["reached"] else "not reached", f"{o['k']}/{o['n']}", run or "-"]
            for where, _q, o, run in dep]
    head = "| outcome | the run shown | perturbed runs reaching it | run |\n| --- | --- | --- | --- |\n"
    return out + [f"These {len(dep)} outcomes depend on round-off:", "",
                  head + "\n".join("| " + " | ".join(r) + " |" for r in rows), ""]
