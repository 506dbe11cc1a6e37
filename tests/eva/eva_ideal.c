/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): every public entry point of the ideal
 * core's modules, with every input unconstrained.
 *
 * eva-modules: status coeffs region margin extremes device batch selftest portable_math
 * eva-split-return: check_many:0,device_check_many:0,fail_all:0,zw_check_many{f}:0,zw_device_check_many{f}:0
 * eva-slevel: store_block:100,fail_all:100,drive_batch:200
 *
 * A read of a volatile zw_real is any value of the type, NaN and both infinities included
 * (Eva runs with -warn-special-float none: IEEE-754 arithmetic on them is defined and the
 * core relies on it).  Structs passed in (zw_coeffs, zw_device) have every field any value,
 * so they cover what a failed init left, a struct a caller filled by hand, and garbage.
 * Integers (a zw_region, n) are any value of their type where the contract allows it.
 *
 * Each entry point is called twice:
 *   - every pointer valid and every output uninitialized before the call; afterwards every
 *     output is read, so an error path that leaves one unwritten is an Eva alarm (the
 *     fail-safe rule: a caller ignoring the status reads a value, never garbage);
 *   - every pointer independently NULL or valid: no invalid access on any combination.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/batch.h"
#include "zwidth/coeffs.h"
#include "zwidth/device.h"
#include "zwidth/extremes.h"
#include "zwidth/margin.h"
#include "zwidth/portable_math.h"
#include "zwidth/region.h"
#include "zwidth/selftest.h"
#include "zwidth/status.h"
#include "eva_any.h"

volatile float any_float_source;
volatile size_t any_size_source;
volatile ptrdiff_t any_stride_source;

volatile size_t sink_size;
volatile const char *sink_name;

static void any_device(zw_device *d)
{
    d->m = any_real();
    d->b = any_real();
    d->T = any_real();
    d->k_scale = any_real();
    d->b_scale = any_real();
    any_coeffs(&d->co);
}

static void read_verdict(const zw_verdict *v)
{
    sink_int = v->stable;
    sink_int = v->marginal;
    sink_int = (int)v->deciding;
    sink_int = v->violated;
}

static void read_coeffs(const zw_coeffs *c)
{
    sink_real = c->delta;
    sink_real = c->e;
    sink_real = c->c1;
    sink_real = c->c2;
    sink_real = c->d12;
    sink_real = c->s;
    sink_real = c->g;
    sink_real = c->sigma;
    sink_real = c->hs;
    sink_real = c->delta_relerr;
}

static void drive_status(void)
{
    sink_name = zw_status_name((zw_status)any_int_source);
}

static void drive_coeffs(void)
{
    zw_coeffs c;
    zw_real c1, c2, d12;
    (void)zw_coeffs_init(&c, any_real());
    read_coeffs(&c);
    (void)zw_coeffs_init(maybe_null(&c), any_real());
    (void)zw_coeffs_literal(any_real(), &c1, &c2, &d12);
    sink_real = c1;
    sink_real = c2;
    sink_real = d12;
    (void)zw_coeffs_literal(any_real(), maybe_null(&c1), maybe_null(&c2), maybe_null(&d12));
}

static void drive_region(void)
{
    zw_coeffs c;
    zw_verdict v;
    any_coeffs(&c);
    (void)zw_check(&c, any_real(), any_real(), &v);
    read_verdict(&v);
    (void)zw_check_region((zw_region)any_int_source, &c, any_real(), any_real(), &v);
    read_verdict(&v);
    (void)zw_check_proportional(&c, any_real(), &v);
    read_verdict(&v);
    (void)zw_check(maybe_null(&c), any_real(), any_real(), maybe_null(&v));
    (void)zw_check_region((zw_region)any_int_source, maybe_null(&c), any_real(), any_real(),
                          maybe_null(&v));
    (void)zw_check_proportional(maybe_null(&c), any_real(), maybe_null(&v));
}

static void drive_margin(void)
{
    zw_coeffs c;
    zw_real p[4], rho;
    bool within;
    any_coeffs(&c);
    (void)zw_char_poly(&c, any_real(), any_real(), p);
    sink_real = p[0];
    sink_real = p[1];
    sink_real = p[2];
    sink_real = p[3];
    (void)zw_spectral_radius(&c, any_real(), any_real(), &rho);
    sink_real = rho;
    (void)zw_radius_within(&c, any_real(), any_real(), any_real(), &within);
    sink_int = within;
    (void)zw_char_poly(maybe_null(&c), any_real(), any_real(), maybe_null(p));
    (void)zw_spectral_radius(maybe_null(&c), any_real(), any_real(), maybe_null(&rho));
    (void)zw_radius_within(maybe_null(&c), any_real(), any_real(), any_real(), maybe_null(&within));
}

static void drive_extremes(void)
{
    zw_coeffs c;
    zw_extremes x;
    zw_real a, b, lo, hi;
    bool nonempty;
    any_coeffs(&c);
    (void)zw_hyperbola_top(&c, &a, &b);
    sink_real = a;
    sink_real = b;
    (void)zw_corner(&c, &a, &b);
    sink_real = a;
    sink_real = b;
    (void)zw_alpha_max(&c, any_real(), &a);
    sink_real = a;
    (void)zw_beta_interval(&c, any_real(), &lo, &hi, &nonempty);
    sink_real = lo;
    sink_real = hi;
    sink_int = nonempty;
    (void)zw_extremes_compute(&c, &x);
    sink_real = x.alpha_mmax;
    sink_real = x.beta_at_alpha_mmax;
    sink_int = x.at_corner;
    sink_real = x.alpha_p_max;
    sink_real = x.beta_mmax;
    sink_real = x.beta_mmin;
    sink_real = x.alpha_mmin;
    (void)zw_hyperbola_top(maybe_null(&c), maybe_null(&a), maybe_null(&b));
    (void)zw_corner(maybe_null(&c), maybe_null(&a), maybe_null(&b));
    (void)zw_alpha_max(maybe_null(&c), any_real(), maybe_null(&a));
    (void)zw_beta_interval(maybe_null(&c), any_real(), maybe_null(&lo), maybe_null(&hi),
                           maybe_null(&nonempty));
    (void)zw_extremes_compute(maybe_null(&c), maybe_null(&x));
}

static void drive_device(void)
{
    zw_device d, made;
    zw_verdict v;
    zw_device_extremes x;
    zw_influence inf;
    zw_real alpha, beta, rho, k_max, lo, hi;
    bool within, nonempty;

    (void)zw_device_init(&made, any_real(), any_real(), any_real());
    sink_real = made.m;
    sink_real = made.b;
    sink_real = made.T;
    sink_real = made.k_scale;
    sink_real = made.b_scale;
    read_coeffs(&made.co);
    (void)zw_device_init(maybe_null(&made), any_real(), any_real(), any_real());

    any_device(&d);
    (void)zw_device_normalize(&d, any_real(), any_real(), &alpha, &beta);
    sink_real = alpha;
    sink_real = beta;
    (void)zw_device_check(&d, any_real(), any_real(), &v);
    read_verdict(&v);
    (void)zw_device_check_region((zw_region)any_int_source, &d, any_real(), any_real(), &v);
    read_verdict(&v);
    (void)zw_device_spectral_radius(&d, any_real(), any_real(), &rho);
    sink_real = rho;
    (void)zw_device_radius_within(&d, any_real(), any_real(), any_real(), &within);
    sink_int = within;
    (void)zw_device_extremes_compute(&d, &x);
    sink_real = x.K_mmax;
    sink_real = x.B_at_K_mmax;
    sink_int = x.at_corner;
    sink_real = x.K_p_max;
    sink_real = x.B_mmax;
    sink_real = x.B_mmin;
    sink_real = x.K_mmin;
    (void)zw_device_k_max(&d, any_real(), &k_max);
    sink_real = k_max;
    (void)zw_device_b_range(&d, any_real(), &lo, &hi, &nonempty);
    sink_real = lo;
    sink_real = hi;
    sink_int = nonempty;
    (void)zw_device_influence(&d, &inf);
    sink_real = inf.delta;
    sink_real = inf.K_mmax;
    sink_real = inf.B_mmax;
    sink_real = inf.m_K1;
    sink_real = inf.m_K2;
    sink_real = inf.K_mmax_at_m_K2;
    sink_real = inf.K_mmax_at_m_K1;
    sink_real = inf.m_K_match;
    sink_real = inf.T_B;
    sink_real = inf.T_0;
    sink_real = inf.m_0;
    sink_real = inf.m_B;
    sink_real = inf.b_0;
    sink_real = inf.b_BB;
    sink_int = (int)inf.K_vs_m;
    sink_int = (int)inf.K_vs_b;
    sink_int = (int)inf.K_vs_T;
    sink_int = (int)inf.B_vs_m;
    sink_int = (int)inf.B_vs_b;
    sink_int = (int)inf.B_vs_T;
    sink_real = inf.best_m_for_K;

    (void)zw_device_normalize(maybe_null(&d), any_real(), any_real(), maybe_null(&alpha),
                              maybe_null(&beta));
    (void)zw_device_check(maybe_null(&d), any_real(), any_real(), maybe_null(&v));
    (void)zw_device_check_region((zw_region)any_int_source, maybe_null(&d), any_real(),
                                 any_real(), maybe_null(&v));
    (void)zw_device_spectral_radius(maybe_null(&d), any_real(), any_real(), maybe_null(&rho));
    (void)zw_device_radius_within(maybe_null(&d), any_real(), any_real(), any_real(),
                                  maybe_null(&within));
    (void)zw_device_extremes_compute(maybe_null(&d), maybe_null(&x));
    (void)zw_device_k_max(maybe_null(&d), any_real(), maybe_null(&k_max));
    (void)zw_device_b_range(maybe_null(&d), any_real(), maybe_null(&lo), maybe_null(&hi),
                            maybe_null(&nonempty));
    (void)zw_device_influence(maybe_null(&d), maybe_null(&inf));
}

/* The batch calls.  The caller's contract is that alpha and beta hold the n pairs at their
 * strides: the strides range over [0, 2] into arrays of 2 ZW_EVA_PAIRS values, each any
 * value.  n is one of 0 (nothing read or written), 1, 16 (one full block), 17 (a block and
 * one) and ZW_EVA_PAIRS = 40 (two blocks and a part), each analysed on its own, so that Eva
 * can tell which flags a call wrote (a single n over [0, 40] merges them). */
#define ZW_EVA_PAIRS 40u

static void drive_batch(size_t n)
{
    zw_coeffs c;
    zw_device d;
    zw_real x[2u * ZW_EVA_PAIRS], y[2u * ZW_EVA_PAIRS];
    bool stable[ZW_EVA_PAIRS];
    size_t first_invalid, i;
    const ptrdiff_t sx = any_stride_source, sy = any_stride_source;
    zw_status st;
    /*@ loop unroll 2u * ZW_EVA_PAIRS; */
    for (i = 0u; i < 2u * ZW_EVA_PAIRS; ++i) {
        x[i] = any_real();
        y[i] = any_real();
    }
    any_coeffs(&c);
    any_device(&d);
    if ((sx < 0) || (sx > 2) || (sy < 0) || (sy > 2)) {
        return; /* outside the contract */
    }
    st = zw_check_many(&c, n, x, sx, y, sy, stable, &first_invalid);
    /*@ loop unroll ZW_EVA_PAIRS; */
    for (i = 0u; i < n; ++i) {
        sink_int = stable[i];
    }
    if (st != ZW_OK) {
        sink_size = first_invalid;
    }
    st = zw_device_check_many(&d, n, x, sx, y, sy, stable, &first_invalid);
    /*@ loop unroll ZW_EVA_PAIRS; */
    for (i = 0u; i < n; ++i) {
        sink_int = stable[i];
    }
    if (st != ZW_OK) {
        sink_size = first_invalid;
    }
    (void)zw_check_many(maybe_null(&c), n, maybe_null(x), sx, maybe_null(y), sy,
                        maybe_null(stable), maybe_null(&first_invalid));
    (void)zw_device_check_many(maybe_null(&d), n, maybe_null(x), sx, maybe_null(y), sy,
                               maybe_null(stable), maybe_null(&first_invalid));
}

static void drive_selftest(void)
{
    uint_least16_t failed;
    (void)zw_selftest();
    (void)zw_selftest_failures(&failed);
    sink_int = failed;
    (void)zw_selftest_failures(maybe_null(&failed));
}

static void drive_portable_math(void)
{
    sink_real = zw_expm1_portable(any_real());
    sink_real = (zw_real)zw_nextafterf_portable(any_float_source, any_float_source);
}

int main(void)
{
    drive_status();
    drive_coeffs();
    drive_region();
    drive_margin();
    drive_extremes();
    drive_device();
    drive_batch(0u);
    drive_batch(1u);
    drive_batch(16u);
    drive_batch(17u);
    drive_batch(ZW_EVA_PAIRS);
    drive_selftest();
    drive_portable_math();
    return 0;
}
