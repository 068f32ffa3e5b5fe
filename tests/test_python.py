"""The Python module (docs/python.md) against the granule command: stepping a Sim from Python gives
bit for bit the state `granule run` reaches; arrays are views; errors carry granule's message;
observables and run folders come back as numpy/pandas.

    test_python.py GRANULE_EXE SOURCE_DIR    (PYTHONPATH=build/python, Debian's /usr/bin/python3)
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

import granule
from checks import check, finish

exe, src = sys.argv[1], sys.argv[2]
scene_path = os.path.join(src, "docs", "scenes", "rfm-2d.ini")


steps = 400  # 4 samples of 100 steps; snapshot at the end
sets = {"system.N": 300, "system.L": 0.08, "run.warmup": 0.0, "run.duration": steps * 1e-6,
        "run.sample_every": 100e-6, "output.snapshot_every": steps * 1e-6, "output.plots": False,
        "analysis.observables": "moments,pv,pair"}
cli_version = subprocess.run([exe, "--version"], check=True, capture_output=True, text=True).stdout.split()[1]
check(getattr(granule, "__version__", None) == granule.version == cli_version,
      f"granule.__version__ {getattr(granule, '__version__', None)} = the C library's {granule.version} = the command's {cli_version}")

with tempfile.TemporaryDirectory() as tmp:
    # 1. bit-identical to `granule run` of the same scene and seed over the same steps
    out = os.path.join(tmp, "run")
    cmd = [exe, "run", scene_path, "--out", out] + sum((["--set", f"{k}={granule._ini_value(v)}"] for k, v in sets.items()), [])
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    scene = granule.load_scene(scene_path, set=sets)
    sim = granule.Sim(scene)
    x, vx = sim.x, sim.vx  # views taken before stepping see the stepped state
    sim.step(steps // 2)
    sim.step(steps - steps // 2)
    snaps = granule.read_snapshots(out)
    last = snaps[-1]
    check(len(snaps) == 2 and abs(last["t"] - sim.t) < 1e-15, f"snapshot at t = {last['t']} matches sim.t = {sim.t}")
    for name in ("x", "y", "vx", "vy"):
        a = getattr(sim, name)
        check(np.array_equal(a, last[name]), f"{name} after {steps} steps bit-identical to granule run "
              f"(max |diff| {np.max(np.abs(a - last[name])):.3g})")
    check(np.array_equal(x, sim.x) and np.array_equal(vx, sim.vx), "views taken before stepping follow the state")

    # 2. views: no copy, read-only, keep the simulation alive
    check(sim.x.base is sim and not sim.x.flags.writeable and sim.x.dtype == np.float64, "x is a read-only float64 view on the Sim")
    check(sim.fx.shape == (300,) and np.any(sim.fx != 0.0) and np.all(np.isfinite(sim.fy)), "contact forces readable as views")
    T_py = np.mean((sim.vx - sim.vx.mean()) ** 2 + (sim.vy - sim.vy.mean()) ** 2)
    check(abs(T_py - sim.temperature) <= 1e-12 * T_py, "temperature (2.19) from the views equals sim.temperature")
    keep = sim.vy
    del sim
    check(np.all(np.isfinite(keep)) and keep.size == 300, "a view outlives the name of its Sim")
    try:
        keep[0] = 1.0
        check(False, "writing into a view raises")
    except ValueError:
        check(True, "writing into a view raises")

    # 3. errors carry granule's message
    for bad, words in ((["system.bogus=1"], "unknown key"), (["system.N=-3"], "N")):
        try:
            granule.load_scene(scene_path, set=bad)
            check(False, f"{bad} raises SceneError")
        except granule.SceneError as e:
            check(words in str(e) and isinstance(e, ValueError), f"{bad} raises SceneError: {e}")
    try:
        granule.load_scene(os.path.join(tmp, "missing.ini"))
        check(False, "a missing scene file raises")
    except granule.Error as e:
        check("missing.ini" in str(e), f"a missing scene file raises granule.Error: {e}")
    d = granule.load_scene({"system": {"dim": 2, "N": 100, "L": 0.1}, "model": {"eps_n": 0.5}}, set=["run.seed=7"])
    check(d.N == 100 and abs(d.L - 0.1) < 1e-15 and granule.scene_dict(d)["run"]["seed"] == 7, "scene from a dict with overrides")

    # 4. observables from Python equal those of the run that sampled the same frames
    sim = granule.Sim(scene)
    frames = []
    for _ in range(steps // 100):
        sim.step(100)
        frames.append({"t": sim.t, "x": sim.x.copy(), "y": sim.y.copy(), "vx": sim.vx.copy(), "vy": sim.vy.copy()})
    res = granule.observe(scene, frames)
    run = granule.read_run(out)
    m_py = res["moments"]["summary"]["speed"]["m2"]
    m_run = run["summary"]["analysis"]["moments"]["speed"]["m2"]
    check(m_py == m_run, f"<|v|^2> from Python observe = run's ({m_py} vs {m_run})")
    g_py, g_run = res["pair"]["tables"]["pair"]["g"].to_numpy(), run["tables"]["pair"]["g"].to_numpy()
    check(np.array_equal(g_py, g_run), "g(R) table from Python observe = run's pair.csv")
    check(run["tables"]["temperature"].shape[0] == steps // 100 + 1 and "T" in run["tables"]["temperature"], "temperature.csv as a DataFrame")

    # 5. granule.run from Python
    r = granule.run(scene, os.path.join(tmp, "pyrun"))
    check(r["T_mean"] == run["summary"]["T_mean"], f"granule.run T_mean {r['T_mean']} = CLI's {run['summary']['T_mean']}")

    # 6. the state as bytes (gr_sim_state_save): restored into a fresh Sim, stepping on is bit-identical
    # (verlet with rotation: the spins are in the state, and in the ledger's kinetic energy compared below)
    for kind, extra in (("verlet", []), ("verlet", ["model.rotation=true", "placement.omega0=200"]),
                        ("hybrid", ["integrator.kick_interval=5e-6"]),
                        ("event", ["model.normal=hard_sphere", "model.tangential=none"])):
        sc = granule.load_scene(scene_path, set=[f"{k}={v}" for k, v in sets.items()] + [f"integrator.kind={kind}"] + extra)
        a, b = granule.Sim(sc), granule.Sim(sc)
        a.step(150)
        state = a.state()
        a.step(250)
        b.restore(state)
        check(b.steps == 150, f"{kind}: restore sets the step counter")
        b.step(250)
        check(np.array_equal(a.x, b.x) and np.array_equal(a.vx, b.vx) and np.array_equal(a.y, b.y) and a.ledger() == b.ledger(),
              f"{kind}: state() then restore() steps on bit-identically")
        try:
            granule.Sim(granule.load_scene(scene_path, set=[f"{k}={v}" for k, v in sets.items() if k != "system.N"] + ["system.N=200"])).restore(state)
            check(False, f"{kind}: a state of another system is refused")
        except granule.Error as e:
            check("particles" in str(e) or "SIM" in str(e), f"{kind}: a state of another system is refused: {e}")

# 6b. walls and gravity (docs/systems-walls-gravity.md): the ledger carries gravity's potential
# energy, and its balance closes while the grain falls onto the floor and bounces
sc = granule.load_scene(os.path.join(src, "docs", "scenes", "bouncing-grain.ini"))
g = granule.Sim(sc)
l0 = g.ledger()
g.step(300000)  # past the first bounce
l1 = g.ledger()
check(l0["potential"] > 0 and l0["initial"] == l0["potential"] and l1["potential"] < l0["potential"]
      and l1["dissipated_normal"] > 0 and abs(l1["residual"]) < 1e-3 * l1["dissipated_normal"],
      f"walls + gravity: ledger with potential {l0['potential']:.4g} -> {l1['potential']:.4g} J, "
      f"residual {l1['residual']:.3g} J")
check(l1["wall_work"] == 0, "a static floor does no work (wall_work 0)")
# a vibrated floor's work is the ledger's wall_work, and the balance closes with it
v = granule.Sim(granule.load_scene(os.path.join(src, "docs", "scenes", "vibrated-bed.ini")))
v.step(40000)
lv = v.ledger()
check(lv["wall_work"] > 0 and lv["injected"] == 0
      and abs(lv["residual"]) < 1e-3 * (lv["wall_work"] + lv["dissipated"]),
      f"vibrated floor: wall_work {lv['wall_work']:.4g} J, residual {lv['residual']:.3g} J")
# the walls' impulses, only for the axis with walls: the grains' momentum changes by exactly the
# floor's impulse minus the ceiling's minus the weight's (pair forces cancel; no noise), so over
# 0.1 s of the bed (J(t1) - J(t0)) balances M sum vy; a periodic box has no walls
J0, t0, P0 = v.wall_impulse(), v.t, v.mass * v.vy.sum()
v.step(100000)
J1, P1 = v.wall_impulse(), v.mass * v.vy.sum()
floor, ceiling = J1["y_lo"] - J0["y_lo"], J1["y_hi"] - J0["y_hi"]
weight = v.N * v.mass * 9.81 * (v.t - t0)
check(sorted(J1) == ["y_hi", "y_lo"] and abs(floor - ceiling - weight - (P1 - P0)) < 1e-9 * floor
      and floor > 0 and granule.Sim(granule.load_scene(scene_path)).wall_impulse() == {},
      f"wall_impulse: floor {floor:.6g} N s - ceiling {ceiling:.3g} - weight {weight:.6g} = "
      f"{floor - ceiling - weight:.6g}, the grains' momentum change {P1 - P0:.6g} N s (difference {floor - ceiling - weight - (P1 - P0):.2g})")
# spheres (3D): the floor and ceiling at z = 0 and L are z_lo and z_hi, and the same balance holds
# along z for a bed of 60 spheres settled on a static floor (as the 2D bed, at rest: the last
# force evaluation of a step() call counts fully in the impulse but only half in the velocities, a
# difference that vanishes when the forces are steady)
b3 = granule.Sim(granule.load_scene(os.path.join(src, "docs", "scenes", "vibrated-bed-3d.ini"),
                                    set=["system.N=60", "system.L=0.02", "placement.v0=0",
                                         "model.eps_n=0.3", "model.k_s=5e3", "boundary.vibrate=none",
                                         "model.tangential=none", "model.rotation=false"]))
b3.step(160000)
J0, t0, P0 = b3.wall_impulse(), b3.t, b3.mass * b3.vz.sum()
b3.step(20000)
J1, P1 = b3.wall_impulse(), b3.mass * b3.vz.sum()
floor, ceiling = J1["z_lo"] - J0["z_lo"], J1["z_hi"] - J0["z_hi"]
weight = b3.N * b3.mass * 9.81 * (b3.t - t0)
check(sorted(J1) == ["z_hi", "z_lo"] and floor > 0
      and abs(floor - ceiling - weight - (P1 - P0)) < 1e-9 * weight,
      f"3D wall_impulse: floor {floor:.6g} N s - ceiling {ceiling:.3g} - weight {weight:.6g} = "
      f"{floor - ceiling - weight:.6g}, the spheres' momentum change {P1 - P0:.6g} N s")

# 7. a frame whose coordinate cannot be wrapped into the box (1e308 is finite) is refused with
# granule's message instead of killing the interpreter in the gridding of sk or the cell list
# of clusters (issue 39 item 8)
sc = granule.load_scene(scene_path, set=[f"{k}={granule._ini_value(v)}" for k, v in sets.items()] +
                        ["analysis.observables=sk,clusters"])
obs = granule.Observer(sc)
n = sc.N
x, y = np.linspace(0.0, 0.07, n), np.linspace(0.0, 0.07, n)
for name, bad in (("x", 1e308), ("y", -1e308), ("x", np.inf)):
    xb, yb = x.copy(), y.copy()
    (xb if name == "x" else yb)[3] = bad
    try:
        obs.sample_frame(0.1, xb, np.zeros(n), y=yb, vy=np.zeros(n))
        check(False, f"sample_frame with {name} = {bad} is refused")
    except granule.SceneError as e:
        check(f"particle 3 has {name} =" in str(e), f"sample_frame with {name} = {bad} is refused: {e}")
obs.sample_frame(0.1, x, np.zeros(n), y=y, vy=np.zeros(n))
check(obs.frames == 1, "the Observer still samples good frames after refusing bad ones")

# 8. Observer.finish into a folder holding a run is refused unless force, as on the command line
# (issue 39: a folder holds one consistent result or nothing)
with tempfile.TemporaryDirectory() as tmp:
    run_dir = os.path.join(tmp, "run")
    subprocess.run([exe, "run", scene_path, "--out", run_dir] + sum((["--set", f"{k}={granule._ini_value(v)}"]
                   for k, v in sets.items()), []), check=True, stdout=subprocess.DEVNULL)
    before = sorted(os.listdir(run_dir))
    try:
        obs.finish(run_dir)
        check(False, "Observer.finish into a run folder is refused")
    except granule.Error as e:
        check("--force" in str(e) or "force" in str(e), f"Observer.finish into a run folder is refused: {e}")
    check(sorted(os.listdir(run_dir)) == before, "the refused run folder is left as it was")
    summary = obs.finish(run_dir, force=True)
    check("summary.json" not in os.listdir(run_dir) and '"sk"' in summary,
          "force=True replaces the run folder's contents with the observables' tables")
# 9. issue 39 item 13: a frame with one NaN velocity or a NaN time is refused (not m2 = 0); a
# state with a flipped byte or cut short is refused by its checksum; a section that is not a dict,
# a line break in a value and a NUL in a set= value raise SceneError (the checks of scene files)
obs = granule.Observer(sc)
vb = np.zeros(n)
vb[5] = np.nan
for what, kw in (("one NaN velocity", dict(t=0.1, x=x, vx=vb, y=y, vy=np.zeros(n))),
                 ("t = nan", dict(t=float("nan"), x=x, vx=np.zeros(n), y=y, vy=np.zeros(n)))):
    try:
        granule.observe(sc, [kw])
        check(False, f"observe() with {what} is refused")
    except granule.SceneError as e:
        check("not a finite number" in str(e), f"observe() with {what} is refused: {e}")
a = granule.Sim(sc)
a.step(20)
state = a.state()
for what, bad in (("a flipped byte", state[:200] + bytes([state[200] ^ 1]) + state[201:]), ("cut short", state[:-1]),
                  ("without its checksum", state[:-8])):
    try:
        granule.Sim(sc).restore(bad)
        check(False, f"restore() of a state with {what} is refused")
    except granule.Error as e:
        check("checksum" in str(e), f"restore() of a state {what} is refused: {e}")
b = granule.Sim(sc)
b.restore(state)
check(b.steps == 20, "restore() of the unchanged state is accepted")
for what, source, set_, words in (
        ("a section that is not a dict", {"system": 5}, None, "[system]: expected a dict"),
        ("a line break in a value", {"system": {"N": "20\n[run]\nduration = 5"}}, None, "control byte 0x0a"),
        ("a ']' in a section name", {"system]x": {"N": 20}}, None, "system]x"),
        ("a NUL in a set= value", None, {"run.warmup": "0\x001"}, "control byte 0x00"),
        ("a line break in a set= value", None, ["run.warmup=0\n1"], "control byte 0x0a")):
    try:
        granule.load_scene(source, set=set_)
        check(False, f"load_scene with {what} raises SceneError")
    except granule.SceneError as e:
        check(words in str(e), f"load_scene with {what} raises SceneError: {e}")
    except Exception as e:
        check(False, f"load_scene with {what} raises SceneError, not {type(e).__name__}: {e}")

# 3D (docs/three-dimensions.md): z and vz are views like x and y; T (2.19) sums three components
s3 = granule.load_scene(os.path.join(src, "docs", "scenes", "rfm-3d.ini"), set={"system.N": 216})
sim3 = granule.Sim(s3)
sim3.step(100)
v3 = np.stack([sim3.vx, sim3.vy, sim3.vz])
T3 = np.mean(np.sum((v3 - v3.mean(axis=1, keepdims=True)) ** 2, axis=0))
check(sim3.dim == 3 and sim3.z.shape == (216,) and sim3.vz.base is sim3 and np.all((sim3.z >= 0) & (sim3.z < sim3.L)),
      "3D: z and vz are read-only views, z inside the cube")
check(abs(T3 - sim3.temperature) <= 1e-12 * T3, f"3D: T from x, y, z views {T3} = sim.temperature {sim3.temperature}")
check(sim.z is None and sim.vz is None, "2D: z and vz are None")
# 3D rotation: the angular velocity vectors are views wx, wy, wz; I <|w|^2> / M is T_rot
s3r = granule.load_scene(os.path.join(src, "docs", "scenes", "rfm-3d.ini"),
                         set={"system.N": 216, "model.tangential": "tangential_spring", "model.rotation": "true",
                              "placement.omega0": "300"})
sim3r = granule.Sim(s3r)
sim3r.step(50)
w2 = np.mean(sim3r.wx ** 2 + sim3r.wy ** 2 + sim3r.wz ** 2)
rot = sim3r.ledger()["rotational"]
I = 0.4 * sim3r.mass * sim3r.radius ** 2
check(sim3r.wx.base is sim3r and sim3r.wz.shape == (216,) and abs(0.5 * I * sim3r.N * w2 - rot) <= 1e-12 * rot,
      f"3D rotation: wx, wy, wz are views, I |w|^2 / 2 summed {0.5 * I * sim3r.N * w2} = the ledger's {rot}")
check(sim3.wx is None and sim3.wz is None and sim.wx is None, "no rotation: wx, wy, wz are None")
obs3 = granule.Observer(granule.load_scene(os.path.join(src, "docs", "scenes", "rfm-3d.ini"),
                                          set={"system.N": 216, "analysis.observables": "moments"}))
obs3.sample(sim3)
check(obs3.frames == 1, "3D: an Observer with moments samples a 3D Sim")
try:
    obs3.sample_frame(0.0, sim3.x, sim3.vx, sim3.y, sim3.vy)
    check(False, "3D: sample_frame without z, vz is refused")
except granule.SceneError as e:
    check("needs y, vy, z and vz" in str(e), f"3D: sample_frame without z, vz is refused: {e}")
# the frame observables in 3D: sample_frame of a Sim's arrays gives what sample(sim) gives
scene3o = granule.load_scene(os.path.join(src, "docs", "scenes", "rfm-3d.ini"),
                             set={"system.N": 216, "analysis.observables": "moments,pv,pair,pressure,sk"})
by_sim, by_arrays = granule.Observer(scene3o), granule.Observer(scene3o)
for _ in range(3):
    sim3.step(50)
    by_sim.sample(sim3)
    by_arrays.sample_frame(sim3.t, sim3.x, sim3.vx, sim3.y, sim3.vy, z=sim3.z, vz=sim3.vz)
with tempfile.TemporaryDirectory() as ta, tempfile.TemporaryDirectory() as tb:
    ja, jb = json.loads(by_sim.finish(ta, force=True)), json.loads(by_arrays.finish(tb, force=True))
    same = all(open(os.path.join(ta, f)).read() == open(os.path.join(tb, f)).read()
               for f in ("moments.csv", "pv.csv", "pair.csv", "pressure.csv", "sk.csv"))
    check(same and set(ja) == {"moments", "pv", "pair", "pressure", "sk"} and ja["pressure"]["unit"] == "Pa (N/m^2)",
          "3D: sample_frame(t, x, vx, y, vy, z=, vz=) equals sample(sim) for moments, pv, pair, pressure, sk")
with tempfile.TemporaryDirectory() as tmp3:
    sets3 = {"system.N": 216, "run.warmup": 0.0, "run.duration": 2e-4, "run.sample_every": 1e-4,
             "output.snapshot_every": 2e-4, "output.plots": False}
    cmd3 = [exe, "run", os.path.join(src, "docs", "scenes", "rfm-3d.ini"), "--out", tmp3, "--force"]
    cmd3 += sum((["--set", f"{k}={granule._ini_value(v)}"] for k, v in sets3.items()), [])
    subprocess.run(cmd3, check=True, stdout=subprocess.DEVNULL)
    last3 = granule.read_snapshots(tmp3)[-1]
    sim3b = granule.Sim(granule.load_scene(os.path.join(src, "docs", "scenes", "rfm-3d.ini"), set=sets3))
    sim3b.step(200)
    check(last3["dim"] == 3 and all(np.array_equal(last3[k], getattr(sim3b, k)) for k in ("x", "y", "z", "vx", "vy", "vz")),
          "3D: read_snapshots gives dim 3 and x, y, z, vx, vy, vz bit-identical to a Sim stepped from Python")
    # the same frames through trajectory.h5 (h5py), and read_run sees the 3D run's observables
    cmd3h = [c if c != tmp3 else tmp3 + "-h5" for c in cmd3] + ["--set", "output.trajectory=h5md",
                                                                  "--set", "analysis.observables=moments,pair"]
    subprocess.run(cmd3h, check=True, stdout=subprocess.DEVNULL)
    h5 = granule.read_snapshots(tmp3 + "-h5")
    check(len(h5) == len(granule.read_snapshots(tmp3)) and h5[-1]["dim"] == 3 and
          all(np.array_equal(h5[-1][k], last3[k]) for k in ("x", "y", "z", "vx", "vy", "vz")),
          "3D: read_snapshots of trajectory.h5 gives the XYZ's frames with z and vz")
    # a 3D LAMMPS dump of the same frames (id x y z vx vy vz) read back with dim=3
    with open(tmp3 + "-dump.lammpstrj", "w") as f:
        for k, fr in enumerate(granule.read_snapshots(tmp3)):
            f.write("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n216\nITEM: BOX BOUNDS pp pp pp\n" % (200 * k))
            f.write(("0 %r\n" % fr["L"]) * 3 + "ITEM: ATOMS id x y z vx vy vz\n")
            for i in range(216):
                f.write("%d %s\n" % (i + 1, " ".join(repr(float(fr[c][i])) for c in ("x", "y", "z", "vx", "vy", "vz"))))
    dumped = granule.read_lammps_dump(tmp3 + "-dump.lammpstrj", 1e-6, dim=3)
    check(len(dumped) == len(h5) and dumped[-1]["dim"] == 3 and
          all(np.array_equal(dumped[-1][k], last3[k]) for k in ("x", "y", "z", "vx", "vy", "vz")),
          "3D: read_lammps_dump(path, dt, dim=3) gives the frames with z and vz")
    os.remove(tmp3 + "-dump.lammpstrj")
    run3 = granule.read_run(tmp3 + "-h5")
    check(run3["trajectory"][0] == "h5md" and "pair" in run3["tables"] and "pair" in run3["summary"]["analysis"],
          "3D: read_run of an h5md run lists its trajectory and the pair table")
    shutil.rmtree(tmp3 + "-h5")

# species (docs/mixtures.md): radii, masses and species as views; read_snapshots gives them back
mix = os.path.join(src, "docs", "scenes", "bidisperse-mixture.ini")
with tempfile.TemporaryDirectory() as tmpm:
    setsm = {"system.N": 100, "run.warmup": 0.0, "run.duration": 2e-3, "run.sample_every": 1e-3,
             "output.snapshot_every": 2e-3, "output.plots": False}
    cmdm = [exe, "run", mix, "--out", tmpm, "--force"]
    cmdm += sum((["--set", f"{k}={granule._ini_value(v)}"] for k, v in setsm.items()), [])
    subprocess.run(cmdm, check=True, stdout=subprocess.DEVNULL)
    lastm = granule.read_snapshots(tmpm)[-1]
    simm = granule.Sim(granule.load_scene(mix, set=setsm))
    check(simm.species is not None and sorted(set(simm.species)) == [0, 1] and (simm.species == 0).sum() == 50
          and np.array_equal(simm.masses, np.where(simm.species == 0, 3.53e-5, 1.412e-4))
          and np.all(simm.radii == 1.5e-3), "species: Sim.species, masses, radii are the scene's")
    simm.step(lastm["step"])
    check(np.array_equal(lastm["species"], simm.species + 1) and np.array_equal(lastm["masses"], simm.masses)
          and np.array_equal(lastm["vx"], simm.vx),
          "species: read_snapshots gives species (1-based), masses and velocities of a Sim stepped from Python")
    check(abs((simm.masses * simm.vx).sum()) < 1e-15, "species: the symmetrised noise keeps the momentum sum m_i v_i at 0")
    stm = simm.state()
    simm.step(50)
    simm2 = granule.Sim(granule.load_scene(mix, set=setsm))
    simm2.restore(stm)
    simm2.step(50)
    check(np.array_equal(simm.vx, simm2.vx) and np.array_equal(simm.x, simm2.x),
          "species: state() / restore() continues a mixture bit for bit")
check(granule.Sim(granule.load_scene(os.path.join(src, "docs", "scenes", "rfm-1d.ini"))).species is None,
      "species: None for one species")

finish()
