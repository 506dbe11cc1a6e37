/* zw_mbhost.c - helpers shared by zwidth-drive and zwidth-tune (see zw_mbhost.h). */
#include "zw_mbhost.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *const zw_cert_option[ZW_CERT_FIELDS] = {
    "--m", "--b", "--T", "--sigma", "--r", "--k-min", "--k-max", "--b-min", "--b-max",
    "--dk-max", "--db-max"};

const char *const zw_cert_label[ZW_CERT_FIELDS] = {
    "m", "b", "T", "sigma", "r", "k_min", "k_max", "b_min", "b_max", "dk_max", "db_max"};

static const double cert_default[ZW_CERT_FIELDS] = {
    85.78e-7, 2.197e-3, 0.02, 0.8, 0.999, 0.0, 10.0, -0.01, 0.01, 1.0, 0.01};

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
    for (i = 0; i < ZW_CERT_FIELDS; ++i) {
        o->v[i] = cert_default[i];
        o->given[i] = 0;
    }
}

int zw_cert_opts_parse(const char *prog, zw_cert_opts *o, int argc, char **argv, int *i)
{
    const char *arg = argv[*i];
    int k;
    for (k = 0; k < ZW_CERT_FIELDS; ++k) {
        if (strcmp(arg, zw_cert_option[k]) == 0 ||
            (k == 0 && strcmp(arg, "--J") == 0)) /* inertia, as in zwidth-limits */
            break;
    }
    if (k == ZW_CERT_FIELDS) return 0;
    if (*i + 1 >= argc) {
        fprintf(stderr, "%s: missing value for '%s'\n", prog, arg);
        return -1;
    }
    if (!zw_parse_double(prog, arg, argv[*i + 1], &o->v[k])) return -1;
    /* A float register cannot hold it: refuse here rather than send infinity. */
    if (fabs(o->v[k]) > (double)FLT_MAX) {
        fprintf(stderr, "%s: %s %s does not fit a float register\n", prog, arg, argv[*i + 1]);
        return -1;
    }
    o->given[k] = 1;
    *i += 1;
    return 1;
}

void zw_cert_opts_to_cert(const zw_cert_opts *o, zw_cert *out)
{
    out->m = (float)o->v[0];
    out->b = (float)o->v[1];
    out->T = (float)o->v[2];
    out->sigma = (float)o->v[3];
    out->r = (float)o->v[4];
    out->k_min = (float)o->v[5];
    out->k_max = (float)o->v[6];
    out->b_min = (float)o->v[7];
    out->b_max = (float)o->v[8];
    out->dk_max = (float)o->v[9];
    out->db_max = (float)o->v[10];
}

float zw_cert_field(const zw_cert *c, int index)
{
    switch (index) {
    case 0: return c->m;
    case 1: return c->b;
    case 2: return c->T;
    case 3: return c->sigma;
    case 4: return c->r;
    case 5: return c->k_min;
    case 6: return c->k_max;
    case 7: return c->b_min;
    case 8: return c->b_max;
    case 9: return c->dk_max;
    default: return c->db_max;
    }
}

void zw_cert_to_words(const zw_cert *c, uint_least16_t words[ZW_CERT_WORDS])
{
    int k;
    for (k = 0; k < ZW_CERT_FIELDS; ++k) zw_float_to_words(zw_cert_field(c, k), &words[2 * k]);
}

void zw_cert_from_words(const uint_least16_t words[ZW_CERT_WORDS], zw_cert *out)
{
    out->m = zw_words_to_float(&words[0]);
    out->b = zw_words_to_float(&words[2]);
    out->T = zw_words_to_float(&words[4]);
    out->sigma = zw_words_to_float(&words[6]);
    out->r = zw_words_to_float(&words[8]);
    out->k_min = zw_words_to_float(&words[10]);
    out->k_max = zw_words_to_float(&words[12]);
    out->b_min = zw_words_to_float(&words[14]);
    out->b_max = zw_words_to_float(&words[16]);
    out->dk_max = zw_words_to_float(&words[18]);
    out->db_max = zw_words_to_float(&words[20]);
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

void zw_json_float(FILE *to, double v)
{
    if (isfinite(v)) fprintf(to, "%.9g", v);
    else fputs("null", to);
}
