/* profile: profiles along one axis (issue 36; docs/analysis-profiles.md), the observable of beds
 * under gravity, vibrated beds and anything with walls: per slab of the box, the number density,
 * the packing fraction, the mean velocity and the granular temperature of each velocity
 * component, time-averaged over the sampled frames.
 *
 * The axis (profile_axis: 0 = x, 1 = y, 2 = z (3D); -1, the default, is the last one: z in 3D, y
 * in 2D, x in 1D) is
 * cut into profile_bins slabs of width dz = L / bins. A particle counts in the slab of its centre
 * (1D positions are wrapped into [0, L) first along a periodic axis; along a wall axis a
 * centre below 0, on a floor vibrating below 0, counts in the first slab), so near a wall, where
 * centres stay at least r away, the first slab's density is lower than the grains' (centre-counted, not area-weighted).
 * Per slab, over all frames F:
 *     n(z)     = <c> / (dz L^(dim-1))                       number density (m^-3 in 3D, m^-2 in 2D,
 *                                                           m^-1 in 1D)
 *     phi(z)   = n(z) (4/3) pi r^3 (3D), n(z) pi r^2 (2D), n(z) 2 r (1D)
 *                                                           packing fraction of the centres
 *     u_a(z)   = <S1_a> / <c>                                mean velocity, component a
 *     T_a(z)   = <S2_a> / <c> - u_a(z)^2                     temperature of component a (m^2/s^2)
 * with c, S1_a = sum v_a and S2_a = sum v_a^2 the frame's sums over the slab's particles and <.>
 * the mean over frames (a slab's T is thus weighted by its occupancy, frame by frame). Errors are
 * block-averaging errors of the per-frame c and S2_a (blocking.c, as T's); T's error combines the
 * two as if independent, which overstates it where they are positively correlated.
 *
 * A mixture (docs/mixtures.md: [species] lists or a radius distribution; the frames carry each
 * grain's radius r_i and mass m_i) uses each grain's own radius and mass: per slab the frame's
 * sums c, A = sum of the grains' areas (pi r_i^2 in 2D, (4/3) pi r_i^3 in 3D, 2 r_i in 1D),
 * M = sum m_i, P_a = sum m_i v_a and K_a = sum m_i v_a^2 give
 *     phi(z)   = <A> / (dz L^(dim-1))                       packing fraction from the actual radii
 *     u_a(z)   = <P_a> / <M>                                 mean (centre-of-mass) velocity
 *     T_a(z)   = (<K_a> - <P_a>^2 / <M>) / <c>               temperature of component a (J, k_B = 1)
 * (T_a in J, as the species observable's T_s: for one mass m it is m times the m^2/s^2 above).
 * The same columns follow for each species of [species] lists (suffix _1, _2, ...: the species'
 * own grains), so n and phi of the species sum to the total's. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/obs_util.h"
#include "granule/analysis.h"
#include "granule/sim.h"

typedef struct profile_params {
    int profile_axis;
    int profile_bins;
} profile_params;

static const gr_param params[] = {
    {"profile_axis", "", GR_PARAM_INT, -1, -1, 2, false, false,
     "axis of the profiles: 0 = x, 1 = y (2D, 3D), 2 = z (3D); -1 = the last axis (z in 3D, y in "
     "2D, x in 1D)",
     offsetof(profile_params, profile_axis)},
    {"profile_bins", "", GR_PARAM_INT, 40, 1, 100000, false, false,
     "slabs of equal width L / profile_bins along the axis",
     offsetof(profile_params, profile_bins)},
};

/* per slab: count, then S1 and S2 of each component (z's last, in 3D only: 1D and 2D keep N_Q_2D
 * accumulators per slab) */
enum { Q_COUNT, Q_S1X, Q_S1Y, Q_S2X, Q_S2Y, N_Q_2D, Q_S1Z = N_Q_2D, Q_S2Z, N_Q };

typedef struct profile {
    int n, dim, axis, bins;
    int nq, nc; /* accumulators per slab (N_Q_2D or N_Q), velocity components kept (2 or 3) */
    bool wall;  /* walls along the axis: clamp into the end slabs instead of wrapping */
    double L, radius, dz, slab; /* slab: dz L^(dim-1), the slab's area (2D) or length (1D) */
    int64_t frames;
    double *c, *s1, *s2; /* this frame's sums per slab: c[b], s1/s2[nc b + a] */
    gr_blocking *b;      /* nq per slab: b[nq bin + q] */
    gr_blocking height;  /* the mean position along the axis, per frame */
    /* a mixture (setup->sizes; 0 groups without): per slab, groups of nm sums (group 0 all grains,
     * 1 + s species s), M_COUNT ... M_K + nc - 1 */
    int groups, nm;
    double *ms;      /* this frame's sums: ms[nm (groups k + g) + q] */
    gr_blocking *mb; /* their time averages, the same layout */
    gr_blocking *hs; /* species lists: hs[1 + s] species s's mean position along the axis */
} profile;

/* a mixture's sums per slab and group: count, area, mass, then nc momenta and nc m v^2 */
enum { M_COUNT, M_AREA, M_MASS, M_P };

/* a grain's area (2D), volume (3D) or length (1D) */
static double measure(int dim, double r)
{
    return dim == 3 ? (4.0 / 3.0) * M_PI * r * r * r : dim == 2 ? M_PI * r * r : 2.0 * r;
}

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    profile *s = state;
    const profile_params *pp = params_block;
    s->n = setup->N;
    s->dim = setup->dim;
    s->L = setup->L;
    s->radius = setup->radius;
    s->axis = pp->profile_axis < 0 ? setup->dim - 1 : pp->profile_axis;
    if (s->axis >= setup->dim) {
        static const char *const name[3] = {"x", "y", "z"};
        static const char *const allowed[3] = {"0 (x)", "0 (x), 1 (y)", "0 (x), 1 (y), 2 (z)"};
        const int d = setup->dim >= 1 && setup->dim <= 3 ? setup->dim : 3;
        return GR_FAIL(err, GR_EINVAL,
                       "%s: [analysis] profile_axis: %d (%s) in a %dD system; allowed in %dD: %s "
                       "or -1 (the last axis)",
                       setup->source ? setup->source : "scene", pp->profile_axis,
                       s->axis <= 2 ? name[s->axis] : "no axis", setup->dim, setup->dim,
                       allowed[d - 1]);
    }
    s->wall = setup->walls[s->axis];
    s->bins = pp->profile_bins;
    s->nq = setup->dim == 3 ? N_Q : N_Q_2D;
    s->nc = setup->dim == 3 ? 3 : 2;
    s->dz = s->L / s->bins;
    s->slab = setup->dim == 3 ? s->dz * s->L * s->L : setup->dim == 2 ? s->dz * s->L : s->dz;
    s->c = gr_obs_calloc(s, (size_t)s->bins, sizeof *s->c);
    s->s1 = gr_obs_calloc(s, (size_t)s->nc * (size_t)s->bins, sizeof *s->s1);
    s->s2 = gr_obs_calloc(s, (size_t)s->nc * (size_t)s->bins, sizeof *s->s2);
    s->b = gr_obs_calloc(s, (size_t)s->nq * (size_t)s->bins, sizeof *s->b);
    if (setup->n_species > GR_MAX_SPECIES) {
        return GR_FAIL(err, GR_EINVAL, "profile: %d species; allowed: 2 to %d", setup->n_species,
                       GR_MAX_SPECIES);
    }
    if (setup->sizes) {
        s->groups = 1 + (setup->n_species >= 2 ? setup->n_species : 0);
        s->nm = M_P + 2 * s->nc;
        const size_t nmb = (size_t)s->nm * (size_t)s->groups * (size_t)s->bins;
        s->ms = gr_obs_calloc(s, nmb, sizeof *s->ms);
        s->mb = gr_obs_calloc(s, nmb, sizeof *s->mb);
        s->hs = gr_obs_calloc(s, (size_t)s->groups, sizeof *s->hs);
    }
    int rc = gr_obs_alloc_ok(s, err);
    if (rc) {
        return rc;
    }
    for (int k = 0; k < s->nq * s->bins; k++) {
        gr_blocking_init(&s->b[k]);
    }
    for (int k = 0; k < s->nm * s->groups * s->bins; k++) {
        gr_blocking_init(&s->mb[k]);
    }
    for (int g = 0; g < s->groups; g++) {
        gr_blocking_init(&s->hs[g]);
    }
    gr_blocking_init(&s->height);
    return GR_OK;
}

/* A grain of radius r and mass mi into a group's sums m (M_COUNT ...). */
static void add_grain(double *m, int nc, int dim, double r, double mi, const double *v)
{
    m[M_COUNT] += 1.0;
    m[M_AREA] += measure(dim, r);
    m[M_MASS] += mi;
    for (int a = 0; a < nc; a++) {
        m[M_P + a] += mi * v[a];
        m[M_P + nc + a] += mi * v[a] * v[a];
    }
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    profile *s = state;
    int bad = gr_obs_check_frame("profile", p, s->n, err);
    if (bad) {
        return bad;
    }
    const int nc = s->nc, nm = s->nm;
    bool bad_species = s->groups > 1 && (!p->species || p->n_species != s->groups - 1);
    for (int i = 0; s->groups > 1 && !bad_species && i < p->n; i++) {
        bad_species = p->species[i] < 0 || p->species[i] >= s->groups - 1;
    }
    if (s->groups && (!p->radii || !p->masses || bad_species)) {
        return GR_FAIL(err, GR_EINVAL,
                       "profile: the frames carry no radii, masses or species of the grains; a "
                       "mixture's profile needs the frames of its run (docs/mixtures.md)");
    }
    for (int k = 0; k < s->nm * s->groups * s->bins; k++) {
        s->ms[k] = 0.0;
    }
    for (int k = 0; k < s->bins; k++) {
        s->c[k] = 0.0;
        for (int a = 0; a < nc; a++) {
            s->s1[nc * k + a] = s->s2[nc * k + a] = 0.0;
        }
    }
    const double *z = s->axis == 0 ? p->x : s->axis == 1 ? p->y : p->z;
    double zsum = 0.0, zs[GR_MAX_SPECIES] = {0}, cs[GR_MAX_SPECIES] = {0};
    for (int i = 0; i < p->n; i++) {
        double zi = z[i];
        if (!s->wall) { /* periodic: 1D positions are unwrapped */
            zi = fmod(zi, s->L);
            zi += zi < 0.0 ? s->L : 0.0;
        }
        zsum += zi;
        int k = (int)(zi / s->dz);
        k = k < 0 ? 0 : (k >= s->bins ? s->bins - 1 : k);
        const double v[3] = {p->vx[i], p->dim >= 2 ? p->vy[i] : 0.0, p->dim == 3 ? p->vz[i] : 0.0};
        s->c[k] += 1.0;
        for (int a = 0; a < nc; a++) {
            s->s1[nc * k + a] += v[a];
            s->s2[nc * k + a] += v[a] * v[a];
        }
        if (s->groups) { /* a mixture: all grains, then the grain's species */
            double *m = s->ms + (size_t)nm * s->groups * k;
            add_grain(m, nc, p->dim, p->radii[i], p->masses[i], v);
            if (s->groups > 1) {
                add_grain(m + (size_t)nm * (1 + p->species[i]), nc, p->dim, p->radii[i],
                          p->masses[i], v);
                zs[p->species[i]] += zi;
                cs[p->species[i]] += 1.0;
            }
        }
    }
    for (int k = 0; k < s->nm * s->groups * s->bins; k++) {
        gr_blocking_add(&s->mb[k], s->ms[k]);
    }
    for (int k = 0; k < s->bins; k++) {
        gr_blocking *b = s->b + (size_t)s->nq * k;
        gr_blocking_add(&b[Q_COUNT], s->c[k]);
        gr_blocking_add(&b[Q_S1X], s->s1[nc * k]);
        gr_blocking_add(&b[Q_S1Y], s->s1[nc * k + 1]);
        gr_blocking_add(&b[Q_S2X], s->s2[nc * k]);
        gr_blocking_add(&b[Q_S2Y], s->s2[nc * k + 1]);
        if (nc == 3) {
            gr_blocking_add(&b[Q_S1Z], s->s1[nc * k + 2]);
            gr_blocking_add(&b[Q_S2Z], s->s2[nc * k + 2]);
        }
    }
    gr_blocking_add(&s->height, zsum / p->n);
    for (int g = 1; g < s->groups; g++) {
        if (cs[g - 1] > 0.0) {
            gr_blocking_add(&s->hs[g], zs[g - 1] / cs[g - 1]);
        }
    }
    s->frames++;
    return GR_OK;
}

/* The slab's numbers: density, its error, mean velocity and temperature (with error) of a. */
typedef struct slab {
    double n, n_err, phi, phi_err, u[3], T[3], T_err[3];
} slab;

static double packing(const profile *s, double n);

static slab slab_of(const profile *s, int k)
{
    const gr_blocking *b = s->b + (size_t)s->nq * k;
    const double c = gr_blocking_mean(&b[Q_COUNT]), c_err = gr_obs_stderr(&b[Q_COUNT]);
    slab o = {.n = c / s->slab, .n_err = c_err / s->slab};
    o.phi = packing(s, o.n);
    o.phi_err = packing(s, o.n_err);
    static const int q1[3] = {Q_S1X, Q_S1Y, Q_S1Z}, q2[3] = {Q_S2X, Q_S2Y, Q_S2Z};
    for (int a = 0; a < s->nc; a++) {
        if (c > 0.0) {
            const double s2 = gr_blocking_mean(&b[q2[a]]), s2_err = gr_obs_stderr(&b[q2[a]]);
            o.u[a] = gr_blocking_mean(&b[q1[a]]) / c;
            o.T[a] = s2 / c - o.u[a] * o.u[a];
            o.T_err[a] = hypot(s2_err / c, s2 * c_err / (c * c));
        } else {
            o.u[a] = o.T[a] = o.T_err[a] = (double)NAN;
        }
    }
    return o;
}

/* A mixture's slab k, group g (0: all grains, 1 + s: species s): T from each grain's own mass. */
static slab mix_slab_of(const profile *s, int k, int g)
{
    const gr_blocking *b = s->mb + (size_t)s->nm * ((size_t)s->groups * k + g);
    const double c = gr_blocking_mean(&b[M_COUNT]), c_err = gr_obs_stderr(&b[M_COUNT]);
    const double M = gr_blocking_mean(&b[M_MASS]);
    slab o = {.n = c / s->slab,
              .n_err = c_err / s->slab,
              .phi = gr_blocking_mean(&b[M_AREA]) / s->slab,
              .phi_err = gr_obs_stderr(&b[M_AREA]) / s->slab};
    for (int a = 0; a < s->nc; a++) {
        if (c > 0.0 && M > 0.0) {
            const double P = gr_blocking_mean(&b[M_P + a]);
            const double K = gr_blocking_mean(&b[M_P + s->nc + a]),
                         K_err = gr_obs_stderr(&b[M_P + s->nc + a]);
            o.u[a] = P / M;
            o.T[a] = (K - P * P / M) / c;
            o.T_err[a] = hypot(K_err / c, K * c_err / (c * c));
        } else {
            o.u[a] = o.T[a] = o.T_err[a] = (double)NAN;
        }
    }
    return o;
}

static double packing(const profile *s, double n)
{
    return s->dim == 3   ? n * (4.0 / 3.0) * M_PI * s->radius * s->radius * s->radius
           : s->dim == 2 ? n * M_PI * s->radius * s->radius
                         : n * 2.0 * s->radius;
}

/* A slab's columns after z (one group of a mixture). */
static void slab_row(FILE *f, const profile *s, const slab *o)
{
    fprintf(f, ",%.8g,%.4g,%.8g,%.4g,%.8g,%.8g,%.8g,%.4g,%.8g,%.4g", o->n, o->n_err, o->phi,
            o->phi_err, o->u[0], o->u[1], o->T[0], o->T_err[0], o->T[1], o->T_err[1]);
    if (s->dim == 3) {
        fprintf(f, ",%.8g,%.8g,%.4g", o->u[2], o->T[2], o->T_err[2]);
    }
}

static void rows(FILE *f, const void *ctx)
{
    const profile *s = ctx;
    for (int k = 0; k < s->bins; k++) {
        fprintf(f, "%.10g", (k + 0.5) * s->dz);
        if (s->groups == 0) {
            const slab o = slab_of(s, k);
            slab_row(f, s, &o);
        }
        for (int g = 0; g < s->groups; g++) {
            const slab o = mix_slab_of(s, k, g);
            slab_row(f, s, &o);
        }
        fputc('\n', f);
    }
}

/* The column names of one group (suffix "" or "_s"), appended to buf. */
static void group_columns(char *buf, size_t cap, int dim, const char *sfx)
{
    const char *n = dim == 3 ? "m-3" : dim == 2 ? "m-2" : "m-1";
    size_t at = strlen(buf);
    snprintf(buf + at, cap - at,
             ",n%s [%s],n%s_err [%s],phi%s [],phi%s_err [],u_x%s [m s-1],u_y%s [m s-1],"
             "T_x%s [J],T_x%s_err [J],T_y%s [J],T_y%s_err [J]",
             sfx, n, sfx, n, sfx, sfx, sfx, sfx, sfx, sfx, sfx, sfx);
    if (dim == 3) {
        at = strlen(buf);
        snprintf(buf + at, cap - at, ",u_z%s [m s-1],T_z%s [J],T_z%s_err [J]", sfx, sfx, sfx);
    }
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    profile *s = state;
    const char axis = "xyz"[s->axis];
    cJSON *j = gr_obs_summary(out, "profile", "profile.csv");
    char ax[2] = {axis, 0};
    cJSON_AddStringToObject(j, "axis", ax);
    cJSON_AddNumberToObject(j, "bins", s->bins);
    cJSON_AddNumberToObject(j, "slab_width", s->dz);
    cJSON_AddNumberToObject(j, "frames", (double)s->frames);
    gr_obs_add_number(j, "mean_position", gr_blocking_mean(&s->height));
    gr_obs_add_number(j, "mean_position_error", gr_obs_stderr(&s->height));
    double top = 0.0;
    for (int k = 0; k < s->bins; k++) {
        top = fmax(top, s->groups ? mix_slab_of(s, k, 0).phi : packing(s, slab_of(s, k).n));
    }
    gr_obs_add_number(j, "max_packing_fraction", s->frames ? top : (double)NAN);
    if (s->groups) {
        cJSON_AddNumberToObject(j, "species", s->groups - 1);
    }
    if (s->groups > 1) { /* each species' mean position: segregation along the axis */
        cJSON *jp = cJSON_AddArrayToObject(j, "species_mean_position");
        cJSON *je = cJSON_AddArrayToObject(j, "species_mean_position_error");
        for (int g = 1; g < s->groups; g++) {
            const double h = gr_blocking_mean(&s->hs[g]), e = gr_obs_stderr(&s->hs[g]);
            cJSON_AddItemToArray(jp, isfinite(h) ? cJSON_CreateNumber(h) : cJSON_CreateNull());
            cJSON_AddItemToArray(je, isfinite(e) ? cJSON_CreateNumber(e) : cJSON_CreateNull());
        }
    }
    cJSON_AddStringToObject(
        j, "note",
        s->groups ? "centre-counted slabs of a mixture: phi from each grain's own radius, u_a = "
                    "<sum m v_a>/<sum m>, T_a = (<sum m v_a^2> - <sum m v_a>^2/<sum m>)/<c> per "
                    "slab (J, one component); columns _s: species s alone; errors: block "
                    "averaging over frames"
                  : "centre-counted slabs; T_a = <sum v_a^2>/<c> - u_a^2 per slab (m^2/s^2, "
                    "one component); errors: block averaging over frames");
    char plot[2400];
    snprintf(plot, sizeof plot,
             "set multiplot layout 1,2\nset xlabel '%c (m)'\n"
             "set ylabel 'packing fraction'\nplot 'profile.csv' using 1:4:5 with yerrorbars pt 7 "
             "ps 0.5 title 'phi (%s)'\nset ylabel 'T per component (%s)'\n"
             "plot 'profile.csv' using 1:8:9 with yerrorbars pt 7 ps 0.5 title 'T_x'%s\n"
             "unset multiplot",
             axis, s->groups ? "actual radii" : "centres", s->groups ? "J" : "m^2/s^2",
             s->dim == 3   ? ", '' using 1:10:11 with yerrorbars pt 5 ps 0.5 title 'T_y', '' using "
                             "1:13:14 with yerrorbars pt 9 ps 0.5 title 'T_z'"
             : s->dim == 2 ? ", '' using 1:10:11 with yerrorbars pt 5 ps 0.5 title 'T_y'"
                           : "");
    if (s->groups > 1) { /* a mixture of species: phi and T_x of each species, with the total's */
        const int gc = s->dim == 3 ? 13 : 10; /* a group's columns */
        int at = snprintf(plot, sizeof plot,
                          "set multiplot layout 1,2\nset xlabel '%c (m)'\nset ylabel 'packing "
                          "fraction'\nplot 'profile.csv' using 1:4 with linespoints pt 7 ps 0.5 "
                          "title 'phi (all)'",
                          axis);
        for (int g = 1; g < s->groups; g++) {
            at += snprintf(plot + at, sizeof plot - (size_t)at,
                           ", '' using 1:%d with linespoints pt 7 ps 0.5 title 'phi_%d'",
                           4 + gc * g, g);
        }
        at += snprintf(plot + at, sizeof plot - (size_t)at,
                       "\nset ylabel 'T_x (J)'\nplot 'profile.csv' using 1:8 with linespoints pt "
                       "7 ps 0.5 title 'T_x (all)'");
        for (int g = 1; g < s->groups; g++) {
            at += snprintf(plot + at, sizeof plot - (size_t)at,
                           ", '' using 1:%d:%d with yerrorbars pt 7 ps 0.5 title 'T_x, species %d'",
                           8 + gc * g, 9 + gc * g, g);
        }
        snprintf(plot + at, sizeof plot - (size_t)at, "\nunset multiplot");
    }
    char columns[4096] = "z [m]";
    for (int g = 0; g < s->groups; g++) {
        char sfx[16] = "";
        if (g > 0) {
            snprintf(sfx, sizeof sfx, "_%d", g);
        }
        group_columns(columns, sizeof columns, s->dim, sfx);
    }
    const gr_obs_table t = {
        .name = "profile.csv",
        .what = s->groups
                    ? "profiles along one axis of a mixture: per slab (centre-counted), number "
                      "density, packing fraction from each grain's own radius, centre-of-mass "
                      "velocity and temperature per component from each grain's own mass "
                      "(J), of all grains and then of each species (suffix _s), "
                      "time-averaged over frames, block-averaging errors"
                    : "profiles along one axis: per slab (centre-counted), number density, "
                      "packing fraction, mean velocity and temperature per component, "
                      "time-averaged over frames, block-averaging errors",
        .columns = s->groups     ? columns
                   : s->dim == 3 ? "z [m],n [m-3],n_err [m-3],phi [],phi_err [],u_x [m s-1],"
                                   "u_y [m s-1],T_x [m2 s-2],T_x_err [m2 s-2],T_y [m2 s-2],"
                                   "T_y_err [m2 s-2],u_z [m s-1],T_z [m2 s-2],T_z_err [m2 s-2]"
                   : s->dim == 2 ? "z [m],n [m-2],n_err [m-2],phi [],phi_err [],u_x [m s-1],"
                                   "u_y [m s-1],T_x [m2 s-2],T_x_err [m2 s-2],T_y [m2 s-2],"
                                   "T_y_err [m2 s-2]"
                                 : "z [m],n [m-1],n_err [m-1],phi [],phi_err [],u_x [m s-1],"
                                   "u_y [m s-1],T_x [m2 s-2],T_x_err [m2 s-2],T_y [m2 s-2],"
                                   "T_y_err [m2 s-2]",
        .rows = rows,
        .ctx = s,
        .png = s->frames > 0 ? "profile.png" : NULL,
        .plot = plot,
    };
    return gr_obs_table_write(out, &t, err);
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    profile *s = state;
    gr_blob_io_i64(io, &s->frames);
    gr_obs_io_blockings(io, s->b, s->nq * s->bins);
    gr_obs_io_blockings(io, &s->height, 1);
    if (s->groups) { /* a mixture's sums (one species: the checkpoint as before) */
        gr_obs_io_blockings(io, s->mb, s->nm * s->groups * s->bins);
        gr_obs_io_blockings(io, s->hs, s->groups);
    }
    return GR_OK;
}

const gr_observable_type gr_obs_profile = {
    .name = "profile",
    .summary = "profiles along an axis: density, packing fraction, mean velocity and T per "
               "component per slab (beds, walls, gravity)",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = (int)(sizeof params / sizeof params[0]),
    .params_size = sizeof(profile_params),
    .state_size = sizeof(profile),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
