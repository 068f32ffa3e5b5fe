#!/usr/bin/env bash
# Soft-sphere throughput against N (2D at phi = 0.53, 1D at L' = N/1000 m so the density is that of
# the 1D RFM scene) and the cost of each effect on the 2D RFM scene, one core.
#   bench/scaling.sh [BUILD_DIR] [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
b="$build/bench/bench_throughput"
if [[ ${2:-} == --quick ]]; then
    "$b" docs/scenes/rfm-2d.ini --set system.N=500 --set system.packing_fraction=0.53 --warmup-steps 20 --steps 20 --repeats 3 --label "2D N=500"
    exit 0
fi
echo "# scaling with N, $(date -u +%Y-%m-%dT%H:%MZ)"
for n in 1000 10000 100000; do
    steps=$((20000000 / n)); warm=$((50000000 / n))
    "$b" docs/scenes/rfm-2d.ini --set system.N=$n --set system.packing_fraction=0.53 --warmup-steps $warm --steps $steps --repeats 5 --label "2D N=$n"
done
for n in 100 1000 10000; do
    steps=$((100000000 / n)); warm=$((100000000 / n))
    lp=$(python3 -c "print($n/1000)")
    "$b" docs/scenes/rfm-1d.ini --set system.N=$n --set system.reduced_length=$lp --warmup-steps $warm --steps $steps --repeats 5 --label "1D N=$n"
done
echo "# effects, 2D RFM N = 12000 (each line switches one effect on or off)"
common="--warmup-steps 20000 --steps 2000 --repeats 5"
"$b" docs/scenes/rfm-2d.ini --set noise.mode=none --set model.eps_n=1 --set model.tangential=none $common --label "elastic, no noise"
"$b" docs/scenes/rfm-2d.ini --set model.eps_n=1 --set model.tangential=none $common --label "+ noise"
"$b" docs/scenes/rfm-2d.ini --set model.tangential=none $common --label "+ normal dashpot"
"$b" docs/scenes/rfm-2d.ini $common --label "+ tangential dashpot"
"$b" docs/scenes/rfm-2d.ini --set model.tangential=sliding_friction $common --label "normal + friction"
"$b" docs/scenes/rfm-2d.ini --set model.clamp=true $common --label "clamped + tangential"
