"""The typed manifest (runtime/model/manifest.py): every key of ``generated/manifest.json`` typed, read and
verified once per file identity, read-only, passed explicitly; the scenario schema made once per manifest."""

from __future__ import annotations

import dataclasses
import json
import os
import pickle
import shutil
from pathlib import Path

import pytest
from structure import manifest_subscripts

from rpo.runtime.errors import ModelError
from rpo.runtime.model.manifest import (
    Interval,
    Manifest,
    ScenarioKey,
    manifest_hash,
    parse_manifest,
    read_manifest,
)
from rpo.runtime.scenario import ScenarioSchema, load_scenario, scenario_model, validate_scenario

ROOT = Path(__file__).resolve().parents[1]
GEN = ROOT / "generated"
#: the top-level keys symbolic/codegen.py writes (a new one must be typed before the runtime reads it)
KEYS = {"controllers", "delay_slots", "faults", "families", "files", "format_version", "functions", "generator",
        "layouts", "manifest_hash", "quaternion_convention", "source_hash", "sources", "specialised", "tools"}


@pytest.fixture
def raw() -> dict:
    return json.loads((GEN / "manifest.json").read_text())


@pytest.fixture
def gen_copy(tmp_path) -> Path:
    dst = tmp_path / "generated"
    shutil.copytree(GEN, dst, ignore=shutil.ignore_patterns("__pycache__", ".lock"))
    return dst


def _interval(d: dict | None) -> Interval | None:
    return None if d is None else Interval(d["lo"], d["hi"], d["lo_open"], d["hi_open"], d.get("per_step"))


def _interval_dict(i: Interval | None) -> dict | None:
    return None if i is None else {"lo": i.lo, "hi": i.hi, "lo_open": i.lo_open, "hi_open": i.hi_open}


def test_every_key_of_the_manifest_is_typed(raw):
    m = read_manifest(GEN)
    assert set(raw) == KEYS
    assert (m.format_version, m.manifest_hash, m.source_hash, m.generator) == \
        (raw["format_version"], raw["manifest_hash"], raw["source_hash"], raw["generator"])
    assert m.manifest_hash == manifest_hash(raw)  # the hash is over the same JSON data as codegen's
    assert dict(m.tools) == raw["tools"] and dict(m.files) == raw["files"] and list(m.sources) == raw["sources"]
    assert (m.delay_slots, m.quaternion_convention) == (raw["delay_slots"], raw["quaternion_convention"])
    assert set(m.functions) == set(raw["functions"])
    for name, d in raw["functions"].items():
        f = m.functions[name]
        assert (f.name, f.source, f.family, f.doc, f.ops) == (name, d["source"], d["family"], d["doc"], d["ops"])
        for ports, want in ((f.inputs, d["inputs"]), (f.outputs, d["outputs"])):
            assert [(p.name, p.layout, list(p.shape)) for p in ports] == \
                [(w["name"], w["layout"], w["shape"]) for w in want], name
            assert [p.size for p in ports] == [w["shape"][0] * w["shape"][1] for w in want]
    assert list(m.layouts) == list(raw["layouts"])
    for lname, fields in raw["layouts"].items():
        lay = m.layouts[lname]
        assert lay.name == lname and lay.names == tuple(d["name"] for d in fields)
        assert lay.size == sum(d["size"] for d in fields)
        assert lay.labels == tuple(lbl for d in fields for lbl in d["labels"])
        for f, d in zip(lay, fields, strict=True):
            assert (f.size, f.unit, f.doc, list(f.labels)) == (d["size"], d["unit"], d["doc"], d["labels"])
            assert f.default == (None if "default" not in d else tuple(d["default"]))
            assert f.bounds == _interval(d.get("bounds")) and f.bounds_why == d.get("bounds_why", "")
            s = d.get("scenario")
            assert f.scenario == (None if s is None else ScenarioKey(s["key"], s["kind"], s["unit"], s["scale"],
                                                                       s.get("choices", {})))
            assert {k: list(v) for k, v in f.presets.items()} == d.get("presets", {})
            if f.default is not None:
                assert lay.defaults[f.name].tolist() == d["default"]
    assert set(m.families) == set(raw["families"])
    for name, d in raw["families"].items():
        fam = m.families[name]
        assert (fam.hash, list(fam.modules), list(fam.files)) == (d["hash"], d["modules"], d["files"])
        assert (list(fam.functions), list(fam.layouts)) == (list(d["functions"]), list(d["layouts"]))
        assert dict(fam.depends_files) == d["depends_files"]
    assert set(m.controllers) == set(raw["controllers"])
    for name, d in raw["controllers"].items():
        c = m.controllers[name]
        assert {k: getattr(c, k) for k in d} == d and (c.xc0 is None) == ("xc0" not in d)
        assert (c.z_layout, c.y_layout) == (f"z_{name}", f"y_{name}") and c.z_layout in m.layouts
    assert {k: [{"function": s.function, "zero": list(s.zero)} for s in v] for k, v in m.specialised.items()} == \
        raw["specialised"]
    f = raw["faults"]
    assert set(f) == {"never", "families", "sensors", "kinds"} and m.faults.never == f["never"]
    assert [{"prefix": x.prefix, "noun": x.noun, "units": list(x.units), "first": x.first, "what": x.what,
             "actuator": x.actuator} for x in m.faults.families.values()] == f["families"]
    assert [{"name": x.name, "short": x.short, "unit": x.unit, "scale": x.scale}
            for x in m.faults.sensors.values()] == f["sensors"]
    kinds = []
    for k in m.faults.kinds.values():
        v = k.value
        kinds.append({"name": k.name, "family": k.family, "param": k.param, "start": k.start, "end": k.end,
                      "value": None if v is None else {
                          "what": v.what, "shape": v.shape, "range": _interval_dict(v.range), "unit": v.unit,
                          "vector": v.vector, "fields": dict(v.fields) or None, "none": v.none}})
    assert kinds == f["kinds"]


def test_a_folder_is_read_once_and_again_when_a_file_changes(gen_copy):
    m = read_manifest(gen_copy)
    assert read_manifest(gen_copy) is m  # verified and parsed once
    assert read_manifest(gen_copy, verify=False) is not m  # another reading: unverified
    c = gen_copy / "step_c001.c"
    st = c.stat()
    os.utime(c, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))  # touched, same bytes: verified again
    again = read_manifest(gen_copy)
    assert again is not m and again.manifest_hash == m.manifest_hash and read_manifest(gen_copy) is again
    data = bytearray(c.read_bytes())  # the same size, other bytes: refused although it was read before
    i = data.index(b"casadi_real")
    data[i] = ord("C")
    c.write_bytes(bytes(data))
    os.utime(c, ns=(st.st_atime_ns, st.st_mtime_ns + 2 * 10**9))
    with pytest.raises(ModelError, match="step_c001.c does not match manifest.json"):
        read_manifest(gen_copy)


def test_the_manifest_is_read_only_and_its_fields_travel(raw):
    m = parse_manifest(raw)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.delay_slots = 5  # type: ignore[misc]
    with pytest.raises(TypeError, match="read-only"):
        m.layouts["p"].by_name["x"] = None  # type: ignore[index]
    with pytest.raises(TypeError, match="read-only"):
        m.controllers.pop("c001")  # type: ignore[attr-defined]
    with pytest.raises(ValueError, match="read-only"):
        m.layouts["p"].defaults["dt"][0] = 1.0
    f = m.layouts["p"].field("orbit_inc")
    assert pickle.loads(pickle.dumps(f)) == f  # a figure worker is sent layout fields
    back = pickle.loads(pickle.dumps(m))
    assert isinstance(back, Manifest) and back.layouts["p"] == m.layouts["p"]


def test_the_scenario_schema_is_made_once_per_manifest(raw):
    m = read_manifest()
    schema = ScenarioSchema.of(m)
    assert ScenarioSchema.of(m) is schema and scenario_model(m) is schema.model
    a = load_scenario(ROOT / "scenarios" / "001_scenario.toml", m)
    b = load_scenario(ROOT / "scenarios" / "000_scenario_III.toml")  # a user's call: the generated manifest
    assert type(a) is type(b) is schema.model and a.manifest is b.manifest is m and a.scenario_schema is schema
    other = parse_manifest(raw)  # another manifest (a patched copy): its own schema
    c = validate_scenario(a.data, "copy.toml", other)
    assert c.manifest is other and ScenarioSchema.of(other) is not schema and type(c) is not type(a)
    assert c.with_overrides(duration=1.0).manifest is other  # a scenario keeps its manifest
    with pytest.raises(TypeError, match="validate_scenario"):
        schema.model.model_validate(a.data)  # not without its schema


def test_nothing_outside_the_model_package_reads_the_manifest_s_json():
    assert manifest_subscripts() == []
