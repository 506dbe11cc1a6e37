/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench_modbus.c - round-trip latency and rate of a gain write over Modbus TCP.
 *
 * One gain write = K and B (two binary32, high word first) in ONE write-multiple request
 * (0x10, 4 registers at ZW_REG_K), alternating between two pairs that the drive accepts.
 * The same client code runs against every target: zwidth-drive, bench_plain_server
 * (libmodbus' modbus_reply, no validation), and optionally the firmware handler
 * zw_regmap_handle_pdu called in this process (no network), so the medians differ by what
 * certification and its server cost.
 *
 *   bench_modbus --target LABEL:PORT [--target LABEL:PORT ...] [--inproc]
 *                [--host 127.0.0.1] [--n 20000] [--block 500] [--warmup 200]
 *                [--pair-a K,B] [--pair-b K,B] [--connect-timeout S]
 *
 * The targets are interleaved in blocks of --block writes (A block, B block, A block, ...)
 * so that a change in machine load during the run hits them alike; every target gets N
 * timed writes after --warmup untimed ones.  Prints a human line per target on stderr and
 * one machine line per target on stdout:
 *   RESULT <label> <n> <median_us> <p99_us> <mean_us> <writes_per_s>
 * (writes_per_s = N / time spent in that target's timed writes).  Exit status 0; 1 if a
 * write is refused or fails (a refusal would mean we are not timing the accepted path) or
 * the read-back does not match the last pair written; 2 on bad arguments.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <modbus.h>

#include "zwidth/regmap.h"

#define MAX_TARGETS 8

typedef struct target {
    const char *label;
    long port;         /* -1: in-process handler */
    modbus_t *ctx;
    zw_regmap rm;      /* in-process only */
    double *lat;       /* seconds, one per timed write */
    long done;         /* writes issued so far (warm-up included) */
    double busy;       /* seconds spent in timed writes */
} target;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int parse_pair(const char *s, float pair[2])
{
    char *end = NULL;
    double k = strtod(s, &end);
    if (!end || *end != ',') return -1;
    double b = strtod(end + 1, &end);
    if (!end || *end != '\0' || !isfinite(k) || !isfinite(b)) return -1;
    pair[0] = (float)k;
    pair[1] = (float)b;
    return 0;
}

static long parse_long(const char *opt, const char *s, long lo, long hi)
{
    char *end = NULL;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || !end || *end != '\0' || v < lo || v > hi) {
        fprintf(stderr, "bench_modbus: %s wants an integer in %ld..%ld, got '%s'\n", opt, lo,
                hi, s);
        exit(2);
    }
    return v;
}

/* The same encoding the drive decodes: zw_float_to_words (ABCD). */
static void encode_pair(const float pair[2], uint16_t out[4])
{
    uint_least16_t w[2];
    zw_float_to_words(pair[0], w);
    out[0] = (uint16_t)w[0];
    out[1] = (uint16_t)w[1];
    zw_float_to_words(pair[1], w);
    out[2] = (uint16_t)w[0];
    out[3] = (uint16_t)w[1];
}

static int open_target(target *t, const char *host, double connect_timeout)
{
    if (t->port < 0) {
        /* The paper's drive with a policy that accepts both pairs and the first step. */
        const zw_cert block = {8.578e-6f, 2.197e-3f, 0.02f, 0.9f, 1.0f, 0.0f, 0.45f,
                               -2.197e-3f, 3.5e-3f, 0.5f, 5e-3f};
        zw_reason why;
        if (zw_regmap_init(&t->rm, &block, &why) != ZW_OK) {
            fprintf(stderr, "bench_modbus: [%s] block refused: %s\n", t->label, zw_reason_name(why));
            return 1;
        }
        return 0;
    }
    t->ctx = modbus_new_tcp(host, (int)t->port);
    if (!t->ctx) {
        fprintf(stderr, "bench_modbus: [%s] %s\n", t->label, modbus_strerror(errno));
        return 1;
    }
    modbus_set_response_timeout(t->ctx, 1, 0);
    double deadline = now_s() + connect_timeout;
    while (modbus_connect(t->ctx) == -1) {
        if (now_s() > deadline) {
            fprintf(stderr, "bench_modbus: [%s] cannot connect to %s:%ld within %.1f s: %s\n",
                    t->label, host, t->port, connect_timeout, modbus_strerror(errno));
            return 1;
        }
        struct timespec ts = {0, 20 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    return 0;
}

/* One gain write; 0 when accepted. */
static int write_pair(target *t, const uint16_t words[4])
{
    if (t->port >= 0) return modbus_write_registers(t->ctx, ZW_REG_K, 4, words) == 4 ? 0 : 1;
    uint_least8_t pdu[14] = {0x10, 0x00, ZW_REG_K, 0x00, 0x04, 0x08};
    uint_least8_t resp[253];
    size_t len;
    for (int w = 0; w < 4; w++) {
        pdu[6 + 2 * w] = (uint_least8_t)(words[w] >> 8);
        pdu[7 + 2 * w] = (uint_least8_t)(words[w] & 0xFFu);
    }
    return zw_regmap_handle_pdu(&t->rm, pdu, sizeof pdu, resp, sizeof resp, &len) == ZW_MB_OK ? 0 : 1;
}

/* The target must hold the last pair written. */
static int read_back(target *t, uint16_t back[4])
{
    if (t->port >= 0) return modbus_read_registers(t->ctx, ZW_REG_K, 4, back) == 4 ? 0 : 1;
    uint_least16_t w[4];
    zw_reason why;
    if (zw_regmap_read(&t->rm, ZW_REG_K, 4, w, &why) != ZW_MB_OK) return 1;
    for (int i = 0; i < 4; i++) back[i] = (uint16_t)w[i];
    return 0;
}

static void close_target(target *t)
{
    if (t->ctx) {
        modbus_close(t->ctx);
        modbus_free(t->ctx);
        t->ctx = NULL;
    }
    free(t->lat);
    t->lat = NULL;
}

int main(int argc, char **argv)
{
    const char *host = "127.0.0.1";
    long n = 20000, warmup = 200, block = 500;
    double connect_timeout = 5.0;
    float pair[2][2] = {{0.30f, -1.0e-3f}, {0.32f, -1.1e-3f}};
    target tg[MAX_TARGETS];
    int nt = 0;
    memset(tg, 0, sizeof tg);

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--inproc") == 0) {
            if (nt == MAX_TARGETS) { fprintf(stderr, "bench_modbus: too many targets\n"); return 2; }
            tg[nt].label = "inproc";
            tg[nt++].port = -1;
            continue;
        }
        const char *v = (i + 1 < argc) ? argv[++i] : NULL;
        if (!v) {
            fprintf(stderr, "bench_modbus: %s needs a value (see the header of bench_modbus.c)\n", a);
            return 2;
        }
        if (strcmp(a, "--target") == 0) {
            const char *colon = strrchr(v, ':');
            if (!colon || colon == v || nt == MAX_TARGETS) {
                fprintf(stderr, "bench_modbus: --target wants LABEL:PORT (at most %d), got '%s'\n",
                        MAX_TARGETS, v);
                return 2;
            }
            size_t len = (size_t)(colon - v);
            char *label = malloc(len + 1);
            if (!label) return 1;
            memcpy(label, v, len);
            label[len] = '\0';
            tg[nt].label = label;
            tg[nt++].port = parse_long("--target", colon + 1, 1, 65535);
        } else if (strcmp(a, "--host") == 0) host = v;
        else if (strcmp(a, "--n") == 0) n = parse_long(a, v, 1, 100000000);
        else if (strcmp(a, "--block") == 0) block = parse_long(a, v, 1, 100000000);
        else if (strcmp(a, "--warmup") == 0) warmup = parse_long(a, v, 0, 1000000);
        else if (strcmp(a, "--connect-timeout") == 0) connect_timeout = atof(v);
        else if (strcmp(a, "--pair-a") == 0 || strcmp(a, "--pair-b") == 0) {
            if (parse_pair(v, pair[a[7] == 'a' ? 0 : 1]) != 0) {
                fprintf(stderr, "bench_modbus: %s wants K,B (two finite numbers), got '%s'\n", a, v);
                return 2;
            }
        } else {
            fprintf(stderr, "bench_modbus: unknown option %s\n", a);
            return 2;
        }
    }
    if (nt == 0) {
        fprintf(stderr, "usage: bench_modbus --target LABEL:PORT [--target ...] [--inproc] [--n N] "
                        "[--block B] [--warmup W] [--host H] [--pair-a K,B] [--pair-b K,B]\n");
        return 2;
    }

    uint16_t words[2][4];
    encode_pair(pair[0], words[0]);
    encode_pair(pair[1], words[1]);

    int fail = 0;
    for (int k = 0; k < nt && !fail; k++) {
        tg[k].lat = malloc((size_t)n * sizeof *tg[k].lat);
        if (!tg[k].lat) {
            fprintf(stderr, "bench_modbus: out of memory\n");
            fail = 1;
        } else {
            fail = open_target(&tg[k], host, connect_timeout);
        }
    }

    /* Warm-up, then interleaved blocks of timed writes. */
    for (int k = 0; k < nt && !fail; k++) {
        for (long i = 0; i < warmup && !fail; i++, tg[k].done++) {
            if (write_pair(&tg[k], words[tg[k].done & 1])) {
                fprintf(stderr, "bench_modbus: [%s] warm-up write %ld refused or failed: %s\n",
                        tg[k].label, i, modbus_strerror(errno));
                fail = 1;
            }
        }
    }
    for (long start = 0; start < n && !fail; start += block) {
        long end = start + block < n ? start + block : n;
        for (int k = 0; k < nt && !fail; k++) {
            target *t = &tg[k];
            double b0 = now_s();
            for (long i = start; i < end; i++, t->done++) {
                double t0 = now_s();
                int rc = write_pair(t, words[t->done & 1]);
                double t1 = now_s();
                if (rc) {
                    fprintf(stderr, "bench_modbus: [%s] write %ld refused or failed: %s\n", t->label,
                            i, modbus_strerror(errno));
                    fail = 1;
                    break;
                }
                t->lat[i] = t1 - t0;
            }
            t->busy += now_s() - b0;
        }
    }
    for (int k = 0; k < nt && !fail; k++) {
        uint16_t back[4];
        if (read_back(&tg[k], back) || memcmp(back, words[(tg[k].done - 1) & 1], sizeof back) != 0) {
            fprintf(stderr, "bench_modbus: [%s] read-back does not match the last pair written\n",
                    tg[k].label);
            fail = 1;
        }
    }

    for (int k = 0; k < nt && !fail; k++) {
        target *t = &tg[k];
        double sum = 0.0;
        for (long i = 0; i < n; i++) sum += t->lat[i];
        qsort(t->lat, (size_t)n, sizeof *t->lat, cmp_double);
        double median = (n % 2) ? t->lat[n / 2] : 0.5 * (t->lat[n / 2 - 1] + t->lat[n / 2]);
        long i99 = (long)ceil(0.99 * (double)n) - 1;
        double p99 = t->lat[i99 < 0 ? 0 : i99];
        double rate = (double)n / t->busy;
        fprintf(stderr, "bench_modbus: [%s] %ld writes in %.3f s: median %.2f us, p99 %.2f us, %.0f writes/s\n",
                t->label, n, t->busy, median * 1e6, p99 * 1e6, rate);
        printf("RESULT %s %ld %.3f %.3f %.3f %.1f\n", t->label, n, median * 1e6, p99 * 1e6,
               sum / (double)n * 1e6, rate);
    }
    for (int k = 0; k < nt; k++) close_target(&tg[k]);
    return fail;
}
