#!/usr/bin/env bash
# The shear instability of the homogeneous cooling state (docs/validation.md, "When Haff's law
# ends: the shear instability"): event-driven free cooling of smooth hard discs at phi = 0.05,
# eps_n = 0.9, in a box below and one above the predicted critical side L_perp = 170 sigma
# (N = 1000: L = 0.74 L_perp; N = 8000: L = 2.09 L_perp), 80 s each (T falls about 3000-fold).
# Below L_perp the local Haff slope d(T^-1/2)/dt stays at the Enskog value and the energy in the
# box's longest shear modes stays of order T; above it the shear modes grow a hundredfold and the
# gas cools more slowly than Haff's law. Release build only (the event integrator runs under the
# sanitizers in the event and haff tests). usage: test_hcs_stability.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for n in 1000 8000; do
    "$granule" run "$src/docs/scenes/cooling-2d-event.ini" --out "$tmp/n$n" --set system.N=$n \
        --set system.packing_fraction=0.05 --set model.eps_n=0.9 --set run.duration=80 \
        --set run.sample_every=0.01 --set output.snapshot_every=8 --set output.plots=false \
        >/dev/null 2>"$tmp/log" || { cat "$tmp/log" >&2; echo "FAIL: run N = $n" >&2; exit 1; }
done
/usr/bin/python3 "$src/scripts/hcs_shear.py" "$tmp/n1000" "$tmp/n8000" --check
