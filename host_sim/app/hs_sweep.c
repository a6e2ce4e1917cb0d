// SPDX-License-Identifier: MIT
/**
 * @file hs_sweep.c
 * @brief `xrsc sweep plan|run|merge` (hs_sweep.h): a sweep file read into cases and settings,
 *        its work units, one unit run as a part of its case's bench, the merge.
 */
#include "hs_sweep.h"

#include "hs_args.h"
#include "hs_bench.h"
#include "hs_bench_columns.h"
#include "hs_opt.h"
#include "u_diag.h"

#include <errno.h>
#include <stddef.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SWEEP_MAX_CASES 256
#define SWEEP_MAX_FORWARD 64
#define SWEEP_MAX_SCORED 4096
#define SWEEP_NAME_MAX 64
#define SWEEP_TEXT_MAX (64 * 1024)

/* The options of `xrsc bench` a sweep file may not set: those each case's or unit's bench
 * command line sets itself (scene, poses: capture, settings: setting, out, part) and those a
 * run split into units does not take (fresh, ref-floor, timing-only). Every other option of
 * the bench's table (hs_bench_cmdline_table) is a sweep key passed on to each case's bench as
 * --KEY [VALUE] (its parser checks the values). */
static const char *const bench_not_forwarded[] = {"--scene",     "--poses",      "--settings",
                                                  "--out",       "--part",       "--fresh",
                                                  "--ref-floor", "--timing-only"};
/* The sweep's own keys: scene and capture and setting may repeat. */
static const char *const sweep_value_keys[] = {"--scene", "--capture", "--setting", "--out"};
#define COUNT_OF(a) (sizeof(a) / sizeof((a)[0]))

/* The keys a sweep file may hold: values[0..bench_values) the bench's options with a value,
 * then the sweep's own; flags the bench's flags. */
typedef struct sweep_keys {
    const char *values[HS_OPT_MAX + COUNT_OF(sweep_value_keys)];
    size_t value_count, bench_values;
    const char *flags[HS_OPT_MAX];
    size_t flag_count;
} sweep_keys;

/* One scene x capture: a bench run into OUT/name. */
typedef struct sweep_case {
    char name[SWEEP_NAME_MAX];
    const char *scene, *poses; /* into the sweep's text, into capture */
    char capture[1024];        /* the capture's value, cut at its commas */
    char start[32], frames[16];
    uint32_t scored[SWEEP_MAX_SCORED], scored_count;
} sweep_case;

typedef struct sweep {
    const char *path, *out;
    hs_args args; /* the file as "--key value" pairs */
    sweep_keys keys;
    const char *forward[2 * SWEEP_MAX_FORWARD];
    uint32_t forward_count;
    const char *scenes[SWEEP_MAX_CASES], *captures[SWEEP_MAX_CASES];
    uint32_t scene_count, capture_count;
    char settings[HS_BENCH_MAX_SETTINGS * HS_BENCH_SPEC_MAX]; /* joined by ';' */
    char setting_names[HS_BENCH_MAX_SETTINGS][HS_BENCH_NAME_MAX];
    uint32_t setting_count;
    sweep_case cases[SWEEP_MAX_CASES];
    uint32_t case_count;
    uint32_t ref_units, run_units;
} sweep;

/* One unit: the reference of a case's scored frame, or a case's setting. */
typedef struct sweep_unit {
    uint32_t index;
    bool is_ref;
    const sweep_case *c;
    uint32_t frame;   /* is_ref: the frame */
    uint32_t setting; /* else: the setting's index */
} sweep_unit;

static int sweep_error(const xrsc_diag *diag)
{
    char msg[1400];
    fprintf(stderr, "xrsc sweep: error: %s\n", xrsc_diag_format(diag, msg, sizeof(msg)));
    return HS_EXIT_BAD_ARGS;
}

/* ---- the sweep file ---- */

/* The last path component without its extension, as a case name part: letters, digits, '.',
 * '_', '+', '-' kept, anything else '_'. */
static void stem(const char *path, char *out, size_t cap)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    const char *dot = strrchr(b, '.');
    size_t n = dot && dot > b ? (size_t)(dot - b) : strlen(b);
    size_t j = 0;
    for (size_t i = 0; i < n && j + 1 < cap; i++) {
        char ch = b[i];
        bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
                  ch == '.' || ch == '_' || ch == '+' || ch == '-';
        out[j++] = ok ? ch : '_';
    }
    out[j] = '\0';
}

/* A capture "PATH[,start=S][,frames=N][,name=LABEL]" (changed in place) into c. */
static xrsc_result parse_capture(sweep *sw, char *value, const char *scene, sweep_case *c,
                                 xrsc_diag *diag)
{
    char *save = NULL, *tok = strtok_r(value, ",", &save);
    char scene_stem[24], capture_stem[24], label[SWEEP_NAME_MAX] = "";
    c->scene = scene;
    c->poses = tok ? tok : "";
    for (char *end = value + strlen(c->poses); end > value && (end[-1] == ' ' || end[-1] == '\t');)
        *--end = '\0';
    for (tok = strtok_r(NULL, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        tok += strspn(tok, " \t");
        if (!strncmp(tok, "start=", 6))
            snprintf(c->start, sizeof(c->start), "%s", tok + 6);
        else if (!strncmp(tok, "frames=", 7))
            snprintf(c->frames, sizeof(c->frames), "%s", tok + 7);
        else if (!strncmp(tok, "name=", 5))
            snprintf(label, sizeof(label), "%s", tok + 5);
        else
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, sw->path, 0, "capture",
                              "'%s': expected start=S, frames=N or name=LABEL after the path",
                              tok);
    }
    stem(scene, scene_stem, sizeof(scene_stem));
    stem(label[0] ? label : c->poses, capture_stem, sizeof(capture_stem));
    snprintf(c->name, sizeof(c->name), "%s-%s%s%s", scene_stem, capture_stem,
             c->start[0] && !label[0] ? "-s" : "", label[0] ? "" : c->start);
    return XRSC_OK;
}

/* The keys from the bench's option table (its rows in order) and the sweep's own. */
static void read_keys(sweep_keys *k)
{
    size_t n = 0;
    const hs_opt *t = hs_bench_cmdline_table(&n);
    memset(k, 0, sizeof(*k));
    for (size_t i = 0; i < n && i < HS_OPT_MAX; i++)
        if (t[i].name &&
            !hs_arg_in(t[i].name, bench_not_forwarded, COUNT_OF(bench_not_forwarded))) {
            if (t[i].arg)
                k->values[k->value_count++] = t[i].name;
            else
                k->flags[k->flag_count++] = t[i].name;
        }
    k->bench_values = k->value_count;
    for (size_t i = 0; i < COUNT_OF(sweep_value_keys); i++)
        k->values[k->value_count++] = sweep_value_keys[i];
}

/* Appends one "--key value" pair (or a flag) of the file to the sweep. */
static xrsc_result take_option(sweep *sw, int *i, xrsc_diag *diag)
{
    const char *k = sw->args.argv[*i];
    const char *v = *i + 1 < sw->args.argc ? sw->args.argv[*i + 1] : "";
    if (hs_arg_in(k, sw->keys.flags, sw->keys.flag_count)) {
        if (sw->forward_count + 1 >= 2 * SWEEP_MAX_FORWARD)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, sw->path, 0, k, "too many keys");
        sw->forward[sw->forward_count++] = k;
        return XRSC_OK;
    }
    (*i)++;
    if (!strcmp(k, "--scene") && sw->scene_count < SWEEP_MAX_CASES)
        sw->scenes[sw->scene_count++] = v;
    else if (!strcmp(k, "--capture") && sw->capture_count < SWEEP_MAX_CASES)
        sw->captures[sw->capture_count++] = v;
    else if (!strcmp(k, "--out"))
        sw->out = v;
    else if (!strcmp(k, "--setting") && sw->setting_count < HS_BENCH_MAX_SETTINGS) {
        size_t used = strlen(sw->settings);
        snprintf(sw->settings + used, sizeof(sw->settings) - used, "%s%s", used ? ";" : "", v);
        sw->setting_count++;
    } else if (hs_arg_in(k, sw->keys.values, sw->keys.bench_values) &&
               sw->forward_count + 2 < 2 * SWEEP_MAX_FORWARD) {
        sw->forward[sw->forward_count++] = k;
        sw->forward[sw->forward_count++] = v;
    } else
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, sw->path, 0, k + 2,
                          "too many (scenes, captures and settings: %u each at most)",
                          SWEEP_MAX_CASES);
    return XRSC_OK;
}

/* Reads the file into sw->args (the --config syntax; unknown keys are errors naming the line:
 * scene, capture, setting, out or an xrsc bench option, bench/README.md "Sweeps") and then
 * into scenes, captures, settings and the keys for the bench. */
static xrsc_result read_sweep(sweep *sw, const char *path, xrsc_diag *diag)
{
    read_keys(&sw->keys);
    sw->path = path;
    sw->out = "out/sweep";
    FILE *f = fopen(path, "rb");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot open: %s", strerror(errno));
    static char text[SWEEP_TEXT_MAX + 1];
    size_t n = fread(text, 1, SWEEP_TEXT_MAX + 1, f);
    fclose(f);
    if (n > SWEEP_TEXT_MAX)
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, path, 0, "", "over %d bytes",
                          SWEEP_TEXT_MAX);
    text[n] = '\0';
    const hs_args_spec spec = {.cmd = "xrsc sweep",
                               .value_options = sw->keys.values,
                               .value_count = sw->keys.value_count,
                               .config = true,
                               .flag_options = sw->keys.flags,
                               .flag_count = sw->keys.flag_count};
    sw->args.argc = 0;
    xrsc_result res = hs_args_config_text(&sw->args, &spec, path, text, diag);
    /* every key is known here: hs_args_config_text refused the others, naming their line */
    for (int i = 0; res == XRSC_OK && i < sw->args.argc; i++)
        res = take_option(sw, &i, diag);
    return res;
}

/* ---- cases and units ---- */

/* The `xrsc bench` command line of case c (settings: all of the sweep's). */
static int case_argv(const sweep *sw, const sweep_case *c, char **argv, char *out_dir,
                     size_t out_cap)
{
    int n = 0;
    argv[n++] = "bench";
    for (uint32_t i = 0; i < sw->forward_count; i++)
        argv[n++] = (char *)sw->forward[i];
    snprintf(out_dir, out_cap, "%s/%s", sw->out, c->name);
    const char *pairs[][2] = {{"--scene", c->scene},       {"--poses", c->poses},
                              {"--start", c->start},       {"--frames", c->frames},
                              {"--settings", sw->settings}, {"--out", out_dir}};
    for (size_t i = 0; i < sizeof(pairs) / sizeof(pairs[0]); i++)
        if (pairs[i][1][0]) {
            argv[n++] = (char *)pairs[i][0];
            argv[n++] = (char *)pairs[i][1];
        }
    argv[n] = NULL;
    return n;
}

/* Parses case c's bench command line: 0 with *out, else an exit status (error printed). */
static int case_bench(const sweep *sw, const sweep_case *c, char *out_dir, size_t cap,
                      hs_bench_cmdline **out)
{
    char *argv[2 * SWEEP_MAX_FORWARD + 16];
    int argc = case_argv(sw, c, argv, out_dir, cap);
    int r = hs_bench_cmdline_parse(argc, argv, out);
    if (r == 0 && !*out)
        r = HS_EXIT_BAD_ARGS; /* --help in a sweep file */
    if (r)
        fprintf(stderr, "xrsc sweep: %s: in case %s\n", sw->path, c->name);
    return r;
}

/* Every scene x capture into a case (named SCENE-CAPTURE[-sSTART], or SCENE-LABEL). */
static int make_cases(sweep *sw)
{
    xrsc_diag diag = {0};
    if (!sw->scene_count || !sw->capture_count || !sw->setting_count)
        return (u_diag_set(&diag, XRSC_ERROR_INVALID_ARGUMENT, sw->path, 0, "",
                           "a sweep needs a scene, a capture and a setting"),
                sweep_error(&diag));
    for (uint32_t s = 0; s < sw->scene_count; s++)
        for (uint32_t p = 0; p < sw->capture_count; p++) {
            if (sw->case_count == SWEEP_MAX_CASES)
                return (u_diag_set(&diag, XRSC_ERROR_INVALID_ARGUMENT, sw->path, 0, "",
                                   "more than %d cases", SWEEP_MAX_CASES),
                        sweep_error(&diag));
            sweep_case *c = &sw->cases[sw->case_count++];
            snprintf(c->capture, sizeof(c->capture), "%s", sw->captures[p]);
            if (parse_capture(sw, c->capture, sw->scenes[s], c, &diag) != XRSC_OK)
                return sweep_error(&diag);
            for (uint32_t o = 0; o + 1 < sw->case_count; o++)
                if (!strcmp(sw->cases[o].name, c->name))
                    return (u_diag_set(&diag, XRSC_ERROR_INVALID_ARGUMENT, sw->path, 0,
                                       "capture", "two cases named %s (name=)", c->name),
                            sweep_error(&diag));
        }
    return 0;
}

/* Each case's scored frames and the settings' names, from the cases' bench command lines. */
static int plan_cases(sweep *sw)
{
    for (uint32_t i = 0; i < sw->case_count; i++) {
        sweep_case *c = &sw->cases[i];
        char out_dir[HS_BENCH_PATH_MAX];
        hs_bench_cmdline *cl = NULL;
        int r = case_bench(sw, c, out_dir, sizeof(out_dir), &cl);
        if (r)
            return r;
        hs_bench_options *opt = hs_bench_cmdline_options(cl);
        xrsc_diag diag = {0};
        xrsc_result res = hs_bench_scored_frames(opt, c->scored, SWEEP_MAX_SCORED,
                                                 &c->scored_count, &diag);
        for (uint32_t j = 0; j < opt->setting_count; j++)
            snprintf(sw->setting_names[j], HS_BENCH_NAME_MAX, "%s", opt->settings[j].name);
        sw->setting_count = opt->setting_count;
        hs_bench_cmdline_free(cl);
        if (res != XRSC_OK)
            return sweep_error(&diag);
        sw->ref_units += c->scored_count;
        sw->run_units += sw->setting_count;
    }
    return 0;
}

/* Unit i: references first (case by case, frame by frame), then runs (case by setting). */
static bool unit_at(const sweep *sw, uint32_t i, sweep_unit *u)
{
    *u = (sweep_unit){.index = i};
    for (uint32_t c = 0; c < sw->case_count; c++) {
        if (i < sw->cases[c].scored_count) {
            *u = (sweep_unit){.index = u->index, .is_ref = true, .c = &sw->cases[c],
                              .frame = sw->cases[c].scored[i]};
            return true;
        }
        i -= sw->cases[c].scored_count;
    }
    if (i >= sw->case_count * sw->setting_count)
        return false;
    u->c = &sw->cases[i / sw->setting_count];
    u->setting = i % sw->setting_count;
    return true;
}

static void unit_name(const sweep *sw, const sweep_unit *u, char *out, size_t cap)
{
    if (u->is_ref)
        snprintf(out, cap, "ref %s frame=%u", u->c->name, u->frame);
    else
        snprintf(out, cap, "run %s %s", u->c->name, sw->setting_names[u->setting]);
}

/* Whether unit u's files are in place: both eyes' references, or the setting's CSV. */
static bool unit_done(const sweep *sw, const sweep_unit *u)
{
    char dir[HS_BENCH_PATH_MAX], path[HS_BENCH_PATH_MAX + 64];
    snprintf(dir, sizeof(dir), "%s/%s", sw->out, u->c->name);
    if (!u->is_ref) {
        hs_bench_setting_csv_path(dir, sw->setting_names[u->setting], path, sizeof(path));
        return access(path, R_OK) == 0;
    }
    for (int e = 0; e < 2; e++) {
        hs_bench_ref_path(dir, u->frame, e, path, sizeof(path));
        if (access(path, R_OK) != 0)
            return false;
    }
    return true;
}

/* OUT/units/NNNNN.failed: the error of a unit's last failed run. */
static void failed_path(const sweep *sw, uint32_t i, char *out, size_t cap)
{
    snprintf(out, cap, "%s/units/%05u.failed", sw->out, i);
}

/* ---- the commands ---- */

static int cmd_plan(const sweep *sw, const char *count)
{
    uint32_t total = sw->ref_units + sw->run_units;
    if (count) {
        printf("%u\n", !strcmp(count, "refs")   ? sw->ref_units
                       : !strcmp(count, "runs") ? sw->run_units
                                                : total);
        return 0;
    }
    printf("# xrsc sweep %s: %u units (%u references, %u runs): %u cases x %u settings, into "
           "%s\n",
           sw->path, total, sw->ref_units, sw->run_units, sw->case_count, sw->setting_count,
           sw->out);
    for (uint32_t i = 0; i < total; i++) {
        sweep_unit u;
        char name[256];
        unit_at(sw, i, &u);
        unit_name(sw, &u, name, sizeof(name));
        printf("%u %s%s\n", i, name, unit_done(sw, &u) ? "  (done)" : "");
    }
    return 0;
}

/* Writes (or, on success, removes) unit i's failure record. */
static void record_unit(const sweep *sw, uint32_t i, const char *error)
{
    char path[HS_BENCH_PATH_MAX + 64], dir[HS_BENCH_PATH_MAX + 16];
    failed_path(sw, i, path, sizeof(path));
    if (!error) {
        unlink(path);
        return;
    }
    xrsc_diag d = {0};
    snprintf(dir, sizeof(dir), "%s/units", sw->out);
    FILE *f = hs_make_dirs(dir, "out", &d) == XRSC_OK ? fopen(path, "w") : NULL;
    if (f) {
        fprintf(f, "%s\n", error);
        fclose(f);
    }
}

/* Runs unit i: its case's bench with --part ref:K, or --part run with the one setting. */
static int run_unit(const sweep *sw, uint32_t i)
{
    sweep_unit u;
    char name[256], out_dir[HS_BENCH_PATH_MAX], msg[1400];
    if (!unit_at(sw, i, &u)) {
        fprintf(stderr, "xrsc sweep: error: --unit %u: the sweep has %u units\n", i,
                sw->ref_units + sw->run_units);
        return HS_EXIT_BAD_ARGS;
    }
    unit_name(sw, &u, name, sizeof(name));
    hs_bench_cmdline *cl = NULL;
    int r = case_bench(sw, u.c, out_dir, sizeof(out_dir), &cl);
    if (r)
        return r;
    hs_bench_options *opt = hs_bench_cmdline_options(cl);
    opt->part = u.is_ref ? HS_BENCH_PART_REF : HS_BENCH_PART_RUN;
    opt->part_frame = u.frame;
    if (!u.is_ref) {
        opt->settings += u.setting;
        opt->setting_count = 1;
    }
    fprintf(stderr, "xrsc sweep: unit %u: %s\n", i, name);
    xrsc_diag diag = {0};
    r = hs_bench_run(opt, NULL, &diag) == XRSC_OK ? 0 : 1;
    if (r) {
        xrsc_diag_format(&diag, msg, sizeof(msg));
        fprintf(stderr, "xrsc sweep: error: unit %u (%s): %s\n", i, name, msg);
    }
    record_unit(sw, i, r ? msg : NULL);
    hs_bench_cmdline_free(cl);
    return r;
}

/* "I", "I..J" or "all" into [*first, *last]. */
static bool parse_units(const char *v, uint32_t total, uint32_t *first, uint32_t *last)
{
    if (!strcmp(v, "all")) {
        *first = 0;
        *last = total ? total - 1 : 0;
        return total > 0;
    }
    char a[32], b[32];
    const char *dots = strstr(v, "..");
    if (!dots)
        return hs_parse_u32(v, first) && (*last = *first, true);
    snprintf(a, sizeof(a), "%.*s", (int)(dots - v), v);
    snprintf(b, sizeof(b), "%s", dots + 2);
    return hs_parse_u32(a, first) && hs_parse_u32(b, last) && *first <= *last;
}

static int cmd_run(const sweep *sw, const char *units)
{
    uint32_t first, last, failed = 0;
    if (!units || !parse_units(units, sw->ref_units + sw->run_units, &first, &last))
        return hs_bad_arg("xrsc sweep run", "--unit", units, "expected I, I..J or all");
    for (uint32_t i = first; i <= last; i++) {
        int r = run_unit(sw, i);
        if (r == HS_EXIT_BAD_ARGS)
            return r;
        failed += r != 0;
    }
    return failed ? 1 : 0;
}

/* Lists the units whose files are missing (with their failure records); the count. */
static uint32_t list_missing(const sweep *sw)
{
    uint32_t missing = 0;
    for (uint32_t i = 0; i < sw->ref_units + sw->run_units; i++) {
        sweep_unit u;
        unit_at(sw, i, &u);
        if (unit_done(sw, &u))
            continue;
        char name[256], path[HS_BENCH_PATH_MAX + 64], why[1400] = "not run, or stopped";
        unit_name(sw, &u, name, sizeof(name));
        failed_path(sw, i, path, sizeof(path));
        FILE *f = fopen(path, "r");
        if (f) {
            char line[1380] = "";
            if (fgets(line, sizeof(line), f))
                line[strcspn(line, "\n")] = '\0';
            snprintf(why, sizeof(why), "failed: %s", line);
            fclose(f);
        }
        fprintf(stderr, "xrsc sweep: missing unit %u (%s): %s\n", i, name, why);
        missing++;
    }
    return missing;
}

/* The report of every case whose runs are all in place (the bench's --part report); the
 * units missing named, with the command that reruns one. */
static int cmd_merge(const sweep *sw)
{
    uint32_t missing = list_missing(sw), merged = 0;
    for (uint32_t c = 0; c < sw->case_count; c++) {
        char out_dir[HS_BENCH_PATH_MAX];
        hs_bench_cmdline *cl = NULL;
        int r = case_bench(sw, &sw->cases[c], out_dir, sizeof(out_dir), &cl);
        if (r)
            return r;
        hs_bench_options *opt = hs_bench_cmdline_options(cl);
        opt->part = HS_BENCH_PART_REPORT;
        xrsc_diag diag = {0};
        char msg[1400];
        printf("== %s (%s)\n", sw->cases[c].name, out_dir);
        if (hs_bench_run(opt, stdout, &diag) == XRSC_OK)
            merged++;
        else
            fprintf(stderr, "xrsc sweep: case %s not merged: %s\n", sw->cases[c].name,
                    xrsc_diag_format(&diag, msg, sizeof(msg)));
        hs_bench_cmdline_free(cl);
    }
    fprintf(stderr, "xrsc sweep: merged %u of %u cases; %u units missing%s\n", merged,
            sw->case_count, missing,
            missing ? " (rerun each: xrsc sweep run FILE --unit I)" : "");
    return missing || merged < sw->case_count ? 1 : 0;
}

/* What `xrsc sweep VERB` reads besides the verb: the sweep file, --count, --units. */
typedef struct sweep_args {
    const char *file, *count, *units;
} sweep_args;

static int parse_file(const hs_opt_arg *a)
{
    sweep_args *sa = a->target;
    if (sa->file)
        return hs_bad_arg(a->cmd, a->value, NULL, "unexpected argument (one sweep file)");
    sa->file = a->value;
    return 0;
}

static int parse_count(const hs_opt_arg *a)
{
    if (strcmp(a->value, "all") && strcmp(a->value, "refs") && strcmp(a->value, "runs"))
        return hs_bad_arg(a->cmd, a->opt->name, a->value, "expected all, refs or runs");
    ((sweep_args *)a->target)->count = a->value;
    return 0;
}

#define TEXT(s) {NULL, NULL, s, NULL, 0, NULL}
static const hs_opt k_sweep_opts[] = {
    TEXT("usage: xrsc sweep plan FILE [--count all|refs|runs]\n"
         "       xrsc sweep run FILE --unit I | --units I..J | --units all\n"
         "       xrsc sweep merge FILE\n"
         "\n"
         "A benchmark split into work units (Slurm array tasks: scripts/slurm/). FILE: one\n"
         "key = value per line: scene = PATH and capture = PATH[,start=S][,frames=N]\n"
         "[,name=LABEL] (each repeatable: every scene x capture is a case, benched into\n"
         "OUT/CASE), setting = METHOD[:KEY=VALUE,...] (repeatable; xrsc bench --settings),\n"
         "out = DIR [out/sweep], and the xrsc bench options listed at the end.\n"
         "  plan    prints the units: first each case's references (one per scored frame),\n"
         "          then each case's settings\n"
         "  run     does units in the shared folder (a finished unit is skipped; a run unit\n"
         "          renders the references it lacks); a failure is kept in OUT/units/\n"
         "  merge   writes each case's bench.csv, summary.csv and charts from the units'\n"
         "          files, exactly as xrsc bench would, and names the units missing\n"
         "\nOptions:\n"),
    {NULL, NULL, NULL, parse_file, 0, NULL},
    {"--count", "WHAT", "plan: print how many units (all, refs or runs) instead", parse_count, 0,
     NULL},
    {"--unit", "I", "run: unit I", NULL, offsetof(sweep_args, units), NULL},
    {"--units", "I..J", "run: units I to J, or all", NULL, offsetof(sweep_args, units), NULL},
    TEXT("  -h, --help          this help\n"
         "Details: bench/README.md \"Sweeps\", README.md \"Sweeps on a cluster\".\n"),
};
#define SWEEP_OPT_COUNT (sizeof(k_sweep_opts) / sizeof(k_sweep_opts[0]))

/* --help: the table, then the bench options a sweep file may set (from the bench's table). */
static void usage(FILE *f)
{
    hs_opt_print_help(f, k_sweep_opts, SWEEP_OPT_COUNT);
    sweep_keys k;
    read_keys(&k);
    fprintf(f, "xrsc bench options a sweep file may set for every case (a capture's start and\n"
               "frames win):");
    int col = 80;
    for (size_t i = 0; i < k.bench_values + k.flag_count; i++) {
        const char *name = (i < k.bench_values ? k.values[i] : k.flags[i - k.bench_values]) + 2;
        if (col + (int)strlen(name) + 2 > 80)
            col = fprintf(f, "\n ");
        col += fprintf(f, " %s%s", name, i + 1 < k.bench_values + k.flag_count ? "," : ".\n");
    }
}

/* The verb's command on the sweep read from sa->file. */
static int sweep_command(sweep *sw, const char *verb, const sweep_args *sa)
{
    if (sa->count && strcmp(verb, "plan"))
        return hs_bad_arg("xrsc sweep", "--count", NULL, "only with plan");
    if (sa->units && strcmp(verb, "run"))
        return hs_bad_arg("xrsc sweep", "--unit", NULL, "only with run");
    if (!strcmp(verb, "plan"))
        return cmd_plan(sw, sa->count);
    if (!strcmp(verb, "run"))
        return cmd_run(sw, sa->units);
    return cmd_merge(sw);
}

int hs_sweep_main(int argc, char **argv)
{
    const char *verb = argc > 1 ? argv[1] : "";
    if (!strcmp(verb, "-h") || !strcmp(verb, "--help")) {
        usage(stdout);
        return 0;
    }
    if (strcmp(verb, "plan") && strcmp(verb, "run") && strcmp(verb, "merge")) {
        usage(stderr);
        return hs_bad_arg("xrsc sweep", verb[0] ? verb : "(nothing)", NULL,
                          "expected plan, run or merge");
    }
    sweep_args sa = {0};
    int r = hs_opt_parse("xrsc sweep", k_sweep_opts, SWEEP_OPT_COUNT, argc, argv, 2, &sa);
    if (r == HS_OPT_HELP) {
        usage(stdout);
        return 0;
    }
    if (r != HS_ARG_NEXT)
        return r;
    if (!sa.file)
        return hs_bad_arg("xrsc sweep", verb, NULL, "needs the sweep file");
    static sweep sw; /* large: the file's text and every case's scored frames */
    memset(&sw, 0, sizeof(sw));
    xrsc_diag diag = {0};
    if (read_sweep(&sw, sa.file, &diag) != XRSC_OK)
        return sweep_error(&diag);
    r = make_cases(&sw);
    if (!r)
        r = plan_cases(&sw);
    if (!r)
        r = sweep_command(&sw, verb, &sa);
    return r;
}
