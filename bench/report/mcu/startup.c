/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/report/mcu/startup.c - reset handler, vector table and semihosting for the
 * report's bare-metal Cortex-M4F image on QEMU mps2-an386 (no vendor files: the image
 * needs only a stack, the FPU, .data and .bss). */
#include <stdint.h>

#include "semihost.h"

extern uint32_t _estack, _sidata, _sdata, _edata, _sbss, _ebss;
int main(void);
void Reset_Handler(void);
void Fault_Handler(void);

/* Initial stack pointer, reset, NMI, HardFault, MemManage, BusFault, UsageFault.  Stored
 * as integers: ISO C has no conversion between object and function pointers. */
__attribute__((section(".isr_vector"), used)) const uintptr_t g_vectors[7] = {
    (uintptr_t)&_estack,       (uintptr_t)Reset_Handler, (uintptr_t)Fault_Handler,
    (uintptr_t)Fault_Handler,  (uintptr_t)Fault_Handler, (uintptr_t)Fault_Handler,
    (uintptr_t)Fault_Handler};

int semihost_call(int op, const void *arg)
{
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void semihost_exit(int ok)
{
    /* SYS_EXIT with ADP_Stopped_ApplicationExit (QEMU exits 0) or
     * ADP_Stopped_RunTimeErrorUnknown (QEMU exits 1).  On AArch32 the reason is passed
     * by value in r1. */
    uintptr_t reason = ok ? 0x20026u : 0x20023u;
    (void)semihost_call(0x18, (const void *)reason);
    for (;;) {
    }
}

void semihost_puts(const char *s)
{
    (void)semihost_call(0x04, s); /* SYS_WRITE0: a NUL-terminated string to the console */
}

void Fault_Handler(void)
{
    semihost_puts("FAULT\n");
    semihost_exit(0 /* not ok */);
}

void Reset_Handler(void)
{
    uint32_t *src = &_sidata, *dst;
    /* Full access to CP10 and CP11 (the FPU) before any floating-point instruction. */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    for (dst = &_sdata; dst < &_edata;) *dst++ = *src++;
    for (dst = &_sbss; dst < &_ebss;) *dst++ = 0u;
    semihost_exit(main() == 0);
}
