// SPDX-License-Identifier: MIT
/**
 * @file hs_poses_cmd.h
 * @brief The `xrsc poses stats` subcommand: samples, duration, angular speed and the fastest
 *        window of a pose stream (issue 9: the start of the `headturn-hololens` case).
 */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Runs `xrsc poses`; argv[0] is "poses", the options follow (see its --help). Prints to stdout,
 * errors to stderr. Returns the process exit code: 0 success, 1 the stream could not be read,
 * 2 bad arguments.
 */
int hs_poses_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
