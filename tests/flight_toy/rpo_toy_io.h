/* rpo_toy_io.h -- the toy's structs to and from flat arrays of doubles. */
#ifndef RPO_TOY_IO_H
#define RPO_TOY_IO_H

#include "rpo_toy.h"

#define RPO_TOY_N_IN 6
#define RPO_TOY_N_OUT 4

void rpo_toy_in_from_array(const double a[RPO_TOY_N_IN], rpo_toy_in *in);
void rpo_toy_out_to_array(const rpo_toy_out *out, double a[RPO_TOY_N_OUT]);

#endif
