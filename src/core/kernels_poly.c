/* The force kernel of a run with species (docs/mixtures.md): the same pair geometry and normal
 * laws as kernels.c (models/NAME.h through kernel_laws.h's normal_law), with the pair's own
 * contact distance r_i + r_j and coefficients (s->cc_pair of the two species: reduced mass,
 * damping, stiffness). In 2D a tangential law without history (tangential_dashpot,
 * sliding_friction; species lists) acts on g_t = g.t with the pair's coefficients, as in
 * kernels.c, and books its dissipation into its own ledger column; with rotation g_t is the
 * contact point's, g.t + a_i w_i + a_j w_j, and f_t turns grain i with the torque a_i f_t
 * (a_i = |r_ij| r_i / (r_i + r_j), the arm to the contact point). The history law
 * (tangential_spring, linear or Mindlin) keeps its slot per list entry as kernels.c does
 * (contact_history.c), with the pair's k_t and gamma_t: the spring's force -k_t s is conservative
 * (its energy goes into the elastic total), the rest goes into G and, with rotation, into s->tg
 * (the non-conservative torques that step_poly.c books). The rolling law (rolling_friction)
 * resists w_i - w_j with the pair's own R_ij = r_i r_j / (r_i + r_j) and, for the limit that
 * arrests the rolling within a step, its reduced moment of inertia I_i I_j / (I_i + I_j). 3D
 * (poly_3d, spheres) has the laws without history with vectors (kernels_3d.c's geometry). A
 * separate instance, chosen once per run (gr_kernel_choose) when the scene has species, so the
 * monodisperse instances (1D, 2D, 3D) load nothing per pair that they did not before.
 * Threads (2D, 3D; poly_rows): the touching pairs of each block of rows are recorded on the
 * threads, then each thread applies the pairs' ends that fall among its own grains, walking all
 * records in entry order, so every grain receives its pairs in the order one thread gives them:
 * the forces are the same bits for every thread count, and the ledger's sums are per block of rows
 * in block order. The Verlet step's contact sublist (core/sublist.c) replaces the list's rows when
 * on, in 2D and 3D alike. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/kernel_laws.h"

/* One contact: fills the force along n, its non-conservative part, the elastic energy (J) and the
 * dissipation rate (-f_d g_n, W); returns 0 when the pair is apart (gap >= d_ij). */
/* A radius distribution (cc_pair NULL): the pair's coefficients from the reference pair's (s->cc,
 * reduced mass cont_m12, effective radius cont_r), scaled to its reduced mass M and effective
 * radius R (gr_size_scaled, sim_internal.h). */
/* The arms from the centres of i and j to the contact point, which divides |r_ij| = dist as
 * r_i : r_j (a_i + a_j = dist to rounding). Each by the same expression, so a grain's arm does not
 * depend on which of the two owns the pair in the neighbour list: that changes with the list's
 * build, and dist - a_i (the earlier a_j) rounded apart from a_j's own expression, so a rotating
 * mixture's spins depended in their last bits on when the list was built (the hybrid's child
 * rebuilds its list every window; docs/hybrid.md, "Mixtures"). */
static inline void contact_arms(const gr_sim *s, int i, int j, double dist, double *ai, double *aj)
{
    const double sum = s->rad[i] + s->rad[j];
    *ai = dist * s->rad[i] / sum;
    *aj = dist * s->rad[j] / sum;
}

static inline int size_contact(const gr_sim *s, int i, int j, double gap, double g_n, double *f,
                               double *f_d, double *el, double *pn, gr_contact_coeffs *c)
{
    const double d = s->rad[i] + s->rad[j];
    if (gap >= d) {
        return 0;
    }
    const double mi = s->mass_i[i], mj = s->mass_i[j], M = mi * mj / (mi + mj);
    gr_size_scaled(&s->cc, s->cont_m12, s->cont_r, M, s->rad[i] * s->rad[j] / d, c);
    const gr_normal_force fn = normal_law(s->kernel.nl, c, d - gap, g_n, s->kernel.clamp);
    *f = fn.f;
    *f_d = fn.f_d;
    *el = c->e_scale * fn.e;
    *pn = -fn.f_d * g_n;
    return 1;
}

/* *cc: the coefficients the contact used (the species pair's, or a distribution's scaled into
 * *tmp), for its tangential and rolling laws. */
static inline int poly_contact(const gr_sim *s, int i, int j, double gap, double g_n, double *f,
                               double *f_d, double *el, double *pn, gr_contact_coeffs *tmp,
                               const gr_contact_coeffs **cc)
{
    if (!s->cc_pair) {
        *cc = tmp;
        return size_contact(s, i, j, gap, g_n, f, f_d, el, pn, tmp);
    }
    const int a = s->species[i], b = s->species[j];
    const double d = s->d_pair[a * s->nsp + b];
    if (gap >= d) {
        return 0;
    }
    const gr_contact_coeffs *c = &s->cc_pair[a * s->nsp + b];
    *cc = c;
    const gr_normal_force fn = normal_law(s->kernel.nl, c, d - gap, g_n, s->kernel.clamp);
    *f = fn.f;
    *f_d = fn.f_d;
    *el = c->e_scale * fn.e;
    *pn = -fn.f_d * g_n;
    return 1;
}

static gr_force_report report(double elastic, double pn, int64_t fresh, double worst, int wi,
                              int wj)
{
    return (gr_force_report){.elastic = elastic,
                             .power_normal = pn,
                             .power_tangential = 0.0,
                             .power_friction = 0.0,
                             .new_contacts = fresh,
                             .max_overlap = worst,
                             .worst_i = wi,
                             .worst_j = wj};
}

static void poly_1d(gr_sim *s, gr_force_report *r)
{
    const int n = s->n;
    double *f = s->fx, *g = s->gx;
    memset(f, 0, sizeof(double) * (size_t)n);
    memset(g, 0, sizeof(double) * (size_t)n);
    double elastic = 0.0, pn = 0.0, worst = 0.0;
    int wi = -1;
    int64_t fresh = 0;
    for (int i = 0; i < n && n > 1; i++) {
        const int j = i + 1 < n ? i + 1 : 0;
        const double gap = i + 1 < n ? s->x[j] - s->x[i] : s->x[0] + s->L - s->x[i];
        double fp, fd, el, p;
        gr_contact_coeffs tmp;
        const gr_contact_coeffs *cc;
        const uint8_t now =
            (uint8_t)poly_contact(s, i, j, gap, s->vx[j] - s->vx[i], &fp, &fd, &el, &p, &tmp, &cc);
        fresh += now > s->pair_contact[i];
        s->pair_contact[i] = now;
        if (!now) {
            continue;
        }
        f[j] += fp;
        f[i] -= fp;
        g[j] += fd;
        g[i] -= fd;
        elastic += el;
        pn += p;
        const double ov = (gr_pair_d(s, i, j) - gap) / gr_pair_d(s, i, j);
        if (ov > worst) {
            worst = ov;
            wi = i;
        }
    }
    *r = report(elastic, pn, fresh, worst, wi, wi >= 0 ? (wi + 1) % n : -1);
}

/* A history law's contact (i, j) that ended (n, dist: the pair's geometry now): the law forgets
 * the slot and returns the energy it held plus the work its last force did (J), as kernels.c's
 * forget with each grain's own arm. */
static double poly_forget(const gr_sim *s, int i, int j, double nx, double ny, double dist,
                          double *slot)
{
    /* a distribution (linear normal law only): the spring's constants are every pair's */
    const gr_contact_coeffs *c =
        s->cc_pair ? &s->cc_pair[s->species[i] * s->nsp + s->species[j]] : &s->cc;
    const double gx = s->vx[j] - s->vx[i], gy = s->vy[j] - s->vy[i];
    double g_t = gx * ny - gy * nx;
    if (s->omega) {
        double ai, aj;
        contact_arms(s, i, j, dist, &ai, &aj);
        g_t += ai * s->omega[i] + aj * s->omega[j];
    }
    const gr_tangential_in in = {.g_t = g_t,
                                 .xi = gr_pair_d(s, i, j) - dist,
                                 .g_n = gx * nx + gy * ny,
                                 .acts = 0,
                                 .hist = slot};
    return tangential_law(s->kernel.tl, c, in).lost;
}

/* The sums of the pair loop over one block of rows: the ledger's terms, new contacts, the deepest
 * pair (added block by block in block order: the same for every thread count). */
typedef struct poly_sums {
    double elastic, pn, worst, pt[2]; /* pt: tangential, friction */
    double el_t, lost;                /* a history law's springs (J) and what it dropped (J) */
    int wi, wj;
    int64_t fresh;
} poly_sums;

/* What one touching pair adds (poly_rec_2d, poly_rec_3d): the force F on j (-F on i) and its
 * non-conservative part G, per component; with rotation the tangential law's torques on i and j
 * (u_i, u_j), their non-conservative parts (w_i, w_j; history laws) and the rolling couple R (+R on
 * j, -R on i). 2D keeps its torques (about z) in component 2, as 3D's tq. Each term is added by
 * itself, in the order the one-pass loop added them, so the forces are the same bits whether a
 * pair is applied at once (one thread) or gathered by each grain (apply_end). */
typedef struct poly_rec {
    int i, j; /* the pair, when recorded for the threads */
    double F[3], G[3];
} poly_rec;

/* With rotation, a touching pair's torques (in their own array, so the records stay small). */
typedef struct poly_spin {
    double ui[3], uj[3], wi[3], wj[3], R[3];
} poly_spin;

/* The run's laws and arrays, read once per evaluation and passed by value, so that every pair sees
 * the same constants (and the compiler knows it): the tangential and rolling laws, the clamp,
 * history, the friction law's ledger column, rotation, whether the non-conservative torques are
 * kept apart (keep_tg; roll_tg: the rolling couple's too), 1 / dt. */
typedef struct poly_run {
    int tl, rl, clamp, hist, col, rot, keep_tg, roll_tg;
    double inv_dt;
} poly_run;

static poly_run run_of(const gr_sim *s)
{
    const int tl = s->kernel.tl, hist = history_of(tl), rot = s->omega != NULL;
    /* 2D: s->tg; 3D: all three arrays */
    const int keep_tg = rot && hist && s->tg && (s->dim == 2 || (s->tgx && s->tgy));
    return (poly_run){.tl = tl,
                      .rl = s->kernel.rl,
                      .clamp = s->kernel.clamp,
                      .hist = hist,
                      .col = book_of(tl) == GR_BOOK_FRICTION,
                      .rot = rot,
                      .keep_tg = keep_tg,
                      .roll_tg = s->dim == 2 ? rot && s->tg != NULL : keep_tg,
                      .inv_dt = 1.0 / s->dt};
}

/* A touching pair (i, j) at distance dist: its elastic energy and dissipation rate. */
static inline void tally(poly_sums *t, const gr_sim *s, int i, int j, double el, double pw,
                         double dist)
{
    t->elastic += el;
    t->pn += pw;
    const double ov = (gr_pair_d(s, i, j) - dist) / gr_pair_d(s, i, j);
    if (ov > t->worst) {
        t->worst = ov;
        t->wi = i;
        t->wj = j;
    }
}

/* 2D: entry p, the pair (i, j). Returns 0 when apart (the contact flag cleared, an ended history
 * spring forgotten); else fills o and adds its sums to t. Sets the entry's own contact flag and
 * history slot (no other entry's). */
static inline __attribute__((always_inline)) int poly_rec_2d(gr_sim *s, const poly_run u,
                                                             const int i, const int j, const int p,
                                                             poly_rec *o, poly_spin *w,
                                                             poly_sums *t)
{
    const double L = s->L;
    const int tl = u.tl, clamp = u.clamp, rl = u.rl, col = u.col, hist = u.hist;
    const double dx = wrap_delta(s->x[j] - s->x[i], L), dy = wrap_delta(s->y[j] - s->y[i], L);
    const double dist = sqrt(dx * dx + dy * dy);
    const double nx = dx / dist, ny = dy / dist;
    const double g_n = (s->vx[j] - s->vx[i]) * nx + (s->vy[j] - s->vy[i]) * ny;
    double f, fd, el, pw;
    gr_contact_coeffs tmp;
    const gr_contact_coeffs *c; /* the pair's coefficients, for its tangential laws */
    if (!poly_contact(s, i, j, dist, g_n, &f, &fd, &el, &pw, &tmp, &c)) {
        s->nl_contact[p] = 0;
        if (hist && s->nl_hist[p] != 0.0) { /* the contact ended: its spring goes */
            t->lost += poly_forget(s, i, j, nx, ny, dist, &s->nl_hist[p]);
        }
        return 0;
    }
    t->fresh += !s->nl_contact[p];
    s->nl_contact[p] = 1;
    o->F[0] = f * nx;
    o->F[1] = f * ny;
    o->G[0] = fd * nx;
    o->G[1] = fd * ny;
    if (tl != TL_none) { /* t = (n_y, -n_x), g_t = g.t, no rotation (kernels.c) */
        const double tx = ny, ty = -nx;
        double g_t = (s->vx[j] - s->vx[i]) * tx + (s->vy[j] - s->vy[i]) * ty;
        /* rotation: the contact point divides |r_ij| as r_i : r_j (midway for equal
         * radii, as kernels.c), so the arms a_i + a_j = |r_ij| make the spin torques
         * a_i f_t, a_j f_t cancel the pair's orbital torque (angular momentum kept) */
        double ai, aj;
        contact_arms(s, i, j, dist, &ai, &aj);
        if (u.rot) {
            g_t += ai * s->omega[i] + aj * s->omega[j];
        }
        double slot = hist ? s->nl_hist[p] : 0.0;
        const gr_tangential_in in = {.g_t = g_t,
                                     .f_n = f,
                                     .xi = gr_pair_d(s, i, j) - dist,
                                     .g_n = g_n,
                                     .acts = !clamp || f > 0.0,
                                     .m12_dt = c->m_t * u.inv_dt,
                                     .hist = hist ? &slot : NULL};
        const gr_tangential_force ft = tangential_law(tl, c, in);
        o->F[0] += ft.f * tx;
        o->F[1] += ft.f * ty;
        w->ui[2] = ai * ft.f;
        w->uj[2] = aj * ft.f;
        if (hist) { /* the spring's -k_t s is conservative: G, tg and the rate get the rest */
            const double nc = ft.f - ft.fc;
            s->nl_hist[p] = slot;
            t->el_t += ft.e;
            t->lost += ft.lost;
            o->G[0] += nc * tx;
            o->G[1] += nc * ty;
            t->pt[col] += -nc * g_t;
            w->wi[2] = ai * nc;
            w->wj[2] = aj * nc;
        } else {
            o->G[0] += ft.f * tx;
            o->G[1] += ft.f * ty;
            t->pt[col] += ft.p;
            w->wi[2] = w->wj[2] = 0.0; /* unread (no history): set for the compiler's sake */
        }
    }
    if (rl != RL_none) { /* rolling resistance (rotation only): a couple, no force */
        const double ri = s->rad[i], rj = s->rad[j];
        const double Ii = s->inertia_i[i], Ij = s->inertia_i[j];
        /* R_ij = r_i r_j / (r_i + r_j); the limit that stops w_i - w_j within a step, which
         * the couple changes by -M dt (1 / I_i + 1 / I_j): the reduced inertia over dt */
        const gr_rolling_in rin = {.dw = s->omega[i] - s->omega[j],
                                   .f_n = f,
                                   .acts = !clamp || f > 0.0,
                                   .r_eff = ri * rj / (ri + rj),
                                   .i_2dt = Ii * Ij / (Ii + Ij) * u.inv_dt};
        const gr_rolling_torque rt = rolling_law(rl, c, rin);
        w->R[2] = rt.m;
        t->pt[1] += rt.p;
    } else {
        w->R[2] = 0.0; /* unread without a rolling law */
    }
    tally(t, s, i, j, el, pw, dist);
    return 1;
}

/* 3D (spheres, species lists): the pair geometry of kernels_3d.c with the pair's own contact
 * distance and coefficients. The contact point divides |r_ij| as r_i : r_j (arms a_i, a_j), so
 * the tangential relative velocity there is g_c = g - g_n n + n x (a_i w_i + a_j w_j); a law
 * without history acts along g_c with its scalar code at |g_c|, and the force F_t on j (-F_t on
 * i) turns i by -a_i n x F_t and j by -a_j n x F_t, which the pair's orbital torque
 * |r_ij| n x F_t cancels (angular momentum kept). */
/* 3D: the contact point's tangential relative velocity g_c = g - g_n n + n x (a_i w_i + a_j w_j)
 * (g = v_j - v_i, the arms a_i + a_j = |r_ij|), rotation or not. */
static void contact_velocity_3d(const gr_sim *s, int i, int j, const double nv[3],
                                const double gv[3], double g_n, double ai, double aj, double gc[3])
{
    for (int a = 0; a < 3; a++) {
        gc[a] = gv[a] - g_n * nv[a];
    }
    if (s->omega) {
        const double W[3] = {ai * s->wx[i] + aj * s->wx[j], ai * s->wy[i] + aj * s->wy[j],
                             ai * s->omega[i] + aj * s->omega[j]};
        gc[0] += nv[1] * W[2] - nv[2] * W[1];
        gc[1] += nv[2] * W[0] - nv[0] * W[2];
        gc[2] += nv[0] * W[1] - nv[1] * W[0];
    }
}

/* 3D: a history law's contact (i, j) that ended (e: r_j - r_i now): the law forgets the vector and
 * returns the energy it held plus the work its last force did (J), as kernels_3d.c's forget_3d
 * with each grain's own arm. */
static double poly_forget_3d(const gr_sim *s, int i, int j, const double e[3], double dist,
                             double *h)
{
    const gr_contact_coeffs *c =
        s->cc_pair ? &s->cc_pair[s->species[i] * s->nsp + s->species[j]] : &s->cc;
    const double nv[3] = {e[0] / dist, e[1] / dist, e[2] / dist};
    const double gv[3] = {s->vx[j] - s->vx[i], s->vy[j] - s->vy[i], s->vz[j] - s->vz[i]};
    const double g_n = gv[0] * nv[0] + gv[1] * nv[1] + gv[2] * nv[2];
    double ai, aj, gc[3];
    contact_arms(s, i, j, dist, &ai, &aj);
    contact_velocity_3d(s, i, j, nv, gv, g_n, ai, aj, gc);
    gr_to_plane(h, nv);
    const gr_tangential_in3 in = {.g = {gc[0], gc[1], gc[2]},
                                  .xi = gr_pair_d(s, i, j) - dist,
                                  .g_n = g_n,
                                  .acts = 0,
                                  .hist = h};
    return tangential3_law(s->kernel.tl, c, in).lost;
}

/* 3D rolling resistance of the touching pair (i, j) (kernels_3d.c's rolling with each sphere's
 * own size): against the relative spin about axes in the tangent plane, dw_perp = (w_i - w_j) -
 * ((w_i - w_j).n) n, the scalar law at |dw_perp| with the pair's R_ij = r_i r_j / (r_i + r_j) and
 * reduced inertia I_i I_j / (I_i + I_j) (as poly_2d), the couple +M along dw_perp on j, -M on i
 * (all of it non-conservative), its loss booked as friction. */
static void roll_3d(const gr_sim *s, const gr_contact_coeffs *c, int i, int j, const double nv[3],
                    double fn, int acts, double inv_dt, poly_spin *w, poly_sums *t)
{
    const double dw[3] = {s->wx[i] - s->wx[j], s->wy[i] - s->wy[j], s->omega[i] - s->omega[j]};
    const double dn = dw[0] * nv[0] + dw[1] * nv[1] + dw[2] * nv[2];
    const double dp[3] = {dw[0] - dn * nv[0], dw[1] - dn * nv[1], dw[2] - dn * nv[2]};
    const double m = sqrt(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2]);
    const double ri = s->rad[i], rj = s->rad[j], Ii = s->inertia_i[i], Ij = s->inertia_i[j];
    const gr_rolling_in rin = {.dw = m,
                               .f_n = fn,
                               .acts = acts,
                               .r_eff = ri * rj / (ri + rj),
                               .i_2dt = Ii * Ij / (Ii + Ij) * inv_dt};
    const gr_rolling_torque rt = rolling_law(s->kernel.rl, c, rin);
    const double along = m > 0.0 ? rt.m / m : 0.0;
    for (int a = 0; a < 3; a++) {
        w->R[a] = along * dp[a];
    }
    t->pt[1] += rt.p;
}

/* 3D: entry p, the pair (i, j); as poly_rec_2d. */
static inline __attribute__((always_inline)) int poly_rec_3d(gr_sim *s, const poly_run u,
                                                             const int i, const int j, const int p,
                                                             poly_rec *o, poly_spin *w,
                                                             poly_sums *t)
{
    double *v[3] = {s->vx, s->vy, s->vz}, *q[3] = {s->x, s->y, s->z};
    const int rot = u.rot, tl = u.tl, clamp = u.clamp, rl = u.rl, col = u.col;
    const int hist = u.hist; /* the spring's vector, 3 doubles per list entry */
    const double inv_dt = u.inv_dt;
    double e[3];
    for (int a = 0; a < 3; a++) {
        e[a] = wrap_delta(q[a][j] - q[a][i], s->period[a]);
    }
    const double dist = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    double *h = hist ? s->nl_hist + 3 * (int64_t)p : NULL;
    const int held = hist && (h[0] != 0.0 || h[1] != 0.0 || h[2] != 0.0);
    if (dist >= gr_pair_d(s, i, j)) {
        s->nl_contact[p] = 0;
        if (held) { /* the contact ended: its spring goes */
            t->lost += poly_forget_3d(s, i, j, e, dist, h);
        }
        return 0;
    }
    double nv[3], gv[3], g_n = 0.0;
    for (int a = 0; a < 3; a++) {
        nv[a] = e[a] / dist;
        gv[a] = v[a][j] - v[a][i];
        g_n += gv[a] * nv[a];
    }
    double fn, fd, el, pw;
    gr_contact_coeffs tmp;
    const gr_contact_coeffs *c;
    if (!poly_contact(s, i, j, dist, g_n, &fn, &fd, &el, &pw, &tmp, &c)) {
        s->nl_contact[p] = 0;
        if (held) {
            t->lost += poly_forget_3d(s, i, j, e, dist, h);
        }
        return 0;
    }
    t->fresh += !s->nl_contact[p];
    s->nl_contact[p] = 1;
    for (int a = 0; a < 3; a++) {
        o->F[a] = fn * nv[a];
        o->G[a] = fd * nv[a];
    }
    if (tl != TL_none) {
        double ai, aj, gc[3];
        contact_arms(s, i, j, dist, &ai, &aj);
        contact_velocity_3d(s, i, j, nv, gv, g_n, ai, aj, gc);
        double Ft[3], Fn[3]; /* the tangential force on j and its non-conservative part */
        if (hist) {          /* the vector law with the pair's k_t, the vector kept in the plane */
            double sv[3] = {h[0], h[1], h[2]};
            gr_to_plane(sv, nv);
            const gr_tangential_in3 in = {.g = {gc[0], gc[1], gc[2]},
                                          .f_n = fn,
                                          .xi = gr_pair_d(s, i, j) - dist,
                                          .g_n = g_n,
                                          .acts = !clamp || fn > 0.0,
                                          .hist = sv};
            const gr_tangential_force3 ft = tangential3_law(tl, c, in);
            for (int a = 0; a < 3; a++) {
                Ft[a] = ft.f[a];
                Fn[a] = ft.f[a] - ft.fc[a];
                h[a] = sv[a];
            }
            t->el_t += ft.e;
            t->lost += ft.lost;
            t->pt[col] += -(Fn[0] * gc[0] + Fn[1] * gc[1] + Fn[2] * gc[2]);
        } else { /* a law without history acts along g_c: its scalar law at |g_c| */
            const double gm = sqrt(gc[0] * gc[0] + gc[1] * gc[1] + gc[2] * gc[2]);
            const gr_tangential_in in = {.g_t = gm,
                                         .f_n = fn,
                                         .xi = gr_pair_d(s, i, j) - dist,
                                         .g_n = g_n,
                                         .acts = !clamp || fn > 0.0,
                                         .m12_dt = c->m_t * inv_dt};
            const gr_tangential_force ft = tangential_law(tl, c, in);
            const double along = gm > 0.0 ? ft.f / gm : 0.0;
            for (int a = 0; a < 3; a++) {
                Ft[a] = Fn[a] = along * gc[a];
            }
            t->pt[col] += ft.p;
        }
        for (int a = 0; a < 3; a++) {
            o->F[a] += Ft[a];
            o->G[a] += Fn[a];
        }
        if (rot) { /* -a n x F_t on each (and its non-conservative part, history laws) */
            const double nf[3] = {nv[1] * Ft[2] - nv[2] * Ft[1], nv[2] * Ft[0] - nv[0] * Ft[2],
                                  nv[0] * Ft[1] - nv[1] * Ft[0]};
            const double nc[3] = {nv[1] * Fn[2] - nv[2] * Fn[1], nv[2] * Fn[0] - nv[0] * Fn[2],
                                  nv[0] * Fn[1] - nv[1] * Fn[0]};
            for (int a = 0; a < 3; a++) { /* x - y is x + (-y), bit for bit */
                w->ui[a] = -(ai * nf[a]);
                w->uj[a] = -(aj * nf[a]);
                w->wi[a] = -(ai * nc[a]);
                w->wj[a] = -(aj * nc[a]);
            }
        }
    }
    if (rl != RL_none) { /* rolling resistance (rotation only): a couple, no force */
        roll_3d(s, c, i, j, nv, fn, !clamp || fn > 0.0, inv_dt, w, t);
    }
    tally(t, s, i, j, el, pw, dist);
    return 1;
}

/* Adds entry k's pair (o) to grain x, its i (is_i) or its j, in the order the one-pass loop did
 * (dim a constant of the call): f and g; with rotation the tangential torques, then their
 * non-conservative parts (history laws), then the rolling couple on tq and (roll_tg) on tg. */
static inline __attribute__((always_inline)) void apply_end(gr_sim *restrict s, const int dim,
                                                            const poly_run u,
                                                            const poly_rec *restrict o,
                                                            const poly_spin *restrict w,
                                                            const int x, const int is_i)
{
    double *f[3] = {s->fx, s->fy, s->fz}, *g[3] = {s->gx, s->gy, s->gz};
    for (int a = 0; a < dim; a++) {
        f[a][x] += is_i ? -o->F[a] : o->F[a];
        g[a][x] += is_i ? -o->G[a] : o->G[a];
    }
    if (!u.rot) {
        return;
    }
    double *tq[3] = {s->tqx, s->tqy, s->tq}, *tg[3] = {s->tgx, s->tgy, s->tg};
    for (int a = dim == 3 ? 0 : 2; a < 3; a++) { /* 2D: the torques about z (component 2) */
        if (u.tl != TL_none) {
            tq[a][x] += is_i ? w->ui[a] : w->uj[a];
            if (u.keep_tg) {
                tg[a][x] += is_i ? w->wi[a] : w->wj[a];
            }
        }
        if (u.rl != RL_none) {
            tq[a][x] += is_i ? -w->R[a] : w->R[a];
            if (u.roll_tg) {
                tg[a][x] += is_i ? -w->R[a] : w->R[a];
            }
        }
    }
}

/* The kernel's state (allocated on first use, freed with the sim): the sums of each block of rows
 * and, for more than one thread, the records of each block's touching pairs, in entry order from
 * the block's first entry on, and their number per block. */
typedef struct gr_poly_par {
    poly_rec *rec;
    poly_spin *spin; /* rotation only */
    int *count;
    int64_t rec_cap;
    poly_sums *sums;
} gr_poly_par;

void gr_poly_par_free(gr_sim *s)
{
    if (s->poly_par) {
        free(s->poly_par->rec);
        free(s->poly_par->spin);
        free(s->poly_par->count);
        free(s->poly_par->sums);
        free(s->poly_par);
        s->poly_par = NULL;
    }
}

/* The rows the kernel walks: the sublist's when on (entry k is list entry sl_p[k]), else the
 * list's. */
static inline int entry_p(const gr_sim *s, const int k) { return s->sl_on ? s->sl_p[k] : k; }

/* Ready the state: the block sums and (threads) room for a record per entry. Returns 0 when an
 * allocation failed (the caller then runs on one thread, or in one block without the state). */
static int par_ready(gr_sim *s, const int threads)
{
    gr_poly_par *pp = s->poly_par;
    if (!pp) {
        pp = s->poly_par = calloc(1, sizeof *pp);
        if (pp) {
            pp->sums = malloc(sizeof(poly_sums) * (size_t)s->nblk);
            pp->count = malloc(sizeof(int) * (size_t)s->nblk);
        }
        if (!pp || !pp->sums || !pp->count) {
            gr_poly_par_free(s);
            return 0;
        }
    }
    const int64_t E = (s->sl_on ? s->sl_start : s->nl_start)[s->n];
    if (threads && E > pp->rec_cap) {
        const int64_t cap = E + E / 4 + 1024; /* room to grow */
        free(pp->rec);
        free(pp->spin);
        pp->rec = malloc(sizeof(poly_rec) * (size_t)cap);
        pp->spin = s->omega ? malloc(sizeof(poly_spin) * (size_t)cap) : NULL;
        pp->rec_cap = pp->rec && (pp->spin || !s->omega) ? cap : 0;
    }
    return !threads || pp->rec_cap >= E;
}

/* The pairs of rows [r0, r1) into *out; each touching pair applied at once to both grains (one
 * thread: `now`) or recorded, from rec on, for the threads' second phase. Returns the number
 * recorded. */
static inline __attribute__((always_inline)) int rows_block(gr_sim *restrict s, const int dim,
                                                            const poly_run u, const int r0,
                                                            const int r1, const int now,
                                                            poly_rec *rec, poly_spin *spin,
                                                            poly_sums *out)
{
    const int *rows = s->sl_on ? s->sl_start : s->nl_start;
    poly_sums sums = {.wi = -1, .wj = -1}, *t = &sums; /* a local: kept in registers */
    int m = 0;
    for (int i = r0; i < r1; i++) {
        for (int k = rows[i]; k < rows[i + 1]; k++) {
            const int p = entry_p(s, k), j = s->nl_j[p];
            poly_rec local; /* a touching pair sets every field apply_end reads */
            poly_spin local_w;
            poly_rec *o = now ? &local : &rec[m];
            poly_spin *w = now || !u.rot ? &local_w : &spin[m];
            if (!(dim == 2 ? poly_rec_2d(s, u, i, j, p, o, w, t)
                           : poly_rec_3d(s, u, i, j, p, o, w, t))) {
                continue;
            }
            if (now) {
                apply_end(s, dim, u, o, w, j, 0);
                apply_end(s, dim, u, o, w, i, 1);
            } else {
                o->i = i;
                o->j = j;
                m++;
            }
        }
    }
    *out = sums;
    return m;
}

/* Zero the forces and torques of grains [lo, hi) (every array the run has). */
static void zero_range(gr_sim *s, const int lo, const int hi)
{
    double *const arr[12] = {s->fx, s->fy, s->fz,  s->gx,  s->gy,  s->gz,
                             s->tq, s->tg, s->tqx, s->tqy, s->tgx, s->tgy};
    for (int a = 0; a < 12; a++) {
        if (arr[a]) {
            memset(arr[a] + lo, 0, sizeof(double) * (size_t)(hi - lo));
        }
    }
}

/* The evaluation's report from the summed blocks. */
static void report_sums(const poly_sums *t, gr_force_report *r)
{
    *r = report(t->elastic + t->el_t, t->pn, t->fresh, t->worst, t->wi, t->wj);
    r->power_tangential = t->pt[0];
    r->power_friction = t->pt[1];
    r->lost = t->lost;
}

/* 2D or 3D (dim a constant). One thread applies each touching pair at once. T threads: (1) each
 * records the touching pairs of its blocks of rows; (2) each walks all the records in entry order
 * and applies the ends that fall in its own range of grains. Either way each grain receives its
 * pairs in entry order, so every force is the same sequence of additions, and the sums are per
 * block of rows in block order: the result is the same for every thread count. */
static inline __attribute__((always_inline)) void poly_rows(gr_sim *s, const int dim,
                                                            gr_force_report *r)
{
    const int n = s->n, nb = s->nblk;
    const poly_run u = run_of(s);
    int T = gr_team(s);
    if (!par_ready(s, T > 1)) {
        if (!s->poly_par) { /* no room even for the block sums: one block */
            poly_sums t;
            zero_range(s, 0, n);
            rows_block(s, dim, u, 0, n, 1, NULL, NULL, &t);
            report_sums(&t, r);
            return;
        }
        T = 1;
    }
    gr_poly_par *pp = s->poly_par;
    poly_sums *sums = pp->sums;
    const int *rows = s->sl_on ? s->sl_start : s->nl_start;
#ifdef _OPENMP
    if (T > 1) {
#pragma omp parallel num_threads(T)
        {
#pragma omp for schedule(static)
            for (int b = 0; b < nb; b++) {
                const int r0 = b * GR_BLOCK, r1 = r0 + GR_BLOCK < n ? r0 + GR_BLOCK : n;
                pp->count[b] = rows_block(s, dim, u, r0, r1, 0, pp->rec + rows[r0],
                                          u.rot ? pp->spin + rows[r0] : NULL, &sums[b]);
            }
            /* after the barrier: this thread's grains, whole blocks as the first phase shares
             * them */
            const int tid = omp_get_thread_num(), nth = omp_get_num_threads();
            const int b0 = nb * tid / nth, b1 = nb * (tid + 1) / nth;
            const int lo = b0 * GR_BLOCK, hi = b1 * GR_BLOCK < n ? b1 * GR_BLOCK : n;
            zero_range(s, lo, hi);
            for (int b = 0; b < nb; b++) {
                const poly_rec *rec = pp->rec + rows[b * GR_BLOCK];
                const poly_spin *spin = u.rot ? pp->spin + rows[b * GR_BLOCK] : NULL;
                for (int q = 0; q < pp->count[b]; q++) {
                    const poly_rec *o = &rec[q];
                    const poly_spin *w = u.rot ? &spin[q] : NULL;
                    if (o->j >= lo && o->j < hi) {
                        apply_end(s, dim, u, o, w, o->j, 0);
                    }
                    if (o->i >= lo && o->i < hi) {
                        apply_end(s, dim, u, o, w, o->i, 1);
                    }
                }
            }
        }
    } else
#endif
    {
        zero_range(s, 0, n);
        for (int b = 0; b < nb; b++) {
            const int r0 = b * GR_BLOCK, r1 = r0 + GR_BLOCK < n ? r0 + GR_BLOCK : n;
            rows_block(s, dim, u, r0, r1, 1, NULL, NULL, &sums[b]);
        }
    }
    poly_sums t = {.wi = -1, .wj = -1};
    for (int b = 0; b < nb; b++) {
        const poly_sums *q = &sums[b];
        t.elastic += q->elastic;
        t.pn += q->pn;
        t.pt[0] += q->pt[0];
        t.pt[1] += q->pt[1];
        t.el_t += q->el_t;
        t.lost += q->lost;
        t.fresh += q->fresh;
        if (q->worst > t.worst) { /* the first deepest pair in entry order, as one pass */
            t.worst = q->worst;
            t.wi = q->wi;
            t.wj = q->wj;
        }
    }
    report_sums(&t, r);
}

static void poly_2d(gr_sim *s, gr_force_report *r) { poly_rows(s, 2, r); }

static void poly_3d(gr_sim *s, gr_force_report *r) { poly_rows(s, 3, r); }

void gr_kernel_run_poly(gr_sim *s, gr_force_report *r)
{
    if (s->dim == 1) {
        poly_1d(s, r);
    } else if (s->dim == 2) {
        poly_2d(s, r);
    } else {
        poly_3d(s, r);
    }
}
