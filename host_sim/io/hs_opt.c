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

int hs_opt_parse(const char *cmd, const hs_opt *t, size_t n, int argc, char **argv, int first,
                 void *target)
{
    struct option lo[HS_OPT_MAX + 2];
    const hs_opt *row[HS_OPT_MAX];
    size_t k = 0;
    for (size_t i = 0; i < n && k < HS_OPT_MAX; i++) {
        if (!t[i].name || !strcmp(t[i].name, "--help"))
            continue;
        lo[k] = (struct option){t[i].name + 2, t[i].arg ? required_argument : no_argument, NULL, 0};
        row[k++] = &t[i];
    }
    lo[k++] = (struct option){"help", no_argument, NULL, 'h'};
    lo[k] = (struct option){0};
    /* A text row with a parser takes the arguments that are not options, in order ("-": getopt
     * returns them as 1); without one the first of them ends the options ("+") and is an
     * error. */
    const hs_opt *positional = NULL;
    for (size_t i = 0; i < n && !positional; i++)
        if (!t[i].name && t[i].parse)
            positional = &t[i];
    /* getopt_long reads argv[1..]: hand it argv[first - 1..] with that element as "argv[0]". */
    int sub_argc = argc - (first - 1);
    char **sub = argv + (first - 1);
    opterr = 0;
    optind = 0; /* glibc: start over (a command may parse more than once) */
    for (;;) {
        int at = optind ? optind : 1;
        int idx = -1;
        int c = getopt_long(sub_argc, sub, positional ? "-:h" : "+:h", lo, &idx);
        if (c == -1)
            break;
        if (c == 1) {
            int r = run_parser(cmd, positional, optarg, target);
            if (r)
                return r;
            continue;
        }
        const char *arg = sub[at];
        char buf[NAME_MAX_LEN];
        const char *name = typed_name(arg, buf);
        if (c == '?' || c == ':')
            return refused(cmd, t, n, arg, c);
        if (c == 'h') {
            if (strcmp(arg, "-h") && strcmp(arg, "--help"))
                return hs_bad_arg(cmd, name, NULL, "unknown option"); /* an abbreviation */
            return HS_OPT_HELP;
        }
        /* getopt_long takes unique abbreviations; the commands never did. */
        if (strncmp(name, "--", 2) || strcmp(name + 2, lo[idx].name))
            return hs_bad_arg(cmd, name, NULL, "unknown option");
        int r = run_parser(cmd, row[idx], optarg, target);
        if (r)
            return r;
    }
    if (optind > 1 && !strcmp(sub[optind - 1], "--"))
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
