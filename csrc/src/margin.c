/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Closed-loop poles: spectral radius by root finding, and "rho < r" by the Jury
 * conditions on p(r z) under a running error bound. */
#include "zwidth/margin.h"

#include <stddef.h>

#include "internal.h"

/* a[0] = a1, a[1] = a2, a[2] = a0 of p(z) = 2 z^3 + a1 z^2 + a2 z + a0 (the only place
 * they are formed):
 *   a1 = c1 (alpha + beta) - 2 (1 + e),  a2 = c2 alpha - d12 beta + 2 e,  a0 = -c2 beta
 * (c2 - c1 = -d12 is taken from the accurate d12).  With with_err, a_eb[i].e receives a
 * bound on the absolute error, given the gains' own bounds (else 0). */
static void char_poly(const zw_coeffs *c, const zw_gains *g, zw_eb a_eb[3], bool with_err)
{
    const zw_real alpha = g->alpha.v, beta = g->beta.v;
    zw_real sum = alpha + beta;
    zw_real t1 = c->c1 * sum, t2 = c->c2 * alpha, t3 = c->d12 * beta;
    zw_real one_plus_e = ZW_R(1.0) + c->e;
    a_eb[0] = zw_eb_exact(t1 - ZW_R(2.0) * one_plus_e);
    a_eb[1] = zw_eb_exact((t2 - t3) + ZW_R(2.0) * c->e);
    a_eb[2] = zw_eb_exact(-(c->c2 * beta));
    if (with_err) {
        /* relative part k; absolute part per unit of |alpha| + |beta| for a subnormal field
         * (c2 for huge delta; c1 > c2, and d12 matters only where it is normal) */
        const zw_real k = zw_coef_relerr(c) + ZW_U, e_err = zw_coef_e_abserr(c);
        const zw_real floor_mag = zw_coef_floor(c->c2 < c->d12 ? c->c2 : c->d12) *
                                  (ZW_FABS(alpha) + ZW_FABS(beta)) + ZW_R(3.0) * ZW_ETA;
        a_eb[0].e = ZW_FABS(t1) * k + c->c1 * (g->alpha.e + g->beta.e + ZW_U * ZW_FABS(sum)) +
                    ZW_R(2.0) * (e_err + ZW_U * one_plus_e) + ZW_U * ZW_FABS(a_eb[0].v) + floor_mag;
        a_eb[1].e = (ZW_FABS(t2) + ZW_FABS(t3)) * (k + ZW_U) + c->c2 * g->alpha.e +
                    c->d12 * g->beta.e + ZW_R(2.0) * e_err + ZW_U * ZW_FABS(a_eb[1].v) + floor_mag;
        a_eb[2].e = ZW_FABS(a_eb[2].v) * k + c->c2 * g->beta.e + floor_mag;
    }
}

static zw_status check_inputs(const zw_coeffs *c, zw_real alpha, zw_real beta)
{
    zw_status st;
    st = zw_require_coeffs(c, false);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_require_finite(alpha);
    if (st != ZW_OK) {
        return st;
    }
    return zw_require_finite(beta);
}

static zw_status char_poly_checked(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real p[4])
{
    zw_eb a[3];
    zw_gains g = zw_gains_exact(alpha, beta);
    zw_status st = check_inputs(c, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    if (p == NULL) {
        return ZW_ERR_NULL;
    }
    char_poly(c, &g, a, false);
    if (!ZW_IS_FINITE(a[0].v) || !ZW_IS_FINITE(a[1].v) || !ZW_IS_FINITE(a[2].v)) {
        return ZW_ERR_RANGE;
    }
    p[0] = ZW_R(2.0);
    p[1] = a[0].v;
    p[2] = a[1].v;
    p[3] = a[2].v;
    return ZW_OK;
}

zw_status zw_char_poly(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real p[4])
{
    zw_status st = char_poly_checked(c, alpha, beta, p);
    if (st != ZW_OK && p != NULL) {
        p[0] = ZW_NAN;
        p[1] = ZW_NAN;
        p[2] = ZW_NAN;
        p[3] = ZW_NAN;
    }
    return st;
}

/* ---- spectral radius --------------------------------------------------------------- */

/* Monic cubic z^3 + A z^2 + B z + C and its derivative at z. */
static zw_real cubic(zw_real A, zw_real B, zw_real C, zw_real z, zw_real *deriv)
{
    *deriv = (ZW_R(3.0) * z + ZW_R(2.0) * A) * z + B;
    return ((z + A) * z + B) * z + C;
}

/* A real root of the monic cubic: Newton's method kept inside a sign-change bracket
 * (bisection whenever a step leaves it or stalls), so it always converges. */
static zw_real real_root(zw_real A, zw_real B, zw_real C)
{
    zw_real bound = ZW_R(1.0) + ZW_FABS(A), lo, hi, z, f, df;
    int iter;
    if (ZW_FABS(B) + ZW_R(1.0) > bound) {
        bound = ZW_FABS(B) + ZW_R(1.0);
    }
    if (ZW_FABS(C) + ZW_R(1.0) > bound) {
        bound = ZW_FABS(C) + ZW_R(1.0);
    }
    lo = -bound; /* Cauchy: every root lies in [-bound, bound]; cubic(lo) < 0 < cubic(hi) */
    hi = bound;
    z = C > ZW_R(0.0) ? -ZW_R(1.0) : ZW_R(1.0); /* poles cluster near the unit circle */
    for (iter = 0; iter < 400; ++iter) {
        zw_real next, width = hi - lo;
        f = cubic(A, B, C, z, &df);
        if (f == ZW_R(0.0)) {
            return z;
        }
        if (f < ZW_R(0.0)) {
            lo = z;
        } else {
            hi = z;
        }
        next = df != ZW_R(0.0) ? z - f / df : lo + ZW_R(0.5) * width;
        if (!(next > lo && next < hi)) {
            next = lo + ZW_R(0.5) * (hi - lo);
        }
        if (next == z || hi - lo <= ZW_R(2.0) * ZW_U * (ZW_FABS(lo) + ZW_FABS(hi))) {
            return next;
        }
        z = next;
    }
    return z;
}

/* max |root| of z^2 + p z + q, by the cancellation-free formulas. */
static zw_real quadratic_radius(zw_real p, zw_real q)
{
    zw_real hp = ZW_R(0.5) * p, sd, big;
    zw_real disc_scaled; /* (hp^2 - q) / hp^2 when |hp| >= 1, else hp^2 - q */
    if (ZW_FABS(hp) >= ZW_R(1.0)) {
        disc_scaled = ZW_R(1.0) - (q / hp) / hp;
        if (disc_scaled < ZW_R(0.0)) { /* complex pair: |z|^2 = q */
            return ZW_SQRT(q);
        }
        sd = ZW_FABS(hp) * ZW_SQRT(disc_scaled);
    } else {
        disc_scaled = hp * hp - q;
        if (disc_scaled < ZW_R(0.0)) {
            return ZW_SQRT(q);
        }
        sd = ZW_SQRT(disc_scaled);
    }
    big = ZW_FABS(hp) + sd; /* |-hp - sign(hp) sd|, the larger root; the other is q / big */
    if (big == ZW_R(0.0)) {
        return ZW_R(0.0);
    }
    return big >= ZW_FABS(q) / big ? big : ZW_FABS(q) / big;
}

static zw_status spectral_radius(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real *rho)
{
    zw_eb a[3];
    zw_real A, B, C, r, p, q, rq; /* rq: largest modulus found so far */
    zw_gains g = zw_gains_exact(alpha, beta);
    zw_status st = check_inputs(c, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    if (rho == NULL) {
        return ZW_ERR_NULL;
    }
    char_poly(c, &g, a, false);
    A = ZW_R(0.5) * a[0].v;
    B = ZW_R(0.5) * a[1].v;
    C = ZW_R(0.5) * a[2].v;
    if (!ZW_IS_FINITE(A) || !ZW_IS_FINITE(B) || !ZW_IS_FINITE(C)) {
        return ZW_ERR_RANGE;
    }

    r = real_root(A, B, C);
    /* Deflate (z - r)(z^2 + p z + q): p = A + r errs by u (|A| + |r|), small against the
     * largest root, and q = -C / r inherits the relative accuracy of C and r.  (Forward
     * q = B + r p and backward p = (q - B) / r can each cancel catastrophically.) */
    p = A + r;
    q = r != ZW_R(0.0) ? -C / r : B;
    rq = quadratic_radius(p, q);
    if (ZW_FABS(r) > rq) {
        rq = ZW_FABS(r);
    }
    if (!ZW_IS_FINITE(rq)) {
        return ZW_ERR_RANGE;
    }
    *rho = rq;
    return ZW_OK;
}

zw_status zw_spectral_radius(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real *rho)
{
    zw_status st = spectral_radius(c, alpha, beta, rho);
    if (st != ZW_OK) {
        zw_fail_real(rho, ZW_INF);
    }
    return st;
}

/* ---- Jury test on p(r z) ------------------------------------------------------------- */

/* The four Jury conditions on q(z) = 2 z^3 + b2 z^2 + b1 z + b0, each required surely:
 * q(1) > 0, q(-1) < 0, |b0| < 2, 4 - b0^2 > |b0 b2 - 2 b1|.  Evaluated one at a time so
 * that few bounded values are live at once (MCU stack). */
static bool jury_surely(const zw_eb b[3])
{
    const zw_eb b2 = b[0], b1 = b[1], b0 = b[2];
    const zw_eb two = zw_eb_exact(ZW_R(2.0));
    const zw_eb zero = zw_eb_exact(ZW_R(0.0));
    zw_eb lhs, rhs;
    if (zw_eb_compare(zero, zw_eb_add(zw_eb_add(two, b2), zw_eb_add(b1, b0))) != ZW_CMP_LT) {
        return false;
    }
    if (zw_eb_compare(zw_eb_add(zw_eb_sub(b2, two), zw_eb_sub(b0, b1)), zero) != ZW_CMP_LT) {
        return false;
    }
    lhs = b0;
    lhs.v = ZW_FABS(b0.v);
    if (zw_eb_compare(lhs, two) != ZW_CMP_LT) {
        return false;
    }
    rhs = zw_eb_sub(zw_eb_exact(ZW_R(4.0)), zw_eb_mul(b0, b0));
    lhs = zw_eb_sub(zw_eb_mul(b0, b2), zw_eb_mul(two, b1));
    lhs.v = ZW_FABS(lhs.v);
    return zw_eb_compare(lhs, rhs) == ZW_CMP_LT;
}

static zw_status radius_within(const zw_coeffs *c, const zw_gains *g, zw_real r, bool *within)
{
    zw_eb b[3], r_eb;
    zw_status st = check_inputs(c, g->alpha.v, g->beta.v);
    if (st != ZW_OK) {
        return st;
    }
    if (within == NULL) {
        return ZW_ERR_NULL;
    }
    if (ZW_IS_NAN(r)) {
        return ZW_ERR_NAN;
    }
    if (!ZW_IS_FINITE(r) || !(r > ZW_R(0.0))) {
        return ZW_ERR_ARG;
    }
    char_poly(c, g, b, true);
    /* q(z) = p(r z) / r^3 = 2 z^3 + b[0] z^2 + b[1] z + b[2] */
    r_eb = zw_eb_exact(r);
    b[0] = zw_eb_div(b[0], r_eb);
    b[1] = zw_eb_div(zw_eb_div(b[1], r_eb), r_eb);
    b[2] = zw_eb_div(zw_eb_div(zw_eb_div(b[2], r_eb), r_eb), r_eb);
    *within = jury_surely(b);
    return ZW_OK;
}

zw_status zw_radius_within_bounded(const zw_coeffs *c, const zw_gains *g, zw_real r,
                                   bool *within)
{
    zw_status st = radius_within(c, g, r, within);
    if (st != ZW_OK) {
        zw_fail_bool(within);
    }
    return st;
}

zw_status zw_radius_within(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real r,
                           bool *within)
{
    zw_gains g = zw_gains_exact(alpha, beta);
    return zw_radius_within_bounded(c, &g, r, within);
}
