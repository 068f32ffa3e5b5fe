/* The common part of the Check test programs' main(): run one suite and turn its failures into
 * the exit status; and the temporary folders some programs write into (removed at the end unless
 * GRANULE_KEEP_TMP=1). */
#ifndef GR_CHECK_MAIN_H
#define GR_CHECK_MAIN_H

#include <check.h>
#include <errno.h>
#include <ftw.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Check's ck_assert_msg (and every typed ck_assert_* built on it) records each PASSED assertion's
 * file and line (_mark_point), which writes and flushes a message to the runner's temporary file:
 * a write(2) per assertion, which made tests that assert once per step (a grain bouncing for 1e6
 * steps) spend most of their time in the kernel. Here a passed assertion records nothing; a failed
 * one reports its file, line and message exactly as before. What is lost: a test that crashes is
 * reported at its last mark_point() rather than its last passed assertion (the sanitizer pass
 * prints the crash's stack instead). */
#undef ck_assert_msg
#define ck_assert_msg(expr, ...)                                                                   \
    ((expr)                                                                                        \
         ? (void)0                                                                                 \
         : _ck_assert_failed(__FILE__, __LINE__, "Assertion '" #expr "' failed", ##__VA_ARGS__))

/* Runs every test of s (CK_NORMAL: the failures and one summary line), frees the runner and s;
 * EXIT_SUCCESS when no test failed, EXIT_FAILURE otherwise. */
static inline int gr_test_run(Suite *s)
{
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}

/* GRANULE_KEEP_TMP set, non-empty and not "0": leave the test folders behind for inspection.
 * (Not test_env.h's env_flag: some test programs define their own quick() and do not include it.) */
static inline int gr_test_keep_tmp(void)
{
    const char *v = getenv("GRANULE_KEEP_TMP");
    return v && *v && strcmp(v, "0") != 0;
}

static inline int gr_test_rm_entry(const char *path, const struct stat *sb, int flag,
                                   struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

/* Removes dir and everything below it (links are removed, not followed). */
static inline void gr_test_rm_tree(const char *dir)
{
    nftw(dir, gr_test_rm_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* Makes root = $TMPDIR (or /tmp)/granule-test-TAG-XXXXXX, before Check forks, so that every test's
 * folder can live below it and a failing test (whose teardown Check skips) leaves nothing behind
 * once gr_test_tmp_root_done has run. 0 on success; otherwise says why on stderr as PROG. */
static inline int gr_test_tmp_root(char *root, size_t size, const char *prog, const char *tag)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(root, size, "%s/granule-test-%s-XXXXXX", tmp && *tmp ? tmp : "/tmp", tag);
    if (!mkdtemp(root)) {
        fprintf(stderr, "%s: mkdtemp %s: %s\n", prog, root, strerror(errno));
        return -1;
    }
    return 0;
}

/* Removes the root made by gr_test_tmp_root, or with GRANULE_KEEP_TMP=1 says where it is kept. */
static inline void gr_test_tmp_root_done(const char *root, const char *prog)
{
    if (gr_test_keep_tmp()) {
        fprintf(stderr, "%s: test folders kept in %s\n", prog, root);
    } else {
        gr_test_rm_tree(root);
    }
}

#endif
