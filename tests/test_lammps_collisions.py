"""Single head-on collisions against LAMMPS (docs/lammps.md, "Single collisions against LAMMPS"):
every normal law (spring_dashpot, hertz Tsuji and viscoelastic, each clamped and not) in granule
(`granule collide --speeds`) and in LAMMPS's pair_style granular, mapped as bench/lammps_collisions.py
documents, at the same time step and start.

    test_lammps_collisions.py BUILD_DIR SOURCE_DIR    exit 77 (skipped) without lmp

Asserted, per law and impact speed:
 - the engines agree to TOL = 1e-9 relative in the restitution and exactly in the number of steps
   with a contact force. Both run velocity Verlet with the dashpot at the half-step velocity from
   the same state, so they differ only by the rounding of the force arithmetic (measured <= 6e-16);
   a wrong parameter mapping (e.g. LAMMPS's hertz k_n without the sqrt(R) of its contact radius, or
   tsuji's damping without sqrt(meff)) or a different scheme would show as >= 1e-5, and one contact
   step more or less as ~ 2 zeta w0 dt ~ 1e-4.
 - each engine's restitution is within DISCRETISATION = 1e-3 of the law's exact eps_n(v): at 1000
   steps per contact the error is first order in dt, measured 6.4e-4 for the unclamped linear
   dashpot (the largest), 1.5e-5 to 7.3e-5 for hertz.
GRANULE_TEST_QUICK=1: one speed instead of two.
"""
import os
import shutil
import subprocess
import sys

build, src = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "bench"))
import lammps_collisions as lc  # noqa: E402

lmp = None
for b in ("lmp", "lmp_serial", "lmp_mpi"):
    path = shutil.which(b)
    if path and "GRANULAR" in subprocess.run([path, "-h"], capture_output=True, text=True).stdout:
        lmp = path
        break
if not lmp:
    print("skipped: no lmp with the GRANULAR package (Debian package lammps; scripts/setup.sh installs it)")
    sys.exit(77)

DISCRETISATION = 1e-3
STEPS_PER_CONTACT = 1000.0
speeds = [1.0] if os.environ.get("GRANULE_TEST_QUICK") else [0.1, 1.0]
rows = lc.run(build, lmp, speeds, STEPS_PER_CONTACT)
print(lc.markdown(rows, []))
failures = []
for r in rows:
    what = f"{r['law']} at {r['speed']:g} m/s"
    if not r["rel_diff"] <= lc.TOL:
        failures.append(f"{what}: eps granule {r['eps_granule']!r}, LAMMPS {r['eps_lammps']!r}: "
                        f"relative difference {r['rel_diff']:.2e} > {lc.TOL:g}")
    if r["steps_granule"] != r["steps_lammps"]:
        failures.append(f"{what}: {r['steps_granule']} contact steps in granule, {r['steps_lammps']} in LAMMPS")
    for engine in ("granule", "lammps"):
        err = abs(r["eps_" + engine] - r["eps_law"]) / r["eps_law"]
        if not err < DISCRETISATION:
            failures.append(f"{what}: {engine} eps {r['eps_' + engine]!r} vs the law's {r['eps_law']!r}: "
                            f"relative error {err:.2e} >= {DISCRETISATION:g}")
expected = len(lc.LAWS) * len(speeds)
if len(rows) != expected:
    failures.append(f"{len(rows)} collisions compared, expected {expected}")
for f in failures:
    print("FAIL", f)
print(f"{len(rows)} collisions compared; {len(failures)} failures")
sys.exit(1 if failures else 0)
