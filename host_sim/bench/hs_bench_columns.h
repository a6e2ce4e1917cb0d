// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_columns.h
 * @brief The schema of a setting's frames CSV, out_dir/frames/NAME.csv: written by the runner
 *        (hs_bench.c), read by the report (hs_bench_report.c); neither includes the other.
 */
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/** Longest path of the bench's files. */
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
/** Columns before relmse (hs_bench_columns[10]): what every frame has, also with --timing-only. */
#define BENCH_FIRST_METRIC_COLUMN 10u
