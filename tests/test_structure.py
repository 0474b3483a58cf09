"""The shape of the code (tests/structure.py): no import cycle anywhere in rpo, the runtime's layers as
docs/architecture.md draws them, no oversized runtime module without a reason, no raw manifest subscripts
outside the model package, no hand-kept package list.  Each check is also shown to fail on a doctored input."""

from __future__ import annotations

from pathlib import Path

import structure

DOC = Path(__file__).resolve().parents[1] / "docs" / "architecture.md"


def test_there_is_no_import_cycle():
    cycles = structure.cycles(structure.graph())
    assert cycles == [], "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


def test_the_cycle_check_finds_a_cycle():
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert structure.cycles(g) == [["a", "b", "c"]]


def test_the_runtime_imports_only_down_its_layers():
    bad = structure.layer_violations(structure.graph())
    assert bad == [], "\n".join(bad)


def test_the_layer_check_sees_an_upward_import_and_the_symbolic_side():
    g = {"rpo.runtime.model.loader": {"rpo.runtime.run.simulate"},
         "rpo.runtime.run.simulate": {"rpo.symbolic.physics.plant"}}
    bad = structure.layer_violations(g)
    assert any("layer 1) imports rpo.runtime.run.simulate (layer 3)" in b for b in bad)
    assert any("never imports rpo.symbolic" in b for b in bad)


def test_the_layers_are_the_ones_the_architecture_doc_draws():
    text = DOC.read_text()
    for i, layer in enumerate(structure.RUNTIME_LAYERS):
        for pkg in layer:
            path = pkg.replace("rpo.", "").replace(".", "/")
            assert f"| {i} |" in text and path in text, f"docs/architecture.md does not draw layer {i}: {path}"


def test_a_type_checking_import_is_not_a_dependency(tmp_path):
    (tmp_path / "runtime").mkdir()
    (tmp_path / "runtime" / "a.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from rpo.runtime import b\nimport rpo.runtime.c\n")
    for n in ("b", "c"):
        (tmp_path / "runtime" / f"{n}.py").write_text("")
    for top in ("symbolic", "generated"):
        (tmp_path / top).mkdir()
    g = structure.graph(tmp_path)
    assert g["rpo.runtime.a"] == {"rpo.runtime.c"}


def test_no_runtime_module_is_oversized_and_no_package_is_listed_by_hand():
    assert structure.oversized() == [], "a runtime module over 600 lines says no reason (# size: ...)"
    assert structure.hand_kept_packages() == 0, "pyproject.toml lists packages by hand: setup.py discovers them"


def test_each_vocabulary_is_declared_once_and_an_output_format_is_added_in_one_module():
    copies = structure.vocabulary_copies()
    assert set(copies) == {"output formats", "figure formats", "distributions", "fault kinds"}
    assert all(v == [] for v in copies.values()), copies
    from rpo.runtime.formats import OUTPUT_FORMATS

    assert structure.files_naming_every(set(OUTPUT_FORMATS)) == ["runtime/formats.py"]
