// SPDX-License-Identifier: MIT
/**
 * @file hs_metrics_cmd.h
 * @brief The `xrsc metrics` subcommand: per-frame relMSE/RMSE/SSIM/CPBD of two PFM sequences,
 *        or (--stereo) one run's stereo discrepancy and temporal difference (hs_metrics_stereo.h).
 */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Runs `xrsc metrics`; argv[0] is "metrics", the options follow (see its --help). Prints to
 * stdout, errors to stderr. Returns the process exit code: 0 success, 1 a file could not be read
 * or the images do not match, 2 bad arguments.
 */
int hs_metrics_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
