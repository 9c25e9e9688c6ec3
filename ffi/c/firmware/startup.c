/* Reset and fault handling for the C example firmware on a Cortex-M4F: the vector table,
 * .data copied, .bss zeroed and the stack painted, the FPU enabled, then main(); its
 * return value is the exit code given to the debugger (QEMU) through semihosting. */
#include <stdint.h>

#include "semihosting.h"
#include "startup.h"

extern uint32_t _data_start, _data_end, _data_load, _bss_start, _bss_end, _stack_top;

int main(void);

/* What the stack's unused words hold. */
#define STACK_PAINT 0xCCCCCCCCu

uint32_t stack_used(void) {
    uint32_t *word = &_bss_end;
    while (word < &_stack_top && *word == STACK_PAINT) word++;
    return (uint32_t)((uintptr_t)&_stack_top - (uintptr_t)word);
}

__attribute__((naked)) void reset_handler(void) {
    /* Paints the stack from the end of .bss up to the top in assembly, before any C code
     * uses it, then runs start(). */
    __asm volatile(
        "ldr r0, =_bss_end\n"
        "ldr r1, =_stack_top\n"
        "ldr r2, =0xCCCCCCCC\n"
        "1: cmp r0, r1\n"
        "bhs 2f\n"
        "str r2, [r0], #4\n"
        "b 1b\n"
        "2: b start\n");
}

void start(void) {
    uint32_t *from = &_data_load;
    for (uint32_t *to = &_data_start; to < &_data_end;) *to++ = *from++;
    /* .bss lies below the painted stack: zero it, not the paint. */
    for (uint32_t *to = &_bss_start; to < &_bss_end;) *to++ = 0;
    /* Full access to the FPU's coprocessors CP10 and CP11 (CPACR). */
    *(volatile uint32_t *)0xE000ED88 |= 0xFu << 20;
    __asm volatile("dsb\n isb");
    semihosting_exit(main());
}

/* A fault: report it and exit with failure. */
static void fault_handler(void) {
    semihosting_write("fault\n");
    semihosting_exit(1);
}

/* The initial stack pointer and the handlers: reset, NMI, hard fault, memory management,
 * bus and usage faults; no interrupt is enabled. */
__attribute__((section(".vectors"), used)) static void (*const vectors[])(void) = {
    (void (*)(void))&_stack_top, reset_handler, fault_handler, fault_handler,
    fault_handler, fault_handler, fault_handler,
};
