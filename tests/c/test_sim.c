/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Scene simulation (zwidth/sim.h): each effect on its own against a hand-computed case, the
 * exact step against the closed-form ZOH solution, the RK4 path against the exact one,
 * resumable runs, the verdict criterion, every error path of zw_sim_init, and a linear
 * scene of paper Fig. 15 kind whose simulated verdict agrees with zw_check.
 *
 * Where a test needs a plant that moves at a known constant velocity whatever force acts on
 * it (a kinematic probe of the controller), it uses a huge mass: with m = 2^66 any force
 * below ~2^10 N changes x and v by less than half an ulp, so x_k = x_0 + k T v_0 exactly for
 * dyadic x_0, v_0 and T = 2^-7. */
#include "zw_test.h"

#include <stdlib.h>

#include "zwidth/sim.h"

/* ---- helpers ------------------------------------------------------------------------------ */

#define T_DYADIC R(0.0078125) /* 2^-7 s: t_k = k T and T^2/m exact */

/* Every trace signal, n samples each. */
typedef struct rec {
    size_t n;
    zw_real *t, *x, *v, *x_measured, *force, *force_command, *stiffness, *stiffness_planned,
        *damping, *velocity_estimate, *wall_force, *friction, *hand_force, *hand_target;
    zw_sim_trace tr;
} rec;

/* Every live trace buffer, so that a failed assertion (which leaves the test by longjmp)
 * does not leak them: the teardown frees what the test could not. */
#define MAX_LIVE 64
static zw_real *g_live[MAX_LIVE];

static zw_real *alloc_signal(size_t n)
{
    zw_real *p = malloc((n != 0 ? n : 1) * sizeof *p);
    size_t i;
    assert_non_null(p);
    for (i = 0; i < MAX_LIVE && g_live[i] != NULL; ++i) continue;
    if (i == MAX_LIVE) {
        free(p);
        fail_msg("more than %d live trace buffers", MAX_LIVE);
    }
    g_live[i] = p;
    return p;
}

static void free_signal(zw_real *p)
{
    size_t i;
    for (i = 0; i < MAX_LIVE; ++i)
        if (g_live[i] == p) g_live[i] = NULL;
    free(p);
}

static int free_all(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < MAX_LIVE; ++i) {
        free(g_live[i]);
        g_live[i] = NULL;
    }
    return 0;
}

static void rec_alloc(rec *r, size_t n)
{
    memset(r, 0, sizeof *r);
    r->n = n;
    r->tr.t = r->t = alloc_signal(n);
    r->tr.x = r->x = alloc_signal(n);
    r->tr.v = r->v = alloc_signal(n);
    r->tr.x_measured = r->x_measured = alloc_signal(n);
    r->tr.force = r->force = alloc_signal(n);
    r->tr.force_command = r->force_command = alloc_signal(n);
    r->tr.stiffness = r->stiffness = alloc_signal(n);
    r->tr.stiffness_planned = r->stiffness_planned = alloc_signal(n);
    r->tr.damping = r->damping = alloc_signal(n);
    r->tr.wall_force = r->wall_force = alloc_signal(n);
    r->tr.friction = r->friction = alloc_signal(n);
    r->tr.hand_force = r->hand_force = alloc_signal(n);
    r->tr.hand_target = r->hand_target = alloc_signal(n);
    r->tr.velocity_estimate = r->velocity_estimate = alloc_signal(n);
}

static void rec_free(rec *r)
{
    free_signal(r->t);
    free_signal(r->x);
    free_signal(r->v);
    free_signal(r->x_measured);
    free_signal(r->force);
    free_signal(r->force_command);
    free_signal(r->stiffness);
    free_signal(r->stiffness_planned);
    free_signal(r->damping);
    free_signal(r->wall_force);
    free_signal(r->friction);
    free_signal(r->hand_force);
    free_signal(r->hand_target);
    free_signal(r->velocity_estimate);
    memset(r, 0, sizeof *r);
}

/* Simulate n samples of a scene from t = 0 into *r (allocated here). */
static void simulate(const zw_sim_scene *sc, size_t n, rec *r)
{
    zw_sim sim;
    EXPECT_OK(zw_sim_init(&sim, sc));
    rec_alloc(r, n);
    EXPECT_OK(zw_sim_run(&sim, n, &r->tr));
}

/* A linear scene (no effect) with every effect's parameters zero. */
static zw_sim_scene scene_linear(zw_real m, zw_real b, zw_real T, zw_real K, zw_real B)
{
    zw_sim_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.m = m;
    sc.b = b;
    sc.T = T;
    sc.K = K;
    sc.B = B;
    sc.hand.t_release = (zw_real)INFINITY;
    sc.hand.speed = R(1.0);
    return sc;
}

/* The kinematic probe: x(t) = x0 + v0 t exactly (see the file comment). */
static zw_sim_scene scene_probe(zw_real x0, zw_real v0)
{
    zw_sim_scene sc = scene_linear(ZW_LDEXP(R(1.0), 66), R(0.0), T_DYADIC, R(0.0), R(0.0));
    sc.x_init = x0;
    sc.v_init = v0;
    return sc;
}

static long double max_abs(const zw_real *a, size_t n)
{
    long double m = 0.0L;
    size_t i;
    for (i = 0; i < n; ++i)
        if (fabsl((long double)a[i]) > m) m = fabsl((long double)a[i]);
    return m;
}

/* ---- the exact step ------------------------------------------------------------------------ */

/* One ZOH step of m x'' + b x' = F from (x, v), in long double:
 *   x+ = x + v (1 - e) m/b + (F/b) (T - (1 - e) m/b),   v+ = e v + (1 - e) F/b,  e = exp(-d),
 * d = b T/m, rewritten without dividing by b:  (1 - e) m/b = T p,  (F/b)(T - T p) = (F T^2/m) r
 * with p = (1 - e)/d and r = (1 - p)/d.  For d < 1, r by its series sum (-d)^n/(n+2)! (1 - p
 * cancels there); d = 0 is the limit p = 1, r = 1/2:  x + v T + F T^2/(2m),  v + F T/m. */
static void zoh_reference(long double m, long double b, long double T, long double x,
                          long double v, long double F, long double *x1, long double *v1)
{
    long double d = b * T / m, e = expl(-d), p, r;
    if (d == 0.0L) {
        p = 1.0L;
        r = 0.5L;
    } else {
        p = -expm1l(-d) / d;
        if (d < 1.0L) {
            long double term = 0.5L;
            int n;
            r = 0.0L;
            for (n = 0; n < 40; ++n) {
                r += term;
                term *= -d / (long double)(n + 3);
            }
        } else {
            r = (1.0L - p) / d;
        }
    }
    *x1 = x + v * T * p + F * T * T / m * r;
    *v1 = e * v + F * T / m * p;
}

/* One sample of the linear loop from (x0, v0) under F = K (x_eq - x0) (exact: v_est_0 = 0)
 * equals the closed form within 16 ulps at every delta: from a moving state under 3 (1.5 -
 * 0.25) = 3.75 N, and each part alone (force only, velocity only) so that every coefficient
 * shows at the ulp level.  m = 2^-3, T = 2^-7 and b = 16 delta make delta = b T/m, T^2/m and
 * T/m exact, so the only errors are the coefficients (ZW_COEF_ULPS = 4 ulps <= 8 u each) and
 * ~4 roundings of the step; every term is positive (no cancellation): <= 13 u of the result
 * <= 13 ulps. */
static void test_exact_step_closed_form(void **state)
{
    const zw_real deltas[] = {R(0.0), R(1e-8), R(0.25), R(3.0), R(50.0), R(1e4)};
    const struct {
        zw_real x0, v0, x_eq;
        long double F;
    } starts[] = {{R(0.25), R(0.7), R(1.5), 3.75L},
                  {R(0.0), R(0.0), R(1.25), 3.75L},
                  {R(0.0), R(0.7), R(0.0), 0.0L}};
    const zw_real m = R(0.125), T = T_DYADIC;
    size_t i, j;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(deltas); ++i) {
        for (j = 0; j < ZWT_ARRAY_LEN(starts); ++j) {
            zw_sim_scene sc = scene_linear(m, R(16.0) * deltas[i], T, R(3.0), R(0.0));
            long double x1, v1;
            rec r;
            sc.x_init = starts[j].x0;
            sc.v_init = starts[j].v0;
            sc.x_eq_after = starts[j].x_eq;
            simulate(&sc, 2, &r);
            EXPECT_ABS(r.force[0], starts[j].F, 0);
            assert_true(r.x[0] == starts[j].x0 && r.v[0] == starts[j].v0);
            assert_true(r.t[0] == R(0.0) && r.t[1] == T);
            zoh_reference((long double)m, (long double)sc.b, (long double)T,
                          (long double)starts[j].x0, (long double)starts[j].v0, starts[j].F, &x1,
                          &v1);
            EXPECT_ULPS(r.x[1], x1, 16);
            EXPECT_ULPS(r.v[1], v1, 16);
            rec_free(&r);
        }
    }
}

/* ---- the reference step -------------------------------------------------------------------- */

/* The plant rests at x_eq_before = 0.25, so the force is exactly 0 until the step; at the
 * first sample with t_k >= t_step it is K (x_eq_after - x) = 4 (1 - 0.25) = 3 N exactly and
 * nothing more (a derivative kick would add B (1 - 0.25)/T = 384 N).  t_step on a sample,
 * between samples, at 0, and +inf (never). */
static void test_reference_step(void **state)
{
    const zw_real t_steps[] = {R(5.0) * T_DYADIC, R(4.5) * T_DYADIC, R(0.0), (zw_real)INFINITY};
    const size_t first_after[] = {5, 5, 0, 20};
    size_t i, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(t_steps); ++i) {
        zw_sim_scene sc = scene_linear(R(0.125), R(2.0), T_DYADIC, R(4.0), R(2.0));
        rec r;
        sc.x_init = R(0.25);
        sc.x_eq_before = R(0.25);
        sc.x_eq_after = R(1.0);
        sc.t_step = t_steps[i];
        simulate(&sc, 20, &r);
        for (k = 0; k < first_after[i]; ++k) {
            assert_true(r.force[k] == R(0.0));
            assert_true(r.x[k] == R(0.25));
        }
        if (first_after[i] == r.n) {
            rec_free(&r);
            continue;
        }
        assert_true(r.force[first_after[i]] == R(3.0));
        /* After the step the law is K (x_eq_after - x_k) - B (x_k - x_{k-1})/T. */
        for (k = first_after[i] + 1; k < r.n; ++k) {
            long double dx = (long double)r.x[k] - (long double)r.x[k - 1];
            long double spring = 4.0L * (1.0L - (long double)r.x[k]);
            long double damper = 2.0L * dx / (long double)T_DYADIC;
            EXPECT_ABS(r.force[k], spring - damper, TOLL(8) * (fabsl(spring) + fabsl(damper)));
        }
        rec_free(&r);
    }
}

/* ---- quantization -------------------------------------------------------------------------- */

/* x_meas = floor(x counts)/counts with 1000 counts per m: the count index by hand, both signs,
 * on a count and between counts; the controller acts on x_meas, the plant keeps x. */
static void test_quantization(void **state)
{
    const struct {
        zw_real x;
        long double count;
    } cases[] = {
        {R(0.0123456), 12.0L},  {R(-0.0123456), -13.0L}, {R(0.5), 500.0L}, {R(-0.5), -500.0L},
        {R(2.9999), 2999.0L},   {R(-0.0004), -1.0L},     {R(0.0), 0.0L},   {R(0.0009), 0.0L},
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_sim_scene sc = scene_linear(R(0.125), R(1.0), T_DYADIC, R(2.0), R(0.0));
        long double want = cases[i].count / 1000.0L;
        rec r;
        sc.effects = ZW_SIM_QUANTIZATION;
        sc.counts_per_unit = R(1000.0);
        sc.x_init = cases[i].x;
        simulate(&sc, 1, &r);
        EXPECT_ULPS(r.x_measured[0], want, 1); /* n/counts rounded once (or via 1/counts) */
        assert_true(r.x[0] == cases[i].x);
        EXPECT_NEAR(r.force_command[0], 2.0L * (0.0L - want), 0, TOLL(4));
        rec_free(&r);
    }
}

/* ---- subnormal velocities ------------------------------------------------------------------ */

/* A quantized loop that settles exactly (x_meas = x_eq, F = 0) leaves v decaying by e per
 * sample: below the smallest normal number it is 0, never a subnormal (10x slower on x86). */
static void test_quantized_settled_velocity_not_subnormal(void **state)
{
    zw_sim_scene sc = scene_linear(R(0.1), R(2.0), R(0.001), R(2000.0), R(1.0));
    rec r;
    size_t k, zeros = 0;
    (void)state;
    sc.effects = ZW_SIM_QUANTIZATION;
    sc.counts_per_unit = R(1048576.0);   /* 2^20 per m */
    sc.x_eq_after = R(0.0078125);        /* a whole number of counts */
    simulate(&sc, 60000, &r);
    for (k = 0; k < r.n; ++k) {
        assert_true(r.v[k] == R(0.0) || ZW_FABS(r.v[k]) >= ZW_REAL_MIN);
        zeros += r.v[k] == R(0.0);
    }
    assert_true(zeros > 1000);   /* it did settle to the flush (the case this is about) */
    assert_true(r.x_measured[r.n - 1] == R(0.0078125));
    rec_free(&r);
}

/* ---- Coulomb friction ---------------------------------------------------------------------- */

/* m = 1/8, b = 0, F_c = 1, F_s = 1.5.  The held force is K (x_eq - x) = K (1 - 0) = K. */
static zw_sim_scene scene_friction(zw_real K, zw_real v0)
{
    zw_sim_scene sc = scene_linear(R(0.125), R(0.0), T_DYADIC, K, R(0.0));
    sc.effects = ZW_SIM_FRICTION;
    sc.coulomb = R(1.0);
    sc.stiction = R(1.5);
    sc.substeps = 10;
    sc.x_eq_after = R(1.0);
    sc.v_init = v0;
    return sc;
}

/* 1.49 N > F_c but < F_s: stiction holds the resting plant exactly, for good. */
static void test_friction_stiction_holds(void **state)
{
    zw_sim_scene sc = scene_friction(R(1.49), R(0.0));
    rec r;
    size_t k;
    (void)state;
    simulate(&sc, 1000, &r);
    for (k = 0; k < r.n; ++k) {
        assert_true(r.x[k] == R(0.0) && r.v[k] == R(0.0));
        assert_true(r.force[k] == R(1.49));
        assert_true(ZW_FABS(r.friction[k]) <= R(1.5));
    }
    rec_free(&r);
}

/* 1.51 N > F_s: the plant breaks away and slides with a = (F - F_c)/m = 4.08 m/s^2, held
 * constant over the first sample (ZOH force, b = 0, friction -F_c once moving), so
 * v(T) = a T, x(T) = a T^2/2; RK4 integrates a constant acceleration exactly, leaving only
 * rounding, a few u per substep. */
static void test_friction_breakaway(void **state)
{
    zw_sim_scene sc = scene_friction(R(1.51), R(0.0));
    const long double a = ((long double)R(1.51) - 1.0L) / 0.125L, T = T_DYADIC;
    rec r;
    (void)state;
    simulate(&sc, 2, &r);
    EXPECT_REL(r.v[1], a * T, TOLL(4 * sc.substeps));
    EXPECT_REL(r.x[1], a * T * T / 2.0L, TOLL(8 * sc.substeps));
    EXPECT_ABS(r.friction[0], -1.0L, 0); /* opposing the motion */
    rec_free(&r);
}

/* Sliding at v0 = 0.31 m/s with no force (F_c = 0.5, F_s = 0.75): decelerates at F_c/m =
 * 4 m/s^2, stops at t* = v0/4 = 0.0775 s (substep 99.2 of 10 per sample, within
 * sample 9) at x* = v0^2/8 = 0.0120125 m, and stays: v = 0 exactly, x unchanged.  The stop is
 * located inside its substep (RK4 is exact for the constant deceleration), so x* is hit to
 * rounding; the stop at the substep's end it replaced missed it by a h^2/2 (1e-4 of x*). */
static void test_friction_sliding_stops(void **state)
{
    zw_sim_scene sc = scene_friction(R(0.0), R(0.31));
    const long double v0 = (long double)R(0.31), decel = 4.0L;
    const long double h = (long double)T_DYADIC / 10.0L;
    const long double t_stop = v0 / decel, x_stop = v0 * v0 / (2.0L * decel);
    rec r;
    size_t k;
    (void)state;
    sc.coulomb = R(0.5);
    sc.stiction = R(0.75);
    simulate(&sc, 300, &r);
    for (k = 0; k < r.n; ++k) {
        long double t = (long double)k * (long double)T_DYADIC;
        if (t < t_stop) {
            /* ~10 roundings per substep of a few terms, over <= 100 substeps */
            EXPECT_ABS(r.v[k], v0 - decel * t, TOLL(4 * 100) * v0);
            EXPECT_ABS(r.x[k], v0 * t - decel * t * t / 2.0L, TOLL(4 * 100) * x_stop);
            EXPECT_ABS(r.friction[k], -0.5L, 0);
        } else {
            assert_true(r.v[k] == R(0.0));
            assert_true(r.x[k] == r.x[10]);
        }
    }
    assert_true(9.0L * (long double)T_DYADIC < t_stop && t_stop < 10.0L * (long double)T_DYADIC);
    EXPECT_ABS(r.x[10], x_stop, TOLL(4 * 100) * x_stop);
    (void)h;
    rec_free(&r);
}

/* Stick-slip with reversals on b = 0, where every piece between events has a constant
 * acceleration: the reference below is the motion derived by hand, piece by piece in long
 * double (stop at t = -v/a, then held while |F| <= F_s or slipping toward F), and RK4 with
 * located events reproduces it to rounding.  The old stop at the end of the substep lost the
 * velocity gained after each reversal (one substep of acceleration). */
static void test_friction_reversals_exact(void **state)
{
    zw_sim_scene sc = scene_friction(R(4.0), R(-0.31));
    const long double m = 0.125L, Fc = 1.0L, Fs = 1.5L, K = 4.0L, T = (long double)T_DYADIC;
    long double x = 0.0L, v = (long double)R(-0.31), err_x = 0.0L, err_v = 0.0L;
    bool stuck;
    int reversals = 0, holds = 0;
    rec r;
    size_t k;
    (void)state;
    simulate(&sc, 600, &r);
    for (k = 0; k < r.n; ++k) {
        const long double F = K * (1.0L - (long double)r.x_measured[k]);   /* the held force */
        long double left = T;
        if (fabsl((long double)r.x[k] - x) > err_x) err_x = fabsl((long double)r.x[k] - x);
        if (fabsl((long double)r.v[k] - v) > err_v) err_v = fabsl((long double)r.v[k] - v);
        x = (long double)r.x[k];   /* restart from the simulated state: no chaos amplification */
        v = (long double)r.v[k];
        stuck = v == 0.0L;
        while (left > 0.0L) {
            long double dir, a;
            if (stuck) {
                if (fabsl(F) <= Fs) {
                    ++holds;
                    break;
                }
                dir = F > 0.0L ? 1.0L : -1.0L;
                stuck = false;
            } else {
                dir = v > 0.0L ? 1.0L : -1.0L;
            }
            a = (F - Fc * dir) / m;
            if (v != 0.0L && a * v < 0.0L && -v / a < left) {
                const long double t = -v / a;
                x += v * t + a * t * t / 2.0L;
                v = 0.0L;
                stuck = true;
                left -= t;
                ++reversals;
                continue;
            }
            x += v * left + a * left * left / 2.0L;
            v += a * left;
            left = 0.0L;
        }
    }
    /* The run has stops inside samples and ends held. */
    assert_true(reversals >= 2 && holds > 0);
    /* Per sample: a few roundings per substep and per located stop (the Illinois steps). */
    assert_true(err_x <= TOLL(400) * 1.0L);
    assert_true(err_v <= TOLL(400) * 10.0L);
    rec_free(&r);
}

/* ---- delay --------------------------------------------------------------------------------- */

/* A delay of n samples: force[k] = force_command[k - n], zeros first.  The plant rests at 0
 * until the first command arrives, so the commands up to sample n are all K (1 - 0) = K. */
static void test_delay(void **state)
{
    const int delays[] = {1, 3, ZW_SIM_MAX_DELAY};
    size_t i, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(delays); ++i) {
        const size_t n = (size_t)delays[i];
        zw_sim_scene sc = scene_linear(R(0.125), R(1.0), T_DYADIC, R(20.0), R(0.5));
        rec r;
        sc.effects = ZW_SIM_DELAY;
        sc.delay_samples = delays[i];
        sc.x_eq_after = R(1.0);
        simulate(&sc, 200, &r);
        for (k = 0; k < r.n; ++k) {
            if (k < n)
                assert_true(r.force[k] == R(0.0));
            else
                assert_true(r.force[k] == r.force_command[k - n]);
            if (k <= n) {
                assert_true(r.force_command[k] == R(20.0));
                assert_true(r.x[k] == R(0.0));
            }
        }
        assert_true(r.x[n + 1] > R(0.0)); /* the first command moved it, one sample later */
        rec_free(&r);
    }
}

/* ---- saturation ---------------------------------------------------------------------------- */

/* F_max = 2: a command of +-10 N is applied as +-2 N (and the plant sees 2 N: b = 0 gives
 * v(T) = 2 T/m = 1/8, x(T) = 2 T^2/(2m) = 2^-11 exactly), the command is recorded unclamped,
 * and every later sample obeys force = clamp(force_command). */
static void test_saturation(void **state)
{
    const zw_real targets[] = {R(1.0), R(-1.0)};
    size_t i, k, inside = 0;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(targets); ++i) {
        zw_sim_scene sc = scene_linear(R(0.125), R(0.0), T_DYADIC, R(10.0), R(0.4));
        zw_real s = targets[i];
        rec r;
        sc.effects = ZW_SIM_SATURATION;
        sc.force_max = R(2.0);
        sc.x_eq_after = s;
        simulate(&sc, 400, &r);
        assert_true(r.force_command[0] == R(10.0) * s);
        assert_true(r.force[0] == R(2.0) * s);
        assert_true(r.v[1] == R(0.125) * s);
        assert_true(r.x[1] == ZW_LDEXP(s, -11));
        for (k = 0; k < r.n; ++k) {
            zw_real c = r.force_command[k];
            zw_real want = c > R(2.0) ? R(2.0) : (c < R(-2.0) ? R(-2.0) : c);
            assert_true(r.force[k] == want);
            if (ZW_FABS(c) < R(2.0)) ++inside;
        }
        rec_free(&r);
    }
    assert_true(inside > 0); /* the unclamped branch was exercised too */
}

/* ---- velocity filter ----------------------------------------------------------------------- */

/* The probe moves at v0 = 1/2 m/s from x = 0, so v_est = 0 at k = 0 (x_meas_{-1} = x_meas_0)
 * and exactly v0 after.  With K = 0, B = 1 the command is -v_f.  The recursion
 * v_f_k = a v_f_{k-1} + (1 - a) v_est_k from v_f_{-1} = 0 gives v_f_k = v0 (1 - a^k),
 * a = exp(-2 pi 5 Hz 2^-7 s) ~ 0.78.  Error: the recursion's roundings, ~4 u v0 each,
 * contracted by a: <= 4 u v0/(1 - a) ~ 18 u v0; a itself is off by ~3 u (its argument) + 1
 * ulp, moving v0 a^k by <= k a^k 3 u v0 <= 3 u v0/(e ln(1/a)) ~ 4.5 u v0.  Tolerance 32 u v0. */
static void test_velocity_filter(void **state)
{
    zw_sim_scene sc = scene_probe(R(0.0), R(0.5));
    const long double a = expl(-2.0L * 3.14159265358979323846264338L * 5.0L * 0.0078125L);
    rec r;
    size_t k;
    (void)state;
    sc.B = R(1.0);
    sc.effects = ZW_SIM_VELOCITY_FILTER;
    sc.cutoff_hz = R(5.0);
    simulate(&sc, 60, &r);
    for (k = 0; k < r.n; ++k) {
        assert_true(r.x[k] == (zw_real)k * R(0.00390625)); /* the probe is exact */
        EXPECT_ABS(r.force_command[k], -0.5L * (1.0L - powl(a, (long double)k)), TOLL(32) * 0.5L);
        /* the trace shows the filtered estimate the damping used (B = 1) */
        EXPECT_ABS(r.velocity_estimate[k], 0.5L * (1.0L - powl(a, (long double)k)), TOLL(32) * 0.5L);
    }
    rec_free(&r);
}

/* ---- wall ---------------------------------------------------------------------------------- */

/* The wall's contract on the probe's exact positions: K_w (x_wall - x) - B_w v_est while
 * inside, clamped so it never pulls, 0 outside (and on the surface). */
static long double wall_expected(int side, long double x_wall, long double x, long double v_est)
{
    long double f = 100.0L * (x_wall - x) - 2.0L * v_est;
    if (side > 0) return x > x_wall && f < 0.0L ? f : 0.0L;
    return x < x_wall && f > 0.0L ? f : 0.0L;
}

/* Both sides, moving in (the spring and the damper push out) and moving out (near the
 * surface the damper outweighs the spring: the sum would pull, the wall gives 0).  x_wall =
 * +-1/2, K_w = 100, B_w = 2, |v0| = 1/2 m/s, positions k/256 apart: every product is exact. */
static void test_wall_force(void **state)
{
    const struct {
        int side;
        zw_real x0, v0;
    } passes[] = {
        {+1, R(0.4375), R(0.5)}, {+1, R(0.6875), R(-0.5)},
        {-1, R(-0.4375), R(-0.5)}, {-1, R(-0.6875), R(0.5)},
    };
    size_t i, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(passes); ++i) {
        zw_sim_scene sc = scene_probe(passes[i].x0, passes[i].v0);
        const long double x_wall = 0.5L * passes[i].side;
        size_t pushed = 0, clamped = 0;
        rec r;
        sc.effects = ZW_SIM_WALL;
        sc.wall.position = (zw_real)x_wall;
        sc.wall.stiffness = R(100.0);
        sc.wall.damping = R(2.0);
        sc.wall.side = passes[i].side;
        simulate(&sc, 64, &r);
        for (k = 0; k < r.n; ++k) {
            long double x =
                (long double)passes[i].x0 + (long double)k * (long double)passes[i].v0 / 128.0L;
            long double v_est = k == 0 ? 0.0L : (long double)passes[i].v0;
            long double want = wall_expected(passes[i].side, x_wall, x, v_est);
            assert_true((long double)r.x[k] == x);
            EXPECT_ABS(r.wall_force[k], want, 0);
            assert_true(r.force_command[k] == r.wall_force[k]); /* K = B = 0 */
            assert_true(r.wall_force[k] * (zw_real)passes[i].side <= R(0.0)); /* never pulls */
            if (want != 0.0L) ++pushed;
            if (want == 0.0L && (passes[i].side > 0 ? x > x_wall : x < x_wall)) ++clamped;
        }
        assert_true(pushed > 0);
        if (passes[i].v0 * (zw_real)passes[i].side < R(0.0)) assert_true(clamped >= 2);
        rec_free(&r);
    }
}

/* A hand (m_h = 0.05, k_h = 50, b_h = 1) pushes the handle from x = -0.01 toward `to` = 1
 * through a wall at 0 (K_w = 1000, B_w = 2), plant m = 0.1, b = 30, T = 0.01.  At rest the
 * forces balance: k_h (1 - x) = K_w x, so x_ss = k_h/(k_h + K_w) = 1/21, and the penetration
 * is the hand's push over K_w.  The poles are fast (~ -34 and -200 /s; the sampled wall sits
 * at alpha = 0.67, beta = 0.13 with delta = 2.07 and is stable), so 30 s leave only rounding:
 * the integrator stops moving x once v h < ulp(x)/2, i.e. with a residual force below
 * (b + b_h) ulp(x)/(2h), a position error below that over K_w + k_h. */
static void test_wall_steady_penetration(void **state)
{
    zw_sim_scene sc = scene_linear(R(0.1), R(30.0), R(0.01), R(0.0), R(0.0));
    const long double x_ss = 50.0L / 1050.0L;
    long double h, dead_band;
    rec r;
    size_t last;
    (void)state;
    sc.effects = ZW_SIM_WALL | ZW_SIM_HAND;
    sc.substeps = 20;
    sc.x_init = R(-0.01);
    sc.wall.position = R(0.0);
    sc.wall.stiffness = R(1000.0);
    sc.wall.damping = R(2.0);
    sc.wall.side = 1;
    sc.hand.mass = R(0.05);
    sc.hand.stiffness = R(50.0);
    sc.hand.damping = R(1.0);
    sc.hand.t_grasp = R(0.0);
    sc.hand.t_release = (zw_real)INFINITY;
    sc.hand.from = R(-0.01);
    sc.hand.to = R(1.0);
    sc.hand.speed = R(1.0);
    simulate(&sc, 3000, &r);
    last = r.n - 1;
    h = (long double)R(0.01) / 20.0L;
    dead_band = 31.0L * zwt_ulp(x_ss) / (2.0L * h) / 1050.0L;
    EXPECT_ABS(r.x[last], x_ss, 4.0L * dead_band + TOLL(64) * x_ss);
    /* penetration = push / K_w, the push read from the trace */
    EXPECT_ABS(r.x[last], (long double)r.hand_force[last] / 1000.0L,
               4.0L * dead_band + TOLL(64) * x_ss);
    EXPECT_ABS(r.hand_force[last], 50.0L * (1.0L - x_ss),
               1000.0L * 4.0L * dead_band + TOLL(64) * 50);
    EXPECT_ABS(r.wall_force[last], -1000.0L * x_ss, 1000.0L * 4.0L * dead_band + TOLL(64) * 50);
    rec_free(&r);
}

/* ---- knob ---------------------------------------------------------------------------------- */

/* Detents at 1/8, 3/8, 5/8 (pitch 1/4, pitch/4 = 1/16), k_detent = 8, k_end = 40, B = 1/2. */
static zw_sim_scene scene_knob(zw_real x0)
{
    zw_sim_scene sc = scene_linear(R(0.125), R(1.0), T_DYADIC, R(0.0), R(0.0));
    sc.effects = ZW_SIM_KNOB;
    sc.knob.first = R(0.125);
    sc.knob.pitch = R(0.25);
    sc.knob.count = 3;
    sc.knob.k_detent = R(8.0);
    sc.knob.k_end = R(40.0);
    sc.knob.damping = R(0.5);
    sc.x_init = x0;
    return sc;
}

/* Sample 0 of a knob scene at x0: stiffness used, stiffness planned, command (v_est = 0). */
static void knob_at(zw_real x0, zw_real *K, zw_real *K_planned, zw_real *F)
{
    zw_sim_scene sc = scene_knob(x0);
    rec r;
    simulate(&sc, 1, &r);
    *K = r.stiffness[0];
    *K_planned = r.stiffness_planned[0];
    *F = r.force_command[0];
    assert_true(r.damping[0] == R(0.5));
    rec_free(&r);
}

/* The map at chosen positions: near a detent k_d toward it; between detents -k_d away from
 * their midpoint (1/4, 1/2); beyond the ends (and on the last detent's outer side) k_end
 * toward the end detent. */
static void test_knob_map(void **state)
{
    const struct {
        zw_real x;
        long double K, x_eq;
    } cases[] = {
        {R(0.15), 8.0L, 0.125L},    {R(0.1), 40.0L, 0.125L},   {R(0.05), 40.0L, 0.125L},
        {R(0.21875), -8.0L, 0.25L}, {R(0.28), -8.0L, 0.25L},   {R(0.4), 8.0L, 0.375L},
        {R(0.35), 8.0L, 0.375L},    {R(0.46), -8.0L, 0.5L},    {R(0.6), 8.0L, 0.625L},
        {R(0.655), 40.0L, 0.625L},  {R(0.7), 40.0L, 0.625L},   {R(-3.0), 40.0L, 0.125L},
        {R(0.2), -8.0L, 0.25L},     {R(0.3), -8.0L, 0.25L},    {R(0.18), 8.0L, 0.125L},
        {R(0.32), 8.0L, 0.375L},
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_real K, Kp, F;
        long double x = (long double)cases[i].x;
        knob_at(cases[i].x, &K, &Kp, &F);
        EXPECT_ABS(K, cases[i].K, 0);
        EXPECT_ABS(Kp, cases[i].K, 0);
        /* K (x_eq - x) with a rounding or two of the terms */
        EXPECT_ABS(F, cases[i].K * (cases[i].x_eq - x),
                   TOLL(4) * fabsl(cases[i].K) * (fabsl(cases[i].x_eq) + fabsl(x)));
    }
}

/* A knob scene that blows up records inf and NaN and goes on (no undefined conversion of a
 * NaN position to a detent index): an end wall far too stiff for the plant. */
static void test_knob_diverging(void **state)
{
    zw_sim_scene sc = scene_knob(R(0.7));
    zw_sim_verdict vd;
    rec r;
    size_t k, nonfinite = 0;
    (void)state;
    sc.knob.k_end = R(1e6);
    simulate(&sc, 400, &r);
    for (k = 0; k < r.n; ++k) nonfinite += ZW_IS_FINITE(r.x[k]) ? 0u : 1u;
    assert_true(nonfinite > 0 && ZW_IS_NAN(r.x[r.n - 1]));
    assert_true(ZW_IS_NAN(r.stiffness[r.n - 1]));
    EXPECT_OK(zw_sim_judge(r.x, r.n, 50, 4, R(1e-3), &vd));
    assert_int_equal(vd.outcome, ZW_SIM_UNSTABLE);
    assert_true(vd.first_nonfinite < r.n);
    rec_free(&r);
}

/* The force is continuous across every boundary of the map (the ends p_0, p_{n-1} and the
 * quarter-pitch points), and takes the shared value there: 0 at the ends, -+k_d pitch/4 =
 * -+0.5 N at p_i +- pitch/4.  A wrong equilibrium on either side would jump by ~1 N.  And
 * nowhere else does it jump: a sweep over [0, 3/4] in steps of 2^-10 moves it by at most
 * k_end 2^-10 per step. */
static void test_knob_continuity(void **state)
{
    const struct {
        zw_real x;
        long double F;
    } bounds[] = {
        {R(0.125), 0.0L},  {R(0.1875), -0.5L}, {R(0.3125), 0.5L},
        {R(0.4375), -0.5L}, {R(0.5625), 0.5L},  {R(0.625), 0.0L},
    };
    const zw_real eps = R(PREC(1e-9, 1e-5));
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(bounds); ++i) {
        zw_real K, Kp, below, at, above;
        knob_at(bounds[i].x - eps, &K, &Kp, &below);
        knob_at(bounds[i].x, &K, &Kp, &at);
        knob_at(bounds[i].x + eps, &K, &Kp, &above);
        /* the steepest slope is k_end = 40 N/m; rounding of K (x_eq - x) a few u of 40 N */
        EXPECT_ABS(at, bounds[i].F, TOLL(4) * 40.0L);
        EXPECT_ABS(below, bounds[i].F, 40.0L * (long double)eps * 1.01L + TOLL(4) * 40.0L);
        EXPECT_ABS(above, bounds[i].F, 40.0L * (long double)eps * 1.01L + TOLL(4) * 40.0L);
    }
    {
        zw_real K, Kp, F, F_prev = R(0.0);
        int k;
        for (k = 0; k <= 768; ++k) {
            knob_at(ZW_LDEXP((zw_real)k, -10), &K, &Kp, &F);
            if (k > 0)
                EXPECT_TRUE_MSG(ZW_FABS(F - F_prev) <= R(40.0) / R(1024.0) + TOL(8) * R(40.0),
                                "force jumps from %g to %g at x = %d/1024", (double)F_prev,
                                (double)F, k);
            F_prev = F;
        }
    }
}

/* stiffness is the map at x_meas, stiffness_planned at the true x: with 12 counts per unit
 * x = 0.2 (between detents: -8) is measured as 2/12 = 0.1667 (in the first detent: +8), and
 * the command is 8 (1/8 - 1/6) = -1/3 N. */
static void test_knob_planned_vs_measured(void **state)
{
    zw_sim_scene sc = scene_knob(R(0.2));
    rec r;
    (void)state;
    sc.effects |= ZW_SIM_QUANTIZATION;
    sc.counts_per_unit = R(12.0);
    simulate(&sc, 1, &r);
    EXPECT_ULPS(r.x_measured[0], 1.0L / 6.0L, 1);
    EXPECT_ABS(r.stiffness[0], 8.0L, 0);
    EXPECT_ABS(r.stiffness_planned[0], -8.0L, 0);
    EXPECT_ABS(r.force_command[0], 8.0L * (0.125L - 1.0L / 6.0L), TOLL(8));
    rec_free(&r);
}

/* ---- schedule ------------------------------------------------------------------------------ */

/* Segments from 0, 10 T (on a sample) and 20.5 T (between samples): the gains switch at the
 * first sample with t_k >= t_i, and the command uses them. */
static void test_schedule(void **state)
{
    const zw_sim_segment seg[3] = {{R(0.0), R(10.0), R(1.0)},
                                   {R(10.0) * T_DYADIC, R(20.0), R(2.0)},
                                   {R(20.5) * T_DYADIC, R(30.0), R(3.0)}};
    zw_sim_scene sc = scene_linear(R(0.125), R(1.0), T_DYADIC, R(NAN), R(NAN));
    rec r;
    size_t k;
    (void)state;
    sc.effects = ZW_SIM_SCHEDULE;
    sc.schedule = seg;
    sc.schedule_len = 3;
    sc.x_eq_after = R(1.0);
    simulate(&sc, 40, &r);
    for (k = 0; k < r.n; ++k) {
        size_t i = k < 10 ? 0 : (k <= 20 ? 1 : 2);
        long double dx = k == 0 ? 0.0L : (long double)r.x[k] - (long double)r.x[k - 1];
        long double spring = (long double)seg[i].K * (1.0L - (long double)r.x[k]);
        long double damper = (long double)seg[i].B * dx / (long double)T_DYADIC;
        assert_true(r.stiffness[k] == seg[i].K && r.damping[k] == seg[i].B);
        assert_true(r.stiffness_planned[k] == seg[i].K);
        EXPECT_ABS(r.force_command[k], spring - damper, TOLL(8) * (fabsl(spring) + fabsl(damper)));
    }
    rec_free(&r);
}

/* ---- hand ---------------------------------------------------------------------------------- */

/* The probe at rest at 0.25 (its own acceleration ~1e-19 m/s^2 moves nothing) held from 3 T
 * to 40 T by a hand (k_h = 10, b_h = 1/2) whose intended position runs from 0.5 at 8 m/s and
 * stops at 1.5 (after 1/8 s = 16 samples):  F = k_h (x_h - x) + b_h (x_h' - 0). */
static void test_hand_force_path(void **state)
{
    zw_sim_scene sc = scene_probe(R(0.25), R(0.0));
    rec r;
    size_t k;
    (void)state;
    sc.effects = ZW_SIM_HAND;
    sc.substeps = 4;
    sc.hand.stiffness = R(10.0);
    sc.hand.damping = R(0.5);
    sc.hand.t_grasp = R(3.0) * T_DYADIC;
    sc.hand.t_release = R(40.0) * T_DYADIC;
    sc.hand.from = R(0.5);
    sc.hand.to = R(1.5);
    sc.hand.speed = R(8.0);
    simulate(&sc, 50, &r);
    for (k = 0; k < r.n; ++k) {
        long double want = 0.0L;
        if (k >= 3 && k < 40) {
            long double travelled = (long double)(k - 3) / 16.0L; /* 8 m/s * (k - 3) 2^-7 s */
            long double xh = travelled < 1.0L ? 0.5L + travelled : 1.5L;
            long double vh = travelled < 1.0L ? 8.0L : 0.0L;
            want = 10.0L * (xh - 0.25L) + 0.5L * vh;
        }
        assert_true(r.x[k] == R(0.25));
        EXPECT_ABS(r.hand_force[k], want, TOLL(8) * 20.0L);
    }
    rec_free(&r);
}

/* While held the hand's mass adds to m: b = 0, m = m_h = 1/8, command F_k = 2 (1 - x_k) held
 * over each sample, so v jumps by F_k T/(m + m_h) while held (until 2 T) and by F_k T/m after. */
static void test_hand_mass(void **state)
{
    zw_sim_scene sc = scene_linear(R(0.125), R(0.0), T_DYADIC, R(2.0), R(0.0));
    const long double T = T_DYADIC;
    rec r;
    size_t k;
    (void)state;
    sc.effects = ZW_SIM_HAND;
    sc.substeps = 8;
    sc.x_eq_after = R(1.0);
    sc.hand.mass = R(0.125);
    sc.hand.t_grasp = R(0.0);
    sc.hand.t_release = R(2.0) * T_DYADIC;
    simulate(&sc, 4, &r);
    assert_true(r.force[0] == R(2.0));
    EXPECT_REL(r.v[1], 2.0L * T / 0.25L, TOLL(4 * 8));   /* 2^-6 */
    EXPECT_REL(r.x[1], 2.0L * T * T / 0.5L, TOLL(8 * 8)); /* 2^-12 */
    for (k = 1; k < 3; ++k) {
        long double mass = k < 2 ? 0.25L : 0.125L;
        long double dv = (long double)r.force[k] * T / mass;
        EXPECT_ABS(r.v[k + 1], (long double)r.v[k] + dv,
                   TOLL(8 * 8) * (fabsl(dv) + (long double)r.v[k]));
    }
    rec_free(&r);
}

/* speed = +inf is "a step to `to`": from the grasp on the hand pulls toward `to`, and the
 * state stays finite (with and without hand damping; the step's velocity is not a force). */
static void test_hand_step_speed_inf(void **state)
{
    const zw_real dampings[] = {R(0.0), R(0.5)};
    size_t i, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(dampings); ++i) {
        zw_sim_scene sc = scene_probe(R(0.25), R(0.0));
        rec r;
        sc.effects = ZW_SIM_HAND;
        sc.substeps = 4;
        sc.hand.stiffness = R(10.0);
        sc.hand.damping = dampings[i];
        sc.hand.t_grasp = R(0.0);
        sc.hand.from = R(0.5);
        sc.hand.to = R(1.5);
        sc.hand.speed = (zw_real)INFINITY;
        simulate(&sc, 10, &r);
        for (k = 0; k < r.n; ++k) {
            EXPECT_TRUE_MSG(ZW_IS_FINITE(r.x[k]) && ZW_IS_FINITE(r.v[k]) &&
                                ZW_IS_FINITE(r.hand_force[k]),
                            "b_h = %g, sample %zu: x = %g, v = %g, hand force = %g",
                            (double)dampings[i], k, (double)r.x[k], (double)r.v[k],
                            (double)r.hand_force[k]);
            if (k >= 1) EXPECT_ABS(r.hand_force[k], 10.0L * (1.5L - 0.25L), TOLL(8) * 20.0L);
        }
        rec_free(&r);
    }
}

/* A hand with m_h = k_h = b_h = 0 turns the integrator on without changing the physics: the
 * RK4 path must follow the exact one.  Scene: m = 0.1, b = 1 (delta = 0.1), T = 0.01,
 * K = 150, B = 4.5 (alpha = 0.15, beta = 0.45, spectral radius ~0.62), step to 1 m.
 *
 * Bound.  Within a sample the ODE is linear with a constant input f = F/m:
 * RK4 keeps the Taylor terms of exp(hM) up to (hM)^4, and for v' = -lambda v + f,
 * z = lambda h = delta/N, the dropped tails are alternating and decreasing (z < 1), so per
 * substep  |err v| <= (z^4/120)(z |v| + h |f|),  |err x| <= (h z^3/120)(z |v| + h |f|);  over
 * the N substeps of a sample (|R(-z)| <= 1; a v error feeds x for at most T)
 *   eps_v <= (z^4/120)(delta V + T Fm),   eps_x <= (T z^3/120)(z V + h Fm) + T eps_v,
 * V = max |v|, Fm = max |F|/m.  Rounding: each substep rounds x and v once at their size,
 * plus the few roundings of the exact path: <= (N + 8) u (X + T V + T^2 Fm) per sample.
 * The per-sample errors e_k (scaled state x, T v, x_prev) propagate through the closed loop:
 * |e_k| <= S max|local|, S = sum_j ||A^j||_inf over the run, computed here.  delta = 0.1,
 * N = 50: truncation ~2e-13 per sample, S ~ 16: a bound ~4e-12 of X = 1 in double; float
 * is rounding-bound, ~58 u S ~ 7e-5. */
static void test_hand_integrator_matches_exact(void **state)
{
    const zw_real m = R(0.1), b = R(1.0), T = R(0.01), K = R(150.0), B = R(4.5);
    const int N = 50;
    const size_t n = 1000;
    zw_sim_scene exact = scene_linear(m, b, T, K, B), rk = exact;
    long double d, e, p, r_c, X, V, Fm, z, h, eps_v, eps_x, local, S = 0.0L, tol, worst = 0.0L;
    long double A[3][3], P[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    rec a, c;
    size_t j, k;
    int i1, i2, i3;
    (void)state;
    exact.x_eq_after = R(1.0);
    rk.x_eq_after = R(1.0);
    rk.effects = ZW_SIM_HAND;
    rk.substeps = N;
    rk.hand.t_grasp = R(0.0);
    rk.hand.t_release = (zw_real)INFINITY;
    simulate(&exact, n, &a);
    simulate(&rk, n, &c);

    /* the closed loop in (x, T v, x_prev): F = -(K + B/T) x + (B/T) x_prev + const */
    d = (long double)b * (long double)T / (long double)m;
    e = expl(-d);
    p = -expm1l(-d) / d;
    r_c = (1.0L - p) / d; /* d = 0.1: cancels ~3 digits of long double's 19, harmless here */
    {
        long double Tl = T, ml = m, Fx = -(long double)K - (long double)B / Tl,
                    Fp = (long double)B / Tl, g = Tl * Tl / ml * r_c, hv = Tl * Tl / ml * p;
        long double rows[3][3] = {{1.0L + g * Fx, p, g * Fp}, {hv * Fx, e, hv * Fp}, {1, 0, 0}};
        memcpy(A, rows, sizeof A);
    }
    for (j = 0; j < n; ++j) {
        long double Q[3][3], norm = 0.0L;
        for (i1 = 0; i1 < 3; ++i1) {
            long double row = 0.0L;
            for (i2 = 0; i2 < 3; ++i2) row += fabsl(P[i1][i2]);
            if (row > norm) norm = row;
        }
        S += norm;
        for (i1 = 0; i1 < 3; ++i1)
            for (i2 = 0; i2 < 3; ++i2) {
                Q[i1][i2] = 0.0L;
                for (i3 = 0; i3 < 3; ++i3) Q[i1][i2] += P[i1][i3] * A[i3][i2];
            }
        memcpy(P, Q, sizeof P);
    }

    X = max_abs(a.x, n);
    V = max_abs(a.v, n);
    Fm = max_abs(a.force, n) / (long double)m;
    z = d / N;
    h = (long double)T / N;
    eps_v = powl(z, 4) / 120.0L * (d * V + (long double)T * Fm);
    eps_x = (long double)T * powl(z, 3) / 120.0L * (z * V + h * Fm) + (long double)T * eps_v;
    local = (eps_x > (long double)T * eps_v ? eps_x : (long double)T * eps_v) +
            TOLL(N + 8) * (X + (long double)T * V + (long double)T * (long double)T * Fm);
    tol = S * local;
    /* the bound is of the order claimed above (else the test would prove little) */
    EXPECT_TRUE_MSG(tol < PREC(1e-11L, 1e-4L) * X, "bound %Lg, S = %Lg", tol, S);

    for (k = 0; k < n; ++k) {
        long double ex = fabsl((long double)c.x[k] - (long double)a.x[k]);
        long double ev = (long double)T * fabsl((long double)c.v[k] - (long double)a.v[k]);
        if (ex > worst) worst = ex;
        EXPECT_TRUE_MSG(ex <= tol && ev <= tol, "sample %zu: |dx| = %Lg, T |dv| = %Lg > %Lg", k,
                        ex, ev, tol);
    }
    printf("    RK4 (N = %d) vs exact over %zu samples: max |dx| = %.3Lg, bound %.3Lg "
           "(S = %.3Lg)\n",
           N, n, worst, tol, S);
    rec_free(&a);
    rec_free(&c);
}

/* ---- resumability -------------------------------------------------------------------------- */

static const zw_sim_segment g_schedule[2] = {{R(0.0), R(200.0), R(1.0)},
                                             {R(0.3), R(300.0), R(2.0)}};

/* Nearly every effect at once (the state each carries: delay line, filter, schedule index,
 * stiction, previous measurement, hand path). */
static zw_sim_scene scene_busy(bool knob)
{
    zw_sim_scene sc = scene_linear(R(0.1), R(3.0), R(0.01), R(200.0), R(1.0));
    sc.x_eq_after = R(1.0);
    sc.t_step = R(0.05);
    sc.effects = ZW_SIM_QUANTIZATION | ZW_SIM_FRICTION | ZW_SIM_DELAY | ZW_SIM_SATURATION |
                 ZW_SIM_VELOCITY_FILTER | ZW_SIM_HAND | ZW_SIM_WALL |
                 (knob ? ZW_SIM_KNOB : ZW_SIM_SCHEDULE);
    sc.counts_per_unit = R(1e4);
    sc.coulomb = R(0.2);
    sc.stiction = R(0.3);
    sc.delay_samples = 2;
    sc.force_max = R(50.0);
    sc.cutoff_hz = R(30.0);
    sc.average_samples = 4;
    sc.actuator_tau = R(0.002);
    sc.hand.mass = R(0.02);
    sc.hand.stiffness = R(20.0);
    sc.hand.damping = R(0.5);
    sc.hand.t_grasp = R(0.1);
    sc.hand.t_release = R(0.6);
    sc.hand.from = R(0.0);
    sc.hand.to = R(0.8);
    sc.hand.speed = R(2.0);
    sc.wall.position = R(0.9);
    sc.wall.stiffness = R(2000.0);
    sc.wall.damping = R(5.0);
    sc.wall.side = 1;
    sc.knob.first = R(0.0);
    sc.knob.pitch = R(0.2);
    sc.knob.count = 5;
    sc.knob.k_detent = R(50.0);
    sc.knob.k_end = R(300.0);
    sc.knob.damping = R(0.5);
    sc.schedule = g_schedule;
    sc.schedule_len = 2;
    sc.substeps = 8;
    return sc;
}

/* A trace whose arrays start at entry `at` of r's. */
static zw_sim_trace trace_from(const rec *r, size_t at)
{
    zw_sim_trace t;
    t.t = r->t + at;
    t.x = r->x + at;
    t.v = r->v + at;
    t.x_measured = r->x_measured + at;
    t.force = r->force + at;
    t.force_command = r->force_command + at;
    t.stiffness = r->stiffness + at;
    t.stiffness_planned = r->stiffness_planned + at;
    t.damping = r->damping + at;
    t.wall_force = r->wall_force + at;
    t.friction = r->friction + at;
    t.hand_force = r->hand_force + at;
    t.hand_target = r->hand_target + at;
    t.velocity_estimate = r->velocity_estimate + at;
    return t;
}

/* run(n1); run(n2); ... equals run(n1 + n2 + ...) bit for bit, every signal, pieces of 0 and
 * 1 samples included; the linear loop and two busy scenes. */
static void test_resumable(void **state)
{
    const size_t pieces[] = {0, 1, 36, 0, 63, 100};
    const size_t total = 200;
    int which;
    (void)state;
    for (which = 0; which < 3; ++which) {
        zw_sim_scene sc = which == 0 ? scene_linear(R(0.1), R(3.0), R(0.01), R(200.0), R(1.0))
                                     : scene_busy(which == 2);
        zw_sim sim;
        rec whole, parts;
        size_t i, at = 0;
        if (which == 0) sc.x_eq_after = R(1.0);
        simulate(&sc, total, &whole);
        rec_alloc(&parts, total);
        EXPECT_OK(zw_sim_init(&sim, &sc));
        for (i = 0; i < ZWT_ARRAY_LEN(pieces); ++i) {
            zw_sim_trace t = trace_from(&parts, at);
            EXPECT_OK(zw_sim_run(&sim, pieces[i], &t));
            at += pieces[i];
        }
        assert_int_equal(at, total);
#define SAME(sig) assert_memory_equal(whole.sig, parts.sig, total * sizeof(zw_real))
        SAME(t);
        SAME(x);
        SAME(v);
        SAME(x_measured);
        SAME(force);
        SAME(force_command);
        SAME(stiffness);
        SAME(stiffness_planned);
        SAME(damping);
        SAME(wall_force);
        SAME(friction);
        SAME(hand_force);
        SAME(hand_target);
        SAME(velocity_estimate);
#undef SAME
        assert_true(max_abs(whole.x, total) > 0.1L); /* it moved */
        rec_free(&whole);
        rec_free(&parts);
    }
}

/* A linear scene runs the ideal loop unless the velocity estimate is asked for, which
 * only the general loop stores: both give the same trajectory bit for bit, and the
 * estimate is the backward difference of the measured position. */
static void test_linear_loops_agree(void **state)
{
    zw_sim_scene sc = scene_linear(R(0.1), R(3.0), R(0.01), R(200.0), R(1.0));
    zw_sim sim;
    zw_sim_trace no_estimate;
    rec all;
    zw_real x[300], F[300];
    size_t k;
    (void)state;
    sc.x_eq_after = R(1.0);
    sc.t_step = R(0.5);
    simulate(&sc, 300, &all);   /* every signal: the general loop */
    memset(&no_estimate, 0, sizeof no_estimate);
    no_estimate.x = x;
    no_estimate.force = F;
    EXPECT_OK(zw_sim_init(&sim, &sc));
    EXPECT_OK(zw_sim_run(&sim, 300, &no_estimate));
    assert_memory_equal(x, all.x, sizeof x);
    assert_memory_equal(F, all.force, sizeof F);
    for (k = 1; k < 300; ++k) assert_true(all.velocity_estimate[k] == (x[k] - x[k - 1]) / sc.T);
    assert_true(all.velocity_estimate[0] == 0);
    rec_free(&all);
}

/* A NULL trace pointer means "not recorded": the other signals are unchanged. */
static void test_partial_trace(void **state)
{
    zw_sim_scene sc = scene_busy(false);
    zw_sim sim;
    zw_sim_trace only_x;
    rec whole;
    zw_real x[120];
    (void)state;
    simulate(&sc, 120, &whole);
    memset(&only_x, 0, sizeof only_x);
    only_x.x = x;
    EXPECT_OK(zw_sim_init(&sim, &sc));
    EXPECT_OK(zw_sim_run(&sim, 120, &only_x));
    assert_memory_equal(x, whole.x, sizeof x);
    rec_free(&whole);
}

/* ---- zw_sim_judge -------------------------------------------------------------------------- */

/* Peak-to-peak of x[from .. from + len), in long double. */
static long double p2p(const zw_real *x, size_t from, size_t len)
{
    long double lo = (long double)x[from], hi = lo;
    size_t i;
    for (i = from; i < from + len; ++i) {
        if ((long double)x[i] < lo) lo = (long double)x[i];
        if ((long double)x[i] > hi) hi = (long double)x[i];
    }
    return hi - lo;
}

/* x_k = r^k sin(0.3 k), n = 1000. */
static void damped_sine(zw_real *x, size_t n, long double r)
{
    size_t k;
    for (k = 0; k < n; ++k) x[k] = (zw_real)(powl(r, (long double)k) * sinl(0.3L * (long double)k));
}

static const char *outcome_name(zw_sim_outcome o)
{
    return o == ZW_SIM_STABLE ? "STABLE" : (o == ZW_SIM_UNSTABLE ? "UNSTABLE" : "UNDECIDED");
}

static zw_sim_verdict judge(const zw_real *x, size_t n, size_t window, size_t windows,
                            zw_real tolerance)
{
    zw_sim_verdict v;
    memset(&v, 0, sizeof v);
    EXPECT_OK(zw_sim_judge(x, n, window, windows, tolerance, &v));
    return v;
}

/* A decaying sinusoid (r = 0.99 per sample), 4 windows of 100 of the last 400 samples:
 * A_1 = p2p(x[600..699]), A_4 = p2p(x[900..999]), growth (A_4/A_1)^(1/300) ~ r.  A window's
 * peak-to-peak is set by its first extremes, which lie within one period P = 2 pi/0.3 ~ 21
 * samples of its start, at a phase that differs between the windows: A_4/A_1 = r^300 within a
 * factor r^-P, so growth = r within P |ln r|/300 ~ 7e-4 (1e-3 allowed).  STABLE when
 * A_4 <= tolerance, else UNDECIDED (still decaying). */
static void test_judge_decaying(void **state)
{
    enum { n = 1000 };
    static zw_real x[n];
    long double a1, aw;
    zw_sim_verdict v;
    (void)state;
    damped_sine(x, n, 0.99L);
    a1 = p2p(x, 600, 100);
    aw = p2p(x, 900, 100);
    v = judge(x, n, 100, 4, (zw_real)(2.0L * aw));
    assert_int_equal(v.outcome, ZW_SIM_STABLE);
    EXPECT_ULPS(v.amplitude_first, a1, 1);
    EXPECT_ULPS(v.amplitude_last, aw, 1);
    /* pow of a quotient and an exponent 1/300, each rounded once: a few ulps */
    EXPECT_ULPS(v.growth, powl(aw / a1, 1.0L / 300.0L), 4);
    EXPECT_ABS(v.growth, 0.99L, 1e-3L);
    assert_true(v.first_nonfinite == n);
    v = judge(x, n, 100, 4, (zw_real)(aw / 2.0L));
    assert_int_equal(v.outcome, ZW_SIM_UNDECIDED);
}

/* A growing sinusoid (1.01 per sample) above the tolerance: UNSTABLE, growth ~ 1.01 (within
 * 1e-3, as in test_judge_decaying). */
static void test_judge_growing(void **state)
{
    enum { n = 1000 };
    static zw_real x[n];
    zw_sim_verdict v;
    (void)state;
    damped_sine(x, n, 1.01L);
    v = judge(x, n, 100, 4, R(1e-3));
    assert_int_equal(v.outcome, ZW_SIM_UNSTABLE);
    EXPECT_ABS(v.growth, 1.01L, 1e-3L);
    assert_true(v.amplitude_last > v.amplitude_first);
}

/* Amplitudes 8, 6, 7, 4 over four windows: smaller at the end than at the start, but not
 * shrinking in every window (a noisy sustained oscillation looks like this): UNSTABLE; and
 * 8, 6, 5, 4 (shrinking in every window, above tolerance): UNDECIDED. */
static void test_judge_every_window_must_shrink(void **state)
{
    enum { w = 10, n = 4 * w };
    static const zw_real noisy[4] = {R(4.0), R(3.0), R(3.5), R(2.0)};
    static const zw_real decaying[4] = {R(4.0), R(3.0), R(2.5), R(2.0)};
    const zw_real *amplitude[2] = {noisy, decaying};
    const zw_sim_outcome expected[2] = {ZW_SIM_UNSTABLE, ZW_SIM_UNDECIDED};
    zw_real x[n];
    int c;
    size_t i;
    (void)state;
    for (c = 0; c < 2; ++c) {
        zw_sim_verdict v;
        /* +a, -a alternating within window i: peak-to-peak exactly 2 a */
        for (i = 0; i < n; ++i) x[i] = (i % 2 == 0 ? 1 : -1) * amplitude[c][i / w];
        v = judge(x, n, w, 4, R(1.0));
        assert_int_equal(v.outcome, expected[c]);
        assert_true(v.amplitude_first == R(8.0) && v.amplitude_last == R(4.0));
    }
}

/* A sustained oscillation, sin(pi k/2) = 0, 1, 0, -1, ...: every window has A = 2 exactly,
 * so the amplitudes do not shrink: UNSTABLE (not dying out), growth exactly 1. */
static void test_judge_constant_amplitude(void **state)
{
    enum { n = 400 };
    static const zw_real pattern[4] = {R(0.0), R(1.0), R(0.0), R(-1.0)};
    zw_real x[n];
    zw_sim_verdict v;
    size_t k;
    (void)state;
    for (k = 0; k < n; ++k) x[k] = R(1.0) + pattern[k % 4];
    v = judge(x, n, 40, 5, R(0.1));
    assert_int_equal(v.outcome, ZW_SIM_UNSTABLE);
    assert_true(v.amplitude_first == R(2.0) && v.amplitude_last == R(2.0));
    assert_true(v.growth == R(1.0));
}

/* A record that settled exactly (x constant: A_1 = A_w = 0, e.g. a stuck plant) is STABLE,
 * with growth 0; so is a sustained oscillation below the tolerance (A_w <= tolerance comes
 * first: what still moves is below it). */
static void test_judge_settled(void **state)
{
    enum { n = 200 };
    zw_real x[n];
    zw_sim_verdict v;
    size_t k;
    (void)state;
    for (k = 0; k < n; ++k) x[k] = k < 50 ? (zw_real)k : R(0.25);
    v = judge(x, n, 20, 4, R(0.0));
    assert_int_equal(v.outcome, ZW_SIM_STABLE);
    assert_true(v.amplitude_first == R(0.0) && v.amplitude_last == R(0.0));
    assert_true(v.growth == R(0.0));
    for (k = 50; k < n; ++k) x[k] = R(0.25) + (k % 2 == 0 ? R(1e-3) : R(0.0));
    v = judge(x, n, 20, 4, R(2e-3));
    assert_int_equal(v.outcome, ZW_SIM_STABLE);
    v = judge(x, n, 20, 4, R(5e-4));
    assert_int_equal(v.outcome, ZW_SIM_UNSTABLE);
}

/* No evidence, no STABLE: a record that never moved, or never by more than the tolerance
 * (a slow growth still inside it), is UNDECIDED, however quiet its last windows. */
static void test_judge_needs_motion(void **state)
{
    enum { n = 200 };
    zw_real x[n];
    zw_sim_verdict v;
    size_t k;
    (void)state;
    for (k = 0; k < n; ++k) x[k] = R(0.125);
    v = judge(x, n, 20, 4, R(0.0));
    assert_int_equal(v.outcome, ZW_SIM_UNDECIDED);
    v = judge(x, n, 20, 4, R(1.0));
    assert_int_equal(v.outcome, ZW_SIM_UNDECIDED);
    /* grows 1e-9 per sample up to 2e-7, then sits still: within a 1e-6 tolerance all along */
    for (k = 0; k < n; ++k) x[k] = (zw_real)(1e-9 * (double)(k < 100u ? k : 200u));
    v = judge(x, n, 20, 4, R(1e-6));
    assert_int_equal(v.outcome, ZW_SIM_UNDECIDED);
    v = judge(x, n, 20, 4, R(1e-8)); /* the same record, a tolerance it crossed: settled */
    assert_int_equal(v.outcome, ZW_SIM_STABLE);
}

/* Any NaN or inf: UNSTABLE, first_nonfinite its index (also before the judged windows),
 * growth +inf. */
static void test_judge_nonfinite(void **state)
{
    enum { n = 1000 };
    static zw_real x[n];
    const struct {
        size_t at;
        zw_real bad;
    } cases[] = {{500, R(NAN)}, {999, (zw_real)INFINITY}, {3, -(zw_real)INFINITY}, {0, R(NAN)}};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_sim_verdict v;
        damped_sine(x, n, 0.99L);
        x[cases[i].at] = cases[i].bad;
        if (cases[i].at == 0) x[700] = R(NAN); /* the first one counts */
        v = judge(x, n, 100, 4, R(1.0));
        assert_int_equal(v.outcome, ZW_SIM_UNSTABLE);
        assert_true(v.first_nonfinite == cases[i].at);
        assert_true(v.growth > ZW_REAL_MAX);
    }
}

/* The fail-safe verdict of a failed zw_sim_judge (sim.h): never STABLE. */
static void expect_judge_failsafe(const zw_sim_verdict *v)
{
    assert_int_equal(v->outcome, ZW_SIM_UNDECIDED);
    assert_true(isinf(v->amplitude_first) && isinf(v->amplitude_last) && isinf(v->growth));
    assert_true(v->first_nonfinite == 0u);
}

/* Argument errors (NaN / inf tolerances: ZW_ERR_NAN / ZW_ERR_INF); each writes the
 * fail-safe verdict over a STABLE one. */
static void test_judge_errors(void **state)
{
    zw_real x[100];
    zw_sim_verdict v, stable;
    size_t k;
    (void)state;
    for (k = 0; k < 100; ++k) x[k] = (k < 10u) ? R(1.0) : R(0.0); /* moved, then settled */
    EXPECT_OK(zw_sim_judge(x, 100, 10, 2, R(0.0), &stable));
    assert_int_equal(stable.outcome, ZW_SIM_STABLE);
    for (k = 0; k < 100; ++k) x[k] = (zw_real)k;
#define ZWT_JUDGE_ERROR(call, want)                                                              \
    do {                                                                                         \
        v = stable;                                                                              \
        EXPECT_STATUS(call, want);                                                               \
        expect_judge_failsafe(&v);                                                               \
    } while (0)
    ZWT_JUDGE_ERROR(zw_sim_judge(NULL, 100, 10, 2, R(0.0), &v), ZW_ERR_NULL);
    EXPECT_STATUS(zw_sim_judge(x, 100, 10, 2, R(0.0), NULL), ZW_ERR_NULL);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 0, 2, R(0.0), &v), ZW_ERR_ARG);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 10, 1, R(0.0), &v), ZW_ERR_ARG);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 10, 0, R(0.0), &v), ZW_ERR_ARG);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 34, 3, R(0.0), &v), ZW_ERR_ARG);  /* 102 > 100 */
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 0, 1, 2, R(0.0), &v), ZW_ERR_ARG);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, (size_t)-1, 2, R(0.0), &v), ZW_ERR_ARG); /* overflow */
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 10, 2, R(-1e-30), &v), ZW_ERR_ARG);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 10, 2, R(NAN), &v), ZW_ERR_NAN);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 10, 2, (zw_real)INFINITY, &v), ZW_ERR_INF);
    ZWT_JUDGE_ERROR(zw_sim_judge(x, 100, 10, 2, -(zw_real)INFINITY, &v), ZW_ERR_INF);
#undef ZWT_JUDGE_ERROR
    EXPECT_OK(zw_sim_judge(x, 100, 50, 2, R(0.0), &v)); /* exactly n */
    assert_int_equal(v.outcome, ZW_SIM_UNSTABLE);      /* a drift */
}

/* ---- zw_sim_init errors -------------------------------------------------------------------- */

static const zw_sim_segment g_good_schedule[2] = {{R(0.0), R(10.0), R(1.0)},
                                                  {R(0.5), R(20.0), R(2.0)}};
static const zw_sim_segment g_late_start[2] = {{R(0.1), R(10.0), R(1.0)},
                                               {R(0.5), R(20.0), R(2.0)}};
static const zw_sim_segment g_repeated[3] = {
    {R(0.0), R(10.0), R(1.0)}, {R(0.2), R(20.0), R(2.0)}, {R(0.2), R(30.0), R(3.0)}};
static const zw_sim_segment g_decreasing[3] = {
    {R(0.0), R(10.0), R(1.0)}, {R(0.4), R(20.0), R(2.0)}, {R(0.2), R(30.0), R(3.0)}};
static const zw_sim_segment g_nan_gain[2] = {{R(0.0), R(10.0), R(1.0)},
                                             {R(0.5), R(NAN), R(2.0)}};

/* Valid parameters for every effect (only the flags in `effects` are read). */
static zw_sim_scene scene_valid(unsigned effects)
{
    zw_sim_scene sc = scene_busy(false);
    sc.effects = effects;
    sc.schedule = g_good_schedule;
    return sc;
}

static void expect_init(const zw_sim_scene *sc, zw_status want, const char *what)
{
    zw_sim sim, before;
    zw_status got;
    memset(&sim, 0xA5, sizeof sim);
    memcpy(&before, &sim, sizeof sim);
    got = zw_sim_init(&sim, sc);
    if (got != want) {
        print_error("zw_sim_init(%s) returned %s, expected %s\n", what, zw_status_name(got),
                    zw_status_name(want));
        fail();
    }
    if (want != ZW_OK && memcmp(&sim, &before, sizeof sim) != 0) {
        print_error("zw_sim_init(%s) wrote *sim on error\n", what);
        fail();
    }
}

/* The step's sample index near the top of its range: t_step / T below 2^p (p = 24 float, 53
 * double) is found exactly, from 2^p on (and past SIZE_MAX: 2^70) zw_sim_init refuses it
 * with ZW_ERR_RANGE instead of searching forever (the old (size_t) cast of 2^70 was UB and
 * hung 16/32-bit targets).  No run reaches such an index, so the index itself is read from
 * the zw_sim (k_step): k T >= t_step > (k - 1) T, in zw_real as the loop compares. */
static void test_step_index_range(void **state)
{
    const int p = ZWT_MANT_DIG;
    const zw_real top = ZW_LDEXP(R(1.0), p);   /* 2^p */
    const struct {
        zw_real T, steps;   /* t_step = steps * T, exact for dyadic T */
        size_t want;
    } exact[] = {
        {T_DYADIC, top - R(1.0), (size_t)(top - R(1.0))},               /* largest accepted */
        {T_DYADIC, ZW_LDEXP(R(1.0), p - 1) - R(0.5), (size_t)ZW_LDEXP(R(1.0), p - 1)},   /* between */
        {T_DYADIC, R(3.0), 3},
    };
    const zw_real refused[] = {top, ZW_LDEXP(R(1.0), 70)};
    /* Non-dyadic T: t_step / T rounds; the index must still be the loop's first sample. */
    const zw_real periods[] = {R(0.001), R(0.0003), R(1e-6) / R(3.0)};
    zw_sim sim;
    size_t i, j;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(exact); ++i) {
        zw_sim_scene sc = scene_linear(R(0.125), R(2.0), exact[i].T, R(4.0), R(2.0));
        sc.t_step = exact[i].steps * exact[i].T;
        EXPECT_OK(zw_sim_init(&sim, &sc));
        assert_true(sim.k_step == exact[i].want);
    }
    for (i = 0; i < ZWT_ARRAY_LEN(refused); ++i) {
        zw_sim_scene sc = scene_linear(R(0.125), R(2.0), T_DYADIC, R(4.0), R(2.0));
        sc.t_step = refused[i] * T_DYADIC;
        expect_init(&sc, ZW_ERR_RANGE, "t_step / T >= 2^p");
    }
    {
        zw_sim_scene sc = scene_linear(R(0.125), R(2.0), T_DYADIC, R(4.0), R(2.0));
        sc.t_step = ZW_REAL_MAX;   /* t_step / T overflows to +inf: finite, so refused */
        expect_init(&sc, ZW_ERR_RANGE, "t_step = ZW_REAL_MAX");
        sc.t_step = (zw_real)INFINITY;   /* no step */
        EXPECT_OK(zw_sim_init(&sim, &sc));
        assert_true(sim.k_step == SIZE_MAX);
    }
    for (i = 0; i < ZWT_ARRAY_LEN(periods); ++i) {
        const zw_real T = periods[i];
        for (j = 0; j < 8; ++j) {
            /* q from 2^(p-1) to just below 2^p, off the integers */
            const zw_real steps = top * (R(0.5) + R(0.0625) * (zw_real)j) + R(0.37) * (zw_real)j;
            zw_sim_scene sc = scene_linear(R(0.125), R(2.0), T, R(4.0), R(2.0));
            size_t k;
            sc.t_step = steps * T;
            if (!(sc.t_step / T < top)) continue;
            EXPECT_OK(zw_sim_init(&sim, &sc));
            k = sim.k_step;
            assert_true(k >= 1 && (zw_real)k * T >= sc.t_step && (zw_real)(k - 1) * T < sc.t_step);
        }
    }
}

/* zw_sim_set_gains: the next samples use the new gains, exactly as a run that had them
 * from that sample on (a schedule switching there); errors leave the run untouched. */
static void test_set_gains(void **state)
{
    static const zw_sim_segment switched[2] = {{R(0.0), R(0.0), R(0.0)}, {R(0.25), R(40.0), R(0.5)}};
    zw_sim_scene sc = scene_linear(R(0.1), R(3.0), R(0.01), R(0.0), R(0.0));
    zw_sim a, b, before;
    zw_real xa[100], xb[100];
    zw_sim_trace ta, tb;
    (void)state;
    sc.x_init = R(0.01);
    sc.effects = ZW_SIM_DELAY | ZW_SIM_AVERAGE | ZW_SIM_TUSTIN;
    sc.delay_samples = 1;
    sc.average_samples = 3;
    EXPECT_OK(zw_sim_init(&a, &sc));
    memset(&ta, 0, sizeof ta);
    ta.x = xa;
    EXPECT_OK(zw_sim_run(&a, 25, &ta));   /* t = 0 .. 0.24 s with (0, 0) */
    EXPECT_OK(zw_sim_set_gains(&a, R(40.0), R(0.5)));
    ta.x = xa + 25;
    EXPECT_OK(zw_sim_run(&a, 75, &ta));
    sc.effects |= ZW_SIM_SCHEDULE;
    sc.schedule = switched;
    sc.schedule_len = 2;
    EXPECT_OK(zw_sim_init(&b, &sc));
    memset(&tb, 0, sizeof tb);
    tb.x = xb;
    EXPECT_OK(zw_sim_run(&b, 100, &tb));
    assert_memory_equal(xa, xb, sizeof xa);
    assert_true(xa[99] != R(0.01)); /* the gains moved it */
    memcpy(&before, &a, sizeof a);
    EXPECT_STATUS(zw_sim_set_gains(&a, R(NAN), R(0.0)), ZW_ERR_NAN);
    EXPECT_STATUS(zw_sim_set_gains(&a, R(1.0), (zw_real)INFINITY), ZW_ERR_INF);
    assert_memory_equal(&a, &before, sizeof a);
    EXPECT_STATUS(zw_sim_set_gains(&b, R(1.0), R(0.0)), ZW_ERR_ARG); /* a schedule's gains */
    EXPECT_STATUS(zw_sim_set_gains(NULL, R(1.0), R(0.0)), ZW_ERR_NULL);
}

static void test_init_errors(void **state)
{
    /* every effect that goes with the others (AVERAGE excludes VELOCITY_FILTER,
     * ACTUATOR_LAG excludes FRICTION, KNOB excludes SCHEDULE) */
    const unsigned others = ZW_SIM_AVERAGE | ZW_SIM_ACTUATOR_LAG;
    const unsigned all = ZW_SIM_ALL_EFFECTS & ~(unsigned)ZW_SIM_KNOB & ~others;
    const unsigned cont = ZW_SIM_FRICTION;
    const unsigned lagged = (ZW_SIM_ALL_EFFECTS & ~(unsigned)(ZW_SIM_KNOB | ZW_SIM_FRICTION |
                                                             ZW_SIM_VELOCITY_FILTER)) |
                            others;
    zw_sim_scene sc;
    zw_sim sim;
    (void)state;

#define CASE(flags, mutation, want)                                                              \
    do {                                                                                         \
        sc = scene_valid(flags);                                                                 \
        mutation;                                                                                \
        expect_init(&sc, want, #flags ": " #mutation);                                           \
    } while (0)

    /* the valid scenes themselves, and edges that are valid */
    CASE(0u, (void)0, ZW_OK);
    CASE(all, (void)0, ZW_OK);
    CASE(ZW_SIM_ALL_EFFECTS & ~(unsigned)ZW_SIM_SCHEDULE & ~others, (void)0, ZW_OK);
    CASE(lagged, (void)0, ZW_OK);
    CASE(ZW_SIM_AVERAGE, sc.average_samples = ZW_SIM_MAX_AVERAGE, ZW_OK);
    CASE(ZW_SIM_AVERAGE | ZW_SIM_TUSTIN, sc.average_samples = 1, ZW_OK);
    CASE(ZW_SIM_ACTUATOR_LAG, sc.substeps = 4, ZW_OK); /* h / tau = 1.25 */
    CASE(0u, sc.substeps = 0, ZW_OK); /* ignored without a continuous effect */
    CASE(ZW_SIM_DELAY, sc.delay_samples = ZW_SIM_MAX_DELAY, ZW_OK);
    CASE(cont, sc.substeps = ZW_SIM_MAX_SUBSTEPS, ZW_OK);
    CASE(cont, sc.stiction = sc.coulomb, ZW_OK);
    CASE(ZW_SIM_KNOB, sc.K = R(NAN), ZW_OK); /* the knob sets the gains */
    CASE(ZW_SIM_SCHEDULE, sc.B = (zw_real)INFINITY, ZW_OK);
    CASE(ZW_SIM_SCHEDULE, sc.schedule_len = 1, ZW_OK);
    CASE(ZW_SIM_KNOB, sc.knob.count = 2, ZW_OK);
    CASE(ZW_SIM_HAND, sc.hand.t_release = (zw_real)INFINITY, ZW_OK);
    CASE(ZW_SIM_HAND, sc.hand.speed = (zw_real)INFINITY, ZW_OK);

    /* the plant, as zw_device_init */
    CASE(all, sc.m = R(NAN), ZW_ERR_NAN);
    CASE(all, sc.b = R(NAN), ZW_ERR_NAN);
    CASE(all, sc.T = R(NAN), ZW_ERR_NAN);
    CASE(all, sc.m = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(all, sc.b = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(all, sc.T = -(zw_real)INFINITY, ZW_ERR_INF);
    CASE(all, sc.m = R(0.0), ZW_ERR_MASS);
    CASE(all, sc.m = R(-0.1), ZW_ERR_MASS);
    CASE(all, sc.T = R(0.0), ZW_ERR_PERIOD);
    CASE(all, sc.T = R(-0.01), ZW_ERR_PERIOD);
    CASE(all, sc.b = R(-1.0), ZW_ERR_DAMPING);
    CASE(all, sc.m = ZW_REAL_MIN / R(4.0), ZW_ERR_RANGE); /* subnormal */

    /* NaN in any field that is read, inf where only finite values mean anything */
    CASE(0u, sc.K = R(NAN), ZW_ERR_NAN);
    CASE(0u, sc.B = -(zw_real)INFINITY, ZW_ERR_INF);
    CASE(0u, sc.x_init = R(NAN), ZW_ERR_NAN);
    CASE(0u, sc.v_init = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(0u, sc.x_eq_after = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(0u, sc.t_step = R(NAN), ZW_ERR_NAN);
    CASE(0u, sc.t_step = -(zw_real)INFINITY, ZW_ERR_INF);
    CASE(0u, sc.t_step = R(-1.0), ZW_ERR_ARG);
    CASE(ZW_SIM_FRICTION, sc.coulomb = R(NAN), ZW_ERR_NAN);
    CASE(ZW_SIM_QUANTIZATION, sc.counts_per_unit = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(ZW_SIM_WALL, sc.wall.position = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(ZW_SIM_HAND, sc.hand.speed = R(NAN), ZW_ERR_NAN);
    CASE(ZW_SIM_HAND, sc.hand.t_release = -(zw_real)INFINITY, ZW_ERR_INF);
    CASE(ZW_SIM_HAND, sc.hand.to = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(ZW_SIM_KNOB, sc.knob.first = R(NAN), ZW_ERR_NAN);
    CASE(ZW_SIM_SCHEDULE, sc.schedule = g_nan_gain, ZW_ERR_NAN);
    /* +inf that means "never" / "at once", and fields of effects that are off: fine */
    CASE(0u, sc.t_step = (zw_real)INFINITY, ZW_OK);
    CASE(0u, (sc.coulomb = R(NAN), sc.wall.side = 7, sc.knob.count = -1), ZW_OK);
    CASE(0u, (sc.schedule = NULL, sc.delay_samples = 0, sc.hand.speed = R(NAN)), ZW_OK);

    /* flags */
    CASE(0u, sc.effects = 1u << 12, ZW_ERR_ARG);
    CASE(ZW_SIM_AVERAGE | ZW_SIM_VELOCITY_FILTER, (void)0, ZW_ERR_ARG);  /* one filter */
    CASE(ZW_SIM_ACTUATOR_LAG | ZW_SIM_FRICTION, (void)0, ZW_ERR_ARG);
    CASE(ZW_SIM_AVERAGE, sc.average_samples = 0, ZW_ERR_ARG);
    CASE(ZW_SIM_AVERAGE, sc.average_samples = ZW_SIM_MAX_AVERAGE + 1, ZW_ERR_ARG);
    CASE(ZW_SIM_ACTUATOR_LAG, sc.actuator_tau = R(0.0), ZW_ERR_ARG);
    CASE(ZW_SIM_ACTUATOR_LAG, sc.substeps = 1, ZW_ERR_ARG); /* h / tau = 5 > ZW_SIM_RK4_LIMIT */
    CASE(ZW_SIM_ACTUATOR_LAG, sc.actuator_tau = R(NAN), ZW_ERR_NAN);
    CASE(ZW_SIM_ACTUATOR_LAG, sc.actuator_tau = (zw_real)INFINITY, ZW_ERR_INF);
    CASE(0u, (sc.average_samples = 0, sc.actuator_tau = R(NAN)), ZW_OK); /* not read when off */
    CASE(0u, sc.effects = ZW_SIM_DELAY | 0x80000000u, ZW_ERR_ARG);
    CASE(ZW_SIM_KNOB | ZW_SIM_SCHEDULE, (void)0, ZW_ERR_ARG);

    /* each effect's domain */
    CASE(ZW_SIM_DELAY, sc.delay_samples = 0, ZW_ERR_ARG);
    CASE(ZW_SIM_DELAY, sc.delay_samples = -1, ZW_ERR_ARG);
    CASE(ZW_SIM_DELAY, sc.delay_samples = ZW_SIM_MAX_DELAY + 1, ZW_ERR_ARG);
    CASE(ZW_SIM_FRICTION, sc.substeps = 0, ZW_ERR_ARG);
    CASE(ZW_SIM_FRICTION, sc.substeps = ZW_SIM_MAX_SUBSTEPS + 1, ZW_ERR_ARG);
    CASE(ZW_SIM_HAND, sc.substeps = 0, ZW_ERR_ARG);
    CASE(ZW_SIM_HAND, sc.substeps = -3, ZW_ERR_ARG);
    CASE(ZW_SIM_FRICTION, sc.stiction = R(0.1), ZW_ERR_ARG); /* < coulomb = 0.2 */
    CASE(ZW_SIM_FRICTION, sc.coulomb = R(-0.1), ZW_ERR_ARG);
    CASE(ZW_SIM_QUANTIZATION, sc.counts_per_unit = R(0.0), ZW_ERR_ARG);
    CASE(ZW_SIM_SATURATION, sc.force_max = R(0.0), ZW_ERR_ARG);
    CASE(ZW_SIM_VELOCITY_FILTER, sc.cutoff_hz = R(-1.0), ZW_ERR_ARG);
    CASE(ZW_SIM_WALL, sc.wall.side = 0, ZW_ERR_ARG);
    CASE(ZW_SIM_WALL, sc.wall.stiffness = R(0.0), ZW_ERR_ARG);
    CASE(ZW_SIM_HAND, sc.hand.speed = R(0.0), ZW_ERR_ARG);
    CASE(ZW_SIM_HAND, sc.hand.t_release = sc.hand.t_grasp, ZW_ERR_ARG);
    CASE(ZW_SIM_HAND, sc.hand.mass = R(-0.01), ZW_ERR_ARG);
    CASE(ZW_SIM_KNOB, sc.knob.count = 1, ZW_ERR_ARG);
    CASE(ZW_SIM_KNOB, sc.knob.count = 0, ZW_ERR_ARG);
    CASE(ZW_SIM_KNOB, sc.knob.pitch = R(0.0), ZW_ERR_ARG);
    CASE(ZW_SIM_SCHEDULE, sc.schedule = g_late_start, ZW_ERR_ARG);
    CASE(ZW_SIM_SCHEDULE, (sc.schedule = g_repeated, sc.schedule_len = 3), ZW_ERR_ARG);
    CASE(ZW_SIM_SCHEDULE, (sc.schedule = g_decreasing, sc.schedule_len = 3), ZW_ERR_ARG);
    CASE(ZW_SIM_SCHEDULE, sc.schedule_len = 0, ZW_ERR_ARG);
    /* a missing required array */
    CASE(ZW_SIM_SCHEDULE, sc.schedule = NULL, ZW_ERR_NULL);
    CASE(ZW_SIM_SCHEDULE, (sc.schedule = NULL, sc.schedule_len = 0), ZW_ERR_NULL);
#undef CASE

    /* NULL arguments */
    sc = scene_valid(0u);
    memset(&sim, 0xA5, sizeof sim);
    {
        zw_sim before;
        zw_sim_trace tr;
        memcpy(&before, &sim, sizeof sim);
        EXPECT_STATUS(zw_sim_init(NULL, &sc), ZW_ERR_NULL);
        EXPECT_STATUS(zw_sim_init(&sim, NULL), ZW_ERR_NULL);
        assert_memory_equal(&sim, &before, sizeof sim);
        memset(&tr, 0, sizeof tr);
        EXPECT_OK(zw_sim_init(&sim, &sc));
        EXPECT_STATUS(zw_sim_run(NULL, 1, &tr), ZW_ERR_NULL);
        EXPECT_STATUS(zw_sim_run(&sim, 1, NULL), ZW_ERR_NULL);
    }
}

/* ---- a linear scene of paper Fig. 15 kind ------------------------------------------------- */

/* m = 0.1 kg, b = 30 N s/m, T = 0.01 s (delta = 3), the equilibrium steps from 0 to 1 m at
 * t = 0.  At beta = 4 the legacy region (hyperbola only) allows alpha < f(4) ~ 8.40, the exact
 * one only alpha < L(4) = 4 (1 + e)/d12 - 8 ~ 7.13.  alpha = 6.8 is stable (spectral radius
 * ~0.926): the response decays by ~0.926^100 ~ 5e-4 before the judged windows (samples
 * 100 .. 199, 4 x 25) and to ~1e-6 by the last, under tolerance 1e-4.  alpha = 7.3, legacy-
 * stable like the paper's points 6, 8, 10, 12, is unstable: dominant pole ~ -1.096 (real),
 * the next ~ -0.82, whose share of the windows (samples 200 .. 299) is ~0.75^200: the
 * envelope's growth per sample is the spectral radius to ~1e-6 (plus rounding). */
static void test_fig15_kind(void **state)
{
    const zw_real m = R(0.1), b = R(30.0), T = R(0.01), beta = R(4.0);
    const zw_real alphas[2] = {R(6.8), R(7.3)};
    zw_device d;
    int i;
    (void)state;
    EXPECT_OK(zw_device_init(&d, m, b, T));
    for (i = 0; i < 2; ++i) {
        const zw_real K = alphas[i] * d.k_scale, B = beta * d.b_scale;
        const bool stable = i == 0;
        const size_t n = stable ? 200 : 300;
        zw_verdict exact, legacy;
        zw_sim_scene sc = scene_linear(m, b, T, K, B);
        zw_sim_verdict v;
        zw_real rho;
        rec r;
        EXPECT_OK(zw_device_check(&d, K, B, &exact));
        EXPECT_OK(zw_device_check_region(ZW_REGION_LEGACY, &d, K, B, &legacy));
        EXPECT_OK(zw_device_spectral_radius(&d, K, B, &rho));
        assert_true(legacy.stable && !legacy.marginal);
        assert_true(exact.stable == stable && !exact.marginal);
        if (!stable) assert_int_equal(exact.deciding, ZW_BOUND_LINE);
        sc.x_eq_after = R(1.0);
        simulate(&sc, n, &r);
        v = judge(r.x, n, 25, 4, R(1e-4));
        printf("    delta = 3, alpha = %.2f, beta = 4: rho = %.6f, simulated %s, growth %.6f, "
               "A_1 = %.3g, A_4 = %.3g\n",
               (double)alphas[i], (double)rho, outcome_name(v.outcome), (double)v.growth,
               (double)v.amplitude_first, (double)v.amplitude_last);
        if (stable) {
            assert_int_equal(v.outcome, ZW_SIM_STABLE);
            assert_true(v.amplitude_last < v.amplitude_first);
            EXPECT_ABS(r.x[n - 1], 1.0L, 1e-4L);
        } else {
            assert_int_equal(v.outcome, ZW_SIM_UNSTABLE);
            EXPECT_REL(v.growth, rho, 1e-4L);
        }
        rec_free(&r);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(test_exact_step_closed_form, free_all),
        cmocka_unit_test_teardown(test_reference_step, free_all),
        cmocka_unit_test_teardown(test_quantization, free_all),
        cmocka_unit_test_teardown(test_friction_stiction_holds, free_all),
        cmocka_unit_test_teardown(test_friction_breakaway, free_all),
        cmocka_unit_test_teardown(test_friction_sliding_stops, free_all),
        cmocka_unit_test_teardown(test_friction_reversals_exact, free_all),
        cmocka_unit_test_teardown(test_quantized_settled_velocity_not_subnormal, free_all),
        cmocka_unit_test_teardown(test_delay, free_all),
        cmocka_unit_test_teardown(test_saturation, free_all),
        cmocka_unit_test_teardown(test_velocity_filter, free_all),
        cmocka_unit_test_teardown(test_wall_force, free_all),
        cmocka_unit_test_teardown(test_wall_steady_penetration, free_all),
        cmocka_unit_test_teardown(test_knob_map, free_all),
        cmocka_unit_test_teardown(test_knob_diverging, free_all),
        cmocka_unit_test_teardown(test_knob_continuity, free_all),
        cmocka_unit_test_teardown(test_knob_planned_vs_measured, free_all),
        cmocka_unit_test_teardown(test_schedule, free_all),
        cmocka_unit_test_teardown(test_hand_force_path, free_all),
        cmocka_unit_test_teardown(test_hand_mass, free_all),
        cmocka_unit_test_teardown(test_hand_step_speed_inf, free_all),
        cmocka_unit_test_teardown(test_hand_integrator_matches_exact, free_all),
        cmocka_unit_test_teardown(test_resumable, free_all),
        cmocka_unit_test_teardown(test_linear_loops_agree, free_all),
        cmocka_unit_test_teardown(test_partial_trace, free_all),
        cmocka_unit_test_teardown(test_judge_decaying, free_all),
        cmocka_unit_test_teardown(test_judge_growing, free_all),
        cmocka_unit_test_teardown(test_judge_constant_amplitude, free_all),
        cmocka_unit_test_teardown(test_judge_every_window_must_shrink, free_all),
        cmocka_unit_test_teardown(test_judge_settled, free_all),
        cmocka_unit_test_teardown(test_judge_needs_motion, free_all),
        cmocka_unit_test_teardown(test_judge_nonfinite, free_all),
        cmocka_unit_test_teardown(test_judge_errors, free_all),
        cmocka_unit_test_teardown(test_set_gains, free_all),
        cmocka_unit_test_teardown(test_init_errors, free_all),
        cmocka_unit_test(test_step_index_range),
        cmocka_unit_test_teardown(test_fig15_kind, free_all),
    };
    printf("zwidth C tests: sim (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("sim_" ZW_REAL_NAME, tests, NULL, NULL);
}
