#!/usr/bin/env bash
# The contact sublist (src/core/sublist.c) changes the speed only: scenes in 2D and 3D (beds with
# walls and gravity, a history spring with rotation, the RFM gas on two threads, mixtures) run with it
# forced off, on, and as the engine decides (auto); temperature.csv and ledger.csv are the same
# bytes in all three (tests/test_walls_3d.c checks that on and auto do turn it on).
# usage: test_sublist.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { # name threads scene duration quick-duration sets...
    local name=$1 threads=$2 scene=$3 duration=$4
    # the sanitizer pass (GRANULE_TEST_QUICK): a shorter run through the same paths
    [[ -n ${GRANULE_TEST_QUICK:-} ]] && duration=$5
    shift 5
    local sets=(--threads "$threads" --set run.duration="$duration")
    for x in "$@"; do sets+=(--set "$x"); done
    for mode in off on auto; do
        GRANULE_SUBLIST=$mode "$granule" run "$src/docs/scenes/$scene" --out "$tmp/$name-$mode" \
            --set output.plots=false --set run.warmup=0 "${sets[@]}" >/dev/null 2>"$tmp/log" ||
            { cat "$tmp/log" >&2; echo "FAIL: $name ($mode) does not run" >&2; fail=1; return; }
    done
    for mode in on auto; do
        for f in temperature.csv ledger.csv; do
            cmp -s "$tmp/$name-off/$f" "$tmp/$name-$mode/$f" ||
                { echo "FAIL: $name: $f with the sublist $mode differs from off" >&2; fail=1; }
        done
    done
    echo "$name: the same bytes off, on and auto"
}
check bed-3d 1 vibrated-bed-3d.ini 0.05 0.012 model.tangential=tangential_spring
# without a history law the 3D kernel screens the sublist's entries first (kernels_3d.c, screen_3d)
check bed-3d-friction 1 vibrated-bed-3d.ini 0.05 0.012
check gas-3d-dashpot 2 rfm-3d.ini 0.005 0.002 system.packing_fraction=0.3 model.tangential=tangential_dashpot
check bed-2d 1 vibrated-bed.ini 0.1 0.024
check gas-2d-threads 2 rfm-2d.ini 0.01 0.003 system.N=3000
check gas-3d-threads 2 rfm-3d.ini 0.005 0.002 model.tangential=tangential_spring model.rotation=true
# one thread (the flat build of sublist.c), from the dilute cubic start whose first list is empty
check gas-3d-one 1 rfm-3d.ini 0.005 0.002
# mixtures (src/core/kernels_poly.c): species in 2D with a history spring and rotation, a bed of
# two sizes, a lognormal radius distribution, spheres of two species
check mixture-2d 1 bidisperse-mixture.ini 0.05 0.015 system.packing_fraction=0.3 \
    model.tangential=tangential_spring model.rotation=true
check mixture-bed-2d 1 vibrated-bed-mixture.ini 0.05 0.014
check lognormal-2d 1 polydisperse-gas.ini 0.1 0.1
check mixture-3d 2 bidisperse-mixture-3d.ini 0.02 0.02 system.packing_fraction=0.3
exit $fail
