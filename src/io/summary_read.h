/* JSON files: summary.json and manifests read back (for compare, sweep and tests), and any cJSON
 * tree written atomically. */
#ifndef GR_SUMMARY_READ_H
#define GR_SUMMARY_READ_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "granule/status.h"

/* Write j, indented, to DIR/NAME atomically (temporary + rename, io/files.h). */
int gr_json_write(const char *dir, const char *name, const cJSON *j, gr_error *err);
/* Parse a JSON file; the caller deletes the result. NULL with err set if missing/invalid. */
cJSON *gr_json_read(const char *path, gr_error *err);
/* Parse dir/summary.json; the caller deletes the result. NULL with err set if missing/invalid. */
cJSON *gr_summary_read(const char *dir, gr_error *err);
/* A number at a dotted path ("ledger.injected", "analysis.moments.speed.1"); a true/false flag
 * ("T_stderr_converged") reads 1/0; NAN if absent. */
double gr_summary_number(const cJSON *root, const char *path);
/* The unit of a summary scalar at a dotted path (UDUNITS-style, "1" for a pure number; moments
 * "analysis.moments.speed.m3" -> "m3 s-3", written into buf), NULL where granule does not know
 * it (src/io/summary_units.c). */
const char *gr_summary_unit(const char *path, char *buf, size_t size);
/* The node at a dotted path, of any type; NULL if absent. */
const cJSON *gr_summary_node(const cJSON *root, const char *path);

#endif
