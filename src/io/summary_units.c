/* Units of summary.json's scalars, for the tables that copy them (compare.csv, sweep.csv) and
 * declare every column's unit in the sidecar NAME.meta.json (io/files.h gr_file_column). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/summary_read.h"

/* By the last name of the dotted path (array indices dropped); "" where the name alone does not
 * say (the caller then leaves the column without a unit). */
static const struct {
    const char *name, *unit;
} by_name[] = {
    /* the run */
    {"T_mean", "m2 s-2"},
    {"T_stderr", "m2 s-2"},
    {"T_blocking_stderr", "m2 s-2"},
    {"T_rot_final", "m2 s-2"},
    {"T_ref", "m2 s-2"},
    {"wall_seconds", "s"},
    {"checkpoint_seconds", "s"},
    {"simulated_seconds", "s"},
    {"particle_steps_per_second", "s-1"},
    {"events_per_second", "s-1"},
    {"energy_injected", "J"},
    {"energy_dissipated", "J"},
    {"energy_injection_rate_expected", "W"},
    {"kinetic", "J"},
    {"elastic", "J"},
    {"initial", "J"},
    {"injected", "J"},
    {"dissipated_normal", "J"},
    {"dissipated_tangential", "J"},
    {"dissipated_friction", "J"},
    {"floor_energy", "J"},
    {"removed_com", "J"},
    {"residual", "J"},
    {"rotational", "J"},
    {"dt", "s"},
    {"t_c", "s"},
    {"gamma_n", "kg s-1"},
    {"gamma_t", "kg s-1"},
    /* velocities and the P(v) fits (analysis.pv, docs/analysis-velocity.md) */
    {"v_max", "m s-1"},
    {"v_min", "m s-1"},
    {"bin_width", "m s-1"},
    {"v_rms", "m s-1"},
    {"rms", "m s-1"},
    {"v0", "m s-1"},
    {"v0_err", "m s-1"},
    {"v_r", "m s-1"},
    {"v_r_err", "m s-1"},
    {"v_c", "m s-1"},
    {"v_c_err", "m s-1"},
    {"v_A", "m s-1"},
    {"P0", "s m-1"},
    {"A", "s m-1"},
    {"D", "s m-1"},
    {"mean_speed_predicted", "m s-1"},
    {"mean_speed_measured", "m s-1"},
};

/* Pure numbers: counts, flags, exponents, ratios, chi-squares. */
static const char *const pure[] = {
    "T_stderr_converged",
    "samples",
    "checkpoints_written",
    "steps",
    "collisions",
    "neighbour_rebuilds",
    "relative_residual",
    "threads",
    "events_processed",
    "steps_per_contact",
    "zeta",
    "eps_n_exact",
    "max_overlap_now",
    "frames",
    "bins",
    "range",
    "components",
    "T_ref_frames",
    "out_of_range_fraction",
    "counts_min",
    "counts_max",
    "chi2_red_max",
    "n_points",
    "decades",
    "accepted",
    "alpha_range",
    "alpha",
    "alpha_halfwidth",
    "contiguous",
    "alpha_step",
    "alpha_best",
    "chi2_red",
    "v0_over_vrms",
    "dispersion",
    "pairs",
    "converged",
    "alpha_err",
    "dof",
    "v_c_over_v_r",
    "P_vc_over_P0",
    "v_r_over_vrms",
    "v_c_beyond_data",
    "C_alpha_2",
    "C_alpha_1_5",
    "C_alpha_1_16",
    "C1_implied",
    "status_code",
    "collisions_floor",
    "collisions_impact",
    "collisions_tc_elastic",
};

const char *gr_summary_unit(const char *path, char *buf, size_t size)
{
    char p[256];
    snprintf(p, sizeof p, "%s", path);
    for (char *dot = strrchr(p, '.'); dot && dot[1] >= '0' && dot[1] <= '9';
         dot = strrchr(p, '.')) {
        *dot = 0; /* an array element: the array's unit */
    }
    const char *last = strrchr(p, '.') ? strrchr(p, '.') + 1 : p;
    /* analysis.moments.speed.mK and speed_stderr.mK: (m/s)^K */
    if (strstr(p, "moments.") && last[0] == 'm' && last[1] >= '1' && last[1] <= '9') {
        int m = atoi(last + 1);
        snprintf(buf, size, "m%d s-%d", m, m);
        return buf;
    }
    for (size_t i = 0; i < sizeof by_name / sizeof by_name[0]; i++) {
        if (!strcmp(last, by_name[i].name)) {
            return by_name[i].unit;
        }
    }
    for (size_t i = 0; i < sizeof pure / sizeof pure[0]; i++) {
        if (!strcmp(last, pure[i])) {
            return "1";
        }
    }
    return NULL;
}
