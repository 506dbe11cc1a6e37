#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
#
# tools/core_modules.sh - the firmware modules: ZW_CORE_SOURCES of CMakeLists.txt (set(...)
# and list(APPEND ...)), in its order, one line, names without csrc/src/ and .c.  The one
# parser of that list for the scripts that build or ship the core themselves (footprint.sh,
# m4f_box_cert.sh, avr_build.sh, amalgamate.sh, firmware_release.sh, dist_check.sh,
# diff_plant.sh), so that a module added there is covered without editing them.
set -euo pipefail
cd "$(dirname "$0")/.."
awk '
    /^[ \t]*(set[ \t]*\([ \t]*ZW_CORE_SOURCES|list[ \t]*\([ \t]*APPEND[ \t]+ZW_CORE_SOURCES)([ \t]|$)/ { on = 1 }
    on {
        line = $0; sub(/#.*/, "", line)
        rest = line
        while (match(rest, /csrc\/src\/[A-Za-z0-9_]+\.c/)) {
            m = substr(rest, RSTART + 9, RLENGTH - 11)
            if (!(m in seen)) { seen[m] = 1; printf "%s ", m }
            rest = substr(rest, RSTART + RLENGTH)
        }
        if (line ~ /\)/) on = 0
    }' CMakeLists.txt | sed 's/ $//'
