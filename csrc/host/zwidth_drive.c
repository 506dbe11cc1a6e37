/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth-drive: a Modbus server (TCP or RTU) for one drive's gain register map.
 *
 * Every request PDU goes to zw_regmap_handle_pdu (the firmware's own handler), which
 * validates the whole request before anything changes; the response ADU is framed here.
 * libmodbus is used for listening, accepting, opening the serial line and receiving
 * (modbus_receive), never for answering: modbus_reply and modbus_mapping_* are not called,
 * so the libmodbus 3.1.6 advisories in those functions (CVE-2022-0367, upstream issue 837,
 * CVE-2024-36843) are unreachable from the network.  See docs/modbus.md.
 *
 * Optionally (--simulate) the drive closes the loop on a simulated plant
 * m x'' + b x' = F, F = -K x - B v (v the backward difference of the sampled position),
 * discretized exactly under the zero-order hold, and reports x, v, F through
 * zw_regmap_set_state.
 */
/* POLLRDHUP (Linux) tells at once that a peer closed in the middle of a frame; elsewhere the
 * frame timeout catches it. */
#if defined(__linux__) && !defined(_GNU_SOURCE)
#define _GNU_SOURCE
#endif
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <sys/types.h>

#include <pthread.h>
#include <stdatomic.h>

#include <modbus.h>

#include "zw_hostloop.h"
#include "zw_mbhost.h"
#include "zwidth/ident.h"
#include "zwidth/sim.h"
#include "zwidth/zwidth.h"

#define PROG "zwidth-drive"
#define MAX_CLIENTS_LIMIT 64
#define LISTEN_BACKLOG 128
#ifndef POLLRDHUP
#define POLLRDHUP 0
#endif
#define FRAMES_PER_WAKE 8       /* pipelined requests served per client per wake-up */
#define PARTIAL_RECHECK_MS 10   /* how often a partial TCP frame is looked at again */
#define SEND_TIMEOUT_MS 1000    /* a peer that does not take its answer within this is dropped */
#define TCP_HEADER 7            /* MBAP: transaction, protocol, length, unit id */
#define TCP_MAX_ADU 260         /* MBAP 7 + PDU 253 */
#define RTU_MAX_ADU 256         /* slave 1 + PDU 253 + CRC 2 */
#define PDU_MAX 253
#define RTU_T15_FLOOR_US 5000  /* the inter-character limit t1.5, at least this (OS latency) */
#define OUTQ_CAP 4096           /* answers queued for a client that is slow to read them */
#define LOG_BURST 20.0          /* refusal lines logged at once before the rate limit bites */
#define LOG_RATE 10.0           /* refusal lines per second in the long run */
#define LOG_SUMMARY_S 10.0      /* how often the refusals not logged are summed up */

static void usage(FILE *to)
{
    fprintf(to,
            "usage: zwidth-drive [--host ADDR] [--port N]        (Modbus TCP, default)\n"
            "       zwidth-drive --rtu DEVICE [--baud N] [--parity N|E|O] [--slave ID]\n"
            "       ... [certified block options | --unsealed] [--simulate [--speed S] [--x0 X]]\n"
            "       ... [--max-clients N] [--frame-timeout MS] [--idle-timeout S] [-v]\n"
            "       ... [--commissioning --key-file PATH]\n"
            "\n"
            "Serves the gain register map of one drive (docs/modbus.md): clients read it and\n"
            "write the stiffness K and damping B, which the drive applies only inside the\n"
            "certified stability policy.  A refused request is answered with a Modbus\n"
            "exception and changes nothing but the refusal registers.\n"
            "\n"
            "Transport\n"
            "  --host ADDR         IPv4 address to listen on (default 127.0.0.1; Modbus has no\n"
            "                      authentication: keep it on loopback or a closed network)\n"
            "  --port N            TCP port (default 1502; 0 picks a free port and prints it)\n"
            "  --rtu DEVICE        serve Modbus RTU on a serial device instead of TCP\n"
            "  --baud N            RTU baud rate (default 19200)\n"
            "  --parity P          RTU parity N, E or O (default N); 8 data bits, 1 stop bit\n"
            "  --slave ID          RTU slave address 1..247 (default 1); TCP answers any unit id\n"
            "  --word-order W      abcd (high word first, default) or cdab (low word first) for\n"
            "                      every float and 32-bit register\n"
            "  --max-clients N     TCP clients served at once, 1..%d (default 16); when full, a\n"
            "                      client stalled in the middle of a frame makes room\n"
            "  --frame-timeout MS  a TCP frame must be complete within this (default 500)\n"
            "  --idle-timeout S    drop TCP clients silent this long, 0 never (default 300)\n"
            "\n",
            MAX_CLIENTS_LIMIT);
    fprintf(to,
            "Certified block at power-up (sealed; without plant options: the paper's drive,\n"
            "its ideal loop and its gain bounds, said at start)\n"
            "  --m M  --b B  --T T plant: mass or inertia J (85.78e-7), damping (2.197e-3),\n"
            "                      sampling period [s] (0.02).  A plant other than the paper's\n"
            "                      needs its loop (--delay) and its gain bounds (--k-max, --b-min,\n"
            "                      --b-max, --dk-max, --db-max, or --gain-bounds from-limits);\n"
            "                      --m LO:HI, --b LO:HI: a box of\n"
            "                      plants, every gain certified for all of them (needs --r 1\n"
            "                      --max-r 1; the nameplate is then the ranges' middle, the\n"
            "                      tolerance at least their half-width; --simulate runs the\n"
            "                      lower ends)\n"
            "  --sigma S --r R     stiffness fraction of K_max(B) (0.8), spectral radius bound\n"
            "                      (0.999)\n"
            "  --k-min --k-max     K bounds (paper's drive: 0, 10)\n"
            "  --b-min --b-max     B bounds (paper's drive: -0.01, 0.01)\n"
            "  --dk-max --db-max   largest change of K and B per accepted write (paper's drive:\n"
            "                      1, 0.01)\n"
            "  --gain-bounds from-limits\n"
            "                      derive the bounds not given from the plant's certified limits\n"
            "                      in this loop: K in [0, K_mmax], B over the loop's B range as\n"
            "                      K -> 0+, steps the full spans (printed at start; a point plant)\n"
            "  --delay D           the loop this drive runs: force applied D samples late\n"
            "                      (required with a plant; the paper's drive: 0)\n"
            "  --velocity-filter F none, lowpass:30Hz (first-order, cut-off in Hz) or average:4\n"
            "                      (moving average over N samples) (none)\n"
            "  --differentiator X  backward or tustin (backward); gains are certified for this\n"
            "                      loop, and --simulate runs it\n"
            "  --unsealed          start uncommissioned: gains are refused until a client\n"
            "                      commissions a block (zwidth-tune commission)\n"
            "\n"
            "Factory ceilings (fixed at power-up; no block may exceed them, this one included)\n"
            "  --max-sigma S       largest stiffness fraction sigma (default 0.95)\n"
            "  --max-r R           largest spectral radius bound r (default 0.999)\n"
            "  --plant-tol F       relative tolerance of m, b and T around the nameplate, which\n"
            "                      is the plant given above (default 0.05); the K and B bounds\n"
            "                      and the step limits given above are the widest allowed\n"
            "\n"
            "Commissioning over Modbus (off by default: nobody can replace the block)\n"
            "  --commissioning     turn the commissioning enable input on (a key switch on a\n"
            "                      real drive); needs --key-file\n"
            "  --state-file PATH   non-volatile storage: SAVE (command 0x5A7E) writes the sealed\n"
            "                      block and the gains there (atomically; the previous copy\n"
            "                      kept as PATH.prev); at start they are checked and restored\n"
            "  --key-file PATH     this drive's key, 64 hex digits, mode 600 (umask 077;\n"
            "                      openssl rand -hex 32 > drive.key); a client must MAC the\n"
            "                      block and the drive's nonce with it (HMAC-SHA256)\n"
            "\n");
    fprintf(to,
            "Simulation\n"
            "  --simulate          run the plant m x'' + b x' = F (from --m --b --T) in this\n"
            "                      drive's loop (--delay, --velocity-filter, --differentiator)\n"
            "                      under the active gains; the state registers report x, the\n"
            "                      loop's velocity estimate and the force applied\n"
            "  --speed S           simulated seconds per real second (default 1)\n"
            "  --x0 X              initial position (default 0.01)\n"
            "\n"
            "Identification (docs/identify.md): with --simulate, --identify FILE plays the\n"
            "experiment through the firmware's zw_ident (ident.h) on the simulated plant with\n"
            "the gains off, writes the log FILE (CSV: t, command, position) for 'zwidth\n"
            "identify FILE --time t' and exits (0 done, 1 tripped); no Modbus is served\n"
            "  --excite KIND       prbs (default) or steps\n"
            "  --amplitude F       the command's amplitude [N or N m] (default 1)\n"
            "  --samples N         the run's length (default 4000; at most 65536)\n"
            "  --hold N            PRBS: samples per level (default 5)\n"
            "  --seed N            PRBS: the sequence's seed (default 1)\n"
            "  --counts-per-unit C the position measured in encoder counts, C per m (or rad)\n"
            "  --x-window X        the firmware's position window around the start (default 1)\n"
            "  --v-max V           the firmware's velocity limit (default 10)\n"
            "  --amplitude-max F   the firmware's amplitude ceiling (default: the amplitude)\n"
            "\n"
            "  -v, --verbose       also log connections and served requests (default: one\n"
            "                      line per refused request on stderr, nothing else)\n"
            "  -h, --help          this text\n"
            "  --version           print the version of zwidth and exit\n"
            "\n"
            "Stops cleanly on SIGINT or SIGTERM.\n"
            "Exit status: 0 stopped by a signal, 1 run-time failure (cannot listen, cannot open\n"
            "or lost the serial device), 2 bad arguments or a certified block that the policy\n"
            "refuses.\n");
}

/* ---------------------------------------------------------------------------------------
 * Signals: a self-pipe, so that poll wakes up at once.
 * ------------------------------------------------------------------------------------- */

static volatile sig_atomic_t g_stop = 0;
static int g_sigpipe[2] = {-1, -1};

static void on_signal(int sig)
{
    int saved = errno;
    char c = 's';
    (void)sig;
    g_stop = 1;
    if (g_sigpipe[1] >= 0) {
        ssize_t rc = write(g_sigpipe[1], &c, 1);
        (void)rc;
    }
    errno = saved;
}

static int install_signals(void)
{
    struct sigaction sa;
    int i;
    if (pipe(g_sigpipe) != 0) return -1;
    for (i = 0; i < 2; ++i) {
        int fl = fcntl(g_sigpipe[i], F_GETFL);
        if (fl < 0 || fcntl(g_sigpipe[i], F_SETFL, fl | O_NONBLOCK) != 0) return -1;
        (void)fcntl(g_sigpipe[i], F_SETFD, FD_CLOEXEC);
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0; /* no SA_RESTART: poll returns EINTR */
    if (sigaction(SIGINT, &sa, NULL) != 0 || sigaction(SIGTERM, &sa, NULL) != 0) return -1;
    sa.sa_handler = SIG_IGN; /* a peer that vanished must not kill the drive */
    return sigaction(SIGPIPE, &sa, NULL);
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* ---------------------------------------------------------------------------------------
 * The drive
 * ------------------------------------------------------------------------------------- */

typedef struct sim {
    int on;
    double T, speed;
    zw_sim run;          /* the plant and the drive's loop (sim.h) */
    double t0;           /* wall clock of step 0 */
    uint_least32_t step; /* steps taken */
    /* each step's lateness behind its scheduled time (the loop's period jitter) */
    double late_max, late_sum;
    unsigned long late_n, late_over_5ms;
} sim;

typedef struct client {
    int fd; /* -1: free slot */
    double last_active;
    double partial_since; /* 0: no partial frame pending */
    char peer[64];
    /* answers not yet taken by the peer: sent without blocking, the rest queued here; no
     * request of this client is read while any is queued (it only delays itself) */
    uint8_t out[OUTQ_CAP];
    size_t out_len;
    double out_since; /* when the queue became non-empty */
} client;

typedef struct drive {
    zw_regmap rm;
    int verbose;
    sim s;
    uint8_t key[ZW_KEY_BYTES]; /* the commissioning key (--key-file) */
    /* refusal logging: a token bucket, and the refusals it kept quiet since the summary */
    double log_tokens, log_last, log_summary_at;
    unsigned long log_quiet;
    const char *state_file; /* --state-file: where SAVE writes (PATH, PATH.prev) */
    atomic_bool sim_stop;   /* tells the simulation thread to end */
} drive;

/* Read a stored image (at most cap bytes); its length, 0 when the file does not exist or
 * cannot be read. */
static size_t read_image(const char *path, uint_least8_t *buf, size_t cap)
{
    uint8_t raw[ZW_IMAGE_BYTES + 16];
    ssize_t n;
    size_t i;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0;
    n = read(fd, raw, sizeof raw);
    close(fd);
    if (n <= 0) return 0;
    for (i = 0; i < (size_t)n && i < cap; ++i) buf[i] = raw[i];
    return (size_t)n; /* a longer file keeps its length: refused as a bad format */
}

/* SAVE's storage hook: the image goes to PATH.tmp (mode 600, synced), the old PATH becomes
 * PATH.prev, and PATH.tmp becomes PATH, each step a rename, so a crash at any point leaves
 * the new or the last good image for zw_regmap_restore. */
static bool drive_save(void *ctx, const uint_least8_t *image, size_t len)
{
    const drive *d = ctx;
    char tmp[4096], prev[4096], dir[4096];
    uint8_t raw[ZW_IMAGE_BYTES];
    size_t i;
    int fd, ok;
    const char *slash;
    if (len != sizeof raw || snprintf(tmp, sizeof tmp, "%s.tmp", d->state_file) >= (int)sizeof tmp ||
        snprintf(prev, sizeof prev, "%s.prev", d->state_file) >= (int)sizeof prev)
        return false;
    for (i = 0; i < len; ++i) raw[i] = (uint8_t)(image[i] & 0xFFu);
    fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) return false;
    ok = write(fd, raw, len) == (ssize_t)len && fsync(fd) == 0;
    ok = close(fd) == 0 && ok;
    if (!ok) {
        (void)unlink(tmp);
        return false;
    }
    if (rename(d->state_file, prev) != 0 && errno != ENOENT) return false;
    if (rename(tmp, d->state_file) != 0) return false;
    slash = strrchr(d->state_file, '/');
    snprintf(dir, sizeof dir, "%.*s", slash == NULL ? 1 : (int)(slash - d->state_file + 1),
             slash == NULL ? "." : d->state_file);
    fd = open(dir, O_RDONLY | O_CLOEXEC);
    if (fd >= 0) { /* the renames themselves durable */
        (void)fsync(fd);
        close(fd);
    }
    return true;
}

/* The firmware's commissioning hooks (regmap_commission.h), on libcrypto. */
static bool drive_random(void *ctx, uint_least8_t *out, size_t n)
{
    (void)ctx;
    return zw_random_bytes(out, n) != 0;
}

static bool drive_verify(void *ctx, const uint_least8_t *msg, size_t msg_len,
                         const uint_least8_t *mac, size_t mac_len)
{
    const drive *d = ctx;
    return zw_hmac_sha256_verify(d->key, msg, msg_len, mac, mac_len) != 0;
}

#if defined(__GNUC__)
static void logf_(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
#endif

/* One line on stderr, prefixed with the program name. */
static void logf_(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs(PROG ": ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* One simulation step of the drive's own loop (its delay, differentiator and velocity
 * filter, as certified: sim.h runs the loops loop.h analyses): the active gains, then the
 * sample's control and report, and the plant propagated over T under the zero-order hold
 * (exact without continuous effects). */
static void sim_step(drive *d)
{
    sim *s = &d->s;
    float Kf, Bf;
    zw_real x, v_est, F;
    zw_sim_trace tr;

    /* the control loop's reader: one certified pair, (0, 0) on any failure */
    (void)zw_regmap_active_gains(&d->rm, &Kf, &Bf);
    if (zw_sim_set_gains(&s->run, (zw_real)Kf, (zw_real)Bf) != ZW_OK)
        (void)zw_sim_set_gains(&s->run, 0, 0); /* not reached: the map hands out finite gains */
    memset(&tr, 0, sizeof tr);
    tr.x = &x;
    tr.velocity_estimate = &v_est;
    tr.force = &F;
    (void)zw_sim_run(&s->run, 1, &tr);
    /* + 0.0: no negative zero with the output off */
    zw_regmap_set_state(&d->rm, (float)x, (float)v_est, (float)(F + 0.0), s->step);
    s->step++;
}

/* The simulated plant m x'' + b x' = F at rest at x0, under the loop of the drive's options
 * (delay, velocity filter, differentiator: the loop its gains are certified for). */
static zw_status sim_start(sim *s, const zw_cert_opts *co, double x0, double speed)
{
    zw_sim_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.m = co->v[0];
    sc.b = co->v[1];
    sc.T = co->v[2];
    sc.x_init = x0;
    sc.t_step = ZW_HUGE_VAL; /* the reference stays at 0 */
    sc.substeps = 1;         /* no continuous effect: not read */
    if (co->v[11] > 0.0) {
        sc.effects |= ZW_SIM_DELAY;
        sc.delay_samples = (int)co->v[11];
    }
    if (co->v[12] == 1.0) {
        sc.effects |= ZW_SIM_VELOCITY_FILTER;
        sc.cutoff_hz = co->v[13];
    } else if (co->v[12] == 2.0) {
        sc.effects |= ZW_SIM_AVERAGE;
        sc.average_samples = (int)co->v[13];
    }
    if (co->v[14] == 1.0) sc.effects |= ZW_SIM_TUSTIN;
    s->on = 1;
    s->T = sc.T;
    s->speed = speed;
    s->step = 0;
    return zw_sim_init(&s->run, &sc);
}

/* Run every step that is due; returns the milliseconds until the next one (-1 if none). */
static int sim_run(drive *d, double now)
{
    sim *s = &d->s;
    double due_steps, next;
    int batch = 0, ms;
    if (!s->on) return -1;
    due_steps = (now - s->t0) * s->speed / s->T;
    while ((double)s->step <= due_steps) {
        double late = now - (s->t0 + (double)s->step * s->T / s->speed);
        if (late > s->late_max) s->late_max = late;
        s->late_sum += late;
        s->late_n++;
        if (late > 0.005) s->late_over_5ms++;
        sim_step(d);
        if (++batch >= 20000) { /* far behind (suspended?): drop the backlog */
            s->t0 = now - (double)s->step * s->T / s->speed;
            break;
        }
    }
    next = s->t0 + (double)s->step * s->T / s->speed;
    ms = (int)ceil((next - now) * 1000.0);
    return ms < 1 ? 1 : ms;
}

/* Refusal lines: LOG_BURST at once, LOG_RATE per second in the long run; the rest are
 * counted and summed up every LOG_SUMMARY_S (a client cannot flood the log). */
static int log_allowed(drive *d)
{
    double now = now_s();
    d->log_tokens += (now - d->log_last) * LOG_RATE;
    if (d->log_tokens > LOG_BURST) d->log_tokens = LOG_BURST;
    d->log_last = now;
    if (d->log_tokens >= 1.0) {
        d->log_tokens -= 1.0;
        return 1;
    }
    if (d->log_quiet++ == 0) d->log_summary_at = now + LOG_SUMMARY_S;
    return 0;
}

/* The summary of the refusals not logged, once LOG_SUMMARY_S has passed (or at the end). */
static void log_summary(drive *d, double now, int final)
{
    if (d->log_quiet == 0 || (!final && now < d->log_summary_at)) return;
    logf_("%lu more refused requests not logged (rate limit %.0f lines/s)", d->log_quiet,
          LOG_RATE);
    d->log_quiet = 0;
}

/* The simulated control loop on a thread of its own (a drive's control interrupt): it
 * sleeps until each step's scheduled time on the monotonic clock, so no Modbus request
 * delays it; it touches the register map only through zw_regmap_active_gains and
 * zw_regmap_set_state (regmap.h, threading model: the core is compiled C11 here). */
static void *sim_thread(void *arg)
{
    drive *d = arg;
    sigset_t all;
    sigfillset(&all);
    (void)pthread_sigmask(SIG_BLOCK, &all, NULL); /* signals go to the Modbus thread */
    while (!atomic_load(&d->sim_stop)) {
        struct timespec ts;
        double next;
        (void)sim_run(d, now_s());
        next = d->s.t0 + (double)d->s.step * d->s.T / d->s.speed;
        ts.tv_sec = (time_t)floor(next);
        ts.tv_nsec = (long)((next - floor(next)) * 1e9);
        if (ts.tv_nsec >= 1000000000L) ts.tv_nsec = 999999999L;
        (void)clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
    }
    return NULL;
}

static const char *fc_name(unsigned fc)
{
    switch (fc) {
    case 0x03: return "read";
    case 0x06: return "write-single";
    case 0x10: return "write-multiple";
    default: return "fc";
    }
}

/* Hand one request PDU (len <= PDU_MAX: both framings bound it) to the register map; the
 * response PDU goes to rsp (PDU_MAX bytes).  Returns its length.  Logs the refusal (always) or the request (-v). */
static size_t serve_pdu(drive *d, const uint8_t *pdu, size_t len, uint8_t *rsp, const char *who)
{
    uint_least8_t req_b[PDU_MAX], rsp_b[PDU_MAX];
    size_t i, rlen = 0;
    zw_mb_exception ex;
    char what[64];
    unsigned fc = len > 0 ? pdu[0] : 0u;

    for (i = 0; i < len; ++i) req_b[i] = pdu[i];
    ex = zw_regmap_handle_pdu(&d->rm, req_b, len, rsp_b, sizeof rsp_b, &rlen);
    if (rlen < 2 || rlen > PDU_MAX) { /* the handler broke its contract: answer 0x04 */
        logf_("internal error: register map answered %lu bytes to %s; sending exception 0x04",
              (unsigned long)rlen, who);
        rsp[0] = (uint8_t)((fc | 0x80u) & 0xFFu);
        rsp[1] = (uint8_t)ZW_MB_SERVER_FAILURE;
        return 2;
    }
    for (i = 0; i < rlen; ++i) rsp[i] = (uint8_t)(rsp_b[i] & 0xFFu);

    if (len >= 5) /* 0x06 carries the value written, 0x03 and 0x10 a quantity */
        snprintf(what, sizeof what, "%s 0x%02X addr 0x%04X %s %u", fc_name(fc), fc,
                 (unsigned)(pdu[1] << 8 | pdu[2]), fc == 0x06u ? "value" : "qty",
                 (unsigned)(pdu[3] << 8 | pdu[4]));
    else
        snprintf(what, sizeof what, "fc 0x%02X, %lu-byte PDU", fc, (unsigned long)len);
    if (ex != ZW_MB_OK) {
        unsigned reason = (unsigned)d->rm.last_reason;
        if (log_allowed(d))
            logf_("refused %s from %s: %s (exception 0x%02X %s)", what, who,
                  zw_reason_name((zw_reason)reason), (unsigned)ex, zw_exception_name((unsigned)ex));
    } else if (d->verbose) {
        if (fc == 0x06 || fc == 0x10)
            logf_("accepted %s from %s; gains now K = %.9g, B = %.9g", what, who,
                  (double)d->rm.K, (double)d->rm.B);
        else
            logf_("served %s from %s", what, who);
    }
    return rlen;
}

/* Write all of buf to fd (a socket when is_socket), waiting at most SEND_TIMEOUT_MS. */
static int send_all(int fd, const uint8_t *buf, size_t len, int is_socket)
{
    size_t off = 0;
    double deadline = now_s() + SEND_TIMEOUT_MS / 1000.0;
    while (off < len) {
        ssize_t n = is_socket ? send(fd, buf + off, len - off, MSG_NOSIGNAL | MSG_DONTWAIT)
                              : write(fd, buf + off, len - off);
        if (n > 0) {
            off += (size_t)n;
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            struct pollfd p;
            double left = deadline - now_s();
            if (left <= 0.0) return -1;
            p.fd = fd;
            p.events = POLLOUT;
            p.revents = 0;
            if (poll(&p, 1, (int)(left * 1000.0) + 1) < 0 && errno != EINTR) return -1;
            continue;
        }
        return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------------------------------
 * Modbus TCP
 * ------------------------------------------------------------------------------------- */

/* How many bytes libmodbus 3.1.6's modbus_receive reads for a request (indication) with
 * this header length and checksum length, from its function code and byte count
 * (compute_meta_length_after_function / compute_data_length_after_meta).  Used only to
 * make sure modbus_receive never reads past the frame the MBAP header declares.  Returns
 * a length larger than avail when it would read more than avail bytes. */
static size_t libmodbus_request_length(const uint8_t *adu, size_t avail, size_t hdr,
                                       size_t checksum)
{
    unsigned fc;
    size_t meta, data = 0, n;
    if (avail < hdr + 1) return avail + 1;
    fc = adu[hdr];
    if (fc <= 0x06) meta = 4;
    else if (fc == 0x0F || fc == 0x10) meta = 5;
    else if (fc == 0x16) meta = 6;
    else if (fc == 0x17) meta = 9;
    else meta = 0;
    n = hdr + 1 + meta;
    if (n > avail) return avail + 1;
    if (fc == 0x0F || fc == 0x10) data = adu[hdr + 5];
    else if (fc == 0x17) data = adu[hdr + 9];
    return n + data + checksum;
}

static void peer_name(int fd, char *out, size_t cap)
{
    struct sockaddr_in a;
    socklen_t alen = sizeof a;
    char ip[INET_ADDRSTRLEN];
    if (getpeername(fd, (struct sockaddr *)&a, &alen) == 0 && a.sin_family == AF_INET &&
        inet_ntop(AF_INET, &a.sin_addr, ip, sizeof ip) != NULL)
        snprintf(out, cap, "%s:%u", ip, (unsigned)ntohs(a.sin_port));
    else
        snprintf(out, cap, "fd %d", fd);
}

/* Send what the client's queue holds, without blocking.  Returns -1 when the peer is gone. */
static int flush_out(client *c, double now)
{
    while (c->out_len > 0) {
        ssize_t n = send(c->fd, c->out, c->out_len, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            memmove(c->out, c->out + n, c->out_len - (size_t)n);
            c->out_len -= (size_t)n;
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) break;
        return -1;
    }
    if (c->out_len == 0) c->out_since = 0.0;
    else if (c->out_since <= 0.0) c->out_since = now;
    return 0;
}

/* Queue an answer and send what the socket takes now.  -1: the queue would overflow (the
 * peer does not read its answers) or the peer is gone; the caller drops the client. */
static int queue_answer(client *c, const uint8_t *buf, size_t len, double now)
{
    if (len > OUTQ_CAP - c->out_len) return -1;
    memcpy(c->out + c->out_len, buf, len);
    c->out_len += len;
    return flush_out(c, now);
}

static void client_close(drive *d, client *c, const char *why)
{
    uint8_t junk[512];
    int k;
    if (why != NULL) logf_("%s: %s; connection closed", c->peer, why);
    else if (d->verbose) logf_("%s: disconnected", c->peer);
    /* Take what the peer already sent, so that the close is an orderly FIN rather than a
     * reset (which could discard an answer still in flight). */
    for (k = 0; k < 8 && recv(c->fd, junk, sizeof junk, MSG_DONTWAIT) > 0; ++k) {}
    close(c->fd);
    c->fd = -1;
    c->partial_since = 0.0;
    c->out_len = 0;
    c->out_since = 0.0;
}

/* Serve every complete frame buffered on this client.  hangup: poll reported that the
 * peer closed or reset the connection, so a partial frame will never complete.  Returns 0
 * to keep the client, -1 once it has been closed. */
static int tcp_service(drive *d, modbus_t *ctx, client *c, double now, int hangup)
{
    int frames;
    for (frames = 0; frames < FRAMES_PER_WAKE; ++frames) {
        uint8_t adu[TCP_MAX_ADU + 8], rsp[TCP_HEADER + PDU_MAX];
        /* answers still queued: read nothing more until the peer takes them */
        if (c->out_len > 0) return 0;
        ssize_t n = recv(c->fd, adu, TCP_MAX_ADU, MSG_PEEK | MSG_DONTWAIT);
        size_t need, got = 0, plen, mbap_len;
        unsigned proto;

        if (n == 0) {
            client_close(d, c, c->partial_since > 0.0 ? "peer closed in the middle of a frame"
                                                      : NULL);
            return -1;
        }
        if (n < 0) {
            if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return 0;
            client_close(d, c, d->verbose ? strerror(errno) : NULL);
            return -1;
        }
        c->last_active = now;
        if (n < TCP_HEADER) {
            if (hangup) {
                client_close(d, c, "peer closed in the middle of a frame");
                return -1;
            }
            if (c->partial_since <= 0.0) c->partial_since = now;
            return 0;
        }
        proto = (unsigned)(adu[2] << 8 | adu[3]);
        mbap_len = (size_t)(adu[4] << 8 | adu[5]);
        if (proto != 0 || mbap_len < 2 || mbap_len > PDU_MAX + 1) {
            char why[96];
            snprintf(why, sizeof why,
                     "refused a frame that is not Modbus TCP (protocol id 0x%04X, length %lu)",
                     proto, (unsigned long)mbap_len);
            client_close(d, c, why);
            return -1;
        }
        need = 6 + mbap_len;
        if ((size_t)n < need) {
            if (hangup) {
                client_close(d, c, "peer closed in the middle of a frame");
                return -1;
            }
            if (c->partial_since <= 0.0) c->partial_since = now;
            return 0;
        }
        c->partial_since = 0.0;

        /* The whole frame is buffered.  modbus_receive reads it when libmodbus's idea of
         * the request's length does not go past the frame (it then cannot block and
         * cannot swallow the next frame); the rest of the frame, if any (a function code
         * libmodbus does not know, or trailing bytes), is read here. */
        if (libmodbus_request_length(adu, need, TCP_HEADER, 0) <= need) {
            int rc;
            modbus_set_socket(ctx, c->fd);
            rc = modbus_receive(ctx, adu);
            if (rc <= 0 || (size_t)rc > need) {
                client_close(d, c, "modbus_receive failed on a complete frame");
                return -1;
            }
            got = (size_t)rc;
        }
        while (got < need) {
            ssize_t r = recv(c->fd, adu + got, need - got, MSG_DONTWAIT);
            if (r <= 0) {
                client_close(d, c, "lost the rest of a buffered frame");
                return -1;
            }
            got += (size_t)r;
        }
        /* got == need == 6 + the MBAP length, checked above. */
        plen = serve_pdu(d, adu + TCP_HEADER, got - TCP_HEADER, rsp + TCP_HEADER, c->peer);
        rsp[0] = adu[0]; /* transaction id */
        rsp[1] = adu[1];
        rsp[2] = 0; /* protocol id */
        rsp[3] = 0;
        rsp[4] = (uint8_t)((plen + 1) >> 8);
        rsp[5] = (uint8_t)((plen + 1) & 0xFFu);
        rsp[6] = adu[6]; /* unit id, echoed */
        if (queue_answer(c, rsp, TCP_HEADER + plen, now) != 0) {
            client_close(d, c, "dropped: its answers pile up unread (output queue full) or it is gone");
            return -1;
        }
    }
    return 0;
}

static int serve_tcp(drive *d, const char *host, int port, int max_clients,
                     double frame_timeout, double idle_timeout)
{
    modbus_t *ctx = modbus_new_tcp(host, port);
    client clients[MAX_CLIENTS_LIMIT];
    struct pollfd pfd[MAX_CLIENTS_LIMIT + 2];
    int slot_of[MAX_CLIENTS_LIMIT + 2];
    int lfd, i, fl;
    struct sockaddr_in a;
    socklen_t alen = sizeof a;
    double last_idle_check = 0.0;

    if (ctx == NULL) {
        logf_("cannot create a Modbus TCP context: %s", modbus_strerror(errno));
        return ZW_EXIT_FAILURE;
    }
    modbus_set_byte_timeout(ctx, 0, 100000);
    lfd = modbus_tcp_listen(ctx, LISTEN_BACKLOG);
    if (lfd < 0) {
        logf_("cannot listen on %s:%d: %s", host, port, modbus_strerror(errno));
        modbus_free(ctx);
        return ZW_EXIT_FAILURE;
    }
    fl = fcntl(lfd, F_GETFL);
    if (fl < 0 || fcntl(lfd, F_SETFL, fl | O_NONBLOCK) != 0 ||
        getsockname(lfd, (struct sockaddr *)&a, &alen) != 0) {
        logf_("cannot set up the listening socket: %s", strerror(errno));
        close(lfd);
        modbus_free(ctx);
        return ZW_EXIT_FAILURE;
    }
    if (d->verbose || port == 0) {
        char bound[INET_ADDRSTRLEN];
        if (a.sin_family != AF_INET || inet_ntop(AF_INET, &a.sin_addr, bound, sizeof bound) == NULL)
            snprintf(bound, sizeof bound, "%s", host);
        logf_("serving Modbus TCP on %s:%u (%s)", bound, (unsigned)ntohs(a.sin_port),
              d->rm.is_sealed ? "sealed" : "unsealed");
    }
    for (i = 0; i < MAX_CLIENTS_LIMIT; ++i) clients[i].fd = -1;

    while (!g_stop) {
        int n = 0, timeout = -1, any_partial = 0, rc;
        double now = now_s();

        /* The listening socket comes last: clients are served (and the ones that are gone
         * closed) before new ones take their slots and descriptor numbers. */
        pfd[n].fd = g_sigpipe[0];
        pfd[n].events = POLLIN;
        slot_of[n++] = -1;
        for (i = 0; i < max_clients; ++i) {
            if (clients[i].fd < 0) continue;
            pfd[n].fd = clients[i].fd;
            /* A client with a partial frame is looked at on a timer (its unread bytes
             * would keep poll returning at once), and when it hangs up; one with answers
             * queued when it can take more (its requests wait). */
            pfd[n].events = clients[i].out_len > 0        ? (short)(POLLOUT | POLLRDHUP)
                            : clients[i].partial_since > 0.0 ? POLLRDHUP
                                                             : POLLIN;
            if (clients[i].partial_since > 0.0 || clients[i].out_len > 0) any_partial = 1;
            slot_of[n++] = i;
        }
        pfd[n].fd = lfd;
        pfd[n].events = POLLIN;
        slot_of[n++] = -2;
        if (any_partial && (timeout < 0 || timeout > PARTIAL_RECHECK_MS))
            timeout = PARTIAL_RECHECK_MS;
        if (idle_timeout > 0.0 && (timeout < 0 || timeout > 1000)) timeout = 1000;
        for (i = 0; i < n; ++i) pfd[i].revents = 0;

        rc = poll(pfd, (nfds_t)n, timeout);
        if (rc < 0 && errno != EINTR) {
            logf_("poll: %s", strerror(errno));
            break;
        }
        if (g_stop) break;
        now = now_s();

        for (i = 0; rc > 0 && i < n; ++i) {
            if (pfd[i].revents == 0) continue;
            if (slot_of[i] == -1) {
                char buf[16];
                while (read(g_sigpipe[0], buf, sizeof buf) > 0) {}
            } else if (slot_of[i] == -2) {
                int k;
                for (k = 0; k < 16; ++k) { /* accept what is pending */
                    int cfd = modbus_tcp_accept(ctx, &lfd), slot, one = 1;
                    char peer[64];
                    if (cfd < 0) break;
                    peer_name(cfd, peer, sizeof peer);
                    for (slot = 0; slot < max_clients && clients[slot].fd >= 0; ++slot) {}
                    if (slot == max_clients) {
                        /* Full: serve what the clients have sent (which also closes the
                         * ones that are gone), else make room by one stalled in a frame. */
                        int j;
                        for (j = 0; j < max_clients; ++j)
                            if (clients[j].fd >= 0) (void)tcp_service(d, ctx, &clients[j], now, 0);
                        for (slot = 0; slot < max_clients && clients[slot].fd >= 0; ++slot) {}
                        if (slot == max_clients) {
                            for (slot = 0;
                                 slot < max_clients && clients[slot].partial_since <= 0.0; ++slot) {}
                            if (slot < max_clients)
                                client_close(d, &clients[slot],
                                             "dropped (stalled in a frame) to make room for a "
                                             "new client");
                        }
                        if (slot == max_clients) {
                            /* else the least recently active one: holding a slot by
                             * being connected is not enough to lock others out */
                            for (slot = 0, j = 1; j < max_clients; ++j)
                                if (clients[j].last_active < clients[slot].last_active) slot = j;
                            client_close(d, &clients[slot],
                                         "dropped (least recently active) to make room for a "
                                         "new client");
                        }
                    }
                    if (slot == max_clients || cfd >= FD_SETSIZE) {
                        /* libmodbus 3.1.6 puts the socket in an fd_set: never past
                         * FD_SETSIZE. */
                        logf_("%s: refused the connection (%d clients at most)", peer,
                              max_clients);
                        close(cfd);
                        continue;
                    }
                    (void)setsockopt(cfd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                    clients[slot].fd = cfd;
                    clients[slot].last_active = now;
                    clients[slot].partial_since = 0.0;
                    clients[slot].out_len = 0;
                    clients[slot].out_since = 0.0;
                    memcpy(clients[slot].peer, peer, sizeof peer);
                    if (d->verbose) logf_("%s: connected", peer);
                }
            } else {
                client *c = &clients[slot_of[i]];
                if (c->fd != pfd[i].fd) continue;
                if ((pfd[i].revents & POLLNVAL) != 0) {
                    c->fd = -1;
                    c->out_len = 0;
                    continue;
                }
                if (c->out_len > 0) {
                    if ((pfd[i].revents & (POLLHUP | POLLERR)) != 0 || flush_out(c, now) != 0) {
                        client_close(d, c, NULL);
                        continue;
                    }
                    if (c->out_len > 0) continue;
                }
                (void)tcp_service(d, ctx, c, now,
                                  (pfd[i].revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0);
            }
        }

        /* Answers not taken within SEND_TIMEOUT_MS: the peer does not read; drop it. */
        for (i = 0; i < max_clients; ++i) {
            client *c = &clients[i];
            if (c->fd >= 0 && c->out_len > 0 && now - c->out_since > SEND_TIMEOUT_MS / 1000.0)
                client_close(d, c, "dropped: did not take its answers within 1 s");
        }
        log_summary(d, now, 0);
        /* Partial frames: look again, and drop the ones that took too long. */
        for (i = 0; i < max_clients; ++i) {
            client *c = &clients[i];
            if (c->fd < 0 || c->partial_since <= 0.0) continue;
            if (tcp_service(d, ctx, c, now, 0) != 0) continue;
            if (c->fd >= 0 && c->partial_since > 0.0 && now - c->partial_since > frame_timeout)
                client_close(d, c, "incomplete frame timed out (peer stalled or vanished)");
        }
        if (idle_timeout > 0.0 && now - last_idle_check >= 1.0) {
            last_idle_check = now;
            for (i = 0; i < max_clients; ++i)
                if (clients[i].fd >= 0 && now - clients[i].last_active > idle_timeout) {
                    if (d->verbose) logf_("%s: idle for %.0f s", clients[i].peer, idle_timeout);
                    clients[i].partial_since = 0.0;
                    client_close(d, &clients[i], NULL);
                }
        }
    }

    for (i = 0; i < max_clients; ++i)
        if (clients[i].fd >= 0) close(clients[i].fd);
    close(lfd);
    modbus_set_socket(ctx, -1); /* sockets are closed above; modbus_free closes nothing */
    modbus_free(ctx);
    if (d->verbose) logf_("stopped");
    return ZW_EXIT_OK;
}

/* ---------------------------------------------------------------------------------------
 * Modbus RTU
 * ------------------------------------------------------------------------------------- */

/* A fresh receiving context on the open serial line.  libmodbus 3.1.6 treats the frame
 * after one addressed to another slave as that slave's answer and ignores it; on a line
 * where garbage can look like another address, the drive instead starts over with a new
 * context (which knows nothing of that) after such a frame. */
static modbus_t *rtu_context(const char *dev, int baud, char parity, int slave, int fd)
{
    modbus_t *ctx = modbus_new_rtu(dev, baud, parity, 8, 1);
    if (ctx == NULL) return NULL;
    if (modbus_set_slave(ctx, slave) != 0) {
        modbus_free(ctx);
        return NULL;
    }
    /* Inside a frame the gap between characters must not exceed t1.5 (Modbus over serial
     * line 2.5.1.1: 1.5 characters of 11 bits, 750 us above 19200 baud); the drive allows
     * at least RTU_T15_FLOOR_US, since the OS and USB-serial adapters deliver bytes in
     * chunks of about a millisecond.  A frame dribbled slower is dropped. */
    {
        double t15 = baud > 19200 ? 0.00075 : 1.5 * 11.0 / (double)baud;
        long us = (long)ceil(t15 * 1e6);
        if (us < RTU_T15_FLOOR_US) us = RTU_T15_FLOOR_US;
        modbus_set_byte_timeout(ctx, 0, (uint32_t)us);
    }
    if (fd >= 0) modbus_set_socket(ctx, fd);
    return ctx;
}

/* Discard input until the line has been quiet for gap seconds (t3.5; at most 1 s): the
 * rest of a frame that could not be used, so the next read starts at a frame boundary.
 * Returns the number of bytes discarded and the first of them in *first. */
static size_t rtu_drain(int fd, double gap, unsigned *first)
{
    double end = now_s() + 1.0;
    uint8_t junk[256];
    size_t total = 0;
    *first = 0;
    for (;;) {
        struct pollfd p;
        int rc;
        ssize_t n;
        p.fd = fd;
        p.events = POLLIN;
        p.revents = 0;
        rc = poll(&p, 1, (int)ceil(gap * 1000.0)); /* poll counts milliseconds: rounded up */
        if (rc <= 0 || (p.revents & POLLIN) == 0) return total;
        n = read(fd, junk, sizeof junk);
        if (n <= 0) return total;
        if (total == 0) *first = junk[0];
        total += (size_t)n;
        if (now_s() > end) return total;
    }
}

/* Drain after an unusable frame; with -v, report what that dropped: bytes that followed
 * within t3.5 break the Modbus framing, so a request among them is lost. */
static void rtu_drain_logged(drive *d, int fd, double gap, const char *dev)
{
    unsigned first;
    size_t n = rtu_drain(fd, gap, &first);
    if (n > 0 && d->verbose)
        logf_("dropped %lu bytes on %s that followed within t3.5 (%.3f ms) of a frame not "
              "answered (first byte 0x%02X); a request among them is lost",
              (unsigned long)n, dev, gap * 1000.0, first);
}

static int serve_rtu(drive *d, const char *dev, int baud, char parity, int slave)
{
    /* conn opened the line (and restores its settings at the end); ctx receives, and is
     * conn until it has to be replaced. */
    modbus_t *conn = rtu_context(dev, baud, parity, slave, -1), *ctx = conn;
    /* t3.5: 3.5 characters of 11 bits; fixed at 1.75 ms above 19200 baud (Modbus over
     * serial line, 2.5.1.1). */
    double gap = baud > 19200 ? 0.00175 : 3.5 * 11.0 / (double)baud;
    int fd, status = ZW_EXIT_OK;
    char who[80];

    if (ctx == NULL) {
        logf_("cannot create a Modbus RTU context for %s: %s", dev, modbus_strerror(errno));
        return ZW_EXIT_FAILURE;
    }
    if (modbus_connect(ctx) != 0) {
        logf_("cannot open %s: %s", dev, modbus_strerror(errno));
        modbus_free(ctx);
        return ZW_EXIT_FAILURE;
    }
    fd = modbus_get_socket(ctx);
    snprintf(who, sizeof who, "%s", dev);
    if (d->verbose)
        logf_("serving Modbus RTU on %s, %d baud, parity %c, slave %d (%s)", dev, baud, parity,
              slave, d->rm.is_sealed ? "sealed" : "unsealed");

    while (!g_stop) {
        struct pollfd p[2];
        int rc, timeout = -1;
        uint8_t adu[RTU_MAX_ADU + 8], rsp[RTU_MAX_ADU];

        p[0].fd = g_sigpipe[0];
        p[0].events = POLLIN;
        p[1].fd = fd;
        p[1].events = POLLIN;
        p[0].revents = p[1].revents = 0;
        rc = poll(p, 2, timeout);
        if (rc < 0 && errno != EINTR) {
            logf_("poll: %s", strerror(errno));
            status = ZW_EXIT_FAILURE;
            break;
        }
        if (g_stop) break;
        if (rc <= 0) continue;
        if ((p[1].revents & (POLLERR | POLLHUP | POLLNVAL)) != 0 && (p[1].revents & POLLIN) == 0) {
            logf_("lost the serial device %s", dev);
            status = ZW_EXIT_FAILURE;
            break;
        }
        if ((p[1].revents & POLLIN) == 0) continue;

        rc = modbus_receive(ctx, adu);
        if (rc < 0) {
            int e = errno;
            if (e == EBADF || e == EIO || e == ENXIO || e == ENODEV) {
                logf_("lost the serial device %s: %s", dev, modbus_strerror(e));
                status = ZW_EXIT_FAILURE;
                break;
            }
            logf_("refused a frame on %s: %s (no answer)", dev,
                  e == EMBBADCRC ? "bad CRC" : e == ETIMEDOUT ? "incomplete frame"
                                                             : modbus_strerror(e));
            rtu_drain_logged(d, fd, gap, dev);
            continue;
        }
        if (rc == 0 || adu[0] != (uint8_t)slave) {
            /* Another slave's request (or garbage that looks like one), or a broadcast:
             * no answer.  A drive takes no gains from a broadcast it cannot confirm. */
            modbus_t *fresh = rtu_context(dev, baud, parity, slave, fd);
            if (rc > 0)
                logf_("refused a broadcast request on %s (fc 0x%02X): not answered, not "
                      "applied", dev, (unsigned)adu[1]);
            else if (d->verbose)
                logf_("ignored a frame for another slave on %s", dev);
            if (fresh != NULL) {
                if (ctx != conn) {
                    modbus_set_socket(ctx, -1);
                    modbus_free(ctx);
                }
                ctx = fresh;
            }
            rtu_drain_logged(d, fd, gap, dev);
            continue;
        }
        {
            size_t hdr = (size_t)modbus_get_header_length(ctx), plen;
            uint16_t crc;
            if (hdr != 1 || (size_t)rc < hdr + 1 + 2) continue;
            plen = serve_pdu(d, adu + hdr, (size_t)rc - hdr - 2, rsp + 1, who);
            rsp[0] = (uint8_t)slave;
            crc = zw_crc16_bytes(rsp, plen + 1);
            rsp[plen + 1] = (uint8_t)(crc & 0xFFu); /* CRC low byte first */
            rsp[plen + 2] = (uint8_t)(crc >> 8);
            if (send_all(fd, rsp, plen + 3, 0) != 0)
                logf_("could not write the answer to %s: %s", dev, strerror(errno));
        }
    }
    if (ctx != conn) {
        modbus_set_socket(ctx, -1);
        modbus_free(ctx);
    }
    modbus_close(conn);
    modbus_free(conn);
    if (d->verbose) logf_("stopped");
    return status;
}

/* ---------------------------------------------------------------------------------------
 * main
 * ------------------------------------------------------------------------------------- */

/* 1 when the options give a plant other than the paper's drive (a value that differs
 * from its default, or a range): it then needs its loop and its gain bounds. */
static int plant_of_options(const zw_cert_opts *co)
{
    zw_cert_opts paper;
    static const int plant_fields[] = {0, 1, 2, 15, 16};
    size_t k;
    zw_cert_opts_defaults(&paper);
    for (k = 0; k < sizeof plant_fields / sizeof plant_fields[0]; ++k) {
        const int f = plant_fields[k];
        if (co->given[f] && (f >= 15 || co->v[f] != paper.v[f])) return 1;
    }
    return 0;
}

/* The gain bounds: the paper drive's defaults without a plant; given, or derived from the
 * plant's certified limits in its loop (--gain-bounds from-limits), with one.  Fills the
 * bounds not given when deriving, says where they come from in from (for the start line);
 * 0 after printing why the drive refuses to start. */
static int gain_bounds(zw_cert_opts *co, int from_limits, char *from, size_t cap)
{
    static const int bound_fields[] = {6, 7, 8, 9, 10}; /* k_max b_min b_max dk_max db_max */
    static zw_device_loop dl;                           /* large: not on the stack */
    static zw_loop_workspace ws;
    const int plant = plant_of_options(co);
    char missing[128] = "";
    size_t k, n_missing = 0;
    if (plant && !co->given[11]) {
        fprintf(stderr, PROG ": a drive given its plant (--m/--J, --b, --T) needs its loop: "
                        ZW_LOOP_NOT_STATED "\n");
        return 0;
    }
    for (k = 0; k < sizeof bound_fields / sizeof bound_fields[0]; ++k)
        if (!co->given[bound_fields[k]]) {
            size_t len = strlen(missing);
            snprintf(missing + len, sizeof missing - len, "%s%s", n_missing ? ", " : "",
                     zw_cert_option[bound_fields[k]]);
            ++n_missing;
        }
    if (!from_limits) {
        if (plant && n_missing > 0) {
            fprintf(stderr, PROG ": a drive given its plant (--m/--J, --b, --T) needs its gain "
                            "bounds: give %s, or --gain-bounds from-limits (K in [0, K_mmax of the "
                            "loop], B over the loop's B range, steps the full spans); the paper "
                            "drive's bounds (K <= 10, |B| <= 0.01) do not fit another plant\n",
                    missing);
            return 0;
        }
        snprintf(from, cap, "%s", !plant && n_missing == 5 ? "the paper drive's defaults"
                                  : n_missing == 0 ? "given" : "given; the others the paper drive's defaults");
        return 1;
    }
    if (co->given[15] || co->given[16]) {
        fprintf(stderr, PROG ": --gain-bounds from-limits needs a point plant (not --m LO:HI or "
                        "--b LO:HI): give the bounds (--k-max, --b-min, --b-max, --dk-max, --db-max)\n");
        return 0;
    }
    {
        zw_device_loop_spec spec;
        zw_device_loop_extremes y;
        zw_status st;
        double v[5];
        memset(&spec, 0, sizeof spec);
        spec.delay = (unsigned)co->v[11];
        spec.filter = co->v[12] == 1.0 ? ZW_VFILTER_LOWPASS : co->v[12] == 2.0 ? ZW_VFILTER_AVERAGE
                                                                               : ZW_VFILTER_NONE;
        if (spec.filter == ZW_VFILTER_LOWPASS) spec.cutoff_hz = co->v[13];
        if (spec.filter == ZW_VFILTER_AVERAGE) spec.average = (unsigned)co->v[13];
        spec.differentiator = co->v[14] == 1.0 ? ZW_DIFF_TUSTIN : ZW_DIFF_BACKWARD;
        if ((st = zw_device_loop_init(&dl, co->v[0], co->v[1], co->v[2], &spec)) != ZW_OK ||
            (st = zw_device_loop_extremes_compute(&dl, &ws, &y)) != ZW_OK || !(y.K_mmax > 0.0)) {
            fprintf(stderr, PROG ": --gain-bounds from-limits: no certified limits for this plant "
                            "and loop (%s)\n", zw_status_name(st));
            return 0;
        }
        v[0] = y.K_mmax;
        v[1] = y.B_mmin;
        v[2] = y.B_mmax;
        v[3] = y.K_mmax;
        v[4] = y.B_mmax - y.B_mmin;
        for (k = 0; k < 5; ++k) { /* the float register rounded inward: never wider */
            float f = (float)v[k];
            if (k == 1 ? (double)f < v[k] : (double)f > v[k]) f = nextafterf(f, k == 1 ? INFINITY : 0.0f);
            if (!co->given[bound_fields[k]]) co->v[bound_fields[k]] = (double)f;
        }
        if (!co->given[5]) co->v[5] = 0.0;
        snprintf(from, cap, "%s from the loop's certified limits: K_mmax = %.6g, B range (%.6g, "
                 "%.6g) as K -> 0+", n_missing == 5 ? "derived" : "those not given derived",
                 v[0], v[1], v[2]);
    }
    return 1;
}

/* An option with one of two values: *first = 1 for the first, 0 for the second; 0 after
 * saying what it expects. */
static int parse_choice(const char *opt, const char *val, const char *first_value, const char *second_value,
                        int *first)
{
    *first = strcmp(val, first_value) == 0;
    if (*first || strcmp(val, second_value) == 0) return 1;
    fprintf(stderr, PROG ": %s expects %s or %s, got '%s'\n", opt, first_value, second_value, val);
    return 0;
}

/* What --identify runs: the experiment of docs/identify.md, offline. */
typedef struct ident_opts {
    const char *out;
    uint_least16_t kind, hold;
    uint_least32_t seed, samples;
    double amplitude, amplitude_max, x_window, v_max, counts_per_unit, x0;
} ident_opts;

#define IDENT_MAX_SAMPLES 65536u

/* Play the identification experiment through zw_ident (the firmware's module, as a
 * drive's control loop calls it) on the plant m x'' + b x' = F, sampled exactly under the
 * zero-order hold, the command computed at tick n applied from tick n + delay; the position
 * measured at each tick (in counts when counts_per_unit > 0), its backward difference the
 * velocity the limits see.  Writes the log and returns the exit status. */
static int run_identify(const ident_opts *o, double m, double b, double T, int delay)
{
    static float command[IDENT_MAX_SAMPLES], position[IDENT_MAX_SAMPLES];
    double pending[ZW_LOOP_MAX_DELAY + 1], x = o->x0, v = 0.0, x_prev;
    const double a = b / m, p = exp(-a * T);
    /* (1 - p)/a and (T - (1 - p)/a)/a, accurate for a T near 0 (b = 0 included) */
    const double g1 = a * T > 1e-5 ? (1.0 - p) / a : T * (1.0 - 0.5 * a * T);
    const double g2 = a * T > 1e-5 ? (T - g1) / a : 0.5 * T * T * (1.0 - a * T / 3.0);
    zw_ident id;
    zw_ident_limits lim;
    zw_ident_request req;
    zw_status st;
    uint_least32_t n;
    FILE *f;
    int k;
    if (delay < 0 || delay > (int)ZW_LOOP_MAX_DELAY) {
        fprintf(stderr, PROG ": --delay must be in 0..%u\n", ZW_LOOP_MAX_DELAY);
        return ZW_EXIT_USAGE;
    }
    lim.amplitude_max = (float)o->amplitude_max;
    lim.x_window = (float)o->x_window;
    lim.v_max = (float)o->v_max;
    lim.samples_max = IDENT_MAX_SAMPLES;
    st = zw_ident_init(&id, &lim, command, position, IDENT_MAX_SAMPLES);
    if (st != ZW_OK) {
        fprintf(stderr, PROG ": the identification ceilings are not valid (%s): --amplitude-max, "
                "--x-window and --v-max must be > 0 and finite\n", zw_status_name(st));
        return ZW_EXIT_USAGE;
    }
    req.kind = o->kind;
    req.hold = o->hold;
    req.seed = o->seed;
    req.amplitude = (float)o->amplitude;
    req.samples = o->samples;
    for (k = 0; k <= (int)ZW_LOOP_MAX_DELAY; ++k) pending[k] = 0.0;
    st = zw_ident_start(&id, &req, (float)o->x0);
    if (st != ZW_OK) {
        fprintf(stderr, PROG ": the identification request is refused by the firmware (%s): the "
                "amplitude must be in (0, --amplitude-max], the samples in 1..%u\n",
                zw_status_name(st), IDENT_MAX_SAMPLES);
        return ZW_EXIT_USAGE;
    }
    x_prev = o->x0;
    for (n = 0; zw_ident_running(&id); ++n) {
        double xm = o->counts_per_unit > 0.0 ? floor(x * o->counts_per_unit + 0.5) / o->counts_per_unit : x;
        double vm = n > 0 ? (xm - x_prev) / T : 0.0, F;
        float u;
        x_prev = xm;
        (void)zw_ident_step(&id, (float)xm, (float)vm, &u);
        /* the delay line: pending[delay] is applied now, the new command enters at 0 */
        for (k = delay; k > 0; --k) pending[k] = pending[k - 1];
        pending[0] = (double)u;
        F = pending[delay];
        x += v * g1 + F * g2 / m;
        v = v * p + F * g1 / m;
    }
    f = fopen(o->out, "w");
    if (f == NULL) {
        fprintf(stderr, PROG ": cannot write %s: %s\n", o->out, strerror(errno));
        return ZW_EXIT_FAILURE;
    }
    fprintf(f, "# zwidth-drive --identify: m = %.9g, b = %.9g, T = %.9g s, delay %d, %s\n", m, b, T, delay,
            o->counts_per_unit > 0.0 ? "position in counts" : "position in m (or rad)");
    fprintf(f, "t,command,position\n");
    for (n = 0; n < id.recorded; ++n) {
        float u, xm;
        (void)zw_ident_sample(&id, n, &u, &xm);
        fprintf(f, "%.9g,%.9g,%.9g\n", (double)n * T, (double)u,
                o->counts_per_unit > 0.0 ? floor((double)xm * o->counts_per_unit + 0.5) : (double)xm);
    }
    if (fclose(f) != 0) {
        fprintf(stderr, PROG ": cannot write %s: %s\n", o->out, strerror(errno));
        return ZW_EXIT_FAILURE;
    }
    if (id.state == ZW_IDENT_TRIPPED) {
        static const char *const why[] = {"", "left the position window (--x-window)",
                                          "exceeded the velocity limit (--v-max)", "measured a non-finite value",
                                          "was aborted"};
        logf_("identification tripped after %lu of %lu samples: the device %s; output off; the %lu "
              "samples before are in %s", (unsigned long)id.recorded, (unsigned long)o->samples,
              why[id.trip <= 4u ? id.trip : 0u], (unsigned long)id.recorded, o->out);
        return ZW_EXIT_FAILURE;
    }
    if (o->counts_per_unit > 0.0)
        logf_("identification done: %lu samples in %s (zwidth identify %s --time t --counts-per-unit %.9g)",
              (unsigned long)id.recorded, o->out, o->out, o->counts_per_unit);
    else
        logf_("identification done: %lu samples in %s (zwidth identify %s --time t)", (unsigned long)id.recorded,
              o->out, o->out);
    return ZW_EXIT_OK;
}

int main(int argc, char **argv)
{
    static drive d; /* large; one per process */
    zw_cert_opts co;
    zw_cert cert;
    zw_reason reason = ZW_REASON_NONE;
    zw_status st;
    const char *host = "127.0.0.1", *rtu = NULL, *key_file = NULL;
    long port = 1502, baud = 19200, slave = 1, max_clients = 16, frame_ms = 500, idle_s = 300;
    char parity = 'N';
    int unsealed = 0, simulate = 0, commissioning = 0, cdab = 0, from_limits = 0, i, rc;
    char bounds_from[200];
    double speed = 1.0, x0 = 0.01, max_sigma = 0.95, max_r = 0.999, plant_tol = 0.05;
    zw_ceilings ceil;
    struct in_addr probe;

    ident_opts io;
    io.out = NULL;
    io.kind = ZW_IDENT_PRBS;
    io.hold = 5u;
    io.seed = 1u;
    io.samples = 4000u;
    io.amplitude = 1.0;
    io.amplitude_max = -1.0; /* the amplitude unless given */
    io.x_window = 1.0;
    io.v_max = 10.0;
    io.counts_per_unit = 0.0;
    zw_cert_opts_defaults(&co);
    for (i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        int r = zw_cert_opts_parse(PROG, &co, argc, argv, &i);
        if (r < 0) return ZW_EXIT_USAGE;
        if (r > 0) continue;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            usage(stdout);
            return ZW_EXIT_OK;
        }
        if (strcmp(arg, "--version") == 0) {
            printf(PROG " %s\n", ZW_VERSION_STRING);
            return ZW_EXIT_OK;
        }
        if (strcmp(arg, "-v") == 0 || strcmp(arg, "--verbose") == 0) { d.verbose = 1; continue; }
        if (strcmp(arg, "--unsealed") == 0) { unsealed = 1; continue; }
        if (strcmp(arg, "--simulate") == 0) { simulate = 1; continue; }
        if (strcmp(arg, "--commissioning") == 0) { commissioning = 1; continue; }
        if (strcmp(arg, "--gain-bounds") == 0) {
            if (val == NULL || strcmp(val, "from-limits") != 0) {
                fprintf(stderr, PROG ": --gain-bounds expects from-limits%s%s%s\n",
                        val != NULL ? ", got '" : "", val != NULL ? val : "", val != NULL ? "'" : "");
                return ZW_EXIT_USAGE;
            }
            from_limits = 1;
            ++i;
            continue;
        }
        if (strcmp(arg, "--host") != 0 && strcmp(arg, "--port") != 0 &&
            strcmp(arg, "--rtu") != 0 && strcmp(arg, "--baud") != 0 &&
            strcmp(arg, "--parity") != 0 && strcmp(arg, "--slave") != 0 &&
            strcmp(arg, "--speed") != 0 && strcmp(arg, "--x0") != 0 &&
            strcmp(arg, "--max-clients") != 0 && strcmp(arg, "--frame-timeout") != 0 &&
            strcmp(arg, "--idle-timeout") != 0 && strcmp(arg, "--key-file") != 0 &&
            strcmp(arg, "--max-sigma") != 0 && strcmp(arg, "--max-r") != 0 &&
            strcmp(arg, "--plant-tol") != 0 && strcmp(arg, "--state-file") != 0 &&
            strcmp(arg, "--word-order") != 0 && strcmp(arg, "--identify") != 0 &&
            strcmp(arg, "--excite") != 0 && strcmp(arg, "--amplitude") != 0 &&
            strcmp(arg, "--samples") != 0 && strcmp(arg, "--hold") != 0 &&
            strcmp(arg, "--seed") != 0 && strcmp(arg, "--counts-per-unit") != 0 &&
            strcmp(arg, "--x-window") != 0 && strcmp(arg, "--v-max") != 0 &&
            strcmp(arg, "--amplitude-max") != 0) {
            fprintf(stderr, PROG ": unknown option '%s'\n", arg);
            usage(stderr);
            return ZW_EXIT_USAGE;
        }
        if (val == NULL) {
            fprintf(stderr, PROG ": missing value for '%s'\n", arg);
            return ZW_EXIT_USAGE;
        }
        ++i;
        if (strcmp(arg, "--host") == 0) {
            if (inet_pton(AF_INET, val, &probe) != 1) {
                fprintf(stderr, PROG ": --host expects an IPv4 address, got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
            /* libmodbus 3.1.6 listens on INADDR_ANY for any address text starting with
             * '0': allow that only for 0.0.0.0 itself. */
            if ((ntohl(probe.s_addr) >> 24) == 0u && probe.s_addr != htonl(INADDR_ANY)) {
                fprintf(stderr, PROG ": --host %s: an address in 0.0.0.0/8 other than 0.0.0.0 "
                                "cannot be listened on\n", val);
                return ZW_EXIT_USAGE;
            }
            host = val;
        } else if (strcmp(arg, "--port") == 0) {
            if (!zw_parse_long(PROG, arg, val, 0, 65535, &port)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--rtu") == 0) {
            rtu = val;
        } else if (strcmp(arg, "--baud") == 0) {
            if (!zw_parse_long(PROG, arg, val, 50, 4000000, &baud)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--parity") == 0) {
            if ((val[0] != 'N' && val[0] != 'E' && val[0] != 'O') || val[1] != '\0') {
                fprintf(stderr, PROG ": --parity expects N, E or O, got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
            parity = val[0];
        } else if (strcmp(arg, "--slave") == 0) {
            if (!zw_parse_long(PROG, arg, val, 1, 247, &slave)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--speed") == 0) {
            if (!zw_parse_double(PROG, arg, val, &speed)) return ZW_EXIT_USAGE;
            if (!(speed > 0.0 && speed <= 1e6)) {
                fprintf(stderr, PROG ": --speed expects a number in (0, 1e6], got '%s'\n", val);
                return ZW_EXIT_USAGE;
            }
        } else if (strcmp(arg, "--x0") == 0) {
            if (!zw_parse_double(PROG, arg, val, &x0)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--max-clients") == 0) {
            if (!zw_parse_long(PROG, arg, val, 1, MAX_CLIENTS_LIMIT, &max_clients))
                return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--frame-timeout") == 0) {
            if (!zw_parse_long(PROG, arg, val, 10, 60000, &frame_ms)) return ZW_EXIT_USAGE;
        } else if (strcmp(arg, "--key-file") == 0) {
            key_file = val;
        } else if (strcmp(arg, "--state-file") == 0) {
            d.state_file = val;
        } else if (strcmp(arg, "--word-order") == 0) {
            int abcd;
            if (!parse_choice(arg, val, "abcd", "cdab", &abcd)) return ZW_EXIT_USAGE;
            cdab = !abcd;
        } else if (strcmp(arg, "--identify") == 0) {
            io.out = val;
        } else if (strcmp(arg, "--excite") == 0) {
            int is_prbs;
            if (!parse_choice(arg, val, "prbs", "steps", &is_prbs)) return ZW_EXIT_USAGE;
            io.kind = is_prbs ? ZW_IDENT_PRBS : ZW_IDENT_STEPS;
        } else if (strcmp(arg, "--samples") == 0) {
            long n;
            if (!zw_parse_long(PROG, arg, val, 1, (long)IDENT_MAX_SAMPLES, &n)) return ZW_EXIT_USAGE;
            io.samples = (uint_least32_t)n;
        } else if (strcmp(arg, "--hold") == 0) {
            long n;
            if (!zw_parse_long(PROG, arg, val, 1, 65535L, &n)) return ZW_EXIT_USAGE;
            io.hold = (uint_least16_t)n;
        } else if (strcmp(arg, "--seed") == 0) {
            long n;
            if (!zw_parse_long(PROG, arg, val, 0, 2147483647L, &n)) return ZW_EXIT_USAGE;
            io.seed = (uint_least32_t)n;
        } else if (strcmp(arg, "--amplitude") == 0 || strcmp(arg, "--amplitude-max") == 0 ||
                   strcmp(arg, "--counts-per-unit") == 0 || strcmp(arg, "--x-window") == 0 ||
                   strcmp(arg, "--v-max") == 0) {
            double *t = strcmp(arg, "--amplitude") == 0       ? &io.amplitude
                        : strcmp(arg, "--amplitude-max") == 0 ? &io.amplitude_max
                        : strcmp(arg, "--counts-per-unit") == 0 ? &io.counts_per_unit
                        : strcmp(arg, "--x-window") == 0      ? &io.x_window
                                                              : &io.v_max;
            if (!zw_parse_double(PROG, arg, val, t)) return ZW_EXIT_USAGE;
            if (!(*t > 0.0 && *t < 1e30)) {
                fprintf(stderr, PROG ": %s expects a number > 0, got '%s'\n", arg, val);
                return ZW_EXIT_USAGE;
            }
        } else if (strcmp(arg, "--max-sigma") == 0 || strcmp(arg, "--max-r") == 0 ||
                   strcmp(arg, "--plant-tol") == 0) {
            double *t = arg[2] == 'p' ? &plant_tol : arg[6] == 's' ? &max_sigma : &max_r;
            if (!zw_parse_double(PROG, arg, val, t)) return ZW_EXIT_USAGE;
        } else {
            if (!zw_parse_long(PROG, arg, val, 0, 86400, &idle_s)) return ZW_EXIT_USAGE;
        }
    }

    if (io.out != NULL) { /* the experiment needs the plant and the loop's delay, no block */
        if (!simulate) {
            fprintf(stderr, PROG ": --identify runs on the simulated plant: give --simulate (on a real drive the "
                    "firmware plays it through ident.h)\n");
            return ZW_EXIT_USAGE;
        }
        if (!(co.v[0] > 0.0) || !(co.v[1] >= 0.0) || !(co.v[2] > 0.0)) {
            fprintf(stderr, PROG ": --identify needs the simulated plant: --m (or --J) > 0, --b >= 0, --T > 0\n");
            return ZW_EXIT_USAGE;
        }
        if (io.amplitude_max < 0.0) io.amplitude_max = io.amplitude;
        io.x0 = x0;
        return run_identify(&io, co.v[0], co.v[1], co.v[2], (int)co.v[11]);
    }
    if (!gain_bounds(&co, from_limits, bounds_from, sizeof bounds_from)) return ZW_EXIT_USAGE;
    zw_cert_opts_to_cert(&co, &cert);
    { /* which plant, loop and bounds this drive certifies for, always said */
        char plant[200], loop[200];
        if (zw_cert_ranged(&cert))
            snprintf(plant, sizeof plant, "m in [%.6g, %.6g], b in [%.6g, %.6g], T = %.6g s",
                     co.v[0], co.given[15] ? co.v[15] : co.v[0], co.v[1],
                     co.given[16] ? co.v[16] : co.v[1], co.v[2]);
        else
            snprintf(plant, sizeof plant, "m = %.6g, b = %.6g, T = %.6g s", co.v[0], co.v[1], co.v[2]);
        zw_cert_loop_text(&cert, loop, sizeof loop);
        logf_("%s %s; loop: %s; gain bounds: K in [%.6g, %.6g], B in [%.6g, %.6g], |dK| <= %.6g, "
              "|dB| <= %.6g per write (%s)", plant_of_options(&co) ? "plant" : "the paper's drive:",
              plant, loop, co.v[5], co.v[6], co.v[7], co.v[8], co.v[9], co.v[10], bounds_from);
    }
    st = zw_regmap_init(&d.rm, unsealed ? NULL : &cert, &reason);
    if (st == ZW_ERR_FPENV) { /* the machine, not the block: no block could be sealed here */
        fprintf(stderr, PROG ": the floating-point self-test failed (%s, %s): this build or "
                "machine cannot certify gains\n", zw_reason_name(reason), zw_status_name(st));
        return ZW_EXIT_FAILURE;
    }
    if (st != ZW_OK) {
        fprintf(stderr, PROG ": the certified block is not acceptable: %s (%s)\n",
                zw_reason_name(reason), zw_status_name(st));
        return ZW_EXIT_USAGE;
    }
    /* The factory ceilings: the plant and the bounds of the block options are the nameplate
     * and the widest allowed, sealed or not (--unsealed). */
    ceil.sigma_max = (float)max_sigma;
    ceil.r_max = (float)max_r;
    ceil.m = cert.m;
    ceil.b = cert.b;
    ceil.T = cert.T;
    ceil.plant_tol = (float)plant_tol;
    if (zw_cert_ranged(&cert)) {
        /* a box at power-up: the nameplate is its middle and the tolerance covers its ends
         * (a little more than the half-width, for the float rounding of the middle) */
        const double mm = 0.5 * ((double)cert.m + (double)cert.m_hi);
        const double bm = 0.5 * ((double)cert.b + (double)cert.b_hi);
        double tol = plant_tol;
        if (mm > 0.0 && 1.001 * ((double)cert.m_hi - mm) / mm > tol) tol = 1.001 * ((double)cert.m_hi - mm) / mm;
        if (bm > 0.0 && 1.001 * ((double)cert.b_hi - bm) / bm > tol) tol = 1.001 * ((double)cert.b_hi - bm) / bm;
        ceil.m = (float)mm;
        ceil.b = (float)bm;
        ceil.plant_tol = (float)tol;
    }
    ceil.k_min = cert.k_min;
    ceil.k_max = cert.k_max;
    ceil.b_min = cert.b_min;
    ceil.b_max = cert.b_max;
    ceil.dk_max = cert.dk_max;
    ceil.db_max = cert.db_max;
    /* the loop this firmware runs: its options' (--delay, --velocity-filter,
     * --differentiator), which --simulate runs too; a block for another loop is refused */
    ceil.delay = cert.delay;
    ceil.vfilter = cert.vfilter;
    ceil.vf_param = cert.vf_param;
    ceil.differentiator = cert.differentiator;
    st = zw_regmap_set_ceilings(&d.rm, &ceil, &reason);
    if (st != ZW_OK) {
        fprintf(stderr, PROG ": %s: %s (%s)\n",
                reason == ZW_REASON_BAD_POLICY ? "the factory ceilings are not valid"
                                               : "the certified block exceeds the factory ceilings",
                zw_reason_name(reason), zw_status_name(st));
        return ZW_EXIT_USAGE;
    }
    if (commissioning && key_file == NULL) {
        fprintf(stderr, PROG ": --commissioning needs --key-file (the key a client must hold)\n");
        return ZW_EXIT_USAGE;
    }
    if (key_file != NULL) {
        zw_regmap_auth hooks;
        if (!zw_key_load(PROG, key_file, d.key)) return ZW_EXIT_USAGE;
        hooks.random = drive_random;
        hooks.verify = drive_verify;
        hooks.ctx = &d;
        zw_regmap_set_auth(&d.rm, &hooks);
    }
    zw_regmap_set_consent(&d.rm, commissioning != 0);
    zw_regmap_set_word_order(&d.rm, cdab ? ZW_WORD_ORDER_CDAB : ZW_WORD_ORDER_ABCD);
    if (d.state_file != NULL) {
        uint_least8_t img[2][ZW_IMAGE_BYTES + 16];
        size_t len[2];
        char prev_path[4096];
        zw_regmap_storage storage;
        if (snprintf(prev_path, sizeof prev_path, "%s.prev", d.state_file) >= (int)sizeof prev_path) {
            fprintf(stderr, PROG ": --state-file path too long\n");
            return ZW_EXIT_USAGE;
        }
        len[0] = read_image(d.state_file, img[0], sizeof img[0]);
        len[1] = read_image(prev_path, img[1], sizeof img[1]);
        if (len[0] > 0 || len[1] > 0) {
            (void)zw_regmap_restore(&d.rm, len[0] > 0 ? img[0] : NULL, len[0],
                                    len[1] > 0 ? img[1] : NULL, len[1], &reason);
            if (d.rm.restore_source == 0u)
                logf_("stored settings refused (%s): the power-up block stays, gains off",
                      zw_reason_name(reason));
            else
                logf_("restored the sealed block%s from %s%s%s", reason == ZW_REASON_NONE || d.rm.restore_source == 2u ? " and gains" : " (gains off)",
                      d.rm.restore_source == 1u ? d.state_file : prev_path,
                      reason != ZW_REASON_NONE ? "; refused: " : "",
                      reason != ZW_REASON_NONE ? zw_reason_name(reason) : "");
        }
        storage.save = drive_save;
        storage.ctx = &d;
        zw_regmap_set_storage(&d.rm, &storage);
    }
    if (simulate) {
        st = sim_start(&d.s, &co, x0, speed);
        if (st != ZW_OK) {
            fprintf(stderr, PROG ": cannot simulate the plant m=%g, b=%g, T=%g with this loop: %s\n",
                    co.v[0], co.v[1], co.v[2], zw_status_name(st));
            return ZW_EXIT_USAGE;
        }
        d.s.t0 = now_s();
    }
    if (rtu == NULL && strncmp(host, "127.", 4) != 0)
        logf_("warning: listening on %s; Modbus has no authentication, anyone who reaches "
              "this port can write gains (see docs/modbus.md)", host);
    if (install_signals() != 0) {
        fprintf(stderr, PROG ": cannot install signal handlers: %s\n", strerror(errno));
        return ZW_EXIT_FAILURE;
    }

    d.log_tokens = LOG_BURST;
    d.log_last = now_s();
    atomic_init(&d.sim_stop, false);
    if (d.s.on) {
        pthread_t sim_tid;
        d.s.t0 = now_s();
        if (pthread_create(&sim_tid, NULL, sim_thread, &d) != 0) {
            fprintf(stderr, PROG ": cannot start the simulation thread\n");
            return ZW_EXIT_FAILURE;
        }
        if (rtu != NULL) rc = serve_rtu(&d, rtu, (int)baud, parity, (int)slave);
        else rc = serve_tcp(&d, host, (int)port, (int)max_clients, (double)frame_ms / 1000.0,
                            (double)idle_s);
        atomic_store(&d.sim_stop, true);
        (void)pthread_join(sim_tid, NULL);
    } else if (rtu != NULL) {
        rc = serve_rtu(&d, rtu, (int)baud, parity, (int)slave);
    } else {
        rc = serve_tcp(&d, host, (int)port, (int)max_clients, (double)frame_ms / 1000.0,
                       (double)idle_s);
    }
    log_summary(&d, now_s(), 1);
    if (d.s.on && d.s.late_n > 0)
        logf_("simulation: %lu steps; lateness behind the schedule: worst %.3f ms, mean %.3f ms, "
              "%lu steps over 5 ms", d.s.late_n, d.s.late_max * 1000.0,
              d.s.late_sum / (double)d.s.late_n * 1000.0, d.s.late_over_5ms);
    close(g_sigpipe[0]);
    close(g_sigpipe[1]);
    return rc;
}
