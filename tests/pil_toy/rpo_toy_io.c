/* rpo_toy_io.c -- see rpo_toy_io.h. */
#include "rpo_toy_io.h"

void rpo_toy_params_from_array(rpo_toy_params_t *p, const rpo_toy_real_t *a)
{
    p->kp = a[0];
    p->kd = a[1];
    p->ki = a[2];
    p->dt = a[3];
    p->u_max = a[4];
}

void rpo_toy_inputs_from_array(rpo_toy_inputs_t *in, const rpo_toy_real_t *a)
{
    int i;
    for (i = 0; i < 3; i++) {
        in->r[i] = a[i];
        in->v[i] = a[3 + i];
    }
}

void rpo_toy_outputs_to_array(const rpo_toy_outputs_t *out, rpo_toy_real_t *a)
{
    int i;
    for (i = 0; i < 3; i++) {
        a[i] = out->u[i];
    }
    a[3] = out->u_norm;
}

void rpo_toy_state_to_array(const rpo_toy_state_t *s, rpo_toy_real_t *a)
{
    int i;
    for (i = 0; i < 3; i++) {
        a[i] = s->z[i];
    }
    a[3] = s->saturated;
}
