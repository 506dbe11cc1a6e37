/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The loop a real drive runs (loop.h): delay, velocity filters, Tustin.
 *
 * The characteristic polynomial p = D + alpha Na + beta Nb is built once per plant as a
 * product of linear factors, each coefficient with a running error bound (internal.h's
 * zw_eb).  Two versions are kept: the z coefficients (zw_loop_poly, roots) and the
 * bilinear ones (z = (1 + s)/(1 - s)), in which every factor has non-negative
 * coefficients formed without cancellation; the guarded verdict is a Routh test on the
 * latter (see zw_loop_check below).
 */
#include "zwidth/loop.h"

#include <stddef.h>
#include <stdint.h>

#include "internal.h"


/* The small helpers of the tests' inner loops, inlined where the build optimizes for speed
 * (host, -O2: the call overhead was half the cost of a low-degree check) and left to the
 * compiler under -Os (firmware: code size and small frames first). */
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define LOOP_HOT __attribute__((always_inline)) inline
#else
#define LOOP_HOT
#endif

/* Inlined in every build: the deepest chains of the checks (the root test's products and
 * Newton steps, the careful coefficient bound) are shallower with these in their callers'
 * frames (the 512 B stack target, tools/footprint.sh; about 1.8 KB more code on the M4F). */
#if defined(__GNUC__)
#define LOOP_INLINE __attribute__((always_inline)) inline
#else
#define LOOP_INLINE
#endif

#define LOOP_PI ZW_R(3.14159265358979323846)
#define LOOP_N (ZW_LOOP_MAX_DEGREE + 1u)

/* ---- input checks ---------------------------------------------------------------------- */

zw_status zw_loop_lowpass_pole(zw_real f_c, zw_real T, zw_real *a)
{
    zw_status st;
    zw_real x;
    if (a == NULL) {
        return ZW_ERR_NULL;
    }
    *a = ZW_R(0.0);
    st = zw_require_finite(f_c);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_require_finite(T);
    if (st != ZW_OK) {
        return st;
    }
    if (!(T > ZW_R(0.0))) {
        return ZW_ERR_PERIOD;
    }
    /* f_c T >= 1/2 implies fl(f_c T) >= 1/2 (rounding is monotone, 1/2 representable), so a
     * cut-off at or above Nyquist is always refused; one a rounding below it may be too */
    x = f_c * T;
    if (!(f_c > ZW_R(0.0)) || !(x < ZW_R(0.5))) {
        return ZW_ERR_FILTER;
    }
    x = ZW_EXP(-(ZW_R(2.0) * LOOP_PI) * x);
    /* a cut-off so low that the pole rounds to 1 is an integrator, not a filter */
    if (!(x < ZW_R(1.0))) {
        return ZW_ERR_FILTER;
    }
    *a = x;
    return ZW_OK;
}

/* Degree of the velocity estimate Nv / Dv (numerator and denominator). */
static unsigned estimate_degree(const zw_loop_spec *spec)
{
    if (spec->filter == ZW_VFILTER_AVERAGE) {
        return spec->average;
    }
    if ((spec->filter == ZW_VFILTER_LOWPASS) && (spec->differentiator == ZW_DIFF_TUSTIN)) {
        return 2u;
    }
    return 1u;
}

static zw_status check_spec(const zw_loop_spec *spec)
{
    zw_status st;
    if (spec == NULL) {
        return ZW_ERR_NULL;
    }
    if (spec->delay > ZW_LOOP_MAX_DELAY) {
        return ZW_ERR_DELAY;
    }
    if ((spec->differentiator != ZW_DIFF_BACKWARD) && (spec->differentiator != ZW_DIFF_TUSTIN)) {
        return ZW_ERR_FILTER;
    }
    switch (spec->filter) {
    case ZW_VFILTER_NONE:
        st = ZW_OK;
        break;
    case ZW_VFILTER_LOWPASS:
        if (ZW_IS_NAN(spec->filter_pole)) {
            st = ZW_ERR_NAN;
        } else if (!((spec->filter_pole >= ZW_R(0.0)) && (spec->filter_pole < ZW_R(1.0)))) {
            st = ZW_ERR_FILTER;
        } else {
            st = ZW_OK;
        }
        break;
    case ZW_VFILTER_AVERAGE:
        if ((spec->average < 1u) || (spec->average > ZW_LOOP_MAX_AVERAGE)) {
            st = ZW_ERR_FILTER;
        } else {
            st = ZW_OK;
        }
        break;
    default:
        st = ZW_ERR_FILTER;
        break;
    }
    return st;
}

/* An initialized loop: its degree matches its spec (a zeroed or garbage struct fails). */
static zw_status check_loop(const zw_loop *loop)
{
    if (loop == NULL) {
        return ZW_ERR_NULL;
    }
    if (check_spec(&loop->spec) != ZW_OK) {
        return ZW_ERR_ARG;
    }
    /* the degree bound follows from the sum (delay and the estimate's degree were
     * checked); it is tested too so that a sound analyser (Eva, docs/eva.md) sees every
     * row index in range without relating the degree to the spec */
    if ((loop->degree > ZW_LOOP_MAX_DEGREE) ||
        ((loop->plant.order != 2u) && (loop->plant.order != 3u)) ||
        (loop->degree != loop->plant.order + loop->spec.delay + estimate_degree(&loop->spec))) {
        return ZW_ERR_ARG;
    }
    return ZW_OK;
}

/* ---- polynomial construction -------------------------------------------------------------- */

/* Linear factors of the loop, as z polynomials; mapped to s by z = (1 + s)/(1 - s) times
 * (1 - s).  PAD is the constant 1 counted as degree one (it lifts a part of lower degree
 * to the loop's degree: a leading zero in z, a factor 1 - s in s). */
typedef enum factor_kind {
    F_Z,     /* z             s: s + 1 */
    F_ZM1,   /* z - 1         s: 2 s */
    F_ZP1,   /* z + 1         s: 2 */
    F_ZMA,   /* z - a         s: (1 + a) s + (1 - a) */
    F_PAD    /* 1             s: 1 - s */
} factor_kind;

typedef struct build_ctx {
    const zw_plant *plant; /* N and D (z or s images, with bounds: plant.h) */
    zw_real a;             /* filter pole (exact) */
    bool bilinear;         /* build the s polynomial */
} build_ctx;


/* f1 x + f0 for the factor in the context's variable. */
static LOOP_INLINE void factor(const build_ctx *ctx, factor_kind kind, zw_eb *f1, zw_eb *f0)
{
    const bool s = ctx->bilinear;
    zw_real v;
    switch (kind) {
    case F_Z:
        *f1 = zw_eb_exact(ZW_R(1.0));
        *f0 = zw_eb_exact(s ? ZW_R(1.0) : ZW_R(0.0));
        break;
    case F_ZM1:
        *f1 = zw_eb_exact(s ? ZW_R(2.0) : ZW_R(1.0));
        *f0 = zw_eb_exact(s ? ZW_R(0.0) : ZW_R(-1.0));
        break;
    case F_ZP1:
        *f1 = zw_eb_exact(s ? ZW_R(0.0) : ZW_R(1.0));
        *f0 = zw_eb_exact(s ? ZW_R(2.0) : ZW_R(1.0));
        break;
    case F_ZMA:
        if (s) {
            v = ZW_R(1.0) + ctx->a;
            *f1 = zw_eb_make(v, ZW_U * v);
            v = ZW_R(1.0) - ctx->a;
            *f0 = zw_eb_make(v, ZW_U * v);
        } else {
            *f1 = zw_eb_exact(ZW_R(1.0));
            *f0 = zw_eb_exact(-ctx->a);
        }
        break;
    case F_PAD:
    default:
        *f1 = zw_eb_exact(s ? ZW_R(-1.0) : ZW_R(0.0));
        *f0 = zw_eb_exact(ZW_R(1.0));
        break;
    }
}

static void mul_factor(const build_ctx *ctx, zw_real v[], zw_real e[], unsigned *deg,
                       factor_kind kind, unsigned times)
{
    unsigned k;
    zw_eb f1, f0;
    factor(ctx, kind, &f1, &f0);
    for (k = 0u; k < times; ++k) {
        /* never taken: deg + times <= ZW_LOOP_MAX_DEGREE for every spec check_spec accepts;
         * the test states it for a sound analyser (docs/eva.md), which cannot relate the
         * count to the degree */
        if (*deg >= ZW_LOOP_MAX_DEGREE) {
            break;
        }
        zw_eb_poly_mul_linear(v, e, *deg, f1, f0);
        *deg += 1u;
    }
}

/* v (degree deg) *= f (degree fdeg, bounds fe), in place (v must hold deg + fdeg + 1
 * entries): entry k of the product reads v[k - fdeg .. k] only, so k runs downwards. */
static void mul_poly(zw_real v[], zw_real e[], unsigned deg, const zw_real f[], const zw_real fe[],
                     unsigned fdeg)
{
    unsigned k = deg + fdeg + 1u, j;
    while (k > 0u) {
        zw_eb sum = zw_eb_exact(ZW_R(0.0));
        --k;
        for (j = 0u; j <= fdeg; ++j) {
            if ((k >= j) && (k - j <= deg)) {
                sum = zw_eb_add_exactish(sum, zw_eb_mul_exactish(zw_eb_make(f[j], fe[j]),
                                                           zw_eb_make(v[k - j], e[k - j])));
            }
        }
        v[k] = sum.v;
        e[k] = sum.e;
    }
}

static void mul_scalar(zw_real v[], zw_real e[], unsigned deg, zw_eb k)
{
    unsigned i;
    for (i = 0u; i <= deg; ++i) {
        zw_eb r = zw_eb_mul_exactish(k, zw_eb_make(v[i], e[i]));
        v[i] = r.v;
        e[i] = r.e;
    }
}

static void set_one(zw_real v[], zw_real e[], unsigned *deg)
{
    v[0] = ZW_R(1.0);
    e[0] = ZW_R(0.0);
    *deg = 0u;
}

/* z^n - 1 (degree n): in s, (1 + s)^n - (1 - s)^n = 2 sum_{k odd} C(n, k) s^k (exact
 * integers: at most 2 C(16, 8) = 25740). */
static void set_power_minus_one(const build_ctx *ctx, zw_real v[], zw_real e[], unsigned n)
{
    unsigned i;
    zw_real binom = ZW_R(1.0); /* C(n, k), k = n - i */
    for (i = 0u; i <= n; ++i) {
        e[i] = ZW_R(0.0);
        v[i] = ZW_R(0.0);
    }
    if (!ctx->bilinear) {
        v[0] = ZW_R(1.0);
        v[n] = ZW_R(-1.0);
        return;
    }
    for (i = 0u; i <= n; ++i) {
        const unsigned k = n - i; /* power of s at index i */
        if (i > 0u) {
            const unsigned k_above = k + 1u, n_less = n - k;
            binom = binom * (zw_real)k_above / (zw_real)n_less; /* C(n,k) from C(n,k+1) */
        }
        if ((k & 1u) != 0u) {
            v[i] = ZW_R(2.0) * binom;
        }
    }
}

/* Dv (into dv) and Nv (into nv) of the velocity estimate, both of degree m. */
static void velocity_estimate(const build_ctx *ctx, const zw_loop_spec *spec, zw_real dv[],
                              zw_real dv_e[], zw_real nv[], zw_real nv_e[])
{
    const bool tustin = (spec->differentiator == ZW_DIFF_TUSTIN);
    unsigned dd, nd;
    set_one(dv, dv_e, &dd);
    set_one(nv, nv_e, &nd);
    switch (spec->filter) {
    case ZW_VFILTER_AVERAGE: {
        /* backward: (z^n - 1) / (n z^n);  Tustin: 2 (z^n - 1) / (n z^(n-1) (z + 1)) */
        const unsigned n = spec->average;
        set_power_minus_one(ctx, nv, nv_e, n);
        mul_factor(ctx, dv, dv_e, &dd, F_Z, tustin ? (n - 1u) : n);
        if (tustin) {
            mul_factor(ctx, dv, dv_e, &dd, F_ZP1, 1u);
            mul_scalar(nv, nv_e, n, zw_eb_exact(ZW_R(2.0)));
        }
        mul_scalar(dv, dv_e, dd, zw_eb_exact((zw_real)n));
        break;
    }
    case ZW_VFILTER_LOWPASS: {
        /* backward: (1 - a)(z - 1) / (z - a);  Tustin: 2 (1 - a) z (z - 1) / ((z + 1)(z - a)) */
        zw_real one_minus_a = ZW_R(1.0) - ctx->a;
        zw_eb gain = zw_eb_make(one_minus_a, ZW_U * one_minus_a);
        mul_factor(ctx, dv, dv_e, &dd, F_ZMA, 1u);
        mul_factor(ctx, nv, nv_e, &nd, F_ZM1, 1u);
        if (tustin) {
            mul_factor(ctx, dv, dv_e, &dd, F_ZP1, 1u);
            mul_factor(ctx, nv, nv_e, &nd, F_Z, 1u);
            gain.v = ZW_R(2.0) * gain.v; /* exact */
            gain.e = ZW_R(2.0) * gain.e;
        }
        mul_scalar(nv, nv_e, nd, gain);
        break;
    }
    case ZW_VFILTER_NONE:
    default:
        /* backward: (z - 1) / z;  Tustin: 2 (z - 1) / (z + 1) */
        mul_factor(ctx, dv, dv_e, &dd, tustin ? F_ZP1 : F_Z, 1u);
        mul_factor(ctx, nv, nv_e, &nd, F_ZM1, 1u);
        if (tustin) {
            mul_scalar(nv, nv_e, nd, zw_eb_exact(ZW_R(2.0)));
        }
        break;
    }
}

/* D = z^d Dp Dv,  Na = Np Dv,  Nb = Np Nv (the plant Np / Dp of order q), the last two
 * lifted to degree n, in the context's variable. */
static void build_parts(const build_ctx *ctx, const zw_loop_spec *spec, unsigned n, zw_real D[],
                        zw_real De[], zw_real Na[], zw_real Nae[], zw_real Nb[], zw_real Nbe[])
{
    const zw_plant *pl = ctx->plant;
    const unsigned m = estimate_degree(spec), q = pl->order;
    unsigned i, dd = m, da, db;
    velocity_estimate(ctx, spec, Na, Nae, Nb, Nbe);
    for (i = 0u; i <= m; ++i) {
        D[i] = Na[i];
        De[i] = Nae[i];
    }
    mul_poly(D, De, dd, ctx->bilinear ? pl->den_s : pl->den, ctx->bilinear ? pl->den_s_err : pl->den_err, q);
    dd += q;
    mul_factor(ctx, D, De, &dd, F_Z, spec->delay);
    da = m + q - 1u;
    db = da;
    mul_poly(Na, Nae, m, ctx->bilinear ? pl->num_s : pl->num, ctx->bilinear ? pl->num_s_err : pl->num_err, q - 1u);
    mul_poly(Nb, Nbe, m, ctx->bilinear ? pl->num_s : pl->num, ctx->bilinear ? pl->num_s_err : pl->num_err, q - 1u);
    mul_factor(ctx, Na, Nae, &da, F_PAD, n - da);
    mul_factor(ctx, Nb, Nbe, &db, F_PAD, n - db);
}

static bool all_finite(const zw_real v[], const zw_real e[], unsigned n)
{
    unsigned i;
    for (i = 0u; i <= n; ++i) {
        if (!ZW_IS_FINITE(v[i]) || !ZW_IS_FINITE(e[i])) {
            return false;
        }
    }
    return true;
}

static const zw_loop k_empty_loop; /* zero: degree 0, refused by check_loop */

/* A plant the loop can be built on: order 2 or 3, every coefficient and bound finite. */
static zw_status check_plant(const zw_plant *pl)
{
    unsigned i;
    if ((pl->order != 2u) && (pl->order != 3u)) {
        return ZW_ERR_ARG;
    }
    for (i = 0u; i <= pl->order; ++i) {
        const zw_real v[4] = {pl->den[i], pl->den_err[i], pl->den_s[i], pl->den_s_err[i]};
        unsigned k;
        for (k = 0u; k < 4u; ++k) {
            if (ZW_IS_NAN(v[k])) {
                return ZW_ERR_NAN;
            }
            if (!ZW_IS_FINITE(v[k])) {
                return ZW_ERR_INF;
            }
        }
        if (i < pl->order) {
            const zw_real w[4] = {pl->num[i], pl->num_err[i], pl->num_s[i], pl->num_s_err[i]};
            for (k = 0u; k < 4u; ++k) {
                if (ZW_IS_NAN(w[k])) {
                    return ZW_ERR_NAN;
                }
                if (!ZW_IS_FINITE(w[k])) {
                    return ZW_ERR_INF;
                }
            }
        }
    }
    return ZW_OK;
}

/* The parts of spec on out->plant (already in place; out otherwise empty). */
static zw_status loop_build(zw_loop *out, const zw_loop_spec *spec)
{
    zw_status st;
    build_ctx ctx;
    unsigned n;
    st = check_plant(&out->plant);
    if (st != ZW_OK) {
        return st;
    }
    st = check_spec(spec);
    if (st != ZW_OK) {
        return st;
    }
    n = out->plant.order + spec->delay + estimate_degree(spec);
    ctx.plant = &out->plant;
    ctx.a = (spec->filter == ZW_VFILTER_LOWPASS) ? spec->filter_pole : ZW_R(0.0);
    ctx.bilinear = false;
    build_parts(&ctx, spec, n, out->D, out->D_err, out->Na, out->Na_err, out->Nb, out->Nb_err);
    ctx.bilinear = true;
    build_parts(&ctx, spec, n, out->Ds, out->Ds_err, out->Nas, out->Nas_err, out->Nbs,
                out->Nbs_err);
    if (!all_finite(out->D, out->D_err, n) || !all_finite(out->Na, out->Na_err, n) ||
        !all_finite(out->Nb, out->Nb_err, n) || !all_finite(out->Ds, out->Ds_err, n) ||
        !all_finite(out->Nas, out->Nas_err, n) || !all_finite(out->Nbs, out->Nbs_err, n)) {
        return ZW_ERR_RANGE;
    }
    out->c = out->plant.c;
    out->spec = *spec;
    if (spec->filter != ZW_VFILTER_LOWPASS) {
        out->spec.filter_pole = ZW_R(0.0);
    }
    if (spec->filter != ZW_VFILTER_AVERAGE) {
        out->spec.average = 0u;
    }
    out->degree = n;
    return ZW_OK;
}

zw_status zw_loop_init(zw_loop *out, const zw_coeffs *c, const zw_loop_spec *spec)
{
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    *out = k_empty_loop;
    if (spec == NULL) {
        return ZW_ERR_NULL;
    }
    /* built in place (a zw_plant is too large for a firmware caller's stack) */
    st = zw_plant_from_coeffs(&out->plant, c);
    if (st == ZW_OK) {
        st = loop_build(out, spec);
    }
    if (st != ZW_OK) {
        *out = k_empty_loop;
    }
    return st;
}

zw_status zw_loop_init_plant(zw_loop *out, const zw_plant *plant, const zw_loop_spec *spec)
{
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    if ((plant == NULL) || (spec == NULL)) {
        *out = k_empty_loop;
        return ZW_ERR_NULL;
    }
    if (plant != &out->plant) {
        *out = k_empty_loop;
        out->plant = *plant;
    } else {
        /* rebuilt on its own plant: every other field is written by loop_build but these */
        out->degree = 0u;
        out->alpha_relerr = ZW_R(0.0);
        out->beta_relerr = ZW_R(0.0);
    }
    st = loop_build(out, spec);
    if (st != ZW_OK) {
        *out = k_empty_loop;
    }
    return st;
}

/* bound + |v| rel, rounded up: (1 + 4u) covers the three roundings of the expression */
static zw_real widened(zw_real bound, zw_real v, zw_real rel)
{
    return (bound + ZW_FABS(v) * rel) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
}

/* Are the gain parts' bounds all finite (after widening)? */
static bool gain_bounds_finite(const zw_loop *loop)
{
    unsigned i;
    for (i = 0u; i <= loop->degree; ++i) {
        if (!ZW_IS_FINITE(loop->Na_err[i]) || !ZW_IS_FINITE(loop->Nas_err[i]) ||
            !ZW_IS_FINITE(loop->Nb_err[i]) || !ZW_IS_FINITE(loop->Nbs_err[i])) {
            return false;
        }
    }
    return true;
}

zw_status zw_loop_carry_gain_rounding(zw_loop *loop, zw_real alpha_relerr, zw_real beta_relerr)
{
    const zw_real cap = ZW_R(0.0625);
    zw_status st = check_loop(loop);
    unsigned i;
    if ((st == ZW_OK) && !((alpha_relerr >= ZW_R(0.0)) && (alpha_relerr < cap) &&
                           (beta_relerr >= ZW_R(0.0)) && (beta_relerr < cap))) {
        st = ZW_ERR_ARG;
    }
    if (st != ZW_OK) {
        if (loop != NULL) {
            *loop = k_empty_loop;
        }
        return st;
    }
    for (i = 0u; i <= loop->degree; ++i) {
        loop->Na_err[i] = widened(loop->Na_err[i], loop->Na[i], alpha_relerr);
        loop->Nas_err[i] = widened(loop->Nas_err[i], loop->Nas[i], alpha_relerr);
        loop->Nb_err[i] = widened(loop->Nb_err[i], loop->Nb[i], beta_relerr);
        loop->Nbs_err[i] = widened(loop->Nbs_err[i], loop->Nbs[i], beta_relerr);
    }
    /* eval_p multiplies |gain| by it once more: (1 + 4u) rounds that product up too */
    loop->alpha_relerr = (loop->alpha_relerr + alpha_relerr) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
    loop->beta_relerr = (loop->beta_relerr + beta_relerr) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
    if (!gain_bounds_finite(loop)) {
        *loop = k_empty_loop;
        return ZW_ERR_RANGE;
    }
    return ZW_OK;
}

static zw_status check_gains(const zw_loop *loop, zw_real alpha, zw_real beta)
{
    zw_status st;
    st = check_loop(loop);
    if (st != ZW_OK) {
        return st;
    }
    /* one comparison for the common case (false for NaN and infinities), then which error */
    if ((ZW_FABS(alpha) <= ZW_REAL_MAX) && (ZW_FABS(beta) <= ZW_REAL_MAX)) {
        return ZW_OK;
    }
    st = zw_require_finite(alpha);
    if (st != ZW_OK) {
        return st;
    }
    return zw_require_finite(beta);
}

/* Every coefficient of a zw_loop_poly output 0 (its fail-safe value). */
static void zero_poly(zw_real p[])
{
    unsigned i;
    for (i = 0u; i < LOOP_N; ++i) {
        p[i] = ZW_R(0.0);
    }
}

zw_status zw_loop_poly(const zw_loop *loop, zw_real alpha, zw_real beta,
                       zw_real p[ZW_LOOP_MAX_DEGREE + 1u], unsigned *degree)
{
    zw_status st;
    unsigned i;
    if ((p == NULL) || (degree == NULL)) {
        if (degree != NULL) {
            *degree = 0u;
        }
        if (p != NULL) {
            zero_poly(p);
        }
        return ZW_ERR_NULL;
    }
    zero_poly(p);
    *degree = 0u;
    st = check_gains(loop, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    for (i = 0u; i <= loop->degree; ++i) {
        p[i] = (loop->D[i] + alpha * loop->Na[i]) + beta * loop->Nb[i];
        if (!ZW_IS_FINITE(p[i])) {
            zero_poly(p);
            return ZW_ERR_RANGE;
        }
    }
    *degree = loop->degree;
    return ZW_OK;
}

/* ---- coefficients with error bounds ----------------------------------------------------- */

/* The working rows of the tests live in the caller's zw_loop_workspace (loop.h), with
 * their error bounds in zw_real. */
typedef zw_real loop_err;

static LOOP_HOT zw_eb eb_stored(zw_real v, loop_err e)
{
    return zw_eb_make(v, e);
}

/* Coefficient i of d + alpha na + beta nb (parts with error bounds de, nae, nbe), with a
 * bound on its error.  First branch-free: the bounds of zw_eb_mul / zw_eb_add written out
 * (a rounding u|result| per operation, the underflow quantum per operation).  Where that
 * leaves the sign in doubt, again through the exact-where-possible operations, whose bound
 * is zero for exact parts and gains (the z = +-1 coefficients at a gain's exact zero, tiny
 * gains).  Both bounds are rigorous; the first only skips branches on the common path. */
static LOOP_HOT zw_eb combine(const zw_real d[], const zw_real de[], const zw_real na[],
                              const zw_real nae[], const zw_real nb[], const zw_real nbe[],
                              unsigned i, zw_real alpha, zw_real beta)
{
    const zw_real pa = alpha * na[i], pb = beta * nb[i], t = d[i] + pa, w = t + pb;
    const zw_real err = ((de[i] + ZW_FABS(alpha) * nae[i]) + ZW_FABS(beta) * nbe[i]) +
                        ZW_U * (((ZW_FABS(pa) + ZW_FABS(pb)) + ZW_FABS(t)) + ZW_FABS(w)) +
                        ZW_R(4.0) * ZW_ETA;
    if (ZW_FABS(w) > ZW_R(2.0) * err) {
        return zw_eb_make(w, err);
    }
    {
        zw_eb v = zw_eb_add_exactish(zw_eb_make(d[i], de[i]),
                                  zw_eb_mul_exactish(zw_eb_exact(alpha), zw_eb_make(na[i], nae[i])));
        return zw_eb_add_exactish(v, zw_eb_mul_exactish(zw_eb_exact(beta), zw_eb_make(nb[i], nbe[i])));
    }
}

/* Coefficient i of the bilinear P = Ds + alpha Nas + beta Nbs, and of p = D + alpha Na +
 * beta Nb. */
static LOOP_HOT zw_eb bilinear_coef(const zw_loop *loop, unsigned i, zw_real alpha, zw_real beta)
{
    return combine(loop->Ds, loop->Ds_err, loop->Nas, loop->Nas_err, loop->Nbs, loop->Nbs_err, i,
                   alpha, beta);
}

static LOOP_HOT zw_eb z_coef(const zw_loop *loop, unsigned i, zw_real alpha, zw_real beta)
{
    return combine(loop->D, loop->D_err, loop->Na, loop->Na_err, loop->Nb, loop->Nb_err, i, alpha,
                   beta);
}

/* ---- guarded Hurwitz test (Routh) ---------------------------------------------------------- */

typedef enum routh_result { ROUTH_STABLE, ROUTH_UNSURE, ROUTH_UNSTABLE } routh_result;

/* A row is rescaled (by a power of two: exact but for underflow) only when its largest
 * entry leaves [2^-16, 2^16]: products of two entries then stay far from overflow and
 * underflow in float too, and the libm calls are skipped for most rows.  A positive
 * factor on a row does not change the signs the tests read. */
#define LOOP_SCALE_LO ZW_R(1.52587890625e-05)
#define LOOP_SCALE_HI ZW_R(65536.0)

/* The exponent e of a finite big > 0 = f 2^e, f in [1/2, 1): within [-(ZW_REAL_MAX_EXP + 64),
 * ZW_REAL_MAX_EXP] (subnormals included); clamped to that range all the same, so that -e
 * cannot overflow whatever a frexp returned (no change for any finite big > 0). */
static int scale_exponent(zw_real big)
{
    int ex = 0;
    (void)ZW_FREXP(big, &ex);
    if (ex > ZW_REAL_MAX_EXP) {
        ex = ZW_REAL_MAX_EXP;
    }
    if (ex < -(ZW_REAL_MAX_EXP + 64)) {
        ex = -(ZW_REAL_MAX_EXP + 64);
    }
    return ex;
}

/* zw_compare(0, v, err) as a verdict on v's sign.  Written out for speed, without its test
 * of the bound for infinity: every bound in this file is a sum of non-negative terms (or
 * NaN / +inf after an overflow), and a comparison with a NaN or infinite bound is false,
 * so such a bound still gives UNSURE. */
static LOOP_HOT routh_result sign_result(zw_real v, zw_real err)
{
    const zw_real bound = zw_compare_bound(v, err);
    if (v > bound) {
        return ROUTH_STABLE;
    }
    if (v < -bound) {
        return ROUTH_UNSTABLE;
    }
    return ROUTH_UNSURE;
}

static routh_result routh_rows(zw_real w[], loop_err we[], unsigned n);

/* The signs of the coefficients (res: their combined verdict), then the rows. */
static routh_result routh_after_signs(zw_real w[], loop_err we[], unsigned n, routh_result res)
{
    return (res != ROUTH_STABLE) ? res : routh_rows(w, we, n);
}

/* Combined verdict of one more coefficient's sign: UNSTABLE wins, then UNSURE. */
static LOOP_HOT routh_result sign_and(routh_result acc, routh_result r)
{
    if ((acc == ROUTH_UNSTABLE) || (r == ROUTH_UNSTABLE)) {
        return ROUTH_UNSTABLE;
    }
    return ((acc == ROUTH_UNSURE) || (r == ROUTH_UNSURE)) ? ROUTH_UNSURE : ROUTH_STABLE;
}

/* Is P(s) = w[0] s^n + ... + w[n] (errors we[]) surely Hurwitz?  Every coefficient must be
 * surely positive (necessary), then the first column of the division-free Routh array:
 *   row k, entry j = B0 A[j+1] - A0 B[j+1]  (A = row k-2, B = row k-1),
 * which has the sign of the classical entry when B0 > 0 (checked first).  Rows are
 * rescaled by powers of two (exact) against overflow (LOOP_SCALE_LO/HI).  The last row is
 * the constant coefficient times positive factors and is not recomputed.  Row k lives in
 * the slots (k mod 2) + 2 j of w, overwriting row k - 2 (whose entry j + 1 is read before
 * entry j is written).  UNSTABLE is certain: the first entry that is not surely positive
 * is surely non-positive while all before it are surely positive. */
static routh_result routh(zw_real w[], loop_err we[], unsigned n)
{
    unsigned i;
    routh_result res = ROUTH_STABLE;
    for (i = 0u; i <= n; ++i) {
        routh_result r = sign_result(w[i], (zw_real)we[i]);
        if (r == ROUTH_UNSTABLE) {
            return r;
        }
        if (r == ROUTH_UNSURE) {
            res = r;
        }
    }
    return routh_after_signs(w, we, n, res);
}

/* The rows of the array (every coefficient already surely positive). */
static routh_result routh_rows(zw_real w[], loop_err we[], unsigned n)
{
    unsigned k;
    routh_result res;
    for (k = 2u; k < n; ++k) {
        const unsigned off = k & 1u, len = (n - k) / 2u + 1u;
        const unsigned len_a = (n - k + 2u) / 2u + 1u, len_b = (n - k + 1u) / 2u + 1u;
        const zw_eb a0 = eb_stored(w[off], we[off]);
        const zw_eb b0 = eb_stored(w[1u - off], we[1u - off]);
        zw_real big = ZW_R(0.0);
        int ex = 0;
        unsigned j;
        for (j = 0u; j < len; ++j) {
            const unsigned ia = off + 2u * (j + 1u), ib = (1u - off) + 2u * (j + 1u);
            zw_eb a1 = (j + 1u < len_a) ? eb_stored(w[ia], we[ia]) : zw_eb_exact(ZW_R(0.0));
            zw_eb b1 = (j + 1u < len_b) ? eb_stored(w[ib], we[ib]) : zw_eb_exact(ZW_R(0.0));
            zw_eb c = zw_eb_sub(zw_eb_mul(b0, a1), zw_eb_mul(a0, b1));
            w[off + 2u * j] = c.v;
            we[off + 2u * j] = c.e;
            if (ZW_FABS(c.v) > big) {
                big = ZW_FABS(c.v);
            }
        }
        if (!ZW_IS_FINITE(big)) {
            return ROUTH_UNSURE;
        }
        if ((big > ZW_R(0.0)) && ((big < LOOP_SCALE_LO) || (big > LOOP_SCALE_HI))) {
            ex = scale_exponent(big);
            for (j = 0u; j < len; ++j) {
                w[off + 2u * j] = ZW_LDEXP(w[off + 2u * j], -ex);
                we[off + 2u * j] = ZW_LDEXP(we[off + 2u * j], -ex) + ZW_ETA;
            }
        }
        res = sign_result(w[off], (zw_real)we[off]);
        if (res != ROUTH_STABLE) {
            return res;
        }
    }
    return ROUTH_STABLE;
}

zw_hurwitz zw_routh_hurwitz(zw_real w[], zw_real we[], unsigned n)
{
    zw_hurwitz verdict;
    switch (routh(w, we, n)) {
    case ROUTH_STABLE:
        verdict = ZW_HURWITZ_STABLE;
        break;
    case ROUTH_UNSTABLE:
        verdict = ZW_HURWITZ_UNSTABLE;
        break;
    case ROUTH_UNSURE:
    default:
        verdict = ZW_HURWITZ_UNSURE;
        break;
    }
    return verdict;
}

/* P = Ds + alpha Nas + beta Nbs with bounds, then Routh.  *lead / *trail: the results of
 * the leading (z = -1) and constant (z = 1) coefficients alone. */
ZW_NOINLINE static routh_result check_bilinear(const zw_loop *loop, zw_loop_workspace *ws,
                                               zw_real alpha, zw_real beta, routh_result *lead,
                                               routh_result *trail)
{
    zw_real *w = ws->row, *we = ws->row_err;
    const unsigned n = loop->degree;
    unsigned i;
    routh_result signs = ROUTH_STABLE;
    /* the coefficients and their signs in one pass (routh's first step) */
    for (i = 0u; i <= n; ++i) {
        const zw_eb v = bilinear_coef(loop, i, alpha, beta);
        const routh_result r = sign_result(v.v, v.e);
        w[i] = v.v;
        we[i] = v.e;
        if (i == 0u) {
            *lead = r;
        }
        if (i == n) {
            *trail = r;
        }
        signs = sign_and(signs, r);
    }
    return routh_after_signs(w, we, n, signs);
}

/* ---- guarded Schur-Cohn test on the z coefficients ------------------------------------------ */

/* Is p(z) = w[0] z^m + ... + w[m] surely Schur stable?  The Schur-Cohn (Levinson) step: with
 * k = w[m] / w[0] (the constant over the leading coefficient),
 *     p is Schur stable  <=>  |k| < 1  and  (p(z) - k p*(z)) / z  is Schur stable,
 * p*(z) = z^m p(1/z) the reversed polynomial; the reduced polynomial, highest power first,
 * is w[t] - k w[m - t], t = 0..m-1 (its leading coefficient w[0] (1 - k^2) keeps the degree).
 * Every step is carried with running error bounds (zw_eb) from the coefficients' own bounds,
 * so by induction each level's exact coefficients (those of the exact p) lie within the
 * stored bounds: STABLE when every |k| is surely below 1 (then the exact p is Schur stable
 * by the equivalence above), UNSTABLE when one |k| is surely above 1 while all before were
 * surely below (the exact p is then not stable), else UNSURE.
 * Why a second test: the Routh array on the bilinear parts loses its bound on the cluster
 * of roots near z = 0 that a delay line and a moving average put there (its rows cancel,
 * and the running bound, which takes the rows' correlated errors as independent, grows
 * ~7x per row at degree 26 while the true error grows ~1.5x).  Here those roots give small
 * reflection coefficients k, each step is w[t] - k w[m - t] with |k| << 1, and the bound
 * grows slowly; it widens only as |k| -> 1 (roots near the circle), where the Routh test
 * does well.  Costs n^2 / 2 multiply-adds; one array, reduced in place. */
/* x - k y with its bound: zw_eb_sub(x, zw_eb_mul(k, y)) written out, with |k| + e_k and
 * e_k hoisted out of the row (ak_ke, ke): e_x + (|k| + e_k) e_y + |y| e_k + u (|k y| + |r|)
 * plus the two underflow quanta. */
static LOOP_HOT zw_real sc_step(zw_real x, zw_real xe, zw_real y, zw_real ye, zw_real k,
                                zw_real ak_ke, zw_real ke, zw_real *err)
{
    const zw_real ky = k * y, r = x - ky;
    *err = ((xe + ak_ke * ye) + ZW_FABS(y) * ke) + ZW_U * (ZW_FABS(ky) + ZW_FABS(r)) +
           ZW_R(2.0) * ZW_ETA;
    return r;
}

ZW_NOINLINE static routh_result schur_cohn(const zw_loop *loop, zw_loop_workspace *ws,
                                           zw_real alpha, zw_real beta)
{
    zw_real *w = ws->row, *we = ws->row_err;
    unsigned m = loop->degree, t;
    for (t = 0u; t <= m; ++t) {
        const zw_eb v = z_coef(loop, t, alpha, beta);
        w[t] = v.v;
        we[t] = v.e;
    }
    for (; m > 0u; --m) {
        const zw_eb lead = eb_stored(w[0], we[0]), con = eb_stored(w[m], we[m]);
        /* |exact con| < |exact lead| surely: upper bound of one below lower bound of the
         * other, each rounded outward (a sum of two terms: within 2 u, covered by 4 u) */
        const zw_real con_hi = (ZW_FABS(con.v) + con.e) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
        const zw_real lead_lo = (ZW_FABS(lead.v) - lead.e) * (ZW_R(1.0) - ZW_R(4.0) * ZW_U);
        zw_eb k;
        zw_real big = ZW_R(0.0);
        int ex = 0;
        if (!ZW_IS_FINITE(con_hi) || !ZW_IS_FINITE(lead_lo)) {
            return ROUTH_UNSURE;
        }
        if (!(con_hi < lead_lo)) {
            const zw_real con_lo = (ZW_FABS(con.v) - con.e) * (ZW_R(1.0) - ZW_R(4.0) * ZW_U);
            const zw_real lead_hi = (ZW_FABS(lead.v) + lead.e) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
            return (con_lo > lead_hi) ? ROUTH_UNSTABLE : ROUTH_UNSURE;
        }
        k = zw_eb_div(con, lead);
        /* the pairs (t, m - t) at once: each new entry reads both old ones; big: the largest
         * new entry (0..m-1).  Entry m is dropped (the degree falls by one), so t = 0 updates
         * w[0] alone, and so does t = m / 2 for even m. */
        {
            const zw_real ak = ZW_FABS(k.v), ke = k.e, ak_ke = ak + ke;
            const unsigned half = m / 2u;
            w[0] = sc_step(w[0], we[0], w[m], we[m], k.v, ak_ke, ke, &we[0]);
            big = ZW_FABS(w[0]);
            for (t = 1u; (t < m) && (2u * t < m); ++t) { /* t < m: implied, for Eva */
                const unsigned t2 = m - t;
                const zw_real x = w[t], xe = we[t], y = w[t2], ye = we[t2];
                w[t] = sc_step(x, xe, y, ye, k.v, ak_ke, ke, &we[t]);
                w[t2] = sc_step(y, ye, x, xe, k.v, ak_ke, ke, &we[t2]);
                if (ZW_FABS(w[t]) > big) {
                    big = ZW_FABS(w[t]);
                }
                if (ZW_FABS(w[t2]) > big) {
                    big = ZW_FABS(w[t2]);
                }
            }
            if ((half > 0u) && (2u * half == m)) {
                w[half] = sc_step(w[half], we[half], w[half], we[half], k.v, ak_ke, ke, &we[half]);
                if (ZW_FABS(w[half]) > big) {
                    big = ZW_FABS(w[half]);
                }
            }
        }
        /* rescale by a power of two (exact but for underflow: ETA) against overflow */
        if (!ZW_IS_FINITE(big)) {
            return ROUTH_UNSURE;
        }
        if ((big > ZW_R(0.0)) && ((big < LOOP_SCALE_LO) || (big > LOOP_SCALE_HI))) {
            ex = scale_exponent(big);
            for (t = 0u; t < m; ++t) {
                w[t] = ZW_LDEXP(w[t], -ex);
                we[t] = ZW_LDEXP(we[t], -ex) + ZW_ETA;
            }
        }
    }
    return ROUTH_STABLE;
}

/* The sign of coefficient i of P = Ds + alpha Nas + beta Nbs (as check_bilinear's *lead for
 * i = 0, *trail for i = n). */
static void bilinear_end(const zw_loop *loop, zw_real alpha, zw_real beta, unsigned i,
                         routh_result *out)
{
    const zw_eb v = bilinear_coef(loop, i, alpha, beta);
    *out = sign_result(v.v, v.e);
}

/* From this degree on (long delays and moving averages) the Schur-Cohn test goes first:
 * there the Routh bound rarely settles a point, and paying for its rows first doubles the
 * cost (callgrind, bench/loop: about even at degree 13 to 18, 2x at 26).  Only the order
 * of two rigorous tests: no verdict depends on it. */
#define LOOP_SCHUR_FIRST 13u

/* The guarded verdict without roots: the Routh test on the bilinear parts and the
 * Schur-Cohn test on the z coefficients, the second only where the first cannot tell
 * (either proves stability alone; UNSTABLE from either is certain).  *lead, *trail as
 * check_bilinear. */
static routh_result decide(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                           routh_result *lead, routh_result *trail)
{
    routh_result res;
    if (loop->degree >= LOOP_SCHUR_FIRST) {
        const unsigned n = loop->degree;
        bilinear_end(loop, alpha, beta, 0u, lead);
        bilinear_end(loop, alpha, beta, n, trail);
        res = schur_cohn(loop, ws, alpha, beta);
        return (res == ROUTH_UNSURE) ? check_bilinear(loop, ws, alpha, beta, lead, trail) : res;
    }
    res = check_bilinear(loop, ws, alpha, beta, lead, trail);
    if (res == ROUTH_UNSURE) {
        res = schur_cohn(loop, ws, alpha, beta);
    }
    return res;
}

/* ---- roots (informational) ------------------------------------------------------------------ */

typedef zw_loop_complex cplx;

static cplx c_make(zw_real re, zw_real im)
{
    cplx r;
    r.re = re;
    r.im = im;
    return r;
}
static cplx c_add(cplx a, cplx b) { return c_make(a.re + b.re, a.im + b.im); }
static cplx c_sub(cplx a, cplx b) { return c_make(a.re - b.re, a.im - b.im); }
static cplx c_mul(cplx a, cplx b)
{
    return c_make(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re);
}
/* Smith's division; b = 0 gives an infinite quotient. */
static LOOP_INLINE cplx c_div_inline(cplx a, cplx b)
{
    zw_real t, den;
    if (ZW_FABS(b.re) >= ZW_FABS(b.im)) {
        if (b.re == ZW_R(0.0)) {
            return c_make(ZW_REAL_MAX * ZW_R(2.0), ZW_R(0.0));
        }
        t = b.im / b.re;
        den = b.re + b.im * t;
        return c_make((a.re + a.im * t) / den, (a.im - a.re * t) / den);
    }
    t = b.re / b.im;
    den = b.re * t + b.im;
    return c_make((a.re * t + a.im) / den, (a.im * t - a.re) / den);
}

static cplx c_div(cplx a, cplx b)
{
    return c_div_inline(a, b);
}
static LOOP_INLINE zw_real c_abs_inline(cplx a)
{
    zw_real x = ZW_FABS(a.re), y = ZW_FABS(a.im), big = (x > y) ? x : y, small = (x > y) ? y : x;
    if (big == ZW_R(0.0)) {
        return ZW_R(0.0);
    }
    small /= big;
    return big * ZW_SQRT(ZW_R(1.0) + small * small);
}

static zw_real c_abs(cplx a)
{
    return c_abs_inline(a);
}

static zw_real poly_coef(const zw_loop *loop, zw_real alpha, zw_real beta, unsigned i)
{
    return (loop->D[i] + alpha * loop->Na[i]) + beta * loop->Nb[i];
}

/* A complex value with a bound on its absolute error. */
typedef zw_loop_ceb ceb;

static ceb ceb_make(cplx v, zw_real e)
{
    ceb r;
    r.v = v;
    r.e = e;
    return r;
}

/* acc *= f (f with absolute error fe); |fl(a b) - a b| <= sqrt(2) gamma_2 |a||b| < 5 u |a||b|
 * for complex products.  In place, through pointers: small frames on an MCU. */
static LOOP_INLINE void ceb_times(ceb *acc, cplx f, zw_real fe)
{
    const zw_real aa = c_abs_inline(acc->v), af = c_abs_inline(f);
    acc->e = aa * fe + af * acc->e + acc->e * fe + ZW_R(5.0) * ZW_U * aa * af + ZW_R(2.0) * ZW_ETA;
    acc->v = c_mul(acc->v, f);
}

/* acc *= the loop's linear factor of that kind at z (its z coefficients carry bounds). */
static void ceb_times_factor(ceb *acc, const zw_loop *loop, factor_kind kind, cplx z)
{
    build_ctx ctx;
    zw_eb f1, f0;
    const zw_real az = c_abs_inline(z);
    ctx.plant = &loop->plant;
    ctx.a = loop->spec.filter_pole;
    ctx.bilinear = false;
    factor(&ctx, kind, &f1, &f0);
    ceb_times(acc, c_make(f1.v * z.re + f0.v, f1.v * z.im),
              f1.e * az + f0.e + ZW_R(4.0) * ZW_U * (ZW_FABS(f1.v) * az + ZW_FABS(f0.v)) + ZW_R(2.0) * ZW_ETA);
}

static void ceb_times_real(ceb *acc, zw_real k, zw_real ke)
{
    ceb_times(acc, c_make(k, ZW_R(0.0)), ke);
}

static void ceb_times_power(ceb *acc, cplx z, unsigned k)
{
    unsigned i;
    for (i = 0u; i < k; ++i) {
        ceb_times(acc, z, ZW_R(0.0));
    }
}

/* acc = x + y */
static void ceb_add_into(ceb *x, const ceb *y)
{
    x->v = c_add(x->v, y->v);
    x->e = x->e + y->e + ZW_R(2.0) * ZW_U * c_abs(x->v) + ZW_R(2.0) * ZW_ETA;
}

/* The plant's N and D at z into ws->plant_at (zw_plant_eval: its factored form, with its
 * bounds) for the next eval_p at z.  A sibling call of eval_p, not under it: the root test's
 * deepest chain stays as it was (the stack target, tools/footprint.sh).  A failed evaluation
 * (never, for a loop check_loop accepted) leaves NaN, whose radius the root test refuses. */
ZW_NOINLINE static void plant_at(const zw_loop *loop, zw_loop_workspace *ws, cplx z)
{
    zw_real *v = ws->plant_at;
    ws->plant_loop = loop;
    if (zw_plant_eval(&loop->plant, z.re, z.im, &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]) != ZW_OK) {
        v[0] = ZW_NAN; /* the others are NaN already (zw_plant_eval's fail-safe) */
    }
}

/* acc *= N (num) or D at z, as plant_at left them. */
static void ceb_times_plant(ceb *acc, const zw_loop_workspace *ws, bool num)
{
    const zw_real *v = ws->plant_at;
    unsigned k = 3u; /* D's value, error bound: v[3..5]; N's: v[0..2] */
    if (num) {
        k = 0u;
    }
    ceb_times(acc, c_make(v[k], v[k + 1u]), v[k + 2u]);
}

/* p(z) = z^d D Dv + N (alpha Dv + beta Nv) from the factors (loop.h), with a bound on its
 * error: far tighter than the expanded coefficients near z = 1 and where the expansion
 * cancels.  The loop and its plant's N(z), D(z): ws->plant_loop and ws->plant_at, from
 * plant_at(loop, ws, z) just before (the loop through ws: one argument less, a smaller
 * frame on the root test's deepest chain). */
static ceb eval_p(zw_loop_workspace *ws, zw_real alpha, zw_real beta, cplx z)
{
    const zw_loop *loop = ws->plant_loop;
    const zw_loop_spec *spec = &loop->spec;
    const bool tustin = (spec->differentiator == ZW_DIFF_TUSTIN);
    /* the three running products in the workspace, not in this frame (the root test's
     * deepest chain runs through it: the stack target of tools/footprint.sh) */
    ceb *const dv = &ws->eval[0], *const nv = &ws->eval[1], *const d = &ws->eval[2];
    *dv = ceb_make(c_make(ZW_R(1.0), ZW_R(0.0)), ZW_R(0.0));
    *nv = *dv;
    switch (spec->filter) {
    case ZW_VFILTER_AVERAGE: /* (z^n - 1) / (n z^n);  2 (z^n - 1) / (n z^(n-1) (z + 1)) */
        ceb_times_power(dv, z, tustin ? (spec->average - 1u) : spec->average);
        ceb_times_real(dv, (zw_real)spec->average, ZW_R(0.0));
        if (tustin) {
            ceb_times_factor(dv, loop, F_ZP1, z);
        }
        ceb_times_power(nv, z, spec->average);
        nv->v.re -= ZW_R(1.0);
        nv->e += ZW_R(2.0) * ZW_U * c_abs(nv->v) + ZW_ETA;
        if (tustin) {
            ceb_times_real(nv, ZW_R(2.0), ZW_R(0.0));
        }
        break;
    case ZW_VFILTER_LOWPASS: /* (1 - a)(z - 1) / (z - a);  2 (1 - a) z (z - 1) / ((z + 1)(z - a)) */
        ceb_times_factor(dv, loop, F_ZMA, z);
        ceb_times_factor(nv, loop, F_ZM1, z);
        if (tustin) {
            ceb_times_factor(dv, loop, F_ZP1, z);
            ceb_times_power(nv, z, 1u);
        }
        ceb_times_real(nv, (tustin ? ZW_R(2.0) : ZW_R(1.0)) * (ZW_R(1.0) - spec->filter_pole),
                       ZW_R(2.0) * ZW_U * (ZW_R(1.0) - spec->filter_pole));
        break;
    case ZW_VFILTER_NONE:
    default: /* (z - 1) / z;  2 (z - 1) / (z + 1) */
        if (tustin) {
            ceb_times_factor(dv, loop, F_ZP1, z);
        } else {
            ceb_times_power(dv, z, 1u);
        }
        ceb_times_factor(nv, loop, F_ZM1, z);
        if (tustin) {
            ceb_times_real(nv, ZW_R(2.0), ZW_R(0.0));
        }
        break;
    }
    *d = *dv; /* z^d D Dv (z^d last: ws and the gains are no longer live across its call) */
    ceb_times_plant(d, ws, false);
    /* N (alpha Dv + beta Nv), the gains with their carried error (0 by default) */
    ceb_times_real(dv, alpha, ZW_FABS(alpha) * loop->alpha_relerr);
    ceb_times_real(nv, beta, ZW_FABS(beta) * loop->beta_relerr);
    ceb_add_into(nv, dv);
    ceb_times_plant(nv, ws, true);
    ceb_times_power(d, z, spec->delay);
    ceb_add_into(d, nv);
    return *d;
}

/* Newton correction p(z) / p'(z) of the degree-m polynomial p[0..m] (coefficients read
 * through poly_coef); for |z| > 1 through the reversed polynomial (no overflow):
 * p / p' = z q(w) / (m q(w) - w q'(w)), w = 1/z, q(w) = sum p_i w^i. */
ZW_NOINLINE static cplx newton_step(const zw_loop *loop, zw_real alpha, zw_real beta, unsigned m,
                                    cplx z, const ceb *accurate, zw_real *noise)
{
    cplx v = c_make(ZW_R(0.0), ZW_R(0.0)), dv = v;
    zw_real mag = ZW_R(0.0), az = c_abs(z);
    const unsigned terms = m + 1u;
    unsigned i;
    if (az <= ZW_R(1.0)) {
        for (i = 0u; i <= m; ++i) {
            const zw_real pk = poly_coef(loop, alpha, beta, i);
            dv = c_add(c_mul(dv, z), v);
            v = c_add(c_mul(v, z), c_make(pk, ZW_R(0.0)));
            mag = mag * az + ZW_FABS(pk);
        }
        mag *= ZW_R(8.0) * (zw_real)terms * ZW_U;
        /* the value from the factors where it is accurate (computed by the caller, so
         * that eval_p's frame does not stack on this one); the derivative needs no such
         * accuracy */
        if (accurate != NULL) {
            v = accurate->v;
            mag = accurate->e;
        }
        *noise = mag / c_abs(dv);
        return c_div_inline(v, dv);
    } else {
        cplx w = c_div_inline(c_make(ZW_R(1.0), ZW_R(0.0)), z), den;
        const zw_real aw = c_abs(w);
        for (i = m + 1u; i > 0u; --i) {
            const zw_real pk = poly_coef(loop, alpha, beta, i - 1u);
            dv = c_add(c_mul(dv, w), v);
            v = c_add(c_mul(v, w), c_make(pk, ZW_R(0.0)));
            mag = mag * aw + ZW_FABS(pk);
        }
        /* v = q(w), dv = q'(w) */
        den = c_sub(c_mul(c_make((zw_real)m, ZW_R(0.0)), v), c_mul(w, dv));
        *noise = ZW_R(8.0) * (zw_real)terms * ZW_U * mag * az / c_abs(den);
        return c_div_inline(c_mul(z, v), den);
    }
}

#define LOOP_ABERTH_ITER 100u  /* sweeps on the expanded coefficients */
#define LOOP_ABERTH_POLISH 8u /* then sweeps with p from its factors */

/* Is coefficient i of p exactly zero (value and every part's bound)? */
static bool coef_exact_zero(const zw_loop *loop, zw_real alpha, zw_real beta, unsigned i)
{
    return (loop->D[i] == ZW_R(0.0)) && (loop->D_err[i] == ZW_R(0.0)) &&
           ((alpha == ZW_R(0.0)) || ((loop->Na[i] == ZW_R(0.0)) && (loop->Na_err[i] == ZW_R(0.0)))) &&
           ((beta == ZW_R(0.0)) || ((loop->Nb[i] == ZW_R(0.0)) && (loop->Nb_err[i] == ZW_R(0.0))));
}

/* The roots of p by Aberth-Ehrlich iteration (simultaneous, no deflation) into z[0..*m-1];
 * exact zero roots (trailing coefficients that are exactly zero) are set aside, so *m may
 * be below the degree.  False when the iteration produced something non-finite. */
static bool aberth(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                   unsigned *m_out, bool accurate)
{
    cplx *z = ws->root;
    unsigned m = loop->degree, i, j, it, pass;
    uint_least32_t done = 0u, all;
    zw_real lead = poly_coef(loop, alpha, beta, 0u), r0;
    while ((m > 0u) && coef_exact_zero(loop, alpha, beta, m)) {
        --m;
    }
    *m_out = m;
    if (m == 0u) {
        return true;
    }
    all = (uint_least32_t)(((uint_least32_t)1u << (m - 1u)) * 2u - 1u); /* m <= 27 bits */
    /* start on the circle of the roots' geometric mean, off the real axis */
    r0 = ZW_POW(ZW_FABS(poly_coef(loop, alpha, beta, m) / lead), ZW_R(1.0) / (zw_real)m);
    if (!(r0 > ZW_R(0.0)) || !ZW_IS_FINITE(r0)) {
        r0 = ZW_R(1.0);
    }
    for (i = 0u; i < m; ++i) {
        zw_real ang = ZW_R(2.0) * LOOP_PI * (zw_real)i / (zw_real)m + ZW_R(0.7);
        z[i] = c_make(r0 * ZW_COS(ang), r0 * ZW_SIN(ang));
    }
    /* pass 0 on the expanded coefficients (cheap); with accurate, pass 1 polishes with p
     * from its factors, from that good start */
    for (pass = 0u; pass < (accurate ? 2u : 1u); ++pass) {
        done = 0u;
        for (it = 0u; (it < ((pass == 0u) ? LOOP_ABERTH_ITER : LOOP_ABERTH_POLISH)) && (done != all); ++it) {
            for (i = 0u; i < m; ++i) {
                cplx n, s = c_make(ZW_R(0.0), ZW_R(0.0)), step;
                zw_real noise = ZW_R(0.0);
                if ((done & ((uint_least32_t)1u << i)) != 0u) {
                    continue; /* converged: frozen */
                }
                if ((pass == 1u) && (m == loop->degree) && (c_abs(z[i]) <= ZW_R(1.0))) {
                    /* p from its factors (the deflated polynomial is p / z^(n - m)) */
                    ceb pz;
                    plant_at(loop, ws, z[i]);
                    pz = eval_p(ws, alpha, beta, z[i]);
                    n = newton_step(loop, alpha, beta, m, z[i], &pz, &noise);
                } else {
                    n = newton_step(loop, alpha, beta, m, z[i], NULL, &noise);
                }
                for (j = 0u; j < m; ++j) {
                    if (j != i) {
                        s = c_add(s, c_div(c_make(ZW_R(1.0), ZW_R(0.0)), c_sub(z[i], z[j])));
                    }
                }
                step = c_div(n, c_sub(c_make(ZW_R(1.0), ZW_R(0.0)), c_mul(n, s)));
                if (!ZW_IS_FINITE(step.re) || !ZW_IS_FINITE(step.im)) {
                    /* p' = 0 or coincident estimates: nudge */
                    step = c_make(ZW_R(1e-3) * (ZW_R(1.0) + c_abs(z[i])), ZW_R(1e-3));
                }
                z[i] = c_sub(z[i], step);
                /* converged once the step is down to the evaluation's own noise, or small
                 * against the root's distance to the unit circle (all that the verdicts need:
                 * a cluster deep inside converges slowly and matters little) */
                {
                    const zw_real st = c_abs(step), az = c_abs(z[i]);
                    const unsigned m64 = 64u * m;
                    if ((st <= ZW_R(2.0) * noise + ZW_R(8.0) * ZW_U * az) ||
                        (st * (zw_real)m64 <= ZW_R(1e-3) * ZW_FABS(ZW_R(1.0) - az))) {
                        done |= (uint_least32_t)1u << i;
                    }
                }
            }
        }
    }
    for (i = 0u; i < m; ++i) {
        if (!ZW_IS_FINITE(c_abs(z[i]))) {
            return false;
        }
    }
    return true;
}

/* The root of largest modulus (0 when every root is an exact zero). */
static cplx largest_root(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                         bool accurate, bool *ok)
{
    const cplx *z = ws->root;
    cplx top = c_make(ZW_R(0.0), ZW_R(0.0));
    zw_real best = -ZW_R(1.0);
    unsigned m = 0u, i;
    *ok = aberth(loop, ws, alpha, beta, &m, accurate);
    for (i = 0u; i < m; ++i) {
        zw_real a = c_abs(z[i]);
        if (a > best) {
            best = a;
            top = z[i];
        }
    }
    return top;
}

/* A rigorous a-posteriori test "every root has |z| < r" from approximate roots z_i
 * (Braess-Hadeler): with W_i = p(z_i) / (p_0 prod_{j != i} (z_i - z_j)), every root of p
 * lies in a disk |z - z_i| <= m |W_i|.  (Proof: p / p_0 = prod (z - z_j) +
 * sum_i W_i prod_{j != i} (z - z_j) by interpolation at the z_i, so a root zeta outside
 * every disk would give 1 + sum_i W_i / (zeta - z_i) = 0 with the sum below 1 in modulus.)
 * |p(z_i)| is bounded above by the computed value plus the Horner rounding and the
 * coefficients' own bounds; the denominator below, with its roundings.  The roots are
 * only a guess: the test is as rigorous as its bounds, whatever they are.  Its band is
 * the roots' own condition, unlike the Routh array, whose entries lose accuracy on the
 * cluster of roots that a delay line and a moving average put near z = 0. */
/* m |W_i| bounded above (+inf when it cannot be bounded). */
static zw_real inclusion_radius(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                zw_real beta, const cplx z[],
                                unsigned m, unsigned i, zw_real lead_low)
{
    const zw_real az = c_abs(z[i]) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
    zw_real num, den = lead_low;
    unsigned j, k;
    if (m == loop->degree) {
        /* from the factors */
        ceb pz;
        plant_at(loop, ws, z[i]);
        pz = eval_p(ws, alpha, beta, z[i]);
        num = (c_abs(pz.v) + pz.e) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
    } else {
        /* exact zero roots set aside: p = z^(n-m) p_m; Horner on p_m, whose complex steps err
         * by at most ~(2 sqrt 2 + 1) u of |v||z| + |p_k| each */
        cplx v = c_make(ZW_R(0.0), ZW_R(0.0));
        zw_real mag = ZW_R(0.0), unc = ZW_R(0.0);
        const unsigned terms = m + 1u;
        for (k = 0u; k <= m; ++k) {
            const zw_real pk = poly_coef(loop, alpha, beta, k);
            const zw_real ek = loop->D_err[k] + ZW_FABS(alpha) * loop->Na_err[k] +
                               ZW_FABS(beta) * loop->Nb_err[k] +
                               ZW_R(4.0) * ZW_U * (ZW_FABS(loop->D[k]) + ZW_FABS(alpha * loop->Na[k]) +
                                                   ZW_FABS(beta * loop->Nb[k])) + ZW_R(4.0) * ZW_ETA;
            v = c_add(c_mul(v, z[i]), c_make(pk, ZW_R(0.0)));
            mag = mag * az + ZW_FABS(pk);
            unc = unc * az + ek;
        }
        num = c_abs(v) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U) +
              ((ZW_R(8.0) * (zw_real)m + ZW_R(8.0)) * ZW_U * mag + unc) * (ZW_R(1.0) + ZW_R(4.0) * (zw_real)m * ZW_U) +
              ZW_R(8.0) * (zw_real)terms * ZW_ETA;
    }
    for (j = 0u; j < m; ++j) {
        if (j != i) {
            den *= c_abs(c_sub(z[i], z[j]));
        }
    }
    den *= ZW_R(1.0) - (ZW_R(8.0) * (zw_real)m + ZW_R(8.0)) * ZW_U;
    if (!(den > ZW_REAL_MIN) || !ZW_IS_FINITE(num)) {
        return ZW_HUGE_VAL;
    }
    return (zw_real)m * (num / den) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
}

/* Is disk i (centre z[i], radius radius[i]) disjoint from every other one? */
static bool disk_isolated(const cplx z[], const zw_real radius[], unsigned m, unsigned i)
{
    unsigned j;
    for (j = 0u; j < m; ++j) {
        if ((j != i) && !(c_abs(c_sub(z[i], z[j])) * (ZW_R(1.0) - ZW_R(4.0) * ZW_U) >
                          (radius[i] + radius[j]) * (ZW_R(1.0) + ZW_R(2.0) * ZW_U))) {
            return false;
        }
    }
    return true;
}

/* Every root inside |z| < r (STABLE), one surely outside (UNSTABLE: a disk wholly outside
 * and disjoint from all others holds exactly one root, by the continuity argument of
 * Braess and Hadeler on p_t = prod (z - z_j) + t sum_i W_i prod_{j != i} (z - z_j)), or
 * UNSURE.  *top: the root of largest modulus, for the deciding boundary. */
/* The verdict from the m roots in ws->root.  Out of line: its frame is not on the stack
 * while the Aberth run is (the deepest chain of the checks). */
ZW_NOINLINE static routh_result inclusion_verdict(const zw_loop *loop, zw_loop_workspace *ws,
                                                  zw_real alpha, zw_real beta, zw_real r,
                                                  unsigned m, cplx *top)
{
    const cplx *z = ws->root;
    zw_real *radius = ws->radius;
    unsigned i;
    zw_real lead_low, best = -ZW_R(1.0);
    for (i = 0u; i < m; ++i) {
        if (c_abs(z[i]) > best) {
            best = c_abs(z[i]);
            *top = z[i];
        }
    }
    {
        const zw_real p0 = poly_coef(loop, alpha, beta, 0u);
        const zw_real e0 = loop->D_err[0] + ZW_FABS(alpha) * loop->Na_err[0] +
                           ZW_FABS(beta) * loop->Nb_err[0] +
                           ZW_R(4.0) * ZW_U * (ZW_FABS(loop->D[0]) + ZW_FABS(alpha * loop->Na[0]) +
                                               ZW_FABS(beta * loop->Nb[0])) + ZW_R(4.0) * ZW_ETA;
        lead_low = (ZW_FABS(p0) - e0) * (ZW_R(1.0) - ZW_R(4.0) * ZW_U);
        if (!(lead_low > ZW_R(0.0))) {
            return ROUTH_UNSURE;
        }
    }
    /* each radius once (the isolation test below reads every other one) */
    for (i = 0u; i < m; ++i) {
        radius[i] = inclusion_radius(loop, ws, alpha, beta, z, m, i, lead_low);
    }
    /* a disk wholly outside and isolated: one root surely outside */
    for (i = 0u; i < m; ++i) {
        const zw_real az = c_abs(z[i]);
        if (((az * (ZW_R(1.0) - ZW_R(4.0) * ZW_U) - radius[i]) * (ZW_R(1.0) - ZW_R(2.0) * ZW_U) > r) &&
            disk_isolated(z, radius, m, i)) {
            return ROUTH_UNSTABLE;
        }
    }
    /* every disk wholly inside: every root inside */
    for (i = 0u; i < m; ++i) {
        const zw_real az = c_abs(z[i]);
        if (!((az * (ZW_R(1.0) + ZW_R(4.0) * ZW_U) + radius[i]) * (ZW_R(1.0) + ZW_R(2.0) * ZW_U) < r)) {
            return ROUTH_UNSURE;
        }
    }
    return ROUTH_STABLE;
}

static routh_result roots_test(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                               zw_real beta, zw_real r, cplx *top, bool *top_ok)
{
    unsigned m = 0u;
    *top = c_make(ZW_R(0.0), ZW_R(0.0));
    *top_ok = aberth(loop, ws, alpha, beta, &m, true);
    if (!*top_ok) {
        return ROUTH_UNSURE;
    }
    return inclusion_verdict(loop, ws, alpha, beta, r, m, top);
}

/* Angle in [0, pi] of a root; within ~sqrt(u) of the real axis counts as real (a double
 * real root is only resolved to that accuracy). */
static zw_real root_angle(cplx z)
{
    const zw_real tol = ZW_R(8.0) * ZW_SQRT(ZW_U);
    if (ZW_FABS(z.im) <= tol * c_abs(z)) {
        return (z.re >= ZW_R(0.0)) ? ZW_R(0.0) : LOOP_PI;
    }
    return ZW_ATAN2(ZW_FABS(z.im), z.re);
}

zw_status zw_loop_spectral_radius(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                  zw_real beta, zw_real *rho, zw_real *theta)
{
    zw_status st;
    bool ok;
    cplx top;
    if (rho != NULL) {
        *rho = ZW_HUGE_VAL;
    }
    if (theta != NULL) {
        *theta = ZW_R(0.0);
    }
    if ((rho == NULL) || (theta == NULL) || (ws == NULL)) {
        return ZW_ERR_NULL;
    }
    st = check_gains(loop, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    {
        unsigned i;
        for (i = 0u; i <= loop->degree; ++i) {
            if (!ZW_IS_FINITE(poly_coef(loop, alpha, beta, i))) {
                return ZW_ERR_RANGE;
            }
        }
    }
    top = largest_root(loop, ws, alpha, beta, true, &ok);
    if (!ok) {
        return ZW_ERR_RANGE;
    }
    *rho = c_abs(top);
    *theta = root_angle(top);
    return ZW_OK;
}

/* ---- verdicts ------------------------------------------------------------------------------ */

/* After decide left a point not stable: the root test where it could not tell (which may
 * still prove stability), and the boundary: z = 1 (p(1) = alpha Na(1)), z = -1 (the leading
 * coefficient of P), else where the root of largest modulus is (*top, *top_ok; without a
 * root run, 0 and false, which the caller does not read).  Inlined: no frame of its own on
 * the root test's chain (the stack target, tools/footprint.sh). */
static LOOP_INLINE routh_result settle(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                       zw_real beta, routh_result res, routh_result lead,
                                       routh_result trail, cplx *top, bool *top_ok)
{
    *top = c_make(ZW_R(0.0), ZW_R(0.0));
    *top_ok = false;
    if (res == ROUTH_UNSURE) {
        return roots_test(loop, ws, alpha, beta, ZW_R(1.0), top, top_ok);
    }
    if ((trail == ROUTH_STABLE) && (lead == ROUTH_STABLE)) {
        *top = largest_root(loop, ws, alpha, beta, false, top_ok);
    }
    return res;
}

zw_status zw_loop_check(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                        zw_loop_verdict *out)
{
    zw_status st;
    routh_result res, lead, trail;
    cplx top;
    bool ok;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    zw_fail_loop_verdict(out);
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = check_gains(loop, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    res = decide(loop, ws, alpha, beta, &lead, &trail);
    if (res == ROUTH_STABLE) {
        out->stable = true;
        return ZW_OK;
    }
    res = settle(loop, ws, alpha, beta, res, lead, trail, &top, &ok);
    if (res == ROUTH_STABLE) {
        out->stable = true;
        return ZW_OK;
    }
    out->marginal = (res == ROUTH_UNSURE);
    if (trail != ROUTH_STABLE) {
        out->deciding = ZW_LOOP_BOUNDARY_Z_PLUS1;
    } else if (lead != ROUTH_STABLE) {
        out->deciding = ZW_LOOP_BOUNDARY_Z_MINUS1;
    } else {
        const zw_real th = root_angle(top);
        if (!ok) {
            out->deciding = ZW_LOOP_BOUNDARY_COMPLEX; /* unknown: not stable all the same */
        } else if (th == ZW_R(0.0)) {
            out->deciding = ZW_LOOP_BOUNDARY_Z_PLUS1;
        } else if (th == LOOP_PI) {
            out->deciding = ZW_LOOP_BOUNDARY_Z_MINUS1;
        } else {
            out->deciding = ZW_LOOP_BOUNDARY_COMPLEX;
            out->theta = th;
        }
    }
    return ZW_OK;
}

/* The boolean fast path: the same two tests as zw_loop_check, in the same order, so the
 * answer is the same for every point; only the deciding boundary of a not-stable point
 * (an Aberth run) is skipped. */
zw_status zw_loop_is_stable(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                            bool *stable)
{
    zw_status st;
    routh_result res, lead, trail;
    if (stable == NULL) {
        return ZW_ERR_NULL;
    }
    *stable = false;
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = check_gains(loop, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    res = decide(loop, ws, alpha, beta, &lead, &trail);
    if (res == ROUTH_UNSURE) {
        cplx top;
        bool ok;
        res = roots_test(loop, ws, alpha, beta, ZW_R(1.0), &top, &ok);
    }
    *stable = (res == ROUTH_STABLE);
    return ZW_OK;
}

/* (1 - s)^n p(r (1 + s)/(1 - s)) = sum_k p_k (r (1 + s))^(n-k) (1 - s)^k by Horner in
 * r (1 + s), with running bounds (in the workspace's row), then the Routh test. */
ZW_NOINLINE static routh_result radius_routh(const zw_loop *loop, zw_loop_workspace *ws,
                                             zw_real alpha, zw_real beta, zw_real r)
{
    zw_real *w = ws->row, *we = ws->row_err;
    unsigned k, i;
    const zw_eb ga = zw_eb_exact(alpha), gb = zw_eb_exact(beta), re = zw_eb_exact(r);
    for (k = 0u; k <= loop->degree; ++k) {
        zw_eb pk = zw_eb_add_exactish(zw_eb_make(loop->D[k], loop->D_err[k]),
                                   zw_eb_mul_exactish(ga, zw_eb_make(loop->Na[k], loop->Na_err[k])));
        uint_least32_t binom = 1u; /* C(k, i): at most C(27, 13) = 4 * 5014575, exact in zw_real */
        pk = zw_eb_add_exactish(pk, zw_eb_mul_exactish(gb, zw_eb_make(loop->Nb[k], loop->Nb_err[k])));
        if (k > 0u) {
            /* w (degree k - 1) *= r (1 + s), in place, highest power first */
            for (i = k; i > 0u; --i) {
                zw_eb sum = (i < k) ? zw_eb_add(eb_stored(w[i], we[i]), eb_stored(w[i - 1u], we[i - 1u]))
                                     : eb_stored(w[i - 1u], we[i - 1u]);
                sum = zw_eb_mul_exactish(re, sum);
                w[i] = sum.v;
                we[i] = sum.e;
            }
            {
                zw_eb top = zw_eb_mul_exactish(re, eb_stored(w[0], we[0]));
                w[0] = top.v;
                we[0] = top.e;
            }
        } else {
            w[0] = ZW_R(0.0);
            we[0] = ZW_R(0.0);
        }
        /* + p_k (1 - s)^k: s^i at index k - i */
        for (i = 0u; i <= k; ++i) {
            zw_real coef = ((i & 1u) != 0u) ? -(zw_real)binom : (zw_real)binom;
            zw_eb t = zw_eb_add_exactish(eb_stored(w[k - i], we[k - i]),
                                      zw_eb_mul_exactish(pk, zw_eb_exact(coef)));
            w[k - i] = t.v;
            we[k - i] = t.e;
            binom = binom * (uint_least32_t)(k - i) / (uint_least32_t)(i + 1u);
        }
    }
    return routh(w, we, loop->degree);
}

zw_status zw_loop_radius_within(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                zw_real beta, zw_real r, bool *within)
{
    zw_status st;
    routh_result res;
    if (within == NULL) {
        return ZW_ERR_NULL;
    }
    *within = false;
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = check_gains(loop, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    if (ZW_IS_NAN(r)) {
        return ZW_ERR_NAN;
    }
    if (!ZW_IS_FINITE(r) || !(r > ZW_R(0.0))) {
        return ZW_ERR_ARG;
    }
    res = radius_routh(loop, ws, alpha, beta, r);
    if (res == ROUTH_UNSURE) {
        cplx top;
        bool ok;
        res = roots_test(loop, ws, alpha, beta, r, &top, &ok);
    }
    *within = (res == ROUTH_STABLE);
    return ZW_OK;
}
