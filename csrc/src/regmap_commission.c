/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Commissioning of the register map, zwidth/regmap_commission.h: the staged block, the
 * command register (UNLOCK1, UNLOCK2, SEAL, ABORT) and SEAL itself.
 */
#include "zwidth/regmap_commission.h"

#include <stddef.h>

#include "regmap_internal.h"
#include "zwidth/selftest.h"

/* Word i (0..22) of the block in force: the sealed block and its CRC, all 0 unsealed.
 * Only the read path needs it, so it re-encodes rather than keeping a copy. */
uint_least16_t zw_rm_sealed_word(const zw_regmap *rm, unsigned i)
{
    uint_least16_t w[2], crc = 0xFFFFu;
    unsigned f;
    if (!rm->is_sealed) return 0u;
    if (i < ZW_CERT_WORDS) {
        zw_float_to_words(zw_cert_field(&rm->sealed, i / 2u), w);
        return w[i & 1u];
    }
    for (f = 0; f < ZW_CERT_FIELDS; ++f) {
        zw_float_to_words(zw_cert_field(&rm->sealed, f), w);
        crc = zw_rm_crc_word(zw_rm_crc_word(crc, w[0]), w[1]);
    }
    return crc;
}

/* SEAL: the self-test, the CRC, the policy (zw_rm_policy_admit), then the block installed
 * and the output off. */
zw_reason zw_rm_seal_staged(zw_regmap *rm)
{
    unsigned i;
    zw_reason why;
    /* every check below, and every certification after it, trusts the arithmetic */
    if (zw_selftest() != ZW_OK) return ZW_REASON_FPENV;
    if (zw_crc16_words(rm->staged, ZW_CERT_WORDS) != (rm->staged[CRC_INDEX] & 0xFFFFu))
        return ZW_REASON_CRC;
    if ((why = zw_rm_policy_admit(rm)) != ZW_REASON_NONE) return why;
    for (i = 0; i < ZW_CERT_FIELDS; ++i) zw_cert_set_field(&rm->sealed, i, zw_rm_staged_float(rm, i));
    rm->is_sealed = 1u;
    rm->mode = 0u;
    zw_rm_publish_gains(rm, 0.0f, 0.0f); /* gains stay off after a seal */
    return ZW_REASON_NONE;
}

/* Staged block: every float finite, then all words stored.  The CRC word is free. */
zw_reason zw_rm_write_cert(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                            const uint_least16_t *words, const uint_least8_t *bytes)
{
    size_t i;
    for (i = 0; i < count && (uint_least32_t)addr + i < ZW_REG_CERT_CRC; i += 2u)
        if (!zw_rm_finite_f(zw_rm_payload_float(words, bytes, i))) return ZW_REASON_NOT_FINITE;
    for (i = 0; i < count; ++i)
        rm->staged[(size_t)(addr - ZW_REG_CERT_M) + i] = zw_rm_payload_word(words, bytes, i);
    return ZW_REASON_NONE;
}

zw_reason zw_rm_command(zw_regmap *rm, uint_least16_t cmd, bool armed)
{
    unsigned i;
    switch (cmd) {
    case ZW_CMD_UNLOCK1:
        if (rm->mode != 0u) return ZW_REASON_BAD_COMMAND; /* already commissioning */
        rm->unlock_armed = 1u;
        return ZW_REASON_NONE;
    case ZW_CMD_UNLOCK2:
        if (rm->mode != 0u || !armed) return ZW_REASON_BAD_COMMAND;
        rm->mode = 1u;
        zw_rm_publish_gains(rm, 0.0f, 0.0f); /* output off while the block may change */
        for (i = 0; i <= ZW_CERT_WORDS; ++i) rm->staged[i] = zw_rm_sealed_word(rm, i);
        return ZW_REASON_NONE;
    case ZW_CMD_SEAL:
        if (rm->mode == 0u) return ZW_REASON_BAD_COMMAND;
        return zw_rm_seal_staged(rm);
    case ZW_CMD_ABORT:
        if (rm->mode == 0u) return ZW_REASON_BAD_COMMAND;
        rm->mode = 0u; /* the sealed block and device were never touched; gains stay off */
        return ZW_REASON_NONE;
    default: return ZW_REASON_BAD_COMMAND;
    }
}

