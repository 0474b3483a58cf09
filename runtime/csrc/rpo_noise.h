/* rpo noise: the standard-normal inputs w of every step, as a pure function of (seed, step, index).
 *
 * Hand-written (not generated).  Sample i of step g of a run with seed s:
 *
 *   key      = mix(mix(s) ^ 0x5851f42d4c957f2d)        (a 64-bit key per seed)
 *   u(c)     = (mix(key + c * 0x9e3779b97f4a7c15) >> 11 + 1) * 2^-53      in (0, 1]
 *   pair j   = i / 2 uses counters c = 2 (g * P + j) and c + 1, P = ceil(nw / 2)
 *   r        = sqrt(-2 log u(c)),  theta = 2 pi (u(c + 1) - 2^-53)
 *   w_i      = r cos(theta) for even i, r sin(theta) for odd i           (Box-Muller)
 *
 * mix is SplitMix64's finaliser, so u(c) over consecutive c is exactly the SplitMix64 sequence
 * started at `key` (it passes BigCrush).  Because a sample depends only on (s, g, i), a run's
 * noise is the same whatever the chunk size, the batch it is in, its lane, the process or the
 * machine, and any step's noise can be drawn without the steps before it.  log, sqrt and sincos
 * are rpo_math.h's, so the scalar loop and every lane of the lockstep loop draw the same bits.
 */
#ifndef RPO_NOISE_H
#define RPO_NOISE_H

#include "rpo_lanes.h"

/* The most noise inputs per step the loops take. */
#define RPO_NOISE_MAX 256

#if RPO_LANES == 1
typedef unsigned long long rpo_u;
static inline rpo_v rpo__u2d(rpo_u x) { return (double)x; }
#else
typedef unsigned long long rpo_u __attribute__((vector_size(8 * RPO_LANES)));
static inline rpo_v rpo__u2d(rpo_u x) { return __builtin_convertvector(x, rpo_v); }
#endif

/* SplitMix64's finaliser, written once for both the lane type and one 64-bit integer */
#define RPO__SPLITMIX(z)                              \
    do {                                              \
        (z) = ((z) ^ ((z) >> 30)) * 0xbf58476d1ce4e5b9ULL; \
        (z) = ((z) ^ ((z) >> 27)) * 0x94d049bb133111ebULL; \
        (z) = (z) ^ ((z) >> 31);                      \
    } while (0)

static inline rpo_u rpo_noise_mix(rpo_u z)
{
    RPO__SPLITMIX(z);
    return z;
}

/* The key of a seed (one lane): mix(mix(seed) ^ salt). */
static inline unsigned long long rpo_noise_key1(unsigned long long seed)
{
    unsigned long long z = seed;
    RPO__SPLITMIX(z);
    z ^= 0x5851f42d4c957f2dULL;
    RPO__SPLITMIX(z);
    return z;
}

static inline rpo_v rpo__noise_uniform(rpo_u key, unsigned long long c)
{
    rpo_u z = rpo_noise_mix(key + c * 0x9e3779b97f4a7c15ULL);
    return (rpo__u2d(z >> 11) + RPO_SPLAT(1.0)) * RPO_SPLAT(0x1p-53);
}

/* w[0..nw) of global step g for the lanes' keys. */
static inline void rpo_noise_step(rpo_u key, long long g, int nw, rpo_v* w)
{
    const unsigned long long pairs = (unsigned long long)(nw + 1) / 2;
    for (int j = 0; 2 * j < nw; ++j) {
        unsigned long long c = 2ULL * ((unsigned long long)g * pairs + (unsigned long long)j);
        rpo_v u1 = rpo__noise_uniform(key, c);
        rpo_v u2 = rpo__noise_uniform(key, c + 1);
        rpo_v r = rpo_sqrt(RPO_SPLAT(-2.0) * rpo_log(u1));
        rpo_v s, co;
        rpo_sincos(RPO_SPLAT(6.283185307179586) * (u2 - RPO_SPLAT(0x1p-53)), &s, &co);
        w[2 * j] = r * co;
        if (2 * j + 1 < nw) w[2 * j + 1] = r * s;
    }
}

#endif
