/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_mbhost.h - helpers shared by the Modbus host programs zwidth-drive and zwidth-tune:
 * number parsing, the certified-block options, the CRC of RTU frames, exception names.
 * Host only (stdio, POSIX); the firmware core never sees this.
 */
#ifndef ZW_MBHOST_H
#define ZW_MBHOST_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "zwidth/regmap.h"

/* Exit statuses shared by both programs (documented in their --help and docs/modbus.md). */
enum {
    ZW_EXIT_OK = 0,
    ZW_EXIT_FAILURE = 1, /* drive: run-time failure (cannot listen, serial line lost) */
    ZW_EXIT_USAGE = 2,   /* bad arguments; tune: also connection or protocol failure */
    ZW_EXIT_REFUSED = 3  /* tune: the drive refused the request (exception response) */
};

/* Strict number parsing: the whole text must be a finite number (or an integer in
 * [lo, hi]); on failure prints "<prog>: <name> expects ..., got '<text>'" and returns 0. */
int zw_parse_double(const char *prog, const char *name, const char *text, double *out);
int zw_parse_long(const char *prog, const char *name, const char *text, long lo, long hi,
                  long *out);

/* The certified block as options: --m --b --T --sigma --r --k-min --k-max --b-min --b-max
 * --dk-max --db-max (the policy, ZW_CERT_NPOLICY fields, all needed to commission), then
 * the loop: --delay D (0..8), --velocity-filter none|lowpass:F[Hz]|average:N (fields
 * vfilter and vf_param; spelled as zw_hostloop.h parses it, shared with zwidth-limits; the
 * block holds a cut-off, so pole:A is refused), --differentiator backward|tustin; the loop
 * fields default to the ideal one (0, none, backward), and given[11] says whether --delay
 * was given (zwidth-drive requires it with a plant).  Then the plant ranges (map version 4): --m-hi, --b-hi, or
 * --m LO:HI and --b LO:HI (the lower end in --m / --b); an upper end not given is the
 * lower end (a point block has M_HI = M, B_HI = B).  Index i is register
 * ZW_REG_CERT_M + 2 i. */
#define ZW_CERT_NFIELDS ((int)ZW_CERT_FIELDS) /* the block's 17 fields, as an int for loops */
#define ZW_CERT_NPOLICY 11                    /* the first 11: plant and policy */

typedef struct zw_cert_opts {
    double v[ZW_CERT_NFIELDS];
    int given[ZW_CERT_NFIELDS];
} zw_cert_opts;

extern const char *const zw_cert_option[ZW_CERT_NFIELDS]; /* "--m", "--b", ... */
extern const char *const zw_cert_label[ZW_CERT_NFIELDS];  /* "m", "b", "T", "sigma", ... */

/* The paper's drive: J = 85.78e-7, b = 2.197e-3, T = 0.02, sigma 0.8, r 0.999, K in
 * [0, 10], B in [-0.01, 0.01], dK 1, dB 0.01 (nothing marked given). */
void zw_cert_opts_defaults(zw_cert_opts *o);

/* If argv[*i] is a certified-block option, parse its value (advancing *i) and return 1;
 * 0 if it is not one; -1 on a missing or bad value (message printed). */
int zw_cert_opts_parse(const char *prog, zw_cert_opts *o, int argc, char **argv, int *i);

/* The numbers as the float block. */
void zw_cert_opts_to_cert(const zw_cert_opts *o, zw_cert *out);

/* 1 when block c holds ranges (M_HI > M or B_HI > B), and the plant as text:
 * "m = .., b = .., T = .. s" or "m in [.., ..], b in [.., ..], T = .. s (a box of plants)". */
int zw_cert_ranged(const zw_cert *c);
void zw_cert_plant_text(const zw_cert *c, char *buf, size_t cap);

/* CRC-16/MODBUS of a byte string (RTU framing; the low byte goes on the wire first). */
uint16_t zw_crc16_bytes(const uint8_t *data, size_t len);

/* "ILLEGAL_DATA_ADDRESS" etc.; "NONE" for 0, "EXCEPTION" for others. */
const char *zw_exception_name(unsigned code);

/* Print a string as a JSON string literal (quotes and escapes). */
void zw_json_string(FILE *to, const char *s);

/* The loop fields of a block as text: "delay 1, low-pass 30 Hz (pole 0.8282), backward
 * difference" (pole from T; "ideal loop" when all are 0). */
void zw_cert_loop_text(const zw_cert *c, char *buf, size_t cap);

/* A float for JSON: %.9g, or null when not finite. */
void zw_json_float(FILE *to, double v);

/* Commissioning key and MAC (OpenSSL libcrypto; docs/modbus.md, "Consent and key").
 * The key file holds the drive's 32-byte key as 64 hex digits (whitespace around them is
 * ignored): `umask 077; openssl rand -hex 32 > drive.key`.  zw_key_load refuses a file
 * that is not a regular file, is not owned by the user running the program, or can be
 * read or written by the group or others (message "<prog>: ..." printed, returns 0). */
#define ZW_KEY_BYTES 32u
int zw_key_load(const char *prog, const char *path, uint8_t key[ZW_KEY_BYTES]);
/* HMAC-SHA256 of msg under key (mac: 32 bytes); 0 on a libcrypto failure. */
int zw_hmac_sha256(const uint8_t key[ZW_KEY_BYTES], const uint8_t *msg, size_t len, uint8_t mac[32]);
/* mac[0..mac_len-1] is the HMAC-SHA256 of msg under key (constant-time comparison). */
int zw_hmac_sha256_verify(const uint8_t key[ZW_KEY_BYTES], const uint8_t *msg, size_t len,
                          const uint8_t *mac, size_t mac_len);
/* n bytes from the OS's cryptographic RNG (libcrypto RAND_bytes); 0 on failure. */
int zw_random_bytes(uint8_t *out, size_t n);

#endif /* ZW_MBHOST_H */
