/* What the startup code offers the program. */
#ifndef STARTUP_H
#define STARTUP_H

#include <stdint.h>

/* Bytes of stack used since reset: from the top down to the lowest word that lost the
 * paint startup.c put there. */
uint32_t stack_used(void);

/* Copies .data, zeroes .bss, enables the FPU and runs main() (called by reset_handler
 * once the stack is painted). */
void start(void);

#endif
