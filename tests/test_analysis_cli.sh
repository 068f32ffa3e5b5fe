#!/usr/bin/env bash
# The analysis commands end to end on tiny runs: observables sampled in a run, granule analyse on
# snapshots, granule compare, granule sweep (parallel, resumable, failed points reported).
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
check() { if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAILED: $*" >&2; fi; }
num() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval('d'+sys.argv[2]))" "$1" "$2"; }

# a 1D run with the moments observable: <v^2> (m = 2) equals T of eq. 2.19 exactly in 1D
"$granule" run "$src/docs/scenes/rfm-1d.ini" --quiet --out "$tmp/run1" --set system.N=200 \
    --set run.warmup=0.01 --set run.duration=0.05 --set output.snapshot_every=0.01 \
    --set analysis.observables=moments >/dev/null
check test -f "$tmp/run1/moments.csv"
check test -f "$tmp/run1/scene.ini"
check python3 -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if abs(d['analysis']['moments']['speed']['m2']-d['T_mean'])<=1e-12*d['T_mean'] else 1)" "$tmp/run1/summary.json"
check python3 -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if 'C_implied' in d['mean_field'] else 1)" "$tmp/run1/summary.json"

# granule analyse on the snapshots gives the same kind of output
check "$granule" analyse "$tmp/run1" --set analysis.observables=moments
check test -f "$tmp/run1/analysis/moments.csv"
check python3 -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if d['frames']==5 else 1)" "$tmp/run1/analysis/summary.json"
# ... and, from 5 frames (fewer than GR_MIN_FRAMES = 16), warns on stderr and in summary.json
check grep -q "analyse: warning: only 5 frames" <<<"$("$granule" analyse "$tmp/run1" --out "$tmp/an-few" --set analysis.observables=moments 2>&1)"
check python3 -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if 'only 5 frames' in d['warnings'] else 1)" "$tmp/an-few/summary.json"

# histogram lines join bins of 2 counts or more; single-count bins (a tail of lone events at one
# level) are drawn as points, never as a flat line (issue 38)
"$granule" run "$src/docs/scenes/rfm-1d.ini" --quiet --out "$tmp/tails" --set system.N=100 --set run.warmup=0.01 \
    --set run.duration=0.05 --set analysis.observables=gaps,postcollision >/dev/null 2>&1
check python3 - "$tmp/tails" <<'PY'
import re, sys
d = sys.argv[1]
ok = True
for gp, count in [("gaps.gp", "$6"), ("gaps_lnR.gp", "$6"), ("postcollision.gp", "$7")]:
    body = open(d + "/" + gp).read()
    series = [x.replace(" ", "") for x in body.split("plot ", 1)[1].split(", ") if "using" in x]
    lines = [sr for sr in series if re.search(r"with(lines|linespoints)", sr)]
    good = bool(lines) and all(count + ">1" in sr for sr in lines)
    good &= any("withpoints" in sr and count + "==1" in sr for sr in series)
    if not good:
        print(gp, series, file=sys.stderr)
    ok &= good
sys.exit(0 if ok else 1)
PY

# warnings a user must see (issue 14): a 2D box with 2 lattice shells below k' gives no D_f, and
# says why; spm full --compare-run on 5 frames gives no "agrees" verdict but a warning
"$granule" run "$src/docs/scenes/steady-2d.ini" --quiet --out "$tmp/few" --set system.N=300 --set system.L=0.05 \
    --set run.warmup=0.005 --set run.duration=0.01 --set output.snapshot_every=0.002 --set output.plots=false \
    --set analysis.observables=sk,freepath >/dev/null
check python3 -c "import json,sys; f=json.load(open(sys.argv[1]))['analysis']['sk']['fit']; sys.exit(0 if f['shells'] == 2 and 'D_f' not in f and 'a fit needs 3' in f['status'] else 1)" "$tmp/few/summary.json"
spm_out=$("$granule" spm full --compare-run "$tmp/few" --out "$tmp/few-spm" --walks 20000 2>&1)
check grep -q "WARNING: no verdict: 5 frames" <<<"$spm_out"
check test "$(grep -c "agrees" <<<"$spm_out")" -eq 0
check python3 -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if 'no agreement verdict' in d['rfm']['warning'] else 1)" "$tmp/few-spm/summary.json"

# offline analysis of snapshots equals the in-run result: snapshots at every sample, no warm-up
"$granule" run "$src/docs/scenes/steady-2d.ini" --quiet --out "$tmp/same" --set system.N=300 --set system.L=0.06 \
    --set run.warmup=0 --set run.duration=0.04 --set run.sample_every=0.002 --set output.snapshot_every=0.002 \
    --set output.plots=false --set analysis.observables=moments,sk,pair >/dev/null
same_out=$("$granule" analyse "$tmp/same" 2>/dev/null)
check test $? -eq 0
# the headline as run prints it (issue 38): T with its error over the frames, then the fits
check grep -Eq "^$tmp/same/analysis: T = [0-9.e+-]+ \+- [0-9.e+-]+ m\^2/s\^2.* over 20 frames" <<<"$same_out"
check python3 - "$tmp/same" "$same_out" <<'PY'
import json, sys
d = sys.argv[1]
run, off = json.load(open(d + "/summary.json")), json.load(open(d + "/analysis/summary.json"))
# T from the snapshots equals the run's T of the same frames, and the printed value is it
ok = abs(off["T_mean"] - run["T_mean"]) <= 1e-12 * run["T_mean"] and off["samples"] == run["samples"] == 20
ok &= off["T_stderr"] is not None and abs(off["T_stderr"] - run["T_stderr"]) <= 1e-9 * run["T_stderr"]
ok &= off["T_stderr_converged"] == run["T_stderr_converged"]
ok &= ("T = %.6g +- %.2g m^2/s^2" % (off["T_mean"], off["T_stderr"])) in sys.argv[2]
fit = off["analysis"]["sk"]["fit"]  # the fitted headline numbers follow T when there are any
ok &= ("; D_f (4.4) = " in sys.argv[2]) == ("D_f" in fit)
sys.exit(0 if ok else 1)
PY
check python3 - "$tmp/same" <<'PY'
import json, sys
d = sys.argv[1]
run = json.load(open(d + "/summary.json"))["analysis"]
off = json.load(open(d + "/analysis/summary.json"))["analysis"]
ok = True
for m in range(1, 13):
    a, b = run["moments"]["speed"]["m%d" % m], off["moments"]["speed"]["m%d" % m]
    ok &= abs(a - b) <= 1e-12 * abs(a)
for path in [("sk", "D_f"), ("pair", "first_peak_g")]:
    pass
a = open(d + "/sk.csv").read().splitlines()[3:]
b = open(d + "/analysis/sk.csv").read().splitlines()[3:]
ok &= a == b
a = open(d + "/pair.csv").read().splitlines()[3:]
b = open(d + "/analysis/pair.csv").read().splitlines()[3:]
ok &= a == b
sys.exit(0 if ok else 1)
PY
# no observables -> refused with exit 2
"$granule" analyse "$tmp/run1" --out "$tmp/an2" --set analysis.observables= >/dev/null 2>&1
check test $? -eq 2
# a folder without snapshots -> refused
"$granule" run "$src/docs/scenes/rfm-1d.ini" --quiet --out "$tmp/run2" --set system.N=50 --set run.warmup=0 \
    --set run.duration=0.002 --set output.snapshot_every=0 >/dev/null
"$granule" analyse "$tmp/run2" --set analysis.observables=moments >/dev/null 2>&1
check test $? -eq 2

# event-driven observables in a 2D run: free paths and post-collision velocities
"$granule" run "$src/docs/scenes/steady-2d.ini" --quiet --out "$tmp/ev" --set system.N=400 --set system.L=0.06 \
    --set run.warmup=0.005 --set run.duration=0.02 --set output.plots=false \
    --set analysis.observables=freepath,postcollision >/dev/null
check test -f "$tmp/ev/freepath.csv"
check test -f "$tmp/ev/postcollision.csv"
check python3 -c "import json,sys; a=json.load(open(sys.argv[1]))['analysis']; sys.exit(0 if a['freepath']['paths']>100 and a['postcollision']['post_samples']>100 else 1)" "$tmp/ev/summary.json"

# the transport, structure and pressure observables (docs/analysis.md): in a run and from snapshots
# at every sample, equal; collisions only in the run (rate x N x time = collisions counted)
for dim in 1 2; do
    scene=$src/docs/scenes/steady-2d.ini
    extra=(--set system.N=300 --set system.L=0.06 --set analysis.observables=msd,vacf,vcorr,clusters,pressure,collisions)
    if [[ $dim == 1 ]]; then
        scene=$src/docs/scenes/rfm-1d.ini
        extra=(--set system.N=200 --set analysis.observables=msd,vacf,clusters,pressure,collisions)
    fi
    "$granule" run "$scene" --quiet --out "$tmp/new$dim" "${extra[@]}" --set run.warmup=0.005 --set run.duration=0.02 \
        --set run.sample_every=0.001 --set output.snapshot_every=0.001 --set analysis.msd_lags=10 \
        --set analysis.vacf_lags=10 >/dev/null
    check "$granule" analyse "$tmp/new$dim"
    check python3 - "$tmp/new$dim" "$dim" <<'PY'
import json, sys
d, dim = sys.argv[1], int(sys.argv[2])
s = json.load(open(d + "/summary.json"))
run, off = s["analysis"], json.load(open(d + "/analysis/summary.json"))["analysis"]
ok = True
def close(a, b, rel=1e-9):
    return a is not None and b is not None and abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)
ok &= close(run["msd"]["D_self"]["value"], off["msd"]["D_self"]["value"], 1e-6)
ok &= close(run["vacf"]["D_green_kubo"]["value"], off["vacf"]["D_green_kubo"]["value"], 1e-6)
ok &= close(run["pressure"]["P"], off["pressure"]["P"], 1e-6) and run["pressure"]["P"] > 0
ok &= run["pressure"]["contacts_per_frame"] > 0 and run["pressure"]["collisional_xx"] > 0
ok &= run["clusters"]["contact"]["mean_size"] == off["clusters"]["contact"]["mean_size"]
ok &= run["msd"]["suspect_jumps"] == 0
if dim == 2:
    ok &= "C1" in run["pressure"]["eos_5_2"] and close(run["vcorr"]["C_L_first"], off["vcorr"]["C_L_first"], 1e-6)
c = run["collisions"]
ok &= c["collisions"] > 0 and c["rate_per_particle"] > 0 and c["rate_per_particle_error"] > 0
t = (run["msd"]["samples"] - 1) * run["msd"]["interval"]
ok &= close(c["rate_per_particle"] * s["scene"]["system"]["N"] * t, c["collisions"], 1e-6)
ok &= off["collisions"]["collisions"] == 0 and off["collisions"]["rate_per_particle"] is None and "note" in off["collisions"]
for f in ["msd.csv", "vacf.csv", "clusters.csv", "pressure.csv", "collisions.csv"] + (["vcorr.csv"] if dim == 2 else []):
    ok &= not open(d + "/" + f).readline().startswith("#")  # plain CSV: the column names first
    ok &= "granule" in open(d + "/" + f[:-4] + ".meta.json").read()  # the notes beside it
if not ok:
    print(json.dumps({k: run[k] for k in ["msd", "pressure", "collisions"]}, indent=1), file=sys.stderr)
sys.exit(0 if ok else 1)
PY
done

# compare: two models, one table row each, same initial state; the headline table on stdout
check "$granule" compare "$src/docs/scenes/steady-2d.ini" --models spring_dashpot+tangential_dashpot,spring_dashpot+sliding_friction \
    --set system.N=200 --set system.L=0.1 --set run.warmup=0 --set run.duration=0.005 --set output.plots=false --out "$tmp/cmp"
"$granule" compare "$src/docs/scenes/steady-2d.ini" --models spring_dashpot+tangential_dashpot,spring_dashpot+sliding_friction \
    --set system.N=200 --set system.L=0.1 --set run.warmup=0 --set run.duration=0.005 --set output.plots=false --out "$tmp/cmp" \
    --force >"$tmp/cmp.out" 2>/dev/null
check grep -q "^T (m^2/s^2) " "$tmp/cmp.out"
check grep -q "particle-steps/s" "$tmp/cmp.out"
check test "$(grep -vc '^#' "$tmp/cmp/compare.csv")" -eq 3
check grep -q "sliding_friction" "$tmp/cmp/compare.md"
# T_stderr_converged is a column, each model whose error bar is not converged is marked in its
# T cell with the footnote under the table (in words in compare.csv), and no nan anywhere
check python3 - "$tmp/cmp" "$tmp/cmp.out" <<'PY'
import csv, sys
d = sys.argv[1]
rows = list(csv.DictReader(l for l in open(d + "/compare.csv") if not l.startswith("#")))
md = open(d + "/compare.md").read()
out = open(sys.argv[2]).read()
assert "| T (m^2/s^2) |" in md
flags = [r["T_stderr_converged"] for r in rows]
assert all(f in ("0", "1") for f in flags), flags
for r in rows:
    # the footnote in words (a '*' or '#' mark stays in the tables; '#' would be a comment to numpy)
    assert (r["T_note"] == "error bar not converged (a lower bound): run longer") == (r["T_stderr_converged"] == "0"), r["model"]
assert "0" in flags, "a 0.005 s run should not have a converged error bar"
assert "*: the error bar of T is not converged" in md and "*: the error bar of T is not converged" in out
for text in (md, out, open(d + "/compare.csv").read()):
    assert "nan" not in text.lower(), text
assert "n/a: 2D" in md  # the G_1 exponent of a 2D scene
PY
# compare with mixed integrators: one 1D scene under verlet, hybrid and event-driven
check "$granule" compare "$src/docs/scenes/rfm-1d.ini" --models spring_dashpot,spring_dashpot@hybrid,hard_sphere@event \
    --set system.N=50 --set run.warmup=0 --set run.duration=0.01 --set output.plots=false --set output.snapshot_every=0 --out "$tmp/cmpi"
check grep -q "| integrator | verlet | hybrid | event |" "$tmp/cmpi/compare.md"
check grep -q "events/s" "$tmp/cmpi/compare.md"
"$granule" compare "$src/docs/scenes/rfm-1d.ini" --models spring_dashpot@event --out "$tmp/cmpi2" >/dev/null 2>"$tmp/cmpi2.err"
check test $? -eq 2
check grep -q "needs an event rule, \[model\] normal = hard_sphere" "$tmp/cmpi2.err"
check test ! -e "$tmp/cmpi2"
# granule plot recurses into the models of a comparison; --format svg; summary.json lists the pictures
cp "$tmp/cmpi/temperature.gp" "$tmp/temperature.gp.before"
"$granule" plot "$tmp/cmpi" --format svg >"$tmp/plot.out" 2>&1
check test $? -eq 0
# a redraw leaves the gnuplot bodies as they were (it once added a blank line each time)
check cmp -s "$tmp/cmpi/temperature.gp" "$tmp/temperature.gp.before"
check test -s "$tmp/cmpi/temperature.svg"
# it says what it drew: every picture's path, then the count (issue 38)
check grep -qx "$tmp/cmpi/temperature.svg" "$tmp/plot.out"
check grep -qx "$tmp/cmpi/spring_dashpot_hybrid/temperature.svg" "$tmp/plot.out"
check grep -qx "plot: drew $(($(grep -c '\.svg$\|\.png$' "$tmp/plot.out"))) pictures under $tmp/cmpi (graphs as svg)" "$tmp/plot.out"
check test -s "$tmp/cmpi/spring_dashpot_hybrid/temperature.svg"
check grep -q '"temperature.svg"' "$tmp/cmpi/hard_sphere_event/summary.json"
"$granule" plot "$tmp/cmpi" --format jpeg >/dev/null 2>"$tmp/plot.err"
check test $? -eq 2
check grep -q "png, svg or pdf" "$tmp/plot.err"
# granule run --format pdf: every plot a PDF, all listed in summary.json
check "$granule" run "$src/docs/scenes/rfm-1d.ini" --set system.N=50 --set run.warmup=0 --set run.duration=0.01 \
    --set analysis.observables=moments --set output.snapshot_every=0 --format pdf --out "$tmp/pdfrun" --quiet
check python3 - "$tmp/pdfrun" <<'PY'
import json, os, sys
d = sys.argv[1]
plots = json.load(open(d + "/summary.json"))["plots"]
assert sorted(plots) == sorted(f for f in os.listdir(d) if f.endswith(".pdf")), plots
assert {"temperature.pdf", "ledger.pdf", "moments.pdf"} <= set(plots), plots
assert all(open(os.path.join(d, f), "rb").read(4) == b"%PDF" for f in plots)
assert not [f for f in os.listdir(d) if f.endswith(".png")]
PY
"$granule" compare "$src/docs/scenes/rfm-1d.ini" --models spring_dashpot@warp --out "$tmp/cmpi2" >/dev/null 2>"$tmp/cmpi2.err"
check test $? -eq 2
check grep -q "@verlet | @event | @hybrid" "$tmp/cmpi2.err"
"$granule" compare "$src/docs/scenes/steady-2d.ini" --models nonsense --out "$tmp/cmp2" >/dev/null 2>&1
check test $? -eq 2

# sweep: 3 N x 2 seeds, then rerun: nothing is redone
cat >"$tmp/sweep.ini" <<EOT
[sweep]
scene = $src/docs/scenes/rfm-1d.ini
out = $tmp/sw
seeds = 1, 2
jobs = 2
[vary]
system.N = 20, 40, 80
[set]
run.warmup = 0
run.duration = 0.02
output.plots = false
output.snapshot_every = 0
analysis.observables = moments
EOT
check "$granule" sweep "$tmp/sweep.ini"
check test "$(grep -vc '^#' "$tmp/sw/sweep.csv")" -eq 7
# the claims and run locks end with the points: no lock file is left in a finished sweep (issue 38)
check test "$(find "$tmp/sw" -name '.point.lock' -o -name '.run.lock' | wc -l)" -eq 0
check python3 -c "import csv,sys; r=list(csv.DictReader(l for l in open(sys.argv[1]) if l[0] != '#')); sys.exit(0 if all(x['T_stderr_converged'] in ('0', '1') for x in r) else 1)" "$tmp/sw/sweep.csv"
check test -f "$tmp/sw/exponents.csv"
out=$("$granule" sweep "$tmp/sweep.ini" 2>/dev/null)
check grep -q "0 run now, 6 already finished" <<<"$out"
# a failing point is reported and the others complete
cat >"$tmp/sweep2.ini" <<EOT
[sweep]
scene = $src/docs/scenes/steady-2d.ini
out = $tmp/sw2
[vary]
system.N = 20, 5120
[set]
run.warmup = 0
run.duration = 0.001
output.plots = false
EOT
"$granule" sweep "$tmp/sweep2.ini" >/dev/null 2>&1
check test $? -eq 1
check grep -q ",completed," "$tmp/sw2/sweep.csv"
check grep -q ",failed," "$tmp/sw2/sweep.csv"
# sweep.csv carries R1..R12 (<R^m>, with their units) only when a point has them: a 1D sweep with
# the gaps observable (the 2D sweeps above have none: issue 38)
cat >"$tmp/sweep3.ini" <<EOT
[sweep]
scene = $src/docs/scenes/rfm-1d.ini
out = $tmp/sw3
[vary]
system.N = 50, 100
[set]
run.warmup = 0
run.duration = 0.005
output.plots = false
analysis.observables = gaps
EOT
check "$granule" sweep "$tmp/sweep3.ini"
check python3 - "$tmp/sw3" "$tmp/sw" <<'PY'
import csv, json, math, sys
with_R, without = (list(csv.DictReader(open(d + "/sweep.csv"))) for d in sys.argv[1:3])
units = json.load(open(sys.argv[1] + "/sweep.meta.json"))["units"]
ok = all(math.isfinite(float(r["R2"])) for r in with_R) and units["R3"] == "m3" and units["m3"] == "m3 s-3"
ok &= not any(k.startswith("R") for k in without[0])
sys.exit(0 if ok else 1)
PY

# the energy-ledger guard stops a run whose time step is far too coarse (forced), keeping outputs
"$granule" run "$src/docs/scenes/steady-2d.ini" --quiet --out "$tmp/coarse" --set integrator.dt=8e-6 \
    --set integrator.force_dt=true --set run.warmup=0 --set run.duration=0.02 --set output.plots=false >/dev/null 2>&1
check test $? -eq 3
check grep -q '"status":.*"unstable"' "$tmp/coarse/summary.json"
check grep -q "energy ledger does not balance" "$tmp/coarse/summary.json"
check test -s "$tmp/coarse/temperature.csv"

# reproduce: unknown figure refused; every observable is listed
"$granule" reproduce nonsense >/dev/null 2>&1
check test $? -eq 2
for o in moments pv postcollision freepath gaps sk pair; do
    check grep -q "^$o " <("$granule" observables)
done

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
