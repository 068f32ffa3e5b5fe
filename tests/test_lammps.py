"""The LAMMPS bridge (docs/lammps.md): export the 2D RFM scene at N = 300, run it on 2 MPI ranks with
Debian's LAMMPS, read its dump with `granule analyse --lammps-dump`, and require agreement with
granule's own run of the same scene (same initial state, independent noise) within errors:
T (2.19) and g(R) (4.10) from granule's observables with their block-averaging errors, P(v) (App.
A.1) from granule's pv.csv in coarse bins with errors from block averaging over the frames. Then
the Langevin bath: docs/scenes/langevin-gas.ini exported as fix langevin, both runs at T_bath. Then
the 3D scene (docs/scenes/rfm-3d.ini, N = 300 spheres) exported as a 3D deck: T and the tail of P(v).
Then a binary mixture's deck (atom types, per-type masses, per-pair damping; 2D, 3D and 2D with the
tangential dashpot) and a radius distribution's (one atom type per grain, a pair_coeff per pair of
grains) without noise: both codes' trajectories agree to rounding.

    test_lammps.py GRANULE_EXE SOURCE_DIR     exit 77 (skipped) without lmp
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

import granule

exe, src = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(src, "bench"))
from lmp_env import fast_mpi_start, run_lmp  # noqa: E402

fast_mpi_start()  # an lmp start in 0.04 s instead of 0.5 (bench/lmp_env.py)
lmp = next((shutil.which(b) for b in ("lmp", "lmp_serial", "lmp_mpi") if shutil.which(b)), None)
if not lmp:
    print("skipped: no lmp (Debian package lammps; scripts/setup.sh installs it)")
    sys.exit(77)
mpirun = shutil.which("mpirun")
ranks = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", "2"] if mpirun else []
Z_MAX = 3.0  # every comparison: |difference| < 3 combined standard errors
sets = {"system.N": 300, "system.L": 0.08, "run.warmup": 0.05, "run.duration": 0.2, "run.sample_every": 1e-3,
        "output.snapshot_every": 1e-3, "output.plots": "false", "analysis.observables": "moments,pv,pair"}
set_args = sum((["--set", f"{k}={v}"] for k, v in sets.items()), [])
scene_path = os.path.join(src, "docs", "scenes", "rfm-2d.ini")
failures = []


def compare(what, a, ea, b, eb):
    z = abs(a - b) / np.hypot(ea, eb)
    ok = bool(z < Z_MAX)
    print(f"{'ok  ' if ok else 'FAIL'} {what}: granule {a:.5g} +- {ea:.2g}, LAMMPS {b:.5g} +- {eb:.2g}, z = {z:.2f}")
    if not ok:
        failures.append(what)


def block_mean(per_frame, blocks=10):
    """Mean over frames and its block-averaging standard error (rows = frames)."""
    a = np.asarray(per_frame)
    m = len(a) // blocks
    means = a[: m * blocks].reshape(blocks, m, *a.shape[1:]).mean(axis=1)
    return a.mean(axis=0), means.std(axis=0, ddof=1) / np.sqrt(blocks)


with tempfile.TemporaryDirectory() as tmp:
    lmpdir, rundir = os.path.join(tmp, "lammps"), os.path.join(tmp, "granule")
    subprocess.run([exe, "export", "lammps", scene_path, "--out", lmpdir] + set_args, check=True)
    r = run_lmp(ranks + [lmp, "-in", "in.granule", "-log", "log.lammps", "-screen", "none"], cwd=lmpdir)
    if r.returncode != 0:
        print(r.stdout[-1000:], r.stderr[-2000:], open(os.path.join(lmpdir, "log.lammps")).read()[-2000:] if os.path.exists(os.path.join(lmpdir, "log.lammps")) else "(no log.lammps)")
        sys.exit("LAMMPS failed on the exported deck")
    dump = os.path.join(lmpdir, "dump.granule.lammpstrj")
    subprocess.run([exe, "analyse", "--lammps-dump", dump], check=True)
    subprocess.run([exe, "run", scene_path, "--out", rundir] + set_args, check=True)
    g = json.load(open(os.path.join(rundir, "summary.json")))["analysis"]
    la = json.load(open(os.path.join(lmpdir, "analysis", "summary.json")))["analysis"]
    print(f"granule analyse read {la['pv']['frames']} LAMMPS frames; granule sampled {g['pv']['frames']}")
    if la["pv"]["frames"] != g["pv"]["frames"]:
        failures.append("frame count")

    # T (2.19) = <|v - <v>|^2>, the m = 2 speed moment, block-averaging errors
    compare("T (m^2/s^2)", g["moments"]["speed"]["m2"], g["moments"]["speed_stderr"]["m2"],
            la["moments"]["speed"]["m2"], la["moments"]["speed_stderr"]["m2"])

    # g(R): the first peak and coarse shells; a shell's error is the mean of its bins' block
    # errors (neighbouring bins are correlated, so errors are not added in quadrature)
    compare("g(R) first peak", g["pair"]["first_peak"]["g"], g["pair"]["first_peak"]["g_error"],
            la["pair"]["first_peak"]["g"], la["pair"]["first_peak"]["g_error"])
    pg = granule.read_csv(os.path.join(rundir, "pair.csv"))
    pl = granule.read_csv(os.path.join(lmpdir, "analysis", "pair.csv"))
    for lo, hi in ((1.0, 1.2), (1.2, 1.8), (1.8, 2.5), (2.5, 4.0), (4.0, 8.0)):
        sel = (pg["R_over_d"] >= lo) & (pg["R_over_d"] < hi)
        compare(f"g(R) mean over {lo} <= R/d < {hi}", pg["g"][sel].mean(), pg["g_error"][sel].mean(),
                pl["g"][sel].mean(), pl["g_error"][sel].mean())

    # P(v) of one component: fractions in coarse |v| bins (units of sqrt(T/2) of granule's run)
    scale = np.sqrt(g["moments"]["speed"]["m2"] / 2)
    edges = np.array([0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.5, np.inf]) * scale

    def coarse_from_pv(folder):
        """Coarse fractions from the fine bins, each split by overlap (the fine grids of the two
        runs differ: they scale with each run's own T_ref)."""
        pv = granule.read_csv(os.path.join(folder, "pv.csv"))
        knots = np.append(pv["v_lo"].to_numpy(), pv["v_hi"].to_numpy()[-1])
        cum = np.append(0.0, np.cumsum(pv["counts"].to_numpy())) / pv["counts"].sum()
        F = lambda v: np.interp(v, knots, cum)
        e = np.minimum(edges, knots[-1])
        return np.array([F(e[k + 1]) - F(e[k]) + F(-e[k]) - F(-e[k + 1]) for k in range(len(e) - 1)])

    def coarse_per_frame(frames):
        rows = []
        for f in frames:
            v = np.abs(np.concatenate([f["vx"] - f["vx"].mean(), f["vy"] - f["vy"].mean()]))
            rows.append(np.histogram(v, bins=edges)[0] / v.size)
        return rows

    t_warm = sets["run.warmup"] * (1 + 1e-12)
    fr_g = [f for f in granule.read_snapshots(rundir) if f["t"] > t_warm]
    fr_l = [f for f in granule.read_lammps_dump(dump, 1e-6) if f["t"] > t_warm]
    (_, err_g), (_, err_l) = block_mean(coarse_per_frame(fr_g)), block_mean(coarse_per_frame(fr_l))
    pg_c, pl_c = coarse_from_pv(rundir), coarse_from_pv(os.path.join(lmpdir, "analysis"))
    for k in range(len(edges) - 1):
        compare(f"P(v) fraction {edges[k] / scale:.1f} <= |v_x|/sqrt(T/2) < {edges[k + 1] / scale:.1f}",
                pg_c[k], err_g[k], pl_c[k], err_l[k])

# The Langevin bath (docs/systems-driving.md): docs/scenes/langevin-gas.ini (elastic discs, T_bath =
# 0.24 m^2/s^2, tau = 15 ms) at N = 300 with softer springs, exported as fix langevin; both runs must
# settle at T_bath (1 - 1/N) (docs/validation.md, "The Langevin bath") and agree with each other.
bath_sets = {"system.N": 300, "system.L": 0.08, "model.k_s": 5e3, "run.warmup": 0.1, "run.duration": 0.2,
             "run.sample_every": 1e-3, "output.snapshot_every": 1e-3, "output.plots": "false",
             "analysis.observables": "moments"}
bath_args = sum((["--set", f"{k}={v}"] for k, v in bath_sets.items()), [])
bath_scene = os.path.join(src, "docs", "scenes", "langevin-gas.ini")
with tempfile.TemporaryDirectory() as tmp:
    lmpdir, rundir = os.path.join(tmp, "lammps"), os.path.join(tmp, "granule")
    subprocess.run([exe, "export", "lammps", bath_scene, "--out", lmpdir] + bath_args, check=True)
    if "fix bath all langevin" not in open(os.path.join(lmpdir, "in.granule")).read():
        failures.append("langevin: no fix langevin in the deck")
    r = run_lmp(ranks + [lmp, "-in", "in.granule", "-log", "log.lammps", "-screen", "none"], cwd=lmpdir)
    if r.returncode != 0:
        print(r.stdout[-1000:], r.stderr[-2000:], open(os.path.join(lmpdir, "log.lammps")).read()[-2000:] if os.path.exists(os.path.join(lmpdir, "log.lammps")) else "(no log.lammps)")
        sys.exit("LAMMPS failed on the exported Langevin deck")
    subprocess.run([exe, "analyse", "--lammps-dump", os.path.join(lmpdir, "dump.granule.lammpstrj")], check=True)
    subprocess.run([exe, "run", bath_scene, "--out", rundir] + bath_args, check=True)
    g = json.load(open(os.path.join(rundir, "summary.json")))["analysis"]["moments"]
    la = json.load(open(os.path.join(lmpdir, "analysis", "summary.json")))["analysis"]["moments"]
    T_el = 0.24 * (1 - 1 / 300)
    compare("Langevin T (m^2/s^2), granule vs LAMMPS", g["speed"]["m2"], g["speed_stderr"]["m2"], la["speed"]["m2"],
            la["speed_stderr"]["m2"])
    compare("Langevin T (m^2/s^2), granule vs T_bath (1 - 1/N)", g["speed"]["m2"], g["speed_stderr"]["m2"], T_el, 0.0)
    compare("Langevin T (m^2/s^2), LAMMPS vs T_bath (1 - 1/N)", la["speed"]["m2"], la["speed_stderr"]["m2"], T_el, 0.0)

# Three dimensions (docs/three-dimensions.md): docs/scenes/rfm-3d.ini at N = 300 spheres exported as a
# 3D deck (dimension 3, noise in x, y and z) and run in LAMMPS from granule's initial state; the
# LAMMPS run's T (2.19, three components) and fraction of fast velocity components agree with
# granule's within the spread of independent runs (five seeds of granule).
sets3 = {"system.N": 300, "run.warmup": 0.05, "run.duration": 0.15, "run.sample_every": 1e-3,
         "output.snapshot_every": 1e-3, "output.plots": "false", "analysis.observables": "moments"}
args3 = sum((["--set", f"{k}={v}"] for k, v in sets3.items()), [])
scene3 = os.path.join(src, "docs", "scenes", "rfm-3d.ini")
with tempfile.TemporaryDirectory() as tmp:
    lmpdir, rundir = os.path.join(tmp, "lammps"), os.path.join(tmp, "granule")
    subprocess.run([exe, "export", "lammps", scene3, "--out", lmpdir] + args3, check=True)
    deck = open(os.path.join(lmpdir, "in.granule")).read()
    if "dimension 3" not in deck or "v_fz" not in deck or "enforce2d" in deck:
        failures.append("3D deck: dimension 3, a z noise component, no enforce2d")
    r = run_lmp(ranks + [lmp, "-in", "in.granule", "-log", "log.lammps", "-screen", "none"], cwd=lmpdir)
    if r.returncode != 0:
        print(r.stdout[-1000:], r.stderr[-2000:], open(os.path.join(lmpdir, "log.lammps")).read()[-2000:] if os.path.exists(os.path.join(lmpdir, "log.lammps")) else "(no log.lammps)")
        sys.exit("LAMMPS failed on the exported 3D deck")
    subprocess.run([exe, "run", scene3, "--out", rundir] + args3, check=True)
    t_warm = sets3["run.warmup"] * (1 + 1e-12)
    fr_g = [f for f in granule.read_snapshots(rundir) if f["t"] > t_warm]
    fr_l = [f for f in granule.read_lammps_dump(os.path.join(lmpdir, "dump.granule.lammpstrj"), 1e-6, dim=3)
            if f["t"] > t_warm]
    print(f"3D: granule {len(fr_g)} frames, LAMMPS {len(fr_l)} frames")
    if len(fr_g) != len(fr_l) or not fr_l or fr_l[0]["dim"] != 3:
        failures.append("3D frame count or dimension")

    def per_frame(frames):
        """T = <|v - <v>|^2> over three components, and the fraction of components beyond 2 sqrt(T/3)."""
        rows = []
        for f in frames:
            c = np.stack([f["vx"] - f["vx"].mean(), f["vy"] - f["vy"].mean(), f["vz"] - f["vz"].mean()])
            T = float((c * c).sum(axis=0).mean())
            rows.append([T, float(np.mean(np.abs(c) > 2 * np.sqrt(T / 3)))])
        return rows

    # The errors: a 0.15 s run of 300 spheres is too short for a converged block error (T's
    # correlation time is a good part of it; summary.json says "not converged"), so the spread of
    # independent runs is the error of one run: granule runs seeds 1-5, LAMMPS (one run, its own
    # noise) is compared with their mean at that spread (sqrt(1 + 1/5) s); each run's mean over its
    # frames is one sample.
    runs = [np.mean(per_frame(fr_g), axis=0)]
    for seed in range(2, 6):
        more = os.path.join(tmp, f"granule-{seed}")
        subprocess.run([exe, "run", scene3, "--out", more, "--set", f"run.seed={seed}"] + args3, check=True,
                       stdout=subprocess.DEVNULL)
        runs.append(np.mean(per_frame([f for f in granule.read_snapshots(more) if f["t"] > t_warm]), axis=0))
    runs = np.array(runs)
    mg, sd = runs.mean(axis=0), runs.std(axis=0, ddof=1)
    ml = np.mean(per_frame(fr_l), axis=0)
    print(f"3D: granule's 5 runs T = {', '.join(f'{t:.4f}' for t in runs[:, 0])}")
    compare("3D T (m^2/s^2)", mg[0], sd[0] / np.sqrt(len(runs)), ml[0], sd[0])
    compare("3D P(|c| > 2 sqrt(T/3))", mg[1], sd[1] / np.sqrt(len(runs)), ml[1], sd[1])

# A mixture (docs/mixtures.md): one atom type per species with its own diameter and mass, one
# pair_coeff per species pair (pair_style granular, hooke with the pair's own damping). Without
# noise both codes integrate the same deterministic system from the same state: every grain's
# position and velocity after 5325 steps and ~60 collisions of all three pair kinds agree to
# rounding (measured 7e-15 m, 2e-13 m/s), which a wrong mass, diameter or damping would break by
# orders of magnitude.
# The same in 3D (spheres, docs/scenes/bidisperse-mixture-3d.ini): the deck is the 2D one with
# dimension 3 and z, the trajectories agree to rounding as well. And the 2D mixture with the
# tangential dashpot: each pair_coeff's tangential linear_nohistory x_ab = gamma_t,ab / gamma_ab
# gives the pair's own tangential damping (mu_t = 1e4, no cap), so oblique contacts of all three
# pair kinds agree to rounding too (a tangential damping of the wrong mass would not).
def trajectories(lmpdir, rundir, axes, typed):
    """LAMMPS's dump against granule's snapshots of the same run: the largest position (minimum
    image) and velocity differences over the frames, whether the dump's types are the species,
    and the numbers of frames of both."""
    fr_g = granule.read_snapshots(rundir)
    blocks = open(os.path.join(lmpdir, "dump.granule.lammpstrj")).read().split("ITEM: TIMESTEP\n")[1:]
    worst_x = worst_v = 0.0
    same_types = True
    c0 = 2 if typed else 1  # id (type) x y (z) vx vy (vz)
    for blk, f in zip(blocks, fr_g):
        lines = blk.splitlines()
        n = int(lines[2])
        a = np.array([ln.split() for ln in lines[8:8 + n]], dtype=float)
        a = a[np.argsort(a[:, 0])]
        if typed:
            same_types &= bool(np.array_equal(a[:, 1].astype(int), f["species"]))
        for c, key in enumerate(axes):
            dx = a[:, c0 + c] - f[key]  # minimum image (harmless along a wall axis: tiny dx)
            worst_x = max(worst_x, float(np.abs(dx - f["L"] * np.round(dx / f["L"])).max()))
            worst_v = max(worst_v, float(np.abs(a[:, c0 + len(axes) + c] - f["v" + key]).max()))
    return worst_x, worst_v, same_types, len(blocks), len(fr_g)


for mix_scene, tangential in (("bidisperse-mixture.ini", None), ("bidisperse-mixture-3d.ini", None),
                              ("bidisperse-mixture.ini", "tangential_dashpot")):
    mix = os.path.join(src, "docs", "scenes", mix_scene)
    three = "3d" in mix_scene
    label = ("3D mixture" if three else "mixture") + (f" with {tangential}" if tangential else "")
    sets_mix = {"system.N": 200, "species.radius": "1e-3, 2e-3", "system.packing_fraction": 0.1, "placement.v0": 0.3,
                "noise.mode": "none", "run.warmup": 0, "run.duration": 0.05, "run.sample_every": 0.01,
                "output.snapshot_every": 0.01, "output.plots": "false"}
    if tangential:
        sets_mix["model.tangential"] = tangential
    args_mix = sum((["--set", f"{k}={v}"] for k, v in sets_mix.items()), [])
    with tempfile.TemporaryDirectory() as tmp:
        lmpdir, rundir = os.path.join(tmp, "lammps"), os.path.join(tmp, "granule")
        subprocess.run([exe, "export", "lammps", mix, "--out", lmpdir] + args_mix, check=True)
        deck = open(os.path.join(lmpdir, "in.granule")).read()
        data = open(os.path.join(lmpdir, "data.granule")).read()
        if not ("2 atom types" in data and "set type 1 mass 3.5299999999999997e-05" in deck
                and "set type 2 mass 0.00014119999999999999" in deck and "pair_style granular" in deck
                and f"dimension {3 if three else 2}" in deck
                and all(f"pair_coeff {a} {b} hooke 5000 " in deck for a, b in ((1, 1), (1, 2), (2, 2)))
                and (deck.count(" 10000\n") == 3) == bool(tangential)):
            failures.append(f"{label} deck: 2 atom types, set type masses, one pair_coeff per species pair")
        r = run_lmp([lmp, "-in", "in.granule", "-log", "log.lammps", "-screen", "none"], cwd=lmpdir)
        if r.returncode != 0:
            print(r.stdout[-1000:], r.stderr[-2000:], open(os.path.join(lmpdir, "log.lammps")).read()[-2000:] if os.path.exists(os.path.join(lmpdir, "log.lammps")) else "(no log.lammps)")
            sys.exit(f"LAMMPS failed on the exported {label}'s deck")
        subprocess.run([exe, "run", os.path.join(lmpdir, "scene.ini"), "--out", rundir, "--quiet"], check=True)
        collisions = json.load(open(os.path.join(rundir, "summary.json")))["collisions"]
        worst_x, worst_v, same_types, nl, ng = trajectories(lmpdir, rundir, ("x", "y", "z") if three else ("x", "y"), True)
        same_types &= nl == ng == 6
        ok = same_types and collisions >= 30 and worst_x < 1e-12 and worst_v < 1e-10
        print(f"{'ok  ' if ok else 'FAIL'} {label}, no noise: {collisions} collisions; LAMMPS against granule: "
              f"positions {worst_x:.2g} m, velocities {worst_v:.2g} m/s apart at most; types = species: {same_types}")
        if not ok:
            failures.append(f"{label} trajectories")

# A radius distribution (docs/mixtures.md): each grain its own atom type and mass, each pair of
# grains its own pair_coeff with the coefficients granule's kernel scales to the pair's reduced mass
# and effective radius (pair_style granular, hooke, tangential linear_nohistory x_ij). 60 lognormal
# discs without noise from the same state: the trajectories agree to rounding, as for species
# lists; one damping for all pairs (the reference pair's) would part them by far more.
def export_and_run(scene, sets, tmp, label):
    """`granule export lammps` of scene with sets, LAMMPS on the deck, and granule's run of the
    deck's scene.ini: (deck folder, granule's folder, the deck's text)."""
    lmpdir, rundir = os.path.join(tmp, "lammps"), os.path.join(tmp, "granule")
    subprocess.run([exe, "export", "lammps", scene, "--out", lmpdir] + sum((["--set", f"{k}={v}"] for k, v in sets.items()), []), check=True)
    r = run_lmp([lmp, "-in", "in.granule", "-log", "log.lammps", "-screen", "none"], cwd=lmpdir)
    if r.returncode != 0:
        print(r.stdout[-1000:], r.stderr[-2000:])
        sys.exit(f"LAMMPS failed on the exported {label}'s deck")
    subprocess.run([exe, "run", os.path.join(lmpdir, "scene.ini"), "--out", rundir, "--quiet"], check=True)
    return lmpdir, rundir, open(os.path.join(lmpdir, "in.granule")).read()


with tempfile.TemporaryDirectory() as tmp:
    lmpdir, rundir, deck = export_and_run(
        os.path.join(src, "docs", "scenes", "polydisperse-gas.ini"),
        {"system.N": 60, "system.packing_fraction": 0.1, "placement.v0": 0.3, "model.k_s": 5e3,
         "model.eps_n": 0.8, "model.tangential": "tangential_dashpot", "model.eps_t": 0.5,
         "run.warmup": 0, "run.duration": 0.2, "run.sample_every": 0.04, "run.seed": 3,
         "output.snapshot_every": 0.04, "output.plots": "false", "analysis.observables": "moments"},
        tmp, "radius distribution")
    if not ("60 atom types" in open(os.path.join(lmpdir, "data.granule")).read()
            and deck.count("\npair_coeff ") == 60 * 61 // 2 and deck.count("\nset type ") == 60):
        failures.append("radius distribution deck: 60 atom types, 60 masses, 1830 pair_coeff lines")
    collisions = json.load(open(os.path.join(rundir, "summary.json")))["collisions"]
    worst_x, worst_v, _, nl, ng = trajectories(lmpdir, rundir, ("x", "y"), False)
    ok = nl == ng == 6 and collisions >= 30 and worst_x < 1e-12 and worst_v < 1e-10
    print(f"{'ok  ' if ok else 'FAIL'} radius distribution with tangential_dashpot, no noise: {collisions} "
          f"collisions; LAMMPS against granule: positions {worst_x:.2g} m, velocities {worst_v:.2g} m/s apart at most")
    if not ok:
        failures.append("radius distribution trajectories")

# A bed of two species between fixed walls under gravity (docs/scenes/vibrated-bed-mixture.ini, the
# floor at rest, 100 grains, no noise): one wall/gran fix per species and wall, each with the
# species' own damping gamma_n,s(wall) / m_s; grains of both sizes land on the floor, and until the
# dense bed's chaos takes over (after about 0.07 s) the trajectories agree to rounding. One wall
# damping for both species (the scene mass's) parts them by micrometres at the first landing.
with tempfile.TemporaryDirectory() as tmp:
    lmpdir, rundir, deck = export_and_run(
        os.path.join(src, "docs", "scenes", "vibrated-bed-mixture.ini"),
        {"boundary.amplitude": 0, "system.N": 100, "run.warmup": 0, "run.duration": 0.06,
         "run.sample_every": 0.02, "output.snapshot_every": 0.02, "output.plots": "false"},
        tmp, "bed of two species")
    if not ("group s2 type 2" in deck and "fix wall_ylo_s1 s1 wall/gran" in deck and "fix wall_yhi_s2 s2 wall/gran" in deck):
        failures.append("species bed deck: a wall/gran fix per species and wall")
    worst_x, worst_v, same_types, nl, ng = trajectories(lmpdir, rundir, ("x", "y"), True)
    # the same deck with species 1's wall damping for species 2 as well: the large grains' landings
    # then differ, so the comparison above did see each species' own wall contact
    fix = [ln for ln in deck.splitlines() if ln.startswith("fix wall_ylo_s1 ")][0].split()
    wrong = deck.replace(" " + [ln for ln in deck.splitlines() if ln.startswith("fix wall_ylo_s2 ")][0].split()[7] + " ",
                         " " + fix[7] + " ")
    open(os.path.join(lmpdir, "in.granule"), "w").write(wrong)
    r = run_lmp([lmp, "-in", "in.granule", "-log", "log.lammps", "-screen", "none"], cwd=lmpdir)
    wrong_x = trajectories(lmpdir, rundir, ("x", "y"), True)[0] if r.returncode == 0 else 0.0
    ok = same_types and nl == ng == 4 and worst_x < 1e-11 and worst_v < 1e-9 and wrong_x > 1e-9
    print(f"{'ok  ' if ok else 'FAIL'} bed of two species on a floor under gravity, no noise: LAMMPS against "
          f"granule: positions {worst_x:.2g} m, velocities {worst_v:.2g} m/s apart at most; with species 1's wall damping for "
          f"both, {wrong_x:.2g} m")
    if not ok:
        failures.append("species bed trajectories")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
