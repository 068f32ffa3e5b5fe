"""Folders granule writes into numpy/pandas: every folder kind (read_run: run, compare, sweep,
reproduce result sets and campaign folders, cost, theory commands) with its JSON and CSV tables,
and every frame of every trajectory format (read_snapshots: per-frame extended-XYZ snapshots, the
multi-frame trajectory.xyz, trajectory.h5) and LAMMPS text dumps. Pure Python: it reads files."""
import glob
import io
import json
import os

import numpy as np


def read_csv(path):
    """A granule CSV as a pandas DataFrame (numpy structured array without pandas). Lines starting
    with '#' are metadata and skipped, wherever they are."""
    with open(path) as f:
        text = "".join(line for line in f if not line.startswith("#"))
    try:
        import pandas
    except ImportError:
        return np.genfromtxt(io.StringIO(text), delimiter=",", names=True, dtype=None, encoding="utf-8")
    return pandas.read_csv(io.StringIO(text))


def _xyz_header(head):
    """The key=value pairs of an extended-XYZ comment line (quoted values unquoted)."""
    out, i = {}, 0
    while i < len(head):
        eq = head.find("=", i)
        if eq < 0:
            break
        key = head[i:eq].strip()
        if head[eq + 1:eq + 2] == '"':
            close = head.index('"', eq + 2)
            out[key], i = head[eq + 2:close], close + 1
        else:
            stop = head.find(" ", eq + 1)
            stop = len(head) if stop < 0 else stop
            out[key], i = head[eq + 1:stop], stop + 1
    return out


def _xyz_frame(head, rows, where):
    """One extended-XYZ frame (its comment line and particle lines) as a frame dict."""
    h = _xyz_header(head)
    if "Properties" not in h:
        raise ValueError(f"{where}: not an extended-XYZ frame (no Properties= in its comment line)")
    props, col = {}, 0
    parts = h["Properties"].split(":")
    for name, _kind, width in zip(parts[0::3], parts[1::3], parts[2::3]):
        props[name] = (col, int(width))
        col += int(width)
    vel = props.get("velo", props.get("vel", props.get("velocities")))
    if "pos" not in props or vel is None:
        raise ValueError(f"{where}: Properties name no pos and velo columns: {h['Properties']}")
    pbc = h.get("pbc", "T T F").split()
    dim = 1 if pbc[:2] == ["T", "F"] else 3 if pbc == ["T", "T", "T"] else 2
    lattice = [float(v) for v in h["Lattice"].split()] if "Lattice" in h else None
    a = np.array([r.split() for r in rows], dtype=object).reshape(len(rows), col)
    pos, vx = props["pos"][0], vel[0]
    num = lambda c: a[:, c].astype(np.float64)  # noqa: E731  (Python's float(): correctly rounded)
    frame = {"t": float(h.get("Time", 0.0)), "step": int(h["Step"]) if "Step" in h else None,
             "L": lattice[0] if lattice else None, "dim": dim, "x": num(pos), "vx": num(vx),
             "y": num(pos + 1) if dim >= 2 else None, "vy": num(vx + 1) if dim >= 2 else None,
             "omega": num(props["omega"][0] + 2) if "omega" in props and dim < 3 else None}
    if dim == 3:  # spheres (docs/three-dimensions.md): z and vz too, and the spin vectors
        frame["z"], frame["vz"] = num(pos + 2), num(vx + 2)
        w = props["omega"][0] if "omega" in props else None
        frame["wx"], frame["wy"], frame["wz"] = (num(w), num(w + 1), num(w + 2)) if w is not None else (None,) * 3
    # a mixture (docs/mixtures.md): each grain's species 1, 2, ..., radius and mass; None without
    sp = props.get("species_index")
    frame["species"] = a[:, sp[0]].astype(np.int64) if sp else None
    frame["radii"] = num(props["radius"][0]) if sp and "radius" in props else None
    frame["masses"] = num(props["masses"][0]) if sp and "masses" in props else None
    return frame


def _xyz_frames(path):
    """Every frame of an extended-XYZ file, in file order."""
    frames = []
    with open(path) as f:
        lines = f.read().splitlines()
    k = 0
    while k < len(lines):
        if not lines[k].strip():
            k += 1
            continue
        try:
            n = int(lines[k])
        except ValueError:
            raise ValueError(f"{path}:{k + 1}: expected the particle count of a frame, got {lines[k][:40]!r}") from None
        if k + 2 + n > len(lines):
            raise ValueError(f"{path}:{k + 1}: frame {len(frames)} announces {n} particles but the file ends "
                             f"after {len(lines) - k - 2}")
        frames.append(_xyz_frame(lines[k + 1], lines[k + 2:k + 2 + n], f"{path}:{k + 2}"))
        k += 2 + n
    return frames


def _h5py():
    try:
        import h5py
    except ImportError:
        raise ImportError("granule: reading trajectory.h5 (output.trajectory = h5md) needs h5py "
                          "(Debian python3-h5py; pip install h5py)", name="h5py") from None
    return h5py


def _h5md_frames(path):
    """Every frame of granule's H5MD file (docs/trajectories.md) as frame dicts."""
    with _h5py().File(path, "r") as f:
        par, part = f["parameters/granule"].attrs, f["particles/all"]
        dim, L = int(par["dim"]), float(par["L"])
        pos, vel = part["position/value"][()], part["velocity/value"][()]
        t, step = part["position/time"][()], part["position/step"][()]
        edges = part["box/edges/value"][()] if "edges" in part["box"] else None
        omega = part["angular_velocity/value"][()] if "angular_velocity" in part else None
        # a mixture (docs/mixtures.md): H5MD's species (1, 2, ...), each grain's radius and mass
        mix = "species" in part
        species = part["species"][()].astype(np.int64) if mix else None
        radii, masses = (part["radius"][()], part["mass"][()]) if mix else (None, None)
    frames = []
    for k in range(pos.shape[0]):
        frame = {"t": float(t[k]), "step": int(step[k]), "L": float(edges[k][0][0]) if edges is not None else L,
                 "species": species, "radii": radii, "masses": masses,
                 "dim": dim, "x": pos[k, :, 0], "vx": vel[k, :, 0],
                 "y": pos[k, :, 1] if dim >= 2 else None, "vy": vel[k, :, 1] if dim >= 2 else None,
                 "omega": omega[k, :, 2] if omega is not None and dim < 3 else None}
        if dim == 3:  # spheres (docs/three-dimensions.md): z and vz too, and the spin vectors
            frame["z"], frame["vz"] = pos[k, :, 2], vel[k, :, 2]
            w = omega[k] if omega is not None else None
            frame["wx"], frame["wy"], frame["wz"] = (w[:, 0], w[:, 1], w[:, 2]) if w is not None else (None,) * 3
        frames.append(frame)
    return frames


def trajectory_files(folder):
    """(format, paths) of the trajectory a run folder holds, chosen as `granule analyse` chooses:
    "h5md" (trajectory.h5), else "xyz" (snapshots/trajectory.xyz), else "snapshots"
    (snapshots/snap_*.xyz, in frame order); (None, []) when it holds none."""
    h5 = os.path.join(folder, "trajectory.h5")
    if os.path.exists(h5):
        return "h5md", [h5]
    xyz = os.path.join(folder, "snapshots", "trajectory.xyz")
    if os.path.exists(xyz):
        return "xyz", [xyz]
    snaps = sorted(glob.glob(os.path.join(folder, "snapshots", "snap_*.xyz")))
    return ("snapshots", snaps) if snaps else (None, [])


def read_snapshot(path):
    """The one frame of a per-frame snapshot file (snapshots/snap_NNNNNN.xyz): dict with t, step, L,
    dim and numpy arrays x, y, vx, vy (y, vy None in 1D; z, vz too in 3D) and omega (None without
    rotation, and in 3D, whose frames have the spin vectors' components wx, wy, wz instead, None
    without rotation) and, for a mixture, species (1, 2, ...), radii and masses (None without),
    whatever the column order, as long as the Properties line names pos and velo (or
    vel). A file holding several frames is refused (read_snapshots reads them all)."""
    frames = _xyz_frames(path)
    if len(frames) != 1:
        raise ValueError(f"{path} holds {len(frames)} frames, not one: read them with read_snapshots({path!r})")
    return frames[0]


def read_snapshots(path):
    """Every frame of a run's trajectory, in time order, as read_snapshot's dicts: a run folder
    (whichever format it holds: trajectory.h5, snapshots/trajectory.xyz or the per-frame
    snapshots/snap_*.xyz, every frame of every file), or one trajectory file (.h5 or extended XYZ).
    A run folder written with output.snapshot_every = 0 gives []; a folder that is not a run
    folder raises FileNotFoundError."""
    path = os.fspath(path)
    if os.path.isfile(path):
        return _h5md_frames(path) if path.endswith((".h5", ".h5md")) else _xyz_frames(path)
    fmt, files = trajectory_files(path)
    if fmt is None:
        if os.path.exists(os.path.join(path, "summary.json")):
            return []
        raise FileNotFoundError(f"{path}: no trajectory (trajectory.h5, snapshots/trajectory.xyz or "
                                "snapshots/snap_*.xyz) and no summary.json: not a run folder")
    if fmt == "h5md":
        return _h5md_frames(files[0])
    return [frame for p in files for frame in _xyz_frames(p)]


def read_lammps_dump(path, dt=1.0, dim=None):
    """Frames of a LAMMPS text dump (dump custom ... id x y vx vy): dicts as read_snapshot gives,
    atoms in id order, t = timestep * dt (the scene's integrator.dt). dim=3 (a 3D scene) reads z
    and vz too (dump custom ... id x y z vx vy vz); otherwise the columns say 1D or 2D (a LAMMPS 2D
    run writes z and vz as well, so they alone do not make a frame 3D)."""
    frames = []
    with open(path) as f:
        while f.readline().startswith("ITEM: TIMESTEP"):
            step = int(f.readline())
            f.readline()
            n = int(f.readline())
            f.readline()
            lo, hi = zip(*[map(float, f.readline().split()[:2]) for _ in range(3)])
            cols = f.readline().split()[2:]
            a = np.loadtxt(f, max_rows=n, ndmin=2)
            a = a[np.argsort(a[:, cols.index("id")])]
            c = {name: a[:, k] for k, name in enumerate(cols)}
            L = hi[0] - lo[0]
            frame = {"t": step * dt, "L": L, "dim": 3 if dim == 3 else 2 if "y" in c else 1,
                     "x": np.mod(c["x"] - lo[0], L), "vx": c["vx"],
                     "y": np.mod(c["y"] - lo[1], L) if "y" in c else None, "vy": c.get("vy")}
            if dim == 3:
                frame["z"], frame["vz"] = np.mod(c["z"] - lo[2], L), c["vz"]
            frames.append(frame)
    return frames


def _json(path):
    with open(path) as f:
        return json.load(f)


def _tables(folder):
    """Every CSV of a folder (not its subfolders) as {name: table}, and the NAME.meta.json beside them."""
    tables = {os.path.basename(p)[:-4]: read_csv(p) for p in sorted(glob.glob(os.path.join(folder, "*.csv")))}
    meta = {os.path.basename(p)[:-10]: _json(p) for p in sorted(glob.glob(os.path.join(folder, "*.meta.json")))}
    return tables, meta


def _subfolders(folder, pattern):
    return sorted(p for p in glob.glob(os.path.join(folder, pattern)) if os.path.isdir(p))


def folder_kind(folder):
    """Which kind of folder granule wrote: "compare" (compare.json), "sweep" (sweep.csv or pNNNN/
    point folders), "results" (a reproduce result set: results.json), "campaign" (a reproduce
    folder OUT/NAME/FIDELITY: runs/ and sweep.ini), "cost" (cost.json), "run" (summary.json: a run,
    a sweep point (also one not finished: point.json only), `granule analyse`'s output and the theory
    commands' folders); None otherwise."""
    has = lambda name: os.path.exists(os.path.join(folder, name))  # noqa: E731
    if has("compare.json"):
        return "compare"
    if has("results.json"):
        return "results"
    if has("runs") and has("sweep.ini"):
        return "campaign"
    if has("sweep.csv") or (not has("summary.json") and _subfolders(folder, "p[0-9][0-9][0-9][0-9]")):
        return "sweep"
    if has("summary.json") or has("point.json"):
        return "run"
    if has("cost.json"):
        return "cost"
    return None


def read_run(folder):
    """Any folder granule writes, as a dict with at least "kind" (folder_kind), "folder",
    "summary" (its main JSON as a dict, None where it has none), "tables" ({name: DataFrame} of
    every CSV in it) and "meta" ({name: dict} of the NAME.meta.json notes beside the CSVs); then
    per kind:
      run       summary.json (None for a sweep point not finished); "point" (a sweep point's point.json) or None; "analysis" (the folder
                `granule analyse DIR` wrote into DIR/analysis) or None; "trajectory" (format, files:
                read them with read_snapshots(folder))
      compare   compare.json as summary; tables compare, pv_collapse; "runs" {model folder: read_run}
      sweep     summary None; tables sweep, exponents; "points" [read_run of every pNNNN/, in order,
                finished or not: see each one's "point"["status"]]
      results   results.json as summary; tables results and every ID_data; "points" [the archived
                points/pNNNN.json: {"point": manifest, "summary": ..., "series": ...}]
      campaign  "runs" (read_run of runs/, a sweep), "results" (read_run of results/, or None before
                the campaign is analysed); summary = the results' summary or None
      cost      cost.json as summary"""
    folder = os.fspath(folder)
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"{folder}: no such folder")
    kind = folder_kind(folder)
    if kind is None:
        raise ValueError(f"{folder}: not a folder granule wrote (no summary.json, compare.json, sweep.csv, "
                         "pNNNN/ points, results.json, runs/ with sweep.ini or cost.json)")
    join = lambda name: os.path.join(folder, name)  # noqa: E731
    tables, meta = _tables(folder)
    out = {"kind": kind, "folder": folder, "summary": None, "tables": tables, "meta": meta}
    if kind == "run":
        out["summary"] = _json(join("summary.json")) if os.path.exists(join("summary.json")) else None
        out["point"] = _json(join("point.json")) if os.path.exists(join("point.json")) else None
        has_analysis = os.path.exists(os.path.join(folder, "analysis", "summary.json"))
        out["analysis"] = read_run(join("analysis")) if has_analysis else None
        out["trajectory"] = trajectory_files(folder)
    elif kind == "compare":
        out["summary"] = _json(join("compare.json"))
        out["runs"] = {os.path.basename(p): read_run(p) for p in _subfolders(folder, "*") if folder_kind(p) == "run"}
    elif kind == "sweep":
        out["points"] = [read_run(p) for p in _subfolders(folder, "p[0-9][0-9][0-9][0-9]*") if folder_kind(p) == "run"]
    elif kind == "results":
        out["summary"] = _json(join("results.json"))
        out["points"] = [_json(p) for p in sorted(glob.glob(join(os.path.join("points", "p*.json"))))]
    elif kind == "campaign":
        out["runs"] = read_run(join("runs")) if folder_kind(join("runs")) else None
        out["results"] = read_run(join("results")) if os.path.exists(join("results/results.json")) else None
        out["summary"] = out["results"]["summary"] if out["results"] else None
    else:
        out["summary"] = _json(join("cost.json"))
    return out
