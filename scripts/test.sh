#!/usr/bin/env bash
# Run the whole test suite: once in the release build, once under AddressSanitizer + UBSan.
# Expects scripts/setup.sh to have run. Ends with one line "N passed, M failed".
set -uo pipefail
cd "$(dirname "$0")/.."

# two tests run at once on a 2-core machine, each with OpenMP threads: spinning threads of one
# test only steal the other's core (runs are bit-identical whatever the wait policy)
export OMP_WAIT_POLICY=passive

passed=0
failed=0
tally() { # meson's summary lines "Ok: N" and "Fail: N" (+ timeouts) of one run
    local log=$1
    passed=$((passed + $(awk '/^Ok:/ {print $2}' "$log")))
    failed=$((failed + $(awk '/^(Fail|Timeout|Unexpected Pass):/ {s += $NF} END {print s + 0}' "$log")))
}

echo "== release build: tests" >&2
log=$(mktemp)
meson test -C build --print-errorlogs | tee "$log"
rc_release=${PIPESTATUS[0]}
tally "$log"

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build: tests" >&2
if [[ ! -f build-asan/build.ninja ]]; then
    meson setup build-asan --buildtype=debug -Doptimization=1 -Db_sanitize=address,undefined \
        -Db_lundef=false >/dev/null || exit 1
fi
ninja -C build-asan >/dev/null || exit 1
# every test but those of tests/sanitizer-skip.txt, whose every line of granule's code the others
# run (scripts/sanitizer_coverage.py); they run in the release pass above
mapfile -t asan_tests < <(meson test -C build-asan --list --no-rebuild 2>/dev/null |
    grep -vxF -f <(grep -v '^#' tests/sanitizer-skip.txt))
[[ ${#asan_tests[@]} -gt 0 ]] || { echo "no sanitizer tests listed" >&2; exit 1; }
UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=1 GRANULE_TEST_QUICK=1 \
    meson test -C build-asan --no-rebuild --print-errorlogs --timeout-multiplier 3 "${asan_tests[@]}" |
    tee "$log"
rc_asan=${PIPESTATUS[0]}
tally "$log"
rm -f "$log"

echo "$passed passed, $failed failed"
[[ $rc_release -eq 0 && $rc_asan -eq 0 && $failed -eq 0 ]]
