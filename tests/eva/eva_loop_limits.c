/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): every public entry point of the general
 * loop's limits (loop_limits.h) with every input unconstrained.
 *
 * eva-modules: loop_limits
 * eva-support: status
 * eva-precision: 0
 * eva-options: -eva-domains cvalue,octagon
 * eva-slevel: plant_init:10,beta_walk:10,clear_set:10,walk_begin:10,clear_extremes:10,zw_loop_alpha_max{f}:10,zw_loop_beta_intervals{f}:10,zw_loop_beta_interval{f}:10,zw_loop_extremes_compute{f}:10,zw_loop_boundary_point{f}:10,zw_loop_boundary_line{f}:10
 *
 * As eva_loop.c: a read of a volatile is any value of its type (NaN and infinities
 * included); the zw_loop passed in has every field any value (a failed init, a struct
 * filled by hand, garbage: any degree, spec, plant, coefficients), so it covers every loop
 * zw_loop_init and zw_loop_init_plant build; the workspace holds any contents (loop.h:
 * "needs no initialisation"): its numbers any values, its flags false or true, its
 * pointers NULL (static storage).  Every output is uninitialized before the call and read
 * after it (the fail-safe rule), and each call is repeated with every pointer
 * independently NULL or valid.
 *
 * The guarded checks the limits run (zw_loop_check, zw_loop_is_stable) are eva_loop.c's
 * (no run-time error for any loop and any workspace contents, every output written); here
 * they are analysed against the contracts below: the verdict written on every return,
 * and of the workspace only the check's part (its rows, roots, radii and the factored
 * evaluation's state), never the limits' lim_* fields (docs/eva.md: shown by the outputs
 * Eva computes for them in eva_loop.c).
 */
#include <stdbool.h>
#include <stddef.h>

#include "zwidth/loop.h"
#include "zwidth/loop_limits.h"
#include "eva_any.h"

/*@ requires \valid(ws) && \valid(out);
    assigns \result, *out, ws->row[0 .. ZW_LOOP_MAX_DEGREE], ws->row_err[0 .. ZW_LOOP_MAX_DEGREE],
            ws->root[0 .. ZW_LOOP_MAX_DEGREE - 1u], ws->radius[0 .. ZW_LOOP_MAX_DEGREE - 1u],
            ws->plant_at[0 .. 5], ws->plant_loop, ws->eval[0 .. 2]
        \from indirect:loop, indirect:*loop, alpha, beta;
    ensures \initialized(out);
    ensures out->stable == 0 || out->stable == 1;
    ensures out->marginal == 0 || out->marginal == 1; */
zw_status zw_loop_check(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                        zw_loop_verdict *out);
/*@ requires \valid(ws) && \valid(stable);
    assigns \result, *stable, ws->row[0 .. ZW_LOOP_MAX_DEGREE], ws->row_err[0 .. ZW_LOOP_MAX_DEGREE],
            ws->root[0 .. ZW_LOOP_MAX_DEGREE - 1u], ws->radius[0 .. ZW_LOOP_MAX_DEGREE - 1u],
            ws->plant_at[0 .. 5], ws->plant_loop, ws->eval[0 .. 2]
        \from indirect:loop, indirect:*loop, alpha, beta;
    ensures \initialized(stable);
    ensures *stable == 0 || *stable == 1; */
zw_status zw_loop_is_stable(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                            bool *stable);

/* Every field any value, the filter kind any int (the known kinds and every other: no
 * split is needed here, unlike eva_loop.c, whose construction of the parts needs the
 * average's bound per kind; this analysis builds no loop). */
static void any_spec(zw_loop_spec *s)
{
    s->delay = any_unsigned_source;
    s->differentiator = (zw_differentiator)any_int_source;
    s->filter = (zw_velocity_filter)any_int_source;
    s->filter_pole = any_real();
    s->average = any_unsigned_source;
}

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

/* A loop with every field any value. */
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

/* A workspace with any contents (see the header). */
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
    ws->lim_plant.one_minus_e = any_real();
    ws->lim_plant.r12 = any_real();
    ws->lim_plant.two_c1 = any_real();
    ws->lim_plant.phase = any_real();
    ws->lim_plant.one_minus_a = any_real();
    ws->lim_plant.eps = any_real();
    ws->lim_plant.grid_h = any_real();
    ws->lim_plant.grid_n = any_unsigned_source;
    ws->lim_plant.general = any_bool();
    ws->lim_plant.stiff = any_bool();
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
    /*@ loop unroll 4; */
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

/* Each entry point with the loop and the workspace each NULL or valid and every output
 * valid, the outputs read afterwards (written on every return, the fail-safe rule); then
 * with one output NULL and the others NULL or valid (each refused before any work: cheap),
 * so that the costly case, every pointer valid, is analysed once. */
static void drive_limits(void)
{
    static zw_loop l; /* large: not in this frame; the workspace keeps a pointer to it */
    static zw_loop_workspace ws_storage;
    zw_loop_workspace *ws = &ws_storage;
    zw_loop_beta_set set;
    zw_loop_extremes x;
    zw_real a, lo, hi, c0, ca, cb;
    bool nonempty;
    unsigned i;
    any_loop(&l);
    any_workspace(ws);
    (void)zw_loop_alpha_max(maybe_null(&l), maybe_null(ws), any_real(), &a);
    sink_real = a;
    (void)zw_loop_beta_intervals(maybe_null(&l), maybe_null(ws), any_real(), &set);
    sink_unsigned = set.count;
    sink_int = set.truncated;
    /*@ loop unroll ZW_LOOP_MAX_INTERVALS; */
    for (i = 0u; i < ZW_LOOP_MAX_INTERVALS; ++i) {
        sink_real = set.lo[i];
        sink_real = set.hi[i];
    }
    (void)zw_loop_beta_interval(maybe_null(&l), maybe_null(ws), any_real(), &lo, &hi, &nonempty);
    sink_real = lo;
    sink_real = hi;
    sink_int = nonempty;
    (void)zw_loop_extremes_compute(maybe_null(&l), maybe_null(ws), &x);
    sink_real = x.alpha_mmax;
    sink_real = x.beta_at_alpha_mmax;
    sink_real = x.alpha_p_max;
    sink_real = x.beta_mmax;
    sink_real = x.beta_mmin;
    (void)zw_loop_boundary_point(maybe_null(&l), any_real(), &a, &lo);
    sink_real = a;
    sink_real = lo;
    (void)zw_loop_boundary_line(maybe_null(&l), (zw_loop_boundary)any_int_source, &c0, &ca, &cb);
    sink_real = c0;
    sink_real = ca;
    sink_real = cb;

    (void)zw_loop_alpha_max(maybe_null(&l), maybe_null(ws), any_real(), NULL);
    (void)zw_loop_beta_intervals(maybe_null(&l), maybe_null(ws), any_real(), NULL);
    (void)zw_loop_beta_interval(maybe_null(&l), maybe_null(ws), any_real(), NULL, maybe_null(&hi),
                                maybe_null(&nonempty));
    (void)zw_loop_beta_interval(maybe_null(&l), maybe_null(ws), any_real(), maybe_null(&lo), NULL,
                                maybe_null(&nonempty));
    (void)zw_loop_beta_interval(maybe_null(&l), maybe_null(ws), any_real(), maybe_null(&lo),
                                maybe_null(&hi), NULL);
    (void)zw_loop_extremes_compute(maybe_null(&l), maybe_null(ws), NULL);
    (void)zw_loop_boundary_point(maybe_null(&l), any_real(), NULL, maybe_null(&lo));
    (void)zw_loop_boundary_point(maybe_null(&l), any_real(), maybe_null(&a), NULL);
    (void)zw_loop_boundary_line(maybe_null(&l), (zw_loop_boundary)any_int_source, NULL,
                                maybe_null(&ca), maybe_null(&cb));
    (void)zw_loop_boundary_line(maybe_null(&l), (zw_loop_boundary)any_int_source, maybe_null(&c0),
                                NULL, maybe_null(&cb));
    (void)zw_loop_boundary_line(maybe_null(&l), (zw_loop_boundary)any_int_source, maybe_null(&c0),
                                maybe_null(&ca), NULL);
}

int main(void)
{
    drive_limits();
    return 0;
}
