/* The verlet step of a simulation with species (docs/mixtures.md): the scheme of step.c (kick,
 * random-force kick, drift, forces with the half-step velocity, kick), each grain with its own
 * mass m_i. Its own instance, chosen once per call, so step.c's loops are the ones they always
 * were.
 *
 * The random force is white noise of the same strength D on every grain, so grain i's kick is
 * sqrt(2 D dt) / m_i times a standard normal per component, and it injects d D / m_i per second
 * on average (the ledger books the exact kinetic energy of each kick). Symmetrised mode (2.18)
 * subtracts the mean of the forces, not of the kicks, so the kicks carry no net momentum:
 * sum_i m_i dv_i = sqrt(2 D dt) sum_i (g_i - <g>) = 0.
 *
 * Rotation (2D and 3D; 3D: each component of the spin vector): each grain's spin is kicked with
 * its own moment of inertia I_i = q m_i r_i^2 by the torques of kernels_poly.c; the work of their
 * non-conservative part is booked as the forces' is (all of a dashpot's or friction's torque; a
 * history law's spring torque is conservative and its energy is the springs', so the kernel keeps
 * the rest apart in s->tg, as step.c reads it).
 *
 * [noise] mode = com removes the centre-of-mass velocity sum_i m_i v_i / sum_i m_i every
 * com_interval (gr_remove_com), between steps as step.c does. The Langevin bath ([driving] kind =
 * langevin) takes the random force's place: bath_range. 3D has the third component of every kick
 * and drift. Along a wall axis the drift does not wrap (a grain riding a floor that vibrates
 * below 0 keeps its coordinate, as step.c).
 *
 * Threads: each pass (half kick, driving, drift) runs over blocks of GR_BLOCK grains shared by
 * the threads; its sums are kept per block in LANES partial sums (so the loops vectorise) and
 * added in block order, and the normals are step.c's (per block, the symmetrised mean from block
 * sums), so a run is bit-identical for every thread count. The pair loop (kernels_poly.c) runs
 * on one thread.
 *
 * The closing half kick ends every step (the velocities are synchronised after each step), so a
 * run split into calls is the same as one call. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "integrators/verlet/verlet.h"

/* The grains i0 + l of [lo, hi) (lo a multiple of LANES) in blocks of LANES whose lanes l the
 * compiler vectorises; the loop body follows. */
#define FOR_LANES(lo, hi, i0, l)                                                                   \
    for (int i0 = (lo); i0 < (hi); i0 += LANES)                                                    \
    _Pragma("omp simd") for (int l = 0; l < ((hi)-i0 < LANES ? (hi)-i0 : LANES); l++)

/* The per-block sums of the passes, PB_FIELDS per block. */
enum { PB_WORK, PB_SUM, PB_ADDED, PB_DRAG, PB_WORST, PB_FIELDS };

/* A half kick of component v: v_i += f_i h / m_i, the work of the non-conservative part g_i at
 * the mid-kick velocity into *w, the new velocity into *sum (finiteness). */
static inline __attribute__((always_inline)) void kick_c(double *restrict v,
                                                         const double *restrict f,
                                                         const double *restrict g, const double hi,
                                                         const int i, double *w, double *sum)
{
    const double dv = hi * f[i];
    *w += g[i] * (v[i] + 0.5 * dv);
    v[i] += dv;
    *sum += v[i];
}

/* A half kick v_i += F_i dt / (2 m_i) of the grains [lo, hi) (dim a constant of each call), and of
 * the spins w += tau dt / (2 I_i) with rotation (3D: each component of the vectors (wx, wy,
 * omega = w_z); a history law's springs: only the non-conservative torques tg do booked work).
 * part[PB_WORK]: the work of G and of the non-conservative torques (before the factor dt / 2),
 * part[PB_SUM]: the sum of the new velocities and spins (finite or not). */
static inline __attribute__((always_inline)) void half_kick_range(gr_sim *restrict s, const int lo,
                                                                  const int hi, const int dim,
                                                                  double *restrict part)
{
    const double h = 0.5 * s->dt;
    const double *restrict inv_m = s->inv_m;
    double wl[LANES] = {0}, sl[LANES] = {0};
    FOR_LANES(lo, hi, i0, l)
    {
        const int i = i0 + l;
        const double hm = h * inv_m[i];
        kick_c(s->vx, s->fx, s->gx, hm, i, &wl[l], &sl[l]);
        if (dim >= 2) {
            kick_c(s->vy, s->fy, s->gy, hm, i, &wl[l], &sl[l]);
        }
        if (dim == 3) {
            kick_c(s->vz, s->fz, s->gz, hm, i, &wl[l], &sl[l]);
        }
    }
    if (s->omega) {
        double *const w[3] = {s->omega, s->wx, s->wy};
        const double *const tq[3] = {s->tq, s->tqx, s->tqy};
        const double *const nc[3] = {s->tg ? s->tg : s->tq, s->tgx ? s->tgx : s->tqx,
                                     s->tgy ? s->tgy : s->tqy};
        const double *restrict inertia = s->inertia_i;
        for (int c = 0; c < (dim == 3 ? 3 : 1); c++) {
            FOR_LANES(lo, hi, i0, l)
            {
                const int i = i0 + l;
                kick_c(w[c], tq[c], nc[c], h / inertia[i], i, &wl[l], &sl[l]);
            }
        }
    }
    part[PB_WORK] = lanes_total(wl);
    part[PB_SUM] = lanes_total(sl);
}

/* The random force's kick of the grains [lo, hi): dv = sqrt(2 D dt) / m_i (g - <g>) per
 * component; part[PB_ADDED] the kinetic energy it added. */
static inline __attribute__((always_inline)) void noise_range(gr_sim *restrict s, const int lo,
                                                              const int hi, const int dim,
                                                              const double mean[3],
                                                              double *restrict part)
{
    const double amp = sqrt(2.0 * s->params.D * s->dt);
    double *const v[3] = {s->vx, s->vy, s->vz};
    const double *restrict g = s->noise, *restrict inv_m = s->inv_m, *restrict mass = s->mass_i;
    double al[LANES] = {0};
    FOR_LANES(lo, hi, i0, l)
    {
        const int i = i0 + l;
        for (int c = 0; c < dim; c++) {
            const double dv = amp * inv_m[i] * (g[(size_t)i * dim + c] - mean[c]);
            al[l] += mass[i] * dv * (v[c][i] + 0.5 * dv);
            v[c][i] += dv;
        }
    }
    part[PB_ADDED] = lanes_total(al);
}

/* The Langevin bath's exact Ornstein-Uhlenbeck update (driving_langevin.c) of the grains
 * [lo, hi), each with its own mass: the drag -m_i v / tau (the same tau, so the same decay for
 * all) and the noise that holds every grain at the bath's energy per degree of freedom,
 * k_B T = m_1 T_bath / dim (m_1 the first species' mass: the scene's T_bath is that species'
 * temperature in the units of eq. 2.19; a radius distribution: the grains' mean mass), so grain
 * i's kick is the one-species kick times sqrt(m_1 / m_i). part[PB_ADDED]: the kinetic energy the
 * noise added; part[PB_DRAG]: the energy the drag removed. */
static inline __attribute__((always_inline)) void bath_range(gr_sim *restrict s, const int lo,
                                                             const int hi, const int dim,
                                                             double *restrict part)
{
    const double decay = s->drive_c.decay, kick = s->drive_c.kick;
    const double m1 = s->params.size_distribution ? s->mass : s->params.species_mass[0];
    double *const v[3] = {s->vx, s->vy, s->vz};
    const double *restrict g = s->noise, *restrict inv_m = s->inv_m, *restrict mass = s->mass_i;
    double al[LANES] = {0}, dl[LANES] = {0};
    FOR_LANES(lo, hi, i0, l)
    {
        const int i = i0 + l;
        const double ki = kick * sqrt(m1 * inv_m[i]);
        for (int c = 0; c < dim; c++) {
            const double vi = v[c][i], vd = decay * vi, dv = ki * g[(size_t)i * dim + c];
            dl[l] += 0.5 * mass[i] * (vi * vi - vd * vd);
            al[l] += mass[i] * dv * (vd + 0.5 * dv);
            v[c][i] = vd + dv;
        }
    }
    part[PB_ADDED] = lanes_total(al);
    part[PB_DRAG] = lanes_total(dl);
}

/* The drift of the grains [lo, hi), wrapping into [0, L) along periodic axes only; part[PB_WORST]
 * the largest squared displacement since the list's build (minimum image along periodic axes).
 * 1D: the ring keeps unwrapped, ordered positions and has no list. */
static inline __attribute__((always_inline)) void drift_range(gr_sim *restrict s, const int lo,
                                                              const int hi, const int dim,
                                                              double *restrict part)
{
    const double dt = s->dt, L = s->L, half = 0.5 * L;
    double *const q[3] = {s->x, s->y, s->z}, *const v[3] = {s->vx, s->vy, s->vz};
    const double *const ref[3] = {s->x_ref, s->y_ref, s->z_ref};
    const int periodic[3] = {isfinite(s->period[0]), isfinite(s->period[1]),
                             isfinite(s->period[2])};
    double wl[LANES] = {0};
    FOR_LANES(lo, hi, i0, l)
    {
        const int i = i0 + l;
        if (dim == 1) {
            q[0][i] += v[0][i] * dt;
            continue;
        }
        double d2 = 0.0;
        for (int a = 0; a < dim; a++) {
            double x = q[a][i] + v[a][i] * dt;
            x += periodic[a] ? (x < 0.0 ? L : (x >= L ? -L : 0.0)) : 0.0;
            q[a][i] = x;
            double dx = x - ref[a][i];
            dx += periodic[a] ? (dx > half ? -L : (dx < -half ? L : 0.0)) : 0.0;
            d2 += dx * dx;
        }
        wl[l] = d2 > wl[l] ? d2 : wl[l]; /* fmax inline (NaN keeps the lane's worst) */
    }
    double worst = 0.0;
    for (int l = 0; l < LANES; l++) {
        worst = wl[l] > worst ? wl[l] : worst;
    }
    part[PB_WORST] = worst;
}

enum { PASS_KICK, PASS_NOISE, PASS_BATH, PASS_DRIFT };

/* One pass over block b's grains, dim a constant. */
static inline __attribute__((always_inline)) void pass_block(gr_sim *s, const int pass, const int b,
                                                             const int dim, const double mean[3],
                                                             double *part)
{
    const int n = s->n, lo = b * GR_BLOCK, hi = lo + GR_BLOCK < n ? lo + GR_BLOCK : n;
    switch (pass) {
    case PASS_KICK: half_kick_range(s, lo, hi, dim, part); break;
    case PASS_NOISE: noise_range(s, lo, hi, dim, mean, part); break;
    case PASS_BATH: bath_range(s, lo, hi, dim, part); break;
    default: drift_range(s, lo, hi, dim, part); break;
    }
}

static void pass_block_any(gr_sim *s, const int pass, const int b, const double mean[3],
                           double *part)
{
    switch (s->dim) {
    case 1: pass_block(s, pass, b, 1, mean, part); break;
    case 2: pass_block(s, pass, b, 2, mean, part); break;
    default: pass_block(s, pass, b, 3, mean, part); break;
    }
}

/* A pass over every block on T threads; the block sums in parts (PB_FIELDS per block). */
static void run_pass(gr_sim *s, const int pass, const double mean[3], double *parts, const int T)
{
    const int nb = s->nblk;
#pragma omp parallel for schedule(static) num_threads(T) if (T > 1)
    for (int b = 0; b < nb; b++) {
        pass_block_any(s, pass, b, mean, parts + (size_t)b * PB_FIELDS);
    }
}

/* The sum of field f over the blocks, in block order. */
static double block_total(const double *parts, const int nb, const int f)
{
    double t = 0.0;
    for (int b = 0; b < nb; b++) {
        t += parts[(size_t)b * PB_FIELDS + f];
    }
    return t;
}

/* A half kick of every grain; returns the work of the non-conservative forces and torques
 * (step.c, half_kick) and sets *finite. */
static double half_kick_poly(gr_sim *s, double *parts, const int T, bool *finite)
{
    const int nb = s->nblk;
    run_pass(s, PASS_KICK, NULL, parts, T);
    const double work = block_total(parts, nb, PB_WORK), sum = block_total(parts, nb, PB_SUM);
    const double h = 0.5 * s->dt;
    *finite = isfinite(sum) && isfinite(work);
    return work * h;
}

int gr_verlet_step_poly(gr_sim *s, int64_t nsteps, gr_error *err)
{
    const bool noise = s->params.noise_mode != GR_NOISE_NONE && s->params.D > 0.0;
    const bool bath = s->drive == GR_DRIVE_BATH, com = s->params.noise_mode == GR_NOISE_COM;
    const double skin_half2 = 0.25 * (s->cutoff - s->d) * (s->cutoff - s->d);
    const int T = gr_team(s), nb = s->nblk;
    double *parts = malloc(sizeof(double) * PB_FIELDS * (size_t)(nb > 0 ? nb : 1));
    if (!parts) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the step's block sums (%d blocks)", nb);
    }
    int rc = 0;
    for (int64_t k = 0; k < nsteps && !rc; k++) {
        bool finite;
        if (com && s->step > 0 && s->step % s->com_every == 0) {
            s->removed_com += gr_remove_com(s); /* between steps: synchronised velocities */
        }
        gr_verlet_book(s, half_kick_poly(s, parts, T, &finite));
        if (bath || noise) { /* the bath replaces the random force, as in step.c */
            double mean[3];
            gr_verlet_draw_noise(s, mean, T);
            run_pass(s, bath ? PASS_BATH : PASS_NOISE, mean, parts, T);
            s->injected += block_total(parts, nb, PB_ADDED);
            if (bath) {
                s->diss_drag += block_total(parts, nb, PB_DRAG);
            }
        }
        run_pass(s, PASS_DRIFT, NULL, parts, T);
        double disp2 = 0.0;
        for (int b = 0; b < nb; b++) {
            const double w = parts[(size_t)b * PB_FIELDS + PB_WORST];
            disp2 = w > disp2 ? w : disp2;
        }
        if (!finite) {
            rc = gr_verlet_check_finite(s, err);
            rc = rc ? rc
                    : GR_FAIL(err, GR_EUNSTABLE, "unstable run: non-finite energy at step %lld",
                              (long long)s->step);
            break;
        }
        s->step++;
        if (s->dim >= 2 && (s->params.skin <= 0.0 || disp2 > skin_half2)) {
            rc = gr_neighbours_build(s, err);
            if (rc) {
                break;
            }
        }
        gr_sublist_refresh(s); /* as step.c: the pairs that can touch (core/sublist.c) */
        rc = gr_verlet_forces(s, err);
        if (rc) {
            break;
        }
        gr_verlet_book(s, half_kick_poly(s, parts, T, &finite));
    }
    free(parts);
    return rc ? rc : gr_verlet_check_finite(s, err);
}
