/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* The certification policy of the register map, zwidth/regmap_policy.h: what SEAL checks
 * in a block, the rules a gain pair must pass, and the live-limit registers.
 *
 * The live-limit registers are cached in rm->live and recomputed after every accepted
 * write (zw_rm_live_all), rather than computed on read: a read then never runs the core,
 * and the deepest chains into the core start from the public function's tail call instead
 * of below a read loop's frame, which keeps the worst stack chain on the Cortex-M4F within
 * the project's 256 bytes (see ZW_NOINLINE).
 */
#include "zwidth/regmap_policy.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "regmap_internal.h"


/* The ideal loop (delay 0, backward difference, no filter): certified by the closed form of
 * region.h / extremes.h, as in map version 1; any other by the general loop (loop.h). */
static bool ideal_loop(const zw_regmap *rm)
{
    return (rm->loop.loop.spec.delay == 0u) && (rm->loop.loop.spec.filter == ZW_VFILTER_NONE) &&
           (rm->loop.loop.spec.differentiator == ZW_DIFF_BACKWARD);
}

/* x is a whole number in [0, max]. */
static bool whole_in(float x, float max)
{
    return (x >= 0.0f) && (x <= max) && ((float)(unsigned)x == x);
}

/* The loop fields of the staged block, each to its named reason (regmap.h). */
static zw_reason check_loop_fields(const zw_regmap *rm)
{
    const float kind = zw_rm_staged_float(rm, F_VFILTER), param = zw_rm_staged_float(rm, F_VF_PARAM);
    bool param_ok;
    if (!whole_in(zw_rm_staged_float(rm, F_DELAY), (float)ZW_LOOP_MAX_DELAY)) {
        return ZW_REASON_BAD_DELAY;
    }
    if (!whole_in(kind, 2.0f)) {
        return ZW_REASON_BAD_FILTER;
    }
    if (kind == 0.0f) { /* none: no parameter */
        param_ok = param == 0.0f;
    } else if (kind == 1.0f) { /* low-pass: a cut-off */
        param_ok = param > 0.0f;
    } else { /* moving average: a length */
        param_ok = whole_in(param, (float)ZW_LOOP_MAX_AVERAGE) && (param >= 1.0f);
    }
    if (!param_ok) {
        return ZW_REASON_BAD_FILTER_PARAM;
    }
    if (!whole_in(zw_rm_staged_float(rm, F_DIFF), 1.0f)) {
        return ZW_REASON_BAD_DIFFERENTIATOR;
    }
    return ZW_REASON_NONE;
}

/* The loop spec of a block's fields f (checked: check_loop_fields).  False (never, for a
 * checked block) when a field cannot be converted. */
static bool spec_of(const float f[ZW_CERT_FIELDS], zw_device_loop_spec *spec_out)
{
    zw_device_loop_spec spec;
    (void)memset(&spec, 0, sizeof spec);
    spec.differentiator = (f[F_DIFF] == 1.0f) ? ZW_DIFF_TUSTIN : ZW_DIFF_BACKWARD;
    if (f[F_VFILTER] == 1.0f) {
        spec.filter = ZW_VFILTER_LOWPASS;
    } else if (f[F_VFILTER] == 2.0f) {
        spec.filter = ZW_VFILTER_AVERAGE;
    } else {
        spec.filter = ZW_VFILTER_NONE;
    }
    /* Never true (check_loop_fields passed these fields, now or when the block was sealed);
     * checked again so that the float-to-unsigned conversions below are defined for any
     * block, which the run-time-error analysis cannot relate to the earlier check. */
    if (!whole_in(f[F_DELAY], (float)ZW_LOOP_MAX_DELAY) ||
        ((spec.filter == ZW_VFILTER_AVERAGE) && !whole_in(f[F_VF_PARAM], (float)ZW_LOOP_MAX_AVERAGE))) {
        return false;
    }
    spec.delay = (unsigned)f[F_DELAY];
    spec.cutoff_hz = (spec.filter == ZW_VFILTER_LOWPASS) ? (zw_real)f[F_VF_PARAM] : ZW_R(0.0);
    spec.pole = ZW_R(0.0);
    spec.average = (spec.filter == ZW_VFILTER_AVERAGE) ? (unsigned)f[F_VF_PARAM] : 0u;
    *spec_out = spec;
    return true;
}

/* The fields of block c, in register order. */
static void fields_of(const zw_cert *c, float f[ZW_CERT_FIELDS])
{
    unsigned i;
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        f[i] = zw_cert_field(c, i);
    }
}

/* Build rm->loop from the staged block (staged) or the sealed one; the fields were checked.
 * Reason: BAD_FILTER_PARAM for a cut-off the pole cannot be formed from, BAD_POLICY for
 * the plant.  The loop's plant is the block's (M, B): with a ranged block its lower ends. */
static zw_reason build_loop(zw_regmap *rm, bool staged)
{
    zw_device_loop_spec spec;
    float f[ZW_CERT_FIELDS];
    unsigned i;
    zw_status st;
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        f[i] = staged ? zw_rm_staged_float(rm, i) : zw_cert_field(&rm->sealed, i);
    }
    rm->kmax_cached = 0u;
    if (!spec_of(f, &spec)) {
        return ZW_REASON_BAD_POLICY;
    }
    st = zw_device_loop_init(&rm->loop, (zw_real)f[F_M], (zw_real)f[F_B], (zw_real)f[F_T], &spec);
    if (st == ZW_OK) {
        return ZW_REASON_NONE;
    }
    return (st == ZW_ERR_FILTER) ? ZW_REASON_BAD_FILTER_PARAM : ZW_REASON_BAD_POLICY;
}

/* The largest float not above x (x not NaN, at most FLT_MAX). */
static float float_down(zw_real x)
{
    float f = zw_rm_to_float(x);
    if ((zw_real)f > x) {
        f = ZW_NEXTAFTERF(f, -ZW_HUGE_VALF);
    }
    return f;
}

/* ---- the plant box (map version 4) --------------------------------------------------------- */

/* M_HI and B_HI both 0: the point block's shorthand (a zw_cert whose new fields are left 0). */
static bool range_absent(float m_hi, float b_hi)
{
    return (m_hi == 0.0f) && (b_hi == 0.0f);
}

/* A block with these plant fields describes a box of plants rather than the one plant
 * (m, b). */
static bool plant_ranged(float m, float m_hi, float b, float b_hi)
{
    return !range_absent(m_hi, b_hi) && ((m_hi != m) || (b_hi != b));
}

/* Block c certifies a box of plants. */
static bool cert_ranged(const zw_cert *c)
{
    return plant_ranged(c->m, c->m_hi, c->b, c->b_hi);
}

/* The box of a block's fields f (zero-initialised first: fields added to zw_plant_box later
 * default to absent). */
static void box_of(const float f[ZW_CERT_FIELDS], zw_plant_box *box)
{
    (void)memset(box, 0, sizeof *box);
    box->m_lo = (zw_real)f[F_M];
    box->m_hi = (zw_real)f[F_M_HI];
    box->b_lo = (zw_real)f[F_B];
    box->b_hi = (zw_real)f[F_B_HI];
    box->T = (zw_real)f[F_T];
}

/* The box and loop of block c (its fields checked) and the search's work list in the map,
 * false if any of them cannot be formed (then nothing may be certified). */
static bool cert_box_setup(zw_regmap *rm, const zw_cert *c, zw_plant_box *box,
                           zw_device_loop_spec *spec, zw_box_loop_work *work)
{
    float f[ZW_CERT_FIELDS];
    fields_of(c, f);
    box_of(f, box);
    if (zw_box_loop_work_init(work, rm->box_cells, ZW_REGMAP_BOX_CELLS, &rm->box_scratch) != ZW_OK) {
        return false;
    }
    work->max_evals = ZW_REGMAP_BOX_EVALS;
    work->rel_tol = ZW_REGMAP_BOX_REL_TOL;
    return spec_of(f, spec);
}

/* The verified certificate of block c, NULL when c is a point block or has none: the one in
 * force for the sealed block, the candidate for a block being admitted. */
static const zw_box_cert *staircase_of(const zw_regmap *rm, const zw_cert *c)
{
    if (!cert_ranged(c)) {
        return NULL;
    }
    if (c == &rm->sealed) {
        return (rm->box_cert_valid != 0u) ? &rm->box_cert : NULL;
    }
    return (rm->box_cert_candidate_valid != 0u) ? &rm->box_cert_candidate : NULL;
}

/* Box K_max at B: a certified lower bound of the infimum over the box (every K in
 * (0, K_lower] stable at B for every plant); 0 with an error status when it fails. */
ZW_NOINLINE static zw_status cert_box_k_max(zw_regmap *rm, const zw_cert *c, float B, zw_real *k_max)
{
    zw_plant_box box;
    zw_device_loop_spec spec;
    zw_box_loop_work work;
    zw_box_loop_bound bound;
    zw_status st;
    const zw_box_cert *stairs = staircase_of(rm, c);
    *k_max = ZW_R(0.0);
    if (stairs != NULL) { /* the level at B: certified for every plant */
        float level = 0.0f; /* set by the lookup; initialized for the analysis (docs/eva.md) */
        bool inside = (level > 0.0f);
        zw_box_cert_level(stairs, B, &level, &inside);
        *k_max = (zw_real)level;
        /* a verified certificate's levels are all > 0, and outside it reads 0: so the level
         * alone says whether B is inside (and a 0 is refused either way) */
        return (level > 0.0f) ? ZW_OK : ZW_ERR_DOMAIN;
    }
    if (!cert_box_setup(rm, c, &box, &spec, &work)) {
        return ZW_ERR_ARG;
    }
    st = zw_box_loop_k_max(&box, &spec, &rm->ws, (zw_real)B, &work, &bound);
    if (st == ZW_OK) {
        *k_max = bound.K_lower;
    }
    return st;
}

/* K / sigma rounded up (K >= 0, sigma in (0, 1]): sigma 1 gives K itself; otherwise the
 * quotient plus one ulp of it, at least its exact value. */
static zw_real k_over_sigma_up(float K, float sigma)
{
    zw_real q;
    if (sigma == 1.0f) {
        return (zw_real)K;
    }
    q = (zw_real)K / (zw_real)sigma;
    return q + (q * ZW_R(2.0) * ZW_UNIT_ROUNDOFF);
}

/* The stability and sigma rules over the box of block c (regmap_policy.h): (0, K / sigma]
 * certified at B for every plant, else the reason.  Nothing of rm but scratch changes. */
ZW_NOINLINE static zw_reason cert_box_certify(zw_regmap *rm, const zw_cert *c, float K, float B)
{
    zw_plant_box box;
    zw_device_loop_spec spec;
    zw_box_loop_work work;
    zw_box_loop_verdict v;
    zw_status st;
    if (staircase_of(rm, c) != NULL) { /* every K' in (0, level] is proven at B: K / sigma within it */
        zw_real level;
        if (cert_box_k_max(rm, c, B, &level) != ZW_OK) { /* B outside the staircase */
            return ZW_REASON_OUTSIDE_CERT;
        }
        if (!(K > 0.0f)) { /* K <= 0 has a pole at or outside z = 1 without stiffness */
            return ZW_REASON_UNSTABLE;
        }
        return (k_over_sigma_up(K, c->sigma) <= level) ? ZW_REASON_NONE : ZW_REASON_ABOVE_SIGMA;
    }
    if (!cert_box_setup(rm, c, &box, &spec, &work)) {
        return ZW_REASON_UNSTABLE;
    }
    st = zw_box_loop_check(&box, &spec, &rm->ws, k_over_sigma_up(K, c->sigma), (zw_real)B, &work, &v);
    if (st != ZW_OK) { /* an error of the core counts against the pair */
        return ZW_REASON_UNSTABLE;
    }
    if (v.stable) {
        return ZW_REASON_NONE;
    }
    if (!v.decided) {
        return ZW_REASON_BOX_BUDGET;
    }
    if (c->sigma == 1.0f) {
        return ZW_REASON_UNSTABLE;
    }
    /* refuted at K / sigma: is K itself unstable at the plant found?  (a one-plant box) */
    box.m_lo = v.m_worst;
    box.m_hi = v.m_worst;
    box.b_lo = v.b_worst;
    box.b_hi = v.b_worst;
    st = zw_box_loop_check(&box, &spec, &rm->ws, (zw_real)K, (zw_real)B, &work, &v);
    return ((st == ZW_OK) && v.decided && !v.stable) ? ZW_REASON_UNSTABLE : ZW_REASON_ABOVE_SIGMA;
}

/* K_MMAX and its B, of the plant and loop in force (the extremes in a frame of their own,
 * only at SEAL and init: with a general loop they cost milliseconds).  *any: some gains are
 * stable (K_mmax > 0). */
ZW_NOINLINE static void live_extremes(zw_regmap *rm, const zw_cert *c, bool *any)
{
    zw_status st;
    zw_real K = ZW_R(0.0), B = ZW_R(0.0);
    const zw_box_cert *stairs = staircase_of(rm, c);
    if (stairs != NULL) { /* the highest level, in the middle of its step */
        float Kf = 0.0f, Bf = 0.0f;
        zw_box_cert_k_mmax(stairs, &Kf, &Bf);
        K = (zw_real)Kf;
        B = (zw_real)Bf;
        st = ZW_OK;
    } else if (cert_ranged(c)) { /* certified for the whole box (box.h) */
        zw_plant_box box;
        zw_device_loop_spec spec;
        zw_box_loop_work work;
        zw_box_loop_extremes e;
        st = ZW_ERR_ARG;
        if (cert_box_setup(rm, c, &box, &spec, &work)) {
            st = zw_box_loop_k_mmax(&box, &spec, &rm->ws, &work, &e);
            K = e.K_mmax;
            B = e.B_at;
        }
    } else if (ideal_loop(rm)) {
        zw_device_extremes e;
        st = zw_device_extremes_compute(&rm->loop.dev, &e);
        K = e.K_mmax;
        B = e.B_at_K_mmax;
    } else {
        zw_device_loop_extremes e;
        st = zw_device_loop_extremes_compute(&rm->loop, &rm->ws, &e);
        K = e.K_mmax;
        B = e.B_at_K_mmax;
    }
    *any = (st == ZW_OK) && (K > ZW_R(0.0));
    rm->live[L_K_MMAX] = (st == ZW_OK) ? zw_rm_to_float(K) : QUIET_NAN_F;
    if ((st == ZW_OK) && cert_ranged(c)) { /* a box bound: rounded down, never above */
        rm->live[L_K_MMAX] = float_down(K);
    }
    rm->live[L_B_AT_KMMAX] = (st == ZW_OK) ? zw_rm_to_float(B) : QUIET_NAN_F;
}

/* SEAL's policy part (after the self-test and the CRC): check the staged block and build
 * rm->loop from it.  A refused block leaves the one in force
 * as it was: the loop is rebuilt from the sealed block when building the staged one
 * failed (zw_device_loop_init leaves a refused plant NaN), and the live extremes are only
 * recomputed for a block that is sealed. */
static bool some_pair_usable(zw_regmap *rm, const zw_cert *c);

/* A nonzero float of magnitude below FLT_MIN. */
static bool subnormal_f(float x)
{
    return x != 0.0f && x > -FLT_MIN && x < FLT_MIN;
}

/* x within tol (relative) of nominal, decided in zw_real. */
static bool within_tol(float x, float nominal, float tol)
{
    zw_real n = (zw_real)nominal, d = (zw_real)tol * (n < ZW_R(0.0) ? -n : n);
    return (zw_real)x >= n - d && (zw_real)x <= n + d;
}

/* The block's fields f (register order) against the factory ceilings (regmap_policy.h). */
static zw_reason check_ceilings(const zw_ceilings *k, const float f[ZW_CERT_FIELDS])
{
    if (f[F_SIGMA] > k->sigma_max || f[F_R] > k->r_max || f[F_K_MIN] < k->k_min ||
        f[F_K_MAX] > k->k_max || f[F_B_MIN] < k->b_min || f[F_B_MAX] > k->b_max ||
        f[F_DK_MAX] > k->dk_max || f[F_DB_MAX] > k->db_max) {
        return ZW_REASON_ABOVE_CEILING;
    }
    if (!within_tol(f[F_M], k->m, k->plant_tol) || !within_tol(f[F_B], k->b, k->plant_tol) ||
        !within_tol(f[F_T], k->T, k->plant_tol)) {
        return ZW_REASON_PLANT_MISMATCH;
    }
    /* each end of the ranges too (the point shorthand has none) */
    if (!range_absent(f[F_M_HI], f[F_B_HI]) &&
        (!within_tol(f[F_M_HI], k->m, k->plant_tol) || !within_tol(f[F_B_HI], k->b, k->plant_tol))) {
        return ZW_REASON_PLANT_MISMATCH;
    }
    return ZW_REASON_NONE;
}

/* The block's loop against the one the firmware runs (the ceilings'), checked after the
 * loop fields' own rules so that a malformed loop gets its named reason. */
static zw_reason check_firmware_loop(const zw_ceilings *k, const float f[ZW_CERT_FIELDS])
{
    if (f[F_DELAY] != k->delay || f[F_VFILTER] != k->vfilter || f[F_VF_PARAM] != k->vf_param ||
        f[F_DIFF] != k->differentiator) {
        return ZW_REASON_LOOP_MISMATCH;
    }
    return ZW_REASON_NONE;
}

/* The staged block's own rules, before the loop is built (regmap_policy.h, in its order). */
static zw_reason check_block_fields(const zw_regmap *rm, const float f[ZW_CERT_FIELDS])
{
    unsigned i;
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        if (!zw_rm_finite_f(f[i])) {
            return ZW_REASON_BAD_POLICY;
        }
    }
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        if (subnormal_f(f[i])) {
            return ZW_REASON_SUBNORMAL;
        }
    }
    if (!(f[F_SIGMA] > 0.0f && f[F_SIGMA] <= 1.0f) || !(f[F_R] > 0.0f && f[F_R] <= 1.0f)) {
        return ZW_REASON_BAD_POLICY;
    }
    /* a plant that cannot exist is a bad policy, not a mismatch with the nameplate */
    if (!(f[F_M] > 0.0f) || !(f[F_T] > 0.0f) || !(f[F_B] >= 0.0f)) {
        return ZW_REASON_BAD_POLICY;
    }
    /* the ranges: upper ends not below the lower ones, every corner a valid plant */
    if (!range_absent(f[F_M_HI], f[F_B_HI])) {
        zw_plant_box box;
        box_of(f, &box);
        if (zw_box_validate(&box) != ZW_OK) {
            return ZW_REASON_BAD_POLICY;
        }
    }
    if (!(f[F_K_MIN] <= f[F_K_MAX]) || !(f[F_B_MIN] <= f[F_B_MAX])) {
        return ZW_REASON_BAD_POLICY;
    }
    if (!(f[F_DK_MAX] > 0.0f) || !(f[F_DB_MAX] > 0.0f)) {
        return ZW_REASON_BAD_POLICY;
    }
    /* After a seal the output is off, (0, 0), and steps count from there: refuse a block
     * from which no pair is within the bounds and one step (it could never be used). */
    if (f[F_K_MIN] > f[F_DK_MAX] || f[F_B_MIN] > f[F_DB_MAX] || f[F_B_MAX] < -f[F_DB_MAX]) {
        return ZW_REASON_BAD_POLICY;
    }
    if (rm->has_ceilings != 0u) {
        const zw_reason why = check_ceilings(&rm->ceilings, f);
        if (why != ZW_REASON_NONE) {
            return why;
        }
    }
    /* no box form of the radius rule here: a ranged block must have r = 1 */
    if (plant_ranged(f[F_M], f[F_M_HI], f[F_B], f[F_B_HI]) && (f[F_R] != 1.0f)) {
        return ZW_REASON_BOX_RADIUS;
    }
    return ZW_REASON_NONE;
}

/* The staged certificate words (ZW_REG_BOX_CERT; power-up and restore put theirs there
 * too), against the staged block c: all 0 is none; otherwise decoded into the candidate,
 * which must encode back to the same words (so the drive holds exactly what the MAC
 * covered) and pass verification (bounded, box_cert.h).  The certificate in force is not
 * touched: the caller installs the candidate once the whole block is admitted. */
ZW_NOINLINE static zw_reason admit_box_cert(zw_regmap *rm, const zw_cert *c)
{
    zw_plant_box box;
    zw_device_loop_spec spec;
    zw_box_loop_work work;
    zw_box_cert_fault fault = ZW_BOX_CERT_BAD_HEADER;
    uint_least32_t leaves = 0u;
    unsigned i, any_bits = 0u;
    rm->box_cert_candidate_valid = 0u;
    for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
        any_bits |= (unsigned)rm->staged_box_cert[i];
    }
    if (any_bits == 0u) { /* all 0: no certificate */
        return ZW_REASON_NONE;
    }
    zw_box_cert_decode(rm->staged_box_cert, &rm->box_cert_candidate);
    for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
        if (zw_box_cert_word(&rm->box_cert_candidate, i) != (rm->staged_box_cert[i] & 0xFFFFu)) {
            return ZW_REASON_BOX_CERT; /* not canonical: a NaN payload, a flushed subnormal */
        }
    }
    if (!cert_ranged(c) || !cert_box_setup(rm, c, &box, &spec, &work) ||
        (zw_box_cert_verify(&box, &spec, &rm->box_cert_candidate, &work, &fault, &leaves) != ZW_OK) ||
        (fault != ZW_BOX_CERT_OK)) {
        return ZW_REASON_BOX_CERT;
    }
    rm->box_cert_candidate_valid = 1u;
    return ZW_REASON_NONE;
}

zw_reason zw_rm_policy_admit(zw_regmap *rm)
{
    unsigned i;
    float f[ZW_CERT_FIELDS];
    zw_cert c;
    zw_reason why;
    bool any;
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        f[i] = zw_rm_staged_float(rm, i);
        zw_cert_set_field(&c, i, f[i]);
    }
    why = check_block_fields(rm, f);
    if (why != ZW_REASON_NONE) {
        return why;
    }
    why = check_loop_fields(rm);
    if (why != ZW_REASON_NONE) {
        return why;
    }
    why = build_loop(rm, true);
    if ((why == ZW_REASON_NONE) && (rm->has_ceilings != 0u)) {
        why = check_firmware_loop(&rm->ceilings, f);
    }
    if (why == ZW_REASON_NONE) {
        why = admit_box_cert(rm, &c);
    }
    if (why == ZW_REASON_NONE) {
        live_extremes(rm, &c, &any);
        if (!any) {
            why = ZW_REASON_LOOP_NEVER_STABLE;
        } else if (!some_pair_usable(rm, &c)) {
            why = ZW_REASON_ONLY_OFF;
        } else {
            /* admitted */
        }
    }
    if (why != ZW_REASON_NONE) {
        /* the sealed block stays in force with its certificate: its loop back (it was
         * valid when sealed), and its extremes */
        rm->box_cert_candidate_valid = 0u;
        if (rm->is_sealed != 0u) {
            (void)build_loop(rm, false);
            live_extremes(rm, &rm->sealed, &any);
        }
        return why;
    }
    /* admitted: its certificate (or none) goes into force with it */
    rm->box_cert = rm->box_cert_candidate;
    rm->box_cert_valid = rm->box_cert_candidate_valid;
    rm->box_cert_candidate_valid = 0u;
    return ZW_REASON_NONE;
}

zw_status zw_regmap_set_ceilings(zw_regmap *rm, const zw_ceilings *k, zw_reason *reason)
{
    const float v[16] = {k != NULL ? k->sigma_max : 0.0f, k != NULL ? k->r_max : 0.0f,
                         k != NULL ? k->m : 0.0f, k != NULL ? k->b : 0.0f,
                         k != NULL ? k->T : 0.0f, k != NULL ? k->plant_tol : 0.0f,
                         k != NULL ? k->k_min : 0.0f, k != NULL ? k->k_max : 0.0f,
                         k != NULL ? k->b_min : 0.0f, k != NULL ? k->b_max : 0.0f,
                         k != NULL ? k->dk_max : 0.0f, k != NULL ? k->db_max : 0.0f,
                         k != NULL ? k->delay : 0.0f, k != NULL ? k->vfilter : 0.0f,
                         k != NULL ? k->vf_param : 0.0f, k != NULL ? k->differentiator : 0.0f};
    float f[ZW_CERT_FIELDS];
    unsigned i;
    zw_reason why = ZW_REASON_NONE;
    if (reason != NULL) {
        *reason = ZW_REASON_BAD_POLICY;
    }
    if (rm == NULL || k == NULL) {
        return ZW_ERR_NULL;
    }
    for (i = 0u; i < 16u; ++i) {
        if (!zw_rm_finite_f(v[i])) {
            return ZW_ERR_ARG;
        }
    }
    if (!(k->sigma_max > 0.0f && k->sigma_max <= 1.0f) || !(k->r_max > 0.0f && k->r_max <= 1.0f) ||
        !(k->m > 0.0f) || !(k->T > 0.0f) || !(k->b >= 0.0f) || !(k->plant_tol >= 0.0f) ||
        !(k->k_min <= k->k_max) || !(k->b_min <= k->b_max) || !(k->dk_max > 0.0f) ||
        !(k->db_max > 0.0f)) {
        return ZW_ERR_ARG;
    }
    rm->ceilings = *k;
    rm->has_ceilings = 1u;
    if (rm->is_sealed != 0u) {
        for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
            f[i] = zw_cert_field(&rm->sealed, i);
        }
        why = check_ceilings(k, f);
        if (why == ZW_REASON_NONE) {
            why = check_firmware_loop(k, f);
        }
        if (why != ZW_REASON_NONE) { /* never run outside the ceilings: unsealed, output off */
            rm->is_sealed = 0u;
            zw_rm_publish_gains(rm, 0.0f, 0.0f);
            (void)zw_rm_live_all(rm);
        }
    }
    if (reason != NULL) {
        *reason = why;
    }
    return why == ZW_REASON_NONE ? ZW_OK : ZW_ERR_ARG;
}

/* ---- certification of a gain pair ---------------------------------------------------------- */

/* |a - b| <= limit, decided on the exact difference: when the rounded difference lands on
 * the limit, its rounding error (Knuth's TwoSum, exact without contraction) tells on which
 * side the exact difference lies.  a, b finite; limit finite and > 0. */
static bool step_within(float a, float b, float limit)
{
    zw_real x = (zw_real)a, y = -(zw_real)b, lim = (zw_real)limit;
    zw_real d = x + y;
    zw_real ad = d < ZW_R(0.0) ? -d : d;
    zw_real yv, err;
    if (ad != lim) { /* an overflowed difference is inf: refused */
        return ad < lim;
    }
    yv = d - x;
    err = (x - (d - yv)) + (y - yv); /* d + err == a - b exactly */
    return d > ZW_R(0.0) ? err <= ZW_R(0.0) : err >= ZW_R(0.0);
}

/* The two rules that need the plant, each in its own small function: the deepest chains of
 * the core (zw_device_radius_within) then start right below a small frame (stack).  Any
 * error of the core (a normalization that overflows) counts against the pair. */
static bool stable_ok(zw_regmap *rm, float K, float B)
{
    if (ideal_loop(rm)) {
        zw_verdict v;
        return zw_device_check(&rm->loop.dev, (zw_real)K, (zw_real)B, &v) == ZW_OK && v.stable;
    } else {
        zw_loop_verdict v;
        return zw_device_loop_check(&rm->loop, &rm->ws, (zw_real)K, (zw_real)B, &v) == ZW_OK && v.stable;
    }
}

static bool radius_ok(zw_regmap *rm, float r, float K, float B)
{
    bool within; /* written by both on every path (their fail-safe rule) */
    zw_status st;
    if (ideal_loop(rm)) {
        st = zw_device_radius_within(&rm->loop.dev, (zw_real)K, (zw_real)B, (zw_real)r, &within);
    } else {
        st = zw_device_loop_radius_within(&rm->loop, &rm->ws, (zw_real)K, (zw_real)B, (zw_real)r,
                                          &within);
    }
    return (st == ZW_OK) && within;
}

/* K_max at B of the drive's loop (certified; 0 on error, by the core's fail-safe).  The
 * general loop's is taken from the cache when B is the one it holds. */
static zw_status drive_k_max(zw_regmap *rm, const zw_cert *c, float B, zw_real *k_max)
{
    const bool ranged = cert_ranged(c);
    if (!ranged && ideal_loop(rm)) {
        return zw_device_k_max(&rm->loop.dev, (zw_real)B, k_max);
    }
    if (rm->kmax_cached != 0u && rm->kmax_B == B) {
        *k_max = rm->kmax_value;
        return ZW_OK;
    }
    if (ranged) { /* the box's: a lower bound of the infimum over the box */
        return cert_box_k_max(rm, c, B, k_max);
    }
    return zw_device_loop_k_max(&rm->loop, &rm->ws, (zw_real)B, k_max);
}

/* Keep K_max(B) for the gains now in force (general loop or ranged block; the ideal point
 * one is cheap).  The cache belongs to the sealed block (build_loop clears it). */
static void cache_k_max(zw_regmap *rm, float B, zw_real k_max)
{
    rm->kmax_B = B;
    rm->kmax_value = k_max;
    rm->kmax_cached = (uint_least16_t)((ideal_loop(rm) && !cert_ranged(&rm->sealed)) ? 0u : 1u);
}

/* The rules of regmap_policy.h, in its order, for a write from (K0, B0) under block c (the
 * loop in rm->loop is c's); the first that fails is the reason. */
static zw_reason certify_under(zw_regmap *rm, const zw_cert *c, float K0, float B0, float K,
                               float B, zw_real *k_max_out)
{
    zw_real k_max;
    *k_max_out = ZW_R(0.0);
    if (!zw_rm_finite_f(K) || !zw_rm_finite_f(B)) {
        return ZW_REASON_NOT_FINITE;
    }
    if (K == 0.0f && B == 0.0f) { /* output off: always allowed */
        return ZW_REASON_NONE;
    }
    if (K < c->k_min) {
        return ZW_REASON_K_BELOW_MIN;
    }
    if (K > c->k_max) {
        return ZW_REASON_K_ABOVE_MAX;
    }
    if (B < c->b_min) {
        return ZW_REASON_B_BELOW_MIN;
    }
    if (B > c->b_max) {
        return ZW_REASON_B_ABOVE_MAX;
    }
    if (!step_within(K, K0, c->dk_max)) {
        return ZW_REASON_K_STEP;
    }
    if (!step_within(B, B0, c->db_max)) {
        return ZW_REASON_B_STEP;
    }
    if (cert_ranged(c)) { /* stability and sigma in one proof over the box; r = 1 */
        return cert_box_certify(rm, c, K, B);
    }
    if (!stable_ok(rm, K, B)) {
        return ZW_REASON_UNSTABLE;
    }
    if (drive_k_max(rm, c, B, &k_max) != ZW_OK || (zw_real)K > (zw_real)c->sigma * k_max) {
        return ZW_REASON_ABOVE_SIGMA;
    }
    *k_max_out = k_max;
    if (!radius_ok(rm, c->r, K, B)) {
        return ZW_REASON_RADIUS;
    }
    return ZW_REASON_NONE;
}

/* A gain write: certified as a pair, then stored (K and B the values after the write;
 * -0.0 stored as +0.0, so "off" reads as two zero words). */
zw_reason zw_rm_apply_gains(zw_regmap *rm, float K, float B)
{
    zw_real k_max;
    zw_reason why = certify_under(rm, &rm->sealed, rm->K, rm->B, K, B, &k_max);
    if (why != ZW_REASON_NONE) {
        return why;
    }
    /* (0, 0) skips the rules: k_max is then not known.  A ranged block's write does not
     * compute it: its cache (keyed on B, the box's value) stays, live_refresh fills it */
    if (!cert_ranged(&rm->sealed)) {
        if (K == 0.0f && B == 0.0f) {
            rm->kmax_cached = 0u;
        } else {
            cache_k_max(rm, B, k_max);
        }
    }
    zw_rm_publish_gains(rm, K == 0.0f ? 0.0f : K, B == 0.0f ? 0.0f : B);
    rm->accepted = (rm->accepted + 1u) & 0xFFFFFFFFu;
    return ZW_REASON_NONE;
}

/* ---- live registers ------------------------------------------------------------------------ */



/* K_CERT of a ranged block: this fraction below sigma K_MAX (regmap.h). */
#define K_CERT_BOX_MARGIN ZW_R(0.015625)

/* Grid of the downward scan in live_k_cert (see there). */
#define K_CERT_GRID 32u

/* Bound on the iterations of live_k_cert's loop (an integer loop counter, MISRA 14.1): the
 * scan takes at most K_CERT_GRID; the bisection starts from lo >= hi / 2 (neighbouring grid
 * points below top), so hi - lo <= lo and after 25 halvings it is below one ulp of lo and
 * the loop has ended.  Never reached; if it were, lo would still be an accepted K. */
#define K_CERT_STEPS (K_CERT_GRID + 64u)

/* LIVE_K_CERT: the largest float K at the current B that the k_max, sigma, stability and
 * radius rules accept (the k_min and step rules depend on where K comes from, so they are
 * left out).  top = min(sigma K_max(B), k_max) is taken when stability and radius accept
 * it; otherwise the largest accepted K lies below top: K is scanned down from top on a grid
 * of K_CERT_GRID points for one that is accepted, and the crossing above it is bisected to
 * float resolution, so the value reported is itself accepted.  0 when no grid point is.
 * NaN without a sealed plant.  Returns ZW_MB_OK so that zw_rm_live_all can end in it. */
ZW_NOINLINE static zw_mb_exception live_k_cert(zw_regmap *rm)
{
    zw_real k_max, top;
    float top_f = 0.0f, lo = 0.0f, hi, k, B = rm->B;
    unsigned grid = K_CERT_GRID; /* scanning grid point grid/K_CERT_GRID of top; 0: bisecting */
    unsigned step;
    bool searching;
    rm->live[L_K_CERT] = QUIET_NAN_F;
    if ((rm->is_sealed == 0u) || (drive_k_max(rm, &rm->sealed, B, &k_max) != ZW_OK)) {
        return ZW_MB_OK;
    }
    top = (zw_real)rm->sealed.sigma * k_max;
    if (top > (zw_real)rm->sealed.k_max) {
        top = (zw_real)rm->sealed.k_max;
    }
    if (cert_ranged(&rm->sealed)) {
        /* k_max is certified for the box: (0, k_max] stable at B for every plant, so sigma
         * k_max shrunk by its rounding (and k_over_sigma_up's) passes the box rule; r = 1.
         * Shrunk by K_CERT_BOX_MARGIN more, so that a write of K_CERT is proven again
         * well within the write's budget (the proof's cost grows as K nears the infimum). */
        top = (zw_real)rm->sealed.sigma * k_max * (ZW_R(1.0) - K_CERT_BOX_MARGIN);
        if (top > (zw_real)rm->sealed.k_max) {
            top = (zw_real)rm->sealed.k_max;
        }
        rm->live[L_K_CERT] = (top > ZW_R(0.0)) ? float_down(top) : 0.0f;
        return ZW_MB_OK;
    }
    if (top > ZW_R(0.0)) {
        top_f = float_down(top);
    }
    /* One loop with one call site of the rules: a smaller frame than a scan loop followed
     * by a bisection loop. */
    hi = top_f;
    k = top_f;
    searching = k > 0.0f;
    for (step = 0u; (step < K_CERT_STEPS) && searching; ++step) {
        const bool ok = stable_ok(rm, k, B) && radius_ok(rm, rm->sealed.r, k, B);
        if ((grid > 0u) && !ok) { /* scanning down */
            hi = k;
            --grid;
            k = top_f * ((float)grid / (float)K_CERT_GRID);
            searching = (grid > 0u) && (k > 0.0f); /* grid 0: none accepted, lo stays 0 */
        } else {
            if (ok) {
                lo = k;
            } else {
                hi = k;
            }
            searching = grid != K_CERT_GRID; /* still K_CERT_GRID: top itself is accepted */
            grid = 0u;
            k = lo + ((hi - lo) * 0.5f); /* lo accepted, hi refused; ends when they are neighbours */
            searching = searching && (k > lo) && (k < hi);
        }
    }
    rm->live[L_K_CERT] = lo;
    return ZW_MB_OK;
}

/* B values probed by some_pair_usable: the B of K_mmax, 0, and a grid over the range. */
#define USABLE_B_GRID 8u

/* Some pair other than (0, 0) passes every rule of a write from (0, 0) under block c (its
 * loop built in rm->loop, its extremes in rm->live): probed at the B of K_mmax, at 0 and on
 * a grid of USABLE_B_GRID points over the B range one step reaches, each with K at eleven
 * fractions of the ceiling there (1/64 .. 1) and at k_min; it stops at the first that passes
 * (usually the first probe).  A block none of these pass is refused
 * (ZW_REASON_ONLY_OFF): it can hold the output off and little else. */
ZW_NOINLINE static bool some_pair_usable(zw_regmap *rm, const zw_cert *c)
{
    /* fractions of the ceiling, on a roughly logarithmic scale (the accepted K at a given B
     * can be a narrow window when r is small) */
    static const float k_fraction[11] = {0.5f,   1.0f,   0.75f,   0.375f, 0.25f,   0.1875f,
                                         0.125f, 0.09375f, 0.0625f, 0.03125f, 0.015625f};
    float lo = c->b_min > -c->db_max ? c->b_min : -c->db_max;
    float hi = c->b_max < c->db_max ? c->b_max : c->db_max;
    float B, top_f, K;
    zw_real k_max, top, km;
    unsigned i, j;
    for (i = 0u; i < USABLE_B_GRID + 2u; ++i) {
        if (i == 0u) {
            B = rm->live[L_B_AT_KMMAX];
        } else if (i == 1u) {
            B = 0.0f;
        } else {
            const unsigned point = i - 2u; /* of the grid over [lo, hi] */
            B = lo + ((hi - lo) * ((float)point / ((float)USABLE_B_GRID - 1.0f)));
        }
        if (!(B >= lo && B <= hi)) { /* NaN too */
            continue;
        }
        if (drive_k_max(rm, c, B, &k_max) != ZW_OK) {
            continue;
        }
        top = (zw_real)c->sigma * k_max;
        if (top > (zw_real)c->k_max) {
            top = (zw_real)c->k_max;
        }
        if (top > (zw_real)c->dk_max) {
            top = (zw_real)c->dk_max;
        }
        if (!(top > ZW_R(0.0))) {
            continue;
        }
        top_f = float_down(top);
        for (j = 0; j <= 11u; ++j) {
            K = j < 11u ? top_f * k_fraction[j] : c->k_min;
            if (K > 0.0f && certify_under(rm, c, 0.0f, 0.0f, K, B, &km) == ZW_REASON_NONE) {
                return true;
            }
        }
    }
    return false;
}

static float value_or_nan(zw_status st, zw_real x)
{
    return st == ZW_OK ? zw_rm_to_float(x) : QUIET_NAN_F;
}

/* Recompute the live registers that depend on the gains (and delta) after an accepted
 * change (gains, seal, unlock), so reads never run the core.  A value that does not exist
 * (no sealed plant, or the core refuses the computation) reads as NaN.  K_CERT, K_MMAX and
 * its B have functions of their own, each called from zw_rm_live_all, so that no frame sits
 * under another one's chain into the core (stack). */
ZW_NOINLINE static void live_refresh(zw_regmap *rm)
{
    const zw_device *d = &rm->loop.dev;
    zw_real x = ZW_R(0.0), y = ZW_R(0.0), th = ZW_R(0.0);
    zw_status st;
    bool any, ranged;
    unsigned i;
    if (rm->is_sealed == 0u) {
        for (i = 0u; i < L_COUNT; ++i) {
            rm->live[i] = QUIET_NAN_F;
        }
        return;
    }
    ranged = cert_ranged(&rm->sealed);
    st = drive_k_max(rm, &rm->sealed, rm->B, &x);
    if (st == ZW_OK && (ranged || !(rm->K == 0.0f && rm->B == 0.0f))) {
        cache_k_max(rm, rm->B, x);
    }
    rm->live[L_K_MAX] = value_or_nan(st, x);
    if (ranged) {
        rm->live[L_K_MAX] = (st == ZW_OK) ? float_down(x) : QUIET_NAN_F;
        /* B range: the certificate's run of steps at K / sigma; without one no box form per
         * write (NaN, regmap.h).  RHO NaN; delta of the lower ends. */
        rm->live[L_B_LO] = QUIET_NAN_F;
        rm->live[L_B_HI] = QUIET_NAN_F;
        if (staircase_of(rm, &rm->sealed) != NULL) {
            float q = rm->K / rm->sealed.sigma, lo = QUIET_NAN_F, hi = QUIET_NAN_F;
            if (rm->sealed.sigma != 1.0f) {
                q = ZW_NEXTAFTERF(q, ZW_HUGE_VALF); /* rounded up */
            }
            zw_box_cert_b_range(&rm->box_cert, q, rm->B, &lo, &hi, &any);
            rm->live[L_B_LO] = lo;
            rm->live[L_B_HI] = hi;
        }
        rm->live[L_RHO] = QUIET_NAN_F;
        rm->live[L_DELTA] = zw_rm_to_float(d->co.delta);
        return;
    }
    /* both report (0, 0) when the interval is empty, which covers K = 0 */
    /* the general loop's B range is not computed per write (regmap.h): NaN */
    st = ideal_loop(rm) ? zw_device_b_range(d, (zw_real)rm->K, &x, &y, &any) : ZW_ERR_ARG;
    rm->live[L_B_LO] = value_or_nan(st, x);
    rm->live[L_B_HI] = value_or_nan(st, y);
    st = ideal_loop(rm) ? zw_device_spectral_radius(d, (zw_real)rm->K, (zw_real)rm->B, &x)
                        : zw_device_loop_spectral_radius(&rm->loop, &rm->ws, (zw_real)rm->K, (zw_real)rm->B, &x, &th);
    rm->live[L_RHO] = value_or_nan(st, x);
    rm->live[L_DELTA] = zw_rm_to_float(d->co.delta);
}

/* Every live register, after an accepted change.  Returns ZW_MB_OK so that the public
 * functions end in it as a tail call, and ends in live_k_cert as one itself. */
/* Every live register, after an accepted change.  Returns ZW_MB_OK so that the public
 * functions end in it as a tail call, and ends in live_k_cert as one itself. */
zw_mb_exception zw_rm_live_all(zw_regmap *rm)
{
    live_refresh(rm);
    return live_k_cert(rm);
}

const char *zw_reason_name(zw_reason reason)
{
    const char *name;
    switch (reason) {
    case ZW_REASON_NONE: name = "ZW_REASON_NONE"; break;
    case ZW_REASON_BAD_FUNCTION: name = "ZW_REASON_BAD_FUNCTION"; break;
    case ZW_REASON_MALFORMED: name = "ZW_REASON_MALFORMED"; break;
    case ZW_REASON_UNMAPPED: name = "ZW_REASON_UNMAPPED"; break;
    case ZW_REASON_READ_ONLY: name = "ZW_REASON_READ_ONLY"; break;
    case ZW_REASON_HALF_FLOAT: name = "ZW_REASON_HALF_FLOAT"; break;
    case ZW_REASON_LOCKED: name = "ZW_REASON_LOCKED"; break;
    case ZW_REASON_NOT_SEALED: name = "ZW_REASON_NOT_SEALED"; break;
    case ZW_REASON_NOT_FINITE: name = "ZW_REASON_NOT_FINITE"; break;
    case ZW_REASON_K_BELOW_MIN: name = "ZW_REASON_K_BELOW_MIN"; break;
    case ZW_REASON_K_ABOVE_MAX: name = "ZW_REASON_K_ABOVE_MAX"; break;
    case ZW_REASON_B_BELOW_MIN: name = "ZW_REASON_B_BELOW_MIN"; break;
    case ZW_REASON_B_ABOVE_MAX: name = "ZW_REASON_B_ABOVE_MAX"; break;
    case ZW_REASON_K_STEP: name = "ZW_REASON_K_STEP"; break;
    case ZW_REASON_B_STEP: name = "ZW_REASON_B_STEP"; break;
    case ZW_REASON_UNSTABLE: name = "ZW_REASON_UNSTABLE"; break;
    case ZW_REASON_ABOVE_SIGMA: name = "ZW_REASON_ABOVE_SIGMA"; break;
    case ZW_REASON_RADIUS: name = "ZW_REASON_RADIUS"; break;
    case ZW_REASON_BAD_COMMAND: name = "ZW_REASON_BAD_COMMAND"; break;
    case ZW_REASON_CRC: name = "ZW_REASON_CRC"; break;
    case ZW_REASON_BAD_POLICY: name = "ZW_REASON_BAD_POLICY"; break;
    case ZW_REASON_FPENV: name = "ZW_REASON_FPENV"; break;
    case ZW_REASON_BAD_DELAY: name = "ZW_REASON_BAD_DELAY"; break;
    case ZW_REASON_BAD_FILTER: name = "ZW_REASON_BAD_FILTER"; break;
    case ZW_REASON_BAD_FILTER_PARAM: name = "ZW_REASON_BAD_FILTER_PARAM"; break;
    case ZW_REASON_BAD_DIFFERENTIATOR: name = "ZW_REASON_BAD_DIFFERENTIATOR"; break;
    case ZW_REASON_LOOP_NEVER_STABLE: name = "ZW_REASON_LOOP_NEVER_STABLE"; break;
    case ZW_REASON_NO_CONSENT: name = "ZW_REASON_NO_CONSENT"; break;
    case ZW_REASON_RNG: name = "ZW_REASON_RNG"; break;
    case ZW_REASON_AUTH: name = "ZW_REASON_AUTH"; break;
    case ZW_REASON_ABOVE_CEILING: name = "ZW_REASON_ABOVE_CEILING"; break;
    case ZW_REASON_PLANT_MISMATCH: name = "ZW_REASON_PLANT_MISMATCH"; break;
    case ZW_REASON_SUBNORMAL: name = "ZW_REASON_SUBNORMAL"; break;
    case ZW_REASON_ONLY_OFF: name = "ZW_REASON_ONLY_OFF"; break;
    case ZW_REASON_NO_CEILINGS: name = "ZW_REASON_NO_CEILINGS"; break;
    case ZW_REASON_NO_STORAGE: name = "ZW_REASON_NO_STORAGE"; break;
    case ZW_REASON_STORAGE: name = "ZW_REASON_STORAGE"; break;
    case ZW_REASON_IMAGE_FORMAT: name = "ZW_REASON_IMAGE_FORMAT"; break;
    case ZW_REASON_IMAGE_CRC: name = "ZW_REASON_IMAGE_CRC"; break;
    case ZW_REASON_LOOP_MISMATCH: name = "ZW_REASON_LOOP_MISMATCH"; break;
    case ZW_REASON_BOX_BUDGET: name = "ZW_REASON_BOX_BUDGET"; break;
    case ZW_REASON_BOX_RADIUS: name = "ZW_REASON_BOX_RADIUS"; break;
    case ZW_REASON_BOX_CERT: name = "ZW_REASON_BOX_CERT"; break;
    case ZW_REASON_OUTSIDE_CERT: name = "ZW_REASON_OUTSIDE_CERT"; break;
    default: name = "ZW_REASON_UNKNOWN"; break; /* a value outside the enumeration */
    }
    return name;
}
