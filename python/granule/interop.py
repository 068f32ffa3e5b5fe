"""A run's trajectory in the tools granular physicists already use, one call each
(docs/trajectories.md): ASE (a list of Atoms for every frame, whichever format the run wrote) and
MDAnalysis (a Universe on trajectory.h5 with the box of every frame). Units stay SI (m, s, m/s, kg)."""
import os

import numpy as np

from .runfolder import _h5py, trajectory_files


def _need(module, debian):
    try:
        return __import__(module)
    except ImportError:
        raise ImportError(f"granule: this needs {module} (Debian {debian}; pip install {module})", name=module) from None


def _trajectory(path, what):
    """(format, files) of a run folder or a single trajectory file."""
    path = os.fspath(path)
    if os.path.isfile(path):
        return ("h5md" if path.endswith((".h5", ".h5md")) else "xyz"), [path]
    fmt, files = trajectory_files(path)
    if fmt is None and not os.path.exists(os.path.join(path, "summary.json")):
        raise FileNotFoundError(f"{what}: {path} is neither a trajectory file nor a run folder")
    return fmt, files


def _h5md_atoms(path):
    """ase.Atoms for every frame of granule's H5MD file, as ASE's extxyz reader gives them for the
    XYZ formats: species X, positions, cell, pbc, masses, velocities (momenta = m v), radius, velo,
    omega (with rotation), info Time and Step."""
    ase = _need("ase", "python3-ase")
    with _h5py().File(path, "r") as f:
        part, par = f["particles/all"], f["parameters/granule"].attrs
        pos, vel = part["position/value"][()], part["velocity/value"][()]
        t, step = part["position/time"][()], part["position/step"][()]
        edges, mass = part["box/edges/value"][()], part["mass"][()]
        omega = part["angular_velocity/value"][()] if "angular_velocity" in part else None
        boundary = [b.decode() if isinstance(b, bytes) else str(b) for b in part["box"].attrs["boundary"]]
        radius = float(par["radius"])
        # a mixture (docs/mixtures.md): each grain's radius and H5MD's species (1, 2, ...)
        radii = part["radius"][()] if "radius" in part else np.full(pos.shape[1], radius)
        species = part["species"][()] if "species" in part else None
    pbc = [b == "periodic" for b in boundary]
    frames = []
    for k in range(pos.shape[0]):
        a = ase.Atoms(["X"] * pos.shape[1], positions=pos[k], cell=edges[k], pbc=pbc, masses=mass)
        a.set_velocities(vel[k])
        a.arrays["velo"] = vel[k].copy()
        a.arrays["radius"] = radii.copy()
        if species is not None:
            a.arrays["species_index"] = species.copy()
        if omega is not None:
            a.arrays["omega"] = omega[k].copy()
        a.info.update({"Time": float(t[k]), "Step": int(step[k])})
        frames.append(a)
    return frames


def read_ase(path):
    """Every frame of a run as a list of ase.Atoms, in time order: a run folder (whichever
    trajectory it holds: the per-frame snapshots/snap_*.xyz, snapshots/trajectory.xyz or
    trajectory.h5) or one trajectory file. Each Atoms has the cell (L x L x d in 2D, L x d x d in
    1D, d the diameter) and pbc of the run, masses, get_velocities() in m/s, arrays radius and velo
    (and omega with rotation), info Time (s) and Step. A run without frames gives []."""
    _need("ase", "python3-ase")
    import ase.io
    fmt, files = _trajectory(path, "read_ase")
    if fmt == "h5md":
        return _h5md_atoms(files[0])
    return [a for p in files for a in ase.io.read(p, index=":")]


def mdanalysis_universe(path, **kwargs):
    """An MDAnalysis Universe on a run's trajectory.h5 (the run folder or the file), in one call.
    MDAnalysis 2.4 cannot make a Universe from an H5MD file alone and knows no metre unit, so this
    builds the topology from the file
    (one atom per particle, name X and type X, or a mixture's species 1, 2, ..., masses in kg,
    radii in m) and loads the frames with
    the H5MD reader and convert_units=False: positions in m, velocities in m/s, ts.time in s,
    ts.data["step"], ts.dimensions the box of every frame ([L, L, d, 90, 90, 90] in 2D,
    [L, d, d, ...] in 1D). kwargs go to Universe.load_new. MDAnalysis keeps coordinates in float32."""
    mda = _need("MDAnalysis", "python3-mdanalysis")
    fmt, files = _trajectory(path, "mdanalysis_universe")
    if fmt != "h5md":
        raise ValueError(f"mdanalysis_universe: {os.fspath(path)} has no trajectory.h5: run with output.trajectory = h5md "
                         "(MDAnalysis's XYZ reader gets no box and no velocities; docs/trajectories.md)")
    with _h5py().File(files[0], "r") as f:
        n = f["particles/all/position/value"].shape[1]
        mass = f["particles/all/mass"][()]
        radius = float(f["parameters/granule"].attrs["radius"])
        # a mixture: each grain's radius, and its species (1, 2, ...) as the atom type
        radii = f["particles/all/radius"][()] if "radius" in f["particles/all"] else np.full(n, radius)
        types = [str(v) for v in f["particles/all/species"][()]] if "species" in f["particles/all"] else ["X"] * n
    u = mda.Universe.empty(n, n_residues=n, atom_resindex=np.arange(n), residue_segindex=np.zeros(n, dtype=int),
                           trajectory=False)
    u.add_TopologyAttr("names", ["X"] * n)
    u.add_TopologyAttr("types", types)
    u.add_TopologyAttr("masses", mass)
    u.add_TopologyAttr("radii", radii)
    u.load_new(files[0], format="H5MD", convert_units=False, **kwargs)
    return u
