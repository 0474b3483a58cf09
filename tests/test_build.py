"""The build system: stale code is never loaded, builds are atomic and concurrent-safe."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime import compiled
from rpo.runtime.errors import ModelError

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def gen_copy(tmp_path):
    dst = tmp_path / "generated"
    shutil.copytree(ROOT / "generated", dst, ignore=shutil.ignore_patterns("__pycache__", ".lock"))
    return dst


def test_manifest_records_hashes_versions_and_io(model):
    m = model.manifest
    assert len(m["source_hash"]) == 64 and set(m["tools"]) == {"casadi", "sympy"}
    for name, desc in m["functions"].items():
        assert desc["inputs"] and desc["outputs"], name
        for io in desc["inputs"] + desc["outputs"]:
            assert len(io["shape"]) == 2
    # units and names of every state entry are recorded for the runtime
    assert all("unit" in f for f in m["layouts"]["x"])


def test_generated_sources_are_marked_as_generated():
    for name in ("rpo_model.c", "rpo_model.h"):
        head = (ROOT / "generated" / name).read_text()[:400]
        assert "GENERATED FILE - DO NOT EDIT" in head and "build.py" in head


def test_hand_edited_generated_source_is_refused(gen_copy):
    c = gen_copy / "rpo_model.c"
    c.write_text(c.read_text().replace("casadi_real a0", "casadi_real  a0", 1))
    with pytest.raises(ModelError, match="does not match manifest"):
        compiled.read_manifest(gen_copy)


def test_library_name_follows_the_content(gen_copy, tmp_path, monkeypatch):
    monkeypatch.setenv("RPO_CACHE_DIR", str(tmp_path / "cache"))
    cc = compiled.find_compiler()
    k1 = compiled.library_key(gen_copy, compiled.read_manifest(gen_copy), compiled.compiler_identity(cc))
    c = gen_copy / "rpo_model.c"
    c.write_text(c.read_text() + "\n/* changed */\n")
    m = json.loads((gen_copy / "manifest.json").read_text())
    import hashlib

    m["files"]["rpo_model.c"] = hashlib.sha256(c.read_bytes()).hexdigest()
    m["manifest_hash"] = compiled.manifest_hash(m)
    (gen_copy / "manifest.json").write_text(json.dumps(m))
    k2 = compiled.library_key(gen_copy, compiled.read_manifest(gen_copy), compiled.compiler_identity(cc))
    assert k1 != k2
    k3 = compiled.library_key(gen_copy, compiled.read_manifest(gen_copy), "another compiler 1.0")
    assert k3 != k2


def test_two_concurrent_builds_are_safe(gen_copy, tmp_path):
    """Two processes build the same library into an empty cache at once: one compiles, the other
    waits on the lock and reuses it; no partial file is ever visible under the final name."""
    cache = tmp_path / "cache"
    code = ("import sys; from pathlib import Path; from rpo.runtime import compiled; "
            "lib, built = compiled.build_library(Path(sys.argv[1]), Path(sys.argv[2])); print(lib, built)")
    procs = [subprocess.Popen([sys.executable, "-c", code, str(gen_copy), str(cache)], stdout=subprocess.PIPE,
                              text=True) for _ in range(2)]
    outs = [p.communicate(timeout=600)[0].split() for p in procs]
    assert all(p.returncode == 0 for p in procs)
    assert outs[0][0] == outs[1][0]
    assert sorted(o[1] for o in outs) == ["False", "True"]
    libs = [f for f in cache.iterdir() if f.suffix == ".so"]
    assert len(libs) == 1 and not [f for f in cache.iterdir() if "tmp" in f.name]


def test_no_compiler_gives_a_clear_error(gen_copy, tmp_path, monkeypatch):
    monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    monkeypatch.setenv("RPO_CACHE_DIR", str(tmp_path / "empty-cache"))
    with pytest.raises(ModelError, match="no C compiler found.*apt-get install gcc.*--backend casadi"):
        compiled.load_model(gen_dir=gen_copy)


def test_casadi_fallback_is_explicit_warned_and_equal(model):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fb = compiled.load_model(backend="casadi")
    assert any("100x slower" in str(w.message) for w in caught)
    rng = np.random.default_rng(0)
    p, k = model.vector("p"), model.vector("k_baseline")
    z = np.zeros(model.layout_size("z_baseline"))
    z[3] = z[14] = 1
    z[18:24] = [60, 0, 25, 3, -0.5, 5]
    w = rng.normal(size=model.layout_size("w"))
    a, b = model.step_baseline(z, 1.0, p, k, w), fb.step_baseline(z, 1.0, p, k, w)
    for x, y in zip(a, b, strict=True):
        assert np.allclose(x, y, rtol=1e-13, atol=1e-13)


def test_hand_edited_manifest_is_refused(gen_copy):
    """Swapping two parameter fields (or a unit, or a default) would silently repack p."""
    path = gen_copy / "manifest.json"
    m = json.loads(path.read_text())
    lay = m["layouts"]["p"]
    i, j = [k for k, f in enumerate(lay) if f["name"] in ("orbit_raan", "orbit_argp")]
    lay[i], lay[j] = lay[j], lay[i]
    path.write_text(json.dumps(m))
    with pytest.raises(ModelError, match="does not match its recorded hash"):
        compiled.read_manifest(gen_copy)


def test_manifest_hash_definitions_agree():
    from rpo.symbolic import codegen

    m = json.loads((ROOT / "generated" / "manifest.json").read_text())
    assert codegen.manifest_hash(m) == compiled.manifest_hash(m) == m["manifest_hash"]


def test_fast_math_library_is_refused(gen_copy, tmp_path, monkeypatch):
    """A $CC that adds -ffast-math breaks NaN detection; the loader's self-test refuses it."""
    cc = compiled.find_compiler()
    wrapper = tmp_path / "ccwrap"
    wrapper.write_text(f'#!/bin/sh\nexec {cc[0]} -ffast-math "$@"\n')
    wrapper.chmod(0o755)
    monkeypatch.setenv("CC", str(wrapper))
    monkeypatch.setenv("RPO_CACHE_DIR", str(tmp_path / "cache"))
    with pytest.raises(ModelError, match="does not detect NaN"):
        compiled.load_model(gen_dir=gen_copy)


def test_loaded_library_is_checked_against_the_manifest(gen_copy, tmp_path, monkeypatch):
    """A manifest that disagrees with the library's signatures is refused at load time."""
    monkeypatch.setenv("RPO_CACHE_DIR", str(tmp_path / "cache"))
    m = json.loads((gen_copy / "manifest.json").read_text())
    m["functions"]["kepler"]["inputs"][0]["shape"] = [2, 1]
    m["manifest_hash"] = compiled.manifest_hash(m)  # consistent manifest, inconsistent library
    (gen_copy / "manifest.json").write_text(json.dumps(m))
    with pytest.raises(ModelError, match="kepler"):
        compiled.load_model(gen_dir=gen_copy)


def test_build_check_detects_a_stale_generated_folder(tmp_path):
    """Edit the model in a copy of the checkout: `build.py --check` fails with a readable diff;
    `build.py` then regenerates, and `--check` passes."""
    repo = tmp_path / "repo"
    repo.mkdir()
    for d in ("symbolic", "runtime", "generated"):
        shutil.copytree(ROOT / d, repo / d, ignore=shutil.ignore_patterns("__pycache__", ".lock"))
    shutil.copy(ROOT / "build.py", repo / "build.py")
    env_py = repo / "symbolic" / "environment.py"
    env_py.write_text(env_py.read_text().replace("return 3 * mu / r**3 * cross(", "return 2 * mu / r**3 * cross("))
    res = subprocess.run([sys.executable, "build.py", "--check"], cwd=repo, capture_output=True, text=True)
    assert res.returncode == 1
    assert "STALE" in res.stdout and "generated/rpo_model.c: differs" in res.stdout
    res = subprocess.run([sys.executable, "build.py", "--no-compile"], cwd=repo, capture_output=True, text=True)
    assert res.returncode == 0 and "regenerating" in res.stdout
    res = subprocess.run([sys.executable, "build.py", "--no-compile"], cwd=repo, capture_output=True, text=True)
    assert "nothing to regenerate" in res.stdout
    res = subprocess.run([sys.executable, "build.py", "--check"], cwd=repo, capture_output=True, text=True)
    assert res.returncode == 0, res.stdout[-2000:]


def test_source_hash_ignores_the_lyapunov_claims(tmp_path):
    """Editing a claim (symbolic/lyapunov/) must not make generated/ stale; editing the model must."""
    import shutil

    from rpo.symbolic import codegen

    src = Path(codegen.SYMBOLIC_DIR)
    dst = tmp_path / "symbolic"
    shutil.copytree(src, dst, ignore=shutil.ignore_patterns("__pycache__"))
    h0 = codegen.source_hash(dst)
    (dst / "lyapunov" / "c004.py").write_text((dst / "lyapunov" / "c004.py").read_text() + "\n# edit\n")
    assert codegen.source_hash(dst) == h0
    (dst / "plant.py").write_text((dst / "plant.py").read_text() + "\n# edit\n")
    assert codegen.source_hash(dst) != h0
