// SPDX-License-Identifier: MIT
/**
 * @file test_gltf_fallbacks.c
 * @brief Issue 18 (loader) on the GPU: a material whose texture file is missing renders with
 *        the warning's ID and its factor alone (white stand-in); EXT_mesh_gpu_instancing draws
 *        N instances; sampler wrap modes reach the GPU (CLAMP_TO_EDGE, REPEAT and
 *        MIRRORED_REPEAT give 2, 4 and 3 colour runs across a quad whose u runs 0..2 over a
 *        red|green texture, NEAREST magnification).
 *
 * Scenes: unlit quads (KHR_materials_unlit: the pixel is base colour x texture, exactly) in
 * z = -1 facing the eye at the origin, environment 0 (background black); 1 spp, no jitter.
 * Runs under the validation layer.
 */
#include "hs_image.h"
#include "t_context.h"
#include "testing.h"
#include "t_frames.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 48u

static xrsc_context *g_ctx;

/** A quad [-h, h]^2 at z = -1 with u running 0..u_max left to right: 4 positions, 4 uvs,
 *  6 u16 indices + padding (92 bytes) as a data uri. */
static char *quad_uri(float h, float u_max)
{
    uint8_t b[92];
    const float pos[12] = {-h, -h, -1, h, -h, -1, h, h, -1, -h, h, -1};
    const float uv[8] = {0, 1, u_max, 1, u_max, 0, 0, 0};
    const uint16_t idx[8] = {0, 1, 2, 0, 2, 3, 0, 0};
    memcpy(b, pos, 48);
    memcpy(b + 48, uv, 32);
    memcpy(b + 80, idx, 12);
    return t_data_uri(b, sizeof b);
}

/** Writes the scene (node_ext on the quad's node, extra at the top level, extra accessors and
 *  views appended, a second buffer when uri1) and returns its path. */
static const char *write_scene(const char *name, float h, float u_max, const char *material,
                               const char *extra, const char *node_ext, const char *accessors,
                               const char *views, const char *buffer1)
{
    char *uri = quad_uri(h, u_max);
    size_t cap = 16384 + strlen(material) + strlen(extra) + strlen(buffer1);
    char *json = malloc(cap);
    snprintf(json, cap,
             "{\"asset\": {\"version\": \"2.0\"}, %s"
             " \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0 %s}],"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1},"
             " \"indices\": 2, \"material\": 0}]}],"
             " \"materials\": [%s],"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},"
             " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
             " {\"bufferView\": 2, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"} %s],"
             " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": 48,"
             " \"byteLength\": 32}, {\"buffer\": 0, \"byteOffset\": 80, \"byteLength\": 12} %s],"
             " \"buffers\": [{\"byteLength\": 92, \"uri\": \"%s\"} %s]}",
             extra, node_ext, material, accessors, views, uri, buffer1);
    free(uri);
    const char *path = t_temp_file(name, json);
    free(json);
    return path;
}

/** Loads path (environment 0), checks the warning ID `warn` (0: none expected), renders
 *  1 spp and copies the left eye's colour (RGBA float) into img. */
static bool render(const char *path, xrsc_result warn, float *img)
{
    char buf[1024];
    xrsc_diag d;
    xrsc_scene *scene = NULL;
    xrsc_scene_options so = {.env_set = true};
    xrsc_result r = xrsc_scene_load(g_ctx, path, &so, &scene, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    if (r != XRSC_OK) return false;
    if (warn) CHECK(xrsc_scene_warned(scene, warn));
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SPP, .width = T_SIZE, .height = T_SIZE};
    ro.spp.samples_per_pixel = 1;
    ro.spp.no_jitter = true;
    xrsc_renderer *rend = NULL;
    r = xrsc_renderer_create(g_ctx, scene, &ro, &rend, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    bool ok = r == XRSC_OK;
    xrsc_frame frame;
    t_frame_identity(&frame);
    ok = ok && xrsc_renderer_render(rend, &frame) == XRSC_OK &&
         xrsc_renderer_read(rend, 0, XRSC_OUTPUT_COLOR, img, T_SIZE * T_SIZE * 16) == XRSC_OK;
    xrsc_renderer_destroy(&rend);
    xrsc_scene_destroy(&scene);
    return ok;
}

/** Classifies the pixels of row y: '.' black, 'R' red-dominated, 'G' green-dominated, 'W'
 *  other lit; returns the number of runs of lit classes (a change of class starts a run). */
static int runs_on_row(const float *img, uint32_t y, char *out_row)
{
    int runs = 0;
    char prev = '.';
    for (uint32_t x = 0; x < T_SIZE; x++) {
        const float *p = img + 4 * (y * T_SIZE + x);
        char c = p[0] + p[1] + p[2] < 1e-3f ? '.'
                 : p[0] > 2.0f * p[1]       ? 'R'
                 : p[1] > 2.0f * p[0]       ? 'G'
                                            : 'W';
        if (c != '.' && c != prev) runs++;
        prev = c;
        out_row[x] = c;
    }
    out_row[T_SIZE] = '\0';
    return runs;
}

/** The row with the most lit pixels (the quads' centre, whatever the FOV's asymmetry). */
static uint32_t best_row(const float *img)
{
    uint32_t best = 0, best_n = 0;
    for (uint32_t y = 0; y < T_SIZE; y++) {
        uint32_t n = 0;
        for (uint32_t x = 0; x < T_SIZE; x++) {
            const float *p = img + 4 * (y * T_SIZE + x);
            n += p[0] + p[1] + p[2] >= 1e-3f;
        }
        if (n > best_n) best = y, best_n = n;
    }
    return best;
}

static void test_missing_texture_renders(void)
{
    const char *path = write_scene(
        "missing-tex.gltf", 10.0f, 1.0f,
        "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.2, 0.4, 0.6, 1],"
        " \"baseColorTexture\": {\"index\": 0}}, \"extensions\": {\"KHR_materials_unlit\": {}}}",
        "\"extensionsUsed\": [\"KHR_materials_unlit\"],"
        " \"images\": [{\"uri\": \"no-such-texture.png\"}], \"textures\": [{\"source\": 0}],",
        "", "", "", "");
    float *img = calloc(T_SIZE * T_SIZE, 16);
    if (render(path, XRSC_WARN_GLTF_IMAGE_MISSING, img)) {
        const float *c = img + 4 * ((T_SIZE / 2) * T_SIZE + T_SIZE / 2);
        printf("missing texture: centre %.7g %.7g %.7g (the factor 0.2 0.4 0.6)\n", c[0], c[1],
               c[2]);
        double dev = 0.0;
        for (uint32_t i = 0; i < T_SIZE * T_SIZE; i++)
            for (int k = 0; k < 3; k++)
                dev = fmax(dev, fabs(img[4 * i + k] - (k == 0 ? 0.2 : k == 1 ? 0.4 : 0.6)));
        CHECK(dev <= 1e-6); /* every pixel: the factor x the white stand-in */
    } else {
        CHECK(false);
    }
    free(img);
}

static void test_instancing_draws_n(void)
{
    /* A 0.1 m quad instanced at x = -0.5, 0, 0.5 (and the third one scaled 2x): three separate
     * lit runs on the centre row, nothing drawn at the node's own place apart from instance 2. */
    const float inst[3 * 3 + 3 * 3] = {-0.5f, 0, 0, 0, 0, 0, 0.5f, 0, 0, 1, 1, 1, 1, 1, 1, 2, 2, 2};
    char *uri = t_data_uri(inst, sizeof inst);
    char buffer1[1024];
    snprintf(buffer1, sizeof buffer1, ", {\"byteLength\": %zu, \"uri\": \"%s\"}", sizeof inst,
             uri);
    free(uri);
    const char *path = write_scene(
        "instanced.gltf", 0.05f, 1.0f,
        "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [1, 1, 1, 1]},"
        " \"extensions\": {\"KHR_materials_unlit\": {}}}",
        "\"extensionsUsed\": [\"KHR_materials_unlit\", \"EXT_mesh_gpu_instancing\"],",
        ", \"extensions\": {\"EXT_mesh_gpu_instancing\": {\"attributes\": {\"TRANSLATION\": 3,"
        " \"SCALE\": 4}}}",
        ", {\"bufferView\": 3, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"},"
        " {\"bufferView\": 4, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"}",
        ", {\"buffer\": 1, \"byteLength\": 36}, {\"buffer\": 1, \"byteOffset\": 36,"
        " \"byteLength\": 36}",
        buffer1);
    float *img = calloc(T_SIZE * T_SIZE, 16);
    char row[T_SIZE + 1];
    if (render(path, 0, img)) {
        int runs = runs_on_row(img, best_row(img), row);
        printf("instancing: centre row %s: %d instances seen\n", row, runs);
        CHECK_EQ_INT(runs, 3);
    } else {
        CHECK(false);
    }
    free(img);
}

static void test_wrap_modes(void)
{
    /* 2x1 texture: red | green (sRGB 255 -> linear 1). u runs 0..2 across the quad. */
    const char *png = t_temp_file("red-green.png", "");
    static const uint8_t texels[6] = {255, 0, 0, 0, 255, 0}; /* RGB */
    xrsc_diag d;
    CHECK_EQ_INT(hs_write_png(png, texels, 2, 1, &d), XRSC_OK);
    const char *slash = strrchr(png, '/');
    char png_name[256];
    snprintf(png_name, sizeof png_name, "%s", slash ? slash + 1 : png);
    const struct {
        int wrap;
        const char *name;
        int runs; /* colour runs across u in [0, 2] */
    } cases[3] = {{33071, "CLAMP_TO_EDGE", 2}, {10497, "REPEAT", 4}, {33648, "MIRRORED_REPEAT", 3}};
    for (int k = 0; k < 3; k++) {
        char extra[1024];
        snprintf(extra, sizeof extra,
                 "\"extensionsUsed\": [\"KHR_materials_unlit\"],"
                 " \"images\": [{\"uri\": \"%s\"}],"
                 " \"samplers\": [{\"wrapS\": %d, \"wrapT\": 33071, \"magFilter\": 9728,"
                 " \"minFilter\": 9728}], \"textures\": [{\"source\": 0, \"sampler\": 0}],",
                 png_name, cases[k].wrap);
        const char *path = write_scene(
            "wrap.gltf", 0.4f, 2.0f,
            "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}},"
            " \"extensions\": {\"KHR_materials_unlit\": {}}}",
            extra, "", "", "", "");
        float *img = calloc(T_SIZE * T_SIZE, 16);
        char row[T_SIZE + 1];
        if (render(path, 0, img)) {
            int runs = runs_on_row(img, best_row(img), row);
            printf("%-16s %s: %d runs (expected %d)\n", cases[k].name, row, runs, cases[k].runs);
            CHECK_EQ_INT(runs, cases[k].runs);
            CHECK(strchr(row, 'W') == NULL); /* nearest: no blended texels */
        } else {
            CHECK(false);
        }
        free(img);
    }
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_missing_texture_renders);
    RUN(test_instancing_draws_n);
    RUN(test_wrap_modes);
    t_context_close(&g_ctx);
    return t_finish();
}
