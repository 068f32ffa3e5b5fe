/* The reproduction page's coverage table and its check against the campaigns (coverage.c). */
#ifndef GRANULE_APP_REPRODUCE_COVERAGE_H
#define GRANULE_APP_REPRODUCE_COVERAGE_H

#include <stddef.h>
#include <stdio.h>

/* Read ROOT/../thesis-coverage.md (absent: nothing, 0) and check it against every compiled-in
 * campaign's covers line. Returns the number of disagreements (described in `problems`, "; "
 * separated); with none and out != NULL, writes the page's "Coverage of the thesis" section. */
int gr_reproduction_coverage(FILE *out, const char *root, char *problems, size_t len);

#endif
