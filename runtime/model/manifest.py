"""The generated model's manifest, typed: read once, verified against its sources, hashed (the runtime's
only knowledge of the model, the acados way).

``generated/manifest.json`` is written by ``symbolic/codegen.py`` (format :data:`MANIFEST_FORMAT`).
:func:`read_manifest` checks it (format, its own hash, the sha256 of every generated file) and parses it
into frozen dataclasses, once per folder and file identity:

* :class:`Manifest`: the functions (:class:`FunctionSpec`, with their :class:`Port` s), the layouts
  (:class:`Layout` of :class:`LayoutField`: units, defaults, bounds as :class:`Interval`, scenario keys
  as :class:`ScenarioKey`, presets), the families (:class:`FamilySpec`), the controllers
  (:class:`ControllerSpec`), the specialised copies (:class:`Specialisation`), the plant's constants
  (``delay_slots``, ``quaternion_convention``), the fault vocabulary (:class:`FaultVocabulary`: the
  kinds a scenario's ``[[faults]]`` may name, their unit families, values and parameters) and the
  hashes and tool versions;
* :meth:`Manifest.derived`: what a higher layer derives from a manifest (the scenario schema), made
  once per manifest and kept with it, so nothing is keyed by ``id()``.

The manifest is passed explicitly (``Model.manifest``, ``Scenario.manifest``); only this module reads
its JSON.  The fault windows and values are fields of layout ``p``; ``faults`` says which.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from rpo.runtime.errors import ModelError

#: The manifest format this runtime reads (``rpo.symbolic.codegen.codegen.FORMAT_VERSION``; a test checks they agree).
MANIFEST_FORMAT = 2

K = TypeVar("K")
V = TypeVar("V")
T = TypeVar("T")


class FrozenDict(dict[K, V]):
    """A read-only dict (picklable, unlike ``MappingProxyType``: the figure workers are sent layout fields)."""

    __slots__ = ()

    def _read_only(self, *_args: Any, **_kw: Any) -> Any:
        raise TypeError("the manifest is read-only")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = __ior__ = _read_only  # type: ignore[assignment]

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (dict(self),))

    def __hash__(self) -> int:  # type: ignore[override]
        return hash(frozenset(self.items()))


def _frozen(d: Mapping[K, V] | None) -> FrozenDict[K, V]:
    return FrozenDict(d or {})


# --------------------------------------------------------------------------- bounds


@dataclass(frozen=True)
class Interval:
    """``lo``/``hi`` (None: unbounded), open or closed, in one unit; ``per_step``: a limit on
    ``|value| * dt`` (a rate the fixed step must resolve), checked once the step is known."""

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    per_step: float | None = None

    @classmethod
    def from_manifest(cls, d: Mapping[str, Any] | None) -> Interval | None:
        """The bounds entry of a layout field as the manifest writes it (None: unbounded)."""
        if not d:
            return None
        per_step = d.get("per_step")
        return cls(d.get("lo"), d.get("hi"), bool(d.get("lo_open")), bool(d.get("hi_open")),
                   None if per_step is None else float(per_step))

    def contains(self, v: float) -> bool:
        """Whether ``v`` is inside (never for nan or +-inf)."""
        if not math.isfinite(v):
            return False
        if self.lo is not None and (v <= self.lo if self.lo_open else v < self.lo):
            return False
        return not (self.hi is not None and (v >= self.hi if self.hi_open else v > self.hi))

    def text(self, unit: str = "") -> str:
        """``in [0, 1)``, ``> 0 kg``, ``<= 5 m``: what an error message says is allowed."""
        u = f" {unit}" if unit and unit != "-" else ""
        if self.lo is not None and self.hi is not None:
            return f"in {'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}{')' if self.hi_open else ']'}{u}"
        if self.lo is not None:
            return f"{'>' if self.lo_open else '>='} {self.lo:g}{u}"
        if self.hi is not None:
            return f"{'<' if self.hi_open else '<='} {self.hi:g}{u}"
        return "any number"

    def refusal(self, v: float, unit: str = "") -> str:
        """Why ``v`` is refused (it is not inside): ``must be in [0.01, 1e+07] kg``; a value of the
        wrong sign is told its sign first (``must be > 0 kg (allowed range [0.01, 1e+07] kg)``)."""
        full = self.text(unit)
        if self.lo is not None and self.lo > 0 and math.isfinite(v) and v <= 0:
            # the range starts above 0 (a magnitude): the sign is the first thing wrong
            return f"must be > 0{f' {unit}' if unit and unit != '-' else ''} (allowed range {full.removeprefix('in ')})"
        return f"must be {full}"

    def step_limit(self, dt: float) -> float | None:
        """The largest |value| the step ``dt`` [s] resolves (None: no such limit)."""
        return None if self.per_step is None else self.per_step / dt


# --------------------------------------------------------------------------- layouts


@dataclass(frozen=True)
class ScenarioKey:
    """How a scenario file sets a field (``symbolic/layout.py`` ``ScenarioKey``): the dotted TOML
    ``key``, the ``kind`` of value (``number``, ``switch``, ``choice``, ``reciprocal``, ``inertia``),
    the ``unit`` it is written in, ``scale`` to SI (SI = scale * value; ``reciprocal``: scale / value)
    and, for a ``choice``, the SI number of each word."""

    key: str
    kind: str = "number"
    unit: str = ""
    scale: float = 1.0
    choices: Mapping[str, float] = field(default_factory=FrozenDict)


@dataclass(frozen=True)
class LayoutField:
    """One block of a layout: ``size`` entries labelled ``labels``, in ``unit``; optionally its
    ``default`` (SI), ``bounds`` (SI, with ``bounds_why``), ``scenario`` key and ``presets``
    (preset name -> SI values)."""

    name: str
    size: int
    unit: str
    doc: str = ""
    labels: tuple[str, ...] = ()
    default: tuple[float, ...] | None = None
    bounds: Interval | None = None
    bounds_why: str = ""
    scenario: ScenarioKey | None = None
    presets: Mapping[str, tuple[float, ...]] = field(default_factory=FrozenDict)


@dataclass(frozen=True)
class Layout:
    """Named, ordered fields packed into one vector (iterating gives the fields)."""

    name: str
    fields: tuple[LayoutField, ...]

    def __iter__(self) -> Iterator[LayoutField]:
        return iter(self.fields)

    def __len__(self) -> int:
        return len(self.fields)

    @cached_property
    def by_name(self) -> Mapping[str, LayoutField]:
        """Field name -> field, in layout order."""
        return FrozenDict({f.name: f for f in self.fields})

    def field(self, name: str) -> LayoutField:
        """The field ``name`` (KeyError if the layout has none)."""
        return self.by_name[name]

    @cached_property
    def size(self) -> int:
        return sum(f.size for f in self.fields)

    @cached_property
    def names(self) -> tuple[str, ...]:
        return tuple(f.name for f in self.fields)

    @cached_property
    def labels(self) -> tuple[str, ...]:
        """Every column's label, in order."""
        return tuple(lbl for f in self.fields for lbl in f.labels)

    @cached_property
    def units(self) -> tuple[str, ...]:
        """Every column's unit, in order."""
        return tuple(f.unit for f in self.fields for _ in range(f.size))

    @cached_property
    def defaults(self) -> Mapping[str, np.ndarray]:
        """Field -> its default (SI), read-only arrays, for the fields that have one."""
        out = {}
        for f in self.fields:
            if f.default is not None:
                a = np.array(f.default, float)
                a.flags.writeable = False
                out[f.name] = a
        return FrozenDict(out)


# --------------------------------------------------------------------------- functions, families, controllers


@dataclass(frozen=True)
class Port:
    """An input or output of a generated function: its name, the layout it packs (None: an unnamed
    vector) and its (rows, columns)."""

    name: str
    layout: str | None
    shape: tuple[int, int]

    @property
    def size(self) -> int:
        return self.shape[0] * self.shape[1]


@dataclass(frozen=True)
class FunctionSpec:
    """A generated function: its C file (``source``), family, ports, operation count and description."""

    name: str
    source: str
    family: str
    inputs: tuple[Port, ...]
    outputs: tuple[Port, ...]
    doc: str = ""
    ops: int = 0


@dataclass(frozen=True)
class FamilySpec:
    """A group of functions derived together (``symbolic/codegen.py`` ``Family``): its hash over the
    modules of its import closure, its files, the functions and layouts it defines and the hashes of
    the files of the families it depends on."""

    name: str
    hash: str
    modules: tuple[str, ...]
    files: tuple[str, ...]
    functions: tuple[str, ...]
    layouts: tuple[str, ...]
    depends_files: Mapping[str, str] = field(default_factory=FrozenDict)


@dataclass(frozen=True)
class ControllerSpec:
    """A controller's generated functions (``law``, ``control``, ``step``, ``xc0`` if the design has
    one) and the layout of its ``gains``; its state and outputs are the layouts ``z_<name>``,
    ``y_<name>``.  (A family that records fewer entries, as the build tests' fixture, leaves them "".)"""

    name: str
    step: str
    law: str = ""
    control: str = ""
    gains: str = ""
    xc0: str | None = None

    @property
    def z_layout(self) -> str:
        return f"z_{self.name}"

    @property
    def y_layout(self) -> str:
        return f"y_{self.name}"

    def function_names(self) -> tuple[str, ...]:
        return tuple(f for f in (self.law, self.control, self.step, self.xc0) if f)


@dataclass(frozen=True)
class Specialisation:
    """A specialised copy of a function: ``function`` equals it where every p field of ``zero`` is 0."""

    function: str
    zero: tuple[str, ...]


# --------------------------------------------------------------------------- the fault vocabulary


@dataclass(frozen=True)
class FaultFamily:
    """Units a fault can name (``symbolic/physics/faults.py`` ``Family``): ``prefix`` of their
    parameters, the ``noun`` of the messages, the ``units`` as the parameters label them, ``first``
    the number a scenario writes for the first unit (None: a scenario writes the label), ``what``
    (``a wheel 1-4``) and whether its units are actuators (``actuator``)."""

    prefix: str
    noun: str
    units: tuple[str, ...]
    first: int | None
    what: str
    actuator: bool = False

    def index(self, unit: Any) -> int | None:
        """Index of the unit a scenario writes as ``unit`` (None: not one of this family's)."""
        if self.first is None:
            return self.units.index(unit) if isinstance(unit, str) and unit in self.units else None
        if isinstance(unit, int) and not isinstance(unit, bool) and 0 <= unit - self.first < len(self.units):
            return unit - self.first
        return None


@dataclass(frozen=True)
class FaultSensor:
    """A sensor a fault can name: its ``name`` in a scenario, ``short`` name in the parameters, the
    ``unit`` a scenario writes its fault values in and their ``scale`` to SI."""

    name: str
    short: str
    unit: str
    scale: float


@dataclass(frozen=True)
class FaultValue:
    """The ``value`` a fault kind takes: ``what`` it is (messages), ``shape`` (1: a number, 3:
    [x, y, z]), the ``range`` a scenario's value must be in (None: the parameter's bounds only), its
    ``unit`` (None: the named sensor's), and where it goes: ``vector``, one parameter over the
    family's units, or ``fields``, unit -> a parameter of its own set whole; ``none``: the kind a
    value of 0 would mean."""

    what: str
    shape: int
    range: Interval | None
    unit: str | None
    vector: str | None
    fields: Mapping[str, str]
    none: str | None = None


@dataclass(frozen=True)
class FaultKind:
    """A fault kind: its ``name`` in a scenario, unit ``family`` (a prefix), ``param`` (its name in the
    parameters), the parameters of its window's ``start`` and ``end``, and its ``value`` (None: none)."""

    name: str
    family: str
    param: str
    start: str
    end: str
    value: FaultValue | None = None


@dataclass(frozen=True)
class FaultVocabulary:
    """What a scenario's ``[[faults]]`` may say (the manifest's ``faults``): the unit families and
    sensors, the kinds (declaration order), and ``never``, the window edge of a window that never
    opens.  Empty for a model without faults."""

    never: float = math.inf
    families: Mapping[str, FaultFamily] = field(default_factory=FrozenDict)
    sensors: Mapping[str, FaultSensor] = field(default_factory=FrozenDict)
    kinds: Mapping[str, FaultKind] = field(default_factory=FrozenDict)

    def family(self, kind: str) -> FaultFamily:
        """The unit family of the kind named ``kind``."""
        return self.families[self.kinds[kind].family]


def _fault_vocabulary(d: Mapping[str, Any] | None) -> FaultVocabulary:
    if not d:
        return FaultVocabulary()

    def value(v: Mapping[str, Any] | None) -> FaultValue | None:
        if v is None:
            return None
        return FaultValue(what=v["what"], shape=int(v["shape"]), range=Interval.from_manifest(v.get("range")),
                          unit=v.get("unit"), vector=v.get("vector"), fields=_frozen(v.get("fields")),
                          none=v.get("none"))

    return FaultVocabulary(
        never=float(d["never"]),
        families=_frozen({f["prefix"]: FaultFamily(f["prefix"], f["noun"], tuple(f["units"]),
                                                   None if f["first"] is None else int(f["first"]), f["what"],
                                                   bool(f["actuator"]))
                          for f in d["families"]}),
        sensors=_frozen({s["name"]: FaultSensor(s["name"], s["short"], s["unit"], float(s["scale"]))
                         for s in d["sensors"]}),
        kinds=_frozen({k["name"]: FaultKind(k["name"], k["family"], k["param"], k["start"], k["end"],
                                            value(k.get("value")))
                       for k in d["kinds"]}))


# --------------------------------------------------------------------------- the manifest


@dataclass(frozen=True, eq=False)
class Manifest:
    """The whole manifest, typed (equal only to itself: one object per read, :func:`read_manifest`)."""

    format_version: int
    manifest_hash: str
    source_hash: str
    generator: str
    tools: Mapping[str, str]
    files: Mapping[str, str]                    # generated file -> sha256
    sources: tuple[str, ...]                    # the C files
    functions: Mapping[str, FunctionSpec]
    layouts: Mapping[str, Layout]
    families: Mapping[str, FamilySpec]
    controllers: Mapping[str, ControllerSpec]
    specialised: Mapping[str, tuple[Specialisation, ...]]
    delay_slots: int = 4                        # steps the wheel command's delay line holds
    quaternion_convention: str = ""
    faults: FaultVocabulary = field(default_factory=FaultVocabulary)
    _derived: dict[Any, Any] = field(default_factory=dict, init=False, repr=False)

    def derived(self, make: Callable[[Manifest], T]) -> T:
        """``make(self)``, made once per manifest and kept with it (keyed by ``make`` itself): how a
        higher layer keeps what it derives from the manifest (the scenario schema) without a cache
        of its own."""
        try:
            return self._derived[make]
        except KeyError:
            out = self._derived[make] = make(self)
            return out

    def controller(self, name: str) -> ControllerSpec:
        """The controller ``name``, or a :class:`ModelError` naming the available ones."""
        try:
            return self.controllers[name]
        except KeyError:
            raise ModelError(f"unknown controller {name!r}; available: {', '.join(sorted(self.controllers))}") \
                from None

    def __getstate__(self) -> dict[str, Any]:
        return {k: v for k, v in self.__dict__.items() if k != "_derived"}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state, _derived={})


def _port(d: Mapping[str, Any]) -> Port:
    rows, cols = d["shape"]
    return Port(name=d["name"], layout=d.get("layout"), shape=(int(rows), int(cols)))


def _labels(d: Mapping[str, Any]) -> tuple[str, ...]:
    if "labels" in d:
        return tuple(d["labels"])
    n = int(d["size"])  # as symbolic/layout.py Field.labels names a field without components
    return (d["name"],) if n == 1 else tuple(f"{d['name']}_{i}" for i in range(n))


def _field(d: Mapping[str, Any]) -> LayoutField:
    s = d.get("scenario")
    key = None if s is None else ScenarioKey(
        key=s["key"], kind=s.get("kind", "number"), unit=s.get("unit", d["unit"]), scale=float(s.get("scale", 1.0)),
        choices=_frozen({k: float(v) for k, v in (s.get("choices") or {}).items()}))
    return LayoutField(
        name=d["name"], size=int(d["size"]), unit=d["unit"], doc=d.get("doc", ""), labels=_labels(d),
        default=None if "default" not in d else tuple(float(x) for x in d["default"]),
        bounds=Interval.from_manifest(d.get("bounds")), bounds_why=d.get("bounds_why", ""), scenario=key,
        presets=_frozen({k: tuple(float(x) for x in v) for k, v in (d.get("presets") or {}).items()}))


def _controller(name: str, d: Mapping[str, str]) -> ControllerSpec:
    return ControllerSpec(name=name, step=d["step"], law=d.get("law", ""), control=d.get("control", ""),
                          gains=d.get("gains", ""), xc0=d.get("xc0"))


def _family(name: str, d: Mapping[str, Any]) -> FamilySpec:
    return FamilySpec(name=name, hash=d["hash"], modules=tuple(d.get("modules", ())), files=tuple(d.get("files", ())),
                      functions=tuple(d.get("functions", {})), layouts=tuple(d.get("layouts", {})),
                      depends_files=_frozen(d.get("depends_files")))


def parse_manifest(data: Mapping[str, Any]) -> Manifest:
    """The typed form of a manifest's JSON data (not verified: :func:`read_manifest` reads and verifies
    a generated folder's; this also serves a test that patches a copy of the data)."""
    funcs = {name: FunctionSpec(name=name, source=d["source"], family=d["family"],
                                inputs=tuple(_port(p) for p in d["inputs"]),
                                outputs=tuple(_port(p) for p in d["outputs"]), doc=d.get("doc", ""),
                                ops=int(d.get("ops", 0)))
             for name, d in data["functions"].items()}
    return Manifest(
        format_version=int(data["format_version"]), manifest_hash=data.get("manifest_hash", ""),
        source_hash=data.get("source_hash", ""), generator=data.get("generator", ""),
        tools=_frozen(data.get("tools")), files=_frozen(data["files"]), sources=tuple(data["sources"]),
        functions=_frozen(funcs),
        layouts=_frozen({name: Layout(name, tuple(_field(f) for f in fields))
                         for name, fields in data["layouts"].items()}),
        families=_frozen({name: _family(name, d) for name, d in data.get("families", {}).items()}),
        controllers=_frozen({name: _controller(name, d) for name, d in data.get("controllers", {}).items()}),
        specialised=_frozen({name: tuple(Specialisation(s["function"], tuple(s["zero"])) for s in copies)
                             for name, copies in data.get("specialised", {}).items()}),
        delay_slots=int(data.get("delay_slots", 4)), quaternion_convention=data.get("quaternion_convention", ""),
        faults=_fault_vocabulary(data.get("faults")))


# --------------------------------------------------------------------------- reading


def generated_dir() -> Path:
    """The folder holding the generated sources and manifest (``rpo.generated``)."""
    return Path(str(resources.files("rpo.generated")))


def _identity(path: Path) -> tuple[int, int, int, int]:
    st = os.stat(path)
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


#: (manifest path, verified?) -> (identity of manifest.json, identities of the files verified, the manifest):
#: a folder is read, hashed and parsed once, and again only if one of its files was replaced or touched
_READ: dict[tuple[str, bool], tuple[tuple[int, int, int, int], dict[str, tuple[int, int, int, int]], Manifest]] = {}


def _unchanged(gen_dir: Path, idents: Mapping[str, tuple[int, int, int, int]]) -> bool:
    try:
        return all(_identity(gen_dir / name) == ident for name, ident in idents.items())
    except OSError:
        return False


def read_manifest(gen_dir: Path | None = None, verify: bool = True) -> Manifest:
    """Read ``manifest.json`` and check the generated files against the hashes it records; the typed
    :class:`Manifest`, the same object for as long as none of the folder's files changes."""
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    path = gen_dir / "manifest.json"
    if not path.exists():
        raise ModelError(f"{path} is missing: run `python build.py` in the rpo checkout")
    key = (str(path), verify)
    try:
        ident = _identity(path)
    except OSError as exc:
        raise ModelError(f"{path} cannot be read ({exc}): run `python build.py`") from exc
    hit = _READ.get(key)
    if hit is not None and hit[0] == ident and _unchanged(gen_dir, hit[1]):
        return hit[2]
    try:
        data = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"{path} cannot be read ({exc}): run `python build.py`") from exc
    if not isinstance(data, dict) or data.get("format_version") != MANIFEST_FORMAT:
        got = data.get("format_version") if isinstance(data, dict) else None
        raise ModelError(f"{path} has format {got}, this runtime reads format {MANIFEST_FORMAT}: run `python build.py`")
    idents: dict[str, tuple[int, int, int, int]] = {}
    if verify:
        if data.get("manifest_hash") != manifest_hash(data):
            raise ModelError(f"{path} does not match its recorded hash (edited by hand?): run `python build.py`")
        for name, digest in data["files"].items():
            f = gen_dir / name
            if not f.exists():
                raise ModelError(f"{f} is missing: run `python build.py`")
            before = _identity(f)
            if hashlib.sha256(f.read_bytes()).hexdigest() != digest:
                raise ModelError(f"{f} does not match manifest.json (edited by hand or half-written):"
                                 " run `python build.py`")
            idents[name] = before
    try:
        manifest = parse_manifest(data)
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise ModelError(f"{path} is malformed ({type(exc).__name__}: {exc}): run `python build.py`") from None
    _READ[key] = (ident, idents, manifest)
    return manifest


def manifest_hash(manifest: Mapping[str, Any]) -> str:
    """sha256 of the manifest's canonical JSON without its ``manifest_hash`` field (of its JSON data).

    Same definition as ``rpo.symbolic.codegen.codegen.manifest_hash`` (the runtime must not import
    rpo.symbolic); ``tests/test_build.py`` checks that the two agree.
    """
    body = {k: v for k, v in manifest.items() if k != "manifest_hash"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def selected_sources(manifest: Manifest, controllers: Iterable[str] | None = None) -> list[str]:
    """The generated C files a library needs: all of them, or (``controllers`` given) those of the
    families that belong to no controller (the plant) plus the families of the named controllers.

    A first ``rpo run`` compiles only what its scenario flies; the objects are cached and shared
    with any later, larger selection.
    """
    if controllers is None:
        return list(manifest.sources)
    ctrls = manifest.controllers
    unknown = sorted(set(controllers) - set(ctrls))
    if unknown:
        raise ModelError(f"unknown controller {', '.join(unknown)}; available: {', '.join(sorted(ctrls))}")
    funcs = manifest.functions
    owned = {name: {funcs[f].family for f in c.function_names() if f in funcs} for name, c in ctrls.items()}
    all_ctrl = set().union(*owned.values()) if owned else set()
    keep = set().union(*(owned[c] for c in controllers)) if controllers else set()
    return [d.source for d in sorted(funcs.values(), key=lambda d: d.source)
            if d.family not in all_ctrl or d.family in keep]
