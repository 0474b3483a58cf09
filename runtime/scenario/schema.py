"""The scenario schema: pydantic sections, half written here and half derived from the manifest.

Written here (and in :mod:`.sections`) are the keys that are not model parameters: ``[meta]``, the
run settings of ``[simulation]`` (duration, seed, controller, record_every), ``orbit.perigee_altitude``
(an alternative to the semi-major axis), the initial state of ``[chaser]``, ``[target]`` and
``[relative]``, ``[goal]`` (:mod:`.goals`), the gains tables ``[controller.<name>]`` (checked against
the manifest's gains layouts), ``[reproduction]`` and ``[output]`` (its channels checked against the layouts of the
controller flown).  Every other key is a parameter of layout ``p`` whose key, kind, unit, scale and
bounds the manifest records (:mod:`.params`): a :class:`ScenarioSchema`, made once per typed manifest
(:meth:`ScenarioSchema.of`, kept with the manifest), adds them to these sections or makes new sections
for them, so a parameter added or re-bounded in ``symbolic/plant.py`` is validated here after
``python build.py`` with no edit of ``runtime/``.  The checks across keys are in :mod:`.checks`.

Every function here takes the manifest explicitly; a :class:`Scenario` holds the one it was validated
against (:attr:`Scenario.manifest`).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, cast

import numpy as np
from pydantic import (
    BaseModel,
    Field,
    PrivateAttr,
    ValidationError,
    ValidationInfo,
    create_model,
    model_validator,
)

from rpo.runtime.errors import ModelError, ScenarioError
from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, DEFAULT_FORMATS, FIGURE_FORMAT_NAMES, FORMAT_NAMES
from rpo.runtime.model.manifest import Manifest
from rpo.runtime.scenario.checks import cross_checks
from rpo.runtime.scenario.faults import Fault, fault_params, faults_field
from rpo.runtime.scenario.goals import Goal, GoalFlown
from rpo.runtime.scenario.messages import field_error, first_error
from rpo.runtime.scenario.params import ScenarioParam
from rpo.runtime.scenario.reproduction import Reproduction
from rpo.runtime.scenario.sections import (
    Chaser,
    GoalSection,
    Meta,
    Orbit,
    Relative,
    SimulationSection,
    Target,
    _range,
    _Section,
    param_type,
)

if TYPE_CHECKING:
    from rpo.runtime.model.loader import Model
    from rpo.runtime.scenario.initial_state import RunInputs


# --------------------------------------------------------------------------- [output]


class OutputSection(_Section):
    """``[output]``: what a run writes (:mod:`rpo.runtime.scenario.channels`, :mod:`rpo.runtime.outputs.writers`).

    ``channels``: field names, column labels or glob patterns over the layouts ``z_<controller>``
    and ``y_<controller>`` (omitted: :data:`rpo.runtime.scenario.channels.DEFAULT_CHANNELS`; ``"default"``
    inside the list stands for that set).  ``every`` (steps of 1 / rate) or ``rate_hz``: the
    written rows, a multiple of ``simulation.record_every`` (omitted: every recorded row).  The
    metrics are always computed from the full in-memory record, never from the written rows.
    ``formats`` and ``figure_format``: the names of :mod:`rpo.runtime.formats`.
    """

    channels: Annotated[list[str], Field(min_length=1)] | None = None
    every: Annotated[int, _range(1, what="an integer")] | None = None
    rate_hz: Annotated[float, _range(0, lo_open=True, unit="Hz")] | None = None
    formats: Annotated[list[Literal[FORMAT_NAMES]], Field(min_length=1)] = list(DEFAULT_FORMATS)  # type: ignore[valid-type]
    figures: bool = True
    figure_format: Literal[FIGURE_FORMAT_NAMES] = DEFAULT_FIGURE_FORMAT  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _one_rate(self):
        if self.every is not None and self.rate_hz is not None:
            raise field_error("rate_hz", self.rate_hz, "give either every (steps) or rate_hz, not both")
        if len(set(self.formats)) != len(self.formats):
            raise field_error("formats", self.formats, "lists a format twice")
        return self

    def step(self, dt: float, record_every: int) -> int:
        """The written rows' spacing in steps (``every``, or ``rate_hz`` converted; validated)."""
        if self.every is not None:
            return self.every
        if self.rate_hz is not None:
            return int(round(1.0 / (self.rate_hz * dt)))
        return record_every


# --------------------------------------------------------------------------- the scenario


class Scenario(_Section):
    """A validated scenario.  Build it with :func:`~rpo.runtime.scenario.load_scenario` or
    :func:`validate_scenario`; turn it into the inputs of a :class:`~rpo.runtime.run.simulate.Simulation`
    with :meth:`to_run`.

    The class validated is the :class:`ScenarioSchema`'s of the manifest, a subclass that adds the
    parameter keys; read those with :meth:`get` (``sc.get("orbit.eccentricity")``).  A validated
    scenario is not edited in place (:meth:`with_overrides` makes a re-validated copy).
    """

    meta: Meta = Field(default_factory=Meta)
    simulation: SimulationSection
    orbit: Orbit = Field(default_factory=Orbit)
    chaser: Chaser
    target: Target
    relative: Relative
    goal: GoalSection | None = None
    controller: dict[str, dict[str, Any]] = Field(default_factory=dict)
    reproduction: Reproduction | None = None
    output: OutputSection = Field(default_factory=OutputSection)
    faults: list[Fault] = Field(default_factory=list)

    _source: str = PrivateAttr(default="scenario")
    _schema: ScenarioSchema | None = PrivateAttr(default=None)
    _data: dict = PrivateAttr(default_factory=dict)
    _text: str | None = PrivateAttr(default=None)
    _overrides: dict[str, Any] | None = PrivateAttr(default=None)
    _goal_flown: GoalFlown | None = PrivateAttr(default=None)

    # -- lookups -----------------------------------------------------------------------------

    def get(self, path: str) -> Any:
        """Value at a dotted path (``"orbit.eccentricity"``), None when omitted."""
        obj: Any = self
        for part in path.split("."):
            obj = getattr(obj, part, None)
            if obj is None:
                return None
        return obj

    @property
    def scenario_schema(self) -> ScenarioSchema:
        """The schema this scenario was validated with (its manifest's)."""
        if self._schema is None:
            raise TypeError("a Scenario is made by validate_scenario(data, source, manifest) or load_scenario")
        return self._schema

    @property
    def manifest(self) -> Manifest:
        """The typed manifest this scenario was validated against."""
        return self.scenario_schema.manifest

    @property
    def data(self) -> dict:
        """A copy of the table the scenario was validated from (``extends`` resolved)."""
        return copy.deepcopy(self._data)

    def param_overrides(self) -> dict[str, Any]:
        """The parameters this scenario sets, by p-field name, in SI (omitted ones are absent; new
        values, the caller may change them)."""
        return {k: v.copy() if isinstance(v, np.ndarray) else v for k, v in self._set_params().items()}

    def _set_params(self) -> dict[str, Any]:
        """:meth:`param_overrides` as computed once per scenario (for readers here)."""
        if self._overrides is None:
            self._overrides = self._param_overrides()
        return self._overrides

    def _param_overrides(self) -> dict[str, Any]:
        schema = self.scenario_schema
        out: dict[str, Any] = {}
        sections: dict[str, Any] = {}  # the ~80 keys sit in a few tables: each table looked up once
        for table, leaf, prm in schema.paths:
            if table not in sections:
                sections[table] = self.get(table) if table else self
            node = sections[table]
            v = None if node is None else getattr(node, leaf, None)  # = self.get(prm.key)
            if v is not None:
                out[prm.name] = prm.to_si(v)
        if self.orbit.perigee_altitude is not None:
            d = schema.p_defaults
            e = out.get("orbit_e", float(d["orbit_e"][0]))
            r_e = out.get("r_earth", float(d["r_earth"][0]))
            out["orbit_a"] = (r_e + self.orbit.perigee_altitude) / (1.0 - e)  # perigee radius = a (1 - e)
        if self.faults:
            out.update(fault_params(self.faults, schema.p_defaults))
        return out

    def params(self, copy: bool = True) -> dict[str, np.ndarray]:
        """Every parameter (defaults overridden by the scenario), by p-field name, SI.  ``copy=False``:
        the defaults' own read-only arrays where the scenario sets nothing (for a caller that copies
        or only reads them: :func:`~.initial_state.run_inputs`)."""
        d = self.scenario_schema.p_defaults
        p = {k: v.copy() for k, v in d.items()} if copy else dict(d)
        for k, v in self._set_params().items():
            p[k] = np.array(v, float, ndmin=1) if copy else np.atleast_1d(np.asarray(v, float))
        return p

    def gains(self) -> dict[str, np.ndarray]:
        """Gains of the selected controller: its defaults, its goal gains for the scenario's goal
        (:attr:`goal_flown`), then ``[controller.<name>]``."""
        g = self.own_gains()
        table = self.controller.get(self.simulation.controller, {})
        for k, v in self.goal_flown.gains.items():
            if k not in table:
                g[k] = v.copy()
        return g

    def own_gains(self) -> dict[str, np.ndarray]:
        """The selected controller's defaults overridden by ``[controller.<name>]`` (its own goal
        gains: what states the goal of a scenario without ``[goal]``)."""
        ctrl = self.simulation.controller
        g = {k: v.copy() for k, v in self._gain_defaults().items()}
        for k, v in self.controller.get(ctrl, {}).items():
            g[k] = _gain_array(v)
        return g

    def gain(self, name: str) -> np.ndarray | None:
        """``self.gains().get(name)``, without making the others (for reading only: a default is the
        manifest's own read-only array)."""
        table = self.controller.get(self.simulation.controller, {})
        if name in table:
            return _gain_array(table[name])
        flown = self._goal_flown.gains if self._goal_flown is not None else {}
        if name in flown:
            return flown[name]
        return self._gain_defaults().get(name)

    @property
    def goal_flown(self) -> GoalFlown:
        """The scenario's goal and the goal gains of the controller flown for it (:mod:`.goals`)."""
        if self._goal_flown is None:
            raise TypeError("a Scenario is made by validate_scenario(data, source, manifest) or load_scenario")
        return self._goal_flown

    def _gain_defaults(self) -> Mapping[str, np.ndarray]:
        manifest = self.manifest
        return manifest.layouts[manifest.controllers[self.simulation.controller].gains].defaults

    # -- cross-field checks (need the manifest's defaults) ---------------------------------------

    @model_validator(mode="after")
    def _cross_checks(self, info: ValidationInfo):
        schema = (info.context or {}).get("schema")
        if not isinstance(schema, ScenarioSchema):
            raise TypeError("validate a scenario with validate_scenario(data, source, manifest)")
        self._schema = schema
        ctx = info.context or {}
        self._goal_flown = cross_checks(self, schema, ctx.get("source", "scenario"), ctx.get("goal_from"),
                                        ctx.get("carried"))
        return self

    # -- to a run ----------------------------------------------------------------------------

    @property
    def source(self) -> str:
        return self._source

    @property
    def text(self) -> str | None:
        """The TOML text the scenario was read from (None if built from a table)."""
        return self._text

    @property
    def name(self) -> str:
        return self.meta.name or Path(self._source).stem

    def with_overrides(self, duration: float | None = None, seed: int | None = None,
                       controller: str | None = None, plant: str | None = None,
                       gains: dict[str, Any] | None = None, faults: list[dict[str, Any]] | None = None) -> Scenario:
        """A re-validated copy with ``simulation.duration`` / ``seed`` / ``controller`` replaced,
        the scenario's goal kept (another ``controller`` flies it, :mod:`.goals`: a scenario without
        ``[goal]`` gets its own controller's goal as one), ``gains`` (name -> value) merged into
        the selected controller's gains table and, with
        ``plant="full"``, the paper's plant replaced by the manifest's preset ``full``: every p
        field with a ``presets.full`` value is set to it (removed from the scenario where that
        value is the manifest default); ``faults`` (entries as in ``[[faults]]``) are added to the
        scenario's own."""
        if (duration is None and seed is None and controller is None and plant in (None, "paper") and not gains
                and not faults):
            return self
        data = copy.deepcopy(self._data)
        if faults:
            data["faults"] = [*data.get("faults", []), *copy.deepcopy(faults)]
        sim = data.setdefault("simulation", {})
        if duration is not None:
            sim["duration"] = duration
        if seed is not None:
            sim["seed"] = seed
        goal = self.goal_flown.goal  # the scenario's, whoever flies it; named where the file states it
        goal_from = None if goal is None else goal.source
        carried = None  # a goal stated by gains stays one when another controller flies it
        if controller is not None:
            if controller != self.simulation.controller and "goal" not in data:
                if goal is not None:
                    data["goal"] = goal.table()
                    carried = goal if not goal.stated else None
                elif controller in self.manifest.controllers:
                    raise ScenarioError(
                        f"{self._source}: simulation.controller = {controller!r}: cannot fly the scenario's goal: "
                        f"rpo cannot tell it (its controller {self.simulation.controller} has no goal description in "
                        "runtime/scenario/goals.py); state it in a [goal] table")
            sim["controller"] = controller
        if gains:
            ctrl = sim.get("controller", self.simulation.controller)
            table = data.setdefault("controller", {}).setdefault(ctrl, {})
            entry = self.manifest.controllers.get(ctrl)
            sizes = {f.name: f.size for f in self.manifest.layouts[entry.gains]} if entry else {}
            for k, v in gains.items():
                arr = np.ravel(np.asarray(v, float))
                # as a scenario would write it: a number for a one-entry gain, else an array
                table[k] = float(arr[0]) if sizes.get(k, arr.size) == 1 and arr.size == 1 else arr.tolist()
        if plant not in (None, "paper"):
            apply_preset(data, self.manifest, plant)
        if carried is None and goal is not None and not goal.stated and "goal" in data:
            carried = goal  # already carried by an earlier override
        sc = validate_scenario(data, f"{self._source} (with command-line overrides)", self.manifest,
                               goal_from=goal_from, carried=carried)
        sc._text = self._text
        return sc

    def to_run(self, model: Model) -> RunInputs:
        """Inputs of :class:`~rpo.runtime.run.simulate.Simulation` for ``model`` (see
        :func:`~rpo.runtime.scenario.initial_state.run_inputs`)."""
        from rpo.runtime.scenario.initial_state import run_inputs
        return run_inputs(self, model)


def _gain_array(value: Any) -> np.ndarray:
    """A gain as a scenario's ``[controller.<name>]`` writes it (a number or an array), as an array."""
    return np.atleast_1d(np.asarray(value, float))


# --------------------------------------------------------------------------- derived from the manifest


class ScenarioSchema:
    """What validating a scenario against one manifest needs, derived from it once: the parameters a
    scenario sets (:class:`~.params.ScenarioParam`, layout order), where each sits in the file, those
    with a per-step bound, the defaults of ``p`` and :attr:`model`, the :class:`Scenario` subclass
    with the parameters' keys.  Made by :meth:`of` (kept with the manifest: ``Manifest.derived``)."""

    def __init__(self, manifest: Manifest):
        self.manifest = manifest
        p = manifest.layouts["p"]
        #: every field of p that a scenario sets, in layout order
        self.params: tuple[ScenarioParam, ...] = tuple(ScenarioParam.from_field(f) for f in p if f.scenario)
        self._by_name = {prm.name: prm for prm in self.params}
        #: (table, leaf, parameter) of every parameter: ``chaser.mass`` -> ("chaser", "mass", ...)
        self.paths: tuple[tuple[str, str, ScenarioParam], ...] = tuple(
            (*prm.key.rpartition(".")[::2], prm) for prm in self.params)
        #: the parameters with a ``per_step`` bound
        self.per_step: tuple[ScenarioParam, ...] = tuple(
            prm for prm in self.params if prm.bounds is not None and prm.bounds.per_step is not None)
        #: the defaults of p (SI, read-only arrays)
        self.p_defaults: Mapping[str, np.ndarray] = p.defaults
        #: :class:`Scenario` with the parameters' keys and the manifest's ``[[faults]]`` entry added
        self.model: type[Scenario] = _derive_model(self.params, {"faults": faults_field(manifest)})

    @classmethod
    def of(cls, manifest: Manifest) -> ScenarioSchema:
        """The schema of ``manifest`` (made on first use, then kept with it)."""
        return manifest.derived(cls)

    def param(self, name: str) -> ScenarioParam:
        """The scenario entry of p field ``name`` (for messages naming its key and unit)."""
        try:
            return self._by_name[name]
        except KeyError:
            raise KeyError(f"the manifest's layout p has no field {name} with a scenario key: run `python build.py`") \
                from None

    def validate(self, data: dict, source: str, *, own: bool = False, goal_from: str | None = None,
                 carried: Goal | None = None) -> Scenario:
        """Validate a parsed scenario table; raises :class:`ScenarioError` with a one-line message.
        ``own``: the caller hands ``data`` over (it will not change it), so it is kept without a copy;
        ``goal_from``: where the scenario's goal is stated, if not in ``data`` itself; ``carried``:
        the goal stated by gains that ``data``'s ``[goal]`` was made from (:meth:`Scenario.with_overrides`)."""
        cls = self.model
        ctx = {"schema": self, "source": source, "goal_from": goal_from, "carried": carried}
        try:
            sc = cls.model_validate(data, context=ctx)
        except ValidationError as exc:
            raise ScenarioError(first_error(exc.errors(include_url=False), source, cls)) from None
        sc._source = source
        sc._data = data if own else copy.deepcopy(data)
        return sc


def scenario_params(manifest: Manifest) -> list[ScenarioParam]:
    """Every field of layout p that a scenario sets, in layout order (a new list; the entries are frozen)."""
    return list(ScenarioSchema.of(manifest).params)


def scenario_model(manifest: Manifest) -> type[Scenario]:
    """:class:`Scenario` with the manifest's parameter keys added (made once per manifest)."""
    return ScenarioSchema.of(manifest).model


def validate_scenario(data: dict, source: str, manifest: Manifest, *, own: bool = False,
                      goal_from: str | None = None, carried: Goal | None = None) -> Scenario:
    """Validate a parsed scenario table against ``manifest``; raises :class:`ScenarioError` with a
    one-line message.  ``own``: the caller hands ``data`` over (it will not change it), so it is kept
    without a copy; ``goal_from``, ``carried``: as for :meth:`ScenarioSchema.validate` (:mod:`.goals`)."""
    return ScenarioSchema.of(manifest).validate(data, source, own=own, goal_from=goal_from, carried=carried)


def apply_preset(data: dict, manifest: Manifest, preset: str) -> None:
    """Set, in a scenario table, every parameter of the manifest's ``preset`` (in place)."""
    members = [prm for prm in ScenarioSchema.of(manifest).params if preset in prm.presets]
    if not members:
        raise ScenarioError(f"the generated model has no parameter preset {preset!r}")
    for prm in members:
        *sections, leaf = prm.key.split(".")
        table = data
        for s in sections:
            table = table.setdefault(s, {})
        value = prm.presets[preset]
        if prm.default is not None and tuple(value) == tuple(prm.default):
            table.pop(leaf, None)
        else:
            table[leaf] = prm.to_scenario(value)


def _derive_model(params: tuple[ScenarioParam, ...], top: dict[str, Any]) -> type[Scenario]:
    """:class:`Scenario` with the parameters' keys added to its sections, or in new ones, and the
    top-level fields ``top`` (name -> pydantic field definition) replaced."""
    tree: dict[str, Any] = {}
    for prm in params:
        *sections, leaf = prm.key.split(".")
        if not sections:
            raise ModelError(f"manifest: parameter {prm.name}: scenario key {prm.key!r} is not in a table")
        node = tree
        for s in sections:
            node = node.setdefault(s, {})
            if not isinstance(node, dict):
                raise ModelError(f"manifest: scenario key {prm.key!r} is inside the key of another parameter")
        if leaf in node:
            raise ModelError(f"manifest: two parameters have the scenario key {prm.key!r}")
        node[leaf] = prm
    return cast(type[Scenario], _build("Scenario", tree, Scenario, top))


def _build(name: str, node: dict[str, Any], base: type[BaseModel], top: dict[str, Any] | None = None) \
        -> type[BaseModel]:
    fields: dict[str, Any] = dict(top or {})
    for k, v in node.items():
        existing = base.model_fields.get(k)
        if isinstance(v, ScenarioParam):
            if existing is not None:
                raise ModelError(f"manifest: scenario key {v.key!r} is also a key written in runtime/scenario")
            fields[k] = (param_type(v) | None, None)
            continue
        sub_base: Any = _Section
        if existing is not None:
            ann = existing.annotation
            if not (isinstance(ann, type) and issubclass(ann, _Section)):
                raise ModelError(f"manifest: scenario keys under {name}.{k} clash with a key of runtime/scenario")
            sub_base = ann
        sub = _build(f"{name}.{k}", v, sub_base)
        required = existing is not None and existing.is_required()
        fields[k] = (sub, ... if required else Field(default_factory=sub))
    return create_model(name, __base__=base, **fields)

