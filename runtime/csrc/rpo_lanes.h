/* rpo lanes: the element type of the lane form of the generated code (runtime/lanes.py).
 *
 * Hand-written (not generated).  RPO_LANES, the number of runs evaluated at once, is the
 * compiler target's vector width in doubles unless given with -DRPO_LANES=K: 8 with AVX-512F,
 * 4 with AVX, 2 with SSE2 or NEON, else 1.  rpo_v is one double per lane (a GCC vector of
 * RPO_LANES doubles, or a plain double); the arithmetic, comparisons and math functions on it
 * come from rpo_math.h, whose functions are also what the scalar compile of the generated files
 * calls (rpo_math_scalar.h), so that one lane's result is bit-identical to the scalar result.
 * Must be compiled with -ffp-contract=off (an FMA contraction in one path only would change bits).
 */
#ifndef RPO_LANES_H
#define RPO_LANES_H

#ifndef RPO_LANES
#  if defined(__AVX512F__)
#    define RPO_LANES 8
#  elif defined(__AVX__)
#    define RPO_LANES 4
#  elif defined(__SSE2__) || defined(__ARM_NEON)
#    define RPO_LANES 2
#  else
#    define RPO_LANES 1
#  endif
#endif

#include "rpo_math.h"

#if defined(__GNUC__)
#  define RPO_EXPORT __attribute__((visibility("default")))
#else
#  define RPO_EXPORT
#endif

/* Signature of a lane function: CasADi's, over rpo_v (iw and mem are unused, kept for symmetry). */
typedef int (*rpo_lane_fn)(const rpo_v** arg, rpo_v** res, long long* iw, rpo_v* w, int mem);

#if RPO_LANES == 1
#  define RPO_LANE(v, l) (v)
#else
#  define RPO_LANE(v, l) ((v)[l])
#endif

/* Most results a dispatched call may have, and most entries over all its results. */
#define RPO_DISPATCH_MAX_RES 8
#define RPO_DISPATCH_MAX_ENTRIES 512

/* The lane form of a call with specialised variants (symbolic/codegen/c_composition.py): lane l takes
 * fns[j] for the first j < n_alt - 1 whose n_zero[j] entries zero[j] of x are all 0 in lane l,
 * else fns[n_alt - 1] (the general function) -- the choice the scalar glue makes for that run
 * alone, so that every lane keeps the bits of its run alone.  When every lane makes the same
 * choice (a campaign's usual case) that one function is called; otherwise each chosen function
 * is called on the whole block into a scratch copy of the results and its lanes are copied out. */
static inline int rpo_dispatch(int n_alt, const rpo_lane_fn* fns, const long long* const* zero,
                               const long long* n_zero, const rpo_v* x, const rpo_v** a, rpo_v** r, int n_res,
                               const long long* res_size, long long* iw, rpo_v* w) {
  int pick[RPO_LANES];
  int l, j, k, same = 1;
  for (l = 0; l < RPO_LANES; ++l) {
    for (j = 0; j < n_alt - 1; ++j) {
      long long i;
      for (i = 0; i < n_zero[j]; ++i)
        if (RPO_LANE(x[zero[j][i]], l) != 0) break;
      if (i == n_zero[j]) break;
    }
    pick[l] = j;
    if (j != pick[0]) same = 0;
  }
  if (same) return fns[pick[0]](a, r, iw, w, 0);
  {
    rpo_v scratch[RPO_DISPATCH_MAX_ENTRIES];
    rpo_v* rr[RPO_DISPATCH_MAX_RES];
    long long total = 0, e;
    if (n_res > RPO_DISPATCH_MAX_RES) return 1;
    for (k = 0; k < n_res; ++k) total += res_size[k];
    if (total > RPO_DISPATCH_MAX_ENTRIES) return 1;
    for (j = 0; j < n_alt; ++j) {
      int used = 0;
      rpo_v* s = scratch;
      for (l = 0; l < RPO_LANES; ++l) used |= pick[l] == j;
      if (!used) continue;
      for (k = 0; k < n_res; ++k) { rr[k] = s; s += res_size[k]; }
      if (fns[j](a, rr, iw, w, 0)) return 1;
      for (k = 0; k < n_res; ++k)
        if (r[k])
          for (e = 0; e < res_size[k]; ++e)
            for (l = 0; l < RPO_LANES; ++l)
              if (pick[l] == j) RPO_LANE(r[k][e], l) = RPO_LANE(rr[k][e], l);
    }
  }
  return 0;
}

#endif
