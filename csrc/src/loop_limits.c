/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Limits of the general loop by D-decomposition (loop_limits.h has the maths).
 *
 * Everything is a search for crossings of a straight line (beta fixed, alpha fixed, or
 * alpha = 0+) with the boundary curves, on the factored frequency response (R0, S) of the
 * loop.  A crossing is reported as (est, lo, hi): its estimate and an interval certain to
 * hold it, given an evaluation error bound eps (relative, per factor product) that covers
 * rounding and the coefficients' error; limits take the inner ends.  The cell a limit
 * bounds is labelled by the guarded zw_loop_check.
 */
#include "zwidth/loop_limits.h"

#include <stddef.h>

#include "internal.h"


#ifdef ZW_REAL_FLOAT
#define LL_ITER 40u    /* bisection / golden-section steps: enough for float's 24 bits */
#define LL_GEO 24u     /* geometric grid points towards 0 and pi */
#else
#define LL_ITER 80u
#define LL_GEO 44u
#endif

/* Inlined into its callers: a helper that only sequences two out-of-line calls, so that its
 * frame does not add to the scan's chain (the stack target of tools/footprint.sh). */
#if defined(__GNUC__)
#define LL_INLINE __attribute__((always_inline)) inline
#else
#define LL_INLINE
#endif

#define LL_PI ZW_R(3.14159265358979323846)
/* The largest zw_real below pi (float's nearest is above it: a grid point there would pass
 * beyond z = -1 and see the asymptote of a Tustin loop from the other side). */
#ifdef ZW_REAL_FLOAT
#define LL_PI_BELOW ZW_R(3.1415925)
#else
#define LL_PI_BELOW ZW_R(3.141592653589793)
#endif
#define LL_INVPHI ZW_R(0.6180339887498948482) /* golden section */
#define LL_GRID_PER_DEGREE 48u                 /* uniform theta grid points per degree */
#define LL_MAX_CROSSINGS (4u * ZW_LOOP_MAX_DEGREE + 8u) /* bound on the steps of a walk */
#define LL_CELL_CHECKS 7u                      /* interior checks of an alpha_max cell */
#define LL_EXT_GRID 24u                        /* beta grid before the golden section */
#define LL_EXT_GRID_N ZW_R(25.0)               /* its intervals: LL_EXT_GRID + 1 */

typedef struct ll_cplx {
    zw_real re, im;
} ll_cplx;

static ll_cplx cmul(ll_cplx a, ll_cplx b)
{
    ll_cplx r;
    r.re = a.re * b.re - a.im * b.im;
    r.im = a.re * b.im + a.im * b.re;
    return r;
}

/* a / b by Smith's method (no overflow or underflow of |b|^2); cdiv_inline inlined
 * (general_r0: no callee frame under it, the scan's stack chain), cdiv out of line. */
static ll_cplx cdiv(ll_cplx a, ll_cplx b);

/* The same, inlined (general_r0: no callee frame under it, the scan's stack chain). */
static LL_INLINE ll_cplx cdiv_inline(ll_cplx a, ll_cplx b)
{
    ll_cplx r;
    zw_real t, den;
    if (ZW_FABS(b.re) >= ZW_FABS(b.im)) {
        t = b.im / b.re;
        den = b.re + b.im * t;
        r.re = (a.re + a.im * t) / den;
        r.im = (a.im - a.re * t) / den;
    } else {
        t = b.re / b.im;
        den = b.im + b.re * t;
        r.re = (a.re * t + a.im) / den;
        r.im = (a.im * t - a.re) / den;
    }
    return r;
}

static ll_cplx cdiv(ll_cplx a, ll_cplx b)
{
    return cdiv_inline(a, b);
}

/* |z|_1 >= |z|: a cheap magnitude bound. */
static zw_real cabs1(ll_cplx a)
{
    return ZW_FABS(a.re) + ZW_FABS(a.im);
}

/* ---- the loop's factored frequency response ----------------------------------------- */

/* In the caller's workspace (loop.h) for the limits, a local for the plot functions:
 *   one_minus_e  1 - e = delta (c1 + c2) / 2, accurate for small delta
 *   r12          d12 / c1: (c1 z + c2) / c1 = (z + 1) - r12
 *   two_c1       2 / c1
 *   phase        d + 1/2
 *   one_minus_a  low-pass
 *   eps          relative error bound of R0 and S (and of the line coefficients)
 *   grid_h       uniform grid step in theta; grid_n its intervals */
typedef struct zw_loop_lim_plant ll_plant;

/* The loop's own consistency (loop.c keeps the same rule): degree matches the spec.  ws may
 * be NULL for the functions that run no check (the callers that do refuse it). */
static zw_status plant_init(ll_plant *p, const zw_loop *loop, zw_loop_workspace *ws)
{
    const zw_loop_spec *sp;
    unsigned est_deg;
    zw_real u = ZW_U, rel, filt;
    zw_status st;
    if (loop == NULL) {
        return ZW_ERR_NULL;
    }
    sp = &loop->spec;
    if (sp->delay > ZW_LOOP_MAX_DELAY) {
        return ZW_ERR_ARG;
    }
    if (sp->differentiator != ZW_DIFF_BACKWARD && sp->differentiator != ZW_DIFF_TUSTIN) {
        return ZW_ERR_ARG;
    }
    switch (sp->filter) {
    case ZW_VFILTER_NONE:
        est_deg = 1u;
        filt = ZW_R(0.0);
        break;
    case ZW_VFILTER_LOWPASS:
        if (!(sp->filter_pole >= ZW_R(0.0) && sp->filter_pole < ZW_R(1.0))) {
            return ZW_ERR_ARG;
        }
        est_deg = 1u;
        if (sp->differentiator == ZW_DIFF_TUSTIN) {
            est_deg = 2u;
        }
        filt = ZW_R(16.0) * u;
        break;
    case ZW_VFILTER_AVERAGE:
        if (sp->average < 1u || sp->average > ZW_LOOP_MAX_AVERAGE) {
            return ZW_ERR_ARG;
        }
        est_deg = sp->average;
        filt = (ZW_R(8.0) + ZW_R(4.0) * (zw_real)sp->average) * u;
        break;
    default: return ZW_ERR_ARG;
    }
    st = zw_require_coeffs(&loop->c, false);
    if (st != ZW_OK) {
        return st;
    }
    if ((loop->plant.order != 2u) && (loop->plant.order != 3u)) {
        return ZW_ERR_ARG;
    }
    if (loop->degree != loop->plant.order + sp->delay + est_deg) {
        return ZW_ERR_ARG;
    }
    p->loop = loop;
    p->ws = ws;
    p->phase = (zw_real)sp->delay + ZW_R(0.5);
    p->one_minus_a = ZW_R(1.0) - sp->filter_pole;
    p->grid_n = LL_GRID_PER_DEGREE * (loop->degree + 1u);
    p->grid_h = LL_PI / (zw_real)p->grid_n;
    p->general = (loop->plant.order != 2u) || !(loop->plant.spec.kappa == ZW_R(0.0));
    p->stiff = false;
    if (p->general != false) {
        const unsigned q = loop->plant.order;
        /* D(1) = D_s(0) = 0 exactly for kappa = 0: the integrating plant (D has the factor
         * z - 1 in exact arithmetic; the stored coefficient's bound is only an underflow floor) */
        p->stiff = !(loop->plant.spec.kappa == ZW_R(0.0)) || !(loop->plant.den_s[q] == ZW_R(0.0));
        p->one_minus_e = ZW_R(0.0);
        p->r12 = ZW_R(0.0);
        p->two_c1 = ZW_R(0.0);
        /* the part of every point's bound that is not the plant's (general_response adds
         * that): the phase and S as below, the products and quotients of R0 */
        p->eps = ZW_R(1.5) * (ZW_R(4.0) * (p->phase + ZW_R(1.0)) * u + ZW_R(32.0) * u + filt) + ZW_ETA;
        return ZW_OK;
    }
    if (!(loop->c.c1 > ZW_R(0.0))) {
        return ZW_ERR_RANGE;
    }
    p->one_minus_e = ZW_R(0.5) * (loop->c.s * loop->c.delta);
    p->r12 = loop->c.d12 / loop->c.c1;
    p->two_c1 = ZW_R(2.0) / loop->c.c1;
    if (!ZW_IS_FINITE(p->two_c1) || !ZW_IS_FINITE(p->one_minus_e)) {
        return ZW_ERR_RANGE;
    }
    /* z - e and (c1 z + c2)/c1 lose at most a factor 3 to cancellation (|z - e| >= 1 - e,
     * |z + 1 - r12| >= r12 on the circle); the phase e^{j(d+1/2)theta} errs by the
     * rounding of its argument; a few roundings for the products; 3/2 for slack. */
    rel = zw_coef_relerr(&loop->c);
    p->eps = ZW_R(1.5) * (ZW_R(3.0) * (rel + ZW_R(4.0) * u) + ZW_R(3.0) * (ZW_R(2.0) * rel + ZW_R(4.0) * u) +
                          rel + ZW_R(4.0) * (p->phase + ZW_R(1.0)) * u + ZW_R(16.0) * u + filt) +
             ZW_ETA;
    return ZW_OK;
}

/* The relative error bound of w = tan(theta/2) or its inverse from sin and cos of theta/2
 * (a few roundings of libm and the quotient, with room). */
#define LL_TAN_RELERR (ZW_R(8.0) * ZW_U)

/* sum_p c_p (j t)^p, c_p = a[deg - p] (rev false) or a[p] (rev true), with a bound on its
 * error: the coefficients' bounds, the roundings (powers, products, two sums: under
 * (2 deg + 2) u of sum |c_p| |t|^p) and t's own relative error LL_TAN_RELERR (under
 * 2 deg of it, times the same magnitude).  Out: *val, *err. */
ZW_NOINLINE static void eval_jt(const zw_real a[], const zw_real ae[], unsigned deg, bool rev,
                                zw_real t, ll_cplx *val, zw_real *err)
{
    zw_real pw = ZW_R(1.0), mag = ZW_R(0.0), cerr = ZW_R(0.0);
    unsigned k;
    val->re = ZW_R(0.0);
    val->im = ZW_R(0.0);
    for (k = 0u; k <= deg; ++k) {
        const unsigned i = rev ? k : deg - k;
        const zw_real term = a[i] * pw;
        switch (k % 4u) {
        case 0u: val->re += term; break;
        case 1u: val->im += term; break;
        case 2u: val->re -= term; break;
        default: val->im -= term; break;
        }
        mag += ZW_FABS(term);
        cerr += ae[i] * ZW_FABS(pw);
        pw *= t;
    }
    *err = (cerr + ((ZW_R(2.0) * (zw_real)deg + ZW_R(2.0)) * ZW_U +
                    ZW_R(2.0) * (zw_real)deg * LL_TAN_RELERR) * mag) * (ZW_R(1.0) + ZW_R(8.0) * ZW_U) +
           ZW_R(4.0) * ((zw_real)deg + ZW_R(1.0)) * ZW_ETA;
}

/* A lower bound of |v| (max of the parts: |v| >= it). */
static zw_real cabs_low(ll_cplx v)
{
    return ZW_FABS(v.re) > ZW_FABS(v.im) ? ZW_FABS(v.re) : ZW_FABS(v.im);
}

/* R0 = W / (2 j sin(theta/2)), W = -z^d D / N, of a general plant from its bilinear images
 * (plant.h) at s = j w, w = tan(theta/2): with (1 - jw) = e^{-j theta/2} / cos(theta/2),
 *     R0 = -e^{j (d + 1/2) theta} D_s(jw) / (2 jw N_s(jw)),
 * the jw dividing D_s's exact factor s for the integrating plant (D(1) = 0), or, for w > 1,
 * R0 = -e^{j (d + 1/2) theta} Drev(-jv) / (2 Nrev(-jv)) with v = 1/w and the reversed
 * polynomials (no overflow towards z = -1).  So z near 1 keeps the relative accuracy of the
 * images' coefficients, which evaluating D at a rounded e^{j theta} would lose.  Returns the
 * relative error bound of R0 (beyond p->eps), ZW_REAL_MAX where it cannot be bounded. */
ZW_NOINLINE static zw_real general_r0(const ll_plant *p, zw_real theta, ll_cplx *r0)
{
    const zw_plant *pl = &p->loop->plant;
    const unsigned q = pl->order;
    const zw_real sh = ZW_SIN(ZW_R(0.5) * theta), ch = ZW_COS(ZW_R(0.5) * theta);
    ll_cplx a, b, t;
    zw_real ea, eb, ra, rb;
    if (sh <= ch) {
        const zw_real w = sh / ch;
        eval_jt(pl->num_s, pl->num_s_err, q - 1u, false, w, &b, &eb);
        if (!p->stiff) {
            eval_jt(pl->den_s, pl->den_s_err, q - 1u, false, w, &a, &ea); /* D_s / s */
        } else {
            if (!(w > ZW_R(0.0))) {
                return ZW_REAL_MAX;
            }
            eval_jt(pl->den_s, pl->den_s_err, q, false, w, &t, &ea);
            a.re = t.im / w; /* D_s / (jw) */
            a.im = -t.re / w;
            ea = ea / w * (ZW_R(1.0) + ZW_R(2.0) * ZW_U);
        }
    } else {
        const zw_real v = ch / sh;
        eval_jt(pl->den_s, pl->den_s_err, q, true, -v, &a, &ea);
        eval_jt(pl->num_s, pl->num_s_err, q - 1u, true, -v, &b, &eb);
    }
    ra = ea / cabs_low(a);
    rb = eb / cabs_low(b);
    if (!(rb < ZW_R(0.5)) || !ZW_IS_FINITE(ra)) {
        return ZW_REAL_MAX;
    }
    t.re = ZW_COS(p->phase * theta); /* the phase e^{j (d + 1/2) theta} */
    t.im = ZW_SIN(p->phase * theta);
    t = cdiv_inline(cmul(t, a), b);
    r0->re = -ZW_R(0.5) * t.re;
    r0->im = -ZW_R(0.5) * t.im;
    /* |A~/B~ - A/B| <= (|A - A~| + |A~/B~| |B - B~|) / |B|, |B| >= |B~| (1 - rb) */
    return (ra + rb) / (ZW_R(1.0) - rb) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
}

/* R0 = e^{j theta/2} Q0 and S = e^{j theta/2} Vt at z = e^{j theta} (loop_limits.h), each
 * within p->eps relative; a general plant's R0 is general_r0's (not computed here). */
ZW_NOINLINE static void response(const ll_plant *p, zw_real theta, ll_cplx *r0, ll_cplx *s)
{
    const zw_loop_spec *sp = &p->loop->spec;
    zw_real sh = ZW_SIN(ZW_R(0.5) * theta), ch = ZW_COS(ZW_R(0.5) * theta);
    zw_real sin_t = ZW_R(2.0) * sh * ch, vers = ZW_R(2.0) * sh * sh; /* sin, 1 - cos */
    ll_cplx ze, cz, rot, f;
    if (!p->general) {
        rot.re = ZW_COS(p->phase * theta);
        rot.im = ZW_SIN(p->phase * theta);
        ze.re = p->one_minus_e - vers;
        ze.im = sin_t;
        cz.re = ZW_R(2.0) * ch * ch - p->r12;
        cz.im = sin_t;
        *r0 = cdiv(cmul(rot, ze), cz);
        r0->re *= -p->two_c1;
        r0->im *= -p->two_c1;
    } else {
        /* general_r0's (which the callers read only where it succeeded); written here so
         * that R0 is defined on every path, as the analysis (docs/eva.md) can see */
        r0->re = ZW_R(0.0);
        r0->im = ZW_R(0.0);
    }
    if (sp->differentiator == ZW_DIFF_TUSTIN) {
        s->re = ZW_R(1.0) / ch;
        s->im = ZW_R(0.0);
    } else {
        s->re = ch;
        s->im = -sh;
    }
    if (sp->filter == ZW_VFILTER_LOWPASS) {
        ll_cplx z, za;
        z.re = ZW_R(1.0) - vers;
        z.im = sin_t;
        za.re = p->one_minus_a - vers;
        za.im = sin_t;
        f = cdiv(z, za);
        f.re *= p->one_minus_a;
        f.im *= p->one_minus_a;
        *s = cmul(*s, f);
    } else if (sp->filter == ZW_VFILTER_AVERAGE) {
        zw_real n = (zw_real)sp->average;
        zw_real dn = sh == ZW_R(0.0) ? ZW_R(1.0) : ZW_SIN(ZW_R(0.5) * n * theta) / (n * sh);
        zw_real ang = -ZW_R(0.5) * (n - ZW_R(1.0)) * theta;
        f.re = dn * ZW_COS(ang);
        f.im = dn * ZW_SIN(ang);
        *s = cmul(*s, f);
    } else {
        /* backward or Tustin alone */
    }
}

/* R0 and S at theta (response, general_r0) and their relative error bound: p->eps, plus the
 * plant's for a general one; ZW_REAL_MAX where that cannot be bounded. */
static LL_INLINE zw_real response_eps(const ll_plant *p, zw_real theta, ll_cplx *r0, ll_cplx *s)
{
    zw_real e;
    response(p, theta, r0, s);
    if (!p->general) {
        return p->eps;
    }
    e = general_r0(p, theta, r0);
    return (e >= ZW_REAL_MAX) ? ZW_REAL_MAX : p->eps + ZW_R(1.5) * e;
}

/* ---- crossing conditions --------------------------------------------------------------- */

/* modes (ll_scan.mode) */
#define LL_FIX_BETA 0u   /* f = Re R0 - beta Re S,  value alpha = -2 sin(theta/2) Im(R0 - beta S) */
#define LL_FIX_ALPHA 1u  /* f = -2 sin(theta/2) Im(R0 conj S) - alpha Re S,  value beta = Re R0 / Re S */
#define LL_ALPHA_ZERO 2u /* f = Im(R0 conj S),  value beta = Re R0 / Re S */

/* which crossing a scan keeps (ll_scan.take) */
#define LL_TAKE_MIN_LO 0u     /* the least lower bound above floor */
#define LL_TAKE_NEXT_ABOVE 1u /* the least estimate above floor */

/* In the caller's workspace (loop.h): fixed is beta (FIX_BETA) or alpha (FIX_ALPHA);
 * found, est, lo, hi the crossing kept; degenerate: the z = -1 line is the search line. */
typedef struct zw_loop_lim_scan ll_scan;
typedef struct zw_loop_lim_walk ll_walk;
typedef struct zw_loop_lim_ext ll_ext;

/* The workspace holds the cells of a walk in arrays of 4 (loop.h). */
#if ZW_LOOP_MAX_INTERVALS != 4u
#error "zw_loop_workspace.lim_walk's cell arrays must have ZW_LOOP_MAX_INTERVALS entries"
#endif

typedef struct zw_loop_lim_point ll_point;

/* theta -> 0+ on a stiff plant, where R0 grows like 1 / theta: the limits of f and of the
 * value, from D_s = d0 + d1 s + ..., N_s = n0 + n1 s + ... (s = j w, theta = 2w + O(w^3),
 * the phase e^{j phi theta}, phi = d + 1/2):
 *     Re R0 -> -(phi d0 / n0 + (d1 - d0 n1 / n0) / (2 n0)),   -2 sin(theta/2) Im R0 -> -d0 / n0
 * (alpha = -d0 / n0 = -kappa is the z = 1 line), S -> Vt(1) (real).  With error bounds. */
ZW_NOINLINE static void stiff_origin(const ll_scan *x, ll_point *pt)
{
    const zw_plant *pl = &x->p->loop->plant;
    const unsigned q = pl->order;
    zw_eb d0, d1, n0, n1, re_r0, a_line, t;
    const zw_eb sre = zw_eb_exact(ZW_R(1.0)); /* S(0) = Vt(1) = 1: every estimate is exact on a ramp */
    d0.v = pl->den_s[q];
    d0.e = pl->den_s_err[q];
    d1.v = pl->den_s[q - 1u];
    d1.e = pl->den_s_err[q - 1u];
    n0.v = pl->num_s[q - 1u];
    n0.e = pl->num_s_err[q - 1u];
    n1.v = (q >= 2u) ? pl->num_s[q - 2u] : ZW_R(0.0);
    n1.e = (q >= 2u) ? pl->num_s_err[q - 2u] : ZW_R(0.0);
    a_line = zw_eb_div(d0, n0); /* kappa */
    t = zw_eb_sub(d1, zw_eb_mul(a_line, n1));
    t = zw_eb_div(t, zw_eb_mul(zw_eb_exact(ZW_R(2.0)), n0));
    re_r0 = zw_eb_add(zw_eb_mul(zw_eb_exact(x->p->phase), a_line), t);
    re_r0.v = -re_r0.v;
    pt->theta = ZW_R(0.0);
    if (x->mode == LL_FIX_BETA) {
        t = zw_eb_sub(re_r0, zw_eb_mul(zw_eb_exact(x->fixed), sre));
        pt->f = t.v;
        pt->f_err = t.e;
        pt->v = -a_line.v;
        pt->v_err = a_line.e + ZW_R(2.0) * ZW_U * ZW_FABS(a_line.v) + ZW_ETA;
    } else {
        /* FIX_ALPHA (the stiff plant's alpha = 0+ walk uses it too): f -> (-kappa - alpha) S */
        t = zw_eb_mul(zw_eb_add(a_line, zw_eb_exact(x->mode == LL_FIX_ALPHA ? x->fixed : ZW_R(0.0))), sre);
        pt->f = -t.v;
        pt->f_err = t.e;
        t = zw_eb_div(re_r0, sre);
        pt->v = t.v;
        pt->v_err = t.e;
    }
    if (!ZW_IS_FINITE(pt->f) || !ZW_IS_FINITE(pt->f_err)) {
        pt->f = ZW_R(0.0);
        pt->f_err = ZW_REAL_MAX;
    }
    if (!ZW_IS_FINITE(pt->v) || !ZW_IS_FINITE(pt->v_err)) {
        pt->v_err = ZW_REAL_MAX;
    }
}

static void eval_point(const ll_scan *x, zw_real theta, ll_point *pt)
{
    ll_cplx r0, s;
    zw_real a0, as, eps, two_sh;
    if (x->p->stiff && !(theta > ZW_R(0.0))) {
        stiff_origin(x, pt);
        return;
    }
    eps = response_eps(x->p, theta, &r0, &s);
    if (!(eps < ZW_REAL_MAX)) {
        pt->theta = theta;
        pt->f = ZW_R(0.0);
        pt->f_err = ZW_REAL_MAX;
        pt->v = ZW_R(0.0);
        pt->v_err = ZW_REAL_MAX;
        return;
    }
    a0 = cabs1(r0);
    as = cabs1(s);
    two_sh = ZW_R(2.0) * ZW_SIN(ZW_R(0.5) * theta);
    pt->theta = theta;
    if (x->mode == LL_FIX_BETA) {
        zw_real b = x->fixed, mag = a0 + ZW_FABS(b) * as;
        pt->f = r0.re - b * s.re;
        pt->f_err = eps * mag + ZW_ETA;
        pt->v = -two_sh * (r0.im - b * s.im);
        pt->v_err = two_sh * (eps * mag) + ZW_R(4.0) * ZW_U * ZW_FABS(pt->v) + ZW_ETA;
    } else {
        zw_real cross = r0.im * s.re - r0.re * s.im; /* Im(R0 conj S) */
        zw_real den = ZW_FABS(s.re) - eps * as;
        if (x->mode == LL_FIX_ALPHA) {
            pt->f = -two_sh * cross - x->fixed * s.re;
            pt->f_err = two_sh * (ZW_R(2.0) * eps * a0 * as) + x->fixed * (eps * as) + ZW_R(4.0) * ZW_U * (two_sh * ZW_FABS(cross)) + ZW_ETA;
        } else {
            pt->f = cross;
            pt->f_err = ZW_R(2.0) * eps * a0 * as + ZW_ETA;
        }
        pt->v = r0.re / s.re;
        pt->v_err = den > ZW_R(0.0)
                        ? (eps * a0 + ZW_FABS(pt->v) * eps * as) / den + ZW_R(4.0) * ZW_U * ZW_FABS(pt->v) + ZW_ETA
                        : ZW_REAL_MAX;
    }
    if (!ZW_IS_FINITE(pt->v) || !ZW_IS_FINITE(pt->v_err)) {
        pt->v_err = ZW_REAL_MAX;
    }
}

static bool is_neg(zw_real f)
{
    return f < ZW_R(0.0);
}

static bool certain(const ll_point *pt)
{
    return ZW_FABS(pt->f) > pt->f_err;
}

static void offer(ll_scan *x, zw_real est, zw_real lo, zw_real hi)
{
    if (x->take == LL_TAKE_MIN_LO) {
        if (hi > x->floor && (!x->found || lo < x->lo)) {
            x->found = true;
            x->est = est;
            x->lo = lo;
            x->hi = hi;
        }
    } else if (est > x->floor && (!x->found || est < x->est)) {
        x->found = true;
        x->est = est;
        x->lo = lo;
        x->hi = hi;
    } else {
        /* not wanted */
    }
}

/* A root of the crossing condition between theta_lo and theta_hi (certified: f's sign is
 * certain on both sides).  Roots the evaluation cannot resolve next to the structural zeros
 * of the condition are dropped: at theta = pi (modes FIX_ALPHA, ALPHA_ZERO: there Re S and
 * Im(R0 conj S) vanish together, the value is 0/0, and the crossing is the z = -1 line's,
 * offered separately; FIX_BETA: a sign change through the asymptote of Tustin or of
 * delta = 0 at z = -1, where the value is unbounded) and at theta = 0 (ALPHA_ZERO: the double root at z = 1, offered
 * separately as theta = 0). */
static void offer_root(ll_scan *x, zw_real theta_lo, zw_real theta_hi, bool certified,
                       zw_real est, zw_real lo, zw_real hi)
{
    bool unbounded = !(lo > -ZW_REAL_MAX && hi < ZW_REAL_MAX);
    if (unbounded && theta_hi > LL_PI - x->p->grid_h) {
        return;
    }
    if (x->mode == LL_ALPHA_ZERO && !certified && theta_lo < x->p->grid_h) {
        return;
    }
    offer(x, est, lo, hi);
}

/* Widen [lo, hi] by the value bounds at pt. */
static void widen(const ll_point *pt, zw_real *lo, zw_real *hi)
{
    zw_real l = pt->v - pt->v_err, h = pt->v + pt->v_err;
    if (pt->v_err >= ZW_REAL_MAX) {
        l = -ZW_REAL_MAX;
        h = ZW_REAL_MAX;
    }
    if (l < *lo) {
        *lo = l;
    }
    if (h > *hi) {
        *hi = h;
    }
}

/* A root of f between a and b (f(a), f(b) of opposite computed signs): bisect, then step
 * outwards to the nearest points where f's sign is certain (the exact root lies between
 * them), and offer the value there with its bounds.  One point at a time (small stack). */
static void refine(ll_scan *x, zw_real a0, zw_real b0)
{
    ll_point *pt = x->pt;
    bool neg_a, certified;
    zw_real a = a0, b = b0, h, t, lo, hi, est, th_lo, th_hi;
    unsigned it;
    eval_point(x, a, pt);
    neg_a = is_neg(pt->f);
    for (it = 0u; it < LL_ITER; ++it) {
        zw_real m = a + ZW_R(0.5) * (b - a);
        if (!(m > a && m < b)) {
            break;
        }
        eval_point(x, m, pt);
        if (is_neg(pt->f) == neg_a) {
            a = m;
        } else {
            b = m;
        }
    }
    eval_point(x, a + ZW_R(0.5) * (b - a), pt);
    est = pt->v;
    lo = pt->v;
    hi = pt->v;
    widen(pt, &lo, &hi);
    h = b - a;
    t = a;
    for (it = 0u; it < LL_ITER; ++it) {
        t = a - h > a0 ? a - h : a0;
        eval_point(x, t, pt);
        if ((certain(pt) && is_neg(pt->f) == neg_a) || !(t > a0)) {
            break;
        }
        h *= ZW_R(4.0);
    }
    certified = certain(pt);
    th_lo = t;
    widen(pt, &lo, &hi);
    h = b - a;
    t = b;
    for (it = 0u; it < LL_ITER; ++it) {
        t = b + h < b0 ? b + h : b0;
        eval_point(x, t, pt);
        if ((certain(pt) && is_neg(pt->f) != neg_a) || !(t < b0)) {
            break;
        }
        h *= ZW_R(4.0);
    }
    certified = certified && certain(pt);
    th_hi = t;
    widen(pt, &lo, &hi);
    offer_root(x, th_lo, th_hi, certified, est, lo, hi);
}

/* f keeps its sign at a, m, b but |f(m)| is a local minimum of the grid: look for a hidden
 * pair of roots by golden-section minimisation of sign * f on [a, b]. */
static void hidden_pair(ll_scan *x, zw_real a_start, zw_real m, zw_real b_start)
{
    ll_point *pt = x->pt;
    bool neg;
    zw_real a = a_start, b = b_start, c, d, fc, fd, best_t, best_f, lo, hi;
    unsigned it;
    eval_point(x, m, pt);
    neg = is_neg(pt->f);
    best_t = m;
    best_f = ZW_FABS(pt->f);
    c = b - LL_INVPHI * (b - a);
    d = a + LL_INVPHI * (b - a);
    eval_point(x, c, pt);
    fc = pt->f;
    eval_point(x, d, pt);
    fd = pt->f;
    for (it = 0u; it < LL_ITER && d > c; ++it) {
        if (is_neg(fc) != neg || is_neg(fd) != neg) {
            break;
        }
        if (ZW_FABS(fc) < best_f) {
            best_f = ZW_FABS(fc);
            best_t = c;
        }
        if (ZW_FABS(fd) < best_f) {
            best_f = ZW_FABS(fd);
            best_t = d;
        }
        if (ZW_FABS(fc) < ZW_FABS(fd)) {
            b = d;
            d = c;
            fd = fc;
            c = b - LL_INVPHI * (b - a);
            eval_point(x, c, pt);
            fc = pt->f;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + LL_INVPHI * (b - a);
            eval_point(x, d, pt);
            fd = pt->f;
        }
    }
    if (is_neg(fc) != neg || is_neg(fd) != neg) {
        zw_real t = is_neg(fc) != neg ? c : d;
        refine(x, a < t ? a : t, t);
        refine(x, t, b > t ? b : t);
        return;
    }
    eval_point(x, best_t, pt);
    if (!certain(pt)) {
        /* a near-tangency within the rounding band: keep it as a crossing, with the values
         * over the whole bracket */
        lo = pt->v;
        hi = pt->v;
        widen(pt, &lo, &hi);
        eval_point(x, a, pt);
        widen(pt, &lo, &hi);
        eval_point(x, b, pt);
        widen(pt, &lo, &hi);
        offer_root(x, a, b, false, lo + ZW_R(0.5) * (hi - lo), lo, hi);
    }
}

/* The j-th grid angle: LL_GEO points geometrically towards 0, the uniform grid, LL_GEO
 * points geometrically towards pi (0 and pi themselves are structural roots). */
static zw_real grid_theta(const ll_plant *p, unsigned j)
{
    unsigned n = p->grid_n;
    if (j < LL_GEO) {
        return ZW_LDEXP(p->grid_h, (int)j - (int)LL_GEO);
    }
    if (j < LL_GEO + n - 1u) {
        return ((zw_real)j - (zw_real)LL_GEO + ZW_R(1.0)) * p->grid_h;
    }
    return LL_PI_BELOW - ZW_LDEXP(p->grid_h, (int)LL_GEO + (int)n - (int)j - 2);
}

/* Every crossing in (0, pi) offered to x.  On a vertical line the scan starts at theta = 0
 * itself: there the condition is -(delta + beta) (the double root at z = 1), and a crossing
 * below the first grid angle has alpha near 0; where its sign is uncertain (beta within
 * the error of -delta, where the region's corner is) a crossing at alpha = 0 is assumed. */
static void scan(ll_scan *x)
{
    ll_point *pt = x->pt;
    zw_real t2, t1, f2, f1;
    unsigned j, total = 2u * LL_GEO + x->p->grid_n - 1u;
    t1 = grid_theta(x->p, 0u);
    eval_point(x, t1, pt);
    f1 = pt->f;
    if (x->mode == LL_FIX_BETA) {
        zw_real v1 = pt->v + pt->v_err, v1_lo = pt->v - pt->v_err;
        eval_point(x, ZW_R(0.0), pt);
        if (!certain(pt) && x->p->stiff) {
            /* the corner on the z = 1 line alpha = -kappa: a crossing between there and the
             * first grid angle's value */
            zw_real lo = pt->v - pt->v_err, hi = pt->v + pt->v_err;
            offer(x, pt->v, lo < v1_lo ? lo : v1_lo, hi > v1 ? hi : v1);
        } else if (!certain(pt)) {
            offer(x, ZW_R(0.0), ZW_R(0.0), v1);
        } else if (is_neg(pt->f) != is_neg(f1)) {
            refine(x, ZW_R(0.0), t1);
        } else {
            /* no crossing below the first grid angle */
        }
    }
    t2 = t1;
    f2 = f1;
    for (j = 1u; j < total; ++j) {
        zw_real t0 = grid_theta(x->p, j), f0;
        eval_point(x, t0, pt);
        f0 = pt->f;
        if (is_neg(f0) != is_neg(f1)) {
            refine(x, t1, t0);
        } else if (j >= 2u && is_neg(f2) == is_neg(f1) && ZW_FABS(f1) < ZW_FABS(f2) &&
                   ZW_FABS(f1) <= ZW_FABS(f0)) {
            hidden_pair(x, t2, t1, t0);
        } else {
            /* nothing between t1 and t0 */
        }
        t2 = t1;
        f2 = f1;
        t1 = t0;
        f1 = f0;
    }
}

/* ---- the z = -1 line ------------------------------------------------------------------- */

/* c0 + ca alpha + cb beta = 0 with a relative error bound rel of each coefficient:
 * p(-1) / (c1 z + c2 at -1) scaled by Dv(-1) / Nv(-1) as pair (dv, nv) up to a factor. */
static void line_minus1(const ll_plant *p, zw_real *c0, zw_real *ca, zw_real *cb, zw_real *rel)
{
    const zw_loop_spec *sp = &p->loop->spec;
    const zw_coeffs *c = &p->loop->c;
    const zw_plant *pl = &p->loop->plant;
    zw_real nv = ZW_R(2.0), dv = ZW_R(1.0); /* backward: V(-1) = 2 */
    zw_real sign = (sp->delay % 2u) == 0u ? ZW_R(1.0) : ZW_R(-1.0);
    if (sp->differentiator == ZW_DIFF_TUSTIN) {
        nv = ZW_R(1.0);
        dv = ZW_R(0.0); /* V has its pole at z = -1 */
    }
    if (sp->filter == ZW_VFILTER_LOWPASS) {
        nv *= p->one_minus_a;
        dv *= ZW_R(1.0) + sp->filter_pole;
    } else if (sp->filter == ZW_VFILTER_AVERAGE) {
        if ((sp->average % 2u) == 0u) {
            nv = ZW_R(0.0);
        }
        dv *= (zw_real)sp->average;
    } else {
        /* no filter */
    }
    if (p->general != false) {
        /* D(-1) = (-1)^q den_s[0], N(-1) = (-1)^(q-1) num_s[0] (z = -1 is s = infinity):
         * p(-1) = (-1)^d D(-1) Dv(-1) + N(-1) (alpha Dv(-1) + beta Nv(-1)), times (-1)^q */
        const zw_real d = pl->den_s[0], n = pl->num_s[0];
        *c0 = sign * d * dv;
        *ca = -n * dv;
        *cb = -n * nv;
        *rel = (pl->den_s_err[0] / ZW_FABS(d) + pl->num_s_err[0] / ZW_FABS(n)) + ZW_R(8.0) * ZW_U;
        if (!ZW_IS_FINITE(*rel)) {
            *rel = ZW_REAL_MAX;
        }
        return;
    }
    *c0 = -ZW_R(4.0) * sign * (ZW_R(1.0) + c->e) * dv;
    *ca = c->d12 * dv;
    *cb = c->d12 * nv;
    *rel = ZW_R(2.0) * zw_coef_relerr(c) + ZW_R(8.0) * ZW_U + zw_coef_floor(c->d12);
}

/* The z = -1 crossing of the current line, offered to x (no crossing: nothing offered;
 * *degenerate set when the line is the boundary itself within the error bound). */
static void offer_line(ll_scan *x, bool *degenerate)
{
    zw_real c0, ca, cb, rel, num, num_mag, den, v, err;
    line_minus1(x->p, &c0, &ca, &cb, &rel);
    *degenerate = false;
    if (x->mode == LL_FIX_BETA) { /* alpha = -(c0 + cb beta) / ca */
        num = c0 + cb * x->fixed;
        num_mag = ZW_FABS(c0) + ZW_FABS(cb * x->fixed);
        den = ca;
    } else {
        zw_real a = x->mode == LL_FIX_ALPHA ? x->fixed : ZW_R(0.0);
        num = c0 + ca * a;
        num_mag = ZW_FABS(c0) + ZW_FABS(ca * a);
        den = cb;
    }
    if (ZW_FABS(den) <= rel * ZW_FABS(den) + ZW_ETA) {
        /* the line is parallel to the search line: a crossing everywhere or nowhere */
        if (ZW_FABS(num) <= ZW_R(2.0) * rel * num_mag + ZW_ETA) {
            *degenerate = true;
        }
        return;
    }
    v = -num / den;
    err = ZW_R(2.0) * rel * (num_mag / ZW_FABS(den) + ZW_FABS(v)) + ZW_R(4.0) * ZW_U * ZW_FABS(v) + ZW_ETA;
    if (!ZW_IS_FINITE(v) || !ZW_IS_FINITE(err)) {
        return;
    }
    offer(x, v, v - err, v + err);
}

/* ---- alpha_max ------------------------------------------------------------------------- */

/* Every function from here on keeps its state in the workspace (ws->lim_*), not in its
 * frame: the guarded check (zw_loop_check, ~450 B on the Cortex-M4F) runs under them, and
 * the 512 B are for the whole chain.  The scan (offer_line, scan and below) runs
 * to completion before any check, so its frames are not on the check's chain. */

/* zw_loop_is_stable: zw_loop_check's verdict, without the deciding boundary's root run. */
static bool checked_stable(zw_loop_workspace *ws, zw_real alpha, zw_real beta)
{
    ws->lim_stable = false;
    return zw_loop_is_stable(ws->lim_plant.loop, ws, alpha, beta, &ws->lim_stable) == ZW_OK &&
           ws->lim_stable;
}

/* The crossings of the line set up in ws->lim_scan (the z = -1 line's, then the scan's);
 * nothing scanned when the line is the z = -1 boundary itself (lim_scan.degenerate). */
ZW_NOINLINE static void scan_line(ll_scan *x)
{
    offer_line(x, &x->degenerate);
    if (!x->degenerate) {
        scan(x);
    }
}

static void scan_setup(zw_loop_workspace *ws, unsigned mode, zw_real fixed, unsigned take,
                       zw_real above)
{
    ll_scan *x = &ws->lim_scan;
    x->p = &ws->lim_plant;
    x->pt = &ws->lim_pt;
    x->mode = mode;
    x->fixed = fixed;
    x->take = take;
    x->floor = above;
    x->found = false;
    x->degenerate = false;
    x->est = ZW_R(0.0);
    x->lo = ZW_R(0.0);
    x->hi = ZW_R(0.0);
}

/* The k-th of the interior points of the cell (0, a1 = lim_scan.lo) is stable.  Out of
 * line: its float temporaries stay out of alpha_max_of's frame. */
ZW_NOINLINE static bool cell_point_stable(zw_loop_workspace *ws, unsigned k)
{
    const ll_scan *x = &ws->lim_scan;
    zw_real t = x->lo * ((zw_real)k / ((zw_real)LL_CELL_CHECKS + ZW_R(1.0)));
    return checked_stable(ws, t, x->fixed);
}

/* ws->lim_amax = the certified alpha_max at beta (0 when nothing is certified). */
ZW_NOINLINE static void alpha_max_of(zw_loop_workspace *ws, zw_real beta)
{
    const ll_scan *x = &ws->lim_scan;
    zw_loop_verdict v;
    unsigned k;
    ws->lim_amax = ZW_R(0.0);
    scan_setup(ws, LL_FIX_BETA, beta, LL_TAKE_MIN_LO, ZW_R(0.0));
    scan_line(&ws->lim_scan);
    if (x->degenerate) {
        return;
    }
    /* No crossing above 0: the half-line alpha > 0 is one cell, and it is unstable (d + 2
     * roots go to infinity with alpha), so nothing is certified. */
    if (!x->found) {
        return;
    }
    if (!(x->lo > ZW_R(0.0))) {
        return;
    }
    /* the cell (0, a1 = x->lo): every interior point must check stable, a1 itself not
     * unstable (the checks leave ws->lim_scan alone) */
    for (k = 1u; k <= LL_CELL_CHECKS; ++k) {
        if (!cell_point_stable(ws, k)) {
            return;
        }
    }
    if (zw_loop_check(ws->lim_plant.loop, ws, x->lo, x->fixed, &v) == ZW_OK && !v.stable &&
        !v.marginal) {
        return;
    }
    ws->lim_amax = x->lo;
}

zw_status zw_loop_alpha_max(const zw_loop *loop, zw_loop_workspace *ws, zw_real beta,
                            zw_real *alpha_max)
{
    zw_status st;
    if (alpha_max == NULL) {
        return ZW_ERR_NULL;
    }
    *alpha_max = ZW_R(0.0);
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = plant_init(&ws->lim_plant, loop, ws);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_require_finite(beta);
    if (st != ZW_OK) {
        return st;
    }
    alpha_max_of(ws, beta);
    *alpha_max = ws->lim_amax;
    return ZW_OK;
}

/* ---- walks along a horizontal line ----------------------------------------------------- */

/* A walk visits the crossings of the line alpha = const (mode FIX_ALPHA) or alpha = 0+
 * (ALPHA_ZERO) in increasing beta; the caller labels each gap between two crossings (a
 * cell) and walk_record keeps the stable ones in ws->lim_walk.  ALPHA_ZERO labels a cell by
 * alpha_max(mid) > 0 (stable just above alpha = 0), FIX_ALPHA by the check at mid.
 * outer[0], outer[1]: the far bounds of the crossings that open the first and close the
 * last stable cell (the exact ends lie between them and the cell's certified ends). */
static void walk_begin(ll_walk *w, zw_real alpha)
{
    unsigned i;
    w->alpha = alpha;
    w->have_prev = false;
    w->cell = false;
    w->truncated = false;
    w->step = 0u;
    w->count = 0u;
    w->prev_est = ZW_R(0.0);
    w->prev_lo = ZW_R(0.0);
    w->prev_hi = ZW_R(0.0);
    w->floor = -ZW_REAL_MAX;
    w->est = ZW_R(0.0);
    w->lo = ZW_R(0.0);
    w->hi = ZW_R(0.0);
    w->mid = ZW_R(0.0);
    for (i = 0u; i < ZW_LOOP_MAX_INTERVALS; ++i) {
        w->cell_lo[i] = ZW_R(0.0);
        w->cell_hi[i] = ZW_R(0.0);
    }
    w->outer[0] = ZW_R(0.0);
    w->outer[1] = ZW_R(0.0);
}

/* The next crossing above the floor: false when the walk is over (none left, the step
 * bound, or a degenerate line, whose set is emptied).  Then w->cell tells whether the gap
 * before it is a cell to label at w->mid.  On ALPHA_ZERO, theta = 0 adds the double root
 * at z = 1: beta = R0(1) / S(1). */
ZW_NOINLINE static bool walk_step(zw_loop_workspace *ws, unsigned mode)
{
    unsigned line_mode = mode;
    ll_walk *w = &ws->lim_walk;
    ll_scan *x = &ws->lim_scan;
    w->cell = false;
    if (w->step >= LL_MAX_CROSSINGS) {
        return false;
    }
    w->step++;
    if ((line_mode == LL_ALPHA_ZERO) && ws->lim_plant.stiff) {
        /* with stiffness alpha = 0 is not a boundary (z = 1 is alpha = -kappa): the line
         * alpha = 0 itself, no double root at z = 1 */
        line_mode = LL_FIX_ALPHA;
    }
    scan_setup(ws, line_mode, w->alpha, LL_TAKE_NEXT_ABOVE, w->floor);
    offer_line(x, &x->degenerate);
    if (line_mode == LL_ALPHA_ZERO) {
        ll_point *pt = x->pt;
        eval_point(x, ZW_R(0.0), pt);
        offer(x, pt->v, pt->v - pt->v_err, pt->v + pt->v_err);
    }
    scan(x);
    if (!x->found) {
        return false;
    }
    if (x->degenerate) {
        w->count = 0u;
        w->truncated = false;
        return false;
    }
    w->est = x->est;
    w->lo = x->lo;
    w->hi = x->hi;
    if (w->have_prev && w->prev_hi < w->lo) {
        w->cell = true;
        w->mid = ZW_R(0.5) * w->prev_est + ZW_R(0.5) * w->est;
    }
    return true;
}

/* After walk_step: keep its cell if stable, and move on. */
static void walk_record(ll_walk *w, bool stable)
{
    if (w->cell && stable) {
        if (w->count < ZW_LOOP_MAX_INTERVALS) {
            if (w->count == 0u) {
                w->outer[0] = w->prev_lo;
            }
            w->outer[1] = w->hi;
            w->cell_lo[w->count] = w->prev_hi;
            w->cell_hi[w->count] = w->lo;
            w->count++;
        } else {
            w->truncated = true;
        }
    }
    w->have_prev = true;
    w->prev_est = w->est;
    w->prev_lo = w->lo;
    w->prev_hi = w->hi;
    w->floor = w->est;
}

/* The stable beta intervals at alpha into ws->lim_walk (count 0 when alpha <= 0). */
static zw_status beta_walk(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha)
{
    zw_status st;
    walk_begin(&ws->lim_walk, alpha);
    st = plant_init(&ws->lim_plant, loop, ws);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_require_finite(alpha);
    if (st != ZW_OK) {
        return st;
    }
    if (!(alpha > ZW_R(0.0))) {
        return ZW_OK;
    }
    while (walk_step(ws, LL_FIX_ALPHA)) {
        walk_record(&ws->lim_walk,
                    ws->lim_walk.cell && checked_stable(ws, ws->lim_walk.alpha, ws->lim_walk.mid));
    }
    return ZW_OK;
}

static void clear_set(zw_loop_beta_set *out)
{
    unsigned i;
    out->count = 0u;
    out->truncated = false;
    for (i = 0u; i < ZW_LOOP_MAX_INTERVALS; ++i) {
        out->lo[i] = ZW_R(0.0);
        out->hi[i] = ZW_R(0.0);
    }
}

zw_status zw_loop_beta_intervals(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                 zw_loop_beta_set *out)
{
    const ll_walk *w;
    zw_status st;
    unsigned i;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    clear_set(out);
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = beta_walk(loop, ws, alpha);
    if (st != ZW_OK) {
        return st;
    }
    w = &ws->lim_walk;
    out->count = w->count;
    out->truncated = w->truncated;
    for (i = 0u; i < w->count; ++i) {
        out->lo[i] = w->cell_lo[i];
        out->hi[i] = w->cell_hi[i];
    }
    return ZW_OK;
}

zw_status zw_loop_beta_interval(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                zw_real *lo, zw_real *hi, bool *nonempty)
{
    const ll_walk *w;
    zw_status st;
    unsigned i, best = 0u;
    zw_fail_interval(lo, hi, nonempty); /* every non-NULL output certifies nothing */
    if (lo == NULL || hi == NULL || nonempty == NULL) {
        return ZW_ERR_NULL;
    }
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = beta_walk(loop, ws, alpha);
    w = &ws->lim_walk;
    if (st != ZW_OK || w->count == 0u) {
        return st;
    }
    for (i = 1u; i < w->count; ++i) {
        if (w->cell_hi[i] - w->cell_lo[i] > w->cell_hi[best] - w->cell_lo[best]) {
            best = i;
        }
    }
    *lo = w->cell_lo[best];
    *hi = w->cell_hi[best];
    *nonempty = true;
    return ZW_OK;
}

/* ---- extremes -------------------------------------------------------------------------- */

/* Where the complex-pair curve ends on the z = -1 line (the pair merges into a double root
 * at z = -1): a corner of the region, where the extremes of delayed or filtered loops
 * (and the ideal loop above delta1) sit.  With theta = pi - phi, Re R0 and Re S both
 * vanish like phi, and their ratio tends to
 *     beta* = (Q0(-1)/2 - Q0'(-1)) / (Vt(-1)/2 - Vt'(-1)),   alpha* = -2 (Q0(-1) - beta* Vt(-1)),
 * from the logarithmic derivatives of the factors at z = -1.  False where the curve has
 * an asymptote there instead (Tustin, delta = 0) or the ratio is undefined. */
static bool corner_minus1(const ll_plant *p, zw_real *alpha_c, zw_real *beta_c)
{
    const zw_loop_spec *sp = &p->loop->spec;
    const zw_coeffs *c = &p->loop->c;
    zw_real q, dq, v, dv, den, b;
    if (p->general || sp->differentiator == ZW_DIFF_TUSTIN || !(c->d12 > ZW_R(0.0))) {
        return false; /* a general plant: the golden section alone (conservative) */
    }
    /* Q0 = -2 z^d (z - e) / (c1 z + c2) */
    q = -ZW_R(2.0) * ((sp->delay % 2u) == 0u ? ZW_R(1.0) : ZW_R(-1.0)) * (ZW_R(1.0) + c->e) / c->d12;
    dq = q * (-(zw_real)sp->delay - ZW_R(1.0) / (ZW_R(1.0) + c->e) + c->c1 / c->d12);
    v = -ZW_R(1.0); /* backward: Vt = 1/z */
    dv = -ZW_R(1.0);
    if (sp->filter == ZW_VFILTER_LOWPASS) {
        zw_real a = sp->filter_pole, f = p->one_minus_a / (ZW_R(1.0) + a);
        zw_real dlog = -ZW_R(1.0) + ZW_R(1.0) / (ZW_R(1.0) + a);
        dv = dv * f + v * f * dlog;
        v *= f;
    } else if (sp->filter == ZW_VFILTER_AVERAGE) {
        zw_real sum = ZW_R(0.0), dsum = ZW_R(0.0), sign = ZW_R(1.0), n = (zw_real)sp->average;
        unsigned i;
        for (i = 0u; i < sp->average; ++i) { /* z^-i at -1 and its derivative -i z^(-i-1) */
            sum += sign;
            dsum += (zw_real)i * sign;
            sign = -sign;
        }
        sum /= n;
        dsum /= n;
        dv = dv * sum + v * dsum;
        v *= sum;
    } else {
        /* backward alone */
    }
    den = ZW_R(0.5) * v - dv;
    if (!(ZW_FABS(den) > ZW_R(64.0) * ZW_U * (ZW_FABS(v) + ZW_FABS(dv)))) {
        return false;
    }
    b = (ZW_R(0.5) * q - dq) / den;
    *beta_c = b;
    *alpha_c = -ZW_R(2.0) * (q - b * v);
    return ZW_IS_FINITE(b) && ZW_IS_FINITE(*alpha_c);
}

/* max of alpha_max over (bl, bh) into e->best_a, attained at e->best_b: grid, then golden
 * section around the best grid point. */
ZW_NOINLINE static void maximise(zw_loop_workspace *ws, zw_real bl, zw_real bh)
{
    ll_ext *e = &ws->lim_ext;
    unsigned k;
    e->ibest = 0u;
    e->bl = bl;
    e->bh = bh;
    e->w = bh - bl;
    e->best_a = ZW_R(0.0);
    e->best_b = ZW_R(0.5) * bl + ZW_R(0.5) * bh;
    e->i = 0u;
    while (e->i < LL_EXT_GRID) {
        k = e->i + 1u;
        e->t = e->bl + e->w * ((zw_real)k / LL_EXT_GRID_N);
        alpha_max_of(ws, e->t);
        if (ws->lim_amax > e->best_a) {
            e->best_a = ws->lim_amax;
            e->best_b = e->t;
            e->ibest = e->i;
        }
        ++e->i;
    }
    k = e->ibest + 2u;
    e->a = e->bl + e->w * ((zw_real)e->ibest / LL_EXT_GRID_N);
    e->b = e->bl + e->w * ((zw_real)k / LL_EXT_GRID_N);
    e->c = e->b - LL_INVPHI * (e->b - e->a);
    e->d = e->a + LL_INVPHI * (e->b - e->a);
    alpha_max_of(ws, e->c);
    e->fc = ws->lim_amax;
    alpha_max_of(ws, e->d);
    e->fd = ws->lim_amax;
    e->it = 0u;
    while (e->it < LL_ITER && e->c < e->d) {
        if (e->fc > e->best_a) {
            e->best_a = e->fc;
            e->best_b = e->c;
        }
        if (e->fd > e->best_a) {
            e->best_a = e->fd;
            e->best_b = e->d;
        }
        if (e->fc >= e->fd) {
            e->b = e->d;
            e->d = e->c;
            e->fd = e->fc;
            e->c = e->b - LL_INVPHI * (e->b - e->a);
            alpha_max_of(ws, e->c);
            e->fc = ws->lim_amax;
        } else {
            e->a = e->c;
            e->c = e->d;
            e->fc = e->fd;
            e->d = e->a + LL_INVPHI * (e->b - e->a);
            alpha_max_of(ws, e->d);
            e->fd = ws->lim_amax;
        }
        ++e->it;
    }
    /* The corner at z = -1, if in this cell: the golden section only approaches it from
     * the side it happens to sample, where the pair next to z = -1 is poorly resolved. */
    if (corner_minus1(&ws->lim_plant, &e->a, &e->t) && e->t > e->bl && e->t < e->bh) {
        e->i = 0u;
        while (e->i < 5u) {
            e->b = e->t + ((zw_real)e->i - ZW_R(2.0)) * (ZW_R(4.0) * ZW_U) * (ZW_FABS(e->t) + e->w);
            alpha_max_of(ws, e->b);
            if (ws->lim_amax > e->best_a) {
                e->best_a = ws->lim_amax;
                e->best_b = e->b;
            }
            ++e->i;
        }
    }
}

/* Move the certified end towards the bound far (exclusive) while alpha_max > 0: from end
 * to e->a. */
ZW_NOINLINE static void push_end(zw_loop_workspace *ws, zw_real end, zw_real far)
{
    ll_ext *e = &ws->lim_ext;
    e->a = end;
    e->b = far;
    if (!ZW_IS_FINITE(far) || !ZW_IS_FINITE(far - e->a)) {
        return;
    }
    e->it = 0u;
    while (e->it < LL_ITER / 2u) {
        e->t = e->a + ZW_R(0.5) * (e->b - e->a);
        if (!(e->t != e->a && e->t != e->b)) {
            break;
        }
        alpha_max_of(ws, e->t);
        if (ws->lim_amax > ZW_R(0.0)) {
            e->a = e->t;
        } else {
            e->b = e->t;
        }
        ++e->it;
    }
}

static void clear_extremes(zw_loop_extremes *out)
{
    out->alpha_mmax = ZW_R(0.0);
    out->beta_at_alpha_mmax = ZW_R(0.0);
    out->alpha_p_max = ZW_R(0.0);
    out->beta_mmax = ZW_R(0.0);
    out->beta_mmin = ZW_R(0.0);
}

/* The stable beta ranges as alpha -> 0+ into ws->lim_walk. */
ZW_NOINLINE static void zero_walk(zw_loop_workspace *ws)
{
    walk_begin(&ws->lim_walk, ZW_R(0.0));
    while (walk_step(ws, LL_ALPHA_ZERO)) {
        if (ws->lim_walk.cell) {
            alpha_max_of(ws, ws->lim_walk.mid);
            walk_record(&ws->lim_walk, ws->lim_amax > ZW_R(0.0));
        } else {
            walk_record(&ws->lim_walk, false);
        }
    }
}

/* The extremes of the loop in ws->lim_plant.  Nothing here fails once the loop is
 * accepted: *out (cleared) is written field by field, and stays cleared on ZW_ERR_DOMAIN. */
ZW_NOINLINE static zw_status extremes_of(zw_loop_workspace *ws, zw_loop_extremes *out)
{
    const ll_walk *w;
    unsigned last;
    zero_walk(ws);
    w = &ws->lim_walk;
    if (w->count == 0u) {
        return ZW_ERR_DOMAIN;
    }
    /* the last cell: count <= ZW_LOOP_MAX_INTERVALS (walk_record's guard), the bound stated
     * where the analysis (docs/eva.md) cannot carry it through the walk's loop */
    last = (w->count < ZW_LOOP_MAX_INTERVALS) ? (w->count - 1u) : (ZW_LOOP_MAX_INTERVALS - 1u);
    /* Where a closing crossing is poorly resolved (its pair next to z = -1, e.g. near
     * delta0), push the ends outwards by bisection on "alpha_max(beta) > 0": every beta
     * where it holds is in the stable range at alpha -> 0+ (certified by alpha_max). */
    out->beta_mmin = w->cell_lo[0];
    out->beta_mmax = w->cell_hi[last];
    push_end(ws, out->beta_mmax, w->outer[1]);
    out->beta_mmax = ws->lim_ext.a;
    push_end(ws, out->beta_mmin, w->outer[0]);
    out->beta_mmin = ws->lim_ext.a;
    ws->lim_walk.i = 0u;
    while (ws->lim_walk.i <= last) { /* i < count */
        maximise(ws, w->cell_lo[ws->lim_walk.i], w->cell_hi[ws->lim_walk.i]);
        if (ws->lim_ext.best_a > out->alpha_mmax) {
            out->alpha_mmax = ws->lim_ext.best_a;
            out->beta_at_alpha_mmax = ws->lim_ext.best_b;
        }
        ++ws->lim_walk.i;
    }
    alpha_max_of(ws, ZW_R(0.0));
    out->alpha_p_max = ws->lim_amax;
    return ZW_OK;
}

zw_status zw_loop_extremes_compute(const zw_loop *loop, zw_loop_workspace *ws,
                                   zw_loop_extremes *out)
{
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    clear_extremes(out);
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = plant_init(&ws->lim_plant, loop, ws);
    if (st != ZW_OK) {
        return st;
    }
    return extremes_of(ws, out);
}

/* ---- boundary for plots ---------------------------------------------------------------- */

zw_status zw_loop_boundary_point(const zw_loop *loop, zw_real theta, zw_real *alpha,
                                 zw_real *beta)
{
    ll_plant p;
    ll_cplx r0, s;
    zw_status st;
    zw_real b;
    zw_fail_real(alpha, ZW_R(0.0));
    zw_fail_real(beta, ZW_R(0.0));
    if (alpha == NULL || beta == NULL) {
        return ZW_ERR_NULL;
    }
    st = plant_init(&p, loop, NULL);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_require_finite(theta);
    if (st != ZW_OK) {
        return st;
    }
    if (!(theta > ZW_R(0.0) && theta <= LL_PI_BELOW)) {
        return ZW_ERR_ARG;
    }
    if (!(response_eps(&p, theta, &r0, &s) < ZW_REAL_MAX) || !(ZW_FABS(s.re) > ZW_R(2.0) * p.eps * cabs1(s))) {
        return ZW_ERR_DOMAIN;
    }
    b = r0.re / s.re;
    *alpha = -ZW_R(2.0) * ZW_SIN(ZW_R(0.5) * theta) * (r0.im - b * s.im);
    *beta = b;
    if (!ZW_IS_FINITE(*alpha) || !ZW_IS_FINITE(b)) {
        *alpha = ZW_R(0.0);
        *beta = ZW_R(0.0);
        return ZW_ERR_DOMAIN;
    }
    return ZW_OK;
}

zw_status zw_loop_boundary_line(const zw_loop *loop, zw_loop_boundary which, zw_real *c0,
                                zw_real *ca, zw_real *cb)
{
    ll_plant p;
    zw_status st;
    zw_real rel;
    zw_fail_real(c0, ZW_R(0.0));
    zw_fail_real(ca, ZW_R(0.0));
    zw_fail_real(cb, ZW_R(0.0));
    if (c0 == NULL || ca == NULL || cb == NULL) {
        return ZW_ERR_NULL;
    }
    st = plant_init(&p, loop, NULL);
    if (st != ZW_OK) {
        return st;
    }
    switch (which) {
    case ZW_LOOP_BOUNDARY_Z_PLUS1:
        if (p.general) {
            /* p(1) = Dv(1) (D(1) + alpha N(1)), D(1) = D_s(0), N(1) = N_s(0) */
            *c0 = loop->plant.den_s[loop->plant.order];
            *ca = loop->plant.num_s[loop->plant.order - 1u];
            return ZW_OK;
        }
        *ca = ZW_R(1.0); /* p(1) = alpha (c1 + c2) Dv(1) */
        return ZW_OK;
    case ZW_LOOP_BOUNDARY_Z_MINUS1:
        line_minus1(&p, c0, ca, cb, &rel);
        return ZW_OK;
    default: return ZW_ERR_ARG;
    }
}
