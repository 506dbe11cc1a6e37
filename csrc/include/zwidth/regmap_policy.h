/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* zwidth/regmap_policy.h - the certification policy of the register map (part of
 * zwidth/regmap.h, the entry point): why a request is refused, and the rules a gain pair
 * must pass against the sealed block.
 *
 * Certification of a gain pair (K, B) against the sealed block, in this order; the first
 * failing rule is the reason:
 *   finite (ZW_REASON_NOT_FINITE), k_min <= K <= k_max, b_min <= B <= b_max,
 *   |K - K_now| <= dk_max, |B - B_now| <= db_max, stable by zw_device_check
 *   (ZW_REASON_UNSTABLE), K <= sigma K_max(B) (ZW_REASON_ABOVE_SIGMA), spectral radius
 *   < r by zw_device_radius_within (ZW_REASON_RADIUS).  With a loop other than the ideal one
 *   (delay 0, backward difference, no filter) the three rules use the drive's loop:
 *   zw_device_loop_check, zw_device_loop_k_max, zw_device_loop_radius_within
 *   (device_loop.h), all with the gains' conversion rounding in their guard.
 *   (-0.0 in a gain is stored as +0.0.)
 * A ranged block (map version 4: M_HI > M or B_HI > B) replaces the stability and sigma
 * rules by one proof over the box: zw_box_loop_check at (K / sigma rounded up, B) certifies
 * every K' in (0, K / sigma] stable at B for every plant of the box (box.h; its outward
 * rounding covers the conversion of the gains, as the point path's guard does), which
 * implies K stable and K <= sigma K_max(B; m, b) at every plant.  Not certified: refuted
 * (a plant of the box where the gains are surely unstable) gives ZW_REASON_UNSTABLE when K
 * itself is unstable there (or sigma = 1), else ZW_REASON_ABOVE_SIGMA; the budget of
 * ZW_REGMAP_BOX_EVALS sub-box tests spent without a proof either way gives
 * ZW_REASON_BOX_BUDGET.  The radius rule is the stability rule there (r = 1: a ranged
 * block with r < 1 is refused at SEAL, ZW_REASON_BOX_RADIUS).
 *
 * What a block must be (power-up and SEAL), in this order, the first failure the reason:
 *   every field finite and none a float subnormal (ZW_REASON_BAD_POLICY, _SUBNORMAL);
 *   plant accepted, sigma and r in (0, 1], min <= max, steps > 0, a pair reachable in one
 *   step from (0, 0) within the bounds (ZW_REASON_BAD_POLICY); within the factory ceilings
 *   when they are set (sigma <= sigma_max, r <= r_max, [k_min, k_max] and [b_min, b_max]
 *   inside the factory's, dk_max and db_max at most the factory's: ZW_REASON_ABOVE_CEILING;
 *   m, b and T each within plant_tol (relative) of the nameplate, for a ranged block each
 *   end of the m and b ranges: ZW_REASON_PLANT_MISMATCH); the ranges (version 4): M_HI >= M
 *   and B_HI >= B (or both 0: the point block) and every corner a valid plant
 *   (zw_box_validate) (ZW_REASON_BAD_POLICY), r = 1 when ranged (ZW_REASON_BOX_RADIUS,
 *   checked after the ceilings);
 *   the loop fields (reasons 22..26); then (ranged: over the box) some pair other than
 *   (0, 0) passes every rule of
 *   a gain write made from (0, 0) (ZW_REASON_ONLY_OFF: probed at the B of K_mmax, at 0 and
 *   at 8 B across the range one step reaches, K at eleven fractions 1/64 .. 1 of
 *   min(sigma K_max(B), k_max, dk_max), and K = k_min; a block whose usable set all these
 *   probes miss is refused too, which errs on the safe side).
 *   Fields equal to -0.0 are stored as +0.0.
 * Factory ceilings are fixed by the firmware at power-up (zw_regmap_set_ceilings), never by
 * a Modbus write; without them the drive cannot be commissioned over Modbus
 * (ZW_REASON_NO_CEILINGS) and only its power-up block can be in force.
 */
#ifndef ZWIDTH_REGMAP_POLICY_H
#define ZWIDTH_REGMAP_POLICY_H

#include "zwidth/precision.h"
#include "zwidth/real.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Why a request was refused (ZW_REG_LAST_REASON). */
typedef enum zw_reason {
    ZW_REASON_NONE = 0,
    ZW_REASON_BAD_FUNCTION = 1,   /* function code not supported */
    ZW_REASON_MALFORMED = 2,      /* PDU length, quantity or byte count inconsistent */
    ZW_REASON_UNMAPPED = 3,       /* an address in the request is not in the map */
    ZW_REASON_READ_ONLY = 4,      /* a write touches a read-only register */
    ZW_REASON_HALF_FLOAT = 5,     /* a write covers one word of a two-word value */
    ZW_REASON_LOCKED = 6,         /* certified block written outside commissioning mode */
    ZW_REASON_NOT_SEALED = 7,     /* gains written while no sealed block (or commissioning) */
    ZW_REASON_NOT_FINITE = 8,     /* NaN or infinity */
    ZW_REASON_K_BELOW_MIN = 9,
    ZW_REASON_K_ABOVE_MAX = 10,
    ZW_REASON_B_BELOW_MIN = 11,
    ZW_REASON_B_ABOVE_MAX = 12,
    ZW_REASON_K_STEP = 13,        /* |K - K_now| > dk_max */
    ZW_REASON_B_STEP = 14,        /* |B - B_now| > db_max */
    ZW_REASON_UNSTABLE = 15,      /* outside the exact stability region (or within its rounding band) */
    ZW_REASON_ABOVE_SIGMA = 16,   /* K > sigma K_max(B) */
    ZW_REASON_RADIUS = 17,        /* spectral radius not below r */
    ZW_REASON_BAD_COMMAND = 18,   /* unknown command, or UNLOCK2 not right after UNLOCK1 */
    ZW_REASON_CRC = 19,           /* seal: CRC does not match the block */
    ZW_REASON_BAD_POLICY = 20,    /* seal: a field not finite, plant invalid (zw_device_init
                                     fails), sigma or r not in (0, 1], k_min > k_max or
                                     b_min > b_max, a step limit not > 0, or no pair
                                     reachable in one step from the output-off state
                                     (k_min > dk_max, b_min > db_max, b_max < -db_max) */
    ZW_REASON_FPENV = 21,         /* seal: the floating-point self-test (zw_selftest) failed;
                                     nothing can be certified on this target */
    /* seal: the loop description (map version 2) */
    ZW_REASON_BAD_DELAY = 22,     /* DELAY not an integer in 0..8 */
    ZW_REASON_BAD_FILTER = 23,    /* VFILTER not 0, 1 or 2 */
    ZW_REASON_BAD_FILTER_PARAM = 24, /* low-pass cut-off not in (0, 1/(2T)) or so low that
                                     the pole rounds to 1; average n not an integer 1..16;
                                     no filter with a parameter other than 0 */
    ZW_REASON_BAD_DIFFERENTIATOR = 25, /* DIFF not 0 or 1 */
    ZW_REASON_LOOP_NEVER_STABLE = 26,  /* no gains are stable with this loop (e.g. Tustin with
                                     an even moving average), or its limits cannot be
                                     computed for this plant */
    /* commissioning (map version 3, zwidth/regmap_commission.h) */
    ZW_REASON_NO_CONSENT = 27,    /* the commissioning enable input is off */
    ZW_REASON_RNG = 28,           /* UNLOCK2: no authentication hooks, or no random nonce */
    ZW_REASON_AUTH = 29,          /* SEAL: the MAC does not verify under the drive's key */
    /* the block against the factory ceilings (zw_regmap_set_ceilings) and usability */
    ZW_REASON_ABOVE_CEILING = 30, /* sigma or r above the ceiling, bounds or steps wider */
    ZW_REASON_PLANT_MISMATCH = 31,/* m, b or T outside the nameplate's tolerance */
    ZW_REASON_SUBNORMAL = 32,     /* a field is a float subnormal */
    ZW_REASON_ONLY_OFF = 33,      /* no pair but (0, 0) can be accepted under the block */
    ZW_REASON_NO_CEILINGS = 34,   /* UNLOCK2 or SEAL on a drive without factory ceilings */
    /* persistence (zwidth/regmap_persist.h) */
    ZW_REASON_NO_STORAGE = 35,    /* SAVE on a drive without a storage hook */
    ZW_REASON_STORAGE = 36,       /* SAVE: the storage hook reported a failure */
    ZW_REASON_IMAGE_FORMAT = 37,  /* restore: length, magic or format version wrong */
    ZW_REASON_IMAGE_CRC = 38,     /* restore: the image's CRC (or its block's) is wrong */
    ZW_REASON_LOOP_MISMATCH = 39, /* the block's loop is not the one the firmware runs */
    /* the plant box (map version 4) */
    ZW_REASON_BOX_BUDGET = 40,    /* a ranged block's search ran out of its budget before a
                                     proof either way: refused, never accepted unproven */
    ZW_REASON_BOX_RADIUS = 41,    /* SEAL: a ranged block with r < 1 (the radius rule has no
                                     box form here) */
    /* box certificates (box_cert.h; map version 5's window, zw_regmap_init_box, the image) */
    ZW_REASON_BOX_CERT = 42,      /* SEAL, power-up, restore: the certificate does not verify
                                     for the block's box and loop, is not canonical, or was
                                     given with a point block */
    ZW_REASON_OUTSIDE_CERT = 43   /* a write's B outside the certificate's staircase */
} zw_reason;

/* The box search of a ranged block (map version 4), its memory in zw_regmap: cells of the
 * depth-first stack, sub-box tests per certification, and the relative width at which the
 * K (and SEAL's B) bisections of the live registers stop.  Worst case of one gain write:
 * ZW_REGMAP_BOX_EVALS sub-box tests for its proof (twice for a refusal with sigma < 1, the
 * second naming the reason); when it is accepted and changes B, the live K_MAX refresh adds
 * at most 60 certifications of as many tests (typically 10 to 12: it stops at
 * ZW_REGMAP_BOX_REL_TOL) and a few point K_max.  SEAL (and restore) of a ranged block: its
 * K_MMAX search runs at most 62 box K_max of 60 certifications each and the ONLY_OFF probe
 * at most 10 x (60 + 24) certifications, about 1.8e7 sub-box tests in all (6.7k-11k
 * instructions each on a Cortex-M4F: minutes at 168 MHz in the worst case, 1-23 s on the
 * boxes measured).  Figures: docs/modbus.md ("Plant ranges"). */
#define ZW_REGMAP_BOX_CELLS 64u
#define ZW_REGMAP_BOX_EVALS 4000u
#define ZW_REGMAP_BOX_REL_TOL ZW_R(1.0e-3)

/* The factory ceilings no block may exceed (zw_regmap_set_ceilings). */
typedef struct zw_ceilings {
    float sigma_max, r_max;        /* in (0, 1] */
    float m, b, T;                 /* nameplate plant: m, T > 0, b >= 0 */
    float plant_tol;               /* relative tolerance of m, b and T, >= 0 */
    float k_min, k_max;            /* the widest K bounds a block may have */
    float b_min, b_max;            /* the widest B bounds */
    float dk_max, db_max;          /* the largest step limits, > 0 */
    /* The loop the firmware runs, as a block's loop fields (regmap.h, 0x0056..0x005C:
     * delay, vfilter, vf_param, differentiator; all 0: the paper's ideal loop).  A block
     * must describe exactly this loop (ZW_REASON_LOOP_MISMATCH): a certificate for another
     * loop protects nobody. */
    float delay, vfilter, vf_param, differentiator;
} zw_ceilings;

/* Stable names for logs and tools ("ZW_REASON_UNSTABLE"; "ZW_REASON_UNKNOWN" for other
 * values). */
const char *zw_reason_name(zw_reason reason);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REGMAP_POLICY_H */
