"""Run folders into numpy/pandas: summary.json, the CSV tables (commented header lines), the
extended-XYZ snapshots and LAMMPS text dumps. Pure Python: it reads files granule wrote."""
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


def read_snapshot(path):
    """One extended-XYZ frame: dict with t, L, dim and numpy arrays x, y, vx, vy (y, vy None in 1D),
    whatever the column order, as long as the Properties line names pos and velo (or vel)."""
    with open(path) as f:
        n = int(f.readline())
        head = f.readline()
        rows = [f.readline().split() for _ in range(n)]
    props, t, lattice, pbc = {}, 0.0, None, "T T F"
    for key in ("Properties=", "Time=", "Lattice=", "pbc="):
        i = head.find(key)
        if i < 0:
            continue
        rest = head[i + len(key):]
        val = rest[1:rest.index('"', 1)] if rest.startswith('"') else rest.split()[0]
        if key == "Properties=":
            parts, col = val.split(":"), 0
            for name, _kind, width in zip(parts[0::3], parts[1::3], parts[2::3]):
                props[name] = (col, int(width))
                col += int(width)
        elif key == "Time=":
            t = float(val)
        elif key == "Lattice=":
            lattice = [float(x) for x in val.split()]
        else:
            pbc = val
    dim = 1 if pbc.split()[:2] == ["T", "F"] else 2
    pos = props["pos"][0]
    vel = props.get("velo", props.get("vel", props.get("velocities")))[0]
    a = np.array([[float(v) for v in r[pos:pos + 3] + r[vel:vel + 3]] for r in rows]) if n else np.zeros((0, 6))
    frame = {"t": t, "L": lattice[0] if lattice else None, "dim": dim, "x": a[:, 0], "vx": a[:, 3]}
    frame.update({"y": a[:, 1], "vy": a[:, 4]} if dim == 2 else {"y": None, "vy": None})
    return frame


def read_snapshots(folder):
    """Every snapshot of a run folder (folder/snapshots/*.xyz), in time order."""
    return [read_snapshot(p) for p in sorted(glob.glob(os.path.join(folder, "snapshots", "*.xyz")))]


def read_lammps_dump(path, dt=1.0):
    """Frames of a LAMMPS text dump (dump custom ... id x y vx vy): dicts as read_snapshot gives,
    atoms in id order, t = timestep * dt (the scene's integrator.dt)."""
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
            frame = {"t": step * dt, "L": L, "dim": 2 if "y" in c else 1,
                     "x": np.mod(c["x"] - lo[0], L), "vx": c["vx"],
                     "y": np.mod(c["y"] - lo[1], L) if "y" in c else None, "vy": c.get("vy")}
            frames.append(frame)
    return frames


def read_run(folder):
    """A run folder: {"summary": dict from summary.json, "tables": {name: DataFrame} for every CSV,
    "folder": folder}. Snapshots are read on demand with read_snapshots(folder)."""
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    tables = {os.path.basename(p)[:-4]: read_csv(p) for p in sorted(glob.glob(os.path.join(folder, "*.csv")))}
    return {"summary": summary, "tables": tables, "folder": folder}
