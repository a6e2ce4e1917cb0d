// SPDX-License-Identifier: MIT
/**
 * @file hs_poses_cmd.c
 * @brief `xrsc poses stats [--fastest S] [--format F] [--refresh HZ] FILE`: what a pose stream
 *        holds and where it turns fastest, so a case can start at a capture's fastest window
 *        (issue 9, `headturn-hololens`) by a command rather than by hand.
 */
#include "hs_poses_cmd.h"

#include "hs_args.h"
#include "hs_opt.h"
#include "hs_pose_stats.h"
#include "hs_pose_stream.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define POSES_CMD "xrsc poses"
#define POSES_DEG_PER_RAD (180.0 / 3.14159265358979323846)
#define POSES_DEFAULT_REFRESH_HZ 90.0

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

/* What `xrsc poses stats` reads from its command line. */
typedef struct poses_args {
    const char *path;
    double window_s, refresh_hz;
    hs_pose_format format;
} poses_args;

#define P(a) ((poses_args *)(a)->target)

static int parse_file(const hs_opt_arg *a)
{
    if (P(a)->path)
        return hs_bad_arg(POSES_CMD, a->value, NULL, "one file only");
    P(a)->path = a->value;
    return 0;
}

/* --fastest, --refresh: a double field in (0, 1e6]. */
static int parse_seconds_or_hz(const hs_opt_arg *a)
{
    double x;
    if (!hs_parse_f(a->value, &x) || !(x > 0.0) || x > 1e6)
        return hs_bad_arg(POSES_CMD, a->opt->name, a->value, "expected a number > 0");
    *(double *)a->field = x;
    return 0;
}

static int parse_format_opt(const hs_opt_arg *a)
{
    if (!parse_format(a->value, &P(a)->format))
        return hs_bad_arg(POSES_CMD, a->opt->name, a->value,
                          "expected auto, xrsc, pred6dof, 360video or librnr");
    return 0;
}

/* Every option of `xrsc poses stats` once, in --help's order; the text row with a parser takes
 * FILE. */
static const hs_opt k_poses_opts[] = {
    {NULL, NULL,
     "usage: xrsc poses stats [options] FILE\n"
     "\n"
     "Prints the samples, duration and peak angular speed of a pose stream (any format\n"
     "the replay reads), and with --fastest the window of that length with the fastest\n"
     "mean angular speed (rotation summed over the steps between samples in the window,\n"
     "divided by its length): its start and end (seconds from the first sample), mean\n"
     "and peak speed (deg/s), the time of the peak, the frame of the peak counted from\n"
     "the window's start at --refresh, and the replay flags that start there.\n"
     "\n",
     parse_file, 0, NULL},
    {"--fastest", "S", "window length in seconds (> 0)", parse_seconds_or_hz,
     offsetof(poses_args, window_s), NULL},
    {"--format", "F", "auto | xrsc | pred6dof | 360video | librnr   [auto]", parse_format_opt, 0,
     NULL},
    {"--refresh", "HZ", "display rate for the peak's frame index      [90]", parse_seconds_or_hz,
     offsetof(poses_args, refresh_hz), NULL},
    {NULL, NULL, "  -h, --help          this help\n", NULL, 0, NULL},
};
#define POSES_OPT_COUNT (sizeof(k_poses_opts) / sizeof(k_poses_opts[0]))

int hs_poses_main(int argc, char **argv)
{
    bool help = argc >= 2 && (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help"));
    if (argc < 2 || help) {
        hs_opt_print_help(help ? stdout : stderr, k_poses_opts, POSES_OPT_COUNT);
        return help ? 0 : HS_EXIT_BAD_ARGS;
    }
    if (strcmp(argv[1], "stats") != 0) {
        char buf[128];
        snprintf(buf, sizeof(buf), "%.*s", (int)strcspn(argv[1], "="), argv[1]);
        return hs_bad_arg(POSES_CMD, buf, NULL, argv[1][0] == '-' ? "unknown option"
                                                                  : "unknown subcommand (expected stats)");
    }
    poses_args pa = {.refresh_hz = POSES_DEFAULT_REFRESH_HZ, .format = HS_POSE_FORMAT_AUTO};
    int r = hs_opt_parse(POSES_CMD, k_poses_opts, POSES_OPT_COUNT, argc, argv, 2, &pa);
    if (r == HS_OPT_HELP) {
        hs_opt_print_help(stdout, k_poses_opts, POSES_OPT_COUNT);
        return 0;
    }
    if (r != HS_ARG_NEXT)
        return r;
    const char *path = pa.path;
    double window_s = pa.window_s, refresh_hz = pa.refresh_hz;
    hs_pose_format format = pa.format;
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
