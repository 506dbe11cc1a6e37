/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* The register map's wire format, zwidth/regmap_codec.h: binary32 floats over two
 * registers, CRC-16/MODBUS over words, the certified block as words.
 *
 * Portability (TI C28x: 16-bit char and int): words are held in uint_least16_t and
 * masked, every shift is done on a uint_least32_t, floats are packed and unpacked by
 * frexpf/ldexpf arithmetic rather than by type punning.
 */
#include "zwidth/regmap_codec.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

#include "regmap_internal.h"

/* ---- words, floats, CRC ----------------------------------------------------------------- */

void zw_float_to_words(float value, uint_least16_t words[2])
{
    uint_least32_t bits;
    if (words == NULL) return;
    if (value != value) {
        bits = 0x7FC00000u; /* every NaN becomes the one quiet NaN */
    } else {
        float a = value < 0.0f ? -value : value;
        int e;
        if (a > FLT_MAX) {
            bits = 0x7F800000u;
        } else if (a == 0.0f) {
            bits = 0u;
        } else {
            /* a = f 2^e with f in [1/2, 1): both f 2^24 and a 2^149 are integers below
             * 2^24, so every step is exact. */
            float f = frexpf(a, &e);
            if (e >= FLT_MIN_EXP) /* normal: biased exponent (e - 1) + 127 */
                bits = ((uint_least32_t)(e + 126) << 23) |
                       ((uint_least32_t)ldexpf(f, 24) - 0x800000u);
            else /* subnormal: the significand is a / 2^-149 */
                bits = (uint_least32_t)ldexpf(a, 149);
        }
        /* signbit, not value < 0, so that -0.0 keeps its sign */
        if (signbit(value)) bits |= 0x80000000u;
    }
    words[0] = (uint_least16_t)((bits >> 16) & 0xFFFFu);
    words[1] = (uint_least16_t)(bits & 0xFFFFu);
}

float zw_words_to_float(const uint_least16_t words[2])
{
    uint_least32_t bits, frac;
    unsigned expo;
    float v;
    if (words == NULL) return QUIET_NAN_F;
    bits = ((uint_least32_t)(words[0] & 0xFFFFu) << 16) | (uint_least32_t)(words[1] & 0xFFFFu);
    expo = (unsigned)((bits >> 23) & 0xFFu);
    frac = bits & 0x7FFFFFu;
    if (expo == 0xFFu) v = frac != 0u ? QUIET_NAN_F : ZW_HUGE_VALF;
    else if (expo == 0u) v = ldexpf((float)frac, -149); /* subnormal (or zero) */
    else v = ldexpf((float)(frac | 0x800000u), (int)expo - 150);
    return (bits & 0x80000000u) != 0u ? -v : v;
}

static uint_least16_t crc_byte(uint_least16_t crc, unsigned byte)
{
    int k;
    crc = (uint_least16_t)((crc ^ (byte & 0xFFu)) & 0xFFFFu);
    for (k = 0; k < 8; ++k)
        crc = (crc & 1u) != 0u ? (uint_least16_t)(((unsigned)crc >> 1) ^ 0xA001u)
                               : (uint_least16_t)((unsigned)crc >> 1);
    return crc;
}

uint_least16_t zw_rm_crc_word(uint_least16_t crc, uint_least16_t word)
{
    crc = crc_byte(crc, ((unsigned)word >> 8) & 0xFFu);
    return crc_byte(crc, (unsigned)word & 0xFFu);
}

uint_least16_t zw_crc16_words(const uint_least16_t *words, size_t count)
{
    uint_least16_t crc = 0xFFFFu;
    size_t i;
    if (words == NULL) return crc;
    for (i = 0; i < count; ++i) crc = zw_rm_crc_word(crc, words[i]);
    return crc;
}

/* ---- the certified block ------------------------------------------------------------------ */

float zw_cert_field(const zw_cert *c, unsigned i)
{
    switch (i) {
    case F_M: return c->m;
    case F_B: return c->b;
    case F_T: return c->T;
    case F_SIGMA: return c->sigma;
    case F_R: return c->r;
    case F_K_MIN: return c->k_min;
    case F_K_MAX: return c->k_max;
    case F_B_MIN: return c->b_min;
    case F_B_MAX: return c->b_max;
    case F_DK_MAX: return c->dk_max;
    case F_DB_MAX: return c->db_max;
    case F_DELAY: return c->delay;
    case F_VFILTER: return c->vfilter;
    case F_VF_PARAM: return c->vf_param;
    default: return c->differentiator;
    }
}

void zw_cert_set_field(zw_cert *c, unsigned i, float v)
{
    switch (i) {
    case F_M: c->m = v; break;
    case F_B: c->b = v; break;
    case F_T: c->T = v; break;
    case F_SIGMA: c->sigma = v; break;
    case F_R: c->r = v; break;
    case F_K_MIN: c->k_min = v; break;
    case F_K_MAX: c->k_max = v; break;
    case F_B_MIN: c->b_min = v; break;
    case F_B_MAX: c->b_max = v; break;
    case F_DK_MAX: c->dk_max = v; break;
    case F_DB_MAX: c->db_max = v; break;
    case F_DELAY: c->delay = v; break;
    case F_VFILTER: c->vfilter = v; break;
    case F_VF_PARAM: c->vf_param = v; break;
    default: c->differentiator = v; break;
    }
}

void zw_cert_encode(const zw_cert *c, uint_least16_t words[ZW_CERT_WORDS + 1u])
{
    unsigned i;
    for (i = 0; i < ZW_CERT_FIELDS; ++i) zw_float_to_words(zw_cert_field(c, i), &words[2u * i]);
    words[CRC_INDEX] = zw_crc16_words(words, ZW_CERT_WORDS);
}

void zw_cert_decode(const uint_least16_t words[ZW_CERT_WORDS], zw_cert *c)
{
    unsigned i;
    for (i = 0; i < ZW_CERT_FIELDS; ++i) zw_cert_set_field(c, i, zw_words_to_float(&words[2u * i]));
}

