#!/usr/bin/env bash
# Reproduction campaigns end to end at quick fidelity (docs/campaigns/README.md): every built-in
# campaign runs from a folder outside the source tree and writes a complete result set; a campaign
# killed with kill -9 mid-way continues and ends with the same numbers as an uninterrupted one; the
# generated page names every thesis value. No numeric agreement is asserted at quick fidelity.
set -uo pipefail
granule=$(realpath "$1")
scripts="$(cd "$(dirname "$0")/.." && pwd)/scripts"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
check() { if "$@"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAILED: $*" >&2; fi; }
cd "$tmp" || exit 1 # no docs/ here: the campaigns and scenes are built in

campaigns=$("$granule" reproduce --list | awk 'NR > 1 {print $1}')
check test "$(echo "$campaigns" | wc -w)" -ge 4
# the sanitizer pass (GRANULE_TEST_QUICK=1) runs two small campaigns; both kill the smallest 1D one
killed=ch3-renormalisation
if [[ -n "${GRANULE_TEST_QUICK:-}" ]]; then campaigns="ch2-placement ch3-renormalisation"; fi
for c in $campaigns; do
    "$granule" reproduce "$c" --out "$tmp/out" --results "$tmp/results/$c" --jobs 2 >"$tmp/$c.txt" 2>"$tmp/$c.err"
    check test $? -eq 0
    check grep -q "CPU-h left" "$tmp/$c.err"
    for f in results.csv results.json; do check test -s "$tmp/results/$c/$f"; done
    check test -n "$(ls "$tmp/results/$c/points/")"
done
# every result, every row, every field; a figure wherever a row has a value
check python3 - "$tmp/results" $campaigns <<'PY'
import json, os, sys
root, names = sys.argv[1], sys.argv[2:]
fields = ["group", "value", "error", "error_fit_or_run", "error_seeds", "seeds", "thesis", "thesis_error", "z",
          "simulated_seconds", "cpu_seconds", "scene_hashes"]
ok = True
def need(cond, *what):
    global ok
    if not cond:
        print(*what, file=sys.stderr)  # say which check failed (the suite prints stderr after stdout)
        ok = False
for n in names:
    d = json.load(open(os.path.join(root, n, "results.json")))
    for k in ["campaign", "title", "covers", "about", "fidelity", "commit", "points_finished", "points_total",
              "cpu_seconds", "simulated_seconds", "results"]:
        need(k in d, n, "no key", k)
    need(d["points_finished"] == d["points_total"] > 0, n, "points", d["points_finished"], "of", d["points_total"])
    need(d["cpu_seconds"] > 0, n, "cpu_seconds", d["cpu_seconds"])
    for r in d["results"]:
        need(len(r["rows"]) > 0, n, r["id"], "no rows")
        need(r.get("verdict") in ("", "explained", "partly explained", "unexplained") and "verdict_why" in r,
             n, r["id"], "verdict", r.get("verdict"))
        for row in r["rows"]:
            missing = [f for f in fields if f not in row]
            need(not missing, n, r["id"], "missing", missing)
        if any(row["value"] is not None for row in r["rows"]):
            need(os.path.exists(os.path.join(root, n, r["id"] + ".png")), n, r["id"], "no figure")
sys.exit(0 if ok else 1)
PY
check head -1 "$tmp/results/ch2-placement/results.csv" | grep -q "^campaign,result,quantity,unit,group,m,value,error,"
# every CSV of every result set: no cell holds a ',' or a '#' (numpy.genfromtxt knows no quoting and
# reads '#' as a comment; a group label's ", " is written "; "), so numpy reads the rows pandas does
# (with Debian's numpy where there is one; the cells are checked either way)
py=python3
if /usr/bin/python3 -c "import numpy" 2>/dev/null; then py=/usr/bin/python3; fi
check "$py" - "$tmp/results" <<'PY'
import csv, glob, os, sys
files = sorted(glob.glob(os.path.join(sys.argv[1], "*", "*.csv")))
sets = glob.glob(os.path.join(sys.argv[1], "*", "results.csv"))  # each with a data table at least
ok, labels = len(sets) > 0 and len(files) >= 2 * len(sets), set()
for f in files:
    rows = list(csv.reader(open(f)))
    bad = [c for r in rows for c in r if "," in c or "#" in c]
    if bad:
        print(f, "cells numpy splits or cuts:", bad[:2]); ok = False
    if rows and "group" in rows[0]:
        labels |= {r[rows[0].index("group")] for r in rows[1:] if r}
    try:
        import numpy as np
    except ImportError:
        continue
    try:
        a = np.atleast_1d(np.genfromtxt(f, names=True, delimiter=",", dtype=None, encoding="utf-8"))
    except ValueError as e:
        print(f, "numpy.genfromtxt:", str(e).splitlines()[:2]); ok = False; continue
    if len(a.dtype.names) != len(rows[0]) or len(a) != sum(1 for r in rows[1:] if r):
        print(f, "numpy reads", len(a.dtype.names), "columns,", len(a), "rows"); ok = False
# a label with more than one part ("eps_n=0.1; N=100", "uniform bisection (3.36); n = 9") was written
if not any("; " in g for g in labels):
    print("no group label with '; ' among", sorted(labels)[:8]); ok = False
sys.exit(0 if ok else 1)
PY
# Fig. 6.3: the cascade row beside the RFM's, both configurations in the figure's data
# a result that reads each run's T(t) (rise_time) cannot be recomputed from archived points (the
# archive keeps no T(t)): collecting restored points is refused, exit 1, and the result set that
# was there stays byte for byte (it used to come out with no values)
if [[ -d $tmp/results/ch2-rise ]]; then
    cp -r "$tmp/results/ch2-rise" "$tmp/rise-restored"
    before=$(cat "$tmp/rise-restored/results.json" "$tmp/rise-restored/results.csv" | md5sum)
    "$granule" reproduce ch2-rise --out "$tmp/rise-elsewhere" --results "$tmp/rise-restored" --jobs 1 >/dev/null 2>"$tmp/rise-restored.err"
    check test $? -eq 1
    check grep -q "reads each run's T(t) (temperature.csv).*nothing was written" "$tmp/rise-restored.err"
    check test "$(cat "$tmp/rise-restored/results.json" "$tmp/rise-restored/results.csv" | md5sum)" = "$before"
fi
if [[ -d $tmp/results/ch6-cascade ]]; then
    check grep -q '^ch6-cascade,fig6.3,D_f,"1","cascade placement (UCP)",0,[0-9]' "$tmp/results/ch6-cascade/results.csv"
    check grep -q "^rfm," "$tmp/results/ch6-cascade/fig6.3_positions.csv"
    check test "$(grep -c "^cascade," "$tmp/results/ch6-cascade/fig6.3_positions.csv")" -eq 400
    check test -s "$tmp/results/ch6-cascade/fig6.3_data.png"
    # restored elsewhere (the archive keeps no frames) the figure keeps the RFM snapshot it had
    cp -r "$tmp/results/ch6-cascade" "$tmp/cascade-restored"
    "$granule" reproduce ch6-cascade --out "$tmp/cascade-elsewhere" --results "$tmp/cascade-restored" --jobs 1 >/dev/null 2>&1
    check test $? -eq 0
    check test "$(grep -c "^rfm," "$tmp/cascade-restored/fig6.3_positions.csv")" -eq "$(grep -c "^rfm," "$tmp/results/ch6-cascade/fig6.3_positions.csv")"
    check cmp -s "$tmp/cascade-restored/fig6.3_positions.csv" "$tmp/results/ch6-cascade/fig6.3_positions.csv"
    # Table 6.2 (kind cascade_field): every variant's own D_f from 2 seeds at quick fidelity, the
    # thesis's six values beside them (the symmetrised cascade has none)
    check python3 - "$tmp/results/ch6-cascade" <<'PY'
import csv, json, os, sys
d = sys.argv[1]
res = {r["id"]: r for r in json.load(open(os.path.join(d, "results.json")))["results"]}
t = res.get("table6.2")
names = ["UCP", "UnonCP", "Symmetrised Cascade", "Meakin 1", "Meakin 2", "Meakin 3", "Meakin 4"]
ok = t is not None and t["kind"] == "cascade_field" and [r["group"] for r in t["rows"]] == names
ok = ok and [r["thesis"] for r in t["rows"]] == [1.602, 1.595, None, 1.287, 1.596, 1.828, 1.689]
ok = ok and all(r["seeds"] == 2 and r["value"] is not None and r["error"] > 0 for r in t["rows"] if r["group"] != "Symmetrised Cascade")
rows = list(csv.DictReader(open(os.path.join(d, "table6.2_data.csv")))) if ok else []
ok &= len(rows) == 14 and all(r["configurations"] == "10" for r in rows)
sk = open(os.path.join(d, "table6.2_sk.dat")).read() if ok else ""
ok &= sk.startswith('"UCP (x 1e-0)"') and sk.count('"') == 14 and os.path.getsize(os.path.join(d, "table6.2_data.png")) > 0
if not ok:
    print("cascade_field results incomplete")
sys.exit(0 if ok else 1)
PY
fi
# Figs. 5.12-5.13 (kind spm): every run's SPM analysis in the data CSV, the P(v) blocks of the
# figures, both figures; a result set restored elsewhere (no run tables, only the archived series)
# gives the same rows
if [[ -d $tmp/results/ch4-structure ]]; then
    d=$tmp/results/ch4-structure
    check python3 - "$d" <<'PY'
import csv, json, os, sys
d = sys.argv[1]
ids = ["fig4.10-tail", "fig5.12-C", "fig5.12-predicted", "fig5.12", "fig5.12-free", "fig5.13", "fig5.13-P0", "fig5.13-A0"]
res = {r["id"]: r for r in json.load(open(os.path.join(d, "results.json")))["results"]}
ok = all(i in res and res[i]["kind"] == "spm" and len(res[i]["rows"]) == 2 for i in ids)
cols = ["group", "seed", "D_f", "C", "alpha", "S_predicted", "S", "S_error", "S_over_predicted", "A0_over_P0", "slope_P0",
        "slope_A0", "v_lo", "v_hi", "fit_points", "decades", "chi2_red_531", "A0", "P0", "alpha_fit", "h_fit", "pl_l_lo", "pl_l_hi",
        "pl_points"]
for i in ids:
    rows = list(csv.DictReader(open(os.path.join(d, i + "_data.csv"))))
    ok &= len(rows) == 4 and all(c in rows[0] for c in cols)
    ok &= any(r[res[i]["y"]] not in ("", "nan") for r in rows)  # the runs give the quantity, not necessarily right
    tail = open(os.path.join(d, i + "_tail.dat")).read()
    ok &= tail.startswith('"N+L=') and len(tail.splitlines()) > 20
    ok &= os.path.getsize(os.path.join(d, i + "_data.png")) > 0
fixed = list(csv.DictReader(open(os.path.join(d, "fig5.12_data.csv"))))
ok &= all(r["D_f"] == "1.63" and abs(float(r["alpha_fit"]) - 0.9717) < 1e-3 for r in fixed)
expo = list(csv.DictReader(open(os.path.join(d, "fig5.13_data.csv"))))
ok &= all(r["alpha_fit"] == "1" and r["h_fit"] == "0" for r in expo if r["alpha_fit"] not in ("", "0"))
if not ok:
    print("spm results incomplete")
sys.exit(0 if ok else 1)
PY
    cp -r "$d" "$tmp/spm-restored"
    "$granule" reproduce ch4-structure --out "$tmp/spm-elsewhere" --results "$tmp/spm-restored" --jobs 1 >/dev/null 2>"$tmp/spm-restored.err"
    check test $? -eq 0
    check grep -q "finished points restored" "$tmp/spm-restored.err"
    check test ! -e "$tmp/spm-elsewhere/ch4-structure/quick/runs/p0000/pv.csv"
    check python3 - "$d" "$tmp/spm-restored" <<'PY'
import csv, os, sys
a, b = sys.argv[1:3]
ok = True
for i in ["fig4.10-tail", "fig5.12", "fig5.13-A0"]:
    ra, rb = (list(csv.DictReader(open(os.path.join(x, i + "_data.csv")))) for x in (a, b))
    for x, y in zip(ra, rb):
        for k in ["D_f", "C", "S", "slope_A0"]:
            if x[k] != y[k]:  # every series is read at the archive's 6 digits: equal, not close
                print("restored", i, x["group"], x["seed"], k, x[k], y[k]); ok = False
    ok &= len(ra) == len(rb) == 4
sys.exit(0 if ok else 1)
PY
fi

# scripts/refit_tail_window.py (docs/results/investigations): at f = 1 its fit of (5.5) is the
# run's own free fit (summary.json), so its refits for smaller samples use the campaign's method
# m = 3-12/3 (docs/campaigns/README.md): Fig. 5.2's moments 3, 6, 9, 12, each with its fit
if [[ -f $tmp/results/ch5-moments/results.csv ]]; then
    check test "$(awk -F, 'NR > 1 && $2 == "fig5.2" && $5 == "\"eps_n=0.1\"" {print $6}' "$tmp/results/ch5-moments/results.csv" | tr '\n' ' ')" = "3 6 9 12 "
    check test "$(awk -F, 'NR > 1 && $2 == "fig5.2" && $5 == "\"eps_n=0.1\"" && $7 != "" {n++} END {print n}' "$tmp/results/ch5-moments/results.csv")" = 4
fi
if [[ -d $tmp/out/ch5-alpha/quick/runs/p0001 ]]; then
    check python3 - "$scripts/refit_tail_window.py" "$tmp/out/ch5-alpha/quick/runs" <<'PY'
import csv, io, json, subprocess, sys
refit, runs = sys.argv[1:3]
dirs = [runs + "/p0000", runs + "/p0001"]
out = list(csv.DictReader(io.StringIO(subprocess.run([refit] + dirs, capture_output=True, text=True, check=True).stdout)))
ok = len(out) == 2
for d, row in zip(dirs, out):
    free = json.load(open(d + "/summary.json"))["analysis"]["pv"]["tail"]["free"]
    ok &= free["converged"] and abs(float(row["alpha_sample_over_1"]) - free["alpha"]) <= 1e-3
    ok &= abs(float(row["chi2_red_sample_over_1"]) - free["chi2_red"]) <= 0.01 * free["chi2_red"]
    if not ok:
        print("refit", d, row["alpha_sample_over_1"], row["chi2_red_sample_over_1"], "summary", free["alpha"], free["chi2_red"])
sys.exit(0 if ok else 1)
PY
fi

# scripts/refit_sk_window.py: its window c = k'/k_D with no shell dropped is the run's own D_f fit
# (a run with a fit, ch4-structure's; and one whose window holds too few shells, ch4-packing's)
if [[ -d $tmp/out/ch4-structure/quick/runs/p0000 && -d $tmp/out/ch4-packing/quick/runs/p0000 ]]; then
    check python3 - "$scripts/refit_sk_window.py" "$tmp/out/ch4-structure/quick/runs/p0000" "$tmp/out/ch4-packing/quick/runs/p0000" <<'PY'
import csv, io, json, subprocess, sys
refit, runs = sys.argv[1], sys.argv[2:]
rows = list(csv.DictReader(io.StringIO(subprocess.run([refit] + runs, capture_output=True, text=True, check=True).stdout)))
ok = len(rows) == 8 * len(runs)
for run in runs:
    sk = json.load(open(run + "/summary.json"))["analysis"]["sk"]
    c = sk["k_prime"] / sk["k_D"]
    own = [r for r in rows if r["run"] == run and abs(float(r["kmax_over_kD"]) - c) < 1e-6 and r["shells_dropped"] == "0" and r["weights"] == "errors"]
    ok &= len(own) == 1 and int(own[0]["shells"]) == sk["fit"]["shells"]
    if ok and sk["fit"]["status"] == "ok":
        ok &= abs(float(own[0]["D_f"]) - sk["fit"]["D_f"]) <= 1e-3 and abs(float(own[0]["D_f_err"]) - sk["fit"]["D_f_err"]) <= 1e-3
    elif ok:
        ok &= own[0]["D_f"] == ""
    if not ok:
        print("refit_sk_window", run, own, sk["fit"])
ok &= json.load(open(runs[0] + "/summary.json"))["analysis"]["sk"]["fit"]["status"] == "ok"
sys.exit(0 if ok else 1)
PY
fi

# scripts/tail_plot_windows.py (docs/results/investigations): its v >= 2 v_rms window is the
# campaign's own Fig. 5.13 fit of each group's first run, slope and error (scaled once by
# sqrt(chi2/dof)); it refuses a result set without the tail plot's data
if [[ -f $tmp/results/ch4-structure/fig5.13-P0_tail.dat ]]; then
    check python3 - "$scripts/tail_plot_windows.py" "$tmp/results/ch4-structure" <<'PY'
import csv, io, math, subprocess, sys
script, res = sys.argv[1:3]
rows = list(csv.DictReader(io.StringIO(subprocess.run([script, res], capture_output=True, text=True, check=True).stdout)))
own = {r["group"]: r for r in csv.DictReader(open(res + "/fig5.13-P0_data.csv")) if r["seed"] == "1"}
ok, compared = True, 0
for r in rows:
    if r["window"] != "v>=2" or r["group"] not in own or r["slope"] == "" or not math.isfinite(float(own[r["group"]]["slope_P0"])):
        continue
    o = own[r["group"]]
    same = abs(float(r["slope"]) - float(o["slope_P0"])) <= 1e-5 * abs(float(o["slope_P0"])) and \
        abs(float(r["slope_err"]) - float(o["slope_P0_error"])) <= 1e-2 * float(o["slope_P0_error"])
    compared += 1
    if not same:
        print("tail_plot_windows", r, o["slope_P0"], o["slope_P0_error"], file=sys.stderr)
        ok = False
ok &= compared > 0 and len({r["window"] for r in rows}) == 6
sys.exit(0 if ok else 1)
PY
    check bash -c '! "$1" "$2" >/dev/null 2>"$3" && grep -q "^tail_plot_windows.py: .*_tail.dat" "$3" && ! grep -q Traceback "$3"' _ \
        "$scripts/tail_plot_windows.py" "$tmp/no-such-results" "$tmp/windows.err"
fi

# scripts/result_windows.py (docs/results/investigations): from the archived points alone, the
# setting that is the campaign's own gives the campaign's numbers, for a key the result sets (x_min
# of fig5.12) and one it leaves at its default (pl_max of fig4.10-tail), and another setting moves
# the window; refit_tail_window.py reads an archived point as the run folder it came from (f = 1 is
# the archived summary's free fit); a folder that is no result set gets one line, no traceback
if [[ -f $tmp/results/ch4-structure/results.csv && -d $tmp/results/ch4-structure/points ]]; then
    check env GRANULE="$granule" python3 - "$scripts" "$tmp/results/ch4-structure" <<'PY'
import csv, io, json, subprocess, sys
scripts, res = sys.argv[1:3]
own = {(r["result"], r["group"]): r for r in csv.DictReader(open(res + "/results.csv"))}
ok, compared, moved = True, 0, 0
for rid, setting in [("fig5.12", "x_min=2,4"), ("fig4.10-tail", "pl_max=default,0.3")]:
    out = subprocess.run([scripts + "/result_windows.py", res, rid, setting], capture_output=True, text=True)
    rows = list(csv.DictReader(io.StringIO(out.stdout)))
    groups = {g for (i, g) in own if i == rid}
    ok &= out.returncode == 0 and len(rows) == 2 * len(groups) and len(groups) > 0
    for r in rows:
        o = own[(rid, r["group"])]
        if r["campaigns_own"] == "yes":
            compared += 1
            for k in ("value", "error", "seeds", "fit_points"):
                if r[k] != o[k]:
                    print("result_windows", rid, r["setting"], r["group"], k, r[k], o[k]); ok = False
        else:
            moved += r["fit_points"] != o["fit_points"] or r["value"] != o["value"]
ok &= compared > 0 and moved > 0
point = res + "/points/p0000.json"
free = json.load(open(point))["summary"]["analysis"]["pv"]["tail"]["free"]
out = subprocess.run([scripts + "/refit_tail_window.py", "--factors", "1,10", point], capture_output=True, text=True, check=True).stdout
row = list(csv.DictReader(io.StringIO(out)))[0]
if free["converged"]:
    ok &= abs(float(row["alpha_sample_over_1"]) - free["alpha"]) <= 2e-3
ok &= row["group"].startswith("N+L=") and row["seed"] == "1"
if not ok:
    print("result_windows/refit_tail_window:", compared, moved, row, free)
sys.exit(0 if ok else 1)
PY
    check bash -c '! "$1" "$2" fig5.12 x_min=2 >/dev/null 2>"$3" && grep -q "^result_windows.py: .*results.json" "$3" && ! grep -q Traceback "$3"' _ \
        "$scripts/result_windows.py" "$tmp/no-such-results" "$tmp/windows.err"
fi

# both refits refuse a folder without what they read, with a message and no traceback
check bash -c '! "$1" "$2" >/dev/null 2>"$3" && grep -q "^refit_tail_window.py: .*pv.csv" "$3" && ! grep -q Traceback "$3"' _ \
    "$scripts/refit_tail_window.py" "$tmp/no-such-run" "$tmp/refit.err"
if [[ -d $tmp/out/ch5-alpha/quick/runs/p0000 ]]; then # a run without the sk observable
    check bash -c '! "$1" "$2" >/dev/null 2>"$3" && grep -q "^refit_sk_window.py: no field .sk." "$3"' _ \
        "$scripts/refit_sk_window.py" "$tmp/out/ch5-alpha/quick/runs/p0000" "$tmp/refit.err"
fi

# Fig. 5.10 (kind spm_compare): every run's SPM walks from its own free paths against its
# snapshots' P(v) in the data CSV and the figure; restored elsewhere (no snapshots, only the
# archived series) the same rows
if [[ -d $tmp/results/ch5-spm-compare ]]; then
    d=$tmp/results/ch5-spm-compare
    check python3 - "$d" <<'PY'
import csv, json, os, sys
d = sys.argv[1]
res = {r["id"]: r for r in json.load(open(os.path.join(d, "results.json")))["results"]}
ids = ["fig5.10", "fig5.10-decades", "fig5.10-k", "fig5.10-s", "fig5.10-alpha-rfm", "fig5.10-alpha-spm"]
ok = all(i in res and res[i]["kind"] == "spm_compare" and len(res[i]["rows"]) == 1 for i in ids)
ok &= all(res[i]["rows"][0]["value"] is not None and res[i]["rows"][0]["seeds"] == 2 for i in ids)
for i in ids:
    rows = list(csv.DictReader(open(os.path.join(d, i + "_data.csv"))))
    ok &= len(rows) == 2 and all(c in rows[0] for c in ["frac_within", "decades", "k", "s", "alpha_spm", "alpha_rfm", "v_rms", "v_from"])
    ok &= 0.0 <= float(rows[0]["frac_within"]) <= 1.0 and float(rows[0]["k"]) > 0.0
    pv = open(os.path.join(d, i + "_pv.dat")).read()
    ok &= pv.startswith('"N = ') and "L = " in pv and pv.count(", seed ") == 2 and len(pv.splitlines()) > 20
    ok &= os.path.getsize(os.path.join(d, i + "_data.png")) > 0
point = json.load(open(os.path.join(d, "points", "p0000.json")))
ok &= any(k.startswith("spm_compare.csv") for k in point.get("series", {}))
if not ok:
    print("spm_compare results incomplete")
sys.exit(0 if ok else 1)
PY
    # Fig. 5.11 (kind spm_circle): Q(v,l) of walks in discs of fixed radius with the runs' M and D;
    # b per radius and pooled, the coefficient b (M^2 / 2 D l)^(2/3) per radius, u_l Q per radius
    check python3 - "$d" <<'PY'
import csv, json, math, os, sys
d = sys.argv[1]
res = {r["id"]: r for r in json.load(open(os.path.join(d, "results.json")))["results"]}
b, c = res.get("fig5.11"), res.get("fig5.11-coefficient")
ok = b is not None and c is not None and b["kind"] == c["kind"] == "spm_circle"
ok = ok and [r["group"] for r in b["rows"]] == ["l=0.0036", "l=0.01", "l=0.02", "l=0.04", "pooled"]
ok = ok and [r["group"] for r in c["rows"]] == ["l=0.0036", "l=0.01", "l=0.02", "l=0.04"]
ok = ok and all(r["thesis"] == 0.98 for r in b["rows"]) and c["rows"][0]["thesis"] == 6.56
rows = list(csv.DictReader(open(os.path.join(d, "fig5.11_data.csv")))) if ok else []
for r in rows[:4]:  # the coefficient is b in physical units: b (M^2 / 2 D l)^(2/3), Table 2.2's M and D
    l, bv, cv = float(r["l"]), float(r["b"]), float(r["coefficient"])
    ok &= abs(cv - bv * (3.53e-5 ** 2 / (2e-8 * l)) ** (2 / 3)) <= 1e-4 * cv
    ok &= abs(float(r["u_l"]) - (2e-8 * l / 3.53e-5 ** 2) ** (1 / 3)) <= 1e-4 * float(r["u_l"])
ok &= len(rows) == 5
q = open(os.path.join(d, "fig5.11_q.dat")).read() if ok else ""
ok &= q.startswith('"l = 3.6 mm"') and q.count('"l = ') == 4
ok &= os.path.getsize(os.path.join(d, "fig5.11_data.png")) > 0
if not ok:
    print("spm_circle results incomplete")
sys.exit(0 if ok else 1)
PY
    cp -r "$d" "$tmp/cmp-restored"
    "$granule" reproduce ch5-spm-compare --out "$tmp/cmp-elsewhere" --results "$tmp/cmp-restored" --jobs 1 >/dev/null 2>"$tmp/cmp-restored.err"
    check test $? -eq 0
    check grep -q "finished points restored" "$tmp/cmp-restored.err"
    check test ! -e "$tmp/cmp-elsewhere/ch5-spm-compare/quick/runs/p0000/snapshots"
    check python3 - "$d" "$tmp/cmp-restored" <<'PY'
import csv, os, sys
a, b = sys.argv[1:3]
ok = True
# the analysis reads every series at the archive's 6 digits, so the rows are equal, not close
for i in ["fig5.10", "fig5.10-decades", "fig5.10-k", "fig5.10-s", "fig5.10-alpha-rfm", "fig5.10-alpha-spm"]:
    ra, rb = (list(csv.DictReader(open(os.path.join(x, i + "_data.csv")))) for x in (a, b))
    ok &= len(ra) == len(rb) == 2
    for x, y in zip(ra, rb):
        for k in x:
            if x[k] != y.get(k):
                print("restored", i, x["seed"], k, x[k], y.get(k)); ok = False
sys.exit(0 if ok else 1)
PY
fi

# the page: an overview linking one page per campaign (RESULTS/NAME/README.md), every thesis value
# of every row on its campaign's page
"$granule" reproduce --page --results-root "$tmp/results" --output "$tmp/reproduction.md" >/dev/null
check test $? -eq 0
# the coverage table beside the results (docs/thesis-coverage.md): copied onto the page with its
# tally, and checked against every campaign's covers line; one that contradicts a campaign (an item
# it claims marked "not", a row naming a campaign that does not claim it) refuses the page, named
check test "$(grep -c '^## Coverage' "$tmp/reproduction.md")" -eq 0 # no coverage file: no section
# the committed reruns behind the sk window refits (docs/results/investigations/README.md) claim to
# reproduce the campaign's runs to every printed digit: their own-window row equals campaign_D_f
check python3 - "$scripts/../docs/results/investigations" <<'PY'
import csv, sys
inv, ok, seen = sys.argv[1], True, 0
for name, own in [("table4.1-phi0.177-windows.csv", "2"), ("table4.3-N12000.csv", "1")]:
    for r in csv.DictReader(open(inv + "/" + name)):
        if r["kmax_over_kD"] == own and r["shells_dropped"] == "0" and r["weights"] == "errors":
            seen += 1
            if r["D_f"] != r["campaign_D_f"]:
                print("rerun differs from the campaign:", name, r["seed"], r["D_f"], r["campaign_D_f"]); ok = False
sys.exit(0 if ok and seen == 5 else 1)
PY

# a note's "results/investigations/NAME" is a link where that file is committed, plain text where not
if [[ -d $tmp/results/ch4-structure ]]; then
    mkdir -p "$tmp/results/investigations" && : >"$tmp/results/investigations/fig5.13-P0-windows.csv"
    "$granule" reproduce --page --results-root "$tmp/results" --output "$tmp/linked.md" >/dev/null
    check grep -qF '[results/investigations/fig5.13-P0-windows.csv](../investigations/fig5.13-P0-windows.csv)' "$tmp/results/ch4-structure/README.md"
    check grep -qF ' results/investigations/table4.1-phi0.177.csv' "$tmp/results/ch4-structure/README.md"
    check test "$(grep -cF '[results/investigations/table4.1' "$tmp/results/ch4-structure/README.md")" -eq 0
    # the page links back to the overview
    check grep -qF '(../../linked.md)' "$tmp/results/ch4-structure/README.md"
    # every number a note quotes is committed: the page says so without exceptions, and a campaign
    # file may not mark numbers as uncommitted (the key is gone: refused as unknown, naming it)
    check python3 -c 'import sys; sys.exit("The\nnumbers a note quotes are in committed files under docs/results/ (an investigation it names is\nlinked).\n" not in open(sys.argv[1]).read())' "$tmp/linked.md"
    printf '[campaign]\ntitle = t\nscene = rfm-1d.ini\n[result r]\ntitle = t\nkind = mean\ny = T_mean\nuncommitted = x\n' >"$tmp/uncommitted.ini"
    check bash -c 'out=$("$1" reproduce "$2" --collect --out "$3" 2>&1); [[ $? -ne 0 && $out == *"uncommitted.ini:8"*"uncommitted: unknown key"* ]]' _ \
        "$granule" "$tmp/uncommitted.ini" "$tmp/u-out"
    rm -r "$tmp/results/investigations"
fi
cp "$scripts/../docs/thesis-coverage.md" "$tmp/thesis-coverage.md"
"$granule" reproduce --page --results-root "$tmp/results" --output "$tmp/covered.md" >/dev/null
check test $? -eq 0
check grep -q '^## Coverage of the thesis' "$tmp/covered.md"
check grep -qE '^[0-9]+ covered, [0-9]+ partly, [0-9]+ not' "$tmp/covered.md"
check grep -q '^| Table A.1 | covered | appA-pv, appA-alpha |' "$tmp/covered.md"
sed -i 's/^| Fig. 2.7 | covered | ch2-rise |/| Fig. 2.7 | not | |/; s/^| Table A.1 | covered | appA-pv, appA-alpha |/| Table A.1 | covered | appA-pv, appA-alpha, ch4-packing |/' "$tmp/thesis-coverage.md"
err=$("$granule" reproduce --page --results-root "$tmp/results" --output "$tmp/broken.md" 2>&1 >/dev/null)
check test $? -ne 0
check test ! -e "$tmp/broken.md"
check grep -q 'ch2-rise claims Fig. 2.7, marked "not"' <<<"$err"
check grep -q 'Table A.1 names ch4-packing, whose covers line does not claim it' <<<"$err"
rm "$tmp/thesis-coverage.md"
check python3 - "$tmp/results" "$tmp/reproduction.md" $campaigns <<'PY'
import json, os, re, sys
root, page, names = sys.argv[1], open(sys.argv[2]).read(), sys.argv[3:]
UNITS = {"L": " m", "reduced_length": " m", "radius": " m", "mass": " kg", "D": " N^2 s", "dt": " s", "duration": " s", "warmup": " s"}
def pretty(group):  # the page's labels: linked keys split, units added (reproduction_page.c)
    out = []
    for item in (i.strip() for i in group.split(",")):
        if "=" not in item:
            out.append(item); continue
        keys, values = item.split("=", 1)
        out += ["%s = %s%s" % (k, v, UNITS.get(k, "")) for k, v in zip(keys.split("+"), values.split("/"))]
    return ", ".join(out)
ok, seen = True, 0
for n in names:
    d = json.load(open(os.path.join(root, n, "results.json")))
    own = open(os.path.join(root, n, "README.md")).read()  # the campaign's page
    ok &= ("\n# " + d["title"]) in own
    # every figure it shows and every file it links sits where the link points
    for target in re.findall(r"\]\(([^)#]+)\)", own):
        if not target.startswith("http") and not os.path.exists(os.path.join(root, n, target)):
            print("broken link on", n, "page:", target); ok = False
    figures = [f for f in os.listdir(os.path.join(root, n)) if f.endswith(".png")]
    ok &= all("(%s)" % f in own for f in figures)
    # the heading adds the covers line in brackets: a title that names them too says them twice
    for item in d.get("covers", "").split(", "):
        if item and item in d["title"]:
            print("title repeats its covers:", n, item); ok = False
    for r in d["results"]:
        ok &= ("### %s: " % r["id"]) in own
        for row in r["rows"]:
            if row["thesis"] is None:
                continue
            seen += 1
            lines = [l for l in own.splitlines() if l.startswith("| " + pretty(row["group"])) and ("%g" % row["thesis"]) in l]
            if not lines:
                print("not on the page:", n, r["id"], row["group"], row["thesis"]); ok = False
# the overview's tally: numbers with a z, |z| > 2, and of those more than 5 % off, per campaign
for n in names:
    d = json.load(open(os.path.join(root, n, "results.json")))
    counted = [r for r in d["results"] if not r.get("restates")]  # a restatement is counted where its numbers are
    rows = [row for r in counted for row in r["rows"] if row["z"] is not None]
    off = [row for row in rows if abs(row["z"]) > 2]
    off5 = [row for row in off if not abs(row["value"] - row["thesis"]) <= 0.05 * abs(row["thesis"])]
    # the other kinds of comparison never give a z (docs/campaigns/README.md, "Kinds of comparison")
    for r in d["results"]:
        for row in r["rows"]:
            kind = row["comparison"]
            if kind != "z" and row["z"] is not None:
                print("a z for a comparison of kind", kind, n, r["id"], row["group"]); ok = False
            if kind == "z" and not (row["thesis_error"] or 0) > 0:
                print("kind z without a thesis error", n, r["id"], row["group"]); ok = False
    other = [row for r in counted for row in r["rows"] if row["comparison"] in ("stated", "about", "range", "model") and row["agrees"] is not None]
    differ = [row for row in other if row["agrees"] is False]
    want = "| %d | %d | %d | %d | %d |" % (len(rows), len(off), len(off5), len(other), len(differ))
    line = [l for l in page.splitlines() if l.startswith("| [%s](results/%s/README.md) |" % (n, n))]
    if len(line) != 1 or not line[0].endswith(want):
        print("tally of", n, "is not", want, line); ok = False
    # the table of disagreements: every result with a row at |z| > 2, once, with its verdict
    for r in d["results"]:
        k = sum(1 for row in r["rows"] if row["z"] is not None and abs(row["z"]) > 2) if not r.get("restates") else 0
        k2 = sum(1 for row in r["rows"] if row["agrees"] is False) if not r.get("restates") else 0
        line = [l for l in page.splitlines() if l.startswith("| [%s: %s](results/%s/README.md#%s-%s) |" % (n, r["id"], n, n, r["id"]))]
        verdict = r["verdict"] or "**not investigated yet**"
        bad = k or k2
        if len(line) != (1 if bad else 0) or (bad and " | %d of " % k not in line[0]) or (bad and " | %d of " % k2 not in line[0]) or (bad and " | %s | " % verdict not in line[0]):
            print("disagreement line of", n, r["id"], "wrong:", line); ok = False
        ok &= ('<a id="%s-%s"></a>' % (n, r["id"])) in open(os.path.join(root, n, "README.md")).read()
sys.exit(0 if ok and seen > 0 else 1)
PY

# a comparison figure is drawn against a physical abscissa where the rows' keys give one
# (campaign_compare_series.c): xi_m / m against m with one series per eps (Fig. 3.5's form), n_N
# against N with one series per eps; every fitted row of the result is a point of its series
if [[ -d $tmp/results/ch3-moments ]]; then
    check python3 - "$tmp/results/ch3-moments" <<'PY'
import json, os, sys
d = sys.argv[1]
res = {r["id"]: r for r in json.load(open(os.path.join(d, "results.json")))["results"]}
ok, checked = True, 0
for rid, by_m in [("fig3.5", True), ("fig3.12", False)]:
    want = set()
    for row in res[rid]["rows"]:
        if row.get("role") or row["value"] is None:
            continue
        items = dict(i.split("=") for i in row["group"].split(", "))
        series = "eps_n = " + items["eps_n"]
        x = float(row["m"]) if by_m else float(items["N"])
        want.add((series, x, "%.6g" % row["value"]))
    if not want:  # no fitted value (the quick campaign's fig3.5 has too few sizes): no figure
        continue
    checked += 1
    got, series = set(), None
    for line in open(os.path.join(d, rid + "_compare.dat")):
        line = line.strip()
        if line.startswith('"'):
            series = line.strip('"')
        elif line:
            x, v = line.split()[:2]
            got.add((series, float(x), v))
    if got != want:
        print(rid, "series figure: missing", sorted(want - got)[:3], "extra", sorted(got - want)[:3]); ok = False
sys.exit(0 if ok and checked else 1)
PY
fi

# kill -9 mid-campaign, run again: finished points are skipped, the interrupted one continues from
# its checkpoint, and the numbers equal those of the uninterrupted campaign above
c=$killed
( exec setsid "$granule" reproduce $c --out "$tmp/killed" --results "$tmp/killed-results" --jobs 1 >/dev/null 2>"$tmp/killed.err" ) &
pid=$!
for _ in $(seq 1 600); do
    [[ -f "$tmp/killed/$c/quick/runs/p0001/point.json" ]] && grep -q '"completed"' "$tmp/killed/$c/quick/runs/p0001/point.json" && break
    sleep 0.1
done
kill -9 -- -$pid 2>/dev/null
wait $pid 2>/dev/null
check test ! -f "$tmp/killed-results/results.json"
"$granule" reproduce $c --out "$tmp/killed" --results "$tmp/killed-results" --jobs 1 >/dev/null 2>"$tmp/resumed.err"
check test $? -eq 0
check grep -q "skipping finished point 0" "$tmp/resumed.err"
check python3 - "$tmp/results/$c/results.csv" "$tmp/killed-results/results.csv" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
keys = ["result", "group", "m", "value", "error", "error_seeds", "thesis", "z", "simulated_seconds"]
sys.exit(0 if len(a) == len(b) > 0 and all(x[k] == y[k] for x, y in zip(a, b) for k in keys) else 1)
PY
# a fresh folder restores the archived points from the result set and runs nothing
"$granule" reproduce $c --out "$tmp/elsewhere" --results "$tmp/killed-results" --jobs 1 >/dev/null 2>"$tmp/restored.err"
check test $? -eq 0
check grep -q "finished points restored" "$tmp/restored.err"
check test "$(grep -c "skipping finished point" "$tmp/restored.err")" -eq "$(python3 -c "import json; print(json.load(open('$tmp/killed-results/results.json'))['points_total'])")"
# curve results: restored points redraw them from the archived series; the live analysis reads
# its tables at the same 6 digits, so the rows are equal
check python3 - "$tmp/results/$c" "$tmp/killed-results" <<'PY'
import csv, json, os, sys
a, b = sys.argv[1:3]
rows = lambda d: list(csv.DictReader(open(os.path.join(d, "fig3.13_data.csv"))))
ra, rb = rows(a), rows(b)
ok = len(ra) == len(rb) > 50 and all(x[k] == y[k] for x, y in zip(ra, rb) for k in ("group", "x", "mean", "error", "seeds"))
ok &= os.path.exists(os.path.join(b, "fig3.13_data.png"))
p = json.load(open(os.path.join(a, "points", sorted(os.listdir(os.path.join(a, "points")))[0])))
ok &= any(len(s["x"]) > 50 for s in p.get("series", {}).values())
# the warm-up check: the restored runs have no T(t), so it comes from each point's archived drift
# (the same doubles, summed in the same order: equal)
wa, wb = (json.load(open(os.path.join(d, "results.json"))).get("warmup_check", {}) for d in (a, b))
print("warm-up check: live", wa, "restored", wb)
ok &= "drift" in wa and all(wa.get(k) == wb.get(k) for k in ("runs", "drift", "drift_error", "z"))
ok &= "runs_without_series" not in wb
sys.exit(0 if ok else 1)
PY

# refusals: an unknown campaign, a bad fidelity
"$granule" reproduce nonsense >/dev/null 2>&1
check test $? -eq 2
"$granule" reproduce $killed --fidelity medium >/dev/null 2>&1
check test $? -eq 2
check "$granule" reproduce table3.1 --help
# an spm result with an unknown quantity, a D_f out of range, an unknown tail form: refused, naming
# the file, the key and what is allowed
# (each key once: a key given twice in a section is refused before its value is looked at)
for bad in "y = Sx|y = Sx: allowed D_f, C, alpha" "y = S\\ndf = 2.5|df = 2.5: expected D_f in (1, 2)" "y = S\\ntail = gauss|tail = gauss: allowed 5.31, exponential"; do
    printf '[campaign]\ntitle = t\nscene = rfm-2d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 100\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 100\n[result r1]\nkind = spm\n%b\n' "${bad%%|*}" >"$tmp/bad-spm.ini"
    "$granule" reproduce "$tmp/bad-spm.ini" --out "$tmp/bad-spm-out" >/dev/null 2>"$tmp/bad-spm.err"
    check test $? -eq 2
    check grep -q "bad-spm.ini.*\[result r1\].*${bad#*|}" "$tmp/bad-spm.err"
    check test ! -e "$tmp/bad-spm-out"
done
# an spm_compare result with a quantity of another kind or too few walks: refused the same way
for bad in "y = S|y = S: allowed frac_within, decades" "y = k\nwalks = 10|walks = 10: expected an integer from 100"; do
    printf '[campaign]\ntitle = t\nscene = rfm-2d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 100\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 100\n[result r1]\nkind = spm_compare\n%b\n' "${bad%%|*}" >"$tmp/bad-cmp.ini"
    "$granule" reproduce "$tmp/bad-cmp.ini" --out "$tmp/bad-cmp-out" >/dev/null 2>"$tmp/bad-cmp.err"
    check test $? -eq 2
    check grep -q "bad-cmp.ini.*\[result r1\].*${bad#*|}" "$tmp/bad-cmp.err"
    check test ! -e "$tmp/bad-cmp-out"
done
# an spm_circle result with a quantity of another kind: refused the same way
printf '[campaign]\ntitle = t\nscene = rfm-2d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 100\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 100\n[result r1]\nkind = spm_circle\ny = k\n' >"$tmp/bad-circle.ini"
"$granule" reproduce "$tmp/bad-circle.ini" --out "$tmp/bad-circle-out" >/dev/null 2>"$tmp/bad-circle.err"
check test $? -eq 2
check grep -q "bad-circle.ini.*\[result r1\].*y = k: allowed b, coefficient" "$tmp/bad-circle.err"
check test ! -e "$tmp/bad-circle-out"

# select on a mean result (a campaign whose tables share runs): only the listed groups become rows
printf '[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N+model.eps_n = 50/0.5, 60/0.9\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 100\n[set]\nrun.warmup = 0.001\nrun.duration = 0.002\n[result both]\nkind = mean\nquantity = T\ny = T_mean\n[result one]\nkind = mean\nquantity = T\ny = T_mean\nselect = N+eps_n=60/0.9\n' >"$tmp/select.ini"
"$granule" reproduce "$tmp/select.ini" --out "$tmp/select-out" --results "$tmp/select-results" --jobs 1 >/dev/null 2>"$tmp/select.err"
check test $? -eq 0
check python3 - "$tmp/select-results/results.json" <<'PY'
import json, sys
res = {r["id"]: [row["group"] for row in r["rows"]] for r in json.load(open(sys.argv[1]))["results"]}
sys.exit(0 if res["both"] == ["N+eps_n=50/0.5", "N+eps_n=60/0.9"] and res["one"] == ["N+eps_n=60/0.9"] else 1)
PY
# a thesis entry whose group no row of a complete (full) campaign has is refused at collection,
# naming it, and no result set is written; spelt right, the same points collect
printf '[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 50\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N+model.eps_n = 50/0.5, 60/0.9\n[set]\nrun.warmup = 0.001\nrun.duration = 0.002\n[result one]\nkind = mean\nquantity = T\ny = T_mean\nthesis = N+eps_n=50/0.5: 0.03 +- 0.01\nthesis = N+eps_n=60/0.09: 0.03 +- 0.01\n' >"$tmp/misspelt.ini"
"$granule" reproduce "$tmp/misspelt.ini" --fidelity full --out "$tmp/misspelt-out" --results "$tmp/misspelt-results" --jobs 1 >/dev/null 2>"$tmp/misspelt.err"
check test $? -eq 1
check grep -q 'campaign misspelt, \[result one\]: 1 thesis entry names a group no row has, first "N+eps_n=60/0.09"' "$tmp/misspelt.err"
check test ! -e "$tmp/misspelt-results/results.json"
sed -i 's|60/0.09|60/0.9|' "$tmp/misspelt.ini"
"$granule" reproduce "$tmp/misspelt.ini" --fidelity full --out "$tmp/misspelt-out" --results "$tmp/misspelt-results" --collect >/dev/null 2>&1
check test $? -eq 0
check test -s "$tmp/misspelt-results/results.json"
# a text value longer than its field is refused, naming the key and the limit (never cut short)
long=$(printf 'x%.0s' $(seq 80))
printf '[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 50\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 100\n[result r1]\nkind = mean\ny = T_mean\nquantity = %s\n' "$long" >"$tmp/long.ini"
"$granule" reproduce "$tmp/long.ini" --out "$tmp/long-out" >/dev/null 2>"$tmp/long.err"
check test $? -eq 2
check grep -q "long.ini.*\[result r1\] quantity: 80 characters, at most 63 allowed" "$tmp/long.err"
check test ! -e "$tmp/long-out"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
