// SPDX-License-Identifier: MIT
/**
 * @file test_gpu_scenes.c
 * @brief GPU plumbing over real and bundled scenes: every scene loads, renders with `spp` and
 *        `primary` (finite, non-negative colour; geometry seen from the default viewpoint;
 *        one counted ray per pixel for `primary`), device-selection errors, method names.
 *
 * Runs under the validation layer; fails if it reported any error.
 */
#include "t_context.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 64u
/* Fraction of pixels that must hit geometry from a scene's default viewpoint (the default
 * headset's wide FOV at the scene's camera or bounds-framing viewpoint, sc_scene.h). Measured
 * 16-40 % on the real scenes, 4-23 % on the bundled ones (small objects in front of the
 * camera); the minimums catch a blank or misplaced image. */
#define T_MIN_HIT_FRACTION_REAL 0.10
#define T_MIN_HIT_FRACTION_BUNDLED 0.02

static xrsc_context *g_ctx;

static void default_frame(const xrsc_scene *scene, xrsc_frame *frame)
{
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    XrPosef eyes[2];
    xrsc_headset_eye_poses(&hs, info.viewpoint, eyes);
    memset(frame, 0, sizeof(*frame));
    for (int e = 0; e < 2; e++) {
        frame->views[e].pose = eyes[e];
        frame->views[e].fov = hs.fov[e];
    }
}

typedef struct scene_stats {
    double hit_fraction;
    bool color_ok;
    uint64_t rays;
} scene_stats;

static void render_and_check(const char *path, xrsc_method method, scene_stats *st)
{
    memset(st, 0, sizeof(*st));
    xrsc_scene *scene = NULL;
    xrsc_diag diag;
    xrsc_result r = xrsc_scene_load(g_ctx, path, NULL, &scene, &diag);
    char buf[1024];
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    if (r != XRSC_OK)
        return;
    xrsc_renderer_options ro = {.method = method, .width = T_SIZE, .height = T_SIZE};
    ro.spp.samples_per_pixel = 1;
    xrsc_renderer *rend = NULL;
    r = xrsc_renderer_create(g_ctx, scene, &ro, &rend, &diag);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    if (r != XRSC_OK) {
        xrsc_scene_destroy(&scene);
        return;
    }
    xrsc_frame frame;
    default_frame(scene, &frame);
    CHECK_EQ_INT(xrsc_renderer_render(rend, &frame), XRSC_OK);
    st->rays = xrsc_renderer_rays_last_frame(rend);

    size_t csize = xrsc_renderer_output_size(rend, XRSC_OUTPUT_COLOR);
    size_t hsize = xrsc_renderer_output_size(rend, XRSC_OUTPUT_HIT_ID);
    CHECK_EQ_INT(csize, T_SIZE * T_SIZE * 16);
    CHECK_EQ_INT(hsize, T_SIZE * T_SIZE * 16);
    float *color = malloc(csize);
    uint32_t *hit = malloc(hsize);
    uint64_t hits = 0, bad = 0, total = 0;
    for (uint32_t eye = 0; eye < 2 && color && hit; eye++) {
        CHECK_EQ_INT(xrsc_renderer_read(rend, eye, XRSC_OUTPUT_COLOR, color, csize), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(rend, eye, XRSC_OUTPUT_HIT_ID, hit, hsize), XRSC_OK);
        for (uint32_t p = 0; p < T_SIZE * T_SIZE; p++) {
            for (int c = 0; c < 3; c++) {
                float v = color[4 * p + c];
                if (!isfinite(v) || v < 0.0f)
                    bad++;
            }
            if (hit[4 * p] != 0xFFFFFFFFu)
                hits++;
            total++;
        }
    }
    st->color_ok = bad == 0;
    st->hit_fraction = total ? (double)hits / (double)total : 0.0;
    free(color);
    free(hit);

    xrsc_pass_timing tm[XRSC_MAX_PASSES];
    uint32_t n = xrsc_renderer_timings(rend, tm, XRSC_MAX_PASSES);
    CHECK(n >= 1);
    CHECK(n == 2 && !strcmp(tm[0].name, "tlas") && !strcmp(tm[1].name, "trace"));
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    printf("%-70s %-7s tris %8llu hit %5.1f%% rays %8llu trace %.2f ms blas %.2f ms\n", path,
           xrsc_method_name(method), (unsigned long long)info.triangle_count,
           100.0 * st->hit_fraction, (unsigned long long)st->rays, n >= 2 ? tm[1].gpu_ms : 0.0,
           info.blas_build_ms);
    CHECK(info.triangle_count > 0);
    CHECK(info.blas_build_ms >= 0.0);
    xrsc_renderer_destroy(&rend);
    CHECK(rend == NULL);
    xrsc_scene_destroy(&scene);
    CHECK(scene == NULL);
}

static void check_scene(const char *path, double min_hit_fraction)
{
    scene_stats st;
    render_and_check(path, XRSC_METHOD_SPP, &st);
    CHECK_MSG(st.color_ok, "%s: non-finite or negative colour", path);
    CHECK_MSG(st.hit_fraction >= min_hit_fraction, "%s: only %.1f%% of pixels hit", path,
              100.0 * st.hit_fraction);
    CHECK_MSG(st.rays >= 2ull * T_SIZE * T_SIZE, "%s: %llu rays", path,
              (unsigned long long)st.rays);
    render_and_check(path, XRSC_METHOD_PRIMARY, &st);
    CHECK(st.color_ok);
    CHECK_MSG(st.hit_fraction >= min_hit_fraction, "%s: only %.1f%% of pixels hit", path,
              100.0 * st.hit_fraction);
    CHECK_EQ_INT(st.rays, 2ull * T_SIZE * T_SIZE);
}

static void test_shared_cornell(void)
{
    check_scene(t_shared_path("scenes/cornellBox_Vinc3r/cornellBox-2.80-Eevee-gltf.gltf"),
                T_MIN_HIT_FRACTION_REAL);
}

static void test_shared_glass(void)
{
    check_scene(
        t_shared_path("scenes/GlassHurricaneCandleHolder/GlassHurricaneCandleHolder.gltf"),
        T_MIN_HIT_FRACTION_REAL);
}

static void test_bundled_scenes(void)
{
    static const char *const names[] = {"scenes/furnace.gltf", "scenes/cornell.gltf",
                                        "scenes/triangles.gltf"};
    for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
        check_scene(t_source_path(names[i]), T_MIN_HIT_FRACTION_BUNDLED);
}

static void test_device_selection(void)
{
    xrsc_context *ctx = NULL;
    xrsc_diag diag;
    xrsc_context_options o = {.device = "no-such-vulkan-device-xyz", .validation = true};
    CHECK_EQ_INT(xrsc_context_create(&o, &ctx, &diag), XRSC_ERROR_DEVICE_NOT_FOUND);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_DEVICE_NOT_FOUND);
    CHECK(ctx == NULL);
    o.device = "97";
    CHECK_EQ_INT(xrsc_context_create(&o, &ctx, &diag), XRSC_ERROR_DEVICE_NOT_FOUND);
    CHECK(ctx == NULL);
    /* "0" is a valid index whenever a ray-tracing device exists (this test's premise). */
    o.device = "0";
    xrsc_result r = xrsc_context_create(&o, &ctx, &diag);
    CHECK(r == XRSC_OK || r == XRSC_ERROR_NO_RAY_TRACING_DEVICE);
    if (ctx)
        CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
    CHECK(ctx == NULL);
    xrsc_context_destroy(NULL);
}

static void test_method_names(void)
{
    xrsc_method m;
    CHECK_EQ_INT(xrsc_method_from_name("spp", &m), XRSC_OK);
    CHECK_EQ_INT(m, XRSC_METHOD_SPP);
    CHECK_EQ_INT(xrsc_method_from_name("primary", &m), XRSC_OK);
    CHECK_EQ_INT(m, XRSC_METHOD_PRIMARY);
    CHECK_EQ_INT(xrsc_method_from_name("nope", &m), XRSC_ERROR_UNKNOWN_METHOD);
    CHECK(!strcmp(xrsc_method_name(XRSC_METHOD_SPP), "spp"));
    CHECK(xrsc_method_name((xrsc_method)42) == NULL);
}

static void test_bad_scene_path(void)
{
    xrsc_scene *scene = NULL;
    xrsc_diag diag;
    xrsc_result r = xrsc_scene_load(g_ctx, t_source_path("scenes/does-not-exist.gltf"), NULL,
                                    &scene, &diag);
    CHECK(r != XRSC_OK);
    CHECK(scene == NULL);
}

/* ---- animation: TLAS update ---- */

/** A triangle (x in [-0.3, 0.3]) at z = -3 whose node moves from x = -1 (t = 0 s) to x = +1
 *  (t = 1 s); camera at the origin. */
static const char *write_moving_triangle(void)
{
    float data[17] = {-0.3f, -0.3f, -3.0f, 0.3f, -0.3f, -3.0f, 0.0f, 0.3f, -3.0f, /* POSITION */
                      0.0f,  1.0f,                                            /* times */
                      -1.0f, 0.0f,  0.0f,  1.0f, 0.0f, 0.0f};                 /* translations */
    char *uri = t_data_uri(data, sizeof(data));
    if (!uri)
        return NULL;
    static char json[4096];
    snprintf(json, sizeof(json),
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
             "\"nodes\":[{\"mesh\":0},{\"camera\":0}],"
             "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":1,\"znear\":0.05}}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
             "\"accessors\":["
             "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[-0.3,-0.3,-3],\"max\":[0.3,0.3,-3]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\","
             "\"min\":[0],\"max\":[1]},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":8},"
             "{\"buffer\":0,\"byteOffset\":44,\"byteLength\":24}],"
             "\"buffers\":[{\"byteLength\":68,"
             "\"uri\":\"%s\"}],"
             "\"animations\":[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,"
             "\"path\":\"translation\"}}],\"samplers\":[{\"input\":1,\"output\":2,"
             "\"interpolation\":\"LINEAR\"}]}]}",
             uri);
    free(uri);
    return t_temp_file("moving_triangle.gltf", json);
}

/** Mean x (pixels) of the hit pixels of the left eye, -1 if none. */
static double hit_centroid_x(xrsc_renderer *r)
{
    size_t size = xrsc_renderer_output_size(r, XRSC_OUTPUT_HIT_ID);
    uint32_t *hit = malloc(size);
    double sum = 0.0;
    uint32_t n = 0;
    if (hit && xrsc_renderer_read(r, 0, XRSC_OUTPUT_HIT_ID, hit, size) == XRSC_OK)
        for (uint32_t p = 0; p < T_SIZE * T_SIZE; p++)
            if (hit[4 * p] != 0xFFFFFFFFu) {
                sum += p % T_SIZE;
                n++;
            }
    free(hit);
    return n ? sum / n : -1.0;
}

/** XRSC_BOUNCES_NONE ends every path at its first hit: no shadow and no bounce rays, so a
 *  frame traces exactly one camera ray per sample, on both methods that take the option. A
 *  sentinel passed through unmapped would instead mean "unlimited" to the shader. */
static void count_rays(const char *path, xrsc_method method, uint32_t bounces, uint64_t *out)
{
    *out = 0;
    xrsc_scene *scene = NULL;
    xrsc_diag diag;
    if (xrsc_scene_load(g_ctx, path, NULL, &scene, &diag) != XRSC_OK) {
        CHECK(false);
        return;
    }
    xrsc_renderer_options ro = {.method = method, .width = T_SIZE, .height = T_SIZE};
    ro.spp.samples_per_pixel = 1;
    ro.spp.max_bounces = bounces;
    ro.samplecache.max_bounces = bounces;
    xrsc_renderer *rend = NULL;
    if (xrsc_renderer_create(g_ctx, scene, &ro, &rend, &diag) == XRSC_OK) {
        xrsc_frame frame;
        default_frame(scene, &frame);
        CHECK_EQ_INT(xrsc_renderer_render(rend, &frame), XRSC_OK);
        *out = xrsc_renderer_rays_last_frame(rend);
    } else {
        CHECK(false);
    }
    xrsc_renderer_destroy(&rend);
    xrsc_scene_destroy(&scene);
}

static void test_no_bounces(void)
{
    const char *path = t_source_path("scenes/cornell.gltf");
    uint64_t none = 0, one = 0;
    count_rays(path, XRSC_METHOD_SPP, XRSC_BOUNCES_NONE, &none);
    count_rays(path, XRSC_METHOD_SPP, 1, &one);
    CHECK_EQ_INT(none, 2ull * T_SIZE * T_SIZE);
    CHECK_MSG(one > none, "1 bounce traces %llu rays, none %llu", (unsigned long long)one,
              (unsigned long long)none);
}

static void test_animation_moves_tlas(void)
{
    const char *path = write_moving_triangle();
    CHECK(path != NULL);
    if (!path)
        return;
    xrsc_scene *scene = NULL;
    xrsc_diag diag;
    char buf[1024];
    xrsc_result r = xrsc_scene_load(g_ctx, path, NULL, &scene, &diag);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&diag, buf, sizeof(buf)));
    if (!scene)
        return;
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    CHECK_NEAR(info.animation_duration_s, 1.0, 1e-6);
    xrsc_renderer *rend = NULL;
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = T_SIZE, .height = T_SIZE};
    CHECK_EQ_INT(xrsc_renderer_create(g_ctx, scene, &ro, &rend, NULL), XRSC_OK);
    if (rend) {
        xrsc_frame f = {0};
        for (int e = 0; e < 2; e++) {
            f.views[e].pose = xrsc_pose_identity();
            f.views[e].fov = (XrFovf){-0.6f, 0.6f, 0.6f, -0.6f};
        }
        /* x = -1, 0, +1 at 3 m with tan(0.6) = 0.684: centroid at 32 +- 32 / (3 * 0.684). */
        static const int64_t times_ns[3] = {0, 500000000, 999000000};
        double cx[3];
        for (int k = 0; k < 3; k++) {
            f.display_time_ns = times_ns[k];
            f.frame_index = (uint32_t)k;
            CHECK_EQ_INT(xrsc_renderer_render(rend, &f), XRSC_OK);
            cx[k] = hit_centroid_x(rend);
            /* The instance update is pass "tlas" of the frame (xrsc.h), then "trace". */
            xrsc_pass_timing tm[XRSC_MAX_PASSES];
            uint32_t n = xrsc_renderer_timings(rend, tm, XRSC_MAX_PASSES);
            CHECK(n == 2 && !strcmp(tm[0].name, "tlas") && !strcmp(tm[1].name, "trace"));
            CHECK(n == 2 && tm[0].gpu_ms >= 0.0 && tm[1].gpu_ms > 0.0);
            printf("frame %d: tlas %.4f ms, trace %.3f ms\n", k, n ? tm[0].gpu_ms : 0.0,
                   n >= 2 ? tm[1].gpu_ms : 0.0);
        }
        /* The same time again: no update, the same image. */
        CHECK_EQ_INT(xrsc_renderer_render(rend, &f), XRSC_OK);
        CHECK_NEAR(hit_centroid_x(rend), cx[2], 1e-9);
        printf("moving triangle: hit centroid x %.2f, %.2f, %.2f px\n", cx[0], cx[1], cx[2]);
        double px_per_m = T_SIZE / (2.0 * 3.0 * tan(0.6));
        CHECK_NEAR(cx[0], T_SIZE / 2.0 - px_per_m, 1.5);
        CHECK_NEAR(cx[1], T_SIZE / 2.0, 1.5);
        CHECK_NEAR(cx[2], T_SIZE / 2.0 + 0.999 * px_per_m, 1.5);
    }
    xrsc_renderer_destroy(&rend);
    xrsc_scene_destroy(&scene);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    printf("device: %s (cpu %d)\n", xrsc_context_device_name(g_ctx), xrsc_context_is_cpu(g_ctx));
    RUN(test_method_names);
    RUN(test_device_selection);
    RUN(test_bad_scene_path);
    RUN(test_shared_cornell);
    RUN(test_shared_glass);
    RUN(test_bundled_scenes);
    RUN(test_animation_moves_tlas);
    RUN(test_no_bounces);
    t_context_close(&g_ctx);
    return t_finish();
}
