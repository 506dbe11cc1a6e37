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

#include "internal.h"

#ifdef ZW_REAL_FLOAT
#define LOOP_ATAN2 atan2f
#define LOOP_COS cosf
#define LOOP_SIN sinf
#else
#define LOOP_ATAN2 atan2
#define LOOP_COS cos
#define LOOP_SIN sin
#endif

#define LOOP_PI ZW_R(3.14159265358979323846)
#define LOOP_N (ZW_LOOP_MAX_DEGREE + 1u)

/* ---- input checks ---------------------------------------------------------------------- */

zw_status zw_loop_lowpass_pole(zw_real f_c, zw_real T, zw_real *a)
{
    zw_status st;
    zw_real x;
    if (a == NULL) return ZW_ERR_NULL;
    *a = ZW_R(0.0);
    if ((st = zw_require_finite(f_c)) != ZW_OK) return st;
    if ((st = zw_require_finite(T)) != ZW_OK) return st;
    if (!(T > ZW_R(0.0))) return ZW_ERR_PERIOD;
    /* f_c T >= 1/2 exactly iff fl(f_c T) >= 1/2 (rounding is monotone, 1/2 representable) */
    x = f_c * T;
    if (!(f_c > ZW_R(0.0)) || !(x < ZW_R(0.5))) return ZW_ERR_FILTER;
    x = ZW_EXP(-(ZW_R(2.0) * LOOP_PI) * x);
    /* a cut-off so low that the pole rounds to 1 is an integrator, not a filter */
    if (!(x < ZW_R(1.0))) return ZW_ERR_FILTER;
    *a = x;
    return ZW_OK;
}

/* Degree of the velocity estimate Nv / Dv (numerator and denominator). */
static unsigned estimate_degree(const zw_loop_spec *spec)
{
    if (spec->filter == ZW_VFILTER_AVERAGE) return spec->average;
    if (spec->filter == ZW_VFILTER_LOWPASS && spec->differentiator == ZW_DIFF_TUSTIN) return 2u;
    return 1u;
}

static zw_status check_spec(const zw_loop_spec *spec)
{
    if (spec == NULL) return ZW_ERR_NULL;
    if (spec->delay > ZW_LOOP_MAX_DELAY) return ZW_ERR_DELAY;
    if (spec->differentiator != ZW_DIFF_BACKWARD && spec->differentiator != ZW_DIFF_TUSTIN)
        return ZW_ERR_FILTER;
    switch (spec->filter) {
    case ZW_VFILTER_NONE: break;
    case ZW_VFILTER_LOWPASS:
        if (ZW_IS_NAN(spec->filter_pole)) return ZW_ERR_NAN;
        if (!(spec->filter_pole >= ZW_R(0.0) && spec->filter_pole < ZW_R(1.0))) return ZW_ERR_FILTER;
        break;
    case ZW_VFILTER_AVERAGE:
        if (spec->average < 1u || spec->average > ZW_LOOP_MAX_AVERAGE) return ZW_ERR_FILTER;
        break;
    default: return ZW_ERR_FILTER;
    }
    return ZW_OK;
}

/* An initialized loop: its degree matches its spec (a zeroed or garbage struct fails). */
static zw_status check_loop(const zw_loop *loop)
{
    if (loop == NULL) return ZW_ERR_NULL;
    if (check_spec(&loop->spec) != ZW_OK) return ZW_ERR_ARG;
    if (loop->degree != 2u + loop->spec.delay + estimate_degree(&loop->spec)) return ZW_ERR_ARG;
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
    F_ZME,   /* z - e         s: (1 + e) s + (1 - e), 1 - e = delta (c1 + c2) / 2 */
    F_PLANT, /* c1 z + c2     s: d12 s + (c1 + c2) */
    F_PAD    /* 1             s: 1 - s */
} factor_kind;

typedef struct build_ctx {
    const zw_coeffs *c;
    zw_real a;       /* filter pole (exact) */
    bool bilinear;   /* build the s polynomial */
} build_ctx;

static zw_eb eb_make(zw_real v, zw_real e)
{
    zw_eb r;
    r.v = v;
    r.e = e;
    return r;
}

/* A coefficient field with its relative bound and the subnormal floor. */
static zw_eb coef_field(const zw_coeffs *c, zw_real v)
{
    return eb_make(v, zw_coef_relerr(c) * ZW_FABS(v) + zw_coef_floor(v));
}

/* f1 x + f0 for the factor in the context's variable. */
static void factor(const build_ctx *ctx, factor_kind kind, zw_eb *f1, zw_eb *f0)
{
    const zw_coeffs *c = ctx->c;
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
            *f1 = eb_make(v, ZW_U * v);
            v = ZW_R(1.0) - ctx->a;
            *f0 = eb_make(v, ZW_U * v);
        } else {
            *f1 = zw_eb_exact(ZW_R(1.0));
            *f0 = zw_eb_exact(-ctx->a);
        }
        break;
    case F_ZME:
        if (s) {
            const zw_real e_err = zw_coef_e_abserr(c);
            v = ZW_R(1.0) + c->e;
            *f1 = eb_make(v, e_err + ZW_U * v);
            /* 1 - e = delta s / 2: s's own bound (which covers its sensitivity to delta),
             * delta's uncertainty, one rounding (the halving is exact but for underflow) */
            v = ZW_R(0.5) * (c->delta * c->s);
            *f0 = eb_make(v, (zw_coef_relerr(c) + c->delta_relerr + ZW_R(2.0) * ZW_U) * v +
                                 zw_coef_floor(c->s) * c->delta + ZW_R(2.0) * ZW_ETA);
        } else {
            *f1 = zw_eb_exact(ZW_R(1.0));
            *f0 = eb_make(-c->e, zw_coef_e_abserr(c));
        }
        break;
    case F_PLANT:
        if (s) {
            *f1 = coef_field(c, c->d12);
            *f0 = coef_field(c, c->s);
        } else {
            *f1 = coef_field(c, c->c1);
            *f0 = coef_field(c, c->c2);
        }
        break;
    case F_PAD:
    default:
        *f1 = zw_eb_exact(s ? ZW_R(-1.0) : ZW_R(0.0));
        *f0 = zw_eb_exact(ZW_R(1.0));
        break;
    }
}

/* Product of two bounded values whose error is exactly zero when both are exact and one
 * of them is 0, +-1 or +-2 (factors of that form are common and must not add rounding). */
static zw_eb eb_mul_exactish(zw_eb a, zw_eb b)
{
    if (a.e == ZW_R(0.0) && b.e == ZW_R(0.0)) {
        zw_real m = ZW_FABS(a.v) < ZW_FABS(b.v) ? ZW_FABS(a.v) : ZW_FABS(b.v);
        if (m == ZW_R(0.0) || m == ZW_R(1.0) || m == ZW_R(2.0)) return zw_eb_exact(a.v * b.v);
    }
    return zw_eb_mul(a, b);
}

/* Sum whose error is the inputs' when one of them is an exact zero. */
static zw_eb eb_add_exactish(zw_eb a, zw_eb b)
{
    if (a.v == ZW_R(0.0) && a.e == ZW_R(0.0)) return b;
    if (b.v == ZW_R(0.0) && b.e == ZW_R(0.0)) return a;
    return zw_eb_add(a, b);
}

/* v (degree deg, highest power first) *= f1 x + f0, in place; the result has degree
 * deg + 1 (v must hold deg + 2 entries). */
static void mul_linear(zw_real v[], zw_real e[], unsigned deg, zw_eb f1, zw_eb f0)
{
    unsigned i;
    for (i = deg + 1u; i > 0u; --i) {
        zw_eb lo = eb_mul_exactish(f0, eb_make(v[i - 1u], e[i - 1u]));
        zw_eb hi = i <= deg ? eb_mul_exactish(f1, eb_make(v[i], e[i])) : zw_eb_exact(ZW_R(0.0));
        zw_eb sum = eb_add_exactish(hi, lo);
        v[i] = sum.v;
        e[i] = sum.e;
    }
    {
        zw_eb top = eb_mul_exactish(f1, eb_make(v[0], e[0]));
        v[0] = top.v;
        e[0] = top.e;
    }
}

static void mul_factor(const build_ctx *ctx, zw_real v[], zw_real e[], unsigned *deg,
                       factor_kind kind, unsigned times)
{
    unsigned k;
    zw_eb f1, f0;
    factor(ctx, kind, &f1, &f0);
    for (k = 0u; k < times; ++k) {
        mul_linear(v, e, *deg, f1, f0);
        *deg += 1u;
    }
}

static void mul_scalar(zw_real v[], zw_real e[], unsigned deg, zw_eb k)
{
    unsigned i;
    for (i = 0u; i <= deg; ++i) {
        zw_eb r = eb_mul_exactish(k, eb_make(v[i], e[i]));
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
        unsigned k = n - i; /* power of s at index i */
        if (i > 0u) binom = binom * (zw_real)(k + 1u) / (zw_real)(n - k); /* C(n,k) from C(n,k+1) */
        if ((k & 1u) != 0u) v[i] = ZW_R(2.0) * binom;
    }
}

/* Dv (into dv) and Nv (into nv) of the velocity estimate, both of degree m. */
static void velocity_estimate(const build_ctx *ctx, const zw_loop_spec *spec, zw_real dv[],
                              zw_real dv_e[], zw_real nv[], zw_real nv_e[])
{
    const bool tustin = spec->differentiator == ZW_DIFF_TUSTIN;
    unsigned dd, nd;
    set_one(dv, dv_e, &dd);
    set_one(nv, nv_e, &nd);
    switch (spec->filter) {
    case ZW_VFILTER_AVERAGE: {
        /* backward: (z^n - 1) / (n z^n);  Tustin: 2 (z^n - 1) / (n z^(n-1) (z + 1)) */
        const unsigned n = spec->average;
        set_power_minus_one(ctx, nv, nv_e, n);
        mul_factor(ctx, dv, dv_e, &dd, F_Z, tustin ? n - 1u : n);
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
        zw_eb gain = eb_make(one_minus_a, ZW_U * one_minus_a);
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
        if (tustin) mul_scalar(nv, nv_e, nd, zw_eb_exact(ZW_R(2.0)));
        break;
    }
}

/* D = 2 z^d (z - 1)(z - e) Dv,  Na = (c1 z + c2) Dv,  Nb = (c1 z + c2) Nv, the last two
 * lifted to degree n, in the context's variable. */
static void build_parts(const build_ctx *ctx, const zw_loop_spec *spec, unsigned n, zw_real D[],
                        zw_real De[], zw_real Na[], zw_real Nae[], zw_real Nb[], zw_real Nbe[])
{
    const unsigned m = estimate_degree(spec);
    unsigned i, dd = m, da, db;
    velocity_estimate(ctx, spec, Na, Nae, Nb, Nbe);
    for (i = 0u; i <= m; ++i) {
        D[i] = Na[i];
        De[i] = Nae[i];
    }
    mul_scalar(D, De, dd, zw_eb_exact(ZW_R(2.0)));
    mul_factor(ctx, D, De, &dd, F_ZM1, 1u);
    mul_factor(ctx, D, De, &dd, F_ZME, 1u);
    mul_factor(ctx, D, De, &dd, F_Z, spec->delay);
    da = m;
    db = m;
    mul_factor(ctx, Na, Nae, &da, F_PLANT, 1u);
    mul_factor(ctx, Nb, Nbe, &db, F_PLANT, 1u);
    mul_factor(ctx, Na, Nae, &da, F_PAD, n - da);
    mul_factor(ctx, Nb, Nbe, &db, F_PAD, n - db);
}

static bool all_finite(const zw_real v[], const zw_real e[], unsigned n)
{
    unsigned i;
    for (i = 0u; i <= n; ++i)
        if (!ZW_IS_FINITE(v[i]) || !ZW_IS_FINITE(e[i])) return false;
    return true;
}

static const zw_loop k_empty_loop; /* zero: degree 0, refused by check_loop */

zw_status zw_loop_init(zw_loop *out, const zw_coeffs *c, const zw_loop_spec *spec)
{
    zw_status st;
    build_ctx ctx;
    unsigned n;
    if (out == NULL) return ZW_ERR_NULL;
    *out = k_empty_loop;
    if (spec == NULL) return ZW_ERR_NULL;
    if ((st = zw_require_coeffs(c, false)) != ZW_OK) return st;
    if ((st = check_spec(spec)) != ZW_OK) return st;
    n = 2u + spec->delay + estimate_degree(spec);
    ctx.c = c;
    ctx.a = spec->filter == ZW_VFILTER_LOWPASS ? spec->filter_pole : ZW_R(0.0);
    ctx.bilinear = false;
    build_parts(&ctx, spec, n, out->D, out->D_err, out->Na, out->Na_err, out->Nb, out->Nb_err);
    ctx.bilinear = true;
    build_parts(&ctx, spec, n, out->Ds, out->Ds_err, out->Nas, out->Nas_err, out->Nbs,
                out->Nbs_err);
    if (!all_finite(out->D, out->D_err, n) || !all_finite(out->Na, out->Na_err, n) ||
        !all_finite(out->Nb, out->Nb_err, n) || !all_finite(out->Ds, out->Ds_err, n) ||
        !all_finite(out->Nas, out->Nas_err, n) || !all_finite(out->Nbs, out->Nbs_err, n)) {
        *out = k_empty_loop;
        return ZW_ERR_RANGE;
    }
    out->c = *c;
    out->spec = *spec;
    if (spec->filter != ZW_VFILTER_LOWPASS) out->spec.filter_pole = ZW_R(0.0);
    if (spec->filter != ZW_VFILTER_AVERAGE) out->spec.average = 0u;
    out->degree = n;
    return ZW_OK;
}

static zw_status check_gains(const zw_loop *loop, zw_real alpha, zw_real beta)
{
    zw_status st;
    if ((st = check_loop(loop)) != ZW_OK) return st;
    if ((st = zw_require_finite(alpha)) != ZW_OK) return st;
    return zw_require_finite(beta);
}

zw_status zw_loop_poly(const zw_loop *loop, zw_real alpha, zw_real beta,
                       zw_real p[ZW_LOOP_MAX_DEGREE + 1u], unsigned *degree)
{
    zw_status st;
    unsigned i;
    if (p == NULL || degree == NULL) {
        if (degree != NULL) *degree = 0u;
        if (p != NULL)
            for (i = 0u; i < LOOP_N; ++i) p[i] = ZW_R(0.0);
        return ZW_ERR_NULL;
    }
    for (i = 0u; i < LOOP_N; ++i) p[i] = ZW_R(0.0);
    *degree = 0u;
    if ((st = check_gains(loop, alpha, beta)) != ZW_OK) return st;
    for (i = 0u; i <= loop->degree; ++i) {
        p[i] = (loop->D[i] + alpha * loop->Na[i]) + beta * loop->Nb[i];
        if (!ZW_IS_FINITE(p[i])) {
            for (i = 0u; i < LOOP_N; ++i) p[i] = ZW_R(0.0);
            return ZW_ERR_RANGE;
        }
    }
    *degree = loop->degree;
    return ZW_OK;
}
