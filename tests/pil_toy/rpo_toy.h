/* rpo_toy.h -- a hand-made toy controller package with the interface of `rpo export` (the PIL
 * tests' package): a 3-axis PID law u = -(kp r + kd v + ki z), z' = r, with its command saturated
 * in norm at u_max.  tests/test_flight_target.py makes the single-precision copy by replacing
 * "double" in the typedef below with "float". */
#ifndef RPO_TOY_H
#define RPO_TOY_H

typedef double rpo_toy_real_t;

typedef struct {
    rpo_toy_real_t kp;
    rpo_toy_real_t kd;
    rpo_toy_real_t ki;
    rpo_toy_real_t dt;
    rpo_toy_real_t u_max;
} rpo_toy_params_t;

typedef struct {
    rpo_toy_real_t r[3];
    rpo_toy_real_t v[3];
} rpo_toy_inputs_t;

typedef struct {
    rpo_toy_real_t u[3];
    rpo_toy_real_t u_norm;
} rpo_toy_outputs_t;

typedef struct {
    rpo_toy_real_t z[3];
    rpo_toy_real_t saturated;
} rpo_toy_state_t;

void rpo_toy_initialize(rpo_toy_state_t *state, const rpo_toy_params_t *params);
void rpo_toy_step(rpo_toy_state_t *state, const rpo_toy_params_t *params, const rpo_toy_inputs_t *in,
                  rpo_toy_outputs_t *out);
void rpo_toy_terminate(rpo_toy_state_t *state);

#endif
