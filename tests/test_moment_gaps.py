"""scripts/moment_exponent_gaps.py (docs/results/investigations/fig3.5-m-dependence.csv) on made-up
campaign results whose moments follow known power laws <|v|^m> = a_m N^-(m x_m) (3.13):

- seed factors that do not depend on N leave every fit exact: the gap x_2 - x_m comes out to
  rounding and its jackknife error is 0;
- one seed whose m = 6 moment scales differently moves the gap and gives a jackknife error equal
  to the one computed here by hand from the three leave-one-out fits;
- --ref 1 compares with xi_1 instead of xi_2/2 (Fig. 3.4b's 0.264 - 0.228);
- an eps with a missing seed is left out with a message; an empty folder is refused without a
  traceback.

usage: test_moment_gaps.py BUILD_DIR SOURCE_DIR
"""
import csv
import io
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

SCRIPT = os.path.join(sys.argv[2], "scripts", "moment_exponent_gaps.py")
SIZES = [100, 251, 398, 631, 1000, 2512]
X = {1: 0.27, 2: 0.26, 5: 0.25, 6: 0.24}  # x_m = xi_m / m
failed = 0


def check(ok, what):
    global failed
    if not ok:
        failed += 1
        print("FAILED:", what)


def write_points(folder, moments):
    """moments(eps, N, seed) -> {"m1": ..}; one points/pNNNN.json per (eps, N, seed) it returns."""
    os.makedirs(os.path.join(folder, "points"))
    k = 0
    for eps in ("0.1", "0.5"):
        for n in SIZES:
            for seed in (1, 2, 3):
                speed = moments(eps, n, seed)
                if speed is None:
                    continue
                p = {"point": {"keys": {"model.eps_n": eps, "system.N": str(n)}, "seed": seed},
                     "summary": {"analysis": {"moments": {"speed": speed}}}}
                json.dump(p, open(os.path.join(folder, "points", "p%04d.json" % k), "w"))
                k += 1


def run(folder, *extra):
    r = subprocess.run([sys.executable, SCRIPT, folder, *extra], capture_output=True, text=True)
    return r.returncode, list(csv.DictReader(io.StringIO(r.stdout))), r.stderr


def power(n, m, x, scale=1.0):
    return scale * (m + 1.0) * n ** (-m * x)


with tempfile.TemporaryDirectory() as tmp:
    # exact power laws, seed factors independent of N
    exact = os.path.join(tmp, "exact")
    write_points(exact, lambda eps, n, seed: {"m%d" % m: power(n, m, x, 1 + 0.1 * seed) for m, x in X.items()})
    rc, rows, err = run(exact, "--m", "1", "5", "6")
    check(rc == 0 and len(rows) == 6, "exact: rc %d, %d rows, %s" % (rc, len(rows), err))
    for r in rows:
        m = int(r["m"])
        check(r["N"] == "251-2512" and r["seeds"] == "3", "exact: sizes >= 251, three seeds: %s" % r)
        check(r["r"] == "2" and abs(float(r["xi_r_over_r"]) - X[2]) < 2e-5 and abs(float(r["xi_m_over_m"]) - X[m]) < 2e-5, "exact exponents: %s" % r)
        check(abs(float(r["gap"]) - (X[2] - X[m])) < 2e-5 and float(r["gap_err"]) < 2e-5, "exact gap: %s" % r)
    rc, rows, _ = run(exact, "--n-min", "100")
    check(rc == 0 and all(r["N"] == "100-2512" and r["m"] in ("5", "6") for r in rows) and len(rows) == 4, "--n-min 100, default m")
    rc, rows, _ = run(exact, "--ref", "1", "--m", "6")
    check(rc == 0 and len(rows) == 2 and all(r["r"] == "1" and abs(float(r["gap"]) - (X[1] - X[6])) < 2e-5 for r in rows), "--ref 1")

    # seed 3's m = 6 moment falls faster: x_6 + 0.01
    shifted = os.path.join(tmp, "shifted")
    def moments(eps, n, seed):
        out = {"m%d" % m: power(n, m, x) for m, x in X.items()}
        if seed == 3:
            out["m6"] = power(n, 6, X[6] + 0.01)
        return out
    write_points(shifted, moments)
    rc, rows, _ = run(shifted, "--m", "6")
    ln = np.log([n for n in SIZES if n >= 251])

    def gap(seeds):
        y2 = np.log([np.mean([power(n, 2, X[2]) for s in seeds]) for n in SIZES if n >= 251])
        y6 = np.log([np.mean([power(n, 6, X[6] + (0.01 if s == 3 else 0)) for s in seeds]) for n in SIZES if n >= 251])
        return -np.polyfit(ln, y2, 1)[0] / 2 + np.polyfit(ln, y6, 1)[0] / 6
    jack = [gap([s for s in (1, 2, 3) if s != out]) for out in (1, 2, 3)]
    want_err = math.sqrt(2 / 3 * sum((j - np.mean(jack)) ** 2 for j in jack))
    check(rc == 0 and len(rows) == 2, "shifted: rc %d, %d rows" % (rc, len(rows)))
    for r in rows:
        check(abs(float(r["gap"]) - gap([1, 2, 3])) < 2e-5, "shifted gap %s against %.5f" % (r["gap"], gap([1, 2, 3])))
        check(0.02 - 0.01 < float(r["gap"]) < 0.02, "one seed of three shifts the gap part way: %s" % r["gap"])
        check(want_err > 1e-3 and abs(float(r["gap_err"]) - want_err) < 2e-5, "jackknife %s against %.5f" % (r["gap_err"], want_err))

    # eps 0.5 without seed 2 at N = 1000: left out, eps 0.1 still there
    partial = os.path.join(tmp, "partial")
    write_points(partial, lambda eps, n, seed: None if (eps, n, seed) == ("0.5", 1000, 2) else
                 {"m%d" % m: power(n, m, x) for m, x in X.items()})
    rc, rows, err = run(partial)
    check(rc == 0 and {r["eps_n"] for r in rows} == {"0.1"} and "eps 0.5 left out" in err, "partial: %s %s" % (rows, err))

    # no points: refused, named, no traceback; a moment the runs do not have is refused too
    rc, rows, err = run(os.path.join(tmp, "nothing"))
    check(rc != 0 and err.startswith("moment_exponent_gaps.py: no points/*.json") and "Traceback" not in err, "empty: %s" % err)
    rc, rows, err = run(exact, "--m", "13")
    check(rc != 0 and "moments 1-12" in err and "Traceback" not in err, "--m 13: %s" % err)
    rc, rows, err = run(exact, "--n-min", "100000")  # every eps left out: refused, nothing on standard output
    check(rc != 0 and rows == [] and "no eps in" in err and "Traceback" not in err, "--n-min 100000: %s" % err)
    rc, rows, err = run(exact, "--ref", "0")
    check(rc != 0 and "moments 1-12" in err and "Traceback" not in err, "--ref 0: %s" % err)

print("moment_exponent_gaps: %d failed" % failed)
sys.exit(1 if failed else 0)
