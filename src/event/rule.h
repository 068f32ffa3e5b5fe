/* The event-driven integrator's collision rule belongs to its model: models/hard_sphere.h
 * (gr_event_collide). */
#ifndef GR_EVENT_RULE_H
#define GR_EVENT_RULE_H

#include "models/hard_sphere.h"

#endif
