#!/usr/bin/env bash
# The main job: build zwidth and print the stability limits and advice for a drive
# (the paper's experimental drive unless options are given; see --help).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/bootstrap.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target zwidth-limits >/dev/null
exec build/zwidth-limits "$@"
