/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): every public entry point of box
 * certification (box.h), every input unconstrained.
 *
 * eva-modules: box
 * eva-support: status coeffs region margin extremes device
 *
 * As eva_ideal.c: a read of a volatile is any value of its type (NaN and infinities
 * included); the plant box and the gains are any values; the work list is any capacity,
 * any budget and any tolerance over a caller's array of cells holding any values (not
 * left uninitialized: docs/eva.md).  The caller's part of the contract (box.h): cells
 * points to capacity cells; here capacity is any value in [0, ZW_EVA_CELLS] over an array
 * of ZW_EVA_CELLS.  Every output is read after the call, and each call is repeated with
 * every pointer independently NULL or valid.  zw_box_fold's output is read field by field
 * (every path writes the whole folded box, the fail-safe one on error).
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/box.h"
#include "eva_any.h"

#define ZW_EVA_CELLS 8u

volatile uint_least32_t any_u32_source;

volatile uint_least32_t sink_u32;

static void any_box(zw_plant_box *b)
{
    b->m_lo = any_real();
    b->m_hi = any_real();
    b->b_lo = any_real();
    b->b_hi = any_real();
    b->T = any_real();
    b->k_lo = any_real();
    b->k_hi = any_real();
    b->m_h_lo = any_real();
    b->m_h_hi = any_real();
    b->b_h_lo = any_real();
    b->b_h_hi = any_real();
    b->k_h_lo = any_real();
    b->k_h_hi = any_real();
    b->tau_lo = any_real();
    b->tau_hi = any_real();
}

/* Every field of a box, read (an output a path leaves unwritten is an alarm). */
static void read_box(const zw_plant_box *b)
{
    sink_real = b->m_lo;
    sink_real = b->m_hi;
    sink_real = b->b_lo;
    sink_real = b->b_hi;
    sink_real = b->T;
    sink_real = b->k_lo;
    sink_real = b->k_hi;
    sink_real = b->m_h_lo;
    sink_real = b->m_h_hi;
    sink_real = b->b_h_lo;
    sink_real = b->b_h_hi;
    sink_real = b->k_h_lo;
    sink_real = b->k_h_hi;
    sink_real = b->tau_lo;
    sink_real = b->tau_hi;
}

int main(void)
{
    zw_box_cell cells[ZW_EVA_CELLS];
    zw_plant_box box;
    zw_box_work work;
    zw_box_bound bound;
    zw_box_verdict verdict;
    zw_box_extremes x;
    zw_real lo, hi;
    bool nonempty;
    uint_least32_t capacity = any_u32_source;
    unsigned i;

    /* Any contents (the search writes a cell before it reads it, but Eva's domains do not
     * relate "below live" to "written": docs/eva.md) */
    /*@ loop unroll ZW_EVA_CELLS; */
    for (i = 0u; i < ZW_EVA_CELLS; ++i) {
        cells[i].m_lo = any_real();
        cells[i].m_hi = any_real();
        cells[i].b_lo = any_real();
        cells[i].b_hi = any_real();
        cells[i].bound = any_real();
    }

    if (capacity > ZW_EVA_CELLS) {
        capacity = ZW_EVA_CELLS; /* the contract: cells holds capacity cells */
    }
    (void)zw_box_work_init(&work, cells, capacity);
    (void)zw_box_work_init(maybe_null(&work), maybe_null(cells), capacity);
    work.cells = maybe_null(cells);
    work.capacity = capacity;
    work.max_evals = any_u32_source;
    work.rel_tol = any_real();

    any_box(&box);
    (void)zw_box_validate(&box);
    (void)zw_box_validate(maybe_null(&box));
    {
        zw_plant_box folded;
        (void)zw_box_fold(&box, &folded);
        read_box(&folded);
        (void)zw_box_fold(maybe_null(&box), maybe_null(&folded));
    }

    (void)zw_box_k_max(&box, any_real(), &work, &bound);
    sink_real = bound.K_lower;
    sink_real = bound.K_upper;
    sink_real = bound.m_worst;
    sink_real = bound.b_worst;
    sink_u32 = bound.evals;
    sink_int = bound.converged;
    sink_real = bound.k_worst;

    (void)zw_box_check(&box, any_real(), any_real(), &work, &verdict);
    sink_int = verdict.stable;
    sink_int = verdict.decided;
    sink_real = verdict.K_lower;
    sink_real = verdict.m_worst;
    sink_real = verdict.b_worst;

    (void)zw_box_b_range(&box, any_real(), &work, &lo, &hi, &nonempty);
    sink_real = lo;
    sink_real = hi;
    sink_int = nonempty;

    (void)zw_box_k_mmax(&box, &work, &x);
    sink_real = x.K_mmax;
    sink_real = x.B_at;
    sink_real = x.K_upper_at;
    sink_real = x.K_mmax_upper;
    sink_real = x.m_worst;
    sink_real = x.b_worst;
    sink_int = x.converged;

    (void)zw_box_k_max(maybe_null(&box), any_real(), maybe_null(&work), maybe_null(&bound));
    (void)zw_box_check(maybe_null(&box), any_real(), any_real(), maybe_null(&work),
                       maybe_null(&verdict));
    (void)zw_box_b_range(maybe_null(&box), any_real(), maybe_null(&work), maybe_null(&lo),
                         maybe_null(&hi), maybe_null(&nonempty));
    (void)zw_box_k_mmax(maybe_null(&box), maybe_null(&work), maybe_null(&x));
    return 0;
}
