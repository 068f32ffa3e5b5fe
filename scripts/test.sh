#!/usr/bin/env bash
# Run the whole test suite: once in the release build, once under AddressSanitizer + UBSan.
# Expects scripts/setup.sh to have run.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== release build: tests" >&2
meson test -C build --print-errorlogs

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build: tests" >&2
if [[ ! -f build-asan/build.ninja ]]; then
    meson setup build-asan --buildtype=debug -Doptimization=1 -Db_sanitize=address,undefined \
        -Db_lundef=false >/dev/null
fi
ninja -C build-asan >/dev/null
UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=1 GRANULE_TEST_QUICK=1 \
    meson test -C build-asan --print-errorlogs --timeout-multiplier 3
