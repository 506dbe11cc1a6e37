/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth-tune: read the state of a zwidth drive and write its gains over Modbus.
 *
 *   zwidth-tune status                 mode, sealed, plant, policy, gains, live limits, ...
 *   zwidth-tune set --K K --B B        one Write Multiple Registers request, then the verdict
 *   zwidth-tune save                   SAVE: the sealed block and the gains to the drive's storage
 *   zwidth-tune commission --m .. ..   unlock, write the certified block and its CRC, seal
 *
 * Register map: csrc/include/zwidth/regmap.h and docs/modbus.md.
 */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <arpa/inet.h>

#include <modbus.h>

#include "box_cert_glue.h"
#include "zw_mbhost.h"
#include "zwidth/version.h"

#define PROG "zwidth-tune"


/* Least wait for SEAL's answer, in seconds (cmd_commission). */
#define SEAL_TIMEOUT_S 30u
static void usage(FILE *to)
{
    fprintf(to,
            "usage: zwidth-tune [connection] status [--json]\n"
            "       zwidth-tune [connection] set [--K K] [--B B] [--json]\n"
            "       zwidth-tune [connection] save [--json]\n"
            "       zwidth-tune [connection] commission --m M[:M_HI] --b B[:B_HI] --T T --sigma S --r R\n"
            "                   --k-min K --k-max K --b-min B --b-max B --dk-max D --db-max D\n"
            "                   [--delay D] [--velocity-filter none|lowpass:F[Hz]|average:N]\n"
            "                   [--differentiator backward|tustin] [--paper-defaults] [--json]\n"
            "                   [--cert-b LO:HI] --key-file PATH\n"
            "\n"
            "Talks to a zwidth drive (zwidth-drive, or firmware with the same register map).\n"
            "\n"
            "  status      print mode, sealed, plant and policy, active gains, live limits,\n"
            "              device state, counters and the last refusal (reason, exception)\n"
            "  set         write K and B in ONE Write Multiple Registers request (judged as a\n"
            "              pair), or one of them alone; then read back and print the verdict\n"
            "  save        SAVE (0x5A7E to COMMAND): the drive writes its sealed block and the\n"
            "              active gains to non-volatile storage, restored at power-up\n"
            "              (zwidth-drive --state-file); then say what was saved, or why not\n"
            "  commission  unlock (two command writes), read the drive's nonce, write the\n"
            "              certified block, its CRC-16 and an HMAC-SHA256 of nonce and block\n"
            "              under the drive's key (--key-file: 64 hex digits, mode 600), seal;\n"
            "              then read back mode, block and CRC and say what the drive did.  On\n"
            "              a refused step the commissioning is aborted (the last sealed block\n"
            "              comes back).  Gains are off afterwards, also after a refusal (the\n"
            "              UNLOCK turned the output off): set them again.  The drive must consent\n"
            "              (zwidth-drive --commissioning --key-file)\n"
            "              --paper-defaults takes omitted fields from the paper's drive\n"
            "              (J = 85.78e-7, b = 2.197e-3, T = 0.02, sigma 0.8, r 0.999, K in\n"
            "              [0, 10], B in [-0.01, 0.01], dK 1, dB 0.01).  The loop the drive\n"
            "              runs (default: the ideal one) is part of the block: --delay D\n"
            "              samples (0..8), --velocity-filter lowpass:30Hz or average:4,\n"
            "              --differentiator tustin; the drive certifies gains for it.\n"
            "              Plant ranges (map version 4): --m LO:HI and/or --b LO:HI (or\n"
            "              --m-hi, --b-hi) commission a box of plants: every gain write is\n"
            "              then certified for every plant of the box (needs --r 1).  With\n"
            "              ranges, a box certificate is built here first, in the drive's\n"
            "              precision (its PRECISION register; map version 5), and sent with\n"
            "              the block: the drive verifies it at SEAL in bounded time and every\n"
            "              gain write is a lookup in its staircase of K limits over B.\n"
            "              --cert-b LO:HI: the staircase's B range (default: [b-min, b-max]\n"
            "              cut to the B the box certifies at half its K_mmax); gain writes\n"
            "              with B outside it are refused (ZW_REASON_OUTSIDE_CERT)\n"
            "\n"
            "Connection (Modbus TCP by default)\n"
            "  --host ADDR     drive address (default 127.0.0.1)\n"
            "  --port N        TCP port (default 1502)\n"
            "  --rtu DEVICE    use Modbus RTU on this serial device instead\n"
            "  --baud N        RTU baud rate (default 19200)\n"
            "  --parity P      RTU parity N, E or O (default N)\n"
            "  --slave ID      RTU slave address 1..247 / TCP unit id 0..255 (default 1)\n"
            "  --timeout MS    response timeout (default 1000; SEAL waits at least 30 s)\n"
            "  --word-order W  auto (default: as the drive's WORD_ORDER register says), abcd\n"
            "                  (high word first) or cdab (low word first, zwidth-drive\n"
            "                  --word-order cdab): floats and 32-bit values; a drive that\n"
            "                  speaks the other order is refused\n"
            "  --json          machine-readable output (one JSON object on stdout)\n"
            "  --version       print the version of zwidth and exit\n"
            "\n"
            "Exit status: 0 done (set: accepted; save: saved; commission: sealed), 3 the drive refused\n"
            "(reason and exception printed), 2 bad arguments, connection or protocol error.\n");
}

typedef struct conn_opts {
    const char *host, *rtu;
    long port, baud, slave, timeout_ms;
    char parity;
    int word_order; /* -1 auto, else ZW_WORD_ORDER_ABCD / _CDAB */
} conn_opts;

/* The drive's word order (read_head sets it from WORD_ORDER): every two-register value is
 * turned into ABCD right after a read and back into the drive's order right before a
 * write, so that everything in between (decoding, the block's CRC, the MAC) sees ABCD. */
static int g_want_order = -1;
static int g_cdab = 0;

/* swap the two words of each pair in w[0..n-1] (n even) when the drive speaks CDAB */
static void wire_pairs(uint_least16_t *w, int n)
{
    int i;
    if (!g_cdab) return;
    for (i = 0; i + 1 < n; i += 2) {
        uint_least16_t t = w[i];
        w[i] = w[i + 1];
        w[i + 1] = t;
    }
}

/* ---------------------------------------------------------------------------------------
 * Register access
 * ------------------------------------------------------------------------------------- */

/* The exception code of a failed libmodbus call (0 when it was not an exception). */
static unsigned exception_of(int err)
{
    if (err > MODBUS_ENOBASE && err <= EMBXGTAR) return (unsigned)(err - MODBUS_ENOBASE);
    return 0;
}

static int read_regs(modbus_t *ctx, int addr, int n, uint_least16_t *out, unsigned *exc)
{
    uint16_t buf[125];
    int i;
    *exc = 0;
    if (modbus_read_registers(ctx, addr, n, buf) != n) {
        *exc = exception_of(errno);
        return -1;
    }
    for (i = 0; i < n; ++i) out[i] = buf[i];
    return 0;
}

static int write_regs(modbus_t *ctx, int addr, int n, const uint_least16_t *in, unsigned *exc)
{
    uint16_t buf[123];
    int i;
    for (i = 0; i < n; ++i) buf[i] = (uint16_t)in[i];
    *exc = 0;
    if (modbus_write_registers(ctx, addr, n, buf) != n) {
        *exc = exception_of(errno);
        return -1;
    }
    return 0;
}

static int write_reg(modbus_t *ctx, int addr, unsigned value, unsigned *exc)
{
    *exc = 0;
    if (modbus_write_register(ctx, addr, (uint16_t)value) != 1) {
        *exc = exception_of(errno);
        return -1;
    }
    return 0;
}

static uint_least32_t u32_at(const uint_least16_t *w)
{
    return ((uint_least32_t)w[0] << 16) | (uint_least32_t)w[1];
}

/* What status shows. */
typedef struct snapshot {
    uint_least16_t head[10];  /* 0x00..0x09 */
    uint_least16_t gains[4];  /* 0x10..0x13 */
    uint_least16_t live[24];  /* 0x20..0x37 */
    uint_least16_t cert[ZW_CERT_WORDS + 1u];  /* 0x40..0x62: the block and its CRC */
    uint_least16_t stairs[ZW_BOX_CERT_WORD_NODES]; /* 0x100..0x143: the box certificate's
                                                       header, breakpoints and levels */
    int have_live, have_cert, have_stairs;
    unsigned cert_exc;
} snapshot;

static int protocol_error(const char *what)
{
    fprintf(stderr, PROG ": %s: %s\n", what, modbus_strerror(errno));
    return ZW_EXIT_USAGE;
}

/* Read the header (first, so the last refusal is the drive's, not ours) and the gains. */
static int read_head(modbus_t *ctx, snapshot *s)
{
    unsigned exc;
    if (read_regs(ctx, ZW_REG_MAGIC, 10, s->head, &exc) != 0)
        return protocol_error("cannot read the status registers");
    if (s->head[0] != ZW_REGMAP_MAGIC) {
        fprintf(stderr, PROG ": not a zwidth drive (register 0 reads 0x%04X, not 0x%04X)\n",
                (unsigned)s->head[0], ZW_REGMAP_MAGIC);
        return ZW_EXIT_USAGE;
    }
    if (s->head[1] != ZW_REGMAP_VERSION) { /* the block's layout differs between versions */
        fprintf(stderr, PROG ": the drive speaks register map v%u; this tool speaks v%u "
                        "(docs/modbus.md, map versions)\n", (unsigned)s->head[1], ZW_REGMAP_VERSION);
        return ZW_EXIT_USAGE;
    }
    {
        uint_least16_t order[1]; /* a one-register value: the same in both orders */
        if (read_regs(ctx, ZW_REG_WORD_ORDER, 1, order, &exc) != 0)
            return protocol_error("cannot read the word order");
        if (order[0] != ZW_WORD_ORDER_ABCD && order[0] != ZW_WORD_ORDER_CDAB) {
            fprintf(stderr, PROG ": the drive reports word order %u (neither 0 ABCD nor 1 CDAB)\n",
                    (unsigned)order[0]);
            return ZW_EXIT_USAGE;
        }
        if (g_want_order >= 0 && (unsigned)g_want_order != order[0]) { /* would read wrong */
            fprintf(stderr, PROG ": the drive sends floats %s; --word-order %s says %s "
                            "(leave --word-order out, or give --word-order %s)\n",
                    order[0] == ZW_WORD_ORDER_CDAB ? "low word first (CDAB)" : "high word first (ABCD)",
                    g_want_order == (int)ZW_WORD_ORDER_CDAB ? "cdab" : "abcd",
                    g_want_order == (int)ZW_WORD_ORDER_CDAB ? "low word first" : "high word first",
                    order[0] == ZW_WORD_ORDER_CDAB ? "cdab" : "abcd");
            return ZW_EXIT_USAGE;
        }
        g_cdab = order[0] == ZW_WORD_ORDER_CDAB;
    }
    wire_pairs(&s->head[6], 4); /* the two counters */
    if (read_regs(ctx, ZW_REG_K, 4, s->gains, &exc) != 0)
        return protocol_error("cannot read the gains");
    wire_pairs(s->gains, 4);
    return ZW_EXIT_OK;
}

static int read_snapshot(modbus_t *ctx, snapshot *s)
{
    unsigned exc;
    int rc = read_head(ctx, s);
    if (rc != ZW_EXIT_OK) return rc;
    s->have_live = read_regs(ctx, ZW_REG_LIVE_K_MAX, 24, s->live, &exc) == 0;
    if (!s->have_live) return protocol_error("cannot read the live limits");
    wire_pairs(s->live, 24); /* 0x20..0x37: all floats, and the u32 step */
    s->have_cert = read_regs(ctx, ZW_REG_CERT_M, (int)ZW_CERT_WORDS + 1, s->cert, &s->cert_exc) == 0;
    if (!s->have_cert && s->cert_exc == 0) return protocol_error("cannot read the certified block");
    if (s->have_cert) wire_pairs(s->cert, (int)ZW_CERT_WORDS); /* not the CRC word */
    s->have_stairs = read_regs(ctx, ZW_REG_BOX_CERT, (int)ZW_BOX_CERT_WORD_NODES, s->stairs, &exc) == 0;
    if (!s->have_stairs && exc == 0) return protocol_error("cannot read the box certificate");
    if (s->have_stairs)
        wire_pairs(&s->stairs[ZW_BOX_CERT_WORD_B], (int)(ZW_BOX_CERT_WORD_NODES - ZW_BOX_CERT_WORD_B));
    return ZW_EXIT_OK;
}

/* Steps of the box certificate the snapshot shows (0: none, or not readable; at most 16). */
static unsigned stairs_steps(const snapshot *s)
{
    unsigned n = s->have_stairs ? (unsigned)s->stairs[0] : 0u;
    return n <= ZW_BOX_CERT_MAX_STEPS ? n : 0u;
}

static float stairs_B(const snapshot *s, unsigned i) { return zw_words_to_float(&s->stairs[ZW_BOX_CERT_WORD_B + 2u * i]); }
static float stairs_K(const snapshot *s, unsigned i) { return zw_words_to_float(&s->stairs[ZW_BOX_CERT_WORD_K + 2u * i]); }

static float fw(const uint_least16_t *w) { return zw_words_to_float(w); }

static const char *const live_label[8] = {"K_max", "K_cert", "B_lo", "B_hi",
                                          "K_mmax", "B_at_K_mmax", "rho", "delta"};

static void print_snapshot_text(const snapshot *s)
{
    char loop[200], plant[200];
    int k;
    unsigned reason = (unsigned)s->head[4], exc = (unsigned)s->head[5];
    printf("drive      : zwidth register map v%u, %s mode, %s\n", (unsigned)s->head[1],
           s->head[2] == 1 ? "commissioning" : "operation",
           s->head[3] ? "sealed" : "NOT sealed (gains refused until commissioned)");
    printf("gains      : K = %.9g, B = %.9g%s\n", (double)fw(&s->gains[0]),
           (double)fw(&s->gains[2]),
           (fw(&s->gains[0]) == 0.0f && fw(&s->gains[2]) == 0.0f) ? "  (output off)" : "");
    if (s->have_cert) {
        zw_cert c;
        zw_cert_decode(s->cert, &c);
        zw_cert_plant_text(&c, plant, sizeof plant);
        printf("plant      : %s\n", plant);
        printf("policy     : sigma = %.9g, r = %.9g, K in [%.9g, %.9g], B in [%.9g, %.9g],\n"
               "             |dK| <= %.9g, |dB| <= %.9g per write; CRC 0x%04X\n",
               (double)c.sigma, (double)c.r, (double)c.k_min, (double)c.k_max, (double)c.b_min,
               (double)c.b_max, (double)c.dk_max, (double)c.db_max, (unsigned)s->cert[ZW_CERT_WORDS]);
        zw_cert_loop_text(&c, loop, sizeof loop);
        printf("loop       : %s\n", loop);
        if (stairs_steps(s) > 0u) {
            unsigned i, n = stairs_steps(s);
            float lo = stairs_K(s, 0u), hi = lo;
            for (i = 1u; i < n; ++i) {
                lo = stairs_K(s, i) < lo ? stairs_K(s, i) : lo;
                hi = stairs_K(s, i) > hi ? stairs_K(s, i) : hi;
            }
            printf("certificate: %u steps over B in [%.9g, %.9g], K levels %.9g .. %.9g (%u proof\n"
                   "             nodes; every gain write is a lookup)\n", n, (double)stairs_B(s, 0u),
                   (double)stairs_B(s, n), (double)lo, (double)hi, (unsigned)s->stairs[1]);
        } else if (zw_cert_ranged(&c)) {
            printf("certificate: none (every gain write runs the drive's box search)\n");
        }
    } else {
        printf("plant      : certified block not readable (exception 0x%02X %s)\n", s->cert_exc,
               zw_exception_name(s->cert_exc));
    }
    printf("live limits:");
    for (k = 0; k < 8; ++k)
        printf("%s %s = %.9g", k == 4 ? "\n            " : (k ? "," : ""), live_label[k],
               (double)fw(&s->live[2 * k]));
    printf("\nstate      : x = %.9g, v = %.9g, F = %.9g, step %lu\n", (double)fw(&s->live[16]),
           (double)fw(&s->live[18]), (double)fw(&s->live[20]), (unsigned long)u32_at(&s->live[22]));
    printf("counters   : %lu accepted gain changes, %lu refused requests\n",
           (unsigned long)u32_at(&s->head[6]), (unsigned long)u32_at(&s->head[8]));
    if (reason == 0 && exc == 0)
        printf("last refusal: none\n");
    else
        printf("last refusal: %s (exception 0x%02X %s)\n", zw_reason_name((zw_reason)reason), exc,
               zw_exception_name(exc));
}

static void json_kv_float(const char *key, double v, int comma)
{
    printf("%s\"%s\": ", comma ? ", " : "", key);
    zw_json_float(stdout, v);
}

/* The reason of a refusal whose LAST_EXCEPTION is not the one our request got: another
 * client's.  zw_reason_name() names it "ZW_REASON_UNKNOWN", as the Python client does. */
#define REASON_NOT_OURS 0xFFFFu

static void print_refusal_json(unsigned reason, unsigned exc)
{
    printf("\"reason\": ");
    zw_json_string(stdout, zw_reason_name((zw_reason)reason));
    printf(", \"reason_code\": %u, \"exception\": %u, \"exception_name\": ", reason, exc);
    zw_json_string(stdout, zw_exception_name(exc));
}

static void print_snapshot_json(const snapshot *s)
{
    int k;
    printf("{\"magic\": %u, \"version\": %u, \"mode\": ", (unsigned)s->head[0],
           (unsigned)s->head[1]);
    zw_json_string(stdout, s->head[2] == 1 ? "commissioning" : "operation");
    printf(", \"sealed\": %s, ", s->head[3] ? "true" : "false");
    printf("\"gains\": {");
    json_kv_float("K", (double)fw(&s->gains[0]), 0);
    json_kv_float("B", (double)fw(&s->gains[2]), 1);
    printf("}, \"cert\": ");
    if (s->have_cert) {
        zw_cert c;
        zw_cert_decode(s->cert, &c);
        printf("{");
        for (k = 0; k < ZW_CERT_NFIELDS; ++k)
            json_kv_float(zw_cert_label[k], (double)zw_cert_field(&c, (unsigned)k), k > 0);
        printf(", \"crc\": %u}", (unsigned)s->cert[ZW_CERT_WORDS]);
    } else {
        printf("null");
    }
    printf(", \"box_certificate\": ");
    if (stairs_steps(s) > 0u) {
        unsigned i, n = stairs_steps(s);
        printf("{\"steps\": %u, \"nodes\": %u, \"B\": [", n, (unsigned)s->stairs[1]);
        for (i = 0u; i <= n; ++i) {
            if (i) printf(", ");
            zw_json_float(stdout, (double)stairs_B(s, i));
        }
        printf("], \"K\": [");
        for (i = 0u; i < n; ++i) {
            if (i) printf(", ");
            zw_json_float(stdout, (double)stairs_K(s, i));
        }
        printf("]}");
    } else {
        printf("null");
    }
    printf(", \"live\": {");
    for (k = 0; k < 8; ++k) json_kv_float(live_label[k], (double)fw(&s->live[2 * k]), k > 0);
    printf("}, \"state\": {");
    json_kv_float("x", (double)fw(&s->live[16]), 0);
    json_kv_float("v", (double)fw(&s->live[18]), 1);
    json_kv_float("F", (double)fw(&s->live[20]), 1);
    printf(", \"step\": %lu}", (unsigned long)u32_at(&s->live[22]));
    printf(", \"accepted\": %lu, \"refused\": %lu, \"last_refusal\": {",
           (unsigned long)u32_at(&s->head[6]), (unsigned long)u32_at(&s->head[8]));
    print_refusal_json((unsigned)s->head[4], (unsigned)s->head[5]);
    printf("}}\n");
}

/* ---------------------------------------------------------------------------------------
 * Commands
 * ------------------------------------------------------------------------------------- */

static int cmd_status(modbus_t *ctx, int json)
{
    snapshot s;
    int rc = read_snapshot(ctx, &s);
    if (rc != ZW_EXIT_OK) return rc;
    if (json) print_snapshot_json(&s);
    else print_snapshot_text(&s);
    return ZW_EXIT_OK;
}

static int cmd_set(modbus_t *ctx, int have_K, double K, int have_B, double B, int json)
{
    uint_least16_t w[4];
    unsigned exc;
    int addr = have_K ? ZW_REG_K : ZW_REG_B, n = 0, wrc, err, rc;
    snapshot after;

    if (have_K) {
        zw_float_to_words((float)K, &w[n]);
        n += 2;
    }
    if (have_B) {
        zw_float_to_words((float)B, &w[n]);
        n += 2;
    }
    rc = read_head(ctx, &after); /* a zwidth drive, and its word order, before writing */
    if (rc != ZW_EXIT_OK) return rc;
    wire_pairs(w, n);
    wrc = write_regs(ctx, addr, n, w, &exc);
    err = errno;
    if (wrc != 0 && exc == 0) {
        errno = err;
        return protocol_error("cannot write the gains");
    }
    rc = read_head(ctx, &after); /* the verdict's context: reason, active gains */
    if (rc != ZW_EXIT_OK) return rc;

    if (wrc == 0) {
        if (json) {
            printf("{\"verdict\": \"accepted\"");
            json_kv_float("K", (double)fw(&after.gains[0]), 1);
            json_kv_float("B", (double)fw(&after.gains[2]), 1);
            printf(", \"requests\": 1}\n");
        } else {
            printf("accepted: active gains K = %.9g, B = %.9g\n", (double)fw(&after.gains[0]),
                   (double)fw(&after.gains[2]));
        }
        return ZW_EXIT_OK;
    }
    /* Refused: the exception came in the answer; the reason is the drive's last refusal
     * (another client refused in between would show its own; the exception is ours). */
    {
        unsigned reason = (unsigned)after.head[4];
        if ((unsigned)after.head[5] != exc) reason = REASON_NOT_OURS; /* do not guess */
        if (json) {
            printf("{\"verdict\": \"refused\", ");
            print_refusal_json(reason, exc);
            json_kv_float("K", (double)fw(&after.gains[0]), 1);
            json_kv_float("B", (double)fw(&after.gains[2]), 1);
            printf("}\n");
        } else {
            printf("refused: %s (exception 0x%02X %s); active gains stay K = %.9g, B = %.9g\n",
                   zw_reason_name((zw_reason)reason), exc, zw_exception_name(exc),
                   (double)fw(&after.gains[0]), (double)fw(&after.gains[2]));
        }
    }
    return ZW_EXIT_REFUSED;
}

/* What the drive is doing now, in words: "in operation, block CRC 0x1234 sealed",
 * "in commissioning mode (output off)", or "state unknown (cannot read it)". */
static void drive_state_text(modbus_t *ctx, char *buf, size_t cap)
{
    uint_least16_t head[4], crc[1];
    unsigned exc;
    if (read_regs(ctx, ZW_REG_MAGIC, 4, head, &exc) != 0) {
        snprintf(buf, cap, "state unknown (cannot read it)");
    } else if (head[2] != 0u) {
        snprintf(buf, cap, "in commissioning mode (output off)");
    } else if (head[3] == 0u) {
        snprintf(buf, cap, "in operation with no sealed block (gains refused)");
    } else if (read_regs(ctx, ZW_REG_CERT_CRC, 1, crc, &exc) == 0) {
        snprintf(buf, cap, "in operation, sealed block CRC 0x%04X", (unsigned)crc[0]);
    } else {
        snprintf(buf, cap, "in operation with a sealed block");
    }
}

/* A refused commissioning step: report, leave commissioning mode if we entered it, and say
 * what the drive is doing afterwards (read back, not assumed). */
static int commission_refused(modbus_t *ctx, const char *step, unsigned exc, int abort_it,
                              int json)
{
    snapshot s;
    unsigned reason = REASON_NOT_OURS, abort_exc = 0, gexc = 0;
    int aborted = 0, have_gains;
    uint_least16_t g[4];
    char state[96];
    if (read_head(ctx, &s) == ZW_EXIT_OK && (unsigned)s.head[5] == exc)
        reason = (unsigned)s.head[4];
    if (abort_it) aborted = write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_ABORT, &abort_exc) == 0;
    drive_state_text(ctx, state, sizeof state);
    /* a refusal after the UNLOCK: the UNLOCK turned the output off, and neither the refusal
     * nor ABORT brings the old gains back; read what the drive holds now */
    have_gains = abort_it && read_regs(ctx, ZW_REG_K, 4, g, &gexc) == 0;
    if (have_gains) wire_pairs(g, 4);
    if (json) {
        printf("{\"verdict\": \"refused\", \"step\": ");
        zw_json_string(stdout, step);
        printf(", ");
        print_refusal_json(reason, exc);
        printf(", \"aborted\": %s, \"drive\": ", aborted ? "true" : "false");
        zw_json_string(stdout, state);
        if (have_gains) {
            printf(", \"gains\": {");
            json_kv_float("K", (double)fw(&g[0]), 0);
            json_kv_float("B", (double)fw(&g[2]), 1);
            printf("}, \"output_off\": %s", fw(&g[0]) == 0.0f && fw(&g[2]) == 0.0f ? "true" : "false");
        }
        printf("}\n");
    } else {
        printf("refused at %s: %s (exception 0x%02X %s)%s; the drive is now %s\n", step,
               zw_reason_name((zw_reason)reason), exc, zw_exception_name(exc),
               !abort_it ? ""
               : aborted ? "; we sent ABORT"
               : abort_exc != 0 ? "; ABORT refused (our session had already ended)"
                                : "; ABORT could not be sent",
               state);
        if (reason == ZW_REASON_NO_CONSENT)
            printf("the drive does not consent to commissioning: turn its commissioning "
                   "enable on (zwidth-drive --commissioning)\n");
        else if (reason == ZW_REASON_AUTH)
            printf("the drive did not accept our MAC: --key-file is not this drive's key "
                   "(or another client changed the staged block)\n");
        else if (reason == ZW_REASON_RNG)
            printf("the drive has no commissioning key or RNG (zwidth-drive --key-file)\n");
        if (have_gains && fw(&g[0]) == 0.0f && fw(&g[2]) == 0.0f)
            printf("the output is now off: gains K = 0, B = 0 (the UNLOCK turned it off; the "
                   "refusal and ABORT do not bring the old gains back); set gains again with "
                   "zwidth-tune set --K K --B B\n");
        else if (have_gains)
            printf("active gains now K = %.9g, B = %.9g (set since the UNLOCK turned the output "
                   "off)\n", (double)fw(&g[0]), (double)fw(&g[2]));
        else if (abort_it)
            printf("the UNLOCK turned the output off (gains 0, 0); set gains again with "
                   "zwidth-tune set --K K --B B once the drive is in operation\n");
    }
    return ZW_EXIT_REFUSED;
}

/* SAVE: the drive writes its sealed block and the active gains to its non-volatile
 * storage (restored at power-up); say what was saved, read back, or why not. */
static int cmd_save(modbus_t *ctx, int json)
{
    snapshot s;
    unsigned exc, reason;
    uint_least16_t crc[1];
    int rc = read_head(ctx, &s), src;
    if (rc != ZW_EXIT_OK) return rc;
    if (write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_SAVE, &exc) != 0) {
        if (exc == 0) return protocol_error("cannot send the save command");
        rc = read_head(ctx, &s);
        if (rc != ZW_EXIT_OK) return rc;
        reason = (unsigned)s.head[5] == exc ? (unsigned)s.head[4] : REASON_NOT_OURS;
        if (json) {
            printf("{\"verdict\": \"refused\", ");
            print_refusal_json(reason, exc);
            printf("}\n");
            return ZW_EXIT_REFUSED;
        }
        printf("refused: %s (exception 0x%02X %s); nothing was saved\n",
               zw_reason_name((zw_reason)reason), exc, zw_exception_name(exc));
        if (reason == ZW_REASON_NO_STORAGE)
            printf("the drive has no non-volatile storage (zwidth-drive --state-file PATH)\n");
        else if (reason == ZW_REASON_STORAGE)
            printf("the drive's storage reported a failure; the previous saved copy is unchanged\n");
        else if (reason == ZW_REASON_NOT_SEALED)
            printf("the drive has no sealed block to save: commission one first\n");
        else if (reason == ZW_REASON_BAD_COMMAND)
            printf("the drive is in commissioning mode: finish (SEAL) or ABORT first\n");
        else if (reason == ZW_REASON_NO_CONSENT)
            printf("the drive does not consent (its commissioning enable input is off: "
                   "zwidth-drive --commissioning)\n");
        return ZW_EXIT_REFUSED;
    }
    rc = read_head(ctx, &s); /* what was saved: the block in force and the gains, read back */
    if (rc != ZW_EXIT_OK) return rc;
    src = read_regs(ctx, ZW_REG_CERT_CRC, 1, crc, &exc) == 0;
    if (json) {
        printf("{\"verdict\": \"saved\", \"crc\": ");
        if (src) printf("%u", (unsigned)crc[0]);
        else printf("null");
        json_kv_float("K", (double)fw(&s.gains[0]), 1);
        json_kv_float("B", (double)fw(&s.gains[2]), 1);
        printf("}\n");
    } else {
        printf("saved: the drive stored its sealed block");
        if (src) printf(" (CRC 0x%04X)", (unsigned)crc[0]);
        printf(" and the active gains K = %.9g, B = %.9g; they are restored at power-up\n",
               (double)fw(&s.gains[0]), (double)fw(&s.gains[2]));
    }
    return ZW_EXIT_OK;
}

/* A transport failure after the drive may have entered commissioning mode: send ABORT
 * (best effort: drop a late answer, and reconnect once if the connection is gone), so the
 * drive does not stay in commissioning mode with the output off.  Exits 2. */
static int commission_transport_error(modbus_t *ctx, const char *what)
{
    int err = errno, aborted;
    unsigned exc = 0;
    (void)modbus_flush(ctx);
    aborted = write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_ABORT, &exc) == 0;
    if (!aborted && exc == 0) {
        modbus_close(ctx);
        aborted = modbus_connect(ctx) == 0 &&
                  write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_ABORT, &exc) == 0;
    }
    fprintf(stderr, PROG ": %s: %s; %s\n", what, modbus_strerror(err),
            aborted ? "sent ABORT: commissioning aborted, the last sealed block is back"
            : exc != 0 ? "ABORT refused: the drive is not in commissioning mode"
                       : "could not send ABORT either: the drive may stay in commissioning "
                         "mode (output off) until a client sends ABORT");
    return ZW_EXIT_USAGE;
}

/* A ranged block's box certificate (box_cert.h), built here in the drive's precision (its
 * PRECISION register) over B in cert_b (NULL: the block's B bounds cut to the B the box
 * certifies at half its K_mmax), before anything is sent.  ZW_EXIT_OK, or a usage error
 * with its message (nothing was sent then). */
static int build_box_cert(modbus_t *ctx, const zw_cert *c, const double *cert_b, zw_box_cert *out)
{
    zwb_box_args a;
    zwb_box_cert_result r;
    uint_least16_t precision;
    unsigned exc;
    double lo, hi;
    int single, rc;
    memset(&a, 0, sizeof a);
    a.box[0] = (double)c->m;
    a.box[1] = (double)(c->m_hi > 0.0f ? c->m_hi : c->m);
    a.box[2] = (double)c->b;
    a.box[3] = (double)(c->b_hi > 0.0f ? c->b_hi : c->b);
    a.box[4] = (double)c->T;
    a.delay = (unsigned)c->delay;
    a.differentiator = (int)c->differentiator;
    a.filter = (int)c->vfilter;
    a.average = a.filter == 2 ? (unsigned)c->vf_param : 0u;
    a.cutoff_or_pole = a.filter == 1 ? (double)c->vf_param : 0.0;
    if (read_regs(ctx, ZW_REG_PRECISION, 1, &precision, &exc) != 0)
        return protocol_error("cannot read the drive's PRECISION register");
    if (precision != 4u && precision != 8u) {
        fprintf(stderr, PROG ": the drive reports a precision of %u bytes (4 or 8 expected)\n",
                (unsigned)precision);
        return ZW_EXIT_USAGE;
    }
    single = precision == 4u;
    if (cert_b != NULL) {
        lo = cert_b[0];
        hi = cert_b[1];
    } else {
        fprintf(stderr, PROG ": finding the B range the box certifies (its K_mmax, then B at half "
                        "of it)...\n");
        rc = single ? zwb_box_cert_range_f(&a, &lo, &hi) : zwb_box_cert_range_d(&a, &lo, &hi);
        if (rc != 0) {
            fprintf(stderr, PROG ": %s: give the certificate's B range, --cert-b LO:HI\n",
                    rc == -2 ? "no B is certified over the box at half its K_mmax"
                    : rc == -1 ? "out of memory for the box search"
                               : "the box search failed");
            return ZW_EXIT_USAGE;
        }
        lo = lo > (double)c->b_min ? lo : (double)c->b_min;
        hi = hi < (double)c->b_max ? hi : (double)c->b_max;
    }
    if (!(lo < hi) || fabs(lo) > (double)FLT_MAX || fabs(hi) > (double)FLT_MAX ||
        (float)lo >= (float)hi) {
        fprintf(stderr, PROG ": the certificate's B range [%.9g, %.9g] is empty (within the "
                        "block's B bounds [%.9g, %.9g]): give --cert-b LO:HI\n",
                lo, hi, (double)c->b_min, (double)c->b_max);
        return ZW_EXIT_USAGE;
    }
    fprintf(stderr, PROG ": building the box certificate (%s, 16 steps over B in [%.9g, %.9g], "
                    "at most 512 leaves)...\n", single ? "float" : "double", lo, hi);
    rc = single ? zwb_box_cert_build_f(&a, (float)lo, (float)hi, 16u, 512u, 1e-4, out, &r)
                : zwb_box_cert_build_d(&a, (float)lo, (float)hi, 16u, 512u, 1e-4, out, &r);
    if (rc != 0 || r.status != 0) {
        fprintf(stderr, PROG ": the box certificate cannot be built (%s)\n",
                rc != 0 ? "out of memory" : "the box or its loop is refused by the core");
        return ZW_EXIT_USAGE;
    }
    if (r.failed_step < 16u) {
        const double width = (hi - lo) / 16.0;
        fprintf(stderr, PROG ": step %u of the box certificate (B in [%.6g, %.6g]) is proven at no "
                        "K: narrow --cert-b away from the edge of stability\n", r.failed_step,
                lo + r.failed_step * width, lo + (r.failed_step + 1u) * width);
        return ZW_EXIT_USAGE;
    }
    if (r.verify_status != 0 || r.fault != 0) {
        fprintf(stderr, PROG ": the box certificate built does not verify (fault %d): please report "
                        "this\n", r.fault);
        return ZW_EXIT_USAGE;
    }
    fprintf(stderr, PROG ": box certificate: %lu leaves, built in %.2f s, verified here in %.3f s\n",
            r.leaves, r.build_seconds, r.verify_seconds);
    return ZW_EXIT_OK;
}

/* Write n words at addr in requests of at most 123 words (FC 0x10's limit). */
static int write_window(modbus_t *ctx, int addr, int n, const uint_least16_t *w, unsigned *exc)
{
    int done;
    for (done = 0; done < n; done += 123) {
        const int part = n - done < 123 ? n - done : 123;
        if (write_regs(ctx, addr + done, part, w + done, exc) != 0) return -1;
    }
    return 0;
}

/* Read n words at addr in requests of at most 125 words (FC 0x03's limit). */
static int read_window(modbus_t *ctx, int addr, int n, uint_least16_t *w, unsigned *exc)
{
    int done;
    for (done = 0; done < n; done += 125) {
        const int part = n - done < 125 ? n - done : 125;
        if (read_regs(ctx, addr + done, part, w + done, exc) != 0) return -1;
    }
    return 0;
}

/* Commission: a ranged block's certificate built first; UNLOCK1, UNLOCK2, read the nonce,
 * write the block with its CRC, the certificate window, and the MAC of (version, nonce,
 * block, certificate) under the drive's key, SEAL; then read back mode, sealed flag, block,
 * CRC and certificate and say what the drive did. */
static int cmd_commission(modbus_t *ctx, const zw_cert_opts *co, const double *cert_b,
                          const uint8_t key[ZW_KEY_BYTES], int json)
{
    zw_cert cert;
    zw_box_cert box_cert;
    uint_least16_t bc[ZW_BOX_CERT_WORDS], bc_wire[ZW_BOX_CERT_WORDS], bc_back[ZW_BOX_CERT_WORDS];
    uint_least16_t w[ZW_CERT_WORDS + 1u], wire[ZW_CERT_WORDS + 1u], head[4], back[ZW_CERT_WORDS + 1u];
    uint_least16_t nonce[ZW_AUTH_NONCE_WORDS], macw[ZW_AUTH_MAC_WORDS];
    uint_least8_t msg[ZW_AUTH_MSG_BYTES];
    uint8_t mac[2u * ZW_AUTH_MAC_WORDS];
    unsigned exc;
    uint_least16_t crc;
    snapshot s;
    int k, rc, same;
    const char *what;

    zw_cert_opts_to_cert(co, &cert);
    zw_cert_encode(&cert, w);
    crc = w[ZW_CERT_WORDS];
    rc = read_head(ctx, &s); /* a drive of another map version is not written to */
    if (rc != ZW_EXIT_OK) return rc;
    memset(&box_cert, 0, sizeof box_cert);
    if (zw_cert_ranged(&cert)) {
        rc = build_box_cert(ctx, &cert, cert_b, &box_cert);
        if (rc != ZW_EXIT_OK) return rc;
        zw_box_cert_encode(&box_cert, bc);
    } else {
        if (cert_b != NULL) {
            fprintf(stderr, PROG ": --cert-b needs plant ranges (--m LO:HI or --b LO:HI)\n");
            return ZW_EXIT_USAGE;
        }
        memset(bc, 0, sizeof bc);
    }

    if (write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_UNLOCK1, &exc) != 0) {
        if (exc == 0) return protocol_error("cannot send the unlock commands");
        return commission_refused(ctx, "unlock", exc, 0, json);
    }
    if (write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_UNLOCK2, &exc) != 0) {
        /* No answer: the drive may have taken UNLOCK2 all the same. */
        if (exc == 0) return commission_transport_error(ctx, "cannot send the unlock commands");
        return commission_refused(ctx, "unlock", exc, 0, json);
    }
    if (read_regs(ctx, ZW_REG_NONCE, (int)ZW_AUTH_NONCE_WORDS, nonce, &exc) != 0) {
        if (exc == 0) return commission_transport_error(ctx, "cannot read the nonce");
        return commission_refused(ctx, "nonce", exc, 1, json);
    }
    zw_regmap_auth_message(nonce, w, bc, msg);
    if (!zw_hmac_sha256(key, msg, sizeof msg, mac)) {
        fprintf(stderr, PROG ": libcrypto cannot compute HMAC-SHA256\n");
        (void)write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_ABORT, &exc);
        return ZW_EXIT_USAGE;
    }
    for (k = 0; k < (int)ZW_AUTH_MAC_WORDS; ++k)
        macw[k] = (uint_least16_t)(((unsigned)mac[2 * k] << 8) | mac[2 * k + 1]);
    for (k = 0; k <= (int)ZW_CERT_WORDS; ++k) wire[k] = w[k];
    wire_pairs(wire, (int)ZW_CERT_WORDS); /* the CRC and the MAC stay over the ABCD words */
    if (write_regs(ctx, ZW_REG_CERT_M, (int)ZW_CERT_WORDS + 1, wire, &exc) != 0) {
        if (exc == 0) return commission_transport_error(ctx, "cannot write the certified block");
        return commission_refused(ctx, "block", exc, 1, json);
    }
    memcpy(bc_wire, bc, sizeof bc);
    wire_pairs(&bc_wire[ZW_BOX_CERT_WORD_B], (int)(ZW_BOX_CERT_WORD_NODES - ZW_BOX_CERT_WORD_B));
    if (write_window(ctx, ZW_REG_BOX_CERT, (int)ZW_BOX_CERT_WORDS, bc_wire, &exc) != 0) {
        if (exc == 0) return commission_transport_error(ctx, "cannot write the box certificate");
        return commission_refused(ctx, "certificate", exc, 1, json);
    }
    if (write_regs(ctx, ZW_REG_MAC, (int)ZW_AUTH_MAC_WORDS, macw, &exc) != 0) {
        if (exc == 0) return commission_transport_error(ctx, "cannot write the MAC");
        return commission_refused(ctx, "mac", exc, 1, json);
    }
    /* SEAL certifies the block (a ranged one over its whole plant box: about a second on a
     * PC, more on a drive's MCU, and more again under a sanitizer): its answer gets at
     * least SEAL_TIMEOUT_S, whatever --timeout says for the other requests. */
    {
        uint32_t to_sec = 0u, to_usec = 0u;
        int sealed_rc;
        (void)modbus_get_response_timeout(ctx, &to_sec, &to_usec);
        if (to_sec < SEAL_TIMEOUT_S) (void)modbus_set_response_timeout(ctx, SEAL_TIMEOUT_S, 0u);
        sealed_rc = write_reg(ctx, ZW_REG_COMMAND, ZW_CMD_SEAL, &exc);
        (void)modbus_set_response_timeout(ctx, to_sec, to_usec);
        if (sealed_rc != 0) {
            if (exc == 0) return commission_transport_error(ctx, "cannot send the seal command");
            return commission_refused(ctx, "seal", exc, 1, json);
        }
    }
    /* SEAL was accepted: the MAC covers our block, so what was sealed is ours.  Read back
     * what the drive is doing now: another client may have unlocked it again since (its
     * reads then show a staged copy, not the block in force). */
    if (read_regs(ctx, ZW_REG_MAGIC, 4, head, &exc) != 0 ||
        read_regs(ctx, ZW_REG_CERT_M, (int)ZW_CERT_WORDS + 1, back, &exc) != 0 ||
        read_window(ctx, ZW_REG_BOX_CERT, (int)ZW_BOX_CERT_WORDS, bc_back, &exc) != 0)
        return protocol_error("cannot read back the sealed block");
    wire_pairs(back, (int)ZW_CERT_WORDS);
    wire_pairs(&bc_back[ZW_BOX_CERT_WORD_B], (int)(ZW_BOX_CERT_WORD_NODES - ZW_BOX_CERT_WORD_B));
    for (k = 0; k <= (int)ZW_CERT_WORDS && back[k] == w[k]; ++k) {}
    same = k > (int)ZW_CERT_WORDS && memcmp(bc_back, bc, sizeof bc) == 0;
    what = head[2] != 0u ? "the drive accepted SEAL, but is in commissioning mode again: another "
                           "client unlocked it after us (output off until that session ends)"
           : head[3] != 1u ? "the drive accepted SEAL but reports no sealed block"
           : !same ? "the drive accepted SEAL, but a different block is in force now: another "
                     "client commissioned after us"
                   : NULL;
    if (what != NULL) {
        fprintf(stderr, PROG ": %s (in force: CRC 0x%04X, ours 0x%04X)\n", what,
                (unsigned)back[ZW_CERT_WORDS], (unsigned)crc);
        if (json)
            printf("{\"verdict\": \"mismatch\", \"crc\": %u, \"sealed_crc\": %u, "
                   "\"sealed\": %s, \"mode\": %s}\n", (unsigned)crc, (unsigned)back[ZW_CERT_WORDS],
                   head[3] == 1u ? "true" : "false", head[2] != 0u ? "\"commissioning\"" : "\"operation\"");
        return ZW_EXIT_REFUSED;
    }
    rc = read_snapshot(ctx, &s);
    if (rc != ZW_EXIT_OK) return rc;
    if (json) {
        printf("{\"verdict\": \"sealed\", \"crc\": %u, \"cert\": {", (unsigned)crc);
        for (k = 0; k < ZW_CERT_NFIELDS; ++k)
            json_kv_float(zw_cert_label[k], (double)zw_cert_field(&cert, (unsigned)k), k > 0);
        printf("}, \"sealed\": true, \"verified\": true, \"mode\": \"operation\"}\n");
    } else {
        printf("commissioned: the drive sealed our block (CRC 0x%04X) and is in operation "
               "(mode, block and CRC read back); gains are off until set\n", (unsigned)crc);
        print_snapshot_text(&s);
    }
    return ZW_EXIT_OK;
}

/* ---------------------------------------------------------------------------------------
 * main
 * ------------------------------------------------------------------------------------- */

static modbus_t *connect_drive(const conn_opts *o)
{
    modbus_t *ctx;
    if (o->rtu != NULL) ctx = modbus_new_rtu(o->rtu, (int)o->baud, o->parity, 8, 1);
    else ctx = modbus_new_tcp(o->host, (int)o->port);
    if (ctx == NULL) {
        fprintf(stderr, PROG ": cannot create a Modbus context: %s\n", modbus_strerror(errno));
        return NULL;
    }
    if (modbus_set_slave(ctx, (int)o->slave) != 0) {
        fprintf(stderr, PROG ": cannot use slave %ld: %s\n", o->slave, modbus_strerror(errno));
        modbus_free(ctx);
        return NULL;
    }
    modbus_set_response_timeout(ctx, (uint32_t)(o->timeout_ms / 1000),
                                (uint32_t)(o->timeout_ms % 1000) * 1000u);
    if (modbus_connect(ctx) != 0) {
        if (o->rtu != NULL)
            fprintf(stderr, PROG ": cannot open %s: %s\n", o->rtu, modbus_strerror(errno));
        else
            fprintf(stderr, PROG ": cannot connect to %s:%ld: %s\n", o->host, o->port,
                    modbus_strerror(errno));
        modbus_free(ctx);
        return NULL;
    }
    return ctx;
}

int main(int argc, char **argv)
{
    conn_opts o = {"127.0.0.1", NULL, 1502, 19200, 1, 1000, 'N', -1};
    zw_cert_opts co;
    const char *cmd = NULL, *key_file = NULL;
    uint8_t key[ZW_KEY_BYTES];
    double K = 0.0, B = 0.0, cert_b[2] = {0.0, 0.0};
    int have_K = 0, have_B = 0, have_cert_b = 0, json = 0, paper = 0, i, rc, k;
    modbus_t *ctx;
    struct in_addr probe;

    zw_cert_opts_defaults(&co);
    for (i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        int r;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            usage(stdout);
            return ZW_EXIT_OK;
        }
        if (strcmp(arg, "--version") == 0) {
            printf(PROG " %s\n", ZW_VERSION_STRING);
            return ZW_EXIT_OK;
        }
        if (arg[0] != '-') {
            if (cmd != NULL) {
                fprintf(stderr, PROG ": unexpected argument '%s'\n", arg);
                return ZW_EXIT_USAGE;
            }
            cmd = arg;
            continue;
        }
        if (strcmp(arg, "--json") == 0) { json = 1; continue; }
        if (strcmp(arg, "--paper-defaults") == 0) { paper = 1; continue; }
        if (strcmp(arg, "--K") == 0 || strcmp(arg, "--B") == 0) {
            double *t = arg[2] == 'K' ? &K : &B;
            if (val == NULL) {
                fprintf(stderr, PROG ": missing value for '%s'\n", arg);
                return ZW_EXIT_USAGE;
            }
            /* NaN and infinities are refused by the drive; let a user send them on purpose. */
            if (strcmp(val, "nan") == 0 || strcmp(val, "NaN") == 0) *t = (double)NAN;
            else if (strcmp(val, "inf") == 0 || strcmp(val, "-inf") == 0)
                *t = val[0] == '-' ? -(double)INFINITY : (double)INFINITY;
            else if (!zw_parse_double(PROG, arg, val, t)) return ZW_EXIT_USAGE;
            else if (fabs(*t) > (double)FLT_MAX) { /* converting it to float is undefined */
                fprintf(stderr, PROG ": %s %s does not fit a float register\n", arg, val);
                return ZW_EXIT_USAGE;
            }
            if (arg[2] == 'K') have_K = 1;
            else have_B = 1;
            ++i;
            continue;
        }
        r = zw_cert_opts_parse(PROG, &co, argc, argv, &i);
        if (r < 0) return ZW_EXIT_USAGE;
        if (r > 0) continue;
        if (val == NULL) {
            fprintf(stderr, PROG ": %s '%s'\n",
                    strcmp(arg, "--host") == 0 || strcmp(arg, "--port") == 0 ||
                            strcmp(arg, "--rtu") == 0 || strcmp(arg, "--baud") == 0 ||
                            strcmp(arg, "--parity") == 0 || strcmp(arg, "--slave") == 0 ||
                            strcmp(arg, "--timeout") == 0 || strcmp(arg, "--key-file") == 0 ||
                            strcmp(arg, "--word-order") == 0 || strcmp(arg, "--cert-b") == 0
                        ? "missing value for"
                        : "unknown option",
                    arg);
            return ZW_EXIT_USAGE;
        }
        if (strcmp(arg, "--host") == 0) {
            if (inet_pton(AF_INET, val, &probe) != 1) {
                fprintf(stderr, PROG ": --host expects an IPv4 address, got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
            o.host = val;
        } else if (strcmp(arg, "--port") == 0) {
            if (!zw_parse_long(PROG, arg, val, 1, 65535, &o.port)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--rtu") == 0) {
            o.rtu = val;
        } else if (strcmp(arg, "--baud") == 0) {
            if (!zw_parse_long(PROG, arg, val, 50, 4000000, &o.baud)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--parity") == 0) {
            if ((val[0] != 'N' && val[0] != 'E' && val[0] != 'O') || val[1] != '\0') {
                fprintf(stderr, PROG ": --parity expects N, E or O, got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
            o.parity = val[0];
        } else if (strcmp(arg, "--slave") == 0) {
            if (!zw_parse_long(PROG, arg, val, 0, 255, &o.slave)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--timeout") == 0) {
            if (!zw_parse_long(PROG, arg, val, 10, 60000, &o.timeout_ms)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--key-file") == 0) {
            key_file = val;
        } else if (strcmp(arg, "--cert-b") == 0) {
            char lo_text[64];
            const char *colon = strchr(val, ':');
            size_t n = colon != NULL ? (size_t)(colon - val) : 0u;
            if (colon == NULL || n == 0u || n >= sizeof lo_text) {
                fprintf(stderr, PROG ": --cert-b expects LO:HI, got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
            memcpy(lo_text, val, n);
            lo_text[n] = '\0';
            if (!zw_parse_double(PROG, arg, lo_text, &cert_b[0]) ||
                !zw_parse_double(PROG, arg, colon + 1, &cert_b[1]))
                return ZW_EXIT_USAGE;
            if (!(cert_b[0] < cert_b[1])) {
                fprintf(stderr, PROG ": --cert-b needs LO < HI, got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
            have_cert_b = 1;
        } else if (strcmp(arg, "--word-order") == 0) {
            if (strcmp(val, "auto") == 0) o.word_order = -1;
            else if (strcmp(val, "abcd") == 0) o.word_order = (int)ZW_WORD_ORDER_ABCD;
            else if (strcmp(val, "cdab") == 0) o.word_order = (int)ZW_WORD_ORDER_CDAB;
            else {
                fprintf(stderr, PROG ": --word-order expects auto, abcd or cdab, got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
        } else {
            fprintf(stderr, PROG ": unknown option '%s'\n", arg);
            usage(stderr);
            return ZW_EXIT_USAGE;
        }
        ++i;
    }

    /* RTU slave 0 is the broadcast address, which is never answered. */
    if (o.rtu != NULL && (o.slave < 1 || o.slave > 247)) {
        fprintf(stderr, PROG ": --slave expects 1..247 with --rtu (0 is broadcast), got %ld\n",
                o.slave);
        return ZW_EXIT_USAGE;
    }
    if (cmd == NULL) {
        fprintf(stderr, PROG ": missing command (status, set, save or commission)\n");
        usage(stderr);
        return ZW_EXIT_USAGE;
    }
    if (strcmp(cmd, "set") == 0) {
        if (!have_K && !have_B) {
            fprintf(stderr, PROG ": set needs --K, --B or both\n");
            return ZW_EXIT_USAGE;
        }
    } else if (strcmp(cmd, "commission") == 0) {
        int missing = 0;
        for (k = 0; k < ZW_CERT_NPOLICY; ++k) /* the loop fields default to the ideal loop */
            if (!co.given[k] && !paper) {
                fprintf(stderr, PROG ": commission needs %s (or --paper-defaults)\n",
                        zw_cert_option[k]);
                missing = 1;
            }
        if (key_file == NULL) {
            fprintf(stderr, PROG ": commission needs --key-file (the drive's key)\n");
            missing = 1;
        }
        if (missing) return ZW_EXIT_USAGE;
        if (!zw_key_load(PROG, key_file, key)) return ZW_EXIT_USAGE;
    } else if (strcmp(cmd, "status") != 0 && strcmp(cmd, "save") != 0) {
        fprintf(stderr, PROG ": unknown command '%s' (status, set, save or commission)\n", cmd);
        return ZW_EXIT_USAGE;
    }
    for (k = 0; k < ZW_CERT_NFIELDS; ++k)
        if (co.given[k] && strcmp(cmd, "commission") != 0) {
            fprintf(stderr, PROG ": %s belongs to commission\n", zw_cert_option[k]);
            return ZW_EXIT_USAGE;
        }
    if (have_cert_b && strcmp(cmd, "commission") != 0) {
        fprintf(stderr, PROG ": --cert-b belongs to commission\n");
        return ZW_EXIT_USAGE;
    }
    if ((have_K || have_B) && strcmp(cmd, "set") != 0) {
        fprintf(stderr, PROG ": --K and --B belong to set\n");
        return ZW_EXIT_USAGE;
    }

    g_want_order = o.word_order;
    ctx = connect_drive(&o);
    if (ctx == NULL) return ZW_EXIT_USAGE;
    if (strcmp(cmd, "status") == 0) rc = cmd_status(ctx, json);
    else if (strcmp(cmd, "save") == 0) rc = cmd_save(ctx, json);
    else if (strcmp(cmd, "set") == 0) rc = cmd_set(ctx, have_K, K, have_B, B, json);
    else rc = cmd_commission(ctx, &co, have_cert_b ? cert_b : NULL, key, json);
    modbus_close(ctx);
    modbus_free(ctx);
    return rc;
}
