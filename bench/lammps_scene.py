"""The 2D (or 3D) RFM scene in granule and in LAMMPS, model by model (docs/lammps.md, "The scene, model by model").

    /usr/bin/python3 bench/lammps_scene.py --build BUILD --lmp LMP [--quick] [--dim 3] [--cases a,b,...] [--json OUT]
    /usr/bin/python3 bench/lammps_scene.py data SNAPSHOT.xyz OUT.data   (granule frame -> LAMMPS data file)

Every case runs the scene (docs/scenes/rfm-2d.ini, N = 12000, phi = 0.53; with --dim 3
docs/scenes/rfm-3d.ini, N = 2000 spheres, phi = 0.1, or --set to change it) from the same initial state
(granule's placement, frame 0) for the same warm-up and sampling window in both engines, with
independent noise streams, and compares
  T (2.19) = <|v|^2>: the sampled series' means, errors from 8 blocks, z;
  P(v): the velocity components of every sampled frame, each frame scaled by its own rms (the shape,
    not T), pooled: two-sample KS distance D, and the tail fractions P(|c| > 2), P(|c| > 3) with
    errors from 8 blocks of frames, z;
  rotation cases: T_rot = <I w^2> / M = q r^2 <w^2> (one rotational degree of freedom; equipartition
    would give T / 2), granule from ledger.csv's rotational column, LAMMPS from omegaz.
A case whose model this build lacks (granule models) is reported as skipped; so is a mapping LAMMPS
cannot express (the error says why). Agreement is statistical: the script reports, it does not judge.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.dirname(HERE)
SCENES = {2: os.path.join(SRC, "docs", "scenes", "rfm-2d.ini"), 3: os.path.join(SRC, "docs", "scenes", "rfm-3d.ini")}
sys.path.insert(0, HERE)
import lammps_collisions  # noqa: E402  (the single-collision mapping of the normal laws, docs/lammps.md)

BLOCKS = 8
XMU = 1e4  # the Coulomb cap mu |F_n| of LAMMPS's tangential laws: large = a pure dashpot


def hooke_gran(c):
    """gran/hooke: damping constants per effective mass (1/s), xmu large, no rotation (fix nve)."""
    return (f"gran/hooke {c['lammps_kn']} 0.0 {c['lammps_gamman']} {c['lammps_gammat']} {XMU!r} 1", "")


def hertz_granular(c, sets):
    """pair granular hertz with the damping of the single-collision mapping (docs/lammps.md)."""
    if abs(float(c["radius"]) - lammps_collisions.RADIUS) > 1e-15:
        raise ValueError("the hertz mapping of bench/lammps_collisions.py is for r = 1.5 mm")
    coeff, _ = lammps_collisions.lammps_pair_coeff("hertz", [s.split(".", 1)[1] for s in sets], c)
    return ("granular", coeff)


def hooke_rotation(c, tangential):
    """pair granular hooke with damping velocity (eta_n = gamma_n, kg/s) and a tangential law at the
    contact point, whose damping LAMMPS sets as x_gamma_t times the normal one: x = gamma_t / gamma_n."""
    x = float(c["gamma_t"]) / float(c["gamma_n"])
    return ("granular", f"hooke {c['k_s']} {c['gamma_n']} tangential {tangential.format(x=x)} damping velocity")


ROTATE = ["model.rotation=true", "model.inertia_factor=0.5"]  # a uniform disc, as LAMMPS's fix nve/sphere disc
# name: granule --set list, the LAMMPS pair (style, coeff) from the coefficients, the integration fix,
# the granule model the case needs. Adding a case is one entry.
CASES = {
    "hooke": dict(sets=[], pair=hooke_gran, fix="nve", needs="spring_dashpot"),
    "hertz-tsuji": dict(sets=["model.normal=hertz", "model.tangential=none"],
                        pair=lambda c: hertz_granular(c, ["model.normal=hertz"]), fix="nve", needs="hertz"),
    "hertz-visco": dict(sets=["model.normal=hertz", "model.tangential=none", "model.viscoelastic=true",
                              "model.visco_A=1e-6"],
                        pair=lambda c: hertz_granular(c, ["model.viscoelastic=true"]), fix="nve", needs="hertz"),
    "hooke-rotation": dict(sets=ROTATE, pair=lambda c: hooke_rotation(c, f"linear_nohistory {{x!r}} {XMU!r}"),
                           fix="nve/sphere disc", needs="tangential_dashpot"),
    # (d) hooke + tangential spring (history, LAMMPS linear_history), no rotation: fix nve leaves
    # omega at 0, so LAMMPS's contact point moves with the centres as granule's does without rotation
    "hooke-history": dict(
        sets=["model.tangential=tangential_spring", "model.k_t=2.5e5", "model.mu=1e4"],
        pair=lambda c: ("granular", f"hooke {c['k_s']} {c['gamma_n']} tangential linear_history 2.5e5 0.0 {XMU!r} "
                                    "damping velocity"),
        fix="nve", needs="tangential_spring"),
    # (e) the same with rotation (fix nve/sphere disc): the spring integrates the contact point's
    # velocity in both engines (LAMMPS with the full radius, granule with |r_ij| / 2: docs/lammps.md,
    # the lever arm); no dashpot (gamma_t = 0, x = 0)
    "hooke-history-rotation": dict(
        sets=["model.tangential=tangential_spring", "model.k_t=2.5e5", "model.mu=1e4"] + ROTATE,
        pair=lambda c: hooke_rotation(c, f"linear_history 2.5e5 {{x!r}} {XMU!r}"),
        fix="nve/sphere disc", needs="tangential_spring"),
}
DEFAULT_CASES = "hooke,hertz-tsuji,hertz-visco,hooke-rotation,hooke-history,hooke-history-rotation"


def read_xyz(path):
    """(time, positions, velocities, box side) of a granule snapshot frame: 2 components (pbc "T T F")
    or 3 (pbc "T T T"); the frame always carries pos:R:3 and velo:R:3."""
    lines = open(path).read().splitlines()
    n = int(lines[0])
    head = lines[1]
    L = float(head.split('Lattice="')[1].split()[0])
    t = float(head.split("Time=")[1].split()[0])
    dim = 3 if 'pbc="T T T"' in head else 2
    a = np.array([ln.split()[1:7] for ln in lines[2:2 + n]], dtype=float)
    return t, a[:, 0:dim], a[:, 3:3 + dim], L


def write_data(snap, out):
    """A LAMMPS data file (atom_style sphere) of a granule frame; the diameter from its radius column.
    A 2D frame gets a thin z slab (LAMMPS's 2D box), a 3D frame the cube."""
    t, x, v, L = read_xyz(snap)
    d = 2 * float(open(snap).read().splitlines()[2].split()[7])
    dim = x.shape[1]
    pad = lambda a: list(a) + [0.0] * (3 - len(a))
    zlo, zhi = (0.0, L) if dim == 3 else (-d, d)
    with open(out, "w") as f:
        f.write(f"granule state ({snap})\n\n{len(x)} atoms\n1 atom types\n\n0 {L!r} xlo xhi\n0 {L!r} ylo yhi\n"
                f"{zlo!r} {zhi!r} zlo zhi\n\nAtoms # sphere\n\n")
        for i, r in enumerate(x, 1):
            f.write(f"{i} 1 {d!r} 1.0 " + " ".join(repr(float(c)) for c in pad(r)) + "\n")
        f.write("\nVelocities\n\n")
        for i, u in enumerate(v, 1):
            f.write(f"{i} " + " ".join(repr(float(c)) for c in pad(u)) + " 0.0 0.0 0.0\n")


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode:
        sys.exit(f"lammps_scene: {' '.join(map(str, cmd))} failed ({r.returncode}):\n{r.stderr[-2000:]}{r.stdout[-2000:]}")
    return r.stdout


def block_mean(x, blocks=BLOCKS):
    """Mean over rows and its standard error from `blocks` consecutive blocks."""
    x = np.asarray(x, dtype=float)
    m = len(x) // blocks
    if m < 1:
        return float(x.mean(axis=0)) if x.ndim == 1 else x.mean(axis=0), float("nan")
    means = x[: m * blocks].reshape(blocks, m, *x.shape[1:]).mean(axis=1)
    return x.mean(axis=0), means.std(axis=0, ddof=1) / math.sqrt(blocks)


def shape(frames_v):
    """Per frame: the components minus the frame's mean, over the frame's rms component (P(v)'s shape)."""
    out = []
    for v in frames_v:
        c = (v - v.mean(axis=0)).ravel()
        out.append(c / math.sqrt(np.mean(c * c)))
    return out


def ks(a, b):
    """Two-sample Kolmogorov-Smirnov distance and its p-value as if the samples were independent."""
    try:
        from scipy.stats import ks_2samp
        r = ks_2samp(a, b)
        return float(r.statistic), float(r.pvalue)
    except ImportError:
        a, b = np.sort(a), np.sort(b)
        grid = np.concatenate([a, b])
        D = float(np.max(np.abs(np.searchsorted(a, grid, "right") / a.size - np.searchsorted(b, grid, "right") / b.size)))
        return D, float("nan")


def z(a, ea, b, eb):
    return abs(a - b) / math.hypot(ea, eb) if ea > 0 or eb > 0 else float("nan")


def granule_side(folder, warmup, N, q, r):
    with open(os.path.join(folder, "temperature.csv")) as f:
        T = [(float(row["t"]), float(row["T"])) for row in csv.DictReader(f) if row["phase"] in ("sample", "sampling")]
    frames = []
    for f in sorted(os.listdir(os.path.join(folder, "snapshots"))):
        t, _, v, _ = read_xyz(os.path.join(folder, "snapshots", f))
        if t > warmup * (1 + 1e-9):
            frames.append(v)
    led = open(os.path.join(folder, "ledger.csv")).read().split()
    head = led[0].split(",")
    Trot = None
    if "rotational" in head:
        k, mass = head.index("rotational"), None
        rows = [ln.split(",") for ln in led[1:]]
        Trot = [float(rw[k]) for rw in rows if float(rw[0]) > warmup * (1 + 1e-9)]  # sum I w^2 / 2 (J)
    return [v for _, v in T], frames, Trot


def lammps_side(folder, warm_steps, dim):
    T, Trot = [], []
    for ln in open(os.path.join(folder, "lammps_T.dat")):
        if ln.strip() and not ln.startswith("#"):
            s = ln.split()
            T.append(float(s[1]))
            Trot.append(float(s[2]))
    frames, text = [], open(os.path.join(folder, "dump.lammpstrj")).read().split("ITEM: TIMESTEP\n")[1:]
    for fr in text:
        lines = fr.splitlines()
        if int(lines[0]) <= warm_steps:
            continue
        n = int(lines[2])
        a = np.array([ln.split() for ln in lines[8:8 + n]], dtype=float)
        frames.append(a[np.argsort(a[:, 0])][:, 1:1 + dim])
    return T, frames, Trot


def deck(c, case, pair, data, every, warm_steps, run_steps, seed):
    """The LAMMPS input of one case; 3D: a third noise component, no enforce2d, momentum in z."""
    style, coeff = pair
    three = c.get("dim") == "3"
    q = 0.4 if three else 0.5  # a solid sphere (fix nve/sphere) or a uniform disc (nve/sphere disc)
    fz = f"variable fz atom normal(0.0,{c['noise_sigma']},{seed + 2})\n" if three else ""
    return f"""units si
dimension {3 if three else 2}
boundary p p p
atom_style sphere
comm_modify vel yes
read_data {data}
set type 1 mass {c['mass']}
pair_style {style}
pair_coeff * * {coeff}
neighbor {0.3 * 2 * float(c['radius'])!r} bin
neigh_modify delay 0 every 1 check yes
variable fx atom normal(0.0,{c['noise_sigma']},{seed})
variable fy atom normal(0.0,{c['noise_sigma']},{seed + 1})
{fz}fix noise all addforce v_fx v_fy {"v_fz" if three else "0.0"}
fix 1 all {case['fix']}
{"" if three else "fix 2 all enforce2d"}
fix com all momentum 1 linear 1 1 {1 if three else 0}
variable vsq atom vx*vx+vy*vy{"+vz*vz" if three else ""}
compute vsum all reduce sum v_vsq
variable T equal c_vsum/atoms
compute om all property/atom omegax omegay omegaz
variable wsq atom {q * float(c["radius"]) ** 2!r}*({"c_om[1]*c_om[1]+c_om[2]*c_om[2]+" if three else ""}c_om[3]*c_om[3])
compute wsum all reduce sum v_wsq
variable Trot equal c_wsum/atoms
timestep {c['dt']}
thermo {every}
thermo_style custom step v_T v_Trot
thermo_modify flush no
run {warm_steps}
fix avg all ave/time {every} 1 {every} v_T v_Trot file lammps_T.dat
dump d all custom {every} dump.lammpstrj id vx vy{" vz" if three else ""}
run {run_steps}
"""


def compare_case(name, case, a, work, models, data):
    if case["needs"] not in models:
        return dict(case=name, skipped=f"model not built: granule models lists no {case['needs']}")
    if case.get("pending"):
        return dict(case=name, skipped=case["pending"])
    sets = a.sets + case["sets"]
    if a.dim == 3:  # spheres: I = 2/5 M r^2 (granule's 3D default) and LAMMPS's nve/sphere
        sets = [x for x in sets if not x.startswith("model.inertia_factor")]
        case = dict(case, fix=case["fix"].replace("nve/sphere disc", "nve/sphere"))
    set_args = sum((["--set", s] for s in sets), [])
    r = subprocess.run([a.coeffs, a.scene] + set_args, capture_output=True, text=True)
    if r.returncode and "not available with dim = 3" in r.stderr:  # a law this build has in 2D only
        return dict(case=name, skipped="granule refuses it in 3D: " + r.stderr.strip().split(": ", 2)[-1][:160])
    c = dict(ln.split("=", 1) for ln in run([a.coeffs, a.scene] + set_args).split())
    try:
        pair = case["pair"](c)
    except ValueError as e:
        return dict(case=name, skipped=f"no LAMMPS equivalent: {e}")
    dt = float(c["dt"])
    warm_steps, run_steps, every = round(a.warmup / dt), round(a.duration / dt), max(1, round(a.sample / dt))
    folder = os.path.join(work, name)
    os.makedirs(folder)
    seed = int(c["seed"]) % 900000 + 1
    with open(os.path.join(folder, "in.rfm"), "w") as f:
        f.write(deck(c, case, pair, data, every, warm_steps, run_steps, seed))
    r = subprocess.run([a.lmp, "-in", "in.rfm", "-log", "log.lammps", "-screen", "none"], cwd=folder)
    if r.returncode:
        sys.exit(f"lammps_scene: LAMMPS failed on {folder}/in.rfm:\n" + open(os.path.join(folder, "log.lammps")).read()[-1500:])
    gdir = os.path.join(folder, "granule")
    run([a.granule, "run", a.scene] + set_args + ["--set", f"run.warmup={a.warmup!r}", "--set", f"run.duration={a.duration!r}",
        "--set", f"run.sample_every={a.sample!r}", "--set", f"output.snapshot_every={a.sample!r}",
        "--set", "output.plots=false", "--out", gdir])
    N, M, rad = int(c["N"]), float(c["mass"]), float(c["radius"])
    Tg, fg, Eg = granule_side(gdir, a.warmup, N, 0.5, rad)
    Tl, fl, Rl = lammps_side(folder, warm_steps, int(c.get("dim", 2)))
    g = json.load(open(os.path.join(gdir, "summary.json")))
    res = dict(case=name, dim=int(c.get("dim", 2)), granule_sets=sets, lammps_pair=f"pair_style {pair[0]}; pair_coeff * * {pair[1]}", lammps_fix=case["fix"],
               N=N, dt=dt, warmup=a.warmup, duration=a.duration, frames=[len(fg), len(fl)], kernel=g["kernel"])
    (mg, eg), (ml, el) = block_mean(Tg), block_mean(Tl)
    res["T"] = dict(granule=[float(mg), float(eg)], lammps=[float(ml), float(el)], z=z(mg, eg, ml, el))
    if Eg is not None:
        (mg, eg), (ml, el) = block_mean(2 * np.asarray(Eg) / (N * M)), block_mean(Rl)
        res["T_rot"] = dict(granule=[float(mg), float(eg)], lammps=[float(ml), float(el)], z=z(mg, eg, ml, el),
                            ratio_to_T_half=[float(mg / (res["T"]["granule"][0] / 2)), float(ml / (res["T"]["lammps"][0] / 2))])
    sg, sl = shape(fg), shape(fl)
    D, p = ks(np.concatenate(sg), np.concatenate(sl))
    # the yardstick for D: the same distance between the first and second half of each engine's own
    # frames (same correlations, same sample size per side as a half)
    half = lambda s: ks(np.concatenate(s[: len(s) // 2]), np.concatenate(s[len(s) // 2:]))[0]
    res["ks"] = dict(D=D, p_independent=p, n=[int(sum(x.size for x in sg)), int(sum(x.size for x in sl))],
                     D_halves=[half(sg), half(sl)])
    for cut in (2.0, 3.0):
        (mg, eg), (ml, el) = (block_mean([np.mean(np.abs(x) > cut) for x in s]) for s in (sg, sl))
        res[f"tail{cut:g}"] = dict(granule=[float(mg), float(eg)], lammps=[float(ml), float(el)], z=z(mg, eg, ml, el))
    loops = [float(ln.split()[3]) for ln in open(os.path.join(folder, "log.lammps")) if ln.startswith("Loop time of")]
    res["wall"] = dict(granule=g["wall_seconds"], lammps=sum(loops))
    return res


def table(results):
    pm = lambda v: f"{v[0]:.5g} +- {v[1]:.2g}"
    out = ["| case | N, window | T granule | T LAMMPS | z(T) | T_rot granule | T_rot LAMMPS | z(T_rot) | KS D granule-LAMMPS (D between halves of granule / LAMMPS frames) | "
           "P(abs(c) > 2) granule / LAMMPS, z | P(abs(c) > 3) granule / LAMMPS, z | wall granule / LAMMPS (s) |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        if "skipped" in r:
            out.append(f"| {r['case']} | skipped: {r['skipped']} |" + " |" * 10)
            continue
        tr = r.get("T_rot")
        halves = "halves " + " / ".join(f"{d:.4f}" for d in r["ks"]["D_halves"]) if "D_halves" in r["ks"] else f"n = {r['ks']['n'][0]}"
        rot = (f"{pm(tr['granule'])} | {pm(tr['lammps'])} | {tr['z']:.2f}" if tr else "- | - | -")
        tails = " | ".join(f"{r[k]['granule'][0]:.5f} +- {r[k]['granule'][1]:.1g} / {r[k]['lammps'][0]:.5f} +- "
                           f"{r[k]['lammps'][1]:.1g}, {r[k]['z']:.2f}" for k in ("tail2", "tail3"))
        out.append(f"| {r['case']} | {r['N']}, {r['warmup']:g} + {r['duration']:g} s ({r['frames'][0]} / {r['frames'][1]} frames) | "
                   f"{pm(r['T']['granule'])} | {pm(r['T']['lammps'])} | {r['T']['z']:.2f} | {rot} | {r['ks']['D']:.4f} ({halves}) | "
                   f"{tails} | {r['wall']['granule']:.0f} / {r['wall']['lammps']:.0f} |")
    return "\n".join(out)


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "data":
        write_data(sys.argv[2], sys.argv[3])
        return 0
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--quick", action="store_true", help="N = 300, 400 steps: the pipeline only, no agreement")
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2, help="2: docs/scenes/rfm-2d.ini; 3: docs/scenes/rfm-3d.ini")
    ap.add_argument("--set", action="append", default=[], dest="extra", help="a scene override for both engines' scene (granule --set)")
    ap.add_argument("--cases", default=DEFAULT_CASES, help=f"comma-separated subset of {','.join(CASES)}")
    ap.add_argument("--warmup", type=float, help="simulated seconds (default 0.05; quick 2e-4)")
    ap.add_argument("--duration", type=float, help="simulated seconds of sampling (default 0.05; quick 2e-4)")
    ap.add_argument("--json", help="write the results here")
    a = ap.parse_args()
    unknown = [n for n in a.cases.split(",") if n not in CASES]
    if unknown:
        print(f"lammps_scene: unknown case {', '.join(unknown)}; choose from {', '.join(CASES)}", file=sys.stderr)
        return 2
    a.granule, a.coeffs = os.path.join(a.build, "granule"), os.path.join(a.build, "bench", "bench_coeffs")
    a.scene = SCENES[a.dim]
    quick_size = ["system.N=300", "system.L=0.08"] if a.dim == 2 else ["system.N=300", "system.packing_fraction=0.3", "placement.v0=2"]
    # 3D: rfm-3d.ini has no tangential law; the cases' "scene" is the 2D one's, a tangential
    # dashpot at the contact point (eps_t = 0.6 here), so that hooke is gran/hooke with gammat
    tangential3 = ["model.tangential=tangential_dashpot", "model.eps_t=0.6"] if a.dim == 3 else []
    a.sets = ["model.clamp=false"] + tangential3 + (quick_size if a.quick else []) + a.extra
    a.warmup = a.warmup if a.warmup is not None else (2e-4 if a.quick else 0.05)
    a.duration = a.duration if a.duration is not None else (2e-4 if a.quick else 0.05)
    a.sample = 2e-5 if a.quick else 1e-3
    models = run([a.granule, "models"])
    with tempfile.TemporaryDirectory(prefix="granule-lammps-scene.") as work:
        init = os.path.join(work, "init")
        set_args = sum((["--set", s] for s in a.sets), [])
        run([a.granule, "run", a.scene] + set_args + ["--set", "run.warmup=0", "--set", f"run.duration={a.sample!r}",
            "--set", f"run.sample_every={a.sample!r}", "--set", "output.snapshot_every=1", "--set", "output.plots=false",
            "--out", init])
        data = os.path.join(work, "rfm.data")
        write_data(os.path.join(init, "snapshots", "snap_000000.xyz"), data)
        results = []
        for name in a.cases.split(","):
            results.append(compare_case(name, CASES[name], a, work, models, data))
            print(f"lammps_scene: {name}: {json.dumps(results[-1])}", file=sys.stderr, flush=True)
    print(table(results))
    if a.json:
        json.dump(results, open(a.json, "w"), indent=1)
    ran = [r for r in results if "skipped" not in r]
    # the pipeline's own checks (no agreement is asked here): both engines sampled T and frames, the
    # rotating cases a rotational temperature, and no case that this build and LAMMPS can run was lost
    bad = [r["case"] for r in ran if not (all(np.isfinite(r["T"][k][0]) and r["T"][k][0] > 0 for k in ("granule", "lammps"))
                                          and min(r["frames"]) > 0 and np.isfinite(r["ks"]["D"])
                                          and ("rotation" not in r["case"] or r.get("T_rot", {}).get("lammps", [0])[0] > 0))]
    bad += [r["case"] for r in results if "hooke" in r["case"] and "history" not in r["case"] and "skipped" in r and a.dim == 2]
    if bad:
        print(f"lammps_scene: no temperature or no frames from {', '.join(bad)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
