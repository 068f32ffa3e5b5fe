/* Scene files: INI (inih) + `--set section.key=value` overrides -> a validated gr_scene.
 *
 * Every engine key is one row of `keys` below (type, default, unit, range, doc); [model] keys
 * come from the models' own parameter tables. The same rows fill defaults, validate input and
 * generate docs/scene-keys.md, so documentation cannot drift from the parser. Every error names
 * where the value came from (file and line, or the --set argument), the key and the allowed
 * range. */
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "granule/scene.h"
#include "io/files.h"
#include "scene/scene_lines.h"
#include "scene/scene_species.h"

typedef enum {
    K_DOUBLE,
    K_INT,
    K_BOOL,
    K_UINT64,
    K_STRING,
    K_ENUM,
    K_NORMAL,
    K_TANGENTIAL,
    K_ROLLING,
    K_INTEGRATOR,
    K_DRIVING,
    K_LIST,
    K_NUMBERS /* gr_number_list: numbers in [min, max], comma-separated */
} key_type;

typedef struct scene_key {
    const char *section;
    const char *name;
    const char *unit;
    key_type type;
    const char *def; /* default, parsed like user input; NULL = unset */
    double min, max;
    bool min_open, max_open;
    const char *choices; /* K_ENUM: "a|b|c" in enum order */
    const char *doc;
    size_t offset;
} scene_key;

/* [system] reduced_length of a 1D scene that gives no length key, m */
#define GR_DEFAULT_REDUCED_LENGTH_1D 1.0

/* the volume of a sphere of radius r, and close packing of spheres (FCC), pi / (3 sqrt 2) */
#define FCC_PHI 0.74048048969306104

#define OFF(f) offsetof(gr_scene, f)
static const scene_key keys[] = {
    {"system", "dim", "", K_INT, "2", 1, 3, false, false, NULL,
     "1 (periodic line), 2 (periodic square) or 3 (spheres in a periodic cube; what runs in 3D: "
     "docs/three-dimensions.md)",
     OFF(dim)},
    {"system", "N", "", K_INT, "2000", 1, 1e8, false, false, NULL, "number of particles", OFF(N)},
    {"system", "L", "m", K_DOUBLE, "0.2", 0, INFINITY, true, true, NULL,
     "box side (2D, 3D) or ring length (1D); give at most one of L, packing_fraction, "
     "reduced_length; the default is 2D's: a 1D scene without any gets reduced_length = 1 m",
     OFF(L)},
    {"system", "packing_fraction", "", K_DOUBLE, NULL, 0, 0.9069, true, false, NULL,
     "2D and 3D: sets L from phi = N pi r^2 / L^2 (2.24; hexagonal maximum 0.9069) in 2D, "
     "from phi = N (4/3) pi r^3 / L^3 (FCC maximum 0.7405) in 3D",
     OFF(packing_fraction)},
    {"system", "reduced_length", "m", K_DOUBLE, NULL, 0, INFINITY, false, true, NULL,
     "1D only: sets L from L' = L - N d (sec. 3.1); a 1D scene without L or reduced_length gets 1 "
     "m",
     OFF(reduced_length)},
    /* bounded so that d = 2 r, N pi r^2, k_s / m and the box stay finite and non-zero */
    {"system", "radius", "m", K_DOUBLE, "1.5e-3", 1e-100, 1e100, false, false, NULL,
     "particle radius r (Table 2.2)", OFF(radius)},
    {"system", "mass", "kg", K_DOUBLE, "3.53e-5", 1e-100, 1e100, false, false, NULL,
     "particle mass M (Table 2.2)", OFF(mass)},
    {"placement", "kind", "", K_ENUM, "hexagonal", 0, 0, false, false,
     "hexagonal|square|uniform|cluster|random|cubic|fcc",
     "initial placement (sec. 2.1.4, Fig. 2.4); default hexagonal in 2D, uniform in 1D, cubic in "
     "3D: hexagonal or square bed from the bottom of the box, uniform = equal area (2D) or spacing "
     "L/N (1D) per particle, cluster = one touching cluster in the middle, random = random "
     "sequential addition (phi <= 0.5; 3D: phi <= 0.3), cubic = simple cubic lattice (3D only, "
     "phi <= 0.5236), fcc = face-centred cubic lattice (3D only, phi <= 0.7405)",
     OFF(placement)},
    {"placement", "v0", "m/s", K_DOUBLE, "0.1", 0, INFINITY, false, true, NULL,
     "initial velocities v0 * U(-0.5, 0.5) per component (sec. 2.2.2), mean removed", OFF(v0)},
    {"placement", "omega0", "rad/s", K_DOUBLE, "0", 0, INFINITY, false, true, NULL,
     "[model] rotation = true only: initial angular velocities omega0 * U(-0.5, 0.5) per disc "
     "(rotational temperature I omega0^2 / 12 M); 3D: per component of each sphere's angular "
     "velocity vector (I <|w|^2> / M = 3 I omega0^2 / 12 M); 0 = not spinning",
     OFF(omega0)},
    {"model", "normal", "", K_NORMAL, "spring_dashpot", 0, 0, false, false, NULL,
     "normal collision model (granule models lists them)", OFF(normal)},
    {"model", "tangential", "", K_TANGENTIAL, "none", 0, 0, false, false, NULL,
     "tangential collision model: none, tangential_dashpot, sliding_friction or tangential_spring "
     "(granule models lists them; 2D and 3D)",
     OFF(tangential)},
    {"model", "rolling", "", K_ROLLING, "none", 0, 0, false, false, NULL,
     "none or rolling_friction: rolling resistance, a torque pair against w_i - w_j (needs "
     "rotation = true; docs/models.md)",
     OFF(rolling)},
    {"driving", "kind", "", K_DRIVING, "rfm", 0, 0, false, false, NULL,
     NULL /* the registry's summaries */, OFF(driving)},
    /* walls and gravity (src/core/walls.c, docs/systems-walls-gravity.md); the defaults are the
     * thesis's periodic box, and a scene that keeps them writes neither section (scene.ini, hash) */
    {"boundary", "x", "", K_ENUM, "periodic", 0, 0, false, false, "periodic|walls",
     "along x: periodic (the thesis), or flat walls at x = 0 and x = L (a wall is a grain of "
     "infinite mass and radius under the scene's normal and tangential laws, with [boundary] "
     "eps_n, eps_t, mu; every integrator, the hybrid in 2D and 3D)",
     OFF(boundary[0])},
    {"boundary", "y", "", K_ENUM, "periodic", 0, 0, false, false, "periodic|walls",
     "along y (2D and 3D): periodic, or flat walls at y = 0 and y = L", OFF(boundary[1])},
    {"boundary", "z", "", K_ENUM, "periodic", 0, 0, false, false, "periodic|walls",
     "along z (3D only): periodic, or flat walls at z = 0 and z = L", OFF(boundary[2])},
    {"boundary", "vibrate", "", K_ENUM, "none", 0, 0, false, false, "none|x|y|z",
     "none, or the axis whose wall at 0 (the floor) moves as amplitude sin(2 pi frequency t); "
     "that axis needs walls; the wall's work is the ledger's wall_work",
     OFF(vibrate)},
    {"boundary", "amplitude", "m", K_DOUBLE, "0", 0, INFINITY, false, true, NULL,
     "vibrate: the wall's amplitude A; below L / 4", OFF(amplitude)},
    {"boundary", "frequency", "Hz", K_DOUBLE, "0", 0, INFINITY, false, true, NULL,
     "vibrate: the wall's frequency f (peak acceleration A (2 pi f)^2)", OFF(frequency)},
    {"boundary", "motion", "", K_ENUM, "sine", 0, 0, false, false, "sine|sawtooth",
     "vibrate: sine = A sin(2 pi f t); sawtooth = A (2 frac(f t + 1/2) - 1): from 0 at t = 0 it "
     "rises at the constant speed 2 A f to A at t = 1 / (2 f), drops instantly to -A and rises "
     "again, every period 1 / f",
     OFF(motion)},
    {"boundary", "eps_n", "", K_DOUBLE, NULL, 0, 1, false, false, NULL,
     "the walls' normal coefficient of restitution (a grain against a wall of infinite mass, "
     "calibrated by the normal law at m12 = M); unset: [model] eps_n, the particles'",
     OFF(wall_eps_n)},
    {"boundary", "eps_t", "", K_DOUBLE, NULL, 0, 1, false, false, NULL,
     "the walls' tangential coefficient of restitution (tangential_dashpot); unset: [model] eps_t",
     OFF(wall_eps_t)},
    {"boundary", "mu", "", K_DOUBLE, NULL, 0, INFINITY, false, true, NULL,
     "the walls' friction coefficient (sliding_friction, tangential_spring); unset: [model] mu",
     OFF(wall_mu)},
    {"gravity", "gx", "m/s^2", K_DOUBLE, "0", -1000, 1000, false, false, NULL,
     "gravitational acceleration along x (a constant force M gx on every grain); non-zero needs "
     "[boundary] x = walls; -9.81 pulls towards the wall at x = 0",
     OFF(gravity[0])},
    {"gravity", "gy", "m/s^2", K_DOUBLE, "0", -1000, 1000, false, false, NULL,
     "gravitational acceleration along y (2D and 3D); non-zero needs [boundary] y = walls; -9.81 "
     "pulls towards the floor at y = 0",
     OFF(gravity[1])},
    {"gravity", "gz", "m/s^2", K_DOUBLE, "0", -1000, 1000, false, false, NULL,
     "gravitational acceleration along z (3D only); non-zero needs [boundary] z = walls; -9.81 "
     "pulls towards the floor at z = 0",
     OFF(gravity[2])},
    /* species (src/core/species.c, docs/mixtures.md): unset, the [system] radius and mass */
    {"species", "radius", "m", K_NUMBERS, "", 1e-100, 1e100, false, false, NULL,
     "radii of the species, comma-separated (2 to 8 species; e.g. 1.5e-3, 3e-3): each grain has "
     "its species' radius and mass instead of [system] radius and mass; packing_fraction counts "
     "the actual radii; unset = one species",
     OFF(species_radius)},
    {"species", "mass", "kg", K_NUMBERS, "", 1e-100, 1e100, false, false, NULL,
     "masses of the species, one per radius; give mass or density", OFF(species_mass)},
    {"species", "density", "kg/m^2", K_NUMBERS, "", 1e-100, 1e100, false, false, NULL,
     "instead of mass: the discs' areal density, mass = density pi r^2 (2D); in 3D kg/m^3, mass = "
     "density (4/3) pi r^3; in 1D kg/m, mass = density 2 r",
     OFF(species_density)},
    {"species", "fraction", "", K_NUMBERS, "", 0, 1, false, false, NULL,
     "number fractions of the species, summing to 1 (grains: round(fraction N), the rest to the "
     "last species); unset = equal fractions",
     OFF(species_fraction)},
    {"species", "distribution", "", K_ENUM, "none", 0, 0, false, false, "none|uniform|lognormal",
     "instead of radius lists: a continuous radius distribution, every grain its own radius drawn "
     "from the seed in [radius_min, radius_max] (uniform, or lognormal of median radius_median and "
     "sigma radius_sigma of ln r, truncated to the bounds) and mass from density (one value); "
     "none = species lists or one species",
     OFF(size_distribution)},
    {"species", "radius_min", "m", K_DOUBLE, "0", 0, 1e100, false, false, NULL,
     "distribution: the smallest radius (> 0); hertz's k_h is that of two such grains",
     OFF(radius_min)},
    {"species", "radius_max", "m", K_DOUBLE, "0", 0, 1e100, false, false, NULL,
     "distribution: the largest radius (> radius_min)", OFF(radius_max)},
    {"species", "radius_median", "m", K_DOUBLE, "0", 0, 1e100, false, false, NULL,
     "distribution = lognormal: the median radius of the untruncated lognormal (> 0)",
     OFF(radius_median)},
    {"species", "radius_sigma", "", K_DOUBLE, "0", 0, 10, false, false, NULL,
     "distribution = lognormal: the standard deviation of ln r (> 0)", OFF(radius_sigma)},
    {"noise", "D", "N^2 s", K_DOUBLE, "1e-8", 0, INFINITY, false, true, NULL,
     "noise strength (2.15, 2.22); 0 switches the random force off (Table 2.2: 1e-8)", OFF(D)},
    {"noise", "mode", "", K_ENUM, "symmetrised", 0, 0, false, false, "none|symmetrised|com",
     "symmetrised: forces shifted to sum to zero every step (2.18); com: centre-of-mass velocity "
     "removed every com_interval (sec. 2.3.1); none: no random force",
     OFF(noise_mode)},
    {"noise", "com_interval", "s", K_DOUBLE, "1e-3", 0, INFINITY, true, true, NULL,
     "com mode: time between centre-of-mass velocity removals", OFF(com_interval)},
    {"noise", "precision", "", K_ENUM, "double", 0, 0, false, false, "double|single",
     "the normals of the random force: double, or single (float normals, one 32-bit Philox word "
     "each through an inverse CDF: same statistics, tails cut at 6.34 sigma, a different "
     "sequence, about 1.5x faster in 1D; verlet only; docs/performance.md, Single-precision "
     "noise)",
     OFF(noise_precision)},
    {"integrator", "kind", "", K_INTEGRATOR, "verlet", 0, 0, false, false, NULL,
     NULL /* the registry's summaries */, OFF(integrator)},
    {"integrator", "dt", "s", K_DOUBLE, NULL, 0, INFINITY, true, true, NULL,
     "time step; give dt or steps_per_contact, not both", OFF(dt)},
    {"integrator", "steps_per_contact", "", K_DOUBLE, "50", 10, 1e9, false, false, NULL,
     "dt = t_c / steps_per_contact, t_c = duration of a binary contact; fewer than 10 is refused "
     "(sec. 2.1.2)",
     OFF(steps_per_contact)},
    {"integrator", "force_dt", "", K_BOOL, "false", 0, 1, false, false, NULL,
     "accept a dt larger than t_c / 10 (results will be wrong; for stability studies)",
     OFF(force_dt)},
    {"integrator", "skin", "d", K_DOUBLE, "0.3", 0, 10, false, false, NULL,
     "Verlet-list skin in diameters; the list is rebuilt when a particle has moved skin/2; 0 "
     "rebuilds the cell list every step",
     OFF(skin)},
    {"integrator", "free_flight", "", K_ENUM, "exact", 0, 0, false, false, "exact|kicks",
     "event/hybrid: how the random force drives free flight: exact = jointly Gaussian velocity and "
     "position increments of the random-acceleration process over each interval (exact for free "
     "flight between interval ends; with kind = event it under-injects energy when collisions fall "
     "inside intervals), kicks = a Gaussian velocity kick of variance 2 D tau / M^2 per component "
     "every kick_interval (the random force's work exact in expectation across collisions). "
     "Default exact for hybrid, kicks for event (docs/event-driven.md); ignored (with a warning) "
     "under [driving] kind = langevin, whose exact OU step acts at each window's end",
     OFF(free_flight)},
    {"integrator", "kick_interval", "s", K_DOUBLE, "1e-4", 0, INFINITY, true, true, NULL,
     "event/hybrid: interval tau between noise (or Langevin bath) updates of free particles "
     "(event) or length of a "
     "free-flight window (hybrid: a whole multiple of dt when given; left unset, 1e-4 s rounded to "
     "whole steps); the accuracy knob of docs/event-driven.md",
     OFF(kick_interval)},
    {"run", "warmup", "s", K_DOUBLE, "1.0", 0, INFINITY, false, true, NULL,
     "simulated time before sampling starts", OFF(warmup)},
    {"run", "duration", "s", K_DOUBLE, "10.0", 0, INFINITY, false, true, NULL,
     "simulated time of sampling", OFF(duration)},
    {"run", "sample_every", "s", K_DOUBLE, "1e-3", 0, INFINITY, true, true, NULL,
     "interval between samples (uniform in time)", OFF(sample_every)},
    {"run", "seed", "", K_UINT64, "1", 0, 1.8446744073709552e19, false, false, NULL,
     "random seed: placement, initial velocities and noise are pure functions of it", OFF(seed)},
    {"run", "ledger_tolerance", "", K_DOUBLE, "0.05", 0, 1, false, false, NULL,
     "stop the run as unstable when the energy ledger's residual exceeds this fraction of the "
     "energy injected + dissipated (it is ~2e-3 at the thesis dt; 0 = no check)",
     OFF(ledger_tolerance)},
    {"run", "checkpoint_every", "s", K_DOUBLE, "0", 0, INFINITY, false, true, NULL,
     "simulated time between checkpoints (taken at the next sample; docs/checkpoints.md); 0 = none",
     OFF(checkpoint_every)},
    {"run", "checkpoint_wall", "s", K_DOUBLE, "1800", 0, INFINITY, false, true, NULL,
     "wall-clock time between checkpoints (taken at the next sample); 0 = none. Checkpoints never "
     "change results",
     OFF(checkpoint_wall)},
    {"run", "wall_limit", "s", K_DOUBLE, "0", 0, INFINITY, false, true, NULL,
     "wall-clock budget: write a checkpoint and stop (exit status 4) before it runs out; resume "
     "with granule run --resume DIR; 0 = none",
     OFF(wall_limit)},
    {"run", "progress", "", K_BOOL, "true", 0, 1, false, false, NULL,
     "progress line with ETA on a terminal (never in CI logs or when stderr is not a terminal)",
     OFF(progress)},
    {"analysis", "observables", "", K_LIST, "", 0, 0, false, false, NULL,
     "statistics to accumulate while sampling, comma-separated (granule observables lists them); "
     "empty = temperature only",
     OFF(observables)},
    {"output", "dir", "", K_STRING, "out", 0, 0, false, false, NULL,
     "output folder (granule run --out overrides it)", OFF(out_dir)},
    {"output", "snapshot_every", "s", K_DOUBLE, "0", 0, INFINITY, false, true, NULL,
     "interval between frames of the trajectory (output.trajectory), a whole number of steps, "
     "independent of sample_every; 0 = none",
     OFF(snapshot_every)},
    {"output", "trajectory", "", K_ENUM, "snapshots", 0, 0, false, false, "snapshots|xyz|h5md",
     "format of the frames written every snapshot_every (docs/trajectories.md): snapshots = one "
     "extended-XYZ file per frame (snapshots/snap_NNNNNN.xyz), xyz = one multi-frame extended-XYZ "
     "file (snapshots/trajectory.xyz), h5md = one H5MD file (trajectory.h5: HDF5, chunked, "
     "deflate-compressed; MDAnalysis and OVITO read it)",
     OFF(trajectory)},
    {"output", "plots", "", K_BOOL, "true", 0, 1, false, false, NULL,
     "write PNG plots with gnuplot at the end of the run (skipped with a note if gnuplot is "
     "missing)",
     OFF(plots)},
};
#undef OFF
static const int n_keys = sizeof keys / sizeof keys[0];

/* The registered integrators with (or without) instantaneous collisions, joined by sep. */
static void integrator_names_where(bool instantaneous, const char *sep, char *buf, size_t cap)
{
    size_t len = 0;
    buf[0] = 0;
    for (int j = 0; gr_integrators[j] && len < cap; j++) {
        if (gr_integrators[j]->instantaneous == instantaneous) {
            int w = snprintf(buf + len, cap - len, "%s%s", len ? sep : "", gr_integrators[j]->name);
            len += w > 0 ? (size_t)w : 0;
        }
    }
}

/* The registered normal models that are (or are not) event rules, joined by sep. */
static void normal_names_where(bool event_rule, const char *sep, char *buf, size_t cap)
{
    size_t len = 0;
    buf[0] = 0;
    for (int j = 0; gr_models[j] && len < cap; j++) {
        const gr_model *m = gr_models[j];
        if ((m->kind & GR_MODEL_NORMAL) && ((m->kind & GR_MODEL_EVENT) != 0) == event_rule) {
            int w = snprintf(buf + len, cap - len, "%s%s", len ? sep : "", m->name);
            len += w > 0 ? (size_t)w : 0;
        }
    }
}

/* ---------- values ---------- */

typedef struct where {
    const char *file; /* NULL for --set */
    int line;
    const char *assignment; /* the --set argument */
} where;

static int fail_at(gr_error *err, const where *w, const char *section, const char *name,
                   const char *fmt, const char *detail)
{
    char loc[1200];
    if (w->file && w->line > 0) {
        snprintf(loc, sizeof loc, "%s:%d", w->file, w->line);
    } else if (w->file) {
        snprintf(loc, sizeof loc, "%s", w->file);
    } else {
        snprintf(loc, sizeof loc, "--set %s", w->assignment ? w->assignment : "");
    }
    char msg[900];
    snprintf(msg, sizeof msg, fmt, detail);
    return GR_FAIL(err, GR_EINVAL, "%s: [%s] %s: %s", loc, section, name, msg);
}

static void range_text(char *buf, size_t n, double min, double max, bool min_open, bool max_open)
{
    snprintf(buf, n, "%c%g, %s%c", min_open ? '(' : '[', min, isinf(max) ? "inf" : "",
             max_open ? ')' : ']');
    if (!isinf(max)) {
        snprintf(buf, n, "%c%g, %g%c", min_open ? '(' : '[', min, max, max_open ? ')' : ']');
    }
}

static bool parse_double(const char *v, double *out)
{
    char *end;
    errno = 0;
    double x = strtod(v, &end);
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    if (end == v || *end || errno == ERANGE || !isfinite(x)) {
        return false;
    }
    *out = x;
    return true;
}

static bool parse_bool(const char *v, bool *out)
{
    static const char *yes[] = {"true", "yes", "on", "1"}, *no[] = {"false", "no", "off", "0"};
    for (int i = 0; i < 4; i++) {
        if (strcasecmp(v, yes[i]) == 0) {
            *out = true;
            return true;
        }
        if (strcasecmp(v, no[i]) == 0) {
            *out = false;
            return true;
        }
    }
    return false;
}

static int check_range(double x, double min, double max, bool min_open, bool max_open)
{
    return !(x < min || (min_open && x == min) || x > max || (max_open && x == max));
}

/* Set a numeric parameter described by (type, range) at `slot`. */
static int set_number(void *slot, key_type type, double min, double max, bool min_open,
                      bool max_open, const char *value, const where *w, const char *section,
                      const char *name, gr_error *err)
{
    char range[96], detail[256];
    range_text(range, sizeof range, min, max, min_open, max_open);
    if (type == K_BOOL) {
        bool b;
        if (!parse_bool(value, &b)) {
            snprintf(detail, sizeof detail, "'%s' is not a boolean; allowed: true | false", value);
            return fail_at(err, w, section, name, "%s", detail);
        }
        *(bool *)slot = b;
        return GR_OK;
    }
    double x;
    if (!parse_double(value, &x)) {
        snprintf(detail, sizeof detail, "'%s' is not a number; allowed range %s", value, range);
        return fail_at(err, w, section, name, "%s", detail);
    }
    if (!check_range(x, min, max, min_open, max_open)) {
        snprintf(detail, sizeof detail, "%s is out of range; allowed range %s", value, range);
        return fail_at(err, w, section, name, "%s", detail);
    }
    if ((type == K_INT || type == K_UINT64) && x != floor(x)) {
        snprintf(detail, sizeof detail, "%s is not an integer; allowed range %s", value, range);
        return fail_at(err, w, section, name, "%s", detail);
    }
    /* integers are decimal digits: "0x1p5", "3.2e1" or "1e3" must not become another N or seed
     * (found by tests/fuzz and issue 39); "1000.0" is 1000 */
    const char *digits = value + strspn(value, " \t");
    digits += type == K_INT && *digits == '-';
    const size_t n_digits = strspn(digits, "0123456789");
    const char *end = digits + n_digits;
    if (*end == '.' && n_digits > 0) {
        end += 1 + strspn(end + 1, "0");
    }
    end += strspn(end, " \t");
    if ((type == K_INT || type == K_UINT64) && (n_digits == 0 || *end)) {
        snprintf(detail, sizeof detail,
                 "%s is not an integer written in decimal digits; allowed range %s", value,
                 type == K_INT ? range : "[0, 18446744073709551615]");
        return fail_at(err, w, section, name, "%s", detail);
    }
    if (type == K_INT) {
        *(int *)slot = (int)x;
    } else if (type == K_UINT64) {
        errno = 0;
        unsigned long long u = strtoull(value, NULL, 10);
        if (errno == ERANGE) {
            snprintf(detail, sizeof detail,
                     "%s is not an integer written in decimal digits; allowed range [0, "
                     "18446744073709551615]",
                     value);
            return fail_at(err, w, section, name, "%s", detail);
        }
        *(uint64_t *)slot = u;
    } else {
        *(double *)slot = x;
    }
    return GR_OK;
}

static const gr_param *find_model_param(const char *name, const gr_model **owner)
{
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            if (strcmp(gr_models[m]->params[i].name, name) == 0) {
                *owner = gr_models[m];
                return &gr_models[m]->params[i];
            }
        }
    }
    return NULL;
}

static const gr_param *find_driving_param(const char *name, const gr_driving_type **owner)
{
    for (int m = 0; gr_drivings[m]; m++) {
        for (int i = 0; i < gr_drivings[m]->n_params; i++) {
            if (strcmp(gr_drivings[m]->params[i].name, name) == 0) {
                *owner = gr_drivings[m];
                return &gr_drivings[m]->params[i];
            }
        }
    }
    return NULL;
}

/* The allowed range of a [model] key that several models share, e.g. "[0, 1] (hard_sphere: (0, 1])":
 * the first model's range, then each model whose own range differs (the scene may not have named
 * its model yet when the key is read). */
static void model_param_ranges(const char *name, const gr_param *first, char *buf, size_t n)
{
    range_text(buf, n, first->min, first->max, first->min_open, first->max_open);
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            const gr_param *q = &gr_models[m]->params[i];
            if (strcmp(q->name, name) != 0 ||
                (q->min == first->min && q->max == first->max && q->min_open == first->min_open &&
                 q->max_open == first->max_open)) {
                continue;
            }
            char own[64];
            size_t len = strlen(buf);
            range_text(own, sizeof own, q->min, q->max, q->min_open, q->max_open);
            snprintf(buf + len, n - len, " (%s: %s)", gr_models[m]->name, own);
        }
    }
}

/* Whether model m's parameter i was already listed by an earlier model (several share a key:
 * eps_n, rotation, ...), so that a key list names it once. */
static bool model_param_listed_before(int m, int i)
{
    const char *name = gr_models[m]->params[i].name;
    for (int a = 0; a <= m; a++) {
        for (int b = 0; b < (a < m ? gr_models[a]->n_params : i); b++) {
            if (strcmp(gr_models[a]->params[b].name, name) == 0) {
                return true;
            }
        }
    }
    return false;
}

static void append_known_keys(char *buf, size_t n, const char *section)
{
    size_t len = strlen(buf);
    for (int i = 0; i < n_keys; i++) {
        if (strcmp(keys[i].section, section) == 0) {
            len += (size_t)snprintf(buf + len, len < n ? n - len : 0, "%s%s", len ? ", " : "",
                                    keys[i].name);
        }
    }
    if (strcmp(section, "model") == 0) {
        for (int m = 0; gr_models[m]; m++) {
            for (int i = 0; i < gr_models[m]->n_params; i++) {
                if (!model_param_listed_before(m, i)) {
                    len += (size_t)snprintf(buf + len, len < n ? n - len : 0, ", %s",
                                            gr_models[m]->params[i].name);
                }
            }
        }
    }
    for (int m = 0; strcmp(section, "driving") == 0 && gr_drivings[m]; m++) {
        for (int i = 0; i < gr_drivings[m]->n_params; i++) {
            len += (size_t)snprintf(buf + len, len < n ? n - len : 0, ", %s",
                                    gr_drivings[m]->params[i].name);
        }
    }
    if (strcmp(section, "analysis") == 0) {
        for (int o = 0; gr_observables[o]; o++) {
            for (int i = 0; i < gr_observables[o]->n_params; i++) {
                len += (size_t)snprintf(buf + len, len < n ? n - len : 0, ", %s",
                                        gr_observables[o]->params[i].name);
            }
        }
    }
}

/* ---------- loading ---------- */

/* Which of the mutually exclusive keys were given, and where (for messages). */
typedef struct given {
    bool L, packing_fraction, reduced_length, dt, steps_per_contact;
    struct {
        const char *name; /* a [model] parameter's key (its descriptor's name) */
        where at;         /* where it was last given */
    } model_at[64];
    int n_model_at;
    where at_L, at_pf, at_rl, at_dt, at_spc;
    where at[80]; /* where each engine key (by row of `keys`) was last given; file NULL = default */
} given;

typedef struct loader {
    gr_scene *scene;
    given g;
    gr_error *err;
    int rc;
    const char *file;
    int line;
    bool defaults;          /* applying defaults: do not mark keys as given */
    bool has_system;        /* a [system] section was read */
    const char *long_value; /* the value of a long line (scene_lines.h) */
    char seen[128][136];    /* "section.key" seen in the file, to refuse duplicates */
    int n_seen;
} loader;

#define SECTIONS                                                                                   \
    "system, placement, model, driving, boundary, gravity, species, noise, integrator, run, "      \
    "analysis, output"

static bool section_known(const char *section)
{
    for (int i = 0; i < n_keys; i++) {
        if (strcmp(keys[i].section, section) == 0) {
            return true;
        }
    }
    return false;
}

static void warn(gr_scene *s, const char *fmt, const char *a, const char *b);

/* [model] tc: `off` switches the TC rule off (GR_TC_OFF); 0 keeps its old meaning (the matching
 * spring-dashpot's contact time, also the default) but is warned about, since a physicist writing
 * tc = 0 means "off" (issue 37). Returns true when the value was one of these spellings. */
static bool tc_value(loader *ld, const char *value, double *x)
{
    const char *v = value + strspn(value, " \t");
    if (strncasecmp(v, "off", 3) == 0 && v[3 + strspn(v + 3, " \t")] == '\0') {
        *x = GR_TC_OFF;
        return true;
    }
    if (parse_double(value, x) && *x == 0.0) {
        if (!ld->defaults) {
            warn(
                ld->scene,
                "[model] tc = 0 is the contact time of the matching spring-dashpot (k_s, eps_n), "
                "the same as "
                "leaving tc out; it does not switch the TC rule off: write tc = off for that%s%s\n",
                "", "");
        }
        return true;
    }
    return false;
}

static int apply(loader *ld, const char *section, const char *name, const char *value,
                 const where *w)
{
    gr_scene *s = ld->scene;
    gr_error *err = ld->err;
    char detail[700];
    for (int i = 0; i < n_keys; i++) {
        const scene_key *k = &keys[i];
        if (strcmp(k->section, section) != 0 || strcmp(k->name, name) != 0) {
            continue;
        }
        void *slot = (char *)s + k->offset;
        int rc = GR_OK;
        switch (k->type) {
        case K_STRING: {
            size_t cap = sizeof s->out_dir;
            if (strlen(value) == 0 || strlen(value) >= cap) {
                snprintf(detail, sizeof detail,
                         "must be a non-empty path shorter than %zu characters", cap);
                return fail_at(err, w, section, name, "%s", detail);
            }
            /* the saved scene.ini writes "key = value", and inih reads a ';' after whitespace as the
             * start of a comment: such a path would not survive a resume */
            if (value[0] == ';' || strstr(value, " ;") || strstr(value, "\t;")) {
                return fail_at(err, w, section, name, "%s",
                               "a path may not begin with ';' or have one after a space: the saved "
                               "scene.ini would read "
                               "the rest as a comment");
            }
            snprintf((char *)slot, cap, "%s", value);
            break;
        }
        case K_LIST: {
            char buf[256];
            if (strlen(value) >= sizeof buf) {
                return fail_at(err, w, section, name, "%s", "list too long");
            }
            snprintf(buf, sizeof buf, "%s", value);
            char *save = NULL, clean[256] = "";
            for (char *tok = strtok_r(buf, ", \t", &save); tok;
                 tok = strtok_r(NULL, ", \t", &save)) {
                if (!gr_observable_find(tok)) {
                    char list[400] = "";
                    size_t len = 0;
                    for (int j = 0; gr_observables[j]; j++) {
                        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s",
                                                len ? ", " : "", gr_observables[j]->name);
                    }
                    snprintf(detail, sizeof detail, "unknown observable '%s'; choose from %s", tok,
                             list);
                    return fail_at(err, w, section, name, "%s", detail);
                }
                size_t cl = strlen(clean);
                snprintf(clean + cl, sizeof clean - cl, "%s%s", cl ? "," : "", tok);
            }
            snprintf((char *)slot, 256, "%s", clean);
            break;
        }
        case K_NUMBERS: {
            gr_number_list *l = slot;
            const char *c = value;
            l->n = 0;
            while (*c) {
                char *end;
                errno = 0;
                const double v = strtod(c, &end);
                if (end == c || errno || l->n == GR_MAX_SPECIES || !(v >= k->min && v <= k->max) ||
                    (k->min_open && v == k->min)) {
                    snprintf(detail, sizeof detail,
                             "'%s' is not a list of at most %d numbers in %s%g, %g]", value,
                             GR_MAX_SPECIES, k->min_open ? "(" : "[", k->min, k->max);
                    return fail_at(err, w, section, name, "%s", detail);
                }
                l->v[l->n++] = v;
                c = end + strspn(end, ", \t");
            }
            break;
        }
        case K_ENUM: {
            int idx = 0, found = -1;
            const char *c = k->choices;
            while (*c) {
                size_t len = strcspn(c, "|");
                if (strlen(value) == len && strncasecmp(c, value, len) == 0) {
                    found = idx;
                }
                c += len + (c[len] == '|');
                idx++;
            }
            if (found < 0) {
                snprintf(detail, sizeof detail, "'%s' is not allowed; choose one of %s", value,
                         k->choices);
                return fail_at(err, w, section, name, "%s", detail);
            }
            *(int *)slot = found;
            break;
        }
        case K_NORMAL:
        case K_TANGENTIAL:
        case K_ROLLING: {
            const gr_model *m = strcmp(value, "none") == 0 ? NULL : gr_model_find(value);
            gr_model_kind want = k->type == K_NORMAL       ? GR_MODEL_NORMAL
                                 : k->type == K_TANGENTIAL ? GR_MODEL_TANGENTIAL
                                                           : GR_MODEL_ROLLING;
            if ((!m && (k->type == K_NORMAL || strcmp(value, "none") != 0)) ||
                (m && !(m->kind & want))) {
                char list[256] = "";
                size_t len = 0;
                if (k->type != K_NORMAL) {
                    len += (size_t)snprintf(list, sizeof list, "none");
                }
                for (int j = 0; gr_models[j]; j++) {
                    if (gr_models[j]->kind & want) {
                        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s",
                                                len ? " | " : "", gr_models[j]->name);
                    }
                }
                snprintf(detail, sizeof detail, "'%s' is not a %s model; choose one of %s", value,
                         k->type == K_NORMAL       ? "normal"
                         : k->type == K_TANGENTIAL ? "tangential"
                                                   : "rolling",
                         list);
                return fail_at(err, w, section, name, "%s", detail);
            }
            *(const gr_model **)slot = m;
            break;
        }
        case K_INTEGRATOR: { /* the registry (granule/integrator.h) */
            const gr_integrator_type *t = NULL;
            for (int j = 0; gr_integrators[j]; j++) {
                t = strcasecmp(gr_integrators[j]->name, value) == 0 ? gr_integrators[j] : t;
            }
            if (!t) {
                char names[200];
                gr_integrator_names(names, sizeof names, "|");
                snprintf(detail, sizeof detail, "'%s' is not allowed; choose one of %s", value,
                         names);
                return fail_at(err, w, section, name, "%s", detail);
            }
            *(const gr_integrator_type **)slot = t;
            break;
        }
        case K_DRIVING: { /* the registry (granule/driving.h) */
            const gr_driving_type *t = NULL;
            for (int j = 0; gr_drivings[j]; j++) {
                t = strcasecmp(gr_drivings[j]->name, value) == 0 ? gr_drivings[j] : t;
            }
            if (!t) {
                char names[200];
                gr_driving_names(names, sizeof names, "|");
                snprintf(detail, sizeof detail, "'%s' is not allowed; choose one of %s", value,
                         names);
                return fail_at(err, w, section, name, "%s", detail);
            }
            *(const gr_driving_type **)slot = t;
            break;
        }
        default:
            rc = set_number(slot, k->type, k->min, k->max, k->min_open, k->max_open, value, w,
                            section, name, err);
        }
        if (rc != GR_OK) {
            return rc;
        }
        if (!ld->defaults) {
            given *g = &ld->g;
            g->at[i] = *w;
            /* an override replaces whichever member of its group the file gave; two overrides of
             * one group conflict as two lines of a file do (resolve refuses them) */
            if (!w->file && (k->offset == offsetof(gr_scene, L) ||
                             k->offset == offsetof(gr_scene, packing_fraction) ||
                             k->offset == offsetof(gr_scene, reduced_length))) {
                g->L &= !g->at_L.file;
                g->packing_fraction &= !g->at_pf.file;
                g->reduced_length &= !g->at_rl.file;
            }
            if (!w->file && (k->offset == offsetof(gr_scene, dt) ||
                             k->offset == offsetof(gr_scene, steps_per_contact))) {
                g->dt &= !g->at_dt.file;
                g->steps_per_contact &= !g->at_spc.file;
            }
            if (k->offset == offsetof(gr_scene, L)) {
                g->L = true;
                g->at_L = *w;
            }
            if (k->offset == offsetof(gr_scene, packing_fraction)) {
                g->packing_fraction = true;
                g->at_pf = *w;
            }
            if (k->offset == offsetof(gr_scene, reduced_length)) {
                g->reduced_length = true;
                g->at_rl = *w;
            }
            if (k->offset == offsetof(gr_scene, dt)) {
                g->dt = true;
                g->at_dt = *w;
            }
            if (k->offset == offsetof(gr_scene, steps_per_contact)) {
                g->steps_per_contact = true;
                g->at_spc = *w;
            }
        }
        return GR_OK;
    }
    if (strcmp(section, "analysis") == 0) {
        for (int o = 0; gr_observables[o]; o++) {
            for (int q = 0; q < gr_observables[o]->n_params; q++) {
                const gr_param *p = &gr_observables[o]->params[q];
                if (strcmp(p->name, name) == 0) {
                    key_type t = p->type == GR_PARAM_BOOL  ? K_BOOL
                                 : p->type == GR_PARAM_INT ? K_INT
                                                           : K_DOUBLE;
                    char *block = gr_analysis_block(&s->analysis, gr_observables[o]);
                    return set_number(block + p->offset, t, p->min, p->max, p->min_open,
                                      p->max_open, value, w, section, name, err);
                }
            }
        }
    }
    if (strcmp(section, "driving") == 0) {
        const gr_driving_type *owner = NULL;
        const gr_param *p = find_driving_param(name, &owner);
        if (p) {
            return set_number((char *)&s->driving_params + p->offset, K_DOUBLE, p->min, p->max,
                              p->min_open, p->max_open, value, w, section, name, err);
        }
    }
    if (strcmp(section, "model") == 0) {
        const gr_model *owner = NULL;
        const gr_param *p = find_model_param(name, &owner);
        if (p && !ld->defaults) {
            given *g = &ld->g;
            int k = 0;
            while (k < g->n_model_at && strcmp(g->model_at[k].name, p->name) != 0) {
                k++;
            }
            if (k < 64) {
                g->model_at[k].name = p->name;
                g->model_at[k].at = *w;
                g->n_model_at = k < g->n_model_at ? g->n_model_at : k + 1;
            }
        }
        if (p) {
            key_type t = p->type == GR_PARAM_BOOL ? K_BOOL : K_DOUBLE;
            double x;
            if (strcmp(name, "tc") == 0 && tc_value(ld, value, &x)) {
                *(double *)((char *)&s->contact + p->offset) = x; /* hard_sphere's own block */
                return GR_OK;
            }
            if (strcmp(name, "tc") == 0 &&
                (!parse_double(value, &x) ||
                 !check_range(x, p->min, p->max, p->min_open, p->max_open))) {
                return fail_at(err, w, section, name,
                               "'%s' is neither a time in [0, inf) s nor off (off: no TC rule)",
                               value);
            }
            if (t == K_DOUBLE && parse_double(value, &x) &&
                !check_range(x, p->min, p->max, p->min_open, p->max_open)) {
                char ranges[300];
                model_param_ranges(name, p, ranges, sizeof ranges);
                snprintf(detail, sizeof detail, "%s is out of range; allowed range %s", value,
                         ranges);
                return fail_at(err, w, section, name, "%s", detail);
            }
            return set_number((char *)&s->contact + p->offset, t, p->min, p->max, p->min_open,
                              p->max_open, value, w, section, name, err);
        }
    }
    char known[600] = "";
    if (!section_known(section)) {
        snprintf(detail, sizeof detail, "unknown section [%s]; sections: " SECTIONS, section);
        return fail_at(err, w, section, name, "%s", detail);
    }
    append_known_keys(known, sizeof known, section);
    snprintf(detail, sizeof detail, "unknown key; keys of [%s]: %s", section, known);
    return fail_at(err, w, section, name, "%s", detail);
}

static int scene_ini_line(void *user, const char *section, const char *name, const char *value)
{
    loader *ld = user;
    if (ld->rc != GR_OK) {
        return 0;
    }
    where w = {ld->file, ld->line, NULL};
    char id[136];
    snprintf(id, sizeof id, "%.64s.%.64s", section, name);
    for (int i = 0; i < ld->n_seen; i++) {
        if (strcmp(ld->seen[i], id) == 0) {
            ld->rc = fail_at(ld->err, &w, section, name, "%s", "given twice in the same file");
            return 0;
        }
    }
    if (ld->n_seen < 128) {
        snprintf(ld->seen[ld->n_seen++], sizeof ld->seen[0], "%s", id);
    }
    if (ld->long_value && strcmp(value, GR_LONG_VALUE) == 0) {
        value = ld->long_value;
    }
    ld->rc = apply(ld, section, name, value, &w);
    return ld->rc == GR_OK;
}

/* inih reads one line per call of the reader; scene_lines.c hands it whole lines and counts them. */
typedef struct line_reader {
    gr_line_reader lines;
    loader *ld;
} line_reader;

static char *read_line(char *str, int num, void *stream)
{
    line_reader *r = stream;
    char *s = r->ld->rc == GR_OK ? gr_line_read(str, num, &r->lines) : NULL;
    r->ld->line = r->lines.line;
    if (r->lines.problem[0] && r->ld->rc == GR_OK) {
        r->ld->rc =
            GR_FAIL(r->ld->err, GR_EINVAL, "%s:%d: %s", r->ld->file, r->ld->line, r->lines.problem);
    }
    r->ld->long_value = r->lines.long_value;
    if (s) {
        /* inih reports keys, not sections: catch a misspelt section even when it is empty */
        const char *p = s + strspn(s, " \t");
        if (*p == '[' && r->ld->rc == GR_OK) {
            char name[64];
            size_t len = strcspn(p + 1, "]");
            snprintf(name, sizeof name, "%.*s", (int)(len < 63 ? len : 63), p + 1);
            r->ld->has_system |= p[1 + len] == ']' && strcmp(name, "system") == 0;
            if (!section_known(name)) { /* gr_line_read refused a header that is not [name] alone */
                where w = {r->ld->file, r->ld->line, NULL};
                r->ld->rc =
                    fail_at(r->ld->err, &w, name, "", "%s", "unknown section; sections: " SECTIONS);
            }
        }
    }
    return s;
}

/* A scene is a regular file (not a folder, device or pipe) that is not empty. */
/* Open the scene file without blocking on a FIFO; anything but a regular file is refused. */
static int open_scene_file(const char *path, FILE **f, gr_error *err)
{
    int why = 0;
    *f = gr_input_fopen(path, &why);
    if (*f) {
        return GR_OK;
    }
    if (why < 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: not a regular file (a scene is an INI file, see docs/scene-keys.md)",
                       path);
    }
    return GR_FAIL(err, GR_EIO, "%s: cannot open scene file: %s", path, strerror(why));
}

static void apply_defaults(loader *ld)
{
    ld->defaults = true;
    where w = {"<defaults>", 0, NULL};
    for (int i = 0; i < n_keys; i++) {
        if (keys[i].def) {
            apply(ld, keys[i].section, keys[i].name, keys[i].def, &w);
        }
    }
    gr_contact_defaults(&ld->scene->contact);
    gr_driving_defaults(&ld->scene->driving_params);
    gr_analysis_defaults(&ld->scene->analysis);
    ld->defaults = false;
}

void gr_scene_default(gr_scene *s)
{
    memset(s, 0, sizeof *s);
    gr_error err = {0};
    loader ld = {.scene = s, .err = &err};
    apply_defaults(&ld);
    s->reduced_length = -1.0;
    s->wall_eps_n = s->wall_eps_t = s->wall_mu = NAN; /* resolved to [model]'s (resolve_walls) */
    snprintf(s->source, sizeof s->source, "<defaults>");
}

static void warn(gr_scene *s, const char *fmt, const char *a, const char *b)
{
    size_t len = strlen(s->warnings);
    snprintf(s->warnings + len, sizeof s->warnings - len, fmt, a, b);
}

static bool model_has_param(const gr_model *m, const char *name)
{
    for (int i = 0; m && i < m->n_params; i++) {
        if (strcmp(m->params[i].name, name) == 0) {
            return true;
        }
    }
    return false;
}

/* Where key section.name was given (the scene file itself when it was left at its default). */
static bool key_given(const given *g, const char *section, const char *name)
{
    for (int i = 0; i < n_keys; i++) {
        if (!strcmp(keys[i].section, section) && !strcmp(keys[i].name, name)) {
            return g->at[i].file || g->at[i].assignment;
        }
    }
    return false;
}

static where where_of(const given *g, const gr_scene *s, const char *section, const char *name)
{
    for (int i = 0; i < n_keys; i++) {
        if (!strcmp(keys[i].section, section) && !strcmp(keys[i].name, name) &&
            (g->at[i].file || g->at[i].assignment)) {
            return g->at[i];
        }
    }
    return (where){s->source, 0, NULL};
}

/* Cross-key checks and derived quantities. */
/* [driving] (granule/driving.h): a drag needs an integrator that models it; the [noise] keys are
 * the rfm's and the langevin keys the bath's, ignored (with a warning) under another driving. */
static int resolve_driving(gr_scene *s, const given *g, const char *const *driving_keys,
                           int n_driving_keys, gr_error *err)
{
    const gr_driving_type *dr = s->driving ? s->driving : (s->driving = gr_driving_default());
    if (dr->drag && !s->integrator->drag) {
        char names[160] = "", detail[500];
        for (int j = 0, len = 0; gr_integrators[j]; j++) {
            if (gr_integrators[j]->drag) {
                len += snprintf(names + len, sizeof names - (size_t)len, "%s%s", len ? " | " : "",
                                gr_integrators[j]->name);
            }
        }
        where w = key_given(g, "driving", "kind") ? where_of(g, s, "driving", "kind")
                                                  : where_of(g, s, "integrator", "kind");
        snprintf(
            detail, sizeof detail,
            "kind = %s has a viscous drag, which [integrator] kind = %s does not model (its free "
            "flight is exact under the random force only); allowed with %s: rfm | none; allowed "
            "with %s: %s",
            dr->name, s->integrator->name, s->integrator->name, dr->name, names);
        return fail_at(err, &w, "driving", "kind", "%s", detail);
    }
    if (dr->drag && s->integrator->free_flight && key_given(g, "integrator", "free_flight")) {
        /* free_flight says how the random force drives free flight; the bath replaces it and acts
         * as the exact OU step at each window's end (event.c, hybrid.c: bath_window) */
        warn(s,
             "[integrator] free_flight is ignored: it says how the random force drives free "
             "flight, and this scene's [driving] kind = %s acts as the exact Ornstein-Uhlenbeck "
             "step of each window at its end (with kind = %s)\n",
             dr->name, s->integrator->name);
    }
    if (dr->update != GR_DRIVE_FORCE) {
        static const char *const noise_keys[] = {"D", "mode", "com_interval"};
        for (int i = 0; i < 3; i++) {
            if (key_given(g, "noise", noise_keys[i])) {
                warn(s,
                     "[noise] %s is ignored: it belongs to the random force (rfm), and this "
                     "scene's [driving] kind = %s\n",
                     noise_keys[i], dr->name);
            }
        }
        s->D = 0.0;
        s->noise_mode = GR_NOISE_NONE;
    }
    for (int i = 0; i < n_driving_keys; i++) {
        const gr_driving_type *owner = NULL;
        find_driving_param(driving_keys[i], &owner);
        if (owner != dr) {
            char why[160];
            snprintf(why, sizeof why, "%s, which this scene does not use ([driving] kind = %s)",
                     owner ? owner->name : "?", dr->name);
            warn(s, "[driving] %s is ignored: it belongs to %s\n", driving_keys[i], why);
        }
    }
    return GR_OK;
}

/* [boundary] and [gravity] (src/core/walls.c): refused here, with the key's file and line, where
 * the core would refuse them too: an integrator without walls, gravity along a periodic axis, y in
 * 1D; and the walls' own coefficients resolved ([model]'s unless given). */
static int resolve_walls(gr_scene *s, const given *g, gr_error *err)
{
    static const char *const axis[3] = {"x", "y", "z"}, *const gkey[3] = {"gx", "gy", "gz"};
    char detail[500];
    const bool on = s->boundary[0] || s->boundary[1] || s->boundary[2] || s->gravity[0] != 0.0 ||
                    s->gravity[1] != 0.0 || s->gravity[2] != 0.0;
    for (int a = 0; a < 3; a++) {
        if (s->dim == 1 && a == 1 && (s->boundary[1] || s->gravity[1] != 0.0)) {
            const char *k = s->boundary[1] ? "y" : "gy";
            where w = where_of(g, s, s->boundary[1] ? "boundary" : "gravity", k);
            return fail_at(err, &w, s->boundary[1] ? "boundary" : "gravity", k, "%s",
                           "only for dim = 2; allowed in 1D: y = periodic, gy = 0 (use x and gx)");
        }
        if (s->dim < 3 && a == 2 && (s->boundary[2] || s->gravity[2] != 0.0)) {
            const char *k = s->boundary[2] ? "z" : "gz";
            where w = where_of(g, s, s->boundary[2] ? "boundary" : "gravity", k);
            snprintf(detail, sizeof detail,
                     "only for dim = 3; allowed in %dD: z = periodic, gz = 0, vibrate = none "
                     "| x%s",
                     s->dim, s->dim == 2 ? " | y" : "");
            return fail_at(err, &w, s->boundary[2] ? "boundary" : "gravity", k, "%s", detail);
        }
        if (s->gravity[a] != 0.0 && !s->boundary[a]) {
            where w = where_of(g, s, "gravity", gkey[a]);
            snprintf(detail, sizeof detail,
                     "%s = %g m/s^2 along a periodic axis: a grain would fall for ever; needs "
                     "[boundary] %s = walls (allowed with %s = periodic: %s = 0)",
                     gkey[a], s->gravity[a], axis[a], axis[a], gkey[a]);
            return fail_at(err, &w, "gravity", gkey[a], "%s", detail);
        }
    }
    if (s->vibrate && !s->boundary[s->vibrate - 1]) {
        where w = where_of(g, s, "boundary", "vibrate");
        snprintf(detail, sizeof detail,
                 "vibrate = %s moves the wall at %s = 0, but [boundary] %s = periodic; allowed: "
                 "an axis with walls, or none",
                 axis[s->vibrate - 1], axis[s->vibrate - 1], axis[s->vibrate - 1]);
        return fail_at(err, &w, "boundary", "vibrate", "%s", detail);
    }
    if (s->vibrate && !(s->amplitude < 0.25 * s->L)) {
        where w = where_of(g, s, "boundary", "amplitude");
        snprintf(detail, sizeof detail,
                 "amplitude = %g m is too large for L = %g m; allowed range [0, L / 4) = [0, %g) m",
                 s->amplitude, s->L, 0.25 * s->L);
        return fail_at(err, &w, "boundary", "amplitude", "%s", detail);
    }
    /* the walls' own coefficients: [model]'s (the particles') unless given; one the scene's laws
     * do not read, or given without walls, is warned about */
    static const char *const wkey[3] = {"eps_n", "eps_t", "mu"};
    const double model_v[3] = {s->contact.eps_n, s->contact.eps_t, s->contact.mu};
    double *const wall_v[3] = {&s->wall_eps_n, &s->wall_eps_t, &s->wall_mu};
    for (int k = 0; k < 3; k++) {
        if (key_given(g, "boundary", wkey[k]) && !s->boundary[0] && !s->boundary[1] &&
            !s->boundary[2]) {
            warn(s, "[boundary] %s is ignored: %s\n", wkey[k],
                 "the scene has no walls ([boundary] x, y = periodic)");
        } else if (key_given(g, "boundary", wkey[k]) && !model_has_param(s->normal, wkey[k]) &&
                   !model_has_param(s->tangential, wkey[k])) {
            warn(s, "[boundary] %s is ignored: %s\n", wkey[k],
                 "the scene's [model] laws have no such coefficient");
        }
        if (isnan(*wall_v[k])) {
            *wall_v[k] = model_v[k];
        }
    }
    if (!on) {
        return GR_OK;
    }
    const int a = s->boundary[0] ? 0 : s->boundary[1] ? 1 : s->boundary[2] ? 2 : -1;
    const char *sec = a >= 0 ? "boundary" : "gravity", *key = a >= 0 ? axis[a] : gkey[0];
    if (!s->integrator->walls) {
        char names[160] = "";
        for (int j = 0, len = 0; gr_integrators[j]; j++) {
            if (gr_integrators[j]->walls) {
                len += snprintf(names + len, sizeof names - (size_t)len, "%s%s", len ? " | " : "",
                                gr_integrators[j]->name);
            }
        }
        where w = key_given(g, "integrator", "kind") ? where_of(g, s, "integrator", "kind")
                                                     : where_of(g, s, sec, key);
        snprintf(
            detail, sizeof detail,
            "kind = %s does not model walls or gravity ([%s] %s); allowed with walls or "
            "gravity: %s; allowed with %s: [boundary] x, y = periodic and [gravity] gx, gy = 0",
            s->integrator->name, sec, key, names, s->integrator->name);
        return fail_at(err, &w, "integrator", "kind", "%s", detail);
    }
    /* a soft integrator with free-flight leaps (hybrid, docs/hybrid.md "Walls and gravity"): its
     * active set is built on the 1D ring, and it symmetrises by moving to the centre-of-mass frame,
     * which walls forbid */
    if (s->integrator->free_flight && !s->integrator->instantaneous && s->dim == 1) {
        where w = where_of(g, s, "integrator", "kind");
        return fail_at(err, &w, "integrator", "kind",
                       "kind = %s runs walls and gravity in 2D and 3D (its 1D active set is built "
                       "on the periodic ring); allowed with walls or gravity in 1D: verlet | event",
                       s->integrator->name);
    }
    if (s->integrator->free_flight && !s->integrator->instantaneous &&
        s->noise_mode == GR_NOISE_SYMMETRISED && s->D > 0.0) {
        where w = key_given(g, "noise", "mode") ? where_of(g, s, "noise", "mode")
                                                : where_of(g, s, "integrator", "kind");
        return fail_at(err, &w, "noise", "mode",
                       "symmetrised with walls and kind = %s: it symmetrises by moving to the "
                       "centre-of-mass frame, which would carry grains through the walls; allowed "
                       "with walls: com | none",
                       s->integrator->name);
    }
    return GR_OK;
}

/* Where a [model] parameter was given (its descriptor's name), else the file. */
static where model_where(const given *g, const gr_scene *s, const char *name)
{
    for (int k = g->n_model_at - 1; k >= 0; k--) {
        if (strcmp(g->model_at[k].name, name) == 0) {
            return g->model_at[k].at;
        }
    }
    return (where){s->source, 0, NULL};
}

/* dim = 3 (spheres, docs/three-dimensions.md): the default placement follows dim (cubic), as does
 * the moment of inertia's factor (2/5, a solid sphere, unless inertia_factor is given), and what
 * 3D cannot run yet is refused at its key, never run silently: walls, gravity, an integrator
 * without spheres (every registered one steps them now), the Langevin bath, single-precision
 * noise, observables not defined in 3D. */
static int resolve_3d(gr_scene *s, const given *g, gr_error *err)
{
    static const char *const why = "dim = 3 runs the soft contact laws (verlet, hybrid) and "
                                   "smooth or rough hard spheres (event) with the random force (or "
                                   "no driving) in a periodic cube so far "
                                   "(docs/three-dimensions.md)";
    char detail[600];
    if (!key_given(g, "placement", "kind")) {
        s->placement = GR_PLACE_CUBIC; /* the default follows dim: hexagonal is a 2D packing */
    }
    bool q_given = false;
    for (int k = 0; k < g->n_model_at; k++) {
        q_given = q_given || strcmp(g->model_at[k].name, "inertia_factor") == 0;
    }
    if (!q_given) {
        s->contact.inertia_factor = 0.4; /* I = (2/5) M r^2, a solid sphere (2D: 1/2, a disc) */
    }
    if (s->placement != GR_PLACE_CUBIC && s->placement != GR_PLACE_FCC &&
        s->placement != GR_PLACE_RANDOM) {
        where w = where_of(g, s, "placement", "kind");
        snprintf(detail, sizeof detail,
                 "%s is a 1D or 2D placement; allowed in 3D: cubic | fcc | random",
                 gr_placement_name(s->placement));
        return fail_at(err, &w, "placement", "kind", "%s", detail);
    }
    if (!s->integrator->spheres) {
        char names[160] = "";
        for (int j = 0, len = 0; gr_integrators[j]; j++) {
            if (gr_integrators[j]->spheres) {
                len += snprintf(names + len, sizeof names - (size_t)len, "%s%s", len ? " | " : "",
                                gr_integrators[j]->name);
            }
        }
        where w = where_of(g, s, "integrator", "kind");
        snprintf(detail, sizeof detail,
                 "kind = %s does not step spheres yet; allowed with dim = 3: %s",
                 s->integrator->name, names);
        return fail_at(err, &w, "integrator", "kind", "%s", detail);
    }
    struct {
        bool on;
        const char *section, *key, *allowed;
    } const refused[] = {
        {false, "", "", ""}, /* walls, gravity, vibrate, bath, single noise: all in 3D now */
    };
    for (size_t k = 0; k < sizeof refused / sizeof refused[0]; k++) {
        if (refused[k].on) {
            /* rotation is a [model] parameter (a model's descriptor), the others scene keys */
            where w = strcmp(refused[k].key, "rotation") == 0
                          ? model_where(g, s, refused[k].key)
                          : where_of(g, s, refused[k].section, refused[k].key);
            snprintf(detail, sizeof detail, "not available with dim = 3 yet; allowed in 3D: %s. %s",
                     refused[k].allowed, why);
            return fail_at(err, &w, refused[k].section, refused[k].key, "%s", detail);
        }
    }
    char buf[sizeof s->observables], *save = NULL;
    snprintf(buf, sizeof buf, "%s", s->observables);
    for (char *tok = strtok_r(buf, ", \t", &save); tok; tok = strtok_r(NULL, ", \t", &save)) {
        const gr_observable_type *t = gr_observable_find(tok);
        if (t && !(t->dims & (1u << 2))) {
            char names[200] = "";
            for (int j = 0, len = 0; gr_observables[j]; j++) {
                if (gr_observables[j]->dims & (1u << 2)) {
                    len += snprintf(names + len, sizeof names - (size_t)len, "%s%s",
                                    len ? " | " : "", gr_observables[j]->name);
                }
            }
            where w = where_of(g, s, "analysis", "observables");
            snprintf(detail, sizeof detail,
                     "%s is not defined for dim = 3 yet; allowed in 3D: %s (temperature.csv, "
                     "ledger.csv and summary.json are always written; docs/three-dimensions.md)",
                     tok, names);
            return fail_at(err, &w, "analysis", "observables", "%s", detail);
        }
    }
    return GR_OK;
}

static int resolve(gr_scene *s, const given *g, const char *const *model_keys, int n_model_keys,
                   const char *const *driving_keys, int n_driving_keys, gr_error *err)
{
    double d = 2.0 * s->radius;
    {
        const char *ssec = "species", *skey = "radius";
        char why[400];
        if (gr_scene_species_resolve(s, &ssec, &skey, why, sizeof why)) { /* scene_species.c */
            where w = strcmp(skey, "rotation") == 0 ? model_where(g, s, skey)
                                                    : where_of(g, s, ssec, skey);
            return fail_at(err, &w, ssec, skey, "%s", why);
        }
    }
    int n_len = g->L + g->packing_fraction + g->reduced_length;
    if (n_len > 1) {
        where w = g->packing_fraction ? g->at_pf : g->at_rl;
        return fail_at(err, &w, "system",
                       g->packing_fraction ? "packing_fraction" : "reduced_length", "%s",
                       "give only one of L, packing_fraction, reduced_length");
    }
    if (g->packing_fraction) {
        if (s->dim == 1) {
            return fail_at(err, &g->at_pf, "system", "packing_fraction", "%s",
                           "only for dim = 2 or 3; use reduced_length or L in 1D");
        }
        s->L = s->dim == 3 ? cbrt(gr_scene_grain_volume(s) / s->packing_fraction)
                           : sqrt(gr_scene_grain_area(s) / s->packing_fraction);
    }
    /* defaults that depend on dim follow it (docs/scene-keys.md): without a length key a 1D ring
     * gets reduced_length = 1 m (the thesis's ch. 3 runs, docs/scenes/rfm-1d.ini), not the 2D
     * box side, which N default particles would not fit */
    const bool default_length = s->dim == 1 && n_len == 0;
    if (default_length) {
        s->reduced_length = GR_DEFAULT_REDUCED_LENGTH_1D;
    }
    if (g->reduced_length || default_length) {
        if (s->dim != 1) {
            return fail_at(err, &g->at_rl, "system", "reduced_length", "%s",
                           "only for dim = 1; use packing_fraction or L in 2D and 3D");
        }
        s->L = s->reduced_length + gr_scene_grain_length(s);
    }
    if (s->dim == 2) {
        s->packing_fraction = gr_scene_grain_area(s) / (s->L * s->L);
        s->reduced_length = -1.0;
    } else if (s->dim == 3) {
        s->packing_fraction = gr_scene_grain_volume(s) / (s->L * s->L * s->L);
        s->reduced_length = -1.0;
    } else {
        s->reduced_length = s->L - gr_scene_grain_length(s);
        s->packing_fraction = 0.0;
    }
    char detail[400];
    const char *len_key = g->reduced_length     ? "reduced_length"
                          : g->packing_fraction ? "packing_fraction"
                          : g->L                ? "L"
                                                : "N";
    where len_at = where_of(g, s, "system", len_key);
    if (s->dim == 1 && s->reduced_length < 0.0) {
        snprintf(detail, sizeof detail,
                 "L = %g m is shorter than N d = %g m: the particles cannot fit on the ring "
                 "(reduced_length L' = L - N d must be >= 0)",
                 s->L, s->N * d);
        return fail_at(err, &len_at, "system", len_key, "%s", detail);
    }
    if (s->dim == 2 && s->packing_fraction > M_PI / (2.0 * sqrt(3.0))) {
        snprintf(detail, sizeof detail,
                 "packing fraction N pi r^2 / L^2 = %.4f exceeds hexagonal close packing 0.9069 "
                 "(allowed range (0, 0.9069])",
                 s->packing_fraction);
        return fail_at(err, &len_at, "system", len_key, "%s", detail);
    }
    if (s->dim == 3 && s->packing_fraction > FCC_PHI) {
        snprintf(detail, sizeof detail,
                 "packing fraction N (4/3) pi r^3 / L^3 = %.4f exceeds close packing of spheres "
                 "(FCC) pi / (3 sqrt 2) = 0.7405 (allowed range (0, 0.7405])",
                 s->packing_fraction);
        return fail_at(err, &len_at, "system", len_key, "%s", detail);
    }
    if (!(s->L / d <= 1e9)) { /* cell and lattice indices are ints (found by tests/fuzz) */
        snprintf(detail, sizeof detail,
                 "L = %g m is %g particle diameters across; at most 1e9 are supported (allowed L/d "
                 "range (0, 1e9])",
                 s->L, s->L / d);
        return fail_at(err, &len_at, "system", len_key, "%s", detail);
    }
    if (g->dt && g->steps_per_contact) {
        return fail_at(err, &g->at_dt, "integrator", "dt", "%s",
                       "give dt or steps_per_contact, not both");
    }
    if (!g->dt) {
        s->dt = 0.0;
    }
    s->kick_interval_default = !key_given(g, "integrator", "kick_interval");
    if (s->dim == 1) {
        if (s->tangential) {
            where w = where_of(g, s, "model", "tangential");
            snprintf(detail, sizeof detail,
                     "%s needs dim = 2 (a 1D collision is head-on); allowed in 1D: none",
                     s->tangential->name);
            return fail_at(err, &w, "model", "tangential", "%s", detail);
        }
        if (!key_given(g, "placement", "kind")) {
            s->placement =
                GR_PLACE_UNIFORM; /* the default follows dim: hexagonal is a 2D packing */
        }
        if (s->placement == GR_PLACE_HEXAGONAL || s->placement == GR_PLACE_SQUARE) {
            where w = where_of(g, s, "placement", "kind");
            snprintf(detail, sizeof detail,
                     "%s is a 2D packing; allowed in 1D: uniform | cluster | random",
                     gr_placement_name(s->placement));
            return fail_at(err, &w, "placement", "kind", "%s", detail);
        }
    }
    if (s->dim != 3 && (s->placement == GR_PLACE_CUBIC || s->placement == GR_PLACE_FCC)) {
        where w = where_of(g, s, "placement", "kind");
        snprintf(detail, sizeof detail, "%s is a 3D lattice (dim = 3); allowed in %dD: %s",
                 gr_placement_name(s->placement), s->dim,
                 s->dim == 1 ? "uniform | cluster | random"
                             : "hexagonal | square | uniform | cluster | random");
        return fail_at(err, &w, "placement", "kind", "%s", detail);
    }
    if (s->dim == 3) {
        int rc3 = resolve_3d(s, g, err);
        if (rc3) {
            return rc3;
        }
    }
    /* integrators of instantaneous collisions (event) and the instantaneous rules (hard_sphere)
     * need each other (docs/event-driven.md) */
    const bool event_rule = s->normal && (s->normal->kind & GR_MODEL_EVENT);
    char soft[160], hard[160], rules[160], laws[160];
    integrator_names_where(false, " | ", soft, sizeof soft);
    if (s->integrator->instantaneous && !event_rule) {
        where w = where_of(g, s, "integrator", "kind");
        normal_names_where(true, " | ", rules, sizeof rules);
        snprintf(detail, sizeof detail,
                 "kind = %s needs an event rule, [model] normal = %s (normal = %s is a force law); "
                 "allowed with %s: %s",
                 s->integrator->name, rules, s->normal ? s->normal->name : "?",
                 s->normal ? s->normal->name : "it", soft);
        return fail_at(err, &w, "integrator", "kind", "%s", detail);
    }
    if (event_rule && !s->integrator->instantaneous) {
        where w = where_of(g, s, "model", "normal");
        integrator_names_where(true, " | ", hard, sizeof hard);
        integrator_names_where(false, " or ", soft, sizeof soft);
        normal_names_where(false, " | ", laws, sizeof laws);
        snprintf(detail, sizeof detail,
                 "%s is an instantaneous collision rule and needs [integrator] kind = %s; allowed "
                 "with kind = %s: %s",
                 s->normal->name, hard, soft, laws);
        return fail_at(err, &w, "model", "normal", "%s", detail);
    }
    if (s->rolling && (s->dim == 1 || !s->contact.rotation || s->integrator->instantaneous)) {
        where w = where_of(g, s, "model", "rolling");
        snprintf(
            detail, sizeof detail,
            "%s is a torque on the spins: it needs dim = 2 or 3, [model] rotation = true and a "
            "force-law integrator (verlet); given dim = %d, rotation = %s, kind = %s; allowed "
            "otherwise: none",
            s->rolling->name, s->dim, s->contact.rotation ? "true" : "false", s->integrator->name);
        return fail_at(err, &w, "model", "rolling", "%s", detail);
    }
    if (s->integrator->instantaneous && !key_given(g, "integrator", "free_flight")) {
        /* kicks: the random force's work is exact in expectation across collisions; exact free flight
         * under-injects when a collision falls inside a window (issue 37, docs/event-driven.md) */
        s->free_flight = GR_FREE_FLIGHT_KICKS;
    }
    if (s->integrator->instantaneous && s->tangential) {
        where w = where_of(g, s, "model", "tangential");
        snprintf(detail, sizeof detail,
                 "%s is a force law; with kind = %s the tangential restitution is %s's own; "
                 "allowed: none",
                 s->tangential->name, s->integrator->name, s->normal->name);
        return fail_at(err, &w, "model", "tangential", "%s", detail);
    }
    if (s->noise_precision == GR_NOISE_SINGLE && !s->integrator->single_noise) {
        where w = where_of(g, s, "noise", "precision");
        return fail_at(err, &w, "noise", "precision",
                       "single needs an integrator that draws it (verlet; given %s); allowed "
                       "otherwise: double",
                       s->integrator->name);
    }
    if (s->D == 0.0) {
        s->noise_mode = GR_NOISE_NONE;
    }
    if (s->noise_mode == GR_NOISE_NONE) {
        s->D = 0.0;
    }
    int rc_driving = resolve_driving(s, g, driving_keys, n_driving_keys, err);
    if (rc_driving) {
        return rc_driving;
    }
    int rc_walls = resolve_walls(s, g, err);
    if (rc_walls) {
        return rc_walls;
    }
    /* a key several models share was checked against the widest of their ranges when it was read
     * (the models may come later in the file); now each chosen model checks its own range, e.g.
     * hard_sphere's eps_n in (0, 1] */
    const gr_model *chosen[3] = {s->normal, s->tangential, s->rolling};
    for (int k = 0; k < g->n_model_at; k++) {
        for (int m = 0; m < 3; m++) {
            for (int i = 0; chosen[m] && i < chosen[m]->n_params; i++) {
                const gr_param *p = &chosen[m]->params[i];
                if (p->type != GR_PARAM_DOUBLE || strcmp(p->name, g->model_at[k].name) != 0) {
                    continue;
                }
                const double x = *(const double *)((const char *)&s->contact + p->offset);
                if (x == GR_TC_OFF && strcmp(p->name, "tc") == 0) {
                    continue; /* tc = off */
                }
                if (!check_range(x, p->min, p->max, p->min_open, p->max_open)) {
                    char r[96];
                    range_text(r, sizeof r, p->min, p->max, p->min_open, p->max_open);
                    snprintf(detail, sizeof detail,
                             "%g is out of %s's range; allowed range with normal = %s: %s", x,
                             chosen[m]->name, s->normal ? s->normal->name : "none", r);
                    return fail_at(err, &g->model_at[k].at, "model", p->name, "%s", detail);
                }
            }
        }
    }
    for (int i = 0; i < n_model_keys; i++) {
        if (!model_has_param(s->normal, model_keys[i]) &&
            !model_has_param(s->tangential, model_keys[i]) &&
            !model_has_param(s->rolling, model_keys[i])) {
            const gr_model *owner = NULL;
            find_model_param(model_keys[i], &owner);
            warn(s, "[model] %s is ignored: it belongs to %s, which this scene does not use\n",
                 model_keys[i], owner ? owner->name : "?");
        }
    }
    return GR_OK;
}

/* Read the scene from `in` (named `path` in messages), or open `path` when `in` is NULL. */
static int load(gr_scene *s, const char *path, FILE *in, const char *const *overrides,
                int n_overrides, bool whole_scene, gr_error *err)
{
    gr_scene_default(s);
    loader ld = {.scene = s, .err = err, .rc = GR_OK, .file = path};
    if (path) {
        snprintf(s->source, sizeof s->source, "%s", path);
        FILE *f = in;
        int rc = in ? GR_OK : open_scene_file(path, &f, err);
        if (rc) {
            return rc;
        }
        line_reader r = {{.f = f, .what = "scene", .sections = SECTIONS}, &ld};
        int bad = rc ? 0 : ini_parse_stream(read_line, &r, scene_ini_line, &ld);
        const bool content = r.lines.content;
        gr_line_reader_free(&r.lines);
        if (!in) {
            fclose(f);
        }
        if (rc || ld.rc != GR_OK) {
            return rc ? rc : ld.rc;
        }
        if (bad > 0) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s:%d: not an INI line (expected [section] or key = value)", path, bad);
        }
        if (bad < 0) {
            return GR_FAIL(err, GR_EIO, "%s: could not be read", path);
        }
        if (whole_scene && !content) {
            return GR_FAIL(
                err, GR_EINVAL,
                "%s: the scene is empty (only blanks and comments); it needs at least a [system] "
                "section with dim and N (docs/scene-keys.md)",
                path);
        }
        if (whole_scene && !ld.has_system) {
            return GR_FAIL(err, GR_EINVAL,
                           "%s: no [system] section; a scene names at least its system (dim, N; "
                           "docs/scene-keys.md)",
                           path);
        }
    }
    for (int i = 0; i < n_overrides; i++) {
        const char *a = overrides[i];
        const char *dot = strchr(a, '.'), *eq = strchr(a, '=');
        where w = {NULL, 0, a};
        for (const char *c = a; *c;
             c++) { /* as in scene files (scene_lines.c): a line break would be another line */
            if (((unsigned char)*c < 0x20 && *c != '\t') || *c == 0x7f) {
                return GR_FAIL(
                    err, GR_EINVAL,
                    "--set %.*s...: control byte 0x%02x at column %d (an assignment is text)",
                    (int)(c - a < 200 ? c - a : 200), a, (unsigned char)*c, (int)(c - a) + 1);
            }
        }
        if (!dot || !eq || dot > eq || dot == a || eq == dot + 1) {
            return GR_FAIL(err, GR_EINVAL,
                           "--set %s: expected section.key=value, e.g. --set model.eps_n=0.5", a);
        }
        char section[64], name[64], value[1100];
        snprintf(section, sizeof section, "%.*s", (int)(dot - a), a);
        snprintf(name, sizeof name, "%.*s", (int)(eq - dot - 1), dot + 1);
        snprintf(value, sizeof value, "%s", eq + 1);
        int rc = apply(&ld, section, name, value, &w);
        if (rc != GR_OK) {
            return rc;
        }
        if (ld.n_seen < 128) {
            snprintf(ld.seen[ld.n_seen++], sizeof ld.seen[0], "%s.%s", section, name);
        }
    }
    /* [model] parameters that were given, for the "ignored" warning */
    const char *model_keys[64];
    int n_model_keys = 0;
    for (int i = 0; i < ld.n_seen && n_model_keys < 64; i++) {
        if (strncmp(ld.seen[i], "model.", 6) == 0) {
            const char *name = ld.seen[i] + 6;
            if (strcmp(name, "normal") && strcmp(name, "tangential") && strcmp(name, "rolling")) {
                bool dup = false;
                for (int j = 0; j < n_model_keys; j++) {
                    dup |= strcmp(model_keys[j], name) == 0;
                }
                if (!dup) {
                    model_keys[n_model_keys++] = name;
                }
            }
        }
    }
    const char *driving_keys[16];
    int n_driving_keys = 0;
    for (int i = 0; i < ld.n_seen && n_driving_keys < 16; i++) {
        if (strncmp(ld.seen[i], "driving.", 8) == 0 && strcmp(ld.seen[i] + 8, "kind") != 0) {
            bool dup = false;
            for (int j = 0; j < n_driving_keys; j++) {
                dup |= strcmp(driving_keys[j], ld.seen[i] + 8) == 0;
            }
            if (!dup) {
                driving_keys[n_driving_keys++] = ld.seen[i] + 8;
            }
        }
    }
    return resolve(s, &ld.g, model_keys, n_model_keys, driving_keys, n_driving_keys, err);
}

int gr_scene_load(gr_scene *s, const char *path, const char *const *overrides, int n_overrides,
                  gr_error *err)
{
    return load(s, path, NULL, overrides, n_overrides, false, err);
}

int gr_scene_load_whole(gr_scene *s, const char *path, const char *const *overrides,
                        int n_overrides, gr_error *err)
{
    return load(s, path, NULL, overrides, n_overrides, true, err);
}

int gr_scene_load_buffer(gr_scene *s, const char *name, const char *text, size_t len,
                         const char *const *overrides, int n_overrides, gr_error *err)
{
    static char empty[1];
    FILE *f = fmemopen(len ? (void *)text : empty, len, "r");
    if (!f) {
        return GR_FAIL(err, GR_ENOMEM, "%s: cannot read scene text: %s", name, strerror(errno));
    }
    int rc = load(s, name ? name : "<buffer>", f, overrides, n_overrides, false, err);
    fclose(f);
    return rc;
}

/* ---------- documentation ---------- */

static const char *type_name(key_type t)
{
    switch (t) {
    case K_DOUBLE: return "number";
    case K_INT: return "integer";
    case K_BOOL: return "true/false";
    case K_UINT64: return "integer";
    case K_STRING: return "path";
    case K_ENUM:
    case K_INTEGRATOR:
    case K_DRIVING: return "choice";
    case K_NORMAL: return "model";
    case K_TANGENTIAL: return "model";
    case K_ROLLING: return "model";
    case K_LIST: return "list";
    case K_NUMBERS: return "numbers";
    }
    return "";
}

void gr_scene_keys_markdown(FILE *out)
{
    fprintf(
        out,
        "# Scene keys\n\n"
        "Generated by `granule keys` from the parser's own tables (src/scene/scene.c and the\n"
        "models' parameter tables), so it always matches what the parser accepts. Ranges\n"
        "use [ ] for inclusive and ( ) for exclusive bounds. Any key can be overridden on\n"
        "the command line with `--set section.key=value`.\n\n"
        "A scene is a regular, non-empty text file with at least a `[system]` section; a\n"
        "folder, an empty or comments-only file, control bytes (NUL included) are refused\n"
        "with the file and line. Lines of any length are read whole (a long value is kept\n"
        "entire; a line that is neither a comment nor `key = value` is refused at its line).\n"
        "A section header stands alone on its line (`[system]x` and an unterminated `[run` are\n"
        "refused); a key given twice is refused; integer keys take decimal digits only (`N =\n"
        "0x1p5` or `2e3` is refused). `--set` overrides, sweep and campaign files and the\n"
        "Python module's `set=` and scene dicts go through the same checks: two overrides of\n"
        "one group (`integrator.dt` and `steps_per_contact`; `system.L`, `packing_fraction`\n"
        "and `reduced_length`) conflict as two lines of a file do; an override replaces the\n"
        "group member the file gave.\n\n"
        "**Schedule** (src/app/run_schedule.h): `run.sample_every` and `output.snapshot_every`\n"
        "are rounded to the nearest whole number of time steps dt (shorter than dt is refused;\n"
        "a rounding that moves an interval by more than 1 %% is stated on stderr and in\n"
        "summary.json's `warnings`); `run.warmup` and `run.duration` must be whole numbers\n"
        "of `run.sample_every` and the duration must hold at least one sample, so the run\n"
        "simulates exactly the time written; snapshots are taken every `snapshot_every`\n"
        "from t = 0, independently of the samples; `run.checkpoint_every` counts whole\n"
        "samples (rounded up), and one longer than the run means no periodic checkpoint;\n"
        "at most 2^52 steps. Whatever is refused names the key and the allowed range, and\n"
        "is refused before the output folder is touched.\n");
    const char *section = "";
    for (int i = 0; i < n_keys; i++) {
        const scene_key *k = &keys[i];
        if (strcmp(section, k->section) != 0) {
            section = k->section;
            fprintf(out,
                    "\n## [%s]\n\n| key | type | unit | default | allowed | meaning "
                    "|\n|---|---|---|---|---|---|\n",
                    section);
        }
        char range[96] = "";
        if (k->type == K_ENUM) {
            snprintf(range, sizeof range, "%s", k->choices);
            for (char *c = range; *c; c++) {
                if (*c == '|') {
                    *c = '/';
                }
            }
        } else if (k->type == K_INTEGRATOR) {
            gr_integrator_names(range, sizeof range, "/");
        } else if (k->type == K_DRIVING) {
            gr_driving_names(range, sizeof range, "/");
        } else if (k->type == K_DOUBLE || k->type == K_INT || k->type == K_NUMBERS) {
            range_text(range, sizeof range, k->min, k->max, k->min_open, k->max_open);
        }
        char doc[1024] = "";
        for (int j = 0; k->type == K_INTEGRATOR && gr_integrators[j]; j++) {
            size_t len = strlen(doc);
            snprintf(doc + len, sizeof doc - len, "%s%s: %s", j ? "; " : "",
                     gr_integrators[j]->name, gr_integrators[j]->summary);
        }
        for (int j = 0; k->type == K_DRIVING && gr_drivings[j]; j++) {
            size_t len = strlen(doc);
            snprintf(doc + len, sizeof doc - len, "%s%s: %s", j ? "; " : "", gr_drivings[j]->name,
                     gr_drivings[j]->summary);
        }
        fprintf(out, "| `%s` | %s | %s | %s | %s | %s |\n", k->name, type_name(k->type), k->unit,
                k->def ? k->def : "(unset)", range, k->doc ? k->doc : doc);
        for (int m = 0; k->type == K_DRIVING && gr_drivings[m]; m++) {
            for (int j = 0; j < gr_drivings[m]->n_params; j++) {
                const gr_param *p = &gr_drivings[m]->params[j];
                char r[96] = "";
                range_text(r, sizeof r, p->min, p->max, p->min_open, p->max_open);
                fprintf(out, "| `%s` | number | %s | %g | %s | %s |\n", p->name, p->unit, p->def, r,
                        p->doc);
            }
        }
        if (strcmp(k->name, "observables") == 0) {
            for (int o = 0; gr_observables[o]; o++) {
                for (int j = 0; j < gr_observables[o]->n_params; j++) {
                    const gr_param *p = &gr_observables[o]->params[j];
                    char r[96] = "", def[32];
                    range_text(r, sizeof r, p->min, p->max, p->min_open, p->max_open);
                    snprintf(def, sizeof def, "%g", p->def);
                    if (p->type == GR_PARAM_BOOL) {
                        snprintf(r, sizeof r, "%s", "");
                        snprintf(def, sizeof def, "%s", p->def != 0.0 ? "true" : "false");
                    }
                    fprintf(out, "| `%s` | %s | %s | %s | %s | (%s) %s |\n", p->name,
                            p->type == GR_PARAM_BOOL  ? "true/false"
                            : p->type == GR_PARAM_INT ? "integer"
                                                      : "number",
                            p->unit, def, r, gr_observables[o]->name, p->doc);
                }
            }
        }
        if (strcmp(k->name, "tangential") == 0) {
            for (int m = 0; gr_models[m]; m++) {
                for (int j = 0; j < gr_models[m]->n_params; j++) {
                    const gr_param *p = &gr_models[m]->params[j];
                    char r[96] = "";
                    if (p->type != GR_PARAM_BOOL) {
                        range_text(r, sizeof r, p->min, p->max, p->min_open, p->max_open);
                    }
                    char def[32];
                    snprintf(def, sizeof def, "%g", p->def);
                    if (p->type == GR_PARAM_BOOL) {
                        snprintf(def, sizeof def, "%s", p->def != 0.0 ? "true" : "false");
                    }
                    fprintf(out, "| `%s` | %s | %s | %s | %s | (%s) %s |\n", p->name,
                            p->type == GR_PARAM_BOOL ? "true/false" : "number", p->unit, def, r,
                            gr_models[m]->name, p->doc);
                }
            }
        }
    }
}

/* The key table's units ("N/m", "m^2", "d") in the sidecars' notation */
static const char *csv_unit(const char *unit, bool number)
{
    static const char *const map[][2] = {{"N/m", "N m-1"},
                                         {"N/m^1.5", "N m-1.5"},
                                         {"N^2 s", "N2 s"},
                                         {"kg/s", "kg s-1"},
                                         {"m/s", "m s-1"},
                                         {"rad/s", "rad s-1"},
                                         {"d", "d (particle diameter)"}};
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++) {
        if (!strcmp(unit, map[i][0])) {
            return map[i][1];
        }
    }
    return unit[0] ? unit : number ? "1" : "";
}

const char *gr_scene_key_unit(const char *key)
{
    const char *dot = strchr(key, '.');
    if (!dot) {
        return NULL;
    }
    const size_t sl = (size_t)(dot - key);
    for (int i = 0; i < n_keys; i++) {
        if (strlen(keys[i].section) == sl && !strncmp(keys[i].section, key, sl) &&
            !strcmp(keys[i].name, dot + 1)) {
            return csv_unit(keys[i].unit, keys[i].type == K_DOUBLE || keys[i].type == K_INT ||
                                              keys[i].type == K_UINT64);
        }
    }
    for (int m = 0; !strncmp(key, "model.", 6) && gr_models[m]; m++) {
        for (int j = 0; j < gr_models[m]->n_params; j++) {
            if (!strcmp(gr_models[m]->params[j].name, dot + 1)) {
                return csv_unit(gr_models[m]->params[j].unit, true);
            }
        }
    }
    for (int m = 0; !strncmp(key, "driving.", 8) && gr_drivings[m]; m++) {
        for (int j = 0; j < gr_drivings[m]->n_params; j++) {
            if (!strcmp(gr_drivings[m]->params[j].name, dot + 1)) {
                return csv_unit(gr_drivings[m]->params[j].unit, true);
            }
        }
    }
    for (int o = 0; !strncmp(key, "analysis.", 9) && gr_observables[o]; o++) {
        for (int j = 0; j < gr_observables[o]->n_params; j++) {
            if (!strcmp(gr_observables[o]->params[j].name, dot + 1)) {
                return csv_unit(gr_observables[o]->params[j].unit, true);
            }
        }
    }
    return NULL;
}

/* ---------- saving ---------- */

static void save_value(FILE *f, const scene_key *k, const gr_scene *s)
{
    const void *slot = (const char *)s + k->offset;
    switch (k->type) {
    case K_DOUBLE: fprintf(f, "%.17g", *(const double *)slot); break;
    case K_INT: fprintf(f, "%d", *(const int *)slot); break;
    case K_BOOL: fprintf(f, "%s", *(const bool *)slot ? "true" : "false"); break;
    case K_UINT64: fprintf(f, "%llu", (unsigned long long)*(const uint64_t *)slot); break;
    case K_STRING:
    case K_LIST: fprintf(f, "%s", (const char *)slot); break;
    case K_NUMBERS:
        for (int i = 0; i < ((const gr_number_list *)slot)->n; i++) {
            fprintf(f, "%s%.17g", i ? ", " : "", ((const gr_number_list *)slot)->v[i]);
        }
        break;
    case K_ENUM: {
        int idx = *(const int *)slot, i = 0;
        const char *c = k->choices;
        while (i < idx && strchr(c, '|')) {
            c = strchr(c, '|') + 1;
            i++;
        }
        fprintf(f, "%.*s", (int)strcspn(c, "|"), c);
        break;
    }
    case K_NORMAL:
    case K_TANGENTIAL:
    case K_ROLLING: {
        const gr_model *m = *(const gr_model *const *)slot;
        fprintf(f, "%s", m ? m->name : "none");
        break;
    }
    case K_INTEGRATOR: fprintf(f, "%s", (*(const gr_integrator_type *const *)slot)->name); break;
    case K_DRIVING: fprintf(f, "%s", (*(const gr_driving_type *const *)slot)->name); break;
    }
}

static void save_params(FILE *f, const gr_param *ps, int n, const void *base)
{
    for (int i = 0; i < n; i++) {
        const void *slot = (const char *)base + ps[i].offset;
        if (ps[i].type == GR_PARAM_BOOL) {
            fprintf(f, "%s = %s\n", ps[i].name, *(const bool *)slot ? "true" : "false");
        } else if (ps[i].type == GR_PARAM_INT) {
            fprintf(f, "%s = %d\n", ps[i].name, *(const int *)slot);
        } else if (strcmp(ps[i].name, "tc") == 0 && *(const double *)slot == GR_TC_OFF) {
            fprintf(
                f,
                "tc = off\n"); /* the default stays "tc = 0", as checkpoints' scene texts have it */
        } else {
            fprintf(f, "%s = %.17g\n", ps[i].name, *(const double *)slot);
        }
    }
}

void gr_scene_saved_warnings(gr_scene *s, const char *dir)
{
    char path[1200], line[1200];
    snprintf(path, sizeof path, "%.1100s/scene.ini", dir);
    int why;
    FILE *f = gr_input_fopen(path, &why);
    if (!f) {
        return;
    }
    s->warnings[0] = '\0';
    const size_t plen = strlen(GR_SCENE_WARNING_PREFIX);
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, GR_SCENE_WARNING_PREFIX, plen) == 0) {
            size_t len = strlen(s->warnings);
            snprintf(s->warnings + len, sizeof s->warnings - len, "%s", line + plen);
        }
    }
    fclose(f);
}

int gr_scene_save(const gr_scene *s, const char *dir, gr_error *err)
{
    gr_file f;
    int rc = gr_file_open(&f, dir, "scene.ini", err);
    if (rc) {
        return rc;
    }
    gr_scene_write(s, f.f);
    return gr_file_commit(&f, err);
}

void gr_scene_write(const gr_scene *s, FILE *f)
{
    fprintf(f, "; resolved scene of this run (from %s); every key as the run used it\n", s->source);
    /* the load's warnings, for a resumed run's summary.json (gr_scene_saved_warnings) */
    for (const char *w = s->warnings; *w;) {
        size_t n = strcspn(w, "\n");
        fprintf(f, "%s%.*s\n", GR_SCENE_WARNING_PREFIX, (int)n, w);
        w += n + (w[n] == '\n');
    }
    const char *section = "";
    for (int i = 0; i < n_keys; i++) {
        const scene_key *k = &keys[i];
        if (k->offset == offsetof(gr_scene, packing_fraction) ||
            k->offset == offsetof(gr_scene, reduced_length)) {
            continue; /* derived: L is written */
        }
        if (k->offset == offsetof(gr_scene, dt) && s->dt <= 0.0) {
            continue;
        }
        if (k->offset == offsetof(gr_scene, steps_per_contact) && s->dt > 0.0) {
            continue;
        }
        const bool rfm = !s->driving || s->driving == gr_driving_default();
        if (k->type == K_DRIVING && rfm) {
            continue; /* the default: scene.ini of an rfm run is what it always was */
        }
        const bool walls = s->boundary[0] || s->boundary[1] || s->gravity[0] != 0.0 ||
                           s->gravity[1] != 0.0 || s->gravity[2] != 0.0;
        if (!walls && (!strcmp(k->section, "boundary") || !strcmp(k->section, "gravity"))) {
            continue; /* the periodic box: scene.ini as it always was */
        }
        if (k->type == K_NUMBERS &&
            ((const gr_number_list *)((const char *)s + k->offset))->n == 0) {
            continue; /* [species] unset: one species, scene.ini as it always was */
        }
        if (!strcmp(k->section, "species") && k->type != K_NUMBERS && !s->size_distribution) {
            continue; /* no radius distribution: scene.ini as it always was */
        }
        if (k->offset == offsetof(gr_scene, motion) && s->motion == GR_WALL_SINE) {
            continue; /* the default: the walls scenes' scene.ini as before */
        }
        if ((k->offset == offsetof(gr_scene, wall_eps_n) && !(s->wall_eps_n != s->contact.eps_n)) ||
            (k->offset == offsetof(gr_scene, wall_eps_t) && !(s->wall_eps_t != s->contact.eps_t)) ||
            (k->offset == offsetof(gr_scene, wall_mu) && !(s->wall_mu != s->contact.mu))) {
            continue; /* the particles' (unset): read back as [model]'s */
        }
        if (k->offset == offsetof(gr_scene, kick_interval) && s->kick_interval_default &&
            s->integrator->free_flight && !s->integrator->instantaneous) {
            continue; /* the hybrid's default window: unset, so a resume rounds it again */
        }
        if (k->offset == offsetof(gr_scene, noise_precision) &&
            s->noise_precision == GR_NOISE_DOUBLE) {
            continue; /* the default: scene.ini and checkpoints of double runs are unchanged */
        }
        if (!rfm && strcmp(k->section, "noise") == 0) {
            continue; /* the random force's keys, unused (and warned about if given) under another driving */
        }
        if (strcmp(section, k->section) != 0) {
            section = k->section;
            fprintf(f, "\n[%s]\n", section);
        }
        fprintf(f, "%s = ", k->name);
        save_value(f, k, s);
        fputc('\n', f);
        if (strcmp(k->name, "tangential") == 0) {
            const gr_model *used[3] = {s->normal, s->tangential, s->rolling};
            for (int u = 0; u < 3; u++) {
                if (used[u]) {
                    save_params(f, used[u]->params, used[u]->n_params, &s->contact);
                }
            }
        }
        if (strcmp(k->name, "observables") == 0) {
            for (int o = 0; gr_observables[o]; o++) {
                save_params(f, gr_observables[o]->params, gr_observables[o]->n_params,
                            gr_analysis_block_const(&s->analysis, gr_observables[o]));
            }
        }
        if (k->type == K_DRIVING) {
            save_params(f, s->driving->params, s->driving->n_params, &s->driving_params);
        }
    }
}
