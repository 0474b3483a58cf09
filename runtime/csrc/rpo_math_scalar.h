/* rpo_math_scalar.h -- make scalar C code call rpo_math.h instead of libm.
 *
 * Use:  gcc -ffp-contract=off -include rpo_math_scalar.h file.c
 * <math.h> is included FIRST, so its declarations are seen before the macros below; the code's
 * own later #include <math.h> is then a no-op (include guard), and its calls sin(a), atan2(a, b)
 * ... expand to rpo_sin(a), rpo_atan2(a, b) ...: the same functions, bit for bit, as the lockstep
 * (RPO_LANES > 1) build of rpo_math.h.  sqrt, floor, ceil, fabs stay libm's: they are exact
 * (correctly rounded or exact by definition), so libm gives the same bits.
 */
#ifndef RPO_MATH_SCALAR_H
#define RPO_MATH_SCALAR_H
#include <math.h>
#undef RPO_LANES
#define RPO_LANES 1
#include "rpo_math.h"

#define sin(x) rpo_sin(x)
#define cos(x) rpo_cos(x)
#define tan(x) rpo_tan(x)
#define exp(x) rpo_exp(x)
#define log(x) rpo_log(x)
#define atan(x) rpo_atan(x)
#define atan2(y, x) rpo_atan2((y), (x))
#define asin(x) rpo_asin(x)
#define acos(x) rpo_acos(x)
#define sinh(x) rpo_sinh(x)
#define cosh(x) rpo_cosh(x)
#define tanh(x) rpo_tanh(x)
#define fmin(a, b) rpo_fmin((a), (b))
#define fmax(a, b) rpo_fmax((a), (b))
#endif
