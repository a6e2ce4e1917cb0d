// SPDX-License-Identifier: MIT
/**
 * @file xrsc.h
 * @brief The public C API of libxrsc: a Vulkan context, scenes, and per-eye renderers.
 *
 * Thread rules: one context, its scenes and renderers are used from one thread at a time.
 * Ownership: every *_create / *_load has a *_destroy taking T ** that accepts NULL and sets
 * the pointer to NULL. Options are zero-initialised structs; zero fields mean the documented
 * defaults.
 */
#pragma once

#include "xrsc/result.h"
#include "xrsc/xrsc_math.h"

#include <openxr/openxr.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct xrsc_context xrsc_context;
typedef struct xrsc_scene xrsc_scene;
typedef struct xrsc_renderer xrsc_renderer;

/**
 * Context options.
 * - device: which Vulkan device to use. NULL/"": the environment variable XRSC_DEVICE if set,
 *   else the first non-CPU device with what xrsc needs (Vulkan 1.3, ray-tracing pipelines),
 *   else the first such CPU device (lavapipe, llvmpipe). "cpu" picks lavapipe, "gpu" the
 *   first non-CPU device, a number picks that physical-device index, any other text the first
 *   device whose name contains it, ignoring case; of several matches the first with what xrsc
 *   needs (plugin/src/util/u_device.h). A selector that matches no device is
 *   XRSC_ERROR_DEVICE_NOT_FOUND, one whose matches all lack ray tracing
 *   XRSC_ERROR_NO_RAY_TRACING_DEVICE.
 * - validation: enable VK_LAYER_KHRONOS_validation, with its synchronization validation when
 *   the layer offers VK_EXT_validation_features, and count its errors, synchronization hazards
 *   included (also enabled when the environment variable XRSC_VALIDATION=1).
 */
typedef struct xrsc_context_options {
    const char *device;
    bool validation;
} xrsc_context_options;

xrsc_result xrsc_context_create(const xrsc_context_options *options, xrsc_context **out_ctx,
                                xrsc_diag *out_diag);
void xrsc_context_destroy(xrsc_context **ctx);
/** The selected device's name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)". */
const char *xrsc_context_device_name(const xrsc_context *ctx);
/** True when the selected device is a CPU implementation (lavapipe). */
bool xrsc_context_is_cpu(const xrsc_context *ctx);
/** Validation-layer messages of severity ERROR seen so far (0 when validation is off). */
uint32_t xrsc_context_validation_errors(const xrsc_context *ctx);

/**
 * Scene options. environment: see sc_load_options (constant environment radiance override
 * when env_set; without it and without extras.xrsc_environment a scene with no directional
 * light gets the built-in studio environment map, emissive materials and point/spot lights notwithstanding: a sky
 * gradient with a soft warm key light and a dimmer fill, normalised so that a white
 * Lambertian plane facing up reflects a radiance of 0.9; env_intensity, env_rotation_deg and
 * env_no_importance apply to it. env_set with (1, 1, 1) gives the grey of earlier versions).
 * keep_triangle_order: skip the Morton sort of each mesh's triangles done before the BLAS
 * build (for benchmarks of its effect; primitive ids then follow the file).
 * Environment map and sky (these replace the constant environment; env_map_path wins):
 * - env_map_path: an equirectangular Radiance .hdr or OpenEXR .exr (R, G, B of its first
 *   part, alpha ignored; recognised by its magic; centre of the image = -Z, top = +Y),
 *   importance-sampled by luminance; env_intensity scales it (or the sky's sun and sky;
 *   0 means 1);
 *   env_rotation_deg turns it (or the sky) about +Y, counter-clockwise seen from above.
 * - sky: the Preetham sun and sky (seed 000 §5.1); sky_turbidity (0 means 3, range 1.7..10);
 *   sun_direction (towards the sun, y >= 0) when sun_direction_set, else the file's
 *   directional light's, else (0.5, 0.707, 0.5) normalised. The sky's sun is a disk of
 *   0.53 degrees that replaces the file's directional lights (point and spot lights stay).
 * - env_no_importance: for tests and benchmarks, the map is reached by escaping BSDF rays
 *   only (no next-event estimation of it).
 * Animation (issue 21): animation names the clip (glTF `animations[i]`) whose channels play,
 * looping over its duration at the frame's display time (xrsc_frame.display_time_ns, the same
 * on the direct and the OpenXR path): NULL, "" or "first" = the first clip (none when the file
 * has none); "all" = every clip's channels at once, looping over the longest; "none" = no
 * animation (the file's rest pose); else a clip's name, or its index in `animations` (digits;
 * a clip named so wins). Any other text is XRSC_ERROR_ANIMATION_UNKNOWN (field "animation")
 * with a message listing the file's clips. The keywords win over clip names of the same text.
 * blas_update (skinned and morphed meshes, issue 21): how their bottom-level acceleration
 * structures follow the pose each frame: XRSC_BLAS_UPDATE_AUTO (zero, the default) refits
 * until the pose drifted far from the last build's, then rebuilds; REFIT and REBUILD force
 * one every frame (to measure which pays, `xrsc bench --blas-update`).
 */
typedef enum xrsc_blas_update {
    XRSC_BLAS_UPDATE_AUTO = 0,
    XRSC_BLAS_UPDATE_REFIT,
    XRSC_BLAS_UPDATE_REBUILD,
} xrsc_blas_update;

typedef struct xrsc_scene_options {
    bool env_set;
    float environment[3];
    bool keep_triangle_order;
    const char *env_map_path;
    float env_intensity;
    float env_rotation_deg;
    bool sky;
    float sky_turbidity;
    bool sun_direction_set;
    float sun_direction[3];
    bool env_no_importance;
    const char *animation;
    xrsc_blas_update blas_update;
} xrsc_scene_options;

typedef struct xrsc_scene_info {
    uint64_t triangle_count;
    uint32_t instance_count, material_count, emitter_count;
    float animation_duration_s;
    bool has_camera;
    float camera_yfov_rad;     /**< the glTF camera's perspective.yfov when has_camera */
    float camera_aspect_ratio; /**< its aspectRatio; 0 when the file gives none */
    XrPosef viewpoint; /**< where a replay's first pose is anchored by default */
    float bounds_min[3], bounds_max[3];
    double blas_build_ms; /**< GPU time of the BLAS builds at load (timestamp queries) */
    uint32_t texture_count;  /**< textures the materials use */
    /** KHR_lights_punctual lights drawn: the sun (the first directional light, or --sky's)
     *  counts as one, plus every point, spot and further directional light. */
    uint32_t light_count;
    uint32_t camera_count;   /**< perspective cameras (::xrsc_scene_camera) */
    bool studio_environment; /**< lit by the built-in studio environment (no light given) */
    /** Wall time of the load in ms: load_ms the whole xrsc_scene_load (or
     *  xrsc_scene_inspect); its parts: reading and parsing the file (tinygltf, images
     *  decoded), reading the geometry, tangents, the Morton sort, the GPU upload and
     *  acceleration-structure builds (0 for xrsc_scene_inspect). */
    double load_ms, load_parse_ms, load_geometry_ms, load_tangents_ms, load_morton_ms;
    double load_gpu_ms;
    /** The file's animation clips, and the one that plays (xrsc_scene_options.animation):
     *  its index, or XRSC_CLIP_NONE / XRSC_CLIP_ALL. animation_duration_s is its duration. */
    uint32_t clip_count;
    int32_t clip_playing;
} xrsc_scene_info;

#define XRSC_CLIP_NONE (-1)
#define XRSC_CLIP_ALL (-2)
/** Most clips ::xrsc_file_info lists (xrsc_file_info.clip_count counts them all). */
#define XRSC_FILE_INFO_MAX_CLIPS 64u

/** One animation clip of a glTF file. */
typedef struct xrsc_clip_info {
    char name[128];         /**< "" when the file gives none */
    float duration_s;       /**< the last key time over its channels */
    uint32_t channel_count; /**< its channels (every path, those xrsc ignores included) */
} xrsc_clip_info;

/**
 * What a user asks first about a glTF file (`xrsc scene info`): the scene as drawn (scene, as
 * ::xrsc_scene_inspect fills it) and what the file holds, counted in the file whether xrsc
 * draws it or not: nodes, meshes, images, materials, skins, morph targets (summed over the
 * primitives, and the meshes that have any), its clips (the first XRSC_FILE_INFO_MAX_CLIPS)
 * and its extensionsUsed / extensionsRequired (comma-separated, "" when none).
 */
typedef struct xrsc_file_info {
    xrsc_scene_info scene;
    uint32_t node_count, mesh_count, image_count, material_count;
    uint32_t skin_count, morph_target_count, morph_mesh_count;
    uint32_t clip_count;
    xrsc_clip_info clips[XRSC_FILE_INFO_MAX_CLIPS];
    char extensions_used[1024], extensions_required[1024];
} xrsc_file_info;

/** Reads a glTF 2.0 file on the CPU alone (no Vulkan device, nothing uploaded, no Morton
 *  sort) into out_info. options may be NULL; its animation is resolved as in xrsc_scene_load
 *  (scene.clip_playing). Errors as xrsc_scene_load's. */
xrsc_result xrsc_file_inspect(const char *path, const xrsc_scene_options *options,
                              xrsc_file_info *out_info, xrsc_diag *out_diag);

/** Loads a glTF 2.0 file and uploads it (BLAS/TLAS built). */
xrsc_result xrsc_scene_load(xrsc_context *ctx, const char *path,
                            const xrsc_scene_options *options, xrsc_scene **out_scene,
                            xrsc_diag *out_diag);
void xrsc_scene_destroy(xrsc_scene **scene);
void xrsc_scene_get_info(const xrsc_scene *scene, xrsc_scene_info *out_info);
/**
 * Perspective camera `index` (< xrsc_scene_info.camera_count; the order the scene's nodes are
 * walked, depth-first from its roots, 0 being the default viewpoint's): its world pose at
 * time 0 and yfov. XRSC_ERROR_INVALID_ARGUMENT (field "camera") when there is no such camera.
 */
xrsc_result xrsc_scene_camera(const xrsc_scene *scene, uint32_t index, XrPosef *out_pose,
                              float *out_yfov_rad, xrsc_diag *out_diag);
/** The info of a glTF 2.0 file read on the CPU alone (no context, nothing uploaded;
 *  blas_build_ms 0): e.g. its camera, before a headset's views are configured. */
xrsc_result xrsc_scene_inspect(const char *path, xrsc_scene_info *out_info, xrsc_diag *out_diag);
/**
 * Per-instance flags for the region metrics (xrsc_metrics.h, XRSC_INSTANCE_FLAG_*): OBJECT for
 * animated instances, SPECULAR for material factors (metallic >= 0.5 or transmission > 0) with
 * roughness < 0.5 (textures not read). Instance i is the first-hit id i of XRSC_OUTPUT_HIT_ID.
 * Writes min(count, max_count) bytes to out (may be NULL) and returns the instance count
 * (0 for a NULL scene).
 */
uint32_t xrsc_scene_instance_flags(const xrsc_scene *scene, uint8_t *out, uint32_t max_count);
/** True when loading the scene printed a warning with this ID (XRSC_WARN_* of result.h: a
 *  missing or undecodable image stood in for, points/lines skipped, an optional extension
 *  ignored). False for a NULL scene. */
bool xrsc_scene_warned(const xrsc_scene *scene, xrsc_result id);

/**
 * Rendering methods.
 * - XRSC_METHOD_SPP: path tracer, N samples per pixel per frame (seed 000 §5.1).
 * - XRSC_METHOD_PRIMARY: one primary ray per pixel through its centre, no shading: colour is
 *   the first hit's albedo (environment for misses). For previews and primary-ray Mrays/s.
 * - XRSC_METHOD_SAMPLECACHE: the per-eye sample cache of seed 000 §3 (reproject, trace mask,
 *   density control, trace, shade, reconstruct), options ::xrsc_samplecache_options.
 */
typedef enum xrsc_method {
    XRSC_METHOD_SPP = 0,
    XRSC_METHOD_PRIMARY = 1,
    XRSC_METHOD_SAMPLECACHE = 2,
    /** 1 spp path traced with Halton(2,3) sub-pixel jitter + TAA ([YLS20] as seed 000 §5 uses
     *  it; TAA on by default, ::xrsc_taa_options). Frame f samples every pixel of both eyes at
     *  Halton point (f mod 16) + 1; max_bounces from ::xrsc_spp_options (its other fields are
     *  ignored). Passes "trace", then "taa". */
    XRSC_METHOD_TAA = 3,
    /** World-space hashed voxel radiance cache (seed 000 §4, seed 001), ::xrsc_hashcache_options:
     *  jittered 1 spp first hits (pass "trace"), then per pixel a lookup/reservation of the hit's
     *  voxel, one secondary path per voxel and frame, the voxel's running mean of demodulated
     *  radiance and the colour (pass "shade"); TAA with PFJ23 weights on by default. */
    XRSC_METHOD_HASHCACHE = 4,
    /** The sample cache's visibility (adaptive first-hit tracing, no shading storage) with
     *  radiance from the hash cache at the hit voxel and its parent LoD (seed 000 §4): a shaded
     *  sample updates one of the two levels at random, a visible sample's radiance is the
     *  count-weighted mean of both; ::xrsc_samplecache_options for visibility (shade must be
     *  uniform; the shading-cache and alpha fields do not apply), ::xrsc_hashcache_options for
     *  radiance (its max_bounces, when set, overrides the sample cache's); TAA with PFJ23
     *  weights on by default. Visibility (masks, first hits, depth, hit id) equals
     *  `samplecache`'s with the same options and seed. */
    XRSC_METHOD_HYBRID = 5,
    /** Interactive stable ray tracing's superresolution layout [DSK*17] (seed 000 Fig. 10):
     *  M x M fixed sub-pixel slots per pixel with the sample cache's shading cache,
     *  ::xrsc_isrt_options and the shading fields of ::xrsc_samplecache_options. */
    XRSC_METHOD_ISRT = 6,
} xrsc_method;
/** Number of xrsc_method values (they are 0 .. XRSC_METHOD_COUNT - 1). */
#define XRSC_METHOD_COUNT 7
/** "spp" / "primary" / "samplecache" / "taa" / "hashcache" / "hybrid" / "isrt"; NULL for
 *  unknown values. */
const char *xrsc_method_name(xrsc_method method);
/** Parses a method name; XRSC_ERROR_UNKNOWN_METHOD when unknown. */
xrsc_result xrsc_method_from_name(const char *name, xrsc_method *out_method);

/**
 * Options of the `spp` method (path tracer, seed 000 §5.1). Defaults: samples_per_pixel 1,
 * max_bounces 3 (Russian roulette from the 2nd), jitter on, no accumulation.
 * - accumulate: progressive accumulation over frames while the views stay the same (for
 *   references); any change of view or scene time restarts it.
 * - no_jitter: every sample through the pixel centre (for exact primary-hit tests).
 * - max_bounces: bounce rays after the camera ray; 0 means the default 3; XRSC_BOUNCES_NONE
 *   asks for none: only emission seen by the camera rays (emitters, the environment on
 *   misses), no light sampling (that happens at vertices that can still bounce, so direct
 *   lighting is max_bounces 1: light sampling at the first hit plus one BSDF ray).
 */
#define XRSC_BOUNCES_NONE UINT32_MAX
typedef struct xrsc_spp_options {
    uint32_t samples_per_pixel;
    uint32_t max_bounces;
    bool accumulate;
    bool no_jitter;
} xrsc_spp_options;

/** Which samples the sample cache retraces each frame (seed 000 §3.2, §3.4). */
typedef enum xrsc_sc_trace {
    XRSC_SC_TRACE_DEFAULT = 0, /**< adaptive */
    XRSC_SC_TRACE_SINGLE,      /**< one sample per pixel, round robin over the slots */
    XRSC_SC_TRACE_MULTI,       /**< every sample, every frame */
    XRSC_SC_TRACE_ADAPTIVE,    /**< one per block x block pixels + all samples at edges (Eq. 2) */
} xrsc_sc_trace;
/** Forward reprojection variant (seed 000 §3.1, Fig. 6). Both now reserve target slots
 *  independently of the order the GPU runs invocations in (each target keeps the N smallest
 *  keys: visible first, then the lowest source address) and copy in a second pass, so they
 *  give the same images; Listing 2's writes during the reservation could not be made so. */
typedef enum xrsc_sc_reproject {
    XRSC_SC_REPROJECT_DEFAULT = 0, /**< 1pass */
    XRSC_SC_REPROJECT_1PASS,       /**< Listing 2 (now the same as 2pass, see above) */
    XRSC_SC_REPROJECT_2PASS,       /**< reserve (source addresses), then copy */
} xrsc_sc_reproject;
/** Which cached samples are re-shaded each frame (seed 000 §3.3, §3.5). */
typedef enum xrsc_sc_shade {
    XRSC_SC_SHADE_DEFAULT = 0, /**< uniform */
    XRSC_SC_SHADE_UNIFORM,     /**< one visible sample per pixel, round robin */
    XRSC_SC_SHADE_ADAPTIVE,    /**< base rate + importance 1/(1+c_s) histogram at shade_rate */
    /** as adaptive, with importance = the estimated relative variance of each sample's mean,
     *  v_pixel / (1 + c_s) (xs_sc_variance_importance; issue 12, seed 000 §6's future work) */
    XRSC_SC_SHADE_ADAPTIVE_VARIANCE,
} xrsc_sc_shade;
/** Temporal blend factor of the shading cache (seed 000 App. C). */
typedef enum xrsc_sc_alpha {
    XRSC_SC_ALPHA_DEFAULT = 0, /**< clamped */
    /** max(1/(c_s+1), alpha_min(roughness)) for metal/glass lobes; the glass (transmission)
     *  share scaled by how far the sample's view turned since the previous frame, from 0 for a
     *  still view to all of it from 1/8 pixel per frame (XS_SC_VIEW_MOTION_PIXELS) */
    XRSC_SC_ALPHA_CLAMPED,
    XRSC_SC_ALPHA_FIXED,       /**< max(1/(c_s+1), alpha_fixed) for every sample */
} xrsc_sc_alpha;

/** Refinement of the shading pass's visibility cache (seed 002 §3.6). */
typedef enum xrsc_sc_vis_refine {
    XRSC_SC_VIS_REFINE_DEFAULT = 0, /**< adaptive */
    /** Alg. 2: a cached answer stands when X's 4 neighbouring clusters agree or are unknown;
     *  else C_E is halved, down to `levels` levels, whose finest cluster then answers */
    XRSC_SC_VIS_REFINE_ADAPTIVE,
    /** zero refinement error tolerance: an answer stands only when all 8 neighbours of X's
     *  3 x 3 block are known and agree; disagreement down to the last level traces the ray.
     *  Exact wherever shadow edges are straight across 3 x 3 clusters (a cluster cut by such
     *  an edge always sees a disagreeing neighbour); thin shadows and penumbrae of area
     *  lights can still be missed */
    XRSC_SC_VIS_REFINE_STRICT,
    XRSC_SC_VIS_REFINE_NONE, /**< Alg. 1: quantisation only, no neighbours */
} xrsc_sc_vis_refine;

/**
 * The shadow visibility cache of the sample cache's shading pass (seed 002, AQVC): the shadow
 * rays of the light samples (sky sun disk, environment map, delta sun, emissive triangle,
 * KHR_lights_punctual light) at the first vertex of each shading path (the cached first hit)
 * are answered per cluster of similar queries: quantised X (oriented grid from the normal,
 * Eq. 4, cell edge from Eq. 7 as C_E pixel footprints) x quantised light end (§3.5), one
 * traced ray per cluster and frame, with the adaptive refinement of §3.6. Deeper vertices
 * always trace (their eye-path density, which Eq. 7 needs, is unknown). The table is cleared
 * every frame: nothing persists between frames, so animated scenes never see stale
 * visibility. No random number is drawn: when every query traces, the image equals the
 * uncached one. Zero fields mean seed 002's defaults:
 * - enabled: off (false): every shadow ray is traced, images as without this option;
 * - error_px: C_E, the screen-space size (pixels) of a cluster's error region, > 0 [4; §5
 *   uses 4..18 for directional and 4..24 for area and environment light without AA];
 * - levels: C_MSR, refinement levels 1..8 [max(1, round(log2 C_E)), §3.6];
 * - normal_bins: C_N of Eq. 4, 1..64 [8]; depth_ratio: C_Z of §3.3, 1..64 [8];
 * - resolution_base: C_R of Eq. 8, in (1, 4] [1.2];
 * - refine: ::xrsc_sc_vis_refine [adaptive];
 * - table_entries: 64-bit words, XS_VC_MIN_ENTRIES (4096) .. 2^26 [16 per pixel of both
 *   eyes, rounded up to a power of two].
 */
typedef struct xrsc_sc_visibility_options {
    bool enabled;
    float error_px;
    uint32_t levels;
    uint32_t normal_bins;
    uint32_t depth_ratio;
    float resolution_base;
    xrsc_sc_vis_refine refine;
    uint32_t table_entries;
} xrsc_sc_visibility_options;

/**
 * Options of the `samplecache` method (seed 000 §3). Zero fields mean the paper's defaults
 * (§4, §3.2, §3.4, App. C): slots N = 12 (1..16: a 32-bit mask, 2 bits per slot),
 * n_target = 4, delta = 1 (density n_target +- delta over 3 x 3), eps0 = 0.001 (retrace:
 * relative distance), eps1 = 0.005 (Eq. 2), block = 4 (one traced / shaded sample per 4 x 4
 * block as base rate), trace adaptive, reprojection 1pass, shading cache on, shading uniform,
 * shade_rate = 1 (shadings per pixel per frame in adaptive shading, 1 = 100 %), alpha clamped
 * (App. C), alpha_fixed = 0.1 (used by XRSC_SC_ALPHA_FIXED), max_bounces as
 * ::xrsc_spp_options (0: 3; XRSC_BOUNCES_NONE: none) for the shading paths. A zero float
 * cannot be asked for: use a tiny value (e.g. delta 1e-6).
 * no_shading_cache: radiance is not kept between frames (only visibility is cached; each
 * frame's shaded samples alone make the colour).
 * cross_eye: cross-eye reuse (issue 12, beyond seed 000, which keeps the eyes apart until the
 * blend): each eye's visible samples whose radiance does not depend on the eye (background;
 * surfaces that are not metal or glass and have no dielectric specular layer with roughness
 * below 0.5: xs_sc_eye_specific) are also forward-reprojected into the other eye's cache as
 * copies, retraced there for visibility like any sample, counted by density control and
 * reconstructed (a pixel's eye-specific and shared samples weighed by the share of its own
 * samples on each), but shaded only by their owner, so a surface point is traced and shaded
 * once for both eyes; +8 B per pixel per eye. The eyes reserve slots in each other's pixels,
 * so images vary slightly from run to run (the order of arrival). Not with `isrt` or
 * `hybrid` (XRSC_ERROR_INVALID_ARGUMENT). Default off.
 */
typedef struct xrsc_samplecache_options {
    uint32_t slots;
    float n_target;
    float delta;
    float eps0;
    float eps1;
    uint32_t block;
    xrsc_sc_trace trace;
    xrsc_sc_reproject reproject;
    bool no_shading_cache;
    xrsc_sc_shade shade;
    float shade_rate;
    xrsc_sc_alpha alpha;
    float alpha_fixed;
    uint32_t max_bounces;
    bool cross_eye;
    xrsc_sc_visibility_options visibility; /**< the shading pass's shadow visibility cache */
    /**
     * Firefly rule (issue 19 item 3, beyond seed 000): k >= 1 caps each new shading of a
     * sample that has XS_SC_FIREFLY_MIN_COUNT (4) observations at k times the luminance of
     * its running mean L_s (the colour kept, scaled down) before it is blended in, so one
     * caustic path cannot light a diffuse sample for dozens of frames. Biased (energy of
     * rare bright paths is lost); references (`spp`) are never clamped. 0: off (default; see
     * bench/results/issue19-defaults/ for why). Other values: XRSC_ERROR_INVALID_ARGUMENT.
     */
    float firefly_clamp;
    /**
     * Moving-sample rule (issue 19, case `moving`, beyond seed 000; XS_SC_MOVING_ALPHA_MIN in
     * shaders/xs_samplecache.h): while a sample's instance turns (the linear part of its
     * transform changed since the previous frame), its pixel shades one of its turning samples
     * more each frame, and on a face that turned its blend factor is at least
     * min(1, turn / 0.01 rad), so it does not keep the radiance of the object's old pose (a
     * turn of 0.01 rad or more: this frame's shading alone; TAA averages it). Instances that
     * only slide, and scenes without animation, render as without the rule; with it the shade
     * list holds one entry more per pixel in scenes with animated instances.
     * false: off (default; bench/results/issue19-moving2/).
     */
    bool moving;
    /**
     * Stratified new samples (issue 19, beyond seed 000, which traces each new sample through
     * a uniform random point of its pixel): the pixel is cut into G x G strata (G =
     * round(sqrt(n_target)), 1..4) and a new sample goes through a random point of a stratum
     * holding the fewest of the pixel's visible samples (projected from their first hits).
     * A pixel keeps its ~n_target points as long as they stay visible, so on a pixel cut by an
     * edge the coverage error of their mean never averages out; stratified points make it
     * smaller (still `edges`, no TAA or blend: relMSE 0.69x). Off (false) by default and in
     * `xrsc replay`'s default: under TAA its gain shrinks and the glossy orbit's relMSE rose
     * 3 % (bench/results/issue19-edges/). No effect with `isrt` (fixed cells).
     */
    bool stratify;
    /**
     * Cover rule (issue 19, beyond seed 000; XS_SC_PLAN_UNOBSERVED in shaders/xs_samplecache.h),
     * with variance-guided shading only: a pixel that has surface samples but none shaded yet
     * shades one of them that frame, outside the shading budget. Without it such a pixel shows
     * black (the colour averages shaded samples only): at 40 % on a first frame most pixels,
     * later the newly uncovered ones, and a temporal filter keeps that darkness for tens of
     * frames. Costs one shading per such pixel (a first frame: one per pixel); the shade list
     * holds one entry more per pixel. false: off (default; bench/results/issue19-headset/).
     */
    bool cover;
} xrsc_samplecache_options;

/**
 * Temporal antialiasing as a post-pass after any method ([YLS20] as seed 000 §5.1 puts it on
 * top of every method): the history is reprojected by depth with camera and instance motion,
 * clipped to the neighbourhood's variance box in YCoCg, and blended with the current frame;
 * disocclusions reject the history. Resampling, clipping, weights and blend work on
 * c / (1 + Y) (Y: YCoCg luma), inverted after the blend, so an emitter's radiance does not
 * leak into the dark surface beside it (issue 19). It runs after the method's reconstruction
 * and before the stereo blend (pass "taa").
 * - XRSC_TAA_DEFAULT (0): the method's default: on for `taa`, pfj23 for `hashcache` and
 *   `hybrid`, off for the others.
 * - XRSC_TAA_OFF: no temporal filter.
 * - XRSC_TAA_ON: blend weight alpha (default 0.1) for the current frame, rising towards 0.5
 *   for history that did not show the pixel's surface itself (::xrsc_taa_options).
 * - XRSC_TAA_PFJ23: per-pixel variance-based temporal blend weights of seed 004 instead of
 *   the fixed alpha: its Eq. 4 per pixel and colour channel, with the current frame's variance
 *   over the 3 x 3 neighbourhood (Eq. 10) and the mean squared difference of the reprojected
 *   history to each neighbour (Eq. 11), as seed 004 §4.2 specifies; no variance clipping
 *   (seed 004 §5.1 leaves out history rectification); the disocclusion test still applies.
 * The history is the filtered colour before any stereo blend; the first frame of a renderer
 * has none (its output is the method's colour). The output replaces the method's colour:
 * XRSC_OUTPUT_COLOR, the OpenXR submission and the bench all see it.
 */
typedef enum xrsc_taa_mode {
    XRSC_TAA_DEFAULT = 0,
    XRSC_TAA_OFF = 1,
    XRSC_TAA_ON = 2,
    XRSC_TAA_PFJ23 = 3,
} xrsc_taa_mode;
/** "default" / "off" / "on" / "pfj23"; NULL for unknown values. */
const char *xrsc_taa_mode_name(xrsc_taa_mode mode);
/** Parses a TAA mode name; XRSC_ERROR_INVALID_ARGUMENT when unknown. */
xrsc_result xrsc_taa_mode_from_name(const char *name, xrsc_taa_mode *out_mode);
/** The mode a renderer of `method` runs for `mode`: XRSC_TAA_DEFAULT resolved per method
 *  (above), any other mode as it is. */
xrsc_taa_mode xrsc_taa_mode_resolve(xrsc_method method, xrsc_taa_mode mode);

/**
 * How the TAA pass resamples the reprojected history (both modes):
 * - XRSC_TAA_HISTORY_DEFAULT (0): bilinear.
 * - XRSC_TAA_HISTORY_BILINEAR: the 2 x 2 bilinear taps. Resampled every frame under sub-pixel
 *   motion, it low-pass filters the history again each frame (texture blurs under a pan); it
 *   also averages noise away, and on issue 19's bench cases it gave the default pipeline a
 *   lower relMSE than Catmull-Rom (bench/results/issue19-taasharp/), hence the default.
 * - XRSC_TAA_HISTORY_CATMULL_ROM: the 4 x 4 Catmull-Rom taps where all 2 x 2 inner taps show
 *   the pixel's surface themselves (else bilinear, as validated); an outer tap that does not
 *   show it takes its nearest inner tap's value, and the result is clamped to the inner taps'
 *   range (no ringing) before the neighbourhood clip. Sharper texture under motion.
 */
typedef enum xrsc_taa_history {
    XRSC_TAA_HISTORY_DEFAULT = 0,
    XRSC_TAA_HISTORY_BILINEAR = 1,
    XRSC_TAA_HISTORY_CATMULL_ROM = 2,
} xrsc_taa_history;
/** "default" / "bilinear" / "catmull-rom"; NULL for unknown values. */
const char *xrsc_taa_history_name(xrsc_taa_history filter);
/** Parses a history filter name; XRSC_ERROR_INVALID_ARGUMENT when unknown. */
xrsc_result xrsc_taa_history_from_name(const char *name, xrsc_taa_history *out_filter);

/**
 * TAA's motion rule (mode XRSC_TAA_ON; issue 19): under sub-pixel motion the history is
 * resampled between pixels each frame, which blurs it (the bilinear kernel's variance
 * fx (1 - fx) + fy (1 - fy) px^2 at the reprojected point); with the rule the current frame's
 * weight for the trusted history rises linearly with that blur, from alpha with none (a still
 * view) to motion_alpha (default 0.5) at motion_px2 (default 0.25 px^2) or more (XS_TF_MOTION_*
 * in shaders/xs_taa.h). On the sample cache (whose colour is already accumulated over frames)
 * it lowers relMSE under pans and sideways motion, but raises the temporal and stereo
 * differences of the orbits (bench/results/issue19-taaedge/), so it is off by default.
 * - XRSC_TAA_MOTION_DEFAULT (0) = XRSC_TAA_MOTION_OFF; XRSC_TAA_MOTION_ON.
 * - XRSC_TAA_MOTION_EDGES: the rule only on the dark side of an edge between surfaces: at
 *   pixels whose current 3 x 3 neighbourhood shows another instance (or background beside a
 *   hit) and whose luma (in the resolve space) is below the neighbourhood's mean. There the
 *   blur carries the bright side's radiance in, a large relative error: the Cornell light
 *   panel (radiance ~15) smeared into the ceiling beside it (~0.05) was half of the
 *   default's relMSE on the Cornell orbit (bench/results/issue19-cornell/). Inside a
 *   surface, and on an edge's bright side, the history keeps alpha, so the temporal and
 *   stereo differences rise far less than with XRSC_TAA_MOTION_ON.
 */
typedef enum xrsc_taa_motion {
    XRSC_TAA_MOTION_DEFAULT = 0,
    XRSC_TAA_MOTION_OFF = 1,
    XRSC_TAA_MOTION_ON = 2,
    XRSC_TAA_MOTION_EDGES = 3,
} xrsc_taa_motion;
/** "default" / "off" / "on" / "edges"; NULL for unknown values. */
const char *xrsc_taa_motion_name(xrsc_taa_motion motion);
/** Parses a motion rule name; XRSC_ERROR_INVALID_ARGUMENT when unknown. */
xrsc_result xrsc_taa_motion_from_name(const char *name, xrsc_taa_motion *out_motion);

/** TAA options. Zero fields mean the defaults: mode per method (above), alpha 0.1, history
 *  filter bilinear, no motion rule (::xrsc_taa_motion). With XRSC_TAA_ON the current frame's
 *  weight rises from alpha towards 0.5 for the share of the history that did not show the
 *  pixel's surface itself (edges, disocclusions; XS_TF_UNTRUSTED_ALPHA in shaders/xs_taa.h),
 *  where the neighbourhood clip cannot correct it. */
typedef struct xrsc_taa_options {
    xrsc_taa_mode mode;
    float alpha; /**< weight of the current frame with XRSC_TAA_ON, (0, 1] (trusted history) */
    xrsc_taa_history history; /**< history resampling (::xrsc_taa_history) */
    xrsc_taa_motion motion;   /**< the motion rule (::xrsc_taa_motion) */
    float motion_px2;   /**< blur (px^2) at which the motion rule reaches motion_alpha; 0 = 0.25 */
    float motion_alpha; /**< the motion rule's highest weight, (0, 1]; 0 = 0.5 */
} xrsc_taa_options;

/** How the hash cache picks a voxel's level of detail (seed 000 §4, Fig. 9). */
typedef enum xrsc_hc_lod {
    XRSC_HC_LOD_DEFAULT = 0,     /**< distance */
    XRSC_HC_LOD_DISTANCE,        /**< voxel smaller than the pixel footprint at the hit distance */
    XRSC_HC_LOD_DISTANCE_NORMAL, /**< also coarser at grazing incidence (Fig. 9, right) */
} xrsc_hc_lod;

/**
 * Options of the `hashcache` method and of `hybrid`'s radiance (seed 000 §4). Zero fields mean
 * the defaults: table_entries 2^22 (24 B each), lod distance, voxel_scale 0.5, max_age 64
 * frames, voxel jitter on, max_bounces as ::xrsc_spp_options for the secondary path.
 * - table_entries: rounded down to a multiple of 16 (4 x 4 tiles); 16 .. 2^27, else
 *   XRSC_ERROR_INVALID_ARGUMENT. Linear probing visits at most 8 tiles; a lookup that finds
 *   neither its voxel nor a free or stale entry there is a failed insert (the pixel is shaded
 *   uncached that frame).
 * - voxel_scale: voxel edge = 2^floor(log2(voxel_scale x footprint)) m, footprint = the pixel
 *   size at the hit distance (tan-space pixel size at the image centre x distance), so with
 *   the default a voxel is at most half a pixel; powers of two so the LoDs nest (hybrid's
 *   parent = edge x 2). XRSC_HC_LOD_DISTANCE_NORMAL divides the footprint by
 *   max(|cos theta|, 0.05) (theta: view ray vs. surface normal).
 * - max_age: an entry whose last access is more than max_age frames old may be overwritten
 *   (an eviction).
 * - no_voxel_jitter: look voxels up at the hit itself instead of a position jittered by up to
 *   half a voxel in the surface's tangent plane [BFK18] (hybrid: jitter applies to its
 *   updates only; its reconstruction never jitters).
 * A voxel keeps the running mean of its samples' demodulated radiance (divided by the
 * first-hit albedo, as the sample cache), counting at most 256 samples (then an exponential
 * average with weight 1/256); one pixel (hybrid: one shaded sample) per voxel and frame
 * traces and updates it, the others read it (or, while it holds nothing yet, shade themselves
 * uncached).
 * Counters (xrsc_renderer_counters) of both methods: hc_table_bytes, hc_occupancy (entries
 * accessed within max_age / entries), hc_probe_mean, hc_probe_max (tiles visited per lookup),
 * hc_lookups, hc_inserts, hc_evictions, hc_failed_inserts, hc_traced (secondary paths).
 */
typedef struct xrsc_hashcache_options {
    uint32_t table_entries;
    xrsc_hc_lod lod;
    float voxel_scale;
    uint32_t max_age;
    bool no_voxel_jitter;
    uint32_t max_bounces;
} xrsc_hashcache_options;

/**
 * Options of `isrt`. m: M x M fixed sub-pixel slots per pixel, 1..4 (0: 2). Slot s of a pixel
 * is the cell (s % M, s / M): a reprojected sample goes to the cell containing its new
 * position (of several, the visible and then the closest one stays), every cell without a
 * visible sample is traced through its centre, a retraced sample found occluded is replaced by
 * the occluder. Retracing follows ::xrsc_samplecache_options trace (seed 000 Fig. 10 uses
 * single); shading, the shading cache and reconstruction are the sample cache's own, with its
 * shading options; slots, n_target, delta and reproject are not used (no density control).
 */
typedef struct xrsc_isrt_options {
    uint32_t m;
} xrsc_isrt_options;

/**
 * Stereo blends, run after the method's reconstruction inside the frame (pass "blend"), before
 * any read-back or submission; each eye is improved from the other (symmetrically) with
 * lerp(X, Y, beta) = (1 - beta) X + beta Y (seed 000 Eq. 3), Y this eye's pixel, X the other
 * eye's reprojected by this eye's depth (disocclusions, detected by a relative depth test of
 * 5 %, are left untouched). See shaders/xs_stereo.h and shaders/stereo_blend.comp.
 * - XRSC_BLEND_NONE (0, the default): the eyes are left as rendered.
 * - XRSC_BLEND_PFJ23: beta from seed 004 Eq. 4 with sigma_Y^2 and E[(X - Y)^2] estimated in
 *   this eye's 3 x 3 neighbourhood (seed 004 Eq. 10-11); bilinear resampling of the other eye.
 * - XRSC_BLEND_MOMENTS: beta from seed 000 Eq. 8 with the raw moments mu_1, mu_2 of the pixels'
 *   own samples (XRSC_OUTPUT_MU1/MU2, Eq. 5-7), this eye's blurred in 3 x 3 (weight 1 - R off
 *   centre, 1 at the centre), the other eye's resampled with Dodgson's quadratic kernel with R
 *   as its spline parameter (seed 000 §5.2); R smooths only these estimates, the colour X is
 *   resampled bilinearly as for PFJ23. Needs a method with moments (`spp`, `samplecache`, `hybrid`).
 */
typedef enum xrsc_blend {
    XRSC_BLEND_NONE = 0,
    XRSC_BLEND_PFJ23 = 1,
    XRSC_BLEND_MOMENTS = 2,
} xrsc_blend;
/** "none" / "pfj23" / "moments"; NULL for unknown values. */
const char *xrsc_blend_name(xrsc_blend blend);
/** Parses a blend name; XRSC_ERROR_INVALID_ARGUMENT when unknown. */
xrsc_result xrsc_blend_from_name(const char *name, xrsc_blend *out_blend);

/**
 * What the moments blend (XRSC_BLEND_MOMENTS) takes as the variances of Eq. 4 (seed 000 §3.6).
 * - XRSC_BLEND_ESTIMATE_SAMPLES (0, the default, "samples"): Eq. 5-8 as printed, the
 *   c_s-weighted spread mu_2 - mu_1^2 of the pixel's samples' values L_s.
 * - XRSC_BLEND_ESTIMATE_MEAN ("mean"): the variance of the pixel's mean, that spread divided
 *   by the pixel's effective sample count c_X (Eq. 6) (xs_st_beta_eq8_mean in
 *   shaders/xs_stereo.h). bench/results/issue12-fig15/README.md compares the two.
 */
typedef enum xrsc_blend_estimate {
    XRSC_BLEND_ESTIMATE_SAMPLES = 0,
    XRSC_BLEND_ESTIMATE_MEAN = 1,
} xrsc_blend_estimate;
/** "samples" / "mean"; NULL for unknown values. */
const char *xrsc_blend_estimate_name(xrsc_blend_estimate estimate);
/** Parses an estimate name; XRSC_ERROR_INVALID_ARGUMENT when unknown. */
xrsc_result xrsc_blend_estimate_from_name(const char *name, xrsc_blend_estimate *out_estimate);

/**
 * Renderer options. width/height per eye (default 256 x 256); seed 0 is a valid seed.
 * blend: the stereo blend (default none). blend_r: the sharpness R in [0, 1] of the moments
 * blend; the zero default R = 0 is the setting with the lowest error and stereo discrepancy in
 * seed 000 §5.2 (Fig. 15: R = 0 beats R = 1 and PFJ23 on RSE and discrepancy, with CPBD
 * sharpness closest to the reference); R = 1 is the conservative, least blurring one.
 * blend_estimate: the variances the moments blend uses (default: Eq. 5 as printed).
 * blend_instance_test: the blend's taps must also show the pixel's instance (hit id), not only
 * its depth within 5 % (default false: the depth test alone). The Cornell light panel lies
 * 1 cm below the ceiling, so the depth test takes it for the ceiling, and the other eye's
 * bilinear tap mixed its radiance (~15) into the ceiling beside it (~0.05): a third of the
 * default's relMSE on the Cornell orbit at 2 x 96^2 (bench/results/issue19-cornell/).
 */
typedef struct xrsc_renderer_options {
    xrsc_method method;
    uint32_t width, height;
    uint32_t seed;
    xrsc_spp_options spp;
    xrsc_samplecache_options samplecache;
    xrsc_blend blend;
    float blend_r;
    xrsc_blend_estimate blend_estimate;
    xrsc_taa_options taa;
    bool blend_instance_test;
    xrsc_hashcache_options hashcache;
    xrsc_isrt_options isrt;
} xrsc_renderer_options;

/** One eye's view. */
typedef struct xrsc_view {
    XrPosef pose; /**< eye pose in scene (world) space */
    XrFovf fov;
} xrsc_view;

/** One stereo frame to render. */
typedef struct xrsc_frame {
    xrsc_view views[2];      /**< [0] left, [1] right */
    int64_t display_time_ns; /**< scene time for animation (relative to the replay start) */
    uint32_t frame_index;    /**< selects the random stream */
} xrsc_frame;

xrsc_result xrsc_renderer_create(xrsc_context *ctx, xrsc_scene *scene,
                                 const xrsc_renderer_options *options,
                                 xrsc_renderer **out_renderer, xrsc_diag *out_diag);
void xrsc_renderer_destroy(xrsc_renderer **renderer);
/** Renders both eyes and waits for completion. */
xrsc_result xrsc_renderer_render(xrsc_renderer *renderer, const xrsc_frame *frame);

/** Per-eye outputs. */
typedef enum xrsc_output {
    XRSC_OUTPUT_COLOR,  /**< float RGBA, linear HDR radiance */
    XRSC_OUTPUT_ALBEDO, /**< float RGBA, demodulated first-hit albedo */
    XRSC_OUTPUT_DEPTH,  /**< float, view-space distance along -Z (m), 0 = background */
    XRSC_OUTPUT_HIT_ID, /**< uint32 x4: instance (UINT32_MAX = miss), primitive, bary u, v bits */
    /** float RGBA, `samplecache` and `spp`: raw moments of the pixel's samples (seed 000
     *  Eq. 5), rgb = mu_1 (resp. mu_2) per channel, a = c_X (Eq. 6, the pixel's effective
     *  sample count). `spp`: the N path values of this frame's samples, c_s = 1, c_X = N.
     *  `hybrid`: as `samplecache` with c_s = the hit voxel's + its parent's counts. */
    XRSC_OUTPUT_MU1,
    XRSC_OUTPUT_MU2,
} xrsc_output;

/** Bytes one eye's image of that output takes (width * height * texel size). */
size_t xrsc_renderer_output_size(const xrsc_renderer *renderer, xrsc_output output);
/** Copies one eye's output of the last rendered frame into dst (rows top to bottom).
 *  `samplecache`'s albedo is made in the frame only when it was read after the frame before;
 *  otherwise this read runs its reconstruction again for it (same values, one more submit). */
xrsc_result xrsc_renderer_read(xrsc_renderer *renderer, uint32_t eye, xrsc_output output,
                               void *dst, size_t dst_size);

#define XRSC_MAX_PASSES 16
typedef struct xrsc_pass_timing {
    const char *name; /**< static string, e.g. "trace" */
    double gpu_ms;    /**< from Vulkan timestamp queries */
} xrsc_pass_timing;

/**
 * GPU time per pass of the last frame (Vulkan timestamp queries around each pass of the
 * frame's one command buffer); returns the number of passes written.
 * A renderer reports the same passes in the same order every frame (so they can be indexed by
 * position after the first frame). The first is always "tlas": the update of moved
 * (animated) instances and of the TLAS, about 0 ms when nothing moved (static scenes, or the
 * same display time as the last frame). Then the method's passes: `spp` and `primary` have
 * one, "trace" (both eyes); `samplecache` has "reproject" (with the trace mask), "density",
 * "trace", "shade", "reconstruct" (`hybrid` the same); `hashcache` has "trace", "shade". With
 * TAA on (::xrsc_taa_options), "taa" follows them (its copies and dispatch); with a stereo blend
 * other than none, "blend" comes last (the copy of the colour and the blend dispatch).
 * Read-back copies for xrsc_renderer_read are not timed.
 */
uint32_t xrsc_renderer_timings(const xrsc_renderer *renderer, xrsc_pass_timing *out,
                               uint32_t max_count);
/** Rays traced in the last frame (primary + secondary + shadow), for Mrays/s. */
uint64_t xrsc_renderer_rays_last_frame(const xrsc_renderer *renderer);

#define XRSC_MAX_COUNTERS 16
/** A method's own statistic of the last frame, e.g. the hash cache's "hc_occupancy". */
typedef struct xrsc_counter {
    const char *name; /**< static string: lower case, digits and '_' (a CSV column) */
    double value;
} xrsc_counter;
/**
 * Method statistics of the last frame (e.g. hash-cache bytes, occupancy, probe lengths and
 * evictions; cache bytes per pixel); returns the number written. A renderer reports the same
 * counters in the same order every frame; 0 when the method has none.
 */
uint32_t xrsc_renderer_counters(const xrsc_renderer *renderer, xrsc_counter *out,
                                uint32_t max_count);

#ifdef __cplusplus
}
#endif
