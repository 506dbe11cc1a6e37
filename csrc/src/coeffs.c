/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Coefficient functions c1, c2, d12 of paper eqs (3), (4), accurate for every delta.
 *
 * Below ZW_SERIES_LIMIT they are evaluated as e^-delta times power series whose terms are
 * all positive (so nothing cancels and Horner's rule is accurate to about an ulp):
 *   c1  = 2 e (delta e^delta - e^delta + 1) / delta^2 = e * sum (2 (k+1) / (k+2)!) delta^k
 *   c2  = 2 e (e^delta - 1 - delta) / delta^2        = e * sum (2 / (k+2)!) delta^k
 *   d12 = c1 - c2                         = e delta * sum (2 (k+1) / (k+3)!) delta^k
 * Above it the literal numerators lose at most a small factor (delta - (1-e) and
 * (1-e) - delta e are well away from cancellation for delta >= 2, and d12's numerator
 * (delta+2) e + (delta-2) is a sum of non-negative terms), and each is divided by delta
 * twice instead of by delta^2, which would overflow.
 */
#include "zwidth/coeffs.h"

#include <stddef.h>

#include "internal.h"

#ifdef ZW_REAL_FLOAT
/* Terms needed for a truncation error below u/10 at delta = 2. */
#define ZW_SERIES_TERMS 16
#else
#define ZW_SERIES_TERMS 24
#endif
#define ZW_SERIES_LIMIT ZW_R(2.0)

/* 2 (k+1) / (k+2)! */
static const zw_real k_series_p1[ZW_SERIES_TERMS] = {
    ZW_R(1.0), ZW_R(0.666666666666666666667), ZW_R(0.25),
    ZW_R(0.0666666666666666666667), ZW_R(0.0138888888888888888889), ZW_R(0.00238095238095238095238),
    ZW_R(0.000347222222222222222222), ZW_R(0.0000440917107583774250441), ZW_R(0.00000496031746031746031746),
    ZW_R(5.01042167708834375501e-7), ZW_R(4.59288653733098177543e-8), ZW_R(3.85417052083718750385e-9),
    ZW_R(2.9823938554097284256e-10), ZW_R(2.14120584490954861325e-11), ZW_R(1.43384319971621558923e-12),
    ZW_R(8.99666321390566644224e-14),
#ifndef ZW_REAL_FLOAT
    ZW_R(5.31053036931931699715e-15), ZW_R(2.9594286887847586981e-16), ZW_R(1.56192069685862264622e-17),
    ZW_R(7.82917642535650449234e-19), ZW_R(3.73665238482924078043e-20), ZW_R(1.7019948750775009766e-21),
    ZW_R(7.41399282704214440562e-23), ZW_R(3.09453613650454723017e-24),
#endif
};
/* 2 / (k+2)! */
static const zw_real k_series_p2[ZW_SERIES_TERMS] = {
    ZW_R(1.0), ZW_R(0.333333333333333333333), ZW_R(0.0833333333333333333333),
    ZW_R(0.0166666666666666666667), ZW_R(0.00277777777777777777778), ZW_R(0.000396825396825396825397),
    ZW_R(0.0000496031746031746031746), ZW_R(0.00000551146384479717813051), ZW_R(5.51146384479717813051e-7),
    ZW_R(5.01042167708834375501e-8), ZW_R(4.17535139757361979584e-9), ZW_R(3.21180876736432291988e-10),
    ZW_R(2.29414911954594494277e-11), ZW_R(1.52943274636396329518e-12), ZW_R(9.55895466477477059488e-14),
    ZW_R(5.6229145086910415264e-15),
#ifndef ZW_REAL_FLOAT
    ZW_R(3.12384139371724529244e-16), ZW_R(1.64412704932486594339e-17), ZW_R(8.22063524662432971696e-19),
    ZW_R(3.91458821267825224617e-20), ZW_R(1.77935827849011465735e-21), ZW_R(7.73634034126136807543e-23),
    ZW_R(3.2234751421922366981e-24), ZW_R(1.28939005687689467924e-25),
#endif
};
/* 2 (k+1) / (k+3)! */
static const zw_real k_series_p12[ZW_SERIES_TERMS] = {
    ZW_R(0.333333333333333333333), ZW_R(0.166666666666666666667), ZW_R(0.05),
    ZW_R(0.0111111111111111111111), ZW_R(0.00198412698412698412698), ZW_R(0.000297619047619047619048),
    ZW_R(0.0000385802469135802469136), ZW_R(0.00000440917107583774250441), ZW_R(4.50937950937950937951e-7),
    ZW_R(4.17535139757361979584e-8), ZW_R(3.53298964410075521187e-9), ZW_R(2.75297894345513393132e-10),
    ZW_R(1.98826257027315228373e-11), ZW_R(1.33825365306846788328e-12), ZW_R(8.4343717630365622896e-14),
    ZW_R(4.99814622994759246791e-15),
#ifndef ZW_REAL_FLOAT
    ZW_R(2.79501598385227210377e-16), ZW_R(1.47971434439237934905e-17), ZW_R(7.43771760408867926772e-19),
    ZW_R(3.5587165569802293147e-20), ZW_R(1.62463147166488729584e-21), ZW_R(7.09164531282292073581e-23),
    ZW_R(2.96559713081685776225e-24), ZW_R(1.19020620634790278084e-25),
#endif
};

static zw_real horner(const zw_real *coef, zw_real x)
{
    int k;
    zw_real acc = coef[ZW_SERIES_TERMS - 1];
    for (k = ZW_SERIES_TERMS - 2; k >= 0; --k) {
        acc = acc * x + coef[k];
    }
    return acc;
}

/* Smallest power of two >= delta, for delta > 1 (exact scaling, no rounding), capped at
 * the largest finite power of two. */
static zw_real power_of_two_above(zw_real delta)
{
    int exponent = 0;
    zw_real mantissa = ZW_FREXP(delta, &exponent); /* delta = mantissa 2^exponent, mantissa in [1/2, 1) */
    /* delta > 1 and finite: exponent is in [1, ZW_REAL_MAX_EXP].  The decrement is guarded
     * by exponent > 1 all the same, so that it cannot overflow whatever a frexp returned
     * (tools/eva.sh cannot know its range otherwise). */
    if ((mantissa == ZW_R(0.5)) && (exponent > 1)) { /* delta is itself a power of two */
        exponent -= 1;
    }
    if (exponent > (ZW_REAL_MAX_EXP - 1)) {
        exponent = ZW_REAL_MAX_EXP - 1;
    }
    return ZW_LDEXP(ZW_R(1.0), exponent);
}

zw_status zw_coeffs_init(zw_coeffs *out, zw_real delta)
{
    zw_coeffs c;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    if (ZW_IS_NAN(delta) || delta < ZW_R(0.0)) {
        zw_fail_coeffs(out);
        return ZW_IS_NAN(delta) ? ZW_ERR_NAN : ZW_ERR_DELTA;
    }

    c.delta = delta;
    c.delta_relerr = ZW_R(0.0);
    if (!ZW_IS_FINITE(delta)) { /* the delta -> inf limits */
        c.e = ZW_R(0.0);
        c.c1 = ZW_R(0.0);
        c.c2 = ZW_R(0.0);
        c.d12 = ZW_R(0.0);
        c.s = ZW_R(0.0);
        c.g = ZW_R(1.0);
        c.sigma = delta;
        c.hs = delta;
        *out = c;
        return ZW_OK;
    }
    c.e = ZW_EXP(-delta);
    if (delta == ZW_R(0.0)) {
        c.s = ZW_R(2.0);
    } else {
        zw_real one_minus_e = -ZW_EXPM1(-delta);
        c.s = (one_minus_e + one_minus_e) / delta;
    }
    c.sigma = delta > ZW_R(1.0) ? power_of_two_above(delta) : ZW_R(1.0);

    if (delta < ZW_SERIES_LIMIT) {
        c.c1 = c.e * horner(k_series_p1, delta);
        c.c2 = c.e * horner(k_series_p2, delta);
        c.d12 = (c.e * delta) * horner(k_series_p12, delta);
        c.hs = ZW_R(2.0) / c.c2 / c.sigma;
    } else {
        zw_real one_minus_e = -ZW_EXPM1(-delta);
        zw_real n2 = one_minus_e - delta * c.e;              /* delta^2 c2 / 2, in (0.59, 1) */
        zw_real t1 = (delta - one_minus_e) / delta;          /* delta c1 / 2 */
        zw_real t2 = n2 / delta;                             /* delta c2 / 2 */
        zw_real t12 = ((delta + ZW_R(2.0)) * c.e + (delta - ZW_R(2.0))) / delta;
        c.c1 = (t1 + t1) / delta;
        c.c2 = (t2 + t2) / delta;
        c.d12 = (t12 + t12) / delta;
        c.hs = (delta / c.sigma) * (delta / n2);             /* delta^2 / n2 / sigma, no overflow */
    }
    c.g = c.c1 / c.s;
    *out = c;
    return ZW_OK;
}

zw_status zw_coeffs_literal(zw_real delta, zw_real *c1, zw_real *c2, zw_real *d12)
{
    zw_real e, dd;
    zw_status st = ZW_OK;
    if (c1 == NULL || c2 == NULL || d12 == NULL) {
        st = ZW_ERR_NULL;
    } else if (ZW_IS_NAN(delta)) {
        st = ZW_ERR_NAN;
    } else if (delta < ZW_R(0.0)) {
        st = ZW_ERR_DELTA;
    } else {
        /* valid: st stays ZW_OK */
    }
    if (st != ZW_OK) {
        zw_fail_real(c1, ZW_NAN);
        zw_fail_real(c2, ZW_NAN);
        zw_fail_real(d12, ZW_NAN);
        return st;
    }
    if (delta == ZW_R(0.0) || !ZW_IS_FINITE(delta)) { /* 0/0 or inf/inf: give the limits */
        const zw_real limit = (delta == ZW_R(0.0)) ? ZW_R(1.0) : ZW_R(0.0);
        *c1 = limit;
        *c2 = limit;
        *d12 = ZW_R(0.0);
        return ZW_OK;
    }
    e = ZW_EXP(-delta);
    dd = delta * delta;
    *c1 = ZW_R(2.0) * (delta - ZW_R(1.0) + e) / dd;
    *c2 = ZW_R(2.0) * (ZW_R(1.0) - e - delta * e) / dd;
    *d12 = ZW_R(2.0) * ((delta + ZW_R(2.0)) * e + delta - ZW_R(2.0)) / dd;
    return ZW_OK;
}
