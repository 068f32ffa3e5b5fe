/* species: the temperature of each species of a mixture and their ratios (docs/mixtures.md).
 *
 * In a mixture the temperature that equipartition compares is the mean kinetic energy per degree
 * of freedom of each species, T_s = (1 / (d N_s)) sum_{i in s} m_i |v_i - V|^2 (J, k_B = 1),
 * with V the frame's centre-of-mass velocity sum m_i v_i / sum m_i: equal T_s is equipartition,
 * whatever the masses. (The run's T of eq. 2.19, mean |v - <v>|^2 over all grains, has no masses
 * in it and does not measure it.) Each frame gives T_s and the ratios T_s / T_1; their time
 * averages carry block-averaging errors. Needs frames with species (a run with [species]). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_util.h"
#include "granule/analysis.h"
#include "granule/sim.h"

typedef struct species_obs {
    int dim, ns;
    int count[GR_MAX_SPECIES];
    double radius[GR_MAX_SPECIES], mass[GR_MAX_SPECIES];
    gr_blocking T[GR_MAX_SPECIES];     /* T_s, J */
    gr_blocking ratio[GR_MAX_SPECIES]; /* T_s / T_1 */
} species_obs;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    (void)params_block;
    (void)err;
    species_obs *m = state;
    m->dim = setup->dim;
    return GR_OK;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    species_obs *m = state;
    if (!p->species || p->n_species < 2 || p->n_species > GR_MAX_SPECIES) {
        return GR_FAIL(err, GR_EINVAL,
                       "species: the frames carry no species; the observable needs a run of a "
                       "scene with [species] (2 to %d species; docs/mixtures.md)",
                       GR_MAX_SPECIES);
    }
    if (m->ns == 0) { /* the first frame names the species */
        m->ns = p->n_species;
        for (int i = 0; i < p->n; i++) {
            const int a = p->species[i];
            m->count[a]++;
            m->radius[a] = p->radii[i];
            m->mass[a] = p->masses[i];
        }
    }
    double V[3] = {0.0, 0.0, 0.0}, M = 0.0;
    for (int i = 0; i < p->n; i++) {
        V[0] += p->masses[i] * p->vx[i];
        V[1] += p->dim >= 2 ? p->masses[i] * p->vy[i] : 0.0;
        V[2] += p->dim == 3 ? p->masses[i] * p->vz[i] : 0.0;
        M += p->masses[i];
    }
    V[0] /= M;
    V[1] /= M;
    V[2] /= M;
    double e[GR_MAX_SPECIES] = {0};
    for (int i = 0; i < p->n; i++) {
        const double ux = p->vx[i] - V[0], uy = p->dim >= 2 ? p->vy[i] - V[1] : 0.0;
        double u2 = ux * ux + uy * uy;
        if (p->dim == 3) {
            u2 += (p->vz[i] - V[2]) * (p->vz[i] - V[2]);
        }
        e[p->species[i]] += p->masses[i] * u2;
    }
    double T[GR_MAX_SPECIES];
    for (int a = 0; a < m->ns; a++) {
        T[a] = m->count[a] > 0 ? e[a] / (p->dim * m->count[a]) : (double)NAN;
        gr_blocking_add(&m->T[a], T[a]);
    }
    for (int a = 0; a < m->ns; a++) {
        gr_blocking_add(&m->ratio[a], T[a] / T[0]);
    }
    return GR_OK;
}

static double finite_or_zero(double x) { return isfinite(x) ? x : 0.0; }

static int finish(void *state, const gr_output *out, gr_error *err)
{
    species_obs *m = state;
    gr_file f;
    int rc = gr_obs_csv_open(out, "species.csv",
                             "temperature of each species T_s = (1/(d N_s)) sum m_i |v_i - V|^2 "
                             "(V the centre-of-mass velocity of the frame; k_B = 1) and T_s / T_1, "
                             "time averages with block-averaging errors (docs/mixtures.md)",
                             &f, err);
    if (rc) {
        return rc;
    }
    gr_file_header(&f, "species [1],N [1],radius [m],mass [kg],T [J],T_stderr [J],"
                       "T_over_T1 [1],T_over_T1_stderr [1],samples [1]");
    cJSON *j = cJSON_AddObjectToObject(out->summary, "species");
    cJSON *jt = cJSON_AddArrayToObject(j, "T");
    cJSON *jte = cJSON_AddArrayToObject(j, "T_stderr");
    cJSON *jr = cJSON_AddArrayToObject(j, "T_over_T1");
    cJSON *jre = cJSON_AddArrayToObject(j, "T_over_T1_stderr");
    for (int a = 0; a < m->ns; a++) {
        const double T = gr_blocking_mean(&m->T[a]), Te = gr_blocking_stderr(&m->T[a], NULL, NULL);
        const double r = gr_blocking_mean(&m->ratio[a]),
                     re = gr_blocking_stderr(&m->ratio[a], NULL, NULL);
        fprintf(f.f, "%d,%d,%.10g,%.10g,%.10g,%.6g,%.10g,%.6g,%lld\n", a + 1, m->count[a],
                m->radius[a], m->mass[a], T, Te, r, re, (long long)m->T[a].count[0]);
        cJSON_AddItemToArray(jt, cJSON_CreateNumber(finite_or_zero(T)));
        cJSON_AddItemToArray(jte, cJSON_CreateNumber(finite_or_zero(Te)));
        cJSON_AddItemToArray(jr, cJSON_CreateNumber(finite_or_zero(r)));
        cJSON_AddItemToArray(jre, cJSON_CreateNumber(finite_or_zero(re)));
    }
    if (m->ns >= 2) { /* the binary mixture's T_1 / T_2, from the per-frame ratio T_2 / T_1 */
        const double r = gr_blocking_mean(&m->ratio[1]),
                     re = gr_blocking_stderr(&m->ratio[1], NULL, NULL);
        cJSON_AddNumberToObject(j, "T1_over_T2", finite_or_zero(1.0 / r));
        cJSON_AddNumberToObject(j, "T1_over_T2_stderr", finite_or_zero(re / (r * r)));
    }
    cJSON_AddStringToObject(j, "file", "species.csv");
    return gr_file_commit(&f, err);
}

/* Checkpoints: the species found in the first frame and the accumulators. */
static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    species_obs *m = state;
    gr_blob_io_int(io, &m->ns);
    for (int a = 0; a < GR_MAX_SPECIES; a++) {
        gr_blob_io_int(io, &m->count[a]);
        gr_blob_io_f64(io, &m->radius[a]);
        gr_blob_io_f64(io, &m->mass[a]);
        gr_obs_io_blockings(io, &m->T[a], 1);
        gr_obs_io_blockings(io, &m->ratio[a], 1);
    }
    return GR_OK;
}

const gr_observable_type gr_obs_species = {
    .name = "species",
    .summary = "temperature of each species of a mixture, T_s = m <|v - V|^2>_s / d, and T_s / T_1 "
               "([species], docs/mixtures.md)",
    .dims = 7, /* 1D, 2D and 3D */
    .state_size = sizeof(species_obs),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
