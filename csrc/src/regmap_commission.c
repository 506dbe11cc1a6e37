/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Commissioning of the register map, zwidth/regmap_commission.h: the staged block, the
 * command register (UNLOCK1, UNLOCK2, SEAL, ABORT) and SEAL itself.
 */
#include "zwidth/regmap_commission.h"

#include <stdbool.h>
#include <stddef.h>

#include "regmap_internal.h"
#include "zwidth/selftest.h"

/* Word i (0..ZW_CERT_WORDS) of the block in force: the sealed block and its CRC, all 0 unsealed.
 * Only the read path needs it, so it re-encodes rather than keeping a copy. */
uint_least16_t zw_rm_sealed_word(const zw_regmap *rm, unsigned i)
{
    uint_least16_t w[2], crc = 0xFFFFu;
    unsigned f;
    if (rm->is_sealed == 0u) {
        return 0u;
    }
    if (i < ZW_CERT_WORDS) {
        zw_float_to_words(zw_cert_field(&rm->sealed, i / 2u), w);
        return w[i & 1u];
    }
    for (f = 0u; f < ZW_CERT_FIELDS; ++f) {
        zw_float_to_words(zw_cert_field(&rm->sealed, f), w);
        crc = zw_rm_crc_word(zw_rm_crc_word(crc, w[0]), w[1]);
    }
    return crc;
}

void zw_regmap_auth_message(const uint_least16_t nonce[ZW_AUTH_NONCE_WORDS],
                            const uint_least16_t block[ZW_CERT_WORDS + 1u],
                            const uint_least16_t box_cert[ZW_BOX_CERT_WORDS],
                            uint_least8_t msg[ZW_AUTH_MSG_BYTES])
{
    size_t i;
    const unsigned version = ZW_REGMAP_VERSION;
    const size_t block_end = ZW_AUTH_NONCE_WORDS + ZW_CERT_WORDS + 1u;
    if ((nonce == NULL) || (block == NULL) || (box_cert == NULL) || (msg == NULL)) {
        return;
    }
    msg[0] = (uint_least8_t)((version >> 8) & 0xFFu);
    msg[1] = (uint_least8_t)(version & 0xFFu);
    /* then the nonce, the block with its CRC and the certificate, each word high byte first */
    for (i = 0u; i < (block_end + ZW_BOX_CERT_WORDS); ++i) {
        unsigned w;
        if (i < ZW_AUTH_NONCE_WORDS) {
            w = (unsigned)nonce[i];
        } else if (i < block_end) {
            w = (unsigned)block[i - ZW_AUTH_NONCE_WORDS];
        } else {
            w = (unsigned)box_cert[i - block_end];
        }
        msg[2u + (2u * i)] = (uint_least8_t)((w >> 8) & 0xFFu);
        msg[3u + (2u * i)] = (uint_least8_t)(w & 0xFFu);
    }
}

/* The firmware's verdict on the client's MAC over this session's nonce, the staged block
 * and the staged certificate (the message in rm's scratch: 736 B is too much for the
 * Modbus task's stack). */
ZW_NOINLINE static bool mac_verifies(zw_regmap *rm)
{
    uint_least8_t mac[2u * ZW_AUTH_MAC_WORDS];
    size_t i;
    if (rm->auth.verify == NULL) {
        return false;
    }
    zw_regmap_auth_message(rm->nonce, rm->staged, rm->staged_box_cert, rm->wire_scratch);
    for (i = 0u; i < ZW_AUTH_MAC_WORDS; ++i) {
        mac[2u * i] = (uint_least8_t)(((unsigned)rm->mac[i] >> 8) & 0xFFu);
        mac[2u * i + 1u] = (uint_least8_t)((unsigned)rm->mac[i] & 0xFFu);
    }
    return rm->auth.verify(rm->auth.ctx, rm->wire_scratch, ZW_AUTH_MSG_BYTES, mac, sizeof mac);
}

/* Back to operation: the nonce and the MAC die with the session. */
static void end_session(zw_regmap *rm)
{
    size_t i;
    rm->mode = 0u;
    for (i = 0u; i < ZW_AUTH_NONCE_WORDS; ++i) {
        rm->nonce[i] = 0u;
    }
    for (i = 0u; i < ZW_AUTH_MAC_WORDS; ++i) {
        rm->mac[i] = 0u;
    }
}

/* UNLOCK2's fresh nonce, drawn before anything changes (false: none). */
static bool draw_nonce(zw_regmap *rm, uint_least16_t nonce[ZW_AUTH_NONCE_WORDS])
{
    uint_least8_t bytes[2u * ZW_AUTH_NONCE_WORDS];
    size_t i;
    if (rm->auth.random == NULL || rm->auth.verify == NULL) {
        return false;
    }
    if (!rm->auth.random(rm->auth.ctx, bytes, sizeof bytes)) {
        return false;
    }
    for (i = 0u; i < ZW_AUTH_NONCE_WORDS; ++i) {
        nonce[i] = (uint_least16_t)((((unsigned)bytes[2u * i] & 0xFFu) << 8) |
                                    ((unsigned)bytes[(2u * i) + 1u] & 0xFFu));
    }
    return true;
}

/* SEAL: the self-test, the CRC, the MAC when authenticate (not for the firmware's own
 * block at power-up), the policy (zw_rm_policy_admit), then the block installed and the
 * output off. */
zw_reason zw_rm_seal_staged(zw_regmap *rm, bool authenticate)
{
    unsigned i;
    zw_reason why;
    /* every check below, and every certification after it, trusts the arithmetic */
    if (zw_selftest() != ZW_OK) {
        return ZW_REASON_FPENV;
    }
    if (zw_crc16_words(rm->staged, ZW_CERT_WORDS) != (rm->staged[CRC_INDEX] & 0xFFFFu)) {
        return ZW_REASON_CRC;
    }
    if (authenticate && !mac_verifies(rm)) {
        return ZW_REASON_AUTH;
    }
    why = zw_rm_policy_admit(rm);
    if (why != ZW_REASON_NONE) {
        return why;
    }
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) { /* -0.0 stored as +0.0 */
        const float v = zw_rm_staged_float(rm, i);
        zw_cert_set_field(&rm->sealed, i, (v == 0.0f) ? 0.0f : v);
    }
    rm->is_sealed = 1u;
    end_session(rm);
    zw_rm_publish_gains(rm, 0.0f, 0.0f); /* gains stay off after a seal */
    return ZW_REASON_NONE;
}

/* The box certificate window, written in commissioning: any words (SEAL judges them), the
 * floats turned from the map's word order into canonical ABCD words. */
zw_reason zw_rm_write_box_cert(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                               const uint_least16_t *words, const uint_least8_t *bytes)
{
    size_t i;
    for (i = 0u; i < count; ++i) {
        const uint_least32_t a = (uint_least32_t)addr + (uint_least32_t)i;
        rm->staged_box_cert[a - ZW_REG_BOX_CERT] =
            ((a >= ZW_REG_BOX_CERT_B) && (a < ZW_REG_BOX_CERT_NODES))
                ? zw_rm_pair_word(rm, words, bytes, i) : zw_rm_payload_word(words, bytes, i);
    }
    return ZW_REASON_NONE;
}

/* Word i of the box certificate in force (all 0 without one). */
uint_least16_t zw_rm_sealed_box_cert_word(const zw_regmap *rm, unsigned i)
{
    return ((rm->is_sealed != 0u) && (rm->box_cert_valid != 0u)) ? zw_box_cert_word(&rm->box_cert, i) : 0u;
}

/* Staged block: every float finite, then all words stored.  The CRC word is free. */
zw_reason zw_rm_write_cert(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                            const uint_least16_t *words, const uint_least8_t *bytes)
{
    size_t i;
    for (i = 0u; (i < count) && (((uint_least32_t)addr + i) < ZW_REG_CERT_CRC); i += 2u) {
        if (!zw_rm_finite_f(zw_rm_pair_float(rm, words, bytes, i))) {
            return ZW_REASON_NOT_FINITE;
        }
    }
    /* the floats in the map's word order (pairs start at even offsets: the write starts
     * on an even address), the CRC word as it is */
    for (i = 0u; i < count; ++i) {
        rm->staged[((size_t)addr - ZW_REG_CERT_M) + i] =
            (((uint_least32_t)addr + i) < ZW_REG_CERT_CRC) ? zw_rm_pair_word(rm, words, bytes, i)
                                                           : zw_rm_payload_word(words, bytes, i);
    }
    return ZW_REASON_NONE;
}

/* The MAC words, written in commissioning (any value). */
zw_reason zw_rm_write_mac(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                          const uint_least16_t *words, const uint_least8_t *bytes)
{
    size_t i;
    for (i = 0u; i < count; ++i) {
        rm->mac[((size_t)addr - ZW_REG_MAC) + i] = zw_rm_payload_word(words, bytes, i);
    }
    return ZW_REASON_NONE;
}

/* UNLOCK2: a commissioning session with a fresh nonce, the staged block and certificate a
 * copy of those in force (a frame of its own: the nonce is not on SEAL's stack). */
ZW_NOINLINE static zw_reason unlock2(zw_regmap *rm, bool armed)
{
    unsigned i;
    uint_least16_t nonce[ZW_AUTH_NONCE_WORDS];
    if ((rm->mode != 0u) || !armed) {
        return ZW_REASON_BAD_COMMAND;
    }
    if (rm->consent == 0u) {
        return ZW_REASON_NO_CONSENT;
    }
    if (rm->has_ceilings == 0u) {
        return ZW_REASON_NO_CEILINGS;
    }
    if (!draw_nonce(rm, nonce)) {
        return ZW_REASON_RNG;
    }
    rm->mode = 1u;
    zw_rm_publish_gains(rm, 0.0f, 0.0f); /* output off while the block may change */
    for (i = 0u; i <= ZW_CERT_WORDS; ++i) {
        rm->staged[i] = zw_rm_sealed_word(rm, i);
    }
    for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
        rm->staged_box_cert[i] = zw_rm_sealed_box_cert_word(rm, i);
    }
    for (i = 0u; i < ZW_AUTH_NONCE_WORDS; ++i) {
        rm->nonce[i] = nonce[i];
    }
    for (i = 0u; i < ZW_AUTH_MAC_WORDS; ++i) {
        rm->mac[i] = 0u;
    }
    return ZW_REASON_NONE;
}

zw_reason zw_rm_command(zw_regmap *rm, uint_least16_t cmd, bool armed)
{
    zw_reason why;
    switch (cmd) {
    case ZW_CMD_UNLOCK1:
        if (rm->mode != 0u) { /* already commissioning */
            why = ZW_REASON_BAD_COMMAND;
        } else if (rm->consent == 0u) {
            why = ZW_REASON_NO_CONSENT;
        } else {
            rm->unlock_armed = 1u;
            why = ZW_REASON_NONE;
        }
        break;
    case ZW_CMD_UNLOCK2:
        why = unlock2(rm, armed);
        break;
    case ZW_CMD_SEAL:
        if (rm->mode == 0u) {
            why = ZW_REASON_BAD_COMMAND;
        } else if (rm->consent == 0u) {
            why = ZW_REASON_NO_CONSENT;
        } else if (rm->has_ceilings == 0u) {
            why = ZW_REASON_NO_CEILINGS;
        } else {
            why = zw_rm_seal_staged(rm, true);
        }
        break;
    case ZW_CMD_SAVE:
        why = zw_rm_save(rm);
        break;
    case ZW_CMD_ABORT:
        if (rm->mode == 0u) {
            why = ZW_REASON_BAD_COMMAND;
        } else {
            end_session(rm); /* the sealed block and device were never touched; gains stay off */
            why = ZW_REASON_NONE;
        }
        break;
    default:
        why = ZW_REASON_BAD_COMMAND;
        break;
    }
    return why;
}

void zw_regmap_set_consent(zw_regmap *rm, bool enabled)
{
    if (rm == NULL) {
        return;
    }
    rm->consent = (uint_least16_t)(enabled ? 1u : 0u);
}

void zw_regmap_set_auth(zw_regmap *rm, const zw_regmap_auth *auth)
{
    if (rm == NULL) {
        return;
    }
    rm->auth.random = NULL;
    rm->auth.verify = NULL;
    rm->auth.ctx = NULL;
    if ((auth != NULL) && (auth->random != NULL) && (auth->verify != NULL)) {
        rm->auth = *auth;
    }
}
