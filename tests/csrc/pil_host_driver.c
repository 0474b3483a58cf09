/* pil_host_driver.c -- the host reference of the PIL tests (tests/test_flight_target.py): the same
 * controller package compiled for the host (gcc -ffp-contract=off), driven with the lines of the
 * PIL protocol on stdin, without the counters:
 *   P <params hex>  -> INIT <state hex>
 *   S <inputs hex>  -> STEP <outputs hex> <state hex>
 * It includes the same pil_adapter.h as the firmware (rpo.runtime.flight.build.adapter_header). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pil_adapter.h"

#if PIL_REAL_BYTES == 8
typedef uint64_t bits_t;
#else
typedef uint32_t bits_t;
#endif

#define MAXV 256

static pil_params_t params;
static pil_state_t state;
static pil_inputs_t inputs;
static pil_outputs_t outputs;
static pil_real_t values[MAXV];

static int parse(char *line, int n)
{
    char *p = line + 1;
    int i;
    for (i = 0; i < n; i++) {
        char *end;
        bits_t b = (bits_t)strtoull(p, &end, 16);
        if (end == p) {
            return -1;
        }
        memcpy(&values[i], &b, sizeof b);
        p = end;
    }
    return 0;
}

static void put(int n)
{
    int i;
    for (i = 0; i < n; i++) {
        bits_t b;
        memcpy(&b, &values[i], sizeof b);
        printf(" %0*llx", 2 * PIL_REAL_BYTES, (unsigned long long)b);
    }
}

int main(void)
{
    static char line[16 * MAXV + 16];
    while (fgets(line, sizeof line, stdin) != NULL) {
        if (line[0] == 'P' && parse(line, PIL_N_PARAMS) == 0) {
            pil_params_from_array(&params, values);
            pil_initialize(&state, &params);
            pil_state_to_array(&state, values);
            printf("INIT");
            put(PIL_N_STATE);
        } else if (line[0] == 'S' && parse(line, PIL_N_INPUTS) == 0) {
            pil_inputs_from_array(&inputs, values);
            pil_step(&state, &params, &inputs, &outputs);
            printf("STEP");
            pil_outputs_to_array(&outputs, values);
            put(PIL_N_OUTPUTS);
            pil_state_to_array(&state, values);
            put(PIL_N_STATE);
        } else {
            fprintf(stderr, "bad line: %s", line);
            return 2;
        }
        printf("\n");
    }
    return 0;
}
