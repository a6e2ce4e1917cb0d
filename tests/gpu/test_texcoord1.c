// SPDX-License-Identifier: MIT
/**
 * @file test_texcoord1.c
 * @brief Issue 18: a texture whose texCoord is 1 reads TEXCOORD_1 (xs_vertex.uv1 through
 *        xs_material.uv1_mask), on the path tracer and on the sample cache's passes.
 *
 * Scene: two 20 m squares at z = -1 facing +Z, side by side (x < 0 and x > 0), seen from the
 * origin looking down -Z; no light, environment 0. Their TEXCOORD_0 is (0.25, 0.5) at every
 * vertex (the left texel of a 2 x 1 texture, red, NEAREST), their TEXCOORD_1 (0.75, 0.5) (the
 * right texel, green). The left square's material reads the texture with texCoord 0, the
 * right one's with texCoord 1. An unlit material shows its base colour texture exactly; an
 * emissive texture over a black base shows exactly the emission. So the left half must be red
 * and the right half green; set 0 for both (the bug: or the texture left out, white) fails.
 * Runs under the validation layer.
 */
#include "hs_image.h"
#include "t_context.h"
#include "testing.h"
#include "t_frames.h"
#include "t_gltf.h"
#include "t_render.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 32u
#define T_FRAMES 2u
#define T_FRAME_NS 11111111u /* display time between frames (90 Hz) */
/* The 2 x 1 texture: left texel red (TEXCOORD_0), right texel green (TEXCOORD_1). */
static const uint8_t k_texels[6] = {255, 0, 0, 0, 255, 0};

static xrsc_context *g_ctx;

/** Writes the scene with the given two materials' JSON (left square, right square) and image
 *  file name; returns its path. The buffer: 4 positions, 4 uv0, 4 uv1, 6 u16 indices (+ 4
 *  bytes padding). */
static const char *write_scene(const char *name, const char *material, const char *image)
{
    uint8_t b[128];
    const float pos[12] = {-10, -10, -1, 10, -10, -1, 10, 10, -1, -10, 10, -1};
    const float uv0[8] = {0.25f, 0.5f, 0.25f, 0.5f, 0.25f, 0.5f, 0.25f, 0.5f};
    const float uv1[8] = {0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f};
    const uint16_t idx[8] = {0, 1, 2, 0, 2, 3, 0, 0};
    memcpy(b, pos, 48);
    memcpy(b + 48, uv0, 32);
    memcpy(b + 80, uv1, 32);
    memcpy(b + 112, idx, 16);
    return t_gltf_write(
        name, b, sizeof b,
        "{\"asset\": {\"version\": \"2.0\"},"
        " \"extensionsUsed\": [\"KHR_materials_unlit\"],"
        " \"scenes\": [{\"nodes\": [0], \"extras\": {\"xrsc_environment\": [0, 0, 0]}}],"
        " \"nodes\": [{\"children\": [1, 2]}, {\"mesh\": 0, \"translation\": [-10, 0, 0]},"
        " {\"mesh\": 1, \"translation\": [10, 0, 0]}],"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0,"
        " \"TEXCOORD_0\": 1, \"TEXCOORD_1\": 2}, \"indices\": 3, \"material\": 0}]},"
        " {\"primitives\": [{\"attributes\": {\"POSITION\": 0,"
        " \"TEXCOORD_0\": 1, \"TEXCOORD_1\": 2}, \"indices\": 3, \"material\": 1}]}],"
        " \"materials\": [%s],"
        " \"images\": [{\"uri\": \"%s\"}], \"textures\": [{\"source\": 0, \"sampler\": 0}],"
        " \"samplers\": [{\"magFilter\": 9728, \"minFilter\": 9728}],"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, "
        "\"type\": \"VEC3\","
        " \"min\": [-10, -10, -1], \"max\": [10, 10, -1]},"
        " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
        " {\"bufferView\": 2, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
        " {\"bufferView\": 3, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}],"
        " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48},"
        " {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 32},"
        " {\"buffer\": 0, \"byteOffset\": 80, \"byteLength\": 32},"
        " {\"buffer\": 0, \"byteOffset\": 112, \"byteLength\": 12}]",
        material, image);
}

/** The left eye's column where x = 0 (between the squares) projects, from its FOV. */
static double seam_column(void)
{
    xrsc_frame frame;
    t_frame_identity(&frame);
    double tl = tan(-frame.views[0].fov.angleLeft), tr = tan(frame.views[0].fov.angleRight);
    return T_SIZE * tl / (tl + tr);
}

/** Renders T_FRAMES frames with `method` (1 spp, no jitter) and returns the largest
 *  difference of the last one's left-eye pixels from red (left of the seam) and green (right
 *  of it), T_SEAM_PX either side of the seam left out. */
#define T_SEAM_PX 2.0
static bool render(const char *path, xrsc_method method, double *max_dev)
{
    xrsc_renderer_options ro = {.method = method, .width = T_SIZE, .height = T_SIZE};
    ro.spp.samples_per_pixel = 1;
    ro.spp.no_jitter = true;
    t_render_job job = {.frames = T_FRAMES, .time_step_ns = T_FRAME_NS, .eyes = 1};
    float *c = t_render_file(g_ctx, path, &ro, NULL, &job);
    bool ok = c != NULL;
    static const double red[3] = {1, 0, 0}, green[3] = {0, 1, 0};
    double seam = seam_column();
    uint32_t n = 0;
    *max_dev = 0.0;
    for (uint32_t y = 0; ok && y < T_SIZE; y++)
        for (uint32_t x = 0; x < T_SIZE; x++) {
            double cx = x + 0.5;
            if (fabs(cx - seam) < T_SEAM_PX)
                continue;
            const double *want = cx < seam ? red : green;
            for (int k = 0; k < 3; k++)
                *max_dev = fmax(*max_dev, fabs(c[4 * (y * T_SIZE + x) + k] - want[k]));
            n++;
        }
    CHECK(n > T_SIZE * T_SIZE / 2);
    free(c);
    return ok;
}

/** The 2 x 1 texture's file name (beside the scenes t_temp_file writes). */
static const char *texture_name(void)
{
    const char *png = t_temp_file("uvsets.png", "");
    xrsc_diag d;
    CHECK_EQ_INT(hs_write_png(png, k_texels, 2, 1, &d), XRSC_OK);
    const char *base = strrchr(png, '/');
    return base ? base + 1 : png;
}

static void test_base_color_set1(void)
{
    const char *path = write_scene(
        "unlit_sets.gltf",
        "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}},"
        " \"extensions\": {\"KHR_materials_unlit\": {}}},"
        " {\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0, \"texCoord\": 1}},"
        " \"extensions\": {\"KHR_materials_unlit\": {}}}",
        texture_name());
    const xrsc_method methods[2] = {XRSC_METHOD_SPP, XRSC_METHOD_SAMPLECACHE};
    for (int m = 0; m < 2; m++) {
        double dev = 1.0;
        CHECK(render(path, methods[m], &dev));
        printf("base colour, method %d: max |c - (red | green)| %.3g\n", (int)methods[m], dev);
        CHECK(dev <= 1e-5);
    }
}

static void test_emissive_set1(void)
{
    const char *path = write_scene(
        "emissive_sets.gltf",
        "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0, 0, 0, 1], \"metallicFactor\": 0},"
        " \"emissiveFactor\": [1, 1, 1], \"emissiveTexture\": {\"index\": 0}},"
        " {\"pbrMetallicRoughness\": {\"baseColorFactor\": [0, 0, 0, 1], \"metallicFactor\": 0},"
        " \"emissiveFactor\": [1, 1, 1], \"emissiveTexture\": {\"index\": 0, \"texCoord\": 1}}",
        texture_name());
    double dev = 1.0;
    CHECK(render(path, XRSC_METHOD_SPP, &dev));
    printf("emissive: max |c - (red | green)| %.3g\n", dev);
    CHECK(dev <= 1e-5);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_base_color_set1);
    RUN(test_emissive_set1);
    t_context_close(&g_ctx);
    return t_finish();
}
