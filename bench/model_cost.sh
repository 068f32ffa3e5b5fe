#!/usr/bin/env bash
# What each collision model costs per particle-step on the 2D RFM scene (N = 12000, phi = 0.53,
# eps = 0.1, one core): the thesis's law, then one change at a time (rotation, hertz, the history
# spring, rolling resistance, Mindlin). One build, the variants interleaved round by round (the order
# rotates), so a loaded machine slows them alike; prints each run, then per variant the median
# particle-steps/s, the ns per particle-step and the median of the per-round ratios to the
# thesis's law. A variant whose model is not in this build is reported as such and skipped.
# --dim 3: the same on the 3D scene of issue 35 (N = 32000 spheres, phi = 0.3, eps_n = eps_t = 0.1,
# spring-dashpot + tangential dashpot unclamped as the base, "thesis" in the table).
#   bench/model_cost.sh BUILD [--quick] [--dim 3] [ROUNDS]   (docs/performance.md, "Collision models")
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: model_cost.sh BUILD [--quick] [--dim 3] [ROUNDS]}
rounds=4
quick=false
dim=2
args=("${@:2}")
for ((k = 0; k < ${#args[@]}; k++)); do
    a=${args[$k]}
    if [[ $a == --quick ]]; then quick=true; rounds=1
    elif [[ $a == --dim ]]; then k=$((k + 1)); dim=${args[$k]:-}
    else rounds=$a; fi
done
[[ $dim == 2 || $dim == 3 ]] || { echo "model_cost.sh: --dim $dim: 2 or 3" >&2; exit 2; }
exe="$build/bench/bench_throughput"
[[ -x $exe ]] || { echo "model_cost.sh: $exe not found (build it first)" >&2; exit 2; }
export OMP_NUM_THREADS=1
spheres=(docs/scenes/rfm-3d.ini --set system.packing_fraction=0.3 --set model.eps_n=0.1 --set model.eps_t=0.1
         --set model.tangential=tangential_dashpot --set model.clamp=false)
if $quick && [[ $dim == 3 ]]; then
    echo "# quick smoke test: tiny sizes, the numbers are not benchmarks"
    base=("${spheres[@]}" --set system.N=300 --warmup-steps 50 --steps 50 --repeats 3)
elif $quick; then
    echo "# quick smoke test: tiny sizes, the numbers are not benchmarks"
    base=(docs/scenes/rfm-2d.ini --set system.N=300 --set system.L=0.08 --warmup-steps 50 --steps 50 --repeats 3)
elif [[ $dim == 3 ]]; then
    base=("${spheres[@]}" --set system.N=32000 --warmup-steps "${WARM3D:-2000}" --steps 1000 --repeats 3)
else
    base=(docs/scenes/rfm-2d.ini --warmup-steps "${WARM2D:-20000}" --steps 2000 --repeats 5)
fi
# label | the --set list that makes the variant (empty: the thesis's scene as it is)
variants=(
    "thesis|"
    "rotation|model.rotation=true"
    "hertz|model.normal=hertz"
    "hertz+rotation|model.normal=hertz model.rotation=true"
    "sliding+rotation|model.tangential=sliding_friction model.rotation=true"
    "spring+rotation|model.tangential=tangential_spring model.rotation=true"
    "spring|model.tangential=tangential_spring"
    "rolling|model.rotation=true model.rolling=rolling_friction model.mu_r=0.1"
    "hertz+spring|model.normal=hertz model.tangential=tangential_spring"
    "hertz+mindlin|model.normal=hertz model.tangential=tangential_spring model.mindlin=true"
)
echo "# model_cost $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# build: $build   commit: $(git rev-parse --short HEAD 2>/dev/null || echo ?)   rounds: $rounds"
tmp=$(mktemp -d /tmp/granule-model-cost.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
declare -A skip=()
nv=${#variants[@]}
for ((r = 1; r <= rounds; r++)); do
    for ((k = 0; k < nv; k++)); do
        v=${variants[$(((k + r - 1) % nv))]}
        label=${v%%|*}
        [[ -n ${skip[$label]:-} ]] && continue
        sets=()
        for kv in ${v#*|}; do sets+=(--set "$kv"); done
        if ! line=$("$exe" "${base[@]}" "${sets[@]}" --csv 2>"$tmp/err" | tail -1) || [[ -z $line ]]; then
            skip[$label]=1
            echo "$label: not in this build ($(head -1 "$tmp/err"))"
            continue
        fi
        ps=$(cut -d, -f6 <<<"$line")
        kernel=$(cut -d, -f4 <<<"$line")
        echo "$r $label $ps" >>"$tmp/runs"
        echo "$label $kernel" >>"$tmp/kernels"
        printf 'round %d  %-17s %s particle-steps/s  (%s)\n' "$r" "$label" "$ps" "$kernel"
    done
done
echo "# load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
[[ -s $tmp/runs ]] || { echo "model_cost.sh: no variant ran" >&2; exit 1; }
awk '
    function median(a, n,    i, j, t) {
        for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
        return n % 2 ? a[(n + 1) / 2] : 0.5 * (a[n / 2] + a[n / 2 + 1])
    }
    { v[$2, $1] = $3; if (!($2 in seen)) { seen[$2] = 1; order[++nl] = $2 } if ($1 > R) R = $1 }
    END {
        printf "%-17s %14s %10s %18s\n", "variant", "steps/s", "ns/step", "ratio to thesis"
        for (i = 1; i <= nl; i++) {
            l = order[i]; n = 0; m = 0
            for (r = 1; r <= R; r++) if ((l, r) in v) {
                a[++n] = v[l, r]
                if ((("thesis", r) in v)) q[++m] = v[l, r] / v["thesis", r]
            }
            med = median(a, n)
            printf "%-17s %14.4g %10.2f %18s\n", l, med, 1e9 / med, m ? sprintf("%.3f", median(q, m)) : "n/a"
        }
    }' "$tmp/runs"
