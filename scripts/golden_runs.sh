#!/bin/bash
# Short runs of every docs/scenes/*.ini (each integrator) with one granule binary, for a
# byte-for-byte comparison of two builds: scripts/golden_runs.sh BIN OUTDIR, twice, then
# diff -r the two OUTDIRs (summary.json is reduced to its deterministic fields).
# Each scene runs plain, with 2 threads, and stopped at a wall-clock limit then resumed.
set -u
bin=$1 out=$2
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
short=(--set run.warmup=0.002 --set run.duration=0.004 --set output.plots=false --set output.snapshot_every=0.002 --quiet)
for scene in "$here"/docs/scenes/*.ini; do
    name=$(basename "$scene" .ini)
    case $name in
        *2d*) size=(--set system.N=2100) ;;
        *) size=(--set system.N=300) ;;
    esac
    [ "$name" = rfm-2d ] && size=(--set system.N=2100 --set system.L=0.17)
    "$bin" run "$scene" --out "$out/$name" "${short[@]}" "${size[@]}" --force >/dev/null 2>"$out/$name.err"; echo "$name rc=$?" >>"$out/rc.txt"
    "$bin" run "$scene" --out "$out/$name-t2" "${short[@]}" "${size[@]}" --threads 2 --force >/dev/null 2>>"$out/$name.err"; echo "$name-t2 rc=$?" >>"$out/rc.txt"
    # stopped by the (fake) wall clock, then resumed
    GRANULE_TEST_CLOCK_TICK=0.05 GRANULE_CHUNK_STEPS=50 "$bin" run "$scene" --out "$out/$name-r" "${short[@]}" "${size[@]}" \
        --set run.wall_limit=3 --force >/dev/null 2>>"$out/$name.err"; echo "$name-r first rc=$?" >>"$out/rc.txt"
    cp -r "$out/$name-r" "$out/$name-ck" # a checkpoint of this binary, to resume with another one
    "$bin" run --resume "$out/$name-r" --quiet >/dev/null 2>>"$out/$name.err"; echo "$name-r resume rc=$?" >>"$out/rc.txt"
done
# summary.json: drop wall times, rates, versions and checkpoint counts (they differ between runs)
for f in "$out"/*/summary.json; do
    /usr/bin/python3 - "$f" <<'PY'
import json, sys
p = sys.argv[1]
j = json.load(open(p))
for k in ("wall_seconds", "particle_steps_per_second", "events_per_second", "granule_version", "commit",
          "checkpoints_written", "checkpoint_seconds", "threads", "checkpoint_error", "warnings"):
    j.pop(k, None)
json.dump(j, open(p + ".cmp", "w"), indent=1, sort_keys=True)
PY
    rm "$f"
done
find "$out" -name '*.meta.json' -exec sed -i -e '/"granule_version"\|"commit"\|"wall/d' {} +
