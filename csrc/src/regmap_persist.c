/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Persistence of the register map, zwidth/regmap_persist.h: the image SAVE writes through
 * the firmware's hook, and its checks at power-up (zw_regmap_restore), which install only
 * what passes SEAL's checks and the certification of a gain write again. */
#include "zwidth/regmap_persist.h"

#include <stddef.h>

#include "regmap_internal.h"

#define IMAGE_MAGIC0 0x5A57u /* "ZW" */
#define IMAGE_MAGIC1 0x4E56u /* "NV" */
#define IMAGE_BLOCK 3u       /* first word of the block */
#define IMAGE_GAINS (IMAGE_BLOCK + ZW_CERT_WORDS + 1u) /* K, then B */
#define IMAGE_BOX_CERT (IMAGE_GAINS + 4u)              /* the box certificate's words */
#define IMAGE_CRC (ZW_IMAGE_WORDS - 1u)

static uint_least16_t image_word(const uint_least8_t *img, unsigned i)
{
    return (uint_least16_t)((((unsigned)img[2u * i] & 0xFFu) << 8) | ((unsigned)img[(2u * i) + 1u] & 0xFFu));
}

/* Word i (below IMAGE_CRC) of the image of what is in force. */
static uint_least16_t image_word_of(const zw_regmap *rm, unsigned i)
{
    uint_least16_t w[2];
    if (i == 0u) {
        return IMAGE_MAGIC0;
    }
    if (i == 1u) {
        return IMAGE_MAGIC1;
    }
    if (i == 2u) {
        return ZW_IMAGE_FORMAT;
    }
    if (i < IMAGE_GAINS) {
        return zw_rm_sealed_word(rm, i - IMAGE_BLOCK);
    }
    if (i < IMAGE_BOX_CERT) {
        zw_float_to_words((i < (IMAGE_GAINS + 2u)) ? rm->K : rm->B, w);
        return w[(i - IMAGE_GAINS) & 1u];
    }
    return zw_rm_sealed_box_cert_word(rm, i - IMAGE_BOX_CERT);
}

bool zw_regmap_image(const zw_regmap *rm, uint_least8_t image[ZW_IMAGE_BYTES])
{
    unsigned i;
    uint_least16_t crc = 0xFFFFu;
    if ((rm == NULL) || (image == NULL) || (rm->is_sealed == 0u)) {
        return false;
    }
    for (i = 0u; i < ZW_IMAGE_WORDS; ++i) {
        const uint_least16_t w = (i < IMAGE_CRC) ? image_word_of(rm, i) : crc;
        crc = zw_rm_crc_word(crc, w);
        image[2u * i] = (uint_least8_t)(((unsigned)w >> 8) & 0xFFu);
        image[2u * i + 1u] = (uint_least8_t)((unsigned)w & 0xFFu);
    }
    return true;
}

/* The SAVE command (regmap_persist.h); the image is built in rm's scratch (734 B). */
zw_reason zw_rm_save(zw_regmap *rm)
{
    if (rm->mode != 0u) {
        return ZW_REASON_BAD_COMMAND;
    }
    if (rm->consent == 0u) {
        return ZW_REASON_NO_CONSENT;
    }
    if (rm->is_sealed == 0u) {
        return ZW_REASON_NOT_SEALED;
    }
    if (rm->storage.save == NULL) {
        return ZW_REASON_NO_STORAGE;
    }
    (void)zw_regmap_image(rm, rm->wire_scratch);
    return rm->storage.save(rm->storage.ctx, rm->wire_scratch, ZW_IMAGE_BYTES) ? ZW_REASON_NONE
                                                                               : ZW_REASON_STORAGE;
}

void zw_regmap_set_storage(zw_regmap *rm, const zw_regmap_storage *storage)
{
    if (rm == NULL) {
        return;
    }
    rm->storage.save = NULL;
    rm->storage.ctx = NULL;
    if ((storage != NULL) && (storage->save != NULL)) {
        rm->storage = *storage;
    }
}

/* One image: its format and CRC, then its block through SEAL's checks (no MAC: the image
 * is the drive's own), then its gains as a write from (0, 0).  Returns the reason the
 * block was refused (nothing changed then); *gains_why the reason the gains were refused
 * (they stay off), ZW_REASON_NONE when they are in force. */
static zw_reason restore_one(zw_regmap *rm, const uint_least8_t *img, size_t len,
                             zw_reason *gains_why)
{
    uint_least16_t gains[4];
    uint_least32_t accepted = rm->accepted;
    unsigned i;
    uint_least16_t crc = 0xFFFFu;
    zw_reason why;
    *gains_why = ZW_REASON_NONE;
    if ((img == NULL) || (len != ZW_IMAGE_BYTES)) {
        return ZW_REASON_IMAGE_FORMAT;
    }
    if ((image_word(img, 0u) != IMAGE_MAGIC0) || (image_word(img, 1u) != IMAGE_MAGIC1) ||
        (image_word(img, 2u) != ZW_IMAGE_FORMAT)) {
        return ZW_REASON_IMAGE_FORMAT;
    }
    for (i = 0u; i < IMAGE_CRC; ++i) {
        crc = zw_rm_crc_word(crc, image_word(img, i));
    }
    if (crc != image_word(img, IMAGE_CRC)) {
        return ZW_REASON_IMAGE_CRC;
    }
    for (i = 0u; i <= ZW_CERT_WORDS; ++i) {
        rm->staged[i] = image_word(img, IMAGE_BLOCK + i);
    }
    for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
        rm->staged_box_cert[i] = image_word(img, IMAGE_BOX_CERT + i);
    }
    for (i = 0u; i < 4u; ++i) {
        gains[i] = image_word(img, IMAGE_GAINS + i);
    }
    why = zw_rm_seal_staged(rm, false); /* sealed: operation, gains off */
    for (i = 0u; i <= ZW_CERT_WORDS; ++i) {
        rm->staged[i] = 0u;
    }
    for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
        rm->staged_box_cert[i] = 0u;
    }
    if (why == ZW_REASON_CRC) {
        return ZW_REASON_IMAGE_CRC;
    }
    if (why != ZW_REASON_NONE) {
        return why;
    }
    *gains_why = zw_rm_apply_gains(rm, zw_words_to_float(&gains[0]), zw_words_to_float(&gains[2]));
    rm->accepted = accepted; /* a restore is not a gain write */
    return ZW_REASON_NONE;
}

zw_status zw_regmap_restore(zw_regmap *rm, const uint_least8_t *newest, size_t newest_len,
                            const uint_least8_t *previous, size_t previous_len,
                            zw_reason *reason)
{
    zw_reason first = ZW_REASON_NONE, why, gains_why = ZW_REASON_NONE;
    uint_least16_t source = 0u;
    if (reason != NULL) {
        *reason = ZW_REASON_NONE;
    }
    if (rm == NULL) {
        return ZW_ERR_NULL;
    }
    if ((newest != NULL) || (newest_len != 0u)) {
        why = restore_one(rm, newest, newest_len, &gains_why);
        if (why == ZW_REASON_NONE) {
            source = 1u;
        } else {
            first = why;
        }
    }
    if ((source == 0u) && ((previous != NULL) || (previous_len != 0u))) {
        why = restore_one(rm, previous, previous_len, &gains_why);
        if (why == ZW_REASON_NONE) {
            source = 2u;
        } else if (first == ZW_REASON_NONE) {
            first = why;
        } else {
            /* the newest image's reason is the one reported */
        }
    }
    rm->restore_source = source;
    rm->restore_reason = (uint_least16_t)((first != ZW_REASON_NONE) ? first : gains_why);
    if (reason != NULL) {
        *reason = (zw_reason)rm->restore_reason;
    }
    (void)zw_rm_live_all(rm);
    return ((source != 0u) || (first == ZW_REASON_NONE)) ? ZW_OK : ZW_ERR_ARG;
}
