/* The contact coefficients granule derives for a scene, printed as shell assignments, with their
 * LAMMPS pair_style gran/hooke equivalents (bench/lammps.sh evaluates this output).
 *
 *   bench_coeffs SCENE [--set section.key=value ...]
 *
 * granule's forces (thesis 2.4-2.5, 2.9): F_n = k_s xi - gamma_n (v12 . n), F_t = -gamma_t (v12 . t),
 * gamma_n and gamma_t in kg/s. LAMMPS gran/hooke multiplies its damping constants by the pair's
 * effective mass (meff = m_i m_j / (m_i + m_j) = M/2 = m12), so its gamma_n and gamma_t are in
 * 1/s: gamman_lammps = gamma_n / m12 = 2 zeta w0, gammat_lammps = gamma_t / m12. Kn = k_s (N/m).
 * LAMMPS clamps F_n >= 0, which is granule's clamp = true; the tangential force in LAMMPS is
 * capped at xmu |F_n|, so a pure dashpot needs xmu large (its maximum, 1e4). The random force
 * per component per step has standard deviation sqrt(2 D / dt) (eqs. 2.16, 2.23). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "granule/granule.h"

int main(int argc, char **argv)
{
    const char *scene_path = NULL;
    const char *sets[64];
    int n_sets = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--set") && i + 1 < argc && n_sets < 64) {
            sets[n_sets++] = argv[++i];
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            fprintf(stderr, "usage: bench_coeffs SCENE [--set section.key=value ...]\n");
            return 2;
        }
    }
    if (!scene_path) {
        fprintf(stderr, "usage: bench_coeffs SCENE [--set section.key=value ...]\n");
        return 2;
    }
    gr_scene sc;
    gr_error err = {0};
    if (gr_scene_load(&sc, scene_path, sets, n_sets, &err)) {
        fprintf(stderr, "bench_coeffs: %s\n", err.message);
        return 2;
    }
    if (!(sc.dt > 0.0)) {
        fprintf(
            stderr,
            "bench_coeffs: %s: give [integrator] dt explicitly (LAMMPS needs the same fixed dt)\n",
            scene_path);
        return 2;
    }
    const double m12 = gr_scene_m12(&sc);
    gr_contact_coeffs c;
    if (gr_contact_prepare(sc.normal, sc.tangential, &sc.contact, m12, sc.dt, &c, &err)) {
        fprintf(stderr, "bench_coeffs: %s\n", err.message);
        return 2;
    }
    /* LAMMPS gran/hooke has a tangential dashpot only */
    const bool dashpot = c.tangential_model == gr_model_find("tangential_dashpot");
    double noise_sigma = sc.noise_mode == GR_NOISE_NONE ? 0.0 : sqrt(2.0 * sc.D / sc.dt);
    printf("dim=%d\nN=%d\nL=%.17g\nradius=%.17g\nmass=%.17g\ndt=%.17g\n", sc.dim, sc.N, sc.L,
           sc.radius, sc.mass, sc.dt);
    printf("normal=%s\ntangential=%s\nclamp=%d\n", sc.normal->name,
           sc.tangential ? sc.tangential->name : "none", c.clamp ? 1 : 0);
    printf(
        "k_s=%.17g\nm12=%.17g\ngamma_n=%.17g\ngamma_t=%.17g\nt_c=%.17g\neps_n=%.17g\neps_t=%.17g\n",
        c.k_s, m12, c.gamma_n, dashpot ? c.gamma_t : 0.0, c.t_c, sc.contact.eps_n,
        sc.contact.eps_t);
    printf("noise_sigma=%.17g\nnoise_mode=%s\nseed=%llu\n", noise_sigma,
           gr_noise_mode_name(sc.noise_mode), (unsigned long long)sc.seed);
    printf("lammps_kn=%.17g\nlammps_gamman=%.17g\nlammps_gammat=%.17g\n", c.k_s, c.gamma_n / m12,
           dashpot ? c.gamma_t / m12 : 0.0);
    printf("warmup=%.17g\nduration=%.17g\nsample_every=%.17g\n", sc.warmup, sc.duration,
           sc.sample_every);
    return 0;
}
