"""The build system: incremental per-function generation, cached parallel compilation, and the
guarantees around it (deterministic bytes, stale code never loaded, atomic and concurrent-safe).

Everything that generates or compiles runs on the tiny fixture model (``tests/fixtures/``), in
milliseconds; the full model is only read (its committed manifest, its module closures) or
loaded through the shared, cached ``model`` fixture.  ``build.py --check`` on the full model is
a CI step of its own and is not repeated here.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
import tiny_model

import build
from rpo.runtime.errors import ModelError
from rpo.runtime.model import library
from rpo.runtime.model.functions import CompiledFunction
from rpo.runtime.model.library import build_library, library_key, link_library, prune_cache
from rpo.runtime.model.loader import load_model
from rpo.runtime.model.manifest import MANIFEST_FORMAT, manifest_hash, parse_manifest, read_manifest, selected_sources
from rpo.runtime.model.toolchain import compile_object, compiler_identity, find_compiler
from rpo.symbolic.codegen import codegen, functions

from conftest import target_state

ROOT = Path(__file__).resolve().parents[1]


def _generate(src: Path, gen: Path, **kw) -> codegen.GenerateResult:
    gen.mkdir(exist_ok=True)
    result = codegen.generate(tiny_model.families(src, **kw), src, reuse=gen)
    codegen.update_folder(result, gen)
    return result


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text, (path, old)
    path.write_text(text.replace(old, new))


@pytest.fixture
def tiny(tmp_path):
    """(model sources, generated folder, cache) of a freshly generated tiny model."""
    src = tiny_model.copy_model(tmp_path / "tiny")
    gen = tmp_path / "generated"
    _generate(src, gen)
    return src, gen, tmp_path / "cache"


def _files(gen: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(gen.iterdir()) if p.is_file() and not p.name.startswith(".")}


# --------------------------------------------------------------------------- generation


def test_one_file_set_per_function_with_banner(tiny):
    src, gen, _ = tiny
    m = read_manifest(gen)
    assert set(m.functions) == {"tiny_rhs", "tiny_out", "law_a", "step_a", "law_b", "step_b"}
    assert list(m.sources) == sorted(f"{n}.c" for n in m.functions)
    for name, desc in m.functions.items():
        for ext in (".c", ".h", ".casadi.gz"):
            assert (gen / f"{name}{ext}").is_file()
        head = (gen / f"{name}.c").read_text()[:1200]
        fam = m.families[desc.family]
        assert head.startswith("/* GENERATED FILE - DO NOT EDIT.") and "python build.py" in head
        assert fam.hash in head and f"Operations: {desc.ops} " in head and desc.ops > 0
        for mod in fam.modules:
            assert f"symbolic/{mod}" in head
    # the closure of a controller family: its own module, not the other controller's
    assert m.families["ctrl_a"].modules == ("__init__.py", "ctrl_a.py")
    assert m.families["plant"].modules == ("__init__.py", "plant.py", "shared.py")


def test_generation_is_deterministic_and_incremental_equals_scratch(tiny, tmp_path):
    src, gen, _ = tiny
    again = codegen.generate(tiny_model.families(src), src, reuse=None)
    files = dict(again.files, **{"manifest.json": codegen.manifest_bytes(again.manifest)})
    assert files == _files(gen)
    # edit one controller: only its family is re-derived, the rest reused; bytes equal a scratch build
    _edit(src / "ctrl_a.py", "K = 0.5", "K = 0.75")
    inc = codegen.generate(tiny_model.families(src), src, reuse=gen)
    assert inc.rebuilt == ["ctrl_a"] and inc.reused == ["plant", "ctrl_b"]
    scratch = codegen.generate(tiny_model.families(src), src, reuse=None)
    assert scratch.rebuilt == ["plant", "ctrl_a", "ctrl_b"]
    assert inc.files == scratch.files and inc.manifest == scratch.manifest
    assert inc.files["law_a.c"] != _files(gen)["law_a.c"]


def test_controller_edit_rewrites_only_its_files(tiny):
    src, gen, _ = tiny
    before = _files(gen)
    _edit(src / "ctrl_b.py", "K = 0.25", "K = 0.3")
    result = codegen.generate(tiny_model.families(src), src, reuse=gen)
    written = codegen.update_folder(result, gen)
    assert sorted(written) == sorted(["law_b.c", "law_b.h", "law_b.casadi.gz", "step_b.c", "step_b.h",
                                      "step_b.casadi.gz", "manifest.json"])
    after = _files(gen)
    assert {n for n in before if before[n] != after[n]} == set(written)


def test_shared_module_edit_rederives_every_dependent_family(tiny):
    src, gen, _ = tiny
    _edit(src / "shared.py", "GAIN = 2.0", "GAIN = 3.0")
    result = codegen.generate(tiny_model.families(src), src, reuse=gen)
    assert result.rebuilt == ["plant", "ctrl_a", "ctrl_b"]  # the steps embed the plant


def test_dependent_family_uses_the_plant_functions_from_generated(tiny):
    """A reused plant is deserialised from generated/: the step evaluates like a fresh composition."""
    src, gen, _ = tiny
    _edit(src / "ctrl_a.py", "K = 0.5", "K = 0.6")
    result = codegen.generate(tiny_model.families(src), src, reuse=gen)
    assert "plant" in result.reused
    import gzip

    step = ca.Function.deserialize(gzip.decompress(result.files["step_a.casadi.gz"]).decode())
    x = np.array([0.3, -0.2, 0.1])
    u = -0.6 * x
    expected = x + 0.01 * (2.0 * x * x + 1 - x + u)
    assert np.allclose(np.asarray(step(x)).ravel(), expected, rtol=0, atol=1e-15)


def test_removed_family_removes_its_files(tiny):
    src, gen, _ = tiny
    (src / "ctrl_b.py").unlink()
    result = codegen.generate(tiny_model.families(src, controllers=("a",)), src, reuse=gen)
    codegen.update_folder(result, gen)
    assert not list(gen.glob("*_b.*"))
    assert set(read_manifest(gen).controllers) == {"a"}


def test_model_definition_errors_are_reported():
    fam = tiny_model.families(tiny_model.FIXTURE)
    with pytest.raises(ValueError, match="cycle"):
        codegen.generate([codegen.Family("x", (), fam[0].build, ("y",)),
                          codegen.Family("y", (), fam[0].build, ("x",))], tiny_model.FIXTURE)
    with pytest.raises(codegen.ModelDefinitionError, match="tiny_rhs is generated by both"):
        codegen.generate([fam[0], codegen.Family("again", (), fam[0].build)], tiny_model.FIXTURE)


def test_check_reports_a_readable_diff(tiny):
    src, gen, _ = tiny
    _edit(src / "ctrl_a.py", "K = 0.5", "K = 0.5 + 1e-3")
    fresh = codegen.generate(tiny_model.families(src), src, reuse=None)
    diff = "".join(build.compare(dict(fresh.files, **{"manifest.json": codegen.manifest_bytes(fresh.manifest)}),
                                 gen))
    assert "generated/law_a.c: differs" in diff and "generated/step_a.c: differs" in diff
    assert "generated/law_b.c" not in diff and "generated/tiny_rhs.c" not in diff
    # the changed constant shows in the unified diff, old and new
    assert any(ln.startswith("-") and "5.0000000000000000e-01" in ln for ln in diff.splitlines())
    assert any(ln.startswith("+") and "5.0100000000000000e-01" in ln for ln in diff.splitlines())


def test_concurrent_regenerations_leave_a_consistent_folder(tiny):
    """Two build processes regenerate the same folder at once: both succeed, the second finds
    nothing to do (lock), and the folder verifies against its manifest."""
    src, gen, _ = tiny
    _edit(src / "ctrl_a.py", "K = 0.5", "K = 0.9")
    code = ("import sys; sys.path[:0] = [sys.argv[3], sys.argv[4]]; from pathlib import Path; import build; "
            "import tiny_model; src = Path(sys.argv[1]); "
            "print(build.regenerate(Path(sys.argv[2]), log=lambda m: None, "
            "families=tiny_model.families(src), root=src))")
    procs = [subprocess.Popen([sys.executable, "-c", code, str(src), str(gen), str(ROOT), str(ROOT / "tests")],
                              stdout=subprocess.PIPE, text=True) for _ in range(2)]
    outs = sorted(p.communicate(timeout=300)[0].strip() for p in procs)
    assert all(p.returncode == 0 for p in procs)
    assert outs == ["['ctrl_a']", "[]"]
    read_manifest(gen)
    assert not [f for f in gen.iterdir() if f.name.startswith(".") and f.name != ".lock"]


# --------------------------------------------------------------------------- the real model's families


def test_rpo_families_cover_every_controller_module():
    fams = functions.families()
    assert [f.name for f in fams] == ["plant", *(f"controller_{n}" for n in functions.controller_names())]
    assert set(functions.controller_names()) >= {"baseline", "c000", "c001", "c002", "c004"}
    m = read_manifest(ROOT / "generated")
    assert set(m.families) == {f.name for f in fams}
    assert set(m.controllers) == set(functions.controller_names())


def test_family_closures_follow_the_imports(tmp_path):
    """Editing a Lyapunov claim changes no family; editing c001 changes only controller_c001;
    editing the plant changes every family (each step embeds the plant)."""
    dst = tmp_path / "symbolic"
    shutil.copytree(functions.SYMBOLIC_DIR, dst, ignore=shutil.ignore_patterns("__pycache__"))

    def hashes():
        fams = [codegen.Family(f.name, tuple(dst / Path(s).relative_to(functions.SYMBOLIC_DIR) for s in f.seeds),
                               f.build, f.depends) for f in functions.families()]
        return {k: v["hash"] for k, v in codegen.family_hashes(fams, dst).items()}

    h0 = hashes()
    m = read_manifest(ROOT / "generated")
    assert h0 == {k: v.hash for k, v in m.families.items()}  # generated/ is of these sources
    for claims in (dst / "lyapunov").rglob("*.py"):
        claims.write_text(claims.read_text() + "\n# edit\n")
    assert hashes() == h0
    (dst / "controllers" / "c001.py").write_text((dst / "controllers" / "c001.py").read_text() + "\n# edit\n")
    h1 = hashes()
    assert {k for k in h0 if h0[k] != h1[k]} == {"controller_c001"}
    (dst / "physics" / "environment.py").write_text((dst / "physics" / "environment.py").read_text() + "\n# edit\n")
    h2 = hashes()
    assert all(h2[k] != h1[k] for k in h0)


def test_manifest_records_hashes_versions_and_io(model):
    m = model.manifest
    assert len(m.source_hash) == 64 and set(m.tools) == {"casadi", "sympy"}
    assert m.tools == codegen.tool_versions() == {"casadi": ca.__version__, "sympy": __import__("sympy").__version__}
    for name, desc in m.functions.items():
        assert desc.inputs and desc.outputs, name
        assert desc.source == f"{name}.c" and desc.family in m.families
        for io in desc.inputs + desc.outputs:
            assert len(io.shape) == 2
    # units and names of every state entry are recorded for the runtime
    raw = json.loads((ROOT / "generated" / "manifest.json").read_text())
    assert all("unit" in f for f in raw["layouts"]["x"])
    assert [f.unit for f in m.layouts["x"]] == [f["unit"] for f in raw["layouts"]["x"]]


def test_manifest_hash_and_format_definitions_agree():
    m = json.loads((ROOT / "generated" / "manifest.json").read_text())
    assert codegen.manifest_hash(m) == manifest_hash(m) == m["manifest_hash"]
    assert codegen.FORMAT_VERSION == MANIFEST_FORMAT == m["format_version"]


# --------------------------------------------------------------------------- compiling and loading


def test_compile_is_cached_per_object_and_parallel(tiny):
    src, gen, cache = tiny
    lines: list[str] = []
    lib1, built = build_library(gen, cache, log=lines.append, jobs=2)
    assert built and lib1.exists()
    assert "compiling 7 of 7 C files on 2 cores (0 cached)" in lines[0]
    assert sum("left)" in ln for ln in lines) == 7  # one progress line per file
    assert build_library(gen, cache) == (lib1, False)
    _edit(src / "ctrl_a.py", "K = 0.5", "K = 0.4")
    _generate(src, gen)
    lines.clear()
    lib2, built = build_library(gen, cache, log=lines.append)
    assert built and lib2 != lib1 and lib1.exists()  # a loaded library is never replaced in place
    assert "compiling 2 of 7 C files" in lines[0] and "(5 cached)" in lines[0]
    assert not [f for f in cache.rglob("*") if "tmp" in f.name]


def test_tiny_library_evaluates_like_casadi(tiny, monkeypatch):
    src, gen, cache = tiny
    monkeypatch.setenv("RPO_CACHE_DIR", str(cache))
    model = load_model(gen_dir=gen)
    rng = np.random.default_rng(1)
    import gzip

    # the compiled code calls rpo's math functions (runtime/csrc/rpo_math.h, <= 0.75 ulp for sin),
    # CasADi's VM the C library's: equal bits without them, a few ulp apart with them
    transcendental = {ca.OP_SIN, ca.OP_COS, ca.OP_TAN, ca.OP_EXP, ca.OP_LOG, ca.OP_ASIN, ca.OP_ACOS,
                      ca.OP_ATAN, ca.OP_ATAN2, ca.OP_SINH, ca.OP_COSH, ca.OP_TANH}
    for name in model.functions:
        ref = ca.Function.deserialize(gzip.decompress((gen / f"{name}.casadi.gz").read_bytes()).decode())
        args = [rng.normal(size=int(np.prod(s))) for s in model.functions[name].in_shapes]
        got = model.functions[name](*args)
        want = ref(*args)
        want = want if isinstance(want, (list, tuple)) else [want]
        ops = {ref.instruction_id(k) for k in range(ref.n_instructions())} if ref.is_a("SXFunction") else set()
        for g, w in zip(got, want, strict=True):
            w = np.asarray(w).ravel(order="F")
            if ops & transcendental:
                np.testing.assert_array_max_ulp(np.ravel(g), w, maxulp=4)
            else:
                assert np.array_equal(np.ravel(g), w), name


def test_library_name_follows_the_content(tiny):
    src, gen, _ = tiny
    cc = find_compiler()
    m = read_manifest(gen)
    k1 = library_key(gen, m, compiler_identity(cc))
    assert library_key(gen, m, "another compiler 1.0") != k1
    _edit(src / "shared.py", "GAIN = 2.0", "GAIN = 2.5")
    _generate(src, gen)
    assert library_key(gen, read_manifest(gen), compiler_identity(cc)) != k1


def test_two_concurrent_builds_are_safe(tiny):
    """Two processes build the same library into an empty cache at once: one compiles, the other
    waits on the lock and reuses it; no partial file is ever visible under the final name."""
    _, gen, cache = tiny
    code = ("import sys; from pathlib import Path; from rpo.runtime.model.library import build_library; "
            "lib, built = build_library(Path(sys.argv[1]), Path(sys.argv[2])); print(lib, built)")
    procs = [subprocess.Popen([sys.executable, "-c", code, str(gen), str(cache)], stdout=subprocess.PIPE,
                              text=True) for _ in range(2)]
    outs = [p.communicate(timeout=300)[0].split() for p in procs]
    assert all(p.returncode == 0 for p in procs)
    assert outs[0][0] == outs[1][0]
    assert sorted(o[1] for o in outs) == ["False", "True"]
    libs = [f for f in cache.iterdir() if f.suffix == ".so"]
    assert len(libs) == 1 and not [f for f in cache.rglob("*") if "tmp" in f.name]


def test_hand_edited_generated_source_is_refused(tiny):
    _, gen, _ = tiny
    c = gen / "step_a.c"
    c.write_text(c.read_text().replace("casadi_real a0", "casadi_real  a0", 1))
    with pytest.raises(ModelError, match="step_a.c does not match manifest"):
        read_manifest(gen)


def test_missing_generated_file_is_refused(tiny):
    _, gen, _ = tiny
    (gen / "law_b.c").unlink()
    with pytest.raises(ModelError, match="law_b.c is missing"):
        read_manifest(gen)


def test_hand_edited_manifest_is_refused(gen_copy):
    """Swapping two parameter fields (or a unit, or a default) would silently repack p."""
    path = gen_copy / "manifest.json"
    m = json.loads(path.read_text())
    lay = m["layouts"]["p"]
    i, j = [k for k, f in enumerate(lay) if f["name"] in ("orbit_raan", "orbit_argp")]
    lay[i], lay[j] = lay[j], lay[i]
    path.write_text(json.dumps(m))
    with pytest.raises(ModelError, match="does not match its recorded hash"):
        read_manifest(gen_copy)


def test_old_manifest_format_is_refused(tiny):
    _, gen, _ = tiny
    m = json.loads((gen / "manifest.json").read_text())
    m["format_version"] = 1
    m["manifest_hash"] = manifest_hash(m)
    (gen / "manifest.json").write_text(json.dumps(m))
    with pytest.raises(ModelError, match="format 1, this runtime reads format 2"):
        read_manifest(gen)


def test_loaded_library_is_checked_against_the_manifest(tiny, monkeypatch):
    """A manifest that disagrees with the library's signatures is refused when the function is loaded
    (compiled on first use), before any call."""
    _, gen, cache = tiny
    monkeypatch.setenv("RPO_CACHE_DIR", str(cache))
    m = json.loads((gen / "manifest.json").read_text())
    m["functions"]["tiny_out"]["inputs"][0]["shape"] = [2, 1]
    m["manifest_hash"] = manifest_hash(m)  # consistent manifest, inconsistent library
    (gen / "manifest.json").write_text(json.dumps(m))
    model = load_model(gen_dir=gen)
    with pytest.raises(ModelError, match="tiny_out"):
        model.function("tiny_out")


def test_no_compiler_gives_a_clear_error(tiny, tmp_path, monkeypatch):
    _, gen, _ = tiny
    monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    monkeypatch.setenv("RPO_CACHE_DIR", str(tmp_path / "empty-cache"))
    with pytest.raises(ModelError, match="no C compiler found.*apt-get install gcc.*--backend casadi"):
        load_model(gen_dir=gen)


def test_compiler_error_is_reported_with_the_file(tiny, tmp_path):
    _, gen, cache = tiny
    broken = gen / "tiny_out.c"
    broken.write_text(broken.read_text() + "\n#error planted\n")
    m = json.loads((gen / "manifest.json").read_text())
    m["files"]["tiny_out.c"] = hashlib.sha256(broken.read_bytes()).hexdigest()
    m["manifest_hash"] = manifest_hash(m)
    (gen / "manifest.json").write_text(json.dumps(m))
    with pytest.raises(ModelError, match="compiling tiny_out.c failed.*planted"):
        build_library(gen, cache)
    assert not list(cache.glob("*.so"))


@pytest.mark.parametrize(("flag", "error"), [
    ("-ffast-math", "compiling .* failed .*-ffast-math breaks IEEE semantics"),  # rpo_math.h refuses to compile
    ("-ffinite-math-only", "does not detect NaN"),                               # the loader's self-test
])
def test_fast_math_library_is_refused(tiny, tmp_path, monkeypatch, flag, error):
    """A $CC that adds -ffast-math or -ffinite-math-only breaks NaN detection: refused."""
    _, gen, _ = tiny
    cc = find_compiler()
    wrapper = tmp_path / "ccwrap"
    wrapper.write_text(f'#!/bin/sh\nexec {cc[0]} {flag} "$@"\n')
    wrapper.chmod(0o755)
    monkeypatch.setenv("CC", str(wrapper))
    monkeypatch.setenv("RPO_CACHE_DIR", str(tmp_path / "cache"))
    with pytest.raises(ModelError, match=error):
        load_model(gen_dir=gen).function("tiny_out")


def test_casadi_fallback_is_explicit_warned_and_equal(model):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fb = load_model(backend="casadi")
    assert any("100x slower" in str(w.message) for w in caught)
    rng = np.random.default_rng(0)
    p, k = model.vector("p"), model.vector("k_baseline")
    z = np.zeros(model.layout_size("z_baseline"))
    oz = model.offsets("z_baseline")
    z[oz["q_c"].stop - 1] = z[oz["q_t"].stop - 1] = 1
    z[oz["r"]], z[oz["v"]] = [60, 0, 25], [3, -0.5, 5]
    ts = target_state(model)
    z[oz["r_T"]], z[oz["v_T"]] = ts["r_T"], ts["v_T"]
    w = rng.normal(size=model.layout_size("w"))
    a, b = model.step_baseline(z, 1.0, p, k, w), fb.step_baseline(z, 1.0, p, k, w)
    for x, y in zip(a, b, strict=True):
        assert np.allclose(x, y, rtol=1e-13, atol=1e-13)


@pytest.fixture
def gen_copy(tmp_path):
    dst = tmp_path / "generated"
    shutil.copytree(ROOT / "generated", dst, ignore=shutil.ignore_patterns("__pycache__", ".lock"))
    return dst


def test_library_for_some_controllers_compiles_only_what_they_need(tiny, monkeypatch):
    """A run loads the plant and its own controller: the first run after an install compiles a
    fraction of the model; a later full build reuses those objects."""
    _, gen, cache = tiny
    monkeypatch.setenv("RPO_CACHE_DIR", str(cache))
    m = read_manifest(gen)
    assert selected_sources(m, ["a"]) == ["law_a.c", "step_a.c", "tiny_out.c", "tiny_rhs.c"]
    lines: list[str] = []
    model = load_model(gen_dir=gen, controllers=["a"], log=lines.append)
    assert lines == []  # nothing is compiled before a function is asked for
    model.prepare(model.functions)
    assert "compiling 5 of 5 C files" in lines[0]  # 4 generated + the loop driver
    assert set(model.functions) == {"law_a", "step_a", "tiny_out", "tiny_rhs"}
    with pytest.raises(ModelError, match="step_b is not loaded"):
        model.function("step_b")
    with pytest.raises(ModelError, match="unknown controller z; available: a, b"):
        load_model(gen_dir=gen, controllers=["z"])
    lines.clear()
    full = load_model(gen_dir=gen, log=lines.append)
    full.prepare(full.functions)
    assert "compiling 2 of 7 C files" in lines[0] and full.library != model.library


def test_composed_c_refuses_a_call_that_does_not_match_its_callee():
    """The C glue is generated only from a composition whose calls match the callees' signatures."""
    from rpo.symbolic.codegen.c_composition import Call, Callee, composed_c

    x = ca.SX.sym("x", 3)
    f = Callee.of(ca.Function("f", [x], [2 * x, x[0]], ["x"], ["y", "s"]))
    ok = dict(inputs=[("x", 3)], outputs=[("y", ["y", "s"])], buffers=[("y", 3), ("s", 1)])
    c_src, h_src = composed_c("g", calls=[Call(f, [("x", 0)], ["y", "s"])], **ok)
    assert "if (f(a, r, iw, w + 4, 0)) return 1;" in c_src and "int g(" in h_src
    with pytest.raises(ValueError, match="f takes 1 inputs and gives 2 outputs; the call passes 1 and takes 1"):
        composed_c("g", calls=[Call(f, [("x", 0)], ["y"])], **ok)
    with pytest.raises(ValueError, match=r"reads x\[1:4\] of a vector of 3"):
        composed_c("g", calls=[Call(f, [("x", 1)], ["y", "s"])], **ok)
    with pytest.raises(ValueError, match=r"writes 3 entries into buffer s \(1 entries\)"):
        composed_c("g", calls=[Call(f, [("x", 0)], ["s", "y"])], **ok)


def test_a_family_may_use_only_the_functions_of_the_families_it_depends_on(tiny):
    """resolve() refuses a function of a family not declared as a dependency, and a reused family
    still counts as the owner of its functions (a duplicate is caught against it)."""
    src, gen, _ = tiny
    fams = tiny_model.families(src)
    undeclared = codegen.Family("ctrl_a", fams[1].seeds, fams[1].build, ())
    with pytest.raises(codegen.ModelDefinitionError, match="ctrl_a asks for tiny_rhs, which no family"):
        codegen.generate([fams[0], undeclared], src, reuse=None)
    dup = codegen.Family("dup", fams[0].seeds, fams[0].build)
    with pytest.raises(codegen.ModelDefinitionError, match="generated by both plant and dup"):
        codegen.generate([*fams, dup], src, reuse=gen)  # plant reused, dup derived


def test_a_dependent_family_is_rederived_when_its_dependency_files_change(tiny):
    """Even with unchanged hashes, a controller family is reused only if the plant's generated files
    are the ones it was built against."""
    src, gen, _ = tiny
    m = json.loads((gen / "manifest.json").read_text())
    m["families"]["ctrl_a"]["depends_files"]["plant"] = "0" * 64
    m["manifest_hash"] = manifest_hash(m)
    (gen / "manifest.json").write_text(json.dumps(m))
    result = codegen.generate(tiny_model.families(src), src, reuse=gen)
    assert result.rebuilt == ["ctrl_a"] and result.reused == ["plant", "ctrl_b"]


def test_sources_are_compiled_from_the_bytes_their_key_was_computed_from(tiny, monkeypatch):
    """A generated/ rewritten between the key and the compile cannot put new code under an old key:
    the compiler is given the verified bytes, not the file."""
    src, gen, cache = tiny
    seen = []
    real = compile_object

    def racing(cc, name, source, obj, flags=None):
        if name == "law_a.c" and not seen:  # a build.py rewrites generated/ right now
            _edit(src / "ctrl_a.py", "K = 0.5", "K = 0.9")
            _generate(src, gen)
            seen.append(name)
        return real(cc, name, source, obj, flags)

    monkeypatch.setattr(library, "compile_object", racing)
    monkeypatch.setenv("RPO_CACHE_DIR", str(cache))
    old = codegen.generate(tiny_model.families(tiny_model.FIXTURE), tiny_model.FIXTURE, reuse=None).manifest
    typed = parse_manifest(old)
    lib, _ = link_library(gen, typed, cache)  # built for the manifest read before the edit
    assert seen
    lib_c = __import__("ctypes").CDLL(str(lib))
    f = CompiledFunction(lib_c, "law_a", typed.functions["law_a"])
    assert np.allclose(f(np.array([1.0, 2.0, 3.0]))[0], [-0.5, -1.0, -1.5])


def test_prune_keeps_what_the_current_model_uses(tiny):
    src, gen, cache = tiny
    old_lib, _ = build_library(gen, cache)
    build_library(gen, cache, controllers=["a"])
    _edit(src / "ctrl_b.py", "K = 0.25", "K = 0.35")
    _generate(src, gen)
    new_lib, _ = build_library(gen, cache)
    assert prune_cache(gen, cache, dry_run=True)[0] >= 3  # old library, law_b and step_b objects
    assert old_lib.exists()
    n, size = prune_cache(gen, cache)
    assert n >= 3 and size > 0 and not old_lib.exists() and new_lib.exists()
    assert build_library(gen, cache) == (new_lib, False)  # nothing the current model needs is gone
    lines: list[str] = []
    build_library(gen, cache, controllers=["a"], log=lines.append)
    assert not any("compiling" in ln for ln in lines)  # the "a" selection was kept: objects and library


def test_a_dead_build_s_temporary_files_are_cleaned_up(tiny):
    src, gen, _ = tiny
    (gen / ".law_a.c.k3j9x_2").write_bytes(b"half")  # as update_folder names them (mkstemp prefix)
    (gen / ".manifest.json.abc123").write_bytes(b"{")
    _edit(src / "ctrl_a.py", "K = 0.5", "K = 0.55")
    _generate(src, gen)
    assert sorted(f.name for f in gen.iterdir() if f.name.startswith(".")) == []
    read_manifest(gen)
