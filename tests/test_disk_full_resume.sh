#!/usr/bin/env bash
# A full disk never loses a run (docs/checkpoints.md, "A full disk"): a small tmpfs, in a private
# mount namespace, fills up at many points of one run (the streamed tables, the snapshots, each
# file of the final writes: temperature.csv, ledger.csv, blocks.csv, pv*.csv, scene.ini,
# summary.json). Each time the run must stop with exit 6 (checkpoint kept; summary.json, if it
# could be written, says status "write_failed"), or exit 1 before its first checkpoint; once
# space is freed, `--resume` (or a fresh `--force` run) must give every output byte for byte
# as the uninterrupted run did, summary.json equal but for its timings (its `warnings`
# included), and no checkpoint and no NAME.tmpPID left.
# Usage: test_disk_full_resume.sh GRANULE   (skipped without mount rights)
set -uo pipefail
g="$(realpath "$1")"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
ns=()
if unshare -m true 2>/dev/null; then
    ns=(unshare -m)
elif unshare -rm true 2>/dev/null; then
    ns=(unshare -rm)
fi
if ! ((${#ns[@]})) || ! "${ns[@]}" sh -c "mount -t tmpfs -o size=64k granule-test '$tmp' 2>/dev/null"; then
    echo "skipped: cannot mount a tmpfs here (needs root or user namespaces)"
    exit 0
fi

# [model] mu is ignored here: a warning that summary.json must keep across a resume
cat >"$tmp/s.ini" <<'INI'
[model]
mu = 0.3
[placement]
kind = uniform
[system]
dim = 1
N = 20
reduced_length = 0.1
[run]
warmup = 0
duration = 0.1
sample_every = 1e-3
checkpoint_every = 0.025
[analysis]
observables = pv
[output]
snapshot_every = 0.01
plots = false
INI

cat >"$tmp/same.py" <<'PY'
import json, sys
timing = {"wall_seconds", "particle_steps_per_second", "checkpoints_written", "checkpoint_seconds",
          "events_per_second", "checkpoint_error"}
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for j in (a, b):
    for k in timing:
        j.pop(k, None)
if a != b:
    diff = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
    sys.exit("summary.json differs in " + ", ".join(diff))
if "warnings" not in a:
    sys.exit("summary.json has no warnings")
PY

# the scan runs inside one private mount namespace; the tmpfs is always on $tmp/mnt
cat >"$tmp/scan.sh" <<'SH'
set -uo pipefail
g="$1" tmp="$2"
mnt="$tmp/mnt" out="$tmp/mnt/out"
mkdir -p "$mnt"
mount -t tmpfs -o size=8m granule-test "$mnt" || exit 99
"$g" run "$tmp/s.ini" --out "$out" --quiet >/dev/null 2>"$tmp/err.txt" || { cat "$tmp/err.txt"; exit 1; }
cp -a "$out" "$tmp/ref"
need_k=$(( $(du -sk "$out" | cut -f1) ))
rm -rf "$out"
umount "$mnt"
echo "uninterrupted run: ${need_k} KiB"
sizes=""
# coarse through the run (tables, snapshots), page by page through the final writes (the old
# checkpoint and scene.ini stay until the end, so the final writes need more than need_k)
for ((s = 8; s < need_k - 96; s += 16)); do sizes+=" $s"; done
for ((s = need_k - 96; s < need_k + 64; s += 4)); do sizes+=" $s"; done
hit=""
for size in $sizes; do
    mount -t tmpfs -o size=${size}k granule-test "$mnt" || exit 99
    "$g" run "$tmp/s.ini" --out "$out" --quiet >/dev/null 2>"$tmp/err.txt"
    rc=$?
    file="$(grep -oE 'disk full[^:]* (while writing|output folder) [^ :]+' "$tmp/err.txt" | sed "s|.*$out/||;s|.*output folder.*|(folder)|" | head -1)"
    case $rc in
        0) umount "$mnt"; echo "${size} KiB: completed"; break ;;
        6) grep -q "continue it with granule run --resume $out" "$tmp/err.txt" || { cat "$tmp/err.txt"; echo "FAIL: ${size} KiB: exit 6 without how to resume"; exit 1; }
           [[ -f "$out/checkpoint" ]] || { echo "FAIL: ${size} KiB: exit 6 but no checkpoint"; exit 1; }
           if [[ -f "$out/summary.json" ]]; then
               grep -qE '"status":[[:space:]]*"write_failed"' "$out/summary.json" || { echo "FAIL: ${size} KiB: summary.json does not say write_failed"; exit 1; }
           fi
           again=(--resume "$out") ;;
        1) [[ ! -f "$out/checkpoint" ]] || { cat "$tmp/err.txt"; echo "FAIL: ${size} KiB: exit 1 with a checkpoint kept"; exit 1; }
           again=("$tmp/s.ini" --out "$out" --force) ;;
        *) cat "$tmp/err.txt"; echo "FAIL: ${size} KiB: exit $rc"; exit 1 ;;
    esac
    hit+=" ${file:-?}"
    mount -o remount,size=8m "$mnt" # space freed
    "$g" run "${again[@]}" --quiet >/dev/null 2>"$tmp/err2.txt" || { cat "$tmp/err.txt" "$tmp/err2.txt"; echo "FAIL: ${size} KiB: run ${again[*]} after freeing space failed"; exit 1; }
    diff -r -q -x summary.json "$tmp/ref" "$out" || { echo "FAIL: ${size} KiB (stopped at ${file}, exit $rc): outputs differ from the uninterrupted run"; exit 1; }
    python3 "$tmp/same.py" "$tmp/ref/summary.json" "$out/summary.json" || { echo "FAIL: ${size} KiB (stopped at ${file})"; exit 1; }
    echo "${size} KiB: exit $rc at ${file:-?}, then ${again[0]} gave identical outputs"
    umount "$mnt"
done
# every kind of output file filled the disk at least once (a table or, at its commit, the notes
# sidecar NAME.meta.json written just before it is moved into place)
for want in 'temperature\.(csv|meta\.json)' 'ledger\.(csv|meta\.json)' 'snapshots/' 'blocks\.(csv|meta\.json)' \
            'pv[a-z_]*\.(csv|meta\.json)' scene.ini summary.json; do
    grep -qE "(^| )$want" <<<"$hit" || { echo "FAIL: no size of the scan filled the disk while writing $want (hit:$hit)"; exit 1; }
done
echo "files that filled the disk:$(tr ' ' '\n' <<<"$hit" | sed 's|snapshots/.*|snapshots/|' | sort -u | tr '\n' ' ')"
SH
"${ns[@]}" bash "$tmp/scan.sh" "$g" "$tmp"
rc=$?
[[ $rc == 0 ]] || { echo "FAIL: test_disk_full_resume (scan exit $rc)" >&2; exit 1; }
echo "test_disk_full_resume: passed"
