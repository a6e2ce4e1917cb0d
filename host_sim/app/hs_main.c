// SPDX-License-Identifier: MIT
/**
 * @file hs_main.c
 * @brief The `xrsc` program: `--version` anywhere, else the command its first word names
 *        (metrics, compare, bench, poses, sweep, scene), else `xrsc [replay]`. Each command is one file of
 *        this folder.
 */
#include "hs_bench.h"
#include "hs_compare_cmd.h"
#include "hs_metrics_cmd.h"
#include "hs_poses_cmd.h"
#include "hs_replay_cmd.h"
#include "hs_run.h"
#include "hs_scene_cmd.h"
#include "hs_sweep.h"

#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    /* xrsc version, and --version anywhere (any command) */
    for (int k = 1; k < argc; k++)
        if (!strcmp(argv[k], "--version") || (k == 1 && !strcmp(argv[k], "version"))) {
            hs_run_print_version(stdout);
            return 0;
        }
    if (argc > 1 && strcmp(argv[1], "metrics") == 0)
        return hs_metrics_main(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "compare") == 0)
        return hs_compare_main(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "bench") == 0)
        return hs_bench_main(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "poses") == 0)
        return hs_poses_main(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "sweep") == 0)
        return hs_sweep_main(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "scene") == 0)
        return hs_scene_main(argc - 1, argv + 1);
    return hs_replay_main(argc, argv);
}
