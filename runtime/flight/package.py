"""``rpo export``: one controller as a self-contained C99 package, with its test vectors.

The package is written into a fresh temporary folder beside ``out`` and renamed into place at the
end, so an interrupted export leaves nothing half-written and an existing folder is never touched
(refused, in one line).  What it holds is listed in its README (:func:`readme`).
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from rpo.runtime.errors import ModelError, OutputError, ScenarioError
from rpo.runtime.flight import csource, testprog
from rpo.runtime.flight import vectors as vec
from rpo.runtime.flight.emit import PRECISIONS, load_function
from rpo.runtime.flight.interface import Interface, controller_interface
from rpo.runtime.model.manifest import Manifest, generated_dir, read_manifest
from rpo.runtime.model.toolchain import csrc_dir

#: the shipped scenario each paper design's vectors are recorded from (c002: the paper's gains diverge at 1.7 s,
#: docs/reproduction.md, so its kappa1 = 3 variant; others: the first shipped
#: scenario, in name order, that flies the controller)
DEFAULT_SCENARIO = {"c000": "000_scenario_I", "c001": "001_scenario", "c002": "002_scenario_kappa3",
                    "c004": "004_scenario", "baseline": "ref_scenario"}

#: the MISRA C:2012 deviations every package ships (and is checked against)
DEVIATIONS = Path(__file__).with_name("data") / "misra_deviations.toml"

#: test vectors recorded by default (steps from t0): the transient, where every branch of a law is visited
DEFAULT_VECTOR_STEPS = 1000

#: the single-precision package's test tolerance, relative to each output's scale over the recorded run
SINGLE_TOLERANCE = 5e-2


@dataclass(frozen=True)
class Export:
    """A written package: its folder, interface, vectors and files."""

    folder: Path
    interface: Interface
    precision: str
    vectors: vec.Vectors
    files: tuple[str, ...]
    scenario: str
    rate_hz: float


def default_scenario(controller: str) -> str:
    from rpo.runtime.scenario.shipped import shipped

    if controller in DEFAULT_SCENARIO:
        return DEFAULT_SCENARIO[controller]
    from rpo.runtime.jobs.api import scenario as load

    for name in (s.name for s in shipped() if "/" not in s.name):
        try:
            if load(name).simulation.controller == controller:
                return name
        except ScenarioError:
            continue
    raise ScenarioError(f"no shipped scenario flies controller {controller!r}: give one with --scenario")


def functions(manifest: Manifest, controller: str) -> tuple[object, object | None]:
    """The CasADi functions of the export (``control_<name>``, ``xc0_<name>`` or None), from the
    generated files the manifest verified."""
    spec = manifest.controller(controller)
    gen = generated_dir()
    control = load_function(gen / f"{spec.control}.casadi.gz")
    start = load_function(gen / f"{spec.xc0}.casadi.gz") if spec.xc0 else None
    return control, start


def _check_out(out: Path) -> None:
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise OutputError(f"{out} exists and is not an empty folder: give a new --out (nothing was written)")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"{parent} is not a folder: create it or give another --out (nothing was written)")
    if not os.access(parent, os.W_OK):
        raise OutputError(f"{parent} is not writable: give another --out (nothing was written)")


def record(controller: str, scenario: str, rate_hz: float | None, steps: int,
           log: Callable[[str], None] | None = None) -> tuple[Interface, vec.Vectors, float, Manifest]:
    """Fly ``scenario`` with ``controller`` for ``steps`` steps and return the export's interface and
    the recorded vectors (and the rate flown)."""
    from rpo.runtime.jobs.api import scenario as load
    from rpo.runtime.model.loader import load_model
    from rpo.runtime.run.preflight import preflight

    overrides: dict[str, object] = {"simulation.controller": controller}
    if rate_hz is not None:
        overrides["simulation.rate"] = rate_hz
    sc = load(scenario, overrides)
    model = load_model(log=log if log is not None else False, controllers=[controller])
    pre = preflight(sc, model)
    sim = pre.sim
    n = min(steps, int(round(pre.inputs.duration / sim.dt)))
    result = sim.run(pre.z0, n * sim.dt, seed=pre.inputs.seed, record_every=1)
    if result.divergence is not None:
        raise ModelError(f"the vector run of {scenario}: {result.divergence.message()}: give another --scenario "
                         "or fewer --vectors")
    control, start = functions(model.manifest, controller)
    iface = controller_interface(model.manifest, controller, control, start)
    v = vec.from_run(iface, model, sim, result, f"`rpo run {scenario} --controller {controller}`, seed "
                     f"{pre.inputs.seed}, dt {sim.dt!r} s")
    return iface, v, 1.0 / sim.dt, model.manifest


def readme(e_iface: Interface, precision: str, rate_hz: float, scenario: str, v: vec.Vectors,
           stack: dict[str, int] | None) -> str:
    p = e_iface.prefix
    also = f" and `{e_iface.start_function}`" if e_iface.start_function else ""
    start = (f"1. `{p}_start(&state, &params, &in)` once with the first measurement (the design starts its "
             "states from it);\n" if e_iface.has_start else "")
    stack_text = ("".join(f"- {n} bytes on {t}\n" for t, n in sorted(stack.items())) if stack
                  else "- not measured (run `rpo export` where gcc is installed)\n")
    rows = []
    for struct in ("inputs", "params", "state", "outputs"):
        for g, m in e_iface.members(struct):
            rows.append(f"| {struct} | `{g.path}{m.name}` | {m.size} | {m.unit} | {m.doc} |")
    return f"""# {p}: rpo controller `{e_iface.controller}` as flight code ({precision} precision)

Written by `rpo export {e_iface.controller}`. Generated: edit the symbolic model and export again instead.
The algorithm is the simulation's own (the generated function `{e_iface.function}`{also}):
the law, its own integration (one RK4 step with the inputs held), its saturations. The plant, the wheel
pyramid and thruster-duty allocation and the PWPF modulator are not in it (the actuator electronics'
side in rpo's model).

## Use
1. Fill a `{p}_params_t` (the gains and the plant values the law reads; units below);
1. `{p}_initialize(&state, &params)`;
{start}1. every 1/{rate_hz:g} s (`{p.upper()}_RATE_HZ`): fill `{p}_inputs_t` with the sample, call
   `{p}_step(&state, &params, &in, &out)`, apply `out.tau_w`, `out.F`, `out.tau_thr`;
1. `{p}_terminate(&state)` at the end.

No heap, no mutable global or static data, no recursion, no variable-length array, no I/O; every
struct is the caller's, so the functions are reentrant. Units SI; quaternions scalar-last [x, y, z, w],
Hamilton product. C99; build with `-ffp-contract=off` (no fused multiply-add) and without
`-ffast-math`: the double-precision package then gives the simulation's outputs bit for bit.

## Files
- `{p}.h`, `{p}.c`: the interface and the controller; `rpo_math.h` (double precision): rpo's own
  portable math functions (the simulation's), header-only;
- `{p}_io.h`, `{p}_io.c`: the structs to and from flat arrays (test drivers, telemetry, PIL);
- `{p}.json`: the interface as data (members, units, where each comes from in rpo's vectors);
- `test_{p}.c`, `{p}_vectors.txt`: the host test ({v.steps} steps recorded from {v.source});
- `misra_deviations.toml`: the MISRA C:2012 deviations, each with its rule and reason (all in
  `rpo_math.h` or the headers' interface macros; the controller's own code has none);
- `Makefile`: `make test` builds and runs it ({'bit for bit' if precision == 'double' else 'within the tolerance'}).

## Worst-case stack of one step
{stack_text}
## Members
| struct | member | size | unit | meaning |
| --- | --- | --- | --- | --- |
""" + "\n".join(rows) + "\n"


def write_package(controller: str, out: Path, precision: str = "double", rate_hz: float | None = None,
                  scenario: str | None = None, steps: int = DEFAULT_VECTOR_STEPS,
                  log: Callable[[str], None] | None = None,
                  measure_stack: Callable[[Path, Interface, str], dict[str, int]] | None = None) -> Export:
    """Export ``controller`` into the new folder ``out`` (see the module docstring)."""
    if precision not in PRECISIONS:
        raise ScenarioError(f"--precision must be one of {', '.join(PRECISIONS)}, got {precision!r}")
    if rate_hz is not None and not (0.0 < rate_hz <= 1e4):
        raise ScenarioError(f"--rate must be in (0, 10000] Hz, got {rate_hz!r}")
    if steps < 1:
        raise ScenarioError(f"--vectors must be at least 1 step, got {steps}")
    manifest = read_manifest()
    if controller not in manifest.controllers:
        raise ScenarioError(f"unknown controller {controller!r}; known: {', '.join(sorted(manifest.controllers))}")
    out = Path(out)
    _check_out(out)
    scen = scenario or default_scenario(controller)
    iface, v, rate, manifest = record(controller, scen, rate_hz, steps, log)
    from importlib import metadata

    __version__ = metadata.version("rpo")

    spec = manifest.controller(controller)
    names = [f"{spec.control}.casadi.gz"] + ([f"{spec.xc0}.casadi.gz"] if spec.xc0 else [])
    prov = csource.Provenance(__version__, manifest.manifest_hash, {n: manifest.files[n] for n in names},
                              manifest.quaternion_convention, scen, rate)
    control, start = functions(manifest, controller)
    p = iface.prefix
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent if str(out.parent) else "."))
    try:
        sources = [f"{p}.c", f"{p}_io.c"]
        files = {f"{p}.c": csource.source(iface, prov, precision, control, start)}
        files[f"{p}_io.h"], files[f"{p}_io.c"] = csource.io_files(iface, prov, precision)
        files[f"test_{p}.c"] = testprog.test_program(iface, precision)
        files["Makefile"] = testprog.makefile(iface, precision, sources)
        files[f"{p}.json"] = json.dumps({**iface.json(), "precision": precision, "rate_hz": rate,
                                         "scenario": scen, "provenance": prov.function_sha256,
                                         "manifest_hash": prov.manifest_hash}, indent=1) + "\n"
        files[f"{p}.h"] = csource.header(iface, prov, precision, None)
        for name, text in files.items():
            (tmp / name).write_text(text)
        if precision == "double":
            shutil.copyfile(csrc_dir() / "rpo_math.h", tmp / "rpo_math.h")
        shutil.copyfile(DEVIATIONS, tmp / "misra_deviations.toml")
        vec.write(tmp / f"{p}_vectors.txt", iface, v, SINGLE_TOLERANCE if precision == "single" else None)
        stack = measure_stack(tmp, iface, precision) if measure_stack is not None else None
        (tmp / f"{p}.h").write_text(csource.header(iface, prov, precision, stack))
        (tmp / "README.md").write_text(readme(iface, precision, rate, scen, v, stack))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)  # mkdtemp's 0700 is for the temporary folder, not the package
        if out.exists():
            out.rmdir()  # empty (checked above): replaced by the finished package
        os.replace(tmp, out)
    except OSError as exc:
        raise OutputError(f"cannot write the package into {out.parent}: {exc.strerror or exc}") from None
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
    return Export(out, iface, precision, v, tuple(sorted(p_.name for p_ in out.iterdir())), scen, rate)
