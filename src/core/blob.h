/* Binary blobs: a growable write buffer and a bounds-checked reader. The core serialises a
 * simulation into one (gr_sim_save_state) and reads it back; the io layer writes it to a
 * checkpoint file (src/io/checkpoint.c), and src/analysis/blob_stats.h adds the analysis accumulators.
 *
 * Values are stored in the machine's own byte order and sizes (the checkpoint header records
 * both and refuses a file from a different machine layout), so doubles round-trip bit for bit.
 * A writer that ran out of memory remembers it (gr_blob_ok); a reader that would run past the
 * end stops, records where (section, offset, wanted bytes) and every later read fails, so
 * callers may check once at the end of a section. */
#ifndef GR_CORE_BLOB_H
#define GR_CORE_BLOB_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "granule/status.h"

typedef struct gr_blob {
    unsigned char *data;
    size_t len, cap;
    bool oom;
} gr_blob;

void gr_blob_free(gr_blob *b);
/* CRC-32 (zlib's) of len bytes: the checksum of checkpoint files and of gr_sim_state_save's bytes. */
uint32_t gr_blob_crc32(const void *data, size_t len);
void gr_blob_put(gr_blob *b, const void *p, size_t n);
void gr_blob_put_u32(gr_blob *b, uint32_t v);
void gr_blob_put_u64(gr_blob *b, uint64_t v);
void gr_blob_put_i64(gr_blob *b, int64_t v);
void gr_blob_put_f64(gr_blob *b, double v);
/* A length-prefixed array (u64 count, then the elements). */
void gr_blob_put_f64s(gr_blob *b, const double *v, int64_t n);
void gr_blob_put_str(gr_blob *b, const char *s);
/* GR_OK, or GR_ENOMEM with a message. */
int gr_blob_ok(const gr_blob *b, gr_error *err);

typedef struct gr_blob_reader {
    const unsigned char *data;
    size_t len, pos;
    const char *what; /* section name, for messages */
    bool bad;
    char why[200]; /* first failure */
} gr_blob_reader;

void gr_blob_reader_init(gr_blob_reader *r, const void *data, size_t len, const char *what);
bool gr_blob_get(gr_blob_reader *r, void *p, size_t n);
uint32_t gr_blob_get_u32(gr_blob_reader *r);
uint64_t gr_blob_get_u64(gr_blob_reader *r);
int64_t gr_blob_get_i64(gr_blob_reader *r);
double gr_blob_get_f64(gr_blob_reader *r);
/* An array written by gr_blob_put_f64s whose count must be exactly n. */
bool gr_blob_get_f64s(gr_blob_reader *r, double *v, int64_t n);
/* A string of at most cap - 1 bytes, NUL-terminated into s. */
bool gr_blob_get_str(gr_blob_reader *r, char *s, size_t cap);
/* A borrowed view of the next n bytes (NULL on failure). */
const void *gr_blob_view(gr_blob_reader *r, size_t n);
/* Mark the reader failed with a message (printf-style), unless it already failed. */
void gr_blob_fail(gr_blob_reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* GR_OK if every read succeeded and the section was consumed exactly; otherwise GR_EINVAL with
 * "checkpoint section <what>: <why>". */
int gr_blob_done(gr_blob_reader *r, gr_error *err);

/* One list for saving and loading: a state's `io` function names every field once, in order,
 * with these calls; with `out` set they append to the blob, with `in` set they read back in the
 * same order. So the save and the load cannot drift apart (docs/checkpoints.md). A failed read
 * marks the reader bad (the whole load then fails with its message) and every later call does
 * nothing. */
typedef struct gr_blob_io {
    gr_blob *out;       /* saving */
    gr_blob_reader *in; /* loading */
} gr_blob_io;

static inline bool gr_blob_io_loading(const gr_blob_io *io) { return io->in != NULL; }
/* Loading and a read already failed. */
bool gr_blob_io_bad(const gr_blob_io *io);
/* Loading: the bytes left to read (a bound for a stored count). */
size_t gr_blob_io_left(const gr_blob_io *io);
/* Mark a load failed (printf-style), e.g. inconsistent counters. */
void gr_blob_io_fail(gr_blob_io *io, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void gr_blob_io_i64(gr_blob_io *io, int64_t *v);
void gr_blob_io_f64(gr_blob_io *io, double *v);
void gr_blob_io_u32(gr_blob_io *io, uint32_t *v);
/* An int stored as i64 (counters, indices). */
void gr_blob_io_int(gr_blob_io *io, int *v);
/* n doubles as a counted array (gr_blob_put_f64s); the count must agree on load. */
void gr_blob_io_f64s(gr_blob_io *io, double *v, int64_t n);
/* n raw bytes. */
void gr_blob_io_bytes(gr_blob_io *io, void *v, size_t n);
/* A size fixed by the scene (a number of bins, lags, particles): stored as u64, and on load it
 * must equal `value` ("<what> = <stored> in the checkpoint, <value> in the scene"). */
void gr_blob_io_check(gr_blob_io *io, const char *what, int64_t value);
/* A value fixed by the scene, stored as i64 / f64: on load it must be the same, bit for bit
 * ("<what> is <stored> in the checkpoint but <value> for this scene"). */
void gr_blob_io_expect_i64(gr_blob_io *io, const char *what, int64_t value);
void gr_blob_io_expect_f64(gr_blob_io *io, const char *what, double value);
/* A tag naming the layout that follows: on load anything else fails ("<what> layout ..."). */
void gr_blob_io_tag(gr_blob_io *io, const char *what, uint32_t tag);

#endif
