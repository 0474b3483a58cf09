/* pil_semihost.c -- ARM semihosting calls (see pil_semihost.h). */
#include "pil_semihost.h"

#define SYS_OPEN 0x01u
#define SYS_WRITE 0x05u
#define SYS_READ 0x06u
#define SYS_EXIT_EXTENDED 0x20u
#define ADP_STOPPED_APPLICATION_EXIT 0x20026u

static int32_t g_in = -1;
static int32_t g_out = -1;

static int32_t semihost(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return (int32_t)r0;
}

static int32_t open_tt(uint32_t mode)
{
    /* ":tt" with mode 0 ("r") is the console input, mode 4 ("w") its output */
    static const char name[] = ":tt";
    uint32_t args[3];
    args[0] = (uint32_t)(uintptr_t)name;
    args[1] = mode;
    args[2] = sizeof(name) - 1u;
    return semihost(SYS_OPEN, args);
}

int pil_sh_open_console(void)
{
    g_in = open_tt(0u);
    g_out = open_tt(4u);
    return (g_in < 0 || g_out < 0) ? -1 : 0;
}

int pil_sh_write(const char *buf, uint32_t len)
{
    uint32_t args[3];
    while (len > 0u) {
        int32_t left;
        args[0] = (uint32_t)g_out;
        args[1] = (uint32_t)(uintptr_t)buf;
        args[2] = len;
        left = semihost(SYS_WRITE, args); /* the number of bytes NOT written */
        if (left < 0 || (uint32_t)left >= len) {
            return -1;
        }
        buf += len - (uint32_t)left;
        len = (uint32_t)left;
    }
    return 0;
}

int pil_sh_puts(const char *s)
{
    uint32_t n = 0u;
    while (s[n] != '\0') {
        n++;
    }
    return pil_sh_write(s, n);
}

int32_t pil_sh_read(char *buf, uint32_t len)
{
    uint32_t args[3];
    int32_t left;
    args[0] = (uint32_t)g_in;
    args[1] = (uint32_t)(uintptr_t)buf;
    args[2] = len;
    left = semihost(SYS_READ, args); /* the number of bytes NOT read; len at end of input */
    if (left < 0 || (uint32_t)left > len) {
        return -1;
    }
    return (int32_t)(len - (uint32_t)left);
}

void pil_sh_exit(uint32_t status)
{
    uint32_t args[2];
    args[0] = ADP_STOPPED_APPLICATION_EXIT;
    args[1] = status;
    for (;;) {
        (void)semihost(SYS_EXIT_EXTENDED, args);
    }
}
