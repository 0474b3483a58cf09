"""Each vocabulary is declared once and derived everywhere else (issue 23).

* the time-history formats and the figure formats: :mod:`rpo.runtime.formats`;
* the distributions of a campaign's dispersions: :mod:`rpo.runtime.campaign.dispersions`;
* the fault kinds, unit families, sensors and NEVER: ``symbolic/physics/faults.py``, through the
  manifest's ``faults`` (:class:`rpo.runtime.model.manifest.FaultVocabulary`).

For each: no other module of ``runtime/`` spells its names (a second list, a ``== "<name>"``
switch), and the consumers (the scenario schema's allowed values, the command's choices and help,
the error messages, the docs) equal the declaration.
"""

from __future__ import annotations

import ast
import json
from pathlib import Path

import click
import pytest
from pydantic import ValidationError

from rpo.runtime import formats
from rpo.runtime.campaign import dispersions
from rpo.runtime.campaign.dispersions import DISTRIBUTIONS, Dispersion, DispersionError, ScipyDistribution
from rpo.runtime.cli.main import cli
from rpo.runtime.docgen.choices import OUTPUT_DOC
from rpo.runtime.errors import OutputError
from rpo.runtime.formats import FIGURE_FORMATS, OUTPUT_FORMATS
from rpo.runtime.outputs.writers import OutputSpec
from rpo.runtime.scenario.schema import OutputSection

ROOT = Path(__file__).resolve().parents[1]
RUNTIME = ROOT / "runtime"
FORMATS_PY = "runtime/formats.py"
DISPERSIONS_PY = "runtime/campaign/dispersions.py"


def _sources() -> dict[str, ast.Module]:
    return {p.relative_to(ROOT).as_posix(): ast.parse(p.read_text(), str(p)) for p in sorted(RUNTIME.rglob("*.py"))}


SOURCES = _sources()


def _strings(tree: ast.AST) -> list[ast.Constant]:
    """The string constants of a module that stand alone (not the text around an f-string's fields:
    ``f"batch_{n}.parquet"`` names a file, not a format)."""
    parts = {id(v) for n in ast.walk(tree) if isinstance(n, ast.JoinedStr) for v in n.values}
    return [n for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)
            and id(n) not in parts]


def _spellings(names: set[str]) -> set[str]:
    """A name as a literal may spell it: ``png``, ``.png``."""
    return names | {f".{n}" for n in names}


def _literal_uses(names: set[str], declared_in: str) -> list[str]:
    """Every string constant equal to one of ``names`` (or its suffix) outside ``declared_in``."""
    spelled = _spellings(names)
    return [f"{rel}:{c.lineno} {c.value!r}" for rel, tree in SOURCES.items() if rel != declared_in
            for c in _strings(tree) if c.value in spelled]


# --------------------------------------------------------------------------- the scan itself can fail


def test_the_scan_sees_a_second_list():
    tree = ast.parse('KINDS = ("png", "svg")\nif fmt == ".pdf":\n    name = f"cdf.{fmt}.png"\n')
    found = [c.value for c in _strings(tree) if c.value in _spellings(set(FIGURE_FORMATS))]
    assert found == ["png", "svg", ".pdf"]


# --------------------------------------------------------------------------- output formats


def test_output_formats_are_spelled_only_where_declared():
    assert not _literal_uses(set(OUTPUT_FORMATS), FORMATS_PY), \
        "a time-history format is named outside runtime/formats.py: derive it from OUTPUT_FORMATS"


def test_every_output_format_has_one_writer_and_its_own_file():
    assert formats.DEFAULT_FORMATS and set(formats.DEFAULT_FORMATS) <= set(OUTPUT_FORMATS)
    files = [f.file for f in OUTPUT_FORMATS.values()]
    assert len(set(files)) == len(files)
    for name, f in OUTPUT_FORMATS.items():
        assert f.name == name and callable(f.write) and f.holds
    writers = [f.write for f in OUTPUT_FORMATS.values()]
    assert len(set(writers)) == len(writers), "two formats share a writer"


def test_the_scenario_schema_allows_exactly_the_output_formats():
    assert OutputSection().formats == list(formats.DEFAULT_FORMATS)
    assert OutputSection(formats=list(OUTPUT_FORMATS)).formats == list(OUTPUT_FORMATS)
    with pytest.raises(ValidationError) as err:
        OutputSection(formats=["no-such-format"])
    shown = [repr(n) for n in OUTPUT_FORMATS]
    assert f"{', '.join(shown[:-1])} or {shown[-1]}" in str(err.value)


def test_the_output_spec_and_its_message_follow_the_registry():
    assert OutputSpec().formats == formats.DEFAULT_FORMATS
    OutputSpec(formats=tuple(OUTPUT_FORMATS))
    with pytest.raises(OutputError, match=f"allowed {', '.join(OUTPUT_FORMATS)}$"):
        OutputSpec(formats=("no-such-format",))


def _option(command: str, name: str) -> click.Option:
    return next(p for p in cli.commands[command].params if isinstance(p, click.Option) and p.name == name)


def test_the_command_offers_exactly_the_output_formats():
    opt = _option("run", "formats")
    for name, f in OUTPUT_FORMATS.items():
        assert name in (opt.help or "")
        assert opt.process_value(click.Context(cli.commands["run"]), name) == (name,)
        if f.note:
            assert f"{name} ({f.note})" in (opt.help or "")
    with pytest.raises(click.BadParameter, match=f"allowed: {', '.join(OUTPUT_FORMATS)} "):
        opt.process_value(click.Context(cli.commands["run"]), "no-such-format")


def test_the_reference_lists_each_output_format_and_what_its_file_holds():
    for name, f in OUTPUT_FORMATS.items():
        assert f'`"{name}"`' in OUTPUT_DOC and f.holds in OUTPUT_DOC and f"`{f.file}`" in OUTPUT_DOC
    assert f"`{json.dumps(list(formats.DEFAULT_FORMATS))}`" in OUTPUT_DOC


# --------------------------------------------------------------------------- figure formats


def test_figure_formats_are_spelled_only_where_declared():
    assert not _literal_uses(set(FIGURE_FORMATS), FORMATS_PY), \
        "a figure format is named outside runtime/formats.py: derive it from FIGURE_FORMATS"


def test_every_figure_format_is_one_matplotlib_writes():
    from matplotlib.backend_bases import FigureCanvasBase

    supported = FigureCanvasBase.get_supported_filetypes()
    assert formats.DEFAULT_FIGURE_FORMAT in FIGURE_FORMATS
    for name, f in FIGURE_FORMATS.items():
        assert f.name == name and name in supported
        assert formats.figure_format_of(f"x.{f.suffix}") is f


def test_the_scenario_schema_the_command_and_the_messages_follow_the_figure_formats():
    assert OutputSection().figure_format == formats.DEFAULT_FIGURE_FORMAT
    for name in FIGURE_FORMATS:
        assert OutputSection(figure_format=name).figure_format == name
        OutputSpec(figure_format=name)
    with pytest.raises(ValidationError):
        OutputSection(figure_format="no-such-format")
    with pytest.raises(OutputError, match=f"allowed {', '.join(FIGURE_FORMATS)}$"):
        OutputSpec(figure_format="no-such-format")
    opt = _option("run", "figure_format")
    assert isinstance(opt.type, click.Choice) and list(opt.type.choices) == list(FIGURE_FORMATS)
    assert f'`"{formats.DEFAULT_FIGURE_FORMAT}"`' in OUTPUT_DOC
    for name in FIGURE_FORMATS:
        assert f'`"{name}"`' in OUTPUT_DOC


def test_the_campaign_report_refuses_another_figure_format(tmp_path):
    from rpo.runtime.campaign.reporting import write_report

    with pytest.raises(ValueError, match=f"allowed {', '.join(FIGURE_FORMATS)}$"):
        write_report(tmp_path, fmt="no-such-format")


# --------------------------------------------------------------------------- distributions


def test_distribution_names_are_spelled_once_where_declared():
    names = set(DISTRIBUTIONS)
    own = [c.value for c in _strings(SOURCES[DISPERSIONS_PY]) if c.value in names]
    assert sorted(own) == sorted(names), "a distribution's name is written twice in dispersions.py"
    # elsewhere a name may be a word of another vocabulary (a parameter's kind "inertia"), but no
    # module holds them all
    for rel, tree in SOURCES.items():
        if rel != DISPERSIONS_PY:
            assert not names <= {c.value for c in _strings(tree)}, f"{rel} lists the distributions"


def _switches_on_dist(tree: ast.AST) -> list[str]:
    """Comparisons of a distribution's name (``x.dist``, ``dist``, ``x["dist"]``) with a string or a
    literal collection."""
    def is_dist(n: ast.AST) -> bool:
        return isinstance(n, ast.Attribute) and n.attr == "dist" or isinstance(n, ast.Name) and n.id == "dist" \
            or isinstance(n, ast.Subscript) and isinstance(n.slice, ast.Constant) and n.slice.value == "dist"

    def is_literal(n: ast.AST) -> bool:
        return isinstance(n, (ast.Tuple, ast.List, ast.Set)) or isinstance(n, ast.Constant) and isinstance(n.value, str)

    return [ast.unparse(node) for node in ast.walk(tree) if isinstance(node, ast.Compare)
            and any(is_dist(n) for n in (node.left, *node.comparators))
            and any(is_literal(n) for n in (node.left, *node.comparators))]


def test_the_switch_scan_can_fail():
    code = ('if self.dist == "normal":\n    pass\nok = d.dist in ("a", "b")\nk = spec["dist"] != "x"\n'
            'f = exc.field != "dist"\n')
    assert _switches_on_dist(ast.parse(code)) == ["self.dist == 'normal'", "d.dist in ('a', 'b')",
                                                  "spec['dist'] != 'x'"]


def test_nothing_switches_on_a_distribution_name():
    found = [f"{rel}: {c}" for rel, tree in SOURCES.items() for c in _switches_on_dist(tree)]
    assert not found


def test_each_distribution_declares_its_parameters_and_is_found_by_name():
    for name, k in DISTRIBUTIONS.items():
        assert k.name == name and k.params and k.value_doc
        assert dispersions.distribution(name) is k
        assert len({p.name for p in k.params}) == len(k.params) and all(p.meaning for p in k.params)
    assert isinstance(dispersions.distribution("lognorm"), ScipyDistribution)
    with pytest.raises(DispersionError, match=f"allowed: {', '.join(DISTRIBUTIONS)} or a scipy"):
        dispersions.distribution("no-such-distribution")


def test_a_parameter_outside_the_declaration_is_refused_naming_the_declared_ones():
    for name, k in DISTRIBUTIONS.items():
        with pytest.raises(DispersionError) as err:
            Dispersion(key="a", dist=name, params={"dist": name, "no_such_parameter": 1.0}, nominal=1.0)
        assert err.value.field == "no_such_parameter"
        assert err.value.message.endswith(", ".join(sorted({"dist", *(p.name for p in k.params)})))


def test_the_campaign_docs_hold_the_table_of_the_distributions():
    text = (ROOT / "docs" / "campaigns.md").read_text()
    table = dispersions.reference_table()
    assert table in text, f"docs/campaigns.md: replace the table of distributions by\n{table}"


# --------------------------------------------------------------------------- fault vocabulary

#: the runtime packages that read a scenario and the manifest: no fault family, sensor or kind is
#: spelled there (elsewhere ``"attitude"``, ``"position"``, ``"rate"`` and ``"wheel"`` name the goals,
#: the figures and the metrics, other vocabularies)
SCENARIO_LAYERS = ("runtime/scenario/", "runtime/model/")
#: the one place a fault kind may be written in runtime/: the reproduction report's fault study, which
#: is [[faults]] entries (a scenario's data, checked below against the manifest), not a list of kinds
FAULT_STUDY = "runtime/jobs/reproduction_runs.py"


def _fault_manifest() -> dict:
    from rpo.runtime.model.manifest import generated_dir

    return json.loads((generated_dir() / "manifest.json").read_text())


def _fault_literals(trees: dict[str, ast.Module], kinds: set[str], words: set[str], never: float) -> list[str]:
    """Every string constant equal to a fault kind (anywhere but the fault study), to a family's or a
    sensor's name (in :data:`SCENARIO_LAYERS`), and every number equal to NEVER."""
    out = []
    for rel, tree in trees.items():
        names = (set() if rel == FAULT_STUDY else kinds) | (words if rel.startswith(SCENARIO_LAYERS) else set())
        out += [f"{rel}:{c.lineno} {c.value!r}" for c in _strings(tree) if c.value in names]
        out += [f"{rel}:{n.lineno} {n.value!r}" for n in ast.walk(tree) if isinstance(n, ast.Constant)
                and isinstance(n.value, float) and n.value == never]
    return out


def _fault_names() -> tuple[set[str], set[str], float]:
    from rpo.symbolic.physics import faults as flt

    words = {s.name for s in flt.SENSORS} | {s.short for s in flt.SENSORS}
    words |= {f.prefix for f in flt.FAMILIES} | {f.noun for f in flt.FAMILIES}
    return {k.name for k in flt.KINDS}, words, flt.NEVER


def test_the_runtime_s_fault_vocabulary_is_the_symbolic_declaration():
    from rpo.runtime.model.manifest import read_manifest
    from rpo.symbolic.physics import faults as flt

    assert _fault_manifest()["faults"] == json.loads(json.dumps(flt.vocabulary()))
    v = read_manifest().faults
    assert list(v.kinds) == [k.name for k in flt.KINDS] and v.never == flt.NEVER
    assert [(s.name, s.short, s.unit, s.scale) for s in v.sensors.values()] == \
        [(s.name, s.short, s.unit, s.scale) for s in flt.SENSORS]
    assert [(f.prefix, f.units, f.first, f.what) for f in v.families.values()] == \
        [(f.prefix, f.units, f.first, f.what) for f in flt.FAMILIES]
    for k in flt.KINDS:
        spec = v.kinds[k.name]
        assert (spec.family, spec.start, spec.end) == (k.family.prefix, k.window("start"), k.window("end"))
        assert (spec.value is None) == (k.value is None)


def test_the_fault_scan_sees_a_second_list():
    kinds, words, never = _fault_names()
    doctored = ast.parse('KINDS = ("wheel_off", "sensor_bias")\nif f.kind in ("thruster_weak",):\n    x = 1e30\n'
                         'SENSORS = {"attitude": ("att", "deg")}\nunit = f"sensor_bias of {u}"\n')
    found = _fault_literals({"runtime/scenario/doctored.py": doctored}, kinds, words, never)
    assert sorted(s.split(" ", 1)[1] for s in found) == \
        sorted(["'wheel_off'", "'sensor_bias'", "'thruster_weak'", "'attitude'", "'att'", "1e+30"])
    # elsewhere in runtime/ the kinds (and NEVER) are still found, the other words are not
    found = _fault_literals({"runtime/outputs/doctored.py": doctored}, kinds, words, never)
    assert sorted(s.split(" ", 1)[1] for s in found) == sorted(["'wheel_off'", "'sensor_bias'", "'thruster_weak'",
                                                                "1e+30"])


def test_no_fault_kind_sensor_family_or_never_is_written_in_the_runtime():
    kinds, words, never = _fault_names()
    assert not _fault_literals(SOURCES, kinds, words, never), \
        "a fault kind, sensor or family is spelled in runtime/: derive it from the manifest's faults"


def test_the_fault_study_names_kinds_of_the_manifest():
    from rpo.runtime.jobs.reproduction_runs import FAULT_CASES
    from rpo.runtime.model.manifest import read_manifest
    from rpo.runtime.scenario.faults import fault_model

    entry = fault_model(read_manifest())
    for _case, faults in FAULT_CASES:
        for f in faults:
            entry(**f)  # a kind and unit of the manifest's vocabulary


EXTRA_KIND = {"name": "wheel_slow", "family": "wheel", "param": "slow", "start": "fault_wheel_slow_start",
              "end": "fault_wheel_slow_end", "value": {
                  "what": "the fraction of the speed limit left, 0 < value <= 2", "shape": 1, "unit": "-",
                  "none": "wheel_off", "range": {"lo": 0.0, "hi": 2.0, "lo_open": True, "hi_open": False},
                  "vector": "fault_wheel_slow_value", "fields": None}}


def test_a_kind_added_to_the_model_is_flown_with_no_edit_of_the_runtime():
    """What adding a fault kind to symbolic/physics/faults.py (and its parameters to p) gives the
    manifest: the runtime validates, maps, describes and lists an entry of it as it does the others."""
    from rpo.runtime.errors import ScenarioError
    from rpo.runtime.model.manifest import parse_manifest
    from rpo.runtime.scenario import loads_scenario
    from rpo.runtime.scenario.faults import active_faults, describe

    data = _fault_manifest()
    p = data["layouts"]["p"]
    like = {f["name"]: f for f in p}
    for edge in ("start", "end"):
        p.append({**like[f"fault_wheel_off_{edge}"], "name": f"fault_wheel_slow_{edge}"})
    p.append({**like["fault_wheel_weak_value"], "name": "fault_wheel_slow_value",
              "bounds": {"lo": 0.0, "hi": 2.0, "lo_open": True, "hi_open": False}})
    data["faults"]["kinds"].append(EXTRA_KIND)
    m = parse_manifest(data)
    base = open(ROOT / "scenarios" / "000_scenario_III.toml").read()
    sc = loads_scenario(base + '\n[[faults]]\nkind = "wheel_slow"\nunit = 2\ntime = 1.0\nvalue = 1.5\n', "s.toml", m)
    params = sc.params()
    never = data["faults"]["never"]
    assert list(params["fault_wheel_slow_start"]) == [never, 1.0, never, never]
    assert list(params["fault_wheel_slow_value"]) == [1.0, 1.5, 1.0, 1.0]
    assert describe(sc.faults)[0]["unit_name"] == "2"
    assert active_faults(m.faults, params, 10.0) == [(1.0, "wheel_slow 2")]
    with pytest.raises(ScenarioError) as exc:
        loads_scenario(base + '\n[[faults]]\nkind = "wheel_slow"\nunit = 2\ntime = 1.0\nvalue = 0.0\n', "s.toml", m)
    assert str(exc.value) == ('s.toml: faults[0] = { kind = "wheel_slow", unit = 2, time = 1.0, value = 0.0 }: '
                              "value = 0: must be the fraction of the speed limit left, 0 < value <= 2 "
                              "(use kind wheel_off for none)")
    # the generated model has no such kind
    with pytest.raises(ScenarioError, match=r"faults\[0\]\.kind = \"wheel_slow\": must be one of"):
        loads_scenario(base + '\n[[faults]]\nkind = "wheel_slow"\nunit = 2\ntime = 1.0\nvalue = 1.5\n', "s.toml")


def test_the_fault_docs_list_the_declared_kinds_and_sensors():
    from rpo.symbolic.physics import faults as flt

    text = (ROOT / "docs" / "faults.md").read_text()
    rows = [line.split("|")[1:3] for line in text.splitlines() if line.startswith("| `")]
    assert [kind.strip().strip("`") for kind, _unit in rows] == [k.name for k in flt.KINDS]
    for (_kind, unit), k in zip(rows, flt.KINDS, strict=True):  # the family as a message names it
        f = k.family
        assert unit.strip() == (f.noun if f.first is None else f.what.removeprefix("a "))
    sensors = text.split("\nSensors: ", 1)[1].split(".\n\n", 1)[0]
    assert [s for s in sensors.split("`")[1::2]] == [s.name for s in flt.SENSORS]
    numbered = ", ".join(f.what.removeprefix("a ") for f in flt.FAMILIES if f.first is not None)
    named = " | ".join(f'"{s.name}"' for s in flt.SENSORS)
    assert f"unit = 1                  # {numbered}, or {named}" in text
