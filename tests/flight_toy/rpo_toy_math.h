/* rpo_toy_math.h -- the toy's own portable math (what an export's math source holds). */
#ifndef RPO_TOY_MATH_H
#define RPO_TOY_MATH_H

/* x clipped to [-limit, limit] (fmin/fmax: IEEE, exact) */
double rpo_toy_sat(double x, double limit);

/* 1.0 for x >= +0, -1.0 for x <= -0 (from the sign bit, so -0.0 gives -1.0) */
double rpo_toy_sign(double x);

static inline double rpo_toy_sq(double x)
{
    return x * x;
}

#endif
