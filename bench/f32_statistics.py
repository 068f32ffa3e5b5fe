#!/usr/bin/env python3
"""The 1D RFM scene with [noise] precision = double and = single: the same statistics?

    bench/f32_statistics.py GRANULE [--quick] [--seeds K] [--warmup S] [--duration S] [--jobs J]

Runs docs/scenes/rfm-1d.ini K times per precision (seeds 1..K for double, 101..100+K for single:
independent runs), then compares, quantity by quantity, the mean over the K runs of each precision:
the granular temperature T = <v^2>, the speed moments <|v|> and the flatness <v^4>/<v^2>^2, the P(v)
tail (the fraction of velocity samples with |v| > 2 and > 3 v_rms, from pv_tail.csv's counts) and
the reduced gap moments <g^2>/<g>^2 and <g^3>/<g>^3 (neighbours h = 1, gaps_moments.csv). The error
of each mean is the spread of the K runs (standard deviation / sqrt(K)), which holds whatever the
correlations inside a run; z = (single - double) / sqrt(err_single^2 + err_double^2). Prints a
Markdown table (docs/performance.md, "Single-precision noise") and exits 1 if any |z| > 4.

--quick (the test suite's noise-f32-run): 3 runs of 0.05 + 0.25 s per precision, about 10 s in all.
Defaults: 6 runs of 1 + 4 s (the scene's own warm-up and duration), 20-40 s per run on one
core. --jobs J runs J at a time (default 1).
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(SRC, "docs", "scenes", "rfm-1d.ini")


def run(granule, out, precision, seed, warmup, duration):
    cmd = [granule, "run", SCENE, "--out", out, "--quiet", "--set", f"noise.precision={precision}",
           "--set", f"run.seed={seed}", "--set", f"run.warmup={warmup}",
           "--set", f"run.duration={duration}", "--set", "output.plots=false",
           "--set", "output.snapshot_every=0", "--set", "run.checkpoint_wall=0",
           "--set", "analysis.observables=moments,gaps,pv"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    assert s["scene"]["noise"]["precision"] == precision, out
    q = {"T": s["T_mean"]}
    with open(os.path.join(out, "moments.csv")) as f:
        m = {int(r["m"]): float(r["component_moment"]) for r in csv.DictReader(f)}
    q["<|v|>"] = m[1]
    q["flatness <v^4>/<v^2>^2"] = m[4] / (m[2] * m[2])
    with open(os.path.join(out, "pv_tail.csv")) as f:
        rows = [(float(r["v_over_vrms"]), float(r["counts"])) for r in csv.DictReader(f)]
    total = sum(c for _, c in rows)
    for cut in (2.0, 3.0):
        q[f"P(|v| > {cut:g} v_rms)"] = sum(c for x, c in rows if x > cut) / total
    with open(os.path.join(out, "gaps_moments.csv")) as f:
        g = {int(r["m"]): float(r["reduced_moment"]) for r in csv.DictReader(f) if r["h"] == "1"}
    q["gap <g^2>/<g>^2"] = g[2]
    q["gap <g^3>/<g>^3"] = g[3]
    return q


def mean_err(xs):
    n = len(xs)
    mu = sum(xs) / n
    sd = math.sqrt(sum((x - mu) ** 2 for x in xs) / (n - 1)) if n > 1 else float("inf")
    return mu, sd / math.sqrt(n)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("granule")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--seeds", type=int)
    ap.add_argument("--warmup", type=float)
    ap.add_argument("--duration", type=float)
    ap.add_argument("--jobs", type=int, default=1)
    a = ap.parse_args()
    k = a.seeds or (3 if a.quick else 6)
    warmup = a.warmup if a.warmup is not None else (0.05 if a.quick else 1.0)
    duration = a.duration if a.duration is not None else (0.25 if a.quick else 4.0)
    if k < 2:
        sys.exit("f32_statistics.py: --seeds must be at least 2 (the error is the runs' spread)")
    with tempfile.TemporaryDirectory(prefix="granule-f32-stats-") as tmp:
        jobs = [(p, (1 if p == "double" else 101) + i) for p in ("double", "single")
                for i in range(k)]
        with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
            res = list(ex.map(lambda j: (j[0], run(a.granule, os.path.join(tmp, f"{j[0]}{j[1]}"),
                                                   j[0], j[1], warmup, duration)), jobs))
    per = {"double": [r for p, r in res if p == "double"],
           "single": [r for p, r in res if p == "single"]}
    print(f"1D RFM (docs/scenes/rfm-1d.ini), {k} runs per precision of {warmup:g} s warm-up + "
          f"{duration:g} s; error = spread of the runs / sqrt({k})\n")
    print("| quantity | double | single | z |")
    print("|---|---|---|---|")
    worst = 0.0
    for name in per["double"][0]:
        md, ed = mean_err([r[name] for r in per["double"]])
        ms, es = mean_err([r[name] for r in per["single"]])
        z = (ms - md) / math.sqrt(ed * ed + es * es) if ed + es > 0 else 0.0
        worst = max(worst, abs(z))
        print(f"| {name} | {md:.5g} +- {ed:.2g} | {ms:.5g} +- {es:.2g} | {z:+.2f} |")
    print(f"\nlargest |z| = {worst:.2f} ({'within' if worst <= 4 else 'OUTSIDE'} 4)")
    return 0 if worst <= 4 else 1


if __name__ == "__main__":
    sys.exit(main())
