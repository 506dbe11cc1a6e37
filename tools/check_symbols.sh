#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# The float build must export every function as zw_name_f (csrc/include/zwidth/precision.h)
# so that an object built for one precision cannot link against the other library.
#   1. every global symbol defined in the float libraries ends in _f,
#   2. the double libraries define the same names without the suffix,
#   3. every function declared in a public header has its line in precision.h
#      (catches a new function before it has a body).
# Usage: tools/check_symbols.sh NM LIBZWIDTH_D LIBZWIDTH_F LIBZWIDTH_SIM_D LIBZWIDTH_SIM_F
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
NM=$1
defined() {  # global symbols defined in the archives (compiler-generated __* names aside)
    "$NM" -g --defined-only "$@" | awk 'NF == 3 && $3 !~ /^__/ { print $3 }' | sort -u
}
status=0
bad=$(defined "$3" "$5" | grep -v '_f$' || true)
if [ -n "$bad" ]; then
    echo "FAIL: float-library symbols without _f (add them to csrc/include/zwidth/precision.h):" $bad
    status=1
fi
diff <(defined "$2" "$4") <(defined "$3" "$5" | sed 's/_f$//' | sort) >/dev/null || {
    echo "FAIL: the double and float libraries define different functions:"
    diff <(defined "$2" "$4") <(defined "$3" "$5" | sed 's/_f$//' | sort) || true
    status=1
}
declared=$(grep -oh '\bzw_[a-z0-9_]*(' csrc/include/zwidth/*.h | tr -d '(' | sort -u)
for f in $declared; do
    grep -q "^#define $f ${f}_f\$" csrc/include/zwidth/precision.h ||
        { echo "FAIL: $f is declared but not renamed in csrc/include/zwidth/precision.h"; status=1; }
done
[ $status = 0 ] && echo "symbols ok: $(defined "$3" "$5" | wc -l) float functions, all *_f;" \
    "$(echo "$declared" | wc -w) declared functions mapped"
exit $status
