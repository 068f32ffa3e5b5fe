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
 *   rotation  fix nve integrates no angular velocity, as granule ignores rotation.
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

#define LMP_XMU 1.0e4 /* gran/hooke's largest friction coefficient: no Coulomb cap */
#define LMP_SKIN 0.3  /* neighbor skin, in diameters */

static int refuse_unmappable(const gr_scene *s, gr_error *err)
{
    if (s->dim == 3) {
        return GR_FAIL(
            err, GR_EINVAL,
            "export lammps: %s: a 3D deck is not written yet (docs/three-dimensions.md); "
            "allowed: a 2D scene",
            s->source);
    }
    if (s->dim != 2) {
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
    if (s->boundary[0] || s->boundary[1] || s->gravity[0] != 0.0 || s->gravity[1] != 0.0) {
        /* the deck writes a periodic box; fix wall/gran and fix gravity are not written yet */
        return GR_FAIL(err, GR_EINVAL,
                       "export lammps: %s: [boundary] walls and [gravity] are not exported yet "
                       "(fix wall/gran, fix gravity); allowed: boundary x, y = periodic, gravity "
                       "gx, gy = 0",
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
    const double d = 2.0 * s->radius;
    fprintf(f.f, "granule initial state of %s (seed %llu)\n\n%d atoms\n1 atom types\n\n", s->source,
            (unsigned long long)s->seed, p->n);
    fprintf(f.f, "0 %.17g xlo xhi\n0 %.17g ylo yhi\n%.17g %.17g zlo zhi\n\nAtoms # sphere\n\n",
            p->L, p->L, -d, d);
    /* id type diameter density x y z; the mass is set in the deck */
    for (int i = 0; i < p->n; i++) {
        fprintf(f.f, "%d 1 %.17g 1 %.17g %.17g 0\n", i + 1, d, p->x[i], p->y[i]);
    }
    fprintf(f.f, "\nVelocities\n\n");
    for (int i = 0; i < p->n; i++) {
        fprintf(f.f, "%d %.17g %.17g 0 0 0 0\n", i + 1, p->vx[i], p->vy[i]);
    }
    return gr_file_commit(&f, err);
}

static int write_deck(const char *dir, const gr_scene *s, const gr_lammps_export *e, bool clamp,
                      gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "in.granule", err);
    if (rc) {
        return rc;
    }
    FILE *o = f.f;
    const double d = 2.0 * s->radius;
    /* LAMMPS seeds are positive 32-bit integers; the x and y streams get distinct ones */
    const long seed = (long)(s->seed % 900000000ULL) + 1;
    fprintf(o,
            "# LAMMPS deck written by granule %s (commit %s) from %s; mapping of every key: "
            "docs/lammps.md\n",
            GR_VERSION, GR_COMMIT, s->source);
    fprintf(o, "# run: mpirun -n RANKS lmp -in in.granule   (writes %s and log.lammps here)\n",
            e->dump);
    fprintf(o, "units si\ndimension 2\nboundary p p p\natom_style sphere\ncomm_modify vel yes\n");
    fprintf(o, "read_data data.granule\nset type 1 mass %.17g\n", s->mass);
    fprintf(
        o,
        "# contact: k_s = %.17g N/m, gamma_n = %.17g kg/s, gamma_t = %.17g kg/s, m12 = %.17g kg\n",
        e->kn, e->gamman * gr_scene_m12(s), e->gammat * gr_scene_m12(s), gr_scene_m12(s));
    fprintf(o, "pair_style gran/hooke %.17g 0.0 %.17g %.17g %.17g 1%s\npair_coeff * *\n", e->kn,
            e->gamman, e->gammat, LMP_XMU, clamp ? " limit_damping" : "");
    fprintf(o, "neighbor %.17g bin\nneigh_modify delay 0 every 1 check yes\n", LMP_SKIN * d);
    if (e->noise_sigma > 0.0) {
        fprintf(o, "# random force (2.16, 2.23): sqrt(2 D / dt) per component, D = %.17g N^2 s\n",
                s->D);
        fprintf(o,
                "variable fx atom normal(0.0,%.17g,%ld)\nvariable fy atom normal(0.0,%.17g,%ld)\n",
                e->noise_sigma, seed, e->noise_sigma, seed + 1);
        fprintf(o, "fix noise all addforce v_fx v_fy 0.0\n");
    }
    if (s->driving && s->driving->update == GR_DRIVE_BATH) {
        const double kB = 1.380649e-23; /* J/K, LAMMPS's boltz in units si */
        const double T_K = s->mass * s->driving_params.T_bath / (s->dim * kB);
        fprintf(o,
                "# Langevin bath: T_bath = %.17g m^2/s^2 (T of eq. 2.19), tau = %.17g s; k_B T = M "
                "T_bath / dim\n",
                s->driving_params.T_bath, s->driving_params.tau);
        fprintf(o, "fix bath all langevin %.17g %.17g %.17g %ld\n", T_K, T_K, s->driving_params.tau,
                seed + 2);
    }
    fprintf(o, "fix integrate all nve\nfix plane all enforce2d\n");
    if (s->noise_mode == GR_NOISE_SYMMETRISED) {
        fprintf(o, "fix com all momentum 1 linear 1 1 0\n");
    } else if (s->noise_mode == GR_NOISE_COM) {
        long every = lround(s->com_interval / s->dt);
        fprintf(o, "fix com all momentum %ld linear 1 1 0\n", every > 0 ? every : 1);
    }
    /* granular temperature (2.19): (1/N) sum |v - <v>|^2 */
    fprintf(o, "variable vsq atom vx*vx+vy*vy\ncompute vsum all reduce sum v_vsq vx vy\n");
    fprintf(o, "variable T equal c_vsum[1]/atoms-(c_vsum[2]/atoms)^2-(c_vsum[3]/atoms)^2\n");
    fprintf(o, "timestep %.17g\nthermo %lld\nthermo_style custom step time v_T\n", s->dt,
            (long long)e->sample_steps);
    fprintf(o, "run %lld\n", (long long)e->warmup_steps);
    fprintf(o, "dump traj all custom %lld %s id x y vx vy\n", (long long)e->sample_steps, e->dump);
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
        rc = write_deck(dir, &s, info, c->clamp, err);
    }
    if (!rc) {
        rc = gr_scene_save(&s, dir, err);
    }
    gr_sim_free(sim);
    return rc;
}
