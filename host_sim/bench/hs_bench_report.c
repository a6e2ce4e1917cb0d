// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_report.c
 * @brief `xrsc bench` report: reads the settings' CSVs back (fresh or from an earlier run),
 *        writes bench.csv and summary.csv, prints the summary with ratios to a baseline, and
 *        writes and runs the gnuplot charts.
 */
#include "hs_args.h"
#include "hs_bench_columns.h"
#include "hs_bench_report.h"
#include "hs_pareto.h"

#include "u_diag.h"
#include "xrsc/xrsc_metrics.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define MAX_COLS 64
#define LINE_MAX_LEN 8192

/* ---- reading a setting's CSV ---- */

typedef struct table {
    uint32_t ncols, nrows, cap;
    char *names[MAX_COLS];
    double *v; /**< nrows x ncols; NaN for empty, text or "nan" cells */
} table;

static void table_free(table *t)
{
    for (uint32_t c = 0; c < t->ncols; c++)
        free(t->names[c]);
    free(t->v);
    memset(t, 0, sizeof(*t));
}

static int table_col(const table *t, const char *name)
{
    for (uint32_t c = 0; c < t->ncols; c++)
        if (!strcmp(t->names[c], name))
            return (int)c;
    return -1;
}

static double cell(const table *t, uint32_t row, const char *name)
{
    int c = table_col(t, name);
    return c < 0 ? NAN : t->v[(size_t)row * t->ncols + (uint32_t)c];
}

static double parse_cell(const char *s)
{
    if (!s[0])
        return NAN;
    char *end;
    double d = strtod(s, &end);
    return end == s || *end ? NAN : d;
}

static xrsc_result table_read(const char *path, table *t, xrsc_diag *diag)
{
    memset(t, 0, sizeof(*t));
    FILE *f = fopen(path, "r");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot open: %s", strerror(errno));
    char line[LINE_MAX_LEN];
    int lineno = 0;
    xrsc_result res = XRSC_OK;
    while (fgets(line, sizeof(line), f)) {
        lineno++;
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '#' || line[0] == '\0')
            continue;
        char *fields[MAX_COLS];
        uint32_t nf = 0;
        char *p = line;
        for (;;) {
            if (nf == MAX_COLS) {
                res = u_diag_set(diag, XRSC_ERROR_UNKNOWN_COLUMN, path, lineno, "",
                                 "more than %d columns", MAX_COLS);
                goto done;
            }
            fields[nf++] = p;
            char *comma = strchr(p, ',');
            if (!comma)
                break;
            *comma = '\0';
            p = comma + 1;
        }
        if (t->ncols == 0) {
            for (uint32_t c = 0; c < nf; c++)
                if (!(t->names[c] = strdup(fields[c]))) {
                    res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, lineno, "", "header");
                    goto done;
                }
            t->ncols = nf;
            continue;
        }
        if (nf != t->ncols) {
            res = u_diag_set(diag, XRSC_ERROR_TRUNCATED_LINE, path, lineno, "",
                             "%u fields, the header has %u", nf, t->ncols);
            goto done;
        }
        if (t->nrows == t->cap) {
            uint32_t cap = t->cap ? 2 * t->cap : 256;
            double *v = realloc(t->v, (size_t)cap * t->ncols * sizeof(double));
            if (!v) {
                res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, lineno, "", "rows");
                goto done;
            }
            t->v = v;
            t->cap = cap;
        }
        for (uint32_t c = 0; c < nf; c++)
            t->v[(size_t)t->nrows * t->ncols + c] = parse_cell(fields[c]);
        t->nrows++;
    }
done:
    fclose(f);
    if (res == XRSC_OK && t->ncols == 0)
        res = u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, path, 0, "", "no header");
    if (res != XRSC_OK)
        table_free(t);
    return res;
}

/* ---- summary ---- */

typedef struct setting_summary {
    uint32_t measured, scored;
    double wall_ms, gpu_ms, rays_per_px, relmse, rmse, ssim, cpbd, ref_cpbd, temporal, stereo;
    double ref_stereo; /**< the reference's own stereo discrepancy (scored frames) */
    double blend_ms;   /**< the stereo blend pass (gpu_blend_ms); NaN without a blend */
    double blend_pct;  /**< blend_ms as a percentage of gpu_ms (ratio of the means) */
    double base_energy; /**< seed 002 §5.1: energy change vs the baseline (scored frames) */
    double pass_ms[MAX_COLS];    /**< by union pass index */
    double counter[MAX_COLS];    /**< by union counter index: means of the "c_*" columns */
} setting_summary;

/* The methods' counters (means after the warm-up), one line per setting that has any. */
static void print_counters(FILE *out, const hs_bench_options *opt, const setting_summary *sum,
                           char *const *names, uint32_t count)
{
    if (count == 0)
        return;
    fprintf(out, "method counters (mean):\n");
    for (uint32_t i = 0; i < opt->setting_count; i++) {
        bool any = false;
        for (uint32_t p = 0; p < count; p++) {
            if (!isfinite(sum[i].counter[p]))
                continue;
            if (!any)
                fprintf(out, "%-24s", opt->settings[i].name);
            any = true;
            fprintf(out, " %s=%.6g", names[p] + strlen(HS_BENCH_COUNTER_PREFIX), sum[i].counter[p]);
        }
        if (any)
            fputc('\n', out);
    }
}

/* Mean of column `name` over rows selected by `scored_only` / not warm-up; NaN when none. */
static double mean_of(const table *t, const char *name, bool scored_only, uint32_t *out_n)
{
    int c = table_col(t, name);
    double sum = 0;
    uint32_t n = 0;
    for (uint32_t r = 0; c >= 0 && r < t->nrows; r++) {
        if (cell(t, r, "warmup") != 0.0)
            continue;
        if (scored_only && cell(t, r, "scored") != 1.0)
            continue;
        double v = t->v[(size_t)r * t->ncols + (uint32_t)c];
        if (isfinite(v)) {
            sum += v;
            n++;
        }
    }
    if (out_n)
        *out_n = n;
    return n ? sum / n : NAN;
}

static void fmt_value(FILE *f, double v)
{
    if (!isfinite(v))
        return; /* empty cell */
    if (v == floor(v) && fabs(v) < 1e15)
        fprintf(f, "%.0f", v);
    else
        fprintf(f, "%.6g", v);
}

static double ratio(double a, double b)
{
    return isfinite(a) && isfinite(b) && b != 0 ? a / b : NAN;
}

static void print_num(FILE *f, const char *fmt, int width, double v)
{
    if (isfinite(v))
        fprintf(f, fmt, v);
    else
        fprintf(f, "%*s", width, "-");
}

/* ---- gnuplot ---- */

static const char *const terminal_preamble =
    "# Generated by xrsc bench; run in this folder: gnuplot %s\n"
    "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
    "  set terminal pngcairo size %d,%d noenhanced font ',10'\n"
    "} else {\n"
    "  set terminal png size %d,%d noenhanced\n"
    "}\n"
    "set output '%s'\n"
    "set datafile separator whitespace\n"
    "set datafile missing 'nan'\n"
    "set grid\n";

FILE *hs_bench_open_script(const char *dir, const char *name, const char *png, int w, int h,
                           xrsc_diag *diag)
{
    char path[HS_BENCH_PATH_MAX + 64];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) {
        u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot create: %s", strerror(errno));
        return NULL;
    }
    fprintf(f, terminal_preamble, name, w, h, w, h, png);
    return f;
}

bool hs_bench_run_gnuplot(const char *dir, const char *script)
{
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0)
        return false;
    if (pid == 0) {
        if (chdir(dir) != 0)
            _exit(126);
        int fd = open("gnuplot.log", O_WRONLY | O_CREAT | O_APPEND, 0666);
        if (fd >= 0) {
            dup2(fd, STDOUT_FILENO);
            dup2(fd, STDERR_FILENO);
            close(fd);
        }
        execlp("gnuplot", "gnuplot", script, (char *)NULL);
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid)
        return false;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
        fprintf(stderr, "xrsc bench: gnuplot not found; the scripts are in %s\n", dir);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

static void names_string(FILE *f, const hs_bench_options *opt)
{
    fputs("names = \"", f);
    for (uint32_t i = 0; i < opt->setting_count; i++)
        fprintf(f, "%s%s", i ? " " : "", opt->settings[i].name);
    fputs("\"\n", f);
}

/* ---- the report ---- */

/* What the report's steps share: the settings' tables, their summaries, the union of their
 * pass and counter columns, and the baseline. One function per file or chart follows. */
typedef struct report {
    const hs_bench_options *opt;
    const hs_bench_report_info *info;
    uint32_t ns;
    table *tab;
    setting_summary *sum;
    char *pass_names[MAX_COLS];
    uint32_t npass;
    char *counter_names[MAX_COLS]; /* the methods' counters, "c_<name>" columns */
    uint32_t ncounter;
    uint32_t base; /* index of the baseline setting */
    bool pareto;   /* pareto.gp written: some setting has a relMSE or temporal figure */
    char plotdir[HS_BENCH_PATH_MAX + 16];
} report;

/* Reads every setting's CSV and collects the union of pass and counter columns. */
static xrsc_result read_tables(report *rp, xrsc_diag *diag)
{
    char path[HS_BENCH_PATH_MAX + 64];
    for (uint32_t i = 0; i < rp->ns; i++) {
        hs_bench_setting_csv_path(rp->opt->out_dir, rp->opt->settings[i].name, path,
                                  sizeof(path));
        xrsc_result res = table_read(path, &rp->tab[i], diag);
        if (res != XRSC_OK)
            return res;
        const table *t = &rp->tab[i];
        for (uint32_t c = HS_BENCH_COLUMN_COUNT; c < t->ncols; c++) {
            bool is_counter = !strncmp(t->names[c], HS_BENCH_COUNTER_PREFIX,
                                       strlen(HS_BENCH_COUNTER_PREFIX));
            char **names = is_counter ? rp->counter_names : rp->pass_names;
            uint32_t *n = is_counter ? &rp->ncounter : &rp->npass;
            bool seen = false;
            for (uint32_t p = 0; p < *n; p++)
                seen |= !strcmp(names[p], t->names[c]);
            if (!seen && *n < MAX_COLS)
                names[(*n)++] = t->names[c];
        }
    }
    return XRSC_OK;
}

/* Opens OUT/name for writing (its path in path). */
static FILE *open_out(const report *rp, const char *name, char *path, size_t size,
                      xrsc_diag *diag)
{
    snprintf(path, size, "%s/%s", rp->opt->out_dir, name);
    FILE *f = fopen(path, "w");
    if (!f)
        u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot create: %s", strerror(errno));
    return f;
}

static xrsc_result close_out(FILE *f, const char *path, xrsc_diag *diag)
{
    return fclose(f) == 0 ? XRSC_OK
                          : u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "writing failed");
}

/* Writes the pass, then the counter columns of row r of t (or their names: t NULL). */
static void extra_columns(FILE *f, const report *rp, const table *t, uint32_t r)
{
    for (uint32_t p = 0; p < rp->npass; p++) {
        fputc(',', f);
        t ? fmt_value(f, cell(t, r, rp->pass_names[p])) : (void)fputs(rp->pass_names[p], f);
    }
    for (uint32_t p = 0; p < rp->ncounter; p++) {
        fputc(',', f);
        t ? fmt_value(f, cell(t, r, rp->counter_names[p]))
          : (void)fputs(rp->counter_names[p], f);
    }
}

/* bench.csv: all rows, the pass and counter columns' union. */
static xrsc_result write_bench_csv(const report *rp, xrsc_diag *diag)
{
    char path[HS_BENCH_PATH_MAX + 64];
    FILE *f = open_out(rp, "bench.csv", path, sizeof(path), diag);
    if (!f)
        return XRSC_ERROR_IO;
    for (uint32_t c = 0; c < HS_BENCH_COLUMN_COUNT; c++)
        fprintf(f, "%s%s", c ? "," : "", hs_bench_columns[c]);
    extra_columns(f, rp, NULL, 0);
    fputc('\n', f);
    for (uint32_t i = 0; i < rp->ns; i++) {
        const table *t = &rp->tab[i];
        for (uint32_t r = 0; r < t->nrows; r++) {
            fprintf(f, "%s,%s", rp->opt->settings[i].name,
                    xrsc_method_name(rp->opt->settings[i].renderer.method));
            for (uint32_t c = 2; c < HS_BENCH_COLUMN_COUNT; c++) {
                fputc(',', f);
                fmt_value(f, cell(t, r, hs_bench_columns[c]));
            }
            extra_columns(f, rp, t, r);
            fputc('\n', f);
        }
    }
    return close_out(f, path, diag);
}

/* Means over the frames after the warm-up, errors over the scored frames; the baseline. */
static xrsc_result summarize(report *rp, xrsc_diag *diag)
{
    for (uint32_t i = 0; i < rp->ns; i++) {
        const table *t = &rp->tab[i];
        setting_summary *s = &rp->sum[i];
        s->wall_ms = mean_of(t, "wall_ms", false, &s->measured);
        s->gpu_ms = mean_of(t, "gpu_ms", false, NULL);
        s->rays_per_px = mean_of(t, "rays_per_px", false, NULL);
        s->cpbd = mean_of(t, "cpbd", false, NULL);
        s->temporal = mean_of(t, "temporal_msd", false, NULL);
        s->stereo = mean_of(t, "stereo_msd", false, NULL);
        s->relmse = mean_of(t, "relmse", true, &s->scored);
        s->rmse = mean_of(t, "rmse", true, NULL);
        s->ssim = mean_of(t, "ssim", true, NULL);
        s->ref_cpbd = mean_of(t, "ref_cpbd", true, NULL);
        s->ref_stereo = mean_of(t, "ref_stereo_msd", true, NULL);
        s->blend_ms = mean_of(t, "gpu_blend_ms", false, NULL);
        s->blend_pct = 100.0 * ratio(s->blend_ms, s->gpu_ms);
        s->base_energy = mean_of(t, "base_energy", true, NULL);
        for (uint32_t p = 0; p < rp->npass; p++)
            s->pass_ms[p] = mean_of(t, rp->pass_names[p], false, NULL);
        for (uint32_t p = 0; p < rp->ncounter; p++)
            s->counter[p] = mean_of(t, rp->counter_names[p], false, NULL);
    }
    const hs_bench_options *opt = rp->opt;
    rp->base = 0;
    for (uint32_t i = 0; i < rp->ns; i++) {
        const hs_bench_setting *s = &opt->settings[i];
        if (opt->baseline ? !strcmp(s->name, opt->baseline)
                          : (s->renderer.method == XRSC_METHOD_SAMPLECACHE &&
                             s->renderer.samplecache.trace == XRSC_SC_TRACE_SINGLE)) {
            rp->base = i;
            return XRSC_OK;
        }
    }
    if (opt->baseline)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--baseline",
                          "no setting is labelled '%s'", opt->baseline);
    return XRSC_OK;
}

/* summary.csv: one row per setting, ratios to the baseline. */
static xrsc_result write_summary_csv(const report *rp, xrsc_diag *diag)
{
    char path[HS_BENCH_PATH_MAX + 64];
    FILE *f = open_out(rp, "summary.csv", path, sizeof(path), diag);
    if (!f)
        return XRSC_ERROR_IO;
    const setting_summary *bs = &rp->sum[rp->base];
    fprintf(f, "setting,spec,r,measured_frames,scored_frames,wall_ms,gpu_ms,gpu_ms_ratio,"
               "wall_ms_ratio,rays_per_px,relmse,relmse_ratio,rmse,ssim,cpbd,ref_cpbd,"
               "temporal_msd,temporal_ratio,stereo_msd,ref_stereo_msd,blend_ms,blend_pct,"
               "baseline,base_energy");
    extra_columns(f, rp, NULL, 0);
    fputc('\n', f);
    for (uint32_t i = 0; i < rp->ns; i++) {
        const setting_summary *s = &rp->sum[i];
        fprintf(f, "%s,\"%s\",", rp->opt->settings[i].name, rp->opt->settings[i].spec);
        fmt_value(f, rp->opt->settings[i].r);
        fprintf(f, ",%u,%u", s->measured, s->scored);
        double v[] = {s->wall_ms,  s->gpu_ms, ratio(s->gpu_ms, bs->gpu_ms),
                      ratio(s->wall_ms, bs->wall_ms), s->rays_per_px, s->relmse,
                      ratio(s->relmse, bs->relmse), s->rmse, s->ssim, s->cpbd, s->ref_cpbd,
                      s->temporal, ratio(s->temporal, bs->temporal), s->stereo,
                      s->ref_stereo, s->blend_ms, s->blend_pct};
        for (size_t k = 0; k < sizeof(v) / sizeof(v[0]); k++) {
            fputc(',', f);
            fmt_value(f, v[k]);
        }
        fprintf(f, ",%d,", i == rp->base);
        fmt_value(f, s->base_energy);
        for (uint32_t p = 0; p < rp->npass; p++) {
            fputc(',', f);
            fmt_value(f, s->pass_ms[p]);
        }
        for (uint32_t p = 0; p < rp->ncounter; p++) {
            fputc(',', f);
            fmt_value(f, s->counter[p]);
        }
        fputc('\n', f);
    }
    return close_out(f, path, diag);
}

/* A pass column's short name: "gpu_<name>_ms" without "gpu_" and "_ms". */
static void pass_short_name(const char *column, char *out, size_t size)
{
    snprintf(out, size, "%s", column + 4);
    out[strlen(out) > 3 ? strlen(out) - 3 : 0] = '\0';
}

/* The printed summary's main table: one row per setting, ratios to the baseline. */
static void print_table(const report *rp, FILE *out)
{
    const hs_bench_report_info *info = rp->info;
    const setting_summary *bs = &rp->sum[rp->base];
    fprintf(out,
            "xrsc bench: %s; %ux%u per eye; %u frames, the first %u (warm-up) left out of "
            "the means; relMSE (eps %g), RMSE, SSIM over %u-spp references of every %u. "
            "frame; ratios (x) to %s\n",
            info->device, info->width, info->height, info->frames, info->warmup,
            XRSC_METRICS_RELMSE_EPSILON, info->ref_spp, info->score_every,
            rp->opt->settings[rp->base].name);
    fprintf(out, "%-24s %8s %6s %8s %6s %7s %9s %6s %6s %6s %6s %10s %6s %10s %10s %8s %6s\n",
            "setting", "GPU ms", "x", "wall ms", "x", "rays/px", "relMSE", "x", "SSIM", "CPBD",
            "ref", "temporal", "x", "stereo", "ref stereo", "blend ms", "blend%");
    for (uint32_t i = 0; i < rp->ns; i++) {
        const setting_summary *s = &rp->sum[i];
        fprintf(out, "%-24s ", rp->opt->settings[i].name);
        print_num(out, "%8.2f ", 8, s->gpu_ms);
        print_num(out, "%6.2f ", 6, ratio(s->gpu_ms, bs->gpu_ms));
        print_num(out, "%8.2f ", 8, s->wall_ms);
        print_num(out, "%6.2f ", 6, ratio(s->wall_ms, bs->wall_ms));
        print_num(out, "%7.3f ", 7, s->rays_per_px);
        print_num(out, "%9.4g ", 9, s->relmse);
        print_num(out, "%6.2f ", 6, ratio(s->relmse, bs->relmse));
        print_num(out, "%6.4f ", 6, s->ssim);
        print_num(out, "%6.3f ", 6, s->cpbd);
        print_num(out, "%6.3f ", 6, s->ref_cpbd);
        print_num(out, "%10.4g ", 10, s->temporal);
        print_num(out, "%6.2f ", 6, ratio(s->temporal, bs->temporal));
        print_num(out, "%10.4g ", 10, s->stereo);
        print_num(out, "%10.4g ", 10, s->ref_stereo);
        print_num(out, "%8.3f ", 8, s->blend_ms);
        print_num(out, "%6.2f", 6, s->blend_pct);
        fputc('\n', out);
    }
}

/* Whether a setting other than the baseline has a base_energy (the --baseline ran first). */
static bool any_base_energy(const report *rp)
{
    for (uint32_t i = 0; i < rp->ns; i++)
        if (i != rp->base && isfinite(rp->sum[i].base_energy))
            return true;
    return false;
}

/* The printed summary: the table, the reference floor, the passes and the counters. */
static void print_summary(const report *rp, FILE *out)
{
    const hs_bench_report_info *info = rp->info;
    print_table(rp, out);
    fprintf(out, "CPBD, stereo: means over the measured frames; ref, ref stereo: the references "
                 "(scored frames); blend%%: the blend pass's share of the GPU time\n");
    if (isfinite(info->ref_floor_relmse))
        fprintf(out,
                "reference floor relMSE \u2248 %.4g (two %u-spp references of frame %u, "
                "independent seeds; a setting's relMSE holds about half of it as the "
                "reference's own noise)\n",
                info->ref_floor_relmse, info->ref_spp, info->floor_frame);
    fprintf(out, "per pass, GPU ms (mean):\n%-24s", "setting");
    for (uint32_t p = 0; p < rp->npass; p++) {
        char nm[64];
        pass_short_name(rp->pass_names[p], nm, sizeof(nm));
        fprintf(out, " %11s", nm);
    }
    fputc('\n', out);
    for (uint32_t i = 0; i < rp->ns; i++) {
        fprintf(out, "%-24s", rp->opt->settings[i].name);
        for (uint32_t p = 0; p < rp->npass; p++) {
            fputc(' ', out);
            print_num(out, "%11.3f", 11, rp->sum[i].pass_ms[p]);
        }
        fputc('\n', out);
    }
    print_counters(out, rp->opt, rp->sum, rp->counter_names, rp->ncounter);
    if (any_base_energy(rp)) {
        fprintf(out, "energy change vs %s (seed 002 section 5.1: sum |I - I_base| / sum I_base, "
                     "scored frames):", rp->opt->settings[rp->base].name);
        for (uint32_t i = 0; i < rp->ns; i++)
            if (isfinite(rp->sum[i].base_energy))
                fprintf(out, " %s=%.4g", rp->opt->settings[i].name, rp->sum[i].base_energy);
        fputc('\n', out);
    }
    fprintf(out, "files: %s/{bench.csv,summary.csv,*.png}\n", rp->opt->out_dir);
}

/* One setting's lines of the plot data files. */
static void plot_data_setting(const report *rp, uint32_t i, FILE *d, FILE *fr, FILE *sc,
                              FILE *pa)
{
    const setting_summary *s = &rp->sum[i];
    const table *t = &rp->tab[i];
    const char *name = rp->opt->settings[i].name;
    fprintf(d, "%u %s %g %g %g %g %g %g %g %g %g %g\n", i + 1, name, s->gpu_ms, s->wall_ms,
            s->relmse, s->temporal, s->stereo, s->cpbd, s->ref_cpbd, s->rays_per_px,
            s->ref_stereo, s->base_energy);
    fprintf(pa, "%s", name);
    for (uint32_t p = 0; p < rp->npass; p++)
        fprintf(pa, " %g", isfinite(s->pass_ms[p]) ? s->pass_ms[p] : 0.0);
    fputc('\n', pa);
    fprintf(fr, "%s# %s: frame gpu_ms wall_ms temporal_msd stereo_msd cpbd\n", i ? "\n\n" : "",
            name);
    fprintf(sc, "%s# %s: frame relmse ssim rmse\n", i ? "\n\n" : "", name);
    for (uint32_t r = 0; r < t->nrows; r++) {
        fprintf(fr, "%g %g %g %g %g %g\n", cell(t, r, "frame"), cell(t, r, "gpu_ms"),
                cell(t, r, "wall_ms"), cell(t, r, "temporal_msd"), cell(t, r, "stereo_msd"),
                cell(t, r, "cpbd"));
        if (cell(t, r, "scored") == 1.0)
            fprintf(sc, "%g %g %g %g\n", cell(t, r, "frame"), cell(t, r, "relmse"),
                    cell(t, r, "ssim"), cell(t, r, "rmse"));
    }
}

/* OUT/plot/{summary,frames,scored,passes}.dat: what the charts draw. */
static xrsc_result write_plot_data(const report *rp, xrsc_diag *diag)
{
    static const char *const names[4] = {"summary.dat", "frames.dat", "scored.dat",
                                         "passes.dat"};
    FILE *fs[4] = {NULL};
    char path[HS_BENCH_PATH_MAX + 64];
    bool opened = true;
    for (int k = 0; k < 4; k++) {
        snprintf(path, sizeof(path), "%s/%s", rp->plotdir, names[k]);
        opened &= (fs[k] = fopen(path, "w")) != NULL;
    }
    xrsc_result res = XRSC_OK;
    if (!opened) {
        res = u_diag_set(diag, XRSC_ERROR_IO, rp->plotdir, 0, "", "cannot write plot data");
    } else {
        fprintf(fs[0], "# idx name gpu_ms wall_ms relmse temporal_msd stereo_msd cpbd ref_cpbd "
                       "rays_per_px ref_stereo_msd base_energy\n");
        fprintf(fs[3], "setting");
        for (uint32_t p = 0; p < rp->npass; p++) {
            char nm[64];
            pass_short_name(rp->pass_names[p], nm, sizeof(nm));
            fprintf(fs[3], " %s", nm);
        }
        fputc('\n', fs[3]);
        for (uint32_t i = 0; i < rp->ns; i++)
            plot_data_setting(rp, i, fs[0], fs[1], fs[2], fs[3]);
    }
    bool bad = false;
    for (int k = 0; k < 4; k++)
        if (fs[k])
            bad |= fclose(fs[k]) != 0;
    if (res == XRSC_OK && bad)
        res = u_diag_set(diag, XRSC_ERROR_IO, rp->plotdir, 0, "", "writing plot data failed");
    return res;
}

/* Writes group s's block of r.dat: its members' points sorted by r (selection sort). */
static void r_block(const report *rp, const char *group, FILE *d)
{
    const hs_bench_options *opt = rp->opt;
    double last = -INFINITY;
    for (;;) {
        int pick = -1;
        for (uint32_t j = 0; j < rp->ns; j++) {
            const hs_bench_setting *q = &opt->settings[j];
            if (isfinite(q->r) && !strcmp(q->group, group) && q->r > last &&
                (pick < 0 || q->r < opt->settings[pick].r))
                pick = (int)j;
        }
        if (pick < 0)
            return;
        last = opt->settings[pick].r;
        const setting_summary *ps = &rp->sum[pick];
        fprintf(d, "%g %g %g %g %g\n", last, ps->stereo, ps->cpbd, ps->ref_cpbd, ps->ref_stereo);
    }
}

/* OUT/plot/r.dat: one block per group (settings equal but for r), sorted by r; the groups'
 * names, space separated, in groups. Returns the number of blocks, or -1 on error. */
static int write_r_data(const report *rp, char *groups, size_t groups_size, xrsc_diag *diag)
{
    const hs_bench_options *opt = rp->opt;
    char path[HS_BENCH_PATH_MAX + 64];
    snprintf(path, sizeof(path), "%s/r.dat", rp->plotdir);
    FILE *d = fopen(path, "w");
    if (!d) {
        u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot create");
        return -1;
    }
    int blocks = 0;
    groups[0] = '\0';
    for (uint32_t i = 0; i < rp->ns; i++) {
        const hs_bench_setting *s = &opt->settings[i];
        bool first = isfinite(s->r);
        for (uint32_t j = 0; j < i && first; j++)
            if (isfinite(opt->settings[j].r) && !strcmp(opt->settings[j].group, s->group))
                first = false;
        if (!first)
            continue;
        fprintf(d, "%s# %s: r stereo_msd cpbd ref_cpbd ref_stereo_msd\n", blocks ? "\n\n" : "",
                s->group);
        snprintf(groups + strlen(groups), groups_size - strlen(groups), "%s%s",
                 blocks ? " " : "", s->group);
        r_block(rp, s->group, d);
        blocks++;
    }
    if (fclose(d) != 0) {
        u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "writing failed");
        return -1;
    }
    return blocks;
}

/* Chart stereo_r: stereo discrepancy and CPBD against R, one line per group; settings without
 * R (no blend, pfj23) as horizontal lines, like the reference. */
static xrsc_result chart_stereo_r(const report *rp, xrsc_diag *diag)
{
    char groups[4096];
    int blocks = write_r_data(rp, groups, sizeof(groups), diag);
    if (blocks < 0)
        return diag ? diag->code : XRSC_ERROR_IO;
    FILE *g =
        hs_bench_open_script(rp->opt->out_dir, "stereo_r.gp", "stereo_r.png", 1100, 520, diag);
    if (!g)
        return diag ? diag->code : XRSC_ERROR_IO;
    fprintf(g, "groups = \"%s\"\n", groups);
    static const char *const flat_colour[] = {"dark-orange", "dark-green", "red",
                                              "dark-cyan", "brown", "dark-magenta"};
    char flat_stereo[2048] = "", flat_cpbd[2048] = "";
    uint32_t nflat = 0;
    for (uint32_t i = 0; i < rp->ns; i++) {
        if (isfinite(rp->opt->settings[i].r))
            continue;
        const char *colour = flat_colour[nflat++ % 6];
        const setting_summary *s = &rp->sum[i];
        if (isfinite(s->stereo))
            snprintf(flat_stereo + strlen(flat_stereo), sizeof(flat_stereo) - strlen(flat_stereo),
                     ", %.9g with lines dt 3 lw 2 lc '%s' title '%s'", s->stereo, colour,
                     rp->opt->settings[i].name);
        if (isfinite(s->cpbd))
            snprintf(flat_cpbd + strlen(flat_cpbd), sizeof(flat_cpbd) - strlen(flat_cpbd),
                     ", %.9g with lines dt 3 lw 2 lc '%s' title '%s'", s->cpbd, colour,
                     rp->opt->settings[i].name);
    }
    unsigned last = blocks ? (unsigned)blocks - 1 : 0;
    fprintf(g, "set multiplot layout 1,2 title 'stereo discrepancy and sharpness vs R'\n"
               "set xlabel 'R'\nset xrange [-0.05:1.05]\nset key below font ',8'\n"
               "set ylabel 'stereo discrepancy (MSE, right vs left reprojected)'\n"
               "plot for [i=0:%u] 'plot/r.dat' index i using 1:2 with linespoints pt 7 "
               "title word(groups, i+1), "
               "'plot/r.dat' index 0 using 1:5 with lines dt 2 lc 'black' title 'reference'"
               "%s\n",
            last, flat_stereo);
    fprintf(g, "set ylabel 'CPBD (higher = sharper)'\n"
               "plot for [i=0:%u] 'plot/r.dat' index i using 1:3 with linespoints pt 7 "
               "title word(groups, i+1), "
               "'plot/r.dat' index 0 using 1:4 with lines dt 2 lc 'black' title 'reference'"
               "%s\n"
               "unset multiplot\n",
            last, flat_cpbd);
    fclose(g);
    return XRSC_OK;
}

/* The charts' common title: device, size, frames, reference (no single quotes: gnuplot). */
static void chart_title(const report *rp, char *title, size_t size)
{
    const hs_bench_report_info *info = rp->info;
    snprintf(title, size, "%s, %ux%u per eye, %u frames (%u warm-up), ref %u spp", info->device,
             info->width, info->height, info->frames, info->warmup, info->ref_spp);
    for (char *p = title; *p; p++)
        if (*p == '\'')
            *p = '"';
}

/* Chart error_vs_time: relMSE and temporal difference against GPU time, one point per
 * setting (a legend rather than labels: settings often share a point). */
static xrsc_result chart_error_vs_time(const report *rp, xrsc_diag *diag)
{
    char title[512];
    chart_title(rp, title, sizeof(title));
    FILE *g = hs_bench_open_script(rp->opt->out_dir, "error_vs_time.gp", "error_vs_time.png",
                                   1300, 520, diag);
    if (!g)
        return diag ? diag->code : XRSC_ERROR_IO;
    names_string(g, rp->opt);
    fprintf(g,
            "N = words(names)\n"
            "set multiplot layout 1,2 title '%s'\n"
            "set logscale y\nset xrange [0:*]\nset offsets 0, graph 0.1, graph 0.1, graph 0.1\n"
            "set key bottom right font ',8' opaque\n"
            "set xlabel 'GPU time per stereo frame, ms (mean)'\n"
            "set ylabel 'relMSE vs reference (mean, eps 0.01)'\n"
            "plot for [i=1:N] 'plot/summary.dat' every ::(i-1)::(i-1) using 3:5 with points "
            "pt (4+i%%8) ps 1.8 lw 2 lc i title word(names, i)\n"
            "set ylabel 'temporal difference (mean squared, reprojected)'\n"
            "plot for [i=1:N] 'plot/summary.dat' every ::(i-1)::(i-1) using 3:6 with points "
            "pt (4+i%%8) ps 1.8 lw 2 lc i title word(names, i)\n"
            "unset multiplot\n",
            title);
    fclose(g);
    return XRSC_OK;
}

/* Chart sequence: relMSE, GPU time and temporal difference per frame. */
static xrsc_result chart_sequence(const report *rp, xrsc_diag *diag)
{
    const hs_bench_report_info *info = rp->info;
    char title[512];
    chart_title(rp, title, sizeof(title));
    /* The frame-time axis ends above the measured frames: warm-up frames (pipeline creation,
     * shader compilation on CPU devices) can be orders of magnitude slower. */
    double gpu_max = 0;
    for (uint32_t i = 0; i < rp->ns; i++)
        for (uint32_t r = 0; r < rp->tab[i].nrows; r++) {
            double v = cell(&rp->tab[i], r, "gpu_ms");
            if (cell(&rp->tab[i], r, "warmup") == 0.0 && isfinite(v) && v > gpu_max)
                gpu_max = v;
        }
    FILE *g =
        hs_bench_open_script(rp->opt->out_dir, "sequence.gp", "sequence.png", 1100, 1000, diag);
    if (!g)
        return diag ? diag->code : XRSC_ERROR_IO;
    names_string(g, rp->opt);
    fprintf(g,
            "N = words(names)\n"
            "set multiplot layout 3,1 title '%s'\n"
            "set key outside right font ',8'\nset xlabel 'frame'\nset xrange [0:%u]\n"
            "set arrow 1 from %u, graph 0 to %u, graph 1 nohead dt 2 lc 'gray'\n"
            "set logscale y\nset ylabel 'relMSE (scored frames)'\n"
            "plot for [i=1:N] 'plot/scored.dat' index (i-1) using 1:2 with linespoints pt 7 ps 0.6 "
            "title word(names, i)\n"
            "unset logscale y\nset ylabel 'GPU ms per stereo frame'\nset yrange [0:%g]\n"
            "plot for [i=1:N] 'plot/frames.dat' index (i-1) using 1:2 with lines title word(names, i)\n"
            "set autoscale y\nset logscale y\nset ylabel 'temporal difference (reprojected)'\n"
            "plot for [i=1:N] 'plot/frames.dat' index (i-1) using 1:4 with lines title word(names, i)\n"
            "unset multiplot\n",
            title, info->frames ? info->frames - 1 : 0, info->warmup, info->warmup,
            gpu_max > 0 ? 1.15 * gpu_max : 1.0);
    fclose(g);
    return XRSC_OK;
}

/* Chart base_energy (with --baseline first): seed 002 §5.1's energy change against the
 * baseline over rays per pixel, one point per setting (e.g. a cache's error against its
 * savings, the baseline at 0). */
static xrsc_result chart_base_energy(const report *rp, xrsc_diag *diag)
{
    char title[512];
    chart_title(rp, title, sizeof(title));
    FILE *g = hs_bench_open_script(rp->opt->out_dir, "base_energy.gp", "base_energy.png", 800,
                                   560, diag);
    if (!g)
        return diag ? diag->code : XRSC_ERROR_IO;
    names_string(g, rp->opt);
    fprintf(g,
            "N = words(names)\nset title '%s' font ',9'\n"
            "set offsets graph 0.1, graph 0.1, graph 0.1, graph 0.1\n"
            "set key outside right font ',8'\nset xlabel 'rays per pixel (mean)'\n"
            "set ylabel 'energy change vs %s (seed 002 sec. 5.1)'\n"
            "plot for [i=1:N] 'plot/summary.dat' every ::(i-1)::(i-1) using 10:12 with points "
            "pt (4+i%%8) ps 1.8 lw 2 lc i title word(names, i)\n",
            title, rp->opt->settings[rp->base].name);
    fclose(g);
    return XRSC_OK;
}

/* Chart passes: the mean GPU time per pass, stacked per setting. */
static xrsc_result chart_passes(const report *rp, xrsc_diag *diag)
{
    FILE *g = hs_bench_open_script(rp->opt->out_dir, "passes.gp", "passes.png", 1100, 550, diag);
    if (!g)
        return diag ? diag->code : XRSC_ERROR_IO;
    fprintf(g,
            "set title 'GPU time per pass (mean per stereo frame, Vulkan timestamps)'\n"
            "set style data histograms\nset style histogram rowstacked\n"
            "set style fill solid 0.85 border -1\nset boxwidth 0.7\n"
            "set xtics rotate by -30 font ',8'\nset key outside right\nset yrange [0:*]\n"
            "set ylabel 'GPU ms'\n"
            "plot for [c=2:%u] 'plot/passes.dat' using c:xtic(1) title columnheader(c)\n",
            rp->npass + 1);
    fclose(g);
    return XRSC_OK;
}

/* The name of the setting that the pareto chart draws as the product's default. */
#define PARETO_DEFAULT_NAME "default"

/* One block of plot/pareto_front.dat: the front's settings sorted by GPU time (a staircase),
 * "gpu_ms error name" per line. */
static void pareto_block(const report *rp, const double *err, const bool *front, FILE *d)
{
    double last = -INFINITY;
    int last_i = -1;
    for (;;) {
        int pick = -1;
        for (uint32_t j = 0; j < rp->ns; j++) {
            double c = rp->sum[j].gpu_ms;
            bool after = c > last || (c == last && (int)j > last_i);
            if (front[j] && after &&
                (pick < 0 || c < rp->sum[pick].gpu_ms ||
                 (c == rp->sum[pick].gpu_ms && (int)j < pick)))
                pick = (int)j;
        }
        if (pick < 0)
            return;
        last = rp->sum[pick].gpu_ms;
        last_i = pick;
        fprintf(d, "%g %g %s\n", last, err[pick], rp->opt->settings[pick].name);
    }
}

/* OUT/pareto.csv (every setting, whether it is on each front) and OUT/plot/pareto*.dat. */
static xrsc_result write_pareto_data(report *rp, const bool *front_r, const bool *front_t,
                                     const double *relmse, const double *temporal, xrsc_diag *diag)
{
    char path[HS_BENCH_PATH_MAX + 64], dpath[HS_BENCH_PATH_MAX + 64];
    FILE *f = open_out(rp, "pareto.csv", path, sizeof(path), diag);
    if (!f)
        return XRSC_ERROR_IO;
    snprintf(dpath, sizeof(dpath), "%s/pareto_front.dat", rp->plotdir);
    FILE *d = fopen(dpath, "w");
    if (!d) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_IO, dpath, 0, "", "cannot create");
    }
    fprintf(f, "setting,spec,gpu_ms,relmse,temporal_msd,front_relmse,front_temporal,default\n");
    for (uint32_t i = 0; i < rp->ns; i++) {
        const hs_bench_setting *s = &rp->opt->settings[i];
        fprintf(f, "%s,\"%s\",", s->name, s->spec);
        fmt_value(f, rp->sum[i].gpu_ms);
        fputc(',', f);
        fmt_value(f, relmse[i]);
        fputc(',', f);
        fmt_value(f, temporal[i]);
        fprintf(f, ",%d,%d,%d\n", front_r[i], front_t[i], !strcmp(s->name, PARETO_DEFAULT_NAME));
    }
    fprintf(d, "# relMSE front: gpu_ms relmse name\n");
    pareto_block(rp, relmse, front_r, d);
    fprintf(d, "\n\n# temporal front: gpu_ms temporal_msd name\n");
    pareto_block(rp, temporal, front_t, d);
    bool bad = fclose(d) != 0;
    xrsc_result res = close_out(f, path, diag);
    if (res == XRSC_OK && bad)
        res = u_diag_set(diag, XRSC_ERROR_IO, dpath, 0, "", "writing failed");
    return res;
}

/* The gnuplot commands of one pareto panel: every setting as an open circle, the front as a
 * staircase of filled points, the default as a large cross; every point named. */
static void pareto_panel(FILE *g, const char *ylabel, int ycol, int block, int defidx)
{
    fprintf(g,
            "set ylabel '%s'\n"
            "plot 'plot/summary.dat' using 3:%d with points pt 6 ps 1.2 lc 'gray50' "
            "title 'setting', "
            "'' using 3:%d:2 with labels left offset 0.6,-0.5 font ',6' tc 'gray40' notitle, "
            "'plot/pareto_front.dat' index %d using 1:2 with steps lw 2 lc 'dark-red' "
            "title 'Pareto front', "
            "'' index %d using 1:2 with points pt 7 ps 1.3 lc 'dark-red' notitle, "
            "'' index %d using 1:2:3 with labels left offset 0.8,0.6 font ',7' notitle",
            ylabel, ycol, ycol, block, block, block);
    if (defidx >= 0)
        fprintf(g,
                ", 'plot/summary.dat' every ::%d::%d using 3:%d with points pt 3 ps 3.5 lw 2 "
                "lc 'blue' title '%s'",
                defidx, defidx, ycol, PARETO_DEFAULT_NAME);
    fputc('\n', g);
}

/* Chart pareto (issue 19 item 4): relMSE and temporal difference against GPU time with the
 * non-dominated settings (hs_pareto_front: no other setting is as fast and as good, and better
 * in one) joined and named, and the setting named "default" (the product) marked. */
static xrsc_result chart_pareto(report *rp, xrsc_diag *diag)
{
    double *cost = calloc(rp->ns, 4 * sizeof(double));
    bool *front = calloc(rp->ns, 2 * sizeof(bool));
    if (!cost || !front) {
        free(cost);
        free(front);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "pareto");
    }
    double *relmse = cost + rp->ns, *temporal = cost + 2 * rp->ns;
    int defidx = -1;
    for (uint32_t i = 0; i < rp->ns; i++) {
        cost[i] = rp->sum[i].gpu_ms;
        relmse[i] = rp->sum[i].relmse;
        temporal[i] = rp->sum[i].temporal;
        if (!strcmp(rp->opt->settings[i].name, PARETO_DEFAULT_NAME))
            defidx = (int)i;
    }
    uint32_t nr = hs_pareto_front(cost, relmse, rp->ns, front);
    uint32_t nt = hs_pareto_front(cost, temporal, rp->ns, front + rp->ns);
    xrsc_result res = write_pareto_data(rp, front, front + rp->ns, relmse, temporal, diag);
    rp->pareto = res == XRSC_OK && nr + nt > 0;
    char title[512];
    chart_title(rp, title, sizeof(title));
    FILE *g = !rp->pareto ? NULL
                          : hs_bench_open_script(rp->opt->out_dir, "pareto.gp", "pareto.png", 1300,
                                                 560, diag);
    if (rp->pareto && !g)
        res = diag ? diag->code : XRSC_ERROR_IO;
    if (g) {
        fprintf(g,
                "set multiplot layout 1,2 title '%s'\n"
                "set logscale y\nset xrange [0:*]\n"
                "set offsets 0, graph 0.25, graph 0.1, graph 0.1\n"
                "set key top right font ',8' opaque\n"
                "set xlabel 'GPU time per stereo frame, ms (mean)'\n",
                title);
        pareto_panel(g, "relMSE vs reference (mean, eps 0.01)", 5, 0, defidx);
        pareto_panel(g, "temporal difference (mean squared, reprojected)", 6, 1, defidx);
        fprintf(g, "unset multiplot\n");
        fclose(g);
    }
    free(cost);
    free(front);
    return res;
}

/* Whether any setting has an R (the stereo_r chart). */
static bool any_r(const report *rp)
{
    for (uint32_t i = 0; i < rp->ns; i++)
        if (isfinite(rp->opt->settings[i].r))
            return true;
    return false;
}

/* The charts' data and scripts, and the scripts run through gnuplot unless --no-plots. */
static xrsc_result write_charts(report *rp, xrsc_diag *diag)
{
    const hs_bench_options *opt = rp->opt;
    snprintf(rp->plotdir, sizeof(rp->plotdir), "%s/plot", opt->out_dir);
    bool with_r = any_r(rp), with_base = any_base_energy(rp);
    xrsc_result res;
    if ((res = hs_make_dirs(rp->plotdir, "--out", diag)) != XRSC_OK ||
        (res = write_plot_data(rp, diag)) != XRSC_OK ||
        (with_r && (res = chart_stereo_r(rp, diag)) != XRSC_OK) ||
        (res = chart_error_vs_time(rp, diag)) != XRSC_OK ||
        (res = chart_sequence(rp, diag)) != XRSC_OK || (res = chart_passes(rp, diag)) != XRSC_OK ||
        (res = chart_pareto(rp, diag)) != XRSC_OK ||
        (with_base && (res = chart_base_energy(rp, diag)) != XRSC_OK))
        return res;
    if (opt->no_plots)
        return XRSC_OK;
    const char *scripts[] = {"error_vs_time.gp", "sequence.gp", "passes.gp", "pareto.gp",
                             "stereo_r.gp"};
    for (size_t k = 0; k < (with_r ? 5u : 4u); k++)
        if ((k != 3 || rp->pareto) && !hs_bench_run_gnuplot(opt->out_dir, scripts[k]))
            fprintf(stderr, "xrsc bench: warning: gnuplot %s failed (see %s/gnuplot.log)\n",
                    scripts[k], opt->out_dir);
    if (with_base && !hs_bench_run_gnuplot(opt->out_dir, "base_energy.gp"))
        fprintf(stderr, "xrsc bench: warning: gnuplot base_energy.gp failed (see %s/gnuplot.log)\n",
                opt->out_dir);
    return XRSC_OK;
}

xrsc_result hs_bench_report(const hs_bench_options *opt, const hs_bench_report_info *info,
                            FILE *out, xrsc_diag *diag)
{
    report rp = {.opt = opt, .info = info, .ns = opt->setting_count};
    rp.tab = calloc(rp.ns, sizeof(table));
    rp.sum = calloc(rp.ns, sizeof(setting_summary));
    xrsc_result res = XRSC_OK;
    if (!rp.tab || !rp.sum)
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "report");
    if (res == XRSC_OK && (res = read_tables(&rp, diag)) == XRSC_OK &&
        (res = write_bench_csv(&rp, diag)) == XRSC_OK && (res = summarize(&rp, diag)) == XRSC_OK &&
        (res = write_summary_csv(&rp, diag)) == XRSC_OK) {
        if (out)
            print_summary(&rp, out);
        res = write_charts(&rp, diag);
    }
    for (uint32_t i = 0; rp.tab && i < rp.ns; i++)
        table_free(&rp.tab[i]);
    free(rp.tab);
    free(rp.sum);
    return res;
}
