// SPDX-License-Identifier: MIT
/**
 * @file hs_compare_cmd.h
 * @brief The `xrsc compare A B` subcommand: an A/B comparison of two run folders, per frame a
 *        labelled image (A, B and their difference as a heat map with its scale) and metrics
 *        of both eyes (B against A).
 */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Runs `xrsc compare`; argv[0] is "compare", the options follow (see its --help). Prints the
 * table to stdout, warnings and errors to stderr. Returns the process exit code: 0 success,
 * 1 a file could not be read or written or the frames do not match, 2 bad arguments.
 */
int hs_compare_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
