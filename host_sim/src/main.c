// SPDX-License-Identifier: MIT
/**
 * @file main.c
 * @brief The `xrsc` program: replays a head-pose stream over a glTF scene and writes the
 *        stereo result (per-eye and side-by-side PNG, linear PFM, per-frame timing).
 */
#include "hs_args.h"
#include "hs_bench.h"
#include "hs_metrics_cmd.h"
#include "hs_poses_cmd.h"
#include "hs_replay.h"
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
#define DEFAULT_WIDTH 256
#define DEFAULT_HEIGHT 256
#define DEFAULT_SPP 2

static void usage(FILE *f)
{
    fprintf(f,
"usage: xrsc [replay] [options]\n"
"       xrsc metrics --ref DIR --test DIR [options]   (image metrics; xrsc metrics --help)\n"
"       xrsc bench [options]        (speed vs. accuracy of methods; xrsc bench --help)\n"
"       xrsc poses stats [--fastest S] FILE   (pose stream speed; xrsc poses --help)\n"
"\n"
"Replays a recorded head-pose stream over a glTF 2.0 scene, ray traces both eyes with\n"
"Vulkan and writes the stereo result: per-eye and side-by-side PNG (tone-mapped), linear\n"
"PFM (optional) and frames.csv (per-frame timing with --direct; through OpenXR the\n"
"runtime's log of display time, stream time and head pose).\n"
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
"                      aspect ratio (needs --direct) [headset]\n"
"  --frame             place the viewpoint so the scene's bounds fill the view (default:\n"
"                      the glTF camera, else in front of the bounds looking down -Z)\n"
"  --frames N          render N frames (0 = until the stream ends) [0]\n"
"\n"
"Rendering:\n"
"  --method M          spp | primary | samplecache | taa | hashcache | hybrid | isrt\n"
"                      [samplecache: the sample cache of seed 000]\n"
"  --spp N             samples per pixel per frame    [%d]\n"
"  --bounces N         bounces after the first hit    [3]\n"
"  --resolution WxH    render size per eye            [%dx%d]\n"
"  --seed N            random seed                    [0]\n"
"  --env R,G,B         constant environment radiance (default: the scene's)\n"
"  --device D          cpu | gpu | index | name part  [$XRSC_DEVICE, else a GPU, else lavapipe]\n"
"  --validation        enable the Vulkan validation layer\n"
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
"  --sc-shade S        uniform | adaptive             [uniform]\n"
"  --sc-shade-rate P   adaptive shading rate, percent of the pixels [100]\n"
"  --sc-alpha A        clamped | fixed (temporal blend, App. C) [clamped]\n"
"  --sc-alpha-fixed X  alpha of --sc-alpha fixed      [0.1]\n"
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
"  variables; host_sim/src/runtime/README.md). XRSC_RT_PREVIEW=1 shows both eyes in a\n"
"  window. --pose-format other than auto needs --direct unless the runtime detects it.\n"
"  --direct            render in-process without OpenXR (tests, benchmarks)\n"
"\n"
"Simulated headset:\n"
"  --ipd MM            interpupillary distance in mm  [63]\n"
"  --refresh HZ        display refresh rate           [90]\n"
"\n"
"Output:\n"
"  --out DIR           output folder                  [out/replay]\n"
"  --write LIST        any of eyes,sbs,linear,none    [eyes,sbs]\n"
"  --exposure X        tone-mapping exposure          [1]\n"
"  --quiet             no progress or summary\n"
"  -h, --help          this help\n",
            DEFAULT_SPP, DEFAULT_WIDTH, DEFAULT_HEIGHT);
}

/* The stereo blend when --blend is not given: the raw-moment blend (R = 0) after the methods
 * that keep per-sample radiance and counts (the sample caches, seed 000 §3.6), none after the
 * others (their moments are those of a few fresh samples, or absent). */
static xrsc_blend default_blend(xrsc_method method)
{
    return method == XRSC_METHOD_SAMPLECACHE || method == XRSC_METHOD_ISRT ||
                   method == XRSC_METHOD_HYBRID
               ? XRSC_BLEND_MOMENTS
               : XRSC_BLEND_NONE;
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
    "--sc-slots", "--sc-target", "--sc-delta", "--sc-eps0", "--sc-eps1", "--sc-block",
    "--sc-trace", "--sc-reproject", "--sc-shading-cache", "--sc-shade", "--sc-shade-rate",
    "--sc-alpha", "--sc-alpha-fixed", "--blend", "--blend-r", "--taa", "--taa-alpha",
    "--isrt-m", "--hc-table", "--hc-lod", "--hc-voxel-scale", "--hc-max-age",
    "--hc-voxel-jitter",
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
        if (!strcmp(v, "on"))
            sc->no_shading_cache = false;
        else if (!strcmp(v, "off"))
            sc->no_shading_cache = true;
        else
            return bad_arg(a, v, "expected on or off");
    } else if (!strcmp(a, "--sc-shade")) {
        if (!strcmp(v, "uniform"))
            sc->shade = XRSC_SC_SHADE_UNIFORM;
        else if (!strcmp(v, "adaptive"))
            sc->shade = XRSC_SC_SHADE_ADAPTIVE;
        else
            return bad_arg(a, v, "expected uniform or adaptive");
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
        if (!strcmp(v, "on"))
            hc->no_voxel_jitter = false;
        else if (!strcmp(v, "off"))
            hc->no_voxel_jitter = true;
        else
            return bad_arg(a, v, "expected on or off");
    } else {
        return bad_arg(a, NULL, "unknown option");
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "metrics") == 0)
        return hs_metrics_main(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "bench") == 0)
        return hs_bench_main(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "poses") == 0)
        return hs_poses_main(argc - 1, argv + 1);
    hs_replay_options opt = {
        .scene_path = DEFAULT_SCENE,
        .poses_path = DEFAULT_POSES,
        .out_dir = DEFAULT_OUT,
        .write_eyes = true,
        .write_sbs = true,
        .progress = true,
        /* the main job (seed 000): the per-eye sample cache with the raw-moment stereo blend
         * at R = 0 (the blend is chosen after parsing: default_blend) */
        .renderer = {.method = XRSC_METHOD_SAMPLECACHE, .width = DEFAULT_WIDTH,
                     .height = DEFAULT_HEIGHT, .spp = {.samples_per_pixel = DEFAULT_SPP}},
    };
    xrsc_headset_default(&opt.headset);
    bool quiet = false;
    bool direct = false;       /* --direct: in-process, no OpenXR */
    bool blend_given = false; /* --blend: else default_blend(method) */
    const char *pose_columns = NULL, *pose_time_unit = NULL, *pose_handedness = NULL;

    int i = 1;
    if (i < argc && strcmp(argv[i], "replay") == 0)
        i++;
    for (; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        if (!strcmp(a, "--no-anchor")) {
            opt.no_anchor = true;
            continue;
        }
        if (!strcmp(a, "--frame")) {
            opt.frame_bounds = true;
            continue;
        }
        if (!strcmp(a, "--direct")) {
            direct = true;
            continue;
        }
        if (!strcmp(a, "--validation")) {
            opt.context.validation = true;
            continue;
        }
        if (!strcmp(a, "--quiet")) {
            quiet = true;
            opt.progress = false;
            continue;
        }
        if (a[0] != '-' || a[1] != '-')
            return bad_arg(a, NULL, "unexpected argument");
        if (!hs_arg_in(a, value_options, sizeof(value_options) / sizeof(value_options[0])))
            return bad_arg(a, NULL, "unknown option");
        if (i + 1 >= argc)
            return bad_arg(a, NULL, "needs a value");
        const char *v = argv[++i];
        uint32_t u;
        double d;
        if (!strcmp(a, "--scene")) {
            opt.scene_path = v;
        } else if (!strcmp(a, "--poses")) {
            opt.poses_path = v;
        } else if (!strcmp(a, "--pose-format")) {
            if (!strcmp(v, "auto"))
                opt.pose_format = HS_POSE_FORMAT_AUTO;
            else if (!strcmp(v, "xrsc"))
                opt.pose_format = HS_POSE_FORMAT_XRSC;
            else if (!strcmp(v, "pred6dof"))
                opt.pose_format = HS_POSE_FORMAT_PRED6DOF;
            else if (!strcmp(v, "360video"))
                opt.pose_format = HS_POSE_FORMAT_360VIDEO;
            else if (!strcmp(v, "librnr"))
                opt.pose_format = HS_POSE_FORMAT_LIBRNR;
            else
                return bad_arg(a, v, "expected auto, xrsc, pred6dof, 360video or librnr");
        } else if (!strcmp(a, "--pose-columns")) {
            pose_columns = v;
        } else if (!strcmp(a, "--pose-time-unit")) {
            pose_time_unit = v;
        } else if (!strcmp(a, "--pose-handedness")) {
            pose_handedness = v;
        } else if (!strcmp(a, "--fov")) {
            if (strcmp(v, "headset") && strcmp(v, "scene"))
                return bad_arg(a, v, "expected headset or scene");
            opt.fov_scene = !strcmp(v, "scene");
        } else if (!strcmp(a, "--start")) {
            if (!hs_parse_f(v, &d) || d < 0)
                return bad_arg(a, v, "expected seconds >= 0");
            opt.start_s = d;
        } else if (!strcmp(a, "--frames")) {
            if (!hs_parse_u32(v, &opt.frames))
                return bad_arg(a, v, "expected a count");
        } else if (!strcmp(a, "--method")) {
            if (xrsc_method_from_name(v, &opt.renderer.method) != XRSC_OK)
                return bad_arg(a, v, "unknown method (xrsc --help lists them)");
        } else if (!strcmp(a, "--taa")) {
            if (!strcmp(v, "default") ||
                xrsc_taa_mode_from_name(v, &opt.renderer.taa.mode) != XRSC_OK)
                return bad_arg(a, v, "expected off, on or pfj23");
        } else if (!strcmp(a, "--isrt-m")) {
            if (!hs_parse_u32(v, &u) || u < 1 || u > 4)
                return bad_arg(a, v, "expected 1..4");
            opt.renderer.isrt.m = u;
        } else if (!strcmp(a, "--taa-alpha")) {
            int r = parse_positive(a, v, 1.0f, &opt.renderer.taa.alpha);
            if (r)
                return r;
        } else if (!strcmp(a, "--blend")) {
            if (xrsc_blend_from_name(v, &opt.renderer.blend) != XRSC_OK)
                return bad_arg(a, v, "unknown blend (none, pfj23, moments)");
            blend_given = true;
        } else if (!strcmp(a, "--blend-r")) {
            if (!hs_parse_f(v, &d) || !(d >= 0.0 && d <= 1.0))
                return bad_arg(a, v, "expected R in [0, 1]");
            opt.renderer.blend_r = (float)d;
        } else if (!strcmp(a, "--spp")) {
            if (!hs_parse_u32(v, &u) || u == 0 || u > 4096)
                return bad_arg(a, v, "expected 1..4096");
            opt.renderer.spp.samples_per_pixel = u;
        } else if (!strcmp(a, "--bounces")) {
            if (!hs_parse_u32(v, &u) || u > 16)
                return bad_arg(a, v, "expected 0..16");
            opt.renderer.spp.max_bounces = u ? u : XRSC_BOUNCES_NONE;
            opt.renderer.samplecache.max_bounces = opt.renderer.spp.max_bounces;
            opt.renderer.hashcache.max_bounces = opt.renderer.spp.max_bounces;
        } else if (!strcmp(a, "--resolution")) {
            unsigned w = 0, h = 0;
            char tail;
            if (sscanf(v, "%ux%u%c", &w, &h, &tail) != 2 || w < 8 || h < 8 || w > 8192 ||
                h > 8192)
                return bad_arg(a, v, "expected WxH, each 8..8192");
            opt.renderer.width = w;
            opt.renderer.height = h;
        } else if (!strcmp(a, "--seed")) {
            if (!hs_parse_u32(v, &opt.renderer.seed))
                return bad_arg(a, v, "expected an unsigned integer");
        } else if (!strcmp(a, "--env")) {
            float r, g, b;
            char tail;
            if (sscanf(v, "%f,%f,%f%c", &r, &g, &b, &tail) != 3 || r < 0 || g < 0 || b < 0)
                return bad_arg(a, v, "expected R,G,B >= 0");
            opt.scene.env_set = true;
            opt.scene.environment[0] = r;
            opt.scene.environment[1] = g;
            opt.scene.environment[2] = b;
        } else if (!strcmp(a, "--device")) {
            opt.context.device = v;
        } else if (!strcmp(a, "--ipd")) {
            if (!hs_parse_f(v, &d) || d < 0 || d > 200)
                return bad_arg(a, v, "expected millimetres 0..200");
            opt.headset.ipd_m = (float)(d * 1e-3);
        } else if (!strcmp(a, "--refresh")) {
            if (!hs_parse_f(v, &d) || d < 1 || d > 1000)
                return bad_arg(a, v, "expected 1..1000 Hz");
            opt.headset.refresh_hz = (float)d;
        } else if (!strcmp(a, "--out")) {
            opt.out_dir = v;
        } else if (!strcmp(a, "--write")) {
            opt.write_eyes = opt.write_sbs = opt.write_linear = false;
            char list[256];
            snprintf(list, sizeof(list), "%s", v);
            for (char *tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
                if (!strcmp(tok, "eyes"))
                    opt.write_eyes = true;
                else if (!strcmp(tok, "sbs"))
                    opt.write_sbs = true;
                else if (!strcmp(tok, "linear"))
                    opt.write_linear = true;
                else if (strcmp(tok, "none") != 0)
                    return bad_arg(a, v, "expected eyes, sbs, linear or none");
            }
        } else if (!strcmp(a, "--exposure")) {
            if (!hs_parse_f(v, &d) || d <= 0)
                return bad_arg(a, v, "expected a positive number");
            opt.exposure = (float)d;
        } else if (!strncmp(a, "--sc-", 5)) {
            int r = parse_samplecache(a, v, &opt.renderer.samplecache);
            if (r)
                return r;
        } else if (!strncmp(a, "--hc-", 5)) {
            int r = parse_hashcache(a, v, &opt.renderer.hashcache);
            if (r)
                return r;
        } else {
            return bad_arg(a, NULL, "unknown option");
        }
    }

    if (pose_columns) {
        xrsc_diag pd = {0};
        if (hs_pose_columns_parse(pose_columns, pose_time_unit, pose_handedness,
                                  &opt.pose_columns, &pd) != XRSC_OK)
            return bad_arg(pd.field, NULL, pd.message);
    } else if (pose_time_unit || pose_handedness) {
        return bad_arg(pose_time_unit ? "--pose-time-unit" : "--pose-handedness", NULL,
                       "needs --pose-columns");
    }
    if (!blend_given)
        opt.renderer.blend = default_blend(opt.renderer.method);
    if (!quiet)
        fprintf(stderr, "xrsc: replaying %s over %s (%s, %ux%u per eye)\n", opt.poses_path,
                opt.scene_path, xrsc_method_name(opt.renderer.method), opt.renderer.width,
                opt.renderer.height);
    hs_replay_stats st;
    xrsc_diag diag = {0};
    xrsc_result res = direct ? hs_replay_run(&opt, &st, &diag) : hs_xr_replay_run(&opt, &st, &diag);
    if (res != XRSC_OK) {
        char msg[1400];
        fprintf(stderr, "xrsc: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        return 1;
    }
    if (!quiet) {
        printf("device: %s\n", st.device);
        printf("method: %s, stereo blend: %s", xrsc_method_name(opt.renderer.method),
               xrsc_blend_name(opt.renderer.blend));
        if (opt.renderer.blend == XRSC_BLEND_MOMENTS)
            printf(", R = %g", (double)opt.renderer.blend_r);
        printf("\n");
        printf("frames: %u  load %.2f s  total %.2f s\n", st.frames, st.load_s, st.total_s);
        printf("render wall time per stereo frame: mean %.2f ms, max %.2f ms\n",
               st.render_ms_mean, st.render_ms_max);
        for (uint32_t p = 0; p < st.pass_count; p++)
            printf("  pass %-12s %.3f ms (GPU timestamps, mean)\n", st.pass_mean[p].name,
                   st.pass_mean[p].gpu_ms);
        if (st.rays_per_frame > 0 && st.render_ms_mean > 0)
            printf("rays per frame: %.0f  (%.2f Mrays/s of wall time)\n", st.rays_per_frame,
                   st.rays_per_frame / (st.render_ms_mean * 1e3));
        if (opt.out_dir)
            printf("output: %s/\n", opt.out_dir);
    }
    return 0;
}
