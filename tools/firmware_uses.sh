#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# Which sources and which C library / libm functions each firmware use of zwidth needs
# (the tables of docs/firmware.md).  For each use a tiny main calling its functions is
# linked for a Cortex-M4F (float build, -Os, nano.specs, --gc-sections) against an archive
# of all firmware modules; the linker map names the modules it pulled, and
# arm-none-eabi-nm -u on those modules names what they need from outside zwidth.
# Run twice: plain, and with -fno-math-errno (sqrtf becomes vsqrt.f32).
# Usage: tools/firmware_uses.sh        (needs gcc-arm-none-eabi and libnewlib-arm-none-eabi)
set -euo pipefail
cd "$(dirname "$0")/.."
CROSS=${CROSS:-arm-none-eabi-}
MODULES=$(sed -n '/^set(ZW_CORE_SOURCES/,/)/s/.*csrc\/src\/\([a-z_]*\)\.c.*/\1/p' CMakeLists.txt) # every firmware module
B=$(mktemp -d "${TMPDIR:-/tmp}/zw-uses.XXXXXX")
trap 'rm -rf "$B"' EXIT
T="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -DZW_REAL_FLOAT"
F="-std=c99 -Os -ffp-contract=off -ffunction-sections -fdata-sections -Wall -Wextra -Werror $T -Icsrc/include"

# use NAME: the main of one use, its body on stdin (inputs from volatile 'in', results
# into volatile 'sink', so that nothing is folded or dropped)
use() {
    {
        printf '#include "zwidth/zwidth.h"\nvolatile zw_real in = ZW_R(1.5);\nvolatile int sink;\n'
        printf 'int main(void)\n{\n'
        cat
        printf '}\n'
    } >"$B/$1.c"
}
use check <<'C'
    zw_coeffs c;
    zw_verdict v;
    if (zw_coeffs_init(&c, in) != ZW_OK || zw_check(&c, in, in, &v) != ZW_OK) return 1;
    sink = v.stable;
    return 0;
C
use extremes <<'C'
    zw_coeffs c;
    zw_verdict v;
    zw_extremes x;
    zw_real lo, hi, am;
    bool ne;
    if (zw_coeffs_init(&c, in) != ZW_OK || zw_check(&c, in, in, &v) != ZW_OK) return 1;
    if (zw_extremes_compute(&c, &x) != ZW_OK || zw_alpha_max(&c, in, &am) != ZW_OK) return 2;
    if (zw_beta_interval(&c, in, &lo, &hi, &ne) != ZW_OK) return 3;
    sink = v.stable + (x.alpha_mmax > lo) + (hi > am) + ne;
    return 0;
C
use units <<'C'
    zw_device d;
    zw_verdict v;
    zw_device_extremes x;
    zw_real k, lo, hi;
    bool ne;
    if (zw_device_init(&d, in, in, in) != ZW_OK || zw_device_check(&d, in, in, &v) != ZW_OK) return 1;
    if (zw_device_extremes_compute(&d, &x) != ZW_OK || zw_device_k_max(&d, in, &k) != ZW_OK) return 2;
    if (zw_device_b_range(&d, in, &lo, &hi, &ne) != ZW_OK) return 3;
    sink = v.stable + (x.K_mmax > k) + (hi > lo) + ne;
    return 0;
C
use loop <<'C'
    static zw_device_loop dl;   /* 1.3 KB: not on the stack */
    static zw_loop_workspace ws; /* the checks' scratch (loop.h) */
    zw_device_loop_spec spec = {1u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, ZW_R(0.0), ZW_R(0.0), 0u};
    zw_loop_verdict v;
    zw_real k, lo, hi;
    bool ne;
    if (zw_device_loop_init(&dl, in, in, in, &spec) != ZW_OK) return 1;
    if (zw_device_loop_check(&dl, &ws, in, in, &v) != ZW_OK || zw_device_loop_k_max(&dl, &ws, in, &k) != ZW_OK) return 2;
    if (zw_device_loop_b_range(&dl, &ws, in, &lo, &hi, &ne) != ZW_OK) return 3;
    sink = v.stable + (hi > k) + ne;
    return 0;
C
use regmap <<'C'
    static zw_regmap rm;
    static zw_cert cert;
    zw_reason why;
    uint_least8_t req[5] = {3u, 0u, 0u, 0u, 1u}, resp[253];
    size_t n = 0u;
    (void)zw_regmap_init(&rm, &cert, &why);
    zw_regmap_set_state(&rm, 0.0f, 0.0f, 0.0f, 0u);
    sink = (int)zw_regmap_handle_pdu(&rm, req, sizeof req, resp, sizeof resp, &n);
    return 0;
C

echo "| use | math flags | modules linked | needs from libm / libc |"
echo "|---|---|---|---|"
for flags in "" "-fno-math-errno"; do
    mkdir -p "$B/o$flags"
    for m in $MODULES; do
        # shellcheck disable=SC2086
        ${CROSS}gcc $F $flags -c "csrc/src/$m.c" -o "$B/o$flags/$m.o"
    done
    rm -f "$B/libz.a"
    (cd "$B/o$flags" && ${CROSS}ar rcs "$B/libz.a" ./*.o)
    for use in check extremes units loop regmap; do
        # shellcheck disable=SC2086
        ${CROSS}gcc $F $flags -c "$B/$use.c" -o "$B/$use.o"
        # shellcheck disable=SC2086
        ${CROSS}gcc $T -specs=nano.specs -specs=nosys.specs -Wl,--gc-sections "$B/$use.o" "$B/libz.a" -lm \
            -Wl,-Map="$B/$use.map" -o "$B/$use.elf"
        mods=$(sed -n 's/^[^ ]*libz\.a(\([a-z_]*\)\.o).*/\1/p' "$B/$use.map" | sort -u)
        needs=$(for m in $mods; do ${CROSS}nm -u "$B/o$flags/$m.o"; done | awk '{print $2}' |
            { grep -v '^zw_' || true; } | sort -u | tr '\n' ' ')
        # shellcheck disable=SC2086
        printf '| %s | %s | %s | %s |\n' "$use" "-Os${flags:+ $flags}" \
            "$(echo $mods | sed 's/ /, /g')" "$(echo ${needs:-none} | sed 's/ /, /g')"
    done
done
