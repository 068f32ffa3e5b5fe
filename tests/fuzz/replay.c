/* Run a fuzz target's corpus without libFuzzer: every file in the folders (or files) given, once,
 * through LLVMFuzzerTestOneInput. Built by tests/meson.build with the ordinary compiler, so the
 * committed corpus (and every input that once found a bug) is a regression test in every build,
 * including the suite's AddressSanitizer pass; the clang build (scripts/fuzz.sh) does the fuzzing. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        return 1;
    }
    size_t cap = 1 << 16, n = 0;
    unsigned char *buf = malloc(cap);
    size_t got;
    while ((got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap);
        }
    }
    fclose(f);
    LLVMFuzzerTestOneInput(buf, n);
    free(buf);
    return 0;
}

int main(int argc, char **argv)
{
    int files = 0, bad = 0;
    for (int a = 1; a < argc; a++) {
        struct stat st;
        if (stat(argv[a], &st) == 0 && S_ISDIR(st.st_mode)) {
            struct dirent **list;
            int n = scandir(argv[a], &list, NULL, alphasort);
            for (int i = 0; i < n; i++) {
                if (list[i]->d_name[0] != '.') {
                    char path[4096];
                    snprintf(path, sizeof path, "%s/%s", argv[a], list[i]->d_name);
                    bad |= run_file(path);
                    files++;
                }
                free(list[i]);
            }
            free(n >= 0 ? list : NULL);
        } else {
            bad |= run_file(argv[a]);
            files++;
        }
    }
    printf("replay: %d inputs, no crash\n", files);
    return bad || files == 0;
}
