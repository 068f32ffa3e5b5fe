"""granule from Python: scenes, simulations stepped in place, the analysis layer's observables,
and run folders as numpy/pandas (docs/python.md). Everything physical runs in libgranule (the C
extension granule._granule); this package only converts.

    import granule
    scene = granule.load_scene("docs/scenes/rfm-2d.ini", set={"system.N": 300, "system.L": 0.08})
    sim = granule.Sim(scene)
    sim.step(1000)
    sim.vx            # read-only numpy view on the simulation's own array
"""
import json
import os
import sys
import tempfile

try:
    import numpy  # noqa: F401  (the C extension needs it; say so instead of numpy's own ImportError)
except ImportError as _e:
    raise ImportError(
        f"granule needs numpy, which {sys.executable} (Python {sys.version.split()[0]}) cannot import "
        f"({_e}): install numpy for this interpreter (pip install numpy; Debian python3-numpy for "
        "/usr/bin/python3, which a venv made with --system-site-packages sees), or use an interpreter "
        "that has it (docs/python.md)", name="numpy") from None
try:
    from ._granule import Error, Observer, Scene, SceneError, Sim, version
    from ._granule import run as _run
except ImportError as _e:
    import importlib.machinery
    _here = os.path.dirname(os.path.abspath(__file__))
    _built = sorted(f for f in os.listdir(_here) if f.startswith("_granule.")) or ["none"]
    raise ImportError(
        f"granule: the compiled part granule._granule cannot be loaded into {sys.executable} (Python "
        f"{sys.version.split()[0]}, which loads {importlib.machinery.EXTENSION_SUFFIXES[0]}): {_e}. "
        f"{_here} holds {', '.join(_built)}: build granule for this interpreter with `pip install .` "
        "in the source tree (docs/python.md)", name="granule._granule") from _e

from .interop import mdanalysis_universe, read_ase
from .runfolder import (folder_kind, read_csv, read_lammps_dump, read_run, read_snapshot, read_snapshots,
                        trajectory_files)

__version__ = version  # the C library's GR_VERSION (meson.build's project version)

__all__ = ["Error", "SceneError", "Scene", "Sim", "Observer", "load_scene", "observe", "run",
           "read_run", "folder_kind", "read_csv", "read_snapshot", "read_snapshots", "trajectory_files",
           "read_lammps_dump", "read_ase", "mdanalysis_universe", "version", "__version__"]


def _overrides(set):
    """--set style overrides from a dict {"section.key": value} or a list of "section.key=value"."""
    if set is None:
        return []
    if isinstance(set, dict):
        return [f"{k}={_ini_value(v)}" for k, v in set.items()]
    return [str(s) for s in set]


def _ini_text(section, key, text, name=False):
    """A section, key or value of a scene dict as one line's text: a line break or other control
    character (which would start another line or be cut at a NUL) is refused as in scene files, and
    so are the separators '=', ':' and ']' in a section or key name."""
    text = str(text)
    bad = next((c for c in text if (ord(c) < 0x20 and c != "\t") or c == "\x7f"), None)
    if bad is not None or (name and any(c in text for c in "=:[]")):
        what = f"control byte {ord(bad):#04x}" if bad is not None else "'=', ':', '[' or ']'"
        raise SceneError(f"[{section!s:.60}] {key!s:.60}: {what} in {text!r:.80} (a scene is text, one key = value per line)")
    return text


def _ini_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return ",".join(str(x) for x in v)
    return repr(v) if isinstance(v, float) else str(v)


def load_scene(source=None, set=None):
    """A Scene from a file path, a dict {section: {key: value}} or None (defaults), with --set
    overrides (dict or list). Invalid keys or values raise SceneError with granule's message."""
    if source is None or isinstance(source, (str, os.PathLike)):
        return Scene(None if source is None else os.fspath(source), _overrides(set))
    if isinstance(source, dict):
        lines = []
        for section, keys in source.items():
            if not isinstance(keys, dict):
                raise SceneError(f"[{section}]: expected a dict {{key: value}} of the section's keys, "
                                 f"not {type(keys).__name__} {keys!r:.60}")
            lines.append(f"[{_ini_text(section, '', section, name=True)}]")
            lines += [f"{_ini_text(section, k, k, name=True)} = {_ini_text(section, k, _ini_value(v))}" for k, v in keys.items()]
        return Scene(None, _overrides(set), text="\n".join(lines) + "\n", name="<dict>")
    raise TypeError("load_scene: expected a path, a dict or None")


def scene_dict(scene):
    """The resolved scene as a dict (the "scene" member of summary.json)."""
    return json.loads(scene.to_json())


def observe(scene, frames, out=None, force=False):
    """Feed frames (Sims, or dicts with t, x, vx[, y, vy][, z, vz]) to the observables the scene names and
    return {observable: {"summary": dict, "tables": {csv name: pandas.DataFrame or numpy array}}}.
    The CSVs go to `out` (kept; a folder holding another result is refused unless force) or a
    temporary folder."""
    obs = Observer(scene)
    for f in frames:
        if isinstance(f, Sim):
            obs.sample(f)
        else:
            obs.sample_frame(**{k: f[k] for k in ("t", "x", "vx", "y", "vy", "L", "z", "vz")
                                if f.get(k) is not None})
    with tempfile.TemporaryDirectory() as tmp:
        folder = out or tmp
        summary = json.loads(obs.finish(folder, force=force))
        return {name: {"summary": member, "tables": _tables(folder, name)} for name, member in summary.items()}


def _tables(folder, name):
    return {f[:-4]: read_csv(os.path.join(folder, f)) for f in sorted(os.listdir(folder))
            if f.endswith(".csv") and (f[:-4] == name or f.startswith(name + "_"))}


def run(scene, out=None, force=False):
    """`granule run` of a Scene into out (default its output.dir); returns the run's result dict
    (T_mean, T_stderr, steps, ...). Read the folder with read_run(result["dir"])."""
    return _run(scene, out, force)
