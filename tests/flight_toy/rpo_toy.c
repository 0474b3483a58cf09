/* rpo_toy.c -- the toy controller: one step of a PD law with a saturation. */
#include <math.h>

#include "rpo_toy.h"
#include "rpo_toy_math.h"

#define RPO_TOY_N_GAINS 4

/* the gain schedule: breakpoints of the range [m] and the gains there */
static const double rpo_toy_range_bp[RPO_TOY_N_GAINS] = {0.0, 10.0, 100.0, 1000.0};
static const double rpo_toy_kp_table[RPO_TOY_N_GAINS] = {0.8, 0.5, 0.2, 0.05};

static const double rpo_toy_kd = 2.0;     /* [N s/m] */
static const double rpo_toy_ki = 0.001;   /* [N/(m s)] */
static const double rpo_toy_umax = 1.5;   /* [N] per axis */
static const double rpo_toy_dt = 0.1;     /* [s] */

/* the proportional gain at the range r (linear between breakpoints, held outside) */
static double rpo_toy_kp(double r)
{
    double kp = rpo_toy_kp_table[RPO_TOY_N_GAINS - 1];
    int i;
    for (i = 0; i < (RPO_TOY_N_GAINS - 1); i++) {
        if (r < rpo_toy_range_bp[i + 1]) {
            double w = (r - rpo_toy_range_bp[i]) / (rpo_toy_range_bp[i + 1] - rpo_toy_range_bp[i]);
            kp = rpo_toy_kp_table[i] + (w * (rpo_toy_kp_table[i + 1] - rpo_toy_kp_table[i]));
            break;
        }
    }
    return kp;
}

void rpo_toy_initialize(rpo_toy_state *state)
{
    state->range_integral = 0.0;
}

void rpo_toy_step(rpo_toy_state *state, const rpo_toy_in *in, rpo_toy_out *out)
{
    const double r = sqrt(rpo_toy_sq(in->pos_err[0]) + rpo_toy_sq(in->pos_err[1]) + rpo_toy_sq(in->pos_err[2]));
    const double kp = rpo_toy_kp(r);
    const double bias = rpo_toy_ki * state->range_integral;
    int k;
    for (k = 0; k < 3; k++) {
        const double u = -((kp * in->pos_err[k]) + (rpo_toy_kd * in->vel_err[k]))
                         - (bias * rpo_toy_sign(in->pos_err[k]));
        out->force[k] = rpo_toy_sat(u, rpo_toy_umax);
    }
    out->bearing = atan2(in->pos_err[1], in->pos_err[0]);
    state->range_integral += rpo_toy_dt * r;
}

void rpo_toy_terminate(rpo_toy_state *state)
{
    state->range_integral = 0.0;
}
