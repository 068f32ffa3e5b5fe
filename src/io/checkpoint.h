/* Checkpoint files: everything a run needs to continue bit for bit (docs/checkpoints.md).
 *
 * Layout (all integers in the writer's byte order, which the header records):
 *   "GRCHKPT\n"  8-byte magic
 *   u32 version (GR_CHECKPOINT_VERSION), u32 0x01020304 (byte order)
 *   u8 sizeof(int), sizeof(long), sizeof(double), sizeof(void *); u32 zero
 *   u64 total file length, u64 scene hash (gr_scene_hash), u32 number of sections
 *   sections: 4-byte tag, u64 length, payload
 *   u32 CRC-32 (zlib) of every byte before it
 * The file is written to checkpoint.tmp, fsync'ed, renamed over `checkpoint` and the folder is
 * fsync'ed, so `checkpoint` is always a complete file: the previous one or the new one. */
#ifndef GR_CHECKPOINT_H
#define GR_CHECKPOINT_H

#include <stddef.h>
#include <stdint.h>

#include "granule/status.h"

#define GR_CHECKPOINT_VERSION 1u
#define GR_CHECKPOINT_MAX_SECTIONS 16
#define GR_CHECKPOINT_NAME "checkpoint"

typedef struct gr_checkpoint_section {
    char tag[5];      /* 4 characters + NUL */
    const void *data; /* borrowed from the buffer that was parsed */
    size_t len;
} gr_checkpoint_section;

typedef struct gr_checkpoint {
    uint32_t version;
    uint64_t scene_hash;
    int n_sections;
    gr_checkpoint_section sections[GR_CHECKPOINT_MAX_SECTIONS];
} gr_checkpoint;

/* Parse and verify a checkpoint held in memory: magic, version, byte order and type sizes,
 * length (a truncated file names the byte where it ends), CRC-32, section table. No side
 * effects besides filling *out (whose sections point into buf) and *err; never reads outside
 * [buf, buf + len). This is the fuzzing entry point. */
int gr_checkpoint_read_buffer(const void *buf, size_t len, gr_checkpoint *out, gr_error *err);

/* The section with this tag, or NULL. */
const gr_checkpoint_section *gr_checkpoint_find(const gr_checkpoint *c, const char *tag);

/* Build a checkpoint image from sections (tags of 4 characters). *out is malloc'ed. */
int gr_checkpoint_build(uint64_t scene_hash, const gr_checkpoint_section *sections, int n,
                        void **out, size_t *out_len, gr_error *err);

/* Write an image atomically as dir/checkpoint (temporary file, fsync, rename, fsync of dir). */
int gr_checkpoint_write_file(const char *dir, const void *image, size_t len, gr_error *err);

/* Read dir/checkpoint into a malloc'ed buffer; a missing file is GR_EINVAL naming the path. */
int gr_checkpoint_load_file(const char *dir, void **buf, size_t *len, gr_error *err);

#endif
