/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* tests/mcu/fpenv_main.c - zw_selftest on a Cortex-M4F (QEMU mps2-an386), under the
 * FPSCR modes an integrator may leave set: default (round to nearest, gradual underflow),
 * flush-to-zero (FPSCR.FZ) and round toward zero (FPSCR.RMode = RZ).  Prints one line per
 * mode, "<mode> (what FLT_MIN/2 gave) <status name> 0x<failed bits>"; tools/fpenv_m4f.sh builds it with several
 * flag sets and checks the lines.  Reuses the report image's start-up and linker script. */
#include <stdint.h>

#include "semihost.h"
#include "zwidth/selftest.h"
#include "zwidth/status.h"

static uint32_t get_fpscr(void)
{
    uint32_t v;
    __asm__ volatile("vmrs %0, fpscr" : "=r"(v));
    return v;
}

static void set_fpscr(uint32_t v)
{
    __asm__ volatile("vmsr fpscr, %0" : : "r"(v) : "memory");
}

static void put_line(const char *mode, int flushes, zw_status st, uint_least16_t failed)
{
    static const char hex[] = "0123456789abcdef";
    char bits[5];
    bits[0] = hex[(failed >> 12) & 0xFu];
    bits[1] = hex[(failed >> 8) & 0xFu];
    bits[2] = hex[(failed >> 4) & 0xFu];
    bits[3] = hex[failed & 0xFu];
    bits[4] = '\0';
    semihost_puts(mode);
    semihost_puts(flushes ? " (FLT_MIN/2 -> 0) " : " (FLT_MIN/2 kept) ");
    semihost_puts(zw_status_name(st));
    semihost_puts(" 0x");
    semihost_puts(bits);
    semihost_puts("\n");
}

static void run(const char *mode, uint32_t fpscr)
{
    const uint32_t saved = get_fpscr();
    volatile float tiny = 1.17549435e-38f; /* FLT_MIN */
    float half;
    uint_least16_t failed = 0u;
    zw_status st;
    set_fpscr(fpscr);
    half = tiny * 0.5f; /* shows the mode really is in force */
    st = zw_selftest_failures(&failed);
    set_fpscr(saved);
    put_line(mode, half == 0.0f, st, failed);
}

int main(void)
{
    const uint32_t base = get_fpscr() & ~((3u << 22) | (1u << 24)); /* RMode = RN, FZ = 0 */
    run("default", base);
    run("flush-to-zero", base | (1u << 24));  /* FPSCR.FZ */
    run("round-to-zero", base | (3u << 22));  /* FPSCR.RMode = RZ */
    semihost_puts("fpenv done\n");
    return 0;
}
