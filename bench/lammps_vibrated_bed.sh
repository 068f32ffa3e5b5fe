#!/usr/bin/env bash
# The vibrated bed (docs/scenes/vibrated-bed.ini with 150 grains and the floor shaken at A = 2 mm,
# f = 50 Hz, Gamma = 20, gravity, no noise) in granule and in LAMMPS from the same initial state (issue 36;
# docs/systems-walls-gravity.md, "Against LAMMPS"): `granule export lammps` writes the deck (fix
# wall/gran hooke with wiggle, fix gravity), LAMMPS runs it on one core, `granule analyse
# --lammps-dump` measures its frames with the same profile observable as granule's own run. Prints,
# slab by slab, the packing fraction and T_x, T_y of both with z = (granule - LAMMPS) / sqrt(err^2
# + err^2), chi2 per slab over the populated slabs, the centre-of-mass height of both, and the
# throughput of both (particle-steps/s; LAMMPS from its production run's loop time) with the ratio.
#
#   bench/lammps_vibrated_bed.sh [BUILD_DIR] [--quick | --check] [--install] [--warmup S]
#                                [--duration S] [--scene FILE] [--set K=V ...]
#
# --scene: another bed (default docs/scenes/vibrated-bed.ini); the 150 grains, A = 2 mm and 25
# slabs above still apply unless a --set says otherwise. The 3D bed of spheres:
#   bench/lammps_vibrated_bed.sh build --scene docs/scenes/vibrated-bed-3d.ini --set system.N=400 \
#       --set boundary.amplitude=1e-3 --set analysis.profile_bins=20 \
#       --set model.tangential=tangential_dashpot --set model.rotation=false
# (gran/hooke has no pure Coulomb slider, so export refuses sliding_friction)
#
# Defaults: 0.3 s of warm-up (the grains start spread over the box and must settle) and 2 s sampled
# every 2 ms (6.1e6 steps of 3.7e-7 s; LAMMPS takes about 15 s on one core). --quick: 0.004 + 0.004 s,
# the pipeline only. --check (the test suite's, about 15 s): 0.3 + 0.6 s, and fails unless the
# profiles agree: chi2 per slab below 3 for phi and each temperature (12 populated slabs measured
# 0.90, 1.74, 1.37) and the centres of mass within 4 errors (z = 0.21); under GRANULE_TEST_QUICK
# (the sanitizer pass) it runs as --quick.
# Needs `lmp` built with GRANULAR (Debian package lammps); skips without it (--install installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
scene=docs/scenes/vibrated-bed.ini
install=${GRANULE_BENCH_INSTALL:-0}
quick=false
check=false
extra=()
warmup=0.3
duration=2
while (($#)); do
    case $1 in
        --quick) quick=true; warmup=0.004; duration=0.004 ;;
        --check) if [[ -n ${GRANULE_TEST_QUICK:-} ]]; then quick=true; warmup=0.004; duration=0.004
                 else check=true; warmup=0.3; duration=0.6; fi ;;
        --install) install=1 ;;
        --warmup | --duration | --set | --scene)
            (($# >= 2)) || { echo "bench/lammps_vibrated_bed.sh: $1 needs a value" >&2; exit 2; }
            case $1 in --warmup) warmup=$2 ;; --duration) duration=$2 ;; --scene) scene=$2 ;; *) extra+=(--set "$2") ;; esac
            shift ;;
        -*) echo "usage: bench/lammps_vibrated_bed.sh [BUILD_DIR] [--quick | --check] [--install] [--warmup S] [--duration S] [--scene FILE] [--set K=V ...]" >&2
            exit 2 ;;
        *) build=$1 ;;
    esac
    shift
done
# shellcheck source=bench/lib.sh
source bench/lib.sh # lmp_or_skip
lmp_or_skip lammps-vibrated-bed "$install"
require_built lammps-vibrated-bed "$build/granule"
export OMP_NUM_THREADS=1
tmp=$(mktemp -d /tmp/granule-vbed.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
# a fluidised bed (150 grains, A = 2 mm > r, Gamma = 20): time averages that do not depend on where
# the chaotic trajectories part (the scene's 500 grains form a crystal whose layers each engine
# stacks its own way); later --set values win
sets=(--set system.N=150 --set boundary.amplitude=2e-3
      --set run.warmup="$warmup" --set run.duration="$duration" --set analysis.observables=profile
      --set analysis.profile_bins=25 --set output.plots=false ${extra[@]+"${extra[@]}"})
$quick && echo "# quick: the pipeline only (tiny windows), the numbers are not a comparison"
echo "# granule vs $lmp on $scene ${extra[*]+${extra[*]}}, $(date -u +%Y-%m-%dT%H:%MZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown), warm-up $warmup s, sampled $duration s, load average $(cut -d' ' -f1-3 /proc/loadavg)"
"$build/granule" run "$scene" --out "$tmp/g" "${sets[@]}" >"$tmp/g.log" 2>&1 ||
    { cat "$tmp/g.log" >&2; echo "lammps-vibrated-bed: granule run failed" >&2; exit 1; }
"$build/granule" export lammps "$scene" --out "$tmp/l" "${sets[@]}" >"$tmp/e.log" 2>&1 ||
    { cat "$tmp/e.log" >&2; echo "lammps-vibrated-bed: export failed" >&2; exit 1; }
(cd "$tmp/l" && "$lmp" -in in.granule -log log.lammps >lmp.out 2>&1) ||
    { tail -20 "$tmp/l/lmp.out" >&2; echo "lammps-vibrated-bed: LAMMPS failed" >&2; exit 1; }
"$build/granule" analyse "$tmp/l" --lammps-dump "$tmp/l/dump.granule.lammpstrj" --out "$tmp/la" \
    --no-plots >"$tmp/a.log" 2>&1 || { cat "$tmp/a.log" >&2; echo "lammps-vibrated-bed: analyse failed" >&2; exit 1; }
/usr/bin/python3 - "$tmp/g" "$tmp/la" "$tmp/l/log.lammps" "$quick" "$check" <<'PY'
import json, re, sys
import numpy as np
g_dir, l_dir, log, quick = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] == "true"
check = sys.argv[5] == "true"
rd = lambda d: np.genfromtxt(d + "/profile.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
g, l = rd(g_dir), rd(l_dir)
sg, sl = json.load(open(g_dir + "/summary.json")), json.load(open(l_dir + "/summary.json"))
# the temperatures per component the profile has (T_z in 3D); the one along gravity is printed
comps = [q for q in ("T_x", "T_y", "T_z") if q in g.dtype.names]
up = comps[-1]
print(f"{'z (mm)':>7} {'phi granule':>20} {'phi LAMMPS':>20} {'z':>6} {up + ' granule':>20} {up + ' LAMMPS':>20} {'z':>6}")
chi = {q: [] for q in ["phi"] + comps}
for k in range(len(g)):
    row = f"{1e3 * g['z'][k]:7.2f}"
    for q in ["phi"] + comps:
        a, b = g[q][k], l[q][k]
        e = np.hypot(g[q + "_err"][k], l[q + "_err"][k])
        z = (a - b) / e if e > 0 and np.isfinite(a) and np.isfinite(b) else np.nan
        if np.isfinite(z) and min(g["phi"][k], l["phi"][k]) > 0.005:
            chi[q].append(z)
        if q in ("phi", up):
            row += f" {a:9.4g} +- {g[q + '_err'][k]:7.2g} {b:9.4g} +- {l[q + '_err'][k]:7.2g} {z:6.2f}"
    print(row)
for q, zs in chi.items():
    zs = np.array(zs)
    if len(zs):
        print(f"{q}: {len(zs)} slabs with phi > 0.005: chi2 / slab = {np.mean(zs**2):.2f}, largest |z| = {np.max(np.abs(zs)):.2f}")
hg, hl = sg["analysis"]["profile"], sl["analysis"]["profile"]
zh = (hg["mean_position"] - hl["mean_position"]) / np.hypot(hg["mean_position_error"], hl["mean_position_error"])
print(f"centre-of-mass height: granule {1e3 * hg['mean_position']:.3f} +- {1e3 * hg['mean_position_error']:.3f} mm, "
      f"LAMMPS {1e3 * hl['mean_position']:.3f} +- {1e3 * hl['mean_position_error']:.3f} mm, z = {zh:.2f}")
loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", open(log).read())
t_l, procs, steps, atoms = loops[-1]
rate_l = int(steps) * int(atoms) / float(t_l)
rate_g = sg["particle_steps_per_second"]
print(f"throughput, one core: granule {rate_g:.3g} particle-steps/s (kernel {sg.get('kernel', '?')}), "
      f"LAMMPS {rate_l:.3g} ({procs} proc, production run): ratio {rate_g / rate_l:.2f}x")
if check:
    bad = [f"{q}: chi2 / slab {np.mean(np.array(zs) ** 2):.2f} over {len(zs)} slabs (limit 3, at least 5 slabs)"
           for q, zs in chi.items() if len(zs) < 5 or np.mean(np.array(zs) ** 2) >= 3.0]
    if not abs(zh) < 4.0:
        bad.append(f"centre of mass z = {zh:.2f} (limit 4)")
    if bad:
        print("FAIL: granule's and LAMMPS's profiles disagree: " + "; ".join(bad))
        sys.exit(1)
    print("check: the profiles agree (chi2 / slab < 3 for each quantity, centre of mass |z| < 4)")
PY
