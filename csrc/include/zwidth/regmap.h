/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/regmap.h - the drive-side gain register map and its certification policy.
 *
 * Portable C99 for the firmware (no libmodbus, no heap, no I/O; works with 16-bit chars
 * on TI C28x): a Modbus stack hands every request PDU to zw_regmap_handle_pdu, which
 * validates the whole request before anything changes and answers with a normal or an
 * exception response.  A refused write changes nothing but the refusal registers.
 *
 * Holding registers (function codes 0x03 read, 0x06 write single, 0x10 write multiple;
 * any other function code gets exception 0x01).  Floats are IEEE-754 binary32 over two
 * registers, high word first (big-endian "ABCD"); 32-bit counters likewise.
 *
 *   addr    name                    access  meaning
 *   0x0000  ZW_REG_MAGIC            r       0x5A57 ("ZW")
 *   0x0001  ZW_REG_VERSION          r       map version, 5 (1: no loop description, 2: no
 *                                           commissioning consent, 3: no plant ranges, 4: no
 *                                           box certificate window; see docs/modbus.md for
 *                                           what changed)
 *   0x0002  ZW_REG_MODE             r       0 operation, 1 commissioning
 *   0x0003  ZW_REG_SEALED           r       1 when the certified block is sealed (CRC valid)
 *   0x0004  ZW_REG_LAST_REASON      r       zw_reason of the last refused request (0 none)
 *   0x0005  ZW_REG_LAST_EXCEPTION   r       Modbus exception code sent for it (0 none)
 *   0x0006  ZW_REG_ACCEPTED (u32)   r       count of accepted gain writes (a write of the
 *                                           current values, or of (0, 0), counts too; block
 *                                           writes and commands do not)
 *   0x0008  ZW_REG_REFUSED (u32)    r       count of refused requests (both wrap at 2^32)
 *           A refused request changes LAST_REASON, LAST_EXCEPTION and REFUSED and nothing
 *           else; an accepted one leaves all three alone.
 *
 *   0x0010  ZW_REG_K (f32)          rw      active stiffness K [N/m or N m/rad]
 *   0x0012  ZW_REG_B (f32)          rw      active damping B [N s/m or N m s/rad]
 *           K and B written in one request (0x10 with 4 registers) are judged as a pair.
 *           Writable in operation mode with a sealed block (else exception 0x02,
 *           ZW_REASON_NOT_SEALED); (0, 0) is "output off" and always accepted (-0.0 counts
 *           as 0).  Writing K alone is judged with the current B, and B alone with the
 *           current K.
 *
 *   0x0020  ZW_REG_LIVE_K_MAX (f32)     r   K_max at the current B (of the drive's loop)
 *   0x0022  ZW_REG_LIVE_K_CERT (f32)    r   certified K ceiling at the current B: the
 *                                           largest K <= min(sigma K_max(B), k_max) that
 *                                           the stability and radius rules accept, to
 *                                           float resolution (found by a 32-point scan down
 *                                           from that bound and a bisection; 0 when no
 *                                           scanned K is accepted).  Itself accepted by
 *                                           the k_max, stability, sigma and radius rules;
 *                                           the k_min and step rules are not applied.
 *   0x0024  ZW_REG_LIVE_B_LO (f32)      r   stable B interval at the current K (lower end)
 *   0x0026  ZW_REG_LIVE_B_HI (f32)      r   ... upper end (both 0 when K = 0).  Ideal loop
 *                                           only: with any other loop both read NaN (the
 *                                           general B range costs ~1.2 M instructions, too
 *                                           slow for every write; hosts compute it)
 *   0x0028  ZW_REG_LIVE_K_MMAX (f32)    r   K_mmax of the plant and loop (computed at SEAL)
 *   0x002A  ZW_REG_LIVE_B_AT_KMMAX (f32) r  the B that attains it (computed at SEAL)
 *   0x002C  ZW_REG_LIVE_RHO (f32)       r   spectral radius at the current gains
 *   0x002E  ZW_REG_LIVE_DELTA (f32)     r   delta = b T / m
 *   0x0038  ZW_REG_LIVE_POLE (f32)      r   the low-pass pole a = exp(-2 pi f_c T) the drive's
 *                                           velocity filter must use (the one certified);
 *                                           0 without a low-pass, NaN unsealed
 *           The live registers but K_MMAX, its B and POLE (plant and loop only: set at SEAL)
 *           are recomputed after every accepted write (and at init),
 *           so a read never runs the core; they read as a quiet NaN (0x7FC0 0x0000)
 *           without a sealed block, or when the core refuses the computation.  In
 *           commissioning mode they describe the last sealed plant with the output off.
 *
 *   0x0030  ZW_REG_STATE_X (f32)        r   device state reported by the firmware through
 *   0x0032  ZW_REG_STATE_V (f32)        r   zw_regmap_set_state (position, velocity,
 *   0x0034  ZW_REG_STATE_F (f32)        r   commanded force, samples since power-up;
 *   0x0036  ZW_REG_STATE_STEP (u32)     r   all 0 until first set)
 *           One read shows one sample: the four come from the same zw_regmap_set_state
 *           call, whichever of them the read covers (see the threading model below).
 *
 *   0x0040  certified block, rw in commissioning mode only (else exception 0x02,
 *           reason ZW_REASON_LOCKED); every field f32.  Reads show the sealed block and
 *           its CRC in operation mode (all 0 when nothing is sealed), the staged words in
 *           commissioning mode.  A staged float must be finite (else 0x03,
 *           ZW_REASON_NOT_FINITE); the CRC word takes any value:
 *   0x0040  ZW_REG_CERT_M       m or J            0x004A  ZW_REG_CERT_K_MIN   K lower bound
 *   0x0042  ZW_REG_CERT_B       b                 0x004C  ZW_REG_CERT_K_MAX   K upper bound
 *   0x0044  ZW_REG_CERT_T       T [s]             0x004E  ZW_REG_CERT_B_MIN   B lower bound
 *   0x0046  ZW_REG_CERT_SIGMA   stiffness fraction 0x0050 ZW_REG_CERT_B_MAX   B upper bound
 *   0x0048  ZW_REG_CERT_R       radius bound r     0x0052 ZW_REG_CERT_DK_MAX  max |dK| per write
 *                                                 0x0054  ZW_REG_CERT_DB_MAX  max |dB| per write
 *   The loop the drive runs (map version 2; each an f32 holding the value):
 *   0x0056  ZW_REG_CERT_DELAY   delay d in samples, an integer 0..8
 *   0x0058  ZW_REG_CERT_VFILTER velocity filter: 0 none, 1 first-order low-pass, 2 moving
 *                               average
 *   0x005A  ZW_REG_CERT_VF_PARAM low-pass: cut-off f_c [Hz], 0 < f_c < 1 / (2 T); moving
 *                               average: n, an integer 1..16; none: 0
 *   0x005C  ZW_REG_CERT_DIFF    differentiator: 0 backward difference, 1 Tustin
 *   The plant box (map version 4): the block certifies every plant m in [M, M_HI],
 *   b in [B, B_HI] (M and B are the lower ends):
 *   0x005E  ZW_REG_CERT_M_HI    upper end of m (M_HI = M, B_HI = B: one plant, as in
 *   0x0060  ZW_REG_CERT_B_HI    upper end of b  version 3; M_HI = B_HI = 0 means the same)
 *   0x0062  ZW_REG_CERT_CRC     CRC-16/MODBUS of the 34 words 0x0040..0x0061, each word
 *                               fed high byte first (rw in commissioning mode)
 *           Older clients can never seal: a version-1 client's CRC at 0x0056 splits DELAY,
 *           and a version-3 client's CRC at 0x005E splits M_HI and its commands at 0x0060
 *           split B_HI (each refused, ZW_REASON_HALF_FLOAT, so it cannot even unlock); a
 *           SEAL over the wrong word count fails the CRC (ZW_REASON_CRC).  Clients read
 *           ZW_REG_VERSION first (zwidth's do, and refuse a version they do not know).
 *   With a ranged block (M_HI > M or B_HI > B) a gain pair is certified for the whole box
 *   (regmap_policy.h); the live registers then hold box values: K_MAX a certified lower
 *   bound of the infimum over the box of K_max(B) (zw_box_loop_k_max, rounded down; lower
 *   than the infimum by up to ZW_REGMAP_BOX_REL_TOL, more when the budget ran out, never
 *   above), K_CERT = min(sigma K_MAX (1 - 1/64), k_max) rounded down (the margin keeps its
 *   proof well within a write's budget), K_MMAX and its B certified for the whole box at
 *   SEAL (zw_box_loop_k_mmax; NaN on error); B_LO, B_HI and RHO read NaN (no box form per
 *   write); DELTA is that of the lower ends (M, B).  Cost: regmap_policy.h and
 *   docs/modbus.md ("Plant ranges").
 *
 *   0x0064  ZW_REG_COMMAND      w       commissioning commands (zwidth/regmap_commission.h)
 *   0x0080  ZW_REG_CONSENT      r       1 when the commissioning enable input is on (map
 *                                       version 3; zwidth/regmap_commission.h)
 *   0x0081  ZW_REG_RESTORE_SOURCE r     what zw_regmap_restore applied: 0 nothing, 1 the
 *                                       newest image, 2 the previous (regmap_persist.h)
 *   0x0082  ZW_REG_RESTORE_REASON r     why an image or its gains were refused (0 none)
 *   0x0083  ZW_REG_WORD_ORDER   r       0 ABCD (high word first, the default), 1 CDAB (low
 *                                       word first) for every f32 and u32 register
 *   0x0084  ZW_REG_PRECISION    r       bytes of the drive's zw_real, 4 (float) or 8 (double)
 *                                       (map version 5): the precision a box certificate
 *                                       must be built in to pass on this drive
 *   0x0088  ZW_REG_NONCE (8)    r       the commissioning session's nonce (0 in operation)
 *   0x0090  ZW_REG_MAC (16)     rw      the client's MAC over the session (rw in
 *                                       commissioning, else LOCKED; 0 in operation)
 *
 *   0x0100  ZW_REG_BOX_CERT (324) rw    a ranged block's box certificate (map version 5;
 *                                       box_cert.h, words as zw_box_cert_encode): rw in
 *                                       commissioning (else LOCKED), reads show the staged
 *                                       words there and the certificate in force in
 *                                       operation (all 0 without one); UNLOCK2 stages the
 *                                       one in force.  Any words may be written (three
 *                                       FC 0x10 requests for the whole window); SEAL judges
 *                                       them:
 *   0x0100  n_steps   0x0101 n_nodes   (one word each)
 *   0x0102  B[0..16]  breakpoints, f32 in the map's word order (34 words)
 *   0x0124  K[0..15]  levels, f32 (32 words)
 *   0x0144  nodes     256 words, four 4-bit node codes each (lowest nibble first)
 *           All 324 words 0: no certificate.  Otherwise SEAL admits the block only with
 *           the certificate verified for its box and loop (at most ZW_BOX_CERT_MAX_LEAVES
 *           interval tests, no search) and canonical (decoding and encoding it gives the
 *           same words); else ZW_REASON_BOX_CERT, and nothing changes.  The MAC covers the
 *           324 words.  A ranged block sealed with one has bounded writes (lookups); one
 *           sealed without runs the box search (unbounded: regmap_policy.h).
 *
 * Everything else is unmapped (exception 0x02, ZW_REASON_UNMAPPED).
 *
 * Certification of a gain pair: zwidth/regmap_policy.h.
 * Value failures answer exception 0x03; address failures (unmapped, read-only, half a
 * float, locked block, gains not writable in this mode) answer 0x02.  The checks run over
 * the whole request in the order of zw_reason (quantity, then every address, then the
 * mode, then the values), so a request that fails several reports the first.  Quantities:
 * 1..125 for reads, 1..123 for writes, address + quantity within 0x10000 (else 0x02).
 * FC 0x06 on one word of a float is ZW_REASON_HALF_FLOAT; a read may start or end inside
 * a float.
 *
 * Threading model.  A drive runs the map in three contexts:
 *   init            zw_regmap_init, before the control interrupt and the Modbus task start
 *                   (it writes everything, with plain stores).
 *   control loop    the control ISR (or the control thread): zw_regmap_active_gains, the
 *                   gain pair to apply this sample, and zw_regmap_set_state.  Both are
 *                   wait-free and constant time (a few loads and stores, no core call),
 *                   never block, and can run at any moment, also in the middle of a
 *                   Modbus request.  Only one context may call zw_regmap_set_state.
 *   Modbus task     zw_regmap_handle_pdu, zw_regmap_read, zw_regmap_write: one task (the
 *                   single writer of everything but the state registers), at a priority
 *                   below the control loop, never in the serial/Ethernet receive ISR: an
 *                   accepted write or a SEAL runs the core (live registers, K_CERT search,
 *                   400-iteration root finder, and for a ranged block the box search): a
 *                   point block's SEAL measured 37,840 instructions on a Cortex-M4F, a
 *                   ranged block's SEAL with its box certificate 3.6-5.0e6 (tools/m4f_box_cert.sh),
 *                   without one (the search) 3.3e9 (about 20 s at 168 MHz), far more on a
 *                   soft-float C28x; measure its worst case on the target and size the
 *                   Modbus task's watchdog and the master's response timeout for it (a
 *                   ranged SEAL needs seconds, not milliseconds).  The control loop only ever reads the
 *                   gains it is handed, so a long request never delays a control sample.
 * The two cross-context channels are published through a double buffer and a sequence word
 * stored once: the writer fills the slot not in force, then stores the sequence word that
 * makes it current.  A reader reads the word, the slot it names, and the word again, and
 * retries (at most ZW_REGMAP_READ_TRIES times) if it changed.  On one core a reader that
 * preempts the writer (the ISR reading the gains) always succeeds at once, because the
 * writer never touches the slot in force; the Modbus task reading the state succeeds
 * unless a control interrupt lands in each of its tries (a few loads each).  On several
 * cores a reader can fail only if the writer publishes throughout all its tries; it then
 * answers fail-safe (gains off, K = B = 0, ZW_ERR_BUSY; a state read answers exception
 * 0x04 and processes nothing) rather than a mix of two publications.  No lock is taken,
 * so nothing an ISR does can deadlock.
 * What a port provides: nothing on one core (every shared access is volatile in C99, and
 * regmap.c puts a compiler barrier, ZW_MEMORY_BARRIER(), between the steps on GCC and
 * Clang).  On several cores, either build regmap.c as C11 with <stdatomic.h> (the shared
 * fields are then _Atomic and the steps acquire/release, the form ThreadSanitizer checks),
 * or define ZW_MEMORY_BARRIER() to a full hardware fence (__DMB(), __sync_synchronize()).
 * The sequence word is 32 bits; where a 32-bit store is two stores (8/16-bit cores) the
 * scheme still holds on one core, as the slot index is its lowest bit.
 */
#ifndef ZWIDTH_REGMAP_H
#define ZWIDTH_REGMAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/box.h"
#include "zwidth/box_cert.h"
#include "zwidth/device_loop.h"
#include "zwidth/regmap_codec.h"
#include "zwidth/regmap_commission.h"
#include "zwidth/regmap_persist.h"
#include "zwidth/regmap_policy.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Register addresses (0-based PDU addresses). */
enum {
    ZW_REG_MAGIC = 0x0000,
    ZW_REG_VERSION = 0x0001,
    ZW_REG_MODE = 0x0002,
    ZW_REG_SEALED = 0x0003,
    ZW_REG_LAST_REASON = 0x0004,
    ZW_REG_LAST_EXCEPTION = 0x0005,
    ZW_REG_ACCEPTED = 0x0006,
    ZW_REG_REFUSED = 0x0008,
    ZW_REG_K = 0x0010,
    ZW_REG_B = 0x0012,
    ZW_REG_LIVE_K_MAX = 0x0020,
    ZW_REG_LIVE_K_CERT = 0x0022,
    ZW_REG_LIVE_B_LO = 0x0024,
    ZW_REG_LIVE_B_HI = 0x0026,
    ZW_REG_LIVE_K_MMAX = 0x0028,
    ZW_REG_LIVE_B_AT_KMMAX = 0x002A,
    ZW_REG_LIVE_RHO = 0x002C,
    ZW_REG_LIVE_DELTA = 0x002E,
    ZW_REG_STATE_X = 0x0030,
    ZW_REG_STATE_V = 0x0032,
    ZW_REG_STATE_F = 0x0034,
    ZW_REG_STATE_STEP = 0x0036,
    ZW_REG_LIVE_POLE = 0x0038,
    ZW_REG_CERT_M = 0x0040,
    ZW_REG_CERT_B = 0x0042,
    ZW_REG_CERT_T = 0x0044,
    ZW_REG_CERT_SIGMA = 0x0046,
    ZW_REG_CERT_R = 0x0048,
    ZW_REG_CERT_K_MIN = 0x004A,
    ZW_REG_CERT_K_MAX = 0x004C,
    ZW_REG_CERT_B_MIN = 0x004E,
    ZW_REG_CERT_B_MAX = 0x0050,
    ZW_REG_CERT_DK_MAX = 0x0052,
    ZW_REG_CERT_DB_MAX = 0x0054,
    ZW_REG_CERT_DELAY = 0x0056,
    ZW_REG_CERT_VFILTER = 0x0058,
    ZW_REG_CERT_VF_PARAM = 0x005A,
    ZW_REG_CERT_DIFF = 0x005C,
    ZW_REG_CERT_M_HI = 0x005E,
    ZW_REG_CERT_B_HI = 0x0060,
    ZW_REG_CERT_CRC = 0x0062,
    ZW_REG_COMMAND = 0x0064,
    ZW_REG_CONSENT = 0x0080,
    ZW_REG_RESTORE_SOURCE = 0x0081,
    ZW_REG_RESTORE_REASON = 0x0082,
    ZW_REG_WORD_ORDER = 0x0083,
    ZW_REG_PRECISION = 0x0084,
    ZW_REG_NONCE = 0x0088,
    ZW_REG_MAC = 0x0090,
    ZW_REG_BOX_CERT = 0x0100,
    ZW_REG_BOX_CERT_B = 0x0102,
    ZW_REG_BOX_CERT_NODES = 0x0144,
    ZW_REG_COUNT = 0x0244 /* registers 0 .. ZW_REG_COUNT-1 may be mapped */
};

#define ZW_REGMAP_MAGIC 0x5A57u
#define ZW_REGMAP_VERSION 5u


/* Modbus exception codes used. */
typedef enum zw_mb_exception {
    ZW_MB_OK = 0,
    ZW_MB_ILLEGAL_FUNCTION = 0x01,
    ZW_MB_ILLEGAL_ADDRESS = 0x02,
    ZW_MB_ILLEGAL_VALUE = 0x03,
    ZW_MB_SERVER_FAILURE = 0x04
} zw_mb_exception;



/* The fields shared between contexts (threading model above).  Under C11 with atomics
 * they are _Atomic, so that ThreadSanitizer and a multi-core memory model see the
 * publication; otherwise volatile.  Every translation unit that shares a zw_regmap must
 * make the same choice (define ZW_REGMAP_NO_C11_ATOMICS in all or none; on GCC and Clang
 * targets both forms have the size and alignment of the plain type). */
#if !defined(__cplusplus) && defined(__STDC_VERSION__) && __STDC_VERSION__ >= 201112L && \
    !defined(__STDC_NO_ATOMICS__) && !defined(ZW_REGMAP_NO_C11_ATOMICS)
#define ZW_REGMAP_C11_ATOMICS 1
#define ZW_REGMAP_SHARED _Atomic
#else
#define ZW_REGMAP_C11_ATOMICS 0
#define ZW_REGMAP_SHARED volatile
#endif

/* Tries of a cross-context reader before it answers fail-safe. */
#define ZW_REGMAP_READ_TRIES 8u

/* One publication of the gain pair (written by the Modbus task). */
typedef struct zw_regmap_gain_slot {
    ZW_REGMAP_SHARED float K, B;
} zw_regmap_gain_slot;

/* One sample of the state registers (written by the control loop). */
typedef struct zw_regmap_state_slot {
    ZW_REGMAP_SHARED float x, v, f;
    ZW_REGMAP_SHARED uint_least32_t step;
} zw_regmap_state_slot;

/* The whole drive-side state; plain data, one per drive, no globals.  Read it only through
 * the functions below: K and B are the Modbus task's own copy, the control loop takes
 * its gains from zw_regmap_active_gains. */
typedef struct zw_regmap {
    zw_cert sealed;                 /* the block in force */
    /* derived from sealed: the plant (loop.dev) and the drive's loop, the gains' rounding
     * in its guard.  1,688 B with float zw_real on a Cortex-M4F (the loop's 12
     * coefficient arrays of ZW_LOOP_MAX_DEGREE + 1; 1,692 B on x86-64), 3,376 B with
     * double (x86-64). */
    zw_device_loop loop;
    zw_loop_workspace ws;           /* scratch of the general loop's checks (loop.h): here, off
                                       the stack; one map is served by one task at a time */
    uint_least16_t staged[ZW_CERT_WORDS + 1u]; /* block + CRC being written in commissioning */
    float K, B;                     /* active gains (Modbus task) */
    zw_regmap_gain_slot gains[2];   /* their publication: gains[gains_seq & 1] is in force */
    ZW_REGMAP_SHARED uint_least32_t gains_seq;
    zw_regmap_state_slot state[2];  /* state registers: state[state_seq & 1] is current */
    ZW_REGMAP_SHARED uint_least32_t state_seq;
    uint_least32_t accepted, refused;
    uint_least16_t mode;            /* 0 operation, 1 commissioning */
    uint_least16_t is_sealed;
    uint_least16_t last_reason, last_exception;
    uint_least16_t unlock_armed;    /* UNLOCK1 seen as the previous request */
    zw_regmap_auth auth;            /* the firmware's RNG and MAC check (zw_regmap_set_auth) */
    uint_least16_t consent;         /* commissioning enable input (zw_regmap_set_consent) */
    uint_least16_t nonce[ZW_AUTH_NONCE_WORDS]; /* this commissioning session's nonce */
    uint_least16_t mac[ZW_AUTH_MAC_WORDS];     /* the MAC the client wrote */
    zw_ceilings ceilings;           /* factory ceilings (zw_regmap_set_ceilings) */
    uint_least16_t has_ceilings;
    zw_regmap_storage storage;      /* the firmware's non-volatile storage (SAVE) */
    uint_least16_t restore_source, restore_reason;
    uint_least16_t word_order;      /* ZW_WORD_ORDER_ABCD or _CDAB (zw_regmap_set_word_order) */
    float live[8];                  /* registers 0x0020..0x002F, recomputed on every accepted
                                       write and seal (so a read never runs the core) */
    /* K_max(B) at the B of the gains in force, general loop only (two zw_loop_alpha_max,
     * ~0.3 M instructions): stored by an accepted write, so a write that keeps B (the
     * usual stiffness change) reuses it.  kmax_cached 0: none (cleared by every seal). */
    float kmax_B;
    zw_real kmax_value;
    uint_least16_t kmax_cached;
    /* The box search of a ranged block (map version 4, regmap_policy.h): its depth-first
     * cell stack and scratch, here rather than on the stack (scratch only, nothing kept
     * between requests): 2,560 + 2,880 B with float zw_real on a Cortex-M4F (2,560 +
     * 2,884 B on x86-64), 5,120 + 5,760 B with double (x86-64), the largest part of the
     * map: sizeof(zw_regmap) is 11,192 B / 19,144 B on x86-64 (float /
     * double; 11,124 B on the Cortex-M4F, tools/m4f_box_cert.sh), the box certificate's
     * 3 x 648 B and the 736 B wire scratch included.  With a ranged block
     * kmax_value holds the box's
     * K_max lower bound. */
    zw_box_loop_cell box_cells[ZW_REGMAP_BOX_CELLS];
    zw_box_loop_scratch box_scratch;
    /* A ranged block's certificate (box_cert.h), 648 B: while box_cert_valid the box rules
     * are lookups in its staircase, no search.  The words being written in commissioning
     * (the window at ZW_REG_BOX_CERT; power-up and restore put theirs here too), 648 B,
     * and the candidate SEAL decodes them into and verifies, 648 B, so that a refused
     * certificate leaves the one in force untouched. */
    zw_box_cert box_cert;
    uint_least16_t box_cert_valid;
    uint_least16_t staged_box_cert[ZW_BOX_CERT_WORDS];
    zw_box_cert box_cert_candidate;
    uint_least16_t box_cert_candidate_valid; /* verified, during one admission only */
    /* SEAL's MAC message and SAVE's image (never both at once), off the Modbus task's
     * stack: 736 B. */
    uint_least8_t wire_scratch[ZW_AUTH_MSG_BYTES];
} zw_regmap;

/* Power-up (init context: before the control loop and the Modbus task run): with cert
 * non-NULL the block is validated and sealed like a SEAL (ZW_ERR_ARG with a reason in
 * *reason if it is not acceptable; ZW_ERR_FPENV with ZW_REASON_FPENV when zw_selftest()
 * fails); with NULL the drive starts unsealed and refuses gains until commissioned.  Gains
 * start off (0, 0).  rm is initialised in every case but ZW_ERR_NULL (rm NULL): after
 * ZW_ERR_ARG or ZW_ERR_FPENV it is a working unsealed drive (gains off) that can be
 * commissioned.  reason may be NULL; it receives ZW_REASON_NONE on success. */
zw_status zw_regmap_init(zw_regmap *rm, const zw_cert *cert, zw_reason *reason);

/* Power-up with a ranged block and its box certificate (box_cert.h, built by the
 * commissioning tool with zw_box_cert_build in this drive's precision): as zw_regmap_init,
 * and the certificate is verified against the block's box and loop before the block is
 * admitted (at most ZW_BOX_CERT_MAX_LEAVES interval tests, the bound of this call).  Then
 * every box rule is a lookup: a write is accepted when K / sigma (rounded up) is at most
 * the certified level at B (else ZW_REASON_ABOVE_SIGMA), refused with
 * ZW_REASON_OUTSIDE_CERT when B is outside the staircase; K_MAX is the level at B, K_MMAX
 * the highest level, B_LO / B_HI the run of steps around B certified at K / sigma.  A
 * certificate that fails verification, or one given with a point block, refuses the block
 * (ZW_REASON_BOX_CERT).  box_cert NULL: zw_regmap_init.  A block sealed later over Modbus
 * brings its own certificate through the window at ZW_REG_BOX_CERT (or none: the search);
 * SAVE's image carries the one in force. */
zw_status zw_regmap_init_box(zw_regmap *rm, const zw_cert *cert, const zw_box_cert *box_cert,
                             zw_reason *reason);

/* Commissioning (zwidth/regmap_commission.h), Modbus task or init context.  The enable
 * input: commissioning is possible only while it is on (off after zw_regmap_init; a
 * drive reports its key switch before each request).  The authentication hooks, copied
 * into rm (auth NULL or a hook NULL: none, commissioning impossible; zw_regmap_init clears
 * them).  rm NULL: no-op. */
void zw_regmap_set_consent(zw_regmap *rm, bool enabled);
void zw_regmap_set_auth(zw_regmap *rm, const zw_regmap_auth *auth);

/* Power-up (init context, after zw_regmap_init): the factory ceilings (regmap_policy.h)
 * that every commissioned block must respect.  They must be valid (every field finite,
 * sigma_max and r_max in (0, 1], m and T > 0, b >= 0, plant_tol >= 0, k_min <= k_max,
 * b_min <= b_max, steps > 0), else ZW_ERR_ARG with ZW_REASON_BAD_POLICY and nothing
 * changes.  The block in force is checked against them: one that exceeds them, or whose
 * loop is not the ceilings' loop (the one the firmware runs: ZW_REASON_LOOP_MISMATCH), is
 * unsealed (gains off; ZW_ERR_ARG with its reason), so the drive never runs outside its
 * ceilings.
 * rm or c NULL: ZW_ERR_NULL.  reason may be NULL. */
zw_status zw_regmap_set_ceilings(zw_regmap *rm, const zw_ceilings *c, zw_reason *reason);

/* Word order of every two-register value on the wire (floats and counters): ABCD, high
 * word first (the default after zw_regmap_init), or CDAB, low word first (many masters'
 * default).  The CRC, the MAC message and the stored image always use ABCD (the canonical
 * words), so a block's CRC does not depend on the wire order.  Init context; rm NULL or
 * another value: no-op. */
#define ZW_WORD_ORDER_ABCD 0u
#define ZW_WORD_ORDER_CDAB 1u
void zw_regmap_set_word_order(zw_regmap *rm, unsigned order);

/* Persistence (zwidth/regmap_persist.h), init context.  The storage hook (NULL or a NULL
 * hook: none, SAVE refused ZW_REASON_NO_STORAGE); rm NULL: no-op.  Restore: newest and
 * previous image (either NULL or of any length; NULL, 0 means none).  Returns ZW_OK when an
 * image's block was installed (its gains too, if they pass), ZW_ERR_ARG when an image was
 * given and none passed (*reason: the first refusal), ZW_OK with nothing done when none
 * was given; ZW_ERR_NULL for rm NULL.  Gains are off unless restored certified. */
void zw_regmap_set_storage(zw_regmap *rm, const zw_regmap_storage *storage);
zw_status zw_regmap_restore(zw_regmap *rm, const uint_least8_t *newest, size_t newest_len,
                            const uint_least8_t *previous, size_t previous_len,
                            zw_reason *reason);
/* The image SAVE writes, of the block and gains in force (rm NULL, image NULL or nothing
 * sealed: false, image untouched). */
bool zw_regmap_image(const zw_regmap *rm, uint_least8_t image[ZW_IMAGE_BYTES]);

/* Control loop: the certified gain pair in force, to apply this sample.  *K and *B are
 * always one pair that the map accepted (or (0, 0), output off: unsealed, commissioning,
 * after a seal), never the K of one accepted write with the B of another.  Wait-free and
 * constant time; callable from an ISR that preempts the Modbus task.  On any error both
 * outputs that are not NULL are 0 (output off): ZW_ERR_NULL (rm, K or B NULL),
 * ZW_ERR_BUSY (no consistent pair in ZW_REGMAP_READ_TRIES tries: only possible while
 * another core publishes continuously).  rm is only read. */
zw_status zw_regmap_active_gains(const zw_regmap *rm, float *K, float *B);

/* Control loop: report the device state (position, velocity, force, sample count) for the
 * state registers.  Wait-free and constant time; one context only (the control loop),
 * never the Modbus side.  rm NULL: no-op. */
void zw_regmap_set_state(zw_regmap *rm, float x, float v, float f, uint_least32_t step);

/* Handle one request PDU (function code first, no address/CRC framing).  Writes the
 * response PDU (normal, or function|0x80 + exception code) into resp, at most resp_cap
 * bytes (253 always suffices), and its length into *resp_len.  Returns the exception
 * code sent (ZW_MB_OK for a normal response).  Bytes are held in uint_least8_t so the
 * same code runs where CHAR_BIT is 16.  Malformed requests (length, quantity or byte count
 * inconsistent; 0x10 must have byte count 2 x quantity and exactly that many bytes) answer
 * 0x03 with ZW_REASON_MALFORMED.
 * The handler's own failures return ZW_MB_SERVER_FAILURE and process nothing (no register
 * changes, refusal registers included): rm, req, resp or resp_len NULL, req_len 0 or
 * resp_cap < 2 (*resp_len = 0 when resp_len is not NULL, nothing written to resp); a
 * normal answer that would not fit in resp_cap, or a read of a state register that cannot
 * take a consistent sample (threading model above) (the 2-byte exception 0x04 is sent). */
zw_mb_exception zw_regmap_handle_pdu(zw_regmap *rm, const uint_least8_t *req, size_t req_len,
                                     uint_least8_t *resp, size_t resp_cap, size_t *resp_len);

/* Register-level access for stacks that decode PDUs themselves (same rules, same
 * atomicity).  *reason receives the refusal reason (ZW_REASON_NONE when accepted); reason
 * may be NULL.  words receive the registers when the read is accepted; when it is not
 * (and words is not NULL, count 1..125) every word reads 0 but LIVE_RHO, which reads +inf
 * (0x7F80 0x0000), so that a caller ignoring the exception reads values that certify
 * nothing (K_CERT 0, gains off, unsealed, empty B interval).  rm or words NULL:
 * ZW_MB_SERVER_FAILURE, nothing processed, *reason untouched.  A read that covers a state
 * register and cannot take a consistent sample (see the threading model) answers
 * ZW_MB_SERVER_FAILURE and processes nothing (no refusal registers change). */
zw_mb_exception zw_regmap_read(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                               uint_least16_t *words, zw_reason *reason);
zw_mb_exception zw_regmap_write(zw_regmap *rm, uint_least16_t addr, uint_least16_t count,
                                const uint_least16_t *words, zw_reason *reason);





#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REGMAP_H */
