#!/usr/bin/env bash
# The run driver's view of a driving (docs/systems-driving.md): a Langevin run's ledger.csv and
# summary.json carry the bath's drag (dissipated_drag, the last column) and the ledger closes;
# the energy its noise injected matches energy_injection_rate_expected (N M T_bath (1 -
# e^{-2 dt/tau}) / (2 dt)) within 4 sigma, where sigma comes from the kicks' cross term
# M a v b xi (a = e^{-dt/tau}, b^2 = T_bath/dim (1 - a^2)): sd M a b sqrt(N steps T_bath) for an
# elastic gas at the bath temperature (the first term, M b^2 xi^2 / 2, scatters far less); a free-cooling run
# expects no injection; a random-force run's ledger keeps its columns (no drag column).
# usage: test_driving_run.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
py=python3
"$granule" run "$src/docs/scenes/langevin-gas.ini" --out "$tmp/lg" --set system.N=400 --set system.L=0.09 \
    --set run.warmup=0.02 --set run.duration=0.04 >"$tmp/lg.log" 2>&1 || bad "langevin run failed: $(tail -2 "$tmp/lg.log")"
header=$(head -1 "$tmp/lg/ledger.csv")
[[ $header == *,dissipated_drag ]] || bad "langevin ledger.csv: no dissipated_drag as the last column: $header"
$py - "$tmp/lg" <<'PY' || fail=1
import json, sys
d = sys.argv[1]
j = json.load(open(d + "/summary.json"))
led = j["ledger"]
t_total = 0.06  # warm-up + duration
expected = j["energy_injection_rate_expected"] * t_total
ok = True
if not (led.get("dissipated_drag", 0) > 0):
    print("FAIL: summary ledger has no positive dissipated_drag:", led); ok = False
if abs(led["relative_residual"]) > 1e-3:
    print("FAIL: ledger does not close:", led["relative_residual"]); ok = False
import math
sc, dt = j["scene"], j["contact"]["dt"]
dim, N, M = sc["system"]["dim"], sc["system"]["N"], sc["system"]["mass"]
T_bath, tau = sc["driving"]["T_bath"], sc["driving"]["tau"]
a = math.exp(-dt / tau)
b = math.sqrt(T_bath / dim * (1 - a * a))
sigma = M * a * b * math.sqrt(N * (t_total / dt) * T_bath)
z = (led["injected"] - expected) / sigma
print("injected %.6g J, expected %.6g +- %.3g J (z = %.2f)" % (led["injected"], expected, sigma, z))
if not abs(z) < 4:
    print("FAIL: injected %.6g J against expected %.6g J (rate %.6g W x %g s), z = %.2f" % (led["injected"], expected,
          j["energy_injection_rate_expected"], t_total, z)); ok = False
rows = [l.split(",") for l in open(d + "/ledger.csv").read().split("\n")[1:] if l]
if abs(float(rows[-1][-1]) - led["dissipated_drag"]) > 1e-9 * led["dissipated_drag"] + 1e-15:
    print("FAIL: ledger.csv's last dissipated_drag", rows[-1][-1], "is not summary's", led["dissipated_drag"]); ok = False
sys.exit(0 if ok else 1)
PY
"$granule" run "$src/docs/scenes/free-cooling.ini" --out "$tmp/fc" --set run.duration=0.01 --set run.warmup=0 \
    >"$tmp/fc.log" 2>&1 || bad "free-cooling run failed: $(tail -2 "$tmp/fc.log")"
$py -c "import json,sys; j=json.load(open('$tmp/fc/summary.json')); sys.exit(0 if j['energy_injection_rate_expected'] == 0 and 'dissipated_drag' not in j['ledger'] else 1)" ||
    bad "free cooling: energy_injection_rate_expected is not 0 or the ledger has a drag entry"
"$granule" run "$src/docs/scenes/rfm-2d.ini" --out "$tmp/rfm" --set run.duration=0.002 --set run.warmup=0 \
    >"$tmp/rfm.log" 2>&1 || bad "rfm run failed: $(tail -2 "$tmp/rfm.log")"
[[ $(head -1 "$tmp/rfm/ledger.csv") == "t,kinetic,elastic,injected,dissipated_normal,dissipated_tangential,dissipated_friction,removed_com,residual" ]] ||
    bad "rfm ledger.csv columns changed: $(head -1 "$tmp/rfm/ledger.csv")"
[ $fail = 0 ] && echo "driving-run: ok (Langevin drag in the ledger, injection as expected; free cooling and rfm unchanged)"
exit $fail
