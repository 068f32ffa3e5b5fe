/* The time step: velocity Verlet in kick-drift-kick form with the random force as a mid-step
 * velocity kick (docs/integrator.md).
 *
 *   v += F_c(x_n, v_{n-1/2}) dt / 2M          close step n
 *   v += eta_n dt / M                          random force (2.16 / 2.23), symmetrised (2.18)
 *   x += v dt                                  drift
 *   F_c(x_{n+1}, v_{n+1/2})                    contact forces with the half-step velocity
 *   v += F_c dt / 2M
 *
 * Positions are identical to the thesis's position Verlet (2.3) with a = (F_c + eta) / M. The
 * dashpots see the half-step velocity, the only velocity known before the force evaluation; any
 * scheme is first order for these forces because they jump at the start and end of a contact
 * (Danby et al. 2013), and this one needs one force evaluation per step.
 *
 * The random force held over a step has standard deviation sqrt(2D/dt) per component, so the
 * velocity kick is sqrt(2 D dt) / M * g, g standard normal. Symmetrised mode subtracts the mean
 * kick (2.18); com mode removes the centre-of-mass velocity every com_interval instead
 * (sec. 2.3.1). The ledger records the exact kinetic energy each kick adds. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "core/sim_internal.h"
#include "granule/noise.h"

/* Closing half kick. Returns the work done on the particles by the non-conservative part of the
 * contact forces (dashpots, friction, a clamp), exactly: a kick changes the kinetic energy of
 * particle i by F_i . vbar_i dt/2 with vbar_i the mean of its velocity before and after, so the
 * part due to G_i = F_i - (spring forces) is G_i . vbar_i dt/2. */
static double half_kick(gr_sim *s, bool *finite)
{
    const double h = 0.5 * s->dt / s->mass, hdt = 0.5 * s->dt;
    const int n = s->n;
    double *restrict vx = s->vx;
    const double *restrict fx = s->fx, *restrict gx = s->gx;
    double work = 0.0, sum = 0.0;
    for (int i = 0; i < n; i++) {
        const double dv = h * fx[i];
        work += gx[i] * (vx[i] + 0.5 * dv);
        vx[i] += dv;
        sum += vx[i];
    }
    if (s->dim == 2) {
        double *restrict vy = s->vy;
        const double *restrict fy = s->fy, *restrict gy = s->gy;
        for (int i = 0; i < n; i++) {
            const double dv = h * fy[i];
            work += gy[i] * (vy[i] + 0.5 * dv);
            vy[i] += dv;
            sum += vy[i];
        }
    }
    *finite = isfinite(sum) && isfinite(work);
    return work * hdt;
}

/* Book energy dissipated (= minus the work of the non-conservative forces), split between the
 * mechanisms in proportion to their dissipation rates at the force evaluation. */
static void book_dissipation(gr_sim *s, double work)
{
    s->diss_n -= work * s->share[0];
    s->diss_t -= work * s->share[1];
    s->diss_f -= work * s->share[2];
}

static void set_shares(gr_sim *s, const gr_force_report *r)
{
    double total = r->power_normal + r->power_tangential + r->power_friction;
    if (total > 0.0) {
        s->share[0] = r->power_normal / total;
        s->share[1] = r->power_tangential / total;
        s->share[2] = r->power_friction / total;
    } else {
        s->share[0] = 1.0;
        s->share[1] = s->share[2] = 0.0;
    }
}

/* Draw this step's normals and the means the symmetrised mode subtracts (2.18). */
static void draw_noise(gr_sim *s, double mean[2])
{
    const int n = s->n, dim = s->dim;
    gr_noise_normals(s->scene.seed, GR_STREAM_NOISE, (uint64_t)s->step, 0, n, dim, s->noise);
    mean[0] = mean[1] = 0.0;
    if (s->scene.noise_mode == GR_NOISE_SYMMETRISED && n > 1) {
        const double *restrict g = s->noise;
        double m0 = 0.0, m1 = 0.0;
        if (dim == 1) {
            for (int i = 0; i < n; i++) {
                m0 += g[i];
            }
        } else {
            for (int i = 0; i < n; i++) {
                m0 += g[2 * i];
                m1 += g[2 * i + 1];
            }
        }
        mean[0] = m0 / n;
        mean[1] = m1 / n;
    }
}

/* First half of a step in one pass: half kick, noise kick (if `noise`), drift. Returns the kinetic
 * energy the noise added; in 2D also the largest squared displacement since the last neighbour
 * list build. */
static inline __attribute__((always_inline)) double
open_step_1d(gr_sim *restrict s, const int noise, const double mean, double *work_nc)
{
    const int n = s->n;
    const double h = 0.5 * s->dt / s->mass, dt = s->dt;
    const double amp = noise ? sqrt(2.0 * s->scene.D * s->dt) / s->mass : 0.0;
    double *restrict x = s->x, *restrict v = s->vx;
    const double *restrict f = s->fx, *restrict g = s->noise, *restrict gnc = s->gx;
    double added = 0.0, work = 0.0;
    for (int i = 0; i < n; i++) {
        const double dvf = h * f[i];
        work += gnc[i] * (v[i] + 0.5 * dvf);
        double vi = v[i] + dvf;
        if (noise) {
            const double dv = amp * (g[i] - mean);
            added += dv * (vi + 0.5 * dv);
            vi += dv;
        }
        v[i] = vi;
        x[i] += vi * dt; /* unwrapped: the ring keeps its order */
    }
    *work_nc = 0.5 * dt * work;
    return s->mass * added;
}

static inline __attribute__((always_inline)) double
open_step_2d(gr_sim *restrict s, const int noise, const double mean[2], double *max_disp2,
             double *work_nc)
{
    const int n = s->n;
    const double h = 0.5 * s->dt / s->mass, dt = s->dt, L = s->L, half = 0.5 * L;
    const double amp = noise ? sqrt(2.0 * s->scene.D * s->dt) / s->mass : 0.0;
    const double m0 = mean[0], m1 = mean[1];
    double *restrict x = s->x, *restrict y = s->y, *restrict vx = s->vx, *restrict vy = s->vy;
    const double *restrict fx = s->fx, *restrict fy = s->fy, *restrict g = s->noise;
    const double *restrict xr = s->x_ref, *restrict yr = s->y_ref;
    const double *restrict gx = s->gx, *restrict gy = s->gy;
    double added = 0.0, worst = 0.0, work = 0.0;
    for (int i = 0; i < n; i++) {
        const double dvx0 = h * fx[i], dvy0 = h * fy[i];
        work += gx[i] * (vx[i] + 0.5 * dvx0) + gy[i] * (vy[i] + 0.5 * dvy0);
        double vxi = vx[i] + dvx0, vyi = vy[i] + dvy0;
        if (noise) {
            const double dvx = amp * (g[2 * i] - m0), dvy = amp * (g[2 * i + 1] - m1);
            added += dvx * (vxi + 0.5 * dvx) + dvy * (vyi + 0.5 * dvy);
            vxi += dvx;
            vyi += dvy;
        }
        vx[i] = vxi;
        vy[i] = vyi;
        double xn = x[i] + vxi * dt, yn = y[i] + vyi * dt;
        xn += xn < 0.0 ? L : (xn >= L ? -L : 0.0);
        yn += yn < 0.0 ? L : (yn >= L ? -L : 0.0);
        x[i] = xn;
        y[i] = yn;
        double dx = xn - xr[i], dy = yn - yr[i];
        dx += dx > half ? -L : (dx < -half ? L : 0.0);
        dy += dy > half ? -L : (dy < -half ? L : 0.0);
        const double d2 = dx * dx + dy * dy;
        worst = d2 > worst ? d2 : worst;
    }
    *max_disp2 = worst;
    *work_nc = 0.5 * dt * work;
    return s->mass * added;
}

/* Remove the centre-of-mass velocity; returns the kinetic energy removed. */
static double remove_com(gr_sim *s)
{
    double removed = 0.0;
    double *v[2] = {s->vx, s->vy};
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

static int check_finite(gr_sim *s, gr_error *err)
{
    for (int i = 0; i < s->n; i++) {
        double sum = s->x[i] + s->vx[i] + (s->dim == 2 ? s->y[i] + s->vy[i] : 0.0);
        if (!isfinite(sum)) {
            return GR_FAIL(err, GR_EUNSTABLE,
                           "unstable run: particle %d has a non-finite position or velocity at step %lld (t = %.6g s); "
                           "dt = %g s may be too large for k_s = %g N/m (t_c = %.3g s)",
                           i, (long long)s->step, gr_sim_time(s), s->dt, s->cc.k_s, s->cc.t_c);
        }
    }
    return GR_OK;
}

/* Overlap beyond this fraction of d means the springs cannot hold the particles apart. */
#define RUNAWAY_OVERLAP 0.5

int gr_sim_step(gr_sim *s, int64_t nsteps, gr_error *err)
{
    const bool noise = s->scene.noise_mode != GR_NOISE_NONE && s->scene.D > 0.0;
    const bool com = s->scene.noise_mode == GR_NOISE_COM;
    const double skin_half2 = 0.25 * (s->cutoff - s->d) * (s->cutoff - s->d);
    for (int64_t k = 0; k < nsteps; k++) {
        double mean[2] = {0.0, 0.0}, disp2 = 0.0, work = 0.0;
        if (com && s->step > 0 && s->step % s->com_every == 0) {
            s->removed_com += remove_com(s); /* at a step boundary; booked in the ledger */
        }
        if (noise) {
            draw_noise(s, mean);
        }
        if (s->dim == 1) {
            s->injected += noise ? open_step_1d(s, 1, mean[0], &work) : open_step_1d(s, 0, 0.0, &work);
        } else {
            s->injected += noise ? open_step_2d(s, 1, mean, &disp2, &work) : open_step_2d(s, 0, mean, &disp2, &work);
        }
        book_dissipation(s, work); /* the previous step's forces, with their shares */
        s->step++;
        if (s->dim == 2 && (s->scene.skin <= 0.0 || disp2 > skin_half2)) {
            int rc = gr_neighbours_build(s, err);
            if (rc) {
                return rc;
            }
        }
        gr_force_report r;
        gr_forces(s, &r);
        set_shares(s, &r);
        bool finite;
        book_dissipation(s, half_kick(s, &finite));
        if (!finite) {
            int rc = check_finite(s, err); /* names the particle */
            return rc ? rc : GR_FAIL(err, GR_EUNSTABLE, "unstable run: non-finite energy at step %lld", (long long)s->step);
        }
        s->elastic = r.elastic;
        s->collisions += r.new_contacts;
        s->last = r;
        if (r.max_overlap > RUNAWAY_OVERLAP) {
            return GR_FAIL(err, GR_EUNSTABLE,
                           "unstable run: particles %d and %d overlap by %.3g d at step %lld (t = %.6g s), beyond the %.2g d limit; "
                           "the springs (k_s = %g N/m) cannot hold them apart at this speed or packing; use a stiffer k_s or a smaller dt",
                           r.worst_i, r.worst_j, r.max_overlap, (long long)s->step, gr_sim_time(s),
                           RUNAWAY_OVERLAP, s->cc.k_s);
        }
        if ((s->step & 1023) == 0) {
            int rc = check_finite(s, err);
            if (rc) {
                return rc;
            }
        }
    }
    return check_finite(s, err);
}
