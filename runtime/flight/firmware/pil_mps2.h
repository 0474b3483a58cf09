/* pil_mps2.h -- what the PIL harness uses of QEMU's MPS2 boards mps2-an500 (Cortex-M7) and
 * mps2-an386 (Cortex-M4F).  Both have the same memory map and peripherals at these addresses
 * (QEMU hw/arm/mps2.c): code in ZBT SSRAM1 at 0x00000000 (4 MiB), data in ZBT SSRAM2/3 at
 * 0x20000000 (4 MiB), CMSDK APB timer 0 at 0x40000000 clocked by the 25 MHz system clock.
 */
#ifndef PIL_MPS2_H
#define PIL_MPS2_H

#include <stdint.h>

/* CMSDK APB timer 0: a 32-bit down-counter */
#define PIL_TIMER_CTRL (*(volatile uint32_t *)0x40000000u)
#define PIL_TIMER_VALUE (*(volatile uint32_t *)0x40000004u)
#define PIL_TIMER_RELOAD (*(volatile uint32_t *)0x40000008u)
#define PIL_TIMER_INTSTATUS (*(volatile uint32_t *)0x4000000Cu) /* write 1 to clear */
#define PIL_TIMER_HZ 25000000u
/* the timer's period in ns: an integer for the 25 MHz clock */
#define PIL_TIMER_NS (1000000000u / PIL_TIMER_HZ)

/* System control block (ARMv7-M) */
#define PIL_SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define PIL_SCB_SHCSR (*(volatile uint32_t *)0xE000ED24u)
#define PIL_SCB_CCR (*(volatile uint32_t *)0xE000ED14u)
#define PIL_SCB_CFSR (*(volatile uint32_t *)0xE000ED28u)
#define PIL_SCB_HFSR (*(volatile uint32_t *)0xE000ED2Cu)

#endif
