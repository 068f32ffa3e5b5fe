#!/usr/bin/env bash
# Tests of the granule command line (SPEC sec. 7): --help everywhere, exit codes, one-line
# refusals naming file:line and key, collide's JSON, models/keys listings, and a tiny run with
# --set overrides that refuses to overwrite an earlier run unless --force.
#
# usage: tests/test_cli.sh path/to/granule
# Prints "N passed, M failed" and exits non-zero if any check failed.
set -euo pipefail

if [[ $# -lt 1 || ! -x "$1" ]]; then
    echo "usage: $0 path/to/granule" >&2
    exit 2
fi
G=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
TMP=$(mktemp -d "${TMPDIR:-/tmp}/granule-test-cli-XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export CI=1 # never a progress line

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok   $1"; }
fail() { failed=$((failed + 1)); echo "FAIL $1"; [[ $# -gt 1 ]] && printf '     %s\n' "${@:2}"; return 0; }

# run CMD...: sets $rc, $out, $err (never aborts the script on a non-zero status)
run() {
    set +e
    "$@" >"$TMP/stdout" 2>"$TMP/stderr"
    rc=$?
    set -e
    out=$(cat "$TMP/stdout")
    err=$(cat "$TMP/stderr")
}

# ---------- --help ----------
run "$G" --help
if [[ $rc -eq 0 && $out == *usage* ]]; then pass "granule --help"; else fail "granule --help exits $rc" "$err"; fi

# every subcommand listed under "commands:" in granule --help, plus the ones SPEC sec. 7 needs here
mapfile -t cmds < <(awk '/^commands:/ {on = 1; next} on && /^  [a-z]/ {print $1} on && /^$/ {on = 0}' <<<"$out" | grep -vx help || true)
for c in run collide models keys; do
    [[ " ${cmds[*]} " == *" $c "* ]] || cmds+=("$c")
done
for c in "${cmds[@]}"; do
    run "$G" "$c" --help
    if [[ $rc -eq 0 && -n $out ]]; then pass "granule $c --help"; else fail "granule $c --help exits $rc (stdout ${#out} bytes)" "$err"; fi
done

# ---------- the option tables (issue 34 item 7) ----------
# `granule help COMMAND` prints exactly what `granule COMMAND --help` does, for every command
for c in "${cmds[@]}"; do
    run "$G" help "$c"
    h=$out
    run "$G" "$c" --help
    if [[ $rc -eq 0 && -n $h && $h == "$out" ]]; then pass "granule help $c = granule $c --help"; else fail "granule help $c differs from granule $c --help"; fi
done
# -V and --version print the version
for v in -V --version; do
    run "$G" $v
    if [[ $rc -eq 0 && $out =~ ^granule\ [0-9]+\.[0-9]+\.[0-9]+\ \( ]]; then pass "granule $v"; else fail "granule $v: exit $rc" "$out"; fi
done
# --help is generated from the table: each row with its value, default and allowed range
run "$G" run --help
if [[ $out == *"--threads N"*"from 1 to 1024"* && $out == *"--format png|svg|pdf"*"(default png)"* && $out == *"--no-plots"* ]]; then
    pass "run --help lists the table's rows with default and range"
else
    fail "run --help lacks a row's default or range" "$out"
fi
run "$G" compare --help
if [[ $out == *"--out DIR"*"(default out/compare)"* ]]; then pass "compare --help shows --out's default"; else fail "compare --help" "$out"; fi
# an unknown option is refused with the nearest one; none is offered when nothing is near
run "$G" run "$TMP/none.ini" --forse
if [[ $rc -eq 2 && $err == *"unknown option --forse; did you mean --force?"* ]]; then pass "run --forse suggests --force"; else fail "run --forse: exit $rc" "$err"; fi
run "$G" sweep "$TMP/none.ini" --colect
if [[ $rc -eq 2 && $err == *"did you mean --collect?"* ]]; then pass "sweep --colect suggests --collect"; else fail "sweep --colect: exit $rc" "$err"; fi
run "$G" compare "$TMP/none.ini" --model x
if [[ $rc -eq 2 && $err == *"did you mean --models?"* ]]; then pass "compare --model suggests --models"; else fail "compare --model: exit $rc" "$err"; fi
run "$G" run "$TMP/none.ini" --zzzzzzzz
if [[ $rc -eq 2 && $err == *"unknown option --zzzzzzzz"* && $err != *"did you mean"* ]]; then pass "nothing near: no suggestion"; else fail "run --zzzzzzzz: exit $rc" "$err"; fi
run "$G" swep
if [[ $rc -eq 2 && $err == *"unknown command 'swep'; did you mean 'sweep'?"* ]]; then pass "granule swep suggests sweep"; else fail "granule swep: exit $rc" "$err"; fi
# a value out of range names the option and the allowed range; --name=value works alike
run "$G" sweep "$TMP/none.ini" --jobs 0
if [[ $rc -eq 2 && $err == *"sweep: --jobs 0: expected an integer from 1 to 4096 (allowed range)"* ]]; then pass "sweep --jobs 0: range"; else fail "sweep --jobs 0: exit $rc" "$err"; fi
run "$G" run "$TMP/none.ini" --threads=2000
if [[ $rc -eq 2 && $err == *"run: --threads 2000: expected an integer from 1 to 1024 (allowed range)"* ]]; then pass "run --threads=2000: range"; else fail "run --threads=2000: exit $rc" "$err"; fi
run "$G" run "$TMP/none.ini" --threads 2.5
if [[ $rc -eq 2 && $err == *"--threads 2.5: expected an integer from 1 to 1024"* ]]; then pass "run --threads 2.5: not an integer"; else fail "run --threads 2.5: exit $rc" "$err"; fi
run "$G" analyse "$TMP" --format gif
if [[ $rc -eq 2 && $err == *"analyse: --format gif: expected png, svg or pdf"* ]]; then pass "analyse --format gif: the choices"; else fail "analyse --format gif: exit $rc" "$err"; fi
run "$G" run "$TMP/none.ini" --force=yes
if [[ $rc -eq 2 && $err == *"--force takes no value"* ]]; then pass "run --force=yes refused"; else fail "run --force=yes: exit $rc" "$err"; fi

# the theory commands take the shared options alike (issue 38): --no-plots and --format in every
# one's table, --set refused naming the command (it has no scene)
for c in "spm circle" "spm full" "spm predict" bisect cascade fokker-planck; do
    # shellcheck disable=SC2086
    run "$G" $c --help
    if [[ $out == *"--out DIR"* && $out == *"--force"* && $out == *"--no-plots"* && $out == *"--format png|svg|pdf"* && $out == *"--set K=V"* ]]; then
        pass "$c --help lists --out, --force, --no-plots, --format, --set"
    else
        fail "$c --help lacks a shared option" "$out"
    fi
    # shellcheck disable=SC2086
    run "$G" $c --format gif --out "$TMP/theory-never"
    if [[ $rc -eq 2 && $err == *"--format gif: expected png, svg or pdf"* && ! -e $TMP/theory-never ]]; then pass "$c --format gif refused"; else fail "$c --format gif: exit $rc" "$err"; fi
    # shellcheck disable=SC2086
    run "$G" $c --set a.b=1 --out "$TMP/theory-never"
    if [[ $rc -eq 2 && $err == *"--set a.b=1: $c has no scene"* && ! -e $TMP/theory-never ]]; then pass "$c --set refused"; else fail "$c --set: exit $rc" "$err"; fi
done
run "$G" fokker-planck --no-sim --points 21 --format svg --no-plots --quiet --out "$TMP/fp"
if [[ $rc -eq 0 && -f $TMP/fp/summary.json && -z $(find "$TMP/fp" -name '*.svg' -o -name '*.png') ]]; then
    pass "fokker-planck --format svg --no-plots: results, no plots"
else
    fail "fokker-planck --format svg --no-plots: exit $rc" "$err"
fi

# ---------- a refused scene ----------
cat >"$TMP/bad.ini" <<'EOF'
[system]
dim = 2
N = 50
[model]
eps_n = 1.5
EOF
run "$G" run "$TMP/bad.ini" --out "$TMP/bad-out"
nlines=$(printf '%s' "$err" | grep -c '' || true)
if [[ $rc -eq 2 ]]; then pass "run bad scene exits 2"; else fail "run bad scene exits $rc, expected 2" "$err"; fi
if [[ $nlines -eq 1 ]]; then pass "run bad scene: one line on stderr"; else fail "run bad scene: $nlines lines on stderr" "$err"; fi
if [[ $err == *"$TMP/bad.ini:5:"* && $err == *eps_n* && $err == *"[0, 1]"* ]]; then
    pass "run bad scene: stderr names file:line, key and range"
else
    fail "run bad scene: stderr lacks $TMP/bad.ini:5:, eps_n or [0, 1]" "$err"
fi
if [[ ! -e "$TMP/bad-out/summary.json" ]]; then pass "run bad scene: no summary.json"; else fail "run bad scene wrote summary.json"; fi

# a bad --set on a good scene is refused the same way, naming the argument
printf '[system]\ndim = 2\nN = 50\nL = 0.05\n' >"$TMP/good.ini"
run "$G" run "$TMP/good.ini" --out "$TMP/bad-out" --set model.eps_n=2
nlines=$(printf '%s' "$err" | grep -c '' || true)
if [[ $rc -eq 2 && $nlines -eq 1 && $err == *"--set model.eps_n=2"* && $err == *"[0, 1]"* ]]; then
    pass "run: bad --set exits 2 with one line naming it and the range"
else
    fail "run: bad --set exits $rc ($nlines lines on stderr)" "$err"
fi
run "$G" run "$TMP/good.ini" --out "$TMP/bad-out" --set model_eps_n=0.5
if [[ $rc -eq 2 && $err == *"section.key=value"* ]]; then pass "run: malformed --set exits 2"; else fail "run: malformed --set exits $rc" "$err"; fi
if [[ ! -e "$TMP/bad-out/summary.json" ]]; then pass "run bad --set: no summary.json"; else fail "run bad --set wrote summary.json"; fi

# ---------- collide ----------
run "$G" collide --case 1 --eps-n 0.5 --phases 8
if [[ $rc -eq 0 ]]; then
    if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
loss = d["energy_loss"]
sys.exit(0 if abs(loss - 0.75) <= 0.01 * 0.75 else 1)' "$out" 2>"$TMP/py"; then
        pass "collide --case 1 --eps-n 0.5: energy_loss within 1% of 0.75"
    else
        fail "collide --case 1 --eps-n 0.5: energy_loss not within 1% of 0.75 (or not JSON)" "$out" "$(cat "$TMP/py")"
    fi
else
    fail "collide --case 1 exits $rc" "$err"
fi
for k in expected_loss contact_time max_overlap eps_n_measured eps_t_measured; do
    if python3 -c 'import json, sys; sys.exit(0 if sys.argv[2] in json.loads(sys.argv[1]) else 1)' "$out" "$k" 2>/dev/null; then
        pass "collide JSON has $k"
    else
        fail "collide JSON lacks $k"
    fi
done
# rotation: the spins after an oblique impact (RFM discs, small overlap), the contact point's eps_t,
# the loss with the spin energy against the law, the CVODE reference's spins; no omega without it
run "$G" collide --case 4 --model spring_dashpot+tangential_dashpot --eps-t 0.3 --mass 3.53e-5 --radius 1.5e-3 \
    --set rotation=true --phases 4 --steps-per-contact 200 --reference
if [[ $rc -eq 0 ]] && python3 -c '
import json, sys
d = json.loads(sys.argv[1])
w, wr = d["omega1"], d["reference_omega1"]
ok = d["rotation"] and w == d["omega2"] and w > 0 and abs(w - wr) <= 1e-2 * wr
ok = ok and abs(d["eps_t_measured"] - 0.3) <= 0.01 and abs(d["energy_loss"] - d["expected_loss"]) <= 0.01 * d["expected_loss"]
ok = ok and d["units"]["omega1"].startswith("rad/s")
sys.exit(0 if ok else 1)' "$out" 2>"$TMP/py"; then
    pass "collide --set rotation=true: omega1 = omega2 > 0 as the reference's, eps_t 0.3 at the contact point"
else
    fail "collide --set rotation=true: spins or contact-point eps_t wrong (exit $rc)" "$out" "$err $(cat "$TMP/py")"
fi
# rolling resistance: counter-rotating discs head-on (the contact point does not slip), the spins
# lose what the law says (with the measured normal impulse), the spins slow down but keep their sign
run "$G" collide --case 1 --model spring_dashpot+sliding_friction+rolling_friction --set rotation=true --set mu_r=0.05 \
    --omega1 50 --omega2 -50 --steps-per-contact 200
if [[ $rc -eq 0 ]] && python3 -c '
import json, sys
d = json.loads(sys.argv[1])
ok = d["rolling"] == "rolling_friction" and d["mu_r"] == 0.05 and d["omega1_before"] == 50
ok = ok and 0 < d["omega1"] < 50 and d["omega2"] == -d["omega1"] and d["spin_loss"] > 0
ok = ok and abs(d["spin_loss"] - d["spin_loss_rolling_law"]) <= 1e-9 * d["spin_loss"]
sys.exit(0 if ok else 1)' "$out" 2>"$TMP/py"; then
    pass "collide +rolling_friction: spin_loss = the law's, spins slowed"
else
    fail "collide +rolling_friction: spin loss or spins wrong (exit $rc)" "$out" "$err $(cat "$TMP/py")"
fi
run "$G" collide --case 1 --model spring_dashpot+sliding_friction+rolling_friction
if [[ $rc -eq 2 && "$err" == *"rotation = true"* ]]; then
    pass "collide +rolling_friction without rotation exits 2 naming rotation"
else
    fail "collide +rolling_friction without rotation: exit $rc" "$err"
fi
run "$G" collide --case 4 --model spring_dashpot+tangential_dashpot
if [[ $rc -eq 0 ]] && python3 -c 'import json, sys; sys.exit(1 if "omega1" in json.loads(sys.argv[1]) else 0)' "$out"; then
    pass "collide without rotation prints no omega"
else
    fail "collide without rotation prints omega (exit $rc)" "$out"
fi
# oblique impact at a chosen speed and angle with initial spins: the JSON names them, momentum is
# conserved (v1' + v2' = v1 = 0.8 (cos 45, sin 45)), the spins change by equal amounts, no
# restitution law for spinning discs (expected_loss null), the velocities carry units
run "$G" collide --speed 0.8 --angle 45 --model spring_dashpot+tangential_dashpot --set rotation=true \
    --omega1 100 --omega2 -50 --mass 3.53e-5 --radius 1.5e-3
if [[ $rc -eq 0 ]] && python3 -c '
import json, math, sys
d = json.loads(sys.argv[1])
v1, v2, c = d["v1_after"], d["v2_after"], 0.8 * math.cos(math.radians(45))
ok = d["speed"] == 0.8 and d["angle"] == 45 and "case" not in d and d["omega1_before"] == 100 and d["omega2_before"] == -50
ok = ok and all(abs(v1[k] + v2[k] - c) <= 1e-12 for k in (0, 1)) and d["expected_loss"] is None
ok = ok and abs((d["omega1"] - 100) - (d["omega2"] + 50)) <= 1e-9 * abs(d["omega1"] - 100) and d["omega1"] != 100
ok = ok and abs(d["impact_angle"] - 45) < 1e-9 and d["units"]["v1_after"] == "m/s"
sys.exit(0 if ok else 1)' "$out" 2>"$TMP/py"; then
    pass "collide --speed 0.8 --angle 45 --omega1 100 --omega2 -50: momentum conserved, equal spin changes, units"
else
    fail "collide --speed/--angle/--omega: JSON wrong (exit $rc)" "$out" "$err $(cat "$TMP/py")"
fi
# the history spring with rotation, sticking (mu huge, no dashpot): the contact point's eps_t is
# cos(w_t t_c), w_t = sqrt(k_t / m_t), k_t = kt_ratio k_s, m_t = m12 q / (1 + q); equal spins
run "$G" collide --speed 0.1 --angle 30 --model spring_dashpot+tangential_spring --set rotation=true --mu 1e6 \
    --mass 3.53e-5 --radius 1.5e-3 --steps-per-contact 200
if [[ $rc -eq 0 ]] && python3 -c '
import json, math, sys
d = json.loads(sys.argv[1])
q, m12 = d["inertia_factor"], 0.5 * d["mass"]
w_t = math.sqrt(d["kt_ratio"] * d["k_s"] / (m12 * q / (1 + q)))
want = math.cos(w_t * d["contact_time"])
ok = d["rotation"] and d["k_t"] == 0 and d["gamma_t"] == 0 and d["units"]["k_t"] == "N/m"
ok = ok and abs(d["eps_t_measured"] - want) <= 0.03 and abs(d["eps_n_measured"] - 0.6) <= 0.01
ok = ok and d["omega1"] == d["omega2"] and d["omega1"] != 0 and d["omega1_before"] == 0
sys.exit(0 if ok else 1)' "$out" 2>"$TMP/py"; then
    pass "collide spring_dashpot+tangential_spring with rotation, sticking: eps_t = cos(w_t t_c), equal spins"
else
    fail "collide tangential_spring with rotation: eps_t, eps_n or spins wrong (exit $rc)" "$out" "$err $(cat "$TMP/py")"
fi
# collide --dim 3 (spheres; the impact in the plane z = 0): with spins along z each soft law gives
# the 2D collision's numbers (same q), velocities and spins as 3-vectors; q defaults to 2/5
for law in spring_dashpot+tangential_dashpot spring_dashpot+sliding_friction spring_dashpot+tangential_spring \
    hertz+tangential_spring:mindlin; do
    m=${law%%:*}
    extra=()
    [[ $law == *mindlin ]] && extra=(--set mindlin=true)
    common=(--speed 0.5 --angle 30 --model "$m" --set rotation=true --mass 3.53e-5 --radius 1.5e-3
        --steps-per-contact 200 --mu 0.3 "${extra[@]}")
    run "$G" collide "${common[@]}" --set inertia_factor=0.4 --omega1 150 --omega2 -300
    out2=$out
    run "$G" collide "${common[@]}" --dim 3 --omega1 0,0,150 --omega2 0,0,-300 --reference
    if [[ $rc -eq 0 ]] && python3 -c '
import json, sys
d3, d2 = json.loads(sys.argv[1]), json.loads(sys.argv[2])
close = lambda a, b, s: abs(a - b) <= 1e-9 * s
ok = d3["dim"] == 3 and d3["inertia_factor"] == 0.4 and len(d3["v1_after"]) == 3 and d3["v1_after"][2] == 0
ok = ok and d3["omega1_before"] == [0, 0, 150] and len(d3["omega1"]) == 3 and d3["omega1"][:2] == [0, 0]
ok = ok and all(close(d3[k], d2[k], 1) for k in ("energy_loss", "eps_n_measured", "eps_t_measured"))
ok = ok and all(close(d3["v%d_after" % p][k], d2["v%d_after" % p][k], 0.5) for p in (1, 2) for k in (0, 1))
ok = ok and all(close(d3["omega%d" % p][2], d2["omega%d" % p], 300) for p in (1, 2))
# the CVODE reference for the same contact, to first order in dt / t_c
ok = ok and abs(d3["energy_loss"] - d3["reference_energy_loss"]) <= 2e-3 and len(d3["reference_omega1"]) == 3
sys.exit(0 if ok else 1)' "$out" "$out2" 2>"$TMP/py"; then
        pass "collide --dim 3 $law in the plane: the 2D numbers, 3-vectors, q = 2/5, the CVODE reference"
    else
        fail "collide --dim 3 $law in the plane differs from 2D (exit $rc)" "$out" "$err $(cat "$TMP/py")"
    fi
done
# spins about other axes: out of the plane (v_z != 0), momentum conserved, the contact's torques
# change both spins equally (no rolling law), no restitution law for spinning spheres
run "$G" collide --dim 3 --speed 0.5 --angle 30 --model spring_dashpot+sliding_friction --set rotation=true \
    --mass 3.53e-5 --radius 1.5e-3 --steps-per-contact 200 --omega1 400,100,150 --omega2 -100,0,-300
if [[ $rc -eq 0 ]] && python3 -c '
import json, math, sys
d = json.loads(sys.argv[1])
v1, v2, w1, w2 = d["v1_after"], d["v2_after"], d["omega1"], d["omega2"]
p = (0.5 * math.cos(math.radians(30)), 0.5 * math.sin(math.radians(30)), 0.0)
ok = all(abs(v1[k] + v2[k] - p[k]) <= 1e-12 for k in range(3)) and abs(v1[2]) > 1e-4
dw1 = [w1[k] - b for k, b in enumerate((400, 100, 150))]
dw2 = [w2[k] - b for k, b in enumerate((-100, 0, -300))]
ok = ok and all(abs(dw1[k] - dw2[k]) <= 1e-9 * 400 for k in range(3)) and abs(dw1[0]) + abs(dw1[1]) > 1
ok = ok and d["expected_loss"] is None and 0 < d["energy_loss"] < 1 and d["momentum_error"] < 1e-13
sys.exit(0 if ok else 1)' "$out" 2>"$TMP/py"; then
    pass "collide --dim 3 --omega1 400,100,150: out of the plane, momentum conserved, equal spin changes"
else
    fail "collide --dim 3 with spins about x and y: JSON wrong (exit $rc)" "$out" "$err $(cat "$TMP/py")"
fi
run "$G" collide --case 9
if [[ $rc -eq 2 ]]; then pass "collide --case 9 exits 2"; else fail "collide --case 9 exits $rc, expected 2" "$err"; fi
# CVODE tolerance: the reference error follows --rtol (exact loss 1 - 0.1^2 = 0.99 head-on)
ref_err() { "$G" collide --case 1 --dim 1 --eps-n 0.1 --mass 3.53e-5 --radius 1.5e-3 --reference --rtol "$1" |
            python3 -c 'import json,sys; print(abs(json.load(sys.stdin)["reference_energy_loss"] - 0.99))'; }
e_tight=$(ref_err 1e-12) e_loose=$(ref_err 1e-5)
if python3 -c "import sys; sys.exit(0 if $e_tight < 1e-12 and 1e-9 < $e_loose < 1e-3 else 1)"; then
    pass "collide --reference --rtol: error $e_tight at 1e-12, $e_loose at 1e-5"
else
    fail "collide --reference --rtol: error $e_tight at 1e-12, $e_loose at 1e-5"
fi
run "$G" collide --reference --rtol 1
if [[ $rc -eq 2 && $err == *"allowed range"* ]]; then pass "collide --rtol 1 refused with the range"; else fail "collide --rtol 1: exit $rc" "$err"; fi

# ---------- models and keys ----------
run "$G" models
if [[ $rc -eq 0 ]]; then pass "models exits 0"; else fail "models exits $rc" "$err"; fi
# each model with its parameters: the parameter lines follow the model's own line
check_model() {
    local name=$1
    shift
    local block
    block=$(awk -v m="$name" '$1 == m {on = 1; print; next} on && /^[^ ]/ {on = 0} on' <<<"$out")
    if [[ -z $block ]]; then
        fail "models does not list $name"
        return
    fi
    for p in "$@"; do
        if grep -qw -- "$p" <<<"$block"; then pass "models: $name lists $p"; else fail "models: $name does not list $p" "$block"; fi
    done
}
check_model spring_dashpot k_s eps_n clamp
check_model tangential_dashpot eps_t
check_model sliding_friction mu
# collide prints exactly the chosen models' parameters, from their descriptors (no list of its own),
# each with its value and, for numbers, a unit
models_out=$out
for m in hertz+tangential_spring spring_dashpot+sliding_friction hard_sphere \
         "spring_dashpot+tangential_dashpot+rolling_friction --set rotation=true"; do
    # shellcheck disable=SC2086
    run "$G" collide --speed 0.1 --angle 30 --model $m
    if [[ $rc -eq 0 ]] && python3 -c '
import json, re, sys
models, cur = {}, None
for line in sys.argv[2].splitlines():
    if re.match(r"^\S", line):
        cur = line.split()[0]
        models[cur] = {}
    elif line.startswith("    ") and cur:
        f = line.split()
        models[cur][f[0]] = "default false" not in line and "default true" not in line
chosen = sys.argv[3].split()[0].split("+")
d = json.loads(sys.argv[1])
mine = {k: num for m in chosen for k, num in models[m].items()}
others = {k for m in models for k in models[m]} - set(mine)
ok = all(k in d for k in mine) and not any(k in d for k in others)
ok = ok and all(d["units"].get(k) for k, num in mine.items() if num)
sys.exit(0 if ok else 1)' "$out" "$models_out" "$m" 2>"$TMP/py"; then
        pass "collide --model $m: prints exactly the models' parameters, with units"
    else
        fail "collide --model $m: parameters differ from the models' descriptors (exit $rc)" "$out" "$err $(cat "$TMP/py")"
    fi
done
out=$models_out

run "$G" keys
if [[ $rc -eq 0 ]]; then pass "keys exits 0"; else fail "keys exits $rc" "$err"; fi
for s in system placement model noise integrator run output; do
    if grep -qF "[$s]" <<<"$out"; then pass "keys mentions [$s]"; else fail "keys does not mention [$s]"; fi
done
for k in packing_fraction reduced_length steps_per_contact eps_n eps_t mu sample_every; do
    if grep -qw -- "$k" <<<"$out"; then pass "keys mentions $k"; else fail "keys does not mention $k"; fi
done

# ---------- a tiny run, then the overwrite guard ----------
cat >"$TMP/tiny.ini" <<'EOF'
[system]
dim = 2
N = 500
L = 0.05
[run]
warmup = 1.0
duration = 10.0
[output]
plots = true
EOF
OUT="$TMP/tiny-out"
sets=(--set system.N=50 --set run.warmup=0 --set run.duration=0.01 --set run.sample_every=1e-3
      --set output.plots=false --set run.seed=11)
run "$G" run "$TMP/tiny.ini" --out "$OUT" "${sets[@]}"
if [[ $rc -eq 0 && -s "$OUT/summary.json" ]]; then
    pass "tiny run with --set exits 0 and writes summary.json"
else
    fail "tiny run exits $rc, summary.json $([[ -e $OUT/summary.json ]] && echo present || echo missing)" "$err"
fi
if [[ -s "$OUT/summary.json" ]] && python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
s = d["scene"]
ok = s["system"]["N"] == 50 and s["run"]["duration"] == 0.01 and s["run"]["seed"] == 11 and s["output"]["plots"] is False
for k in ("T_mean", "T_stderr", "wall_seconds", "particle_steps_per_second", "collisions",
          "energy_injected", "energy_dissipated", "kernel"):
    ok = ok and k in d
sys.exit(0 if ok else 1)' "$OUT/summary.json" 2>"$TMP/py"; then
    pass "tiny run: summary.json has the SPEC keys and the overridden scene"
else
    fail "tiny run: summary.json lacks SPEC keys or the --set values" "$(cat "$TMP/py")"
fi
for f in temperature.csv ledger.csv; do
    # column names on the first line, the notes (what, units, scene, hash, seed) in NAME.meta.json
    if [[ -s "$OUT/$f" && $(head -c2 "$OUT/$f") == "t," ]] && grep -q '"notes"' "$OUT/${f%.csv}.meta.json"; then
        pass "tiny run: $f with its column names first and ${f%.csv}.meta.json"
    else fail "tiny run: $f missing, not starting with its column names, or without ${f%.csv}.meta.json"; fi
done
# --threads on a run whose step uses one thread (50 grains: one block of rows) says why, and
# summary.json records the one thread; the results are those of one thread
run "$G" run "$TMP/tiny.ini" --out "$TMP/threads-out" "${sets[@]}" --threads 2
if [[ $rc -eq 0 && $err == *"note: 2 threads were asked for, but a run of at most 1024 grains is one block"* ]] &&
    grep -q '"threads":[[:space:]]*1,' "$TMP/threads-out/summary.json" && cmp -s "$OUT/ledger.csv" "$TMP/threads-out/ledger.csv"; then
    pass "run --threads 2 on one block: a note, threads 1, the same ledger"
else fail "run --threads 2 on one block: exit $rc" "$err"; fi
if ! ls -A "$OUT" 2>/dev/null | grep -q '\.tmp'; then pass "tiny run: no temporary files"; else fail "tiny run left temporaries" "$(ls -A "$OUT")"; fi
# with rotation, ledger.csv's last column is the rotational energy sum I w^2 / 2 (part of kinetic):
# zero at the start (the discs start without spin), then positive (the tangential torques spin them)
# and never more than the kinetic energy; without rotation there is no such column
run "$G" run "$TMP/tiny.ini" --out "$TMP/rot-out" "${sets[@]}" --set model.tangential=tangential_dashpot --set model.rotation=true
if [[ $rc -eq 0 ]] && ! head -1 "$OUT/ledger.csv" | grep -q rotational && /usr/bin/python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
rot = [float(r["rotational"]) for r in rows]
kin = [float(r["kinetic"]) for r in rows]
sys.exit(0 if rot[0] == 0 and rot[-1] > 0 and all(0 <= a <= k for a, k in zip(rot, kin)) else 1)' "$TMP/rot-out/ledger.csv" 2>"$TMP/py"; then
    pass "rotation: ledger.csv has the rotational energy column (0 at t = 0, then in (0, kinetic])"
else
    fail "rotation: ledger.csv's rotational column missing or out of range (rc $rc)" "$err $(cat "$TMP/py") $(head -3 "$TMP/rot-out/ledger.csv")"
fi

cp "$OUT/summary.json" "$TMP/first-summary.json" 2>/dev/null || true
run "$G" run "$TMP/tiny.ini" --out "$OUT" "${sets[@]}" --set run.seed=12
if [[ $rc -ne 0 ]]; then pass "re-run into the same folder without --force exits non-zero ($rc)"; else fail "re-run without --force exits 0"; fi
if [[ $err == *summary.json* || $err == *--force* ]]; then pass "re-run refusal explains itself"; else fail "re-run refusal does not mention summary.json or --force" "$err"; fi
if cmp -s "$OUT/summary.json" "$TMP/first-summary.json"; then pass "re-run left the first summary.json untouched"; else fail "re-run changed the first summary.json"; fi

run "$G" run "$TMP/tiny.ini" --out "$OUT" "${sets[@]}" --set run.seed=12 --force
if [[ $rc -eq 0 ]]; then pass "re-run with --force exits 0"; else fail "re-run with --force exits $rc" "$err"; fi
if python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["scene"]["run"]["seed"] == 12 else 1)' "$OUT/summary.json" 2>/dev/null; then
    pass "re-run with --force replaced summary.json"
else
    fail "re-run with --force did not replace summary.json"
fi

# ---------- the schedule (issue 14): snapshots independent of samples, checkpoint_every beyond the run ----------
printf '%s\n' '[system]' 'dim = 1' 'N = 20' 'reduced_length = 0.1' '[placement]' 'kind = uniform' '[run]' 'warmup = 0' \
    'duration = 0.05' 'sample_every = 1e-3' 'checkpoint_every = 1e300' '[output]' 'plots = false' 'snapshot_every = 1e-4' >"$TMP/sched.ini"
run "$G" run "$TMP/sched.ini" --out "$TMP/sched-out"
nsnap=$(ls "$TMP/sched-out/snapshots" 2>/dev/null | wc -l)
if [[ $rc -eq 0 && $nsnap -eq 501 ]]; then pass "snapshot_every = 1e-4 with sample_every = 1e-3: 501 snapshots"; else fail "snapshot schedule: exit $rc, $nsnap snapshots, expected 501" "$err"; fi
if python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["checkpoints_written"] == 0 else 1)' "$TMP/sched-out/summary.json" 2>/dev/null; then
    pass "checkpoint_every = 1e300: no checkpoint during the run"
else
    fail "checkpoint_every = 1e300 wrote checkpoints"
fi
conv=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["T_stderr_converged"])' "$TMP/sched-out/summary.json" 2>/dev/null)
if [[ $conv == False && $out == *"T_stderr_converged = false"* ]] || [[ $conv == True && $out != *"not converged"* ]]; then
    pass "result line carries the T_stderr_converged warning ($conv)"
else
    fail "result line and T_stderr_converged = $conv disagree" "$out"
fi

# granule cost ends with its recommendation as --set arguments (issue 38): pasted after granule
# run SCENE they run the scene at that integrator and dt
printf '[system]\ndim = 2\nN = 200\nL = 0.06\n[model]\neps_n = 0.1\n[run]\nwarmup = 0\nduration = 0.002\n[output]\nplots = false\n' >"$TMP/cost.ini"
run "$G" cost "$TMP/cost.ini" --calibrate 0.3 --out "$TMP/cost-out"
sets=$(sed -n 's/^  as --set: //p' <<<"$out")
if [[ $rc -eq 0 && $sets == "--set integrator."* ]]; then
    # shellcheck disable=SC2086
    run "$G" run "$TMP/cost.ini" --out "$TMP/cost-run" --quiet $sets
    dt=$(sed -n 's/.*--set integrator.dt=\([^ ]*\).*/\1/p' <<<"$sets")
    kind=$(sed -n 's/.*--set integrator.kind=\([^ ]*\).*/\1/p' <<<"$sets")
    if [[ $rc -eq 0 ]] && python3 -c "import sys; v = float(sys.argv[1]); sys.exit(0 if abs(v - $dt) <= 1e-12 * $dt else 1)" \
        "$(sed -n 's/^dt = //p' "$TMP/cost-run/scene.ini")" && grep -q "^kind = $kind\$" "$TMP/cost-run/scene.ini"; then
        pass "cost's --set line runs the scene at its integrator and dt ($sets)"
    else
        fail "cost's --set line ($sets) did not run as recommended (exit $rc)" "$err"
    fi
else
    fail "granule cost printed no '  as --set:' line (exit $rc)" "$out" "$err"
fi

# ---------- 3D (docs/three-dimensions.md): the example scene runs and writes its outputs ----------
scene3d="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/docs/scenes/rfm-3d.ini"
run "$G" run "$scene3d" --out "$TMP/run3d" --set system.N=343 --set run.warmup=0 --set run.duration=0.01 \
    --set output.snapshot_every=0.005 --set output.plots=false --set analysis.observables=moments
if [[ $rc -eq 0 && -s $TMP/run3d/temperature.csv && -s $TMP/run3d/ledger.csv && -s $TMP/run3d/summary.json ]] &&
    /usr/bin/python3 - "$TMP/run3d" <<'PY'
import json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
L = s["scene"]["system"]["L"]
ok = s["scene"]["system"]["dim"] == 3 and abs(s["scene"]["system"]["packing_fraction"] - 0.1) < 1e-12
ok = ok and s["kernel"].startswith("3d-verlet-list/spring_dashpot") and abs(s["ledger"]["relative_residual"]) < 5e-3
lines = open(f"{d}/snapshots/snap_000002.xyz").read().splitlines()
lattice = [float(v) for v in lines[1].split('Lattice="')[1].split('"')[0].split()]
ok = ok and lines[0] == "343" and 'pbc="T T T"' in lines[1] and lattice == [L, 0, 0, 0, L, 0, 0, 0, L]
z = [float(l.split()[3]) for l in lines[2:]]
ok = ok and len(z) == 343 and all(0 <= v < L for v in z) and len(set(z)) > 7  # spread in z, not a slab
# moments in 3D: <|v|^2> is T (2.19) over three components, the pooled component's a third of it
m = s["analysis"]["moments"]["speed"]["m2"]
rows = {int(r.split(",")[0]): r.split(",") for r in open(f"{d}/moments.csv").read().splitlines()[1:]}
ok = ok and abs(m - s["T_mean"]) <= 1e-12 * m and abs(3 * float(rows[2][3]) - float(rows[2][1])) <= 1e-9 * m
sys.exit(0 if ok else 1)
PY
then
    pass "granule run docs/scenes/rfm-3d.ini: temperature.csv, ledger.csv, summary.json (dim 3), XYZ with z and pbc T T T, moments (<|v|^2> = T, a component's a third)"
else
    fail "3D run (exit $rc) or its outputs" "$err"
fi
# 3D with friction, rotation and rolling: the scene takes the keys, the kernel names them, the
# ledger closes with the spins' energy, temperature.csv has T_rot (3 rotational degrees of freedom)
run "$G" run "$scene3d" --out "$TMP/run3d-rot" --set system.N=343 --set system.packing_fraction=0.3 --set run.warmup=0 \
    --set run.duration=0.01 --set output.plots=false --set model.tangential=tangential_spring --set model.mu=0.5 \
    --set model.rotation=true --set model.rolling=rolling_friction --set placement.omega0=300
if [[ $rc -eq 0 ]] && /usr/bin/python3 - "$TMP/run3d-rot" <<'PY'
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
ok = s["kernel"].startswith("3d-verlet-list/spring_dashpot+tangential_spring+rotation+rolling_friction/")
ok = ok and s["scene"]["model"]["inertia_factor"] == 0.4 and abs(s["ledger"]["relative_residual"]) < 5e-3
rows = list(csv.DictReader(open(f"{d}/temperature.csv")))
led = list(csv.DictReader(open(f"{d}/ledger.csv")))
# omega0 = 300 per component: T_rot(0) = I <|w|^2> / M = 0.4 r^2 3 omega0^2 / 12, within sampling
r = s["scene"]["system"]["radius"]
want = 0.4 * r * r * 3 * 300.0**2 / 12
ok = ok and abs(float(rows[0]["T_rot"]) / want - 1) < 0.15 and float(led[-1]["rotational"]) > 0
ok = ok and float(led[-1]["dissipated_friction"]) > 0
sys.exit(0 if ok else 1)
PY
then
    pass "3D run with tangential_spring, rotation and rolling: kernel, q = 2/5, T_rot, ledger closes"
else
    fail "3D run with friction and rotation (exit $rc) or its outputs" "$err"
fi
run "$G" compare "$scene3d" --models spring_dashpot,hertz --out "$TMP/cmp3d" --set system.N=64 --set run.warmup=0 \
    --set run.duration=0.005 --set output.plots=false
if [[ $rc -eq 0 ]] && grep -q "G_1 tail exponent n_N (3.22) | n/a: 3D | n/a: 3D" "$TMP/cmp3d/compare.md" &&
    grep -q "3d-verlet-list/hertz" "$TMP/cmp3d/compare.md"; then
    pass "granule compare of a 3D scene: both laws run in 3D, 1D/2D-only rows say n/a: 3D"
else
    fail "3D compare (exit $rc)" "$err"
fi

# an event-driven run reports its rate in events per second, a time-stepped one in particle-steps
# per second (the final line; the progress line says the same)
src=$(cd "$(dirname "$0")/.." && pwd)
run "$G" run "$src/docs/scenes/rfm-1d-event.ini" --quiet --out "$TMP/event-rate" \
    --set system.N=100 --set system.reduced_length=0.1 --set run.warmup=0 --set run.duration=0.05
if [[ $rc -eq 0 && $out == *" events/s; kernel event"* && $out != *particle-steps* ]]; then
    pass "event run reports events/s"
else
    fail "event run's rate (exit $rc)" "$out" "$err"
fi
# the noise windows against the run (docs/event-driven.md, "Accuracy and the kick interval"):
# summary.json's noise_windows has the kick over the thermal speed sqrt(2 D tau) / M / sqrt(T) (1D)
# and the collisions per grain and window; the short run above is within both limits and says
# nothing, windows 20 times longer warn about both, naming the key
/usr/bin/python3 - "$TMP/event-rate/summary.json" <<'PY' && pass "noise_windows of an event run: the kick against the thermal speed, collisions per window" || fail "noise_windows in summary.json"
import json, math, sys
s = json.load(open(sys.argv[1]))
w, sc = s["noise_windows"], s["scene"]
kick = math.sqrt(2 * sc["noise"]["D"] * w["kick_interval"]) / sc["system"]["mass"] / math.sqrt(s["T_mean"])
rate = 2 * s["collisions"] / sc["system"]["N"] / s["simulated_seconds"] * w["kick_interval"]
assert abs(w["kick_over_thermal"] / kick - 1) < 1e-9 and abs(w["collisions_per_window"] / rate - 1) < 1e-9, (w, kick, rate)
assert w["kick_over_thermal"] < 0.5 and w["collisions_per_window"] < 0.5 and "warnings" not in s, w
PY
run "$G" run "$src/docs/scenes/rfm-1d-event.ini" --quiet --out "$TMP/event-coarse" \
    --set system.N=100 --set system.reduced_length=0.1 --set run.warmup=0 --set run.duration=0.05 \
    --set integrator.kick_interval=2e-3
if [[ $rc -eq 0 && $err == *"noise windows are coarse"*"integrator.kick_interval = 0.002 s"* &&
    $err == *"noise windows are long: a grain collides"* ]] &&
    grep -q "noise windows are coarse" "$TMP/event-coarse/summary.json"; then
    pass "coarse noise windows: a warning on stderr and in summary.json"
else
    fail "coarse noise windows' warning (exit $rc)" "$err"
fi
run "$G" run "$src/docs/scenes/rfm-1d.ini" --quiet --out "$TMP/step-rate" \
    --set system.N=100 --set system.reduced_length=0.1 --set run.warmup=0 --set run.duration=0.01
if [[ $rc -eq 0 && $out == *" particle-steps/s; kernel 1d"* ]]; then
    pass "time-stepped run reports particle-steps/s"
else
    fail "time-stepped run's rate (exit $rc)" "$out" "$err"
fi

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
