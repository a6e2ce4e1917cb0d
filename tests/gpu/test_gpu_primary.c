// SPDX-License-Identifier: MIT
/**
 * @file test_gpu_primary.c
 * @brief Exact primary hits: `primary` on scenes/triangles.gltf against a CPU Möller–Trumbore
 *        reference over the same (Morton-sorted) triangles and instance transforms.
 *
 * Rays go through pixel centres with the convention of xs_camera.glsl: eye-space direction
 * (mix(tanL, tanR, u), mix(tanU, tanD, v), -1), u = (x + 0.5) / w, v = (y + 0.5) / h with row 0
 * at the top, rotated by the eye orientation. For every pixel whose reference hit is not
 * ambiguous, instance and primitive must be equal; barycentrics and depth must agree within
 * the tolerances below. Ambiguous pixels (ray within T_EDGE_EPS barycentric of an edge of a
 * triangle it reaches, or nearest and second-nearest hits within T_T_EPS) are counted and must
 * stay below T_MAX_AMBIGUOUS_FRACTION.
 *
 * Facing (test_front_face): xs_hit.front_face must mean "the ray hit the glTF front side".
 * Neither `primary` nor any public output carries front_face, so this check traces with a
 * raygen of its own (facing.rgen, built with the test) that stores what the library's
 * hit.rchit reports, over the library's TLAS (gpu_scene, instance flags included), through the
 * internal method layer (mt_trace).
 */
#include "gpu_scene.h"
#include "mt_trace.h"
#include "sc_scene.h"
#include "t_context.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* generated from facing.rgen: const uint32_t t_facing_rgen_spv[] (needs <stdint.h> first) */
#include "facing_rgen_spv.h"

#define T_W 96u
#define T_H 96u
#define T_MISS 0xFFFFFFFFu
/* Ambiguity: barycentric distance to an edge, and relative gap between the two nearest hits. */
#define T_EDGE_EPS 1e-4
#define T_T_EPS 1e-5
#define T_MAX_AMBIGUOUS_FRACTION 0.01
/* Float32 hardware-style intersection vs double reference. */
#define T_BARY_TOL 2e-4
#define T_DEPTH_REL_TOL 1e-4

static xrsc_context *g_ctx;

typedef struct ref_hit {
    uint32_t instance, primitive;
    double u, v, depth;
    bool ambiguous;
} ref_hit;

typedef struct world_tri {
    double p[3][3];
    uint32_t instance, primitive;
} world_tri;

static void xform_point(const float m[16], const float p[3], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = (double)m[r] * p[0] + (double)m[4 + r] * p[1] + (double)m[8 + r] * p[2] +
                 (double)m[12 + r];
}

static world_tri *world_triangles(const sc_scene *s, uint32_t *out_count)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->instance_count; i++)
        n += s->meshes[s->instances[i].mesh].index_count / 3;
    world_tri *t = calloc(n ? n : 1, sizeof(*t));
    uint32_t k = 0;
    for (uint32_t i = 0; t && i < s->instance_count; i++) {
        const sc_mesh *m = &s->meshes[s->instances[i].mesh];
        for (uint32_t p = 0; p < m->index_count / 3; p++, k++) {
            for (int c = 0; c < 3; c++) {
                uint32_t vi = s->indices[m->first_index + 3 * p + c]; /* absolute (sc_scene.h) */
                xform_point(s->instances[i].world, s->vertices[vi].position, t[k].p[c]);
            }
            t[k].instance = i;
            t[k].primitive = p;
        }
    }
    *out_count = n;
    return t;
}

static void sub3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}
static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/** Möller–Trumbore in double: plane distance t and barycentrics (u of v1, v of v2), whether or
 *  not they lie inside. Returns false for rays parallel to the plane. */
static bool intersect(const world_tri *tri, const double o[3], const double d[3], double *t,
                      double *u, double *v)
{
    double e1[3], e2[3], pv[3], tv[3], qv[3];
    sub3(tri->p[1], tri->p[0], e1);
    sub3(tri->p[2], tri->p[0], e2);
    cross3(d, e2, pv);
    double det = dot3(e1, pv);
    if (fabs(det) < 1e-300)
        return false;
    double inv = 1.0 / det;
    sub3(o, tri->p[0], tv);
    *u = dot3(tv, pv) * inv;
    cross3(tv, e1, qv);
    *v = dot3(d, qv) * inv;
    *t = dot3(e2, qv) * inv;
    return true;
}

static void reference(const world_tri *tris, uint32_t n, const xrsc_view *view, uint32_t x,
                      uint32_t y, ref_hit *out)
{
    double tl = tan(view->fov.angleLeft), tr = tan(view->fov.angleRight);
    double tu = tan(view->fov.angleUp), td = tan(view->fov.angleDown);
    double fu = (x + 0.5) / T_W, fv = (y + 0.5) / T_H;
    XrVector3f de = {(float)(tl + (tr - tl) * fu), (float)(tu + (td - tu) * fv), -1.0f};
    XrVector3f dw = xrsc_quat_rotate(view->pose.orientation, de);
    XrVector3f fw = xrsc_quat_rotate(view->pose.orientation, (XrVector3f){0, 0, -1});
    double d[3] = {dw.x, dw.y, dw.z};
    double len = sqrt(dot3(d, d));
    for (int i = 0; i < 3; i++)
        d[i] /= len;
    double o[3] = {view->pose.position.x, view->pose.position.y, view->pose.position.z};
    double best = DBL_MAX, second = DBL_MAX;
    memset(out, 0, sizeof(*out));
    out->instance = T_MISS;
    bool near_edge = false;
    for (uint32_t k = 0; k < n; k++) {
        double t, u, v;
        if (!intersect(&tris[k], o, d, &t, &u, &v) || t <= 0.0)
            continue;
        double w = 1.0 - u - v;
        double mn = fmin(w, fmin(u, v));
        if (fabs(mn) < T_EDGE_EPS && t <= best * (1.0 + T_T_EPS))
            near_edge = true;
        if (mn < 0.0)
            continue;
        if (t < best) {
            second = best;
            best = t;
            out->instance = tris[k].instance;
            out->primitive = tris[k].primitive;
            out->u = u;
            out->v = v;
        } else if (t < second) {
            second = t;
        }
    }
    if (out->instance != T_MISS) {
        double fwd[3] = {fw.x, fw.y, fw.z};
        out->depth = best * dot3(d, fwd);
    }
    out->ambiguous = near_edge || (second < DBL_MAX && second - best <= T_T_EPS * best);
}

static void make_views(xrsc_view views[2])
{
    /* Asymmetric FOVs, mirrored for the right eye, and a small yaw on the right eye so both the
     * rotation and the tan_fov mapping are exercised. Eyes at the scene camera (0, 0, 2). */
    for (int e = 0; e < 2; e++) {
        float s = e == 0 ? -1.0f : 1.0f;
        views[e].pose.position = (XrVector3f){0.0315f * s, 0.02f, 2.0f};
        views[e].pose.orientation =
            e == 0 ? (XrQuaternionf){0, 0, 0, 1}
                   : xrsc_quat_from_axis_angle((XrVector3f){0, 1, 0}, 0.06f);
        views[e].fov.angleLeft = e == 0 ? -0.33f : -0.27f;
        views[e].fov.angleRight = e == 0 ? 0.27f : 0.33f;
        views[e].fov.angleUp = 0.22f;
        views[e].fov.angleDown = -0.25f;
    }
}

static void test_primary_hits(void)
{
    const char *path = t_source_path("scenes/triangles.gltf");
    sc_scene *cpu = NULL;
    xrsc_diag diag;
    char buf[1024];
    xrsc_result r = sc_scene_load(path, NULL, &cpu, &diag);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    xrsc_scene *scene = NULL;
    r = xrsc_scene_load(g_ctx, path, NULL, &scene, &diag);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    xrsc_renderer *rend = NULL;
    if (scene) {
        xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = T_W, .height = T_H};
        r = xrsc_renderer_create(g_ctx, scene, &ro, &rend, &diag);
        CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    }
    if (!cpu || !rend) {
        xrsc_renderer_destroy(&rend);
        xrsc_scene_destroy(&scene);
        sc_scene_destroy(&cpu);
        return;
    }
    xrsc_frame frame = {0};
    make_views(frame.views);
    CHECK_EQ_INT(xrsc_renderer_render(rend, &frame), XRSC_OK);
    CHECK_EQ_INT(xrsc_renderer_rays_last_frame(rend), 2ull * T_W * T_H);

    uint32_t ntri = 0;
    world_tri *tris = world_triangles(cpu, &ntri);
    uint32_t *hit = malloc(T_W * T_H * 16);
    float *depth = malloc(T_W * T_H * 4);
    CHECK_EQ_INT(xrsc_renderer_output_size(rend, XRSC_OUTPUT_HIT_ID), T_W * T_H * 16);
    CHECK_EQ_INT(xrsc_renderer_output_size(rend, XRSC_OUTPUT_DEPTH), T_W * T_H * 4);
    /* A too-small destination is refused. */
    CHECK(xrsc_renderer_read(rend, 0, XRSC_OUTPUT_DEPTH, depth, 16) != XRSC_OK);

    uint32_t ambiguous = 0, mismatched_id = 0, hits = 0, misses = 0, checked = 0;
    double max_bary = 0.0, max_depth_rel = 0.0;
    uint32_t instances_seen = 0;
    for (uint32_t eye = 0; eye < 2 && tris && hit && depth; eye++) {
        CHECK_EQ_INT(xrsc_renderer_read(rend, eye, XRSC_OUTPUT_HIT_ID, hit, T_W * T_H * 16),
                     XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(rend, eye, XRSC_OUTPUT_DEPTH, depth, T_W * T_H * 4),
                     XRSC_OK);
        for (uint32_t y = 0; y < T_H; y++) {
            for (uint32_t x = 0; x < T_W; x++) {
                ref_hit ref;
                reference(tris, ntri, &frame.views[eye], x, y, &ref);
                if (ref.ambiguous) {
                    ambiguous++;
                    continue;
                }
                checked++;
                const uint32_t *g = &hit[4 * (y * T_W + x)];
                float gd = depth[y * T_W + x];
                if (g[0] != ref.instance || (ref.instance != T_MISS && g[1] != ref.primitive)) {
                    if (mismatched_id++ < 10)
                        fprintf(stderr, "eye %u pixel (%u, %u): gpu %u/%u, cpu %u/%u\n", eye, x,
                                y, g[0], g[1], ref.instance, ref.primitive);
                    continue;
                }
                if (ref.instance == T_MISS) {
                    misses++;
                    CHECK(gd == 0.0f);
                    continue;
                }
                hits++;
                if (ref.instance < 32)
                    instances_seen |= 1u << ref.instance;
                float gu, gv;
                memcpy(&gu, &g[2], 4);
                memcpy(&gv, &g[3], 4);
                max_bary = fmax(max_bary, fmax(fabs(gu - ref.u), fabs(gv - ref.v)));
                max_depth_rel = fmax(max_depth_rel, fabs(gd - ref.depth) / ref.depth);
            }
        }
    }
    uint32_t total = 2 * T_W * T_H;
    printf("primary: %u pixels, %u checked (%u hits, %u misses), %u ambiguous (%.3f%%), "
           "%u id mismatches, max |bary| err %.2e, max depth rel err %.2e\n",
           total, checked, hits, misses, ambiguous, 100.0 * ambiguous / total, mismatched_id,
           max_bary, max_depth_rel);
    CHECK_EQ_INT(mismatched_id, 0);
    CHECK_MSG(ambiguous < T_MAX_AMBIGUOUS_FRACTION * total, "%u ambiguous", ambiguous);
    CHECK(max_bary <= T_BARY_TOL);
    CHECK(max_depth_rel <= T_DEPTH_REL_TOL);
    /* The views see every instance and both hits and misses. */
    CHECK_EQ_INT(instances_seen, (1u << cpu->instance_count) - 1u);
    CHECK(hits > total / 2);
    CHECK(misses > 0);

    free(tris);
    free(hit);
    free(depth);
    xrsc_renderer_destroy(&rend);
    xrsc_scene_destroy(&scene);
    sc_scene_destroy(&cpu);
}

/** `spp` with no_jitter shoots its first ray through the pixel centre too: same hit ids. */
static void test_spp_no_jitter_same_first_hits(void)
{
    const char *path = t_source_path("scenes/triangles.gltf");
    xrsc_scene *scene = NULL;
    CHECK_EQ_INT(xrsc_scene_load(g_ctx, path, NULL, &scene, NULL), XRSC_OK);
    if (!scene)
        return;
    xrsc_renderer *a = NULL, *b = NULL;
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = T_W, .height = T_H};
    CHECK_EQ_INT(xrsc_renderer_create(g_ctx, scene, &ro, &a, NULL), XRSC_OK);
    ro.method = XRSC_METHOD_SPP;
    ro.spp.no_jitter = true;
    CHECK_EQ_INT(xrsc_renderer_create(g_ctx, scene, &ro, &b, NULL), XRSC_OK);
    size_t size = T_W * T_H * 16;
    uint32_t *ha = malloc(size), *hb = malloc(size);
    if (a && b && ha && hb) {
        xrsc_frame frame = {0};
        make_views(frame.views);
        CHECK_EQ_INT(xrsc_renderer_render(a, &frame), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_render(b, &frame), XRSC_OK);
        for (uint32_t eye = 0; eye < 2; eye++) {
            CHECK_EQ_INT(xrsc_renderer_read(a, eye, XRSC_OUTPUT_HIT_ID, ha, size), XRSC_OK);
            CHECK_EQ_INT(xrsc_renderer_read(b, eye, XRSC_OUTPUT_HIT_ID, hb, size), XRSC_OK);
            uint32_t diff = 0;
            for (uint32_t p = 0; p < T_W * T_H; p++)
                diff += ha[4 * p] != hb[4 * p] || ha[4 * p + 1] != hb[4 * p + 1];
            CHECK_EQ_INT(diff, 0);
        }
    }
    free(ha);
    free(hb);
    xrsc_renderer_destroy(&a);
    xrsc_renderer_destroy(&b);
    xrsc_scene_destroy(&scene);
}

/* ---- facing ---- */

/** Front side of instance i of the facing scene as seen from the origin: 1 = glTF front. */
static const uint32_t t_facing_expected[4] = {1, 0, 1, 0};

/**
 * One triangle, counter-clockwise seen from +Z (its glTF front, normals +Z), 0.5 m in size,
 * instanced 3 m in front of a camera at the origin looking down -Z:
 *   node 0 at (-1, 0, -3): as is, the camera sees its front;
 *   node 1 at (+1, 0, -3): turned 180 deg about Y, the camera sees its back;
 *   node 2 at (0, +1.1, -3): mirrored (scale x -1, determinant < 0): glTF 2.0 ("Meshes") makes
 *     the clockwise side the front, so the front still faces the camera (and the normals,
 *     transformed by the inverse transpose, still point to +Z);
 *   node 3 at (0, -1.1, -3): mirrored and turned 180 deg: the camera sees its back.
 */
static const char *write_facing_scene(void)
{
    float data[18] = {-0.5f, -0.5f, 0.0f, 0.5f, -0.5f, 0.0f, 0.0f, 0.5f, 0.0f, /* POSITION */
                      0.0f,  0.0f,  1.0f, 0.0f, 0.0f,  1.0f, 0.0f, 0.0f, 1.0f}; /* NORMAL */
    char *uri = t_data_uri(data, sizeof(data));
    if (!uri)
        return NULL;
    static char json[4096];
    snprintf(json, sizeof(json),
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1,2,3]}],"
             "\"nodes\":[{\"mesh\":0,\"translation\":[-1,0,-3]},"
             "{\"mesh\":0,\"translation\":[1,0,-3],\"rotation\":[0,1,0,0]},"
             "{\"mesh\":0,\"translation\":[0,1.1,-3],\"scale\":[-1,1,1]},"
             "{\"mesh\":0,\"translation\":[0,-1.1,-3],\"rotation\":[0,1,0,0],"
             "\"scale\":[-1,1,1]}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1}}]}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,"
             "\"type\":\"VEC3\",\"min\":[-0.5,-0.5,0],\"max\":[0.5,0.5,0]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":36}],"
             "\"buffers\":[{\"byteLength\":72,"
             "\"uri\":\"%s\"}]}",
             uri);
    free(uri);
    return t_temp_file("facing.gltf", json);
}

static void test_front_face(void)
{
    const char *path = write_facing_scene();
    CHECK(path != NULL);
    if (!path)
        return;
    gpu_context_options go = {.validation = true};
    gpu_context *gpu = NULL;
    sc_scene *cpu = NULL;
    gpu_scene *gs = NULL;
    mt_trace tr = {0};
    bool have_trace = false;
    xrsc_diag diag;
    char buf[1024];
    uint32_t *hit = malloc(T_W * T_H * 16);
    CHECK(hit != NULL);
    xrsc_result r = gpu_context_create(&go, &gpu, &diag);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    if (r == XRSC_OK) {
        r = sc_scene_load(path, NULL, &cpu, &diag);
        CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    }
    if (r == XRSC_OK) {
        CHECK_EQ_INT(cpu->instance_count, 4);
        r = gpu_scene_create(gpu, cpu, &gs, &diag);
        CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    }
    if (r == XRSC_OK && cpu->instance_count == 4) {
        mt_env env = {.gpu = gpu, .scene = gs, .cpu_scene = cpu, .width = T_W, .height = T_H};
        gpu_rt_program_desc desc = {.raygen = "facing.rgen",
                                    .raygen_spirv = t_facing_rgen_spv,
                                    .raygen_spirv_size = sizeof(t_facing_rgen_spv)};
        r = mt_trace_init_program(&tr, &env, &desc, &diag);
        CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
        have_trace = r == XRSC_OK;
    }
    if (have_trace && hit) {
        xrsc_frame frame = {0};
        for (int e = 0; e < 2; e++) {
            frame.views[e].pose = xrsc_pose_identity();
            frame.views[e].fov = (XrFovf){-0.6f, 0.6f, 0.6f, -0.6f};
        }
        xs_frame xf;
        mt_trace_frame_constants(&tr, &frame, &xf);
        CHECK_EQ_INT(mt_trace_run(&tr, &xf, false, NULL), XRSC_OK);
        CHECK_EQ_INT(mt_trace_read(&tr, 0, XRSC_OUTPUT_HIT_ID, hit, T_W * T_H * 16, NULL),
                     XRSC_OK);
        /* per instance: pixels reported front-facing, back-facing, anything else */
        uint32_t front[4] = {0}, back[4] = {0}, other = 0;
        for (uint32_t p = 0; p < T_W * T_H; p++) {
            const uint32_t *g = &hit[4 * p];
            if (g[0] == T_MISS)
                continue;
            if (g[0] >= 4 || g[3] != 1u || g[2] > 1u) {
                other++;
                continue;
            }
            (g[2] ? front : back)[g[0]]++;
        }
        /* One submission per frame (xrsc.h timings): the instance update, the trace and the
         * read-back of the outputs read last frame; a read after it submits nothing. */
        float *color = malloc(T_W * T_H * 16);
        for (int k = 0; k < 3 && color; k++) {
            CHECK_EQ_INT(gpu_scene_stage_instances(gpu, gs, cpu, NULL), XRSC_OK);
            uint64_t s0 = gpu->submit_count;
            CHECK_EQ_INT(mt_trace_run(&tr, &xf, false, NULL), XRSC_OK);
            uint64_t s1 = gpu->submit_count;
            for (uint32_t e = 0; e < 2; e++)
                CHECK_EQ_INT(mt_trace_read(&tr, e, XRSC_OUTPUT_COLOR, color, T_W * T_H * 16,
                                           NULL),
                             XRSC_OK);
            uint64_t s2 = gpu->submit_count;
            CHECK_EQ_INT(s1 - s0, 1);
            /* frame 0: colour was not read before, one submission stages both eyes */
            CHECK_EQ_INT(s2 - s1, k == 0 ? 1 : 0);
            CHECK(tr.timer.pass_count == 2 && !strcmp(tr.timer.names[0], "tlas") &&
                  !strcmp(tr.timer.names[1], "trace"));
        }
        free(color);
        /* The instance updates above moved nothing: the same hits. */
        uint32_t *again = malloc(T_W * T_H * 16);
        if (again) {
            CHECK_EQ_INT(mt_trace_read(&tr, 0, XRSC_OUTPUT_HIT_ID, again, T_W * T_H * 16, NULL),
                         XRSC_OK);
            CHECK(memcmp(again, hit, T_W * T_H * 16) == 0);
        }
        free(again);
        printf("facing (front/back pixels): instance 0 (front seen) %u/%u, 1 (back seen) "
               "%u/%u, 2 (mirrored, front seen) %u/%u, 3 (mirrored, back seen) %u/%u\n",
               front[0], back[0], front[1], back[1], front[2], back[2], front[3], back[3]);
        CHECK_EQ_INT(other, 0);
        for (int i = 0; i < 4; i++) {
            uint32_t right = t_facing_expected[i] ? front[i] : back[i];
            uint32_t wrong = t_facing_expected[i] ? back[i] : front[i];
            CHECK_MSG(right > 100 && wrong == 0, "instance %d: %u right, %u wrong", i, right,
                      wrong);
        }
    }
    free(hit);
    if (have_trace)
        mt_trace_fini(&tr);
    if (gpu) {
        gpu_scene_destroy(gpu, &gs);
        uint32_t errors = gpu->validation_errors;
        CHECK_MSG(errors == 0, "%u validation errors", errors);
    }
    sc_scene_destroy(&cpu);
    gpu_context_destroy(&gpu);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_primary_hits);
    RUN(test_spp_no_jitter_same_first_hits);
    RUN(test_front_face);
    t_context_close(&g_ctx);
    return t_finish();
}
