#!/usr/bin/env bash
# 3D runs' outputs read back (issue 35; docs/three-dimensions.md):
#   - a 3D run with every frame observable that covers 3D and collisions writes each CSV, and
#     `granule analyse` of its extended-XYZ trajectory and of its snapshots gives the same
#     moments, pv, pair, msd, vacf, vcorr, clusters, pressure, profile and sk byte for byte
#     (frames are read back in 3D, z and vz included); the same through trajectory.h5;
#   - the collision rate per particle agrees with the Enskog frequency of hard spheres,
#     nu_E = 24 phi chi(phi) sqrt(T/3) / (sqrt(pi) d) with Carnahan-Starling chi, within 4 errors
#     plus 5 % (the soft contacts and the Sonine correction: below 2 %; a 2D-normalised density or
#     the 2D chi are off by more);
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
for fmt in xyz snapshots h5md; do
    plots=false
    [[ $fmt == xyz ]] && plots=true
    "$granule" run "$src/docs/scenes/rfm-3d.ini" --out "$tmp/$fmt" "${common[@]}" --set output.trajectory=$fmt \
        --set analysis.observables=$obs,collisions --set output.plots=$plots >"$tmp/$fmt.log" 2>&1 ||
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
python3 - "$tmp/xyz" <<'PY' || fail=1
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
sys.exit(0 if ok else 1)
PY
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
