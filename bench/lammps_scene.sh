#!/usr/bin/env bash
# The 2D RFM scene (N = 12000, phi = 0.53) in granule and in LAMMPS, model by model (docs/lammps.md,
# "The scene, model by model"): hooke (gran/hooke), hertz with the Tsuji-form damping at the scene's
# eps_n and viscoelastic (pair granular), hooke + tangential dashpot + rotation (pair granular
# linear_nohistory, fix nve/sphere disc), and hooke + tangential spring + rotation once granule has
# that law. Same initial state and window in both engines, independent noise: T with block errors
# and z, P(v) (KS distance, tail fractions with errors), the rotational temperature.
#
#   bench/lammps_scene.sh [BUILD_DIR] [--quick] [--install] [--dim 3] [--cases a,b,...] [--json OUT]
#                         [--warmup S] [--duration S] [--set KEY=VALUE ...]
#
# --dim 3: the 3D scene docs/scenes/rfm-3d.ini (N = 2000 spheres, phi = 0.1; --set system.N=...
# to change it) with the cases that have a 3D mapping (hooke, hertz-tsuji, hertz-visco, hooke-history).
#
# Defaults: 0.05 s of warm-up and 0.05 s of sampling (1e5 steps; a case takes a few minutes of
# LAMMPS on one core). --quick: N = 300, 400 steps: the pipeline only (the test suite runs it).
# Needs `lmp` built with GRANULAR (Debian package lammps); skips without it (--install installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
install=${GRANULE_BENCH_INSTALL:-0}
pass=()
while (($#)); do
    case $1 in
        --quick) pass+=(--quick) ;;
        --install) install=1 ;;
        --cases | --json | --warmup | --duration | --dim | --set)
            (($# >= 2)) || { echo "bench/lammps_scene.sh: $1 needs a value" >&2; exit 2; }
            pass+=("$1" "$2")
            shift ;;
        -*) echo "usage: bench/lammps_scene.sh [BUILD_DIR] [--quick] [--install] [--dim 3] [--cases a,b,...] [--json OUT] [--warmup S] [--duration S] [--set KEY=VALUE]" >&2
            exit 2 ;;
        *) build=$1 ;;
    esac
    shift
done
# shellcheck source=bench/lib.sh
source bench/lib.sh # lmp_or_skip
lmp_or_skip lammps-scene "$install"
for p in "$build/granule" "$build/bench/bench_coeffs"; do
    require_built lammps-scene "$p"
done
echo "# granule vs $lmp, $(date -u +%Y-%m-%dT%H:%MZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown), load average $(cut -d' ' -f1-3 /proc/loadavg)"
exec /usr/bin/python3 bench/lammps_scene.py --build "$build" --lmp "$lmp" "${pass[@]}"
