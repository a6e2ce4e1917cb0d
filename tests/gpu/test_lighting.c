// SPDX-License-Identifier: MIT
/**
 * @file test_lighting.c
 * @brief Issue 11 (lighting) on the GPU, under the validation layer:
 *  - a project-made scene with only an emissive material and no lights (the DamagedHelmet
 *    case) renders its non-emissive surface visibly lit under --env 1,1,1;
 *  - a constant-valued .hdr environment map gives what --env with that constant gives: the
 *    white furnace (scenes/furnace.gltf, a convex Lambertian sphere of albedo 0.5) returns
 *    exactly 0.5 L per pixel under a constant L, so with the map's importance sampling and MIS
 *    the mean over the sphere's pixels must be 0.5 L within T_SIGMAS standard errors;
 *  - importance sampling of a map with a small bright spot has a much lower per-pixel
 *    variance at equal spp than BSDF sampling alone (and the same mean within noise);
 *  - the Preetham sky (--sky) renders finite, with the side facing the sun brighter;
 *  - issue 18: a scene with no light gets the studio environment by default, under which a
 *    white Lambertian plane facing up reads 0.9 (its normalisation) within the noise.
 * Method spp, 2 x 32 x 32 (the furnace cases) and 2 x 24 x 24 (the helmet-like case).
 */
#include "hs_image.h"
#include "t_context.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Standard errors allowed between a measured mean and its expectation. */
#define T_SIGMAS 4.0
#define T_SIZE 32u
/* Half field of view of the furnace views (rad); the sphere (radius 1 at 3 m) spans 0.34. */
#define T_HALF_FOV 0.4f
/* Pixels of the sphere: within this fraction of its projected radius (tan space). */
#define T_SPHERE_INNER 0.8
/* Background pixels: beyond this multiple of it. */
#define T_SPHERE_OUTER 1.25

static xrsc_context *g_ctx;

static xrsc_frame make_frame(float z, float half_fov, uint32_t frame_index)
{
    xrsc_frame f;
    memset(&f, 0, sizeof(f));
    for (int e = 0; e < 2; e++) {
        f.views[e].pose.orientation.w = 1.0f;
        f.views[e].pose.position.z = z;
        f.views[e].fov.angleLeft = f.views[e].fov.angleDown = -half_fov;
        f.views[e].fov.angleRight = f.views[e].fov.angleUp = half_fov;
    }
    f.frame_index = frame_index;
    return f;
}

/** Renders both eyes with method spp; returns 2*size*size RGBA floats (malloc'ed) or NULL. */
static float *render_spp(xrsc_scene *scene, uint32_t size, uint32_t spp, uint32_t seed,
                         const xrsc_frame *frame)
{
    xrsc_renderer_options o = {0};
    o.method = XRSC_METHOD_SPP;
    o.width = o.height = size;
    o.seed = seed;
    o.spp.samples_per_pixel = spp;
    xrsc_renderer *r = NULL;
    xrsc_diag d = {0};
    xrsc_result res = xrsc_renderer_create(g_ctx, scene, &o, &r, &d);
    CHECK_MSG(res == XRSC_OK, "renderer: %s", d.message);
    if (res != XRSC_OK) return NULL;
    size_t bytes = (size_t)size * size * 4 * sizeof(float);
    float *px = malloc(2 * bytes);
    res = xrsc_renderer_render(r, frame);
    CHECK_EQ_INT(res, XRSC_OK);
    for (uint32_t e = 0; e < 2 && res == XRSC_OK; e++)
        res = xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, (char *)px + e * bytes, bytes);
    CHECK_EQ_INT(res, XRSC_OK);
    xrsc_renderer_destroy(&r);
    if (res != XRSC_OK) {
        free(px);
        return NULL;
    }
    return px;
}

static xrsc_scene *load(const char *path, const xrsc_scene_options *so)
{
    xrsc_scene *s = NULL;
    xrsc_diag d = {0};
    xrsc_result r = xrsc_scene_load(g_ctx, path, so, &s, &d);
    CHECK_MSG(r == XRSC_OK, "load %s: %s (%s)", path, xrsc_result_name(r), d.message);
    return s;
}

/* ---- the DamagedHelmet-like case ---- */

/** A 4 x 4 m grey Lambertian wall at z = -2 facing +Z and a 0.2 m emissive-only tile out of
 *  view at x = 3: no lights, no environment in the file (what glTF models look like). */
static const char *helmet_like_scene(void)
{
    static const float pos[24] = {-2, -2, -2, 2, -2, -2, 2, 2, -2, -2, 2, -2,
                                  3, -0.1f, -1.9f, 3, -0.1f, -2.1f, 3, 0.1f, -2.1f, 3, 0.1f, -1.9f};
    static const uint16_t idx[12] = {0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3};
    uint8_t bytes[96 + 24];
    memcpy(bytes, pos, 96);
    memcpy(bytes + 96, idx, 24);
    char *uri = t_data_uri(bytes, sizeof bytes);
    size_t cap = strlen(uri) + 4096;
    char *json = malloc(cap);
    snprintf(json, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
             "\"nodes\":[{\"mesh\":0},{\"mesh\":1}],\"meshes\":["
             "{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":2,\"material\":0}]},"
             "{\"primitives\":[{\"attributes\":{\"POSITION\":1},\"indices\":3,\"material\":1}]}],"
             "\"materials\":[{\"name\":\"grey\",\"pbrMetallicRoughness\":{\"baseColorFactor\":"
             "[0.6,0.6,0.6,1],\"metallicFactor\":0,\"roughnessFactor\":1},\"extensions\":"
             "{\"KHR_materials_ior\":{\"ior\":1}}},"
             "{\"name\":\"glow\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0,0,0,1]},"
             "\"emissiveFactor\":[1,0.6,0.3]}],"
             "\"extensionsUsed\":[\"KHR_materials_ior\"],"
             "\"buffers\":[{\"byteLength\":120,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":12},"
             "{\"buffer\":0,\"byteOffset\":108,\"byteLength\":12}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":"
             "\"VEC3\",\"min\":[-2,-2,-2],\"max\":[2,2,-2]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
             "\"min\":[3,-0.1,-2.1],\"max\":[3,0.1,-1.9]},"
             "{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"},"
             "{\"bufferView\":3,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]}",
             uri);
    free(uri);
    const char *path = t_temp_file("helmet_like.gltf", json);
    free(json);
    return path;
}

static void test_emissive_only_scene_is_lit(void)
{
    /* --env 1,1,1: the grey this test was written for (the default is now the studio
     * environment, tested in test_hdr_env and test_studio_default_lights_white_plane) */
    xrsc_scene_options grey = {.env_set = true, .environment = {1.0f, 1.0f, 1.0f}};
    xrsc_scene *scene = load(helmet_like_scene(), &grey);
    if (!scene) return;
    const uint32_t n = 24;
    xrsc_frame f = make_frame(0.0f, 0.5f, 0); /* the wall fills the view */
    float *px = render_spp(scene, n, 4, 1, &f);
    xrsc_scene_destroy(&scene);
    if (!px) return;
    double sum = 0.0;
    for (uint32_t i = 0; i < 2 * n * n; i++)
        sum += 0.2126 * px[i * 4] + 0.7152 * px[i * 4 + 1] + 0.0722 * px[i * 4 + 2];
    double mean = sum / (2.0 * n * n);
    /* Lambertian 0.6 under the grey environment of 1 (half of it seen past the tile):
     * about 0.6; with the old rule (environment 0 when a material emits) only the tile's
     * light, below 0.01. */
    printf("  helmet-like: mean wall radiance %.4f (environment %.1f)\n", mean, 1.0);
    CHECK_MSG(mean > 0.45 && mean < 0.7, "mean radiance %.4f", mean);
    /* visible in the tone-mapped output: exposure 1 and the automatic exposure */
    uint8_t *rgb = malloc((size_t)n * n * 3);
    hs_tonemap tm = {.exposure = 1.0f};
    hs_tonemap_rgba(&tm, px, n, n, rgb);
    double m8 = 0.0;
    for (uint32_t i = 0; i < n * n * 3; i++) m8 += rgb[i];
    m8 /= n * n * 3.0;
    printf("  helmet-like: mean 8-bit value %.1f at exposure 1\n", m8);
    CHECK(m8 > 100.0);
    hs_autoexposure ae = {0};
    const float *eyes[2] = {px, px + (size_t)n * n * 4};
    tm.exposure = hs_autoexposure_update(&ae, eyes, 2, n, n);
    hs_tonemap_rgba(&tm, px, n, n, rgb);
    m8 = 0.0;
    for (uint32_t i = 0; i < n * n * 3; i++) m8 += rgb[i];
    CHECK(m8 / (n * n * 3.0) > 100.0);
    free(rgb);
    free(px);
}

/* ---- furnace with environment maps ---- */

/** Writes a w x h .hdr of flat scanlines (the reader accepts them at any width): every texel
 *  is the RGBE value base, except those in x0..x1, y0..y1, which are spot (when not NULL). */
static const char *write_hdr(const char *name, uint32_t w, uint32_t h, const uint8_t base[4],
                             const uint8_t spot[4], uint32_t x0, uint32_t x1, uint32_t y0,
                             uint32_t y1)
{
    static char path[512];
    snprintf(path, sizeof path, "%s", t_temp_file(name, ""));
    FILE *fp = fopen(path, "wb");
    CHECK(fp != NULL);
    if (!fp) return path;
    fprintf(fp, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %u +X %u\n", h, w);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            bool in = spot && x >= x0 && x <= x1 && y >= y0 && y <= y1;
            fwrite(in ? spot : base, 1, 4, fp);
        }
    fclose(fp);
    return path;
}

/** RGBE as the .hdr reader decodes it (stb_image: m x 2^(e - 136), no +0.5; sc_hdr.h). */
static double decoded(uint8_t m, uint8_t e) { return m * ldexp(1.0, e - 136); }

/** Sphere pixel mask (1 sphere, 2 background, 0 neither) of pixel (x, y). */
static int pixel_class(uint32_t x, uint32_t y, uint32_t n)
{
    double t = tan(T_HALF_FOV);
    double tx = t * (2.0 * (x + 0.5) / n - 1.0), ty = t * (2.0 * (y + 0.5) / n - 1.0);
    double r = sqrt(tx * tx + ty * ty), rs = tan(asin(1.0 / 3.0));
    return r < T_SPHERE_INNER * rs ? 1 : r > T_SPHERE_OUTER * rs ? 2 : 0;
}

typedef struct t_moments {
    double sum[3], sum2[3];
    uint32_t count;
} t_moments;

/** Mean and spread of the sphere pixels (class 1) of both eyes. */
static t_moments sphere_moments(const float *px, uint32_t n)
{
    t_moments m = {0};
    for (uint32_t e = 0; e < 2; e++)
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++) {
                if (pixel_class(x, y, n) != 1) continue;
                const float *p = &px[(((size_t)e * n + y) * n + x) * 4];
                for (int c = 0; c < 3; c++) {
                    m.sum[c] += p[c];
                    m.sum2[c] += (double)p[c] * p[c];
                }
                m.count++;
            }
    return m;
}

static double mean_of(const t_moments *m, int c) { return m->sum[c] / m->count; }
static double se_of(const t_moments *m, int c)
{
    double mu = mean_of(m, c), var = m->sum2[c] / m->count - mu * mu;
    return sqrt(fmax(var, 0.0) / (m->count - 1));
}

static void test_constant_map_equals_env(void)
{
    const uint8_t base[4] = {127, 100, 80, 129};
    const char *hdr = write_hdr("const.hdr", 16, 8, base, NULL, 0, 0, 0, 0);
    double L[3] = {decoded(base[0], base[3]), decoded(base[1], base[3]),
                   decoded(base[2], base[3])};
    xrsc_scene_options env = {.env_set = true,
                              .environment = {(float)L[0], (float)L[1], (float)L[2]}};
    xrsc_scene_options map = {.env_map_path = hdr};
    xrsc_scene *a = load(t_source_path("scenes/furnace.gltf"), &env);
    xrsc_scene *b = load(t_source_path("scenes/furnace.gltf"), &map);
    if (!a || !b) {
        xrsc_scene_destroy(&a);
        xrsc_scene_destroy(&b);
        return;
    }
    xrsc_frame f = make_frame(3.0f, T_HALF_FOV, 0);
    float *pa = render_spp(a, T_SIZE, 4, 7, &f);
    float *pb = render_spp(b, T_SIZE, 4, 7, &f);
    xrsc_scene_destroy(&a);
    xrsc_scene_destroy(&b);
    if (pa && pb) {
        t_moments ma = sphere_moments(pa, T_SIZE), mb = sphere_moments(pb, T_SIZE);
        for (int c = 0; c < 3; c++) {
            /* --env: every path returns 0.5 L (BSDF sampling of a Lambertian), up to the
             * tessellation of the sphere (smooth normals on 64 x 32 segments: ~0.1 % lost) */
            double env = mean_of(&ma, c), se_env = se_of(&ma, c);
            CHECK_MSG(fabs(env - 0.5 * L[c]) < 5e-3 * L[c], "env: %.6f vs %.6f", env,
                      0.5 * L[c]);
            /* the map (light samples + BSDF samples with MIS): the same within its noise */
            double se = sqrt(se_of(&mb, c) * se_of(&mb, c) + se_env * se_env);
            printf("  constant map, channel %d: sphere mean %.5f, --env %.5f (0.5 L = %.5f), "
                   "standard error %.5f (%u pixels, 4 spp), z = %.2f\n",
                   c, mean_of(&mb, c), env, 0.5 * L[c], se, mb.count, (mean_of(&mb, c) - env) / se);
            CHECK_MSG(fabs(mean_of(&mb, c) - env) <= T_SIGMAS * se, "map: %.6f vs %.6f (se %.6f)",
                      mean_of(&mb, c), env, se);
        }
        /* the background sees the map's constant exactly */
        uint32_t bad = 0;
        for (uint32_t y = 0; y < T_SIZE; y++)
            for (uint32_t x = 0; x < T_SIZE; x++)
                if (pixel_class(x, y, T_SIZE) == 2)
                    for (int c = 0; c < 3; c++)
                        bad += fabs(pb[(y * T_SIZE + x) * 4 + c] - L[c]) > 1e-6 * L[c];
        CHECK_EQ_INT(bad, 0);
    }
    free(pa);
    free(pb);
}

static void test_importance_sampling_variance(void)
{
    /* 64 x 32 map of 0.05 with a 2 x 2 texel spot of about 2000 up and behind the camera
     * (+Z, u = 0), which lights the sphere's visible side */
    const uint8_t base[4] = {204, 204, 204, 124}, spot[4] = {250, 250, 250, 139};
    const char *hdr = write_hdr("spot.hdr", 64, 32, base, spot, 0, 1, 9, 10);
    xrsc_scene_options is = {.env_map_path = hdr};
    xrsc_scene_options bsdf_only = {.env_map_path = hdr, .env_no_importance = true};
    xrsc_scene *a = load(t_source_path("scenes/furnace.gltf"), &is);
    xrsc_scene *b = load(t_source_path("scenes/furnace.gltf"), &bsdf_only);
    double var[2] = {0, 0}, mean[2] = {0, 0}, se[2] = {0, 0};
    for (int k = 0; k < 2 && a && b; k++) {
        xrsc_scene *s = k ? b : a;
        xrsc_frame f = make_frame(3.0f, T_HALF_FOV, 0);
        float *p1 = render_spp(s, T_SIZE, 4, 11, &f);
        float *p2 = render_spp(s, T_SIZE, 4, 12, &f);
        if (p1 && p2) {
            /* per-pixel variance of a 4-spp estimate from two independent renders:
             * E[(a - b)^2] = 2 var (luminance, sphere pixels) */
            double d2 = 0.0;
            uint32_t cnt = 0;
            for (uint32_t i = 0; i < 2 * T_SIZE * T_SIZE; i++) {
                uint32_t x = i % T_SIZE, y = (i / T_SIZE) % T_SIZE;
                if (pixel_class(x, y, T_SIZE) != 1) continue;
                double l1 = 0.2126 * p1[i * 4] + 0.7152 * p1[i * 4 + 1] + 0.0722 * p1[i * 4 + 2];
                double l2 = 0.2126 * p2[i * 4] + 0.7152 * p2[i * 4 + 1] + 0.0722 * p2[i * 4 + 2];
                d2 += (l1 - l2) * (l1 - l2);
                mean[k] += 0.5 * (l1 + l2);
                cnt++;
            }
            var[k] = d2 / (2.0 * cnt);
            mean[k] /= cnt;
            /* the sphere mean's standard error: pixel means differ (shading), so bound it by
             * the noise alone: sqrt(var / (2 cnt)) */
            se[k] = sqrt(var[k] / (2.0 * cnt));
        }
        free(p1);
        free(p2);
    }
    xrsc_scene_destroy(&a);
    xrsc_scene_destroy(&b);
    printf("  spot map, 4 spp: per-pixel variance %.4g with importance sampling, %.4g with BSDF "
           "sampling only (ratio %.1f); sphere means %.4f +- %.4f and %.4f +- %.4f\n",
           var[0], var[1], var[0] > 0 ? var[1] / var[0] : 0.0, mean[0], se[0], mean[1], se[1]);
    CHECK_MSG(var[0] > 0.0 && var[1] > 10.0 * var[0], "variance %.4g vs %.4g", var[0], var[1]);
    /* both unbiased: the same sphere mean within the noise */
    CHECK_MSG(fabs(mean[0] - mean[1]) <= T_SIGMAS * sqrt(se[0] * se[0] + se[1] * se[1]),
              "means %.5f vs %.5f", mean[0], mean[1]);
}

static void test_sky(void)
{
    /* sun up and behind the camera on the right: the sphere's upper right is sunlit */
    xrsc_scene_options so = {.sky = true, .sun_direction_set = true,
                             .sun_direction = {0.6f, 0.6f, 0.53f}};
    xrsc_scene *s = load(t_source_path("scenes/furnace.gltf"), &so);
    if (!s) return;
    xrsc_frame f = make_frame(3.0f, T_HALF_FOV, 0);
    float *px = render_spp(s, T_SIZE, 4, 3, &f);
    xrsc_scene_destroy(&s);
    if (!px) return;
    bool finite = true;
    for (uint32_t i = 0; i < 2 * T_SIZE * T_SIZE * 4; i++) finite &= isfinite(px[i]);
    CHECK(finite);
    /* the sphere's sunlit quadrant (right, upper: image rows top to bottom) vs the opposite */
    double lit = 0.0, dark = 0.0;
    uint32_t q = T_SIZE / 2, d = T_SIZE / 8;
    for (uint32_t y = q - 3 * d; y < q - d; y++)
        for (uint32_t x = q + d; x < q + 3 * d; x++) lit += px[(y * T_SIZE + x) * 4 + 1];
    for (uint32_t y = q + d; y < q + 3 * d; y++)
        for (uint32_t x = q - 3 * d; x < q - d; x++) dark += px[(y * T_SIZE + x) * 4 + 1];
    printf("  sky: sunlit quadrant %.4f, opposite %.4f (green, sums)\n", lit, dark);
    CHECK(lit > 2.0 * dark && dark > 0.0);
    free(px);
}

/* ---- the studio environment of a scene without light (issue 18) ---- */

/** A 40 x 40 m white Lambertian plane (IOR 1: no specular layer) at y = 0 facing +Y, with
 *  normals, no light and no environment in the file. */
static const char *white_plane_scene(void)
{
    static const float geo[24] = {-20, 0, -20, 20, 0, -20, 20, 0, 20, -20, 0, 20,
                                  0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
    static const uint16_t idx[6] = {0, 2, 1, 0, 3, 2};
    uint8_t bytes[96 + 12];
    memcpy(bytes, geo, 96);
    memcpy(bytes + 96, idx, 12);
    char *uri = t_data_uri(bytes, sizeof bytes);
    size_t cap = strlen(uri) + 4096;
    char *json = malloc(cap);
    snprintf(json, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":"
             "{\"POSITION\":0,\"NORMAL\":1},\"indices\":2,\"material\":0}]}],"
             "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,1,1,1],"
             "\"metallicFactor\":0,\"roughnessFactor\":1},\"extensions\":"
             "{\"KHR_materials_ior\":{\"ior\":1}}}],\"extensionsUsed\":[\"KHR_materials_ior\"],"
             "\"buffers\":[{\"byteLength\":108,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":12}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":"
             "\"VEC3\",\"min\":[-20,0,-20],\"max\":[20,0,20]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
             "{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]}",
             uri);
    free(uri);
    const char *path = t_temp_file("white_plane.gltf", json);
    free(json);
    return path;
}

/** The default lighting of a scene with no light is the studio environment: a white
 *  Lambertian plane facing up, seen from above, reads SC_STUDIO_UP_RADIANCE (0.9) in
 *  luminance, through the GPU's map lookup and its importance sampling with MIS. */
static void test_studio_default_lights_white_plane(void)
{
    xrsc_scene *scene = load(white_plane_scene(), NULL);
    if (!scene) return;
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    CHECK(info.studio_environment);
    const uint32_t n = 24;
    xrsc_frame f = make_frame(0.0f, 0.3f, 0);
    for (int e = 0; e < 2; e++) { /* 1 m above the plane, looking straight down */
        f.views[e].pose.position.y = 1.0f;
        f.views[e].pose.orientation = (XrQuaternionf){-0.70710678f, 0.0f, 0.0f, 0.70710678f};
    }
    float *px = render_spp(scene, n, 16, 5, &f);
    xrsc_scene_destroy(&scene);
    if (!px) return;
    double sum = 0.0, sum2 = 0.0;
    const uint32_t count = 2 * n * n;
    for (uint32_t i = 0; i < count; i++) {
        double l = 0.2126 * px[i * 4] + 0.7152 * px[i * 4 + 1] + 0.0722 * px[i * 4 + 2];
        sum += l, sum2 += l * l;
    }
    double mean = sum / count, se = sqrt(fmax(sum2 / count - mean * mean, 0.0) / count);
    printf("  studio: white plane facing up reads %.4f +- %.4f (expected 0.9)\n", mean, se);
    CHECK_MSG(fabs(mean - 0.9) <= T_SIGMAS * se + 0.005, "mean %.4f +- %.4f", mean, se);
    free(px);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_emissive_only_scene_is_lit);
    RUN(test_constant_map_equals_env);
    RUN(test_importance_sampling_variance);
    RUN(test_sky);
    RUN(test_studio_default_lights_white_plane);
    t_context_close(&g_ctx);
    return t_finish();
}
