// SPDX-License-Identifier: MIT
/**
 * @file test_opt.c
 * @brief Issue 22 item 2: option tables read with getopt_long (hs_opt.h): "--opt value" and
 *        "--opt=value" alike, fields set by their parsers, errors for unknown options,
 *        abbreviations, flags given a value, missing values and stray arguments, --help from
 *        the table, and the value-option list that --config and run.conf use.
 */
#include "hs_args.h"
#include "hs_opt.h"
#include "testing.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct opts {
    uint32_t frames;
    float alpha;
    const char *out;
    bool direct;
    int mode;
} opts;

static const hs_opt_name k_modes[] = {
    {"single", 1, "expected single or multi"}, {"multi", 2, NULL}, {NULL, 0, NULL}};

static const hs_opt k_table[] = {
    {NULL, NULL, "\nInput:\n", NULL, 0, NULL},
    {"--frames", "N", "frames to render\nsecond line", hs_opt_u32, offsetof(opts, frames),
     &(const hs_opt_num){1, 100, "expected 1..100"}},
    {"--frame", NULL, "a flag that --frames must not be taken for", NULL, offsetof(opts, direct),
     NULL},
    {"--alpha", "X", "blend weight", hs_opt_positive, offsetof(opts, alpha),
     &(const hs_opt_num){0, 1, NULL}},
    {"--out", "DIR", "output folder", NULL, offsetof(opts, out), NULL},
    {"--mode", "M", "single | multi", hs_opt_enum, offsetof(opts, mode), k_modes},
};
#define N (sizeof(k_table) / sizeof(k_table[0]))

/* Parses a copy of the words (getopt_long may permute nothing here, but takes char **). */
static int parse(opts *o, int argc, const char *const *words)
{
    static char store[16][64];
    char *argv[17];
    for (int i = 0; i < argc; i++) {
        snprintf(store[i], sizeof(store[i]), "%s", words[i]);
        argv[i] = store[i];
    }
    argv[argc] = NULL;
    memset(o, 0, sizeof(*o));
    return hs_opt_parse("t", k_table, N, argc, argv, 1, o);
}

static void test_values_both_spellings(void)
{
    opts o;
    const char *a[] = {"t", "--frames", "7", "--alpha=0.5", "--out", "-dir", "--mode=multi",
                       "--frame"};
    CHECK_EQ_INT(parse(&o, 8, a), HS_ARG_NEXT);
    CHECK_EQ_INT(o.frames, 7);
    CHECK_NEAR(o.alpha, 0.5, 1e-6);
    CHECK(o.out && !strcmp(o.out, "-dir")); /* a value is never taken for an option */
    CHECK_EQ_INT(o.mode, 2);
    CHECK(o.direct);
}

static void test_errors(void)
{
    opts o;
    const char *unknown[] = {"t", "--bogus"};
    CHECK_EQ_INT(parse(&o, 2, unknown), HS_EXIT_BAD_ARGS);
    const char *abbrev[] = {"t", "--fr", "3"};
    CHECK_EQ_INT(parse(&o, 3, abbrev), HS_EXIT_BAD_ARGS);
    const char *abbrev2[] = {"t", "--out=x", "--mod", "single"};
    CHECK_EQ_INT(parse(&o, 4, abbrev2), HS_EXIT_BAD_ARGS);
    const char *flag_value[] = {"t", "--frame=1"};
    CHECK_EQ_INT(parse(&o, 2, flag_value), HS_EXIT_BAD_ARGS);
    const char *missing[] = {"t", "--frames"};
    CHECK_EQ_INT(parse(&o, 2, missing), HS_EXIT_BAD_ARGS);
    const char *stray[] = {"t", "--frames", "3", "extra"};
    CHECK_EQ_INT(parse(&o, 4, stray), HS_EXIT_BAD_ARGS);
    const char *range[] = {"t", "--frames", "101"};
    CHECK_EQ_INT(parse(&o, 3, range), HS_EXIT_BAD_ARGS);
    CHECK_EQ_INT(o.frames, 0); /* not set on failure */
    const char *enum_bad[] = {"t", "--mode", "triple"};
    CHECK_EQ_INT(parse(&o, 3, enum_bad), HS_EXIT_BAD_ARGS);
    const char *positive[] = {"t", "--alpha", "0"};
    CHECK_EQ_INT(parse(&o, 3, positive), HS_EXIT_BAD_ARGS);
    const char *help[] = {"t", "--frames", "2", "--help"};
    CHECK_EQ_INT(parse(&o, 4, help), HS_OPT_HELP);
    const char *help_short[] = {"t", "-h"};
    CHECK_EQ_INT(parse(&o, 2, help_short), HS_OPT_HELP);
    const char *dashes_value[] = {"t", "--out", "--"}; /* a value, not the end of options */
    CHECK_EQ_INT(parse(&o, 3, dashes_value), HS_ARG_NEXT);
    CHECK(o.out && !strcmp(o.out, "--"));
    const char *dashes[] = {"t", "--frame", "--"};
    CHECK_EQ_INT(parse(&o, 3, dashes), HS_EXIT_BAD_ARGS);
    /* parsing twice in one process starts over */
    const char *again[] = {"t", "--frames", "4"};
    CHECK_EQ_INT(parse(&o, 3, again), HS_ARG_NEXT);
    CHECK_EQ_INT(o.frames, 4);
}

/* A text row with a parser takes the arguments that are not options, between the options. */
typedef struct files {
    const char *a, *b;
    bool quiet;
} files;

static int take_file(const hs_opt_arg *a)
{
    files *f = a->target;
    if (f->a && f->b)
        return hs_bad_arg(a->cmd, a->value, NULL, "unexpected argument");
    *(f->a ? &f->b : &f->a) = a->value;
    return 0;
}

static const hs_opt k_files[] = {
    {NULL, NULL, "usage: t A B\n", take_file, 0, NULL},
    {"--quiet", NULL, "quiet", NULL, offsetof(files, quiet), NULL},
};

static void test_positional(void)
{
    char w0[] = "t", w1[] = "A", w2[] = "--quiet", w3[] = "B", w4[] = "C";
    char *argv[] = {w0, w1, w2, w3, w4, NULL};
    files f = {0};
    CHECK_EQ_INT(hs_opt_parse("t", k_files, 2, 4, argv, 1, &f), HS_ARG_NEXT);
    CHECK(f.a && !strcmp(f.a, "A") && f.b && !strcmp(f.b, "B") && f.quiet);
    memset(&f, 0, sizeof(f));
    CHECK_EQ_INT(hs_opt_parse("t", k_files, 2, 5, argv, 1, &f), HS_EXIT_BAD_ARGS);
    /* without such a row a word that is not an option is an error */
    char w5[] = "--frame";
    char *argv2[] = {w0, w5, w1, NULL};
    opts o = {0};
    CHECK_EQ_INT(hs_opt_parse("t", k_table, N, 3, argv2, 1, &o), HS_EXIT_BAD_ARGS);
    CHECK(o.direct); /* the flag before it was read */
}

static void test_help_and_value_names(void)
{
    const char *path = t_temp_file("test_opt_help.txt", "");
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (!f)
        return;
    hs_opt_print_help(f, k_table, N);
    fclose(f);
    size_t size = 0;
    char *text = t_read_file(path, &size);
    CHECK(text != NULL);
    if (text) {
        CHECK(strstr(text, "\nInput:\n  --frames N          frames to render\n"
                           "                      second line\n") != NULL);
        CHECK(strstr(text, "  --frame             a flag") != NULL);
        CHECK(strstr(text, "  --mode M            single | multi\n") != NULL);
        free(text);
    }
    const char *names[8];
    size_t k = hs_opt_value_names(k_table, N, names, 8);
    CHECK_EQ_INT(k, 4);
    CHECK(k == 4 && !strcmp(names[0], "--frames") && !strcmp(names[3], "--mode"));
}

int main(void)
{
    RUN(test_values_both_spellings);
    RUN(test_errors);
    RUN(test_positional);
    RUN(test_help_and_value_names);
    return t_finish();
}
