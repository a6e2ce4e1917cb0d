// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_columns.c
 * @brief The schema of a setting's frames CSV (hs_bench_columns.h): its columns, where it is,
 *        which frames are scored.
 */
#include "hs_bench_columns.h"

#include <stdio.h>

/* The fixed columns of a setting's CSV, before the per-pass columns "gpu_<pass>_ms". */
const char *const hs_bench_columns[HS_BENCH_COLUMN_COUNT] = {
    "setting",    "method",       "frame",          "display_time_ns", "warmup",
    "scored",     "wall_ms",      "gpu_ms",         "rays",            "rays_per_px",
    "relmse",     "rmse",         "ssim",           "cpbd",            "ref_cpbd",
    "temporal_msd", "temporal_valid", "stereo_msd", "stereo_valid", "ref_stereo_msd",
    "base_energy",
};

bool hs_bench_is_scored(uint32_t k, uint32_t warmup, uint32_t score_every)
{
    return k >= warmup && (k - warmup) % score_every == 0;
}

void hs_bench_setting_csv_path(const char *out_dir, const char *name, char *out, size_t cap)
{
    snprintf(out, cap, "%s/frames/%s.csv", out_dir, name);
}
