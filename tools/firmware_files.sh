#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# tools/firmware_files.sh - build what docs/firmware.md and README.md tell a new user to
# build, from those files' own text, so that a list or an example that stops compiling
# fails CI.
#
# 1. README.md's C example (the ```c block of "A short tour"), as pasted into a program:
#    the block is a fragment (a helper function, then statements), so it is wrapped: its
#    lines up to the last one that is "}" alone stay at file scope, the statements after it
#    become the body of a main().  Compiled with gcc -std=c99 -Wall -Wextra -Wpedantic
#    -Wfloat-conversion -Wdouble-promotion -Werror, float (-DZW_REAL_FLOAT) and double,
#    linked with the "real units" files of step 2 and run.
# 2. docs/firmware.md, "Files to copy, per use": the table is parsed (its "sources" and
#    "headers" columns; rows are cumulative, "every use" is part of every row, files in
#    "(+ ...)" are optional).  For each use, exactly its files are copied into an empty
#    directory (sources and private headers in src/, headers in inc/zwidth/) with a tiny
#    main calling the use's functions (including only the use's headers, not zwidth.h),
#    then built twice, without and with the optional files:
#      - for the Cortex-M4F with the doc's own "typical Cortex-M4F line" (read from
#        firmware.md) plus -Wall -Wextra -Wpedantic -Werror, linked with nano.specs,
#        nosys.specs and --gc-sections;
#      - on the host, gcc -std=c99 -ffp-contract=off -Wall -Wextra -Wpedantic -Werror, float
#        and double, linked and run (the main checks a few known answers of the paper's
#        drive).
# 3. The checker checks itself: the same run on a copy of firmware.md with portable_math.h
#    dropped from the "every use" row, and on a copy of README.md with one ZW_R() removed
#    from the example, must both fail.
#
# Usage: tools/firmware_files.sh   (needs gcc, gcc-arm-none-eabi, libnewlib-arm-none-eabi)
# Environment: ZW_FIRMWARE_DOC, ZW_README (other copies of the two files: the self-check of
# step 3 uses them), ZW_FILES_NO_SELFCHECK=1 (skip step 3), ZW_FILES_KEEP=1 (keep the
# temporary directory), CROSS (arm-none-eabi-), HOSTCC (gcc).
# Exit status: 0 everything builds and runs; 1 something named on stderr does not.
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
ROOT=$PWD
DOC=${ZW_FIRMWARE_DOC:-docs/firmware.md}
README=${ZW_README:-README.md}
CROSS=${CROSS:-arm-none-eabi-}
HOSTCC=${HOSTCC:-gcc}
fail() {
    echo "firmware_files: FAIL: $*" >&2
    exit 1
}
for cc in "${CROSS}gcc" "$HOSTCC"; do
    command -v "$cc" >/dev/null || fail "$cc not found (tools/bootstrap.sh --check)"
done
W=$(mktemp -d "${TMPDIR:-/tmp}/zw-fwfiles.XXXXXX")
trap '[ -n "${ZW_FILES_KEEP:-}" ] || rm -rf "$W"' EXIT
WARN="-Wall -Wextra -Wpedantic -Werror"
HOST="-std=c99 -O2 -ffp-contract=off $WARN"

# ---- the doc's M4F compile line ("A typical Cortex-M4F line:", its indented lines) -------
M4F=$(awk '/^A typical Cortex-M4F line:/ { on = 1; next }
    on && /^    / { gsub(/\\/, ""); print; next } on && NF { exit }' "$DOC" |
    tr ' ' '\n' | grep -E '^-' | grep -vE '^-(I|c$)' | tr '\n' ' ')
case "$M4F" in
*-mcpu=cortex-m4*-DZW_REAL_FLOAT* | *-DZW_REAL_FLOAT*-mcpu=cortex-m4*) ;;
*) fail "$DOC: no 'A typical Cortex-M4F line:' with -mcpu=cortex-m4 and -DZW_REAL_FLOAT (read: '$M4F')" ;;
esac
M4F_LINK="--specs=nano.specs --specs=nosys.specs -Wl,--gc-sections"

# ---- the table, one line per row: name, sources, optional sources, headers, optional
# headers (file names from the backquoted words of each cell), separated by \037 --------
awk -F'|' '
    function files(cell,   out, n, i, w, parts, k, words) {
        out = ""
        n = split(cell, parts, "`")
        for (i = 2; i <= n; i += 2) {
            k = split(parts[i], words, " ")
            for (w = 1; w <= k; w++) if (words[w] ~ /^[A-Za-z0-9_*]+\.[ch]$/) out = out " " words[w]
        }
        return out
    }
    # base: the cell without its "(+ ...)" parts; opt: only those parts
    function split_opt(cell,   rest, opt) {
        rest = cell; opt = ""
        while (match(rest, /\(\+[^)]*\)/)) {
            opt = opt " " substr(rest, RSTART, RLENGTH)
            rest = substr(rest, 1, RSTART - 1) substr(rest, RSTART + RLENGTH)
        }
        BASE = rest; OPT = opt
    }
    function trim(s) { gsub(/^[ \t]+|[ \t]+$/, "", s); return s }
    /^## Files to copy, per use/ { on = 1; next }
    on && /^## / { exit }
    !on || !/^\|/ { next }
    !hdr {
        for (i = 2; i < NF; i++) { c = trim($i); if (c ~ /^sources/) cs = i; if (c ~ /^headers/) ch = i }
        hdr = 1; next
    }
    /^\|[- |:]+\|$/ { next }
    {
        split_opt($cs); sb = files(BASE); so = files(OPT)
        split_opt($ch); hb = files(BASE); ho = files(OPT)
        printf "%s\037%s\037%s\037%s\037%s\n", trim($2), sb, so, hb, ho
    }
    END { if (!cs || !ch) exit 3 }' "$DOC" >"$W/table.tsv" ||
    fail "$DOC: no table with 'sources' and 'headers' columns under '## Files to copy, per use'"
[ -s "$W/table.tsv" ] || fail "$DOC: the table of '## Files to copy, per use' has no rows"
if grep -q '\*' "$W/table.tsv"; then
    fail "$DOC: the table names files by a pattern ($(grep -o '[A-Za-z0-9_]*\*[A-Za-z0-9_.*]*' "$W/table.tsv" | sort -u | tr '\n' ' ')); name each file"
fi

key_of() {
    case "$1" in
    "every use"*) echo every ;;
    "check only"*) echo check ;;
    "check + extremes"*) echo extremes ;;
    "real units"*) echo units ;;
    "general loop"*) echo loop ;;
    "register map"*) echo regmap ;;
    *) fail "$DOC: row '$1' has no main in tools/firmware_files.sh (add one)" ;;
    esac
}

# ---- a tiny main per use: the use's own headers only, known answers of the paper's drive
# (delta = 2.049: (6.09, 0.42075) stable, (6.11, 0.42075) not; the drive J = 85.78e-7,
# b = 2.197e-3, T = 0.02: K_mmax 0.4934, with one sample of delay K_max(0) 0.1061) --------
main_of() {
    local inc body
    case "$1" in
    check)
        inc='#include "zwidth/region.h"'
        body='
    zw_coeffs c;
    zw_verdict v;
    int ok = zw_coeffs_init(&c, ZW_R(2.049)) == ZW_OK;
    ok = ok && zw_check(&c, ZW_R(6.09), ZW_R(0.42075), &v) == ZW_OK && v.stable;
    ok = ok && zw_check(&c, ZW_R(6.11), ZW_R(0.42075), &v) == ZW_OK && !v.stable;
    ok = ok && zw_check_proportional(&c, ZW_R(1.0), &v) == ZW_OK && v.stable;'
        ;;
    extremes)
        inc='#include "zwidth/extremes.h"
#include "zwidth/region.h"'
        body='
    zw_coeffs c;
    zw_verdict v;
    zw_extremes x;
    zw_real am = ZW_R(0.0), lo = ZW_R(0.0), hi = ZW_R(0.0);
    bool nonempty = false;
    int ok = zw_coeffs_init(&c, ZW_R(2.049)) == ZW_OK;
    ok = ok && zw_check(&c, ZW_R(6.09), ZW_R(0.42075), &v) == ZW_OK && v.stable;
    ok = ok && zw_extremes_compute(&c, &x) == ZW_OK && x.alpha_mmax > ZW_R(6.09);
    ok = ok && zw_alpha_max(&c, ZW_R(0.42075), &am) == ZW_OK && am > ZW_R(6.09) && am < ZW_R(6.11);
    ok = ok && zw_beta_interval(&c, ZW_R(1.0), &lo, &hi, &nonempty) == ZW_OK && nonempty && lo < hi;'
        ;;
    units)
        inc='#include "zwidth/device.h"
#ifdef ZW_DOC_OPTIONAL
#include "zwidth/batch.h"
#endif'
        body='
    zw_device d;
    zw_verdict v;
    zw_device_extremes x;
    zw_real k = ZW_R(0.0);
    int ok = zw_device_init(&d, ZW_R(85.78e-7), ZW_R(2.197e-3), ZW_R(0.02)) == ZW_OK;
    ok = ok && zw_device_check(&d, ZW_R(0.45), ZW_R(-1.0e-3), &v) == ZW_OK && v.stable;
    ok = ok && zw_device_extremes_compute(&d, &x) == ZW_OK && x.K_mmax > ZW_R(0.493) && x.K_mmax < ZW_R(0.494);
    ok = ok && zw_device_k_max(&d, ZW_R(0.0), &k) == ZW_OK && k > ZW_R(0.357) && k < ZW_R(0.358);
#ifdef ZW_DOC_OPTIONAL
    {
        const zw_real K[2] = {ZW_R(0.45), ZW_R(0.6)}, B[2] = {ZW_R(-1.0e-3), ZW_R(-1.0e-3)};
        bool st[2] = {false, true};
        size_t bad = 0u;
        ok = ok && zw_device_check_many(&d, 2u, K, 1, B, 1, st, &bad) == ZW_OK && st[0] && !st[1];
    }
#endif'
        ;;
    loop)
        inc='#include "zwidth/device_loop.h"'
        body='
    static zw_device_loop dl;    /* 1.3 KB in float: not on the stack */
    static zw_loop_workspace ws; /* the checks scratch (loop.h) */
    zw_device_loop_spec spec = {1u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, ZW_R(0.0), ZW_R(0.0), 0u};
    zw_loop_verdict v;
    zw_real k = ZW_R(0.0);
    int ok = zw_device_loop_init(&dl, ZW_R(85.78e-7), ZW_R(2.197e-3), ZW_R(0.02), &spec) == ZW_OK;
    ok = ok && zw_device_loop_k_max(&dl, &ws, ZW_R(0.0), &k) == ZW_OK && k > ZW_R(0.1055) && k < ZW_R(0.1065);
    ok = ok && zw_device_loop_check(&dl, &ws, ZW_R(0.1), ZW_R(0.0), &v) == ZW_OK && v.stable;'
        ;;
    regmap)
        inc='#include "zwidth/regmap.h"'
        body='
    static zw_regmap rm;
    static zw_cert cert; /* all zero: refused, the map stays unsealed (output off) */
    zw_reason why;
    float K = 1.0f, B = 1.0f;
    uint_least8_t req[5] = {3u, 0u, 0u, 0u, 1u}, resp[253];
    size_t n = 0u;
    int ok = 1;
    (void)zw_regmap_init(&rm, &cert, &why);
    zw_regmap_set_state(&rm, 0.0f, 0.0f, 0.0f, 0u);
    (void)zw_regmap_active_gains(&rm, &K, &B);
    ok = ok && K == 0.0f && B == 0.0f;
    /* read holding register 0 (a read is answered while unsealed): 03, 2 bytes, 1 word */
    ok = ok && zw_regmap_handle_pdu(&rm, req, sizeof req, resp, sizeof resp, &n) == ZW_MB_OK;
    ok = ok && n == 4u && resp[0] == 3u && resp[1] == 2u;'
        ;;
    esac
    cat <<EOF
/* Generated by tools/firmware_files.sh: use "$1" of docs/firmware.md. */
#include "zwidth/selftest.h"
$inc

int main(void)
{
    int st_ok = zw_selftest() == ZW_OK;
$body
#ifdef ZW_DOC_OPTIONAL
    ok = ok && zw_status_name(ZW_OK)[0] != '\0';
#endif
    return (st_ok && ok) ? 0 : 1;
}
EOF
}

# copy NAME DIR SOURCES HEADERS: exactly those files into DIR/src and DIR/inc/zwidth
copy_files() {
    local dir=$2 f
    mkdir -p "$dir/src" "$dir/inc/zwidth"
    for f in $3; do
        [ -f "csrc/src/$f" ] || fail "$DOC, use '$1': sources column names $f, not in csrc/src/"
        cp "csrc/src/$f" "$dir/src/"
    done
    for f in $4; do
        [ -f "csrc/include/zwidth/$f" ] || fail "$DOC, use '$1': headers column names $f, not in csrc/include/zwidth/"
        cp "csrc/include/zwidth/$f" "$dir/inc/zwidth/"
    done
}

# build NAME DIR DEFS: the M4F image, the host programs (float, double), run
build_use() {
    local name=$1 dir=$2 defs=$3 log=$2/log
    # shellcheck disable=SC2086
    ${CROSS}gcc $M4F $WARN $defs -Iinc -Isrc src/*.c main.c $M4F_LINK -lm -o m4f.elf \
        >"$log" 2>&1 < /dev/null || { cat "$log" >&2; fail "use '$name' ($dir): the files docs/firmware.md lists do not build for the Cortex-M4F: ${CROSS}gcc $M4F $WARN $defs -Iinc -Isrc src/*.c main.c $M4F_LINK -lm"; }
    for prec in float double; do
        local p=""
        [ "$prec" = float ] && p=-DZW_REAL_FLOAT
        # shellcheck disable=SC2086
        $HOSTCC $HOST $p $defs -Iinc -Isrc src/*.c main.c -lm -o "host_$prec" >"$log" 2>&1 ||
            { cat "$log" >&2; fail "use '$name' ($dir): the files docs/firmware.md lists do not build on the host ($prec): $HOSTCC $HOST $p $defs -Iinc -Isrc src/*.c main.c -lm"; }
        "./host_$prec" || fail "use '$name' ($dir): the host program ($prec) returned $? (a known answer of the paper's drive or zw_selftest failed)"
    done
}

# ---- 1. README.md's C example ------------------------------------------------------------
awk '/^## A short tour/ { on = 1 } on && /^```c$/ { inb = 1; next } inb && /^```$/ { exit } inb { print }' \
    "$README" >"$W/readme_block.c"
[ -s "$W/readme_block.c" ] || fail "$README: no \`\`\`c block in '## A short tour'"
last=$(grep -nx '}' "$W/readme_block.c" | tail -n 1 | cut -d: -f1 || true)
last=${last:-0}
{
    echo "/* README.md's C example, wrapped by tools/firmware_files.sh: file scope up to line $last, then main(). */"
    head -n "$last" "$W/readme_block.c"
    echo 'int main(void)'
    echo '{'
    tail -n +"$((last + 1))" "$W/readme_block.c"
    echo '    return 0;'
    echo '}'
} >"$W/readme_example.c"

# ---- 2. the table ------------------------------------------------------------------------
every_s="" every_so="" every_h="" every_ho=""
acc_s="" acc_so="" acc_h="" acc_ho=""
seen=""
n_built=0
readme_done=0
while IFS=$'\037' read -r name s so h ho; do
    key=$(key_of "$name")
    case " $seen " in *" $key "*) fail "$DOC: two rows for use '$key'" ;; esac
    seen="$seen $key"
    if [ "$key" = every ]; then
        every_s=$s every_so=$so every_h=$h every_ho=$ho
        continue
    fi
    [ -n "$every_s" ] || fail "$DOC: the 'every use' row must come first"
    acc_s="$acc_s $s" acc_so="$acc_so $so" acc_h="$acc_h $h" acc_ho="$acc_ho $ho"
    for variant in base optional; do
        srcs="$every_s $acc_s" hdrs="$every_h $acc_h" defs=""
        if [ "$variant" = optional ]; then
            srcs="$srcs $every_so $acc_so" hdrs="$hdrs $every_ho $acc_ho" defs=-DZW_DOC_OPTIONAL
        fi
        d=$W/$key-$variant
        copy_files "$name" "$d" "$srcs" "$hdrs"
        main_of "$key" >"$d/main.c"
        (cd "$d" && build_use "$name" "$d" "$defs")
        n_built=$((n_built + 1))
        printf 'firmware_files: %-9s %-8s %2d sources, %2d headers: Cortex-M4F links, host float + double run\n' \
            "$key" "$variant" "$(find "$d/src" -name '*.c' | wc -l)" "$(find "$d/inc/zwidth" -type f | wc -l)"
    done
    # The README example, linked with the real-units files (it calls zw_device_*).
    if [ "$key" = units ]; then
        for prec in float double; do
            p=""
            [ "$prec" = float ] && p=-DZW_REAL_FLOAT
            # shellcheck disable=SC2086
            $HOSTCC $HOST -Wfloat-conversion -Wdouble-promotion $p -Icsrc/include -I"$W/units-base/src" \
                "$W/readme_example.c" "$W"/units-base/src/*.c -lm -o "$W/readme_$prec" >"$W/readme.log" 2>&1 ||
                { cat "$W/readme.log" >&2; fail "$README: the C example of 'A short tour' does not compile warning-free ($prec; $HOSTCC $HOST -Wfloat-conversion -Wdouble-promotion $p, wrapped as $W/readme_example.c)"; }
            "$W/readme_$prec" || fail "$README: the C example ($prec) returned $?"
        done
        readme_done=1
        echo "firmware_files: README.md's C example compiles with -Wfloat-conversion -Wdouble-promotion -Werror, float and double, and runs"
    fi
done <"$W/table.tsv"
for k in every check extremes units loop regmap; do
    case " $seen " in *" $k "*) ;; *) fail "$DOC: no row for use '$k'" ;; esac
done
[ "$readme_done" = 1 ] || fail "the README example was not built"

# ---- 3. the checker fails on a broken list and on a broken example -------------------------
if [ "${ZW_FILES_NO_SELFCHECK:-0}" != 1 ]; then
    awk -F'|' 'index($2, "every use") { sub(/portable_math\.h /, "") } { print }' "$DOC" >"$W/broken.md"
    cmp -s "$DOC" "$W/broken.md" && fail "self-check: found no portable_math.h in the 'every use' row to drop"
    if ZW_FIRMWARE_DOC="$W/broken.md" ZW_FILES_NO_SELFCHECK=1 "$ROOT/tools/firmware_files.sh" >"$W/self.log" 2>&1; then
        fail "self-check: a firmware.md without portable_math.h in 'every use' still passed"
    fi
    grep -q 'portable_math.h' "$W/self.log" || { cat "$W/self.log" >&2; fail "self-check: the broken list failed, but not on portable_math.h"; }
    awk '/^## A short tour/ { on = 1 } on && !done && sub(/ZW_R\(0\.02\)/, "0.02") { done = 1 } { print }' "$README" >"$W/broken_readme.md"
    cmp -s "$README" "$W/broken_readme.md" && fail "self-check: found no ZW_R(0.02) in the README example to remove"
    if ZW_README="$W/broken_readme.md" ZW_FILES_NO_SELFCHECK=1 "$ROOT/tools/firmware_files.sh" >"$W/self.log" 2>&1; then
        fail "self-check: a README example without ZW_R() on 0.02 still passed"
    fi
    grep -q 'Wfloat-conversion\|Wdouble-promotion' "$W/self.log" || { cat "$W/self.log" >&2; fail "self-check: the broken README example failed, but not on a float warning"; }
    echo "firmware_files: self-check: fails without portable_math.h in the list, and on a README literal without ZW_R()"
fi
echo "firmware_files: $n_built builds of docs/firmware.md's file lists and README.md's C example: all pass"
