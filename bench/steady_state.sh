#!/usr/bin/env bash
# Throughput at the steady state (issue 17's 2D target is "at steady state"): the 1D and 2D RFM
# scenes are first run for 1e6 steps (1 simulated s, past the warm-up both need: Fig. 2.7, sec.
# 2.3.3), their state is saved (bench_throughput --save-state; out/bench/steady-{1d,2d}.state,
# kept and reused while the build can read it), and every timed block starts from that same state
# (--state). compare_builds.sh times the state 20000 steps after the hexagonal start instead,
# which is still compressed (2.9 listed pairs per particle in 2D against 1.7 at steady state).
# Usage:
#   bench/steady_state.sh BUILD [OTHER_BUILD] [--quick] [ROUNDS]
# With OTHER_BUILD (it must have --state too), both are timed interleaved from the same states and
# the median ratio OTHER/BUILD is printed. --quick: tiny sizes and a short warm-up in a temporary
# folder (the test suite's smoke test; the numbers are not benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."
builds=() quick=false rounds=3
for a in "$@"; do
    case $a in
        --quick) quick=true; rounds=1 ;;
        [0-9]*) rounds=$a ;;
        *) builds+=("$a") ;;
    esac
done
((${#builds[@]} >= 1 && ${#builds[@]} <= 2)) || { echo "usage: bench/steady_state.sh BUILD [OTHER_BUILD] [--quick] [ROUNDS]" >&2; exit 2; }
for b in "${builds[@]}"; do
    [[ -x $b/bench/bench_throughput ]] || { echo "steady_state.sh: $b/bench/bench_throughput not found (build it first)" >&2; exit 2; }
done
cores=$(nproc)
export OMP_NUM_THREADS=1
if $quick; then
    dir=$(mktemp -d /tmp/granule-steady.XXXXXX)
    trap 'rm -rf "$dir"' EXIT
    echo "# quick smoke test: tiny sizes, the numbers are not benchmarks"
    scenes=("1d|1000|docs/scenes/rfm-1d.ini --set system.N=100|--steps 100 --repeats 3"
        "2d|1000|docs/scenes/rfm-2d.ini --set system.N=300 --set system.L=0.08|--steps 50 --repeats 3")
else
    dir=out/bench
    mkdir -p "$dir"
    scenes=("1d|1000000|docs/scenes/rfm-1d.ini|--steps 50000 --repeats 5"
        "2d|1000000|docs/scenes/rfm-2d.ini|--steps 2000 --repeats 5")
fi
echo "# steady_state $(date -u +%Y-%m-%dT%H:%MZ), $cores cores, load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
first=${builds[0]}
for s in "${scenes[@]}"; do
    IFS='|' read -r name warm scene timing <<<"$s"
    read -r -a sargs <<<"$scene"
    state="$dir/steady-$name.state"
    # reuse a state this build can read (a tiny timed block checks it); else warm up and save one
    if ! [[ -f $state ]] || ! "$first/bench/bench_throughput" "${sargs[@]}" --state "$state" --steps 1 --repeats 1 >/dev/null 2>&1; then
        echo "# $name: warming up $warm steps with $first (saved to $state)"
        "$first/bench/bench_throughput" "${sargs[@]}" --warmup-steps "$warm" --steps 1 --repeats 1 --save-state "$state" >/dev/null
    fi
done
declare -A rates
for ((r = 1; r <= rounds; r++)); do
    order=("${builds[@]}")
    if ((r % 2 == 0 && ${#builds[@]} == 2)); then order=("${builds[1]}" "${builds[0]}"); fi
    for s in "${scenes[@]}"; do
        IFS='|' read -r name warm scene timing <<<"$s"
        read -r -a sargs <<<"$scene"
        read -r -a targs <<<"$timing"
        for b in "${order[@]}"; do
            line=$("$b/bench/bench_throughput" "${sargs[@]}" --state "$dir/steady-$name.state" "${targs[@]}" --csv | tail -1)
            v=$(cut -d, -f6 <<<"$line")
            rates[$r,$name,$b]=$v
            printf 'round %d  %-3s %-40s %s particle-steps/s  (kernel %s, contacts/step %s)\n' "$r" "$name" "$b" "$v" \
                "$(cut -d, -f4 <<<"$line")" "$(cut -d, -f10 <<<"$line")"
        done
    done
done
for s in "${scenes[@]}"; do
    name=${s%%|*}
    for b in "${builds[@]}"; do
        med=$(for ((r = 1; r <= rounds; r++)); do echo "${rates[$r,$name,$b]}"; done | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}')
        echo "$name steady state: $b median $med particle-steps/s"
    done
    if ((${#builds[@]} == 2)); then
        ratio=$(for ((r = 1; r <= rounds; r++)); do echo "${rates[$r,$name,${builds[1]}]} ${rates[$r,$name,${builds[0]}]}"; done |
            awk '{print $1 / $2}' | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}')
        echo "$name steady state: ratio ${builds[1]} / ${builds[0]} (median of rounds) $ratio"
    fi
done
