#!/usr/bin/env bash
# Core-engine throughput on the reference scenes (one core): particle-steps per second, median
# of repeated blocks after a warm-up that melts the initial lattice. Usage:
#   bench/core_throughput.sh [BUILD_DIR] [--quick]
# --quick runs tiny sizes (used by the test suite so the bench cannot rot).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
quick=${2:-}
b="$build/bench/bench_throughput"
if [[ $quick == --quick ]]; then
    "$b" docs/scenes/rfm-2d.ini --set system.N=300 --set system.L=0.08 --warmup-steps 50 --steps 50 --repeats 3 --label "2D quick"
    "$b" docs/scenes/rfm-1d.ini --set system.N=100 --warmup-steps 50 --steps 50 --repeats 3 --label "1D quick"
    exit 0
fi
warm2d=${WARM2D:-100000}
echo "# granule core throughput, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores; warm-up $warm2d steps (2D)"
"$b" docs/scenes/rfm-2d.ini --warmup-steps "$warm2d" --steps 2000 --repeats 7 --label "2D RFM eps 0.1/0.1"
"$b" docs/scenes/rfm-2d.ini --set model.eps_t=1 --warmup-steps "$warm2d" --steps 2000 --repeats 7 --label "2D RFM eps_n 0.1, eps_t 1"
"$b" docs/scenes/rfm-2d.ini --set integrator.skin=0 --warmup-steps "$warm2d" --steps 2000 --repeats 7 --label "2D RFM cell list every step"
"$b" docs/scenes/rfm-1d.ini --warmup-steps 1000000 --steps 100000 --repeats 7 --label "1D RFM eps 0.1"
