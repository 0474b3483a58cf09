"""MISRA C:2012 and cppcheck's own checks on a flight package, matched against a deviations file.

The command (run in a scratch copy of the package, so the addon's ``.dump`` files land there)::

    cppcheck --addon=misra --std=c99 --enable=warning,style,portability --suppress=missingIncludeSystem
             --xml --xml-version=2 --quiet -I . <the flight *.c> zz_rpo_misra_canary.c

cppcheck 2.10 runs the addon ``misra.py`` from its addons folder (Debian: the package cppcheck,
``/usr/lib/<triplet>/cppcheck/addons/``).  Without the MISRA rule texts (a licensed document, not
shipped) the addon reports rule numbers only, which is all the matching needs; ``rule_texts`` names a
texts file made from the standard's Appendix A to get the headlines too.  cppcheck says nothing when
the addon cannot run (no python3, a broken addon): every run therefore checks one more file, a canary
with a known violation (rule 19.2, ``union``), and a run without its finding is an error, never a pass.

The deviations file (TOML), one ``[[deviation]]`` per rule::

    [[deviation]]
    rule = "19.2"                          # MISRA C:2012 rule ("10.4", "Dir 4.6" as "dir-4.6") or a
                                           # cppcheck check id ("variableScope"); a string, always
    category = "advisory"                  # optional: mandatory | required | advisory
    reason = "bit casts of IEEE doubles"   # required: why the rule does not hold here
    files = ["rpo_*_math.c"]               # optional: file-name patterns (fnmatch); default every file

A finding whose rule has a deviation (and whose file matches its patterns) is *justified*, the rest
*unjustified*.  A mandatory rule (MISRA C:2012 with its amendments 1 and 2) admits no deviation: an
entry naming one is refused and its findings stay unjustified.
"""

from __future__ import annotations

import fnmatch
import json
import time
import tomllib
import xml.etree.ElementTree as ET
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.tools import Finding, flight_sources, require, run, scratch_copy

MISRA_PREFIX = "misra-c2012-"

CANARY = "zz_rpo_misra_canary.c"
CANARY_SOURCE = ("/* the MISRA addon ran: rule 19.2 (union) must be reported here */\n"
                 "union rpo_misra_canary { int i; float f; };\n")
CANARY_RULE = "19.2"

#: the mandatory guidelines of MISRA C:2012 (amendments 1 and 2 included): no deviation is permitted
MANDATORY = frozenset({"9.1", "12.5", "13.6", "17.3", "17.4", "17.6", "19.1", "21.13", "21.17", "21.18",
                       "21.19", "21.20", "22.2", "22.4", "22.5", "22.6"})

CATEGORIES = ("mandatory", "required", "advisory")

#: cppcheck's notes about itself, not about the code
IGNORED_IDS = frozenset({"missingIncludeSystem", "checkersReport", "toomanyconfigs", "unmatchedSuppression"})

ENABLE = "warning,style,portability"


@dataclass(frozen=True)
class Deviation:
    rule: str
    reason: str
    category: str = ""
    files: tuple[str, ...] = ()

    def covers(self, finding: Finding) -> bool:
        if normal_rule(finding.rule) != self.rule:
            return False
        return not self.files or any(fnmatch.fnmatchcase(finding.file, p) for p in self.files)

    @property
    def mandatory(self) -> bool:
        return self.category == "mandatory" or self.rule in MANDATORY


def normal_rule(rule: str) -> str:
    """``misra-c2012-10.4`` and ``10.4`` alike: the rule as deviations name it."""
    return rule[len(MISRA_PREFIX):] if rule.startswith(MISRA_PREFIX) else rule


def read_deviations(path: Path | str | None) -> list[Deviation]:
    """The deviations of a TOML file (none for None); a malformed entry is a ModelError naming it."""
    if path is None:
        return []
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as err:
        raise ModelError(f"deviations file {p}: {err}") from None
    extra = set(data) - {"deviation"}
    if extra:
        raise ModelError(f"deviations file {p}: unknown key(s) {', '.join(sorted(extra))} (only [[deviation]])")
    entries = data.get("deviation", [])
    if not isinstance(entries, list):
        raise ModelError(f"deviations file {p}: deviation must be an array of tables ([[deviation]])")
    out = []
    for i, entry in enumerate(entries, 1):
        where = f"deviations file {p}, deviation {i}"
        if not isinstance(entry, dict):
            raise ModelError(f"{where}: not a table")
        e: dict[str, object] = entry
        unknown = set(e) - {"rule", "category", "reason", "files"}
        if unknown:
            raise ModelError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        rule, reason = e.get("rule"), e.get("reason")
        if not isinstance(rule, str) or not rule.strip():
            raise ModelError(f'{where}: rule must be a non-empty string (rule = "10.4", quoted)')
        if not isinstance(reason, str) or not reason.strip():
            raise ModelError(f"{where} (rule {rule}): reason must be a non-empty string")
        category = e.get("category", "")
        if category not in ("", *CATEGORIES):
            raise ModelError(f"{where} (rule {rule}): category must be one of {', '.join(CATEGORIES)}")
        files = e.get("files", [])
        if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
            raise ModelError(f"{where} (rule {rule}): files must be a list of file-name patterns")
        out.append(Deviation(normal_rule(rule.strip()), reason.strip(), str(category), tuple(files)))
    return out


@dataclass
class MisraResult:
    """The MISRA findings and cppcheck's own (each justified or not), the deviations no finding used,
    and the deviations refused (a mandatory rule)."""

    findings: list[Finding] = field(default_factory=list)
    cppcheck: list[Finding] = field(default_factory=list)
    unused_deviations: list[str] = field(default_factory=list)
    refused_deviations: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def total(self) -> int:
        return len(self.findings)

    @property
    def justified(self) -> int:
        return sum(f.justified for f in self.findings)

    @property
    def unjustified(self) -> int:
        return self.total - self.justified

    @property
    def by_rule(self) -> dict[str, int]:
        return dict(sorted(Counter(f.rule for f in self.findings).items(), key=lambda kv: _rule_key(kv[0])))

    @property
    def cppcheck_unjustified(self) -> int:
        return sum(not f.justified for f in self.cppcheck)


def _rule_key(rule: str) -> tuple[int, ...] | tuple[float, str]:
    try:
        return tuple(int(x) for x in rule.split("."))
    except ValueError:
        return (float("inf"), rule)


def command(files: list[str], addon: str = "misra") -> list[str]:
    """The cppcheck command line (run in the package's scratch copy)."""
    return ["cppcheck", f"--addon={addon}", "--std=c99", f"--enable={ENABLE}", "--suppress=missingIncludeSystem",
            "--xml", "--xml-version=2", "--quiet", "-I", ".", *files]


def parse_xml(text: str) -> list[tuple[str, str, str, str, int]]:
    """(id, severity, message, file, line) of each error of cppcheck's XML report (on its stderr)."""
    start = text.find("<?xml")
    if start < 0:
        return []
    try:
        root = ET.fromstring(text[start:])
    except ET.ParseError as e:
        raise ModelError(f"cppcheck's XML report cannot be read: {e}") from None
    out = []
    for err in root.iter("error"):
        loc = err.find("location")
        file = loc.get("file", "") if loc is not None else ""
        line = int(loc.get("line", "0")) if loc is not None else 0
        out.append((err.get("id", ""), err.get("severity", ""), err.get("msg", ""), file, line))
    return out


def misra(pkg: Path | str, deviations_path: Path | str | None = None,
          rule_texts: Path | str | None = None) -> MisraResult:
    """cppcheck with the MISRA addon on the flight sources of ``pkg``: every finding, justified by the
    deviations file or not (see the module's docstring)."""
    t0 = time.perf_counter()
    deviations = read_deviations(deviations_path)
    require("cppcheck")
    with scratch_copy(pkg) as work:
        (work / CANARY).write_text(CANARY_SOURCE, encoding="utf-8")
        addon = "misra"
        if rule_texts is not None:
            cfg = work / "rpo_misra_addon.json"
            cfg.write_text(json.dumps({"script": "misra.py", "args": [f"--rule-texts={Path(rule_texts).resolve()}"]}))
            addon = cfg.name
        proc = run(command([*flight_sources(work), CANARY], addon), work)
    errors = parse_xml(proc.stderr)
    bailouts = [ln.strip() for ln in (proc.stdout + proc.stderr).splitlines() if "Bailing out" in ln]
    if not any(i == MISRA_PREFIX + CANARY_RULE and Path(f).name == CANARY for i, _, _, f, _ in errors):
        detail = bailouts[0] if bailouts else "no finding on its canary file"
        raise ModelError(f"cppcheck's MISRA addon did not run (Debian: apt-get install cppcheck python3): {detail}")
    res = MisraResult()
    # a file cppcheck gave up on was not checked: never a pass
    res.cppcheck += [Finding("cppcheck", f"error: {b}", rule="internalError") for b in bailouts if CANARY not in b]
    seen: set[tuple[str, str, int]] = set()
    for ident, severity, msg, file, line in errors:
        name = Path(file).name if file else ""
        if name == CANARY or ident in IGNORED_IDS or (ident, name, line) in seen:
            continue
        seen.add((ident, name, line))
        if ident.startswith(MISRA_PREFIX):
            rule = normal_rule(ident)
            text = msg if "use --rule-texts" not in msg else "violation"
            res.findings.append(Finding("misra", f"MISRA C:2012 rule {rule}: {text}", name, line, rule))
        else:
            res.cppcheck.append(Finding("cppcheck", f"{severity}: {msg}", name, line, ident))
    res.findings.sort(key=lambda f: (f.file, f.line, _rule_key(f.rule)))
    res.cppcheck.sort(key=lambda f: (f.file, f.line, f.rule))
    used: set[Deviation] = set()
    for f in [*res.findings, *res.cppcheck]:
        for d in deviations:
            if d.covers(f):
                used.add(d)
                if d.mandatory:
                    f.message += " (mandatory rule: no deviation permitted)"
                else:
                    f.justified, f.reason = True, d.reason
                break
    res.unused_deviations = sorted({d.rule for d in deviations if d not in used} - {d.rule for d in used},
                                   key=_rule_key)
    res.refused_deviations = sorted({d.rule for d in deviations if d.mandatory}, key=_rule_key)
    res.seconds = time.perf_counter() - t0
    return res
