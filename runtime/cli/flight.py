"""``rpo export CONTROLLER --out DIR`` and ``rpo pil SCENARIO --controller NAME``: the flight-code commands
(:mod:`rpo.runtime.flight`), registered on the ``rpo`` group by :mod:`rpo.runtime.cli.main`."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from rpo.runtime.errors import ScenarioError


def _err(msg: str) -> None:
    click.echo(msg, err=True)


@click.command("export")
@click.argument("controller")
@click.option("--out", "out", type=click.Path(path_type=Path), required=True,
              help="The package folder to write (must not exist, or be empty).")
@click.option("--precision", type=click.Choice(["double", "single"]), default="double", show_default=True,
              help="The real type of the package: double gives the simulation's outputs bit for bit.")
@click.option("--rate", "rate", type=float, default=None, metavar="HZ",
              help="The step rate the package is for (its test vectors are flown at it); default: the scenario's.")
@click.option("--scenario", default=None, metavar="SCENARIO",
              help="The scenario the test vectors are recorded from (default: the controller's shipped one).")
@click.option("--vectors", "steps", type=int, default=None, metavar="N",
              help="Test-vector steps recorded from t0 (default 1000).")
@click.option("--check/--no-check", default=False, show_default=True,
              help="Run the flight-code checks on the written package (compilers, stack, symbols, MISRA) and "
                   "print their figures.")
def export_cmd(controller: str, out: Path, precision: str, rate: float | None, scenario: str | None,
               steps: int | None, check: bool) -> int:
    """Write CONTROLLER as a self-contained C99 package: named structs, initialize/step/terminate, no
    heap, no globals; a README, a Makefile and test vectors recorded from a closed-loop run."""
    from rpo.runtime.flight.package import DEFAULT_VECTOR_STEPS, write_package
    from rpo.runtime.flight.stack import header_stack
    e = write_package(controller, out, precision=precision, rate_hz=rate, scenario=scenario,
                      steps=steps if steps is not None else DEFAULT_VECTOR_STEPS,
                      log=lambda m: _err(m), measure_stack=header_stack)
    click.echo(f"wrote {e.folder}: {e.interface.prefix} ({precision}), {len(e.files)} files, "
               f"{e.vectors.steps} test-vector steps from {e.scenario} at {e.rate_hz:g} Hz")
    if check:
        from rpo.runtime.flight.checks import check_package

        result = check_package(e.folder, precision, e.folder / "misra_deviations.toml")
        click.echo(result.format_report())
        return 0 if result.passed else 1
    return 0


@click.command("pil")
@click.argument("scenario")
@click.option("--controller", required=True, help="The controller to export and fly on the target.")
@click.option("--precision", type=click.Choice(["double", "single"]), default="double", show_default=True)
@click.option("--on", "where", type=click.Choice(["qemu", "host"]), default="qemu", show_default=True,
              help="qemu: the package cross-compiled for an emulated Cortex-M7 (double) or M4F (single); host: "
                   "compiled for this machine.")
@click.option("--duration", type=float, default=None, help="Seconds to fly (default: the scenario's).")
@click.option("--package", "package", type=click.Path(path_type=Path), default=None,
              help="An existing export to fly (default: exported afresh into a temporary folder).")
@click.option("--json", "as_json", is_flag=True, help="Print the figures as one JSON line.")
def pil_cmd(scenario: str, controller: str, precision: str, where: str, duration: float | None,
            package: Path | None, as_json: bool) -> int:
    """Fly SCENARIO with CONTROLLER's exported package in the loop (on an emulated flight processor by
    default) against rpo's plant, and compare the run with the simulation's."""
    from rpo.runtime.flight.pil import fly_in_the_loop

    if duration is not None and not duration > 0:
        raise ScenarioError(f"--duration must be > 0 s, got {duration}")
    report = fly_in_the_loop(scenario, controller, precision=precision, where=where, duration=duration,
                             package=package, log=_err)
    if as_json:
        click.echo(json.dumps(report.json()))
    else:
        click.echo(report.text())
    sys.stdout.flush()
    return 0 if report.passed else 1
