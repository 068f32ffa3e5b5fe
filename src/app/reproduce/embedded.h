/* The scene and campaign files of docs/ compiled into the library (scripts/embed.py), so that a
 * campaign runs from any working folder and on a machine without the source tree. */
#ifndef GR_REPRODUCE_EMBEDDED_H
#define GR_REPRODUCE_EMBEDDED_H

typedef struct gr_embedded_file {
    const char *name; /* relative to docs/, e.g. "scenes/rfm-1d.ini", "campaigns/ch3-1d.ini" */
    const char *text;
} gr_embedded_file;

extern const gr_embedded_file gr_embedded_files[];
extern const int gr_embedded_count;

/* The text of docs/NAME, or NULL. */
const char *gr_embedded_find(const char *name);

#endif
