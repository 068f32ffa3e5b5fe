#!/usr/bin/env bash
# Build granule's libFuzzer targets (clang, ASan + UBSan) and fuzz them (docs/fuzzing.md).
#   scripts/fuzz.sh [--quick | --replay | --time SECONDS] [--build DIR] [TARGET ...]
#     --quick      each target ~4 s from the committed corpus (CI; total < 20 s); fails on any
#                  crash, hang (> 30 s per input), leak or sanitizer report
#     --replay     run every committed corpus input once (regression check, a few seconds)
#     --time S     fuzz each target for S seconds (a campaign; new inputs go to DIR/corpus-TARGET)
#   TARGET: scene, sweep, campaign, checkpoint (default: every target that was built).
# Exit 0 clean, 1 a finding (the crashing input is saved as DIR/crash-TARGET-*), 77 no clang
# with libFuzzer (skipped). One core, nice 19: it never starves other work.
set -euo pipefail
src="$(cd "$(dirname "$0")/.." && pwd)"
mode=quick seconds=4 build="${GRANULE_FUZZ_BUILD:-$src/build-fuzz}" targets=()
while (($#)); do
    case "$1" in
        --quick) mode=quick seconds=4 ;;
        --replay) mode=replay ;;
        --time) mode=time seconds="$2"; shift ;;
        --build) build="$2"; shift ;;
        -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
        -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
        *) targets+=("$1") ;;
    esac
    shift
done
if [[ "${GRANULE_TEST_QUICK:-0}" == 1 && "$mode" == quick ]]; then
    # the suite's sanitizer pass: the release pass already built and ran the fuzz targets
    echo "fuzz.sh: GRANULE_TEST_QUICK=1: skipped (the release test pass runs it)" >&2
    exit 77
fi

# clang with libFuzzer's runtime (Debian: clang + libclang-rt-dev)?
probe="$(mktemp -d)"
trap 'rm -rf "$probe"' EXIT
echo 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { return 0; }' > "$probe/p.c"
if ! command -v clang >/dev/null || ! clang -fsanitize=fuzzer,address,undefined "$probe/p.c" -o "$probe/p" 2>/dev/null; then
    echo "fuzz.sh: clang with libFuzzer not found (apt-get install clang libclang-rt-dev); skipped" >&2
    exit 77
fi

# a fuzzing campaign (--time) wants fast executions (-O2); the suite's --quick and --replay want a
# fast build: -O0 compiles the instrumented library 4x faster (39 against 152 CPU s, the kernels'
# many instantiations) and 10 s of fuzzing still runs thousands of inputs per target
buildtype=debug
[[ $mode == time ]] && buildtype=debugoptimized
if [[ ! -f "$build/build.ninja" ]]; then
    if ! CC=clang nice -n 19 meson setup "$build" "$src" -Dfuzz=true -Dnative=false -Dtests=disabled \
        -Dbuildtype=$buildtype -Db_sanitize=address,undefined -Db_lundef=false >"$probe/setup.log" 2>&1; then
        tail -20 "$probe/setup.log" >&2
        echo "fuzz.sh: meson setup of $build failed" >&2
        exit 1
    fi
fi
# only the fuzz targets (and the library they link), not the CLI, benches or Python module
fuzz_exes=$(ninja -C "$build" -t targets all 2>/dev/null | grep -oE '^tests/fuzz/fuzz_[a-z]+' | sort -u)
if ! nice -n 19 ninja -C "$build" ${fuzz_exes} >"$probe/ninja.log" 2>&1; then
    grep -E 'error|FAILED' "$probe/ninja.log" | head -20 >&2
    echo "fuzz.sh: build of the fuzz targets in $build failed" >&2
    exit 1
fi
if ((${#targets[@]} == 0)); then
    for t in scene sweep campaign checkpoint; do
        [[ -x "$build/tests/fuzz/fuzz_$t" ]] && targets+=("$t")
    done
fi

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
status=0
for t in "${targets[@]}"; do
    exe="$build/tests/fuzz/fuzz_$t" corpus="$src/tests/fuzz/corpus/$t" dict="$src/tests/fuzz/$t.dict"
    # the example files are seeds too, so new ones are fuzzed without copying them
    extra=()
    [[ $t == scene ]] && extra=("$src/docs/scenes")
    [[ $t == sweep ]] && extra=("$src/docs/sweeps")
    [[ $t == campaign ]] && extra=("$src/docs/campaigns")
    [[ -x "$exe" ]] || { echo "fuzz.sh: $t: not built (see tests/fuzz/meson.build)" >&2; status=1; continue; }
    opts=(-timeout=30 -rss_limit_mb=1024 -malloc_limit_mb=512 -artifact_prefix="$build/crash-$t-" -print_final_stats=1)
    [[ -f "$dict" ]] && opts+=(-dict="$dict")
    log="$build/fuzz-$t.log"
    if [[ "$mode" == replay ]]; then
        shopt -s nullglob; files=("$corpus"/*); for d in "${extra[@]}"; do files+=("$d"/*.ini); done; shopt -u nullglob
        ((${#files[@]})) || { echo "fuzz.sh: $t: no corpus inputs in $corpus" >&2; continue; }
        if nice -n 19 "$exe" "${opts[@]}" -runs=1 "${files[@]}" >"$log" 2>&1; then
            echo "fuzz.sh: $t: replayed ${#files[@]} corpus inputs: clean" >&2
        else
            status=1
            tail -40 "$log" >&2
            echo "fuzz.sh: $t: replayed ${#files[@]} corpus inputs: FAILED" >&2
        fi
        continue
    fi
    work="$build/corpus-$t"
    mkdir -p "$work"
    # new inputs go to the work folder; the committed corpus is read only
    if nice -n 19 "$exe" "${opts[@]}" -max_total_time="$seconds" "$work" "$corpus" "${extra[@]}" >"$log" 2>&1; then
        echo "fuzz.sh: $t: $(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | awk '{print $2}') executions in ${seconds} s, clean" >&2
    else
        status=1
        tail -60 "$log" >&2
        echo "fuzz.sh: $t: FINDING; input saved as $(ls "$build"/crash-"$t"-* 2>/dev/null | head -3 | tr '\n' ' ')" >&2
    fi
done
exit $status
