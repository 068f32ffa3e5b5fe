/* Binary blobs: the byte buffer the core serialises its state into (see blob.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "core/blob.h"

void gr_blob_free(gr_blob *b)
{
    free(b->data);
    *b = (gr_blob){0};
}

void gr_blob_put(gr_blob *b, const void *p, size_t n)
{
    if (b->oom || n == 0) {
        return;
    }
    if (b->len + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->len + n) {
            cap *= 2;
        }
        unsigned char *d = realloc(b->data, cap);
        if (!d) {
            b->oom = true;
            return;
        }
        b->data = d;
        b->cap = cap;
    }
    memcpy(b->data + b->len, p, n);
    b->len += n;
}

void gr_blob_put_u32(gr_blob *b, uint32_t v) { gr_blob_put(b, &v, sizeof v); }
void gr_blob_put_u64(gr_blob *b, uint64_t v) { gr_blob_put(b, &v, sizeof v); }
void gr_blob_put_i64(gr_blob *b, int64_t v) { gr_blob_put(b, &v, sizeof v); }
void gr_blob_put_f64(gr_blob *b, double v) { gr_blob_put(b, &v, sizeof v); }

void gr_blob_put_f64s(gr_blob *b, const double *v, int64_t n)
{
    gr_blob_put_i64(b, n);
    gr_blob_put(b, v, sizeof(double) * (size_t)n);
}

void gr_blob_put_str(gr_blob *b, const char *s)
{
    uint64_t n = strlen(s);
    gr_blob_put_u64(b, n);
    gr_blob_put(b, s, n);
}

int gr_blob_ok(const gr_blob *b, gr_error *err)
{
    return b->oom ? GR_FAIL(err, GR_ENOMEM, "out of memory writing a checkpoint (%zu bytes so far)",
                            b->len)
                  : GR_OK;
}

void gr_blob_reader_init(gr_blob_reader *r, const void *data, size_t len, const char *what)
{
    *r = (gr_blob_reader){.data = data, .len = len, .what = what};
}

void gr_blob_fail(gr_blob_reader *r, const char *fmt, ...)
{
    if (r->bad) {
        return;
    }
    r->bad = true;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->why, sizeof r->why, fmt, ap);
    va_end(ap);
}

const void *gr_blob_view(gr_blob_reader *r, size_t n)
{
    if (r->bad) {
        return NULL;
    }
    if (n > r->len - r->pos) {
        gr_blob_fail(r, "ends at byte %zu of the section, %zu more bytes needed", r->len,
                     n - (r->len - r->pos));
        return NULL;
    }
    const void *p = r->data + r->pos;
    r->pos += n;
    return p;
}

bool gr_blob_get(gr_blob_reader *r, void *p, size_t n)
{
    const void *src = gr_blob_view(r, n);
    if (!src) {
        return false;
    }
    if (n) {
        memcpy(p, src, n);
    }
    return true;
}

uint32_t gr_blob_get_u32(gr_blob_reader *r)
{
    uint32_t v = 0;
    gr_blob_get(r, &v, sizeof v);
    return v;
}

uint64_t gr_blob_get_u64(gr_blob_reader *r)
{
    uint64_t v = 0;
    gr_blob_get(r, &v, sizeof v);
    return v;
}

int64_t gr_blob_get_i64(gr_blob_reader *r)
{
    int64_t v = 0;
    gr_blob_get(r, &v, sizeof v);
    return v;
}

double gr_blob_get_f64(gr_blob_reader *r)
{
    double v = 0.0;
    gr_blob_get(r, &v, sizeof v);
    return v;
}

bool gr_blob_get_f64s(gr_blob_reader *r, double *v, int64_t n)
{
    int64_t m = gr_blob_get_i64(r);
    if (!r->bad && m != n) {
        gr_blob_fail(r, "holds %lld values where %lld are expected", (long long)m, (long long)n);
    }
    return gr_blob_get(r, v, sizeof(double) * (size_t)(r->bad ? 0 : n)) && !r->bad;
}

bool gr_blob_get_str(gr_blob_reader *r, char *s, size_t cap)
{
    uint64_t n = gr_blob_get_u64(r);
    if (!r->bad && n >= cap) {
        gr_blob_fail(r, "a string of %llu bytes exceeds the %zu allowed", (unsigned long long)n,
                     cap - 1);
    }
    if (r->bad || !gr_blob_get(r, s, (size_t)n)) {
        s[0] = 0;
        return false;
    }
    s[n] = 0;
    return true;
}

int gr_blob_done(gr_blob_reader *r, gr_error *err)
{
    if (!r->bad && r->pos != r->len) {
        gr_blob_fail(r, "%zu unexpected bytes after its end (byte %zu of %zu)", r->len - r->pos,
                     r->pos, r->len);
    }
    return r->bad ? GR_FAIL(err, GR_EINVAL, "checkpoint section %s: %s", r->what, r->why) : GR_OK;
}

uint32_t gr_blob_crc32(const void *data, size_t len)
{
    const unsigned char *p = data;
    uLong crc = crc32(0L, Z_NULL, 0);
    while (len > 0) { /* zlib takes uInt lengths */
        uInt chunk = len > (1u << 30) ? (1u << 30) : (uInt)len;
        crc = crc32(crc, p, chunk);
        p += chunk;
        len -= chunk;
    }
    return (uint32_t)crc;
}

bool gr_blob_io_bad(const gr_blob_io *io) { return io->in && io->in->bad; }

size_t gr_blob_io_left(const gr_blob_io *io) { return io->in ? io->in->len - io->in->pos : 0; }

void gr_blob_io_fail(gr_blob_io *io, const char *fmt, ...)
{
    if (!io->in || io->in->bad) {
        return;
    }
    char msg[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    gr_blob_fail(io->in, "%s", msg);
}

void gr_blob_io_i64(gr_blob_io *io, int64_t *v)
{
    if (!io->in) {
        gr_blob_put_i64(io->out, *v);
    } else if (!io->in->bad) {
        *v = gr_blob_get_i64(io->in);
    }
}

void gr_blob_io_int(gr_blob_io *io, int *v)
{
    int64_t w = *v;
    gr_blob_io_i64(io, &w);
    if (io->in && !io->in->bad) {
        if (w < INT32_MIN || w > INT32_MAX) {
            gr_blob_fail(io->in, "a count of %lld does not fit an int", (long long)w);
        } else {
            *v = (int)w;
        }
    }
}

void gr_blob_io_f64(gr_blob_io *io, double *v)
{
    if (!io->in) {
        gr_blob_put_f64(io->out, *v);
    } else if (!io->in->bad) {
        *v = gr_blob_get_f64(io->in);
    }
}

void gr_blob_io_u32(gr_blob_io *io, uint32_t *v)
{
    if (!io->in) {
        gr_blob_put_u32(io->out, *v);
    } else if (!io->in->bad) {
        *v = gr_blob_get_u32(io->in);
    }
}

void gr_blob_io_f64s(gr_blob_io *io, double *v, int64_t n)
{
    if (!io->in) {
        gr_blob_put_f64s(io->out, v, n);
    } else if (!io->in->bad) {
        gr_blob_get_f64s(io->in, v, n);
    }
}

void gr_blob_io_bytes(gr_blob_io *io, void *v, size_t n)
{
    if (!io->in) {
        gr_blob_put(io->out, v, n);
    } else if (!io->in->bad) {
        gr_blob_get(io->in, v, n);
    }
}

void gr_blob_io_check(gr_blob_io *io, const char *what, int64_t value)
{
    if (!io->in) {
        gr_blob_put_u64(io->out, (uint64_t)value);
    } else if (!io->in->bad) {
        uint64_t stored = gr_blob_get_u64(io->in);
        if (!io->in->bad && stored != (uint64_t)value) {
            gr_blob_fail(io->in, "%s = %llu in the checkpoint, %lld in the scene", what,
                         (unsigned long long)stored, (long long)value);
        }
    }
}

void gr_blob_io_expect_i64(gr_blob_io *io, const char *what, int64_t value)
{
    int64_t v = value;
    gr_blob_io_i64(io, &v);
    if (io->in && !io->in->bad && v != value) {
        gr_blob_fail(io->in, "%s is %lld in the checkpoint but %lld for this scene", what,
                     (long long)v, (long long)value);
    }
}

void gr_blob_io_expect_f64(gr_blob_io *io, const char *what, double value)
{
    double v = value;
    gr_blob_io_f64(io, &v);
    if (io->in && !io->in->bad && memcmp(&v, &value, sizeof v) != 0) {
        gr_blob_fail(io->in, "%s is %.17g in the checkpoint but %.17g for this scene", what, v,
                     value);
    }
}

void gr_blob_io_tag(gr_blob_io *io, const char *what, uint32_t tag)
{
    uint32_t t = tag;
    gr_blob_io_u32(io, &t);
    if (io->in && !io->in->bad && t != tag) {
        gr_blob_fail(io->in, "%s layout %08x, this build reads %08x", what, t, tag);
    }
}
