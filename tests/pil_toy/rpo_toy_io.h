/* rpo_toy_io.h -- flat-array converters of the toy package (the order of the struct fields). */
#ifndef RPO_TOY_IO_H
#define RPO_TOY_IO_H

#include "rpo_toy.h"

#define RPO_TOY_N_PARAMS 5
#define RPO_TOY_N_INPUTS 6
#define RPO_TOY_N_OUTPUTS 4
#define RPO_TOY_N_STATE 4

void rpo_toy_params_from_array(rpo_toy_params_t *p, const rpo_toy_real_t *a);
void rpo_toy_inputs_from_array(rpo_toy_inputs_t *in, const rpo_toy_real_t *a);
void rpo_toy_outputs_to_array(const rpo_toy_outputs_t *out, rpo_toy_real_t *a);
void rpo_toy_state_to_array(const rpo_toy_state_t *s, rpo_toy_real_t *a);

#endif
