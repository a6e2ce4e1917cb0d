// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_report.h
 * @brief `xrsc bench`'s report (hs_bench_report.c): what the runner (hs_bench.c) tells it, and
 *        the gnuplot helpers the stability suite (hs_bench_suite.c) shares. It reads the frames
 *        CSVs through their schema (hs_bench_columns.h), not through the runner.
 */
#pragma once

#include "hs_bench.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

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
