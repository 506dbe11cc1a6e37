/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Batch verdicts (zwidth/batch.h): zw_check_many and zw_device_check_many against the
 * per-call zw_check and zw_device_check, bit for bit, over large sweeps that put points on
 * and a few ulps either side of every boundary of the exact region, at the hard deltas
 * (0, subnormal, the critical constants, the switch points of the coefficients, up to the
 * largest delta the checks accept); every stride form (0, 1, 3, negative); and validation
 * before any write (first invalid pair's status and index; on any error every flag false,
 * the fail-safe output of status.h, and nothing past n written). */
#include "zw_test.h"

#include <stdlib.h>

/* Totals over the run, printed at the end of each sweep (the report counts them). */
static unsigned long g_compared, g_stable, g_marginal, g_flips;

/* ---- growable lists ----------------------------------------------------------------------- */

typedef struct vals {
    zw_real *v;
    size_t n, cap;
} vals;

static void vals_push(vals *l, zw_real x)
{
    if (!ZW_IS_FINITE(x)) return; /* the sweeps compare valid pairs only */
    if (l->n == l->cap) {
        size_t cap = l->cap != 0 ? 2 * l->cap : 256;
        zw_real *v = realloc(l->v, cap * sizeof *v);
        assert_non_null(v);
        l->v = v;
        l->cap = cap;
    }
    l->v[l->n++] = x;
}

/* x moved k zw_reals up (k > 0) or down (k < 0). */
static zw_real step(zw_real x, int k)
{
    for (; k > 0; --k) x = ZWT_UP(x);
    for (; k < 0; ++k) x = ZWT_DOWN(x);
    return x;
}

/* x and the k zw_reals either side of it. */
static void vals_push_ulps(vals *l, zw_real x, int k)
{
    int j;
    if (!ZW_IS_FINITE(x)) return;
    for (j = -k; j <= k; ++j) vals_push(l, step(x, j));
}

/* n + 1 evenly spaced values from lo to hi. */
static void vals_push_grid(vals *l, zw_real lo, zw_real hi, int n)
{
    int i;
    for (i = 0; i <= n; ++i) vals_push(l, lo + (hi - lo) * (zw_real)i / (zw_real)n);
}

/* Values far from any boundary, up to the largest finite one, both signs. */
static void vals_push_large(vals *l)
{
    const zw_real big[] = {R(1e6), R(1e15), R(1e30), R(PREC(1e150, 1e19)),
                           ZW_SQRT(ZW_REAL_MAX), ZW_REAL_MAX / R(4.0), ZW_REAL_MAX / R(2.0),
                           ZWT_DOWN(ZW_REAL_MAX), ZW_REAL_MAX};
    size_t i;
    for (i = 0; i < ZWT_ARRAY_LEN(big); ++i) {
        vals_push(l, big[i]);
        vals_push(l, -big[i]);
    }
}

/* Zero, signed zero and the smallest numbers either side. */
static void vals_push_tiny(vals *l)
{
    vals_push_ulps(l, R(0.0), 2); /* 0, +-1 and +-2 subnormal quanta */
    vals_push(l, -R(0.0));
    vals_push(l, ZW_REAL_MIN);
    vals_push(l, -ZW_REAL_MIN);
    vals_push(l, R(1e-12));
    vals_push(l, -R(1e-12));
}

static void vals_free(vals *l)
{
    free(l->v);
    l->v = NULL;
    l->n = l->cap = 0;
}

typedef struct pairs {
    zw_real *a, *b; /* alpha and beta (or K and B) */
    size_t n, cap;
} pairs;

static void pairs_push(pairs *p, zw_real a, zw_real b)
{
    if (p->n == p->cap) {
        size_t cap = p->cap != 0 ? 2 * p->cap : 1024;
        zw_real *na = realloc(p->a, cap * sizeof *na), *nb;
        assert_non_null(na);
        p->a = na;
        nb = realloc(p->b, cap * sizeof *nb);
        assert_non_null(nb);
        p->b = nb;
        p->cap = cap;
    }
    p->a[p->n] = a;
    p->b[p->n] = b;
    ++p->n;
}

static void pairs_free(pairs *p)
{
    free(p->a);
    free(p->b);
    p->a = p->b = NULL;
    p->n = p->cap = 0;
}

/* ---- the comparison ------------------------------------------------------------------------- */

/* One verdict source: zw_check on a plant's coefficients, or zw_device_check on a device. */
typedef struct source {
    const zw_coeffs *c;
    const zw_device *d;
} source;

static zw_status single(const source *s, zw_real a, zw_real b, zw_verdict *v)
{
    return s->d != NULL ? zw_device_check(s->d, a, b, v) : zw_check(s->c, a, b, v);
}

static zw_status many(const source *s, size_t n, const zw_real *a, ptrdiff_t as, const zw_real *b,
                      ptrdiff_t bs, bool *stable, size_t *first_invalid)
{
    return s->d != NULL ? zw_device_check_many(s->d, n, a, as, b, bs, stable, first_invalid)
                        : zw_check_many(s->c, n, a, as, b, bs, stable, first_invalid);
}

#define ZWT_GUARD 8 /* sentinel bytes after the output, to see that nothing past n is written */

/* The batch over pair i = (a[i as], b[i bs]), i < n, against the per-call verdict of each
 * pair: every output byte must equal the bool the single call returns (so also be 0 or 1),
 * and the bytes after stable[n - 1] must stay untouched.  Counts into the totals. */
static void expect_batch_equals_single(const source *s, size_t n, const zw_real *a, ptrdiff_t as,
                                       const zw_real *b, ptrdiff_t bs)
{
    bool *got = malloc((n + ZWT_GUARD) * sizeof(bool)), *want = malloc((n + 1) * sizeof(bool));
    unsigned char guard[ZWT_GUARD];
    size_t i, bad = 0;
    assert_non_null(got);
    assert_non_null(want);
    memset(got, ZWT_SENTINEL, (n + ZWT_GUARD) * sizeof(bool));
    memset(guard, ZWT_SENTINEL, sizeof guard);
    for (i = 0; i < n; ++i) {
        zw_verdict v;
        EXPECT_OK(single(s, a[(ptrdiff_t)i * as], b[(ptrdiff_t)i * bs], &v));
        want[i] = v.stable;
        g_stable += v.stable;
        g_marginal += v.marginal;
        if (i > 0 && want[i] != want[i - 1]) ++g_flips;
    }
    EXPECT_OK(many(s, n, a, as, b, bs, got, NULL));
    for (i = 0; i < n; ++i) {
        if (memcmp(&got[i], &want[i], sizeof(bool)) != 0) {
            unsigned char byte;
            memcpy(&byte, &got[i], 1);
            if (bad++ < 10)
                print_error("pair %zu: %s = %a, %s = %a (delta %a): batch byte %u, single %d\n", i,
                            s->d != NULL ? "K" : "alpha", (double)a[(ptrdiff_t)i * as],
                            s->d != NULL ? "B" : "beta", (double)b[(ptrdiff_t)i * bs],
                            (double)(s->d != NULL ? s->d->co.delta : s->c->delta), (unsigned)byte,
                            (int)want[i]);
        }
    }
    EXPECT_TRUE_MSG(bad == 0, "%zu of %zu batch verdicts differ from the single calls", bad, n);
    assert_memory_equal((const unsigned char *)(got + n), guard, ZWT_GUARD);
    g_compared += n;
    free(got);
    free(want);
}

static void expect_pairs_equal(const source *s, const pairs *p)
{
    expect_batch_equals_single(s, p->n, p->a, 1, p->b, 1);
}

/* ---- normalized sweeps ------------------------------------------------------------------------- */

/* The points of one plant: a cross product of alphas and betas on and around every named
 * point of the region (the extremes, the corner, the top of the hyperbola, its right end
 * 2/c2, beta = -delta, alpha = 0, the largest numbers), a grid, and along every beta the
 * boundary alpha_max(beta) and along every alpha the ends of the beta interval, each with
 * the zw_reals a few ulps either side. */
static void normalized_pairs(const zw_coeffs *c, pairs *p)
{
    const zw_real d = c->delta, scale = d + R(1.0);
    vals A = {NULL, 0, 0}, B = {NULL, 0, 0};
    zw_extremes x;
    zw_real a1, b1, a2, b2, am, lo, hi;
    bool nonempty, have_x = zw_extremes_compute(c, &x) == ZW_OK;
    size_t i, j;
    int k, n;

    /* betas */
    vals_push_ulps(&B, -d, 4);
    vals_push(&B, -d * (R(1.0) + TOL(64)));
    vals_push(&B, -d * (R(1.0) - TOL(64)));
    vals_push(&B, -d + R(1e-3) * scale);
    vals_push_tiny(&B);
    if (have_x) {
        vals_push_ulps(&B, x.beta_mmax, 4);
        vals_push_ulps(&B, x.beta_at_alpha_mmax, 2);
    }
    if (c->c2 > R(0.0)) vals_push_ulps(&B, R(2.0) / c->c2, 3); /* right end of the hyperbola */
    if (zw_hyperbola_top(c, &a1, &b1) == ZW_OK) vals_push_ulps(&B, b1, 2);
    if (zw_corner(c, &a2, &b2) == ZW_OK) vals_push_ulps(&B, b2, 3);
    vals_push_grid(&B, -d - R(0.1) * scale, (have_x ? x.beta_mmax : R(2.0)) + R(0.1) * scale, 48);
    vals_push_large(&B);

    /* alphas */
    vals_push_tiny(&A);
    if (have_x) {
        vals_push_ulps(&A, x.alpha_mmax, 4);
        vals_push_ulps(&A, x.alpha_p_max, 4);
        vals_push_grid(&A, -R(0.05) * x.alpha_mmax, R(1.25) * x.alpha_mmax + R(0.05), 48);
    } else {
        vals_push_grid(&A, -R(0.05) * scale, R(5.0) * scale, 48);
    }
    if (zw_hyperbola_top(c, &a1, &b1) == ZW_OK) vals_push_ulps(&A, a1, 2);
    if (zw_corner(c, &a2, &b2) == ZW_OK) vals_push_ulps(&A, a2, 3);
    vals_push_large(&A);

    for (i = 0; i < A.n; ++i)
        for (j = 0; j < B.n; ++j) pairs_push(p, A.v[i], B.v[j]);
    /* the boundary alpha = alpha_max(beta) along every beta, to the ulp */
    for (j = 0; j < B.n; ++j) {
        if (zw_alpha_max(c, B.v[j], &am) != ZW_OK || !(am > R(0.0))) continue;
        for (k = -6; k <= 6; ++k) pairs_push(p, step(am, k), B.v[j]);
        pairs_push(p, am * (R(1.0) - TOL(64)), B.v[j]);
        pairs_push(p, am * (R(1.0) + TOL(64)), B.v[j]);
        pairs_push(p, am * R(0.5), B.v[j]);
    }
    /* the ends of the stable beta interval along every alpha, to the ulp */
    for (i = 0; i < A.n; ++i) {
        if (zw_beta_interval(c, A.v[i], &lo, &hi, &nonempty) != ZW_OK || !nonempty) continue;
        for (k = -6; k <= 6; ++k) {
            zw_real bl = step(lo, k), bh = step(hi, k);
            if (ZW_IS_FINITE(bl)) pairs_push(p, A.v[i], bl);
            if (ZW_IS_FINITE(bh)) pairs_push(p, A.v[i], bh);
        }
    }
    /* a dense walk along the boundary */
    if (have_x) {
        n = 400;
        for (j = 1; j < (size_t)n; ++j) {
            zw_real beta = -d + (x.beta_mmax + d) * (zw_real)j / (zw_real)n;
            if (zw_alpha_max(c, beta, &am) != ZW_OK || !(am > R(0.0))) continue;
            for (k = -3; k <= 3; ++k) pairs_push(p, step(am, k), beta);
        }
    }
    vals_free(&A);
    vals_free(&B);
}

/* The largest delta at which the checks still answer (hs finite), to the ulp. */
static zw_real largest_checked_delta(void)
{
    zw_real lo = ZW_REAL_MAX / R(16.0), hi = ZW_REAL_MAX;
    zw_coeffs c = zwt_coeffs(lo);
    assert_true(ZW_IS_FINITE(c.hs));
    c = zwt_coeffs(hi);
    assert_false(ZW_IS_FINITE(c.hs));
    while (ZWT_UP(lo) < hi) {
        zw_real mid = lo + (hi - lo) / R(2.0);
        if (mid <= lo || mid >= hi) mid = ZWT_UP(lo);
        c = zwt_coeffs(mid);
        if (ZW_IS_FINITE(c.hs)) lo = mid;
        else hi = mid;
    }
    return lo;
}

/* The deltas of the sweeps: 0, subnormal, tiny, the switch points of the coefficients
 * (the series/literal switch at 2, sigma at powers of two) and the critical constants
 * with a few ulps either side, the paper's plants, and large deltas up to the largest one
 * the checks accept. */
static void sweep_deltas(vals *D)
{
    const zw_real named[] = {ZW_DELTA0, ZW_DELTA1, ZW_DELTA2, ZW_DELTA_K1, ZW_DELTA_K2,
                             ZW_DELTA_B, ZW_DELTA_BB, ZW_DELTA_KM, R(1.0), R(2.0), R(4.0),
                             R(1024.0)};
    const zw_real plain[] = {R(0.0), ZWT_TRUE_MIN, R(7.0) * ZWT_TRUE_MIN, ZW_REAL_MIN / R(2.0),
                             ZW_REAL_MIN, R(1e-30), R(1e-12), R(1e-6), R(0.013), R(0.5), R(2.049),
                             R(3.0), R(5.1224), R(10.0), R(20.0), R(100.0), R(1e4), R(1e6),
                             R(1e12), R(1e15), R(1e30), R(PREC(1e100, 1e20)),
                             ZW_SQRT(ZW_REAL_MAX), ZW_REAL_MAX / R(64.0)};
    zw_real top = largest_checked_delta();
    size_t i;
    for (i = 0; i < ZWT_ARRAY_LEN(named); ++i) vals_push_ulps(D, named[i], 2);
    for (i = 0; i < ZWT_ARRAY_LEN(plain); ++i) vals_push(D, plain[i]);
    vals_push(D, top / R(4.0));
    vals_push(D, top / R(2.0));
    vals_push(D, step(top, -3));
    vals_push(D, step(top, -1));
    vals_push(D, top);
}

/* (a) Every delta, exactly given (delta_relerr 0) and with an uncertain delta (3 u, as a
 * device has, and 1e-3): the batch answers what zw_check answers, pair for pair. */
static void test_check_many_equals_check(void **state)
{
    vals D = {NULL, 0, 0};
    const zw_real relerrs[] = {R(0.0), TOL(3), R(1e-3)};
    unsigned long before = g_compared, st0 = g_stable, mg0 = g_marginal, fl0 = g_flips;
    size_t k, r;
    (void)state;
    sweep_deltas(&D);
    for (k = 0; k < D.n; ++k) {
        zw_coeffs c = zwt_coeffs(D.v[k]);
        pairs p = {NULL, NULL, 0, 0};
        source s;
        s.c = &c;
        s.d = NULL;
        assert_true(ZW_IS_FINITE(c.hs)); /* the checks answer at every delta of the sweep */
        normalized_pairs(&c, &p);
        assert_true(p.n > 1000);
        for (r = 0; r < ZWT_ARRAY_LEN(relerrs); ++r) {
            c.delta_relerr = relerrs[r];
            expect_pairs_equal(&s, &p);
        }
        pairs_free(&p);
    }
    printf("  check_many: %zu deltas x %zu delta uncertainties, %lu pairs compared "
           "(%lu stable, %lu marginal, %lu verdict changes between neighbours)\n",
           D.n, ZWT_ARRAY_LEN(relerrs), g_compared - before, g_stable - st0, g_marginal - mg0,
           g_flips - fl0);
    /* the sweep really sits on the boundaries: inside, outside and in the rounding band */
    assert_true(g_stable - st0 > 10000);
    assert_true(g_marginal - mg0 > 1000);
    assert_true(g_flips - fl0 > 1000);
    vals_free(&D);
}

/* ---- device sweeps ------------------------------------------------------------------------------ */

/* Gains (K, B) of one device: a log grid of K over [1e-6, 1e9] and of |B|, B near -b, the
 * device extremes, K = K_max(B) along every B and the ends of the B range along every K,
 * each with neighbours to the ulp; only pairs zw_device_check accepts (the others are
 * errors, tested below). */
static void device_pairs(const zw_device *d, pairs *p)
{
    vals K = {NULL, 0, 0}, B = {NULL, 0, 0};
    zw_device_extremes x;
    bool have_x = zw_device_extremes_compute(d, &x) == ZW_OK, nonempty;
    zw_real km, lo, hi;
    size_t i, j;
    int k;

    vals_push_tiny(&K);
    vals_push(&K, R(-1.0));
    for (k = 0; k <= 30; ++k) vals_push(&K, (zw_real)pow(10.0, -6.0 + 0.5 * (double)k));
    if (have_x) {
        vals_push_ulps(&K, x.K_mmax, 4);
        vals_push_ulps(&K, x.K_p_max, 4);
        vals_push_grid(&K, R(0.0), R(1.25) * x.K_mmax, 24);
    }
    vals_push(&K, R(1e15));
    vals_push(&K, R(1e30));
    vals_push(&K, ZW_REAL_MAX);

    vals_push_ulps(&B, -d->b, 4);
    vals_push(&B, -d->b * R(0.999));
    vals_push_tiny(&B);
    for (k = 0; k <= 15; ++k) {
        zw_real m = (zw_real)pow(10.0, -9.0 + (double)k);
        vals_push(&B, m);
        vals_push(&B, -m);
    }
    if (have_x) {
        vals_push_ulps(&B, x.B_mmax, 4);
        vals_push_ulps(&B, x.B_at_K_mmax, 2);
        vals_push_grid(&B, -d->b - R(0.1) * x.B_mmax, R(1.1) * x.B_mmax, 24);
    }
    vals_push(&B, ZW_REAL_MAX);
    vals_push(&B, -ZW_REAL_MAX);

#define PUSH_IF_OK(kk, bb)                                                                         \
    do {                                                                                           \
        zw_verdict v_;                                                                             \
        if (zw_device_check(d, (kk), (bb), &v_) == ZW_OK) pairs_push(p, (kk), (bb));              \
    } while (0)
    for (i = 0; i < K.n; ++i)
        for (j = 0; j < B.n; ++j) PUSH_IF_OK(K.v[i], B.v[j]);
    for (j = 0; j < B.n; ++j) {
        if (zw_device_k_max(d, B.v[j], &km) != ZW_OK || !(km > R(0.0))) continue;
        for (k = -6; k <= 6; ++k) PUSH_IF_OK(step(km, k), B.v[j]);
    }
    for (i = 0; i < K.n; ++i) {
        if (zw_device_b_range(d, K.v[i], &lo, &hi, &nonempty) != ZW_OK || !nonempty) continue;
        for (k = -6; k <= 6; ++k) {
            PUSH_IF_OK(K.v[i], step(lo, k));
            PUSH_IF_OK(K.v[i], step(hi, k));
        }
    }
#undef PUSH_IF_OK
    vals_free(&K);
    vals_free(&B);
}

/* (a) Plants m in [1e-8, 1e3], T in [1e-6, 1], b from 0 up, including the b that put
 * delta on the critical constants. */
static void test_device_check_many_equals_device_check(void **state)
{
    const zw_real ms[] = {R(1e-8), R(1e-6), R(1e-4), R(1e-2), R(1.0), R(10.0), R(1e3)};
    const zw_real Ts[] = {R(1e-6), R(1e-4), R(1e-3), R(1e-2), R(0.1), R(1.0)};
    const zw_real bs_abs[] = {R(0.0), R(1e-6), R(1e-3), R(1.0), R(1e3)};
    const zw_real deltas[] = {R(1e-9), R(0.013), R(1.0), ZW_DELTA0, ZW_DELTA1, ZW_DELTA2,
                              R(5.1224), R(1e3), R(1e6)};
    unsigned long before = g_compared, st0 = g_stable, mg0 = g_marginal;
    size_t im, it, ib, devices = 0, refused = 0;
    (void)state;
    for (im = 0; im < ZWT_ARRAY_LEN(ms); ++im) {
        for (it = 0; it < ZWT_ARRAY_LEN(Ts); ++it) {
            for (ib = 0; ib < ZWT_ARRAY_LEN(bs_abs) + ZWT_ARRAY_LEN(deltas); ++ib) {
                zw_real m = ms[im], T = Ts[it];
                zw_real b = ib < ZWT_ARRAY_LEN(bs_abs) ? bs_abs[ib]
                                                       : deltas[ib - ZWT_ARRAY_LEN(bs_abs)] * m / T;
                zw_device d;
                pairs p = {NULL, NULL, 0, 0};
                source s;
                if (zw_device_init(&d, m, b, T) != ZW_OK) {
                    ++refused; /* e.g. delta subnormal in float */
                    continue;
                }
                ++devices;
                s.c = NULL;
                s.d = &d;
                device_pairs(&d, &p);
                assert_true(p.n > 500);
                expect_pairs_equal(&s, &p);
                pairs_free(&p);
            }
        }
    }
    printf("  device_check_many: %zu devices (%zu plants refused by zw_device_init), %lu pairs "
           "compared (%lu stable, %lu marginal)\n",
           devices, refused, g_compared - before, g_stable - st0, g_marginal - mg0);
    assert_true(devices > 300);
    assert_true(g_stable - st0 > 10000);
    assert_true(g_marginal - mg0 > 100);
}

/* ---- strides ------------------------------------------------------------------------------------- */

/* A strided copy of v (n values): element i at out[i * stride] (stride != 0, pointer to the
 * first pair returned); the gaps hold NaN, which the batch must never read. */
static zw_real *strided(const zw_real *v, size_t n, ptrdiff_t stride, zw_real **base)
{
    size_t span = (n - 1) * (size_t)(stride < 0 ? -stride : stride) + 1, i;
    zw_real *buf = malloc(span * sizeof *buf), *first;
    assert_non_null(buf);
    for (i = 0; i < span; ++i) buf[i] = (zw_real)NAN;
    first = stride < 0 ? buf + span - 1 : buf;
    for (i = 0; i < n; ++i) first[(ptrdiff_t)i * stride] = v[i];
    *base = buf;
    return first;
}

/* (b) Strides 1, 3, -1, -3 on each side, mixed, and 0 (one value broadcast) on either or
 * both sides: the same answers as the per-call loop on the same pairs. */
static void stride_forms(const source *s, const pairs *p)
{
    static const ptrdiff_t strides[] = {1, 3, -1, -3, 2};
    size_t ia, ib, k;
    for (ia = 0; ia < ZWT_ARRAY_LEN(strides); ++ia) {
        for (ib = 0; ib < ZWT_ARRAY_LEN(strides); ++ib) {
            zw_real *abuf, *bbuf;
            const zw_real *a = strided(p->a, p->n, strides[ia], &abuf);
            const zw_real *b = strided(p->b, p->n, strides[ib], &bbuf);
            expect_batch_equals_single(s, p->n, a, strides[ia], b, strides[ib]);
            free(abuf);
            free(bbuf);
        }
    }
    /* stride 0: one alpha (or K) against every beta, one beta against every alpha, and one
     * pair repeated; the broadcast values are boundary points of the set itself */
    for (k = 0; k < p->n; k += p->n / 13 + 1) {
        zw_real *bbuf;
        const zw_real *b = strided(p->b, p->n, -3, &bbuf);
        expect_batch_equals_single(s, p->n, &p->a[k], 0, p->b, 1);
        expect_batch_equals_single(s, p->n, p->a, 1, &p->b[k], 0);
        expect_batch_equals_single(s, p->n, &p->a[k], 0, b, -3);
        expect_batch_equals_single(s, 257, &p->a[k], 0, &p->b[k], 0);
        expect_batch_equals_single(s, 1, &p->a[k], 0, &p->b[k], 0);
        free(bbuf);
    }
}

static void test_strides(void **state)
{
    static const zw_real ds[] = {R(0.0), R(1e-12), R(1.0), ZW_DELTA0, R(5.1224), R(1e6)};
    unsigned long before = g_compared;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        pairs p = {NULL, NULL, 0, 0};
        source s;
        s.c = &c;
        s.d = NULL;
        normalized_pairs(&c, &p);
        stride_forms(&s, &p);
        pairs_free(&p);
    }
    {
        zw_device d;
        pairs p = {NULL, NULL, 0, 0};
        source s;
        EXPECT_OK(zw_device_init(&d, R(85.78e-7), R(2.197e-3), R(0.02))); /* the paper's drive */
        s.c = NULL;
        s.d = &d;
        device_pairs(&d, &p);
        stride_forms(&s, &p);
        pairs_free(&p);
    }
    printf("  strides: %lu pairs compared\n", g_compared - before);
}

/* ---- errors ---------------------------------------------------------------------------------------- */

#define ZWT_N 16u
#define ZWT_NO_INDEX ((size_t)0xA5A5A5A5u)

/* The fail-safe output of a failed call: stable[0 .. n-1] false, the bytes after them (to
 * total) still the sentinel.  Read as bytes: a sentinel is not a valid bool. */
static void expect_all_false(const bool *out, size_t n, size_t total)
{
    const unsigned char *bytes = (const unsigned char *)out;
    size_t i;
    for (i = 0; i < n * sizeof(bool); ++i) EXPECT_TRUE_MSG(bytes[i] == 0u, "byte %zu", i);
    for (; i < total * sizeof(bool); ++i) EXPECT_TRUE_MSG(bytes[i] == ZWT_SENTINEL, "byte %zu", i);
}

/* Expect status want, every flag false and nothing past n written; *first_invalid ==
 * want_index.  Also with first_invalid NULL. */
static void expect_many_error(const source *s, size_t n, const zw_real *a, ptrdiff_t as,
                              const zw_real *b, ptrdiff_t bs, zw_status want, size_t want_index)
{
    bool out[ZWT_N + ZWT_GUARD];
    size_t fi = ZWT_NO_INDEX;
    memset(out, ZWT_SENTINEL, sizeof out);
    EXPECT_STATUS(many(s, n, a, as, b, bs, out, &fi), want);
    expect_all_false(out, n, ZWT_ARRAY_LEN(out));
    assert_true(fi == want_index);
    memset(out, ZWT_SENTINEL, sizeof out);
    EXPECT_STATUS(many(s, n, a, as, b, bs, out, NULL), want);
    expect_all_false(out, n, ZWT_ARRAY_LEN(out));
}

/* Fill n valid pairs (inside and outside the region). */
static void fill_valid(zw_real *a, zw_real *b, size_t n, zw_real scale)
{
    size_t i;
    for (i = 0; i < n; ++i) {
        a[i] = scale * (zw_real)(i % 5) * R(0.7);
        b[i] = scale * ((zw_real)(i % 7) - R(2.0)) * R(0.4);
    }
}

/* (c) An invalid alpha or beta at pair k: the status zw_check gives that pair, index k,
 * nothing written (also when it is the last pair, so the loop proper never started),
 * whatever the stride; the first of two invalid pairs wins. */
static void invalid_pairs(const source *s, zw_real scale)
{
    const zw_real nan = (zw_real)NAN, inf = (zw_real)INFINITY;
    const zw_real bad[][2] = {{nan, R(0.0)}, {R(1.0), nan}, {inf, R(0.0)}, {-inf, R(0.0)},
                              {R(1.0), inf}, {R(1.0), -inf}, {inf, nan}, {nan, inf}};
    const size_t ks[] = {0, 1, ZWT_N / 2, ZWT_N - 1};
    zw_real a[ZWT_N], b[ZWT_N], ra[ZWT_N], rb[ZWT_N];
    size_t ib, ik, i;
    for (ib = 0; ib < ZWT_ARRAY_LEN(bad); ++ib) {
        zw_verdict v;
        zw_status want = single(s, bad[ib][0], bad[ib][1], &v);
        assert_int_not_equal(want, ZW_OK);
        for (ik = 0; ik < ZWT_ARRAY_LEN(ks); ++ik) {
            size_t k = ks[ik];
            fill_valid(a, b, ZWT_N, scale);
            a[k] = bad[ib][0];
            b[k] = bad[ib][1];
            expect_many_error(s, ZWT_N, a, 1, b, 1, want, k);
            /* reversed storage, stride -1: pair k is at index N - 1 - k */
            for (i = 0; i < ZWT_N; ++i) {
                ra[ZWT_N - 1 - i] = a[i];
                rb[ZWT_N - 1 - i] = b[i];
            }
            expect_many_error(s, ZWT_N, ra + ZWT_N - 1, -1, rb + ZWT_N - 1, -1, want, k);
            /* a second invalid pair after it does not change the answer */
            if (k + 1 < ZWT_N) {
                a[ZWT_N - 1] = nan;
                expect_many_error(s, ZWT_N, a, 1, b, 1, want, k);
            }
        }
        /* stride 0 on the invalid side: pair 0 already reads it */
        fill_valid(a, b, ZWT_N, scale);
        if ((want = single(s, bad[ib][0], b[0], &v)) != ZW_OK)
            expect_many_error(s, ZWT_N, &bad[ib][0], 0, b, 1, want, 0);
        if ((want = single(s, a[0], bad[ib][1], &v)) != ZW_OK)
            expect_many_error(s, ZWT_N, a, 1, &bad[ib][1], 0, want, 0);
    }
}

static void test_errors_invalid_pairs(void **state)
{
    zw_coeffs c = zwt_coeffs(R(5.1224));
    zw_device d;
    source s;
    (void)state;
    s.c = &c;
    s.d = NULL;
    invalid_pairs(&s, R(1.0));
    EXPECT_OK(zw_device_init(&d, R(85.78e-7), R(2.197e-3), R(0.02)));
    s.c = NULL;
    s.d = &d;
    invalid_pairs(&s, R(1e-3));
}

/* (c) Device gains whose normalized value overflows: ZW_ERR_RANGE at that pair, as
 * zw_device_check says (k_scale = m / T^2 and b_scale = m / T both 1e-8 here). */
static void test_errors_device_range(void **state)
{
    zw_device d;
    zw_real K[ZWT_N], B[ZWT_N];
    zw_verdict v;
    source s;
    size_t k;
    (void)state;
    EXPECT_OK(zw_device_init(&d, R(1e-8), R(1e-9), R(1.0)));
    s.c = NULL;
    s.d = &d;
    for (k = 0; k < ZWT_N; ++k) {
        fill_valid(K, B, ZWT_N, R(1e-9));
        K[k] = ZW_REAL_MAX / R(2.0); /* alpha = K / 1e-8: +inf */
        EXPECT_STATUS(zw_device_check(&d, K[k], B[k], &v), ZW_ERR_RANGE);
        expect_many_error(&s, ZWT_N, K, 1, B, 1, ZW_ERR_RANGE, k);
        fill_valid(K, B, ZWT_N, R(1e-9));
        B[k] = -ZW_REAL_MAX; /* beta = B / 1e-8: -inf */
        EXPECT_STATUS(zw_device_check(&d, K[k], B[k], &v), ZW_ERR_RANGE);
        expect_many_error(&s, ZWT_N, K, 1, B, 1, ZW_ERR_RANGE, k);
        /* a range error before an invalid input: the earlier pair wins */
        if (k + 1 < ZWT_N) {
            fill_valid(K, B, ZWT_N, R(1e-9));
            K[k] = ZW_REAL_MAX;
            K[ZWT_N - 1] = (zw_real)NAN;
            expect_many_error(&s, ZWT_N, K, 1, B, 1, ZW_ERR_RANGE, k);
        }
    }
    /* the boundary of the overflow: the last K that normalizes is compared, the next refused */
    {
        zw_real kmax = ZW_REAL_MAX * d.k_scale, Bz = R(0.0);
        zw_real alpha, beta;
        while (zw_device_normalize(&d, kmax, Bz, &alpha, &beta) != ZW_OK) kmax = ZWT_DOWN(kmax);
        while (zw_device_normalize(&d, ZWT_UP(kmax), Bz, &alpha, &beta) == ZW_OK) kmax = ZWT_UP(kmax);
        expect_batch_equals_single(&s, 1, &kmax, 0, &Bz, 0);
        kmax = ZWT_UP(kmax);
        expect_many_error(&s, 1, &kmax, 0, &Bz, 0, ZW_ERR_RANGE, 0);
    }
}

/* (c) Coefficient errors: the status zw_check gives every pair (delta = +inf: ZW_ERR_INF,
 * NaN: ZW_ERR_NAN, delta_relerr < 0: ZW_ERR_ARG, hs = +inf: ZW_ERR_RANGE), before any
 * pair is looked at, every flag false, *first_invalid = 0 (they concern every pair). */
static void test_errors_coefficients(void **state)
{
    zw_coeffs cinf = zwt_coeffs((zw_real)INFINITY), cnan = zwt_coeffs(R(1.0)),
              cbig = zwt_coeffs(ZW_REAL_MAX), carg = zwt_coeffs(R(5.0)),
              cedge = zwt_coeffs(ZWT_UP(largest_checked_delta()));
    const zw_coeffs *cs[] = {&cinf, &cnan, &cbig, &carg, &carg, &cedge};
    zw_real a[ZWT_N], b[ZWT_N];
    size_t i, k;
    (void)state;
    cnan.delta = (zw_real)NAN;
    for (i = 0; i < ZWT_ARRAY_LEN(cs); ++i) {
        zw_coeffs c = *cs[i];
        zw_verdict v;
        zw_status want;
        source s;
        if (i == 3) c.delta_relerr = R(-1e-3);
        if (i == 4) c.delta_relerr = (zw_real)NAN;
        s.c = &c;
        s.d = NULL;
        fill_valid(a, b, ZWT_N, R(1.0));
        want = zw_check(&c, a[0], b[0], &v);
        assert_int_not_equal(want, ZW_OK);
        for (k = 0; k < 2; ++k) {
            if (k == 1) a[3] = (zw_real)NAN; /* and an invalid pair: the plant is reported */
            expect_many_error(&s, ZWT_N, a, 1, b, 1, want, 0);
        }
    }
}

/* (c) NULL pointers, and n = 0 (ZW_OK whatever the pointers, nothing touched). */
static void test_errors_null_and_empty(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0));
    zw_device d;
    zw_real a[ZWT_N], b[ZWT_N];
    bool out[ZWT_N];
    unsigned char before[sizeof out];
    size_t fi;
    (void)state;
    EXPECT_OK(zw_device_init(&d, R(1.0), R(1.0), R(1e-3)));
    fill_valid(a, b, ZWT_N, R(1.0));
    memset(out, ZWT_SENTINEL, sizeof out);
    memcpy(before, out, sizeof out);

    fi = ZWT_NO_INDEX;
    EXPECT_STATUS(zw_check_many(NULL, ZWT_N, a, 1, b, 1, out, &fi), ZW_ERR_NULL);
    assert_true(fi == 0); /* a NULL concerns every pair */
    expect_all_false(out, ZWT_N, ZWT_N); /* the other outputs are still fail-safe */
    memset(out, ZWT_SENTINEL, sizeof out);
    EXPECT_STATUS(zw_check_many(&c, ZWT_N, NULL, 1, b, 1, out, &fi), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check_many(&c, ZWT_N, a, 1, NULL, 1, out, &fi), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check_many(&c, ZWT_N, a, 1, b, 1, NULL, &fi), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check_many(&c, ZWT_N, a, 0, b, 0, NULL, NULL), ZW_ERR_NULL);
    /* NULL wins over an invalid pair (it is found without reading any) */
    a[2] = (zw_real)NAN;
    EXPECT_STATUS(zw_check_many(&c, ZWT_N, a, 1, b, 1, NULL, &fi), ZW_ERR_NULL);
    a[2] = R(0.5);
    expect_all_false(out, ZWT_N, ZWT_N);
    memset(out, ZWT_SENTINEL, sizeof out);

    fi = ZWT_NO_INDEX;
    EXPECT_STATUS(zw_device_check_many(NULL, ZWT_N, a, 1, b, 1, out, &fi), ZW_ERR_NULL);
    assert_true(fi == 0);
    expect_all_false(out, ZWT_N, ZWT_N);
    memset(out, ZWT_SENTINEL, sizeof out);
    EXPECT_STATUS(zw_device_check_many(&d, ZWT_N, NULL, 1, b, 1, out, &fi), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_check_many(&d, ZWT_N, a, 1, NULL, 1, out, &fi), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_check_many(&d, ZWT_N, a, 1, b, 1, NULL, &fi), ZW_ERR_NULL);
    expect_all_false(out, ZWT_N, ZWT_N);
    memset(out, ZWT_SENTINEL, sizeof out);

    /* n = 0: nothing to check, nothing read or written, even with every pointer NULL */
    fi = ZWT_NO_INDEX;
    EXPECT_OK(zw_check_many(NULL, 0, NULL, 1, NULL, 1, NULL, &fi));
    EXPECT_OK(zw_check_many(&c, 0, NULL, 0, NULL, 0, NULL, NULL));
    EXPECT_OK(zw_check_many(&c, 0, a, 1, b, 1, out, &fi));
    EXPECT_OK(zw_device_check_many(NULL, 0, NULL, 1, NULL, 1, NULL, &fi));
    EXPECT_OK(zw_device_check_many(&d, 0, NULL, -1, NULL, 3, NULL, NULL));
    EXPECT_OK(zw_device_check_many(&d, 0, a, 1, b, 1, out, &fi));
    assert_true(fi == ZWT_NO_INDEX);
    assert_memory_equal(out, before, sizeof out);
    /* n = 0 with an invalid plant is still nothing to do */
    {
        zw_coeffs cinf = zwt_coeffs((zw_real)INFINITY);
        EXPECT_OK(zw_check_many(&cinf, 0, a, 1, b, 1, out, &fi));
        assert_memory_equal(out, before, sizeof out);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_check_many_equals_check),
        cmocka_unit_test(test_device_check_many_equals_device_check),
        cmocka_unit_test(test_strides),
        cmocka_unit_test(test_errors_invalid_pairs),
        cmocka_unit_test(test_errors_device_range),
        cmocka_unit_test(test_errors_coefficients),
        cmocka_unit_test(test_errors_null_and_empty),
    };
    int failed;
    printf("zwidth C tests: batch (%s)\n", ZW_REAL_NAME);
    failed = cmocka_run_group_tests_name("batch_" ZW_REAL_NAME, tests, NULL, NULL);
    printf("batch (%s): %lu pairs compared in all\n", ZW_REAL_NAME, g_compared);
    return failed;
}
