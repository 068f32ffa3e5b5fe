/* clusters: cluster-size distributions, 1D, 2D and 3D, from union-find over the
 * pairs of a frame. contact clusters: particles touching, |r_ij| <= d (1 +
 * 1e-9) (d = 2 r; overlapping soft particles and particles exactly at contact
 * both count); density clusters: centres closer than cluster_distance * d (a
 * key; default 1.5 d). Per frame every cluster of size s adds 1 to n(s); the
 * distribution is reported as the mean number of clusters of each size per
 * frame, the fraction of particles in clusters of size s (s n(s) / N), and the
 * per-frame mean and largest cluster sizes with block-averaging errors. Memory:
 * N counters per kind, independent of the run length. Known answers: a touching
 * chain is one cluster of N; particles further apart than the threshold are N
 * singletons. On a mixture (species lists or a radius distribution) grains i and j touch at
 * r_i + r_j and the density threshold is cluster_distance (r_i + r_j): the pairs are searched out to
 * the largest pair's distance and each is judged at its own. With species lists each species'
 * grains are also followed (summary clusters.<kind>.species_*): per frame the fraction of the
 * species' grains in a cluster of two or more, and the mean size of the cluster a grain of the
 * species belongs to, each time-averaged with block-averaging errors. Weighted by N_s / N they are
 * the same quantities of all grains; a species more often clustered than the others, or in larger
 * clusters, shows up there (segregation by cluster). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "analysis/obs_cells.h"
#include "analysis/obs_util.h"
#include "granule/analysis.h"

#define CONTACT_TOL 1e-9

typedef struct clusters_params {
    double cluster_distance;
} clusters_params;

static const gr_param params[] = {
    {"cluster_distance", "d", GR_PARAM_DOUBLE, 1.5, 1, 1e3, false, false,
     "(clusters) density clusters join centres closer than this many diameters",
     offsetof(clusters_params, cluster_distance)},
};

enum { CONTACT, DENSITY, KINDS };
static const char *const kind_name[KINDS] = {"contact", "density"};

typedef struct clusters {
    int n;
    double cut[KINDS];    /* m; a mixture: for the largest pair */
    double factor[KINDS]; /* a mixture: pair i, j joins within factor (r_i + r_j) */
    int *parent, *size;
    double *hist[KINDS]; /* clusters of size s, summed over frames (index s, 1 ..
                            n) */
    gr_blocking mean_size[KINDS], largest[KINDS], count[KINDS];
    gr_cells cells;
    int64_t frames;
    /* species lists (ns >= 2; 0 otherwise): each grain's species, grains per species, and per kind
     * and species the per-frame fraction clustered and mean cluster size seen by a grain */
    int ns;
    int *species;
    int N_s[GR_MAX_SPECIES];
    gr_blocking clustered[KINDS][GR_MAX_SPECIES], seen[KINDS][GR_MAX_SPECIES];
} clusters;

static int init(void *state, const gr_obs_setup *setup, const void *params_block, gr_error *err)
{
    (void)err;
    clusters *c = state;
    const clusters_params *a = params_block;
    c->n = setup->N;
    double d = 2.0 * setup->radius;
    c->cut[CONTACT] = fmin(d * (1.0 + CONTACT_TOL), 0.5 * setup->L);
    c->cut[DENSITY] = fmin(a->cluster_distance * d, 0.5 * setup->L);
    c->factor[CONTACT] = 1.0 + CONTACT_TOL;
    c->factor[DENSITY] = a->cluster_distance;
    c->parent = gr_obs_calloc(c, (size_t)c->n, sizeof(int));
    c->size = gr_obs_calloc(c, (size_t)c->n + 1, sizeof(int));
    for (int k = 0; k < KINDS; k++) {
        c->hist[k] = gr_obs_calloc(c, (size_t)c->n + 1, sizeof(double));
    }
    gr_cells_own(c, &c->cells);
    if (setup->n_species >= 2 && setup->n_species <= GR_MAX_SPECIES) {
        c->ns = setup->n_species;
        c->species = gr_obs_calloc(c, (size_t)c->n, sizeof(int));
    }
    return GR_OK;
}

static int root(int *parent, int i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]]; /* path halving */
        i = parent[i];
    }
    return i;
}

typedef struct join_ctx {
    int *parent;
    const double *radii; /* a mixture's radii, NULL for one size */
    double factor;
} join_ctx;

static void join(int i, int j, const double dr[3], double r2, void *user)
{
    (void)dr;
    const join_ctx *ctx = user;
    if (ctx->radii) { /* a mixture: this pair's own threshold */
        const double cut = ctx->factor * (ctx->radii[i] + ctx->radii[j]);
        if (r2 > cut * cut) {
            return;
        }
    }
    int *parent = ctx->parent;
    int a = root(parent, i), b = root(parent, j);
    if (a != b) {
        parent[a < b ? b : a] = a < b ? a : b;
    }
}

static int frame(clusters *c, const gr_particles *p, int k, gr_error *err)
{
    for (int i = 0; i < c->n; i++) {
        c->parent[i] = i;
        c->size[i] = 0;
    }
    double cut = c->cut[k];
    if (p->radii) { /* the largest pair's distance bounds the search */
        double rmax = 0.0;
        for (int i = 0; i < c->n; i++) {
            rmax = fmax(rmax, p->radii[i]);
        }
        cut = fmin(c->factor[k] * 2.0 * rmax, 0.5 * p->L);
    }
    join_ctx ctx = {c->parent, p->radii, c->factor[k]};
    int rc = gr_cells_pairs(&c->cells, p, cut, join, &ctx, err);
    if (rc) {
        return rc;
    }
    for (int i = 0; i < c->n; i++) {
        c->size[root(c->parent, i)]++;
    }
    int n_clusters = 0, largest = 0;
    for (int i = 0; i < c->n; i++) {
        if (c->size[i] > 0) {
            c->hist[k][c->size[i]] += 1.0;
            n_clusters++;
            largest = c->size[i] > largest ? c->size[i] : largest;
        }
    }
    gr_blocking_add(&c->count[k], n_clusters);
    gr_blocking_add(&c->mean_size[k], (double)c->n / n_clusters);
    gr_blocking_add(&c->largest[k], largest);
    if (c->ns) { /* each species: grains in a cluster of two or more, the size a grain sees */
        double clustered[GR_MAX_SPECIES] = {0}, seen[GR_MAX_SPECIES] = {0};
        for (int i = 0; i < c->n; i++) {
            const int sz = c->size[root(c->parent, i)];
            clustered[c->species[i]] += sz >= 2;
            seen[c->species[i]] += sz;
        }
        for (int a = 0; a < c->ns; a++) {
            if (c->N_s[a] > 0) {
                gr_blocking_add(&c->clustered[k][a], clustered[a] / c->N_s[a]);
                gr_blocking_add(&c->seen[k][a], seen[a] / c->N_s[a]);
            }
        }
    }
    return GR_OK;
}

static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)t;
    clusters *c = state;
    int bad = gr_obs_check_frame("clusters", p, c->n, err);
    if (!bad && c->ns) {
        bad = gr_obs_frame_species("clusters", p, c->ns, c->n, c->species, err);
        for (int a = 0; !bad && a < c->ns; a++) {
            c->N_s[a] = 0;
        }
        for (int i = 0; !bad && i < c->n; i++) {
            c->N_s[c->species[i]]++;
        }
    }
    if (bad) {
        return bad;
    }
    for (int k = 0; k < KINDS; k++) {
        int rc = frame(c, p, k, err);
        if (rc) {
            return rc;
        }
    }
    c->frames++;
    return GR_OK;
}

static void rows(FILE *f, const void *ctx)
{
    const clusters *c = ctx;
    double fr = c->frames > 0 ? (double)c->frames : 1.0;
    for (int s = 1; s <= c->n; s++) {
        if (c->hist[CONTACT][s] > 0.0 || c->hist[DENSITY][s] > 0.0) {
            fprintf(f, "%d,%.8g,%.8g,%.8g,%.8g\n", s, c->hist[CONTACT][s] / fr,
                    s * c->hist[CONTACT][s] / fr / c->n, c->hist[DENSITY][s] / fr,
                    s * c->hist[DENSITY][s] / fr / c->n);
        }
    }
}

static int finish(void *state, const gr_output *out, gr_error *err)
{
    clusters *c = state;
    cJSON *j = gr_obs_summary(out, "clusters", "clusters.csv");
    cJSON_AddNumberToObject(j, "frames", (double)c->frames);
    for (int k = 0; k < KINDS; k++) {
        cJSON *o = cJSON_AddObjectToObject(j, kind_name[k]);
        cJSON_AddNumberToObject(o, "distance", c->cut[k]);
        gr_obs_add_number(o, "clusters_per_frame", gr_blocking_mean(&c->count[k]));
        gr_obs_add_number(o, "clusters_per_frame_error", gr_obs_stderr(&c->count[k]));
        gr_obs_add_number(o, "mean_size", gr_blocking_mean(&c->mean_size[k]));
        gr_obs_add_number(o, "mean_size_error", gr_obs_stderr(&c->mean_size[k]));
        gr_obs_add_number(o, "largest", gr_blocking_mean(&c->largest[k]));
        gr_obs_add_number(o, "largest_error", gr_obs_stderr(&c->largest[k]));
        if (c->ns) {
            const char *name[4] = {"species_fraction_clustered", "species_fraction_clustered_error",
                                   "species_mean_size_seen", "species_mean_size_seen_error"};
            for (int q = 0; q < 4; q++) {
                cJSON *arr = cJSON_AddArrayToObject(o, name[q]);
                for (int a = 0; a < c->ns; a++) {
                    const gr_blocking *b = q < 2 ? &c->clustered[k][a] : &c->seen[k][a];
                    double v = q % 2 ? gr_obs_stderr(b) : gr_blocking_mean(b);
                    cJSON_AddItemToArray(arr,
                                         isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull());
                }
            }
        }
    }
    if (c->ns) {
        cJSON_AddStringToObject(
            j, "species_definition",
            "per species s and frame: the fraction of its grains in a cluster "
            "of two or more, and the mean size of the cluster one of its grains "
            "is in; time averages with block-averaging errors");
    }
    const gr_obs_table t = {
        .name = "clusters.csv",
        .what = "cluster-size distributions: mean number of clusters of size s "
                "per frame and the fraction "
                "of particles in them; contact clusters (touching, |r_ij| <= d, on a mixture "
                "r_i + r_j) and density clusters "
                "(|r_ij| < cluster_distance d, on a mixture cluster_distance (r_i + r_j))",
        .columns = "size [1],contact_clusters [1],contact_fraction [1],density_clusters [1],"
                   "density_fraction [1]",
        .rows = rows,
        .ctx = c,
        .png = c->frames > 0 ? "clusters.png" : NULL,
        .plot = "set logscale xy\nset format y '10^{%L}'\nset xlabel 'cluster size s'\nset ylabel "
                "'clusters of size s per frame'\n"
                "set title 'Cluster-size distributions'\n"
                "plot 'clusters.csv' skip 1 using 1:($2>0?$2:1/0) with "
                "linespoints title 'contact clusters', "
                "'' skip 1 using 1:($4>0?$4:1/0) with linespoints title 'density "
                "clusters'",
    };
    return gr_obs_table_write(out, &t, err);
}

static int io(void *state, gr_blob_io *io, gr_error *err)
{
    (void)err;
    clusters *c = state;
    gr_blob_io_i64(io, &c->frames);
    for (int k = 0; k < KINDS; k++) {
        gr_blob_io_f64s(io, c->hist[k], (int64_t)c->n + 1);
        gr_obs_io_blockings(io, &c->mean_size[k], 1);
        gr_obs_io_blockings(io, &c->largest[k], 1);
        gr_obs_io_blockings(io, &c->count[k], 1);
        if (c->ns) { /* a mixture's (one species: the checkpoint as before) */
            gr_obs_io_blockings(io, c->clustered[k], c->ns);
            gr_obs_io_blockings(io, c->seen[k], c->ns);
        }
    }
    return GR_OK;
}

const gr_observable_type gr_obs_clusters = {
    .name = "clusters",
    .summary = "contact-cluster and density-cluster size distributions "
               "(union-find over the pairs of each frame)",
    .dims = 7, /* 1D, 2D and 3D */
    .params = params,
    .n_params = sizeof params / sizeof params[0],
    .params_size = sizeof(clusters_params),
    .state_size = sizeof(clusters),
    .init = init,
    .sample = sample,
    .finish = finish,
    .io = io,
};
