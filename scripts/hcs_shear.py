#!/usr/bin/env python3
"""The shear instability of the homogeneous cooling state, measured on granule's free-cooling runs
of smooth hard discs (docs/validation.md, "When Haff's law ends: the shear instability").

    hcs_shear.py RUN_DIR [RUN_DIR ...] [--check]

For each 2D run without driving: the predicted critical box side L_perp (linear hydrodynamics of
the HCS with the first-Sonine Navier-Stokes viscosity of inelastic hard discs, Garzo & Dufty 1999,
and Enskog's chi), the box's L / L_perp, the local slope of T_dof^(-1/2)(t) over windows against
Haff's Enskog slope, and from the snapshots (extended XYZ) the energy of the box's longest shear
modes over its equilibrium value, R = |sum_j v_perp,j exp(i k x_j)|^2 / (N T_dof) at k = 2 pi / L
(R = 1 for a homogeneous gas at equipartition), with its growth exponent d ln R / d ln(1/T) against
the linear theory's 1 - (L_perp / L)^2. --check: exit 1 unless every box with L < 0.8 L_perp
keeps the late Haff slope (>= 0.93) and R < 30, and every box with L > 1.5 L_perp has a late slope
<= 0.85 and R > 100 at its end (tests/test_hcs_stability.sh).
"""
import glob
import json
import math
import sys

import numpy as np


def theory(phi, eps, sigma, d=2):
    """L_perp / sigma, Haff's slope d(T_dof^-1/2)/dt and the HCS a2 (docs/validation.md)."""
    a2 = 16 * (1 - eps) * (1 - 2 * eps**2) / (9 + 24 * d - eps * (41 - 8 * d) + 30 * (1 - eps) * eps**2)
    zeta = (d + 2) / (4 * d) * (1 - eps**2) * (1 + 3 * a2 / 16)
    nu_eta = 3 / (4 * d) * (1 - eps + 2 * d / 3) * (1 + 7 * a2 / 16)
    eta = 1 / (nu_eta - zeta / 2)
    chi = (1 - 7 * phi / 16) / (1 - phi) ** 2  # Henderson
    n_sigma2 = 4 * phi / math.pi  # n sigma^2 in 2D
    k_perp_sigma = n_sigma2 * chi * math.sqrt(2 * math.pi * zeta / eta)
    haff = 2 / math.sqrt(math.pi) * phi * chi * (1 - eps**2) * (1 + 3 * a2 / 16) / sigma
    return 2 * math.pi / k_perp_sigma, haff, a2


def shear_modes(run):
    rows = []
    for f in sorted(glob.glob(run + "/snapshots/*.xyz")):
        with open(f) as fh:
            n = int(fh.readline())
            hdr = fh.readline()
            a = np.loadtxt(fh, usecols=(1, 2, 4, 5), max_rows=n)
        L = float(hdr.split('Lattice="')[1].split()[0])
        t = float(hdr.split("Time=")[1].split()[0])
        x, y, vx, vy = a.T
        T = 0.5 * np.mean(vx**2 + vy**2)
        k = 2 * math.pi / L
        m = abs(np.sum(vy * np.exp(1j * k * x))) ** 2 + abs(np.sum(vx * np.exp(1j * k * y))) ** 2
        rows.append((t, T, 0.5 * m / (n * T)))
    return np.array(rows)


def main(argv):
    check = "--check" in argv
    runs = [a for a in argv if a != "--check"]
    if not runs:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    ok = True
    for run in runs:
        s = json.load(open(run + "/summary.json"))["scene"]
        sy, mo = s["system"], s["model"]
        if sy["dim"] != 2:
            print(f"hcs_shear.py: {run}: dim = {sy['dim']}; this analysis is for 2D runs", file=sys.stderr)
            return 2
        sigma = 2 * sy["radius"]
        Lp, haff, a2 = theory(sy["packing_fraction"], mo["eps_n"], sigma)
        ratio = sy["L"] / sigma / Lp
        a = np.genfromtxt(run + "/temperature.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
        t, T = a["t"], a["T"] / sy["dim"]
        u = T**-0.5
        print(f"{run}: N = {sy['N']}, phi = {sy['packing_fraction']:.3g}, eps_n = {mo['eps_n']}: "
              f"L = {sy['L'] / sigma:.0f} sigma, L_perp = {Lp:.0f} sigma, L / L_perp = {ratio:.2f}")
        t_end = t[-1]
        edges = [e for e in (0.5, 2, 5, 10, 20, 40, 80, 160, 320) if e < t_end] + [t_end]
        slopes = []
        for lo, hi in zip(edges[:-1], edges[1:]):
            w = (t >= lo) & (t <= hi)
            if w.sum() < 10:
                continue
            slopes.append(np.polyfit(t[w], u[w], 1)[0] / haff)
            print(f"  t {lo:6.1f} - {hi:6.1f} s: T_dof {T[w][0]:.3g} -> {T[w][-1]:.3g} m^2/s^2, "
                  f"slope / Haff {slopes[-1]:.3f}")
        modes = shear_modes(run)
        if len(modes):
            print("  shear-mode energy R (t: R): " + ", ".join(f"{r[0]:.0f}: {r[2]:.3g}" for r in modes))
            late = modes[modes[:, 0] >= 0.1 * t_end]
            if len(late) >= 3:
                g = np.polyfit(np.log(1 / late[:, 1]), np.log(late[:, 2]), 1)[0]
                print(f"  d ln R / d ln(1/T) over t >= {0.1 * t_end:.0f} s: {g:.2f} "
                      f"(linear theory {1 - 1 / ratio**2:.2f})")
        if check:
            r_end = modes[-1, 2] if len(modes) else float("nan")
            if ratio < 0.8:
                good = slopes[-1] >= 0.93 and r_end < 30
            elif ratio > 1.5:
                good = slopes[-1] <= 0.85 and r_end > 100
            else:
                good = True
            print(f"  check: late slope / Haff {slopes[-1]:.3f}, R at the end {r_end:.3g}: "
                  f"{'as predicted' if good else 'NOT as predicted'}")
            ok = ok and good
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
