#!/usr/bin/env bash
# The Langevin bath with every integrator (issue 36; docs/validation.md, "The Langevin bath";
# docs/event-driven.md and docs/hybrid.md, "Langevin bath"): docs/scenes/langevin-gas.ini's
# inelastic gases run by verlet (soft discs, the bath every step), the hybrid (soft discs, the bath
# at each window's end) and the event integrator (hard discs with eps_t = 1, the bath at the end of
# each kick_interval, at the default 1e-4 s and at 1e-3 s). Prints each run's T with its block
# error, its z against verlet's, and its wall time (one core, one after the other in this run: the
# speed ratios compare within one run only).
#
#   bench/bath_integrators.sh [BUILD_DIR] [--quick]
#
# The two gases: the scene at eps_n = 0.6 (phi = 0.353, clustering) and at L = 0.376 m, eps_n = 0.7
# (phi = 0.1). Defaults: 0.1 s of warm-up and 3 s sampled each, about 15 minutes on one core
# (verlet is most of it). --quick: 0.005 + 0.01 s, the pipeline only. Environment: DURATION, SEED.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
build_and_quick "bench/bath_integrators.sh [BUILD_DIR] [--quick]" "$@"
g="$build/granule"
require_built bath-integrators "$g"
export OMP_NUM_THREADS=1
tmp=$(mktemp -d /tmp/granule-bath.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
warm=0.1 dur=${DURATION:-3} seed=${SEED:-1}
$quick && { warm=0.005; dur=0.01; echo "# quick: the pipeline only, the numbers are not a comparison"; }
echo "# docs/scenes/langevin-gas.ini, $(date -u +%Y-%m-%dT%H:%MZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown), seed $seed, warm-up $warm s, sampled $dur s, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-34s %-24s %-26s %8s %10s\n' gas integrator "T (m^2/s^2)" z "wall (s)"
gases=("phi=0.353,eps_n=0.6|--set model.eps_n=0.6" "phi=0.1,eps_n=0.7|--set system.L=0.376 --set model.eps_n=0.7")
kinds=("verlet|--set integrator.kind=verlet"
       "hybrid|--set integrator.kind=hybrid"
       "event(kick 1e-4 s)|--set integrator.kind=event --set model.normal=hard_sphere --set model.eps_t=1"
       "event(kick 1e-3 s)|--set integrator.kind=event --set model.normal=hard_sphere --set model.eps_t=1 --set integrator.kick_interval=1e-3")
for gas in "${gases[@]}"; do
    gname=${gas%%|*}
    read -r -a gargs <<<"${gas#*|}"
    ref_T="" ref_e=""
    for kind in "${kinds[@]}"; do
        kname=${kind%%|*}
        read -r -a kargs <<<"${kind#*|}"
        out="$tmp/run"
        rm -rf "$out"
        start=$(date +%s.%N)
        "$g" run docs/scenes/langevin-gas.ini --out "$out" --quiet --set run.seed="$seed" \
            --set run.warmup="$warm" --set run.duration="$dur" --set output.plots=false \
            "${gargs[@]}" "${kargs[@]}" >"$tmp/log" 2>&1 ||
            { cat "$tmp/log" >&2; echo "bath-integrators: $kname on $gname failed" >&2; exit 1; }
        end=$(date +%s.%N)
        # T and its error (nan when too few samples for blocking), z against the first (verlet)
        read -r T e z wall < <(/usr/bin/python3 - "$out/summary.json" "${ref_T:-nan}" "${ref_e:-nan}" "$start" "$end" <<'PY'
import json, math, sys
s = json.load(open(sys.argv[1]))
T, e = s["T_mean"], s.get("T_stderr")
e = float("nan") if e is None else e
rT, re = float(sys.argv[2]), float(sys.argv[3])
den = math.hypot(e, re)
z = "%+.1f" % ((T - rT) / den) if math.isfinite(rT) and den > 0 else "-"
print(T, e, z, "%.1f" % (float(sys.argv[5]) - float(sys.argv[4])))
PY
)
        [[ -z $ref_T ]] && { ref_T=$T; ref_e=$e; }
        printf '%-34s %-24s %-26s %8s %10s\n' "$gname" "$kname" "$(printf '%.4f +- %.4f' "$T" "$e")" "$z" "$wall"
    done
done
echo "# T's errors are block errors of one run (lower bounds where the blocking does not converge); z against verlet"
