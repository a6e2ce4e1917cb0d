// SPDX-License-Identifier: MIT
/**
 * @file test_samplecache_moving.c
 * @brief The sample cache's moving-sample rule (xrsc_samplecache_options.moving, issue 19,
 *        case `moving`; XS_SC_MOVING_ALPHA_MIN), under the validation layer.
 *
 * test_turning_cone: scenes/moving.gltf (a 12-sided cone turning 90 degrees a second about
 * its axis, lit by a sun), the environment set to black and max_bounces 1 (the sun's light
 * sample at the first hit; the bounce ray finds black), so a sample's shading has no noise:
 * the sun's cosine on its face and its shadow ray. A still view narrowed onto the cone
 * (2 x T_SIZE^2), T_FRAMES frames of 90 Hz display time (one degree a frame). The last frame
 * of `samplecache` (no blend, no TAA) is compared with `spp` (T_REF_SPP jittered samples per
 * pixel) of the same display time on the cone's inner pixels (the cone's hit id on the whole
 * 3 x 3 neighbourhood, from `primary`): with the rule their relMSE must be below T_MAX_RELMSE
 * and the mean ratio within T_MAX_BIAS of 1; without it (the default) the relMSE must be
 * above T_MAX_RELMSE, so the scene does tell the two apart (without the rule a sample keeps
 * the plain mean of every pose since it was made).
 *
 * test_still_scene_unchanged: the rule is in force only on instances that turn: on the glossy
 * scene (nothing animated) and on disocclusion.gltf (a box that slides without turning) the
 * default with the rule renders the same bytes as without it, every frame (stop 20's version
 * changed the round robin of every pixel and broke the glossy case on an NVIDIA GPU;
 * bench/results/issue19-moving2/README.md).
 */
#include "t_context.h"
#include "t_render.h"
#include "test_samplecache_util.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 32u
#define T_FRAMES 24u
#define T_REF_SPP 16u
#define T_HALF_FOV 0.3f     /* rad: the cone fills the view */
#define T_STEP_NS 11111111u /* 90 Hz */
#define T_MIN_PIXELS 100u   /* inner cone pixels, both eyes */
#define T_MAX_RELMSE 0.025
#define T_MAX_BIAS 0.1
#define T_STILL_SIZE 24u
#define T_STILL_FRAMES 6u

static xrsc_context *g_ctx;

/** The scene's viewpoint, both eyes' frusta narrowed onto the cone. */
static xrsc_frame cone_view(const xrsc_scene *scene)
{
    xrsc_frame f = tsc_viewpoint_frame(scene);
    for (int e = 0; e < 2; e++) {
        f.views[e].fov.angleLeft = f.views[e].fov.angleDown = -T_HALF_FOV;
        f.views[e].fov.angleRight = f.views[e].fov.angleUp = T_HALF_FOV;
    }
    return f;
}

/** Reads output `what` of both eyes after rendering T_FRAMES frames of f with ro. */
static bool render_last(xrsc_scene *scene, xrsc_renderer_options ro, const xrsc_frame *f,
                        xrsc_output what, void *out, size_t eye_bytes)
{
    xrsc_renderer *r = NULL;
    xrsc_diag d = {0};
    ro.width = ro.height = T_SIZE;
    xrsc_result res = xrsc_renderer_create(g_ctx, scene, &ro, &r, &d);
    CHECK_MSG(res == XRSC_OK, "renderer: %s", d.message);
    if (res != XRSC_OK)
        return false;
    xrsc_frame frame = *f;
    for (uint32_t i = 0; i < T_FRAMES && res == XRSC_OK; i++) {
        frame.display_time_ns += T_STEP_NS;
        frame.frame_index = i;
        res = xrsc_renderer_render(r, &frame);
    }
    for (uint32_t e = 0; e < 2 && res == XRSC_OK; e++)
        res = xrsc_renderer_read(r, e, what, (char *)out + e * eye_bytes, eye_bytes);
    CHECK_EQ_INT(res, XRSC_OK);
    xrsc_renderer_destroy(&r);
    return res == XRSC_OK;
}

/** Whether pixel (x, y) of eye e and its 3 x 3 neighbours all show instance `cone`. */
static bool inner(const uint32_t *ids, uint32_t e, uint32_t x, uint32_t y, uint32_t cone)
{
    if (x == 0 || y == 0 || x + 1 >= T_SIZE || y + 1 >= T_SIZE)
        return false;
    for (uint32_t j = y - 1; j <= y + 1; j++)
        for (uint32_t i = x - 1; i <= x + 1; i++)
            if (ids[4 * ((e * T_SIZE + j) * T_SIZE + i)] != cone)
                return false;
    return true;
}

/** relMSE and mean ratio of sc against ref on the cone's inner pixels (out_n of them). */
static void cone_error(const uint32_t *ids, const float *sc, const float *ref, double *out_rel,
                       double *out_ratio, uint32_t *out_n)
{
    uint32_t cone = ids[4 * ((T_SIZE / 2) * T_SIZE + T_SIZE / 2)]; /* the view's centre */
    double e2 = 0.0, s_sc = 0.0, s_ref = 0.0;
    uint32_t n = 0;
    for (uint32_t e = 0; e < 2; e++)
        for (uint32_t y = 0; y < T_SIZE; y++)
            for (uint32_t x = 0; x < T_SIZE; x++) {
                if (cone == UINT32_MAX || !inner(ids, e, x, y, cone))
                    continue;
                const float *a = &sc[4 * ((e * T_SIZE + y) * T_SIZE + x)];
                const float *b = &ref[4 * ((e * T_SIZE + y) * T_SIZE + x)];
                for (int c = 0; c < 3; c++) {
                    e2 += (a[c] - b[c]) * (a[c] - b[c]) / (b[c] * b[c] + 1e-2);
                    s_sc += a[c], s_ref += b[c];
                }
                n++;
            }
    *out_rel = n ? e2 / (3.0 * n) : 0.0;
    *out_ratio = s_ref > 0.0 ? s_sc / s_ref : 0.0;
    *out_n = n;
}

static void test_turning_cone(void)
{
    xrsc_scene_options so = {.env_set = true}; /* black: the sun alone, no noise */
    xrsc_scene *scene = NULL;
    xrsc_diag d = {0};
    const char *path = t_source_path("scenes/moving.gltf");
    xrsc_result lr = xrsc_scene_load(g_ctx, path, &so, &scene, &d);
    CHECK_MSG(lr == XRSC_OK, "load %s: %s", path, d.message);
    if (lr != XRSC_OK)
        return;
    xrsc_frame f = cone_view(scene);
    size_t px = (size_t)T_SIZE * T_SIZE, eye_bytes = px * 4 * sizeof(float);
    uint32_t *ids = calloc(2 * px * 4, sizeof(uint32_t));
    float *on = calloc(2 * px * 4, sizeof(float)), *off = calloc(2 * px * 4, sizeof(float));
    float *ref = calloc(2 * px * 4, sizeof(float));
    xrsc_renderer_options po = {.method = XRSC_METHOD_PRIMARY};
    xrsc_renderer_options so_off = {.method = XRSC_METHOD_SAMPLECACHE};
    so_off.samplecache.max_bounces = 1; /* the sun's light sample; the bounce finds black */
    xrsc_renderer_options so_on = so_off;
    so_on.samplecache.moving = true;
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SPP};
    ro.spp.samples_per_pixel = T_REF_SPP;
    ro.spp.max_bounces = 1;
    bool ok = render_last(scene, po, &f, XRSC_OUTPUT_HIT_ID, ids, px * 4 * sizeof(uint32_t)) &&
              render_last(scene, so_on, &f, XRSC_OUTPUT_COLOR, on, eye_bytes) &&
              render_last(scene, so_off, &f, XRSC_OUTPUT_COLOR, off, eye_bytes) &&
              render_last(scene, ro, &f, XRSC_OUTPUT_COLOR, ref, eye_bytes);
    if (ok) {
        double rel_on, ratio_on, rel_off, ratio_off;
        uint32_t n, n_off;
        cone_error(ids, on, ref, &rel_on, &ratio_on, &n);
        cone_error(ids, off, ref, &rel_off, &ratio_off, &n_off);
        printf("  %u inner cone pixels at frame %u: with the rule relMSE %.5f (limit %.4f), "
               "mean / reference %.4f (limit 1 +- %.2f); without it relMSE %.5f, mean / "
               "reference %.4f\n",
               n, T_FRAMES, rel_on, T_MAX_RELMSE, ratio_on, T_MAX_BIAS, rel_off, ratio_off);
        CHECK(n >= T_MIN_PIXELS);
        CHECK_MSG(rel_on < T_MAX_RELMSE, "stale radiance on the moving cone: relMSE %.5f", rel_on);
        CHECK_MSG(fabs(ratio_on - 1.0) < T_MAX_BIAS, "cone mean / reference %.4f", ratio_on);
        CHECK_MSG(rel_off > T_MAX_RELMSE,
                  "without the rule relMSE %.5f: the case does not "
                  "tell the rule apart",
                  rel_off);
    }
    free(ids);
    free(on);
    free(off);
    free(ref);
    xrsc_scene_destroy(&scene);
}

/** The last frame of T_STILL_FRAMES of the default pipeline (variance-guided shading, TAA)
 *  on a still scene, with or without the rule, both eyes. */
static bool still_frames(xrsc_scene *scene, bool moving, float *out)
{
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SAMPLECACHE, .seed = 3};
    ro.samplecache.shade = XRSC_SC_SHADE_ADAPTIVE_VARIANCE;
    ro.samplecache.shade_rate = 0.4f;
    ro.samplecache.moving = moving;
    ro.taa.mode = XRSC_TAA_ON;
    ro.width = ro.height = T_STILL_SIZE;
    xrsc_renderer *r = NULL;
    xrsc_diag d = {0};
    xrsc_result res = xrsc_renderer_create(g_ctx, scene, &ro, &r, &d);
    CHECK_MSG(res == XRSC_OK, "renderer: %s", d.message);
    if (res != XRSC_OK)
        return false;
    xrsc_frame frame = tsc_viewpoint_frame(scene);
    size_t eye_floats = (size_t)T_STILL_SIZE * T_STILL_SIZE * 4;
    for (uint32_t i = 0; i < T_STILL_FRAMES && res == XRSC_OK; i++) {
        frame.display_time_ns += T_STEP_NS;
        frame.frame_index = i;
        frame.views[0].pose.position.x += 0.01f; /* a moving view: reprojection and retrace */
        frame.views[1].pose.position.x += 0.01f;
        res = xrsc_renderer_render(r, &frame);
        for (uint32_t e = 0; e < 2 && res == XRSC_OK; e++)
            res = xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, out + (i * 2 + e) * eye_floats,
                                     eye_floats * sizeof(float));
    }
    CHECK_EQ_INT(res, XRSC_OK);
    xrsc_renderer_destroy(&r);
    return res == XRSC_OK;
}

/** The default with the rule renders the same bytes as without it on scene `rel`. */
static void same_bytes(const char *rel)
{
    xrsc_scene *scene = NULL;
    xrsc_diag d = {0};
    const char *path = t_source_path(rel);
    xrsc_result lr = xrsc_scene_load(g_ctx, path, NULL, &scene, &d);
    CHECK_MSG(lr == XRSC_OK, "load %s: %s", path, d.message);
    if (lr != XRSC_OK)
        return;
    size_t n = (size_t)T_STILL_FRAMES * 2 * T_STILL_SIZE * T_STILL_SIZE * 4;
    float *a = calloc(n, sizeof(float)), *b = calloc(n, sizeof(float));
    if (still_frames(scene, false, a) && still_frames(scene, true, b)) {
        size_t differ = 0;
        for (size_t i = 0; i < n; i++)
            differ += memcmp(&a[i], &b[i], sizeof(float)) != 0;
        printf("  %s, %u frames: %zu of %zu values differ with the rule on\n", rel, T_STILL_FRAMES,
               differ, n);
        CHECK_EQ_INT((int)differ, 0);
    }
    free(a);
    free(b);
    xrsc_scene_destroy(&scene);
}

/* Nothing animated (glossy), and a box that only slides (disocclusion: its faces keep their
 * angle to the sun, sc_instance_turned): the rule is not in force. */
static void test_still_scene_unchanged(void)
{
    same_bytes("scenes/glossy.gltf");
    same_bytes("scenes/disocclusion.gltf");
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_turning_cone);
    RUN(test_still_scene_unchanged);
    t_context_close(&g_ctx); /* the validation layer reported no error */
    return t_finish();
}
