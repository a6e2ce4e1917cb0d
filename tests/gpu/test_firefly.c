// SPDX-License-Identifier: MIT
/**
 * @file test_firefly.c
 * @brief The sample cache's firefly rule (issue 19 item 3, xrsc_samplecache_options
 *        .firefly_clamp), under the validation layer (zero errors asserted).
 *
 * scenes/cornell.gltf, 2 x T_W x T_H, T_FRAMES frames of a still view, `samplecache` without
 * a blend:
 * - k = 1 (every observation above its sample's mean is cut to it): the image changes and
 *   its mean luminance drops (clamping only removes energy);
 * - k in (0, 1): XRSC_ERROR_INVALID_ARGUMENT.
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

#define T_W 32u
#define T_H 32u
#define T_FRAMES 8u

static xrsc_context *g_ctx;

/** T_FRAMES frames of the still view f with firefly_clamp k, both eyes' colour into out. */
static bool render(xrsc_scene *scene, const xrsc_frame *f, float k, float *out)
{
    xrsc_renderer_options ro = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SAMPLECACHE};
    ro.samplecache.firefly_clamp = k;
    return t_render(g_ctx, scene, &ro, f, &(t_render_job){.frames = T_FRAMES}, out);
}

static double mean_luminance(const float *img, size_t pixels)
{
    double s = 0.0;
    for (size_t p = 0; p < pixels; p++)
        s += 0.2126 * img[4 * p] + 0.7152 * img[4 * p + 1] + 0.0722 * img[4 * p + 2];
    return s / (double)pixels;
}

static void test_firefly_rule(void)
{
    xrsc_scene *scene = t_scene_load(g_ctx, t_source_path("scenes/cornell.gltf"));
    if (!scene)
        return;
    xrsc_frame f = tsc_viewpoint_frame(scene);
    size_t pixels = 2u * T_W * T_H;
    float *off = calloc(pixels * 4, sizeof(float)), *k1 = calloc(pixels * 4, sizeof(float));
    bool ok = render(scene, &f, 0.0f, off) && render(scene, &f, 1.0f, k1);
    if (ok) {
        double l_off = mean_luminance(off, pixels), l_k1 = mean_luminance(k1, pixels);
        printf("  mean luminance: off %.5f, k = 1 %.5f\n", l_off, l_k1);
        CHECK(memcmp(off, k1, pixels * 4 * sizeof(float)) != 0);
        CHECK(l_k1 < l_off);
    }
    xrsc_renderer_options bad = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SAMPLECACHE};
    bad.samplecache.firefly_clamp = 0.5f;
    xrsc_renderer *r = NULL;
    xrsc_diag diag = {0};
    CHECK_EQ_INT(xrsc_renderer_create(g_ctx, scene, &bad, &r, &diag), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(r == NULL);
    free(off);
    free(k1);
    xrsc_scene_destroy(&scene);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_firefly_rule);
    t_context_close(&g_ctx); /* the validation layer reported no error */
    return t_finish();
}
