// SPDX-License-Identifier: MIT
/**
 * @file test_gltf_materials.c
 * @brief Issue 13 on the GPU: KHR_materials_unlit returns its base colour exactly (also under
 *        a sun), and a normal-mapped plane lit at a grazing angle renders differently from
 *        the flat one and matches a CPU shading of its texel (Lambertian, sun only).
 *
 * Scene: a 20 m square at z = -1 facing +Z (u along +x, v along -y: tangent +x, w = +1),
 * seen from the origin looking down -Z; a directional light 10 degrees above the plane
 * towards +x; environment 0; 1 spp, no jitter. The plane's material is an IOR-1 opaque
 * dielectric (pure Lambertian, xs_bsdf.glsl), so every pixel's radiance is deterministic:
 * base / pi x E x dot(n, L) from next-event estimation of the sun, nothing from the black
 * environment. Runs under the validation layer.
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
#define T_PI 3.14159265358979323846
#define T_SUN_ELEVATION_RAD (10.0 * T_PI / 180.0)
#define T_SUN_LUX 3.0
#define T_BASE 0.5
/* The normal map's one texel (8-bit, linear): tilts the normal towards +x. */
static const uint8_t k_texel[3] = {220, 128, 255};

static xrsc_context *g_ctx;

/** Writes the scene with the given material JSON; returns its path. The buffer: 4 positions,
 *  4 uvs, 6 u16 indices (+ 4 bytes padding) = 92 bytes. */
static const char *write_scene(const char *name, const char *material, const char *image_uri)
{
    uint8_t b[92];
    const float pos[12] = {-10, -10, -1, 10, -10, -1, 10, 10, -1, -10, 10, -1};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const uint16_t idx[8] = {0, 1, 2, 0, 2, 3, 0, 0};
    memcpy(b, pos, 48);
    memcpy(b + 48, uv, 32);
    memcpy(b + 80, idx, 12);
    double th = 0.5 * (0.5 * T_PI - T_SUN_ELEVATION_RAD); /* +Z of the light node -> L */
    char images[512] = "";
    if (image_uri)
        snprintf(images, sizeof images,
                 "\"images\": [{\"uri\": \"%s\"}], \"textures\": [{\"source\": 0}],", image_uri);
    return t_gltf_write(
        name, b, sizeof b,
        "{\"asset\": {\"version\": \"2.0\"},"
        " \"extensionsUsed\": [\"KHR_lights_punctual\", \"KHR_materials_ior\","
        " \"KHR_materials_unlit\"],"
        " \"extensions\": {\"KHR_lights_punctual\": {\"lights\": [{\"type\": \"directional\","
        " \"intensity\": %.17g}]}},"
        " \"scenes\": [{\"nodes\": [0, 1]}],"
        " \"nodes\": [{\"mesh\": 0}, {\"rotation\": [0, %.17g, 0, %.17g],"
        " \"extensions\": {\"KHR_lights_punctual\": {\"light\": 0}}}],"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1},"
        " \"indices\": 2, \"material\": 0}]}],"
        " \"materials\": [%s], %s"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": "
        "\"VEC3\"},"
        " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
        " {\"bufferView\": 2, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}],"
        " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": "
        "48,"
        " \"byteLength\": 32}, {\"buffer\": 0, \"byteOffset\": 80, \"byteLength\": 12}]",
        T_SUN_LUX, sin(th), cos(th), material, images);
}

/** Renders 1 spp and returns the mean colour of the centre pixels of the left eye, and the
 *  largest deviation of any of them from that mean. */
static bool render(const char *path, double mean[3], double *max_dev)
{
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SPP, .width = T_SIZE, .height = T_SIZE};
    ro.spp.samples_per_pixel = 1;
    ro.spp.no_jitter = true;
    float *c = t_render_file(g_ctx, path, &ro, NULL, &(t_render_job){.eyes = 1});
    bool ok = c != NULL;
    /* the centre half of the image: all on the plane */
    uint32_t lo = T_SIZE / 4, hi = 3 * T_SIZE / 4, n = 0;
    mean[0] = mean[1] = mean[2] = 0.0;
    for (uint32_t y = lo; ok && y < hi; y++)
        for (uint32_t x = lo; x < hi; x++, n++)
            for (int k = 0; k < 3; k++)
                mean[k] += c[4 * (y * T_SIZE + x) + k];
    for (int k = 0; k < 3 && n; k++)
        mean[k] /= n;
    *max_dev = 0.0;
    for (uint32_t y = lo; ok && y < hi; y++)
        for (uint32_t x = lo; x < hi; x++)
            for (int k = 0; k < 3; k++)
                *max_dev = fmax(*max_dev, fabs(c[4 * (y * T_SIZE + x) + k] - mean[k]));
    free(c);
    return ok;
}

static void test_unlit_exact(void)
{
    const char *path = write_scene(
        "unlit.gltf",
        "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.2, 0.4, 0.6, 1]},"
        " \"extensions\": {\"KHR_materials_unlit\": {}}}",
        NULL);
    double m[3], dev;
    CHECK(render(path, m, &dev));
    printf("unlit: %.9g %.9g %.9g (max deviation %.3g)\n", m[0], m[1], m[2], dev);
    CHECK_NEAR(m[0], 0.2, 1e-6);
    CHECK_NEAR(m[1], 0.4, 1e-6);
    CHECK_NEAR(m[2], 0.6, 1e-6);
    CHECK(dev <= 1e-6);
}

static void test_normal_map_grazing(void)
{
    static const char *flat_mat =
        "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.5, 0.5, 0.5, 1],"
        " \"metallicFactor\": 0, \"roughnessFactor\": 1},"
        " \"extensions\": {\"KHR_materials_ior\": {\"ior\": 1.0}}}";
    static const char *mapped_mat =
        "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.5, 0.5, 0.5, 1],"
        " \"metallicFactor\": 0, \"roughnessFactor\": 1},"
        " \"normalTexture\": {\"index\": 0},"
        " \"extensions\": {\"KHR_materials_ior\": {\"ior\": 1.0}}}";
    const char *png = t_temp_file("normal.png", "");
    xrsc_diag d;
    CHECK_EQ_INT(hs_write_png(png, k_texel, 1, 1, &d), XRSC_OK);
    const char *base = strrchr(png, '/');
    double flat[3], mapped[3], dev_f, dev_m;
    CHECK(render(write_scene("flat.gltf", flat_mat, NULL), flat, &dev_f));
    CHECK(render(write_scene("mapped.gltf", mapped_mat, base ? base + 1 : png), mapped, &dev_m));

    /* CPU reference: n = normalize(T c.x + B c.y + N c.z), T = +x, B = +y, N = +z. */
    double c[3], len = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k] = k_texel[k] / 255.0 * 2.0 - 1.0;
        len += c[k] * c[k];
    }
    len = sqrt(len);
    double L[3] = {cos(T_SUN_ELEVATION_RAD), 0.0, sin(T_SUN_ELEVATION_RAD)};
    double cos_mapped = (c[0] * L[0] + c[1] * L[1] + c[2] * L[2]) / len;
    double want_flat = T_BASE / T_PI * T_SUN_LUX * L[2];
    double want_mapped = T_BASE / T_PI * T_SUN_LUX * cos_mapped;
    printf("flat %.6g (CPU %.6g), normal-mapped %.6g (CPU %.6g); max deviations %.3g %.3g\n",
           flat[0], want_flat, mapped[0], want_mapped, dev_f, dev_m);
    for (int k = 0; k < 3; k++) {
        CHECK_NEAR(flat[k], want_flat, 1e-4 * want_flat);
        CHECK_NEAR(mapped[k], want_mapped, 1e-4 * want_mapped);
    }
    CHECK(mapped[0] > 3.0 * flat[0]); /* clearly different, not a rounding effect */
    CHECK(dev_f <= 1e-4 * want_flat && dev_m <= 1e-4 * want_mapped);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_unlit_exact);
    RUN(test_normal_map_grazing);
    t_context_close(&g_ctx);
    return t_finish();
}
