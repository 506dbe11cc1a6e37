#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# Cost of certification on the Modbus path: latency and rate of a gain write (K and B in one
# write-multiple request, alternating between two accepted pairs) against zwidth-drive and
# against a plain libmodbus server that validates nothing (bench/modbus/).
#
#   tools/bench_modbus.sh [--n N]        N timed writes per server (default 20000)
#
# The servers are measured by one client process, interleaved in blocks of 500 writes; a
# last row times the same PDUs handed straight to zw_regmap_handle_pdu in that process:
# the certification itself, without sockets.
#
# Environment: ZW_BUILD_DIR (default <repo>/build) holds zwidth-drive and libzwidth_d.a;
# CC (default cc).  Both servers listen on free 127.0.0.1 ports and are stopped on exit.
# Prints a Markdown table.  Wall-clock only: one run, medians, no profiler.
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$PWD
BUILD=${ZW_BUILD_DIR:-$REPO/build}
CC=${CC:-cc}
N=20000

while [ $# -gt 0 ]; do
    case "$1" in
        --n) N=${2:?--n needs a number}; shift 2 ;;
        --n=*) N=${1#--n=}; shift ;;
        -h|--help) awk 'NR > 1 && /^# Environment/ { exit } NR > 1 && /^#/ && !/SPDX-/' "$0"; exit 0 ;;
        *) echo "bench_modbus.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
case "$N" in ''|*[!0-9]*) echo "bench_modbus.sh: --n wants a positive integer, got '$N'" >&2; exit 2 ;; esac

die() { echo "bench_modbus.sh: $*" >&2; exit 1; }
pkg-config --exists libmodbus || die "libmodbus not found (Debian: apt-get install libmodbus-dev)"

# zwidth-drive and the core library, from the CMake build (Release recommended).
if [ -f "$BUILD/build.ninja" ] || [ -f "$BUILD/Makefile" ]; then
    cmake --build "$BUILD" --target zwidth_d zwidth-drive >/dev/null
fi
DRIVE=$BUILD/zwidth-drive
[ -x "$DRIVE" ] || die "$DRIVE not built (cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build)"

OUT=$BUILD/bench-modbus
mkdir -p "$OUT"
CORE=("$BUILD/libzwidth_d.a")
[ -f "${CORE[0]}" ] || CORE=(csrc/src/*.c -ffp-contract=off)
MB_CFLAGS=$(pkg-config --cflags libmodbus)
MB_LIBS=$(pkg-config --libs libmodbus)
# shellcheck disable=SC2086
$CC -std=c99 -O2 -Wall -Wextra -I csrc/include $MB_CFLAGS bench/modbus/bench_modbus.c \
    "${CORE[@]}" $MB_LIBS -lm -o "$OUT/bench_modbus"
# shellcheck disable=SC2086
$CC -std=c99 -O2 -Wall -Wextra -I csrc/include $MB_CFLAGS bench/modbus/bench_plain_server.c \
    $MB_LIBS -o "$OUT/bench_plain_server"

free_port() {
    python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1]); s.close()'
}

PIDS=()
cleanup() {
    for pid in "${PIDS[@]:-}"; do
        [ -n "$pid" ] || continue
        kill "$pid" 2>/dev/null || true
        for _ in 1 2 3 4 5 6 7 8 9 10; do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
        wait "$pid" 2>/dev/null || true
    done
}
trap cleanup EXIT

# The paper's drive (short-circuited load), a policy that accepts both benchmark pairs
# (0.30, -1.0e-3) and (0.32, -1.1e-3) and the first step from (0, 0).
# Client and both servers pinned to one CPU (the first this script may use): every round
# trip is then a same-CPU wake-up for both servers alike, instead of whatever the scheduler
# picks per process (on a busy 2-CPU machine that alone moved a median by 2x).
SERVER_CPU=() CLIENT_CPU=() CPU=""
if command -v taskset >/dev/null; then
    CPU=$(taskset -pc $$ 2>/dev/null | sed 's/.*: *//; s/[,-].*//')
    if [ -n "$CPU" ]; then
        SERVER_CPU=(taskset -c "$CPU")
        CLIENT_CPU=(taskset -c "$CPU")
    fi
fi
PLAIN_PORT=$(free_port)
"${SERVER_CPU[@]}" "$OUT/bench_plain_server" --port "$PLAIN_PORT" >"$OUT/plain.log" 2>&1 &
PIDS+=($!)
DRIVE_PORT=$(free_port)
"${SERVER_CPU[@]}" "$DRIVE" --host 127.0.0.1 --port "$DRIVE_PORT" --m 8.578e-6 --b 2.197e-3 --T 0.02 --sigma 0.9 --r 1 \
    --k-min 0 --k-max 0.45 --b-min -2.197e-3 --b-max 3.5e-3 --dk-max 0.5 --db-max 5e-3 \
    >"$OUT/drive.log" 2>&1 &
PIDS+=($!)

# One client process, the targets interleaved in blocks of 500 writes (plain, zwidth,
# in-process, plain, ...) so that load changes during the run hit all of them alike.
RESULTS=$("${CLIENT_CPU[@]}" "$OUT/bench_modbus" --target "plain:$PLAIN_PORT" --target "zwidth:$DRIVE_PORT" --inproc \
    --n "$N" 2>"$OUT/bench.log") \
    || die "benchmark failed (see $OUT/bench.log, $OUT/plain.log, $OUT/drive.log)"
cleanup
PIDS=()
PLAIN=$(grep '^RESULT plain ' <<<"$RESULTS")
ZW=$(grep '^RESULT zwidth ' <<<"$RESULTS")
INPROC=$(grep '^RESULT inproc ' <<<"$RESULTS")

read -r _ _ n_p med_p p99_p mean_p rate_p <<<"$PLAIN"
read -r _ _ n_z med_z p99_z mean_z rate_z <<<"$ZW"
read -r _ _ n_i med_i p99_i mean_i rate_i <<<"$INPROC"
awk -v ni="$n_i" -v mi="$med_i" -v pi="$p99_i" -v ai="$mean_i" -v ri="$rate_i" \
    -v np="$n_p" -v mp="$med_p" -v pp="$p99_p" -v ap="$mean_p" -v rp="$rate_p" \
    -v nz="$n_z" -v mz="$med_z" -v pz="$p99_z" -v az="$mean_z" -v rz="$rate_z" \
    -v pin="$CPU" -v cpu="$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //')" 'BEGIN {
    printf "Gain write over Modbus TCP on 127.0.0.1 (K and B in one 0x10 request, alternating between two accepted pairs), %d writes per server, one run, servers interleaved in blocks of 500", np
    if (cpu != "") printf ", %s", cpu
    if (pin != "") printf ", client and servers pinned to CPU %s", pin
    printf ".\n\n"
    printf "| server | writes | median (us) | p99 (us) | mean (us) | writes/s |\n"
    printf "|---|---:|---:|---:|---:|---:|\n"
    printf "| plain libmodbus (`modbus_reply`, no validation) | %d | %.1f | %.1f | %.1f | %.0f |\n", np, mp, pp, ap, rp
    printf "| zwidth-drive (certified) | %d | %.1f | %.1f | %.1f | %.0f |\n", nz, mz, pz, az, rz
    printf "| **cost of certification** (zwidth / plain) | | **%.2fx** (%+.1f us) | %.2fx | %.2fx (%+.1f us) | %.2fx |\n", mz / mp, mz - mp, pz / pp, az / ap, az - ap, rz / rp
    printf "| handler alone (`zw_regmap_handle_pdu` in-process, no network) | %d | %.2f | %.2f | %.2f | %.0f |\n", ni, mi, pi, ai, ri
}'
