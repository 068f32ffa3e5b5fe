#!/usr/bin/env bash
# Exact restarts (docs/checkpoints.md): a run interrupted and resumed ends bit-identical to one
# that never stopped.
#   - 2D scene with every 2D observable and snapshots, 1D scene (com noise mode) with every 1D
#     observable: straight run vs run stopped by SIGTERM (exit 5) + --resume, vs a run stopped
#     again and again by --wall-limit (exit 4) + --resume, vs kill -9 after a checkpoint +
#     --resume; summary.json (wall-time and checkpoint-count lines excepted), every CSV and every
#     snapshot compared byte for byte
#   - the event-driven and hybrid integrators (1D, N = 100): SIGTERM + --resume and repeated
#     --wall-limit stops + --resume, compared the same way
#   - walls and gravity (a 2D bed under gravity with the random force; spheres between z walls,
#     SIGTERM only): the same two
#   - 3D spheres with the tangential spring, rotation and rolling: repeated --wall-limit stops
#   - 3D hard spheres, event-driven, smooth (SIGTERM and --wall-limit) and rough (SIGTERM: the
#     spin vectors)
#   - refusals: flipped byte (checksum), truncated file, other format version, not a checkpoint,
#     different scene (names the key), finished run, missing checkpoint, fresh run over an
#     interrupted one without --force, a run or --resume into the folder of a run still going
#   - an unstable scene stops with exit 3, keeps its earlier outputs and its last checkpoint
#     (which still loads, and reproduces the same instability)
#
# usage: tests/test_resume.sh path/to/granule
# GRANULE_TEST_QUICK=1 (the sanitizer build) shortens the runs.
set -euo pipefail

if [[ $# -lt 1 || ! -x "$1" ]]; then
    echo "usage: $0 path/to/granule" >&2
    exit 2
fi
G=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
TMP=$(mktemp -d "${TMPDIR:-/tmp}/granule-test-resume-XXXXXX")
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null || true; done
    rm -rf "$TMP"
}
trap cleanup EXIT
export CI=1
cd "$TMP"

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok   $1"; }
fail() { failed=$((failed + 1)); echo "FAIL $1"; [[ $# -gt 1 ]] && printf '     %s\n' "${@:2}"; return 0; }

run() {
    set +e
    "$@" >"$TMP/stdout" 2>"$TMP/stderr"
    rc=$?
    set -e
    err=$(cat "$TMP/stderr")
}

quick=${GRANULE_TEST_QUICK:-0}
if [[ $quick == 1 ]]; then n2=120 n1=100 dur2=0.03 dur1=0.03; else n2=300 n1=200 dur2=0.05 dur1=0.06; fi

# 2D: N = 300 (quick: 120), every 2D observable, snapshots; 5000 steps per sample
cat >s2.ini <<EOF
[system]
dim = 2
N = $n2
packing_fraction = 0.4
[model]
normal = spring_dashpot
tangential = tangential_dashpot
eps_n = 0.6
eps_t = 0.6
[noise]
D = 1e-8
[integrator]
dt = 1e-6
[run]
warmup = 0.005
duration = $dur2
sample_every = 5e-3
checkpoint_wall = 0
[analysis]
observables = moments, freepath, postcollision, sk, pair, pv
[output]
plots = false
snapshot_every = 0.01
EOF
# 1D: N = 200 (quick: 100) on a ring, com noise mode (centre-of-mass resets on a step schedule)
cat >s1.ini <<EOF
[system]
dim = 1
N = $n1
reduced_length = 0.5
[placement]
kind = uniform
[model]
normal = spring_dashpot
eps_n = 0.5
[noise]
D = 1e-8
mode = com
com_interval = 3e-4
[integrator]
dt = 1e-6
[run]
warmup = 0.01
duration = $dur1
sample_every = 2e-3
checkpoint_wall = 0
[analysis]
observables = moments, freepath, postcollision, gaps, pv
[output]
plots = false
snapshot_every = 0.02
EOF

# same DIR_A DIR_B: summary.json (wall-time and checkpoint lines and the folder name excepted),
# every CSV and snapshot byte for byte
same() {
    local a=$1 b=$2 f rel
    local skip='wall_seconds|_per_second|checkpoint|"dir"'
    if ! diff <(grep -Ev "$skip" "$a/summary.json") <(grep -Ev "$skip" "$b/summary.json") >"$TMP/diff"; then
        echo "summary.json differs: $(head -4 "$TMP/diff" | tr '\n' ' ')"
        return 1
    fi
    for f in "$a"/*.csv "$a"/snapshots/*; do
        rel=${f#"$a"/}
        [[ -e $f ]] || continue
        if ! cmp -s "$f" "$b/$rel"; then
            echo "$rel differs"
            return 1
        fi
    done
    if ls "$b" | grep -q '\.tmp'; then
        echo "temporary files left in $b: $(ls "$b" | grep '\.tmp' | tr '\n' ' ')"
        return 1
    fi
    return 0
}

# wait_for FILE PID: until FILE exists (or the process ended)
wait_for() {
    for _ in $(seq 1 600); do
        [[ -e $1 ]] && return 0
        kill -0 "$2" 2>/dev/null || return 1
        sleep 0.02
    done
    return 1
}

# busy_case NAME SCENE DIR: while a run writes DIR, another run into DIR (with or without --force)
# and a --resume of DIR are refused (exit 2) naming the run still going; sigterm_case then checks
# that the first run ends as if nothing had happened
busy_case() {
    local name=$1 scene=$2 dir=$3 ok=1 msgs=""
    for args in "run $scene --out $dir --quiet" "run $scene --out $dir --force --quiet" "run --resume $dir --quiet"; do
        # shellcheck disable=SC2086
        run "$G" $args
        if [[ $rc -ne 2 ]] || ! grep -q "output folder $dir is in use by a run still going (pid [0-9]* on .* since .*)" <<<"$err"; then
            ok=0
            msgs+="granule $args: exit $rc: $err; "
        fi
    done
    if [[ $ok == 1 ]] && grep -q "nothing to resume until it stops" <<<"$err"; then
        pass "$name: a second run or a --resume into the folder of a run still going is refused (exit 2)"
    else
        fail "$name: a run or resume into a busy folder" "$msgs" "$err"
    fi
}

# sigterm_case NAME TAG SCENE PAUSE_STEP EVERY PAUSE_SECONDS: a run paused at PAUSE_STEP
# (GRANULE_TEST_PAUSE_AT_STEP) gets SIGTERM once a checkpoint exists: exit 5, checkpoint kept, no
# summary; --resume finishes it bit-identical to refTAG
sigterm_case() {
    local name=$1 tag=$2 scene=$3 pause=$4 every=$5 delay=$6 pid
    GRANULE_TEST_PAUSE_AT_STEP=$pause "$G" run "$scene" --out term$tag --quiet --set run.checkpoint_every="$every" >/dev/null 2>"$TMP/term.err" &
    pid=$!
    pids+=("$pid")
    if wait_for "term$tag/checkpoint" "$pid"; then
        busy_case "$name" "$scene" "term$tag"
        sleep "$delay"
        kill -TERM "$pid" 2>/dev/null || true
    fi
    set +e
    wait "$pid"
    rc=$?
    set -e
    if [[ $rc -eq 5 && -s term$tag/checkpoint && ! -e term$tag/summary.json ]] && grep -q "resume" "$TMP/term.err"; then
        pass "$name: SIGTERM writes a checkpoint and exits 5"
    else
        fail "$name: SIGTERM: exit $rc (want 5; the run may have finished before the signal)" "$(cat "$TMP/term.err")"
    fi
    run "$G" run --resume term$tag --quiet
    if [[ $rc -eq 0 ]] && msg=$(same ref$tag term$tag); then
        pass "$name: run + SIGTERM + resume equals the uninterrupted run bit for bit"
    else
        fail "$name: SIGTERM + resume (exit $rc)" "$err" "${msg:-}"
    fi
    # the lock ends with the run: a finished folder holds no .run.lock (issue 38)
    if [[ ! -e term$tag/.run.lock && ! -e ref$tag/.run.lock ]]; then
        pass "$name: no .run.lock left in the finished folders"
    else
        fail "$name: a finished folder keeps its .run.lock" "$(ls -la term$tag ref$tag | grep lock)"
    fi
}

# wall_case NAME TAG SCENE TICK CHUNK LIMIT PER: stop with exit 4 under --wall-limit LIMIT and
# resume, again and again, until done (test clock GRANULE_TEST_CLOCK_TICK = TICK, chunks of at
# most CHUNK steps, so most stops fall between two samples of PER steps); the result must equal refTAG
wall_case() {
    local name=$1 tag=$2 scene=$3 tick=$4 chunk=$5 wl=$6 per=$7 sessions=0 mid=0 step
    local -a what=(run "$scene" --out wall$tag)
    rc=4
    while [[ $rc -eq 4 && $sessions -lt 60 ]]; do
        run env GRANULE_TEST_CLOCK_TICK="$tick" GRANULE_CHUNK_STEPS="$chunk" "$G" "${what[@]}" --quiet --wall-limit "$wl"
        what=(run --resume wall$tag)
        sessions=$((sessions + 1))
        step=$(grep -o 'at step [0-9]*' <<<"$err" | grep -o '[0-9]*' || true)
        if [[ -n $step && $per -gt 0 ]] && ((step % per != 0)); then mid=$((mid + 1)); fi
    done
    if [[ $rc -eq 0 && $sessions -ge 2 && $mid -ge 1 ]] && msg=$(same ref$tag wall$tag); then
        pass "$name: $sessions sessions under --wall-limit (exit 4 each; $mid stopped between samples) equal the uninterrupted run"
    else
        fail "$name: --wall-limit sessions: $sessions ($mid between samples), last exit $rc (want 0 after >= 2, >= 1 between samples)" "$err" "${msg:-}"
    fi
}

for d in 2 1; do
    scene=s$d.ini
    run "$G" run "$scene" --out ref$d --quiet
    [[ $rc -eq 0 ]] || fail "${d}D reference run exits $rc" "$err"
    # the background runs below pause halfway (GRANULE_TEST_PAUSE_AT_STEP) until they are signalled
    # or killed, so they are still running when the signal comes, on a machine of any speed
    half=$(( $(grep -o '"steps":[[:space:]]*[0-9]*' ref$d/summary.json | grep -o '[0-9]*$') / 2 ))

    sigterm_case "${d}D" "$d" "$scene" "$half" 0.004 0.1

    # a wall-time budget: stop with exit 4 and resume, again and again, until done
    if [[ $d == 2 ]]; then
        wall_case "2D" 2 "$scene" 0.01 777 1.5 5000
    else
        wall_case "1D" 1 "$scene" 0.002 777 1.15 2000
    fi

    # kill -9 after a checkpoint: the rows and snapshots written after it are redone identically
    GRANULE_TEST_PAUSE_AT_STEP=$half "$G" run "$scene" --out kill$d --quiet --set run.checkpoint_every=0.004 >/dev/null 2>&1 &
    pid=$!
    pids+=("$pid")
    if wait_for "kill$d/checkpoint" "$pid"; then sleep 0.15; kill -9 "$pid" 2>/dev/null || true; fi
    set +e
    { wait "$pid"; } 2>/dev/null
    rc=$?
    set -e
    if [[ $rc -ne 137 ]]; then
        fail "${d}D: kill -9 did not hit the running process (exit $rc)"
    fi
    run "$G" run --resume kill$d --quiet
    if [[ $rc -eq 0 ]] && msg=$(same ref$d kill$d); then
        pass "${d}D: kill -9 after a checkpoint + resume equals the uninterrupted run"
    else
        fail "${d}D: kill -9 + resume (exit $rc)" "$err" "${msg:-}"
    fi
done

# 3D spheres with the tangential spring, rotation and rolling (docs/three-dimensions.md): the spin
# vectors, torques and history vectors travel through the checkpoint; repeated --wall-limit stops
# + --resume equal the uninterrupted run
cat >s3.ini <<EOF
[system]
dim = 3
N = 343
packing_fraction = 0.25
[placement]
v0 = 0.3
omega0 = 200
[model]
normal = spring_dashpot
eps_n = 0.9
tangential = tangential_spring
mu = 0.5
rotation = true
rolling = rolling_friction
mu_r = 0.05
[noise]
D = 1e-8
[integrator]
dt = 1e-6
[run]
warmup = 0.002
duration = 0.01
sample_every = 1e-3
checkpoint_wall = 0
[output]
plots = false
snapshot_every = 0.005
EOF
run "$G" run s3.ini --out ref3 --quiet
[[ $rc -eq 0 ]] || fail "3D reference run exits $rc" "$err"
wall_case "3D friction + rotation + rolling" 3 s3.ini 0.01 777 1.5 1000

# [noise] precision = single (the 1D scene): repeated --wall-limit stops + --resume equal the
# uninterrupted run; the resumed sessions keep the precision (scene.ini carries it)
sed 's/^mode = com$/mode = symmetrised\nprecision = single/' s1.ini >s1f.ini
run "$G" run s1f.ini --out ref1f --quiet
if [[ $rc -ne 0 ]] || ! grep -q '"precision":[[:space:]]*"single"' ref1f/summary.json; then
    fail "1D single precision: reference run exits $rc or does not record the precision" "$err"
fi
wall_case "1D single precision" 1f s1f.ini 0.002 777 1.15 2000

# ---------- the event-driven and hybrid integrators ----------
# docs/scenes/rfm-1d-event.ini (kick_interval 2e-5 s, so that stepping, not sampling, takes most
# of the time and stops fall between samples) and rfm-1d-hybrid.ini shrunk to N = 100 and short
# runs, with every 1D observable: straight run vs SIGTERM (exit 5) + --resume and vs repeated --wall-limit stops
# (exit 4) + --resume, compared as above. The event-driven state is mid-window at every call
# boundary (per-particle base times, the window's noise, the calendar); the hybrid's windows must
# fall at the same steps however the run is cut into calls.
if [[ $quick == 1 ]]; then dure=0.5 durh=0.3; else dure=1.0 durh=0.8; fi
common='[system]
dim = 1
N = 100
reduced_length = 1.0
radius = 1.5e-3
mass = 3.53e-5
[placement]
kind = uniform
v0 = 0.1
[noise]
D = 1e-8
mode = symmetrised
[analysis]
observables = moments, freepath, postcollision, gaps, pv'
cat >se.ini <<EOF
$common
[output]
plots = false
snapshot_every = 0.25
[model]
normal = hard_sphere
k_s = 5e5
eps_n = 0.1
[integrator]
kind = event
free_flight = exact
kick_interval = 2e-5
[run]
warmup = 0.05
duration = $dure
sample_every = 2e-3
checkpoint_wall = 0
EOF
cat >sh.ini <<EOF
$common
[output]
plots = false
snapshot_every = 0.1
[model]
normal = spring_dashpot
tangential = none
k_s = 5e5
eps_n = 0.1
clamp = false
[integrator]
kind = hybrid
dt = 1e-6
kick_interval = 3e-5
free_flight = exact
[run]
warmup = 0.01
duration = $durh
sample_every = 1e-3
checkpoint_wall = 0
EOF
for d in e h; do
    name=$([[ $d == e ]] && echo "event-driven" || echo "hybrid")
    scene=s$d.ini
    run "$G" run "$scene" --out ref$d --quiet
    [[ $rc -eq 0 ]] || fail "$name reference run exits $rc" "$err"
    # steps per sample, for telling stops between samples
    steps=$(grep -o '"steps":[[:space:]]*[0-9]*' ref$d/summary.json | grep -o '[0-9]*$' || echo 0)
    per=$(awk -v n="$steps" -v t="$([[ $d == e ]] && echo "$dure 0.05 2e-3" || echo "$durh 0.01 1e-3")" \
        'BEGIN { split(t, a, " "); printf "%d", n / int((a[1] + a[2]) / a[3] + 0.5) }')

    sigterm_case "$name" "$d" "$scene" $((steps / 2)) 0.002 0

    # a machine-independent clock (GRANULE_TEST_CLOCK_TICK) sized for about ten sessions
    # (a chunk costs about 3 readings, a session may use 0.05 s minus 2 chunks and 2 checkpoints:
    #  c chunks of up to 97 steps per session need tick = 0.05 / (3 c + 6); aim at ~8 sessions)
    tick=$(awk -v s="$steps" 'BEGIN { c = s / 640; if (c < 1) c = 1; printf "%.3g", 0.05 / (3 * c + 6) }')
    wall_case "$name" "$d" "$scene" "$tick" 97 1.05 "$per"
done

# ---------- walls and gravity (docs/systems-walls-gravity.md) ----------
# a 2D bed between walls at y = 0 and L under gravity, x periodic, driven by the random force and
# a sawtooth floor, rotating grains with the tangential spring (its per-wall history), the walls'
# own eps_n and mu: its ledger has the potential energy, the wall springs and the floor's
# wall_work, summary.json the walls' mean forces; SIGTERM + --resume and repeated --wall-limit
# stops + --resume end bit-identical to the straight run
if [[ $quick == 1 ]]; then durw=0.01; else durw=0.02; fi
cat >sw.ini <<EOF
[system]
dim = 2
N = 150
L = 0.08
[placement]
kind = uniform
v0 = 0.2
[model]
eps_n = 0.7
tangential = tangential_spring
rotation = true
[noise]
D = 1e-8
[boundary]
y = walls
vibrate = y
amplitude = 5e-4
frequency = 50
motion = sawtooth
eps_n = 0.8
mu = 0.3
[gravity]
gy = -9.81
[analysis]
observables = moments
[output]
plots = false
[run]
warmup = 0.002
duration = $durw
sample_every = 1e-3
checkpoint_wall = 0
EOF
run "$G" run sw.ini --out refw --quiet
[[ $rc -eq 0 ]] || fail "walls+gravity reference run exits $rc" "$err"
steps=$(grep -o '"steps":[[:space:]]*[0-9]*' refw/summary.json | grep -o '[0-9]*$' || echo 0)
per=$(awk -v n="$steps" -v t="$durw" 'BEGIN { printf "%d", n / int((t + 0.002) / 1e-3 + 0.5) }')
sigterm_case "walls+gravity" w sw.ini $((steps / 2)) 0.004 0.1
tick=$(awk -v s="$steps" 'BEGIN { c = s / 640; if (c < 1) c = 1; printf "%.3g", 0.05 / (3 * c + 6) }')
wall_case "walls+gravity" w sw.ini "$tick" 97 1.05 "$per"
# a bed of hard discs, event-driven: exact parabolas, wall hits with the walls' own eps_n (their
# count is in the checkpoint only when the run has walls), exact free flight under the noise
cat >swe.ini <<EOF
[system]
dim = 2
N = 150
L = 0.08
[placement]
kind = uniform
v0 = 0.2
[model]
normal = hard_sphere
eps_n = 0.7
eps_t = 1
[noise]
D = 1e-8
[boundary]
y = walls
eps_n = 0.8
[gravity]
gy = -9.81
[integrator]
kind = event
[analysis]
observables = moments
[output]
plots = false
[run]
warmup = 0.002
duration = $durw
sample_every = 1e-3
checkpoint_wall = 0
EOF
run "$G" run swe.ini --out refwe --quiet
[[ $rc -eq 0 ]] || fail "event walls+gravity reference run exits $rc" "$err"
steps=$(grep -o '"steps":[[:space:]]*[0-9]*' refwe/summary.json | grep -o '[0-9]*$' || echo 0)
sigterm_case "event walls+gravity" we swe.ini $((steps / 2)) 0.004 0.1
# spheres between walls at z = 0 and L under gz (issue 35): the 3D walls' history vectors of the
# tangential spring, rotation, a sawtooth floor and the random force; walls.csv has z_0 and z_L
cat >sw3.ini <<EOF
[system]
dim = 3
N = 150
L = 0.025
[placement]
kind = random
v0 = 0.2
[model]
eps_n = 0.7
k_s = 5e4
tangential = tangential_spring
rotation = true
[noise]
D = 1e-8
[boundary]
z = walls
vibrate = z
amplitude = 5e-4
frequency = 50
motion = sawtooth
mu = 0.3
[gravity]
gz = -9.81
[analysis]
observables = moments
[output]
plots = false
[run]
warmup = 0.002
duration = $durw
sample_every = 1e-3
checkpoint_wall = 0
EOF
run "$G" run sw3.ini --out refw3 --quiet
[[ $rc -eq 0 ]] || fail "3D walls+gravity reference run exits $rc" "$err"
steps=$(grep -o '"steps":[[:space:]]*[0-9]*' refw3/summary.json | grep -o '[0-9]*$' || echo 0)
sigterm_case "3D walls+gravity" w3 sw3.ini $((steps / 2)) 0.004 0.1
# smooth hard spheres in 3D, event-driven (issue 35): exact free flight with three noise
# components, cell crossings on the 3D grid, eps_t on the tangential relative velocity, snapshots
cat >s3e.ini <<EOF
[system]
dim = 3
N = 300
packing_fraction = 0.1
[placement]
kind = random
v0 = 0.2
[model]
normal = hard_sphere
eps_n = 0.8
eps_t = 0.6
[noise]
D = 1e-8
[integrator]
kind = event
free_flight = exact
[analysis]
observables = moments
[output]
plots = false
snapshot_every = 0.005
[run]
warmup = 0.002
duration = $durw
sample_every = 1e-3
checkpoint_wall = 0
EOF
run "$G" run s3e.ini --out ref3e --quiet
[[ $rc -eq 0 ]] || fail "3D event reference run exits $rc" "$err"
steps=$(grep -o '"steps":[[:space:]]*[0-9]*' ref3e/summary.json | grep -o '[0-9]*$' || echo 0)
per=$(awk -v n="$steps" -v t="$durw" 'BEGIN { printf "%d", n / int((t + 0.002) / 1e-3 + 0.5) }')
sigterm_case "3D event" 3e s3e.ini $((steps / 2)) 0.004 0.1
tick=$(awk -v s="$steps" 'BEGIN { c = s / 640; if (c < 1) c = 1; printf "%.3g", 0.05 / (3 * c + 6) }')
wall_case "3D event" 3e s3e.ini "$tick" 97 1.05 "$per"
# rough hard spheres in 3D (Walton's beta with a Coulomb limit): the spin vectors go through the
# checkpoint; temperature.csv has T_rot
sed -e 's/^eps_t = 0.6$/rotation = true\nbeta = 0.5\nbeta_mu = 0.3/' -e 's/^v0 = 0.2$/v0 = 0.2\nomega0 = 200/' s3e.ini >s3r.ini
grep -q '^beta_mu = 0.3$' s3r.ini && grep -q '^omega0 = 200$' s3r.ini || fail "3D rough event scene not written" "$(cat s3r.ini)"
run "$G" run s3r.ini --out ref3r --quiet
[[ $rc -eq 0 ]] || fail "3D rough event reference run exits $rc" "$err"
head -1 ref3r/temperature.csv | grep -q T_rot || fail "3D rough event: no T_rot in temperature.csv" "$(head -1 ref3r/temperature.csv)"
steps=$(grep -o '"steps":[[:space:]]*[0-9]*' ref3r/summary.json | grep -o '[0-9]*$' || echo 0)
sigterm_case "3D rough event" 3r s3r.ini $((steps / 2)) 0.004 0.1

# ---------- refusals ----------
# an interrupted run to corrupt (copied fresh for each case)
GRANULE_TEST_CLOCK_TICK=0.01 "$G" run s2.ini --out base --quiet --set run.checkpoint_every=0.004 --wall-limit 1.2 >/dev/null 2>&1 || true
if [[ ! -s base/checkpoint || -e base/summary.json ]]; then
    fail "could not make an interrupted run to corrupt"
fi
size=$(stat -c %s base/checkpoint)
refused() { # NAME PATTERN: the resume of case/ fails with exit 2 and a message matching PATTERN
    run "$G" run --resume case --quiet
    if [[ $rc -eq 2 && $err == *"$2"* ]]; then
        pass "$1 is refused: ${err:0:150}"
    else
        fail "$1: exit $rc (want 2 and '$2')" "$err"
    fi
    if [[ -e case/summary.json ]]; then fail "$1: a refused resume wrote summary.json"; fi
}
fresh() { rm -rf case; cp -r base case; }

fresh
printf '\xff' | dd of=case/checkpoint bs=1 seek=$((size / 2)) conv=notrunc status=none
orig=$(dd if=base/checkpoint bs=1 skip=$((size / 2)) count=1 status=none | od -An -tx1 | tr -d ' ')
if [[ $orig == ff ]]; then printf '\x00' | dd of=case/checkpoint bs=1 seek=$((size / 2)) conv=notrunc status=none; fi
refused "a flipped byte" "checksum mismatch"

fresh
truncate -s $((size - 100)) case/checkpoint
refused "a truncated checkpoint" "truncated at byte $((size - 100)) of $size"

fresh
truncate -s 20 case/checkpoint
refused "a checkpoint cut inside its header" "truncated at byte 20"

fresh
printf '\x63' | dd of=case/checkpoint bs=1 seek=8 conv=notrunc status=none
refused "another format version" "format version 99"

fresh
echo "not a checkpoint" >case/checkpoint
refused "a foreign file" "not a granule checkpoint"

fresh
rm case/checkpoint
refused "a missing checkpoint" "cannot open the checkpoint"

fresh
run "$G" run --resume case --quiet --set model.eps_n=0.5
if [[ $rc -eq 2 && $err == *"[model] eps_n = 0.59999999999999998 in the checkpoint, 0.5 now"* ]]; then
    pass "a different scene is refused, naming the key: ${err:0:160}"
else
    fail "a different scene: exit $rc" "$err"
fi
fresh
run "$G" run --resume case --quiet --set noise.precision=single
if [[ $rc -eq 2 && $err == *"[noise] precision = (unset) in the checkpoint, single now"* ]]; then
    pass "a change of [noise] precision is refused, naming the key: ${err:0:160}"
else
    fail "a change of [noise] precision: exit $rc" "$err"
fi
fresh
sed -i 's/^seed = .*/seed = 7/' case/scene.ini
refused "an edited scene.ini" "[run] seed = 1 in the checkpoint, 7 now"

fresh
run "$G" run s2.ini --out case --quiet
if [[ $rc -eq 2 && $err == *"--resume"* && -s case/checkpoint ]]; then
    pass "a fresh run over an interrupted one is refused without --force"
else
    fail "a fresh run over an interrupted one: exit $rc" "$err"
fi
had_partials=$(ls case | grep -c '\.tmp[0-9]' || true)
run "$G" run s2.ini --out case --quiet --force
if [[ $rc -eq 0 && $had_partials -gt 0 && ! -e case/checkpoint && -s case/summary.json ]] && ! ls case | grep -q '\.tmp'; then
    pass "--force over an interrupted run discards its checkpoint and its $had_partials partial files"
else
    fail "--force over an interrupted run: exit $rc, $had_partials partial files before, now: $(ls case | tr '\n' ' ')" "$err"
fi

run "$G" run --resume ref2 --quiet
if [[ $rc -eq 2 && $err == *"has finished"* ]]; then
    pass "resuming a finished run is refused (its results are kept)"
else
    fail "resuming a finished run: exit $rc" "$err"
fi

# ---------- the instability guard keeps outputs and the last checkpoint ----------
cat >u.ini <<EOF
[system]
dim = 2
N = 200
packing_fraction = 0.5
[model]
normal = spring_dashpot
eps_n = 0.9
[noise]
D = 1e-6
[integrator]
dt = 1e-5
force_dt = true
[run]
warmup = 0
duration = 0.2
sample_every = 1e-4
checkpoint_every = 2e-4
ledger_tolerance = 0
[output]
plots = false
snapshot_every = 2e-4
EOF
run "$G" run u.ini --out unstable --quiet
if [[ $rc -eq 3 && $err == *"unstable run"* && -s unstable/checkpoint && -s unstable/temperature.csv &&
      -s unstable/snapshots/snap_000000.xyz ]] && grep -q '"status":.*"unstable"' unstable/summary.json; then
    pass "an unstable run exits 3 and keeps its outputs and last checkpoint"
else
    fail "unstable run: exit $rc" "$err" "$(ls unstable 2>&1 | tr '\n' ' ')"
fi
diag=$(grep -o 'particles [0-9]* and [0-9]* overlap by [0-9.]* d at step [0-9]*' <<<"$err" || true)
cp unstable/checkpoint "$TMP/unstable.ckpt"
run "$G" run --resume unstable --quiet
if [[ $rc -eq 2 && $err == *"status unstable"* ]] && cmp -s unstable/checkpoint "$TMP/unstable.ckpt"; then
    pass "the unstable run's folder refuses a resume and its checkpoint is untouched"
else
    fail "resume of an unstable run: exit $rc" "$err"
fi
rm unstable/summary.json
run "$G" run --resume unstable --quiet
if [[ $rc -eq 3 && -n $diag ]] && grep -q "$diag" unstable/summary.json; then
    pass "the kept checkpoint is valid: resumed, it meets the same instability ($diag)"
else
    fail "resuming from the unstable run's checkpoint: exit $rc" "$err"
fi

# SIGTERM in the first milliseconds (issue 39 item 14): granule catches it before anything else,
# so a signal either stops the run with a checkpoint (exit 5) or, while the shared libraries are
# still loading, ends the process before it has written anything (exit 143, no folder); never a
# folder without a checkpoint to continue from (docs/checkpoints.md, "Exit status")
early_bad=()
early_scene="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/docs/scenes/rfm-2d.ini"
for ms in 0 2 4 6 8 10 12 15 20 30 50 80; do
    d="$TMP/early-term-$ms"
    "$G" run "$early_scene" --out "$d" --quiet >/dev/null 2>&1 &
    pid=$!
    sleep "$(printf '0.%03d' "$ms")"
    kill -TERM "$pid" 2>/dev/null || true
    rc=0
    wait "$pid" || rc=$?
    if ! { [[ $rc == 5 && -f $d/checkpoint ]] || [[ $rc == 143 && ! -e $d ]]; }; then
        early_bad+=("SIGTERM after $ms ms: exit $rc, folder: $(ls "$d" 2>&1 | tr '\n' ' ' | head -c 200)")
    fi
done
if ((${#early_bad[@]} == 0)); then
    pass "SIGTERM in the first 0-80 ms: exit 5 with a checkpoint, or 143 with nothing written"
else
    fail "SIGTERM in the first milliseconds" "${early_bad[@]}"
fi

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
