/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (docs/eva.md, "Pending: the general loop's limits"): every public
 * entry point of the general loop's limits (loop_limits.h), with every input
 * unconstrained, and the loop.h functions they run on (loop.c is counted for coverage by
 * eva_loop.c).  PENDING: not named eva_*.c, so tools/eva.sh does not run it yet (its
 * alarms are not explained); run it with tools/eva.sh --keep tests/eva/pending_loop_limits.c.
 *
 * eva-modules: loop_limits
 * eva-support: status coeffs loop
 * eva-precision: 0
 * eva-options: -eva-domains cvalue,octagon
 * eva-slevel: check_spec:50,zero_poly:30,check_bilinear:60,check_loop:10,check_gains:10,mul_factor:30,build_parts:10,velocity_estimate:10,zw_loop_lowpass_pole{f}:10,zw_loop_init{f}:10,zw_loop_carry_gain_rounding{f}:10,zw_loop_poly{f}:10,zw_loop_check{f}:10,zw_loop_is_stable{f}:10,zw_loop_radius_within{f}:10,zw_loop_spectral_radius{f}:10,plant_init:10,zw_loop_alpha_max{f}:10,zw_loop_beta_intervals{f}:10,zw_loop_beta_interval{f}:10,zw_loop_extremes_compute{f}:10,zw_loop_boundary_point{f}:10,zw_loop_boundary_line{f}:10
 *
 * As in eva_ideal.c: a read of a volatile zw_real is any value of the type, NaN and both
 * infinities included; the structs passed in (zw_coeffs, zw_loop, zw_loop_spec) have every
 * field any value (a failed init, a struct filled by hand, garbage), and so has the
 * workspace (loop.h: it needs no initialisation, any contents are fine): its numbers any
 * values, its flags false or true, its pointers NULL (static storage: a read of one
 * before the call wrote it would be an alarm).  Each entry point is called with every output
 * uninitialized and every output read afterwards (the fail-safe rule), then with every
 * pointer independently NULL or valid.
 */
#include <stdbool.h>
#include <stddef.h>

#include "zwidth/coeffs.h"
#include "zwidth/loop.h"
#include "zwidth/loop_limits.h"
#include "zwidth/status.h"

volatile zw_real any_real_source;
volatile unsigned any_unsigned_source;
volatile int any_int_source;

/* Sinks: every output is read into one of these. */
volatile zw_real sink_real;
volatile int sink_int;

/* The loop and its scratch: static, as a firmware keeps them (about 2 KB in double). */
static zw_loop g_loop;
static zw_loop_workspace g_ws;

static zw_real any_real(void) { return any_real_source; }
static bool any_bool(void) { return any_int_source != 0; }

/* The pointer or NULL, either way. */
#define maybe_null(p) (any_bool() ? (p) : NULL)

static void any_coeffs(zw_coeffs *c)
{
    c->delta = any_real();
    c->e = any_real();
    c->c1 = any_real();
    c->c2 = any_real();
    c->d12 = any_real();
    c->s = any_real();
    c->g = any_real();
    c->sigma = any_real();
    c->hs = any_real();
    c->delta_relerr = any_real();
}

static void any_spec(zw_loop_spec *sp)
{
    sp->delay = any_unsigned_source;
    sp->differentiator = (zw_differentiator)any_int_source;
    sp->filter = (zw_velocity_filter)any_int_source;
    sp->filter_pole = any_real();
    sp->average = any_unsigned_source;
}

/* A loop with every field any value. */
static void any_loop(zw_loop *lp)
{
    unsigned i;
    any_coeffs(&lp->c);
    any_spec(&lp->spec);
    lp->degree = any_unsigned_source;
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        lp->D[i] = any_real();
        lp->D_err[i] = any_real();
        lp->Na[i] = any_real();
        lp->Na_err[i] = any_real();
        lp->Nb[i] = any_real();
        lp->Nb_err[i] = any_real();
        lp->Ds[i] = any_real();
        lp->Ds_err[i] = any_real();
        lp->Nas[i] = any_real();
        lp->Nas_err[i] = any_real();
        lp->Nbs[i] = any_real();
        lp->Nbs_err[i] = any_real();
    }
    lp->alpha_relerr = any_real();
    lp->beta_relerr = any_real();
}

/* A loop as zw_loop_init builds it from any plant and any spec (or the empty loop of its
 * error path). */
static void built_loop(zw_loop *lp)
{
    zw_coeffs c;
    zw_loop_spec sp;
    (void)zw_coeffs_init(&c, any_real());
    any_spec(&sp);
    (void)zw_loop_init(lp, &c, &sp);
}

/* A workspace with any contents (see above). */
static void any_workspace(zw_loop_workspace *ws)
{
    unsigned i;
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        ws->row[i] = any_real();
        ws->row_err[i] = any_real();
    }
    for (i = 0u; i < ZW_LOOP_MAX_DEGREE; ++i) {
        ws->root[i].re = any_real();
        ws->root[i].im = any_real();
        ws->radius[i] = any_real();
    }
    ws->lim_plant.one_minus_e = any_real();
    ws->lim_plant.r12 = any_real();
    ws->lim_plant.two_c1 = any_real();
    ws->lim_plant.phase = any_real();
    ws->lim_plant.one_minus_a = any_real();
    ws->lim_plant.eps = any_real();
    ws->lim_plant.grid_h = any_real();
    ws->lim_plant.grid_n = any_unsigned_source;
    ws->lim_pt.theta = any_real();
    ws->lim_pt.f = any_real();
    ws->lim_pt.f_err = any_real();
    ws->lim_pt.v = any_real();
    ws->lim_pt.v_err = any_real();
    ws->lim_r0.re = any_real();
    ws->lim_r0.im = any_real();
    ws->lim_s.re = any_real();
    ws->lim_s.im = any_real();
    ws->lim_scan.mode = any_unsigned_source;
    ws->lim_scan.take = any_unsigned_source;
    ws->lim_scan.fixed = any_real();
    ws->lim_scan.floor = any_real();
    ws->lim_scan.found = any_bool();
    ws->lim_scan.degenerate = any_bool();
    ws->lim_scan.est = any_real();
    ws->lim_scan.lo = any_real();
    ws->lim_scan.hi = any_real();
    ws->lim_walk.have_prev = any_bool();
    ws->lim_walk.cell = any_bool();
    ws->lim_walk.truncated = any_bool();
    ws->lim_walk.step = any_unsigned_source;
    ws->lim_walk.count = any_unsigned_source;
    ws->lim_walk.i = any_unsigned_source;
    ws->lim_walk.alpha = any_real();
    ws->lim_walk.prev_est = any_real();
    ws->lim_walk.prev_lo = any_real();
    ws->lim_walk.prev_hi = any_real();
    ws->lim_walk.floor = any_real();
    ws->lim_walk.est = any_real();
    ws->lim_walk.lo = any_real();
    ws->lim_walk.hi = any_real();
    ws->lim_walk.mid = any_real();
    for (i = 0u; i < 4u; ++i) {
        ws->lim_walk.cell_lo[i] = any_real();
        ws->lim_walk.cell_hi[i] = any_real();
    }
    ws->lim_walk.outer[0] = any_real();
    ws->lim_walk.outer[1] = any_real();
    ws->lim_ext.bl = any_real();
    ws->lim_ext.bh = any_real();
    ws->lim_ext.w = any_real();
    ws->lim_ext.a = any_real();
    ws->lim_ext.b = any_real();
    ws->lim_ext.c = any_real();
    ws->lim_ext.d = any_real();
    ws->lim_ext.fc = any_real();
    ws->lim_ext.fd = any_real();
    ws->lim_ext.t = any_real();
    ws->lim_ext.best_a = any_real();
    ws->lim_ext.best_b = any_real();
    ws->lim_ext.i = any_unsigned_source;
    ws->lim_ext.ibest = any_unsigned_source;
    ws->lim_ext.it = any_unsigned_source;
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

static void drive_loop(zw_loop *lp)
{
    zw_coeffs c;
    zw_loop_spec sp;
    zw_loop_verdict v;
    zw_real p[ZW_LOOP_MAX_DEGREE + 1u], a, rho, theta;
    unsigned degree, i;
    bool yes;
    (void)zw_loop_lowpass_pole(any_real(), any_real(), &a);
    sink_real = a;
    (void)zw_loop_lowpass_pole(any_real(), any_real(), maybe_null(&a));
    any_coeffs(&c);
    any_spec(&sp);
    (void)zw_loop_init(maybe_null(lp), maybe_null(&c), maybe_null(&sp));
    (void)zw_loop_carry_gain_rounding(maybe_null(lp), any_real(), any_real());
    (void)zw_loop_poly(lp, any_real(), any_real(), p, &degree);
    sink_int = (int)degree;
    for (i = 0u; i <= ZW_LOOP_MAX_DEGREE; ++i) {
        sink_real = p[i];
    }
    (void)zw_loop_poly(maybe_null(lp), any_real(), any_real(), maybe_null(p), maybe_null(&degree));
    (void)zw_loop_check(lp, &g_ws, any_real(), any_real(), &v);
    read_verdict(&v);
    (void)zw_loop_check(maybe_null(lp), maybe_null(&g_ws), any_real(), any_real(), maybe_null(&v));
    (void)zw_loop_is_stable(lp, &g_ws, any_real(), any_real(), &yes);
    sink_int = yes;
    (void)zw_loop_is_stable(maybe_null(lp), maybe_null(&g_ws), any_real(), any_real(), maybe_null(&yes));
    (void)zw_loop_radius_within(lp, &g_ws, any_real(), any_real(), any_real(), &yes);
    sink_int = yes;
    (void)zw_loop_radius_within(maybe_null(lp), maybe_null(&g_ws), any_real(), any_real(), any_real(),
                                maybe_null(&yes));
    (void)zw_loop_spectral_radius(lp, &g_ws, any_real(), any_real(), &rho, &theta);
    sink_real = rho;
    sink_real = theta;
    (void)zw_loop_spectral_radius(maybe_null(lp), maybe_null(&g_ws), any_real(), any_real(),
                                  maybe_null(&rho), maybe_null(&theta));
}

static void drive_limits(const zw_loop *lp)
{
    zw_loop_beta_set set;
    zw_loop_extremes x;
    zw_real a, lo, hi, c0, ca, cb;
    bool nonempty;
    unsigned i;
    (void)zw_loop_alpha_max(lp, &g_ws, any_real(), &a);
    sink_real = a;
    (void)zw_loop_alpha_max(maybe_null(lp), maybe_null(&g_ws), any_real(), maybe_null(&a));
    (void)zw_loop_beta_intervals(lp, &g_ws, any_real(), &set);
    sink_int = (int)set.count;
    sink_int = set.truncated;
    for (i = 0u; i < ZW_LOOP_MAX_INTERVALS; ++i) {
        sink_real = set.lo[i];
        sink_real = set.hi[i];
    }
    (void)zw_loop_beta_intervals(maybe_null(lp), maybe_null(&g_ws), any_real(), maybe_null(&set));
    (void)zw_loop_beta_interval(lp, &g_ws, any_real(), &lo, &hi, &nonempty);
    sink_real = lo;
    sink_real = hi;
    sink_int = nonempty;
    (void)zw_loop_beta_interval(maybe_null(lp), maybe_null(&g_ws), any_real(), maybe_null(&lo),
                                maybe_null(&hi), maybe_null(&nonempty));
    (void)zw_loop_extremes_compute(lp, &g_ws, &x);
    sink_real = x.alpha_mmax;
    sink_real = x.beta_at_alpha_mmax;
    sink_real = x.alpha_p_max;
    sink_real = x.beta_mmax;
    sink_real = x.beta_mmin;
    (void)zw_loop_extremes_compute(maybe_null(lp), maybe_null(&g_ws), maybe_null(&x));
    (void)zw_loop_boundary_point(lp, any_real(), &a, &lo);
    sink_real = a;
    sink_real = lo;
    (void)zw_loop_boundary_point(maybe_null(lp), any_real(), maybe_null(&a), maybe_null(&lo));
    (void)zw_loop_boundary_line(lp, (zw_loop_boundary)any_int_source, &c0, &ca, &cb);
    sink_real = c0;
    sink_real = ca;
    sink_real = cb;
    (void)zw_loop_boundary_line(maybe_null(lp), (zw_loop_boundary)any_int_source, maybe_null(&c0),
                                maybe_null(&ca), maybe_null(&cb));
}

int main(void)
{
    any_loop(&g_loop);
    any_workspace(&g_ws);
    drive_loop(&g_loop);
    drive_limits(&g_loop);
    built_loop(&g_loop);
    drive_limits(&g_loop);
    return 0;
}
