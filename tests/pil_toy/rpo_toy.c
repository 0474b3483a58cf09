/* rpo_toy.c -- the toy PID law (see rpo_toy.h). */
#include <string.h>

#include "rpo_toy.h"
#include "rpo_toy_math.h"

void rpo_toy_initialize(rpo_toy_state_t *state, const rpo_toy_params_t *params)
{
    (void)params;
    memset(state, 0, sizeof *state);
}

void rpo_toy_step(rpo_toy_state_t *state, const rpo_toy_params_t *params, const rpo_toy_inputs_t *in,
                  rpo_toy_outputs_t *out)
{
    rpo_toy_real_t u[3];
    int i;
    for (i = 0; i < 3; i++) {
        state->z[i] = state->z[i] + params->dt * in->r[i];
        u[i] = -(params->kp * in->r[i] + params->kd * in->v[i] + params->ki * state->z[i]);
    }
    out->u_norm = rpo_toy_saturate_norm(u, params->u_max, out->u);
    state->saturated = out->u_norm < rpo_toy_norm3(u) ? (rpo_toy_real_t)1 : (rpo_toy_real_t)0;
}

void rpo_toy_terminate(rpo_toy_state_t *state)
{
    (void)state;
}
