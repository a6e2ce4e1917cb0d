// SPDX-License-Identifier: MIT
/**
 * @file main.c
 * @brief The `xrsc` program: replays a head-pose stream over a glTF scene and writes the
 *        stereo result (per-eye and side-by-side PNG, linear PFM, per-frame timing).
 */
#include "hs_args.h"
#include "hs_bench.h"
#include "hs_compare_cmd.h"
#include "hs_headset.h"
#include "hs_light_args.h"
#include "hs_metrics_cmd.h"
#include "hs_poses_cmd.h"
#include "hs_replay.h"
#include "hs_run.h"
#include "hs_xr_replay.h"
#include "u_diag.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef HS_XR_DEFAULT_MANIFEST
#define HS_XR_DEFAULT_MANIFEST "host_sim/src/runtime/xrsc_runtime.json"
#endif
#define HS_XR_DEFAULT_MANIFEST_TEXT HS_XR_DEFAULT_MANIFEST

#ifndef XRSC_SOURCE_DIR
#define XRSC_SOURCE_DIR "."
#endif

/* Defaults of the main job: sized so the bundled replay finishes in about a minute on lavapipe
 * with two CPU cores (DESIGN.md: benchmarks at 2 x 256 x 256). */
#define DEFAULT_SCENE XRSC_SOURCE_DIR "/scenes/cornell.gltf"
#define DEFAULT_POSES XRSC_SOURCE_DIR "/poses/orbit_cornell.xrpose"
#define DEFAULT_OUT "out/replay"
#define DEFAULT_WIDTH HS_REPLAY_DEFAULT_SIZE_PX
#define DEFAULT_HEIGHT HS_REPLAY_DEFAULT_SIZE_PX
#define DEFAULT_SPP HS_REPLAY_DEFAULT_SPP

static void usage(FILE *f)
{
    fprintf(f,
"usage: xrsc [replay] [options]\n"
"       xrsc metrics --ref DIR --test DIR [options]   (image metrics; xrsc metrics --help)\n"
"       xrsc compare A B [options]  (A/B images and metrics of two runs; xrsc compare --help)\n"
"       xrsc bench [options]        (speed vs. accuracy of methods; xrsc bench --help)\n"
"       xrsc poses stats [--fastest S] FILE   (pose stream speed; xrsc poses --help)\n"
"       xrsc version | --version   (program, Vulkan loader and OpenXR versions)\n"
"\n"
"Replays a recorded head-pose stream over a glTF 2.0 scene, ray traces both eyes with\n"
"Vulkan and writes the stereo result: per-eye and side-by-side PNG (tone-mapped), linear\n"
"PFM (optional) and frames.csv (per-frame timing with --direct; through OpenXR the\n"
"runtime's log of display time, stream time and head pose), and views.csv (each frame's\n"
"eye poses, FOVs and sizes, both paths; README.md, \"views.csv\").\n"
"\n"
"Input:\n"
"  --scene PATH        glTF scene (.gltf/.glb)        [scenes/cornell.gltf]\n"
"  --poses PATH        pose stream                    [poses/orbit_cornell.xrpose]\n"
"  --pose-format F     auto | xrsc | pred6dof | 360video | librnr   [auto]\n"
"  --pose-columns L    read a CSV/TSV export by columns, e.g. t,x,y,z,qx,qy,qz,qw (any\n"
"                      order; _ skips a column; delimiter, header and a leading index\n"
"                      column are detected; poses/README.md, \"Import by columns\")\n"
"  --pose-time-unit U  s | ms | us | ns | ticks (with --pose-columns) [s]\n"
"  --pose-handedness H right | left-unity (with --pose-columns) [right]\n"
"  --no-anchor         use the stream's coordinates as they are (default: its first pose\n"
"                      is placed at the scene's viewpoint)\n"
"  --start S           start S seconds into the stream (past its end: an error) [0]\n"
"  --fov F             headset | scene: scene = both eyes use the glTF camera's yfov and\n"
"                      aspect ratio (both paths) [headset]\n"
"  --frame             place the viewpoint so the scene's bounds fill the view (default:\n"
"                      the glTF camera, else in front of the bounds looking down -Z); a\n"
"                      scene narrower than the IPD gets an IPD of a tenth of the viewing\n"
"                      distance (--direct, unless --ipd is given)\n"
"  --viewpoint V       camera:N (the scene's N-th camera, from 0) | x,y,z[:yaw] (metres;\n"
"                      degrees about +Y, 0 looks down -Z) | inside (the bounds' centre):\n"
"                      where the stream's first pose is placed (not with --frame)\n"
"  --frames N          render N frames (0 = until the stream ends) [0]; frames past the\n"
"                      stream's end hold its last pose, with a warning\n"
"                      (XRSC_WARN_FRAMES_PAST_END) naming how many\n"
"  --hold-last         hold the last pose past the stream's end without that warning\n"
"  --max-pose-bytes N  refuse pose files larger than N bytes (suffix K, M or G) [1G]\n"
"\n"
"Rendering:\n"
"  --method M          spp | primary | samplecache | taa | hashcache | hybrid | isrt\n"
"                      [samplecache: the sample cache of seed 000]\n"
"  --spp N             samples per pixel per frame    [%d]\n"
"  --bounces N         bounces after the first hit    [3]\n"
"  --resolution WxH    render size per eye            [%dx%d]\n"
"  --seed N            random seed                    [0]\n"
"  --env R,G,B         constant environment radiance (default: the scene's)\n"
HS_LIGHT_USAGE
"  --device D          cpu | gpu | index | name part  [$XRSC_DEVICE, else a GPU, else lavapipe]\n"
"  --validation        enable the Vulkan validation layer, synchronization checks included\n"
"\n"
"Sample cache (--method samplecache; seed 000 section 3, defaults of section 4):\n"
"  --sc-slots N        slots per pixel, 1..16         [12]\n"
"  --sc-target X       target samples per pixel       [4]\n"
"  --sc-delta X        density tolerance              [1]\n"
"  --sc-eps0 X         retrace tolerance (relative)   [0.001]\n"
"  --sc-eps1 X         edge test epsilon (Eq. 2)      [0.005]\n"
"  --sc-block N        base-rate block size           [4]\n"
"  --sc-trace T        single | multi | adaptive      [adaptive]\n"
"  --sc-reproject R    1pass | 2pass                  [1pass]\n"
"  --sc-shading-cache  on | off                       [on]\n"
"  --sc-shade S        uniform | adaptive | adaptive-variance (importance = the\n"
"                      relative variance of each sample's mean)   [uniform]\n"
"  --sc-shade-rate P   adaptive shading rate, percent of the pixels [100]\n"
"  --sc-alpha A        clamped | fixed (temporal blend, App. C) [clamped]\n"
"  --sc-alpha-fixed X  alpha of --sc-alpha fixed      [0.1]\n"
"  --sc-cross-eye      on | off: each eye's view-independent samples also serve the other\n"
"                      eye, traced and shaded once for both (beyond seed 000) [off]\n"
"  --sc-visibility-cache on | off: shadow visibility cache of the shading pass's light\n"
"                      samples at the first hit (seed 002, AQVC) [off]\n"
"  --sc-visibility-tolerance C  its error threshold C_E, pixels (seed 002 Eq. 3, 7) [4]\n"
"  --sc-visibility-refine R  adaptive | strict | none: Alg. 2, zero refinement error\n"
"                      tolerance (trace unless all 8 neighbours agree), no refinement\n"
"                      [adaptive]\n"
"  --isrt-m N          --method isrt: M x M fixed sub-pixel slots, 1..4 [2] (interactive\n"
"                      stable ray tracing's layout, seed 000 Fig. 10; the --sc-* shading and\n"
"                      --sc-trace options apply, slots/target/delta/reproject do not)\n"
"\n"
"Hash cache (--method hashcache, and hybrid's radiance; seed 000 section 4):\n"
"  --hc-table N        table entries, 16..2^27 (24 B each) [4194304]\n"
"  --hc-lod L          distance | distance-normal (voxel LoD; Fig. 9) [distance]\n"
"  --hc-voxel-scale X  voxel edge / pixel footprint, rounded down to 2^k m [0.5]\n"
"  --hc-max-age N      frames an entry lives unaccessed before it may be overwritten [64]\n"
"  --hc-voxel-jitter   on | off (jitter the lookup within +-1/2 voxel, BFK18) [on]\n"
"\n"
"Stereo blend (after reconstruction, before submission; seed 000 section 3.6):\n"
"  --blend B           none | pfj23 | moments  [moments for the sample caches\n"
"                      (samplecache, isrt, hybrid), else none]\n"
"  --blend-r R         sharpness R in [0, 1] of moments (0: lowest error, Fig. 15) [0]\n"
"  --blend-estimate E  samples | mean: the variances moments uses, the spread of the\n"
"                      samples (Eq. 5 as printed) or of the pixel's mean [samples]\n"
"\n"
"Temporal antialiasing (after reconstruction, before the stereo blend; seed 000 section 5.1):\n"
"  --taa T             off | on | pfj23  [on for taa, pfj23 for hashcache and hybrid, else off]\n"
"  --taa-alpha X       weight of the current frame with --taa on [0.1]\n"
"\n"
"OpenXR (the default path):\n"
"  The plugin runs as an OpenXR application (XR_KHR_vulkan_enable2) on the runtime that\n"
"  XR_RUNTIME_JSON names, or, when it is unset, on this build's host_sim runtime\n"
"  (" HS_XR_DEFAULT_MANIFEST_TEXT "); the runtime replays the poses and writes\n"
"  the frames it is given (--start, --ipd, --device, ... reach it as XRSC_RT_*\n"
"  variables; host_sim/src/runtime/README.md). --pose-format other than auto needs\n"
"  --direct unless the runtime detects it.\n"
"  --preview           show the run in the runtime's preview window (as XRSC_RT_PREVIEW=1):\n"
"                      overlay with frame, time, ms, method, blend, R; keys V/1/2/3 views,\n"
"                      D depth-compensated stereo difference, E error vs. the reference,\n"
"                      Left/Right step through recent frames, O overlay, Esc/Q quit; it\n"
"                      stays open after the last frame until closed (needs DISPLAY)\n"
"  --preview-reference DIR  linear frames (xrsc replay --write linear) for the E view\n"
"  --preview-autoclose close the window when the run ends (scripts, tests)\n"
"  --direct            render in-process without OpenXR (tests, benchmarks)\n"
"\n"
"Simulated headset:\n"
"  --headset NAME      a headset profile: per-eye resolution, refresh rate, IPD and\n"
"                      asymmetric per-eye FOV (quest3, quest2, index, vision-pro, ...;\n"
"                      --headset list shows them and their sources); --resolution, --ipd,\n"
"                      --refresh given too win over the profile's  [a Quest-like default]\n"
"  --headsets FILE     read the profiles from FILE (format: host_sim/headsets.txt)\n"
"  --ipd MM            interpupillary distance in mm  [63]\n"
"  --refresh HZ        display refresh rate           [90]\n"
"\n"
"Output:\n"
"  --out DIR           output folder                  [out/replay]\n"
"  --write LIST        any of eyes,sbs,linear,exr,none [eyes,sbs]; exr: OpenEXR float\n"
"                      R,G,B + depth Z (m at the pixel centre, 0 = no hit) per eye,\n"
"                      frame_NNNNN_left/right.exr (scored by xrsc metrics --stereo)\n"
"  --video FILE        the side-by-side stream as a video through ffmpeg at the refresh\n"
"                      rate (e.g. out.mp4), when ffmpeg is installed (else a warning)\n"
"  --exposure X        tone-mapping exposure, or auto: middle grey at the stereo frame's\n"
"                      log-average luminance, smoothed over frames [auto]\n"
"  --overwrite         replace the earlier run in --out: its files (frame_*.png/pfm/exr,\n"
"                      frames.csv, views.csv, run.json, run.conf) are removed first,\n"
"                      others kept; without it a folder holding a run is refused (exit 2)\n"
"  --quiet             errors only: no progress, summary, warnings or runtime info lines\n"
"  Each run writes run.json into --out (command line, settings, device, version, start\n"
"  time UTC, status and summary) and run.conf (its settings in --config format). Every\n"
"  file is written under a temporary name and renamed, a frame's files together, so none\n"
"  is ever truncated and no frame is half there. The first failed write stops the run\n"
"  (status failed, exit 1). Ctrl-C (SIGINT), SIGTERM or SIGHUP finishes the frame in\n"
"  flight, writes the files and the summary and exits 130, 143 or 129 (status\n"
"  interrupted); a second Ctrl-C ends at once, run.json still saying interrupted.\n"
"\n"
"Command line:\n"
"  --opt=value         the same as --opt value (every command)\n"
"  --config FILE       options from FILE, one per line: \"key = value\", \"--key value\" or\n"
"                      a flag alone; '#' starts a comment, \"...\" quotes a value; options\n"
"                      after --config override it. xrsc --config RUN/run.conf --out NEW\n"
"                      repeats a run exactly\n"
"  --version           versions of xrsc, the Vulkan loader and OpenXR (also xrsc version)\n"
"  -h, --help          this help\n",
            DEFAULT_SPP, DEFAULT_WIDTH, DEFAULT_HEIGHT);
}

static int bad_arg(const char *flag, const char *value, const char *why)
{
    return hs_bad_arg("xrsc", flag, value, why);
}

/* Options that take a value; anything else starting with "--" is unknown. */
static const char *const value_options[] = {
    "--scene", "--poses",   "--pose-format", "--start", "--frames", "--method",
    "--pose-columns", "--pose-time-unit", "--pose-handedness", "--fov",
    "--spp",   "--bounces", "--resolution",  "--seed",  "--env",    "--device",
    "--ipd",   "--refresh", "--out",         "--write", "--exposure",
    "--headset", "--headsets", "--video", "--preview-reference",
    "--env-map", "--env-intensity", "--env-rotation", "--sky-turbidity", "--sun-dir",
    "--sc-slots", "--sc-target", "--sc-delta", "--sc-eps0", "--sc-eps1", "--sc-block",
    "--sc-trace", "--sc-reproject", "--sc-shading-cache", "--sc-shade", "--sc-shade-rate",
    "--sc-alpha", "--sc-alpha-fixed", "--sc-cross-eye", "--sc-visibility-cache",
    "--sc-visibility-tolerance", "--sc-visibility-refine", "--blend", "--blend-r",
    "--blend-estimate", "--taa", "--taa-alpha",
    "--isrt-m", "--hc-table", "--hc-lod", "--hc-voxel-scale", "--hc-max-age",
    "--hc-voxel-jitter", "--viewpoint",
    "--max-pose-bytes",
};

/* Positive float option; returns 0 or the exit code of bad_arg. */
static int parse_positive(const char *flag, const char *v, float max, float *out)
{
    double d;
    if (!hs_parse_f(v, &d) || !(d > 0) || d > max) {
        char why[64];
        snprintf(why, sizeof(why), "expected a number in (0, %g]", max);
        return bad_arg(flag, v, why);
    }
    *out = (float)d;
    return 0;
}

/* The --sc-* options (xrsc_samplecache_options); returns 0 or the exit code of bad_arg. */
static int parse_samplecache(const char *a, const char *v, xrsc_samplecache_options *sc)
{
    uint32_t u;
    if (!strcmp(a, "--sc-slots")) {
        if (!hs_parse_u32(v, &u) || u < 1 || u > 16)
            return bad_arg(a, v, "expected 1..16");
        sc->slots = u;
    } else if (!strcmp(a, "--sc-block")) {
        if (!hs_parse_u32(v, &u) || u < 1 || u > 64)
            return bad_arg(a, v, "expected 1..64");
        sc->block = u;
    } else if (!strcmp(a, "--sc-target")) {
        return parse_positive(a, v, 16.0f, &sc->n_target);
    } else if (!strcmp(a, "--sc-delta")) {
        return parse_positive(a, v, 16.0f, &sc->delta);
    } else if (!strcmp(a, "--sc-eps0")) {
        return parse_positive(a, v, 1.0f, &sc->eps0);
    } else if (!strcmp(a, "--sc-eps1")) {
        return parse_positive(a, v, 1.0f, &sc->eps1);
    } else if (!strcmp(a, "--sc-alpha-fixed")) {
        return parse_positive(a, v, 1.0f, &sc->alpha_fixed);
    } else if (!strcmp(a, "--sc-shade-rate")) {
        int r = parse_positive(a, v, 1600.0f, &sc->shade_rate);
        sc->shade_rate *= 0.01f; /* percent -> shadings per pixel */
        return r;
    } else if (!strcmp(a, "--sc-trace")) {
        if (!strcmp(v, "single"))
            sc->trace = XRSC_SC_TRACE_SINGLE;
        else if (!strcmp(v, "multi"))
            sc->trace = XRSC_SC_TRACE_MULTI;
        else if (!strcmp(v, "adaptive"))
            sc->trace = XRSC_SC_TRACE_ADAPTIVE;
        else
            return bad_arg(a, v, "expected single, multi or adaptive");
    } else if (!strcmp(a, "--sc-reproject")) {
        if (!strcmp(v, "1pass"))
            sc->reproject = XRSC_SC_REPROJECT_1PASS;
        else if (!strcmp(v, "2pass"))
            sc->reproject = XRSC_SC_REPROJECT_2PASS;
        else
            return bad_arg(a, v, "expected 1pass or 2pass");
    } else if (!strcmp(a, "--sc-shading-cache")) {
        bool on;
        if (!hs_parse_on_off(v, &on))
            return bad_arg(a, v, "expected on or off");
        sc->no_shading_cache = !on;
    } else if (!strcmp(a, "--sc-shade")) {
        if (!strcmp(v, "uniform"))
            sc->shade = XRSC_SC_SHADE_UNIFORM;
        else if (!strcmp(v, "adaptive"))
            sc->shade = XRSC_SC_SHADE_ADAPTIVE;
        else if (!strcmp(v, "adaptive-variance"))
            sc->shade = XRSC_SC_SHADE_ADAPTIVE_VARIANCE;
        else
            return bad_arg(a, v, "expected uniform, adaptive or adaptive-variance");
    } else if (!strcmp(a, "--sc-cross-eye")) {
        if (!hs_parse_on_off(v, &sc->cross_eye))
            return bad_arg(a, v, "expected on or off");
    } else if (!strcmp(a, "--sc-visibility-cache")) {
        if (!hs_parse_on_off(v, &sc->visibility.enabled))
            return bad_arg(a, v, "expected on or off");
    } else if (!strcmp(a, "--sc-visibility-tolerance")) {
        return parse_positive(a, v, 1024.0f, &sc->visibility.error_px);
    } else if (!strcmp(a, "--sc-visibility-refine")) {
        if (!strcmp(v, "adaptive"))
            sc->visibility.refine = XRSC_SC_VIS_REFINE_ADAPTIVE;
        else if (!strcmp(v, "strict"))
            sc->visibility.refine = XRSC_SC_VIS_REFINE_STRICT;
        else if (!strcmp(v, "none"))
            sc->visibility.refine = XRSC_SC_VIS_REFINE_NONE;
        else
            return bad_arg(a, v, "expected adaptive, strict or none");
    } else if (!strcmp(a, "--sc-alpha")) {
        if (!strcmp(v, "clamped"))
            sc->alpha = XRSC_SC_ALPHA_CLAMPED;
        else if (!strcmp(v, "fixed"))
            sc->alpha = XRSC_SC_ALPHA_FIXED;
        else
            return bad_arg(a, v, "expected clamped or fixed");
    } else {
        return bad_arg(a, NULL, "unknown option");
    }
    return 0;
}

/* The --hc-* options (xrsc_hashcache_options); returns 0 or the exit code of bad_arg. */
static int parse_hashcache(const char *a, const char *v, xrsc_hashcache_options *hc)
{
    uint32_t u;
    if (!strcmp(a, "--hc-table")) {
        if (!hs_parse_u32(v, &u) || u < 16 || u > (1u << 27))
            return bad_arg(a, v, "expected 16..134217728");
        hc->table_entries = u;
    } else if (!strcmp(a, "--hc-lod")) {
        if (!strcmp(v, "distance"))
            hc->lod = XRSC_HC_LOD_DISTANCE;
        else if (!strcmp(v, "distance-normal"))
            hc->lod = XRSC_HC_LOD_DISTANCE_NORMAL;
        else
            return bad_arg(a, v, "expected distance or distance-normal");
    } else if (!strcmp(a, "--hc-voxel-scale")) {
        return parse_positive(a, v, 1024.0f, &hc->voxel_scale);
    } else if (!strcmp(a, "--hc-max-age")) {
        if (!hs_parse_u32(v, &u) || u < 1)
            return bad_arg(a, v, "expected frames >= 1");
        hc->max_age = u;
    } else if (!strcmp(a, "--hc-voxel-jitter")) {
        bool on;
        if (!hs_parse_on_off(v, &on))
            return bad_arg(a, v, "expected on or off");
        hc->no_voxel_jitter = !on;
    } else {
        return bad_arg(a, NULL, "unknown option");
    }
    return 0;
}

/* --headset NAME (and --headsets FILE): the profile's resolution, refresh, IPD and per-eye
 * FOV, except what --resolution, --ipd or --refresh set. Returns -1 to go on, else the exit
 * code (0 after --headset list). */
static int apply_headset(const char *name, const char *path, bool size_given, bool ipd_given,
                         bool refresh_given, hs_replay_options *opt)
{
    hs_headset_table table;
    xrsc_diag diag = {0};
    char msg[1400];
    if (hs_headsets_load(path, &table, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        return 2;
    }
    const hs_headset_profile *p = NULL;
    int rc = -1;
    if (name && !strcmp(name, "list")) {
        hs_headsets_print(&table, stdout);
        rc = 0;
    } else if (name && hs_headsets_select(&table, name, &p, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        rc = 2;
    } else if (p) {
        xrsc_headset hs = p->headset;
        if (ipd_given)
            hs.ipd_m = opt->headset.ipd_m;
        if (refresh_given) {
            hs.refresh_hz = opt->headset.refresh_hz;
            bool offered = false;
            for (uint32_t m = 0; m < p->refresh_mode_count; m++)
                offered = offered || p->refresh_modes_hz[m] == hs.refresh_hz;
            if (!offered)
                U_LOG_W("--refresh %g: %s does not offer this rate (--headset list)",
                        (double)hs.refresh_hz, p->name);
        }
        if (!size_given) {
            opt->renderer.width = hs.width_px;
            opt->renderer.height = hs.height_px;
        }
        opt->headset = hs;
    }
    hs_headsets_free(&table);
    return rc;
}

/* The summary of a run (also of one stopped by a signal), on stdout. */
static void print_summary(const hs_replay_options *opt, const hs_replay_stats *st)
{
    printf("device: %s\n", st->device);
    printf("method: %s, stereo blend: %s", xrsc_method_name(opt->renderer.method),
           xrsc_blend_name(opt->renderer.blend));
    if (opt->renderer.blend == XRSC_BLEND_MOMENTS)
        printf(", R = %g", (double)opt->renderer.blend_r);
    if (opt->renderer.blend == XRSC_BLEND_MOMENTS && opt->renderer.blend_estimate)
        printf(", estimate %s", xrsc_blend_estimate_name(opt->renderer.blend_estimate));
    printf("\n");
    printf("frames: %u  load %.2f s  total %.2f s\n", st->frames, st->load_s, st->total_s);
    const xrsc_scene_info *si = &st->scene;
    /* materials: the file's (the scene adds glTF's default material to them) */
    printf("load: scene %.2f s (parse %.2f, geometry %.2f, tangents %.2f, Morton %.2f, GPU "
           "%.2f), %llu triangles, %u materials, %u textures, %u lights%s, peak memory %.0f MiB\n",
           si->load_ms * 1e-3, si->load_parse_ms * 1e-3, si->load_geometry_ms * 1e-3,
           si->load_tangents_ms * 1e-3, si->load_morton_ms * 1e-3, si->load_gpu_ms * 1e-3,
           (unsigned long long)si->triangle_count,
           si->material_count > 0 ? si->material_count - 1 : 0, si->texture_count,
           si->light_count, si->studio_environment ? " (studio environment)" : "",
           st->load_peak_rss_kib / 1024.0);
    printf("render wall time per stereo frame: mean %.2f ms, max %.2f ms\n",
           st->render_ms_mean, st->render_ms_max);
    for (uint32_t p = 0; p < st->pass_count; p++)
        printf("  pass %-12s %.3f ms (GPU timestamps, mean)\n", st->pass_mean[p].name,
               st->pass_mean[p].gpu_ms);
    if (st->rays_per_frame > 0 && st->render_ms_mean > 0)
        printf("rays per frame: %.0f  (%.2f Mrays/s of wall time)\n", st->rays_per_frame,
               st->rays_per_frame / (st->render_ms_mean * 1e3));
    if (opt->out_dir)
        printf("output: %s/\n", opt->out_dir);
}

/* Options that are not settings of a run (run.json, run.conf). */
static const char *const not_settings[] = {"--quiet", "--overwrite"};

/* Runs the replay with its record: the output folder checked (--overwrite), run.json and
 * run.conf written before, run.json after (hs_run.h), SIGINT/SIGTERM/SIGHUP as a clean stop
 * and a second one as the end at once. Returns the exit status:
 * 0, 1 (failed), 2 (the folder holds a run), 128 + signal (stopped). */
static int run_recorded(hs_replay_options *opt, bool direct, bool overwrite, bool quiet,
                        hs_run_info *run)
{
    xrsc_diag diag = {0};
    char msg[1400];
    if (opt->out_dir) {
        xrsc_result pr = hs_run_prepare_out(opt->out_dir, overwrite, &diag);
        if (pr == XRSC_OK)
            pr = hs_run_write_record(run, NULL, "running", 0, NULL, &diag);
        if (pr != XRSC_OK) {
            fprintf(stderr, "xrsc: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
            return pr == XRSC_ERROR_INVALID_ARGUMENT ? HS_EXIT_BAD_ARGS : 1;
        }
    }
    if (!quiet)
        fprintf(stderr, "xrsc: replaying %s over %s (%s, %ux%u per eye)\n", opt->poses_path,
                opt->scene_path, xrsc_method_name(opt->renderer.method), opt->renderer.width,
                opt->renderer.height);
    opt->stop = hs_run_catch_signals();
    hs_replay_stats st;
    xrsc_result res = direct ? hs_replay_run(opt, &st, &diag) : hs_xr_replay_run(opt, &st, &diag);
    int rc = res != XRSC_OK ? 1 : st.stopped_by ? hs_run_exit_status(st.stopped_by) : 0;
    if (res != XRSC_OK)
        fprintf(stderr, "xrsc: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
    if (opt->out_dir) {
        xrsc_diag rd = {0};
        const char *status = res != XRSC_OK ? "failed" : st.stopped_by ? "interrupted" : "completed";
        if (hs_run_write_record(run, &st, status, rc, res != XRSC_OK ? msg : NULL, &rd) !=
                XRSC_OK &&
            res == XRSC_OK) { /* a failed run's one error is the one above */
            fprintf(stderr, "xrsc: error: %s\n", xrsc_diag_format(&rd, msg, sizeof(msg)));
            rc = rc ? rc : 1;
        }
        hs_run_disarm();
    }
    if (!quiet && res == XRSC_OK) {
        char sig[32];
        if (st.stopped_by)
            fprintf(stderr, "xrsc: %s: stopped after %u frames; the files written are whole\n",
                    hs_run_signal_name(st.stopped_by, sig, sizeof(sig)), st.frames);
        print_summary(opt, &st);
    }
    return rc;
}

/* What the command line of `xrsc replay` sets beyond hs_replay_options. */
typedef struct main_args {
    hs_replay_options opt;
    bool quiet, direct, overwrite;
    bool blend_given;                             /* --blend: else hs_replay_default_blend(method) */
    bool size_given, ipd_given, refresh_given;    /* these win over --headset */
    const char *pose_columns, *pose_time_unit, *pose_handedness;
    const char *headset_name, *headsets_path; /* --headset, --headsets */
} main_args;

/* Options without a value. */
static int parse_flag(const char *a, main_args *m)
{
    hs_replay_options *opt = &m->opt;
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(a, "--no-anchor"))
        opt->no_anchor = true;
    else if (!strcmp(a, "--frame"))
        opt->frame_bounds = true;
    else if (!strcmp(a, "--hold-last"))
        opt->hold_last = true;
    else if (!strcmp(a, "--direct"))
        m->direct = true;
    else if (!strcmp(a, "--preview") || !strcmp(a, "--preview-autoclose")) {
        opt->preview = true;
        opt->preview_autoclose |= !strcmp(a, "--preview-autoclose");
    } else if (!strcmp(a, "--validation"))
        opt->context.validation = true;
    else if (!strcmp(a, HS_LIGHT_FLAG_SKY))
        hs_light_parse("xrsc", a, NULL, &opt->scene);
    else if (!strcmp(a, "--quiet")) {
        m->quiet = true;
        opt->progress = false;
    } else if (!strcmp(a, "--overwrite"))
        m->overwrite = true;
    else
        return HS_ARG_NOT_MINE;
    return HS_ARG_NEXT;
}

/* The input: scene, pose stream, which part of it, and the views' FOV. */
static int parse_input_option(const char *a, const char *v, main_args *m)
{
    hs_replay_options *opt = &m->opt;
    double d;
    if (!strcmp(a, "--scene")) {
        opt->scene_path = v;
    } else if (!strcmp(a, "--poses")) {
        opt->poses_path = v;
    } else if (!strcmp(a, "--pose-format")) {
        if (!hs_pose_format_from_name(v, &opt->pose_format))
            return bad_arg(a, v, "expected auto, xrsc, pred6dof, 360video or librnr");
    } else if (!strcmp(a, "--pose-columns")) {
        m->pose_columns = v;
    } else if (!strcmp(a, "--pose-time-unit")) {
        m->pose_time_unit = v;
    } else if (!strcmp(a, "--pose-handedness")) {
        m->pose_handedness = v;
    } else if (!strcmp(a, "--fov")) {
        if (strcmp(v, "headset") && strcmp(v, "scene"))
            return bad_arg(a, v, "expected headset or scene");
        opt->fov_scene = !strcmp(v, "scene");
    } else if (!strcmp(a, "--start")) {
        if (!hs_parse_f(v, &d) || d < 0)
            return bad_arg(a, v, "expected seconds >= 0");
        opt->start_s = d;
    } else if (!strcmp(a, "--frames")) {
        if (!hs_parse_u32(v, &opt->frames))
            return bad_arg(a, v, "expected a count");
    } else if (!strcmp(a, "--viewpoint")) {
        xrsc_diag d = {0};
        if (hs_viewpoint_parse(v, &opt->viewpoint, &d) != XRSC_OK)
            return bad_arg(a, v, d.message);
    } else if (!strcmp(a, "--max-pose-bytes")) {
        if (!hs_parse_bytes(v, &opt->max_pose_bytes))
            return bad_arg(a, v, "expected a byte count >= 1, e.g. 1G or 500M");
    } else {
        return HS_ARG_NOT_MINE;
    }
    return HS_ARG_NEXT;
}

/* The method, its blend and TAA, and what every method shares (samples, bounces, size). */
static int parse_method_option(const char *a, const char *v, main_args *m)
{
    xrsc_renderer_options *ro = &m->opt.renderer;
    uint32_t u;
    double d;
    if (!strcmp(a, "--method")) {
        if (xrsc_method_from_name(v, &ro->method) != XRSC_OK)
            return bad_arg(a, v, "unknown method (xrsc --help lists them)");
    } else if (!strcmp(a, "--taa")) {
        if (!strcmp(v, "default") || xrsc_taa_mode_from_name(v, &ro->taa.mode) != XRSC_OK)
            return bad_arg(a, v, "expected off, on or pfj23");
    } else if (!strcmp(a, "--isrt-m")) {
        if (!hs_parse_u32(v, &u) || u < 1 || u > 4)
            return bad_arg(a, v, "expected 1..4");
        ro->isrt.m = u;
    } else if (!strcmp(a, "--taa-alpha")) {
        int r = parse_positive(a, v, 1.0f, &ro->taa.alpha);
        if (r)
            return r;
    } else if (!strcmp(a, "--blend")) {
        if (xrsc_blend_from_name(v, &ro->blend) != XRSC_OK)
            return bad_arg(a, v, "unknown blend (none, pfj23, moments)");
        m->blend_given = true;
    } else if (!strcmp(a, "--blend-r")) {
        if (!hs_parse_f(v, &d) || !(d >= 0.0 && d <= 1.0))
            return bad_arg(a, v, "expected R in [0, 1]");
        ro->blend_r = (float)d;
    } else if (!strcmp(a, "--blend-estimate")) {
        if (xrsc_blend_estimate_from_name(v, &ro->blend_estimate) != XRSC_OK)
            return bad_arg(a, v, "unknown estimate (samples, mean)");
    } else if (!strcmp(a, "--spp")) {
        if (!hs_parse_u32(v, &u) || u == 0 || u > 4096)
            return bad_arg(a, v, "expected 1..4096");
        ro->spp.samples_per_pixel = u;
    } else if (!strcmp(a, "--bounces")) {
        if (!hs_parse_u32(v, &u) || u > 16)
            return bad_arg(a, v, "expected 0..16");
        ro->spp.max_bounces = u ? u : XRSC_BOUNCES_NONE;
        ro->samplecache.max_bounces = ro->spp.max_bounces;
        ro->hashcache.max_bounces = ro->spp.max_bounces;
    } else if (!strcmp(a, "--resolution")) {
        unsigned w, h;
        if (!hs_parse_size(v, 8, 8192, &w, &h))
            return bad_arg(a, v, "expected WxH, each 8..8192");
        ro->width = w;
        ro->height = h;
        m->size_given = true;
    } else if (!strcmp(a, "--seed")) {
        if (!hs_parse_u32(v, &ro->seed))
            return bad_arg(a, v, "expected an unsigned integer");
    } else if (!strncmp(a, "--sc-", 5)) {
        int r = parse_samplecache(a, v, &ro->samplecache);
        return r ? r : HS_ARG_NEXT;
    } else if (!strncmp(a, "--hc-", 5)) {
        int r = parse_hashcache(a, v, &ro->hashcache);
        return r ? r : HS_ARG_NEXT;
    } else {
        return HS_ARG_NOT_MINE;
    }
    return HS_ARG_NEXT;
}

/* The world around the scene and the simulated headset: lighting, device, IPD, refresh. */
static int parse_world_option(const char *a, const char *v, main_args *m)
{
    hs_replay_options *opt = &m->opt;
    double d;
    if (!strcmp(a, "--env")) {
        if (!hs_parse_rgb(v, opt->scene.environment))
            return bad_arg(a, v, "expected R,G,B >= 0");
        opt->scene.env_set = true;
    } else if (hs_arg_in(a, hs_light_value_options, hs_light_value_option_count)) {
        int r = hs_light_parse("xrsc", a, v, &opt->scene);
        if (r)
            return r;
    } else if (!strcmp(a, "--device")) {
        opt->context.device = v;
    } else if (!strcmp(a, "--ipd")) {
        if (!hs_parse_f(v, &d) || d < 0 || d > 200)
            return bad_arg(a, v, "expected millimetres 0..200");
        opt->headset.ipd_m = (float)(d * 1e-3);
        m->ipd_given = true;
    } else if (!strcmp(a, "--refresh")) {
        if (!hs_parse_f(v, &d) || d < 1 || d > 1000)
            return bad_arg(a, v, "expected 1..1000 Hz");
        opt->headset.refresh_hz = (float)d;
        m->refresh_given = true;
    } else if (!strcmp(a, "--headset")) {
        m->headset_name = v;
    } else if (!strcmp(a, "--headsets")) {
        m->headsets_path = v;
    } else {
        return HS_ARG_NOT_MINE;
    }
    return HS_ARG_NEXT;
}

/* What is written: the folder, the image files, the video, tone mapping, the preview. */
static int parse_output_option(const char *a, const char *v, main_args *m)
{
    hs_replay_options *opt = &m->opt;
    double d;
    if (!strcmp(a, "--video")) {
        opt->video_path = v;
    } else if (!strcmp(a, "--out")) {
        opt->out_dir = v;
    } else if (!strcmp(a, "--preview-reference")) {
        opt->preview_reference = v;
        opt->preview = true;
    } else if (!strcmp(a, "--write")) {
        opt->write_eyes = opt->write_sbs = opt->write_linear = opt->write_exr = false;
        char list[256];
        snprintf(list, sizeof(list), "%s", v);
        for (char *tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
            if (!strcmp(tok, "eyes"))
                opt->write_eyes = true;
            else if (!strcmp(tok, "sbs"))
                opt->write_sbs = true;
            else if (!strcmp(tok, "linear"))
                opt->write_linear = true;
            else if (!strcmp(tok, "exr"))
                opt->write_exr = true;
            else if (strcmp(tok, "none") != 0)
                return bad_arg(a, v, "expected eyes, sbs, linear, exr or none");
        }
    } else if (!strcmp(a, "--exposure")) {
        if (!strcmp(v, "auto"))
            opt->exposure = 0.0f; /* automatic (hs_image.h) */
        else if (!hs_parse_f(v, &d) || d <= 0)
            return bad_arg(a, v, "expected a positive number or auto");
        else
            opt->exposure = (float)d;
    } else {
        return HS_ARG_NOT_MINE;
    }
    return HS_ARG_NEXT;
}

/* Reads argv[1..argc) into m: HS_ARG_NEXT when all of it was read, else the exit status. */
static int parse_args(int argc, char **argv, main_args *m)
{
    typedef int (*value_step)(const char *, const char *, main_args *);
    static const value_step steps[] = {parse_input_option, parse_method_option,
                                       parse_world_option, parse_output_option};
    int i = 1;
    if (i < argc && strcmp(argv[i], "replay") == 0)
        i++;
    for (; i < argc; i++) {
        const char *a = argv[i];
        int r = parse_flag(a, m);
        if (r == HS_ARG_NEXT)
            continue;
        if (r != HS_ARG_NOT_MINE)
            return r;
        if (a[0] != '-' || a[1] != '-')
            return bad_arg(a, NULL, "unexpected argument");
        if (!hs_arg_in(a, value_options, sizeof(value_options) / sizeof(value_options[0])))
            return bad_arg(a, NULL, "unknown option");
        if (i + 1 >= argc)
            return bad_arg(a, NULL, "needs a value");
        const char *v = argv[++i];
        r = HS_ARG_NOT_MINE;
        for (size_t k = 0; r == HS_ARG_NOT_MINE && k < sizeof(steps) / sizeof(steps[0]); k++)
            r = steps[k](a, v, m);
        if (r == HS_ARG_NOT_MINE)
            return bad_arg(a, NULL, "unknown option");
        if (r != HS_ARG_NEXT)
            return r;
    }
    return HS_ARG_NEXT;
}

/* What the options mean together: pose columns, the headset profile, the method's default
 * blend, --preview without --direct, --quiet for the library and runtime too. */
static int finish_args(main_args *m)
{
    hs_replay_options *opt = &m->opt;
    if (m->pose_columns) {
        xrsc_diag pd = {0};
        if (hs_pose_columns_parse(m->pose_columns, m->pose_time_unit, m->pose_handedness,
                                  &opt->pose_columns, &pd) != XRSC_OK)
            return bad_arg(pd.field, NULL, pd.message);
    } else if (m->pose_time_unit || m->pose_handedness) {
        return bad_arg(m->pose_time_unit ? "--pose-time-unit" : "--pose-handedness", NULL,
                       "needs --pose-columns");
    }
    if (m->headset_name || m->headsets_path) {
        int r = apply_headset(m->headset_name, m->headsets_path, m->size_given, m->ipd_given,
                              m->refresh_given, opt);
        if (r >= 0)
            return r;
    }
    if (!m->blend_given)
        opt->renderer.blend = hs_replay_default_blend(opt->renderer.method);
    if (opt->frame_bounds && opt->viewpoint.kind != HS_VIEWPOINT_DEFAULT)
        return bad_arg("--viewpoint", NULL, "--frame and --viewpoint both place the view: give one");
    opt->frame_keep_ipd = m->ipd_given;
    if (opt->preview && m->direct)
        return bad_arg("--preview", NULL,
                       "the preview window is the OpenXR runtime's: drop --direct");
    if (m->quiet) /* errors only, also from the library and the OpenXR runtime (u_diag.h) */
        setenv("XRSC_LOG", "error", 1);
    return HS_ARG_NEXT;
}

/* Runs the replay with run.json / run.conf: the given options as parsed (args), and the
 * values of the options not given, as they would be typed. */
static int run_with_record(main_args *m, const hs_args *args, hs_run_info *run)
{
    hs_replay_options *opt = &m->opt;
    char res_s[32], spp_s[16], ipd_s[32], refresh_s[32];
    snprintf(res_s, sizeof(res_s), "%ux%u", opt->renderer.width, opt->renderer.height);
    snprintf(spp_s, sizeof(spp_s), "%u", opt->renderer.spp.samples_per_pixel);
    snprintf(ipd_s, sizeof(ipd_s), "%g", (double)opt->headset.ipd_m * 1e3);
    snprintf(refresh_s, sizeof(refresh_s), "%g", (double)opt->headset.refresh_hz);
    const hs_run_setting defaults[] = {
        {"--scene", opt->scene_path},   {"--poses", opt->poses_path},
        {"--pose-format", "auto"},      {"--start", "0"},
        {"--frames", "0"},              {"--fov", "headset"},
        {"--max-pose-bytes", "1G"},
        {"--method", xrsc_method_name(opt->renderer.method)},
        {"--blend", xrsc_blend_name(opt->renderer.blend)},
        {"--blend-r", "0"},             {"--blend-estimate", "samples"},
        {"--spp", spp_s},
        {"--resolution", res_s},        {"--seed", "0"},
        {"--ipd", ipd_s},               {"--refresh", refresh_s},
        {"--out", opt->out_dir},        {"--write", "eyes,sbs"},
        {"--exposure", "auto"},
    };
    run->args_argc = args->argc;
    run->args_argv = args->argv;
    run->value_options = value_options;
    run->value_count = sizeof(value_options) / sizeof(value_options[0]);
    run->defaults = defaults;
    run->default_count = sizeof(defaults) / sizeof(defaults[0]);
    run->not_settings = not_settings;
    run->not_settings_count = sizeof(not_settings) / sizeof(not_settings[0]);
    run->out_dir = opt->out_dir;
    hs_run_info_start(run);
    return run_recorded(opt, m->direct, m->overwrite, m->quiet, run);
}

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
    main_args m = {
        .opt = {
            .scene_path = DEFAULT_SCENE,
            .poses_path = DEFAULT_POSES,
            .out_dir = DEFAULT_OUT,
            .write_eyes = true,
            .write_sbs = true,
            .progress = true,
        },
    };
    /* the main job (seed 000), the one source of the replay's defaults and of `xrsc bench`'s
     * setting `default`; the blend is chosen again after parsing (hs_replay_default_blend) */
    hs_replay_default_renderer(&m.opt.renderer);
    xrsc_headset_default(&m.opt.headset);
    /* --opt=value and --config FILE (hs_args_prepare); the parse sees "--opt value" pairs. */
    hs_run_info run = {.argc = argc, .argv = argv};
    hs_args args; /* about 140 KiB of stack; argv points into it until the run ends */
    const hs_args_spec spec = {.cmd = "xrsc", .value_options = value_options,
                               .value_count = sizeof(value_options) / sizeof(value_options[0]),
                               .config = true};
    int r = hs_args_prepare(&args, &spec, argc, argv);
    if (r)
        return r;
    if ((r = parse_args(args.argc, args.argv, &m)) != HS_ARG_NEXT)
        return r;
    if ((r = finish_args(&m)) != HS_ARG_NEXT)
        return r;
    return run_with_record(&m, &args, &run);
}
