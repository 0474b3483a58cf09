"""``rpo mc``: Monte Carlo campaigns from the command line (docs/campaigns.md).

``rpo mc run CAMPAIGN.toml --out DIR`` flies a campaign into a new folder, ``rpo mc resume DIR``
flies what is missing, ``rpo mc report DIR`` writes its statistics.  Exit codes: 0 every run is
recorded (a diverged or failed run is a result, not an error); 1 some runs ended in an error
(``resume`` flies them again); 2 a user error (one ``error:`` line, nothing written); 130/143
interrupted (the runs recorded so far are kept: ``resume`` goes on).

Heavy imports (SciPy, the model) happen inside the commands, so ``rpo --help`` stays fast.
"""

from __future__ import annotations

import os
import shlex
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from rpo.runtime.cli.options import _SET, _source
from rpo.runtime.errors import CampaignError

if TYPE_CHECKING:
    from rpo.runtime.model.manifest import Manifest
    from rpo.runtime.scenario.loader import ScenarioSource
    from rpo.runtime.scenario.schema import Scenario

EXIT_RUN_ERRORS = 1


def _err(msg: str) -> None:
    click.echo(msg, err=True)


def os_error_line(exc: OSError, folder: Path | None, again: str) -> str:
    """One line for an OSError met while flying or reporting: the path, what happened and what to
    do (``again``: the command that goes on afterwards)."""
    import errno

    where = exc.filename or folder or "?"
    what = exc.strerror or type(exc).__name__
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        fix = "free space"
    elif exc.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        inside = folder is not None and exc.filename is not None and \
            Path(os.path.abspath(exc.filename)).is_relative_to(os.path.abspath(folder))
        # outside the campaign folder, it is most often the model cache (its lock, a library)
        fix = "make it writable" if inside else \
            "make it writable (if it is the model cache: or set RPO_CACHE_DIR to a writable folder)"
    else:
        fix = "fix it"
    return f"{where}: {what} ({errno.errorcode.get(exc.errno or 0, 'OSError')}): {fix}, then {again}"


def _again(folder: Path | None, command: str) -> str:
    """The command that goes on after an error: resume once the folder holds its campaign."""
    from rpo.runtime.campaign import storage
    if folder is not None and command != "report" and (folder / storage.RESOLVED).is_file():
        return f"`rpo mc resume {shlex.quote(str(folder))}` (the runs recorded so far are kept)"
    if command == "report":
        return f"`rpo mc report {shlex.quote(str(folder))}` again"
    return "run the command again"


def _notes(scan_problems: list[str], unverified: list[int], folder: Path, quiet: bool) -> None:
    """The manifest lines not counted and the histories not verified, one line each (on stderr)."""
    from rpo.runtime.campaign import storage
    if scan_problems:
        more = f" (and {len(scan_problems) - 3} more)" if len(scan_problems) > 3 else ""
        lines = "line" if len(scan_problems) == 1 else "lines"
        _err(f"warning: {folder / storage.MANIFEST}: {len(scan_problems)} {lines} not counted: "
             f"{'; '.join(scan_problems[:3])}{more}")
    if unverified and not quiet:
        _err(f"note: {len(unverified)} runs' histories have no recorded sha256 (a folder written before rpo "
             "recorded them): read, not verified")


class _Progress:
    """Runs done, failed (diverged, constraint violated or a goal not reached), invalid and in
    error, with an ETA: a click progress bar on a terminal, one line per 10 % otherwise."""

    def __init__(self, total: int, quiet: bool):
        self.total, self.quiet = total, quiet
        self.n = self.failed = self.invalid = self.errors = 0
        self.t0 = time.perf_counter()
        self.bar: Any = None
        self.next_line = 0.1
        if not quiet and total and sys.stderr.isatty():
            self.bar = click.progressbar(length=total, label="runs", file=sys.stderr, show_eta=True,
                                         item_show_func=lambda _: self._text()).__enter__()

    def _text(self) -> str:
        return f"{self.n} done, {self.failed} failed, {self.invalid} invalid, {self.errors} errors"

    def rows(self, rows: list[dict]) -> None:
        for r in rows:
            self.failed += bool(r.get("outcome", {}).get("failed"))
            self.invalid += r["status"] == "invalid"
            self.errors += r["status"] == "error"
        self.n += len(rows)
        if self.bar is not None:
            self.bar.update(len(rows), current_item=True)
        elif not self.quiet and self.total and self.n / self.total >= self.next_line:
            el = time.perf_counter() - self.t0
            eta = el / self.n * (self.total - self.n)
            _err(f"runs: {self.n}/{self.total} ({self._text()}), {el:.0f} s, ETA {eta:.0f} s")
            while self.next_line <= self.n / self.total:
                self.next_line += 0.1

    def close(self) -> None:
        if self.bar is not None:
            self.bar.__exit__(None, None, None)


def _model(controller: str, quiet: bool) -> Any:
    from rpo.runtime.model.loader import load_model
    return load_model("auto", log=None if quiet else _err, controllers=[controller])


def campaign_or_scenario(name: str, source: str | ScenarioSource, manifest: Manifest) -> Scenario:
    """The scenario `rpo validate` checks: the file's, or for a campaign file (a ``[campaign]``
    table) its base scenario, once the campaign passed every check `rpo mc run` makes on reading it
    (dispersions, median draw, keys the flown configuration reads)."""
    from rpo.runtime.campaign.spec import load_campaign
    from rpo.runtime.scenario import load_scenario, read_scenario, validate_scenario

    src = read_scenario(source) if isinstance(source, str) else source
    if not isinstance(src.data.get("campaign"), dict):
        return load_scenario(src, manifest)
    camp = load_campaign(src, manifest)
    click.echo(f"{name}: campaign {camp.name!r}: {camp.runs} runs, {len(camp.dispersions)} dispersions "
               f"({', '.join(d.key for d in camp.dispersions)}); its scenario:")
    return validate_scenario(camp.scenario_data, src.source, manifest)


def _dask_option(value: str | None) -> str | None:
    if value is None:
        return None
    v = value.strip()
    if v != "local" and "://" not in v and ":" not in v:
        raise CampaignError(f"--dask {value!r}: must be \"local\" (a LocalCluster on this machine) or a scheduler "
                            "address such as tcp://10.0.0.5:8786")
    return v


def _fly(camp: Any, model: Any, folder: Path, workers: int | None, dask: str | None, batch: int | None,
         quiet: bool, what: str) -> int:
    from rpo.runtime.campaign import execute, sequential, storage

    done = storage.read_rows(folder)
    lost = {c for _, cases in storage.damaged_histories(folder, done).values() for c in cases}  # flown again
    todo = sum(1 for c in range(camp.runs) if c not in done or done[c]["status"] == "error" or c in lost)
    n_workers = workers or execute.default_workers()
    if not quiet:
        how = f"Dask {dask}" if dask else ("this process" if n_workers == 1 else f"{n_workers} worker processes")
        upto = f"up to {todo}" if camp.settings.sequential else str(todo)
        seq = f", sequential in {camp.looks} looks, stopping once decided" if camp.settings.sequential else ""
        _err(f"{camp.name}: {what} {upto} of {camp.runs} runs ({camp.settings.sampling} sampling, seed "
             f"{camp.settings.seed}{seq}) on {how}, into {folder}")
    bar = _Progress(todo, quiet)
    try:
        out = sequential.run_campaign(camp, model, folder, workers=n_workers, dask=dask, batch=batch,
                                      on_rows=bar.rows)
    finally:
        bar.close()
    _notes(out.problems, out.unverified, folder, quiet)
    c = out.counts
    flown = c["ok"] + c["diverged"]
    rows = storage.read_rows(folder)
    failed = sum(1 for r in rows.values() if r.get("outcome", {}).get("failed"))
    if out.interrupted is not None:
        from rpo.runtime.run.interrupts import Interrupted
        raise Interrupted(out.interrupted, f"interrupted: {len(rows)} of {camp.runs} runs are recorded in {folder}; "
                             f"`rpo mc resume {folder}` flies the rest")
    if not quiet:
        click.echo(f"done: {len(rows)} of {camp.runs} runs in {out.wall_s:.1f} s: {c['ok']} ok, {c['diverged']} "
                   f"diverged, {c['invalid']} invalid draws, {c['error']} errors; {failed} of {flown} flown runs "
                   "failed (diverged, a goal not reached or a constraint violated)")
        _verdict_lines(camp, out, rows)
        click.echo(f"summary: {folder / storage.SUMMARY}; statistics: rpo mc report {shlex.quote(str(folder))}")
    if c["error"]:
        first = next(r for r in rows.values() if r["status"] == "error")
        _err(f"error: {c['error']} runs ended in an error (first: case {first['case']}: {first['message']}); "
             f"`rpo mc resume {folder}` flies them again")
        return EXIT_RUN_ERRORS
    return 0


def _verdict_lines(camp: Any, out: Any, rows: dict) -> None:
    """One line per requirement (PASS / FAIL / UNDECIDED, k/n, bounds), after the sequential stop's."""
    from rpo.runtime.campaign.requirements import judge_rows
    from rpo.runtime.campaign.sequential import SequentialOutcome

    if not camp.requirements:
        return
    looks = camp.looks if camp.settings.sequential else 1
    if isinstance(out, SequentialOutcome) and out.look:
        click.echo(f"sequential: look {out.look} of {out.looks} after {out.runs_judged} runs: "
                   + ("every requirement decided, stopped" if out.decided else "not every requirement decided"))
    for v in judge_rows(camp.requirements, rows, looks):
        more = "" if v.verdict != "UNDECIDED" else (
            f", {v.runs_still_needed} more runs without failure to pass" if v.runs_still_needed is not None else "")
        click.echo(f"requirement {v.requirement.name} ({v.requirement.text}, p >= {v.requirement.probability:g} at "
                   f"{100 * v.confidence_used:g} %): {v.verdict}, met {v.met}/{v.n}, bounds "
                   f"[{v.lower:.6f}, {v.upper:.6f}]{more}")


@click.group()
def mc() -> None:
    """Monte Carlo campaigns: disperse a scenario, fly it many times, read the statistics.

    \b
      rpo mc run scenarios/campaigns/000_III_mc.toml --out runs/mc
      rpo mc resume runs/mc          (after an interruption: flies the missing runs)
      rpo mc report runs/mc          (report.md and figures)
      rpo run --campaign runs/mc --case 17   (one run again, every step recorded)
      rpo mc plan scenarios/campaigns/000_III_mc.toml   (the runs its requirements need)
    """


@mc.command("run")
@click.argument("campaign_file", type=click.Path(dir_okay=False, path_type=str))
@click.option("--out", "out", required=True, type=click.Path(file_okay=False, path_type=str),
              help="Campaign folder (must not exist or be empty).")
@click.option("--workers", type=click.IntRange(min=1), default=None,
              help="Worker processes (default: every core; 1 flies in this process).")
@click.option("--dask", default=None, metavar="local|ADDRESS",
              help="Fly on Dask: 'local' starts a LocalCluster of --workers processes, an address "
                   "(tcp://host:8786) connects to a running scheduler (pip install 'dask[distributed]').")
@click.option("--runs", type=click.IntRange(min=1), default=None, help="Override campaign.runs (a quick look).")
@click.option("--duration", type=click.FloatRange(min=0, min_open=True), default=None,
              help="Override simulation.duration [s] (a quick look).")
@click.option("--batch", type=click.IntRange(min=1), default=None,
              help="Runs per task (default campaign.batch, else 4 lane blocks).")
@click.option("--quiet", "-q", is_flag=True, help="Print only errors.")
@_SET
def run_cmd(campaign_file: str, out: str, workers: int | None, dask: str | None, runs: int | None,
            duration: float | None, batch: int | None, quiet: bool, sets: tuple[str, ...]) -> int:
    """Fly CAMPAIGN_FILE (a scenario with [campaign] and [dispersions]) into a new folder."""
    from rpo.runtime.campaign import execute
    from rpo.runtime.campaign.lock import folder_lock
    from rpo.runtime.campaign.spec import load_campaign
    from rpo.runtime.campaign.up_front import check_dask
    from rpo.runtime.model.manifest import read_manifest
    from rpo.runtime.outputs.writers import check_out_dir

    dask = _dask_option(dask)
    source = _source(campaign_file, sets)  # --set: the campaign's scenario (or its [campaign]) changed first
    camp = _with_sets(load_campaign(source, read_manifest(), runs=runs, duration=duration), sets)
    # every check before the folder exists, so that a refused command can be run again unchanged
    folder = check_out_dir(out)  # before the model loads (which may compile): a bad folder is told at once
    check_dask(dask)
    ctrl = camp.scenario_data.get("simulation", {}).get("controller", "baseline")
    with _os_errors(None, "run"):
        model = _model(ctrl, quiet)
    if model.manifest.manifest_hash != camp.manifest.manifest_hash:
        camp = _with_sets(load_campaign(source, model.manifest, runs=runs, duration=duration), sets)
    command = " ".join(shlex.quote(a) for a in ["rpo", "mc", "run", *sys.argv[3:]]) if len(sys.argv) > 3 else ""
    with _os_errors(folder, "run"):
        made = not folder.exists()
        folder.mkdir(parents=True, exist_ok=True)
        with folder_lock(folder):  # a second `rpo mc run --out` the same folder refuses
            try:
                folder = execute.start_folder(camp, model, folder, command=command)
            except OSError:  # not started (a full disk, a read-only folder): the folder this command made goes
                if made:  # (an OutputError, a folder that another command filled meanwhile, is left alone)
                    import shutil
                    shutil.rmtree(folder, ignore_errors=True)
                raise
            return _fly(camp, model, folder, workers, dask, batch, quiet, "flying")


def _with_sets(camp: Any, sets: tuple[str, ...]) -> Any:
    """``camp`` with its ``--set`` items recorded in ``overrides["set"]`` (as TOML text, in
    ``resolved.json`` and the hash), so that ``rpo mc resume`` applies them again."""
    if sets:
        camp.overrides["set"] = {k.strip(): v.strip() for k, _, v in (s.partition("=") for s in sets)}
    return camp


@mc.command("resume")
@click.argument("folder", type=click.Path(file_okay=False, path_type=Path))
@click.option("--workers", type=click.IntRange(min=1), default=None, help="Worker processes (default: every core).")
@click.option("--dask", default=None, metavar="local|ADDRESS", help="Fly on Dask (as for `rpo mc run`).")
@click.option("--batch", type=click.IntRange(min=1), default=None, help="Runs per task.")
@click.option("--quiet", "-q", is_flag=True, help="Print only errors.")
def resume_cmd(folder: Path, workers: int | None, dask: str | None, batch: int | None, quiet: bool) -> int:
    """Fly the runs of FOLDER that are missing or ended in an error; refused, naming what changed,
    if the model or the campaign (its file, or the scenario it extends) changed since it started."""
    from rpo.runtime.campaign import execute, storage
    from rpo.runtime.campaign.lock import folder_lock
    from rpo.runtime.campaign.spec import load_campaign
    from rpo.runtime.campaign.up_front import check_dask

    dask = _dask_option(dask)
    resolved = storage.read_resolved(folder)
    check_dask(dask)
    with _os_errors(folder, "resume"), folder_lock(folder):  # before the model loads: a folder in use is told at once
        model = _model(resolved["controller"], quiet)
        source = Path(resolved["campaign_file"])
        again = None
        if source.is_file():
            ov = resolved.get("overrides", {})
            sets = tuple(f"{k}={v}" for k, v in ov.get("set", {}).items())
            again = _with_sets(load_campaign(_source(str(source), sets), model.manifest, runs=ov.get("runs"),
                                             duration=ov.get("duration")), sets)
        elif not quiet:
            _err(f"note: {source} is not there any more: resuming the campaign recorded in "
                 f"{folder}/{storage.RESOLVED}")
        camp = execute.check_resume(folder, model, again)
        return _fly(camp, model, folder, workers, dask, batch, quiet, "resuming:")


@mc.command("report")
@click.argument("folder", type=click.Path(file_okay=False, path_type=Path))
@click.option("--coverage", type=click.FloatRange(0, 1, min_open=True, max_open=True), default=0.95,
              show_default=True, help="Coverage of the Wilks tolerance bounds.")
@click.option("--confidence", type=click.FloatRange(0, 1, min_open=True, max_open=True), default=0.95,
              show_default=True, help="Confidence of the intervals and of the Wilks bounds.")
@click.option("--no-figures", is_flag=True, help="Write report.md only.")
def report_cmd(folder: Path, coverage: float, confidence: float, no_figures: bool) -> int:
    """Write FOLDER/report.md and FOLDER/figures/: statistics of every metric, failure rates with
    confidence intervals, envelopes, CDFs, sensitivities and the worst cases."""
    from rpo.runtime.campaign import storage
    from rpo.runtime.campaign.reporting import write_report

    storage.read_resolved(folder)  # a clear error for a folder that is not a campaign
    with _os_errors(folder, "report"):
        scan = storage.scan_manifest(folder)
        _notes(scan.problems, scan.unverified, folder, False)
        damaged = storage.damaged_histories(folder, scan.rows)
        if damaged and not no_figures:
            (path0, (state, cases)), n = next(iter(damaged.items())), sum(len(c) for _, c in damaged.values())
            _err(f"warning: {len(damaged)} history files missing or damaged (first: {path0}: {state}, cases "
                 f"{cases[0]}-{cases[-1]}): {n} runs left out of the figures; `rpo mc resume {folder}` flies "
                 "them again")
        path = write_report(folder, coverage=coverage, confidence=confidence, figures=not no_figures)
    click.echo(f"wrote {path}")
    return 0


#: Failures allowed in the columns of `rpo mc plan`.
PLAN_FAILURES = (0, 1, 2)


@mc.command("plan")
@click.argument("campaign_file", type=click.Path(dir_okay=False, path_type=str))
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of the table.")
@_SET
def plan_cmd(campaign_file: str, as_json: bool, sets: tuple[str, ...]) -> int:
    """The runs each requirement of CAMPAIGN_FILE needs for a PASS, before flying: with no failure,
    and with 1 and 2 failures allowed (one-sided Clopper-Pearson, docs/campaigns.md); the most over
    the requirements; for a sequential campaign the same at the confidence of each look."""
    import json

    from rpo.runtime.campaign.requirements import runs_needed
    from rpo.runtime.campaign.spec import load_campaign
    from rpo.runtime.model.manifest import read_manifest

    camp = load_campaign(_source(campaign_file, sets), read_manifest())
    if not camp.requirements:
        raise CampaignError(f"{campaign_file}: no [requirements.<name>] table to plan for (add one with metric, "
                            "max or min, probability, confidence: docs/campaigns.md)")
    looks = camp.looks if camp.settings.sequential else 1
    plan = []
    for r in camp.requirements:
        conf = 1.0 - (1.0 - r.confidence) / looks
        plan.append({"name": r.name, "metric": r.metric, "kind": r.kind, "bound": r.bound,
                     "probability": r.probability, "confidence": r.confidence, "confidence_per_look": conf,
                     "runs": {str(k): runs_needed(r.probability, conf, k) for k in PLAN_FAILURES}})
    most = {str(k): max(p["runs"][str(k)] for p in plan) for k in PLAN_FAILURES}
    out = {"campaign": camp.name, "runs": camp.runs, "looks": looks, "requirements": plan, "most": most}
    if as_json:
        click.echo(json.dumps(out, sort_keys=True))
        return 0
    click.echo(f"{camp.name}: runs for a PASS of each requirement (k failures allowed among them)"
               + (f"; sequential, {looks} looks: each look at confidence 1 - (1 - c) / {looks}" if looks > 1 else ""))
    head = ["requirement", "bound", "p", "confidence", *[f"k={k}" for k in PLAN_FAILURES]]
    body = [[p["name"], f"{p['metric']} {'<=' if p['kind'] == 'max' else '>='} {p['bound']:g}", f"{p['probability']:g}",
             f"{p['confidence_per_look']:g}", *[str(p["runs"][str(k)]) for k in PLAN_FAILURES]] for p in plan]
    body.append(["most", "", "", "", *[str(most[str(k)]) for k in PLAN_FAILURES]])
    widths = [max(len(str(row[i])) for row in [head, *body]) for i in range(len(head))]
    for row in [head, *body]:
        click.echo("  ".join(str(v).ljust(w) for v, w in zip(row, widths, strict=True)).rstrip())
    note = f"the campaign asks for {camp.runs} runs"
    if camp.runs < most["0"]:
        note += f": too few for a PASS of every requirement even with no failure (needs {most['0']})"
    click.echo(note)
    return 0


@contextmanager
def _os_errors(folder: Path | None, command: str) -> Iterator[None]:
    """An OSError (a full disk, no permission, a read-only cache) as one CampaignError line naming
    the path and what to do; what is written stays (a cut last line or a temporary file is cleaned
    by the next resume)."""
    try:
        yield
    except OSError as exc:
        if isinstance(exc, CampaignError):  # already one line (folder.MissingSummary)
            raise
        raise CampaignError(os_error_line(exc, folder, _again(folder, command))) from None
