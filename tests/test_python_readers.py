"""granule's Python readers on every folder and trajectory format granule writes (docs/python.md,
docs/trajectories.md), with Debian's /usr/bin/python3, ASE, MDAnalysis and h5py:
  - read_snapshots returns every frame of every trajectory format (per-frame snapshots,
    snapshots/trajectory.xyz, trajectory.h5), counted independently in the files themselves (the
    Properties= lines of the XYZ text, the H5MD datasets' extent), in 2D and 1D, equal across formats;
  - read_run reads a run (with granule analyse's output), a compare, a sweep, a reproduce result set,
    a reproduce campaign folder, cost and a theory command's folder, each table and JSON complete;
  - read_ase gives every frame of a run in any format as ase.Atoms (cell, pbc, velocities, masses);
  - mdanalysis_universe opens trajectory.h5 in one call with the box of every frame;
  - 3D: both on a cube (pbc T T T, box L L L, z and vz).

    test_python_readers.py GRANULE_EXE SOURCE_DIR    (PYTHONPATH=build/python)
"""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import warnings

import numpy as np

import granule
from checks import check, finish

warnings.simplefilter("ignore")
for module, package in (("ase", "python3-ase"), ("MDAnalysis", "python3-mdanalysis"), ("h5py", "python3-h5py")):
    try:
        __import__(module)
    except ImportError:
        print(f"skipped: {sys.executable} cannot import {module} (apt-get install {package})")
        sys.exit(77)
import h5py  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
scene = os.path.join(src, "docs", "scenes", "rfm-2d.ini")


def granule_cmd(*args):
    subprocess.run([exe, *args], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def sets(d):
    return sum((["--set", f"{k}={v}"] for k, v in d.items()), [])


small2d = {"system.N": 300, "system.L": 0.08, "run.warmup": 0.004, "run.duration": 0.03, "run.sample_every": 0.002,
           "output.snapshot_every": 0.002, "output.plots": "false"}
small1d = {"system.dim": 1, "system.N": 100, "system.L": 1, "placement.kind": "uniform", "model.tangential": "none",
           "run.warmup": 0, "run.duration": 0.01, "run.sample_every": 0.001, "output.snapshot_every": 0.001,
           "output.plots": "false"}


def xyz_frames_in(paths):
    """Frames and their Time= values counted in the text itself: one Properties= line per frame."""
    times = []
    for p in paths:
        with open(p) as f:
            times += [float(m.group(1)) for line in f if "Properties=" in line for m in [re.search(r"Time=(\S+)", line)]]
    return times


def frames_in(folder):
    """(format, frame times) counted in the files the run folder holds, without granule's readers."""
    if os.path.exists(os.path.join(folder, "trajectory.h5")):
        with h5py.File(os.path.join(folder, "trajectory.h5"), "r") as f:
            pos = f["particles/all/position"]
            assert pos["value"].shape[0] == pos["time"].shape[0]
            return "h5md", list(pos["time"][()])
    xyz = os.path.join(folder, "snapshots", "trajectory.xyz")
    if os.path.exists(xyz):
        return "xyz", xyz_frames_in([xyz])
    return "snapshots", xyz_frames_in(sorted(glob.glob(os.path.join(folder, "snapshots", "snap_*.xyz"))))


with tempfile.TemporaryDirectory() as tmp:
    os.chdir(tmp)
    # 1. read_snapshots: every frame of every format, in 2D and 1D
    runs = {}
    for dim, base in ((2, small2d), (1, small1d)):
        for fmt in ("snapshots", "xyz", "h5md"):
            d = f"{fmt}{dim}d"
            granule_cmd("run", scene, "--out", d, "--quiet", *sets({**base, "output.trajectory": fmt}))
            runs[(dim, fmt)] = d
    for (dim, fmt), d in runs.items():
        kind, times = frames_in(d)
        frames = granule.read_snapshots(d)
        check(kind == fmt and len(times) > 10 and len(frames) == len(times),
              f"{dim}D {fmt}: read_snapshots gives {len(frames)} frames, the files hold {len(times)}")
        check([f["t"] for f in frames] == times, f"{dim}D {fmt}: the frames' times are the files' own, in order")
        check(all(f["dim"] == dim and f["x"].shape == (base["system.N"],) and (f["y"] is None) == (dim == 1)
                  for f in frames for base in [small2d if dim == 2 else small1d]), f"{dim}D {fmt}: dim and shapes")
        check(granule.trajectory_files(d)[0] == fmt, f"{dim}D {fmt}: trajectory_files names the format")
    for dim in (2, 1):
        ref = granule.read_snapshots(runs[(dim, "snapshots")])
        for fmt in ("xyz", "h5md"):
            got = granule.read_snapshots(runs[(dim, fmt)])
            same = len(ref) == len(got) and all(
                np.array_equal(a[k], b[k]) for a, b in zip(ref, got) for k in ("x", "vx", "y", "vy") if a[k] is not None)
            check(same and all(a["step"] == b["step"] for a, b in zip(ref, got)),
                  f"{dim}D: the {fmt} frames equal the per-frame snapshots bit for bit (same seed)")
    xyz2 = os.path.join(runs[(2, "xyz")], "snapshots", "trajectory.xyz")
    check(len(granule.read_snapshots(xyz2)) == len(xyz_frames_in([xyz2])), "read_snapshots of the trajectory.xyz file itself")
    h5 = os.path.join(runs[(2, "h5md")], "trajectory.h5")
    check(len(granule.read_snapshots(h5)) == frames_in(runs[(2, "h5md")])[1].__len__(), "read_snapshots of the trajectory.h5 file itself")
    try:
        granule.read_snapshot(xyz2)
        check(False, "read_snapshot of a multi-frame file refuses instead of returning its first frame")
    except ValueError as e:
        check("read_snapshots" in str(e), f"read_snapshot of a multi-frame file refuses: {e}")
    granule_cmd("run", scene, "--out", "noframes", "--quiet", *sets({**small2d, "output.snapshot_every": 0}))
    check(granule.read_snapshots("noframes") == [], "a run without frames gives []")
    try:
        granule.read_snapshots(tmp)
        check(False, "read_snapshots of a folder that is not a run raises")
    except FileNotFoundError as e:
        check("not a run folder" in str(e), f"read_snapshots of a folder that is not a run raises: {e}")

    # 2. read_run: every folder kind, with every table and its JSON
    def tables_complete(r, folder):
        """Every CSV of the folder is a table, with as many rows as the file has lines after its header."""
        names = sorted(os.path.basename(p)[:-4] for p in glob.glob(os.path.join(folder, "*.csv")))
        rows = {n: sum(1 for line in open(os.path.join(folder, n + ".csv")) if not line.startswith("#")) - 1 for n in names}
        return sorted(r["tables"]) == names and all(len(r["tables"][n]) == rows[n] for n in names) and sum(rows.values()) > 0

    run = runs[(2, "snapshots")]
    granule_cmd("analyse", run, "--set", "analysis.observables=pv,moments")
    r = granule.read_run(run)
    check(r["kind"] == "run" and r["summary"] == json.load(open(f"{run}/summary.json")) and tables_complete(r, run)
          and r["point"] is None and r["trajectory"][0] == "snapshots", "read_run of a run folder")
    check(r["analysis"] is not None and "pv" in r["analysis"]["tables"] and tables_complete(r["analysis"], f"{run}/analysis")
          and "moments" in r["analysis"]["summary"]["analysis"], "read_run includes granule analyse's output (DIR/analysis)")
    check(r["meta"]["temperature"]["file"] == "temperature.csv", "read_run reads the tables' meta.json notes")

    granule_cmd("compare", scene, "--models", "spring_dashpot+tangential_dashpot,spring_dashpot", "--out", "cmp",
                *sets({**small2d, "analysis.observables": "pv"}))
    r = granule.read_run("cmp")
    models = sorted(os.path.basename(os.path.dirname(p)) for p in glob.glob("cmp/*/summary.json"))
    check(r["kind"] == "compare" and r["summary"] == json.load(open("cmp/compare.json")) and tables_complete(r, "cmp")
          and len(r["tables"]["compare"]) == 2, "read_run of a compare folder: compare.json, compare.csv, pv_collapse.csv")
    check(sorted(r["runs"]) == models == ["spring_dashpot", "spring_dashpot_tangential_dashpot"]
          and all(tables_complete(r["runs"][m], f"cmp/{m}") and r["runs"][m]["summary"]["T_mean"] > 0 for m in models),
          f"read_run of a compare folder: each model's run ({', '.join(models)})")

    with open("sw.ini", "w") as f:
        f.write(f"[sweep]\nscene = {scene}\nout = sweep\n[vary]\nsystem.N = 100, 200, 300\n[set]\nsystem.L = 0.08\n"
                "run.warmup = 0.002\nrun.duration = 0.004\nrun.sample_every = 0.002\noutput.plots = false\n"
                "analysis.observables = moments\n")
    granule_cmd("sweep", "sw.ini")
    r = granule.read_run("sweep")
    points = sorted(glob.glob("sweep/p[0-9]*"))
    check(r["kind"] == "sweep" and tables_complete(r, "sweep") and len(r["tables"]["sweep"]) == len(points) == 3,
          "read_run of a sweep folder: sweep.csv")
    check([p["point"]["keys"]["system.N"] for p in r["points"]] == ["100", "200", "300"]
          and all(p["summary"]["status"] == "completed" and "moments" in p["tables"] for p in r["points"]),
          "read_run of a sweep folder: every point with its point.json, summary and tables")
    os.remove("sweep/p0002/summary.json")  # a point not finished: kept, with its manifest
    r = granule.read_run("sweep")
    check(len(r["points"]) == 3 and r["points"][2]["summary"] is None and r["points"][2]["point"]["point"] == 2,
          "read_run of a sweep keeps a point without summary.json (its point.json)")

    committed = os.path.join(src, "docs", "results", "ch2-placement")
    r = granule.read_run(committed)
    archived = sorted(glob.glob(os.path.join(committed, "points", "p*.json")))
    check(r["kind"] == "results" and r["summary"] == json.load(open(os.path.join(committed, "results.json")))
          and tables_complete(r, committed) and {"results", "fig2.10_data"} <= set(r["tables"]),
          "read_run of a reproduce result set: results.json, results.csv, fig2.10_data.csv")
    check(len(r["points"]) == len(archived) == 6 and all("summary" in p and "point" in p for p in r["points"]),
          f"read_run of a reproduce result set: its {len(archived)} archived points")
    # a campaign folder OUT/NAME/FIDELITY: the committed result set restored with --collect (runs nothing)
    shutil.copytree(committed, "rp/ch2-placement/full/results")
    granule_cmd("reproduce", "ch2-placement", "--fidelity", "full", "--collect", "--out", "rp")
    r = granule.read_run("rp/ch2-placement/full")
    check(r["kind"] == "campaign" and r["runs"]["kind"] == "sweep" and len(r["runs"]["points"]) == 6
          and r["results"]["kind"] == "results" and r["summary"]["campaign"] == "ch2-placement",
          "read_run of a reproduce campaign folder: runs/ (a sweep of 6 points) and results/")

    granule_cmd("cost", scene, "--calibrate", "0.2", "--set", "system.N=100", "--out", "cost")
    r = granule.read_run("cost")
    check(r["kind"] == "cost" and r["summary"] == json.load(open("cost/cost.json")), "read_run of a cost folder (cost.json)")
    granule_cmd("bisect", "--out", "bisect", "--levels", "6", "--repetitions", "10")
    r = granule.read_run("bisect")
    check(r["kind"] == "run" and r["summary"]["command"] == "bisect" and tables_complete(r, "bisect"),
          "read_run of a theory command's folder (bisect)")
    try:
        granule.read_run(os.path.join(src, "docs"))
        check(False, "read_run of a folder granule did not write raises")
    except ValueError as e:
        check("not a folder granule wrote" in str(e), f"read_run of a folder granule did not write raises: {e}")

    # 3. ASE: one call reads every frame of a run, whatever its format
    import ase.io
    for dim in (2, 1):
        base = small2d if dim == 2 else small1d
        L, d = float(base["system.L"]), 2 * 1.5e-3
        ref = granule.read_snapshots(runs[(dim, "snapshots")])
        for fmt in ("snapshots", "xyz", "h5md"):
            atoms = granule.read_ase(runs[(dim, fmt)])
            n = len(frames_in(runs[(dim, fmt)])[1])
            check(len(atoms) == n and all(a.info["Time"] == f["t"] for a, f in zip(atoms, ref)),
                  f"{dim}D {fmt}: read_ase gives all {n} frames with their times")
            want_cell = [L, L, d] if dim == 2 else [L, d, d]
            ok = all(np.allclose(a.cell.lengths(), want_cell) and list(a.pbc) == [True, dim == 2, False]
                     and np.array_equal(a.positions[:, 0], f["x"]) and np.array_equal(a.arrays["velo"][:, 0], f["vx"])
                     and np.allclose(a.get_velocities(), a.arrays["velo"], rtol=1e-15, atol=0)
                     and np.all(a.get_velocities()[:, dim:] == 0) and np.allclose(a.get_masses(), 3.53e-5, rtol=1e-15)
                     and np.allclose(a.arrays["radius"], 1.5e-3) for a, f in zip(atoms, ref))
            check(ok, f"{dim}D {fmt}: cell {want_cell}, pbc, positions, velocities (velo, and get_velocities() "
                  "= momenta / masses within 1e-15), masses and radii of every frame")
    a = granule.read_ase(runs[(2, "h5md")])[-1]
    b = ase.io.read(xyz2, index=-1)
    check(np.array_equal(a.positions, b.positions) and np.array_equal(a.get_velocities(), b.get_velocities())
          and np.array_equal(a.cell[:], b.cell[:]) and a.info["Step"] == b.info["Step"],
          "read_ase of trajectory.h5 gives the Atoms ase.io.read gives for the same run's trajectory.xyz")

    # 4. MDAnalysis: one call on the H5MD file, the box of every frame set
    for dim in (2, 1):
        base = small2d if dim == 2 else small1d
        L, d = float(base["system.L"]), 2 * 1.5e-3
        u = granule.mdanalysis_universe(runs[(dim, "h5md")])
        ref = granule.read_ase(runs[(dim, "xyz")])
        box = [L, L, d, 90, 90, 90] if dim == 2 else [L, d, d, 90, 90, 90]
        check(len(u.trajectory) == len(ref) and len(u.atoms) == base["system.N"], f"{dim}D: mdanalysis_universe has every frame and particle")
        ok = True
        for k, ts in enumerate(u.trajectory):
            ok &= bool(np.allclose(ts.dimensions, box) and abs(ts.time - ref[k].info["Time"]) < 1e-12
                       and ts.data["step"] == ref[k].info["Step"]
                       and np.array_equal(ts.positions, np.float32(ref[k].positions))
                       and np.allclose(ts.velocities, ref[k].get_velocities(), rtol=1e-6, atol=1e-9))
        check(ok, f"{dim}D: every frame's box {box}, time, step, positions and velocities (SI) equal the XYZ's")
        check(np.allclose(u.atoms.masses, 3.53e-5) and np.allclose(u.atoms.radii, 1.5e-3), f"{dim}D: masses and radii")
    # 5. 3D (spheres, docs/three-dimensions.md): read_ase and mdanalysis_universe on a cube
    scene3 = os.path.join(src, "docs", "scenes", "rfm-3d.ini")
    small3d = {"system.N": 200, "run.warmup": 0.002, "run.duration": 0.006, "run.sample_every": 0.002,
               "output.snapshot_every": 0.002, "output.plots": "false"}
    for fmt in ("xyz", "h5md"):
        granule_cmd("run", scene3, "--out", f"{fmt}3d", "--quiet", *sets({**small3d, "output.trajectory": fmt}))
    L3 = json.load(open("xyz3d/summary.json"))["scene"]["system"]["L"]
    a3, h3 = granule.read_ase("xyz3d"), granule.read_ase("h5md3d")
    check(len(a3) == len(h3) == 5 and all(list(a.pbc) == [True] * 3 and np.allclose(a.cell.lengths(), [L3] * 3)
                                          and np.array_equal(a.positions, b.positions)
                                          and np.array_equal(a.get_velocities(), b.get_velocities())
                                          and np.all(np.abs(a.get_velocities()).max(axis=0) > 0)
                                          for a, b in zip(a3, h3)),
          "3D: read_ase of trajectory.xyz and trajectory.h5 give the same Atoms: the cube, pbc T T T, z and vz")
    u3 = granule.mdanalysis_universe("h5md3d")
    check(len(u3.trajectory) == 5 and all(np.allclose(ts.dimensions, [L3, L3, L3, 90, 90, 90])
                                          and np.array_equal(ts.positions, np.float32(a3[k].positions))
                                          for k, ts in enumerate(u3.trajectory)),
          "3D: mdanalysis_universe has the cube's box and the XYZ's positions in every frame")
    # 3D with rotation: read_snapshots gives the spin vectors' components wx, wy, wz from either
    # format (ASE's omega array, columns 0, 1, 2), omega None; without rotation all None
    spin = {"model.rotation": "true", "placement.omega0": 200, "model.tangential": "tangential_spring",
            "model.mu": 0.5}
    for fmt in ("xyz", "h5md"):
        granule_cmd("run", scene3, "--out", f"{fmt}3dr", "--quiet",
                    *sets({**small3d, **spin, "output.trajectory": fmt}))
    ar, fx, fh = granule.read_ase("xyz3dr"), granule.read_snapshots("xyz3dr"), granule.read_snapshots("h5md3dr")
    check(len(ar) == len(fx) == len(fh) == 5
          and all(all(np.array_equal(f[c], a.arrays["omega"][:, k]) for k, c in enumerate(("wx", "wy", "wz")))
                  and f["omega"] is None for a, f in zip(ar + ar, fx + fh))
          and all(np.abs(f[c]).max() > 0 for f in fx for c in ("wx", "wy", "wz")),
          "3D with rotation: read_snapshots of trajectory.xyz and trajectory.h5 give wx, wy, wz (ASE's omega)")
    plain = granule.read_snapshots("xyz3d") + granule.read_snapshots("h5md3d")
    check(all(f["wx"] is None and f["wy"] is None and f["wz"] is None and f["omega"] is None for f in plain),
          "3D without rotation: read_snapshots gives wx, wy, wz and omega None")
    try:
        granule.mdanalysis_universe(runs[(2, "xyz")])
        check(False, "mdanalysis_universe of a run without trajectory.h5 says what to do")
    except ValueError as e:
        check("output.trajectory = h5md" in str(e), f"mdanalysis_universe of a run without trajectory.h5 says what to do: {e}")
    # 6. a mixture (docs/mixtures.md): trajectory.h5 carries H5MD's species (1, 2, ...), each grain's
    # mass and radius; every reader gives what the XYZ trajectory of the same run gives; in 2D and
    # in 3D (spheres: z and vz too; masses 3.53e-5 and 1.412e-4 kg given, radii 1 and 2 mm)
    small_mix = {"system.N": 200, "species.radius": "1e-3, 2e-3", "run.warmup": 0, "run.duration": 0.006,
                 "run.sample_every": 0.002, "output.snapshot_every": 0.002, "output.plots": "false"}
    for mixname, scene_file in (("mix", "bidisperse-mixture.ini"), ("mix3", "bidisperse-mixture-3d.ini")):
        mix = os.path.join(src, "docs", "scenes", scene_file)
        label = "mixture" if mixname == "mix" else "3D mixture"
        for fmt in ("xyz", "h5md"):
            granule_cmd("run", mix, "--out", f"{mixname}-{fmt}", "--quiet",
                        *sets({**small_mix, "output.trajectory": fmt}))
        with h5py.File(f"{mixname}-h5md/trajectory.h5", "r") as f:
            part = f["particles/all"]
            sp, m, r = part["species"][()], part["mass"][()], part["radius"][()]
            nsp = int(f["parameters/granule"].attrs["n_species"])
            dim = int(f["parameters/granule"].attrs["dim"])
        want_m, want_r = np.where(sp == 1, 3.53e-5, 1.412e-4), np.where(sp == 1, 1e-3, 2e-3)
        check(sorted(set(sp.tolist())) == [1, 2] and (sp == 1).sum() == 100 and nsp == 2
              and dim == (2 if mixname == "mix" else 3)
              and np.array_equal(m, want_m) and np.array_equal(r, want_r),
              f"{label}: trajectory.h5 has /particles/all/species 1, 2 (100 each), each grain's mass and radius")
        fx, fh = granule.read_snapshots(f"{mixname}-xyz"), granule.read_snapshots(f"{mixname}-h5md")
        cols = ("species", "radii", "masses", "x", "vx") + (("z", "vz") if dim == 3 else ())
        check(len(fx) == len(fh) == 4 and all(np.array_equal(a[k], b[k]) for a, b in zip(fx, fh)
                                              for k in cols),
              f"{label}: read_snapshots of trajectory.h5 gives the XYZ's species, radii and masses")
        ax, ah = granule.read_ase(f"{mixname}-xyz"), granule.read_ase(f"{mixname}-h5md")
        check(all(np.array_equal(a.arrays["species_index"], b.arrays["species_index"])
                  and np.array_equal(a.get_masses(), b.get_masses()) and np.array_equal(a.arrays["radius"], b.arrays["radius"])
                  for a, b in zip(ax, ah)), f"{label}: read_ase of trajectory.h5: species_index, masses, radii as the XYZ's")
        um = granule.mdanalysis_universe(f"{mixname}-h5md")
        check(list(um.atoms.types) == [str(v) for v in sp] and np.array_equal(um.atoms.masses, m)
              and np.array_equal(um.atoms.radii, r), f"{label}: mdanalysis_universe types are the species, masses and radii each grain's")
        granule_cmd("analyse", f"{mixname}-h5md", "--out", f"{mixname}-h5md-an")
        rows = [ln.split(",") for ln in open(f"{mixname}-h5md-an/species.csv") if ln[0].isdigit()]
        check([(int(w[1]), float(w[2])) for w in rows] == [(100, 1e-3), (100, 2e-3)],
              f"{label}: granule analyse reads the species back from trajectory.h5 (species.csv)")

finish()
