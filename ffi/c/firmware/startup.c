/* Reset and fault handling for the C example firmware on a Cortex-M4F: the vector table,
 * .data copied and .bss zeroed, the FPU enabled, then main(); its return value is the
 * exit code given to the debugger (QEMU) through semihosting. */
#include <stdint.h>

#include "semihosting.h"

extern uint32_t _data_start, _data_end, _data_load, _bss_start, _bss_end, _stack_top;

int main(void);

void reset_handler(void) {
    uint32_t *from = &_data_load;
    for (uint32_t *to = &_data_start; to < &_data_end;) *to++ = *from++;
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
