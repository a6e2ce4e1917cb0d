// SPDX-License-Identifier: MIT
/**
 * @file hs_replay.h
 * @brief The host's frame loop: replays a pose stream through the plugin's public C API.
 *
 * Frame k is predicted to be displayed at t_k = start + k / refresh_hz (a simulated clock).
 * The head pose is interpolated from the stream at t_k, the eye poses follow from the
 * simulated headset's IPD (or, for a stream with recorded eye views such as librnr's `v`
 * records, are those views with their per-eye FOVs: hs_pose_stream_eyes), and both eyes are
 * rendered and written.
 */
#pragma once

#include "hs_pose_stream.h"
#include "hs_view.h"
#include "xrsc/xrsc.h"

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hs_replay_options {
    const char *scene_path;
    const char *poses_path;
    hs_pose_format pose_format;
    /** --pose-columns: when count > 0 the stream is read with these columns (pose_format is
     *  then ignored; through OpenXR the runtime is given a canonical copy). */
    hs_pose_columns pose_columns;
    const char *out_dir;          /**< created if missing; NULL writes nothing */
    xrsc_context_options context;
    xrsc_renderer_options renderer;
    xrsc_scene_options scene;
    xrsc_headset headset;         /**< fill with xrsc_headset_default first (all zero: default) */
    double start_s;               /**< offset into the stream */
    uint32_t frames;              /**< 0: until the stream ends */
    /** --hold-last: frames past the stream's end hold its last pose without the warning
     *  XRSC_WARN_FRAMES_PAST_END (hs_warn_frames_past_end). */
    bool hold_last;
    /** --max-pose-bytes: pose files larger than this are refused (0: 1 GiB,
     *  HS_POSE_DEFAULT_MAX_BYTES; hs_pose_stream.h). */
    uint64_t max_pose_bytes;
    bool no_anchor;               /**< keep the stream's own coordinates */
    /** --fov scene: both eyes get the glTF camera's FOV (yfov, and aspectRatio or else the
     *  eye's width/height) instead of the headset's or the stream's; a scene without a
     *  perspective camera is an error. Direct path only (the OpenXR path refuses it). */
    bool fov_scene;
    /** --frame: anchor at ::hs_view_frame instead of the scene's viewpoint; a scene narrower
     *  than the IPD gets ::hs_frame_ipd_m on the direct path unless frame_keep_ipd. */
    bool frame_bounds;
    bool frame_keep_ipd; /**< --ipd was given: --frame keeps it */
    /** --viewpoint: anchor there instead (zero: the scene's viewpoint; not with --frame). */
    hs_viewpoint viewpoint;
    bool write_eyes;              /**< frame_NNNNN_left.png / _right.png */
    bool write_sbs;               /**< frame_NNNNN_sbs.png */
    bool write_linear;            /**< frame_NNNNN_left.pfm / _right.pfm (linear HDR) */
    /** frame_NNNNN_left.exr / _right.exr: linear RGB and depth as Z (hs_exr.h), written by
     *  the program from the renderer's outputs on both paths (hs_outputs.h). */
    bool write_exr;
    /** --video FILE: the side-by-side stream (as the _sbs.png) encoded by ffmpeg when it is
     *  installed (hs_outputs.h); NULL: none. */
    const char *video_path;
    float exposure;               /**< tone mapping: > 0 fixed; 0 automatic (hs_image.h) */
    bool progress;                /**< show progress on stderr after a few seconds */
    /** --preview (OpenXR path only): the runtime's preview window (XRSC_RT_PREVIEW=1), told
     *  the run's method, blend, R and per-frame timings for its overlay (hs_xr_replay.h). */
    bool preview;
    bool preview_autoclose;        /**< --preview-autoclose: close the window when the run ends */
    const char *preview_reference; /**< --preview-reference DIR: linear frames for its error view */
    /** Optional: called with each frame just before it is rendered (its eye poses and FOVs
     *  in scene space), e.g. for tests; user is passed through. hs_xr_replay_run calls it
     *  after each frame the plugin rendered through OpenXR. */
    void (*on_frame)(void *user, const xrsc_frame *frame);
    void *on_frame_user;
    /** Optional (NULL: never): a flag a signal handler sets (hs_run_catch_signals); once it is
     *  non-zero the run finishes the frame it is on, writes its files whole and returns
     *  XRSC_OK with the frames done so far, the flag's value in stats.stopped_by. */
    const volatile sig_atomic_t *stop;
} hs_replay_options;

typedef struct hs_replay_stats {
    uint32_t frames;
    double render_ms_mean, render_ms_max; /**< wall time of xrsc_renderer_render per frame */
    double total_s;                       /**< whole run including loading and writing */
    double load_s;                        /**< context + scene + stream */
    /** The scene's info right after its load (counts, load_ms and its stages), and the
     *  process's peak resident memory then (getrusage ru_maxrss, KiB): the `load` line. */
    xrsc_scene_info scene;
    long load_peak_rss_kib;
    /** The first frame: the hint it got (HS_HINT_NONE: none) and its background fraction. */
    hs_hint first_frame_hint;
    double first_frame_background;
    uint32_t pass_count;
    xrsc_pass_timing pass_mean[XRSC_MAX_PASSES]; /**< GPU ms per pass, mean over frames */
    double rays_per_frame;
    uint32_t validation_errors; /**< validation-layer errors over the run (0 when it is off) */
    char device[256];
    int stopped_by; /**< the signal that stopped the run early (opt.stop), else 0 */
} hs_replay_stats;

/**
 * Runs the replay. Writes frames.csv (a header, then one row per frame: display time in ns
 * on the simulated clock, lookup kind, timing) into out_dir. out_stats may be NULL. Renderer
 * width/height 0 mean xrsc.h's default (256); a headset left all zero means
 * xrsc_headset_default.
 */
xrsc_result hs_replay_run(const hs_replay_options *opt, hs_replay_stats *out_stats,
                          xrsc_diag *diag);

/**
 * --frame: hs_view_frame with the eyes together (IPD 0): looking down -Z at the scene's
 * bounds, every corner of them inside both eyes' FOVs, their middle at the image's middle.
 */
XrPosef hs_frame_viewpoint(const xrsc_scene_info *info, const XrFovf fov[2]);

/**
 * --fov scene: the symmetric FOV of the scene's camera (tan of half yfov up and down, times
 * the aspect ratio left and right; aspect = the file's aspectRatio, else width/height).
 * Returns false when the scene has no perspective camera with a usable yfov.
 */
bool hs_scene_fov(const xrsc_scene_info *info, uint32_t width, uint32_t height, XrFovf *out);

/** Loads opt's pose stream as both replay paths do: --pose-format or --pose-columns, and the
 *  --max-pose-bytes limit (hs_pose_stream_load_with). */
xrsc_result hs_replay_load_poses(const hs_replay_options *opt, hs_pose_stream **out,
                                 xrsc_diag *diag);

/**
 * --start past the stream's end: XRSC_ERROR_INVALID_ARGUMENT naming the stream's duration
 * (field "--start"); XRSC_OK otherwise. Both replay paths check it before rendering.
 */
xrsc_result hs_check_start(const char *poses_path, double start_s, int64_t duration_ns,
                           xrsc_diag *diag);

/**
 * --frames past the stream's end: frames first..last (inclusive, at period_ns on the simulated
 * clock from --start) whose time is past the stream's duration hold its last pose. Unless
 * opt->hold_last, warns once on stderr with XRSC_WARN_FRAMES_PAST_END naming the stream,
 * its duration from --start and how many frames hold. Returns that count. Both replay paths
 * call it before rendering.
 */
uint32_t hs_warn_frames_past_end(const hs_replay_options *opt, int64_t duration_ns,
                                 double period_ns, uint32_t first, uint32_t last);

/**
 * The first frame's check, both replay paths call it after their first rendered frame: reads
 * both eyes' colour (black: linear value x exposure that the 8-bit PNG rounds to 0) and depth
 * (background: 0), and warns once on stderr with ::hs_first_frame_hint's ID and what to try
 * for this scene (views: the frame's eye poses; info: the scene's). Sets
 * st->first_frame_hint and st->first_frame_background.
 */
void hs_warn_first_frame(const hs_replay_options *opt, xrsc_renderer *r, uint32_t width,
                         uint32_t height, const xrsc_scene_info *info, const xrsc_view views[2],
                         hs_replay_stats *st);

/**
 * Where the stream is anchored: --viewpoint (camera:N from the scene: an error naming
 * --viewpoint when it has no such camera; x,y,z[:yaw]; inside), else --frame's
 * (::hs_view_frame with the eyes ipd_m apart), else the scene's viewpoint.
 */
xrsc_result hs_replay_viewpoint(const hs_replay_options *opt, const xrsc_scene *scene,
                                const xrsc_scene_info *info, const XrFovf fov[2], double ipd_m,
                                XrPosef *out, xrsc_diag *diag);

/** Warns ([narrower-than-ipd]) when the scene is narrower than the headset's IPD, saying
 *  which IPD is used (used_ipd_m: --frame's, hs_frame_ipd_m) or what to give. */
void hs_warn_narrow_scene(const xrsc_scene_info *info, double ipd_m, double used_ipd_m);

/** Fills st->scene and st->load_peak_rss_kib after the scene's load (both replay paths). */
void hs_replay_stats_scene(hs_replay_stats *st, const xrsc_scene *scene);

/**
 * Turns the per-frame sums a run gathered in st (render_ms_mean, rays_per_frame, pass_mean)
 * into means over st->frames; both replay paths (hs_replay_run, hs_xr_replay_run) end with it.
 */
void hs_replay_stats_average(hs_replay_stats *st);
/** Adds frame st->frames's wall time and r's last frame (pass timings: named after the first
 *  frame's; rays) to the sums hs_replay_stats_average divides; passes/out_np: the timings read
 *  (XRSC_MAX_PASSES), for the caller's own records. */
void hs_replay_stats_add(hs_replay_stats *st, xrsc_renderer *r, double render_ms,
                         xrsc_pass_timing passes[XRSC_MAX_PASSES], uint32_t *out_np);

/** `xrsc replay`'s eye size and samples per pixel when no option says otherwise. */
#define HS_REPLAY_DEFAULT_SIZE_PX 256
#define HS_REPLAY_DEFAULT_SPP 2

/**
 * The stereo blend when --blend is not given: the raw-moment blend (R = 0) after the methods
 * that keep per-sample radiance and counts (the sample caches, seed 000 §3.6), none after the
 * others (their moments are those of a few fresh samples, or absent).
 */
xrsc_blend hs_replay_default_blend(xrsc_method method);

/**
 * The temporal filter when --taa is not given: `on` (fixed alpha 0.1) after `samplecache`,
 * chosen by the issue-19 bench table (bench/results/issue19-defaults/: it lowered the
 * temporal difference 3-69x and the stereo discrepancy 1.3-35x on all 10 bundled cases, relMSE
 * on 7); the method's own default (XRSC_TAA_DEFAULT) after the others.
 */
xrsc_taa_mode hs_replay_default_taa(xrsc_method method);

/** The shading rate of the main job's variance-guided shading: 40 % = 0.4 shadings per pixel (0.3
 *  until stop 21; bench/results/issue19-rate/: 40 % lowers relMSE and the temporal difference
 *  on the head turns 1.7x and 3-4x for 0.25 more rays per pixel, still below 1 spp's). */
#define HS_REPLAY_DEFAULT_SHADE_PERCENT 40
#define HS_REPLAY_DEFAULT_SHADE_RATE (HS_REPLAY_DEFAULT_SHADE_PERCENT / 100.0f)
/** HS_REPLAY_DEFAULT_SHADE_PERCENT as a string, for help texts. */
#define HS_REPLAY_DEFAULT_SHADE_PERCENT_STR HS_REPLAY_STR(HS_REPLAY_DEFAULT_SHADE_PERCENT)
#define HS_REPLAY_STR(x) HS_REPLAY_STR_(x)
#define HS_REPLAY_STR_(x) #x

/**
 * The sample cache's shading when --sc-shade / --sc-shade-rate (bench keys shade, shade_rate)
 * are not given: after `samplecache`, variance-guided shading (xrsc_sc_shade
 * XRSC_SC_SHADE_ADAPTIVE_VARIANCE) at HS_REPLAY_DEFAULT_SHADE_RATE, chosen by the issue-19
 * tables (bench/results/issue19-defaults/ chose the mode, at 30 %; issue19-rate/ the rate, see
 * HS_REPLAY_DEFAULT_SHADE_RATE); a mode given without a rate keeps the
 * library's rate (100 %), and after other methods nothing given means the library's own.
 */
void hs_replay_default_shading(xrsc_renderer_options *o, bool shade_given, bool rate_given);

/** Which of the rules of ::hs_replay_default_rules the command line or setting gave. */
typedef struct hs_replay_given {
    bool taa_motion;      /**< --taa-motion (bench key taa_motion) */
    bool blend_instances; /**< --blend-instances (blend_inst) */
    bool moving;          /**< --sc-moving (moving) */
    bool cover;           /**< --sc-cover (cover) */
} hs_replay_given;

/**
 * The main job's rules since stop 22, each where `given` does not name it: after
 * `samplecache`,
 * - TAA's motion rule at edges (XRSC_TAA_MOTION_EDGES) and the stereo blend's instance test
 *   (blend_instance_test): together they take the Cornell light panel's ring out of the ceiling
 *   (bench/results/issue19-cornell/: relMSE 0.33x there and 0.77-0.99x on the other cases at
 *   2 x 96^2, the temporal and stereo figures up to 1.8x and 5.3x but still below `taa`'s on
 *   all 10);
 * - the moving-sample rule (xrsc_samplecache_options.moving; bench/results/issue19-moving2/:
 *   `moving` 0.68x relMSE at 96^2, the other 9 cases byte-identical);
 * - the cover rule (xrsc_samplecache_options.cover: no pixel with a surface stays black for
 *   want of a shaded sample; bench/results/issue19-headset/).
 * Other methods keep the library's (all off).
 */
void hs_replay_default_rules(xrsc_renderer_options *o, hs_replay_given given);

/**
 * The renderer options `xrsc replay` runs when no option is given: the main job (seed 000),
 * the per-eye sample cache with the blend of ::hs_replay_default_blend, the temporal filter of
 * ::hs_replay_default_taa, the shading of ::hs_replay_default_shading and the rules of
 * ::hs_replay_default_rules, at
 * HS_REPLAY_DEFAULT_SIZE_PX with HS_REPLAY_DEFAULT_SPP. The one source of the replay's
 * defaults and of `xrsc bench`'s setting `default` (the product as shipped).
 */
void hs_replay_default_renderer(xrsc_renderer_options *out);

#ifdef __cplusplus
}
#endif
