/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* zwidth/regmap_codec.h - the register map's wire format (part of zwidth/regmap.h, the
 * entry point): IEEE-754 binary32 floats over two registers, CRC-16/MODBUS over words, and
 * the certified block as words.  Portable C99 (no type punning; 16-bit chars work).
 */
#ifndef ZWIDTH_REGMAP_CODEC_H
#define ZWIDTH_REGMAP_CODEC_H

#include <stddef.h>
#include <stdint.h>

#include "zwidth/box_cert.h"
#include "zwidth/precision.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ZW_CERT_WORDS 34u /* words 0x0040..0x0061 covered by the CRC (map version 4) */

/* The certified block as numbers (what the CRC seals, in register order). */
typedef struct zw_cert {
    float m, b, T;         /* plant */
    float sigma;           /* stiffness fraction of K_max(B), (0, 1] */
    float r;               /* spectral radius bound, (0, 1] */
    float k_min, k_max;    /* absolute K bounds */
    float b_min, b_max;    /* absolute B bounds */
    float dk_max, db_max;  /* largest change per accepted write, > 0 */
    /* the loop the drive runs (integers held as floats, as on the wire) */
    float delay;           /* d samples */
    float vfilter;         /* 0 none, 1 low-pass, 2 moving average */
    float vf_param;        /* low-pass cut-off [Hz], or the average's n, or 0 */
    float differentiator;  /* 0 backward, 1 Tustin */
    /* the plant box (map version 4): m in [m, m_hi], b in [b, b_hi].  A point block has
     * m_hi = m and b_hi = b; m_hi = b_hi = 0 is the same point block (so a zw_cert whose
     * new fields are zero-initialised keeps its version-3 meaning). */
    float m_hi, b_hi;
} zw_cert;

/* The block's fields in register order (0 m, 1 b, 2 T, 3 sigma, 4 r, 5 k_min, 6 k_max,
 * 7 b_min, 8 b_max, 9 dk_max, 10 db_max, 11 delay, 12 vfilter, 13 vf_param,
 * 14 differentiator, 15 m_hi, 16 b_hi): the one place that order is written down. */
#define ZW_CERT_FIELDS 17u
float zw_cert_field(const zw_cert *c, unsigned field);
void zw_cert_set_field(zw_cert *c, unsigned field, float value);
/* The block as it is on the wire: 34 words, then its CRC (words[ZW_CERT_WORDS]). */
void zw_cert_encode(const zw_cert *c, uint_least16_t words[ZW_CERT_WORDS + 1u]);
void zw_cert_decode(const uint_least16_t words[ZW_CERT_WORDS], zw_cert *c);

/* A box certificate (box_cert.h) as words (map version 5's window, the stored image):
 * word i (0..ZW_BOX_CERT_WORDS-1; 0 past the end); all of them; and back.  Decoding and
 * encoding again gives the same words exactly when the words are canonical (every float
 * finite, or the one quiet NaN; no subnormal on a flushing FPU): the register map seals
 * only such a certificate, so what it holds is bit for bit what the client wrote. */
uint_least16_t zw_box_cert_word(const zw_box_cert *c, unsigned i);
void zw_box_cert_encode(const zw_box_cert *c, uint_least16_t words[ZW_BOX_CERT_WORDS]);
void zw_box_cert_decode(const uint_least16_t words[ZW_BOX_CERT_WORDS], zw_box_cert *c);

/* CRC-16/MODBUS (poly 0xA001 reflected, init 0xFFFF) of 16-bit words, high byte first
 * (words NULL: the CRC of no words, 0xFFFF). */
uint_least16_t zw_crc16_words(const uint_least16_t *words, size_t count);

/* IEEE-754 binary32 <-> two registers, high word first (portable: no type punning).
 * Exact for every finite value (subnormals and -0.0 included) and the infinities; every
 * NaN becomes the quiet NaN 0x7FC0 0x0000.  words NULL: no-op, and NaN back.  On an FPU
 * that flushes subnormals to zero (C28x, Cortex-M with FZ set) a subnormal decodes as 0;
 * no certified field can be subnormal and still pass the policy, so nothing depends on it. */
void zw_float_to_words(float value, uint_least16_t words[2]);
float zw_words_to_float(const uint_least16_t words[2]);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REGMAP_CODEC_H */
