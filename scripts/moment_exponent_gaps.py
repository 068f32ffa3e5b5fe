#!/usr/bin/python3
"""The m-dependence of the velocity-moment exponents, xi_r/r - xi_m/m (Fig. 3.5, campaign ch3-moments).

The thesis states multi-scaling as differences from xi_2/2 (sec. 3.2.2: xi_m/m falls from 0.264 at
m = 2 to 0.252 at m = 5 and 0.247 at m = 6, so xi_2/2 - xi_m/m = 0.012 and 0.017; Fig. 3.4b: xi_1
falls to xi_9/9 by 0.264 - 0.228 = 0.036 at eps = 0.001). A difference of
two exponents fitted to the same runs cancels what they share (the finite-size offset of both), so
it is compared on its own. For each eps with every seed at every N >= N_MIN this fits
ln <|v|^m> = c - m (xi_m/m) ln N (3.13) to the seed means of <|v|^m> (analysis.moments.speed in each
point's summary) and takes the difference between the reference moment r (default 2) and each m
asked for. The error is the
jackknife over seeds: the fit repeated with each seed left out, sqrt((n-1)/n sum (d_i - mean d)^2).

usage: moment_exponent_gaps.py RESULTS [--n-min N_MIN] [--ref R] [--m M ...]   (CSV on standard output)
       RESULTS is a campaign's result folder (docs/results/ch3-moments: points/*.json)
"""
import argparse
import collections
import csv
import glob
import json
import math
import os
import sys

import numpy as np

NAME = os.path.basename(sys.argv[0])


def fail(msg):
    sys.exit(f"{NAME}: {msg}")


def load(results):
    """{eps: {N: {seed: {"m1": <|v|>, ...}}}} from every points/*.json under results."""
    files = sorted(glob.glob(os.path.join(results, "points", "*.json")))
    if not files:
        fail(f"no points/*.json in {results} (a campaign result folder, e.g. docs/results/ch3-moments)")
    by = collections.defaultdict(lambda: collections.defaultdict(dict))
    for f in files:
        try:
            p = json.load(open(f))
            keys = p["point"]["keys"]
            by[keys["model.eps_n"]][int(keys["system.N"])][p["point"]["seed"]] = p["summary"]["analysis"]["moments"]["speed"]
        except (KeyError, TypeError, ValueError) as e:
            fail(f"{f}: no model.eps_n, system.N, seed or analysis.moments.speed ({e!r})")
    return by


def exponent(runs, sizes, seeds, m):
    """xi_m/m from the least-squares line through (ln N, ln of the seed mean of <|v|^m>)."""
    y = [math.log(np.mean([runs[n][s][f"m{m}"] for s in seeds])) for n in sizes]
    return -np.polyfit(np.log(sizes), y, 1)[0] / m


def gaps(by, n_min, ref, ms):
    """Rows (eps, r, m, sizes, seeds, xi_r/r, xi_m/m, difference, jackknife error) for every complete eps."""
    rows = []
    for eps in sorted(by, key=float):
        runs = by[eps]
        sizes = sorted(n for n in runs if n >= n_min)
        seeds = sorted(runs[sizes[0]]) if sizes else []
        if len(sizes) < 3 or len(seeds) < 2 or any(sorted(runs[n]) != seeds for n in sizes):
            print(f"{NAME}: eps {eps} left out: needs the same >= 2 seeds at >= 3 sizes N >= {n_min}", file=sys.stderr)
            continue
        for m in ms:
            def diff(use):
                return exponent(runs, sizes, use, ref) - exponent(runs, sizes, use, m)
            jack = [diff([s for s in seeds if s != out]) for out in seeds]
            n = len(seeds)
            err = math.sqrt((n - 1) / n * sum((j - np.mean(jack)) ** 2 for j in jack))
            rows.append([eps, ref, m, f"{sizes[0]}-{sizes[-1]}", n, exponent(runs, sizes, seeds, ref),
                         exponent(runs, sizes, seeds, m), diff(seeds), err])
    return rows


def main():
    ap = argparse.ArgumentParser(prog=NAME, description=__doc__.split("\n")[0])
    ap.add_argument("results")
    ap.add_argument("--n-min", type=int, default=251, help="smallest N in the fits (the campaign's fig3.5 x_min)")
    ap.add_argument("--ref", type=int, default=2, help="the moment r the others are compared with")
    ap.add_argument("--m", type=int, nargs="+", default=[5, 6], help="moments compared with r")
    a = ap.parse_args()
    if any(m < 1 or m > 12 for m in a.m + [a.ref]):
        fail("--m and --ref take moments 1-12 (analysis.moments.speed has m1-m12)")
    rows = gaps(load(a.results), a.n_min, a.ref, a.m)
    if not rows:
        fail(f"no eps in {a.results} has the same >= 2 seeds at >= 3 sizes N >= {a.n_min}")
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["eps_n", "r", "m", "N", "seeds", "xi_r_over_r", "xi_m_over_m", "gap", "gap_err"])
    for r in rows:
        w.writerow(r[:5] + [f"{x:.5f}" for x in r[5:]])


if __name__ == "__main__":
    main()
