/* rpo_toy_io.c -- the toy's structs to and from flat arrays of doubles. */
#include "rpo_toy_io.h"

void rpo_toy_in_from_array(const double a[RPO_TOY_N_IN], rpo_toy_in *in)
{
    in->pos_err[0] = a[0];
    in->pos_err[1] = a[1];
    in->pos_err[2] = a[2];
    in->vel_err[0] = a[3];
    in->vel_err[1] = a[4];
    in->vel_err[2] = a[5];
}

void rpo_toy_out_to_array(const rpo_toy_out *out, double a[RPO_TOY_N_OUT])
{
    a[0] = out->force[0];
    a[1] = out->force[1];
    a[2] = out->force[2];
    a[3] = out->bearing;
}
