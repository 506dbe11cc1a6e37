/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The drive-side register map (zwidth/regmap.h): every register and its access rights, every
 * refusal path with its exception code and reason, atomicity (after any refusal every
 * register but the three refusal registers reads back as before, and the struct itself is
 * unchanged), the certification rules on the paper's drive, the CRC seal and the
 * commissioning sequence, the float word order, malformed PDUs, a too-small response
 * buffer and NULL arguments.
 *
 * Independent references: the float words are compared with a host bit cast (memcpy), the
 * CRC with a bytewise CRC-16/MODBUS written here and its published check values, the paper
 * numbers with the printed digits.  The live registers are compared with the zw_device_*
 * functions they are documented to report. */
#include "zw_test.h"

#include <fenv.h>

#include "zwidth/regmap.h"

/* The checks' scratch (loop.h): static, as a drive keeps it; tests run one at a time. */
static zw_loop_workspace g_ws;

/* ---- the paper's drive (Section V-B, load motor short-circuited), T = 20 ms -------------- */

#define J1 85.78e-7f    /* kg m^2 */
#define B_SHORT 2.197e-3f /* N m s/rad */
#define T_20MS 0.02f

/* A permissive policy: every rule but stability is out of the way unless a test tightens it. */
static zw_cert paper_cert(void)
{
    zw_cert c;
    c.m = J1;
    c.b = B_SHORT;
    c.T = T_20MS;
    c.sigma = 1.0f;
    c.r = 1.0f;
    c.k_min = 0.0f;
    c.k_max = 10.0f;
    c.b_min = -0.01f;
    c.b_max = 0.01f;
    c.dk_max = 1.0f;
    c.db_max = 0.01f;
    c.delay = 0.0f; /* the ideal loop */
    c.vfilter = 0.0f;
    c.vf_param = 0.0f;
    c.differentiator = 0.0f;
    c.m_hi = 0.0f; /* the point block's shorthand (map version 4) */
    c.b_hi = 0.0f;
    return c;
}

static zw_device paper_device(void)
{
    zw_device d;
    memset(&d, 0, sizeof d);
    EXPECT_OK(zw_device_init(&d, (zw_real)J1, (zw_real)B_SHORT, (zw_real)T_20MS));
    return d;
}

/* ---- the firmware's commissioning hooks, as a test double ---------------------------------
 * The map has no crypto: it hands a message to the firmware's verify hook.  The double's
 * "MAC" is a keyed FNV-1a per output byte (no security, only a function of key and message
 * that these tests compute independently of the map); its RNG is a counter, so every
 * nonce differs.  strict 0 (most tests, which test other things): any MAC verifies. */
typedef struct test_auth {
    unsigned char key[8];
    uint32_t counter;
    int strict, rng_fails;
    unsigned calls;                            /* verify calls */
    unsigned char last_msg[ZW_AUTH_MSG_BYTES]; /* what verify saw last */
    size_t last_msg_len, last_mac_len;
} test_auth;

static void test_mac(const unsigned char key[8], const unsigned char *msg, size_t n,
                     unsigned char mac[2u * ZW_AUTH_MAC_WORDS])
{
    size_t j, i;
    for (j = 0; j < 2u * ZW_AUTH_MAC_WORDS; ++j) {
        uint32_t h = 2166136261u ^ (uint32_t)j;
        for (i = 0; i < 8u; ++i) h = (h ^ key[i]) * 16777619u;
        for (i = 0; i < n; ++i) h = (h ^ msg[i]) * 16777619u;
        mac[j] = (unsigned char)(h >> 24);
    }
}

static bool test_random(void *ctx, uint_least8_t *out, size_t n)
{
    test_auth *a = ctx;
    size_t i;
    if (a->rng_fails) return false;
    a->counter++;
    for (i = 0; i < n; ++i) out[i] = (uint_least8_t)((a->counter * 2654435761u) >> (8u * (i % 4u)) ^ i);
    return true;
}

static bool test_verify(void *ctx, const uint_least8_t *msg, size_t msg_len, const uint_least8_t *mac,
                        size_t mac_len)
{
    test_auth *a = ctx;
    unsigned char m[ZW_AUTH_MSG_BYTES], want[2u * ZW_AUTH_MAC_WORDS];
    size_t i;
    a->calls++;
    a->last_msg_len = msg_len;
    a->last_mac_len = mac_len;
    if (msg_len != ZW_AUTH_MSG_BYTES || mac_len != sizeof want) return false;
    for (i = 0; i < msg_len; ++i) m[i] = (unsigned char)msg[i];
    memcpy(a->last_msg, m, sizeof m);
    if (!a->strict) return true;
    test_mac(a->key, m, sizeof m, want);
    for (i = 0; i < sizeof want; ++i)
        if ((unsigned char)mac[i] != want[i]) return false;
    return true;
}

/* One double for every map of this file (tests run one at a time); reset by rm_init. */
static test_auth g_auth;

/* Factory ceilings that let every block of these tests through (tests of the ceilings set
 * their own): no margin required, any plant, any bounds. */
static zw_ceilings permissive_ceilings(void)
{
    zw_ceilings k;
    memset(&k, 0, sizeof k); /* the ideal loop */
    k.sigma_max = 1.0f;
    k.r_max = 1.0f;
    k.m = J1;
    k.b = B_SHORT;
    k.T = T_20MS;
    k.plant_tol = 1e30f;
    k.k_min = -FLT_MAX;
    k.k_max = FLT_MAX;
    k.b_min = -FLT_MAX;
    k.b_max = FLT_MAX;
    k.dk_max = FLT_MAX;
    k.db_max = FLT_MAX;
    return k;
}

/* Consent on, the double's hooks and permissive ceilings: commissioning possible
 * (power-up leaves it off). */
static void allow_commissioning(zw_regmap *rm)
{
    zw_ceilings k = permissive_ceilings();
    zw_regmap_auth hooks;
    if (rm->is_sealed != 0u) { /* the firmware runs its power-up block's loop */
        k.delay = rm->sealed.delay;
        k.vfilter = rm->sealed.vfilter;
        k.vf_param = rm->sealed.vf_param;
        k.differentiator = rm->sealed.differentiator;
    }
    EXPECT_OK(zw_regmap_set_ceilings(rm, &k, NULL));
    hooks.random = test_random;
    hooks.verify = test_verify;
    hooks.ctx = &g_auth;
    zw_regmap_set_auth(rm, &hooks);
    zw_regmap_set_consent(rm, true);
}

/* A map sealed with c (the struct is filled with garbage first: init must set everything),
 * commissioning allowed with the trusting double. */
static void rm_init(zw_regmap *rm, const zw_cert *c)
{
    zw_reason why = ZW_REASON_CRC;
    memset(rm, 0xA5, sizeof *rm);
    (void)zw_regmap_init(rm, c, &why);
    assert_string_equal(zw_reason_name(why), "ZW_REASON_NONE");
    memset(&g_auth, 0, sizeof g_auth);
    allow_commissioning(rm);
}

/* ---- small helpers ------------------------------------------------------------------------ */

static void words_of(float f, uint_least16_t w[2])
{
    uint32_t u = zwt_bits_of(f);
    w[0] = (uint_least16_t)(u >> 16);
    w[1] = (uint_least16_t)(u & 0xFFFFu);
}

static uint_least16_t rd(zw_regmap *rm, uint_least16_t addr)
{
    uint_least16_t w = 0xDEADu;
    zw_reason why = ZW_REASON_CRC;
    assert_int_equal(zw_regmap_read(rm, addr, 1, &w, &why), ZW_MB_OK);
    assert_int_equal(why, ZW_REASON_NONE);
    return w;
}

static uint32_t rd32(zw_regmap *rm, uint_least16_t addr)
{
    uint_least16_t w[2] = {0xDEADu, 0xBEEFu};
    assert_int_equal(zw_regmap_read(rm, addr, 2, w, NULL), ZW_MB_OK);
    return ((uint32_t)w[0] << 16) | (uint32_t)w[1];
}

/* A float register, through a host bit cast (independent of zw_words_to_float). */
static float rdf(zw_regmap *rm, uint_least16_t addr)
{
    return zwt_float_of(rd32(rm, addr));
}

typedef struct outcome {
    zw_mb_exception exc;
    zw_reason why;
} outcome;

static outcome write_words(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                           const uint_least16_t *words)
{
    outcome o;
    o.why = (zw_reason)999;
    o.exc = zw_regmap_write(rm, addr, count, words, &o.why);
    return o;
}

static outcome read_words(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                          uint_least16_t *words)
{
    outcome o;
    o.why = (zw_reason)999;
    o.exc = zw_regmap_read(rm, addr, count, words, &o.why);
    return o;
}

static outcome write_pair(zw_regmap *rm, float K, float B)
{
    uint_least16_t w[4];
    words_of(K, w);
    words_of(B, w + 2);
    return write_words(rm, ZW_REG_K, 4, w);
}

static outcome write_K(zw_regmap *rm, float K)
{
    uint_least16_t w[2];
    words_of(K, w);
    return write_words(rm, ZW_REG_K, 2, w);
}

static outcome write_B(zw_regmap *rm, float B)
{
    uint_least16_t w[2];
    words_of(B, w);
    return write_words(rm, ZW_REG_B, 2, w);
}

static outcome command(zw_regmap *rm, uint_least16_t cmd)
{
    return write_words(rm, ZW_REG_COMMAND, 1, &cmd);
}

static void expect_outcome(outcome o, zw_mb_exception exc, zw_reason why, const char *expr,
                           const char *file, int line)
{
    if (o.exc != exc || o.why != why) {
        print_error("%s:%d: %s gave exception %d, %s; expected %d, %s\n", file, line, expr,
                    (int)o.exc, zw_reason_name(o.why), (int)exc, zw_reason_name(why));
        _fail(file, line);
    }
}
#define EXPECT_OUTCOME(call, exc, why)                                                           \
    expect_outcome((call), (exc), (why), #call, __FILE__, __LINE__)
#define EXPECT_ACCEPTED(call) EXPECT_OUTCOME(call, ZW_MB_OK, ZW_REASON_NONE)

/* ---- snapshots: every mapped register, read through the map ------------------------------- */

/* The mapped ranges, as regmap.h lists them (test_access_map checks that they are exactly
 * the mapped addresses). */
static const struct {
    uint_least16_t first, last;
} k_mapped[] = {
    {0x00, 0x09}, {0x10, 0x13}, {0x20, 0x39}, {0x40, 0x62}, {0x64, 0x64}, {0x80, 0x84},
    {0x88, 0x9F}, {0x100, 0x243},
};

static bool is_mapped(unsigned addr)
{
    size_t i;
    for (i = 0; i < ZWT_ARRAY_LEN(k_mapped); ++i)
        if (addr >= k_mapped[i].first && addr <= k_mapped[i].last) return true;
    return false;
}

typedef struct snap {
    uint_least16_t w[ZW_REG_COUNT];
} snap;

/* Read on a copy, so that taking a snapshot cannot change the map under test. */
static snap snapshot(const zw_regmap *rm)
{
    snap s;
    size_t i;
    zw_regmap copy = *rm;
    memset(&s, 0, sizeof s);
    for (i = 0; i < ZWT_ARRAY_LEN(k_mapped); ++i) {
        unsigned a;
        for (a = k_mapped[i].first; a <= k_mapped[i].last; a += 125u) { /* FC 0x03's limit */
            unsigned n = k_mapped[i].last - a + 1u;
            n = n < 125u ? n : 125u;
            assert_int_equal(zw_regmap_read(&copy, (uint_least16_t)a, (uint_least16_t)n, &s.w[a], NULL),
                             ZW_MB_OK);
        }
    }
    return s;
}

static bool is_refusal_register(unsigned a)
{
    return a == ZW_REG_LAST_REASON || a == ZW_REG_LAST_EXCEPTION || a == ZW_REG_REFUSED ||
           a == ZW_REG_REFUSED + 1u;
}

static void expect_same_registers(const snap *before, const snap *after, bool refusal_too,
                                  const char *file, int line)
{
    unsigned a;
    for (a = 0; a < ZW_REG_COUNT; ++a) {
        if (!refusal_too && is_refusal_register(a)) continue;
        if (before->w[a] != after->w[a]) {
            print_error("%s:%d: register 0x%04X changed from 0x%04X to 0x%04X\n", file, line, a,
                        (unsigned)before->w[a], (unsigned)after->w[a]);
            _fail(file, line);
        }
    }
}

static uint32_t snap32(const snap *s, unsigned a)
{
    return ((uint32_t)s->w[a] << 16) | (uint32_t)s->w[a + 1u];
}

/* A refused request: the outcome, then that only the refusal registers changed (REFUSED by
 * exactly one), and that the struct itself holds the same data but for those fields. */
static void check_refused(zw_regmap *rm, const snap *before, const zw_regmap *struct_before,
                          outcome o, zw_mb_exception exc, zw_reason why, const char *expr,
                          const char *file, int line)
{
    snap after;
    zw_regmap expect;
    expect_outcome(o, exc, why, expr, file, line);
    expect = *struct_before;
    expect.last_reason = (uint_least16_t)why;
    expect.last_exception = (uint_least16_t)exc;
    expect.refused = (struct_before->refused + 1u) & 0xFFFFFFFFu;
    expect.unlock_armed = rm->unlock_armed;
    expect.ws = rm->ws; /* the loop checks' scratch: no state, any contents */
    memcpy(expect.box_cells, rm->box_cells, sizeof expect.box_cells); /* the box search's too */
    expect.box_scratch = rm->box_scratch;
    memcpy(expect.wire_scratch, rm->wire_scratch, sizeof expect.wire_scratch); /* SEAL's, SAVE's */
    expect.box_cert_candidate = rm->box_cert_candidate; /* SEAL's decoded certificate */
    if (memcmp(&expect, rm, sizeof expect) != 0) {
        print_error("%s:%d: %s changed the map beyond the refusal registers\n", file, line, expr);
        _fail(file, line);
    }
    after = snapshot(rm);
    expect_same_registers(before, &after, false, file, line);
    if (snap32(&after, ZW_REG_REFUSED) != ((snap32(before, ZW_REG_REFUSED) + 1u) & 0xFFFFFFFFu) ||
        after.w[ZW_REG_LAST_REASON] != (uint_least16_t)why ||
        after.w[ZW_REG_LAST_EXCEPTION] != (uint_least16_t)exc) {
        print_error("%s:%d: %s: refusal registers %u, 0x%02X, %lu (before %lu)\n", file, line, expr,
                    (unsigned)after.w[ZW_REG_LAST_REASON], (unsigned)after.w[ZW_REG_LAST_EXCEPTION],
                    (unsigned long)snap32(&after, ZW_REG_REFUSED),
                    (unsigned long)snap32(before, ZW_REG_REFUSED));
        _fail(file, line);
    }
}

#define EXPECT_REFUSED(rm, call, exc, why)                                                       \
    do {                                                                                         \
        snap before_ = snapshot(rm);                                                             \
        zw_regmap struct_before_ = *(rm);                                                        \
        outcome o_ = (call);                                                                     \
        check_refused((rm), &before_, &struct_before_, o_, (exc), (why), #call, __FILE__,        \
                      __LINE__);                                                                 \
    } while (0)

/* ---- independent CRC-16/MODBUS ------------------------------------------------------------ */

static uint16_t ref_crc_bytes(const unsigned char *p, size_t n)
{
    uint16_t crc = 0xFFFFu;
    size_t i;
    int k;
    for (i = 0; i < n; ++i) {
        crc = (uint16_t)(crc ^ p[i]);
        for (k = 0; k < 8; ++k)
            crc = (crc & 1u) ? (uint16_t)((crc >> 1) ^ 0xA001u) : (uint16_t)(crc >> 1);
    }
    return crc;
}

static uint16_t ref_crc_words(const uint_least16_t *w, size_t n)
{
    unsigned char bytes[2 * 400];
    size_t i;
    assert_true(n <= 400);
    for (i = 0; i < n; ++i) {
        bytes[2 * i] = (unsigned char)(w[i] >> 8);
        bytes[2 * i + 1] = (unsigned char)(w[i] & 0xFFu);
    }
    return ref_crc_bytes(bytes, 2 * n);
}

/* The 34 block words of c (host bit casts) and their CRC. */
static void block_words(const zw_cert *c, uint_least16_t w[ZW_CERT_WORDS + 1u])
{
    const float f[17] = {c->m,     c->b,     c->T,      c->sigma,  c->r,
                         c->k_min, c->k_max, c->b_min,  c->b_max,  c->dk_max,
                         c->db_max, c->delay, c->vfilter, c->vf_param, c->differentiator,
                         c->m_hi, c->b_hi};
    size_t i;
    for (i = 0; i < 17; ++i) words_of(f[i], &w[2 * i]);
    w[ZW_CERT_WORDS] = ref_crc_words(w, ZW_CERT_WORDS);
}

/* ---- floats over two registers --------------------------------------------------------- */

static void check_pattern(uint32_t u)
{
    uint_least16_t w[2], back[2] = {0xDEADu, 0xBEEFu};
    float f;
    bool nan_pattern = (u & 0x7F800000u) == 0x7F800000u && (u & 0x7FFFFFu) != 0u;
    w[0] = (uint_least16_t)(u >> 16);
    w[1] = (uint_least16_t)(u & 0xFFFFu);
    f = zw_words_to_float(w);
    zw_float_to_words(f, back);
    if (nan_pattern) {
        if (!(f != f) || back[0] != 0x7FC0u || back[1] != 0u) {
            print_error("pattern 0x%08lX: NaN expected, back 0x%04X%04X\n", (unsigned long)u,
                        (unsigned)back[0], (unsigned)back[1]);
            fail();
        }
    } else if (zwt_bits_of(f) != u || back[0] != w[0] || back[1] != w[1]) {
        print_error("pattern 0x%08lX: decoded 0x%08lX, encoded back 0x%04X%04X\n",
                    (unsigned long)u, (unsigned long)zwt_bits_of(f), (unsigned)back[0],
                    (unsigned)back[1]);
        fail();
    }
}

/* Known encodings, high word first (1.0f is 0x3F80 0x0000). */
static void test_float_words_known(void **state)
{
    static const struct {
        float f;
        uint_least16_t hi, lo;
    } k[] = {
        {1.0f, 0x3F80u, 0x0000u},       {-2.0f, 0xC000u, 0x0000u},   {0.0f, 0x0000u, 0x0000u},
        {0.1f, 0x3DCCu, 0xCCCDu},       {-2.5f, 0xC020u, 0x0000u},   {85.78e-7f, 0x370Fu, 0xEA3Bu},
        {FLT_MAX, 0x7F7Fu, 0xFFFFu},    {FLT_MIN, 0x0080u, 0x0000u}, {-FLT_MAX, 0xFF7Fu, 0xFFFFu},
        {FLT_MIN * FLT_EPSILON, 0x0000u, 0x0001u}, /* smallest subnormal 2^-149 */
    };
    size_t i;
    uint_least16_t w[2];
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(k); ++i) {
        zw_float_to_words(k[i].f, w);
        assert_int_equal(w[0], k[i].hi);
        assert_int_equal(w[1], k[i].lo);
        assert_true(zwt_bits_of(zw_words_to_float(w)) == zwt_bits_of(k[i].f));
    }
    zw_float_to_words(-0.0f, w);
    assert_int_equal(w[0], 0x8000u);
    assert_int_equal(w[1], 0u);
    zw_float_to_words((float)INFINITY, w);
    assert_int_equal(w[0], 0x7F80u);
    assert_int_equal(w[1], 0u);
    zw_float_to_words(-(float)INFINITY, w);
    assert_int_equal(w[0], 0xFF80u);
    assert_int_equal(w[1], 0u);
    /* every NaN, whatever its sign or payload, becomes the one quiet NaN */
    zw_float_to_words((float)NAN, w);
    assert_int_equal(w[0], 0x7FC0u);
    assert_int_equal(w[1], 0u);
    zw_float_to_words(zwt_float_of(0xFFC12345u), w);
    assert_int_equal(w[0], 0x7FC0u);
    assert_int_equal(w[1], 0u);
    zw_float_to_words(zwt_float_of(0x7F800001u), w); /* signalling pattern */
    assert_int_equal(w[0], 0x7FC0u);
    assert_int_equal(w[1], 0u);
    /* words wider than 16 bits are masked */
    {
        const uint_least16_t one[2] = {0x3F80u, 0x0000u};
        assert_true(zw_words_to_float(one) == 1.0f);
    }
}

/* Round trip of every exponent with edge and sample significands, both signs, and a
 * strided sweep of the whole 32-bit space, against a host bit cast. */
static void test_float_words_round_trip(void **state)
{
    uint32_t e, s, u, i;
    static const uint32_t mant[] = {0u,        1u,        2u,        3u,        0x7FFFFFu,
                                    0x7FFFFEu, 0x400000u, 0x3FFFFFu, 0x400001u, 0x123456u,
                                    0x654321u, 0x0F0F0Fu, 0x555555u, 0x2AAAAAu};
    (void)state;
    for (s = 0; s < 2; ++s)
        for (e = 0; e < 256; ++e)
            for (i = 0; i < ZWT_ARRAY_LEN(mant); ++i)
                check_pattern((s << 31) | (e << 23) | mant[i]);
    /* 4099 is prime: the stride visits every exponent and a spread of significands */
    for (u = 0; u < 0xFFFFFFFFu - 4099u; u += 4099u) check_pattern(u);
    check_pattern(0xFFFFFFFFu);
}

/* ---- CRC ------------------------------------------------------------------------------------ */

static void test_crc(void **state)
{
    static const unsigned char check[] = "123456789";
    static const unsigned char eight[] = "12345678";
    /* "12345678" packed two bytes a word, high byte first */
    static const uint_least16_t eight_w[4] = {0x3132u, 0x3334u, 0x3536u, 0x3738u};
    /* the classic Modbus RTU request 01 03 00 00 00 0A, sent with CRC bytes C5 CD */
    static const uint_least16_t rtu_w[3] = {0x0103u, 0x0000u, 0x000Au};
    uint_least16_t block[ZW_CERT_WORDS + 1u];
    zw_cert c = paper_cert();
    (void)state;
    /* the reference itself against the catalogue check value of CRC-16/MODBUS */
    assert_int_equal(ref_crc_bytes(check, 9), 0x4B37u);
    assert_int_equal(zw_crc16_words(eight_w, 4), ref_crc_bytes(eight, 8));
    assert_int_equal(zw_crc16_words(eight_w, 4), 0x37DDu);
    assert_int_equal(zw_crc16_words(rtu_w, 3), 0xCDC5u);
    block_words(&c, block);
    assert_int_equal(zw_crc16_words(block, ZW_CERT_WORDS), block[ZW_CERT_WORDS]);
    assert_int_equal(zw_crc16_words(block, 0), 0xFFFFu);
    assert_int_equal(zw_crc16_words(NULL, 5), 0xFFFFu);
}

/* ---- init ------------------------------------------------------------------------------------ */

static void test_init_sealed(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t block[ZW_CERT_WORDS + 1u];
    unsigned i;
    (void)state;
    rm_init(&rm, &c);
    assert_int_equal(rd(&rm, ZW_REG_MAGIC), 0x5A57u);
    assert_int_equal(rd(&rm, ZW_REG_VERSION), 5u);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    assert_int_equal(rd(&rm, ZW_REG_LAST_REASON), 0u);
    assert_int_equal(rd(&rm, ZW_REG_LAST_EXCEPTION), 0u);
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 0u);
    assert_int_equal(rd32(&rm, ZW_REG_REFUSED), 0u);
    assert_true(zwt_bits_of(rdf(&rm, ZW_REG_K)) == 0u);
    assert_true(zwt_bits_of(rdf(&rm, ZW_REG_B)) == 0u);
    for (i = ZW_REG_STATE_X; i <= ZW_REG_STATE_STEP + 1u; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)i), 0u);
    assert_int_equal(rd(&rm, ZW_REG_COMMAND), 0u);
    /* the sealed block and its CRC read back word for word */
    block_words(&c, block);
    for (i = 0; i <= ZW_CERT_WORDS; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)(ZW_REG_CERT_M + i)), block[i]);
    /* reason may be NULL */
    EXPECT_OK(zw_regmap_init(&rm, &c, NULL));
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
}

static void test_init_unsealed(void **state)
{
    zw_regmap rm;
    zw_reason why = ZW_REASON_CRC;
    unsigned i;
    (void)state;
    memset(&rm, 0xA5, sizeof rm);
    EXPECT_OK(zw_regmap_init(&rm, NULL, &why));
    assert_int_equal(why, ZW_REASON_NONE);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    /* no block: all zero, CRC included; no plant: live registers NaN */
    for (i = ZW_REG_CERT_M; i <= ZW_REG_CERT_CRC; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)i), 0u);
    for (i = ZW_REG_LIVE_K_MAX; i <= ZW_REG_LIVE_DELTA; i += 2u)
        assert_int_equal(rd32(&rm, (uint_least16_t)i), 0x7FC00000u);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.1f, 0.0f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.0f, 0.0f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
    EXPECT_STATUS(zw_regmap_init(NULL, NULL, &why), ZW_ERR_NULL);
}

/* Every BAD_POLICY rule at power-up; the drive comes up unsealed and usable. */
static void test_init_bad_policy(void **state)
{
    int n;
    (void)state;
    for (n = 0; n < 23; ++n) {
        zw_cert c = paper_cert();
        zw_regmap rm;
        zw_reason why = ZW_REASON_NONE;
        switch (n) {
        case 0: c.sigma = 0.0f; break;
        case 1: c.sigma = 1.0000001f; break;
        case 2: c.r = 0.0f; break;
        case 3: c.r = 1.5f; break;
        case 4: c.sigma = -0.5f; break;
        case 5: c.k_min = 1.0f; c.k_max = 0.5f; break;
        case 6: c.b_min = 0.01f; c.b_max = -0.01f; break;
        case 7: c.dk_max = 0.0f; break;
        case 8: c.db_max = -1.0f; break;
        case 9: c.m = 0.0f; break;
        case 10: c.T = 0.0f; break;
        case 11: c.b = -1e-3f; break;
        case 12: c.m = (float)NAN; break;
        case 13: c.k_max = (float)INFINITY; break;
        case 14: c.b_min = -(float)INFINITY; break;
        case 15: c.dk_max = (float)INFINITY; break;
        case 16: c.r = (float)NAN; break;
        case 17: c.T = -0.02f; break;
        case 18: c.b = (float)INFINITY; break;
        /* no pair reachable in one step from the output-off state (review finding F2) */
        case 19: c.k_min = 0.3f; c.dk_max = 0.1f; break;
        case 20: c.b_min = -2e-3f; c.b_max = -1e-3f; c.db_max = 5e-4f; break;
        case 21: c.b_min = 1e-3f; c.b_max = 2e-3f; c.db_max = 5e-4f; break;
        default: c.sigma = (float)NAN; break;
        }
        memset(&rm, 0xA5, sizeof rm);
        EXPECT_TRUE_MSG(zw_regmap_init(&rm, &c, &why) == ZW_ERR_ARG, "case %d", n);
        allow_commissioning(&rm);
        EXPECT_TRUE_MSG(why == ZW_REASON_BAD_POLICY, "case %d: %s", n, zw_reason_name(why));
        assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
        assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
        assert_int_equal(rd(&rm, ZW_REG_CERT_M), 0u);
        assert_int_equal(rd32(&rm, ZW_REG_LIVE_K_MMAX), 0x7FC00000u);
        EXPECT_OUTCOME(write_K(&rm, 0.1f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
        /* and it can be commissioned */
        EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
        EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK2));
        assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    }
}

/* ---- the map ----------------------------------------------------------------------------- */

/* Reads: exactly the documented addresses are mapped; reads may start or end mid-value. */
static void test_access_map_reads(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    unsigned a;
    uint_least16_t w[4] = {0u, 0u, 0u, 0u};
    zw_reason why;
    (void)state;
    rm_init(&rm, &c);
    for (a = 0; a < 0x100u; ++a) {
        uint_least16_t before = 0x1234u;
        why = (zw_reason)999;
        w[0] = before;
        if (is_mapped(a)) {
            EXPECT_TRUE_MSG(zw_regmap_read(&rm, (uint_least16_t)a, 1, w, &why) == ZW_MB_OK,
                            "read 0x%04X", a);
            assert_int_equal(why, ZW_REASON_NONE);
        } else {
            EXPECT_REFUSED(&rm, read_words(&rm, (uint_least16_t)a, 1, w),
                           ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
            (void)before;
            assert_int_equal(w[0], 0u); /* fail-safe words on refusal (regmap.h) */
        }
    }
    /* a range touching one unmapped word is refused as a whole */
    EXPECT_REFUSED(&rm, read_words(&rm, 0x08, 3, w), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_UNMAPPED);
    EXPECT_REFUSED(&rm, read_words(&rm, 0x62, 2, w), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_UNMAPPED);
    /* past the end of the address space */
    EXPECT_REFUSED(&rm, read_words(&rm, 0xFFFF, 1, w),
                   ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
    EXPECT_REFUSED(&rm, read_words(&rm, 0xFFFF, 2, w),
                   ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
    /* quantity */
    EXPECT_REFUSED(&rm, read_words(&rm, 0, 0, w), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_MALFORMED);
    EXPECT_REFUSED(&rm, read_words(&rm, 0, 126, w),
                   ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    /* mid-value reads: the low word of K alone, and the high word of B with the low of K */
    EXPECT_ACCEPTED(write_pair(&rm, 0.1f, 1e-3f));
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_K + 1, 2, w, NULL), ZW_MB_OK);
    assert_int_equal(w[0], (uint_least16_t)(zwt_bits_of(0.1f) & 0xFFFFu));
    assert_int_equal(w[1], (uint_least16_t)(zwt_bits_of(1e-3f) >> 16));
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_K, 4, w, NULL), ZW_MB_OK);
    assert_true((((uint32_t)w[0] << 16) | w[1]) == zwt_bits_of(0.1f));
    assert_true((((uint32_t)w[2] << 16) | w[3]) == zwt_bits_of(1e-3f));
    /* a full read of 125 registers at the end of the map is unmapped, not malformed */
    {
        uint_least16_t big[125];
        EXPECT_REFUSED(&rm, read_words(&rm, 0, 125, big),
                       ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
    }
}

/* Writes: the access right of every mapped address. */
static void test_access_map_writes(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    unsigned a;
    uint_least16_t w[2] = {0u, 0u};
    (void)state;
    rm_init(&rm, &c);
    for (a = 0; a < ZW_REG_COUNT + 8u; ++a) {
        uint_least16_t addr = (uint_least16_t)a;
        if (!is_mapped(a)) {
            EXPECT_REFUSED(&rm, write_words(&rm, addr, 1, w), ZW_MB_ILLEGAL_ADDRESS,
                           ZW_REASON_UNMAPPED);
        } else if (a >= ZW_REG_BOX_CERT_B && a < ZW_REG_BOX_CERT_NODES) {
            /* the certificate's floats: as the block's */
            EXPECT_REFUSED(&rm, write_words(&rm, addr, 1, w), ZW_MB_ILLEGAL_ADDRESS,
                           ZW_REASON_HALF_FLOAT);
            if ((a & 1u) == 0u)
                EXPECT_REFUSED(&rm, write_words(&rm, addr, 2, w), ZW_MB_ILLEGAL_ADDRESS,
                               ZW_REASON_LOCKED);
        } else if (a <= 0x09u || (a >= 0x20u && a <= 0x39u) ||
                   (a >= ZW_REG_CONSENT && a <= ZW_REG_PRECISION) ||
                   (a >= ZW_REG_NONCE && a < ZW_REG_MAC)) {
            /* read-only, whether one word or a whole (aligned) value is written */
            EXPECT_REFUSED(&rm, write_words(&rm, addr, 1, w), ZW_MB_ILLEGAL_ADDRESS,
                           ZW_REASON_READ_ONLY);
            if ((a & 1u) == 0u && a >= 0x06u && a <= 0x39u)
                EXPECT_REFUSED(&rm, write_words(&rm, addr, 2, w), ZW_MB_ILLEGAL_ADDRESS,
                               ZW_REASON_READ_ONLY);
        } else if (a >= 0x10u && a <= 0x13u) {
            EXPECT_REFUSED(&rm, write_words(&rm, addr, 1, w), ZW_MB_ILLEGAL_ADDRESS,
                           ZW_REASON_HALF_FLOAT);
        } else if (a >= 0x40u && a <= 0x61u) {
            /* the block: a single word is half a float; a whole float is locked */
            EXPECT_REFUSED(&rm, write_words(&rm, addr, 1, w), ZW_MB_ILLEGAL_ADDRESS,
                           ZW_REASON_HALF_FLOAT);
            if ((a & 1u) == 0u)
                EXPECT_REFUSED(&rm, write_words(&rm, addr, 2, w), ZW_MB_ILLEGAL_ADDRESS,
                               ZW_REASON_LOCKED);
        } else if (a == ZW_REG_CERT_CRC || a >= ZW_REG_MAC) {
            EXPECT_REFUSED(&rm, write_words(&rm, addr, 1, w), ZW_MB_ILLEGAL_ADDRESS,
                           ZW_REASON_LOCKED);
        } else {
            assert_int_equal(a, ZW_REG_COMMAND);
            EXPECT_REFUSED(&rm, write_words(&rm, addr, 1, w), ZW_MB_ILLEGAL_VALUE,
                           ZW_REASON_BAD_COMMAND);
        }
    }
    /* the whole-request order: unmapped before read-only before half a float before mode */
    {
        uint_least16_t z[16];
        memset(z, 0, sizeof z);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x0E, 4, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_UNMAPPED);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x08, 2, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_READ_ONLY);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x11, 2, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_HALF_FLOAT);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x10, 3, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_HALF_FLOAT);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x41, 2, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_HALF_FLOAT);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x60, 3, z), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_LOCKED);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x61, 2, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_HALF_FLOAT);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x62, 2, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_UNMAPPED);
        EXPECT_REFUSED(&rm, write_words(&rm, 0xFFFF, 2, z), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_UNMAPPED);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x10, 0, z), ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
        EXPECT_REFUSED(&rm, write_words(&rm, 0x10, 124, z), ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_MALFORMED);
    }
}

/* ---- gains -------------------------------------------------------------------------------- */

/* The issue's motivating case: K then B through an unstable intermediate is refused at the
 * intermediate; the same pair in one request is accepted. */
static void test_pair_atomicity(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    zw_device d = paper_device();
    zw_verdict v;
    (void)state;
    rm_init(&rm, &c);
    EXPECT_ACCEPTED(write_pair(&rm, 0.1f, 0.0f));
    /* (0.4, 0) is beyond K_max(0) = 0.3577; (0.4, -1.36e-3) is inside (K_max = 0.4928) */
    EXPECT_OK(zw_device_check(&d, R(0.4f), R(0.0f), &v));
    assert_false(v.stable);
    EXPECT_OK(zw_device_check(&d, R(0.4f), R(-1.36e-3f), &v));
    assert_true(v.stable);
    EXPECT_REFUSED(&rm, write_K(&rm, 0.4f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
    assert_true(rdf(&rm, ZW_REG_K) == 0.1f);
    assert_true(rdf(&rm, ZW_REG_B) == 0.0f);
    EXPECT_ACCEPTED(write_pair(&rm, 0.4f, -1.36e-3f));
    assert_true(rdf(&rm, ZW_REG_K) == 0.4f);
    assert_true(rdf(&rm, ZW_REG_B) == -1.36e-3f);
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 2u);
    /* and back: B alone first would leave (0.4, 0), unstable; the pair is fine */
    EXPECT_REFUSED(&rm, write_B(&rm, 0.0f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
    EXPECT_ACCEPTED(write_pair(&rm, 0.1f, 0.0f));
    /* K alone is judged with the current B, B alone with the current K */
    EXPECT_ACCEPTED(write_B(&rm, -1.36e-3f));
    EXPECT_ACCEPTED(write_K(&rm, 0.4f));
    assert_true(rdf(&rm, ZW_REG_K) == 0.4f);
    assert_true(rdf(&rm, ZW_REG_B) == -1.36e-3f);
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 5u);
    assert_int_equal(rd32(&rm, ZW_REG_REFUSED), 2u);
}

/* Each rule with its reason, in the documented order. */
static void test_rules_and_order(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    (void)state;
    c.k_min = 0.05f;
    c.k_max = 0.45f;
    c.b_min = -2e-3f;
    c.b_max = 2e-3f;
    c.dk_max = 0.2f;
    c.db_max = 1e-3f;
    rm_init(&rm, &c);
    EXPECT_ACCEPTED(write_pair(&rm, 0.1f, 0.0f));
    /* NaN and infinities, in either gain, before anything else */
    EXPECT_REFUSED(&rm, write_pair(&rm, (float)NAN, 0.0f), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_NOT_FINITE);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.1f, (float)NAN), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_NOT_FINITE);
    EXPECT_REFUSED(&rm, write_pair(&rm, (float)INFINITY, 0.0f), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_NOT_FINITE);
    EXPECT_REFUSED(&rm, write_B(&rm, -(float)INFINITY), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NOT_FINITE);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.0f, (float)NAN), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_NOT_FINITE);
    {
        /* a signalling-NaN pattern on the wire */
        uint_least16_t w[2] = {0x7F80u, 0x0001u};
        EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_K, 2, w), ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_NOT_FINITE);
    }
    EXPECT_REFUSED(&rm, write_pair(&rm, (float)NAN, 1.0f), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_NOT_FINITE);
    /* bounds, K before B */
    EXPECT_REFUSED(&rm, write_K(&rm, 0.04f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_BELOW_MIN);
    EXPECT_REFUSED(&rm, write_K(&rm, -0.1f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_BELOW_MIN);
    EXPECT_REFUSED(&rm, write_K(&rm, 0.46f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_ABOVE_MAX);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.46f, -1.0f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_ABOVE_MAX);
    EXPECT_REFUSED(&rm, write_B(&rm, -2.1e-3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_B_BELOW_MIN);
    EXPECT_REFUSED(&rm, write_B(&rm, 2.1e-3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_B_ABOVE_MAX);
    /* bounds are inclusive */
    EXPECT_ACCEPTED(write_K(&rm, 0.05f));
    /* steps, K before B, both against the active pair */
    EXPECT_REFUSED(&rm, write_K(&rm, 0.3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_STEP);
    EXPECT_REFUSED(&rm, write_B(&rm, 1.5e-3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_B_STEP);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.3f, 1.5e-3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_STEP);
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, -0.9e-3f));
    EXPECT_ACCEPTED(write_pair(&rm, 0.35f, -1.36e-3f));
    /* unstable: beyond K_max(B) = 0.2577 at B = 1e-3 (within bounds and steps) */
    EXPECT_ACCEPTED(write_pair(&rm, 0.25f, -0.5e-3f));
    EXPECT_ACCEPTED(write_B(&rm, 0.4e-3f));
    EXPECT_REFUSED(&rm, write_B(&rm, 1.2e-3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 6u);
}

/* The paper's numbers: K_mmax = 0.4934 at B = -1.357e-3.  With sigma = 0.85 the ceiling at
 * B = -1.36e-3 is 0.85 K_max(B) = 0.4188: K = 0.40 is accepted, K = 0.45 refused
 * ABOVE_SIGMA although stable.  (With sigma = 0.8 the ceiling is 0.3942, below 0.40.) */
static void test_sigma_rule(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    zw_device d = paper_device();
    zw_verdict v;
    zw_real kmax;
    (void)state;
    EXPECT_OK(zw_device_k_max(&d, R(-1.36e-3f), &kmax));
    EXPECT_NEAR(kmax, 0.4928, 5e-4, 0);
    c.sigma = 0.85f;
    rm_init(&rm, &c);
    EXPECT_NEAR(rdf(&rm, ZW_REG_LIVE_K_MMAX), 0.4934, 1e-4, 0);
    EXPECT_NEAR(rdf(&rm, ZW_REG_LIVE_B_AT_KMMAX), -1.357e-3, 1e-6, 0);
    EXPECT_ACCEPTED(write_pair(&rm, 0.40f, -1.36e-3f));
    EXPECT_OK(zw_device_check(&d, R(0.45f), R(-1.36e-3f), &v));
    assert_true(v.stable);
    EXPECT_REFUSED(&rm, write_K(&rm, 0.45f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_ABOVE_SIGMA);
    /* unstable wins over sigma: (0.50, -1.36e-3) is past K_max */
    EXPECT_REFUSED(&rm, write_K(&rm, 0.50f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
    /* K_CERT is the largest float not above sigma K_max(B), and it is accepted */
    {
        /* the rule as documented, K <= sigma K_max(B), evaluated as the drive does */
        float kc = rdf(&rm, ZW_REG_LIVE_K_CERT);
        zw_real top = (zw_real)0.85f * kmax;
        assert_true((zw_real)kc <= top);
        assert_true((zw_real)nextafterf(kc, 1.0f) > top);
        EXPECT_ACCEPTED(write_K(&rm, kc));
        EXPECT_REFUSED(&rm, write_K(&rm, nextafterf(kc, 1.0f)), ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_ABOVE_SIGMA);
    }
    /* sigma = 0.8: 0.40 is above 0.8 K_max(-1.36e-3) = 0.3942 */
    c.sigma = 0.8f;
    rm_init(&rm, &c);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.40f, -1.36e-3f), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_ABOVE_SIGMA);
    EXPECT_ACCEPTED(write_pair(&rm, 0.39f, -1.36e-3f));
}

/* r = 0.9 on the paper's drive at B = -1.36e-3: rho(0.2) = 0.872, rho(0.3) = 0.908. */
static void test_radius_rule(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    zw_device d = paper_device();
    zw_real rho;
    float kc;
    (void)state;
    c.r = 0.9f;
    rm_init(&rm, &c);
    EXPECT_OK(zw_device_spectral_radius(&d, R(0.3f), R(-1.36e-3f), &rho));
    assert_true(rho > R(0.9) && rho < R(1.0));
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, -1.36e-3f));
    EXPECT_REFUSED(&rm, write_K(&rm, 0.3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_RADIUS);
    /* K_CERT: the radius bites below K_max; the value shown is accepted, the next float not */
    kc = rdf(&rm, ZW_REG_LIVE_K_CERT);
    assert_true(kc > 0.2f && kc < 0.3f);
    EXPECT_OK(zw_device_spectral_radius(&d, (zw_real)kc, R(-1.36e-3f), &rho));
    EXPECT_NEAR(rho, 0.9, 1e-4, 0);
    EXPECT_ACCEPTED(write_K(&rm, kc));
    EXPECT_REFUSED(&rm, write_K(&rm, nextafterf(kc, 1.0f)), ZW_MB_ILLEGAL_VALUE, ZW_REASON_RADIUS);
    EXPECT_NEAR(rdf(&rm, ZW_REG_LIVE_RHO), 0.9, 1e-4, 0);
    /* at B = 0 with r = 0.5: rho(0.0625) = 0.336, rho(0.2) = 0.590 */
    c.r = 0.5f;
    rm_init(&rm, &c);
    kc = rdf(&rm, ZW_REG_LIVE_K_CERT);
    assert_true(kc > 0.0625f && kc < 0.2f);
    EXPECT_ACCEPTED(write_K(&rm, kc));
    EXPECT_REFUSED(&rm, write_K(&rm, nextafterf(kc, 1.0f)), ZW_MB_ILLEGAL_VALUE, ZW_REASON_RADIUS);
    /* r below every radius reachable at B = 0 (rho -> 1 as K -> 0, and grows past its
     * minimum): K_CERT reads 0 and every non-zero K is refused */
    {
        zw_real k_max0, rho_min = R(1.0);
        int i;
        EXPECT_OK(zw_device_k_max(&d, R(0.0), &k_max0));
        for (i = 1; i < 1000; ++i) {
            EXPECT_OK(zw_device_spectral_radius(&d, k_max0 * (zw_real)i / R(1000.0), R(0.0), &rho));
            if (rho < rho_min) rho_min = rho;
        }
        /* ... and below every radius of the whole bounds box (a grid over K in (0, 0.6],
         * B in [-0.01, 0.01]: the smallest stable radius there is about 0.2): no pair but
         * (0, 0) could ever be accepted, so the block is refused (review A4) */
        c.r = (float)(R(0.5) * rho_min);
        {
            zw_real grid_min = R(1.0);
            zw_reason why = ZW_REASON_NONE;
            int j;
            zw_verdict v;
            for (i = 1; i <= 60; ++i)
                for (j = -40; j <= 40; ++j) {
                    zw_real K = R(0.01) * (zw_real)i, B = R(0.00025) * (zw_real)j;
                    if (zw_device_check(&d, K, B, &v) != ZW_OK || !v.stable) continue;
                    EXPECT_OK(zw_device_spectral_radius(&d, K, B, &rho));
                    if (rho < grid_min) grid_min = rho;
                }
            assert_true(grid_min > (zw_real)c.r * R(1.2));
            assert_int_equal(zw_regmap_init(&rm, &c, &why), ZW_ERR_ARG);
            assert_int_equal(why, ZW_REASON_ONLY_OFF);
            assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
        }
    }
}

/* ACCEPTED/REFUSED bookkeeping and the output-off pair. */
static void test_output_off_and_counters(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    (void)state;
    c.k_min = 0.1f;
    c.dk_max = 0.11f; /* usable: 0.1 .. 0.11 is one step from off */
    rm_init(&rm, &c);
    /* (0, 0) is always accepted: below k_min, whatever the step */
    EXPECT_ACCEPTED(write_pair(&rm, 0.0f, 0.0f));
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 1u);
    /* from off, the step limit applies to the first non-zero pair */
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.12f, 0.0f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_STEP);
    c.dk_max = 0.2f;
    rm_init(&rm, &c);
    EXPECT_ACCEPTED(write_pair(&rm, 0.12f, 0.0f));
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, 0.0f));
    /* back to off in one write, although that step (0.3) is beyond dk_max (-0.0 is 0) */
    EXPECT_ACCEPTED(write_pair(&rm, -0.0f, -0.0f));
    /* stored as +0.0 (review A2: an HMI comparing the words with 0 sees "off") */
    assert_int_equal(rd32(&rm, ZW_REG_K), 0u);
    assert_int_equal(rd32(&rm, ZW_REG_B), 0u);
    /* the same values again count as accepted */
    EXPECT_ACCEPTED(write_pair(&rm, 0.12f, 0.0f));
    EXPECT_ACCEPTED(write_pair(&rm, 0.12f, 0.0f));
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 5u);
    /* a command or a refused write does not count */
    EXPECT_REFUSED(&rm, write_K(&rm, 0.05f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_BELOW_MIN);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 5u);
    assert_int_equal(rd32(&rm, ZW_REG_REFUSED), 1u);
    /* both counters wrap at 2^32 */
    rm.accepted = 0xFFFFFFFFu;
    rm.refused = 0xFFFFFFFFu;
    EXPECT_ACCEPTED(write_K(&rm, 0.12f));
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 0u);
    (void)write_K(&rm, (float)NAN);
    assert_int_equal(rd32(&rm, ZW_REG_REFUSED), 0u);
    rm.accepted = 0x00012345u;
    assert_int_equal(rd(&rm, ZW_REG_ACCEPTED), 0x0001u);
    assert_int_equal(rd(&rm, ZW_REG_ACCEPTED + 1), 0x2345u);
}

/* dk_max = 0.25 exactly: a step of exactly 0.25 is accepted, one of 0.25 + 2^-28 (which
 * rounds to 0.25 in float arithmetic) is refused, in both directions. */
static void test_step_limit_exact(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    const float B = -1.357e-3f;
    const float just_below = 0.0625f - 0x1p-28f; /* 2^-4 - 2^-28, a float */
    (void)state;
    c.dk_max = 0.25f;
    rm_init(&rm, &c);
    assert_true((long double)0.3125f - (long double)just_below > 0.25L);
    EXPECT_ACCEPTED(write_pair(&rm, just_below, B));
    EXPECT_REFUSED(&rm, write_K(&rm, 0.3125f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_STEP);
    EXPECT_ACCEPTED(write_K(&rm, 0.0625f));
    EXPECT_ACCEPTED(write_K(&rm, 0.3125f));
    EXPECT_REFUSED(&rm, write_K(&rm, just_below), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_STEP);
    EXPECT_ACCEPTED(write_K(&rm, 0.0625f));
    /* B likewise: a step of exactly db_max = 2^-10 is accepted, 2^-10 + 2^-30 is not */
    c.db_max = 0x1p-10f;
    c.dk_max = 1.0f;
    rm_init(&rm, &c);
    EXPECT_ACCEPTED(write_pair(&rm, 0.1f, -0x1p-10f));
    EXPECT_ACCEPTED(write_B(&rm, 0.0f));
    EXPECT_REFUSED(&rm, write_B(&rm, -0x1p-10f - 0x1p-30f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_B_STEP);
}

/* Live registers after a change, against the device functions they report. */
static void test_live_registers(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    zw_device d = paper_device();
    zw_device_extremes x;
    zw_real v, lo, hi;
    bool any;
    (void)state;
    rm_init(&rm, &c);
    EXPECT_OK(zw_device_extremes_compute(&d, &x));
    /* gains off: K_max at B = 0 (= K_p_max), the B interval of K = 0 is (0, 0), rho = 1 */
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_K_MAX), x.K_p_max, 1e-6);
    assert_true(rdf(&rm, ZW_REG_LIVE_B_LO) == 0.0f);
    assert_true(rdf(&rm, ZW_REG_LIVE_B_HI) == 0.0f);
    EXPECT_NEAR(rdf(&rm, ZW_REG_LIVE_RHO), 1.0, 1e-5, 0);
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_DELTA), 5.1224, 1e-4);
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_K_MMAX), x.K_mmax, 1e-6);
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_B_AT_KMMAX), x.B_at_K_mmax, 1e-6);
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, -1e-3f));
    EXPECT_OK(zw_device_k_max(&d, R(-1e-3f), &v));
    assert_true(rdf(&rm, ZW_REG_LIVE_K_MAX) == (float)v);
    assert_true(rdf(&rm, ZW_REG_LIVE_K_CERT) <= (float)v);
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_K_CERT), v, PREC(1e-6, 1e-4)); /* just inside the sup */
    EXPECT_OK(zw_device_b_range(&d, R(0.3f), &lo, &hi, &any));
    assert_true(any);
    assert_true(rdf(&rm, ZW_REG_LIVE_B_LO) == (float)lo);
    assert_true(rdf(&rm, ZW_REG_LIVE_B_HI) == (float)hi);
    EXPECT_OK(zw_device_spectral_radius(&d, R(0.3f), R(-1e-3f), &v));
    assert_true(rdf(&rm, ZW_REG_LIVE_RHO) == (float)v);
    EXPECT_NEAR(rdf(&rm, ZW_REG_LIVE_RHO), 0.84626, 1e-4, 0);
    /* a refused write leaves them alone (snapshot comparison covers 0x20..0x2F) */
    EXPECT_REFUSED(&rm, write_K(&rm, 0.9f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
}

static void test_state_registers(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    (void)state;
    rm_init(&rm, &c);
    zw_regmap_set_state(&rm, 0.125f, -2.5f, 1e-3f, 0x89ABCDEFu);
    assert_true(rdf(&rm, ZW_REG_STATE_X) == 0.125f);
    assert_true(rdf(&rm, ZW_REG_STATE_V) == -2.5f);
    assert_true(rdf(&rm, ZW_REG_STATE_F) == 1e-3f);
    assert_int_equal(rd(&rm, ZW_REG_STATE_STEP), 0x89ABu);
    assert_int_equal(rd(&rm, ZW_REG_STATE_STEP + 1), 0xCDEFu);
    zw_regmap_set_state(&rm, (float)NAN, (float)INFINITY, -0.0f, 0u);
    assert_int_equal(rd32(&rm, ZW_REG_STATE_X), 0x7FC00000u);
    assert_int_equal(rd32(&rm, ZW_REG_STATE_V), 0x7F800000u);
    assert_int_equal(rd32(&rm, ZW_REG_STATE_F), 0x80000000u);
    zw_regmap_set_state(NULL, 1.0f, 1.0f, 1.0f, 1u); /* no-op */
    /* the state does not count as a request and changes no refusal register */
    assert_int_equal(rd32(&rm, ZW_REG_REFUSED), 0u);
}

/* ---- commissioning ----------------------------------------------------------------------- */

static void unlock(zw_regmap *rm)
{
    EXPECT_ACCEPTED(command(rm, ZW_CMD_UNLOCK1));
    EXPECT_ACCEPTED(command(rm, ZW_CMD_UNLOCK2));
    assert_int_equal(rd(rm, ZW_REG_MODE), 1u);
}

static void test_unlock_sequence(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t w = 0u;
    snap sealed_view;
    unsigned i;
    (void)state;
    rm_init(&rm, &c);
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, 0.0f));
    /* UNLOCK2 alone, or in the wrong order */
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_REFUSED(&rm, command(&rm, (uint_least16_t)(ZW_CMD_UNLOCK1 ^ 1u)), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_BAD_COMMAND);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    /* reads, accepted, refused or unprocessed, leave UNLOCK1 armed: a client polling the
     * map must not be able to block commissioning */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    (void)rd(&rm, ZW_REG_MAGIC);
    assert_int_equal(zw_regmap_read(&rm, 0x0A, 1, &w, NULL), ZW_MB_ILLEGAL_ADDRESS);
    assert_int_equal(zw_regmap_read(&rm, 0, 1, NULL, NULL), ZW_MB_SERVER_FAILURE);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK2));
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, 0.0f));
    /* interrupted by an accepted gain write */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_ACCEPTED(write_K(&rm, 0.2f));
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    /* by a refused write */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_REFUSED(&rm, write_K(&rm, 1e30f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_ABOVE_MAX);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    /* by a write that could not be processed (NULL words) */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    assert_int_equal(zw_regmap_write(&rm, ZW_REG_K, 2, NULL, NULL), ZW_MB_SERVER_FAILURE);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    /* SEAL and ABORT outside commissioning; unknown values */
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_ABORT), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    EXPECT_REFUSED(&rm, command(&rm, 0u), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    EXPECT_REFUSED(&rm, command(&rm, 0xFFFFu), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    assert_true(rdf(&rm, ZW_REG_K) == 0.2f);
    /* the right sequence (UNLOCK1 twice is fine: the second one re-arms) */
    sealed_view = snapshot(&rm);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK2));
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    /* output off; the staged block is the sealed one with its CRC */
    assert_true(zwt_bits_of(rdf(&rm, ZW_REG_K)) == 0u && zwt_bits_of(rdf(&rm, ZW_REG_B)) == 0u);
    for (i = ZW_REG_CERT_M; i <= ZW_REG_CERT_CRC; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)i), sealed_view.w[i]);
    /* in commissioning: gains not writable, unlock again refused */
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.1f, 0.0f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.0f, 0.0f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK1), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    /* ABORT: back to operation with the same block, output still off */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    assert_true(zwt_bits_of(rdf(&rm, ZW_REG_K)) == 0u);
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, 0.0f));
}

/* Edit, fail to seal (CRC, policy), abort, edit again, seal a new plant. */
static void test_seal(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert(), c2 = paper_cert();
    uint_least16_t block[ZW_CERT_WORDS + 1u], old_block[ZW_CERT_WORDS + 1u];
    unsigned i;
    (void)state;
    rm_init(&rm, &c);
    block_words(&c, old_block);
    unlock(&rm);
    /* a new period: 10 ms, and a tighter sigma */
    c2.T = 0.01f;
    c2.sigma = 0.9f;
    block_words(&c2, block);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS, block)); /* CRC not yet */
    for (i = 0; i < ZW_CERT_WORDS; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)(ZW_REG_CERT_M + i)), block[i]);
    assert_int_equal(rd(&rm, ZW_REG_CERT_CRC), old_block[ZW_CERT_WORDS]);
    /* CRC of the old block: refused, still commissioning, nothing installed */
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_CRC);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_DELTA), 5.1224, 1e-4);
    /* a staged NaN or infinity is refused at the write */
    {
        uint_least16_t bad[2] = {0x7FC0u, 0u};
        EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_CERT_SIGMA, 2, bad), ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_NOT_FINITE);
        bad[0] = 0xFF80u;
        EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_CERT_B_MIN, 2, bad), ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_NOT_FINITE);
        EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_CERT_M + 1, 1, bad), ZW_MB_ILLEGAL_ADDRESS,
                       ZW_REASON_HALF_FLOAT);
    }
    /* a valid CRC over a bad policy: refused, still commissioning */
    {
        zw_cert bad = c2;
        uint_least16_t bw[ZW_CERT_WORDS + 1u];
        bad.r = 1.25f;
        block_words(&bad, bw);
        EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, bw));
        EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_POLICY);
        assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
        bad = c2;
        bad.m = 0.0f;
        block_words(&bad, bw);
        EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, bw));
        EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_POLICY);
        /* a CRC one bit off */
        block_words(&c2, bw);
        bw[ZW_CERT_WORDS] = (uint_least16_t)(bw[ZW_CERT_WORDS] ^ 0x8000u);
        EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, bw));
        EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_CRC);
    }
    /* ABORT restores the sealed block */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    for (i = 0; i <= ZW_CERT_WORDS; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)(ZW_REG_CERT_M + i)), old_block[i]);
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, block),
                   ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_LOCKED);
    /* again, now with the right CRC (written on its own) */
    unlock(&rm);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS, block));
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_CRC, 1, &block[ZW_CERT_WORDS]));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SEAL));
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    assert_true(zwt_bits_of(rdf(&rm, ZW_REG_K)) == 0u);
    for (i = 0; i <= ZW_CERT_WORDS; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)(ZW_REG_CERT_M + i)), block[i]);
    /* the new plant is in force: delta halves, sigma = 0.9 applies */
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_DELTA), 5.1224 / 2, 1e-4);
    {
        zw_device d;
        zw_real kmax;
        EXPECT_OK(zw_device_init(&d, (zw_real)J1, (zw_real)B_SHORT, R(0.01f)));
        EXPECT_OK(zw_device_k_max(&d, R(0.0), &kmax));
        EXPECT_REFUSED(&rm, write_K(&rm, (float)(R(0.95) * kmax)), ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_ABOVE_SIGMA);
        EXPECT_ACCEPTED(write_K(&rm, (float)(R(0.85) * kmax)));
    }
}

/* Commissioning a drive that started unsealed: the staged block is all zero. */
static void test_commission_unsealed(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t block[ZW_CERT_WORDS + 1u];
    unsigned i;
    (void)state;
    EXPECT_OK(zw_regmap_init(&rm, NULL, NULL));
    allow_commissioning(&rm);
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_CERT_CRC, 1, block), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_LOCKED);
    unlock(&rm);
    for (i = ZW_REG_CERT_M; i <= ZW_REG_CERT_CRC; ++i)
        assert_int_equal(rd(&rm, (uint_least16_t)i), 0u);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_CRC);
    block_words(&c, block);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, block));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SEAL));
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    EXPECT_ACCEPTED(write_pair(&rm, 0.4f, -1.36e-3f));
    /* ABORT on a drive that was never sealed leaves it unsealed */
    EXPECT_OK(zw_regmap_init(&rm, NULL, NULL));
    allow_commissioning(&rm);
    unlock(&rm);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, block));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    assert_int_equal(rd(&rm, ZW_REG_CERT_M), 0u);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.1f, 0.0f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
}

/* ---- PDUs ---------------------------------------------------------------------------------- */

typedef struct reply {
    zw_mb_exception exc;
    size_t len;
    uint_least8_t b[260];
} reply;

static reply pdu_cap(zw_regmap *rm, const uint_least8_t *req, size_t n, size_t cap)
{
    reply r;
    memset(&r, 0xEE, sizeof r);
    r.exc = zw_regmap_handle_pdu(rm, req, n, r.b, cap, &r.len);
    return r;
}

static reply pdu(zw_regmap *rm, const uint_least8_t *req, size_t n)
{
    return pdu_cap(rm, req, n, 253);
}

static void expect_exception_reply(reply r, unsigned fc, zw_mb_exception exc)
{
    assert_int_equal(r.exc, exc);
    assert_int_equal(r.len, 2);
    assert_int_equal(r.b[0], (fc | 0x80u) & 0xFFu);
    assert_int_equal(r.b[1], exc);
}

/* A refused PDU: exception reply, and only the refusal registers moved. */
#define EXPECT_PDU_REFUSED(rm, req, n, want_exc, want_why)                                     \
    do {                                                                                         \
        snap b_ = snapshot(rm);                                                                  \
        zw_regmap s_ = *(rm);                                                                    \
        reply r_ = pdu((rm), (req), (n));                                                        \
        outcome o_;                                                                              \
        expect_exception_reply(r_, (unsigned)(req)[0], (want_exc));                              \
        o_.exc = r_.exc;                                                                         \
        o_.why = (zw_reason)(rm)->last_reason;                                                   \
        check_refused((rm), &b_, &s_, o_, (want_exc), (want_why), #req, __FILE__, __LINE__);     \
    } while (0)

static void test_pdu_read(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    static const uint_least8_t rd10[] = {0x03, 0x00, 0x00, 0x00, 0x0A};
    static const uint_least8_t rd_k[] = {0x03, 0x00, 0x10, 0x00, 0x04};
    static const uint_least8_t short4[] = {0x03, 0x00, 0x00, 0x00};
    static const uint_least8_t long6[] = {0x03, 0x00, 0x00, 0x00, 0x01, 0x00};
    static const uint_least8_t q0[] = {0x03, 0x00, 0x00, 0x00, 0x00};
    static const uint_least8_t q126[] = {0x03, 0x00, 0x00, 0x00, 0x7E};
    static const uint_least8_t q125[] = {0x03, 0x00, 0x00, 0x00, 0x7D};
    static const uint_least8_t unm[] = {0x03, 0x00, 0x0A, 0x00, 0x01};
    static const uint_least8_t wrap[] = {0x03, 0xFF, 0xFF, 0x00, 0x02};
    static const uint_least8_t only_fc[] = {0x03};
    reply r;
    (void)state;
    rm_init(&rm, &c);
    r = pdu(&rm, rd10, sizeof rd10);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_int_equal(r.len, 22);
    assert_int_equal(r.b[0], 0x03);
    assert_int_equal(r.b[1], 20);
    assert_int_equal(r.b[2], 0x5A);
    assert_int_equal(r.b[3], 0x57);
    assert_int_equal(r.b[4], 0x00);
    assert_int_equal(r.b[5], 0x05); /* map version 5 */
    assert_int_equal(r.b[8], 0x00);
    assert_int_equal(r.b[9], 0x01); /* SEALED */
    EXPECT_ACCEPTED(write_pair(&rm, 0.25f, -0x1p-11f));
    r = pdu(&rm, rd_k, sizeof rd_k);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_int_equal(r.len, 10);
    assert_int_equal(r.b[1], 8);
    assert_int_equal(r.b[2], 0x3E); /* 0.25f = 0x3E80 0000 */
    assert_int_equal(r.b[3], 0x80);
    assert_int_equal(r.b[4], 0x00);
    assert_int_equal(r.b[5], 0x00);
    assert_int_equal(r.b[6], 0xBA); /* -2^-11 = 0xBA00 0000 */
    assert_int_equal(r.b[7], 0x00);
    EXPECT_PDU_REFUSED(&rm, short4, sizeof short4, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, long6, sizeof long6, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, only_fc, sizeof only_fc, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, q0, sizeof q0, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, q126, sizeof q126, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, q125, sizeof q125, ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
    EXPECT_PDU_REFUSED(&rm, unm, sizeof unm, ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
    EXPECT_PDU_REFUSED(&rm, wrap, sizeof wrap, ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
    /* the largest read the map allows: its 23-word block */
    {
        static const uint_least8_t blk[] = {0x03, 0x00, 0x40, 0x00, 0x17};
        r = pdu(&rm, blk, sizeof blk);
        assert_int_equal(r.exc, ZW_MB_OK);
        assert_int_equal(r.len, 2 + 46);
        assert_int_equal(r.b[2], 0x37); /* J = 85.78e-7 = 0x370F EA3B */
        assert_int_equal(r.b[3], 0x0F);
        assert_int_equal(r.b[4], 0xEA);
        assert_int_equal(r.b[5], 0x3B);
    }
}

static void test_pdu_write(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    /* K = 0.25 (0x3E80 0000), B = -2^-11 (0xBA00 0000) */
    static const uint_least8_t pair[] = {0x10, 0x00, 0x10, 0x00, 0x04, 0x08, 0x3E, 0x80,
                                         0x00, 0x00, 0xBA, 0x00, 0x00, 0x00};
    static const uint_least8_t k_only[] = {0x10, 0x00, 0x10, 0x00, 0x02,
                                           0x04, 0x3E, 0x00, 0x00, 0x00};
    static const uint_least8_t bc_mismatch[] = {0x10, 0x00, 0x10, 0x00, 0x02, 0x06, 0x3E,
                                                0x00, 0x00, 0x00, 0x00, 0x00};
    static const uint_least8_t truncated[] = {0x10, 0x00, 0x10, 0x00, 0x02, 0x04, 0x3E, 0x00, 0x00};
    static const uint_least8_t extra[] = {0x10, 0x00, 0x10, 0x00, 0x02, 0x04,
                                          0x3E, 0x00, 0x00, 0x00, 0x00};
    static const uint_least8_t hdr_only[] = {0x10, 0x00, 0x10, 0x00, 0x02};
    static const uint_least8_t q0[] = {0x10, 0x00, 0x10, 0x00, 0x00, 0x00};
    static const uint_least8_t fc6_k[] = {0x06, 0x00, 0x10, 0x3E, 0x80};
    static const uint_least8_t fc6_short[] = {0x06, 0x00, 0x64, 0xC0};
    static const uint_least8_t fc6_long[] = {0x06, 0x00, 0x64, 0xC0, 0xDE, 0x00};
    static const uint_least8_t fc6_ro[] = {0x06, 0x00, 0x00, 0x00, 0x00};
    static const uint_least8_t fc6_unlock1[] = {0x06, 0x00, 0x64, 0xC0, 0xDE};
    static const uint_least8_t fc6_unlock2[] = {0x06, 0x00, 0x64, 0x5A, 0xFE};
    static const uint_least8_t fc16_abort[] = {0x10, 0x00, 0x64, 0x00, 0x01, 0x02, 0xAB, 0x07};
    static const uint_least8_t nan_b[] = {0x10, 0x00, 0x12, 0x00, 0x02,
                                          0x04, 0x7F, 0xC0, 0x00, 0x00};
    reply r;
    size_t i;
    (void)state;
    rm_init(&rm, &c);
    r = pdu(&rm, pair, sizeof pair);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_int_equal(r.len, 5);
    for (i = 0; i < 5; ++i) assert_int_equal(r.b[i], pair[i]);
    assert_true(rdf(&rm, ZW_REG_K) == 0.25f);
    assert_true(rdf(&rm, ZW_REG_B) == -0x1p-11f);
    r = pdu(&rm, k_only, sizeof k_only);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_true(rdf(&rm, ZW_REG_K) == 0.125f);
    EXPECT_PDU_REFUSED(&rm, bc_mismatch, sizeof bc_mismatch, ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, truncated, sizeof truncated, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, extra, sizeof extra, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, hdr_only, sizeof hdr_only, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, q0, sizeof q0, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, fc6_k, sizeof fc6_k, ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_HALF_FLOAT);
    EXPECT_PDU_REFUSED(&rm, fc6_short, sizeof fc6_short, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, fc6_long, sizeof fc6_long, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    EXPECT_PDU_REFUSED(&rm, fc6_ro, sizeof fc6_ro, ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_READ_ONLY);
    EXPECT_PDU_REFUSED(&rm, nan_b, sizeof nan_b, ZW_MB_ILLEGAL_VALUE, ZW_REASON_NOT_FINITE);
    /* quantity 124 (one past 123) with a consistent byte count, and 123 (allowed, unmapped) */
    {
        uint_least8_t big[6 + 2 * 124];
        memset(big, 0, sizeof big);
        big[0] = 0x10;
        big[2] = 0x10;
        big[4] = 124;
        big[5] = 248;
        EXPECT_PDU_REFUSED(&rm, big, sizeof big, ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
        big[4] = 123;
        big[5] = 246;
        EXPECT_PDU_REFUSED(&rm, big, sizeof big - 2, ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_UNMAPPED);
    }
    /* commands through FC 0x06 (echoed) and FC 0x10 */
    r = pdu(&rm, fc6_unlock1, sizeof fc6_unlock1);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_int_equal(r.len, 5);
    for (i = 0; i < 5; ++i) assert_int_equal(r.b[i], fc6_unlock1[i]);
    r = pdu(&rm, fc6_unlock2, sizeof fc6_unlock2);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    r = pdu(&rm, fc16_abort, sizeof fc16_abort);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_int_equal(r.len, 5);
    assert_int_equal(r.b[4], 0x01);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
}

static void test_pdu_bad_function(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    static const uint_least8_t fcs[] = {0x00, 0x01, 0x02, 0x04, 0x05, 0x0F,
                                        0x16, 0x17, 0x2B, 0x83, 0xFF};
    size_t i;
    (void)state;
    rm_init(&rm, &c);
    for (i = 0; i < ZWT_ARRAY_LEN(fcs); ++i) {
        uint_least8_t req[5] = {0, 0x00, 0x00, 0x00, 0x01};
        req[0] = fcs[i];
        EXPECT_PDU_REFUSED(&rm, req, sizeof req, ZW_MB_ILLEGAL_FUNCTION, ZW_REASON_BAD_FUNCTION);
        EXPECT_PDU_REFUSED(&rm, req, 1, ZW_MB_ILLEGAL_FUNCTION, ZW_REASON_BAD_FUNCTION);
    }
}

/* resp_cap too small: nothing processed, not even counted. */
static void test_pdu_resp_cap(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    static const uint_least8_t rd10[] = {0x03, 0x00, 0x00, 0x00, 0x0A};
    static const uint_least8_t pair[] = {0x10, 0x00, 0x10, 0x00, 0x04, 0x08, 0x3E, 0x80,
                                         0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
    static const uint_least8_t bad_fc[] = {0x2B};
    static const uint_least8_t unlock1[] = {0x06, 0x00, 0x64, 0xC0, 0xDE};
    static const uint_least8_t unlock2[] = {0x06, 0x00, 0x64, 0x5A, 0xFE};
    snap before, after;
    zw_regmap copy;
    reply r;
    size_t cap;
    (void)state;
    rm_init(&rm, &c);
    before = snapshot(&rm);
    for (cap = 0; cap < 2; ++cap) {
        copy = rm;
        r = pdu_cap(&rm, rd10, sizeof rd10, cap);
        assert_int_equal(r.exc, ZW_MB_SERVER_FAILURE);
        assert_int_equal(r.len, 0);
        assert_int_equal(r.b[0], 0xEE); /* nothing written */
        r = pdu_cap(&rm, pair, sizeof pair, cap);
        assert_int_equal(r.exc, ZW_MB_SERVER_FAILURE);
        assert_int_equal(r.len, 0);
        r = pdu_cap(&rm, bad_fc, sizeof bad_fc, cap);
        assert_int_equal(r.exc, ZW_MB_SERVER_FAILURE);
        assert_int_equal(r.len, 0);
        assert_memory_equal(&copy, &rm, sizeof rm);
    }
    /* room for an exception but not for the answer: 0x04, nothing applied or counted */
    for (cap = 2; cap < 22; ++cap) {
        copy = rm;
        r = pdu_cap(&rm, rd10, sizeof rd10, cap);
        expect_exception_reply(r, 0x03, ZW_MB_SERVER_FAILURE);
        if (cap < 5) {
            r = pdu_cap(&rm, pair, sizeof pair, cap);
            expect_exception_reply(r, 0x10, ZW_MB_SERVER_FAILURE);
        }
        assert_memory_equal(&copy, &rm, sizeof rm);
    }
    after = snapshot(&rm);
    expect_same_registers(&before, &after, true, __FILE__, __LINE__);
    /* exact fits work */
    r = pdu_cap(&rm, rd10, sizeof rd10, 22);
    assert_int_equal(r.exc, ZW_MB_OK);
    r = pdu_cap(&rm, pair, sizeof pair, 5);
    assert_int_equal(r.exc, ZW_MB_OK);
    assert_true(rdf(&rm, ZW_REG_K) == 0.25f);
    /* a bad function code with room for its exception is an ordinary refusal */
    r = pdu_cap(&rm, bad_fc, sizeof bad_fc, 2);
    expect_exception_reply(r, 0x2B, ZW_MB_ILLEGAL_FUNCTION);
    /* an unprocessed write still disarms UNLOCK1; an unprocessed read does not */
    r = pdu(&rm, unlock1, sizeof unlock1);
    assert_int_equal(r.exc, ZW_MB_OK);
    r = pdu_cap(&rm, rd10, sizeof rd10, 1);
    assert_int_equal(r.exc, ZW_MB_SERVER_FAILURE);
    r = pdu_cap(&rm, pair, sizeof pair, 4);
    assert_int_equal(r.exc, ZW_MB_SERVER_FAILURE);
    r = pdu(&rm, unlock2, sizeof unlock2);
    expect_exception_reply(r, 0x06, ZW_MB_ILLEGAL_VALUE);
    assert_int_equal(rd(&rm, ZW_REG_LAST_REASON), ZW_REASON_BAD_COMMAND);
}

static void test_null_arguments(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    static const uint_least8_t rd1[] = {0x03, 0x00, 0x00, 0x00, 0x01};
    uint_least8_t resp[8];
    uint_least16_t w[2] = {0x1111u, 0x2222u};
    size_t len = 99;
    zw_reason why = ZW_REASON_CRC;
    zw_regmap copy;
    (void)state;
    rm_init(&rm, &c);
    assert_int_equal(zw_regmap_handle_pdu(NULL, rd1, sizeof rd1, resp, sizeof resp, &len),
                     ZW_MB_SERVER_FAILURE);
    assert_int_equal(len, 0);
    copy = rm;
    len = 99;
    assert_int_equal(zw_regmap_handle_pdu(&rm, NULL, sizeof rd1, resp, sizeof resp, &len),
                     ZW_MB_SERVER_FAILURE);
    assert_int_equal(len, 0);
    len = 99;
    assert_int_equal(zw_regmap_handle_pdu(&rm, rd1, sizeof rd1, NULL, sizeof resp, &len),
                     ZW_MB_SERVER_FAILURE);
    assert_int_equal(len, 0);
    assert_int_equal(zw_regmap_handle_pdu(&rm, rd1, sizeof rd1, resp, sizeof resp, NULL),
                     ZW_MB_SERVER_FAILURE);
    len = 99;
    assert_int_equal(zw_regmap_handle_pdu(&rm, rd1, 0, resp, sizeof resp, &len),
                     ZW_MB_SERVER_FAILURE);
    assert_int_equal(len, 0);
    assert_int_equal(zw_regmap_read(NULL, 0, 1, w, &why), ZW_MB_SERVER_FAILURE);
    assert_int_equal(zw_regmap_read(&rm, 0, 1, NULL, &why), ZW_MB_SERVER_FAILURE);
    assert_int_equal(zw_regmap_write(NULL, ZW_REG_K, 2, w, &why), ZW_MB_SERVER_FAILURE);
    assert_int_equal(zw_regmap_write(&rm, ZW_REG_K, 2, NULL, &why), ZW_MB_SERVER_FAILURE);
    assert_int_equal(why, ZW_REASON_CRC); /* untouched */
    assert_memory_equal(&copy, &rm, sizeof rm);
    /* reason is optional */
    assert_int_equal(zw_regmap_read(&rm, 0, 1, w, NULL), ZW_MB_OK);
    assert_int_equal(zw_regmap_read(&rm, 0x0A, 1, w, NULL), ZW_MB_ILLEGAL_ADDRESS);
    words_of(0.1f, w);
    assert_int_equal(zw_regmap_write(&rm, ZW_REG_K, 2, w, NULL), ZW_MB_OK);
    assert_int_equal(zw_regmap_write(&rm, ZW_REG_K, 1, w, NULL), ZW_MB_ILLEGAL_ADDRESS);
    /* the conversions */
    zw_float_to_words(1.0f, NULL);
    assert_true(zw_words_to_float(NULL) != zw_words_to_float(NULL));
    assert_int_equal(zw_crc16_words(NULL, 3), 0xFFFFu);
}

static void test_reason_names(void **state)
{
#define ZWT_REASON(x) {x, #x}
    static const struct {
        zw_reason reason;
        const char *spelled;
    } k[] = {
        ZWT_REASON(ZW_REASON_NONE),         ZWT_REASON(ZW_REASON_BAD_FUNCTION),
        ZWT_REASON(ZW_REASON_MALFORMED),    ZWT_REASON(ZW_REASON_UNMAPPED),
        ZWT_REASON(ZW_REASON_READ_ONLY),    ZWT_REASON(ZW_REASON_HALF_FLOAT),
        ZWT_REASON(ZW_REASON_LOCKED),       ZWT_REASON(ZW_REASON_NOT_SEALED),
        ZWT_REASON(ZW_REASON_NOT_FINITE),   ZWT_REASON(ZW_REASON_K_BELOW_MIN),
        ZWT_REASON(ZW_REASON_K_ABOVE_MAX),  ZWT_REASON(ZW_REASON_B_BELOW_MIN),
        ZWT_REASON(ZW_REASON_B_ABOVE_MAX),  ZWT_REASON(ZW_REASON_K_STEP),
        ZWT_REASON(ZW_REASON_B_STEP),       ZWT_REASON(ZW_REASON_UNSTABLE),
        ZWT_REASON(ZW_REASON_ABOVE_SIGMA),  ZWT_REASON(ZW_REASON_RADIUS),
        ZWT_REASON(ZW_REASON_BAD_COMMAND),  ZWT_REASON(ZW_REASON_CRC),
        ZWT_REASON(ZW_REASON_BAD_POLICY),   ZWT_REASON(ZW_REASON_FPENV),
        ZWT_REASON(ZW_REASON_BAD_DELAY),    ZWT_REASON(ZW_REASON_BAD_FILTER),
        ZWT_REASON(ZW_REASON_BAD_FILTER_PARAM), ZWT_REASON(ZW_REASON_BAD_DIFFERENTIATOR),
        ZWT_REASON(ZW_REASON_LOOP_NEVER_STABLE), ZWT_REASON(ZW_REASON_NO_CONSENT),
        ZWT_REASON(ZW_REASON_RNG),          ZWT_REASON(ZW_REASON_AUTH),
        ZWT_REASON(ZW_REASON_ABOVE_CEILING), ZWT_REASON(ZW_REASON_PLANT_MISMATCH),
        ZWT_REASON(ZW_REASON_SUBNORMAL),    ZWT_REASON(ZW_REASON_ONLY_OFF),
        ZWT_REASON(ZW_REASON_NO_CEILINGS),  ZWT_REASON(ZW_REASON_NO_STORAGE),
        ZWT_REASON(ZW_REASON_STORAGE),      ZWT_REASON(ZW_REASON_IMAGE_FORMAT),
        ZWT_REASON(ZW_REASON_IMAGE_CRC),    ZWT_REASON(ZW_REASON_LOOP_MISMATCH),
        ZWT_REASON(ZW_REASON_BOX_BUDGET),   ZWT_REASON(ZW_REASON_BOX_RADIUS),
        ZWT_REASON(ZW_REASON_BOX_CERT),     ZWT_REASON(ZW_REASON_OUTSIDE_CERT),
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(k); ++i) {
        assert_int_equal((int)k[i].reason, (int)i);
        assert_string_equal(zw_reason_name(k[i].reason), k[i].spelled);
    }
    assert_string_equal(zw_reason_name((zw_reason)ZWT_ARRAY_LEN(k)), "ZW_REASON_UNKNOWN");
    assert_string_equal(zw_reason_name((zw_reason)-1), "ZW_REASON_UNKNOWN");
}

/* A long mixed sequence: after every refusal, only the refusal registers have moved. */
static void test_refusals_change_nothing(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t junk[8] = {0x7FC0u, 0u, 0x4000u, 0u, 0xFFFFu, 0xFFFFu, 0x1234u, 0x5678u};
    (void)state;
    c.sigma = 0.85f;
    c.r = 0.95f;
    c.dk_max = 0.3f;
    c.db_max = 2e-3f;
    rm_init(&rm, &c);
    zw_regmap_set_state(&rm, 1.0f, 2.0f, 3.0f, 4u);
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, -1.2e-3f));
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_K, 4, junk), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_NOT_FINITE);
    EXPECT_REFUSED(&rm, write_pair(&rm, 20.0f, 0.0f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_K_ABOVE_MAX);
    /* sigma before radius: rho(0.45, -1.36e-3) = 0.977 > r too */
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.45f, -1.36e-3f), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_ABOVE_SIGMA);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.41f, -1.36e-3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_RADIUS);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.3f, 1e-3f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_B_STEP);
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_CERT_M, 2, junk + 2), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_LOCKED);
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_LIVE_K_MAX, 2, junk), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_READ_ONLY);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    EXPECT_ACCEPTED(write_pair(&rm, 0.35f, -1.36e-3f));
    assert_int_equal(rd32(&rm, ZW_REG_REFUSED), 8u);
    assert_int_equal(rd(&rm, ZW_REG_LAST_REASON), ZW_REASON_BAD_COMMAND);
    assert_int_equal(rd(&rm, ZW_REG_LAST_EXCEPTION), ZW_MB_ILLEGAL_VALUE);
}

/* The exported block codec: register order, round trip, and the CRC the drive itself
 * reports for the sealed block (the words a commissioning tool must send). */
static void test_cert_codec(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert(), back;
    uint_least16_t words[ZW_CERT_WORDS + 1u];
    unsigned i;
    (void)state;
    c.sigma = 0.8f;
    c.r = 0.999f;
    zw_cert_encode(&c, words);
    for (i = 0; i < ZW_CERT_FIELDS; ++i) {
        uint_least16_t one[2];
        zw_float_to_words(zw_cert_field(&c, i), one);
        assert_int_equal(words[2u * i], one[0]);
        assert_int_equal(words[2u * i + 1u], one[1]);
    }
    /* m = 85.78e-7f is 0x370FEA3B (Python: struct.pack('>f', 85.78e-7)): high word first */
    assert_int_equal(words[0], 0x370Fu);
    assert_int_equal(words[1], 0xEA3Bu);
    memset(&back, 0, sizeof back);
    zw_cert_decode(words, &back);
    assert_memory_equal(&back, &c, sizeof c);
    rm_init(&rm, &c);
    for (i = 0; i <= ZW_CERT_WORDS; ++i) assert_int_equal(rd(&rm, (uint_least16_t)(ZW_REG_CERT_M + i)), words[i]);
}

/* ---- the control loop's side: zw_regmap_active_gains, and what crosses contexts ------------ */

/* The reader hands out the pair in force, bit for bit the K and B registers (registers: the
 * Modbus task's view, not compared in the mid-publication states built below). */
static void expect_active(zw_regmap *rm, float K, float B, bool registers, const char *file,
                          int line)
{
    float k = 1234.0f, b = 1234.0f;
    zw_status st = zw_regmap_active_gains(rm, &k, &b);
    if (st != ZW_OK || zwt_bits_of(k) != zwt_bits_of(K) || zwt_bits_of(b) != zwt_bits_of(B) ||
        (registers && (zwt_bits_of(k) != rd32(rm, ZW_REG_K) || zwt_bits_of(b) != rd32(rm, ZW_REG_B)))) {
        print_error("%s:%d: active gains %s (%.9g, %.9g), expected (%.9g, %.9g); registers "
                    "0x%08lX 0x%08lX\n", file, line, zw_status_name(st), (double)k, (double)b,
                    (double)K, (double)B, (unsigned long)rd32(rm, ZW_REG_K),
                    (unsigned long)rd32(rm, ZW_REG_B));
        _fail(file, line);
    }
}
#define EXPECT_ACTIVE(rm, K, B) expect_active((rm), (K), (B), true, __FILE__, __LINE__)
#define EXPECT_READER(rm, K, B) expect_active((rm), (K), (B), false, __FILE__, __LINE__)

static void test_active_gains(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    float K = 1.0f, B = 1.0f;
    (void)state;
    rm_init(&rm, &c);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, -1.2e-3f));
    EXPECT_ACTIVE(&rm, 0.3f, -1.2e-3f);
    EXPECT_OUTCOME(write_pair(&rm, 0.9f, 0.0f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
    EXPECT_ACTIVE(&rm, 0.3f, -1.2e-3f);
    EXPECT_ACCEPTED(write_K(&rm, 0.35f)); /* judged with, and paired with, the B in force */
    EXPECT_ACTIVE(&rm, 0.35f, -1.2e-3f);
    EXPECT_ACCEPTED(write_B(&rm, -1.36e-3f));
    EXPECT_ACTIVE(&rm, 0.35f, -1.36e-3f);
    /* through the PDU handler too */
    {
        static const uint_least8_t wr[] = {0x10, 0x00, 0x10, 0x00, 0x04, 0x08, 0x3E, 0x80,
                                           0x00, 0x00, 0xBA, 0x83, 0x12, 0x6F}; /* 0.25, -1e-3 */
        uint_least8_t resp[8];
        size_t len = 0;
        assert_int_equal(zw_regmap_handle_pdu(&rm, wr, sizeof wr, resp, sizeof resp, &len),
                         ZW_MB_OK);
        EXPECT_ACTIVE(&rm, 0.25f, zwt_float_of(0xBA83126Fu));
    }
    /* commissioning turns the output off, and a seal keeps it off */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_ACTIVE(&rm, 0.25f, zwt_float_of(0xBA83126Fu)); /* UNLOCK1 alone changes nothing */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK2));
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    EXPECT_OUTCOME(write_pair(&rm, 0.3f, 0.0f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SEAL));
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, -1.2e-3f));
    EXPECT_ACTIVE(&rm, 0.3f, -1.2e-3f);
    unlock(&rm);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    /* unsealed: off */
    EXPECT_OK(zw_regmap_init(&rm, NULL, NULL));
    allow_commissioning(&rm);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    /* errors: every output that exists reads "off" */
    EXPECT_STATUS(zw_regmap_active_gains(NULL, &K, &B), ZW_ERR_NULL);
    assert_true(K == 0.0f && B == 0.0f);
    rm_init(&rm, &c);
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, -1.2e-3f));
    K = 1.0f;
    EXPECT_STATUS(zw_regmap_active_gains(&rm, &K, NULL), ZW_ERR_NULL);
    assert_true(K == 0.0f);
    B = 1.0f;
    EXPECT_STATUS(zw_regmap_active_gains(&rm, NULL, &B), ZW_ERR_NULL);
    assert_true(B == 0.0f);
}

/* On one core the control ISR can preempt the Modbus task at any point of a publication.
 * Every state the struct passes through before the sequence word is stored (any subset of
 * the new slot's stores done, in any order) must read as the old pair, and the final state
 * as the new one: the writer only ever touches the slot that is not in force. */
static void test_active_gains_mid_publication(void **state)
{
    zw_regmap before, after;
    zw_cert c = paper_cert();
    unsigned subset;
    (void)state;
    rm_init(&before, &c);
    EXPECT_ACCEPTED(write_pair(&before, 0.3f, -1.2e-3f));
    after = before;
    EXPECT_ACCEPTED(write_pair(&after, 0.35f, -1.36e-3f));
    assert_true(after.gains_seq != before.gains_seq);
    for (subset = 0; subset < 4u; ++subset) {
        zw_regmap mid = before;
        unsigned i;
        for (i = 0; i < 2u; ++i) {
            if ((subset & 1u) != 0u) mid.gains[i].K = after.gains[i].K;
            if ((subset & 2u) != 0u) mid.gains[i].B = after.gains[i].B;
        }
        EXPECT_READER(&mid, 0.3f, -1.2e-3f);
        mid.gains_seq = after.gains_seq;
        if (subset == 3u) EXPECT_READER(&mid, 0.35f, -1.36e-3f);
    }
}

/* The same for the state registers, written by the control ISR while the Modbus task reads:
 * until the sequence word is stored, a read shows the previous sample, all four values. */
static void test_state_mid_publication(void **state)
{
    zw_regmap before, after;
    zw_cert c = paper_cert();
    unsigned subset;
    (void)state;
    rm_init(&before, &c);
    zw_regmap_set_state(&before, 1.0f, 2.0f, 3.0f, 4u);
    after = before;
    zw_regmap_set_state(&after, -1.0f, -2.0f, -3.0f, 5u);
    for (subset = 0; subset < 16u; ++subset) {
        zw_regmap mid = before;
        unsigned i;
        for (i = 0; i < 2u; ++i) {
            if ((subset & 1u) != 0u) mid.state[i].x = after.state[i].x;
            if ((subset & 2u) != 0u) mid.state[i].v = after.state[i].v;
            if ((subset & 4u) != 0u) mid.state[i].f = after.state[i].f;
            if ((subset & 8u) != 0u) mid.state[i].step = after.state[i].step;
        }
        assert_true(rdf(&mid, ZW_REG_STATE_X) == 1.0f && rdf(&mid, ZW_REG_STATE_V) == 2.0f &&
                    rdf(&mid, ZW_REG_STATE_F) == 3.0f && rd32(&mid, ZW_REG_STATE_STEP) == 4u);
        mid.state_seq = after.state_seq;
        if (subset == 15u)
            assert_true(rdf(&mid, ZW_REG_STATE_X) == -1.0f && rdf(&mid, ZW_REG_STATE_V) == -2.0f &&
                        rdf(&mid, ZW_REG_STATE_F) == -3.0f && rd32(&mid, ZW_REG_STATE_STEP) == 5u);
    }
}

/* A refused register-level read fills the caller's words with values that certify nothing:
 * 0, and +inf for the spectral radius; a quantity no read may have writes nothing. */
static void test_read_fail_safe_words(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t w[32];
    unsigned i;
    (void)state;
    rm_init(&rm, &c);
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, -1.2e-3f));
    for (i = 0; i < 32u; ++i) w[i] = 0x1234u;
    /* 0x0020..0x003F: the live and state registers, then unmapped 0x0038.. */
    EXPECT_REFUSED(&rm, read_words(&rm, ZW_REG_LIVE_K_MAX, 32, w), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_UNMAPPED);
    for (i = 0; i < 32u; ++i)
        assert_int_equal(w[i], ZW_REG_LIVE_K_MAX + i == ZW_REG_LIVE_RHO ? 0x7F80u : 0u);
    assert_true(zwt_float_of(((uint32_t)w[ZW_REG_LIVE_RHO - ZW_REG_LIVE_K_MAX] << 16) |
                         w[ZW_REG_LIVE_RHO - ZW_REG_LIVE_K_MAX + 1u]) == (float)INFINITY);
    /* the handler's own failure (rm NULL) too */
    w[0] = w[1] = 0x1234u;
    assert_int_equal(zw_regmap_read(NULL, ZW_REG_LIVE_K_CERT, 2, w, NULL), ZW_MB_SERVER_FAILURE);
    assert_true(w[0] == 0u && w[1] == 0u);
    /* quantities 0 and 126: nothing written */
    w[0] = 0x1234u;
    EXPECT_REFUSED(&rm, read_words(&rm, ZW_REG_K, 0, w), ZW_MB_ILLEGAL_VALUE, ZW_REASON_MALFORMED);
    assert_int_equal(w[0], 0x1234u);
}

/* Item 4 of the review: on a target whose arithmetic is not what the bounds assume, nothing
 * is sealed, at power-up or by SEAL.  The environment is broken for real: rounding upward
 * (C99 fesetround), which zw_selftest's rounding check must catch. */
static int restore_rounding(void **state)
{
    (void)state;
    return fesetround(FE_TONEAREST);
}

static void test_fpenv_refuses_seal(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t block[ZW_CERT_WORDS + 1u];
    zw_reason why = ZW_REASON_NONE;
    zw_status selftest_broken, init_st;
    outcome seal;
    (void)state;
    if (fesetround(FE_UPWARD) != 0) skip();
    selftest_broken = zw_selftest();
    init_st = zw_regmap_init(&rm, &c, &why);
    allow_commissioning(&rm);
    assert_int_equal(fesetround(FE_TONEAREST), 0);
    EXPECT_STATUS(selftest_broken, ZW_ERR_FPENV);
    EXPECT_STATUS(init_st, ZW_ERR_FPENV);
    assert_int_equal(why, ZW_REASON_FPENV);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    EXPECT_OUTCOME(write_pair(&rm, 0.3f, -1.2e-3f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
    /* commissioning: the same block and CRC, sealed under the broken environment */
    unlock(&rm);
    block_words(&c, block);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, block));
    assert_int_equal(fesetround(FE_UPWARD), 0);
    seal = command(&rm, ZW_CMD_SEAL);
    assert_int_equal(fesetround(FE_TONEAREST), 0);
    EXPECT_OUTCOME(seal, ZW_MB_ILLEGAL_VALUE, ZW_REASON_FPENV);
    assert_int_equal(rd(&rm, ZW_REG_LAST_REASON), ZW_REASON_FPENV);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u); /* still commissioning, nothing sealed */
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    /* FPENV is checked first: a wrong CRC is not even looked at */
    block[ZW_CERT_WORDS] = (uint_least16_t)(block[ZW_CERT_WORDS] ^ 1u);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_CRC, 1, &block[ZW_CERT_WORDS]));
    assert_int_equal(fesetround(FE_UPWARD), 0);
    seal = command(&rm, ZW_CMD_SEAL);
    assert_int_equal(fesetround(FE_TONEAREST), 0);
    EXPECT_OUTCOME(seal, ZW_MB_ILLEGAL_VALUE, ZW_REASON_FPENV);
    /* back to round to nearest: the same requests seal */
    block[ZW_CERT_WORDS] = (uint_least16_t)(block[ZW_CERT_WORDS] ^ 1u);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_CRC, 1, &block[ZW_CERT_WORDS]));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SEAL));
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    EXPECT_ACCEPTED(write_pair(&rm, 0.3f, -1.2e-3f));
    EXPECT_ACTIVE(&rm, 0.3f, -1.2e-3f);
}

/* ---- the loop the drive runs (map version 2) ------------------------------------------------ */

/* Stage c's block with its CRC and SEAL it (from operation mode). */
static outcome seal_block(zw_regmap *rm, const zw_cert *c)
{
    uint_least16_t block[ZW_CERT_WORDS + 1u];
    unlock(rm);
    block_words(c, block);
    EXPECT_ACCEPTED(write_words(rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, block));
    return command(rm, ZW_CMD_SEAL);
}

/* Each bad loop description is refused at SEAL with its own reason, the block in force is
 * kept (its gains still certified), and the drive stays in commissioning until ABORT. */
static void test_loop_block_refusals(void **state)
{
    static zw_regmap rm;
    static const struct {
        float delay, vfilter, param, diff;
        zw_reason why;
    } bad[] = {
        {1.5f, 0.0f, 0.0f, 0.0f, ZW_REASON_BAD_DELAY},      {9.0f, 0.0f, 0.0f, 0.0f, ZW_REASON_BAD_DELAY},
        {-1.0f, 0.0f, 0.0f, 0.0f, ZW_REASON_BAD_DELAY},     {0.0f, 3.0f, 0.0f, 0.0f, ZW_REASON_BAD_FILTER},
        {0.0f, 0.5f, 0.0f, 0.0f, ZW_REASON_BAD_FILTER},     {0.0f, -1.0f, 0.0f, 0.0f, ZW_REASON_BAD_FILTER},
        {0.0f, 0.0f, 1.0f, 0.0f, ZW_REASON_BAD_FILTER_PARAM}, /* no filter with a parameter */
        {1.0f, 1.0f, 0.0f, 0.0f, ZW_REASON_BAD_FILTER_PARAM}, /* cut-off 0 */
        {1.0f, 1.0f, -3.0f, 0.0f, ZW_REASON_BAD_FILTER_PARAM},
        {1.0f, 1.0f, 25.5f, 0.0f, ZW_REASON_BAD_FILTER_PARAM}, /* past Nyquist at T = 20 ms */
        {1.0f, 1.0f, 1e-30f, 0.0f, ZW_REASON_BAD_FILTER_PARAM}, /* the pole rounds to 1 */
        {0.0f, 2.0f, 0.0f, 0.0f, ZW_REASON_BAD_FILTER_PARAM},  {0.0f, 2.0f, 17.0f, 0.0f, ZW_REASON_BAD_FILTER_PARAM},
        {0.0f, 2.0f, 2.5f, 0.0f, ZW_REASON_BAD_FILTER_PARAM},  {0.0f, 0.0f, 0.0f, 2.0f, ZW_REASON_BAD_DIFFERENTIATOR},
        {0.0f, 0.0f, 0.0f, 0.5f, ZW_REASON_BAD_DIFFERENTIATOR},
        /* a valid loop the firmware does not run (permissive ceilings: the ideal loop) */
        {1.0f, 0.0f, 0.0f, 0.0f, ZW_REASON_LOOP_MISMATCH},
    };
    zw_cert c = paper_cert();
    size_t i;
    (void)state;
    rm_init(&rm, &c);
    for (i = 0; i < ZWT_ARRAY_LEN(bad); ++i) {
        zw_cert b = paper_cert();
        b.delay = bad[i].delay;
        b.vfilter = bad[i].vfilter;
        b.vf_param = bad[i].param;
        b.differentiator = bad[i].diff;
        EXPECT_TRUE_MSG(seal_block(&rm, &b).why == bad[i].why, "case %zu: %s, expected %s", i,
                        zw_reason_name((zw_reason)rd(&rm, ZW_REG_LAST_REASON)), zw_reason_name(bad[i].why));
        assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
        EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
        /* the ideal block in force still certifies as before */
        EXPECT_ACCEPTED(write_pair(&rm, 0.4f, -1.36e-3f));
        assert_true(rdf(&rm, ZW_REG_LIVE_POLE) == 0.0f);
    }
    { /* a firmware whose loop is never stable: Tustin with an even average (z = -1 is a
       * root for every gain); its ceilings unseal the ideal block in force */
        zw_ceilings k = permissive_ceilings();
        zw_cert b = paper_cert();
        b.vfilter = k.vfilter = 2.0f;
        b.vf_param = k.vf_param = 2.0f;
        b.differentiator = k.differentiator = 1.0f;
        assert_int_equal(zw_regmap_set_ceilings(&rm, &k, NULL), ZW_ERR_ARG);
        assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
        EXPECT_TRUE_MSG(seal_block(&rm, &b).why == ZW_REASON_LOOP_NEVER_STABLE, "%s",
                        zw_reason_name((zw_reason)rd(&rm, ZW_REG_LAST_REASON)));
    }
}

/* The certification follows the sealed loop: a pair stable for the ideal loop but not for
 * the drive's delayed one is refused as UNSTABLE; the live registers are those of the
 * delayed loop (device_loop.h); the low-pass pole is published. */
static void test_loop_block_certifies_the_real_loop(void **state)
{
    static zw_regmap rm;
    static zw_device_loop dl;
    zw_cert c = paper_cert();
    zw_device d = paper_device();
    zw_device_loop_spec spec;
    zw_real K_ideal = R(0.0), K_delay = R(0.0), rho = R(0.0), th = R(0.0);
    zw_verdict v;
    float K, k;
    (void)state;
    c.delay = 1.0f;
    rm_init(&rm, &c);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    memset(&spec, 0, sizeof spec);
    spec.delay = 1u;
    EXPECT_OK(zw_device_loop_init(&dl, (zw_real)J1, (zw_real)B_SHORT, (zw_real)T_20MS, &spec));
    EXPECT_OK(zw_device_k_max(&d, R(0.0), &K_ideal));
    EXPECT_OK(zw_device_loop_k_max(&dl, &g_ws, R(0.0), &K_delay));
    assert_true(K_delay > R(0.0) && K_delay < K_ideal * R(0.9));
    /* live registers of the delayed loop */
    assert_true(rdf(&rm, ZW_REG_LIVE_K_MAX) == (float)K_delay);
    assert_true(rdf(&rm, ZW_REG_LIVE_K_CERT) <= (float)K_delay && rdf(&rm, ZW_REG_LIVE_K_CERT) > 0.0f);
    assert_true(rdf(&rm, ZW_REG_LIVE_K_MMAX) < (float)K_ideal * 2.0f && rdf(&rm, ZW_REG_LIVE_K_MMAX) > 0.0f);
    assert_true(rdf(&rm, ZW_REG_LIVE_POLE) == 0.0f);
    /* K between the two limits: stable for the ideal loop, refused for the drive's */
    K = (float)((K_ideal + K_delay) / R(2.0));
    EXPECT_OK(zw_device_check(&d, (zw_real)K, R(0.0), &v));
    assert_true(v.stable);
    EXPECT_OK(zw_device_loop_spectral_radius(&dl, &g_ws, (zw_real)K, R(0.0), &rho, &th));
    assert_true(rho > R(1.0)); /* informational: the delayed loop is unstable there */
    for (k = 0.0f; k + 1.0f < K; k += 1.0f)
        if (k > 0.0f && (zw_real)k < K_delay) EXPECT_ACCEPTED(write_pair(&rm, k, 0.0f));
    while ((zw_real)rdf(&rm, ZW_REG_K) + R(1.0) < (zw_real)K) {
        float next = rdf(&rm, ZW_REG_K) + 1.0f;
        if ((zw_real)next >= K_delay) break;
        EXPECT_ACCEPTED(write_pair(&rm, next, 0.0f));
    }
    assert_true((zw_real)K - (zw_real)rdf(&rm, ZW_REG_K) <= R(1.0)); /* one step away */
    EXPECT_REFUSED(&rm, write_pair(&rm, K, 0.0f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
    /* K_CERT itself is accepted (when reachable in one step) and just above it is not */
    {
        const float kc = rdf(&rm, ZW_REG_LIVE_K_CERT);
        assert_true(kc - rdf(&rm, ZW_REG_K) <= 1.0f);
        EXPECT_ACCEPTED(write_pair(&rm, kc, 0.0f));
    }
    /* a low-pass by its cut-off: the pole the drive must use is published (a firmware that
     * runs that loop; its ceilings say so, and unseal the delay-only block) */
    c.vfilter = 1.0f;
    c.vf_param = 5.0f; /* Hz, at T = 20 ms */
    {
        zw_ceilings kc = permissive_ceilings();
        kc.delay = c.delay;
        kc.vfilter = c.vfilter;
        kc.vf_param = c.vf_param;
        assert_int_equal(zw_regmap_set_ceilings(&rm, &kc, NULL), ZW_ERR_ARG);
    }
    EXPECT_ACCEPTED(seal_block(&rm, &c));
    EXPECT_REL(rdf(&rm, ZW_REG_LIVE_POLE), expl(-2.0L * 3.14159265358979323846L * 5.0L * 0.02L), 1e-6);
    assert_true(rdf(&rm, ZW_REG_LIVE_K_CERT) > 0.0f);
    EXPECT_ACCEPTED(write_pair(&rm, 0.5f * rdf(&rm, ZW_REG_LIVE_K_CERT), 0.0f));
}

/* ---- consent and authentication (map version 3; review 2026-12, A3 and A4) --------------- */

/* The message a client MACs, built here from the documented layout (regmap_commission.h):
 * the map version, the nonce words, the 34 block words and the CRC, the 324 words of the
 * box certificate window (box NULL: all 0), high byte first. */
static void ref_auth_message_box(const uint_least16_t nonce[8], const uint_least16_t block[35],
                                 const uint_least16_t *box, unsigned char msg[ZW_AUTH_MSG_BYTES])
{
    size_t i, n = 0;
    msg[n++] = 0x00;
    msg[n++] = 0x05;
    for (i = 0; i < 8; ++i) {
        msg[n++] = (unsigned char)(nonce[i] >> 8);
        msg[n++] = (unsigned char)(nonce[i] & 0xFFu);
    }
    for (i = 0; i < 35; ++i) {
        msg[n++] = (unsigned char)(block[i] >> 8);
        msg[n++] = (unsigned char)(block[i] & 0xFFu);
    }
    for (i = 0; i < 324; ++i) {
        const unsigned w = box != NULL ? (unsigned)box[i] : 0u;
        msg[n++] = (unsigned char)(w >> 8);
        msg[n++] = (unsigned char)(w & 0xFFu);
    }
    assert_int_equal(n, ZW_AUTH_MSG_BYTES);
}

static void ref_auth_message(const uint_least16_t nonce[8], const uint_least16_t block[35],
                             unsigned char msg[ZW_AUTH_MSG_BYTES])
{
    ref_auth_message_box(nonce, block, NULL, msg);
}

/* n words at addr in writes of at most 123 (FC 0x10's limit); the first refusal, if any. */
static outcome write_window(zw_regmap *rm, uint_least16_t addr, unsigned n, const uint_least16_t *w)
{
    unsigned done;
    outcome o = {ZW_MB_OK, ZW_REASON_NONE};
    for (done = 0; done < n && o.exc == ZW_MB_OK; done += 123u)
        o = write_words(rm, (uint_least16_t)(addr + done), (uint_least16_t)(n - done < 123u ? n - done : 123u),
                        w + done);
    return o;
}

/* A commissioning client in commissioning mode: stages block (with its CRC), the box
 * certificate window (box NULL: left as UNLOCK2 staged it, and MACed as all 0) and the MAC
 * under key over this session's nonce (read from the map), or the given mac_words when
 * not NULL (a replay); returns the SEAL's outcome. */
static outcome client_seal_box(zw_regmap *rm, const uint_least16_t block[35], const uint_least16_t *box,
                               const unsigned char key[8], const uint_least16_t *mac_words,
                               uint_least16_t mac_out[16])
{
    uint_least16_t nonce[8], macw[16];
    unsigned char msg[ZW_AUTH_MSG_BYTES], mac[32];
    size_t i;
    assert_int_equal(zw_regmap_read(rm, ZW_REG_NONCE, 8, nonce, NULL), ZW_MB_OK);
    ref_auth_message_box(nonce, block, box, msg);
    test_mac(key, msg, sizeof msg, mac);
    for (i = 0; i < 16; ++i)
        macw[i] = mac_words != NULL ? mac_words[i]
                                    : (uint_least16_t)(((unsigned)mac[2 * i] << 8) | mac[2 * i + 1]);
    if (mac_out != NULL) memcpy(mac_out, macw, sizeof macw);
    EXPECT_ACCEPTED(write_words(rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, block));
    if (box != NULL) EXPECT_ACCEPTED(write_window(rm, ZW_REG_BOX_CERT, ZW_BOX_CERT_WORDS, box));
    EXPECT_ACCEPTED(write_words(rm, ZW_REG_MAC, 16, macw));
    return command(rm, ZW_CMD_SEAL);
}

static outcome client_seal(zw_regmap *rm, const uint_least16_t block[35], const unsigned char key[8],
                           const uint_least16_t *mac_words, uint_least16_t mac_out[16])
{
    return client_seal_box(rm, block, NULL, key, mac_words, mac_out);
}

/* The lying block of the review (A3): the plant's inertia doubled, no margin, no step limit. */
static zw_cert lying_cert(void)
{
    zw_cert c = paper_cert();
    c.m = 2.0f * J1;
    c.k_max = 1e6f;
    c.b_min = -1e3f;
    c.b_max = 1e3f;
    c.dk_max = 1e6f;
    c.db_max = 1e3f;
    return c;
}

static const unsigned char k_key[8] = {0x13, 0x57, 0x9B, 0xDF, 0x02, 0x46, 0x8A, 0xCE};

/* Power-up: no consent, no hooks.  The unlock codes alone get nobody in. */
static void test_commission_needs_consent(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    (void)state;
    memset(&rm, 0xA5, sizeof rm);
    EXPECT_OK(zw_regmap_init(&rm, &c, NULL));
    assert_int_equal(rd(&rm, ZW_REG_CONSENT), 0u);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK1), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NO_CONSENT);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    memset(&g_auth, 0, sizeof g_auth);
    allow_commissioning(&rm);
    zw_regmap_set_consent(&rm, false); /* hooks but no consent: still closed */
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK1), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NO_CONSENT);
    zw_regmap_set_consent(&rm, true);
    assert_int_equal(rd(&rm, ZW_REG_CONSENT), 1u);
    /* consent withdrawn between UNLOCK1 and UNLOCK2 */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    zw_regmap_set_consent(&rm, false);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NO_CONSENT);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    /* and during the session: SEAL refused even with the right key; ABORT still leaves */
    zw_regmap_set_consent(&rm, true);
    g_auth.strict = 1;
    memcpy(g_auth.key, k_key, sizeof k_key);
    unlock(&rm);
    zw_regmap_set_consent(&rm, false);
    {
        uint_least16_t block[35];
        zw_cert lie = lying_cert();
        block_words(&lie, block);
        EXPECT_OUTCOME(client_seal(&rm, block, k_key, NULL, NULL), ZW_MB_ILLEGAL_VALUE,
                       ZW_REASON_NO_CONSENT);
    }
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_true(rdf(&rm, ZW_REG_CERT_M) == J1);
}

/* Without the firmware's hooks, or with an RNG that fails, UNLOCK2 changes nothing. */
static void test_commission_needs_rng(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    zw_regmap_auth half;
    (void)state;
    EXPECT_OK(zw_regmap_init(&rm, &c, NULL));
    zw_regmap_set_consent(&rm, true);
    {
        zw_ceilings k = permissive_ceilings();
        EXPECT_OK(zw_regmap_set_ceilings(&rm, &k, NULL));
    }
    EXPECT_ACCEPTED(write_pair(&rm, 0.25f, 0.0f));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_RNG);
    EXPECT_ACTIVE(&rm, 0.25f, 0.0f); /* the output stayed on: nothing happened */
    half.random = test_random;
    half.verify = NULL; /* a verify hook is required too */
    half.ctx = &g_auth;
    zw_regmap_set_auth(&rm, &half);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_RNG);
    memset(&g_auth, 0, sizeof g_auth);
    allow_commissioning(&rm);
    g_auth.rng_fails = 1;
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_RNG);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    EXPECT_ACTIVE(&rm, 0.25f, 0.0f);
    zw_regmap_set_auth(NULL, &half); /* no-ops */
    zw_regmap_set_consent(NULL, true);
}

/* The review's attack (A3) with consent on: public codes, layout and CRC are not enough. */
static void test_lying_block_needs_key(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert(), lie = lying_cert();
    uint_least16_t block[35], zeros[16] = {0};
    unsigned char wrong[8];
    unsigned char msg[ZW_AUTH_MSG_BYTES];
    uint_least16_t nonce[8];
    (void)state;
    rm_init(&rm, &c);
    g_auth.strict = 1;
    memcpy(g_auth.key, k_key, sizeof k_key);
    block_words(&lie, block);
    unlock(&rm);
    /* no MAC at all (the registers read 0 after UNLOCK2) */
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, ZW_CERT_WORDS + 1u, block));
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_AUTH);
    /* a MAC under another key */
    memcpy(wrong, k_key, sizeof wrong);
    wrong[7] ^= 1u;
    EXPECT_OUTCOME(client_seal(&rm, block, wrong, NULL, NULL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_AUTH);
    EXPECT_OUTCOME(client_seal(&rm, block, k_key, zeros, NULL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_AUTH);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_true(rdf(&rm, ZW_REG_CERT_M) == J1); /* the true plant is still sealed */
    /* the key holder's SEAL goes through, and the hook saw exactly the documented message */
    unlock(&rm);
    c.sigma = 0.9f;
    block_words(&c, block);
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, nonce, NULL), ZW_MB_OK);
    EXPECT_ACCEPTED(client_seal(&rm, block, k_key, NULL, NULL));
    ref_auth_message(nonce, block, msg);
    assert_int_equal(g_auth.last_msg_len, ZW_AUTH_MSG_BYTES);
    assert_int_equal(g_auth.last_mac_len, 32u);
    assert_memory_equal(g_auth.last_msg, msg, sizeof msg);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    assert_true(rdf(&rm, ZW_REG_CERT_SIGMA) == 0.9f);
}

/* A recorded session replayed later fails: every UNLOCK2 draws a fresh nonce, and the
 * nonce and MAC registers are cleared when the session ends.  Within a session a refused
 * SEAL changes nothing, so the key holder may retry. */
static void test_replay_refused(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t block[35], mac1[16], nonce1[8], nonce2[8], w[16];
    size_t i;
    (void)state;
    rm_init(&rm, &c);
    g_auth.strict = 1;
    memcpy(g_auth.key, k_key, sizeof k_key);
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, w, NULL), ZW_MB_OK);
    for (i = 0; i < 8; ++i) assert_int_equal(w[i], 0u); /* no session: no nonce */
    c.sigma = 0.5f;
    block_words(&c, block);
    unlock(&rm);
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, nonce1, NULL), ZW_MB_OK);
    EXPECT_ACCEPTED(client_seal(&rm, block, k_key, NULL, mac1));
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_MAC, 16, w, NULL), ZW_MB_OK);
    for (i = 0; i < 16; ++i) assert_int_equal(w[i], 0u);
    /* the attacker replays the recorded block and MAC in a new session */
    unlock(&rm);
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, nonce2, NULL), ZW_MB_OK);
    assert_memory_not_equal(nonce1, nonce2, sizeof nonce1);
    EXPECT_OUTCOME(client_seal(&rm, block, k_key, mac1, NULL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_AUTH);
    /* the key holder, same session, same nonce: accepted */
    EXPECT_ACCEPTED(client_seal(&rm, block, k_key, NULL, NULL));
    /* ABORT ends a session too: its nonce is gone, the next one is new */
    unlock(&rm);
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, nonce1, NULL), ZW_MB_OK);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, w, NULL), ZW_MB_OK);
    for (i = 0; i < 8; ++i) assert_int_equal(w[i], 0u);
    unlock(&rm);
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, nonce2, NULL), ZW_MB_OK);
    assert_memory_not_equal(nonce1, nonce2, sizeof nonce1);
    /* the MAC registers are locked outside commissioning */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_MAC, 16, mac1), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_LOCKED);
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_NONCE, 8, nonce1), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_READ_ONLY);
}

static void test_auth_message_layout(void **state)
{
    uint_least16_t nonce[8], block[35], box[324];
    uint_least8_t msg[ZW_AUTH_MSG_BYTES];
    unsigned char ref[ZW_AUTH_MSG_BYTES], got[ZW_AUTH_MSG_BYTES];
    size_t i;
    (void)state;
    for (i = 0; i < 8; ++i) nonce[i] = (uint_least16_t)(0xA100u + i);
    for (i = 0; i < 35; ++i) block[i] = (uint_least16_t)(0x0100u * i + 0xFFu - i);
    for (i = 0; i < 324; ++i) box[i] = (uint_least16_t)((0x9E37u * (i + 1u)) & 0xFFFFu);
    zw_regmap_auth_message(nonce, block, box, msg);
    ref_auth_message_box(nonce, block, box, ref);
    for (i = 0; i < sizeof got; ++i) got[i] = (unsigned char)msg[i];
    assert_memory_equal(got, ref, sizeof ref);
    memset(msg, 0xEE, sizeof msg);
    zw_regmap_auth_message(NULL, block, box, msg); /* no-ops */
    zw_regmap_auth_message(nonce, NULL, box, msg);
    zw_regmap_auth_message(nonce, block, NULL, msg);
    zw_regmap_auth_message(nonce, block, box, NULL);
    for (i = 0; i < sizeof msg; ++i) assert_int_equal(msg[i], 0xEEu);
    /* the scratch that holds the message also holds SAVE's image */
    assert_true(ZW_IMAGE_BYTES <= sizeof ((zw_regmap *)NULL)->wire_scratch);
}

/* ---- factory ceilings and unusable blocks (review A3, A4, A2) ----------------------------- */

static zw_ceilings factory_ceilings(void)
{
    zw_ceilings k;
    memset(&k, 0, sizeof k); /* the ideal loop */
    k.sigma_max = 0.9f;
    k.r_max = 0.999f;
    k.m = J1;
    k.b = B_SHORT;
    k.T = T_20MS;
    k.plant_tol = 0.05f;
    k.k_min = 0.0f;
    k.k_max = 10.0f;
    k.b_min = -0.01f;
    k.b_max = 0.01f;
    k.dk_max = 1.0f;
    k.db_max = 0.01f;
    return k;
}

/* The key holder commissions c on a map with the factory's ceilings; the SEAL's outcome. */
static outcome keyed_seal(zw_regmap *rm, const zw_cert *c)
{
    uint_least16_t block[35];
    block_words(c, block);
    unlock(rm);
    return client_seal(rm, block, k_key, NULL, NULL);
}

static void test_factory_ceilings(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert(), x;
    zw_ceilings k = factory_ceilings(), bad;
    zw_reason why = ZW_REASON_NONE;
    (void)state;
    c.sigma = 0.8f;
    c.r = 0.999f;
    EXPECT_OK(zw_regmap_init(&rm, &c, NULL));
    memset(&g_auth, 0, sizeof g_auth);
    g_auth.strict = 1;
    memcpy(g_auth.key, k_key, sizeof k_key);
    {
        zw_regmap_auth hooks = {test_random, test_verify, &g_auth};
        zw_regmap_set_auth(&rm, &hooks);
    }
    zw_regmap_set_consent(&rm, true);
    /* no ceilings: no commissioning at all */
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NO_CEILINGS);
    /* invalid ceilings change nothing */
    bad = k;
    bad.sigma_max = 0.0f;
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, &bad, &why), ZW_ERR_ARG);
    bad = k;
    bad.m = (float)NAN;
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, &bad, &why), ZW_ERR_ARG);
    bad = k;
    bad.plant_tol = -1.0f;
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, &bad, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_BAD_POLICY);
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, NULL, &why), ZW_ERR_NULL);
    EXPECT_STATUS(zw_regmap_set_ceilings(NULL, &k, &why), ZW_ERR_NULL);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_UNLOCK1));
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_UNLOCK2), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NO_CEILINGS);
    EXPECT_OK(zw_regmap_set_ceilings(&rm, &k, &why));
    assert_int_equal(why, ZW_REASON_NONE);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    /* the review's lie (inertia x2) with the key: the nameplate refuses it */
    x = c;
    x.m = 2.0f * J1;
    EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, ZW_REASON_PLANT_MISMATCH);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    x = c;
    x.T = 2.0f * T_20MS;
    EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, ZW_REASON_PLANT_MISMATCH);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    x = c;
    x.b = 1.06f * B_SHORT;
    EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, ZW_REASON_PLANT_MISMATCH);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    /* margins and limits: sigma 1, r 1, wider bounds, no step limit */
    {
        static const unsigned fields[] = {3, 4, 5, 6, 7, 8, 9, 10};
        static const float values[] = {1.0f, 1.0f, -1.0f, 10.5f, -0.02f, 0.02f, 1e30f, 1.0f};
        size_t i;
        for (i = 0; i < ZWT_ARRAY_LEN(fields); ++i) {
            x = c;
            zw_cert_set_field(&x, fields[i], values[i]);
            if (fields[i] == 5) x.dk_max = 1.0f; /* k_min -1 stays reachable */
            EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, ZW_REASON_ABOVE_CEILING);
            EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
        }
    }
    /* a block for another loop than the firmware's (the ideal one here), each field */
    {
        static const unsigned fields[] = {11, 12, 13, 14};
        static const float values[] = {1.0f, 2.0f, 4.0f, 1.0f};
        size_t i;
        for (i = 0; i < ZWT_ARRAY_LEN(fields); ++i) {
            x = c;
            zw_cert_set_field(&x, fields[i], values[i]);
            if (fields[i] == 12) x.vf_param = 3.0f;  /* a valid moving average */
            if (fields[i] == 13) x.vfilter = 2.0f;
            EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, ZW_REASON_LOOP_MISMATCH);
            EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
        }
    }
    bad = k;
    bad.delay = (float)NAN;
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, &bad, &why), ZW_ERR_ARG);
    assert_true(rdf(&rm, ZW_REG_CERT_SIGMA) == 0.8f); /* the power-up block is still in force */
    /* tightening is fine, and a plant within the tolerance */
    x = c;
    x.m = 1.04f * J1;
    x.k_max = 5.0f;
    x.sigma = 0.9f;
    x.dk_max = 0.5f;
    EXPECT_ACCEPTED(keyed_seal(&rm, &x));
    assert_true(rdf(&rm, ZW_REG_CERT_K_MAX) == 5.0f);
    /* ceilings the block in force exceeds: unsealed at once, output off */
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, 0.0f));
    bad = k;
    bad.sigma_max = 0.85f;
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, &bad, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_ABOVE_CEILING);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.1f, 0.0f), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_NOT_SEALED);
    /* a firmware whose loop is not the sealed block's: unsealed at once, output off */
    EXPECT_OK(zw_regmap_init(&rm, &c, NULL));
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, 0.0f));
    bad = k;
    bad.delay = 1.0f;
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, &bad, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_LOOP_MISMATCH);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
}

/* m = 3e38: the float build refuses the plant itself (zw_device_init), the double build
 * forms it and finds no usable pair. */
#ifdef ZW_REAL_FLOAT
#define M_3E38_REASON ZW_REASON_BAD_POLICY
#else
#define M_3E38_REASON ZW_REASON_ONLY_OFF
#endif

/* Blocks the review sealed although they are unusable: float-subnormal fields, and plants
 * under which no pair but (0, 0) passes (m = 3e38: K_max is 0 everywhere in the bounds). */
static void test_unusable_blocks_refused(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert(), x;
    zw_reason why = ZW_REASON_NONE;
    (void)state;
    x = c;
    x.m = 1e-40f; /* a float subnormal (normal as a double) */
    assert_true(x.m > 0.0f && x.m < FLT_MIN);
    assert_int_equal(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_SUBNORMAL);
    x = c;
    x.dk_max = 1.4e-45f;
    assert_int_equal(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_SUBNORMAL);
    x = c;
    x.m = 3e38f;
    assert_int_equal(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, M_3E38_REASON);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    /* over Modbus too (ceilings that admit any m up to 6e38), and the block in force stays */
    rm_init(&rm, &c);
    {
        zw_ceilings k = permissive_ceilings();
        k.m = 3e38f;
        k.plant_tol = 1.0f;
        EXPECT_OK(zw_regmap_set_ceilings(&rm, &k, NULL));
    }
    x = c;
    x.m = 3e38f;
    EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, M_3E38_REASON);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_true(rdf(&rm, ZW_REG_CERT_M) == J1);
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, 0.0f));
    /* -0.0 in a field is stored as +0.0 */
    x = c;
    x.k_min = -0.0f;
    x.differentiator = -0.0f;
    EXPECT_ACCEPTED(keyed_seal(&rm, &x));
    assert_int_equal(rd32(&rm, ZW_REG_CERT_K_MIN), 0u);
    assert_int_equal(rd32(&rm, ZW_REG_CERT_DIFF), 0u);
}

/* ---- persistence: SAVE, and the image checked at power-up ------------------------------- */

typedef struct test_store {
    int fails, calls;
    unsigned char image[ZW_IMAGE_BYTES];
    size_t len;
} test_store;

static bool test_save(void *ctx, const uint_least8_t *image, size_t len)
{
    test_store *st = ctx;
    size_t i;
    st->calls++;
    if (st->fails || len != ZW_IMAGE_BYTES) return false;
    for (i = 0; i < len; ++i) st->image[i] = (unsigned char)image[i];
    st->len = len;
    return true;
}

/* The documented image (regmap_persist.h), built here: magic, format, block + CRC, K, B,
 * the box certificate's 324 words (box NULL: 0), CRC of the 366 words before it (format 3). */
static void ref_image_box(const zw_cert *c, float K, float B, unsigned format, const uint_least16_t *box,
                          unsigned char img[ZW_IMAGE_BYTES])
{
    uint_least16_t w[367];
    size_t i;
    w[0] = 0x5A57u;
    w[1] = 0x4E56u;
    w[2] = (uint_least16_t)format;
    block_words(c, &w[3]);
    words_of(K, &w[38]);
    words_of(B, &w[40]);
    for (i = 0; i < 324; ++i) w[42 + i] = box != NULL ? box[i] : 0u;
    w[366] = ref_crc_words(w, 366);
    assert_int_equal(2u * ZWT_ARRAY_LEN(w), ZW_IMAGE_BYTES);
    for (i = 0; i < 367; ++i) {
        img[2 * i] = (unsigned char)(w[i] >> 8);
        img[2 * i + 1] = (unsigned char)(w[i] & 0xFFu);
    }
}

static void ref_image(const zw_cert *c, float K, float B, unsigned format, unsigned char img[ZW_IMAGE_BYTES])
{
    ref_image_box(c, K, B, format, NULL, img);
}

/* A drive at power-up: the paper's block with sigma 0.8, factory ceilings, gains off. */
static void fresh_drive(zw_regmap *rm)
{
    zw_cert c = paper_cert();
    zw_ceilings k = factory_ceilings();
    c.sigma = 0.8f;
    c.r = 0.999f;
    memset(rm, 0xA5, sizeof *rm);
    EXPECT_OK(zw_regmap_init(rm, &c, NULL));
    EXPECT_OK(zw_regmap_set_ceilings(rm, &k, NULL));
}

static zw_status restore_bytes(zw_regmap *rm, const unsigned char *a, size_t alen,
                               const unsigned char *b, size_t blen, zw_reason *why)
{
    uint_least8_t x[ZW_IMAGE_BYTES + 1], y[ZW_IMAGE_BYTES + 1];
    size_t i;
    for (i = 0; i < alen && i < sizeof x; ++i) x[i] = a[i];
    for (i = 0; i < blen && i < sizeof y; ++i) y[i] = b[i];
    return zw_regmap_restore(rm, a != NULL ? x : NULL, alen, b != NULL ? y : NULL, blen, why);
}

static void test_save_is_separate_and_checked(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    test_store st;
    zw_regmap_storage hook;
    unsigned char want[ZW_IMAGE_BYTES];
    (void)state;
    c.sigma = 0.8f;
    c.r = 0.999f;
    rm_init(&rm, &c);
    memset(&st, 0, sizeof st);
    EXPECT_ACCEPTED(write_pair(&rm, 0.2f, -5e-4f)); /* applied, not saved */
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SAVE), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NO_STORAGE);
    hook.save = test_save;
    hook.ctx = &st;
    zw_regmap_set_storage(&rm, &hook);
    st.fails = 1;
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SAVE), ZW_MB_ILLEGAL_VALUE, ZW_REASON_STORAGE);
    st.fails = 0;
    zw_regmap_set_consent(&rm, false);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SAVE), ZW_MB_ILLEGAL_VALUE, ZW_REASON_NO_CONSENT);
    zw_regmap_set_consent(&rm, true);
    assert_int_equal(st.calls, 1);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SAVE));
    ref_image(&c, 0.2f, -5e-4f, ZW_IMAGE_FORMAT, want);
    assert_int_equal(st.len, ZW_IMAGE_BYTES);
    assert_memory_equal(st.image, want, sizeof want);
    unlock(&rm);
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SAVE), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BAD_COMMAND);
    zw_regmap_set_storage(NULL, &hook); /* no-op */
}

/* Saved settings survive a restart, and a corrupted image never applies anything. */
static void test_restore_checks_everything(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert(), wide;
    unsigned char good[ZW_IMAGE_BYTES], bad[ZW_IMAGE_BYTES], older[ZW_IMAGE_BYTES];
    zw_reason why = ZW_REASON_NONE;
    size_t bit;
    (void)state;
    c.sigma = 0.75f; /* a block other than the power-up one */
    c.r = 0.999f;
    ref_image(&c, 0.2f, -5e-4f, ZW_IMAGE_FORMAT, good);
    /* no image: nothing done */
    fresh_drive(&rm);
    EXPECT_OK(zw_regmap_restore(&rm, NULL, 0, NULL, 0, &why));
    assert_int_equal(rd(&rm, ZW_REG_RESTORE_SOURCE), 0u);
    /* the restart: block and gains back */
    fresh_drive(&rm);
    EXPECT_OK(restore_bytes(&rm, good, sizeof good, NULL, 0, &why));
    assert_int_equal(why, ZW_REASON_NONE);
    assert_int_equal(rd(&rm, ZW_REG_RESTORE_SOURCE), 1u);
    assert_true(rdf(&rm, ZW_REG_CERT_SIGMA) == 0.75f);
    EXPECT_ACTIVE(&rm, 0.2f, -5e-4f);
    assert_int_equal(rd32(&rm, ZW_REG_ACCEPTED), 0u);
    /* truncated, or one byte longer */
    fresh_drive(&rm);
    EXPECT_STATUS(restore_bytes(&rm, good, sizeof good - 1u, NULL, 0, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_IMAGE_FORMAT);
    assert_int_equal(rd(&rm, ZW_REG_RESTORE_REASON), ZW_REASON_IMAGE_FORMAT);
    assert_true(rdf(&rm, ZW_REG_CERT_SIGMA) == 0.8f); /* the power-up block, gains off */
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    /* every single flipped bit */
    for (bit = 0; bit < 8u * sizeof good; ++bit) {
        memcpy(bad, good, sizeof bad);
        bad[bit / 8u] ^= (unsigned char)(1u << (bit % 8u));
        fresh_drive(&rm);
        EXPECT_STATUS(restore_bytes(&rm, bad, sizeof bad, NULL, 0, &why), ZW_ERR_ARG);
        assert_true(why == ZW_REASON_IMAGE_CRC || why == ZW_REASON_IMAGE_FORMAT);
        assert_true(rdf(&rm, ZW_REG_CERT_SIGMA) == 0.8f);
        EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    }
    /* an older format, with a valid CRC */
    ref_image(&c, 0.2f, -5e-4f, ZW_IMAGE_FORMAT - 1u, older);
    fresh_drive(&rm);
    EXPECT_STATUS(restore_bytes(&rm, older, sizeof older, NULL, 0, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_IMAGE_FORMAT);
    /* the newest bad: the last good one */
    memcpy(bad, good, sizeof bad);
    bad[40] ^= 0x10u;
    fresh_drive(&rm);
    EXPECT_OK(restore_bytes(&rm, bad, sizeof bad, good, sizeof good, &why));
    assert_int_equal(rd(&rm, ZW_REG_RESTORE_SOURCE), 2u);
    assert_int_equal(rd(&rm, ZW_REG_RESTORE_REASON), ZW_REASON_IMAGE_CRC);
    EXPECT_ACTIVE(&rm, 0.2f, -5e-4f);
    /* CRCs right, but the block beyond the factory ceilings: refused like a SEAL */
    wide = c;
    wide.sigma = 1.0f;
    ref_image(&wide, 0.2f, -5e-4f, ZW_IMAGE_FORMAT, bad);
    fresh_drive(&rm);
    EXPECT_STATUS(restore_bytes(&rm, bad, sizeof bad, NULL, 0, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_ABOVE_CEILING);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    /* CRCs right, but the block certifies a loop this firmware does not run (one sample
     * of delay; the firmware's is the ideal loop): refused like a SEAL */
    wide = c;
    wide.delay = 1.0f;
    ref_image(&wide, 0.1f, 0.0f, ZW_IMAGE_FORMAT, bad);
    fresh_drive(&rm);
    EXPECT_STATUS(restore_bytes(&rm, bad, sizeof bad, NULL, 0, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_LOOP_MISMATCH);
    assert_true(rdf(&rm, ZW_REG_CERT_DELAY) == 0.0f && rdf(&rm, ZW_REG_CERT_SIGMA) == 0.8f);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    /* CRCs right, block fine, gains not certified (above sigma K_max): block only */
    ref_image(&c, 0.45f, -1.36e-3f, ZW_IMAGE_FORMAT, bad);
    fresh_drive(&rm);
    EXPECT_OK(restore_bytes(&rm, bad, sizeof bad, NULL, 0, &why));
    assert_int_equal(why, ZW_REASON_ABOVE_SIGMA);
    assert_int_equal(rd(&rm, ZW_REG_RESTORE_SOURCE), 1u);
    assert_true(rdf(&rm, ZW_REG_CERT_SIGMA) == 0.75f);
    EXPECT_ACTIVE(&rm, 0.0f, 0.0f);
    EXPECT_STATUS(zw_regmap_restore(NULL, NULL, 0, NULL, 0, &why), ZW_ERR_NULL);
}

/* CDAB: every two-register value low word first on the wire; CRC and MAC over the
 * canonical (ABCD) words. */
static void test_word_order_cdab(void **state)
{
    zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t w[4], ref[4], block[35], swapped[35];
    size_t i;
    (void)state;
    rm_init(&rm, &c);
    assert_int_equal(rd(&rm, ZW_REG_WORD_ORDER), 0u);
    zw_regmap_set_word_order(&rm, 7u); /* not an order: no-op */
    zw_regmap_set_word_order(&rm, ZW_WORD_ORDER_CDAB);
    assert_int_equal(rd(&rm, ZW_REG_WORD_ORDER), 1u);
    assert_int_equal(rd(&rm, ZW_REG_MAGIC), 0x5A57u); /* one-word registers as they are */
    words_of(0.25f, &ref[0]);
    words_of(-5e-4f, &ref[2]);
    w[0] = ref[1], w[1] = ref[0], w[2] = ref[3], w[3] = ref[2];
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_K, 4, w));
    {
        float K = 1.0f, B = 1.0f;
        EXPECT_OK(zw_regmap_active_gains(&rm, &K, &B));
        assert_true(K == 0.25f && B == -5e-4f);
    }
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_K, 4, w, NULL), ZW_MB_OK);
    assert_true(w[0] == ref[1] && w[1] == ref[0] && w[2] == ref[3] && w[3] == ref[2]);
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_ACCEPTED, 2, w, NULL), ZW_MB_OK);
    assert_true(w[0] == 1u && w[1] == 0u); /* the counter 1, low word first */
    /* commissioning: floats swapped on the wire, CRC over the canonical words */
    c.sigma = 0.7f;
    block_words(&c, block);
    for (i = 0; i < 34; i += 2) {
        swapped[i] = block[i + 1];
        swapped[i + 1] = block[i];
    }
    swapped[34] = block[34];
    unlock(&rm);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, 35, swapped));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SEAL));
    assert_int_equal(zw_regmap_read(&rm, ZW_REG_CERT_SIGMA, 2, w, NULL), ZW_MB_OK);
    words_of(0.7f, ref);
    assert_true(w[0] == ref[1] && w[1] == ref[0]);
    assert_int_equal(rd(&rm, ZW_REG_CERT_CRC), block[34]);
    /* a read that starts inside a value gets its second word on the wire */
    assert_int_equal(rd(&rm, ZW_REG_CERT_SIGMA + 1), ref[0]);
}

/* ---- plant ranges (map version 4) ----------------------------------------------------------- */

/* The paper's drive with the inertia uncertain over [2e-5, 1.5e-4]: at B = 1e-3, K_max has an
 * interior minimum in m (docs/box.md), so the corners overstate the box's K_max. */
#define VALLEY_M_LO 2.0e-5f
#define VALLEY_M_HI 1.5e-4f
#define VALLEY_B 1.0e-3f
#define VALLEY_GRID 401

static zw_loop_workspace g_box_ws;

/* K_max(B) of the ideal loop at plant (m, B_SHORT) by the point function (certified, never
 * above the true one). */
static double point_k_max(float m, float B)
{
    zw_device_loop dl;
    zw_device_loop_spec spec;
    zw_real k = 0;
    memset(&spec, 0, sizeof spec);
    EXPECT_OK(zw_device_loop_init(&dl, (zw_real)m, (zw_real)B_SHORT, (zw_real)T_20MS, &spec));
    EXPECT_OK(zw_device_loop_k_max(&dl, &g_box_ws, (zw_real)B, &k));
    return (double)k;
}

/* (K, B) at plant (m, B_SHORT) by the point check: 1 stable, -1 surely unstable, 0 marginal. */
static int point_verdict(float m, float K, float B)
{
    zw_device_loop dl;
    zw_device_loop_spec spec;
    zw_loop_verdict v;
    memset(&spec, 0, sizeof spec);
    EXPECT_OK(zw_device_loop_init(&dl, (zw_real)m, (zw_real)B_SHORT, (zw_real)T_20MS, &spec));
    EXPECT_OK(zw_device_loop_check(&dl, &g_box_ws, (zw_real)K, (zw_real)B, &v));
    return v.stable ? 1 : (v.marginal ? 0 : -1);
}

/* The least point K_max(B) over the valley's m range (a grid, refined around its least
 * point), and where. */
static double valley_min(float B, float *m_at)
{
    double least = 0;
    float lo = VALLEY_M_LO, hi = VALLEY_M_HI;
    int pass, i;
    for (pass = 0; pass < 2; ++pass) {
        float best_m = lo, step = (hi - lo) / (float)(VALLEY_GRID - 1);
        least = point_k_max(lo, B);
        for (i = 1; i < VALLEY_GRID; ++i) {
            const float m = (i == VALLEY_GRID - 1) ? hi : lo + step * (float)i;
            const double k = point_k_max(m, B);
            if (k < least) {
                least = k;
                best_m = m;
            }
        }
        *m_at = best_m;
        lo = best_m - step > VALLEY_M_LO ? best_m - step : VALLEY_M_LO;
        hi = best_m + step < VALLEY_M_HI ? best_m + step : VALLEY_M_HI;
    }
    return least;
}

/* A ranged block over the valley: sigma 1, r 1 (required with ranges), wide bounds. */
static zw_cert valley_cert(void)
{
    zw_cert c = paper_cert();
    c.m = VALLEY_M_LO;
    c.m_hi = VALLEY_M_HI;
    c.b = B_SHORT;
    c.b_hi = B_SHORT;
    c.k_max = 100.0f;
    c.dk_max = 100.0f;
    return c;
}

/* A pair stable at the block's nominal plant (the lower ends) and at both corners but unstable
 * at an interior plant is refused; one certified over the box is accepted; the live registers
 * are box bounds. */
static void test_box_refuses_interior_instability(void **state)
{
    static zw_regmap rm, pt;
    zw_cert c = valley_cert(), point = valley_cert();
    float m_at = 0.0f, K_bad, K_good, K_cert;
    const double least = valley_min(VALLEY_B, &m_at);
    const double corner_lo = point_k_max(VALLEY_M_LO, VALLEY_B), corner_hi = point_k_max(VALLEY_M_HI, VALLEY_B);
    (void)state;
    /* the valley: its least point well below both corners */
    EXPECT_TRUE_MSG(m_at > VALLEY_M_LO && m_at < VALLEY_M_HI && least < 0.98 * corner_lo &&
                        least < 0.98 * corner_hi,
                    "least %g at %g, corners %g %g", least, (double)m_at, (double)corner_lo,
                    (double)corner_hi);
    K_bad = (float)((least + (corner_lo < corner_hi ? corner_lo : corner_hi)) / 2);
    assert_int_equal(point_verdict(VALLEY_M_LO, K_bad, VALLEY_B), 1);
    assert_int_equal(point_verdict(VALLEY_M_HI, K_bad, VALLEY_B), 1);
    assert_int_equal(point_verdict(m_at, K_bad, VALLEY_B), -1);
    /* the point block (the nominal plant alone) accepts it */
    point.m_hi = 0.0f;
    point.b_hi = 0.0f;
    rm_init(&pt, &point);
    EXPECT_ACCEPTED(write_pair(&pt, K_bad, VALLEY_B));
    /* the box refuses it, changing nothing (EXPECT_REFUSED compares the whole map) */
    rm_init(&rm, &c);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 1u);
    EXPECT_REFUSED(&rm, write_pair(&rm, K_bad, VALLEY_B), ZW_MB_ILLEGAL_VALUE, ZW_REASON_UNSTABLE);
    /* 0.9 of the least point value is certified over the box */
    K_good = (float)(0.9 * least);
    EXPECT_ACCEPTED(write_pair(&rm, K_good, VALLEY_B));
    {
        float K = 0.0f, B = 0.0f;
        EXPECT_OK(zw_regmap_active_gains(&rm, &K, &B));
        assert_true(K == K_good && B == VALLEY_B);
    }
    /* live: K_MAX a lower bound of the box's infimum, K_CERT below it and itself accepted,
     * no box form of the B range and the radius */
    EXPECT_TRUE_MSG((double)rdf(&rm, ZW_REG_LIVE_K_MAX) <= least &&
                        (double)rdf(&rm, ZW_REG_LIVE_K_MAX) >= 0.95 * least,
                    "K_MAX %g, least point %g", (double)rdf(&rm, ZW_REG_LIVE_K_MAX), least);
    K_cert = rdf(&rm, ZW_REG_LIVE_K_CERT);
    assert_true(K_cert > 0.0f && K_cert <= rdf(&rm, ZW_REG_LIVE_K_MAX));
    assert_true(isnan(rdf(&rm, ZW_REG_LIVE_B_LO)) && isnan(rdf(&rm, ZW_REG_LIVE_B_HI)) &&
                isnan(rdf(&rm, ZW_REG_LIVE_RHO)));
    EXPECT_ACCEPTED(write_K(&rm, K_cert));
    /* K_MMAX: certified for the box, so not above any plant's own K_mmax */
    {
        const float m_probe[3] = {VALLEY_M_LO, m_at, VALLEY_M_HI};
        const float kmm = rdf(&rm, ZW_REG_LIVE_K_MMAX);
        int i;
        assert_true(kmm > 0.0f);
        for (i = 0; i < 3; ++i) {
            zw_device_loop dl;
            zw_device_loop_spec spec;
            zw_device_loop_extremes e;
            memset(&spec, 0, sizeof spec);
            EXPECT_OK(zw_device_loop_init(&dl, (zw_real)m_probe[i], (zw_real)B_SHORT, (zw_real)T_20MS, &spec));
            EXPECT_OK(zw_device_loop_extremes_compute(&dl, &g_box_ws, &e));
            EXPECT_TRUE_MSG((zw_real)kmm <= e.K_mmax, "K_MMAX %g above %g at m %g", (double)kmm,
                            (double)e.K_mmax, (double)m_probe[i]);
        }
        /* a pair at the B of K_MMAX, just below it, is certified over the box */
        EXPECT_ACCEPTED(write_pair(&rm, 0.0f, 0.0f));
        EXPECT_ACCEPTED(write_pair(&rm, 0.98f * kmm, rdf(&rm, ZW_REG_LIVE_B_AT_KMMAX)));
        assert_int_equal(point_verdict(m_at, 0.98f * kmm, rdf(&rm, ZW_REG_LIVE_B_AT_KMMAX)), 1);
    }
}

/* sigma over the box: K stable at every plant but above sigma K_max at some is ABOVE_SIGMA;
 * a K unstable at an interior plant is UNSTABLE, whatever sigma. */
static void test_box_sigma_rule(void **state)
{
    static zw_regmap rm;
    zw_cert c = valley_cert();
    float m_at = 0.0f;
    const double least = valley_min(VALLEY_B, &m_at);
    (void)state;
    c.sigma = 0.5f;
    rm_init(&rm, &c);
    EXPECT_REFUSED(&rm, write_pair(&rm, (float)(0.7 * least), VALLEY_B), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_ABOVE_SIGMA);
    EXPECT_REFUSED(&rm, write_pair(&rm, (float)(1.05 * least), VALLEY_B), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_UNSTABLE);
    assert_int_equal(point_verdict(m_at, (float)(1.05 * least), VALLEY_B), -1);
    EXPECT_ACCEPTED(write_pair(&rm, (float)(0.45 * least), VALLEY_B));
    assert_true(rdf(&rm, ZW_REG_LIVE_K_CERT) <= 0.5f * rdf(&rm, ZW_REG_LIVE_K_MAX));
}

/* A K just below the box's infimum cannot be proven within the budget: refused, named,
 * changing nothing (never accepted without a proof). */
static void test_box_budget_refuses(void **state)
{
    static zw_regmap rm;
    zw_cert c = valley_cert();
    float m_at = 0.0f, K;
    const double least = valley_min(VALLEY_B, &m_at);
    (void)state;
    rm_init(&rm, &c);
    K = (float)(least * (1.0 - 1e-4));
    assert_int_equal(point_verdict(m_at, K, VALLEY_B), 1);
    EXPECT_REFUSED(&rm, write_pair(&rm, K, VALLEY_B), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BOX_BUDGET);
    assert_int_equal(rd(&rm, ZW_REG_LAST_REASON), ZW_REASON_BOX_BUDGET);
}

/* The valley block's certificate over B in [0, 2 VALLEY_B], built in this precision. */
static zw_box_cert valley_box_cert(void)
{
    static zw_box_loop_cell cells[ZW_BOX_CERT_STACK];
    static zw_box_loop_scratch scratch;
    zw_box_cert bc;
    zw_box_cert_report r;
    zw_box_loop_work w;
    zw_device_loop_spec spec;
    zw_plant_box box;
    memset(&spec, 0, sizeof spec);
    memset(&box, 0, sizeof box);
    box.m_lo = (zw_real)VALLEY_M_LO;
    box.m_hi = (zw_real)VALLEY_M_HI;
    box.b_lo = (zw_real)B_SHORT;
    box.b_hi = (zw_real)B_SHORT;
    box.T = (zw_real)T_20MS;
    EXPECT_OK(zw_box_loop_work_init(&w, cells, ZW_BOX_CERT_STACK, &scratch));
    EXPECT_OK(zw_box_cert_build(&box, &spec, &g_box_ws, 0.0f, 2.0f * VALLEY_B, 8u, 256u, R(1.0e-3), &w, &bc, &r));
    assert_int_equal(r.failed_step, ZW_BOX_CERT_MAX_STEPS);
    return bc;
}

/* Power-up with a certificate: writes are lookups in its staircase (accepted up to the
 * level, ABOVE_SIGMA above it, OUTSIDE_CERT beyond its B range), the live registers come
 * from it, and a damaged one or one for a point block refuses the block. */
static void test_box_certificate(void **state)
{
    static zw_regmap rm;
    zw_cert c = valley_cert(), point = valley_cert();
    zw_box_cert bc = valley_box_cert(), bad;
    zw_reason why = ZW_REASON_NONE;
    float level = 0.0f, m_at = 0.0f;
    bool inside = false;
    const double least = valley_min(VALLEY_B, &m_at);
    (void)state;
    zw_box_cert_level(&bc, VALLEY_B, &level, &inside);
    assert_true(inside && level > 0.0f && (double)level <= least);
    c.sigma = 0.8f;
    memset(&rm, 0xA5, sizeof rm);
    EXPECT_OK(zw_regmap_init_box(&rm, &c, &bc, &why));
    assert_string_equal(zw_reason_name(why), "ZW_REASON_NONE");
    assert_int_equal(rm.box_cert_valid, 1);
    memset(&g_auth, 0, sizeof g_auth);
    allow_commissioning(&rm);
    EXPECT_ACCEPTED(write_pair(&rm, 0.79f * level, VALLEY_B));
    /* live: the level, sigma times it, the run of steps certified at K / sigma */
    assert_true(rdf(&rm, ZW_REG_LIVE_K_MAX) == level);
    assert_true(rdf(&rm, ZW_REG_LIVE_K_CERT) <= 0.8f * level && rdf(&rm, ZW_REG_LIVE_K_CERT) > 0.7f * level);
    assert_true(rdf(&rm, ZW_REG_LIVE_B_LO) <= VALLEY_B && rdf(&rm, ZW_REG_LIVE_B_HI) >= VALLEY_B);
    {
        float K_mm = 0.0f, B_mm = 0.0f;
        zw_box_cert_k_mmax(&bc, &K_mm, &B_mm);
        assert_true(rdf(&rm, ZW_REG_LIVE_K_MMAX) == K_mm && rdf(&rm, ZW_REG_LIVE_B_AT_KMMAX) == B_mm);
    }
    EXPECT_ACCEPTED(write_K(&rm, rdf(&rm, ZW_REG_LIVE_K_CERT)));
    EXPECT_REFUSED(&rm, write_K(&rm, 0.81f * level), ZW_MB_ILLEGAL_VALUE, ZW_REASON_ABOVE_SIGMA);
    EXPECT_ACCEPTED(write_pair(&rm, 0.0f, 0.0f));
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.01f * level, -1.0e-4f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_OUTSIDE_CERT);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.01f * level, 2.0f * VALLEY_B + 1.0e-4f), ZW_MB_ILLEGAL_VALUE,
                   ZW_REASON_OUTSIDE_CERT);
    /* every accepted K at B is stable at the interior plant the point block misses */
    assert_int_equal(point_verdict(m_at, 0.79f * level, VALLEY_B), 1);
    /* a block refused at SEAL after its box was set up (no usable pair: K >= 50) leaves the
     * one in force with its certificate: writes are still lookups */
    {
        zw_cert only_off = c;
        only_off.k_min = 50.0f;
        only_off.dk_max = 50.0f;
        EXPECT_TRUE_MSG(seal_block(&rm, &only_off).why == ZW_REASON_ONLY_OFF, "%s",
                        zw_reason_name((zw_reason)rd(&rm, ZW_REG_LAST_REASON)));
        EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
        assert_int_equal(rm.box_cert_valid, 1);
        EXPECT_ACCEPTED(write_pair(&rm, 0.79f * level, VALLEY_B));
        assert_true(rdf(&rm, ZW_REG_LIVE_K_MAX) == level);
    }
    /* a level raised above what its leaves prove: the block is refused, the drive unsealed */
    bad = bc;
    bad.K[3] = 1.5f * bad.K[3];
    memset(&rm, 0xA5, sizeof rm);
    EXPECT_STATUS(zw_regmap_init_box(&rm, &c, &bad, &why), ZW_ERR_ARG);
    assert_string_equal(zw_reason_name(why), "ZW_REASON_BOX_CERT");
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
    assert_int_equal(rm.box_cert_valid, 0);
    /* a certificate with a point block */
    point.m_hi = 0.0f;
    point.b_hi = 0.0f;
    EXPECT_STATUS(zw_regmap_init_box(&rm, &point, &bc, &why), ZW_ERR_ARG);
    assert_string_equal(zw_reason_name(why), "ZW_REASON_BOX_CERT");
    /* without one the ranged block runs the search, as before */
    EXPECT_OK(zw_regmap_init_box(&rm, &c, NULL, &why));
    assert_int_equal(rm.box_cert_valid, 0);
}

/* A box certificate as the window's words, from the documented layout (regmap.h): n_steps,
 * n_nodes, 17 breakpoints and 16 levels (host bit casts, high word first), 256 node words. */
static void ref_box_cert_words(const zw_box_cert *bc, uint_least16_t w[324])
{
    size_t i;
    w[0] = bc->n_steps;
    w[1] = bc->n_nodes;
    for (i = 0; i < 17; ++i) words_of(bc->B[i], &w[2 + 2 * i]);
    for (i = 0; i < 16; ++i) words_of(bc->K[i], &w[36 + 2 * i]);
    for (i = 0; i < 256; ++i) w[68 + i] = bc->nodes[i];
}

static void read_window(zw_regmap *rm, uint_least16_t addr, unsigned n, uint_least16_t *w)
{
    unsigned done;
    for (done = 0; done < n; done += 125u)
        EXPECT_ACCEPTED(read_words(rm, (uint_least16_t)(addr + done),
                                   (uint_least16_t)(n - done < 125u ? n - done : 125u), w + done));
}

/* Map version 5: a ranged block commissioned over Modbus with its certificate (the window
 * at ZW_REG_BOX_CERT, under the MAC), verified at SEAL; writes are then lookups.  Forged,
 * damaged, non-canonical or misplaced certificates are refused and change nothing; the
 * certificate is staged by UNLOCK2, read back, saved in the image and verified again at
 * restore. */
static void test_box_certificate_window(void **state)
{
    static zw_regmap rm, fresh;
    zw_cert c = valley_cert(), point = valley_cert();
    zw_box_cert bc = valley_box_cert();
    uint_least16_t block[35], box[324], bad[324], back[324], zeros[324];
    float level = 0.0f;
    bool inside = false;
    test_store st;
    zw_regmap_storage storage;
    unsigned i;
    (void)state;
    memset(zeros, 0, sizeof zeros);
    zw_box_cert_level(&bc, VALLEY_B, &level, &inside);
    assert_true(inside && level > 0.0f);
    ref_box_cert_words(&bc, box);
    rm_init(&rm, &c); /* the ranged block without a certificate: the search */
    g_auth.strict = 1;
    memcpy(g_auth.key, k_key, sizeof k_key);
    assert_int_equal(rd(&rm, ZW_REG_VERSION), 5u);
    assert_int_equal(rd(&rm, ZW_REG_PRECISION), (unsigned)sizeof(zw_real));
    read_window(&rm, ZW_REG_BOX_CERT, 324, back);
    assert_memory_equal(back, zeros, sizeof back);
    /* the window is locked outside commissioning */
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_BOX_CERT, 2, box), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_LOCKED);
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_BOX_CERT_B + 1u, 2, box), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_HALF_FLOAT);
    c.sigma = 0.8f;
    block_words(&c, block);
    /* a level raised above what its leaves prove, under a valid MAC: refused, nothing changes */
    memcpy(bad, box, sizeof bad);
    words_of(1.5f * bc.K[3], &bad[36 + 2 * 3]);
    unlock(&rm);
    EXPECT_OUTCOME(client_seal_box(&rm, block, bad, k_key, NULL, NULL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BOX_CERT);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    assert_int_equal(rm.box_cert_valid, 0);
    /* a NaN payload in the padding (decodes to the quiet NaN: not what was MACed) */
    memcpy(bad, box, sizeof bad);
    bad[36 + 2 * 15] = 0x7F80u;
    bad[36 + 2 * 15 + 1] = 0x0001u;
    EXPECT_OUTCOME(client_seal_box(&rm, block, bad, k_key, NULL, NULL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BOX_CERT);
    /* the certificate changed after the MAC was computed over the good one */
    EXPECT_OUTCOME(client_seal_box(&rm, block, box, k_key, NULL, NULL), ZW_MB_OK, ZW_REASON_NONE);
    assert_int_equal(rm.box_cert_valid, 1);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 0u);
    read_window(&rm, ZW_REG_BOX_CERT, 324, back);
    assert_memory_equal(back, box, sizeof back); /* in force: exactly the words sent */
    allow_commissioning(&rm);
    /* writes are lookups in its staircase */
    EXPECT_ACCEPTED(write_pair(&rm, 0.79f * level, VALLEY_B));
    assert_true(rdf(&rm, ZW_REG_LIVE_K_MAX) == level);
    EXPECT_REFUSED(&rm, write_K(&rm, 0.81f * level), ZW_MB_ILLEGAL_VALUE, ZW_REASON_ABOVE_SIGMA);
    EXPECT_REFUSED(&rm, write_pair(&rm, 0.01f * level, -1.0e-4f), ZW_MB_ILLEGAL_VALUE, ZW_REASON_OUTSIDE_CERT);
    /* UNLOCK2 stages the certificate in force; a keyless change of it fails the MAC */
    unlock(&rm);
    read_window(&rm, ZW_REG_BOX_CERT, 324, back);
    assert_memory_equal(back, box, sizeof back);
    {
        uint_least16_t nonce[8], macw[16];
        unsigned char msg[ZW_AUTH_MSG_BYTES], mac[32];
        assert_int_equal(zw_regmap_read(&rm, ZW_REG_NONCE, 8, nonce, NULL), ZW_MB_OK);
        ref_auth_message_box(nonce, block, box, msg);
        test_mac(k_key, msg, sizeof msg, mac);
        for (i = 0; i < 16; ++i) macw[i] = (uint_least16_t)(((unsigned)mac[2 * i] << 8) | mac[2 * i + 1]);
        EXPECT_ACCEPTED(write_words(&rm, ZW_REG_MAC, 16, macw));
        memcpy(bad, box, sizeof bad);
        bad[68 + 5] ^= 0x0010u; /* one node changed after the MAC */
        EXPECT_ACCEPTED(write_window(&rm, ZW_REG_BOX_CERT, 324, bad));
        EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_AUTH);
    }
    /* a certificate with a point block */
    point.m_hi = 0.0f;
    point.b_hi = 0.0f;
    point.sigma = 0.8f;
    block_words(&point, block);
    EXPECT_OUTCOME(client_seal_box(&rm, block, box, k_key, NULL, NULL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_BOX_CERT);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_int_equal(rm.box_cert_valid, 1); /* the block in force kept its own */
    EXPECT_ACCEPTED(write_pair(&rm, 0.79f * level, VALLEY_B));
    /* SAVE carries it; restore verifies it again */
    memset(&st, 0, sizeof st);
    storage.save = test_save;
    storage.ctx = &st;
    zw_regmap_set_storage(&rm, &storage);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SAVE));
    {
        unsigned char want[ZW_IMAGE_BYTES];
        ref_image_box(&c, 0.79f * level, VALLEY_B, ZW_IMAGE_FORMAT, box, want);
        assert_memory_equal(st.image, want, sizeof want);
        memset(&fresh, 0xA5, sizeof fresh);
        EXPECT_OK(zw_regmap_init(&fresh, NULL, NULL));
        EXPECT_OK(restore_bytes(&fresh, want, sizeof want, NULL, 0, NULL));
        assert_int_equal(fresh.box_cert_valid, 1);
        read_window(&fresh, ZW_REG_BOX_CERT, 324, back);
        assert_memory_equal(back, box, sizeof back);
        EXPECT_ACTIVE(&fresh, 0.79f * level, VALLEY_B);
        /* an image whose certificate claims more than it proves (its CRC made right) */
        memcpy(bad, box, sizeof bad);
        words_of(1.5f * bc.K[3], &bad[36 + 2 * 3]);
        ref_image_box(&c, 0.79f * level, VALLEY_B, ZW_IMAGE_FORMAT, bad, want);
        memset(&fresh, 0xA5, sizeof fresh);
        EXPECT_OK(zw_regmap_init(&fresh, NULL, NULL));
        EXPECT_STATUS(restore_bytes(&fresh, want, sizeof want, NULL, 0, NULL), ZW_ERR_ARG);
        assert_int_equal(rd(&fresh, ZW_REG_RESTORE_REASON), ZW_REASON_BOX_CERT);
        assert_int_equal(rd(&fresh, ZW_REG_SEALED), 0u);
    }
}

/* Fuzzed certificates over Modbus, every one under a valid MAC: random words, bits and nodes
 * changed.  Each is refused (BOX_CERT) and changes nothing, or it verifies; then every level
 * it certifies must hold at the box's least point K_max (the valley's interior plant). */
static void test_box_certificate_fuzz(void **state)
{
    static zw_regmap rm;
    zw_cert c = valley_cert();
    zw_box_cert bc = valley_box_cert();
    uint_least16_t block[35], box[324], bad[324];
    uint32_t seed = 0x2545F491u;
    unsigned trial, refused = 0u, accepted = 0u;
    (void)state;
    ref_box_cert_words(&bc, box);
    c.sigma = 0.8f;
    rm_init(&rm, &c);
    g_auth.strict = 1;
    memcpy(g_auth.key, k_key, sizeof k_key);
    block_words(&c, block);
    unlock(&rm);
    for (trial = 0; trial < 60u; ++trial) {
        unsigned k, n = 1u + trial % 4u;
        outcome o;
        memcpy(bad, box, sizeof bad);
        for (k = 0; k < n; ++k) {
            seed = seed * 1664525u + 1013904223u;
            {
                const unsigned at = (seed >> 8) % 324u, bit = (seed >> 20) % 16u;
                bad[at] = (uint_least16_t)(bad[at] ^ (1u << bit));
            }
        }
        o = client_seal_box(&rm, block, bad, k_key, NULL, NULL);
        if (o.exc == ZW_MB_OK) {
            unsigned s;
            float m_at = 0.0f;
            ++accepted;
            assert_int_equal(rm.box_cert_valid, 1);
            for (s = 0; s < rm.box_cert.n_steps; ++s) {
                const float lo = rm.box_cert.B[s], hi = rm.box_cert.B[s + 1u];
                const float mid = 0.5f * (lo + hi);
                /* no level above the box's least K_max at the step's ends and middle */
                assert_true((double)rm.box_cert.K[s] <= valley_min(lo, &m_at));
                assert_true((double)rm.box_cert.K[s] <= valley_min(hi, &m_at));
                assert_true((double)rm.box_cert.K[s] <= valley_min(mid, &m_at));
            }
            unlock(&rm);
        } else {
            ++refused;
            assert_int_equal(o.why, ZW_REASON_BOX_CERT);
            assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
        }
    }
    assert_true(refused > 30u); /* most changes break the proof */
    print_message("fuzzed certificates: %u refused, %u accepted (each sound)\n", refused, accepted);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
}

/* SEAL's rules for the ranges, and the ceilings applied to each end. */
static void test_box_block_validation(void **state)
{
    static zw_regmap rm;
    zw_cert c = valley_cert(), x;
    zw_ceilings k = factory_ceilings();
    zw_reason why = ZW_REASON_NONE;
    (void)state;
    x = c;
    x.m_hi = 0.5f * x.m; /* below the lower end */
    EXPECT_STATUS(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_BAD_POLICY);
    x = c;
    x.b_hi = 0.5f * x.b;
    EXPECT_STATUS(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_BAD_POLICY);
    x = c;
    x.m_hi = 0.0f; /* half the shorthand: m_hi 0 with b_hi set is no plant */
    EXPECT_STATUS(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_BAD_POLICY);
    x = c;
    x.m_hi = (float)INFINITY;
    EXPECT_STATUS(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_BAD_POLICY);
    x = c;
    x.r = 0.999f; /* no box form of the radius rule */
    EXPECT_STATUS(zw_regmap_init(&rm, &x, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_BOX_RADIUS);
    x.m_hi = x.m; /* the same r on a point block (explicit ends) is fine */
    x.b_hi = x.b;
    EXPECT_OK(zw_regmap_init(&rm, &x, &why));
    /* ceilings: each end within plant_tol of the nameplate (r_max 1 allows ranges) */
    k.r_max = 1.0f;
    x = paper_cert();
    x.sigma = 0.8f;
    rm_init(&rm, &x);
    EXPECT_OK(zw_regmap_set_ceilings(&rm, &k, &why));
    x.m = 0.97f * J1;
    x.m_hi = 1.04f * J1;
    x.b_hi = 1.04f * B_SHORT;
    EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_OK, ZW_REASON_NONE);
    assert_true(rdf(&rm, ZW_REG_CERT_M_HI) == 1.04f * J1);
    x.m_hi = 1.06f * J1; /* the upper end beyond the 5 % tolerance */
    EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, ZW_REASON_PLANT_MISMATCH);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    x.m_hi = 1.04f * J1;
    x.b_hi = 1.06f * B_SHORT;
    EXPECT_OUTCOME(keyed_seal(&rm, &x), ZW_MB_ILLEGAL_VALUE, ZW_REASON_PLANT_MISMATCH);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_true(rdf(&rm, ZW_REG_CERT_B_HI) == 1.04f * B_SHORT); /* the sealed block stays */
    /* a ranged block in force, then a narrower nameplate tolerance unseals it */
    k.plant_tol = 0.035f;
    EXPECT_STATUS(zw_regmap_set_ceilings(&rm, &k, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_PLANT_MISMATCH);
    assert_int_equal(rd(&rm, ZW_REG_SEALED), 0u);
}

/* A version-3 client (30-word block, CRC at 0x005E, commands at 0x0060) cannot unlock, stage
 * its CRC or seal: every such write splits a version-4 float. */
static void test_version3_client_refused(void **state)
{
    static zw_regmap rm;
    zw_cert c = paper_cert();
    uint_least16_t v3[35], cmd;
    (void)state;
    rm_init(&rm, &c);
    c.sigma = 0.6f;
    block_words(&c, v3); /* the first 30 words are the version-3 block */
    v3[30] = ref_crc_words(v3, 30);
    cmd = ZW_CMD_UNLOCK1;
    EXPECT_REFUSED(&rm, write_words(&rm, 0x0060, 1, &cmd), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_HALF_FLOAT);
    unlock(&rm); /* even when a version-4 tool unlocked for it: */
    EXPECT_REFUSED(&rm, write_words(&rm, ZW_REG_CERT_M, 31, v3), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_HALF_FLOAT);
    EXPECT_ACCEPTED(write_words(&rm, ZW_REG_CERT_M, 30, v3));
    EXPECT_REFUSED(&rm, write_words(&rm, 0x005E, 1, &v3[30]), ZW_MB_ILLEGAL_ADDRESS,
                   ZW_REASON_HALF_FLOAT);
    cmd = ZW_CMD_SEAL;
    EXPECT_REFUSED(&rm, write_words(&rm, 0x0060, 1, &cmd), ZW_MB_ILLEGAL_ADDRESS, ZW_REASON_HALF_FLOAT);
    assert_int_equal(rd(&rm, ZW_REG_MODE), 1u);
    /* a SEAL by the version-4 tool of what the old client left fails the CRC */
    EXPECT_REFUSED(&rm, command(&rm, ZW_CMD_SEAL), ZW_MB_ILLEGAL_VALUE, ZW_REASON_CRC);
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_ABORT));
    assert_true(rdf(&rm, ZW_REG_CERT_SIGMA) == 1.0f); /* the block in force is the old one */
}

static bool g_saved_ok;
static unsigned char g_saved[ZW_IMAGE_BYTES];
static bool save_copy(void *ctx, const uint_least8_t *image, size_t len)
{
    size_t i;
    (void)ctx;
    g_saved_ok = len == ZW_IMAGE_BYTES;
    for (i = 0; i < len && i < ZW_IMAGE_BYTES; ++i) g_saved[i] = (unsigned char)image[i];
    return true;
}

/* A ranged block and its gains survive SAVE and restore; a format-1 image is refused. */
static void test_box_persistence(void **state)
{
    static zw_regmap rm, back;
    zw_cert c = valley_cert();
    zw_regmap_storage storage;
    uint_least8_t img[ZW_IMAGE_BYTES], old[78];
    uint_least16_t w[39];
    float m_at = 0.0f, K = 0.0f, B = 0.0f;
    const double least = valley_min(VALLEY_B, &m_at);
    zw_reason why = ZW_REASON_NONE;
    size_t i;
    (void)state;
    rm_init(&rm, &c);
    storage.save = save_copy;
    storage.ctx = NULL;
    zw_regmap_set_storage(&rm, &storage);
    zw_regmap_set_consent(&rm, true);
    EXPECT_ACCEPTED(write_pair(&rm, (float)(0.8 * least), VALLEY_B));
    EXPECT_ACCEPTED(command(&rm, ZW_CMD_SAVE));
    assert_true(g_saved_ok);
    /* the image as documented: block words from the map's registers */
    assert_true(zw_regmap_image(&rm, img));
    for (i = 0; i < ZW_IMAGE_BYTES; ++i) assert_int_equal(img[i], g_saved[i]);
    for (i = 0; i <= ZW_CERT_WORDS; ++i)
        assert_int_equal(((unsigned)img[6 + 2 * i] << 8) | img[7 + 2 * i],
                         rd(&rm, (uint_least16_t)(ZW_REG_CERT_M + i)));
    memset(&back, 0xA5, sizeof back);
    EXPECT_OK(zw_regmap_init(&back, NULL, &why));
    EXPECT_OK(zw_regmap_restore(&back, img, sizeof img, NULL, 0, &why));
    assert_int_equal(why, ZW_REASON_NONE);
    assert_int_equal(rd(&back, ZW_REG_RESTORE_SOURCE), 1u);
    for (i = 0; i <= ZW_CERT_WORDS; ++i)
        assert_int_equal(rd(&back, (uint_least16_t)(ZW_REG_CERT_M + i)),
                         rd(&rm, (uint_least16_t)(ZW_REG_CERT_M + i)));
    EXPECT_OK(zw_regmap_active_gains(&back, &K, &B));
    assert_true(K == (float)(0.8 * least) && B == VALLEY_B);
    assert_true(rdf(&back, ZW_REG_LIVE_K_MAX) == rdf(&rm, ZW_REG_LIVE_K_MAX));
    /* a format-1 image (map version 3: 30 block words, 78 bytes), valid in its own format:
     * refused by name, not migrated */
    w[0] = 0x5A57u;
    w[1] = 0x4E56u;
    w[2] = 1u;
    block_words(&c, &w[3]); /* writes 35 words: the 30 of version 3 are the first */
    w[33] = ref_crc_words(&w[3], 30);
    words_of(0.1f, &w[34]);
    words_of(0.0f, &w[36]);
    w[38] = ref_crc_words(w, 38);
    for (i = 0; i < 39; ++i) {
        old[2 * i] = (uint_least8_t)(w[i] >> 8);
        old[2 * i + 1] = (uint_least8_t)(w[i] & 0xFFu);
    }
    memset(&back, 0xA5, sizeof back);
    EXPECT_OK(zw_regmap_init(&back, NULL, &why));
    EXPECT_STATUS(zw_regmap_restore(&back, old, sizeof old, NULL, 0, &why), ZW_ERR_ARG);
    assert_int_equal(why, ZW_REASON_IMAGE_FORMAT);
    assert_int_equal(rd(&back, ZW_REG_SEALED), 0u);
    assert_int_equal(rd(&back, ZW_REG_RESTORE_REASON), ZW_REASON_IMAGE_FORMAT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_words_known),
        cmocka_unit_test(test_float_words_round_trip),
        cmocka_unit_test(test_crc),
        cmocka_unit_test(test_cert_codec),
        cmocka_unit_test(test_init_sealed),
        cmocka_unit_test(test_loop_block_refusals),
        cmocka_unit_test(test_loop_block_certifies_the_real_loop),
        cmocka_unit_test(test_init_unsealed),
        cmocka_unit_test(test_init_bad_policy),
        cmocka_unit_test(test_access_map_reads),
        cmocka_unit_test(test_access_map_writes),
        cmocka_unit_test(test_pair_atomicity),
        cmocka_unit_test(test_rules_and_order),
        cmocka_unit_test(test_sigma_rule),
        cmocka_unit_test(test_radius_rule),
        cmocka_unit_test(test_output_off_and_counters),
        cmocka_unit_test(test_step_limit_exact),
        cmocka_unit_test(test_live_registers),
        cmocka_unit_test(test_state_registers),
        cmocka_unit_test(test_unlock_sequence),
        cmocka_unit_test(test_commission_needs_consent),
        cmocka_unit_test(test_commission_needs_rng),
        cmocka_unit_test(test_lying_block_needs_key),
        cmocka_unit_test(test_replay_refused),
        cmocka_unit_test(test_auth_message_layout),
        cmocka_unit_test(test_factory_ceilings),
        cmocka_unit_test(test_unusable_blocks_refused),
        cmocka_unit_test(test_save_is_separate_and_checked),
        cmocka_unit_test(test_restore_checks_everything),
        cmocka_unit_test(test_word_order_cdab),
        cmocka_unit_test(test_box_refuses_interior_instability),
        cmocka_unit_test(test_box_sigma_rule),
        cmocka_unit_test(test_box_budget_refuses),
        cmocka_unit_test(test_box_certificate),
        cmocka_unit_test(test_box_certificate_window),
        cmocka_unit_test(test_box_certificate_fuzz),
        cmocka_unit_test(test_box_block_validation),
        cmocka_unit_test(test_version3_client_refused),
        cmocka_unit_test(test_box_persistence),
        cmocka_unit_test(test_seal),
        cmocka_unit_test(test_commission_unsealed),
        cmocka_unit_test(test_pdu_read),
        cmocka_unit_test(test_pdu_write),
        cmocka_unit_test(test_pdu_bad_function),
        cmocka_unit_test(test_pdu_resp_cap),
        cmocka_unit_test(test_null_arguments),
        cmocka_unit_test(test_active_gains),
        cmocka_unit_test(test_active_gains_mid_publication),
        cmocka_unit_test(test_state_mid_publication),
        cmocka_unit_test(test_read_fail_safe_words),
        cmocka_unit_test_teardown(test_fpenv_refuses_seal, restore_rounding),
        cmocka_unit_test(test_reason_names),
        cmocka_unit_test(test_refusals_change_nothing),
    };
    return cmocka_run_group_tests_name("regmap (" ZW_REAL_NAME ")", tests, NULL, NULL);
}
