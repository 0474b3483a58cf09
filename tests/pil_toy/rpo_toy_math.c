/* rpo_toy_math.c -- see rpo_toy_math.h. */
#include <math.h>

#include "rpo_toy_math.h"

rpo_toy_real_t rpo_toy_norm3(const rpo_toy_real_t *x)
{
    return (rpo_toy_real_t)sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
}

rpo_toy_real_t rpo_toy_saturate_norm(const rpo_toy_real_t *x, rpo_toy_real_t limit, rpo_toy_real_t *y)
{
    rpo_toy_real_t n = rpo_toy_norm3(x);
    rpo_toy_real_t scale = n > limit ? limit / n : (rpo_toy_real_t)1;
    int i;
    for (i = 0; i < 3; i++) {
        y[i] = x[i] * scale;
    }
    return n * scale;
}
