#!/usr/bin/env bash
# Cost of a checkpoint against the cost of a step (docs/checkpoints.md, "Cost").
#
# usage: bench/checkpoint_cost.sh path/to/granule [N ...]     (default N: 12000 1000000)
# Runs the 2D RFM scene (docs/scenes/rfm-2d.ini, phi = 0.53) at each N for 20 steps per sample,
# 3 samples, a checkpoint after each of the first 3, and prints per N: checkpoint size, seconds
# per checkpoint, seconds per step, and their ratio. Set OMP_NUM_THREADS as for production runs.
set -euo pipefail
granule=${1:?usage: $0 path/to/granule [N ...]}
shift
sizes=("$@")
[[ $# -gt 0 ]] || sizes=(12000 1000000)
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/granule-ckpt-cost-XXXXXX")
trap 'rm -rf "$tmp"' EXIT
num() { grep -o "\"$1\":[[:space:]]*[-0-9.e+]*" "$2" | head -1 | sed 's/.*:[[:space:]]*//'; }
printf '%-9s %-12s %-16s %-14s %s\n' N bytes s/checkpoint s/step checkpoint/step
for n in "${sizes[@]}"; do
    L=$(awk -v n="$n" 'BEGIN { printf "%.6g", sqrt(n * 3.141592653589793 * 1.5e-3 * 1.5e-3 / 0.53) }')
    common=(--quiet --set system.N="$n" --set system.L="$L" --set run.warmup=0 --set run.sample_every=2e-5
            --set output.plots=false --set output.snapshot_every=0 --set analysis.observables=)
    # one run that stops (keeps its checkpoint, to measure its size) ...
    "$granule" run "$src/docs/scenes/rfm-2d.ini" --out "$tmp/keep$n" "${common[@]}" --set run.duration=1 \
        --set run.checkpoint_every=2e-5 --wall-limit 0.5 >/dev/null 2>&1 || true
    bytes=$(stat -c %s "$tmp/keep$n/checkpoint" 2>/dev/null || echo "?")
    # ... and one that writes 3 checkpoints in 60 steps
    "$granule" run "$src/docs/scenes/rfm-2d.ini" --out "$tmp/run$n" "${common[@]}" --set run.duration=6e-5 \
        --set run.checkpoint_every=2e-5 >/dev/null
    s=$tmp/run$n/summary.json
    awk -v n="$n" -v b="$bytes" -v c="$(num checkpoint_seconds "$s")" -v k="$(num checkpoints_written "$s")" \
        -v rate="$(num particle_steps_per_second "$s")" \
        'BEGIN { per = c / k; step = n / rate; printf "%-9d %-12s %-16.4g %-14.4g %.1f\n", n, b, per, step, per / step }'
done
