#!/usr/bin/env python3
"""The pressure observable on a radius distribution against the Enskog equation of state of a
polydisperse hard-disc fluid (docs/validation.md, "Pressure of a polydisperse gas").

Runs docs/scenes/polydisperse-gas.ini, an elastic gas (eps_n = 1, no driving: an equilibrium fluid,
so every size has the same T) of N = 300 discs with lognormal radii in [1, 4] mm (median 2 mm,
sigma 0.4) at phi = 0.2, and compares
its Z - 1 = P_coll / (n T) with

    Z - 1 = (pi / 2) n sum_ij x_i x_j sigma_ij^2 chi_ij,   sigma_ij = r_i + r_j,
    chi_ij = 1 / (1 - phi) + (9 / 16) phi / (1 - phi)^2 (sigma_i sigma_j / sigma_ij) M1 / M2,

over the run's own grains (each its own species, x_i = 1 / N; sigma_i = 2 r_i, M_k = <sigma^k>):
the Enskog virial of hard discs with Jenkins and Mancini's contact values (J. Appl. Mech. 54, 27
(1987); checked against event-driven hard-disc mixtures by Luding and Santos, J. Chem. Phys. 121,
8458 (2004)). For one size chi_ij is Henderson's (1 - 7 phi / 16) / (1 - phi)^2; the script
prints that value at the same phi too, which the measurement must miss.

usage: polydisperse_eos.py GRANULE OUT_DIR [--seed S] [--duration SECONDS]
"""
import json
import math
import os
import subprocess
import sys

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "scenes",
                     "polydisperse-gas.ini")



def radii(snapshot):
    """the grains' radii from an extended-XYZ frame (its `radius` property)."""
    lines = open(snapshot).read().split("\n")
    n = int(lines[0])
    props = lines[1].split("Properties=")[1].split()[0].split(":")
    col = 0
    for k in range(0, len(props), 3):
        if props[k] == "radius":
            break
        col += int(props[k + 2])
    return [float(l.split()[col]) for l in lines[2:2 + n]], float(lines[1].split('"')[1].split()[0])


def enskog(r, L):
    """Z - 1 of the Enskog virial with Jenkins-Mancini contact values, and phi."""
    n = len(r) / L**2
    sig = [2.0 * x for x in r]
    phi = n * math.pi * sum(x * x for x in r) / len(r)
    M1 = sum(sig) / len(sig)
    M2 = sum(s * s for s in sig) / len(sig)
    tot = 0.0
    for si in sig:
        for sj in sig:
            sij = 0.5 * (si + sj)
            chi = 1 / (1 - phi) + 9 / 16 * phi / (1 - phi)**2 * si * sj * M1 / (sij * M2)
            tot += sij * sij * chi
    return math.pi / 2 * n * tot / len(sig)**2, phi


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    granule, out = args[0], args[1]
    seed = args[args.index("--seed") + 1] if "--seed" in args else "2"
    duration = args[args.index("--duration") + 1] if "--duration" in args else "10"
    subprocess.run([granule, "run", SCENE, "--out", out, "--force", "--set", "run.seed=" + seed,
                    "--set", "run.duration=" + duration, "--set", "output.plots=false"],
                   check=True, env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    p = json.load(open(out + "/summary.json"))["analysis"]["pressure"]
    r, L = radii(out + "/snapshots/snap_000000.xyz")
    want, phi = enskog(r, L)
    got = (p["collisional_xx"] + p["collisional_yy"]) / 2 / p["nT"]
    err = math.hypot(p["collisional_xx_error"], p["collisional_yy_error"]) / 2 / p["nT"]
    mono = 2 * phi * (1 - 7 * phi / 16) / (1 - phi)**2
    print(f"phi = {phi:.4f}, {p['contacts_per_frame']:.3g} contacts per frame")
    print(f"Z - 1 measured {got:.4f} +- {err:.4f}")
    print(f"  Enskog, Jenkins-Mancini chi_ij of these radii: {want:.4f} (z = {(got - want) / err:+.2f})")
    print(f"  one size at the same phi (Henderson): {mono:.4f} (z = {(got - mono) / err:+.2f})")


if __name__ == "__main__":
    main()
