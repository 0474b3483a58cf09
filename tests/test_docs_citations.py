"""The repository cites papers, not paths: no tracked text names a file a user does not have.

rpo was written from text extractions of four papers and a brief that came with them, outside
the repository.  A reader has neither, so every file of the repository (scenario files, docs,
code, tests) cites a paper by its short name ("paper 001, section 7, Table 2"), which
``docs/papers.md`` resolves to its bibliographic data, and rpo's reading of whatever the
extraction lost is written in the repository (``docs/papers.md``, ``docs/controllers/``).
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAPERS = ROOT / "docs" / "papers.md"
SELF = Path(__file__).resolve().relative_to(ROOT).as_posix()

#: What a user of the repository does not have: the folder the papers' texts and the brief came
#: from, the brief itself, and absolute paths of the machine rpo was written on.
FORBIDDEN = {
    "the shared folder of the papers' texts": re.compile("shared" + "/"),
    "the brief (a file outside the repository)": re.compile(r"\bSPEC" + r"(\.md)?\b"),
    "an absolute path of a machine": re.compile(r"(?<![\w.~$}\-/])/(?:" + "work|tmp|home" + r")(?:/|\b)"),
}

#: Lines that still cite the brief, each with the reason it cannot change now.  A comment in
#: symbolic/ is part of the model's source hash (``symbolic/codegen/codegen.py``): editing it
#: changes every generated file's banner and the library's cache key, so these change with the
#: next model edit (and ``python build.py``), not in a documentation change.  An entry that no
#: longer matches fails the test, so the list only shrinks.
KNOWN = {
    ("symbolic/physics/actuators.py", "Values (000 Table 3, via SPEC.md) are parameters"),
    ("symbolic/physics/mass_properties.py", "SPEC.md gives the described features"),
    ("symbolic/physics/plant.py", '# constants (SPEC.md "Common constants")'),
}

_BINARY = {".gz", ".png", ".parquet", ".npz", ".mat", ".pdf", ".jpg", ".svg", ".so", ".o", ".pyc"}


def _text_files() -> list[Path]:
    """The tracked files (and new ones not ignored) that are text."""
    try:
        out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"], cwd=ROOT,
                             capture_output=True, check=True, timeout=60).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    files = []
    for name in sorted(set(out.decode().split("\0")) - {""}):
        path = ROOT / name
        if path.suffix in _BINARY or not path.is_file():
            continue
        try:
            path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        files.append(path)
    return files


@pytest.fixture(scope="module")
def texts() -> dict[str, str]:
    return {p.relative_to(ROOT).as_posix(): p.read_text(encoding="utf-8") for p in _text_files()}


def test_no_file_cites_a_path_outside_the_repository(texts):
    bad, seen = [], set()
    for name, text in texts.items():
        if name == SELF:  # it names what it looks for
            continue
        for n, line in enumerate(text.splitlines(), 1):
            for what, pattern in FORBIDDEN.items():
                if not pattern.search(line):
                    continue
                known = next((k for k in KNOWN if k[0] == name and k[1] in line), None)
                if known:
                    seen.add(known)
                    continue
                bad.append(f"{name}:{n}: {what}: {line.strip()[:120]}")
    assert not bad, "cite the paper (docs/papers.md) or an in-repository doc instead:\n" + "\n".join(bad)
    assert seen == KNOWN, f"KNOWN entries that no longer match (remove them): {sorted(KNOWN - seen)}"


def _papers() -> dict[str, str]:
    """docs/papers.md's citations: short name -> the entry's text."""
    text = PAPERS.read_text(encoding="utf-8")
    section = text.split("## Citations", 1)[1].split("\n## ", 1)[0]
    entries = re.split(r"\n- (?=\*\*paper \d{3}\*\*)", section)
    return {m.group(1): e for e in entries if (m := re.match(r"\*\*paper (\d{3})\*\*", e))}


def test_every_paper_cited_is_in_papers_md(texts):
    papers = _papers()
    assert set(papers) == {"000", "001", "002", "004"}
    cite = re.compile(r"\b(?:paper|seed)s? (\d{3})\b", re.IGNORECASE)
    unknown = [f"{name}: paper {m.group(1)}" for name, text in texts.items() for m in cite.finditer(text)
               if m.group(1) not in papers]
    assert not unknown, "cited but not in docs/papers.md:\n" + "\n".join(sorted(set(unknown)))


def test_each_citation_has_its_bibliographic_data():
    """Each entry gives the venue and year, or says the text it was read from prints none."""
    for pid, entry in _papers().items():
        if "prints no venue, year or DOI" in entry:
            continue
        assert re.search(r"doi:10\.\d{4,}/\S+", entry), f"paper {pid}: no DOI"
        assert re.search(r"\b(19|20)\d\d\b", entry), f"paper {pid}: no year"


def test_the_forbidden_patterns_match_what_they_should():
    hits = {
        "shared" + "/seeds/001_x.txt": True, "see " + "SPEC" + ".md": True, "(SPEC" + ")": True,
        # the paths spelled in pieces, so that this file writes no path of a machine itself
        "--out " + "/t" + "mp/x": True, "/ho" + "me" + "/u/rpo": True, "`" + "/wo" + "rk/main`": True,
        "SPECTRAL_NORM": False, "$tmp" + "/wo" + "rk": False, "runs/report/x": False,
        "https://doi.org/10.1" + "/wo" + "rk/x": False,
    }
    for line, expected in hits.items():
        assert any(p.search(line) for p in FORBIDDEN.values()) is expected, line
