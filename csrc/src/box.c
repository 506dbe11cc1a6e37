/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* Certification over a plant box (box.h): branch and bound on an interval enclosure of
 * the exact region, eq (10), in real units.
 *
 * At one plant, K_max(B) = max(0, min(K_f, K_L)) when B + b > 0 (else 0), with
 *   K_f = (m h / T^2 - B / T) / (g + 1 / X),   X = (B + b) T / m,  h = 2 / c2,  g = c1 / s
 *   K_L = 2 (m lambda / T^2 - B / T),          lambda = 2 (1 + e) / d12
 * (alpha < f(beta) = x (h - beta) / (g x + 1) and alpha < L(beta) = 2 (lambda - beta)
 * multiplied by m / T^2; the same forms as extremes.c).  Over a cell, a lower bound
 * follows from the monotonicity of each piece in its interval arguments: K_f rises with
 * m h, X and falls with g; K_L rises with m lambda.  The coefficients over the cell's
 * delta interval [bT/m_hi, bT/m_lo] come from zw_coeffs_init at its two ends (the
 * paper's functions are monotone there: e, c1, c2, s fall and g, h rise with delta;
 * d12 rises up to ZW_BOX_D12_PEAK and falls beyond; tests/py/test_box_reference.py checks
 * each at 40 digits), widened by ZW_COEF_ULPS.
 *
 * Outward rounding without changing the rounding mode: every operation is rounded to
 * nearest and then moved by widen_down / widen_up, which step by 4u|r| + ZW_REAL_MIN.
 * A correctly rounded r of an exact v has |r - v| <= u |r| (1 + 2u) + ZW_REAL_MIN / 2 (also
 * under gradual underflow), and the step's own roundings take away at most 1.1 u |r|, so
 * bx_down(r) <= v <= bx_up(r).  Overflow is excluded by the box's validation
 * (ZW_BOX_DELTA_MAX and corners accepted by zw_device_init) and checked at the end.
 */
#include "zwidth/box.h"

#include <stddef.h>

#include "zwidth/coeffs.h"
#include "zwidth/device.h"
#include "box_interval.h"

#include "internal.h"

/* d12 peaks at delta = 2.68799934549949... with 0.27870311291437160... (40 digits in
 * tests/py/test_box_reference.py); the bracket and the peak are rounded outward. */
#define ZW_BOX_D12_PEAK_LO ZW_R(2.6875)
#define ZW_BOX_D12_PEAK_HI ZW_R(2.6885)
#define ZW_BOX_D12_MAX_UP ZW_R(0.2787032)
/* relative error bound of a coefficient field (ZW_COEF_ULPS ulps, an ulp <= 2u), plus u */
#define ZW_BOX_COEF_REL ((ZW_R(2.0) * (zw_real)ZW_COEF_ULPS + ZW_R(1.0)) * ZW_U)
/* bisection steps of the B range ends, and golden-section steps of the K_mmax search */
#define ZW_BOX_BISECT_STEPS 64
#define ZW_BOX_GOLDEN_STEPS 80

/* A coefficient field v (error <= ZW_COEF_ULPS ulps, or ZW_COEF_ABSERR if subnormal). */
static zw_real box_coef_down(zw_real v)
{
    return bx_down(v - (ZW_BOX_COEF_REL * ZW_FABS(v) + ZW_COEF_ABSERR));
}

static zw_real box_coef_up(zw_real v)
{
    return bx_up(v + (ZW_BOX_COEF_REL * ZW_FABS(v) + ZW_COEF_ABSERR));
}

/* ---- validation ------------------------------------------------------------------- */

static zw_status box_validate(const zw_plant_box *box)
{
    zw_device d;
    zw_real delta_hi;
    if (box == NULL) {
        return ZW_ERR_NULL;
    }
    if (ZW_IS_NAN(box->m_lo) || ZW_IS_NAN(box->m_hi) || ZW_IS_NAN(box->b_lo) ||
        ZW_IS_NAN(box->b_hi) || ZW_IS_NAN(box->T)) {
        return ZW_ERR_NAN;
    }
    if (!ZW_IS_FINITE(box->m_lo) || !ZW_IS_FINITE(box->m_hi) || !ZW_IS_FINITE(box->b_lo) ||
        !ZW_IS_FINITE(box->b_hi) || !ZW_IS_FINITE(box->T)) {
        return ZW_ERR_INF;
    }
    if (!(box->m_lo > ZW_R(0.0))) {
        return ZW_ERR_MASS;
    }
    if (box->b_lo < ZW_R(0.0)) {
        return ZW_ERR_DAMPING;
    }
    if (!(box->T > ZW_R(0.0))) {
        return ZW_ERR_PERIOD;
    }
    if ((box->m_lo > box->m_hi) || (box->b_lo > box->b_hi)) {
        return ZW_ERR_BOX;
    }
    /* the corners span every range a cell can reach (m/T, m/T^2, T/m, b T/m) */
    if (zw_device_init(&d, box->m_lo, box->b_lo, box->T) != ZW_OK) {
        return ZW_ERR_RANGE;
    }
    if (zw_device_init(&d, box->m_hi, box->b_hi, box->T) != ZW_OK) {
        return ZW_ERR_RANGE;
    }
    if (zw_device_init(&d, box->m_lo, box->b_hi, box->T) != ZW_OK) {
        return ZW_ERR_RANGE;
    }
    if (zw_device_init(&d, box->m_hi, box->b_lo, box->T) != ZW_OK) {
        return ZW_ERR_RANGE;
    }
    delta_hi = bx_up(bx_up(box->b_hi * box->T) / box->m_lo);
    if (!(delta_hi <= ZW_BOX_DELTA_MAX)) {
        return ZW_ERR_RANGE;
    }
    return ZW_OK;
}

/* A part's range: finite, 0 <= lo <= hi (negative: `negative`, as plant.h names it). */
static zw_status box_part_range(zw_real lo, zw_real hi, zw_status negative)
{
    if (ZW_IS_NAN(lo) || ZW_IS_NAN(hi)) {
        return ZW_ERR_NAN;
    }
    if (!ZW_IS_FINITE(lo) || !ZW_IS_FINITE(hi)) {
        return ZW_ERR_INF;
    }
    if (lo < ZW_R(0.0)) {
        return negative;
    }
    if (lo > hi) {
        return ZW_ERR_BOX;
    }
    return ZW_OK;
}

/* [a_lo + p_lo, a_hi + p_hi] rounded outward (exact when the part is 0: today's box). */
static void box_fold_sum(zw_real a_lo, zw_real a_hi, zw_real p_lo, zw_real p_hi, zw_real *lo,
                         zw_real *hi)
{
    *lo = (p_lo > ZW_R(0.0)) ? bx_max(a_lo, bx_down(a_lo + p_lo)) : a_lo;
    *hi = (p_hi > ZW_R(0.0)) ? bx_up(a_hi + p_hi) : a_hi;
}

static zw_status box_fold(const zw_plant_box *box, zw_plant_box *f)
{
    zw_status st;
    if ((box == NULL) || (f == NULL)) {
        return ZW_ERR_NULL;
    }
    st = box_part_range(box->k_lo, box->k_hi, ZW_ERR_ARG);
    if (st == ZW_OK) {
        st = box_part_range(box->m_h_lo, box->m_h_hi, ZW_ERR_ARG);
    }
    if (st == ZW_OK) {
        st = box_part_range(box->b_h_lo, box->b_h_hi, ZW_ERR_DAMPING);
    }
    if (st == ZW_OK) {
        st = box_part_range(box->k_h_lo, box->k_h_hi, ZW_ERR_ARG);
    }
    if (st == ZW_OK) {
        st = box_part_range(box->tau_lo, box->tau_hi, ZW_ERR_ARG);
    }
    if (st != ZW_OK) {
        return st;
    }
    if (box->tau_hi > ZW_R(0.0)) {
        return ZW_ERR_ARG; /* a lag range: not supported yet */
    }
    st = box_validate(box); /* m, b, T themselves */
    if (st != ZW_OK) {
        return st;
    }
    *f = *box;
    box_fold_sum(box->m_lo, box->m_hi, box->m_h_lo, box->m_h_hi, &f->m_lo, &f->m_hi);
    box_fold_sum(box->b_lo, box->b_hi, box->b_h_lo, box->b_h_hi, &f->b_lo, &f->b_hi);
    box_fold_sum(box->k_lo, box->k_hi, box->k_h_lo, box->k_h_hi, &f->k_lo, &f->k_hi);
    f->m_h_lo = ZW_R(0.0);
    f->m_h_hi = ZW_R(0.0);
    f->b_h_lo = ZW_R(0.0);
    f->b_h_hi = ZW_R(0.0);
    f->k_h_lo = ZW_R(0.0);
    f->k_h_hi = ZW_R(0.0);
    st = box_validate(f); /* the totals */
    if (st != ZW_OK) {
        return st;
    }
    if (f->k_hi > ZW_R(0.0)) {
        /* the enclosure's series domain: delta, kappa <= ZW_BOX_KAPPA_MAX over the box */
        const zw_real delta_hi = bx_up(bx_up(f->b_hi * f->T) / f->m_lo);
        const zw_real kappa_hi = bx_up(bx_up(bx_up(f->k_hi * f->T) * f->T) / f->m_lo);
        if (!(delta_hi <= ZW_BOX_KAPPA_MAX) || !(kappa_hi <= ZW_BOX_KAPPA_MAX)) {
            return ZW_ERR_RANGE;
        }
    }
    return ZW_OK;
}

zw_status zw_box_fold(const zw_plant_box *box, zw_plant_box *folded)
{
    const zw_status st = box_fold(box, folded);
    if ((st != ZW_OK) && (folded != NULL)) {
        /* fail-safe: a box every function refuses (NaN), never a partly folded one */
        folded->m_lo = ZW_NAN;
        folded->m_hi = ZW_NAN;
        folded->b_lo = ZW_NAN;
        folded->b_hi = ZW_NAN;
        folded->T = ZW_NAN;
        folded->k_lo = ZW_NAN;
        folded->k_hi = ZW_NAN;
        folded->m_h_lo = ZW_NAN;
        folded->m_h_hi = ZW_NAN;
        folded->b_h_lo = ZW_NAN;
        folded->b_h_hi = ZW_NAN;
        folded->k_h_lo = ZW_NAN;
        folded->k_h_hi = ZW_NAN;
        folded->tau_lo = ZW_NAN;
        folded->tau_hi = ZW_NAN;
    }
    return st;
}

zw_status zw_box_validate(const zw_plant_box *box)
{
    zw_plant_box f;
    return box_fold(box, &f);
}

/* The closed form's box: folded, without stiffness (ZW_ERR_ARG). */
static zw_status box_fold_ideal(const zw_plant_box *box, zw_plant_box *f)
{
    zw_status st = box_fold(box, f);
    if ((st == ZW_OK) && (f->k_hi > ZW_R(0.0))) {
        st = ZW_ERR_ARG;
    }
    return st;
}

static zw_status box_validate_work(const zw_box_work *work)
{
    if ((work == NULL) || (work->cells == NULL)) {
        return ZW_ERR_NULL;
    }
    /* constant returns: a sound analyser splits its callers' states by them (docs/eva.md) */
    if (bx_validate_work(work->capacity, ZW_BOX_MIN_CELLS, work->max_evals, work->rel_tol) != ZW_OK) {
        return ZW_ERR_ARG;
    }
    return ZW_OK;
}

zw_status zw_box_work_init(zw_box_work *work, zw_box_cell *cells, uint_least32_t capacity)
{
    if ((work == NULL) || (cells == NULL)) {
        return ZW_ERR_NULL;
    }
    if (capacity < ZW_BOX_MIN_CELLS) {
        return ZW_ERR_ARG;
    }
    work->cells = cells;
    work->capacity = capacity;
    work->max_evals = ZW_BOX_DEFAULT_EVALS;
    work->rel_tol = ZW_BOX_DEFAULT_REL_TOL;
    return ZW_OK;
}

/* ---- the enclosure ------------------------------------------------------------------ */

/* Upper bound of d12 over [delta_lo, delta_hi] from its values at the ends. */
static zw_real box_d12_upper(const zw_coeffs *lo, const zw_coeffs *hi)
{
    if (hi->delta <= ZW_BOX_D12_PEAK_LO) {
        return box_coef_up(hi->d12); /* rising */
    }
    if (lo->delta >= ZW_BOX_D12_PEAK_HI) {
        return box_coef_up(lo->d12); /* falling */
    }
    return ZW_BOX_D12_MAX_UP;
}

/* A lower bound of K_max(B; m, b) over the cell; ZW_ERR_RANGE if anything overflowed. */
static zw_status box_cell_bound(zw_real T, zw_real B, zw_box_cell *cell)
{
    zw_coeffs at_lo, at_hi;
    zw_status st;
    zw_real sum_lo, x_lo, delta_lo, delta_hi, k_lo, bt_hi, h_lo, g_hi, num, den, k_f, bound;
    zw_real d12_hi;
    cell->bound = ZW_R(0.0);
    sum_lo = bx_down(B + cell->b_lo);
    if (!(sum_lo > ZW_R(0.0))) {
        return ZW_OK; /* some plant has B + b <= 0: nothing stable */
    }
    x_lo = bx_down(bx_down(sum_lo * T) / cell->m_hi);
    delta_lo = bx_max(ZW_R(0.0), bx_down(bx_down(cell->b_lo * T) / cell->m_hi));
    delta_hi = bx_up(bx_up(cell->b_hi * T) / cell->m_lo);
    st = zw_coeffs_init(&at_lo, delta_lo);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_coeffs_init(&at_hi, delta_hi);
    if (st != ZW_OK) {
        return st;
    }
    k_lo = bx_down(bx_down(cell->m_lo / T) / T);
    bt_hi = bx_up(B / T);
    h_lo = box_coef_down(at_lo.hs * at_lo.sigma); /* sigma a power of two: the product is exact */
    g_hi = box_coef_up(at_hi.g);
    num = bx_down(bx_down(k_lo * h_lo) - bt_hi);
    if (!(num > ZW_R(0.0)) || !(x_lo > ZW_R(0.0))) {
        return ZW_OK;
    }
    den = bx_up(g_hi + bx_up(ZW_R(1.0) / x_lo));
    k_f = bx_down(num / den);
    bound = k_f;
    d12_hi = box_d12_upper(&at_lo, &at_hi);
    if (d12_hi > ZW_R(0.0)) {
        zw_real e_lo = bx_max(ZW_R(0.0), box_coef_down(at_hi.e));
        zw_real two_1pe = ZW_R(2.0) * bx_down(ZW_R(1.0) + e_lo); /* 2 (1 + e), doubling exact */
        zw_real lambda_lo = bx_down(two_1pe / d12_hi);
        zw_real room = bx_down(bx_down(k_lo * lambda_lo) - bt_hi); /* m lambda/T^2 - B/T */
        zw_real k_l = bx_down(ZW_R(2.0) * room);
        bound = bx_min(bound, k_l);
    }
    if (!ZW_IS_FINITE(bound)) {
        return ZW_ERR_RANGE;
    }
    cell->bound = bx_max(ZW_R(0.0), bound);
    return ZW_OK;
}

/* ---- the branch and bound ------------------------------------------------------------ */

typedef struct zw_box_search {
    zw_real T;
    const zw_box_work *work;
    zw_box_cell *cells;    /* work->cells */
    zw_real B;
    uint_least32_t live;   /* cells in cells[0 .. live) */
    uint_least32_t evals;
    zw_real dropped_min;   /* least bound of the cells dropped (pruned) */
    zw_real upper;         /* least point value of K_max found */
    zw_real m_worst, b_worst;
} zw_box_search;

/* Thresholds that end a search early (zw_box_check, zw_box_b_range): "certified" once the
 * lower bound exceeds K, "refuted" once a plant with K_max <= K is found. */
typedef enum zw_box_goal { ZW_BOX_GOAL_BOUND = 0, ZW_BOX_GOAL_DECIDE = 1 } zw_box_goal;

typedef enum zw_box_outcome {
    ZW_BOX_OPEN = 0,       /* budget spent */
    ZW_BOX_CONVERGED = 1,  /* gap within rel_tol */
    ZW_BOX_CERTIFIED = 2,  /* lower > K */
    ZW_BOX_REFUTED = 3     /* an unstable plant found */
} zw_box_outcome;

/* K_max(B) at one plant: the point value behind the upper bound. */
static zw_status box_point_value(zw_box_search *s, zw_real m, zw_real b)
{
    zw_device d;
    zw_real k;
    zw_status st;
    st = zw_device_init(&d, m, b, s->T);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_device_k_max(&d, s->B, &k);
    if (st != ZW_OK) {
        return st;
    }
    if (k < s->upper) {
        s->upper = k;
        s->m_worst = m;
        s->b_worst = b;
    }
    return ZW_OK;
}

static zw_real box_cell_m_mid(const zw_box_cell *c)
{
    return c->m_lo + ZW_R(0.5) * (c->m_hi - c->m_lo);
}

static zw_real box_cell_b_mid(const zw_box_cell *c)
{
    return c->b_lo + ZW_R(0.5) * (c->b_hi - c->b_lo);
}

/* Widths in the units K_max feels: m relative; b through delta = b T / m (absolute for
 * small delta, relative for large). */
static bool box_split_cell(zw_real T, const zw_box_cell *c, zw_box_cell *left, zw_box_cell *right)
{
    zw_real m_mid = box_cell_m_mid(c), b_mid = box_cell_b_mid(c);
    zw_real wm = (c->m_hi - c->m_lo) / c->m_hi;
    zw_real wb = (c->b_hi - c->b_lo) / (b_mid + m_mid / T);
    bool can_m = (m_mid > c->m_lo) && (m_mid < c->m_hi);
    bool can_b = (b_mid > c->b_lo) && (b_mid < c->b_hi);
    *left = *c;
    *right = *c;
    if (can_m && (!can_b || (wm >= wb))) {
        left->m_hi = m_mid;
        right->m_lo = m_mid;
        return true;
    }
    if (can_b) {
        left->b_hi = b_mid;
        right->b_lo = b_mid;
        return true;
    }
    return false;
}

/* The live cells form a binary min-heap on bound in work->cells[0 .. live): the cell with
 * the least bound is cells[0], and a split costs O(log live). */
static bool box_heap_less(const zw_box_cell *cells, uint_least32_t i, uint_least32_t j)
{
    return cells[i].bound < cells[j].bound;
}

static void box_heap_swap(zw_box_cell *cells, uint_least32_t i, uint_least32_t j)
{
    zw_box_cell t = cells[i];
    cells[i] = cells[j];
    cells[j] = t;
}

static void box_sift_up(zw_box_cell *cells, uint_least32_t start)
{
    uint_least32_t i = start;
    while (i > 0u) {
        uint_least32_t parent = (i - 1u) / 2u;
        if (!box_heap_less(cells, i, parent)) {
            break;
        }
        box_heap_swap(cells, i, parent);
        i = parent;
    }
}

static void box_sift_down(zw_box_cell *cells, uint_least32_t live, uint_least32_t start)
{
    uint_least32_t i = start;
    for (;;) {
        uint_least32_t least = i;
        uint_least32_t left = 2u * i + 1u;
        uint_least32_t right = left + 1u;
        if ((left < live) && box_heap_less(cells, left, least)) {
            least = left;
        }
        if ((right < live) && box_heap_less(cells, right, least)) {
            least = right;
        }
        if (least == i) {
            break;
        }
        box_heap_swap(cells, i, least);
        i = least;
    }
}

/* The least bound of any cell, live or dropped: the search's certified lower bound. */
static zw_real box_search_lower(const zw_box_search *s)
{
    return (s->live > 0u) ? bx_min(s->cells[0].bound, s->dropped_min) : s->dropped_min;
}

/* Drop the cells that cannot hold a value below the best plant found, then re-heap. */
static void box_prune(zw_box_search *s)
{
    uint_least32_t i, kept = 0u;
    for (i = 0u; i < s->live; ++i) {
        const zw_box_cell *c = &s->cells[i];
        if (c->bound >= s->upper) {
            s->dropped_min = bx_min(s->dropped_min, c->bound);
        } else {
            s->cells[kept] = *c;
            kept += 1u;
        }
    }
    s->live = kept;
    for (i = kept / 2u; i > 0u; --i) {
        box_sift_down(s->cells, kept, i - 1u);
    }
}

static zw_status box_add_cell(zw_box_search *s, const zw_box_cell *c)
{
    zw_status st = box_point_value(s, box_cell_m_mid(c), box_cell_b_mid(c));
    if (st != ZW_OK) {
        return st;
    }
    if (c->bound >= s->upper) {
        s->dropped_min = bx_min(s->dropped_min, c->bound);
    } else {
        s->cells[s->live] = *c;
        box_sift_up(s->cells, s->live);
        s->live += 1u;
    }
    return ZW_OK;
}

static zw_status box_search_init(zw_box_search *s, const zw_plant_box *box, const zw_box_work *work,
                                 zw_real B)
{
    zw_box_cell root;
    zw_status st;
    s->T = box->T;
    s->work = work;
    s->cells = work->cells;
    s->B = B;
    s->live = 0u;
    s->evals = 1u;
    s->dropped_min = ZW_INF;
    s->upper = ZW_INF;
    s->m_worst = box->m_lo;
    s->b_worst = box->b_lo;
    root.m_lo = box->m_lo;
    root.m_hi = box->m_hi;
    root.b_lo = box->b_lo;
    root.b_hi = box->b_hi;
    st = box_cell_bound(box->T, B, &root);
    if (st != ZW_OK) {
        return st;
    }
    /* the corners first: where K_max is monotone, one of them is the worst plant */
    st = box_point_value(s, box->m_lo, box->b_lo);
    if (st != ZW_OK) {
        return st;
    }
    st = box_point_value(s, box->m_hi, box->b_lo);
    if (st != ZW_OK) {
        return st;
    }
    st = box_point_value(s, box->m_lo, box->b_hi);
    if (st != ZW_OK) {
        return st;
    }
    st = box_point_value(s, box->m_hi, box->b_hi);
    if (st != ZW_OK) {
        return st;
    }
    return box_add_cell(s, &root);
}

/* Runs until the goal is met or the budget is spent; *lower is always a valid bound. */
static zw_status box_search_run(zw_box_search *s, zw_box_goal goal, zw_real K,
                                zw_box_outcome *outcome, zw_real *lower)
{
    zw_status st;
    *outcome = ZW_BOX_OPEN;
    for (;;) {
        zw_box_cell parent, left, right;
        *lower = bx_min(box_search_lower(s), s->upper);
        if (goal == ZW_BOX_GOAL_DECIDE) {
            if (*lower > K) {
                *outcome = ZW_BOX_CERTIFIED;
                return ZW_OK;
            }
            if (s->upper <= K) {
                zw_device d;
                zw_verdict v;
                st = zw_device_init(&d, s->m_worst, s->b_worst, s->T);
                if (st != ZW_OK) {
                    return st;
                }
                st = zw_device_check(&d, K, s->B, &v);
                if (st != ZW_OK) {
                    return st;
                }
                if (!v.stable) {
                    *outcome = ZW_BOX_REFUTED;
                    return ZW_OK;
                }
            }
        }
        if ((s->live == 0u) || (s->upper - *lower <= s->work->rel_tol * s->upper)) {
            /* no cell below the best plant, or the gap is closed */
            if (goal == ZW_BOX_GOAL_BOUND) {
                *outcome = ZW_BOX_CONVERGED;
            }
            if ((s->live == 0u) || (goal == ZW_BOX_GOAL_BOUND)) {
                return ZW_OK;
            }
        }
        if (s->evals + 2u > s->work->max_evals) {
            return ZW_OK;
        }
        if (s->live + 1u > s->work->capacity) {
            box_prune(s);
            if (s->live + 1u > s->work->capacity) {
                return ZW_OK;
            }
            continue;
        }
        parent = s->cells[0];
        if (!box_split_cell(s->T, &parent, &left, &right)) {
            return ZW_OK; /* cannot refine */
        }
        s->live -= 1u;
        s->cells[0] = s->cells[s->live];
        box_sift_down(s->cells, s->live, 0u);
        st = box_cell_bound(s->T, s->B, &left);
        if (st != ZW_OK) {
            return st;
        }
        st = box_cell_bound(s->T, s->B, &right);
        if (st != ZW_OK) {
            return st;
        }
        s->evals += 2u;
        /* a child's bound is at least its parent's (a cell's enclosure contains its parts') */
        left.bound = bx_max(left.bound, parent.bound);
        right.bound = bx_max(right.bound, parent.bound);
        st = box_add_cell(s, &left);
        if (st != ZW_OK) {
            return st;
        }
        st = box_add_cell(s, &right);
        if (st != ZW_OK) {
            return st;
        }
    }
}

/* ---- public functions ----------------------------------------------------------------- */


/* Fold and validate the box, the work and the gains (K when with_K), and start the search
 * (box_search_init).  Not inlined: the folded box (60 B in float) stays off the search's
 * chain (tools/footprint.sh), the search keeps only T. */
ZW_NOINLINE static zw_status box_setup(zw_box_search *s, const zw_plant_box *box, const zw_box_work *work,
                                        zw_real K, bool with_K, zw_real B)
{
    zw_plant_box f;
    zw_status st = box_fold_ideal(box, &f);
    if (st != ZW_OK) {
        return st;
    }
    st = box_validate_work(work);
    if (st != ZW_OK) {
        return st;
    }
    if (with_K) {
        st = bx_validate_gain(&f, K, true);
        if (st != ZW_OK) {
            return st;
        }
    }
    st = bx_validate_gain(&f, B, false);
    if (st != ZW_OK) {
        return st;
    }
    return box_search_init(s, &f, work, B);
}

static zw_status box_k_max(const zw_plant_box *box, zw_real B, const zw_box_work *work,
                           zw_box_bound *out)
{
    zw_box_search s;
    zw_box_outcome outcome;
    zw_real lower;
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = box_setup(&s, box, work, ZW_R(0.0), false, B);
    if (st != ZW_OK) {
        return st;
    }
    st = box_search_run(&s, ZW_BOX_GOAL_BOUND, ZW_R(0.0), &outcome, &lower);
    if (st != ZW_OK) {
        return st;
    }
    out->K_lower = lower;
    out->K_upper = s.upper;
    out->m_worst = s.m_worst;
    out->b_worst = s.b_worst;
    out->evals = s.evals;
    out->converged = (outcome == ZW_BOX_CONVERGED);
    out->k_worst = ZW_R(0.0);
    return ZW_OK;
}

zw_status zw_box_k_max(const zw_plant_box *box, zw_real B, const zw_box_work *work,
                       zw_box_bound *out)
{
    zw_status st = box_k_max(box, B, work, out); /* folds in box_setup */
    if (st != ZW_OK) {
        bx_fail_bound(out);
    }
    return st;
}

static void box_fail_box_verdict(zw_box_verdict *out)
{
    if (out == NULL) {
        return;
    }
    out->stable = false;
    out->decided = false;
    out->K_lower = ZW_R(0.0);
    out->m_worst = ZW_NAN;
    out->b_worst = ZW_NAN;
}

/* Decide (K, B) over the box; *outcome CERTIFIED, REFUTED or OPEN. */
static zw_status box_decide(const zw_plant_box *box, zw_real K, zw_real B, const zw_box_work *work,
                            zw_box_outcome *outcome, zw_box_search *s, zw_real *lower)
{
    zw_status st;
    st = box_search_init(s, box, work, B);
    if (st != ZW_OK) {
        return st;
    }
    if (!(K > ZW_R(0.0))) { /* K <= 0 is unstable at every plant */
        *lower = ZW_R(0.0);
        *outcome = ZW_BOX_REFUTED;
        return ZW_OK;
    }
    return box_search_run(s, ZW_BOX_GOAL_DECIDE, K, outcome, lower);
}

static zw_status box_check(const zw_plant_box *box, zw_real K, zw_real B, const zw_box_work *work,
                           zw_box_verdict *out)
{
    zw_box_search s;
    zw_box_outcome outcome;
    zw_real lower;
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = box_setup(&s, box, work, K, true, B);
    if (st != ZW_OK) {
        return st;
    }
    if (!(K > ZW_R(0.0))) { /* K <= 0 is unstable at every plant */
        lower = ZW_R(0.0);
        outcome = ZW_BOX_REFUTED;
    } else {
        st = box_search_run(&s, ZW_BOX_GOAL_DECIDE, K, &outcome, &lower);
        if (st != ZW_OK) {
            return st;
        }
    }
    out->stable = (outcome == ZW_BOX_CERTIFIED);
    out->decided = (outcome == ZW_BOX_CERTIFIED) || (outcome == ZW_BOX_REFUTED);
    out->K_lower = lower;
    out->m_worst = s.m_worst;
    out->b_worst = s.b_worst;
    return ZW_OK;
}

zw_status zw_box_check(const zw_plant_box *box, zw_real K, zw_real B, const zw_box_work *work,
                       zw_box_verdict *out)
{
    zw_status st = box_check(box, K, B, work, out); /* folds in box_setup */
    if (st != ZW_OK) {
        box_fail_box_verdict(out);
    }
    return st;
}

/* The certified lower bound of K_box(B) (a full bound search). */
static zw_status box_k_box_lower(const zw_plant_box *box, zw_real B, const zw_box_work *work,
                                 zw_box_search *s, zw_real *lower, bool *converged)
{
    zw_box_outcome outcome;
    zw_status st;
    st = box_search_init(s, box, work, B);
    if (st != ZW_OK) {
        return st;
    }
    st = box_search_run(s, ZW_BOX_GOAL_BOUND, ZW_R(0.0), &outcome, lower);
    if (st != ZW_OK) {
        return st;
    }
    *converged = (outcome == ZW_BOX_CONVERGED);
    return ZW_OK;
}

/* The B bracket where K_box can be positive: (-b_lo, the least B_mmax of the corners). */
static zw_status box_b_bracket(const zw_plant_box *box, zw_real *left, zw_real *right)
{
    zw_device d;
    zw_device_extremes x;
    zw_status st;
    int corner;
    zw_real least = ZW_INF;
    for (corner = 0; corner < 4; ++corner) {
        zw_real m = ((corner & 1) != 0) ? box->m_hi : box->m_lo;
        zw_real b = ((corner & 2) != 0) ? box->b_hi : box->b_lo;
        st = zw_device_init(&d, m, b, box->T);
        if (st != ZW_OK) {
            return st;
        }
        st = zw_device_extremes_compute(&d, &x);
        if (st != ZW_OK) {
            return st;
        }
        least = bx_min(least, x.B_mmax);
    }
    *left = -box->b_lo;
    *right = bx_up(least);
    return ZW_OK;
}

static void box_fail_extremes(zw_box_extremes *out)
{
    if (out == NULL) {
        return;
    }
    out->K_mmax = ZW_R(0.0);
    out->K_upper_at = ZW_R(0.0);
    out->K_mmax_upper = ZW_R(0.0);
    out->B_at = ZW_NAN;
    out->m_worst = ZW_NAN;
    out->b_worst = ZW_NAN;
    out->converged = false;
}

/* Golden-section search of B over the bracket (K_box is quasi-concave in B: its
 * superlevel sets are intersections of the plants' B intervals). */
static zw_status box_k_mmax(const zw_plant_box *box, const zw_box_work *work, zw_box_extremes *out)
{
    static const zw_real k_inv_phi = ZW_R(0.6180339887498948482);
    zw_box_search s;
    zw_device d;
    zw_device_extremes x;
    zw_real a, b, c1, c2, f1, f2, lower, best_b;
    bool conv;
    int step;
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = box_validate(box);
    if (st != ZW_OK) {
        return st;
    }
    st = box_validate_work(work);
    if (st != ZW_OK) {
        return st;
    }
    st = box_b_bracket(box, &a, &b);
    if (st != ZW_OK) {
        return st;
    }
    c1 = b - k_inv_phi * (b - a);
    c2 = a + k_inv_phi * (b - a);
    st = box_k_box_lower(box, c1, work, &s, &f1, &conv);
    if (st != ZW_OK) {
        return st;
    }
    st = box_k_box_lower(box, c2, work, &s, &f2, &conv);
    if (st != ZW_OK) {
        return st;
    }
    for (step = 0; step < ZW_BOX_GOLDEN_STEPS; ++step) {
        if (!(c2 - c1 > work->rel_tol * (ZW_FABS(c1) + ZW_FABS(c2)) + ZW_ETA)) {
            break;
        }
        if (f1 < f2) {
            a = c1;
            c1 = c2;
            f1 = f2;
            c2 = a + k_inv_phi * (b - a);
            st = box_k_box_lower(box, c2, work, &s, &f2, &conv);
            if (st != ZW_OK) {
                return st;
            }
        } else {
            b = c2;
            c2 = c1;
            f2 = f1;
            c1 = b - k_inv_phi * (b - a);
            st = box_k_box_lower(box, c1, work, &s, &f1, &conv);
            if (st != ZW_OK) {
                return st;
            }
        }
    }
    best_b = (f1 >= f2) ? c1 : c2;
    /* the final search at the chosen B gives the reported figures */
    st = box_k_box_lower(box, best_b, work, &s, &lower, &conv);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_device_init(&d, s.m_worst, s.b_worst, box->T);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_device_extremes_compute(&d, &x);
    if (st != ZW_OK) {
        return st;
    }
    out->K_mmax = lower;
    out->B_at = best_b;
    out->K_upper_at = s.upper;
    out->K_mmax_upper = x.K_mmax;
    out->m_worst = s.m_worst;
    out->b_worst = s.b_worst;
    out->converged = conv;
    return ZW_OK;
}

zw_status zw_box_k_mmax(const zw_plant_box *box, const zw_box_work *work, zw_box_extremes *out)
{
    zw_plant_box f;
    zw_status st = box_fold_ideal(box, &f);
    if (st == ZW_OK) {
        st = box_k_mmax(&f, work, out);
    }
    if (st != ZW_OK) {
        box_fail_extremes(out);
    }
    return st;
}

/* Is K certified at B for the whole box? */
static zw_status box_certified_at(const zw_plant_box *box, zw_real K, zw_real B,
                                  const zw_box_work *work, bool *yes)
{
    zw_box_search s;
    zw_box_outcome outcome;
    zw_real lower;
    zw_status st = box_decide(box, K, B, work, &outcome, &s, &lower);
    *yes = (st == ZW_OK) && (outcome == ZW_BOX_CERTIFIED);
    return st;
}

/* Bisection between a certified B (inside) and an uncertified one (outside): returns the
 * last certified B. */
static zw_status box_bisect_end(const zw_plant_box *box, zw_real K, const zw_box_work *work,
                                zw_real inside_start, zw_real outside_start, zw_real *end)
{
    int step;
    zw_status st;
    zw_real inside = inside_start, outside = outside_start;
    const zw_real scale = ZW_FABS(inside) + ZW_FABS(outside) + box->b_hi;
    for (step = 0; step < ZW_BOX_BISECT_STEPS; ++step) {
        bool yes;
        zw_real mid = inside + ZW_R(0.5) * (outside - inside);
        if (!(ZW_FABS(outside - inside) > work->rel_tol * scale) || (mid == inside) || (mid == outside)) {
            break;
        }
        st = box_certified_at(box, K, mid, work, &yes);
        if (st != ZW_OK) {
            return st;
        }
        if (yes) {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    *end = inside;
    return ZW_OK;
}

/* The middle of the nominal plant's B range at K as a start (*start), and whether it is
 * certified for the whole box (*yes; false when that range is empty). */
static zw_status box_nominal_start(const zw_plant_box *box, zw_real K, const zw_box_work *work,
                                   zw_real *start, bool *yes)
{
    zw_device d;
    zw_real nom_lo, nom_hi;
    bool any;
    zw_status st;
    *start = ZW_R(0.0);
    *yes = false;
    st = zw_device_init(&d, box->m_lo + ZW_R(0.5) * (box->m_hi - box->m_lo),
                        box->b_lo + ZW_R(0.5) * (box->b_hi - box->b_lo), box->T);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_device_b_range(&d, K, &nom_lo, &nom_hi, &any);
    if ((st == ZW_OK) && any) {
        *start = nom_lo + ZW_R(0.5) * (nom_hi - nom_lo);
        st = box_certified_at(box, K, *start, work, yes);
    }
    return st;
}

static zw_status box_b_range(const zw_plant_box *box, zw_real K, const zw_box_work *work,
                             zw_real *B_lo, zw_real *B_hi, bool *nonempty)
{
    zw_box_extremes x;
    zw_real lo_out, hi_out, start, lo, hi;
    bool yes;
    zw_status st;
    if ((B_lo == NULL) || (B_hi == NULL) || (nonempty == NULL)) {
        return ZW_ERR_NULL;
    }
    st = box_validate(box);
    if (st != ZW_OK) {
        return st;
    }
    st = box_validate_work(work);
    if (st != ZW_OK) {
        return st;
    }
    st = bx_validate_gain(box, K, true);
    if (st != ZW_OK) {
        return st;
    }
    *B_lo = ZW_R(0.0);
    *B_hi = ZW_R(0.0);
    *nonempty = false;
    if (!(K > ZW_R(0.0))) {
        return ZW_OK;
    }
    st = box_b_bracket(box, &lo_out, &hi_out);
    if (st != ZW_OK) {
        return st;
    }
    /* A certified start: the middle of the nominal plant's range, else the K_mmax B. */
    st = box_nominal_start(box, K, work, &start, &yes);
    if (st != ZW_OK) {
        return st;
    }
    if (!yes) {
        st = box_k_mmax(box, work, &x);
        if (st != ZW_OK) {
            return st;
        }
        start = x.B_at;
        if (!(K < x.K_mmax)) {
            return ZW_OK; /* nothing certified: empty */
        }
        st = box_certified_at(box, K, start, work, &yes);
        if (st != ZW_OK) {
            return st;
        }
        if (!yes) {
            return ZW_OK;
        }
    }
    st = box_bisect_end(box, K, work, start, lo_out, &lo);
    if (st != ZW_OK) {
        return st;
    }
    st = box_bisect_end(box, K, work, start, hi_out, &hi);
    if (st != ZW_OK) {
        return st;
    }
    *B_lo = lo;
    *B_hi = hi;
    *nonempty = true;
    return ZW_OK;
}

zw_status zw_box_b_range(const zw_plant_box *box, zw_real K, const zw_box_work *work,
                         zw_real *B_lo, zw_real *B_hi, bool *nonempty)
{
    zw_plant_box f;
    zw_status st = box_fold_ideal(box, &f);
    if (st == ZW_OK) {
        st = box_b_range(&f, K, work, B_lo, B_hi, nonempty);
    }
    if (st != ZW_OK) {
        zw_fail_interval(B_lo, B_hi, nonempty);
    }
    return st;
}
