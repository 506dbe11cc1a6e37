/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* zwidth/regmap_commission.h - commissioning of the register map (part of
 * zwidth/regmap.h, the entry point): the command register and what its commands do.
 *
 *   0x0060  ZW_REG_COMMAND      w       ZW_CMD_UNLOCK1 then ZW_CMD_UNLOCK2 (two writes in a
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
 */
#ifndef ZWIDTH_REGMAP_COMMISSION_H
#define ZWIDTH_REGMAP_COMMISSION_H

#ifdef __cplusplus
extern "C" {
#endif

/* Command values (macros, not enum constants: an enum constant must fit a 16-bit int on
 * TI C28x, and 0xC0DE does not). */
#define ZW_CMD_UNLOCK1 0xC0DEu
#define ZW_CMD_UNLOCK2 0x5AFEu
#define ZW_CMD_SEAL 0x5EA1u
#define ZW_CMD_ABORT 0xAB07u

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REGMAP_COMMISSION_H */
