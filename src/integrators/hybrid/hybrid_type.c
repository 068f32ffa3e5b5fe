/* The hybrid integrator's registration: its hooks for the core and the run driver. */
#include "integrators/hybrid/hybrid.h"

/* End a call on a window boundary (at or before step + n, else the next one) unless the caller
 * must stop earlier, so the windows do not depend on how the steps are split into calls. */
static int64_t hybrid_call_steps(const gr_sim *s, int64_t n, int64_t todo)
{
    const int64_t q = gr_hybrid_window_steps(s);
    if (q > 1 && n < todo) {
        const int64_t end = (s->step + n) / q * q;
        n = end > s->step ? end - s->step : q - s->step % q;
        n = n < todo ? n : todo;
    }
    return n;
}

/* summary.json "hybrid" (docs/hybrid.md) */
static int hybrid_describe(const gr_sim *s, gr_integrator_figure *out, int cap)
{
    gr_hybrid_stats st;
    if (!gr_sim_hybrid_stats(s, &st) || cap < 5) {
        return 0;
    }
    out[0] = (gr_integrator_figure){"window", st.window};
    out[1] = (gr_integrator_figure){"windows", (double)st.windows};
    out[2] = (gr_integrator_figure){"rollbacks", (double)st.rollbacks};
    out[3] = (gr_integrator_figure){"active_fraction", st.active_fraction};
    out[4] = (gr_integrator_figure){"margin_sigmas", st.margin_sigmas};
    return 5;
}

const gr_integrator_type gr_integrator_hybrid = {
    .name = "hybrid",
    .summary = "free flight event-driven, contacts by the soft-sphere model (docs/hybrid.md)",
    .free_flight = true,
    .spheres = true,  /* 3D: the soft laws, with or without rotation (docs/hybrid.md, "Spheres") */
    .rotation = true, /* the active set's spins kicked by the child as step.c kicks them */
    .walls = true,    /* 2D and 3D: grains that could reach a wall are active (docs/hybrid.md) */
    .species = true,  /* species lists, com or no noise (docs/hybrid.md, "Mixtures") */
    .drag = true,     /* the Langevin bath at each window's end (hybrid.c, bath_window) */
    .threads = true,  /* the active set's forces, once it holds more than one block (child.c) */
    .create = gr_hybrid_init,
    .step = gr_hybrid_step,
    .free = gr_hybrid_free,
    .call_steps = hybrid_call_steps,
    .state_io = gr_hybrid_state_io,
    .describe = hybrid_describe,
    .section = "hybrid",
};
