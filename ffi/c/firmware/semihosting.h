/* Output and exit through the debugger's semihosting (QEMU: -semihosting-config
 * enable=on): no C library needed. */
#ifndef SEMIHOSTING_H
#define SEMIHOSTING_H

#include <stdint.h>

/* Semihosting call `op` with argument block `arg`. */
static inline int32_t semihosting_call(int32_t op, const void *arg) {
    register int32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

/* Writes the NUL-terminated `text` to the debugger's console (SYS_WRITE0). */
static inline void semihosting_write(const char *text) { semihosting_call(0x04, text); }

/* Ends the program (SYS_EXIT): QEMU exits with 0 for a `code` of 0
 * (ADP_Stopped_ApplicationExit), 1 otherwise (ADP_Stopped_RunTimeErrorUnknown). */
static inline void semihosting_exit(int code) {
    semihosting_call(0x18, (const void *)(uintptr_t)(code == 0 ? 0x20026 : 0x20023));
    for (;;) __asm__ volatile("wfi");
}

#endif
