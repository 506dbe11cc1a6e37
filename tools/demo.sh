#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# The main job: build zwidth and print the stability limits and advice for a drive.
# Without options: the paper's experimental drive and its ideal loop, named explicitly
# (--preset paper-drive); with options, they go to zwidth-limits as they are (the plant
# needs --m or --J, --b, --T, and the loop --delay: 0 for the paper's ideal loop, 1 for
# firmware that applies the force at the next tick; optionally --velocity-filter).
set -euo pipefail
cd "$(dirname "$0")/.."
# Only a C compiler, CMake and Ninja are needed here (the tests need much more).
tools/bootstrap.sh --demo
cmake -S . -B build-demo -G Ninja -DCMAKE_BUILD_TYPE=Release -DZW_BUILD_TESTS=OFF >/dev/null
cmake --build build-demo --target zwidth-limits >/dev/null
if [ "$#" -eq 0 ]; then
    echo "$ zwidth-limits --preset paper-drive"
    set -- --preset paper-drive
fi
exec build-demo/zwidth-limits "$@"
