#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# The Modbus demo: a simulated drive on 127.0.0.1, tuned by zwidth-tune.  A pair inside
# the certified limits is accepted; one outside is refused with a reason, and reading back
# shows the old gains.  Port: $ZW_DEMO_PORT (default 1502).
#
# It needs only the C build of zwidth-drive and zwidth-tune, libmodbus and libcrypto
# (tools/bootstrap.sh --modbus-demo: no test packages, no .venv), and builds them in
# build-demo (without the tests), as tools/demo.sh does.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/bootstrap.sh --modbus-demo
cmake -S . -B build-demo -G Ninja -DCMAKE_BUILD_TYPE=Release -DZW_BUILD_TESTS=OFF >/dev/null
cmake --build build-demo --target zwidth-drive zwidth-tune >/dev/null
port=${ZW_DEMO_PORT:-1502}
tune() { echo; echo "\$ zwidth-tune $*"; build-demo/zwidth-tune --port "$port" "$@"; }

build-demo/zwidth-drive --port "$port" --simulate --speed 10 &
drive=$!
trap 'kill "$drive" 2>/dev/null; wait "$drive" 2>/dev/null || true' EXIT
for _ in $(seq 50); do build-demo/zwidth-tune --port "$port" status >/dev/null 2>&1 && break; sleep 0.1; done

echo "zwidth-drive: the paper's drive (J = 85.78e-7 kg m^2, b = 2.197e-3 N m s/rad, T = 0.02 s),"
echo "certified with sigma = 0.8 of K_max(B), spectral radius < 0.999, on 127.0.0.1:$port"
tune set --K 0.39 --B -1.36e-3
set +e
tune set --K 0.45 --B -1.36e-3
echo "(exit status $?: refused)"
set -e
tune status
