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
 - oblique collisions with rotation (bench/lammps_collisions.py, run_oblique: spring_dashpot with
   tangential_dashpot, unclamped and clamped, and with sliding_friction; hertz Tsuji with
   tangential_dashpot through hybrid/overlay), at 30 degrees without spin and at 60 degrees with
   w1 != w2 before: at v = 1e-6 m/s (xi_max/d <= 1.4e-8, where the engines' different lever arm
   for the contact point's velocity is negligible) the velocities after (normal and tangential)
   and both spins agree to 1e-6 over v, v/r and over their own values (measured <= 4e-8); at
   v = 1e-2 m/s (full mode) the difference stays below 0.2 xi_max/d (the lever-arm term).
 - the history spring with rotation (bench/lammps_collisions.py, run_history: tangential_spring
   against LAMMPS's `tangential linear_history`, sticking, stick-slip and sliding, the same
   geometries): the difference stays below granule's half first step (docs/models.md; at most
   1 / steps per contact) plus 1.0 xi_max/d (the lever arms); with LAMMPS's whole first step they
   agreed to <= 5.6e-10 over v, v/r at 1e-6 m/s; the spins change by equal amounts; sticking,
   stick-slip and sliding end with different g_t' (the Coulomb limit really acts).
 - Mindlin (bench/lammps_collisions.py, run_mindlin): tangential_spring with mindlin = true on hertz
   against LAMMPS's tangential mindlin, no rotation, 0.1 m/s, 1e3 and 2e3 steps per contact: the
   difference is granule's half first step, first order (halving with dt within 30 %, below
   1 / steps per contact; measured 0.03-0.77 / steps per contact).
 - rolling resistance (bench/lammps_collisions.py, run_rolling: rolling_friction against LAMMPS's
   `rolling sds k_roll 0 mu_r` with a stiff k_roll, on pure rolling resistance (sliding_friction
   mu = 0) with both normal laws, clamped or not, and on tangential_dashpot, sliding_friction,
   tangential_spring and hertz + tangential_dashpot): w1' - w2' (set by the rolling law alone)
   agrees to ROLLING_TOL = 1e-9 over v/r (measured <= 2e-12); without a tangential force every
   compared number does (measured <= 7e-15); with one, the tangential law's bounds above hold; the
   rolling changed w1 - w2 and did not stop it.
 - rolling arrested within the contact (run_rolling_arrest, mu_r = 2 and 1, no tangential force),
   where the laws part: translation and w1' + w2' equal in both engines (1e-9), granule's
   w1' - w2' = 0 (1e-12 of its value before), LAMMPS's spring leaves a residue above 1e-9 of it
   and below its energy bound mu_r max|F_n| sqrt(2 / (k_roll I)) (measured 8e-5 to 2e-3 v/r).
GRANULE_TEST_QUICK=1: one head-on speed instead of two, the oblique cases at v = 1e-6 only, the
Mindlin cases at 60 degrees only, the rolling cases at 1e-6 m/s only (each in one geometry,
alternating, in both modes).
"""
import os
import sys

build, src = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "bench"))
import lammps_collisions as lc  # noqa: E402

lmp = lc.find_lmp()
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

oblique_speeds = [1e-6] if os.environ.get("GRANULE_TEST_QUICK") else [1e-6, 1e-2]


oblique = lc.run_oblique(build, lmp, oblique_speeds, STEPS_PER_CONTACT)
print(lc.markdown_oblique(oblique))
failures += ["oblique " + m for m in lc.oblique_failures(oblique)]
slow = [r for r in oblique if r["speed"] == 1e-6]
if any(r["xi_over_d"] > lc.OBLIQUE_SMALL_OVERLAP for r in slow):
    failures.append("oblique at 1e-6 m/s: xi_max/d above the small-overlap bound, the 1e-6 check did not run")
expected = len(lc.OBLIQUE) * len(lc.OBLIQUE_GEOMETRIES) * len(oblique_speeds)
if len(oblique) != expected:
    failures.append(f"{len(oblique)} oblique collisions compared, expected {expected}")
for r in oblique:
    # the spins change by equal amounts (equal torques a F_t on both discs) in both engines
    for e in ("granule", "lammps"):
        dw1 = r[e]["w1"] - r["omega1_before"] * lc.RADIUS / r["speed"]
        dw2 = r[e]["w2"] - r["omega2_before"] * lc.RADIUS / r["speed"]
        if not abs(dw1 - dw2) <= 1e-9 * max(abs(dw1), 1e-300) + 1e-12:
            failures.append(f"oblique {r['case']} at {r['speed']:g} m/s: {e}'s spins changed by {dw1!r} and {dw2!r}")
    if not abs(r["granule"]["w1"] - r["omega1_before"] * lc.RADIUS / r["speed"]) > 1e-3:
        failures.append(f"oblique {r['case']} at {r['speed']:g} m/s: no spin-up, the tangential law did not act")
# Mindlin (tangential_spring mindlin = true on hertz, no rotation) against LAMMPS's plain tangential
# mindlin: granule's half first step (docs/models.md) is the only difference, first order
mindlin = lc.run_mindlin(build, lmp, 0.1, [1e3, 2e3], angles=[60.0] if os.environ.get("GRANULE_TEST_QUICK") else lc.MINDLIN_ANGLES)
print(lc.markdown_mindlin(mindlin))
failures += ["mindlin " + m for m in lc.mindlin_failures(mindlin)]
if not mindlin or not all(r["diff"] > 0.0 for r in mindlin):
    failures.append("mindlin: no collisions compared, or no first-step difference (is the half step gone?)")
# the history spring with rotation against linear_history: granule's half first step and the lever arms
history = lc.run_history(build, lmp, oblique_speeds, STEPS_PER_CONTACT)
print(lc.markdown_oblique(history))
failures += ["history " + m for m in lc.history_failures(history)]
if len(history) != len(lc.HISTORY) * len(lc.OBLIQUE_GEOMETRIES) * len(oblique_speeds):
    failures.append(f"{len(history)} history-spring collisions compared")
for angle in {r["angle"] for r in history}:
    g_t = sorted(r["granule"]["g_t"] for r in history if r["angle"] == angle and r["speed"] == 1e-6)
    if not all(b - a > 1e-2 for a, b in zip(g_t, g_t[1:])):
        failures.append(f"history at {angle:g} deg: sticking, stick-slip and sliding end alike (g_t'/v {g_t})")
# rolling_friction against rolling sds: each case in one geometry (alternating, so both are
# covered; the bench runs every case in both), at 1e-6 m/s (quick) or 1e-6 and 1e-2 m/s
rolling, arrest = [], []
for table, run in ((lc.ROLLING, lc.run_rolling), (lc.ROLLING_ARREST, lc.run_rolling_arrest)):
    for i, name in enumerate(table):
        out = run(build, lmp, oblique_speeds, STEPS_PER_CONTACT, cases=[name], geometries=[lc.ROLLING_GEOMETRIES[i % 2]])
        (rolling if table is lc.ROLLING else arrest).extend(out)
print(lc.markdown_rolling(rolling))
print(lc.markdown_rolling(arrest))
failures += ["rolling " + m for m in lc.rolling_failures(rolling) + lc.arrest_failures(arrest)]
if len(rolling) != len(lc.ROLLING) * len(oblique_speeds) or len(arrest) != len(lc.ROLLING_ARREST) * len(oblique_speeds):
    failures.append(f"{len(rolling)} rolling and {len(arrest)} arrested-rolling collisions compared")
for f in failures:
    print("FAIL", f)
print(f"{len(rows)} head-on, {len(oblique)} oblique, {len(history)} history-spring, {len(mindlin)} Mindlin, "
      f"{len(rolling)} rolling and {len(arrest)} arrested-rolling collisions compared; "
      f"{len(failures)} failures")
sys.exit(1 if failures else 0)
