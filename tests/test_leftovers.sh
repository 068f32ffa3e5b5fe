#!/usr/bin/env bash
# No partial file NAME.tmpPID (src/io/files.c) outlives a run (docs/checkpoints.md):
#   1. a fresh run over a folder whose run was killed before its first checkpoint (temporaries,
#      no checkpoint) removes the old temporaries, in the folder and in snapshots/;
#   2. a run killed during its final writes (temporaries beside a checkpoint) that is resumed
#      leaves none once it has finished: kill -9 at that moment is reproduced by planting the
#      temporaries such a kill leaves (pv.csv.tmpPID, a snapshot's, scene.ini's) after a stop
#      by --wall-limit, since no signal lands there reliably.
# Each time the finished folder must equal an uninterrupted run's, file for file, and its
# summary.json keep the scene's warnings (`[model] mu` is ignored here) after the resume.
# Usage: test_leftovers.sh GRANULE
set -uo pipefail
g="$(realpath "$1")"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cat >"$tmp/s.ini" <<'INI'
[system]
dim = 1
N = 40
reduced_length = 0.1
[placement]
kind = uniform
[model]
mu = 0.3
[run]
warmup = 0
duration = 0.1
sample_every = 1e-3
checkpoint_every = 0.02
[analysis]
observables = pv
[output]
snapshot_every = 0.02
plots = false
INI
leftovers() { find "$1" -name '*.tmp[0-9]*' | sed "s|$1/||" | sort | tr '\n' ' '; }
same_files() { # same_files A B: the same file names, the same bytes but summary.json and scene.ini's folder and wall_limit
    [[ "$(cd "$1" && find . -type f | sort)" == "$(cd "$2" && find . -type f | sort)" ]] ||
        fail "$2 holds other files than $1: $(diff <(cd "$1" && find . -type f | sort) <(cd "$2" && find . -type f | sort) | tr '\n' ' ')"
    diff -r -q -x summary.json -x scene.ini "$1" "$2" >/dev/null || fail "$2 differs from $1: $(diff -r -q -x summary.json -x scene.ini "$1" "$2")"
    diff <(grep -vE '^(dir|wall_limit) = ' "$1/scene.ini") <(grep -vE '^(dir|wall_limit) = ' "$2/scene.ini") >/dev/null || fail "$2/scene.ini differs from $1's"
}
"$g" run "$tmp/s.ini" --out "$tmp/ref" --quiet >/dev/null 2>&1 || fail "the uninterrupted run failed"

# 1. killed before its first checkpoint: temporaries and no checkpoint
mkdir -p "$tmp/a/snapshots"
for f in temperature.csv ledger.csv pv.csv scene.ini snapshots/snap_000000.xyz; do
    echo partial >"$tmp/a/$f.tmp99999"
done
[[ -n "$(leftovers "$tmp/a")" ]] || fail "test set-up: no temporaries planted"
"$g" run "$tmp/s.ini" --out "$tmp/a" --quiet >/dev/null 2>"$tmp/err.txt" || { cat "$tmp/err.txt"; fail "fresh run over a killed one failed"; }
[[ -z "$(leftovers "$tmp/a")" ]] || fail "a fresh run kept the killed run's temporaries: $(leftovers "$tmp/a")"
same_files "$tmp/ref" "$tmp/a"
echo "ok: a fresh run over a run killed before its first checkpoint removes its temporaries"
# ... and every other file such a run left (issue 39): a killed run of another scene with more
# snapshots and other observables leaves none of them beside the new run (its .run.lock shows a
# run wrote the folder); the same folder without .run.lock is a user's: nothing is removed
mkdir -p "$tmp/a2/snapshots"
cp "$tmp/ref/scene.ini" "$tmp/a2/" && : >"$tmp/a2/.run.lock"
for f in gaps.csv gaps.meta.json snapshots/snap_000099.xyz temperature.csv.tmp99999; do
    echo stale >"$tmp/a2/$f"
done
"$g" run "$tmp/s.ini" --out "$tmp/a2" --quiet >/dev/null 2>"$tmp/err.txt" || { cat "$tmp/err.txt"; fail "fresh run over a killed one failed"; }
same_files "$tmp/ref" "$tmp/a2"
mkdir -p "$tmp/a3" && cp "$tmp/s.ini" "$tmp/a3/scene.ini" && echo mine >"$tmp/a3/data.csv"
"$g" run "$tmp/s.ini" --out "$tmp/a3" --quiet >/dev/null 2>"$tmp/err.txt" || { cat "$tmp/err.txt"; fail "run into a user's folder failed"; }
[[ $(cat "$tmp/a3/data.csv") == mine ]] || fail "a run without --force removed a user's file"
echo "ok: a fresh run over a run killed before its first checkpoint leaves none of its files; a user's folder keeps its files"

# 2. killed during the final writes (after the last checkpoint), then resumed
GRANULE_TEST_CLOCK_TICK=0.01 GRANULE_CHUNK_STEPS=50 "$g" run "$tmp/s.ini" --out "$tmp/b" --quiet --wall-limit 3 \
    >/dev/null 2>"$tmp/err.txt"
rc=$?
[[ $rc == 4 && -f "$tmp/b/checkpoint" ]] || { cat "$tmp/err.txt"; fail "the --wall-limit stop gave exit $rc (expected 4, with a checkpoint)"; }
for f in pv.csv pv_tail.csv scene.ini blocks.csv snapshots/snap_000003.xyz; do
    echo partial >"$tmp/b/$f.tmp99999"
done
# the resume lifts the limit: with the real clock a slow (sanitizer) build could hit 3 s again
"$g" run --resume "$tmp/b" --set run.wall_limit=0 --quiet >/dev/null 2>"$tmp/err.txt" || { cat "$tmp/err.txt"; fail "the resume failed"; }
[[ -z "$(leftovers "$tmp/b")" ]] || fail "a finished run kept the temporaries of a killed attempt: $(leftovers "$tmp/b")"
[[ ! -f "$tmp/b/checkpoint" ]] || fail "a finished run kept its checkpoint"
same_files "$tmp/ref" "$tmp/b"
python3 -c 'import json, sys; a, b = (json.load(open(p)).get("warnings") for p in sys.argv[1:]); sys.exit(0 if a and a == b else "warnings %r, uninterrupted %r" % (b, a))' \
    "$tmp/ref/summary.json" "$tmp/b/summary.json" || fail "the resumed summary.json lost the scene's warnings"
echo "ok: a resumed run finishes without the temporaries of the killed attempt"
echo "test_leftovers: passed"
