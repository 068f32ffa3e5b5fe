/* granule reproduce NAME [--fidelity quick|full]: rerun a figure of the thesis and print a
 * Markdown report with the thesis's value beside ours and the wall time (docs/reproduction.md
 * collects them). quick runs in minutes on 2 cores; full uses the thesis's sizes and durations
 * where the machine allows (hours). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "cli/cli.h"
#include "granule/run.h"
#include "granule_commit.h"
#include "io/files.h"
#include "io/summary_read.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: granule reproduce NAME [--fidelity quick|full] [--out DIR] [--source DIR] [--threads N]\n\n"
               "NAME: fig2.10   steady T of the sec. 2.3.3 scene for three placements (Fig. 2.10)\n"
               "      fig3.2    xi_2 of <v^2> ~ N^-xi_2 against eps in 1D, L' = 1 (Figs. 3.1-3.2)\n"
               "      fig4.2    S(k) and D_f of the 2D RFM, phi = 0.53, eps = 0.1 (Fig. 4.2, Tables 4.1-4.3)\n"
               "      fig5.3    P(v) tails of the same system, accepted alpha range (Fig. 5.3, Tables 5.1-5.2)\n"
               "      all       every one of them\n"
               "Runs go to DIR/NAME (default out/reproduce), the report to DIR/NAME/report.md and stdout.\n"
               "--source DIR: the granule source tree holding docs/scenes (default: the working folder).\n"
               "--threads N: threads for the 2D runs (default 1); results do not depend on N.\n");
}

static int run_scene(const char *scene_path, const char *const *sets, int n_sets, const char *out, gr_error *err)
{
    gr_scene sc;
    int rc = gr_scene_load(&sc, scene_path, sets, n_sets, err);
    if (rc) {
        return rc;
    }
    snprintf(sc.out_dir, sizeof sc.out_dir, "%.1000s", out);
    sc.progress = false;
    gr_run_options opt = {.force = true};
    gr_run_result res;
    return gr_run(&sc, &opt, &res, err);
}

static FILE *report_open(const char *dir, gr_file *f, gr_error *err)
{
    if (gr_output_dir_prepare(dir, true, err) || gr_file_open(f, dir, "report.md", err)) {
        return NULL;
    }
    return f->f;
}

static int finish_report(gr_file *f, double t0, bool quick, gr_error *err)
{
    fprintf(f->f, "\nFidelity: %s; wall time %.0f s on %ld cores (commit %s).\n", quick ? "quick" : "full", now() - t0,
            sysconf(_SC_NPROCESSORS_ONLN), GR_COMMIT);
    return gr_file_commit(f, err);
}

static int fig2_10(const char *src, const char *out, bool quick, gr_error *err)
{
    char scene[1100], dir[1200];
    snprintf(scene, sizeof scene, "%.1000s/docs/scenes/steady-2d.ini", src);
    const char *kinds[] = {"hexagonal", "square", "uniform"};
    gr_file f;
    if (!report_open(out, &f, err)) {
        return GR_EIO;
    }
    double t0 = now();
    fprintf(f.f, "### Fig. 2.10: steady temperature independent of the placement\n\n"
                 "N = 2000, L = 0.2 m (phi = 0.353), eps_n = eps_t = 0.6, dt = 1e-6 s; warm-up %s s, sampling %s s.\n\n"
                 "| placement | T (m^2/s^2), granule | thesis |\n|---|---|---|\n",
            quick ? "0.5" : "1", quick ? "1" : "10");
    for (int k = 0; k < 3; k++) {
        char a[64], b[64], c[64];
        snprintf(a, sizeof a, "placement.kind=%s", kinds[k]);
        snprintf(b, sizeof b, "run.warmup=%s", quick ? "0.5" : "1");
        snprintf(c, sizeof c, "run.duration=%s", quick ? "1" : "10");
        const char *sets[] = {a, b, c, "output.plots=false"};
        snprintf(dir, sizeof dir, "%.1000s/%.100s", out, kinds[k]);
        fprintf(stderr, "reproduce fig2.10: %s\n", kinds[k]);
        int rc = run_scene(scene, sets, 4, dir, err);
        cJSON *j = rc ? NULL : gr_summary_read(dir, err);
        fprintf(f.f, "| %s | %.4f +- %.4f | ~12 (quoted; see below) |\n", kinds[k], gr_summary_number(j, "T_mean"),
                gr_summary_number(j, "T_stderr"));
        cJSON_Delete(j);
        if (rc) {
            gr_file_abandon(&f);
            return rc;
        }
    }
    fprintf(f.f, "\nThe thesis's 12 m^2/s^2 does not fit its own D and M; LAMMPS and an independent kernel give 0.24 "
                 "(docs/reproduction.md explains why 0.24 is right).\n");
    return finish_report(&f, t0, quick, err);
}

static int fig3_2(const char *src, const char *out, bool quick, gr_error *err)
{
    gr_file f;
    if (!report_open(out, &f, err)) {
        return GR_EIO;
    }
    double t0 = now();
    char sweep_path[1200], sweep_out[1200];
    snprintf(sweep_path, sizeof sweep_path, "%.1000s/sweep.ini", out);
    snprintf(sweep_out, sizeof sweep_out, "%.1000s/sweep", out);
    gr_file sf;
    if (gr_file_open(&sf, out, "sweep.ini", err)) {
        gr_file_abandon(&f);
        return GR_EIO;
    }
    fprintf(sf.f, "[sweep]\nscene = %s/docs/scenes/rfm-1d.ini\nout = %s\nseeds = %s\n[vary]\nsystem.N = %s\nmodel.eps_n = %s\n"
               "[set]\nrun.warmup = %s\nrun.duration = %s\noutput.plots = false\noutput.snapshot_every = 0\n",
            src, sweep_out, quick ? "1, 2" : "1, 2, 3",
            quick ? "100, 158, 251, 398, 631" : "100, 158, 251, 398, 631, 1000, 1585",
            quick ? "0.1, 0.5, 0.9" : "0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99", quick ? "2" : "10", quick ? "20" : "200");
    if (gr_file_commit(&sf, err)) {
        gr_file_abandon(&f);
        return GR_EIO;
    }
    char *argv[] = {"sweep", "--all", sweep_path, NULL}; /* all points, even inside a batch-array task */
    int rc = cmd_sweep(3, argv);
    fprintf(f.f, "### Figs. 3.1-3.2: xi_2 of <v^2> = lambda N^-xi_2 (3.8), 1D, L' = 1 m\n\n"
                 "N = %s; T averaged over %s s after %s s (in 1D <v^2> = T); %s seeds per point; "
                 "power law fitted with the seed spread as error (`granule sweep`).\n\n"
                 "| eps | xi_2, granule | chi2/dof | thesis (Fig. 3.2) |\n|---|---|---|---|\n",
            quick ? "100-631" : "100-1585", quick ? "20" : "200", quick ? "2" : "10", quick ? "2" : "3");
    char exp_path[1300];
    snprintf(exp_path, sizeof exp_path, "%s/exponents.csv", sweep_out);
    FILE *e = fopen(exp_path, "r");
    char line[512];
    while (e && fgets(line, sizeof line, e)) {
        char eps[64], q[16];
        int m, pts;
        double x, xe, A, c2;
        if (sscanf(line, "%63[^,],%15[^,],%d,%lf,%lf,%lf,%lf,%d", eps, q, &m, &x, &xe, &A, &c2, &pts) == 8 &&
            !strcmp(q, "xi") && m == 2) {
            double ev = atof(eps);
            fprintf(f.f, "| %s | %.3f +- %.3f | %.2f | %s |\n", eps, x, xe, c2,
                    ev <= 0.5 ? "~0.53" : ev >= 0.99 ? "-> 2/3" : "between 0.53 and 2/3");
        }
    }
    if (e) {
        fclose(e);
    }
    if (rc != EXIT_OK) {
        fprintf(f.f, "\n(Some points failed: see %s/sweep.csv.)\n", sweep_out);
    }
    return finish_report(&f, t0, quick, err);
}

static int rfm2d(const char *src, const char *out, bool quick, bool want_sk, gr_error *err)
{
    char scene[1100], dir[1200];
    snprintf(scene, sizeof scene, "%.1000s/docs/scenes/rfm-2d.ini", src);
    snprintf(dir, sizeof dir, "%.1000s/run", out);
    gr_file f;
    if (!report_open(out, &f, err)) {
        return GR_EIO;
    }
    double t0 = now();
    const char *sets_quick[] = {"system.N=3000", "system.L=0.2", "run.warmup=1", "run.duration=1", "output.snapshot_every=0",
                                "analysis.observables=sk,pv,moments"};
    const char *sets_full[] = {"run.warmup=1", "run.duration=10", "output.snapshot_every=1", "analysis.observables=sk,pv,moments"};
    fprintf(stderr, "reproduce: 2D RFM run (%s)\n", quick ? "N = 3000, L = 0.2 m, 1 s + 1 s" : "N = 12000, L = 0.4 m, 1 s + 10 s");
    int rc = run_scene(scene, quick ? sets_quick : sets_full, quick ? 6 : 4, dir, err);
    cJSON *j = rc ? NULL : gr_summary_read(dir, err);
    if (want_sk) {
        fprintf(f.f, "### Fig. 4.2: S(k) ~ k^-D_f of the 2D RFM, phi = 0.53, eps_n = eps_t = 0.1\n\n"
                     "%s, dt = 1e-6 s; S(k) by Gaussian gridding + FFTW every 1 ms of sampling (`sk` observable).\n\n"
                     "| quantity | granule | thesis |\n|---|---|---|\n",
                quick ? "N = 3000, L = 0.2 m, 1 s warm-up + 1 s sampling" : "N = 12000, L = 0.4 m, 1 s warm-up + 10 s sampling");
        fprintf(f.f, "| D_f | %.2f +- %.2f (chi2/dof %.1f) | %s (Table 4.1) |\n",
                gr_summary_number(j, "analysis.sk.fit.D_f"), gr_summary_number(j, "analysis.sk.fit.D_f_err"),
                gr_summary_number(j, "analysis.sk.fit.chi2_red"), quick ? "1.63 +- 0.03 at L = 0.2 m" : "1.65 +- 0.02 at L = 0.4 m");
        fprintf(f.f, "| k_D d (4.5) | %.3f | 0.334 (Table 4.1) |\n| L_Eff (m) | %.3f | 0.16 (Table 4.1) |\n| fit window k d | %.3f - %.3f | below k' |\n",
                gr_summary_number(j, "analysis.sk.k_D_d"), gr_summary_number(j, "analysis.sk.L_Eff"),
                gr_summary_number(j, "analysis.sk.fit.kd_lo"), gr_summary_number(j, "analysis.sk.fit.kd_hi"));
    } else {
        const cJSON *ar = cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "analysis"), "pv"), "tail"), "alpha_range");
        const cJSON *dc = cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "analysis"), "pv"), "tail"),
                                                                  "dispersion_corrected"), "alpha_range");
        char acc[64] = "none accepted", dacc[64] = "none accepted";
        if (cJSON_GetArraySize(ar) == 2) {
            snprintf(acc, sizeof acc, "%.2f - %.2f", cJSON_GetArrayItem(ar, 0)->valuedouble, cJSON_GetArrayItem(ar, 1)->valuedouble);
        }
        if (cJSON_GetArraySize(dc) == 2) {
            snprintf(dacc, sizeof dacc, "%.2f - %.2f", cJSON_GetArrayItem(dc, 0)->valuedouble, cJSON_GetArrayItem(dc, 1)->valuedouble);
        }
        fprintf(f.f, "### Fig. 5.3: tails of P(v), 2D RFM, phi = 0.53, eps_n = eps_t = 0.1\n\n"
                     "%s; P(v) per component with sqrt(X) errors, stretched exponential (5.5) over counts 50-50 000 "
                     "(`pv` observable).\n\n| quantity | granule | thesis |\n|---|---|---|\n",
                quick ? "N = 3000, L = 0.2 m, 1 s + 1 s" : "N = 12000, L = 0.4 m, 1 s + 10 s");
        fprintf(f.f, "| alpha, free fit | %.3f +- %.3f | 1.10 +- 0.15 (Table 5.2) |\n",
                gr_summary_number(j, "analysis.pv.tail.free.alpha"), gr_summary_number(j, "analysis.pv.tail.free.alpha_err"));
        fprintf(f.f, "| accepted alpha (chi2/dof < 1.2) | %s | Table 5.1 window |\n| accepted, errors scaled by the measured over-dispersion | %s | |\n",
                acc, dacc);
    }
    fprintf(f.f, "| T (m^2/s^2) | %.4f +- %.4f | |\n", gr_summary_number(j, "T_mean"), gr_summary_number(j, "T_stderr"));
    cJSON_Delete(j);
    if (rc) {
        gr_file_abandon(&f);
        return rc;
    }
    return finish_report(&f, t0, quick, err);
}

int cmd_reproduce(int argc, char **argv)
{
    const char *name = NULL, *out = "out/reproduce", *src = ".";
    bool quick = true;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return EXIT_OK;
        } else if (!strcmp(argv[i], "--fidelity") && i + 1 < argc) {
            const char *v = argv[++i];
            if (strcmp(v, "quick") && strcmp(v, "full")) {
                cli_error("reproduce: --fidelity quick or full, got '%s'", v);
                return EXIT_REFUSED;
            }
            quick = !strcmp(v, "quick");
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            out = argv[++i];
        } else if (!strcmp(argv[i], "--source") && i + 1 < argc) {
            src = argv[++i];
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            if (!cli_threads(argv[++i])) {
                return EXIT_REFUSED;
            }
        } else if (argv[i][0] != '-' && !name) {
            name = argv[i];
        } else {
            cli_error("reproduce: unexpected argument %s", argv[i]);
            return EXIT_REFUSED;
        }
    }
    const char *names[] = {"fig2.10", "fig3.2", "fig4.2", "fig5.3"};
    bool all = name && !strcmp(name, "all"), known = all;
    for (int k = 0; k < 4 && name; k++) {
        known |= !strcmp(name, names[k]);
    }
    if (!known) {
        if (name) {
            cli_error("reproduce: unknown figure '%s'; one of fig2.10, fig3.2, fig4.2, fig5.3, all", name);
        }
        usage(stderr);
        return EXIT_REFUSED;
    }
    char absolute[4096];
    if (realpath(src, absolute)) {
        src = absolute; /* the sweep file resolves its scene relative to itself */
    }
    char check[1200];
    snprintf(check, sizeof check, "%.1000s/docs/scenes/rfm-1d.ini", src);
    if (access(check, R_OK) != 0) {
        cli_error("reproduce: %s not found; run from the source tree or pass --source DIR", check);
        return EXIT_REFUSED;
    }
    int failures = 0;
    for (int k = 0; k < 4; k++) {
        if (!all && strcmp(name, names[k])) {
            continue;
        }
        char dir[1200];
        snprintf(dir, sizeof dir, "%s/%s", out, names[k]);
        gr_error err = {0};
        int rc = k == 0 ? fig2_10(src, dir, quick, &err) : k == 1 ? fig3_2(src, dir, quick, &err)
                                                                : rfm2d(src, dir, quick, k == 2, &err);
        if (rc) {
            cli_error("reproduce %s: %s", names[k], err.message);
            failures++;
            continue;
        }
        char path[1300];
        snprintf(path, sizeof path, "%s/report.md", dir);
        FILE *f = fopen(path, "r");
        char buf[4096];
        size_t nread;
        while (f && (nread = fread(buf, 1, sizeof buf, f)) > 0) {
            fwrite(buf, 1, nread, stdout);
        }
        if (f) {
            fclose(f);
        }
        printf("\n");
    }
    return failures ? EXIT_FAILED : EXIT_OK;
}
