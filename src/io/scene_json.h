#ifndef GR_SCENE_JSON_H
#define GR_SCENE_JSON_H

#include <cjson/cJSON.h>
#include <stdint.h>

#include "granule/scene.h"

/* The resolved scene (every key the run used) as a JSON object; caller deletes it. */
cJSON *gr_scene_to_json(const gr_scene *s);
/* FNV-1a hash of the resolved physics (output keys excluded), printed in CSV headers. */
uint64_t gr_scene_hash(const gr_scene *s);

#endif
