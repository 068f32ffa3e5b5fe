#!/usr/bin/env bash
# Accuracy against cost (docs/performance.md, "Accuracy against cost"): for each scene, as the time
# step grows from the thesis's dt towards the stability limit,
#   - the error of the energy loss of one collision (RFM particles, Table 2.1 case 1 head-on and, in
#     2D, case 3 oblique; mean of contact phases) against 1 - eps^2 (2.13) and against the SUNDIALS
#     CVODE integration of the same contact (granule collide --reference),
#   - the error of the steady temperature (2.19) of a short run against a reference run at dt/REF_DIV,
#   - in 1D the error of <R^2>, the mean squared neighbour separation (3.18), against the same reference,
#   - the tail of P(v): the exponent alpha of the free fit of (5.5) over the Table 5.1 counts window,
#     as a difference from the reference's alpha,
# each against the wall seconds per simulated second of the scene at that dt (one core). Then the
# same temperature error for the event-driven integrator (against its own exact-sampling run) and
# the hybrid integrator (against the soft-sphere reference) as the kick interval shrinks, and the
# CVODE reference collision against its tolerance, each when the build has it (otherwise
# "skipped: not built").
#
#   bench/accuracy_cost.sh [BUILD_DIR] [--quick]
#
# Scenes: docs/scenes/rfm-1d.ini (1D RFM, N = 1000, eps = 0.1), docs/scenes/steady-2d.ini (2D,
# N = 2000, eps_n = eps_t = 0.6) and docs/scenes/rfm-3d.ini (3D, N = 2000 spheres, phi = 0.1,
# eps_n = 0.9, head-on collisions only: the scene has no tangential law). Writes out/bench/accuracy-SCENE.csv and .md and
# docs/img/accuracy-SCENE.png (log-log error against seconds per simulated second). Run lengths:
# ACC_WARMUP, ACC_DURATION (simulated s; defaults 0.5 and 2), ACC_REF_DIV (default 4); ACC_SCENES
# picks scenes ("rfm-1d steady-2d rfm-3d"), ACC_RUN_TIMEOUT bounds each run (s).
# --quick: tiny systems, two time steps, output in a temporary folder (the test suite runs this).
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
build_and_quick "bench/accuracy_cost.sh [BUILD_DIR] [--quick]" "$@"
granule="$build/granule"
coeffs="$build/bench/bench_coeffs"
for p in "$granule" "$coeffs" "$build/bench/bench_throughput"; do
    require_built accuracy_cost "$p"
done
bench_outputs "$quick" accuracy
work=$(mktemp -d /tmp/granule-accuracy-runs.XXXXXX)
trap 'rm -rf "$work"; [[ $quick == true ]] && rm -rf "$out"' EXIT
export OMP_NUM_THREADS=1

if $quick; then
    run_timeout=20
    mults=(1 4); ref_div=2; warm=0.002; dur=0.004; every=1e-4; phases=4
    kicks=(1e-4 1e-5)
    size1=(--set system.N=100 --set system.reduced_length=0.1)
    size2=(--set system.N=200 --set system.L=0.063)
    size3=(--set system.N=250)
else
    run_timeout=${ACC_RUN_TIMEOUT:-3600}
    mults=(1 1.5 2 3 4 6 8 10); ref_div=${ACC_REF_DIV:-4}; warm=${ACC_WARMUP:-0.5}; dur=${ACC_DURATION:-2}; every=1e-3
    phases=32
    kicks=(1e-3 3e-4 1e-4 3e-5 1e-5)
    size1=(); size2=(); size3=()
fi
runset=(--set run.warmup="$warm" --set run.duration="$dur" --set run.sample_every="$every" --set run.ledger_tolerance=0
        --set integrator.force_dt=true --set output.plots=false --set run.progress=false)

# one granule run; prints its summary path (or nothing when it failed: unstable or not built)
run_scene() { # name scene sets...
    local name=$1 scene=$2
    shift 2
    local rc=0
    timeout -k 5 "$run_timeout" "$granule" run "$scene" "${runset[@]}" "$@" --out "$work/$name" >"$work/$name.log" 2>&1 || rc=$?
    if ((rc == 124)); then
        echo "$name: timed out after $run_timeout s (ACC_RUN_TIMEOUT)" >&2
    elif ((rc == 0)); then
        echo "$work/$name/summary.json"
    elif [[ -f $work/$name/summary.json ]]; then
        echo "$work/$name/summary.json" # unstable: the summary says so
    fi
}

csv_row() { # csv series x-label summary.json ref-summary.json [collide json...]
    python3 - "$@" <<'EOF'
import json, math, sys
csv, series, label, summ, ref = sys.argv[1:6]
cols = sys.argv[6:]
def load(p):
    try:
        return json.load(open(p))
    except Exception:
        return None
s, r = load(summ), load(ref)
nan = float("nan")
status = s["status"] if s else "failed"
cost = s["wall_seconds"] / s["simulated_seconds"] if s and s.get("simulated_seconds") else nan
T = s["T_mean"] if s and s.get("T_mean") is not None else nan
Ts = s["T_stderr"] if s and s.get("T_stderr") is not None else nan
Tr = r["T_mean"] if r and r.get("T_mean") is not None else nan
Trs = r["T_stderr"] if r and r.get("T_stderr") is not None else nan
dT = (T - Tr) / Tr if Tr == Tr and Tr != 0 else nan
sig = math.hypot(Ts, Trs) / Tr if Tr == Tr and Tr != 0 else nan
out = [series, label, status, f"{cost:.4e}", f"{T:.6g}", f"{Ts:.3g}", f"{Tr:.6g}", f"{dT:.4e}", f"{sig:.3e}"]
for c in cols:
    g = load(c) or {}
    loss, exp, ref_loss = g.get("energy_loss", nan), g.get("expected_loss", nan), g.get("reference_energy_loss", nan)
    out += [f"{(loss - exp) / exp:.4e}" if exp == exp and loss is not None else "nan",
            f"{(loss - ref_loss) / ref_loss:.4e}" if ref_loss == ref_loss and ref_loss is not None else "nan"]
while len(out) < 13:
    out.append("nan")
def dig(d, *path):  # a number deep in a summary, nan when absent
    for k in path:
        try:
            d = d[k]
        except (KeyError, IndexError, TypeError):
            return nan
    return d if isinstance(d, (int, float)) else nan
# <R^2> (1D, observable gaps: moments[1] is m = 2) and the tail exponent alpha (observable pv)
R2, R2s = dig(s, "analysis", "gaps", "moments", 1), dig(s, "analysis", "gaps", "moments_stderr", 1)
R2r, R2rs = dig(r, "analysis", "gaps", "moments", 1), dig(r, "analysis", "gaps", "moments_stderr", 1)
al, als = dig(s, "analysis", "pv", "tail", "free", "alpha"), dig(s, "analysis", "pv", "tail", "free", "alpha_err")
alr, alrs = dig(r, "analysis", "pv", "tail", "free", "alpha"), dig(r, "analysis", "pv", "tail", "free", "alpha_err")
out += [f"{R2:.6g}", f"{(R2 - R2r) / R2r:.4e}" if R2r == R2r and R2r else "nan",
        f"{math.hypot(R2s, R2rs) / R2r:.3e}" if R2r == R2r and R2r else "nan",
        f"{al:.4g}", f"{al - alr:.4e}", f"{math.hypot(als, alrs):.3e}"]
with open(csv, "a") as f:
    f.write(",".join(out) + "\n")
EOF
}

scene_bench() { # name scene model dim size-sets...
    local name=$1 scene=$2 model=$3 dim=$4
    shift 4
    local size=("$@")
    local csv="$out/accuracy-$name.csv"
    echo "series,point,status,wall_s_per_sim_s,T,T_stderr,T_ref,T_rel_error,T_rel_sigma,loss_err_formula_headon,loss_err_cvode_headon,loss_err_formula_oblique,loss_err_cvode_oblique,R2,R2_rel_error,R2_rel_sigma,alpha,alpha_diff,alpha_sigma" >"$csv"
    (
        # shellcheck disable=SC1090
        source <("$coeffs" "$scene" "${size[@]}")
        printf '## %s: %s, dim %d, N = %d, eps_n = %g, eps_t = %g, thesis dt = %g s, t_c = %.4g s (%.1f steps per contact)\n' \
            "$name" "$scene" "$dim" "$N" "$eps_n" "$eps_t" "$dt" "$t_c" "$(python3 -c "print($t_c / $dt)")"
        local ref_dt
        ref_dt=$(python3 -c "print($dt / $ref_div)")
        local ref
        ref=$(run_scene "$name-ref" "$scene" "${size[@]}" --set integrator.dt="$ref_dt")
        echo "reference: dt = $ref_dt s, T = $(python3 -c "import json; d = json.load(open('$ref')); print(d['T_mean'], '+-', d['T_stderr'])" 2>/dev/null || echo failed)"
        for m in "${mults[@]}"; do
            local d
            d=$(python3 -c "print(f'{$dt * $m:.6g}')")
            local cols=()
            "$granule" collide --case 1 --dim "$dim" --model "$model" --eps-n "$eps_n" --eps-t "$eps_t" --k "$k_s" \
                --mass "$mass" --radius "$radius" --dt "$d" --force-dt --phases "$phases" --reference \
                >"$work/$name-c1-$m.json" 2>/dev/null || true
            cols+=("$work/$name-c1-$m.json")
            if [[ $dim == 2 ]]; then
                "$granule" collide --case 3 --dim 2 --model "$model" --eps-n "$eps_n" --eps-t "$eps_t" --k "$k_s" \
                    --mass "$mass" --radius "$radius" --dt "$d" --force-dt --phases "$phases" --reference \
                    >"$work/$name-c3-$m.json" 2>/dev/null || true
                cols+=("$work/$name-c3-$m.json")
            fi
            local s
            s=$(run_scene "$name-$m" "$scene" "${size[@]}" --set integrator.dt="$d")
            csv_row "$csv" "soft-sphere dt" "dt=$d" "${s:-none}" "$ref" "${cols[@]}"
        done
        # hybrid: free-flight windows of kick_interval, soft-sphere contacts; against the soft-sphere reference
        local kind
        for kind in hybrid event; do
            local kset=(--set integrator.kind="$kind")
            [[ $kind == event ]] && kset+=(--set model.normal=hard_sphere --set model.tangential=none)
            local msg
            if ! msg=$(probe_kind "$scene" "$kind" "${kset[@]}"); then
                echo "$kind: $msg"
                continue
            fi
            local kref=$ref
            local exact
            exact=$(run_scene "$name-$kind-exact" "$scene" "${size[@]}" "${kset[@]}" --set integrator.free_flight=exact)
            if [[ -z $exact ]]; then
                echo "$kind: skipped: the exact-sampling run failed or timed out: $(tail -n 1 "$work/$name-$kind-exact.log" 2>/dev/null)"
                continue
            fi
            [[ $kind == event ]] && kref=$exact # hard spheres are another model: their own exact run is the reference
            csv_row "$csv" "$kind exact" "exact" "${exact:-none}" "$ref"
            local k
            for k in "${kicks[@]}"; do
                local s
                s=$(run_scene "$name-$kind-$k" "$scene" "${size[@]}" "${kset[@]}" --set integrator.free_flight=kicks \
                    --set integrator.kick_interval="$k")
                csv_row "$csv" "$kind kicks" "tau=$k" "${s:-none}" "$kref"
            done
        done
    )
    # the soft-sphere run at the thesis's dt and the reference must work (this is what keeps the
    # script from rotting: the test suite runs it with --quick)
    if ! awk -F, 'NR == 2 && $3 == "completed" && $7 != "nan" { ok = 1 } END { exit !ok }' "$csv"; then
        echo "accuracy_cost: $name: the soft-sphere run at the thesis's dt or the reference run failed (logs were in $work)" >&2
        exit 1
    fi
    python3 - "$csv" "$out/accuracy-$name.md" "$out/accuracy-$name" <<'EOF'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
def f(x, fmt):
    v = float(x)
    return "n/a" if v != v else format(v, fmt)
with open(sys.argv[2], "w") as o:
    o.write("| series | point | status | wall s per simulated s | T (m^2/s^2) | T error vs reference (+- 1 sigma) "
            "| <R^2> error vs reference (+- 1 sigma) | tail alpha (minus the reference's, +- 1 sigma) "
            "| loss error vs 1-eps^2 (head-on) | vs CVODE (head-on) | vs formula (oblique) | vs CVODE (oblique) |\n")
    o.write("|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        o.write(f"| {r['series']} | {r['point']} | {r['status']} | {f(r['wall_s_per_sim_s'], '.3g')} | {f(r['T'], '.5g')} "
                f"| {f(r['T_rel_error'], '+.2e')} +- {f(r['T_rel_sigma'], '.1e')} "
                f"| {f(r['R2_rel_error'], '+.2e')} +- {f(r['R2_rel_sigma'], '.1e')} "
                f"| {f(r['alpha'], '.3f')} ({f(r['alpha_diff'], '+.3f')} +- {f(r['alpha_sigma'], '.3f')}) "
                f"| {f(r['loss_err_formula_headon'], '+.2e')} "
                f"| {f(r['loss_err_cvode_headon'], '+.2e')} | {f(r['loss_err_formula_oblique'], '+.2e')} | {f(r['loss_err_cvode_oblique'], '+.2e')} |\n")
# gnuplot data: one block per series, |error| > 0 only (log axes)
series = [("T_rel_error", "soft-sphere dt", "steady T vs reference (dt/REF)"),
          ("T_rel_sigma", "soft-sphere dt", "1 sigma of that T comparison (statistics, not dt)"),
          ("loss_err_formula_headon", "soft-sphere dt", "collision loss vs 1-eps^2 (head-on)"),
          ("loss_err_cvode_headon", "soft-sphere dt", "collision loss vs CVODE (head-on)"),
          ("loss_err_cvode_oblique", "soft-sphere dt", "collision loss vs CVODE (oblique)"),
          ("T_rel_error", "hybrid kicks", "hybrid: steady T vs soft-sphere reference"),
          ("T_rel_error", "hybrid exact", "hybrid exact sampling: steady T"),
          ("T_rel_error", "event kicks", "event-driven: steady T vs exact sampling")]
with open(sys.argv[3] + ".dat", "w") as o:
    n = 0
    for col, ser, title in series:
        pts = [(float(r["wall_s_per_sim_s"]), abs(float(r[col])), r["point"], float(r["T_rel_sigma"]) if col == "T_rel_error" else 0.0)
               for r in rows if r["series"] == ser and r["status"] == "completed"]
        pts = [p for p in pts if p[0] == p[0] and p[1] == p[1] and p[1] > 0]  # in dt (tau) order
        if not pts:
            continue
        o.write(f'"{title}"\n')
        for x, y, lab, s in pts:
            o.write(f"{x:.5g} {y:.5g} {lab} {s if s == s else 0:.4g}\n")
        o.write("\n\n")
        n += 1
    # the Pareto front of the collision error: the cheapest point for a given error, over the
    # soft-sphere time steps and the hybrid runs (whose contacts are Verlet's at the scene's dt, the
    # first soft-sphere row); error = the larger of the head-on and oblique errors against CVODE
    def loss(r):
        e = [abs(float(r[c])) for c in ("loss_err_cvode_headon", "loss_err_cvode_oblique") if float(r[c]) == float(r[c])]
        return max(e) if e else float("nan")
    soft = [r for r in rows if r["series"] == "soft-sphere dt"]
    pts = [(float(r["wall_s_per_sim_s"]), loss(r), r["point"]) for r in soft if r["status"] == "completed"]
    if soft:
        pts += [(float(r["wall_s_per_sim_s"]), loss(soft[0]), r["series"].split()[0] + "-" + r["point"])
                for r in rows if r["series"].startswith("hybrid") and r["status"] == "completed"]
    front, best = [], float("inf")
    for x, y, lab in sorted(p for p in pts if p[0] == p[0] and p[1] == p[1] and p[1] > 0):
        if y < best:
            front.append((x, y, lab))
            best = y
    if front:
        o.write('"Pareto front of the collision error (verlet dt, hybrid)"\n')
        for x, y, lab in front:
            o.write(f"{x:.5g} {y:.5g} {lab} 0\n")
        o.write("\n\n")
        n += 1
EOF
}

plot() { # name title
    local name=$1 title=$2 dat="$out/accuracy-$1.dat"
    local n
    n=$(grep -c '^"' "$dat" || true)
    if ! command -v gnuplot >/dev/null; then
        echo "plot: skipped (gnuplot not installed)"
        return 0
    fi
    if ((n == 0)); then
        echo "plot: skipped (no finite errors)"
        return 0
    fi
    local front=0
    grep '^"' "$dat" | tail -n 1 | grep -q '^"Pareto' && front=1
    gnuplot <<EOF
set terminal pngcairo size 1250,700 font ",11" noenhanced
set output "$img/accuracy-$name.png"
set logscale xy
set format y "%.0e"
set xlabel "wall seconds per simulated second (one core)"
set ylabel "|relative error|"
set key outside right top vertical font ",9"
set grid
set title "$title"
# the Pareto front, when written, is the last block: a thick black dashed line
set linetype 9 lc rgb "black" lw 3 dt 2
last = $((n - 1)); front = $front
plot for [i=0:$((n - 1))] "$dat" index i using 1:2 with linespoints lt (front && i == last ? 9 : i + 1) pt 7 title columnheader(1), \
     "$dat" index 0 using 1:2:3 with labels offset 0,1 font ",8" notitle
EOF
    echo "plot: $img/accuracy-$name.png"
}

bench_header
scenes=${ACC_SCENES:-rfm-1d steady-2d rfm-3d}
if [[ " $scenes " == *" rfm-1d "* ]]; then
    scene_bench rfm-1d docs/scenes/rfm-1d.ini spring_dashpot 1 "${size1[@]}" --set "analysis.observables=gaps, pv"
    cat "$out/accuracy-rfm-1d.md"
    plot rfm-1d "1D RFM (N = 1000, eps = 0.1): error against cost, dt from the thesis's 1e-6 s upwards"
fi
if [[ " $scenes " == *" steady-2d "* ]]; then
    scene_bench steady-2d docs/scenes/steady-2d.ini spring_dashpot+tangential_dashpot 2 "${size2[@]}" --set analysis.observables=pv
    cat "$out/accuracy-steady-2d.md"
    plot steady-2d "2D steady scene (N = 2000, eps_n = eps_t = 0.6): error against cost"
fi
if [[ " $scenes " == *" rfm-3d "* ]]; then
    scene_bench rfm-3d docs/scenes/rfm-3d.ini spring_dashpot 3 "${size3[@]}" --set analysis.observables=pv
    cat "$out/accuracy-rfm-3d.md"
    plot rfm-3d "3D RFM (N = 2000 spheres, phi = 0.1, eps_n = 0.9): error against cost"
fi

# CVODE against its tolerance (needs granule collide --rtol)
if "$granule" collide --help 2>&1 | grep -q -- '--rtol'; then
    echo "## CVODE reference collision against its tolerance (head-on, RFM particles, eps 0.1)"
    echo "| rtol | wall s | loss | error vs rtol 1e-12 |"
    echo "|---|---|---|---|"
    tight=$("$granule" collide --case 1 --dim 1 --eps-n 0.1 --mass 3.53e-5 --radius 1.5e-3 --reference --rtol 1e-12 |
        python3 -c "import json,sys; print(json.load(sys.stdin)['reference_energy_loss'])")
    for tol in 1e-4 1e-6 1e-8 1e-10; do
        t0=$(date +%s.%N)
        l=$("$granule" collide --case 1 --dim 1 --eps-n 0.1 --mass 3.53e-5 --radius 1.5e-3 --reference --rtol "$tol" |
            python3 -c "import json,sys; print(json.load(sys.stdin)['reference_energy_loss'])")
        t1=$(date +%s.%N)
        python3 -c "print(f'| $tol | {$t1 - $t0:.3g} | {$l:.12f} | {abs($l - $tight) / $tight:.2e} |')"
    done
else
    echo "CVODE against its tolerance: skipped: not built (granule collide has no --rtol; the reference runs at a fixed rtol)"
fi
echo "tables: $out/accuracy-*.md, $out/accuracy-*.csv"
