/* Creating a simulation: allocate the particle arrays, place the particles, give them small
 * random velocities, derive the contact coefficients and the time step, choose the kernel, let
 * the integrator build its state; stepping through the integrator's hooks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/sim_internal.h"
#include "granule/noise.h"

static _Atomic int threads_setting; /* gr_set_threads; 0: default */

void gr_set_threads(int n) { threads_setting = n > 0 ? n : 0; }

int gr_get_threads(void)
{
#ifdef _OPENMP
    if (omp_in_parallel()) {
        return 1;
    }
    int t = threads_setting;
    if (t == 0) { /* default: one thread, unless OMP_NUM_THREADS asks for more */
        const char *env = getenv("OMP_NUM_THREADS");
        t = env && *env ? omp_get_max_threads() : 1;
    }
    return t;
#else
    return 1;
#endif
}

int gr_team(const gr_sim *s)
{
#ifdef _OPENMP
    if (s->dim == 1 || s->nblk < 2) {
        return 1;
    }
    int t = gr_get_threads();
    return t < s->nblk ? t : s->nblk;
#else
    (void)s;
    return 1;
#endif
}

const char *gr_sim_one_thread_reason(const gr_sim *s)
{
    if (s->dim == 1) {
        return "a 1D run steps on one thread";
    }
    if (s->integrator && !s->integrator->threads) {
        return "the event-driven integrator steps on one thread (docs/event-driven.md)";
    }
    if (s->nblk < 2) {
        return "a run of at most 1024 grains is one block of rows and steps on one thread";
    }
    return NULL;
}

int gr_sim_threads(const gr_sim *s) { return gr_sim_one_thread_reason(s) ? 1 : gr_team(s); }

static double *alloc_array(int n)
{
    size_t bytes = ((sizeof(double) * (size_t)(n > 0 ? n : 1)) + 63) & ~(size_t)63;
    double *p = aligned_alloc(64, bytes);
    if (p) {
        memset(p, 0, bytes);
    }
    return p;
}

void gr_sim_free(gr_sim *s)
{
    if (!s) {
        return;
    }
    if (s->integrator && s->integrator->free) {
        s->integrator->free(s);
    }
    free(s->x);
    free(s->y);
    free(s->vx);
    free(s->vy);
    free(s->fx);
    free(s->fy);
    free(s->gx);
    free(s->gy);
    free(s->z);
    free(s->vz);
    free(s->fz);
    free(s->gz);
    free(s->z_ref);
    free(s->noise);
    free(s->x_ref);
    free(s->y_ref);
    free(s->cell_start);
    free(s->cell_of);
    free(s->cell_order);
    free(s->nl_start);
    free(s->nl_j);
    free(s->nl_contact);
    gr_sublist_free(s);
    free(s->nl_hist);
    free(s->hist_start);
    free(s->hist_j);
    free(s->hist_v);
    free(s->pair_contact);
    free(s->ring_scratch);
    free(s->contacts);
    free(s->contacts_now);
    free(s->events);
    free(s->blk);
    gr_poly_par_free(s);
    free(s->par_row);
    free(s->cross_start);
    free(s->cross_p);
    free(s->cross_i);
    free(s->in_start);
    free(s->in_k);
    free(s->in_list);
    free(s->in_list_start);
    free(s->pair_f);
    free(s->pair_tq);
    free(s->pair_tg);
    free(s->omega);
    free(s->tq);
    free(s->tg);
    free(s->wx);
    free(s->wy);
    free(s->tqx);
    free(s->tqy);
    free(s->tgx);
    free(s->tgy);
    free(s->wall_hist);
    free(s->wall_cc_sp);
    free(s->inertia_i);
    free(s->species);
    free(s->rad);
    free(s->mass_i);
    free(s->inv_m);
    free(s->cc_pair);
    free(s);
}

/* Coefficients and time step. dt comes from the scene or from steps_per_contact; a dt too coarse
 * for the contact (fewer than 10 steps, sec. 2.1.2) or for an overdamped dashpot is refused. */
static int prepare_contact(gr_sim *s, gr_error *err)
{
    const gr_sim_params *sc = &s->params;
    double m12 = 0.5 * sc->mass; /* reduced mass of two identical particles */
    /* species: the coefficients of the pair with the shortest contact set the time step */
    gr_contact_params species_ref;
    const gr_contact_params *cp = &sc->contact;
    if (s->nsp) {
        gr_species_reference(s, &species_ref, &m12);
        cp = &species_ref;
    }
    int rc = gr_contact_prepare(sc->normal, sc->tangential, cp, m12, 0.0, &s->cc, err);
    if (!rc) {
        rc = gr_contact_prepare_rolling(sc->rolling, &sc->contact, m12, 0.0, &s->cc, err);
    }
    if (rc) {
        return rc;
    }
    /* a sticking contact (unclamped eps_n = 0) never ends: measure steps against pi / w0 */
    double t_c = isfinite(s->cc.t_c) ? s->cc.t_c : M_PI / s->cc.w0;
    if (!isfinite(s->cc.w0) || !(t_c > 0.0)) { /* e.g. k_s = 1e308: k_s / m12 overflows */
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [model] k_s = %g N/m (normal = %s) over the reduced mass m12 = %g kg "
                       "gives the contact "
                       "frequency w0 = sqrt(k_s / m12) = %g rad/s and contact time t_c = %g s: no "
                       "time step can resolve "
                       "it; allowed: k_s / m12 finite (w0 and t_c finite and > 0), e.g. k_s <= %g "
                       "N/m at this mass",
                       sc->source, sc->contact.k_s, sc->normal->name, m12, s->cc.w0, t_c,
                       1e300 * m12);
    }
    double dt = sc->dt > 0.0 ? sc->dt : t_c / sc->steps_per_contact;
    if (sc->dt == 0.0 && 2.0 * s->cc.zeta * s->cc.w0 * dt > 1.0) {
        dt = 1.0 / (2.0 * s->cc.zeta * s->cc.w0); /* overdamped: the dashpot sets the step */
    }
    /* The dashpot sees the half-step velocity, which acts like a damping ratio
     * zeta (1 + zeta w0 dt / 2). An unclamped contact just below critical damping would then be
     * overdamped and the pair would stick numerically; keep half the margin to zeta = 1. */
    double dt_lag = s->cc.clamp || s->cc.zeta >= 1.0 || s->cc.zeta == 0.0
                        ? (double)INFINITY
                        : (1.0 / s->cc.zeta - 1.0) * 2.0 / (s->cc.zeta * s->cc.w0);
    if (sc->dt == 0.0 && dt > 0.5 * dt_lag) {
        dt = 0.5 * dt_lag;
    }
    double steps = t_c / dt;
    if (steps < 10.0 && !sc->force_dt) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [integrator] dt = %g s resolves a contact (t_c = %.4g s) with only %.1f steps; "
            "at least 10 are needed (sec. 2.1.2): use dt <= %.4g s, steps_per_contact >= 10, or "
            "force_dt = true",
            sc->source, dt, t_c, steps, t_c / 10.0);
    }
    if (2.0 * s->cc.zeta * s->cc.w0 * dt > 1.0 && !sc->force_dt) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [integrator] dt = %g s is too large for the overdamped dashpot (zeta = %.3g): "
            "explicit damping needs 2 zeta w0 dt < 1, i.e. dt < %.4g s",
            sc->source, dt, s->cc.zeta, 1.0 / (2.0 * s->cc.zeta * s->cc.w0));
    }
    if (dt >= dt_lag && !sc->force_dt) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [integrator] dt = %g s is too large for eps_n = %g unclamped (zeta = "
                       "%.4f): with the half-step "
                       "dashpot the contact becomes overdamped (zeta_eff = %.4f) and pairs stick "
                       "numerically; use dt < %.4g s, "
                       "leave dt unset (steps_per_contact), or force_dt = true",
                       sc->source, dt, sc->contact.eps_n, s->cc.zeta,
                       s->cc.zeta * (1.0 + 0.5 * s->cc.zeta * s->cc.w0 * dt), dt_lag);
    }
    s->dt = dt;
    int rc2 = gr_contact_prepare(sc->normal, sc->tangential, cp, m12, dt, &s->cc, err);
    if (!rc2 && s->nsp) {
        rc2 = gr_species_coeffs(s, dt, err);
    }
    return rc2 ? rc2 : gr_contact_prepare_rolling(sc->rolling, &sc->contact, m12, dt, &s->cc, err);
}

/* The dimension, and what a simulation of spheres (dim = 3) runs so far (docs/three-dimensions.md):
 * the soft contact laws (normal, tangential, rolling; rotation) and the random force (or no
 * driving) in a periodic cube, with an integrator that steps spheres. The scene refuses the same with the file and line; this guards the
 * library's other callers (Python, C programs). */
static int check_dim(const gr_sim_params *p, gr_error *err)
{
    if (p->dim < 1 || p->dim > 3) {
        return GR_FAIL(err, GR_EINVAL, "%s: [system] dim = %d; allowed: 1, 2 or 3", p->source,
                       p->dim);
    }
    if (p->dim != 3) {
        return GR_OK;
    }
    if (!p->integrator->spheres) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [integrator] kind = %s: not available with dim = 3 yet; 3D runs the "
                       "soft contact laws (verlet and hybrid integrators) and smooth or rough "
                       "hard spheres (event integrator) (docs/three-dimensions.md)",
                       p->source, p->integrator->name);
    }
    return GR_OK;
}

static int alloc_state(const gr_sim_params *p, int n, gr_sim **out, gr_error *err)
{
    if (!p->integrator || !p->integrator->step) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: no integrator given (gr_sim_params.integrator: one of the registry, "
                       "include/granule/integrator.h)",
                       p->source);
    }
    int rc_dim = check_dim(p, err);
    if (rc_dim) {
        return rc_dim;
    }
    /* the driving, once per run (granule/driving.h): none runs the noise-free loop, as D = 0 does;
     * langevin replaces the random force by the bath, which the integrator must model */
    const gr_driving_type *drive = p->driving ? p->driving : gr_driving_default();
    if (drive->drag && !p->integrator->drag) {
        /* the core knows no integrator by name (docs/architecture.md): the scene names the allowed ones */
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [driving] kind = %s has a viscous drag, which [integrator] kind = %s does not "
            "model (gr_integrator_type.drag; docs/systems-driving.md lists the integrators that "
            "do)",
            p->source, drive->name, p->integrator->name);
    }
    gr_sim *s = calloc(1, sizeof *s);
    if (!s) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    s->params = *p;
    s->params.driving = drive;
    s->drive = drive->update;
    if (drive->update != GR_DRIVE_FORCE) { /* the random force is off; the bath has its own noise */
        s->params.D = 0.0;
        s->params.noise_mode = GR_NOISE_NONE;
    }
    s->integrator = p->integrator;
    s->n = n;
    s->dim = p->dim;
    s->L = p->L;
    s->period[0] = s->period[1] = s->period[2] =
        p->L; /* periodic; walls.c makes a wall axis INFINITY */
    s->d = 2.0 * p->radius;
    s->mass = p->mass;
    s->x = alloc_array(n);
    s->vx = alloc_array(n);
    s->fx = alloc_array(n);
    s->gx = alloc_array(n);
    s->noise = alloc_array(n * s->dim);
    s->nblk = n > 0 ? (n + GR_BLOCK - 1) / GR_BLOCK : 1;
    s->blk = calloc((size_t)s->nblk * GR_BLK_FIELDS, sizeof(double));
    if (s->dim >= 2) {
        s->y = alloc_array(n);
        s->vy = alloc_array(n);
        s->fy = alloc_array(n);
        s->gy = alloc_array(n);
    } else {
        s->pair_contact = calloc((size_t)n + 1, 1);
        s->ring_scratch = alloc_array(3 * n);
    }
    if (s->dim == 3) { /* spheres (docs/three-dimensions.md) */
        s->z = alloc_array(n);
        s->vz = alloc_array(n);
        s->fz = alloc_array(n);
        s->gz = alloc_array(n);
    }
    if (!s->x || !s->vx || !s->fx || !s->gx || !s->noise || !s->blk ||
        (s->dim >= 2 ? (!s->y || !s->vy || !s->fy || !s->gy)
                     : !s->pair_contact || !s->ring_scratch) ||
        (s->dim == 3 && (!s->z || !s->vz || !s->fz || !s->gz))) {
        gr_sim_free(s);
        return GR_FAIL(err, GR_ENOMEM, "out of memory for %d particles", n);
    }
    int rc_sp = gr_species_setup(s, err); /* species (species.c): nothing without */
    if (rc_sp) {
        gr_sim_free(s);
        return rc_sp;
    }
    *out = s;
    return GR_OK;
}

/* Rotation ([model] rotation = true): angular velocities (zero) and torques, 2D or 3D (vectors:
 * omega, tq are the z components, wx, wy, tqx, tqy the others) and an integrator that kicks
 * them only. I = q M r^2. */
static int alloc_rotation(gr_sim *s, gr_error *err)
{
    if (s->dim == 1 || !s->integrator->rotation) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [model] rotation = true needs dim = 2 or 3 and an integrator that rotates the "
            "particles (verlet, event); given dim = %d, kind = %s",
            s->params.source, s->dim, s->integrator->name);
    }
    s->omega = calloc((size_t)s->n + 1, sizeof(double));
    s->tq = calloc((size_t)s->n + 1, sizeof(double));
    if (s->dim == 3) {
        s->wx = calloc((size_t)s->n + 1, sizeof(double));
        s->wy = calloc((size_t)s->n + 1, sizeof(double));
        s->tqx = calloc((size_t)s->n + 1, sizeof(double));
        s->tqy = calloc((size_t)s->n + 1, sizeof(double));
    }
    if (!s->omega || !s->tq || (s->dim == 3 && (!s->wx || !s->wy || !s->tqx || !s->tqy))) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for %d angular velocities", s->n);
    }
    s->inertia = s->cc.q * s->mass * 0.25 * s->d * s->d;
    if (s->rad) { /* species: each grain's own moment of inertia */
        s->inertia_i = calloc((size_t)s->n + 1, sizeof(double));
        if (!s->inertia_i) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory for %d moments of inertia", s->n);
        }
        for (int i = 0; i < s->n; i++) {
            s->inertia_i[i] = s->cc.q * s->mass_i[i] * s->rad[i] * s->rad[i];
        }
    }
    return GR_OK;
}

/* [placement] omega0: initial angular velocities omega0 * U(-0.5, 0.5) from the seed (the
 * velocities' stream, component 2, which 1D and 2D velocities never draw), before the first
 * forces and the ledger's initial energy. 3D: each component of the vector so, w_z from
 * component 2 as in 2D (a sphere in the plane z = 0 spins as the disc), w_x and w_y from
 * components 4 and 5 (the velocities take 0, 1 and 3). */
static int spin_up(gr_sim *s, gr_error *err)
{
    if (s->params.omega0 > 0.0 && !s->omega) {
        return GR_FAIL(
            err, GR_EINVAL,
            "%s: [placement] omega0 = %g needs [model] rotation = true (allowed without it: 0)",
            s->params.source, s->params.omega0);
    }
    for (int i = 0; s->omega && s->params.omega0 > 0.0 && i < s->n; i++) {
        s->omega[i] =
            s->params.omega0 *
            (gr_noise_uniform(s->params.seed, GR_STREAM_INIT_VELOCITY, (uint64_t)i, 2) - 0.5);
        if (s->dim == 3) {
            s->wx[i] =
                s->params.omega0 *
                (gr_noise_uniform(s->params.seed, GR_STREAM_INIT_VELOCITY, (uint64_t)i, 4) - 0.5);
            s->wy[i] =
                s->params.omega0 *
                (gr_noise_uniform(s->params.seed, GR_STREAM_INIT_VELOCITY, (uint64_t)i, 5) - 0.5);
        }
    }
    return GR_OK;
}

/* Everything after the positions and velocities are set. */
static int finish(gr_sim *s, gr_error *err)
{
    int rc = prepare_contact(s, err);
    if (!rc && s->params.driving->prepare) {
        rc = s->params.driving->prepare(&s->params.driving_params, s->dim, s->dt, &s->drive_c, err);
    }
    if (!rc && s->cc.rotation) {
        rc = alloc_rotation(s, err);
    }
    if (!rc) {
        rc = spin_up(s, err);
    }
    if (!rc) {
        rc = gr_check_overlaps(s, err);
    }
    if (!rc) {
        rc = gr_walls_prepare(s, err); /* walls and gravity (walls.c); off: nothing */
    }
    if (!rc && s->dim >= 2) {
        rc = gr_neighbours_alloc(s, err);
        if (!rc) {
            rc = gr_neighbours_build(s, err);
        }
    }
    if (rc) {
        return rc;
    }
    if (s->dim == 1) {
        for (int i = 0; i < s->n && s->n > 1; i++) {
            double gap = i + 1 < s->n ? s->x[i + 1] - s->x[i] : s->x[0] + s->L - s->x[i];
            s->pair_contact[i] = gap < gr_pair_d(s, i, (i + 1) % s->n);
        }
    }
    if ((rc = gr_kernel_choose(s, err))) {
        return rc;
    }
    if (gr_kernel_history(s)) { /* a tangential law with per-contact history (models/list.h) */
        if (!s->integrator->contact_history) {
            return GR_FAIL(
                err, GR_EINVAL,
                "%s: [model] tangential = %s keeps a contact history, which only the verlet "
                "integrator carries; given [integrator] kind = %s (allowed: verlet)",
                s->params.source, s->cc.tangential_model->name, s->integrator->name);
        }
        int rc_h = gr_history_enable(s, err);
        if (rc_h) {
            return rc_h;
        }
        /* rotation: the springs' torques are conservative; the kernel keeps the rest apart */
        if (s->omega && !s->tg && !(s->tg = calloc((size_t)s->n + 1, sizeof(double)))) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory for %d torques", s->n);
        }
        if (s->wx && ((!s->tgx && !(s->tgx = calloc((size_t)s->n + 1, sizeof(double)))) ||
                      (!s->tgy && !(s->tgy = calloc((size_t)s->n + 1, sizeof(double)))))) {
            return GR_FAIL(err, GR_ENOMEM, "out of memory for %d torques", s->n);
        }
    }
    s->com_every = (int64_t)llround(s->params.com_interval / s->dt);
    if (s->com_every < 1) {
        s->com_every = 1;
    }
    gr_force_report r;
    gr_forces(s, &r);
    s->elastic = r.elastic;
    s->last = r;
    double total = r.power_normal + r.power_tangential + r.power_friction;
    s->share[0] = total > 0.0 ? r.power_normal / total : 1.0;
    s->share[1] = total > 0.0 ? r.power_tangential / total : 0.0;
    s->share[2] = total > 0.0 ? r.power_friction / total : 0.0;
    gr_ledger l = gr_sim_ledger(s);
    s->initial_energy = l.kinetic + l.elastic + l.potential; /* potential: 0 without gravity */
    return s->integrator->create ? s->integrator->create(s, err) : GR_OK;
}

int gr_sim_new(const gr_sim_params *p, gr_sim **out, gr_error *err)
{
    *out = NULL;
    gr_sim *s;
    int rc = alloc_state(p, p->N, &s, err);
    if (rc) {
        return rc;
    }
    rc = gr_place(s, err);
    if (!rc) {
        /* v0 * U(-0.5, 0.5) per component (sec. 2.2.2); the mean is removed so the total momentum
         * starts at zero and the symmetrised noise keeps it there. The uniforms' second counter
         * word is 0 for vx, 1 for vy and 3 for vz: 2 belongs to the spins (spin_up) */
        double mean[3] = {0.0, 0.0, 0.0};
        double *v[3] = {s->vx, s->vy, s->vz};
        static const uint64_t word[3] = {0, 1, 3};
        for (int c = 0; c < s->dim; c++) {
            double mtot = 0.0;
            for (int i = 0; i < s->n; i++) {
                v[c][i] = p->v0 * (gr_noise_uniform(p->seed, GR_STREAM_INIT_VELOCITY, (uint64_t)i,
                                                    word[c]) -
                                   0.5);
                if (s->mass_i) { /* species: the centre-of-mass velocity is removed */
                    mean[c] += s->mass_i[i] * v[c][i];
                    mtot += s->mass_i[i];
                } else {
                    mean[c] += v[c][i];
                }
            }
            mean[c] /= s->mass_i ? mtot : s->n;
            for (int i = 0; i < s->n && s->n > 1; i++) {
                v[c][i] -= mean[c];
            }
        }
        rc = finish(s, err);
    }
    if (rc) {
        gr_sim_free(s);
        return rc;
    }
    *out = s;
    return GR_OK;
}

int gr_sim_new_with_state(const gr_sim_params *p, int n, const double *x, const double *y,
                          const double *vx, const double *vy, gr_sim **out, gr_error *err)
{
    *out = NULL;
    gr_sim *s;
    if (p->dim == 3) { /* no z arrays in this interface yet (docs/three-dimensions.md) */
        return GR_FAIL(err, GR_EINVAL,
                       "%s: a state given as x, y arrays is 1D or 2D; dim = 3 starts from a "
                       "placement only (allowed here: dim = 1 or 2)",
                       p->source);
    }
    if (p->n_species >= 2) { /* the species are dealt by the seed, not given with the state */
        return GR_FAIL(err, GR_EINVAL,
                       "%s: a state given as arrays carries no species yet; a mixture ([species], "
                       "docs/mixtures.md) starts from a placement (allowed here: n_species = 0)",
                       p->source);
    }
    int rc = alloc_state(p, n, &s, err);
    if (rc) {
        return rc;
    }
    s->params.N = n;
    for (int i = 0; i < n; i++) {
        if (!isfinite(x[i]) || !isfinite(vx[i]) ||
            (s->dim == 2 && (!isfinite(y[i]) || !isfinite(vy[i])))) {
            gr_sim_free(s);
            return GR_FAIL(err, GR_EINVAL,
                           "initial state: particle %d has a non-finite position or velocity", i);
        }
        s->x[i] = x[i];
        s->vx[i] = vx[i];
        if (s->dim == 2) {
            s->x[i] = x[i] - s->L * floor(x[i] / s->L);
            s->y[i] = y[i] - s->L * floor(y[i] / s->L);
            s->vy[i] = vy[i];
        }
    }
    rc = finish(s, err);
    if (rc) {
        gr_sim_free(s);
        return rc;
    }
    *out = s;
    return GR_OK;
}

int gr_sim_new_with_state_3d(const gr_sim_params *p, int n, const double *const r[3],
                             const double *const v[3], gr_sim **out, gr_error *err)
{
    *out = NULL;
    if (p->dim != 3) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: a state given as x, y, z arrays is 3D (given dim = %d; allowed here: "
                       "dim = 3)",
                       p->source, p->dim);
    }
    gr_sim *s;
    int rc = alloc_state(p, n, &s, err);
    if (rc) {
        return rc;
    }
    s->params.N = n;
    double *sr[3] = {s->x, s->y, s->z}, *sv[3] = {s->vx, s->vy, s->vz};
    for (int i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            if (!isfinite(r[a][i]) || !isfinite(v[a][i])) {
                gr_sim_free(s);
                return GR_FAIL(err, GR_EINVAL,
                               "initial state: particle %d has a non-finite position or velocity",
                               i);
            }
            sr[a][i] = r[a][i] - s->L * floor(r[a][i] / s->L);
            sv[a][i] = v[a][i];
        }
    }
    rc = finish(s, err);
    if (rc) {
        gr_sim_free(s);
        return rc;
    }
    *out = s;
    return GR_OK;
}

/* Canonical order (gr_sim_new_canonical): 1D by x; 2D by cell of a grid of side >= d in
 * row-major order, then x, then y, on the wrapped positions. Distinct positions (every accepted
 * state has them) get a unique order, and neighbours in space are near in the order. */
typedef struct canon_key {
    int64_t cell;
    double x, y;
    int i;
} canon_key;

static int canon_cmp(const void *pa, const void *pb)
{
    const canon_key *a = pa, *b = pb;
    if (a->cell != b->cell) {
        return a->cell < b->cell ? -1 : 1;
    }
    if (a->x != b->x) {
        return a->x < b->x ? -1 : 1;
    }
    if (a->y != b->y) {
        return a->y < b->y ? -1 : 1;
    }
    return 0;
}

int gr_sim_new_canonical(const gr_sim_params *p, int n, const double *x, const double *y,
                         const double *vx, const double *vy, gr_sim **out, gr_error *err)
{
    *out = NULL;
    const int dim = p->dim;
    const double L = p->L, d = 2.0 * p->radius;
    if (n < 1) {
        return gr_sim_new_with_state(p, n, x, y, vx, vy, out, err);
    }
    canon_key *key = malloc(sizeof *key * (size_t)n);
    double *buf = malloc(sizeof(double) * 4 * (size_t)n);
    if (!key || !buf) {
        free(key);
        free(buf);
        return GR_FAIL(err, GR_ENOMEM, "out of memory for %d particles", n);
    }
    int64_t side = dim == 2 && d > 0.0 && L > d ? (int64_t)floor(L / d) : 1;
    const int64_t max_side = (int64_t)ceil(sqrt((double)n)) + 1; /* about one particle per cell */
    side = side < 1 ? 1 : (side > max_side ? max_side : side);
    for (int i = 0; i < n; i++) {
        key[i].i = i;
        key[i].x = x[i];
        key[i].y = 0.0;
        key[i].cell = 0;
        if (dim == 2 && isfinite(x[i]) && isfinite(y[i])) {
            const double xw = x[i] - L * floor(x[i] / L), yw = y[i] - L * floor(y[i] / L);
            int64_t cx = (int64_t)(xw / L * (double)side), cy = (int64_t)(yw / L * (double)side);
            cx = cx >= side ? side - 1 : (cx < 0 ? 0 : cx);
            cy = cy >= side ? side - 1 : (cy < 0 ? 0 : cy);
            key[i] = (canon_key){.cell = cx + side * cy, .x = xw, .y = yw, .i = i};
        }
    }
    qsort(key, (size_t)n, sizeof *key, canon_cmp);
    double *px = buf, *py = buf + n, *pvx = buf + 2 * (size_t)n, *pvy = buf + 3 * (size_t)n;
    for (int k = 0; k < n; k++) {
        const int i = key[k].i;
        px[k] = x[i];
        pvx[k] = vx[i];
        py[k] = dim == 2 ? y[i] : 0.0;
        pvy[k] = dim == 2 ? vy[i] : 0.0;
    }
    free(key);
    int rc = gr_sim_new_with_state(p, n, px, py, pvx, pvy, out, err);
    free(buf);
    return rc;
}

gr_particles gr_sim_particles(const gr_sim *s)
{
    return (gr_particles){.n = s->n,
                          .dim = s->dim,
                          .L = s->L,
                          .radius = 0.5 * s->d,
                          .mass = s->mass,
                          .x = s->x,
                          .y = s->y,
                          .vx = s->vx,
                          .vy = s->vy,
                          .z = s->z,
                          .vz = s->vz,
                          /* 3D: the spins are vectors (wx, wy, omega), not one column */
                          .omega = s->dim == 3 ? NULL : s->omega,
                          .wx = s->dim == 3 ? s->wx : NULL,
                          .wy = s->dim == 3 ? s->wy : NULL,
                          .wz = s->dim == 3 && s->wx ? s->omega : NULL,
                          .species = s->species,
                          .radii = s->rad,
                          .masses = s->mass_i,
                          .n_species = s->nsp};
}

void gr_sim_forces(const gr_sim *s, const double **fx, const double **fy)
{
    *fx = s->fx;
    *fy = s->dim >= 2 ? s->fy : NULL;
}

void gr_sim_spins(const gr_sim *s, const double **wx, const double **wy, const double **wz)
{
    *wx = s->wx;
    *wy = s->wy;
    *wz = s->omega;
}

double gr_sim_time(const gr_sim *s) { return (double)s->step * s->dt; }
int64_t gr_sim_steps(const gr_sim *s) { return s->step; }
double gr_sim_dt(const gr_sim *s) { return s->dt; }
const gr_contact_coeffs *gr_sim_coeffs(const gr_sim *s) { return &s->cc; }

const gr_contact_coeffs *gr_sim_species_coeffs(const gr_sim *s, int a, int b)
{
    const bool in = s->cc_pair && a >= 0 && b >= 0 && a < s->nsp && b < s->nsp;
    return in ? &s->cc_pair[a * s->nsp + b] : NULL;
}

const gr_contact_coeffs *gr_sim_wall_coeffs(const gr_sim *s)
{
    const bool walls = s->params.walls[0] || s->params.walls[1] || s->params.walls[2];
    return walls && !s->integrator->instantaneous ? &s->wall_cc : NULL;
}
const gr_contact_coeffs *gr_sim_species_wall_coeffs(const gr_sim *s, int a)
{
    const bool in = gr_sim_wall_coeffs(s) && s->wall_cc_sp && a >= 0 && a < s->nsp;
    return in ? &s->wall_cc_sp[a] : NULL;
}
const char *gr_sim_kernel(const gr_sim *s) { return s->kernel_name; }
int64_t gr_sim_collisions(const gr_sim *s) { return s->collisions; }
int64_t gr_sim_rebuilds(const gr_sim *s) { return s->rebuilds; }
int64_t gr_sim_sublist_rebuilds(const gr_sim *s) { return s->sl_rebuilds; }
const gr_integrator_type *gr_sim_integrator(const gr_sim *s) { return s->integrator; }

int gr_sim_step(gr_sim *s, int64_t nsteps, gr_error *err)
{
    return s->integrator->step(s, nsteps, err);
}

void gr_sim_set_stop(gr_sim *s, volatile sig_atomic_t *stop)
{
    if (s->integrator->set_stop) {
        s->integrator->set_stop(s, stop);
    }
}

int64_t gr_sim_events_processed(const gr_sim *s)
{
    return s->integrator->events ? s->integrator->events(s) : 0;
}

const char *gr_noise_mode_name(gr_noise_mode m)
{
    static const char *names[] = {"none", "symmetrised", "com"};
    return names[m];
}

/* Species: the velocity of the centre of mass V = sum_i m_i v_i / sum_i m_i, so that afterwards
 * sum_i m_i v_i = 0; the kinetic energy removed is sum_i m_i |V|^2 / 2. */
static double remove_com_masses(gr_sim *s)
{
    double removed = 0.0, mtot = 0.0;
    double *v[3] = {s->vx, s->vy, s->vz};
    for (int i = 0; i < s->n; i++) {
        mtot += s->mass_i[i];
    }
    for (int c = 0; c < s->dim; c++) {
        double p = 0.0;
        for (int i = 0; i < s->n; i++) {
            p += s->mass_i[i] * v[c][i];
        }
        const double V = p / mtot;
        for (int i = 0; i < s->n; i++) {
            v[c][i] -= V;
        }
        removed += 0.5 * mtot * V * V;
    }
    return removed;
}

/* Remove the centre-of-mass velocity; returns the kinetic energy removed. */
double gr_remove_com(gr_sim *s)
{
    if (s->mass_i && s->n > 0) { /* species (1D, 2D and 3D) */
        return remove_com_masses(s);
    }
    double removed = 0.0;
    double *v[3] = {s->vx, s->vy, s->vz};
    for (int c = 0; c < s->dim; c++) {
        double mean = 0.0;
        for (int i = 0; i < s->n; i++) {
            mean += v[c][i];
        }
        mean /= s->n;
        for (int i = 0; i < s->n; i++) {
            v[c][i] -= mean;
        }
        removed += 0.5 * s->mass * s->n * mean * mean;
    }
    return removed;
}

double gr_ledger_dissipated(const gr_ledger *l)
{
    return l->dissipated_normal + l->dissipated_tangential + l->dissipated_friction +
           l->dissipated_drag;
}

double gr_ledger_residual(const gr_ledger *l)
{
    return (l->kinetic + l->elastic + l->potential) - l->initial - l->injected - l->wall_work +
           gr_ledger_dissipated(l) + l->removed_com;
}

gr_ledger gr_sim_ledger(gr_sim *s)
{
    double ke = 0.0;
    for (int i = 0; i < s->n && !s->mass_i; i++) {
        ke += s->vx[i] * s->vx[i];
        if (s->dim == 2) {
            ke += s->vy[i] * s->vy[i];
        } else if (s->dim == 3) {
            ke += s->vy[i] * s->vy[i] + s->vz[i] * s->vz[i];
        }
    }
    for (int i = 0; i < s->n && s->mass_i; i++) { /* species: each grain its own mass */
        double v2 = s->vx[i] * s->vx[i] + (s->dim >= 2 ? s->vy[i] * s->vy[i] : 0.0);
        if (s->dim == 3) {
            v2 += s->vz[i] * s->vz[i];
        }
        ke += s->mass_i[i] / s->mass * v2;
    }
    double rot = 0.0; /* sum I w^2 / 2, part of the kinetic energy */
    for (int i = 0; s->omega && i < s->n; i++) {
        /* species: each grain's own I_i (1.0 without: exact) */
        const double w = s->inertia_i ? s->inertia_i[i] / s->inertia : 1.0;
        rot += w * s->omega[i] * s->omega[i];
        if (s->wx) { /* 3D: |w|^2 */
            rot += w * (s->wx[i] * s->wx[i] + s->wy[i] * s->wy[i]);
        }
    }
    rot *= 0.5 * s->inertia;
    return (gr_ledger){.kinetic = s->omega ? 0.5 * s->mass * ke + rot : 0.5 * s->mass * ke,
                       .rotational = rot,
                       .elastic = s->elastic,
                       .initial = s->initial_energy,
                       .injected = s->injected,
                       .dissipated_normal = s->diss_n,
                       .dissipated_tangential = s->diss_t,
                       .dissipated_friction = s->diss_f,
                       .removed_com = s->removed_com,
                       .dissipated_drag = s->diss_drag,
                       .potential = s->walls_on ? gr_walls_potential(s) : 0.0,
                       .wall_work = s->wall_work};
}

double gr_sim_temperature(const gr_sim *s)
{
    double sum = 0.0, mx = 0.0, my = 0.0, mz = 0.0;
    for (int i = 0; i < s->n; i++) {
        mx += s->vx[i];
        if (s->dim >= 2) {
            my += s->vy[i];
        }
        if (s->dim == 3) {
            mz += s->vz[i];
        }
    }
    mx /= s->n;
    my /= s->n;
    mz /= s->n;
    for (int i = 0; i < s->n; i++) {
        double ux = s->vx[i] - mx;
        sum += ux * ux;
        if (s->dim >= 2) {
            double uy = s->vy[i] - my;
            sum += uy * uy;
        }
        if (s->dim == 3) {
            double uz = s->vz[i] - mz;
            sum += uz * uz;
        }
    }
    return sum / s->n; /* eq. 2.19: all dim components (docs/three-dimensions.md) */
}

double gr_sim_rotational_temperature(const gr_sim *s)
{
    if (!s->omega) {
        return (double)NAN;
    }
    double sum = 0.0;
    for (int i = 0; i < s->n; i++) {
        /* species: each grain's own I_i (1.0 without: exact) */
        const double w = s->inertia_i ? s->inertia_i[i] / s->inertia : 1.0;
        sum += w * s->omega[i] * s->omega[i];
        if (s->wx) { /* 3D: |w|^2 over the three rotational degrees of freedom, as T sums v */
            sum += w * (s->wx[i] * s->wx[i] + s->wy[i] * s->wy[i]);
        }
    }
    return s->inertia * sum /
           (s->mass * s->n); /* I <w^2> / M: the one rotational degree of freedom (2D) */
}

double gr_sim_max_overlap(gr_sim *s) { return s->last.max_overlap; }

void gr_sim_momentum(const gr_sim *s, double p[2])
{
    p[0] = p[1] = 0.0;
    for (int i = 0; i < s->n; i++) {
        const double w = s->mass_i ? s->mass_i[i] / s->mass : 1.0; /* species: its own mass */
        p[0] += w * s->vx[i];
        if (s->dim == 2) {
            p[1] += w * s->vy[i];
        }
    }
    p[0] *= s->mass;
    p[1] *= s->mass;
}
