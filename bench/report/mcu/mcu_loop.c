/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/report/mcu/mcu_loop.c - the general loop's calls on QEMU mps2-an386, counted.
 *
 * Built by bench/report/loop_section.py like mcu_main.c (the flags of tools/footprint.sh,
 * float core), against mcu_loop_data.c (rows: loop spec, alpha, beta).  For every row:
 * zw_loop_init (when the spec changes), zw_loop_is_stable and zw_loop_check, each between
 * two calls of report_marker(), for QEMU's one-instruction-per-block trace (the counting
 * method of mcu.py).  Then the same calibration block of 605 instructions.
 */
#include <stdint.h>

#include "counting.h"
#include "semihost.h"
#include "zwidth/zwidth.h"

extern const unsigned long mcu_loop_n_rows;
extern const unsigned mcu_loop_spec[][5]; /* delay, differentiator, filter, average, new loop */
extern const zw_real mcu_loop_gains[][4]; /* delta, alpha, beta, low-pass pole */

static zw_loop g_loop; /* large: static, as a drive keeps it */
static zw_loop_workspace g_ws; /* the checks' scratch (loop.h), off the stack */

int main(void)
{
    unsigned long i;
    uint32_t acc = 0u;
    zw_coeffs c;
    for (i = 0; i < mcu_loop_n_rows; ++i) {
        const unsigned *s = mcu_loop_spec[i];
        const zw_real *g = mcu_loop_gains[i];
        zw_loop_verdict v;
        bool fast = false;
        zw_status st = ZW_OK;
        if (s[4] != 0u) {
            zw_loop_spec spec;
            spec.delay = s[0];
            spec.differentiator = (zw_differentiator)s[1];
            spec.filter = (zw_velocity_filter)s[2];
            spec.filter_pole = g[3];
            spec.average = s[3];
            st |= zw_coeffs_init(&c, g[0]);
            report_marker();
            st |= zw_loop_init(&g_loop, &c, &spec);
        }
        report_marker();
        st |= zw_loop_is_stable(&g_loop, &g_ws, g[1], g[2], &fast);
        report_marker();
        st |= zw_loop_check(&g_loop, &g_ws, g[1], g[2], &v);
        acc += (uint32_t)st + (uint32_t)fast + (uint32_t)v.stable;
        if (fast != v.stable || st != ZW_OK) semihost_puts("mismatch\n");
    }
    report_count_done(acc);
    return 0;
}
