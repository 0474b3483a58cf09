/* test_rpo_toy.c -- a host test program of the toy package: never part of the firmware (it has its
 * own main, so linking it into the PIL firmware would fail). */
#include <stdio.h>

#include "rpo_toy.h"
#include "rpo_toy_io.h"

int main(void)
{
    const rpo_toy_real_t pa[RPO_TOY_N_PARAMS] = {1, 2, 0.1, 0.5, 10};
    const rpo_toy_real_t ia[RPO_TOY_N_INPUTS] = {1, 0, 0, 0, 0, 0};
    rpo_toy_params_t p;
    rpo_toy_inputs_t in;
    rpo_toy_state_t s;
    rpo_toy_outputs_t out;
    rpo_toy_params_from_array(&p, pa);
    rpo_toy_inputs_from_array(&in, ia);
    rpo_toy_initialize(&s, &p);
    rpo_toy_step(&s, &p, &in, &out);
    rpo_toy_terminate(&s);
    printf("u = %g\n", (double)out.u[0]);
    return out.u[0] == -(1.0 + 0.1 * 0.5) ? 0 : 1;
}
