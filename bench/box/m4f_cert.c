/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/box/m4f_cert.c - Cortex-M4F half of the box-certificate benchmark (QEMU
 * mps2-an386, tools/m4f_box_cert.sh): for each box of the generated table (bench/box/
 * cert_gen.c), the drive verifies the host's certificate (zw_box_cert_verify), looks levels
 * up (zw_box_cert_level) and refuses a corrupted copy (one level doubled), and prints what
 * each cost over semihosting, one "BOX key=value ..." line per box.
 *
 * Counting: run with -icount shift=0 (1 instruction = 1 ns of virtual time); the CMSDK APB
 * timer 0 at 0x40000000 counts the 25 MHz clock, so 1 tick = 40 instructions (as in the
 * firmware review's m4f_cost.c): a figure is within 40 instructions of the count.  A
 * calibration loop of exactly CALIB_INSN instructions checks that at start-up.  A lookup is
 * too short for that resolution: LOOKUP_REPS calls are timed, less the same loop calling an
 * empty function, plus that function's one instruction (bx lr): instructions inside
 * zw_box_cert_level per call, in hundredths.  Stack: the free RAM between the bss end and sp
 * is painted before each verify and the deepest word touched is reported.
 *
 * The register map with the certificate in force (one "RM key=value ..." line per box): a
 * ranged block over the box (m, m_hi, b, b_hi the box's; T 0.02; sigma CERT_CASE_SIGMA;
 * r 1; K in [0, CERT_CASE_K_MAX], step CERT_CASE_DK_MAX; B in the certificate's
 * [B[0], B[n]], step its width; the box's delay; backward differentiator, no filter) is
 * sealed at power-up with zw_regmap_init_box (timed, and its stack; zw_selftest, which the
 * SEAL runs first, is timed alone too), then three gain writes (K and B, FC 0x10's
 * zw_regmap_write of 4 registers) are timed: one that moves B to the middle of step 3 with
 * K half the level there (accepted), one that moves B to the middle of step 10 with K 1.1
 * times the level there (ZW_REASON_ABOVE_SIGMA), and one with B outside the staircase
 * (ZW_REASON_OUTSIDE_CERT).  The last needs a block whose B range is wider than the
 * staircase (else ZW_REASON_B_ABOVE_MAX comes first): the same block with the range widened
 * by a quarter of its width on each side (B step: the widened width), sealed with the same
 * certificate (also timed), B at the staircase's top plus an eighth of its width.  One
 * "SIZE regmap=..." line: sizeof(zw_regmap).  zw_regmap is static (about 9 KB).
 *
 * Exit status (main's return: 0 -> QEMU exits 0): 1 when the calibration is off, a
 * verification is not ZW_BOX_CERT_OK, its leaves differ from the host's, a lookup differs
 * from the host's, the corrupted copy is accepted, a verify exceeds VERIFY_LIMIT
 * instructions, a SEAL is not ZW_OK / ZW_REASON_NONE or exceeds SEAL_LIMIT, a write's outcome
 * is not the expected one or exceeds WRITE_LIMIT instructions, or sizeof(zw_regmap) exceeds
 * REGMAP_SIZE_LIMIT bytes. */
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "cert_case.h"
#include "semihost.h"

#define TIMER0 ((volatile uint32_t *)0x40000000u)
#define INSN_PER_TICK 40ul
#ifndef VERIFY_LIMIT
#define VERIFY_LIMIT 8400000ul /* the SEAL target (tools/m4f_box_cert.sh may set it) */
#endif
#ifndef SEAL_LIMIT
#define SEAL_LIMIT 8400000ul /* zw_regmap_init_box with a certificate */
#endif
#ifndef WRITE_LIMIT
#define WRITE_LIMIT 20000ul /* one gain write with a certificate in force */
#endif
#ifndef REGMAP_SIZE_LIMIT
#define REGMAP_SIZE_LIMIT 12288ul /* sizeof(zw_regmap), bytes */
#endif
#define LOOKUP_REPS 1000u
#define CALIB_ITER 100000u
#define CALIB_INSN (2ul * CALIB_ITER + 3ul) /* movw, movt, CALIB_ITER x (subs, bne), bx lr */

extern uint32_t _ebss;

static zw_box_loop_cell g_cells[ZW_BOX_CERT_STACK];
static zw_box_loop_scratch g_scratch;
static zw_box_loop_work g_work;
static zw_box_cert g_bad_cert;
static zw_regmap g_rm; /* about 9 KB: static, not on the stack */

/* ---- output: one line built in a buffer, written with SYS_WRITE0 */
static char g_line[512];
static unsigned g_len;

static void out_s(const char *s)
{
    while (*s != '\0' && g_len + 1u < sizeof g_line) {
        g_line[g_len++] = *s++;
    }
    g_line[g_len] = '\0';
}
static void out_u(unsigned long v)
{
    char num[12];
    unsigned n = 0u;
    do {
        num[n++] = (char)('0' + (int)(v % 10ul));
        v /= 10ul;
    } while (v != 0ul && n < sizeof num);
    while (n > 0u && g_len + 1u < sizeof g_line) {
        g_line[g_len++] = num[--n];
    }
    g_line[g_len] = '\0';
}
static void out_kv(const char *key, unsigned long v)
{
    out_s(" ");
    out_s(key);
    out_s("=");
    out_u(v);
}
static void out_hundredths(const char *key, unsigned long v100)
{
    char frac[3];
    out_s(" ");
    out_s(key);
    out_s("=");
    out_u(v100 / 100ul);
    frac[0] = (char)('0' + (int)((v100 / 10ul) % 10ul));
    frac[1] = (char)('0' + (int)(v100 % 10ul));
    frac[2] = '\0';
    out_s(".");
    out_s(frac);
}
static void out_end(void)
{
    out_s("\n");
    semihost_puts(g_line);
    g_len = 0u;
    g_line[0] = '\0';
}

/* ---- counting */
/* VALUE: counts down.  The compiler barriers keep ordinary loads and stores (the stack
 * paint before a timed call, above all: a megabyte) on their side of the reading; a volatile
 * access alone does not order them. */
static uint32_t now(void)
{
    uint32_t v;
    __asm__ volatile("" ::: "memory");
    v = TIMER0[1];
    __asm__ volatile("" ::: "memory");
    return v;
}
static unsigned long insn(uint32_t t0, uint32_t t1) { return (unsigned long)(t0 - t1) * INSN_PER_TICK; }

static uint32_t *paint(void)
{
    uint32_t *p = &_ebss, *sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    sp -= 16;
    while (p < sp) {
        *p++ = 0xA5A5A5A5u;
    }
    return sp;
}
static unsigned long used(const uint32_t *top)
{
    const uint32_t *p = &_ebss;
    while (p < top && *p == 0xA5A5A5A5u) {
        p++;
    }
    return (unsigned long)((const char *)top - (const char *)p);
}

/* Exactly CALIB_INSN instructions (from its first to its return). */
__attribute__((naked, noinline)) static void calib_loop(void)
{
    __asm__ volatile("movw r0, #:lower16:100000\n\t"
                     "movt r0, #:upper16:100000\n"
                     "1:\n\t"
                     "subs r0, #1\n\t"
                     "bne 1b\n\t"
                     "bx lr\n" ::: "r0", "cc");
}

/* The lookup's baseline: the same signature, one instruction (bx lr). */
__attribute__((naked, noinline)) static void empty_level(const zw_box_cert *c, float B, float *K, bool *in)
{
    (void)c;
    (void)B;
    (void)K;
    (void)in;
    __asm__ volatile("bx lr\n");
}

typedef void (*level_fn)(const zw_box_cert *, float, float *, bool *);

static unsigned long time_level(level_fn f, const zw_box_cert *c, float B)
{
    volatile level_fn vf = f; /* an indirect call in both loops: the same overhead */
    float K = 0.0f;
    bool in = false;
    unsigned i;
    uint32_t t0, t1;
    t0 = now();
    for (i = 0u; i < LOOKUP_REPS; ++i) {
        vf(c, B, &K, &in);
    }
    t1 = now();
    return insn(t0, t1);
}

static bool same_float(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* ---- the register map with the certificate in force */

/* The ranged block over the box of cc, B range [b_min, b_max] (B step: its width). */
static zw_cert block_of(const cert_case *cc, float b_min, float b_max)
{
    zw_cert c;
    memset(&c, 0, sizeof c);
    c.m = (float)cc->box.m_lo;
    c.m_hi = (float)cc->box.m_hi;
    c.b = (float)cc->box.b_lo;
    c.b_hi = (float)cc->box.b_hi;
    c.T = (float)cc->box.T;
    c.sigma = CERT_CASE_SIGMA;
    c.r = 1.0f; /* required for a ranged block */
    c.k_min = 0.0f;
    c.k_max = CERT_CASE_K_MAX;
    c.b_min = b_min;
    c.b_max = b_max;
    c.dk_max = CERT_CASE_DK_MAX;
    c.db_max = b_max - b_min;
    c.delay = (float)cc->spec.delay;
    c.vfilter = 0.0f;
    c.vf_param = 0.0f;
    c.differentiator = 0.0f;
    return c;
}

/* zw_regmap_init_box of block c with certificate bc: instructions; *stack the bytes used. */
static unsigned long time_seal(const zw_cert *c, const zw_box_cert *bc, zw_status *st, zw_reason *why,
                               unsigned long *stack)
{
    uint32_t *top = paint();
    uint32_t t0, t1;
    *why = (zw_reason)999;
    t0 = now();
    *st = zw_regmap_init_box(&g_rm, c, bc, why);
    t1 = now();
    *stack = used(top);
    return insn(t0, t1);
}

/* One gain write, K and B (ZW_REG_K, 4 registers, as FC 0x10 writes them): instructions. */
static unsigned long time_write(float K, float B, zw_mb_exception *exc, zw_reason *why)
{
    uint_least16_t w[4];
    uint32_t t0, t1;
    zw_float_to_words(K, &w[0]);
    zw_float_to_words(B, &w[2]);
    *why = (zw_reason)999;
    t0 = now();
    *exc = zw_regmap_write(&g_rm, ZW_REG_K, 4u, w, why);
    t1 = now();
    return insn(t0, t1);
}

static float read_float(uint_least16_t addr)
{
    uint_least16_t w[2] = {0u, 0u};
    (void)zw_regmap_read(&g_rm, addr, 2u, w, NULL);
    return zw_words_to_float(w);
}

static void fail_s(const char *what, unsigned box)
{
    out_s("FAIL box ");
    out_u(box);
    out_s(": ");
    out_s(what);
    out_end();
}

/* The register map over box i+1: its "RM" line; 1 when something failed. */
static int regmap_case(unsigned i, const cert_case *cc)
{
    const zw_box_cert *bc = &cc->cert;
    const unsigned n = bc->n_steps;
    const float lo = bc->B[0], hi = bc->B[n], w = hi - lo;
    const float B_acc = 0.5f * (bc->B[3] + bc->B[4]), B_above = 0.5f * (bc->B[10] + bc->B[11]);
    const float B_out = hi + 0.125f * w;
    zw_cert c = block_of(cc, lo, hi), wide = block_of(cc, lo - 0.25f * w, hi + 0.25f * w);
    zw_status st = ZW_ERR_ARG, wst = ZW_ERR_ARG, self;
    zw_reason why = ZW_REASON_NONE, wwhy = ZW_REASON_NONE, acc_why, above_why, out_why;
    zw_mb_exception acc_exc, above_exc, out_exc;
    unsigned long seal, seal_stack, wseal, wseal_stack, self_insn, acc, above, out;
    float L_acc = 0.0f, L_above = 0.0f, K_now = -1.0f, B_now = -1.0f;
    bool in_acc = false, in_above = false, in_out = true, live_ok;
    uint32_t t0, t1;
    int failed = 0;

    zw_box_cert_level(bc, B_acc, &L_acc, &in_acc);
    zw_box_cert_level(bc, B_above, &L_above, &in_above);
    zw_box_cert_level(bc, B_out, &K_now, &in_out);
    t0 = now();
    self = zw_selftest();
    t1 = now();
    self_insn = insn(t0, t1);

    seal = time_seal(&c, bc, &st, &why, &seal_stack);
    acc = time_write(0.5f * L_acc, B_acc, &acc_exc, &acc_why);
    (void)zw_regmap_active_gains(&g_rm, &K_now, &B_now);
    live_ok = same_float(K_now, 0.5f * L_acc) && same_float(B_now, B_acc) &&
              same_float(read_float(ZW_REG_LIVE_K_MAX), L_acc);
    above = time_write(1.1f * L_above, B_above, &above_exc, &above_why);

    wseal = time_seal(&wide, bc, &wst, &wwhy, &wseal_stack);
    out = time_write(0.5f * L_acc, B_out, &out_exc, &out_why);

    out_s("RM");
    out_kv("box", i + 1u);
    out_kv("selftest_insn", self_insn);
    out_kv("seal_status", (unsigned long)st);
    out_kv("seal_reason", (unsigned long)why);
    out_kv("seal_insn", seal);
    out_kv("seal_stack", seal_stack);
    out_kv("acc_exc", (unsigned long)acc_exc);
    out_kv("acc_reason", (unsigned long)acc_why);
    out_kv("acc_insn", acc);
    out_kv("live_ok", live_ok ? 1ul : 0ul);
    out_kv("above_exc", (unsigned long)above_exc);
    out_kv("above_reason", (unsigned long)above_why);
    out_kv("above_insn", above);
    out_kv("wide_seal_status", (unsigned long)wst);
    out_kv("wide_seal_reason", (unsigned long)wwhy);
    out_kv("wide_seal_insn", wseal);
    out_kv("out_exc", (unsigned long)out_exc);
    out_kv("out_reason", (unsigned long)out_why);
    out_kv("out_insn", out);
    out_end();

    if (self != ZW_OK) {
        fail_s("zw_selftest is not ZW_OK", i + 1u);
        failed = 1;
    }
    if (!in_acc || !in_above || in_out || !(L_acc > 0.0f) || !(L_above > 0.0f)) {
        fail_s("the write's B are not where the staircase was expected", i + 1u);
        failed = 1;
    }
    if (st != ZW_OK || why != ZW_REASON_NONE) {
        out_s("FAIL box ");
        out_u(i + 1u);
        out_s(": zw_regmap_init_box: ");
        out_s(zw_status_name(st));
        out_s(", ");
        out_s(zw_reason_name(why));
        out_end();
        failed = 1;
    }
    if (wst != ZW_OK || wwhy != ZW_REASON_NONE) {
        out_s("FAIL box ");
        out_u(i + 1u);
        out_s(": zw_regmap_init_box (B range widened): ");
        out_s(zw_status_name(wst));
        out_s(", ");
        out_s(zw_reason_name(wwhy));
        out_end();
        failed = 1;
    }
    if (seal > SEAL_LIMIT || wseal > SEAL_LIMIT) {
        out_s("FAIL box ");
        out_u(i + 1u);
        out_s(": SEAL over SEAL_LIMIT instructions: ");
        out_u(SEAL_LIMIT);
        out_end();
        failed = 1;
    }
    if (acc_exc != ZW_MB_OK || acc_why != ZW_REASON_NONE) {
        out_s("FAIL box ");
        out_u(i + 1u);
        out_s(": the write at half the level is refused: ");
        out_s(zw_reason_name(acc_why));
        out_end();
        failed = 1;
    } else if (!live_ok) {
        fail_s("after the accepted write the gains or LIVE_K_MAX are not the written pair / the level", i + 1u);
        failed = 1;
    }
    if (above_exc != ZW_MB_ILLEGAL_VALUE || above_why != ZW_REASON_ABOVE_SIGMA) {
        out_s("FAIL box ");
        out_u(i + 1u);
        out_s(": the write above the level is not refused ZW_REASON_ABOVE_SIGMA: ");
        out_s(zw_reason_name(above_why));
        out_end();
        failed = 1;
    }
    if (out_exc != ZW_MB_ILLEGAL_VALUE || out_why != ZW_REASON_OUTSIDE_CERT) {
        out_s("FAIL box ");
        out_u(i + 1u);
        out_s(": the write outside the staircase is not refused ZW_REASON_OUTSIDE_CERT: ");
        out_s(zw_reason_name(out_why));
        out_end();
        failed = 1;
    }
    if (acc > WRITE_LIMIT || above > WRITE_LIMIT || out > WRITE_LIMIT) {
        out_s("FAIL box ");
        out_u(i + 1u);
        out_s(": a write over WRITE_LIMIT instructions: ");
        out_u(WRITE_LIMIT);
        out_end();
        failed = 1;
    }
    return failed;
}

int main(void)
{
    unsigned i, j;
    int failed = 0;
    uint32_t t0, t1;
    unsigned long calib;

    TIMER0[0] = 0u;
    TIMER0[2] = 0xFFFFFFFFu;
    TIMER0[1] = 0xFFFFFFFFu;
    TIMER0[0] = 1u;
    t0 = now();
    calib_loop();
    t1 = now();
    calib = insn(t0, t1);
    out_s("CALIB");
    out_kv("insn", calib);
    out_kv("expected", CALIB_INSN);
    out_end();
    if (calib + 2ul * INSN_PER_TICK < CALIB_INSN || calib > CALIB_INSN + 2ul * INSN_PER_TICK) {
        out_s("FAIL calibration: the timer does not count 40 instructions a tick (-icount shift=0?)");
        out_end();
        failed = 1;
    }
    if (zw_box_loop_work_init(&g_work, g_cells, ZW_BOX_CERT_STACK, &g_scratch) != ZW_OK) {
        out_s("FAIL zw_box_loop_work_init");
        out_end();
        return 1;
    }
    for (i = 0u; i < cert_n_cases; ++i) {
        const cert_case *cc = &cert_cases[i];
        zw_box_cert_fault fault = ZW_BOX_CERT_BAD_HEADER, bad_fault = ZW_BOX_CERT_OK;
        uint_least32_t leaves = 0u, bad_leaves = 0u;
        zw_status st, bad_st;
        unsigned long v_insn, v_stack, bad_insn, lk_max = 0ul, base;
        bool lookups_ok = true;
        uint32_t *top;

        top = paint();
        t0 = now();
        st = zw_box_cert_verify(&cc->box, &cc->spec, &cc->cert, &g_work, &fault, &leaves);
        t1 = now();
        v_insn = insn(t0, t1);
        v_stack = used(top);

        base = time_level(empty_level, &cc->cert, cc->lookup_B[0]);
        for (j = 0u; j < CERT_CASE_LOOKUPS; ++j) {
            float K = -1.0f;
            bool in = false;
            unsigned long t = time_level(zw_box_cert_level, &cc->cert, cc->lookup_B[j]);
            /* instructions inside zw_box_cert_level per call, in hundredths */
            unsigned long per100 = (t > base ? (t - base) / (LOOKUP_REPS / 100u) : 0ul) + 100ul;
            if (per100 > lk_max) {
                lk_max = per100;
            }
            zw_box_cert_level(&cc->cert, cc->lookup_B[j], &K, &in);
            if (in != cc->lookup_inside[j] || !same_float(K, cc->lookup_K[j])) {
                lookups_ok = false;
            }
        }

        g_bad_cert = cc->cert;
        g_bad_cert.K[cc->corrupt_step] *= 2.0f;
        t0 = now();
        bad_st = zw_box_cert_verify(&cc->box, &cc->spec, &g_bad_cert, &g_work, &bad_fault, &bad_leaves);
        t1 = now();
        bad_insn = insn(t0, t1);

        out_s("BOX");
        out_kv("box", i + 1u);
        out_kv("status", (unsigned long)st);
        out_kv("fault", (unsigned long)fault);
        out_kv("leaves", (unsigned long)leaves);
        out_kv("host_leaves", (unsigned long)cc->host_leaves);
        out_kv("nodes", (unsigned long)cc->cert.n_nodes);
        out_kv("verify_insn", v_insn);
        out_kv("per_leaf", leaves ? v_insn / leaves : 0ul);
        out_kv("stack", v_stack);
        out_hundredths("lookup_insn", lk_max);
        out_kv("lookups_ok", lookups_ok ? 1ul : 0ul);
        out_kv("corrupt_step", cc->corrupt_step);
        out_kv("bad_status", (unsigned long)bad_st);
        out_kv("bad_fault", (unsigned long)bad_fault);
        out_kv("bad_leaves", (unsigned long)bad_leaves);
        out_kv("bad_insn", bad_insn);
        out_s(" name=");
        out_s(cc->name); /* last: it has spaces */
        out_end();

        if (st != ZW_OK || fault != ZW_BOX_CERT_OK) {
            out_s("FAIL verification fault on the M4F (the host's: ");
            out_u((unsigned long)cc->host_fault);
            out_s(")");
            out_end();
            failed = 1;
        } else if (leaves != cc->host_leaves) {
            out_s("FAIL leaves differ from the host's");
            out_end();
            failed = 1;
        }
        if (v_insn > VERIFY_LIMIT) {
            out_s("FAIL verify over VERIFY_LIMIT instructions: ");
            out_u(VERIFY_LIMIT);
            out_end();
            failed = 1;
        }
        if (!lookups_ok) {
            out_s("FAIL zw_box_cert_level differs from the host's");
            out_end();
            failed = 1;
        }
        if (bad_fault == ZW_BOX_CERT_OK) {
            out_s("FAIL the corrupted copy is accepted");
            out_end();
            failed = 1;
        }
    }
    out_s("SIZE");
    out_kv("regmap", (unsigned long)sizeof(zw_regmap));
    out_kv("box_cert", (unsigned long)sizeof(zw_box_cert));
    out_kv("limit", REGMAP_SIZE_LIMIT);
    out_end();
    if ((unsigned long)sizeof(zw_regmap) > REGMAP_SIZE_LIMIT) {
        out_s("FAIL sizeof(zw_regmap) over REGMAP_SIZE_LIMIT bytes");
        out_end();
        failed = 1;
    }
    for (i = 0u; i < cert_n_cases; ++i) {
        if (regmap_case(i, &cert_cases[i]) != 0) {
            failed = 1;
        }
    }
    out_s(failed ? "DONE fail" : "DONE ok");
    out_end();
    return failed;
}
