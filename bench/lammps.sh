#!/usr/bin/env bash
# granule side by side with LAMMPS on the 2D RFM scene (docs/performance.md, "Side by side with LAMMPS").
#
#   bench/lammps.sh [BUILD_DIR] [--quick] [--install]
#
# 1. The contact law in both engines: the same binary collisions (Table 2.1 case 1 head-on, case 3
#    oblique at 30 degrees) stepped by granule (`granule collide`) and by LAMMPS (pair gran/hooke),
#    averaged over the same contact phases; the energy loss of each against 1 - eps^2.
# 2. The 2D RFM scene (N = 12000, phi = 0.53, eps_n = eps_t = 0.1, dt = 1e-6 s) from the same
#    initial state, the same N, dt and number of steps: particle-steps per second of both, their
#    ratio, and the mean temperature (2.19) of both over the sampling phase.
#
# Same physics: gran/hooke's normal force k_s xi - gamma v_n may turn attractive at the end of a
# contact, like the thesis's law (granule model.clamp = false, the scene's setting); with
# LAMMPS_CLAMP=1 both engines clamp it (granule model.clamp = true, LAMMPS keyword limit_damping,
# gamma_n from the exact clamped restitution). gran/hooke multiplies its damping constants by the pair's effective mass
# (meff = M/2 = m12), so gamma_n(LAMMPS) = gamma_n(granule) / m12 and likewise gamma_t (both in
# 1/s); bench_coeffs prints both. Plain `fix nve` integrates no rotation, like granule; xmu = 1e4
# (its maximum) makes the Coulomb cap inactive for the tangential dashpot. The random force is
# `fix addforce` with a per-atom normal() of standard deviation sqrt(2 D / dt) each step; granule's
# symmetrised noise keeps the centre of mass at rest, which `fix momentum 1 linear 1 1 0` does in
# LAMMPS.
#
# Needs `lmp` (Debian package lammps) built with the GRANULAR package. Without it the bench says
# so and exits 0; --install (or GRANULE_BENCH_INSTALL=1) installs the package with apt-get when run
# as root. --quick: a tiny scene (the test suite runs this so the script cannot rot).
# Longer runs: LAMMPS_WARMUP and LAMMPS_DURATION (simulated seconds, defaults 0.05 and 0.05).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
quick=false
install=${GRANULE_BENCH_INSTALL:-0}
for a in "$@"; do
    case $a in
        --quick) quick=true ;;
        --install) install=1 ;;
        -*) echo "usage: bench/lammps.sh [BUILD_DIR] [--quick] [--install]" >&2; exit 2 ;;
        *) build=$a ;;
    esac
done
granule="$build/granule"
coeffs="$build/bench/bench_coeffs"

# shellcheck source=bench/lib.sh
source bench/lib.sh # lmp_or_skip
lmp_or_skip lammps "$install"
lmp_help=$("$lmp" -h 2>/dev/null || true)
for p in "$granule" "$coeffs"; do
    require_built lammps "$p"
done
lmp_version=$(grep -m1 -o 'LAMMPS version: .*\|Simulator - .*' <<<"$lmp_help" | sed 's/.*Simulator - //; s/LAMMPS version: //' || true)
lmp_version="LAMMPS ${lmp_version:-(version unknown)}"

work=$(mktemp -d /tmp/granule-lammps.XXXXXX)
trap '[[ -n ${GRANULE_BENCH_KEEP:-} ]] || rm -rf "$work"' EXIT
scene=docs/scenes/rfm-2d.ini
clamp=${LAMMPS_CLAMP:-0}
if [[ $clamp == 1 ]]; then
    sets=(--set model.clamp=true)
    collide_clamp=(--clamp)
    lmp_clamp=limit_damping
else
    sets=(--set model.clamp=false)
    collide_clamp=()
    lmp_clamp=
fi
phases=16
if $quick; then
    sets+=(--set system.N=300 --set system.L=0.08)
    phases=4
    : "${LAMMPS_WARMUP:=2e-4}" "${LAMMPS_DURATION:=2e-4}"
    lmp_sample=2e-5
else
    : "${LAMMPS_WARMUP:=0.05}" "${LAMMPS_DURATION:=0.05}"
    lmp_sample=1e-3
fi
"$coeffs" "$scene" "${sets[@]}" >"$work/coeffs.sh"
# shellcheck disable=SC1091
source "$work/coeffs.sh"
echo "# granule vs $lmp_version ($lmp), $(date -u +%Y-%m-%dT%H:%MZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo "# contact law: k_s = $k_s N/m, m12 = $m12 kg, clamp = $clamp; granule gamma_n = $gamma_n kg/s, gamma_t = $gamma_t kg/s"
echo "# LAMMPS gran/hooke: Kn = $lammps_kn, gamma_n = $lammps_gamman 1/s, gamma_t = $lammps_gammat 1/s (= granule / m12), xmu = 1e4, dampflag 1 $lmp_clamp"

# ---- 1. single collisions: granule collide vs the same pairs in LAMMPS ----
# Each LAMMPS run holds one pair per contact phase, far apart, each started (1 + phase) steps
# before touching (the placement of src/collide/collide.c), so both engines see the same phases.
collision() { # case label
    local case=$1 label=$2
    "$granule" collide --case "$case" --dim 2 --model "$normal+$tangential" "${collide_clamp[@]}" --eps-n "$eps_n" --eps-t "$eps_t" \
        --k "$k_s" --mass "$mass" --radius "$radius" --dt "$dt" --phases "$phases" >"$work/collide$case.json"
    python3 - "$case" "$radius" "$dt" "$phases" "$mass" "$work/pairs$case.data" <<'EOF'
import math, sys
case, r, dt, P, M, out = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]), sys.argv[6]
# Table 2.1 (x1, v1, x2, v2), as in src/collide/collide.c
table = {1: ((0, 0), (1, 0), (1, 0), (0, 0)), 2: ((0, 0), (1, 1), (1, 1), (0, 0)),
         3: ((0, 0), (0, 1), (r, 1), (0, 0)), 4: ((0, 0), (1 + r, 1), (1, 1), (0, 0))}
x1, v1, x2, v2 = table[case]
d = 2 * r
r0 = (x2[0] - x1[0], x2[1] - x1[1]); g0 = (v2[0] - v1[0], v2[1] - v1[1])
b = r0[0] * g0[0] + r0[1] * g0[1]; gg = g0[0] ** 2 + g0[1] ** 2; c = r0[0] ** 2 + r0[1] ** 2 - d * d
t_hit = (-b - math.sqrt(b * b - gg * c)) / gg
span = 40 * d  # pairs this far apart never meet during the run
L = span * (P + 1)
with open(out, "w") as f:
    f.write(f"granule collision pairs, case {case}\n\n{2 * P} atoms\n1 atom types\n\n")
    f.write(f"0 {L!r} xlo xhi\n0 {L!r} ylo yhi\n-{d!r} {d!r} zlo zhi\n\nAtoms # sphere\n\n")
    vel = []
    for p in range(P):
        phase = (p + 0.5) / P if P > 1 else 0.0
        t0 = t_hit - min(t_hit, (1 + phase) * dt)
        cx, cy = span * (p + 0.5), span * (p + 0.5)
        for k, (x, v) in enumerate(((x1, v1), (x2, v2))):
            px = cx + x[0] + v[0] * t0 - 0.5 * r0[0]
            py = cy + x[1] + v[1] * t0 - 0.5 * r0[1]
            i = 2 * p + k + 1
            f.write(f"{i} 1 {d!r} 1.0 {px!r} {py!r} 0.0\n")
            vel.append(f"{i} {float(v[0])!r} {float(v[1])!r} 0.0 0.0 0.0 0.0\n")
    f.write("\nVelocities\n\n" + "".join(vel))
EOF
    local steps
    steps=$(python3 -c "import math; print(int(math.ceil(20 * $t_c / $dt)) + 20)")
    cat >"$work/pairs$case.in" <<EOF
units si
dimension 2
boundary p p p
atom_style sphere
comm_modify vel yes
read_data $work/pairs$case.data
set type 1 mass $mass
pair_style gran/hooke $lammps_kn 0.0 $lammps_gamman $lammps_gammat 1.0e4 1 $lmp_clamp
pair_coeff * *
neighbor $(python3 -c "print(0.3 * 2 * $radius)") bin
neigh_modify delay 0 every 1 check yes
fix 1 all nve
fix 2 all enforce2d
timestep $dt
thermo 0
run $steps
write_dump all custom $work/pairs$case.out id vx vy modify sort id
EOF
    (cd "$work" && "$lmp" -in "pairs$case.in" -log none -screen none) ||
        { echo "lammps: LAMMPS failed on the collision deck $work/pairs$case.in" >&2; return 1; }
    python3 - "$work/collide$case.json" "$work/pairs$case.out" "$label" <<'EOF'
import json, sys
g = json.load(open(sys.argv[1]))
rows = {}
lines = open(sys.argv[2]).read().split("ITEM: ATOMS")[1].strip().splitlines()[1:]
for ln in lines:
    i, vx, vy = ln.split()
    rows[int(i)] = (float(vx), float(vy))
# initial relative speed of every pair is that of the Table 2.1 case
import math
losses = []
P = len(rows) // 2
for p in range(P):
    a, b = rows[2 * p + 1], rows[2 * p + 2]
    losses.append((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2)
gg0 = {1: 1.0, 2: 2.0, 3: 1.0, 4: None}[g["case"]]
lam = sum(1 - x / gg0 for x in losses) / P
exp = g["expected_loss"]
diff = abs(lam - g['energy_loss']) / exp
print(f"| {sys.argv[3]} | {g['impact_angle']:.1f} | {exp:.6f} | {g['energy_loss']:.6f} ({(g['energy_loss'] - exp) / exp:+.2e}) "
      f"| {lam:.6f} ({(lam - exp) / exp:+.2e}) | {diff:.1e} |")
# same scheme (velocity Verlet, dashpot at the half-step velocity), same phases: only rounding differs
if not diff < 1e-6:
    print(f"lammps: MISMATCH: granule and LAMMPS energy losses differ by {diff:.2e} (> 1e-6) for {sys.argv[3]}", file=sys.stderr)
    sys.exit(1)
EOF
}
echo
printf 'Single collisions, RFM particles, eps_n = %g, eps_t = %g (clamp = %s), dt = %g s, mean of %d contact phases:\n' \
    "$eps_n" "$eps_t" "$clamp" "$dt" "$phases"
echo
echo "| collision | angle (deg) | expected loss | granule (rel. error) | LAMMPS (rel. error) | |granule - LAMMPS| / expected |"
echo "|---|---|---|---|---|---|"
collision 1 "Table 2.1 case 1, head-on, 1 m/s"
collision 3 "Table 2.1 case 3, oblique"

# ---- 2. the 2D RFM scene, same initial state ----
"$granule" run "$scene" "${sets[@]}" --set run.warmup=0 --set run.duration="$lmp_sample" --set run.sample_every="$lmp_sample" \
    --set output.snapshot_every=1e9 --set output.plots=false --out "$work/init" >/dev/null 2>&1
/usr/bin/python3 bench/lammps_scene.py data "$work/init/snapshots/snap_000000.xyz" "$work/rfm.data"
warm_steps=$(python3 -c "print(round($LAMMPS_WARMUP / $dt))")
run_steps=$(python3 -c "print(round($LAMMPS_DURATION / $dt))")
every=$(python3 -c "print(max(1, round($lmp_sample / $dt)))")
seed_lmp=$(( (seed % 900000) + 1 ))
cat >"$work/rfm.in" <<EOF
units si
dimension 2
boundary p p p
atom_style sphere
comm_modify vel yes
read_data $work/rfm.data
set type 1 mass $mass
pair_style gran/hooke $lammps_kn 0.0 $lammps_gamman $lammps_gammat 1.0e4 1 $lmp_clamp
pair_coeff * *
neighbor $(python3 -c "print(0.3 * 2 * $radius)") bin
neigh_modify delay 0 every 1 check yes
variable fx atom normal(0.0,$noise_sigma,$seed_lmp)
variable fy atom normal(0.0,$noise_sigma,$((seed_lmp + 1)))
fix noise all addforce v_fx v_fy 0.0
fix 1 all nve
fix 2 all enforce2d
fix com all momentum 1 linear 1 1 0
variable vsq atom vx*vx+vy*vy
compute vsum all reduce sum v_vsq
variable T equal c_vsum/atoms
timestep $dt
thermo $every
thermo_style custom step v_T
thermo_modify flush no
run $warm_steps
fix avg all ave/time $every 1 $every v_T file $work/lammps_T.dat
run $run_steps
EOF
(cd "$work" && "$lmp" -in rfm.in -log "$work/lammps.log" -screen none) ||
    { echo "lammps: LAMMPS failed on the scene deck (log: $work/lammps.log)" >&2; tail -5 "$work/lammps.log" >&2; exit 1; }
"$granule" run "$scene" "${sets[@]}" --set run.warmup="$LAMMPS_WARMUP" --set run.duration="$LAMMPS_DURATION" \
    --set run.sample_every="$lmp_sample" --set output.plots=false --out "$work/granule" >/dev/null 2>&1
python3 - "$work/granule/summary.json" "$work/lammps.log" "$work/lammps_T.dat" "$N" "$dt" "$((warm_steps + run_steps))" <<'EOF'
import json, re, sys, statistics
g = json.load(open(sys.argv[1]))
log = open(sys.argv[2]).read()
N, dt, steps = int(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6])
loops = [float(x) for x in re.findall(r"Loop time of ([0-9.eE+-]+) on", log)]
lam_rate = N * steps / sum(loops)
T = [float(l.split()[1]) for l in open(sys.argv[3]) if l.strip() and not l.startswith("#")]
def block_err(xs, nb=8):
    if len(xs) < 2 * nb:
        return float("nan")
    m = len(xs) // nb
    means = [statistics.fmean(xs[i * m:(i + 1) * m]) for i in range(nb)]
    return statistics.stdev(means) / nb ** 0.5
Tl = statistics.fmean(T)
gr = g["particle_steps_per_second"]
print()
print(f"2D RFM scene, N = {N}, dt = {dt:g} s, {steps} steps (warm-up + sampling) from the same initial state, one core:")
print()
print("| engine | kernel / style | particle-steps/s | mean T (m^2/s^2) over sampling |")
print("|---|---|---|---|")
print(f"| granule | {g['kernel']} | {gr:.3e} | {g['T_mean']:.5g} +- {g['T_stderr'] if g['T_stderr'] is not None else float('nan'):.2g} |")
print(f"| LAMMPS | gran/hooke, fix nve + enforce2d + addforce + momentum | {lam_rate:.3e} | {Tl:.5g} +- {block_err(T):.2g} |")
print()
print(f"throughput ratio granule / LAMMPS = {gr / lam_rate:.2f}; T ratio granule / LAMMPS = {g['T_mean'] / Tl:.4f}")
share = {k: float(v) for k, v in re.findall(r"^(Pair|Neigh|Comm|Modify|Output|Other)\s*\|.*\|\s*([0-9.]+)\s*$", log, re.M)}
if share:
    print("LAMMPS time shares of the last run (%): " + ", ".join(f"{k} {v:.0f}" for k, v in share.items())
          + " (Modify = the fixes: per-atom normal() noise variable, nve, enforce2d, momentum)")
EOF
