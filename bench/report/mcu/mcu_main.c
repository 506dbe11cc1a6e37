/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/report/mcu/mcu_main.c - the report's bare-metal program for QEMU mps2-an386.
 *
 * Built by bench/report/mcu.py with the flags of tools/footprint.sh (-Os, Cortex-M4F hard
 * FPU, float core), against mcu_data.c, which generate.py writes from the report's point
 * set (the same points the host programs judge, rounded to zw_real).
 *
 * REPORT_MODE_ACCURACY: every point: zw_coeffs_init, zw_check, zw_device_init and
 *   zw_device_k_max; every delta: zw_coeffs_init and zw_extremes_compute.  One line each
 *   on the semihosting console, values as the hexadecimal bytes of zw_real, so that the
 *   host scores what the target computed with the target's libm (newlib).
 * REPORT_MODE_COUNT: the calls to measure, each between two calls of report_marker(), for
 *   QEMU's one-instruction-per-block execution trace (bench/report/mcu.py counts the
 *   executed instructions outside this file's own functions between markers).  Then a
 *   calibration block of known length, the check of the counting method.
 */
#include <stdint.h>
#include <string.h>

#include "counting.h"
#include "semihost.h"
#include "zwidth/zwidth.h"

extern const unsigned long mcu_n_points;
extern const zw_real mcu_points[][3]; /* delta, alpha, beta */
extern const unsigned long mcu_n_deltas;
extern const zw_real mcu_deltas[];
extern const unsigned long mcu_n_count; /* points measured in REPORT_MODE_COUNT */

/* ---- output: one line at a time through SYS_WRITE0 ------------------------------------ */
#if !defined(REPORT_MODE_COUNT)
static char g_line[192];
static unsigned g_len;

static void put_char(char c)
{
    if (g_len + 2 < sizeof g_line) g_line[g_len++] = c;
}

static void put_hex(uint32_t v, int digits)
{
    static const char hex[] = "0123456789abcdef";
    int i;
    for (i = digits - 1; i >= 0; --i) put_char(hex[(v >> (4 * i)) & 0xFu]);
}

/* The bytes of x, most significant first (the target is little-endian). */
static void put_real(zw_real x)
{
    unsigned char b[sizeof(zw_real)];
    int i;
    memcpy(b, &x, sizeof b);
    put_char(' ');
    for (i = (int)sizeof b - 1; i >= 0; --i) put_hex(b[i], 2);
}

static void put_int(uint32_t v)
{
    put_char(' ');
    put_hex(v, 1 + (v > 0xFu) + (v > 0xFFu) + (v > 0xFFFu));
}

static void end_line(void)
{
    g_line[g_len++] = '\n';
    g_line[g_len] = '\0';
    semihost_puts(g_line);
    g_len = 0;
}
#endif

/* ---- instruction counting: report_marker() and report_calibration(), counting.c ---- */

#if defined(REPORT_MODE_COUNT)

int main(void)
{
    unsigned long i;
    uint32_t acc = 0;
    for (i = 0; i < mcu_n_count && i < mcu_n_points; ++i) {
        const zw_real *p = mcu_points[i];
        zw_coeffs c;
        zw_device d;
        zw_verdict v;
        zw_extremes x;
        zw_real k = ZW_R(0.0);
        zw_status st;
        report_marker();
        st = zw_coeffs_init(&c, p[0]);
        report_marker();
        st |= zw_check(&c, p[1], p[2], &v);
        report_marker();
        st |= zw_device_init(&d, ZW_R(1.0), p[0], ZW_R(1.0));
        report_marker();
        st |= zw_device_k_max(&d, p[2], &k);
        report_marker();
        st |= zw_extremes_compute(&c, &x);
        acc += (uint32_t)st + (uint32_t)v.stable + (uint32_t)(k > ZW_R(1.0)) + (uint32_t)(x.alpha_mmax > ZW_R(1.0));
    }
    report_count_done(acc);
    return 0;
}
#else
int main(void)
{
    unsigned long i;
    for (i = 0; i < mcu_n_points; ++i) {
        const zw_real *p = mcu_points[i];
        zw_coeffs c;
        zw_device d;
        zw_verdict v = {false, false, ZW_BOUND_NONE, 0};
        zw_real k = ZW_R(0.0);
        zw_status st = zw_coeffs_init(&c, p[0]), st_k;
        if (st == ZW_OK) st = zw_check(&c, p[1], p[2], &v);
        st_k = zw_device_init(&d, ZW_R(1.0), p[0], ZW_R(1.0));
        if (st_k == ZW_OK) st_k = zw_device_k_max(&d, p[2], &k);
        put_char('P');
        put_int((uint32_t)i);
        put_int((uint32_t)st);
        put_int((uint32_t)v.stable);
        put_int((uint32_t)v.marginal);
        put_int((uint32_t)st_k);
        put_real(k);
        end_line();
    }
    for (i = 0; i < mcu_n_deltas; ++i) {
        zw_coeffs c;
        zw_extremes x;
        zw_status st = zw_coeffs_init(&c, mcu_deltas[i]), st_x = ZW_ERR_ARG;
        if (st != ZW_OK) memset(&c, 0, sizeof c);
        memset(&x, 0, sizeof x);
        if (st == ZW_OK) st_x = zw_extremes_compute(&c, &x);
        put_char('D');
        put_int((uint32_t)i);
        put_int((uint32_t)st);
        put_real(c.e);
        put_real(c.c1);
        put_real(c.c2);
        put_real(c.d12);
        put_int((uint32_t)st_x);
        put_real(x.alpha_mmax);
        put_real(x.beta_at_alpha_mmax);
        put_real(x.alpha_p_max);
        put_real(x.beta_mmax);
        end_line();
    }
    semihost_puts("accuracy done\n");
    return 0;
}
#endif
