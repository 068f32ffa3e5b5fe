"""Single head-on collisions in granule and in LAMMPS (pair_style granular), law by law and speed by
speed (docs/lammps.md, "Single collisions against LAMMPS"; bench/lammps_collisions.sh runs it).

Both engines integrate the same pair with the same velocity-Verlet scheme (the dashpot sees the
half-step velocity), the same time step dt = t_c(v) / steps_per_contact and the same start (the
pair one step before touching, as `granule collide` places it), so they must agree to rounding:
restitution eps_n = (v2' - v1') / v and the number of steps with a contact force. Both are also
compared with the law's exact restitution (granule's eps_n(v)) and the CVODE reference, whose
difference is the discretisation error common to both engines.

Parameter mapping (granule -> LAMMPS pair_coeff, R = r_i r_j / (r_i + r_j) = r/2, meff = M/2 = m12):
  spring_dashpot  F = k_s xi - gamma_n g_n          -> hooke k_s gamma_n damping velocity
  hertz, Tsuji    F = k_h xi^1.5 + alpha sqrt(m12 k_h) xi^(1/4) xi'
                  -> hertz k_h/sqrt(R) COR damping tsuji: LAMMPS's hertz is k_n a xi with
                     a = sqrt(R xi), and tsuji's damping alpha(COR) sqrt(meff k_n a) is our form;
                     COR is chosen so that LAMMPS's fitted alpha(COR) equals granule's exact alpha
  hertz, visco    F = k_h xi^1.5 + (3/2) A k_h sqrt(xi) xi'
                  -> hertz k_h/sqrt(R) eta damping viscoelastic, eta = (3/2) A k_h / (meff sqrt(R))
                     (LAMMPS: eta a meff xi')
  clamp = true    -> keyword limit_damping (F_n >= 0)

Then oblique collisions with rotation (run_oblique below; docs/lammps.md, "Oblique collisions
with rotation").

    /usr/bin/python3 bench/lammps_collisions.py --build BUILD --lmp LMP [--quick] [--speeds ...]
        [--steps-per-contact S] [--convergence V] [--oblique-speeds ...] [--no-oblique] [--no-mindlin]
        [--no-rolling] [--json OUT]
(--no-oblique also skips the history spring's oblique cases, run_history; --no-rolling the rolling
resistance against LAMMPS's rolling sds, run_rolling and run_rolling_arrest at the end, which run
at --oblique-speeds.)
Exit 1 when any pair of engines differs by more than --tol (default 1e-9, see TOL below).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lmp_env import fast_mpi_start, run_lmp  # noqa: E402

fast_mpi_start()  # each collision is one lmp run: its start dominates (bench/lmp_env.py)

MASS, RADIUS = 3.53e-5, 1.5e-3  # the RFM discs
# Same scheme, same dt, same start: the engines differ only by the rounding of the force
# arithmetic (e.g. LAMMPS forms k_n a xi with a = sqrt(R xi)), ~1e-16 per step, ~1e-13 after
# 1e4 steps of a contact; one step more or less in a contact would show as ~2 zeta w0 dt ~ 1e-4.
# 1e-9 leaves room for the rounding and still catches any mapping or scheme difference.
TOL = 1e-9

# name -> (granule --model, granule --set list); k_s = 5e5 N/m and k_h = 1e9 N/m^1.5 are the defaults
LAWS = {
    "spring_dashpot": ("spring_dashpot", ["eps_n=0.6"]),
    "spring_dashpot clamped": ("spring_dashpot", ["eps_n=0.6", "clamp=true"]),
    "hertz Tsuji": ("hertz", ["eps_n=0.6"]),
    "hertz Tsuji clamped": ("hertz", ["eps_n=0.6", "clamp=true"]),
    "hertz viscoelastic": ("hertz", ["viscoelastic=true", "visco_A=1e-6"]),
    "hertz viscoelastic clamped": ("hertz", ["viscoelastic=true", "visco_A=1e-6", "clamp=true"]),
}


def tsuji_alpha(cor):
    """LAMMPS's damping tsuji: alpha(e), Tsuji et al. 1992's fit, as pair_granular.cpp evaluates it."""
    return (1.2728 - 4.2783 * cor + 11.087 * cor ** 2 - 22.348 * cor ** 3 + 27.467 * cor ** 4
            - 18.022 * cor ** 5 + 4.8218 * cor ** 6)


def tsuji_cor_for(alpha):
    """The COR to give LAMMPS so that its alpha(COR) is our alpha (alpha(e) falls on [0, 1])."""
    lo, hi = 0.0, 1.0
    if not tsuji_alpha(hi) <= alpha <= tsuji_alpha(lo):
        raise ValueError(f"alpha = {alpha} outside LAMMPS's Tsuji fit range [{tsuji_alpha(1.0)}, {tsuji_alpha(0.0)}]")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if tsuji_alpha(mid) > alpha:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def scaled_restitution(alpha, clamp):
    """E(alpha) of the scaled Tsuji contact X'' = -X^1.5 - alpha X^(1/4) X' (docs/models.md), by an
    independent integrator (scipy DOP853): used for LAMMPS's own alpha(COR). None without scipy."""
    try:
        from scipy.integrate import solve_ivp
    except ImportError:
        return None

    def force(X, V):
        X = max(X, 0.0)
        return X ** 1.5 + alpha * X ** 0.25 * V

    def rhs(_t, y):
        return [y[1], -force(y[0], y[1])]

    def end(_t, y):
        return force(y[0], y[1]) if clamp else y[0]
    end.terminal, end.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 50.0), [0.0, 1.0], method="DOP853", rtol=1e-13, atol=1e-15, events=end,
                    first_step=1e-8)
    return -sol.y_events[0][0][1]


def coefficients(build, model, sets):
    """granule's own coefficients (bench_coeffs prints what gr_contact_prepare derives)."""
    args = [os.path.join(build, "bench", "bench_coeffs"), os.path.join(SRC, "docs", "scenes", "rfm-2d.ini"),
            "--set", f"model.normal={model}", "--set", "model.tangential=none",
            "--set", f"system.mass={MASS!r}", "--set", f"system.radius={RADIUS!r}"]
    for s in sets:
        args += ["--set", "model." + s]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return {k: v for k, v in (ln.split("=", 1) for ln in out.split())}


def lammps_pair_coeff(model, sets, c):
    k, gamma_n, m12 = float(c["k_s"]), float(c["gamma_n"]), float(c["m12"])
    R = RADIUS * RADIUS / (2 * RADIUS)
    clamp = " limit_damping" if "clamp=true" in sets else ""
    tail = f" tangential linear_nohistory 0.0 0.0{clamp}"
    if model == "spring_dashpot":
        return f"hooke {k!r} {gamma_n!r} damping velocity" + tail, {}
    kn = k / math.sqrt(R)
    if "viscoelastic=true" in sets:
        return f"hertz {kn!r} {gamma_n / (m12 * math.sqrt(R))!r} damping viscoelastic" + tail, {}
    alpha = gamma_n / math.sqrt(m12 * k)
    cor = tsuji_cor_for(alpha)
    return f"hertz {kn!r} {cor!r} damping tsuji" + tail, {"alpha": alpha, "lammps_cor": cor}


def granule_collide(build, model, sets, speeds, spc):
    args = [os.path.join(build, "granule"), "collide", "--model", model, "--mass", repr(MASS), "--radius", repr(RADIUS),
            "--speeds", ",".join(repr(v) for v in speeds), "--steps-per-contact", repr(spc), "--reference"]
    for s in sets:
        args += ["--set", s]
    return json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)["restitution_vs_speed"]


def write_pair_data(work, L, p1, p2, v1, w1, w2):
    """pair.data: the two discs (diameter d) at p1, p2 in a square box of side L, particle 1 moving
    with v1, particle 2 at rest, spins w1, w2 (rad/s about z)."""
    d = 2 * RADIUS
    with open(os.path.join(work, "pair.data"), "w") as f:
        f.write(f"granule pair\n\n2 atoms\n1 atom types\n\n0 {L!r} xlo xhi\n0 {L!r} ylo yhi\n"
                f"{-d!r} {d!r} zlo zhi\n\nAtoms # sphere\n\n"
                f"1 1 {d!r} 1.0 {p1[0]!r} {p1[1]!r} 0.0\n2 1 {d!r} 1.0 {p2[0]!r} {p2[1]!r} 0.0\n\n"
                f"Velocities\n\n1 {v1[0]!r} {v1[1]!r} 0.0 0.0 0.0 {w1!r}\n2 0.0 0.0 0.0 0.0 0.0 {w2!r}\n")


def deck_head(pair_lines, dim=2):
    """The input deck up to the integrator: 2D (or dim) SI, the pair of pair.data with the RFM mass."""
    pair = "\n".join(pair_lines)
    return f"""units si
dimension {dim}
boundary p p p
atom_style sphere
atom_modify map array
comm_modify vel yes
read_data pair.data
set type 1 mass {MASS!r}
{pair}
neighbor {0.3 * 2 * RADIUS!r} bin
neigh_modify delay 0 every 1 check yes
"""


def lammps_collide(lmp, work, pair_coeff, v, dt, t_c):
    """One head-on collision in LAMMPS, placed as granule collide places it: particle 2 at rest at
    2r + r/2 ahead, both moved along their free flight to one step before contact."""
    d = 2 * RADIUS
    gap = 0.5 * RADIUS
    r0 = d + gap
    L = 64 * d
    c = r0 * r0 - d * d
    t_hit = c / (r0 * v + math.sqrt((r0 * v) ** 2 - v * v * c))  # granule's contact_time_of
    t0 = t_hit - min(t_hit, dt)
    x1 = 0.5 * L + v * t0 - 0.5 * r0
    x2 = 0.5 * L + r0 - 0.5 * r0
    steps = int(math.ceil(2.0 * t_c / dt)) + 20
    write_pair_data(work, L, (x1, 0.5 * L), (x2, 0.5 * L), (v, 0.0), 0.0, 0.0)
    with open(os.path.join(work, "pair.in"), "w") as f:
        f.write(deck_head(["pair_style granular", f"pair_coeff * * {pair_coeff}"]) + f"""fix 1 all nve
fix 2 all enforce2d
timestep {dt!r}
variable on equal "fx[2] != 0.0"
fix count all ave/time 1 {steps} {steps} v_on file count.dat format " %.17g"
thermo 0
run {steps}
print "$(vx[1]:%.17g) $(vx[2]:%.17g)" file velocities.dat screen no
""")
    subprocess.run([lmp, "-in", "pair.in", "-log", "none", "-screen", "none"], cwd=work, check=True)
    v1, v2 = (float(x) for x in open(os.path.join(work, "velocities.dat")).read().split())
    mean_on = float(open(os.path.join(work, "count.dat")).read().split("\n")[2].split()[1])
    return (v2 - v1) / v, round(mean_on * steps)


def run(build, lmp, speeds, spc, laws=LAWS):
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name in laws:
            model, sets = LAWS[name]
            c = coefficients(build, model, sets)
            pair_coeff, extra = lammps_pair_coeff(model, sets, c)
            for g in granule_collide(build, model, sets, speeds, spc):
                eps_l, n_l = lammps_collide(lmp, work, pair_coeff, g["speed"], g["dt"], g["contact_time_law"])
                rows.append(dict(law=name, speed=g["speed"], dt=g["dt"], eps_law=g["eps_n_law"],
                                 eps_reference=g["eps_n_reference"], eps_granule=g["eps_n_measured"], eps_lammps=eps_l,
                                 rel_diff=abs(eps_l - g["eps_n_measured"]) / g["eps_n_law"],
                                 steps_granule=round(g["contact_time_measured"] / g["dt"]), steps_lammps=n_l,
                                 t_c_law=g["contact_time_law"], t_c_reference=g["contact_time_reference"],
                                 pair_coeff=pair_coeff, **extra))
    return rows


def lammps_own_tsuji(lmp, build, speeds, spc, eps=0.6, clamp=False):
    """LAMMPS's own calibration (damping tsuji COR = eps): the fitted alpha(eps), its exact
    restitution E(alpha) and what LAMMPS measures, at each speed."""
    sets = [f"eps_n={eps!r}"] + (["clamp=true"] if clamp else [])
    c = coefficients(build, "hertz", sets)
    R = RADIUS / 2
    alpha = tsuji_alpha(eps)
    exact = scaled_restitution(alpha, clamp)
    tail = " limit_damping" if clamp else ""
    pair_coeff = f"hertz {float(c['k_s']) / math.sqrt(R)!r} {eps!r} damping tsuji tangential linear_nohistory 0.0 0.0{tail}"
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for g in granule_collide(build, "hertz", sets, speeds, spc):
            eps_l, _ = lammps_collide(lmp, work, pair_coeff, g["speed"], g["dt"], 2 * g["contact_time_law"])
            rows.append(dict(speed=g["speed"], cor=eps, alpha_fit=alpha, eps_exact_fit=exact, eps_lammps=eps_l,
                             eps_granule=g["eps_n_measured"], alpha_exact=float(c["gamma_n"]) / math.sqrt(float(c["m12"]) * float(c["k_s"]))))
    return rows


def fmt6(x):
    return "n/a (needs python3-scipy)" if x is None else f"{x:.6f}"


def markdown(rows, own):
    out = ["| law | v (m/s) | eps law (exact) | eps CVODE | eps granule | eps LAMMPS | rel. diff. | "
           "contact steps granule / LAMMPS | t_c law (s) | t_c granule (s) |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['law']} | {r['speed']:g} | {r['eps_law']:.9f} | {r['eps_reference']:.9f} | {r['eps_granule']:.9f} | "
                   f"{r['eps_lammps']:.9f} | {r['rel_diff']:.1e} | {r['steps_granule']} / {r['steps_lammps']} | "
                   f"{r['t_c_law']:.6e} | {r['steps_granule'] * r['dt']:.6e} |")
    if own:
        o = own[0]
        out += ["", f"LAMMPS's own `damping tsuji` with COR = {o['cor']}: fitted alpha = {o['alpha_fit']:.6f} "
                f"(granule's exact inversion: {o['alpha_exact']:.6f}); the exact restitution of the fitted alpha "
                f"E(alpha_fit) = {fmt6(o['eps_exact_fit'])}", "",
                "| v (m/s) | requested eps | E(alpha_fit) | eps LAMMPS (tsuji COR) | eps granule (exact alpha) |",
                "|---|---|---|---|---|"]
        for o in own:
            out.append(f"| {o['speed']:g} | {o['cor']} | {fmt6(o['eps_exact_fit'])} | {o['eps_lammps']:.6f} | {o['eps_granule']:.6f} |")
    return "\n".join(out)


def convergence(build, lmp, v, spcs):
    """Both engines against the exact law as the step shrinks (first order for a dashpot that sees
    the half-step velocity): at which resolution each is within 1e-6 of the law."""
    rows = []
    for spc in spcs:
        for r in run(build, lmp, [v], spc):
            rows.append(dict(r, steps_per_contact=spc))
    return rows


def markdown_convergence(rows):
    out = ["| law | steps per contact | (granule - law) / law | (LAMMPS - law) / law | (granule - CVODE) / CVODE | |granule - LAMMPS| / law |",
           "|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['law']} | {r['steps_per_contact']:g} | {(r['eps_granule'] - r['eps_law']) / r['eps_law']:+.2e} | "
                   f"{(r['eps_lammps'] - r['eps_law']) / r['eps_law']:+.2e} | "
                   f"{(r['eps_granule'] - r['eps_reference']) / r['eps_reference']:+.2e} | {r['rel_diff']:.1e} |")
    return "\n".join(out)



# ---------------------------------------------------------------------------------------------
# Oblique collisions with rotation (docs/lammps.md, "Oblique collisions with rotation").
#
# `granule collide --speed V --angle A [--omega1 W1 --omega2 W2]` (the normal at impact is the x
# axis, particle 2 at rest) against LAMMPS's pair_style granular with `fix nve/sphere disc`
# (I = M r^2 / 2, granule's inertia_factor = 1/2), from the same state at the same dt. Mapping
# (LAMMPS 2021: damp_tangential = x * damp_normal_prefactor, F_t = -min(mu |F_n|, damp_tangential
# |v_tr|) v_tr / |v_tr|, |F_n| clamped to >= 0 with limit_damping):
#   tangential_dashpot  F_t = -gamma_t g_t   -> tangential linear_nohistory gamma_t/gamma_n 1e200
#                       (damping velocity: damp_normal_prefactor = gamma_n; mu = 1e200 keeps the
#                       Coulomb cap mu |F_n| out of the way: 1e4 is not enough where F_n falls
#                       continuously to 0 at the end of a clamped contact, measured 2.3e-6)
#   sliding_friction    F_t = -sign(g_t) min(mu |F_n|, m_t |g_t| / dt)   (granule's chatter-free
#                       law) -> tangential linear_nohistory (m_t/dt)/gamma_n mu: LAMMPS's damping
#                       branch of the min is exactly granule's one-step cap, m_t = m12 q/(1 + q)
#   hertz (Tsuji) + tangential_dashpot: LAMMPS scales the tangential damping with the normal
#                       one (x sqrt(meff k_n a) for tsuji, so ~ xi^(1/4)), granule's gamma_t is a
#                       constant, so one pair style cannot hold both. pair_style hybrid/overlay of
#                       two granular styles does: (1) hertz k_h/sqrt(R) COR damping tsuji
#                       tangential linear_nohistory 0 0, (2) hooke 0 ETA damping velocity
#                       tangential linear_nohistory gamma_t/ETA MU with ETA = 1e-100 (its normal
#                       force -ETA g_n is 1e-100 of the real one) and MU = 1e200 (its Coulomb cap
#                       MU ETA |g_n| = 1e100 |g_n| never acts). Unclamped only: with limit_damping
#                       style (2) would not know when the hertz force vanishes.
# The lever arm: both engines apply the torque a F_t with a = |r_ij|/2 = r - xi/2 to both discs,
# but LAMMPS forms the contact point's velocity with the full radius r (v_t - r (w_i + w_j)) and
# granule with a. The tangential laws therefore see velocities that differ by (xi/2)(w_i + w_j),
# an O(xi/d) relative difference; it vanishes only as xi_max/d -> 0 (slow impacts, stiff springs),
# which is why the comparison runs at impact speeds where xi_max/d is ~1e-8 and also at 1 m/s to
# show the O(xi/d) difference.

# name -> (granule --model, granule --set list, LAMMPS mapping kind)
OBLIQUE = {
    "spring_dashpot + tangential_dashpot": ("spring_dashpot+tangential_dashpot",
                                            ["eps_n=0.6", "eps_t=0.6", "rotation=true"], "dashpot"),
    "spring_dashpot clamped + tangential_dashpot": ("spring_dashpot+tangential_dashpot",
                                                    ["eps_n=0.6", "eps_t=0.6", "rotation=true", "clamp=true"], "dashpot"),
    "spring_dashpot + sliding_friction": ("spring_dashpot+sliding_friction",
                                          ["eps_n=0.6", "mu=0.3", "rotation=true"], "friction"),
    "hertz Tsuji + tangential_dashpot": ("hertz+tangential_dashpot",
                                         ["eps_n=0.6", "eps_t=0.6", "rotation=true"], "overlay"),
}
# (angle in degrees, omega1, omega2 in units of v / r): a plain oblique impact, and one with
# spins that make particle 1's surface run against the impact (w1 != w2, so the test sees each)
OBLIQUE_GEOMETRIES = [(30.0, 0.0, 0.0), (60.0, -0.4, 0.25)]
OVERLAY_ETA, OVERLAY_MU = 1e-100, 1e200
# What the engines must meet. The differences of g_n', g_t' (over v) and of w1', w2' (over v / r)
# stay below LEVER_ARM_BOUND x xi_max / d everywhere (measured 0.006-0.025 for the linear law,
# whose difference falls exactly in proportion to v, i.e. to xi_max / d; 0.006-0.084 for hertz,
# whose constant gamma_t damps relatively more of the longer slow contacts). A mapping error would
# not shrink with the overlap: the linear law is scale-free in v apart from xi / d. Where the
# lever-arm term is negligible (xi_max / d <= OBLIQUE_SMALL_OVERLAP), every difference is below
# OBLIQUE_TOL both over those scales and over the quantity's own value.
OBLIQUE_TOL, OBLIQUE_SMALL_OVERLAP, LEVER_ARM_BOUND = 1e-6, 1e-7, 0.2
OBLIQUE_SPEEDS = [1e-6, 1e-4, 1e-2, 1.0]


def oblique_pair_style(kind, model, sets, c, dt):
    """LAMMPS pair_style + pair_coeff lines for an oblique case (mapping above)."""
    k, gamma_n, gamma_t, m12 = float(c["k_s"]), float(c["gamma_n"]), float(c["gamma_t"]), float(c["m12"])
    clamp = " limit_damping" if "clamp=true" in sets else ""
    if kind == "dashpot":
        return ["pair_style granular",
                f"pair_coeff * * hooke {k!r} {gamma_n!r} damping velocity "
                f"tangential linear_nohistory {gamma_t / gamma_n!r} {OVERLAY_MU!r}{clamp}"]
    if kind == "friction":
        q = 0.5
        m_t = m12 * q / (1.0 + q)
        mu = float(next(x.split("=")[1] for x in sets if x.startswith("mu=")))
        return ["pair_style granular",
                f"pair_coeff * * hooke {k!r} {gamma_n!r} damping velocity "
                f"tangential linear_nohistory {m_t / dt / gamma_n!r} {mu!r}{clamp}"]
    assert kind == "overlay" and not clamp
    hertz, _ = lammps_pair_coeff(model.split("+")[0], sets, c)
    hertz = hertz.replace(" tangential linear_nohistory 0.0 0.0", "")
    return ["pair_style hybrid/overlay granular granular",
            f"pair_coeff * * granular 1 {hertz} tangential linear_nohistory 0.0 0.0",
            f"pair_coeff * * granular 2 hooke 0.0 {OVERLAY_ETA!r} damping velocity "
            f"tangential linear_nohistory {gamma_t / OVERLAY_ETA!r} {OVERLAY_MU!r}"]


def granule_oblique(build, model, sets, v, angle, w1, w2, spc, dim=2):
    """granule collide --speed --angle: dt = t_c(v_n) / spc (the normal law's contact time at the
    normal impact speed), returns (result JSON, dt). dim = 3: spheres, w1 and w2 vectors
    (bench/lammps_collisions_3d.py)."""
    # --force-dt: hertz's own t_c (at its v_max) is shorter than a slow impact's, which the step
    # check would otherwise hold against the dt resolving t_c(v_n)
    base = [os.path.join(build, "granule"), "collide", "--dim", str(dim), "--model", model, "--mass", repr(MASS),
            "--radius", repr(RADIUS), "--force-dt"]
    if dim == 3:
        w1, w2 = (",".join(repr(x) for x in w) for w in (w1, w2))
    else:
        w1, w2 = repr(w1), repr(w2)
    for s in sets:
        base += ["--set", s]
    vn = v * math.cos(math.radians(angle))
    law = json.loads(subprocess.run(base + ["--speeds", repr(vn)], check=True, capture_output=True,
                                    text=True).stdout)["restitution_vs_speed"][0]
    dt = law["contact_time_law"] / spc
    out = subprocess.run(base + ["--speed", repr(v), "--angle", repr(angle), "--omega1", w1,
                                 "--omega2", w2, "--dt", repr(dt)], check=True, capture_output=True, text=True)
    return json.loads(out.stdout), dt, law["contact_time_law"]


def run_final_dump(lmp, work, pair_lines, steps):
    """Runs pair.in in work and returns the last frame of its dump final.txt (written at step
    `steps`) as {atom id: [the dumped columns after id]}."""
    out = os.path.join(work, "final.txt")
    if os.path.exists(out):
        os.remove(out)
    p = run_lmp([lmp, "-in", "pair.in", "-log", "none"], cwd=work)
    text = open(out).read() if os.path.exists(out) else ""
    frames = text.split("ITEM: TIMESTEP")
    done = len(frames) > 1 and int(frames[-1].split()[0]) == steps
    # LAMMPS 2021 with two granular sub-styles (the hybrid/overlay mapping) ends the run with
    # "ERROR: Could not find fix ID to delete" (both sub-styles delete the one neighbour-history
    # fix); the dump of the last step is written before, so that one error is accepted
    known = "Could not find fix ID to delete" in p.stdout and pair_lines[0].startswith("pair_style hybrid")
    if not done or (p.returncode != 0 and not known):
        raise RuntimeError(f"lmp failed ({pair_lines}):\n" + "\n".join((p.stdout + p.stderr).splitlines()[-8:]))
    lines = frames[-1].split("ITEM: ATOMS")[-1].strip().split("\n")[1:]
    return {int(ln.split()[0]): [float(x) for x in ln.split()[1:]] for ln in lines}


def lammps_oblique(lmp, work, pair_lines, v, angle, w1, w2, dt, t_c, fix="nve/sphere disc", force_max=False):
    """The same oblique impact in LAMMPS, placed exactly as granule collide places it (src/collide:
    gr_collision_case_oblique, then both moved along their free flight to one step before contact,
    centred in a box of side max(64 d, 8 (|r0x| + |r0y| + d))). force_max: also the largest |f|
    on particle 2 over the run (fmax; the normal force when no tangential force acts)."""
    d = 2 * RADIUS
    a = angle * math.pi / 180.0
    c, sn = math.cos(a), math.sin(a)
    x1, v1, x2 = (-0.5 * RADIUS * c, -0.5 * RADIUS * sn), (v * c, v * sn), (2.0 * RADIUS, 0.0)
    r0 = (x2[0] - x1[0], x2[1] - x1[1])
    g0 = (-v1[0], -v1[1])
    L = max(64.0 * d, 8.0 * (abs(r0[0]) + abs(r0[1]) + d))
    # granule's contact_time_of (cancellation-free root)
    b = r0[0] * g0[0] + r0[1] * g0[1]
    gg = g0[0] * g0[0] + g0[1] * g0[1]
    cc = r0[0] * r0[0] + r0[1] * r0[1] - d * d
    t_hit = cc / (-b + math.sqrt(b * b - gg * cc))
    t0 = t_hit - min(t_hit, dt)
    p1 = (0.5 * L + x1[0] + v1[0] * t0 - 0.5 * r0[0], 0.5 * L + x1[1] + v1[1] * t0 - 0.5 * r0[1])
    p2 = (0.5 * L + x2[0] + 0.0 * t0 - 0.5 * r0[0], 0.5 * L + x2[1] + 0.0 * t0 - 0.5 * r0[1])
    steps = int(math.ceil(2.0 * t_c / dt)) + 20
    write_pair_data(work, L, p1, p2, v1, w1, w2)
    record = ('variable fmag equal "sqrt(fx[2]*fx[2] + fy[2]*fy[2])"\n'
              'fix fmag all print 1 "${fmag}" file fmag.txt screen no\n') if force_max else ""
    with open(os.path.join(work, "pair.in"), "w") as f:
        f.write(deck_head(pair_lines) + f"""fix 1 all {fix}
fix 2 all enforce2d
timestep {dt!r}
{record}thermo 0
dump final all custom {steps} final.txt id vx vy omegaz
dump_modify final sort id format float %.17g
run {steps}
""")
    vals = run_final_dump(lmp, work, pair_lines, steps)
    out = dict(v1=vals[1][0:2], v2=vals[2][0:2], omega1=vals[1][2], omega2=vals[2][2])
    if force_max:
        out["fmax"] = max(float(ln) for ln in open(os.path.join(work, "fmag.txt")) if not ln.startswith("#"))
    return out


def run_oblique(build, lmp, speeds, spc, cases=OBLIQUE, geometries=OBLIQUE_GEOMETRIES, table=OBLIQUE,
                pair_style=oblique_pair_style, force_max=False):
    """Every oblique case x geometry x speed in both engines. Compared (the normal at impact is x):
    the relative velocity's normal (x) and tangential (y) components after the collision, each
    over the impact speed, and both angular velocities over v / r; rel_diff is the largest.
    (table, pair_style: the cases and their mapping; the history spring's are at the end.)"""
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name in cases:
            model, sets, kind = table[name]
            c = coefficients_with(build, model, sets)
            for angle, w1r, w2r in geometries:
                for v in speeds:
                    w1, w2 = w1r * v / RADIUS, w2r * v / RADIUS
                    g, dt, t_c = granule_oblique(build, model, sets, v, angle, w1, w2, spc)
                    lines = pair_style(kind, model, sets, c, dt)
                    lm = lammps_oblique(lmp, work, lines, v, angle, w1, w2, dt, t_c, force_max=force_max)
                    eng = {"granule": dict(v1=g["v1_after"], v2=g["v2_after"], omega1=g["omega1"], omega2=g["omega2"]),
                           "lammps": lm}
                    q = {}
                    for e, r in eng.items():
                        q[e] = dict(g_n=(r["v2"][0] - r["v1"][0]) / v, g_t=(r["v2"][1] - r["v1"][1]) / v,
                                    w1=r["omega1"] * RADIUS / v, w2=r["omega2"] * RADIUS / v)
                    diffs = {k: abs(q["granule"][k] - q["lammps"][k]) for k in q["granule"]}
                    own = max(diffs[k] / abs(q["granule"][k]) for k in diffs if q["granule"][k] != 0.0)
                    rows.append(dict(case=name, speed=v, angle=angle, omega1_before=w1, omega2_before=w2, dt=dt,
                                     xi_over_d=g["max_overlap"] / (2 * RADIUS), granule=q["granule"], lammps=q["lammps"],
                                     diffs=diffs, rel_diff=max(diffs.values()), rel_own=own,
                                     pair_coeff=" / ".join(lines[1:]), lammps_fmax=lm.get("fmax")))
    return rows


def coefficients_with(build, model, sets):
    """bench_coeffs for NORMAL+TANGENTIAL with the given model keys (gamma_t with rotation: m_t)."""
    normal, tangential = model.split("+")[:2]  # a third part, the rolling law, sets no coefficient here
    args = [os.path.join(build, "bench", "bench_coeffs"), os.path.join(SRC, "docs", "scenes", "rfm-2d.ini"),
            "--set", f"model.normal={normal}", "--set", f"model.tangential={tangential}",
            "--set", f"system.mass={MASS!r}", "--set", f"system.radius={RADIUS!r}"]
    for s in sets:
        if not s.startswith("mu_r="):
            args += ["--set", "model." + s]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return {k: v for k, v in (ln.split("=", 1) for ln in out.split())}


def oblique_failures(rows, tol=OBLIQUE_TOL, bound=LEVER_ARM_BOUND):
    """The rows that break the bounds above, as messages (bound: the lever-arm term's, over xi_max/d)."""
    bad = []
    for r in rows:
        what = f"{r['case']} at {r['speed']:g} m/s, {r['angle']:g} deg (xi_max/d = {r['xi_over_d']:.1e})"
        if r["xi_over_d"] <= OBLIQUE_SMALL_OVERLAP and not max(r["rel_diff"], r["rel_own"]) <= tol:
            bad.append(f"{what}: engines differ by {r['rel_diff']:.2e} of v, v/r and by {r['rel_own']:.2e} of "
                       f"the values > {tol:g} ({r['diffs']})")
        if not r["rel_diff"] <= bound * r["xi_over_d"] + 1e-12:
            bad.append(f"{what}: engines differ by {r['rel_diff']:.2e} > {bound:g} xi_max/d: more than "
                       "the lever-arm term explains")
    return bad


def markdown_oblique(rows):
    out = ["| case | v (m/s) | angle | w1, w2 before (v/r) | xi_max/d | g_n'/v granule | g_t'/v granule | "
           "w1' r/v granule | w2' r/v granule | max abs. diff. granule - LAMMPS (of g_n', g_t', w1', w2' in these units) | "
           "same, each over its own value | diff / (xi_max/d) |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        gq = r["granule"]
        out.append(f"| {r['case']} | {r['speed']:g} | {r['angle']:g} | {r['omega1_before'] * RADIUS / r['speed']:g}, "
                   f"{r['omega2_before'] * RADIUS / r['speed']:g} | {r['xi_over_d']:.1e} | {gq['g_n']:.9f} | "
                   f"{gq['g_t']:.9f} | {gq['w1']:.9f} | {gq['w2']:.9f} | {r['rel_diff']:.1e} | {r['rel_own']:.1e} | "
                   f"{r['rel_diff'] / r['xi_over_d']:.3f} |")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# The history spring with rotation (issue 13; docs/lammps.md, "The history spring with rotation").
#
# granule's tangential_spring (Cundall-Strack: s += g_t dt, F_t = -k_t s - gamma_t g_t, at the
# Coulomb limit mu |F_n| the spring is shortened so that spring + dashpot give exactly mu |F_n|)
# is LAMMPS's `tangential linear_history k_t x mu` (pair_granular.cpp 2021: the same update, the
# same rescaling, Fscrit = mu |F_n,total|, the history zeroed when the discs part), with
# x = gamma_t / gamma_n for `damping velocity`. Both keep the spring in the tangent plane as the line
# of centres turns (granule: a scalar along t; LAMMPS: projected and rescaled to its magnitude).
# Same lever-arm difference as above (the spring integrates the contact point's velocity, LAMMPS
# with the full radius): the comparison at 1e-6 m/s is where it is below 1e-6. Unclamped only:
# with limit_damping LAMMPS keeps a history while F_n is held at 0 (Fscrit = 0 rescales it to
# -x eta_n v_tr / k_t), granule forgets it as soon as the normal force stops acting.
K_T, GAMMA_T = 1.5e5, 0.2  # N/m (about 0.3 k_s), kg/s (about 0.2 gamma_n at eps_n = 0.6)
HISTORY = {
    # mu so large that the Coulomb limit never acts: the undamped tangential oscillator
    "spring_dashpot + tangential_spring, sticking (mu = 1e4, no dashpot)": (
        "spring_dashpot+tangential_spring", ["eps_n=0.6", f"k_t={K_T!r}", "gamma_t=0", "mu=1e4", "rotation=true"],
        "history"),
    # sticks, then slips where F_n is small (the start and the end of the contact)
    "spring_dashpot + tangential_spring, stick-slip (mu = 0.3, gamma_t = 0.2 kg/s)": (
        "spring_dashpot+tangential_spring", ["eps_n=0.6", f"k_t={K_T!r}", f"gamma_t={GAMMA_T!r}", "mu=0.3",
                                             "rotation=true"], "history"),
    # slips through most of the contact: the spring is held at the Coulomb limit
    "spring_dashpot + tangential_spring, sliding (mu = 0.05, gamma_t = 0.2 kg/s)": (
        "spring_dashpot+tangential_spring", ["eps_n=0.6", f"k_t={K_T!r}", f"gamma_t={GAMMA_T!r}", "mu=0.05",
                                             "rotation=true"], "history"),
}


# The engines' difference has two known parts. The first step of a contact: granule accumulates s
# over half a step, LAMMPS over the whole step (see MINDLIN below): a first-order difference, at most
# FIRST_STEP_COEFF / steps per contact. The lever arms, over xi_max/d: measured 0.15-0.29 for the sticking spring (the undamped
# oscillator integrates the contact point's velocity, where the lever arms differ, for the whole
# contact) and 0.2-0.7 at 1e-6-1e-5 m/s, where g_n' differs most: there the line of centres turns
# by less than LAMMPS's threshold for rotating its history vector (|s.n| k_t > 1e-10 mu |F_n|), so
# its spring keeps a normal component of the order of the turn (also O(xi/d)); stick-slip <= 0.1,
# sliding <= 1e-3 (the Coulomb force does not see the velocity).
HISTORY_LEVER_ARM_BOUND = 1.0
FIRST_STEP_COEFF = 1.0


def history_pair_style(kind, model, sets, c, dt):
    """pair_style granular hooke + linear_history for a HISTORY case (mapping above)."""
    assert kind == "history" and "clamp=true" not in sets
    key = dict(x.split("=", 1) for x in sets)
    k, gamma_n = float(c["k_s"]), float(c["gamma_n"])
    return ["pair_style granular",
            f"pair_coeff * * hooke {k!r} {gamma_n!r} damping velocity "
            f"tangential linear_history {float(key['k_t'])!r} {float(key['gamma_t']) / gamma_n!r} {float(key['mu'])!r}"]


def run_history(build, lmp, speeds, spc):
    """The HISTORY cases in both engines, geometries and comparison as run_oblique's."""
    rows = run_oblique(build, lmp, speeds, spc, cases=HISTORY, table=HISTORY, pair_style=history_pair_style)
    for r in rows:
        r["steps_per_contact"] = spc
    return rows


def history_failures(rows):
    """The HISTORY rows whose difference is more than the first step's and the lever arms' terms."""
    bad = []
    for r in rows:
        bound = HISTORY_LEVER_ARM_BOUND * r["xi_over_d"] + FIRST_STEP_COEFF / r["steps_per_contact"]
        if not r["rel_diff"] <= bound:
            bad.append(f"{r['case']} at {r['speed']:g} m/s, {r['angle']:g} deg (xi_max/d = {r['xi_over_d']:.1e}, "
                       f"{r['steps_per_contact']:g} steps per contact): engines differ by {r['rel_diff']:.2e} > {bound:.2e}")
    return bad


# Mindlin: tangential_spring with mindlin = true (k_t = k_m sqrt(xi), k_m = kt_ratio (3/2) k_h) on
# hertz (Tsuji), no rotation, against LAMMPS's plain `tangential mindlin k_L 0 mu` (its history is
# the displacement, kept when the contact radius changes): LAMMPS's k_L a with a = sqrt(R xi) is
# k_m sqrt(xi), so k_L = k_m / sqrt(R). fix nve (no rotation: the contact point's velocity is g.t in
# both). The engines differ in one thing, on purpose: in the step where a contact forms, granule
# accumulates s over half a step (the mean time since the touch), LAMMPS over the whole dt
# (docs/models.md, tangential_spring). Their difference is therefore first order: it must halve
# when dt halves (within MINDLIN_ORDER_TOL) and stay below MINDLIN_COEFF / steps per contact
# (measured 0.03-0.77). With the first step as LAMMPS's, they agreed to rounding (<= 3.4e-10, mu
# <= 100). The sticking case uses mu = 100 (it slips only where F_n falls to 0 at the end), not
# more: LAMMPS turns the history with the line of centres only where |s.n| k_t > 1e-10 mu |F_n|
# (frame_update in gran_sub_mod_tangential.cpp), so a huge mu leaves it unturned (measured with
# LAMMPS's first step, clamped, 60 degrees, 1e3 steps per contact: difference 4.9e-10 at mu = 1e3,
# 1.6e-5 at 1e6, 4.1e-5 at 1e9, granule's result the same for all three).
MINDLIN = {
    "hertz Tsuji + tangential_spring mindlin": ("hertz+tangential_spring", ["eps_n=0.6", "mindlin=true", "mu=0.5"]),
    "hertz Tsuji clamped + tangential_spring mindlin, sticking": (
        "hertz+tangential_spring", ["eps_n=0.6", "mindlin=true", "mu=100", "clamp=true"]),
    "hertz viscoelastic + tangential_spring mindlin": ("hertz+tangential_spring",
                                                       ["viscoelastic=true", "visco_A=1e-6", "mindlin=true", "mu=0.3"]),
}
MINDLIN_ORDER_TOL, MINDLIN_COEFF = 0.3, 1.0
MINDLIN_ANGLES = [30.0, 60.0]


def mindlin_pair_style(sets, c):
    """pair_style + pair_coeff of a Mindlin case (mapping above)."""
    R = RADIUS * RADIUS / (2 * RADIUS)
    hertz, _ = lammps_pair_coeff("hertz", sets, c)
    hertz = hertz.replace(" tangential linear_nohistory 0.0 0.0", "")
    k_m = (2.0 / 7.0) * 1.5 * float(c["k_s"])  # kt_ratio at its default 2/7
    mu = float(next(x.split("=")[1] for x in sets if x.startswith("mu=")))
    return ["pair_style granular", f"pair_coeff * * {hertz} tangential mindlin {k_m / math.sqrt(R)!r} 0.0 {mu!r}"]


def run_mindlin(build, lmp, v, spcs, cases=MINDLIN, angles=MINDLIN_ANGLES):
    """Every Mindlin case x angle at impact speed v and each steps-per-contact in spcs, in both
    engines: g_n', g_t' over v after the collision, their largest difference, and that times the
    steps per contact (constant for the first step's difference)."""
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name, (model, sets) in cases.items():
            c = coefficients_with(build, model, sets)
            lines = mindlin_pair_style(sets, c)
            for angle in angles:
                for spc in spcs:
                    g, dt, t_c = granule_oblique(build, model, sets, v, angle, 0.0, 0.0, spc)
                    lm = lammps_oblique(lmp, work, lines, v, angle, 0.0, 0.0, dt, t_c, fix="nve")
                    q = {e: dict(g_n=(r["v2"][0] - r["v1"][0]) / v, g_t=(r["v2"][1] - r["v1"][1]) / v)
                         for e, r in (("granule", dict(v1=g["v1_after"], v2=g["v2_after"])), ("lammps", lm))}
                    diff = max(abs(q["granule"][k] - q["lammps"][k]) for k in ("g_n", "g_t"))
                    rows.append(dict(case=name, speed=v, angle=angle, steps_per_contact=spc, granule=q["granule"],
                                     lammps=q["lammps"], diff=diff, diff_x_spc=diff * spc, pair_coeff=lines[1]))
    return rows


def markdown_mindlin(rows):
    out = ["| case | angle | steps per contact | g_n'/v granule | g_t'/v granule | g_t'/v LAMMPS | max abs. diff. | "
           "diff x steps per contact |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['case']} | {r['angle']:g} | {r['steps_per_contact']:g} | {r['granule']['g_n']:.9f} | "
                   f"{r['granule']['g_t']:.9f} | {r['lammps']['g_t']:.9f} | {r['diff']:.1e} | {r['diff_x_spc']:.3f} |")
    return "\n".join(out)


def mindlin_failures(rows):
    """The rows whose difference is not the first step's: not first order (halving with dt within
    MINDLIN_ORDER_TOL) or above MINDLIN_COEFF / steps per contact, as messages."""
    bad = [f"{r['case']} at {r['angle']:g} deg, {r['steps_per_contact']:g} steps per contact: engines differ by "
           f"{r['diff']:.2e} > {MINDLIN_COEFF:g} / steps per contact" for r in rows
           if not r["diff"] * r["steps_per_contact"] <= MINDLIN_COEFF]
    for a, b in zip(rows, rows[1:]):
        if (a["case"], a["angle"]) != (b["case"], b["angle"]):
            continue
        order = (a["diff"] / b["diff"]) / (b["steps_per_contact"] / a["steps_per_contact"]) if b["diff"] > 0 else 0.0
        if not abs(order - 1.0) <= MINDLIN_ORDER_TOL:
            bad.append(f"{a['case']} at {a['angle']:g} deg: differences {a['diff']:.2e}, {b['diff']:.2e} at "
                       f"{a['steps_per_contact']:g}, {b['steps_per_contact']:g} steps per contact: not first order")
    return bad


# ---------------------------------------------------------------------------------------------
# Rolling resistance: rolling_friction against LAMMPS's `rolling sds` (issue 13; docs/lammps.md,
# "Rolling resistance").
#
# granule's rolling_friction (models/rolling_friction.h): a torque pair -+M sign(w_i - w_j),
# M = min(mu_r |F_n| R_eff, I |w_i - w_j| / (2 dt)), no spring. LAMMPS 2021's `rolling sds k_roll
# gamma_roll mu_roll` (pair_granular.cpp): a rolling displacement s += v_rl dt with v_rl = R_eff
# (w_i - w_j) z x n, the force f_r = -k_roll s - gamma_roll v_rl truncated at Frcrit = mu_roll
# Fncrit (Fncrit = |F_n,total| for hooke and hertz, damping included, 0 where limit_damping clamps
# it), s then reset to -(f_r + gamma_roll v_rl) / k_roll, the torques -+R_eff n x f_r, the history
# zeroed when the discs part. In 2D the torque on i is -R_eff |f_r| sign(w_i - w_j) while the
# spring sits at its limit, so with gamma_roll = 0 and mu_roll = mu_r it is granule's mu_r |F_n|
# R_eff exactly (the same R_eff = r / 2, the same |F_n|), as long as the spring is at the limit in
# every step of the contact: from its first step, when k_roll R_eff |w_i - w_j| dt exceeds
# mu_r |F_n| of that step, and in every later one, when it exceeds the step's growth of mu_r |F_n|
# (the truncated spring, Frcrit_old / k_roll, grows by R_eff |w_i - w_j| dt per step). A stiff
# k_roll does both: k_roll = M (ROLL_OMEGA_DT / dt)^2, where sqrt(k_roll / M) is the angular
# frequency of the stuck spring's relative-spin oscillation (dw'' = -2 R_eff^2 k_roll theta / I,
# I = M r^2 / 2), so ROLL_OMEGA_DT = 0.1 resolves it with 63 steps a period (stable) while
# k_roll dt is 1/dt times larger than the per-step growth of the limit. (k_roll = 0 is no
# option: LAMMPS's rescaling divides by it.) The tangential laws are mapped as above; the
# rolling torques are equal and opposite, the tangential ones equal on both discs (the same arm
# in both engines), so the rolling law alone sets w_i - w_j, the tangential law alone w_i + w_j,
# g_t (and g_n as always). Hence w_i - w_j must agree to rounding at every impact speed, the
# rest within the tangential law's own bounds (lever arm, first step).
#
# The laws part where the relative rolling stops within the contact (mu_r R_eff int |F_n| dt >=
# I |w_i - w_j|_0 / 2): granule's limit arrests it, w_i - w_j = 0 exactly from then on, no energy
# stored; LAMMPS's spring crosses zero and holds, w_i - w_j oscillates about 0 (angular frequency
# sqrt(k_roll / M)) with the energy the spring held at its limit, Frcrit^2 / (2 k_roll), at most,
# and the discs part with a residue |w_i - w_j| <= mu_r max |F_n| sqrt(2 / (k_roll I)) (the
# relative spin's energy I (w_i - w_j)^2 / 4 can be no more than that). ROLLING_ARREST checks
# exactly that, on contacts without tangential force (so |f| on a disc is |F_n|).
ROLL_OMEGA_DT = 0.1
ROLLING = {
    "spring_dashpot + rolling_friction (mu = 0, mu_r = 0.3)": (
        "spring_dashpot+sliding_friction+rolling_friction", ["eps_n=0.6", "mu=0", "rotation=true", "mu_r=0.3"], "none"),
    "spring_dashpot clamped + rolling_friction (mu = 0, mu_r = 0.1)": (
        "spring_dashpot+sliding_friction+rolling_friction", ["eps_n=0.6", "mu=0", "rotation=true", "mu_r=0.1",
                                                             "clamp=true"], "none"),
    "hertz Tsuji + rolling_friction (mu = 0, mu_r = 0.3)": (
        "hertz+sliding_friction+rolling_friction", ["eps_n=0.6", "mu=0", "rotation=true", "mu_r=0.3"], "none"),
    "hertz viscoelastic clamped + rolling_friction (mu = 0, mu_r = 0.3)": (
        "hertz+sliding_friction+rolling_friction", ["viscoelastic=true", "visco_A=1e-6", "clamp=true", "mu=0",
                                                    "rotation=true", "mu_r=0.3"], "none"),
    "spring_dashpot + tangential_dashpot + rolling_friction (mu_r = 0.3)": (
        "spring_dashpot+tangential_dashpot+rolling_friction", ["eps_n=0.6", "eps_t=0.6", "rotation=true", "mu_r=0.3"],
        "dashpot"),
    "spring_dashpot + sliding_friction (mu = 0.3) + rolling_friction (mu_r = 0.1)": (
        "spring_dashpot+sliding_friction+rolling_friction", ["eps_n=0.6", "mu=0.3", "rotation=true", "mu_r=0.1"],
        "friction"),
    "spring_dashpot + tangential_spring stick-slip + rolling_friction (mu_r = 0.3)": (
        "spring_dashpot+tangential_spring+rolling_friction", ["eps_n=0.6", f"k_t={K_T!r}", f"gamma_t={GAMMA_T!r}",
                                                              "mu=0.3", "rotation=true", "mu_r=0.3"], "history"),
    "hertz Tsuji + tangential_dashpot + rolling_friction (mu_r = 0.1)": (
        "hertz+tangential_dashpot+rolling_friction", ["eps_n=0.6", "eps_t=0.6", "rotation=true", "mu_r=0.1"], "overlay"),
}
# (angle, w1, w2 in v / r): w1 - w2 = 1 and -0.65 before; the rolling impulse changes it by about
# mu_r (1 + eps_n) cos(angle) (2 mu_r R_eff P_n / I with P_n = m12 (1 + eps_n) v cos(angle)),
# at most 0.52 and 0.26 here: the relative rolling never stops
ROLLING_GEOMETRIES = [(30.0, 0.5, -0.5), (60.0, -0.4, 0.25)]
# The same geometries with mu_r large enough to stop the relative rolling within the contact:
# mu_r (1 + eps_n) cos(angle) = 2.8 and 1.6 (mu_r = 2; arrested at 36 % and 40 % of the normal
# impulse, while loading), 1.4 and 0.8 (mu_r = 1; at 72 % and 81 %, while unloading)
ROLLING_ARREST = {
    "spring_dashpot + rolling_friction, arrested (mu = 0, mu_r = 2)": (
        "spring_dashpot+sliding_friction+rolling_friction", ["eps_n=0.6", "mu=0", "rotation=true", "mu_r=2"], "none"),
    "hertz Tsuji + rolling_friction, arrested (mu = 0, mu_r = 1)": (
        "hertz+sliding_friction+rolling_friction", ["eps_n=0.6", "mu=0", "rotation=true", "mu_r=1"], "none"),
}
# w_i - w_j agrees to ROLLING_TOL over v / r: without tangential force (kind none) at every speed,
# and so does everything else there (measured <= 2.2e-14); with one, where xi_max/d <= 1e-7
# (measured <= 2.0e-12; 4.1e-12 at 1e-4 m/s). At finite overlaps a tangential law moves the two engines' trajectories
# apart by its lever-arm (or first-step) term, so the normal force, and with it the rolling
# torque's limit, differs a little: w_i - w_j then differs by ROLLING_TRAJECTORY xi_max/d at most
# (measured 1e-5 xi_max/d, e.g. 1.4e-8 at 1 m/s, 1.7e-11 at 1e-2 m/s)
ROLLING_TOL, ROLLING_TRAJECTORY = 1e-9, 1e-4


def rolling_pair_style(kind, model, sets, c, dt):
    """The LAMMPS lines of a ROLLING case: the tangential law's mapping (above; kind none: no
    tangential force, granule's sliding_friction with mu = 0) + `rolling sds k_roll 0 mu_r` on the
    pair style that carries the normal force (the first: its F_n sets Frcrit)."""
    base = [x for x in sets if not x.startswith("mu_r=")]
    if kind == "none":
        lines = ["pair_style granular", "pair_coeff * * " + lammps_pair_coeff(model.split("+")[0], base, c)[0]]
    elif kind == "history":
        lines = history_pair_style(kind, model, base, c, dt)
    else:
        lines = oblique_pair_style(kind, model, base, c, dt)
    return with_rolling_sds(lines, sets, dt)


def with_rolling_sds(lines, sets, dt):
    """lines (pair_style, pair_coeff...) with `rolling sds k_roll 0 mu_r` on the first pair_coeff:
    k_roll = M (ROLL_OMEGA_DT / dt)^2, mu_r from sets (also bench/lammps_collisions_3d.py)."""
    mu_r = float(next(x.split("=")[1] for x in sets if x.startswith("mu_r=")))
    k_roll = MASS * (ROLL_OMEGA_DT / dt) ** 2
    lines[1] += f" rolling sds {k_roll!r} 0.0 {mu_r!r}"
    return lines


def with_spin_difference(rows):
    """Adds to each row the relative spin (w1 - w2) r / v before (dw0) and after in both engines
    (dw: granule, LAMMPS) and their difference dw_diff."""
    for r in rows:
        r["dw0"] = (r["omega1_before"] - r["omega2_before"]) * RADIUS / r["speed"]
        r["dw"] = {e: r[e]["w1"] - r[e]["w2"] for e in ("granule", "lammps")}
        r["dw_diff"] = abs(r["dw"]["granule"] - r["dw"]["lammps"])
    return rows


def run_rolling(build, lmp, speeds, spc, cases=ROLLING, geometries=ROLLING_GEOMETRIES):
    """The ROLLING cases in both engines (geometries and comparison as run_oblique's)."""
    rows = run_oblique(build, lmp, speeds, spc, cases=cases, geometries=geometries, table=ROLLING,
                       pair_style=rolling_pair_style)
    for r in rows:
        r["steps_per_contact"], r["kind"] = spc, ROLLING[r["case"]][2]
    return with_spin_difference(rows)


def rolling_failures(rows):
    """The ROLLING rows that break the mapping: w1 - w2 not equal to rounding (ROLLING_TOL, over
    v / r; plus the trajectory term with a tangential force), the rolling not acting or stopping,
    and the rest outside its tangential law's bounds (none: ROLLING_TOL too, there is no lever arm
    without a tangential force)."""
    bad = []
    for r in rows:
        what = f"{r['case']} at {r['speed']:g} m/s, {r['angle']:g} deg"
        bound = ROLLING_TOL + (0.0 if r["kind"] == "none" else ROLLING_TRAJECTORY * r["xi_over_d"])
        if not r["dw_diff"] <= bound:
            bad.append(f"{what}: w1 - w2 differs by {r['dw_diff']:.2e} (v / r) > {bound:.2e}")
        change = r["dw"]["granule"] - r["dw0"]
        if not (abs(change) > 1e-2 and r["dw"]["granule"] * r["dw0"] > 0.0):
            bad.append(f"{what}: w1 - w2 from {r['dw0']:g} to {r['dw']['granule']:g} (v / r): the rolling law did "
                       "not act, or it stopped the rolling (not a non-arrest case)")
    none = [r for r in rows if r["kind"] == "none"]
    bad += [f"{r['case']} at {r['speed']:g} m/s, {r['angle']:g} deg: engines differ by {r['rel_diff']:.2e} > "
            f"{ROLLING_TOL:g} without a tangential force" for r in none if not r["rel_diff"] <= ROLLING_TOL]
    bad += history_failures([r for r in rows if r["kind"] == "history"])
    bad += oblique_failures([r for r in rows if r["kind"] not in ("none", "history")])
    return bad


def run_rolling_arrest(build, lmp, speeds, spc, cases=ROLLING_ARREST, geometries=ROLLING_GEOMETRIES):
    """The ROLLING_ARREST cases (in ROLLING's geometries), with LAMMPS's largest |F_n| (no tangential
    force: |f| on a disc) and its residue bound mu_r max |F_n| sqrt(2 / (k_roll I)) in v / r."""
    rows = run_oblique(build, lmp, speeds, spc, cases=cases, geometries=geometries,
                       table=ROLLING_ARREST, pair_style=rolling_pair_style, force_max=True)
    inertia = 0.5 * MASS * RADIUS ** 2
    for r in with_spin_difference(rows):
        mu_r = float(next(x.split("=")[1] for x in ROLLING_ARREST[r["case"]][1] if x.startswith("mu_r=")))
        k_roll = MASS * (ROLL_OMEGA_DT / r["dt"]) ** 2
        r["residue_bound"] = mu_r * r["lammps_fmax"] * math.sqrt(2.0 / (k_roll * inertia)) * RADIUS / r["speed"]
    return rows


# granule's arrested w1 - w2 over its value before; LAMMPS's residue must be at least this much
# larger (a spring that springs back), and within ARREST_BOUND_SLACK of its energy bound (the
# explicit step can overshoot the limit by one step's change)
ARREST_ZERO, ARREST_BOUND_SLACK = 1e-12, 1.05


def arrest_failures(rows):
    """What the ROLLING_ARREST rows must show: translation and w1 + w2 the same in both engines
    (rolling touches neither), granule's w1 - w2 = 0, LAMMPS's residue nonzero and within its bound."""
    bad = []
    for r in rows:
        what = f"{r['case']} at {r['speed']:g} m/s, {r['angle']:g} deg"
        g, lm = r["granule"], r["lammps"]
        rest = max(abs(g["g_n"] - lm["g_n"]), abs(g["g_t"] - lm["g_t"]), abs(g["w1"] + g["w2"] - lm["w1"] - lm["w2"]))
        if not rest <= ROLLING_TOL:
            bad.append(f"{what}: g_n', g_t' or w1' + w2' differ by {rest:.2e} > {ROLLING_TOL:g}")
        if not abs(r["dw"]["granule"]) <= ARREST_ZERO * abs(r["dw0"]):
            bad.append(f"{what}: granule's w1 - w2 = {r['dw']['granule']:.3e} v/r after, not arrested")
        res = abs(r["dw"]["lammps"])
        if not ARREST_ZERO * abs(r["dw0"]) * 1e3 < res <= ARREST_BOUND_SLACK * r["residue_bound"]:
            bad.append(f"{what}: LAMMPS's w1 - w2 = {r['dw']['lammps']:.3e} v/r after: not a spring's residue in "
                       f"(0, {r['residue_bound']:.3e}]")
    return bad


def markdown_rolling(rows):
    out = ["| case | v (m/s) | angle | (w1 - w2) r/v before | xi_max/d | (w1' - w2') r/v granule | LAMMPS | abs. diff. | "
           "max abs. diff. of g_n', g_t', w1', w2' | same, over own values | LAMMPS residue bound |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        bound = f"{r['residue_bound']:.3e}" if "residue_bound" in r else "-"
        out.append(f"| {r['case']} | {r['speed']:g} | {r['angle']:g} | {r['dw0']:g} | {r['xi_over_d']:.1e} | "
                   f"{r['dw']['granule']:.9f} | {r['dw']['lammps']:.9f} | {r['dw_diff']:.1e} | {r['rel_diff']:.1e} | "
                   f"{r['rel_own']:.1e} | {bound} |")
    return "\n".join(out)


SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def find_lmp():
    """The first lmp on PATH built with the GRANULAR package, or None (the tests then skip)."""
    import shutil
    for b in ("lmp", "lmp_serial", "lmp_mpi"):
        path = shutil.which(b)
        if path and "GRANULAR" in subprocess.run([path, "-h"], capture_output=True, text=True).stdout:
            return path
    return None

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(SRC, "build"))
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--quick", action="store_true", help="two speeds, 1000 steps per contact")
    ap.add_argument("--speeds", default="0.001,0.01,0.1,1,3")
    ap.add_argument("--steps-per-contact", type=float, default=1e4)
    ap.add_argument("--convergence", type=float, metavar="V",
                    help="also step sizes from 1e3 to 1e6 steps per contact at impact speed V (m/s)")
    ap.add_argument("--json")
    ap.add_argument("--tol", type=float, default=TOL)
    ap.add_argument("--oblique-speeds", default=",".join(repr(v) for v in OBLIQUE_SPEEDS),
                    help="impact speeds (m/s) of the oblique cases with rotation; --quick: 1e-6 only")
    ap.add_argument("--no-oblique", action="store_true", help="head-on collisions only")
    ap.add_argument("--mindlin-speed", type=float, default=0.1,
                    help="impact speed (m/s) of the Mindlin cases (tangential_spring mindlin = true, no rotation)")
    ap.add_argument("--no-mindlin", action="store_true", help="leave out the Mindlin cases")
    ap.add_argument("--no-rolling", action="store_true",
                    help="leave out rolling_friction against rolling sds (run at --oblique-speeds)")
    a = ap.parse_args()
    speeds = [float(x) for x in a.speeds.split(",")]
    spc = a.steps_per_contact
    if a.quick:
        speeds, spc = [0.1, 1.0], 1000.0
    rows = run(a.build, a.lmp, speeds, spc)
    own = lammps_own_tsuji(a.lmp, a.build, speeds, spc)
    print(markdown(rows, own))
    conv = []
    if a.convergence:
        conv = convergence(a.build, a.lmp, a.convergence, [1e3, 1e4, 1e5, 1e6])
        print(f"\nConvergence at v = {a.convergence:g} m/s:\n")
        print(markdown_convergence(conv))
        rows += conv
    oblique, history = [], []
    if not a.no_oblique:
        oblique = run_oblique(a.build, a.lmp, [1e-6] if a.quick else [float(x) for x in a.oblique_speeds.split(",")], spc)
        print("\nOblique collisions with rotation:\n")
        print(markdown_oblique(oblique))
        history = run_history(a.build, a.lmp, [1e-6] if a.quick else [float(x) for x in a.oblique_speeds.split(",")], spc)
        print("\nThe history spring with rotation:\n")
        print(markdown_oblique(history))
    mindlin = []
    if not a.no_mindlin:
        mindlin = run_mindlin(a.build, a.lmp, a.mindlin_speed, [1e3, 2e3] if a.quick else [1e3, 4e3, 1.6e4])
        print("\nMindlin (tangential_spring mindlin = true, no rotation) against tangential mindlin:\n")
        print(markdown_mindlin(mindlin))
    rolling, arrest = [], []
    if not a.no_rolling:
        rolling_speeds = [1e-6] if a.quick else [float(x) for x in a.oblique_speeds.split(",")]
        rolling = run_rolling(a.build, a.lmp, rolling_speeds, spc)
        arrest = run_rolling_arrest(a.build, a.lmp, rolling_speeds, spc)
        print("\nRolling resistance (rolling_friction) against rolling sds:\n")
        print(markdown_rolling(rolling))
        print("\nRolling arrested within the contact (where the laws part):\n")
        print(markdown_rolling(arrest))
    if a.json:
        json.dump({"rows": rows, "lammps_tsuji": own, "steps_per_contact": spc, "oblique": oblique, "history": history,
                   "mindlin": mindlin, "rolling": rolling, "rolling_arrest": arrest}, open(a.json, "w"), indent=1)
    rolling_bad = rolling_failures(rolling) + arrest_failures(arrest)
    for msg in rolling_bad:
        print(f"lammps_collisions: MISMATCH rolling {msg}", file=sys.stderr)
    history_bad = history_failures(history)
    for msg in history_bad:
        print(f"lammps_collisions: MISMATCH history {msg}", file=sys.stderr)
    for msg in mindlin_failures(mindlin):
        print(f"lammps_collisions: MISMATCH mindlin {msg}", file=sys.stderr)
    for msg in oblique_failures(oblique):
        print(f"lammps_collisions: MISMATCH oblique {msg}", file=sys.stderr)
    bad = [r for r in rows if not (r["rel_diff"] <= a.tol and r["steps_granule"] == r["steps_lammps"])]
    for r in bad:
        print(f"lammps_collisions: MISMATCH {r['law']} at {r['speed']} m/s: eps {r['eps_granule']!r} vs "
              f"{r['eps_lammps']!r} (rel. {r['rel_diff']:.2e} > {a.tol:g}), contact steps {r['steps_granule']} vs "
              f"{r['steps_lammps']}", file=sys.stderr)
    sys.exit(1 if bad or oblique_failures(oblique) or history_bad or mindlin_failures(mindlin) or rolling_bad else 0)
