/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_mbhost.c - helpers shared by zwidth-drive and zwidth-tune (see zw_mbhost.h). */
#include "zw_mbhost.h"
#include "zw_hostloop.h"

#include <errno.h>
#include <fcntl.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/rand.h>

const char *const zw_cert_option[ZW_CERT_NFIELDS] = {
    "--m", "--b", "--T", "--sigma", "--r", "--k-min", "--k-max", "--b-min", "--b-max",
    "--dk-max", "--db-max", "--delay", "--velocity-filter", "--velocity-filter",
    "--differentiator", "--m-hi", "--b-hi"};

const char *const zw_cert_label[ZW_CERT_NFIELDS] = {
    "m", "b", "T", "sigma", "r", "k_min", "k_max", "b_min", "b_max", "dk_max", "db_max",
    "delay", "vfilter", "vf_param", "differentiator", "m_hi", "b_hi"};

static const double cert_default[ZW_CERT_NFIELDS] = {
    85.78e-7, 2.197e-3, 0.02, 0.8, 0.999, 0.0, 10.0, -0.01, 0.01, 1.0, 0.01, 0.0, 0.0, 0.0, 0.0,
    0.0, 0.0}; /* m_hi = b_hi = 0: the point block */

/* --velocity-filter as the block holds it: none, lowpass:F[Hz] (the cut-off; the block has
 * no field for a bare pole) or average:N.  The spelling is zw_hostloop's, shared with
 * zwidth-limits and the Python CLI. */
static int parse_velocity_filter(const char *prog, const char *text, double *kind, double *param)
{
    zw_velocity_filter k;
    double f_c, pole;
    unsigned n;
    if (!zw_parse_velocity_filter(prog, text, &k, &f_c, &pole, &n)) return 0;
    if (k == ZW_VFILTER_NONE) {
        *kind = *param = 0.0;
        return 1;
    }
    if (k == ZW_VFILTER_LOWPASS && f_c > 0.0 && f_c <= (double)FLT_MAX) {
        *kind = 1.0;
        *param = f_c;
        return 1;
    }
    if (k == ZW_VFILTER_AVERAGE && n >= 1u && n <= 16u) {
        *kind = 2.0;
        *param = (double)n;
        return 1;
    }
    fprintf(stderr, "%s: --velocity-filter expects none, lowpass:F[Hz] (F > 0) or average:N "
                    "(1..16), got '%s'%s\n", prog, text,
            k == ZW_VFILTER_LOWPASS && f_c == 0.0 && pole != 0.0
                ? " (the certified block holds a cut-off in Hz, not a pole)" : "");
    return 0;
}

int zw_parse_double(const char *prog, const char *name, const char *text, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(text, &end);
    if (errno != 0 || end == text || *end != '\0' || !isfinite(v)) {
        fprintf(stderr, "%s: %s expects a finite number, got '%s'\n", prog, name, text);
        return 0;
    }
    *out = v;
    return 1;
}

int zw_parse_long(const char *prog, const char *name, const char *text, long lo, long hi,
                  long *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || v < lo || v > hi) {
        fprintf(stderr, "%s: %s expects an integer in [%ld, %ld], got '%s'\n", prog, name, lo,
                hi, text);
        return 0;
    }
    *out = v;
    return 1;
}

void zw_cert_opts_defaults(zw_cert_opts *o)
{
    int i;
    for (i = 0; i < ZW_CERT_NFIELDS; ++i) {
        o->v[i] = cert_default[i];
        o->given[i] = 0;
    }
}

int zw_cert_opts_parse(const char *prog, zw_cert_opts *o, int argc, char **argv, int *i)
{
    const char *arg = argv[*i];
    int k;
    for (k = 0; k < ZW_CERT_NFIELDS; ++k) {
        if (strcmp(arg, zw_cert_option[k]) == 0 ||
            (k == 0 && strcmp(arg, "--J") == 0)) /* inertia, as in zwidth-limits */
            break;
    }
    if (k == ZW_CERT_NFIELDS) return 0;
    if (*i + 1 >= argc) {
        fprintf(stderr, "%s: missing value for '%s'\n", prog, arg);
        return -1;
    }
    if (k == 11) { /* --delay */
        long d;
        if (!zw_parse_long(prog, arg, argv[*i + 1], 0, 8, &d)) return -1;
        o->v[k] = (double)d;
    } else if (k == 12) { /* --velocity-filter: kind and parameter */
        if (!parse_velocity_filter(prog, argv[*i + 1], &o->v[12], &o->v[13])) return -1;
        o->given[13] = 1;
    } else if (k == 14) { /* --differentiator */
        zw_differentiator diff;
        if (!zw_parse_differentiator(prog, argv[*i + 1], &diff)) return -1;
        o->v[k] = diff == ZW_DIFF_TUSTIN ? 1.0 : 0.0;
    } else if ((k == 0 || k == 1) && strchr(argv[*i + 1], ':') != NULL) {
        /* --m LO:HI, --b LO:HI: a range (map version 4), the lower end in m or b */
        char lo[64];
        const char *text = argv[*i + 1], *colon = strchr(text, ':');
        const int hi_k = k == 0 ? 15 : 16;
        size_t len = (size_t)(colon - text);
        if (len == 0 || len >= sizeof lo) {
            fprintf(stderr, "%s: %s expects a number or LO:HI, got '%s'\n", prog, arg, text);
            return -1;
        }
        memcpy(lo, text, len);
        lo[len] = '\0';
        if (!zw_parse_double(prog, arg, lo, &o->v[k]) ||
            !zw_parse_double(prog, arg, colon + 1, &o->v[hi_k]))
            return -1;
        if (fabs(o->v[k]) > (double)FLT_MAX || fabs(o->v[hi_k]) > (double)FLT_MAX) {
            fprintf(stderr, "%s: %s %s does not fit a float register\n", prog, arg, text);
            return -1;
        }
        o->given[hi_k] = 1;
    } else {
        if (!zw_parse_double(prog, arg, argv[*i + 1], &o->v[k])) return -1;
        /* A float register cannot hold it: refuse here rather than send infinity. */
        if (fabs(o->v[k]) > (double)FLT_MAX) {
            fprintf(stderr, "%s: %s %s does not fit a float register\n", prog, arg, argv[*i + 1]);
            return -1;
        }
    }
    o->given[k] = 1;
    *i += 1;
    return 1;
}

void zw_cert_opts_to_cert(const zw_cert_opts *o, zw_cert *out)
{
    unsigned k;
    memset(out, 0, sizeof *out);
    for (k = 0; k < ZW_CERT_FIELDS; ++k) zw_cert_set_field(out, k, (float)o->v[k]);
    /* an upper end not given is the lower end (a point in that quantity): the block always
     * carries explicit ends, as the Python client writes it */
    if (!o->given[15]) out->m_hi = out->m;
    if (!o->given[16]) out->b_hi = out->b;
}

int zw_cert_ranged(const zw_cert *c)
{
    return !(c->m_hi == 0.0f && c->b_hi == 0.0f) && (c->m_hi != c->m || c->b_hi != c->b);
}

void zw_cert_plant_text(const zw_cert *c, char *buf, size_t cap)
{
    if (zw_cert_ranged(c))
        snprintf(buf, cap, "m in [%.9g, %.9g], b in [%.9g, %.9g], T = %.9g s (a box of plants)",
                 (double)c->m, (double)c->m_hi, (double)c->b, (double)c->b_hi, (double)c->T);
    else
        snprintf(buf, cap, "m = %.9g, b = %.9g, T = %.9g s", (double)c->m, (double)c->b,
                 (double)c->T);
}

uint16_t zw_crc16_bytes(const uint8_t *data, size_t len)
{
    unsigned crc = 0xFFFFu;
    size_t i;
    int bit;
    for (i = 0; i < len; ++i) {
        crc ^= data[i];
        for (bit = 0; bit < 8; ++bit) crc = (crc & 1u) ? (crc >> 1) ^ 0xA001u : crc >> 1;
    }
    return (uint16_t)crc;
}

const char *zw_exception_name(unsigned code)
{
    switch (code) {
    case 0x00: return "NONE";
    case 0x01: return "ILLEGAL_FUNCTION";
    case 0x02: return "ILLEGAL_DATA_ADDRESS";
    case 0x03: return "ILLEGAL_DATA_VALUE";
    case 0x04: return "SERVER_DEVICE_FAILURE";
    case 0x06: return "SERVER_DEVICE_BUSY";
    default: return "EXCEPTION";
    }
}

void zw_json_string(FILE *to, const char *s)
{
    fputc('"', to);
    for (; *s != '\0'; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(to, "\\%c", c);
        else if (c < 0x20) fprintf(to, "\\u%04x", c);
        else fputc(c, to);
    }
    fputc('"', to);
}

void zw_cert_loop_text(const zw_cert *c, char *buf, size_t cap)
{
    char filt[96];
    const char *diff = c->differentiator == 1.0f ? "Tustin" : "backward difference";
    if (c->delay == 0.0f && c->vfilter == 0.0f && c->differentiator == 0.0f) {
        snprintf(buf, cap, "ideal loop (delay 0, backward difference, no filter)");
        return;
    }
    if (c->vfilter == 1.0f)
        snprintf(filt, sizeof filt, "low-pass %.6g Hz (pole %.6g)", (double)c->vf_param,
                 exp(-2.0 * 3.14159265358979323846 * (double)c->vf_param * (double)c->T));
    else if (c->vfilter == 2.0f)
        snprintf(filt, sizeof filt, "moving average over %.0f", (double)c->vf_param);
    else
        snprintf(filt, sizeof filt, "no filter");
    snprintf(buf, cap, "delay %.0f, %s, %s", (double)c->delay, filt, diff);
}

void zw_json_float(FILE *to, double v)
{
    if (isfinite(v)) fprintf(to, "%.9g", v);
    else fputs("null", to);
}

/* ---- commissioning key and MAC -------------------------------------------------------- */

static int hex_digit(int c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

int zw_key_load(const char *prog, const char *path, uint8_t key[ZW_KEY_BYTES])
{
    char text[256];
    struct stat st;
    ssize_t n;
    size_t i, k = 0;
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        fprintf(stderr, "%s: cannot open the key file %s: %s\n", prog, path, strerror(errno));
        return 0;
    }
    /* checked on the open file, so that nothing can swap it between check and read */
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        fprintf(stderr, "%s: the key file %s is not a regular file\n", prog, path);
        close(fd);
        return 0;
    }
    if (st.st_uid != geteuid()) {
        fprintf(stderr, "%s: the key file %s is not owned by this user\n", prog, path);
        close(fd);
        return 0;
    }
    if ((st.st_mode & (mode_t)077) != 0) {
        fprintf(stderr, "%s: the key file %s is accessible by group or others (mode %03o); "
                        "chmod 600 it\n", prog, path, (unsigned)(st.st_mode & 0777));
        close(fd);
        return 0;
    }
    n = read(fd, text, sizeof text - 1u);
    close(fd);
    if (n < 0) {
        fprintf(stderr, "%s: cannot read the key file %s: %s\n", prog, path, strerror(errno));
        return 0;
    }
    for (i = 0; i < (size_t)n; ++i) {
        int c = (unsigned char)text[i], h;
        if (c == ' ' || c == '\n' || c == '\r' || c == '\t') {
            if (k != 0u && k != 2u * ZW_KEY_BYTES) break; /* whitespace only around the digits */
            continue;
        }
        h = hex_digit(c);
        if (h < 0 || k >= 2u * ZW_KEY_BYTES) { k = 0; break; }
        if (k % 2u == 0u) key[k / 2u] = (uint8_t)(h << 4);
        else key[k / 2u] = (uint8_t)(key[k / 2u] | h);
        ++k;
    }
    OPENSSL_cleanse(text, sizeof text);
    if (k != 2u * ZW_KEY_BYTES) {
        fprintf(stderr, "%s: the key file %s must hold exactly 64 hex digits (a 32-byte key: "
                        "openssl rand -hex 32)\n", prog, path);
        OPENSSL_cleanse(key, ZW_KEY_BYTES);
        return 0;
    }
    return 1;
}

int zw_hmac_sha256(const uint8_t key[ZW_KEY_BYTES], const uint8_t *msg, size_t len, uint8_t mac[32])
{
    unsigned int out_len = 0;
    if (HMAC(EVP_sha256(), key, (int)ZW_KEY_BYTES, msg, len, mac, &out_len) == NULL) return 0;
    return out_len == 32u;
}

int zw_hmac_sha256_verify(const uint8_t key[ZW_KEY_BYTES], const uint8_t *msg, size_t len,
                          const uint8_t *mac, size_t mac_len)
{
    uint8_t want[32];
    int ok;
    if (mac_len != sizeof want || !zw_hmac_sha256(key, msg, len, want)) return 0;
    ok = CRYPTO_memcmp(want, mac, sizeof want) == 0;
    OPENSSL_cleanse(want, sizeof want);
    return ok;
}

int zw_random_bytes(uint8_t *out, size_t n)
{
    return n <= (size_t)0x7FFFFFFF && RAND_bytes(out, (int)n) == 1;
}
