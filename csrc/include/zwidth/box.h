/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* zwidth/box.h - certification over an uncertain plant (the paper's ideal loop).
 *
 * A plant box is every plant with m in [m_lo, m_hi] and b in [b_lo, b_hi], sampled every
 * T (fixed).  K_max is not monotone in m (paper Section IV), so the corners do not decide:
 * each function runs a branch and bound over the box on an interval enclosure of the
 * closed-form region (eq (10)) with outward rounding, never sampling alone.
 *
 * For a gain B, K_box(B) = min over the box of K_max(B; m, b), the largest K that is
 * stable at B for every plant of the box (the stable K at each plant is the open interval
 * (0, K_max(B; m, b)), so K_box(B) is a sup, not attained).
 *
 * Guarantees (docs/box.md): every K_lower is <= the true K_box(B) (proof: it is the least
 * of rigorous lower bounds on the cells of a partition of the box); "stable" means
 * 0 < K < K_lower; a B range [B_lo, B_hi] holds only B at which K was certified for the
 * whole box (the set of such B is an interval, so certified ends certify the range).
 * K_upper is K_max at the worst plant found (a point value, accurate to a few ulps), so
 * the true K_box(B) lies in [K_lower, K_upper]; the search stops when the relative gap
 * (K_upper - K_lower) / K_upper is at most rel_tol, or when its budget runs out.
 *
 * Firmware rules: no heap (the caller provides the cells of the work list), no recursion,
 * no global state, every loop bounded by the work's max_evals and capacity.
 */
#ifndef ZWIDTH_BOX_H
#define ZWIDTH_BOX_H

#include <stdbool.h>
#include <stdint.h>

#include "zwidth/device_loop.h"
#include "zwidth/plant_box.h"
#include "zwidth/real.h"
#include "zwidth/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Plants m in [m_lo, m_hi] (mass or inertia), b in [b_lo, b_hi], period T.  Valid:
 * finite, 0 < m_lo <= m_hi, 0 <= b_lo <= b_hi, T > 0, every plant's (m, b, T) accepted by
 * zw_device_init, and b_hi T / m_lo below ZW_BOX_DELTA_MAX.
 *
 * The plant-side parts (plant.h), added at the end so that a zero-initialised box (or a
 * positional {m_lo, m_hi, b_lo, b_hi, T}) is the ideal plant's box as before: a physical
 * stiffness k_p in [k_lo, k_hi], a coupled hand of mass m_h in [m_h_lo, m_h_hi], damping
 * b_h in [b_h_lo, b_h_hi] and stiffness k_h in [k_h_lo, k_h_hi] (every range 0 <= lo <= hi;
 * all 0: no part).  The plant depends on them only through M = m + m_h, Bp = b + b_h,
 * Kp = k_p + k_h, so the box is folded into ranges of M, Bp, Kp (sums rounded outward)
 * and a plant reported by the functions below (m_worst, b_worst, k_worst) is (M, Bp, Kp).
 * With stiffness (k_hi + k_h_hi > 0) only the general loop (zw_box_loop_*) certifies, and
 * the folded box must keep delta = Bp T / M and kappa = Kp T^2 / M at most ZW_BOX_KAPPA_MAX
 * (ZW_ERR_RANGE; the enclosure's series domain, docs/box.md); the closed-form functions
 * (zw_box_k_max, _check, _b_range, _k_mmax) refuse stiffness with ZW_ERR_ARG.  An actuator
 * lag range (tau_hi > 0) is not supported yet: ZW_ERR_ARG everywhere. */
typedef struct zw_plant_box {
    zw_real m_lo, m_hi;
    zw_real b_lo, b_hi;
    zw_real T;
    zw_real k_lo, k_hi;     /* physical stiffness k_p [N/m] */
    zw_real m_h_lo, m_h_hi; /* the hand's mass */
    zw_real b_h_lo, b_h_hi; /* the hand's damping */
    zw_real k_h_lo, k_h_hi; /* the hand's stiffness */
    zw_real tau_lo, tau_hi; /* actuator lag [s]: must be 0 (not supported yet) */
} zw_plant_box;

/* Largest normalized delta and kappa of a box with stiffness (plant_box.h). */
#define ZW_BOX_KAPPA_MAX ZW_PLANT_ENCLOSE_MAX

/* The box folded into M, Bp, Kp ranges (m_lo.. = M, b_lo.. = Bp, k_lo.. = Kp, the hand's
 * fields 0; sums rounded outward) and validated: zw_box_validate's errors (then *folded is
 * all NaN, a box every function refuses). */
zw_status zw_box_fold(const zw_plant_box *box, zw_plant_box *folded);

/* Largest normalized damping b T / m a box may reach (far beyond any real device; keeps
 * every bound of the enclosure finite in both precisions). */
#define ZW_BOX_DELTA_MAX ZW_R(1.0e6)

/* One cell of the work list: a sub-box and a lower bound of K_max over it. */
typedef struct zw_box_cell {
    zw_real m_lo, m_hi, b_lo, b_hi;
    zw_real bound;
} zw_box_cell;

/* Caller-provided work list and budget.  capacity >= ZW_BOX_MIN_CELLS; max_evals in
 * 1..ZW_BOX_MAX_EVALS (cell bounds per search); rel_tol in [0, 1). */
typedef struct zw_box_work {
    zw_box_cell *cells;
    uint_least32_t capacity;
    uint_least32_t max_evals;
    zw_real rel_tol;
} zw_box_work;

#define ZW_BOX_MIN_CELLS 4u
#define ZW_BOX_MAX_EVALS 10000000u
/* Defaults of zw_box_work_init: a 1e-6 relative gap costs ~1000 cells where K_max has an
 * interior minimum in m (first-order enclosure, quadratic valley); float stops at 1e-4. */
#define ZW_BOX_DEFAULT_EVALS 20000u
#ifdef ZW_REAL_FLOAT
#define ZW_BOX_DEFAULT_REL_TOL ZW_R(1.0e-4)
#else
#define ZW_BOX_DEFAULT_REL_TOL ZW_R(1.0e-6)
#endif

/* Fills *work with cells, capacity and the defaults above (ZW_ERR_NULL, ZW_ERR_ARG for
 * cells NULL or capacity < ZW_BOX_MIN_CELLS). */
zw_status zw_box_work_init(zw_box_work *work, zw_box_cell *cells, uint_least32_t capacity);

/* The box's own errors: ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_MASS (m_lo <= 0),
 * ZW_ERR_DAMPING (b_lo < 0), ZW_ERR_PERIOD (T <= 0), ZW_ERR_BOX (m_lo > m_hi or
 * b_lo > b_hi), ZW_ERR_RANGE (a corner refused by zw_device_init, or b_hi T / m_lo above
 * ZW_BOX_DELTA_MAX). */
zw_status zw_box_validate(const zw_plant_box *box);

typedef struct zw_box_bound {
    zw_real K_lower;          /* certified: <= min over the box of K_max(B) */
    zw_real K_upper;          /* K_max(B) at the worst plant found */
    zw_real m_worst, b_worst; /* that plant */
    uint_least32_t evals;     /* cell bounds computed */
    bool converged;           /* relative gap <= rel_tol */
    zw_real k_worst;          /* that plant's Kp (0 without stiffness) */
} zw_box_bound;

/* Errors of the functions below: those of zw_box_validate, ZW_ERR_NULL (work, its cells,
 * an output), ZW_ERR_ARG (work's capacity, max_evals or rel_tol out of range), ZW_ERR_NAN /
 * ZW_ERR_INF (K, B), ZW_ERR_RANGE (a gain that overflows once normalized).  Fail-safe
 * (status.h): on each error every non-NULL output certifies nothing: limits 0, verdicts
 * not stable and not decided, ranges empty, plants NaN, flags false, counts 0. */

/* min over the box of K_max(B): sup K stable at B for every plant. */
zw_status zw_box_k_max(const zw_plant_box *box, zw_real B, const zw_box_work *work,
                       zw_box_bound *out);

typedef struct zw_box_verdict {
    bool stable;              /* certified: 0 < K < K_max(B) for every plant of the box */
    bool decided;             /* false: budget spent before a proof either way (stable false) */
    zw_real K_lower;          /* the certified lower bound of K_box(B) reached */
    zw_real m_worst, b_worst; /* unstable: a plant where (K, B) is unstable (zw_device_check);
                                 stable: the plant of least K_max found */
} zw_box_verdict;

/* Is (K, B) stable for every plant of the box?  Stops as soon as either is proven. */
zw_status zw_box_check(const zw_plant_box *box, zw_real K, zw_real B, const zw_box_work *work,
                       zw_box_verdict *out);

/* A closed interval [B_lo, B_hi] of B at which K is stable for every plant of the box,
 * inside the true (open) one; its ends are found by bisection to rel_tol of the range.
 * nonempty false (B_lo = B_hi = 0) when no B could be certified (K <= 0, K at or above
 * the box's K_mmax, or too close to it for the budget). */
zw_status zw_box_b_range(const zw_plant_box *box, zw_real K, const zw_box_work *work,
                         zw_real *B_lo, zw_real *B_hi, bool *nonempty);

typedef struct zw_box_extremes {
    zw_real K_mmax;           /* certified: K_box(B_at) >= K_mmax, so every K in (0, K_mmax)
                                 is stable at B_at for every plant */
    zw_real B_at;             /* the B found (golden-section search of K_box) */
    zw_real K_upper_at;       /* K_max(B_at) at the worst plant found */
    zw_real K_mmax_upper;     /* K_mmax of that plant: no B does better for the whole box
                                 (up to a few ulps) */
    zw_real m_worst, b_worst; /* the worst plant at B_at */
    bool converged;           /* every search at the final B converged */
} zw_box_extremes;

/* The largest K that some single B makes stable for every plant: max over B of K_box(B). */
zw_status zw_box_k_mmax(const zw_plant_box *box, const zw_box_work *work, zw_box_extremes *out);

/* ---- the general loop (box_loop.c) ----------------------------------------------------
 *
 * The same questions for the loop a drive runs (device_loop.h: delay, Tustin, low-pass,
 * moving average), certified by a different enclosure (docs/box.md): over a sub-box of
 * plants, gains and a range of B, the bilinear image P(s) of the characteristic polynomial
 * is enclosed coefficient by coefficient (zw_plant_enclose for the plant, the gains
 * alpha = K T^2 / m and beta = B T / m over the sub-box's K and B ranges, outward
 * rounding), and the interval polynomial is proved Hurwitz by Kharitonov's theorem: its
 * four Kharitonov polynomials (the constant coefficient, alpha (c1 + c2) Dv(1) > 0, runs
 * down to 0+, which takes K1 / s and K4 / s instead of K1, K4) each pass a guarded Routh
 * test.  A sub-box that does not pass is split (m relative, b through delta, B), depth
 * first, on the caller's explicit stack of cells (m relative, b through delta, K and B
 * relative to the gains asked for); no recursion, no heap.
 *
 * "Certified at (K, B)" means more than (K, B) stable: every K' in (0, K] is stable at B
 * for every plant of the box (the gain can be ramped up from 0), so K_lower below is a
 * lower bound of the infimum over the box of K_max(B; m, b) (device_loop.h) even where a
 * plant's stable K are not one interval.  With stiffness the plant is enclosed over the
 * sub-box's (delta, kappa) by zw_plant_enclose2 and Kp is one more dimension of the
 * sub-boxes; a hand is folded into M, Bp, Kp (zw_box_fold).  No lag yet.
 */

/* A sub-box of plants and of the gains (K_lo = 0 stands for K -> 0+). */
typedef struct zw_box_loop_cell {
    zw_real m_lo, m_hi, b_lo, b_hi, K_lo, K_hi, B_lo, B_hi;
    zw_real k_lo, k_hi; /* Kp */
} zw_box_loop_cell;

/* An interval [lo, hi] (the scratch's polynomials). */
typedef struct zw_box_loop_iv {
    zw_real lo, hi;
} zw_box_loop_iv;

/* Scratch memory of the functions below (the large arrays that would otherwise sit on the
 * stack): a plant's loop for the point checks, the velocity estimate and a sub-box's
 * polynomials as intervals, a Routh row.  Owned by the caller (static storage, not an MCU's
 * stack: ~1.9 KB float, 3.6 KB double), needs no initialisation, holds nothing between
 * calls; one per concurrent caller.  Members private to the library. */
typedef struct zw_box_loop_scratch {
    zw_device_loop dl;
    zw_box_loop_iv dvs[ZW_LOOP_MAX_AVERAGE + 1u], nvs[ZW_LOOP_MAX_AVERAGE + 1u];
    zw_box_loop_iv poly[3][ZW_LOOP_MAX_DEGREE + 2u];
    zw_real row[ZW_LOOP_MAX_DEGREE + 1u], row_err[ZW_LOOP_MAX_DEGREE + 1u];
} zw_box_loop_scratch;

/* Caller-provided stack of cells, scratch and budget: capacity >= ZW_BOX_LOOP_MIN_CELLS
 * (depth first: a capacity of 64 per halving of the gap is plenty), max_evals in
 * 1..ZW_BOX_MAX_EVALS (cell tests per certification), rel_tol in [0, 1) (the K and B
 * bisections stop at that relative width). */
typedef struct zw_box_loop_work {
    zw_box_loop_cell *cells;
    zw_box_loop_scratch *scratch;
    uint_least32_t capacity;
    uint_least32_t max_evals;
    zw_real rel_tol;
} zw_box_loop_work;

#define ZW_BOX_LOOP_MIN_CELLS 8u
#define ZW_BOX_LOOP_DEFAULT_EVALS 20000u
#ifdef ZW_REAL_FLOAT
#define ZW_BOX_LOOP_DEFAULT_REL_TOL ZW_R(1.0e-3)
#else
#define ZW_BOX_LOOP_DEFAULT_REL_TOL ZW_R(1.0e-4)
#endif

/* ZW_ERR_NULL (also scratch), ZW_ERR_ARG (capacity < ZW_BOX_LOOP_MIN_CELLS). */
zw_status zw_box_loop_work_init(zw_box_loop_work *work, zw_box_loop_cell *cells,
                                uint_least32_t capacity, zw_box_loop_scratch *scratch);

typedef struct zw_box_loop_verdict {
    bool stable;              /* certified: every K' in (0, K] stable at B for every plant */
    bool decided;             /* stable, or refuted (a plant where (K, B) is surely unstable) */
    zw_real m_worst, b_worst; /* refuted: that plant; else the centre of the last sub-box not
                                 certified (NaN when every sub-box was) */
    uint_least32_t evals;     /* sub-box tests */
    zw_real k_worst;          /* that plant's Kp */
} zw_box_loop_verdict;

/* Errors of the functions below: those of zw_box_validate and of zw_device_loop_init at the
 * box's centre (spec), ZW_ERR_NULL (spec, ws, work, its cells, an output), ZW_ERR_ARG
 * (work out of range), ZW_ERR_NAN / ZW_ERR_INF (K, B), ZW_ERR_RANGE (a gain that overflows
 * once normalized).  Fail-safe: verdicts not stable, not decided; limits 0; ranges empty;
 * (work's scratch NULL: ZW_ERR_NULL.)
 * plants NaN; counts 0. */
zw_status zw_box_loop_check(const zw_plant_box *box, const zw_device_loop_spec *spec,
                            zw_loop_workspace *ws, zw_real K, zw_real B,
                            const zw_box_loop_work *work, zw_box_loop_verdict *out);

/* zw_box_bound's fields: K_lower certified (every K in (0, K_lower] stable at B for every
 * plant), K_upper zw_device_loop_k_max at the worst plant found (the true infimum is below
 * it, up to that value's own rounding band), that plant, evals (sub-box tests and bisection
 * steps), converged ((K_upper - K_lower) <= rel_tol K_upper). */
typedef zw_box_bound zw_box_loop_bound;

/* inf over the box of K_max(B): bisection on K between 0 and the least point value found,
 * each step a certification of (0, K] over the box. */
zw_status zw_box_loop_k_max(const zw_plant_box *box, const zw_device_loop_spec *spec,
                            zw_loop_workspace *ws, zw_real B, const zw_box_loop_work *work,
                            zw_box_loop_bound *out);

/* A closed interval [B_lo, B_hi] every B of which is certified at K (every K' in (0, K] is
 * stable for every plant): grown from the middle of the centre plant's B range by
 * bisection, each piece certified as a whole (B is a dimension of the sub-boxes).
 * nonempty false when none could be certified. */
zw_status zw_box_loop_b_range(const zw_plant_box *box, const zw_device_loop_spec *spec,
                              zw_loop_workspace *ws, zw_real K, const zw_box_loop_work *work,
                              zw_real *B_lo, zw_real *B_hi, bool *nonempty);

typedef struct zw_box_loop_extremes {
    zw_real K_mmax;           /* certified: every K in (0, K_mmax] is stable at B_at for every plant */
    zw_real B_at;             /* the B found (golden-section search of the box's K_max over
                                 the centre plant's certified B range at K -> 0+) */
    zw_real K_upper_at;       /* zw_device_loop_k_max(B_at) at the worst plant found */
    zw_real m_worst, b_worst; /* that plant */
    uint_least32_t evals;     /* sub-box tests, every search */
    bool converged;           /* the search at B_at converged */
    zw_real k_worst;          /* that plant's Kp */
} zw_box_loop_extremes;

/* The largest K that one B makes stable for every plant (max over B of zw_box_loop_k_max's
 * K_lower; whatever B the search ends on, K_mmax is certified there).  Errors as above, and
 * ZW_ERR_DOMAIN when the centre plant has no stable B (every field 0, plants NaN). */
zw_status zw_box_loop_k_mmax(const zw_plant_box *box, const zw_device_loop_spec *spec,
                             zw_loop_workspace *ws, const zw_box_loop_work *work,
                             zw_box_loop_extremes *out);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_BOX_H */
