#!/usr/bin/env bash
# The ceiling of per-particle (asynchronous) hybrid windows (issue 17's route), measured rather than
# built: runs the hybrid (window 3e-5 s, seed 1) on the 1D RFM scene at eps = 0.1, 0.5 and 0.9 (N = 1000,
# 1 s) and the 2D steady-state scene (N = 2000, 0.5 s), writes three snapshots after the warm-up and
# prints, per scene, the fraction of today's per-free-particle work that per-particle windows would
# still do (bench/hybrid_horizons.py: each free particle touched only when its own horizon runs out,
# an oracle that ignores the schedule's bookkeeping). Combined with the profile's share of that work
# it bounds the route's gain: docs/hybrid.md, "Per-particle windows: the ceiling". Usage:
#   bench/hybrid_horizons.sh BUILD [--quick]
# --quick runs tiny sizes (the test suite's smoke test; says so). Counts, not timings: it may run on
# a loaded machine.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: hybrid_horizons.sh BUILD [--quick]}
[[ -x $build/granule ]] || { echo "hybrid_horizons.sh: $build/granule not found (build it first)" >&2; exit 2; }
quick=false
[[ ${2:-} == --quick ]] && quick=true
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
common=(--force --quiet --set output.plots=false --set run.seed=1 --set integrator.kind=hybrid
        --set integrator.kick_interval=3e-5 --set output.trajectory=snapshots)
if $quick; then
    echo "# quick smoke test: tiny sizes, the numbers are not measurements"
    one=(--set system.N=100 --set system.reduced_length=0.1 --set run.warmup=0.003 --set run.duration=0.003
         --set output.snapshot_every=0.001)
    two=(--set system.N=200 --set system.L=0.06 --set placement.kind=random --set run.warmup=0.002
         --set run.duration=0.003 --set output.snapshot_every=0.001)
else
    one=(--set run.warmup=1 --set run.duration=0.03 --set output.snapshot_every=0.01)
    two=(--set run.warmup=0.5 --set run.duration=0.03 --set output.snapshot_every=0.01)
fi
echo "# $(date -u +%FT%TZ) $(uname -n), $("$build/granule" --version)"
for e in 0.1 0.5 0.9; do
    echo "## 1D RFM, eps = $e"
    "$build/granule" run docs/scenes/rfm-1d.ini --out "$tmp/1d-$e" "${common[@]}" "${one[@]}" --set model.eps_n=$e
    /usr/bin/python3 bench/hybrid_horizons.py "$tmp/1d-$e/snapshots" 3e-5 1e-8
done
echo "## 2D steady-state scene"
"$build/granule" run docs/scenes/steady-2d.ini --out "$tmp/2d" "${common[@]}" "${two[@]}"
/usr/bin/python3 bench/hybrid_horizons.py "$tmp/2d/snapshots" 3e-5 1e-8
