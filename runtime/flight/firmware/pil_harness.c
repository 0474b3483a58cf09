/* pil_harness.c -- processor-in-the-loop harness: one exported rpo controller package driven one
 * step at a time over ARM semihosting (rpo.runtime.flight.target is the host side).
 *
 * The package is reached only through "pil_adapter.h", which the Python builder writes for each
 * package: it includes the package's headers and maps its prefixed names (rpo_<name>_step, ...)
 * onto the generic ones used here (pil_step, pil_real_t, PIL_N_INPUTS, ...).
 *
 * PROTOCOL (text lines ending in '\n'; every real value is the hexadecimal IEEE bit pattern of the
 * package's real type, 16 digits for double, 8 for float, most significant digit first, as
 * Python's struct.pack('>d', x).hex(); counters are decimal):
 *   target: READY <version> <n_params> <n_inputs> <n_outputs> <n_state> <sizeof real> <stack bytes>
 *   host:   P <params>                 -> target: INIT <state>             (initialize; again: terminate + initialize)
 *   host:   I <inputs>                 -> target: INIT <state>             (start from a measurement, designs
 *                                                                         with rpo_<name>_start only)
 *   host:   S <inputs>                 -> target: STEP <instructions> <stack bytes> <outputs> <state>
 *   host:   C <n>                      -> target: CAL <instructions> <stack bytes>  (known loop, see below)
 *   host:   Q                          -> target: BYE, exit status 0      (terminate if initialized)
 * Values are separated by one space.  Any protocol error (unknown command, wrong count or length
 * of values, a bad hex digit, a step before P, end of input) prints "ERR <message>" and exits with
 * status 2; a fault exits with status 3 (pil_startup.c).
 *
 * INSTRUCTIONS PER STEP.  QEMU runs with -icount shift=PIL_ICOUNT_SHIFT: its virtual clock advances
 * exactly 2^shift ns per guest instruction, whatever the host does, and a device register read
 * sees the clock at that very instruction.  CMSDK timer 0 counts down at 25 MHz (40 ns) of that
 * clock, so with shift 10 (1024 ns per instruction, 25.6 ticks) the instructions between two reads
 * are round(ticks * 40 / 1024): exact, as the ticks are within one of 25.6 per instruction.  The
 * step is called through a function pointer by timed_call(); the same call of an empty function
 * (one `bx lr`) gives the cost of the reads and the call, which is subtracted, so the count is
 * the instructions executed from the step's first instruction to its return, callees included
 * (instructions retired, not cycles: QEMU models no pipeline, cache or memory timing).  At boot
 * the harness checks itself with a loop of known length (pil_calib_loop: 2n + 4 instructions)
 * and refuses to start if the count is not exact (QEMU started without -icount).  The counter
 * restarts before every measurement; a step of more than 2^32 ticks (167,772,160 instructions)
 * is an error, never a wrapped count.
 *
 * STACK BYTES PER STEP.  Before the call, the stack below the current SP (down to the bottom of
 * the stack region, __pil_stack_bottom) is painted with PIL_STACK_PAINT; after it, the lowest
 * word that differs from the paint is the high-water mark; the step's stack bytes are the SP at
 * the call minus that address (0 if nothing was written; timed_call's own frame, measured at boot
 * with the empty function, is subtracted).  A word the step writes with the paint
 * value itself is not seen (an underestimate of at most the words below the lowest other write).
 * If the step writes into the lowest PIL_STACK_GUARD bytes of the region, it may have used more
 * than the region: an error, never a wrong figure (the RAM below the region is unused, so such a
 * step corrupts nothing of the harness).
 */
#include <stdint.h>
#include <string.h>

#include "pil_adapter.h"
#include "pil_mps2.h"
#include "pil_semihost.h"

#define PIL_PROTOCOL_VERSION 1
#define PIL_EXIT_PROTOCOL 2u

#ifndef PIL_ICOUNT_SHIFT
#define PIL_ICOUNT_SHIFT 10
#endif

#define PIL_STACK_PAINT 0xC5A5F00Du
/* the lowest bytes of the stack region: a step that writes there has (nearly) overrun the region */
#define PIL_STACK_GUARD 1024

#define PIL_STR2(x) #x
#define PIL_STR(x) PIL_STR2(x)

#if PIL_REAL_BYTES == 8
typedef uint64_t pil_bits_t;
#elif PIL_REAL_BYTES == 4
typedef uint32_t pil_bits_t;
#else
#error "PIL_REAL_BYTES must be 4 or 8"
#endif
typedef char pil_real_size_check[(sizeof(pil_real_t) == PIL_REAL_BYTES) ? 1 : -1];

#define PIL_HEX (2 * PIL_REAL_BYTES)
#define PIL_MAX2(a, b) ((a) > (b) ? (a) : (b))
/* the longest host line: a command letter and its values, each with a separating space */
#define PIL_LINE_MAX (8 + PIL_MAX2(PIL_N_PARAMS, PIL_N_INPUTS) * (PIL_HEX + 1))
/* the longest target line: STEP, two counters, the outputs and the state */
#define PIL_OUT_MAX (64 + (PIL_N_OUTPUTS + PIL_N_STATE) * (PIL_HEX + 1))

/* linker symbols (pil_mps2.ld): arrays, so that no code assumes they are single objects */
extern uint32_t __pil_stack_bottom[];
extern uint32_t __pil_stack_size[];

typedef void (*pil_step_fn)(pil_state_t *, const pil_params_t *, const pil_inputs_t *, pil_outputs_t *);

void pil_empty_step(pil_state_t *s, const pil_params_t *p, const pil_inputs_t *in, pil_outputs_t *out);
void pil_calib_loop(pil_state_t *s, const pil_params_t *p, const pil_inputs_t *in, pil_outputs_t *out);

/* the loop count of pil_calib_loop (at least 1) */
volatile uint32_t pil_calib_n = 1u;

/* One instruction: the baseline of measure(). */
__attribute__((naked, noinline)) void pil_empty_step(pil_state_t *s, const pil_params_t *p,
                                                     const pil_inputs_t *in, pil_outputs_t *out)
{
    (void)s;
    (void)p;
    (void)in;
    (void)out;
    __asm__ volatile("bx lr\n\t");
}

/* 2 * pil_calib_n + 4 instructions: movw, movt, ldr, n x (subs, bne), bx lr. */
__attribute__((naked, noinline)) void pil_calib_loop(pil_state_t *s, const pil_params_t *p,
                                                     const pil_inputs_t *in, pil_outputs_t *out)
{
    (void)s;
    (void)p;
    (void)in;
    (void)out;
    __asm__ volatile("movw r0, #:lower16:pil_calib_n\n\t"
                     "movt r0, #:upper16:pil_calib_n\n\t"
                     "ldr r0, [r0]\n\t"
                     "1:\n\t"
                     "subs r0, r0, #1\n\t"
                     "bne 1b\n\t"
                     "bx lr\n\t");
}

static pil_params_t g_params;
static pil_state_t g_state;
static pil_inputs_t g_inputs;
static pil_outputs_t g_outputs;
static pil_real_t g_values[PIL_MAX2(PIL_MAX2(PIL_N_PARAMS, PIL_N_INPUTS), PIL_MAX2(PIL_N_OUTPUTS, PIL_N_STATE)) + 1];
static char g_line[PIL_LINE_MAX + 2];
static char g_out[PIL_OUT_MAX];
static char g_rx[256];
static uint32_t g_rx_len;
static uint32_t g_rx_pos;
/* the cost of the reads and the call in timed_call (instructions) and its frame (bytes), from
 * pil_empty_step at boot */
static uint32_t g_overhead;
static uint32_t g_frame;
/* nonzero if the timer passed zero during the last timed_call */
static uint32_t g_wrapped;

static void fail(const char *what, const char *detail) __attribute__((noreturn));

static void fail(const char *what, const char *detail)
{
    (void)pil_sh_puts("ERR ");
    (void)pil_sh_puts(what);
    if (detail != 0) {
        (void)pil_sh_puts(detail);
    }
    (void)pil_sh_puts("\n");
    pil_sh_exit(PIL_EXIT_PROTOCOL);
}

/* ------------------------------------------------------------------ measurement */

static uint32_t ticks_to_instructions(uint32_t ticks)
{
    uint64_t ns = (uint64_t)ticks * PIL_TIMER_NS;
    return (uint32_t)((ns + (1u << PIL_ICOUNT_SHIFT) / 2u) >> PIL_ICOUNT_SHIFT);
}

static uint32_t current_sp(void)
{
    uint32_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* Paint [from, to) (word addresses, from <= to) with PIL_STACK_PAINT.  Inlined, and volatile so that
 * the loops do not become a memset call: a callee's frame would be below the caller's SP, in the
 * region it paints.  Unrolled by 8, as QEMU's cost is mostly per translated block. */
static inline __attribute__((always_inline)) void paint(uint32_t from, uint32_t to)
{
    volatile uint32_t *p = (volatile uint32_t *)from;
    const volatile uint32_t *const end = (const volatile uint32_t *)to;
    while (end - p >= 8) {
        p[0] = PIL_STACK_PAINT;
        p[1] = PIL_STACK_PAINT;
        p[2] = PIL_STACK_PAINT;
        p[3] = PIL_STACK_PAINT;
        p[4] = PIL_STACK_PAINT;
        p[5] = PIL_STACK_PAINT;
        p[6] = PIL_STACK_PAINT;
        p[7] = PIL_STACK_PAINT;
        p += 8;
    }
    while (p < end) {
        *p++ = PIL_STACK_PAINT;
    }
}

/* The address of the lowest word of [from, to) that is not PIL_STACK_PAINT, else to. */
static uint32_t lowest_written(uint32_t from, uint32_t to)
{
    const volatile uint32_t *p = (const volatile uint32_t *)from;
    const volatile uint32_t *const end = (const volatile uint32_t *)to;
    while (end - p >= 8) {
        if (((p[0] ^ PIL_STACK_PAINT) | (p[1] ^ PIL_STACK_PAINT) | (p[2] ^ PIL_STACK_PAINT) |
             (p[3] ^ PIL_STACK_PAINT) | (p[4] ^ PIL_STACK_PAINT) | (p[5] ^ PIL_STACK_PAINT) |
             (p[6] ^ PIL_STACK_PAINT) | (p[7] ^ PIL_STACK_PAINT)) != 0u) {
            break;
        }
        p += 8;
    }
    while (p < end && *p == PIL_STACK_PAINT) {
        p++;
    }
    return (uint32_t)(uintptr_t)p;
}

/* The timer ticks of fn(&g_state, &g_params, &g_inputs, &g_outputs), the reads and the call
 * included.  A function of its own, without loops: every call executes the same instructions
 * around fn, whose count g_overhead holds. */
static __attribute__((noinline)) uint32_t timed_call(pil_step_fn fn)
{
    uint32_t t0;
    uint32_t t1;
    PIL_TIMER_CTRL = 0u;
    PIL_TIMER_RELOAD = 0xFFFFFFFFu;
    PIL_TIMER_VALUE = 0xFFFFFFFFu;
    PIL_TIMER_INTSTATUS = 1u;
    PIL_TIMER_CTRL = 1u;
    t0 = PIL_TIMER_VALUE;
    fn(&g_state, &g_params, &g_inputs, &g_outputs);
    t1 = PIL_TIMER_VALUE;
    g_wrapped = PIL_TIMER_INTSTATUS & 1u;
    return t0 - t1;
}

/* The instructions of fn (its first to its return: the cost of timed_call subtracted), and the
 * bytes it wrote below the SP at its call (timed_call's own frame subtracted). */
static __attribute__((noinline)) uint32_t measure(pil_step_fn fn, uint32_t *stack_bytes)
{
    const uint32_t bottom = (uint32_t)(uintptr_t)__pil_stack_bottom;
    const uint32_t sp = current_sp();
    uint32_t ticks;
    uint32_t low;

    paint(bottom, sp);
    ticks = timed_call(fn);
    low = lowest_written(bottom, sp);
    if (low < bottom + PIL_STACK_GUARD) {
        fail("stack overflow: the step wrote into the lowest " PIL_STR(PIL_STACK_GUARD)
             " bytes of the stack region (build with a larger stack_size)", 0);
    }
    if (g_wrapped != 0u) {
        fail("the step took more than 2^32 timer ticks: the instruction count would wrap", 0);
    }
    *stack_bytes = sp - low - g_frame;
    return ticks_to_instructions(ticks) - g_overhead;
}

static uint32_t calibrate(uint32_t n, uint32_t *stack_bytes)
{
    pil_calib_n = n;
    return measure(pil_calib_loop, stack_bytes);
}

static void self_check(void)
{
    static const uint32_t ns[3] = {1u, 100u, 10000u};
    uint32_t i;
    g_overhead = 0u;
    g_frame = 0u;
    /* pil_empty_step is one instruction and writes nothing */
    g_overhead = measure(pil_empty_step, &g_frame) - 1u;
    for (i = 0u; i < 3u; i++) {
        uint32_t stack;
        if (calibrate(ns[i], &stack) != 2u * ns[i] + 4u || stack != 0u) {
            fail("the instruction count is not exact: run QEMU with -icount shift=" PIL_STR(PIL_ICOUNT_SHIFT), 0);
        }
    }
}

/* ------------------------------------------------------------------ text */

static char *put_u32(char *p, uint32_t v)
{
    char tmp[10];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0) {
        *p++ = tmp[--n];
    }
    return p;
}

static char *put_str(char *p, const char *s)
{
    while (*s != '\0') {
        *p++ = *s++;
    }
    return p;
}

static char *put_values(char *p, const pil_real_t *v, uint32_t n)
{
    uint32_t i;
    for (i = 0u; i < n; i++) {
        pil_bits_t bits;
        int k;
        memcpy(&bits, &v[i], sizeof bits);
        *p++ = ' ';
        for (k = PIL_HEX - 1; k >= 0; k--) {
            *p++ = "0123456789abcdef"[(uint32_t)(bits >> (4 * k)) & 0xFu];
        }
    }
    return p;
}

static void send(char *end)
{
    *end++ = '\n';
    if (pil_sh_write(g_out, (uint32_t)(end - g_out)) != 0) {
        pil_sh_exit(PIL_EXIT_PROTOCOL);
    }
}

/* The next line from the host into g_line, without its '\n' (and a '\r' before it); its length. */
static uint32_t read_line(void)
{
    uint32_t n = 0u;
    for (;;) {
        char c;
        if (g_rx_pos == g_rx_len) {
            int32_t got = pil_sh_read(g_rx, sizeof g_rx);
            if (got <= 0) {
                fail(got == 0 ? "end of input before Q" : "semihosting read failed", 0);
            }
            g_rx_len = (uint32_t)got;
            g_rx_pos = 0u;
        }
        c = g_rx[g_rx_pos++];
        if (c == '\n') {
            break;
        }
        if (n >= PIL_LINE_MAX) {
            fail("line too long", 0);
        }
        g_line[n++] = c;
    }
    if (n > 0u && g_line[n - 1u] == '\r') {
        n--;
    }
    g_line[n] = '\0';
    return n;
}

static int hex_digit(char c)
{
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    return -1;
}

/* n values after the command letter of a line of length len, into g_values */
static void parse_values(uint32_t len, uint32_t n, const char *what)
{
    const char *p = g_line + 1;
    uint32_t i;
    if (len != 1u + n * (PIL_HEX + 1u)) {
        fail(what, ": wrong number of values or digits in the line");
    }
    for (i = 0u; i < n; i++) {
        pil_bits_t bits = 0u;
        int k;
        if (*p++ != ' ') {
            fail(what, ": values must be separated by one space");
        }
        for (k = 0; k < PIL_HEX; k++) {
            int d = hex_digit(*p++);
            if (d < 0) {
                fail(what, ": not a hexadecimal digit");
            }
            bits = (pil_bits_t)((bits << 4) | (pil_bits_t)d);
        }
        memcpy(&g_values[i], &bits, sizeof bits);
    }
}

static uint32_t parse_count(uint32_t len)
{
    uint32_t v = 0u;
    uint32_t i;
    if (len < 3u || len > 11u || g_line[1] != ' ') {
        fail("C: expected one decimal count", 0);
    }
    for (i = 2u; i < len; i++) {
        uint32_t d = (uint32_t)(g_line[i] - '0');
        if (d > 9u || v > 100000000u) {
            fail("C: expected a decimal count from 1 to 100000000", 0);
        }
        v = v * 10u + d;
    }
    if (v < 1u || v > 100000000u) {
        fail("C: expected a decimal count from 1 to 100000000", 0);
    }
    return v;
}

/* ------------------------------------------------------------------ main loop */

int main(void)
{
    int initialized = 0;
    char *p;

    if (pil_sh_open_console() != 0) {
        return 4;
    }
    self_check();

    p = put_str(g_out, "READY ");
    p = put_u32(p, PIL_PROTOCOL_VERSION);
    *p++ = ' ';
    p = put_u32(p, PIL_N_PARAMS);
    *p++ = ' ';
    p = put_u32(p, PIL_N_INPUTS);
    *p++ = ' ';
    p = put_u32(p, PIL_N_OUTPUTS);
    *p++ = ' ';
    p = put_u32(p, PIL_N_STATE);
    *p++ = ' ';
    p = put_u32(p, (uint32_t)sizeof(pil_real_t));
    *p++ = ' ';
    p = put_u32(p, (uint32_t)(uintptr_t)__pil_stack_size);
    send(p);

    for (;;) {
        uint32_t len = read_line();
        uint32_t instructions;
        uint32_t stack;
        char cmd = len > 0u ? g_line[0] : '\0';
        if (len > 1u && g_line[1] != ' ') {
            cmd = '\0';
        }
        switch (cmd) {
        case 'P':
            parse_values(len, PIL_N_PARAMS, "P");
            if (initialized) {
                pil_terminate(&g_state);
            }
            pil_params_from_array(&g_params, g_values);
            pil_initialize(&g_state, &g_params);
            initialized = 1;
            pil_state_to_array(&g_state, g_values);
            p = put_str(g_out, "INIT");
            p = put_values(p, g_values, PIL_N_STATE);
            send(p);
            break;
        case 'S':
            if (!initialized) {
                fail("S before P: send the parameters first", 0);
            }
            parse_values(len, PIL_N_INPUTS, "S");
            pil_inputs_from_array(&g_inputs, g_values);
            instructions = measure(pil_step, &stack);
            p = put_str(g_out, "STEP ");
            p = put_u32(p, instructions);
            *p++ = ' ';
            p = put_u32(p, stack);
            pil_outputs_to_array(&g_outputs, g_values);
            p = put_values(p, g_values, PIL_N_OUTPUTS);
            pil_state_to_array(&g_state, g_values);
            p = put_values(p, g_values, PIL_N_STATE);
            send(p);
            break;
        case 'I':
#ifdef PIL_HAS_START
            if (!initialized) {
                fail("I before P: send the parameters first", 0);
            }
            parse_values(len, PIL_N_INPUTS, "I");
            pil_inputs_from_array(&g_inputs, g_values);
            pil_start(&g_state, &g_params, &g_inputs);
            pil_state_to_array(&g_state, g_values);
            p = put_str(g_out, "INIT");
            p = put_values(p, g_values, PIL_N_STATE);
            send(p);
#else
            fail("I: this package has no start function", 0);
#endif
            break;
        case 'C':
            instructions = calibrate(parse_count(len), &stack);
            p = put_str(g_out, "CAL ");
            p = put_u32(p, instructions);
            *p++ = ' ';
            p = put_u32(p, stack);
            send(p);
            break;
        case 'Q':
            if (len != 1u) {
                fail("Q takes no argument", 0);
            }
            if (initialized) {
                pil_terminate(&g_state);
            }
            p = put_str(g_out, "BYE");
            send(p);
            return 0;
        default:
            fail("unknown command: expected P, I, S, C or Q", 0);
        }
    }
}
