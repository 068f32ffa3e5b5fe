/* moments: velocity moments <|v|^m>, m = 1 .. moments_max (eq. 3.11; 3.10 for m = 2), averaged
 * over particles and, uniformly in time, over samples, with block-averaging errors. In 2D and 3D
 * |v| is the speed and each component's moments <|v_x|^m> are reported too (pooled over the
 * components). Velocities are taken relative to the mean velocity of the frame, as T of eq. 2.19,
 * so <|v|^2> is T.
 *
 * A mixture of species ([species] lists, docs/mixtures.md) adds the speed moments of each species'
 * grains, relative to the same mean velocity of all grains (so the species' moments weighted by
 * N_s / N are the total's): moments_species.csv and summary.json -> moments.species_speed. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_util.h"
#include "granule/analysis.h"
#include "granule/sim.h"

#define MAX_M 16

typedef struct moments_params {
    int moments_max;
} moments_params;

static const gr_param params[] = {
    {"moments_max", "", GR_PARAM_INT, 12, 1, MAX_M, false, false,
     "highest velocity moment m of <|v|^m> (3.11)", offsetof(moments_params, moments_max)},
};

typedef struct moments {
    int m_max, dim;
    gr_blocking speed[MAX_M + 1];       /* <|v|^m> (1D: |v_x|^m) */
    gr_blocking comp[MAX_M + 1];        /* <|v_x|^m>, <|v_y|^m> (and <|v_z|^m>) pooled (2D, 3D) */
    int ns;                             /* species of a mixture (0: one species) */
    int counted, count[GR_MAX_SPECIES]; /* grains of each species (the first frame's) */
    gr_blocking *sp; /* ns == 0: NULL; else <|v|^m> of species s: sp[(MAX_M + 1) s + m] */
    double ss[GR_MAX_SPECIES * (MAX_M + 1)]; /* this frame's sums of |v|^m per species */
} moments;

/* A grain of species a and speed |v| into the frame's per-species sums (a mixture only). */
static void species_add(moments *m, const gr_particles *p, int i, double speed)
{
    if (m->ns) {
        double ps = 1.0, *s = m->ss + (MAX_M + 1) * p->species[i];
        for (int k = 1; k <= m->m_max; k++) {
            ps *= speed;
            s[k] += ps;
        }
    }
}

/* A mixture's frame carries the scene's species (GR_OK without species). */
static int species_check(const moments *m, const gr_particles *p, gr_error *err)
{
    bool ok = !m->ns || (p->species && p->n_species == m->ns);
    for (int i = 0; ok && m->ns && i < p->n; i++) {
        ok = p->species[i] >= 0 && p->species[i] < m->ns;
    }
    return ok ? GR_OK
              : GR_FAIL(err, GR_EINVAL,
                        "moments: the frames carry %d species, the scene %d ([species]; "
                        "docs/mixtures.md)",
                        p->species ? p->n_species : 0, m->ns);
}

/* The frame's per-species sums into the averages (a mixture only); a species without grains adds
 * nothing. */
static void species_frame(moments *m, const gr_particles *p)
{
    if (!m->ns) {
        return;
    }
    if (!m->counted) {
        for (int i = 0; i < p->n; i++) {
            m->count[p->species[i]]++;
        }
        m->counted = 1;
    }
    for (int a = 0; a < m->ns; a++) {
        for (int k = 1; k <= m->m_max && m->count[a] > 0; k++) {
            gr_blocking_add(&m->sp[(MAX_M + 1) * a + k], m->ss[(MAX_M + 1) * a + k] / m->count[a]);
        }
    }
    for (int k = 0; k < GR_MAX_SPECIES * (MAX_M + 1); k++) {
        m->ss[k] = 0.0;
    }
}

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    (void)err;
    moments *m = state;
    m->m_max = ((const moments_params *)params_block)->moments_max;
    m->dim = setup->dim;
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        m->ns = setup->n_species;
        m->sp = gr_obs_calloc(m, (size_t)(MAX_M + 1) * (size_t)m->ns, sizeof *m->sp);
        int rc = gr_obs_alloc_ok(m, err);
        if (rc) {
            return rc;
        }
        for (int k = 0; k < (MAX_M + 1) * m->ns; k++) {
            gr_blocking_init(&m->sp[k]);
        }
    }
    return GR_OK;
}

/* 3D (spheres): the same moments with three components. */
static void sample_3d(moments *m, const gr_particles *p)
{
    double mean[3];
    gr_obs_mean_velocity(p, mean);
    double s[MAX_M + 1] = {0}, c[MAX_M + 1] = {0};
    for (int i = 0; i < p->n; i++) {
        const double u[3] = {p->vx[i] - mean[0], p->vy[i] - mean[1], p->vz[i] - mean[2]};
        const double speed = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        species_add(m, p, i, speed);
        double ps = 1.0, pc[3] = {1.0, 1.0, 1.0};
        for (int k = 1; k <= m->m_max; k++) {
            ps *= speed;
            s[k] += ps;
            for (int a = 0; a < 3; a++) {
                pc[a] *= fabs(u[a]);
            }
            c[k] += (pc[0] + pc[1] + pc[2]) / 3.0;
        }
    }
    for (int k = 1; k <= m->m_max; k++) {
        gr_blocking_add(&m->speed[k], s[k] / p->n);
        gr_blocking_add(&m->comp[k], c[k] / p->n);
    }
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    moments *m = state;
    int rc = species_check(m, p, err);
    if (rc) {
        return rc;
    }
    if (p->dim == 3) {
        if (!p->vy || !p->vz) {
            return GR_FAIL(err, GR_EINVAL, "moments: a 3D frame without vy and vz");
        }
        sample_3d(m, p);
        species_frame(m, p);
        return GR_OK;
    }
    double mean[3];
    gr_obs_mean_velocity(p, mean);
    double s[MAX_M + 1] = {0}, c[MAX_M + 1] = {0};
    for (int i = 0; i < p->n; i++) {
        double ux = p->vx[i] - mean[0], uy = p->dim == 2 ? p->vy[i] - mean[1] : 0.0;
        double speed = sqrt(ux * ux + uy * uy), ax = fabs(ux), ay = fabs(uy);
        species_add(m, p, i, speed);
        double ps = 1.0, px = 1.0, py = 1.0;
        for (int k = 1; k <= m->m_max; k++) {
            ps *= speed;
            px *= ax;
            py *= ay;
            s[k] += ps;
            c[k] += p->dim == 2 ? 0.5 * (px + py) : px;
        }
    }
    for (int k = 1; k <= m->m_max; k++) {
        gr_blocking_add(&m->speed[k], s[k] / p->n);
        gr_blocking_add(&m->comp[k], c[k] / p->n);
    }
    species_frame(m, p);
    return GR_OK;
}

/* moments_species.csv and moments.species_speed of a mixture: each species' speed moments. */
static int species_finish(const moments *m, const gr_output *out, cJSON *j, gr_error *err)
{
    gr_file f;
    int rc = gr_obs_csv_open(out, "moments_species.csv",
                             "speed moments <|v|^m> of each species of a mixture, relative to the "
                             "frame's mean velocity of all grains; units (m/s)^m; errors from "
                             "block averaging over samples (docs/mixtures.md)",
                             &f, err);
    if (rc) {
        return rc;
    }
    gr_file_header(&f, "species [1],N [1],m [1],speed_moment [(m s-1)^m],"
                       "speed_stderr [(m s-1)^m],samples [1]");
    cJSON *js = cJSON_AddObjectToObject(j, "species_speed");
    for (int k = 1; k <= m->m_max; k++) {
        char key[16];
        snprintf(key, sizeof key, "m%d", k);
        cJSON *arr = cJSON_AddArrayToObject(js, key);
        for (int a = 0; a < m->ns; a++) {
            const gr_blocking *b = &m->sp[(MAX_M + 1) * a + k];
            const double mk = gr_blocking_mean(b);
            cJSON_AddItemToArray(arr, cJSON_CreateNumber(isfinite(mk) ? mk : 0.0));
        }
    }
    for (int a = 0; a < m->ns; a++) {
        for (int k = 1; k <= m->m_max; k++) {
            const gr_blocking *b = &m->sp[(MAX_M + 1) * a + k];
            fprintf(f.f, "%d,%d,%d,%.10g,%.6g,%lld\n", a + 1, m->count[a], k, gr_blocking_mean(b),
                    gr_blocking_stderr(b, NULL, NULL), (long long)b->count[0]);
        }
    }
    cJSON_AddStringToObject(js, "file", "moments_species.csv");
    return gr_file_commit(&f, err);
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    moments *m = state;
    gr_file f;
    /* the 1D and 2D text as it always was (their files stay byte for byte) */
    int rc = gr_obs_csv_open(
        out, "moments.csv",
        m->dim == 3 ? "velocity moments <|v|^m> (3.11), relative to the frame's mean velocity; "
                      "speed = |v| of the three components, component = mean of <|v_x|^m>, "
                      "<|v_y|^m> and <|v_z|^m>; units (m/s)^m; errors from block averaging over "
                      "samples"
                    : "velocity moments <|v|^m> (3.11), relative to the frame's mean velocity; "
                      "speed = |v| (2D) or |v_x| (1D), component = mean of <|v_x|^m> and "
                      "<|v_y|^m>; "
                      "units (m/s)^m; errors from block averaging over samples",
        &f, err);
    if (rc) {
        return rc;
    }
    gr_file_header(
        &f, "m [1],speed_moment [(m s-1)^m],speed_stderr [(m s-1)^m],component_moment [(m s-1)^m],"
            "component_stderr [(m s-1)^m],samples [1]");
    cJSON *j = cJSON_AddObjectToObject(out->summary, "moments");
    cJSON *arr = cJSON_AddObjectToObject(j, "speed");
    cJSON *err_arr = cJSON_AddObjectToObject(j, "speed_stderr");
    for (int k = 1; k <= m->m_max; k++) {
        double mk = gr_blocking_mean(&m->speed[k]),
               ek = gr_blocking_stderr(&m->speed[k], NULL, NULL);
        double ck = gr_blocking_mean(&m->comp[k]), dk = gr_blocking_stderr(&m->comp[k], NULL, NULL);
        fprintf(f.f, "%d,%.10g,%.6g,%.10g,%.6g,%lld\n", k, mk, ek, ck, dk,
                (long long)m->speed[k].count[0]);
        char key[8];
        snprintf(key, sizeof key, "m%d", k);
        cJSON_AddNumberToObject(arr, key, isfinite(mk) ? mk : 0.0);
        cJSON_AddNumberToObject(err_arr, key, isfinite(ek) ? ek : 0.0);
    }
    cJSON_AddStringToObject(j, "file", "moments.csv");
    rc = gr_file_commit(&f, err);
    if (!rc && m->ns) {
        rc = species_finish(m, out, j, err);
    }
    if (!rc && out->plots) {
        gr_obs_plot(
            out, "moments.png",
            "set logscale y\nset xlabel 'm'\nset ylabel '<|v|^m> (m^m/s^m)'\nset key top left\nset "
            "xtics 1\n"
            "set title \"Velocity moments\\n{/*0.75 eq. (3.11); error bars: block averaging}\"\n"
            "plot 'moments.csv' skip 1 using 1:2:3 with yerrorbars pt 6 ps 1.6 title 'speed |v|', "
            "'' skip 1 using 1:4:5 with yerrorbars pt 7 ps 0.8 title 'one component |v_x|'");
    }
    return rc;
}

/* Checkpoints: the blocking accumulators of every moment. */
static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    moments *m = state;
    gr_blob_io_check(io, "moments_max", m->m_max);
    for (int k = 0; k <= MAX_M; k++) {
        gr_obs_io_blockings(io, &m->speed[k], 1);
        gr_obs_io_blockings(io, &m->comp[k], 1);
    }
    if (m->ns) { /* a mixture's (one species: the checkpoint as before) */
        gr_blob_io_int(io, &m->counted);
        for (int a = 0; a < m->ns; a++) {
            gr_blob_io_int(io, &m->count[a]);
        }
        gr_obs_io_blockings(io, m->sp, (MAX_M + 1) * m->ns);
    }
    return GR_OK;
}

const gr_observable_type gr_obs_moments = {
    .name = "moments",
    .summary = "velocity moments <|v|^m>, m = 1..12 (3.10-3.11), with block-averaging errors",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(moments_params),
    .state_size = sizeof(moments),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
