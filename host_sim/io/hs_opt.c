// SPDX-License-Identifier: MIT
/**
 * @file hs_opt.c
 * @brief Option tables read with getopt_long, printed as --help (hs_opt.h).
 */
#include "hs_opt.h"

#include "hs_args.h"

#include <getopt.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

/* Help text starts in this column (after "  --name ARG"). */
#define HELP_COLUMN 22
/* Longest option name copied for an error. */
#define NAME_MAX_LEN 128

/* The option as typed, up to '=': "--frames" of "--frames=3". */
static const char *typed_name(const char *arg, char *buf)
{
    size_t k = strcspn(arg, "=");
    if (k >= NAME_MAX_LEN)
        k = NAME_MAX_LEN - 1;
    memcpy(buf, arg, k);
    buf[k] = '\0';
    return buf;
}

static const hs_opt *find(const hs_opt *t, size_t n, const char *name)
{
    for (size_t i = 0; i < n; i++)
        if (t[i].name && !strcmp(t[i].name, name))
            return &t[i];
    return NULL;
}

/* Why getopt_long refused argv[at] ('?' or ':'): printed, the exit status returned. */
static int refused(const char *cmd, const hs_opt *t, size_t n, const char *arg, int c)
{
    char buf[NAME_MAX_LEN];
    const char *name = typed_name(arg, buf);
    if (c == ':')
        return hs_bad_arg(cmd, name, NULL, "needs a value");
    const hs_opt *o = find(t, n, name);
    if (o && !o->arg && strchr(arg, '='))
        return hs_bad_arg(cmd, name, NULL, "takes no value (a flag), or is unknown: no '=' after it");
    return hs_bad_arg(cmd, name, NULL, "unknown option");
}

static int run_parser(const char *cmd, const hs_opt *o, const char *value, void *target)
{
    hs_opt_arg a = {cmd, o, value, (char *)target + o->offset, target};
    if (o->parse)
        return o->parse(&a);
    if (o->arg)
        *(const char **)a.field = value;
    else
        *(bool *)a.field = true;
    return 0;
}

/* getopt_long's table of t's options (lo, ending in a zero row; "help" returns 'h'), with the
 * row of each in rows; the text row that takes the other arguments, or NULL. Returns false
 * when t has more than HS_OPT_MAX options. */
static bool long_options(const hs_opt *t, size_t n, struct option *lo, const hs_opt **rows,
                         const hs_opt **positional)
{
    size_t k = 0;
    *positional = NULL;
    for (size_t i = 0; i < n; i++) {
        if (!t[i].name) {
            if (t[i].parse && !*positional)
                *positional = &t[i];
            continue;
        }
        if (k == HS_OPT_MAX)
            return false;
        lo[k] = (struct option){t[i].name + 2, t[i].arg ? required_argument : no_argument, NULL, 0};
        rows[k++] = &t[i];
    }
    lo[k++] = (struct option){"help", no_argument, NULL, 'h'};
    lo[k] = (struct option){0};
    return true;
}

/* One getopt_long result c for sub[at] (long option lo[idx]): parsed into target, or the exit
 * status of an error, or HS_OPT_HELP. */
static int one_option(const char *cmd, const hs_opt *t, size_t n, int c, const char *arg,
                      const char *typed, const hs_opt *row, void *target)
{
    if (c == '?' || c == ':')
        return refused(cmd, t, n, arg, c);
    if (c == 'h')
        return strcmp(arg, "-h") && strcmp(arg, "--help")
                   ? hs_bad_arg(cmd, typed, NULL, "unknown option") /* an abbreviation */
                   : HS_OPT_HELP;
    /* getopt_long takes unique abbreviations; the commands never did. */
    if (strncmp(typed, "--", 2) || strcmp(typed, row->name))
        return hs_bad_arg(cmd, typed, NULL, "unknown option");
    return run_parser(cmd, row, optarg, target);
}

int hs_opt_parse(const char *cmd, const hs_opt *t, size_t n, int argc, char **argv, int first,
                 void *target)
{
    struct option lo[HS_OPT_MAX + 2];
    const hs_opt *rows[HS_OPT_MAX];
    const hs_opt *positional;
    if (!long_options(t, n, lo, rows, &positional))
        return hs_bad_arg(cmd, t[0].name ? t[0].name : cmd, NULL, "too many options (HS_OPT_MAX)");
    /* getopt_long reads argv[1..]: hand it argv[first - 1..] with that element as "argv[0]".
     * With a text row that takes the other arguments they come in order as 1 ("-"); without
     * one the first of them ends the options ("+") and is an error. */
    int sub_argc = argc - (first - 1);
    char **sub = argv + (first - 1);
    int read_to = 1; /* sub[1..read_to) are read */
    opterr = 0;
    optind = 0; /* glibc: start over (a command may parse more than once) */
    for (;;) {
        int at = optind ? optind : 1;
        int idx = -1;
        int c = getopt_long(sub_argc, sub, positional ? "-:h" : "+:h", lo, &idx);
        if (c == -1)
            break;
        char buf[NAME_MAX_LEN];
        int r = c == 1 ? run_parser(cmd, positional, optarg, target)
                       : one_option(cmd, t, n, c, sub[at], typed_name(sub[at], buf),
                                    c == 0 ? rows[idx] : NULL, target);
        if (r)
            return r;
        read_to = optind;
    }
    if (optind > read_to && !strcmp(sub[read_to], "--"))
        return hs_bad_arg(cmd, "--", NULL, "unknown option");
    if (optind < sub_argc)
        return hs_bad_arg(cmd, sub[optind], NULL, "unexpected argument");
    return HS_ARG_NEXT;
}

size_t hs_opt_value_names(const hs_opt *t, size_t n, const char **out, size_t cap)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (t[i].name && t[i].arg && k < cap)
            out[k++] = t[i].name;
    return k;
}

void hs_opt_print_help(FILE *f, const hs_opt *t, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (!t[i].name) {
            if (t[i].help)
                fputs(t[i].help, f);
            continue;
        }
        if (!t[i].help)
            continue;
        int w = fprintf(f, "  %s%s%s", t[i].name, t[i].arg ? " " : "", t[i].arg ? t[i].arg : "");
        fprintf(f, "%*s", w < HELP_COLUMN ? HELP_COLUMN - w : 2, "");
        for (const char *s = t[i].help; *s;) {
            size_t len = strcspn(s, "\n");
            fprintf(f, "%.*s\n", (int)len, s);
            s += len;
            if (*s == '\n' && *++s)
                fprintf(f, "%*s", HELP_COLUMN, "");
        }
    }
}

/* ---- parsers ---- */

static int number(const hs_opt_arg *a, double *out)
{
    const hs_opt_num *num = a->opt->data;
    if (!hs_parse_f(a->value, out) || *out < num->min || *out > num->max)
        return hs_bad_arg(a->cmd, a->opt->name, a->value, num->why);
    return 0;
}

int hs_opt_u32(const hs_opt_arg *a)
{
    const hs_opt_num *num = a->opt->data;
    uint32_t u;
    if (!hs_parse_u32(a->value, &u) || u < num->min || u > num->max)
        return hs_bad_arg(a->cmd, a->opt->name, a->value, num->why);
    *(uint32_t *)a->field = u;
    return 0;
}

int hs_opt_float(const hs_opt_arg *a)
{
    double d;
    int r = number(a, &d);
    if (!r)
        *(float *)a->field = (float)d;
    return r;
}

int hs_opt_double(const hs_opt_arg *a)
{
    double d;
    int r = number(a, &d);
    if (!r)
        *(double *)a->field = d;
    return r;
}

int hs_opt_positive(const hs_opt_arg *a)
{
    const hs_opt_num *num = a->opt->data;
    double d;
    if (!hs_parse_f(a->value, &d) || !(d > 0) || d > num->max) {
        char why[64];
        snprintf(why, sizeof(why), "expected a number in (0, %g]", num->max);
        return hs_bad_arg(a->cmd, a->opt->name, a->value, num->why ? num->why : why);
    }
    *(float *)a->field = (float)d;
    return 0;
}

int hs_opt_on_off(const hs_opt_arg *a)
{
    if (!hs_parse_on_off(a->value, (bool *)a->field))
        return hs_bad_arg(a->cmd, a->opt->name, a->value, "expected on or off");
    return 0;
}

int hs_opt_enum(const hs_opt_arg *a)
{
    const hs_opt_name *names = a->opt->data;
    for (const hs_opt_name *p = names; p->name; p++)
        if (!strcmp(p->name, a->value)) {
            *(int *)a->field = p->value;
            return 0;
        }
    return hs_bad_arg(a->cmd, a->opt->name, a->value, names[0].why);
}

const char *hs_opt_enum_name(const hs_opt_name *names, int value)
{
    for (const hs_opt_name *p = names; p->name; p++)
        if (p->value == value)
            return p->name;
    return NULL;
}
