#!/usr/bin/python3
"""Refit D_f of S(k) = A k^-D_f (4.4) over other windows (docs/results/investigations).

The sk observable fits the lattice shells of sk_shells.csv with k < k' (k' = k_D above L_Eff, 2 k_D
below; Table 4.3), weighted least squares of ln S on ln k with sigma_ln S = S_err / S (the error of D_f inflated by
sqrt(chi2/dof) where that exceeds 1). This refits
the same shells below k_max = c k_D for several c, also without the lowest shells (the box scale)
and with equal weights (every shell's ln S alike, the error from the scatter), so a short window's
dependence on its ends and weights can be seen. The row with c = k'/k_D, no shell dropped and
weights "errors" is the fit in summary.json (analysis.sk.fit).

usage: refit_sk_window.py RUN [RUN ...]      (CSV on standard output)
"""
import csv
import json
import sys

import numpy as np

# (k_max / k_D, lowest shells dropped, weighted by the errors)
WINDOWS = [(1.0, 0, True), (1.0, 2, True), (4.0 / 3.0, 0, True), (2.0, 0, True), (2.0, 1, True), (2.0, 2, True), (1.0, 0, False), (2.0, 0, False)]


def fit(shells, k_max, drop, weighted=True):
    """(D_f, its error, chi2/dof, shells) of the fit of ln S on ln k for k < k_max (weighted by
    sigma_ln S, or equal weights: chi2/dof is then the scatter's variance, and the error from it)."""
    rows = [r for r in shells if float(r["k"]) < k_max * (1 + 1e-9)][drop:]
    if len(rows) < 3:  # as the observable: a slope and its error need three shells
        return float("nan"), float("nan"), float("nan"), len(rows)
    k = np.array([float(r["k"]) for r in rows])
    s = np.array([float(r["S"]) for r in rows])
    w = (s / np.array([float(r["S_err"]) for r in rows])) ** 2 if weighted else np.ones_like(s)
    x = np.vstack([np.ones_like(k), -np.log(k)]).T
    cov = np.linalg.inv(x.T @ (w[:, None] * x))
    p = cov @ x.T @ (w * np.log(s))
    chi2 = np.sum(w * (np.log(s) - x @ p) ** 2) / max(len(k) - 2, 1)
    # as the observable: the error is inflated by sqrt(chi2/dof) where the shells scatter more than their
    # errors; with equal weights the scatter is the only error there is
    return p[1], np.sqrt(cov[1, 1] * (max(chi2, 1.0) if weighted else chi2)), chi2, len(k)


def main(runs):
    if not runs:
        sys.exit(__doc__)
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["run", "k_D_d", "L_over_L_Eff", "kmax_over_kD", "shells_dropped", "weights", "shells", "kd_lo", "kd_hi", "D_f", "D_f_err", "chi2_red"])
    for run in runs:
        sk = json.load(open(run + "/summary.json"))["analysis"]["sk"]
        with open(run + "/sk_shells.csv") as f:
            shells = list(csv.DictReader(f))
        d = sk["k_D_d"] / sk["k_D"]
        for c, drop, weighted in WINDOWS:
            df, err, chi2, n = fit(shells, c * sk["k_D"], drop, weighted)
            used = [float(r["k"]) for r in shells if float(r["k"]) < c * sk["k_D"] * (1 + 1e-9)][drop:]
            ends = ["%.4g" % (used[0] * d), "%.4g" % (used[-1] * d)] if used else ["", ""]
            fitted = ["%.4f" % df, "%.4f" % err, "%.3g" % chi2] if n >= 3 else ["", "", ""]
            w.writerow([run.rstrip("/"), "%.4g" % sk["k_D_d"], "%.3g" % (sk["L"] / sk["L_Eff"]), "%.4g" % c, drop, "errors" if weighted else "equal", n] + ends + fitted)


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except (OSError, KeyError, ValueError) as e:  # a run folder without the files or fields needed
        what = "no field %s in summary.json or the table" % e if isinstance(e, KeyError) else str(e)
        sys.exit("%s: %s (give run folders written with the observables this refit reads)" % (sys.argv[0].split("/")[-1], what))
