/* rpo_toy.h -- a hand-made toy flight package (tests/test_flight_checks.py checks it).
 *
 * A PD law on the relative position with a saturation, one integrator state (the integral of the
 * range) and a gain table scheduled on the range.  Shaped like an `rpo export` package: structs,
 * rpo_toy_initialize / rpo_toy_step / rpo_toy_terminate, no heap, no I/O, no mutable globals.
 */
#ifndef RPO_TOY_H
#define RPO_TOY_H

/* the inputs of one step [m, m/s] */
typedef struct {
    double pos_err[3];
    double vel_err[3];
} rpo_toy_in;

/* the outputs of one step: the commanded force [N] and the bearing of the error [rad] */
typedef struct {
    double force[3];
    double bearing;
} rpo_toy_out;

/* the controller's state: the integral of the range [m s] */
typedef struct {
    double range_integral;
} rpo_toy_state;

void rpo_toy_initialize(rpo_toy_state *state);
void rpo_toy_step(rpo_toy_state *state, const rpo_toy_in *in, rpo_toy_out *out);
void rpo_toy_terminate(rpo_toy_state *state);

#endif
