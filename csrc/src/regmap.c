/* The drive-side gain register map, zwidth/regmap.h.
 *
 * Every request goes through the same steps: the whole address range is checked (mapped,
 * writable, whole two-word values, writable in the current mode), then the whole payload
 * (the gain pair is certified as a pair, staged floats must be finite), and only then is
 * anything stored.  A refusal therefore leaves every register as it was except the three
 * refusal registers.
 *
 * Portability (TI C28x: 16-bit char and int): bytes and words are held in uint_least*
 * types and masked, every shift is done on a uint_least32_t, floats are packed and
 * unpacked by frexpf/ldexpf arithmetic rather than by type punning.
 *
 * The live-limit registers are cached in rm->live and recomputed after every accepted
 * write (live_all), rather than computed on read: a read then never runs the core, and the
 * deepest chains into the core start from the public function's tail call instead of
 * below a read loop's frame, which keeps the worst stack chain on the Cortex-M4F within
 * the project's 256 bytes (see ZW_NOINLINE).
 *
 * The gain pair (Modbus task -> control loop) and the state registers (control loop ->
 * Modbus task) cross contexts through a double buffer and a sequence word (regmap.h,
 * threading model): publish_gains / zw_regmap_set_state write, zw_regmap_active_gains /
 * read_state read; nothing else is shared.
 */
#include "zwidth/regmap.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "zwidth/selftest.h"

#if ZW_REGMAP_C11_ATOMICS
#include <stdatomic.h>
#endif

/* Modbus limits on one request (Modbus Application Protocol v1.1b3, 6.3 and 6.12). */
#define ZW_MB_READ_MAX 125u
#define ZW_MB_WRITE_MAX 123u
#define ZW_MB_READ_HOLDING 0x03u
#define ZW_MB_WRITE_SINGLE 0x06u
#define ZW_MB_WRITE_MULTIPLE 0x10u

#define CRC_INDEX ZW_CERT_WORDS /* staged[CRC_INDEX] is the CRC word */

/* Register kinds (bits). */
#define RK_RO 1u    /* read-only */
#define RK_GAIN 2u  /* K, B: writable in operation with a sealed block */
#define RK_CERT 4u  /* certified block and its CRC: writable in commissioning */
#define RK_CMD 8u   /* the command register */
#define RK_PAIR 16u /* two-word values, each starting at an even address */

/* Index of each live register in rm->live (register ZW_REG_LIVE_K_MAX + 2 i). */
enum { L_K_MAX, L_K_CERT, L_B_LO, L_B_HI, L_K_MMAX, L_B_AT_KMMAX, L_RHO, L_DELTA, L_COUNT };

/* Index of each field of the certified block (register ZW_REG_CERT_M + 2 i). */
enum {
    F_M, F_B, F_T, F_SIGMA, F_R, F_K_MIN, F_K_MAX, F_B_MIN, F_B_MAX, F_DK_MAX, F_DB_MAX,
    F_DELAY, F_VFILTER, F_VF_PARAM, F_DIFF
};

/* A quiet NaN of type float, for values that do not exist (live registers without a
 * sealed plant).  NAN is optional in C99 (only where quiet NaNs exist); the fallback is
 * 0/0 at run time (not through zw_words_to_float, which itself needs QUIET_NAN_F). */
#ifdef NAN
#define QUIET_NAN_F ((float)NAN)
#else
static float quiet_nan_f(void)
{
    volatile float zero = 0.0f; /* volatile: no constant folding of 0/0 */
    return zero / zero;
}
#define QUIET_NAN_F (quiet_nan_f())
#endif

/* Keeps a function out of line where the compiler would merge it into its only caller, so
 * that the caller can end in it as a tail call and the deep chains into the core start from
 * a small frame (the stack gate of tools/footprint.sh).  Only a hint: nothing depends on it
 * for correctness. */
#if defined(__GNUC__)
#define ZW_NOINLINE __attribute__((noinline))
#else
#define ZW_NOINLINE
#endif

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
static void publish_gains(zw_regmap *rm, float K, float B)
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
        if (SHARED_LOAD(rm->state_seq) == seq) return true;
    }
    return false;
}

typedef struct reg_range {
    uint_least16_t first, last, kind;
} reg_range;

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
};

/* Kind bits of one address, 0 when unmapped. */
static uint_least16_t reg_kind(uint_least32_t addr)
{
    size_t i;
    for (i = 0; i < sizeof k_ranges / sizeof k_ranges[0]; ++i)
        if (addr >= k_ranges[i].first && addr <= k_ranges[i].last) return k_ranges[i].kind;
    return 0;
}

static bool finite_f(float x)
{
    return x == x && x <= FLT_MAX && x >= -FLT_MAX;
}

/* zw_real -> float without undefined behaviour when the value does not fit (saturates to
 * an infinity; NaN stays NaN). */
static float to_float(zw_real x)
{
    if (x != x) return QUIET_NAN_F;
    if (x > (zw_real)FLT_MAX) return ZW_HUGE_VALF;
    if (x < -(zw_real)FLT_MAX) return -ZW_HUGE_VALF;
    return (float)x;
}

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

static uint_least16_t crc_word(uint_least16_t crc, uint_least16_t word)
{
    crc = crc_byte(crc, ((unsigned)word >> 8) & 0xFFu);
    return crc_byte(crc, (unsigned)word & 0xFFu);
}

uint_least16_t zw_crc16_words(const uint_least16_t *words, size_t count)
{
    uint_least16_t crc = 0xFFFFu;
    size_t i;
    if (words == NULL) return crc;
    for (i = 0; i < count; ++i) crc = crc_word(crc, words[i]);
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

/* Word i (0..22) of the block in force: the sealed block and its CRC, all 0 unsealed.
 * Only the read path needs it, so it re-encodes rather than keeping a copy. */
static uint_least16_t sealed_word(const zw_regmap *rm, unsigned i)
{
    uint_least16_t w[2], crc = 0xFFFFu;
    unsigned f;
    if (!rm->is_sealed) return 0u;
    if (i < ZW_CERT_WORDS) {
        zw_float_to_words(zw_cert_field(&rm->sealed, i / 2u), w);
        return w[i & 1u];
    }
    for (f = 0; f < ZW_CERT_FIELDS; ++f) {
        zw_float_to_words(zw_cert_field(&rm->sealed, f), w);
        crc = crc_word(crc_word(crc, w[0]), w[1]);
    }
    return crc;
}

static float staged_float(const zw_regmap *rm, unsigned field)
{
    return zw_words_to_float(&rm->staged[2u * field]);
}

/* The ideal loop (delay 0, backward difference, no filter): certified by the closed form of
 * region.h / extremes.h, as in map version 1; any other by the general loop (loop.h). */
static bool ideal_loop(const zw_regmap *rm)
{
    return rm->loop.loop.spec.delay == 0u && rm->loop.loop.spec.filter == ZW_VFILTER_NONE &&
           rm->loop.loop.spec.differentiator == ZW_DIFF_BACKWARD;
}

/* x is a whole number in [0, max]. */
static bool whole_in(float x, float max)
{
    return x >= 0.0f && x <= max && (float)(unsigned)x == x;
}

/* The loop fields of the staged block, each to its named reason (regmap.h). */
static zw_reason check_loop_fields(const zw_regmap *rm)
{
    const float kind = staged_float(rm, F_VFILTER), param = staged_float(rm, F_VF_PARAM);
    if (!whole_in(staged_float(rm, F_DELAY), (float)ZW_LOOP_MAX_DELAY)) return ZW_REASON_BAD_DELAY;
    if (!whole_in(kind, 2.0f)) return ZW_REASON_BAD_FILTER;
    if (kind == 0.0f ? param != 0.0f
                     : kind == 1.0f ? !(param > 0.0f)
                                    : !(whole_in(param, (float)ZW_LOOP_MAX_AVERAGE) && param >= 1.0f))
        return ZW_REASON_BAD_FILTER_PARAM;
    if (!whole_in(staged_float(rm, F_DIFF), 1.0f)) return ZW_REASON_BAD_DIFFERENTIATOR;
    return ZW_REASON_NONE;
}

/* Build rm->loop from the staged block (staged) or the sealed one; the fields were checked.
 * Reason: BAD_FILTER_PARAM for a cut-off the pole cannot be formed from, BAD_POLICY for
 * the plant. */
static zw_reason build_loop(zw_regmap *rm, bool staged)
{
    zw_device_loop_spec spec;
    float f[ZW_CERT_FIELDS];
    unsigned i;
    zw_status st;
    for (i = 0; i < ZW_CERT_FIELDS; ++i) f[i] = staged ? staged_float(rm, i) : zw_cert_field(&rm->sealed, i);
    spec.delay = (unsigned)f[F_DELAY];
    spec.differentiator = f[F_DIFF] == 1.0f ? ZW_DIFF_TUSTIN : ZW_DIFF_BACKWARD;
    spec.filter = f[F_VFILTER] == 1.0f   ? ZW_VFILTER_LOWPASS
                  : f[F_VFILTER] == 2.0f ? ZW_VFILTER_AVERAGE
                                         : ZW_VFILTER_NONE;
    spec.cutoff_hz = spec.filter == ZW_VFILTER_LOWPASS ? (zw_real)f[F_VF_PARAM] : ZW_R(0.0);
    spec.pole = ZW_R(0.0);
    spec.average = spec.filter == ZW_VFILTER_AVERAGE ? (unsigned)f[F_VF_PARAM] : 0u;
    rm->kmax_cached = 0u;
    st = zw_device_loop_init(&rm->loop, (zw_real)f[F_M], (zw_real)f[F_B], (zw_real)f[F_T], &spec);
    if (st == ZW_OK) return ZW_REASON_NONE;
    return st == ZW_ERR_FILTER ? ZW_REASON_BAD_FILTER_PARAM : ZW_REASON_BAD_POLICY;
}

/* K_MMAX and its B, of the plant and loop in force (the extremes in a frame of their own,
 * only at SEAL and init: with a general loop they cost milliseconds).  *any: some gains are
 * stable (K_mmax > 0). */
ZW_NOINLINE static void live_extremes(zw_regmap *rm, bool *any)
{
    zw_status st;
    zw_real K = ZW_R(0.0), B = ZW_R(0.0);
    if (ideal_loop(rm)) {
        zw_device_extremes e;
        st = zw_device_extremes_compute(&rm->loop.dev, &e);
        K = e.K_mmax;
        B = e.B_at_K_mmax;
    } else {
        zw_device_loop_extremes e;
        st = zw_device_loop_extremes_compute(&rm->loop, &rm->ws, &e);
        K = e.K_mmax;
        B = e.B_at_K_mmax;
    }
    *any = st == ZW_OK && K > ZW_R(0.0);
    rm->live[L_K_MMAX] = st == ZW_OK ? to_float(K) : QUIET_NAN_F;
    rm->live[L_B_AT_KMMAX] = st == ZW_OK ? to_float(B) : QUIET_NAN_F;
}

/* SEAL: check the staged block and install it.  A refused block leaves the one in force
 * as it was: the loop is rebuilt from the sealed block when building the staged one
 * failed (zw_device_loop_init leaves a refused plant NaN), and the live extremes are only
 * recomputed for a block that is sealed. */
static zw_reason seal_staged(zw_regmap *rm)
{
    unsigned i;
    float sigma, r;
    zw_reason why;
    bool any = false;
    /* every check below, and every certification after it, trusts the arithmetic */
    if (zw_selftest() != ZW_OK) return ZW_REASON_FPENV;
    if (zw_crc16_words(rm->staged, ZW_CERT_WORDS) != (rm->staged[CRC_INDEX] & 0xFFFFu))
        return ZW_REASON_CRC;
    for (i = 0; i < ZW_CERT_FIELDS; ++i)
        if (!finite_f(staged_float(rm, i))) return ZW_REASON_BAD_POLICY;
    sigma = staged_float(rm, F_SIGMA);
    r = staged_float(rm, F_R);
    if (!(sigma > 0.0f && sigma <= 1.0f) || !(r > 0.0f && r <= 1.0f)) return ZW_REASON_BAD_POLICY;
    if (!(staged_float(rm, F_K_MIN) <= staged_float(rm, F_K_MAX)) ||
        !(staged_float(rm, F_B_MIN) <= staged_float(rm, F_B_MAX)))
        return ZW_REASON_BAD_POLICY;
    if (!(staged_float(rm, F_DK_MAX) > 0.0f) || !(staged_float(rm, F_DB_MAX) > 0.0f))
        return ZW_REASON_BAD_POLICY;
    /* After a seal the output is off, (0, 0), and steps count from there: refuse a block
     * from which no pair is within the bounds and one step (it could never be used). */
    if (staged_float(rm, F_K_MIN) > staged_float(rm, F_DK_MAX) ||
        staged_float(rm, F_B_MIN) > staged_float(rm, F_DB_MAX) ||
        staged_float(rm, F_B_MAX) < -staged_float(rm, F_DB_MAX))
        return ZW_REASON_BAD_POLICY;
    if ((why = check_loop_fields(rm)) != ZW_REASON_NONE) return why;
    why = build_loop(rm, true);
    if (why == ZW_REASON_NONE) {
        live_extremes(rm, &any);
        if (!any) why = ZW_REASON_LOOP_NEVER_STABLE;
    }
    if (why != ZW_REASON_NONE) {
        /* the sealed block stays in force: its loop back (it was valid when sealed), and
         * its extremes */
        if (rm->is_sealed) {
            (void)build_loop(rm, false);
            live_extremes(rm, &any);
        }
        return why;
    }
    for (i = 0; i < ZW_CERT_FIELDS; ++i) zw_cert_set_field(&rm->sealed, i, staged_float(rm, i));
    rm->is_sealed = 1u;
    rm->mode = 0u;
    publish_gains(rm, 0.0f, 0.0f); /* gains stay off after a seal */
    return ZW_REASON_NONE;
}

/* ---- certification of a gain pair ---------------------------------------------------------- */

/* |a - b| <= limit, decided on the exact difference: when the rounded difference lands on
 * the limit, its rounding error (Knuth's TwoSum, exact without contraction) tells on which
 * side the exact difference lies.  a, b finite; limit finite and > 0. */
static bool step_within(float a, float b, float limit)
{
    zw_real x = (zw_real)a, y = -(zw_real)b, lim = (zw_real)limit;
    zw_real d = x + y;
    zw_real ad = d < ZW_R(0.0) ? -d : d;
    zw_real yv, err;
    if (ad != lim) return ad < lim; /* an overflowed difference is inf: refused */
    yv = d - x;
    err = (x - (d - yv)) + (y - yv); /* d + err == a - b exactly */
    return d > ZW_R(0.0) ? err <= ZW_R(0.0) : err >= ZW_R(0.0);
}

/* The two rules that need the plant, each in its own small function: the deepest chains of
 * the core (zw_device_radius_within) then start right below a small frame (stack).  Any
 * error of the core (a normalization that overflows) counts against the pair. */
static bool stable_ok(zw_regmap *rm, float K, float B)
{
    if (ideal_loop(rm)) {
        zw_verdict v;
        return zw_device_check(&rm->loop.dev, (zw_real)K, (zw_real)B, &v) == ZW_OK && v.stable;
    } else {
        zw_loop_verdict v;
        return zw_device_loop_check(&rm->loop, &rm->ws, (zw_real)K, (zw_real)B, &v) == ZW_OK && v.stable;
    }
}

static bool radius_ok(zw_regmap *rm, float K, float B)
{
    bool within = false;
    zw_status st = ideal_loop(rm)
                       ? zw_device_radius_within(&rm->loop.dev, (zw_real)K, (zw_real)B,
                                                 (zw_real)rm->sealed.r, &within)
                       : zw_device_loop_radius_within(&rm->loop, &rm->ws, (zw_real)K, (zw_real)B,
                                                      (zw_real)rm->sealed.r, &within);
    return st == ZW_OK && within;
}

/* K_max at B of the drive's loop (certified; 0 on error, by the core's fail-safe).  The
 * general loop's is taken from the cache when B is the one it holds. */
static zw_status drive_k_max(zw_regmap *rm, float B, zw_real *k_max)
{
    if (ideal_loop(rm)) return zw_device_k_max(&rm->loop.dev, (zw_real)B, k_max);
    if (rm->kmax_cached != 0u && rm->kmax_B == B) {
        *k_max = rm->kmax_value;
        return ZW_OK;
    }
    return zw_device_loop_k_max(&rm->loop, &rm->ws, (zw_real)B, k_max);
}

/* Keep K_max(B) for the gains now in force (general loop; the ideal one is cheap). */
static void cache_k_max(zw_regmap *rm, float B, zw_real k_max)
{
    rm->kmax_B = B;
    rm->kmax_value = k_max;
    rm->kmax_cached = (uint_least16_t)(ideal_loop(rm) ? 0u : 1u);
}

/* The rules of regmap.h, in its order; the first that fails is the reason. */
static zw_reason certify(zw_regmap *rm, float K, float B, zw_real *k_max_out)
{
    const zw_cert *c = &rm->sealed;
    zw_real k_max;
    *k_max_out = ZW_R(0.0);
    if (!finite_f(K) || !finite_f(B)) return ZW_REASON_NOT_FINITE;
    if (K == 0.0f && B == 0.0f) return ZW_REASON_NONE; /* output off: always allowed */
    if (K < c->k_min) return ZW_REASON_K_BELOW_MIN;
    if (K > c->k_max) return ZW_REASON_K_ABOVE_MAX;
    if (B < c->b_min) return ZW_REASON_B_BELOW_MIN;
    if (B > c->b_max) return ZW_REASON_B_ABOVE_MAX;
    if (!step_within(K, rm->K, c->dk_max)) return ZW_REASON_K_STEP;
    if (!step_within(B, rm->B, c->db_max)) return ZW_REASON_B_STEP;
    if (!stable_ok(rm, K, B)) return ZW_REASON_UNSTABLE;
    if (drive_k_max(rm, B, &k_max) != ZW_OK || (zw_real)K > (zw_real)c->sigma * k_max)
        return ZW_REASON_ABOVE_SIGMA;
    *k_max_out = k_max;
    if (!radius_ok(rm, K, B)) return ZW_REASON_RADIUS;
    return ZW_REASON_NONE;
}

/* A gain write: certified as a pair, then stored (K and B the values after the write). */
ZW_NOINLINE static zw_reason apply_gains(zw_regmap *rm, float K, float B)
{
    zw_real k_max;
    zw_reason why = certify(rm, K, B, &k_max);
    if (why != ZW_REASON_NONE) return why;
    /* (0, 0) skips the rules: k_max is then not known */
    if (K == 0.0f && B == 0.0f) rm->kmax_cached = 0u;
    else cache_k_max(rm, B, k_max);
    publish_gains(rm, K, B);
    rm->accepted = (rm->accepted + 1u) & 0xFFFFFFFFu;
    return ZW_REASON_NONE;
}

/* ---- live registers ------------------------------------------------------------------------ */


/* The largest float not above x (x not NaN, at most FLT_MAX). */
static float float_down(zw_real x)
{
    float f = to_float(x);
    if ((zw_real)f > x) f = ZW_NEXTAFTERF(f, -ZW_HUGE_VALF);
    return f;
}

/* Grid of the downward scan in live_k_cert (see there). */
#define K_CERT_GRID 32

/* LIVE_K_CERT: the largest float K at the current B that the k_max, sigma, stability and
 * radius rules accept (the k_min and step rules depend on where K comes from, so they are
 * left out).  top = min(sigma K_max(B), k_max) is taken when stability and radius accept
 * it; otherwise the largest accepted K lies below top: K is scanned down from top on a grid
 * of K_CERT_GRID points for one that is accepted, and the crossing above it is bisected to
 * float resolution, so the value reported is itself accepted.  0 when no grid point is.
 * NaN without a sealed plant.  Returns ZW_MB_OK so that live_all can end in it. */
ZW_NOINLINE static zw_mb_exception live_k_cert(zw_regmap *rm)
{
    zw_real k_max, top;
    float top_f = 0.0f, lo = 0.0f, hi, k, B = rm->B;
    int grid = K_CERT_GRID; /* scanning grid point grid/K_CERT_GRID of top; 0: bisecting */
    bool ok;
    rm->live[L_K_CERT] = QUIET_NAN_F;
    if (!rm->is_sealed || drive_k_max(rm, B, &k_max) != ZW_OK)
        return ZW_MB_OK;
    top = (zw_real)rm->sealed.sigma * k_max;
    if (top > (zw_real)rm->sealed.k_max) top = (zw_real)rm->sealed.k_max;
    if (top > ZW_R(0.0)) top_f = float_down(top);
    /* One loop with one call site of the rules: a smaller frame than a scan loop followed
     * by a bisection loop. */
    hi = k = top_f;
    while (k > 0.0f) {
        ok = stable_ok(rm, k, B) && radius_ok(rm, k, B);
        if (grid > 0 && !ok) { /* scanning down */
            hi = k;
            if (--grid == 0) break; /* no grid point accepted: lo stays 0 */
            k = top_f * ((float)grid / (float)K_CERT_GRID);
            continue;
        }
        if (ok) lo = k;
        else hi = k;
        if (grid == K_CERT_GRID) break; /* top itself is accepted */
        grid = 0;
        k = lo + (hi - lo) * 0.5f; /* lo accepted, hi refused; ends when they are neighbours */
        if (!(k > lo && k < hi)) break;
    }
    rm->live[L_K_CERT] = lo;
    return ZW_MB_OK;
}

static float value_or_nan(zw_status st, zw_real x)
{
    return st == ZW_OK ? to_float(x) : QUIET_NAN_F;
}

/* Recompute the live registers that depend on the gains (and delta) after an accepted
 * change (gains, seal, unlock), so reads never run the core.  A value that does not exist
 * (no sealed plant, or the core refuses the computation) reads as NaN.  K_CERT, K_MMAX and
 * its B have functions of their own, each called from live_all, so that no frame sits
 * under another one's chain into the core (stack). */
ZW_NOINLINE static void live_refresh(zw_regmap *rm)
{
    const zw_device *d = &rm->loop.dev;
    zw_real x = ZW_R(0.0), y = ZW_R(0.0), th = ZW_R(0.0);
    zw_status st;
    bool any;
    unsigned i;
    if (!rm->is_sealed) {
        for (i = 0; i < L_COUNT; ++i) rm->live[i] = QUIET_NAN_F;
        return;
    }
    st = drive_k_max(rm, rm->B, &x);
    if (st == ZW_OK && !(rm->K == 0.0f && rm->B == 0.0f)) cache_k_max(rm, rm->B, x);
    rm->live[L_K_MAX] = value_or_nan(st, x);
    /* both report (0, 0) when the interval is empty, which covers K = 0 */
    /* the general loop's B range is not computed per write (regmap.h): NaN */
    st = ideal_loop(rm) ? zw_device_b_range(d, (zw_real)rm->K, &x, &y, &any) : ZW_ERR_ARG;
    rm->live[L_B_LO] = value_or_nan(st, x);
    rm->live[L_B_HI] = value_or_nan(st, y);
    st = ideal_loop(rm) ? zw_device_spectral_radius(d, (zw_real)rm->K, (zw_real)rm->B, &x)
                        : zw_device_loop_spectral_radius(&rm->loop, &rm->ws, (zw_real)rm->K, (zw_real)rm->B, &x, &th);
    rm->live[L_RHO] = value_or_nan(st, x);
    rm->live[L_DELTA] = to_float(d->co.delta);
}

/* Every live register, after an accepted change.  Returns ZW_MB_OK so that the public
 * functions end in it as a tail call, and ends in live_k_cert as one itself. */
static zw_mb_exception live_all(zw_regmap *rm)
{
    live_refresh(rm);
    return live_k_cert(rm);
}

/* ---- reads --------------------------------------------------------------------------------- */

/* Both words of the two-word value at base (even address of an RK_PAIR register); the
 * state registers from the sample st. */
static void read_pair(const zw_regmap *rm, const state_sample *st, uint_least16_t base,
                      uint_least16_t w[2])
{
    uint_least32_t u;
    float f;
    if (base >= ZW_REG_CERT_M) { /* the block: staged in commissioning, else sealed */
        unsigned i = (unsigned)(base - ZW_REG_CERT_M);
        w[0] = rm->mode != 0u ? rm->staged[i] : sealed_word(rm, i);
        w[1] = rm->mode != 0u ? rm->staged[i + 1u] : sealed_word(rm, i + 1u);
        return;
    }
    if (base == ZW_REG_ACCEPTED || base == ZW_REG_REFUSED || base == ZW_REG_STATE_STEP) {
        u = base == ZW_REG_ACCEPTED ? rm->accepted
            : base == ZW_REG_REFUSED ? rm->refused : st->step;
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
    case ZW_REG_LIVE_POLE: f = rm->is_sealed ? to_float(rm->loop.loop.spec.filter_pole) : QUIET_NAN_F; break;
    default: f = rm->live[(unsigned)(base - ZW_REG_LIVE_K_MAX) / 2u]; break;
    }
    zw_float_to_words(f, w);
}

/* A one-word register. */
static uint_least16_t read_single(const zw_regmap *rm, uint_least16_t addr)
{
    switch (addr) {
    case ZW_REG_MAGIC: return ZW_REGMAP_MAGIC;
    case ZW_REG_VERSION: return ZW_REGMAP_VERSION;
    case ZW_REG_MODE: return rm->mode;
    case ZW_REG_SEALED: return rm->is_sealed;
    case ZW_REG_LAST_REASON: return rm->last_reason;
    case ZW_REG_LAST_EXCEPTION: return rm->last_exception;
    case ZW_REG_CERT_CRC:
        return rm->mode != 0u ? rm->staged[CRC_INDEX] : sealed_word(rm, CRC_INDEX);
    default: return 0u; /* ZW_REG_COMMAND reads as 0 */
    }
}

/* ---- requests ------------------------------------------------------------------------------ */

static zw_mb_exception exception_of(zw_reason reason)
{
    switch (reason) {
    case ZW_REASON_NONE: return ZW_MB_OK;
    case ZW_REASON_BAD_FUNCTION: return ZW_MB_ILLEGAL_FUNCTION;
    case ZW_REASON_UNMAPPED:
    case ZW_REASON_READ_ONLY:
    case ZW_REASON_HALF_FLOAT:
    case ZW_REASON_LOCKED:
    case ZW_REASON_NOT_SEALED: return ZW_MB_ILLEGAL_ADDRESS;
    default: return ZW_MB_ILLEGAL_VALUE;
    }
}

/* Record a refusal: only the three refusal registers change.  (Whether a pending UNLOCK1
 * survives is decided by the caller: writes disarm it, reads do not.) */
static zw_mb_exception refuse(zw_regmap *rm, zw_reason reason, zw_reason *out)
{
    zw_mb_exception exc = exception_of(reason);
    rm->last_reason = (uint_least16_t)reason;
    rm->last_exception = (uint_least16_t)exc;
    rm->refused = (rm->refused + 1u) & 0xFFFFFFFFu;
    if (out != NULL) *out = reason;
    return exc;
}

/* Word i of a request payload: from a word array, or from big-endian PDU bytes. */
static uint_least16_t payload_word(const uint_least16_t *words, const uint_least8_t *bytes,
                                   size_t i)
{
    if (words != NULL) return (uint_least16_t)(words[i] & 0xFFFFu);
    return (uint_least16_t)((((unsigned)bytes[2u * i] & 0xFFu) << 8) |
                            ((unsigned)bytes[2u * i + 1u] & 0xFFu));
}

static float payload_float(const uint_least16_t *words, const uint_least8_t *bytes, size_t i)
{
    uint_least16_t w[2];
    w[0] = payload_word(words, bytes, i);
    w[1] = payload_word(words, bytes, i + 1u);
    return zw_words_to_float(w);
}

/* Quantity and addresses, shared by reads and writes: the kind bits of all the words, or
 * the reason. */
static zw_reason check_range(uint_least16_t addr, uint_least16_t count, uint_least16_t max_count,
                             uint_least16_t *kinds)
{
    uint_least32_t a, end = (uint_least32_t)addr + count;
    uint_least16_t k, all = 0u;
    if (count < 1u || count > max_count) return ZW_REASON_MALFORMED;
    if (end > 0x10000u) return ZW_REASON_UNMAPPED;
    for (a = addr; a < end; ++a) {
        if ((k = reg_kind(a)) == 0u) return ZW_REASON_UNMAPPED;
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
    if ((why = check_range(addr, count, ZW_MB_READ_MAX, &kinds)) != ZW_REASON_NONE) return why;
    /* one sample for the whole read, so that x, v, f and step belong together */
    if ((uint_least32_t)addr + count > ZW_REG_STATE_X && addr <= ZW_REG_STATE_STEP + 1u &&
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
            first = a & 1u;
            if (first == 0u && i + 1u < count) n = 2;
        } else {
            w[0] = read_single(rm, a);
        }
        for (j = first; j < first + n; ++j, ++i) {
            if (words != NULL) {
                words[i] = w[j];
            } else {
                bytes[2u * i] = (uint_least8_t)(((unsigned)w[j] >> 8) & 0xFFu);
                bytes[2u * i + 1u] = (uint_least8_t)((unsigned)w[j] & 0xFFu);
            }
        }
    }
    return ZW_REASON_NONE;
}

/* Staged block: every float finite, then all words stored.  The CRC word is free. */
static zw_reason write_cert(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                            const uint_least16_t *words, const uint_least8_t *bytes)
{
    size_t i;
    for (i = 0; i < count && (uint_least32_t)addr + i < ZW_REG_CERT_CRC; i += 2u)
        if (!finite_f(payload_float(words, bytes, i))) return ZW_REASON_NOT_FINITE;
    for (i = 0; i < count; ++i)
        rm->staged[(size_t)(addr - ZW_REG_CERT_M) + i] = payload_word(words, bytes, i);
    return ZW_REASON_NONE;
}

static zw_reason command(zw_regmap *rm, uint_least16_t cmd, bool armed)
{
    unsigned i;
    switch (cmd) {
    case ZW_CMD_UNLOCK1:
        if (rm->mode != 0u) return ZW_REASON_BAD_COMMAND; /* already commissioning */
        rm->unlock_armed = 1u;
        return ZW_REASON_NONE;
    case ZW_CMD_UNLOCK2:
        if (rm->mode != 0u || !armed) return ZW_REASON_BAD_COMMAND;
        rm->mode = 1u;
        publish_gains(rm, 0.0f, 0.0f); /* output off while the block may change */
        for (i = 0; i <= ZW_CERT_WORDS; ++i) rm->staged[i] = sealed_word(rm, i);
        return ZW_REASON_NONE;
    case ZW_CMD_SEAL:
        if (rm->mode == 0u) return ZW_REASON_BAD_COMMAND;
        return seal_staged(rm);
    case ZW_CMD_ABORT:
        if (rm->mode == 0u) return ZW_REASON_BAD_COMMAND;
        rm->mode = 0u; /* the sealed block and device were never touched; gains stay off */
        return ZW_REASON_NONE;
    default: return ZW_REASON_BAD_COMMAND;
    }
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
    if ((why = check_range(addr, count, ZW_MB_WRITE_MAX, &kinds)) != ZW_REASON_NONE) return why;
    if ((kinds & RK_RO) != 0u) return ZW_REASON_READ_ONLY;
    /* Pairs start at even addresses, so a write splits a value exactly when it starts on
     * an odd word or ends on an even one of an RK_PAIR range. */
    last = (uint_least16_t)(addr + count - 1u);
    if (((reg_kind(addr) & RK_PAIR) != 0u && (addr & 1u) != 0u) ||
        ((reg_kind(last) & RK_PAIR) != 0u && (last & 1u) == 0u))
        return ZW_REASON_HALF_FLOAT;
    /* Past the checks above the request lies in exactly one group (the map has unmapped
     * or read-only words between groups). */
    if ((kinds & RK_CERT) != 0u) {
        if (rm->mode == 0u) return ZW_REASON_LOCKED;
        return write_cert(rm, addr, count, words, bytes);
    }
    if ((kinds & RK_GAIN) != 0u) {
        float K = rm->K, B = rm->B;
        if (rm->mode != 0u || !rm->is_sealed) return ZW_REASON_NOT_SEALED;
        if (addr == ZW_REG_K) K = payload_float(words, bytes, 0);
        if (addr == ZW_REG_B || count == 4u) B = payload_float(words, bytes, count - 2u);
        return apply_gains(rm, K, B); /* a tail call: this frame is gone (stack) */
    }
    return command(rm, payload_word(words, bytes, 0), armed);
}

/* ---- public API ---------------------------------------------------------------------------- */

/* Power-up state without the live registers: unsealed, gains off, counters 0, then the
 * given block through the path of a commissioned one (the same checks). */
ZW_NOINLINE static zw_reason power_up(zw_regmap *rm, const zw_cert *cert)
{
    unsigned i;
    zw_reason why = ZW_REASON_NONE;
    /* the floats are set explicitly rather than trusting all-zero bits to mean 0.0f */
    (void)memset(rm, 0, sizeof *rm);
    for (i = 0; i < ZW_CERT_FIELDS; ++i) zw_cert_set_field(&rm->sealed, i, 0.0f);
    for (i = 0; i < 2u; ++i) { /* both slots of each double buffer */
        publish_gains(rm, 0.0f, 0.0f);
        zw_regmap_set_state(rm, 0.0f, 0.0f, 0.0f, 0u);
    }
    if (cert != NULL) {
        zw_cert_encode(cert, rm->staged);
        why = seal_staged(rm);
        for (i = 0; i <= ZW_CERT_WORDS; ++i) rm->staged[i] = 0u;
    }
    return why;
}

zw_status zw_regmap_init(zw_regmap *rm, const zw_cert *cert, zw_reason *reason)
{
    zw_reason why;
    if (rm == NULL) return ZW_ERR_NULL;
    why = power_up(rm, cert);
    if (reason != NULL) *reason = why;
    (void)live_all(rm);
    if (why == ZW_REASON_NONE) return ZW_OK;
    /* otherwise a valid unsealed drive with the output off */
    return why == ZW_REASON_FPENV ? ZW_ERR_FPENV : ZW_ERR_ARG;
}

zw_status zw_regmap_active_gains(const zw_regmap *rm, float *K, float *B)
{
    unsigned tries;
    if (K != NULL) *K = 0.0f; /* output off unless a consistent pair is read */
    if (B != NULL) *B = 0.0f;
    if (rm == NULL || K == NULL || B == NULL) return ZW_ERR_NULL;
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
    if (rm == NULL) return;
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
    if (words == NULL || count < 1u || count > ZW_MB_READ_MAX) return;
    for (i = 0; i < count; ++i)
        words[i] = (uint_least16_t)((uint_least32_t)addr + i == ZW_REG_LIVE_RHO ? 0x7F80u : 0u);
}

zw_mb_exception zw_regmap_read(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                               uint_least16_t *words, zw_reason *reason)
{
    zw_reason why;
    bool sampled = true;
    if (rm == NULL || words == NULL) {
        fail_safe_words(addr, count, words);
        return ZW_MB_SERVER_FAILURE;
    }
    why = read_core(rm, addr, count, words, NULL, &sampled);
    if (why != ZW_REASON_NONE || !sampled) {
        fail_safe_words(addr, count, words);
        return !sampled ? ZW_MB_SERVER_FAILURE : refuse(rm, why, reason);
    }
    if (reason != NULL) *reason = ZW_REASON_NONE;
    return ZW_MB_OK;
}

zw_mb_exception zw_regmap_write(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                                const uint_least16_t *words, zw_reason *reason)
{
    zw_reason why;
    if (rm == NULL) return ZW_MB_SERVER_FAILURE;
    if (words == NULL) {
        rm->unlock_armed = 0u;
        return ZW_MB_SERVER_FAILURE;
    }
    if ((why = write_core(rm, addr, count, words, NULL)) != ZW_REASON_NONE)
        return refuse(rm, why, reason);
    if (reason != NULL) *reason = ZW_REASON_NONE;
    return live_all(rm);
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

zw_mb_exception zw_regmap_handle_pdu(zw_regmap *rm, const uint_least8_t *req, size_t req_len,
                                     uint_least8_t *resp, size_t resp_cap, size_t *resp_len)
{
    unsigned fc;
    uint_least16_t addr = 0u, qty = 0u;
    size_t i;
    zw_reason why;
    bool sampled = true;
    if (rm == NULL) {
        if (resp_len != NULL) *resp_len = 0;
        return ZW_MB_SERVER_FAILURE;
    }
    /* Every request but a read disarms a pending UNLOCK1, even one that cannot be
     * processed; write_core reads the flag before it clears it. */
    if (resp_len == NULL || req == NULL || resp == NULL || req_len < 1u || resp_cap < 2u) {
        /* no room even for an exception, or no function code to answer: not processed */
        rm->unlock_armed = 0u;
        if (resp_len != NULL) *resp_len = 0;
        return ZW_MB_SERVER_FAILURE;
    }
    *resp_len = 0;
    fc = (unsigned)req[0] & 0xFFu;
    if (req_len >= 5u) {
        addr = be16(req + 1);
        qty = be16(req + 3); /* the value itself for 0x06 */
    }
    if (fc == ZW_MB_READ_HOLDING) {
        if (req_len != 5u || qty < 1u || qty > ZW_MB_READ_MAX) {
            why = ZW_REASON_MALFORMED;
        } else if (2u + 2u * (size_t)qty > resp_cap) {
            /* the answer would not fit: nothing is processed, not even counted */
            return answer_exception(resp, resp_len, fc, ZW_MB_SERVER_FAILURE);
        } else if ((why = read_core(rm, addr, qty, NULL, resp + 2, &sampled)) == ZW_REASON_NONE) {
            if (!sampled) return answer_exception(resp, resp_len, fc, ZW_MB_SERVER_FAILURE);
            resp[0] = (uint_least8_t)fc;
            resp[1] = (uint_least8_t)(2u * (unsigned)qty);
            *resp_len = 2u + 2u * (size_t)qty;
            return ZW_MB_OK;
        }
    } else if (fc == ZW_MB_WRITE_SINGLE || fc == ZW_MB_WRITE_MULTIPLE) {
        if (fc == ZW_MB_WRITE_SINGLE ? req_len != 5u
                                     : req_len < 6u || qty < 1u || qty > ZW_MB_WRITE_MAX ||
                                           ((unsigned)req[5] & 0xFFu) != 2u * (unsigned)qty ||
                                           req_len != 6u + 2u * (size_t)qty) {
            why = ZW_REASON_MALFORMED;
        } else if (resp_cap < 5u) {
            rm->unlock_armed = 0u;
            return answer_exception(resp, resp_len, fc, ZW_MB_SERVER_FAILURE);
        } else if ((why = fc == ZW_MB_WRITE_SINGLE
                              ? write_core(rm, addr, 1u, NULL, req + 3)
                              : write_core(rm, addr, qty, NULL, req + 6)) == ZW_REASON_NONE) {
            /* 0x06 echoes the request; 0x10 answers its address and quantity: the same
             * first 5 bytes either way */
            for (i = 0; i < 5u; ++i) resp[i] = (uint_least8_t)((unsigned)req[i] & 0xFFu);
            *resp_len = 5u;
            return live_all(rm);
        }
    } else {
        why = ZW_REASON_BAD_FUNCTION;
    }
    if (fc != ZW_MB_READ_HOLDING) rm->unlock_armed = 0u; /* a refused read leaves it armed */
    return answer_exception(resp, resp_len, fc, refuse(rm, why, NULL));
}

const char *zw_reason_name(zw_reason reason)
{
    switch (reason) {
    case ZW_REASON_NONE: return "ZW_REASON_NONE";
    case ZW_REASON_BAD_FUNCTION: return "ZW_REASON_BAD_FUNCTION";
    case ZW_REASON_MALFORMED: return "ZW_REASON_MALFORMED";
    case ZW_REASON_UNMAPPED: return "ZW_REASON_UNMAPPED";
    case ZW_REASON_READ_ONLY: return "ZW_REASON_READ_ONLY";
    case ZW_REASON_HALF_FLOAT: return "ZW_REASON_HALF_FLOAT";
    case ZW_REASON_LOCKED: return "ZW_REASON_LOCKED";
    case ZW_REASON_NOT_SEALED: return "ZW_REASON_NOT_SEALED";
    case ZW_REASON_NOT_FINITE: return "ZW_REASON_NOT_FINITE";
    case ZW_REASON_K_BELOW_MIN: return "ZW_REASON_K_BELOW_MIN";
    case ZW_REASON_K_ABOVE_MAX: return "ZW_REASON_K_ABOVE_MAX";
    case ZW_REASON_B_BELOW_MIN: return "ZW_REASON_B_BELOW_MIN";
    case ZW_REASON_B_ABOVE_MAX: return "ZW_REASON_B_ABOVE_MAX";
    case ZW_REASON_K_STEP: return "ZW_REASON_K_STEP";
    case ZW_REASON_B_STEP: return "ZW_REASON_B_STEP";
    case ZW_REASON_UNSTABLE: return "ZW_REASON_UNSTABLE";
    case ZW_REASON_ABOVE_SIGMA: return "ZW_REASON_ABOVE_SIGMA";
    case ZW_REASON_RADIUS: return "ZW_REASON_RADIUS";
    case ZW_REASON_BAD_COMMAND: return "ZW_REASON_BAD_COMMAND";
    case ZW_REASON_CRC: return "ZW_REASON_CRC";
    case ZW_REASON_BAD_POLICY: return "ZW_REASON_BAD_POLICY";
    case ZW_REASON_FPENV: return "ZW_REASON_FPENV";
    case ZW_REASON_BAD_DELAY: return "ZW_REASON_BAD_DELAY";
    case ZW_REASON_BAD_FILTER: return "ZW_REASON_BAD_FILTER";
    case ZW_REASON_BAD_FILTER_PARAM: return "ZW_REASON_BAD_FILTER_PARAM";
    case ZW_REASON_BAD_DIFFERENTIATOR: return "ZW_REASON_BAD_DIFFERENTIATOR";
    case ZW_REASON_LOOP_NEVER_STABLE: return "ZW_REASON_LOOP_NEVER_STABLE";
    default: break; /* a value outside the enumeration: named below */
    }
    return "ZW_REASON_UNKNOWN";
}
