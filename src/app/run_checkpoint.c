/* Checkpoints of `granule run`: writing them and resuming from them (docs/checkpoints.md).
 *
 * Sections of a run's checkpoint:
 *   SCEN  the resolved scene as gr_scene_write prints it (checked key by key on resume)
 *   SRC   the scene's original source path (CSV headers and scene.ini name it)
 *   SIM   the simulation state (src/core/sim_state.c)
 *   OBS   every enabled observable's accumulators (gr_observer_save)
 *   RUN   the driver: next sample, T block averaging, the Haff's-law series of a cooling run,
 *         the snapshot schedule, and the streamed CSVs' temporary names and lengths
 * Checkpoints are taken between gr_sim_step calls and never change what a run computes: the
 * streamed CSVs are flushed (which only moves bytes to the kernel) and the state is read. */
#include <dirent.h>
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/sim_state.h"
#include "analysis/blob_stats.h"
#include "io/files.h"
#include "app/run_checkpoint.h"
#include "scene/scene_json.h"

#define RUN_STATE_TAG 0x52554e31u /* "RUN1" */

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* fflush + fsync of a streamed CSV; its length so far. */
static int sync_stream(gr_file *f, int64_t *length, gr_error *err)
{
    if (fflush(f->f) != 0 || fsync(fileno(f->f)) != 0) {
        return GR_FAIL(err, GR_EIO, "cannot write %s: %s", f->tmp, strerror(errno));
    }
    off_t pos = ftello(f->f);
    if (pos < 0) {
        return GR_FAIL(err, GR_EIO, "cannot tell the length of %s: %s", f->tmp, strerror(errno));
    }
    *length = (int64_t)pos;
    return GR_OK;
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

int gr_run_checkpoint_write(const char *dir, const gr_scene *scene, const gr_sim *sim,
                            const gr_observer *obs, const gr_run_ckpt *st, double *seconds,
                            size_t *bytes, gr_error *err)
{
    const double t0 = wall_now();
    int64_t len_t = 0, len_l = 0;
    int rc = sync_stream(st->ft, &len_t, err);
    rc = rc ? rc : sync_stream(st->fl, &len_l, err);
    rc = rc ? rc : gr_traj_writer_sync(st->traj, err);
    if (rc) {
        return rc;
    }
    char *text = NULL;
    size_t text_len = 0;
    FILE *m = open_memstream(&text, &text_len);
    if (!m) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory for the scene text of a checkpoint");
    }
    gr_scene_write(scene, m);
    fclose(m);
    gr_blob bsim = {0}, bobs = {0}, brun = {0};
    rc = gr_sim_save_state(sim, &bsim, err);
    rc = rc ? rc : gr_observer_save(obs, &bobs, err);
    if (!rc) {
        gr_blob_put_u32(&brun, RUN_STATE_TAG);
        gr_blob_put_i64(&brun, st->k_next);
        gr_blob_put_i64(&brun, st->per_sample);
        gr_blob_put_i64(&brun, st->warm_samples);
        gr_blob_put_i64(&brun, st->run_samples);
        gr_blob_put_blocking(&brun, st->blk);
        gr_blob_put_f64s(&brun, st->haff_t, *st->haff_n);
        gr_blob_put_f64s(&brun, st->haff_T, *st->haff_n);
        gr_blob_put_i64(&brun, *st->next_snap);
        gr_blob_put_i64(&brun, *st->snap_index);
        gr_blob_put_str(&brun, base_name(st->ft->tmp));
        gr_blob_put_i64(&brun, len_t);
        gr_blob_put_str(&brun, base_name(st->fl->tmp));
        gr_blob_put_i64(&brun, len_l);
        for (int w = 0; w < st->walls; w++) {
            gr_blob_put_blocking(&brun, &st->wall_blk[w]);
        }
        if (st->walls) {
            gr_blob_put_f64s(&brun, st->wall_prev, st->walls);
        }
        rc = gr_blob_ok(&brun, err);
    }
    void *image = NULL;
    size_t image_len = 0;
    if (!rc) {
        const gr_checkpoint_section sec[] = {
            {"SCEN", text, text_len},      {"SRC ", scene->source, strlen(scene->source)},
            {"SIM ", bsim.data, bsim.len}, {"OBS ", bobs.data, bobs.len},
            {"RUN ", brun.data, brun.len},
        };
        rc = gr_checkpoint_build(gr_scene_hash(scene), sec, (int)(sizeof sec / sizeof sec[0]),
                                 &image, &image_len, err);
    }
    free(text);
    gr_blob_free(&bsim);
    gr_blob_free(&bobs);
    gr_blob_free(&brun);
    if (!rc) {
        rc = gr_checkpoint_write_file(dir, image, image_len, err);
    }
    free(image);
    if (seconds) {
        *seconds = wall_now() - t0;
    }
    if (bytes) {
        *bytes = rc ? 0 : image_len;
    }
    return rc;
}

/* Partial files NAME.tmpPID (src/io/files.c) in folder `dir`: left by a process that was killed
 * or stopped while writing. Only a resume adopts two of them (the streamed CSVs it names), so
 * wherever this is called (a fresh start, a finished run) all are stale. */
static int remove_partials(const char *dir, gr_error *err)
{
    DIR *d = opendir(dir);
    if (!d) {
        return GR_OK; /* no such folder (e.g. no snapshots): nothing to clean */
    }
    int rc = GR_OK;
    for (struct dirent *de; !rc && (de = readdir(d));) {
        const char *tmp = strstr(de->d_name, ".tmp");
        if (!tmp || tmp == de->d_name || !tmp[4] ||
            strspn(tmp + 4, "0123456789") != strlen(tmp + 4)) {
            continue;
        }
        char path[1400];
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        if (unlink(path) != 0 && errno != ENOENT) {
            rc = GR_FAIL(err, GR_EIO, "cannot remove %s, a partial file of an interrupted run: %s",
                         path, strerror(errno));
        }
    }
    closedir(d);
    return rc;
}

bool gr_run_checkpoint_present(const char *dir)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, GR_CHECKPOINT_NAME);
    return access(path, F_OK) == 0;
}

int gr_run_checkpoint_guard(const char *dir, bool force, gr_error *err)
{
    if (force || !gr_run_checkpoint_present(dir)) {
        return GR_OK;
    }
    return GR_FAIL(err, GR_EINVAL,
                   "output folder %s holds the checkpoint of an interrupted run: continue it with "
                   "granule run --resume %s, or pass --force to discard it and start again",
                   dir, dir);
}

int gr_run_clear_leftovers(const char *dir, gr_error *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%.1100s/%s", dir, GR_CHECKPOINT_NAME);
    if (unlink(path) != 0 && errno != ENOENT) {
        return GR_FAIL(err, GR_EIO, "cannot remove the old checkpoint %s: %s", path,
                       strerror(errno));
    }
    int rc = remove_partials(dir, err);
    snprintf(path, sizeof path, "%.1100s/snapshots", dir);
    return rc ? rc : remove_partials(path, err);
}

/* ---------- scene comparison ---------- */

/* Keys that may differ on resume: they never change what the run computes. */
static bool may_differ(const char *section, const char *key)
{
    static const char *const ok[] = {"run.checkpoint_every", "run.checkpoint_wall",
                                     "run.wall_limit", "run.progress", "output.dir"};
    char full[160];
    snprintf(full, sizeof full, "%s.%s", section, key);
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        if (strcmp(full, ok[i]) == 0) {
            return true;
        }
    }
    return false;
}

/* The value of section.key in an INI text (a pointer to it and its length), or NULL. */
static const char *find_value(const char *text, size_t len, const char *section, const char *key,
                              size_t *vlen)
{
    char sec[64] = "";
    const char *p = text, *end = text + len;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *e = nl ? nl : end;
        size_t n = (size_t)(e - p);
        if (n > 2 && p[0] == '[' && p[n - 1] == ']') {
            snprintf(sec, sizeof sec, "%.*s", (int)(n - 2), p + 1);
        } else if (n > 0 && p[0] != ';' && strcmp(sec, section) == 0) {
            const char *eq = memchr(p, '=', n);
            size_t klen = strlen(key);
            if (eq && eq - p == (ptrdiff_t)(klen + 1) && memcmp(p, key, klen) == 0 &&
                p[klen] == ' ') {
                const char *v = eq + 1 + (eq + 1 < e && eq[1] == ' ');
                *vlen = (size_t)(e - v);
                return v;
            }
        }
        p = e + 1;
    }
    return NULL;
}

/* Check every key of `a` against `b`; *key_out names the first that differs. A key that only one
 * side has (a checkpoint written by a granule without it, say) is compared with the default
 * scene's value `dflt`, which is what that side ran with. */
static bool keys_agree(const char *a, size_t alen, const char *b, size_t blen, const char *dflt,
                       size_t dlen, char *msg, size_t msg_len, bool a_is_checkpoint,
                       bool *defaulted)
{
    char sec[64] = "";
    const char *p = a, *end = a + alen;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *e = nl ? nl : end;
        size_t n = (size_t)(e - p);
        if (n > 2 && p[0] == '[' && p[n - 1] == ']') {
            snprintf(sec, sizeof sec, "%.*s", (int)(n - 2), p + 1);
        } else if (n > 0 && p[0] != ';') {
            const char *eq = memchr(p, '=', n);
            if (eq) {
                char key[64];
                size_t klen = (size_t)(eq - p);
                while (klen > 0 && p[klen - 1] == ' ') {
                    klen--;
                }
                snprintf(key, sizeof key, "%.*s", (int)klen, p);
                const char *v = eq + 1 + (eq + 1 < e && eq[1] == ' ');
                size_t vlen = (size_t)(e - v), wlen = 0;
                const char *w = find_value(b, blen, sec, key, &wlen);
                if (!w) {
                    w = find_value(dflt, dlen, sec, key, &wlen);
                    *defaulted |= w != NULL;
                }
                if (!may_differ(sec, key) && (!w || wlen != vlen || memcmp(v, w, vlen) != 0)) {
                    const char *ck = a_is_checkpoint ? v : w, *now = a_is_checkpoint ? w : v;
                    size_t ck_len = a_is_checkpoint ? vlen : wlen,
                           now_len = a_is_checkpoint ? wlen : vlen;
                    snprintf(msg, msg_len, "[%s] %s = %.*s in the checkpoint, %.*s now", sec, key,
                             ck ? (int)(ck_len > 100 ? 100 : ck_len) : 7, ck ? ck : "(unset)",
                             now ? (int)(now_len > 100 ? 100 : now_len) : 7, now ? now : "(unset)");
                    return false;
                }
            }
        }
        p = e + 1;
    }
    return true;
}

int gr_scene_text_compare(const char *ck, size_t ck_len, const char *now, bool *defaulted,
                          gr_error *err)
{
    bool used_default = false;
    char msg[400];
    size_t now_len = strlen(now), dlen = 0;
    char *dflt = NULL;
    FILE *f = open_memstream(&dflt, &dlen);
    if (!f) {
        return GR_FAIL(err, GR_ENOMEM, "out of memory comparing the checkpoint's scene");
    }
    gr_scene d;
    gr_scene_default(&d);
    gr_scene_write(&d, f);
    fclose(f);
    bool same =
        keys_agree(ck, ck_len, now, now_len, dflt, dlen, msg, sizeof msg, true, &used_default) &&
        keys_agree(now, now_len, ck, ck_len, dflt, dlen, msg, sizeof msg, false, &used_default);
    free(dflt);
    if (defaulted) {
        *defaulted = used_default;
    }
    if (!same) {
        return GR_FAIL(err, GR_EINVAL,
                       "the scene differs from the one the checkpoint was written with: %s; "
                       "a resumed run must use the same scene (only run.checkpoint_every, "
                       "run.checkpoint_wall, run.wall_limit, run.progress may change)",
                       msg);
    }
    return GR_OK;
}

/* ---------- resuming ---------- */

int gr_run_resume_open(const char *dir, gr_scene *scene, void **buf, gr_checkpoint *ck,
                       gr_error *err)
{
    *buf = NULL;
    char path[1200];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    int why;
    FILE *sf = gr_input_fopen(path, &why);
    char status[64] = "?";
    if (sf) {
        char head[4096] = "";
        size_t got = fread(head, 1, sizeof head - 1, sf);
        head[got] = 0;
        fclose(sf);
        const char *s = strstr(head, "\"status\":");
        if (s) {
            sscanf(s + 9, " \"%63[^\"]\"", status);
        }
    }
    /* a run stopped by a failed write (a full disk) kept its checkpoint: it continues */
    if (sf && (!strcmp(status, "failed") || !strcmp(status, "interrupted")) &&
        !gr_run_checkpoint_present(dir)) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: this run stopped (summary.json, status %s) before its first "
                       "checkpoint, so it cannot be "
                       "continued: start it again with granule run %s/scene.ini --out %s --force",
                       dir, status, dir, dir);
    }
    if (sf && strcmp(status, GR_RUN_STATUS_WRITE_FAILED) != 0) {
        return GR_FAIL(err, GR_EINVAL,
                       "%s: this run has finished (summary.json, status %s): there is nothing to "
                       "resume and its "
                       "results are not overwritten; start a new run in another folder",
                       dir, status);
    }
    size_t len = 0;
    int rc = gr_checkpoint_load_file(dir, buf, &len, err);
    if (rc) {
        return rc;
    }
    gr_error perr = {0};
    if (gr_checkpoint_read_buffer(*buf, len, ck, &perr) != GR_OK) {
        free(*buf);
        *buf = NULL;
        return GR_FAIL(err, GR_EINVAL, "%s/%s is refused: %s", dir, GR_CHECKPOINT_NAME,
                       perr.message);
    }
    static const char *const need[] = {"SCEN", "SRC ", "SIM ", "OBS ", "RUN "};
    for (size_t i = 0; i < sizeof need / sizeof need[0]; i++) {
        if (!gr_checkpoint_find(ck, need[i])) {
            free(*buf);
            *buf = NULL;
            return GR_FAIL(err, GR_EINVAL,
                           "%s/%s is refused: it has no %.4s section (not a run checkpoint)", dir,
                           GR_CHECKPOINT_NAME, need[i]);
        }
    }
    const gr_checkpoint_section *src = gr_checkpoint_find(ck, "SRC ");
    if (src->len < sizeof scene->source) { /* CSV headers and scene.ini name the original scene */
        memcpy(scene->source, src->data, src->len);
        scene->source[src->len] = 0;
    }
    char *text = NULL;
    size_t text_len = 0;
    FILE *m = open_memstream(&text, &text_len);
    if (!m) {
        free(*buf);
        *buf = NULL;
        return GR_FAIL(err, GR_ENOMEM, "out of memory");
    }
    gr_scene_write(scene, m);
    fclose(m);
    const gr_checkpoint_section *sc = gr_checkpoint_find(ck, "SCEN");
    gr_error cerr = {0};
    bool older = false; /* the checkpoint's granule lacked keys: its hash covered fewer keys */
    rc = gr_scene_text_compare(sc->data, sc->len, text, &older, &cerr);
    free(text);
    if (!rc && !older && gr_scene_hash(scene) != ck->scene_hash) {
        rc = GR_FAIL(&cerr, GR_EINVAL,
                     "the scene's hash %016llx differs from the checkpoint's %016llx",
                     (unsigned long long)gr_scene_hash(scene), (unsigned long long)ck->scene_hash);
    }
    if (rc) {
        free(*buf);
        *buf = NULL;
        return GR_FAIL(err, GR_EINVAL, "%s/%s is refused: %s", dir, GR_CHECKPOINT_NAME,
                       cerr.message);
    }
    gr_scene_saved_warnings(scene, dir); /* the first start's warnings, for summary.json */
    return GR_OK;
}

/* Reopen a streamed CSV where the checkpoint left it. */
static int reopen(const char *dir, const char *name, const char *tmp, int64_t length, gr_file *f,
                  gr_error *err)
{
    size_t nlen = strlen(name);
    if (strchr(tmp, '/') || strncmp(tmp, name, nlen) != 0 || strncmp(tmp + nlen, ".tmp", 4) != 0 ||
        length < 0) {
        return GR_FAIL(err, GR_EINVAL, "checkpoint section RUN: '%s' is not a temporary file of %s",
                       tmp, name);
    }
    snprintf(f->path, sizeof f->path, "%s/%s", dir, name);
    snprintf(f->tmp, sizeof f->tmp, "%s/%s", dir, tmp);
    f->f = fopen(f->tmp, "r+");
    if (!f->f && errno == ENOENT && rename(f->path, f->tmp) == 0) {
        /* the run had already moved it into place (stopped unstable, or killed while finishing) */
        f->f = fopen(f->tmp, "r+");
    }
    if (!f->f) { /* missing (or a symlink loop): the folder does not hold what the checkpoint recorded */
        const int e = errno;
        const bool input = e != EIO && e != ENOMEM && e != EMFILE && e != ENFILE && e != ENOSPC;
        return GR_FAIL(err, input ? GR_EINVAL : GR_EIO,
                       "cannot continue %s: its partial file %s: %s", f->path, f->tmp, strerror(e));
    }
    struct stat st;
    if (fstat(fileno(f->f), &st) != 0 || (int64_t)st.st_size < length) {
        long long have = (long long)st.st_size;
        fclose(f->f);
        f->f = NULL;
        return GR_FAIL(
            err, GR_EINVAL,
            "cannot continue %s: %s holds %lld bytes, fewer than the %lld the checkpoint recorded",
            f->path, f->tmp, have, (long long)length);
    }
    /* rows written after the checkpoint are written again, identically */
    if (ftruncate(fileno(f->f), (off_t)length) != 0 || fseeko(f->f, 0, SEEK_END) != 0) {
        int e = errno;
        fclose(f->f);
        f->f = NULL;
        return GR_FAIL(err, GR_EIO, "cannot continue %s: %s", f->tmp, strerror(e));
    }
    return GR_OK;
}

int gr_run_resume_state(const gr_checkpoint *ck, const char *dir, gr_sim *sim, gr_observer *obs,
                        gr_run_ckpt *st, gr_error *err)
{
    const gr_checkpoint_section *s = gr_checkpoint_find(ck, "SIM ");
    gr_blob_reader r;
    gr_blob_reader_init(&r, s->data, s->len, "SIM (simulation state)");
    int rc = gr_sim_load_state(sim, &r, err);
    if (rc) {
        return rc;
    }
    s = gr_checkpoint_find(ck, "OBS ");
    rc = gr_observer_load(obs, s->data, s->len, err);
    if (rc) {
        return rc;
    }
    s = gr_checkpoint_find(ck, "RUN ");
    gr_blob_reader_init(&r, s->data, s->len, "RUN (run driver)");
    uint32_t tag = gr_blob_get_u32(&r);
    if (!r.bad && tag != RUN_STATE_TAG) {
        gr_blob_fail(&r, "layout %08x, this build reads %08x", tag, RUN_STATE_TAG);
    }
    int64_t k_next = gr_blob_get_i64(&r), per = gr_blob_get_i64(&r), warm = gr_blob_get_i64(&r),
            run = gr_blob_get_i64(&r);
    if (!r.bad && (per != st->per_sample || warm != st->warm_samples || run != st->run_samples)) {
        gr_blob_fail(&r, "%lld + %lld samples of %lld steps, the scene gives %lld + %lld of %lld",
                     (long long)warm, (long long)run, (long long)per, (long long)st->warm_samples,
                     (long long)st->run_samples, (long long)st->per_sample);
    }
    if (!r.bad && (k_next < 1 || k_next > warm + run + 1)) {
        gr_blob_fail(&r, "next sample %lld is outside 1..%lld", (long long)k_next,
                     (long long)(warm + run + 1));
    }
    const int64_t step = gr_sim_steps(sim);
    if (!r.bad && (step < (k_next - 1) * per || step > k_next * per)) {
        gr_blob_fail(&r, "the simulation is at step %lld, not between samples %lld and %lld",
                     (long long)step, (long long)(k_next - 1), (long long)k_next);
    }
    st->k_next = k_next;
    gr_blob_get_blocking(&r, st->blk);
    int64_t haff_n = gr_blob_get_i64(&r);
    if (!r.bad && (haff_n < 0 || haff_n > st->haff_cap)) {
        gr_blob_fail(&r, "%lld cooling-curve samples, room for %lld", (long long)haff_n,
                     (long long)st->haff_cap);
    }
    if (!r.bad) {
        r.pos -= 8; /* the count is read again by the checked array read */
        gr_blob_get_f64s(&r, st->haff_t, haff_n);
        gr_blob_get_f64s(&r, st->haff_T, haff_n);
        *st->haff_n = haff_n;
    }
    *st->next_snap = gr_blob_get_i64(&r);
    int64_t snap_index = gr_blob_get_i64(&r);
    if (!r.bad && (snap_index < 0 || snap_index > 100000000)) {
        gr_blob_fail(&r, "snapshot index %lld", (long long)snap_index);
    }
    *st->snap_index = (int)snap_index;
    char tmp_t[256], tmp_l[256];
    gr_blob_get_str(&r, tmp_t, sizeof tmp_t);
    int64_t len_t = gr_blob_get_i64(&r);
    gr_blob_get_str(&r, tmp_l, sizeof tmp_l);
    int64_t len_l = gr_blob_get_i64(&r);
    for (int w = 0; w < st->walls; w++) {
        gr_blob_get_blocking(&r, &st->wall_blk[w]);
    }
    if (st->walls) {
        gr_blob_get_f64s(&r, st->wall_prev, st->walls);
    }
    rc = gr_blob_done(&r, err);
    if (rc) {
        return rc;
    }
    rc = reopen(dir, "temperature.csv", tmp_t, len_t, st->ft, err);
    if (rc) {
        return rc;
    }
    rc = reopen(dir, "ledger.csv", tmp_l, len_l, st->fl, err);
    if (rc) {
        fclose(st->ft->f);
        st->ft->f = NULL;
        return rc;
    }
    return GR_OK;
}
