/* rpo_toy.h -- the toy flight package in single precision (tests/test_flight_checks.py).
 *
 * The PD law of tests/flight_toy/ in float: what `rpo export --precision single` writes must compile
 * without a warning under -Wconversion -Wdouble-promotion, and use no double arithmetic.
 */
#ifndef RPO_TOY_H
#define RPO_TOY_H

typedef struct {
    float pos_err[3];
    float vel_err[3];
} rpo_toy_in;

typedef struct {
    float force[3];
    float bearing;
} rpo_toy_out;

typedef struct {
    float range_integral;
} rpo_toy_state;

void rpo_toy_initialize(rpo_toy_state *state);
void rpo_toy_step(rpo_toy_state *state, const rpo_toy_in *in, rpo_toy_out *out);
void rpo_toy_terminate(rpo_toy_state *state);

#endif
