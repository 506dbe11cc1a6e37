/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* test_loop_plant.c - the general loop on a plant with plant-side parts
 * (zw_loop_init_plant, zw_device_loop_init_plant; issue 16).
 *
 * Reference, in long double and from the state-space definition only: the normalized
 * plant x'' + delta x' + kappa x = u under a zero-order hold, one period Phi = e^A and
 * Gamma = int_0^1 e^{A s} ds b by the Taylor series of the augmented matrix [[A, b], [0, 0]]
 * (60 terms), the sampled transfer function N / D = [1 0] adj(zI - Phi) Gamma / det(zI - Phi),
 * the loop with delay d and the backward difference:
 *     p(z) = z^(d+1) D(z) + N(z) (alpha z + beta (z - 1)),
 * Schur stability by the Schur-Cohn recursion in long double; alpha_max by bisection.
 */
#include "zw_test.h"

#include <stdlib.h>

#include "zwidth/device_loop.h"
#include "zwidth/loop_limits.h"
#include "zwidth/plant.h"

static zw_loop_workspace g_ws;
static zw_loop g_loop;
static zw_plant g_plant;
static zw_device_loop g_dl;

/* ---- reference ------------------------------------------------------------------------- */

typedef struct ref_plant {
    long double den[3], num[2]; /* z^2 + den[1] z + den[2]; num[0] z + num[1] */
} ref_plant;

static ref_plant ref_plant_of(long double delta, long double kappa)
{
    /* M = [[0, 1, 0], [-kappa, -delta, 1], [0, 0, 0]]; E = e^M = sum M^k / k! */
    long double M[3][3] = {{0.0L, 1.0L, 0.0L}, {-kappa, -delta, 1.0L}, {0.0L, 0.0L, 0.0L}};
    long double E[3][3] = {{1.0L, 0.0L, 0.0L}, {0.0L, 1.0L, 0.0L}, {0.0L, 0.0L, 1.0L}};
    long double P[3][3] = {{1.0L, 0.0L, 0.0L}, {0.0L, 1.0L, 0.0L}, {0.0L, 0.0L, 1.0L}};
    long double phi11, phi12, phi21, phi22, g1, g2;
    ref_plant r;
    unsigned k, i, j, l;
    for (k = 1u; k <= 60u; ++k) {
        long double Q[3][3];
        for (i = 0u; i < 3u; ++i) {
            for (j = 0u; j < 3u; ++j) {
                Q[i][j] = 0.0L;
                for (l = 0u; l < 3u; ++l) {
                    Q[i][j] += P[i][l] * M[l][j];
                }
                Q[i][j] /= (long double)k;
            }
        }
        for (i = 0u; i < 3u; ++i) {
            for (j = 0u; j < 3u; ++j) {
                P[i][j] = Q[i][j];
                E[i][j] += Q[i][j];
            }
        }
    }
    phi11 = E[0][0];
    phi12 = E[0][1];
    phi21 = E[1][0];
    phi22 = E[1][1];
    g1 = E[0][2];
    g2 = E[1][2];
    r.den[0] = 1.0L;
    r.den[1] = -(phi11 + phi22);
    r.den[2] = phi11 * phi22 - phi12 * phi21;
    /* [1 0] adj(zI - Phi) Gamma = g1 (z - phi22) + phi12 g2 */
    r.num[0] = g1;
    r.num[1] = -g1 * phi22 + phi12 * g2;
    return r;
}

/* p = z^(d+1) D + N (alpha z + beta (z - 1)), degree d + 3, highest power first */
static unsigned ref_poly(const ref_plant *pl, unsigned d, long double alpha, long double beta,
                         long double p[])
{
    const unsigned n = d + 3u;
    unsigned i;
    for (i = 0u; i <= n; ++i) {
        p[i] = 0.0L;
    }
    for (i = 0u; i < 3u; ++i) {
        p[i] += pl->den[i];
    }
    /* N (alpha + beta) z - N beta: degree 2, at indices n - 2 .. n */
    p[n - 2u] += pl->num[0] * (alpha + beta);
    p[n - 1u] += pl->num[1] * (alpha + beta) - pl->num[0] * beta;
    p[n] += -pl->num[1] * beta;
    return n;
}

static bool ref_schur(const long double p_in[], unsigned n)
{
    long double p[16];
    unsigned m, i;
    for (i = 0u; i <= n; ++i) {
        p[i] = p_in[i];
    }
    for (m = n; m > 0u; --m) {
        long double k;
        if (p[0] == 0.0L) {
            return false;
        }
        k = p[m] / p[0];
        if (!(fabsl(k) < 1.0L)) {
            return false;
        }
        for (i = 0u; 2u * i <= m; ++i) { /* the pairs (i, m - i) at once */
            const long double x = p[i], y = p[m - i];
            p[i] = x - k * y;
            p[m - i] = y - k * x;
        }
    }
    return true;
}

static bool ref_stable(const ref_plant *pl, unsigned d, long double alpha, long double beta)
{
    long double p[16];
    const unsigned n = ref_poly(pl, d, alpha, beta, p);
    return ref_schur(p, n);
}

/* sup of the stable alphas above start (stable), by bisection */
static long double ref_alpha_sup(const ref_plant *pl, unsigned d, long double beta, long double start)
{
    long double lo = start, hi = 2.0L * start + 1e-6L;
    unsigned it;
    while (ref_stable(pl, d, hi, beta)) {
        lo = hi;
        hi *= 2.0L;
    }
    for (it = 0u; it < 80u; ++it) {
        const long double mid = 0.5L * (lo + hi);
        if (ref_stable(pl, d, mid, beta)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* ---- helpers --------------------------------------------------------------------------- */

static zw_loop *plant_loop(zw_real delta, zw_real kappa, unsigned d)
{
    zw_plant_spec ps;
    zw_loop_spec ls;
    memset(&ps, 0, sizeof ps);
    memset(&ls, 0, sizeof ls);
    ps.delta = delta;
    ps.kappa = kappa;
    ls.delay = d;
    assert_int_equal(zw_plant_init(&g_plant, &ps), ZW_OK);
    assert_int_equal(zw_loop_init_plant(&g_loop, &g_plant, &ls), ZW_OK);
    assert_int_equal(g_loop.degree, 3u + d);
    return &g_loop;
}

static bool lib_stable(const zw_loop *lp, zw_real alpha, zw_real beta)
{
    zw_loop_verdict v;
    assert_int_equal(zw_loop_check(lp, &g_ws, alpha, beta, &v), ZW_OK);
    return v.stable;
}

/* ---- tests ----------------------------------------------------------------------------- */

/* Verdicts against the reference on a grid around the region, springs and hands with real
 * and complex poles, critical damping (delta^2 = 4 kappa): no false stable; a false unstable
 * only next to the reference's boundary (the point 1e-6 relative further out is unstable, or
 * 1e-6 further in is, for either gain). */
static void test_verdicts_against_reference(void **state)
{
    static const zw_real cases[][2] = {{R(0.5), R(0.1)}, {R(0.05), R(2.0)}, {R(1.0), R(0.25)},
                                       {R(0.01), R(5.0)}, {R(2.0), R(0.5)}, {R(0.3), R(30.0)}};
    unsigned c, d, i, j, n = 0u, false_unstable = 0u;
    (void)state;
    for (c = 0u; c < ZWT_ARRAY_LEN(cases); ++c) {
        for (d = 0u; d <= 2u; ++d) {
            const zw_loop *lp = plant_loop(cases[c][0], cases[c][1], d);
            const ref_plant rp = ref_plant_of((long double)cases[c][0], (long double)cases[c][1]);
            for (i = 0u; i <= 12u; ++i) {
                for (j = 0u; j <= 12u; ++j) {
                    const zw_real alpha = R(-1.2) * cases[c][1] + (R(3.0) + cases[c][1]) * (zw_real)i / R(12.0);
                    const zw_real beta = -cases[c][0] + R(3.0) * (zw_real)j / R(12.0);
                    const bool lib = lib_stable(lp, alpha, beta);
                    const bool ref = ref_stable(&rp, d, (long double)alpha, (long double)beta);
                    ++n;
                    if (lib) {
                        assert_true(ref);
                    } else if (ref) {
                        const long double a = (long double)alpha, b = (long double)beta;
                        ++false_unstable;
                        if (getenv("ZWT_DEBUG") != NULL) {
                            fprintf(stderr, "case %u d %u alpha %.17Lg beta %.17Lg\n", c, d, a, b);
                        }
                        assert_true(!ref_stable(&rp, d, a * (1.0L + 1e-6L), b) ||
                                    !ref_stable(&rp, d, a * (1.0L - 1e-6L), b) ||
                                    !ref_stable(&rp, d, a, b * (1.0L + 1e-6L)) ||
                                    !ref_stable(&rp, d, a, b * (1.0L - 1e-6L)));
                    } else {
                        /* both unstable */
                    }
                }
            }
        }
    }
    assert_true(n > 2000u);
    assert_true(false_unstable <= n / 100u);
}

/* alpha_max never above the reference's sup, and within a rounding-sized gap of it. */
static void test_alpha_max_certified(void **state)
{
    static const zw_real cases[][2] = {{R(0.5), R(0.1)}, {R(0.05), R(2.0)}, {R(1.0), R(0.25)},
                                       {R(2.0), R(0.5)}};
    static const zw_real betas[] = {R(0.0), R(0.2), R(0.6)};
    unsigned c, d, i;
    long double worst = 0.0L;
    (void)state;
    for (c = 0u; c < ZWT_ARRAY_LEN(cases); ++c) {
        for (d = 0u; d <= 1u; ++d) {
            const zw_loop *lp = plant_loop(cases[c][0], cases[c][1], d);
            const ref_plant rp = ref_plant_of((long double)cases[c][0], (long double)cases[c][1]);
            for (i = 0u; i < ZWT_ARRAY_LEN(betas); ++i) {
                zw_real amax = R(-1.0);
                long double truth, gap;
                assert_int_equal(zw_loop_alpha_max(lp, &g_ws, betas[i], &amax), ZW_OK);
                if (amax == R(0.0)) {
                    /* nothing certified: the reference is unstable just above 0 */
                    assert_false(ref_stable(&rp, d, 1e-9L, (long double)betas[i]) &&
                                 ref_stable(&rp, d, 1e-3L, (long double)betas[i]));
                    continue;
                }
                assert_true(ref_stable(&rp, d, (long double)amax, (long double)betas[i]));
                assert_true(ref_stable(&rp, d, 0.5L * (long double)amax, (long double)betas[i]));
                truth = ref_alpha_sup(&rp, d, (long double)betas[i], (long double)amax);
                assert_true((long double)amax <= truth);
                gap = (truth - (long double)amax) / truth;
                if (gap > worst) {
                    worst = gap;
                }
            }
        }
    }
    assert_true(worst < PREC(1e-9L, 1e-2L));
}

/* Stiffness moves the z = 1 boundary to alpha = -kappa (p(1) = Dv(1) (D(1) + alpha N(1)),
 * D(1) / N(1) = kappa: the sampled plant's static gain is the continuous one, 1 / kappa):
 * stable just above it, unstable just below with deciding z = 1; the boundary line says so. */
static void test_stiffness_moves_z1_line(void **state)
{
    const zw_real kappa = R(0.5), delta = R(1.5), beta = R(0.3);
    const zw_loop *lp = plant_loop(delta, kappa, 0u);
    zw_real c0, ca, cb;
    zw_loop_verdict v;
    (void)state;
    assert_int_equal(zw_loop_boundary_line(lp, ZW_LOOP_BOUNDARY_Z_PLUS1, &c0, &ca, &cb), ZW_OK);
    assert_true(fabsl((long double)(-c0 / ca) + 0.5L) < 64.0L * TOLL(1));
    assert_true(cb == R(0.0));
    assert_true(lib_stable(lp, R(-0.49), beta));
    assert_true(lib_stable(lp, R(0.0), beta));
    assert_int_equal(zw_loop_check(lp, &g_ws, R(-0.51), beta, &v), ZW_OK);
    assert_false(v.stable);
    assert_int_equal(v.deciding, ZW_LOOP_BOUNDARY_Z_PLUS1);
}

/* kappa -> 0 reduces to the ideal loop: alpha_max and the extremes converge to
 * zw_loop_init's (the truths differ by O(kappa)). */
static void test_kappa_to_zero_is_ideal(void **state)
{
    static zw_loop ideal;
    zw_coeffs c;
    zw_loop_spec ls;
    zw_loop_extremes xi, xp;
    unsigned d, i;
    (void)state;
    memset(&ls, 0, sizeof ls);
    for (d = 0u; d <= 2u; ++d) {
        const zw_loop *lp = plant_loop(R(0.8), PREC(R(1e-12), R(1e-7)), d);
        ls.delay = d;
        assert_int_equal(zw_coeffs_init(&c, R(0.8)), ZW_OK);
        assert_int_equal(zw_loop_init(&ideal, &c, &ls), ZW_OK);
        for (i = 0u; i < 4u; ++i) {
            const zw_real beta = R(-0.4) + R(0.5) * (zw_real)i;
            zw_real a1, a2;
            assert_int_equal(zw_loop_alpha_max(lp, &g_ws, beta, &a1), ZW_OK);
            assert_int_equal(zw_loop_alpha_max(&ideal, &g_ws, beta, &a2), ZW_OK);
            assert_true(fabsl((long double)a1 - (long double)a2) <= PREC(1e-9L, 1e-3L) * (1.0L + (long double)a2));
        }
        assert_int_equal(zw_loop_extremes_compute(lp, &g_ws, &xp), ZW_OK);
        assert_int_equal(zw_loop_extremes_compute(&ideal, &g_ws, &xi), ZW_OK);
        assert_true(fabsl((long double)xp.alpha_mmax - (long double)xi.alpha_mmax) <=
                    PREC(1e-6L, 1e-2L) * (long double)xi.alpha_mmax);
    }
}

/* lambda -> 0 (a vanishing actuator lag, order 3) reduces to the ideal loop too. */
static void test_lambda_to_zero_is_ideal(void **state)
{
    static zw_loop ideal;
    zw_coeffs c;
    zw_plant_spec ps;
    zw_loop_spec ls;
    unsigned d, i;
    (void)state;
    memset(&ls, 0, sizeof ls);
    memset(&ps, 0, sizeof ps);
    ps.delta = R(0.8);
    ps.lambda = PREC(R(1e-9), R(1e-4));
    assert_int_equal(zw_plant_init(&g_plant, &ps), ZW_OK);
    assert_int_equal(g_plant.order, 3u);
    assert_int_equal(zw_coeffs_init(&c, R(0.8)), ZW_OK);
    for (d = 0u; d <= 2u; ++d) {
        ls.delay = d;
        assert_int_equal(zw_loop_init_plant(&g_loop, &g_plant, &ls), ZW_OK);
        assert_int_equal(g_loop.degree, 4u + d);
        assert_int_equal(zw_loop_init(&ideal, &c, &ls), ZW_OK);
        for (i = 0u; i < 4u; ++i) {
            const zw_real beta = R(-0.4) + R(0.5) * (zw_real)i;
            zw_real a1, a2;
            assert_int_equal(zw_loop_alpha_max(&g_loop, &g_ws, beta, &a1), ZW_OK);
            assert_int_equal(zw_loop_alpha_max(&ideal, &g_ws, beta, &a2), ZW_OK);
            assert_true(fabsl((long double)a1 - (long double)a2) <= PREC(1e-6L, 1e-2L) * (1.0L + (long double)a2));
        }
    }
}

/* A stiff plant's extremes are certified: the reference is stable at (alpha_mmax,
 * beta_at_alpha_mmax) and at alpha_p_max on beta = 0, and inside (beta_mmin, beta_mmax) just
 * above alpha = 0. */
static void test_extremes_stiff(void **state)
{
    static const zw_real cases[][2] = {{R(0.5), R(0.1)}, {R(1.0), R(0.25)}, {R(0.05), R(2.0)}};
    unsigned c, k;
    (void)state;
    for (c = 0u; c < ZWT_ARRAY_LEN(cases); ++c) {
        const zw_loop *lp = plant_loop(cases[c][0], cases[c][1], 0u);
        const ref_plant rp = ref_plant_of((long double)cases[c][0], (long double)cases[c][1]);
        zw_loop_extremes x;
        assert_int_equal(zw_loop_extremes_compute(lp, &g_ws, &x), ZW_OK);
        assert_true(x.alpha_mmax > R(0.0));
        assert_true(x.alpha_mmax >= x.alpha_p_max);
        assert_true(ref_stable(&rp, 0u, (long double)x.alpha_mmax, (long double)x.beta_at_alpha_mmax));
        assert_true(x.alpha_p_max == R(0.0) || ref_stable(&rp, 0u, (long double)x.alpha_p_max, 0.0L));
        for (k = 1u; k < 8u; ++k) {
            const long double b = (long double)x.beta_mmin +
                                  ((long double)x.beta_mmax - (long double)x.beta_mmin) * (long double)k / 8.0L;
            assert_true(ref_stable(&rp, 0u, 1e-6L, b));
        }
    }
}

/* Real units: all parts 0 is zw_device_loop_init's loop (same K_max); bad parts are named
 * errors with the fail-safe outputs; a hand normalizes the gains by m + m_h. */
static void test_device_loop_plant(void **state)
{
    static zw_device_loop plain;
    zw_device_loop_spec spec;
    zw_real k1, k2;
    bool stable = true;
    (void)state;
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    assert_int_equal(zw_device_loop_init(&plain, R(0.1), R(3.0), R(1e-3), &spec), ZW_OK);
    assert_int_equal(zw_device_loop_init_plant(&g_dl, R(0.1), R(3.0), R(1e-3), R(0.0), R(0.0), R(0.0),
                                               R(0.0), R(0.0), &spec),
                     ZW_OK);
    assert_int_equal(zw_device_loop_k_max(&plain, &g_ws, R(1.0), &k1), ZW_OK);
    assert_int_equal(zw_device_loop_k_max(&g_dl, &g_ws, R(1.0), &k2), ZW_OK);
    assert_true(k1 > R(0.0));
    assert_true(fabsl((long double)k1 - (long double)k2) <= PREC(1e-9L, 1e-3L) * (long double)k1);
    /* errors */
    assert_int_equal(zw_device_loop_init_plant(&g_dl, R(0.1), R(3.0), R(1e-3), R(-1.0), R(0.0), R(0.0),
                                               R(0.0), R(0.0), &spec),
                     ZW_ERR_ARG);
    assert_int_not_equal(zw_device_loop_is_stable(&g_dl, &g_ws, R(1.0), R(0.0), &stable), ZW_OK);
    assert_false(stable);
    assert_int_equal(zw_device_loop_init_plant(&g_dl, R(0.1), R(3.0), R(1e-3), R(0.0), R(-1e-3), R(0.0),
                                               R(0.0), R(0.0), &spec),
                     ZW_ERR_ARG);
    assert_int_equal(zw_device_loop_init_plant(&g_dl, R(0.1), R(3.0), R(1e-3), R(0.0), R(0.0), R(0.1),
                                               R(-1.0), R(0.0), &spec),
                     ZW_ERR_DAMPING);
    assert_int_equal(zw_device_loop_init_plant(NULL, R(0.1), R(3.0), R(1e-3), R(0.0), R(0.0), R(0.0),
                                               R(0.0), R(0.0), &spec),
                     ZW_ERR_NULL);
    assert_int_equal(zw_device_loop_init_plant(&g_dl, R(0.1), R(3.0), R(1e-3), R(0.0), R(0.0), R(0.0),
                                               R(0.0), R(0.0), NULL),
                     ZW_ERR_NULL);
    /* a hand: K_max scales with M = m + m_h against the normalized limit */
    assert_int_equal(zw_device_loop_init_plant(&g_dl, R(0.1), R(3.0), R(1e-3), R(0.0), R(0.0), R(0.1),
                                               R(1.0), R(200.0), &spec),
                     ZW_OK);
    {
        zw_real amax, K;
        const zw_real M = R(0.2), T = R(1e-3);
        assert_int_equal(zw_loop_alpha_max(&g_dl.loop, &g_ws, R(0.0), &amax), ZW_OK);
        assert_int_equal(zw_device_loop_k_max(&g_dl, &g_ws, R(0.0), &K), ZW_OK);
        assert_true(K > R(0.0));
        assert_true((long double)K <= (long double)amax * (long double)M / ((long double)T * (long double)T));
        assert_true((long double)K >= (1.0L - PREC(1e-12L, 1e-5L)) * (long double)amax * (long double)M /
                                           ((long double)T * (long double)T));
    }
}

/* zw_loop_init_plant refuses a plant a failed zw_plant_init left (order 0), NULLs, and
 * leaves the empty loop that every function refuses. */
static void test_init_plant_errors(void **state)
{
    zw_plant_spec ps;
    zw_loop_spec ls;
    bool stable = true;
    zw_real amax = R(1.0);
    (void)state;
    memset(&ps, 0, sizeof ps);
    memset(&ls, 0, sizeof ls);
    ps.delta = R(-1.0);
    assert_int_equal(zw_plant_init(&g_plant, &ps), ZW_ERR_DELTA);
    assert_int_equal(zw_loop_init_plant(&g_loop, &g_plant, &ls), ZW_ERR_ARG);
    assert_int_equal(g_loop.degree, 0u);
    assert_int_equal(zw_loop_is_stable(&g_loop, &g_ws, R(0.1), R(0.1), &stable), ZW_ERR_ARG);
    assert_false(stable);
    assert_int_equal(zw_loop_alpha_max(&g_loop, &g_ws, R(0.1), &amax), ZW_ERR_ARG);
    assert_true(amax == R(0.0));
    assert_int_equal(zw_loop_init_plant(&g_loop, NULL, &ls), ZW_ERR_NULL);
    assert_int_equal(zw_loop_init_plant(NULL, &g_plant, &ls), ZW_ERR_NULL);
    ps.delta = R(0.5);
    ps.kappa = R(0.1);
    assert_int_equal(zw_plant_init(&g_plant, &ps), ZW_OK);
    assert_int_equal(zw_loop_init_plant(&g_loop, &g_plant, NULL), ZW_ERR_NULL);
    ls.delay = 99u;
    assert_int_equal(zw_loop_init_plant(&g_loop, &g_plant, &ls), ZW_ERR_DELAY);
    /* a loop rebuilt on its own plant (aliasing) */
    ls.delay = 1u;
    assert_int_equal(zw_loop_init_plant(&g_loop, &g_plant, &ls), ZW_OK);
    assert_int_equal(zw_loop_init_plant(&g_loop, &g_loop.plant, &ls), ZW_OK);
    assert_int_equal(g_loop.degree, 4u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_verdicts_against_reference),
        cmocka_unit_test(test_alpha_max_certified),
        cmocka_unit_test(test_stiffness_moves_z1_line),
        cmocka_unit_test(test_kappa_to_zero_is_ideal),
        cmocka_unit_test(test_lambda_to_zero_is_ideal),
        cmocka_unit_test(test_extremes_stiff),
        cmocka_unit_test(test_device_loop_plant),
        cmocka_unit_test(test_init_plant_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
