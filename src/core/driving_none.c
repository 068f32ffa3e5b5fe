/* [driving] kind = none: nothing drives the gas; between collisions the particles fly freely and
 * an inelastic gas cools (Haff's law, docs/validation.md). The same as the rfm with D = 0, which
 * every integrator supports: the engine runs the noise-free loop, so it costs nothing. */
#include "granule/driving.h"

const gr_driving_type gr_driving_none = {
    .name = "none",
    .summary = "no driving: free cooling (the [noise] keys are ignored)",
    .update = GR_DRIVE_OFF,
};
