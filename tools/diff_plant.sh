#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# tools/diff_plant.sh - differential test: the core at BASE (a commit) against the working
# tree, both precisions: zw_plant_init's every field and status (bitwise) and
# zw_box_loop_check's verdicts and zw_box_loop_k_max's bounds (every filter) must be
# identical (tools/diff_plant.c).
# Usage: bash tools/diff_plant.sh [BASE [SPECS [BOXES]]]   (defaults: HEAD 50000 300)
# DIFF_PLANT_VALUES_ONLY=1: compare the values and statuses only, not the bounds (*_err).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
BASE=${1:-HEAD}
SPECS=${2:-50000}
BOXES=${3:-300}
T=$(mktemp -d "${TMPDIR:-/tmp}/zw-diff-plant.XXXXXX")
trap 'rm -rf "$T"' EXIT
mkdir -p "$T/old"
git archive "$BASE" csrc | tar -x -C "$T/old"
# ZW_CORE_SOURCES of CMakeLists.txt (the libraries' sources)
SRCS=$(tools/core_modules.sh | tr ' ' '\n' | sed 's|.*|csrc/src/&.c|' | sort -u)
CFLAGS="-std=c99 -O2 -ffp-contract=off -fPIC -shared"
status=0
for prec in double float; do
    def=""
    [ "$prec" = float ] && def="-DZW_REAL_FLOAT"
    # shellcheck disable=SC2086
    (cd "$T/old" && gcc $CFLAGS $def -Icsrc/include $SRCS -o "$T/old-$prec.so" -lm)
    # shellcheck disable=SC2086
    gcc $CFLAGS $def -Icsrc/include $SRCS -o "$T/new-$prec.so" -lm
    # shellcheck disable=SC2086
    gcc -std=c99 -O2 -Wall -Wextra -ffp-contract=off $def -Icsrc/include tools/diff_plant.c -o "$T/diff-$prec" -ldl -lm
    echo "== $prec: $BASE vs working tree"
    "$T/diff-$prec" "$T/old-$prec.so" "$T/new-$prec.so" "$SPECS" "$BOXES" || status=1
done
exit $status
