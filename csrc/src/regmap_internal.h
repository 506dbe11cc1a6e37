/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Private to the register map: what its four files (regmap.c the map and its requests,
 * regmap_codec.c the wire format, regmap_policy.c the certification policy,
 * regmap_commission.c commissioning) share.  Names zw_rm_*; renamed for the float build in
 * zwidth/precision.h like every other symbol. */
#ifndef ZWIDTH_REGMAP_INTERNAL_H
#define ZWIDTH_REGMAP_INTERNAL_H

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "zwidth/regmap.h"
#include "internal.h"

#define CRC_INDEX ZW_CERT_WORDS /* staged[CRC_INDEX] is the CRC word */

/* Index of each live register in rm->live (register ZW_REG_LIVE_K_MAX + 2 i). */
enum { L_K_MAX, L_K_CERT, L_B_LO, L_B_HI, L_K_MMAX, L_B_AT_KMMAX, L_RHO, L_DELTA, L_COUNT };

/* Index of each field of the certified block (register ZW_REG_CERT_M + 2 i). */
enum {
    F_M, F_B, F_T, F_SIGMA, F_R, F_K_MIN, F_K_MAX, F_B_MIN, F_B_MAX, F_DK_MAX, F_DB_MAX,
    F_DELAY, F_VFILTER, F_VF_PARAM, F_DIFF, F_M_HI, F_B_HI
};

/* A quiet NaN of type float, for values that do not exist (live registers without a
 * sealed plant).  NAN is optional in C99 (only where quiet NaNs exist); the fallback is
 * 0/0 at run time (not through zw_words_to_float, which itself needs QUIET_NAN_F). */
#ifdef NAN
#define QUIET_NAN_F ((float)NAN)
#else
static inline float zw_rm_quiet_nan_f(void)
{
    volatile float zero = 0.0f; /* volatile: no constant folding of 0/0 */
    return zero / zero;
}
#define QUIET_NAN_F (zw_rm_quiet_nan_f())
#endif


static inline bool zw_rm_finite_f(float x)
{
    return (x == x) && (x <= FLT_MAX) && (x >= -FLT_MAX);
}

/* zw_real -> float without undefined behaviour when the value does not fit (saturates to
 * an infinity; NaN stays NaN). */
static inline float zw_rm_to_float(zw_real x)
{
    float f;
    if (x != x) {
        f = QUIET_NAN_F;
    } else if (x > (zw_real)FLT_MAX) {
        f = ZW_HUGE_VALF;
    } else if (x < -(zw_real)FLT_MAX) {
        f = -ZW_HUGE_VALF;
    } else {
        f = (float)x;
    }
    return f;
}

/* Field `field` of the staged block. */
static inline float zw_rm_staged_float(const zw_regmap *rm, unsigned field)
{
    return zw_words_to_float(&rm->staged[2u * field]);
}

/* regmap.c: the gain pair the control loop applies from now on (the Modbus task, the only
 * writer of the gains), and word i of a request payload (words, or big-endian bytes). */
void zw_rm_publish_gains(zw_regmap *rm, float K, float B);
uint_least16_t zw_rm_payload_word(const uint_least16_t *words, const uint_least8_t *bytes,
                                  size_t i);
float zw_rm_payload_float(const uint_least16_t *words, const uint_least8_t *bytes, size_t i);
/* The same in the map's word order: word i of a payload whose two-word values start at
 * even i, as the canonical (ABCD) word; the value starting at word i. */
uint_least16_t zw_rm_pair_word(const zw_regmap *rm, const uint_least16_t *words,
                               const uint_least8_t *bytes, size_t i);
float zw_rm_pair_float(const zw_regmap *rm, const uint_least16_t *words,
                       const uint_least8_t *bytes, size_t i);

/* regmap_codec.c: one word into a CRC-16/MODBUS, high byte first. */
uint_least16_t zw_rm_crc_word(uint_least16_t crc, uint_least16_t word);

/* regmap_policy.c: the staged block's checks (after its CRC), building rm->loop from it;
 * a refused block leaves the one in force as it was.  A gain write certified and stored.
 * Every live register after an accepted change (returns ZW_MB_OK, for tail calls). */
zw_reason zw_rm_policy_admit(zw_regmap *rm);
zw_reason zw_rm_apply_gains(zw_regmap *rm, float K, float B);
zw_mb_exception zw_rm_live_all(zw_regmap *rm);

/* regmap_commission.c: the staged block written, a command, SEAL of the staged block
 * (authenticate: the MAC checked, for a Modbus SEAL), the MAC words written, word i of the
 * block in force. */
zw_reason zw_rm_write_cert(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                           const uint_least16_t *words, const uint_least8_t *bytes);
zw_reason zw_rm_command(zw_regmap *rm, uint_least16_t cmd, bool armed);
zw_reason zw_rm_seal_staged(zw_regmap *rm, bool authenticate);
zw_reason zw_rm_write_mac(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                          const uint_least16_t *words, const uint_least8_t *bytes);
uint_least16_t zw_rm_sealed_word(const zw_regmap *rm, unsigned i);
/* The same for the box certificate window: a write of it in commissioning, word i of the
 * certificate in force. */
zw_reason zw_rm_write_box_cert(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                               const uint_least16_t *words, const uint_least8_t *bytes);
uint_least16_t zw_rm_sealed_box_cert_word(const zw_regmap *rm, unsigned i);

/* regmap_persist.c: the SAVE command. */
zw_reason zw_rm_save(zw_regmap *rm);

#endif /* ZWIDTH_REGMAP_INTERNAL_H */
