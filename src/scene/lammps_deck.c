/* `granule export lammps`: a scene as a LAMMPS input deck and data file (docs/lammps.md).
 *
 * The mapping (thesis eqs. 2.4-2.5, 2.9, 2.16, 2.23):
 *   contact   pair_style gran/hooke Kn 0 gamman gammat xmu 1: F_n = Kn xi - meff gamman v_n and
 *             F_t = -min(xmu |F_n|, meff gammat |v_t|) along v_t. LAMMPS multiplies its damping
 *             constants by the pair's effective mass meff = M/2 = m12, so gamman = gamma_n / m12
 *             and gammat = gamma_t / m12 (1/s); xmu = 1e4 (its largest value) keeps the Coulomb
 *             cap off, leaving the pure tangential dashpot. gran/hooke lets F_n turn attractive at
 *             the end of a contact like granule's clamp = false; clamp = true adds limit_damping.
 *   noise     fix addforce with per-atom normal() variables of standard deviation sqrt(2 D / dt)
 *             per component, redrawn every step; symmetrised noise keeps the centre of mass at
 *             rest, which fix momentum 1 does; com mode removes it every com_interval.
 *   driving   none: no noise fix. langevin: fix langevin T T tau with k_B T = M T_bath / dim (units si,
 *             k_B = 1.380649e-23 J/K): its drag -M v / tau and random force of variance
 *             2 k_B T M / (tau dt) are the bath's (docs/systems-driving.md), no momentum fix.
 *   walls     boundary f along a wall axis, and per wall fix wall/gran hooke Kn 0 gamman_w
 *             gammat_w xmu 1 with gamman_w = gamma_n(wall) / M (and gammat_w = gamma_t(wall) / M):
 *             LAMMPS's wall contact has meff = M, granule's wall law the reduced mass M and the
 *             walls' own eps_n, eps_t. A sawtooth floor is refused (wiggle is sinusoidal). The vibrating floor is its own fix with
 *             wiggle, whose plane is at lo + A - A cos(2 pi f t): with lo = -A it oscillates about 0
 *             with granule's amplitude, a quarter period behind granule's A sin(2 pi f t) (the
 *             time averages of a steady bed do not see the phase); with A >= r the box
 *             reaches A + d below 0 so that no grain riding the floor leaves it.
 *   gravity   fix gravity |g| vector gx/|g| gy/|g| 0. With walls no fix momentum is written (the
 *             walls and gravity change the total momentum): the noise is then not symmetrised.
 *   rotation  fix nve integrates no angular velocity, as granule ignores rotation.
 *   species   a mixture ([species] lists, docs/mixtures.md): atom type s + 1 per species s, each
 *             atom's own diameter in the data file, set type s mass m_s, and pair_style granular
 *             with one pair_coeff per species pair: hooke k_s gamma_ab damping velocity
 *             (F_n = k_s xi - gamma_ab v_n with the pair's own damping, kg/s, which granule
 *             calibrates to the pair's reduced mass) and, with tangential_dashpot, tangential
 *             linear_nohistory x mu: F_t = -x gamma_ab v_t with x = gamma_t,ab / gamma_ab (the
 *             pair's own tangential damping) and mu = 1e4 (no Coulomb cap); without a tangential
 *             law x = mu = 0. The dump adds the type column. Walls: one wall/gran fix per species
 *             (group sN of type N) with gamman_w = gamma_n,s(wall) / m_s, the species' own wall
 *             damping (LAMMPS's wall meff is the atom's mass, granule calibrates each species').
 *   sizes     a radius distribution ([species] distribution): the same with one atom type per
 *             grain (at most LMP_GRAIN_TYPES grains), set type i mass m_i, and one pair_coeff per
 *             pair of grains with the coefficients the force kernel scales to the pair's reduced
 *             mass and effective radius (gr_contact_size_scaled). Walls are refused there (one
 *             wall fix per grain would cost N fixes).
 *   3D        dimension 3, a periodic cube, a third noise component (fz), no enforce2d, the
 *             momentum fix and T over three components (docs/three-dimensions.md).
 *   schedule  run warmup / dt steps, then dump every sample_every / dt steps for duration / dt.
 * The initial particles are those gr_sim_create places for the scene and its seed, so granule's
 * own run and the LAMMPS run start from the same state. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/export.h"
#include "granule/sim.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"

#define LMP_XMU 1.0e4       /* gran/hooke's largest friction coefficient: no Coulomb cap */
#define LMP_SKIN 0.3        /* neighbor skin, in diameters */
#define LMP_GRAIN_TYPES 400 /* a radius distribution: one atom type per grain, at most this many */

static int refuse_unmappable(const gr_scene *s, gr_error *err)
{
    if (s->size_distribution && s->N > LMP_GRAIN_TYPES) {
        return GR_FAIL(err, GR_EINVAL,
                       "export lammps: %s: [species] distribution with N = %d: the deck gives each "
                       "grain its own atom type and each pair of grains its own pair_coeff, which "
                       "is allowed for N <= %d (docs/lammps.md)",
                       s->source, s->N, LMP_GRAIN_TYPES);
    }
    if (s->size_distribution && (s->boundary[0] || s->boundary[1] || s->boundary[2])) {
        return GR_FAIL(err, GR_EINVAL,
                       "export lammps: %s: [species] distribution with walls: every grain's wall "
                       "damping is its own and LAMMPS's wall/gran takes one per fix; allowed: a "
                       "radius distribution in a periodic box, or [species] lists with walls",
                       s->source);
    }
    if ((s->n_species >= 2 || s->size_distribution) && s->tangential && !(s->contact.eps_n < 1.0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "export lammps: %s: model.tangential = %s with [species] and eps_n = 1: "
                       "pair_style granular gives the tangential damping as a multiple of the "
                       "normal one, which is zero; allowed with a tangential law: eps_n < 1",
                       s->source, s->tangential->name);
    }
    if (s->dim == 1) {
        return GR_FAIL(
            err, GR_EINVAL,
            "export lammps: %s: LAMMPS has no 1D systems (dimension is 2 or 3); export a 2D scene",
            s->source);
    }
    /* capabilities, not names: a soft time-stepped integrator, laws that say which LAMMPS pair
     * style they are (gr_model.lammps_pair) */
    if (s->integrator->instantaneous || s->integrator->free_flight) {
        return GR_FAIL(err, GR_EINVAL,
                       "export lammps: %s: LAMMPS is time-stepped only; set integrator.kind = "
                       "verlet (its event-driven and hybrid integrators have no LAMMPS equivalent)",
                       s->source);
    }
    if (s->vibrate && s->motion != 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "export lammps: %s: [boundary] motion = sawtooth: fix wall/gran's wiggle is "
                       "sinusoidal; allowed: motion = sine",
                       s->source);
    }
    if (!s->normal->lammps_pair || strcmp(s->normal->lammps_pair, "gran/hooke") != 0) {
        return GR_FAIL(
            err, GR_EINVAL,
            "export lammps: %s: model.normal = %s has no gran/hooke equivalent; use spring_dashpot",
            s->source, s->normal->name);
    }
    if (s->tangential && !(s->tangential->lammps_pair &&
                           strcmp(s->tangential->lammps_pair, s->normal->lammps_pair) == 0)) {
        return GR_FAIL(err, GR_EINVAL,
                       "export lammps: %s: model.tangential = %s: gran/hooke caps a dashpot at xmu "
                       "|F_n| but has no pure Coulomb force; use tangential_dashpot or none",
                       s->source, s->tangential->name);
    }
    return GR_OK;
}

static int write_data(const char *dir, const gr_scene *s, const gr_particles *p, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "data.granule", err);
    if (rc) {
        return rc;
    }
    const double d = 2.0 * p->radius;         /* a mixture: the largest diameter */
    const bool grains = s->size_distribution; /* one type per grain (write_sizes) */
    const int types = grains ? p->n : (p->species ? p->n_species : 1);
    fprintf(f.f, "granule initial state of %s (seed %llu)\n\n%d atoms\n%d atom types\n\n",
            s->source, (unsigned long long)s->seed, p->n, types);
    /* a vibrating floor goes A below 0; a grain on it keeps its centre above 0 while A < r, else
     * the box must reach below 0 (A + d), and is then not square (granule analyse
     * --lammps-dump reads square boxes only) */
    double lo[3] = {0.0, 0.0, 0.0};
    if (s->vibrate && s->amplitude >= s->radius) {
        lo[s->vibrate - 1] = -(s->amplitude + d);
    }
    const bool three = p->dim == 3; /* a cube; 2D: a slab one diameter either side of z = 0 */
    fprintf(f.f,
            "%.17g %.17g xlo xhi\n%.17g %.17g ylo yhi\n%.17g %.17g zlo zhi\n\nAtoms # sphere\n\n",
            lo[0], p->L, lo[1], p->L, three ? lo[2] : -d, three ? p->L : d);
    /* id type diameter density x y z; the mass is set in the deck (a mixture: per type) */
    for (int i = 0; i < p->n; i++) {
        const int type = grains ? i + 1 : (p->species ? p->species[i] + 1 : 1);
        fprintf(f.f, "%d %d %.17g 1 %.17g %.17g %.17g\n", i + 1, type,
                p->radii ? 2.0 * p->radii[i] : d, p->x[i], p->y[i], three ? p->z[i] : 0.0);
    }
    fprintf(f.f, "\nVelocities\n\n");
    for (int i = 0; i < p->n; i++) {
        fprintf(f.f, "%d %.17g %.17g %.17g 0 0 0\n", i + 1, p->vx[i], p->vy[i],
                three ? p->vz[i] : 0.0);
    }
    return gr_file_commit(&f, err);
}

/* One wall/gran fix of group `group` (suffix for its name) with damping constants gn, gt (1/s). */
static void write_wall_fix(FILE *o, const gr_scene *s, const gr_lammps_export *e, bool clamp, int a,
                           int side, const char *group, const char *suffix, double gn, double gt)
{
    static const char axis[3] = {'x', 'y', 'z'};
    const bool wiggle = s->vibrate == a + 1 && s->amplitude > 0.0 && s->frequency > 0.0;
    fprintf(o, "fix wall_%c%s%s %s wall/gran hooke %.17g 0.0 %.17g %.17g %.17g 1 %cplane ", axis[a],
            side ? "hi" : "lo", suffix, group, e->kn, gn, gt, LMP_XMU, axis[a]);
    if (side) {
        fprintf(o, "NULL %.17g", s->L);
    } else {
        /* wiggle puts the plane at lo + A - A cos(w t): lo = -A oscillates it about 0 as
         * granule's A sin(w t), a quarter period apart */
        fprintf(o, "%.17g NULL", wiggle ? -s->amplitude : 0.0);
        if (wiggle) {
            fprintf(o, " wiggle %c %.17g %.17g", axis[a], s->amplitude, 1.0 / s->frequency);
        }
    }
    fprintf(o, "%s\n", clamp ? " limit_damping" : "");
}

/* walls and gravity: boundary letters already written; the wall fixes and gravity. A mixture of
 * species lists gets one fix per species and wall, each with the species' own damping. */
static void write_walls(FILE *o, const gr_scene *s, const gr_sim *sim, const gr_lammps_export *e,
                        bool clamp)
{
    static const char axis[3] = {'x', 'y', 'z'};
    const bool species = s->n_species >= 2 && gr_sim_species_wall_coeffs(sim, 0);
    if (species && (s->boundary[0] || s->boundary[1] || s->boundary[2])) {
        for (int k = 0; k < s->n_species; k++) {
            fprintf(o, "group s%d type %d\n", k + 1, k + 1);
        }
    }
    for (int a = 0; a < 3; a++) {
        if (!s->boundary[a]) {
            continue;
        }
        if (species) {
            fprintf(o,
                    "# walls along %c, one fix per species: gamma_n(wall) of each species at its "
                    "own mass (meff = m_s)\n",
                    axis[a]);
            for (int side = 0; side < 2; side++) {
                for (int k = 0; k < s->n_species; k++) {
                    const gr_contact_coeffs *c = gr_sim_species_wall_coeffs(sim, k);
                    const double m = s->species_masses[k];
                    char group[16], suffix[16];
                    snprintf(group, sizeof group, "s%d", k + 1);
                    snprintf(suffix, sizeof suffix, "_s%d", k + 1);
                    write_wall_fix(o, s, e, clamp, a, side, group, suffix, c->gamma_n / m,
                                   s->tangential ? c->gamma_t / m : 0.0);
                }
            }
            continue;
        }
        fprintf(o,
                "# walls along %c: gamma_n(wall) = %.17g kg/s at the reduced mass M (meff = M)\n",
                axis[a], e->gamman_wall * s->mass);
        for (int side = 0; side < 2; side++) {
            write_wall_fix(o, s, e, clamp, a, side, "all", "", e->gamman_wall, e->gammat_wall);
        }
    }
    const double g = s->gravity[2] != 0.0
                         ? hypot(hypot(s->gravity[0], s->gravity[1]), s->gravity[2])
                         : hypot(s->gravity[0], s->gravity[1]);
    if (g > 0.0) {
        fprintf(o, "fix gravity all gravity %.17g vector %.17g %.17g ", g, s->gravity[0] / g,
                s->gravity[1] / g);
        if (s->gravity[2] != 0.0) {
            fprintf(o, "%.17g\n", s->gravity[2] / g);
        } else {
            fputs("0.0\n", o);
        }
    }
}

/* A mixture's masses and contacts: set type per species, pair_style granular per species pair. */
static void write_species(FILE *o, const gr_scene *s, const gr_sim *sim, const gr_lammps_export *e,
                          bool clamp)
{
    for (int a = 0; a < s->n_species; a++) {
        fprintf(o, "set type %d mass %.17g\n", a + 1, s->species_masses[a]);
    }
    fprintf(o,
            "# contact of species a and b: F_n = k_s xi - gamma_ab v_n, gamma_ab calibrated to "
            "the pair's reduced mass (k_s = %.17g N/m)%s\npair_style granular\n",
            e->kn,
            s->tangential ? "; F_t = -x_ab gamma_ab v_t with x_ab = gamma_t,ab / gamma_ab and "
                            "mu_t so large that no Coulomb cap acts"
                          : "");
    for (int a = 0; a < s->n_species; a++) {
        for (int b = a; b < s->n_species; b++) {
            const gr_contact_coeffs *c = gr_sim_species_coeffs(sim, a, b);
            fprintf(o, "pair_coeff %d %d hooke %.17g %.17g damping velocity tangential ", a + 1,
                    b + 1, c->k_s, c->gamma_n);
            if (s->tangential) { /* refuse_unmappable: gamma_n > 0 */
                fprintf(o, "linear_nohistory %.17g %.17g", c->gamma_t / c->gamma_n, LMP_XMU);
            } else {
                fprintf(o, "linear_nohistory 0.0 0.0");
            }
            fprintf(o, "%s\n", clamp ? " limit_damping" : "");
        }
    }
}

/* A radius distribution: each grain its own atom type and mass, each pair of grains its own
 * pair_coeff with the coefficients the force kernel scales to the pair's reduced mass and
 * effective radius from the reference pair's (gr_contact_size_scaled). */
static int write_sizes(FILE *o, const gr_scene *s, const gr_sim *sim, const gr_lammps_export *e,
                       bool clamp, gr_error *err)
{
    gr_sim_params sp;
    gr_scene_sim_params(s, &sp);
    gr_contact_coeffs unused;
    double m_ref, r_ref;
    int rc = gr_size_reference_coeffs(&sp, &unused, &m_ref, &r_ref, err);
    if (rc) {
        return rc;
    }
    const gr_contact_coeffs *ref = gr_sim_coeffs(sim); /* the kernel's reference pair */
    const gr_particles p = gr_sim_particles(sim);
    for (int i = 0; i < p.n; i++) {
        fprintf(o, "set type %d mass %.17g\n", i + 1, p.masses[i]);
    }
    fprintf(
        o,
        "# contact of grains i and j: F_n = k_ij xi - gamma_ij v_n, the reference pair's (k_s = "
        "%.17g N/m, reduced mass %.17g kg, effective radius %.17g m) scaled to the pair's "
        "reduced mass and effective radius r_i r_j / (r_i + r_j)%s\npair_style granular\n",
        e->kn, m_ref, r_ref,
        s->tangential ? "; F_t = -x_ij gamma_ij v_t with x_ij = gamma_t,ij / gamma_ij" : "");
    for (int i = 0; i < p.n; i++) {
        for (int j = i; j < p.n; j++) {
            const double mi = p.masses[i], mj = p.masses[j], ri = p.radii[i], rj = p.radii[j];
            gr_contact_coeffs c;
            gr_contact_size_scaled(ref, m_ref, r_ref, mi * mj / (mi + mj), ri * rj / (ri + rj), &c);
            fprintf(o, "pair_coeff %d %d hooke %.17g %.17g damping velocity tangential ", i + 1,
                    j + 1, c.k_s, c.gamma_n);
            if (s->tangential) { /* refuse_unmappable: gamma_n > 0 */
                fprintf(o, "linear_nohistory %.17g %.17g", c.gamma_t / c.gamma_n, LMP_XMU);
            } else {
                fprintf(o, "linear_nohistory 0.0 0.0");
            }
            fprintf(o, "%s\n", clamp ? " limit_damping" : "");
        }
    }
    return GR_OK;
}

static int write_deck(const char *dir, const gr_scene *s, const gr_sim *sim,
                      const gr_lammps_export *e, bool clamp, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "in.granule", err);
    if (rc) {
        return rc;
    }
    FILE *o = f.f;
    const gr_particles parts = gr_sim_particles(sim);
    const bool mixture = parts.species && s->n_species >= 2;
    const double d = 2.0 * parts.radius; /* a mixture: the largest diameter */
    /* LAMMPS seeds are positive 32-bit integers; the x and y streams get distinct ones */
    const long seed = (long)(s->seed % 900000000ULL) + 1;
    fprintf(o,
            "# LAMMPS deck written by granule %s (commit %s) from %s; mapping of every key: "
            "docs/lammps.md\n",
            GR_VERSION, GR_COMMIT, s->source);
    fprintf(o, "# run: mpirun -n RANKS lmp -in in.granule   (writes %s and log.lammps here)\n",
            e->dump);
    const bool three = s->dim == 3;
    fprintf(
        o, "units si\ndimension %d\nboundary %c %c %c\natom_style sphere\ncomm_modify vel yes\n",
        s->dim, s->boundary[0] ? 'f' : 'p', s->boundary[1] ? 'f' : 'p', s->boundary[2] ? 'f' : 'p');
    fprintf(o, "read_data data.granule\n");
    if (s->size_distribution) {
        rc = write_sizes(o, s, sim, e, clamp, err);
        if (rc) {
            gr_file_abandon(&f);
            return rc;
        }
    } else if (mixture) {
        write_species(o, s, sim, e, clamp);
    } else {
        fprintf(o, "set type 1 mass %.17g\n", s->mass);
        fprintf(o,
                "# contact: k_s = %.17g N/m, gamma_n = %.17g kg/s, gamma_t = %.17g kg/s, m12 = "
                "%.17g kg\n",
                e->kn, e->gamman * gr_scene_m12(s), e->gammat * gr_scene_m12(s), gr_scene_m12(s));
        fprintf(o, "pair_style gran/hooke %.17g 0.0 %.17g %.17g %.17g 1%s\npair_coeff * *\n", e->kn,
                e->gamman, e->gammat, LMP_XMU, clamp ? " limit_damping" : "");
    }
    fprintf(o, "neighbor %.17g bin\nneigh_modify delay 0 every 1 check yes\n", LMP_SKIN * d);
    if (e->noise_sigma > 0.0) {
        fprintf(o, "# random force (2.16, 2.23): sqrt(2 D / dt) per component, D = %.17g N^2 s\n",
                s->D);
        fprintf(o,
                "variable fx atom normal(0.0,%.17g,%ld)\nvariable fy atom normal(0.0,%.17g,%ld)\n",
                e->noise_sigma, seed, e->noise_sigma, seed + 1);
        if (three) {
            fprintf(o, "variable fz atom normal(0.0,%.17g,%ld)\n", e->noise_sigma, seed + 3);
        }
        fprintf(o, "fix noise all addforce v_fx v_fy %s\n", three ? "v_fz" : "0.0");
    }
    if (s->driving && s->driving->update == GR_DRIVE_BATH) {
        const double kB = 1.380649e-23; /* J/K, LAMMPS's boltz in units si */
        /* species: every grain at the first species' energy, k_B T = m_1 T_bath / dim (the drag
         * m_i / tau of fix langevin's damp = tau is granule's, docs/mixtures.md) */
        const double mb = s->n_species >= 2      ? s->species_masses[0]
                          : s->size_distribution ? parts.mass /* the grains' mean mass */
                                                 : s->mass;
        const double T_K = mb * s->driving_params.T_bath / (s->dim * kB);
        fprintf(
            o,
            "# Langevin bath: T_bath = %.17g m^2/s^2 (T of eq. 2.19), tau = %.17g s; k_B T = %s "
            "T_bath / dim\n",
            s->driving_params.T_bath, s->driving_params.tau,
            s->n_species >= 2 ? "m_1" : (s->size_distribution ? "<m>" : "M"));
        fprintf(o, "fix bath all langevin %.17g %.17g %.17g %ld\n", T_K, T_K, s->driving_params.tau,
                seed + 2);
    }
    write_walls(o, s, sim, e, clamp);
    const bool walls = s->boundary[0] || s->boundary[1] || s->boundary[2];
    fprintf(o, "fix integrate all nve\n%s", three ? "" : "fix plane all enforce2d\n");
    if (walls) {
        /* walls and gravity change the total momentum: no fix momentum (see the head comment) */
    } else if (s->noise_mode == GR_NOISE_SYMMETRISED) {
        fprintf(o, "fix com all momentum 1 linear 1 1 %d\n", three);
    } else if (s->noise_mode == GR_NOISE_COM) {
        long every = lround(s->com_interval / s->dt);
        fprintf(o, "fix com all momentum %ld linear 1 1 %d\n", every > 0 ? every : 1, three);
    }
    /* granular temperature (2.19): (1/N) sum |v - <v>|^2 */
    if (three) {
        fprintf(
            o, "variable vsq atom vx*vx+vy*vy+vz*vz\ncompute vsum all reduce sum v_vsq vx vy vz\n");
        fprintf(o, "variable T equal "
                   "c_vsum[1]/atoms-(c_vsum[2]/atoms)^2-(c_vsum[3]/atoms)^2-(c_vsum[4]/atoms)^2\n");
    } else {
        fprintf(o, "variable vsq atom vx*vx+vy*vy\ncompute vsum all reduce sum v_vsq vx vy\n");
        fprintf(o, "variable T equal c_vsum[1]/atoms-(c_vsum[2]/atoms)^2-(c_vsum[3]/atoms)^2\n");
    }
    fprintf(o, "timestep %.17g\nthermo %lld\nthermo_style custom step time v_T\n", s->dt,
            (long long)e->sample_steps);
    fprintf(o, "run %lld\n", (long long)e->warmup_steps);
    fprintf(o, "dump traj all custom %lld %s id%s x y%s vx vy%s\n", (long long)e->sample_steps,
            e->dump, mixture ? " type" : "", three ? " z" : "", three ? " vz" : "");
    fprintf(o, "dump_modify traj sort id format float %%.17g\n");
    fprintf(o, "run %lld\n", (long long)e->run_steps);
    return gr_file_commit(&f, err);
}

int gr_export_lammps(const gr_scene *scene, const char *dir, bool force, gr_lammps_export *info,
                     gr_error *err)
{
    memset(info, 0, sizeof *info);
    int rc = refuse_unmappable(scene, err);
    if (rc) {
        return rc;
    }
    gr_sim *sim = NULL;
    rc = gr_sim_create(scene, &sim, err);
    if (rc) {
        return rc;
    }
    gr_scene s = *scene;
    s.dt = gr_sim_dt(sim); /* resolved (steps_per_contact); scene.ini then gives the dump's times */
    const gr_contact_coeffs *c = gr_sim_coeffs(sim);
    const double m12 = gr_scene_m12(&s);
    info->kn = c->k_s;
    info->gamman = c->gamma_n / m12;
    const gr_contact_coeffs *cw = gr_sim_wall_coeffs(sim);
    info->gamman_wall = cw ? cw->gamma_n / s.mass : 0.0; /* LAMMPS: meff = M at a wall */
    info->gammat_wall = cw && s.tangential ? cw->gamma_t / s.mass : 0.0;
    info->gammat = s.tangential
                       ? c->gamma_t / m12
                       : 0.0; /* only a law of the same pair style exports (refuse_unmappable) */
    info->noise_sigma =
        s.noise_mode == GR_NOISE_NONE || !(s.D > 0.0) ? 0.0 : sqrt(2.0 * s.D / s.dt);
    info->sample_steps = llround(s.sample_every / s.dt) > 0 ? llround(s.sample_every / s.dt) : 1;
    info->warmup_steps = llround(s.warmup / s.sample_every) * info->sample_steps;
    info->run_steps = llround(s.duration / s.sample_every) * info->sample_steps;
    snprintf(info->dump, sizeof info->dump, "dump.granule.lammpstrj");
    snprintf(info->deck, sizeof info->deck, "%.1080s/in.granule", dir);
    snprintf(info->data, sizeof info->data, "%.1080s/data.granule", dir);
    gr_particles p = gr_sim_particles(sim);
    rc = gr_output_dir_prepare(dir, GR_OUTPUT_LAMMPS, force, err);
    if (!rc) {
        rc = write_data(dir, &s, &p, err);
    }
    if (!rc) {
        rc = write_deck(dir, &s, sim, info, c->clamp, err);
    }
    if (!rc) {
        rc = gr_scene_save(&s, dir, err);
    }
    gr_sim_free(sim);
    return rc;
}
