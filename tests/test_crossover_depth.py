"""scripts/crossover_depth.py (docs/results/investigations/*-crossover-depth.csv) on made-up archived
points whose crossover fits follow a known law of depth:

- v_r(d) = V + a 2^-d over depths d = 4.5, 3.5, 2.5 (bins with >= 50, 500, 5000 counts), so each
  step halves and the extrapolation with --ratio 0.5 must give V + a 2^-D exactly, and the
  measured step_ratio s1 / s2 must be 1/2;
- `step` is v_r(d) / v_r(d + 1) - 1 and the deepest fit has none;
- the seed mean averages the seeds and its error is their standard error; one seed gives no mean;
- the committed investigations/table5.3-depth-L0.*.csv are the script's output on the committed archives;
- a point without by_depth, an empty folder and a bad --ratio are refused with one line and no
  traceback; a depth deeper than wanted gives no extrapolated row.

usage: test_crossover_depth.py BUILD_DIR SOURCE_DIR
"""
import csv
import io
import json
import math
import os
import subprocess
import sys
import tempfile

from checks import check, finish

SCRIPT = os.path.join(sys.argv[2], "scripts", "crossover_depth.py")
DEPTHS = [(50, 4.5), (500, 3.5), (5000, 2.5)]


def law(V, a, d):
    return V + a * 2.0 ** -d


def write_points(folder, systems, without_depth=False):
    os.makedirs(os.path.join(folder, "points"))
    k = 0
    for label, (V, a, C, b) in systems.items():
        for seed, shift in ((1, -0.001), (2, 0.001)):
            depth = [{"counts_min": c, "decades": d, "n_points": 100 - 10 * i, "converged": True,
                      "v_r": law(V, a, d) + shift, "v_r_err": 0.0005,
                      "v_c_over_v_r": law(C, b, d), "chi2_red": 0.01} for i, (c, d) in enumerate(DEPTHS)]
            pv = {"crossover_log": {} if without_depth else {"by_depth": depth}}
            p = {"point": {"keys": {"model.eps_n+model.eps_t": label}, "seed": seed},
                 "summary": {"analysis": {"pv": pv}}}
            json.dump(p, open(os.path.join(folder, "points", "p%04d.json" % k), "w"))
            k += 1


def run(folder, *extra):
    r = subprocess.run([sys.executable, SCRIPT, *extra, folder], capture_output=True, text=True)
    return r.returncode, list(csv.DictReader(io.StringIO(r.stdout))), r.stderr


SYSTEMS = {"0.1/0.1": (0.17, -0.3, 1.5, -4.0), "0.4/1.0": (0.35, 0.2, 4.4, 6.0)}
with tempfile.TemporaryDirectory() as tmp:
    good = os.path.join(tmp, "good")
    write_points(good, SYSTEMS)
    rc, rows, err = run(good, "--decades", "6,8")
    check(rc == 0, "good: rc %d %s" % (rc, err))
    for label, (V, a, C, b) in SYSTEMS.items():
        system = "eps_n+eps_t=" + label
        mine = [r for r in rows if r["system"] == system]
        check(len(mine) == 3 * (3 + 2), "%s: 3 depths and 2 extrapolations for 2 seeds and the mean: %d rows" % (system, len(mine)))
        for seed, shift in (("1", -0.001), ("2", 0.001), ("mean", 0.0)):
            fits = [r for r in mine if r["seed"] == seed and r["kind"] == "fit"]
            ext = [r for r in mine if r["seed"] == seed and r["kind"] == "extrapolated"]
            check([float(r["decades"]) for r in fits] == [d for _, d in DEPTHS], "%s %s depths %s" % (system, seed, fits))
            for r, (_, d) in zip(fits, DEPTHS):
                check(abs(float(r["v_r"]) - (law(V, a, d) + shift)) < 1e-6, "%s %s v_r at %g: %s" % (system, seed, d, r["v_r"]))
            check(fits[0]["step"] == "", "the deepest fit has no step: %s" % fits[0])
            want = (law(V, a, 3.5) + shift) / (law(V, a, 4.5) + shift) - 1.0
            check(abs(float(fits[1]["step"]) - want) < 1e-5, "%s %s step %s against %.6f" % (system, seed, fits[1]["step"], want))
            for r, D in zip(ext, (6.0, 8.0)):
                check(abs(float(r["v_r"]) - (law(V, a, D) + shift)) < 1e-6, "%s %s v_r extrapolated to %g: %s against %.6f" % (system, seed, D, r["v_r"], law(V, a, D) + shift))
                check(abs(float(r["v_c_over_v_r"]) - law(C, b, D)) < 1e-5, "%s %s v_c/v_r extrapolated to %g: %s" % (system, seed, D, r["v_c_over_v_r"]))
                check(abs(float(r["step_ratio"]) - 0.5) < 1e-4, "halving steps: s1/s2 = 1/2, got %s" % r["step_ratio"])
        mean = [r for r in mine if r["seed"] == "mean" and r["kind"] == "fit"][0]
        check(abs(float(mean["v_r_err"]) - 0.001) < 1e-7, "standard error of two seeds 0.002 apart: %s" % mean["v_r_err"])

    # --ratio 0.25 with halving data: no longer exact, and moves the extrapolation the right way
    rc, rows, _ = run(good, "--decades", "8", "--ratio", "0.25")
    r = [r for r in rows if r["seed"] == "mean" and r["kind"] == "extrapolated" and r["system"].endswith("0.1/0.1")][0]
    V, a = SYSTEMS["0.1/0.1"][:2]
    s1 = law(V, a, 4.5) - law(V, a, 3.5)
    check(rc == 0 and abs(float(r["v_r"]) - (law(V, a, 4.5) + s1 * 0.25 * (1 - 0.25 ** 3.5) / 0.75)) < 1e-6, "--ratio 0.25: %s" % r)
    # no decade beyond the deepest fit: no extrapolated row
    rc, rows, _ = run(good, "--decades", "4")
    check(rc == 0 and rows and all(r["kind"] == "fit" for r in rows), "--decades 4 gives fits only")

    one = os.path.join(tmp, "one")
    write_points(one, {"0.1/0.1": SYSTEMS["0.1/0.1"]})
    os.remove(os.path.join(one, "points", "p0001.json"))
    rc, rows, _ = run(one, "--decades", "7")
    check(rc == 0 and len(rows) == 4 and {r["seed"] for r in rows} == {"1"}, "one seed: its rows, no mean: %s" % rows)

    # the committed investigations are what the script makes of the committed archives, to the digit
    for name, results in (("table5.3-depth-L0.4.csv", "ch5-crossover-size"), ("table5.3-depth-L0.2.csv", "ch5-dissipation")):
        docs = os.path.join(sys.argv[2], "docs", "results")
        r = subprocess.run([sys.executable, SCRIPT, os.path.join(docs, results)], capture_output=True, text=True)
        check(r.returncode == 0 and r.stdout == open(os.path.join(docs, "investigations", name)).read(),
              "investigations/%s is crossover_depth.py of docs/results/%s" % (name, results))

    old = os.path.join(tmp, "old")
    write_points(old, SYSTEMS, without_depth=True)
    for folder, extra, want in ((old, [], "by_depth"), (os.path.join(tmp, "nothing"), [], "no points/*.json"),
                                (good, ["--ratio", "1.5"], "--ratio must lie"), (good, ["--decades", "x"], "expects numbers separated by commas")):
        rc, rows, err = run(folder, *extra)
        check(rc != 0 and rows == [] and err.startswith("crossover_depth.py: ") and want in err and "Traceback" not in err
              and err.count("\n") == 1, "refused with one line naming %s: %r" % (want, err))

finish()
