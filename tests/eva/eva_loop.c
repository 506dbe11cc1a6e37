/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md).  Every public entry point of the general loop
 * (loop.h) and of the loop in real units (device_loop.h), every input unconstrained.
 *
 * eva-modules: loop device_loop
 * eva-support: status coeffs region margin extremes device plant
 * eva-precision: 0
 * eva-options: -eva-domains cvalue,octagon
 * eva-slevel: zw_plant_fail{f}:20,finite_bounded:40,zw_eb_poly_mul_linear:40,check_plant:30,mul_poly:120,all_finite:40,mul_scalar:40,set_power_minus_one:40,loop_build:10,zw_plant_from_coeffs{f}:10,check_spec:50,zero_poly:30,check_bilinear:60,zw_device_normalize{f}:10,normalize:10,check_loop:10,check_gains:10,mul_factor:30,build_parts:10,velocity_estimate:10,zw_loop_lowpass_pole{f}:10,zw_loop_init{f}:10,zw_loop_init_plant{f}:10,zw_device_loop_init_plant{f}:10,zw_loop_carry_gain_rounding{f}:10,zw_loop_poly{f}:10,zw_loop_check{f}:10,zw_loop_is_stable{f}:10,zw_loop_radius_within{f}:10,zw_loop_spectral_radius{f}:10,device_loop_init:10,zw_device_loop_init{f}:10,gains:10,zw_device_loop_check{f}:10,zw_device_loop_is_stable{f}:10,zw_device_loop_radius_within{f}:10,zw_device_loop_spectral_radius{f}:10,k_max:10,zw_device_loop_k_max{f}:10,loop_b_range:10,zw_device_loop_b_range{f}:10,extremes:10,zw_device_loop_extremes_compute{f}:10
 *
 * As eva_ideal.c: a read of a volatile is any value of its type (NaN and infinities
 * included); structs passed in (zw_coeffs, zw_loop_spec, zw_loop, zw_device_loop) have every
 * field any value, so a loop given to a check may have any degree, any spec and garbage
 * coefficients; the workspace holds any contents (loop.h: "needs no initialisation ...
 * any contents (garbage, another loop's) are fine"; the check's rows, roots and
 * radii any values; the limits' part, which loop_limits.c uses (its driver is
 * eva_loop_limits.c), as in static storage); every output is read after the call, and each
 * call is repeated with every pointer independently NULL or valid.
 *
 * device_loop's limits call loop_limits.h (zw_loop_alpha_max, zw_loop_beta_interval,
 * zw_loop_extremes_compute), which another driver covers; here they are analysed against
 * the contracts below, which are what loop_limits.h promises: the outputs written on every
 * return, with any value (the fail-safe rule).
 */
#include <stdbool.h>
#include <stddef.h>

#include "zwidth/device_loop.h"
#include "zwidth/loop.h"
#include "zwidth/loop_limits.h"
#include "../../csrc/src/internal.h" /* zw_routh_hurwitz, the loop's Routh test for box_loop.c */
#include "eva_any.h"

/*@ requires \valid(alpha_max);
    assigns \result, *alpha_max \from indirect:loop, indirect:ws, beta;
    ensures \initialized(alpha_max); */
zw_status zw_loop_alpha_max(const zw_loop *loop, zw_loop_workspace *ws, zw_real beta,
                            zw_real *alpha_max);
/*@ requires \valid(lo) && \valid(hi) && \valid(nonempty);
    assigns \result, *lo, *hi, *nonempty \from indirect:loop, indirect:ws, alpha;
    ensures \initialized(lo) && \initialized(hi) && \initialized(nonempty);
    ensures *nonempty == 0 || *nonempty == 1; */
zw_status zw_loop_beta_interval(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                zw_real *lo, zw_real *hi, bool *nonempty);
/*@ requires \valid(out);
    assigns \result, *out \from indirect:loop, indirect:ws;
    ensures \initialized(&out->alpha_mmax) && \initialized(&out->beta_at_alpha_mmax) &&
            \initialized(&out->alpha_p_max) && \initialized(&out->beta_mmax) &&
            \initialized(&out->beta_mmin); */
zw_status zw_loop_extremes_compute(const zw_loop *loop, zw_loop_workspace *ws,
                                   zw_loop_extremes *out);

static void any_spec(zw_loop_spec *s)
{
    s->delay = any_unsigned_source;
    s->differentiator = (zw_differentiator)any_int_source;
    s->filter = (zw_velocity_filter)any_int_source;
    s->filter_pole = any_real();
    s->average = any_unsigned_source;
}

/* A zw_plant with every field any value (a failed init's, a hand-filled one, garbage). */
static void any_plant(zw_plant *p)
{
    unsigned i;
    p->spec.delta = any_real();
    p->spec.kappa = any_real();
    p->spec.lambda = any_real();
    p->spec.delta_relerr = any_real();
    p->spec.kappa_relerr = any_real();
    p->spec.lambda_relerr = any_real();
    p->order = any_unsigned_source;
    /*@ loop unroll ZW_PLANT_MAX_ORDER + 1u; */
    for (i = 0u; i <= ZW_PLANT_MAX_ORDER; ++i) {
        p->den[i] = any_real();
        p->den_err[i] = any_real();
        p->den_s[i] = any_real();
        p->den_s_err[i] = any_real();
        p->den_w[i] = any_real();
        p->den_w_err[i] = any_real();
    }
    /*@ loop unroll ZW_PLANT_MAX_ORDER; */
    for (i = 0u; i < ZW_PLANT_MAX_ORDER; ++i) {
        p->num[i] = any_real();
        p->num_err[i] = any_real();
        p->num_s[i] = any_real();
        p->num_s_err[i] = any_real();
    }
    any_coeffs(&p->c);
}

static void any_loop(zw_loop *l)
{
    unsigned i;
    any_coeffs(&l->c);
    any_plant(&l->plant);
    any_spec(&l->spec);
    l->degree = any_unsigned_source;
    /*@ loop unroll ZW_LOOP_MAX_DEGREE + 1u; */
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        l->D[i] = any_real();
        l->D_err[i] = any_real();
        l->Na[i] = any_real();
        l->Na_err[i] = any_real();
        l->Nb[i] = any_real();
        l->Nb_err[i] = any_real();
        l->Ds[i] = any_real();
        l->Ds_err[i] = any_real();
        l->Nas[i] = any_real();
        l->Nas_err[i] = any_real();
        l->Nbs[i] = any_real();
        l->Nbs_err[i] = any_real();
    }
    l->alpha_relerr = any_real();
    l->beta_relerr = any_real();
}

/* Every field a successful or failed init leaves defined (the arrays up to the degree). */
static void read_loop(const zw_loop *l)
{
    unsigned i;
    sink_unsigned = l->degree;
    sink_unsigned = l->spec.delay;
    sink_int = (int)l->spec.differentiator;
    sink_int = (int)l->spec.filter;
    sink_real = l->spec.filter_pole;
    sink_unsigned = l->spec.average;
    sink_real = l->c.delta;
    sink_real = l->alpha_relerr;
    sink_real = l->beta_relerr;
    /*@ loop unroll ZW_LOOP_MAX_DEGREE + 1u; */
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        sink_real = l->D[i];
        sink_real = l->D_err[i];
        sink_real = l->Na_err[i];
        sink_real = l->Nbs[i];
        sink_real = l->Nbs_err[i];
    }
}

/* A workspace with any contents (see the header comment). */
static void any_workspace(zw_loop_workspace *ws)
{
    unsigned i;
    /*@ loop unroll ZW_LOOP_MAX_DEGREE + 1u; */
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        ws->row[i] = any_real();
        ws->row_err[i] = any_real();
    }
    /*@ loop unroll ZW_LOOP_MAX_DEGREE; */
    for (i = 0u; i < ZW_LOOP_MAX_DEGREE; ++i) {
        ws->root[i].re = any_real();
        ws->root[i].im = any_real();
        ws->radius[i] = any_real();
    }
    ws->lim_amax = any_real();
    ws->lim_stable = any_bool();
}

static void read_verdict(const zw_loop_verdict *v)
{
    sink_int = v->stable;
    sink_int = v->marginal;
    sink_int = (int)v->deciding;
    sink_real = v->theta;
}

static void drive_pole(void)
{
    zw_real a;
    (void)zw_loop_lowpass_pole(any_real(), any_real(), &a);
    sink_real = a;
    (void)zw_loop_lowpass_pole(any_real(), any_real(), maybe_null(&a));
}

/* The filter kind is split: NONE, LOWPASS, AVERAGE, every negative int (kind -1) and every
 * int above AVERAGE (kind -2), each analysed on its own (together: every spec).  One spec
 * with any kind would merge the AVERAGE case's n in 1..16 with the other kinds' unchecked
 * n, and Eva could not bound the parts' degree; the invalid kinds are two intervals
 * because their union is not one. */
static void any_spec_of_kind(zw_loop_spec *spec, int kind)
{
    int other = any_int_source;
    any_spec(spec);
    if (kind >= 0) {
        spec->filter = (zw_velocity_filter)kind;
    } else if (kind == -1) {
        spec->filter = (zw_velocity_filter)((other < 0) ? other : -1);
    } else {
        spec->filter = (zw_velocity_filter)((other > (int)ZW_VFILTER_AVERAGE) ? other : 3);
    }
}

static void drive_init(int kind)
{
    zw_coeffs c;
    zw_loop_spec spec;
    zw_loop l;
    any_coeffs(&c);
    any_spec_of_kind(&spec, kind);
    (void)zw_loop_init(&l, &c, &spec);
    read_loop(&l);
    (void)zw_loop_carry_gain_rounding(&l, any_real(), any_real());
    read_loop(&l);
    (void)zw_loop_init(maybe_null(&l), maybe_null(&c), maybe_null(&spec));
    (void)zw_loop_carry_gain_rounding(maybe_null(&l), any_real(), any_real());
    {
        static zw_plant plant; /* large: not in this frame */
        any_plant(&plant);
        (void)zw_loop_init_plant(&l, &plant, &spec);
        read_loop(&l);
        (void)zw_loop_init_plant(maybe_null(&l), maybe_null(&plant), maybe_null(&spec));
    }
}

/* loop.c's guarded Routh test as box_loop.c calls it (internal.h): any coefficients and
 * bounds, any degree up to the arrays' (the caller's contract: n + 1 entries). */
static void drive_routh(void)
{
    static zw_real w[ZW_LOOP_MAX_DEGREE + 1u], we[ZW_LOOP_MAX_DEGREE + 1u];
    unsigned i, n = any_unsigned_source;
    /*@ loop unroll ZW_LOOP_MAX_DEGREE + 1u; */
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        w[i] = any_real();
        we[i] = any_real();
    }
    if (n > ZW_LOOP_MAX_DEGREE) {
        n = ZW_LOOP_MAX_DEGREE;
    }
    sink_int = (int)zw_routh_hurwitz(w, we, n);
}

static void drive_checks(void)
{
    static zw_loop l; /* the workspace may keep a pointer to it (the limits' state) */
    static zw_loop_workspace ws_storage;
    zw_loop_workspace *ws = &ws_storage;
    zw_loop_verdict v;
    zw_real p[ZW_LOOP_MAX_DEGREE + 1u], rho, theta;
    unsigned degree, i;
    bool yes;
    any_loop(&l);
    any_workspace(ws);
    (void)zw_loop_poly(&l, any_real(), any_real(), p, &degree);
    sink_unsigned = degree;
    /*@ loop unroll ZW_LOOP_MAX_DEGREE + 1u; */
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        sink_real = p[i];
    }
    (void)zw_loop_check(&l, ws, any_real(), any_real(), &v);
    read_verdict(&v);
    (void)zw_loop_is_stable(&l, ws, any_real(), any_real(), &yes);
    sink_int = yes;
    (void)zw_loop_radius_within(&l, ws, any_real(), any_real(), any_real(), &yes);
    sink_int = yes;
    (void)zw_loop_spectral_radius(&l, ws, any_real(), any_real(), &rho, &theta);
    sink_real = rho;
    sink_real = theta;
    (void)zw_loop_poly(maybe_null(&l), any_real(), any_real(), maybe_null(p), maybe_null(&degree));
    (void)zw_loop_check(maybe_null(&l), maybe_null(ws), any_real(), any_real(), maybe_null(&v));
    (void)zw_loop_is_stable(maybe_null(&l), maybe_null(ws), any_real(), any_real(), maybe_null(&yes));
    (void)zw_loop_radius_within(maybe_null(&l), maybe_null(ws), any_real(), any_real(), any_real(),
                                maybe_null(&yes));
    (void)zw_loop_spectral_radius(maybe_null(&l), maybe_null(ws), any_real(), any_real(),
                                  maybe_null(&rho), maybe_null(&theta));
}

static void any_device_loop(zw_device_loop *dl)
{
    dl->dev.m = any_real();
    dl->dev.b = any_real();
    dl->dev.T = any_real();
    dl->dev.k_scale = any_real();
    dl->dev.b_scale = any_real();
    any_coeffs(&dl->dev.co);
    any_loop(&dl->loop);
    dl->mass_relerr = any_real();
}

static void drive_device_loop_init(int kind)
{
    static zw_device_loop dl; /* large: not in this frame */
    zw_device_loop_spec spec;
    zw_loop_spec ls;
    any_spec_of_kind(&ls, kind);
    spec.delay = ls.delay;
    spec.differentiator = ls.differentiator;
    spec.filter = ls.filter;
    spec.cutoff_hz = any_real();
    spec.pole = ls.filter_pole;
    spec.average = ls.average;
    (void)zw_device_loop_init(&dl, any_real(), any_real(), any_real(), &spec);
    sink_real = dl.dev.m;
    sink_real = dl.dev.k_scale;
    sink_real = dl.dev.co.delta;
    read_loop(&dl.loop);
    (void)zw_device_loop_init(maybe_null(&dl), any_real(), any_real(), any_real(), maybe_null(&spec));
    (void)zw_device_loop_init_plant(&dl, any_real(), any_real(), any_real(), any_real(), any_real(),
                                    any_real(), any_real(), any_real(), &spec);
    sink_real = dl.dev.m;
    sink_real = dl.mass_relerr;
    read_loop(&dl.loop);
    (void)zw_device_loop_init_plant(maybe_null(&dl), any_real(), any_real(), any_real(), any_real(),
                                    any_real(), any_real(), any_real(), any_real(), maybe_null(&spec));
}

static void drive_device_loop(void)
{
    static zw_device_loop dl; /* large: not in this frame */
    static zw_loop_workspace ws_storage;
    zw_loop_workspace *ws = &ws_storage;
    zw_loop_verdict v;
    zw_device_loop_extremes x;
    zw_real rho, theta, k_max, lo, hi;
    bool yes, nonempty;

    any_device_loop(&dl);
    any_workspace(ws);
    (void)zw_device_loop_check(&dl, ws, any_real(), any_real(), &v);
    read_verdict(&v);
    (void)zw_device_loop_is_stable(&dl, ws, any_real(), any_real(), &yes);
    sink_int = yes;
    (void)zw_device_loop_radius_within(&dl, ws, any_real(), any_real(), any_real(), &yes);
    sink_int = yes;
    (void)zw_device_loop_spectral_radius(&dl, ws, any_real(), any_real(), &rho, &theta);
    sink_real = rho;
    sink_real = theta;
    (void)zw_device_loop_k_max(&dl, ws, any_real(), &k_max);
    sink_real = k_max;
    (void)zw_device_loop_b_range(&dl, ws, any_real(), &lo, &hi, &nonempty);
    sink_real = lo;
    sink_real = hi;
    sink_int = nonempty;
    (void)zw_device_loop_extremes_compute(&dl, ws, &x);
    sink_real = x.K_mmax;
    sink_real = x.B_at_K_mmax;
    sink_real = x.K_p_max;
    sink_real = x.B_mmax;
    sink_real = x.B_mmin;

    (void)zw_device_loop_check(maybe_null(&dl), maybe_null(ws), any_real(), any_real(), maybe_null(&v));
    (void)zw_device_loop_is_stable(maybe_null(&dl), maybe_null(ws), any_real(), any_real(),
                                   maybe_null(&yes));
    (void)zw_device_loop_radius_within(maybe_null(&dl), maybe_null(ws), any_real(), any_real(),
                                       any_real(), maybe_null(&yes));
    (void)zw_device_loop_spectral_radius(maybe_null(&dl), maybe_null(ws), any_real(), any_real(),
                                         maybe_null(&rho), maybe_null(&theta));
    (void)zw_device_loop_k_max(maybe_null(&dl), maybe_null(ws), any_real(), maybe_null(&k_max));
    (void)zw_device_loop_b_range(maybe_null(&dl), maybe_null(ws), any_real(), maybe_null(&lo),
                                 maybe_null(&hi), maybe_null(&nonempty));
    (void)zw_device_loop_extremes_compute(maybe_null(&dl), maybe_null(ws), maybe_null(&x));
}

int main(void)
{
    drive_pole();
    drive_init(-1);
    drive_init(-2);
    drive_init((int)ZW_VFILTER_NONE);
    drive_init((int)ZW_VFILTER_LOWPASS);
    drive_init((int)ZW_VFILTER_AVERAGE);
    drive_device_loop_init(-1);
    drive_device_loop_init(-2);
    drive_device_loop_init((int)ZW_VFILTER_NONE);
    drive_device_loop_init((int)ZW_VFILTER_LOWPASS);
    drive_device_loop_init((int)ZW_VFILTER_AVERAGE);
    drive_checks();
    drive_routh();
    drive_device_loop();
    return 0;
}
