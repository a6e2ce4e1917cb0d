// SPDX-License-Identifier: MIT
/**
 * @file hs_replay_cmd.c
 * @brief `xrsc [replay]` (hs_replay_cmd.h): replays a head-pose stream over a glTF scene and
 *        writes the stereo result (per-eye and side-by-side PNG, linear PFM, per-frame timing).
 */
#include "hs_anim_args.h"
#include "hs_args.h"
#include "hs_bench.h"
#include "hs_compare_cmd.h"
#include "hs_headset.h"
#include "hs_light_args.h"
#include "hs_metrics_cmd.h"
#include "hs_opt.h"
#include "hs_replay.h"
#include "hs_run.h"
#include "hs_xr_replay.h"
#include "u_diag.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef HS_XR_DEFAULT_MANIFEST
#define HS_XR_DEFAULT_MANIFEST "host_sim/runtime/xrsc_runtime.json"
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

/* What the command line of `xrsc replay` sets beyond hs_replay_options. */
typedef struct main_args {
    hs_replay_options opt;
    bool quiet, direct, overwrite;
    bool blend_given;                             /* --blend: else hs_replay_default_blend(method) */
    bool taa_given;                               /* --taa: else hs_replay_default_taa(method) */
    bool shade_given, shade_rate_given;           /* else hs_replay_default_shading */
    hs_replay_given rules_given;                  /* else hs_replay_default_rules */
    bool size_given, ipd_given, refresh_given;    /* these win over --headset */
    const char *pose_columns, *pose_time_unit, *pose_handedness;
    const char *headset_name, *headsets_path; /* --headset, --headsets */
} main_args;

static int bad_arg(const char *flag, const char *value, const char *why)
{
    return hs_bad_arg("xrsc", flag, value, why);
}

/* hs_opt_enum writes an int: the enums it sets are int-sized. */
_Static_assert(sizeof(xrsc_sc_trace) == sizeof(int) && sizeof(xrsc_sc_shade) == sizeof(int) &&
                   sizeof(xrsc_hc_lod) == sizeof(int) && sizeof(xrsc_sc_vis_refine) == sizeof(int),
               "enum fields set through int");

/* ---- the parsers of options that set more than one field or check more than a range ---- */

#define M(a) ((main_args *)(a)->target)

static int parse_pose_format(const hs_opt_arg *a)
{
    if (!hs_pose_format_from_name(a->value, &M(a)->opt.pose_format))
        return bad_arg(a->opt->name, a->value, "expected auto, xrsc, pred6dof, 360video or librnr");
    return 0;
}

static int parse_fov(const hs_opt_arg *a)
{
    if (strcmp(a->value, "headset") && strcmp(a->value, "scene"))
        return bad_arg(a->opt->name, a->value, "expected headset or scene");
    M(a)->opt.fov_scene = !strcmp(a->value, "scene");
    return 0;
}

static int parse_viewpoint(const hs_opt_arg *a)
{
    xrsc_diag d = {0};
    if (hs_viewpoint_parse(a->value, &M(a)->opt.viewpoint, &d) != XRSC_OK)
        return bad_arg(a->opt->name, a->value, d.message);
    return 0;
}

static int parse_max_pose_bytes(const hs_opt_arg *a)
{
    if (!hs_parse_bytes(a->value, &M(a)->opt.max_pose_bytes))
        return bad_arg(a->opt->name, a->value, "expected a byte count >= 1, e.g. 1G or 500M");
    return 0;
}

static int parse_method(const hs_opt_arg *a)
{
    if (xrsc_method_from_name(a->value, &M(a)->opt.renderer.method) != XRSC_OK)
        return bad_arg(a->opt->name, a->value, "unknown method (xrsc --help lists them)");
    return 0;
}

/* --taa MODE; "default": the method's own (off after samplecache, as before issue 19; what a
 * run.conf without a taa line means, hs_args_spec.record_defaults) */
static int parse_taa(const hs_opt_arg *a)
{
    if (xrsc_taa_mode_from_name(a->value, &M(a)->opt.renderer.taa.mode) != XRSC_OK)
        return bad_arg(a->opt->name, a->value, "expected off, on, pfj23 or default");
    M(a)->taa_given = true;
    return 0;
}

static int parse_taa_history(const hs_opt_arg *a)
{
    if (!strcmp(a->value, "default") ||
        xrsc_taa_history_from_name(a->value, &M(a)->opt.renderer.taa.history) != XRSC_OK)
        return bad_arg(a->opt->name, a->value, "expected bilinear or catmull-rom");
    return 0;
}

/* --taa-motion (xrsc_taa_motion; "default" = off) */
static int parse_taa_motion(const hs_opt_arg *a)
{
    if (xrsc_taa_motion_from_name(a->value, &M(a)->opt.renderer.taa.motion) != XRSC_OK)
        return bad_arg(a->opt->name, a->value, "expected off, on, edges or default");
    M(a)->rules_given.taa_motion = true;
    return 0;
}

/* --sc-moving on|off */
static int parse_sc_moving(const hs_opt_arg *a)
{
    M(a)->rules_given.moving = true;
    return hs_opt_on_off(a);
}

/* --sc-cover on|off */
static int parse_sc_cover(const hs_opt_arg *a)
{
    M(a)->rules_given.cover = true;
    return hs_opt_on_off(a);
}

/* --blend-instances on|off */
static int parse_blend_instances(const hs_opt_arg *a)
{
    M(a)->rules_given.blend_instances = true;
    return hs_opt_on_off(a);
}

static int parse_blend(const hs_opt_arg *a)
{
    if (xrsc_blend_from_name(a->value, &M(a)->opt.renderer.blend) != XRSC_OK)
        return bad_arg(a->opt->name, a->value, "unknown blend (none, pfj23, moments)");
    M(a)->blend_given = true;
    return 0;
}

static int parse_blend_estimate(const hs_opt_arg *a)
{
    if (xrsc_blend_estimate_from_name(a->value, &M(a)->opt.renderer.blend_estimate) != XRSC_OK)
        return bad_arg(a->opt->name, a->value, "unknown estimate (samples, mean)");
    return 0;
}

static int parse_bounces(const hs_opt_arg *a)
{
    xrsc_renderer_options *ro = &M(a)->opt.renderer;
    uint32_t u;
    if (!hs_parse_u32(a->value, &u) || u > 16)
        return bad_arg(a->opt->name, a->value, "expected 0..16");
    ro->spp.max_bounces = u ? u : XRSC_BOUNCES_NONE;
    ro->samplecache.max_bounces = ro->spp.max_bounces;
    ro->hashcache.max_bounces = ro->spp.max_bounces;
    return 0;
}

static int parse_resolution(const hs_opt_arg *a)
{
    unsigned w, h;
    if (!hs_parse_size(a->value, 8, 8192, &w, &h))
        return bad_arg(a->opt->name, a->value, "expected WxH, each 8..8192");
    M(a)->opt.renderer.width = w;
    M(a)->opt.renderer.height = h;
    M(a)->size_given = true;
    return 0;
}

/* --sc-shade-rate P: percent of the pixels -> shadings per pixel. */
static int parse_shade_rate(const hs_opt_arg *a)
{
    int r = hs_opt_positive(a);
    M(a)->opt.renderer.samplecache.shade_rate *= 0.01f;
    M(a)->shade_rate_given = true;
    return r;
}

/* --sc-shade S */
static int parse_shade(const hs_opt_arg *a)
{
    M(a)->shade_given = true;
    return hs_opt_enum(a);
}

/* on | off into a field that means off ("no_..."). */
static int parse_on_means_false(const hs_opt_arg *a)
{
    bool on;
    if (!hs_parse_on_off(a->value, &on))
        return bad_arg(a->opt->name, a->value, "expected on or off");
    *(bool *)a->field = !on;
    return 0;
}

static int parse_env(const hs_opt_arg *a)
{
    if (!hs_parse_rgb(a->value, M(a)->opt.scene.environment))
        return bad_arg(a->opt->name, a->value, "expected R,G,B >= 0");
    M(a)->opt.scene.env_set = true;
    return 0;
}

static int parse_light(const hs_opt_arg *a)
{
    int r = hs_light_parse("xrsc", a->opt->name, a->value, &M(a)->opt.scene);
    return r > 0 ? r : 0;
}

static int parse_animation(const hs_opt_arg *a)
{
    return hs_anim_parse("xrsc", HS_ANIM_FLAG, a->value, &M(a)->opt.scene);
}

static int parse_ipd(const hs_opt_arg *a)
{
    double d;
    if (!hs_parse_f(a->value, &d) || d < 0 || d > 200)
        return bad_arg(a->opt->name, a->value, "expected millimetres 0..200");
    M(a)->opt.headset.ipd_m = (float)(d * 1e-3);
    M(a)->ipd_given = true;
    return 0;
}

static int parse_refresh(const hs_opt_arg *a)
{
    double d;
    if (!hs_parse_f(a->value, &d) || d < 1 || d > 1000)
        return bad_arg(a->opt->name, a->value, "expected 1..1000 Hz");
    M(a)->opt.headset.refresh_hz = (float)d;
    M(a)->refresh_given = true;
    return 0;
}

static int parse_preview(const hs_opt_arg *a)
{
    M(a)->opt.preview = true;
    M(a)->opt.preview_autoclose |= !strcmp(a->opt->name, "--preview-autoclose");
    return 0;
}

static int parse_preview_reference(const hs_opt_arg *a)
{
    M(a)->opt.preview_reference = a->value;
    M(a)->opt.preview = true;
    return 0;
}

static int parse_quiet(const hs_opt_arg *a)
{
    M(a)->quiet = true;
    M(a)->opt.progress = false;
    return 0;
}

static int parse_write(const hs_opt_arg *a)
{
    hs_replay_options *opt = &M(a)->opt;
    opt->write_eyes = opt->write_sbs = opt->write_linear = opt->write_exr = false;
    char list[256];
    snprintf(list, sizeof(list), "%s", a->value);
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
            return bad_arg(a->opt->name, a->value, "expected eyes, sbs, linear, exr or none");
    }
    return 0;
}

static int parse_exposure(const hs_opt_arg *a)
{
    double d;
    if (!strcmp(a->value, "auto"))
        M(a)->opt.exposure = 0.0f; /* automatic (hs_image.h) */
    else if (!hs_parse_f(a->value, &d) || d <= 0)
        return bad_arg(a->opt->name, a->value, "expected a positive number or auto");
    else
        M(a)->opt.exposure = (float)d;
    return 0;
}

/* ---- the table: every option of `xrsc replay` once, in --help's order ---- */

#define STR_(x) #x
#define STR(x) STR_(x)
#define F(field) offsetof(main_args, field)
#define RO(field) offsetof(main_args, opt.renderer.field)
#define SC(field) offsetof(main_args, opt.renderer.samplecache.field)
#define HC(field) offsetof(main_args, opt.renderer.hashcache.field)
#define NUM(lo, hi, why) (&(const hs_opt_num){lo, hi, why})
#define TEXT(s) {NULL, NULL, s, NULL, 0, NULL}

static const hs_opt_name k_sc_trace[] = {
    {"single", XRSC_SC_TRACE_SINGLE, "expected single, multi or adaptive"},
    {"multi", XRSC_SC_TRACE_MULTI, NULL}, {"adaptive", XRSC_SC_TRACE_ADAPTIVE, NULL}, {NULL, 0, NULL}};
static const hs_opt_name k_sc_reproject[] = {
    {"1pass", XRSC_SC_REPROJECT_1PASS, "expected 1pass or 2pass"},
    {"2pass", XRSC_SC_REPROJECT_2PASS, NULL}, {NULL, 0, NULL}};
static const hs_opt_name k_sc_shade[] = {
    {"uniform", XRSC_SC_SHADE_UNIFORM, "expected uniform, adaptive or adaptive-variance"},
    {"adaptive", XRSC_SC_SHADE_ADAPTIVE, NULL},
    {"adaptive-variance", XRSC_SC_SHADE_ADAPTIVE_VARIANCE, NULL}, {NULL, 0, NULL}};
static const hs_opt_name k_sc_alpha[] = {
    {"clamped", XRSC_SC_ALPHA_CLAMPED, "expected clamped or fixed"},
    {"fixed", XRSC_SC_ALPHA_FIXED, NULL}, {NULL, 0, NULL}};
static const hs_opt_name k_sc_refine[] = {
    {"adaptive", XRSC_SC_VIS_REFINE_ADAPTIVE, "expected adaptive, strict or none"},
    {"strict", XRSC_SC_VIS_REFINE_STRICT, NULL}, {"none", XRSC_SC_VIS_REFINE_NONE, NULL},
    {NULL, 0, NULL}};
static const hs_opt_name k_hc_lod[] = {
    {"distance", XRSC_HC_LOD_DISTANCE, "expected distance or distance-normal"},
    {"distance-normal", XRSC_HC_LOD_DISTANCE_NORMAL, NULL}, {NULL, 0, NULL}};

static const hs_opt k_replay_opts[] = {
    TEXT("\nInput:\n"),
    {"--scene", "PATH", "glTF scene (.gltf/.glb)        [scenes/cornell.gltf]", NULL,
     F(opt.scene_path), NULL},
    {"--poses", "PATH", "pose stream                    [poses/orbit_cornell.xrpose]", NULL,
     F(opt.poses_path), NULL},
    {"--pose-format", "F", "auto | xrsc | pred6dof | 360video | librnr   [auto]",
     parse_pose_format, 0, NULL},
    {"--pose-columns", "L",
     "read a CSV/TSV export by columns, e.g. t,x,y,z,qx,qy,qz,qw (any\n"
     "order; _ skips a column; delimiter, header and a leading index\n"
     "column are detected; poses/README.md, \"Import by columns\")",
     NULL, F(pose_columns), NULL},
    {"--pose-time-unit", "U", "s | ms | us | ns | ticks (with --pose-columns) [s]", NULL,
     F(pose_time_unit), NULL},
    {"--pose-handedness", "H", "right | left-unity (with --pose-columns) [right]", NULL,
     F(pose_handedness), NULL},
    {"--no-anchor", NULL,
     "use the stream's coordinates as they are (default: its first pose\n"
     "is placed at the scene's viewpoint)",
     NULL, F(opt.no_anchor), NULL},
    {"--start", "S", "start S seconds into the stream (past its end: an error) [0]",
     hs_opt_double, F(opt.start_s), NUM(0, INFINITY, "expected seconds >= 0")},
    {"--fov", "F",
     "headset | scene: scene = both eyes use the glTF camera's yfov and\n"
     "aspect ratio (both paths) [headset]",
     parse_fov, 0, NULL},
    {"--frame", NULL,
     "place the viewpoint so the scene's bounds fill the view (default:\n"
     "the glTF camera, else in front of the bounds looking down -Z); a\n"
     "scene narrower than the IPD gets an IPD of a tenth of the viewing\n"
     "distance (--direct, unless --ipd is given)",
     NULL, F(opt.frame_bounds), NULL},
    {"--viewpoint", "V",
     "camera:N (the scene's N-th camera, from 0) | x,y,z[:yaw] (metres;\n"
     "degrees about +Y, 0 looks down -Z) | inside (the bounds' centre):\n"
     "where the stream's first pose is placed (not with --frame)",
     parse_viewpoint, 0, NULL},
    {"--frames", "N",
     "render N frames (0 = until the stream ends) [0]; frames past the\n"
     "stream's end hold its last pose, with a warning\n"
     "(XRSC_WARN_FRAMES_PAST_END) naming how many",
     hs_opt_u32, F(opt.frames), NUM(0, UINT32_MAX, "expected a count")},
    {"--hold-last", NULL, "hold the last pose past the stream's end without that warning", NULL,
     F(opt.hold_last), NULL},
    {"--max-pose-bytes", "N", "refuse pose files larger than N bytes (suffix K, M or G) [1G]",
     parse_max_pose_bytes, 0, NULL},

    TEXT("\nRendering:\n"),
    {"--method", "M",
     "spp | primary | samplecache | taa | hashcache | hybrid | isrt\n"
     "[samplecache: the sample cache of seed 000]",
     parse_method, 0, NULL},
    {"--spp", "N", "samples per pixel per frame    [" STR(DEFAULT_SPP) "]", hs_opt_u32,
     RO(spp.samples_per_pixel), NUM(1, 4096, "expected 1..4096")},
    {"--bounces", "N", "bounces after the first hit    [3]", parse_bounces, 0, NULL},
    {"--resolution", "WxH",
     "render size per eye            [" STR(DEFAULT_WIDTH) "x" STR(DEFAULT_HEIGHT) "]",
     parse_resolution, 0, NULL},
    {"--seed", "N", "random seed                    [0]", hs_opt_u32, RO(seed),
     NUM(0, UINT32_MAX, "expected an unsigned integer")},
    {"--env", "R,G,B",
     "constant environment radiance (default: the scene's)\n"
     "(a scene without one and without a directional light: the built-in\n"
     "studio environment, emissive materials notwithstanding; 1,1,1 is\n"
     "the grey of earlier versions)",
     parse_env, 0, NULL},
    HS_LIGHT_OPTS(parse_light),
    {HS_ANIM_FLAG, "A",
     "the clip that plays, looping at the display time: first (the file's\n"
     "first clip) | all (every clip at once) | none | a clip's name or\n"
     "index (xrsc scene info FILE lists them) [first]",
     parse_animation, 0, NULL},
    {"--device", "D", "cpu | gpu | index | name part  [$XRSC_DEVICE, else a GPU, else lavapipe]",
     NULL, F(opt.context.device), NULL},
    {"--validation", NULL, "enable the Vulkan validation layer, synchronization checks included",
     NULL, F(opt.context.validation), NULL},

    TEXT("\nSample cache (--method samplecache; seed 000 section 3, defaults of section 4):\n"),
    {"--sc-slots", "N", "slots per pixel, 1..16         [12]", hs_opt_u32, SC(slots),
     NUM(1, 16, "expected 1..16")},
    {"--sc-target", "X", "target samples per pixel       [4]", hs_opt_positive, SC(n_target),
     NUM(0, 16, NULL)},
    {"--sc-delta", "X", "density tolerance              [1]", hs_opt_positive, SC(delta),
     NUM(0, 16, NULL)},
    {"--sc-eps0", "X", "retrace tolerance (relative)   [0.001]", hs_opt_positive, SC(eps0),
     NUM(0, 1, NULL)},
    {"--sc-eps1", "X", "edge test epsilon (Eq. 2)      [0.005]", hs_opt_positive, SC(eps1),
     NUM(0, 1, NULL)},
    {"--sc-block", "N", "base-rate block size           [4]", hs_opt_u32, SC(block),
     NUM(1, 64, "expected 1..64")},
    {"--sc-trace", "T", "single | multi | adaptive      [adaptive]", hs_opt_enum, SC(trace),
     k_sc_trace},
    {"--sc-reproject", "R", "1pass | 2pass                  [1pass]", hs_opt_enum,
     SC(reproject), k_sc_reproject},
    {"--sc-shading-cache", "on|off", "keep radiance between frames   [on]",
     parse_on_means_false, SC(no_shading_cache), NULL},
    {"--sc-shade", "S",
     "uniform | adaptive | adaptive-variance (importance = the\n"
     "relative variance of each sample's mean)\n"
     "[adaptive-variance after samplecache, else uniform]",
     parse_shade, SC(shade), k_sc_shade},
    {"--sc-shade-rate", "P",
     "adaptive shading rate, percent of the pixels [" HS_REPLAY_DEFAULT_SHADE_PERCENT_STR " with the\n"
     "default shading, 100 with --sc-shade]",
     parse_shade_rate, SC(shade_rate), NUM(0, 1600, NULL)},
    {"--sc-alpha", "A", "clamped | fixed (temporal blend, App. C) [clamped]", hs_opt_enum,
     SC(alpha), k_sc_alpha},
    {"--sc-alpha-fixed", "X", "alpha of --sc-alpha fixed      [0.1]", hs_opt_positive,
     SC(alpha_fixed), NUM(0, 1, NULL)},
    {"--sc-cross-eye", "on|off",
     "each eye's view-independent samples also serve the other\n"
     "eye, traced and shaded once for both (beyond seed 000) [off]",
     hs_opt_on_off, SC(cross_eye), NULL},
    {"--sc-moving", "on|off",
     "moving-sample rule: samples on a turning instance are shaded\n"
     "more often, with a short history on turning faces (issue 19)\n"
     "[on after samplecache, else off]",
     parse_sc_moving, SC(moving), NULL},
    {"--sc-cover", "on|off",
     "cover rule (variance-guided shading): a pixel with surface samples\n"
     "but none shaded yet shades one, so it never shows black (issue 19)\n"
     "[on after samplecache, else off]",
     parse_sc_cover, SC(cover), NULL},
    {"--sc-stratify", "on|off",
     "new samples through the emptiest strata of their pixel\n"
     "(issue 19, beyond seed 000; bench/results/issue19-edges/) [off]",
     hs_opt_on_off, SC(stratify), NULL},
    {"--sc-visibility-cache", "on|off",
     "shadow visibility cache of the shading pass's light\n"
     "samples at the first hit (seed 002, AQVC) [off]",
     hs_opt_on_off, SC(visibility.enabled), NULL},
    {"--sc-visibility-tolerance", "C", "its error threshold C_E, pixels (seed 002 Eq. 3, 7) [4]",
     hs_opt_positive, SC(visibility.error_px), NUM(0, 1024, NULL)},
    {"--sc-visibility-refine", "R",
     "adaptive | strict | none: Alg. 2, zero refinement error\n"
     "tolerance (trace unless all 8 neighbours agree), no refinement\n"
     "[adaptive]",
     hs_opt_enum, SC(visibility.refine), k_sc_refine},
    {"--isrt-m", "N",
     "--method isrt: M x M fixed sub-pixel slots, 1..4 [2] (interactive\n"
     "stable ray tracing's layout, seed 000 Fig. 10; the --sc-* shading and\n"
     "--sc-trace options apply, slots/target/delta/reproject do not)",
     hs_opt_u32, RO(isrt.m), NUM(1, 4, "expected 1..4")},

    TEXT("\nHash cache (--method hashcache, and hybrid's radiance; seed 000 section 4):\n"),
    {"--hc-table", "N", "table entries, 16..2^27 (24 B each) [4194304]", hs_opt_u32,
     HC(table_entries), NUM(16, 1u << 27, "expected 16..134217728")},
    {"--hc-lod", "L", "distance | distance-normal (voxel LoD; Fig. 9) [distance]", hs_opt_enum,
     HC(lod), k_hc_lod},
    {"--hc-voxel-scale", "X", "voxel edge / pixel footprint, rounded down to 2^k m [0.5]",
     hs_opt_positive, HC(voxel_scale), NUM(0, 1024, NULL)},
    {"--hc-max-age", "N", "frames an entry lives unaccessed before it may be overwritten [64]",
     hs_opt_u32, HC(max_age), NUM(1, UINT32_MAX, "expected frames >= 1")},
    {"--hc-voxel-jitter", "on|off", "jitter the lookup within +-1/2 voxel (BFK18) [on]",
     parse_on_means_false, HC(no_voxel_jitter), NULL},

    TEXT("\nStereo blend (after reconstruction, before submission; seed 000 section 3.6):\n"),
    {"--blend", "B",
     "none | pfj23 | moments  [moments for the sample caches\n"
     "(samplecache, isrt, hybrid), else none]",
     parse_blend, 0, NULL},
    {"--blend-r", "R", "sharpness R in [0, 1] of moments (0: lowest error, Fig. 15) [0]",
     hs_opt_float, RO(blend_r), NUM(0, 1, "expected R in [0, 1]")},
    {"--blend-estimate", "E",
     "samples | mean: the variances moments uses, the spread of the\n"
     "samples (Eq. 5 as printed) or of the pixel's mean [samples]",
     parse_blend_estimate, 0, NULL},
    {"--blend-instances", "on|off",
     "the blend's taps must also show the pixel's instance (hit id), not\n"
     "only its depth within 5 % [on after samplecache, else off]",
     parse_blend_instances, RO(blend_instance_test), NULL},

    TEXT("\nTemporal antialiasing (after reconstruction, before the stereo blend; seed 000 "
         "section 5.1):\n"),
    {"--taa", "T", "off | on | pfj23 | default (the method's own)  [on for samplecache\n"
     "and taa, pfj23 for hashcache and hybrid, else off]",
     parse_taa, 0, NULL},
    {"--taa-alpha", "X", "weight of the current frame with --taa on [0.1]", hs_opt_positive,
     RO(taa.alpha), NUM(0, 1, NULL)},
    {"--taa-history", "F",
     "bilinear | catmull-rom: how the TAA pass resamples its reprojected\n"
     "history (catmull-rom keeps texture sharper under motion) [bilinear]",
     parse_taa_history, 0, NULL},
    {"--taa-motion", "M",
     "off | on | edges | default: with --taa on, raise the current frame's\n"
     "weight with the blur of resampling the history under sub-pixel motion\n"
     "(to 0.5 at 0.25 px^2; lower relMSE, higher temporal and stereo\n"
     "differences); edges: only on the dark side of an edge between surfaces\n"
     "[edges after samplecache, else off]",
     parse_taa_motion, 0, NULL},

    TEXT("\nOpenXR (the default path):\n"
         "  The plugin runs as an OpenXR application (XR_KHR_vulkan_enable2) on the runtime that\n"
         "  XR_RUNTIME_JSON names, or, when it is unset, on this build's host_sim runtime\n"
         "  (" HS_XR_DEFAULT_MANIFEST_TEXT "); the runtime replays the poses and writes\n"
         "  the frames it is given (--start, --ipd, --device, ... reach it as XRSC_RT_*\n"
         "  variables; host_sim/runtime/README.md). --pose-format other than auto needs\n"
         "  --direct unless the runtime detects it.\n"),
    {"--preview", NULL,
     "show the run in the runtime's preview window (as XRSC_RT_PREVIEW=1):\n"
     "overlay with frame, time, ms, method, blend, R; keys V/1/2/3 views,\n"
     "D depth-compensated stereo difference, E error vs. the reference,\n"
     "Left/Right step through recent frames, O overlay, Esc/Q quit; it\n"
     "stays open after the last frame until closed (needs DISPLAY)",
     parse_preview, 0, NULL},
    {"--preview-reference", "DIR", "linear frames (xrsc replay --write linear) for the E view",
     parse_preview_reference, 0, NULL},
    {"--preview-autoclose", NULL, "close the window when the run ends (scripts, tests)",
     parse_preview, 0, NULL},
    {"--direct", NULL, "render in-process without OpenXR (tests, benchmarks)", NULL, F(direct),
     NULL},

    TEXT("\nSimulated headset:\n"),
    {"--headset", "NAME",
     "a headset profile: per-eye resolution, refresh rate, IPD and\n"
     "asymmetric per-eye FOV (quest3, quest2, index, vision-pro, ...;\n"
     "--headset list shows them and their sources); --resolution, --ipd,\n"
     "--refresh given too win over the profile's  [a Quest-like default]",
     NULL, F(headset_name), NULL},
    {"--headsets", "FILE", "read the profiles from FILE (format: host_sim/headsets.txt)", NULL,
     F(headsets_path), NULL},
    {"--ipd", "MM", "interpupillary distance in mm  [63]", parse_ipd, 0, NULL},
    {"--refresh", "HZ", "display refresh rate           [90]", parse_refresh, 0, NULL},

    TEXT("\nOutput:\n"),
    {"--out", "DIR", "output folder                  [" DEFAULT_OUT "]", NULL, F(opt.out_dir),
     NULL},
    {"--write", "LIST",
     "any of eyes,sbs,linear,exr,none [eyes,sbs]; exr: OpenEXR float\n"
     "R,G,B + depth Z (m at the pixel centre, 0 = no hit) per eye,\n"
     "frame_NNNNN_left/right.exr (scored by xrsc metrics --stereo)",
     parse_write, 0, NULL},
    {"--video", "FILE",
     "the side-by-side stream as a video through ffmpeg at the refresh\n"
     "rate (e.g. out.mp4), when ffmpeg is installed (else a warning)",
     NULL, F(opt.video_path), NULL},
    {"--exposure", "X",
     "tone-mapping exposure, or auto: middle grey at the stereo frame's\n"
     "log-average luminance, smoothed over frames [auto]",
     parse_exposure, 0, NULL},
    {"--overwrite", NULL,
     "replace the earlier run in --out: its files (frame_*.png/pfm/exr,\n"
     "frames.csv, views.csv, run.json, run.conf) are removed first,\n"
     "others kept; without it a folder holding a run is refused (exit 2)",
     NULL, F(overwrite), NULL},
    {"--quiet", NULL, "errors only: no progress, summary, warnings or runtime info lines",
     parse_quiet, 0, NULL},
    TEXT("  Each run writes run.json into --out (command line, settings, device, version, start\n"
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
         "  -h, --help          this help\n"),
};
#define REPLAY_OPT_COUNT (sizeof(k_replay_opts) / sizeof(k_replay_opts[0]))

static void usage(FILE *f)
{
    fprintf(f,
"usage: xrsc [replay] [options]\n"
"       xrsc metrics --ref DIR --test DIR [options]   (image metrics; xrsc metrics --help)\n"
"       xrsc compare A B [options]  (A/B images and metrics of two runs; xrsc compare --help)\n"
"       xrsc bench [options]        (speed vs. accuracy of methods; xrsc bench --help)\n"
"       xrsc poses stats [--fastest S] FILE   (pose stream speed; xrsc poses --help)\n"
"       xrsc sweep plan|run|merge FILE   (a bench split into units; xrsc sweep --help)\n"
"       xrsc scene info [--json] FILE        (what a glTF file holds; xrsc scene --help)\n"
"       xrsc version | --version   (program, Vulkan loader and OpenXR versions)\n"
"\n"
"Replays a recorded head-pose stream over a glTF 2.0 scene, ray traces both eyes with\n"
"Vulkan and writes the stereo result: per-eye and side-by-side PNG (tone-mapped), linear\n"
"PFM (optional) and frames.csv (per-frame timing with --direct; through OpenXR the\n"
"runtime's log of display time, stream time and head pose), and views.csv (each frame's\n"
"eye poses, FOVs and sizes, both paths; README.md, \"views.csv\").\n");
    hs_opt_print_help(f, k_replay_opts, REPLAY_OPT_COUNT);
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
    if (opt->renderer.blend != XRSC_BLEND_NONE && opt->renderer.blend_instance_test)
        printf(", instance test");
    xrsc_taa_mode taa = xrsc_taa_mode_resolve(opt->renderer.method, opt->renderer.taa.mode);
    printf(", temporal filter: %s", xrsc_taa_mode_name(taa));
    if (taa == XRSC_TAA_ON && opt->renderer.taa.alpha > 0) /* given; else the plugin's */
        printf(" (alpha %g)", (double)opt->renderer.taa.alpha);
    if (taa == XRSC_TAA_ON && opt->renderer.taa.motion == XRSC_TAA_MOTION_ON)
        printf(", motion rule");
    if (taa == XRSC_TAA_ON && opt->renderer.taa.motion == XRSC_TAA_MOTION_EDGES)
        printf(", motion rule at edges");
    const xrsc_samplecache_options *sc = &opt->renderer.samplecache;
    if (opt->renderer.method == XRSC_METHOD_SAMPLECACHE || opt->renderer.method == XRSC_METHOD_ISRT) {
        const char *shade = hs_opt_enum_name(k_sc_shade, (int)sc->shade);
        printf(", shading: %s", shade ? shade : "uniform");
        if (sc->shade != XRSC_SC_SHADE_DEFAULT && sc->shade != XRSC_SC_SHADE_UNIFORM)
            printf(" %g %%", (double)(sc->shade_rate > 0.0f ? sc->shade_rate : 1.0f) * 100.0);
        if (sc->moving)
            printf(", moving-sample rule");
        if (sc->cover && sc->shade == XRSC_SC_SHADE_ADAPTIVE_VARIANCE)
            printf(", cover rule");
    }
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
    if (si->clip_count > 0 && si->clip_playing >= 0)
        printf("animation: clip %d of %u, %.2f s, looping\n", si->clip_playing, si->clip_count,
               (double)si->animation_duration_s);
    else if (si->clip_count > 0)
        printf("animation: %s of %u clips\n",
               si->clip_playing == XRSC_CLIP_ALL ? "all" : "none", si->clip_count);
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
 * 0, 1 (failed), 2 (the folder holds a run), 3 (validation errors), 128 + signal (stopped). */
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
    if (rc == 0 && st.validation_errors > 0)
        rc = HS_EXIT_VALIDATION;
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
    if (!m->taa_given)
        opt->renderer.taa.mode = hs_replay_default_taa(opt->renderer.method);
    hs_replay_default_shading(&opt->renderer, m->shade_given, m->shade_rate_given);
    hs_replay_default_rules(&opt->renderer, m->rules_given);
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
static int run_with_record(main_args *m, const hs_args *args, const char *const *value_options,
                           size_t value_count, hs_run_info *run)
{
    hs_replay_options *opt = &m->opt;
    char res_s[32], spp_s[16], ipd_s[32], refresh_s[32], rate_buf[32];
    snprintf(res_s, sizeof(res_s), "%ux%u", opt->renderer.width, opt->renderer.height);
    snprintf(spp_s, sizeof(spp_s), "%u", opt->renderer.spp.samples_per_pixel);
    snprintf(ipd_s, sizeof(ipd_s), "%g", (double)opt->headset.ipd_m * 1e3);
    snprintf(refresh_s, sizeof(refresh_s), "%g", (double)opt->headset.refresh_hz);
    /* the shading recorded as typed: a run.conf names it, so a later default cannot change it */
    const xrsc_samplecache_options *sc = &opt->renderer.samplecache;
    const char *shade_s = hs_opt_enum_name(k_sc_shade, (int)sc->shade);
    snprintf(rate_buf, sizeof(rate_buf), "%g", (double)sc->shade_rate * 100.0);
    const char *rate_s = sc->shade_rate > 0.0f ? rate_buf : NULL;
    const hs_run_setting defaults[] = {
        {"--scene", opt->scene_path},   {"--poses", opt->poses_path},
        {"--pose-format", "auto"},      {"--start", "0"},
        {"--frames", "0"},              {"--fov", "headset"},
        {"--max-pose-bytes", "1G"},
        {"--method", xrsc_method_name(opt->renderer.method)},
        {"--blend", xrsc_blend_name(opt->renderer.blend)},
        {"--blend-r", "0"},             {"--blend-estimate", "samples"},
        {"--taa", xrsc_taa_mode_name(xrsc_taa_mode_resolve(opt->renderer.method,
                                                           opt->renderer.taa.mode))},
        {"--sc-shade", shade_s},        {"--sc-shade-rate", rate_s},
        {"--taa-motion", xrsc_taa_motion_name(opt->renderer.taa.motion)},
        {"--blend-instances", opt->renderer.blend_instance_test ? "on" : "off"},
        {"--sc-moving", opt->renderer.samplecache.moving ? "on" : "off"},
        {"--sc-cover", opt->renderer.samplecache.cover ? "on" : "off"},
        {"--spp", spp_s},
        {"--resolution", res_s},        {"--seed", "0"},
        {"--ipd", ipd_s},               {"--refresh", refresh_s},
        {"--out", opt->out_dir},        {"--write", "eyes,sbs"},
        {"--exposure", "auto"},
        {HS_ANIM_FLAG, HS_ANIM_DEFAULT},
    };
    run->args_argc = args->argc;
    run->args_argv = args->argv;
    run->value_options = value_options;
    run->value_count = value_count;
    run->defaults = defaults;
    run->default_count = sizeof(defaults) / sizeof(defaults[0]);
    run->not_settings = not_settings;
    run->not_settings_count = sizeof(not_settings) / sizeof(not_settings[0]);
    run->out_dir = opt->out_dir;
    hs_run_info_start(run);
    return run_recorded(opt, m->direct, m->overwrite, m->quiet, run);
}

int hs_replay_main(int argc, char **argv)
{
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
    const char *value_options[HS_OPT_MAX];
    size_t value_count = hs_opt_value_names(k_replay_opts, REPLAY_OPT_COUNT, value_options,
                                            HS_OPT_MAX);
    /* what a run.conf without these lines ran (older builds did not name them): the
     * library's own temporal filter and uniform shading (the defaults before issue 19) */
    static const char *const record_defaults[] = {"--taa", "default", "--sc-shade", "uniform",
                                                  "--taa-motion", "off", "--blend-instances", "off",
                                                  "--sc-moving", "off", "--sc-cover", "off"};
    const hs_args_spec spec = {.cmd = "xrsc", .value_options = value_options,
                               .value_count = value_count, .config = true,
                               .record_defaults = record_defaults,
                               .record_default_count =
                                   sizeof(record_defaults) / sizeof(record_defaults[0])};
    int r = hs_args_prepare(&args, &spec, argc, argv);
    if (r)
        return r;
    int first = args.argc > 1 && !strcmp(args.argv[1], "replay") ? 2 : 1;
    r = hs_opt_parse("xrsc", k_replay_opts, REPLAY_OPT_COUNT, args.argc, args.argv, first, &m);
    if (r == HS_OPT_HELP) {
        usage(stdout);
        return 0;
    }
    if (r != HS_ARG_NEXT)
        return r;
    if ((r = finish_args(&m)) != HS_ARG_NEXT)
        return r;
    return run_with_record(&m, &args, value_options, value_count, &run);
}
