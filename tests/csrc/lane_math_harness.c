/* Test and benchmark harness for runtime/csrc/rpo_math.h (compiled by tests/test_lane_math.py).
 *
 *   harness IN OUT     IN: int64 n, then n doubles a[], n doubles b[].
 *                      OUT: for each entry of FUNCS (in order), n doubles.  Inputs are fed
 *                      RPO_LANES consecutive elements per vector, so a lane's neighbours are
 *                      unrelated values (tests cross-lane independence).
 *   harness --bench N  (built with -DRPO_HARNESS_BENCH) ns per element of rpo_* and glibc over N inputs in [-10, 10] (exp: [-50, 50]).
 *
 * Build: cc -O2 -ffp-contract=off -DRPO_LANES=K -I runtime/csrc lane_math_harness.c -lm
 */
#include "rpo_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define UNARY(name, expr) \
    static rpo_v f_##name(rpo_v a, rpo_v b) { (void)b; return expr; }
#define BINARY(name, expr) \
    static rpo_v f_##name(rpo_v a, rpo_v b) { return expr; }

UNARY(sin, rpo_sin(a))
UNARY(cos, rpo_cos(a))
UNARY(tan, rpo_tan(a))
UNARY(exp, rpo_exp(a))
UNARY(log, rpo_log(a))
UNARY(atan, rpo_atan(a))
UNARY(asin, rpo_asin(a))
UNARY(acos, rpo_acos(a))
UNARY(sinh, rpo_sinh(a))
UNARY(cosh, rpo_cosh(a))
UNARY(tanh, rpo_tanh(a))
UNARY(expm1, rpo_expm1(a))
UNARY(sqrt, rpo_sqrt(a))
UNARY(floor, rpo_floor(a))
UNARY(ceil, rpo_ceil(a))
UNARY(fabs, rpo_fabs(a))
UNARY(sign, rpo_sign(a))
static rpo_v f_sincos_s(rpo_v a, rpo_v b) { rpo_v s, c; (void)b; rpo_sincos(a, &s, &c); return s; }
static rpo_v f_sincos_c(rpo_v a, rpo_v b) { rpo_v s, c; (void)b; rpo_sincos(a, &s, &c); return c; }
BINARY(atan2, rpo_atan2(a, b))
BINARY(fmin, rpo_fmin(a, b))
BINARY(fmax, rpo_fmax(a, b))
BINARY(lt, RPO_B2D(RPO_LT(a, b)))
BINARY(le, RPO_B2D(RPO_LE(a, b)))
BINARY(gt, RPO_B2D(RPO_GT(a, b)))
BINARY(ge, RPO_B2D(RPO_GE(a, b)))
BINARY(eq, RPO_B2D(RPO_EQ(a, b)))
BINARY(ne, RPO_B2D(RPO_NE(a, b)))
BINARY(select_lt, RPO_SELECT(RPO_LT(a, b), a, b))
BINARY(mand, RPO_B2D(RPO_MAND(RPO_LT(a, b), RPO_GT(a, RPO_SPLAT(0.0)))))
BINARY(mor, RPO_B2D(RPO_MOR(RPO_LT(a, b), RPO_GT(a, RPO_SPLAT(0.0)))))
BINARY(mnot, RPO_B2D(RPO_MNOT(RPO_LT(a, b))))
BINARY(splat, RPO_SELECT(RPO_LT(a, b), RPO_SPLAT(-0.0), RPO_SPLAT(1.0)))

typedef rpo_v (*fn_t)(rpo_v, rpo_v);
#define E(name) {#name, f_##name}
static const struct { const char* name; fn_t f; } FUNCS[] = {
    E(sin), E(cos), E(tan), E(exp), E(log), E(atan), E(asin), E(acos), E(sinh), E(cosh),
    E(tanh), E(expm1), E(sqrt), E(floor), E(ceil), E(fabs), E(sign), E(sincos_s), E(sincos_c),
    E(atan2), E(fmin), E(fmax), E(lt), E(le), E(gt), E(ge), E(eq), E(ne), E(select_lt),
    E(mand), E(mor), E(mnot), E(splat),
};
#define NFUNCS ((int)(sizeof FUNCS / sizeof FUNCS[0]))

static int run(const char* in, const char* out)
{
    FILE* fi = fopen(in, "rb");
    if (!fi) return 2;
    long long n;
    if (fread(&n, sizeof n, 1, fi) != 1) return 2;
    double* a = malloc(sizeof(double) * (size_t)n);
    double* b = malloc(sizeof(double) * (size_t)n);
    double* r = malloc(sizeof(double) * (size_t)n);
    if (fread(a, sizeof(double), (size_t)n, fi) != (size_t)n) return 2;
    if (fread(b, sizeof(double), (size_t)n, fi) != (size_t)n) return 2;
    fclose(fi);
    FILE* fo = fopen(out, "wb");
    if (!fo) return 2;
    for (int f = 0; f < NFUNCS; f++) {
        for (long long i = 0; i < n; i += RPO_LANES) {
            rpo_v va = RPO_SPLAT(0.0), vb = RPO_SPLAT(0.0);
            for (int l = 0; l < RPO_LANES && i + l < n; l++) {
                va = rpo_lane_set(va, l, a[i + l]);
                vb = rpo_lane_set(vb, l, b[i + l]);
            }
            rpo_v vr = FUNCS[f].f(va, vb);
            for (int l = 0; l < RPO_LANES && i + l < n; l++) r[i + l] = rpo_lane_get(vr, l);
        }
        fwrite(r, sizeof(double), (size_t)n, fo);
    }
    fclose(fo);
    return 0;
}

/* ---------------------------------------------------------------------------------------- */
#ifdef RPO_HARNESS_BENCH
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
static volatile double sink;

#define BENCH_RPO(label, EXPR)                                                     \
    do {                                                                           \
        double best = 1e30;                                                        \
        for (int rep = 0; rep < 7; rep++) {                                        \
            double t0 = now();                                                     \
            rpo_v acc = RPO_SPLAT(0.0);                                            \
            for (long i = 0; i + RPO_LANES <= n; i += RPO_LANES) {                 \
                rpo_v a, b;                                                        \
                memcpy(&a, x + i, sizeof a);                                       \
                memcpy(&b, y + i, sizeof b);                                       \
                (void)b;                                                           \
                acc += EXPR;                                                       \
            }                                                                      \
            double dt = now() - t0;                                                \
            sink = rpo_lane_get(acc, 0);                                           \
            if (dt < best) best = dt;                                              \
        }                                                                          \
        printf("K=%d  %-12s %7.2f ns/elem\n", RPO_LANES, label, 1e9 * best / n); \
    } while (0)

#define BENCH_LIBM(label, EXPR)                                         \
    do {                                                                \
        double best = 1e30;                                             \
        for (int rep = 0; rep < 7; rep++) {                             \
            double t0 = now();                                          \
            double acc = 0;                                             \
            for (long i = 0; i < n; i++) {                              \
                double a = x[i], b = y[i];                              \
                (void)b;                                                \
                acc += EXPR;                                            \
            }                                                           \
            double dt = now() - t0;                                     \
            sink = acc;                                                 \
            if (dt < best) best = dt;                                   \
        }                                                               \
        printf("glibc %-14s %7.2f ns/elem\n", label, 1e9 * best / n); \
    } while (0)

static rpo_v sc_sum(rpo_v a)
{
    rpo_v s, c;
    rpo_sincos(a, &s, &c);
    return s + c;
}

static int bench(long n)
{
    double* x = malloc(sizeof(double) * (size_t)n);
    double* y = malloc(sizeof(double) * (size_t)n);
    double* e = malloc(sizeof(double) * (size_t)n);
    srand(12345);
    for (long i = 0; i < n; i++) {
        x[i] = 20.0 * rand() / RAND_MAX - 10.0;
        y[i] = 20.0 * rand() / RAND_MAX - 10.0;
        e[i] = 5.0 * x[i];
    }
    BENCH_RPO("rpo_sin", rpo_sin(a));
    BENCH_RPO("rpo_cos", rpo_cos(a));
    BENCH_RPO("rpo_sincos", sc_sum(a));
    BENCH_RPO("rpo_tan", rpo_tan(a));
    BENCH_RPO("rpo_atan2", rpo_atan2(a, b));
    BENCH_RPO("rpo_log", rpo_log(rpo_fabs(a)));
    {
        double* t = x;
        x = e;
        BENCH_RPO("rpo_exp", rpo_exp(a));
        x = t;
    }
#if RPO_LANES == 1
    BENCH_LIBM("sin", sin(a));
    BENCH_LIBM("cos", cos(a));
    BENCH_LIBM("sin+cos", sin(a) + cos(a));
    BENCH_LIBM("tan", tan(a));
    BENCH_LIBM("atan2", atan2(a, b));
    BENCH_LIBM("log", log(fabs(a)));
    {
        double* t = x;
        x = e;
        BENCH_LIBM("exp", exp(a));
        x = t;
    }
#endif
    return 0;
}
#endif

int main(int argc, char** argv)
{
    if (argc == 2 && strcmp(argv[1], "--names") == 0) {
        for (int f = 0; f < NFUNCS; f++) printf("%s\n", FUNCS[f].name);
        return 0;
    }
#ifdef RPO_HARNESS_BENCH
    if (argc == 3 && strcmp(argv[1], "--bench") == 0) return bench(atol(argv[2]));
#endif
    if (argc == 3) return run(argv[1], argv[2]);
    fprintf(stderr, "usage: %s IN OUT | --bench N | --names\n", argv[0]);
    return 2;
}
