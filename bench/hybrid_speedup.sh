#!/usr/bin/env bash
# Hybrid integrator against soft-sphere Verlet (docs/hybrid.md): wall seconds per simulated
# second, speed-up, and the accuracy of the time-averaged temperature T (2.19) and, in 1D, of the
# reduced-gap moment <R^2>/<R>^2 (3.18), with block-averaging errors; plus the hybrid's active
# fraction and rollbacks. One core (OMP_NUM_THREADS=1 unless set). Usage:
#   bench/hybrid_speedup.sh [BUILD_DIR] [--quick]
# Environment: WARMUP, DURATION (1D, s; default 1 and 4), WARMUP2D, DURATION2D (default 0.5 and 2),
# WINDOWS (1D kick_interval list), WINDOWS2D, SEED. --quick runs tiny systems for a few ms (the
# test suite runs it so the script cannot rot).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
quick=${2:-}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
g="$build/granule"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
seed=${SEED:-1}
if [[ $quick == --quick ]]; then
    one=(--set system.N=100 --set system.reduced_length=0.1)
    two=(--set system.N=200 --set system.L=0.06 --set placement.kind=random)
    w1=0.002; d1=0.004; w2=0.001; d2=0.002; windows="1e-5 3e-5"; windows2d="1e-5"
else
    one=(); two=()
    w1=${WARMUP:-1}; d1=${DURATION:-4}; w2=${WARMUP2D:-0.5}; d2=${DURATION2D:-2}
    windows=${WINDOWS:-"1e-5 3e-5 1e-4 3e-4"}; windows2d=${WINDOWS2D:-"1e-5 3e-5 1e-4"}
fi

run() { # label scene warmup duration [extra args...]; CPU seconds (user, sys) into $tmp/label.cpu
    local label=$1 scene=$2 warm=$3 dur=$4
    shift 4
    local TIMEFORMAT='%3U %3S'
    { time "$g" run "$scene" --out "$tmp/$label" --force --set run.warmup="$warm" --set run.duration="$dur" \
        --set run.seed="$seed" --set output.plots=false --set output.snapshot_every=0 --set run.progress=false "$@" \
        >/dev/null 2>"$tmp/$label.err"; } 2>"$tmp/$label.cpu" || { cat "$tmp/$label.err" >&2; return 1; }
}

table() { # dir of runs, reference label
    python3 - "$tmp" "$@" <<'PY'
import json, sys, os
d, ref, labels = sys.argv[1], sys.argv[2], sys.argv[3:]
def get(l):
    j = json.load(open(os.path.join(d, l, "summary.json")))
    u, s_ = (float(v) for v in open(os.path.join(d, l + ".cpu")).read().split())
    r = {"wall": j["wall_seconds"] / j["simulated_seconds"], "cpu": (u + s_) / j["simulated_seconds"], "T": j["T_mean"], "eT": j["T_stderr"] or float("nan"),
         "res": j["ledger"]["relative_residual"], "hy": j.get("hybrid")}
    g = j.get("analysis", {}).get("gaps")
    if g:
        e = g["moments_stderr"][1]
        r["R2"], r["eR2"] = g["moments_reduced"][1], (e if e is not None else float("nan")) / g["mean_separation"] ** 2
    return r
base = get(ref)
print(f"{'run':<22} {'wall s/sim s':>12} {'speed-up':>8} {'cpu s/sim s':>11} {'speed-up':>8} {'T':>10} {'+-':>8} {'dT/T %':>7} {'z':>5}"
      f" {'<R2>/<R>2':>10} {'+-':>7} {'dR2 %':>6} {'z':>5} {'active':>7} {'rollbk':>6} {'ledger':>9}")
for l in [ref] + labels:
    r = get(l)
    zT = (r["T"] - base["T"]) / max((r["eT"] ** 2 + base["eT"] ** 2) ** 0.5, 1e-300)
    line = (f"{l:<22} {r['wall']:12.3f} {base['wall'] / r['wall']:8.2f} {r['cpu']:11.3f} {base['cpu'] / r['cpu']:8.2f} {r['T']:10.5g} {r['eT']:8.2g}"
            f" {100 * (r['T'] / base['T'] - 1):7.2f} {zT if l != ref else 0:5.1f}")
    if "R2" in r:
        zR = (r["R2"] - base["R2"]) / max((r["eR2"] ** 2 + base["eR2"] ** 2) ** 0.5, 1e-300)
        line += f" {r['R2']:10.4g} {r['eR2']:7.2g} {100 * (r['R2'] / base['R2'] - 1):6.2f} {zR if l != ref else 0:5.1f}"
    else:
        line += f" {'-':>10} {'-':>7} {'-':>6} {'-':>5}"
    hy = r["hy"]
    line += f" {hy['active_fraction'] if hy else 1:7.3f} {hy['rollbacks'] if hy else 0:6d} {r['res']:9.2e}"
    print(line)
PY
}

echo "# hybrid vs Verlet, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, OMP_NUM_THREADS=$OMP_NUM_THREADS, seed $seed"
echo "# 1D RFM (docs/scenes/rfm-1d.ini${one[*]:+ ${one[*]}}), warm-up $w1 s, sampled $d1 s"
run verlet-1d docs/scenes/rfm-1d.ini "$w1" "$d1" "${one[@]}" --set analysis.observables=gaps
labels=()
for w in $windows; do
    run "hybrid-1d-$w" docs/scenes/rfm-1d.ini "$w1" "$d1" "${one[@]}" --set analysis.observables=gaps \
        --set integrator.kind=hybrid --set integrator.kick_interval="$w"
    labels+=("hybrid-1d-$w")
done
table verlet-1d "${labels[@]}"
echo "# 2D steady state (docs/scenes/steady-2d.ini${two[*]:+ ${two[*]}}), warm-up $w2 s, sampled $d2 s"
run verlet-2d docs/scenes/steady-2d.ini "$w2" "$d2" "${two[@]}"
labels=()
for w in $windows2d; do
    run "hybrid-2d-$w" docs/scenes/steady-2d.ini "$w2" "$d2" "${two[@]}" \
        --set integrator.kind=hybrid --set integrator.kick_interval="$w"
    labels+=("hybrid-2d-$w")
done
table verlet-2d "${labels[@]}"
