#!/usr/bin/env bash
# The 1D RFM scene (docs/scenes/rfm-1d.ini, N = 1000) three ways, side by side in one run, one
# core: granule with [noise] precision = double (the default), granule with precision = single,
# and the tight single-file kernel bench/tight_1d.c (issue 38 item 8; docs/performance.md,
# "Single-precision noise"). Usage:
#   bench/f32_noise.sh BUILD [--quick] [--cpu] [ROUNDS]
# Each round runs the three (warm-up, then 5 timed blocks, median), the order rotating from round to
# round (ROUNDS, default 6), so a loaded or throttled machine slows all alike; then the median over
# rounds of each and of the per-round ratios. Pause other work for the measurement. --quick runs
# tiny sizes (the test suite's smoke test; says so). --cpu rates each whole process by its CPU time
# (user + system, /usr/bin/time: all its particle-steps, warm-up included, over the CPU seconds)
# instead of the wall-clock median of its blocks: on a machine that other work shares, the wall
# clock also counts the time the process waited for a core.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: f32_noise.sh BUILD [--quick] [--cpu] [ROUNDS]}
quick=false
cpu=false
rounds=6
for a in "${@:2}"; do
    case $a in
        --quick) quick=true; rounds=2 ;;
        --cpu) cpu=true ;;
        *) rounds=$a ;;
    esac
done
for p in bench_throughput tight_1d; do
    [[ -x $build/bench/$p ]] || { echo "f32_noise.sh: $build/bench/$p not found (build it first)" >&2; exit 2; }
done
export OMP_NUM_THREADS=1
if $quick; then
    echo "# quick smoke test: tiny sizes, the numbers are not benchmarks"
    steps=(--warmup-steps 200 --steps 200 --repeats 3)
else
    steps=(--warmup-steps ${WARM1D:-200000} --steps 50000 --repeats 5)
fi
echo "# f32_noise $(date -u +%Y-%m-%dT%H:%MZ), $(nproc --all) cores, load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# build: $build ($(git rev-parse --short HEAD 2>/dev/null || echo '?')), rounds: $rounds (order rotates)"
tmp=$(mktemp -d /tmp/granule-f32-noise.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
timer=()
if $cpu; then
    timer=(/usr/bin/time -f '%U %S' -o "$tmp/time")
fi
run_wall() { # TAG: one median particle-steps/s (with --cpu under /usr/bin/time)
    case $1 in
        double) "${timer[@]}" "$build/bench/bench_throughput" docs/scenes/rfm-1d.ini "${steps[@]}" --csv |
            tail -1 | cut -d, -f6 ;;
        single) "${timer[@]}" "$build/bench/bench_throughput" docs/scenes/rfm-1d.ini --set noise.precision=single \
            "${steps[@]}" --csv | tail -1 | cut -d, -f6 ;;
        tight) "${timer[@]}" "$build/bench/tight_1d" "${steps[@]}" | sed -E 's/.*median ([^ ]+) .*/\1/' ;;
    esac
}
run_one() { # TAG: one particle-steps/s (the median of the blocks, or with --cpu per CPU second)
    if $cpu; then
        run_wall "$1" >/dev/null
        # particle-steps of the whole process: N = 1000 times the warm-up and the timed steps
        awk -v w="${steps[1]}" -v s="${steps[3]}" -v r="${steps[5]}" \
            '{ t = $1 + $2; if (t < 0.01) t = 0.01; printf "%.5g\n", 1000 * (w + s * r) / t }' "$tmp/time"
    else
        run_wall "$1"
    fi
}
tags=(double single tight)
for ((r = 1; r <= rounds; r++)); do
    for ((i = 0; i < 3; i++)); do
        t=${tags[(i + r) % 3]}
        v=$(run_one "$t")
        echo "$r $t $v" >>"$tmp/runs"
        printf 'round %d  %-6s %s particle-steps/s\n' "$r" "$t" "$v"
    done
done
echo "# load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
awk '
    function median(a, n,    i, j, t) {
        for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
        return n % 2 ? a[(n + 1) / 2] : 0.5 * (a[n / 2] + a[n / 2 + 1])
    }
    { v[$2, $1] = $3; if ($1 > R) R = $1 }
    END {
        for (r = 1; r <= R; r++) {
            d[r] = v["double", r]; s[r] = v["single", r]; t[r] = v["tight", r]
            st[r] = s[r] / t[r]; dt[r] = d[r] / t[r]; sd[r] = s[r] / d[r]
        }
        printf "medians over %d rounds: double %.4g  single %.4g  tight %.4g particle-steps/s\n", R, median(d, R), median(s, R), median(t, R)
        printf "ratios (median of per-round ratios): single/tight %.3fx  double/tight %.3fx  single/double %.3fx\n", median(st, R), median(dt, R), median(sd, R)
    }' "$tmp/runs"
