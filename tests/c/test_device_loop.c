/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* test_device_loop.c - the drive's loop in real units (device_loop.h).
 *
 * Reference: the characteristic polynomial of the loop built in long double from the exact
 * real inputs (delta = b T / m, alpha = K T^2 / m, beta = B T / m in long double, the
 * coefficient functions from zwt_reference), its Schur stability by the Schur-Cohn
 * recursion in long double; the loop's parts from loop.h's definitions (D = 2 z^d (z - 1)
 * (z - e) Dv, Na = (c1 z + c2) Dv, Nb = (c1 z + c2) Nv), not from the library.
 */
#include "zw_test.h"

/* The checks' scratch (loop.h): static, as a drive keeps it; tests run one at a time. */
static zw_loop_workspace g_ws;

#define REF_N (ZW_LOOP_MAX_DEGREE + 2u)

typedef struct ref_loop {
    unsigned n; /* degree */
    long double D[REF_N], Na[REF_N], Nb[REF_N]; /* highest power first, index 0 = z^n */
} ref_loop;

/* r = a * b, polynomials highest power first of degrees na, nb */
static unsigned poly_mul(long double *r, const long double *a, unsigned na, const long double *b,
                         unsigned nb)
{
    long double t[2 * REF_N];
    unsigned i, j;
    for (i = 0; i <= na + nb; ++i) t[i] = 0.0L;
    for (i = 0; i <= na; ++i)
        for (j = 0; j <= nb; ++j) t[i + j] += a[i] * b[j];
    for (i = 0; i <= na + nb; ++i) r[i] = t[i];
    return na + nb;
}

/* Right-align a polynomial of degree k into degree n (leading zeros). */
static void align(long double *dst, const long double *src, unsigned k, unsigned n)
{
    unsigned i;
    for (i = 0; i <= n; ++i) dst[i] = 0.0L;
    for (i = 0; i <= k; ++i) dst[n - k + i] = src[i];
}

/* The loop of (m, b, T) with delay d, backward difference and: no filter (a < 0, n = 0), a
 * low-pass of pole a (a >= 0), or a moving average over n. */
static ref_loop ref_build(long double m, long double b, long double T, unsigned d, long double a,
                          unsigned n_avg)
{
    const long double delta = b * T / m;
    const zwt_ref c = zwt_reference(delta);
    long double Dv[REF_N] = {0}, Nv[REF_N] = {0}, tmp[REF_N] = {0}, f[3];
    unsigned ndv, nnv, k, i;
    ref_loop r;
    if (n_avg > 0u) { /* (z^n - 1) / (n z^n) */
        ndv = nnv = n_avg;
        for (i = 0; i <= n_avg; ++i) Dv[i] = Nv[i] = 0.0L;
        Dv[0] = (long double)n_avg;
        Nv[0] = 1.0L;
        Nv[n_avg] = -1.0L;
    } else if (a >= 0.0L) { /* (1 - a)(z - 1) / (z - a) */
        ndv = nnv = 1u;
        Dv[0] = 1.0L;
        Dv[1] = -a;
        Nv[0] = 1.0L - a;
        Nv[1] = -(1.0L - a);
    } else { /* (z - 1) / z */
        ndv = nnv = 1u;
        Dv[0] = 1.0L;
        Dv[1] = 0.0L;
        Nv[0] = 1.0L;
        Nv[1] = -1.0L;
    }
    /* D = 2 z^d (z - 1)(z - e) Dv */
    f[0] = 2.0L;
    f[1] = -2.0L * (1.0L + c.e);
    f[2] = 2.0L * c.e;
    k = poly_mul(tmp, f, 2u, Dv, ndv);
    for (i = 1; i <= d; ++i) tmp[k + i] = 0.0L;
    k += d;
    r.n = k;
    align(r.D, tmp, k, r.n);
    f[0] = c.c1;
    f[1] = c.c2;
    k = poly_mul(tmp, f, 1u, Dv, ndv);
    align(r.Na, tmp, k, r.n);
    k = poly_mul(tmp, f, 1u, Nv, nnv);
    align(r.Nb, tmp, k, r.n);
    return r;
}

/* Schur stable (every root |z| < 1) by the Schur-Cohn recursion. */
static bool ref_stable(const ref_loop *r, long double alpha, long double beta)
{
    long double p[REF_N], q[REF_N];
    unsigned n = r->n, i;
    for (i = 0; i <= n; ++i) p[i] = r->D[i] + alpha * r->Na[i] + beta * r->Nb[i];
    while (n > 0u) {
        if (!(fabsl(p[n]) < fabsl(p[0]))) return false;
        for (i = 0; i < n; ++i) q[i] = p[0] * p[i] - p[n] * p[n - i];
        --n;
        for (i = 0; i <= n; ++i) p[i] = q[i];
    }
    return true;
}

typedef struct plant_case {
    zw_real m, b, T;
    unsigned delay;
    zw_real cutoff; /* low-pass cut-off [Hz], 0: none */
    unsigned average;
} plant_case;

static const plant_case cases[] = {
    {R(0.12), R(0.8), R(1e-3), 1u, R(0.0), 0u},
    {R(0.12), R(0.8), R(1e-3), 1u, R(100.0), 0u},
    {R(2.5), R(40.0), R(5e-4), 2u, R(0.0), 0u},
    {R(0.05), R(3.0), R(1e-3), 0u, R(0.0), 4u},
};

static void build_case(const plant_case *pc, zw_device_loop *dl, ref_loop *ref)
{
    zw_device_loop_spec spec;
    memset(&spec, 0, sizeof spec);
    spec.delay = pc->delay;
    if (pc->cutoff > R(0.0)) {
        spec.filter = ZW_VFILTER_LOWPASS;
        spec.cutoff_hz = pc->cutoff;
    } else if (pc->average > 0u) {
        spec.filter = ZW_VFILTER_AVERAGE;
        spec.average = pc->average;
    }
    EXPECT_OK(zw_device_loop_init(dl, pc->m, pc->b, pc->T, &spec));
    /* the pole the drive stores is the one certified: the reference takes it as given */
    *ref = ref_build(pc->m, pc->b, pc->T, pc->delay,
                     pc->cutoff > R(0.0) ? (long double)dl->loop.spec.filter_pole : -1.0L, pc->average);
}

static long double alpha_of(const plant_case *pc, long double K)
{
    return K * (long double)pc->T * (long double)pc->T / (long double)pc->m;
}

static long double beta_of(const plant_case *pc, long double B)
{
    return B * (long double)pc->T / (long double)pc->m;
}

/* Bisect K to the verdict's switch at fixed B: the last K called stable is stable for the
 * exact inputs, and the switch is close to the reference's. */
static void test_verdict_is_safe_at_its_switch(void **state)
{
    static zw_device_loop dl;
    size_t i, j;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        const plant_case *pc = &cases[i];
        ref_loop ref;
        const zw_real Bs[] = {R(0.0), R(0.3) * pc->m / pc->T, -R(0.5) * pc->b};
        build_case(pc, &dl, &ref);
        for (j = 0; j < ZWT_ARRAY_LEN(Bs); ++j) {
            zw_real lo = R(1e-6) * pc->m / (pc->T * pc->T), hi = R(10.0) * pc->m / (pc->T * pc->T);
            zw_loop_verdict v;
            int it;
            EXPECT_OK(zw_device_loop_check(&dl, &g_ws, lo, Bs[j], &v));
            if (!v.stable) continue; /* nothing stable at this B (checked by K_max below) */
            for (it = 0; it < 200; ++it) {
                const zw_real mid = lo + (hi - lo) / R(2.0);
                if (mid == lo || mid == hi) break;
                EXPECT_OK(zw_device_loop_check(&dl, &g_ws, mid, Bs[j], &v));
                {
                    bool fast = !v.stable;
                    EXPECT_OK(zw_device_loop_is_stable(&dl, &g_ws, mid, Bs[j], &fast));
                    assert_int_equal(fast, v.stable); /* the fast path: the same verdict */
                }
                if (v.stable) lo = mid;
                else hi = mid;
            }
            EXPECT_TRUE_MSG(ref_stable(&ref, alpha_of(pc, lo), beta_of(pc, Bs[j])),
                            "case %zu B %g: K %.17g called stable is not", i, (double)Bs[j], (double)lo);
            EXPECT_TRUE_MSG(!ref_stable(&ref, alpha_of(pc, lo) * (1.0L + PREC(1e-6L, 1e-1L)), beta_of(pc, Bs[j])),
                            "case %zu: switch at K %.17g far below the boundary", i, (double)lo);
        }
    }
}

/* K_max(B): every K below is stable for the exact inputs (sampled, up to K_max itself), and
 * it is tight (a little above is unstable). */
static void test_k_max_certified_and_tight(void **state)
{
    static zw_device_loop dl;
    size_t i, j, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        const plant_case *pc = &cases[i];
        ref_loop ref;
        const zw_real Bs[] = {R(0.0), R(0.1) * pc->m / pc->T, R(0.3) * pc->m / pc->T, -R(0.5) * pc->b};
        build_case(pc, &dl, &ref);
        for (j = 0; j < ZWT_ARRAY_LEN(Bs); ++j) {
            zw_real K_max = R(-1.0);
            const long double beta = beta_of(pc, Bs[j]);
            EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, Bs[j], &K_max));
            assert_true(K_max > R(0.0));
            for (k = 1; k <= 64; ++k) {
                const long double K = (long double)K_max * (long double)k / 64.0L;
                EXPECT_TRUE_MSG(ref_stable(&ref, alpha_of(pc, K), beta),
                                "case %zu B %g: K %.17Lg <= K_max %.17g unstable", i, (double)Bs[j], K,
                                (double)K_max);
            }
            EXPECT_TRUE_MSG(!ref_stable(&ref, alpha_of(pc, K_max) * (1.0L + PREC(1e-6L, 5e-2L)), beta),
                            "case %zu B %g: K_max %.17g not tight", i, (double)Bs[j], (double)K_max);
        }
    }
}

/* B range at K: every B in it is stable for the exact inputs (ends included), and it is
 * tight at both ends. */
static void test_b_range_certified_and_tight(void **state)
{
    static zw_device_loop dl;
    size_t i, j, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        const plant_case *pc = &cases[i];
        ref_loop ref;
        zw_real K_p = R(0.0);
        build_case(pc, &dl, &ref);
        EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, R(0.0), &K_p));
        for (j = 1; j <= 3; ++j) {
            const zw_real K = K_p * (zw_real)j / R(4.0);
            const long double alpha = alpha_of(pc, K);
            zw_real lo, hi;
            bool ok = false;
            long double w;
            EXPECT_OK(zw_device_loop_b_range(&dl, &g_ws, K, &lo, &hi, &ok));
            assert_true(ok && lo < hi);
            w = (long double)hi - (long double)lo;
            for (k = 0; k <= 64; ++k) {
                const long double B = (long double)lo + w * (long double)k / 64.0L;
                EXPECT_TRUE_MSG(ref_stable(&ref, alpha, beta_of(pc, k == 64 ? hi : B)),
                                "case %zu K %g: B %.17Lg in [%.17g, %.17g] unstable", i, (double)K, B,
                                (double)lo, (double)hi);
            }
            EXPECT_TRUE_MSG(!ref_stable(&ref, alpha, beta_of(pc, (long double)hi + w * PREC(1e-6L, 5e-2L))) &&
                                !ref_stable(&ref, alpha, beta_of(pc, (long double)lo - w * PREC(1e-6L, 5e-2L))),
                            "case %zu K %g: range [%.17g, %.17g] not tight", i, (double)K, (double)lo, (double)hi);
        }
    }
}

/* Extremes: within the loop's normalized extremes times the scales, never beyond. */
static void test_extremes_scale_the_normalized_ones(void **state)
{
    static zw_device_loop dl;
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        const plant_case *pc = &cases[i];
        ref_loop ref;
        zw_device_loop_extremes x;
        zw_real K_p = R(0.0);
        build_case(pc, &dl, &ref);
        EXPECT_OK(zw_device_loop_extremes_compute(&dl, &g_ws, &x));
        EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, R(0.0), &K_p));
        assert_true(x.K_p_max == K_p);
        assert_true(x.K_mmax >= x.K_p_max && x.B_mmin < R(0.0) && R(0.0) < x.B_mmax);
        EXPECT_TRUE_MSG(ref_stable(&ref, alpha_of(pc, x.K_mmax) * (1.0L - PREC(1e-9L, 1e-4L)),
                                   beta_of(pc, x.B_at_K_mmax)),
                        "case %zu: K_mmax %.17g at B %.17g unstable", i, (double)x.K_mmax, (double)x.B_at_K_mmax);
        /* the ideal loop's B_mmin is -b; every loop here has the same z = 1 corner */
        EXPECT_TRUE_MSG(x.B_mmin >= -pc->b && x.B_mmin < -pc->b * (R(1.0) - PREC(R(1e-6), R(1e-2))),
                        "case %zu: B_mmin %.17g vs -b %.17g", i, (double)x.B_mmin, (double)-pc->b);
    }
}

/* Errors: named, with fail-safe outputs. */
static void test_errors_are_fail_safe(void **state)
{
    static zw_device_loop dl;
    zw_device_loop_spec spec;
    zw_loop_verdict v;
    zw_real K = R(5.0), lo = R(5.0), hi = R(5.0), rho = R(0.0), th = R(1.0);
    bool ok = true, within = true;
    zw_device_loop_extremes x;
    (void)state;
    memset(&spec, 0, sizeof spec);
    EXPECT_STATUS(zw_device_loop_init(NULL, R(1.0), R(1.0), R(1e-3), &spec), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_loop_init(&dl, R(1.0), R(1.0), R(1e-3), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_loop_init(&dl, R(-1.0), R(1.0), R(1e-3), &spec), ZW_ERR_MASS);
    spec.delay = ZW_LOOP_MAX_DELAY + 1u;
    EXPECT_STATUS(zw_device_loop_init(&dl, R(1.0), R(1.0), R(1e-3), &spec), ZW_ERR_DELAY);
    spec.delay = 1u;
    spec.filter = ZW_VFILTER_LOWPASS;
    spec.cutoff_hz = R(600.0); /* above Nyquist at 1 kHz */
    EXPECT_STATUS(zw_device_loop_init(&dl, R(1.0), R(1.0), R(1e-3), &spec), ZW_ERR_FILTER);
    spec.cutoff_hz = (zw_real)NAN;
    EXPECT_STATUS(zw_device_loop_init(&dl, R(1.0), R(1.0), R(1e-3), &spec), ZW_ERR_NAN);
    /* the failed loop is refused with fail-safe outputs */
    v.stable = true;
    assert_int_not_equal(zw_device_loop_check(&dl, &g_ws, R(1.0), R(0.0), &v), ZW_OK);
    assert_false(v.stable);
    assert_int_not_equal(zw_device_loop_k_max(&dl, &g_ws, R(0.0), &K), ZW_OK);
    assert_true(K == R(0.0));
    assert_int_not_equal(zw_device_loop_b_range(&dl, &g_ws, R(1.0), &lo, &hi, &ok), ZW_OK);
    assert_true(!ok && lo == R(0.0) && hi == R(0.0));
    assert_int_not_equal(zw_device_loop_radius_within(&dl, &g_ws, R(1.0), R(0.0), R(1.0), &within), ZW_OK);
    assert_false(within);
    assert_int_not_equal(zw_device_loop_spectral_radius(&dl, &g_ws, R(1.0), R(0.0), &rho, &th), ZW_OK);
    assert_true(rho == (zw_real)INFINITY);
    x.K_mmax = R(1.0);
    assert_int_not_equal(zw_device_loop_extremes_compute(&dl, &g_ws, &x), ZW_OK);
    assert_true(x.K_mmax == R(0.0) && x.B_mmax == R(0.0));
    /* a good loop: bad gains */
    spec.cutoff_hz = R(100.0);
    EXPECT_OK(zw_device_loop_init(&dl, R(0.12), R(0.8), R(1e-3), &spec));
    v.stable = true;
    EXPECT_STATUS(zw_device_loop_check(&dl, &g_ws, (zw_real)NAN, R(0.0), &v), ZW_ERR_NAN);
    assert_false(v.stable);
    {
        bool fast = true;
        EXPECT_STATUS(zw_device_loop_is_stable(&dl, &g_ws, (zw_real)NAN, R(0.0), &fast), ZW_ERR_NAN);
        assert_false(fast);
        fast = true;
        EXPECT_STATUS(zw_device_loop_is_stable(&dl, NULL, R(1.0), R(0.0), &fast), ZW_ERR_NULL);
        assert_false(fast);
    }
    K = R(5.0);
    EXPECT_STATUS(zw_device_loop_k_max(&dl, &g_ws, (zw_real)INFINITY, &K), ZW_ERR_INF);
    assert_true(K == R(0.0));
    EXPECT_STATUS(zw_device_loop_k_max(&dl, &g_ws, R(0.0), NULL), ZW_ERR_NULL);
    /* a non-zero gain normalized to 0 (or a subnormal) has no relative error bound */
    v.stable = true;
    EXPECT_STATUS(zw_device_loop_check(&dl, &g_ws, ZWT_TRUE_MIN, R(0.0), &v), ZW_ERR_RANGE);
    assert_false(v.stable);
    K = R(5.0);
    EXPECT_STATUS(zw_device_loop_k_max(&dl, &g_ws, ZWT_TRUE_MIN, &K), ZW_ERR_RANGE);
    assert_true(K == R(0.0));
    EXPECT_STATUS(zw_device_loop_k_max(&dl, &g_ws, -ZWT_TRUE_MIN, &K), ZW_ERR_RANGE);
    assert_true(K == R(0.0));
    EXPECT_OK(zw_device_loop_b_range(&dl, &g_ws, R(-1.0), &lo, &hi, &ok)); /* K <= 0: empty */
    assert_true(!ok && lo == R(0.0) && hi == R(0.0));
    EXPECT_STATUS(zw_device_loop_check(NULL, &g_ws, R(1.0), R(0.0), &v), ZW_ERR_NULL);
    /* one output NULL: the others are still written (status.h) */
    lo = hi = R(5.0);
    ok = true;
    EXPECT_STATUS(zw_device_loop_b_range(&dl, &g_ws, R(1.0), &lo, NULL, &ok), ZW_ERR_NULL);
    assert_true(!ok && lo == R(0.0));
    EXPECT_STATUS(zw_device_loop_b_range(&dl, &g_ws, R(1.0), NULL, &hi, NULL), ZW_ERR_NULL);
    assert_true(hi == R(0.0));
    rho = R(0.0);
    EXPECT_STATUS(zw_device_loop_spectral_radius(&dl, &g_ws, R(1.0), R(0.0), &rho, NULL), ZW_ERR_NULL);
    assert_true(rho == (zw_real)INFINITY);
    /* the cut-off became the pole exp(-2 pi f_c T) */
    EXPECT_NEAR(dl.loop.spec.filter_pole, expl(-2.0L * 3.14159265358979323846L * 0.1L), 0, TOLL(8));
}

/* The gain rounding is carried: the loop's gain errors and the widened parts. */
static void test_gain_rounding_is_carried(void **state)
{
    static zw_device_loop dl;
    static zw_loop plain;
    zw_device_loop_spec spec;
    unsigned i;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    EXPECT_OK(zw_device_loop_init(&dl, R(0.12), R(0.8), R(1e-3), &spec));
    {
        zw_loop_spec ls;
        memset(&ls, 0, sizeof ls);
        ls.delay = 1u;
        EXPECT_OK(zw_loop_init(&plain, &dl.dev.co, &ls));
    }
    assert_true(plain.alpha_relerr == R(0.0) && plain.beta_relerr == R(0.0));
    assert_true(dl.loop.alpha_relerr >= TOL(4) && dl.loop.beta_relerr >= TOL(3));
    for (i = 0; i <= plain.degree; ++i) {
        assert_true(dl.loop.Na_err[i] >= plain.Na_err[i] + ZW_FABS(plain.Na[i]) * TOL(4) * R(0.99));
        assert_true(dl.loop.Nbs_err[i] >= plain.Nbs_err[i] + ZW_FABS(plain.Nbs[i]) * TOL(3) * R(0.99));
        assert_true(dl.loop.D_err[i] == plain.D_err[i]);
    }
    EXPECT_STATUS(zw_loop_carry_gain_rounding(&plain, R(-1.0), R(0.0)), ZW_ERR_ARG);
    assert_int_equal(plain.degree, 0); /* emptied: refused from now on */
    EXPECT_STATUS(zw_loop_carry_gain_rounding(NULL, R(0.0), R(0.0)), ZW_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_verdict_is_safe_at_its_switch),
        cmocka_unit_test(test_k_max_certified_and_tight),
        cmocka_unit_test(test_b_range_certified_and_tight),
        cmocka_unit_test(test_extremes_scale_the_normalized_ones),
        cmocka_unit_test(test_errors_are_fail_safe),
        cmocka_unit_test(test_gain_rounding_is_carried),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
