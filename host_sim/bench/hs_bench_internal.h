// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_internal.h
 * @brief Shared between the parts of `xrsc bench` (run, report, command line).
 */
#pragma once

#include "hs_bench.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define HS_BENCH_PATH_MAX 1024

/** The fixed leading columns of a setting's CSV (then "gpu_<pass>_ms" per pass). */
#define HS_BENCH_COLUMN_COUNT 21
extern const char *const hs_bench_columns[HS_BENCH_COLUMN_COUNT];
/** Prefix of the columns that hold a method's counters (xrsc_renderer_counters), after the
 *  per-pass columns "gpu_<pass>_ms". */
#define HS_BENCH_COUNTER_PREFIX "c_"


/** out_dir/frames/NAME.csv */
void hs_bench_setting_csv_path(const char *out_dir, const char *name, char *out, size_t cap);
/** Frame k is scored: k >= warmup and (k - warmup) % score_every == 0. */
bool hs_bench_is_scored(uint32_t k, uint32_t warmup, uint32_t score_every);

/** What the report needs to know of the run (defaults resolved). */
typedef struct hs_bench_report_info {
    uint32_t frames, warmup, score_every, ref_spp, width, height;
    const char *device;
    /** relMSE between two independent references of floor_frame (both eyes' mean); NaN when
     *  --ref-floor was not given. */
    double ref_floor_relmse;
    uint32_t floor_frame;
} hs_bench_report_info;

/** Creates dir/name, a gnuplot script whose preamble draws png (w x h pixels); NULL and diag on
 *  failure. Shared by the report and the stability suite (hs_bench_suite.c). */
FILE *hs_bench_open_script(const char *dir, const char *name, const char *png, int w, int h,
                           xrsc_diag *diag);
/** Runs `gnuplot script` in dir, its output into dir/gnuplot.log; false on failure. */
bool hs_bench_run_gnuplot(const char *dir, const char *script);

/**
 * Reads every setting's CSV back from out_dir/frames, writes bench.csv, summary.csv, the plot
 * data and the gnuplot scripts, runs gnuplot (unless opt->no_plots) and prints the summary.
 */
xrsc_result hs_bench_report(const hs_bench_options *opt, const hs_bench_report_info *info,
                            FILE *summary, xrsc_diag *diag);
