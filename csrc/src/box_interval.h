/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Private to plant_box.c and box_loop.c: closed intervals with outward rounding.
 *
 * No rounding-mode changes (several MCU toolchains ignore fesetround): every operation is
 * rounded to nearest, then moved by 4u|r| + ZW_REAL_MIN outward.  A correctly rounded r of
 * an exact v has |r - v| <= u |r| (1 + 2u) + ZW_REAL_MIN / 2 (gradual underflow included;
 * zw_selftest refuses flush-to-zero), and the step's own roundings take back at most
 * 1.1 u |r|, so bx_down(r) <= v <= bx_up(r) (the argument of box.c, docs/box.md).
 */
#ifndef ZWIDTH_BOX_INTERVAL_H
#define ZWIDTH_BOX_INTERVAL_H

#include "zwidth/box.h"
#include "internal.h"

typedef zw_box_loop_iv bx_iv;

/* An overflowed +inf (-inf) stands for a value beyond the largest finite one. */
static inline zw_real bx_down(zw_real r)
{
    return (r > ZW_REAL_MAX) ? ZW_REAL_MAX : (r - (ZW_R(4.0) * ZW_U * ZW_FABS(r) + ZW_ETA));
}

static inline zw_real bx_up(zw_real r)
{
    return (r < -ZW_REAL_MAX) ? -ZW_REAL_MAX : (r + (ZW_R(4.0) * ZW_U * ZW_FABS(r) + ZW_ETA));
}

static inline bx_iv bx_make(zw_real lo, zw_real hi)
{
    bx_iv r;
    r.lo = lo;
    r.hi = hi;
    return r;
}

/* An exact value (no widening). */
static inline bx_iv bx_point(zw_real v)
{
    return bx_make(v, v);
}

static inline zw_real bx_min(zw_real a, zw_real b)
{
    return (a < b) ? a : b;
}

static inline zw_real bx_max(zw_real a, zw_real b)
{
    return (a > b) ? a : b;
}

static inline bool bx_is_zero(bx_iv a)
{
    return (a.lo == ZW_R(0.0)) && (a.hi == ZW_R(0.0));
}

/* a + b (an exact zero operand adds nothing). */
static inline bx_iv bx_add(bx_iv a, bx_iv b)
{
    bx_iv r = a;
    if (bx_is_zero(a)) {
        r = b;
    } else if (!bx_is_zero(b)) {
        r = bx_make(bx_down(a.lo + b.lo), bx_up(a.hi + b.hi));
    } else {
        /* b is an exact zero: r = a */
    }
    return r;
}

/* The least and largest of four end products or quotients, rounded outward. */
static inline bx_iv bx_hull4(zw_real p1, zw_real p2, zw_real p3, zw_real p4)
{
    return bx_make(bx_down(bx_min(bx_min(p1, p2), bx_min(p3, p4))),
                   bx_up(bx_max(bx_max(p1, p2), bx_max(p3, p4))));
}

/* a * b (exact zeros stay exact). */
static inline bx_iv bx_mul(bx_iv a, bx_iv b)
{
    bx_iv r = bx_point(ZW_R(0.0));
    if (!bx_is_zero(a) && !bx_is_zero(b)) {
        r = bx_hull4(a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi);
    }
    return r;
}

/* a / b for b > 0 (b.lo > 0). */
static inline bx_iv bx_div_pos(bx_iv a, bx_iv b)
{
    return bx_hull4(a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi);
}

/* A work list's settings (zw_box_work, zw_box_loop_work): capacity >= min_cells, max_evals
 * in 1..ZW_BOX_MAX_EVALS, rel_tol in [0, 1); else ZW_ERR_ARG. */
static inline zw_status bx_validate_work(uint_least32_t capacity, uint_least32_t min_cells,
                                         uint_least32_t max_evals, zw_real rel_tol)
{
    const bool counts_ok = (capacity >= min_cells) && (max_evals >= 1u) &&
                           (max_evals <= ZW_BOX_MAX_EVALS);
    const bool tol_ok = (rel_tol >= ZW_R(0.0)) && (rel_tol < ZW_R(1.0));
    return (counts_ok && tol_ok) ? ZW_OK : ZW_ERR_ARG;
}

/* A gain that normalizes without overflow at every plant of the box: K T^2 / m and B T / m
 * are largest at m_lo (ZW_ERR_RANGE), and |K| T T (rounded up) is finite. */
static inline zw_status bx_validate_gain(const zw_plant_box *box, zw_real gain, bool stiffness)
{
    zw_status st = zw_require_finite(gain);
    if (st == ZW_OK) {
        zw_real scale = box->m_lo / box->T;
        if (stiffness) {
            scale = scale / box->T;
        }
        if (!ZW_IS_FINITE(gain / scale) ||
            !ZW_IS_FINITE(bx_up(bx_up(ZW_FABS(gain) * box->T) * box->T))) {
            st = ZW_ERR_RANGE;
        }
    }
    return st;
}

/* The fail-safe bound (status.h): certifies nothing. */
static inline void bx_fail_bound(zw_box_bound *out)
{
    if (out != NULL) {
        out->K_lower = ZW_R(0.0);
        out->K_upper = ZW_R(0.0);
        out->m_worst = ZW_NAN;
        out->b_worst = ZW_NAN;
        out->evals = 0u;
        out->converged = false;
        out->k_worst = ZW_NAN;
    }
}

#endif /* ZWIDTH_BOX_INTERVAL_H */
