/* rpo_toy_math.c -- the toy's own portable math. */
#include <math.h>

#include "rpo_toy_math.h"

double rpo_toy_sat(double x, double limit)
{
    return fmin(fmax(x, -limit), limit);
}

double rpo_toy_sign(double x)
{
    union {
        double d;
        unsigned long long u;
    } bits;
    bits.d = x;
    return ((bits.u >> 63U) != 0U) ? -1.0 : 1.0;
}
