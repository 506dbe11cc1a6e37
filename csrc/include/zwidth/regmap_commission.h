/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* zwidth/regmap_commission.h - commissioning of the register map (part of
 * zwidth/regmap.h, the entry point): the command register and what its commands do.
 *
 *   0x0064  ZW_REG_COMMAND      w       ZW_CMD_UNLOCK1 then ZW_CMD_UNLOCK2 (two writes in a
 *                                       row) opens commissioning mode and turns the output
 *                                       off (K = B = 0); ZW_CMD_SEAL checks the CRC and the
 *                                       policy and returns to operation (gains stay off);
 *                                       ZW_CMD_ABORT leaves commissioning and restores the
 *                                       last sealed block.  Reads as 0.
 *           Any request but a read between UNLOCK1 and UNLOCK2 (a refused or even an
 *           unprocessed one) disarms UNLOCK1; reads never do, so a client polling the
 *           map cannot block commissioning.  UNLOCK2 stages the block in force and its
 *           CRC (all 0 when nothing is sealed).  SEAL refused (CRC or BAD_POLICY) stays in
 *           commissioning mode.  UNLOCK1/UNLOCK2 in commissioning mode, SEAL/ABORT in
 *           operation mode and unknown values are refused with ZW_REASON_BAD_COMMAND.
 *           SEAL first runs zw_selftest() (zwidth/selftest.h): on a target whose
 *           floating-point environment is not the one the error bounds assume it is
 *           refused with ZW_REASON_FPENV (before the CRC is looked at) and nothing is
 *           sealed, so no gain pair can ever be accepted there.
 *
 * Consent and authentication (map version 3).  Knowing the unlock codes, the layout and
 * the CRC (all public) gets nobody in:
 *   - the drive must consent: ZW_REG_CONSENT (0x0080, r) reads the commissioning enable
 *     input the firmware reports with zw_regmap_set_consent (a key switch or a jumper on a
 *     real drive); it is off at power-up.  UNLOCK1, UNLOCK2 and SEAL are refused with
 *     ZW_REASON_NO_CONSENT while it is off.
 *   - the client must hold the drive's key: UNLOCK2 draws a fresh nonce from the RNG the
 *     firmware supplies (zw_regmap_set_auth) and publishes it in ZW_REG_NONCE (0x0088,
 *     8 words, r; 0 outside commissioning); without the hooks, or when the RNG fails,
 *     UNLOCK2 is refused with ZW_REASON_RNG and nothing changes.  The client writes the
 *     block, its CRC and a MAC of zw_regmap_auth_message (the map version, the nonce, the
 *     34 block words, the CRC and the 324 words of the box certificate window) under the
 *     drive's key into ZW_REG_MAC (0x0090, 16 words, rw in commissioning, reset to 0 by
 *     UNLOCK2).  SEAL checks, in this order: consent,
 *     the self-test, the CRC, the MAC (the firmware's verify hook; ZW_REASON_AUTH), then
 *     the policy.  A refused SEAL changes nothing (the client may correct and retry under
 *     the same nonce); the nonce dies with the session (SEAL accepted or ABORT), so a
 *     recorded session replayed later fails the MAC.
 * The block given to zw_regmap_init at power-up is the firmware's own and needs neither.
 */
#ifndef ZWIDTH_REGMAP_COMMISSION_H
#define ZWIDTH_REGMAP_COMMISSION_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/box_cert.h"
#include "zwidth/regmap_codec.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Command values (macros, not enum constants: an enum constant must fit a 16-bit int on
 * TI C28x, and 0xC0DE does not). */
#define ZW_CMD_UNLOCK1 0xC0DEu
#define ZW_CMD_UNLOCK2 0x5AFEu
#define ZW_CMD_SEAL 0x5EA1u
#define ZW_CMD_ABORT 0xAB07u

#define ZW_AUTH_NONCE_WORDS 8u  /* 128-bit nonce, ZW_REG_NONCE */
#define ZW_AUTH_MAC_WORDS 16u   /* 256-bit MAC (HMAC-SHA256 on zwidth's hosts), ZW_REG_MAC */
/* 2 (map version) + 16 (nonce) + 70 (block words and CRC) + 648 (box certificate words) */
#define ZW_AUTH_MSG_BYTES 736u

/* What the firmware supplies for commissioning (the map has no crypto of its own).  Both
 * run in the Modbus task, during the request that needs them.
 *   random: fill out[0 .. n-1] with fresh unpredictable bytes (each 0..255) from a
 *           cryptographic RNG (a TRNG, or a DRBG seeded from one); false when it cannot.
 *   verify: true only when mac[0 .. mac_len-1] is the MAC of msg[0 .. msg_len-1] under this
 *           drive's key (zwidth's hosts: HMAC-SHA256); compare in constant time.
 *   ctx:    handed to both unchanged. */
typedef struct zw_regmap_auth {
    bool (*random)(void *ctx, uint_least8_t *out, size_t n);
    bool (*verify)(void *ctx, const uint_least8_t *msg, size_t msg_len, const uint_least8_t *mac,
                   size_t mac_len);
    void *ctx;
} zw_regmap_auth;

/* The message a commissioning client MACs (and SEAL verifies): ZW_REGMAP_VERSION as two
 * bytes, high first; the nonce words; the 34 block words and the CRC word; the 324 box
 * certificate words (ZW_REG_BOX_CERT, all 0 for none; floats as canonical ABCD words
 * whatever the wire order); each word high byte first.  Bytes 0..255 in uint_least8_t.
 * Any argument NULL: no-op. */
void zw_regmap_auth_message(const uint_least16_t nonce[ZW_AUTH_NONCE_WORDS],
                            const uint_least16_t block[ZW_CERT_WORDS + 1u],
                            const uint_least16_t box_cert[ZW_BOX_CERT_WORDS],
                            uint_least8_t msg[ZW_AUTH_MSG_BYTES]);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REGMAP_COMMISSION_H */
