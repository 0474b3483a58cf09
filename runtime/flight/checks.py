"""The checks that make an exported controller package (``rpo export``) flight code, and their report.

    compile_warnings(pkg, compilers, precision)   every *.c, test program included: 0 warnings, no VLA
    stack_usage(pkg, entry, target)                worst-case stack of one call, summed on the call graph
    misra(pkg, deviations_path)                    cppcheck + MISRA addon against a deviations file
    forbidden_symbols(pkg, target, precision)      no heap, no I/O, no exit, no mutable data
    recursion(pkg)                                 no cycle in the source-level call graph
    check_package(pkg, precision, deviations)      all of them: PackageCheck (.json(), .format_report())

A check never raises on a finding (each result holds numbers and its findings); a missing tool raises
ModelError naming the Debian package.  ``pkg`` is the package folder; the flight sources are its ``*.c``
but the host test program ``test_*.c`` (compiled for warnings only).  The tools, targets and flags are
``rpo.runtime.flight.tools``, the call graph ``.callgraph``, cppcheck ``.cppcheck``, the symbol tables
``.symbols``.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, field
from pathlib import Path

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.callgraph import StackBound, cycles, read_callgraph, stack_bound
from rpo.runtime.flight.cppcheck import MisraResult, misra
from rpo.runtime.flight.symbols import SymbolsResult, classify
from rpo.runtime.flight.tools import (
    Finding,
    Target,
    check_precision,
    compile_flight,
    flight_sources,
    host_test_sources,
    require,
    resolve_target,
    run,
    scratch_copy,
    targets,
    warning_flags,
)

__all__ = ["MisraResult", "PackageCheck", "RecursionResult", "StackResult", "SymbolsResult", "WarningsResult",
           "check_package", "compile_warnings", "forbidden_symbols", "misra", "package_prefix", "recursion",
           "stack_usage"]

_DIAG = re.compile(r"^(?P<file>[^:\s][^:]*):(?P<line>\d+):(?:\d+:)? (?P<kind>warning|error): (?P<msg>.*?)"
                   r"(?: \[(?P<opt>-W[^\]]+)\])?$")


@dataclass
class WarningsResult:
    """The diagnostics of each compiler (0 expected): ``counts`` by compiler, ``vla`` the -Wvla ones."""

    flags: tuple[str, ...]
    counts: dict[str, int] = field(default_factory=dict)
    findings: list[Finding] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def total(self) -> int:
        return sum(self.counts.values())

    @property
    def vla(self) -> int:
        return sum(f.rule == "-Wvla" for f in self.findings)


def _option(opt: str | None) -> str:
    """The warning option of a diagnostic tag: -Werror=vla (gcc), -Werror,-Wvla (clang) -> -Wvla."""
    if not opt:
        return "error"
    last = opt.split(",")[-1]
    return "-W" + last[len("-Werror="):] if last.startswith("-Werror=") else last


def _diagnostics(stderr: str, where: str) -> list[Finding]:
    out = []
    for line in stderr.splitlines():
        m = _DIAG.match(line)
        if m:
            out.append(Finding("warnings", m["msg"], Path(m["file"]).name, int(m["line"]), _option(m["opt"]), where))
    return out


def compile_warnings(pkg: Path | str, compilers: tuple[str, ...] = ("gcc", "clang"),
                     precision: str = "double") -> WarningsResult:
    """Compile every flight source and the host test program with each compiler under
    ``tools.warning_flags(precision)`` (-Werror: each diagnostic is one finding; -Wvla counts as ``vla``)."""
    t0 = time.perf_counter()
    flags = warning_flags(precision)
    res = WarningsResult(flags)
    paths = [require(cc) for cc in compilers]
    with scratch_copy(pkg) as work:
        for cc, path in zip(compilers, paths, strict=True):
            found: list[Finding] = []
            for name in [*flight_sources(work), *host_test_sources(work)]:
                proc = run([path, *flags, "-I", ".", "-c", name, "-o", str(work / f"{cc}-{name}.o")], work)
                diags = _diagnostics(proc.stderr, cc)
                if proc.returncode != 0 and not diags:
                    diags = [Finding("warnings", (proc.stderr.strip().splitlines() or ["failed"])[-1], name,
                                     rule="error", where=cc)]
                found += [d for d in diags if all((d.file, d.line, d.message) != (f.file, f.line, f.message)
                                                  for f in found)]
            res.counts[cc] = len(found)
            res.findings += found
    res.seconds = time.perf_counter() - t0
    return res


@dataclass
class StackResult:
    """The worst-case stack [bytes] of one call of ``entry`` on ``target`` (None: unknown, see findings),
    the worst path, and the callees outside the package whose frames are not counted."""

    target: str
    entry: str
    bytes: int | None
    path: list[str]
    not_counted: list[str]
    findings: list[Finding]
    seconds: float = 0.0


def _stack(work: Path, tgt: Target, entry: str, out: Path) -> tuple[StackResult, list[Path]]:
    """Compile for ``tgt`` (a source that fails is a finding and leaves the bound unknown) and bound the stack."""
    objs = compile_flight(work, tgt, out)
    bound: StackBound = stack_bound(read_callgraph(sorted(out.glob("*.ci"))), entry, tgt.name)
    res = StackResult(tgt.name, entry, None if objs.findings else bound.bytes, bound.path, bound.not_counted,
                      [*objs.findings, *bound.findings])
    return res, objs.objects


def stack_usage(pkg: Path | str, entry: str, target: str | Target = "host-gcc") -> StackResult:
    """Worst-case stack of one call of ``entry`` (e.g. ``rpo_<name>_step``) built for the target
    (``tools.TARGETS``: host-gcc, cortex-m7, cortex-m4): the maximum over the call paths of the sum of
    the frames gcc reports (-fstack-usage, -fcallgraph-info=su).  A dynamic frame, an indirect call or
    recursion makes it unknown (None, and a finding)."""
    t0 = time.perf_counter()
    tgt = resolve_target(target)
    with scratch_copy(pkg) as work:
        res, _ = _stack(work, tgt, entry, work / f"obj-{tgt.name}")
    res.seconds = time.perf_counter() - t0
    return res


def forbidden_symbols(pkg: Path | str, target: str | Target = "host-gcc", precision: str = "double",
                      extra_allowed: frozenset[str] = frozenset()) -> SymbolsResult:
    """The symbol tables of the flight objects built for the target: undefined symbols off the allow-list
    (allocation, I/O, exit and any other), writable data (see ``rpo.runtime.flight.symbols``)."""
    t0 = time.perf_counter()
    check_precision(precision)
    tgt = resolve_target(target)
    with scratch_copy(pkg) as work:
        objs = compile_flight(work, tgt, work / f"obj-{tgt.name}")
        res = classify(tgt, objs.objects, precision, extra_allowed)
    res.findings = [*objs.findings, *res.findings]
    res.seconds = time.perf_counter() - t0
    return res


@dataclass
class RecursionResult:
    """The recursion cycles of the source-level call graph (host gcc at -O0, where no call is inlined
    or turned into a loop): each a sorted list of functions."""

    cycles: list[list[str]]
    findings: list[Finding]
    seconds: float = 0.0


RECURSION_TARGET = Target("host-gcc-O0", "gcc", "nm", ("-std=c99", "-O0"))


def recursion(pkg: Path | str) -> RecursionResult:
    """Direct or mutual recursion anywhere in the flight sources (MISRA C:2012 rule 17.2)."""
    t0 = time.perf_counter()
    with scratch_copy(pkg) as work:
        out = work / "obj-recursion"
        objs = compile_flight(work, RECURSION_TARGET, out)
        graph = read_callgraph(sorted(out.glob("*.ci")))
    found = cycles(graph)
    findings = [*objs.findings, *(Finding("recursion", "recursion: " + ", ".join(c), graph.frames[c[0]].file,
                                          graph.frames[c[0]].line, "17.2") for c in found)]
    return RecursionResult(found, findings, time.perf_counter() - t0)


def package_prefix(pkg: Path | str) -> str:
    """``rpo_<name>`` of a package: from its test program ``test_rpo_<name>.c``, else its one header
    ``rpo_<name>.h`` (the io and math headers aside)."""
    folder = Path(pkg)
    tests = [n[len("test_"):-len(".c")] for n in host_test_sources(folder)]
    if len(tests) == 1:
        return tests[0]
    heads = [p.stem for p in folder.glob("rpo_*.h") if not p.stem.endswith(("_io", "_math"))]
    if len(heads) == 1:
        return heads[0]
    raise ModelError(f"cannot tell the package's prefix in {folder}: pass prefix= (rpo_<name>)")


@dataclass
class PackageCheck:
    """Every check of one package (``check_package``)."""

    prefix: str
    precision: str
    warnings: WarningsResult
    stacks: dict[str, StackResult]
    symbols: dict[str, SymbolsResult]
    misra: MisraResult
    recursion: RecursionResult

    def findings(self) -> list[Finding]:
        """Everything found, justified MISRA and cppcheck findings included (their ``justified`` set)."""
        out = [*self.warnings.findings]
        for s in self.stacks.values():
            out += s.findings
        for y in self.symbols.values():
            out += y.findings
        return [*out, *self.misra.findings, *self.misra.cppcheck, *self.recursion.findings]

    def failures(self) -> list[Finding]:
        return [f for f in self.findings() if not f.justified]

    @property
    def heap_symbols(self) -> int:
        """Allocation symbols: distinct (source, symbol) over the targets."""
        return len({(f.file, f.message) for y in self.symbols.values() for f in y.findings if f.rule == "allocation"})

    def _symbol_count(self, rule: str) -> int:
        return len({(f.file, f.message.split(":")[0]) for y in self.symbols.values() for f in y.findings
                    if f.rule == rule})

    @property
    def passed(self) -> bool:
        return not self.failures() and all(s.bytes is not None for s in self.stacks.values())

    def json(self) -> dict[str, object]:
        return {
            "prefix": self.prefix,
            "precision": self.precision,
            "passed": self.passed,
            "export_warnings": self.warnings.total,
            "warnings_by_compiler": dict(self.warnings.counts),
            "warning_flags": list(self.warnings.flags),
            "vla": self.warnings.vla,
            "heap_symbols": self.heap_symbols,
            "io_symbols": self._symbol_count("io"),
            "termination_symbols": self._symbol_count("termination"),
            "mutable_data_symbols": self._symbol_count("mutable-data"),
            "other_forbidden_symbols": self._symbol_count("not-allowed") + self._symbol_count("double"),
            "library_symbols": {t: y.library for t, y in self.symbols.items()},
            "stack_bytes_per_step": {t: s.bytes for t, s in self.stacks.items()},
            "stack_worst_path": {t: s.path for t, s in self.stacks.items()},
            "stack_not_counted": {t: s.not_counted for t, s in self.stacks.items()},
            "recursion_cycles": len(self.recursion.cycles),
            "misra_findings_total": self.misra.total,
            "misra_findings_justified": self.misra.justified,
            "misra_findings_unjustified": self.misra.unjustified,
            "misra_by_rule": self.misra.by_rule,
            "cppcheck_findings_total": len(self.misra.cppcheck),
            "cppcheck_findings_unjustified": self.misra.cppcheck_unjustified,
            "unused_deviations": self.misra.unused_deviations,
            "refused_deviations": self.misra.refused_deviations,
            "seconds": self.seconds(),
            "findings": [f.json() for f in self.failures()],
            "justified_findings": [f.json() for f in self.findings() if f.justified],
        }

    def seconds(self) -> dict[str, float]:
        return {"warnings": round(self.warnings.seconds, 2),
                "stack_and_symbols": round(sum(s.seconds for s in self.stacks.values()), 2),
                "misra": round(self.misra.seconds, 2), "recursion": round(self.recursion.seconds, 2)}

    def format_report(self) -> str:
        j = self.json()
        by_compiler = ", ".join(f"{c} {n}" for c, n in self.warnings.counts.items())
        lines = [f"flight checks of {self.prefix} ({self.precision} precision): "
                 + ("PASSED" if self.passed else "FAILED"),
                 f"  warnings      {self.warnings.total} ({by_compiler}; VLAs {self.warnings.vla})",
                 f"  symbols       heap {j['heap_symbols']}, I/O {j['io_symbols']}, exit {j['termination_symbols']}, "
                 f"mutable data {j['mutable_data_symbols']}, other {j['other_forbidden_symbols']}"]
        for t, s in self.stacks.items():
            size = "unknown" if s.bytes is None else f"{s.bytes} bytes"
            lines.append(f"  stack         {t}: {size} per call of {s.entry} (path {' -> '.join(s.path)}; "
                         f"not counted: {', '.join(s.not_counted) or 'none'})")
        lines += [f"  recursion     {len(self.recursion.cycles)} cycle(s)",
                  f"  MISRA C:2012  {self.misra.total} findings, {self.misra.justified} justified, "
                  f"{self.misra.unjustified} unjustified; by rule: "
                  + (", ".join(f"{r} x{n}" for r, n in self.misra.by_rule.items()) or "none"),
                  f"  cppcheck      {len(self.misra.cppcheck)} findings, {self.misra.cppcheck_unjustified} unjustified"]
        if self.misra.unused_deviations:
            lines.append(f"  deviations no finding uses: {', '.join(self.misra.unused_deviations)}")
        failures = self.failures()
        if failures:
            lines.append(f"  {len(failures)} finding(s) to fix:")
            lines += [f"    {f.text()}" for f in failures]
        return "\n".join(lines)


def check_package(pkg: Path | str, precision: str = "double", deviations: Path | str | None = None, *,
                  prefix: str | None = None, compilers: tuple[str, ...] = ("gcc", "clang"),
                  rule_texts: Path | str | None = None) -> PackageCheck:
    """Every check on the package folder ``pkg``; the stack is that of one ``<prefix>_step`` call per target
    (``tools.targets(precision)``), each target compiled once for both its stack and its symbols."""
    check_precision(precision)
    name = prefix or package_prefix(pkg)
    warnings = compile_warnings(pkg, compilers, precision)
    stacks: dict[str, StackResult] = {}
    symbols: dict[str, SymbolsResult] = {}
    with scratch_copy(pkg) as work:
        for tgt in targets(precision):
            t0 = time.perf_counter()
            stacks[tgt.name], objects = _stack(work, tgt, f"{name}_step", work / f"obj-{tgt.name}")
            symbols[tgt.name] = classify(tgt, objects, precision)
            stacks[tgt.name].seconds = time.perf_counter() - t0
    return PackageCheck(name, precision, warnings, stacks, symbols, misra(pkg, deviations, rule_texts), recursion(pkg))
