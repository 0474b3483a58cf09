/* rpo lockstep loops: K runs (RPO_LANES) of a lane function at once.
 *
 * Hand-written (not generated).  Compiled with the lane forms of the generated files
 * (runtime/lanes.py) into the lane library by rpo.runtime.compiled.  Points and runs are laid
 * out point-major in the caller's arrays; here they are gathered into rpo_v (one lane per point
 * or run), evaluated, and scattered back.  A lane's arithmetic never depends on another lane's
 * values, so a run's trajectory is the same whichever lane it has and whatever its neighbours
 * do (a neighbour that diverges only stops being checked and recorded).
 */
#include "rpo_lanes.h"
#include "rpo_noise.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define K RPO_LANES
/* element e, lane l of an rpo_v array, as a double */
#define LANE(buf, e, l) (((double*)(buf))[(size_t)(e) * K + (l)])

RPO_EXPORT int rpo_lanes_width(void) { return K; }

static rpo_v* lane_alloc(size_t n)
{
    void* p = NULL;
    if (posix_memalign(&p, 64, (n ? n : 1) * sizeof(rpo_v)) != 0) return NULL;
    memset(p, 0, (n ? n : 1) * sizeof(rpo_v));
    return (rpo_v*)p;
}

/* One aligned block for a lane function's inputs, outputs and work space (sz_w, at *work);
 * NULL when memory is short or there are more than 64 inputs or outputs. */
static rpo_v* lane_buffers(long long sz_w, int n_in, const long long* in_size, int n_out, const long long* out_size,
                           const rpo_v** arg, rpo_v** res, rpo_v** work)
{
    if (n_in > 64 || n_out > 64) return NULL;
    size_t total = (size_t)sz_w;
    for (int j = 0; j < n_in; ++j) total += (size_t)in_size[j];
    for (int j = 0; j < n_out; ++j) total += (size_t)out_size[j];
    rpo_v* buf = lane_alloc(total);
    if (!buf) return NULL;
    rpo_v* next = buf;
    for (int j = 0; j < n_in; ++j) { arg[j] = next; next += in_size[j]; }
    for (int j = 0; j < n_out; ++j) { res[j] = next; next += out_size[j]; }
    *work = next;
    return buf;
}

/* Evaluate f at N points: input j of point i is in[j][i * in_stride[j] .. + in_size[j]] (stride 0:
 * the same value for every point), output j of point i goes to out[j][i * out_size[j] ..].
 * Returns 0, -1 when memory is short, or 1 + the first point of a block f reported an error in. */
RPO_EXPORT long long rpo_batch_lanes(rpo_lane_fn f, long long sz_w, int n_in, const double* const* in,
                                     const long long* in_size, const long long* in_stride, int n_out,
                                     double* const* out, const long long* out_size, long long N)
{
    const rpo_v* arg[64];
    rpo_v* res[64];
    rpo_v* next;
    rpo_v* buf = lane_buffers(sz_w, n_in, in_size, n_out, out_size, arg, res, &next);
    if (!buf) return -1;
    rpo_v* work = next;
    long long ret = 0;
    /* an input shared by every point (stride 0) is broadcast once */
    for (int j = 0; j < n_in; ++j) {
        if (in_stride[j] != 0) continue;
        for (long long e = 0; e < in_size[j]; ++e) ((rpo_v*)arg[j])[e] = RPO_SPLAT(in[j][e]);
    }
    for (long long b = 0; b < N; b += K) {
        for (int j = 0; j < n_in; ++j) {
            /* locals: with -fno-strict-aliasing every store below could otherwise alias the sizes */
            const long long stride = in_stride[j], size = in_size[j];
            if (stride == 0) continue;
            double* dst = (double*)arg[j];
            for (int l = 0; l < K; ++l) {
                long long i = b + l < N ? b + l : N - 1;  /* a short last block repeats its last point */
                const double* src = in[j] + i * stride;
                for (long long e = 0; e < size; ++e) dst[(size_t)e * K + l] = src[e];
            }
        }
        if (f(arg, res, NULL, work, 0) != 0) { ret = 1 + b; break; }
        for (int j = 0; j < n_out; ++j) {
            const long long size = out_size[j];
            const double* src = (const double*)res[j];
            double* base = out[j];
            for (int l = 0; l < K && b + l < N; ++l) {
                double* dst = base + (b + l) * size;
                for (long long e = 0; e < size; ++e) dst[e] = src[(size_t)e * K + l];
            }
        }
    }
    free(buf);
    return ret;
}

/* n closed-loop steps of K runs from global step k0 (t_k = t0 + (k0 + k) dt, as rpo_run).
 *
 * Per lane l: P[l], G[l] its parameters and gains, keys[l] its noise key (rpo_noise.h), Z[l] the state
 * (in: at step k0; out: at the end, or the last good state of a run that diverged).  Steps whose
 * global index is a multiple of `every` are recorded: state at the step's start and the step's
 * output, into rows r of Zrec[l] and Yrec[l] (r counts recorded steps in this call).  status[l]: in,
 * 1 for a run to advance and 0 for a lane to ignore; out, 0 once the run diverged, with
 * steps_ok[l] the global count of its healthy steps, bad[l] the first offending entry of the
 * next state (nz + e: entry e of the step's output, non-finite; -1: the step function failed), Zbad[l] that state, Ylast[l] the failing step's
 * output.  Returns 0, or -1 when memory is short. */
RPO_EXPORT int rpo_run_lanes(rpo_lane_fn step, long long sz_w, double t0, double dt, long long k0, int n,
                             long long every, const double* P, int np, const double* G, int nk,
                             const unsigned long long* keys, int nw, double* Z, int nz, double* const* Zrec,
                             double* const* Yrec, int ny,
                             const double* bound, int* status, long long* steps_ok, int* bad, double* Zbad,
                             double* Ylast)
{
    size_t total = (size_t)(2 * nz + 1 + np + nk + nw + ny) + (size_t)sz_w;
    rpo_v* buf = lane_alloc(total);
    if (!buf) return -1;
    rpo_v *z = buf, *zn = z + nz, *t = zn + nz, *p = t + 1, *g = p + np, *w = g + nk, *y = w + nw;
    rpo_v* work = y + ny;
    rpo_u key;
    for (int l = 0; l < K; ++l) ((unsigned long long*)&key)[l] = keys[l];
    for (int l = 0; l < K; ++l) {
        for (int e = 0; e < nz; ++e) LANE(z, e, l) = Z[(size_t)l * nz + e];
        for (int e = 0; e < np; ++e) LANE(p, e, l) = P[(size_t)l * np + e];
        for (int e = 0; e < nk; ++e) LANE(g, e, l) = G[(size_t)l * nk + e];
    }
    const rpo_v* arg[5];
    rpo_v* res[2];
    arg[1] = t; arg[2] = p; arg[3] = g;
    long long r = 0;
    int active = 0;
    for (int l = 0; l < K; ++l) active += status[l] != 0;
    for (int i = 0; i < n && active; ++i) {
        double tk = t0 + (double)(k0 + i) * dt;
        for (int l = 0; l < K; ++l) LANE(t, 0, l) = tk;
        rpo_noise_step(key, k0 + i, nw, w);
        arg[0] = z; arg[4] = w;
        res[0] = zn; res[1] = y;
        int failed = step(arg, res, NULL, work, 0) != 0;
        int rec = (k0 + i) % every == 0;
        if (rec) {
            for (int l = 0; l < K; ++l) {
                if (!status[l]) continue;
                double* zr = Zrec[l] + (size_t)r * nz;
                double* yr = Yrec[l] + (size_t)r * ny;
                for (int e = 0; e < nz; ++e) zr[e] = LANE(z, e, l);
                for (int e = 0; e < ny; ++e) yr[e] = LANE(y, e, l);
            }
            ++r;
        }
        /* divergence: a non-finite entry or |z_j| > bound[j] (NaN fails every comparison) */
        rpo_m m = RPO_MNOT(RPO_GE(RPO_SPLAT(0.), RPO_SPLAT(0.)));
        for (int e = 0; e < nz; ++e) {
            rpo_v a = rpo_fabs(zn[e]);
            m = RPO_MOR(m, RPO_MOR(RPO_MNOT(RPO_LT(a, RPO_SPLAT(INFINITY))), RPO_GT(a, RPO_SPLAT(bound[e]))));
        }
        /* and a non-finite output, as rpo_run checks it (index nz + e, after the state's) */
        for (int e = 0; e < ny; ++e) m = RPO_MOR(m, RPO_MNOT(RPO_LT(rpo_fabs(y[e]), RPO_SPLAT(INFINITY))));
        if (failed || RPO_ANY(m)) {
            for (int l = 0; l < K; ++l) {
                if (!status[l]) continue;
                int j = failed ? -1 : -2;
                for (int e = 0; e < nz && j == -2; ++e) {
                    double v = LANE(zn, e, l);
                    if (!isfinite(v) || fabs(v) > bound[e]) j = e;
                }
                for (int e = 0; e < ny && j == -2; ++e)
                    if (!isfinite(LANE(y, e, l))) j = nz + e;
                if (j == -2) continue;
                status[l] = 0;
                --active;
                steps_ok[l] = k0 + i;
                bad[l] = j;
                for (int e = 0; e < nz; ++e) {
                    Zbad[(size_t)l * nz + e] = LANE(zn, e, l);
                    Z[(size_t)l * nz + e] = LANE(z, e, l);
                }
                for (int e = 0; e < ny; ++e) Ylast[(size_t)l * ny + e] = LANE(y, e, l);
            }
        }
        rpo_v* tmp = z; z = zn; zn = tmp;
    }
    for (int l = 0; l < K; ++l) {
        if (!status[l]) continue;
        steps_ok[l] = k0 + n;
        for (int e = 0; e < nz; ++e) Z[(size_t)l * nz + e] = LANE(z, e, l);
    }
    free(buf);
    return 0;
}

/* For benchmarks: evaluate f `reps` times on the first K points of `in` (gathered once), so
 * that the time per call over K is the compiled code's own cost per evaluation. */
RPO_EXPORT int rpo_repeat_lanes(rpo_lane_fn f, long long sz_w, int n_in, const double* const* in,
                                const long long* in_size, const long long* in_stride, int n_out,
                                const long long* out_size, long long reps)
{
    const rpo_v* arg[64];
    rpo_v* res[64];
    rpo_v* next;
    rpo_v* buf = lane_buffers(sz_w, n_in, in_size, n_out, out_size, arg, res, &next);
    if (!buf) return -1;
    for (int j = 0; j < n_in; ++j)
        for (int l = 0; l < K; ++l)
            for (long long e = 0; e < in_size[j]; ++e) LANE(arg[j], e, l) = in[j][l * in_stride[j] + e];
    int rc = 0;
    for (long long r = 0; r < reps; ++r) rc |= f(arg, res, NULL, next, 0);
    free(buf);
    return rc;
}
