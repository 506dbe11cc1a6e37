/* Stability verdicts, paper eqs (10), (14)-(18), each guarded by a running error bound.
 *
 * Exact region in division-free forms (x = beta + delta > 0, sigma a power of two):
 *   hyperbola  (alpha/sigma) g + (alpha/sigma) / x  <  hs - beta/sigma
 *              (alpha < f(beta) multiplied by (g + 1/x)/sigma > 0; g = c1/s, hs = 2/(c2 sigma);
 *               beta >= 2/c2 makes the right side <= 0, so the right end is included)
 *   line       d12 (alpha/2) + d12 beta  <  2 (1 + e)
 *              (p(-1) < 0; at delta = 0, d12 = 0 and it always holds, as it must)
 * Using c1 beta + 2 = c1 x + s avoids the cancellation of the paper's form near the corner
 * beta -> -delta, and sigma keeps every term finite up to delta ~ max/2.
 */
#include "zwidth/region.h"

#include <stddef.h>

#include "internal.h"

/* Collects the outcome of each constraint, then decides. */
typedef struct verdict_builder {
    uint_least16_t surely;  /* constraints certainly violated */
    uint_least16_t unsure;  /* constraints within the rounding band */
} verdict_builder;

/* Record the outcome of "lhs < rhs must hold" for constraint bit. */
static void require_less(verdict_builder *vb, zw_bound bit, zw_eb lhs, zw_eb rhs)
{
    zw_cmp cmp = zw_eb_compare(lhs, rhs);
    if (cmp == ZW_CMP_GE) vb->surely = (uint_least16_t)(vb->surely | bit);
    else if (cmp == ZW_CMP_UNSURE) vb->unsure = (uint_least16_t)(vb->unsure | bit);
}

static zw_bound first_bit(uint_least16_t mask)
{
    uint_least16_t bit;
    for (bit = 1; bit <= ZW_BOUND_PASSIVITY; bit = (uint_least16_t)(bit << 1))
        if (mask & bit) return (zw_bound)bit;
    return ZW_BOUND_NONE;
}

static void finish(const verdict_builder *vb, zw_verdict *out)
{
    zw_verdict v;
    v.violated = (uint_least16_t)(vb->surely | vb->unsure);
    v.stable = v.violated == 0;
    v.marginal = vb->surely == 0 && vb->unsure != 0;
    v.deciding = first_bit(vb->surely != 0 ? vb->surely : vb->unsure);
    *out = v;
}

/* beta + delta, with delta's own uncertainty. */
static zw_eb damping_excess(const zw_coeffs *c, zw_eb beta)
{
    zw_eb delta = zw_eb_exact(c->delta);
    delta.e = c->delta * c->delta_relerr;
    return zw_eb_add(beta, delta);
}

static void exact_constraints(const zw_coeffs *c, zw_eb alpha, zw_eb beta, bool with_line,
                              verdict_builder *vb)
{
    const zw_eb zero = zw_eb_exact(ZW_R(0.0));
    zw_eb x = damping_excess(c, beta);
    require_less(vb, ZW_BOUND_DAMPING, zero, x);
    require_less(vb, ZW_BOUND_STIFFNESS, zero, alpha);

    if (zw_eb_compare(zero, x) == ZW_CMP_LT) { /* the hyperbola form needs x > 0 */
        zw_eb inv_sigma = zw_eb_exact(ZW_R(1.0) / c->sigma); /* exact: sigma is a power of two */
        zw_eb alpha_s = zw_eb_mul(alpha, inv_sigma);
        zw_eb lhs = zw_eb_add(zw_eb_mul(alpha_s, zw_eb_coef(c, c->g)), zw_eb_div(alpha_s, x));
        zw_eb rhs = zw_eb_sub(zw_eb_coef(c, c->hs), zw_eb_mul(beta, inv_sigma));
        require_less(vb, ZW_BOUND_HYPERBOLA, lhs, rhs);
    } else {
        vb->unsure = (uint_least16_t)(vb->unsure | ZW_BOUND_HYPERBOLA);
    }
    if (with_line) {
        zw_eb d12 = zw_eb_coef(c, c->d12);
        zw_eb half_alpha = zw_eb_mul(alpha, zw_eb_exact(ZW_R(0.5)));
        zw_eb lhs = zw_eb_add(zw_eb_mul(d12, half_alpha), zw_eb_mul(d12, beta));
        zw_eb one_plus_e = zw_eb_add(zw_eb_exact(ZW_R(1.0)), zw_eb_coef_e(c));
        require_less(vb, ZW_BOUND_LINE, lhs, zw_eb_mul(zw_eb_exact(ZW_R(2.0)), one_plus_e));
    }
}

/* alpha / 2 + sign_beta * beta < limit, for the linear regions (14)-(18). */
static void linear_constraint(verdict_builder *vb, zw_bound bit, zw_eb alpha, zw_eb beta_term,
                              zw_eb limit)
{
    zw_eb half_alpha = zw_eb_mul(alpha, zw_eb_exact(ZW_R(0.5)));
    require_less(vb, bit, zw_eb_add(half_alpha, beta_term), limit);
}

/* The delta = 0 coefficients, for the region of eq (17) (c1 = c2 = 1, e = 1, d12 = 0). */
static const zw_coeffs k_delta_zero = {
    ZW_R(0.0), ZW_R(1.0), ZW_R(1.0), ZW_R(1.0), ZW_R(0.0),
    ZW_R(2.0), ZW_R(0.5), ZW_R(1.0), ZW_R(2.0), ZW_R(0.0)};

zw_status zw_check_bounded(zw_region region, const zw_coeffs *c, zw_eb alpha, zw_eb beta,
                           zw_verdict *out)
{
    verdict_builder vb = {0, 0};
    const zw_eb zero = zw_eb_exact(ZW_R(0.0));
    zw_eb delta;
    zw_status st;
    if (c == NULL || out == NULL) return ZW_ERR_NULL;
    if ((st = zw_require_finite(alpha.v)) != ZW_OK) return st;
    if ((st = zw_require_finite(beta.v)) != ZW_OK) return st;
    if ((st = zw_require_finite(c->delta)) != ZW_OK) return st;
    if (!ZW_IS_FINITE(c->hs)) return ZW_ERR_RANGE;
    delta = zw_eb_exact(c->delta);
    delta.e = c->delta * c->delta_relerr;

    switch (region) {
    case ZW_REGION_EXACT: exact_constraints(c, alpha, beta, true, &vb); break;
    case ZW_REGION_LEGACY: exact_constraints(c, alpha, beta, false, &vb); break;
    case ZW_REGION_DELTA0: exact_constraints(&k_delta_zero, alpha, beta, false, &vb); break;
    case ZW_REGION_PASSIVITY: {
        zw_eb abs_beta = beta;
        abs_beta.v = ZW_FABS(beta.v);
        require_less(&vb, ZW_BOUND_STIFFNESS, zero, alpha);
        linear_constraint(&vb, ZW_BOUND_PASSIVITY, alpha, abs_beta, delta);
        break;
    }
    case ZW_REGION_DELTA_INF:
        require_less(&vb, ZW_BOUND_DAMPING, zero, damping_excess(c, beta));
        require_less(&vb, ZW_BOUND_STIFFNESS, zero, alpha);
        linear_constraint(&vb, ZW_BOUND_LINE, alpha, beta, delta);
        break;
    case ZW_REGION_SMALL: {
        zw_eb minus_beta = beta;
        minus_beta.v = -beta.v;
        require_less(&vb, ZW_BOUND_STIFFNESS, zero, alpha);
        linear_constraint(&vb, ZW_BOUND_HYPERBOLA, alpha, minus_beta, delta);
        break;
    }
    default: return ZW_ERR_ARG;
    }
    finish(&vb, out);
    return ZW_OK;
}

zw_status zw_check_region(zw_region region, const zw_coeffs *c, zw_real alpha, zw_real beta,
                          zw_verdict *out)
{
    return zw_check_bounded(region, c, zw_eb_exact(alpha), zw_eb_exact(beta), out);
}

zw_status zw_check(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_verdict *out)
{
    return zw_check_region(ZW_REGION_EXACT, c, alpha, beta, out);
}

zw_status zw_check_proportional(const zw_coeffs *c, zw_real alpha, zw_verdict *out)
{
    return zw_check_region(ZW_REGION_EXACT, c, alpha, ZW_R(0.0), out);
}
