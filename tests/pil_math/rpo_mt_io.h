/* rpo_mt_io.h -- flat-array converters of the rpo_mt test package. */
#ifndef RPO_MT_IO_H
#define RPO_MT_IO_H
#include "rpo_mt.h"
#define RPO_MT_N_PARAMS 1
#define RPO_MT_N_INPUTS 4
#define RPO_MT_N_OUTPUTS 12
#define RPO_MT_N_STATE 1
void rpo_mt_params_from_array(rpo_mt_params_t *p, const rpo_mt_real_t *a);
void rpo_mt_inputs_from_array(rpo_mt_inputs_t *in, const rpo_mt_real_t *a);
void rpo_mt_outputs_to_array(const rpo_mt_outputs_t *out, rpo_mt_real_t *a);
void rpo_mt_state_to_array(const rpo_mt_state_t *s, rpo_mt_real_t *a);
#endif
