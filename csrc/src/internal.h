/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Private to the core: running error bounds and the shared input checks.
 *
 * A zw_eb carries a value and a bound on its absolute error against the exact result of
 * the same expression on exact inputs (Wilkinson's running error analysis).  Every
 * operation adds one rounding (u |v|) and one underflow quantum (ZW_REAL_MIN; it bounds a
 * flushed result, but zw_selftest refuses flush-to-zero: docs/fp-environment.md).  Verdicts compare bounded values with zw_compare
 * (zw_eb_compare for zw_eb pairs), which answers "surely less", "surely not less" or
 * "cannot tell".  region.c writes its bounds out term by term instead of using zw_eb.
 */
#ifndef ZWIDTH_INTERNAL_H
#define ZWIDTH_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>

#include "zwidth/coeffs.h"
#include "zwidth/loop.h"
#include "zwidth/region.h"

#define ZW_U ZW_UNIT_ROUNDOFF
#define ZW_ETA ZW_REAL_MIN

/* Keeps a helper out of line where the compiler would merge it into its caller, so that
 * the frames along the deep call chains (root test, box search, register map) stay small
 * (the stack gate of tools/footprint.sh).  Only a hint: nothing depends on it for
 * correctness. */
#if defined(__GNUC__)
#define ZW_NOINLINE __attribute__((noinline))
#else
#define ZW_NOINLINE
#endif

typedef struct zw_eb {
    zw_real v; /* computed value */
    zw_real e; /* bound on |v - exact| */
} zw_eb;

static inline zw_eb zw_eb_exact(zw_real v)
{
    zw_eb r;
    r.v = v;
    r.e = ZW_R(0.0);
    return r;
}

/* A value known to relative accuracy rel (plus the underflow quantum). */
static inline zw_eb zw_eb_rel(zw_real v, zw_real rel)
{
    zw_eb r;
    r.v = v;
    r.e = rel * ZW_FABS(v) + ZW_ETA;
    return r;
}

static inline zw_eb zw_eb_add(zw_eb a, zw_eb b)
{
    zw_eb r;
    r.v = a.v + b.v;
    r.e = a.e + b.e + ZW_U * ZW_FABS(r.v) + ZW_ETA;
    return r;
}

static inline zw_eb zw_eb_sub(zw_eb a, zw_eb b)
{
    zw_eb r;
    r.v = a.v - b.v;
    r.e = a.e + b.e + ZW_U * ZW_FABS(r.v) + ZW_ETA;
    return r;
}

static inline zw_eb zw_eb_mul(zw_eb a, zw_eb b)
{
    zw_eb r;
    r.v = a.v * b.v;
    r.e = ZW_FABS(a.v) * b.e + ZW_FABS(b.v) * a.e + a.e * b.e + ZW_U * ZW_FABS(r.v) + ZW_ETA;
    return r;
}

/* a / b.  When b's bound reaches zero the quotient is unbounded: the error becomes
 * infinite-like (ZW_REAL_MAX) so every comparison with it answers "cannot tell". */
static inline zw_eb zw_eb_div(zw_eb a, zw_eb b)
{
    zw_eb r;
    zw_real den = ZW_FABS(b.v) - b.e;
    r.v = a.v / b.v;
    if (!(den > ZW_R(0.0))) {
        r.e = ZW_REAL_MAX;
        return r;
    }
    r.e = (a.e + ZW_FABS(r.v) * b.e) / den * (ZW_R(1.0) + ZW_R(4.0) * ZW_U) + ZW_U * ZW_FABS(r.v) +
          ZW_ETA;
    return r;
}

typedef enum zw_cmp { ZW_CMP_LT = -1, ZW_CMP_UNSURE = 0, ZW_CMP_GE = 1 } zw_cmp;

/* Is exact(lhs) < exact(rhs), given that |lhs - exact(lhs)| + |rhs - exact(rhs)| <= err?
 * The bound is inflated for the roundings of err and of the difference themselves. */
static inline zw_real zw_compare_bound(zw_real diff, zw_real err)
{
    return err * (ZW_R(1.0) + ZW_R(16.0) * ZW_U) + ZW_R(2.0) * ZW_U * ZW_FABS(diff) + ZW_ETA;
}

static inline zw_cmp zw_compare(zw_real lhs, zw_real rhs, zw_real err)
{
    zw_real diff = rhs - lhs;
    zw_real bound = zw_compare_bound(diff, err);
    if (!ZW_IS_FINITE(bound) || ZW_IS_NAN(diff)) return ZW_CMP_UNSURE; /* overflowed: cannot tell */
    if (diff > bound) return ZW_CMP_LT;
    if (diff < -bound) return ZW_CMP_GE;
    return ZW_CMP_UNSURE;
}

/* zw_compare(lhs, rhs, err) == ZW_CMP_LT as 1 or 0 in zw_real, without branches or
 * integer conversions, so that loops over it vectorize (a NaN difference compares false;
 * the bound must be finite).  Products of these are "and". */
static inline zw_real zw_surely_less01(zw_real lhs, zw_real rhs, zw_real err)
{
    zw_real diff = rhs - lhs;
    zw_real bound = zw_compare_bound(diff, err);
    zw_real less = diff > bound ? ZW_R(1.0) : ZW_R(0.0);
    return ZW_FABS(bound) <= ZW_REAL_MAX ? less : ZW_R(0.0);
}

static inline zw_cmp zw_eb_compare(zw_eb a, zw_eb b)
{
    return zw_compare(a.v, b.v, a.e + b.e);
}

/* A coefficient field that is subnormal (c2 for delta > ~1e154 / 1e19, d12 for subnormal
 * delta) errs by up to ZW_COEF_ABSERR absolutely, whatever its relative bound says:
 * zw_coef_floor gives that floor (0 for a normal field), and callers add it times the
 * magnitude of what multiplies the field. */
#define ZW_COEF_ABSERR ((zw_real)ZW_COEF_ULPS * ZW_ETA)

static inline zw_real zw_coef_floor(zw_real v)
{
    return ZW_FABS(v) < ZW_REAL_MIN ? ZW_COEF_ABSERR : ZW_R(0.0);
}

/* Relative error bound of a (normal) coefficient field: its own accuracy (ZW_COEF_ULPS
 * ulps, an ulp being at most 2u relative) plus its sensitivity to an uncertain delta
 * (every field's relative condition number in delta is at most 2; tests/py/test_coeffs.py
 * checks it). */
static inline zw_real zw_coef_relerr(const zw_coeffs *c)
{
    return ZW_R(2.0) * (zw_real)ZW_COEF_ULPS * ZW_U + ZW_R(2.0) * c->delta_relerr;
}

/* Absolute error bound of e = exp(-delta): exp(-delta) has absolute sensitivity
 * delta e^-delta <= 1/e to a relative error of delta. */
static inline zw_real zw_coef_e_abserr(const zw_coeffs *c)
{
    return zw_coef_relerr(c) * c->e + ZW_R(0.5) * c->delta_relerr + ZW_ETA;
}

/* ---- The ideal plant's factors with their bounds (one copy: plant.c, loop.c) -------- */

/* A coefficient field (c1, c2, d12, s) with its relative bound and the subnormal floor. */
static inline zw_eb zw_coef_field(const zw_coeffs *c, zw_real v)
{
    zw_eb r;
    r.v = v;
    r.e = zw_coef_relerr(c) * ZW_FABS(v) + zw_coef_floor(v);
    return r;
}

/* z - e as f1 z + f0. */
static inline void zw_coef_zme(const zw_coeffs *c, zw_eb *f1, zw_eb *f0)
{
    *f1 = zw_eb_exact(ZW_R(1.0));
    f0->v = -c->e;
    f0->e = zw_coef_e_abserr(c);
}

/* Its bilinear image (1 + e) s + (1 - e), with 1 - e = delta s / 2 (no cancellation):
 * s's own bound (which covers its sensitivity to delta), delta's uncertainty, one rounding
 * (the halving is exact but for underflow). */
static inline void zw_coef_zme_s(const zw_coeffs *c, zw_eb *f1, zw_eb *f0)
{
    zw_real v = ZW_R(1.0) + c->e;
    f1->v = v;
    f1->e = zw_coef_e_abserr(c) + ZW_U * v;
    v = ZW_R(0.5) * (c->delta * c->s);
    f0->v = v;
    f0->e = (zw_coef_relerr(c) + c->delta_relerr + ZW_R(2.0) * ZW_U) * v +
            zw_coef_floor(c->s) * c->delta + ZW_R(2.0) * ZW_ETA;
}

/* ---- Fail-safe outputs (status.h): what a failed call writes ------------------------ */

/* A quiet NaN: unknown values (coefficients, normalized gains, advice) that every check
 * refuses with ZW_ERR_NAN.  NAN is optional in C99; the fallback is 0/0 at run time. */
#ifdef NAN
#define ZW_NAN ((zw_real)NAN)
#else
static inline zw_real zw_nan_fallback(void)
{
    volatile zw_real zero = ZW_R(0.0); /* volatile: no constant folding of 0/0 */
    return zero / zero;
}
#define ZW_NAN (zw_nan_fallback())
#endif
/* +inf: a spectral radius that certifies nothing (rho >= 1). */
#define ZW_INF (ZW_HUGE_VAL)

/* The verdict of a failed check: not stable, not marginal, no constraint blamed. */
static inline void zw_fail_verdict(zw_verdict *out)
{
    if (out == NULL) return;
    out->stable = false;
    out->marginal = false;
    out->deciding = ZW_BOUND_INVALID;
    out->violated = (uint_least16_t)ZW_BOUND_INVALID;
}

/* The same for the general loop (loop.h). */
static inline void zw_fail_loop_verdict(zw_loop_verdict *out)
{
    if (out == NULL) return;
    out->stable = false;
    out->marginal = false;
    out->deciding = ZW_LOOP_BOUNDARY_NONE;
    out->theta = ZW_R(0.0);
}

static inline void zw_fail_real(zw_real *out, zw_real value)
{
    if (out != NULL) *out = value;
}

static inline void zw_fail_bool(bool *out)
{
    if (out != NULL) *out = false;
}

/* An empty interval: lo = hi = 0, nonempty false. */
static inline void zw_fail_interval(zw_real *lo, zw_real *hi, bool *nonempty)
{
    zw_fail_real(lo, ZW_R(0.0));
    zw_fail_real(hi, ZW_R(0.0));
    zw_fail_bool(nonempty);
}

/* Every field NaN: a later check on it answers ZW_ERR_NAN. */
static inline void zw_fail_coeffs(zw_coeffs *out)
{
    if (out == NULL) return;
    out->delta = ZW_NAN;
    out->e = ZW_NAN;
    out->c1 = ZW_NAN;
    out->c2 = ZW_NAN;
    out->d12 = ZW_NAN;
    out->s = ZW_NAN;
    out->g = ZW_NAN;
    out->sigma = ZW_NAN;
    out->hs = ZW_NAN;
    out->delta_relerr = ZW_NAN;
}

/* Validate one finite real input: ZW_ERR_NAN / ZW_ERR_INF, else ZW_OK. */
static inline zw_status zw_require_finite(zw_real x)
{
    if (ZW_IS_NAN(x)) return ZW_ERR_NAN;
    if (!ZW_IS_FINITE(x)) return ZW_ERR_INF;
    return ZW_OK;
}

/* A coefficient struct the checks can use: finite delta (ZW_ERR_NULL / NAN / INF) and a
 * delta uncertainty that is a finite non-negative number (ZW_ERR_ARG: a negative one
 * would shrink every guard).  need_hs: the caller uses hs, which is +inf for delta above
 * ~max/2 (ZW_ERR_RANGE). */
static inline zw_status zw_require_coeffs(const zw_coeffs *c, bool need_hs)
{
    zw_status st;
    if (c == NULL) return ZW_ERR_NULL;
    st = zw_require_finite(c->delta);
    if (st != ZW_OK) return st;
    if (!(c->delta_relerr >= ZW_R(0.0) && ZW_IS_FINITE(c->delta_relerr))) return ZW_ERR_ARG;
    if (need_hs && !ZW_IS_FINITE(c->hs)) return ZW_ERR_RANGE;
    return ZW_OK;
}

/* Roundings in the conversions, budgeted in the checks' guard
 * (device.c converts, batch.c repeats the conversion inside its loop):
 * delta = (b T) / m: 2;  k_scale = m / T / T: 2, alpha = K / k_scale: 1 more;
 * b_scale = m / T: 1, beta = B / b_scale: 1 more.  One extra u each for slack. */
#define ZW_DELTA_RELERR (ZW_R(3.0) * ZW_U)
#define ZW_ALPHA_RELERR (ZW_R(4.0) * ZW_U)
#define ZW_BETA_RELERR (ZW_R(3.0) * ZW_U)

/* Normalized gains with bounds on their absolute errors (0 when given exactly, a few
 * roundings when converted from real units). */
typedef struct zw_gains {
    zw_eb alpha;
    zw_eb beta;
} zw_gains;

static inline zw_gains zw_gains_exact(zw_real alpha, zw_real beta)
{
    zw_gains g;
    g.alpha = zw_eb_exact(alpha);
    g.beta = zw_eb_exact(beta);
    return g;
}

/* The constraints of the exact region, eq (10), each "lhs < rhs" with err bounding the
 * errors of both sides.  One definition serves the verdicts (region.c) and the batch
 * loops (batch.c), so both decide every point identically.
 * x = beta + delta > 0 is the damping constraint; the hyperbola form divides by x and
 * means nothing unless x is surely positive (callers must not use it otherwise). */
typedef struct zw_constraint {
    zw_real lhs, rhs, err;
} zw_constraint;

static inline zw_eb zw_exact_x(const zw_coeffs *c, const zw_gains *g)
{
    zw_eb x;
    x.v = g->beta.v + c->delta;
    x.e = g->beta.e + c->delta * c->delta_relerr + ZW_U * ZW_FABS(x.v) + ZW_ETA;
    return x;
}

/* hyperbola  (alpha/sigma) g + (alpha/sigma) / x  <  hs - beta/sigma */
static inline zw_constraint zw_hyperbola_constraint(const zw_coeffs *c, zw_real coef_err,
                                                    const zw_gains *g, zw_eb x)
{
    zw_constraint k;
    const zw_real alpha = g->alpha.v, beta = g->beta.v;
    zw_real inv_sigma = ZW_R(1.0) / c->sigma;          /* exact: sigma = 2^k */
    zw_real as = alpha * inv_sigma, as_err = g->alpha.e * inv_sigma + ZW_ETA;
    zw_real t1 = as * c->g;
    zw_real t2 = as / x.v;
    k.lhs = t1 + t2;
    k.rhs = c->hs - beta * inv_sigma;
    k.err = ZW_FABS(t1) * (coef_err + ZW_U) + as_err * c->g                   /* t1 */
          + (as_err + ZW_FABS(t2) * x.e) / (x.v - x.e) + ZW_U * ZW_FABS(t2)   /* t2 */
          + ZW_U * ZW_FABS(k.lhs)                                              /* sum */
          + c->hs * coef_err + g->beta.e * inv_sigma + ZW_U * ZW_FABS(k.rhs)   /* rhs */
          + ZW_R(4.0) * ZW_ETA;
    return k;
}

/* line  d12 (alpha/2) + d12 beta  <  2 (1 + e) */
static inline zw_constraint zw_line_constraint(const zw_coeffs *c, zw_real coef_err,
                                               const zw_gains *g)
{
    zw_constraint k;
    const zw_real alpha = g->alpha.v, beta = g->beta.v;
    zw_real t3 = c->d12 * (ZW_R(0.5) * alpha);
    zw_real t4 = c->d12 * beta;
    k.lhs = t3 + t4;
    k.rhs = ZW_R(2.0) * (ZW_R(1.0) + c->e);
    k.err = (ZW_FABS(t3) + ZW_FABS(t4)) * (coef_err + ZW_U)
          + zw_coef_floor(c->d12) * (ZW_R(0.5) * ZW_FABS(alpha) + ZW_FABS(beta))
          + c->d12 * (ZW_R(0.5) * g->alpha.e + g->beta.e) + ZW_U * ZW_FABS(k.lhs)
          + ZW_R(2.0) * zw_coef_e_abserr(c) + ZW_U * k.rhs + ZW_R(3.0) * ZW_ETA;
    return k;
}

/* The checks on bounded gains (passed by pointer: small stack on soft-float MCUs). */
zw_status zw_check_bounded(zw_region region, const zw_coeffs *c, const zw_gains *g,
                           zw_verdict *out);

/* Jury test on p(r z) with bounded inputs. */
zw_status zw_radius_within_bounded(const zw_coeffs *c, const zw_gains *g, zw_real r,
                                   bool *within);

/* The general loop's guarded Routh test (loop.c), for another module's polynomial (box
 * certification's Kharitonov polynomials, box_loop.c): is w[0] s^n + ... + w[n] (absolute
 * error bounds we[], both overwritten) surely Hurwitz?  UNSTABLE is certain. */
typedef enum zw_hurwitz {
    ZW_HURWITZ_STABLE = 0,
    ZW_HURWITZ_UNSURE = 1,
    ZW_HURWITZ_UNSTABLE = 2
} zw_hurwitz;
zw_hurwitz zw_routh_hurwitz(zw_real w[], zw_real we[], unsigned n);

/* The fail-safe zw_plant (plant.h): order 0, which every consumer refuses, every number
 * NaN (plant.c; also plant_box.c's enclosures).  NULL: nothing. */
struct zw_plant;
void zw_plant_fail(struct zw_plant *out);

/* ---- polynomial building with running bounds (loop.c, plant.c) ---------------------- */

static inline zw_eb zw_eb_make(zw_real v, zw_real e)
{
    zw_eb r;
    r.v = v;
    r.e = e;
    return r;
}

/* Product whose error is exactly zero when both are exact and one of them is 0, +-1 or
 * +-2 (factors of that form are common and must not add rounding). */
static inline zw_eb zw_eb_mul_exactish(zw_eb a, zw_eb b)
{
    if ((a.e == ZW_R(0.0)) && (b.e == ZW_R(0.0))) {
        zw_real m = ZW_FABS(a.v) < ZW_FABS(b.v) ? ZW_FABS(a.v) : ZW_FABS(b.v);
        if ((m == ZW_R(0.0)) || (m == ZW_R(1.0)) || (m == ZW_R(2.0))) {
            return zw_eb_exact(a.v * b.v);
        }
    }
    return zw_eb_mul(a, b);
}

/* Sum whose error is the inputs' when one of them is an exact zero. */
static inline zw_eb zw_eb_add_exactish(zw_eb a, zw_eb b)
{
    if ((a.v == ZW_R(0.0)) && (a.e == ZW_R(0.0))) {
        return b;
    }
    if ((b.v == ZW_R(0.0)) && (b.e == ZW_R(0.0))) {
        return a;
    }
    return zw_eb_add(a, b);
}

/* v (degree deg, highest power first; error bounds e) *= f1 x + f0, in place; the result
 * has degree deg + 1 (v and e must hold deg + 2 entries). */
static inline void zw_eb_poly_mul_linear(zw_real v[], zw_real e[], unsigned deg, zw_eb f1,
                                         zw_eb f0)
{
    unsigned i;
    for (i = deg + 1u; i > 0u; --i) {
        zw_eb lo = zw_eb_mul_exactish(f0, zw_eb_make(v[i - 1u], e[i - 1u]));
        zw_eb hi = (i <= deg) ? zw_eb_mul_exactish(f1, zw_eb_make(v[i], e[i]))
                              : zw_eb_exact(ZW_R(0.0));
        zw_eb sum = zw_eb_add_exactish(hi, lo);
        v[i] = sum.v;
        e[i] = sum.e;
    }
    {
        zw_eb top = zw_eb_mul_exactish(f1, zw_eb_make(v[0], e[0]));
        v[0] = top.v;
        e[0] = top.e;
    }
}

#endif /* ZWIDTH_INTERNAL_H */
