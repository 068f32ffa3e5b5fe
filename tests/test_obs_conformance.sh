#!/usr/bin/env bash
# Conformance of every registered observable (issue 34 item 6), looped over `granule observables`,
# so a new observable is checked without editing this file. For each observable and each
# dimension it supports, on a small scene (N = 60 in 1D, 120 in 2D, 125 spheres in 3D, 20 samples):
#   - streamed equals offline: the CSVs of `granule analyse` on the run's snapshots (one per
#     sample, no warm-up) equal the run's own, byte for byte (the run feeds the integrator's
#     positions, the snapshots hold them wrapped into the box: on a longer run an observable of
#     position differences, such as 1D gaps, can differ in the last digits there); an observable
#     that takes contact events (none in snapshots) must instead say so in its summary member
#   - checkpoint round trip: a run stopped again and again under --wall-limit (exit 4, test clock)
#     and resumed ends with the observable's CSVs and summary member identical to a straight run,
#     and the checkpoint's OBS section does not change when malloc'd memory is filled with
#     another byte (MALLOC_PERTURB_): no uninitialised bytes are saved
#   - thread-count invariance: OMP_NUM_THREADS=1 and 2 give identical CSVs and summary member
#   - refusal: a scene of a dimension it does not support, and an out-of-range value of each of
#     its [analysis] keys, are refused (exit 2) with a message naming the observable or the key
# usage: tests/test_obs_conformance.sh path/to/granule
set -uo pipefail
G=$(realpath "$1")
TMP=$(mktemp -d "${TMPDIR:-/tmp}/granule-obs-conformance-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
cd "$TMP" || exit 1
# results: one line per check in results.OBSERVABLE ("ok" or "FAILED: ..."), observables run
# side by side (at most 3 at a time)
ok() { echo ok >>"$TMP/results.$o"; }
bad() { echo "FAILED: $*" >>"$TMP/results.$o"; }

for d in 1 2 3; do
    cat >"s$d.ini" <<EOF
[system]
dim = $d
N = $([[ $d == 1 ]] && echo 60 || { [[ $d == 2 ]] && echo 120 || echo 125; })
$([[ $d == 1 ]] && echo "reduced_length = 0.3" || { [[ $d == 2 ]] && echo "L = 0.045" || echo "packing_fraction = 0.1"; })
[placement]
kind = $([[ $d == 3 ]] && echo cubic || echo uniform)
v0 = 0.5
[model]
normal = spring_dashpot
$([[ $d == 2 ]] && echo "tangential = tangential_dashpot")
eps_n = 0.6
[noise]
D = 1e-8
[integrator]
dt = 1e-6
[run]
warmup = 0
duration = 0.02
sample_every = 1e-3
seed = 3
[output]
snapshot_every = 1e-3
plots = false
EOF
done
# a mixture's scenes (docs/mixtures.md) for the observables that need one: s1/s2 with two species
# of masses 1:2 (a mixture runs the normal law alone), 1D, 2D and 3D
for d in 1 2 3; do
    grep -v '^tangential' "s$d.ini" >"sp$d.ini"
    printf '[species]\nradius = 1.5e-3, 1.5e-3\nmass = 3.53e-5, 7.06e-5\nfraction = 0.5, 0.5\n' >>"sp$d.ini"
done

# the registry as `granule observables` lists it: "name  [1D, 2D]", then the summary line, the
# parameters ("    key  default ..."), and a line for observables that take contact events
listing=$("$G" observables)
names=()
declare -A dims events keys mixture
cur=
while IFS= read -r line; do
    if [[ $line =~ ^([a-z0-9_]+)\ \ \[(.*)\]$ ]]; then
        cur=${BASH_REMATCH[1]}
        names+=("$cur")
        dims[$cur]=${BASH_REMATCH[2]}
        events[$cur]=0
        mixture[$cur]=0
        keys[$cur]=
    elif [[ -n $cur && $line == *"takes contact events"* ]]; then
        events[$cur]=1
    elif [[ -n $cur && $line == *"([species]"* ]]; then
        mixture[$cur]=1 # its summary says it needs a scene with [species]
    elif [[ -n $cur && $line =~ ^\ \ \ \ ([a-z0-9_]+)\ +default ]]; then
        keys[$cur]+="${BASH_REMATCH[1]} "
    fi
done <<<"$listing"
o=registry
if [[ ${#names[@]} -lt 13 ]]; then
    bad "granule observables lists ${#names[@]} observables: $listing"
fi

# equal_member A B NAME: the summary.json "analysis" member NAME of two runs, equal
equal_member() {
    python3 - "$1/summary.json" "$2/summary.json" "$3" <<'PY'
import json, sys
a, b = (json.load(open(p))["analysis"].get(sys.argv[3]) for p in sys.argv[1:3])
sys.exit(0 if a is not None and a == b else 1)
PY
}

# equal_csvs A B: every observable CSV of A (the engine's own tables left out) equal in B, byte
# for byte
engine_csv='^(temperature|blocks|ledger|cooling|energy)\.csv$'
equal_csvs() {
    local f n=0
    for f in "$1"/*.csv; do
        [[ -e $f ]] || continue
        [[ $(basename "$f") =~ $engine_csv ]] && continue
        n=$((n + 1))
        cmp -s "$f" "$2/$(basename "$f")" && continue
        echo "$(basename "$f") differs"
        return 1
    done
    [[ $n -gt 0 ]] || { echo "no CSV in $1"; return 1; }
}

check_observable() {
    local o=$1 d k err rc msg sessions sc=s
    local -a run what
    [[ ${mixture[$o]} == 1 ]] && sc=sp
    for d in 1 2 3; do
        if [[ ${dims[$o]} != *"${d}D"* ]]; then
            # refusal: this dimension is not supported
            err=$("$G" run "s$d.ini" --quiet --out "no-$o-$d" --set analysis.observables="$o" 2>&1 >/dev/null)
            rc=$?
            if [[ $rc -eq 2 && $err == *"$o"* && $err == *"dim"* ]]; then ok; else bad "$o on a ${d}D scene: exit $rc, '$err'"; fi
            continue
        fi
        run=(run "$sc$d.ini" --quiet --set analysis.observables="$o")
        OMP_NUM_THREADS=1 "$G" "${run[@]}" --out "a-$o-$d" >/dev/null 2>"err-$o" || { bad "$o ${d}D run: $(cat "err-$o")"; continue; }
        # streamed equals offline
        "$G" analyse "a-$o-$d" >/dev/null 2>"err-$o" || bad "$o ${d}D analyse: $(cat "err-$o")"
        if [[ ${events[$o]} == 1 ]]; then
            if grep -q "granule analyse has no contact events" <<<"$(python3 -c "import json,sys; print(json.dumps(json.load(open(sys.argv[1]))['analysis'][sys.argv[2]]))" "a-$o-$d/analysis/summary.json" "$o")"; then
                ok
            else
                bad "$o ${d}D: offline analysis of an observable that takes contact events does not say it has none"
            fi
        elif msg=$(equal_csvs "a-$o-$d/analysis" "a-$o-$d"); then
            ok
        else
            bad "$o ${d}D: streamed != offline: $msg"
        fi
        # thread-count invariance (the release pass's: the sanitizers see no ordering)
        if [[ ${GRANULE_TEST_QUICK:-0} != 1 ]]; then
            OMP_NUM_THREADS=2 "$G" "${run[@]}" --out "b-$o-$d" --set output.snapshot_every=0 >/dev/null 2>&1
            if msg=$(equal_csvs "a-$o-$d" "b-$o-$d") && equal_member "a-$o-$d" "b-$o-$d" "$o"; then ok; else bad "$o ${d}D: 1 vs 2 threads: ${msg:-summary member differs}"; fi
        fi
        # checkpoint round trip: stop under --wall-limit (test clock) and resume until done
        sessions=0
        rc=4
        what=("${run[@]}" --out "c-$o-$d" --set output.snapshot_every=0)
        while [[ $rc -eq 4 && $sessions -lt 20 ]]; do
            OMP_NUM_THREADS=1 GRANULE_TEST_CLOCK_TICK=0.002 GRANULE_CHUNK_STEPS=2000 "$G" "${what[@]}" --quiet --wall-limit 1.15 >/dev/null 2>&1
            rc=$?
            if [[ $sessions -eq 0 && ${GRANULE_TEST_QUICK:-0} != 1 ]]; then
                # the same first session with malloc'd memory filled (MALLOC_PERTURB_): the
                # observable's checkpoint bytes must not depend on memory it never wrote (glibc's
                # malloc: the release pass; AddressSanitizer's allocator ignores MALLOC_PERTURB_)
                OMP_NUM_THREADS=1 MALLOC_PERTURB_=165 GRANULE_TEST_CLOCK_TICK=0.002 GRANULE_CHUNK_STEPS=2000 "$G" \
                    "${run[@]}" --out "p-$o-$d" --set output.snapshot_every=0 --quiet --wall-limit 1.15 >/dev/null 2>&1
                if [[ $rc -eq 4 ]] && python3 - "c-$o-$d/checkpoint" "p-$o-$d/checkpoint" <<'PY'; then
import struct, sys
def obs(path):  # the OBS section (docs/checkpoints.md, "File format")
    d = open(path, "rb").read()
    pos = 44
    for _ in range(struct.unpack_from("<I", d, 40)[0]):
        n = struct.unpack_from("<Q", d, pos + 4)[0]
        if d[pos:pos + 4] == b"OBS ":
            return d[pos + 12:pos + 12 + n]
        pos += 12 + n
sys.exit(0 if obs(sys.argv[1]) is not None and obs(sys.argv[1]) == obs(sys.argv[2]) else 1)
PY
                    ok
                else
                    bad "$o ${d}D: the checkpoint's OBS section changes with MALLOC_PERTURB_ (uninitialised bytes saved), or no checkpoint (exit $rc)"
                fi
            fi
            what=(run --resume "c-$o-$d")
            sessions=$((sessions + 1))
        done
        if [[ $rc -eq 0 && $sessions -ge 2 ]] && msg=$(equal_csvs "a-$o-$d" "c-$o-$d") && equal_member "a-$o-$d" "c-$o-$d" "$o"; then
            ok
        else
            bad "$o ${d}D: $sessions sessions under --wall-limit (last exit $rc, want 0 after >= 2) != straight run: ${msg:-summary member differs}"
        fi
    done
    # refusal: every [analysis] key of the observable, far out of its range, names the key
    for k in ${keys[$o]}; do
        d=1
        [[ ${dims[$o]} == *1D* ]] || d=2
        err=$("$G" run "$sc$d.ini" --quiet --out "k-$o-$k" --set analysis.observables="$o" --set "analysis.$k=1e300" 2>&1 >/dev/null)
        rc=$?
        if [[ $rc -eq 2 && $err == *"$k"* ]]; then ok; else bad "$o: $k = 1e300 accepted or unnamed: exit $rc, '$err'"; fi
    done
}

for o in "${names[@]}"; do
    while [[ $(jobs -rp | wc -l) -ge 3 ]]; do wait -n; done
    check_observable "$o" &
done
wait
pass=$(cat "$TMP"/results.* 2>/dev/null | grep -c '^ok$')
fail=$(cat "$TMP"/results.* 2>/dev/null | grep -c '^FAILED')
grep -h '^FAILED' "$TMP"/results.* >&2
for o in "${names[@]}"; do
    [[ -s $TMP/results.$o ]] || { echo "FAILED: $o: no check ran" >&2; fail=$((fail + 1)); }
done
echo "obs-conformance: $pass passed, $fail failed (${#names[@]} observables)"
[[ $fail -eq 0 && $pass -gt 0 ]]
