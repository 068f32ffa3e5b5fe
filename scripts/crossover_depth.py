#!/usr/bin/python3
"""How deep the crossover fit (5.32) reaches, and where it would land deeper (Tables 5.3-5.4).

The pv observable fits P_0(v) (5.32) to ln P(v) over every bin with >= 50 counts, and again over
the bins with >= 500, 5000, ... counts: the same fit one, two, ... decades less deep below the
peak (summary.json analysis.pv.crossover_log.by_depth; docs/analysis-velocity.md). The thesis
sampled "6 to 8 decades" of P(v) (sec. 5.3.4); our runs reach 4-5. This reads a committed result
set's archived points (RESULTS/points/pNNNN.json) and writes, per system (the campaign's varied
keys) and seed and for the seed mean:

- kind "fit": v_r and v_c/v_r at each depth, and `step`, the relative change of v_r from the next
  deeper fit (v_r(d) / v_r(d + 1) - 1: what one more decade of depth did);
- kind "extrapolated": the deepest fit continued to D decades below the peak (--decades, default
  6, 7, 8) with each further decade's step the previous one times RATIO (--ratio, default 1/2):
  v(D) = v(d0) + s1 q (1 - q^n) / (1 - q), n = D - d0, s1 = v(d0) - v(d0 - 1) the last measured
  step. Indicative only: it assumes the steps keep shrinking geometrically. `step_ratio` on these
  rows is the measured ratio of the two deepest steps, s1 / s2, to compare with RATIO.

With two or more seeds per system, rows "mean" follow: the seeds' v_r and v_c/v_r averaged depth
by depth, v_r_err the standard error over the seeds.

usage: crossover_depth.py [--decades D,D,...] [--ratio Q] RESULTS     (CSV on standard output)
"""
import argparse
import csv
import glob
import json
import math
import os
import sys

NAME = os.path.basename(sys.argv[0])
COLUMNS = ["system", "seed", "kind", "counts_min", "decades", "n_points", "v_r", "v_r_err",
           "v_c_over_v_r", "chi2_red", "step", "step_ratio"]


def fail(message):
    sys.stderr.write("%s: %s\n" % (NAME, message))
    sys.exit(1)


def decades_list(text):
    try:
        out = [float(d) for d in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError("expects numbers separated by commas, not '%s'" % text)
    if not all(math.isfinite(d) and d > 0 for d in out):
        raise argparse.ArgumentTypeError("must be positive numbers, not '%s'" % text)
    return out


def arguments():
    ap = argparse.ArgumentParser(prog=NAME, description=__doc__.split("\n")[0])
    ap.error = lambda message: fail(message)  # one line, as the other refusals
    ap.add_argument("results", help="a committed result set, docs/results/NAME")
    ap.add_argument("--decades", type=decades_list, default=[6.0, 7.0, 8.0],
                    help="where to continue the deepest fit to (default 6,7,8)")
    ap.add_argument("--ratio", type=float, default=0.5, help="each further step over the one before (default 0.5)")
    a = ap.parse_args()
    if not 0.0 < a.ratio < 1.0:
        fail("--ratio must lie between 0 and 1 (a shrinking step), not %g" % a.ratio)
    return a.decades, a.ratio, a.results


def load(results):
    files = sorted(glob.glob(os.path.join(results, "points", "p*.json")))
    if not files:
        fail("no points/*.json in %s (a committed result set, docs/results/NAME)" % results)
    runs = {}
    for path in files:
        try:
            point = json.load(open(path))
            keys = point["point"]["keys"]
            seed = int(point["point"]["seed"])
        except (OSError, ValueError, KeyError, TypeError) as e:
            fail("%s: not an archived point (%s)" % (path, e))
        depth = point.get("summary", {}).get("analysis", {}).get("pv", {}).get("crossover_log", {}).get("by_depth")
        if not depth:
            fail("%s has no analysis.pv.crossover_log.by_depth (a run made before 2026-12-02: rerun the campaign)" % path)
        system = " ".join("%s=%s" % (k.replace("model.", "").replace("system.", ""), v) for k, v in keys.items())
        runs.setdefault(system, {})[seed] = [d for d in depth if d.get("converged")]
    return runs


def fit_rows(system, seed, depths):
    rows = []
    for i, d in enumerate(depths):
        deeper = depths[i - 1] if i > 0 else None  # by_depth runs from the deepest (>= 50 counts)
        rows.append({"system": system, "seed": seed, "kind": "fit", "counts_min": d["counts_min"],
                     "decades": d["decades"], "n_points": d.get("n_points", ""), "v_r": d["v_r"],
                     "v_r_err": d["v_r_err"], "v_c_over_v_r": d["v_c_over_v_r"],
                     "chi2_red": d.get("chi2_red", ""),
                     "step": d["v_r"] / deeper["v_r"] - 1.0 if deeper else ""})
    return rows


def extrapolated(system, seed, depths, decades, ratio):
    if len(depths) < 3:
        return []
    rows = []
    for D in decades:
        n = D - depths[0]["decades"]
        if n <= 0:
            continue
        out = {"system": system, "seed": seed, "kind": "extrapolated", "counts_min": "",
               "decades": D, "n_points": "", "v_r_err": "", "chi2_red": "", "step": ""}
        for key in ("v_r", "v_c_over_v_r"):
            s1 = depths[0][key] - depths[1][key]
            out[key] = depths[0][key] + s1 * ratio * (1.0 - ratio ** n) / (1.0 - ratio)
        s2 = depths[1]["v_r"] - depths[2]["v_r"]
        out["step_ratio"] = (depths[0]["v_r"] - depths[1]["v_r"]) / s2 if s2 else ""
        rows.append(out)
    return rows


def mean_depths(seeds):
    """The seeds' fits averaged depth by depth, over the depths every seed has."""
    n = min(len(d) for d in seeds.values())
    out = []
    for i in range(n):
        at = [seeds[s][i] for s in sorted(seeds)]
        m = {"counts_min": at[0]["counts_min"], "decades": sum(a["decades"] for a in at) / len(at),
             "n_points": "", "chi2_red": ""}
        for key in ("v_r", "v_c_over_v_r"):
            m[key] = sum(a[key] for a in at) / len(at)
        if len(at) > 1:
            var = sum((a["v_r"] - m["v_r"]) ** 2 for a in at) / (len(at) - 1)
            m["v_r_err"] = math.sqrt(var / len(at))
        else:
            m["v_r_err"] = at[0]["v_r_err"]
        out.append(m)
    return out


def main():
    decades, ratio, results = arguments()
    runs = load(results)
    w = csv.DictWriter(sys.stdout, COLUMNS, lineterminator="\n")
    w.writeheader()
    fmt = lambda v: "%.6g" % v if isinstance(v, float) else v
    for system in runs:  # in the campaign's order
        seeds = runs[system]
        rows = []
        for seed in sorted(seeds):
            rows += fit_rows(system, seed, seeds[seed]) + extrapolated(system, seed, seeds[seed], decades, ratio)
        if len(seeds) > 1:
            mean = mean_depths(seeds)
            rows += fit_rows(system, "mean", mean) + extrapolated(system, "mean", mean, decades, ratio)
        for r in rows:
            r.setdefault("step_ratio", "")
            w.writerow({k: fmt(r[k]) for k in COLUMNS})


if __name__ == "__main__":
    main()
