/* granule: a C engine for granular dynamics built around the Random Force Model.
 * Umbrella header: include this to use the library. */
#ifndef GRANULE_H
#define GRANULE_H

#include "granule/collide.h"
#include "granule/model.h"
#include "granule/noise.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "granule/status.h"

#endif
