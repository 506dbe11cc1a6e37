/* Closed-loop poles: spectral radius by root finding, and "rho < r" by the Jury
 * conditions on p(r z) under a running error bound. */
#include "zwidth/margin.h"

#include <stddef.h>

#include "internal.h"

/* a1, a2, a0 of p(z) = 2 z^3 + a1 z^2 + a2 z + a0, with error bounds. */
static void char_poly_bounded(const zw_coeffs *c, zw_eb alpha, zw_eb beta, zw_eb *a1, zw_eb *a2,
                              zw_eb *a0)
{
    zw_eb c1 = zw_eb_coef(c, c->c1), c2 = zw_eb_coef(c, c->c2), d12 = zw_eb_coef(c, c->d12);
    zw_eb e = zw_eb_coef_e(c);
    zw_eb two = zw_eb_exact(ZW_R(2.0));
    /* a1 = c1 (alpha + beta) - 2 (1 + e) */
    *a1 = zw_eb_sub(zw_eb_mul(c1, zw_eb_add(alpha, beta)),
                    zw_eb_mul(two, zw_eb_add(zw_eb_exact(ZW_R(1.0)), e)));
    /* a2 = c2 alpha - d12 beta + 2 e   (c2 - c1 = -d12, taken from the accurate d12) */
    *a2 = zw_eb_add(zw_eb_sub(zw_eb_mul(c2, alpha), zw_eb_mul(d12, beta)), zw_eb_mul(two, e));
    /* a0 = -c2 beta */
    *a0 = zw_eb_mul(c2, beta);
    a0->v = -a0->v;
}

static zw_status check_inputs(const zw_coeffs *c, zw_real alpha, zw_real beta)
{
    zw_status st;
    if (c == NULL) return ZW_ERR_NULL;
    if ((st = zw_require_finite(alpha)) != ZW_OK) return st;
    if ((st = zw_require_finite(beta)) != ZW_OK) return st;
    return zw_require_finite(c->delta);
}

zw_status zw_char_poly(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real p[4])
{
    zw_eb a1, a2, a0;
    zw_status st = check_inputs(c, alpha, beta);
    if (st != ZW_OK) return st;
    if (p == NULL) return ZW_ERR_NULL;
    char_poly_bounded(c, zw_eb_exact(alpha), zw_eb_exact(beta), &a1, &a2, &a0);
    if (!ZW_IS_FINITE(a1.v) || !ZW_IS_FINITE(a2.v)) return ZW_ERR_RANGE;
    p[0] = ZW_R(2.0);
    p[1] = a1.v;
    p[2] = a2.v;
    p[3] = a0.v;
    return ZW_OK;
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
    if (ZW_FABS(B) + ZW_R(1.0) > bound) bound = ZW_FABS(B) + ZW_R(1.0);
    if (ZW_FABS(C) + ZW_R(1.0) > bound) bound = ZW_FABS(C) + ZW_R(1.0);
    lo = -bound; /* Cauchy: every root lies in [-bound, bound]; cubic(lo) < 0 < cubic(hi) */
    hi = bound;
    z = C > ZW_R(0.0) ? -ZW_R(1.0) : ZW_R(1.0); /* poles cluster near the unit circle */
    for (iter = 0; iter < 400; ++iter) {
        zw_real next, width = hi - lo;
        f = cubic(A, B, C, z, &df);
        if (f == ZW_R(0.0)) return z;
        if (f < ZW_R(0.0)) lo = z;
        else hi = z;
        next = df != ZW_R(0.0) ? z - f / df : lo + ZW_R(0.5) * width;
        if (!(next > lo && next < hi)) next = lo + ZW_R(0.5) * (hi - lo);
        if (next == z || hi - lo <= ZW_R(2.0) * ZW_U * (ZW_FABS(lo) + ZW_FABS(hi))) return next;
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
        if (disc_scaled < ZW_R(0.0)) return ZW_SQRT(q); /* complex pair: |z|^2 = q */
        sd = ZW_FABS(hp) * ZW_SQRT(disc_scaled);
    } else {
        disc_scaled = hp * hp - q;
        if (disc_scaled < ZW_R(0.0)) return ZW_SQRT(q);
        sd = ZW_SQRT(disc_scaled);
    }
    big = ZW_FABS(hp) + sd; /* |-hp - sign(hp) sd|, the larger root; the other is q / big */
    if (big == ZW_R(0.0)) return ZW_R(0.0);
    return big >= ZW_FABS(q) / big ? big : ZW_FABS(q) / big;
}

zw_status zw_spectral_radius(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real *rho)
{
    zw_eb a1, a2, a0;
    zw_real A, B, C, r, p, q, rq;
    zw_status st = check_inputs(c, alpha, beta);
    if (st != ZW_OK) return st;
    if (rho == NULL) return ZW_ERR_NULL;
    char_poly_bounded(c, zw_eb_exact(alpha), zw_eb_exact(beta), &a1, &a2, &a0);
    A = ZW_R(0.5) * a1.v;
    B = ZW_R(0.5) * a2.v;
    C = ZW_R(0.5) * a0.v;
    if (!ZW_IS_FINITE(A) || !ZW_IS_FINITE(B) || !ZW_IS_FINITE(C)) return ZW_ERR_RANGE;

    r = real_root(A, B, C);
    /* Deflate (z - r)(z^2 + p z + q): p = A + r errs by u (|A| + |r|), small against the
     * largest root, and q = -C / r inherits the relative accuracy of C and r.  (Forward
     * q = B + r p and backward p = (q - B) / r can each cancel catastrophically.) */
    p = A + r;
    q = r != ZW_R(0.0) ? -C / r : B;
    rq = quadratic_radius(p, q);
    *rho = ZW_FABS(r) > rq ? ZW_FABS(r) : rq;
    if (!ZW_IS_FINITE(*rho)) return ZW_ERR_RANGE;
    return ZW_OK;
}

/* ---- Jury test on p(r z) ------------------------------------------------------------- */

zw_status zw_radius_within_bounded(const zw_coeffs *c, zw_eb alpha, zw_eb beta, zw_real r,
                                   bool *within)
{
    zw_eb a1, a2, a0, b2, b1, b0, r_eb, two = zw_eb_exact(ZW_R(2.0)), four = zw_eb_exact(ZW_R(4.0));
    zw_eb zero = zw_eb_exact(ZW_R(0.0));
    zw_status st = check_inputs(c, alpha.v, beta.v);
    if (st != ZW_OK) return st;
    if (within == NULL) return ZW_ERR_NULL;
    if (ZW_IS_NAN(r)) return ZW_ERR_NAN;
    if (!ZW_IS_FINITE(r) || !(r > ZW_R(0.0))) return ZW_ERR_ARG;
    char_poly_bounded(c, alpha, beta, &a1, &a2, &a0);
    /* q(z) = p(r z) / r^3 = 2 z^3 + b2 z^2 + b1 z + b0 */
    r_eb = zw_eb_exact(r);
    b2 = zw_eb_div(a1, r_eb);
    b1 = zw_eb_div(zw_eb_div(a2, r_eb), r_eb);
    b0 = zw_eb_div(zw_eb_div(zw_eb_div(a0, r_eb), r_eb), r_eb);
    {
        /* Jury: q(1) > 0, q(-1) < 0, |b0| < 2, 4 - b0^2 > |b0 b2 - 2 b1|. */
        zw_eb q_plus = zw_eb_add(zw_eb_add(two, b2), zw_eb_add(b1, b0));
        zw_eb q_minus = zw_eb_add(zw_eb_sub(b2, two), zw_eb_sub(b0, b1));
        zw_eb abs_b0 = b0, lhs4 = zw_eb_sub(four, zw_eb_mul(b0, b0));
        zw_eb rhs4 = zw_eb_sub(zw_eb_mul(b0, b2), zw_eb_mul(two, b1));
        abs_b0.v = ZW_FABS(b0.v);
        rhs4.v = ZW_FABS(rhs4.v);
        *within = zw_eb_compare(zero, q_plus) == ZW_CMP_LT &&
                  zw_eb_compare(q_minus, zero) == ZW_CMP_LT &&
                  zw_eb_compare(abs_b0, two) == ZW_CMP_LT &&
                  zw_eb_compare(rhs4, lhs4) == ZW_CMP_LT;
    }
    return ZW_OK;
}

zw_status zw_radius_within(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real r,
                           bool *within)
{
    return zw_radius_within_bounded(c, zw_eb_exact(alpha), zw_eb_exact(beta), r, within);
}
