/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* zwidth/regmap_persist.h - persistence of the register map (part of zwidth/regmap.h, the
 * entry point): applying gains and saving them are separate.  A gain write applies a pair;
 * ZW_CMD_SAVE writes the sealed block and the active gains to non-volatile storage through
 * a hook the firmware supplies; at power-up zw_regmap_restore checks a stored image and
 * installs only what passes every check again.
 *
 * The image (ZW_IMAGE_BYTES, every word high byte first):
 *   words 0, 1   0x5A57 0x4E56 ("ZWNV")
 *   word  2      ZW_IMAGE_FORMAT
 *   words 3..37  the sealed block's 34 words and its CRC (map version 4: the plant ranges)
 *   words 38..41 K and B (binary32, high word first)
 *   words 42..365 the box certificate in force (the window of ZW_REG_BOX_CERT; all 0
 *                without one), verified again at restore
 *   word  366    CRC-16/MODBUS of words 0..365
 * Format 3 (map version 5).  An image of an older format (format 2: 86 bytes, no
 * certificate; format 1: 78 bytes, map version 3's 30-word block) is refused,
 * ZW_REASON_IMAGE_FORMAT, not migrated: the drive then starts with its power-up
 * block and gains off until it is commissioned again (a migration would seal a block no
 * client wrote in the new layout; the old image stays in storage, untouched).
 * SAVE (in operation, with a sealed block and consent; refused ZW_REASON_NO_CONSENT,
 * ZW_REASON_NOT_SEALED, ZW_REASON_NO_STORAGE without the hook, ZW_REASON_STORAGE when it
 * reports a failure) changes no register but the refusal ones when refused.
 *
 * zw_regmap_restore (init context, after zw_regmap_init and zw_regmap_set_ceilings) tries
 * the newest image, then the previous one (the last good, when the firmware keeps two):
 * length, magic, format version (an older format is refused), image CRC, block CRC, the
 * policy and the ceilings (as SEAL, without the MAC: the image is the drive's own), then
 * the gains, re-certified as a write from (0, 0) (all rules, steps included).  A block
 * that passes is sealed; gains that do not pass stay off.  Nothing uncertified is ever
 * applied: when no image passes, the power-up block (or none) stays in force, gains off.
 * ZW_REG_RESTORE_SOURCE reads 0 (no image applied), 1 (the newest), 2 (the previous);
 * ZW_REG_RESTORE_REASON the reason the first refused image or gain pair was refused (0
 * when the newest was applied whole, or no image was given).
 */
#ifndef ZWIDTH_REGMAP_PERSIST_H
#define ZWIDTH_REGMAP_PERSIST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ZW_CMD_SAVE 0x5A7Eu
#define ZW_IMAGE_FORMAT 3u
#define ZW_IMAGE_WORDS 367u
#define ZW_IMAGE_BYTES 734u

/* The firmware's non-volatile storage: save writes the image (len bytes, each 0..255)
 * and returns true once it is stored durably (write the new copy, keep the previous one
 * until the new one is complete).  Runs in the Modbus task, during SAVE. */
typedef struct zw_regmap_storage {
    bool (*save)(void *ctx, const uint_least8_t *image, size_t len);
    void *ctx;
} zw_regmap_storage;

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REGMAP_PERSIST_H */
