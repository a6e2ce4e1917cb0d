// SPDX-License-Identifier: MIT
/**
 * @file hs_sweep.h
 * @brief `xrsc sweep`: a benchmark too large for one machine, split into work units that run
 *        anywhere (Slurm array tasks: scripts/slurm/) and merge into what `xrsc bench` writes.
 *
 * A sweep file (`key = value` lines, the `--config` syntax) names scenes, captures (pose
 * streams with their start and frames) and settings; every scene x capture is a case, and each
 * case is one `xrsc bench` run into OUT/CASE/. Its work units, numbered in file order:
 * first the references (one unit per case and scored frame), then the runs (one per case and
 * setting). `xrsc sweep run --unit I` does one unit (a part of the case's bench, hs_bench_part)
 * in the shared output folder; `xrsc sweep merge` writes each case's report from the units'
 * files, exactly what `xrsc bench` writes for the case in one process, or names the units that
 * are missing. Keys and files: bench/README.md "Sweeps".
 */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/** `xrsc sweep plan|run|merge FILE ...`; argv[0] is "sweep". Returns the exit status: 0, 1 (a
 *  unit failed, or merge found units missing), 2 (bad command line or sweep file). */
int hs_sweep_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
