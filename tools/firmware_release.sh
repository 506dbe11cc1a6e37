#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
#
# The C source release of the firmware part, for teams that build with their own tools:
#   OUT/zwidth-firmware-VERSION.tar.gz  ->  zwidth-firmware-VERSION/
#     csrc/src/        the firmware modules (ZW_CORE_SOURCES of CMakeLists.txt, so a module
#                      added there is released without editing this script) and the private
#                      headers they include (internal.h)
#     csrc/include/zwidth/  the headers those modules and zwidth.h include, transitively
#                      (not the host-only sim.h)
#     amalgamation/    zwidth.c + zwidth.h, the same in one file (tools/amalgamate.sh)
#     docs/firmware.md and the docs it links to, LICENSE, LICENSES/, CHANGELOG.md, README,
#                      REUSE.toml (the archive is REUSE-compliant: an SBOM tool reads every
#                      file's SPDX tags)
# VERSION is that of csrc/include/zwidth/version.h.  The archive is reproducible: sorted
# names, owner 0, every mtime that of the last commit.
#
# --check also unpacks the archive in an empty temporary directory, runs reuse lint on it
# and, from there only, builds it for the Cortex-M4F with arm-none-eabi-gcc and newlib (float and double
# builds, and the amalgamation; -std=c99 -Os and the project's warnings as errors, flags
# of docs/firmware.md), links every module into one image, and runs a small main under
# QEMU (mps2-an386: zw_selftest, a stable and an unstable pair of the paper, extremes).
# The image's start-up code and linker script are the benchmark report's
# (bench/report/mcu/), which the archive does not carry.
#
# Usage: tools/firmware_release.sh [--check] [OUT]   (OUT default build/release)
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
CHECK=0
if [ "${1:-}" = --check ]; then CHECK=1; shift; fi
OUT=${1:-build/release}
fail() { echo "firmware_release: FAIL: $*" >&2; exit 1; }

VERSION=$(sed -n 's/^#define ZW_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)$/\2/p' \
    csrc/include/zwidth/version.h | paste -sd.)
NAME=zwidth-firmware-$VERSION
MODULES=$(tools/core_modules.sh)
[ -n "$MODULES" ] || fail "no ZW_CORE_SOURCES in CMakeLists.txt"
T=$(mktemp -d "${TMPDIR:-/tmp}/zw-fwrel.XXXXXX")
trap 'rm -rf "$T"' EXIT
S=$T/$NAME
mkdir -p "$S/csrc/src" "$S/csrc/include/zwidth" "$S/docs" "$S/LICENSES"

# Headers: the closure of the #include "zwidth/..." lines of zwidth.h and the modules.
includes_of() { sed -n 's/^#include "zwidth\/\([a-z0-9_]*\)\.h".*/\1/p' "$@" | sort -u; }
headers=$(includes_of csrc/include/zwidth/zwidth.h csrc/src/*.h $(for m in $MODULES; do echo "csrc/src/$m.c"; done))
headers=$(printf '%s\nzwidth\n' "$headers" | sort -u)
while :; do
    more=$(printf '%s\n' $headers $(includes_of $(for h in $headers; do echo "csrc/include/zwidth/$h.h"; done)) | sort -u)
    [ "$more" = "$headers" ] && break
    headers=$more
done
for h in $headers; do cp "csrc/include/zwidth/$h.h" "$S/csrc/include/zwidth/"; done
for m in $MODULES; do cp "csrc/src/$m.c" "$S/csrc/src/"; done
# Private headers (internal.h, ...): those of csrc/src the modules include, transitively.
private=""
next=$(for m in $MODULES; do echo "csrc/src/$m.c"; done)
while [ -n "$next" ]; do
    found=$(sed -n 's/^#include "\([a-z0-9_]*\.h\)".*/\1/p' $next | sort -u)
    next=""
    for h in $found; do
        case " $private " in *" $h "*) continue ;; esac
        [ -f "csrc/src/$h" ] || continue
        private="$private $h"; next="$next csrc/src/$h"
    done
done
for h in $private; do cp "csrc/src/$h" "$S/csrc/src/"; done
tools/amalgamate.sh "$S/amalgamation" >/dev/null
cp docs/firmware.md "$S/docs/"
# every doc firmware.md links, to the page or to a section of it ((modbus.md#firmware-...))
for d in $(grep -oE '\([a-z_-]+\.md[)#]' docs/firmware.md | tr -d '()#' | sort -u); do
    cp "docs/$d" "$S/docs/"   # a link to a missing doc fails the release
done
cp LICENSE CHANGELOG.md REUSE.toml "$S/"
cp LICENSES/*.txt "$S/LICENSES/"
# REUSE-IgnoreStart (the README's tags, not this script's)
cat >"$S/README" <<README
SPDX-FileCopyrightText: 2026 The zwidth authors
SPDX-License-Identifier: Apache-2.0

zwidth $VERSION, firmware part: the exact stability region of impedance-controlled haptic
devices and drives, in portable C99 (no heap, no I/O, no global state; double or float).

Either compile csrc/src/*.c with csrc/include on the include path, or the one file
amalgamation/zwidth.c with amalgamation/zwidth.h.  Flags, which modules each use needs,
the libm functions they call and the float/double choice: docs/firmware.md.  Call
zw_selftest() once at start-up (docs/fp-environment.md).

Modules: $(echo $MODULES | tr ' ' ',' | sed 's/,/, /g')
License: Apache-2.0 (LICENSE).  Changes: CHANGELOG.md.
README
# REUSE-IgnoreEnd

mkdir -p "$OUT"
EPOCH=$(git log -1 --format=%ct 2>/dev/null || echo 0)
ARCHIVE=$OUT/$NAME.tar.gz
tar --sort=name --owner=0 --group=0 --numeric-owner --mtime="@$EPOCH" -C "$T" -cf - "$NAME" |
    gzip -n -9 >"$ARCHIVE.tmp"
mv "$ARCHIVE.tmp" "$ARCHIVE"
echo "firmware_release: wrote $ARCHIVE ($(stat -c %s "$ARCHIVE") bytes; $(echo $MODULES | wc -w) modules, $(echo $headers | wc -w) headers)"
[ "$CHECK" = 1 ] || exit 0

# ---- --check: build the archive alone, in an empty directory, for the Cortex-M4F ----
C=$T/check
MCU=$PWD/bench/report/mcu
REUSE=${REUSE:-$( [ -x .venv/bin/reuse ] && echo "$PWD/.venv/bin/reuse" || echo reuse )}
mkdir -p "$C"
tar -xzf "$ARCHIVE" -C "$C"
cd "$C/$NAME"
"$REUSE" lint --lines >"$C/reuse.log" 2>&1 || { cat "$C/reuse.log"; fail "reuse lint of the archive"; }
echo "firmware_release: reuse lint of the archive: every file carries its copyright and license"
CC=arm-none-eabi-gcc
M4F="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard"
CFLAGS="-std=c99 -Os -ffp-contract=off -fno-math-errno -ffunction-sections -fdata-sections -Wall -Wextra
    -Wpedantic -Werror -Wshadow -Wconversion -Wdouble-promotion -Wstrict-prototypes -Wmissing-prototypes"
LDFLAGS="-nostartfiles -specs=nano.specs -specs=nosys.specs -T $MCU/mps2_an386.ld"
cat >"$C/main.c" <<'MAIN'
/* Every module linked (not garbage-collected), then the paper's drive at delta = 2.049. */
#include "semihost.h"
#ifdef ZW_FW_AMALGAMATION
#include "zwidth.h"
#else
#include "zwidth/zwidth.h"
#endif

int main(void)
{
    zw_coeffs c;
    zw_verdict v;
    zw_extremes x;
    int ok = zw_selftest() == ZW_OK;
    ok = ok && zw_coeffs_init(&c, ZW_R(2.049)) == ZW_OK;
    ok = ok && zw_check(&c, ZW_R(6.09), ZW_R(0.42075), &v) == ZW_OK && v.stable;
    ok = ok && zw_check(&c, ZW_R(6.11), ZW_R(0.42075), &v) == ZW_OK && !v.stable;
    ok = ok && zw_extremes_compute(&c, &x) == ZW_OK && x.alpha_mmax > ZW_R(6.09);
    semihost_puts(ok ? "firmware ok " ZW_VERSION_STRING "\n" : "firmware FAILED\n");
    return ok ? 0 : 1;
}
MAIN
build_and_run() {  # name, precision flags, sources..., include flags after --
    local name=$1 prec=$2 srcs=() incs=() out
    shift 2
    while [ "$1" != -- ]; do srcs+=("$1"); shift; done
    shift; incs=("$@")
    mkdir -p "$C/$name"
    for s in "${srcs[@]}"; do
        # shellcheck disable=SC2086
        $CC $CFLAGS $M4F $prec "${incs[@]}" -c "$s" -o "$C/$name/$(basename "$s" .c).o" ||
            fail "$name: $s does not compile for the Cortex-M4F"
    done
    # shellcheck disable=SC2086
    $CC -std=c99 -Os -Wall -Wextra -Werror $M4F $prec "${incs[@]}" -I"$MCU" $LDFLAGS \
        "$C/main.c" "$MCU/startup.c" "$C/$name"/*.o -lm -o "$C/$name.elf" || fail "$name: link"
    out=$(timeout 60 qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none \
        -semihosting-config enable=on,target=native -kernel "$C/$name.elf" 2>&1 | tr -d '\r') ||
        fail "$name: the image failed under QEMU: $out"
    [ "$out" = "firmware ok $VERSION" ] || fail "$name: printed '$out'"
    printf '  %-12s %s\n' "$name" "$out ($(arm-none-eabi-size "$C/$name.elf" | awk 'NR == 2 { print $1 + $2 }') B flash, every module linked)"
}
echo "firmware_release: $NAME built alone from the archive for the Cortex-M4F, run under QEMU:"
build_and_run float -DZW_REAL_FLOAT csrc/src/*.c -- -Icsrc/include
build_and_run double "" csrc/src/*.c -- -Icsrc/include
build_and_run amalgamation "-DZW_REAL_FLOAT -DZW_FW_AMALGAMATION" amalgamation/zwidth.c -- -Iamalgamation
