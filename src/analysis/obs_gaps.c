/* gaps observable: placeholder, being written (issue 4). Not registered yet. */
#include "granule/observe.h"

static int create(const struct gr_scene *scene, void **state, gr_error *err)
{
    (void)scene;
    (void)state;
    return GR_FAIL(err, GR_EINVAL, "observable gaps is not available yet");
}
static int sample(void *state, const gr_particles *p, double t, gr_error *err)
{
    (void)state;
    (void)p;
    (void)t;
    (void)err;
    return GR_OK;
}
static int finish(void *state, const gr_output *out, gr_error *err)
{
    (void)state;
    (void)out;
    (void)err;
    return GR_OK;
}
static void destroy(void *state) { (void)state; }

const gr_observable_type gr_obs_gaps = {
    .name = "gaps", .summary = "placeholder", .dims = 3, .create = create, .sample = sample,
    .finish = finish, .destroy = destroy,
};
