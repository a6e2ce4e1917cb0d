// SPDX-License-Identifier: MIT
/**
 * @file gpu_deform.c
 * @brief Skins and morph targets posed on the GPU (deform.comp), one dispatch per mesh.
 */
#include "gpu_deform.h"

#include "u_diag.h"
#include "xrsc_shared.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(sc_skin_influence) == sizeof(xs_skin_influence), "influence layout");

struct gpu_deform {
    gpu_compute_program program;
    gpu_buffer rest, influences, deltas, prev;
    gpu_buffer matrices, weights; /**< host-visible: the pose */
    xs_deform_push *jobs;         /**< one per deformed mesh */
    uint32_t job_count;
    float *radius;    /**< per job: half the rest bounding box's diagonal (its size) */
    float *reach;     /**< per job: the farthest rest vertex from the object origin */
    float *max_delta; /**< per job: longest morph position delta */
    float *built_matrices, *built_weights; /**< the pose at the last BLAS build */
};

static const gpu_binding deform_bindings[] = {
    {XS_DEFORM_BIND_VERTICES, GPU_BINDING_STORAGE_BUFFER, 0},
    {XS_DEFORM_BIND_REST, GPU_BINDING_STORAGE_BUFFER, 0},
    {XS_DEFORM_BIND_INFLUENCES, GPU_BINDING_STORAGE_BUFFER, 0},
    {XS_DEFORM_BIND_DELTAS, GPU_BINDING_STORAGE_BUFFER, 0},
    {XS_DEFORM_BIND_MATRICES, GPU_BINDING_STORAGE_BUFFER, 0},
    {XS_DEFORM_BIND_WEIGHTS, GPU_BINDING_STORAGE_BUFFER, 0},
    {XS_DEFORM_BIND_PREV, GPU_BINDING_STORAGE_BUFFER, 0},
};

/** The jobs and the rest copy (xs_vertex) of every deformed mesh's vertices. */
static xs_vertex *make_jobs(gpu_deform *d, const sc_scene *scene, uint32_t *out_rest_count)
{
    uint32_t nrest = 0;
    for (uint32_t m = 0; m < scene->mesh_count; m++)
        if (scene->meshes[m].deform_node != SC_NO_DEFORM)
            nrest += scene->meshes[m].vertex_count;
    d->jobs = calloc(scene->deform_mesh_count ? scene->deform_mesh_count : 1, sizeof(*d->jobs));
    xs_vertex *rest = malloc((nrest ? nrest : 1) * sizeof(*rest));
    if (!d->jobs || !rest) {
        free(rest);
        return NULL;
    }
    uint32_t at = 0;
    for (uint32_t m = 0; m < scene->mesh_count; m++) {
        const sc_mesh *mesh = &scene->meshes[m];
        if (mesh->deform_node == SC_NO_DEFORM)
            continue;
        d->jobs[d->job_count++] = (xs_deform_push){mesh->first_vertex,
                                                   mesh->vertex_count,
                                                   at,
                                                   mesh->first_influence,
                                                   mesh->skin_sets,
                                                   mesh->first_pose_matrix,
                                                   mesh->first_delta,
                                                   mesh->target_count,
                                                   mesh->first_pose_weight,
                                                   0,
                                                   mesh->skin_joint_count,
                                                   0};
        for (uint32_t i = 0; i < mesh->vertex_count; i++, at++) {
            const sc_vertex *s = &scene->vertices[mesh->first_vertex + i];
            rest[at].position_u =
                (xs_vec4){s->position[0], s->position[1], s->position[2], s->uv[0]};
            rest[at].normal_v = (xs_vec4){s->normal[0], s->normal[1], s->normal[2], s->uv[1]};
            rest[at].tangent =
                (xs_vec4){s->tangent[0], s->tangent[1], s->tangent[2], s->tangent[3]};
        }
    }
    *out_rest_count = nrest;
    return rest;
}

/** The morph deltas as xs_morph_delta (vec4 padded). */
static xs_morph_delta *make_deltas(const sc_scene *scene)
{
    xs_morph_delta *x = calloc(scene->delta_count ? scene->delta_count : 1, sizeof(*x));
    for (uint32_t i = 0; x && i < scene->delta_count; i++) {
        const sc_morph_delta *s = &scene->deltas[i];
        x[i].position = (xs_vec4){s->position[0], s->position[1], s->position[2], 0};
        x[i].normal = (xs_vec4){s->normal[0], s->normal[1], s->normal[2], 0};
        x[i].tangent = (xs_vec4){s->tangent[0], s->tangent[1], s->tangent[2], 0};
    }
    return x;
}

/** prev[] with every vertex's rest position: rigid vertices keep it (their motion is 0). */
static xrsc_result create_prev(gpu_context *ctx, gpu_deform *d, const sc_scene *scene,
                               xrsc_diag *diag)
{
    xs_vec4 *p = malloc((size_t)(scene->vertex_count ? scene->vertex_count : 1) * sizeof(*p));
    if (!p)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    for (uint32_t i = 0; i < scene->vertex_count; i++) {
        const float *v = scene->vertices[i].position;
        p[i] = (xs_vec4){v[0], v[1], v[2], 1.0f};
    }
    xrsc_result res = gpu_buffer_create_with_data(
        ctx, p, (VkDeviceSize)(scene->vertex_count ? scene->vertex_count : 1) * sizeof(*p),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, &d->prev, diag);
    free(p);
    return res;
}

/** Uploads the rest copy, influences, deltas; creates prev[] and the pose buffers. */
static xrsc_result create_buffers(gpu_context *ctx, gpu_deform *d, const sc_scene *scene,
                                  xrsc_diag *diag)
{
    const VkBufferUsageFlags ssbo = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    uint32_t nrest = 0;
    xs_vertex *rest = make_jobs(d, scene, &nrest);
    xs_morph_delta *deltas = make_deltas(scene);
    xrsc_result res = XRSC_OK;
    if (!rest || !deltas)
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    if (res == XRSC_OK)
        res = gpu_buffer_create_with_data(
            ctx, rest, (VkDeviceSize)(nrest ? nrest : 1) * sizeof(*rest), ssbo, &d->rest, diag);
    if (res == XRSC_OK)
        res = gpu_buffer_create_with_data(
            ctx, scene->influence_count ? (const void *)scene->influences : NULL,
            (VkDeviceSize)(scene->influence_count ? scene->influence_count : 1) *
                sizeof(xs_skin_influence),
            ssbo, &d->influences, diag);
    if (res == XRSC_OK)
        res = gpu_buffer_create_with_data(
            ctx, deltas,
            (VkDeviceSize)(scene->delta_count ? scene->delta_count : 1) * sizeof(*deltas), ssbo,
            &d->deltas, diag);
    if (res == XRSC_OK)
        res = create_prev(ctx, d, scene, diag);
    if (res == XRSC_OK)
        res = gpu_buffer_create(ctx, (VkDeviceSize)(scene->pose_matrix_count + 1) * 64u, ssbo,
                                GPU_MEMORY_UPLOAD, &d->matrices, diag);
    if (res == XRSC_OK)
        res = gpu_buffer_create(ctx, (VkDeviceSize)(scene->pose_weight_count + 1) * 4u, ssbo,
                                GPU_MEMORY_UPLOAD, &d->weights, diag);
    free(rest);
    free(deltas);
    return res;
}

/** Per job: the rest radius and longest morph delta (drift scales); the built pose. */
static bool drift_init(gpu_deform *d, const sc_scene *scene)
{
    uint32_t n = d->job_count ? d->job_count : 1;
    d->radius = calloc(n, sizeof(float));
    d->reach = calloc(n, sizeof(float));
    d->max_delta = calloc(n, sizeof(float));
    d->built_matrices = calloc((size_t)scene->pose_matrix_count * 16 + 1, sizeof(float));
    d->built_weights = calloc((size_t)scene->pose_weight_count + 1, sizeof(float));
    if (!d->radius || !d->reach || !d->max_delta || !d->built_matrices || !d->built_weights)
        return false;
    for (uint32_t j = 0; j < d->job_count; j++) {
        const xs_deform_push *job = &d->jobs[j];
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t i = 0; i < job->vertex_count; i++)
            for (int c = 0; c < 3; c++) {
                float v = scene->vertices[job->first_vertex + i].position[c];
                lo[c] = fminf(lo[c], v), hi[c] = fmaxf(hi[c], v);
            }
        for (uint32_t i = 0; i < job->vertex_count; i++) {
            const float *v = scene->vertices[job->first_vertex + i].position;
            d->reach[j] = fmaxf(d->reach[j], sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        }
        for (int c = 0; c < 3; c++)
            d->radius[j] += 0.25f * (hi[c] - lo[c]) * (hi[c] - lo[c]);
        d->radius[j] = sqrtf(d->radius[j]);
        for (uint32_t i = 0; i < job->target_count * job->vertex_count; i++) {
            const float *dp = scene->deltas[job->first_delta + i].position;
            d->max_delta[j] =
                fmaxf(d->max_delta[j], sqrtf(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2]));
        }
    }
    gpu_deform_mark_built(d, scene);
    return true;
}

void gpu_deform_mark_built(gpu_deform *d, const sc_scene *scene)
{
    memcpy(d->built_matrices, scene->pose_matrices,
           (size_t)scene->pose_matrix_count * 16 * sizeof(float));
    memcpy(d->built_weights, scene->pose_weights, (size_t)scene->pose_weight_count * sizeof(float));
}

float gpu_deform_drift(const gpu_deform *d, const sc_scene *scene)
{
    float drift = 0.0f;
    for (uint32_t j = 0; j < d->job_count; j++) {
        const xs_deform_push *job = &d->jobs[j];
        float r = d->radius[j] > 0.0f ? d->radius[j] : 1.0f, worst = 0.0f, morph = 0.0f;
        /* a point within `reach` of the origin moves by at most |dt| + reach ||dA||_F */
        for (uint32_t m = job->first_matrix; m < job->first_matrix + job->joint_count; m++) {
            const float *a = &scene->pose_matrices[16 * m], *b = &d->built_matrices[16 * m];
            float dlin = 0.0f, dt = 0.0f;
            for (int e = 0; e < 12; e++)
                dlin += (a[e] - b[e]) * (a[e] - b[e]);
            for (int e = 12; e < 15; e++)
                dt += (a[e] - b[e]) * (a[e] - b[e]);
            worst = fmaxf(worst, sqrtf(dt) + d->reach[j] * sqrtf(dlin));
        }
        for (uint32_t k = 0; k < job->target_count; k++)
            morph += fabsf(scene->pose_weights[job->first_weight + k] -
                           d->built_weights[job->first_weight + k]);
        drift = fmaxf(drift, (worst + morph * d->max_delta[j]) / r);
    }
    return drift;
}

xrsc_result gpu_deform_create(gpu_context *ctx, const sc_scene *scene, const gpu_buffer *vertices,
                              gpu_deform **out, xrsc_diag *diag)
{
    *out = NULL;
    if (scene->deform_mesh_count == 0)
        return XRSC_OK;
    gpu_deform *d = calloc(1, sizeof(*d));
    if (!d)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    xrsc_result res = create_buffers(ctx, d, scene, diag);
    if (res == XRSC_OK && !drift_init(d, scene))
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, scene->path, 0, "", "out of memory");
    if (res == XRSC_OK)
        res = gpu_compute_program_create(ctx, "deform.comp", deform_bindings,
                                         sizeof deform_bindings / sizeof deform_bindings[0],
                                         sizeof(xs_deform_push), &d->program, diag);
    if (res != XRSC_OK) {
        gpu_deform_destroy(ctx, &d);
        return res;
    }
    gpu_descriptors *set = &d->program.set0;
    gpu_descriptors_write_buffer(ctx, set, XS_DEFORM_BIND_VERTICES, vertices);
    gpu_descriptors_write_buffer(ctx, set, XS_DEFORM_BIND_REST, &d->rest);
    gpu_descriptors_write_buffer(ctx, set, XS_DEFORM_BIND_INFLUENCES, &d->influences);
    gpu_descriptors_write_buffer(ctx, set, XS_DEFORM_BIND_DELTAS, &d->deltas);
    gpu_descriptors_write_buffer(ctx, set, XS_DEFORM_BIND_MATRICES, &d->matrices);
    gpu_descriptors_write_buffer(ctx, set, XS_DEFORM_BIND_WEIGHTS, &d->weights);
    gpu_descriptors_write_buffer(ctx, set, XS_DEFORM_BIND_PREV, &d->prev);
    gpu_deform_stage(ctx, d, scene);
    *out = d;
    return XRSC_OK;
}

void gpu_deform_destroy(gpu_context *ctx, gpu_deform **pd)
{
    if (!pd || !*pd)
        return;
    gpu_deform *d = *pd;
    gpu_compute_program_destroy(ctx, &d->program);
    gpu_buffer_destroy(ctx, &d->rest);
    gpu_buffer_destroy(ctx, &d->influences);
    gpu_buffer_destroy(ctx, &d->deltas);
    gpu_buffer_destroy(ctx, &d->prev);
    gpu_buffer_destroy(ctx, &d->matrices);
    gpu_buffer_destroy(ctx, &d->weights);
    free(d->jobs);
    free(d->radius);
    free(d->reach);
    free(d->max_delta);
    free(d->built_matrices);
    free(d->built_weights);
    free(d);
    *pd = NULL;
}

void gpu_deform_stage(gpu_context *ctx, gpu_deform *d, const sc_scene *scene)
{
    memcpy(d->matrices.mapped, scene->pose_matrices,
           (size_t)scene->pose_matrix_count * 16 * sizeof(float));
    memcpy(d->weights.mapped, scene->pose_weights,
           (size_t)scene->pose_weight_count * sizeof(float));
    gpu_buffer_flush(ctx, &d->matrices);
    gpu_buffer_flush(ctx, &d->weights);
}

static void barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage, VkAccessFlags src,
                    VkPipelineStageFlags dst_stage, VkAccessFlags dst)
{
    VkMemoryBarrier mb = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = src, .dstAccessMask = dst};
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 1, &mb, 0, NULL, 0, NULL);
}

void gpu_deform_cmd(gpu_deform *d, VkCommandBuffer cmd, bool keep_prev)
{
    const VkPipelineStageFlags readers = VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR |
                                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                                         VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
    /* Build inputs are read as SHADER_READ in the AS build stage. */
    barrier(cmd, readers | VK_PIPELINE_STAGE_HOST_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    for (uint32_t j = 0; j < d->job_count; j++) {
        xs_deform_push push = d->jobs[j];
        push.keep_prev = keep_prev ? 1u : 0u;
        uint32_t groups = (push.vertex_count + XS_DEFORM_GROUP_SIZE - 1) / XS_DEFORM_GROUP_SIZE;
        gpu_compute_program_cmd_dispatch(cmd, &d->program, &push, groups, 1, 1);
    }
    barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, readers,
            VK_ACCESS_SHADER_READ_BIT);
}

const gpu_buffer *gpu_deform_prev(const gpu_deform *d)
{
    return &d->prev;
}
