/* Checkpoint files: format, verification, atomic writing (see checkpoint.h). */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "core/blob.h"
#include "io/checkpoint.h"
#include "io/files.h"

static const char MAGIC[8] = {'G', 'R', 'C', 'H', 'K', 'P', 'T', '\n'};
#define BYTE_ORDER_MARK 0x01020304u
/* magic, version, byte order, 4 sizes + 4 zero bytes, total length, hash, section count */
#define HEADER_LEN (8 + 4 + 4 + 4 + 4 + 8 + 8 + 4)
#define SECTION_HEAD (4 + 8)
#define TRAILER_LEN 4

static uint32_t crc_of(const unsigned char *p, size_t len) { return gr_blob_crc32(p, len); }

int gr_checkpoint_read_buffer(const void *buf, size_t len, gr_checkpoint *out, gr_error *err)
{
    memset(out, 0, sizeof *out);
    const unsigned char *p = buf;
    if (len < sizeof MAGIC || memcmp(p, MAGIC, sizeof MAGIC) != 0) {
        return GR_FAIL(
            err, GR_EINVAL,
            "checkpoint: not a granule checkpoint (%zu bytes, no GRCHKPT magic at the start)", len);
    }
    if (len < HEADER_LEN + TRAILER_LEN) {
        return GR_FAIL(err, GR_EINVAL,
                       "checkpoint: truncated at byte %zu, inside the %d-byte header", len,
                       HEADER_LEN);
    }
    uint32_t version, bom;
    memcpy(&version, p + 8, 4);
    memcpy(&bom, p + 12, 4);
    if (bom != BYTE_ORDER_MARK) {
        return GR_FAIL(err, GR_EINVAL,
                       "checkpoint: written on a machine with a different byte order (mark %08x); "
                       "resume it on the kind of machine that wrote it",
                       bom);
    }
    if (version != GR_CHECKPOINT_VERSION) {
        return GR_FAIL(err, GR_EINVAL,
                       "checkpoint: format version %u, this granule reads version %u only", version,
                       GR_CHECKPOINT_VERSION);
    }
    const unsigned char want[4] = {sizeof(int), sizeof(long), sizeof(double), sizeof(void *)};
    if (memcmp(p + 16, want, 4) != 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "checkpoint: written with type sizes int/long/double/pointer = %u/%u/%u/%u, "
                       "this machine has %u/%u/%u/%u",
                       p[16], p[17], p[18], p[19], want[0], want[1], want[2], want[3]);
    }
    uint64_t total, hash;
    uint32_t nsec;
    memcpy(&total, p + 24, 8);
    memcpy(&hash, p + 32, 8);
    memcpy(&nsec, p + 40, 4);
    if (len < total) {
        return GR_FAIL(err, GR_EINVAL,
                       "checkpoint: truncated at byte %zu of %llu (the write was cut short or the "
                       "file was cut)",
                       len, (unsigned long long)total);
    }
    if (len > total) {
        return GR_FAIL(err, GR_EINVAL,
                       "checkpoint: %zu bytes where the header says %llu: trailing garbage", len,
                       (unsigned long long)total);
    }
    uint32_t stored, computed = crc_of(p, len - TRAILER_LEN);
    memcpy(&stored, p + len - TRAILER_LEN, 4);
    if (stored != computed) {
        return GR_FAIL(err, GR_EINVAL,
                       "checkpoint: checksum mismatch (CRC-32 stored %08x, computed %08x): the "
                       "file is corrupt",
                       stored, computed);
    }
    if (nsec > GR_CHECKPOINT_MAX_SECTIONS) {
        return GR_FAIL(err, GR_EINVAL, "checkpoint: %u sections, at most %d are allowed", nsec,
                       GR_CHECKPOINT_MAX_SECTIONS);
    }
    size_t pos = HEADER_LEN, end = len - TRAILER_LEN;
    for (uint32_t s = 0; s < nsec; s++) {
        if (end - pos < SECTION_HEAD) {
            return GR_FAIL(err, GR_EINVAL,
                           "checkpoint: section %u header runs past the end (byte %zu of %zu)", s,
                           pos, end);
        }
        gr_checkpoint_section *sec = &out->sections[s];
        memcpy(sec->tag, p + pos, 4);
        sec->tag[4] = 0;
        uint64_t slen;
        memcpy(&slen, p + pos + 4, 8);
        pos += SECTION_HEAD;
        if (slen > end - pos) {
            return GR_FAIL(
                err, GR_EINVAL,
                "checkpoint: section %s of %llu bytes runs past the end (byte %zu of %zu)",
                sec->tag, (unsigned long long)slen, pos, end);
        }
        sec->data = p + pos;
        sec->len = (size_t)slen;
        pos += (size_t)slen;
    }
    if (pos != end) {
        return GR_FAIL(err, GR_EINVAL, "checkpoint: %zu bytes after the last section", end - pos);
    }
    out->version = version;
    out->scene_hash = hash;
    out->n_sections = (int)nsec;
    return GR_OK;
}

const gr_checkpoint_section *gr_checkpoint_find(const gr_checkpoint *c, const char *tag)
{
    for (int i = 0; i < c->n_sections; i++) {
        if (strncmp(c->sections[i].tag, tag, 4) == 0) {
            return &c->sections[i];
        }
    }
    return NULL;
}

int gr_checkpoint_build(uint64_t scene_hash, const gr_checkpoint_section *sections, int n,
                        void **out, size_t *out_len, gr_error *err)
{
    *out = NULL;
    *out_len = 0;
    if (n < 0 || n > GR_CHECKPOINT_MAX_SECTIONS) {
        return GR_FAIL(err, GR_EINVAL, "checkpoint: %d sections, at most %d are allowed", n,
                       GR_CHECKPOINT_MAX_SECTIONS);
    }
    size_t total = HEADER_LEN + TRAILER_LEN;
    for (int i = 0; i < n; i++) {
        total += SECTION_HEAD + sections[i].len;
    }
    unsigned char *p = malloc(total);
    if (!p) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for a checkpoint of %zu bytes", total);
    }
    memset(p, 0, HEADER_LEN);
    memcpy(p, MAGIC, 8);
    const uint32_t version = GR_CHECKPOINT_VERSION, bom = BYTE_ORDER_MARK, nsec = (uint32_t)n;
    const uint64_t total64 = total;
    memcpy(p + 8, &version, 4);
    memcpy(p + 12, &bom, 4);
    p[16] = sizeof(int);
    p[17] = sizeof(long);
    p[18] = sizeof(double);
    p[19] = sizeof(void *);
    memcpy(p + 24, &total64, 8);
    memcpy(p + 32, &scene_hash, 8);
    memcpy(p + 40, &nsec, 4);
    size_t pos = HEADER_LEN;
    for (int i = 0; i < n; i++) {
        const uint64_t slen = sections[i].len;
        memcpy(p + pos, sections[i].tag, 4);
        memcpy(p + pos + 4, &slen, 8);
        pos += SECTION_HEAD;
        if (slen) {
            memcpy(p + pos, sections[i].data, sections[i].len);
        }
        pos += sections[i].len;
    }
    const uint32_t crc = crc_of(p, pos);
    memcpy(p + pos, &crc, 4);
    *out = p;
    *out_len = total;
    return GR_OK;
}

int gr_checkpoint_write_file(const char *dir, const void *image, size_t len, gr_error *err)
{
    char path[1200], tmp[1220];
    snprintf(path, sizeof path, "%s/%s", dir, GR_CHECKPOINT_NAME);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
        return GR_FAIL(err, GR_EIO, "cannot write %s: %s", tmp, strerror(errno));
    }
    const unsigned char *p = image;
    size_t done = 0;
    while (done < len) {
        ssize_t w = write(fd, p + done, len - done);
        if (w < 0 && errno == EINTR) {
            continue;
        }
        if (w <= 0) {
            int e = errno;
            close(fd);
            unlink(tmp);
            return GR_FAIL(err, GR_EIO, "cannot write %s: %s (the previous checkpoint is kept)",
                           tmp, strerror(e));
        }
        done += (size_t)w;
    }
    if (fsync(fd) != 0) {
        int e = errno;
        close(fd);
        unlink(tmp);
        return GR_FAIL(err, GR_EIO, "cannot write %s: %s (the previous checkpoint is kept)", tmp,
                       strerror(e));
    }
    close(fd);
    if (rename(tmp, path) != 0) {
        int e = errno;
        unlink(tmp);
        return GR_FAIL(err, GR_EIO,
                       "cannot move %s into place: %s (the previous checkpoint is kept)", path,
                       strerror(e));
    }
    int dfd = open(dir, O_RDONLY | O_DIRECTORY);
    if (dfd >= 0) { /* make the rename itself durable */
        fsync(dfd);
        close(dfd);
    }
    return GR_OK;
}

int gr_checkpoint_load_file(const char *dir, void **buf, size_t *len, gr_error *err)
{
    *buf = NULL;
    *len = 0;
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, GR_CHECKPOINT_NAME);
    int why = 0;
    FILE *f = gr_input_fopen(path, &why);
    if (!f && why < 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: not a regular file (a checkpoint is a file granule wrote)", path);
    }
    if (!f) { /* a missing file or a symlink loop is bad input; a failing disk is not */
        const bool input = why != EIO && why != ENOMEM && why != EMFILE && why != ENFILE;
        return GR_FAIL(
            err, input ? GR_EINVAL : GR_EIO, "%s: cannot open the checkpoint: %s%s", path,
            strerror(why),
            why == ENOENT ? " (was the run started with checkpoints, and did it write one?)" : "");
    }
    struct stat st;
    if (fstat(fileno(f), &st) != 0) {
        fclose(f);
        return GR_FAIL(err, GR_EIO, "%s: cannot read the checkpoint: %s", path, strerror(errno));
    }
    size_t n = (size_t)st.st_size;
    unsigned char *p = malloc(n ? n : 1);
    if (!p) {
        fclose(f);
        return GR_FAIL(err, GR_ENOMEM, "%s: out of memory for %zu bytes", path, n);
    }
    size_t got = fread(p, 1, n, f);
    int bad = ferror(f);
    fclose(f);
    if (bad || got != n) {
        free(p);
        return GR_FAIL(err, GR_EIO, "%s: read %zu of %zu bytes", path, got, n);
    }
    *buf = p;
    *len = n;
    return GR_OK;
}
