#!/usr/bin/env bash
# sk and vcorr per species on a mixture (docs/mixtures.md "Observables on a mixture",
# docs/analysis-structure-factor.md "On a mixture", docs/analysis.md "vcorr"):
# - sk on the driven binary gas of docs/scenes/bidisperse-mixture.ini (2D): the Bhatia-Thornton
#   S_NN = sum_ab sqrt(x_a x_b) S_ab of sk_species.csv is sk.csv's S in every |n| bin to 1e-9
#   (sk.csv prints 10 digits), x_a = N_a / N of analysis.sk.species_N; at k d >= 3 the partial
#   structure factors average to the dilute hard-disc gas's S_ab = delta_ab - sqrt(x_a x_b) n pi d^2
#   2 J_1(k d) / (k d) within 3.5 errors (S_12 -> 0, S_aa -> 1: the ideal gas plus its first
#   density correction, a few 1e-3 there); the same identity on the 3D gas of spheres;
# - vcorr on one frame of the gas: c0 n C(r) = sum_ab n_ab sqrt(var_a var_b) C_ab(r) for C_L and C_T
#   in every bin (the total's un-normalised sum of products split by pair kind: n_ab = pairs_ab,
#   n = sum_ab n_ab, var_s = analysis.vcorr.species_var, c0 = sum_s x_s var_s), to 1e-9;
# - a mixture's sk and vcorr resume from a checkpoint bit for bit (SIGTERM, --resume);
# - one species: no species file or summary field, and (release pass) sk.csv, sk_shells.csv and
#   vcorr.csv as at the branch point (commit b4a0e9e). usage: test_obs_mixture_structure.sh GRANULE SOURCE_DIR
source "$(dirname "$0")/obs_run_lib.sh"
dur=0.1
[[ $quick == 1 ]] && dur=0.06
mix=(--set output.plots=false --set run.warmup=0.02 --set 'species.fraction=0.3, 0.7')
run gas "$src/docs/scenes/bidisperse-mixture.ini" "${mix[@]}" --set run.duration=$dur \
    --set analysis.sk_kd_max=6 --set analysis.observables=sk,vcorr
run gas3 "$src/docs/scenes/bidisperse-mixture-3d.ini" "${mix[@]}" --set run.duration=0.02 \
    --set 'species.fraction=0.7, 0.3' --set analysis.observables=sk
python3 - "$tmp/gas" "$tmp/gas3" <<'PY' || fail "sk per species, vcorr's pairs"
import csv, json, math, sys
ok = True
def table(path):
    return list(csv.DictReader(l for l in open(path) if not l.startswith("#")))
def identity(d):  # S_NN of the partial structure factors = the total S, bin by bin
    global ok
    a = json.load(open(d + "/summary.json"))["analysis"]["sk"]
    N = a["species_N"]
    x = [n / sum(N) for n in N]
    tot, sp = table(d + "/sk.csv"), table(d + "/sk_species.csv")
    good = len(tot) == len(sp) > 10 and a["species_file"] == "sk_species.csv"
    worst = 0.0
    for t, s in zip(tot, sp):
        good &= t["n"] == s["n"] and t["kd"] == s["kd"]
        snn = sum(math.sqrt(x[int(p[0]) - 1] * x[int(p[1]) - 1]) * float(s["S_" + p]) * (1 if p[0] == p[1] else 2)
                  for p in a["species_pairs"])
        worst = max(worst, abs(snn - float(t["S"])) / float(t["S"]))
    good &= worst < 1e-9 and a["species_pairs"] == ["11", "12", "22"] and N[0] != N[1]
    print(f"{d.rsplit('/', 1)[1]}: S_NN = sum_ab sqrt(x_a x_b) S_ab is S in {len(tot)} bins to "
          f"{worst:.2g} (N_a = {N})" + ("" if good else "  <- FAIL"))
    ok &= good
    return a, sp
a, sp = identity(sys.argv[1])
identity(sys.argv[2])
# large k: the dilute gas of hard discs of diameter d (both species 1.5 mm), S_ab = delta_ab -
# sqrt(x_a x_b) n pi d^2 2 J_1(kd) / (kd) (g = 0 inside d, 1 beyond), averaged over the bins k d >= 3
def J1(z, m=200):  # (1 / pi) int_0^pi cos(t - z sin t) dt, Simpson
    h = math.pi / m
    return sum((1 if k in (0, m) else 4 if k % 2 else 2) * math.cos(k * h - z * math.sin(k * h))
               for k in range(m + 1)) * h / (3 * math.pi)
N = a["species_N"]
n, x = sum(N) / a["L"] ** 2, [q / sum(N) for q in N]
for p in a["species_pairs"]:
    i, j = int(p[0]) - 1, int(p[1]) - 1
    dev, raw, err = [], [], []
    for r in sp:
        kd = float(r["kd"])
        if kd >= 3:
            S, e = float(r["S_" + p]), float(r["S_" + p + "_err"])
            raw.append(S - (i == j))
            dev.append(raw[-1] + math.sqrt(x[i] * x[j]) * n * math.pi * a["d"] ** 2 * 2 * J1(kd) / kd)
            err.append(e)
    m, mr = sum(dev) / len(dev), sum(raw) / len(raw)
    e = math.sqrt(sum(q * q for q in err)) / len(err)
    good = len(dev) > 30 and all(q > 0 for q in err) and abs(m) < 3.5 * e
    print(f"S_{p} - (ideal gas + hard-disc correction) over {len(dev)} bins k d >= 3: {m:+.5f} +- "
          f"{e:.5f} (ideal gas alone {mr:+.5f})" + ("" if good else "  <- FAIL"))
    ok &= good
# vcorr's pairs by kind: within r_max their numbers go as N_a (N_a - 1) / 2 and N_a N_b (a
# uniform gas of equal discs; each within 10 %; the quick run has them within 3 %)
v = json.load(open(sys.argv[1] + "/summary.json"))["analysis"]["vcorr"]
P = {p: sum(float(r["pairs_" + p]) for r in table(sys.argv[1] + "/vcorr_species.csv"))
     for p in v["species_pairs"]}
want = {"11": N[0] * (N[0] - 1) / 2, "12": N[0] * N[1], "22": N[1] * (N[1] - 1) / 2}
for p in P:
    f, fw = P[p] / sum(P.values()), want[p] / sum(want.values())
    good = abs(f / fw - 1) < 0.10
    print(f"vcorr: {f:.4f} of the pairs are {p} pairs, {fw:.4f} expected" + ("" if good else "  <- FAIL"))
    ok &= good
sys.exit(0 if ok else 1)
PY

# vcorr on one frame: the species pairs' correlations, weighted by their pairs and sqrt(var_a var_b),
# are the total's un-normalised correlation
run frame "$src/docs/scenes/bidisperse-mixture.ini" "${mix[@]}" --set run.duration=0.005 \
    --set analysis.observables=sk,vcorr
python3 - "$tmp/frame" <<'PY' || fail "vcorr per species"
import csv, json, math, sys
d = sys.argv[1]
a = json.load(open(d + "/summary.json"))["analysis"]["vcorr"]
var, labels = a["species_var"], a["species_pairs"]
assert a["frames"] == 1 and labels == ["11", "12", "22"] and a["species_file"] == "vcorr_species.csv", a
N = json.load(open(d + "/summary.json"))["analysis"]["sk"]["species_N"]
c0 = sum(q * v for q, v in zip(N, var)) / sum(N)  # <|u|^2> / 2 = sum_s x_s var_s
tot, sp = list(csv.DictReader(open(d + "/vcorr.csv"))), list(csv.DictReader(open(d + "/vcorr_species.csv")))
assert len(tot) == len(sp) > 10, (len(tot), len(sp))
worst = 0.0
for t, s in zip(tot, sp):
    assert t["r"] == s["r"], (t, s)
    n = sum(float(s["pairs_" + p]) for p in labels)
    for c in ("C_L", "C_T"):
        terms = [float(s["pairs_" + p]) * math.sqrt(var[int(p[0]) - 1] * var[int(p[1]) - 1]) *
                 float(s[f"{c}_{p}"]) for p in labels if float(s["pairs_" + p]) > 0]
        lhs = c0 * n * float(t[c])
        worst = max(worst, abs(lhs - sum(terms)) / (abs(lhs) + sum(abs(q) for q in terms)))
assert worst < 1e-9, worst
print(f"vcorr: c0 n C = sum_ab n_ab sqrt(var_a var_b) C_ab in {len(tot)} bins to {worst:.2g}; "
      f"var_s = {var[0]:.4g}, {var[1]:.4g} m^2/s^2")
PY

# a mixture's sk and vcorr resume from a checkpoint bit for bit (as tests/test_obs_mixture.sh)
short=(--set output.plots=false --set system.N=200 --set run.warmup=0.01 --set run.duration=0.06
    --set analysis.observables=sk,vcorr)
run straight "$src/docs/scenes/bidisperse-mixture.ini" "${short[@]}"
run_term_resume term "$src/docs/scenes/bidisperse-mixture.ini" "${short[@]}"
for f in sk.csv sk_shells.csv sk_species.csv vcorr.csv vcorr_species.csv; do
    cmp -s "$tmp/straight/$f" "$tmp/term/$f" || fail "$f differs after SIGTERM and --resume"
done
python3 - "$tmp/straight/summary.json" "$tmp/term/summary.json" <<'PY' || fail "summary.json's analysis differs after --resume"
import json, sys
a, b = (json.load(open(p))["analysis"] for p in sys.argv[1:])
assert a == b and len(a["sk"]["species_k_min"]["S"]) == 3, (a, b)
PY

# one species: no species output; the tables as at the branch point (release pass)
run one "$src/docs/scenes/rfm-2d.ini" --set output.plots=false --set system.N=300 \
    --set run.warmup=0.01 --set run.duration=0.03 --set analysis.observables=sk,vcorr
[[ -s $tmp/one/sk.csv && -s $tmp/one/vcorr.csv ]] || fail "one species: no sk.csv or vcorr.csv"
[ ! -e "$tmp/one/sk_species.csv" ] && [ ! -e "$tmp/one/vcorr_species.csv" ] ||
    fail "one species: a species file"
grep -q '"species_' "$tmp/one/summary.json" && fail "one species: a species field in summary.json"
if [[ $quick != 1 ]]; then
    for want in 9ed8860ebdbdf5bde14c6df2b4b051b85f952ae5536e5f8257a5c4b203e51101:sk.csv \
        af469c19fc43ef58e95a6c061047b47890cd44b4b09849b1ce34e6e05bddc689:sk_shells.csv \
        d86a9e6d5e759025c2724d5db1771454acb49c03a66669f8f2e8f87506bef15c:vcorr.csv; do
        sum=$(sha256sum <"$tmp/one/${want#*:}" | cut -d' ' -f1)
        [[ $sum == "${want%%:*}" ]] || fail "one species: ${want#*:} changed (sha256 $sum)"
    done
fi
echo "obs-mixture-structure: ok"
