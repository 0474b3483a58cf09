"""The C text of an exported controller: header (structs, entry points), source, flat-array converters.

Embedded Coder's shape, without a tool to buy: ``<prefix>_initialize(state, params)``,
``<prefix>_step(state, params, inputs, outputs)``, ``<prefix>_terminate(state)``; the caller owns every
struct (no heap, no mutable globals, no recursion, no variable-length array: checked by
:mod:`rpo.runtime.flight.checks`).  Designs whose states start from a measurement (``xc0_<name>``)
have ``<prefix>_start(state, params, inputs)`` besides.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from rpo.runtime.flight.emit import PRECISIONS, Body, body
from rpo.runtime.flight.interface import Group, Interface, Member

#: every multiply and add rounded on its own, whatever the build's flags: GCC in its GNU modes fuses
#: a*b + c across statements where the target has an FMA (Cortex-M7, x86 with -march=native)
CONTRACT_OFF = """/* No fused multiply-add, whatever the flags: the simulation rounds every operation on its own. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#else
#pragma STDC FP_CONTRACT OFF
#endif
"""

#: double precision: each operation rounded once, to double (an x87 FPU's extended precision would not)
EVAL_DOUBLE = """#include <float.h>
#if defined(FLT_EVAL_METHOD) && (FLT_EVAL_METHOD == 1 || FLT_EVAL_METHOD == 2)
#error "rpo: doubles must be evaluated in double precision (FLT_EVAL_METHOD 0): e.g. -msse2 -mfpmath=sse on x86"
#endif
"""


@dataclass(frozen=True)
class Provenance:
    """Where an export comes from, written into every file's banner."""

    rpo_version: str
    manifest_hash: str
    function_sha256: dict[str, str]       # generated file -> sha256
    quaternion_convention: str
    scenario: str
    rate_hz: float


def _access(group: Group, m: Member, i: int) -> str:
    return f"{group.path}{m.name}" + (f"[{i}]" if m.size > 1 else "")


def _element_map(iface: Interface, struct: str, source: str) -> dict[int, str]:
    """Element j of the simulation vector ``source`` -> its C access in ``struct`` (without the pointer)."""
    out = {}
    for g, m in iface.members(struct):
        if m.source == source:
            for i in range(m.size):
                out[m.offset + i] = _access(g, m, i)
    return out


def banner(iface: Interface, prov: Provenance, what: str, precision: str) -> str:
    files = "".join(f" *   generated/{f} sha256 {h}\n" for f, h in sorted(prov.function_sha256.items()))
    return (f"/* {what}\n"
            f" * Flight-code export of rpo controller '{iface.controller}' ({precision} precision), written by\n"
            f" * `rpo export {iface.controller}` (rpo {prov.rpo_version}).  GENERATED: edit symbolic/ and export\n"
            " * again instead.  The algorithm is the simulation's own, from\n"
            f"{files}"
            f" * (manifest {prov.manifest_hash}).\n"
            " */\n")


def _struct(name: str, groups: tuple[Group, ...], ctype: str, doc: str, extra: list[str] | None = None,
            nested: bool = True) -> str:
    lines = [f"/* {doc} */", "typedef struct {"]
    body_lines: list[str] = []
    for g in groups:
        inner = [f"    {ctype} {m.name}{f'[{m.size}]' if m.size > 1 else ''};"
                 f"  /* [{m.unit}] {m.doc}{_labels(m)} */" for m in g.members]
        if nested and g.path:
            body_lines.append("    struct {")
            body_lines += ["    " + s for s in inner] if inner else ["        unsigned char none;  /* (empty) */"]
            body_lines.append(f"    }} {g.path.rstrip('.')};")
        else:
            body_lines += inner
    body_lines += extra or []
    if not body_lines:
        body_lines = ["    unsigned char none;  /* the design has none */"]
    return "\n".join(lines + body_lines + [f"}} {name};", ""])


def _labels(m: Member) -> str:
    return f" ({', '.join(m.labels)})" if m.size > 1 and m.labels else ""


def header(iface: Interface, prov: Provenance, precision: str, stack: dict[str, int] | None) -> str:
    p = iface.prefix
    P = p.upper()
    ctype = PRECISIONS[precision][0]
    t = f"{p}_real_t"
    stack_lines = "".join(f" *   {n} bytes on {target}\n" for target, n in sorted((stack or {}).items()))
    stack_max = max((stack or {"none": 0}).values())
    start = ""
    if iface.has_start:
        start = (f"/* Start the design's states from a measurement (call once, after {p}_initialize and before the\n"
                 " * first step; the simulation starts them from the noise-free measurement at t0). */\n"
                 f"void {p}_start({p}_state_t *state, const {p}_params_t *params, const {p}_inputs_t *in);\n\n")
    return (banner(iface, prov, f"{p}.h: the interface of the exported controller", precision)
            + f"#ifndef {P}_H\n#define {P}_H\n\n#include <stdint.h>\n\n"
            f"/* Precision of every value: {precision}. */\ntypedef {ctype} {t};\n\n"
            f"/* The rate the step is meant to be called at [Hz]: the sample period params->model.dt of the law's\n"
            " * own integration, when it reads one, must be its inverse. */\n"
            f"#define {P}_RATE_HZ {prov.rate_hz!r}\n\n"
            "/* Worst-case stack of one call of the step [bytes], summed along its call graph from the\n"
            " * compilers' -fstack-usage (rpo.runtime.flight.checks); the macro is the largest:\n"
            f"{stack_lines or ' *   (not measured)' + chr(10)}"
            " */\n"
            f"#define {P}_STACK_BYTES {stack_max}\n\n"
            f"/* Units: SI.  Quaternions: {prov.quaternion_convention}. */\n\n"
            + _struct(f"{p}_inputs_t", iface.inputs, t, "Inputs of one step: the measurement at the sample time.")
            + "\n" + _struct(f"{p}_params_t", iface.params, t,
                             "Parameters: the design's gains and the plant values the law reads (constant).")
            + "\n" + _struct(f"{p}_state_t", iface.state, t, "The controller's own states (owned by the caller).",
                             extra=["    uint32_t steps;  /* [-] steps taken since initialize (wraps) */"])
            + "\n" + _struct(f"{p}_outputs_t", iface.outputs, t,
                             "Outputs of one step: the command, held until the next step, and diagnostics.")
            + f"\n/* Set the states to their initial values (zeros) and the step counter to 0. */\n"
            f"void {p}_initialize({p}_state_t *state, const {p}_params_t *params);\n\n"
            + start
            + f"/* One step: the command from the inputs at t_k, and the states advanced to t_k + dt (RK4, the\n"
            " * inputs held over the step).  No allocation, no I/O, no global state: reentrant. */\n"
            f"void {p}_step({p}_state_t *state, const {p}_params_t *params, const {p}_inputs_t *in,\n"
            f"{' ' * (len(p) + 10)}{p}_outputs_t *out);\n\n"
            f"/* Release nothing (no resources are held); provided for the initialize/step/terminate shape. */\n"
            f"void {p}_terminate({p}_state_t *state);\n\n"
            f"#endif /* {P}_H */\n")


def _function(name: str, signature: str, b: Body) -> str:
    lines = [f"static void {name}({signature})", "{"]
    lines += ["    " + d for d in b.declarations]
    lines += ["    " + s for s in b.statements]
    lines.append("}")
    return "\n".join(lines) + "\n"


def source(iface: Interface, prov: Provenance, precision: str, control_fn: object,
           start_fn: object | None) -> str:
    p = iface.prefix
    sizes = iface.sources
    reads = {
        0: _element_map(iface, "inputs", "meas"), 1: _element_map(iface, "state", "xc"),
        2: {0: "t"}, 3: _element_map(iface, "params", "p"), 4: _element_map(iface, "params", "k")}
    owner = {0: "in->", 1: "state->", 2: "in->", 3: "params->", 4: "params->"}

    def read(i: int, j: int) -> str:
        return owner[i] + reads[i][j]

    writes = {0: _element_map(iface, "outputs", "cmd"), 1: _element_map(iface, "state", "xc"),
              2: _element_map(iface, "outputs", "diag")}
    wown = {0: "out->", 1: "next->", 2: "out->"}

    def write(i: int, j: int) -> str:
        return wown[i] + writes[i][j]

    control = body(control_fn, precision, read, write)
    r = control.inputs_read
    uses = (("state", 1 in r), ("params", 3 in r or 4 in r), ("in", 0 in r or 2 in r), ("next", sizes["xc"] > 0))
    unused = [f"    (void){n};" for n, used in uses if not used]
    text = banner(iface, prov, f"{p}.c: the exported controller (law, its own integration, saturation)", precision)
    text += CONTRACT_OFF
    if precision == "double":
        text += EVAL_DOUBLE
    text += f'#include "{p}.h"\n'
    text += '#include "rpo_math.h"\n' if precision == "double" else "#include <math.h>\n"
    text += f"\n/* control_{iface.controller}: (meas[{sizes['meas']}], xc[{sizes['xc']}], t, p[{sizes['p']}], " \
            f"k[{sizes['k']}]) -> (cmd, xc_next, diag), {control.operations} instructions */\n"
    sig = (f"const {p}_state_t *state, const {p}_params_t *params, const {p}_inputs_t *in, {p}_outputs_t *out, "
           f"{p}_state_t *next")
    fn = _function(f"{p}_control", sig, control)
    if unused:
        fn = fn.replace("{\n", "{\n" + "\n".join(unused) + "\n", 1)
    text += fn
    zero = PRECISIONS[precision][1]
    inits = [f"    state->{_access(g, m, i)} = 0.0{zero};" for g, m in iface.members("state") for i in range(m.size)]
    text += (f"\nvoid {p}_initialize({p}_state_t *state, const {p}_params_t *params)\n{{\n    (void)params;\n"
             + "".join(s + "\n" for s in inits) + "    state->steps = 0U;\n}\n")
    if start_fn is not None:
        sreads = {0: (reads[0], "in->"), 1: (reads[3], "params->"), 2: (reads[4], "params->")}

        def sread(i: int, j: int) -> str:
            return sreads[i][1] + sreads[i][0][j]

        def swrite(i: int, j: int) -> str:
            return "state->" + writes[1][j]

        start = body(start_fn, precision, sread, swrite)
        text += f"\n/* {iface.start_function}: (meas, p, k) -> xc0, {start.operations} instructions */\n"
        fn = _function(f"{p}_start_body", f"{p}_state_t *state, const {p}_params_t *params, "
                                          f"const {p}_inputs_t *in", start)
        r = start.inputs_read
        unused = [f"    (void){n};" for n, used in (("params", 1 in r or 2 in r), ("in", 0 in r)) if not used]
        text += fn.replace("{\n", "{\n" + "\n".join(unused) + "\n", 1) if unused else fn
        text += (f"\nvoid {p}_start({p}_state_t *state, const {p}_params_t *params, const {p}_inputs_t *in)\n"
                 f"{{\n    {p}_start_body(state, params, in);\n}}\n")
    text += (f"\nvoid {p}_step({p}_state_t *state, const {p}_params_t *params, const {p}_inputs_t *in,\n"
             f"{' ' * (len(p) + 10)}{p}_outputs_t *out)\n{{\n"
             f"    {p}_state_t next;\n"
             "    /* the next states go to a copy: the law reads the current ones until its last statement */\n"
             f"    {p}_control(state, params, in, out, &next);\n"
             "    next.steps = state->steps + 1U;\n"
             "    *state = next;\n}\n")
    text += f"\nvoid {p}_terminate({p}_state_t *state)\n{{\n    (void)state;\n}}\n"
    return text


def _converter(name: str, sig: str, iface: Interface, struct: str, ptr: str, to_array: bool) -> str:
    lines = [f"void {name}({sig})", "{"]
    k = 0
    for g, m in iface.members(struct):
        for i in range(m.size):
            acc = f"{ptr}->{_access(g, m, i)}"
            lines.append(f"    a[{k}] = {acc};" if to_array else f"    {acc} = a[{k}];")
            k += 1
    if k == 0:
        lines.append(f"    (void){ptr};\n    (void)a;")
    lines.append("}")
    return "\n".join(lines) + "\n"


def io_files(iface: Interface, prov: Provenance, precision: str) -> tuple[str, str]:
    """``<prefix>_io.h`` and ``_io.c``: the structs to and from flat arrays, in the members' order
    (for test drivers, telemetry, the processor-in-the-loop harness)."""
    p = iface.prefix
    P = p.upper()
    t = f"{p}_real_t"
    specs: list[tuple[str, str, str, str, bool]] = [
        ("params_from_array", f"{p}_params_t *params, const {t} *a", "params", "params", False),
        ("inputs_from_array", f"{p}_inputs_t *in, const {t} *a", "inputs", "in", False),
        ("outputs_to_array", f"const {p}_outputs_t *out, {t} *a", "outputs", "out", True),
        ("state_to_array", f"const {p}_state_t *state, {t} *a", "state", "state", True),
        ("state_from_array", f"{p}_state_t *state, const {t} *a", "state", "state", False),
    ]
    h = banner(iface, prov, f"{p}_io.h: the structs to and from flat arrays (members' order)", precision)
    h += f"#ifndef {P}_IO_H\n#define {P}_IO_H\n\n#include \"{p}.h\"\n\n"
    for s in ("params", "inputs", "outputs", "state"):
        h += f"#define {P}_N_{s.upper()} {iface.size(s)}\n"
    h += "\n" + "".join(f"void {p}_{n}({sig});\n" for n, sig, *_ in specs) + f"\n#endif /* {P}_IO_H */\n"
    c = banner(iface, prov, f"{p}_io.c: the structs to and from flat arrays", precision)
    c += f'#include "{p}_io.h"\n\n'
    c += "\n".join(_converter(f"{p}_{n}", sig, iface, struct, ptr, to) for n, sig, struct, ptr, to in specs)
    return h, c


Printer = Callable[[Interface, Provenance, str], str]
