#!/usr/bin/env bash
# The README's first command (issue 38): its run ends with a converged error bar on T (no
# warning) and writes a space-time diagram resolved finely enough to show clusters forming and
# dissolving (at least 1000 frames, 20 ms apart, in one trajectory file).
# usage: test_readme_demo.sh GRANULE SOURCE_DIR
source "$(dirname "$0")/cli_test_lib.sh"
# the scene of the README's first command, run as the README runs it (into a temporary folder)
cmd=$(sed -n '/^```sh$/{n;p;q}' "$SRC/README.md")
scene=$(grep -o 'granule run [^ ]*' <<<"$cmd" | awk '{print $3}')
check test -n "$scene"
(cd "$SRC" && "$G" run "$scene" --out "$tmp/demo") >"$tmp/out" 2>&1
check test $? -eq 0
check grep -q "^.*: T = .* m^2/s^2 over" "$tmp/out"
check bash -c "! grep -q WARNING '$tmp/out'"
check /usr/bin/python3 - "$tmp/demo" <<'PY'
import json, sys
import h5py
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
with h5py.File(f"{d}/trajectory.h5", "r") as f:
    frames = f["particles/all/position/value"].shape[0]
print(f"T = {s['T_mean']:.4g} +- {s['T_stderr']:.2g}, converged {s['T_stderr_converged']}, {frames} frames")
sys.exit(0 if s["T_stderr_converged"] and s["status"] == "completed" and frames >= 1000 else 1)
PY
check test -s "$tmp/demo/snapshots.png"
finish
