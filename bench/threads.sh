#!/usr/bin/env bash
# OpenMP speed-up of the soft-sphere core: particle-steps per second at 1 and 2 threads (and at
# $THREADS_MAX if set) for the 2D RFM scene (N = 12000, phi = 0.53, eps_n = eps_t = 0.1) and at
# N = 1e5 and 1e6 (same phi, short runs), plus the 1D RFM scene (runs on one thread whatever
# OMP_NUM_THREADS says). The trajectory is bit-identical for every thread count
# (tests/test_threads.c), so only the speed is compared. Usage:
#   bench/threads.sh [BUILD_DIR] [--quick]
# --quick runs tiny sizes (used by the test suite so the bench cannot rot). Run on a quiet
# machine: with other processes on the cores, threads wait for each other at every step.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
quick=${2:-}
b="$build/bench/bench_throughput"
threads="1 2 ${THREADS_MAX:-}"
# one scene at each thread count; prints the bench lines and the speed-up of each over 1 thread
run() {
    local label=$1
    shift
    local base=""
    for t in $threads; do
        line=$(OMP_NUM_THREADS=$t OMP_PROC_BIND=${OMP_PROC_BIND:-close} "$b" "$@" --label "$label T=$t")
        rate=$(sed -n 's/.* median \([0-9.e+-]*\) .*/\1/p' <<<"$line")
        base=${base:-$rate}
        echo "$line"
        awk -v r="$rate" -v b0="$base" -v t="$t" -v l="$label" 'BEGIN { printf "# %s: %d threads %.3g particle-steps/s, speed-up %.2f\n", l, t, r, r / b0 }'
    done
}
if [[ $quick == --quick ]]; then
    run "2D quick" docs/scenes/rfm-2d.ini --set system.N=2500 --set system.packing_fraction=0.53 --warmup-steps 20 --steps 20 --repeats 3
    exit 0
fi
echo "# granule threads, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, OMP_PROC_BIND=${OMP_PROC_BIND:-close}"
run "2D RFM N=12000" docs/scenes/rfm-2d.ini --warmup-steps "${WARM2D:-100000}" --steps 2000 --repeats 7
run "2D N=1e5" docs/scenes/rfm-2d.ini --set system.N=100000 --set system.packing_fraction=0.53 --warmup-steps 2000 --steps 300 --repeats 5
run "2D N=1e6" docs/scenes/rfm-2d.ini --set system.N=1000000 --set system.packing_fraction=0.53 --warmup-steps 300 --steps 50 --repeats 3
run "1D RFM N=1000" docs/scenes/rfm-1d.ini --warmup-steps 1000000 --steps 100000 --repeats 7
