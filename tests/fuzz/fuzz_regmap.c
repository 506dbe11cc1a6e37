/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* fuzz_regmap.c - libFuzzer harness for zw_regmap_handle_pdu (build and run: tools/fuzz.sh).
 *
 *   clang -fsanitize=fuzzer,address,undefined -I csrc/include tests/fuzz/fuzz_regmap.c \
 *         csrc/src/(all .c) -lm
 *
 * Input: a sequence of records fed, in order, to ONE zw_regmap initialised with the paper's
 * drive block (J = 85.78e-7 kg m^2, b = 2.197e-3 N m s/rad, T = 0.02 s and a policy below):
 *   [L] [L bytes]    L = 0 .. 253: one request PDU of L bytes (fewer if the input ends)
 *   [254] [c]        the response buffer for the following requests is c bytes (0 .. 255)
 *   [255]            back to the 253-byte response buffer
 * Request and response buffers are heap blocks of exactly their size, so ASan sees any
 * access past the PDU or past resp_cap.
 *
 * After every request the invariants below are checked and a violation calls abort():
 *   - resp_len <= resp_cap; the return value is a Modbus exception code 0..4; the response
 *     is well formed: function code echoed (0x03: byte count 2 x quantity and the words the
 *     map holds; 0x06: echo of the request; 0x10: address and quantity echoed), or
 *     function | 0x80 and the returned code 1..4 (2 bytes; may be empty only if cap < 2);
 *   - a refused request changed no register but ZW_REG_LAST_REASON, ZW_REG_LAST_EXCEPTION
 *     and ZW_REG_REFUSED (which holds the old count + 1; the exception register holds the
 *     code sent, the reason is a known non-zero zw_reason, answered with the exception
 *     class regmap.h gives it: 0x01 bad function, 0x02 address failures, 0x03 value
 *     failures NOT_FINITE .. RADIUS); an accepted one left those three
 *     alone and bumped ZW_REG_ACCEPTED by at most one; exception 0x04 (the handler's own
 *     failure: empty PDU, resp_cap < 2, or a normal answer that would not fit) changed no
 *     register at all, refusal registers included (regmap.c: "not even counted");
 *   - the pair the control loop applies, read through zw_regmap_active_gains (ZW_OK), is bit
 *     for bit the K and B registers, and it is (0, 0), or the map is in operation mode with
 *     a sealed block and an independent re-check with the library's device functions on that
 *     block (read from its registers, plant and loop re-initialised with zw_device_init and
 *     zw_device_loop_init) accepts them: finite, within [k_min, k_max] x [b_min, b_max],
 *     stable and not marginal, K <= sigma K_max(B), spectral radius provably below r; for
 *     the ideal loop by zw_device_check / zw_device_k_max / zw_device_radius_within, for any
 *     other by the drive's loop: zw_device_loop_check / _k_max / _radius_within (the harness
 *     starts from a block with a delay of one sample, so the loop path is the one fuzzed;
 *     commissioning can switch to any loop);
 *   - a gain change to a pair other than (0, 0) moved K by <= dk_max and B by <= db_max;
 *   - ZW_REG_LIVE_K_CERT (the ceiling shown to tuning tools), when positive, passes the same
 *     re-check (k_max, stability, sigma, radius) with the current B;
 *   - a sealed block in operation mode has a valid CRC (computed here independently) and a
 *     valid policy; commissioning mode has the output off; magic, version, flags and the
 *     command register read as documented.
 *   - commissioning (map v3): the map consents and has hooks; the RNG hands out a counter
 *     (never 0), and the verify hook accepts exactly the MACs whose first word is 0x600D
 *     (FUZZ_MAC_OK: a rule the fuzzer can find, so both verdicts are explored; the real
 *     MAC is the hosts' business).  The hook must see an 80-byte message that starts with
 *     the map version and carries the session's nonce; NONCE and MAC read 0 in operation,
 *     the nonce is non-zero and fixed for a whole session, and a SEAL that installs a
 *     block (commissioning -> operation with another sealed block) happened only after a
 *     verify that said yes.
 * Snapshots are taken with zw_regmap_read on a copy of the map (reads are requests: on the
 * real map a refused read would bump the refusal registers).
 */
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "zwidth/regmap.h"

/* The harness's own comparisons are not coverage the fuzzer should chase (and tracing
 * them costs most of the run time): no coverage instrumentation in the checking code. */
#if defined(__clang__)
#define NO_COV __attribute__((no_sanitize("coverage")))
#else
#define NO_COV
#endif

#define CHECK(cond, ...)                                                                     \
    do {                                                                                     \
        if (!(cond)) {                                                                       \
            fprintf(stderr, "fuzz_regmap: invariant failed at line %d: %s\n  ", __LINE__,   \
                    #cond);                                                                  \
            fprintf(stderr, __VA_ARGS__);                                                    \
            fprintf(stderr, "\n");                                                           \
            abort();                                                                         \
        }                                                                                    \
    } while (0)

/* The paper's drive with a policy that makes every rule reachable: sigma and r below 1,
 * K bound above K_mmax = 0.4934, B bounds around the stable range (-b, B_mmax), and step
 * limits that need several writes to cross the region. */
static const zw_cert paper_block = {
    8.578e-6f, 2.197e-3f, 0.02f, /* m (J), b, T */
    0.9f,                        /* sigma */
    0.98f,                       /* r */
    0.0f, 0.5f,                  /* k_min, k_max */
    -2.2e-3f, 3.6e-3f,           /* b_min, b_max */
    0.1f, 1.0e-3f,               /* dk_max, db_max */
    1.0f, 0.0f, 0.0f, 0.0f       /* the loop: delay 1, no filter, backward difference */
};

/* The factory ceilings of the fuzzed map: every sealed block must stay within them. */
static const zw_ceilings fuzz_ceilings = {
    0.95f, 1.0f,                         /* sigma_max, r_max */
    8.578e-6f, 2.197e-3f, 0.02f, 0.25f,  /* nameplate m, b, T and tolerance */
    0.0f, 1.0f, -0.01f, 0.01f,           /* widest K and B bounds */
    0.5f, 5e-3f,                         /* largest steps */
    1.0f, 0.0f, 0.0f, 0.0f               /* the firmware's loop: the paper block's */
};

/* ---------------------------------------------------------------------------------------
 * Commissioning hooks (fuzz doubles)
 * ------------------------------------------------------------------------------------- */

#define FUZZ_MAC_OK 0x600Du

static uint32_t g_nonce_counter;
static int g_verify_said_yes;       /* the last verify call of this request said yes */
static uint16_t g_session_nonce[ZW_AUTH_NONCE_WORDS];

NO_COV static bool fuzz_random(void *ctx, uint_least8_t *out, size_t n)
{
    (void)ctx;
    g_nonce_counter++;
    for (size_t i = 0; i < n; i++)
        out[i] = (uint_least8_t)((i < 4 ? g_nonce_counter >> (8 * i) : 0xA5u ^ i) & 0xFFu);
    return true;
}

NO_COV static bool fuzz_verify(void *ctx, const uint_least8_t *msg, size_t msg_len,
                               const uint_least8_t *mac, size_t mac_len)
{
    (void)ctx;
    CHECK(msg_len == ZW_AUTH_MSG_BYTES && mac_len == 2 * ZW_AUTH_MAC_WORDS, "verify got %zu, %zu bytes",
          msg_len, mac_len);
    CHECK(((unsigned)msg[0] << 8 | msg[1]) == ZW_REGMAP_VERSION, "message does not start with the version");
    for (unsigned i = 0; i < ZW_AUTH_NONCE_WORDS; i++)
        CHECK(((unsigned)msg[2 + 2 * i] << 8 | msg[3 + 2 * i]) == g_session_nonce[i],
              "message nonce word %u is not the session's", i);
    g_verify_said_yes = ((unsigned)mac[0] << 8 | mac[1]) == FUZZ_MAC_OK;
    return g_verify_said_yes != 0;
}

static uint16_t crc16_modbus_words(const uint16_t *w, size_t n);

/* SAVE's storage: the image must be whole, of the documented format, with a valid CRC. */
NO_COV static bool fuzz_save(void *ctx, const uint_least8_t *image, size_t len)
{
    (void)ctx;
    CHECK(len == ZW_IMAGE_BYTES, "image of %zu bytes", len);
    uint_least16_t w[ZW_IMAGE_WORDS];
    for (unsigned i = 0; i < ZW_IMAGE_WORDS; i++) w[i] = (uint_least16_t)(image[2 * i] << 8 | image[2 * i + 1]);
    CHECK(w[0] == 0x5A57u && w[1] == 0x4E56u && w[2] == ZW_IMAGE_FORMAT, "image header");
    uint16_t w16[ZW_IMAGE_WORDS];
    for (unsigned i = 0; i < ZW_IMAGE_WORDS; i++) w16[i] = (uint16_t)w[i];
    CHECK(crc16_modbus_words(w16, ZW_IMAGE_WORDS - 1) == w16[ZW_IMAGE_WORDS - 1], "image CRC");
    return true;
}

/* ---------------------------------------------------------------------------------------
 * Register snapshots
 * ------------------------------------------------------------------------------------- */

typedef struct snapshot {
    uint16_t w[ZW_REG_COUNT];
    bool have[ZW_REG_COUNT]; /* the block holding this address could be read */
} snapshot;

static const struct { uint16_t addr, count; bool must; } blocks[] = {
    {ZW_REG_MAGIC, 10, true},   {ZW_REG_K, 4, true},          {ZW_REG_LIVE_K_MAX, 16, true},
    {ZW_REG_STATE_X, 10, true},  {ZW_REG_CERT_M, ZW_CERT_WORDS + 1, false},
    {ZW_REG_COMMAND, 1, false}, {ZW_REG_CONSENT, 4, true},
    {ZW_REG_NONCE, ZW_AUTH_NONCE_WORDS + ZW_AUTH_MAC_WORDS, true},
};

NO_COV static void take_snapshot(const zw_regmap *rm, snapshot *s)
{
    memset(s, 0, sizeof *s);
    for (size_t i = 0; i < sizeof blocks / sizeof blocks[0]; i++) {
        zw_regmap copy = *rm; /* plain data: a read on the copy leaves rm untouched */
        uint_least16_t words[ZW_AUTH_NONCE_WORDS + ZW_AUTH_MAC_WORDS + ZW_CERT_WORDS];
        zw_reason reason = ZW_REASON_NONE;
        zw_mb_exception e = zw_regmap_read(&copy, blocks[i].addr, blocks[i].count, words, &reason);
        CHECK(e == ZW_MB_OK || !blocks[i].must, "reading %u registers at 0x%04X: exception %d reason %d",
              blocks[i].count, blocks[i].addr, (int)e, (int)reason);
        if (e != ZW_MB_OK) continue;
        for (uint16_t k = 0; k < blocks[i].count; k++) {
            CHECK(words[k] <= 0xFFFFu, "register 0x%04X holds more than 16 bits",
                  blocks[i].addr + k);
            s->w[blocks[i].addr + k] = (uint16_t)words[k];
            s->have[blocks[i].addr + k] = true;
        }
    }
}

NO_COV static uint32_t u32_at(const snapshot *s, unsigned addr)
{
    return ((uint32_t)s->w[addr] << 16) | s->w[addr + 1];
}

/* Independent of zw_words_to_float: a host bit cast. */
NO_COV static float f32_at(const snapshot *s, unsigned addr)
{
    uint32_t u = u32_at(s, addr);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

NO_COV static uint16_t crc16_modbus_words(const uint16_t *w, size_t n)
{
    uint16_t crc = 0xFFFFu;
    for (size_t i = 0; i < n; i++) {
        const uint8_t bytes[2] = {(uint8_t)(w[i] >> 8), (uint8_t)(w[i] & 0xFFu)};
        for (int j = 0; j < 2; j++) {
            crc ^= bytes[j];
            for (int b = 0; b < 8; b++) crc = (crc & 1u) ? (uint16_t)((crc >> 1) ^ 0xA001u) : (uint16_t)(crc >> 1);
        }
    }
    return crc;
}

NO_COV static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* The certified block as the registers show it (operation mode: the sealed one). */
NO_COV static zw_cert block_of(const snapshot *s)
{
    zw_cert c;
    c.m = f32_at(s, ZW_REG_CERT_M);
    c.b = f32_at(s, ZW_REG_CERT_B);
    c.T = f32_at(s, ZW_REG_CERT_T);
    c.sigma = f32_at(s, ZW_REG_CERT_SIGMA);
    c.r = f32_at(s, ZW_REG_CERT_R);
    c.k_min = f32_at(s, ZW_REG_CERT_K_MIN);
    c.k_max = f32_at(s, ZW_REG_CERT_K_MAX);
    c.b_min = f32_at(s, ZW_REG_CERT_B_MIN);
    c.b_max = f32_at(s, ZW_REG_CERT_B_MAX);
    c.dk_max = f32_at(s, ZW_REG_CERT_DK_MAX);
    c.db_max = f32_at(s, ZW_REG_CERT_DB_MAX);
    c.delay = f32_at(s, ZW_REG_CERT_DELAY);
    c.vfilter = f32_at(s, ZW_REG_CERT_VFILTER);
    c.vf_param = f32_at(s, ZW_REG_CERT_VF_PARAM);
    c.differentiator = f32_at(s, ZW_REG_CERT_DIFF);
    c.m_hi = f32_at(s, ZW_REG_CERT_M_HI);
    c.b_hi = f32_at(s, ZW_REG_CERT_B_HI);
    return c;
}

/* The plant and the drive's loop of a sealed block (both re-initialised here). */
typedef struct plant {
    zw_device dev;
    zw_device_loop dl;
    bool ideal;
} plant;

/* The loop checks' scratch (loop.h); the harness runs one input at a time. */
static zw_loop_workspace g_ws;

NO_COV static bool ideal(const zw_cert *c)
{
    return c->delay == 0.0f && c->vfilter == 0.0f && c->differentiator == 0.0f;
}

NO_COV static bool pair_stable(const plant *p, float K, float B)
{
    if (p->ideal) {
        zw_verdict v;
        return zw_device_check(&p->dev, (zw_real)K, (zw_real)B, &v) == ZW_OK && v.stable && !v.marginal;
    }
    zw_loop_verdict lv;
    return zw_device_loop_check(&p->dl, &g_ws, (zw_real)K, (zw_real)B, &lv) == ZW_OK && lv.stable && !lv.marginal;
}

NO_COV static bool pair_k_max(const plant *p, float B, zw_real *kmax)
{
    return (p->ideal ? zw_device_k_max(&p->dev, (zw_real)B, kmax)
                     : zw_device_loop_k_max(&p->dl, &g_ws, (zw_real)B, kmax)) == ZW_OK;
}

NO_COV static bool pair_within(const plant *p, float K, float B, float r)
{
    bool within = false;
    zw_status st = p->ideal ? zw_device_radius_within(&p->dev, (zw_real)K, (zw_real)B, (zw_real)r, &within)
                            : zw_device_loop_radius_within(&p->dl, &g_ws, (zw_real)K, (zw_real)B, (zw_real)r, &within);
    return st == ZW_OK && within;
}

NO_COV static void check_policy(const zw_cert *c, plant *p)
{
    zw_device_loop_spec spec;
    CHECK(zw_device_init(&p->dev, (zw_real)c->m, (zw_real)c->b, (zw_real)c->T) == ZW_OK,
          "sealed plant m=%g b=%g T=%g does not initialise", (double)c->m, (double)c->b, (double)c->T);
    CHECK(c->delay >= 0.0f && c->delay <= 8.0f && c->delay == (float)(unsigned)c->delay,
          "sealed delay %g", (double)c->delay);
    CHECK(c->vfilter == 0.0f || c->vfilter == 1.0f || c->vfilter == 2.0f, "sealed filter %g", (double)c->vfilter);
    CHECK(c->differentiator == 0.0f || c->differentiator == 1.0f, "sealed differentiator %g",
          (double)c->differentiator);
    memset(&spec, 0, sizeof spec);
    spec.delay = (unsigned)c->delay;
    spec.differentiator = c->differentiator == 1.0f ? ZW_DIFF_TUSTIN : ZW_DIFF_BACKWARD;
    spec.filter = c->vfilter == 1.0f ? ZW_VFILTER_LOWPASS : c->vfilter == 2.0f ? ZW_VFILTER_AVERAGE : ZW_VFILTER_NONE;
    if (spec.filter == ZW_VFILTER_LOWPASS) spec.cutoff_hz = (zw_real)c->vf_param;
    if (spec.filter == ZW_VFILTER_AVERAGE) spec.average = (unsigned)c->vf_param;
    CHECK(zw_device_loop_init(&p->dl, (zw_real)c->m, (zw_real)c->b, (zw_real)c->T, &spec) == ZW_OK,
          "sealed loop (delay %g, filter %g %g, differentiator %g) does not initialise", (double)c->delay,
          (double)c->vfilter, (double)c->vf_param, (double)c->differentiator);
    p->ideal = ideal(c);
    CHECK(c->sigma > 0.0f && c->sigma <= 1.0f, "sealed sigma %g", (double)c->sigma);
    CHECK(c->r > 0.0f && c->r <= 1.0f, "sealed r %g", (double)c->r);
    CHECK(isfinite(c->k_min) && isfinite(c->k_max) && c->k_min <= c->k_max,
          "sealed K bounds [%g, %g]", (double)c->k_min, (double)c->k_max);
    CHECK(isfinite(c->b_min) && isfinite(c->b_max) && c->b_min <= c->b_max,
          "sealed B bounds [%g, %g]", (double)c->b_min, (double)c->b_max);
    CHECK(c->dk_max > 0.0f && c->db_max > 0.0f, "sealed step limits %g %g", (double)c->dk_max,
          (double)c->db_max);
}

/* The re-check of an active pair other than (0, 0), against the sealed block. */
NO_COV static void check_pair(const zw_cert *c, const plant *p, float K, float B)
{
    CHECK(isfinite(K) && isfinite(B), "active gains not finite: K=%a B=%a", (double)K, (double)B);
    CHECK(c->k_min <= K && K <= c->k_max, "K=%.9g outside [%.9g, %.9g]", (double)K,
          (double)c->k_min, (double)c->k_max);
    CHECK(c->b_min <= B && B <= c->b_max, "B=%.9g outside [%.9g, %.9g]", (double)B,
          (double)c->b_min, (double)c->b_max);
    CHECK(pair_stable(p, K, B), "active pair K=%.9g B=%.9g not provably stable (ideal loop %d)",
          (double)K, (double)B, (int)p->ideal);
    zw_real kmax = 0;
    CHECK(pair_k_max(p, B, &kmax), "K_max failed");
    CHECK((zw_real)K <= (zw_real)c->sigma * kmax, "K=%.9g above sigma K_max(B) = %.9g x %.9g",
          (double)K, (double)c->sigma, (double)kmax);
    CHECK(pair_within(p, K, B, c->r), "active pair K=%.9g B=%.9g: spectral radius not provably below r=%.9g",
          (double)K, (double)B, (double)c->r);
}

/* ZW_REG_LIVE_K_CERT is shown to tuning tools as the certified ceiling at the current B:
 * when positive, that K with the current B must itself pass the rules that do not depend
 * on the previous gains (k_max, stability, sigma, radius). */
NO_COV static void check_k_cert(const zw_cert *c, const plant *p, float kc, float B)
{
    if (!(kc > 0.0f)) {
        CHECK(kc == 0.0f, "LIVE_K_CERT = %a in operation with a sealed block", (double)kc);
        return;
    }
    CHECK(kc <= c->k_max, "LIVE_K_CERT %.9g above k_max %.9g", (double)kc, (double)c->k_max);
    CHECK(pair_stable(p, kc, B), "LIVE_K_CERT %.9g at B=%.9g is not provably stable", (double)kc, (double)B);
    zw_real kmax = 0;
    CHECK(pair_k_max(p, B, &kmax) && (zw_real)kc <= (zw_real)c->sigma * kmax,
          "LIVE_K_CERT %.9g above sigma K_max(B) = %.9g x %.9g", (double)kc, (double)c->sigma, (double)kmax);
    CHECK(pair_within(p, kc, B, c->r), "LIVE_K_CERT %.9g at B=%.9g: radius not provably below r=%.9g",
          (double)kc, (double)B, (double)c->r);
}

NO_COV static bool is_refusal_register(unsigned a)
{
    return a == ZW_REG_LAST_REASON || a == ZW_REG_LAST_EXCEPTION || a == ZW_REG_REFUSED ||
           a == ZW_REG_REFUSED + 1u;
}

/* ---------------------------------------------------------------------------------------
 * One request and its invariants
 * ------------------------------------------------------------------------------------- */

NO_COV static void check_response(const uint_least8_t *req, size_t n, const uint_least8_t *resp,
                           size_t resp_len, size_t cap, zw_mb_exception ret, const snapshot *after)
{
    CHECK(resp_len <= cap, "resp_len %zu > cap %zu", resp_len, cap);
    CHECK(resp_len <= 253u, "resp_len %zu > 253", resp_len);
    CHECK((int)ret >= 0 && (int)ret <= 4, "return value %d is not an exception code", (int)ret);
    for (size_t i = 0; i < resp_len; i++) CHECK(resp[i] <= 0xFFu, "response byte %zu > 0xFF", i);

    if (n == 0) {
        CHECK(ret != ZW_MB_OK, "an empty request was accepted");
        CHECK(resp_len == 0 || (resp_len == 2 && (resp[0] & 0x80u) && resp[1] == (unsigned)ret),
              "empty request: malformed exception response (len %zu)", resp_len);
        return;
    }
    if (ret != ZW_MB_OK) {
        CHECK(resp_len == 2 || (resp_len == 0 && cap < 2), "exception response length %zu (cap %zu)",
              resp_len, cap);
        if (resp_len == 2) {
            CHECK(resp[0] == (req[0] | 0x80u), "exception response function 0x%02X for request 0x%02X",
                  (unsigned)resp[0], (unsigned)req[0]);
            CHECK(resp[1] == (unsigned)ret, "exception byte %u but returned %d", (unsigned)resp[1], (int)ret);
        }
        return;
    }
    CHECK(resp_len >= 1 && resp[0] == req[0], "normal response does not echo function 0x%02X",
          (unsigned)req[0]);
    switch (req[0]) {
    case 0x03: {
        CHECK(n >= 5, "read accepted from a %zu-byte PDU", n);
        unsigned addr = (unsigned)(req[1] << 8 | req[2]), qty = (unsigned)(req[3] << 8 | req[4]);
        CHECK(qty >= 1 && qty <= 125, "read of %u registers accepted", qty);
        CHECK(resp_len == 2u + 2u * qty && resp[1] == 2u * qty, "read response length %zu, byte count %u for %u registers",
              resp_len, (unsigned)resp[1], qty);
        CHECK(addr + qty <= ZW_REG_COUNT, "read of 0x%04X+%u accepted beyond the map", addr, qty);
        for (unsigned k = 0; k < qty; k++) {
            unsigned a = addr + k;
            if (!after->have[a]) continue;
            unsigned w = (unsigned)(resp[2 + 2 * k] << 8 | resp[3 + 2 * k]);
            CHECK(w == after->w[a], "read returned 0x%04X at 0x%04X, zw_regmap_read 0x%04X", w, a,
                  after->w[a]);
        }
        break;
    }
    case 0x06:
        CHECK(n == 5 && resp_len == 5 && memcmp(resp, req, 5) == 0, "write-single response is not an echo");
        break;
    case 0x10:
        CHECK(n >= 6 && resp_len == 5 && memcmp(resp + 1, req + 1, 4) == 0,
              "write-multiple response does not echo address and quantity");
        break;
    default:
        CHECK(false, "function 0x%02X accepted", (unsigned)req[0]);
    }
}

/* The pair the control loop applies: through the control loop's reader only. */
typedef struct active_pair {
    zw_status st;
    float K, B;
} active_pair;

NO_COV static active_pair read_active(const zw_regmap *rm)
{
    active_pair a;
    a.K = a.B = 1234.0f;
    a.st = zw_regmap_active_gains(rm, &a.K, &a.B);
    return a;
}

/* The block in force the last time the map was seen in operation, sealed. */
static uint16_t g_sealed_words[ZW_CERT_WORDS + 1];

NO_COV static void check_state(const snapshot *before, const snapshot *after, zw_mb_exception ret,
                               bool first, active_pair active)
{
    const snapshot *s = after;
    CHECK(s->w[ZW_REG_MAGIC] == ZW_REGMAP_MAGIC && s->w[ZW_REG_VERSION] == ZW_REGMAP_VERSION,
          "magic 0x%04X version %u", s->w[ZW_REG_MAGIC], s->w[ZW_REG_VERSION]);
    CHECK(s->w[ZW_REG_MODE] <= 1 && s->w[ZW_REG_SEALED] <= 1, "mode %u sealed %u",
          s->w[ZW_REG_MODE], s->w[ZW_REG_SEALED]);
    CHECK(s->w[ZW_REG_LAST_REASON] <= ZW_REASON_LOOP_MISMATCH && s->w[ZW_REG_LAST_EXCEPTION] <= 4,
          "last reason %u exception %u", s->w[ZW_REG_LAST_REASON], s->w[ZW_REG_LAST_EXCEPTION]);
    CHECK(!s->have[ZW_REG_COMMAND] || s->w[ZW_REG_COMMAND] == 0, "command register reads 0x%04X",
          s->w[ZW_REG_COMMAND]);

    /* Commissioning session: consent on; nonce and MAC 0 outside a session; a session's
     * nonce is non-zero and does not change; a new block is installed only after a yes. */
    CHECK(s->w[ZW_REG_CONSENT] == 1, "consent reads %u", s->w[ZW_REG_CONSENT]);
    bool nonce_zero = true;
    for (unsigned i = 0; i < ZW_AUTH_NONCE_WORDS + ZW_AUTH_MAC_WORDS; i++) {
        if (s->w[ZW_REG_MODE] == 0)
            CHECK(s->w[ZW_REG_NONCE + i] == 0, "nonce/MAC word 0x%04X reads 0x%04X in operation",
                  ZW_REG_NONCE + i, s->w[ZW_REG_NONCE + i]);
        if (i < ZW_AUTH_NONCE_WORDS && s->w[ZW_REG_NONCE + i] != 0) nonce_zero = false;
    }
    if (s->w[ZW_REG_MODE] == 1) {
        CHECK(!nonce_zero, "commissioning without a nonce");
        if (before->w[ZW_REG_MODE] == 1)
            CHECK(memcmp(&before->w[ZW_REG_NONCE], &s->w[ZW_REG_NONCE], 2 * ZW_AUTH_NONCE_WORDS) == 0,
                  "the nonce changed within a session");
    }
    if (!first && before->w[ZW_REG_MODE] == 1 && s->w[ZW_REG_MODE] == 0 && s->w[ZW_REG_SEALED] == 1 &&
        memcmp(&g_sealed_words[0], &s->w[ZW_REG_CERT_M], sizeof g_sealed_words) != 0)
        CHECK(g_verify_said_yes, "a block was installed without a MAC the verify hook accepted");
    if (s->w[ZW_REG_MODE] == 0 && s->w[ZW_REG_SEALED] == 1)
        memcpy(g_sealed_words, &s->w[ZW_REG_CERT_M], sizeof g_sealed_words);
    for (unsigned i = 0; i < ZW_AUTH_NONCE_WORDS; i++) g_session_nonce[i] = s->w[ZW_REG_NONCE + i];

    /* Refused: nothing moved but the refusal registers. */
    for (unsigned a = 0; a < ZW_REG_COUNT; a++) {
        if (!before->have[a] || !after->have[a]) continue;
        if (ret != ZW_MB_OK && !is_refusal_register(a))
            CHECK(before->w[a] == after->w[a], "refused request (exception %d, reason %u) changed register 0x%04X: 0x%04X -> 0x%04X",
                  (int)ret, after->w[ZW_REG_LAST_REASON], a, before->w[a], after->w[a]);
        if (ret == ZW_MB_OK && is_refusal_register(a))
            CHECK(before->w[a] == after->w[a], "accepted request changed refusal register 0x%04X", a);
    }
    uint32_t acc0 = u32_at(before, ZW_REG_ACCEPTED), acc1 = u32_at(after, ZW_REG_ACCEPTED);
    if (ret == ZW_MB_SERVER_FAILURE) {
        for (unsigned a = 0; a < ZW_REG_COUNT; a++)
            CHECK(!before->have[a] || !after->have[a] || before->w[a] == after->w[a],
                  "exception 0x04 (not processed) changed register 0x%04X", a);
    } else if (ret != ZW_MB_OK) {
        CHECK(u32_at(after, ZW_REG_REFUSED) == u32_at(before, ZW_REG_REFUSED) + 1u,
              "refused counter %u -> %u", (unsigned)u32_at(before, ZW_REG_REFUSED),
              (unsigned)u32_at(after, ZW_REG_REFUSED));
        CHECK(after->w[ZW_REG_LAST_EXCEPTION] == (unsigned)ret, "last exception %u, sent %d",
              after->w[ZW_REG_LAST_EXCEPTION], (int)ret);
        unsigned why = after->w[ZW_REG_LAST_REASON];
        CHECK(why != ZW_REASON_NONE, "refused with reason NONE");
        /* The classes regmap.h documents (the others it leaves open). */
        if (why == ZW_REASON_BAD_FUNCTION)
            CHECK(ret == ZW_MB_ILLEGAL_FUNCTION, "BAD_FUNCTION answered %d", (int)ret);
        if (why == ZW_REASON_UNMAPPED || why == ZW_REASON_READ_ONLY || why == ZW_REASON_HALF_FLOAT ||
            why == ZW_REASON_LOCKED)
            CHECK(ret == ZW_MB_ILLEGAL_ADDRESS, "address failure %u answered %d", why, (int)ret);
        if (why >= ZW_REASON_NOT_FINITE && why <= ZW_REASON_RADIUS)
            CHECK(ret == ZW_MB_ILLEGAL_VALUE, "value failure %u answered %d", why, (int)ret);
    } else {
        CHECK(acc1 == acc0 || acc1 == acc0 + 1u, "accepted counter %u -> %u", (unsigned)acc0,
              (unsigned)acc1);
    }

    /* Gains: the control loop's pair is the registers' pair, and it is what is checked. */
    CHECK(active.st == ZW_OK, "zw_regmap_active_gains: status %d", (int)active.st);
    CHECK(same_bits(active.K, f32_at(after, ZW_REG_K)) && same_bits(active.B, f32_at(after, ZW_REG_B)),
          "control loop reads K=%a B=%a, registers hold K=%a B=%a", (double)active.K,
          (double)active.B, (double)f32_at(after, ZW_REG_K), (double)f32_at(after, ZW_REG_B));
    float K = active.K, B = active.B;
    float K0 = f32_at(before, ZW_REG_K), B0 = f32_at(before, ZW_REG_B);
    bool off = (K == 0.0f && B == 0.0f);
    bool operation = after->w[ZW_REG_MODE] == 0;
    bool sealed = after->w[ZW_REG_SEALED] == 1;
    if (!operation) CHECK(off, "commissioning mode with gains K=%g B=%g", (double)K, (double)B);
    if (operation && sealed) {
        CHECK(after->have[ZW_REG_CERT_M] && after->have[ZW_REG_CERT_CRC],
              "sealed block not readable in operation mode");
        uint16_t words[ZW_CERT_WORDS];
        uint_least16_t lw[ZW_CERT_WORDS];
        for (unsigned i = 0; i < ZW_CERT_WORDS; i++) {
            words[i] = after->w[ZW_REG_CERT_M + i];
            lw[i] = words[i];
        }
        uint16_t crc = crc16_modbus_words(words, ZW_CERT_WORDS);
        CHECK(crc == after->w[ZW_REG_CERT_CRC], "sealed block CRC register 0x%04X, computed 0x%04X",
              after->w[ZW_REG_CERT_CRC], crc);
        CHECK(zw_crc16_words(lw, ZW_CERT_WORDS) == crc, "zw_crc16_words disagrees with CRC-16/MODBUS");
        zw_cert c = block_of(after);
        const zw_ceilings *k = &fuzz_ceilings;
        CHECK(c.sigma <= k->sigma_max && c.r <= k->r_max && c.k_min >= k->k_min && c.k_max <= k->k_max &&
              c.b_min >= k->b_min && c.b_max <= k->b_max && c.dk_max <= k->dk_max && c.db_max <= k->db_max,
              "sealed block beyond the factory ceilings");
        CHECK(fabs((double)c.m - (double)k->m) <= (double)k->plant_tol * (double)k->m &&
              fabs((double)c.b - (double)k->b) <= (double)k->plant_tol * (double)k->b &&
              fabs((double)c.T - (double)k->T) <= (double)k->plant_tol * (double)k->T,
              "sealed plant outside the nameplate tolerance");
        CHECK(c.delay == k->delay && c.vfilter == k->vfilter && c.vf_param == k->vf_param &&
                  c.differentiator == k->differentiator,
              "sealed block for a loop the firmware does not run");
        for (unsigned f = 0; f < ZW_CERT_FIELDS; f++)
            CHECK(!(zw_cert_field(&c, f) != 0.0f && fabsf(zw_cert_field(&c, f)) < FLT_MIN),
                  "sealed field %u is subnormal", f);
        /* map v4: a ranged block (M_HI = B_HI = 0 is the point shorthand) has ordered ends,
         * each within the nameplate's tolerance, and r = 1; its pairs are certified for the
         * whole box, so they must pass the point rules at each corner (checked below) */
        const bool ranged = !(c.m_hi == 0.0f && c.b_hi == 0.0f) && (c.m_hi != c.m || c.b_hi != c.b);
        if (ranged) {
            CHECK(c.m_hi >= c.m && c.b_hi >= c.b && c.r == 1.0f, "sealed ranged block m [%g, %g] b [%g, %g] r %g",
                  (double)c.m, (double)c.m_hi, (double)c.b, (double)c.b_hi, (double)c.r);
            CHECK(fabs((double)c.m_hi - (double)k->m) <= (double)k->plant_tol * (double)k->m &&
                  fabs((double)c.b_hi - (double)k->b) <= (double)k->plant_tol * (double)k->b,
                  "sealed range ends outside the nameplate tolerance");
        }
        static plant pl; /* large (the loop); the harness is single-threaded */
        const bool check_kc = first || u32_at(before, ZW_REG_LIVE_K_CERT) != u32_at(after, ZW_REG_LIVE_K_CERT) ||
            u32_at(before, ZW_REG_B) != u32_at(after, ZW_REG_B) || before->w[ZW_REG_MODE] != 0;
        for (unsigned corner = 1; ranged && corner < 4; corner++) {
            zw_cert cc = c;
            cc.m = (corner & 1u) ? c.m_hi : c.m;
            cc.b = (corner & 2u) ? c.b_hi : c.b;
            check_policy(&cc, &pl);
            if (check_kc) check_k_cert(&cc, &pl, f32_at(after, ZW_REG_LIVE_K_CERT), B);
            if (!off) check_pair(&cc, &pl, K, B);
        }
        check_policy(&c, &pl);
        if (check_kc)
            check_k_cert(&c, &pl, f32_at(after, ZW_REG_LIVE_K_CERT), B);
        if (!off) {
            check_pair(&c, &pl, K, B);
            if (!same_bits(K, K0) || !same_bits(B, B0)) {
                CHECK(fabs((double)K - (double)K0) <= (double)c.dk_max,
                      "K moved %.9g -> %.9g, dk_max %.9g", (double)K0, (double)K, (double)c.dk_max);
                CHECK(fabs((double)B - (double)B0) <= (double)c.db_max,
                      "B moved %.9g -> %.9g, db_max %.9g", (double)B0, (double)B, (double)c.db_max);
            }
        }
    } else {
        CHECK(off, "gains K=%g B=%g without a sealed block in operation mode", (double)K, (double)B);
    }
}

/* Requests checked over the whole run, printed at exit for the summary of tools/fuzz.sh. */
static unsigned long long g_requests = 0;

#if defined(__clang__) || defined(__GNUC__)
__attribute__((destructor)) static void report_requests(void)
{
    fprintf(stderr, "fuzz_regmap: %llu requests checked\n", g_requests);
}
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    zw_regmap rm;
    zw_reason why = ZW_REASON_NONE;
    CHECK(zw_regmap_init(&rm, &paper_block, &why) == ZW_OK, "the paper's block is refused (reason %d)", (int)why);
    const zw_regmap_auth hooks = {fuzz_random, fuzz_verify, NULL};
    CHECK(zw_regmap_set_ceilings(&rm, &fuzz_ceilings, &why) == ZW_OK, "ceilings refused (reason %d)", (int)why);
    zw_regmap_set_auth(&rm, &hooks);
    zw_regmap_set_consent(&rm, true);
    const zw_regmap_storage storage = {fuzz_save, NULL};
    zw_regmap_set_storage(&rm, &storage);
    g_nonce_counter = 0;
    memset(g_sealed_words, 0, sizeof g_sealed_words);

    snapshot before, after;
    take_snapshot(&rm, &before);
    check_state(&before, &before, ZW_MB_OK, true, read_active(&rm));
    CHECK(before.w[ZW_REG_SEALED] == 1 && before.w[ZW_REG_MODE] == 0, "fresh map not sealed in operation");

    size_t cap = 253, pos = 0;
    while (pos < size) {
        unsigned len = data[pos++];
        if (len == 254) {
            if (pos < size) cap = data[pos++];
            continue;
        }
        if (len == 255) {
            cap = 253;
            continue;
        }
        size_t n = (size - pos < len) ? size - pos : len;
        uint_least8_t *req = malloc(n ? n : 1);
        uint_least8_t *resp = malloc(cap ? cap : 1);
        if (!req || !resp) abort();
        for (size_t i = 0; i < n; i++) req[i] = data[pos + i];
        pos += n;

        size_t resp_len = (size_t)-1;
        g_verify_said_yes = 0;
        zw_mb_exception ret = zw_regmap_handle_pdu(&rm, req, n, resp, cap, &resp_len);
        g_requests++;
        take_snapshot(&rm, &after);
        check_response(req, n, resp, resp_len, cap, ret, &after);
        check_state(&before, &after, ret, false, read_active(&rm));
        before = after;
        free(req);
        free(resp);
    }
    return 0;
}
