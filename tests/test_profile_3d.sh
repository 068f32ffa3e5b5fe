#!/usr/bin/env bash
# The profile observable on a 3D isothermal atmosphere (docs/systems-walls-gravity.md, "Spheres"):
# elastic spheres (eps_n = 1) between a floor and a ceiling at z = 0 and L under gz = -9.81, held
# at T_bath by the Langevin bath (3D, docs/systems-driving.md), N = 100, 6 s sampled after 0.2 s.
# At equilibrium (the Boltzmann distribution of the soft spheres) every slab has
# T_x = T_y = T_z = T_bath / 3 (equipartition per degree of freedom), and the slabs obey the
# hydrostatic balance d(n T Z)/dz = -g n with the hard-sphere equation of state
# Z = 1 + 4 phi chi(phi), chi = (1 - phi/2) / (1 - phi)^3 (Carnahan-Starling). Two gases: radius
# 1.5 mm (phi up to 0.11 at the floor: the barometric law is off by the excluded volume) and
# 0.1 mm (an ideal gas, phi < 1e-4, 3 s sampled: the density is the barometric
# exp(-M g z / (k T)) = exp(-g z / T_c)).
# The dense gas also with the event integrator (hard spheres, for which Carnahan-Starling is the
# equation of state) and the hybrid: their bath acts at each window's end.
# Checks: every slab holding 5 % of the densest one has each T_c within 4 errors of T_bath / 3; the
# mean over slabs (two away from each wall) of -d(n T Z)/dz / (g n) is 1 within 3 errors and its
# error is below 0.05; the ideal gas's fitted ln n slope (weighted by the slabs' errors) is
# -g / T_c within 3 errors, the error below 5 %.
# usage: test_profile_3d.sh GRANULE
set -uo pipefail
granule=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat >"$tmp/atm.ini" <<'INI'
[system]
dim = 3
N = 100
L = 0.03
radius = 1.5e-3
mass = 3.53e-5
[placement]
kind = random
v0 = 0.3
[model]
normal = spring_dashpot
k_s = 5e3
eps_n = 1
[driving]
kind = langevin
T_bath = 0.22
tau = 0.02
[boundary]
z = walls
[gravity]
gz = -9.81
[integrator]
kind = verlet
steps_per_contact = 20
[run]
warmup = 0.2
duration = 6
sample_every = 0.002
[analysis]
observables = profile
profile_bins = 12
[output]
plots = false
INI
"$granule" run "$tmp/atm.ini" --out "$tmp/dense" --quiet >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: run radius 1.5 mm" >&2; exit 1; }
# the ideal gas: tiny spheres, a stiffer spring so that a fast one stays within r / 2 of a wall
"$granule" run "$tmp/atm.ini" --out "$tmp/ideal" --quiet --set system.radius=1e-4 --set model.k_s=1e5 \
    --set run.duration=3 >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: run radius 0.1 mm" >&2; exit 1; }
# the same atmosphere with the event integrator (hard spheres) and the hybrid, whose bath acts at
# each window's end (docs/event-driven.md, docs/hybrid.md, "Langevin bath")
"$granule" run "$tmp/atm.ini" --out "$tmp/event" --quiet --set integrator.kind=event \
    --set model.normal=hard_sphere --set model.eps_t=1 >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: run event" >&2; exit 1; }
"$granule" run "$tmp/atm.ini" --out "$tmp/hybrid" --quiet --set integrator.kind=hybrid >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: run hybrid" >&2; exit 1; }
/usr/bin/python3 - "$tmp/dense" "$tmp/ideal" "$tmp/event" "$tmp/hybrid" <<'PY'
import sys
import numpy as np
T_bath, g = 0.22, 9.81
Tc = T_bath / 3
def check(run, dilute):
    a = np.genfromtxt(run + "/profile.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    z, n, phi = a["z"], a["n"], a["phi"]
    dz, name = z[1] - z[0], run.rsplit("/", 1)[-1]
    ok = True
    w = n >= 0.05 * n.max()
    for c in ("T_x", "T_y", "T_z"):
        dev = np.abs(a[c][w] - Tc) / a[c + "_err"][w]
        print(f"{name}: {c}: {w.sum()} slabs, largest |T_c - T_bath/3| / error = {dev.max():.2f} (T_bath/3 = {Tc:.5f} m^2/s^2)")
        ok &= bool(dev.max() < 4)
    chi = (1 - phi / 2) / (1 - phi) ** 3
    P = n * Tc * (1 + 4 * phi * chi)
    k = np.arange(2, len(z) - 2)
    R = -(P[k + 1] - P[k - 1]) / (2 * dz) / (g * n[k])
    m, e = R.mean(), R.std(ddof=1) / np.sqrt(len(R))
    print(f"{name}: hydrostatic balance with Z(phi): -d(nTZ)/dz / (g n) = {m:.3f} +- {e:.3f} over {len(R)} slabs "
          f"(must be 1 within 3 errors, error < 0.05); densest phi = {phi.max():.3f}")
    ok &= abs(m - 1) < 3 * e and e < 0.05
    # ln n against z, weighted by each slab's error (ln n's is n_err / n)
    s = slice(2, len(z) - 2)
    (slope, _), cov = np.polyfit(z[s], np.log(n[s]), 1, w=n[s] / a["n_err"][s], cov="unscaled")
    ratio, err = -slope * Tc / g, np.sqrt(cov[0, 0]) * Tc / g
    print(f"{name}: barometric fit: ln n slope {slope:.1f} 1/m against -g/T_c = {-g / Tc:.1f} 1/m (ratio {ratio:.3f} +- {err:.3f}{', must be 1 within 3 errors, error < 0.05' if dilute else ', excluded volume'})")
    if dilute:
        ok &= abs(ratio - 1) < 3 * err and err < 0.05
    return ok
ok = check(sys.argv[1], False)
ok = check(sys.argv[2], True) and ok
ok = check(sys.argv[3], False) and ok
ok = check(sys.argv[4], False) and ok
sys.exit(0 if ok else 1)
PY
