"""The package's host test program and Makefile: drive the export with its recorded test vectors.

``test_<prefix>.c`` reads ``<prefix>_vectors.txt`` (:mod:`rpo.runtime.flight.vectors`), starts the
states as the simulation did, steps through every recorded step and compares: double precision bit
for bit (the first difference is printed with its step, array and index); single precision within
the file's tolerance, relative to each output's scale over the run (the worst is printed).  It uses
stdio, so it is no part of the flight code (the Makefile builds it apart from the library).
"""

from __future__ import annotations

from rpo.runtime.flight.emit import PRECISIONS
from rpo.runtime.flight.interface import Interface
from rpo.runtime.flight.tools import warning_flags

_DOUBLE_HELPERS = r"""
static int same(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static int fail(const char *what, long step, int i, double got, double expected)
{
    fprintf(stderr, "@P@: %s %d differs at step %ld: %.17g, recorded %.17g\n", what, i, step, got, expected);
    return 1;
}
"""


def test_program(iface: Interface, precision: str) -> str:
    p = iface.prefix
    P = p.upper()
    real = PRECISIONS[precision][0]
    single = precision == "single"
    conv = "(float)" if single else ""
    compare = (
        """        for (i = 0; i < NO; ++i) {
            double e = fabs((double)out_a[i] - exp_o[i]) / (scale[i] > 0.0 ? scale[i] : 1.0);
            /* !(e <= worst): a NaN is the worst error there is */
            if (i < NCMD && !(e <= worst)) { worst = e; worst_step = step; worst_index = i; }
            if (i >= NCMD && !(e <= worst_diag)) { worst_diag = e; }
        }
        for (i = 0; i < NS; ++i) {
            double e = fabs((double)st_a[i] - exp_s[i]) / (fabs(exp_s[i]) > 1.0 ? fabs(exp_s[i]) : 1.0);
            if (!(e <= worst_state)) { worst_state = e; }
        }
""" if single else """        for (i = 0; i < NO; ++i) {
            if (!same(out_a[i], exp_o[i])) { return fail("output", step, i, out_a[i], exp_o[i]); }
        }
        for (i = 0; i < NS; ++i) {
            if (!same(st_a[i], exp_s[i])) { return fail("state", step, i, st_a[i], exp_s[i]); }
        }
""")
    verdict = (
        f"""    printf("{p}: %ld steps; worst command error %.3g of its scale (step %ld, output %d; tolerance %.3g); "
           "worst diagnostic error %.3g, state error %.3g (reported)\\n", steps, worst, worst_step, worst_index,
           tol[0], worst_diag, worst_state);
    return (worst <= tol[0]) ? 0 : 1;
""" if single else f"""    printf("{p}: %ld steps, outputs and states equal to the simulation's bit for bit\\n", steps);
    return 0;
""")
    start = ""
    start_buffer = " v_i[NI]," if iface.has_start else ""
    if iface.has_start:
        start = f"""    if (!tagged(f, "I", v_i, {P}_N_INPUTS)) {{ return bad_file(); }}
    for (i = 0; i < NI; ++i) {{ in_a[i] = {conv}v_i[i]; }}
    {p}_inputs_from_array(&in, in_a);
    {p}_start(&state, &params, &in);
"""
    state_check = ("" if single else f"""    {p}_state_to_array(&state, st_a);
    for (i = 0; i < NS; ++i) {{
        if (!same(st_a[i], exp_s0[i])) {{ return fail("initial state", -1L, i, st_a[i], exp_s0[i]); }}
    }}
""")
    helpers = "" if single else _DOUBLE_HELPERS.replace("@P@", p)
    return f"""/* test_{p}.c: the export against its recorded test vectors (host only: uses stdio).
 * Build and run: make test   (or: ./test_{p} {p}_vectors.txt) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "{p}.h"
#include "{p}_io.h"

#define NP ({P}_N_PARAMS + 1)
#define NI ({P}_N_INPUTS + 1)
#define NO ({P}_N_OUTPUTS)
#define NS ({P}_N_STATE)
#define NCMD {iface.outputs[0].size}

static double v_p[NP], v_s0[NS + 1],{start_buffer} v_in[NI], exp_o[NO + 1], exp_s[NS + 1], scale[NO + 1];
static double tol[1];
static double exp_s0[NS + 1];

static int values(FILE *f, double *v, int n)
{{
    int i;
    char tok[40];
    for (i = 0; i < n; ++i) {{
        unsigned long long bits;
        if (fscanf(f, "%39s", tok) != 1) {{ return 0; }}
        bits = strtoull(tok, NULL, 16);
        memcpy(&v[i], &bits, sizeof v[i]);
    }}
    return 1;
}}

static int tagged(FILE *f, const char *tag, double *v, int n)
{{
    char tok[8];
    if (fscanf(f, "%7s", tok) != 1 || strcmp(tok, tag) != 0) {{ return 0; }}
    return values(f, v, n);
}}

static int bad_file(void)
{{
    fprintf(stderr, "{p}: the vector file is not in the expected format\\n");
    return 2;
}}
{helpers}
int main(int argc, char **argv)
{{
    FILE *f;
    char line[256] = {{0}};
    long steps = 0, step;
    int i;
    {p}_params_t params;
    {p}_state_t state;
    {p}_inputs_t in;
    {p}_outputs_t out;
    {real} p_a[NP], in_a[NI], out_a[NO + 1], st_a[NS + 1];
    double worst = 0.0, worst_state = 0.0, worst_diag = 0.0;
    long worst_step = -1;
    int worst_index = -1;
    (void)worst; (void)worst_state; (void)worst_diag; (void)worst_step; (void)worst_index;
    if (argc != 2) {{
        fprintf(stderr, "usage: %s {p}_vectors.txt\\n", argv[0]);
        return 2;
    }}
    f = fopen(argv[1], "r");
    if (f == NULL) {{
        fprintf(stderr, "{p}: cannot open %s\\n", argv[1]);
        return 2;
    }}
    while (fgets(line, (int)sizeof line, f) != NULL && line[0] == '#') {{
        size_t n = strlen(line);
        while (n > 0U && line[n - 1U] != '\\n' && fgets(line, (int)sizeof line, f) != NULL) {{ n = strlen(line); }}
    }}
    if (sscanf(line, "N %ld", &steps) != 1) {{ return bad_file(); }}
    if (!tagged(f, "P", v_p, {P}_N_PARAMS) || !tagged(f, "S", v_s0, NS)) {{ return bad_file(); }}
    for (i = 0; i < NS; ++i) {{ exp_s0[i] = v_s0[i]; }}
    for (i = 0; i < {P}_N_PARAMS; ++i) {{ p_a[i] = {conv}v_p[i]; }}
    {p}_params_from_array(&params, p_a);
    {p}_initialize(&state, &params);
{start}{state_check}    if (!tagged(f, "C", scale, NO) || !tagged(f, "T", tol, 1)) {{ return bad_file(); }}
    for (step = 0; step < steps; ++step) {{
        if (!tagged(f, "V", v_in, {P}_N_INPUTS) || !values(f, exp_o, NO) || !values(f, exp_s, NS)) {{
            return bad_file();
        }}
        for (i = 0; i < {P}_N_INPUTS; ++i) {{ in_a[i] = {conv}v_in[i]; }}
        {p}_inputs_from_array(&in, in_a);
        {p}_step(&state, &params, &in, &out);
        {p}_outputs_to_array(&out, out_a);
        {p}_state_to_array(&state, st_a);
{compare}    }}
    (void)fclose(f);
{verdict}}}
"""


def makefile(iface: Interface, precision: str, sources: list[str]) -> str:
    p = iface.prefix
    double = precision == "double"
    objs = " ".join(s.replace(".c", ".o") for s in sources)
    return f"""# {p}: flight-code export of rpo controller '{iface.controller}' ({precision} precision).
# make            the library lib{p}.a and the host test program
# make test       run the test vectors ({'bit for bit' if precision == 'double' else 'within the tolerance'})
# make CC=clang   a C99 compiler{" with GCC's builtins (rpo_math.h): gcc, clang, arm-none-eabi-gcc" if double else ""}
# RPO_NUMERIC is kept whatever CFLAGS says: no fused multiply-add (the simulation's bits; the source says so too)
CFLAGS ?= {' '.join(warning_flags(precision))}
RPO_NUMERIC = -ffp-contract=off

OBJS = {objs}

all: lib{p}.a test_{p}

lib{p}.a: $(OBJS)
\t$(AR) rcs $@ $(OBJS)

%.o: %.c *.h
\t$(CC) $(CFLAGS) $(RPO_NUMERIC) -c -o $@ $<

test_{p}: test_{p}.c lib{p}.a
\t$(CC) $(CFLAGS) $(RPO_NUMERIC) -o $@ test_{p}.c lib{p}.a -lm

test: test_{p}
\t./test_{p} {p}_vectors.txt

clean:
\trm -f $(OBJS) lib{p}.a test_{p} *.su *.ci

.PHONY: all test clean
"""
