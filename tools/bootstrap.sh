#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# Install what zwidth needs on a Debian machine (idempotent; quiet when all is there).
#
# Each step of tools/test.sh needs a capability, not a command: "clang is on the PATH"
# does not mean libFuzzer links, and "arm-none-eabi-gcc exists" does not mean a Cortex-M
# image with newlib links.  So every capability is probed by doing the smallest real
# thing the step does (compile and link a one-line program, find a header, start a
# program), and the Debian packages that provide it are installed only when that fails.
# After installing, every probe runs again and a capability still missing stops here
# with its name, instead of failing minutes later inside a test step.
#
#   tools/bootstrap.sh            probe, install what is missing, verify
#   tools/bootstrap.sh --check    probe only; print what is missing (exit 1 if anything is)
#   tools/bootstrap.sh --demo     only what tools/demo.sh needs (C compiler, CMake, Ninja)
#   tools/bootstrap.sh --modbus-demo
#                                 only what tools/modbus_demo.sh needs (the demo's, plus
#                                 pkg-config, libmodbus and libcrypto; no .venv)
#
# Python: a virtualenv in .venv with tools/requirements-test.txt; the zwidth package itself
# is installed by tools/test.sh (pip install .).
# First run on a fresh Debian 12 machine: about 5 minutes (apt and pip downloads; Frama-C
# alone is 208 MB, 0.9 GB installed), then
# a few seconds (probes only).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=all
case "${1:-}" in
    "") ;;
    --check) mode=check ;;
    --demo) mode=demo ;;
    --modbus-demo) mode=modbus-demo ;;
    -h|--help) sed -n '2,/^[^#]/{/^#/p}' "$0" | grep -v 'SPDX-' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bootstrap.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
esac

PROBE_DIR=$(mktemp -d "${TMPDIR:-/tmp}/zw-probe.XXXXXX")
trap 'rm -rf "$PROBE_DIR"' EXIT
quiet() { "$@" >/dev/null 2>&1; }

# compile_and_link CC SOURCE_EXT FLAGS... : builds a one-line program read from stdin.
compile_and_link() {
    local cc=$1 ext=$2; shift 2
    local src="$PROBE_DIR/probe.$ext"
    cat >"$src"
    quiet "$cc" "$src" -o "$PROBE_DIR/probe.out" "$@"
}

probe_c() { printf '#include <math.h>\nint main(void){volatile double x=2;return sqrt(x)>1?0:1;}\n' \
    | compile_and_link cc c -std=c99 -lm; }
probe_cxx() { printf '#include <vector>\nint main(){std::vector<int> v(1);return v[0];}\n' \
    | compile_and_link c++ cpp; }
probe_cmake() { echo 'cmake_minimum_required(VERSION 3.18)' >"$PROBE_DIR/version.cmake"
    quiet cmake -P "$PROBE_DIR/version.cmake"; }
probe_ninja() { quiet ninja --version; }
probe_pkg_config() { quiet pkg-config --version; }
probe_sanitizers() { printf 'int main(void){return 0;}\n' \
    | compile_and_link cc c -fsanitize=address,undefined && "$PROBE_DIR/probe.out"; }
probe_tsan() { printf '#include <pthread.h>\nstatic void*f(void*p){return p;}\nint main(void){pthread_t t;pthread_create(&t,0,f,0);return pthread_join(t,0);}\n' \
    | compile_and_link cc c -fsanitize=thread -pthread && "$PROBE_DIR/probe.out"; }
probe_cmocka() { printf '#include <stdarg.h>\n#include <stddef.h>\n#include <stdint.h>\n#include <setjmp.h>\n#include <cmocka.h>\nstatic void t(void **s){(void)s;assert_true(1);}\nint main(void){const struct CMUnitTest ts[]={cmocka_unit_test(t)};return cmocka_run_group_tests(ts,0,0);}\n' \
    | compile_and_link cc c -lcmocka; }
probe_modbus() { printf '#include <modbus.h>\nint main(void){modbus_t*c=modbus_new_tcp("127.0.0.1",1502);if(c)modbus_free(c);return 0;}\n' \
    | compile_and_link cc c $(pkg-config --cflags --libs libmodbus 2>/dev/null || echo -I/usr/include/modbus -lmodbus); }
probe_libcrypto() { printf '#include <openssl/hmac.h>\n#include <openssl/evp.h>\nint main(void){unsigned char m[32];unsigned n=0;return HMAC(EVP_sha256(),"k",1,(const unsigned char*)"m",1,m,&n)&&n==32?0:1;}\n' \
    | compile_and_link cc c $(pkg-config --cflags --libs libcrypto 2>/dev/null || echo -lcrypto) && "$PROBE_DIR/probe.out"; }
probe_arm() { printf '#include <math.h>\nvolatile float x=2.0f;int main(void){return sqrtf(x)>1.0f?0:1;}\n' \
    | compile_and_link arm-none-eabi-gcc c -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard \
        --specs=nano.specs --specs=nosys.specs -Wl,--gc-sections -lm; }
probe_avr() { printf '#include <math.h>\n#include <stdint.h>\nvolatile float x = 2.0f;\nint main(void){return (sizeof(int) == 2u && sqrtf(x) > 1.0f) ? 0 : 1;}\n' \
    | compile_and_link avr-gcc c -mmcu=atmega2560 -std=c99 -Os -lm; }
probe_qemu_m4() { qemu-system-arm -machine help 2>/dev/null | grep -q '^mps2-an386'; }
probe_valgrind() { quiet valgrind --tool=callgrind --callgrind-out-file=/dev/null true; }
probe_fuzzer() { printf '#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t*d,size_t n){(void)d;(void)n;return 0;}\n' \
    | compile_and_link clang c -fsanitize=fuzzer,address,undefined; }
probe_socat() { quiet socat -V; }
probe_mbpoll() { mbpoll -h 2>&1 | grep -qi modbus; }
probe_cppcheck_misra() { printf 'int main(void){int x = 0; goto done; done: return x;}\n' >"$PROBE_DIR/misra.c"
    local log; log=$(cppcheck -q --addon=misra --template='{id}' "$PROBE_DIR/misra.c" 2>&1) &&
        grep -q 'misra-c2012-15\.1' <<<"$log"; }
probe_frama_c_eva() { printf 'int main(void){volatile int v = 0; int a[2] = {0, 0}; return a[v];}\n' >"$PROBE_DIR/eva.c"
    local log; log=$(frama-c -eva "$PROBE_DIR/eva.c" 2>&1) && grep -q '^\[eva:alarm\]' <<<"$log"; }
probe_python_venv() { quiet python3 -c 'import venv, ensurepip'; }
probe_python_headers() { quiet python3 -c 'import os, sysconfig; assert os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h"))'; }

# The capabilities, the Debian packages that give each, and which demo modes need it
# (demo: tools/demo.sh, mbdemo: tools/modbus_demo.sh; every capability is needed by the
# full mode).
#        name           probe               packages                                  demos
caps=(
    "C99 compiler + libm|probe_c|gcc libc6-dev|demo mbdemo"
    "C++ compiler|probe_cxx|g++|"
    "CMake >= 3.18|probe_cmake|cmake|demo mbdemo"
    "Ninja|probe_ninja|ninja-build|demo mbdemo"
    "pkg-config|probe_pkg_config|pkg-config|mbdemo"
    "gcc ASan/UBSan runtime|probe_sanitizers|libasan8 libubsan1|"
    "gcc ThreadSanitizer runtime|probe_tsan|libtsan2|"
    "cmocka (C unit tests)|probe_cmocka|libcmocka-dev|"
    "libmodbus (drive, tuning tool)|probe_modbus|libmodbus-dev|mbdemo"
    "OpenSSL libcrypto HMAC-SHA256 (commissioning key)|probe_libcrypto|libssl-dev|mbdemo"
    "Cortex-M cross link with newlib (footprint, QEMU)|probe_arm|gcc-arm-none-eabi libnewlib-arm-none-eabi|"
    "QEMU mps2-an386 (Cortex-M4 benchmark)|probe_qemu_m4|qemu-system-arm|"
    "avr-gcc + avr-libc (16-bit-int build, tools/avr_build.sh)|probe_avr|gcc-avr avr-libc|"
    "valgrind callgrind (instruction counts)|probe_valgrind|valgrind|"
    "clang libFuzzer + ASan/UBSan (fuzzing)|probe_fuzzer|clang|"
    "socat (RTU over a pseudo-terminal)|probe_socat|socat|"
    "mbpoll (an independent Modbus client)|probe_mbpoll|mbpoll|"
    "cppcheck MISRA C:2012 addon (tools/misra.sh)|probe_cppcheck_misra|cppcheck|"
    "Frama-C Eva (tools/eva.sh; about 210 MB download, 0.9 GB installed)|probe_frama_c_eva|frama-c-base|"
    "python3 venv + ensurepip|probe_python_venv|python3-venv|"
    "Python.h of python3 (the extension)|probe_python_headers|python3-dev|"
)

missing_names=()
missing_pkgs=()
probe_all() {
    missing_names=(); missing_pkgs=()
    local entry name probe pkgs demo
    for entry in "${caps[@]}"; do
        IFS='|' read -r name probe pkgs demo <<<"$entry"
        case "$mode" in  # a demo mode probes only what that demo needs
            demo) [[ " $demo " == *" demo "* ]] || continue ;;
            modbus-demo) [[ " $demo " == *" mbdemo "* ]] || continue ;;
        esac
        if ! "$probe"; then
            missing_names+=("$name")
            # libFuzzer's runtime is a separate package named after clang's major version
            # (libclang-rt-14-dev on Debian 12); clang itself does not pull it in.
            if [ "$probe" = probe_fuzzer ] && command -v clang >/dev/null 2>&1; then
                pkgs="libclang-rt-$(clang -dumpversion | cut -d. -f1)-dev"
            fi
            missing_pkgs+=($pkgs)
        fi
    done
}

apt_install() {
    local SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    echo "bootstrap: installing $*" >&2
    if [ -z "${ZW_APT_UPDATED:-}" ]; then
        $SUDO apt-get update -qq
        ZW_APT_UPDATED=1
    fi
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

probe_all
if [ ${#missing_names[@]} -gt 0 ]; then
    printf 'bootstrap: missing: %s\n' "${missing_names[@]}" >&2
    [ "$mode" = check ] && exit 1
    apt_install "${missing_pkgs[@]}"
    # A second round for what only the first install can name (libclang-rt-N-dev).
    probe_all
    [ ${#missing_names[@]} -gt 0 ] && apt_install "${missing_pkgs[@]}"
    probe_all
    if [ ${#missing_names[@]} -gt 0 ]; then
        printf 'bootstrap: still missing after installing: %s\n' "${missing_names[@]}" >&2
        exit 1
    fi
fi
[ "$mode" = all ] || exit 0

if [ ! -x .venv/bin/python ]; then
    echo "bootstrap: creating .venv" >&2
    python3 -m venv .venv
fi
if ! .venv/bin/python -c 'import mpmath, numpy, pytest, xdist, pymodbus, hypothesis, mypy, matplotlib, scipy, control, pybind11, scikit_build_core, pint, tqdm, reuse, build, twine' >/dev/null 2>&1; then
    echo "bootstrap: installing Python test requirements into .venv" >&2
    .venv/bin/python -m pip install -q --disable-pip-version-check -r tools/requirements-test.txt
fi
