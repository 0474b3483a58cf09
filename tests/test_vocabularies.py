"""Each vocabulary is declared once and derived everywhere else (issue 23).

* the time-history formats and the figure formats: :mod:`rpo.runtime.formats`;
* the distributions of a campaign's dispersions: :mod:`rpo.runtime.campaign.dispersions`.

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
