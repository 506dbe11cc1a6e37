/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* Plant boxes with stiffness and a hand (box.h's plant-side parts, zw_plant_enclose2): the
 * enclosure against the ZOH of x'' = -kappa x - delta x' + u by a long double matrix
 * exponential (Taylor series with scaling and squaring, no closed form), the boxes against
 * the library's certified point K_max on grids, and the errors. */
#include "zw_test.h"

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

/* exp of the 3 x 3 [[0, 1, 0], [-kappa, -delta, 1], [0, 0, 0]]: Phi (2 x 2) and Gamma. */
typedef struct ref2 {
    long double tr, det, b1, b0;
} ref2;

static void mat3_mul(long double a[3][3], long double b[3][3], long double out[3][3])
{
    int i, j, k;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            long double s = 0.0L;
            for (k = 0; k < 3; ++k) {
                s += a[i][k] * b[k][j];
            }
            out[i][j] = s;
        }
    }
}

static ref2 ref_plant2(long double delta, long double kappa)
{
    long double a[3][3] = {{0.0L, 1.0L, 0.0L}, {-kappa, -delta, 1.0L}, {0.0L, 0.0L, 0.0L}};
    long double e[3][3] = {{1.0L, 0.0L, 0.0L}, {0.0L, 1.0L, 0.0L}, {0.0L, 0.0L, 1.0L}};
    long double term[3][3], t2[3][3];
    int squarings = 0, n, i, j;
    ref2 r;
    long double norm = 1.0L + delta + kappa;
    while (norm > 0.125L) {
        norm *= 0.5L;
        squarings += 1;
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            a[i][j] = ldexpl(a[i][j], -squarings);
            term[i][j] = e[i][j];
        }
    }
    for (n = 1; n <= 30; ++n) {
        mat3_mul(term, a, t2);
        for (i = 0; i < 3; ++i) {
            for (j = 0; j < 3; ++j) {
                term[i][j] = t2[i][j] / (long double)n;
                e[i][j] += term[i][j];
            }
        }
    }
    for (n = 0; n < squarings; ++n) {
        mat3_mul(e, e, t2);
        memcpy(e, t2, sizeof e);
    }
    r.tr = e[0][0] + e[1][1];
    r.det = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    r.b1 = e[0][2];
    r.b0 = e[0][1] * e[1][2] - e[1][1] * e[0][2];
    return r;
}

static void expect_in(long double ref, zw_real v, zw_real err, const char *what, long double d,
                      long double k)
{
    long double slack = 1e-17L * fabsl(ref) + 1e-18L; /* the reference's own error */
    EXPECT_TRUE_MSG(fabsl(ref - (long double)v) <= (long double)err + slack,
                    "%s at (delta, kappa) = (%.17Lg, %.17Lg): ref %.20Lg, enclosure %.17g +- %.3g", what,
                    d, k, ref, (double)v, (double)err);
}

static void check_enclosure(zw_real dlo, zw_real dhi, zw_real klo, zw_real khi)
{
    zw_plant p;
    int i, j;
    EXPECT_OK(zw_plant_enclose2(&p, dlo, dhi, klo, khi));
    assert_int_equal(p.order, 2);
    for (i = 0; i <= 6; ++i) {
        for (j = 0; j <= 6; ++j) {
            long double d = (long double)dlo + ((long double)dhi - (long double)dlo) * i / 6.0L;
            long double k = (long double)klo + ((long double)khi - (long double)klo) * j / 6.0L;
            ref2 r = ref_plant2(d, k);
            long double P = 1.0L - r.tr + r.det, Q = 1.0L + r.tr + r.det, R_ = 1.0L - r.det;
            expect_in(2.0L, p.den[0], p.den_err[0], "den0", d, k);
            expect_in(-2.0L * r.tr, p.den[1], p.den_err[1], "den1", d, k);
            expect_in(2.0L * r.det, p.den[2], p.den_err[2], "den2", d, k);
            expect_in(2.0L * r.b1, p.num[0], p.num_err[0], "num0", d, k);
            expect_in(2.0L * r.b0, p.num[1], p.num_err[1], "num1", d, k);
            expect_in(2.0L * Q, p.den_s[0], p.den_s_err[0], "den_s0", d, k);
            expect_in(4.0L * R_, p.den_s[1], p.den_s_err[1], "den_s1", d, k);
            expect_in(2.0L * P, p.den_s[2], p.den_s_err[2], "den_s2", d, k);
            expect_in(2.0L * (r.b1 - r.b0), p.num_s[0], p.num_s_err[0], "num_s0", d, k);
            expect_in(2.0L * (r.b1 + r.b0), p.num_s[1], p.num_s_err[1], "num_s1", d, k);
            expect_in(2.0L * (P + R_), p.den_w[1], p.den_w_err[1], "den_w1", d, k);
            expect_in(2.0L * P, p.den_w[2], p.den_w_err[2], "den_w2", d, k);
        }
    }
}

static void test_enclose2_contains(void **state)
{
    unsigned seed = 777u;
    int n;
    (void)state;
    /* near critical damping (kappa = delta^2 / 4), the corners of the domain, a point */
    check_enclosure(R(0.9), R(1.1), R(0.2), R(0.3));
    check_enclosure(R(0.0), R(4.0), R(0.0), R(4.0));
    check_enclosure(R(3.9), R(4.0), R(3.9), R(4.0));
    check_enclosure(R(0.0), R(1e-3), R(0.0), R(1e-6));
    check_enclosure(R(0.5), R(0.5), R(0.0625), R(0.0625));
    for (n = 0; n < 200; ++n) {
        zw_real dlo, dhi, klo, khi, wd, wk;
        seed = seed * 1103515245u + 12345u;
        dlo = R(3.5) * (zw_real)(seed % 10000u) / R(10000.0);
        seed = seed * 1103515245u + 12345u;
        klo = R(3.5) * (zw_real)(seed % 10000u) / R(10000.0);
        if (n % 4 == 1) {
            klo = R(0.25) * dlo * dlo; /* on critical damping */
        }
        wd = (n % 3 == 0) ? R(1e-6) : R(0.3);
        wk = (n % 5 == 0) ? R(0.0) : R(0.3);
        dhi = dlo + wd * (zw_real)(seed % 97u) / R(97.0);
        khi = klo + wk * (zw_real)(seed % 89u) / R(89.0);
        check_enclosure(dlo, dhi, klo, khi);
    }
}

static void test_enclose2_tight_and_errors(void **state)
{
    zw_plant p, q;
    zw_plant_spec sp;
    int i;
    (void)state;
    /* a point: radii of a few hundred u of the coefficient, as the point plant's */
    EXPECT_OK(zw_plant_enclose2(&p, R(0.5), R(0.5), R(0.0625), R(0.0625)));
    memset(&sp, 0, sizeof sp);
    sp.delta = R(0.5);
    sp.kappa = R(0.0625);
    EXPECT_OK(zw_plant_init(&q, &sp));
    for (i = 0; i < 3; ++i) {
        EXPECT_TRUE_MSG(p.den_s_err[i] <= TOL(400) * ZW_FABS(p.den_s[i]) + TOL(400),
                        "den_s[%d] radius %g", i, (double)p.den_s_err[i]);
        EXPECT_NEAR(p.den_s[i], q.den_s[i], TOL(400), TOL(400));
    }
    /* kappa_hi = 0 is the ideal enclosure */
    EXPECT_OK(zw_plant_enclose2(&p, R(1.0), R(2.0), R(0.0), R(0.0)));
    EXPECT_OK(zw_plant_enclose(&q, R(1.0), R(2.0)));
    assert_memory_equal(p.num_s, q.num_s, sizeof p.num_s);
    EXPECT_STATUS(zw_plant_enclose2(NULL, R(1.0), R(2.0), R(0.0), R(1.0)), ZW_ERR_NULL);
    EXPECT_STATUS(zw_plant_enclose2(&p, R(1.0), R(2.0), R(1.0), R(0.5)), ZW_ERR_BOX);
    assert_int_equal(p.order, 0);
    assert_true(isnan(p.num[0]));
    EXPECT_STATUS(zw_plant_enclose2(&p, R(1.0), R(2.0), -R(1.0), R(0.5)), ZW_ERR_ARG);
    EXPECT_STATUS(zw_plant_enclose2(&p, R(1.0), R(2.0), (zw_real)NAN, R(0.5)), ZW_ERR_NAN);
    EXPECT_STATUS(zw_plant_enclose2(&p, R(1.0), R(2.0), R(0.0), (zw_real)INFINITY), ZW_ERR_INF);
    EXPECT_STATUS(zw_plant_enclose2(&p, R(1.0), R(4.5), R(0.0), R(0.5)), ZW_ERR_RANGE);
    EXPECT_STATUS(zw_plant_enclose2(&p, R(1.0), R(2.0), R(0.0), R(4.5)), ZW_ERR_RANGE);
    assert_int_equal(p.order, 0);
}

/* A drive-like device: m in [0.1, 0.14] kg, b in [0.5, 0.8] N s/m, T = 1 ms. */
static zw_plant_box device_box(void)
{
    zw_plant_box box;
    memset(&box, 0, sizeof box);
    box.m_lo = R(0.1);
    box.m_hi = R(0.14);
    box.b_lo = R(0.5);
    box.b_hi = R(0.8);
    box.T = R(0.001);
    return box;
}

/* K_lower is stable at every plant of a grid and below each plant's certified K_max. */
static void expect_box_sound(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_real B,
                             const zw_box_loop_bound *bd, int n)
{
    zw_plant_box f;
    int i, j, k;
    zw_real least = (zw_real)INFINITY;
    EXPECT_OK(zw_box_fold(box, &f));
    for (i = 0; i <= n; ++i) {
        for (j = 0; j <= n; ++j) {
            for (k = 0; k <= n; ++k) {
                zw_device_loop dl;
                zw_real kmax;
                bool stable;
                const zw_real m = f.m_lo + (f.m_hi - f.m_lo) * (zw_real)i / (zw_real)n;
                const zw_real b = f.b_lo + (f.b_hi - f.b_lo) * (zw_real)j / (zw_real)n;
                const zw_real kp = f.k_lo + (f.k_hi - f.k_lo) * (zw_real)k / (zw_real)n;
                EXPECT_OK(zw_device_loop_init_plant(&dl, m, b, f.T, kp, R(0.0), R(0.0), R(0.0), R(0.0), spec));
                EXPECT_OK(zw_device_loop_is_stable(&dl, &g_ws, bd->K_lower, B, &stable));
                EXPECT_TRUE_MSG(stable, "K_lower %g unstable at (%g, %g, %g)", (double)bd->K_lower, (double)m,
                                (double)b, (double)kp);
                EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, B, &kmax));
                EXPECT_TRUE_MSG(bd->K_lower <= kmax * (R(1.0) + TOL(1e6)), "K_lower %g above K_max %g",
                                (double)bd->K_lower, (double)kmax);
                least = (kmax < least) ? kmax : least;
            }
        }
    }
    print_message("K_lower %.9g, grid min %.9g, ratio %.6f, evals %u\n", (double)bd->K_lower, (double)least,
                  (double)(bd->K_lower / least), (unsigned)bd->evals);
}

static void test_stiffness_box_sound(void **state)
{
    zw_plant_box box = device_box();
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_bound bd;
    zw_box_loop_verdict v;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    box.k_lo = R(0.0);
    box.k_hi = R(2000.0);
    EXPECT_OK(zw_box_loop_k_max(&box, &spec, &g_ws, R(5.0), &w, &bd));
    assert_true(bd.K_lower > R(0.0));
    assert_true(bd.k_worst >= box.k_lo && bd.k_worst <= box.k_hi);
    expect_box_sound(&box, &spec, R(5.0), &bd, 4);
    EXPECT_OK(zw_box_loop_check(&box, &spec, &g_ws, R(0.99) * bd.K_lower, R(5.0), &w, &v));
    assert_true(v.stable && v.decided);
    EXPECT_OK(zw_box_loop_check(&box, &spec, &g_ws, R(1.05) * bd.K_upper, R(5.0), &w, &v));
    assert_false(v.stable); /* refuted only when a sub-box centre is unstable: not asked */
    assert_true(!v.decided || (v.k_worst >= box.k_lo && v.k_worst <= box.k_hi));
}

/* Near critical damping (kappa = delta^2 / 4 inside the box): m 0.1, b 5, T 10 ms, k 62.5. */
static void test_critical_damping_box_sound(void **state)
{
    zw_plant_box box;
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_bound bd;
    (void)state;
    memset(&box, 0, sizeof box);
    memset(&spec, 0, sizeof spec);
    box.m_lo = R(0.1);
    box.m_hi = R(0.11);
    box.b_lo = R(4.5);
    box.b_hi = R(5.5);
    box.T = R(0.01);
    box.k_lo = R(55.0);
    box.k_hi = R(70.0);
    EXPECT_OK(zw_box_loop_k_max(&box, &spec, &g_ws, R(1.0), &w, &bd));
    assert_true(bd.K_lower > R(0.0));
    expect_box_sound(&box, &spec, R(1.0), &bd, 4);
}

/* A point box with stiffness equals the point plant's K_max up to the bisection tolerance. */
static void test_point_box_tight(void **state)
{
    zw_plant_box box = device_box();
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_bound bd;
    zw_device_loop dl;
    zw_real kmax;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    box.m_hi = box.m_lo;
    box.b_hi = box.b_lo;
    box.k_lo = R(800.0);
    box.k_hi = R(800.0);
    EXPECT_OK(zw_box_loop_k_max(&box, &spec, &g_ws, R(5.0), &w, &bd));
    EXPECT_OK(zw_device_loop_init_plant(&dl, box.m_lo, box.b_lo, box.T, R(800.0), R(0.0), R(0.0), R(0.0),
                                        R(0.0), &spec));
    EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, R(5.0), &kmax));
    print_message("point box: K_lower / K_max = %.9f\n", (double)(bd.K_lower / kmax));
    assert_true(bd.K_lower <= kmax * (R(1.0) + TOL(1e6)));
    assert_true(bd.K_lower >= kmax * (R(1.0) - R(4.0) * w.rel_tol));
    assert_true(bd.converged);
}

/* A hand folds into M, Bp, Kp: the same K_lower as the box of the totals. */
static void test_hand_folds(void **state)
{
    zw_plant_box hand = device_box(), total = device_box(), f;
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_bound b1, b2;
    (void)state;
    memset(&spec, 0, sizeof spec);
    hand.m_h_lo = R(0.25);
    hand.m_h_hi = R(0.5);
    hand.b_h_lo = R(1.0);
    hand.b_h_hi = R(3.0);
    hand.k_h_lo = R(100.0);
    hand.k_h_hi = R(600.0);
    hand.k_hi = R(50.0);
    EXPECT_OK(zw_box_fold(&hand, &f));
    assert_true(f.m_lo <= R(0.35) && f.m_hi >= R(0.64) && f.m_hi < R(0.6401));
    assert_true(f.b_lo <= R(1.5) && f.b_hi >= R(3.8));
    assert_true(f.k_lo <= R(100.0) && f.k_hi >= R(650.0));
    assert_true(f.m_h_hi == R(0.0) && f.k_h_hi == R(0.0));
    total.m_lo = f.m_lo;
    total.m_hi = f.m_hi;
    total.b_lo = f.b_lo;
    total.b_hi = f.b_hi;
    total.k_lo = f.k_lo;
    total.k_hi = f.k_hi;
    EXPECT_OK(zw_box_loop_k_max(&hand, &spec, &g_ws, R(5.0), &w, &b1));
    EXPECT_OK(zw_box_loop_k_max(&total, &spec, &g_ws, R(5.0), &w, &b2));
    assert_true(b1.K_lower == b2.K_lower);
    expect_box_sound(&hand, &spec, R(5.0), &b1, 3);
}

static void test_errors(void **state)
{
    zw_plant_box box = device_box();
    zw_device_loop_spec spec;
    zw_box_loop_work w = work();
    zw_box_loop_bound bd;
    zw_box_work bw;
    zw_box_bound ib;
    (void)state;
    memset(&spec, 0, sizeof spec);
    EXPECT_OK(zw_box_work_init(&bw, (zw_box_cell *)(void *)g_cells, 64u));
    /* zero-initialised parts: today's box */
    EXPECT_OK(zw_box_validate(&box));
    box.tau_hi = R(1e-4);
    EXPECT_STATUS(zw_box_validate(&box), ZW_ERR_ARG);
    EXPECT_STATUS(zw_box_loop_k_max(&box, &spec, &g_ws, R(5.0), &w, &bd), ZW_ERR_ARG);
    assert_true(bd.K_lower == R(0.0) && isnan(bd.k_worst));
    box = device_box();
    box.k_lo = R(2.0);
    box.k_hi = R(1.0);
    EXPECT_STATUS(zw_box_validate(&box), ZW_ERR_BOX);
    box.k_lo = -R(1.0);
    EXPECT_STATUS(zw_box_validate(&box), ZW_ERR_ARG);
    box = device_box();
    box.b_h_lo = -R(1.0);
    EXPECT_STATUS(zw_box_validate(&box), ZW_ERR_DAMPING);
    box = device_box();
    box.m_h_hi = (zw_real)NAN;
    EXPECT_STATUS(zw_box_validate(&box), ZW_ERR_NAN);
    box = device_box();
    box.k_h_hi = (zw_real)INFINITY;
    EXPECT_STATUS(zw_box_validate(&box), ZW_ERR_INF);
    /* kappa beyond the series domain: k T^2 / m_lo = 5 */
    box = device_box();
    box.k_hi = R(5.0e5);
    EXPECT_STATUS(zw_box_validate(&box), ZW_ERR_RANGE);
    /* fail-safe: a failed fold (here after the totals were written) leaves no usable box */
    {
        zw_plant_box f = device_box();
        EXPECT_STATUS(zw_box_fold(&box, &f), ZW_ERR_RANGE);
        assert_true(isnan(f.m_lo) && isnan(f.m_hi) && isnan(f.b_lo) && isnan(f.b_hi) && isnan(f.T));
        assert_true(isnan(f.k_lo) && isnan(f.k_hi) && isnan(f.m_h_lo) && isnan(f.k_h_hi) && isnan(f.tau_hi));
        EXPECT_STATUS(zw_box_validate(&f), ZW_ERR_NAN);
    }
    /* the closed form has no spring; a hand's mass and damping it takes */
    box = device_box();
    box.k_hi = R(10.0);
    EXPECT_STATUS(zw_box_k_max(&box, R(5.0), &bw, &ib), ZW_ERR_ARG);
    assert_true(ib.K_lower == R(0.0));
    box = device_box();
    box.m_h_hi = R(0.2);
    EXPECT_OK(zw_box_k_max(&box, R(5.0), &bw, &ib));
    assert_true(ib.m_worst >= box.m_lo && ib.m_worst <= R(0.34001) && ib.k_worst == R(0.0));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_enclose2_contains),
        cmocka_unit_test(test_enclose2_tight_and_errors),
        cmocka_unit_test(test_stiffness_box_sound),
        cmocka_unit_test(test_critical_damping_box_sound),
        cmocka_unit_test(test_point_box_tight),
        cmocka_unit_test(test_hand_folds),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
