/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): the sweep module (zwidth/sweep.h), with
 * every input unconstrained.
 *
 * eva-modules: sweep
 * eva-support: status coeffs
 * eva-split-return: sweep_check_many:0,zw_sweep_check_many{f}:0
 * eva-slevel: drive_sweep:200
 * eva-defines: -include tests/eva/eva_sweep_gather.h
 *
 * A read of a volatile zw_real is any value of the type, NaN and both infinities included
 * (eva_any.h).  Each entry point is called with every pointer valid and every output
 * uninitialized before the call (every output is read afterwards: the fail-safe rule), and
 * with every pointer independently NULL or valid.
 *
 * zw_sweep_check_many: the caller's contract is that delta, alpha and beta hold the n
 * points at their strides: the strides range over [0, 2] into arrays of 2 ZW_EVA_POINTS
 * values, each any value.  n is one of 0, 1, 16 (one full block), 17 (a block and one) and
 * ZW_EVA_POINTS = 40 (two blocks and a part), each analysed on its own (as eva_ideal.c's
 * batch calls), so that Eva can tell which flags a call wrote.
 */
#include <stdbool.h>
#include <stddef.h>

#include "zwidth/status.h"
#include "zwidth/sweep.h"
#include "eva_any.h"

#define ZW_EVA_POINTS 40u

/* ZW_SWEEP_GATHER in this analysis (eva_sweep_gather.h): any value, so both the default
 * build's field loop and the vector builds' are analysed. */
volatile int zw_eva_sweep_gather;

volatile ptrdiff_t any_stride_source;
volatile size_t sink_size;

static void read_fields(const zw_sweep_fields *f)
{
    sink_real = f->e;
    sink_real = f->g;
    sink_real = f->hs;
    sink_real = f->d12;
    sink_real = f->sigma;
}

static void drive_fields(void)
{
    zw_sweep_fields f;
    (void)zw_sweep_fields_init(&f, any_real());
    read_fields(&f);
    (void)zw_sweep_fields_init(maybe_null(&f), any_real());
}

static void drive_sweep(size_t n)
{
    zw_real d[2u * ZW_EVA_POINTS], a[2u * ZW_EVA_POINTS], b[2u * ZW_EVA_POINTS];
    bool stable[ZW_EVA_POINTS];
    size_t first_invalid, i;
    const ptrdiff_t sd = any_stride_source, sa = any_stride_source, sb = any_stride_source;
    zw_status st;
    /*@ loop unroll 2u * ZW_EVA_POINTS; */
    for (i = 0u; i < 2u * ZW_EVA_POINTS; ++i) {
        d[i] = any_real();
        a[i] = any_real();
        b[i] = any_real();
    }
    if ((sd < 0) || (sd > 2) || (sa < 0) || (sa > 2) || (sb < 0) || (sb > 2)) {
        return; /* outside the contract */
    }
    st = zw_sweep_check_many(n, d, sd, a, sa, b, sb, stable, &first_invalid);
    /*@ loop unroll ZW_EVA_POINTS; */
    for (i = 0u; i < n; ++i) {
        sink_int = stable[i];
    }
    if (st != ZW_OK) {
        sink_size = first_invalid;
    }
    (void)zw_sweep_check_many(n, maybe_null(d), sd, maybe_null(a), sa, maybe_null(b), sb,
                              maybe_null(stable), maybe_null(&first_invalid));
}

int main(void)
{
    drive_fields();
    drive_sweep(0u);
    drive_sweep(1u);
    drive_sweep(16u);
    drive_sweep(17u);
    drive_sweep(ZW_EVA_POINTS);
    return 0;
}
