// SPDX-License-Identifier: MIT
/**
 * @file test_pipeline_share.c
 * @brief One ray-tracing pipeline per raygen and specialization in a context (issue 22): a
 *        second renderer of the same method reuses the first one's pipelines.
 *
 * lavapipe numbers each new pipeline's shader groups from a device-wide counter and compiles
 * the numbers into the pipeline's code, so each new pipeline of the same shaders was another
 * LLVM compile that no shader cache serves (20-30 s of CPU for `spp` on a cold cache; four
 * `spp` renderers in one context were four compiles). Must hold: renderers of a method already
 * made add no pipeline to the context, another method adds its own; a renderer's images are
 * unchanged, bit for bit, after the renderer that made the shared pipeline is destroyed (the
 * pipeline lives on with the context); zero validation errors.
 */
#include "gpu_context.h"
#include "t_context.h"
#include "t_frames.h"
#include "t_render.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xrsc_core_internal.h"

#include <stdlib.h>
#include <string.h>

#define T_W 32u
#define T_H 32u

/** Renders f with r and reads both eyes' colour into out (2 x T_W x T_H RGBA floats). */
static void render_read(xrsc_renderer *r, const xrsc_frame *f, float *out)
{
    size_t layer = (size_t)T_W * T_H * 4;
    CHECK_EQ_INT(xrsc_renderer_render(r, f), XRSC_OK);
    for (uint32_t e = 0; e < 2; e++)
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, out + e * layer,
                                        layer * sizeof(float)),
                     XRSC_OK);
}

static void test_renderers_share_pipelines(void)
{
    xrsc_context *ctx = t_context_open();
    CHECK(ctx != NULL);
    xrsc_scene *scene = ctx ? t_scene_load(ctx, t_source_path("scenes/triangles.gltf")) : NULL;
    if (!scene) {
        xrsc_context_destroy(&ctx);
        return;
    }
    gpu_context *gpu = xrsc_context_gpu(ctx);
    xrsc_frame f;
    t_frame_identity(&f);
    f.frame_index = 3;
    size_t floats = 2u * T_W * T_H * 4;
    float *a = calloc(floats, sizeof(float)), *b = calloc(floats, sizeof(float));
    float *b2 = calloc(floats, sizeof(float));
    uint32_t before = gpu->rt_pipeline_count;

    xrsc_renderer_options ro = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SPP, .seed = 5};
    ro.spp.samples_per_pixel = 2;
    xrsc_renderer *ra = NULL, *rb = NULL, *rp = NULL;
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &ro, &ra, NULL), XRSC_OK);
    uint32_t after_first = gpu->rt_pipeline_count;
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &ro, &rb, NULL), XRSC_OK);
    printf("  rt pipelines: %u before, %u after one `spp` renderer, %u after two\n", before,
           after_first, gpu->rt_pipeline_count);
    CHECK(after_first > before);
    CHECK_EQ_INT(gpu->rt_pipeline_count, after_first);
    if (ra && rb) {
        render_read(ra, &f, a);
        render_read(rb, &f, b);
        CHECK(memcmp(a, b, floats * sizeof(float)) == 0); /* same seed, same frame */
        xrsc_renderer_destroy(&ra); /* made the pipeline: rb's goes on working */
        render_read(rb, &f, b2);
        CHECK(memcmp(b, b2, floats * sizeof(float)) == 0);
    }
    xrsc_renderer_options po = {.width = T_W, .height = T_H, .method = XRSC_METHOD_PRIMARY};
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &po, &rp, NULL), XRSC_OK);
    printf("  after a `primary` renderer: %u\n", gpu->rt_pipeline_count);
    CHECK_EQ_INT(gpu->rt_pipeline_count, after_first + 1);
    xrsc_renderer_destroy(&rp);
    xrsc_renderer_destroy(&rb);
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &ro, &ra, NULL), XRSC_OK);
    CHECK_EQ_INT(gpu->rt_pipeline_count, after_first + 1); /* kept after its users went */
    xrsc_renderer_destroy(&ra);
    free(a), free(b), free(b2);
    xrsc_scene_destroy(&scene);
    t_context_close(&ctx);
}

int main(void)
{
    RUN(test_renderers_share_pipelines);
    return t_finish();
}
