# Sourced by the shell tests of observables on runs, called as `test_X.sh GRANULE SOURCE_DIR`
# (tests/test_obs_mixture.sh, tests/test_obs_mixture_structure.sh): $granule, $src
# (absolute), a temporary folder $tmp removed at exit, $quick (GRANULE_TEST_QUICK), and
#   fail MESSAGE...               print FAIL: MESSAGE and exit 1;
#   run NAME SCENE [ARGS...]      granule run SCENE --out $tmp/NAME without snapshots, one thread;
#   run_term_resume NAME SCENE [ARGS...]   the same run with checkpoints every 0.01 s, paused at
#                                 step 3000 (GRANULE_TEST_PAUSE_AT_STEP) and stopped by SIGTERM
#                                 once a checkpoint exists (exit 5), then --resume to the end.
set -uo pipefail
granule=$1
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
quick=${GRANULE_TEST_QUICK:-0}
fail() {
    echo "FAIL: $*" >&2
    exit 1
}
run() {
    local name=$1 scene=$2
    shift 2
    OMP_NUM_THREADS=1 "$granule" run "$scene" --out "$tmp/$name" --set output.snapshot_every=0 \
        "$@" >"$tmp/$name.log" 2>&1 || { cat "$tmp/$name.log" >&2; fail "run $name"; }
}
run_term_resume() {
    local name=$1 scene=$2 pid rc
    shift 2
    GRANULE_TEST_PAUSE_AT_STEP=3000 OMP_NUM_THREADS=1 "$granule" run "$scene" --out "$tmp/$name" \
        --set output.snapshot_every=0 --set run.checkpoint_every=0.01 "$@" >"$tmp/$name.log" 2>&1 &
    pid=$!
    for _ in $(seq 600); do
        [[ -s $tmp/$name/checkpoint ]] && break
        sleep 0.1
    done
    kill -TERM "$pid" 2>/dev/null
    wait "$pid"
    rc=$?
    [[ $rc == 5 ]] || { cat "$tmp/$name.log" >&2; fail "SIGTERM of $name: exit $rc, want 5"; }
    OMP_NUM_THREADS=1 "$granule" run --resume "$tmp/$name" >"$tmp/$name-resume.log" 2>&1 ||
        { cat "$tmp/$name-resume.log" >&2; fail "resume of $name"; }
}
