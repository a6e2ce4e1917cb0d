// SPDX-License-Identifier: MIT
/**
 * @file test_samplecache_strata.c
 * @brief The sample cache's stratified new samples (issue 19, xrsc_samplecache_options
 *        .stratify), under the validation layer (zero errors asserted).
 *
 * scenes/edges.gltf (thin black bars and cubes on a white wall, sun light) from its viewpoint,
 * 2 x T_W x T_H, a still view, 1 bounce, uniform shading, no TAA and no blend, so the error
 * left after T_FRAMES frames is mostly where in its pixel each of the ~4 samples lies: on a
 * pixel cut by an edge their mean is a coverage estimate that never averages out while the
 * view is still. Against the box-filtered reference (`spp`, jittered, accumulated):
 * - stratify on: the pixel's new samples go through distinct strata of a 2 x 2 grid (the
 *   emptiest first), and the relMSE falls below T_RATIO times the one of uniform random points
 *   (lavapipe: 0.2285 -> 0.1565; without the strata the ratio is 1);
 * - stratify off renders exactly what the options without the field render (the field's zero
 *   is the former behaviour).
 */
#include "t_context.h"
#include "t_render.h"
#include "test_samplecache_util.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_metrics.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_W 32u
#define T_H 32u
#define T_FRAMES 8u
#define T_REF_SPP 16u
#define T_REF_FRAMES 16u
#define T_RATIO 0.8

static xrsc_context *g_ctx;

/** Mean relMSE of both eyes of img against ref. */
static double rel_mse(const float *img, const float *ref)
{
    size_t layer = (size_t)T_W * T_H * 4;
    double sum = 0.0;
    for (uint32_t e = 0; e < 2; e++) {
        xrsc_error_metrics em;
        CHECK_EQ_INT(xrsc_metrics_error(img + e * layer, ref + e * layer, T_W, T_H, NULL, &em),
                     XRSC_OK);
        sum += em.relmse;
    }
    return sum / 2.0;
}

static bool render_cache(xrsc_scene *scene, const xrsc_frame *f, int stratify, float *out)
{
    xrsc_renderer_options ro = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SAMPLECACHE};
    ro.samplecache.max_bounces = 1;
    if (stratify >= 0) /* < 0: the field left at its zero */
        ro.samplecache.stratify = stratify != 0;
    return t_render(g_ctx, scene, &ro, f, &(t_render_job){.frames = T_FRAMES}, out);
}

static void test_strata_edges(void)
{
    xrsc_scene *scene = t_scene_load(g_ctx, t_source_path("scenes/edges.gltf"));
    if (!scene)
        return;
    xrsc_frame f = tsc_viewpoint_frame(scene);
    size_t floats = 2u * T_W * T_H * 4;
    float *ref = calloc(floats, sizeof(float)), *off = calloc(floats, sizeof(float)),
          *on = calloc(floats, sizeof(float)), *zero = calloc(floats, sizeof(float));
    xrsc_renderer_options rr = {
        .width = T_W,
        .height = T_H,
        .method = XRSC_METHOD_SPP,
        .seed = 1234,
        .spp = {.samples_per_pixel = T_REF_SPP, .max_bounces = 1, .accumulate = true}};
    bool ok = ref && off && on && zero &&
              t_render(g_ctx, scene, &rr, &f, &(t_render_job){.frames = T_REF_FRAMES}, ref) &&
              render_cache(scene, &f, 0, off) && render_cache(scene, &f, 1, on) &&
              render_cache(scene, &f, -1, zero);
    if (ok) {
        double e_off = rel_mse(off, ref), e_on = rel_mse(on, ref);
        printf("  relMSE vs %u spp after %u frames: uniform points %.5f, strata %.5f\n",
               T_REF_SPP * T_REF_FRAMES, T_FRAMES, e_off, e_on);
        CHECK(e_on < T_RATIO * e_off);
        CHECK(memcmp(off, zero, floats * sizeof(float)) == 0);
    }
    free(ref);
    free(off);
    free(on);
    free(zero);
    xrsc_scene_destroy(&scene);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_strata_edges);
    t_context_close(&g_ctx); /* the validation layer reported no error */
    return t_finish();
}
