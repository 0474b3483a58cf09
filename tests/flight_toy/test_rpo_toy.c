/* test_rpo_toy.c -- host test of the toy package (not flight code: it uses stdio).
 *
 * Reads the test vectors (default rpo_toy_vectors.txt, or the file named as the first argument):
 * one step a line, the 6 inputs then the 4 expected outputs; the state runs on from line to line.
 * Exits 0 when every output agrees to 1e-12 (relative, absolute below 1).
 */
#include <math.h>
#include <stdio.h>

#include "rpo_toy.h"
#include "rpo_toy_io.h"

static int close_enough(double got, double want)
{
    const double scale = fmax(1.0, fabs(want));
    return fabs(got - want) <= (1e-12 * scale);
}

int main(int argc, char **argv)
{
    const char *path = (argc > 1) ? argv[1] : "rpo_toy_vectors.txt";
    FILE *f = fopen(path, "r");
    rpo_toy_state state;
    double in_a[RPO_TOY_N_IN];
    double want[RPO_TOY_N_OUT];
    double got[RPO_TOY_N_OUT];
    int lines = 0;
    int bad = 0;
    if (f == NULL) {
        fprintf(stderr, "cannot open %s\n", path);
        return 2;
    }
    rpo_toy_initialize(&state);
    for (;;) {
        rpo_toy_in in;
        rpo_toy_out out;
        int i;
        int n = 0;
        for (i = 0; i < RPO_TOY_N_IN; i++) {
            n += fscanf(f, "%lf", &in_a[i]);
        }
        for (i = 0; i < RPO_TOY_N_OUT; i++) {
            n += fscanf(f, "%lf", &want[i]);
        }
        if (n != (RPO_TOY_N_IN + RPO_TOY_N_OUT)) {
            break;
        }
        rpo_toy_in_from_array(in_a, &in);
        rpo_toy_step(&state, &in, &out);
        rpo_toy_out_to_array(&out, got);
        for (i = 0; i < RPO_TOY_N_OUT; i++) {
            if (!close_enough(got[i], want[i])) {
                fprintf(stderr, "line %d output %d: got %.17g, want %.17g\n", lines + 1, i, got[i], want[i]);
                bad++;
            }
        }
        lines++;
    }
    rpo_toy_terminate(&state);
    (void)fclose(f);
    printf("%d vectors, %d mismatches\n", lines, bad);
    return ((bad == 0) && (lines > 0)) ? 0 : 1;
}
