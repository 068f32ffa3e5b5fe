#!/usr/bin/env bash
# Regenerate tests/fuzz/corpus/checkpoint/ from real checkpoints of the scene the checkpoint
# harness restores into (FUZZ_SCENE in tests/fuzz/fuzz_checkpoint.c; keep the two in step):
#   tests/fuzz/gen-corpus-checkpoint.sh build/granule
set -euo pipefail
g="$1"
out="$(cd "$(dirname "$0")" && pwd)/corpus/checkpoint"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/s.ini" <<'INI'
[system]
dim = 2
N = 16
packing_fraction = 0.3
[placement]
kind = random
[model]
tangential = tangential_dashpot
[integrator]
steps_per_contact = 20
[run]
warmup = 0
duration = 0.002
sample_every = 1e-4
checkpoint_every = 5e-4
[analysis]
observables = moments
[output]
plots = false
INI
mkdir -p "$out"
# at step 0 (the wall-time budget is spent at once): the harness's scene exactly
"$g" run "$tmp/s.ini" --out "$tmp/a" --wall-limit 0.0001 >/dev/null 2>&1 || [[ $? == 4 ]]
cp "$tmp/a/checkpoint" "$out/step0.ckpt"
# mid-run, another seed and duration (the scene compare then names the differing key)
"$g" run "$tmp/s.ini" --out "$tmp/b" --set run.duration=20 --set run.seed=7 --wall-limit 1 >/dev/null 2>&1 || [[ $? == 4 ]]
cp "$tmp/b/checkpoint" "$out/midrun-other-scene.ckpt"
# edge cases: magic only, a header cut short, the first 100 bytes
printf 'GRCHKPT\n' > "$out/magic-only.ckpt"
head -c 40 "$tmp/a/checkpoint" > "$out/header-cut.ckpt"
head -c 100 "$tmp/a/checkpoint" > "$out/truncated.ckpt"
ls -l "$out"
