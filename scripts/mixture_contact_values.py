#!/usr/bin/env python3
"""The partial pair correlations at contact of an elastic gas of two sizes against the theory of
hard-disc mixtures (docs/validation.md, "Contact values of a binary mixture").

Runs docs/scenes/bidisperse-sizes-gas.ini (400 discs, radii 1 and 2 mm in equal numbers, one
material, phi = 0.2, eps_n = 1, undriven: an equilibrium fluid) for each seed and compares

  - each contact value g_ab(sigma_ab+) (pair observable, summary pair.species) with Jenkins and
    Mancini's (J. Appl. Mech. 54, 27 (1987)), in 2D
        g_ab = 1 / (1 - phi) + (9 / 16) phi / (1 - phi)^2 (sigma_a sigma_b / sigma_ab) M1 / M2,
    sigma_a = 2 r_a, sigma_ab = (sigma_a + sigma_b) / 2, M_k = sum_a x_a sigma_a^k;
  - the virial of hard discs written with the measured contact values (exact for hard discs),
        Z - 1 = (pi / 2) n sum_ab x_a x_b sigma_ab^2 g_ab(sigma_ab+),
    with the pressure observable's collisional Z - 1 of the same run (the forces' virial).

usage: mixture_contact_values.py GRANULE OUT_DIR [--seeds 1,2,3] [--duration SECONDS]
"""
import json
import math
import os
import subprocess
import sys

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "scenes",
                     "bidisperse-sizes-gas.ini")
PHI, SIGMA, X = 0.2, (2e-3, 4e-3), (0.5, 0.5)  # the scene's packing fraction, diameters, fractions
KINDS = ((0, 0), (0, 1), (1, 1))


def jenkins_mancini():
    M1 = sum(x * s for x, s in zip(X, SIGMA))
    M2 = sum(x * s * s for x, s in zip(X, SIGMA))
    out = []
    for a, b in KINDS:
        sab = (SIGMA[a] + SIGMA[b]) / 2
        out.append(1 / (1 - PHI) + 9 / 16 * PHI / (1 - PHI)**2 * SIGMA[a] * SIGMA[b] / sab * M1 / M2)
    return out


def virial(g, n):
    """(pi / 2) n sum_ab x_a x_b sigma_ab^2 g_ab over ordered pairs (a != b counted twice)."""
    tot = 0.0
    for (a, b), v in zip(KINDS, g):
        tot += X[a] * X[b] * (1 if a == b else 2) * ((SIGMA[a] + SIGMA[b]) / 2)**2 * v
    return math.pi / 2 * n * tot


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    granule, out = args[0], args[1]
    seeds = args[args.index("--seeds") + 1].split(",") if "--seeds" in args else ["1", "2", "3"]
    duration = args[args.index("--duration") + 1] if "--duration" in args else "10"
    want = jenkins_mancini()
    rows = []
    for seed in seeds:
        d = os.path.join(out, "seed" + seed)
        subprocess.run([granule, "run", SCENE, "--out", d, "--force", "--set", "run.seed=" + seed,
                        "--set", "run.duration=" + duration, "--set", "output.plots=false",
                        "--set", "output.snapshot_every=0"], check=True,
                       env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
        s = json.load(open(os.path.join(d, "summary.json")))
        ps, p = s["analysis"]["pair"]["species"], s["analysis"]["pressure"]
        n = s["scene"]["system"]["N"] / s["scene"]["system"]["L"]**2
        g, ge = ps["contact_value"], ps["contact_value_error"]
        zg = virial(g, n)
        zge = math.pi / 2 * n * math.sqrt(sum(
            (X[a] * X[b] * (1 if a == b else 2) * ((SIGMA[a] + SIGMA[b]) / 2)**2 * e)**2
            for (a, b), e in zip(KINDS, ge)))
        zp = (p["collisional_xx"] + p["collisional_yy"]) / 2 / p["nT"]
        zpe = math.hypot(p["collisional_xx_error"], p["collisional_yy_error"]) / 2 / p["nT"]
        rows.append((g, ge, zg, zge, zp, zpe))
        print(f"seed {seed}: " + ", ".join(f"g_{a + 1}{b + 1} = {v:.4f} +- {e:.4f}"
                                            for (a, b), v, e in zip(KINDS, g, ge))
              + f"; Z - 1 from them {zg:.4f} +- {zge:.4f}, pressure {zp:.4f} +- {zpe:.4f}")
    k = len(rows)
    print(f"\nover {k} seeds (mean +- standard error of the seeds' values):")
    for q, (a, b) in enumerate(KINDS):
        v = [r[0][q] for r in rows]
        m = sum(v) / k
        e = math.sqrt(sum((x - m)**2 for x in v) / (k - 1) / k) if k > 1 else rows[0][1][q]
        print(f"  g_{a + 1}{b + 1}(sigma+) = {m:.4f} +- {e:.4f}; Jenkins-Mancini {want[q]:.4f} "
              f"(z = {(m - want[q]) / e:+.2f}, {100 * (m / want[q] - 1):+.1f} %)")
    for q, name in ((2, "from the contact values"), (4, "pressure observable's virial")):
        v = [r[q] for r in rows]
        m = sum(v) / k
        e = math.sqrt(sum((x - m)**2 for x in v) / (k - 1) / k) if k > 1 else rows[0][q + 1]
        print(f"  Z - 1 {name}: {m:.4f} +- {e:.4f}")
    n_th = PHI / (math.pi * sum(x * (s / 2)**2 for x, s in zip(X, SIGMA)))
    print(f"  Z - 1 of the Jenkins-Mancini contact values: {virial(want, n_th):.4f}")


if __name__ == "__main__":
    main()
