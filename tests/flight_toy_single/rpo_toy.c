/* rpo_toy.c -- the toy controller in single precision: one step of a PD law with a saturation. */
#include <math.h>

#include "rpo_toy.h"

static const float rpo_toy_gains[3] = {0.5F, 2.0F, 0.001F}; /* kp [N/m], kd [N s/m], ki [N/(m s)] */
static const float rpo_toy_umax = 1.5F;                      /* [N] per axis */
static const float rpo_toy_dt = 0.1F;                        /* [s] */

void rpo_toy_initialize(rpo_toy_state *state)
{
    state->range_integral = 0.0F;
}

void rpo_toy_step(rpo_toy_state *state, const rpo_toy_in *in, rpo_toy_out *out)
{
    const float r = sqrtf((in->pos_err[0] * in->pos_err[0]) + (in->pos_err[1] * in->pos_err[1])
                          + (in->pos_err[2] * in->pos_err[2]));
    const float bias = rpo_toy_gains[2] * state->range_integral;
    int k;
    for (k = 0; k < 3; k++) {
        const float s = (in->pos_err[k] < 0.0F) ? -1.0F : 1.0F;
        const float u = -((rpo_toy_gains[0] * in->pos_err[k]) + (rpo_toy_gains[1] * in->vel_err[k])) - (bias * s);
        out->force[k] = fminf(fmaxf(u, -rpo_toy_umax), rpo_toy_umax);
    }
    out->bearing = atan2f(in->pos_err[1], in->pos_err[0]);
    state->range_integral += rpo_toy_dt * r;
}

void rpo_toy_terminate(rpo_toy_state *state)
{
    state->range_integral = 0.0F;
}
