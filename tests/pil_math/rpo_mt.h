/* rpo_mt.h -- a second test package of the PIL tests: the math functions of rpo_math.h
 * (runtime/csrc, copied in by the test, as an export would ship them) over four inputs. */
#ifndef RPO_MT_H
#define RPO_MT_H
typedef double rpo_mt_real_t;
typedef struct { rpo_mt_real_t k; } rpo_mt_params_t;
typedef struct { rpo_mt_real_t x[4]; } rpo_mt_inputs_t;
typedef struct { rpo_mt_real_t y[12]; } rpo_mt_outputs_t;
typedef struct { rpo_mt_real_t n; } rpo_mt_state_t;
void rpo_mt_initialize(rpo_mt_state_t *s, const rpo_mt_params_t *p);
void rpo_mt_step(rpo_mt_state_t *s, const rpo_mt_params_t *p, const rpo_mt_inputs_t *in, rpo_mt_outputs_t *out);
void rpo_mt_terminate(rpo_mt_state_t *s);
#endif
