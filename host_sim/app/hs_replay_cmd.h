// SPDX-License-Identifier: MIT
/**
 * @file hs_replay_cmd.h
 * @brief `xrsc [replay]`: a head-pose stream replayed over a glTF scene, through OpenXR on this
 *        build's runtime or --direct, with the run's record (run.json, run.conf).
 */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Runs `xrsc [replay] [options]`: argv[0] is the program, argv[1] may be "replay" (see its
 * --help). Returns the process exit code: 0 success, 1 the run failed, 2 bad arguments,
 * 128 + signal when stopped by one.
 */
int hs_replay_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
