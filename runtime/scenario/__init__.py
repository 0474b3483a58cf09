"""Scenario files: a TOML description of one run, validated into the inputs of a simulation.

Every table and key is optional unless marked *required*.  Unknown keys are errors.  Two kinds of
key exist:

* **parameters** of the model (orbit, environment, bodies' mass properties, wheels, thrusters,
  plant options, disturbances, sensors, constraints, the step): their key, unit, scale to SI and
  admissible range are recorded per field of layout ``p`` in ``generated/manifest.json`` (declared
  in ``symbolic/physics/plant.py``; ``rpo info`` lists them with their keys).  An omitted parameter takes
  the manifest default;
* the keys written in :mod:`.schema`: ``[meta]`` (name, description, source); ``[simulation]``
  ``duration`` (*required*, s), ``seed``, ``controller``, ``record_every``;
  ``orbit.perigee_altitude`` (m, instead of the semi-major axis); the initial state of
  ``[chaser]`` and ``[target]`` (*required* ``attitude_frame`` = ``"eci"``, ``"lvlh"`` or
  ``"orbit"`` and ``quaternion`` [x, y, z, w] relative to it; ``angular_velocity`` rad/s or
  ``angular_velocity_deg_s``, body axes, relative to ECI or, with
  ``angular_velocity_relative_to = "attitude_frame"``, to that frame; chaser ``wheel_speed_rpm``
  relative to the body or ``wheel_momentum`` N m s); ``[relative]`` ``position`` [m] and
  ``velocity`` [m/s] in LVLH (*required*); ``[goal]`` (:mod:`.goals`): the pose to reach and hold,
  ``position`` [m] of the chaser relative to the target in ``frame`` (``"target"``: the target's
  axes; ``"lvlh"``), ``attitude`` [x, y, z, w] of the chaser relative to the target, optional
  ``camera_at_target`` and ``contact`` (each *required* but the last two; without the table, the
  goal gains of the scenario's own controller state the goal; ``rpo run --controller`` keeps it);
  ``[controller.<name>]`` gains by the names of the
  manifest layout ``k_<name>``; ``[reproduction]`` (:mod:`.reproduction`); ``[output]``
  (what a run writes: ``channels``, ``every`` or ``rate_hz``, ``formats``, ``figures``,
  ``figure_format``; :class:`~.schema.OutputSection`, docs/scenarios.md).

``extends = "<base>.toml"`` makes a variant of a base file (:mod:`.loader`; every file read is a
regular UTF-8 file of at most 1 MiB).  Every parameter and gain has a range (``docs/parameters.md``,
:mod:`.ranges`); :mod:`.preflight` makes the checks of a run before its first step, for ``rpo run``
and ``rpo validate`` alike.  Every error is ONE
line naming the file, the dotted key, the offending value and the allowed range, e.g.
``scenario.toml: orbit.eccentricity = 1.2: must be in [0, 1)``, raised as
:class:`~rpo.runtime.errors.ScenarioError` (:mod:`.messages`).

Modules: :mod:`.loader` (TOML and ``extends``), :mod:`.params` (the manifest's parameter
entries), :mod:`.sections` (the value types and static sections), :mod:`.schema` (the scenario and
its schema per manifest, validation), :mod:`.checks` (the checks across keys), :mod:`.goals` (the
goal and each controller's goal coordinates), :mod:`.initial_state` (to the inputs of a run),
:mod:`.messages` (error text), :mod:`.reproduction` (the report's table),
:mod:`.preflight`, :mod:`.ranges`,
:mod:`.shipped` (the scenarios shipped with rpo, read through importlib.resources).

Validation takes the typed manifest (:class:`~rpo.runtime.model.manifest.Manifest`, ``model.manifest``
or :func:`~rpo.runtime.model.manifest.read_manifest`) explicitly; only the user-facing
:func:`load_scenario` and :func:`loads_scenario` read the generated model's when given none.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rpo.runtime.model.manifest import Manifest, read_manifest
from rpo.runtime.scenario import shipped
from rpo.runtime.scenario.checks import MAX_RECORD_BYTES
from rpo.runtime.scenario.initial_state import RunInputs, run_inputs
from rpo.runtime.scenario.loader import ScenarioSource, merge, parse_toml, read_scenario
from rpo.runtime.scenario.messages import format_error
from rpo.runtime.scenario.params import Interval, ScenarioParam, manifest_defaults
from rpo.runtime.scenario.reproduction import Reproduction
from rpo.runtime.scenario.schema import (
    Scenario,
    ScenarioSchema,
    apply_preset,
    scenario_model,
    scenario_params,
    validate_scenario,
)
from rpo.runtime.scenario.sections import QUAT_TOL
from rpo.runtime.scenario.units import DEG, RPM

#: The shipped scenarios (package data of ``rpo.scenarios``, :mod:`.shipped`): this checkout's
#: ``scenarios/`` after ``pip install -e .``, ``site-packages/rpo/scenarios`` otherwise.
SCENARIO_DIR = shipped.folder()

__all__ = [
    "DEG", "MAX_RECORD_BYTES", "QUAT_TOL", "RPM", "SCENARIO_DIR", "Interval", "Reproduction", "RunInputs",
    "Scenario", "ScenarioParam", "ScenarioSchema", "ScenarioSource", "apply_preset", "format_error", "load_scenario",
    "loads_scenario", "manifest_defaults", "merge", "paper_data", "parse_toml", "read_scenario", "run_inputs",
    "scenario_model", "scenario_params", "shipped", "validate_scenario",
]


def load_scenario(path: str | Path | ScenarioSource, manifest: Manifest | None = None) -> Scenario:
    """Read and validate a scenario file (TOML, optionally ``extends`` a base file), or validate one
    already read by :func:`read_scenario`, against ``manifest``.  A user's entry point: without a
    manifest it reads the generated model's here (:func:`read_manifest`, once per process); code
    holding a model passes ``model.manifest``."""
    src = path if isinstance(path, ScenarioSource) else read_scenario(path)
    sc = validate_scenario(src.data, src.source, read_manifest() if manifest is None else manifest)
    sc._text = src.text
    return sc


def loads_scenario(text: str, source: str = "scenario", manifest: Manifest | None = None) -> Scenario:
    """Validate a scenario given as TOML text (``source`` names it in error messages); ``manifest`` as
    for :func:`load_scenario`."""
    data = parse_toml(text, source)
    sc = validate_scenario(data, source, read_manifest() if manifest is None else manifest)
    sc._text = text
    return sc


def paper_data(name: str | Path, folder: Path | None = None) -> dict[str, Any]:
    """The table of a scenario file as written (``extends`` resolved, not validated): the one place
    a paper's gains, initial state and published values are typed, for tests and scripts to read
    instead of retyping them.  ``name`` is a path, or a file stem in ``folder`` (default: the shipped
    scenarios, :data:`SCENARIO_DIR`, in every install mode):
    ``paper_data("000_scenario_III")["orbit"]["eccentricity"]``, ``paper_data("campaigns/000_III_mc")``."""
    path = Path(name)
    if not path.suffix:
        path = (folder or SCENARIO_DIR) / f"{name}.toml"
    return read_scenario(path).data
