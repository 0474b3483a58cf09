/* rpo simulation loop: runs a generated closed-loop step function for n steps.
 *
 * Hand-written (not generated).  Compiled together with generated/rpo_model.c into one
 * shared library by rpo.runtime.compiled.  The step function has CasADi's calling convention:
 *   step(arg = {z_k, t_k, p, k, w_k}, res = {z_{k+1}, y_k}, iw, w, mem)
 * w_k, the standard-normal inputs of step k, are drawn here (rpo_noise.h) from the run's key.
 * Divergence (a non-finite state entry, |z_j| above bound[j], or a non-finite output y_j) stops
 * the loop after writing the offending state and output, so the caller keeps everything computed
 * so far.
 */
#define RPO_LANES 1
#include "rpo_noise.h"

#include <math.h>
#include <stddef.h>

typedef long long casadi_int;
typedef int (*rpo_step_fn)(const double** arg, double** res, casadi_int* iw, double* w, int mem);

/* 1 if x is finite, else 0.  The loader calls it with NaN and inf: a library built with
 * -ffast-math (which may fold isfinite to 1) would miss divergence, so it is refused. */
int rpo_selftest_nan(double x) { return isfinite(x) ? 1 : 0; }

/* Returns the number of completed, healthy steps (0..n).  If it is less than n, *bad_index is
 * the index j of the first offending entry of Z[ret + 1] (0 <= j < nz), or nz + j for a
 * non-finite entry j of Y[ret] when the state is healthy, or -1 when the step function itself
 * reported an error.  t_k = t0 + (k0 + k) dt, formed from the integer step count so that
 * time does not drift over millions of steps. */
int rpo_run(rpo_step_fn step, casadi_int* iw, double* work, double t0, double dt, long long k0,
            int n, const double* p, const double* gains, unsigned long long key, int nw, double* Z,
            int nz, double* Y, int ny, const double* bound, int* bad_index)
{
    const double* arg[5];
    double* res[2];
    double t;
    double w[RPO_NOISE_MAX];
    *bad_index = -2;
    if (nw > RPO_NOISE_MAX) {
        *bad_index = -1;
        return 0;
    }
    for (int i = 0; i < n; ++i) {
        t = t0 + (double)(k0 + i) * dt;
        rpo_noise_step(key, k0 + i, nw, w);
        arg[0] = Z + (size_t)i * nz;
        arg[1] = &t;
        arg[2] = p;
        arg[3] = gains;
        arg[4] = w;
        res[0] = Z + (size_t)(i + 1) * nz;
        res[1] = Y + (size_t)i * ny;
        if (step(arg, res, iw, work, 0) != 0) {
            *bad_index = -1;
            return i;
        }
        const double* zn = res[0];
        for (int j = 0; j < nz; ++j) {
            if (!isfinite(zn[j]) || fabs(zn[j]) > bound[j]) {
                *bad_index = j;
                return i;
            }
        }
        /* the outputs too: a non-finite output (e.g. a wheel speed over a near-zero inertia) is a
         * divergence even while the state stays finite; one compare per entry, no bound */
        const double* yn = res[1];
        for (int j = 0; j < ny; ++j) {
            if (!isfinite(yn[j])) {
                *bad_index = nz + j;
                return i;
            }
        }
    }
    return n;
}

/* The key of a seed, and the noise of steps g0 .. g0 + n - 1 into W[n][nw] (for checks and tools). */
unsigned long long rpo_noise_key(unsigned long long seed) { return rpo_noise_key1(seed); }

void rpo_noise_fill(unsigned long long key, long long g0, long long n, int nw, double* W)
{
    for (long long i = 0; i < n; ++i) rpo_noise_step(key, g0 + i, nw, W + (size_t)i * nw);
}

/* Evaluate a generated function at N points, one call each, in place: input j of point i at
 * in[j] + i * in_stride[j] (stride 0: shared by every point), output j at out[j] + i * out_size[j].
 * Returns 0, or 1 + the index of the first point the function reported an error at. */
long long rpo_batch_scalar(rpo_step_fn f, casadi_int* iw, double* work, int n_in, const double* const* in,
                           const long long* in_stride, int n_out, double* const* out, const long long* out_size,
                           long long N)
{
    const double* arg[64];
    double* res[64];
    if (n_in > 64 || n_out > 64) return 1;
    for (long long i = 0; i < N; ++i) {
        for (int j = 0; j < n_in; ++j) arg[j] = in[j] + i * in_stride[j];
        for (int j = 0; j < n_out; ++j) res[j] = out[j] + i * out_size[j];
        if (f(arg, res, iw, work, 0) != 0) return 1 + i;
    }
    return 0;
}
