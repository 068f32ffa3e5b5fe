/* The verlet step of a simulation with species (docs/mixtures.md): the scheme of step.c (kick,
 * random-force kick, drift, forces with the half-step velocity, kick), each grain with its own
 * mass m_i. One thread, plain loops: its own instance, chosen once per call, so step.c's loops
 * are the ones they always were.
 *
 * The random force is white noise of the same strength D on every grain, so grain i's kick is
 * sqrt(2 D dt) / m_i times a standard normal per component, and it injects d D / m_i per second
 * on average (the ledger books the exact kinetic energy of each kick). Symmetrised mode (2.18)
 * subtracts the mean of the forces, not of the kicks, so the kicks carry no net momentum:
 * sum_i m_i dv_i = sqrt(2 D dt) sum_i (g_i - <g>) = 0.
 *
 * Rotation (2D and 3D; 3D: each component of the spin vector): each grain's spin is kicked with
 * its own moment of inertia I_i = q m_i r_i^2 by the torques of kernels_poly.c; the work of their non-conservative part is booked as the forces'
 * is (all of a dashpot's or friction's torque; a history law's spring torque is conservative and
 * its energy is the springs', so the kernel keeps the rest apart in s->tg, as step.c reads it).
 *
 * [noise] mode = com removes the centre-of-mass velocity sum_i m_i v_i / sum_i m_i every
 * com_interval (gr_remove_com), between steps as step.c does. The Langevin bath ([driving] kind =
 * langevin) takes the random force's place: bath_poly. 3D has the third component of every kick
 * and drift.
 *
 * The closing half kick ends every step (the velocities are synchronised after each step), so a
 * run split into calls is the same as one call. */
#include <math.h>
#include <stdbool.h>

#include "granule/noise.h"
#include "integrators/verlet/verlet.h"

/* A half kick v_i += F_i dt / (2 m_i); returns the work of the non-conservative part G (step.c,
 * half_kick), and whether every velocity is finite. */
static double half_kick_poly(gr_sim *s, bool *finite)
{
    const double h = 0.5 * s->dt;
    double work = 0.0, sum = 0.0;
    for (int i = 0; i < s->n; i++) {
        const double hi = h * s->inv_m[i];
        const double dvx = hi * s->fx[i];
        work += s->gx[i] * (s->vx[i] + 0.5 * dvx);
        s->vx[i] += dvx;
        sum += s->vx[i];
        if (s->dim >= 2) {
            const double dvy = hi * s->fy[i];
            work += s->gy[i] * (s->vy[i] + 0.5 * dvy);
            s->vy[i] += dvy;
            sum += s->vy[i];
        }
        if (s->dim == 3) {
            const double dvz = hi * s->fz[i];
            work += s->gz[i] * (s->vz[i] + 0.5 * dvz);
            s->vz[i] += dvz;
            sum += s->vz[i];
        }
    }
    /* rotation: w_i += tq_i dt / (2 I_i), the torques' work as for v (step.c); 3D: each
     * component of the vectors (wx, wy, omega = w_z); a history law's springs: only the
     * non-conservative torques (tg; 3D tgx, tgy, tg) do booked work */
    double *const w[3] = {s->omega, s->wx, s->wy};
    const double *const tq[3] = {s->tq, s->tqx, s->tqy}, *const nc[3] = {s->tg ? s->tg : s->tq,
                                                                         s->tgx ? s->tgx : s->tqx,
                                                                         s->tgy ? s->tgy : s->tqy};
    for (int c = 0; s->omega && c < (s->dim == 3 ? 3 : 1); c++) {
        for (int i = 0; i < s->n; i++) {
            const double dw = h / s->inertia_i[i] * tq[c][i];
            work += nc[c][i] * (w[c][i] + 0.5 * dw);
            w[c][i] += dw;
            sum += w[c][i];
        }
    }
    *finite = isfinite(sum) && isfinite(work);
    return work * h;
}

/* The Langevin bath's exact Ornstein-Uhlenbeck update (driving_langevin.c) of grain i with its
 * own mass: the drag -m_i v / tau (the same tau, so the same decay for all) and the noise that
 * holds every grain at the bath's energy per degree of freedom, k_B T = m_1 T_bath / dim (m_1 the
 * first species' mass: the scene's T_bath is that species' temperature in the units of eq. 2.19;
 * a radius distribution: the grains' mean mass), so grain i's kick is the one-species kick times
 * sqrt(m_1 / m_i). Returns the kinetic energy the
 * noise added; *drag the drag removed. */
static double bath_poly(gr_sim *s, double *drag)
{
    const int n = s->n, dim = s->dim;
    gr_noise_normals(s->params.seed, GR_STREAM_NOISE, (uint64_t)s->step, 0, n, dim, s->noise);
    const double decay = s->drive_c.decay, kick = s->drive_c.kick;
    const double m1 = s->params.size_distribution ? s->mass : s->params.species_mass[0];
    double *v[3] = {s->vx, s->vy, s->vz};
    double added = 0.0, dragged = 0.0;
    for (int i = 0; i < n; i++) {
        const double ki = kick * sqrt(m1 * s->inv_m[i]);
        for (int c = 0; c < dim; c++) {
            const double vi = v[c][i], vd = decay * vi, dv = ki * s->noise[(size_t)i * dim + c];
            dragged += 0.5 * s->mass_i[i] * (vi * vi - vd * vd);
            added += s->mass_i[i] * dv * (vd + 0.5 * dv);
            v[c][i] = vd + dv;
        }
    }
    *drag = dragged;
    return added;
}

/* The random force's kicks; returns the kinetic energy they added. */
static double noise_kick_poly(gr_sim *s)
{
    const int n = s->n, dim = s->dim;
    gr_noise_normals(s->params.seed, GR_STREAM_NOISE, (uint64_t)s->step, 0, n, dim, s->noise);
    double mean[3] = {0.0, 0.0, 0.0};
    if (s->params.noise_mode == GR_NOISE_SYMMETRISED && n > 1) {
        for (int i = 0; i < n; i++) {
            for (int c = 0; c < dim; c++) {
                mean[c] += s->noise[(size_t)i * dim + c];
            }
        }
        mean[0] /= n;
        mean[1] /= n;
        mean[2] /= n;
    }
    const double amp = sqrt(2.0 * s->params.D * s->dt);
    double *v[3] = {s->vx, s->vy, s->vz};
    double added = 0.0;
    for (int i = 0; i < n; i++) {
        for (int c = 0; c < dim; c++) {
            const double dv = amp * s->inv_m[i] * (s->noise[(size_t)i * dim + c] - mean[c]);
            added += s->mass_i[i] * dv * (v[c][i] + 0.5 * dv);
            v[c][i] += dv;
        }
    }
    return added;
}

/* 3D: the drift, wrapping into [0, L) along periodic axes only (a wall axis keeps the coordinate,
 * as step.c); the displacement since the list's build under the minimum image. */
static double drift_poly_3d(gr_sim *s)
{
    const double dt = s->dt, L = s->L, half = 0.5 * L;
    double *const q[3] = {s->x, s->y, s->z}, *const v[3] = {s->vx, s->vy, s->vz},
                  *const ref[3] = {s->x_ref, s->y_ref, s->z_ref};
    double worst = 0.0;
    for (int i = 0; i < s->n; i++) {
        double d2 = 0.0;
        for (int a = 0; a < 3; a++) {
            const int periodic = isfinite(s->period[a]);
            double x = q[a][i] + v[a][i] * dt;
            x += periodic ? (x < 0.0 ? L : (x >= L ? -L : 0.0)) : 0.0;
            q[a][i] = x;
            double dx = x - ref[a][i];
            dx += periodic ? (dx > half ? -L : (dx < -half ? L : 0.0)) : 0.0;
            d2 += dx * dx;
        }
        worst = d2 > worst ? d2 : worst; /* fmax(worst, d2) inline (NaN keeps worst) */
    }
    return worst;
}

/* The drift; returns the largest squared displacement since the last list build (2D, 3D). */
static double drift_poly(gr_sim *s)
{
    if (s->dim == 3) {
        return drift_poly_3d(s);
    }
    const double dt = s->dt, L = s->L, half = 0.5 * L;
    double worst = 0.0;
    for (int i = 0; i < s->n; i++) {
        s->x[i] += s->vx[i] * dt;
        if (s->dim == 1) {
            continue; /* the ring keeps unwrapped, ordered positions */
        }
        double y = s->y[i] + s->vy[i] * dt, x = s->x[i];
        x += x < 0.0 ? L : (x >= L ? -L : 0.0);
        y += y < 0.0 ? L : (y >= L ? -L : 0.0);
        s->x[i] = x;
        s->y[i] = y;
        double dx = x - s->x_ref[i], dy = y - s->y_ref[i];
        dx += dx > half ? -L : (dx < -half ? L : 0.0);
        dy += dy > half ? -L : (dy < -half ? L : 0.0);
        const double d2 = dx * dx + dy * dy;
        worst = d2 > worst ? d2 : worst; /* fmax(worst, d2) inline (NaN keeps worst) */
    }
    return worst;
}

int gr_verlet_step_poly(gr_sim *s, int64_t nsteps, gr_error *err)
{
    const bool noise = s->params.noise_mode != GR_NOISE_NONE && s->params.D > 0.0;
    const bool bath = s->drive == GR_DRIVE_BATH, com = s->params.noise_mode == GR_NOISE_COM;
    const double skin_half2 = 0.25 * (s->cutoff - s->d) * (s->cutoff - s->d);
    for (int64_t k = 0; k < nsteps; k++) {
        bool finite;
        if (com && s->step > 0 && s->step % s->com_every == 0) {
            s->removed_com += gr_remove_com(s); /* between steps: synchronised velocities */
        }
        gr_verlet_book(s, half_kick_poly(s, &finite));
        if (bath) { /* the bath replaces the random force, as in step.c */
            double drag;
            s->injected += bath_poly(s, &drag);
            s->diss_drag += drag;
        } else if (noise) {
            s->injected += noise_kick_poly(s);
        }
        const double disp2 = drift_poly(s);
        if (!finite) {
            int rc = gr_verlet_check_finite(s, err);
            return rc ? rc
                      : GR_FAIL(err, GR_EUNSTABLE, "unstable run: non-finite energy at step %lld",
                                (long long)s->step);
        }
        s->step++;
        if (s->dim >= 2 && (s->params.skin <= 0.0 || disp2 > skin_half2)) {
            int rc = gr_neighbours_build(s, err);
            if (rc) {
                return rc;
            }
        }
        gr_sublist_refresh(s); /* as step.c: the pairs that can touch (core/sublist.c) */
        int rc = gr_verlet_forces(s, err);
        if (rc) {
            return rc;
        }
        gr_verlet_book(s, half_kick_poly(s, &finite));
    }
    return gr_verlet_check_finite(s, err);
}
