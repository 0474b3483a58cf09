"""docs/architecture.md stays true: every module of symbolic/ and runtime/ is named there.

Controller modules (``symbolic/controllers/<name>.py``) and their claims packages
(``symbolic/lyapunov/<name>/``) are discovered, not listed, so the file describes the pattern and
they are exempt: adding a controller must not require editing a document.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "architecture.md"


def _modules() -> list[str]:
    out = []
    for top in ("symbolic", "runtime"):
        for f in sorted((ROOT / top).rglob("*")):
            rel = f.relative_to(ROOT)
            if "__pycache__" in rel.parts or f.name == "__init__.py" or f.suffix not in (".py", ".c"):
                continue
            if rel.parts[:2] == ("symbolic", "controllers"):
                continue
            if rel.parts[:2] == ("symbolic", "lyapunov") and len(rel.parts) > 3:
                continue  # symbolic/lyapunov/<controller>/...
            out.append(rel.as_posix())
    return [*out, "build.py", "verify.py"]


def _missing(text: str) -> list[str]:
    return [m for m in _modules() if m not in text]


def test_every_module_is_named_in_the_architecture_doc():
    missing = _missing(DOC.read_text())
    assert not missing, f"docs/architecture.md does not name: {', '.join(missing)}"


def test_the_discovered_folders_are_described():
    text = DOC.read_text()
    for pattern in ("symbolic/controllers/<name>.py", "symbolic/lyapunov/<name>/", "`symbolic/controllers/`"):
        assert pattern in text, pattern


def test_the_check_sees_a_module_missing_from_the_doc():
    """The check can fail: a module the doc does not name is reported, and only that one."""
    text = DOC.read_text().replace("symbolic/codegen/structural_cse.py", "(removed)")
    assert _missing(text) == ["symbolic/codegen/structural_cse.py"]
