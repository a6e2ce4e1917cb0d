// SPDX-License-Identifier: MIT
/**
 * @file test_cli_args.c
 * @brief The `xrsc` command-line conventions on the CPU (issue 11): --opt=value and --config
 *        FILE (hs_args_prepare), and whole-or-nothing output files (hs_file.h).
 */
#include "hs_args.h"
#include "hs_file.h"
#include "testing.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const values[] = {"--frames", "--out", "--scene", "--write"};
static const hs_args_spec spec = {.cmd = "xrsc",
                                  .value_options = values,
                                  .value_count = sizeof(values) / sizeof(values[0]),
                                  .config = true};

/* hs_args is large: one per test, on the heap. */
static hs_args *args_new(void)
{
    hs_args *a = malloc(sizeof(*a));
    if (a)
        memset(a, 0, sizeof(*a));
    return a;
}

/* Runs hs_args_prepare on a copy of argv (it may write into the strings). */
static int prepare(hs_args *a, int argc, const char *const *argv_in, char store[][256])
{
    char *argv[32];
    for (int i = 0; i < argc; i++) {
        snprintf(store[i], 256, "%s", argv_in[i]);
        argv[i] = store[i];
    }
    argv[argc] = NULL;
    return hs_args_prepare(a, &spec, argc, argv);
}

static bool args_are(const hs_args *a, int n, const char *const *want)
{
    if (a->argc != n)
        return false;
    for (int i = 0; i < n; i++)
        if (strcmp(a->argv[i], want[i]) != 0)
            return false;
    return a->argv[n] == NULL;
}

/* Whether stderr output of fn (run with the file as stderr) contains every needle. */
static char err_text[4096];
static int prepare_capturing(hs_args *a, int argc, const char *const *argv, char store[][256])
{
    fflush(stderr);
    int saved = dup(2);
    const char *path = t_temp_file("stderr.txt", "");
    FILE *f = fopen(path, "w");
    dup2(fileno(f), 2);
    int rc = prepare(a, argc, argv, store);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    fclose(f);
    size_t n = 0;
    char *text = t_read_file(path, &n);
    snprintf(err_text, sizeof(err_text), "%.*s", (int)n, text ? text : "");
    free(text);
    remove(path);
    return rc;
}

static void t_split_equals(void)
{
    hs_args *a = args_new();
    char store[32][256];
    const char *in[] = {"xrsc",      "replay",  "--frames=3", "--direct",
                        "--out=a=b", "--write", "--x=y"};
    CHECK_EQ_INT(prepare(a, 7, in, store), 0);
    /* A value option's value is never split (getopt_long): "--write" takes "--x=y". */
    const char *want[] = {"xrsc",  "replay", "--frames", "3",    "--direct",
                          "--out", "a=b",    "--write",  "--x=y"};
    CHECK(args_are(a, 9, want));
    const char *empty[] = {"xrsc", "--out="};
    CHECK_EQ_INT(prepare(a, 2, empty, store), 0);
    const char *want_empty[] = {"xrsc", "--out", ""};
    CHECK(args_are(a, 3, want_empty));
    free(a);
}

static void t_flag_with_value(void)
{
    hs_args *a = args_new();
    char store[32][256];
    const char *in[] = {"xrsc", "--direct=1"};
    CHECK_EQ_INT(prepare_capturing(a, 2, in, store), HS_EXIT_BAD_ARGS);
    CHECK_MSG(strstr(err_text, "--direct:") != NULL, "stderr: %s", err_text);
    free(a);
}

static void t_config(void)
{
    hs_args *a = args_new();
    char store[32][256];
    const char *conf = t_temp_file("a.conf", "# comment\n"
                                             "\n"
                                             "frames = 5   # trailing comment\n"
                                             "--direct\n"
                                             "  out \"dir with # and \\\"q\\\"\"\n"
                                             "--scene=s.gltf\r\n"
                                             "validation\n");
    char cfg[1100];
    snprintf(cfg, sizeof(cfg), "--config=%s", conf);
    /* In place: options after it override it (the parse loops keep the last value). */
    const char *in[] = {"xrsc", "--frames", "1", cfg, "--frames", "9"};
    CHECK_EQ_INT(prepare(a, 6, in, store), 0);
    const char *want[] = {"xrsc",
                          "--frames",
                          "1",
                          "--frames",
                          "5",
                          "--direct",
                          "--out",
                          "dir with # and \"q\"",
                          "--scene",
                          "s.gltf",
                          "--validation",
                          "--frames",
                          "9"};
    CHECK(args_are(a, 13, want));
    for (int i = 0; i < a->argc; i++)
        if (i >= 13 || strcmp(a->argv[i], want[i]))
            fprintf(stderr, "  argv[%d] = '%s'\n", i, a->argv[i]);
    remove(conf);
    free(a);
}

/* Each bad line: exit code for bad arguments, the error names the file and the line. */
static void t_config_errors(void)
{
    static const struct {
        const char *text;
        int line;
        const char *field;
    } cases[] = {
        {"frames = 2\nbogus = 3\n", 2, "--bogus"}, /* unknown option with a value */
        {"\n\ndirect = yes\n", 3, "--direct"},     /* a flag given a value */
        {"frames\n", 1, "--frames"},               /* a value option without one */
        {"out = \"open\n", 1, "--out"},            /* unterminated quote */
        {"config = other.conf\n", 1, "--config"},  /* nesting */
        {"Frames = 2\n", 1, "--Frames"},           /* not an option name */
    };
    hs_args *a = args_new();
    char store[32][256];
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
        const char *conf = t_temp_file("bad.conf", cases[k].text);
        const char *in[] = {"xrsc", "--config", conf};
        CHECK_EQ_INT(prepare_capturing(a, 3, in, store), HS_EXIT_BAD_ARGS);
        char where[1200];
        snprintf(where, sizeof(where), "%s:%d: %s:", conf, cases[k].line, cases[k].field);
        CHECK_MSG(strstr(err_text, where) != NULL, "case %zu: want '%s' in: %s", k, where,
                  err_text);
        CHECK_MSG(strstr(err_text, "XRSC_ERROR_INVALID_ARGUMENT") != NULL, "case %zu", k);
        remove(conf);
    }
    const char *missing[] = {"xrsc", "--config", "/nonexistent/xrsc.conf"};
    CHECK_EQ_INT(prepare_capturing(a, 3, missing, store), HS_EXIT_BAD_ARGS);
    CHECK(strstr(err_text, "/nonexistent/xrsc.conf") != NULL);
    free(a);
}

/* A spec that lists its flags: any other key alone is an error naming file, line and key;
 * one that lists none keeps such keys for the option table (as above). */
static void t_config_flags(void)
{
    static const char *const flags[] = {"--quiet"};
    hs_args_spec fs = spec;
    fs.flag_options = flags;
    fs.flag_count = 1;
    hs_args *a = args_new();
    char ok_text[] = "frames = 2\nquiet\n", bad_text[] = "frames = 2\nquiet\nfresh\n";
    xrsc_diag d = {0};
    CHECK_EQ_INT(hs_args_config_text(a, &fs, "f.conf", ok_text, &d), XRSC_OK);
    CHECK(a->argc == 3 && !strcmp(a->argv[2], "--quiet"));
    a->argc = 0;
    CHECK_EQ_INT(hs_args_config_text(a, &fs, "f.conf", bad_text, &d), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(d.line == 3 && !strcmp(d.field, "--fresh") && !strcmp(d.file, "f.conf"));
    char any_text[] = "fresh\n";
    a->argc = 0;
    CHECK_EQ_INT(hs_args_config_text(a, &spec, "f.conf", any_text, &d), XRSC_OK);
    CHECK(a->argc == 1 && !strcmp(a->argv[0], "--fresh"));
    free(a);
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* hs_out_open/close: nothing under the final name until the close, then the whole file; an
 * aborted file leaves neither name. */
static void t_whole_files(void)
{
    char dir[] = "/tmp/xrsc-test-outXXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256], tmp[300];
    snprintf(path, sizeof(path), "%s/frame_00000_left.pfm", dir);
    CHECK(hs_temp_path(path, tmp, sizeof(tmp)));
    hs_out_file out;
    xrsc_diag d = {0};
    CHECK_EQ_INT(hs_out_open(&out, path, &d), XRSC_OK);
    fputs("partial", out.f);
    fflush(out.f);
    CHECK(!exists(path) && exists(tmp));
    CHECK_EQ_INT(hs_out_close(&out, true, &d), XRSC_OK);
    CHECK(exists(path) && !exists(tmp));
    size_t n = 0;
    char *text = t_read_file(path, &n);
    CHECK(n == 7 && text && !memcmp(text, "partial", 7));
    free(text);
    /* Aborted over an existing file: the old one stays whole, no temporary is left. */
    CHECK_EQ_INT(hs_out_open(&out, path, &d), XRSC_OK);
    fputs("x", out.f);
    CHECK_EQ_INT(hs_out_close(&out, false, &d), XRSC_OK);
    text = t_read_file(path, &n);
    CHECK(n == 7 && !exists(tmp));
    free(text);
    /* A folder that does not exist: an IO error naming the final path. */
    char bad[300];
    snprintf(bad, sizeof(bad), "%s/missing/x.png", dir);
    CHECK_EQ_INT(hs_out_open(&out, bad, &d), XRSC_ERROR_IO);
    CHECK(!strcmp(d.file, bad));
    CHECK_EQ_INT(hs_out_close(&out, true, &d), XRSC_OK);
    remove(path);
    rmdir(dir);
}

int main(void)
{
    RUN(t_split_equals);
    RUN(t_flag_with_value);
    RUN(t_config);
    RUN(t_config_errors);
    RUN(t_config_flags);
    RUN(t_whole_files);
    return t_finish();
}
