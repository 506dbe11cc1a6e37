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
    if (r > ZW_REAL_MAX) {
        return ZW_REAL_MAX;
    }
    return r - (ZW_R(4.0) * ZW_U * ZW_FABS(r) + ZW_ETA);
}

static inline zw_real bx_up(zw_real r)
{
    if (r < -ZW_REAL_MAX) {
        return -ZW_REAL_MAX;
    }
    return r + (ZW_R(4.0) * ZW_U * ZW_FABS(r) + ZW_ETA);
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

static inline bx_iv bx_add(bx_iv a, bx_iv b)
{
    if (bx_is_zero(a)) {
        return b;
    }
    if (bx_is_zero(b)) {
        return a;
    }
    return bx_make(bx_down(a.lo + b.lo), bx_up(a.hi + b.hi));
}

/* a * b: the least and largest of the four end products (exact zeros stay exact). */
static inline bx_iv bx_mul(bx_iv a, bx_iv b)
{
    zw_real p1, p2, p3, p4;
    if (bx_is_zero(a) || bx_is_zero(b)) {
        return bx_point(ZW_R(0.0));
    }
    p1 = a.lo * b.lo;
    p2 = a.lo * b.hi;
    p3 = a.hi * b.lo;
    p4 = a.hi * b.hi;
    return bx_make(bx_down(bx_min(bx_min(p1, p2), bx_min(p3, p4))),
                   bx_up(bx_max(bx_max(p1, p2), bx_max(p3, p4))));
}

/* a / b for b > 0 (b.lo > 0). */
static inline bx_iv bx_div_pos(bx_iv a, bx_iv b)
{
    zw_real p1 = a.lo / b.lo, p2 = a.lo / b.hi, p3 = a.hi / b.lo, p4 = a.hi / b.hi;
    return bx_make(bx_down(bx_min(bx_min(p1, p2), bx_min(p3, p4))),
                   bx_up(bx_max(bx_max(p1, p2), bx_max(p3, p4))));
}

#endif /* ZWIDTH_BOX_INTERVAL_H */
