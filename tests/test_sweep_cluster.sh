#!/usr/bin/env bash
# granule sweep on clusters (docs/cluster.md), on tiny 1D scenes:
#   resume: --list, --point K, the batch-array index from the environment (with --array-base),
#           --collect naming missing and failed points, per-point manifests, a sweep stopped by
#           SIGTERM mid-point (to it, or to its whole process group) continues that point from its
#           checkpoint (same results as an uninterrupted sweep; a corrupt checkpoint is discarded
#           and the point starts again), two sweeps over one folder share its points, a sweep
#           killed midway and rerun runs only its unfinished points, changed settings rerun a
#           finished point;
#   mpi:    mpirun -n 2 granule sweep gives the same per-point results, sweep.csv and
#           exponents.csv as the serial sweep (skipped with exit 77 only when built without MPI).
# usage: test_sweep_cluster.sh GRANULE SOURCE_DIR resume|mpi [mpi-built: yes|no]
set -uo pipefail
granule=$1
src=$2
part=$3
mpi_built=${4:-no}
tmp=$(mktemp -d)
bg=
trap '[[ -n $bg ]] && kill -KILL $bg 2>/dev/null; rm -rf "$tmp"' EXIT
pass=0
fail=0
check() { if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAILED: $*" >&2; fi; }
# no scheduler or MPI launcher around us may pick the points
unset SLURM_ARRAY_TASK_ID PBS_ARRAY_INDEX PBS_ARRAYID SGE_TASK_ID LSB_JOBINDEX \
    OMPI_COMM_WORLD_SIZE PMI_SIZE PMIX_SIZE PMIX_RANK MPI_LOCALNRANKS
quick=${GRANULE_TEST_QUICK:-0}

# sweep.ini OUT DURATION: 3 N x 2 seeds = 6 points
sweep_file() {
    cat >"$tmp/$1.ini" <<EOT
[sweep]
scene = $src/docs/scenes/rfm-1d.ini
out = $tmp/$1
seeds = 1, 2
[vary]
system.N = 20, 40, 80
[set]
run.warmup = 0
run.duration = $2
output.plots = false
output.snapshot_every = 0
analysis.observables = moments
EOT
}

# same DIR_A DIR_B: identical per-point summaries (wall-clock fields aside), sweep.csv (throughput
# column aside) and exponents.csv
same() {
    python3 - "$1" "$2" <<'PY'
import json, os, sys
a, b = sys.argv[1], sys.argv[2]
def clean(x):
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items() if k not in ("wall_seconds", "particle_steps_per_second", "progress")}
    if isinstance(x, list):
        return [clean(v) for v in x]
    return x
ok = True
pts = sorted(p for p in os.listdir(a) if p.startswith("p"))
ok &= pts == sorted(p for p in os.listdir(b) if p.startswith("p")) and len(pts) == 6
for p in pts:
    sa = clean(json.load(open(f"{a}/{p}/summary.json")))
    sb = clean(json.load(open(f"{b}/{p}/summary.json")))
    sa["scene"]["output"] = sb["scene"]["output"] = None
    if sa != sb:
        print("summary differs:", p, file=sys.stderr)
        ok = False
    ma, mb = json.load(open(f"{a}/{p}/point.json")), json.load(open(f"{b}/{p}/point.json"))
    ok &= ma["scene_hash"] == mb["scene_hash"] and ma["overrides"] == mb["overrides"] and ma["status"] == "completed"
def rows(d):
    out, drop = [], None
    for line in open(d + "/sweep.csv"):
        if line.startswith("#"):
            continue
        f = line.rstrip("\n").split(",")
        drop = f.index("particle_steps_per_second") if drop is None else drop  # the header row
        out.append(f[:drop] + f[drop + 1:])
    return out
if rows(a) != rows(b):
    print("sweep.csv differs", file=sys.stderr)
    ok = False
if open(a + "/exponents.csv").read() != open(b + "/exponents.csv").read():
    print("exponents.csv differs", file=sys.stderr)
    ok = False
sys.exit(0 if ok else 1)
PY
}

if [[ $part == resume ]]; then
    sweep_file serial 0.02
    # --list: 6 points, seed fastest
    out=$("$granule" sweep "$tmp/serial.ini" --list)
    check test "$(grep -vc '^#' <<<"$out")" -eq 6
    check grep -q "^1 system.N=20 run.seed=2$" <<<"$out"
    check grep -q "^4 system.N=80 run.seed=1$" <<<"$out"
    # [vary] run.seed (the seed as the slowest key): each point runs the seed it is labelled with
    sed -e '/^seeds = /d' -e 's/^\[vary\]$/[vary]\nrun.seed = 1, 2/' "$tmp/serial.ini" >"$tmp/seedvary.ini"
    sed -i "s|^out = .*|out = $tmp/seedvary|" "$tmp/seedvary.ini"
    out=$("$granule" sweep "$tmp/seedvary.ini" --list)
    check grep -q "^1 run.seed=1 system.N=40$" <<<"$out"
    check grep -q "^3 run.seed=2 system.N=20$" <<<"$out"
    check "$granule" sweep "$tmp/seedvary.ini" --jobs 1
    check grep -q '"seed":[[:space:]]*2' "$tmp/seedvary/p0003/point.json"
    check grep -q '"seed":[[:space:]]*2' "$tmp/seedvary/p0003/summary.json"
    check grep -q '^3,2,2,20,completed' "$tmp/seedvary/sweep.csv"
    t1=$(grep '"T_mean"' "$tmp/seedvary/p0000/summary.json") t2=$(grep '"T_mean"' "$tmp/seedvary/p0003/summary.json")
    check test "$t1" != "$t2"
    # a [vary] list continues on a line that repeats its key (an INI line holds 200 characters)
    sed 's/^system.N = \(.*\)$/system.N = 20\nsystem.N = 40, 80/' "$tmp/serial.ini" >"$tmp/split.ini"
    check test "$(grep -c "^system.N = " "$tmp/split.ini")" -eq 2
    check diff <("$granule" sweep "$tmp/serial.ini" --list | grep -v '^#') <("$granule" sweep "$tmp/split.ini" --list | grep -v '^#')
    # the serial sweep: every point has a completed manifest naming its overrides and host
    check "$granule" sweep "$tmp/serial.ini" --jobs 1
    check python3 - "$tmp/serial/p0003/point.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
ok = m["point"] == 3 and m["status"] == "completed" and m["exit_code"] == 0 and m["keys"] == {"system.N": "40"}
ok &= "run.seed=2" in m["overrides"] and "system.N=40" in m["overrides"] and "run.duration=0.02" in m["overrides"]
ok &= len(m["scene_hash"]) == 16 and m["host"] and m["runner"] == "local" and m["started"] <= m["finished"]
ok &= m["commit"] != "" and m["granule_version"] != "" and m["wall_seconds"] >= 0
sys.exit(0 if ok else 1)
PY
    # one point per array task: --point K, then SLURM_ARRAY_TASK_ID with a 1-based array, then collect
    sweep_file array 0.02
    "$granule" sweep "$tmp/array.ini" --collect >/dev/null 2>"$tmp/collect0.log"
    check test $? -eq 1
    check grep -q "unfinished points (6;.*: 0-5$" "$tmp/collect0.log"
    check test "$(grep -c ',missing,' "$tmp/array/sweep.csv")" -eq 6
    check "$granule" sweep "$tmp/array.ini" --point 0
    check "$granule" sweep "$tmp/array.ini" --point 1
    "$granule" sweep "$tmp/array.ini" --collect >/dev/null 2>"$tmp/collect1.log"
    check test $? -eq 1
    check grep -q "unfinished points (4;.*: 2-5$" "$tmp/collect1.log"
    for i in 3 4 5 6; do
        SLURM_ARRAY_TASK_ID=$i "$granule" sweep "$tmp/array.ini" --array-base 1 2>>"$tmp/array.log"
        check test $? -eq 0
    done
    check grep -q "point 2 from SLURM_ARRAY_TASK_ID=3" "$tmp/array.log"
    check grep -q '"runner":.*"array SLURM_ARRAY_TASK_ID=6"' "$tmp/array/p0005/point.json"
    SGE_TASK_ID=undefined "$granule" sweep "$tmp/array.ini" --point 5 2>"$tmp/skip.log" # SGE outside arrays
    check test $? -eq 0
    check grep -q "skipping finished point 5" "$tmp/skip.log"
    check "$granule" sweep "$tmp/array.ini" --collect
    check same "$tmp/serial" "$tmp/array"
    # the fork-parallel sweep gives the same results too
    sweep_file forked 0.02
    check "$granule" sweep "$tmp/forked.ini" --jobs 2
    check same "$tmp/serial" "$tmp/forked"
    # bad indices are refused naming the allowed range
    "$granule" sweep "$tmp/array.ini" --point 6 >/dev/null 2>"$tmp/bad.log"
    check test $? -eq 2
    check grep -q "points 0..5" "$tmp/bad.log"
    SLURM_ARRAY_TASK_ID=x "$granule" sweep "$tmp/array.ini" >/dev/null 2>&1
    check test $? -eq 2
    SLURM_ARRAY_TASK_ID=0 "$granule" sweep "$tmp/array.ini" --array-base 1 >/dev/null 2>&1
    check test $? -eq 2
    if [[ $mpi_built == no ]]; then # an MPI launch of a granule without MPI must not run the sweep P times
        OMPI_COMM_WORLD_SIZE=2 "$granule" sweep "$tmp/array.ini" >/dev/null 2>"$tmp/nompi.log"
        check test $? -eq 2
        check grep -q "built without MPI" "$tmp/nompi.log"
    fi

    # a failed point is recorded in its manifest, the others go on; collect names it
    cat >"$tmp/fail.ini" <<EOT
[sweep]
scene = $src/docs/scenes/steady-2d.ini
out = $tmp/fail
[vary]
system.N = 20, 5120
[set]
run.warmup = 0
run.duration = 0.001
output.plots = false
EOT
    "$granule" sweep "$tmp/fail.ini" --point 1 >/dev/null 2>&1
    check test $? -ne 0
    check grep -q '"status":.*"refused"' "$tmp/fail/p0001/point.json" # N does not fit in L
    check grep -q '"error":' "$tmp/fail/p0001/point.json"
    "$granule" sweep "$tmp/fail.ini" >/dev/null 2>"$tmp/fail.log"
    check test $? -eq 1
    check grep -q '"status":.*"completed"' "$tmp/fail/p0000/point.json"
    check grep -q "failed points (1): 1 " "$tmp/fail.log"

    # SIGTERM to a sweep (a batch system ending the job) while point 0 runs: the run writes a
    # checkpoint (it gets SIGTERM itself when the sweep dies, PR_SET_PDEATHSIG); the rerun continues
    # it from there and every result equals the uninterrupted serial sweep's
    stop_point0() { # NAME [group] [DURING]: a sweep of 6 points stopped by SIGTERM (to the sweep, or
        # with group to its whole process group as scancel does) while point 0 is held at step
        # 10000; the function DURING NAME, if given, is called while it is held
        sweep_file "$1" 0.02
        GRANULE_TEST_PAUSE_AT_STEP=10000 setsid "$granule" sweep "$tmp/$1.ini" --jobs 1 >/dev/null 2>"$tmp/$1-1.log" &
        bg=$!
        for _ in $(seq 1 600); do # the point's folder exists once it runs; the pause holds it at step 10000
            [[ -f $tmp/$1/p0000/scene.ini ]] && break
            sleep 0.05
        done
        sleep 1
        [[ -n ${3-} ]] && "$3" "$1"
        if [[ ${2-} == group ]]; then
            kill -TERM -- "-$bg" 2>/dev/null # setsid made the sweep its group's leader
        else
            kill -TERM "$bg" 2>/dev/null
        fi
        wait "$bg" 2>/dev/null
        bg=
        for _ in $(seq 1 200); do
            grep -qs "stopped by a signal" "$tmp/$1-1.log" && break
            sleep 0.05
        done
        check grep -q "point 0: stopped by a signal at step 10000; checkpoint written" "$tmp/$1-1.log"
        check test -f "$tmp/$1/p0000/checkpoint"
        check test ! -f "$tmp/$1/p0000/summary.json"
    }
    stop_point0 stop
    out=$("$granule" sweep "$tmp/stop.ini" --jobs 1 2>"$tmp/stop2.log")
    check grep -q "6 run now, 0 already finished, 0 failed" <<<"$out"
    check grep -q "point 0: continuing from $tmp/stop/p0000/checkpoint" "$tmp/stop2.log"
    check test "$(grep -c "continuing from" "$tmp/stop2.log")" -eq 1
    check same "$tmp/serial" "$tmp/stop"
    # the same with the sweep and its run signalled together: the run's second SIGTERM (the sweep's
    # death) must not kill it before its checkpoint
    stop_point0 group group
    out=$("$granule" sweep "$tmp/group.ini" --jobs 1 2>"$tmp/group2.log")
    check grep -q "6 run now, 0 already finished, 0 failed" <<<"$out"
    check grep -q "point 0: continuing from $tmp/group/p0000/checkpoint" "$tmp/group2.log"
    check same "$tmp/serial" "$tmp/group"
    # a checkpoint that cannot be continued (here corrupt) is discarded, with its partial files, and
    # the point starts again
    stop_point0 corrupt
    printf '\xa5' | dd of="$tmp/corrupt/p0000/checkpoint" bs=1 seek=200 conv=notrunc status=none
    out=$("$granule" sweep "$tmp/corrupt.ini" --jobs 1 2>"$tmp/corrupt2.log")
    check grep -q "6 run now, 0 already finished, 0 failed" <<<"$out"
    check grep -q "point 0: starting again, its checkpoint cannot be continued: .*checksum mismatch" "$tmp/corrupt2.log"
    check test -z "$(ls "$tmp/corrupt/p0000" | grep '\.tmp')"
    check same "$tmp/serial" "$tmp/corrupt"
    # two sweeps over one folder share its points: while the first runs point 0, a second leaves
    # it to the first (the claim on p0000/.point.lock) and runs the other five, and --point 0 refuses to
    # touch it; the point then continues from the first sweep's checkpoint as before
    second_sweep() {
        cp "$tmp/$1/p0000/point.json" "$tmp/held.json"
        "$granule" sweep "$tmp/$1.ini" --point 0 >/dev/null 2>"$tmp/$1-point.log"
        check test $? -eq 1
        check grep -q "point 0 is being run by pid [0-9]* on .* since .*; left to it" "$tmp/$1-point.log"
        check cmp -s "$tmp/held.json" "$tmp/$1/p0000/point.json"
        second_out=$("$granule" sweep "$tmp/$1.ini" --jobs 2 2>"$tmp/$1-second.log")
        second_rc=$?
    }
    stop_point0 shared term second_sweep
    check test "$second_rc" -eq 1 # point 0 was not finished when the second sweep ended
    check grep -q "5 run now, 0 already finished, 0 failed, 1 left to other processes" <<<"$second_out"
    check grep -q "point 0 is being run by pid [0-9]* on .* since .*; left to it" "$tmp/shared-second.log"
    out=$("$granule" sweep "$tmp/shared.ini" --jobs 1 2>"$tmp/shared2.log")
    check grep -q "1 run now, 5 already finished, 0 failed" <<<"$out"
    check grep -q "point 0: continuing from $tmp/shared/p0000/checkpoint" "$tmp/shared2.log"
    check same "$tmp/serial" "$tmp/shared"

    # kill a sweep after its first point finished; the rerun runs only the unfinished points
    sweep_file kill 0.5
    [[ $quick == 1 ]] && sweep_file kill 0.25
    "$granule" sweep "$tmp/kill.ini" --jobs 1 >/dev/null 2>"$tmp/kill1.log" &
    bg=$!
    # kill it while point 1 runs (point 0 finished): waiting for point 0 alone could kill the sweep
    # between two points on a loaded machine, with no point left running
    for _ in $(seq 1 600); do
        grep -qs '"completed"' "$tmp/kill/p0000/point.json" && grep -qs '"running"' "$tmp/kill/p0001/point.json" && break
        sleep 0.05
    done
    kill -KILL "$bg" 2>/dev/null
    wait "$bg" 2>/dev/null
    bg=
    sleep 0.3 # the orphaned run gets SIGTERM from the kernel (PR_SET_PDEATHSIG)
    finished=()
    for k in 0 1 2 3 4 5; do
        d=$(printf "%s/kill/p%04d" "$tmp" "$k")
        if grep -qs '"completed"' "$d/point.json"; then
            finished+=("$k")
            cp "$d/point.json" "$tmp/kept-$k.json"
        fi
    done
    check test "${#finished[@]}" -ge 1
    check test "${#finished[@]}" -lt 6
    check grep -q '"running"' "$tmp/kill/p$(printf %04d "${#finished[@]}")/point.json"
    out=$("$granule" sweep "$tmp/kill.ini" --jobs 1 2>"$tmp/kill2.log")
    check grep -q "$((6 - ${#finished[@]})) run now, ${#finished[@]} already finished, 0 failed" <<<"$out"
    for k in "${finished[@]}"; do
        check grep -q "skipping finished point $k\$" "$tmp/kill2.log"
        check cmp -s "$tmp/kept-$k.json" "$(printf "%s/kill/p%04d/point.json" "$tmp" "$k")"
    done
    for k in 0 1 2 3 4 5; do
        [[ " ${finished[*]} " == *" $k "* ]] && continue
        check grep -q "^sweep: point $k completed" "$tmp/kill2.log"
    done
    # a third run finds nothing to do; changed settings make the finished points stale and rerun
    out=$("$granule" sweep "$tmp/kill.ini" --jobs 1 2>/dev/null)
    check grep -q "0 run now, 6 already finished" <<<"$out"
    sed -i 's/^run.duration = .*/run.duration = 0.02/' "$tmp/kill.ini"
    out=$("$granule" sweep "$tmp/kill.ini" --jobs 2 2>"$tmp/kill3.log")
    check grep -q "6 run now, 0 already finished" <<<"$out"
    check grep -q "point 0: run with other settings" "$tmp/kill3.log"
    # a folder holding the points of another, larger sweep file: refused; --force deletes them
    sweep_file foreign 0.01
    "$granule" sweep "$tmp/foreign.ini" --jobs 2 >/dev/null 2>&1
    sed -i 's/^system.N = .*/system.N = 20/' "$tmp/foreign.ini"
    "$granule" sweep "$tmp/foreign.ini" --jobs 2 >/dev/null 2>"$tmp/foreign.err"
    check test $? -eq 2
    check grep -q "holds 4 point folders (p0002..p0005) beyond this sweep's 2 points" "$tmp/foreign.err"
    check test -d "$tmp/foreign/p0005"
    check "$granule" sweep "$tmp/foreign.ini" --jobs 2 --force
    check test ! -e "$tmp/foreign/p0002"
    check test "$(ls -d "$tmp"/foreign/p* | wc -l)" -eq 2
elif [[ $part == mpi ]]; then
    if [[ $mpi_built != yes ]]; then
        echo "SKIP: granule was built without MPI (meson setup -Dmpi=enabled needs Debian's libopenmpi-dev openmpi-bin)"
        exit 77
    fi
    if ! command -v mpirun >/dev/null; then
        echo "FAILED: granule was built with MPI but mpirun is missing (apt-get install openmpi-bin)" >&2
        exit 1
    fi
    # Open MPI: allow root (containers, CI), two ranks on any core count, shared memory without ptrace
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
    export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_pml=ob1 OMPI_MCA_btl=self,vader
    # Open MPI's own allocations are not granule's leaks
    export ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0
    sweep_file serial 0.02
    check "$granule" sweep "$tmp/serial.ini" --jobs 1
    sweep_file mpi 0.02
    mpirun -n 2 "$granule" sweep "$tmp/mpi.ini" >"$tmp/mpi.out" 2>"$tmp/mpi.log"
    rc=$?
    check test $rc -eq 0
    [[ $rc -ne 0 ]] && cat "$tmp/mpi.log" >&2
    check grep -q "over 2 MPI ranks" "$tmp/mpi.log"
    check grep -q "6 run now, 0 already finished, 0 failed" "$tmp/mpi.out"
    check grep -q '"runner":.*"mpi rank 1 of 2"' "$tmp"/mpi/p000*/point.json
    check same "$tmp/serial" "$tmp/mpi"
    # rerun under MPI: nothing is redone
    mpirun -n 2 "$granule" sweep "$tmp/mpi.ini" >"$tmp/mpi2.out" 2>/dev/null
    check grep -q "0 run now, 6 already finished" "$tmp/mpi2.out"
else
    echo "usage: $0 GRANULE SOURCE_DIR resume|mpi [yes|no]" >&2
    exit 2
fi

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
