#!/usr/bin/python3
"""Slopes of Fig. 5.13's tail plot over other windows (docs/results/investigations).

The campaign's result fig5.13-P0 (campaign ch4-structure) fits a line to -ln(-ln(P/P')), P' = P(0),
against ln(v/v_rms) over the bins with v >= 2 v_rms and at least 50 counts, weighted by the errors,
the error scaled by sqrt(chi2/dof). The thesis draws its line (-1.15 ln v + const) over ln(v/v_rms)
= 0.5-2 without stating a window. The tail plot is curved, so the slope depends on the window: this
refits the same bins over v >= 1.5, 2, 3, 4 and 5 v_rms and over the thesis's span, from the
result's gnuplot data (RESULT_tail.dat: each group's first run, the in_window column marking the
campaign's bins). The v >= 2 v_rms row is the campaign's own fit of that run.

usage: tail_plot_windows.py RESULTS_DIR [RESULT]   (RESULT default fig5.13-P0; CSV on standard output)
"""
import math
import sys

import numpy as np

WINDOWS = [("v>=1.5", 1.5, math.inf), ("v>=2", 2.0, math.inf), ("v>=3", 3.0, math.inf),
           ("v>=4", 4.0, math.inf), ("v>=5", 5.0, math.inf),
           ("ln(v/v_rms)=0.5-2", math.exp(0.5), math.exp(2.0))]


def blocks(path):
    """The groups of a _tail.dat file: name -> rows of its 11 columns."""
    out, name, rows = {}, None, []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            if line.startswith('"'):
                if name is not None:
                    out[name] = np.array(rows)
                name, rows = line.strip('"'), []
            else:
                rows.append([float(x) for x in line.split()])
    if name is not None:
        out[name] = np.array(rows)
    return out


def line_fit(x, y, sy):
    """Weighted straight line: slope, its error scaled by sqrt(chi2/dof) when that exceeds 1, chi2/dof."""
    w = 1.0 / sy**2
    a = np.vstack([x, np.ones_like(x)]).T
    cov = np.linalg.inv(a.T @ (a * w[:, None]))
    p = cov @ (a.T @ (w * y))
    chi2 = float(((y - a @ p) ** 2 * w).sum() / (len(x) - 2)) if len(x) > 2 else math.nan
    scale = math.sqrt(chi2) if chi2 > 1.0 else 1.0
    return p[0], math.sqrt(cov[0, 0]) * scale, chi2


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        sys.stderr.write(__doc__)
        return 2
    result = argv[2] if len(argv) > 2 else "fig5.13-P0"
    path = f"{argv[1]}/{result}_tail.dat"
    try:
        groups = blocks(path)
    except OSError as e:
        sys.stderr.write(f"tail_plot_windows.py: {path}: {e.strerror}\n")
        return 1
    print("group,seed,window,v_over_vrms_lo,v_over_vrms_hi,bins,slope,slope_err,chi2_red")
    for name, a in groups.items():
        _v, vr, p, pe, in_window, moon = a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 4], a[:, 7]
        ok = np.isfinite(moon)
        # P' from the file's own column: moon = -ln(-ln(P/P')), so P' = P / exp(-exp(-moon))
        p0 = float(np.median(p[ok] / np.exp(-np.exp(-moon[ok]))))
        # the campaign's bins (>= 50 counts) beyond 2 v_rms; below it every bin of the tail has more
        counted = (in_window > 0) | (vr < 2.0)
        for label, lo, hi in WINDOWS:
            s = ok & counted & (vr >= lo) & (vr <= hi) & (p < p0)
            if s.sum() < 3:
                print(f'"{name}",1,{label},{lo:.4g},{hi:.4g},{int(s.sum())},,,')
                continue
            r = p[s] / p0
            y = -np.log(-np.log(r))
            sy = pe[s] / (p[s] * np.abs(np.log(r)))
            slope, err, chi2 = line_fit(np.log(vr[s]), y, sy)
            top = float(vr[s].max()) if math.isinf(hi) else hi
            print(f'"{name}",1,{label},{lo:.4g},{top:.4g},{int(s.sum())},{slope:.6g},{err:.3g},{chi2:.4g}')
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
