/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* Certification over a plant box (box.h) against a long double reference: the paper's
 * f(beta) (factored form of eq (10)) and L(beta) from the literal coefficient formulas,
 * minimized over a dense grid of plants.  The grid minimum is >= the true minimum, so
 * "never above" is asserted against it with only the reference's own rounding as slack;
 * tightness is asserted as a relative gap to it. */
#include "zw_test.h"

#define CELLS 4096u
static zw_box_cell g_cells[CELLS];

static zw_box_work work(void)
{
    zw_box_work w;
    EXPECT_OK(zw_box_work_init(&w, g_cells, CELLS));
    return w;
}

/* K_max(B) at one plant, long double, literal formulas (delta 0 or in [1e-3, 100] here). */
static long double k_max_ref(long double m, long double b, long double T, long double B)
{
    long double d = b * T / m, beta = B * T / m, alpha, e, c1, c2, d12, f, L;
    if (!(beta + d > 0.0L)) return 0.0L;
    if (d == 0.0L) { /* eq (17): c1 = c2 = e = 1, no line */
        alpha = (-2.0L * beta * beta + 4.0L * beta) / (beta + 2.0L);
        return (alpha > 0.0L ? alpha : 0.0L) * m / (T * T);
    }
    e = expl(-d);
    c1 = 2.0L * (d - 1.0L + e) / (d * d);
    c2 = 2.0L * (1.0L - e - d * e) / (d * d);
    d12 = 2.0L * ((d + 2.0L) * e + d - 2.0L) / (d * d);
    f = (c1 + c2) * (beta + d) * (2.0L - c2 * beta) / ((c1 * beta + 2.0L) * c2);
    L = 4.0L * (1.0L + e) / d12 - 2.0L * beta;
    alpha = f < L ? f : L;
    if (alpha < 0.0L) alpha = 0.0L;
    return alpha * m / (T * T);
}

/* Least K_max(B) over an n x n grid of the box (ends included), and where. */
static long double grid_min(const zw_plant_box *box, long double B, int n, long double *m_at,
                            long double *b_at)
{
    int i, j;
    long double least = INFINITY;
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            long double m = box->m_lo + (long double)(box->m_hi - box->m_lo) * i / (n - 1);
            long double b = box->b_lo + (long double)(box->b_hi - box->b_lo) * j / (n - 1);
            long double k = k_max_ref(m, b, box->T, B);
            if (k < least) {
                least = k;
                if (m_at != NULL) *m_at = m;
                if (b_at != NULL) *b_at = b;
            }
        }
    }
    return least;
}

/* The paper's rotary plant (b = 2.197e-3, T = 0.02) with J from 5e-6 to 5e-5: the box
 * spans m_K2 = 7.6e-6 and m_K1 = 4.2e-5, where K_mmax falls and rises again in m. */
static zw_plant_box nonmonotone_box(void)
{
    zw_plant_box box = {.m_lo = R(5e-6), .m_hi = R(5e-5), .b_lo = R(2.0e-3), .b_hi = R(2.4e-3), .T = R(0.02)};
    return box;
}

static void expect_bound_below_grid(const zw_plant_box *box, zw_real B, long double tight)
{
    zw_box_work w = work();
    zw_box_bound r;
    long double ref = grid_min(box, B, 201, NULL, NULL);
    EXPECT_OK(zw_box_k_max(box, B, &w, &r));
    EXPECT_TRUE_MSG((long double)r.K_lower <= ref * (1.0L + 1e-15L),
                    "K_lower %.17Lg above the grid minimum %.17Lg", (long double)r.K_lower, ref);
    EXPECT_TRUE_MSG((long double)r.K_lower >= ref * (1.0L - tight),
                    "K_lower %.17Lg not within %Lg of the grid minimum %.17Lg",
                    (long double)r.K_lower, tight, ref);
    /* the worst plant lies in the box and its K_max is the upper figure */
    assert_true(r.m_worst >= box->m_lo && r.m_worst <= box->m_hi);
    assert_true(r.b_worst >= box->b_lo && r.b_worst <= box->b_hi);
    EXPECT_REL((long double)r.K_upper, k_max_ref(r.m_worst, r.b_worst, box->T, B), PREC(1e-12, 1e-4));
    assert_true(r.K_lower <= r.K_upper);
}

static void test_k_max_nonmonotone(void **state)
{
    zw_plant_box box = nonmonotone_box();
    (void)state;
    expect_bound_below_grid(&box, R(0.0), PREC(2e-4, 2e-3));
    expect_bound_below_grid(&box, R(-1.0e-3), PREC(2e-4, 2e-3));
    expect_bound_below_grid(&box, R(2.0e-4), PREC(2e-4, 2e-3));
}

/* In m, K_max(B = 1e-3) at fixed b has an interior minimum (m ~ 5.2e-5) inside this box:
 * the corners alone overestimate the box's K_max (why the search exists). */
static void test_corners_are_not_enough(void **state)
{
    zw_plant_box box = {.m_lo = R(2.0e-5), .m_hi = R(1.5e-4), .b_lo = R(2.197e-3), .b_hi = R(2.197e-3), .T = R(0.02)};
    const zw_real B = R(1.0e-3);
    long double m_at = 0, b_at = 0;
    long double least = grid_min(&box, B, 401, &m_at, &b_at);
    long double corner_lo = k_max_ref(box.m_lo, box.b_lo, box.T, B);
    long double corner_hi = k_max_ref(box.m_hi, box.b_lo, box.T, B);
    zw_box_work w = work();
    zw_box_bound r;
    (void)state;
    EXPECT_TRUE_MSG(least < corner_lo * (1.0L - 1e-3L) && least < corner_hi * (1.0L - 1e-3L),
                    "grid min %Lg not below both corners %Lg %Lg (m at %Lg)", least, corner_lo,
                    corner_hi, m_at);
    EXPECT_OK(zw_box_k_max(&box, B, &w, &r));
    assert_true((long double)r.K_lower <= least * (1.0L + 1e-15L));
    assert_true((long double)r.K_lower >= least * (1.0L - PREC(1e-5L, 1e-3L)));
    assert_true(r.m_worst > box.m_lo && r.m_worst < box.m_hi);
    /* an interior minimum costs the first-order enclosure most: 4096 cells reach ~1e-5 */
    EXPECT_TRUE_MSG(r.K_upper - r.K_lower <= R(PREC(2e-5, 2e-3)) * r.K_upper, "gap %g of %g",
                    (double)(r.K_upper - r.K_lower), (double)r.K_upper);
}

static void test_point_box(void **state)
{
    zw_plant_box box = {.m_lo = R(1e-5), .m_hi = R(1e-5), .b_lo = R(2.197e-3), .b_hi = R(2.197e-3), .T = R(0.02)};
    (void)state;
    expect_bound_below_grid(&box, R(-1.0e-3), PREC(1e-5, 1e-3));
    expect_bound_below_grid(&box, R(1.0e-4), PREC(1e-5, 1e-3));
}

/* b = 0 (delta = 0: no line, eq (17)) for every plant, and b from 0: stable only for
 * B > 0, and the bound stays below the grid (the line's overflowed lambda is not a NaN). */
static void test_zero_damping(void **state)
{
    zw_plant_box flat = {.m_lo = R(0.1), .m_hi = R(0.3), .b_lo = R(0.0), .b_hi = R(0.0), .T = R(0.01)};
    zw_plant_box from0 = {.m_lo = R(0.1), .m_hi = R(0.3), .b_lo = R(0.0), .b_hi = R(5.0), .T = R(0.01)};
    zw_box_work w = work();
    zw_box_bound r;
    (void)state;
    EXPECT_OK(zw_box_k_max(&flat, R(10.0), &w, &r));
    /* delta = 0: alpha < (-2 beta^2 + 4 beta)/(beta + 2) (eq (17)), K = alpha m / T^2;
     * beta = B T / m is smallest at m_hi, and K_max rises with m here */
    {
        long double beta = 10.0L * 0.01L / 0.1L, k = (-2 * beta * beta + 4 * beta) / (beta + 2) * 0.1L / 1e-4L;
        EXPECT_TRUE_MSG((long double)r.K_lower <= k && (long double)r.K_lower >= k * (1 - PREC(1e-5L, 1e-3L)),
                        "K_lower %Lg, delta = 0 reference %Lg", (long double)r.K_lower, k);
    }
    EXPECT_OK(zw_box_k_max(&flat, R(-1.0), &w, &r));
    assert_true(r.K_lower == R(0.0));
    EXPECT_OK(zw_box_k_max(&from0, R(10.0), &w, &r));
    assert_true(r.K_lower > R(0.0) && (long double)r.K_lower <= grid_min(&from0, 10.0L, 101, NULL, NULL));
}

/* B <= -b_lo: the plant with b = b_lo has nothing stable, so K_box is 0. */
static void test_negative_damping_edge(void **state)
{
    zw_plant_box box = nonmonotone_box();
    zw_box_work w = work();
    zw_box_bound r;
    zw_box_verdict v;
    (void)state;
    EXPECT_OK(zw_box_k_max(&box, -box.b_lo, &w, &r));
    assert_true(r.K_lower == R(0.0));
    EXPECT_OK(zw_box_check(&box, R(1e-6), -box.b_lo, &w, &v));
    assert_false(v.stable);
    assert_true(v.decided);
}

static void test_check(void **state)
{
    zw_plant_box box = nonmonotone_box();
    zw_box_work w = work();
    zw_box_bound r;
    zw_box_verdict v;
    long double ref = grid_min(&box, 0.0L, 201, NULL, NULL);
    (void)state;
    EXPECT_OK(zw_box_k_max(&box, R(0.0), &w, &r));
    /* below the certified bound: stable for the whole box */
    EXPECT_OK(zw_box_check(&box, r.K_lower * R(0.999), R(0.0), &w, &v));
    assert_true(v.stable && v.decided);
    assert_true(v.K_lower > r.K_lower * R(0.999));
    /* above the grid minimum: unstable, and the plant named is unstable */
    EXPECT_OK(zw_box_check(&box, (zw_real)(ref * 1.001L), R(0.0), &w, &v));
    assert_false(v.stable);
    assert_true(v.decided);
    assert_true(k_max_ref(v.m_worst, v.b_worst, box.T, 0.0L) <= ref * 1.001L);
    /* K <= 0 is never stable */
    EXPECT_OK(zw_box_check(&box, R(0.0), R(0.0), &w, &v));
    assert_false(v.stable);
    EXPECT_OK(zw_box_check(&box, R(-1.0), R(0.0), &w, &v));
    assert_false(v.stable);
}

/* A budget too small to decide answers "not stable, not decided". */
static void test_check_budget(void **state)
{
    zw_plant_box box = nonmonotone_box();
    zw_box_work w = work();
    zw_box_bound r;
    zw_box_verdict v;
    (void)state;
    EXPECT_OK(zw_box_k_max(&box, R(0.0), &w, &r));
    w.max_evals = 3u;
    EXPECT_OK(zw_box_check(&box, r.K_lower * R(0.9999), R(0.0), &w, &v));
    assert_false(v.stable);
    assert_false(v.decided);
    w.capacity = ZW_BOX_MIN_CELLS;
    w.max_evals = ZW_BOX_DEFAULT_EVALS;
    EXPECT_OK(zw_box_k_max(&box, R(0.0), &w, &r));
    assert_true((long double)r.K_lower <= grid_min(&box, 0.0L, 201, NULL, NULL));
    /* the search stays inside the caller's capacity: cells past it are never written */
    {
        const zw_plant_box valley = {.m_lo = R(2.0e-5), .m_hi = R(1.5e-4), .b_lo = R(2.197e-3), .b_hi = R(2.197e-3), .T = R(0.02)};
        size_t i;
        memset(g_cells, ZWT_SENTINEL, sizeof g_cells);
        w.capacity = 64u;
        EXPECT_OK(zw_box_k_max(&valley, R(1.0e-3), &w, &r));
        assert_false(r.converged); /* an interior minimum needs far more than 64 cells */
        assert_true((long double)r.K_lower <= grid_min(&valley, 1.0e-3L, 401, NULL, NULL));
        for (i = 64u * sizeof(zw_box_cell); i < sizeof g_cells; ++i)
            assert_int_equal(((const unsigned char *)g_cells)[i], ZWT_SENTINEL);
    }
}

static void test_b_range(void **state)
{
    zw_plant_box box = nonmonotone_box();
    zw_box_work w = work();
    zw_box_extremes x;
    zw_real lo = 0, hi = 0, K;
    bool ne = false;
    int i;
    (void)state;
    EXPECT_OK(zw_box_k_mmax(&box, &w, &x));
    K = x.K_mmax * R(0.5);
    EXPECT_OK(zw_box_b_range(&box, K, &w, &lo, &hi, &ne));
    assert_true(ne && lo < hi);
    /* every B of the range is stable at K for every plant of the grid */
    for (i = 0; i <= 40; ++i) {
        long double B = lo + (long double)(hi - lo) * i / 40;
        long double least = grid_min(&box, B, 61, NULL, NULL);
        EXPECT_TRUE_MSG(least > (long double)K, "B %.10Lg in the range but K_max %.10Lg <= K %.10g",
                        B, least, (double)K);
    }
    /* and the range is not much narrower than the grid's: a step outside fails */
    {
        long double step = 0.01L * (long double)(hi - lo);
        assert_true(grid_min(&box, lo - step, 201, NULL, NULL) <= (long double)K);
        assert_true(grid_min(&box, hi + step, 201, NULL, NULL) <= (long double)K);
    }
    /* above K_mmax: empty */
    EXPECT_OK(zw_box_b_range(&box, x.K_mmax_upper * R(1.01), &w, &lo, &hi, &ne));
    assert_false(ne);
    assert_true(lo == R(0.0) && hi == R(0.0));
}

static void test_k_mmax(void **state)
{
    zw_plant_box box = nonmonotone_box();
    zw_box_work w = work();
    zw_box_extremes x;
    long double best = 0.0L;
    int i;
    (void)state;
    EXPECT_OK(zw_box_k_mmax(&box, &w, &x));
    /* certified at B_at against the grid */
    assert_true((long double)x.K_mmax <= grid_min(&box, x.B_at, 201, NULL, NULL) * (1.0L + 1e-15L));
    assert_true(x.K_mmax <= x.K_upper_at && x.K_upper_at <= x.K_mmax_upper * (1 + TOL(64)));
    /* tight: no B on a grid does much better */
    for (i = 0; i <= 200; ++i) {
        long double B = -2.0e-3L + 4.0e-3L * i / 200;
        long double k = grid_min(&box, B, 41, NULL, NULL);
        if (k > best) best = k;
    }
    EXPECT_TRUE_MSG((long double)x.K_mmax >= best * (1.0L - PREC(1e-3L, 3e-3L)),
                    "K_mmax %.10Lg well below the grid's best %.10Lg", (long double)x.K_mmax, best);
}

/* Every bad input has its named error and the fail-safe outputs. */
static void test_errors(void **state)
{
    zw_box_work w = work();
    zw_box_bound r;
    zw_box_verdict v;
    zw_box_extremes x;
    zw_real lo = 1, hi = 2;
    bool ne = true;
    const zw_plant_box ok = nonmonotone_box();
    struct {
        zw_plant_box box;
        zw_status want;
    } bad[] = {
        {{.m_lo = R(1e-5), .m_hi = R(1e-6), .b_lo = R(1e-3), .b_hi = R(2e-3), .T = R(0.02)}, ZW_ERR_BOX},
        {{.m_lo = R(1e-5), .m_hi = R(2e-5), .b_lo = R(3e-3), .b_hi = R(2e-3), .T = R(0.02)}, ZW_ERR_BOX},
        {{.m_lo = R(0.0), .m_hi = R(2e-5), .b_lo = R(1e-3), .b_hi = R(2e-3), .T = R(0.02)}, ZW_ERR_MASS},
        {{.m_lo = R(-1e-5), .m_hi = R(2e-5), .b_lo = R(1e-3), .b_hi = R(2e-3), .T = R(0.02)}, ZW_ERR_MASS},
        {{.m_lo = R(1e-5), .m_hi = R(2e-5), .b_lo = R(-1e-3), .b_hi = R(2e-3), .T = R(0.02)}, ZW_ERR_DAMPING},
        {{.m_lo = R(1e-5), .m_hi = R(2e-5), .b_lo = R(1e-3), .b_hi = R(2e-3), .T = R(0.0)}, ZW_ERR_PERIOD},
        {{.m_lo = (zw_real)NAN, .m_hi = R(2e-5), .b_lo = R(1e-3), .b_hi = R(2e-3), .T = R(0.02)}, ZW_ERR_NAN},
        {{.m_lo = R(1e-5), .m_hi = R(2e-5), .b_lo = R(1e-3), .b_hi = (zw_real)NAN, .T = R(0.02)}, ZW_ERR_NAN},
        {{.m_lo = R(1e-5), .m_hi = (zw_real)INFINITY, .b_lo = R(1e-3), .b_hi = R(2e-3), .T = R(0.02)}, ZW_ERR_INF},
        {{.m_lo = R(1e-5), .m_hi = R(2e-5), .b_lo = R(1e-3), .b_hi = R(2e3), .T = R(0.02)}, ZW_ERR_RANGE}, /* delta 4e6 */
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(bad); ++i) {
        memset(&r, 0x5A, sizeof r);
        EXPECT_STATUS(zw_box_validate(&bad[i].box), bad[i].want);
        EXPECT_STATUS(zw_box_k_max(&bad[i].box, R(0.0), &w, &r), bad[i].want);
        assert_true(r.K_lower == R(0.0) && r.K_upper == R(0.0) && !r.converged && r.evals == 0u);
        assert_true(r.m_worst != r.m_worst);
        memset(&v, 0x5A, sizeof v);
        EXPECT_STATUS(zw_box_check(&bad[i].box, R(1.0), R(0.0), &w, &v), bad[i].want);
        assert_true(!v.stable && !v.decided && v.K_lower == R(0.0));
        EXPECT_STATUS(zw_box_b_range(&bad[i].box, R(1.0), &w, &lo, &hi, &ne), bad[i].want);
        assert_true(lo == R(0.0) && hi == R(0.0) && !ne);
        memset(&x, 0x5A, sizeof x);
        EXPECT_STATUS(zw_box_k_mmax(&bad[i].box, &w, &x), bad[i].want);
        assert_true(x.K_mmax == R(0.0) && x.K_mmax_upper == R(0.0) && !x.converged);
    }
    EXPECT_STATUS(zw_box_validate(NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_box_k_max(&ok, R(0.0), NULL, &r), ZW_ERR_NULL);
    EXPECT_STATUS(zw_box_k_max(&ok, R(0.0), &w, NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_box_k_max(&ok, (zw_real)NAN, &w, &r), ZW_ERR_NAN);
    EXPECT_STATUS(zw_box_k_max(&ok, (zw_real)INFINITY, &w, &r), ZW_ERR_INF);
    EXPECT_STATUS(zw_box_check(&ok, (zw_real)NAN, R(0.0), &w, &v), ZW_ERR_NAN);
    assert_false(v.stable);
    EXPECT_STATUS(zw_box_b_range(&ok, R(1.0), &w, NULL, &hi, &ne), ZW_ERR_NULL);
    assert_true(hi == R(0.0) && !ne);
    {
        zw_box_work bw = w;
        bw.capacity = ZW_BOX_MIN_CELLS - 1u;
        EXPECT_STATUS(zw_box_k_max(&ok, R(0.0), &bw, &r), ZW_ERR_ARG);
        bw = w;
        bw.max_evals = 0u;
        EXPECT_STATUS(zw_box_k_max(&ok, R(0.0), &bw, &r), ZW_ERR_ARG);
        bw = w;
        bw.rel_tol = (zw_real)NAN;
        EXPECT_STATUS(zw_box_k_max(&ok, R(0.0), &bw, &r), ZW_ERR_ARG);
        bw = w;
        bw.rel_tol = R(-1e-3);
        EXPECT_STATUS(zw_box_k_max(&ok, R(0.0), &bw, &r), ZW_ERR_ARG);
        bw = w;
        bw.cells = NULL;
        EXPECT_STATUS(zw_box_k_max(&ok, R(0.0), &bw, &r), ZW_ERR_NULL);
        EXPECT_STATUS(zw_box_work_init(&bw, g_cells, 2u), ZW_ERR_ARG);
        EXPECT_STATUS(zw_box_work_init(&bw, NULL, CELLS), ZW_ERR_NULL);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_k_max_nonmonotone),
        cmocka_unit_test(test_corners_are_not_enough),
        cmocka_unit_test(test_point_box),
        cmocka_unit_test(test_zero_damping),
        cmocka_unit_test(test_negative_damping_edge),
        cmocka_unit_test(test_check),
        cmocka_unit_test(test_check_budget),
        cmocka_unit_test(test_b_range),
        cmocka_unit_test(test_k_mmax),
        cmocka_unit_test(test_errors),
    };
    printf("zwidth C tests: box (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("box_" ZW_REAL_NAME, tests, NULL, NULL);
}
