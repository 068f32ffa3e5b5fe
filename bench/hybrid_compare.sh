#!/usr/bin/env bash
# The hybrid integrator of two builds against Verlet, interleaved in one run: CPU seconds of whole
# `granule run`s (warm-up from the scene's start included), window 3e-5 s, seed 1, one core, on
# the 1D RFM scene at eps = 0.1, 0.5 and 0.9 (N = 1000, 1 s + 2 s) and the 2D steady-state scene
# (N = 2000, 0.5 s + 2 s). Usage:
#   bench/hybrid_compare.sh OLD_BUILD NEW_BUILD [--quick] [ROUNDS]
# A line per run (label, CPU seconds, T, active fraction, rollbacks), then per scene the median
# over the rounds of each build's Verlet / its own hybrid (the issue's speed-up, before and after),
# and new / old for the hybrid and for Verlet.
# --quick runs tiny sizes (the test suite's smoke test; says so). docs/hybrid.md, "Cheaper windows".
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: hybrid_compare.sh OLD_BUILD NEW_BUILD [--quick] [ROUNDS]}
new=${2:?usage: hybrid_compare.sh OLD_BUILD NEW_BUILD [--quick] [ROUNDS]}
quick=false
rounds=2
for a in "${@:3}"; do
    if [[ $a == --quick ]]; then quick=true; rounds=1; else rounds=$a; fi
done
for b in "$old" "$new"; do
    [[ -x $b/granule ]] || { echo "hybrid_compare.sh: $b/granule not found (build it first)" >&2; exit 2; }
done
export OMP_NUM_THREADS=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
common=(--force --set output.plots=false --set output.snapshot_every=0 --set run.progress=false --set run.seed=1)
if $quick; then
    echo "# quick smoke test: tiny sizes, the numbers are not benchmarks"
    one=(--set system.N=100 --set system.reduced_length=0.1 --set run.warmup=0.002 --set run.duration=0.004)
    two=(--set system.N=200 --set system.L=0.06 --set placement.kind=random --set run.warmup=0.001 --set run.duration=0.002)
else
    one=(--set run.warmup=1 --set run.duration=2)
    two=(--set run.warmup=0.5 --set run.duration=2)
fi
hy=(--set integrator.kind=hybrid --set integrator.kick_interval=3e-5)
echo "# $(date -u +%FT%TZ) $(uname -n), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# old: $("$old/granule" --version) new: $("$new/granule" --version)"
run() { # label build scene args...: one line "label cpu_seconds T active rollbacks"
    local label=$1 b=$2 scene=$3
    shift 3
    local TIMEFORMAT='%3U'
    local cpu
    cpu=$({ time "$b/granule" run "$scene" --out "$tmp/$label" "${common[@]}" "$@" >/dev/null 2>"$tmp/$label.err"; } 2>&1) ||
        { cat "$tmp/$label.err" >&2; return 1; }
    /usr/bin/python3 - "$tmp/$label/summary.json" "$label" "$cpu" <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); h = j.get("hybrid") or {}
print(f"{sys.argv[2]:<14} {float(sys.argv[3]):8.2f} s  T {j['T_mean']:.5g}  active {h.get('active_fraction', 1.0):.3f}  rollbacks {h.get('rollbacks', 0)}")
PY
}
for r in $(seq "$rounds"); do
    for e in 0.1 0.5 0.9; do
        s1=(docs/scenes/rfm-1d.ini "${one[@]}" --set model.eps_n=$e)
        run "verlet-1d-$e" "$new" "${s1[@]}"
        run "oldverlet-1d-$e" "$old" "${s1[@]}"
        run "old-1d-$e" "$old" "${s1[@]}" "${hy[@]}"
        run "new-1d-$e" "$new" "${s1[@]}" "${hy[@]}"
    done
    s2=(docs/scenes/steady-2d.ini "${two[@]}")
    run verlet-2d "$new" "${s2[@]}"
    run oldverlet-2d "$old" "${s2[@]}"
    run old-2d "$old" "${s2[@]}" "${hy[@]}"
    run new-2d "$new" "${s2[@]}" "${hy[@]}"
done | tee "$tmp/lines"
/usr/bin/python3 - "$tmp/lines" <<'PY'
import sys, statistics as st
t = {}
for line in open(sys.argv[1]):
    label, cpu = line.split()[:2]
    t.setdefault(label, []).append(float(cpu))
print("scene      old: Verlet/hybrid  new: Verlet/hybrid  hybrid new/old  Verlet new/old (medians over rounds)")
for sc in ("1d-0.1", "1d-0.5", "1d-0.9", "2d"):
    v, ov, o, n = t[f"verlet-{sc}"], t[f"oldverlet-{sc}"], t[f"old-{sc}"], t[f"new-{sc}"]
    r = lambda a, b: st.median(x / max(y, 1e-3) for x, y in zip(a, b))
    print(f"{sc:<10} {r(ov, o):18.2f}x {r(v, n):18.2f}x {r(o, n):14.2f}x {r(ov, v):14.2f}x")
PY
