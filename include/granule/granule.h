/* granule: a C engine for granular dynamics built around the Random Force Model.
 * Umbrella header: include this to use the library. */
#ifndef GRANULE_H
#define GRANULE_H

#include "granule/analysis.h"
#include "granule/bisect.h"
#include "granule/cascade.h"
#include "granule/cascade_study.h"
#include "granule/collide.h"
#include "granule/compare.h"
#include "granule/driving.h"
#include "granule/fokker_planck.h"
#include "granule/fokker_planck_study.h"
#include "granule/integrator.h"
#include "granule/model.h"
#include "granule/noise.h"
#include "granule/observe.h"
#include "granule/particles.h"
#include "granule/run.h"
#include "granule/scene.h"
#include "granule/sim.h"
#include "granule/spm.h"
#include "granule/spm_study.h"
#include "granule/status.h"

#endif
