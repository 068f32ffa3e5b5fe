"""Single oblique collisions of two spheres in granule (`granule collide --dim 3`) and in LAMMPS
(pair_style granular, dimension 3, fix nve/sphere), model pair by model pair (docs/lammps.md,
"Single collisions in 3D"; issue 35). The machinery and the parameter mappings are
bench/lammps_collisions.py's (the 2D comparison); this adds the third dimension:

 - granule places the impact in its plane z = 0 (normal x, particle 2 at rest) and gives the
   spheres spins about arbitrary axes (--omega1 WX,WY,WZ), so the contact point's velocity, the
   history vector and the torques leave the plane;
 - LAMMPS gets the same pair turned by the rotation Q that takes granule's x, y, z to LAMMPS's
   y, z, x (a cyclic permutation, exact in floating point: the impact lies in LAMMPS's yz plane,
   its impact parameter along LAMMPS's z), and its velocities and spins after the collision are
   turned back by Q^T before they are compared. A general rotation (frame(axis, angle)) moves
   the positions by rounding, and the pair starts exactly one step before the touch (as in
   `granule collide`), so whether the first step overlaps becomes a matter of rounding: one
   contact step more or less, an O(1 / steps per contact) difference (measured 0.5 / steps per
   contact at 1e-4 m/s), which is why the exact permutation is the default;
 - spheres: I = 2/5 M r^2 in both (granule's default inertia_factor in 3D, LAMMPS's nve/sphere).

Compared, over v (velocities) and v / r (spins): the relative velocity after the collision
(normal x, tangential y, z) and both angular velocity vectors; rel_diff is the largest difference.
The known, documented differences are the 2D comparison's: the lever arm (LAMMPS forms the
contact point's velocity with the full radius, granule with |r_ij| / 2: O(xi_max / d)) and, for
the history springs, granule's half first step (O(1 / steps per contact)). Both shrink: the
cases run at v = 1e-6 m/s (xi_max / d ~ 1e-9), and --spc sets the steps per contact.

Then the rolling law (run_rolling, after the cases above; --no-rolling skips it): the 2D
comparison's rolling_friction cases against LAMMPS's `rolling sds`, with its mapping and its rule
(ROLLING and rolling_failures below), spins with a twisting and an out-of-plane rolling part.

    /usr/bin/python3 bench/lammps_collisions_3d.py --build BUILD --lmp LMP [--speeds V,...]
        [--spc S,...] [--cases SUBSTRING] [--no-rolling] [--json OUT]
Exit 1 when a case differs by more than its bound (bound_of below; rolling: rolling_failures).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lammps_collisions as lc  # noqa: E402

MASS, RADIUS = lc.MASS, lc.RADIUS
Q_SPHERE = 0.4  # solid spheres: granule's default with --dim 3, LAMMPS's fix nve/sphere
K_T, GAMMA_T = lc.K_T, lc.GAMMA_T
# hertz at v = 1e-6 m/s is much softer than the linear spring (dF_n/dxi ~ 1e4 N/m at xi_max):
# k_t about 0.3 of that, so that the step check (10 steps a tangential period) holds
K_T_HERTZ = 3e3
# name -> (granule --model, granule --set list, LAMMPS mapping kind)
CASES = {
    "hooke + linear_nohistory (tangential_dashpot)": lc.OBLIQUE["spring_dashpot + tangential_dashpot"],
    "hooke + linear_nohistory (sliding_friction mu = 0.3)": lc.OBLIQUE["spring_dashpot + sliding_friction"],
    "hooke undamped + linear_history, sticking (mu = 1e4, no dashpot)": (
        "spring_dashpot+tangential_spring", ["eps_n=1", f"k_t={K_T!r}", "gamma_t=0", "mu=1e4", "rotation=true"],
        "history"),
    # the 2D comparison's three: sticking, stick-slip, sliding
    **{"hooke + linear_history, " + name.split(", ", 1)[1]: case for name, case in lc.HISTORY.items()},
    "hertz Tsuji + linear_nohistory (tangential_dashpot)": lc.OBLIQUE["hertz Tsuji + tangential_dashpot"],
    "hertz undamped + linear_history, stick-slip (mu = 0.3)": (
        "hertz+tangential_spring", ["eps_n=1", f"k_t={K_T_HERTZ!r}", "gamma_t=0", "mu=0.3", "rotation=true"], "hertz_history"),
    "hertz Tsuji + linear_history, stick-slip (mu = 0.3)": (
        "hertz+tangential_spring", ["eps_n=0.6", f"k_t={K_T_HERTZ!r}", "gamma_t=0", "mu=0.3", "rotation=true"],
        "hertz_history"),
    "hertz Tsuji + mindlin, stick-slip (mu = 0.5)": (
        "hertz+tangential_spring", ["eps_n=0.6", "mindlin=true", "mu=0.5", "v_max=1e-6", "rotation=true"], "mindlin"),
}
# (angle in degrees, w1, w2 in units of v / r): spins about (1, 2, -1) and (0, -1, 3)
GEOMETRIES = [(30.0, (0.5, 1.0, -0.5), (0.0, 0.0, 0.0)), (60.0, (-0.2, 0.3, 0.4), (0.0, -0.25, 0.75))]
SPEEDS = [1e-6]
# A case passes when rel_diff <= LEVER_ARM x xi_max/d + FIRST_STEP / steps per contact (history
# laws) + ROUNDING. The coefficients are the 2D comparison's (bench/lammps_collisions.py:
# LEVER_ARM_BOUND 0.2 without history, HISTORY_LEVER_ARM_BOUND 1.0 and FIRST_STEP_COEFF 1.0 with).
ROUNDING = 1e-9


# granule's x, y, z -> LAMMPS's y, z, x
CYCLIC = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]


def frame(axis=(1.0, 2.0, -1.0), angle=0.9):
    """Rodrigues' rotation matrix about axis by angle (not exact in floating point: see above)."""
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    c, s, t = math.cos(angle), math.sin(angle), 1.0 - math.cos(angle)
    return [[c + x * x * t, x * y * t - z * s, x * z * t + y * s],
            [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
            [z * x * t - y * s, z * y * t + x * s, c + z * z * t]]


def mul(m, v):
    return [sum(m[r][k] * v[k] for k in range(3)) for r in range(3)]


def mul_t(m, v):
    return [sum(m[k][r] * v[k] for k in range(3)) for r in range(3)]


def coefficients_3d(build, model, sets):
    """bench_coeffs on the 3D scene (inertia_factor 2/5: gamma_t of eps_t with m_t = m12 q/(1+q))."""
    normal, tangential = model.split("+")[:2]
    args = [os.path.join(build, "bench", "bench_coeffs"), os.path.join(lc.SRC, "docs", "scenes", "rfm-3d.ini"),
            "--set", f"model.normal={normal}", "--set", f"model.tangential={tangential}",
            "--set", f"system.mass={MASS!r}", "--set", f"system.radius={RADIUS!r}"]
    for s in sets:
        if not s.startswith("mu_r="):  # the rolling law (a third part of model) sets no coefficient here
            args += ["--set", "model." + s]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return {k: v for k, v in (ln.split("=", 1) for ln in out.split())}


def pair_lines(kind, model, sets, c, dt):
    """The LAMMPS pair_style and pair_coeff lines of a case (the 2D mappings; friction with q = 2/5)."""
    key = dict(x.split("=", 1) for x in sets)
    k, gamma_n = float(c["k_s"]), float(c["gamma_n"])
    if kind == "dashpot" or kind == "overlay":
        return lc.oblique_pair_style(kind, model, sets, c, dt)
    if kind == "friction":
        m_t = float(c["m12"]) * Q_SPHERE / (1.0 + Q_SPHERE)
        return ["pair_style granular", f"pair_coeff * * hooke {k!r} {gamma_n!r} damping velocity "
                f"tangential linear_nohistory {m_t / dt / gamma_n!r} {float(key['mu'])!r}"]
    gamma_t = float(key.get("gamma_t", "0"))
    x = gamma_t / gamma_n if gamma_t != 0.0 else 0.0
    if kind == "history":
        return ["pair_style granular", f"pair_coeff * * hooke {k!r} {gamma_n!r} damping velocity "
                f"tangential linear_history {float(key['k_t'])!r} {x!r} {float(key['mu'])!r}"]
    if kind == "hertz_history":
        assert gamma_t == 0.0  # LAMMPS's tangential damping follows tsuji's xi^(1/4): only gamma_t = 0 maps
        R = RADIUS / 2
        if gamma_n == 0.0:
            normal = f"hertz {k / math.sqrt(R)!r} 0.0 damping viscoelastic"
        else:
            normal = lc.lammps_pair_coeff("hertz", sets, c)[0].replace(" tangential linear_nohistory 0.0 0.0", "")
        return ["pair_style granular",
                f"pair_coeff * * {normal} tangential linear_history {float(key['k_t'])!r} 0.0 {float(key['mu'])!r}"]
    assert kind == "mindlin"
    return lc.mindlin_pair_style(sets, c)


def lammps_3d(lmp, work, lines, v, angle, w1, w2, dt, t_c, Q, rotation=True):
    """The same impact in LAMMPS (dimension 3, nve/sphere), placed as granule collide places it
    (gr_collision_case_oblique, moved along the free flight to one step before contact) and turned
    by Q about the box centre; returns the velocities and spins after, turned back."""
    d = 2 * RADIUS
    a = math.radians(angle)
    ca, sa = math.cos(a), math.sin(a)
    x1, v1, x2 = (-0.5 * RADIUS * ca, -0.5 * RADIUS * sa), (v * ca, v * sa), (2.0 * RADIUS, 0.0)
    r0 = (x2[0] - x1[0], x2[1] - x1[1])
    b = -(r0[0] * v1[0] + r0[1] * v1[1])
    gg = v1[0] ** 2 + v1[1] ** 2
    cc = r0[0] ** 2 + r0[1] ** 2 - d * d
    t_hit = cc / (-b + math.sqrt(b * b - gg * cc))
    t0 = t_hit - min(t_hit, dt)
    L = max(64.0 * d, 8.0 * (abs(r0[0]) + abs(r0[1]) + d))
    # granule's positions, rounded as src/collide/collide.c forms them (the first contact step
    # hangs on that rounding: the pair starts one step before the touch), then turned by Q
    p1 = [0.5 * L + x1[0] + v1[0] * t0 - 0.5 * r0[0], 0.5 * L + x1[1] + v1[1] * t0 - 0.5 * r0[1], 0.5 * L]
    p2 = [0.5 * L + x2[0] + 0.0 * t0 - 0.5 * r0[0], 0.5 * L + x2[1] + 0.0 * t0 - 0.5 * r0[1], 0.5 * L]
    if Q == CYCLIC:
        P1, P2 = mul(Q, p1), mul(Q, p2)
    else:
        P1 = [0.5 * L + c for c in mul(Q, [x - 0.5 * L for x in p1])]
        P2 = [0.5 * L + c for c in mul(Q, [x - 0.5 * L for x in p2])]
    V1 = mul(Q, [v1[0], v1[1], 0.0])
    W1, W2 = mul(Q, w1), mul(Q, w2)
    steps = int(math.ceil(2.0 * t_c / dt)) + 20
    f = lambda xs: " ".join(repr(x) for x in xs)  # noqa: E731
    with open(os.path.join(work, "pair.data"), "w") as fh:
        fh.write(f"granule pair 3d\n\n2 atoms\n1 atom types\n\n0 {L!r} xlo xhi\n0 {L!r} ylo yhi\n0 {L!r} zlo zhi\n\n"
                 f"Atoms # sphere\n\n1 1 {d!r} 1.0 {f(P1)}\n2 1 {d!r} 1.0 {f(P2)}\n\n"
                 f"Velocities\n\n1 {f(V1)} {f(W1)}\n2 0.0 0.0 0.0 {f(W2)}\n")
    fix = "nve/sphere" if rotation else "nve"
    with open(os.path.join(work, "pair.in"), "w") as fh:
        fh.write(lc.deck_head(lines, dim=3) + f"""fix 1 all {fix}
timestep {dt!r}
thermo 0
dump final all custom {steps} final.txt id vx vy vz omegax omegay omegaz
dump_modify final sort id format float %.17g
run {steps}
""")
    vals = lc.run_final_dump(lmp, work, lines, steps)
    return dict(v1=mul_t(Q, vals[1][0:3]), v2=mul_t(Q, vals[2][0:3]), omega1=mul_t(Q, vals[1][3:6]),
                omega2=mul_t(Q, vals[2][3:6]))


def bound_of(kind, xi_over_d, spc):
    """How far the engines may differ (over v, v/r): the lever arm and the half first step."""
    hist = kind in ("history", "hertz_history", "mindlin")
    return (lc.HISTORY_LEVER_ARM_BOUND if hist else lc.LEVER_ARM_BOUND) * xi_over_d + \
        (lc.FIRST_STEP_COEFF / spc if hist else 0.0) + ROUNDING


def run(build, lmp, speeds, spcs, cases=CASES, geometries=GEOMETRIES, Q=None, pair_style=pair_lines):
    """Every case x geometry x speed x steps per contact in both engines (pair_style: the LAMMPS
    mapping, pair_lines or rolling_lines)."""
    Q = Q or CYCLIC
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name, (model, sets, kind) in cases.items():
            c = coefficients_3d(build, model, sets)
            for angle, w1r, w2r in geometries:
                for v in speeds:
                    for spc in spcs:
                        w1, w2 = [x * v / RADIUS for x in w1r], [x * v / RADIUS for x in w2r]
                        g, dt, t_c = lc.granule_oblique(build, model, sets, v, angle, w1, w2, spc, dim=3)
                        lines = pair_style(kind, model, sets, c, dt)
                        lm = lammps_3d(lmp, work, lines, v, angle, w1, w2, dt, t_c, Q, "rotation=true" in sets)
                        zero = [0.0, 0.0, 0.0]
                        eng = {"granule": dict(v1=g["v1_after"], v2=g["v2_after"], omega1=g.get("omega1", zero),
                                               omega2=g.get("omega2", zero)), "lammps": lm}
                        q = {}
                        for e, r in eng.items():
                            gv = [(r["v2"][a] - r["v1"][a]) / v for a in range(3)]
                            q[e] = dict(g_n=gv[0], g_ty=gv[1], g_tz=gv[2],
                                        **{f"w{p}{ax}": r[f"omega{p}"][a] * RADIUS / v
                                           for p in (1, 2) for a, ax in enumerate("xyz")})
                        diffs = {k: abs(q["granule"][k] - q["lammps"][k]) for k in q["granule"]}
                        xi = g["max_overlap"] / (2 * RADIUS)
                        rows.append(dict(case=name, kind=kind, speed=v, angle=angle, w1_before=list(w1r),
                                         w2_before=list(w2r), steps_per_contact=spc, dt=dt, xi_over_d=xi,
                                         granule=q["granule"], lammps=q["lammps"], diffs=diffs,
                                         rel_diff=max(diffs.values()), bound=bound_of(kind, xi, spc),
                                         pair_coeff=" / ".join(lines[1:])))
    return rows


def failures(rows):
    return [f"{r['case']} at {r['speed']:g} m/s, {r['angle']:g} deg, {r['steps_per_contact']:g} steps per contact "
            f"(xi_max/d = {r['xi_over_d']:.1e}): engines differ by {r['rel_diff']:.2e} > {r['bound']:.2e} "
            f"({ {k: f'{x:.1e}' for k, x in r['diffs'].items()} })" for r in rows if not r["rel_diff"] <= r["bound"]]


def markdown(rows):
    head = ["case", "angle", "w1, w2 before (v/r)", "steps per contact", "xi_max/d", "g_n'/v", "g_t'/v (y, z)",
            "max abs. diff. (velocities over v, spins over v/r)", "x steps per contact", "bound"]
    vec = lambda w: "(" + ", ".join(f"{x:g}" for x in w) + ")"  # noqa: E731
    table = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        gq = r["granule"]
        cells = [r["case"], f"{r['angle']:g}", vec(r["w1_before"]) + ", " + vec(r["w2_before"]),
                 f"{r['steps_per_contact']:g}", f"{r['xi_over_d']:.1e}", f"{gq['g_n']:.9f}",
                 f"{gq['g_ty']:.6f}, {gq['g_tz']:.6f}", f"{r['rel_diff']:.1e}",
                 f"{r['rel_diff'] * r['steps_per_contact']:.3f}", f"{r['bound']:.1e}"]
        table.append("| " + " | ".join(cells) + " |")
    return "\n".join(table)


# ---------------------------------------------------------------------------------------------
# Rolling resistance in 3D: rolling_friction against `rolling sds` (docs/lammps.md, "Single
# collisions in 3D"). The cases, the mapping (`rolling sds k_roll 0 mu_r`, k_roll = M (0.1 / dt)^2,
# on the style carrying F_n; lc.with_rolling_sds) and the regime are the 2D comparison's
# (bench/lammps_collisions.py, ROLLING): the slider at its limit in every step, the relative
# rolling slowed but never stopped. In 3D both engines take the relative spin's part in the
# tangent plane, dw_perp = (w_i - w_j) - ((w_i - w_j).n) n: granule's torque -+M dw_perp/|dw_perp|
# (src/core/kernels_3d.c), LAMMPS's -+R_eff n x f_r with f_r along -R_eff (w_i - w_j) x n at the
# limit, i.e. along -dw_perp too; the part about n (twisting) neither touches (LAMMPS `twisting`
# off). Spheres: the rolling impulse changes |dw_perp| by about 1.25 mu_r (1 + eps_n) cos(angle)
# (2 mu_r R_eff P_n / I, I = 2/5 M r^2), at most 0.54 and 0.30 v/r here (mu_r = 0.3), against
# |dw_perp| = 0.875 and 0.743 before; the stuck spring's angular frequency is sqrt(1.25 k_roll / M)
# = 0.11 / dt (56 steps a period). The geometries: spins about axes out of the impact plane, with
# a twisting part (along n = x at the touch) and the rolling part in y and z; w1 at 30 degrees is
# (300, -200, 150) rad/s at 1 m/s.
#
# The 2D rule holds where xi_max/d <= 1e-7 (the default 1e-6 m/s). At finite overlaps the laws part
# by a term of LAMMPS's spring: n turns within the contact (by about pi xi_max/d tan(angle)), and
# with it dw_perp turns about n when dw has a twisting part; LAMMPS projects its history into the
# new tangent plane (which turns it about the axis n_old x n_new, not about n), so its force lags
# dw_perp's direction by a fraction Frcrit / (k_roll R_eff |dw_perp| dt) of each step's turn, where
# granule's torque (the rigid limit) follows it. Measured (hooke, 30 degrees, 1 m/s, xi_max/d =
# 1.4e-3, 1e3 steps per contact): w1' - w2' differs by 6.6e-8 v/r; 1.3e-7 with twice the twisting
# part, 7.5e-11 with none; 1.6e-8 and 4.1e-9 at 2e3 and 4e3 steps per contact; 2.6e-7, 1.6e-8 and
# 4.1e-9 at ROLL_OMEGA_DT 0.05, 0.2, 0.4 (i.e. 1 / k_roll). In 2D dw_perp turns exactly with the
# tangent plane, so the projection follows it and the laws agree at every overlap. The rule is
# not widened for this: run_rolling at such speeds reports these cases as mismatches.
ROLLING = lc.ROLLING
ROLLING_GEOMETRIES = [(30.0, (0.45, -0.3, 0.225), (-0.3, 0.4, -0.3)), (60.0, (-0.2, -0.3, 0.4), (0.1, 0.25, -0.1))]


def rolling_lines(kind, model, sets, c, dt):
    """The LAMMPS lines of a ROLLING case: the tangential mapping (pair_lines; kind none: no
    tangential force, granule's sliding_friction with mu = 0) + lc.with_rolling_sds."""
    base = [x for x in sets if not x.startswith("mu_r=")]
    if kind == "none":
        lines = ["pair_style granular", "pair_coeff * * " + lc.lammps_pair_coeff(model.split("+")[0], base, c)[0]]
    else:
        lines = pair_lines(kind, model, base, c, dt)
    return lc.with_rolling_sds(lines, sets, dt)


def run_rolling(build, lmp, speeds, spcs, cases=ROLLING, geometries=ROLLING_GEOMETRIES, Q=None):
    """The ROLLING cases (run above with rolling_lines), with the relative spin w1 - w2 (v / r)
    before (dw0) and after in both engines (dw) and its largest componentwise difference dw_diff."""
    rows = run(build, lmp, speeds, spcs, cases, geometries, Q, pair_style=rolling_lines)
    for r in rows:
        r["dw0"] = [a - b for a, b in zip(r["w1_before"], r["w2_before"])]
        r["dw"] = {e: [r[e][f"w1{ax}"] - r[e][f"w2{ax}"] for ax in "xyz"] for e in ("granule", "lammps")}
        r["dw_diff"] = max(abs(a - b) for a, b in zip(r["dw"]["granule"], r["dw"]["lammps"]))
    return rows


def rolling_failures(rows):
    """The 2D comparison's rule (lc.rolling_failures): w1 - w2 (each component, v / r) agrees to
    lc.ROLLING_TOL, plus lc.ROLLING_TRAJECTORY xi_max/d with a tangential force; without one every
    compared number agrees to lc.ROLLING_TOL; with one the rest keeps its law's bound_of; the
    rolling part (y, z: n = x at the touch) changes by > 0.01 v/r and keeps its direction."""
    bad = []
    for r in rows:
        what = f"{r['case']} at {r['speed']:g} m/s, {r['angle']:g} deg, {r['steps_per_contact']:g} steps per contact"
        bound = lc.ROLLING_TOL + (0.0 if r["kind"] == "none" else lc.ROLLING_TRAJECTORY * r["xi_over_d"])
        if not r["dw_diff"] <= bound:
            why = " (LAMMPS's spring lags dw_perp turning about n, see ROLLING)" if r["xi_over_d"] > 1e-7 else ""
            bad.append(f"{what}: w1 - w2 differs by {r['dw_diff']:.2e} (v / r) > {bound:.2e}{why}")
        p0, p1 = r["dw0"][1:], r["dw"]["granule"][1:]
        if not (abs(math.hypot(*p1) - math.hypot(*p0)) > 1e-2 and p0[0] * p1[0] + p0[1] * p1[1] > 0.0):
            bad.append(f"{what}: w1 - w2 from {r['dw0']} to {r['dw']['granule']} (v / r): the rolling law did not "
                       "act, or it stopped the rolling")
        if r["kind"] == "none" and not r["rel_diff"] <= lc.ROLLING_TOL:
            bad.append(f"{what}: engines differ by {r['rel_diff']:.2e} > {lc.ROLLING_TOL:g} without a tangential force")
    return bad + failures([r for r in rows if r["kind"] != "none"])


def markdown_rolling(rows):
    head = ["case", "angle", "w1, w2 before (v/r)", "steps per contact", "xi_max/d", "(w1 - w2) r/v after, granule",
            "abs. diff. of w1' - w2'", "max abs. diff. (all)", "bound of w1' - w2'"]
    vec = lambda w, f="g": "(" + ", ".join(f"{x:{f}}" for x in w) + ")"  # noqa: E731
    table = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        b = lc.ROLLING_TOL + (0.0 if r["kind"] == "none" else lc.ROLLING_TRAJECTORY * r["xi_over_d"])
        cells = [r["case"], f"{r['angle']:g}", vec(r["w1_before"]) + ", " + vec(r["w2_before"]),
                 f"{r['steps_per_contact']:g}", f"{r['xi_over_d']:.1e}", vec(r["dw"]["granule"], ".9f"),
                 f"{r['dw_diff']:.1e}", f"{r['rel_diff']:.1e}", f"{b:.1e}"]
        table.append("| " + " | ".join(cells) + " |")
    return "\n".join(table)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(lc.SRC, "build"))
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--speeds", default=",".join(repr(v) for v in SPEEDS))
    ap.add_argument("--spc", default="1000,4000", help="steps per contact (comma-separated)")
    ap.add_argument("--cases", default="", help="only the cases whose name contains this")
    ap.add_argument("--no-rolling", action="store_true", help="leave out rolling_friction against rolling sds")
    ap.add_argument("--json")
    a = ap.parse_args()
    speeds, spcs = [float(x) for x in a.speeds.split(",")], [float(x) for x in a.spc.split(",")]
    rows = run(a.build, a.lmp, speeds, spcs, {k: v for k, v in CASES.items() if a.cases in k})
    print(markdown(rows))
    rolling = [] if a.no_rolling else run_rolling(a.build, a.lmp, speeds, spcs,
                                                  {k: v for k, v in ROLLING.items() if a.cases in k})
    if rolling:
        print("\nRolling resistance (rolling_friction) against rolling sds:\n")
        print(markdown_rolling(rolling))
    if a.json:
        json.dump({"rows": rows, "rolling": rolling}, open(a.json, "w"), indent=1)
    bad = failures(rows) + rolling_failures(rolling)
    for m in bad:
        print(f"lammps_collisions_3d: MISMATCH {m}", file=sys.stderr)
    sys.exit(1 if bad else 0)
