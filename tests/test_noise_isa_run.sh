#!/usr/bin/env bash
# The noise kernel does not change a run: the 1D RFM scene (symmetrised noise, N = 200) and a 2D
# scene (N = 300, tangential forces, every 2D observable), run with the vector kernel this CPU
# picks and again with GRANULE_NOISE_ISA capped at scalar (Random123's portable philox4x32 and the
# scalar ziggurat), avx2 and sse2, end with the same summary.json (wall-time lines excepted) and
# the same CSVs and snapshots, byte for byte. tests/test_noise.c checks the variates themselves
# bit for bit; this checks that nothing downstream depends on the kernel either. Both scenes again
# with [noise] precision = single: its AVX-512 kernel against the portable loop (any cap).
#
# usage: tests/test_noise_isa_run.sh path/to/granule
# GRANULE_TEST_QUICK=1 (the sanitizer build) shortens the runs.
set -euo pipefail

if [[ $# -lt 1 || ! -x "$1" ]]; then
    echo "usage: $0 path/to/granule" >&2
    exit 2
fi
G=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$(dirname "$0")/.." && pwd)
TMP=$(mktemp -d "${TMPDIR:-/tmp}/granule-test-noise-isa-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export CI=1
cd "$TMP"

if [[ ${GRANULE_TEST_QUICK:-0} == 1 ]]; then dur=0.004; else dur=0.02; fi

# the shipped scenes, shrunk: 1D N = 200 on a ring of reduced length 0.2 m; 2D N = 300 at phi = 0.53
src=$SRC/docs/scenes
common=(--set run.warmup=0.002 --set run.duration=$dur --set run.checkpoint_wall=0 --set output.plots=false
    --set output.snapshot_every=0.002)
s1=("$src/rfm-1d.ini" --set system.N=200 --set system.reduced_length=0.2 --set run.seed=7
    --set analysis.observables=moments,freepath,postcollision,gaps,pv "${common[@]}")
s2=("$src/rfm-2d.ini" --set system.N=300 --set system.L=0.0633 --set run.seed=11
    --set analysis.observables=moments,freepath,postcollision,sk,pair,pv "${common[@]}")

failed=0
# same DIR_A DIR_B: summary.json (wall-time lines and the folder name excepted), every CSV and
# snapshot byte for byte
same() {
    local a=$1 b=$2 f rel skip='wall_seconds|_per_second|checkpoint|"dir"'
    if ! diff <(grep -Ev "$skip" "$a/summary.json") <(grep -Ev "$skip" "$b/summary.json") >"$TMP/diff"; then
        echo "summary.json differs: $(head -4 "$TMP/diff" | tr '\n' ' ')"
        return 1
    fi
    local n=0
    for f in "$a"/*.csv "$a"/snapshots/*; do
        [[ -e $f ]] || continue
        rel=${f#"$a"/}
        n=$((n + 1))
        if ! cmp -s "$f" "$b/$rel"; then
            echo "$rel differs"
            return 1
        fi
    done
    if ((n == 0)); then
        echo "no CSV or snapshot written in $a"
        return 1
    fi
    return 0
}

# [noise] precision = single: the AVX-512 group kernel and the portable loop (any cap below avx512)
s1f=("${s1[@]}" --set noise.precision=single)
s2f=("${s2[@]}" --set noise.precision=single)
for s in s1 s2 s1f s2f; do
    declare -n scene=$s
    "$G" run "${scene[@]}" --out "$s-native" --quiet >/dev/null
    for isa in scalar sse2 avx2; do
        GRANULE_NOISE_ISA=$isa "$G" run "${scene[@]}" --out "$s-$isa" --quiet >/dev/null
        if msg=$(same "$s-native" "$s-$isa"); then
            echo "ok   $s: GRANULE_NOISE_ISA=$isa gives the run of the native kernel"
        else
            echo "FAIL $s: GRANULE_NOISE_ISA=$isa: $msg"
            failed=$((failed + 1))
        fi
    done
done
# the check can fail: a run with other noise (another seed) must differ
"$G" run "${s1[@]}" --set run.seed=8 --out s1-seed8 --quiet >/dev/null
if same s1-native s1-seed8 >/dev/null; then
    echo "FAIL the comparison cannot tell two seeds apart"
    failed=$((failed + 1))
else
    echo "ok   another seed gives another run (the comparison can fail)"
fi
exit $((failed > 0))
