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

#endif
