#!/usr/bin/env bash
# 3D runs' outputs read back (issue 35; docs/three-dimensions.md):
#   - a 3D run with every frame observable that covers 3D and collisions writes each CSV, and
#     `granule analyse` of its extended-XYZ trajectory and of its snapshots gives the same
#     moments, pv, pair, msd, vacf, vcorr, clusters, pressure, profile and sk byte for byte
#     (frames are read back in 3D, z and vz included); the same through trajectory.h5;
#   - the collision rate per particle agrees with the Enskog frequency of hard spheres,
#     nu_E = 24 phi chi(phi) sqrt(T/3) / (sqrt(pi) d) with Carnahan-Starling chi, within 4 errors
#     plus 5 % (the soft contacts and the Sonine correction: below 2 %; a 2D-normalised density or
#     the 2D chi are off by more); the mean free path (freepath, 3D displacements between
#     contacts) is Enskog's l_E = d / (6 sqrt(2) phi chi) within 10 % (measured 0.95 l_E: the paths
#     start at the end of a contact, not at the centres' closest approach); postcollision's
#     <v^2> of the frames pools three components (T/3);
#   - the pressure of the driven gas (frames every 2e-5 s, so that the contact virial is sampled
#     often) gives the compressibility factor Z = P / (n T_1) of Enskog's inelastic hard spheres,
#     Z_E = 1 + 2 (1 + eps_n) phi chi(phi) (Garzo & Dufty, Phys. Rev. E 59, 5895 (1999); 2D has
#     1 + (1 + eps_n) phi chi), within 4 errors plus 3 % (measured 0.990 Z_E at N = 2000, 0.1 s);
#     a 2D volume or the 2D virial would be off by far more;
#   - a 3D run with every 3D observable stopped again and again by its wall-time budget (between
#     samples) and resumed ends with the uninterrupted run's CSVs, byte for byte (the observables'
#     3D accumulators and the pending contact events with z, vz are checkpointed);
#   - `granule analyse --lammps-dump` of the same frames written as a 3D LAMMPS dump (id x y z vx
#     vy vz, one frame in scaled xs ys zs, the columns reordered) gives the run's frame observables
#     byte for byte; a dump without z, or with a box that is not a cube, is refused;
#   - the run's snapshot.png is the 3D picture, and `granule plot` draws it again;
#   - the observables that cannot compute 3D are refused with the scene file and key.
# usage: test_3d_outputs.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
obs=moments,pv,pair,msd,vacf,vcorr,clusters,pressure,profile,sk
common=(--set system.N=400 --set run.warmup=0.01 --set run.duration=0.06 --set run.sample_every=0.002
        --set output.snapshot_every=0.002 --quiet)
# the sanitizer pass (GRANULE_TEST_QUICK=1): the same code on a third of the grains and half the
# time; the kinetic-theory checks below are the release pass's (too few collisions here)
quick=${GRANULE_TEST_QUICK:-0}
[[ $quick == 1 ]] && common=(--set system.N=150 --set run.warmup=0.004 --set run.duration=0.03
                             --set run.sample_every=0.002 --set output.snapshot_every=0.002 --quiet)
for fmt in xyz snapshots h5md; do
    plots=false
    [[ $fmt == xyz ]] && plots=true
    "$granule" run "$src/docs/scenes/rfm-3d.ini" --out "$tmp/$fmt" "${common[@]}" --set output.trajectory=$fmt \
        --set analysis.observables=$obs,collisions,freepath,postcollision --set output.plots=$plots >"$tmp/$fmt.log" 2>&1 ||
        bad "3D run ($fmt) failed: $(tail -2 "$tmp/$fmt.log")"
    "$granule" analyse "$tmp/$fmt" --set analysis.observables=$obs >"$tmp/$fmt.analyse.log" 2>&1 ||
        bad "analyse of the 3D $fmt run failed: $(tail -2 "$tmp/$fmt.analyse.log")"
    for f in ${obs//,/ }; do
        [[ -s $tmp/$fmt/$f.csv ]] || bad "3D run ($fmt): no $f.csv"
        cmp -s "$tmp/$fmt/$f.csv" "$tmp/$fmt/analysis/$f.csv" ||
            bad "analyse of the 3D $fmt trajectory: $f.csv differs from the run's"
    done
done
[[ -s $tmp/xyz/collisions.csv ]] || bad "3D run: no collisions.csv"
[[ $quick == 1 ]] || python3 - "$tmp/xyz" <<'PY' || fail=1
import json, math, sys
j = json.load(open(sys.argv[1] + "/summary.json"))
sc = j["scene"]["system"]
phi, d = sc["packing_fraction"], 2 * sc["radius"]
chi = (1 - phi / 2) / (1 - phi) ** 3
T1 = j["T_mean"] / 3
nu_E = 24 * phi * chi * math.sqrt(T1) / (math.sqrt(math.pi) * d)
c = j["analysis"]["collisions"]
nu, err = c["rate_per_particle"], c["rate_per_particle_error"]
ok = abs(nu - nu_E) < 4 * err + 0.05 * nu_E and err < 0.05 * nu_E
print("%s collision rate %.1f +- %.1f /s, Enskog %.1f /s (ratio %.3f)" % ("ok" if ok else "FAIL", nu, err, nu_E, nu / nu_E))
fp = j["analysis"]["freepath"]
l_E = d / (6 * math.sqrt(2) * phi * chi)
ok_fp = fp["paths"] > 2000 and abs(fp["mean_over_d"] * d / l_E - 1) < 0.1
print("%s mean free path %.4f d over %d paths, Enskog %.4f d" % ("ok" if ok_fp else "FAIL", fp["mean_over_d"], fp["paths"], l_E / d))
pc = j["analysis"]["postcollision"]
ok_pc = pc["post_samples"] > 3000 and abs(pc["all_v2"] / (j["T_mean"] / 3) - 1) < 1e-9
print("%s postcollision: %d post-collision components, <v^2> of the frames %.6g = T/3 %.6g" % (
    "ok" if ok_pc else "FAIL", pc["post_samples"], pc["all_v2"], j["T_mean"] / 3))
sys.exit(0 if ok and ok_fp and ok_pc else 1)
PY
# the equation of state: Z against Enskog's (a statistical check: the release pass's; the sanitizer
# pass runs the 3D pressure code in the observables above and in obs_3d)
if [[ ${GRANULE_TEST_QUICK:-0} != 1 ]]; then
"$granule" run "$src/docs/scenes/rfm-3d.ini" --out "$tmp/eos" --set system.N=1000 --set run.warmup=0.02 \
    --set run.duration=0.1 --set run.sample_every=2e-5 --set analysis.observables=pressure \
    --set output.plots=false --set output.snapshot_every=0 --quiet >"$tmp/eos.log" 2>&1 || bad "3D pressure run failed"
python3 - "$tmp/eos" <<'PY' || fail=1
import json, sys
j = json.load(open(sys.argv[1] + "/summary.json"))
phi, eps = j["scene"]["system"]["packing_fraction"], 0.9
chi = (1 - phi / 2) / (1 - phi) ** 3
p = j["analysis"]["pressure"]
# the kinetic trace / 3 is n T_1 frame by frame, so Z - 1 is the collisional part over nT: its error
# is the collisional diagonal's (the slow drift of T scales both and cancels in the ratio)
Z = p["Z"]
Z_err = sum(p["collisional_%s_error" % a] ** 2 for a in ("xx", "yy", "zz")) ** 0.5 / 3 / p["nT"]
Z_E = 1 + 2 * (1 + eps) * phi * chi
ok = abs(Z - Z_E) < 4 * Z_err + 0.03 * Z_E and Z_err < 0.02 and p["unit"] == "Pa (N/m^2)"
print("%s Z = P / (n T_1) = %.4f +- %.4f, Enskog %.4f (ratio %.3f)" % ("ok" if ok else "FAIL", Z, Z_err, Z_E, Z / Z_E))
sys.exit(0 if ok else 1)
PY
fi
# the xyz run's frames as a LAMMPS dump: analyse --lammps-dump equals the run
python3 - "$tmp/xyz" <<'PY' || fail=1
import sys
d = sys.argv[1]
lines = open(d + "/snapshots/trajectory.xyz").read().split("\n")
out, bad_z, bad_box, k, frame = [], [], [], 0, 0
while k < len(lines) and lines[k].strip():
    n = int(lines[k]); head = lines[k + 1]
    L = head.split('Lattice="')[1].split()[0]
    step = int(head.split("Step=")[1].split()[0])
    rows = [r.split() for r in lines[k + 2:k + 2 + n]]
    box = ["ITEM: TIMESTEP", str(step), "ITEM: NUMBER OF ATOMS", str(n), "ITEM: BOX BOUNDS pp pp pp"]
    if frame == 1:  # scaled coordinates, columns reordered
        out += box + ["0 " + L] * 3 + ["ITEM: ATOMS vz id xs vx ys vy zs"]
        out += ["%s %d %r %s %r %s %r" % (r[6], i + 1, float(r[1]) / float(L), r[4], float(r[2]) / float(L), r[5],
                                          float(r[3]) / float(L)) for i, r in enumerate(rows)]
    else:
        out += box + ["0 " + L] * 3 + ["ITEM: ATOMS id x y z vx vy vz"]
        out += ["%d %s" % (i + 1, " ".join(r[1:7])) for i, r in enumerate(rows)]
    if frame == 0:
        bad_z = box + ["0 " + L] * 3 + ["ITEM: ATOMS id x y vx vy"] + ["%d %s %s %s %s" % (i + 1, r[1], r[2], r[4], r[5]) for i, r in enumerate(rows)]
        bad_box = box + ["0 " + L, "0 " + L, "0 1"] + ["ITEM: ATOMS id x y z vx vy vz"] + ["%d %s" % (i + 1, " ".join(r[1:7])) for i, r in enumerate(rows)]
    k += 2 + n; frame += 1
open(d + "/dump.lammpstrj", "w").write("\n".join(out) + "\n")
open(d + "/bad_z.lammpstrj", "w").write("\n".join(bad_z) + "\n")
open(d + "/bad_box.lammpstrj", "w").write("\n".join(bad_box) + "\n")
PY
"$granule" analyse "$tmp/xyz" --lammps-dump "$tmp/xyz/dump.lammpstrj" --out "$tmp/lmp" \
    --set analysis.observables=moments,pv,pair,vcorr,clusters,pressure,profile,sk >"$tmp/lmp.log" 2>&1 ||
    bad "analyse --lammps-dump of a 3D dump failed: $(tail -2 "$tmp/lmp.log")"
for f in moments pv pair vcorr clusters pressure profile sk; do
    cmp -s "$tmp/xyz/$f.csv" "$tmp/lmp/$f.csv" || bad "analyse --lammps-dump (3D): $f.csv differs from the run's"
done
for b in bad_z bad_box; do
    out=$("$granule" analyse "$tmp/xyz" --lammps-dump "$tmp/xyz/$b.lammpstrj" --out "$tmp/lmp-$b" 2>&1)
    rc=$?
    want="need id, x, y, z, vx, vy, vz"
    [[ $b == bad_box ]] && want="is not a cube"
    [[ $rc -eq 2 && $out == *"$want"* ]] || bad "analyse --lammps-dump $b: exit $rc, '$out'"
done
# --wall-limit stops + --resume: the uninterrupted run's CSVs (every 3D observable)
all=$obs,collisions,freepath,postcollision
ck=(--set run.checkpoint_every=0.0203 --set analysis.observables=$all --set output.plots=false)
"$granule" run "$src/docs/scenes/rfm-3d.ini" --out "$tmp/whole" "${common[@]}" "${ck[@]}" >/dev/null 2>&1 ||
    bad "3D run with checkpoints failed"
# stop under a wall-time budget (test clock: chunks of 777 steps, so stops fall between samples,
# with contact events pending) and resume until done
what=(run "$src/docs/scenes/rfm-3d.ini" --out "$tmp/killed" "${common[@]}" "${ck[@]}")
sessions=0
rc=4
while [[ $rc -eq 4 && $sessions -lt 60 ]]; do
    GRANULE_TEST_CLOCK_TICK=0.01 GRANULE_CHUNK_STEPS=777 "$granule" "${what[@]}" --wall-limit 1.5 >"$tmp/resume.log" 2>&1
    rc=$?
    what=(run --resume "$tmp/killed" --quiet)
    sessions=$((sessions + 1))
done
[[ $rc -eq 0 && $sessions -ge 3 ]] || bad "3D --wall-limit + --resume: $sessions sessions, last exit $rc: $(tail -2 "$tmp/resume.log")"
for f in ${all//,/ } temperature ledger; do
    cmp -s "$tmp/whole/$f.csv" "$tmp/killed/$f.csv" || bad "3D --wall-limit + --resume: $f.csv differs from the uninterrupted run's"
done
# the 3D picture: written by the run, drawn again by granule plot
png=$tmp/xyz/snapshot.png
if [[ -s $png ]]; then
    rm "$png"
    "$granule" plot "$tmp/xyz" >"$tmp/plot.log" 2>&1 || bad "granule plot of a 3D run failed: $(tail -2 "$tmp/plot.log")"
    [[ -s $png ]] || bad "granule plot did not draw the 3D snapshot.png"
else
    bad "the 3D run wrote no snapshot.png"
fi
[[ $(head -c 8 "$png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] || bad "snapshot.png is not a PNG"
grep -q "snapshot.png" "$tmp/xyz/summary.json" || bad "summary.json does not list snapshot.png"
# refusals: gaps (1D) is not defined for dim = 3
for o in gaps; do
    out=$("$granule" run "$src/docs/scenes/rfm-3d.ini" --out "$tmp/refused-$o" "${common[@]}" \
        --set analysis.observables=$o 2>&1)
    rc=$?
    [[ $rc -eq 2 ]] || bad "observables = $o in 3D: exit $rc, expected 2"
    [[ $out == *"analysis.observables"*"$o is not defined for dim = 3"* || $out == *"[analysis] observables"*"$o is not defined for dim = 3"* ]] ||
        bad "observables = $o in 3D: message '$out'"
    [[ ! -e $tmp/refused-$o ]] || bad "observables = $o in 3D: the refused run made its folder"
done
((fail == 0)) && echo "ok 3D outputs: analyse equals the run (xyz, snapshots, h5md), Enskog collision rate, snapshot.png"
exit $fail
