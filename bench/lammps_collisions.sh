#!/usr/bin/env bash
# Single head-on collisions in granule and in LAMMPS (pair_style granular), every normal law
# (spring_dashpot and hertz Tsuji / viscoelastic, clamped and not) at several impact speeds:
# restitution and contact steps of both engines at the same time step, against the law's exact
# restitution and the CVODE reference (docs/lammps.md, "Single collisions against LAMMPS").
#
#   bench/lammps_collisions.sh [BUILD_DIR] [--quick] [--speeds V1,V2,...] [--steps-per-contact S]
#                              [--convergence V] [--oblique-speeds V1,...] [--no-oblique]
#                              [--mindlin-speed V] [--no-mindlin] [--no-rolling] [--json OUT]
#
# Then oblique collisions with rotation (tangential dashpot, clamped or not, sliding friction,
# hertz + tangential dashpot) at 30 and 60 degrees, with and without spins before, at the impact
# speeds --oblique-speeds (default 1e-6,1e-4,1e-2,1 m/s; --quick 1e-6): velocities and spins after
# agree to 1e-6 where xi_max/d <= 1e-7, and by O(xi_max/d) (the lever arm) elsewhere.
# Then tangential_spring with mindlin = true on hertz against LAMMPS's tangential mindlin, no
# rotation (--mindlin-speed, default 0.1 m/s): they differ by granule's half first step only,
# first order (halving with dt, below 1 / steps per contact).
# Then rolling_friction against LAMMPS's rolling sds (stiff k_roll, gamma_roll = 0, mu_roll = mu_r)
# at --oblique-speeds: w1 - w2 after agrees to rounding while the rolling keeps its direction;
# where it stops within the contact granule ends with w1 = w2 and LAMMPS with a spring's residue.
#
# Spheres (3D, every model pair, spins about any axis): /usr/bin/python3 bench/lammps_collisions_3d.py
# --build BUILD --lmp LMP (docs/lammps.md, "Single collisions in 3D").
#
# Defaults: speeds 0.001,0.01,0.1,1,3 m/s, 1e4 steps per contact; --convergence V adds 1e3..1e6
# steps per contact at speed V (about a minute). --quick: two speeds at 1e3 steps per contact.
# Exits 1 when the engines differ by more than 1e-9 relative or by a contact step; skips (exit 0)
# without an lmp built with the GRANULAR package. The Python part is bench/lammps_collisions.py
# (Debian's /usr/bin/python3; scipy optional, for the exact restitution of LAMMPS's own Tsuji fit).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
if [[ $# -gt 0 && $1 != -* ]]; then
    build=$1
    shift
fi
# shellcheck source=bench/lib.sh
source bench/lib.sh
lmp=$(find_lmp || true)
if [[ -z $lmp ]]; then
    echo "lammps_collisions: skipped: no lmp with pair_style granular (Debian package lammps)"
    exit 0
fi
for p in "$build/granule" "$build/bench/bench_coeffs"; do
    require_built lammps_collisions "$p"
done
lmp_help=$("$lmp" -h 2>/dev/null || true)
lmp_version=$(grep -m1 -o 'Simulator - .*' <<<"$lmp_help" | sed 's/Simulator - //' || true)
echo "$(bench_header), $lmp: LAMMPS ${lmp_version:-(version unknown)}"
echo
/usr/bin/python3 bench/lammps_collisions.py --build "$build" --lmp "$lmp" "$@"
