/* rpo_toy_math.h -- the toy package's helper functions (a second C file in the package). */
#ifndef RPO_TOY_MATH_H
#define RPO_TOY_MATH_H

#include "rpo_toy.h"

rpo_toy_real_t rpo_toy_norm3(const rpo_toy_real_t *x);
/* y = x scaled down to norm limit if its norm exceeds it; returns the norm of y */
rpo_toy_real_t rpo_toy_saturate_norm(const rpo_toy_real_t *x, rpo_toy_real_t limit, rpo_toy_real_t *y);

#endif
