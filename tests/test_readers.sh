#!/usr/bin/env bash
# Real readers on granule's real outputs, with Debian's /usr/bin/python3 (docs/trajectories.md):
#   ase   ASE 3.22 (python3-ase) reads a 2D and a 1D snapshot and the multi-frame trajectory.xyz:
#         species, positions, get_velocities(), masses, radii, cell and pbc; frame times; the spins
#         (omega) of a rotating run
#   h5md  MDAnalysis (python3-mdanalysis + python3-h5py) reads trajectory.h5: frames, times, box,
#         positions and velocities equal to the XYZ trajectory of the same run; granule analyse on
#         the H5MD file gives the in-run observables; kill -9 after a checkpoint leaves a file h5py
#         reads, and --resume ends with the same frames as an uninterrupted run (also trajectory.xyz)
#   csv   every CSV of a run (2D and 1D, every observable; a Langevin run's ledger with its drag
#         column), an analyse, a compare and a sweep
#         folder loads with plain pandas.read_csv(path) and numpy.genfromtxt(path, names=True,
#         delimiter=',', dtype=None, encoding='utf-8') with the same rows and columns; no cell
#         holds a '#'; NAME.meta.json gives every column a unit ("units"); pv_collapse.csv is a
#         long table; sweep.csv has no R1-R12 columns when no point has <R^m>
#   results  the committed result sets (docs/results): every CSV has NAME.meta.json whose units
#         name each of its columns in order (per-row forms naming columns of the table), no cell
#         holds a ',' or a '#' (a group label's ", " is written "; "), and it loads with pandas
#         and numpy.genfromtxt with the same rows and columns; `granule reproduce
#         --collect` of three committed sets (means, power laws with per-row powers, curves, spm)
#         writes every ID_data.meta.json again, equal to the committed ones, its CSVs without a
#         comma in a cell, and the figures' blocks with the groups as the campaign has them; a
#         data table read with its units as docs/python.md does
# Exit 77 (skipped) only when the part's Python package cannot be imported.
#   3d    ASE reads a 3D run's extended XYZ (with rotation its spin vectors, omega:R:3), MDAnalysis
#         and h5py its trajectory.h5 (box, frames, angular_velocity with rotation,
#         positions and velocities equal to the XYZ's)
# usage: tests/test_readers.sh path/to/granule SOURCE_DIR ase|h5md|csv|results|3d
set -euo pipefail
G=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$2
part=$3
PY=/usr/bin/python3
TMP=$(mktemp -d "${TMPDIR:-/tmp}/granule-test-readers-XXXXXX")
bg=0 # a background run to kill on exit
trap 'if ((bg)); then kill -9 $bg 2>/dev/null || true; fi; rm -rf "$TMP"' EXIT
export CI=1
cd "$TMP"
need() {
    if ! "$PY" -c "import $1" 2>/dev/null; then
        echo "skipped: $PY cannot import $1 (apt-get install $2)"
        exit 77
    fi
}
small2d=(--set system.N=300 --set system.L=0.08 --set run.warmup=0.004 --set run.duration=0.012
         --set run.sample_every=0.002 --set output.snapshot_every=0.002 --set output.plots=false --quiet)

case $part in
ase)
    need ase python3-ase
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out r2 "${small2d[@]}" --set output.trajectory=snapshots
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out x2 "${small2d[@]}" --set output.trajectory=xyz
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out r1 --set system.dim=1 --set system.N=100 --set system.L=1 \
        --set placement.kind=uniform --set model.tangential=none --set run.warmup=0 --set run.duration=0.004 --set run.sample_every=0.002 \
        --set output.snapshot_every=0.002 --set output.plots=false --quiet
    "$PY" - <<'EOF'
import glob, warnings
import numpy as np
import ase.io
warnings.simplefilter("ignore")
M, r = 3.53e-5, 1.5e-3
def check(path, L, dim):
    a = ase.io.read(path)
    assert set(a.get_chemical_symbols()) == {"X"}, a.get_chemical_symbols()[:3]
    assert np.allclose(a.get_masses(), M, rtol=1e-15), a.get_masses()[:3]
    v = a.get_velocities()
    assert np.allclose(v, a.arrays["velo"], rtol=1e-12, atol=1e-15), (v[:2], a.arrays["velo"][:2])
    assert np.abs(v[:, :dim]).max() > 0 and np.all(v[:, dim:] == 0)
    assert np.allclose(a.arrays["radius"], r)
    want = [L, L, 2 * r] if dim == 2 else [L, 2 * r, 2 * r]
    assert np.allclose(a.cell.lengths(), want), (a.cell.lengths(), want)
    assert list(a.pbc) == [True, dim == 2, False], a.pbc
    assert np.all(a.positions[:, 0] >= 0) and np.all(a.positions[:, 0] < L)
    return a
for p in sorted(glob.glob("r2/snapshots/snap_*.xyz")):
    check(p, 0.08, 2)
for p in sorted(glob.glob("r1/snapshots/snap_*.xyz")):
    check(p, 1.0, 1)
frames = ase.io.read("x2/snapshots/trajectory.xyz", index=":")
files = sorted(glob.glob("r2/snapshots/snap_*.xyz"))
assert len(frames) == len(files) == 9, (len(frames), len(files))
for k, (a, f) in enumerate(zip(frames, files)):
    b = ase.io.read(f)
    assert abs(a.info["Time"] - 0.002 * k) < 1e-12, a.info
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.get_velocities(), b.get_velocities())
print("ok ASE %s: 2D and 1D snapshots and a %d-frame trajectory.xyz" % (ase.__version__, len(frames)))
EOF
    # rotation: the spins are the extended-XYZ column omega:R:3 (only then), read by ASE as an array
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out xr "${small2d[@]}" --set output.trajectory=xyz \
        --set model.rotation=true --set placement.omega0=200
    "$PY" - <<'EOF'
import ase.io, numpy as np
frames = ase.io.read("xr/snapshots/trajectory.xyz", index=":")
plain = ase.io.read("x2/snapshots/trajectory.xyz")
assert "omega" not in plain.arrays
for a in frames:
    w = a.arrays["omega"]
    assert w.shape == (300, 3) and np.all(w[:, :2] == 0) and np.abs(w[:, 2]).max() > 0, w.shape
print("ok ASE reads the spins (omega) of a rotating run, %d frames" % len(frames))
EOF
    "$G" analyse x2 --set analysis.observables=pv,moments >/dev/null
    "$G" analyse r2 --set analysis.observables=pv,moments >/dev/null
    cmp x2/analysis/pv.csv r2/analysis/pv.csv && cmp x2/analysis/moments.csv r2/analysis/moments.csv
    echo "ok granule analyse reads trajectory.xyz as the per-frame snapshots"
    ;;
h5md)
    need MDAnalysis python3-mdanalysis
    need h5py python3-h5py
    obs=(--set analysis.observables=pv,moments,sk,pair)
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out h "${small2d[@]}" "${obs[@]}" --set output.trajectory=h5md
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out x "${small2d[@]}" "${obs[@]}" --set output.trajectory=xyz
    "$PY" - <<'EOF'
import warnings
import numpy as np
warnings.simplefilter("ignore")
import MDAnalysis as mda, h5py, ase.io
u = mda.Universe.empty(300, trajectory=False)
u.load_new("h/trajectory.h5", format="H5MD", convert_units=False)
xyz = ase.io.read("x/snapshots/trajectory.xyz", index=":")
assert len(u.trajectory) == len(xyz) == 9, (len(u.trajectory), len(xyz))
for k, ts in enumerate(u.trajectory):
    assert abs(ts.time - 0.002 * k) < 1e-12, ts.time
    assert ts.data["step"] == 2000 * k, ts.data
    assert np.allclose(ts.dimensions, [0.08, 0.08, 3e-3, 90, 90, 90]), ts.dimensions
    assert np.array_equal(ts.positions.astype(float), np.float32(xyz[k].positions)), k
    assert np.allclose(ts.velocities, xyz[k].get_velocities(), rtol=1e-6, atol=1e-9), k
with h5py.File("h/trajectory.h5", "r") as f:
    p = f["particles/all/position/value"]
    assert p.compression == "gzip" and p.chunks[0] == 1, (p.compression, p.chunks)
    assert np.array_equal(p[8], xyz[8].positions), "double positions differ from the XYZ"
    assert list(f["particles/all/box"].attrs["boundary"]) == ["periodic", "periodic", "none"]
    assert f["particles/all/velocity/value"].attrs["unit"] == "m s-1"
print("ok MDAnalysis %s: %d frames, times, steps, box, positions and velocities" % (mda.__version__, len(u.trajectory)))
EOF
    # rotation: /particles/all/angular_velocity (only then), the same values as the XYZ's omega
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out hr "${small2d[@]}" --set output.trajectory=h5md \
        --set model.rotation=true --set placement.omega0=200
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out xr "${small2d[@]}" --set output.trajectory=xyz \
        --set model.rotation=true --set placement.omega0=200
    "$PY" - <<'EOF'
import h5py, ase.io, numpy as np
xyz = ase.io.read("xr/snapshots/trajectory.xyz", index=":")
with h5py.File("hr/trajectory.h5", "r") as f, h5py.File("h/trajectory.h5", "r") as g:
    assert "angular_velocity" not in g["particles/all"]
    w = f["particles/all/angular_velocity/value"]
    assert w.shape == (len(xyz), 300, 3), w.shape
    for k, a in enumerate(xyz):
        assert np.array_equal(w[k], a.arrays["omega"]), k
print("ok h5py reads the spins (angular_velocity) of a rotating run, equal to the XYZ's")
EOF
    "$G" analyse h --set run.warmup=0.004 >/dev/null
    for f in pv.csv moments.csv sk.csv pair.csv; do
        cmp h/$f h/analysis/$f || { echo "FAIL analyse of trajectory.h5: $f differs from the run's"; exit 1; }
    done
    echo "ok granule analyse of trajectory.h5 gives the in-run pv, moments, sk, pair"
    # kill -9 after a checkpoint, then --resume: the same frames as the uninterrupted run
    for fmt in h5md xyz; do
        GRANULE_TEST_PAUSE_AT_STEP=9000 "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out k$fmt "${small2d[@]}" \
            --set output.trajectory=$fmt --set run.checkpoint_every=0.004 >/dev/null 2>&1 &
        pid=$!
        bg=$pid
        for _ in $(seq 1 1500); do [[ -e k$fmt/checkpoint ]] && break; sleep 0.02; done
        sleep 0.3
        kill -9 "$pid" 2>/dev/null || true
        set +e; { wait "$pid"; } 2>/dev/null; rc=$?; set -e
        [[ $rc -eq 137 ]] || { echo "FAIL kill -9 did not hit the $fmt run (exit $rc)"; exit 1; }
        [[ $fmt == xyz ]] || "$PY" -c "
import h5py
with h5py.File('kh5md/trajectory.h5', 'r') as f:
    n = f['particles/all/position/value'].shape[0]
    assert n >= 2 and f['particles/all/position/time'].shape[0] >= n, n  # the frames before the first checkpoint
print('ok a killed run leaves trajectory.h5 readable (%d frames)' % n)"
        "$G" run --resume k$fmt --quiet
    done
    "$PY" - <<'EOF'
import numpy as np, h5py, ase.io
with h5py.File("h/trajectory.h5", "r") as a, h5py.File("kh5md/trajectory.h5", "r") as b:
    for name in ["position/value", "velocity/value", "position/time", "position/step", "box/edges/value"]:
        x, y = a["particles/all/" + name][()], b["particles/all/" + name][()]
        assert x.shape == y.shape and np.array_equal(x, y), name
ref, got = ase.io.read("x/snapshots/trajectory.xyz", index=":"), ase.io.read("kxyz/snapshots/trajectory.xyz", index=":")
assert len(ref) == len(got) and all(np.array_equal(p.positions, q.positions) for p, q in zip(ref, got))
print("ok kill -9 + --resume: trajectory.h5 and trajectory.xyz equal the uninterrupted run's")
EOF
    ;;
3d)
    # spheres (docs/three-dimensions.md): ASE reads the 3D extended XYZ (pbc T T T, the cube, z and
    # vz), MDAnalysis and h5py the 3D trajectory.h5 (box L L L, three periodic directions, the
    # XYZ's positions and velocities in every frame)
    need ase python3-ase
    need MDAnalysis python3-mdanalysis
    need h5py python3-h5py
    small3d=(--set system.N=300 --set run.warmup=0.004 --set run.duration=0.012 --set run.sample_every=0.002
             --set output.snapshot_every=0.002 --set output.plots=false --quiet)
    "$G" run "$SRC/docs/scenes/rfm-3d.ini" --out x3 "${small3d[@]}" --set output.trajectory=xyz
    "$G" run "$SRC/docs/scenes/rfm-3d.ini" --out h3 "${small3d[@]}" --set output.trajectory=h5md
    "$PY" - <<'EOF'
import json, warnings
import numpy as np
warnings.simplefilter("ignore")
import ase.io, MDAnalysis as mda, h5py
L = json.load(open("x3/summary.json"))["scene"]["system"]["L"]
M, r = 3.53e-5, 1.5e-3
xyz = ase.io.read("x3/snapshots/trajectory.xyz", index=":")
assert len(xyz) == 9, len(xyz)
for k, a in enumerate(xyz):
    assert list(a.pbc) == [True, True, True], a.pbc
    assert np.allclose(a.cell.lengths(), [L, L, L], rtol=1e-15), a.cell.lengths()
    assert abs(a.info["Time"] - 0.002 * k) < 1e-12, a.info
    assert np.all(a.positions >= 0) and np.all(a.positions < L)
    v = a.get_velocities()
    assert np.allclose(v, a.arrays["velo"], rtol=1e-12, atol=1e-15)
    assert np.all(np.abs(v).max(axis=0) > 0), "a velocity component is zero"
    assert np.allclose(a.get_masses(), M, rtol=1e-15) and np.allclose(a.arrays["radius"], r)
print("ok ASE %s: %d 3D frames, pbc T T T, the cube, z and vz" % (ase.__version__, len(xyz)))
u = mda.Universe.empty(300, trajectory=False)
u.load_new("h3/trajectory.h5", format="H5MD", convert_units=False)
assert len(u.trajectory) == len(xyz), (len(u.trajectory), len(xyz))
for k, ts in enumerate(u.trajectory):
    assert abs(ts.time - 0.002 * k) < 1e-12, ts.time
    assert np.allclose(ts.dimensions, [L, L, L, 90, 90, 90]), ts.dimensions
    assert np.array_equal(ts.positions.astype(float), np.float32(xyz[k].positions)), k
    assert np.allclose(ts.velocities, xyz[k].get_velocities(), rtol=1e-6, atol=1e-9), k
with h5py.File("h3/trajectory.h5", "r") as f:
    p = f["particles/all/position/value"]
    assert p.shape == (9, 300, 3), p.shape
    assert np.array_equal(p[8], xyz[8].positions), "double positions differ from the XYZ"
    assert np.array_equal(f["particles/all/velocity/value"][8], xyz[8].arrays["velo"])
    assert list(f["particles/all/box"].attrs["boundary"]) == ["periodic"] * 3
    assert np.array_equal(f["particles/all/box/edges/value"][0], np.diag([L, L, L]))
    assert f["parameters/granule"].attrs["dim"] == 3
print("ok MDAnalysis %s and h5py: %d 3D frames, box, positions and velocities equal the XYZ's" % (mda.__version__, len(u.trajectory)))
EOF
    # rotation: the spin vectors are the extended-XYZ column omega:R:3 and H5MD's angular_velocity
    # (only then), read by ASE as an array and by h5py, the same values
    spin3d=(--set model.rotation=true --set placement.omega0=200 --set model.tangential=tangential_spring
            --set model.mu=0.5)
    "$G" run "$SRC/docs/scenes/rfm-3d.ini" --out x3r "${small3d[@]}" "${spin3d[@]}" --set output.trajectory=xyz
    "$G" run "$SRC/docs/scenes/rfm-3d.ini" --out h3r "${small3d[@]}" "${spin3d[@]}" --set output.trajectory=h5md
    "$PY" - <<'EOF'
import ase.io, h5py, numpy as np
xyz = ase.io.read("x3r/snapshots/trajectory.xyz", index=":")
assert "omega" not in ase.io.read("x3/snapshots/trajectory.xyz").arrays
assert len(xyz) == 9, len(xyz)
for a in xyz:
    w = a.arrays["omega"]
    assert w.shape == (300, 3) and np.all(np.abs(w).max(axis=0) > 0), (w.shape, np.abs(w).max(axis=0))
    assert list(a.pbc) == [True] * 3 and np.all(np.abs(a.get_velocities()).max(axis=0) > 0)
assert not np.array_equal(xyz[0].arrays["omega"], xyz[-1].arrays["omega"]), "the spins never changed"
with h5py.File("h3r/trajectory.h5", "r") as f, h5py.File("h3/trajectory.h5", "r") as g:
    assert "angular_velocity" not in g["particles/all"]
    w = f["particles/all/angular_velocity/value"]
    assert w.shape == (len(xyz), 300, 3) and w.attrs["unit"] == "rad s-1", (w.shape, dict(w.attrs))
    for k, a in enumerate(xyz):
        assert np.array_equal(w[k], a.arrays["omega"]), k
print("ok ASE and h5py read the 3D spin vectors (omega:R:3, angular_velocity), %d frames, equal" % len(xyz))
EOF
    ;;
csv)
    need pandas python3-pandas
    need numpy python3-numpy
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out run "${small2d[@]}" --set output.plots=true \
        --set analysis.observables=pv,moments,sk,pair,freepath,postcollision,msd,vacf,vcorr,clusters,pressure,collisions
    "$G" run "$SRC/docs/scenes/rfm-2d.ini" --out run1 --set system.dim=1 --set system.N=100 --set system.L=1 \
        --set placement.kind=uniform --set model.tangential=none --set run.warmup=0 --set run.duration=0.004 --set run.sample_every=0.002 \
        --set analysis.observables=gaps,moments,pv,freepath,postcollision,msd,vacf,clusters,pressure,collisions \
        --set output.plots=false --quiet
    # a Langevin bath adds the ledger's dissipated_drag column (docs/systems-driving.md)
    "$G" run "$SRC/docs/scenes/langevin-gas.ini" --out run2 --set system.N=200 --set system.L=0.06 \
        --set run.warmup=0 --set run.duration=0.004 --set run.sample_every=0.002 --set output.plots=false --quiet
    # gravity adds the ledger's potential column (docs/systems-walls-gravity.md)
    "$G" run "$SRC/docs/scenes/gravity-bed.ini" --out run3 --set run.warmup=0 --set run.duration=0.004 \
        --set run.sample_every=0.002 --set output.plots=false --quiet
    # a moving floor adds the ledger's wall_work column, walls the mean forces in summary.json
    "$G" run "$SRC/docs/scenes/vibrated-bed.ini" --out run4 --set run.warmup=0 --set run.duration=0.02 \
        --set run.sample_every=0.01 --set output.plots=false --quiet
    # a mixture adds pv_species.csv, species.csv and moments_species.csv (docs/mixtures.md)
    "$G" run "$SRC/docs/scenes/bidisperse-mixture.ini" --out run5 --set system.N=200 --set run.warmup=0 \
        --set run.duration=0.01 --set run.sample_every=0.002 --set output.plots=false --set output.snapshot_every=0 \
        --set analysis.observables=species,pv,moments,clusters,sk,pair,pressure --quiet
    "$G" analyse run --set analysis.observables=pv,moments,sk,pair >/dev/null 2>&1
    "$G" compare "$SRC/docs/scenes/rfm-2d.ini" --models spring_dashpot+tangential_dashpot,spring_dashpot --out cmp \
        "${small2d[@]:0:${#small2d[@]}-1}" --set analysis.observables=pv >/dev/null
    cat >sw.ini <<EOF
[sweep]
scene = $SRC/docs/scenes/rfm-2d.ini
out = sweep
[vary]
system.N = 100, 200
[set]
system.L = 0.08
run.warmup = 0.002
run.duration = 0.004
run.sample_every = 0.002
output.plots = false
analysis.observables = moments
EOF
    "$G" sweep sw.ini >/dev/null 2>&1 || { echo "FAIL sweep"; cat sweep/*.log 2>/dev/null | tail -5; exit 1; }
    "$PY" - <<'EOF'
import glob, json, os, warnings
import numpy as np, pandas as pd
warnings.simplefilter("ignore")
files = sorted(glob.glob("run/*.csv") + glob.glob("run/analysis/*.csv") + glob.glob("run1/*.csv") + glob.glob("run2/*.csv") + glob.glob("run3/*.csv") + glob.glob("run4/*.csv") + glob.glob("run5/*.csv") + glob.glob("cmp/*.csv")
               + glob.glob("cmp/*/*.csv") + glob.glob("sweep/*.csv") + glob.glob("sweep/*/*.csv"))
assert len(files) > 60, files
assert "run5/pv_species.csv" in files, "a mixture's P(v) per species"

units_seen = set()
for f in files:
    df = pd.read_csv(f)
    assert len(df.columns) > 1 and len(df) > 0, f
    assert not any(str(c).startswith("#") or str(c).startswith("Unnamed") for c in df.columns), (f, list(df.columns))
    assert "#" not in open(f).read(), (f, "a '#' starts a comment for numpy.genfromtxt")
    a = np.atleast_1d(np.genfromtxt(f, names=True, delimiter=",", dtype=None, encoding="utf-8"))
    assert a.dtype.names and len(a.dtype.names) == len(df.columns), (f, a.dtype.names, list(df.columns))
    assert len(a) == len(df), (f, len(a), len(df))
    meta = f[:-4] + ".meta.json"
    assert os.path.exists(meta), meta
    m = json.load(open(meta))
    assert m["file"] == os.path.basename(f), meta
    units = m.get("units", {})
    missing = [c for c in df.columns if not isinstance(units.get(c), str)]
    assert not missing, (f, "columns without a unit", missing)
    assert len(units) == len(df.columns), (f, sorted(set(units) - set(df.columns)))
    for c, u in units.items():  # "@col": the unit is in that text column of each row
        if u.startswith("@"):
            assert u[1:] in df.columns and df[u[1:]].notna().all(), (f, c, u)
        units_seen.add(u)
assert {"s", "m2 s-2", "J", "m s-1", "s m-1", "(m s-1)^m", "m^m", "1", ""} <= units_seen, units_seen
sw = pd.read_csv("sweep/sweep.csv")
assert "m2" in sw.columns and not any(c.startswith("R") for c in sw.columns), list(sw.columns)
for need in ["run/temperature.csv", "run/ledger.csv", "run/pv.csv", "cmp/compare.csv", "cmp/pv_collapse.csv", "sweep/sweep.csv"]:
    assert need in files, need
    assert os.path.exists(need[:-4] + ".meta.json"), need
pc = pd.read_csv("cmp/pv_collapse.csv")
assert list(pc.columns) == ["model", "v_over_vrms", "P_scaled"] and pc["model"].nunique() == 2 and pc.notna().all().all()
lg = pd.read_csv("run2/ledger.csv")
assert lg.columns[-1] == "dissipated_drag" and (lg["dissipated_drag"].iloc[1:] > 0).all(), list(lg.columns)
assert json.load(open("run2/ledger.meta.json"))["units"]["dissipated_drag"] == "J"
lp = pd.read_csv("run3/ledger.csv")
assert lp.columns[-1] == "potential" and (lp["potential"] > 0).all(), list(lp.columns)
assert json.load(open("run3/ledger.meta.json"))["units"]["potential"] == "J"
lw = pd.read_csv("run4/ledger.csv")
assert list(lw.columns[-2:]) == ["potential", "wall_work"] and lw["wall_work"].iloc[-1] > 0, list(lw.columns)
assert json.load(open("run4/ledger.meta.json"))["units"]["wall_work"] == "J"
assert "wall_work" not in pd.read_csv("run3/ledger.csv").columns  # a static wall does no work
sj = json.load(open("run4/summary.json"))
assert sj["walls"]["y_0"]["force"] > 0 and sj["walls"]["y_L"]["force"] == 0 and "x_0" not in sj["walls"], sj["walls"]
ww = pd.read_csv("run4/walls.csv")
assert list(ww["wall"]) == ["y_0", "y_L"] and abs(ww["force"].iloc[0] / sj["walls"]["y_0"]["force"] - 1) < 1e-8, ww
assert abs(ww["pressure"].iloc[0] * 0.1 / ww["force"].iloc[0] - 1) < 1e-8  # force per unit length, L = 0.1 m
assert "run4/walls.csv" in files and not os.path.exists("run/walls.csv")  # periodic runs write none
assert sj["ledger"]["wall_work"] == lw["wall_work"].iloc[-1] or abs(sj["ledger"]["wall_work"] / lw["wall_work"].iloc[-1] - 1) < 1e-9
t = pd.read_csv("run/temperature.csv")
assert list(t.columns) == ["t", "T", "running_mean", "phase"] and len(t) == 9
assert list(t["phase"].unique()) == ["warmup", "sampling"], t["phase"].unique()  # the docs' words
print("ok pandas %s and numpy %s read %d CSVs without options" % (pd.__version__, np.__version__, len(files)))
EOF
    ;;
results)
    need pandas python3-pandas
    need numpy python3-numpy
    # collected again from their archived points (no run), without their data tables' meta files
    for n in ch2-placement ch3-moments ch4-structure; do
        mkdir -p res && cp -r "$SRC/docs/results/$n" res/$n && rm res/$n/*_data.meta.json
        # (exit 1 with "only K of M points are finished" is a campaign extended since: it collects)
        "$G" reproduce $n --fidelity full --collect --out rp --results res/$n >rp-$n.log 2>&1 ||
            grep -q "^reproduce: $n: only [0-9]* of [0-9]* points are finished" rp-$n.log ||
            { echo "FAIL reproduce $n --collect"; tail -5 rp-$n.log; exit 1; }
    done
    "$PY" - "$SRC" <<'EOF'
import csv, glob, json, os, re, sys, warnings
import numpy as np, pandas as pd
warnings.simplefilter("ignore")
src = sys.argv[1]
# sets a running campaign still writes and nobody has collected with the current code (none now:
# ch3-xi2-large was collected after its units and cells changed)
pending = set()
def units_of(f, df, rows_named=False):
    meta = f[:-4] + ".meta.json"
    assert os.path.exists(meta), (meta, "missing: the table's units")
    m = json.load(open(meta))
    assert m["file"] == os.path.basename(f), meta
    units = m.get("units", {})
    assert list(units) == list(df.columns), (f, "units name the columns in order", list(units), list(df.columns))
    for c, u in units.items():
        assert isinstance(u, str), (f, c, u)
        if u.startswith("@"):  # the unit is in that text column of each row (that has a value)
            assert u[1:] in df.columns, (f, c, u)
            assert not rows_named or df.loc[df[c].notna(), u[1:]].notna().all(), (f, c, u, "a row without its unit")
        for power in re.findall(r"\^-?([A-Za-z_][A-Za-z0-9_]*)", u):  # a power in a column of the row
            assert power in df.columns and df[power].dtype.kind in "if", (f, c, u, power)
    return units
files = sorted(f for f in glob.glob(os.path.join(src, "docs/results/**/*.csv"), recursive=True)
               if f.split(os.sep)[-2] not in pending)
assert len(files) > 80, len(files)
seen = set()
for f in files:
    df = pd.read_csv(f)
    assert len(df.columns) > 1 and len(df) > 0, f
    seen |= set(units_of(f, df).values())
    bad = [cell for row in csv.reader(open(f)) for cell in row if "," in cell or "#" in cell]
    assert not bad, (f, "cells numpy splits or cuts (no quoting; '#' a comment)", bad[:3])
    a = np.atleast_1d(np.genfromtxt(f, names=True, delimiter=",", dtype=None, encoding="utf-8"))
    assert len(a.dtype.names) == len(df.columns) and len(a) == len(df), (f, a.dtype.names, len(a), len(df))
assert {"m2 s-2", "(m s-1)^m", "m^m", "m^2/s^2", "m m^-D_f", "m-1", "s m-1", "1", ""} <= seen, seen
# the data tables collected again: the same units as the committed ones
data = sorted(glob.glob("res/*/*_data.csv"))
assert len(data) == 27, data
for f in data + sorted(glob.glob("res/*/results.csv")):  # results.csv: every fit window's x_unit (curve, spm)
    df = pd.read_csv(f)
    units_of(f, df, rows_named=True)
    # written now: ch3-moments's labels "eps_n=0.1; N=100" in one cell that numpy reads too
    assert not [c for row in csv.reader(open(f)) for c in row if "," in c or "#" in c], f
    a = np.atleast_1d(np.genfromtxt(f, names=True, delimiter=",", dtype=None, encoding="utf-8"))
    assert len(a.dtype.names) == len(df.columns) and len(a) == len(df), (f, a.dtype.names, len(a), len(df))
    if "group" in df.columns:
        assert all(g.strip('"') == h for g, h in zip(a["group"], df["group"])), f
# ... and read back for the figures as the page writes them ("eps_n = 0.1, N = 100", the series'
# titles): the gnuplot blocks and thesis lines equal the committed ones
dat = sorted(glob.glob("res/*/*_blocks.dat") + glob.glob("res/*/*_thesis.dat") + glob.glob("res/*/*_series.dat"))
assert any('"eps_n = 0.1, N = 100"' in open(f).read() for f in dat), dat
for f in dat:
    assert open(f).read() == open(os.path.join(src, "docs/results", f[4:])).read(), f
# a handful of series per plot (issue 37): a figure of many is drawn in panels
for f in sorted(glob.glob(os.path.join(src, "docs/results/*/*.gp"))):
    for lo, hi in re.findall(r"^plot for \[i=(\d+):(\d+)\]", open(f).read(), re.M):
        assert int(hi) - int(lo) + 1 <= 9, (f, "series in one plot", int(hi) - int(lo) + 1)
labels = set(pd.read_csv("res/ch3-moments/results.csv")["group"])
assert "eps_n=0.1; N=100" in labels and not any(", " in g for g in labels), sorted(labels)[:5]
for f in data:
    new, old = json.load(open(f[:-4] + ".meta.json")), json.load(open(os.path.join(src, "docs/results", f[4:-4] + ".meta.json")))
    assert new == old, (f, new, old)
# a data table with its units, as docs/python.md reads it: <R^m> per row in m^m
f = os.path.join(src, "docs/results/ch3-moments/table3.1_data.csv")
df = pd.read_csv(f)
a = np.genfromtxt(f, names=True, delimiter=",", dtype=None, encoding="utf-8")
units = json.load(open(f[:-4] + ".meta.json"))["units"]
assert units["x"] == "1" and units["mean"] == "m^m" and a.dtype.names == tuple(df.columns)
row_units = [units["mean"].replace("^m", "^%d" % m) for m in a["m"]]
assert row_units[0] == "m^1" and "m^5" in row_units and np.allclose(a["mean"], df["mean"])
# docs/campaigns/ch3-xi2-large.ini says its seeds 1-3 at N = 398-2512 are ch3-moments' runs bit for
# bit (the same scene, seed and noise keys): their archived <v^2> must be equal, not merely close
def archived_m2(campaign):
    out = {}
    for f in glob.glob(os.path.join(src, "docs/results", campaign, "points", "p*.json")):
        j = json.load(open(f))
        keys = j["point"]["keys"]
        if keys.get("model.eps_n") == "0.1":
            out[(j["point"]["seed"], keys["system.N"])] = j["summary"]["analysis"]["moments"]["speed"]["m2"]
    return out
xi2, moments = archived_m2("ch3-xi2-large"), archived_m2("ch3-moments")
shared = sorted(k for k in xi2 if k in moments)
assert len(shared) == 15, shared  # seeds 1-3 x N = 398, 631, 1000, 1585, 2512
assert all(xi2[k] == moments[k] for k in shared), [(k, xi2[k], moments[k]) for k in shared if xi2[k] != moments[k]]
print("ok %d CSVs of docs/results (all but %s) have their units and load with pandas and numpy; "
      "--collect writes the %d data tables' units again" % (len(files), ", ".join(sorted(pending)) or "none", len(data)))
EOF
    ;;
*) echo "unknown part $part" >&2; exit 2 ;;
esac
