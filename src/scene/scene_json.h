#ifndef GR_SCENE_JSON_H
#define GR_SCENE_JSON_H

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "granule/scene.h"

/* The resolved scene (every key the run used) as a JSON object; caller deletes it. */
cJSON *gr_scene_to_json(const gr_scene *s);
/* FNV-1a hash of the resolved physics (output keys excluded), printed in CSV headers. */
uint64_t gr_scene_hash(const gr_scene *s);
/* Whether a run recorded with scene JSON `recorded` (summary.json's "scene", perhaps written by an
 * older granule) ran the physics of `now`: every key of both equal, and every key that only `now`
 * has at its default (a key added to granule since, which the older run had at that value). The
 * output keys are ignored. On false, why names the first differing key. For sweeps and campaigns
 * that outlive a granule version: a new key changes the hash but not the physics. */
bool gr_scene_json_compatible(const cJSON *recorded, const gr_scene *now, char *why, size_t len);

#endif
