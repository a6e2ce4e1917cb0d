// SPDX-License-Identifier: MIT
/**
 * @file testing.c
 * @brief The tiny test harness behind testing.h.
 */
#include "testing.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

t_state t_g;

/** Whether name is one of the comma-separated names of list. */
static int t_listed(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && *p;) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (len == n && strncmp(p, name, n) == 0)
            return 1;
        p = end ? end + 1 : NULL;
    }
    return 0;
}

void t_run(const char *name, void (*fn)(void))
{
    /* issue 22: T_CASES=a,b runs only those cases, T_SKIP_CASES=a,b all but those, so that one
     * program can be two ctest entries that run side by side (tests/gpu/CMakeLists.txt) */
    const char *only = getenv("T_CASES"), *skip = getenv("T_SKIP_CASES");
    if ((only && *only && !t_listed(only, name)) || (skip && t_listed(skip, name)))
        return;
    int before = t_g.failures;
    /* CPU seconds of the case (all threads, lavapipe's included): what it costs on an idle
     * machine whatever else runs beside it (issue 22); printed, never asserted */
    clock_t c0 = clock();
    fn();
    double cpu_s = (double)(clock() - c0) / CLOCKS_PER_SEC;
    if (t_g.failures == before) {
        t_g.cases_passed++;
        fprintf(stderr, "[ ok ] %s (%.1f s CPU)\n", name, cpu_s);
    } else {
        t_g.cases_failed++;
        fprintf(stderr, "[FAIL] %s (%.1f s CPU)\n", name, cpu_s);
    }
}

int t_finish(void)
{
    printf("%d passed, %d failed\n", t_g.cases_passed, t_g.cases_failed);
    return t_g.cases_failed == 0 && t_g.failures == 0 ? 0 : 1;
}

static const char *join(const char *dir, const char *rel)
{
    static char buf[4][1024];
    static int next;
    char *b = buf[next++ % 4];
    snprintf(b, sizeof(buf[0]), "%s/%s", dir, rel);
    return b;
}

const char *t_source_path(const char *rel) { return join(XRSC_SOURCE_DIR, rel); }
const char *t_shared_path(const char *rel) { return join(XRSC_SHARED_DIR, rel); }

const char *t_temp_file(const char *name, const char *contents)
{
    static char path[4][1024];
    static int next;
    char *p = path[next++ % 4];
    const char *tmp = getenv("TMPDIR");
    snprintf(p, sizeof(path[0]), "%s/xrsc-test-%ld-%s", tmp ? tmp : "/tmp", (long)getpid(),
             name);
    FILE *f = fopen(p, "wb");
    if (f) {
        fwrite(contents, 1, strlen(contents), f);
        fclose(f);
    }
    return p;
}

void *t_read_file(const char *path, size_t *out_size)
{
    *out_size = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc(n > 0 ? (size_t)n : 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (buf)
        *out_size = (size_t)n;
    return buf;
}

char *t_data_uri(const void *data, size_t n)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    static const char prefix[] = "data:application/octet-stream;base64,";
    const unsigned char *p = data;
    char *out = malloc(sizeof prefix + (n + 2) / 3 * 4);
    if (!out)
        return NULL;
    memcpy(out, prefix, sizeof prefix - 1);
    char *o = out + sizeof prefix - 1;
    for (size_t i = 0; i < n; i += 3) {
        unsigned long v = (unsigned long)p[i] << 16;
        if (i + 1 < n)
            v |= (unsigned long)p[i + 1] << 8;
        if (i + 2 < n)
            v |= p[i + 2];
        *o++ = tab[v >> 18 & 63];
        *o++ = tab[v >> 12 & 63];
        *o++ = i + 1 < n ? tab[v >> 6 & 63] : '=';
        *o++ = i + 2 < n ? tab[v & 63] : '=';
    }
    *o = '\0';
    return out;
}
