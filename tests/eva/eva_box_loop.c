/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): every public entry point of the general
 * loop's box certification (box.h, second part: box_loop.c), every input unconstrained.
 *
 * eva-modules: box_loop
 * eva-support: status coeffs plant plant_box box loop
 * eva-precision: 1
 * eva-split-return: bl_loop_init:0,bl_setup_scratch:0,bl_setup:0,bc_validate_work:0,bc_setup:0
 * eva-options: -eva-domains cvalue,octagon -eva-widening-delay 10
 *
 * As eva_ideal.c: a read of a volatile is any value of its type (NaN and infinities
 * included); the plant box, the spec (any delay, differentiator, cut-off, pole, average;
 * each filter kind analysed apart, any other value included), the gains, the work's budget
 * and tolerance are any values; capacity any value up to the caller's array of
 * ZW_EVA_CELLS cells (the contract: cells holds capacity cells), the cells and the scratch
 * holding any values (box.h: the scratch "needs no initialisation"; left uninitialized,
 * Eva cannot see that each entry is written before it is read: docs/eva.md).  Every output
 * is read after the call, and each call is repeated with every pointer independently NULL
 * or valid.
 *
 * box_loop.c calls the loop in real units (device_loop.h) for its point checks; that module
 * (and loop.c's checks and loop_limits.c under it) is eva_loop.c's, and analysing it inside
 * every search step would take far longer than the budget.  Here it is replaced by the stubs
 * below, which do what device_loop.h promises and nothing more: zw_device_loop_init returns
 * ZW_OK only for a spec zw_loop_init accepts (delay <= ZW_LOOP_MAX_DELAY, a known
 * differentiator and filter, a low-pass pole in [0, 1) when no cut-off is given, an average
 * in 1..ZW_LOOP_MAX_AVERAGE) and may fail on any input; every other stub writes every output
 * on every return, any value on success and the fail-safe value on error (verdict not
 * stable, limit 0, range empty, extremes 0), and returns any status.  The loop workspace is
 * only passed through to them.  zw_loop_lowpass_pole (loop.c), zw_box_validate and
 * zw_box_fold (box.c) and zw_plant_enclose2 (plant_box.c) are the real ones;
 * zw_device_loop_init_plant (the point plant with stiffness) is stubbed as
 * zw_device_loop_init.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/box.h"
#include "zwidth/box_cert.h"
#include "zwidth/device_loop.h"
#include "eva_any.h"

#define ZW_EVA_CELLS 10u

volatile uint_least32_t any_u32_source;
volatile uint_least16_t any_u16_source;
volatile float any_float_source;

volatile uint_least32_t sink_u32;

/* ---- device_loop.h by its contract ------------------------------------------------------ */

static zw_status any_error(void)
{
    return any_bool() ? ZW_ERR_NAN : ZW_ERR_RANGE;
}

static bool spec_accepted(const zw_device_loop_spec *spec)
{
    if (spec->delay > ZW_LOOP_MAX_DELAY) {
        return false;
    }
    if ((spec->differentiator != ZW_DIFF_BACKWARD) && (spec->differentiator != ZW_DIFF_TUSTIN)) {
        return false;
    }
    switch (spec->filter) {
    case ZW_VFILTER_NONE:
        return true;
    case ZW_VFILTER_LOWPASS:
        return !(spec->cutoff_hz == ZW_R(0.0)) ||
               ((spec->pole >= ZW_R(0.0)) && (spec->pole < ZW_R(1.0)));
    case ZW_VFILTER_AVERAGE:
        return (spec->average >= 1u) && (spec->average <= ZW_LOOP_MAX_AVERAGE);
    default:
        return false;
    }
}

zw_status zw_device_loop_init(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                              const zw_device_loop_spec *spec)
{
    (void)m;
    (void)b;
    (void)T;
    if ((out == NULL) || (spec == NULL)) {
        return ZW_ERR_NULL;
    }
    out->loop.degree = 0u; /* what the consumers below look at: not read by box_loop.c */
    if (!spec_accepted(spec)) {
        return ZW_ERR_FILTER;
    }
    if (any_bool()) {
        return any_error();
    }
    return ZW_OK;
}

zw_status zw_device_loop_init_plant(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                                    zw_real k_p, zw_real tau, zw_real m_h, zw_real b_h,
                                    zw_real k_h, const zw_device_loop_spec *spec)
{
    (void)k_p;
    (void)tau;
    (void)m_h;
    (void)b_h;
    (void)k_h;
    return zw_device_loop_init(out, m, b, T, spec);
}

zw_status zw_device_loop_check(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                               zw_real B, zw_loop_verdict *out)
{
    (void)K;
    (void)B;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->deciding = ZW_LOOP_BOUNDARY_NONE;
    out->theta = any_real();
    if ((dl == NULL) || (ws == NULL) || any_bool()) {
        out->stable = false;
        out->marginal = false;
        return (dl == NULL) || (ws == NULL) ? ZW_ERR_NULL : any_error();
    }
    out->stable = any_bool();
    out->marginal = any_bool();
    return ZW_OK;
}

zw_status zw_device_loop_k_max(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real B,
                               zw_real *K_max)
{
    (void)B;
    if (K_max == NULL) {
        return ZW_ERR_NULL;
    }
    if ((dl == NULL) || (ws == NULL) || any_bool()) {
        *K_max = ZW_R(0.0);
        return (dl == NULL) || (ws == NULL) ? ZW_ERR_NULL : any_error();
    }
    *K_max = any_real();
    return ZW_OK;
}

zw_status zw_device_loop_b_range(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                                 zw_real *B_lo, zw_real *B_hi, bool *nonempty)
{
    (void)K;
    if ((B_lo == NULL) || (B_hi == NULL) || (nonempty == NULL)) {
        return ZW_ERR_NULL;
    }
    if ((dl == NULL) || (ws == NULL) || any_bool()) {
        *B_lo = ZW_R(0.0);
        *B_hi = ZW_R(0.0);
        *nonempty = false;
        return (dl == NULL) || (ws == NULL) ? ZW_ERR_NULL : any_error();
    }
    *B_lo = any_real();
    *B_hi = any_real();
    *nonempty = any_bool();
    return ZW_OK;
}

zw_status zw_device_loop_extremes_compute(const zw_device_loop *dl, zw_loop_workspace *ws,
                                          zw_device_loop_extremes *out)
{
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    if ((dl == NULL) || (ws == NULL) || any_bool()) {
        out->K_mmax = ZW_R(0.0);
        out->B_at_K_mmax = ZW_R(0.0);
        out->K_p_max = ZW_R(0.0);
        out->B_mmax = ZW_R(0.0);
        out->B_mmin = ZW_R(0.0);
        return (dl == NULL) || (ws == NULL) ? ZW_ERR_NULL : any_error();
    }
    out->K_mmax = any_real();
    out->B_at_K_mmax = any_real();
    out->K_p_max = any_real();
    out->B_mmax = any_real();
    out->B_mmin = any_real();
    return ZW_OK;
}

/* ---- the driver --------------------------------------------------------------------------- */

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

/* Any contents (box.h: the scratch needs no initialisation; each entry is written before it
 * is read, but at a degree Eva knows only as an interval those writes are weak updates:
 * docs/eva.md). */
static void any_scratch(zw_box_loop_scratch *sc)
{
    unsigned i, k;
    /*@ loop unroll ZW_LOOP_MAX_AVERAGE + 1u; */
    for (i = 0u; i <= ZW_LOOP_MAX_AVERAGE; ++i) {
        sc->dvs[i].lo = any_real();
        sc->dvs[i].hi = any_real();
        sc->nvs[i].lo = any_real();
        sc->nvs[i].hi = any_real();
    }
    /*@ loop unroll 3; */
    for (k = 0u; k < 3u; ++k) {
        /*@ loop unroll ZW_LOOP_MAX_DEGREE + 2u; */
        for (i = 0u; i < ZW_LOOP_MAX_DEGREE + 2u; ++i) {
            sc->poly[k][i].lo = any_real();
            sc->poly[k][i].hi = any_real();
        }
    }
    /*@ loop unroll ZW_LOOP_MAX_DEGREE + 1u; */
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        sc->row[i] = any_real();
        sc->row_err[i] = any_real();
    }
}

/* A spec with the given filter kind and every other field any value.  The kinds are analysed
 * apart: merged, Eva loses the relation between the kind and the average that the
 * validation establishes (an average of 1..16 only for AVERAGE). */
static void any_spec(zw_device_loop_spec *s, zw_velocity_filter filter)
{
    s->delay = any_unsigned_source;
    s->differentiator = (zw_differentiator)any_int_source;
    s->filter = filter;
    s->cutoff_hz = any_real();
    s->pole = any_real();
    s->average = any_unsigned_source;
}

/* A certificate holding any values (box_cert.h: the drive must refuse whatever is wrong). */
static void any_cert(zw_box_cert *c)
{
    unsigned i;
    c->n_steps = any_u16_source;
    c->n_nodes = any_u16_source;
    /*@ loop unroll ZW_BOX_CERT_MAX_STEPS + 1u; */
    for (i = 0u; i <= ZW_BOX_CERT_MAX_STEPS; ++i) {
        c->B[i] = any_float_source;
    }
    /*@ loop unroll ZW_BOX_CERT_MAX_STEPS; */
    for (i = 0u; i < ZW_BOX_CERT_MAX_STEPS; ++i) {
        c->K[i] = any_float_source;
    }
    /*@ loop unroll ZW_BOX_CERT_NODE_WORDS; */
    for (i = 0u; i < ZW_BOX_CERT_NODE_WORDS; ++i) {
        c->nodes[i] = any_u16_source;
    }
}

/* The certificates' functions: verify with any certificate and a work whose capacity is any
 * value up to its stack's; build with any arguments; the lookups on any certificate. */
static void drive_cert(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_loop_workspace *ws,
                       zw_box_loop_scratch *scratch)
{
    zw_box_loop_cell cells[ZW_BOX_CERT_STACK];
    zw_box_loop_work work;
    zw_box_cert cert;
    zw_box_cert_report report;
    zw_box_cert_fault fault;
    uint_least32_t leaves;
    float K, B, lo, hi;
    bool flag;
    unsigned i;
    /*@ loop unroll ZW_BOX_CERT_STACK; */
    for (i = 0u; i < ZW_BOX_CERT_STACK; ++i) {
        cells[i].m_lo = any_real();
        cells[i].m_hi = any_real();
        cells[i].b_lo = any_real();
        cells[i].b_hi = any_real();
        cells[i].K_lo = any_real();
        cells[i].K_hi = any_real();
        cells[i].B_lo = any_real();
        cells[i].B_hi = any_real();
        cells[i].k_lo = any_real();
        cells[i].k_hi = any_real();
    }
    work.cells = cells;
    work.scratch = scratch;
    work.capacity = any_u32_source;
    if (work.capacity > ZW_BOX_CERT_STACK) {
        work.capacity = ZW_BOX_CERT_STACK; /* the contract: cells holds capacity cells */
    }
    work.max_evals = any_u32_source;
    work.rel_tol = any_real();
    any_cert(&cert);
    (void)zw_box_cert_verify(box, spec, &cert, &work, &fault, &leaves);
    sink_int = (int)fault;
    sink_u32 = leaves;
    zw_box_cert_level(&cert, any_float_source, &K, &flag);
    sink_real = (zw_real)K;
    sink_int = flag;
    zw_box_cert_b_range(&cert, any_float_source, any_float_source, &lo, &hi, &flag);
    sink_real = (zw_real)lo;
    sink_real = (zw_real)hi;
    sink_int = flag;
    zw_box_cert_k_mmax(&cert, &K, &B);
    sink_real = (zw_real)K;
    sink_real = (zw_real)B;
    (void)zw_box_cert_build(box, spec, ws, any_float_source, any_float_source, any_unsigned_source,
                            any_unsigned_source, any_real(), &work, &cert, &report);
    sink_u32 = report.tests;
    sink_u32 = report.leaves;
    sink_unsigned = report.failed_step;
    sink_real = report.K_upper[0];
    sink_unsigned = cert.n_steps;
    sink_unsigned = cert.n_nodes;
    (void)zw_box_cert_verify(maybe_null(box), maybe_null(spec), maybe_null(&cert), maybe_null(&work),
                             maybe_null(&fault), maybe_null(&leaves));
    zw_box_cert_level(maybe_null(&cert), any_float_source, maybe_null(&K), maybe_null(&flag));
    zw_box_cert_b_range(maybe_null(&cert), any_float_source, any_float_source, maybe_null(&lo), maybe_null(&hi),
                        maybe_null(&flag));
    zw_box_cert_k_mmax(maybe_null(&cert), maybe_null(&K), maybe_null(&B));
    (void)zw_box_cert_build(maybe_null(box), maybe_null(spec), maybe_null(ws), any_float_source,
                            any_float_source, any_unsigned_source, any_unsigned_source, any_real(),
                            maybe_null(&work), maybe_null(&cert), maybe_null(&report));
}

/* Every public function, first with every pointer valid (every output read after the
 * call), then with every pointer independently NULL or valid. */
static void drive(zw_velocity_filter filter)
{
    zw_box_loop_cell cells[ZW_EVA_CELLS];
    zw_box_loop_scratch scratch;
    zw_loop_workspace ws;
    zw_plant_box box;
    zw_device_loop_spec spec;
    zw_box_loop_work work;
    zw_box_loop_verdict verdict;
    zw_box_loop_bound bound;
    zw_box_loop_extremes x;
    zw_real lo, hi;
    bool nonempty;
    uint_least32_t capacity = any_u32_source;
    unsigned i;

    /*@ loop unroll ZW_EVA_CELLS; */
    for (i = 0u; i < ZW_EVA_CELLS; ++i) {
        cells[i].m_lo = any_real();
        cells[i].m_hi = any_real();
        cells[i].b_lo = any_real();
        cells[i].b_hi = any_real();
        cells[i].K_lo = any_real();
        cells[i].K_hi = any_real();
        cells[i].B_lo = any_real();
        cells[i].B_hi = any_real();
        cells[i].k_lo = any_real();
        cells[i].k_hi = any_real();
    }
    any_scratch(&scratch);
    if (capacity > ZW_EVA_CELLS) {
        capacity = ZW_EVA_CELLS; /* the contract: cells holds capacity cells */
    }
    if (zw_box_loop_work_init(&work, cells, capacity, &scratch) == ZW_OK) {
        /* no fail-safe output (a work, not a verdict or limit): read on success only */
        sink_u32 = work.capacity;
        sink_u32 = work.max_evals;
        sink_real = work.rel_tol;
    }
    (void)zw_box_loop_work_init(maybe_null(&work), maybe_null(cells), capacity,
                                maybe_null(&scratch));
    work.cells = maybe_null(cells);
    work.scratch = maybe_null(&scratch);
    work.capacity = capacity;
    work.max_evals = any_u32_source;
    work.rel_tol = any_real();

    any_box(&box);
    any_spec(&spec, filter);

    (void)zw_box_loop_check(&box, &spec, &ws, any_real(), any_real(), &work, &verdict);
    sink_int = verdict.stable;
    sink_int = verdict.decided;
    sink_real = verdict.m_worst;
    sink_real = verdict.b_worst;
    sink_u32 = verdict.evals;
    sink_real = verdict.k_worst;

    (void)zw_box_loop_k_max(&box, &spec, &ws, any_real(), &work, &bound);
    sink_real = bound.K_lower;
    sink_real = bound.K_upper;
    sink_real = bound.m_worst;
    sink_real = bound.b_worst;
    sink_u32 = bound.evals;
    sink_int = bound.converged;
    sink_real = bound.k_worst;

    (void)zw_box_loop_b_range(&box, &spec, &ws, any_real(), &work, &lo, &hi, &nonempty);
    sink_real = lo;
    sink_real = hi;
    sink_int = nonempty;

    (void)zw_box_loop_k_mmax(&box, &spec, &ws, &work, &x);
    sink_real = x.K_mmax;
    sink_real = x.B_at;
    sink_real = x.K_upper_at;
    sink_real = x.m_worst;
    sink_real = x.b_worst;
    sink_u32 = x.evals;
    sink_int = x.converged;
    sink_real = x.k_worst;

    (void)zw_box_loop_check(maybe_null(&box), maybe_null(&spec), maybe_null(&ws), any_real(),
                            any_real(), maybe_null(&work), maybe_null(&verdict));
    (void)zw_box_loop_k_max(maybe_null(&box), maybe_null(&spec), maybe_null(&ws), any_real(),
                            maybe_null(&work), maybe_null(&bound));
    (void)zw_box_loop_b_range(maybe_null(&box), maybe_null(&spec), maybe_null(&ws), any_real(),
                              maybe_null(&work), maybe_null(&lo), maybe_null(&hi),
                              maybe_null(&nonempty));
    (void)zw_box_loop_k_mmax(maybe_null(&box), maybe_null(&spec), maybe_null(&ws),
                             maybe_null(&work), maybe_null(&x));
    drive_cert(&box, &spec, &ws, &scratch);
}

int main(void)
{
    int other = any_int_source;
    drive(ZW_VFILTER_NONE);
    drive(ZW_VFILTER_LOWPASS);
    drive(ZW_VFILTER_AVERAGE);
    /* any other value: refused (below and above the enum's range, apart as intervals) */
    if (other < (int)ZW_VFILTER_NONE) {
        drive((zw_velocity_filter)other);
    } else if (other > (int)ZW_VFILTER_AVERAGE) {
        drive((zw_velocity_filter)other);
    }
    return 0;
}
