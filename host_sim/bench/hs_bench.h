// SPDX-License-Identifier: MIT
/**
 * @file hs_bench.h
 * @brief `xrsc bench`: the speed-vs-accuracy benchmark (DESIGN.md "Measuring").
 *
 * Runs a list of settings (a method and its options) over one scene and pose stream. Every
 * setting renders the same frames (same display times, views and seeds). Every scored frame is
 * compared with a converged reference (`spp`, accumulated to ref_spp samples at that frame's
 * views, cached as PFM in out_dir/ref/). Per frame and setting one CSV row; at the end a summary
 * (means over the measured frames, ratios to a baseline setting) and gnuplot charts.
 *
 * Output folder (out_dir):
 * - frames/NAME.csv   one file per setting: a "# xrsc-bench ..." line with the run's
 *                     configuration, a header, one row per frame. Written as NAME.csv.part and
 *                     renamed when the setting is complete, so a rerun with the same
 *                     configuration skips complete settings (restartable).
 * - ref/              frame_NNNNN_{left,right}.pfm references and config.txt; a rerun with the
 *                     same reference configuration reuses them (resumable). With ref_floor also
 *                     frame_NNNNN_{left,right}_floor.pfm (the second reference, another seed).
 * - bench.csv         all rows of all settings, pass columns the union over the methods.
 * - summary.csv       one row per setting: means and ratios to the baseline.
 * - NAME.gp, NAME.png gnuplot scripts and their charts; plot/ holds their data.
 */
#pragma once

#include "hs_opt.h"
#include "hs_pose_stream.h"
#include "xrsc/xrsc.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HS_BENCH_MAX_SETTINGS 64
#define HS_BENCH_NAME_MAX 48
#define HS_BENCH_SPEC_MAX 320

/**
 * The default set: the issue-3 set (`spp` 1 and 4, `samplecache` single / multi / adaptive x
 * 1pass / 2pass), then the main job's stereo blends on the default sample cache (adaptive,
 * 1pass): `moments` at R = 0 (xrsc replay's default) and R = 1, and `pfj23`.
 * Settings text: settings separated by ';', each "METHOD[:KEY=VALUE,KEY=VALUE...]";
 * name=LABEL sets the label (default: derived from method and keys). Keys: hs_bench_print_keys.
 * METHOD may also be HS_BENCH_DEFAULT_SETTING.
 */
#define HS_BENCH_DEFAULT_SETTINGS                                                                 \
    "spp:spp=1;spp:spp=4;"                                                                        \
    "samplecache:trace=single,reproject=1pass;samplecache:trace=multi,reproject=1pass;"           \
    "samplecache:trace=adaptive,reproject=1pass;"                                                 \
    "samplecache:trace=single,reproject=2pass;samplecache:trace=multi,reproject=2pass;"           \
    "samplecache:trace=adaptive,reproject=2pass;"                                                 \
    "samplecache:blend=moments,r=0;samplecache:blend=moments,r=1;samplecache:blend=pfj23"

/** The setting that is what `xrsc replay` renders without options: its renderer options come
 *  from hs_replay_default_renderer (method, blend, R: the product as shipped), the run's size
 *  and seed as for every setting; keys of that method may follow ("default:taa=on"). */
#define HS_BENCH_DEFAULT_SETTING "default"

/** One benchmarked setting. */
typedef struct hs_bench_setting {
    char name[HS_BENCH_NAME_MAX]; /**< label: letters, digits, '.', '_', '+', '-' (file name) */
    char spec[HS_BENCH_SPEC_MAX]; /**< canonical text: method, then the keys as given */
    /** spec without its r=... key (settings that differ only in R share a group; the stereo
     *  discrepancy / CPBD vs R chart draws one line per group). */
    char group[HS_BENCH_SPEC_MAX];
    double r; /**< the value of key "r" (stereo blend radius R), NaN when not set */
    /** Method and method options; size and seed are the run's (hs_bench_options). */
    xrsc_renderer_options renderer;
} hs_bench_setting;

/**
 * Parses a settings text (see HS_BENCH_DEFAULT_SETTINGS) into out[0..*out_count). Unknown
 * methods or keys, keys of another method, bad values, duplicate names: XRSC_ERROR_INVALID_ARGUMENT
 * with the offending setting in diag.
 */
xrsc_result hs_bench_parse_settings(const char *text, hs_bench_setting *out, uint32_t max_count,
                                    uint32_t *out_count, xrsc_diag *diag);
/** Prints the setting keys (name, methods, values) for --help. */
void hs_bench_print_keys(FILE *f);

/** How the stream is placed in the scene. */
typedef enum hs_bench_anchor {
    HS_BENCH_ANCHOR_START = 0, /**< the head pose at start_s is placed at the scene viewpoint */
    HS_BENCH_ANCHOR_FIRST,     /**< the stream's first pose (as `xrsc replay`) */
    HS_BENCH_ANCHOR_NONE,      /**< the stream's own coordinates */
} hs_bench_anchor;

/** Which part of a bench run to do (`xrsc sweep` runs a bench in parts, one per work unit). */
typedef enum hs_bench_part {
    HS_BENCH_PART_ALL = 0, /**< references, every setting, the report */
    HS_BENCH_PART_REF,     /**< only the reference of frame part_frame (a scored frame) */
    HS_BENCH_PART_RUN,     /**< the settings (references they lack rendered first), no report */
    HS_BENCH_PART_REPORT,  /**< no rendering: the report from complete settings; a setting not
                                complete is an error naming it (no Vulkan device is made) */
} hs_bench_part;

typedef struct hs_bench_options {
    const char *scene_path;
    const char *poses_path;
    hs_pose_format pose_format;
    const char *out_dir;
    xrsc_context_options context;
    xrsc_scene_options scene;
    xrsc_headset headset; /**< all zero: xrsc_headset_default */
    hs_bench_anchor anchor;
    double start_s;
    uint32_t frames;      /**< 0: until the stream ends */
    uint32_t warmup;      /**< first frames of every setting left out of the means */
    uint32_t score_every; /**< frames warmup, warmup+K, ... are scored against a reference; 0: 1 */
    uint32_t width, height;
    uint32_t seed;
    uint32_t ref_spp; /**< samples per pixel of the references; 0: 256 */
    const hs_bench_setting *settings;
    uint32_t setting_count;
    const char *baseline; /**< setting name for the ratios; NULL: first samplecache single, else
                               the first setting */
    /** Also render a second reference of the first scored frame with another seed and print
     *  the relMSE between the two references: the noise floor of the relMSE column. */
    bool ref_floor;
    bool fresh;           /**< ignore results and references already in out_dir */
    bool no_plots;        /**< write the gnuplot scripts but do not run gnuplot */
    /** GPU and wall times, rays and counters only: no references, no read-backs, no image
     *  metrics (their columns stay empty), so that large sizes measure the GPU, not the CPU's
     *  metrics (scripts/gpu-check.sh at headset sizes). */
    bool timing_only;
    /** Also write every scored frame's two eyes as PFM files,
     *  out_dir/frames/NAME/frame_%05u_{left,right}.pfm beside ref/'s references of the same
     *  frame, for per-pixel error maps (bench/results/issue19-cornell/). */
    bool keep_frames;
    bool progress;        /**< progress lines on stderr */
    /** A part of the run (sweeps). Any part but ALL shares out_dir with other processes: the
     *  reference cache is never emptied (references of another configuration there are an
     *  error), and files are written under names of this process before their rename. */
    hs_bench_part part;
    uint32_t part_frame; /**< HS_BENCH_PART_REF: the frame */
} hs_bench_options;

/**
 * Runs the benchmark, writes the files above and prints the summary table to `summary`
 * (may be NULL).
 */
xrsc_result hs_bench_run(const hs_bench_options *opt, FILE *summary, xrsc_diag *diag);

/**
 * `xrsc bench`; argv[0] is "bench". Returns the exit code: 0 success, 1 failure, 2 bad
 * arguments.
 */
int hs_bench_main(int argc, char **argv);

/**
 * The frames opt would score (no device needed: the pose stream is read for the frame count):
 * out[0..*count), at most cap of them (more is an error naming --frames).
 */
xrsc_result hs_bench_scored_frames(const hs_bench_options *opt, uint32_t *out, uint32_t cap,
                                   uint32_t *count, xrsc_diag *diag);

/** out_dir/ref/frame_NNNNN_{left,right}.pfm: the cached reference of frame k, eye 0 or 1. */
void hs_bench_ref_path(const char *out_dir, uint32_t k, int eye, char *out, size_t cap);

/** A parsed `xrsc bench` command line (options, settings, resolved paths). */
typedef struct hs_bench_cmdline hs_bench_cmdline;

/**
 * Parses an `xrsc bench` command line (argv[0] is "bench"; --opt=value too) with the command's
 * defaults, without running it. Returns 0 with *out set, 0 with *out NULL after printing
 * --help, or the exit status of a bad command line (the error printed). Free with
 * hs_bench_cmdline_free. `xrsc sweep` builds each work unit's bench this way.
 */
int hs_bench_cmdline_parse(int argc, char **argv, hs_bench_cmdline **out);
/** The options of a parsed command line (settings included), to change before hs_bench_run. */
hs_bench_options *hs_bench_cmdline_options(hs_bench_cmdline *c);
void hs_bench_cmdline_free(hs_bench_cmdline *c);
/** The `xrsc bench` option table (hs_opt.h, static), *out_count rows: for commands that build
 *  bench command lines (`xrsc sweep` reads from it the options a sweep file may set). */
const hs_opt *hs_bench_cmdline_table(size_t *out_count);

/**
 * `xrsc bench --suite stability [...]` (hs_bench_suite.c, issue 9): the failure cases, each
 * for every method present, scored per image region; called by hs_bench_main when argv has
 * --suite. Same exit codes.
 */
int hs_bench_suite_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
