#!/usr/bin/env bash
# A floor that vibrates below 0 by more than a radius (docs/systems-walls-gravity.md): the grains
# riding it go below y = 0 and must stay there, not be wrapped to the ceiling. The vibrated bed
# with N = 150 and A = 2 mm > r = 1.5 mm (Gamma = 20), 0.3 s: the run finishes, some centre goes
# below 0, none ever appears inside the ceiling (a centre wrapped from below 0 would sit above
# L - r), the ledger closes (wall_work booked), and the
# profile observable counts the grains below 0 in its first slab (all N in every frame).
# usage: test_vibrated_floor.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$granule" run "$src/docs/scenes/vibrated-bed.ini" --out "$tmp/run" --set system.N=150 \
    --set boundary.amplitude=2e-3 --set run.warmup=0 --set run.duration=0.3 \
    --set output.snapshot_every=2e-3 --set output.plots=false --set analysis.observables=profile \
    --set analysis.profile_bins=20 >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: the bed with A > r does not run" >&2; exit 1; }
/usr/bin/python3 - "$tmp/run" <<'PY'
import glob, json, sys
import numpy as np
run = sys.argv[1]
lo, hi = np.inf, -np.inf
for f in sorted(glob.glob(run + "/snapshots/*.xyz")):
    with open(f) as fh:
        n = int(fh.readline()); fh.readline()
        y = np.loadtxt(fh, usecols=(2,), max_rows=n)
    lo, hi = min(lo, y.min()), max(hi, y.max())
s = json.load(open(run + "/summary.json"))
res = s["ledger"]["relative_residual"]
p = np.genfromtxt(run + "/profile.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
count = np.sum(p["n"]) * (p["z"][1] - p["z"][0]) * 0.1
print(f"lowest centre {1e3 * lo:.3f} mm, highest {1e3 * hi:.2f} mm (box 100 mm); ledger residual "
      f"{res:.2e}; profile holds {count:.3f} grains per frame of 150")
ok = lo < 0 and hi <= 0.1 - 1.5e-3 and abs(res) < 5e-3 and abs(count - 150) < 1e-6
sys.exit(0 if ok else 1)
PY
