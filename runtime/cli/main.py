"""The ``rpo`` command: run, validate and inspect scenarios of the generated model.

Exit codes: 0 success; 2 a user error (bad scenario, bad option, output folder not empty,
missing compiler...), printed as one ``error: ...`` line on stderr without a traceback;
3 the simulation diverged (the results up to the divergence are written, the message says
where); 130 interrupted.  Also runnable as ``python -m rpo.runtime.cli.main``.
"""

from __future__ import annotations

import math
import sys
import warnings
from collections.abc import Callable
from importlib import metadata
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click
import numpy as np

from rpo.runtime import frames
from rpo.runtime.cli.options import _SET, _source
from rpo.runtime.errors import RpoError
from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, FIGURE_FORMAT_NAMES, FORMAT_NAMES, OUTPUT_FORMATS
from rpo.runtime.model.toolchain import find_compiler, native_target
from rpo.runtime.run import interrupts

if TYPE_CHECKING:
    from rpo.runtime.model.loader import Model
    from rpo.runtime.model.manifest import LayoutField

EXIT_USAGE = 2
EXIT_DIVERGED = 3
#: Rough cost of one step, to decide whether a progress bar is worth showing [s].
STEP_COST = {"compiled": 2e-5, "casadi": 2e-3}

#: click >= 8.2 raises this for a group called without a command (its message is the help).
_NO_ARGS = getattr(click.exceptions, "NoArgsIsHelpError", ())

BACKENDS = click.Choice(["auto", "compiled", "casadi"])
#: ``parquet (default), mat (MATLAB), ...``: the formats of --format's help, from the registry.
_FORMATS_HELP = ", ".join(f.name + (" (default)" if f.default else "") + (f" ({f.note})" if f.note else "")
                          for f in OUTPUT_FORMATS.values())


def _err(msg: str) -> None:
    click.echo(msg, err=True)


def _format_warning(message, category, filename, lineno, line=None) -> str:
    return f"warning: {' '.join(str(message).split())}\n"


def _loader(quiet: bool):
    return None if quiet else (lambda m: _err(m))


def _load_model(backend: str, quiet: bool, controllers: list[str] | None = None):
    """The model; ``controllers``: only these (a run loads, and on first use compiles, what it flies)."""
    from rpo.runtime.model.loader import load_model
    return load_model(backend, log=_loader(quiet), controllers=controllers)


def _formats(ctx, param, value: str | None) -> tuple[str, ...] | None:
    """``--format parquet,mat``: each name checked against :data:`rpo.runtime.formats.OUTPUT_FORMATS`."""
    if value is None:
        return None
    names = [v.strip() for v in value.split(",") if v.strip()]
    bad = [n for n in names if n not in OUTPUT_FORMATS]
    if bad or not names:
        raise click.BadParameter(f"{value!r}: unknown format {', '.join(bad) or '(none)'}; allowed: "
                                 f"{', '.join(FORMAT_NAMES)} (comma-separated)")
    if len(set(names)) != len(names):
        raise click.BadParameter(f"{value!r} lists a format twice")
    return tuple(names)


# --------------------------------------------------------------------------- commands


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="rpo", prog_name="rpo")
def cli() -> None:
    """rpo: spacecraft rendezvous simulations on a generated, compiled model.

    \b
    Typical use:
      rpo validate scenarios/000_scenario_III.toml
      rpo run scenarios/000_scenario_III.toml --out runs/iii
      rpo info
      rpo linearize scenarios/000_scenario_III.toml   (closed-loop eigenvalues at the goal)
      rpo report                       (the reproduction report: docs/reproduction.md)
      rpo scenarios                    (the shipped scenarios; NAME --to FILE copies one to edit)
      rpo view runs/iii                (an interactive page of a run: runs/iii/view.html)
    """


@cli.command()
@click.argument("scenario", type=click.Path(dir_okay=False, path_type=str), required=False)
@click.option("--out", "out", type=click.Path(file_okay=False, path_type=str), default=None,
              help="Output folder (must not exist or be empty). Default: runs/<scenario>-<UTC time>; with "
                   "--campaign: <campaign>/cases/case_<n>.")
@click.option("--campaign", "campaign", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Fly one case of this campaign folder (with --case) instead of SCENARIO, every step recorded.")
@click.option("--case", "case", type=click.IntRange(min=0), default=None, help="The case of --campaign.")
@click.option("--duration", type=click.FloatRange(min=0, min_open=True), default=None,
              help="Override simulation.duration [s].")
@click.option("--seed", type=click.IntRange(min=0), default=None, help="Override simulation.seed.")
@click.option("--controller", default=None, help="Override simulation.controller (see `rpo info`).")
@click.option("--plant", type=click.Choice(["paper", "full"]), default=None,
              help="paper (default): the scenario's own plant (its paper's model); full: the common full-fidelity "
                   "plant of seed 000 (orbit, environment, wheels, PWPF thrusters, mass profile).")
@click.option("--backend", type=BACKENDS, default="auto", show_default=True,
              help="Model backend: compiled C (auto) or the slow CasADi fallback.")
@click.option("--format", "formats", default=None, callback=_formats, metavar="LIST",
              help=f"Time-history formats, comma-separated: {_FORMATS_HELP}. Replaces [output] formats.")
@click.option("--figure-format", type=click.Choice(FIGURE_FORMAT_NAMES), default=None,
              help=f"Figure file format (default {DEFAULT_FIGURE_FORMAT}, or [output] figure_format).")
@click.option("--no-plots", is_flag=True, help="Do not write the figures.")
@click.option("--quiet", "-q", is_flag=True,
              help="Print only errors and the divergence message (the verdict is still in metrics.json, run.json).")
@_SET
def run(scenario: str | None, out: str | None, campaign: Path | None, case: int | None, duration: float | None,
        seed: int | None, controller: str | None, plant: str | None, backend: str, formats: tuple[str, ...] | None,
        figure_format: str | None, no_plots: bool, quiet: bool, sets: tuple[str, ...]) -> int:
    """Simulate SCENARIO (a TOML file) and write the results into a new folder.

    The folder gets timeseries.parquet (and the other --format files), metrics.json, run.json, a
    copy of the scenario and the figures.  The scenario's [output] table chooses the columns and
    rows written (docs/scenarios.md); the metrics always use every recorded step.  The output ends
    with the verdict: which goals were reached and when, and the main reason for each one that
    was not (docs/verdict.md).  Exit code 3 if the simulation diverged (the results up to that
    point are still written).

    With ``--campaign DIR --case N`` (no SCENARIO), case N of a Monte Carlo campaign is flown again
    alone, every step recorded, and checked against the campaign's record of it bit for bit.
    """
    if campaign is not None or case is not None:
        if scenario is not None or campaign is None or case is None:
            raise click.UsageError("give either SCENARIO, or --campaign DIR with --case N")
        given = [n for n, v in (("--duration", duration), ("--seed", seed), ("--controller", controller),
                                ("--plant", plant), ("--set", sets or None)) if v is not None]
        if given:
            raise click.UsageError(f"{', '.join(given)}: not with --campaign (the case would not be the campaign's "
                                   "run; edit the campaign file instead)")
    elif scenario is None:
        raise click.UsageError("missing SCENARIO (a scenario file), or --campaign DIR --case N")
    if not no_plots:  # matplotlib is imported by the figure workers while this process works
        from rpo.runtime.outputs.figure_workers import start
        start()
    from rpo.runtime.jobs.runner import execute_run
    from rpo.runtime.outputs.metrics import format_table

    loaded: list[Model] = []

    def model(controller: str) -> Model:  # called by the runner once the scenario and the folder are good
        loaded.append(_load_model(backend, quiet, controllers=[controller]))
        return loaded[0]

    source: Any = _source(scenario, sets) if scenario is not None else None
    camp = None
    if campaign is not None:
        from rpo.runtime.campaign.replay import case_scenario
        from rpo.runtime.campaign.storage import read_resolved
        m = model(read_resolved(campaign)["controller"])
        source, camp = case_scenario(campaign, int(case or 0), m)
        out = out if out is not None else str(campaign / "cases" / f"case_{case:06d}")
    bar = _ProgressBar(enabled=not quiet, step_cost=lambda: STEP_COST.get(loaded[0].backend, 2e-3))
    try:
        outcome = execute_run(source, out, loaded[0] if loaded else model, duration=duration, seed=seed,
                              controller=controller, plant=plant, plots=not no_plots, log=None if quiet else _err,
                              progress=bar.update,
                              formats=formats, figure_format=figure_format)
    finally:
        bar.close()
    result = outcome.result
    if camp is not None:
        from rpo.runtime.campaign.replay import compare
        assert campaign is not None and case is not None
        diffs = compare(campaign, camp, outcome.model, case, result, outcome.inputs)
        if diffs:
            _err(f"error: case {case} flown alone differs from the campaign's record: {'; '.join(diffs[:5])}")
            return 1
        if not quiet:
            from rpo.runtime.campaign.replay import compared
            click.echo(f"case {case} of {campaign}: the campaign's run, bit for bit ({compared(campaign, case)})")
    if result.divergence is not None:
        _err(f"diverged: {result.divergence.message()}")
        _err(f"results up to t = {result.t[-1]:.6g} s written to {outcome.out_dir}")
        if not quiet:
            click.echo(f"goal: {outcome.inputs.goal.get('text', '-')}")
            click.echo(outcome.metrics["verdict"]["line"])
        return EXIT_DIVERGED
    if not quiet:
        _summary(result, outcome.model, outcome.inputs, outcome.out_dir, outcome.write_time)
        click.echo("metrics (metrics.json; definitions in rpo.runtime.outputs.metrics):")
        from rpo.runtime.jobs.runner import ideal_actuators
        click.echo(format_table(outcome.metrics, ideal_actuators=ideal_actuators(outcome.inputs.params)))
        # the goal flown (the scenario's, runtime/scenario/goals.py), then the verdict last, so that the run
        # ends with it (rule: rpo.runtime.outputs.verdict, docs/verdict.md)
        click.echo(f"goal: {outcome.inputs.goal.get('text', '-')}")
        click.echo(outcome.metrics["verdict"]["line"])
    return 0


class _ProgressBar:
    """A click progress bar on stderr, opened at the first step count if the run is long enough
    (expected > 1 s) and stderr is a terminal."""

    def __init__(self, enabled: bool, step_cost: Callable[[], float]):
        self.enabled, self.step_cost = enabled, step_cost
        self.bar: Any = None
        self.done = 0

    def update(self, done: int, total: int) -> None:
        if self.bar is None:
            if not (self.enabled and total * self.step_cost() > 1.0 and sys.stderr.isatty()):
                self.enabled = False
                return
            self.bar = click.progressbar(length=total, label="simulating", file=sys.stderr, show_eta=True).__enter__()
        self.bar.update(done - self.done)
        self.done = done

    def close(self) -> None:
        if self.bar is not None:
            self.bar.__exit__(None, None, None)


def _summary(result, model, inputs, out_dir: Path, t_write: float) -> None:
    """Timing and where the results are; the errors (each controller's own) are in the metrics table."""
    z_lay = model.layouts[f"z_{inputs.controller}"]
    r = result.block("r", z_lay)[-1]
    m_prop = float(result.block("m_prop", z_lay)[-1, 0])
    click.echo(f"done: {result.steps_done} steps in {result.wall_time:.3g} s (+{t_write:.3g} s writing)")
    click.echo(f"final: separation {np.linalg.norm(r):.4g} m, propellant {m_prop:.4g} kg")
    click.echo(f"results: {out_dir}")


@cli.command()
@click.argument("run_list", default="scenarios", type=click.Path(path_type=str))
@click.option("--out", "out_base", default="runs/report", show_default=True, type=click.Path(file_okay=False),
              help="Base folder; each invocation writes its runs into a fresh <UTC time> folder inside.")
@click.option("--md", "md_path", default="docs/reproduction.md", show_default=True, type=click.Path(dir_okay=False),
              help="The markdown report to (re)write.")
@click.option("--json", "json_path", default="docs/reproduction.json", show_default=True,
              type=click.Path(dir_okay=False), help="Its JSON twin (all tables and metrics).")
@click.option("--notes", "notes_path", default="docs/reproduction_notes.toml", show_default=True,
              type=click.Path(dir_okay=False), help="Free text per paper (TOML; skipped if absent).")
@click.option("--only", multiple=True, help="Run only this label (repeatable).")
@click.option("--backend", type=BACKENDS, default="auto", show_default=True, help="Model backend.")
@click.option("--no-plots", is_flag=True, help="Do not write the PNG figures of the runs.")
@click.option("--quiet", "-q", is_flag=True, help="Print only errors.")
def report(run_list: str, out_base: str, md_path: str, json_path: str, notes_path: str, only: tuple[str, ...],
           backend: str, no_plots: bool, quiet: bool) -> int:
    """Run the reproduction runs and render the report (published values against ours) as
    markdown and JSON.

    RUN_LIST is a folder of scenario files (default: scenarios), whose [reproduction] tables
    declare the runs and published values, or a TOML run list.  Each run goes through the same
    code as `rpo run`; see rpo.runtime.jobs.reproduction for the formats.
    """
    from rpo.runtime.jobs.reproduction import make_report, summary_line

    model = _load_model(backend, quiet)
    state: dict = {"lines": []}

    def on_plan(runs):
        if not quiet:
            bar = click.progressbar(length=len(runs), label=f"report: {len(runs)} runs", file=sys.stderr,
                                    item_show_func=lambda r: r.label if r is not None else "")
            state["bar"] = bar.__enter__()

    def on_run(r):
        state["lines"].append(summary_line(r))
        if "bar" in state:
            state["bar"].update(1, r)

    try:
        twin = make_report(Path(run_list), model, out_base=Path(out_base), md_path=Path(md_path),
                           json_path=Path(json_path), notes_path=Path(notes_path), plots=not no_plots,
                           only=list(only) or None, on_run=on_run, on_plan=on_plan)
    finally:
        if "bar" in state:
            state["bar"].__exit__(None, None, None)
    if not quiet:
        for line in state["lines"]:
            click.echo(line)
        click.echo(f"runs: {twin['runs_dir']}\nreport: {md_path} (+ {json_path})")
    return 0


@cli.command()
@click.argument("scenario", type=click.Path(dir_okay=False, path_type=str))
@click.option("--backend", type=BACKENDS, default="auto", show_default=True,
              help="Model backend used to compute the initial state.")
@_SET
def validate(scenario: str, backend: str, sets: tuple[str, ...]) -> int:
    """Check SCENARIO without running it and print what it sets.

    Makes every check `rpo run` makes before its first step (the same function: the schema and
    ranges, the initial state, the controller's initial states, step 0 on trial), so a scenario
    called valid is one `rpo run` accepts.  Prints the run settings, the orbit, the initial state
    (attitudes relative to ECI and to LVLH) and every parameter the scenario changes from the
    manifest defaults.
    """
    from rpo.runtime.cli.campaign import campaign_or_scenario
    from rpo.runtime.model.manifest import read_manifest
    from rpo.runtime.run.preflight import preflight

    sc = campaign_or_scenario(scenario, _source(scenario, sets), read_manifest())  # a campaign: checked as mc run
    model = _load_model(backend, quiet=True)
    pre = preflight(sc, model)  # every check `rpo run` makes before its first step, by the same function
    inputs = pre.inputs

    p = {k: float(v[0]) if v.size == 1 else v for k, v in inputs.params.items()}
    n_steps = int(round(inputs.duration / inputs.dt))
    mu, a, e = p["mu"], p["orbit_a"], p["orbit_e"]
    q_IL = inputs.frame_info["q_IL0"]
    echo = click.echo
    echo(f"{scenario}: valid")
    for note in pre.notes:
        _err(f"warning: {note}")
    echo(f"  name        {sc.name}" + (f": {sc.meta.description}" if sc.meta.description else ""))
    echo(f"  run         {inputs.duration:g} s, dt = {inputs.dt:g} s ({n_steps} steps), controller "
         f"{inputs.controller}, seed {inputs.seed}, record every {inputs.record_every}")
    echo(f"  goal        {inputs.goal['text']}")  # the goal flown (runtime/scenario/goals.py)
    if not inputs.goal["mapped"]:
        _err(f"warning: {inputs.controller} flies its own goal gains: rpo has no goal mapping for it")
    if inputs.goal.get("warning"):
        _err(f"warning: {inputs.goal['warning']}")
    h_p = (a * (1 - e) - p["r_earth"]) / 1e3
    echo(f"  orbit       a = {a / 1e3:.6g} km, e = {e:g}, perigee altitude {h_p:.6g} km, "
         f"i = {math.degrees(p['orbit_inc']):g} deg, period {2 * math.pi * math.sqrt(a**3 / mu) / 60:.5g} min, "
         f"LVLH rate n(0) = {inputs.frame_info['n0']:.6g} rad/s")
    from rpo.runtime.jobs.runner import plant_summary
    summary = plant_summary(inputs.params, None)
    echo(f"  plant       target orbit {summary['target_orbit']}; {summary['actuators']}")
    pl = inputs.plant
    for body, q, w in (("chaser", pl["q_c"], pl["w_c"]), ("target", pl["q_t"], pl["w_t"])):
        q_L = frames.attitude_from_eci(q, "lvlh", q_IL)
        echo(f"  {body:<11s} q_ECI = {_vec(q, '.6f')}, q_LVLH = {_vec(q_L, '.6f')}, "
             f"w = {_vec(np.degrees(w), '.6g')} deg/s")
    q_r = frames.quat_multiply(frames.quat_conjugate(pl["q_t"]), pl["q_c"])
    echo(f"  relative    r = {_vec(pl['r'], 'g')} m (|r| = {np.linalg.norm(pl['r']):.4g} m), "
         f"v = {_vec(pl['v'], 'g')} m/s, chaser-to-target rotation {np.degrees(frames.rotation_angle(q_r)):.4g} deg")
    echo(f"  wheels      h_w = {_vec(pl['h_w'], '.6g')} N m s")
    echo("  gains       " + ", ".join(f"{k} = {_fmt(v)}" for k, v in inputs.gains.items()))
    if sc.faults:
        fdir = "fault-aware allocation" if float(np.ravel(p["fdir_allocation"])[0]) == 1.0 else "nominal allocation"
        echo("  faults      " + "; ".join(
            f"{f.kind} {f.unit_name()} from {f.time:g} s" + ("" if f.end is None else f" to {f.end:g} s")
            + ("" if f.value is None else f" (value {f.value})") for f in sc.faults) + f"; {fdir}")
    defaults = model.defaults("p")
    changed = [k for k, v in inputs.params.items() if k in defaults and not np.array_equal(v, defaults[k])]
    units = {f.name: f.unit for f in model.layouts["p"]}
    echo(f"  parameters  {len(changed)} differ from the manifest defaults:")
    for k in changed:
        echo(f"    {k:<18s} {_fmt(inputs.params[k]):>28s} {units[k]:<8s} (default {_fmt(defaults[k])})")
    return 0


def _preset_word(f: LayoutField) -> str:
    """The full preset's value of a switch or choice parameter, as a scenario writes it."""
    v = float(f.presets["full"][0])
    sk = f.scenario
    if sk is not None and sk.kind == "choice":
        return next((f'"{name}"' for name, val in sk.choices.items() if float(val) == v), f"{v:g}")
    return "true" if v == 1.0 else "false"


def _vec(v, fmt: str) -> str:
    return "[" + ", ".join(format(float(x), fmt) for x in np.ravel(v)) + "]"


def _fmt(v) -> str:
    a = np.ravel(np.asarray(v, float))
    return format(float(a[0]), ".8g") if a.size == 1 else _vec(a, ".6g")


@cli.command()
@click.argument("scenario", type=click.Path(dir_okay=False, path_type=str))
@click.option("--controller", default=None, help="Override simulation.controller (see `rpo info`).")
@click.option("--plant", type=click.Choice(["paper", "full"]), default=None,
              help="paper (default): the scenario's own plant; full: the common full-fidelity plant.")
@click.option("--at", "at", type=click.Choice(["goal", "initial"]), default="goal", show_default=True,
              help="goal: the state the controller regulates to (its q_err, rate_err, pos_err, vel_err zero); "
                   "initial: the scenario's initial state.")
@click.option("--json", "as_json", is_flag=True, help="Print the linearisation (A, labels, groups, modes) as JSON.")
@_SET
def linearize(scenario: str, controller: str | None, plant: str | None, at: str, as_json: bool,
              sets: tuple[str, ...]) -> int:
    """Eigenvalues of SCENARIO's closed-loop step linearised at its goal (or initial state).

    The step's Jacobian is CasADi AD of the generated step_<controller>, in reduced coordinates
    (attitudes as rotation vectors, actuator and controller states listed separately); see
    docs/linearization.md and rpo.runtime.run.linearize.
    """
    import json

    from rpo.runtime.model.manifest import read_manifest
    from rpo.runtime.run.linearize import format_report, linearize_scenario
    from rpo.runtime.scenario import load_scenario

    source = _source(scenario, sets)
    load_scenario(source, read_manifest())  # a bad file fails before anything is compiled
    res = linearize_scenario(source, model=None, controller=controller, plant=plant, at=at, log=_loader(False))
    if as_json:
        out = {"scenario": res.scenario, "at": res.at, "plant": res.plant, **res.lin.to_json(),
               "z": res.lin.z.tolist(), "z_labels": res.lin.coords.z_labels}
        click.echo(json.dumps(out))
    else:
        click.echo(format_report(res))
    return 0


@cli.command()
@click.option("--backend", type=BACKENDS, default="auto", show_default=True,
              help="Backend to load (compiles the model into the cache if needed).")
def info(backend: str) -> int:
    """Show the generated model: source hash, tools, library, functions, layouts, parameters."""
    from rpo.runtime.scenario import ScenarioParam

    model = _load_model(backend, quiet=False)
    m = model.manifest
    echo = click.echo

    def version(pkg):
        try:
            return metadata.version(pkg)
        except metadata.PackageNotFoundError:
            return "not installed"

    echo(f"rpo {version('rpo')}  (python {sys.version.split()[0]})")
    echo(f"model            {len(m.functions)} functions in {len(m.families)} families, "
         f"source hash {m.source_hash}")
    echo("generated with   " + ", ".join(f"{k} {v}" for k, v in sorted(m.tools.items())))
    echo("runtime          " + ", ".join(f"{k} {version(k)}" for k in ("numpy", "scipy", "matplotlib", "pydantic",
                                                                          "click")))
    echo(f"backend          {model.backend}" + (f", library {model.library}" if model.library else ""))
    if model.backend == "compiled":
        from rpo.runtime.model import fastcall

        native, _target = native_target(find_compiler() or ["cc"])
        echo(f"lockstep lanes   built on first batch for {' '.join(native) or 'the default target'} "
             "(runtime/model/lanes.py; Simulation.run_batch, f.batch)")
        echo("single calls     " + ("in place (fast-call extension)" if not fastcall.why_not
                                    else f"ctypes ({fastcall.why_not[0]})"))
    echo(f"quaternions      {m.quaternion_convention or '?'}")
    # the two plants: a scenario's own values, or the full preset over them (--plant full)
    p = m.layouts["p"]
    switches = [(f.scenario.key, f) for f in p if f.presets.get("full") and f.size == 1 and f.scenario is not None
                and f.scenario.kind in ("switch", "choice")]
    echo("plants           paper (default): the scenario's own values; full (--plant full): " + ", ".join(
        f"{key} = {_preset_word(f)}" for key, f in switches) + "; target orbit of the defaults: "
        + ("propagated" if float(p.defaults["orbit_propagated"][0]) else "kepler"))
    echo("controllers      " + ", ".join(f"{k} (gains {v.gains})" for k, v in sorted(m.controllers.items())))
    echo("\nfunctions:")
    for name, f in sorted(m.functions.items()):
        ins = ", ".join(f"{i.name}[{i.shape[0]}]" for i in f.inputs)
        outs = ", ".join(f"{o.name}[{'x'.join(map(str, o.shape)) if o.shape[1] > 1 else o.shape[0]}]"
                         for o in f.outputs)
        echo(f"  {name:<24s} ({ins}) -> ({outs})")
        echo(f"  {'':<24s} {f.doc}")
    echo("\nlayouts:")
    for name, lay in m.layouts.items():
        echo(f"  {name:<16s} {lay.size:>4d} values: " + ", ".join(lay.names))
    def table(layout):
        for f in layout:
            default = _fmt(f.default) if f.default is not None else "-"
            echo(f"  {f.name:<18s} {f.unit:<9s} {default:>40s}  {f.doc}")
            if f.scenario is not None:  # where a scenario file sets it, in which unit, and its bounds
                prm = ScenarioParam.from_field(f)
                unit = f" [{prm.unit}]" if prm.unit not in ("", "-") else ""
                echo(f"  {'':<18s} {'':<9s} {'':>40s}  scenario: {prm.key}{unit}"
                     + (f", {prm.allowed()}" if prm.bounds else ""))

    echo("\nparameters (layout p, SI):")
    echo(f"  {'name':<18s} {'unit':<9s} {'default':>40s}  description")
    table(p)
    for ctrl, entry in sorted(m.controllers.items()):
        echo(f"\ngains of {ctrl} (layout {entry.gains}; [controller.{ctrl}] in a scenario):")
        table(m.layouts[entry.gains])
    return 0


@cli.command()
@click.option("--scenarios", "folder", type=click.Path(file_okay=False, exists=True, path_type=Path),
              default=Path("scenarios"), show_default=True, help="Folder of scenario files.")
@click.option("--write", "target", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Write the table here (e.g. docs/scenarios.md) instead of printing it.")
@click.option("--check", "check", type=click.Path(dir_okay=False, exists=True, path_type=Path), default=None,
              help="Exit 1 if this file differs from the table (for CI).")
def choices(folder: Path, target: Path | None, check: Path | None) -> int:
    """Table of the values the scenario files mark as chosen (the papers are silent there)."""
    from rpo.runtime.docgen.choices import render, scenario_files

    text = render(scenario_files(folder))
    if check is not None:
        if check.read_text() != text:
            _err(f"{check} is out of date: run `rpo choices --write {check}`")
            return 1
        return 0
    if target is None:
        click.echo(text, nl=False)
        return 0
    tmp = target.with_name(f".{target.name}.tmp")
    tmp.write_text(text)
    tmp.replace(target)
    _err(f"wrote {target}")
    return 0


@cli.command()
@click.argument("name", required=False)
@click.option("--to", "to", type=click.Path(path_type=str), default=None,
              help="Copy NAME to this file (or into this folder) for editing; never overwrites a file.")
def scenarios(name: str | None, to: str | None) -> int:
    """The scenarios shipped with rpo: list them, or copy one out for editing.

    \b
      rpo scenarios                               (name and description of each)
      rpo scenarios 001_scenario --to my.toml     (a copy to edit, then: rpo run my.toml)
      rpo scenarios campaigns/000_III_mc          (where the shipped file is, to run it as it is)

    A variant is copied with the files it extends, next to it.
    """
    from rpo.runtime.scenario import shipped

    if name is None:
        if to is not None:
            raise click.UsageError("--to needs the NAME of the scenario to copy (`rpo scenarios` lists them)")
        items = shipped.shipped()
        width = max(len(s.name) for s in items)
        click.echo(f"{'name':<{width}}  description")
        for s in items:
            click.echo(f"{s.name:<{width}}  {s.description}")
        _err(f"{len(items)} shipped scenarios and campaigns in {shipped.folder()}; "
             "copy one to edit: rpo scenarios NAME --to FILE")
        return 0
    if to is None:
        click.echo(shipped.find(name).path)
        return 0
    for c in shipped.copy_out(name, to):
        if not c.written:
            _err(f"{c.path}: there already, identical to the shipped {c.source.name}")
        else:
            _err(f"wrote {c.path}" + ("" if c.path.name == c.source.name else f" (a copy of {c.source.name})"))
    return 0


# --------------------------------------------------------------------------- entry point


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rpo`` script: user errors become one ``error:`` line and exit code 2."""
    warnings.formatwarning = _format_warning
    interrupts.install()  # SIGINT and SIGTERM: exit 130 / 143, never a half-written folder
    try:
        rv = cli.main(args=argv, prog_name="rpo", standalone_mode=False)
    except click.exceptions.Abort as exc:  # click wraps a KeyboardInterrupt (ours: Interrupted)
        cause = exc.__cause__ or exc.__context__
        _err(f"error: {cause}" if isinstance(cause, interrupts.Interrupted) else "error: interrupted")
        return getattr(cause, "exit_code", 130)
    except _NO_ARGS as exc:  # `rpo` alone: the help, as click does, on stderr
        _err(exc.format_message())
        return EXIT_USAGE
    except click.ClickException as exc:
        _err(f"error: {' '.join(exc.format_message().split())}")
        return EXIT_USAGE
    except RpoError as exc:
        _err(f"error: {exc}")
        return EXIT_USAGE
    except OSError as exc:  # a full disk, no permission, a read-only cache: the machine's, said in one line
        from rpo.runtime.cli.campaign import os_error_line
        _err(f"error: {os_error_line(exc, None, 'run the command again')}")
        return 1
    except KeyboardInterrupt as exc:
        _err(f"error: {exc}" if isinstance(exc, interrupts.Interrupted) else "error: interrupted")
        return getattr(exc, "exit_code", 130)
    return rv if isinstance(rv, int) else 0


def _register() -> None:
    from rpo.runtime.cli.campaign import mc
    from rpo.runtime.cli.compile import build_cmd, cache
    from rpo.runtime.cli.flight import export_cmd, pil_cmd
    from rpo.runtime.cli.view import view
    for command in (mc, build_cmd, cache, view, export_cmd, pil_cmd):
        cli.add_command(command)


_register()


if __name__ == "__main__":  # python -m rpo.runtime.cli.main
    sys.exit(main())
