// SPDX-License-Identifier: MIT
/**
 * @file hs_args.c
 * @brief Command-line helpers of the `xrsc` commands (hs_args.h).
 */
#include "hs_args.h"

#include "u_diag.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/** Longest path hs_make_dirs accepts, terminator included. */
#define HS_MAKE_DIRS_MAX 1024

int hs_bad_arg(const char *cmd, const char *flag, const char *value, const char *why)
{
    fprintf(stderr, "%s: error: %s%s%s: %s (see %s --help)\n", cmd, flag, value ? " " : "",
            value ? value : "", why, cmd);
    return HS_EXIT_BAD_ARGS;
}

bool hs_parse_u32(const char *s, uint32_t *out)
{
    char *end;
    errno = 0;
    unsigned long v = strtoul(s, &end, 10);
    if (errno || end == s || *end || v > 0xFFFFFFFFul || s[0] == '-')
        return false;
    *out = (uint32_t)v;
    return true;
}

bool hs_parse_bytes(const char *s, uint64_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno || end == s || s[0] == '-' || v == 0)
        return false;
    int shift = 0;
    if (*end == 'K' || *end == 'k')
        shift = 10;
    else if (*end == 'M' || *end == 'm')
        shift = 20;
    else if (*end == 'G' || *end == 'g')
        shift = 30;
    if ((shift && end[1]) || (!shift && *end) || v > (UINT64_MAX >> shift))
        return false;
    *out = (uint64_t)v << shift;
    return true;
}

bool hs_parse_f(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || v != v)
        return false;
    *out = v;
    return true;
}

bool hs_parse_size(const char *s, unsigned min, unsigned max, unsigned *w, unsigned *h)
{
    unsigned x = 0, y = 0;
    char tail;
    if (sscanf(s, "%ux%u%c", &x, &y, &tail) != 2 || x < min || y < min || x > max || y > max)
        return false;
    *w = x;
    *h = y;
    return true;
}

bool hs_parse_on_off(const char *s, bool *out)
{
    if (strcmp(s, "on") && strcmp(s, "off"))
        return false;
    *out = !strcmp(s, "on");
    return true;
}

bool hs_parse_rgb(const char *s, float out[3])
{
    float r, g, b;
    char tail;
    if (sscanf(s, "%f,%f,%f%c", &r, &g, &b, &tail) != 3 || r < 0 || g < 0 || b < 0)
        return false;
    out[0] = r;
    out[1] = g;
    out[2] = b;
    return true;
}

bool hs_arg_in(const char *flag, const char *const *list, size_t count)
{
    for (size_t k = 0; k < count; k++)
        if (!strcmp(flag, list[k]))
            return true;
    return false;
}

xrsc_result hs_make_dirs(const char *path, const char *field, xrsc_diag *diag)
{
    char buf[HS_MAKE_DIRS_MAX];
    if (path[0] == '\0' || (size_t)snprintf(buf, sizeof(buf), "%s", path) >= sizeof(buf))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path, 0, field,
                          "output folder name is empty or too long");
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST)
            return u_diag_set(diag, XRSC_ERROR_IO, buf, 0, field, "cannot create folder: %s",
                              strerror(errno));
        *p = '/';
    }
    if (mkdir(buf, 0777) != 0 && errno != EEXIST)
        return u_diag_set(diag, XRSC_ERROR_IO, buf, 0, field, "cannot create folder: %s",
                          strerror(errno));
    return XRSC_OK;
}

/* ---- hs_args_prepare: --name=value and --config FILE ---- */

/** Appends one argument; false when HS_ARGS_MAX is reached. */
static bool args_push(hs_args *a, char *arg)
{
    if (a->argc >= HS_ARGS_MAX)
        return false;
    a->argv[a->argc++] = arg;
    a->argv[a->argc] = NULL;
    return true;
}

/** Copies s (terminated) into a->text; NULL when it is full. */
static char *args_store(hs_args *a, const char *s)
{
    size_t n = strlen(s);
    if (a->text_used + n + 1 > sizeof(a->text))
        return NULL;
    char *dst = a->text + a->text_used;
    memcpy(dst, s, n + 1);
    a->text_used += n + 1;
    return dst;
}

static xrsc_result config_error(xrsc_diag *diag, const char *path, int line, const char *field,
                                const char *why)
{
    return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path, line, field, "%s", why);
}

/** Reads a double-quoted value starting at *p (at the quote) into place; NULL when unclosed or
 *  followed by anything but blanks. */
static char *unquote(char *p)
{
    char *dst = p, *src = p + 1;
    for (; *src && *src != '"'; src++) {
        if (*src == '\\' && (src[1] == '"' || src[1] == '\\'))
            src++;
        *dst++ = *src;
    }
    if (*src != '"')
        return NULL;
    for (char *t = src + 1; *t; t++)
        if (*t != ' ' && *t != '\t')
            return NULL;
    *dst = '\0';
    return p;
}

static char *trim(char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r'))
        s[--n] = '\0';
    return s;
}

/** Cuts a comment: '#' at the start or after a blank, outside double quotes. */
static void cut_comment(char *s)
{
    bool quoted = false;
    for (char *p = s; *p; p++) {
        if (*p == '"')
            quoted = !quoted;
        else if (*p == '\\' && quoted && p[1])
            p++;
        else if (*p == '#' && !quoted && (p == s || p[-1] == ' ' || p[-1] == '\t')) {
            *p = '\0';
            return;
        }
    }
}

/** One config line (terminated, trimmed, not empty) as options of out. */
static xrsc_result config_line(hs_args *out, const hs_args_spec *spec, const char *path,
                               int line_no, char *line, xrsc_diag *diag)
{
    if (line[0] == '-' && line[1] == '-')
        line += 2;
    /* The key runs to '=', a blank or the end. */
    size_t k = strcspn(line, "= \t");
    char key[96];
    if (k == 0 || k + 3 > sizeof(key))
        return config_error(diag, path, line_no, "", "expected \"key = value\" or a flag");
    snprintf(key, sizeof(key), "--%.*s", (int)k, line);
    for (size_t i = 2; key[i]; i++)
        if (!(key[i] >= 'a' && key[i] <= 'z') && !(key[i] >= '0' && key[i] <= '9') &&
            key[i] != '-')
            return config_error(diag, path, line_no, key,
                                "not an option name (lower case letters, digits, '-')");
    char *rest = trim(line + k);
    bool has_eq = *rest == '=';
    if (has_eq)
        rest = trim(rest + 1);
    bool takes_value = hs_arg_in(key, spec->value_options, spec->value_count);
    if (!strcmp(key, "--config"))
        return config_error(diag, path, line_no, key, "config files do not nest");
    if (!takes_value && (*rest || has_eq))
        return config_error(diag, path, line_no, key,
                            "unknown option, or a flag that takes no value");
    if (takes_value && !*rest)
        return config_error(diag, path, line_no, key, "needs a value");
    if (!takes_value && spec->flag_options && !hs_arg_in(key, spec->flag_options, spec->flag_count))
        return config_error(diag, path, line_no, key, "unknown option");
    if (*rest == '"' && !(rest = unquote(rest)))
        return config_error(diag, path, line_no, key, "unterminated quoted value");
    char *kcopy = args_store(out, key);
    char *vcopy = takes_value ? args_store(out, rest) : NULL;
    if (!kcopy || (takes_value && !vcopy) || !args_push(out, kcopy) ||
        (takes_value && !args_push(out, vcopy)))
        return config_error(diag, path, line_no, key, "too many options");
    return XRSC_OK;
}

/** Whether text (a config file) is a run's record: its first line as HS_ARGS_RECORD_HEAD. */
static bool is_run_record(const char *text)
{
    if (strncmp(text, HS_ARGS_RECORD_HEAD, strlen(HS_ARGS_RECORD_HEAD)))
        return false;
    const char *eol = strchr(text, '\n');
    const char *mark = strstr(text, HS_ARGS_RECORD_MARK);
    return mark && (!eol || mark < eol);
}

/** The older builds' values before a run record's lines (hs_args_spec.record_defaults). */
static xrsc_result push_record_defaults(hs_args *out, const hs_args_spec *spec, const char *path,
                                        xrsc_diag *diag)
{
    for (size_t i = 0; i < spec->record_default_count; i++)
        if (!args_push(out, (char *)spec->record_defaults[i]))
            return config_error(diag, path, 0, "--config", "too many options");
    return XRSC_OK;
}

xrsc_result hs_args_config_text(hs_args *out, const hs_args_spec *spec, const char *path,
                                char *text, xrsc_diag *diag)
{
    xrsc_result res = is_run_record(text) ? push_record_defaults(out, spec, path, diag) : XRSC_OK;
    int line_no = 0;
    for (char *line = text; line && res == XRSC_OK; line_no++) {
        char *next = strchr(line, '\n');
        if (next)
            *next++ = '\0';
        cut_comment(line);
        char *t = trim(line);
        if (*t)
            res = config_line(out, spec, path, line_no + 1, t, diag);
        line = next;
    }
    return res;
}

/** Expands one --config FILE into out; 0 or the exit code after printing the error. */
static int config_read(hs_args *out, const hs_args_spec *spec, const char *path)
{
    xrsc_diag diag = {0};
    xrsc_result res = XRSC_OK;
    char *buf = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) {
        res = u_diag_set(&diag, XRSC_ERROR_INVALID_ARGUMENT, path, 0, "--config",
                         "cannot open: %s", strerror(errno));
    } else if (!(buf = malloc(HS_ARGS_CONFIG_MAX + 1))) {
        res = config_error(&diag, path, 0, "--config", "out of memory");
    } else {
        size_t n = fread(buf, 1, HS_ARGS_CONFIG_MAX + 1, f);
        buf[n <= HS_ARGS_CONFIG_MAX ? n : HS_ARGS_CONFIG_MAX] = '\0';
        res = n > HS_ARGS_CONFIG_MAX
                  ? config_error(&diag, path, 0, "--config", "larger than 64 KiB")
                  : hs_args_config_text(out, spec, path, buf, &diag);
    }
    if (f)
        fclose(f);
    free(buf);
    if (res == XRSC_OK)
        return 0;
    char msg[1400];
    fprintf(stderr, "%s: error: %s (see %s --help)\n", spec->cmd,
            xrsc_diag_format(&diag, msg, sizeof(msg)), spec->cmd);
    return HS_EXIT_BAD_ARGS;
}

int hs_args_prepare(hs_args *out, const hs_args_spec *spec, int argc, char **argv)
{
    out->argc = 0;
    out->text_used = 0;
    out->argv[0] = NULL;
    if (argc > 0)
        args_push(out, argv[0]);
    for (int i = 1; i < argc; i++) {
        char *a = argv[i];
        char *eq = a[0] == '-' && a[1] == '-' ? strchr(a, '=') : NULL;
        char name[96];
        snprintf(name, sizeof(name), "%.*s", eq ? (int)(eq - a) : (int)strlen(a), a);
        bool config = spec->config && !strcmp(name, "--config");
        bool takes_value = config || hs_arg_in(name, spec->value_options, spec->value_count);
        if (eq && !takes_value)
            return hs_bad_arg(spec->cmd, name, NULL,
                              "takes no value (a flag), or is unknown: no '=' after it");
        char *value = eq ? eq + 1 : NULL;
        if (takes_value && !eq && i + 1 < argc)
            value = argv[++i];
        if (config) {
            if (!value)
                return hs_bad_arg(spec->cmd, name, NULL, "needs a value");
            int rc = config_read(out, spec, value);
            if (rc)
                return rc;
            continue;
        }
        if (eq) {
            /* The name is a copy, the value the original's tail (argv strings stay put). */
            char *n = args_store(out, name);
            if (!n || !args_push(out, n) || !args_push(out, eq + 1))
                return hs_bad_arg(spec->cmd, name, NULL, "too many arguments");
            continue;
        }
        if (!args_push(out, a) || (value && !args_push(out, value)))
            return hs_bad_arg(spec->cmd, a, NULL, "too many arguments");
    }
    return 0;
}
