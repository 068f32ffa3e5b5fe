/* The multiplicative bisection process of thesis sec. 3.4 (`granule bisect`).
 *
 * An interval of length 1 is bisected level by level: every partition [r_i, r_{i+1}] receives a
 * boundary at r_i + a (r_{i+1} - r_i) with a drawn from U_0(a) (3.26-3.27), so a level-n partition
 * has length x_n = prod_{i=1}^n a_i (3.28) and the lengths follow the recursion 3.29. Repeating the
 * process many times gives P_n(x) (against 3.36 for the uniform U_0), the moments <x^m> at every
 * level N = 2^k (against mu_m^k, 3.37), the exponents zeta_m of <x^m> = A N^-zeta_m fitted as the
 * thesis fits the RFM's moments of separation (3.20, Table 3.1), and the collapse 3.39-3.40.
 *
 * Precision: a split draws f = min(a, 1 - a) (exact in floating point), puts f L on its side and
 * L - f L on the other, so both pieces carry relative errors of one rounding and the two sum to L
 * to within one rounding; the lengths of a realisation sum to 1 to within n roundings. */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_sf_gamma.h>
#include <gsl/gsl_sf_psi.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>

#include "granule/bisect.h"
#include "granule_commit.h"
#include "granule_config.h"
#include "io/files.h"
#include "io/summary_read.h"
#include "io/plot.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ==========================================================================================
 * Small CSV tables: '#' comments (kept for key = value look-ups), an optional header line naming
 * the columns, then numbers separated by commas, semicolons, tabs or spaces. */
typedef struct csv_table {
    int n, cap;
    double *x, *y, *e; /* e stays NULL unless an error column exists */
    char comments[8192];
} csv_table;

static void csv_table_free(csv_table *t)
{
    free(t->x);
    free(t->y);
    free(t->e);
    memset(t, 0, sizeof *t);
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s)) {
        s++;
    }
    char *end = s + strlen(s);
    while (end > s && isspace((unsigned char)end[-1])) {
        *--end = 0;
    }
    return s;
}

static bool parse_number(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno == ERANGE) {
        return false;
    }
    while (isspace((unsigned char)*end)) {
        end++;
    }
    if (*end || !isfinite(v)) {
        return false;
    }
    *out = v;
    return true;
}

static int split_fields(char *line, char **fields, int max)
{
    int nf = 0;
    bool delimited = strpbrk(line, ",;\t") != NULL;
    char *p = line;
    while (nf < max) {
        if (!delimited) {
            while (*p == ' ') {
                p++;
            }
            if (!*p) {
                break;
            }
        }
        fields[nf++] = p;
        size_t len = delimited ? strcspn(p, ",;\t") : strcspn(p, " ");
        if (!p[len]) {
            break;
        }
        p[len] = 0;
        p += len + 1;
    }
    for (int i = 0; i < nf; i++) {
        fields[i] = trim(fields[i]);
    }
    return nf;
}

static int find_column(char **fields, int nf, const char *const *names)
{
    for (int j = 0; names && names[j]; j++) {
        for (int i = 0; i < nf; i++) {
            if (!strcasecmp(fields[i], names[j])) {
                return i;
            }
        }
    }
    return -1;
}

/* Column names looked up in a header line (case-insensitive, first match wins); without a header,
 * or when the header names none of them, x and y are the first two columns and e the third. Rows
 * are kept only where each filter column that the header has holds the filter value. */
typedef struct csv_spec {
    const char *const *x, *const *y, *const *e; /* e NULL: no error column */
    const char *filter_column[2], *filter_value[2];
} csv_spec;

static int csv_read(const char *path, const csv_spec *spec, csv_table *t, gr_error *err)
{
    memset(t, 0, sizeof *t);
    int why = 0;
    FILE *f = gr_input_fopen(path, &why);
    if (!f) {
        return GR_FAIL(err, why < 0 ? GR_EINVAL : GR_EIO, "cannot read %s: %s", path,
                       why < 0 ? "not a regular file" : strerror(why));
    }
    char line[4096], *fields[64];
    int lineno = 0, cx = 0, cy = 1, ce = -1, fc[2] = {-1, -1}, rc = GR_OK;
    bool have_columns = false;
    size_t used = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        if (!strchr(line, '\n') && !feof(f)) {
            rc = GR_FAIL(err, GR_EINVAL, "%s:%d: line longer than %zu characters", path, lineno,
                         sizeof line - 2);
            break;
        }
        char *p = trim(line);
        if (!*p) {
            continue;
        }
        if (*p == '#') {
            int w = snprintf(t->comments + used, sizeof t->comments - used, "%s\n", p + 1);
            if (w > 0 && used + (size_t)w < sizeof t->comments) {
                used += (size_t)w;
            }
            continue;
        }
        int nf = split_fields(p, fields, 64);
        double v;
        if (!have_columns) {
            have_columns = true;
            ce = spec->e && nf >= 3 ? 2 : -1;
            if (!parse_number(fields[0], &v)) { /* a header line */
                int hx = find_column(fields, nf, spec->x), hy = find_column(fields, nf, spec->y);
                if (hx >= 0 && hy >= 0) {
                    cx = hx;
                    cy = hy;
                    ce = find_column(fields, nf, spec->e);
                }
                for (int k = 0; k < 2; k++) {
                    const char *names[2] = {spec->filter_column[k], NULL};
                    fc[k] = spec->filter_column[k] ? find_column(fields, nf, names) : -1;
                }
                continue;
            }
        }
        int need = (cx > cy ? cx : cy) + 1;
        for (int k = 0; k < 2; k++) {
            need = fc[k] + 1 > need ? fc[k] + 1 : need;
        }
        need = ce + 1 > need ? ce + 1 : need;
        if (nf < need) {
            rc = GR_FAIL(err, GR_EINVAL, "%s:%d: expected %d columns, found %d", path, lineno, need,
                         nf);
            break;
        }
        if ((fc[0] >= 0 && strcmp(fields[fc[0]], spec->filter_value[0])) ||
            (fc[1] >= 0 && strcmp(fields[fc[1]], spec->filter_value[1]))) {
            continue;
        }
        double xv, yv, ev = 0.0;
        const char *bad = !parse_number(fields[cx], &xv)                ? fields[cx]
                          : !parse_number(fields[cy], &yv)              ? fields[cy]
                          : (ce >= 0 && !parse_number(fields[ce], &ev)) ? fields[ce]
                                                                        : NULL;
        if (bad) {
            rc = GR_FAIL(err, GR_EINVAL, "%s:%d: '%s' is not a finite number", path, lineno, bad);
            break;
        }
        if (t->n == t->cap) {
            int cap = t->cap ? 2 * t->cap : 256;
            double *nx = realloc(t->x, sizeof(double) * (size_t)cap);
            if (nx) {
                t->x = nx;
            }
            double *ny = nx ? realloc(t->y, sizeof(double) * (size_t)cap) : NULL;
            if (ny) {
                t->y = ny;
            }
            double *ne = ny && ce >= 0 ? realloc(t->e, sizeof(double) * (size_t)cap) : NULL;
            if (ne) {
                t->e = ne;
            }
            if (!nx || !ny || (ce >= 0 && !ne)) {
                rc = GR_FAIL(err, GR_ENOMEM, "%s: out of memory at line %d", path, lineno);
                break;
            }
            t->cap = cap;
        }
        t->x[t->n] = xv;
        t->y[t->n] = yv;
        if (ce >= 0) {
            t->e[t->n] = ev;
        }
        t->n++;
    }
    if (!rc && ferror(f)) {
        rc = GR_FAIL(err, GR_EIO, "cannot read %s: %s", path, strerror(errno));
    }
    fclose(f);
    if (rc) {
        csv_table_free(t);
    }
    return rc;
}

static int csv_need_rows(const char *path, csv_table *t, const char *what, gr_error *err)
{
    if (t->n >= 2) {
        return GR_OK;
    }
    int n = t->n;
    csv_table_free(t);
    return GR_FAIL(err, GR_EINVAL, "%s: needs at least 2 data rows%s, found %d", path, what, n);
}

/* "key = value" (or "key: value") anywhere in the comment text; key matched as a whole word. */
static bool comment_value(const char *text, const char *key, double *out)
{
    size_t kl = strlen(key);
    for (const char *p = text; (p = strstr(p, key)) != NULL; p++) {
        bool start = p == text || !(isalnum((unsigned char)p[-1]) || p[-1] == '_' || p[-1] == '\'');
        const char *q = p + kl;
        if (!start || isalnum((unsigned char)*q) || *q == '_' || *q == '\'') {
            continue;
        }
        while (*q == ' ' || *q == '\t') {
            q++;
        }
        if (*q != '=' && *q != ':') {
            continue;
        }
        char *end;
        double v = strtod(q + 1, &end);
        if (end != q + 1 && isfinite(v)) {
            *out = v;
            return true;
        }
    }
    return false;
}

/* ==========================================================================================
 * U_0(a) */

void gr_bisect_u0_uniform(gr_bisect_u0 *u)
{
    memset(u, 0, sizeof *u);
    u->kind = GR_BISECT_U0_UNIFORM;
    snprintf(u->name, sizeof u->name, "uniform");
}

int gr_bisect_u0_power(gr_bisect_u0 *u, double A, gr_error *err)
{
    memset(u, 0, sizeof *u);
    if (!(A >= GR_BISECT_POWER_A_MIN && A <= GR_BISECT_POWER_A_MAX)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "U_0 power:A needs %g <= A <= %g (a^-A + (1-a)^-A is normalisable for A < 1), got %g",
            GR_BISECT_POWER_A_MIN, GR_BISECT_POWER_A_MAX, A);
    }
    u->kind = GR_BISECT_U0_POWER;
    u->A = A;
    snprintf(u->name, sizeof u->name, "power:%g", A);
    return GR_OK;
}

static double table_density(const gr_bisect_u0 *u, double a)
{
    const int n = u->n_points;
    if (!(a >= u->a[0] && a <= u->a[n - 1])) {
        return 0.0;
    }
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (u->a[mid] <= a) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    double t = (a - u->a[lo]) / (u->a[hi] - u->a[lo]);
    return u->U[lo] + t * (u->U[hi] - u->U[lo]);
}

int gr_bisect_u0_table(gr_bisect_u0 *u, const double *a, const double *U, int n, gr_error *err)
{
    memset(u, 0, sizeof *u);
    if (n < 2) {
        return GR_FAIL(err, GR_EINVAL, "U_0 table needs at least 2 points, got %d", n);
    }
    for (int i = 0; i < n; i++) {
        if (!(isfinite(a[i]) && a[i] >= 0.0 && a[i] <= 1.0)) {
            return GR_FAIL(err, GR_EINVAL, "U_0 table point %d: a = %g outside [0, 1]", i + 1,
                           a[i]);
        }
        if (!(isfinite(U[i]) && U[i] >= 0.0)) {
            return GR_FAIL(err, GR_EINVAL, "U_0 table point %d: U = %g is not a density (>= 0)",
                           i + 1, U[i]);
        }
        if (i > 0 && !(a[i] > a[i - 1])) {
            return GR_FAIL(err, GR_EINVAL,
                           "U_0 table point %d: a = %g does not increase (after %g)", i + 1, a[i],
                           a[i - 1]);
        }
    }
    double total = 0.0;
    for (int i = 1; i < n; i++) {
        total += 0.5 * (U[i] + U[i - 1]) * (a[i] - a[i - 1]);
    }
    if (!(total > 0.0)) {
        return GR_FAIL(err, GR_EINVAL, "U_0 table integrates to 0: not a density");
    }
    u->a = malloc(sizeof(double) * (size_t)n);
    u->U = malloc(sizeof(double) * (size_t)n);
    u->cdf = malloc(sizeof(double) * (size_t)n);
    if (!u->a || !u->U || !u->cdf) {
        gr_bisect_u0_free(u);
        return GR_FAIL(err, GR_ENOMEM, "U_0 table: out of memory");
    }
    u->kind = GR_BISECT_U0_TABLE;
    u->n_points = n;
    u->table_norm = total;
    double peak = 0.0;
    for (int i = 0; i < n; i++) {
        u->a[i] = a[i];
        u->U[i] = U[i] / total;
        peak = fmax(peak, u->U[i]);
    }
    u->cdf[0] = 0.0;
    for (int i = 1; i < n; i++) {
        u->cdf[i] = u->cdf[i - 1] + 0.5 * (u->U[i] + u->U[i - 1]) * (a[i] - a[i - 1]);
    }
    u->cdf[n - 1] = 1.0; /* exact by construction, up to rounding */
    for (int i = 0; i < n; i++) {
        u->asymmetry = fmax(u->asymmetry, fabs(u->U[i] - table_density(u, 1.0 - a[i])) / peak);
    }
    snprintf(u->name, sizeof u->name, "table");
    return GR_OK;
}

int gr_bisect_u0_load(gr_bisect_u0 *u, const char *path, gr_error *err)
{
    static const char *const xn[] = {"a", NULL}, *const yn[] = {"U", "U_0", "U0", "density", NULL};
    const csv_spec spec = {.x = xn, .y = yn};
    memset(u, 0, sizeof *u);
    csv_table t;
    int rc = csv_read(path, &spec, &t, err);
    if (!rc) {
        rc = csv_need_rows(path, &t, "", err);
    }
    if (rc) {
        return rc;
    }
    gr_error e = {0};
    rc = gr_bisect_u0_table(u, t.x, t.y, t.n, &e);
    csv_table_free(&t);
    if (rc) {
        return GR_FAIL(err, rc, "%s: %s", path, e.message);
    }
    snprintf(u->name, sizeof u->name, "%s", path);
    return GR_OK;
}

int gr_bisect_u0_parse(gr_bisect_u0 *u, const char *spec, gr_error *err)
{
    memset(u, 0, sizeof *u);
    if (!spec || !*spec) {
        return GR_FAIL(err, GR_EINVAL, "U_0: expected uniform, power:A or a CSV file of a,U");
    }
    if (!strcmp(spec, "uniform")) {
        gr_bisect_u0_uniform(u);
        return GR_OK;
    }
    if (!strncmp(spec, "power:", 6)) {
        double A;
        if (!parse_number(spec + 6, &A)) {
            return GR_FAIL(err, GR_EINVAL, "U_0 %s: A must be a number, e.g. power:0.3", spec);
        }
        return gr_bisect_u0_power(u, A, err);
    }
    return gr_bisect_u0_load(u, spec, err);
}

void gr_bisect_u0_free(gr_bisect_u0 *u)
{
    free(u->a);
    free(u->U);
    free(u->cdf);
    u->a = u->U = u->cdf = NULL;
    u->n_points = 0;
}

double gr_bisect_u0_density(const gr_bisect_u0 *u, double a)
{
    if (!(a > 0.0 && a < 1.0)) {
        return u->kind == GR_BISECT_U0_TABLE && (a == 0.0 || a == 1.0) ? table_density(u, a) : 0.0;
    }
    switch (u->kind) {
    case GR_BISECT_U0_UNIFORM: return 1.0;
    case GR_BISECT_U0_POWER: return 0.5 * (1.0 - u->A) * (pow(a, -u->A) + pow(1.0 - a, -u->A));
    case GR_BISECT_U0_TABLE: return table_density(u, a);
    }
    return 0.0;
}

/* One split (gr_bisect_u0_draw): the smaller fraction f = min(a, 1 - a) in (0, 1/2] and whether it
 * is the left piece. */
static inline double draw(const gr_bisect_u0 *u, gsl_rng *r, bool *small_left)
{
    for (;;) {
        double a;
        switch (u->kind) {
        case GR_BISECT_U0_POWER: {
            /* U_0 = (1-A)/2 (a^-A + (1-a)^-A) is an equal mixture of b = v^(1/(1-A)) (density
             * (1-A) b^-A) and 1 - b: draw b by inversion, the side by a fair coin */
            double b = pow(gsl_rng_uniform_pos(r), 1.0 / (1.0 - u->A));
            bool left_is_b = gsl_rng_uniform(r) < 0.5;
            if (!(b > 0.0 && b < 1.0)) {
                continue;
            }
            *small_left = left_is_b == (b < 0.5);
            return b < 0.5 ? b : 1.0 - b;
        }
        case GR_BISECT_U0_TABLE: {
            /* inversion of the piecewise-linear CDF: find the node interval, then solve
             * U_j h s + (U_{j+1} - U_j) h s^2 / 2 = q for s in [0, 1] in the cancellation-free form */
            double t = gsl_rng_uniform(r);
            int lo = 0, hi = u->n_points - 1;
            while (hi - lo > 1) {
                int mid = (lo + hi) / 2;
                if (u->cdf[mid] <= t) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            double h = u->a[hi] - u->a[lo], q = (t - u->cdf[lo]) / h, U0 = u->U[lo], U1 = u->U[hi];
            double disc = fmax(U0 * U0 + 2.0 * (U1 - U0) * q, 0.0), den = U0 + sqrt(disc);
            double s = den > 0.0 ? fmin(fmax(2.0 * q / den, 0.0), 1.0) : 0.0;
            a = u->a[lo] + s * h;
            break;
        }
        default: a = gsl_rng_uniform_pos(r); break;
        }
        if (a > 0.0 && a < 1.0) {
            *small_left = a < 0.5;
            return a < 0.5 ? a : 1.0 - a; /* 1 - a is exact for a >= 1/2 (Sterbenz) */
        }
    }
}

double gr_bisect_u0_draw(const gr_bisect_u0 *u, gsl_rng *r, bool *small_left)
{
    return draw(u, r, small_left);
}

double gr_bisect_u0_sample(const gr_bisect_u0 *u, gsl_rng *r)
{
    bool small_left;
    double f = draw(u, r, &small_left);
    return small_left ? f : 1.0 - f;
}

/* E[g] under the symmetrised U_0 by adaptive quadrature (QAGS copes with the integrable end-point
 * singularities of a^-A and ln a): g(a) = (a^m + (1-a)^m)/2, or the first/second power of -ln. */
typedef struct expect_ctx {
    const gr_bisect_u0 *u;
    int what; /* 0: a^m, 1: -ln a, 2: ln^2 a (each symmetrised) */
    double m;
} expect_ctx;

static double expect_integrand(double a, void *p)
{
    const expect_ctx *c = p;
    double g;
    if (c->what == 0) {
        g = 0.5 * (pow(a, c->m) + pow(1.0 - a, c->m));
    } else {
        double l1 = log(a), l2 = log1p(-a);
        g = c->what == 1 ? -0.5 * (l1 + l2) : 0.5 * (l1 * l1 + l2 * l2);
    }
    return gr_bisect_u0_density(c->u, a) * g;
}

static int u0_expect(const gr_bisect_u0 *u, int what, double m, double *out, gr_error *err)
{
    expect_ctx c = {u, what, m};
    gsl_function F = {expect_integrand, &c};
    gsl_integration_workspace *w = gsl_integration_workspace_alloc(1000);
    if (!w) {
        return GR_FAIL(err, GR_ENOMEM, "U_0 quadrature: out of memory");
    }
    double edges2[3] = {0.0, 0.5, 1.0};
    const double *edges = u->kind == GR_BISECT_U0_TABLE ? u->a : edges2;
    int pieces = u->kind == GR_BISECT_U0_TABLE ? u->n_points - 1 : 2;
    double sum = 0.0;
    int rc = GR_OK;
    for (int i = 0; i < pieces && !rc; i++) {
        double v, abserr;
        int st = gsl_integration_qags(&F, edges[i], edges[i + 1], 0.0, 1e-11, 1000, w, &v, &abserr);
        if (st == GSL_EROUND && abserr <= 1e-9 * fabs(v)) {
            st = GSL_SUCCESS; /* roundoff limits QAGS, but well below what we need */
        }
        if (st != GSL_SUCCESS || !isfinite(v)) {
            rc = GR_FAIL(err, GR_EINVAL, "U_0 %s: quadrature on [%g, %g] failed: %s", u->name,
                         edges[i], edges[i + 1], gsl_strerror(st));
        }
        sum += v;
    }
    gsl_integration_workspace_free(w);
    *out = sum;
    return rc;
}

int gr_bisect_u0_moment(const gr_bisect_u0 *u, double m, double *mu, gr_error *err)
{
    if (!(m >= 0.0 && isfinite(m))) {
        return GR_FAIL(err, GR_EINVAL, "U_0 moment: need a finite m >= 0, got %g", m);
    }
    if (u->kind == GR_BISECT_U0_UNIFORM) {
        *mu = 1.0 / (1.0 + m); /* 3.37 with n = 1 */
        return GR_OK;
    }
    if (u->kind == GR_BISECT_U0_POWER) {
        /* U_0 is the equal mixture of b ~ (1-A) b^-A and 1 - b: <b^m> = (1-A)/(m+1-A) and
         * <(1-b)^m> = (1-A) B(1-A, m+1) */
        const double s = 1.0 - u->A;
        *mu = 0.5 * s * (1.0 / (m + s) + gsl_sf_beta(s, m + 1.0));
        return GR_OK;
    }
    return u0_expect(u, 0, m, mu, err);
}

int gr_bisect_u0_log_stats(const gr_bisect_u0 *u, double *mean, double *var, gr_error *err)
{
    if (u->kind == GR_BISECT_U0_UNIFORM) {
        *mean =
            1.0; /* -ln a of a uniform a is exponential with mean 1 (3.36: Gamma(n, 1) in -ln x) */
        *var = 1.0;
        return GR_OK;
    }
    if (u->kind == GR_BISECT_U0_POWER) {
        /* the same mixture, s = 1 - A: <-ln b> = 1/s, <ln^2 b> = 2/s^2, <-ln(1-b)> = psi(1+s) - psi(1),
         * <ln^2(1-b)> = (psi(1+s) - psi(1))^2 + psi'(1) - psi'(1+s) (derivatives of B(s, t) at t = 1) */
        const double s = 1.0 - u->A, d = gsl_sf_psi(1.0 + s) - gsl_sf_psi(1.0);
        *mean = 0.5 * (1.0 / s + d);
        double second = 0.5 * (2.0 / (s * s) + d * d + gsl_sf_psi_1(1.0) - gsl_sf_psi_1(1.0 + s));
        *var = fmax(second - *mean * *mean, 0.0);
        return GR_OK;
    }
    double m1, m2;
    int rc = u0_expect(u, 1, 0.0, &m1, err);
    if (!rc) {
        rc = u0_expect(u, 2, 0.0, &m2, err);
    }
    if (rc) {
        return rc;
    }
    *mean = m1;
    *var = fmax(m2 - m1 * m1, 0.0);
    return GR_OK;
}

/* ==========================================================================================
 * The process (3.26-3.28) */

void gr_bisect_level(const gr_bisect_u0 *u, gsl_rng *r, double *x, size_t count)
{
    /* backwards, so that partitions 2i and 2i+1 only overwrite partitions already split */
    for (size_t i = count; i-- > 0;) {
        bool small_left;
        const double L = x[i], f = draw(u, r, &small_left);
        const double s = f * L, o = L - s;
        x[2 * i] = small_left ? s : o;
        x[2 * i + 1] = small_left ? o : s;
    }
}

int gr_bisect_realise(const gr_bisect_u0 *u, int levels, gsl_rng *r, double *x, gr_error *err)
{
    if (levels < 0 || levels > GR_BISECT_MAX_LEVELS) {
        return GR_FAIL(err, GR_EINVAL, "bisection: levels must lie in [0, %d], got %d",
                       GR_BISECT_MAX_LEVELS, levels);
    }
    x[0] = 1.0; /* P_0(x) = delta(x - 1) (3.32) */
    for (int k = 0; k < levels; k++) {
        gr_bisect_level(u, r, x, (size_t)1 << k);
    }
    return GR_OK;
}

double gr_bisect_pn_uniform(int n, double x)
{
    if (!(x > 0.0 && x <= 1.0) || n < 1) {
        return 0.0;
    }
    if (n == 1) {
        return 1.0; /* 3.33 */
    }
    double z = -log(x);
    return z > 0.0 ? exp((n - 1) * log(z) - gsl_sf_lnfact((unsigned)(n - 1))) : 0.0; /* 3.36 */
}

double gr_bisect_pn_uniform_mass(int n, double lo, double hi)
{
    /* z = -ln x is Gamma(n, 1)-distributed under 3.36; take the difference of whichever tail
     * is small so that neither end of the range loses precision */
    lo = fmax(lo, 0.0);
    hi = fmin(hi, 1.0);
    if (!(hi > lo) || n < 1) {
        return 0.0;
    }
    double z_small = -log(hi), z_big = lo > 0.0 ? -log(lo) : (double)INFINITY;
    if (z_small > n) {
        return gsl_cdf_gamma_Q(z_small, n, 1.0) -
               (isinf(z_big) ? 0.0 : gsl_cdf_gamma_Q(z_big, n, 1.0));
    }
    return (isinf(z_big) ? 1.0 : gsl_cdf_gamma_P(z_big, n, 1.0)) - gsl_cdf_gamma_P(z_small, n, 1.0);
}

double gr_bisect_moment_uniform(int n, double m) { return pow(1.0 + m, -n); } /* 3.37 */

double gr_bisect_zeta_uniform(double m) { return log1p(m) / M_LN2; } /* 3.38 */

double gr_bisect_zeta_rfm_table31(int m, double *error)
{
    static const double zeta[5] = {1.0, 1.729, 2.31, 2.81, 3.2},
                        err[5] = {0.0, 0.008, 0.03, 0.06, 0.1};
    if (m < 1 || m > 5) {
        if (error) {
            *error = NAN;
        }
        return NAN;
    }
    if (error) {
        *error = err[m - 1];
    }
    return zeta[m - 1];
}

/* ==========================================================================================
 * Repetitions and statistics */

void gr_bisect_settings_default(gr_bisect_settings *s)
{
    memset(s, 0, sizeof *s);
    s->levels = 9;
    s->repetitions = 10000;
    s->seed = 1;
    s->moments_max = 6;
    s->bins_per_decade = 10;
    s->fit_level_min = 1;
    s->jackknife_groups = 32;
    s->anchor = 0.7;
    s->anchor_min_count = 100.0;
}

int gr_bisect_settings_check(const gr_bisect_settings *s, gr_error *err)
{
    if (s->levels < 1 || s->levels > GR_BISECT_MAX_LEVELS) {
        return GR_FAIL(err, GR_EINVAL, "levels must lie in [1, %d], got %d", GR_BISECT_MAX_LEVELS,
                       s->levels);
    }
    if (s->repetitions < 2 || s->repetitions > (int64_t)1 << 50) {
        return GR_FAIL(
            err, GR_EINVAL,
            "repetitions must lie in [2, 2^50] (errors come from their spread), got %lld",
            (long long)s->repetitions);
    }
    if (s->moments_max < 1 || s->moments_max > GR_BISECT_MAX_MOMENTS) {
        return GR_FAIL(err, GR_EINVAL, "moments must lie in [1, %d], got %d", GR_BISECT_MAX_MOMENTS,
                       s->moments_max);
    }
    if (s->bins_per_decade < 1 || s->bins_per_decade > 1000) {
        return GR_FAIL(err, GR_EINVAL, "bins per decade must lie in [1, 1000], got %d",
                       s->bins_per_decade);
    }
    if (s->fit_level_min < 1 || (s->levels > 1 && s->fit_level_min > s->levels - 1)) {
        return GR_FAIL(
            err, GR_EINVAL,
            "the zeta fit needs 2 levels: first fitted level must lie in [1, %d], got %d",
            s->levels > 1 ? s->levels - 1 : 1, s->fit_level_min);
    }
    if (s->jackknife_groups < 2 || s->jackknife_groups > 1024) {
        return GR_FAIL(err, GR_EINVAL, "jackknife groups must lie in [2, 1024], got %d",
                       s->jackknife_groups);
    }
    if (!(s->anchor > 0.0 && s->anchor < 1.0)) {
        return GR_FAIL(err, GR_EINVAL, "the collapse anchor R_0 (3.40) must lie in (0, 1), got %g",
                       s->anchor);
    }
    if (!(s->anchor_min_count >= 1.0 && isfinite(s->anchor_min_count))) {
        return GR_FAIL(err, GR_EINVAL, "anchor_min_count must be >= 1, got %g",
                       s->anchor_min_count);
    }
    return GR_OK;
}

void gr_bisect_result_free(gr_bisect_result *res)
{
    gr_histogram_free(&res->pn);
    free(res->pn_count_var);
    free(res->moment);
    free(res->moment_err);
    free(res->moment_pred);
    res->pn_count_var = res->moment = res->moment_err = res->moment_pred = NULL;
}

double gr_bisect_result_moment(const gr_bisect_result *res, int level, int m, double *error)
{
    if (level < 0 || level > res->levels || m < 1 || m > res->moments_max || !res->moment) {
        if (error) {
            *error = NAN;
        }
        return NAN;
    }
    size_t i = (size_t)level * (size_t)res->moments_max + (size_t)(m - 1);
    if (error) {
        *error = res->moment_err[i];
    }
    return res->moment[i];
}

/* The chi-square weight of a level's moment: its standard error, floored at 1e-13 relative so that
 * the exact m = 1 moment (2^-k up to rounding) keeps a finite weight. */
static double moment_sigma(double value, double error) { return fmax(error, 1e-13 * fabs(value)); }

/* zeta_m: <x_k^m> = A (2^k)^-zeta over the fitted levels (3.20 with N = 2^k, 3.38); the jackknife
 * repeats the fit leaving out one group of realisations at a time. */
static void fit_zeta(gr_bisect_result *res, int m, const double *ysum, const double *gsum,
                     const int64_t *gcount, int G)
{
    const int M = res->moments_max, k0 = res->fit_level_min, np = res->levels - k0 + 1;
    gr_bisect_zeta *z = &res->zeta[m - 1];
    *z = (gr_bisect_zeta){.m = m,
                          .zeta = NAN,
                          .err_fit = NAN,
                          .err_jackknife = NAN,
                          .prefactor = NAN,
                          .prefactor_err = NAN,
                          .chi2_red = NAN,
                          .predicted = -log2(res->mu[m])};
    if (np < 2) {
        return;
    }
    double xN[GR_BISECT_MAX_LEVELS + 1], y[GR_BISECT_MAX_LEVELS + 1], sig[GR_BISECT_MAX_LEVELS + 1];
    for (int j = 0; j < np; j++) {
        size_t i = (size_t)(k0 + j) * (size_t)M + (size_t)(m - 1);
        xN[j] = ldexp(1.0, k0 + j);
        y[j] = res->moment[i];
        sig[j] = moment_sigma(res->moment[i], res->moment_err[i]);
    }
    gr_fit fit;
    gr_error e = {0};
    if (gr_fit_power_law(xN, y, sig, np, &fit, &e)) {
        return;
    }
    z->zeta = -fit.p[1];
    z->err_fit = fit.err[1];
    z->prefactor = fit.p[0];
    z->prefactor_err = fit.err[0];
    z->chi2_red = fit.chi2_red;
    z->dof = fit.dof;
    double slope[1024], s1 = 0.0, s2 = 0.0;
    const double R = (double)res->repetitions;
    for (int g = 0; g < G; g++) {
        for (int j = 0; j < np; j++) {
            size_t i = (size_t)(k0 + j) * (size_t)M + (size_t)(m - 1);
            size_t gi = (size_t)g * (size_t)(res->levels + 1) * (size_t)M + i;
            y[j] = (ysum[i] - gsum[gi]) / (R - (double)gcount[g]);
        }
        gr_fit jf;
        if (gr_fit_power_law(xN, y, sig, np, &jf, &e)) {
            return;
        }
        slope[g] = -jf.p[1];
        s1 += slope[g];
    }
    for (int g = 0; g < G; g++) {
        s2 += (slope[g] - s1 / G) * (slope[g] - s1 / G);
    }
    z->err_jackknife =
        sqrt((double)(G - 1) / G * s2); /* jackknife variance (G-1)/G sum (s_g - mean)^2 */
}

int gr_bisect_run(const gr_bisect_settings *s, const gr_bisect_u0 *u, gr_bisect_result *res,
                  gr_error *err)
{
    memset(res, 0, sizeof *res);
    int rc = gr_bisect_settings_check(s, err);
    if (rc) {
        return rc;
    }
    const double t_start = now();
    const int n = s->levels, M = s->moments_max;
    const int64_t R = s->repetitions;
    const int G = s->jackknife_groups < R ? s->jackknife_groups : (int)R;
    const size_t N = (size_t)1 << n, KM = (size_t)(n + 1) * (size_t)M;
    res->levels = n;
    res->moments_max = M;
    res->fit_level_min = s->fit_level_min;
    res->repetitions = R;
    res->segments = (double)R * (double)N;
    res->mu[0] = 1.0;
    for (int m = 1; m <= M; m++) {
        rc = gr_bisect_u0_moment(u, m, &res->mu[m], err);
        if (rc) {
            return rc;
        }
    }
    /* the histogram spans -ln x up to n <z> + 10 sd + 10, in whole decades */
    double zmean, zvar;
    rc = gr_bisect_u0_log_stats(u, &zmean, &zvar, err);
    if (rc) {
        return rc;
    }
    int decades = (int)ceil((n * zmean + 10.0 * sqrt(n * zvar) + 10.0) / M_LN10);
    decades = decades > 300 ? 300 : decades;
    gr_histogram rep_h;
    rc = gr_histogram_init(&res->pn, decades * s->bins_per_decade, pow(10.0, -decades), 1.0, true,
                           err);
    if (rc) {
        return rc;
    }
    rc = gr_histogram_init(&rep_h, res->pn.nbins, res->pn.lo, res->pn.hi, true, err);
    if (rc) {
        gr_bisect_result_free(res);
        return rc;
    }
    const int nb = res->pn.nbins;
    double *x = malloc(sizeof(double) * N), *mean = calloc(KM, sizeof(double)),
           *m2 = calloc(KM, sizeof(double));
    double *ysum = calloc(KM, sizeof(double)), *gsum = calloc(KM * (size_t)G, sizeof(double));
    int64_t *gcount = calloc((size_t)G, sizeof(int64_t));
    long double *sq = calloc((size_t)nb, sizeof(long double));
    res->pn_count_var = calloc((size_t)nb, sizeof(double));
    res->moment = calloc(KM, sizeof(double));
    res->moment_err = calloc(KM, sizeof(double));
    res->moment_pred = calloc(KM, sizeof(double));
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    if (!x || !mean || !m2 || !ysum || !gsum || !gcount || !sq || !res->pn_count_var ||
        !res->moment || !res->moment_err || !res->moment_pred || !r) {
        rc = GR_FAIL(err, GR_ENOMEM, "bisection: out of memory for 2^%d partitions", n);
        goto done;
    }
    gsl_rng_set(r, (unsigned long)s->seed);
    const int64_t report_every = R / 256 > 0 ? R / 256 : 1;
    for (int64_t rep = 0; rep < R; rep++) {
        const int g = (int)((double)rep * G / (double)R);
        gcount[g]++;
        x[0] = 1.0;
        size_t count = 1;
        for (int k = 1; k <= n; k++) {
            gr_bisect_level(u, r, x, count);
            count *= 2;
            /* the level's moments; the m = 1 sum compensated (Neumaier) to check the total length */
            double sums[GR_BISECT_MAX_MOMENTS] = {0}, c1 = 0.0;
            for (size_t i = 0; i < count; i++) {
                const double xi = x[i];
                double t = sums[0] + xi;
                c1 += fabs(sums[0]) >= fabs(xi) ? (sums[0] - t) + xi : (xi - t) + sums[0];
                sums[0] = t;
                double p = xi;
                for (int m = 1; m < M; m++) {
                    p *= xi;
                    sums[m] += p;
                }
            }
            res->sum_error_max = fmax(res->sum_error_max, fabs(sums[0] - 1.0 + c1));
            sums[0] += c1;
            const double inv = 1.0 / (double)count;
            for (int m = 0; m < M; m++) {
                /* Welford over realisations of the per-realisation mean of x^m */
                size_t i = (size_t)k * (size_t)M + (size_t)m;
                double yv = sums[m] * inv, d = yv - mean[i];
                mean[i] += d / (double)(rep + 1);
                m2[i] += d * (yv - mean[i]);
                ysum[i] += yv;
                gsum[(size_t)g * KM + i] += yv;
            }
        }
        for (size_t i = 0; i < N; i++) {
            gr_histogram_add(&rep_h, x[i], 1.0);
            res->underflows += x[i] == 0.0;
        }
        for (int b = 0; b < nb; b++) {
            long double c = rep_h.count[b];
            sq[b] += c * c;
        }
        gr_histogram_merge(&res->pn, &rep_h, err); /* same binning: cannot fail */
        memset(rep_h.count, 0, sizeof(double) * (size_t)nb);
        rep_h.below = rep_h.above = rep_h.total = 0.0;
        if (s->progress && ((rep + 1) % report_every == 0 || rep + 1 == R)) {
            s->progress(rep + 1, R, s->user);
        }
    }
    for (int b = 0; b < nb; b++) {
        long double c = res->pn.count[b];
        res->pn_count_var[b] =
            (double)fmaxl((sq[b] - c * c / (long double)R) / (long double)(R - 1), 0.0L);
    }
    for (int m = 0; m < M; m++) {
        res->moment[m] = res->moment_pred[m] = 1.0; /* level 0: one partition of length 1 */
        ysum[m] = (double)R;
        for (int g = 0; g < G; g++) {
            gsum[(size_t)g * KM + (size_t)m] = (double)gcount[g];
        }
    }
    for (int k = 1; k <= n; k++) {
        for (int m = 0; m < M; m++) {
            size_t i = (size_t)k * (size_t)M + (size_t)m;
            res->moment[i] = mean[i];
            res->moment_err[i] = sqrt(m2[i] / (double)(R - 1) / (double)R);
            res->moment_pred[i] = pow(res->mu[m + 1], k); /* mu_m^k; (1+m)^-k for U_0 = 1 (3.37) */
        }
    }
    for (int m = 1; m <= M; m++) {
        fit_zeta(res, m, ysum, gsum, gcount, G);
    }
    res->wall_seconds = now() - t_start;
done:
    gr_histogram_free(&rep_h);
    free(x);
    free(mean);
    free(m2);
    free(ysum);
    free(gsum);
    free(gcount);
    free(sq);
    if (r) {
        gsl_rng_free(r);
    }
    if (rc) {
        gr_bisect_result_free(res);
    }
    return rc;
}

int gr_bisect_pn_gof(const gr_bisect_result *res, double min_expected, gr_bisect_gof *out,
                     gr_error *err)
{
    memset(out, 0, sizeof *out);
    const gr_histogram *h = &res->pn;
    for (int b = 0; b < h->nbins; b++) {
        double E = res->segments * gr_bisect_pn_uniform_mass(res->levels, gr_histogram_lower(h, b),
                                                             gr_histogram_upper(h, b));
        if (!(E >= min_expected)) {
            continue;
        }
        double C = h->count[b], d = C - E;
        double var =
            (double)res->repetitions * res->pn_count_var[b]; /* variance of the bin's total */
        out->chi2 += d * d / (var > 0.0 ? var : E);
        out->chi2_poisson += d * d / (C > 0.0 ? C : E);
        out->dof++;
    }
    if (out->dof == 0) {
        return GR_FAIL(err, GR_EINVAL, "P_n goodness of fit: no bin expects %g partitions",
                       min_expected);
    }
    out->p_value = gsl_cdf_chisq_Q(out->chi2, out->dof);
    return GR_OK;
}

/* ==========================================================================================
 * The collapse (3.39-3.40) and RFM G_1 tables */

double gr_bisect_collapse_factor(double n, double R0, double G0)
{
    return -log(R0) * pow(G0, -1.0 / (n - 1.0));
}

double gr_bisect_collapse_map(double n, double A_N, double G)
{
    return A_N * pow(G, 1.0 / (n - 1.0));
}

void gr_bisect_g1_free(gr_bisect_g1 *g)
{
    free(g->R);
    free(g->G);
    free(g->G_err);
    g->R = g->G = g->G_err = NULL;
    g->n_points = 0;
}

/* N and L' from a run folder's summary.json ("analysis": {"gaps": {"N", "reduced_length"}}, written by the 1D
 * gaps observable); false if the file or the keys are missing. */
static bool run_gaps_info(const char *dir, double *N, double *Lr)
{
    char path[1240];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    FILE *f = gr_input_fopen(path, &(int){0});
    if (!f) {
        return false;
    }
    char *text = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len + 4096 + 1 > cap) {
            cap = 2 * cap + 8192;
            char *nt = realloc(text, cap);
            if (!nt) {
                break;
            }
            text = nt;
        }
        size_t r = fread(text + len, 1, 4096, f);
        len += r;
        if (r < 4096) {
            break;
        }
    }
    fclose(f);
    bool ok = false;
    if (text && len + 1 <= cap) {
        text[len] = 0;
        cJSON *j = cJSON_Parse(text);
        /* a run folder writes analysis.gaps; a bare "gaps" member is accepted too */
        const cJSON *gaps = cJSON_GetObjectItemCaseSensitive(
            cJSON_GetObjectItemCaseSensitive(j, "analysis"), "gaps");
        if (!gaps) {
            gaps = cJSON_GetObjectItemCaseSensitive(j, "gaps");
        }
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(gaps, "N"),
                    *l = cJSON_GetObjectItemCaseSensitive(gaps, "reduced_length");
        if (cJSON_IsNumber(n) && cJSON_IsNumber(l)) {
            *N = n->valuedouble;
            *Lr = l->valuedouble;
            ok = true;
        }
        cJSON_Delete(j);
    }
    free(text);
    return ok;
}

int gr_bisect_g1_load(gr_bisect_g1 *g, const char *path, gr_error *err)
{
    static const char *const xn[] = {"R", NULL}, *const yn[] = {"G", "G_1", "G1", "density", NULL},
                             *const en[] = {"G_err",         "G_error", "G_1_err",
                                            "density_error", "sigma",   NULL};
    memset(g, 0, sizeof *g);
    /* a run folder stands for its gaps.csv; a gaps.csv (columns h, binning, ...) gives its h = 1
     * rows, logarithmic bins if it has them, and N, L' from the summary.json beside it */
    char csv[1240], dir[1200];
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        snprintf(dir, sizeof dir, "%s", path);
        snprintf(csv, sizeof csv, "%s/gaps.csv", path);
    } else {
        const char *slash = strrchr(path, '/');
        snprintf(csv, sizeof csv, "%s", path);
        snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) : 1, slash ? path : ".");
    }
    csv_spec spec = {
        .x = xn, .y = yn, .e = en, .filter_column = {"h", "binning"}, .filter_value = {"1", "log"}};
    csv_table t;
    int rc = csv_read(csv, &spec, &t, err);
    if (!rc && t.n < 2) { /* a gaps.csv without logarithmic bins */
        csv_table_free(&t);
        spec.filter_value[1] = "lin";
        rc = csv_read(csv, &spec, &t, err);
    }
    if (!rc) {
        rc = csv_need_rows(csv, &t, " (of G_1)", err);
    }
    if (rc) {
        return rc;
    }
    double N = NAN, Lr = 1.0, runN = NAN, runLr = 1.0;
    bool have_run = run_gaps_info(dir, &runN, &runLr);
    if (!comment_value(t.comments, "N", &N) && have_run) {
        N = runN;
        Lr = runLr;
    }
    if (!(N > 2.0)) {
        csv_table_free(&t);
        return GR_FAIL(err, GR_EINVAL,
                       "%s: needs a comment line '# N = <particles>' with N > 2, or a run's "
                       "summary.json beside it "
                       "(n = log2 N enters the collapse 3.39)",
                       csv);
    }
    if (comment_value(t.comments, "reduced_length", &Lr) && !(Lr > 0.0)) {
        csv_table_free(&t);
        return GR_FAIL(err, GR_EINVAL, "%s: reduced_length must be > 0, got %g", csv, Lr);
    }
    if (!(Lr > 0.0)) {
        csv_table_free(&t);
        return GR_FAIL(err, GR_EINVAL, "%s: the run's reduced_length must be > 0, got %g", csv, Lr);
    }
    for (int i = 0; i < t.n; i++) {
        if (!(t.x[i] >= 0.0) || (i > 0 && !(t.x[i] > t.x[i - 1]))) {
            double bad = t.x[i];
            csv_table_free(&t);
            return GR_FAIL(err, GR_EINVAL,
                           "%s: R must be >= 0 and increase strictly (row %d: R = %g)", csv, i + 1,
                           bad);
        }
        if (!(t.y[i] >= 0.0) || (t.e && !(t.e[i] >= 0.0))) {
            csv_table_free(&t);
            return GR_FAIL(err, GR_EINVAL, "%s: G and its error must be >= 0 (row %d)", csv, i + 1);
        }
    }
    for (int i = 0; i < t.n; i++) {
        t.x[i] /= Lr; /* to L' = 1 as in the thesis: R -> R/L', G -> G L' */
        t.y[i] *= Lr;
        if (t.e) {
            t.e[i] *= Lr;
        }
    }
    g->n_points = t.n;
    g->R = t.x;
    g->G = t.y;
    g->G_err = t.e;
    g->N = N;
    g->reduced_length = Lr;
    snprintf(g->name, sizeof g->name, "%s", path);
    return GR_OK;
}

int gr_bisect_g1_at(const gr_bisect_g1 *g, double R, double *G, gr_error *err)
{
    const int n = g->n_points;
    if (!(R >= g->R[0] && R <= g->R[n - 1])) {
        return GR_FAIL(err, GR_EINVAL, "%s: no data at R = %g (the table spans [%g, %g])", g->name,
                       R, g->R[0], g->R[n - 1]);
    }
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (g->R[mid] <= R) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    const double R0 = g->R[lo], R1 = g->R[hi], G0 = g->G[lo], G1 = g->G[hi];
    if (R == R0 || R == R1) {
        *G = R == R0 ? G0 : G1;
    } else if (R0 > 0.0 && R1 < 1.0 && G0 > 0.0 && G1 > 0.0) {
        /* ln G linear in ln(-ln R): exact for the logarithmic form G ~ (-ln R)^(n_N - 1) (3.22) */
        double u = log(-log(R)), u0 = log(-log(R0)), u1 = log(-log(R1));
        *G = exp(log(G0) + (u - u0) / (u1 - u0) * (log(G1) - log(G0)));
    } else {
        *G = G0 + (R - R0) / (R1 - R0) * (G1 - G0);
    }
    return GR_OK;
}

/* The process's own anchor: the bin holding R_0 if it has anchor_min_count partitions (3.40), else
 * the largest-x bin that has (for n >~ 5 the uniform process almost never reaches x = 0.7). Every
 * anchor gives the same collapse for the uniform process: A_n (P_n)^(1/(n-1)) = -ln x exactly. */
static int process_anchor_bin(const gr_bisect_result *res, const gr_bisect_settings *s)
{
    const gr_histogram *h = &res->pn;
    int best = -1;
    for (int b = 0; b < h->nbins; b++) {
        if (h->count[b] >= s->anchor_min_count) {
            best = b;
            if (gr_histogram_lower(h, b) <= s->anchor && s->anchor < gr_histogram_upper(h, b)) {
                return b;
            }
        }
    }
    if (best < 0) { /* too few repetitions: the fullest bin */
        for (int b = 0; b < h->nbins; b++) {
            if (best < 0 || h->count[b] > h->count[best]) {
                best = b;
            }
        }
    }
    return best;
}

/* ==========================================================================================
 * Outputs */

static void csv_header(gr_file *f, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                       const char *what)
{
    gr_file_note(f, "# granule bisect %s (commit %s): %s\n", GR_VERSION, GR_COMMIT, what);
    gr_file_note(f,
                 "# multiplicative bisection process (thesis sec. 3.4): n = %d levels (N = 2^n = "
                 "%lld partitions), "
                 "%lld realisations, U_0 = %s, gsl_rng_mt19937 seed %llu\n",
                 s->levels, 1LL << s->levels, (long long)s->repetitions, u->name,
                 (unsigned long long)s->seed);
}

static int write_pn(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                    const gr_bisect_result *res, int *first, int *last, gr_error *err)
{
    const gr_histogram *h = &res->pn;
    *first = -1;
    *last = -1;
    for (int b = 0; b < h->nbins; b++) {
        if (h->count[b] > 0.0) {
            *first = *first < 0 ? b : *first;
            *last = b;
        }
    }
    gr_file f;
    int rc = gr_file_open(&f, dir, "pn.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, s, u, "P_n(x), the distribution of partition lengths x at level n");
    gr_file_note(&f,
                 "# log bins (%d per decade; empty bins at either end left out); density = count / "
                 "(partitions * "
                 "width) with sqrt(count) errors (App. A.1); density_error_reps from the spread of "
                 "the counts over "
                 "realisations (the partitions of one realisation are correlated)\n",
                 s->bins_per_decade);
    gr_file_note(
        &f,
        "# uniform_3_36 = (-ln x)^(n-1)/(n-1)! at the bin centre (eq. 3.36, the uniform U_0); "
        "uniform_3_36_bin = its average over the bin; %.0f of %.0f partitions fell below x = %g\n",
        h->below, h->total, h->lo);
    gr_file_header(&f, "x_lo [1],x_hi [1],x [1],minus_ln_x [1],count [1],density [1],density_error "
                       "[1],density_error_reps [1],uniform_3_36 [1],uniform_3_36_bin [1]");
    for (int b = *first; b >= 0 && b <= *last; b++) {
        double lo = gr_histogram_lower(h, b), hi = gr_histogram_upper(h, b),
               xc = gr_histogram_center(h, b);
        double w = hi - lo;
        fprintf(f.f, "%.10g,%.10g,%.10g,%.10g,%.0f,%.10g,%.6g,%.6g,%.10g,%.10g\n", lo, hi, xc,
                -log(xc), h->count[b], gr_histogram_density(h, b), gr_histogram_density_error(h, b),
                sqrt((double)res->repetitions * res->pn_count_var[b]) / (h->total * w),
                gr_bisect_pn_uniform(s->levels, xc),
                gr_bisect_pn_uniform_mass(s->levels, lo, hi) / w);
    }
    return gr_file_commit(&f, err);
}

static int write_moments(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                         const gr_bisect_result *res, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "moments.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, s, u,
               "moments <x^m> of the partition lengths at every level k (N = 2^k partitions)");
    gr_file_note(&f, "# moment = mean over realisations of the mean over the N partitions; "
                     "moment_error = standard "
                     "error from its spread over realisations; predicted = mu_m^k, mu_m = <(a^m + "
                     "(1-a)^m)/2> under "
                     "U_0 (= (1+m)^-k for the uniform U_0, eq. 3.37); z = (moment - predicted) / "
                     "moment_error\n");
    gr_file_header(&f, "level [1],N [1],m [1],moment [1],moment_error [1],predicted [1],z [1]");
    for (int k = 1; k <= res->levels; k++) {
        for (int m = 1; m <= res->moments_max; m++) {
            size_t i = (size_t)k * (size_t)res->moments_max + (size_t)(m - 1);
            double sig = moment_sigma(res->moment[i], res->moment_err[i]);
            fprintf(f.f, "%d,%lld,%d,%.12g,%.6g,%.12g,%.4f\n", k, 1LL << k, m, res->moment[i],
                    res->moment_err[i], res->moment_pred[i],
                    (res->moment[i] - res->moment_pred[i]) / sig);
        }
    }
    return gr_file_commit(&f, err);
}

static void csv_number(FILE *f, double v, const char *sep)
{
    if (isfinite(v)) {
        fprintf(f, "%.6g%s", v, sep);
    } else {
        fprintf(f, "%s", sep);
    }
}

static int write_zeta(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                      const gr_bisect_result *res, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "zeta.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, s, u,
               "the exponents zeta_m of <x^m> = A N^-zeta_m (eqs. 3.20, 3.38; Table 3.1)");
    gr_file_note(
        &f,
        "# chi-square power-law fit over N = 2^k, k = %d..%d, with the moments' standard errors; "
        "zeta_error_fit from the fit (levels taken as independent, as the thesis), "
        "zeta_error_jackknife "
        "from %d groups of realisations (levels of one realisation are correlated)\n",
        res->fit_level_min, res->levels,
        s->jackknife_groups < s->repetitions ? s->jackknife_groups : (int)s->repetitions);
    gr_file_note(
        &f,
        "# zeta_predicted = -log2 mu_m for this U_0; zeta_uniform_3_38 = ln(1+m)/ln 2; "
        "zeta_rfm_table_3_1 = the 1D Random Force Model's measured value (Table 3.1, m <= 5)\n");
    gr_file_header(
        &f, "m [1],zeta [1],zeta_error_fit [1],zeta_error_jackknife [1],chi2_red [1],prefactor [1],"
            "prefactor_error [1],zeta_predicted [1],zeta_uniform_3_38 [1],zeta_rfm_table_3_1 "
            "[1],zeta_rfm_error [1]");
    for (int m = 1; m <= res->moments_max; m++) {
        const gr_bisect_zeta *z = &res->zeta[m - 1];
        double re, rv = gr_bisect_zeta_rfm_table31(m, &re);
        fprintf(f.f, "%d,", m);
        csv_number(f.f, z->zeta, ",");
        csv_number(f.f, z->err_fit, ",");
        csv_number(f.f, z->err_jackknife, ",");
        csv_number(f.f, z->chi2_red, ",");
        csv_number(f.f, z->prefactor, ",");
        csv_number(f.f, z->prefactor_err, ",");
        csv_number(f.f, z->predicted, ",");
        csv_number(f.f, gr_bisect_zeta_uniform(m), ",");
        csv_number(f.f, rv, ",");
        csv_number(f.f, re, "\n");
    }
    return gr_file_commit(&f, err);
}

typedef struct collapse_info {
    int anchor_bin;
    double anchor_R, anchor_G, A_N; /* the process */
    double g_anchor[64], g_A[64];   /* each G_1 table */
} collapse_info;

static void collapse_row(FILE *f, int set, double N, double n, double A, double R, double G,
                         double Ge)
{
    if (!(R > 0.0 && R < 1.0 && G > 0.0)) {
        return; /* -ln R > 0 and G > 0 for the logarithmic axes */
    }
    double y = gr_bisect_collapse_map(n, A, G);
    fprintf(f, "%d,%.10g,%.6g,%.10g,%.10g,%.10g,", set, N, n, R, -log(R), G);
    if (isfinite(Ge)) {
        fprintf(f, "%.6g,%.10g,%.6g\n", Ge, y, y * Ge / ((n - 1.0) * G)); /* d(A G^(1/(n-1))) */
    } else {
        fprintf(f, ",%.10g,\n", y);
    }
}

static int write_collapse(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                          const gr_bisect_result *res, const gr_bisect_output *out,
                          collapse_info *ci, gr_error *err)
{
    const gr_histogram *h = &res->pn;
    const double n = res->levels, N = ldexp(1.0, res->levels);
    gr_file f;
    int rc = gr_file_open(&f, dir, "collapse.csv", err);
    if (rc) {
        return rc;
    }
    csv_header(&f, s, u, "the collapse G(R;N) -> A_N G^(1/(n-1)), n = log2 N (eq. 3.39)");
    gr_file_note(&f, "# A_N = -ln(R_0) G(R_0;N)^(-1/(n-1)) (eq. 3.40) so every set passes through "
                     "-ln R_0 at R_0; "
                     "the uniform process collapses onto -ln R. Sets are separated by two blank "
                     "lines (gnuplot index)\n");
    gr_file_note(&f,
                 "# set 0: the process (G = P_n(x) at the bin centres R = x), n = %d, anchored at "
                 "R_0 = %.6g "
                 "(the bin centre%s), A_N = %.8g\n",
                 res->levels, ci->anchor_R,
                 gr_histogram_lower(h, ci->anchor_bin) <= s->anchor &&
                         s->anchor < gr_histogram_upper(h, ci->anchor_bin)
                     ? " holding the requested anchor"
                     : "; the requested anchor has too few partitions",
                 ci->A_N);
    for (int k = 0; k < out->n_g1; k++) {
        const gr_bisect_g1 *g = &out->g1[k];
        gr_file_note(&f,
                     "# set %d: RFM G_1 from %s, N = %g (n = %.6g), reduced_length %g, anchored at "
                     "R_0 = %g, A_N = %.8g\n",
                     k + 1, g->name, g->N, log2(g->N), g->reduced_length, s->anchor, ci->g_A[k]);
    }
    gr_file_header(&f, "set [1],N [1],n [1],R [1],minus_ln_R [1],G [1],G_error [1],collapsed "
                       "[1],collapsed_error [1]");
    for (int b = 0; b < h->nbins; b++) {
        if (h->count[b] > 0.0) {
            collapse_row(f.f, 0, N, n, ci->A_N, gr_histogram_center(h, b),
                         gr_histogram_density(h, b), gr_histogram_density_error(h, b));
        }
    }
    for (int k = 0; k < out->n_g1; k++) {
        const gr_bisect_g1 *g = &out->g1[k];
        fputs("\n\n", f.f);
        for (int i = 0; i < g->n_points; i++) {
            collapse_row(f.f, k + 1, g->N, log2(g->N), ci->g_A[k], g->R[i], g->G[i],
                         g->G_err ? g->G_err[i] : (double)NAN);
        }
    }
    return gr_file_commit(&f, err);
}

/* Literal text inside a single-quoted gnuplot string drawn as enhanced text: quotes doubled,
 * the enhanced-text operators (_ ^ { } @ & ~ \) escaped with a backslash. */
static void gp_quote(char *dst, size_t size, const char *src)
{
    size_t j = 0;
    for (size_t i = 0; src[i] && j + 3 < size; i++) {
        if (src[i] == '\'') {
            dst[j++] = '\'';
        } else if (strchr("_^{}@&~\\", src[i])) {
            dst[j++] = '\\';
        }
        dst[j++] = src[i];
    }
    dst[j] = 0;
}

static void draw_plots(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                       const gr_bisect_result *res, const gr_bisect_output *out, int first,
                       char *note, size_t note_size)
{
    char(*bodies)[16384] = malloc(4 * sizeof *bodies);
    if (!bodies) {
        snprintf(note, note_size, "skipped: out of memory");
        return;
    }
    char name[400], one[400], why[400], drawn[200] = "", failed[400] = "";
    const int n = res->levels;
    const gr_histogram *h = &res->pn;
    gp_quote(name, sizeof name, u->name);
    /* P_n(x) against 3.36 on log axes (Fig. 3.15), down to a decade below the smallest density shown */
    double ymin = INFINITY;
    for (int b = 0; b < h->nbins; b++) {
        if (h->count[b] >= 5.0) {
            ymin = fmin(ymin, 0.1 * gr_histogram_density(h, b));
        }
    }
    ymin = isfinite(ymin) ? ymin : 1e-300;
    snprintf(bodies[0], sizeof *bodies,
             "set logscale xy\nset format x '10^{%%L}'\nset format y '10^{%%L}'\nset samples 1000\n"
             "set xrange [%g:1]\nset yrange [%g:*]\nset key bottom left\n"
             "set title 'Multiplicative bisection: P_n(x) at n = %d (N = %lld), %lld realisations, "
             "U_0 = %s'\n"
             "set xlabel 'partition length x'\nset ylabel 'P_n(x)'\n"
             "f(x) = (-log(x))**(%d-1)/gamma(%d)\n"
             "plot 'pn.csv' using ($5>=5?$3:1/0):6:7 with yerrorbars pt 7 ps 0.5 lc rgb '#1f4e9a' "
             "title 'simulated (bins with >= 5 partitions, sqrt(X) errors)', "
             "f(x) with lines lw 2 lc rgb '#cc3333' title '(-ln x)^{n-1}/(n-1)!  (eq. 3.36, "
             "uniform U_0)'\n",
             first >= 0 ? gr_histogram_lower(h, first) : h->lo, ymin, n, 1LL << n,
             (long long)res->repetitions, name, n, n);
    const char *pngs[4] = {"pn.png", "moments.png", "moments_N.png", "collapse.png"};
    /* <x^m> at level n against (1+m)^-n (3.37) */
    int len = snprintf(
        bodies[1], sizeof *bodies,
        "set logscale y\nset format y '10^{%%L}'\nset xrange [0.5:%d.5]\nset xtics 1\nset key "
        "bottom left\n"
        "set title 'Moments of the partition lengths at level n = %d, U_0 = %s'\n"
        "set xlabel 'm'\nset ylabel '<x^m>'\n"
        "plot 'moments.csv' using ($1==%d?$3:1/0):4:5 with yerrorbars pt 7 lc rgb '#1f4e9a' title "
        "'simulated', "
        "(1+x)**(-%d) with lines lw 2 lc rgb '#cc3333' title '(1+m)^{-n}  (eq. 3.37, uniform U_0)'",
        res->moments_max, n, name, n, n);
    if (u->kind != GR_BISECT_U0_UNIFORM && len > 0 && (size_t)len < sizeof *bodies) {
        snprintf(bodies[1] + len, sizeof *bodies - (size_t)len,
                 ", 'moments.csv' using ($1==%d?$3:1/0):6 with linespoints dt 2 pt 6 lc rgb "
                 "'black' title 'mu_m^n of this U_0'",
                 n);
    }
    strncat(bodies[1], "\n", sizeof *bodies - strlen(bodies[1]) - 1);
    /* <x^m> against N with the fitted power laws (3.20, 3.38) */
    len = snprintf(
        bodies[2], sizeof *bodies,
        "set logscale xy\nset format y '10^{%%L}'\nset key outside right\n"
        "set title 'Moments against the number of partitions N = 2^k: <x^m> = A N^{-zeta_m}'\n"
        "set xlabel 'N'\nset ylabel '<x^m>'\nplot ");
    for (int m = 1; m <= res->moments_max && len > 0 && (size_t)len < sizeof *bodies; m++) {
        const gr_bisect_zeta *z = &res->zeta[m - 1];
        len += snprintf(bodies[2] + len, sizeof *bodies - (size_t)len,
                        "%s'moments.csv' using ($3==%d?$2:1/0):4:5 with yerrorbars pt 7 ps 0.6 lc "
                        "%d title 'm = %d'",
                        m > 1 ? ", " : "", m, m, m);
        if (isfinite(z->zeta) && len > 0 && (size_t)len < sizeof *bodies) {
            len += snprintf(
                bodies[2] + len, sizeof *bodies - (size_t)len,
                ", (x >= %g ? %.10g*x**(-%.10g) : 1/0) with lines lc %d title 'zeta_%d = %.4f'",
                ldexp(1.0, res->fit_level_min), z->prefactor, z->zeta, m, m, z->zeta);
        }
    }
    strncat(bodies[2], "\n", sizeof *bodies - strlen(bodies[2]) - 1);
    /* the collapse (3.39, Fig. 3.17) */
    len = snprintf(
        bodies[3], sizeof *bodies,
        "set logscale xy\nset key top left\nset samples 200\n"
        "set title 'Collapse A_N G(R;N)^{1/(n-1)}, n = log_2 N (eqs. 3.39-3.40, R_0 = %g)'\n"
        "set xlabel '-ln R'\nset ylabel 'A_N G^{1/(n-1)}'\n"
        "plot 'collapse.csv' index 0 using 5:8 with points pt 7 ps 0.6 lc rgb '#1f4e9a' title "
        "'bisection process, n = %d'",
        s->anchor, n);
    for (int k = 0; k < out->n_g1 && len > 0 && (size_t)len < sizeof *bodies; k++) {
        gp_quote(one, sizeof one, out->g1[k].name);
        len += snprintf(bodies[3] + len, sizeof *bodies - (size_t)len,
                        ", 'collapse.csv' index %d using 5:8 with points pt %d ps 0.7 title 'RFM "
                        "G_1, N = %g (%s)'",
                        k + 1, (k % 10) + 1, out->g1[k].N, one);
    }
    if (len > 0 && (size_t)len < sizeof *bodies) {
        snprintf(
            bodies[3] + len, sizeof *bodies - (size_t)len,
            ", x with lines dt 2 lw 2 lc rgb 'black' title '-ln R (uniform process, eq. 3.36)'\n");
    }
    for (int i = 0; i < 4; i++) {
        if (i == 3 && n < 2) {
            continue; /* 3.39 needs n > 1 */
        }
        if (gr_plot_script(dir, pngs[i], bodies[i], why, sizeof why) == 0) {
            size_t dl = strlen(drawn);
            snprintf(drawn + dl, sizeof drawn - dl, "%s%s", dl ? ", " : "", pngs[i]);
        } else if (!failed[0]) {
            snprintf(failed, sizeof failed, "%s", why);
        }
    }
    free(bodies);
    snprintf(note, note_size, "%s", drawn);
    if (failed[0]) {
        size_t nl = strlen(note);
        snprintf(note + nl, note_size - nl, "%s%s", nl ? "; " : "", failed);
    }
}

static cJSON *number_or_null(double v)
{
    return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

static int write_summary(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                         const gr_bisect_result *res, const gr_bisect_output *out,
                         const collapse_info *ci, double write_seconds, gr_error *err)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "status", "completed");
    cJSON_AddStringToObject(j, "command", "bisect");
    cJSON_AddStringToObject(j, "granule_version", GR_VERSION);
    cJSON_AddStringToObject(j, "commit", GR_COMMIT);
    cJSON_AddNumberToObject(j, "levels", res->levels);
    cJSON_AddNumberToObject(j, "partitions_per_realisation", ldexp(1.0, res->levels));
    cJSON_AddNumberToObject(j, "repetitions", (double)res->repetitions);
    cJSON_AddNumberToObject(j, "partitions", res->segments);
    cJSON_AddNumberToObject(j, "seed", (double)s->seed);
    cJSON_AddStringToObject(j, "rng", "gsl_rng_mt19937");
    cJSON *uj = cJSON_AddObjectToObject(j, "u0");
    static const char *const kinds[] = {"uniform", "power", "table"};
    cJSON_AddStringToObject(uj, "kind", kinds[u->kind]);
    cJSON_AddStringToObject(uj, "name", u->name);
    if (u->kind == GR_BISECT_U0_POWER) {
        cJSON_AddNumberToObject(uj, "A", u->A);
    }
    if (u->kind == GR_BISECT_U0_TABLE) {
        cJSON_AddNumberToObject(uj, "points", u->n_points);
        cJSON_AddNumberToObject(uj, "file_integral", u->table_norm);
        cJSON_AddNumberToObject(uj, "asymmetry", u->asymmetry);
    }
    cJSON *mu = cJSON_AddArrayToObject(uj, "mu_m");
    for (int m = 1; m <= res->moments_max; m++) {
        cJSON_AddItemToArray(mu, cJSON_CreateNumber(res->mu[m]));
    }
    cJSON_AddNumberToObject(j, "wall_seconds", res->wall_seconds);
    cJSON_AddNumberToObject(j, "write_seconds", write_seconds);
    cJSON_AddNumberToObject(j, "partitions_per_second",
                            res->wall_seconds > 0.0 ? res->segments / res->wall_seconds : 0.0);
    cJSON_AddNumberToObject(j, "sum_error_max", res->sum_error_max);
    cJSON_AddNumberToObject(j, "underflowed_partitions", (double)res->underflows);
    cJSON *pj = cJSON_AddObjectToObject(j, "pn");
    cJSON_AddNumberToObject(pj, "bins", res->pn.nbins);
    cJSON_AddNumberToObject(pj, "bins_per_decade", s->bins_per_decade);
    cJSON_AddNumberToObject(pj, "x_min", res->pn.lo);
    cJSON_AddNumberToObject(pj, "below_x_min", res->pn.below);
    gr_bisect_gof gof;
    gr_error e = {0};
    cJSON *gj = cJSON_AddObjectToObject(pj, "against_3_36");
    cJSON_AddStringToObject(
        gj, "note",
        u->kind == GR_BISECT_U0_UNIFORM
            ? "chi-square of the simulated P_n against (3.36) over bins expecting >= 20 partitions"
            : "(3.36) is the uniform process; this U_0 is not expected to match it");
    if (!gr_bisect_pn_gof(res, 20.0, &gof, &e)) {
        cJSON_AddNumberToObject(gj, "chi2", gof.chi2);
        cJSON_AddNumberToObject(gj, "chi2_poisson", gof.chi2_poisson);
        cJSON_AddNumberToObject(gj, "dof", gof.dof);
        cJSON_AddNumberToObject(gj, "p_value", gof.p_value);
    }
    cJSON *mj = cJSON_AddArrayToObject(j, "moments_level_n");
    for (int m = 1; m <= res->moments_max; m++) {
        size_t i = (size_t)res->levels * (size_t)res->moments_max + (size_t)(m - 1);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "m", m);
        cJSON_AddNumberToObject(o, "moment", res->moment[i]);
        cJSON_AddNumberToObject(o, "error", res->moment_err[i]);
        cJSON_AddNumberToObject(o, "predicted", res->moment_pred[i]);
        cJSON_AddNumberToObject(o, "uniform_3_37", gr_bisect_moment_uniform(res->levels, m));
        cJSON_AddNumberToObject(o, "z",
                                (res->moment[i] - res->moment_pred[i]) /
                                    moment_sigma(res->moment[i], res->moment_err[i]));
        cJSON_AddItemToArray(mj, o);
    }
    cJSON *fit_levels = cJSON_AddArrayToObject(j, "zeta_fit_levels");
    cJSON_AddItemToArray(fit_levels, cJSON_CreateNumber(res->fit_level_min));
    cJSON_AddItemToArray(fit_levels, cJSON_CreateNumber(res->levels));
    cJSON *zj = cJSON_AddArrayToObject(j, "zeta");
    for (int m = 1; m <= res->moments_max; m++) {
        const gr_bisect_zeta *z = &res->zeta[m - 1];
        double re, rv = gr_bisect_zeta_rfm_table31(m, &re);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "m", m);
        cJSON_AddItemToObject(o, "zeta", number_or_null(z->zeta));
        cJSON_AddItemToObject(o, "error_fit", number_or_null(z->err_fit));
        cJSON_AddItemToObject(o, "error_jackknife", number_or_null(z->err_jackknife));
        cJSON_AddItemToObject(o, "chi2_red", number_or_null(z->chi2_red));
        cJSON_AddNumberToObject(o, "predicted", z->predicted);
        cJSON_AddNumberToObject(o, "uniform_3_38", gr_bisect_zeta_uniform(m));
        cJSON_AddItemToObject(o, "rfm_table_3_1", number_or_null(rv));
        cJSON_AddItemToObject(o, "rfm_table_3_1_error", number_or_null(re));
        cJSON_AddItemToArray(zj, o);
    }
    cJSON *cj = cJSON_AddObjectToObject(j, "collapse");
    cJSON_AddNumberToObject(cj, "anchor", s->anchor);
    if (res->levels >= 2) {
        cJSON_AddNumberToObject(cj, "process_anchor_R", ci->anchor_R);
        cJSON_AddNumberToObject(cj, "process_A_N", ci->A_N);
    } else {
        cJSON_AddStringToObject(cj, "note", "n = 1: the collapse 3.39 needs n > 1");
    }
    cJSON *ga = cJSON_AddArrayToObject(cj, "g1");
    for (int k = 0; k < out->n_g1; k++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "file", out->g1[k].name);
        cJSON_AddNumberToObject(o, "N", out->g1[k].N);
        cJSON_AddNumberToObject(o, "n", log2(out->g1[k].N));
        cJSON_AddNumberToObject(o, "reduced_length", out->g1[k].reduced_length);
        cJSON_AddNumberToObject(o, "G_at_anchor", ci->g_anchor[k]);
        cJSON_AddNumberToObject(o, "A_N", ci->g_A[k]);
        cJSON_AddNumberToObject(o, "points", out->g1[k].n_points);
        cJSON_AddItemToArray(ga, o);
    }
    cJSON_AddStringToObject(j, "plots", out->plots_note);
    cJSON *settings = cJSON_AddObjectToObject(j, "settings");
    cJSON_AddNumberToObject(settings, "moments_max", s->moments_max);
    cJSON_AddNumberToObject(settings, "bins_per_decade", s->bins_per_decade);
    cJSON_AddNumberToObject(settings, "fit_level_min", s->fit_level_min);
    cJSON_AddNumberToObject(settings, "jackknife_groups", s->jackknife_groups);
    cJSON_AddNumberToObject(settings, "anchor", s->anchor);
    cJSON_AddNumberToObject(settings, "anchor_min_count", s->anchor_min_count);
    int rc = gr_json_write(dir, "summary.json", j, err);
    cJSON_Delete(j);
    return rc;
}

int gr_bisect_write(const char *dir, const gr_bisect_settings *s, const gr_bisect_u0 *u,
                    const gr_bisect_result *res, gr_bisect_output *out, gr_error *err)
{
    const double t0 = now();
    collapse_info ci = {0};
    if (out->n_g1 < 0 || out->n_g1 > 64 || (out->n_g1 > 0 && !out->g1)) {
        return GR_FAIL(err, GR_EINVAL, "bisect output: between 0 and 64 G_1 tables, got %d",
                       out->n_g1);
    }
    for (int k = 0; k < out->n_g1; k++) {
        int rc = gr_bisect_g1_at(&out->g1[k], s->anchor, &ci.g_anchor[k], err);
        if (rc) {
            return rc;
        }
        if (!(ci.g_anchor[k] > 0.0)) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: G_1 = 0 at the anchor R_0 = %g: A_N (3.40) is undefined; choose "
                           "another anchor",
                           out->g1[k].name, s->anchor);
        }
        ci.g_A[k] = gr_bisect_collapse_factor(log2(out->g1[k].N), s->anchor, ci.g_anchor[k]);
    }
    if (res->levels >= 2) {
        ci.anchor_bin = process_anchor_bin(res, s);
        ci.anchor_R = gr_histogram_center(&res->pn, ci.anchor_bin);
        ci.anchor_G = gr_histogram_density(&res->pn, ci.anchor_bin);
        ci.A_N = gr_bisect_collapse_factor(res->levels, ci.anchor_R, ci.anchor_G);
    }
    int first, last;
    int rc = write_pn(dir, s, u, res, &first, &last, err);
    if (!rc) {
        rc = write_moments(dir, s, u, res, err);
    }
    if (!rc) {
        rc = write_zeta(dir, s, u, res, err);
    }
    if (!rc && res->levels >= 2) {
        rc = write_collapse(dir, s, u, res, out, &ci, err);
    }
    if (rc) {
        return rc;
    }
    if (out->plots) {
        draw_plots(dir, s, u, res, out, first, out->plots_note, sizeof out->plots_note);
    } else {
        snprintf(out->plots_note, sizeof out->plots_note, "not requested");
    }
    return write_summary(dir, s, u, res, out, &ci, now() - t0, err);
}
