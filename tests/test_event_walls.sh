#!/usr/bin/env bash
# Walls and gravity in the event-driven integrator (docs/systems-walls-gravity.md, "Event-driven"):
#  1. docs/scenes/bouncing-grain-event.ini (one disc dropped from 0.1 m, eps_n = 0.9, no TC):
#     the free fall is exact, kinetic energy M g^2 t^2 / 2 before the first impact; every bounce
#     keeps exactly eps_n^2 of the impact energy (the losses of successive bounces fall by eps_n^2,
#     so the apex heights do too); the ledger closes: kinetic + potential + dissipated = initial.
#     With the walls' own [boundary] eps_n = 0.5 the losses fall by 0.25 per bounce (0.36 s: the
#     bounces pile up towards an inelastic collapse at 0.425 s, which without TC stops the run:
#  1b. that collapse is stopped by the event-rate guard, naming the grain and the wall).
#  2. The same with eps_n = 1 and 8 discs in a box with walls on both axes, given a sideways
#     speed: kinetic + potential is conserved and no centre ever leaves [r, L - r].
#  3. A run stopped by SIGTERM mid-run and resumed equals the uninterrupted one; so does a bed of 40
#     discs on a vibrating floor (event-driven moving wall, its work in the checkpoint).
#  (A vibrating floor, rough and viscoelastic grains and 1D rods between walls:
#  tests/test_event_vibrate.c.)
# usage: test_event_walls.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scene=$src/docs/scenes/bouncing-grain-event.ini
"$granule" run "$scene" --out "$tmp/b" --set output.plots=false >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: run bouncing grain" >&2; exit 1; }
"$granule" run "$scene" --out "$tmp/box" --set output.plots=false --set system.N=8 \
    --set boundary.x=walls --set model.eps_n=1 --set placement.kind=uniform --set placement.v0=2 \
    --set run.duration=2 --set output.snapshot_every=0.05 >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: run box" >&2; exit 1; }
"$granule" run "$scene" --out "$tmp/own" --set output.plots=false --set boundary.eps_n=0.5 --set run.duration=0.36 \
    >/dev/null 2>"$tmp/log" || { cat "$tmp/log" >&2; echo "FAIL: run wall eps_n" >&2; exit 1; }
if "$granule" run "$scene" --out "$tmp/collapse" --set output.plots=false --set boundary.eps_n=0.5 \
    >/dev/null 2>"$tmp/log" || ! grep -q "of particle 0 on a wall" "$tmp/log"; then
    cat "$tmp/log" >&2; echo "FAIL: the inelastic collapse on the floor is not diagnosed" >&2; exit 1
fi
echo "collapse on the floor: $(grep -o 'the event rate diverges.*on a wall' "$tmp/log" | head -c 200)"
/usr/bin/python3 - "$tmp/b" "$tmp/box" "$tmp/own" <<'PY'
import glob, json, sys
import numpy as np
M, g, eps, r, L = 3.53e-5, 9.81, 0.9, 1.5e-3, 0.2
ok = True
a = np.genfromtxt(sys.argv[1] + "/ledger.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
t, K, P, Dn = a["t"], a["kinetic"], a["potential"], a["dissipated_normal"]
E0 = P[0]
fall = (t > 0) & (t < np.sqrt(2 * (0.1 - r) / g))
err = np.max(np.abs(K[fall] - 0.5 * M * g**2 * t[fall]**2) / (0.5 * M * g**2 * t[fall]**2))
print(f"free fall: largest relative deviation of K from M g^2 t^2 / 2: {err:.2e} (t printed to 9 digits)")
ok &= err < 1e-7
close = np.max(np.abs(K + P + Dn - E0)) / E0
print(f"ledger: largest |kinetic + potential + dissipated - initial| / initial = {close:.2e}")
ok &= close < 2e-11  # ledger.csv holds 12 significant digits
steps = np.diff(np.unique(Dn))
ratios = steps[1:] / steps[:-1]
print(f"{len(steps)} bounces; losses of successive bounces over each other: "
      + ", ".join(f"{x:.12f}" for x in ratios) + f" (eps_n^2 = {eps**2})")
ok &= len(steps) >= 4 and bool(np.all(np.abs(ratios - eps**2) < 1e-9))
first = steps[0] / ((1 - eps**2) * M * g * (0.1 - r))
print(f"first bounce loses {first:.12f} of (1 - eps_n^2) M g h")
ok &= abs(first - 1) < 1e-9
b = np.genfromtxt(sys.argv[2] + "/ledger.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
E = b["kinetic"] + b["potential"]
drift = np.max(np.abs(E - E[0])) / E[0]
hits = json.load(open(sys.argv[2] + "/summary.json"))["event"]["wall_hits"]
print(f"box, eps_n = 1: largest |E - E0| / E0 = {drift:.2e} over {hits:.0f} wall hits")
ok &= drift < 2e-11 and hits > 50
worst = 0.0
for f in sorted(glob.glob(sys.argv[2] + "/snapshots/*.xyz")):
    with open(f) as fh:
        n = int(fh.readline()); fh.readline()
        q = np.loadtxt(fh, usecols=(1, 2), max_rows=n, ndmin=2)
    worst = max(worst, np.max(r - q), np.max(q - (L - r)))
print(f"box: deepest centre beyond [r, L - r] over the snapshots: {worst:.2e} m")
ok &= worst <= 1e-12
c = np.genfromtxt(sys.argv[3] + "/ledger.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
own = np.diff(np.unique(c["dissipated_normal"]))
print("the walls' own eps_n = 0.5 (grains 0.9): loss ratios " + ", ".join(f"{x:.12f}" for x in own[1:] / own[:-1]))
ok &= len(own) >= 3 and bool(np.all(np.abs(own[1:] / own[:-1] - 0.25) < 1e-9))
sys.exit(0 if ok else 1)
PY
rc=$?
# a checkpoint taken while the grain's next event is a wall hit (a single grain has no other:
# partner -1 - face with face >= 4): SIGTERM mid-run (the run paused at a step), then --resume,
# equals the uninterrupted run byte for byte; the same for a bed on a vibrating floor (its wall's
# work in the checkpoint)
resumes() { # NAME PAUSE-STEP REFERENCE-DIR EXTRA-SETTINGS...
    local name=$1 pause=$2 ref=$3
    shift 3
    GRANULE_TEST_PAUSE_AT_STEP=$pause "$granule" run "$scene" --out "$tmp/$name" --quiet \
        --set output.plots=false --set run.checkpoint_every=0.2 "$@" >/dev/null 2>"$tmp/$name.err" &
    local pid=$!
    for _ in $(seq 1 300); do [[ -s $tmp/$name/checkpoint ]] && break; sleep 0.05; done
    sleep 0.3
    kill -TERM "$pid" 2>/dev/null
    wait "$pid"
    local code=$?
    "$granule" run --resume "$tmp/$name" --quiet >/dev/null 2>"$tmp/$name.resume.err"
    local resumed=$?
    if [[ $code -eq 5 && $resumed -eq 0 ]] && cmp -s "$ref/ledger.csv" "$tmp/$name/ledger.csv" &&
        cmp -s "$ref/temperature.csv" "$tmp/$name/temperature.csv"; then
        echo "resume: SIGTERM (exit 5) + --resume equals the uninterrupted run ($name)"
    else
        echo "FAIL: $name: SIGTERM exit $code; $(head -c 300 "$tmp/$name.err") $(head -c 300 "$tmp/$name.resume.err")" >&2
        rc=1
    fi
}
resumes term 1300000 "$tmp/b"
vib=(--set system.N=40 --set boundary.vibrate=y --set boundary.amplitude=0.002
    --set boundary.frequency=25 --set model.tc=0 --set model.eps_n=0.8 --set run.duration=1)
"$granule" run "$scene" --out "$tmp/vib" --quiet --set output.plots=false "${vib[@]}" \
    >/dev/null 2>"$tmp/log" || { cat "$tmp/log" >&2; echo "FAIL: run vibrated bed" >&2; exit 1; }
resumes vibterm 1300000 "$tmp/vib" "${vib[@]}"
exit $rc
