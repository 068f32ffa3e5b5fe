#!/usr/bin/env bash
# The bad-input battery (issue 14): one table of scene, arguments, expected exit code, words the
# message must hold and the state of the output folder afterwards. Every refusal must exit with
# the documented code, explain itself in words a user can act on, escape binary bytes, and leave
# the output folder exactly as it was: absent when it was absent (no scene.ini, no empty
# folder), byte for byte the earlier run or comparison when one was there.
#
# usage: tests/test_bad_inputs.sh path/to/granule [--list]
# A case that still runs after 20 s fails (exit 124): a refusal is immediate.
# Prints one line per case and "N passed, M failed"; exits non-zero if any case failed.
set -uo pipefail
if [[ $# -lt 1 || ! -x "$1" ]]; then
    echo "usage: $0 path/to/granule" >&2
    exit 2
fi
G=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
TMP=$(mktemp -d "${TMPDIR:-/tmp}/granule-bad-inputs-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export CI=1

# the base scene: a 1D ring of 20 particles, 10 samples; --set varies it per case
BASE="$TMP/base.ini"
printf '%s\n' '[system]' 'dim = 1' 'N = 20' 'reduced_length = 0.1' '[placement]' 'kind = uniform' \
    '[run]' 'warmup = 0' 'duration = 0.01' 'sample_every = 1e-3' '[output]' 'plots = false' >"$BASE"
# fixtures an output folder may start from: a finished run and a finished comparison
"$G" run "$BASE" --out "$TMP/fixture-run" >/dev/null 2>&1 || { echo "FAIL: fixture run" >&2; exit 1; }
"$G" compare "$BASE" --models spring_dashpot,spring_dashpot@clamp --out "$TMP/fixture-compare" >/dev/null 2>&1 ||
    { echo "FAIL: fixture compare" >&2; exit 1; }
# a run of another seed with snapshots and pv.csv (what --force must not leave behind)
"$G" run "$BASE" --out "$TMP/fixture-snap" --set analysis.observables=pv --set output.snapshot_every=1e-3 --set run.seed=7 \
    >/dev/null 2>&1 || { echo "FAIL: fixture run with snapshots" >&2; exit 1; }
mkdir -p "$TMP/ckdir/checkpoint" && cp "$TMP/fixture-run/scene.ini" "$TMP/ckdir/"
mkdir -p "$TMP/ckzero" && cp "$TMP/fixture-run/scene.ini" "$TMP/ckzero/" && ln -s /dev/zero "$TMP/ckzero/checkpoint"
# runs stopped by a full disk (docs/checkpoints.md, "A full disk"): summary.json says write_failed;
# one kept its checkpoint (a fresh run over it must point to --resume), one had none to keep
cp -a "$TMP/fixture-run" "$TMP/wf-ck" && sed -i 's/"status":[[:space:]]*"completed"/"status": "write_failed"/' "$TMP/wf-ck/summary.json" &&
    echo not-a-checkpoint >"$TMP/wf-ck/checkpoint"
cp -a "$TMP/wf-ck" "$TMP/wf-nock" && rm "$TMP/wf-nock/checkpoint"

# snapshot of a folder: every path with its type and content hash ("absent" when it does not exist)
state() {
    [[ -e $1 ]] || { echo absent; return; }
    (cd "$1" && find . -printf '%y %p\n' | sort && find . -type f -print0 | sort -z | xargs -0 -r sha256sum)
}

# The table. Fields are separated by " | ":
#   SCENE   base | file:TEXT (printf %b; the scene file holds TEXT) | dir (a folder) | missing
#   ARGS    the command after `granule`, with $S the scene, $O the output folder (eval'd)
#   EXIT    the expected exit code
#   WORDS   ';'-separated texts the message must contain; !TEXT must not appear; ASCII: the
#           message is printable ASCII only
#   FOLDER  new (the output folder does not exist and must not afterwards) | run | compare
#           (it starts as a copy of that fixture and must end byte for byte the same) | foreign
#           (the fixture run with a file of the user's, notes.txt: --force must not empty it) |
#           scene-inside (the fixture run with the user's scene file my.ini) | snap (a run with
#           snapshots) | failed (the fixture run, its status failed: stopped before a checkpoint)
cases=$(cat <<'TABLE'
base | run $S --out $O --set model.eps_n=1.5 | 2 | eps_n;[0, 1] | new
base | run $S --out $O --set model.eps_n=-0.1 | 2 | eps_n;[0, 1] | new
base | run $S --out $O --set system.dim=4 | 2 | dim;[1, 3] | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[model]\nrolling = rolling_friction\ntangential = sliding_friction\n | run $S --out $O | 2 | :6:;[model] rolling;needs dim = 2 or 3, [model] rotation = true;given dim = 3, rotation = false | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[model]\nrotation = true\ninertia_factor = 1.5\ntangential = tangential_dashpot\n | run $S --out $O | 2 | :7:;inertia_factor;(0, 1] | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[model]\nrotation = true\ntangential = tangential_spring\n[integrator]\nkind = hybrid\n | run $S --out $O | 2 | [model] tangential = tangential_spring;keeps a contact history, which only the verlet integrator carries;given [integrator] kind = hybrid (allowed: verlet) | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[integrator]\nkind = hybrid\n[boundary]\nz = walls\n | run $S --out $O | 2 | :6:;[noise] mode;symmetrised with walls and kind = hybrid;allowed with walls: com | none | new
file:[system]\ndim = 3\nN = 64\npacking_fraction = 0.1\n[model]\nnormal = hard_sphere\nrotation = true\nbeta_mu = 0.2\n[integrator]\nkind = event\n | run $S --out $O | 2 | [model] beta_mu = 0.2 with beta = -1;smooth discs and spheres;set beta in (-1, 1] | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.3\n[model]\nnormal = hard_sphere\n[integrator]\nkind = event\n | run $S --out $O | 2 | 2.41 particle diameters;event-driven integrator needs at least 4;[system] N or L | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[gravity]\ngz = -9.81\n | run $S --out $O | 2 | :6:;[gravity] gz;periodic axis;[boundary] z = walls | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[gravity]\ngy = -9.81\n | run $S --out $O | 2 | :6:;[gravity] gy;periodic axis;[boundary] y = walls | new
file:[system]\ndim = 2\nN = 8\npacking_fraction = 0.1\n[boundary]\nz = walls\n | run $S --out $O | 2 | :6:;[boundary] z;only for dim = 3;z = periodic | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[boundary]\nvibrate = z\namplitude = 1e-3\nfrequency = 50\n | run $S --out $O | 2 | :6:;[boundary] vibrate;[boundary] z = periodic;an axis with walls | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[placement]\nkind = hexagonal\n | run $S --out $O | 2 | :6:;[placement] kind;hexagonal;allowed in 3D: cubic | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.1\n[analysis]\nobservables = gaps\n | run $S --out $O | 2 | :6:;[analysis] observables;gaps is not defined for dim = 3;allowed in 3D: moments | new
file:[system]\ndim = 1\nN = 20\n[analysis]\nobservables = profile\nprofile_axis = 1\n | run $S --out $O | 2 | [analysis] profile_axis;(y) in a 1D system;allowed in 1D: 0 (x) or -1 | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[analysis]\nobservables = profile\nprofile_axis = 2\n | run $S --out $O | 2 | [analysis] profile_axis;2 (z) in a 2D system;allowed in 2D: 0 (x), 1 (y) or -1 | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[analysis]\nobservables = profile\nprofile_bins = 0\n | run $S --out $O | 2 | :7:;[analysis] profile_bins;allowed range [1, 100000] | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[species]\ndistribution = uniform\nradius_min = 1e-3\nradius_max = 2e-3\ndensity = 5\n[analysis]\nobservables = profile, species\n | run $S --out $O | 2 | :11:;[analysis] observables;species needs [species] lists;allowed with a radius distribution: moments, pv, msd, vacf, postcollision, collisions, profile, clusters, sk, pair, vcorr, freepath, gaps, pressure | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[species]\ndistribution = uniform\nradius_min = 1e-3\nradius_max = 2e-3\ndensity = 5\n[analysis]\nobservables = species\n | run $S --out $O | 2 | :11:;[analysis] observables;species needs [species] lists;allowed with a radius distribution: moments | new
file:[system]\ndim = 3\nN = 8\npacking_fraction = 0.75\n | run $S --out $O | 2 | :4:;packing_fraction;0.7405;(0, 0.7405] | new
file:[system]\ndim = 3\nN = 8\nreduced_length = 0.1\n | run $S --out $O | 2 | :4:;reduced_length;only for dim = 1 | new
file:[system]\ndim = 3\nN = 100\npacking_fraction = 0.35\n[placement]\nkind = random\n | run $S --out $O | 2 | kind = random;phi = 0.350;(0, 0.3];cubic | new
file:[system]\ndim = 3\nN = 9\npacking_fraction = 0.2\n | run $S --out $O | 2 | kind = cubic;3 sites per edge;0.1745 | new
file:[system]\ndim = 3\nN = 33\npacking_fraction = 0.5\n[placement]\nkind = fcc\n | run $S --out $O | 2 | kind = fcc;3 cells per edge;0.2263 | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[placement]\nkind = cubic\n | run $S --out $O | 2 | :6:;[placement] kind;cubic is a 3D lattice;allowed in 2D: hexagonal | new
base | run $S --out $O --set system.N=0 | 2 | N | new
base | run $S --out $O --set system.N=abc | 2 | N | new
base | run $S --out $O --set system.N=5.5 | 2 | N | new
base | run $S --out $O --set system.N=1e9 | 2 | N | new
base | run $S --out $O --set system.radius=0 | 2 | radius | new
base | run $S --out $O --set system.mass=-1 | 2 | mass | new
base | run $S --out $O --set system.L=0 | 2 | L | new
base | run $S --out $O --set system.packing_fraction=0.5 | 2 | packing_fraction | new
base | run $S --out $O --set system.dim=2 --set system.packing_fraction=0.95 | 2 | packing_fraction | new
base | run $S --out $O --set run.sample_every=0 | 2 | sample_every | new
base | run $S --out $O --set run.sample_every=nan | 2 | sample_every | new
base | run $S --out $O --set run.duration=-1 | 2 | duration | new
base | run $S --out $O --set run.duration=inf | 2 | duration | new
base | run $S --out $O --set run.warmup=-1 | 2 | warmup | new
base | run $S --out $O --set run.seed=-1 | 2 | seed | new
base | run $S --out $O --set run.seed=12abc | 2 | seed | new
base | run $S --out $O --set run.ledger_tolerance=2 | 2 | ledger_tolerance | new
base | run $S --out $O --set run.checkpoint_every=-1 | 2 | checkpoint_every | new
base | run $S --out $O --set run.wall_limit=-1 | 2 | wall_limit | new
base | run $S --out $O --set run.progress=maybe | 2 | progress | new
base | run $S --out $O --set noise.D=-1 | 2 | D | new
base | run $S --out $O --set noise.mode=bogus | 2 | mode;symmetrised | new
base | run $S --out $O --set noise.com_interval=0 | 2 | com_interval | new
base | run $S --out $O --set noise.precision=half | 2 | [noise] precision;'half' is not allowed;choose one of double | new
base | run $S --out $O --set noise.precision=single --set integrator.kind=hybrid | 2 | [noise] precision;single needs an integrator that draws it (verlet; given hybrid);allowed otherwise: double | new
base | run $S --out $O --set driving.kind=bogus | 2 | [driving] kind;bogus;choose one of rfm | new
base | run $S --out $O --set driving.kind=langevin --set driving.tau=0 | 2 | [driving] tau;(0, inf) | new
base | run $S --out $O --set driving.kind=langevin --set driving.tau=-1 | 2 | [driving] tau;(0, inf) | new
base | run $S --out $O --set driving.kind=langevin --set driving.T_bath=-0.1 | 2 | [driving] T_bath;[0, inf) | new
base | run $S --out $O --set driving.kind=langevin --set driving.T_bath=nan | 2 | [driving] T_bath;not a number | new
base | run $S --out $O --set driving.gamma=1 | 2 | [driving] gamma;unknown key;T_bath;tau | new
file:[system]\ndim = 1\nN = 20\nreduced_length = 0.1\n[driving]\nkind = langevin\ntau = 0\n | run $S --out $O | 2 | :7:;[driving] tau;(0, inf) | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[placement]\nkind = uniform\n[gravity]\ngy = -9.81\n | run $S --out $O | 2 | :8:;[gravity] gy;[boundary] y = walls;allowed with y = periodic: gy = 0 | new
file:[system]\ndim = 1\nN = 1\nL = 0.04\n[placement]\nkind = uniform\n[boundary]\nx = walls\n[gravity]\ngx = -9.81\n[integrator]\nkind = hybrid\n | run $S --out $O | 2 | :12:;[integrator] kind;kind = hybrid runs walls and gravity in 2D and 3D;allowed with walls or gravity in 1D: verlet | event | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[placement]\nkind = uniform\n[boundary]\ny = walls\n[gravity]\ngy = -2000\n | run $S --out $O | 2 | :10:;[gravity] gy;[-1000, 1000] | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[boundary]\ny = wall\n | run $S --out $O | 2 | :6:;[boundary] y;periodic|walls | new
file:[system]\ndim = 1\nN = 1\nL = 0.04\n[boundary]\ny = walls\n | run $S --out $O | 2 | :6:;[boundary] y;dim = 2 | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[boundary]\ny = walls\neps_n = 1.5\n | run $S --out $O | 2 | :7:;[boundary] eps_n;allowed range [0, 1] | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[boundary]\ny = walls\neps_t = -0.2\n | run $S --out $O | 2 | :7:;[boundary] eps_t;allowed range [0, 1] | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[boundary]\ny = walls\nmu = -1\n | run $S --out $O | 2 | :7:;[boundary] mu;allowed range [0, inf) | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[boundary]\ny = walls\nvibrate = y\nmotion = square\n | run $S --out $O | 2 | :8:;[boundary] motion;sine|sawtooth | new
file:[system]\ndim = 2\nN = 400\nL = 0.12\n[placement]\nkind = hexagonal\n[boundary]\ny = walls\n | run $S --out $O | 2 | particle 0;overlaps a wall;[r, L - r];[placement] kind | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[placement]\nkind = uniform\n[boundary]\ny = walls\nvibrate = x\n | run $S --out $O | 2 | :9:;[boundary] vibrate;[boundary] x = periodic;an axis with walls | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[placement]\nkind = uniform\n[boundary]\ny = walls\nvibrate = y\namplitude = 0.02\n | run $S --out $O | 2 | :10:;[boundary] amplitude;[0, L / 4) = [0, 0.01) m | new
file:[system]\ndim = 2\nN = 1\nL = 0.04\n[boundary]\ny = walls\nvibrate = y\nfrequency = -5\n | run $S --out $O | 2 | :8:;[boundary] frequency;[0, inf) | new
base | run $S --out $O --set placement.kind=bogus | 2 | kind;uniform | new
base | run $S --out $O --set placement.v0=-1 | 2 | v0 | new
base | run $S --out $O --set integrator.kind=bogus | 2 | kind;bogus;verlet;event;hybrid | new
base | run $S --out $O --set integrator.steps_per_contact=5 | 2 | steps_per_contact | new
base | run $S --out $O --set integrator.skin=11 | 2 | skin | new
base | run $S --out $O --set integrator.kick_interval=0 | 2 | kick_interval | new
file:[system]\ndim = 1\nN = 20\nreduced_length = 0.1\n[placement]\nkind = uniform\n[integrator]\ndt = 1e-9\nsteps_per_contact = 50\n | run $S --out $O | 2 | dt;steps_per_contact | new
base | run $S --out $O --set integrator.dt=1e-3 | 2 | dt | new
base | run $S --out $O --set model.normal=nosuch | 2 | normal;spring_dashpot | new
base | run $S --out $O --set model.tangential=nosuch | 2 | tangential | new
base | run $S --out $O --set model.k_s=0 | 2 | k_s | new
base | run $S --out $O --set model.clamp=perhaps | 2 | clamp | new
base | run $S --out $O --set analysis.observables=nosuch | 2 | observables;nosuch | new
base | run $S --out $O --set analysis.pv_bins=5 | 2 | pv_bins | new
base | run $S --out $O --set analysis.moments_max=0 | 2 | moments_max | new
base | run $S --out $O --set analysis.gaps_h_max=300 | 2 | gaps_h_max | new
base | run $S --out $O --set analysis.observables=gaps --set analysis.gaps_h_max=25 | 2 | gaps_h_max | new
base | run $S --out $O --set output.snapshot_every=-1 | 2 | snapshot_every | new
base | run $S --out $O --set output.plots=maybe | 2 | plots | new
base | run $S --out $O --set bogus.key=1 | 2 | unknown section | new
base | run $S --out $O --set system.bogus=1 | 2 | unknown key | new
base | run $S --out $O --set noequals | 2 | section.key=value | new
base | run $S --out $O --set system.dim=2 --set system.N=50 --set system.L=0.01 --set placement.kind=square | 2 | N | new
file:[system]\ndim = 2\nN = 50\n[model]\neps_n = 1.5\n | run $S --out $O | 2 | :5:;eps_n;[0, 1] | new
file:[system]\ndim = 2\ndim = 1\n | run $S --out $O | 2 | :3:;given twice | new
file:[sytem]\ndim = 1\n | run $S --out $O | 2 | :1:;unknown section | new
file:[system]\nthis is not ini\n | run $S --out $O | 2 | :2:;not an INI line | new
file:[system]\ndim = 1\nL = 0.1\nreduced_length = 0.1\n | run $S --out $O | 2 | L;reduced_length | new
missing | run $S --out $O | 2 | cannot open | new
dir | run $S --out $O | 2 | not a regular file | new
file: | run $S --out $O | 2 | empty | new
file:; only a comment\n# and another\n | run $S --out $O | 2 | [system] | new
file:[run]\nduration = 0.01\n | run $S --out $O | 2 | [system] | new
file:[system]\ndim = 1\nN = 5\x000\n | run $S --out $O | 2 | :3:;control | new
file:[system]\ndim = 1\nN = 5\x01\n | run $S --out $O | 2 | :3:;control;ASCII | new
file:[system]\n\xff\xfe = 1\n | run $S --out $O | 2 | :2:;\\xff;ASCII | new
file:[system]\ndim = 1\n[output]\ndir = 0123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789\nplots = 1x\n | run $S | 2 | :5:;plots | new
file:[system]\ndim = 1\n[run]\nseed = 0123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789012345678901234567890123456789\n | run $S --out $O | 2 | :4:;seed | new
base | run $S --out $O --set integrator.dt=1e-30 | 2 | integrator.dt;run.sample_every | new
base | run $S --out $O --set run.sample_every=0.1 | 2 | run.sample_every;run.duration | new
base | run $S --out $O --set run.sample_every=1e-9 | 2 | run.sample_every;dt | new
base | run $S --out $O --set run.duration=0 | 2 | run.duration | new
base | run $S --out $O --set run.duration=0.0105 | 2 | run.duration;whole number | new
base | run $S --out $O --set run.warmup=0.0005 | 2 | run.warmup;whole number | new
base | run $S --out $O --set output.snapshot_every=1e-12 | 2 | output.snapshot_every;dt | new
base | run $S --out $'$O\nnext' | 2 | newline | new
base | run $S --out $O --force --set model.eps_n=2 | 2 | eps_n | run
base | run $S --out $O --force --set integrator.dt=1e-30 | 2 | integrator.dt | run
base | run $S --out $O | 2 | summary.json;--force | run
base | run $S --out $O --threads 0 | 2 | --threads | new
base | run $S --out $O --bogus | 2 | unknown option | new
base | run $S $S --out $O | 2 | one scene | new
base | run --out $O | 2 | usage | new
base | run --resume $O | 2 | $O | new
base | run --resume $O --out $O | 2 | --resume | run
base | run --resume $O | 2 | completed | run
base | run --resume $O | 2 | status failed;before its first checkpoint;granule run $O/scene.ini --out $O --force | failed
base | run $S --out $O | 2 | $O already holds a run;--force | failed
base | run --resume $TMP/ckdir | 2 | checkpoint | new
base | run --resume $TMP/ckzero | 2 | checkpoint | new
base | run $S --out $TMP/wf-ck | 2 | --resume $TMP/wf-ck;--force | new
base | run --resume $TMP/wf-ck | 2 | not a granule checkpoint | new
base | run --resume $TMP/wf-nock | 2 | checkpoint | new
base | run $S --out $O --wall-limit abc | 2 | wall_limit | new
base | nosuchcommand | 2 | unknown command | new
base | collide --case 9 | 2 | case | new
base | collide --reference --rtol 1 | 2 | allowed range | new
base | collide --model hard_sphere --reference | 2 | reference;hard_sphere | new
base | collide --dim 3 --model hard_sphere --omega1 1,0,0 | 2 | --omega1/--omega2;initial spins need rotation = true;allowed without: 0,0,0 | new
base | collide --eps-n 2 | 2 | eps | new
base | collide --model nosuch | 2 | nosuch;!collide: collide: | new
base | collide --bogus | 2 | --bogus;!collide: collide: | new
base | collide --dim 4 | 2 | --dim;1 to 3 | new
base | collide --dim 3 --speed 1 --angle 30 --omega1 0,0,5 | 2 | --omega1/--omega2;rotation = true | new
base | collide --dim 3 --speed 1 --angle 30 --model spring_dashpot+tangential_dashpot --set rotation=true --omega1 150 | 2 | --omega1 150;WX,WY,WZ | new
base | collide --dim 3 --speed 1 --angle 30 --model spring_dashpot+tangential_dashpot --set rotation=true --omega2 0,0,nan | 2 | --omega2 0,0,nan;three finite numbers | new
base | collide --speed 1 --angle 30 --model spring_dashpot+tangential_dashpot --set rotation=true --omega1 1,2,3 | 2 | --omega1 1,2,3;needs --dim 3 | new
base | collide --steps-per-contact 5 | 2 | steps_per_contact;!collide: collide: | new
base | collide --speed 0 | 2 | --speed;> 0;!collide: collide: | new
base | collide --speed 1 --angle 90 | 2 | --angle;[0, 90) | new
base | collide --speed 1 --angle -5 | 2 | --angle;[0, 90) | new
base | collide --angle 30 | 2 | --angle;--speed | new
base | collide --speed 1 --angle 30 --dim 1 | 2 | --dim 2 | new
base | collide --speed 1 --angle 30 --omega1 5 | 2 | --omega1;rotation | new
base | collide --speed 1 --model hard_sphere --set rotation=true --omega2 5 | 2 | --omega2;hard_sphere | new
base | cost $S --out $O --tolerance 0 | 2 | --tolerance;(0, 1) | new
base | cost $S --out $O --tolerance 150% | 2 | --tolerance | new
base | cost $S --out $O --observable nosuch | 2 | nosuch;T or loss | new
base | cost $S --out $O --calibrate -1 | 2 | --calibrate | new
base | cost $S --out $O --phases 0 | 2 | --phases | new
base | cost $S --out $O --set model.normal=hard_sphere --set model.tangential=none --set integrator.kind=event | 2 | hard_sphere;instantaneous | new
missing | cost $S --out $O | 2 | cannot open | new
base | cost $S --out $O | 2 | $O already holds a run;summary.json;--force | run
base | cost $S --out $O --set model.eps_n=0 | 2 | t_c;nothing to resolve | new
base | compare $S --out $O --models nosuch | 2 | nosuch | new
base | compare $S --out $O --models spring_dashpot@bogus | 2 | @clamp | new
base | compare $S --out $O --models nosuch@event | 2 | nosuch;spring_dashpot;hard_sphere | new
base | compare $S --out $O --models spring_dashpot+nosuch | 2 | nosuch;tangential_dashpot;sliding_friction | new
base | compare $S --out $O --models spring_dashpot@warp | 2 | @warp;@verlet;@hybrid | new
base | compare $S --out $O --models spring_dashpot@event@hybrid | 2 | twice | new
base | compare $S --out $O --models spring_dashpot,spring_dashpot@event | 2 | spring_dashpot@event: ;hard_sphere | new
base | compare $S --out $O --models spring_dashpot,spring_dashpot | 2 | share the folder | new
base | compare $S --out $O | 2 | usage | new
missing | compare $S --out $O --models spring_dashpot | 2 | cannot open | new
base | compare $S --out $O --models spring_dashpot,spring_dashpot@clamp | 2 | --force | compare
base | compare $S --out $O --models spring_dashpot | 2 | --force | compare
base | compare $S --out $O --models spring_dashpot --set model.eps_n=3 | 2 | eps_n | compare
missing | sweep $S | 2 | cannot open | new
missing | reproduce $S --out $O | 2 | not a campaign file | new
base | reproduce nosuch --out $O | 2 | nosuch;--list | new
base | reproduce ch3-moments --fidelity medium --out $O | 2 | quick or full | new
file:[campaign]\nbogus = 1\n | reproduce $S --out $O | 2 | bogus;title, covers | new
file:[campaign]\ntitle = t\nscene = nosuch.ini\n | reproduce $S --out $O | 2 | nosuch.ini | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\nabout = xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\n | reproduce $S --out $O | 2 | :4: line longer than 198 characters | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = curve\ny = g\n | reproduce $S --out $O | 2 | kind = curve needs table | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = mean\ny = T_mean\nrestates = nosuch\n | reproduce $S --out $O | 2 | restates = nosuch;not another result | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = power_law\ny = T_mean\nx = system.N\nlocal_slopes = maybe\n | reproduce $S --out $O | 2 | local_slopes = maybe;true or false | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = power_law\ny = T_mean\nx = system.N\nlocal_slopes = true\nslope_span = 1\n | reproduce $S --out $O | 2 | slope_span = 1;from 2 to 8 | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = power_law\ny = T_mean\nx = system.N\nslope_span = 3\n | reproduce $S --out $O | 2 | slope_span needs kind = power_law and local_slopes = true | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[result a]\ntransform = flip\n | reproduce $S --out $O | 2 | transform = flip;bisection_collapse | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = curve\ntable = pv.csv\nx = v\ny = density\noverlay = power_law\n | reproduce $S --out $O | 2 | overlay = power_law needs overlay_exponent and a window | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = curve\ntable = pv.csv\nx = v\ny = density\noverlay_exponent = 0\n | reproduce $S --out $O | 2 | overlay_exponent = 0;not 0 | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = curve\ntable = pv.csv\nx = v\ny = density\noverlay = column\noverlay_y = fit\ntransform = log_ratio\n | reproduce $S --out $O | 2 | overlay = column needs overlay_y and no transform | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = curve\ntable = pv.csv\nx = v\ny = density\ntransform = scale_at\n | reproduce $S --out $O | 2 | transform = scale_at needs collapse_at | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[result a]\nkind = curve\ntable = pv.csv\nx = v\ny = density\noverlay = sine\n | reproduce $S --out $O | 2 | overlay = sine;allowed bisection, power_law, column | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[result a]\nverdict = fine: we agree\n | reproduce $S --out $O | 2 | :5:;verdict = fine;partly explained: WHY | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[result a]\nverdict = explained:\n | reproduce $S --out $O | 2 | verdict = explained:;unexplained: WHY | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N+model.eps_n = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n | reproduce $S --out $O | 2 | linked;nothing was run | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[set]\nmodel.nosuch = 1\n | reproduce $S --out $O | 2 | nosuch;nothing was run | new
file:[sweep]\nbogus = 1\n | sweep $S | 2 | bogus | new
file:[sweep]\nseeds = 1, 2, 1\n[vary]\nsystem.N = 10\n | sweep $S | 2 | 1 is listed twice | new
file:[sweep]\nseeds = 1\nseeds = 2\n[vary]\nsystem.N = 10\n | sweep $S | 2 | given twice | new
file:[sweep]\nseeds = 0x10\n[vary]\nsystem.N = 10\n | sweep $S | 2 | decimal digits | new
file:[sweep]\nseeds = 1\n[vary]\nrun.seed = 1, 2\n | sweep $S | 2 | seeds are given twice | new
file:[sweep]\n[vary]\nrun.seed = 1, -2\n | sweep $S | 2 | decimal digits | new
file:[sweep]\n[vary]\nsystem.N+run.seed = 10/1, 12/2\n | sweep $S | 2 | cannot be linked | new
file:[sweep]\n[vary]\nsystem.N = 10, 12\nmodel.eps_n = 0.5\nsystem.N = 14\n | sweep $S | 2 | system.N: given twice | new
file:[sweep]\n[vary]\nsystem.N = 10, 12, 10\n | sweep $S | 2 | '10' is listed twice | new
file:[sweep]\n[vary]\nsystem.N = 10\n[set]\nsystem.N = 12\n | sweep $S | 2 | either set or varied | new
file:[sweep]\n[set]\nsystem.N = 12\n[vary]\nsystem.N = 10\n | sweep $S | 2 | either set or varied | new
file:[sweep]\n[set]\nrun.seed = 3\n[vary]\nsystem.N = 10\n | sweep $S | 2 | [sweep] seeds | new
file:[sweep]\n[set]\nrun.warmup = 0\nrun.warmup = 0.1\n[vary]\nsystem.N = 10\n | sweep $S | 2 | given twice | new
file:[sweep]\n[vary]\nsystem.N = 10, 9999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999999\n | sweep $S | 2 | at most 127 characters | new
file:[sweep]\n[vary]\nsystem.N = 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42\nsystem.N = 43, 44, 45, 46, 47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63, 64, 65, 66, 67, 68, 69, 70, 71, 72, 73, 74\n | sweep $S | 2 | at most 64 values | new
file:[sweep]\nscene = /dev/null\nout = /nonexistent-granule-out\n[vary]\nsystem.N = 10\n | sweep $S | 2 | not a regular file | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n | export lammps $S --out $O | 2 | $O already holds a run;summary.json;--force | run
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n | export lammps $S --out $O | 2 | $O already holds a comparison;compare.json;--force | compare
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n | export lammps $S --out $O --force | 2 | notes.txt;did not write | foreign
base | export lammps $S --out $O --force | 2 | LAMMPS has no 1D | run
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[model]\nnormal = hard_sphere\ntc = offf\n[integrator]\nkind = event\n | run $S --out $O | 2 | :7:;[model] tc;offf;[0, inf) s;nor off | new
base | run $S --out $O --set model.tc=-1 | 2 | [model] tc;-1;nor off | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[model]\neps_n = 0\nnormal = hard_sphere\n[integrator]\nkind = event\n | run $S --out $O | 2 | :6:;[model] eps_n;hard_sphere's range;(0, 1] | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[model]\nnormal = spring_dashpot\n[integrator]\nkind = event\n | run $S --out $O | 2 | :8:;[integrator] kind;needs an event rule;hard_sphere;verlet | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[model]\nnormal = hard_sphere\n[integrator]\nkind = event\n | export lammps $S --out $O | 2 | time-stepped only;integrator.kind = verlet | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[model]\nnormal = hertz\n | export lammps $S --out $O | 2 | model.normal = hertz;no gran/hooke equivalent | new
file:[system]\ndim = 2\nN = 20\npacking_fraction = 0.1\n[model]\ntangential = sliding_friction\n | export lammps $S --out $O | 2 | model.tangential = sliding_friction;no pure Coulomb | new
base | run $S --out $O | 2 | $O already holds a comparison;compare.json;--force | compare
base | run $S --out $O --force | 2 | $O/notes.txt;did not write;--force | foreign
base | run $O/my.ini --out $O --force | 2 | $O/my.ini;did not write | scene-inside
base | compare $S --out $O --models spring_dashpot | 2 | $O already holds a run;summary.json;--force | run
base | compare $S --out $O --models spring_dashpot --force | 2 | notes.txt;did not write | foreign
file:[sweep]\nscene = ../base.ini\nout = out\n[vary]\nsystem.N = 10\n | sweep $S | 2 | out already holds a run;summary.json;--force | run
file:[sweep]\nscene = ../base.ini\nout = out\n[vary]\nsystem.N = 10\n | sweep $S | 2 | out already holds a comparison;--force | compare
file:[sweep]\nscene = ../base.ini\nout = out\n[vary]\nsystem.N = 10\n | sweep $S --force | 2 | notes.txt;did not write | foreign
base | analyse $O --out $O --force | 2 | --out $O is the folder analysed | snap
base | analyse $O --out $O/analysis | 2 | $O | new
base | analyse $O --set analysis.observables=nosuch | 2 | nosuch | run
base | plot $O | 2 | $O | new
base | reproduce nosuch --out $O | 2 | nosuch | new
base | reproduce fig2.10 --fidelity bogus --out $O | 2 | fidelity | new
base | reproduce ch3-moments --point 12 --out $O | 2 | --point 12: ch3-moments has points 0..11 at quick fidelity | new
base | reproduce ch3-moments --jobs 0 --out $O | 2 | --jobs 0: expected an integer from 1 to 4096 | new
base | reproduce ch3-moments --fidelity full --point x --out $O | 2 | --point x;0..167 at full | new
base | spm bogus | 2 | bogus | new
base | spm circle --out $O --bogus | 2 | --bogus | new
base | bisect --out $O --levels 0 | 2 | levels | new
base | cascade --out $O --levels 20 | 2 | levels | new
base | fokker-planck --out $O --length -1 | 2 | length | new
base | bench bogus | 2 | bogus | new
base | collide --speed 1e6 | 2 | passed through each other;tunnelled;--dt | new
base | collide --speeds 1,1e6 | 2 | 1e+06 m/s;tunnelled | new
base | collide --dt 1e-20 | 2 | dt = 1e-20 s;more than the 1e+07;--dt | new
base | collide --speed 10 --angle 89.999 --model spring_dashpot+tangential_spring | 2 | grazing;turned;--angle | new
base | collide --speed 1 --angle 89.999 --model spring_dashpot+tangential_spring | 2 | never came into contact;--angle | new
base | collide --phases 1000000000 | 2 | --phases 1000000000;from 1 to 1000 | new
base | collide --phases 1e300 | 2 | --phases;from 1 to 1000 | new
TABLE
)
# a note (or thesis, about) continued over lines to more than its 2047 characters is refused, not cut
long_line="note = $(printf 'x%.0s' {1..190})\\n"
long_note="[campaign]\\ntitle = t\\nscene = rfm-1d.ini\\n[result a]\\n"
for _ in {1..11}; do long_note+=$long_line; done
cases+=$'\n'"file:$long_note | reproduce \$S --out \$O | 2 | [result a] note;at most 2047 | new"

# Inputs that must be refused without blocking or crashing (issue 39 items 8, 9, 11, 14). FOLDER
# NAME (not new/run/compare) starts the output folder as a copy of $TMP/fixture-NAME: a run with
# snapshots whose trajectory or dumps were damaged; `analyse $O` must leave it as it was (no
# analysis/ folder).
SNAP="$TMP/snap.ini"
printf '%s\n' '[system]' 'dim = 2' 'N = 20' 'packing_fraction = 0.1' '[placement]' 'kind = uniform' '[run]' 'warmup = 0' \
    'duration = 0.01' 'sample_every = 1e-3' '[output]' 'plots = false' 'snapshot_every = 1e-3' >"$SNAP"
"$G" run "$SNAP" --out "$TMP/fixture-snaps" >/dev/null 2>&1 || { echo "FAIL: fixture run with snapshots" >&2; exit 1; }
L=$(sed -n 's/^L = //p' "$TMP/fixture-snaps/scene.ini")
fix() { cp -a "$TMP/fixture-snaps" "$TMP/fixture-$1" && echo "$TMP/fixture-$1"; }
s3=snapshots/snap_000003.xyz
sed -i '3s/^X [^ ]*/X 1e308/' "$(fix far)/$s3"
sed -i '4s/^X [^ ]* [^ ]*/X 0.01 -1e308/' "$(fix fary)/$s3"
sed -i '2s/Time=[^ ]*/Time=abc/' "$(fix timeabc)/$s3"
sed -i '2s/Time=[^ ]*/Time=nan/' "$(fix timenan)/$s3"
sed -i '2s/Time=[^ ]* //' "$(fix notime)/$s3"
sed -i '2s/Time=[^ ]*/Time=0.0095/' "$(fix order)/$s3"
sed -i '2s/Lattice="[^ ]*/Lattice="0.5/' "$(fix box)/$s3"
d=$(fix fifo) && rm "$d/$s3" && mkfifo "$d/$s3"
d=$(fix ckfifo) && mkfifo "$d/checkpoint" && rm "$d/summary.json"
# LAMMPS dumps of the same scene: dump STEPS... writes one frame per timestep, BOX its box length
dump() {
    local box=$1 step
    shift
    for step in "$@"; do
        printf 'ITEM: TIMESTEP\n%s\nITEM: NUMBER OF ATOMS\n20\nITEM: BOX BOUNDS pp pp pp\n0 %s\n0 %s\n-0.003 0.003\n' "$step" "$box" "$box"
        printf 'ITEM: ATOMS id x y vx vy\n'
        for i in $(seq 1 20); do printf '%d 0.00%d 0.00%d 0.1 -0.1\n' "$i" "$i" "$i"; done
    done
}
d=$(fix dumps)
dump "$L" 1000 2000 3000 >"$d/ok.dump"
dump "$L" -1000 1000 >"$d/negative.dump"
dump "$L" 1000 3000 2000 >"$d/decreasing.dump"
dump "$L" 1000 1000 >"$d/repeated.dump"
dump 0.5 1000 2000 >"$d/box.dump"
: >"$d/empty.dump"
mkdir "$d/folder.dump" && mkfifo "$d/fifo.dump"
mkfifo "$TMP/fifo.ini"
printf '[sweep]\nscene = %s\nout = %s\n[vary]\nsystem.N = 10\n' "$TMP/fifo.ini" "$TMP/fifo-sweep-out" >"$TMP/fifo-scene-sweep.ini"
cases+=$'\n'$(cat <<'TABLE'
base | analyse $O --set analysis.observables=sk | 2 | snap_*.xyz, frame 4;x = 1e+308;outside the range | far
base | analyse $O --set analysis.observables=clusters | 2 | frame 4;x = 1e+308 | far
base | analyse $O --set analysis.observables=pressure,pair,pv | 2 | frame 4;x = 1e+308 | far
base | analyse $O --set analysis.observables=sk | 2 | frame 4;y = -1e+308 | fary
base | analyse $O --set analysis.observables=moments | 2 | snap_000003.xyz:2;Time=abc;finite | timeabc
base | analyse $O --set analysis.observables=moments | 2 | snap_000003.xyz:2;Time=nan;finite | timenan
base | analyse $O --set analysis.observables=moments | 2 | snap_000003.xyz:2;no Time= | notime
base | analyse $O --set analysis.observables=moments | 2 | frame 5;not after frame 4;increasing time order | order
base | analyse $O --set analysis.observables=moments | 2 | frame 4;box length 0.5 m;system.L | box
base | analyse $O --set analysis.observables=moments --set run.warmup=1 | 2 | none of its 11 frames;run.warmup = 1 s;nothing to analyse | snaps
base | analyse $O --set analysis.observables=moments | 2 | snap_000003.xyz;not a regular file | fifo
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/negative.dump | 2 | negative.dump:2;timestep -1000 is negative | dumps
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/decreasing.dump | 2 | decreasing.dump:;timestep 2000;increasing time order | dumps
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/repeated.dump | 2 | repeated.dump:;timestep 1000;increasing time order | dumps
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/box.dump | 2 | box.dump, frame 1;box length 0.5 m;system.L | dumps
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/empty.dump | 2 | empty.dump holds no frames | dumps
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/folder.dump | 2 | folder.dump: not a regular file | dumps
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/fifo.dump | 2 | fifo.dump: not a regular file | dumps
base | analyse $O --set analysis.observables=moments --set integrator.dt=1e-6 --lammps-dump $O/nosuch.dump | 2 | nosuch.dump: cannot open | dumps
base | analyse $O --set analysis.observables=moments --out | 2 | --out needs a value;!unexpected argument | snaps
base | analyse $O --set analysis.observables=moments --out $TMP/a-file | 2 | a-file exists but is not a folder | snaps
base | analyse $O --set analysis.observables=moments --lammps-dump $O/ok.dump | 2 | ok.dump;integrator.dt unset;--set integrator.dt | dumps
base | run --resume $O | 2 | checkpoint;not a regular file | ckfifo
base | run $TMP/fifo.ini --out $O | 2 | fifo.ini: not a regular file | new
base | sweep $TMP/fifo.ini | 2 | fifo.ini: not a regular file | new
base | reproduce $TMP/fifo.ini --out $O | 2 | fifo.ini: not a campaign file;not a regular file | new
base | cost $TMP/fifo.ini --out $O | 2 | fifo.ini: not a regular file | new
base | sweep $TMP/fifo-scene-sweep.ini | 2 | fifo.ini: not a regular file | new
base | run --resume $O | 2 | temperature.csv.tmp;No such file | notmp
base | run --resume $O | 2 | checkpoint;symbolic links | ckloop
base | run $S --out $O --set model.k_s=1e308 | 2 | k_s = 1e+308 N/m;w0;allowed;!-nan;!dt = 0 s | new
base | run $S --out $O --set system.radius=1e308 | 2 | [system] radius;[1e-100, 1e+100];!-nan;!reduced_length | new
base | run $S --out $O --set system.mass=1e-300 | 2 | [system] mass;[1e-100, 1e+100] | new
file:[system]\ndim = 1\nN = 20\nreduced_length = 0.1\n[run\nduration = 0.01\n | run $S --out $O | 2 | :5:;unterminated section header '[run';!unknown key | new
base | run $S --out $O --set model.normal=hard_sphere --set model.tangential=none --set integrator.kind=event --set model.eps_n=1.5 | 2 | eps_n;hard_sphere: (0, 1] | new
base | collide --model hard_sphere --eps-n 1.5 | 2 | --eps-n;(0, 1] | new
base | cost $S --out $TMP/a-file | 2 | a-file exists but is not a folder;!calibrating | new
base | run $S --out | 2 | --out needs a value;!unknown option | new
base | compare $S --models | 2 | --models needs a value | new
base | collide --speed | 2 | --speed needs a value | new
base | reproduce ch3-moments --out | 2 | --out needs a value | new
file:[sweep]\n[vary]\nsystem.N = 10\n | sweep $S --array-base 99999999999999999999 --point 0 | 2 | --array-base;from 0 to 1000000000000 | new
file:[sweep]\n[vary]\nsystem.N = 10\n | sweep $S --point 99999999999999999999 | 2 | --point;from 0 to 1000000000000 | new
base | run $S --out $O --set integrator.dt=1e-7 --set integrator.steps_per_contact=50 | 2 | --set integrator.dt=1e-7;give dt or steps_per_contact, not both | new
base | run $S --out $O --set system.L=0.5 --set system.reduced_length=0.1 | 2 | reduced_length;give only one of L | new
base | run $S --out $O --set system.N=0x1p5 | 2 | [system] N;0x1p5 is not an integer written in decimal digits;[1, 1e+08] | new
base | run $S --out $O --set system.N=2e1 | 2 | [system] N;decimal digits | new
base | run $S --out $O --set analysis.moments_max=0x4 | 2 | moments_max;decimal digits | new
file:[system]x\ndim = 1\nN = 20\nreduced_length = 0.1\n | run $S --out $O | 2 | :1:;characters after the section header [system] | new
file:[sweep]\n[vary]\nsystem.N = 10, 1\x002\n | sweep $S | 2 | :3:;control byte 0x00;sweep file | new
file:[sweep]x\n[vary]\nsystem.N = 10\n | sweep $S | 2 | :1:;characters after the section header [sweep] | new
file:[sweep]\n[vary\nsystem.N = 10\n | sweep $S | 2 | :2:;unterminated section header | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1, 1\n | reproduce $S --out $O | 2 | :11:;[sweep.quick] seeds: 1 is listed twice | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[set]\nsystem.N = 12\n | reproduce $S --out $O | 2 | :13:;[set] system.N: also in [vary.quick] system.N | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[campaign]\ntitle = u\n | reproduce $S --out $O | 2 | :13:;[campaign] title: given twice | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[set]\nrun.warmup = 0\nrun.warmup = 1\n | reproduce $S --out $O | 2 | :14:;[set] run.warmup: given twice | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[result a]\nkind = mean\ny = T\n[result b]\nkind = mean\ny = T\n[result a]\nunit = s\n | reproduce $S --out $O | 2 | :19:;[result a]: given twice | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[result a]\nkind = mean\ny = T\nthesis = nan\n | reproduce $S --out $O | 2 | [result a] thesis;nan;finite VALUE | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[result a]\nkind = mean\ny = T\nthesis = *: inf +- 1\n | reproduce $S --out $O | 2 | [result a] thesis;finite VALUE | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[res\x00ult a]\nkind = mean\n | reproduce $S --out $O | 2 | :12:;control byte 0x00;campaign file | new
file:[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[vary.quick]\nsystem.N = 10\n[sweep.quick]\nseeds = 1\n[result a]x\nkind = mean\n | reproduce $S --out $O | 2 | :12:;characters after the section header [result a] | new
TABLE
)
: >"$TMP/a-file"
# a run stopped by its wall limit (exit 4, with a checkpoint), then damaged: its temporary
# temperature.csv lost, or its checkpoint a symlink loop (docs/checkpoints.md: exit 2)
"$G" run "$BASE" --out "$TMP/fixture-stopped" --set run.duration=1000 --wall-limit 2 >/dev/null 2>&1
[[ $? == 4 && -f $TMP/fixture-stopped/checkpoint ]] || { echo "FAIL: fixture stopped by its wall limit" >&2; exit 1; }
cp -a "$TMP/fixture-stopped" "$TMP/fixture-notmp" && rm "$TMP"/fixture-notmp/temperature.csv.tmp*
cp -a "$TMP/fixture-stopped" "$TMP/fixture-ckloop" && rm "$TMP/fixture-ckloop/checkpoint" && ln -s checkpoint "$TMP/fixture-ckloop/checkpoint"

[[ ${2:-} == --list ]] && { printf '%s\n' "$cases"; exit 0; }
passed=0 failed=0 i=0
# report WHAT STDERR-FILE [NOTE]: case $i passed unless problems[] holds something
report() {
    if ((${#problems[@]} == 0)); then
        passed=$((passed + 1))
        echo "ok   $i $1"
    else
        failed=$((failed + 1))
        echo "FAIL $i $1${3:+ $3}"
        printf '     %s\n' "${problems[@]}" "stderr: $(head -c 300 "$2" | tr '\n' ' ' | LC_ALL=C tr -c '[:print:]' '?')"
    fi
}
while IFS= read -r row; do
    [[ -z $row ]] && continue
    i=$((i + 1))
    IFS='|' read -r scene args code words folder <<<"$row"
    scene=${scene# } scene=${scene% } args=${args# } args=${args% } code=${code// /} words=${words# } words=${words% }
    folder=${folder// /}
    c="$TMP/case$i"
    mkdir -p "$c"
    S="$c/scene.ini" O="$c/out"
    case $scene in
        base) S=$BASE ;;
        file:*) printf '%b' "${scene#file:}" >"$S" ;;
        dir) S="$c/a-folder" && mkdir -p "$S" ;;
        missing) S="$c/no-such.ini" ;;
    esac
    case $folder in
        foreign) cp -a "$TMP/fixture-run" "$O" && echo "the user's own notes" >"$O/notes.txt" ;;
        scene-inside) cp -a "$TMP/fixture-run" "$O" && cp "$BASE" "$O/my.ini" ;;
        failed) cp -a "$TMP/fixture-run" "$O" && sed -i 's/"status":[[:space:]]*"completed"/"status": "failed"/' "$O/summary.json" ;;
        new) ;;
        *) cp -a "$TMP/fixture-$folder" "$O" ;;
    esac
    before=$(state "$O")
    eval "set -- $args"
    (cd "$c" && timeout 20 "$G" "$@" >"$c/stdout" 2>"$c/stderr")
    rc=$?
    after=$(state "$O")
    [[ -e $O ]] || after=$(state "$c/out"$'\n'"next")
    problems=()
    [[ $rc == "$code" ]] || problems+=("exit $rc, expected $code")
    IFS=';' read -ra want <<<"$words"
    for w in "${want[@]}"; do
        w=$(eval "printf '%s' \"$w\"")
        if [[ $w == ASCII ]]; then
            LC_ALL=C grep -q '[^[:print:][:space:]]' "$c/stderr" && problems+=("message holds raw non-printable bytes")
        elif [[ $w == '!'* ]]; then
            grep -qiF -- "${w#!}" "$c/stderr" && problems+=("message holds '${w#!}'")
        else
            grep -qiF -- "$w" "$c/stderr" || problems+=("message lacks '$w'")
        fi
    done
    [[ $after == "$before" ]] || problems+=("output folder changed")
    report "granule $args" "$c/stderr" "[$scene]"
done <<<"$cases"
# --force replaces a folder's contents as a whole (issue 39): whatever the folder held before (a
# run of another scene with snapshots and pv.csv, a comparison of other models, a run under a
# sweep or an export), afterwards it holds exactly the files a fresh command writes into a new
# folder, and `analyse` finds no stale frames
names() { (cd "$1" && find . -not -name .run.lock | sort); }
big="$TMP/fixture-snap"
SCENE2D="$TMP/s2d.ini"
printf '%s\n' '[system]' 'dim = 2' 'N = 20' 'packing_fraction = 0.1' '[run]' 'warmup = 0' 'duration = 0.01' 'sample_every = 1e-3' \
    '[output]' 'plots = false' >"$SCENE2D"
# a sweep over folder DIR (its out) is written to DIR.ini
sweep_file() { printf '%s\n' '[sweep]' "scene = $BASE" "out = $1" 'seeds = 1' '[vary]' 'system.N = 10, 12' >"$1.ini"; }
replace_cases=(
    "run over a run with snapshots|$big|run $BASE --out {}"
    "run over a comparison|$TMP/fixture-compare|run $BASE --out {}"
    "compare over a comparison of other models|$TMP/fixture-compare|compare $BASE --models spring_dashpot@clamp --out {}"
    "compare over a run with snapshots|$big|compare $BASE --models spring_dashpot --out {}"
    "sweep over a run with snapshots|$big|sweep {}.ini --jobs 1"
    "export over a run with snapshots|$big|export lammps $SCENE2D --out {}"
    "export over a comparison|$TMP/fixture-compare|export lammps $SCENE2D --out {}"
)
for rc_case in "${replace_cases[@]}"; do
    IFS='|' read -r what from cmd <<<"$rc_case"
    i=$((i + 1))
    fresh="$TMP/replace$i-fresh" forced="$TMP/replace$i-forced"
    cp -a "$from" "$forced"
    sweep_file "$fresh" && sweep_file "$forced"
    read -ra a <<<"${cmd//\{\}/$fresh}"
    "$G" "${a[@]}" >/dev/null 2>"$TMP/replace$i.err"
    rc_fresh=$?
    read -ra a <<<"${cmd//\{\}/$forced}"
    "$G" "${a[@]}" --force >/dev/null 2>>"$TMP/replace$i.err"
    rc_forced=$?
    problems=()
    [[ $rc_fresh == 0 && $rc_forced == 0 ]] || problems+=("exit $rc_fresh (new folder), $rc_forced (--force)")
    stale=$(diff <(names "$fresh") <(names "$forced"))
    [[ -z $stale ]] || problems+=("--force left a folder that differs from a fresh one: $(tr '\n' ' ' <<<"$stale" | head -c 300)")
    report "--force replaces the folder as a whole: $what" "$TMP/replace$i.err"
done
# a reproduce campaign's folder (DIR/NAME/FIDELITY) that holds a run is refused, and left as it was
i=$((i + 1))
mkdir -p "$TMP/rp/ch3-moments" && cp -a "$TMP/fixture-run" "$TMP/rp/ch3-moments/quick"
before=$(state "$TMP/rp")
"$G" reproduce ch3-moments --out "$TMP/rp" >/dev/null 2>"$TMP/rp.err"
rc=$?
problems=()
[[ $rc == 2 ]] || problems+=("exit $rc, expected 2")
grep -qF "$TMP/rp/ch3-moments/quick already holds a run (summary.json)" "$TMP/rp.err" || problems+=("message lacks 'already holds a run'")
[[ $(state "$TMP/rp") == "$before" ]] || problems+=("output folder changed")
report "granule reproduce ch3-moments --out DIR, DIR/ch3-moments/quick a run" "$TMP/rp.err"
# a campaign result whose y no point's summary.json holds (a misspelt path) is refused when the
# results are collected, naming it, instead of an empty result (issue 39 item 12)
i=$((i + 1))
printf '%b' '[campaign]\ntitle = t\nscene = rfm-1d.ini\n[sweep.quick]\nseeds = 1\n[vary.quick]\nsystem.N = 10\n[sweep.full]\nseeds = 1\n[vary.full]\nsystem.N = 10\n[set]\nrun.warmup = 0\nrun.duration = 0.01\nrun.sample_every = 1e-3\noutput.plots = false\n[result a]\nkind = mean\ny = nosuch\n' >"$TMP/ynosuch.ini"
"$G" reproduce "$TMP/ynosuch.ini" --out "$TMP/ynosuch" >/dev/null 2>"$TMP/ynosuch.err"
rc=$?
problems=()
[[ $rc != 0 ]] || problems+=("exit 0, expected a refusal")
grep -qF "[result a] y = nosuch: no such entry in the summary.json of any of the 1 finished points" "$TMP/ynosuch.err" ||
    problems+=("message lacks '[result a] y = nosuch: no such entry'")
report "granule reproduce CAMPAIGN with y = nosuch" "$TMP/ynosuch.err"
echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
