/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* test_loop_limits.c - limits of the general loop (loop_limits.h).
 *
 * The ideal loop (zero spec) through the general path against the closed forms of
 * extremes.h (themselves tested against 60-digit references in test_extremes.c and
 * tests/py): never above, and within GAP_U unit roundoffs times the scale of the gains
 * (alpha_scale below; the general path certifies, i.e. subtracts its error bound, so it
 * sits below the closed form by about that bound).  The z = -1 line and the boundary
 * curve against the paper's line L and hyperbola f in long double.  Errors and fail-safe
 * outputs.  The general loops are checked against mpmath in
 * tests/py/test_loop_limits_reference.py.
 */
#include "zw_test.h"

/* The checks' scratch (loop.h): static, as a drive keeps it; tests run one at a time. */
static zw_loop_workspace g_ws;

/* Measured worst gap of the ideal loop: ~2e4 u x alpha_scale (double and float: the
 * certified limit sits below the truth by the evaluation's error bound, ~190 u relative to
 * the terms of the crossing condition, times the crossing's conditioning); 2x slack. */
#define GAP_U 40000.0L

static long double alpha_scale(long double delta, long double beta)
{
    long double d = delta < 1.0L ? delta : 1.0L;
    return (1.0L + delta + fabsl(beta)) / sqrtl(d);
}

static void ideal_loop(zw_real delta, zw_coeffs *c, zw_loop *loop)
{
    zw_loop_spec spec;
    memset(&spec, 0, sizeof spec);
    *c = zwt_coeffs(delta);
    EXPECT_OK(zw_loop_init(loop, c, &spec));
}

/* The deltas of the brief: tiny, paper's, critical +- ulps, large. */
static const zw_real test_deltas[] = {
    R(1e-6), R(1e-3), R(0.013), R(0.5), R(1.0), R(2.0), R(5.12241), R(10.0), R(100.0), R(1e3),
};

static void deltas_with_critical(zw_real *out, size_t *n)
{
    const zw_real crit[] = {ZW_DELTA0, ZW_DELTA1, ZW_DELTA2};
    size_t i, k = 0;
    for (i = 0; i < ZWT_ARRAY_LEN(test_deltas); ++i) out[k++] = test_deltas[i];
    for (i = 0; i < ZWT_ARRAY_LEN(crit); ++i) {
        out[k++] = ZWT_DOWN(ZWT_DOWN(crit[i]));
        out[k++] = crit[i];
        out[k++] = ZWT_UP(ZWT_UP(crit[i]));
    }
    *n = k;
}

static void test_ideal_alpha_max_matches_closed_form(void **state)
{
    zw_real deltas[32];
    size_t nd, i;
    long double worst = 0.0L;
    (void)state;
    deltas_with_critical(deltas, &nd);
    for (i = 0; i < nd; ++i) {
        zw_coeffs c;
        zw_loop loop;
        zw_extremes x;
        int k;
        ideal_loop(deltas[i], &c, &loop);
        EXPECT_OK(zw_extremes_compute(&c, &x));
        for (k = 1; k < 12; ++k) {
            zw_real beta = -c.delta + (x.beta_mmax + c.delta) * ((zw_real)k / R(12.0));
            zw_real got, want;
            long double gap;
            EXPECT_OK(zw_loop_alpha_max(&loop, &g_ws, beta, &got));
            EXPECT_OK(zw_alpha_max(&c, beta, &want));
            /* never above (the closed form itself is within a few ulps of the truth) */
            EXPECT_TRUE_MSG(got <= want * (R(1.0) + TOL(8)), "delta %g beta %g: %.17g > %.17g",
                            (double)c.delta, (double)beta, (double)got, (double)want);
            gap = ((long double)want - (long double)got) / alpha_scale((long double)c.delta, (long double)beta) / TOLL(1);
            if (gap > worst) worst = gap;
            EXPECT_TRUE_MSG(gap <= GAP_U, "delta %g beta %g: gap %.0Lf u x scale", (double)c.delta,
                            (double)beta, gap);
        }
    }
    print_message("ideal alpha_max via the general path: worst gap %.0Lf u x scale\n", worst);
}

static void test_ideal_extremes_match_closed_form(void **state)
{
    zw_real deltas[32];
    size_t nd, i;
    (void)state;
    deltas_with_critical(deltas, &nd);
    for (i = 0; i < nd; ++i) {
        zw_coeffs c;
        zw_loop loop;
        zw_extremes want;
        zw_loop_extremes got;
        long double s, bmax_tol, amax_tol;
        ideal_loop(deltas[i], &c, &loop);
        EXPECT_OK(zw_extremes_compute(&c, &want));
        EXPECT_OK(zw_loop_extremes_compute(&loop, &g_ws, &got));
        s = alpha_scale((long double)c.delta, (long double)want.beta_at_alpha_mmax);
        EXPECT_TRUE_MSG(got.alpha_mmax <= want.alpha_mmax * (R(1.0) + TOL(8)), "delta %g",
                        (double)c.delta);
        /* At delta1 the hyperbola's flat top is the corner: alpha_max(beta) is flat on one
         * side within its own noise, so the golden section stops ~sqrt(noise) off in beta
         * (measured 3e-11 relative in double). */
        amax_tol = ZW_FABS(c.delta - ZW_DELTA1) < R(0.01) ? PREC(1e-9L, 1e-3L) * (long double)want.alpha_mmax
                                                           : GAP_U * TOLL(1) * s;
        EXPECT_TRUE_MSG((long double)want.alpha_mmax - (long double)got.alpha_mmax <= amax_tol,
                        "delta %g: alpha_mmax %.17g vs %.17g", (double)c.delta,
                        (double)got.alpha_mmax, (double)want.alpha_mmax);
        EXPECT_TRUE_MSG(got.alpha_p_max <= want.alpha_p_max * (R(1.0) + TOL(8)) &&
                            (long double)want.alpha_p_max - (long double)got.alpha_p_max <= GAP_U * TOLL(1) * s,
                        "delta %g: alpha_p_max %.17g vs %.17g", (double)c.delta,
                        (double)got.alpha_p_max, (double)want.alpha_p_max);
        /* the beta range at alpha -> 0+: inside (-delta, beta_mmax), and close */
        EXPECT_TRUE_MSG(got.beta_mmin >= -c.delta && got.beta_mmax <= want.beta_mmax * (R(1.0) + TOL(8)),
                        "delta %g: (%g, %g)", (double)c.delta, (double)got.beta_mmin,
                        (double)got.beta_mmax);
        /* Just below delta0 the hyperbola meets alpha = 0 with its pair next to z = -1 (at
         * delta0 the line and the hyperbola meet there): the crossing condition vanishes
         * structurally at z = -1; the end is then pushed out by bisection on alpha_max > 0
         * (measured, relative: 4e-9 in double at delta0 - 2 ulps, 1e-3 in float). */
        bmax_tol = ZW_FABS(c.delta - ZW_DELTA0) < R(0.01) ? PREC(1e-8L, 3e-3L) * (long double)want.beta_mmax
                                                           : GAP_U * TOLL(1) * s;
        EXPECT_TRUE_MSG((long double)got.beta_mmin + (long double)c.delta <= GAP_U * TOLL(1) * s &&
                            (long double)want.beta_mmax - (long double)got.beta_mmax <= bmax_tol,
                        "delta %g: (%.17g, %.17g) vs (-delta, %.17g)", (double)c.delta,
                        (double)got.beta_mmin, (double)got.beta_mmax, (double)want.beta_mmax);
        /* where the max sits: the smooth top is flat (beta known to ~sqrt(gap)), a corner
         * is sharp; 1e-3 of the range covers both in float */
        EXPECT_NEAR(got.beta_at_alpha_mmax, want.beta_at_alpha_mmax,
                    (long double)PREC(1e-5, 1e-2) * ((long double)want.beta_mmax + (long double)c.delta), 0);
    }
}

static void test_ideal_beta_interval_matches_closed_form(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(test_deltas); ++i) {
        zw_coeffs c;
        zw_loop loop;
        zw_extremes x;
        int k;
        ideal_loop(test_deltas[i], &c, &loop);
        EXPECT_OK(zw_extremes_compute(&c, &x));
        for (k = 1; k < 6; ++k) {
            zw_real alpha = x.alpha_mmax * ((zw_real)k / R(6.0));
            zw_real lo, hi, wlo, whi;
            bool ne, wne;
            long double s = alpha_scale((long double)c.delta, (long double)x.beta_mmax) * (1.0L + (long double)c.delta);
            EXPECT_OK(zw_loop_beta_interval(&loop, &g_ws, alpha, &lo, &hi, &ne));
            EXPECT_OK(zw_beta_interval(&c, alpha, &wlo, &whi, &wne));
            EXPECT_TRUE_MSG(ne && wne, "delta %g alpha %g", (double)c.delta, (double)alpha);
            /* inside the true interval (up to the closed form's ulps), and close to it */
            EXPECT_TRUE_MSG(lo >= wlo - TOL(8) * (ZW_FABS(wlo) + c.delta) &&
                                hi <= whi + TOL(8) * ZW_FABS(whi),
                            "delta %g alpha %g: (%.17g, %.17g) vs (%.17g, %.17g)", (double)c.delta,
                            (double)alpha, (double)lo, (double)hi, (double)wlo, (double)whi);
            EXPECT_TRUE_MSG((long double)lo - (long double)wlo <= GAP_U * TOLL(1) * s &&
                                (long double)whi - (long double)hi <= GAP_U * TOLL(1) * s,
                            "delta %g alpha %g: (%.17g, %.17g) vs (%.17g, %.17g)", (double)c.delta,
                            (double)alpha, (double)lo, (double)hi, (double)wlo, (double)whi);
        }
    }
}

/* The z = -1 line is the paper's L: d12 alpha + 2 d12 beta = 4 (1 + e); the curve at
 * theta lies on the hyperbola alpha = f(beta) (long double, factored form of math.md). */
static void test_ideal_boundary_is_line_and_hyperbola(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(test_deltas); ++i) {
        zw_coeffs c;
        zw_loop loop;
        zw_real c0, ca, cb;
        zwt_ref r;
        int k;
        ideal_loop(test_deltas[i], &c, &loop);
        r = zwt_reference((long double)c.delta);
        EXPECT_OK(zw_loop_boundary_line(&loop, ZW_LOOP_BOUNDARY_Z_MINUS1, &c0, &ca, &cb));
        EXPECT_REL((long double)cb / (long double)ca, 2.0L, TOLL(4));
        EXPECT_REL(-(long double)c0 / (long double)ca, 4.0L * (1.0L + r.e) / r.d12, TOLL(64));
        EXPECT_OK(zw_loop_boundary_line(&loop, ZW_LOOP_BOUNDARY_Z_PLUS1, &c0, &ca, &cb));
        assert_true(c0 == R(0.0) && cb == R(0.0) && ca != R(0.0));
        for (k = 1; k < 16; ++k) {
            zw_real th = R(3.14159265358979) * ((zw_real)k / R(16.0)), a, b;
            long double f, x, bl;
            EXPECT_OK(zw_loop_boundary_point(&loop, th, &a, &b));
            bl = (long double)b;
            x = bl + (long double)c.delta;
            f = r.s * x * (2.0L - r.c2 * bl) / ((r.c1 * bl + 2.0L) * r.c2);
            /* f is proportional to beta + delta: an error of b near -delta moves it by f / x */
            EXPECT_TRUE_MSG(fabsl((long double)a - f) <=
                                TOLL(2000) * (1.0L + fabsl(f) + fabsl(bl) * (1.0L + fabsl(f / x))),
                            "delta %g theta %g: (%.17g, %.17g), f = %.17Lg", (double)c.delta, (double)th, (double)a, (double)b, f);
        }
    }
}

/* Delay and filters only shrink the ideal loop's region here (a sanity property of these
 * plants, checked against mpmath in Python): K_mmax with d = 1 is below the ideal one. */
static void test_delay_lowers_k_mmax(void **state)
{
    zw_coeffs c = zwt_coeffs(R(5.12241));
    zw_loop ideal, delayed;
    zw_loop_spec spec;
    zw_loop_extremes xi, xd;
    (void)state;
    memset(&spec, 0, sizeof spec);
    EXPECT_OK(zw_loop_init(&ideal, &c, &spec));
    spec.delay = 1u;
    EXPECT_OK(zw_loop_init(&delayed, &c, &spec));
    EXPECT_OK(zw_loop_extremes_compute(&ideal, &g_ws, &xi));
    EXPECT_OK(zw_loop_extremes_compute(&delayed, &g_ws, &xd));
    /* paper's drive: ratio 4.6187 (mpmath reference, tests/py) */
    EXPECT_NEAR(xi.alpha_mmax / xd.alpha_mmax, 4.6187, 2e-3, 0);
}

/* Tustin with an even moving average: p(-1) = 0 for all gains, nothing is stable. */
static void test_tustin_even_average_is_never_stable(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0));
    zw_loop loop;
    zw_loop_spec spec;
    zw_loop_extremes x;
    zw_real c0, ca, cb, a;
    zw_loop_beta_set set;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.differentiator = ZW_DIFF_TUSTIN;
    spec.filter = ZW_VFILTER_AVERAGE;
    spec.average = 4u;
    EXPECT_OK(zw_loop_init(&loop, &c, &spec));
    EXPECT_OK(zw_loop_boundary_line(&loop, ZW_LOOP_BOUNDARY_Z_MINUS1, &c0, &ca, &cb));
    assert_true(c0 == R(0.0) && ca == R(0.0) && cb == R(0.0));
    EXPECT_OK(zw_loop_alpha_max(&loop, &g_ws, R(-0.5), &a));
    assert_true(a == R(0.0));
    EXPECT_OK(zw_loop_beta_intervals(&loop, &g_ws, R(0.1), &set));
    assert_true(set.count == 0u);
    memset(&x, ZWT_SENTINEL, sizeof x);
    EXPECT_STATUS(zw_loop_extremes_compute(&loop, &g_ws, &x), ZW_ERR_DOMAIN);
    assert_true(x.alpha_mmax == R(0.0) && x.beta_mmax == R(0.0) && x.beta_mmin == R(0.0) &&
                x.alpha_p_max == R(0.0) && x.beta_at_alpha_mmax == R(0.0));
}

static void test_errors_are_fail_safe(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0));
    zw_loop loop, empty;
    zw_loop_spec spec;
    zw_real a, lo, hi, c0, ca, cb, b;
    bool ne;
    zw_loop_beta_set set;
    zw_loop_extremes x;
    (void)state;
    memset(&spec, 0, sizeof spec);
    memset(&empty, 0, sizeof empty);
    EXPECT_OK(zw_loop_init(&loop, &c, &spec));
#define SENT(v) memset(&(v), ZWT_SENTINEL, sizeof(v))
    SENT(a);
    EXPECT_STATUS(zw_loop_alpha_max(NULL, &g_ws, R(0.0), &a), ZW_ERR_NULL);
    assert_true(a == R(0.0));
    EXPECT_STATUS(zw_loop_alpha_max(&loop, &g_ws, R(0.0), NULL), ZW_ERR_NULL);
    SENT(a);
    EXPECT_STATUS(zw_loop_alpha_max(&empty, &g_ws, R(0.0), &a), ZW_ERR_ARG);
    assert_true(a == R(0.0));
    SENT(a);
    EXPECT_STATUS(zw_loop_alpha_max(&loop, &g_ws, (zw_real)NAN, &a), ZW_ERR_NAN);
    assert_true(a == R(0.0));
    SENT(a);
    EXPECT_STATUS(zw_loop_alpha_max(&loop, &g_ws, (zw_real)INFINITY, &a), ZW_ERR_INF);
    assert_true(a == R(0.0));

    SENT(set);
    EXPECT_STATUS(zw_loop_beta_intervals(&loop, &g_ws, (zw_real)NAN, &set), ZW_ERR_NAN);
    assert_true(set.count == 0u && !set.truncated && set.lo[0] == R(0.0) && set.hi[3] == R(0.0));
    SENT(set);
    EXPECT_STATUS(zw_loop_beta_intervals(&empty, &g_ws, R(1.0), &set), ZW_ERR_ARG);
    assert_true(set.count == 0u);
    EXPECT_STATUS(zw_loop_beta_intervals(&loop, &g_ws, R(1.0), NULL), ZW_ERR_NULL);
    SENT(set);
    EXPECT_OK(zw_loop_beta_intervals(&loop, &g_ws, R(0.0), &set)); /* alpha <= 0: empty */
    assert_true(set.count == 0u);
    SENT(set);
    EXPECT_OK(zw_loop_beta_intervals(&loop, &g_ws, R(1e6), &set)); /* above alpha_mmax: empty */
    assert_true(set.count == 0u);

    SENT(lo);
    SENT(hi);
    SENT(ne);
    EXPECT_STATUS(zw_loop_beta_interval(&loop, &g_ws, (zw_real)INFINITY, &lo, &hi, &ne), ZW_ERR_INF);
    assert_true(lo == R(0.0) && hi == R(0.0) && !ne);
    /* with one output NULL the others are still written fail-safe */
    lo = R(1.0);
    ne = true;
    EXPECT_STATUS(zw_loop_beta_interval(&loop, &g_ws, R(1.0), &lo, NULL, &ne), ZW_ERR_NULL);
    assert_true(lo == R(0.0) && !ne);

    SENT(x);
    EXPECT_STATUS(zw_loop_extremes_compute(&empty, &g_ws, &x), ZW_ERR_ARG);
    assert_true(x.alpha_mmax == R(0.0) && x.beta_mmax == R(0.0) && x.alpha_p_max == R(0.0));
    EXPECT_STATUS(zw_loop_extremes_compute(NULL, &g_ws, &x), ZW_ERR_NULL);
    EXPECT_STATUS(zw_loop_extremes_compute(&loop, &g_ws, NULL), ZW_ERR_NULL);

    SENT(a);
    SENT(b);
    EXPECT_STATUS(zw_loop_boundary_point(&loop, R(0.0), &a, &b), ZW_ERR_ARG);
    assert_true(a == R(0.0) && b == R(0.0));
    EXPECT_STATUS(zw_loop_boundary_point(&loop, R(3.5), &a, &b), ZW_ERR_ARG);
    EXPECT_STATUS(zw_loop_boundary_point(&loop, (zw_real)NAN, &a, &b), ZW_ERR_NAN);
    b = R(1.0);
    EXPECT_STATUS(zw_loop_boundary_point(&loop, R(1.0), NULL, &b), ZW_ERR_NULL);
    assert_true(b == R(0.0));
    SENT(c0);
    SENT(ca);
    SENT(cb);
    EXPECT_STATUS(zw_loop_boundary_line(&loop, ZW_LOOP_BOUNDARY_COMPLEX, &c0, &ca, &cb), ZW_ERR_ARG);
    assert_true(c0 == R(0.0) && ca == R(0.0) && cb == R(0.0));
    EXPECT_STATUS(zw_loop_boundary_line(&empty, ZW_LOOP_BOUNDARY_Z_MINUS1, &c0, &ca, &cb), ZW_ERR_ARG);
    ca = cb = R(1.0);
    EXPECT_STATUS(zw_loop_boundary_line(&loop, ZW_LOOP_BOUNDARY_Z_MINUS1, NULL, &ca, &cb), ZW_ERR_NULL);
    assert_true(ca == R(0.0) && cb == R(0.0));
#undef SENT
}

/* Outside the stable beta range alpha_max certifies nothing (0); the ideal loop's range is
 * (-delta, beta_mmax). */
static void test_outside_range_is_zero(void **state)
{
    zw_coeffs c;
    zw_loop loop;
    zw_extremes x;
    zw_real a;
    (void)state;
    ideal_loop(R(2.0), &c, &loop);
    EXPECT_OK(zw_extremes_compute(&c, &x));
    EXPECT_OK(zw_loop_alpha_max(&loop, &g_ws, -c.delta * R(1.01), &a));
    assert_true(a == R(0.0));
    EXPECT_OK(zw_loop_alpha_max(&loop, &g_ws, x.beta_mmax * R(1.01), &a));
    assert_true(a == R(0.0));
}

/* A moving average opens the region's corner at (alpha, beta) = (0, -delta) to the left:
 * just below beta = -delta some alpha > 0 are stable, but not those next to 0, so the
 * interval (0, alpha_max) is empty (a scan that starts at its first grid angle instead of
 * theta = 0 misses that crossing and claims the whole (0, 44)). */
static void test_average_corner_below_minus_delta(void **state)
{
    zw_coeffs c = zwt_coeffs(R(20.0));
    zw_loop loop;
    zw_loop_spec spec;
    zw_loop_verdict v;
    zw_real a, beta = ZWT_DOWN(R(-20.0)); /* 1 ulp below -delta */
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.filter = ZW_VFILTER_AVERAGE;
    spec.average = 8u;
    EXPECT_OK(zw_loop_init(&loop, &c, &spec));
    EXPECT_OK(zw_loop_check(&loop, &g_ws, R(20.0), beta, &v));
    assert_true(v.stable);
    EXPECT_OK(zw_loop_alpha_max(&loop, &g_ws, beta, &a));
    assert_true(a == R(0.0));
    EXPECT_OK(zw_loop_alpha_max(&loop, &g_ws, R(-20.0), &a)); /* on the corner itself */
    assert_true(a == R(0.0));
    EXPECT_OK(zw_loop_alpha_max(&loop, &g_ws, R(-19.0), &a));
    assert_true(a > R(40.0));
}

/* The limits keep their state in the workspace (loop.h): its contents before a call never
 * matter.  A delayed, filtered loop (every walk, scan and extremes path) gives the same
 * limits, bit for bit, from a zeroed workspace and from one full of garbage (NaN patterns,
 * another loop's leftovers), and the same again when the workspace is reused. */
static void test_workspace_contents_do_not_matter(void **state)
{
    static zw_loop_workspace zeroed, garbage;
    zw_coeffs c = zwt_coeffs(R(0.7));
    zw_loop loop;
    zw_loop_spec spec;
    zw_loop_extremes x, y;
    zw_loop_beta_set s, t;
    zw_real a, b;
    unsigned i, j;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    spec.filter = ZW_VFILTER_LOWPASS;
    spec.filter_pole = R(0.6);
    EXPECT_OK(zw_loop_init(&loop, &c, &spec));
    memset(&s, 0, sizeof s); /* the padding too: the sets are compared byte for byte */
    memset(&t, 0, sizeof t);
    for (j = 0u; j < 2u; ++j) {
        memset(&zeroed, 0, sizeof zeroed);
        memset(&garbage, j == 0u ? 0xFF : ZWT_SENTINEL, sizeof garbage);
        EXPECT_OK(zw_loop_extremes_compute(&loop, &zeroed, &x));
        EXPECT_OK(zw_loop_extremes_compute(&loop, &garbage, &y));
        assert_memory_equal(&x, &y, sizeof x);
        assert_true(x.alpha_mmax > R(0.0));
        for (i = 0u; i < 8u; ++i) {
            const zw_real beta = x.beta_mmin + (x.beta_mmax - x.beta_mmin) * ((zw_real)i / R(7.0));
            const zw_real alpha = x.alpha_mmax * ((zw_real)(i + 1u) / R(9.0));
            EXPECT_OK(zw_loop_alpha_max(&loop, &zeroed, beta, &a));
            EXPECT_OK(zw_loop_alpha_max(&loop, &garbage, beta, &b));
            assert_true(a == b);
            EXPECT_OK(zw_loop_beta_intervals(&loop, &zeroed, alpha, &s));
            EXPECT_OK(zw_loop_beta_intervals(&loop, &garbage, alpha, &t));
            assert_memory_equal(&s, &t, sizeof s);
            assert_true(s.count > 0u);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ideal_alpha_max_matches_closed_form),
        cmocka_unit_test(test_ideal_extremes_match_closed_form),
        cmocka_unit_test(test_ideal_beta_interval_matches_closed_form),
        cmocka_unit_test(test_ideal_boundary_is_line_and_hyperbola),
        cmocka_unit_test(test_delay_lowers_k_mmax),
        cmocka_unit_test(test_tustin_even_average_is_never_stable),
        cmocka_unit_test(test_errors_are_fail_safe),
        cmocka_unit_test(test_outside_range_is_zero),
        cmocka_unit_test(test_average_corner_below_minus_delta),
        cmocka_unit_test(test_workspace_contents_do_not_matter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
