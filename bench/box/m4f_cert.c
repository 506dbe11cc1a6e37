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
 * Exit status (main's return: 0 -> QEMU exits 0): 1 when the calibration is off, a
 * verification is not ZW_BOX_CERT_OK, its leaves differ from the host's, a lookup differs
 * from the host's, the corrupted copy is accepted, or a verify exceeds VERIFY_LIMIT
 * instructions. */
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
#define LOOKUP_REPS 1000u
#define CALIB_ITER 100000u
#define CALIB_INSN (2ul * CALIB_ITER + 3ul) /* movw, movt, CALIB_ITER x (subs, bne), bx lr */

extern uint32_t _ebss;

static zw_box_loop_cell g_cells[ZW_BOX_CERT_STACK];
static zw_box_loop_scratch g_scratch;
static zw_box_loop_work g_work;
static zw_box_cert g_bad_cert;

/* ---- output: one line built in a buffer, written with SYS_WRITE0 */
static char g_line[256];
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
static uint32_t now(void) { return TIMER0[1]; } /* VALUE: counts down */
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
    out_s(failed ? "DONE fail" : "DONE ok");
    out_end();
    return failed;
}
