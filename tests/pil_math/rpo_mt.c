/* rpo_mt.c -- see rpo_mt.h.  rpo_math_scalar.h maps sin ... atan onto rpo's own functions. */
#include "rpo_math_scalar.h"
#include "rpo_mt.h"
void rpo_mt_initialize(rpo_mt_state_t *s, const rpo_mt_params_t *p) { (void)p; s->n = 0; }
void rpo_mt_terminate(rpo_mt_state_t *s) { (void)s; }
void rpo_mt_step(rpo_mt_state_t *s, const rpo_mt_params_t *p, const rpo_mt_inputs_t *in, rpo_mt_outputs_t *out)
{
    double a = in->x[0] * p->k, b = in->x[1], c = in->x[2], d = in->x[3];
    out->y[0] = sin(a); out->y[1] = cos(a); out->y[2] = tan(b); out->y[3] = exp(b);
    out->y[4] = log(fabs(c) + 1e-3); out->y[5] = atan2(c, d); out->y[6] = asin(tanh(d)); out->y[7] = acos(tanh(c));
    out->y[8] = sinh(b); out->y[9] = cosh(b); out->y[10] = expm1(d); out->y[11] = sqrt(fabs(a)) + floor(c) + atan(d);
    s->n = s->n + 1;
}
