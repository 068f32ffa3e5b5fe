#!/usr/bin/env bash
# Two builds side by side, interleaved in one run, so a loaded or throttled machine slows both
# alike: particle-steps/s of the 1D RFM scene (N = 1000) and the 2D RFM scene (N = 12000,
# phi = 0.53), one core, and the share of a step spent drawing the random force. Usage:
#   bench/compare_builds.sh OLD_BUILD NEW_BUILD [--quick] [ROUNDS]
# e.g. `git worktree add /tmp/old HEAD~1 && meson setup /tmp/old/build --buildtype=release &&
# ninja -C /tmp/old/build` then `bench/compare_builds.sh /tmp/old/build build`.
# Each round runs old then new, the next new then old (ROUNDS, default 4); a line per run, then the
# median of the per-round ratios new/old. The noise share is bench_noise's minimum ns per normal
# (n = 1000 per = 1, n = 12000 per = 2) times the normals per particle-step (dim) over the ns per
# particle-step at the median throughput: an estimate (the profile, `perf record`, gives the same
# to a few per cent). --quick runs tiny sizes (the test suite's smoke test; says so).
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: compare_builds.sh OLD_BUILD NEW_BUILD [--quick] [ROUNDS]}
new=${2:?usage: compare_builds.sh OLD_BUILD NEW_BUILD [--quick] [ROUNDS]}
quick=false
rounds=4
for a in "${@:3}"; do
    if [[ $a == --quick ]]; then quick=true; rounds=2; else rounds=$a; fi
done
for b in "$old" "$new"; do
    for p in bench_throughput bench_noise; do
        [[ -x $b/bench/$p ]] || { echo "compare_builds.sh: $b/bench/$p not found (build it first)" >&2; exit 2; }
    done
done
cores=$(nproc)
export OMP_NUM_THREADS=1
if $quick; then
    echo "# quick smoke test: tiny sizes, the numbers are not benchmarks"
    scenes=("1d|docs/scenes/rfm-1d.ini --set system.N=100 --warmup-steps 100 --steps 100 --repeats 3"
        "2d|docs/scenes/rfm-2d.ini --set system.N=300 --set system.L=0.08 --warmup-steps 50 --steps 50 --repeats 3")
    noise_args=(--repeats 1 --normals 20000)
else
    scenes=("1d|docs/scenes/rfm-1d.ini --warmup-steps ${WARM1D:-200000} --steps 50000 --repeats 5"
        "2d|docs/scenes/rfm-2d.ini --warmup-steps ${WARM2D:-20000} --steps 2000 --repeats 5")
    noise_args=(--repeats 5 --normals 2000000)
fi
echo "# compare_builds $(date -u +%Y-%m-%dT%H:%MZ), $cores cores, load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# old: $old   new: $new   rounds: $rounds (order alternates)"
tmp=$(mktemp -d /tmp/granule-compare.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
for ((r = 1; r <= rounds; r++)); do
    order=("old:$old" "new:$new")
    if ((r % 2 == 0)); then order=("new:$new" "old:$old"); fi
    for s in "${scenes[@]}"; do
        name=${s%%|*}
        read -r -a args <<<"${s#*|}"
        for ob in "${order[@]}"; do
            tag=${ob%%:*}
            b=${ob#*:}
            v=$("$b/bench/bench_throughput" "${args[@]}" --csv | tail -1 | cut -d, -f6)
            echo "$r $name $tag $v" >>"$tmp/runs"
            printf 'round %d  %-3s %-3s %s particle-steps/s\n' "$r" "$name" "$tag" "$v"
        done
    done
    for ob in "${order[@]}"; do
        tag=${ob%%:*}
        b=${ob#*:}
        "$b/bench/bench_noise" "${noise_args[@]}" | awk -v t="$tag" -v r="$r" \
            '$1 == "gr_noise_normals" && (($2 == "per=1" && $3 == "n=1000") || ($2 == "per=2" && $3 == "n=12000")) {
                 print r, ($2 == "per=1" ? "1d" : "2d"), t, $7 }' >>"$tmp/noise"
    done
done
echo "# load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/env awk '
    function median(a, n,    i, j, t) {
        for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
        return n % 2 ? a[(n + 1) / 2] : 0.5 * (a[n / 2] + a[n / 2 + 1])
    }
    FILENAME ~ /runs$/ { v[$2, $3, $1] = $4; sc[$2] = 1; if ($1 > R) R = $1; next }
    { ns[$2, $3, ++k[$2, $3]] = $4 }
    END {
        printf "%-3s %12s %12s %10s %14s %14s\n", "", "old", "new", "new/old", "noise old", "noise new"
        split("1d 2d", names, " ")
        for (si = 1; si <= 2; si++) {
            s = names[si]; if (!(s in sc)) continue
            n = 0
            for (r = 1; r <= R; r++) { n++; ro[n] = v[s, "old", r]; rn[n] = v[s, "new", r]; q[n] = v[s, "new", r] / v[s, "old", r] }
            mo = median(ro, n); mn = median(rn, n); mq = median(q, n)
            dim = s == "1d" ? 1 : 2
            for (t = 1; t <= 2; t++) {
                tag = t == 1 ? "old" : "new"; best = 1e300
                for (i = 1; i <= k[s, tag]; i++) if (ns[s, tag, i] + 0 < best) best = ns[s, tag, i] + 0
                share[t] = best * dim * (t == 1 ? mo : mn) * 1e-9
            }
            printf "%-3s %12.4g %12.4g %9.3fx %6.1f%% of step %6.1f%% of step\n", s, mo, mn, mq, 100 * share[1], 100 * share[2]
        }
    }' "$tmp/runs" "$tmp/noise"
