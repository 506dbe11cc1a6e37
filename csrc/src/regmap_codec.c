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
    if (words == NULL) {
        return;
    }
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
            if (e >= FLT_MIN_EXP) { /* normal: biased exponent (e - 1) + 127 */
                const uint_least32_t biased = (uint_least32_t)e + 126u;
                const uint_least32_t significand = (uint_least32_t)ldexpf(f, 24);
                bits = (biased << 23) | (significand - 0x800000u);
            } else { /* subnormal: the significand is a / 2^-149 */
                bits = (uint_least32_t)ldexpf(a, 149);
            }
        }
        /* signbit, not value < 0, so that -0.0 keeps its sign */
        if (signbit(value) != 0) {
            bits |= 0x80000000u;
        }
    }
    words[0] = (uint_least16_t)((bits >> 16) & 0xFFFFu);
    words[1] = (uint_least16_t)(bits & 0xFFFFu);
}

float zw_words_to_float(const uint_least16_t words[2])
{
    uint_least32_t bits, frac;
    unsigned expo;
    float v;
    if (words == NULL) {
        return QUIET_NAN_F;
    }
    bits = ((uint_least32_t)(words[0] & 0xFFFFu) << 16) | (uint_least32_t)(words[1] & 0xFFFFu);
    expo = (unsigned)((bits >> 23) & 0xFFu);
    frac = bits & 0x7FFFFFu;
    if (expo == 0xFFu) {
        v = (frac != 0u) ? QUIET_NAN_F : ZW_HUGE_VALF;
    } else if (expo == 0u) { /* subnormal (or zero) */
        v = ldexpf((float)frac, -149);
    } else {
        const uint_least32_t significand = frac | 0x800000u; /* the implicit leading 1 */
        v = ldexpf((float)significand, (int)expo - 150);
    }
    return ((bits & 0x80000000u) != 0u) ? -v : v;
}

static uint_least16_t crc_byte(uint_least16_t crc_in, unsigned byte)
{
    unsigned k;
    uint_least16_t crc = (uint_least16_t)((crc_in ^ (byte & 0xFFu)) & 0xFFFFu);
    for (k = 0u; k < 8u; ++k) {
        crc = ((crc & 1u) != 0u) ? (uint_least16_t)(((unsigned)crc >> 1) ^ 0xA001u)
                                 : (uint_least16_t)((unsigned)crc >> 1);
    }
    return crc;
}

uint_least16_t zw_rm_crc_word(uint_least16_t crc, uint_least16_t word)
{
    return crc_byte(crc_byte(crc, ((unsigned)word >> 8) & 0xFFu), (unsigned)word & 0xFFu);
}

uint_least16_t zw_crc16_words(const uint_least16_t *words, size_t count)
{
    uint_least16_t crc = 0xFFFFu;
    size_t i;
    if (words == NULL) {
        return crc;
    }
    for (i = 0u; i < count; ++i) {
        crc = zw_rm_crc_word(crc, words[i]);
    }
    return crc;
}

/* ---- the certified block ------------------------------------------------------------------ */

float zw_cert_field(const zw_cert *c, unsigned i)
{
    float v;
    switch (i) {
    case F_M: v = c->m; break;
    case F_B: v = c->b; break;
    case F_T: v = c->T; break;
    case F_SIGMA: v = c->sigma; break;
    case F_R: v = c->r; break;
    case F_K_MIN: v = c->k_min; break;
    case F_K_MAX: v = c->k_max; break;
    case F_B_MIN: v = c->b_min; break;
    case F_B_MAX: v = c->b_max; break;
    case F_DK_MAX: v = c->dk_max; break;
    case F_DB_MAX: v = c->db_max; break;
    case F_DELAY: v = c->delay; break;
    case F_VFILTER: v = c->vfilter; break;
    case F_VF_PARAM: v = c->vf_param; break;
    case F_DIFF: v = c->differentiator; break;
    case F_M_HI: v = c->m_hi; break;
    default: v = c->b_hi; break;
    }
    return v;
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
    case F_DIFF: c->differentiator = v; break;
    case F_M_HI: c->m_hi = v; break;
    default: c->b_hi = v; break;
    }
}

void zw_cert_encode(const zw_cert *c, uint_least16_t words[ZW_CERT_WORDS + 1u])
{
    unsigned i;
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        zw_float_to_words(zw_cert_field(c, i), &words[2u * i]);
    }
    words[CRC_INDEX] = zw_crc16_words(words, ZW_CERT_WORDS);
}

void zw_cert_decode(const uint_least16_t words[ZW_CERT_WORDS], zw_cert *c)
{
    unsigned i;
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        zw_cert_set_field(c, i, zw_words_to_float(&words[2u * i]));
    }
}


uint_least16_t zw_box_cert_word(const zw_box_cert *c, unsigned i)
{
    uint_least16_t w[2] = {0u, 0u};
    unsigned k;
    if (i == 0u) {
        w[0] = c->n_steps;
    } else if (i == 1u) {
        w[0] = c->n_nodes;
    } else if (i < ZW_BOX_CERT_WORD_K) {
        k = i - ZW_BOX_CERT_WORD_B;
        zw_float_to_words(c->B[k / 2u], w);
        w[0] = w[k & 1u];
    } else if (i < ZW_BOX_CERT_WORD_NODES) {
        k = i - ZW_BOX_CERT_WORD_K;
        zw_float_to_words(c->K[k / 2u], w);
        w[0] = w[k & 1u];
    } else if (i < ZW_BOX_CERT_WORDS) {
        w[0] = c->nodes[i - ZW_BOX_CERT_WORD_NODES];
    } else {
        /* past the end: 0 */
    }
    return (uint_least16_t)(w[0] & 0xFFFFu);
}

void zw_box_cert_encode(const zw_box_cert *c, uint_least16_t words[ZW_BOX_CERT_WORDS])
{
    unsigned i;
    for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
        words[i] = zw_box_cert_word(c, i);
    }
}

void zw_box_cert_decode(const uint_least16_t words[ZW_BOX_CERT_WORDS], zw_box_cert *c)
{
    unsigned i;
    c->n_steps = (uint_least16_t)(words[0] & 0xFFFFu);
    c->n_nodes = (uint_least16_t)(words[1] & 0xFFFFu);
    for (i = 0u; i <= ZW_BOX_CERT_MAX_STEPS; ++i) {
        c->B[i] = zw_words_to_float(&words[ZW_BOX_CERT_WORD_B + (2u * i)]);
    }
    for (i = 0u; i < ZW_BOX_CERT_MAX_STEPS; ++i) {
        c->K[i] = zw_words_to_float(&words[ZW_BOX_CERT_WORD_K + (2u * i)]);
    }
    for (i = 0u; i < ZW_BOX_CERT_NODE_WORDS; ++i) {
        c->nodes[i] = (uint_least16_t)(words[ZW_BOX_CERT_WORD_NODES + i] & 0xFFFFu);
    }
}
