#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# tools/m4f_box_cert.sh - instructions of a box certificate's check on the Cortex-M4F
# (zw_box_cert_verify, zw_box_cert_level, a corrupted copy refused) and of the register map
# with the certificate in force (zw_regmap_init_box, gain writes, sizeof(zw_regmap)), under
# QEMU mps2-an386.
#
# Usage:  bash tools/m4f_box_cert.sh [--keep]
#   --keep   keep the temporary build directory (its path goes to stderr)
# Environment:
#   M4F_CERT_VERIFY_LIMIT  verify's instruction target per box (8400000: the issue's SEAL target)
#   M4F_SEAL_LIMIT         zw_regmap_init_box's instruction target per box (8400000)
#   M4F_WRITE_LIMIT        a gain write's instruction target (20000)
#   M4F_REGMAP_SIZE_LIMIT  sizeof(zw_regmap) target on the M4F, bytes (12288)
#   ZW_HOST_LIB            link the generator with this float library (e.g. build/libzwidth_f.a)
#                          instead of compiling ZW_CORE_SOURCES with the host compiler (the
#                          default: the generator then sees exactly the sources the M4F image has)
#   CC                     the host compiler (cc)
#   QEMU_TIMEOUT           seconds (300)
#
# Exit status: 0 every box verified on the M4F within the target, its lookups as on the
# host, its corrupted copy refused, the register map sealed with it (ZW_OK, ZW_REASON_NONE)
# within the SEAL target, its three gain writes with the expected outcome within the write
# target, sizeof(zw_regmap) within its target; 1 one of those failed (each failure on
# stderr); 2 a build or the generator failed; 77 (skip) the Arm toolchain, newlib or
# qemu-system-arm is missing.
#
# What it does
#   1. bench/box/cert_gen.c, built for the host in float (-DZW_REAL_FLOAT), builds the
#      certificates of the three boxes (16 steps, 512 leaves, rel_tol 1e-3), verifies them
#      on the host and writes them as initialised constants (exact hexadecimal floats).
#   2. bench/box/m4f_cert.c + the table + every file of ZW_CORE_SOURCES (CMakeLists.txt, read
#      as tools/footprint.sh reads it) are cross-compiled with tools/footprint.sh's CFLAGS
#      and TFLAGS[m4f] (read from it, as bench/report/mcu.py does, so they cannot drift) and
#      linked with bench/report/mcu's startup.c and mps2_an386.ld.
#   3. qemu-system-arm -M mps2-an386 -icount shift=0 -semihosting runs it: instructions are
#      counted with the CMSDK timer 0 (1 tick = 40 instructions, checked by a calibration
#      loop; figures within 40), as the firmware review's m4f_cost.c does.
#   4. Prints two Markdown tables: the certificate alone, and the register map with it in
#      force (bench/box/m4f_cert.c's header says which block and which writes).
#
# Needs: a host C compiler, gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm.
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."

KEEP=0
for arg in "$@"; do
    case "$arg" in
    --keep) KEEP=1 ;;
    -h | --help)
        awk 'NR > 1 && /^# Needs/ { exit } NR > 1 && /^#/ && !/SPDX-/' "$0" | sed 's/^# \{0,1\}//'
        exit 0
        ;;
    *)
        echo "m4f_box_cert.sh: unknown argument '$arg' (try --help)" >&2
        exit 2
        ;;
    esac
done

CROSS=arm-none-eabi-
QEMU=qemu-system-arm
HOST_CC=${CC:-cc}
LIMIT=${M4F_CERT_VERIFY_LIMIT:-8400000}
SEAL_LIMIT=${M4F_SEAL_LIMIT:-8400000}
WRITE_LIMIT=${M4F_WRITE_LIMIT:-20000}
SIZE_LIMIT=${M4F_REGMAP_SIZE_LIMIT:-12288}
QEMU_TIMEOUT=${QEMU_TIMEOUT:-300}
for v in LIMIT SEAL_LIMIT WRITE_LIMIT SIZE_LIMIT; do
    case "${!v}" in '' | *[!0-9]*) echo "m4f_box_cert.sh: the M4F_* limits must be integers ($v=${!v})" >&2; exit 2 ;; esac
done

skip() {
    echo "m4f_box_cert.sh: SKIP: $1" >&2
    exit 77
}
command -v "${CROSS}gcc" >/dev/null 2>&1 || skip "${CROSS}gcc not found (sudo apt-get install -y gcc-arm-none-eabi libnewlib-arm-none-eabi)"
[ "$(${CROSS}gcc -print-file-name=nano.specs)" != nano.specs ] || skip "newlib (nano.specs) not found (sudo apt-get install -y libnewlib-arm-none-eabi)"
command -v "$QEMU" >/dev/null 2>&1 || skip "$QEMU not found (sudo apt-get install -y qemu-system-arm)"
"$QEMU" -machine help 2>/dev/null | grep -q '^mps2-an386 ' || skip "$QEMU has no mps2-an386 machine"
command -v "$HOST_CC" >/dev/null 2>&1 || skip "host compiler $HOST_CC not found"

# The core's sources: ZW_CORE_SOURCES of CMakeLists.txt (set(...) and list(APPEND ...)), the
# same awk as tools/footprint.sh.
MODULES=$(tools/core_modules.sh)
[ -n "$MODULES" ] || { echo "m4f_box_cert.sh: no csrc/src/*.c in ZW_CORE_SOURCES of CMakeLists.txt" >&2; exit 2; }
SOURCES=()
for m in $MODULES; do
    [ -f "csrc/src/$m.c" ] || { echo "m4f_box_cert.sh: csrc/src/$m.c (in ZW_CORE_SOURCES) does not exist" >&2; exit 2; }
    SOURCES+=("csrc/src/$m.c")
done
case " $MODULES " in *" box_loop "*) ;; *) echo "m4f_box_cert.sh: box_loop is not in ZW_CORE_SOURCES" >&2; exit 2 ;; esac

# The cross flags, from tools/footprint.sh (less -fstack-usage: its .su files are footprint's).
fp_var() { sed -n "s/^$1=\"\\([^\"]*\\)\"\$/\\1/p" tools/footprint.sh | head -n 1; }
CFLAGS=$(fp_var CFLAGS)
M4F_FLAGS=$(fp_var 'TFLAGS\[m4f\]')
LDFLAGS=$(fp_var LDFLAGS)
if [ -z "$CFLAGS" ] || [ -z "$M4F_FLAGS" ] || [ -z "$LDFLAGS" ]; then
    echo "m4f_box_cert.sh: cannot read CFLAGS / TFLAGS[m4f] / LDFLAGS from tools/footprint.sh" >&2
    exit 2
fi
CFLAGS=$(echo " $CFLAGS " | sed 's/ -fstack-usage / /; s/^ //; s/ $//')
case " $M4F_FLAGS " in *" -DZW_REAL_FLOAT "*) ;; *) echo "m4f_box_cert.sh: TFLAGS[m4f] is not the float build" >&2; exit 2 ;; esac

W=$(mktemp -d)
if [ "$KEEP" = 1 ]; then echo "m4f_box_cert.sh: build directory $W" >&2; else trap 'rm -rf "$W"' EXIT; fi
MCU=bench/report/mcu

# 1. the generator (host, float) and the table
GEN_FLAGS=(-std=c99 -O2 -ffp-contract=off -DZW_REAL_FLOAT -Icsrc/include)
GEN_WARN=(-Wall -Wextra -Wpedantic -Werror) # the bench's own file; the core's warnings are CMake's
gen_build() {
    if [ -n "${ZW_HOST_LIB:-}" ]; then
        [ -f "$ZW_HOST_LIB" ] || { echo "ZW_HOST_LIB=$ZW_HOST_LIB not found"; return 1; }
        "$HOST_CC" "${GEN_FLAGS[@]}" "${GEN_WARN[@]}" -Ibench/box bench/box/cert_gen.c "$ZW_HOST_LIB" -lm -o "$W/cert_gen"
    else
        "$HOST_CC" "${GEN_FLAGS[@]}" "${GEN_WARN[@]}" -Ibench/box -c bench/box/cert_gen.c -o "$W/cert_gen.o" &&
            "$HOST_CC" "${GEN_FLAGS[@]}" "$W/cert_gen.o" "${SOURCES[@]}" -lm -o "$W/cert_gen"
    fi
}
if ! gen_build >"$W/log" 2>&1; then
    cat "$W/log" >&2
    echo "m4f_box_cert.sh: the generator does not build" >&2
    exit 2
fi
"$W/cert_gen" "$W/cert_data.c" 2>"$W/gen.log" || { cat "$W/gen.log" >&2; echo "m4f_box_cert.sh: the generator failed" >&2; exit 2; }

# 2. the M4F image
# shellcheck disable=SC2086 # the flag lists are word lists
if ! "${CROSS}gcc" $CFLAGS $M4F_FLAGS -DVERIFY_LIMIT="${LIMIT}ul" \
    -DSEAL_LIMIT="${SEAL_LIMIT}ul" -DWRITE_LIMIT="${WRITE_LIMIT}ul" -DREGMAP_SIZE_LIMIT="${SIZE_LIMIT}ul" -Icsrc/include -I"$MCU" -Ibench/box \
    -nostartfiles $LDFLAGS -T "$MCU/mps2_an386.ld" "$MCU/startup.c" bench/box/m4f_cert.c "$W/cert_data.c" \
    "${SOURCES[@]}" -lm -o "$W/m4f_cert.elf" >"$W/log" 2>&1; then
    cat "$W/log" >&2
    echo "m4f_box_cert.sh: the M4F image does not build" >&2
    exit 2
fi

# 3. run
rc=0
timeout "$QEMU_TIMEOUT" "$QEMU" -M mps2-an386 -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native -icount shift=0 -kernel "$W/m4f_cert.elf" >"$W/run.txt" 2>&1 || rc=$?

# 4. the table
GCCV=$("${CROSS}gcc" -dumpversion)
QEMUV=$("$QEMU" --version | head -n 1 | sed 's/^QEMU emulator version //')
echo "## zw_box_cert_verify on the Cortex-M4F (QEMU $QEMUV mps2-an386, -icount shift=0)"
echo
echo "arm-none-eabi-gcc $GCCV, \`$CFLAGS $M4F_FLAGS\`; float certificates built on the host"
echo "(16 steps, 512 leaves, rel_tol 1e-3); instructions from the CMSDK timer (1 tick = 40"
echo "instructions, so within 40); lookup: inside zw_box_cert_level, worst of 5 B, mean of 1000 calls."
echo
awk -v limit="$LIMIT" '
    /^CALIB / { for (i = 2; i <= NF; i++) { split($i, kv, "="); c[kv[1]] = kv[2] } calib = c["insn"] " (exact: " c["expected"] ")" }
    /^BOX / {
        delete f; name = $0; sub(/.* name=/, "", name)
        for (i = 2; i <= NF; i++) if (index($i, "=")) { k = substr($i, 1, index($i, "=") - 1); f[k] = substr($i, index($i, "=") + 1) }
        if (!hdr) {
            print "| box | leaves | verify (instructions) | per leaf | stack (B) | lookup (instructions) | corrupted copy (level x2) |"
            print "|---|---:|---:|---:|---:|---:|---|"
            hdr = 1
        }
        ok = (f["status"] == 0 && f["fault"] == 0) ? "" : " **fault " f["fault"] "**"
        over = (f["verify_insn"] + 0 > limit + 0) ? " **over**" : ""
        refused = (f["bad_fault"] != 0) ? "refused (fault " f["bad_fault"] ", step " f["corrupt_step"] ", " f["bad_leaves"] " leaves, " f["bad_insn"] " instructions)" : "**accepted**"
        printf "| %s. %s | %s | %s%s%s | %s | %s | %s | %s |\n", f["box"], name, f["leaves"], f["verify_insn"], over, ok, f["per_leaf"], f["stack"], f["lookup_insn"], refused
    }
    END {
        print ""
        print "Target: verify <= " limit " instructions per box.  Timer calibration: " calib " instructions."
    }' "$W/run.txt"
echo
echo "### The register map with the certificate in force (zw_regmap_init_box, then gain writes)"
echo
echo "Block: the box's m, m_hi, b, b_hi; T 0.02, sigma 0.8, r 1, K in [0, 10] step 1, B in the"
echo "certificate's [B[0], B[n]] step its width, the box's delay, no filter.  Writes: K and B"
echo "(zw_regmap_write, 4 registers, as FC 0x10), from (0, 0): accepted at the middle of step 3"
echo "with K = 0.5 x the level; refused at the middle of step 10 with K = 1.1 x the level; outside"
echo "at B[n] + w/8 (w = B[n] - B[0]) under the same block with its B range widened by w/4 each side"
echo "(with b_max = B[n] it would be ZW_REASON_B_ABOVE_MAX).  selftest: zw_selftest alone (SEAL's first step)."
echo
awk -v seal_limit="$SEAL_LIMIT" -v write_limit="$WRITE_LIMIT" -v size_limit="$SIZE_LIMIT" '
    function kv(line, i) { delete f; for (i = 2; i <= NF; i++) if (index($i, "=")) f[substr($i, 1, index($i, "=") - 1)] = substr($i, index($i, "=") + 1) }
    function mark(x, lim) { return (x + 0 > lim + 0) ? " **over**" : "" }
    function outcome(exc, reason, want) { return (reason + 0 == want + 0) ? "" : " **reason " reason ", exception " exc "**" }
    /^BOX / { kv(); verify[f["box"]] = f["verify_insn"] }
    /^SIZE / { kv(); size = f["regmap"]; bcsize = f["box_cert"] }
    /^RM / {
        kv()
        if (!hdr) {
            print "| box | SEAL: zw_regmap_init_box (instructions) | verify alone (above) | zw_selftest alone | SEAL stack (B) | SEAL, B range widened | write accepted (B changes) | refused ABOVE_SIGMA | refused OUTSIDE_CERT |"
            print "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
            hdr = 1
        }
        sealok = (f["seal_status"] == 0 && f["seal_reason"] == 0) ? "" : " **status " f["seal_status"] ", reason " f["seal_reason"] "**"
        wideok = (f["wide_seal_status"] == 0 && f["wide_seal_reason"] == 0) ? "" : " **status " f["wide_seal_status"] ", reason " f["wide_seal_reason"] "**"
        printf "| %s | %s%s%s | %s | %s | %s | %s%s%s | %s%s%s | %s%s%s | %s%s%s |\n", f["box"],
            f["seal_insn"], mark(f["seal_insn"], seal_limit), sealok, verify[f["box"]], f["selftest_insn"], f["seal_stack"],
            f["wide_seal_insn"], mark(f["wide_seal_insn"], seal_limit), wideok,
            f["acc_insn"], mark(f["acc_insn"], write_limit), outcome(f["acc_exc"], f["acc_reason"], 0) (f["live_ok"] == 1 ? "" : " **live**"),
            f["above_insn"], mark(f["above_insn"], write_limit), outcome(f["above_exc"], f["above_reason"], 16),
            f["out_insn"], mark(f["out_insn"], write_limit), outcome(f["out_exc"], f["out_reason"], 43)
    }
    END {
        print ""
        printf "sizeof(zw_regmap) on the M4F: %s B%s (target <= %s B; its zw_box_cert %s B).  ", size, (size + 0 > size_limit + 0) ? " **over**" : "", size_limit, bcsize
        print "Targets: SEAL <= " seal_limit " instructions, a write <= " write_limit "."
    }' "$W/run.txt"
echo

FAIL=0
if grep -q '^FAIL' "$W/run.txt"; then
    grep '^FAIL' "$W/run.txt" | sed 's/^/m4f_box_cert.sh: /' >&2
    FAIL=1
fi
if [ "$rc" != 0 ] || ! grep -qx 'DONE ok' "$W/run.txt"; then
    echo "m4f_box_cert.sh: FAIL: the M4F run exited $rc (124: timeout) without 'DONE ok'; its output:" >&2
    sed 's/^/  /' "$W/run.txt" >&2
    FAIL=1
fi
[ "$(grep -c '^BOX ' "$W/run.txt")" = 3 ] || { echo "m4f_box_cert.sh: FAIL: expected 3 boxes" >&2; FAIL=1; }
[ "$(grep -c '^RM ' "$W/run.txt")" = 3 ] || { echo "m4f_box_cert.sh: FAIL: expected 3 register-map lines" >&2; FAIL=1; }
grep -q '^SIZE ' "$W/run.txt" || { echo "m4f_box_cert.sh: FAIL: no sizeof(zw_regmap) line" >&2; FAIL=1; }
if [ "$FAIL" = 0 ]; then
    echo "m4f_box_cert.sh: all boxes verified within $LIMIT instructions, corrupted copies refused;" \
        "sealed within $SEAL_LIMIT, writes within $WRITE_LIMIT as expected, sizeof(zw_regmap) within $SIZE_LIMIT B" >&2
fi
exit "$FAIL"
