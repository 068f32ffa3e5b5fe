#!/usr/bin/env bash
# Ctrl-C at a terminal (issue 38): SIGINT reaches the whole foreground process group. `granule
# sweep` (1 and 2 parallel runs) must stop its running points with checkpoints, mark them
# stopped, say how to continue and exit 5; the same command then continues them from their
# checkpoints. `granule run` does the same for its one run, `granule compare` for its running
# model (continued by --resume, equal to an uninterrupted comparison); `granule cost`, which has
# nothing to continue, stops at once and writes nothing. Driven through a real
# pseudo-terminal (tests/pty_interrupt.py).
# usage: test_ctrl_c.sh GRANULE SOURCE_DIR
source "$(dirname "$0")/cli_test_lib.sh"
pty() { python3 "$SRC/tests/pty_interrupt.py" "$@"; }

for jobs in 1 2; do
    out="$tmp/sweep$jobs"
    cat >"$tmp/s$jobs.ini" <<EOT
[sweep]
scene = $SRC/docs/scenes/rfm-1d.ini
out = $out
seeds = 1, 2
[vary]
system.N = 100
[set]
run.warmup = 0
run.duration = 1000
output.plots = false
output.snapshot_every = 0
EOT
    # Ctrl-C half a second after the first point wrote its first table
    pty "$out/p0000/scene.ini" 0.5 "$G" sweep "$tmp/s$jobs.ini" --jobs $jobs >"$tmp/log$jobs" 2>&1
    rc=$?
    check test $rc -eq 5
    check grep -q "stopped by a signal: $jobs point.* stopped with a checkpoint; run the same command to continue" "$tmp/log$jobs"
    for k in $(seq 0 $((jobs - 1))); do
        check test -f "$out/p000$k/checkpoint"
        check grep -q '"status":[[:space:]]*"stopped"' "$out/p000$k/point.json"
    done
    check test ! -e "$out/p0000/checkpoint.tmp"
    [[ $rc -eq 5 ]] || cat "$tmp/log$jobs" >&2
    # the same command continues the stopped points from their checkpoints
    pty "$out/p0000/point.json" 1.0 "$G" sweep "$tmp/s$jobs.ini" --jobs $jobs >"$tmp/again$jobs" 2>&1
    check grep -q "point 0: continuing from $out/p0000/checkpoint" "$tmp/again$jobs"
done

# granule run: the same promise for one run
pty "$tmp/run/scene.ini" 0.5 "$G" run "$SRC/docs/scenes/rfm-1d.ini" --out "$tmp/run" --set run.duration=1000 \
    --set output.plots=false >"$tmp/runlog" 2>&1
check test $? -eq 5
check test -f "$tmp/run/checkpoint"
check grep -q -- "--resume" "$tmp/runlog"

# granule compare: the running model stops with a checkpoint; --resume keeps the finished ones,
# continues it, and the comparison equals an uninterrupted one
cmp_args=("$SRC/docs/scenes/rfm-1d.ini" --models spring_dashpot,spring_dashpot@clamp --set run.duration=2 --set system.N=100
    --set output.plots=false)
pty "$tmp/cmp/spring_dashpot/scene.ini" 0.3 "$G" compare "${cmp_args[@]}" --out "$tmp/cmp" >"$tmp/cmplog" 2>&1
check test $? -eq 5
check test -f "$tmp/cmp/spring_dashpot/checkpoint"
check grep -q "run the same command with --resume" "$tmp/cmplog"
"$G" compare "${cmp_args[@]}" --out "$tmp/cmp" >/dev/null 2>"$tmp/cmplog2"
check test $? -eq 2 # a stopped comparison is not overwritten by accident
check grep -q -- "--resume to continue it" "$tmp/cmplog2"
"$G" compare "${cmp_args[@]}" --out "$tmp/cmp" --resume >/dev/null 2>"$tmp/cmplog3"
check test $? -eq 0
check grep -q "continuing from its checkpoint" "$tmp/cmplog3"
"$G" compare "${cmp_args[@]}" --out "$tmp/cmp-ref" >/dev/null 2>&1
for m in spring_dashpot spring_dashpot_clamp; do
    check test "$(grep '"T_mean"' "$tmp/cmp/$m/summary.json")" = "$(grep '"T_mean"' "$tmp/cmp-ref/$m/summary.json")"
done

# granule cost: nothing to continue; it stops at once, says so and writes nothing
pty - 2 "$G" cost "$SRC/docs/scenes/rfm-1d.ini" --calibrate 60 --out "$tmp/cost" >"$tmp/costlog" 2>&1
check test $? -eq 5
check grep -q "cost: stopped by a signal before anything was written" "$tmp/costlog"
check test ! -e "$tmp/cost/cost.json"

finish
