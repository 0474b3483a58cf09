/* rpo_mt_io.c -- see rpo_mt_io.h. */
#include "rpo_mt_io.h"
void rpo_mt_params_from_array(rpo_mt_params_t *p, const rpo_mt_real_t *a) { p->k = a[0]; }
void rpo_mt_inputs_from_array(rpo_mt_inputs_t *in, const rpo_mt_real_t *a)
{
    for (int i = 0; i < 4; i++) {
        in->x[i] = a[i];
    }
}
void rpo_mt_outputs_to_array(const rpo_mt_outputs_t *out, rpo_mt_real_t *a)
{
    for (int i = 0; i < 12; i++) {
        a[i] = out->y[i];
    }
}
void rpo_mt_state_to_array(const rpo_mt_state_t *s, rpo_mt_real_t *a) { a[0] = s->n; }
