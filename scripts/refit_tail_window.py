#!/usr/bin/python3
"""Refit the tail exponent of Table 5.1 over other counts windows (docs/results/investigations).

The thesis fits P(v) = A exp(-(|v|/v0)^alpha) (5.5) to the counts X of the bins with 50 <= X <= 50 000,
errors sqrt(X) (sec. 5.1.1). The window is in absolute counts, so where it sits on the tail depends
on the sample: a sample f times smaller has counts X / f, and its window is our bins with
50 f <= X <= 50 000 f; the best alpha is the same (scaling X and its variance by 1/f scales chi2 by
1/f), its chi2/dof is ours divided by f. For each run folder given (with pv.csv) this prints the
free fit for f = 1/2 ... 10 (or the factors --factors lists), f = 1 being the fit in summary.json
(analysis.pv.tail.free). A RUN is a run folder, or a point a result set archived (RESULTS/points/
pNNNN.json, where the campaign keeps P(v): its series at 6 digits, counts = density x components
x bin width).

usage: refit_tail_window.py [--factors F,F,...] RUN [RUN ...]      (CSV on standard output)
"""
import csv
import json
import sys

import numpy as np

FACTORS = [0.5, 1, 2, 3, 5, 10]
LO, HI = 50.0, 50000.0


def load(run):
    if run.endswith(".json"):  # an archived point: P(v) as density, so counts = density components bin_width
        point = json.load(open(run))
        pv = point["summary"]["analysis"]["pv"]
        series = point["series"]["pv.csv?#v,density,density_error"]
        per_bin = pv["components"] * pv["bin_width"]
        return np.abs(np.array(series["x"])), np.round(np.array(series["y"]) * per_bin)
    v, c = [], []
    with open(run + "/pv.csv") as f:
        for r in csv.DictReader(f):
            v.append(abs(float(r["v"])))
            c.append(float(r["counts"]))
    return np.array(v), np.array(c)


def golden(g, a, b, tol):
    r = (5 ** 0.5 - 1) / 2
    c1, c2 = b - r * (b - a), a + r * (b - a)
    f1, f2 = g(c1), g(c2)
    while b - a > tol:
        if f1 < f2:
            b, c2, f2 = c2, c1, f1
            c1 = b - r * (b - a)
            f1 = g(c1)
        else:
            a, c1, f1 = c1, c2, f2
            c2 = a + r * (b - a)
            f2 = g(c2)
    return (a + b) / 2


def fit(v, c, lo, hi):
    """(alpha, chi2 per degree of freedom, bins) of the free fit over lo <= X <= hi."""
    m = (c >= lo) & (c <= hi) & (c > 0)
    x, y = v[m], c[m]

    def chi2(alpha, ln_v0):  # A enters linearly: its best value for given alpha, v0
        f = np.exp(-((x / np.exp(ln_v0)) ** alpha))
        d = np.sum(f * f / y)
        if not d > 0:
            return np.inf
        a = np.sum(f) / d
        return np.sum((y - a * f) ** 2 / y)

    def profile(alpha):  # chi2 at the best v0 for this alpha
        grid = np.linspace(np.log(1e-3), np.log(5.0), 120)
        k = int(np.argmin([chi2(alpha, g) for g in grid]))
        g = golden(lambda g: chi2(alpha, g), grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)], 1e-7)
        return chi2(alpha, g)

    grid = np.arange(0.4, 4.0, 0.02)
    k = int(np.argmin([profile(a) for a in grid]))
    alpha = golden(profile, grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)], 1e-6)
    return alpha, profile(alpha) / max(len(x) - 3, 1), len(x)


def point_of(run):
    """(group, seed) of a sweep point: its keys as in results.csv ("N+L=3000/0.2"), "" where unknown"""
    try:
        p = json.load(open(run))["point"] if run.endswith(".json") else json.load(open(run + "/point.json"))
    except OSError:
        return "", ""
    keys = "; ".join("%s=%s" % (k.replace("system.", "").replace("model.", ""), v) for k, v in p["keys"].items() if k != "run.seed")
    return keys, "%d" % p["seed"]


def main(args):
    factors = FACTORS
    if args[:1] == ["--factors"] and len(args) > 1:
        factors = [float(f) for f in args[1].split(",")]
        if not all(f > 0 for f in factors):
            raise ValueError("--factors %s: expected positive numbers" % args[1])
        args = args[2:]
    runs = args
    if not runs:
        sys.exit(__doc__)
    w = csv.writer(sys.stdout, lineterminator="\n")
    head = ["run", "group", "seed", "components"]
    for f in factors:
        head += ["alpha_sample_over_%g" % f, "chi2_red_sample_over_%g" % f]
    w.writerow(head)
    for run in runs:
        v, c = load(run)
        row = [run.rstrip("/"), *point_of(run.rstrip("/")), "%d" % c.sum()]  # velocity components sampled
        for f in factors:
            alpha, chi2_red, _ = fit(v, c, LO * f, HI * f)
            row += ["%.4f" % alpha, "%.3g" % (chi2_red / f)]
        w.writerow(row)
        sys.stdout.flush()


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except (OSError, KeyError, ValueError) as e:  # a run folder without the files or fields needed
        what = "no field %s in summary.json or the table" % e if isinstance(e, KeyError) else str(e)
        sys.exit("%s: %s (give run folders written with the observables this refit reads)" % (sys.argv[0].split("/")[-1], what))
