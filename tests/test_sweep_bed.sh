#!/usr/bin/env bash
# A sweep over a vibrated bed's floor amplitude (docs/sweeps/vibrated-bed-gamma.ini, shortened):
# sweep.csv carries the profile's centre-of-mass height, its error and the densest slab when the
# points have the profile observable (issue 36), with their units in sweep.meta.json; the bed
# rises with Gamma (mean over seeds, each step up beyond the errors) and its T grows. Then free
# cooling over eps_n (docs/sweeps/free-cooling-eps.ini, whole): sweep.csv has Haff's fitted t0 and
# the Enskog t0 per point; t0 grows with eps_n and fitted / Enskog averages 1 within 3 % (the
# seeds scatter by about 2 % each, docs/systems-driving.md).
# usage: test_sweep_bed.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed -e "s|^scene = ../scenes/vibrated-bed.ini|scene = $src/docs/scenes/vibrated-bed.ini|" \
    -e "s|^out = out/sweep-vibrated-bed|out = $tmp/out|" -e 's/^run.duration = 0.5/run.duration = 0.2/' \
    "$src/docs/sweeps/vibrated-bed-gamma.ini" >"$tmp/sweep.ini"
OMP_NUM_THREADS=1 "$granule" sweep "$tmp/sweep.ini" --jobs 2 >"$tmp/log" 2>&1 ||
    { cat "$tmp/log" >&2; echo "FAIL: the sweep" >&2; exit 1; }
/usr/bin/python3 - "$tmp/out" <<'PY'
import json, sys
import numpy as np
out = sys.argv[1]
a = np.genfromtxt(out + "/sweep.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
units = json.load(open(out + "/sweep.meta.json"))["units"]
assert units["profile_height"] == "m" and units["profile_max_phi"] == "1", units
amps = sorted(set(a["boundaryamplitude"]))
h = [a["profile_height"][a["boundaryamplitude"] == x].mean() for x in amps]
e = [np.hypot(*a["profile_height_stderr"][a["boundaryamplitude"] == x]) / 2 for x in amps]
T = [a["T_mean"][a["boundaryamplitude"] == x].mean() for x in amps]
print("Gamma 5, 10, 15, 20: centre of mass " + ", ".join(f"{1e3 * x:.2f}" for x in h) + " mm; T "
      + ", ".join(f"{x:.3g}" for x in T) + " m^2/s^2")
ok = all(h[k + 1] - h[k] > 5 * np.hypot(e[k], e[k + 1]) for k in range(3)) and all(np.diff(T) > 0)
sys.exit(0 if ok else 1)
PY
[[ $? -eq 0 ]] || { echo "FAIL: the bed does not rise with Gamma" >&2; exit 1; }
sed -e "s|^scene = ../scenes/free-cooling.ini|scene = $src/docs/scenes/free-cooling.ini|" \
    -e "s|^out = out/sweep-free-cooling|out = $tmp/cool|" "$src/docs/sweeps/free-cooling-eps.ini" >"$tmp/cool.ini"
"$granule" sweep "$tmp/cool.ini" --jobs 2 >"$tmp/log" 2>&1 ||
    { cat "$tmp/log" >&2; echo "FAIL: the free-cooling sweep" >&2; exit 1; }
/usr/bin/python3 - "$tmp/cool" <<'PY'
import json, sys
import numpy as np
out = sys.argv[1]
a = np.genfromtxt(out + "/sweep.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
units = json.load(open(out + "/sweep.meta.json"))["units"]
assert units["haff_t0"] == "s" and units["haff_t0_enskog"] == "s" and units["events_per_second"] == "s-1", units
eps = sorted(set(a["modeleps_n"]))
t0 = [a["haff_t0"][a["modeleps_n"] == x].mean() for x in eps]
ratio = a["haff_t0"] / a["haff_t0_enskog"]
print("eps_n " + ", ".join(f"{x:g}" for x in eps) + ": t0 " + ", ".join(f"{x:.3f}" for x in t0)
      + f" s; fitted / Enskog {ratio.mean():.4f} +- {ratio.std(ddof=1) / np.sqrt(ratio.size):.4f} over {ratio.size} runs")
sys.exit(0 if all(np.diff(t0) > 0) and abs(ratio.mean() - 1) < 0.03 and np.all(a["events_per_second"] > 0) else 1)
PY
