#!/usr/bin/env bash
# The profile observable on the isothermal atmosphere (docs/analysis-profiles.md): elastic grains
# under gravity (docs/scenes/elastic-atmosphere.ini, N = 100, eps_n = 1, no driving, 24 s sampled
# after 2 s), as soft discs (verlet) and as hard discs (event-driven). At equilibrium T is the
# same in every slab and for both components, and the slabs obey the hydrostatic balance d(n T Z(phi))/dy = -g n with the hard-disc equation of state
# Z = 1 + 2 phi chi(phi) (Henderson's chi, as docs/validation.md). Checks: every slab holding at
# least 5 % of the densest one has T_x and T_y within 4 errors of the gas's mean T; the mean
# over slabs of -d(n T Z)/dy / (g n) (centred differences, away from the walls) is 1 within 3
# errors and its error is below 0.05. usage: test_profile.sh GRANULE SOURCE_DIR
set -uo pipefail
granule=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# soft discs (verlet, the scene as written) and hard discs (event-driven: walls and gravity are
# its own events, docs/systems-walls-gravity.md) from the same start
"$granule" run "$src/docs/scenes/elastic-atmosphere.ini" --out "$tmp/verlet" --set output.plots=false \
    --set run.duration=24 >/dev/null 2>"$tmp/log" || { cat "$tmp/log" >&2; echo "FAIL: run verlet" >&2; exit 1; }
"$granule" run "$src/docs/scenes/elastic-atmosphere.ini" --out "$tmp/event" --set output.plots=false \
    --set run.duration=24 --set integrator.kind=event --set model.normal=hard_sphere \
    --set model.eps_t=1 --set model.tc=off >/dev/null 2>"$tmp/log" ||
    { cat "$tmp/log" >&2; echo "FAIL: run event" >&2; exit 1; }
/usr/bin/python3 - "$tmp/verlet" "$tmp/event" <<'PY'
import sys
import numpy as np
def check(run):
  a = np.genfromtxt(run + "/profile.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
  z, n, phi = a["z"], a["n"], a["phi"]
  g, dz = 9.81, z[1] - z[0]
  T = np.sum(n * (a["T_x"] + a["T_y"]) / 2) / np.sum(n)
  ok = True
  for c in ("T_x", "T_y"):
      w = n >= 0.05 * n.max()
      dev = np.abs(a[c][w] - T) / a[c + "_err"][w]
      print(f"{run.rsplit('/', 1)[-1]}: {c}: {w.sum()} slabs, largest |T_a - T| / error = {dev.max():.2f} (T = {T:.4f} m^2/s^2)")
      ok &= bool(dev.max() < 4)
  chi = (1 - 7 * phi / 16) / (1 - phi) ** 2
  P = n * T * (1 + 2 * phi * chi)
  k = np.arange(2, len(z) - 3)
  R = -(P[k + 1] - P[k - 1]) / (2 * dz) / (g * n[k])
  m, e = R.mean(), R.std(ddof=1) / np.sqrt(len(R))
  ideal = -np.polyfit(z[2:-2], np.log(n[2:-2]), 1)[0] * T / g
  print(f"{run.rsplit('/', 1)[-1]}: hydrostatic balance with Z(phi): -d(nTZ)/dy / (g n) = {m:.3f} +- {e:.3f} over {len(R)} slabs "
        f"(must be 1 within 3 errors, error < 0.05); the ideal-gas slope would give {ideal:.3f}")
  ok &= abs(m - 1) < 3 * e and e < 0.05
  return ok, T
ok_v, T_v = check(sys.argv[1])
ok_e, T_e = check(sys.argv[2])
print(f"T: verlet {T_v:.4f}, event {T_e:.4f} m^2/s^2")
sys.exit(0 if ok_v and ok_e else 1)
PY
