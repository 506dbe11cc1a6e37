#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# Use zwidth from another project, as docs/firmware.md describes: install the build tree
# into a temporary prefix (then move it, to prove the installed files are relocatable), and
# build tests/consumer/ (a C and a C++ program) against it
#   1. with find_package(zwidth): zwidth::core (double) and zwidth::core_f (float),
#   2. with add_subdirectory of the source tree (same target names),
#   3. with pkg-config and plain cc / c++: zwidth.pc and zwidth_f.pc,
# run all eight programs, compile every installed header alone as C++, and check that an
# object built for one precision does not link against the other library.  Then the same
# programs against the one-file amalgamation (tools/amalgamate.sh), double and float.
#
# Usage: tools/consumer_test.sh [BUILD_DIR]   (default build; must be built already)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
CC=${CC:-cc}
CXX=${CXX:-c++}
T=$(mktemp -d "${TMPDIR:-/tmp}/zw-consumer.XXXXXX")
trap 'rm -rf "$T"' EXIT
fail() { echo "consumer_test: FAIL: $*" >&2; exit 1; }

cmake --install "$BUILD" --prefix "$T/stage" >/dev/null
mv "$T/stage" "$T/prefix"
P=$T/prefix
for f in include/zwidth/zwidth.h include/zwidth/precision.h lib/libzwidth_d.a lib/libzwidth_f.a \
         lib/cmake/zwidth/zwidthConfig.cmake lib/cmake/zwidth/zwidthConfigVersion.cmake \
         lib/pkgconfig/zwidth.pc lib/pkgconfig/zwidth_f.pc; do
    [ -f "$P/$f" ] || fail "cmake --install did not install $f"
done

run() {  # run PROGRAM EXPECTED-LINE
    local out
    out=$("$1") || fail "$1: $out"
    [ "$out" = "$2" ] || fail "$1 printed '$out', expected '$2'"
    echo "  $out  ($(basename "$1"))"
}

echo "find_package(zwidth):"
cmake -S tests/consumer -B "$T/cm" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$P" \
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >"$T/log" 2>&1 || { cat "$T/log"; fail "configure"; }
cmake --build "$T/cm" >"$T/log" 2>&1 || { cat "$T/log"; fail "build"; }
n=$(grep -c -- '-ffp-contract=off' "$T/cm/compile_commands.json" || true)
[ "$n" = 4 ] || fail "-ffp-contract=off reached $n of 4 consumer compilations"
run "$T/cm/consumer_c" "consumer ok (double, C)"
run "$T/cm/consumer_cxx" "consumer ok (double, C++)"
run "$T/cm/consumer_c_f" "consumer ok (float, C)"
run "$T/cm/consumer_cxx_f" "consumer ok (float, C++)"

echo "add_subdirectory(zwidth):"
cmake -S tests/consumer -B "$T/sub" -G Ninja -DCMAKE_BUILD_TYPE=Release -DZWIDTH_SOURCE_DIR="$PWD" \
    >"$T/log" 2>&1 || { cat "$T/log"; fail "configure"; }
cmake --build "$T/sub" >"$T/log" 2>&1 || { cat "$T/log"; fail "build"; }
run "$T/sub/consumer_c" "consumer ok (double, C)"
run "$T/sub/consumer_cxx_f" "consumer ok (float, C++)"

echo "pkg-config:"
export PKG_CONFIG_PATH="$P/lib/pkgconfig"
CWARN="-std=c99 -Wall -Wextra -Wpedantic -Werror -Wconversion -Wdouble-promotion -Wstrict-prototypes"
XWARN="-std=c++17 -Wall -Wextra -Wpedantic -Werror -Wconversion -Wdouble-promotion"
for pc in zwidth zwidth_f; do
    name=double; [ $pc = zwidth_f ] && name=float
    # shellcheck disable=SC2046,SC2086
    $CC $CWARN $(pkg-config --cflags $pc) tests/consumer/consumer.c $(pkg-config --libs $pc) -o "$T/pc_c_$pc"
    # shellcheck disable=SC2046,SC2086
    $CXX $XWARN $(pkg-config --cflags $pc) tests/consumer/consumer.cpp $(pkg-config --libs $pc) -o "$T/pc_cxx_$pc"
    run "$T/pc_c_$pc" "consumer ok ($name, C)"
    run "$T/pc_cxx_$pc" "consumer ok ($name, C++)"
done

echo "every installed header alone, as C++ and as C99, double and float:"
for h in "$P"/include/zwidth/*.h; do
    for def in "" -DZW_REAL_FLOAT; do
        # shellcheck disable=SC2086
        printf '#include "zwidth/%s"\ntypedef int zw_nonempty_unit;\n' "$(basename "$h")" |
            $CXX -std=c++11 -Wall -Wextra -Wpedantic -Werror $def -I"$P/include" -x c++ -fsyntax-only - ||
            fail "$(basename "$h") $def as C++"
        # shellcheck disable=SC2086
        printf '#include "zwidth/%s"\ntypedef int zw_nonempty_unit;\n' "$(basename "$h")" |
            $CC $CWARN $def -I"$P/include" -x c -fsyntax-only - || fail "$(basename "$h") $def as C99"
    done
done
echo "  $(ls "$P"/include/zwidth/*.h | wc -l) headers ok"

echo "precision mismatch fails at link time:"
mismatch() {  # mismatch LANG COMPILER SOURCE CFLAGS-PC LIBS-PC MISSING-SYMBOL
    local o=$T/mm.o
    # shellcheck disable=SC2046
    $2 $(pkg-config --cflags "$4") -c "$3" -o "$o"
    # shellcheck disable=SC2046
    if $2 "$o" $(pkg-config --libs "$5") -o "$T/mm" >"$T/log" 2>&1; then
        fail "$1 object built for $4 linked against $5"
    fi
    grep -q "undefined reference to .$6" "$T/log" || { cat "$T/log"; fail "$1 $4 vs $5: unexpected link error"; }
    echo "  $1 object of $4 + lib of $5: undefined reference to $6"
}
mismatch C "$CC" tests/consumer/consumer.c zwidth_f zwidth "zw_coeffs_init_f'"
mismatch C "$CC" tests/consumer/consumer.c zwidth zwidth_f "zw_coeffs_init'"
mismatch C++ "$CXX" tests/consumer/consumer.cpp zwidth_f zwidth "zw_coeffs_init_f'"
mismatch C++ "$CXX" tests/consumer/consumer.cpp zwidth zwidth_f "zw_coeffs_init'"
echo "amalgamation (tools/amalgamate.sh: zwidth.c + zwidth.h), strict flags:"
tools/amalgamate.sh "$T/amal" >/dev/null
# The consumer includes "zwidth/zwidth.h" (and "zwidth/sim.h", host-only, not in the
# amalgamation); a vendored copy includes "zwidth.h".  Two forwarding headers bridge that.
mkdir -p "$T/amal_inc/zwidth"
echo "#include \"$T/amal/zwidth.h\"" >"$T/amal_inc/zwidth/zwidth.h"
echo "#include \"$T/amal/zwidth.h\"" >"$T/amal_inc/zwidth/sim.h"
STRICT="$CWARN -Wshadow -Wmissing-prototypes -ffp-contract=off"
for def in "" -DZW_REAL_FLOAT; do
    name=double; [ -n "$def" ] && name=float
    # shellcheck disable=SC2086
    $CC $STRICT $def -O2 -c "$T/amal/zwidth.c" -o "$T/amal.o"
    # shellcheck disable=SC2086
    $CC $CWARN $def -ffp-contract=off -I"$T/amal" -I"$T/amal_inc" tests/consumer/consumer.c "$T/amal.o" -lm -o "$T/amal_c"
    # shellcheck disable=SC2086
    $CXX $XWARN $def -ffp-contract=off -I"$T/amal" -I"$T/amal_inc" tests/consumer/consumer.cpp "$T/amal.o" -lm -o "$T/amal_cxx"
    run "$T/amal_c" "consumer ok ($name, C)"
    run "$T/amal_cxx" "consumer ok ($name, C++)"
done
echo "consumer_test: all passed"
