// SPDX-License-Identifier: MIT
/**
 * @file gpu_scene.c
 * @brief Scene upload, BLAS per mesh, TLAS per scene with update.
 */
#include "gpu_scene.h"

#include "gpu_deform.h"
#include "gpu_timer.h"
#include "u_diag.h"
#include "xrsc_shared.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(sc_vertex) == 56 && sizeof(xs_vertex) == 64, "vertex sizes");
_Static_assert(SC_UV1_TRANSMISSION == XS_UV1_TRANSMISSION && SC_UV1_SPECULAR == XS_UV1_SPECULAR &&
                   SC_UV1_SPECULAR_COLOR == XS_UV1_SPECULAR_COLOR &&
                   SC_UV1_CLEARCOAT == XS_UV1_CLEARCOAT &&
                   SC_UV1_CLEARCOAT_ROUGH == XS_UV1_CLEARCOAT_ROUGH &&
                   SC_UV1_SHEEN_COLOR == XS_UV1_SHEEN_COLOR &&
                   SC_UV1_SHEEN_ROUGH == XS_UV1_SHEEN_ROUGH,
               "TEXCOORD_1 mask bits");
_Static_assert(SC_TEX_SLOTS == XS_TEX_SLOTS && SC_TEX_NORMAL == XS_TEX_NORMAL &&
                   SC_TEX_BASE == XS_TEX_BASE && SC_TEX_EMISSION == XS_TEX_EMISSION &&
                   SC_TEX_METAL_ROUGH == XS_TEX_METAL_ROUGH,
               "texture slots");
_Static_assert(SC_NO_TEXTURE == XS_NO_TEXTURE, "no-texture markers agree");

/** Buffers read by the AS builder and by shaders. */
#define GPU_SCENE_INPUT_USAGE                                                                      \
    (VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |              \
     VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR)

/** Distinct sc_sampler values: 3 wrap modes per axis x 2 mag x 2 min filters. */
#define GPU_SAMPLER_KINDS (3 * 3 * 2 * 2)

typedef struct gpu_accel {
    gpu_buffer buffer;
    VkAccelerationStructureKHR handle;
    VkDeviceAddress address;
} gpu_accel;

struct gpu_scene {
    gpu_buffer vertices, indices, instances, materials, emitters;
    gpu_buffer lights;  /**< xs_light[], host-visible: rewritten when lights move */
    uint32_t light_count;
    bool lights_animated;
    gpu_buffer env_map; /**< float[]: XS_ENV_* layout of xrsc_shared.h (4 zeros without a map) */
    gpu_image *textures;
    uint32_t texture_count;
    gpu_image white;
    VkSampler sampler; /**< linear, repeat: the white fill's */
    /** One VkSampler per distinct glTF sampler (wrap u, wrap v, mag, min: see sampler_key),
     *  created on first use; tex_samplers[i] is textures[i]'s (not owned). */
    VkSampler sampler_table[GPU_SAMPLER_KINDS];
    VkSampler *tex_samplers;

    gpu_accel *blas;
    uint32_t blas_count;
    gpu_accel tlas;
    gpu_buffer tlas_instances; /**< VkAccelerationStructureInstanceKHR[], host-visible */
    gpu_buffer instances_staging; /**< xs_instance[], host-visible: source of updates */
    bool update_pending;          /**< staged by gpu_scene_stage_instances, not yet recorded */
    gpu_buffer tlas_scratch;   /**< max(build, update) scratch, kept for updates */
    VkDeviceAddress tlas_scratch_address; /**< aligned */
    uint32_t instance_count;

    xs_instance *host_instances; /**< CPU copy of instances[] */
    uint32_t emitter_count;
    uint32_t glass_instance_count; /**< instances in XS_CULL_GLASS (xs_frame.glass_instances) */
    bool animated; /**< an instance has animated transforms (gpu_scene_animated) */
    double blas_ms, tlas_ms;

    /* skins and morph targets (gpu_deform.h): posed into vertices[], then their BLAS updated */
    gpu_deform *deform;           /**< NULL when no mesh deforms */
    bool deform_pending;          /**< a pose staged, not yet recorded */
    bool prev_stale;              /**< prev[] holds the pose before the last step: a frame
                                   *   without a new pose sets prev[] = the pose (no motion) */
    bool deform_off;              /**< tests: the pose is staged but never recorded */
    bool deform_rebuild;          /**< the pending BLAS update rebuilds (else refits) */
    gpu_blas_mode blas_mode;
    uint32_t deform_mesh_count;
    sc_mesh *deform_meshes;       /**< copy of each deformed mesh (its BLAS inputs) */
    uint32_t *deform_blas;        /**< its BLAS (mesh index) */
    gpu_buffer deform_scratch;    /**< per deformed BLAS: max(build, update) scratch */
    VkDeviceSize *deform_scratch_offsets;
    uint32_t blas_rebuilds, blas_refits;
};

static VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

/* ---- small matrix helpers (column-major) ---- */

static void normal_matrix(const float m[16], float out[16])
{
    /* inverse transpose of the upper 3x3 = cofactor matrix / det */
    float a = m[0], b = m[4], c = m[8];
    float d = m[1], e = m[5], f = m[9];
    float g = m[2], h = m[6], i = m[10];
    float cof[3][3] = {
        {e * i - f * h, -(d * i - f * g), d * h - e * g},
        {-(b * i - c * h), a * i - c * g, -(a * h - b * g)},
        {b * f - c * e, -(a * f - c * d), a * e - b * d},
    };
    float det = a * cof[0][0] + b * cof[0][1] + c * cof[0][2];
    float inv_det = det != 0.0f ? 1.0f / det : 0.0f;
    memset(out, 0, 16 * sizeof(float));
    /* (M^-1)^T = cof / det; cof[r][col] is for row r, column col of M */
    for (int r = 0; r < 3; r++)
        for (int col = 0; col < 3; col++)
            out[col * 4 + r] = cof[r][col] * inv_det;
    out[15] = 1.0f;
}

static void fill_instance_transform(const float world[16], VkTransformMatrixKHR *t)
{
    for (int r = 0; r < 3; r++)
        for (int col = 0; col < 4; col++)
            t->matrix[r][col] = world[col * 4 + r];
}

/** XS_MAT_GLASS_SHADOW's rule (xrsc_shared.h): a thin-walled material whose smooth
 *  transmission may let shadow rays through somewhere (the shader decides per point from the
 *  textured values, which only lower the factors). */
static bool material_glass_shadow(const sc_material *m)
{
    bool smooth_dielectric = m->roughness < XS_GLASS_SMOOTH_ROUGHNESS && m->metallic < 1.0f;
    return m->alpha_mode != SC_ALPHA_BLEND && !m->unlit && m->transmission > 0.0f &&
           !(m->thickness > 0.0f) &&
           (smooth_dielectric || m->metal_rough_tex != SC_NO_TEXTURE);
}

static void write_tlas_instances(gpu_scene *gs, const sc_scene *scene)
{
    gs->glass_instance_count = 0;
    VkAccelerationStructureInstanceKHR *inst = gs->tlas_instances.mapped;
    for (uint32_t i = 0; i < scene->instance_count; i++) {
        const sc_instance *si = &scene->instances[i];
        memset(&inst[i], 0, sizeof(inst[i]));
        fill_instance_transform(si->world, &inst[i].transform);
        inst[i].instanceCustomIndex = i;
        const sc_material *mat = &scene->materials[scene->meshes[si->mesh].material];
        inst[i].mask = mat->alpha_mode == SC_ALPHA_BLEND ? XS_CULL_BLEND
                       : material_glass_shadow(mat)     ? XS_CULL_GLASS
                                                        : XS_CULL_SOLID;
        gs->glass_instance_count += inst[i].mask == XS_CULL_GLASS ? 1u : 0u;
        inst[i].instanceShaderBindingTableRecordOffset = 0;
        /* Facing: no FLIP_FACING / FRONT_COUNTERCLOCKWISE bit. Vulkan determines facing in
         * object space, and its default front (clockwise in a left-handed system) is the
         * counter-clockwise side in glTF's right-handed coordinates: the glTF front, also for
         * mirrored instances (glTF 2.0 "Meshes": a negative determinant makes the front
         * clockwise in world space, i.e. still counter-clockwise in object space).
         * Checked by test_gpu_primary's test_front_face (the bit makes it fail).
         * Single-sided materials leave back faces to the ray's cull flag (camera rays cull them,
         * as glTF viewers do); MASK and BLEND instances are not opaque, so the any-hit shader
         * (hit.rahit) runs for them, and for them only: the BLAS geometry stays opaque. */
        VkGeometryInstanceFlagsKHR f = 0;
        if (mat->double_sided)
            f |= VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
        if (mat->alpha_mode != SC_ALPHA_OPAQUE)
            f |= VK_GEOMETRY_INSTANCE_FORCE_NO_OPAQUE_BIT_KHR;
        inst[i].flags = f;
        inst[i].accelerationStructureReference = gs->blas[si->mesh].address;
    }
}

/* ---- upload of the shared buffers ---- */

/** Vertices converted to xs_vertex per chunk of GPU_UPLOAD_CHUNK_BYTES and uploaded,
 *  so that no whole converted copy is held next to the scene's. */
static xrsc_result upload_vertices(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                   xrsc_diag *diag)
{
    VkDeviceSize bytes = (VkDeviceSize)scene->vertex_count * sizeof(xs_vertex);
    /* TRANSFER_SRC: tests read the posed vertices back (gpu_scene_download_vertices) */
    xrsc_result res = gpu_buffer_create_with_data(ctx, NULL, bytes,
                                                  GPU_SCENE_INPUT_USAGE |
                                                      VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                  &gs->vertices, diag);
    const uint32_t per_chunk = (uint32_t)(GPU_UPLOAD_CHUNK_BYTES / sizeof(xs_vertex));
    xs_vertex *v = res == XRSC_OK ? malloc((size_t)per_chunk * sizeof(*v)) : NULL;
    if (res == XRSC_OK && !v)
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    for (uint32_t first = 0; res == XRSC_OK && first < scene->vertex_count; first += per_chunk) {
        uint32_t n = scene->vertex_count - first < per_chunk ? scene->vertex_count - first
                                                             : per_chunk;
        for (uint32_t i = 0; i < n; i++) {
            const sc_vertex *s = &scene->vertices[first + i];
            v[i].position_u = (xs_vec4){s->position[0], s->position[1], s->position[2], s->uv[0]};
            v[i].normal_v = (xs_vec4){s->normal[0], s->normal[1], s->normal[2], s->uv[1]};
            v[i].tangent = (xs_vec4){s->tangent[0], s->tangent[1], s->tangent[2], s->tangent[3]};
            v[i].uv1 = (xs_vec4){s->uv1[0], s->uv1[1], 0.0f, 0.0f};
        }
        res = gpu_buffer_upload(ctx, &gs->vertices, (VkDeviceSize)first * sizeof(*v), v,
                                (VkDeviceSize)n * sizeof(*v), diag);
    }
    free(v);
    return res;
}

static xrsc_result upload_geometry(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                   xrsc_diag *diag)
{
    /* sc_scene indices are already absolute (sc_scene.h); check they stay in their mesh,
     * then upload them as they are. */
    for (uint32_t m = 0; m < scene->mesh_count; m++) {
        const sc_mesh *mesh = &scene->meshes[m];
        for (uint32_t k = 0; k < mesh->index_count; k++) {
            uint32_t vi = scene->indices[mesh->first_index + k];
            if (vi < mesh->first_vertex || vi - mesh->first_vertex >= mesh->vertex_count)
                return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, scene->path, 0, "indices",
                                  "mesh %u index %u outside its vertices [%u, %u)", m, vi,
                                  mesh->first_vertex, mesh->first_vertex + mesh->vertex_count);
        }
    }
    xrsc_result res = gpu_buffer_create_with_data(
        ctx, scene->indices, (VkDeviceSize)scene->index_count * sizeof(uint32_t),
        GPU_SCENE_INPUT_USAGE, &gs->indices, diag);
    if (res == XRSC_OK)
        res = upload_vertices(ctx, gs, scene, diag);
    return res;
}

/** A texture index for the GPU: XS_NO_TEXTURE unless it names one of the scene's textures. */
static uint32_t gpu_texture_index(const sc_scene *scene, uint32_t t)
{
    return t < scene->texture_count ? t : XS_NO_TEXTURE;
}

/** xs_material's KHR_materials_specular / _clearcoat / _sheen / _volume fields. */
static void upload_material_extensions(const sc_scene *scene, const sc_material *s,
                                       xs_material *d)
{
    d->specular = (xs_vec4){s->specular_color[0], s->specular_color[1], s->specular_color[2],
                            s->specular};
    d->sheen = (xs_vec4){s->sheen_color[0], s->sheen_color[1], s->sheen_color[2],
                         s->sheen_roughness};
    d->attenuation = (xs_vec4){s->sigma_a[0], s->sigma_a[1], s->sigma_a[2], s->thickness};
    d->clearcoat = s->clearcoat;
    d->clearcoat_roughness = s->clearcoat_roughness;
    d->transmission_tex = gpu_texture_index(scene, s->transmission_tex);
    d->specular_tex = gpu_texture_index(scene, s->specular_tex);
    d->specular_color_tex = gpu_texture_index(scene, s->specular_color_tex);
    d->clearcoat_tex = gpu_texture_index(scene, s->clearcoat_tex);
    d->clearcoat_rough_tex = gpu_texture_index(scene, s->clearcoat_rough_tex);
    d->sheen_color_tex = gpu_texture_index(scene, s->sheen_color_tex);
    d->sheen_rough_tex = gpu_texture_index(scene, s->sheen_rough_tex);
}

static xrsc_result upload_materials(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                    xrsc_diag *diag)
{
    uint32_t n = scene->material_count;
    xs_material *mats = calloc(n ? n : 1, sizeof(*mats));
    if (!mats)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    for (uint32_t i = 0; i < n; i++) {
        const sc_material *s = &scene->materials[i];
        xs_material *d = &mats[i];
        d->base_color = (xs_vec4){s->base_color[0], s->base_color[1], s->base_color[2],
                                  s->base_color[3]};
        d->emission = (xs_vec4){s->emission[0], s->emission[1], s->emission[2], 0.0f};
        d->metallic = s->metallic;
        d->roughness = s->roughness;
        d->transmission = s->transmission;
        d->ior = s->ior;
        d->base_color_tex = s->base_color_tex < scene->texture_count ? s->base_color_tex
                                                                     : XS_NO_TEXTURE;
        d->metal_rough_tex = s->metal_rough_tex < scene->texture_count ? s->metal_rough_tex
                                                                       : XS_NO_TEXTURE;
        d->emission_tex = s->emission_tex < scene->texture_count ? s->emission_tex
                                                                 : XS_NO_TEXTURE;
        d->flags = (s->double_sided ? XS_MAT_DOUBLE_SIDED : 0u) | (s->unlit ? XS_MAT_UNLIT : 0u) |
                   (s->alpha_mode == SC_ALPHA_MASK ? XS_MAT_ALPHA_MASK : 0u) |
                   (s->alpha_mode == SC_ALPHA_BLEND ? XS_MAT_ALPHA_BLEND : 0u) |
                   (material_glass_shadow(s) ? XS_MAT_GLASS_SHADOW : 0u);
        d->alpha_cutoff = s->alpha_cutoff;
        d->uv1_mask = s->uv1_mask;
        d->normal_tex = s->normal_tex < scene->texture_count ? s->normal_tex : XS_NO_TEXTURE;
        d->normal_scale = s->normal_scale;
        for (int k = 0; k < XS_TEX_SLOTS; k++) {
            const float *m = s->uv_transform[k];
            d->uv_rows[2 * k] = (xs_vec4){m[0], m[1], m[2], 0.0f};
            d->uv_rows[2 * k + 1] = (xs_vec4){m[3], m[4], m[5], 0.0f};
        }
        upload_material_extensions(scene, s, d);
    }
    xrsc_result res = gpu_buffer_create_with_data(
        ctx, mats, (VkDeviceSize)n * sizeof(*mats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
        &gs->materials, diag);
    free(mats);
    return res;
}

/** Triangles of instance i's mesh. */
static uint32_t instance_triangles(const sc_scene *scene, uint32_t i)
{
    return scene->meshes[scene->instances[i].mesh].index_count / 3;
}

/** Each instance's first entry in the emitter table (XS_NO_EMITTER: no emissive triangle):
 *  every triangle of an instance with an emitter gets an entry; returns the entry count. */
static uint64_t emitter_bases(const sc_scene *scene, bool *emissive, uint32_t *base)
{
    uint32_t ni = scene->instance_count;
    for (uint32_t e = 0; e < scene->emitter_count; e++)
        if (scene->emitters[e].instance < ni)
            emissive[scene->emitters[e].instance] = true;
    uint64_t count = 0;
    for (uint32_t i = 0; i < ni; i++) {
        base[i] = XS_NO_EMITTER;
        if (emissive[i]) {
            base[i] = (uint32_t)count;
            count += instance_triangles(scene, i);
        }
    }
    return count;
}

/** The table's entries: instance and primitive of each, pmf proportional to the triangle's
 *  power (uniform when no triangle has any), and the running cdf ending at exactly 1. */
static void fill_emitters(const sc_scene *scene, const uint32_t *base, xs_emitter *em,
                          uint64_t count)
{
    uint32_t ni = scene->instance_count;
    for (uint32_t i = 0; i < ni; i++) {
        if (base[i] == XS_NO_EMITTER)
            continue;
        uint32_t tris = instance_triangles(scene, i);
        for (uint32_t t = 0; t < tris; t++) {
            em[base[i] + t].instance = i;
            em[base[i] + t].primitive = t;
        }
    }
    double total = 0.0;
    for (uint32_t e = 0; e < scene->emitter_count; e++) {
        const sc_emitter *s = &scene->emitters[e];
        if (s->instance >= ni || base[s->instance] == XS_NO_EMITTER)
            continue;
        if (s->primitive >= instance_triangles(scene, s->instance) || !(s->power > 0.0f))
            continue;
        em[base[s->instance] + s->primitive].pmf = s->power;
        total += s->power;
    }
    double cdf = 0.0;
    for (uint64_t k = 0; k < count; k++) {
        double pmf = total > 0.0 ? em[k].pmf / total : 1.0 / (double)count;
        em[k].pmf = (float)pmf;
        cdf += pmf;
        em[k].cdf = (float)cdf;
    }
    if (count)
        em[count - 1].cdf = 1.0f;
}

static xrsc_result upload_emitters(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                   xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    uint32_t ni = scene->instance_count;
    bool *emissive = calloc(ni ? ni : 1, sizeof(*emissive));
    uint32_t *base = calloc(ni ? ni : 1, sizeof(*base));
    xs_emitter *em = NULL;
    if (!emissive || !base) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
        goto done;
    }
    uint64_t count = emitter_bases(scene, emissive, base);
    em = calloc(count ? count : 1, sizeof(*em));
    if (!em) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
        goto done;
    }
    fill_emitters(scene, base, em, count);
    for (uint32_t i = 0; i < ni; i++)
        gs->host_instances[i].emitter_base = base[i];
    gs->emitter_count = (uint32_t)count;
    res = gpu_buffer_create_with_data(ctx, em, count * sizeof(*em),
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, &gs->emitters, diag);
done:
    free(emissive);
    free(base);
    free(em);
    return res;
}

/* Luminance weights (Rec. 709) of the lights' power estimate, as sc_scene's emitters. */
#define GPU_LUMA_R 0.2126
#define GPU_LUMA_G 0.7152
#define GPU_LUMA_B 0.0722
#define GPU_PI 3.14159265358979323846
/* glTF's implementation note: the spot's cos range never below this (no division by 0). */
#define GPU_SPOT_MIN_COS_RANGE 0.001

/** Power estimate of light l for its pick probability (gpu_scene.h): point 4 pi I, spot
 *  2 pi (1 - cos(mean cone angle)) I, directional E x pi r^2 of the scene's bounding sphere. */
static double light_power(const sc_scene *scene, const sc_light *l)
{
    const float *c = l->intensity;
    double lum = GPU_LUMA_R * c[0] + GPU_LUMA_G * c[1] + GPU_LUMA_B * c[2];
    if (l->type == SC_LIGHT_POINT)
        return 4.0 * GPU_PI * lum;
    if (l->type == SC_LIGHT_SPOT)
        return 2.0 * GPU_PI * (1.0 - cos(0.5 * (l->inner_cone_rad + l->outer_cone_rad))) * lum;
    double r2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double h = 0.5 * ((double)scene->bounds_max[k] - (double)scene->bounds_min[k]);
        r2 += h * h;
    }
    return GPU_PI * r2 * lum;
}

/** Unit column k (0 x, 1 y, 2 z) of a column-major matrix, times sign; +Z when degenerate. */
static xs_vec4 unit_axis(const float m[16], int k, float sign)
{
    float x = m[4 * k], y = m[4 * k + 1], z = m[4 * k + 2];
    float n = sqrtf(x * x + y * y + z * z);
    if (!(n > 1e-20f) || !isfinite(n))
        return (xs_vec4){0.0f, 0.0f, sign, 0.0f};
    return (xs_vec4){sign * x / n, sign * y / n, sign * z / n, 0.0f};
}

/** The scene's lights at their nodes' current world transforms (pmf and cdf in xl[]). */
static void fill_lights(const sc_scene *scene, xs_light *xl)
{
    double total = 0.0;
    for (uint32_t i = 0; i < scene->light_count; i++) {
        const sc_light *l = &scene->lights[i];
        const float *w = scene->nodes[l->node].world;
        xs_light *o = &xl[i];
        o->type = l->type == SC_LIGHT_DIRECTIONAL ? XS_LIGHT_DIRECTIONAL
                  : l->type == SC_LIGHT_POINT     ? XS_LIGHT_POINT
                                                  : XS_LIGHT_SPOT;
        o->position = (xs_vec4){w[12], w[13], w[14], l->range_m};
        /* a light shines along its node's -Z; a directional one is stored towards it (+Z) */
        o->direction = unit_axis(w, 2, l->type == SC_LIGHT_DIRECTIONAL ? 1.0f : -1.0f);
        double ci = cos((double)l->inner_cone_rad), co = cos((double)l->outer_cone_rad);
        double scale = 1.0 / fmax(GPU_SPOT_MIN_COS_RANGE, ci - co);
        o->spot_scale = (float)scale;
        o->spot_offset = (float)(-co * scale);
        double p = light_power(scene, l);
        o->intensity = (xs_vec4){l->intensity[0], l->intensity[1], l->intensity[2],
                                 (float)(p > 0.0 ? p : 0.0)};
        total += p > 0.0 ? p : 0.0;
    }
    double cdf = 0.0;
    for (uint32_t i = 0; i < scene->light_count; i++) {
        double pmf = total > 0.0 ? xl[i].intensity.w / total : 1.0 / scene->light_count;
        xl[i].intensity.w = (float)pmf;
        cdf += pmf;
        xl[i].cdf = (float)cdf;
    }
    if (scene->light_count)
        xl[scene->light_count - 1].cdf = 1.0f;
}

/** XS_BIND_LIGHTS: host-visible (persistently mapped), so moving lights are rewritten in place
 *  by gpu_scene_stage_instances; one unused entry when the scene has none. */
static xrsc_result upload_lights(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                 xrsc_diag *diag)
{
    uint32_t n = scene->light_count;
    xrsc_result res = gpu_buffer_create(ctx, (VkDeviceSize)(n ? n : 1) * sizeof(xs_light),
                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEMORY_UPLOAD,
                                        &gs->lights, diag);
    if (res != XRSC_OK)
        return res;
    memset(gs->lights.mapped, 0, (size_t)(n ? n : 1) * sizeof(xs_light));
    fill_lights(scene, gs->lights.mapped);
    gpu_buffer_flush(ctx, &gs->lights);
    gs->light_count = n;
    for (uint32_t i = 0; i < n; i++)
        gs->lights_animated = gs->lights_animated || scene->lights[i].animated;
    return XRSC_OK;
}

/** The environment map and its cdfs packed as XS_ENV_* says (sc_env.h builds them). */
static xrsc_result upload_env_map(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                  xrsc_diag *diag)
{
    const sc_env_map *m = &scene->env_map;
    uint32_t n = m->width * m->height, h = m->height;
    size_t floats = n ? XS_ENV_FLOATS(n, h) : 4u;
    float *data = calloc(floats, sizeof(float));
    if (!data)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "environment",
                          "out of memory");
    if (n) {
        memcpy(data, m->texels, (size_t)n * 4 * sizeof(float));
        memcpy(data + XS_ENV_MARGINAL(n), m->marginal_cdf, (size_t)h * sizeof(float));
        memcpy(data + XS_ENV_CONDITIONAL(n, h), m->conditional_cdf, (size_t)n * sizeof(float));
    }
    xrsc_result res = gpu_buffer_create_with_data(ctx, data, floats * sizeof(float),
                                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                  &gs->env_map, diag);
    free(data);
    return res;
}

static uint32_t sampler_key(sc_sampler s)
{
    return (((uint32_t)s.wrap_u * 3 + (uint32_t)s.wrap_v) * 2 + (s.mag_nearest ? 1 : 0)) * 2 +
           (s.min_nearest ? 1 : 0);
}

static VkSamplerAddressMode vk_wrap(sc_wrap w)
{
    return w == SC_WRAP_CLAMP_TO_EDGE       ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
           : w == SC_WRAP_MIRRORED_REPEAT ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                          : VK_SAMPLER_ADDRESS_MODE_REPEAT;
}

/** The VkSampler of a glTF sampler, one per distinct value (sampler_table). */
static xrsc_result texture_sampler(gpu_context *ctx, gpu_scene *gs, sc_sampler s, VkSampler *out,
                                   xrsc_diag *diag)
{
    uint32_t key = sampler_key(s);
    if (key >= GPU_SAMPLER_KINDS) key = 0; /* values outside the enums: the default */
    if (!gs->sampler_table[key]) {
        xrsc_result res = gpu_sampler_create_mode(
            ctx, vk_wrap(s.wrap_u), vk_wrap(s.wrap_v),
            s.mag_nearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR,
            s.min_nearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR, &gs->sampler_table[key], diag);
        if (res != XRSC_OK) return res;
    }
    *out = gs->sampler_table[key];
    return XRSC_OK;
}

static xrsc_result upload_textures(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                   xrsc_diag *diag)
{
    static const uint8_t white[4] = {255, 255, 255, 255};
    xrsc_result res = gpu_image_create_texture(ctx, 1, 1, false, white, &gs->white, diag);
    if (res != XRSC_OK)
        return res;
    res = gpu_sampler_create(ctx, &gs->sampler, diag);
    if (res != XRSC_OK)
        return res;
    uint32_t n = scene->texture_count;
    if (n > XS_MAX_TEXTURES) {
        U_LOG_W("%s: %u textures, only the first %u are used", scene->path, n, XS_MAX_TEXTURES);
        n = XS_MAX_TEXTURES;
    }
    gs->textures = calloc(n ? n : 1, sizeof(*gs->textures));
    gs->tex_samplers = calloc(n ? n : 1, sizeof(*gs->tex_samplers));
    if (!gs->textures || !gs->tex_samplers)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    for (uint32_t i = 0; i < n; i++) {
        const sc_texture *t = &scene->textures[i];
        if (!t->rgba8 || t->width == 0 || t->height == 0)
            res = gpu_image_create_texture(ctx, 1, 1, false, white, &gs->textures[i], diag);
        else
            res = gpu_image_create_texture(ctx, t->width, t->height, t->srgb, t->rgba8,
                                           &gs->textures[i], diag);
        if (res != XRSC_OK)
            return res;
        gs->texture_count = i + 1;
        if ((res = texture_sampler(ctx, gs, t->sampler, &gs->tex_samplers[i], diag)) != XRSC_OK)
            return res;
    }
    return XRSC_OK;
}

static void fill_host_instances(gpu_scene *gs, const sc_scene *scene, bool keep_prev)
{
    for (uint32_t i = 0; i < scene->instance_count; i++) {
        const sc_instance *si = &scene->instances[i];
        xs_instance *d = &gs->host_instances[i];
        if (keep_prev)
            d->prev_object_to_world = d->object_to_world;
        memcpy(d->object_to_world.m, si->world, sizeof(d->object_to_world.m));
        normal_matrix(si->world, d->normal_to_world.m);
        if (!keep_prev)
            d->prev_object_to_world = d->object_to_world;
        const sc_mesh *mesh = &scene->meshes[si->mesh];
        d->first_index = mesh->first_index;
        d->material = mesh->material;
        d->triangle_count = mesh->index_count / 3;
    }
}

/* ---- acceleration structures ---- */

static xrsc_result accel_create(gpu_context *ctx, VkAccelerationStructureTypeKHR type,
                                VkDeviceSize size, gpu_accel *out, xrsc_diag *diag)
{
    xrsc_result res = gpu_buffer_create(ctx, size,
                                        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR |
                                            VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                        GPU_MEMORY_DEVICE, &out->buffer, diag);
    if (res != XRSC_OK)
        return res;
    VkAccelerationStructureCreateInfoKHR ci = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR,
        .buffer = out->buffer.buffer,
        .size = size,
        .type = type,
    };
    GPU_CHECK(res, diag, fail,
              ctx->vk.CreateAccelerationStructureKHR(ctx->device, &ci, NULL, &out->handle));
    VkAccelerationStructureDeviceAddressInfoKHR ai = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR,
        .accelerationStructure = out->handle,
    };
    out->address = ctx->vk.GetAccelerationStructureDeviceAddressKHR(ctx->device, &ai);
    return XRSC_OK;
fail:
    gpu_buffer_destroy(ctx, &out->buffer);
    return res;
}

static void accel_destroy(gpu_context *ctx, gpu_accel *a)
{
    if (a->handle)
        ctx->vk.DestroyAccelerationStructureKHR(ctx->device, a->handle, NULL);
    gpu_buffer_destroy(ctx, &a->buffer);
    memset(a, 0, sizeof(*a));
}

static void tlas_geometry(const gpu_scene *gs, VkAccelerationStructureGeometryKHR *geom,
                          VkAccelerationStructureBuildGeometryInfoKHR *info,
                          VkBuildAccelerationStructureModeKHR mode)
{
    *geom = (VkAccelerationStructureGeometryKHR){
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR,
        .geometry.instances =
            {
                .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR,
                .arrayOfPointers = VK_FALSE,
                .data.deviceAddress = gs->tlas_instances.address,
            },
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
    *info = (VkAccelerationStructureBuildGeometryInfoKHR){
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
        .type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR,
        .flags = VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR |
                 VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR,
        .mode = mode,
        .srcAccelerationStructure =
            mode == VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR ? gs->tlas.handle
                                                                    : VK_NULL_HANDLE,
        .dstAccelerationStructure = gs->tlas.handle,
        .geometryCount = 1,
        .pGeometries = geom,
        .scratchData.deviceAddress = gs->tlas_scratch_address,
    };
}

static void cmd_as_barrier(VkCommandBuffer cmd)
{
    VkMemoryBarrier mb = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
        .dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                         VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                         VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR |
                             VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR,
                         0, 1, &mb, 0, NULL, 0, NULL);
}

/** Inputs of the per-mesh BLAS builds, kept until the one batched build call is recorded. */
typedef struct gpu_blas_batch {
    uint32_t count;             /**< meshes, one BLAS each */
    VkDeviceSize scratch_align; /**< minAccelerationStructureScratchOffsetAlignment, else 256 */
    VkAccelerationStructureGeometryKHR *geoms;
    VkAccelerationStructureBuildGeometryInfoKHR *infos;
    VkAccelerationStructureBuildRangeInfoKHR *ranges;
    const VkAccelerationStructureBuildRangeInfoKHR **range_ptrs;
    VkDeviceSize *scratch_offsets; /**< of each build's range in scratch */
    VkDeviceSize scratch_total;
    gpu_buffer scratch;
} gpu_blas_batch;

/** Allocates the batch's arrays and gs->blas; blas_batch_free frees the batch, also after a
 *  failure (gs->blas goes with the scene). */
static xrsc_result blas_batch_alloc(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                    gpu_blas_batch *b, xrsc_diag *diag)
{
    uint32_t nm = scene->mesh_count;
    memset(b, 0, sizeof(*b));
    b->count = nm;
    b->scratch_align = ctx->as_properties.minAccelerationStructureScratchOffsetAlignment;
    if (b->scratch_align == 0)
        b->scratch_align = 256;
    b->geoms = calloc(nm ? nm : 1, sizeof(*b->geoms));
    b->infos = calloc(nm ? nm : 1, sizeof(*b->infos));
    b->ranges = calloc(nm ? nm : 1, sizeof(*b->ranges));
    b->range_ptrs = calloc(nm ? nm : 1, sizeof(*b->range_ptrs));
    b->scratch_offsets = calloc(nm ? nm : 1, sizeof(*b->scratch_offsets));
    gs->blas = calloc(nm ? nm : 1, sizeof(*gs->blas));
    if (!b->geoms || !b->infos || !b->ranges || !b->range_ptrs || !b->scratch_offsets || !gs->blas)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    gs->blas_count = nm;
    return XRSC_OK;
}

static void blas_batch_free(gpu_context *ctx, gpu_blas_batch *b)
{
    gpu_buffer_destroy(ctx, &b->scratch);
    free(b->geoms);
    free(b->infos);
    free(b->ranges);
    free(b->range_ptrs);
    free(b->scratch_offsets);
    memset(b, 0, sizeof(*b));
}

/** A mesh's BLAS input: opaque triangles straight from the shared vertex/index buffers. */
static void blas_geometry(const gpu_scene *gs, const sc_mesh *mesh,
                          VkAccelerationStructureGeometryKHR *geom,
                          VkAccelerationStructureBuildGeometryInfoKHR *info)
{
    *geom = (VkAccelerationStructureGeometryKHR){
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR,
        .geometry.triangles =
            {
                .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR,
                .vertexFormat = VK_FORMAT_R32G32B32_SFLOAT,
                .vertexData.deviceAddress = gs->vertices.address,
                .vertexStride = sizeof(xs_vertex),
                .maxVertex = mesh->first_vertex + (mesh->vertex_count ? mesh->vertex_count - 1 : 0),
                .indexType = VK_INDEX_TYPE_UINT32,
                .indexData.deviceAddress =
                    gs->indices.address + (VkDeviceAddress)mesh->first_index * 4u,
            },
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
    *info = (VkAccelerationStructureBuildGeometryInfoKHR){
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
        .type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
        /* a deformed mesh's BLAS is refitted as it moves (gpu_scene_cmd_deform) */
        .flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
                 (mesh->deform_node != SC_NO_DEFORM
                      ? VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR
                      : 0),
        .mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR,
        .geometryCount = 1,
        .pGeometries = geom,
    };
}

/** One BLAS per mesh: sizes its build, creates its storage and places its scratch range. */
static xrsc_result blas_create_all(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                   gpu_blas_batch *b, xrsc_diag *diag)
{
    for (uint32_t m = 0; m < b->count; m++) {
        const sc_mesh *mesh = &scene->meshes[m];
        blas_geometry(gs, mesh, &b->geoms[m], &b->infos[m]);
        b->ranges[m] =
            (VkAccelerationStructureBuildRangeInfoKHR){.primitiveCount = mesh->index_count / 3};
        b->range_ptrs[m] = &b->ranges[m];
        VkAccelerationStructureBuildSizesInfoKHR sizes = {
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
        ctx->vk.GetAccelerationStructureBuildSizesKHR(
            ctx->device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &b->infos[m],
            &b->ranges[m].primitiveCount, &sizes);
        xrsc_result res = accel_create(ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                                       sizes.accelerationStructureSize, &gs->blas[m], diag);
        if (res != XRSC_OK)
            return res;
        b->infos[m].dstAccelerationStructure = gs->blas[m].handle;
        b->scratch_offsets[m] = b->scratch_total;
        b->scratch_total += align_up(sizes.buildScratchSize, b->scratch_align);
    }
    return XRSC_OK;
}

/** TLAS: sizes, storage, instance buffer and a scratch that also serves updates. */
static xrsc_result tlas_create(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                               VkDeviceSize scratch_align, xrsc_diag *diag)
{
    uint32_t ni = scene->instance_count;
    gs->instance_count = ni;
    xrsc_result res = gpu_buffer_create(
        ctx, (VkDeviceSize)(ni ? ni : 1) * sizeof(VkAccelerationStructureInstanceKHR),
        VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
            VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR,
        GPU_MEMORY_UPLOAD, &gs->tlas_instances, diag);
    if (res != XRSC_OK)
        return res;
    write_tlas_instances(gs, scene);
    gpu_buffer_flush(ctx, &gs->tlas_instances);
    VkAccelerationStructureGeometryKHR tgeom;
    VkAccelerationStructureBuildGeometryInfoKHR tinfo;
    tlas_geometry(gs, &tgeom, &tinfo, VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR);
    VkAccelerationStructureBuildSizesInfoKHR tsizes = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    ctx->vk.GetAccelerationStructureBuildSizesKHR(
        ctx->device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &tinfo, &ni, &tsizes);
    res = accel_create(ctx, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR,
                       tsizes.accelerationStructureSize, &gs->tlas, diag);
    if (res != XRSC_OK)
        return res;
    VkDeviceSize tscratch = tsizes.buildScratchSize > tsizes.updateScratchSize
                                ? tsizes.buildScratchSize
                                : tsizes.updateScratchSize;
    res = gpu_buffer_create(ctx, tscratch + scratch_align,
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                            GPU_MEMORY_DEVICE, &gs->tlas_scratch, diag);
    if (res != XRSC_OK)
        return res;
    gs->tlas_scratch_address = align_up(gs->tlas_scratch.address, scratch_align);
    return XRSC_OK;
}

/** BLAS scratch: one buffer, disjoint aligned ranges, so all builds go in one call. */
static xrsc_result blas_scratch_create(gpu_context *ctx, gpu_blas_batch *b, xrsc_diag *diag)
{
    xrsc_result res = gpu_buffer_create(ctx, b->scratch_total + b->scratch_align,
                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                            VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                        GPU_MEMORY_DEVICE, &b->scratch, diag);
    if (res != XRSC_OK)
        return res;
    VkDeviceAddress scratch_base = align_up(b->scratch.address, b->scratch_align);
    for (uint32_t m = 0; m < b->count; m++)
        b->infos[m].scratchData.deviceAddress = scratch_base + b->scratch_offsets[m];
    return XRSC_OK;
}

/** The timer passes of the BLAS and TLAS builds. */
typedef struct gpu_accel_passes {
    uint32_t blas, tlas;
} gpu_accel_passes;

/** Records all BLAS builds in one call, then the TLAS build, each timed. */
static gpu_accel_passes cmd_build_accels(gpu_context *ctx, const gpu_scene *gs,
                                         const gpu_blas_batch *b, VkCommandBuffer cmd,
                                         gpu_timer *timer)
{
    gpu_accel_passes p;
    gpu_timer_cmd_reset(cmd, timer);
    p.blas = gpu_timer_cmd_begin(cmd, timer, "blas");
    if (b->count)
        ctx->vk.CmdBuildAccelerationStructuresKHR(cmd, b->count, b->infos, b->range_ptrs);
    gpu_timer_cmd_end(cmd, timer, p.blas);
    cmd_as_barrier(cmd);
    p.tlas = gpu_timer_cmd_begin(cmd, timer, "tlas");
    VkAccelerationStructureGeometryKHR tgeom;
    VkAccelerationStructureBuildGeometryInfoKHR tinfo;
    tlas_geometry(gs, &tgeom, &tinfo, VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR);
    VkAccelerationStructureBuildRangeInfoKHR trange = {.primitiveCount = gs->instance_count};
    const VkAccelerationStructureBuildRangeInfoKHR *trange_ptr = &trange;
    ctx->vk.CmdBuildAccelerationStructuresKHR(cmd, 1, &tinfo, &trange_ptr);
    gpu_timer_cmd_end(cmd, timer, p.tlas);
    cmd_as_barrier(cmd);
    return p;
}

/** Builds the BLAS and the TLAS in one submission and keeps their GPU times in gs. */
static xrsc_result accels_build_timed(gpu_context *ctx, gpu_scene *gs, const gpu_blas_batch *b,
                                      xrsc_diag *diag)
{
    gpu_timer timer = {0};
    xrsc_result res = gpu_timer_create(ctx, &timer, diag);
    if (res != XRSC_OK)
        goto done;
    VkCommandBuffer cmd;
    res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res != XRSC_OK)
        goto done;
    gpu_accel_passes passes = cmd_build_accels(ctx, gs, b, cmd, &timer);
    res = gpu_cmd_submit_wait(ctx, cmd, diag);
    if (res != XRSC_OK)
        goto done;
    res = gpu_timer_resolve(ctx, &timer, diag);
    if (res != XRSC_OK)
        goto done;
    gs->blas_ms = timer.ms[passes.blas];
    gs->tlas_ms = timer.ms[passes.tlas];
done:
    gpu_timer_destroy(ctx, &timer);
    return res;
}

static xrsc_result build_accels(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                xrsc_diag *diag)
{
    gpu_blas_batch b;
    xrsc_result res = XRSC_OK;
    if ((res = blas_batch_alloc(ctx, gs, scene, &b, diag)) != XRSC_OK ||
        (res = blas_create_all(ctx, gs, scene, &b, diag)) != XRSC_OK ||
        (res = tlas_create(ctx, gs, scene, b.scratch_align, diag)) != XRSC_OK ||
        (res = blas_scratch_create(ctx, &b, diag)) != XRSC_OK)
        goto done;
    res = accels_build_timed(ctx, gs, &b, diag);
done:
    blas_batch_free(ctx, &b);
    return res;
}

/* ---- skins and morph targets: GPU pose, then a BLAS refit or rebuild ---- */

static VkDeviceSize scratch_alignment(const gpu_context *ctx)
{
    VkDeviceSize a = ctx->as_properties.minAccelerationStructureScratchOffsetAlignment;
    return a ? a : 256;
}

/** The deformation pass, and the load-time pose written before the first BLAS build. */
static xrsc_result deform_create(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                 xrsc_diag *diag)
{
    xrsc_result res = gpu_deform_create(ctx, scene, &gs->vertices, &gs->deform, diag);
    if (res != XRSC_OK || !gs->deform)
        return res;
    VkCommandBuffer cmd;
    if ((res = gpu_cmd_begin(ctx, &cmd, diag)) != XRSC_OK)
        return res;
    gpu_deform_cmd(gs->deform, cmd, false);
    return gpu_cmd_submit_wait(ctx, cmd, diag);
}

/** The deformed meshes' BLAS inputs and one scratch with a range per BLAS. */
static xrsc_result deform_scratch_create(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                         xrsc_diag *diag)
{
    if (!gs->deform)
        return XRSC_OK;
    uint32_t n = scene->deform_mesh_count;
    gs->deform_meshes = calloc(n, sizeof(sc_mesh));
    gs->deform_blas = calloc(n, sizeof(uint32_t));
    gs->deform_scratch_offsets = calloc(n, sizeof(VkDeviceSize));
    if (!gs->deform_meshes || !gs->deform_blas || !gs->deform_scratch_offsets)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    VkDeviceSize align = scratch_alignment(ctx), total = 0;
    for (uint32_t m = 0; m < scene->mesh_count && gs->deform_mesh_count < n; m++) {
        const sc_mesh *mesh = &scene->meshes[m];
        if (mesh->deform_node == SC_NO_DEFORM)
            continue;
        VkAccelerationStructureGeometryKHR geom;
        VkAccelerationStructureBuildGeometryInfoKHR info;
        blas_geometry(gs, mesh, &geom, &info);
        uint32_t prims = mesh->index_count / 3;
        VkAccelerationStructureBuildSizesInfoKHR sizes = {
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
        ctx->vk.GetAccelerationStructureBuildSizesKHR(
            ctx->device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &prims, &sizes);
        VkDeviceSize need = sizes.buildScratchSize > sizes.updateScratchSize
                                ? sizes.buildScratchSize
                                : sizes.updateScratchSize;
        gs->deform_meshes[gs->deform_mesh_count] = *mesh;
        gs->deform_blas[gs->deform_mesh_count] = m;
        gs->deform_scratch_offsets[gs->deform_mesh_count++] = total;
        total += align_up(need, align);
    }
    return gpu_buffer_create(ctx, total + align,
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                 VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                             GPU_MEMORY_DEVICE, &gs->deform_scratch, diag);
}

/** Stages the scene's pose and chooses refit or rebuild (gpu_blas_mode, the pose's drift). */
static void stage_deform(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene)
{
    if (!gs->deform || gs->deform_off)
        return;
    gpu_deform_stage(ctx, gs->deform, scene);
    gs->deform_rebuild = gs->blas_mode == GPU_BLAS_REBUILD ||
                         (gs->blas_mode == GPU_BLAS_AUTO &&
                          gpu_deform_drift(gs->deform, scene) > GPU_BLAS_REBUILD_DRIFT);
    if (gs->deform_rebuild)
        gpu_deform_mark_built(gs->deform, scene);
    gs->deform_pending = true;
}

/** Refits (UPDATE from itself) or rebuilds each deformed mesh's BLAS from vertices[]. */
static void cmd_blas_update(gpu_context *ctx, gpu_scene *gs, VkCommandBuffer cmd, bool rebuild)
{
    /* earlier reads of these BLAS (shaders, the TLAS build) before they are rewritten */
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR,
                          .dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                                           VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR};
    vkCmdPipelineBarrier(cmd,
                         VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR |
                             VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                         VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, 0, 1, &mb, 0,
                         NULL, 0, NULL);
    VkDeviceAddress base = align_up(gs->deform_scratch.address, scratch_alignment(ctx));
    for (uint32_t k = 0; k < gs->deform_mesh_count; k++) {
        VkAccelerationStructureGeometryKHR geom;
        VkAccelerationStructureBuildGeometryInfoKHR info;
        blas_geometry(gs, &gs->deform_meshes[k], &geom, &info);
        VkAccelerationStructureKHR as = gs->blas[gs->deform_blas[k]].handle;
        info.mode = rebuild ? VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR
                            : VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR;
        info.srcAccelerationStructure = rebuild ? VK_NULL_HANDLE : as;
        info.dstAccelerationStructure = as;
        info.scratchData.deviceAddress = base + gs->deform_scratch_offsets[k];
        VkAccelerationStructureBuildRangeInfoKHR range = {
            .primitiveCount = gs->deform_meshes[k].index_count / 3};
        const VkAccelerationStructureBuildRangeInfoKHR *range_ptr = &range;
        ctx->vk.CmdBuildAccelerationStructuresKHR(cmd, 1, &info, &range_ptr);
    }
    if (rebuild)
        gs->blas_rebuilds++;
    else
        gs->blas_refits++;
}

bool gpu_scene_cmd_deform(gpu_context *ctx, gpu_scene *gs, VkCommandBuffer cmd, gpu_timer *timer)
{
    if (!gs->deform)
        return false;
    /* A scene with deformed meshes always has both passes (empty when no pose is pending), so
     * every frame lists the same passes (the bench's per-pass columns). */
    bool pending = gs->deform_pending;
    gs->deform_pending = false;
    uint32_t pass = timer ? gpu_timer_cmd_begin(cmd, timer, GPU_PASS_SKIN) : 0;
    if (pending || gs->prev_stale)
        gpu_deform_cmd(gs->deform, cmd, pending);
    gs->prev_stale = pending;
    if (timer)
        gpu_timer_cmd_end(cmd, timer, pass);
    pass = timer ? gpu_timer_cmd_begin(cmd, timer, GPU_PASS_BLAS_UPDATE) : 0;
    if (pending)
        cmd_blas_update(ctx, gs, cmd, gs->deform_rebuild);
    if (timer)
        gpu_timer_cmd_end(cmd, timer, pass);
    if (pending)
        cmd_as_barrier(cmd);
    return pending;
}

void gpu_scene_set_blas_mode(gpu_scene *gs, gpu_blas_mode mode) { gs->blas_mode = mode; }
void gpu_scene_set_deform_enabled(gpu_scene *gs, bool enabled) { gs->deform_off = !enabled; }
uint32_t gpu_scene_deform_mesh_count(const gpu_scene *gs) { return gs->deform_mesh_count; }

void gpu_scene_blas_update_counts(const gpu_scene *gs, uint32_t *out_rebuilds,
                                  uint32_t *out_refits)
{
    *out_rebuilds = gs->blas_rebuilds;
    *out_refits = gs->blas_refits;
}

const gpu_buffer *gpu_scene_prev_positions(const gpu_scene *gs)
{
    return gs->deform ? gpu_deform_prev(gs->deform) : NULL;
}

xrsc_result gpu_scene_download_vertices(gpu_context *ctx, const gpu_scene *gs, uint32_t first,
                                        uint32_t count, void *dst, xrsc_diag *diag)
{
    return gpu_buffer_download(ctx, &gs->vertices, (VkDeviceSize)first * sizeof(xs_vertex), dst,
                               (VkDeviceSize)count * sizeof(xs_vertex), diag);
}

xrsc_result gpu_scene_create(gpu_context *ctx, const sc_scene *scene, gpu_scene **out,
                             xrsc_diag *diag)
{
    *out = NULL;
    for (uint32_t i = 0; i < scene->instance_count; i++)
        if (scene->instances[i].mesh >= scene->mesh_count)
            return u_diag_set(diag, XRSC_ERROR_GLTF_INVALID, scene->path, 0, "instances",
                              "instance %u uses mesh %u of %u", i, scene->instances[i].mesh,
                              scene->mesh_count);
    gpu_scene *gs = calloc(1, sizeof(*gs));
    if (!gs)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    xrsc_result res = XRSC_OK;
    uint32_t ni = scene->instance_count;
    gs->host_instances = calloc(ni ? ni : 1, sizeof(*gs->host_instances));
    if (!gs->host_instances) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
        goto fail;
    }
    fill_host_instances(gs, scene, false);
    for (uint32_t i = 0; i < ni; i++)
        gs->animated = gs->animated || scene->instances[i].animated;
    gs->animated = gs->animated && scene->animation_duration_s > 0.0f;
    if ((res = upload_geometry(ctx, gs, scene, diag)) != XRSC_OK ||
        (res = upload_materials(ctx, gs, scene, diag)) != XRSC_OK ||
        (res = upload_emitters(ctx, gs, scene, diag)) != XRSC_OK ||
        (res = upload_lights(ctx, gs, scene, diag)) != XRSC_OK ||
        (res = upload_env_map(ctx, gs, scene, diag)) != XRSC_OK ||
        (res = upload_textures(ctx, gs, scene, diag)) != XRSC_OK)
        goto fail;
    res = gpu_buffer_create_with_data(ctx, gs->host_instances,
                                      (VkDeviceSize)ni * sizeof(xs_instance),
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, &gs->instances, diag);
    if (res != XRSC_OK)
        goto fail;
    res = gpu_buffer_create(ctx, (VkDeviceSize)ni * sizeof(xs_instance),
                            VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEMORY_UPLOAD,
                            &gs->instances_staging, diag);
    if (res != XRSC_OK)
        goto fail;
    res = deform_create(ctx, gs, scene, diag);
    if (res != XRSC_OK)
        goto fail;
    res = build_accels(ctx, gs, scene, diag);
    if (res != XRSC_OK)
        goto fail;
    res = deform_scratch_create(ctx, gs, scene, diag);
    if (res != XRSC_OK)
        goto fail;
    U_LOG_D("%s: %u meshes, %u instances, %u emitters, BLAS %.3f ms, TLAS %.3f ms", scene->path,
            scene->mesh_count, ni, gs->emitter_count, gs->blas_ms, gs->tlas_ms);
    *out = gs;
    return XRSC_OK;
fail:
    gpu_scene_destroy(ctx, &gs);
    return res;
}

void gpu_scene_destroy(gpu_context *ctx, gpu_scene **pgs)
{
    if (!pgs || !*pgs)
        return;
    gpu_scene *gs = *pgs;
    if (ctx->device)
        vkDeviceWaitIdle(ctx->device);
    accel_destroy(ctx, &gs->tlas);
    gpu_buffer_destroy(ctx, &gs->tlas_scratch);
    gpu_deform_destroy(ctx, &gs->deform);
    gpu_buffer_destroy(ctx, &gs->deform_scratch);
    free(gs->deform_meshes);
    free(gs->deform_blas);
    free(gs->deform_scratch_offsets);
    gpu_buffer_destroy(ctx, &gs->tlas_instances);
    gpu_buffer_destroy(ctx, &gs->instances_staging);
    if (gs->blas)
        for (uint32_t m = 0; m < gs->blas_count; m++)
            accel_destroy(ctx, &gs->blas[m]);
    free(gs->blas);
    if (gs->textures)
        for (uint32_t i = 0; i < gs->texture_count; i++)
            gpu_image_destroy(ctx, &gs->textures[i]);
    free(gs->textures);
    gpu_image_destroy(ctx, &gs->white);
    gpu_sampler_destroy(ctx, &gs->sampler);
    for (uint32_t k = 0; k < GPU_SAMPLER_KINDS; k++) gpu_sampler_destroy(ctx, &gs->sampler_table[k]);
    free(gs->tex_samplers);
    gpu_buffer_destroy(ctx, &gs->vertices);
    gpu_buffer_destroy(ctx, &gs->indices);
    gpu_buffer_destroy(ctx, &gs->instances);
    gpu_buffer_destroy(ctx, &gs->materials);
    gpu_buffer_destroy(ctx, &gs->emitters);
    gpu_buffer_destroy(ctx, &gs->lights);
    gpu_buffer_destroy(ctx, &gs->env_map);
    free(gs->host_instances);
    free(gs);
    *pgs = NULL;
}

xrsc_result gpu_scene_stage_instances(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                      xrsc_diag *diag)
{
    if (scene->instance_count != gs->instance_count)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, scene->path, 0, "instances",
                          "instance count changed from %u to %u", gs->instance_count,
                          scene->instance_count);
    if (gs->lights_animated && scene->light_count == gs->light_count) {
        fill_lights(scene, gs->lights.mapped);
        gpu_buffer_flush(ctx, &gs->lights);
    }
    stage_deform(ctx, gs, scene);
    if (gs->instance_count == 0)
        return XRSC_OK;
    fill_host_instances(gs, scene, true);
    memcpy(gs->instances_staging.mapped, gs->host_instances,
           (size_t)gs->instance_count * sizeof(xs_instance));
    gpu_buffer_flush(ctx, &gs->instances_staging);
    write_tlas_instances(gs, scene);
    gpu_buffer_flush(ctx, &gs->tlas_instances);
    gs->update_pending = true;
    return XRSC_OK;
}

bool gpu_scene_cmd_update(gpu_context *ctx, gpu_scene *gs, VkCommandBuffer cmd)
{
    if (!gs->update_pending)
        return false;
    gs->update_pending = false;
    /* Host writes (staging, TLAS instances) and earlier reads of instances[] / the TLAS
     * before the copy and the build. */
    VkMemoryBarrier before = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_HOST_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT |
                         VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR,
        .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                         VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                         VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
    };
    vkCmdPipelineBarrier(cmd,
                         VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR |
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT |
                             VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                         0, 1, &before, 0, NULL, 0, NULL);
    VkBufferCopy region = {0, 0, (VkDeviceSize)gs->instance_count * sizeof(xs_instance)};
    vkCmdCopyBuffer(cmd, gs->instances_staging.buffer, gs->instances.buffer, 1, &region);
    VkAccelerationStructureGeometryKHR geom;
    VkAccelerationStructureBuildGeometryInfoKHR info;
    tlas_geometry(gs, &geom, &info, VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR);
    VkAccelerationStructureBuildRangeInfoKHR range = {.primitiveCount = gs->instance_count};
    const VkAccelerationStructureBuildRangeInfoKHR *range_ptr = &range;
    ctx->vk.CmdBuildAccelerationStructuresKHR(cmd, 1, &info, &range_ptr);
    /* The new TLAS and instances[] before any later shader. */
    VkMemoryBarrier after = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask =
            VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
        .dstAccessMask = VK_ACCESS_SHADER_READ_BIT |
                         VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                         VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
    };
    vkCmdPipelineBarrier(cmd,
                         VK_PIPELINE_STAGE_TRANSFER_BIT |
                             VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                         VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR |
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                             VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                         0, 1, &after, 0, NULL, 0, NULL);
    return true;
}

bool gpu_scene_update_pending(const gpu_scene *gs) { return gs->update_pending; }

xrsc_result gpu_scene_update_instances(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                       xrsc_diag *diag)
{
    xrsc_result res = gpu_scene_stage_instances(ctx, gs, scene, diag);
    if (res != XRSC_OK || !gs->update_pending)
        return res;
    VkCommandBuffer cmd;
    res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    gpu_scene_cmd_deform(ctx, gs, cmd, NULL);
    gpu_scene_cmd_update(ctx, gs, cmd);
    return gpu_cmd_submit_wait(ctx, cmd, diag);
}

xrsc_result gpu_scene_clear_motion(gpu_context *ctx, gpu_scene *gs, xrsc_diag *diag)
{
    if (gs->deform) { /* prev[] = the current pose */
        VkCommandBuffer cmd;
        xrsc_result res = gpu_cmd_begin(ctx, &cmd, diag);
        if (res != XRSC_OK)
            return res;
        gpu_deform_cmd(gs->deform, cmd, false);
        gs->prev_stale = false;
        if ((res = gpu_cmd_submit_wait(ctx, cmd, diag)) != XRSC_OK)
            return res;
    }
    for (uint32_t i = 0; i < gs->instance_count; i++)
        gs->host_instances[i].prev_object_to_world = gs->host_instances[i].object_to_world;
    return gpu_buffer_upload(ctx, &gs->instances, 0, gs->host_instances,
                             (VkDeviceSize)gs->instance_count * sizeof(xs_instance), diag);
}

void gpu_scene_write_descriptors(gpu_context *ctx, const gpu_scene *gs, gpu_descriptors *d)
{
    gpu_descriptors_write_tlas(ctx, d, XS_BIND_TLAS, gs->tlas.handle);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_VERTICES, &gs->vertices);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_INDICES, &gs->indices);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_INSTANCES, &gs->instances);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_MATERIALS, &gs->materials);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_EMITTERS, &gs->emitters);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_ENV_MAP, &gs->env_map);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_LIGHTS, &gs->lights);
    gpu_descriptors_write_textures(ctx, d, XS_BIND_TEXTURES, gs->textures, gs->tex_samplers,
                                   gs->texture_count, &gs->white, gs->sampler);
}

uint32_t gpu_scene_emitter_count(const gpu_scene *gs) { return gs->emitter_count; }
bool gpu_scene_animated(const gpu_scene *gs) { return gs->animated; }
uint32_t gpu_scene_light_count(const gpu_scene *gs) { return gs->light_count; }

uint32_t gpu_scene_glass_count(const gpu_scene *gs) { return gs->glass_instance_count; }
double gpu_scene_blas_build_ms(const gpu_scene *gs) { return gs->blas_ms; }
double gpu_scene_tlas_build_ms(const gpu_scene *gs) { return gs->tlas_ms; }
