// SPDX-License-Identifier: MIT
/**
 * @file xrsc_core.c
 * @brief The public API (xrsc.h) on top of the gpu, scene and methods layers.
 */
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_metrics.h" /* XRSC_INSTANCE_FLAG_* (constants only) */

#include "xrsc_core_internal.h"

#include "gpu_scene.h"
#include "mt_hashcache.h"
#include "mt_method.h"
#include "mt_samplecache.h"
#include "sc_scene.h"
#include "st_blend.h"
#include "tf_taa.h"
#include "u_diag.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

/** Default per-eye size of a renderer (xrsc.h). */
#define XRSC_DEFAULT_SIZE_PX 256u

struct xrsc_context {
    gpu_context *gpu;
};

struct xrsc_scene {
    xrsc_context *ctx;
    sc_scene *cpu;
    gpu_scene *gpu;
    bool animated;
    int64_t time_ns; /**< scene time the instances were last evaluated at */
    xrsc_scene_info info;
};

struct xrsc_renderer {
    xrsc_context *ctx;
    xrsc_scene *scene;
    mt_method *method;
    xrsc_renderer_options opt;
    tf_taa *taa;     /**< NULL when TAA is off (after resolving XRSC_TAA_DEFAULT) */
    st_blend *blend; /**< NULL for XRSC_BLEND_NONE */
    mt_post post;    /**< records TAA, then the blend, into the method's frame (env.post) */
};

/* ---- context ---- */

xrsc_result xrsc_context_create(const xrsc_context_options *options, xrsc_context **out_ctx,
                                xrsc_diag *out_diag)
{
    if (!out_ctx)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "out_ctx", "NULL");
    *out_ctx = NULL;
    xrsc_context *ctx = calloc(1, sizeof(*ctx));
    if (!ctx)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    gpu_context_options go = {0};
    if (options) {
        go.device = options->device;
        go.validation = options->validation;
    }
    xrsc_result res = gpu_context_create(&go, &ctx->gpu, out_diag);
    if (res != XRSC_OK) {
        free(ctx);
        return res;
    }
    *out_ctx = ctx;
    return XRSC_OK;
}

void xrsc_context_destroy(xrsc_context **ctx)
{
    if (!ctx || !*ctx)
        return;
    gpu_context_destroy(&(*ctx)->gpu);
    free(*ctx);
    *ctx = NULL;
}

const char *xrsc_context_device_name(const xrsc_context *ctx)
{
    return ctx ? ctx->gpu->properties.deviceName : "";
}

bool xrsc_context_is_cpu(const xrsc_context *ctx) { return ctx && ctx->gpu->is_cpu; }

uint32_t xrsc_context_validation_errors(const xrsc_context *ctx)
{
    return ctx ? ctx->gpu->validation_errors : 0;
}

/* ---- scenes ---- */

static double core_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static void scene_info_fill(const sc_scene *c, xrsc_scene_info *info);

xrsc_result xrsc_scene_load(xrsc_context *ctx, const char *path,
                            const xrsc_scene_options *options, xrsc_scene **out_scene,
                            xrsc_diag *out_diag)
{
    if (!out_scene)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "out_scene", "NULL");
    *out_scene = NULL;
    if (!ctx || !path)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0,
                          ctx ? "path" : "ctx", "NULL");
    xrsc_scene *s = calloc(1, sizeof(*s));
    if (!s)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "out of memory");
    s->ctx = ctx;
    sc_load_options lo = {0};
    if (options) {
        lo.env_set = options->env_set;
        memcpy(lo.environment, options->environment, sizeof(lo.environment));
        lo.keep_triangle_order = options->keep_triangle_order;
        lo.env_map_path = options->env_map_path;
        lo.env_intensity = options->env_intensity;
        lo.env_rotation_deg = options->env_rotation_deg;
        lo.sky = options->sky;
        lo.sky_turbidity = options->sky_turbidity;
        lo.sun_direction_set = options->sun_direction_set;
        memcpy(lo.sun_direction, options->sun_direction, sizeof(lo.sun_direction));
        lo.env_no_importance = options->env_no_importance;
        lo.animation = options->animation;
    }
    double t0 = core_now_ms();
    xrsc_result res = sc_scene_load(path, &lo, &s->cpu, out_diag);
    if (res != XRSC_OK)
        goto fail;
    double t1 = core_now_ms();
    res = gpu_scene_create(ctx->gpu, s->cpu, &s->gpu, out_diag);
    if (res != XRSC_OK)
        goto fail;
    if (options) {
        _Static_assert((int)XRSC_BLAS_UPDATE_REFIT == (int)GPU_BLAS_REFIT &&
                           (int)XRSC_BLAS_UPDATE_REBUILD == (int)GPU_BLAS_REBUILD,
                       "xrsc_blas_update mirrors gpu_blas_mode");
        gpu_scene_set_blas_mode(s->gpu, (gpu_blas_mode)options->blas_update);
    }
    double t2 = core_now_ms();
    for (uint32_t i = 0; i < s->cpu->instance_count; i++)
        s->animated = s->animated || s->cpu->instances[i].animated;
    for (uint32_t i = 0; i < s->cpu->light_count; i++) /* lights on animated nodes move too */
        s->animated = s->animated || s->cpu->lights[i].animated;
    s->animated = s->animated && s->cpu->animation_duration_s > 0.0f;
    s->time_ns = 0; /* sc_scene_load evaluates at time 0 */

    scene_info_fill(s->cpu, &s->info);
    s->info.blas_build_ms = gpu_scene_blas_build_ms(s->gpu);
    s->info.load_gpu_ms = t2 - t1;
    s->info.load_ms = t2 - t0;
    *out_scene = s;
    return XRSC_OK;
fail:
    xrsc_scene_destroy(&s);
    return res;
}

struct gpu_scene *xrsc_scene_gpu(const xrsc_scene *scene) { return scene ? scene->gpu : NULL; }

/** The scene's xrsc_scene_info from its CPU copy (all but blas_build_ms). */
static void scene_info_fill(const sc_scene *c, xrsc_scene_info *info)
{
    memset(info, 0, sizeof(*info));
    info->triangle_count = c->triangle_count;
    info->instance_count = c->instance_count;
    info->material_count = c->material_count;
    info->emitter_count = c->emitter_count;
    info->animation_duration_s = c->animation_duration_s;
    info->has_camera = c->has_camera;
    info->camera_yfov_rad = c->camera_yfov_rad;
    info->camera_aspect_ratio = c->camera_aspect_ratio;
    info->viewpoint.position = (XrVector3f){c->viewpoint_position[0], c->viewpoint_position[1],
                                            c->viewpoint_position[2]};
    info->viewpoint.orientation =
        (XrQuaternionf){c->viewpoint_orientation[0], c->viewpoint_orientation[1],
                        c->viewpoint_orientation[2], c->viewpoint_orientation[3]};
    memcpy(info->bounds_min, c->bounds_min, sizeof(info->bounds_min));
    memcpy(info->bounds_max, c->bounds_max, sizeof(info->bounds_max));
    info->texture_count = c->texture_count;
    info->light_count = c->light_count + (c->sun.present ? 1u : 0u);
    info->camera_count = c->camera_count;
    info->studio_environment = c->env_studio;
    const sc_load_timing *t = &c->load_timing;
    info->load_ms = t->read_ms + t->parse_ms + t->build_ms;
    info->load_parse_ms = t->read_ms + t->parse_ms;
    info->load_geometry_ms = t->geometry_ms;
    info->load_tangents_ms = t->tangents_ms;
    info->load_morton_ms = t->morton_ms;
    info->clip_count = c->clip_count;
    info->clip_playing = c->clip_playing;
}

xrsc_result xrsc_scene_camera(const xrsc_scene *scene, uint32_t index, XrPosef *out_pose,
                              float *out_yfov_rad, xrsc_diag *out_diag)
{
    if (!scene || !out_pose)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0,
                          scene ? "out_pose" : "scene", "NULL");
    const sc_scene *c = scene->cpu;
    if (index >= c->camera_count)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, c->path, 0, "camera",
                          "camera %u does not exist (the scene has %u perspective camera%s)",
                          index, c->camera_count, c->camera_count == 1 ? "" : "s");
    const sc_camera *k = &c->cameras[index];
    out_pose->position = (XrVector3f){k->position[0], k->position[1], k->position[2]};
    out_pose->orientation = (XrQuaternionf){k->orientation[0], k->orientation[1],
                                            k->orientation[2], k->orientation[3]};
    if (out_yfov_rad)
        *out_yfov_rad = k->yfov_rad;
    return XRSC_OK;
}

xrsc_result xrsc_scene_inspect(const char *path, xrsc_scene_info *out_info, xrsc_diag *out_diag)
{
    if (!path || !out_info)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0,
                          path ? "out_info" : "path", "NULL");
    sc_load_options lo = {0};
    sc_scene *c = NULL;
    xrsc_result res = sc_scene_load(path, &lo, &c, out_diag);
    if (res == XRSC_OK)
        scene_info_fill(c, out_info);
    sc_scene_destroy(&c);
    return res;
}

_Static_assert(XRSC_CLIP_NONE == SC_CLIP_NONE && XRSC_CLIP_ALL == SC_CLIP_ALL, "clip ids");
_Static_assert(sizeof(((xrsc_clip_info *)0)->name) == sizeof(((sc_clip *)0)->name), "name");
_Static_assert(sizeof(((xrsc_file_info *)0)->extensions_used) ==
                   sizeof(((sc_file_facts *)0)->extensions_used), "extensions");

xrsc_result xrsc_file_inspect(const char *path, const xrsc_scene_options *options,
                              xrsc_file_info *out_info, xrsc_diag *out_diag)
{
    if (!path || !out_info)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0,
                          path ? "out_info" : "path", "NULL");
    memset(out_info, 0, sizeof(*out_info));
    /* No Morton sort: nothing is traced, and the counts do not depend on the order. */
    sc_load_options lo = {.keep_triangle_order = true,
                          .animation = options ? options->animation : NULL};
    sc_scene *c = NULL;
    xrsc_result res = sc_scene_load(path, &lo, &c, out_diag);
    if (res != XRSC_OK)
        return res;
    scene_info_fill(c, &out_info->scene);
    const sc_file_facts *f = &c->facts;
    out_info->node_count = f->node_count;
    out_info->mesh_count = f->mesh_count;
    out_info->image_count = f->image_count;
    out_info->material_count = f->material_count;
    out_info->skin_count = f->skin_count;
    out_info->morph_target_count = f->morph_target_count;
    out_info->morph_mesh_count = f->morph_mesh_count;
    out_info->clip_count = c->clip_count;
    for (uint32_t i = 0; i < c->clip_count && i < XRSC_FILE_INFO_MAX_CLIPS; i++) {
        xrsc_clip_info *k = &out_info->clips[i];
        memcpy(k->name, c->clips[i].name, sizeof k->name);
        k->duration_s = c->clips[i].duration_s;
        k->channel_count = c->clips[i].channel_count;
    }
    memcpy(out_info->extensions_used, f->extensions_used, sizeof out_info->extensions_used);
    memcpy(out_info->extensions_required, f->extensions_required,
           sizeof out_info->extensions_required);
    sc_scene_destroy(&c);
    return XRSC_OK;
}

void xrsc_scene_destroy(xrsc_scene **scene)
{
    if (!scene || !*scene)
        return;
    xrsc_scene *s = *scene;
    gpu_scene_destroy(s->ctx->gpu, &s->gpu);
    sc_scene_destroy(&s->cpu);
    free(s);
    *scene = NULL;
}

void xrsc_scene_get_info(const xrsc_scene *scene, xrsc_scene_info *out_info)
{
    if (!out_info)
        return;
    if (!scene) {
        memset(out_info, 0, sizeof(*out_info));
        return;
    }
    *out_info = scene->info;
}

/* Material factors only: a texture could vary them per texel, but the case scenes use
 * factors (scenes/README.md). */
#define SPECULAR_METALLIC_MIN 0.5f
#define SPECULAR_ROUGHNESS_MAX 0.5f

bool xrsc_scene_warned(const xrsc_scene *scene, xrsc_result id)
{
    return scene && sc_scene_warned(scene->cpu, id);
}

uint32_t xrsc_scene_instance_flags(const xrsc_scene *scene, uint8_t *out, uint32_t max_count)
{
    if (!scene)
        return 0;
    const sc_scene *s = scene->cpu;
    for (uint32_t i = 0; out && i < s->instance_count && i < max_count; i++) {
        const sc_instance *inst = &s->instances[i];
        const sc_material *m = &s->materials[s->meshes[inst->mesh].material];
        bool glossy = (m->metallic >= SPECULAR_METALLIC_MIN || m->transmission > 0.0f) &&
                      m->roughness < SPECULAR_ROUGHNESS_MAX;
        out[i] = (uint8_t)((inst->animated ? XRSC_INSTANCE_FLAG_OBJECT : 0u) |
                           (glossy ? XRSC_INSTANCE_FLAG_SPECULAR : 0u));
    }
    return s->instance_count;
}

/** Moves animated instances to time_ns (prev transforms keep the last evaluated time's). The
 *  GPU side (instances[] copy, TLAS update) is recorded into the next frame's command buffer
 *  by the method (pass "tlas"). */
static xrsc_result scene_set_time(xrsc_scene *s, int64_t time_ns, xrsc_diag *diag)
{
    if (!s->animated || time_ns == s->time_ns)
        return XRSC_OK;
    sc_scene_evaluate(s->cpu, (double)time_ns * 1e-9);
    s->time_ns = time_ns;
    return gpu_scene_stage_instances(s->ctx->gpu, s->gpu, s->cpu, diag);
}

/* ---- names of the option enums (xrsc.h): one table each, indexed by value ---- */

#define NAMES_COUNT(t) ((int)(sizeof(t) / sizeof((t)[0])))

static const char *const method_names[] = {
    [XRSC_METHOD_SPP] = "spp",         [XRSC_METHOD_PRIMARY] = "primary",
    [XRSC_METHOD_SAMPLECACHE] = "samplecache", [XRSC_METHOD_TAA] = "taa",
    [XRSC_METHOD_HASHCACHE] = "hashcache", [XRSC_METHOD_HYBRID] = "hybrid",
    [XRSC_METHOD_ISRT] = "isrt",
};
_Static_assert(NAMES_COUNT(method_names) == XRSC_METHOD_COUNT, "a name per method");
static const char *const taa_mode_names[] = {
    [XRSC_TAA_DEFAULT] = "default", [XRSC_TAA_OFF] = "off",
    [XRSC_TAA_ON] = "on",           [XRSC_TAA_PFJ23] = "pfj23",
};
static const char *const taa_history_names[] = {
    [XRSC_TAA_HISTORY_DEFAULT] = "default",
    [XRSC_TAA_HISTORY_BILINEAR] = "bilinear",
    [XRSC_TAA_HISTORY_CATMULL_ROM] = "catmull-rom",
};
static const char *const taa_motion_names[] = {
    [XRSC_TAA_MOTION_DEFAULT] = "default", [XRSC_TAA_MOTION_OFF] = "off",
    [XRSC_TAA_MOTION_ON] = "on", [XRSC_TAA_MOTION_EDGES] = "edges",
};
static const char *const blend_names[] = {
    [XRSC_BLEND_NONE] = "none", [XRSC_BLEND_PFJ23] = "pfj23", [XRSC_BLEND_MOMENTS] = "moments",
};
static const char *const blend_estimate_names[] = {
    [XRSC_BLEND_ESTIMATE_SAMPLES] = "samples", [XRSC_BLEND_ESTIMATE_MEAN] = "mean",
};

/** names[value], or NULL for a value outside the table. */
static const char *name_of(const char *const *names, int count, int value)
{
    return value >= 0 && value < count ? names[value] : NULL;
}

/** The value whose name is `name` into *out (when out is not NULL); `unknown` when none is. */
static xrsc_result value_of(const char *const *names, int count, const char *name, int *out,
                            xrsc_result unknown)
{
    for (int i = 0; name && i < count; i++) {
        if (names[i] && !strcmp(name, names[i])) {
            *out = i;
            return XRSC_OK;
        }
    }
    return unknown;
}

/* Defines xrsc_<what>_name and xrsc_<what>_from_name over the table <what>_names. */
#define XRSC_ENUM_NAMES(what, type, unknown)                                                   \
    const char *xrsc_##what##_name(type value)                                                 \
    {                                                                                          \
        return name_of(what##_names, NAMES_COUNT(what##_names), (int)value);                   \
    }                                                                                          \
    xrsc_result xrsc_##what##_from_name(const char *name, type *out)                           \
    {                                                                                          \
        int v = 0;                                                                             \
        xrsc_result res = value_of(what##_names, NAMES_COUNT(what##_names), name, &v, unknown); \
        if (res == XRSC_OK && out)                                                             \
            *out = (type)v;                                                                    \
        return res;                                                                            \
    }

XRSC_ENUM_NAMES(method, xrsc_method, XRSC_ERROR_UNKNOWN_METHOD)
XRSC_ENUM_NAMES(taa_mode, xrsc_taa_mode, XRSC_ERROR_INVALID_ARGUMENT)
XRSC_ENUM_NAMES(taa_history, xrsc_taa_history, XRSC_ERROR_INVALID_ARGUMENT)
XRSC_ENUM_NAMES(taa_motion, xrsc_taa_motion, XRSC_ERROR_INVALID_ARGUMENT)
XRSC_ENUM_NAMES(blend, xrsc_blend, XRSC_ERROR_INVALID_ARGUMENT)
XRSC_ENUM_NAMES(blend_estimate, xrsc_blend_estimate, XRSC_ERROR_INVALID_ARGUMENT)

/** mt_post: the post-passes after the method's last pass, in its command buffer and timer:
 *  TAA (its history is the filtered colour before any blend), then the stereo blend (seed 004
 *  Fig. 1: stereo filtering on top of temporal filtering). Either may be absent. */
static void post_record(void *user, VkCommandBuffer cmd, gpu_timer *timer, const xs_frame *xf)
{
    xrsc_renderer *r = user;
    tf_taa_cmd_record(r->taa, cmd, timer, xf);
    st_blend_cmd_record(r->blend, cmd, timer, xf->eyes);
}

/** XRSC_TAA_DEFAULT per method (xrsc.h): on for `taa`, pfj23 for `hashcache` and `hybrid`
 *  (seed 000 §4), off for the others. */
xrsc_taa_mode xrsc_taa_mode_resolve(xrsc_method method, xrsc_taa_mode mode)
{
    if (mode != XRSC_TAA_DEFAULT)
        return mode;
    if (method == XRSC_METHOD_TAA)
        return XRSC_TAA_ON;
    if (method == XRSC_METHOD_HASHCACHE || method == XRSC_METHOD_HYBRID)
        return XRSC_TAA_PFJ23;
    return XRSC_TAA_OFF;
}

/** The TAA post-pass on the method's colour, depth and hit ids, unless it resolves to off. */
static xrsc_result taa_create(xrsc_renderer *r, xrsc_diag *diag)
{
    r->opt.taa.mode = xrsc_taa_mode_resolve(r->opt.method, r->opt.taa.mode);
    if (r->opt.taa.mode == XRSC_TAA_OFF)
        return XRSC_OK;
    tf_settings set = {.mode = r->opt.taa.mode,
                       .alpha = r->opt.taa.alpha,
                       .history = r->opt.taa.history,
                       .motion = r->opt.taa.motion,
                       .motion_px2 = r->opt.taa.motion_px2,
                       .motion_alpha = r->opt.taa.motion_alpha};
    tf_images imgs = {
        .color = mt_method_output_image(r->method, XRSC_OUTPUT_COLOR),
        .depth = mt_method_output_image(r->method, XRSC_OUTPUT_DEPTH),
        .hitid = mt_method_output_image(r->method, XRSC_OUTPUT_HIT_ID),
    };
    return tf_taa_create(r->ctx->gpu, r->scene->gpu, r->scene->cpu->instance_count,
                         r->opt.width, r->opt.height, &set, &imgs, &r->taa, diag);
}

/** The blend and TAA options are checked before any GPU object is made. */
static xrsc_result renderer_options_check(const xrsc_renderer_options *opt, xrsc_diag *diag)
{
    if ((unsigned)opt->blend > XRSC_BLEND_MOMENTS || !(opt->blend_r >= 0.0f) ||
        !(opt->blend_r <= 1.0f) || (unsigned)opt->blend_estimate > XRSC_BLEND_ESTIMATE_MEAN)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "blend",
                          "blend %d with R = %g, estimate %d (R must be in [0, 1])",
                          (int)opt->blend, (double)opt->blend_r, (int)opt->blend_estimate);
    if ((unsigned)opt->taa.mode > XRSC_TAA_PFJ23 || !(opt->taa.alpha >= 0.0f) ||
        !(opt->taa.alpha <= 1.0f) || (unsigned)opt->taa.history > XRSC_TAA_HISTORY_CATMULL_ROM)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "taa",
                          "TAA mode %d with alpha = %g, history filter %d (alpha must be in "
                          "(0, 1], 0 = default)",
                          (int)opt->taa.mode, (double)opt->taa.alpha, (int)opt->taa.history);
    if ((unsigned)opt->taa.motion > XRSC_TAA_MOTION_EDGES || !(opt->taa.motion_px2 >= 0.0f) ||
        !(opt->taa.motion_alpha >= 0.0f && opt->taa.motion_alpha <= 1.0f))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "taa.motion",
                          "TAA motion rule %d with blur %g px^2, alpha %g (blur >= 0, alpha in "
                          "[0, 1], 0 = default)",
                          (int)opt->taa.motion, (double)opt->taa.motion_px2,
                          (double)opt->taa.motion_alpha);
    return XRSC_OK;
}

/** The method selected by r->opt.method, rendering at r->opt's size into r->method. */
static xrsc_result method_create(xrsc_renderer *r, xrsc_diag *diag)
{
    mt_env env = {
        .gpu = r->ctx->gpu,
        .scene = r->scene->gpu,
        .cpu_scene = r->scene->cpu,
        .width = r->opt.width,
        .height = r->opt.height,
        .seed = r->opt.seed,
        .post = &r->post, /* filled in once TAA and the blend exist */
    };
    switch (r->opt.method) {
    case XRSC_METHOD_SPP:
        return mt_spp_create(&env, &r->opt.spp, &r->method, diag);
    case XRSC_METHOD_PRIMARY:
        return mt_primary_create(&env, &r->method, diag);
    case XRSC_METHOD_SAMPLECACHE:
        return mt_samplecache_create(&env, &r->opt.samplecache, &r->method, diag);
    case XRSC_METHOD_TAA:
        return mt_taa_create(&env, &r->opt.spp, &r->method, diag);
    case XRSC_METHOD_ISRT:
        return mt_isrt_create(&env, &r->opt.isrt, &r->opt.samplecache, &r->method, diag);
    case XRSC_METHOD_HASHCACHE:
        return mt_hashcache_create(&env, &r->opt.hashcache, &r->method, diag);
    case XRSC_METHOD_HYBRID:
        return mt_hybrid_create(&env, &r->opt.samplecache, &r->opt.hashcache, &r->method, diag);
    default:
        return u_diag_set(diag, XRSC_ERROR_UNKNOWN_METHOD, "", 0, "method", "unknown method %d",
                          (int)r->opt.method);
    }
}

/** The stereo blend post-pass on the method's colour, depth and moments, unless it is none. */
static xrsc_result blend_create(xrsc_renderer *r, xrsc_diag *diag)
{
    if (r->opt.blend == XRSC_BLEND_NONE)
        return XRSC_OK;
    st_settings set = {.blend = r->opt.blend,
                       .r = r->opt.blend_r,
                       .pixel_mean = r->opt.blend_estimate == XRSC_BLEND_ESTIMATE_MEAN,
                       .instance_test = r->opt.blend_instance_test};
    st_images imgs = {
        .color = mt_method_output_image(r->method, XRSC_OUTPUT_COLOR),
        .depth = mt_method_output_image(r->method, XRSC_OUTPUT_DEPTH),
        .mu1 = mt_method_output_image(r->method, XRSC_OUTPUT_MU1),
        .mu2 = mt_method_output_image(r->method, XRSC_OUTPUT_MU2),
        .hitid = mt_method_output_image(r->method, XRSC_OUTPUT_HIT_ID),
    };
    return st_blend_create(r->ctx->gpu, r->opt.width, r->opt.height, &set, &imgs, &r->blend, diag);
}

/* ---- renderers ---- */

xrsc_result xrsc_renderer_create(xrsc_context *ctx, xrsc_scene *scene,
                                 const xrsc_renderer_options *options,
                                 xrsc_renderer **out_renderer, xrsc_diag *out_diag)
{
    if (!out_renderer)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "out_renderer", "NULL");
    *out_renderer = NULL;
    if (!ctx || !scene)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, ctx ? "scene" : "ctx",
                          "NULL");
    xrsc_renderer *r = calloc(1, sizeof(*r));
    if (!r)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    r->ctx = ctx;
    r->scene = scene;
    if (options)
        r->opt = *options;
    if (r->opt.width == 0)
        r->opt.width = XRSC_DEFAULT_SIZE_PX;
    if (r->opt.height == 0)
        r->opt.height = XRSC_DEFAULT_SIZE_PX;
    xrsc_result res;
    if ((res = renderer_options_check(&r->opt, out_diag)) != XRSC_OK ||
        (res = method_create(r, out_diag)) != XRSC_OK) {
        free(r);
        return res;
    }
    if ((res = taa_create(r, out_diag)) != XRSC_OK) {
        mt_method_destroy(&r->method);
        free(r);
        return res;
    }
    if ((res = blend_create(r, out_diag)) != XRSC_OK) {
        mt_method_destroy(&r->method);
        tf_taa_destroy(&r->taa);
        free(r);
        return res;
    }
    if (r->taa && r->blend) /* TAA's history is a copy of its output: the blend reads it */
        st_blend_use_source(r->blend, tf_taa_history(r->taa));
    if (r->taa || r->blend)
        r->post = (mt_post){.record = post_record, .user = r};
    *out_renderer = r;
    return XRSC_OK;
}

void xrsc_renderer_destroy(xrsc_renderer **renderer)
{
    if (!renderer || !*renderer)
        return;
    mt_method_destroy(&(*renderer)->method);
    tf_taa_destroy(&(*renderer)->taa);
    st_blend_destroy(&(*renderer)->blend);
    free(*renderer);
    *renderer = NULL;
}

xrsc_result xrsc_renderer_render(xrsc_renderer *renderer, const xrsc_frame *frame)
{
    if (!renderer || !frame)
        return XRSC_ERROR_INVALID_ARGUMENT;
    xrsc_result res = scene_set_time(renderer->scene, frame->display_time_ns, NULL);
    if (res != XRSC_OK)
        return res;
    return mt_method_render(renderer->method, frame, NULL);
}

size_t xrsc_renderer_output_size(const xrsc_renderer *renderer, xrsc_output output)
{
    return renderer ? mt_method_output_size(renderer->method, output) : 0;
}

xrsc_result xrsc_renderer_read(xrsc_renderer *renderer, uint32_t eye, xrsc_output output,
                               void *dst, size_t dst_size)
{
    if (!renderer)
        return XRSC_ERROR_INVALID_ARGUMENT;
    return mt_method_read(renderer->method, eye, output, dst, dst_size, NULL);
}

uint32_t xrsc_renderer_timings(const xrsc_renderer *renderer, xrsc_pass_timing *out,
                               uint32_t max_count)
{
    if (!renderer || !out)
        return 0;
    return mt_method_timings(renderer->method, out, max_count);
}

uint64_t xrsc_renderer_rays_last_frame(const xrsc_renderer *renderer)
{
    return renderer ? mt_method_rays_last_frame(renderer->method) : 0;
}

uint32_t xrsc_renderer_counters(const xrsc_renderer *renderer, xrsc_counter *out,
                                uint32_t max_count)
{
    if (!renderer || !out)
        return 0;
    return mt_method_counters(renderer->method, out, max_count);
}

/* ---- internal (xrsc_core_internal.h): the OpenXR front end's access ---- */

xrsc_result xrsc_context_create_hooked(const xrsc_context_options *options,
                                       const gpu_context_hooks *hooks, xrsc_context **out_ctx,
                                       xrsc_diag *out_diag)
{
    if (!out_ctx)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "out_ctx", "NULL");
    *out_ctx = NULL;
    xrsc_context *ctx = calloc(1, sizeof(*ctx));
    if (!ctx)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    gpu_context_options go = {.validation = options && options->validation,
                              .device = options ? options->device : NULL};
    xrsc_result res = gpu_context_create_hooked(&go, hooks, &ctx->gpu, out_diag);
    if (res != XRSC_OK) {
        free(ctx);
        return res;
    }
    *out_ctx = ctx;
    return XRSC_OK;
}

gpu_context *xrsc_context_gpu(xrsc_context *ctx) { return ctx ? ctx->gpu : NULL; }

void xrsc_renderer_size(const xrsc_renderer *renderer, uint32_t *out_width, uint32_t *out_height)
{
    if (out_width)
        *out_width = renderer ? renderer->opt.width : 0;
    if (out_height)
        *out_height = renderer ? renderer->opt.height : 0;
}

const gpu_image *xrsc_renderer_output_image(const xrsc_renderer *renderer, xrsc_output output)
{
    return renderer ? mt_method_output_image(renderer->method, output) : NULL;
}
