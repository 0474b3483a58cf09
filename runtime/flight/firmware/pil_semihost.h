/* pil_semihost.h -- the few ARM semihosting calls the PIL harness needs (no newlib rdimon).
 *
 * Semihosting: the target executes `bkpt 0xAB` with the operation in r0 and a pointer to its
 * argument block in r1; QEMU (-semihosting-config enable=on,target=native) performs the call on
 * the host and returns the result in r0.  The console ":tt" is QEMU's own stdin/stdout when no
 * semihosting chardev is given, which is what the Python side (rpo.runtime.flight.target) pipes.
 */
#ifndef PIL_SEMIHOST_H
#define PIL_SEMIHOST_H

#include <stdint.h>

/* Open the console for reading and writing; 0 on success. */
int pil_sh_open_console(void);

/* Write len bytes to the console; 0 on success. */
int pil_sh_write(const char *buf, uint32_t len);

/* Write a NUL-terminated string to the console (one SYS_WRITE call); 0 on success. */
int pil_sh_puts(const char *s);

/* Read up to len bytes from the console: the number read (0 at end of input), or -1 on error. */
int32_t pil_sh_read(char *buf, uint32_t len);

/* Stop the emulator with this exit status (SYS_EXIT_EXTENDED, ADP_Stopped_ApplicationExit). */
void pil_sh_exit(uint32_t status) __attribute__((noreturn));

#endif
