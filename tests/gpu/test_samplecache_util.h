// SPDX-License-Identifier: MIT
/**
 * @file test_samplecache_util.h
 * @brief Helpers of the sample-cache tests (test_samplecache_*.c): a GPU context with the
 *        validation layer, a method on a loaded scene, frames from eye poses, the CPU
 *        (double precision) projection of a cached first hit, and small glTF scenes of quads
 *        written to temporary files (data-URI buffers, optional translation animation).
 */
#pragma once

#include "gpu_scene.h"
#include "mt_samplecache.h"
#include "sc_scene.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_math.h"
#include "xrsc/xrsc_metrics.h"
#include "xs_sc_math.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TSC_PI 3.14159265358979323846

static inline void tsc_print_diag(const xrsc_diag *d)
{
    char msg[1400];
    fprintf(stderr, "%s\n", xrsc_diag_format(d, msg, sizeof(msg)));
}

/** A `samplecache` method on a scene (CPU + GPU copies), validation layer on. */
typedef struct tsc_rig {
    gpu_context *gpu;
    sc_scene *cpu;
    gpu_scene *gs;
    mt_method *m;
    uint32_t width, height;
} tsc_rig;

static inline bool tsc_open(tsc_rig *r, const char *scene_path, uint32_t w, uint32_t h,
                            const xrsc_samplecache_options *opt)
{
    memset(r, 0, sizeof(*r));
    r->width = w;
    r->height = h;
    gpu_context_options go = {.validation = true};
    xrsc_diag diag = {0};
    xrsc_result res = gpu_context_create(&go, &r->gpu, &diag);
    if (res == XRSC_OK)
        CHECK(r->gpu->validation); /* the layer is there: errors are counted */
    if (res == XRSC_OK)
        res = sc_scene_load(scene_path, NULL, &r->cpu, &diag);
    if (res == XRSC_OK)
        res = gpu_scene_create(r->gpu, r->cpu, &r->gs, &diag);
    if (res == XRSC_OK) {
        mt_env env = {.gpu = r->gpu, .scene = r->gs, .cpu_scene = r->cpu, .width = w, .height = h};
        res = mt_samplecache_create(&env, opt, &r->m, &diag);
    }
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    return res == XRSC_OK;
}

/** A second method on the same scene and context. */
static inline mt_method *tsc_new_method(tsc_rig *r, const xrsc_samplecache_options *opt)
{
    mt_env env = {
        .gpu = r->gpu, .scene = r->gs, .cpu_scene = r->cpu, .width = r->width, .height = r->height};
    mt_method *m = NULL;
    xrsc_diag diag = {0};
    xrsc_result res = mt_samplecache_create(&env, opt, &m, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    return m;
}

/** Destroys everything and checks the validation layer reported nothing. */
static inline void tsc_close(tsc_rig *r)
{
    mt_method_destroy(&r->m);
    if (r->gs)
        gpu_scene_destroy(r->gpu, &r->gs);
    sc_scene_destroy(&r->cpu);
    if (r->gpu) {
        CHECK_EQ_INT(r->gpu->validation_errors, 0);
        gpu_context_destroy(&r->gpu);
    }
}

/** Moves the scene's animated instances to time_s (CPU and the GPU's staged copy; the
 *  method's next frame records the TLAS update). */
static inline void tsc_set_time(tsc_rig *r, double time_s)
{
    sc_scene_evaluate(r->cpu, time_s);
    xrsc_diag diag = {0};
    CHECK_EQ_INT(gpu_scene_stage_instances(r->gpu, r->gs, r->cpu, &diag), XRSC_OK);
}

static inline bool tsc_render(mt_method *m, const xrsc_frame *f)
{
    xrsc_diag diag = {0};
    xrsc_result res = mt_method_render(m, f, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    return res == XRSC_OK;
}

/** The method's counter called name after its last frame; a missing counter fails the test. */
static inline double tsc_counter(const mt_method *m, const char *name)
{
    xrsc_counter c[XRSC_MAX_COUNTERS];
    uint32_t n = mt_method_counters(m, c, XRSC_MAX_COUNTERS);
    for (uint32_t i = 0; i < n; i++)
        if (!strcmp(c[i].name, name))
            return c[i].value;
    CHECK_MSG(false, "no counter %s", name);
    return 0.0;
}

static inline bool tsc_snapshot(mt_method *m, uint32_t eye, mt_sc_snapshot *out)
{
    xrsc_diag diag = {0};
    xrsc_result res = mt_samplecache_snapshot(m, eye, out, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    return res == XRSC_OK;
}

/** The scene's viewpoint as a pose. */
static inline XrPosef tsc_viewpoint(const sc_scene *s)
{
    XrPosef p = {
        .orientation = {s->viewpoint_orientation[0], s->viewpoint_orientation[1],
                        s->viewpoint_orientation[2], s->viewpoint_orientation[3]},
        .position = {s->viewpoint_position[0], s->viewpoint_position[1], s->viewpoint_position[2]}};
    return p;
}

/** Frame k at display time time_s: both eyes at the scene's viewpoint, +-32 mm along x, a
 *  symmetric field of view of half-angle atan 0.6 (~62 deg; the skinned-figure tests). */
static inline xrsc_frame tsc_viewpoint_stereo(const sc_scene *s, uint32_t k, double time_s)
{
    xrsc_frame f = {.frame_index = k, .display_time_ns = (int64_t)(time_s * 1e9)};
    XrPosef head = tsc_viewpoint(s);
    float a = (float)atan(0.6);
    for (int e = 0; e < 2; e++) {
        f.views[e].pose = head;
        f.views[e].pose.position.x += e == 0 ? -0.032f : 0.032f;
        f.views[e].fov = (XrFovf){-a, a, a, -a};
    }
    return f;
}

/** A frame of the default headset at head pose `head`. */
static inline xrsc_frame tsc_headset_frame(XrPosef head, uint32_t frame_index)
{
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    XrPosef eyes[2];
    xrsc_headset_eye_poses(&hs, head, eyes);
    xrsc_frame f = {.frame_index = frame_index};
    for (int e = 0; e < 2; e++) {
        f.views[e].pose = eyes[e];
        f.views[e].fov = hs.fov[e];
    }
    return f;
}

/** Frame 0 of the default headset at the scene's viewpoint. */
static inline xrsc_frame tsc_viewpoint_frame(const xrsc_scene *scene)
{
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    return tsc_headset_frame(info.viewpoint, 0);
}

/** Quaternion of a rotation by `angle` rad about the unit axis (x, y, z). */
static inline XrQuaternionf tsc_quat_axis(double x, double y, double z, double angle)
{
    double s = sin(0.5 * angle);
    XrQuaternionf q = {(float)(x * s), (float)(y * s), (float)(z * s), (float)cos(0.5 * angle)};
    return q;
}

/* ---- CPU projection (double) ---- */

typedef struct tsc_view {
    double view[16]; /* world -> eye, column-major (from the same float matrix as the GPU's) */
    double tan_l, tan_r, tan_u, tan_d;
    uint32_t width, height;
} tsc_view;

static inline void tsc_make_view(const xrsc_view *v, uint32_t w, uint32_t h, tsc_view *out)
{
    float m[16];
    xrsc_pose_view_matrix(v->pose, m);
    for (int i = 0; i < 16; i++)
        out->view[i] = m[i];
    /* the GPU gets tanf() of the angles (mt_trace_frame_constants) */
    out->tan_l = tanf(v->fov.angleLeft);
    out->tan_r = tanf(v->fov.angleRight);
    out->tan_u = tanf(v->fov.angleUp);
    out->tan_d = tanf(v->fov.angleDown);
    out->width = w;
    out->height = h;
}

/** Image position (pixels) of a world point (w = 1) or direction (w = 0); false behind. */
static inline bool tsc_project(const tsc_view *v, const double p[3], double w, double out[2])
{
    double q[3];
    for (int r = 0; r < 3; r++)
        q[r] =
            v->view[r] * p[0] + v->view[4 + r] * p[1] + v->view[8 + r] * p[2] + v->view[12 + r] * w;
    if (!(q[2] < 0.0))
        return false;
    double tx = q[0] / -q[2], ty = q[1] / -q[2];
    out[0] = (tx - v->tan_l) / (v->tan_r - v->tan_l) * v->width;
    out[1] = (ty - v->tan_u) / (v->tan_d - v->tan_u) * v->height;
    return true;
}

/** Eye-space -z of a world point (view depth). */
static inline double tsc_view_depth(const tsc_view *v, const double p[3])
{
    return -(v->view[2] * p[0] + v->view[6] * p[1] + v->view[10] * p[2] + v->view[14]);
}

/**
 * World position of a Listing 1 first hit with the scene's CURRENT instance transforms
 * (*out_w = 1), or the direction of a background sample (*out_w = 0). False when the ids are
 * out of range, the barycentrics leave the triangle or a direction is not unit.
 */
static inline bool tsc_sample_world(const sc_scene *s, const uint32_t fh[4], double out[3],
                                    double *out_w)
{
    if (fh[3] == XS_SC_BACKGROUND) {
        float d[3];
        memcpy(d, fh, sizeof(d));
        double len = sqrt((double)d[0] * d[0] + (double)d[1] * d[1] + (double)d[2] * d[2]);
        for (int i = 0; i < 3; i++)
            out[i] = d[i];
        *out_w = 0.0;
        return fabs(len - 1.0) <= 1e-5;
    }
    *out_w = 1.0;
    uint32_t inst = fh[3], prim = fh[2];
    if (inst >= s->instance_count)
        return false;
    const sc_instance *in = &s->instances[inst];
    const sc_mesh *mesh = &s->meshes[in->mesh];
    if (prim >= mesh->index_count / 3 || xs_sc_unpack_material(fh[0], fh[1]) >= s->material_count)
        return false;
    double u = xs_sc_unpack_bary(fh[0]), v = xs_sc_unpack_bary(fh[1]);
    if (u + v > 1.0 + 1e-6)
        return false;
    double wt[3] = {1.0 - u - v, u, v};
    out[0] = out[1] = out[2] = 0.0;
    for (int c = 0; c < 3; c++) {
        const float *p = s->vertices[s->indices[mesh->first_index + 3 * prim + c]].position;
        for (int r = 0; r < 3; r++)
            out[r] += wt[c] * ((double)in->world[r] * p[0] + (double)in->world[4 + r] * p[1] +
                               (double)in->world[8 + r] * p[2] + (double)in->world[12 + r]);
    }
    return true;
}

/* ---- snapshot access ---- */

static inline const uint32_t *tsc_fh(const mt_sc_snapshot *sn, uint32_t slot, uint32_t p)
{
    return &sn->fh[((size_t)slot * sn->width * sn->height + p) * 4];
}
static inline const float *tsc_rad(const mt_sc_snapshot *sn, uint32_t slot, uint32_t p)
{
    return &sn->rad[((size_t)slot * sn->width * sn->height + p) * 4];
}
static inline uint32_t tsc_occ(const mt_sc_snapshot *sn, uint32_t p)
{
    return sn->mask[p] & XS_SC_OCC_MASK & ((1u << sn->slots) - 1u);
}
static inline uint32_t tsc_vis(const mt_sc_snapshot *sn, uint32_t p)
{
    return (sn->mask[p] >> XS_SC_MAX_SLOTS) & ((1u << sn->slots) - 1u);
}
static inline uint32_t tsc_popcount(uint32_t v)
{
    return (uint32_t)__builtin_popcount(v);
}

/* ---- glTF scenes of quads ---- */

/** One quad of a test scene: the square [-half, half]^2 of the node's z = 0 plane (normal
 *  +z), translated to `pos`, with a diffuse base colour; `move` != 0 adds a LINEAR
 *  translation animation from pos (time 0) to pos + move (time anim_s). */
typedef struct tsc_quad {
    float half;
    float pos[3];
    float color[3];
    float move[3];
} tsc_quad;

/**
 * Writes a glTF of quads (one mesh, material and node each) to a temporary file and returns
 * its path (static buffer of t_temp_file). Environment radiance env (extras.xrsc_environment).
 */
static inline const char *tsc_quads_gltf(const char *name, const tsc_quad *q, uint32_t count,
                                         double anim_s, float env)
{
    /* buffer: per quad 4 positions, 4 normals (96 B); shared u16 indices (12 B); then times
     * (8 B) and per moving quad 2 translations (24 B) */
    uint32_t movers = 0;
    for (uint32_t i = 0; i < count; i++)
        movers += q[i].move[0] != 0.0f || q[i].move[1] != 0.0f || q[i].move[2] != 0.0f;
    size_t size = count * 96u + 12u + 8u + movers * 24u;
    uint8_t *buf = calloc(1, size);
    size_t json_cap = 4096 + count * 1024 + size * 2;
    char *json = malloc(json_cap);
    char *nodes = malloc(count * 256 + 16), *meshes = malloc(count * 256 + 16);
    char *mats = malloc(count * 256 + 16), *acc = malloc(count * 512 + 1024);
    char *views = malloc(count * 256 + 1024), *anim = malloc(movers * 256 + 256);
    nodes[0] = meshes[0] = mats[0] = acc[0] = views[0] = anim[0] = '\0';
    size_t off = 0;
    for (uint32_t i = 0; i < count; i++) {
        float h = q[i].half;
        float pos[12] = {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0};
        float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
        memcpy(buf + off, pos, 48);
        memcpy(buf + off + 48, nrm, 48);
        off += 96;
    }
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    size_t idx_off = off;
    memcpy(buf + off, idx, 12);
    off += 12;
    size_t time_off = off;
    const float times[2] = {0.0f, (float)anim_s};
    memcpy(buf + off, times, 8);
    off += 8;
    size_t tr_off = off;
    /* accessors: per quad 2 (position, normal); then indices; times; per mover 1 */
    uint32_t acc_idx = 2 * count + 0, acc_time = 2 * count + 1, acc_tr = 2 * count + 2;
    uint32_t mover = 0;
    for (uint32_t i = 0; i < count; i++) {
        char tmp[1024];
        snprintf(tmp, sizeof tmp, "%s{\"translation\": [%.9g, %.9g, %.9g], \"mesh\": %u}",
                 i ? ", " : "", q[i].pos[0], q[i].pos[1], q[i].pos[2], i);
        strcat(nodes, tmp);
        snprintf(tmp, sizeof tmp,
                 "%s{\"primitives\": [{\"attributes\": {\"POSITION\": %u, \"NORMAL\": %u},"
                 " \"indices\": %u, \"material\": %u}]}",
                 i ? ", " : "", 2 * i, 2 * i + 1, acc_idx, i);
        strcat(meshes, tmp);
        snprintf(tmp, sizeof tmp,
                 "%s{\"pbrMetallicRoughness\": {\"baseColorFactor\": [%.9g, %.9g, %.9g, 1],"
                 " \"metallicFactor\": 0, \"roughnessFactor\": 1}}",
                 i ? ", " : "", q[i].color[0], q[i].color[1], q[i].color[2]);
        strcat(mats, tmp);
        float h = q[i].half;
        snprintf(tmp, sizeof tmp,
                 "%s{\"bufferView\": %u, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\","
                 " \"min\": [%.9g, %.9g, 0], \"max\": [%.9g, %.9g, 0]},"
                 " {\"bufferView\": %u, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"}",
                 i ? ", " : "", 2 * i, -h, -h, h, h, 2 * i + 1);
        strcat(acc, tmp);
        snprintf(tmp, sizeof tmp,
                 "%s{\"buffer\": 0, \"byteOffset\": %u, \"byteLength\": 48},"
                 " {\"buffer\": 0, \"byteOffset\": %u, \"byteLength\": 48}",
                 i ? ", " : "", i * 96u, i * 96u + 48u);
        strcat(views, tmp);
        if (q[i].move[0] != 0.0f || q[i].move[1] != 0.0f || q[i].move[2] != 0.0f) {
            float tr[6] = {q[i].pos[0],
                           q[i].pos[1],
                           q[i].pos[2],
                           q[i].pos[0] + q[i].move[0],
                           q[i].pos[1] + q[i].move[1],
                           q[i].pos[2] + q[i].move[2]};
            if (mover < movers) /* always true; tells the compiler the slot exists */
                memcpy(buf + tr_off + mover * 24u, tr, 24);
            snprintf(tmp, sizeof tmp,
                     "%s{\"sampler\": %u, \"target\": {\"node\": %u, \"path\": \"translation\"}}",
                     mover ? ", " : "", mover, i);
            strcat(anim, tmp);
            mover++;
        }
    }
    char tmp[1024];
    /* views: 2 per quad, then indices, times, translations */
    snprintf(tmp, sizeof tmp,
             ", {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": 12},"
             " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": 8}",
             idx_off, time_off);
    strcat(views, tmp);
    if (movers) {
        snprintf(tmp, sizeof tmp, ", {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %u}",
                 tr_off, movers * 24u);
        strcat(views, tmp);
    }
    snprintf(tmp, sizeof tmp,
             ", {\"bufferView\": %u, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"},"
             " {\"bufferView\": %u, \"componentType\": 5126, \"count\": 2, \"type\": \"SCALAR\","
             " \"min\": [0], \"max\": [%.9g]}",
             2 * count, 2 * count + 1, anim_s);
    strcat(acc, tmp);
    char *samplers = malloc(movers * 128 + 16);
    samplers[0] = '\0';
    for (uint32_t k = 0; k < movers; k++) {
        snprintf(tmp, sizeof tmp,
                 ", {\"bufferView\": %u, \"byteOffset\": %u, \"componentType\": 5126,"
                 " \"count\": 2, \"type\": \"VEC3\"}",
                 2 * count + 2, k * 24u);
        strcat(acc, tmp);
        snprintf(tmp, sizeof tmp,
                 "%s{\"input\": %u, \"output\": %u, \"interpolation\": \"LINEAR\"}", k ? ", " : "",
                 acc_time, acc_tr + k);
        strcat(samplers, tmp);
    }
    char *uri = t_data_uri(buf, size);
    char *scene_nodes = malloc(count * 12 + 4);
    scene_nodes[0] = '\0';
    for (uint32_t i = 0; i < count; i++) {
        snprintf(tmp, sizeof tmp, "%s%u", i ? ", " : "", i);
        strcat(scene_nodes, tmp);
    }
    char *anims = malloc(strlen(samplers) + strlen(anim) + 128);
    if (movers)
        sprintf(anims, ", \"animations\": [{\"samplers\": [%s], \"channels\": [%s]}]", samplers,
                anim);
    else
        anims[0] = '\0';
    snprintf(json, json_cap,
             "{\"asset\": {\"version\": \"2.0\"}, \"extras\": {\"xrsc_environment\": [%.9g, %.9g, "
             "%.9g]}, \"scene\": 0, \"scenes\": [{\"nodes\": [%s]}], \"nodes\": [%s],"
             " \"meshes\": [%s], \"materials\": [%s], \"accessors\": [%s], \"bufferViews\": [%s],"
             " \"buffers\": [{\"byteLength\": %zu, \"uri\": \"%s\"}]%s}",
             env, env, env, scene_nodes, nodes, meshes, mats, acc, views, size, uri, anims);
    const char *path = t_temp_file(name, json);
    free(anims);
    free(scene_nodes);
    free(uri);
    free(samplers);
    free(buf);
    free(json);
    free(nodes);
    free(meshes);
    free(mats);
    free(acc);
    free(views);
    free(anim);
    return path;
}

/* ---- the cache invariants of one eye's snapshot (seed 000 §3) ---- */

/* A stored sample vs its pixel: float (GPU) vs double (here), pixels. */
#define TSC_PIXEL_MARGIN 1e-2

typedef struct tsc_invariants {
    uint32_t bad_bits;    /**< mask bits of slots >= N */
    uint32_t vis_not_occ; /**< v_s without o_s */
    uint32_t no_visible;  /**< pixels without a visible sample */
    uint32_t bad_hit;     /**< occupied slots that decode to no valid first hit / direction */
    uint32_t outside;     /**< samples whose position projects outside their pixel */
    uint32_t samples, visible;
    uint32_t background; /**< occupied slots holding a background direction */
} tsc_invariants;

/** Checks the invariants of snapshot sn against the scene's current transforms and view v. */
static inline void tsc_check_invariants(const mt_sc_snapshot *sn, const sc_scene *cpu,
                                        const tsc_view *v, tsc_invariants *c)
{
    uint32_t n = sn->slots, px = sn->width * sn->height;
    uint32_t all = (1u << n) - 1u;
    for (uint32_t p = 0; p < px; p++) {
        uint32_t m = sn->mask[p];
        uint32_t occ = m & XS_SC_OCC_MASK, vis = m >> XS_SC_MAX_SLOTS;
        c->bad_bits += (occ & ~all) || (vis & ~all);
        c->vis_not_occ += (vis & ~occ) != 0;
        c->no_visible += (vis & all) == 0;
        uint32_t x = p % sn->width, y = p / sn->width;
        for (uint32_t s = 0; s < n; s++) {
            if (!(occ >> s & 1u))
                continue;
            c->samples++;
            c->visible += vis >> s & 1u;
            double wp[3], w, pos[2] = {0.0, 0.0};
            const uint32_t *fh = tsc_fh(sn, s, p);
            c->background += fh[3] == XS_SC_BACKGROUND;
            if (!tsc_sample_world(cpu, fh, wp, &w)) {
                c->bad_hit++;
                continue;
            }
            bool ok = tsc_project(v, wp, w, pos);
            if (!ok || pos[0] < x - TSC_PIXEL_MARGIN || pos[0] > x + 1 + TSC_PIXEL_MARGIN ||
                pos[1] < y - TSC_PIXEL_MARGIN || pos[1] > y + 1 + TSC_PIXEL_MARGIN) {
                if (c->outside < 5)
                    fprintf(stderr, "  sample (%u,%u) slot %u projects to (%.4f, %.4f)\n", x, y, s,
                            pos[0], pos[1]);
                c->outside++;
            }
        }
    }
}

/**
 * Convergence on a still view of scenes/cornell.gltf (its viewpoint, the default headset):
 * renders `frames` frames of a w x w renderer with options ro and, after each frame k listed in
 * at[0..at_count), stores in rel[k] the relMSE (mean of both eyes) against an `spp` reference
 * accumulated over ref_frames frames of ref_spp samples (seed 1234). Prints the series; checks
 * every call and zero validation errors. rel has room for frames + 1 values.
 */
static inline void tsc_convergence(const xrsc_renderer_options *ro, uint32_t w, uint32_t frames,
                                   const uint32_t *at, uint32_t at_count, uint32_t ref_spp,
                                   uint32_t ref_frames, double *rel)
{
    xrsc_context *ctx = NULL;
    xrsc_scene *scene = NULL;
    xrsc_renderer *r = NULL, *ref = NULL;
    xrsc_context_options co = {.validation = true};
    CHECK_EQ_INT(xrsc_context_create(&co, &ctx, NULL), XRSC_OK);
    if (!ctx)
        return;
    CHECK_EQ_INT(xrsc_scene_load(ctx, t_source_path("scenes/cornell.gltf"), NULL, &scene, NULL),
                 XRSC_OK);
    xrsc_renderer_options o = *ro;
    o.width = o.height = w;
    xrsc_renderer_options rr = {.method = XRSC_METHOD_SPP,
                                .width = w,
                                .height = w,
                                .seed = 1234,
                                .spp = {.samples_per_pixel = ref_spp, .accumulate = true}};
    if (scene) {
        CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &o, &r, NULL), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &rr, &ref, NULL), XRSC_OK);
    }
    size_t n = (size_t)w * w;
    float *refimg[2] = {malloc(n * 16), malloc(n * 16)}, *img = malloc(n * 16);
    if (!r || !ref || !refimg[0] || !refimg[1] || !img)
        goto done;
    xrsc_frame f = tsc_viewpoint_frame(scene);
    for (uint32_t k = 0; k < ref_frames; k++) {
        f.frame_index = k;
        CHECK_EQ_INT(xrsc_renderer_render(ref, &f), XRSC_OK);
    }
    for (uint32_t e = 0; e < 2; e++)
        CHECK_EQ_INT(xrsc_renderer_read(ref, e, XRSC_OUTPUT_COLOR, refimg[e], n * 16), XRSC_OK);
    printf("  relMSE vs %u spp:", ref_spp * ref_frames);
    for (uint32_t k = 0; k < frames; k++) {
        f.frame_index = k;
        CHECK_EQ_INT(xrsc_renderer_render(r, &f), XRSC_OK);
        uint32_t frame = k + 1;
        bool scored = false;
        for (uint32_t i = 0; i < at_count; i++)
            scored |= at[i] == frame;
        if (!scored)
            continue;
        double sum = 0.0;
        for (uint32_t e = 0; e < 2; e++) {
            xrsc_error_metrics em;
            CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, img, n * 16), XRSC_OK);
            CHECK_EQ_INT(xrsc_metrics_error(img, refimg[e], w, w, NULL, &em), XRSC_OK);
            sum += em.relmse;
        }
        rel[frame] = sum / 2.0;
        printf(" %u: %.4f", frame, rel[frame]);
    }
    printf("\n");
done:
    free(refimg[0]);
    free(refimg[1]);
    free(img);
    xrsc_renderer_destroy(&r);
    xrsc_renderer_destroy(&ref);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}
