"""C99 statements from a generated function's instruction list: the body of the exported controller.

The committed ``generated/<fn>.casadi.gz`` is the very CasADi function whose C the simulation runs
(``generated/<fn>.c``, written by CasADi's code generator from it).  Here its straight-line algorithm
(``Function.instruction_*``: one operation per instruction, on a work vector CasADi already sized and
reused) is printed again as C99 with named inputs and outputs instead of CasADi's ``arg``/``res``
pointer arrays, in double or single precision.

Each operation is printed so that it computes exactly what CasADi's C computes (same operands, same
order, IEEE semantics, no contraction): ``x*x`` for ``casadi_sq``, ``2.0*x`` for twice, ``1.0/x``
for the inverse, CasADi's ``sign``, a comparison giving 1.0 or 0.0, an ``if_else_zero`` giving
``+0.0``.  The transcendental functions are rpo's own (``rpo_math.h``, the functions the simulation
is compiled against), so the double-precision export gives the simulation's bits on any IEEE-754
machine; tests/test_flight_export.py checks it at random points and along closed-loop runs.  In
single precision the same algorithm is printed over ``float`` with the C99 ``<math.h>`` float
functions: not bit-identical, measured instead (benchmarks/bench_export.py).

An operation outside :data:`BINARY`, :data:`UNARY` and the structural ones is refused by name
(:class:`~rpo.runtime.errors.ModelError`), never approximated.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError

#: the two precisions an export is printed in: C type, literal suffix, function-name suffix
PRECISIONS = {"double": ("double", "", ""), "single": ("float", "F", "f")}

#: binary operations: CasADi op name -> C format over operands {0}, {1} (as CasADi's C prints them)
BINARY = {
    "OP_ADD": "{0} + {1}",
    "OP_SUB": "{0} - {1}",
    "OP_MUL": "{0} * {1}",
    "OP_DIV": "{0} / {1}",
    "OP_LT": "({0} < {1}) ? {one} : {zero}",
    "OP_LE": "({0} <= {1}) ? {one} : {zero}",
    "OP_EQ": "({0} == {1}) ? {one} : {zero}",
    "OP_NE": "({0} != {1}) ? {one} : {zero}",
    # (c ? x : 0): C's truth test of a double is c != 0 (NaN counts as true), the 0 is +0.0
    "OP_IF_ELSE_ZERO": "({0} != {zero}) ? {1} : {zero}",
    "OP_FMIN": "{fmin}({0}, {1})",
    "OP_FMAX": "{fmax}({0}, {1})",
    "OP_ATAN2": "{atan2}({0}, {1})",
    "OP_AND": "(({0} != {zero}) && ({1} != {zero})) ? {one} : {zero}",
    "OP_OR": "(({0} != {zero}) || ({1} != {zero})) ? {one} : {zero}",
}

#: unary operations: CasADi op name -> C format over operand {0}
UNARY = {
    "OP_NEG": "-{0}",
    "OP_SQ": "{0} * {0}",
    "OP_TWICE": "{two} * {0}",
    "OP_INV": "{one} / {0}",
    "OP_NOT": "({0} == {zero}) ? {one} : {zero}",
    # casadi_sign: x<0 ? -1 : x>0 ? 1 : x  (sign(+-0) = +-0, sign(NaN) = NaN)
    "OP_SIGN": "({0} < {zero}) ? -{one} : (({0} > {zero}) ? {one} : {0})",
    "OP_FABS": "{fabs}({0})",
    "OP_SQRT": "{sqrt}({0})",
    "OP_SIN": "{sin}({0})",
    "OP_COS": "{cos}({0})",
    "OP_TAN": "{tan}({0})",
    "OP_ASIN": "{asin}({0})",
    "OP_ACOS": "{acos}({0})",
    "OP_ATAN": "{atan}({0})",
    "OP_EXP": "{exp}({0})",
    "OP_LOG": "{log}({0})",
    "OP_SINH": "{sinh}({0})",
    "OP_COSH": "{cosh}({0})",
    "OP_TANH": "{tanh}({0})",
    "OP_FLOOR": "{floor}({0})",
    "OP_CEIL": "{ceil}({0})",
}

#: the math functions each precision calls: double -> rpo_math.h (the simulation's), single -> C99 <math.h>
_DOUBLE_FUNCS = {f: f"rpo_{f}" for f in ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "exp", "log", "sinh",
                                          "cosh", "tanh", "fmin", "fmax", "floor", "ceil")}
_DOUBLE_FUNCS |= {"fabs": "fabs", "sqrt": "sqrt"}  # exact in libm: the simulation's objects call libm's too
_SINGLE_FUNCS = {f: f"{f}f" for f in (*_DOUBLE_FUNCS, "fabs", "sqrt")}


def _op_names() -> dict[int, str]:
    import casadi as ca

    return {getattr(ca, n): n for n in dir(ca) if n.startswith("OP_")}


def literal(value: float, precision: str) -> str:
    """A C literal equal to ``value`` (double: the same double; single: ``value`` rounded to float)."""
    if not math.isfinite(value):
        raise ModelError(f"the generated function holds the constant {value!r}: a flight export needs finite "
                         "constants")
    if precision == "single":
        with np.errstate(over="ignore"):
            single = float(np.float32(value))
        if not math.isfinite(single) or (single == 0.0 and value != 0.0):
            raise ModelError(f"the generated function holds the constant {value!r}, outside single precision's "
                             "range: export it in double precision")
        text = repr(single)
    else:
        text = repr(float(value))
    if "e" not in text and "." not in text:
        text += ".0"
    return text + PRECISIONS[precision][1]


@dataclass(frozen=True)
class Body:
    """The printed algorithm: local declarations and statements, and what it reads and writes."""

    declarations: list[str]
    statements: list[str]
    inputs_read: dict[int, set[int]]      # input index -> element indices read
    math_calls: set[str]                  # the C functions called
    operations: int                       # instructions printed (inputs and outputs included)


def load_function(path: Any) -> Any:
    """The CasADi function serialised in ``path`` (a ``.casadi.gz`` of generated/)."""
    import gzip

    import casadi as ca

    with gzip.open(path, "rt") as fh:
        return ca.Function.deserialize(fh.read())


def inputs_read(f: Any) -> dict[int, set[int]]:
    """Input index -> the element indices the SX function ``f`` reads (its OP_INPUT instructions)."""
    import casadi as ca

    out: dict[int, set[int]] = {}
    for k in range(f.n_instructions()):
        if f.instruction_id(k) == ca.OP_INPUT:
            i, j = f.instruction_input(k)
            out.setdefault(int(i), set()).add(int(j))
    return out


def body(f: Any, precision: str, read: Callable[[int, int], str], write: Callable[[int, int], str | None],
         local: str = "a") -> Body:
    """The statements computing the SX function ``f``: input element j of input i is the C expression
    ``read(i, j)``; output element j of output i is assigned to ``write(i, j)`` (None: not written).
    Locals are ``<local>000``... of the precision's type, one per slot of CasADi's work vector."""
    if not f.is_a("SXFunction"):
        raise ModelError(f"{f.name()} is not a straight-line (SX) function: it cannot be exported")
    if precision not in PRECISIONS:
        raise ModelError(f"precision must be one of {', '.join(PRECISIONS)}, got {precision!r}")
    for i in range(f.n_in()):
        if not f.sparsity_in(i).is_dense():
            raise ModelError(f"{f.name()}: input {f.name_in(i)} is sparse; the export maps dense ports only")
    for i in range(f.n_out()):
        if not f.sparsity_out(i).is_dense():
            raise ModelError(f"{f.name()}: output {f.name_out(i)} is sparse; the export maps dense ports only")
    ctype, suffix, _ = PRECISIONS[precision]
    funcs = _DOUBLE_FUNCS if precision == "double" else _SINGLE_FUNCS
    names = _op_names()
    n_w = int(f.sz_w())
    width = max(3, len(str(max(n_w - 1, 0))))

    def a(i: int) -> str:
        return f"{local}{i:0{width}d}"

    words = {"zero": f"0.0{suffix}", "one": f"1.0{suffix}", "two": f"2.0{suffix}", **funcs}
    called: set[str] = set()
    stmts: list[str] = []
    used: set[int] = set()
    for k in range(f.n_instructions()):
        op = names.get(f.instruction_id(k), str(f.instruction_id(k)))
        ins, outs = list(f.instruction_input(k)), list(f.instruction_output(k))
        if op == "OP_INPUT":
            stmts.append(f"{a(outs[0])} = {read(int(ins[0]), int(ins[1]))};")
            used.add(outs[0])
        elif op == "OP_OUTPUT":
            target = write(int(outs[0]), int(outs[1]))
            if target is not None:
                stmts.append(f"{target} = {a(ins[0])};")
        elif op == "OP_CONST":
            stmts.append(f"{a(outs[0])} = {literal(float(f.instruction_constant(k)), precision)};")
            used.add(outs[0])
        elif op == "OP_ASSIGN":
            stmts.append(f"{a(outs[0])} = {a(ins[0])};")
            used.add(outs[0])
        elif op in BINARY:
            text = BINARY[op].format(a(ins[0]), a(ins[1]), **words)
            called.update(fn for fn in funcs.values() if text.startswith(fn + "("))
            stmts.append(f"{a(outs[0])} = {text};")
            used.add(outs[0])
        elif op in UNARY:
            text = UNARY[op].format(a(ins[0]), **words)
            called.update(fn for fn in funcs.values() if text.startswith(fn + "("))
            stmts.append(f"{a(outs[0])} = {text};")
            used.add(outs[0])
        else:
            raise ModelError(f"{f.name()}: operation {op} (instruction {k}) has no flight-code printing; "
                             "supported: " + ", ".join(sorted({*BINARY, *UNARY})))
    # one declaration per line: MISRA C 2012 rule 12.3 (cppcheck reads a declaration list as a comma)
    decls = [f"{ctype} {a(j)};" for j in sorted(used)]
    return Body(decls, stmts, inputs_read(f), called, int(f.n_instructions()))
