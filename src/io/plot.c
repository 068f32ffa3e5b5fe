/* Plots of a run folder, drawn by gnuplot (the pngcairo terminal of Debian's gnuplot-nox):
 * temperature.png (T(t) with its running average, as Figs. 2.7-2.8) and ledger.png (energy
 * injected, dissipated by each mechanism, kinetic + elastic and the balance residual). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/files.h"
#include "io/plot.h"

/* Okabe-Ito's colour-blind-safe set without its yellow, orange and sky blue, completed by black, wine,
 * brown and purple: every colour has a contrast ratio of at least 3:1 against white. */
const char *const gr_plot_palette[GR_PLOT_COLOURS] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                                     "#000000", "#882255", "#8c510a", "#5e3c99"};

void gr_plot_series_style(int k, char *buf, size_t size)
{
    k = k < 0 ? 0 : k;
    snprintf(buf, size, "lc rgb '%s' dt %d lw 2", gr_plot_palette[k % GR_PLOT_COLOURS], 1 + k % 4);
}

static int gnuplot_available(void)
{
    return system("command -v gnuplot >/dev/null 2>&1") == 0;
}

int gr_plot_run(const char *dir, int dim, char *note, size_t note_size)
{
    (void)dim;
    if (!gnuplot_available()) {
        snprintf(note, note_size, "skipped: gnuplot not found (apt-get install gnuplot-nox)");
        return 1;
    }
    FILE *g = popen("gnuplot 2>&1 >/dev/null", "w");
    if (!g) {
        snprintf(note, note_size, "skipped: could not start gnuplot");
        return 1;
    }
    fprintf(g,
            "set terminal pngcairo size 1000,640 font 'Sans,11'\n"
            "set datafile separator ','\n"
            "set key top right\n"
            "set grid\n"
            "set output '%s/temperature.png.tmp'\n"
            "set title 'Granular temperature (eq. 2.19)'\n"
            "set xlabel 't (s)'\nset ylabel 'T (m^2/s^2)'\n"
            "plot '%s/temperature.csv' skip 1 using 1:2 with lines lc rgb '#9ab' title 'T(t)', "
            "'' skip 1 using 1:3 with lines lw 2 lc rgb '#c33' title 'running mean (sampling)'\n"
            "set output '%s/ledger.png.tmp'\n"
            "set title 'Energy ledger'\n"
            "set ylabel 'energy (J)'\n"
            "plot '%s/ledger.csv' skip 1 using 1:4 with lines lw 2 title 'injected by noise', "
            "'' skip 1 using 1:($5+$6+$7) with lines lw 2 title 'dissipated (all)', "
            "'' skip 1 using 1:5 with lines title 'dissipated normal', "
            "'' skip 1 using 1:($6+$7) with lines title 'dissipated tangential+friction', "
            "'' skip 1 using 1:($2+$3) with lines title 'kinetic + elastic', "
            "'' skip 1 using 1:9 with lines lc rgb 'black' dt 2 title 'residual'\n"
            "set output\n",
            dir, dir, dir, dir);
    int rc = pclose(g);
    char from[1200], to[1200];
    const char *names[] = {"temperature.png", "ledger.png"};
    for (int i = 0; i < 2; i++) {
        snprintf(from, sizeof from, "%s/%s.tmp", dir, names[i]);
        snprintf(to, sizeof to, "%s/%s", dir, names[i]);
        if (rc != 0 || rename(from, to) != 0) {
            remove(from);
            snprintf(note, note_size, "failed: gnuplot could not draw %s", names[i]);
            return 1;
        }
    }
    return 0;
}

int gr_plot_script(const char *dir, const char *png_name, const char *body, char *note, size_t note_size)
{
    if (!gnuplot_available()) {
        snprintf(note, note_size, "skipped: gnuplot not found (apt-get install gnuplot-nox)");
        return 1;
    }
    /* keep the body beside the picture so `granule plot DIR` can redraw it */
    char gp[300];
    snprintf(gp, sizeof gp, "%.*s.gp", (int)(strlen(png_name) > 4 ? strlen(png_name) - 4 : strlen(png_name)), png_name);
    gr_file script;
    gr_error gp_err = {0};
    if (gr_file_open(&script, dir, gp, &gp_err) == GR_OK) {
        fprintf(script.f, "# granule: gnuplot body of %s (run inside this folder); granule plot DIR redraws it\n%s\n", png_name, body);
        if (gr_file_commit(&script, &gp_err) != GR_OK) {
            snprintf(note, note_size, "failed: %s", gp_err.message);
            return 1;
        }
    }
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "cd '%s' && gnuplot >/dev/null 2>&1", dir);
    FILE *g = popen(cmd, "w");
    if (!g) {
        snprintf(note, note_size, "skipped: could not start gnuplot");
        return 1;
    }
    fprintf(g, "set terminal pngcairo size 1000,640 font 'Sans,11'\nset datafile separator ','\n"
               "set grid\nset output '%s.tmp'\n%s\nset output\n", png_name, body);
    int rc = pclose(g);
    char from[1200], to[1200];
    snprintf(from, sizeof from, "%s/%s.tmp", dir, png_name);
    snprintf(to, sizeof to, "%s/%s", dir, png_name);
    if (rc != 0 || rename(from, to) != 0) {
        remove(from);
        snprintf(note, note_size, "failed: gnuplot could not draw %s", png_name);
        return 1;
    }
    return 0;
}
