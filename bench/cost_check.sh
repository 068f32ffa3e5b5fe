#!/usr/bin/env bash
# `granule cost` against real runs (docs/performance.md, "What accuracy costs"): for each scene,
# the recommended time step and predicted wall time for a tolerance, then the scene run at that dt;
# prints predicted +- error, the real wall time and their ratio. Run it on a quiet machine.
#
#   bench/cost_check.sh [BUILD_DIR] [--quick]
#
# COST_SCENES (default "rfm-1d rfm-2d"), COST_TOLERANCE (default 1%), COST_CALIBRATE (wall s,
# default 10), COST_DURATION (simulated s of the real run, default the scene's warm-up + duration
# cut to 1 s in 2D). --quick: a small 1D scene, short runs (the test suite runs this).
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
build_and_quick "bench/cost_check.sh [BUILD_DIR] [--quick]" "$@"
granule="$build/granule"
require_built cost_check "$granule"
bench_outputs "$quick" cost
work=$(mktemp -d /tmp/granule-cost-check.XXXXXX)
trap 'rm -rf "$work"; [[ $quick == true ]] && rm -rf "$out"' EXIT
export OMP_NUM_THREADS=1
tol=${COST_TOLERANCE:-1%}
if $quick; then
    scenes=(rfm-1d); calib=0.5
    sets=(--set system.N=200 --set system.reduced_length=0.2 --set run.warmup=0.05 --set run.duration=0.2)
else
    read -r -a scenes <<<"${COST_SCENES:-rfm-1d rfm-2d}"; calib=${COST_CALIBRATE:-10}
    sets=()
fi
sets+=(--set output.plots=false --set output.snapshot_every=0 --set run.progress=false)
bench_header
echo "| scene | tolerance | integrator | dt (s) | steps per contact | predicted wall (s) | real wall (s) | real / predicted |"
echo "|---|---|---|---|---|---|---|---|"
for s in "${scenes[@]}"; do
    scene=docs/scenes/$s.ini
    extra=()
    [[ $quick == false && $s == rfm-2d ]] && extra=(--set run.warmup=0.1 --set run.duration=${COST_DURATION:-0.9})
    "$granule" cost "$scene" --tolerance "$tol" --calibrate "$calib" "${sets[@]}" "${extra[@]}" --out "$work/$s" >"$work/$s.txt" 2>&1 ||
        { echo "cost_check: $s: granule cost found no time step: $(tail -n 3 "$work/$s.txt")" >&2; continue; }
    read -r dt spc pred perr kind window < <(/usr/bin/python3 -c "
import json, sys; r = json.load(open('$work/$s/cost.json'))['recommended']
print(r['dt'], r['steps_per_contact'], r['predicted_wall'], r['predicted_wall_err'], r.get('integrator', 'verlet'),
      r.get('window') or 0)")
    how=(--set integrator.kind="$kind")
    [[ $kind == hybrid ]] && how+=(--set integrator.kick_interval="$window")
    t0=$(date +%s.%N)
    "$granule" run "$scene" "${sets[@]}" "${extra[@]}" "${how[@]}" --set integrator.dt="$dt" --set integrator.force_dt=true \
        --out "$work/$s-run" >"$work/$s-run.log" 2>&1
    t1=$(date +%s.%N)
    label=$kind
    [[ $kind == hybrid ]] && label="hybrid, window $(printf '%.3g' "$window") s"
    python3 -c "
dt, spc, pred, perr, real = $dt, $spc, $pred, $perr, $t1 - $t0
print(f'| $s | $tol | $label | {dt:.4g} | {spc:.3g} | {pred:.3g} +- {perr:.2g} | {real:.3g} | {real / pred:.3f} |')"
done | tee "$out/cost-check.md"
