#!/usr/bin/env bash
# OpenMP speed-up of the soft-sphere core: particle-steps per second at 1 and 2 threads (and at
# $THREADS_MAX if set) for the 2D RFM scene (N = 12000, phi = 0.53, eps_n = eps_t = 0.1, timed
# from the state after WARM2D = 100000 steps) and at N = 1e5 and 1e6 (same phi, short runs), plus
# the 1D RFM scene (runs on one thread whatever OMP_NUM_THREADS says). The trajectory is
# bit-identical for every thread count (tests/test_threads.c), so only the speed is compared.
# Usage:
#   bench/threads.sh BUILD [OTHER_BUILD] [--quick] [ROUNDS]
# With OTHER_BUILD (e.g. the branch point, built in another folder), both builds are timed
# interleaved (round by round: BUILD 1 thread, BUILD 2 threads, OTHER 1, OTHER 2, ...) from the
# same saved 2D state, and every line says which build it is; the summary gives each build's
# speed-up 1 -> 2 threads (median over the rounds of the per-round ratio) and OTHER/BUILD at each
# thread count. ROUNDS (default 3) applies to the 2D N = 12000 scene; ONLY12000=1 runs only that.
# --quick runs tiny sizes (used by the test suite so the bench cannot rot). Run on a quiet
# machine: with other processes on the cores, threads wait for each other at every step. With
# the kernel's autogroups (/proc/sys/kernel/sched_autogroup_enabled = 1) `nice` on the other
# processes does not help: each session's group gets an equal share of the cores, so a niced
# campaign still takes half a core from each bench thread. AUTOGROUP_NICE=-20 (root) runs every
# timed process in a session of its own with that group priority (docs/performance.md, "Threads").
set -euo pipefail
cd "$(dirname "$0")/.."
builds=() quick=false rounds=3
for a in "$@"; do
    case $a in
        --quick) quick=true ;;
        [0-9]*) rounds=$a ;;
        *) builds+=("$a") ;;
    esac
done
((${#builds[@]} <= 2)) || { echo "usage: bench/threads.sh [BUILD] [OTHER_BUILD] [--quick] [ROUNDS]" >&2; exit 2; }
((${#builds[@]} >= 1)) || builds=(build)
for b in "${builds[@]}"; do
    [[ -x $b/bench/bench_throughput ]] || { echo "threads.sh: $b/bench/bench_throughput not found (build it first)" >&2; exit 2; }
done
threads="1 2 ${THREADS_MAX:-}"
results=$(mktemp /tmp/granule-threads.XXXXXX)
trap 'rm -f "$results"' EXIT
# run a command, in its own session with autogroup priority $AUTOGROUP_NICE if set
prio() {
    if [[ -n ${AUTOGROUP_NICE:-} ]]; then
        setsid bash -c 'echo "$0" >/proc/self/autogroup && exec "$@"' "$AUTOGROUP_NICE" "$@"
    else
        "$@"
    fi
}
# one round of a scene: every build at every thread count; prints the bench lines and keeps
# "label build threads rate" in $results
round() {
    local label=$1 r=$2
    shift 2
    for b in "${builds[@]}"; do
        for t in $threads; do
            line=$(OMP_NUM_THREADS=$t OMP_PROC_BIND=${OMP_PROC_BIND:-close} prio "$b/bench/bench_throughput" "$@" --label "$label T=$t")
            rate=$(sed -n 's/.* median \([0-9.e+-]*\) .*/\1/p' <<<"$line")
            echo "$line  [build $b, round $r]"
            echo "$label|$b|$t|$r|$rate" >>"$results"
        done
    done
}
run() {
    local label=$1 n=$2
    shift 2
    for r in $(seq 1 "$n"); do
        round "$label" "$r" "$@"
    done
}
# per scene and build: median rate per thread count, the median per-round speed-up over 1 thread,
# and with two builds OTHER/BUILD per thread count (median of the per-round ratios)
summary() {
    /usr/bin/env awk -F'|' -v first="${builds[0]}" '
        { key = $1 SUBSEP $2 SUBSEP $3; rate[$1, $2, $3, $4] = $5; labels[$1] = 1; bld[$2] = 1; thr[$3] = 1; rnd[$4] = 1 }
        function median(a, n,   i, j, t) {
            for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
            return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
        }
        END {
            for (l in labels) for (b in bld) for (t in thr) {
                n = 0; m = 0; split("", v); split("", s); split("", o)
                for (r in rnd) if ((l, b, t, r) in rate) {
                    v[++n] = rate[l, b, t, r]
                    if (t != 1 && (l, b, 1, r) in rate) s[++m] = rate[l, b, t, r] / rate[l, b, 1, r]
                }
                if (n == 0) continue
                line = sprintf("# %s, build %s: %s threads %.3g particle-steps/s", l, b, t, median(v, n))
                if (m > 0) line = line sprintf(", speed-up over 1 thread %.2f", median(s, m))
                if (b != first) {
                    k = 0
                    for (r in rnd) if ((l, b, t, r) in rate && (l, first, t, r) in rate) o[++k] = rate[l, b, t, r] / rate[l, first, t, r]
                    if (k > 0) line = line sprintf(", ratio to build %s %.3f", first, median(o, k))
                }
                print line
            }
        }' "$results" | sort
}
if $quick; then
    run "2D quick" 1 docs/scenes/rfm-2d.ini --set system.N=2500 --set system.packing_fraction=0.53 --warmup-steps 20 --steps 20 --repeats 3
    summary
    exit 0
fi
echo "# granule threads, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, OMP_PROC_BIND=${OMP_PROC_BIND:-close}, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# builds: ${builds[*]}; autogroup priority ${AUTOGROUP_NICE:-not set}"
# the N = 12000 state after the warm-up, saved once (by the first build) and timed by every build
state=$(mktemp /tmp/granule-threads-state.XXXXXX)
trap 'rm -f "$results" "$state"' EXIT
OMP_NUM_THREADS=2 "${builds[0]}/bench/bench_throughput" docs/scenes/rfm-2d.ini --warmup-steps "${WARM2D:-100000}" --steps 1 \
    --repeats 1 --save-state "$state" >/dev/null
run "2D RFM N=12000" "$rounds" docs/scenes/rfm-2d.ini --state "$state" --steps 2000 --repeats 7
if [[ -z ${ONLY12000:-} ]]; then
run "2D N=1e5" 1 docs/scenes/rfm-2d.ini --set system.N=100000 --set system.packing_fraction=0.53 --warmup-steps 2000 --steps 300 --repeats 5
run "2D N=1e6" 1 docs/scenes/rfm-2d.ini --set system.N=1000000 --set system.packing_fraction=0.53 --warmup-steps 300 --steps 50 --repeats 3
run "1D RFM N=1000" 1 docs/scenes/rfm-1d.ini --warmup-steps 1000000 --steps 100000 --repeats 7
fi
echo "# load at the end $(cut -d' ' -f1-3 /proc/loadavg)"
summary
