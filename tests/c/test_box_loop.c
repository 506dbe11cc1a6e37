/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* Plant boxes of the general loop (box.h, box_loop.c) and the ideal plant's enclosure over
 * a delta interval (plant_box.h), against long double references: the coefficient
 * functions from their literal formulas (delta >= 0.3, where they lose little in long
 * double), and the ideal loop's K_max(B) (eq (10)) minimized over a dense grid of plants. */
#include "zw_test.h"
#include "zw_ref_box.h"

#define CELLS 4096u
static zw_box_loop_cell g_cells[CELLS];
static zw_box_loop_scratch g_scratch;
static zw_loop_workspace g_ws;

static zw_box_loop_work work(void)
{
    zw_box_loop_work w;
    EXPECT_OK(zw_box_loop_work_init(&w, g_cells, CELLS, &g_scratch));
    return w;
}

/* |ref - v| <= err, with the reference's own error (1e-16 relative) as slack */
static void expect_within(long double ref, zw_real v, zw_real err, const char *what, long double d)
{
    long double slack = 1e-16L * fabsl(ref) + 1e-30L;
    EXPECT_TRUE_MSG(fabsl(ref - (long double)v) <= (long double)err + slack,
                    "%s at delta %.17Lg: ref %.20Lg, enclosure %.17g +- %.3g", what, d, ref,
                    (double)v, (double)err);
}

static void test_enclose_contains(void **state)
{
    unsigned seed = 12345u;
    int box, k;
    (void)state;
    for (box = 0; box < 300; ++box) {
        zw_plant p;
        zw_real lo, hi;
        seed = seed * 1103515245u + 12345u;
        lo = (zw_real)(0.3 + 40.0 * (double)(seed % 100000u) / 100000.0);
        seed = seed * 1103515245u + 12345u;
        hi = lo * (zw_real)(1.0 + ((box % 3 == 0) ? 1e-6 : 2.0) * (double)(seed % 100000u) / 100000.0);
        if (box == 7) { /* around the d12 peak */
            lo = R(2.5);
            hi = R(2.9);
        }
        EXPECT_OK(zw_plant_enclose(&p, lo, hi));
        assert_int_equal(p.order, 2);
        for (k = 0; k <= 40; ++k) {
            long double d = (long double)lo + ((long double)hi - (long double)lo) * k / 40.0L;
            ref_plant r = ref_at(d);
            expect_within(r.c1, p.num[0], p.num_err[0], "c1", d);
            expect_within(r.c2, p.num[1], p.num_err[1], "c2", d);
            expect_within(2.0L, p.den[0], p.den_err[0], "den0", d);
            expect_within(-2.0L * (1.0L + r.e), p.den[1], p.den_err[1], "den1", d);
            expect_within(2.0L * r.e, p.den[2], p.den_err[2], "den2", d);
            expect_within(4.0L * (1.0L + r.e), p.den_s[0], p.den_s_err[0], "den_s0", d);
            expect_within(4.0L * (1.0L - r.e), p.den_s[1], p.den_s_err[1], "den_s1", d);
            expect_within(0.0L, p.den_s[2], p.den_s_err[2], "den_s2", d);
            expect_within(r.d12, p.num_s[0], p.num_s_err[0], "d12", d);
            expect_within(r.s, p.num_s[1], p.num_s_err[1], "s", d);
            expect_within(2.0L, p.den_w[0], p.den_w_err[0], "den_w0", d);
            expect_within(2.0L * (1.0L - r.e), p.den_w[1], p.den_w_err[1], "den_w1", d);
            expect_within(0.0L, p.den_w[2], p.den_w_err[2], "den_w2", d);
        }
    }
}

static void test_enclose_tight_and_errors(void **state)
{
    zw_plant p;
    (void)state;
    /* a point interval: rounding-sized radii */
    EXPECT_OK(zw_plant_enclose(&p, R(1.5), R(1.5)));
    EXPECT_TRUE_MSG(p.num_err[0] <= TOL(64) * p.num[0], "c1 radius %g", (double)p.num_err[0]);
    EXPECT_TRUE_MSG(p.num_s_err[0] <= TOL(64) * p.num_s[0], "d12 radius %g", (double)p.num_s_err[0]);
    EXPECT_STATUS(zw_plant_enclose(NULL, R(1.0), R(2.0)), ZW_ERR_NULL);
    EXPECT_STATUS(zw_plant_enclose(&p, R(2.0), R(1.0)), ZW_ERR_BOX);
    assert_int_equal(p.order, 0);
    assert_true(isnan(p.num[0]));
    EXPECT_STATUS(zw_plant_enclose(&p, -R(1.0), R(1.0)), ZW_ERR_DELTA);
    EXPECT_STATUS(zw_plant_enclose(&p, (zw_real)NAN, R(1.0)), ZW_ERR_NAN);
    EXPECT_STATUS(zw_plant_enclose(&p, R(1.0), (zw_real)INFINITY), ZW_ERR_INF);
    assert_int_equal(p.order, 0);
    EXPECT_OK(zw_plant_enclose(&p, R(0.0), R(0.0)));
    EXPECT_NEAR(p.num_s[1], R(2.0), TOL(64), 0);
}

/* The ideal loop through the general path: never above the grid minimum, and within the
 * search's tolerance of it (the paper's drive; the second box has an interior minimum in m,
 * where the default budget stops at a 3.3e-3 gap in double at B = 1e-3). */
static void test_ideal_loop_never_above_and_tight(void **state)
{
    const zw_plant_box boxes[2] = {{.m_lo = R(1.0e-5), .m_hi = R(1.4e-5), .b_lo = R(2.0e-3), .b_hi = R(2.4e-3), .T = R(0.02)},
                                   {.m_lo = R(2.0e-5), .m_hi = R(9.0e-5), .b_lo = R(2.0e-3), .b_hi = R(2.4e-3), .T = R(0.02)}};
    const zw_real Bs[3] = {R(0.0), R(1.0e-4), R(1.0e-3)};
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    int i, j;
    (void)state;
    memset(&spec, 0, sizeof spec);
    for (i = 0; i < 2; ++i) {
        for (j = 0; j < 3; ++j) {
            zw_box_loop_bound bd;
            long double g = ideal_grid_min(&boxes[i], (long double)Bs[j], 201);
            EXPECT_OK(zw_box_loop_k_max(&boxes[i], &spec, &g_ws, Bs[j], &w, &bd));
            EXPECT_TRUE_MSG((long double)bd.K_lower <= g * (1.0L + 1e-15L), "box %d B %g: %.17g above grid min %.17Lg",
                            i, (double)Bs[j], (double)bd.K_lower, g);
            EXPECT_TRUE_MSG((long double)bd.K_lower >= g * (1.0L - (ZWT_FLOAT ? 1e-2L : 5e-3L)),
                            "box %d B %g: %.17g not tight against %.17Lg", i, (double)Bs[j],
                            (double)bd.K_lower, g);
            assert_true(bd.K_lower <= bd.K_upper);
            print_message("ideal box %d B %g: K_lower / grid min = %.8Lf (evals %u)\n", i, (double)Bs[j],
                          (long double)bd.K_lower / g, (unsigned)bd.evals);
        }
    }
}

/* One sample of delay: K_lower is stable at every plant of a grid (the guarded point check,
 * itself tested against mpmath), and every plant's certified point K_max is above it. */
static void test_delay_box_consistent(void **state)
{
    const zw_plant_box box = {.m_lo = R(1.0e-5), .m_hi = R(1.4e-5), .b_lo = R(2.0e-3), .b_hi = R(2.4e-3), .T = R(0.02)};
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_bound bd;
    zw_box_loop_verdict v;
    int i, j;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    EXPECT_OK(zw_box_loop_k_max(&box, &spec, &g_ws, R(1.0e-4), &w, &bd));
    assert_true(bd.K_lower > R(0.0));
    assert_true(bd.converged);
    for (i = 0; i <= 10; ++i) {
        for (j = 0; j <= 10; ++j) {
            zw_device_loop dl;
            zw_real k;
            bool stable;
            zw_real m = box.m_lo + (box.m_hi - box.m_lo) * (zw_real)i / R(10.0);
            zw_real b = box.b_lo + (box.b_hi - box.b_lo) * (zw_real)j / R(10.0);
            EXPECT_OK(zw_device_loop_init(&dl, m, b, box.T, &spec));
            EXPECT_OK(zw_device_loop_is_stable(&dl, &g_ws, bd.K_lower, R(1.0e-4), &stable));
            assert_true(stable);
            EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, R(1.0e-4), &k));
            EXPECT_TRUE_MSG(bd.K_lower <= k * (R(1.0) + TOL(1e6)), "K_lower %g above K_max %g at (%g, %g)",
                            (double)bd.K_lower, (double)k, (double)m, (double)b);
        }
    }
    /* the verdicts: below certified, above refuted at a plant where it is unstable */
    EXPECT_OK(zw_box_loop_check(&box, &spec, &g_ws, R(0.99) * bd.K_lower, R(1.0e-4), &w, &v));
    assert_true(v.stable && v.decided);
    EXPECT_OK(zw_box_loop_check(&box, &spec, &g_ws, R(1.05) * bd.K_upper, R(1.0e-4), &w, &v));
    assert_false(v.stable);
    assert_true(v.decided);
    assert_true(v.m_worst >= box.m_lo && v.m_worst <= box.m_hi);
}

static void test_filters(void **state)
{
    const zw_plant_box box = {.m_lo = R(1.0e-5), .m_hi = R(1.2e-5), .b_lo = R(2.0e-3), .b_hi = R(2.2e-3), .T = R(0.02)};
    zw_device_loop_spec specs[4];
    zw_box_loop_work w = work();
    int i;
    (void)state;
    memset(specs, 0, sizeof specs);
    specs[0].delay = 1u;
    specs[0].filter = ZW_VFILTER_LOWPASS;
    specs[0].cutoff_hz = R(5.0);
    specs[1].differentiator = ZW_DIFF_TUSTIN;
    specs[2].filter = ZW_VFILTER_AVERAGE;
    specs[2].average = 3u;
    specs[3].differentiator = ZW_DIFF_TUSTIN;
    specs[3].filter = ZW_VFILTER_LOWPASS;
    specs[3].pole = R(0.5);
    specs[3].delay = 2u;
    for (i = 0; i < 4; ++i) {
        /* Tustin: stable only for B < 0 (z = -1 is the line beta = 0, loop.h) */
        const zw_real B = (specs[i].differentiator == ZW_DIFF_TUSTIN) ? -R(1.0e-4) : R(1.0e-4);
        zw_box_loop_bound bd;
        zw_device_loop dl;
        bool stable;
        EXPECT_OK(zw_box_loop_k_max(&box, &specs[i], &g_ws, B, &w, &bd));
        assert_true(bd.K_lower > R(0.0));
        assert_true(bd.K_lower <= bd.K_upper);
        EXPECT_OK(zw_device_loop_init(&dl, box.m_hi, box.b_lo, box.T, &specs[i]));
        EXPECT_OK(zw_device_loop_is_stable(&dl, &g_ws, bd.K_lower, B, &stable));
        assert_true(stable);
        print_message("spec %d: K_lower %g K_upper %g (gap %.2e)\n", i, (double)bd.K_lower, (double)bd.K_upper,
                      (double)((bd.K_upper - bd.K_lower) / bd.K_upper));
    }
}

static void test_b_range(void **state)
{
    const zw_plant_box box = {.m_lo = R(1.0e-5), .m_hi = R(1.4e-5), .b_lo = R(2.0e-3), .b_hi = R(2.4e-3), .T = R(0.02)};
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_verdict v;
    zw_real lo, hi;
    bool any;
    int k;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    EXPECT_OK(zw_box_loop_b_range(&box, &spec, &g_ws, R(0.05), &w, &lo, &hi, &any));
    assert_true(any);
    assert_true(lo < hi);
    for (k = 0; k <= 8; ++k) {
        zw_real B = lo + (hi - lo) * (zw_real)k / R(8.0);
        EXPECT_OK(zw_box_loop_check(&box, &spec, &g_ws, R(0.05), B, &w, &v));
        assert_true(v.stable);
    }
    /* K above every plant's K_mmax: nothing */
    EXPECT_OK(zw_box_loop_b_range(&box, &spec, &g_ws, R(10.0), &w, &lo, &hi, &any));
    assert_false(any);
}

/* K_mmax of a delayed loop's box: certified at its B (every plant's K_max there is above it),
 * at least the box's K_max at B = 0, below the centre plant's K_mmax. */
static void test_k_mmax(void **state)
{
    const zw_plant_box box = {.m_lo = R(1.0e-5), .m_hi = R(1.4e-5), .b_lo = R(2.0e-3), .b_hi = R(2.4e-3), .T = R(0.02)};
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_extremes x;
    zw_box_loop_bound b0;
    zw_device_loop dl;
    zw_device_loop_extremes nx;
    int i;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    EXPECT_OK(zw_box_loop_k_mmax(&box, &spec, &g_ws, &w, &x));
    EXPECT_OK(zw_box_loop_k_max(&box, &spec, &g_ws, R(0.0), &w, &b0));
    assert_true(x.K_mmax >= b0.K_lower);
    EXPECT_OK(zw_device_loop_init(&dl, R(1.2e-5), R(2.2e-3), box.T, &spec));
    EXPECT_OK(zw_device_loop_extremes_compute(&dl, &g_ws, &nx));
    assert_true(x.K_mmax <= nx.K_mmax * (R(1.0) + TOL(1e4)));
    for (i = 0; i <= 4; ++i) {
        zw_real k;
        EXPECT_OK(zw_device_loop_init(&dl, box.m_lo + (box.m_hi - box.m_lo) * (zw_real)i / R(4.0), box.b_lo, box.T, &spec));
        EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, x.B_at, &k));
        assert_true(x.K_mmax <= k * (R(1.0) + TOL(1e4)));
    }
    print_message("box K_mmax %g at B %g (K_max at B = 0: %g; centre plant's K_mmax %g)\n", (double)x.K_mmax,
                  (double)x.B_at, (double)b0.K_lower, (double)nx.K_mmax);
}

static void test_errors(void **state)
{
    const zw_plant_box box = {.m_lo = R(1.0e-5), .m_hi = R(1.4e-5), .b_lo = R(2.0e-3), .b_hi = R(2.4e-3), .T = R(0.02)};
    zw_plant_box bad = box;
    zw_device_loop_spec spec;
    zw_box_loop_work w = work(), bw;
    zw_box_loop_verdict v;
    zw_box_loop_bound bd;
    zw_real lo = R(1.0), hi = R(1.0);
    bool any = true;
    (void)state;
    memset(&spec, 0, sizeof spec);
    EXPECT_STATUS(zw_box_loop_work_init(&bw, g_cells, 2u, &g_scratch), ZW_ERR_ARG);
    EXPECT_STATUS(zw_box_loop_work_init(NULL, g_cells, CELLS, &g_scratch), ZW_ERR_NULL);
    EXPECT_STATUS(zw_box_loop_work_init(&bw, g_cells, CELLS, NULL), ZW_ERR_NULL);
    bw = w;
    bw.scratch = NULL;
    EXPECT_STATUS(zw_box_loop_k_max(&box, &spec, &g_ws, R(0.0), &bw, &bd), ZW_ERR_NULL);
    assert_true(bd.K_lower == R(0.0));
    bad.m_lo = R(2.0e-5);
    EXPECT_STATUS(zw_box_loop_check(&bad, &spec, &g_ws, R(0.1), R(0.0), &w, &v), ZW_ERR_BOX);
    assert_false(v.stable || v.decided);
    assert_true(isnan(v.m_worst));
    spec.delay = 9u;
    EXPECT_STATUS(zw_box_loop_k_max(&box, &spec, &g_ws, R(0.0), &w, &bd), ZW_ERR_DELAY);
    assert_true(bd.K_lower == R(0.0) && bd.K_upper == R(0.0) && !bd.converged);
    {
        zw_box_loop_extremes x;
        EXPECT_STATUS(zw_box_loop_k_mmax(&box, &spec, &g_ws, &w, &x), ZW_ERR_DELAY);
        assert_true(x.K_mmax == R(0.0) && isnan(x.B_at) && !x.converged);
    }
    spec.delay = 0u;
    EXPECT_STATUS(zw_box_loop_check(&box, &spec, &g_ws, (zw_real)NAN, R(0.0), &w, &v), ZW_ERR_NAN);
    assert_false(v.stable);
    EXPECT_STATUS(zw_box_loop_check(&box, &spec, NULL, R(0.1), R(0.0), &w, &v), ZW_ERR_NULL);
    EXPECT_STATUS(zw_box_loop_check(&box, NULL, &g_ws, R(0.1), R(0.0), &w, &v), ZW_ERR_NULL);
    EXPECT_STATUS(zw_box_loop_b_range(&box, &spec, &g_ws, (zw_real)INFINITY, &w, &lo, &hi, &any), ZW_ERR_INF);
    assert_false(any);
    assert_true(lo == R(0.0) && hi == R(0.0));
    bw = w;
    bw.max_evals = 0u;
    EXPECT_STATUS(zw_box_loop_k_max(&box, &spec, &g_ws, R(0.0), &bw, &bd), ZW_ERR_ARG);
    /* a tiny budget: never stable without proof */
    bw = w;
    bw.max_evals = 1u;
    EXPECT_OK(zw_box_loop_check(&box, &spec, &g_ws, R(0.34), R(0.0), &bw, &v));
    assert_false(v.stable);
    EXPECT_OK(zw_box_loop_check(&box, &spec, &g_ws, R(0.0), R(0.0), &w, &v));
    assert_false(v.stable);
    assert_true(v.decided);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_enclose_contains),
        cmocka_unit_test(test_enclose_tight_and_errors),
        cmocka_unit_test(test_ideal_loop_never_above_and_tight),
        cmocka_unit_test(test_delay_box_consistent),
        cmocka_unit_test(test_filters),
        cmocka_unit_test(test_b_range),
        cmocka_unit_test(test_k_mmax),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
