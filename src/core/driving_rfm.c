/* [driving] kind = rfm: the thesis's random force (sec. 2.2.1, 2.3.1), unchanged: independent
 * Gaussian white noise per particle and component, <eta eta'> = 2 D delta(t - t') (2.15, 2.22),
 * held over a step as sqrt(2D/dt) xi (2.16, 2.23), symmetrised (2.18) or with the centre-of-mass
 * velocity removed ([noise] D, mode, com_interval keep their meaning; docs/integrator.md). It has
 * no parameters of its own: the [noise] section is its parameter set. The default driving. */
#include "granule/driving.h"

const gr_driving_type gr_driving_rfm = {
    .name = "rfm",
    .summary = "the thesis's random force: white noise of strength [noise] D (2.15-2.18), no drag; "
               "D = 0 or "
               "[noise] mode = none switches it off",
    .update = GR_DRIVE_FORCE,
};
