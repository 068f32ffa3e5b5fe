#!/usr/bin/env bash
# Throughput of every collision model and integrator against N (docs/performance.md, "Throughput
# over N"): 2D at phi = 0.53 for N = 1e3 .. 1e5, 1D at the density of the 1D RFM scene
# (L' = N / 1000 m) for N = 1e2 .. 1e4, eps = 0.1 (the RFM scenes), one core; then the 2D RFM scene
# on 1, 2, ... threads. Each row is the median of repeated blocks after a warm-up, with the kernel,
# thread count, compiler flags and commit (bench_throughput --csv).
#
#   bench/throughput_all.sh [BUILD_DIR] [--quick]
#
# Writes out/bench/throughput.csv, out/bench/throughput.md and docs/img/scaling.png (cost per
# particle-step against N, one line per model). Integrators that are not in this build (event,
# hybrid) and threads (OpenMP missing) print "skipped: not built" and the rest goes on.
# --quick: tiny sizes, output in a temporary folder (the test suite runs this).
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
build_and_quick "bench/throughput_all.sh [BUILD_DIR] [--quick]" "$@"
b="$build/bench/bench_throughput"
require_built throughput_all "$b"
bench_outputs "$quick" throughput
csv="$out/throughput.csv"
"$b" --csv-header | sed 's/^/group,/' >"$csv"

if $quick; then
    sizes2=(300 600); sizes1=(50 100); budget=20000; warm_budget=20000; repeats=3; threads=(1 2); row_timeout=20
else
    sizes2=(1000 3000 10000 30000 100000); sizes1=(100 300 1000 3000 10000)
    budget=${BUDGET:-20000000}; warm_budget=${WARM_BUDGET:-50000000}; repeats=${REPEATS:-5}
    # the start (hexagonal bed in 2D, equal spacing in 1D) must melt before timing: at least
    # 0.01 s (2D) or 0.05 s (1D) of simulated time whatever N
    warm2=${WARM_MIN_2D:-10000}; warm1=${WARM_MIN_1D:-50000}
    threads=(1 2 4); row_timeout=${ROW_TIMEOUT:-900}
fi

row() { # group scene label extra-args...
    local group=$1 scene=$2 label=$3
    shift 3
    local line
    if line=$(OMP_NUM_THREADS=${T:-1} timeout -k 5 "$row_timeout" "$b" "$scene" "$@" --repeats "$repeats" --label "$label" --csv 2>&1); then
        echo "$group,$line" >>"$csv"
        echo "$label: ${line#*,}" | cut -c1-160
    else
        echo "$label: failed${line:+: $line} (rows time out after $row_timeout s, ROW_TIMEOUT)"
        return 1
    fi
}

sized() { # N [min warm-up steps] -> --warmup-steps W --steps S for the particle-step budget
    local n=$1 wmin=${2:-0}
    local s=$((budget / n)) w=$((warm_budget / n))
    ((s < 10)) && s=10
    $quick || ((w >= wmin)) || w=$wmin
    echo "--warmup-steps $w --steps $s"
}

bench_header
# soft-sphere models, 2D
declare -A models2=(
    [spring_dashpot]="--set model.tangential=none"
    [spring_dashpot+tangential_dashpot]=""
    [spring_dashpot+sliding_friction]="--set model.tangential=sliding_friction --set model.mu=0.5"
    [spring_dashpot-clamped+tangential_dashpot]="--set model.clamp=true"
)
for m in spring_dashpot spring_dashpot+tangential_dashpot spring_dashpot+sliding_friction spring_dashpot-clamped+tangential_dashpot; do
    for n in "${sizes2[@]}"; do
        # shellcheck disable=SC2086
        row "2D verlet $m" docs/scenes/rfm-2d.ini "2D $m N=$n" --set system.N="$n" --set system.packing_fraction=0.53 \
            ${models2[$m]} $(sized "$n" "${warm2:-0}")
    done
done
# soft-sphere, 1D
for m in spring_dashpot spring_dashpot-clamped; do
    extra=()
    [[ $m == spring_dashpot-clamped ]] && extra=(--set model.clamp=true)
    for n in "${sizes1[@]}"; do
        lp=$(awk -v n="$n" 'BEGIN { printf "%.6g", n / 1000 }')
        # shellcheck disable=SC2046
        row "1D verlet $m" docs/scenes/rfm-1d.ini "1D $m N=$n" --set system.N="$n" --set system.reduced_length="$lp" \
            "${extra[@]}" $(sized "$n" "${warm1:-0}")
    done
done
# event-driven and hybrid integrators (rows run once the integrators are in the build)
for kind in event hybrid; do
    for dim in 2 1; do
        if [[ $dim == 2 ]]; then scene=docs/scenes/rfm-2d.ini; sizes=("${sizes2[@]}"); else scene=docs/scenes/rfm-1d.ini; sizes=("${sizes1[@]}"); fi
        kset=(--set integrator.kind="$kind")
        [[ $kind == event ]] && kset+=(--set model.normal=hard_sphere --set model.tangential=none)
        if ! msg=$(probe_kind "$scene" "$kind" "${kset[@]}"); then
            echo "${dim}D $kind: $msg"
            continue
        fi
        for n in "${sizes[@]}"; do
            size=(--set system.N="$n")
            if [[ $dim == 2 ]]; then size+=(--set system.packing_fraction=0.53); else
                size+=(--set system.reduced_length="$(awk -v n="$n" 'BEGIN { printf "%.6g", n / 1000 }')"); fi
            # shellcheck disable=SC2046
            wm=${warm2:-0}
            [[ $dim == 1 ]] && wm=${warm1:-0}
            row "${dim}D $kind" "$scene" "${dim}D $kind N=$n" "${size[@]}" "${kset[@]}" $(sized "$n" "$wm") || true
        done
    done
done
# threads, 2D RFM scene (N = 12000; tiny in --quick)
tn=12000
$quick && tn=600
if [[ $(OMP_NUM_THREADS=2 "$b" docs/scenes/rfm-2d.ini --set system.N=20 --set system.packing_fraction=0.53 --warmup-steps 0 --steps 1 --repeats 1 --csv | cut -d, -f5) != 2 ]]; then
    echo "threads: skipped: not built (no OpenMP)"
else
    for t in "${threads[@]}"; do
        # shellcheck disable=SC2046
        T=$t row "2D verlet threads" docs/scenes/rfm-2d.ini "2D RFM N=$tn T=$t" --set system.N=$tn \
            --set system.packing_fraction=0.53 --threads "$t" $(sized $tn "${warm2:-0}")
    done
fi

# tables and the scaling plot
python3 - "$csv" "$out/throughput.md" "$out/scaling.dat" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("| group | N | threads | kernel | particle-steps/s (median) | min - max | ns per particle-step | wall s per simulated s | contacts/step | collisions per wall s |\n")
    f.write("|---|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        med = float(r["median"])
        f.write(f"| {r['group']} | {r['N']} | {r['threads']} | {r['kernel']} | {med:.3g} | {float(r['min']):.3g} - {float(r['max']):.3g} "
                f"| {1e9 / med:.2f} | {float(r['wall_per_simulated_s']):.3g} | {float(r['contacts_per_step']):.2f} | {float(r['collisions_per_s']):.3g} |\n")
    if rows:
        f.write(f"\nCPU: {rows[0]['cpu']}; flags: {rows[0]['cflags'].strip()}; commit {rows[0]['commit']}\n")
groups = {}
for r in rows:
    if "threads" in r["group"]:
        continue
    groups.setdefault(r["group"], []).append((int(r["N"]), 1e9 / float(r["median"])))
with open(sys.argv[3], "w") as f:
    for g, pts in groups.items():
        f.write(f'"{g}"\n')
        for n, c in sorted(pts):
            f.write(f"{n} {c:.4f}\n")
        f.write("\n\n")
EOF
cat "$out/throughput.md"
if command -v gnuplot >/dev/null; then
    n_groups=$(grep -c '^"' "$out/scaling.dat" || true)
    gnuplot <<EOF
set terminal pngcairo size 1250,700 font ",11" noenhanced
set output "$img/scaling.png"
set logscale x
set xlabel "N"
set ylabel "ns per particle-step (one core; event/hybrid: per particle per dt simulated)"
set key outside right top vertical font ",9"
set logscale y
set grid
set title "Cost per particle-step against N (flat = O(N))"
plot for [i=0:$((n_groups - 1))] "$out/scaling.dat" index i using 1:2 with linespoints title columnheader(1)
EOF
    echo "plot: $img/scaling.png"
else
    echo "plot: skipped (gnuplot not installed)"
fi
echo "table: $out/throughput.md, $csv"
