"""What a flight object may reference and hold: the symbol tables (``nm -P``) of a package's objects.

An undefined symbol must be defined by another object of the package or be on the allow-list: the
<math.h> functions (C99, with their float and long double forms, and GNU's sincos, which gcc makes of a
sin and a cos of one argument), memcpy/memset/memmove (gcc emits them for struct copies and zeroing)
and the compiler's runtime helpers (``__aeabi_*`` on ARM).  Allocation, I/O and process-ending calls
are findings by kind; any other undefined symbol is a finding too.  A defined writable data symbol
(nm types D d B b C G g S s: a mutable global or a static, in a function or not) is a finding: flight
code keeps its state in the caller's structs; const tables (R r) are fine.  In single precision a
double <math.h> function, or a double software-float helper on an FPU without double (Cortex-M4), is
a finding as well: double arithmetic has slipped into the package.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from rpo.runtime.flight.tools import Finding, Target, require, run

_MATH = ("acos asin atan atan2 cos sin tan acosh asinh atanh cosh sinh tanh exp exp2 expm1 frexp ilogb ldexp log "
         "log10 log1p log2 logb modf scalbn scalbln cbrt fabs hypot pow sqrt erf erfc lgamma tgamma ceil floor "
         "nearbyint rint lrint llrint round lround llround trunc fmod remainder remquo copysign nan nextafter "
         "nexttoward fdim fmax fmin fma sincos").split()

#: the double <math.h> functions
MATH_DOUBLE = frozenset(_MATH)
MATH = frozenset(_MATH + [f + "f" for f in _MATH] + [f + "l" for f in _MATH])
MEMORY = frozenset({"memcpy", "memset", "memmove"})

ALLOCATION = frozenset({"malloc", "calloc", "realloc", "free", "aligned_alloc", "alloca", "__builtin_alloca",
                        "posix_memalign", "memalign", "valloc", "pvalloc", "reallocarray", "strdup", "strndup",
                        "_malloc_r", "_calloc_r", "_realloc_r", "_free_r", "sbrk", "_sbrk", "brk", "mmap"})
IO = frozenset({
    "printf", "fprintf", "sprintf", "snprintf", "vprintf", "vfprintf", "vsprintf", "vsnprintf", "dprintf",
    "puts", "fputs", "putchar", "fputc", "putc", "_IO_putc", "getchar", "fgetc", "getc", "gets", "fgets",
    "scanf", "fscanf", "sscanf", "vscanf", "vfscanf", "vsscanf", "fopen", "freopen", "fclose", "fread", "fwrite",
    "fflush", "fseek", "ftell", "rewind", "perror", "open", "close", "read", "write", "_write", "_read",
    "_open", "_close", "iprintf", "fiprintf", "siprintf", "stdin", "stdout", "stderr", "_impure_ptr",
    "__printf_chk", "__fprintf_chk", "__sprintf_chk", "__snprintf_chk", "__vfprintf_chk", "__vprintf_chk",
    "__isoc99_scanf", "__isoc99_fscanf", "__isoc99_sscanf", "__isoc99_vfscanf", "__isoc99_vsscanf"})
TERMINATION = frozenset({"exit", "_exit", "_Exit", "abort", "quick_exit", "atexit", "at_quick_exit",
                         "__assert_fail", "__assert_func", "__assert", "raise", "signal", "longjmp", "setjmp",
                         "_longjmp", "_setjmp", "__longjmp_chk"})

#: nm's types of writable data: initialised (D d), zero-initialised (B b), common (C), small data (G g S s)
WRITABLE = frozenset("DdBbCGgSs")
_HELPER = re.compile(r"^(__aeabi_\w+|__powi[sdx]f2)$")
_SOFT_DOUBLE = re.compile(r"^__aeabi_(d(?!iv0)\w+|\w+2d)$")
#: the targets whose FPU has no double arithmetic
SINGLE_FPU = frozenset({"cortex-m4"})


@dataclass
class SymbolsResult:
    """The symbols of one target's flight objects: the library ones used, and what is forbidden."""

    target: str
    library: list[str] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    seconds: float = 0.0

    def count(self, rule: str) -> int:
        return sum(f.rule == rule for f in self.findings)

    @property
    def heap_symbols(self) -> int:
        return self.count("allocation")


def read_symbols(nm: str, obj: Path) -> list[tuple[str, str]]:
    """(name, nm type) of every symbol of ``obj`` (POSIX format, mapping and local labels left out)."""
    proc = run([nm, "-P", str(obj)], obj.parent)
    out = []
    for line in proc.stdout.splitlines():
        parts = line.split()
        if len(parts) >= 2 and not parts[0].startswith(("$", ".L")) and not parts[0].endswith(":"):
            out.append((parts[0], parts[1]))
    return out


def classify(tgt: Target, objects: list[Path], precision: str = "double",
             extra_allowed: frozenset[str] = frozenset()) -> SymbolsResult:
    """The findings of the symbol tables of ``objects`` (the flight objects of one target)."""
    nm = require(tgt.nm)
    res = SymbolsResult(tgt.name)
    tables = {obj.with_suffix(".c").name: read_symbols(nm, obj) for obj in objects}
    defined = {name for syms in tables.values() for name, kind in syms if kind not in ("U", "v", "w")}
    library: set[str] = set()
    reported: set[tuple[str, str]] = set()

    def find(rule: str, name: str, src: str, message: str) -> None:
        if (name, src) not in reported:
            reported.add((name, src))
            res.findings.append(Finding("symbols", message, src, rule=rule, where=tgt.name))

    for src, syms in tables.items():
        for name, kind in syms:
            if kind in WRITABLE:
                find("mutable-data", name, src, f"{name}: writable data (nm type {kind}): a mutable global or static")
                continue
            if kind not in ("U", "v", "w") or name in defined:
                continue
            if name in ALLOCATION:
                find("allocation", name, src, f"{name}: heap allocation")
            elif name in IO:
                find("io", name, src, f"{name}: I/O")
            elif name in TERMINATION:
                find("termination", name, src, f"{name}: ends or jumps out of the program")
            elif name in MATH or name in MEMORY or name in extra_allowed or _HELPER.match(name):
                library.add(name)
                if precision == "single" and name in MATH_DOUBLE:
                    find("double", name, src, f"{name}: double-precision math in a single-precision package")
                elif precision == "single" and tgt.name in SINGLE_FPU and _SOFT_DOUBLE.match(name):
                    find("double", name, src, f"{name}: software double arithmetic (the {tgt.name} FPU has none)")
            else:
                find("not-allowed", name, src, f"{name}: undefined symbol outside the allow-list")
    res.library = sorted(library)
    return res
