/* The verlet integrator's registration (the scheme itself is step.c). */
#include "integrators/verlet/verlet.h"

const gr_integrator_type gr_integrator_verlet = {
    .name = "verlet",
    .rotation = true,
    .contact_history = true,
    .drag = true,
    .walls = true,
    .single_noise = true,
    .spheres = true,
    .species = true,
    .threads = true, /* identical grains; a run with species steps on one thread (step_poly.c) */
    .summary = "soft-sphere velocity Verlet (docs/integrator.md)",
    .step = gr_verlet_step,
};
