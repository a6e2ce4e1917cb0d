// SPDX-License-Identifier: MIT
/**
 * @file hs_poses_cmd.c
 * @brief `xrsc poses stats [--fastest S] [--format F] [--refresh HZ] FILE`: what a pose stream
 *        holds and where it turns fastest, so a case can start at a capture's fastest window
 *        (issue 9, `headturn-hololens`) by a command rather than by hand.
 */
#include "hs_poses_cmd.h"

#include "hs_args.h"
#include "hs_pose_stats.h"
#include "hs_pose_stream.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define POSES_CMD "xrsc poses"
#define POSES_DEG_PER_RAD (180.0 / 3.14159265358979323846)
#define POSES_DEFAULT_REFRESH_HZ 90.0

static void usage(FILE *f)
{
    fprintf(f, "usage: xrsc poses stats [options] FILE\n"
               "\n"
               "Prints the samples, duration and peak angular speed of a pose stream (any format\n"
               "the replay reads), and with --fastest the window of that length with the fastest\n"
               "mean angular speed (rotation summed over the steps between samples in the window,\n"
               "divided by its length): its start and end (seconds from the first sample), mean\n"
               "and peak speed (deg/s), the time of the peak, the frame of the peak counted from\n"
               "the window's start at --refresh, and the replay flags that start there.\n"
               "\n"
               "  --fastest S   window length in seconds (> 0)\n"
               "  --format F    auto | xrsc | pred6dof | 360video | librnr   [auto]\n"
               "  --refresh HZ  display rate for the peak's frame index      [90]\n"
               "  -h, --help    this help\n");
}

static bool parse_format(const char *v, hs_pose_format *out)
{
    static const struct {
        const char *name;
        hs_pose_format format;
    } names[] = {{"auto", HS_POSE_FORMAT_AUTO},
                 {"xrsc", HS_POSE_FORMAT_XRSC},
                 {"pred6dof", HS_POSE_FORMAT_PRED6DOF},
                 {"360video", HS_POSE_FORMAT_360VIDEO},
                 {"librnr", HS_POSE_FORMAT_LIBRNR}};
    for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
        if (!strcmp(v, names[i].name)) {
            *out = names[i].format;
            return true;
        }
    return false;
}

static void print_stats(const char *path, const hs_pose_stream *s, double window_s,
                        double refresh_hz)
{
    printf("file: %s (%s)\n", path, hs_pose_format_name(s->format));
    printf("samples: %zu\n", s->count);
    printf("duration_s: %.6f\n", (double)hs_pose_stream_duration_ns(s) * 1e-9);
    hs_pose_window all;
    /* the whole stream as one window gives the peak step speed */
    if (hs_pose_stream_fastest_window(s, hs_pose_stream_duration_ns(s) + 1, &all) == XRSC_OK)
        printf("peak_speed_deg_s: %.3f at %.6f s\n", all.peak_speed_rad_s * POSES_DEG_PER_RAD,
               (double)all.peak_ns * 1e-9);
    if (window_s <= 0.0)
        return;
    hs_pose_window w;
    if (hs_pose_stream_fastest_window(s, (int64_t)llround(window_s * 1e9), &w) != XRSC_OK)
        return;
    double start_s = (double)w.start_ns * 1e-9;
    printf("fastest_window_s: %.6f\n", window_s);
    printf("window_start_s: %.6f\n", start_s);
    printf("window_end_s: %.6f\n", (double)w.end_ns * 1e-9);
    printf("window_mean_speed_deg_s: %.3f\n", w.mean_speed_rad_s * POSES_DEG_PER_RAD);
    printf("window_peak_speed_deg_s: %.3f\n", w.peak_speed_rad_s * POSES_DEG_PER_RAD);
    printf("window_peak_t_s: %.6f\n", (double)w.peak_ns * 1e-9);
    printf("window_peak_frame: %.0f (at %.0f Hz from the window start)\n",
           floor(((double)w.peak_ns * 1e-9 - start_s) * refresh_hz), refresh_hz);
    printf("replay: --start %.6f --frames %.0f\n", start_s, ceil(window_s * refresh_hz));
}

/* The options that take a value, for --opt=value (hs_args_prepare). */
static const char *const poses_value_options[] = {"--fastest", "--refresh", "--format"};

int hs_poses_main(int argc, char **argv)
{
    hs_args args; /* --opt=value */
    int prep = hs_args_normalize(&args, POSES_CMD, poses_value_options,
                                 sizeof(poses_value_options) / sizeof(poses_value_options[0]),
                                 &argc, &argv);
    if (prep)
        return prep;
    if (argc < 2 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? HS_EXIT_BAD_ARGS : 0;
    }
    if (strcmp(argv[1], "stats") != 0)
        return hs_bad_arg(POSES_CMD, argv[1], NULL, "unknown subcommand (expected stats)");
    const char *path = NULL;
    double window_s = 0.0, refresh_hz = POSES_DEFAULT_REFRESH_HZ;
    hs_pose_format format = HS_POSE_FORMAT_AUTO;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--fastest") || !strcmp(a, "--refresh")) {
            double x;
            if (!v || !hs_parse_f(v, &x) || !(x > 0.0) || x > 1e6)
                return hs_bad_arg(POSES_CMD, a, v, "expected a number > 0");
            *(!strcmp(a, "--fastest") ? &window_s : &refresh_hz) = x;
            i++;
        } else if (!strcmp(a, "--format")) {
            if (!v || !parse_format(v, &format))
                return hs_bad_arg(POSES_CMD, a, v,
                                  "expected auto, xrsc, pred6dof, 360video or librnr");
            i++;
        } else if (a[0] == '-' && a[1]) {
            return hs_bad_arg(POSES_CMD, a, NULL, "unknown option");
        } else if (path) {
            return hs_bad_arg(POSES_CMD, a, NULL, "one file only");
        } else {
            path = a;
        }
    }
    if (!path)
        return hs_bad_arg(POSES_CMD, "FILE", NULL, "missing");
    hs_pose_stream *s = NULL;
    xrsc_diag diag;
    memset(&diag, 0, sizeof(diag));
    if (hs_pose_stream_load(path, format, &s, &diag) != XRSC_OK) {
        char msg[1400];
        fprintf(stderr, "%s: %s\n", POSES_CMD, xrsc_diag_format(&diag, msg, sizeof(msg)));
        return 1;
    }
    print_stats(path, s, window_s, refresh_hz);
    hs_pose_stream_destroy(&s);
    return 0;
}
