/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/report/mcu/counting.c - what the instruction counter of bench/report/mcu.py keys on,
 * shared by every counted image (mcu_main.c, mcu_loop.c). */
#include "counting.h"

#include "semihost.h"

static volatile unsigned long g_sink;

/* Called between the measured calls; the counter splits the trace at its entry. */
__attribute__((noinline)) void report_marker(void);
void report_marker(void)
{
    __asm__ volatile("" ::: "memory");
}

/* Calibration: exactly 605 instructions from its first to its last (push, mov, 100 loop
 * iterations of 6 with an IT block and a taken / not-taken branch, a call to a leaf that
 * returns with bx lr, and a return by pop {pc}), the kinds of control flow the measured
 * code uses.  The counter must report 605 for it, or the report says the method failed. */
__attribute__((naked, noinline)) void report_calib_leaf(void);
void report_calib_leaf(void)
{
    __asm__ volatile("bx lr\n");
}

__attribute__((naked, noinline)) void report_calibration(void);
void report_calibration(void)
{
    __asm__ volatile(
        "push {r4, lr}\n\t"
        "movs r4, #100\n"
        "1:\n\t"
        "cmp r0, r0\n\t"
        "ite eq\n\t"
        "moveq r1, #1\n\t"
        "movne r1, #2\n\t"
        "subs r4, #1\n\t"
        "bne 1b\n\t"
        "bl report_calib_leaf\n\t"
        "pop {r4, pc}\n");
}

void report_count_done(unsigned long acc)
{
    report_marker();
    report_calibration();
    report_marker();
    g_sink = acc;
    semihost_puts("count done\n");
}
