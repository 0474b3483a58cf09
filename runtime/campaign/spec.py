"""Campaign files: a scenario (``extends``) plus ``[campaign]`` and ``[dispersions]``.

::

    extends = "../000_scenario_III.toml"

    [campaign]
    name = "000 III dispersed"     # default: the file's stem
    runs = 1000                    # >= 1
    sampling = "random"            # random | lhs | sobol | sobol-indices (rpo.runtime.campaign.sampling)
    seed = 1                       # the root of every draw and of the runs' noise seeds
    rate_hz = 1.0                  # the runs' record (metrics, histories); or record_every (steps)
    channels = ["q_c", "r", ...]   # the histories' columns (default CHANNELS); err_att_rad,
                                   # err_pos_m and h_w_norm are always added
    batch = 32                     # runs per task sent to a worker (default: 4 lane blocks)

    [dispersions.relative.position]  # any scenario key, dotted as in the file
    dist = "normal"
    std = [2.0, 2.0, 2.0]            # in the key's unit (m)

    [dispersions.faults.0.time]      # the first [[faults]] entry's start time
    dist = "uniform"
    low = 50.0
    high = 250.0

A dispersed key is a model parameter (``rpo info``), a controller gain
(``controller.<name>.<gain>``), an initial-state key (``relative.*``, ``chaser.*``, ``target.*``),
``orbit.perigee_altitude`` or a field of a ``[[faults]]`` entry (``faults.<n>.time``, ``end``,
``value``, ``unit``).  Its nominal value is the scenario's (or the manifest default).  The
distributions: :mod:`.dispersions`.

**Invalid draws.**  Each run's scenario (the base with that run's draws) is validated exactly as
``rpo run`` validates a file, and given the same pre-flight (:mod:`rpo.runtime.run.preflight`).
A draw that is refused is recorded as status ``invalid`` with the one-line reason and is not
flown; it is never clipped, replaced or redrawn (either would change the distribution without
saying so).  The report gives the invalid count and rate apart from the flown runs' statistics.
A campaign whose *median* draw (every dispersion at u = 0.5) is refused is refused as a whole when
it is read: almost every run would be; so is a dispersion of a key the flown configuration never
reads (:mod:`.reach`).
"""

from __future__ import annotations

import copy
import functools
import hashlib
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from rpo.runtime.campaign.dispersions import Dispersion, DispersionError
from rpo.runtime.campaign.reach import check_reach
from rpo.runtime.campaign.requirements import Requirement, of_resolved, parse_requirements
from rpo.runtime.campaign.sampling import SAMPLINGS, Design, noise_case, run_seed, run_seeds
from rpo.runtime.errors import CampaignError, ScenarioError
from rpo.runtime.model.manifest import Manifest
from rpo.runtime.scenario import ScenarioSchema, read_scenario, validate_scenario
from rpo.runtime.scenario.loader import ScenarioSource, parse_toml
from rpo.runtime.scenario.messages import first_error, show

FORMAT = 1
#: The histories' channels by default (fields of the state and outputs; rpo.runtime.scenario.channels).
CHANNELS: tuple[str, ...] = ("q_c", "w_c", "h_w", "r", "v", "m_prop")
#: Columns every history gets, derived from the record (rpo.runtime.outputs.metrics.error_signals).
DERIVED = ("err_att_rad", "err_pos_m", "h_w_norm")
#: Most runs a campaign file may ask for (a typo guard: 10 million runs of 1 ms each is hours).
MAX_RUNS = 10_000_000
#: Keys that say how a run is run or written, not what is flown: never dispersed.
FIXED_SECTIONS = ("meta", "simulation", "output", "reproduction", "campaign", "dispersions")
#: Initial-state keys written in runtime/scenario/schema.py (not manifest parameters), with units.
STATE_KEYS = {
    "relative.position": "m", "relative.velocity": "m/s",
    **{f"{b}.{k}": u for b in ("chaser", "target") for k, u in (
        ("quaternion", "-"), ("angular_velocity", "rad/s"), ("angular_velocity_deg_s", "deg/s"))},
    "chaser.wheel_momentum": "N m s", "chaser.wheel_speed_rpm": "rpm",
    "orbit.perigee_altitude": "m",
}
FAULT_FIELDS = ("time", "end", "value", "unit", "kind")
#: Looks of a sequential campaign when ``[campaign] looks`` is not given.
DEFAULT_LOOKS = 10


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)


class CampaignSection(_Section):
    """``[campaign]``: the runs, the design and what each run records."""

    name: str | None = None
    description: str = ""
    runs: Annotated[int, Field(ge=1, le=MAX_RUNS)]
    sampling: Literal[SAMPLINGS] = "random"  # type: ignore[valid-type]
    seed: Annotated[int, Field(ge=0, le=2**63 - 1)] = 0
    rate_hz: Annotated[float, Field(gt=0)] | None = None
    record_every: Annotated[int, Field(ge=1)] | None = None
    channels: Annotated[list[str], Field(min_length=1)] | None = None
    batch: Annotated[int, Field(ge=1, le=100_000)] | None = None
    #: fly in ``looks`` equal steps up to ``runs`` and stop once every requirement is decided
    #: (rpo.runtime.campaign.sequential)
    sequential: bool = False
    looks: Annotated[int, Field(ge=1, le=1000)] | None = None


@dataclass
class Campaign:
    """A validated campaign: the base scenario table (``extends`` resolved, the overrides and the
    record applied), the settings and the dispersions, and how to make any run's scenario."""

    name: str
    source: str
    text: str
    settings: CampaignSection
    scenario_data: dict[str, Any]
    dispersions: list[Dispersion]
    manifest: Manifest = field(repr=False)
    overrides: dict[str, Any] = field(default_factory=dict)
    #: the scenario file the campaign extends (itself when it extends none)
    base: str = ""
    #: ``[requirements]``, judged on the summary (rpo.runtime.campaign.requirements)
    requirements: list[Requirement] = field(default_factory=list)
    _design: Design | None = field(default=None, init=False, repr=False, compare=False)
    #: (campaign seed, case) -> the run's noise seed: asked for twice a run (its row, its scenario)
    _seeds: dict[tuple[int, int], int] = field(default_factory=dict, init=False, repr=False, compare=False)

    # -- identity ----------------------------------------------------------------------------

    def resolved(self) -> dict[str, Any]:
        """Everything that decides the runs' results (JSON-ready), written to ``resolved.json``."""
        sim = self.scenario_data.get("simulation", {})
        return {
            "format": FORMAT, "name": self.name, "campaign_file": _absolute(self.source),
            "scenario_file": _absolute(self.base or self.source),
            "runs": self.settings.runs, "sampling": self.settings.sampling, "seed": self.settings.seed,
            "record_every": int(sim.get("record_every", 1)), "channels": list(self.channels),
            "controller": sim.get("controller", "baseline"), "duration_s": float(sim["duration"]),
            "overrides": dict(self.overrides),
            "dispersions": [{"key": d.key, "dist": d.dist, "params": d.params, "size": d.size, "unit": d.unit,
                             "nominal": d.nominal} for d in self.dispersions],
            "scenario": self.scenario_data,
            # only when given, so that the hash of a campaign without them is what it always was
            **({"requirements": [r.to_json() for r in self.requirements]} if self.requirements else {}),
            **({"sequential": {"looks": self.looks}} if self.settings.sequential else {}),
        }

    @property
    def hash(self) -> str:
        """sha256 of :meth:`resolved` without the file's path (canonical JSON): equal hashes, equal
        runs (with the same model), wherever the file lies."""
        body = {k: v for k, v in self.resolved().items() if k not in ("campaign_file", "scenario_file")}
        return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()

    @property
    def channels(self) -> tuple[str, ...]:
        return tuple(self.settings.channels) if self.settings.channels else CHANNELS

    @property
    def runs(self) -> int:
        return self.settings.runs

    @property
    def looks(self) -> int:
        """The looks of a sequential campaign (:mod:`.sequential`; default 10, at most ``runs``)."""
        return min(self.settings.looks or DEFAULT_LOOKS, self.settings.runs)

    @property
    def design(self) -> Design:
        """The uniforms of every run (made once: an LHS or Sobol design is built whole)."""
        if self._design is None:
            self._design = Design(self.settings.sampling, self.settings.seed, self.settings.runs, self.dispersions)
        return self._design

    # -- runs --------------------------------------------------------------------------------

    def seed_of(self, case: int) -> int:
        """Run ``case``'s noise seed (:func:`~.sampling.run_seed` of :func:`~.sampling.noise_case`;
        made once per case)."""
        key = (self.settings.seed, case)
        seed = self._seeds.get(key)
        if seed is None:
            seed = self._seeds[key] = run_seed(self.settings.seed, self._noise_case(case))
        return seed

    def _noise_case(self, case: int) -> int:
        return noise_case(self.settings.sampling, len(self.dispersions), case)

    def draws(self, case: int) -> dict[str, Any]:
        """key -> the value drawn for run ``case`` (in the key's unit, as a scenario holds it)."""
        u = self.design.uniforms(case)
        with np.errstate(over="ignore", invalid="ignore"):  # a draw that overflows: refused by validation, named
            return {d.key: d.value(u[d.key]) for d in self.dispersions}

    def draws_many(self, cases: Sequence[int]) -> list[dict[str, Any]]:
        """:meth:`draws` of each of ``cases`` (the same values; the uniforms made at once)."""
        us = self.design.uniforms_many(cases)
        # the batch's noise seeds at once too (the same numbers: run_seeds is run_seed on arrays)
        fresh = [c for c in cases if (self.settings.seed, c) not in self._seeds]
        self._seeds.update(zip(((self.settings.seed, c) for c in fresh),
                               run_seeds(self.settings.seed, [self._noise_case(c) for c in fresh]), strict=True))
        with np.errstate(over="ignore", invalid="ignore"):  # as in draws: the row's message names it
            by_key = {d.key: d.values([u[d.key] for u in us]) for d in self.dispersions}
        return [{d.key: by_key[d.key][i] for d in self.dispersions} for i in range(len(us))]

    def case_data(self, case: int, draws: dict[str, Any] | None = None, share: bool = False) -> dict[str, Any]:
        """The scenario table of run ``case``: the base with its draws and its noise seed.  A deep
        copy; with ``share`` only the tables and arrays on the way to a changed key are copied and
        the rest is the base's (for a caller that reads it only: a campaign's validation)."""
        changes = dict(draws if draws is not None else self.draws(case))
        changes["simulation.seed"] = self.seed_of(case)
        if not share:
            data = copy.deepcopy(self.scenario_data)
            for key, value in changes.items():
                set_path(data, key, value)
            return data
        data = dict(self.scenario_data)
        for key, value in changes.items():
            node: Any = data
            parts = _parts(key)
            for p in parts[:-1]:  # copy each container on the path once, share the others
                child = node[p] if isinstance(p, int) else node.get(p, {})
                child = list(child) if isinstance(child, list) else dict(child)
                node[p] = child
                node = child
            node[parts[-1]] = plain_copy(value)
        return data

    def case_source(self, case: int) -> str:
        return f"{self.source} case {case}"


# --------------------------------------------------------------------------- paths in a table


@functools.lru_cache(maxsize=4096)
def _parts(key: str) -> tuple[str | int, ...]:
    """A dotted key's steps (``faults.0.time`` -> ("faults", 0, "time")); parsed once per key, a
    campaign sets the same keys in every run's table."""
    return tuple(int(p) if p.isdigit() else p for p in key.split("."))


def plain_copy(value: Any) -> Any:
    """A copy of a TOML-like value (tables, arrays, and immutable scalars: numbers, strings,
    booleans, dates): what ``copy.deepcopy`` gives for them, at a fraction of its cost (a campaign
    copies every draw of every run into its scenario table)."""
    if isinstance(value, list):
        return [plain_copy(v) for v in value]
    if isinstance(value, dict):
        return {k: plain_copy(v) for k, v in value.items()}
    if isinstance(value, (int, float, str, bool)) or value is None:
        return value
    return copy.deepcopy(value)


def get_path(data: Any, key: str) -> Any:
    """The value at a dotted key (``faults.0.time``: an index into an array), None when absent."""
    node = data
    for p in _parts(key):
        if isinstance(p, int):
            if not isinstance(node, list) or p >= len(node):
                return None
            node = node[p]
        else:
            if not isinstance(node, dict) or p not in node:
                return None
            node = node[p]
    return node


def set_path(data: dict, key: str, value: Any) -> None:
    """Set the value at a dotted key, creating tables on the way (not array entries)."""
    parts = _parts(key)
    node: Any = data
    for p in parts[:-1]:
        if isinstance(p, int):
            node = node[p]
        else:
            node = node.setdefault(p, {})
    node[parts[-1]] = copy.deepcopy(value)


# --------------------------------------------------------------------------- reading


def _flatten(table: dict, prefix: str = "") -> list[tuple[str, dict]]:
    """``[dispersions]`` -> [(key, its table)]: a table holding ``dist`` is one dispersion."""
    out = []
    for k, v in table.items():
        key = f"{prefix}.{k}" if prefix else str(k)
        if not isinstance(v, dict):
            raise CampaignError(f"dispersions.{key} = {show(v)}: must be a table with dist = ... (e.g. "
                                f"[dispersions.{key}] dist = \"normal\")")
        if "dist" in v:
            out.append((key, v))
        elif not v:
            raise CampaignError(f"dispersions.{key}: empty table: give dist = ...")
        else:
            out.extend(_flatten(v, key))
    return out


def _nominal(key: str, data: dict, manifest: Manifest) -> tuple[Any, str, int | None]:
    """(nominal value in the key's unit or None, unit, size or None) of a dispersible key; raises
    CampaignError for a key that is not one."""
    parts = key.split(".")
    if parts[0] in FIXED_SECTIONS:
        raise CampaignError(f"dispersions.{key}: [{parts[0]}] is not dispersed (it says how runs are run or "
                            "written); disperse the model's values, the gains, the initial state or the faults")
    value = get_path(data, key)
    params = {p.key: p for p in ScenarioSchema.of(manifest).params}
    if key in params:
        prm = params[key]
        if value is None and prm.default is not None:
            value = prm.to_scenario(prm.default)
        return value, prm.unit, prm.size if prm.kind != "inertia" else 9
    if key in STATE_KEYS:
        return value, STATE_KEYS[key], None if value is None else (len(value) if isinstance(value, list) else 1)
    if parts[0] == "controller" and len(parts) == 3:
        ctrls = manifest.controllers
        if parts[1] not in ctrls:
            raise CampaignError(f"dispersions.{key}: unknown controller {parts[1]!r}; available: "
                                f"{', '.join(sorted(ctrls))}")
        layout = manifest.layouts[ctrls[parts[1]].gains]
        if parts[2] not in layout.by_name:
            raise CampaignError(f"dispersions.{key}: unknown gain of {parts[1]}; its gains: "
                                f"{', '.join(layout.names)}")
        f = layout.field(parts[2])
        if value is None:
            d = layout.defaults[parts[2]]
            value = float(d[0]) if f.size == 1 else [float(x) for x in d]
        return value, f.unit, f.size
    if parts[0] == "faults" and len(parts) == 3 and parts[1].isdigit():
        n = int(parts[1])
        faults = data.get("faults", [])
        if n >= len(faults):
            raise CampaignError(f"dispersions.{key}: the scenario has {len(faults)} [[faults]] entries "
                                f"(faults.0 .. faults.{len(faults) - 1})" if faults else
                                f"dispersions.{key}: the scenario has no [[faults]] entry to disperse")
        if parts[2] not in FAULT_FIELDS:
            raise CampaignError(f"dispersions.{key}: unknown field of a fault; allowed: {', '.join(FAULT_FIELDS)}")
        unit = {"time": "s", "end": "s"}.get(parts[2], "")
        return value, unit, None if value is None else (len(value) if isinstance(value, list) else 1)
    allowed = "a model parameter (rpo info), controller.<name>.<gain>, " + ", ".join(STATE_KEYS) + \
        ", faults.<n>.<field>"
    import difflib
    close = difflib.get_close_matches(key, [*params, *STATE_KEYS], n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    raise CampaignError(f"dispersions.{key}: unknown key ({hint}allowed: {allowed})")


def load_campaign(path: str | Path | ScenarioSource, manifest: Manifest, *, runs: int | None = None,
                  duration: float | None = None) -> Campaign:
    """Read and validate a campaign file against ``manifest`` (``model.manifest``, or
    :func:`~rpo.runtime.model.manifest.read_manifest`); ``runs`` and ``duration`` [s] override the file's
    (a quick look).  Raises :class:`CampaignError` / :class:`ScenarioError` with one line."""
    src = path if isinstance(path, ScenarioSource) else read_scenario(path)
    data = copy.deepcopy(src.data)
    camp = campaign_from_table(data, src.source, src.text, manifest, runs=runs, duration=duration)
    camp.base = str(src.bases[0]) if src.bases else src.source
    return camp


def loads_campaign(text: str, source: str, manifest: Manifest, **kw: Any) -> Campaign:
    """A campaign from TOML text (no ``extends``: the text holds the whole scenario), against ``manifest``."""
    return campaign_from_table(parse_toml(text, source), source, text, manifest, **kw)


def campaign_from_table(data: dict, source: str, text: str, manifest: Manifest, *, runs: int | None = None,
                        duration: float | None = None) -> Campaign:
    table = data.pop("campaign", None)
    disp_table = data.pop("dispersions", {})
    req_table = data.pop("requirements", None)
    if table is None:
        raise CampaignError(f"{source}: [campaign]: required table is missing (a campaign file extends a "
                            "scenario and adds [campaign] with runs = ... and [dispersions])")
    if not isinstance(table, dict):
        raise CampaignError(f"{source}: campaign = {show(table)}: must be a table")
    overrides: dict[str, Any] = {}
    if runs is not None:
        if not (isinstance(runs, int) and 1 <= runs <= MAX_RUNS):
            raise CampaignError(f"{source}: --runs {runs}: must be an integer in [1, {MAX_RUNS}]")
        table = {**table, "runs": runs}
        overrides["runs"] = runs
    try:
        settings = CampaignSection.model_validate(table)
    except ValidationError as exc:
        raise CampaignError(first_error(exc.errors(include_url=False), source, CampaignSection,
                                        prefix=("campaign",))) from None
    if settings.rate_hz is not None and settings.record_every is not None:
        raise CampaignError(f"{source}: campaign.rate_hz = {settings.rate_hz:g}: give either rate_hz or "
                            "record_every (steps), not both")
    if not isinstance(disp_table, dict):
        raise CampaignError(f"{source}: dispersions = {show(disp_table)}: must be a table of [dispersions.<key>]")
    sim = data.setdefault("simulation", {})
    if duration is not None:
        if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
            raise CampaignError(f"{source}: --duration {duration}: must be a finite number > 0 s")
        sim["duration"] = float(duration)
        overrides["duration"] = float(duration)
    # the base scenario, validated as `rpo run` would (its errors name the file and key)
    base = validate_scenario(data, source, manifest)
    dt = float(base.params(copy=False)["dt"][0])
    if settings.record_every is not None:
        every = settings.record_every
    else:
        rate = settings.rate_hz if settings.rate_hz is not None else 1.0
        n = 1.0 / (rate * dt)
        if not (abs(n - round(n)) <= 1e-9 * max(1.0, n) and round(n) >= 1):
            raise CampaignError(f"{source}: campaign.rate_hz = {rate:g}: must divide the step rate {1 / dt:g} Hz "
                                "by a whole number (or give campaign.record_every in steps)")
        every = int(round(n))
    sim["record_every"] = every
    data.pop("output", None)  # a campaign writes its own histories (campaign.channels)
    data.pop("reproduction", None)
    dispersions = []
    try:
        flat = _flatten(disp_table)
    except CampaignError as exc:
        raise CampaignError(f"{source}: {exc}") from None
    for key, spec in flat:
        try:
            nominal, unit, size = _nominal(key, data, manifest)
        except CampaignError as exc:
            raise CampaignError(f"{source}: {exc}") from None
        if size is None:
            vals = spec.get("values")
            size = len(vals[0]) if isinstance(vals, list) and vals and isinstance(vals[0], list) else 1
        try:
            dispersions.append(Dispersion(key=key, dist=str(spec["dist"]), params=dict(spec), nominal=nominal,
                                          unit=unit, size=size))
        except DispersionError as exc:
            where = f"dispersions.{key}.{exc.field}"
            shown = spec.get(exc.field.split(".")[0], spec["dist"]) if exc.field != "dist" else spec["dist"]
            raise CampaignError(f"{source}: {where} = {show(shown)}: {exc.message}") from None
    requirements = [] if req_table is None else parse_requirements(req_table, source)
    _check_sequential(settings, requirements, source)
    _check_saltelli(settings, dispersions, source)
    name = settings.name or Path(source).stem
    camp = Campaign(name=name, source=str(source), text=text, settings=settings, scenario_data=data,
                    dispersions=dispersions, manifest=manifest, overrides=overrides, requirements=requirements)
    _check_channels(camp, manifest, source)
    check_reach(camp, source)  # a dispersed key the flown configuration never reads (runtime/campaign/reach.py)
    _check_median(camp, manifest, source)
    return camp


def _check_sequential(settings: CampaignSection, requirements: list[Requirement], source: str) -> None:
    """A sequential campaign stops when its requirements are decided, on a design whose first n runs
    are those of a campaign of n runs (random, sobol)."""
    if not settings.sequential:
        if settings.looks is not None:
            raise CampaignError(f"{source}: campaign.looks = {settings.looks}: only with campaign.sequential = true")
        return
    if not requirements:
        raise CampaignError(f"{source}: campaign.sequential = true: needs [requirements.<name>] to decide "
                            "(it stops when every requirement is PASS or FAIL)")
    if settings.sampling not in ("random", "sobol"):
        raise CampaignError(f"{source}: campaign.sampling = {settings.sampling!r}: a sequential campaign needs "
                            "\"random\" or \"sobol\" (designs whose first n runs are a campaign of n runs)")


def _check_saltelli(settings: CampaignSection, dispersions: list[Dispersion], source: str) -> None:
    """A Saltelli design flies whole blocks of (dispersions + 2) runs, at least 2 of them."""
    if settings.sampling != "sobol-indices":
        return
    size = len(dispersions) + 2
    if not dispersions:
        raise CampaignError(f"{source}: campaign.sampling = \"sobol-indices\": needs at least one [dispersions.<key>]")
    if settings.runs % size or settings.runs < 2 * size:
        blocks = max(2, round(settings.runs / size))
        raise CampaignError(f"{source}: campaign.runs = {settings.runs}: a sobol-indices design of {len(dispersions)} "
                            f"dispersions flies blocks of {size} runs: give a multiple of {size}, at least {2 * size} "
                            f"(e.g. {blocks * size}; best a power of 2 times {size}, e.g. {1024 * size})")


def _check_channels(camp: Campaign, manifest: Manifest, source: str) -> None:
    from rpo.runtime.scenario.channels import ChannelError, select
    ctrl = camp.scenario_data.get("simulation", {}).get("controller", "baseline")
    lay = manifest.layouts
    try:
        select(list(camp.channels), lay[f"z_{ctrl}"], lay[f"y_{ctrl}"], where=f"z_{ctrl}/y_{ctrl}")
    except ChannelError as exc:
        raise CampaignError(f"{source}: campaign.channels: {exc}") from None


def _check_median(camp: Campaign, manifest: Manifest, source: str) -> None:
    """Every dispersion at its median: refused means nearly every run would be."""
    if not camp.dispersions:
        return
    draws = {d.key: d.value(np.full(d.dims, 0.5)) for d in camp.dispersions}
    data = camp.case_data(0, draws)
    try:
        validate_scenario(data, f"{source} (every dispersion at its median)", manifest)
    except ScenarioError as exc:
        raise CampaignError(f"{exc} (nearly every draw would be refused: check the dispersions)") from None
    except Exception as exc:  # a draw of the wrong type for its key (e.g. a number for a table)
        raise CampaignError(f"{source}: the dispersions give values the scenario cannot take ({exc})") from None


def _absolute(source: str) -> str:
    try:
        return str(Path(source).resolve())
    except (OSError, RuntimeError):
        return source


def campaign_from_resolved(resolved: dict, manifest: Manifest) -> Campaign:
    """The campaign recorded in a folder's ``resolved.json`` (no file needed)."""
    settings = CampaignSection.model_validate({
        "name": resolved["name"], "runs": resolved["runs"], "sampling": resolved["sampling"],
        "seed": resolved["seed"], "record_every": resolved["record_every"], "channels": resolved["channels"],
        **({"sequential": True, "looks": resolved["sequential"]["looks"]} if resolved.get("sequential") else {})})
    data = copy.deepcopy(resolved["scenario"])
    disps = [Dispersion(key=d["key"], dist=d["dist"], params=d["params"], nominal=d["nominal"], unit=d["unit"],
                        size=d["size"]) for d in resolved["dispersions"]]
    return Campaign(name=resolved["name"], source=resolved["campaign_file"], text="", settings=settings,
                    scenario_data=data, dispersions=disps, manifest=manifest, overrides=resolved.get("overrides", {}),
                    base=resolved.get("scenario_file", ""), requirements=of_resolved(resolved))
