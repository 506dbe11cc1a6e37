/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The drive-side gain register map, zwidth/regmap.h: the map, its requests and the
 * publication between contexts.  The wire format is in regmap_codec.c, the certification
 * policy in regmap_policy.c, commissioning in regmap_commission.c.
 *
 * Every request goes through the same steps: the whole address range is checked (mapped,
 * writable, whole two-word values, writable in the current mode), then the whole payload
 * (the gain pair is certified as a pair, staged floats must be finite), and only then is
 * anything stored.  A refusal therefore leaves every register as it was except the three
 * refusal registers.
 *
 * The gain pair (Modbus task -> control loop) and the state registers (control loop ->
 * Modbus task) cross contexts through a double buffer and a sequence word (regmap.h,
 * threading model): zw_rm_publish_gains / zw_regmap_set_state write, zw_regmap_active_gains /
 * read_state read; nothing else is shared.
 */
#include "zwidth/regmap.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "regmap_internal.h"

#if ZW_REGMAP_C11_ATOMICS
#include <stdatomic.h>
#endif

/* Modbus limits on one request (Modbus Application Protocol v1.1b3, 6.3 and 6.12). */
#define ZW_MB_READ_MAX 125u
#define ZW_MB_WRITE_MAX 123u
#define ZW_MB_READ_HOLDING 0x03u
#define ZW_MB_WRITE_SINGLE 0x06u
#define ZW_MB_WRITE_MULTIPLE 0x10u

/* Register kinds (bits). */
#define RK_RO 1u    /* read-only */
#define RK_GAIN 2u  /* K, B: writable in operation with a sealed block */
#define RK_CERT 4u  /* certified block and its CRC: writable in commissioning */
#define RK_CMD 8u   /* the command register */
#define RK_PAIR 16u /* two-word values, each starting at an even address */
#define RK_MAC 32u  /* the commissioning MAC: writable in commissioning */
#define RK_BOXC 64u /* the box certificate window: writable in commissioning */

/* ---- publication between contexts (regmap.h, threading model) ---------------------------- */

/* Port hook: orders the shared accesses around it.  On one core every shared access is
 * volatile and the compiler barrier is all that is needed; a multi-core build without C11
 * atomics must define it to a hardware fence (__DMB(), __sync_synchronize()). */
#ifndef ZW_MEMORY_BARRIER
#if defined(__GNUC__)
#define ZW_MEMORY_BARRIER() __asm__ __volatile__("" ::: "memory")
#else
#define ZW_MEMORY_BARRIER() ((void)0) /* volatile accesses keep their order */
#endif
#endif

/* C11: every shared store is a release and every shared load an acquire (also those of the
 * slots, so that a reader whose slot was overwritten sees the new sequence word); C99:
 * volatile accesses, ordered by the barrier between the steps. */
#if ZW_REGMAP_C11_ATOMICS
#define SHARED_LOAD(obj) atomic_load_explicit(&(obj), memory_order_acquire)
#define SHARED_STORE(obj, value) atomic_store_explicit(&(obj), (value), memory_order_release)
#define SHARED_ORDER() ((void)0)
#else
#define SHARED_LOAD(obj) (obj)
#define SHARED_STORE(obj, value) ((obj) = (value))
#define SHARED_ORDER() ZW_MEMORY_BARRIER()
#endif

/* The next sequence value: the slot it names, seq & 1, is the one not in force. */
static uint_least32_t next_seq(uint_least32_t seq)
{
    return (seq + 1u) & 0xFFFFFFFFu;
}

/* Modbus task, the only writer of the gains: the pair the control loop applies from now on
 * (and the task's own copy in rm->K, rm->B). */
void zw_rm_publish_gains(zw_regmap *rm, float K, float B)
{
    uint_least32_t seq = next_seq(SHARED_LOAD(rm->gains_seq));
    zw_regmap_gain_slot *slot = &rm->gains[seq & 1u];
    rm->K = K;
    rm->B = B;
    SHARED_ORDER(); /* the previous sequence word before this slot changes */
    SHARED_STORE(slot->K, K);
    SHARED_STORE(slot->B, B);
    SHARED_ORDER(); /* the whole slot before the word that makes it current */
    SHARED_STORE(rm->gains_seq, seq);
}

/* One sample of the state registers, as the Modbus side reads it. */
typedef struct state_sample {
    float x, v, f;
    uint_least32_t step;
} state_sample;

/* Modbus task: one consistent sample, or false after ZW_REGMAP_READ_TRIES tries. */
static bool read_state(const zw_regmap *rm, state_sample *out)
{
    unsigned tries;
    for (tries = 0u; tries < ZW_REGMAP_READ_TRIES; ++tries) {
        uint_least32_t seq = SHARED_LOAD(rm->state_seq);
        const zw_regmap_state_slot *slot = &rm->state[seq & 1u];
        SHARED_ORDER();
        out->x = SHARED_LOAD(slot->x);
        out->v = SHARED_LOAD(slot->v);
        out->f = SHARED_LOAD(slot->f);
        out->step = SHARED_LOAD(slot->step);
        SHARED_ORDER();
        if (SHARED_LOAD(rm->state_seq) == seq) {
            return true;
        }
    }
    return false;
}

typedef struct reg_range {
    uint_least16_t first, last, kind;
} reg_range;

/* Kind bits of one address, 0 when unmapped. */
static uint_least16_t reg_kind(uint_least32_t addr)
{
    /* The map of regmap.h; every address not covered here is unmapped. */
    static const reg_range k_ranges[] = {
        {ZW_REG_MAGIC, ZW_REG_LAST_EXCEPTION, RK_RO},
        {ZW_REG_ACCEPTED, ZW_REG_REFUSED + 1, RK_RO | RK_PAIR},
        {ZW_REG_K, ZW_REG_B + 1, RK_GAIN | RK_PAIR},
        {ZW_REG_LIVE_K_MAX, ZW_REG_STATE_STEP + 1, RK_RO | RK_PAIR},
        {ZW_REG_LIVE_POLE, ZW_REG_LIVE_POLE + 1, RK_RO | RK_PAIR},
        {ZW_REG_CERT_M, ZW_REG_CERT_CRC - 1, RK_CERT | RK_PAIR},
        {ZW_REG_CERT_CRC, ZW_REG_CERT_CRC, RK_CERT},
        {ZW_REG_COMMAND, ZW_REG_COMMAND, RK_CMD},
        {ZW_REG_CONSENT, ZW_REG_PRECISION, RK_RO},
        {ZW_REG_NONCE, ZW_REG_NONCE + ZW_AUTH_NONCE_WORDS - 1u, RK_RO},
        {ZW_REG_MAC, ZW_REG_MAC + ZW_AUTH_MAC_WORDS - 1u, RK_MAC},
        {ZW_REG_BOX_CERT, ZW_REG_BOX_CERT_B - 1u, RK_BOXC},
        {ZW_REG_BOX_CERT_B, ZW_REG_BOX_CERT_NODES - 1u, RK_BOXC | RK_PAIR},
        {ZW_REG_BOX_CERT_NODES, ZW_REG_COUNT - 1u, RK_BOXC},
    };
    size_t i;
    for (i = 0u; i < (sizeof k_ranges / sizeof k_ranges[0]); ++i) {
        if ((addr >= k_ranges[i].first) && (addr <= k_ranges[i].last)) {
            return k_ranges[i].kind;
        }
    }
    return 0u;
}

/* ---- reads --------------------------------------------------------------------------------- */

/* Both words of the two-word value at base (even address of an RK_PAIR register); the
 * state registers from the sample st. */
static void read_pair(const zw_regmap *rm, const state_sample *st, uint_least16_t base,
                      uint_least16_t w[2])
{
    uint_least32_t u;
    float f;
    if (base >= ZW_REG_BOX_CERT) { /* the certificate: staged in commissioning, else in force */
        unsigned i = (unsigned)(base - ZW_REG_BOX_CERT);
        w[0] = (rm->mode != 0u) ? rm->staged_box_cert[i] : zw_rm_sealed_box_cert_word(rm, i);
        w[1] = (rm->mode != 0u) ? rm->staged_box_cert[i + 1u] : zw_rm_sealed_box_cert_word(rm, i + 1u);
        return;
    }
    if (base >= ZW_REG_CERT_M) { /* the block: staged in commissioning, else sealed */
        unsigned i = (unsigned)(base - ZW_REG_CERT_M);
        w[0] = (rm->mode != 0u) ? rm->staged[i] : zw_rm_sealed_word(rm, i);
        w[1] = (rm->mode != 0u) ? rm->staged[i + 1u] : zw_rm_sealed_word(rm, i + 1u);
        return;
    }
    if ((base == ZW_REG_ACCEPTED) || (base == ZW_REG_REFUSED) || (base == ZW_REG_STATE_STEP)) {
        if (base == ZW_REG_ACCEPTED) {
            u = rm->accepted;
        } else if (base == ZW_REG_REFUSED) {
            u = rm->refused;
        } else {
            u = st->step;
        }
        w[0] = (uint_least16_t)((u >> 16) & 0xFFFFu);
        w[1] = (uint_least16_t)(u & 0xFFFFu);
        return;
    }
    switch (base) {
    case ZW_REG_K: f = rm->K; break;
    case ZW_REG_B: f = rm->B; break;
    case ZW_REG_STATE_X: f = st->x; break;
    case ZW_REG_STATE_V: f = st->v; break;
    case ZW_REG_STATE_F: f = st->f; break;
    case ZW_REG_LIVE_POLE:
        f = (rm->is_sealed != 0u) ? zw_rm_to_float(rm->loop.loop.spec.filter_pole) : QUIET_NAN_F;
        break;
    default: f = rm->live[(unsigned)(base - ZW_REG_LIVE_K_MAX) / 2u]; break;
    }
    zw_float_to_words(f, w);
}

/* A one-word register. */
static uint_least16_t read_single(const zw_regmap *rm, uint_least16_t addr)
{
    uint_least16_t w = 0u; /* ZW_REG_COMMAND reads as 0 */
    switch (addr) {
    case ZW_REG_MAGIC: w = ZW_REGMAP_MAGIC; break;
    case ZW_REG_VERSION: w = ZW_REGMAP_VERSION; break;
    case ZW_REG_MODE: w = rm->mode; break;
    case ZW_REG_SEALED: w = rm->is_sealed; break;
    case ZW_REG_LAST_REASON: w = rm->last_reason; break;
    case ZW_REG_LAST_EXCEPTION: w = rm->last_exception; break;
    case ZW_REG_CONSENT: w = rm->consent; break;
    case ZW_REG_RESTORE_SOURCE: w = rm->restore_source; break;
    case ZW_REG_RESTORE_REASON: w = rm->restore_reason; break;
    case ZW_REG_WORD_ORDER: w = rm->word_order; break;
    case ZW_REG_PRECISION: w = (uint_least16_t)ZW_REAL_BYTES; break;
    case ZW_REG_CERT_CRC:
        w = (rm->mode != 0u) ? rm->staged[CRC_INDEX] : zw_rm_sealed_word(rm, CRC_INDEX);
        break;
    default:
        if ((addr >= ZW_REG_NONCE) && (addr < (ZW_REG_NONCE + ZW_AUTH_NONCE_WORDS))) {
            w = rm->nonce[addr - ZW_REG_NONCE];
        } else if ((addr >= ZW_REG_MAC) && (addr < (ZW_REG_MAC + ZW_AUTH_MAC_WORDS))) {
            w = rm->mac[addr - ZW_REG_MAC];
        } else if ((addr >= ZW_REG_BOX_CERT) && (addr < ZW_REG_COUNT)) {
            const unsigned i = (unsigned)(addr - ZW_REG_BOX_CERT);
            w = (rm->mode != 0u) ? rm->staged_box_cert[i] : zw_rm_sealed_box_cert_word(rm, i);
        } else {
            /* the command register and the unmapped words in between (never asked) */
        }
        break;
    }
    return w;
}

/* ---- requests ------------------------------------------------------------------------------ */

static zw_mb_exception exception_of(zw_reason reason)
{
    zw_mb_exception exc;
    switch (reason) {
    case ZW_REASON_NONE: exc = ZW_MB_OK; break;
    case ZW_REASON_BAD_FUNCTION: exc = ZW_MB_ILLEGAL_FUNCTION; break;
    case ZW_REASON_UNMAPPED:
    case ZW_REASON_READ_ONLY:
    case ZW_REASON_HALF_FLOAT:
    case ZW_REASON_LOCKED:
    case ZW_REASON_NOT_SEALED: exc = ZW_MB_ILLEGAL_ADDRESS; break;
    default: exc = ZW_MB_ILLEGAL_VALUE; break;
    }
    return exc;
}

/* Record a refusal: only the three refusal registers change.  (Whether a pending UNLOCK1
 * survives is decided by the caller: writes disarm it, reads do not.) */
static zw_mb_exception refuse(zw_regmap *rm, zw_reason reason, zw_reason *out)
{
    zw_mb_exception exc = exception_of(reason);
    rm->last_reason = (uint_least16_t)reason;
    rm->last_exception = (uint_least16_t)exc;
    rm->refused = (rm->refused + 1u) & 0xFFFFFFFFu;
    if (out != NULL) {
        *out = reason;
    }
    return exc;
}

/* Word i of a request payload: from a word array, or from big-endian PDU bytes. */
uint_least16_t zw_rm_payload_word(const uint_least16_t *words, const uint_least8_t *bytes,
                                   size_t i)
{
    if (words != NULL) {
        return (uint_least16_t)(words[i] & 0xFFFFu);
    }
    return (uint_least16_t)((((unsigned)bytes[2u * i] & 0xFFu) << 8) |
                            ((unsigned)bytes[2u * i + 1u] & 0xFFu));
}

float zw_rm_payload_float(const uint_least16_t *words, const uint_least8_t *bytes, size_t i)
{
    uint_least16_t w[2];
    w[0] = zw_rm_payload_word(words, bytes, i);
    w[1] = zw_rm_payload_word(words, bytes, i + 1u);
    return zw_words_to_float(w);
}

uint_least16_t zw_rm_pair_word(const zw_regmap *rm, const uint_least16_t *words,
                               const uint_least8_t *bytes, size_t i)
{
    return zw_rm_payload_word(words, bytes, (rm->word_order == ZW_WORD_ORDER_CDAB) ? (i ^ 1u) : i);
}

float zw_rm_pair_float(const zw_regmap *rm, const uint_least16_t *words,
                       const uint_least8_t *bytes, size_t i)
{
    uint_least16_t w[2];
    w[0] = zw_rm_pair_word(rm, words, bytes, i);
    w[1] = zw_rm_pair_word(rm, words, bytes, i + 1u);
    return zw_words_to_float(w);
}

void zw_regmap_set_word_order(zw_regmap *rm, unsigned order)
{
    if ((rm != NULL) && ((order == ZW_WORD_ORDER_ABCD) || (order == ZW_WORD_ORDER_CDAB))) {
        rm->word_order = (uint_least16_t)order;
    }
}

/* Quantity and addresses, shared by reads and writes: the kind bits of all the words, or
 * the reason. */
static zw_reason check_range(uint_least16_t addr, uint_least16_t count, uint_least16_t max_count,
                             uint_least16_t *kinds)
{
    uint_least32_t a, end = (uint_least32_t)addr + count;
    uint_least16_t k, all = 0u;
    if ((count < 1u) || (count > max_count)) {
        return ZW_REASON_MALFORMED;
    }
    if (end > 0x10000u) {
        return ZW_REASON_UNMAPPED;
    }
    for (a = addr; a < end; ++a) {
        k = reg_kind(a);
        if (k == 0u) {
            return ZW_REASON_UNMAPPED;
        }
        all = (uint_least16_t)(all | k);
    }
    *kinds = all;
    return ZW_REASON_NONE;
}

/* One read request into words or big-endian bytes (written only when it is accepted).
 * *sampled is false, and nothing written, when the read covers a state register and no
 * consistent sample could be taken (the caller answers 0x04). */
static zw_reason read_core(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                           uint_least16_t *words, uint_least8_t *bytes, bool *sampled)
{
    uint_least16_t kinds, w[2];
    zw_reason why;
    size_t i = 0;
    state_sample st = {0.0f, 0.0f, 0.0f, 0u};
    *sampled = true;
    /* reads leave a pending UNLOCK1 armed: a client polling the map must not be able to
     * block commissioning */
    why = check_range(addr, count, ZW_MB_READ_MAX, &kinds);
    if (why != ZW_REASON_NONE) {
        return why;
    }
    /* one sample for the whole read, so that x, v, f and step belong together */
    if ((((uint_least32_t)addr + count) > ZW_REG_STATE_X) && (addr <= (ZW_REG_STATE_STEP + 1u)) &&
        !read_state(rm, &st)) {
        *sampled = false;
        return ZW_REASON_NONE;
    }
    while (i < count) {
        uint_least16_t a = (uint_least16_t)(addr + i);
        size_t first = 0, n = 1, j;
        if ((reg_kind(a) & RK_PAIR) != 0u) {
            /* both words of a value at once (a read may start or end mid-value) */
            read_pair(rm, &st, (uint_least16_t)(a & ~1u), w);
            if (rm->word_order == ZW_WORD_ORDER_CDAB) { /* low word first on the wire */
                uint_least16_t hi = w[0];
                w[0] = w[1];
                w[1] = hi;
            }
            first = a & 1u;
            if ((first == 0u) && ((i + 1u) < count)) {
                n = 2;
            }
        } else {
            w[0] = read_single(rm, a);
        }
        for (j = first; j < (first + n); ++j) {
            if (words != NULL) {
                words[i] = w[j];
            } else {
                bytes[2u * i] = (uint_least8_t)(((unsigned)w[j] >> 8) & 0xFFu);
                bytes[(2u * i) + 1u] = (uint_least8_t)((unsigned)w[j] & 0xFFu);
            }
            ++i;
        }
    }
    return ZW_REASON_NONE;
}

/* One write request, from words or from PDU bytes: addresses, then mode, then values, and
 * only then the store.  Returns the refusal reason; the caller records it. */
static zw_reason write_core(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                            const uint_least16_t *words, const uint_least8_t *bytes)
{
    uint_least16_t kinds, last;
    bool armed = rm->unlock_armed != 0u;
    zw_reason why;
    rm->unlock_armed = 0u;
    why = check_range(addr, count, ZW_MB_WRITE_MAX, &kinds);
    if (why != ZW_REASON_NONE) {
        return why;
    }
    if ((kinds & RK_RO) != 0u) {
        return ZW_REASON_READ_ONLY;
    }
    /* Pairs start at even addresses, so a write splits a value exactly when it starts on
     * an odd word or ends on an even one of an RK_PAIR range. */
    last = (uint_least16_t)(addr + count - 1u);
    if ((((reg_kind(addr) & RK_PAIR) != 0u) && ((addr & 1u) != 0u)) ||
        (((reg_kind(last) & RK_PAIR) != 0u) && ((last & 1u) == 0u))) {
        return ZW_REASON_HALF_FLOAT;
    }
    /* Past the checks above the request lies in exactly one group (the map has unmapped
     * or read-only words between groups). */
    if ((kinds & RK_MAC) != 0u) {
        if (rm->mode == 0u) {
            return ZW_REASON_LOCKED;
        }
        return zw_rm_write_mac(rm, addr, count, words, bytes);
    }
    if ((kinds & RK_BOXC) != 0u) {
        if (rm->mode == 0u) {
            return ZW_REASON_LOCKED;
        }
        return zw_rm_write_box_cert(rm, addr, count, words, bytes);
    }
    if ((kinds & RK_CERT) != 0u) {
        if (rm->mode == 0u) {
            return ZW_REASON_LOCKED;
        }
        return zw_rm_write_cert(rm, addr, count, words, bytes);
    }
    if ((kinds & RK_GAIN) != 0u) {
        float K = rm->K, B = rm->B;
        if ((rm->mode != 0u) || (rm->is_sealed == 0u)) {
            return ZW_REASON_NOT_SEALED;
        }
        if (addr == ZW_REG_K) {
            K = zw_rm_pair_float(rm, words, bytes, 0u);
        }
        if ((addr == ZW_REG_B) || (count == 4u)) {
            B = zw_rm_pair_float(rm, words, bytes, (size_t)count - 2u);
        }
        return zw_rm_apply_gains(rm, K, B); /* a tail call: this frame is gone (stack) */
    }
    return zw_rm_command(rm, zw_rm_payload_word(words, bytes, 0), armed);
}

/* ---- public API ---------------------------------------------------------------------------- */

/* Power-up state without the live registers: unsealed, gains off, counters 0, then the
 * given block through the path of a commissioned one (the same checks). */
ZW_NOINLINE static zw_reason power_up(zw_regmap *rm, const zw_cert *cert, const zw_box_cert *box_cert)
{
    unsigned i;
    zw_reason why = ZW_REASON_NONE;
    /* the floats are set explicitly rather than trusting all-zero bits to mean 0.0f */
    (void)memset(rm, 0, sizeof *rm);
    for (i = 0u; i < ZW_CERT_FIELDS; ++i) {
        zw_cert_set_field(&rm->sealed, i, 0.0f);
    }
    for (i = 0u; i < 2u; ++i) { /* both slots of each double buffer */
        zw_rm_publish_gains(rm, 0.0f, 0.0f);
        zw_regmap_set_state(rm, 0.0f, 0.0f, 0.0f, 0u);
    }
    if (cert != NULL) { /* the block and its certificate through a SEAL's checks, no MAC */
        zw_cert_encode(cert, rm->staged);
        if (box_cert != NULL) { /* verified by the admission (regmap_policy.c) */
            zw_box_cert_encode(box_cert, rm->staged_box_cert);
        }
        why = zw_rm_seal_staged(rm, false);
        for (i = 0u; i <= ZW_CERT_WORDS; ++i) {
            rm->staged[i] = 0u;
        }
        for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
            rm->staged_box_cert[i] = 0u;
        }
    }
    return why;
}

zw_status zw_regmap_init(zw_regmap *rm, const zw_cert *cert, zw_reason *reason)
{
    return zw_regmap_init_box(rm, cert, NULL, reason);
}

zw_status zw_regmap_init_box(zw_regmap *rm, const zw_cert *cert, const zw_box_cert *box_cert, zw_reason *reason)
{
    zw_reason why;
    if (rm == NULL) {
        return ZW_ERR_NULL;
    }
    why = power_up(rm, cert, box_cert);
    if (reason != NULL) {
        *reason = why;
    }
    (void)zw_rm_live_all(rm);
    if (why == ZW_REASON_NONE) {
        return ZW_OK;
    }
    /* otherwise a valid unsealed drive with the output off */
    return (why == ZW_REASON_FPENV) ? ZW_ERR_FPENV : ZW_ERR_ARG;
}

zw_status zw_regmap_active_gains(const zw_regmap *rm, float *K, float *B)
{
    unsigned tries;
    if (K != NULL) {
        *K = 0.0f; /* output off unless a consistent pair is read */
    }
    if (B != NULL) {
        *B = 0.0f;
    }
    if ((rm == NULL) || (K == NULL) || (B == NULL)) {
        return ZW_ERR_NULL;
    }
    for (tries = 0u; tries < ZW_REGMAP_READ_TRIES; ++tries) {
        uint_least32_t seq = SHARED_LOAD(rm->gains_seq);
        const zw_regmap_gain_slot *slot = &rm->gains[seq & 1u];
        float k, b;
        SHARED_ORDER();
        k = SHARED_LOAD(slot->K);
        b = SHARED_LOAD(slot->B);
        SHARED_ORDER();
        if (SHARED_LOAD(rm->gains_seq) == seq) {
            *K = k;
            *B = b;
            return ZW_OK;
        }
    }
    return ZW_ERR_BUSY;
}

/* Control loop, the only writer of the state registers. */
void zw_regmap_set_state(zw_regmap *rm, float x, float v, float f, uint_least32_t step)
{
    uint_least32_t seq;
    zw_regmap_state_slot *slot;
    if (rm == NULL) {
        return;
    }
    seq = next_seq(SHARED_LOAD(rm->state_seq));
    slot = &rm->state[seq & 1u];
    SHARED_ORDER(); /* the previous sequence word before this slot changes */
    SHARED_STORE(slot->x, x);
    SHARED_STORE(slot->v, v);
    SHARED_STORE(slot->f, f);
    SHARED_STORE(slot->step, step & 0xFFFFFFFFu);
    SHARED_ORDER(); /* the whole slot before the word that makes it current */
    SHARED_STORE(rm->state_seq, seq);
}

/* What a refused register-level read leaves in words (regmap.h): values that certify
 * nothing, 0 everywhere (K_CERT 0, gains off, unsealed, empty B interval) but the spectral
 * radius, +inf.  Only for a quantity a read may have (the caller's buffer holds count). */
static void fail_safe_words(uint_least16_t addr, uint_least16_t count, uint_least16_t *words)
{
    size_t i;
    if ((words == NULL) || (count < 1u) || (count > ZW_MB_READ_MAX)) {
        return;
    }
    for (i = 0u; i < count; ++i) {
        words[i] = (uint_least16_t)((((uint_least32_t)addr + i) == ZW_REG_LIVE_RHO) ? 0x7F80u : 0u);
    }
}

zw_mb_exception zw_regmap_read(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                               uint_least16_t *words, zw_reason *reason)
{
    zw_reason why;
    bool sampled;
    if ((rm == NULL) || (words == NULL)) {
        fail_safe_words(addr, count, words);
        return ZW_MB_SERVER_FAILURE;
    }
    why = read_core(rm, addr, count, words, NULL, &sampled);
    if ((why != ZW_REASON_NONE) || !sampled) {
        fail_safe_words(addr, count, words);
        return !sampled ? ZW_MB_SERVER_FAILURE : refuse(rm, why, reason);
    }
    if (reason != NULL) {
        *reason = ZW_REASON_NONE;
    }
    return ZW_MB_OK;
}

zw_mb_exception zw_regmap_write(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                                const uint_least16_t *words, zw_reason *reason)
{
    zw_reason why;
    if (rm == NULL) {
        return ZW_MB_SERVER_FAILURE;
    }
    if (words == NULL) {
        rm->unlock_armed = 0u;
        return ZW_MB_SERVER_FAILURE;
    }
    why = write_core(rm, addr, count, words, NULL);
    if (why != ZW_REASON_NONE) {
        return refuse(rm, why, reason);
    }
    if (reason != NULL) {
        *reason = ZW_REASON_NONE;
    }
    return zw_rm_live_all(rm);
}

static uint_least16_t be16(const uint_least8_t *p)
{
    return (uint_least16_t)((((unsigned)p[0] & 0xFFu) << 8) | ((unsigned)p[1] & 0xFFu));
}

/* Exception response fc|0x80, code. */
static zw_mb_exception answer_exception(uint_least8_t *resp, size_t *resp_len, unsigned fc,
                                        zw_mb_exception exc)
{
    resp[0] = (uint_least8_t)((fc | 0x80u) & 0xFFu);
    resp[1] = (uint_least8_t)exc;
    *resp_len = 2u;
    return exc;
}

/* A 0x10 request whose quantity, byte count and length agree. */
static bool write_multiple_well_formed(const uint_least8_t *req, size_t req_len, uint_least16_t qty)
{
    return (req_len >= 6u) && (qty >= 1u) && (qty <= ZW_MB_WRITE_MAX) &&
           (((unsigned)req[5] & 0xFFu) == (2u * (unsigned)qty)) &&
           (req_len == (6u + (2u * (size_t)qty)));
}

zw_mb_exception zw_regmap_handle_pdu(zw_regmap *rm, const uint_least8_t *req, size_t req_len,
                                     uint_least8_t *resp, size_t resp_cap, size_t *resp_len)
{
    unsigned fc;
    uint_least16_t addr = 0u, qty = 0u;
    size_t i;
    zw_reason why;
    bool sampled;
    if (rm == NULL) {
        if (resp_len != NULL) {
            *resp_len = 0u;
        }
        return ZW_MB_SERVER_FAILURE;
    }
    /* Every request but a read disarms a pending UNLOCK1, even one that cannot be
     * processed; write_core reads the flag before it clears it. */
    if ((resp_len == NULL) || (req == NULL) || (resp == NULL) || (req_len < 1u) || (resp_cap < 2u)) {
        /* no room even for an exception, or no function code to answer: not processed */
        rm->unlock_armed = 0u;
        if (resp_len != NULL) {
            *resp_len = 0u;
        }
        return ZW_MB_SERVER_FAILURE;
    }
    *resp_len = 0u;
    fc = (unsigned)req[0] & 0xFFu;
    if (req_len >= 5u) {
        addr = be16(&req[1]);
        qty = be16(&req[3]); /* the value itself for 0x06 */
    }
    if (fc == ZW_MB_READ_HOLDING) {
        if ((req_len != 5u) || (qty < 1u) || (qty > ZW_MB_READ_MAX)) {
            why = ZW_REASON_MALFORMED;
        } else if ((2u + (2u * (size_t)qty)) > resp_cap) {
            /* the answer would not fit: nothing is processed, not even counted */
            return answer_exception(resp, resp_len, fc, ZW_MB_SERVER_FAILURE);
        } else {
            why = read_core(rm, addr, qty, NULL, &resp[2], &sampled);
            if (why == ZW_REASON_NONE) {
                if (!sampled) {
                    return answer_exception(resp, resp_len, fc, ZW_MB_SERVER_FAILURE);
                }
                resp[0] = (uint_least8_t)fc;
                resp[1] = (uint_least8_t)(2u * (unsigned)qty);
                *resp_len = 2u + (2u * (size_t)qty);
                return ZW_MB_OK;
            }
        }
    } else if ((fc == ZW_MB_WRITE_SINGLE) || (fc == ZW_MB_WRITE_MULTIPLE)) {
        const bool well_formed = (fc == ZW_MB_WRITE_SINGLE) ? (req_len == 5u)
                                                            : write_multiple_well_formed(req, req_len, qty);
        if (!well_formed) {
            why = ZW_REASON_MALFORMED;
        } else if (resp_cap < 5u) {
            rm->unlock_armed = 0u;
            return answer_exception(resp, resp_len, fc, ZW_MB_SERVER_FAILURE);
        } else {
            if (fc == ZW_MB_WRITE_SINGLE) {
                why = write_core(rm, addr, 1u, NULL, &req[3]);
            } else {
                why = write_core(rm, addr, qty, NULL, &req[6]);
            }
            if (why == ZW_REASON_NONE) {
                /* 0x06 echoes the request; 0x10 answers its address and quantity: the same
                 * first 5 bytes either way */
                for (i = 0u; i < 5u; ++i) {
                    resp[i] = (uint_least8_t)((unsigned)req[i] & 0xFFu);
                }
                *resp_len = 5u;
                return zw_rm_live_all(rm);
            }
        }
    } else {
        why = ZW_REASON_BAD_FUNCTION;
    }
    if (fc != ZW_MB_READ_HOLDING) {
        rm->unlock_armed = 0u; /* a refused read leaves it armed */
    }
    return answer_exception(resp, resp_len, fc, refuse(rm, why, NULL));
}
