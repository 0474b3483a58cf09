/* pil_startup.c -- vector table, reset and fault handlers of the PIL firmware (ARMv7-M: the
 * Cortex-M7 of mps2-an500 and the Cortex-M4F of mps2-an386).
 *
 * The reset handler enables the FPU (CPACR: full access to CP10/CP11) before any floating-point
 * instruction can run, sets FPSCR to IEEE defaults (round to nearest, no flush-to-zero, no
 * default-NaN mode), copies .data, zeroes .bss, enables the separate fault handlers and the trap
 * on integer division by zero, and calls main(); main's return value is the exit status.
 *
 * A fault prints one "ERR fault ..." line (exception number, stacked PC, CFSR, HFSR) on the
 * semihosting console and exits with status 3, so a step that crashes ends the emulator with a
 * message instead of hanging it.
 */
#include <stdint.h>

#include "pil_mps2.h"
#include "pil_semihost.h"

#define PIL_EXIT_FAULT 3u

/* linker symbols (pil_mps2.ld): arrays, as they are addresses, not objects */
extern uint32_t __pil_stack_top[];
extern uint32_t __pil_data_start[];
extern uint32_t __pil_data_end[];
extern uint32_t __pil_data_load[];
extern uint32_t __pil_bss_start[];
extern uint32_t __pil_bss_end[];

int main(void);
void pil_reset(void) __attribute__((noreturn));
void pil_fault(void) __attribute__((naked, noreturn));
void pil_fault_report(const uint32_t *frame) __attribute__((noreturn, used));

typedef void (*pil_vector_t)(void);

/* the 16 system vectors; no interrupt is ever enabled, so no external vector is needed */
__attribute__((section(".pil_vectors"), used)) const pil_vector_t pil_vectors[16] = {
    (pil_vector_t)(uintptr_t)__pil_stack_top,  /* initial SP */
    pil_reset,                                 /* reset */
    pil_fault,                                 /* NMI */
    pil_fault,                                 /* HardFault */
    pil_fault,                                 /* MemManage */
    pil_fault,                                 /* BusFault */
    pil_fault,                                 /* UsageFault */
    0, 0, 0, 0,                                /* reserved */
    pil_fault,                                 /* SVCall */
    pil_fault,                                 /* DebugMonitor */
    0,                                         /* reserved */
    pil_fault,                                 /* PendSV */
    pil_fault,                                 /* SysTick */
};

void pil_reset(void)
{
    uintptr_t dst;
    uintptr_t src;

    PIL_SCB_CPACR |= 0xFu << 20; /* CP10, CP11: full access */
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    __asm__ volatile("vmsr fpscr, %0" : : "r"(0u) : "memory");

    /* word by word through volatile pointers: these loops must not become calls of memcpy/memset */
    for (dst = (uintptr_t)__pil_data_start, src = (uintptr_t)__pil_data_load; dst < (uintptr_t)__pil_data_end;
         dst += 4u, src += 4u) {
        *(volatile uint32_t *)dst = *(const volatile uint32_t *)src;
    }
    for (dst = (uintptr_t)__pil_bss_start; dst < (uintptr_t)__pil_bss_end; dst += 4u) {
        *(volatile uint32_t *)dst = 0u;
    }
    PIL_SCB_SHCSR |= (1u << 16) | (1u << 17) | (1u << 18); /* MemManage, BusFault, UsageFault */
    PIL_SCB_CCR |= 1u << 4;                                /* DIV_0_TRP */
    __asm__ volatile("dsb\n\tisb" ::: "memory");

    pil_sh_exit((uint32_t)main());
}

/* The exception frame is on the MSP (the harness never switches to the PSP). */
void pil_fault(void)
{
    __asm__ volatile("mrs r0, msp\n\t"
                     "b pil_fault_report\n\t");
}

static char *put_hex(char *p, uint32_t v)
{
    int i;
    *p++ = '0';
    *p++ = 'x';
    for (i = 7; i >= 0; i--) {
        *p++ = "0123456789abcdef"[(v >> (4 * i)) & 0xFu];
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

void pil_fault_report(const uint32_t *frame)
{
    char line[128];
    char *p = line;
    uint32_t ipsr;
    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    p = put_str(p, "ERR fault: exception ");
    p = put_hex(p, ipsr & 0x1FFu);
    p = put_str(p, " pc ");
    p = put_hex(p, frame[6]);
    p = put_str(p, " cfsr ");
    p = put_hex(p, PIL_SCB_CFSR);
    p = put_str(p, " hfsr ");
    p = put_hex(p, PIL_SCB_HFSR);
    *p++ = '\n';
    (void)pil_sh_write(line, (uint32_t)(p - line));
    pil_sh_exit(PIL_EXIT_FAULT);
}
