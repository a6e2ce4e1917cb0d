// SPDX-License-Identifier: MIT
/**
 * @file test_glass.c
 * @brief Shadow rays through glass and emission of alpha holes (issue 18, item 3), on the GPU
 *        under the validation layer.
 *
 * - A smooth thin-walled glass pane (KHR_materials_transmission 1, IOR 1.5, base colour
 *   T_TINT) 1 m in front of the camera, before a Lambertian wall 2 m away (albedo T_ALBEDO,
 *   IOR 1: no specular), under one directional light shining along the view (environment 0,
 *   max_bounces 2: light sampling at the wall plus one escaping BSDF ray, so no indirect light
 *   reaches the camera). The wall's radiance is E albedo / pi where lit directly, and E albedo
 *   / pi x (1 - F(0)) tint where the pane's shadow falls (the shadow ray passes the thin wall,
 *   xs_path.glsl); seen through the pane it is further times (1 - F(cos)) tint. Without the
 *   shadow rule the wall behind the pane is black; without the colour, grey. Checked per region
 *   (mean over its pixels within T_SIGMAS standard errors + T_REL_TOL: the only randomness is
 *   the camera ray's Fresnel choice at the pane) for method spp, and the sample cache (with its
 *   visibility cache) against spp's region means within T_SC_TOL.
 * - An emissive quad above a Lambertian floor: alphaMode MASK with alpha 0 (a hole everywhere)
 *   lights nothing (the floor is exactly 0); BLEND with alpha 0.5 gives half the light of the
 *   same quad OPAQUE (image means within T_SIGMAS standard errors).
 */
#include "t_context.h"
#include "t_frames.h"
#include "t_gltf.h"
#include "t_optics.h"
#include "t_render.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 32u
#define T_SPP 16u
#define T_HALF_FOV 0.3f /* rad */
#define T_PI 3.14159265358979323846
#define T_ALBEDO 0.5
#define T_E 2.0         /* the directional light's irradiance */
#define T_IOR 1.5
#define T_GLASS_HALF 0.2 /* the pane spans |x|, |y| <= this at z = -1 */
#define T_MARGIN 0.02    /* pixels whose ray is this close (tan units) to an edge are skipped */
#define T_SIGMAS 5.0
#define T_REL_TOL 0.01
#define T_SC_TOL 0.05
static const double T_TINT[3] = {0.9, 0.6, 0.3};

static xrsc_context *g_ctx;

/** A scene of two quads (each 4 corners x 3 floats; quad 0 from q0, quad 1 from q1, in one
 *  buffer) with materials m0 and m1 (JSON objects), environment 0, and the given extra
 *  top-level JSON (lights); node 2 is added to the scene when light_node is not NULL. */
static const char *quads_scene(const char *name, const float q0[12], const float q1[12],
                               const float lo0[3], const float hi0[3], const float lo1[3],
                               const float hi1[3], const char *m0, const char *m1,
                               const char *light_node, const char *extensions)
{
    static const uint16_t idx[12] = {0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3};
    uint8_t bytes[96 + 24];
    memcpy(bytes, q0, 48);
    memcpy(bytes + 48, q1, 48);
    memcpy(bytes + 96, idx, 24);
    return t_gltf_write(
        name, bytes, sizeof bytes,
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1%s],"
        "\"extras\":{\"xrsc_environment\":[0,0,0]}}],"
        "\"nodes\":[{\"mesh\":0},{\"mesh\":1}%s%s],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":2,"
        "\"material\":0}]},{\"primitives\":[{\"attributes\":{\"POSITION\":1},"
        "\"indices\":3,\"material\":1}]}],"
        "\"materials\":[%s,%s],%s"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":12},"
        "{\"buffer\":0,\"byteOffset\":108,\"byteLength\":12}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":"
        "\"VEC3\",\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":"
        "\"VEC3\",\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]},"
        "{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"},"
        "{\"bufferView\":3,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]",
        light_node ? ",2" : "", light_node ? "," : "", light_node ? light_node : "", m0, m1,
        extensions, lo0[0], lo0[1], lo0[2], hi0[0], hi0[1], hi0[2], lo1[0], lo1[1], lo1[2], hi1[0],
        hi1[1], hi1[2]);
}

/** Renders both eyes of f; returns 2 * T_SIZE^2 RGBA floats (malloc'ed) or NULL. */
static float *render(xrsc_scene *scene, xrsc_method method, uint32_t seed, uint32_t bounces,
                     const xrsc_frame *f)
{
    xrsc_renderer_options o = {.method = method, .width = T_SIZE, .height = T_SIZE, .seed = seed};
    o.spp.samples_per_pixel = T_SPP;
    o.spp.no_jitter = true;
    o.spp.max_bounces = bounces;
    o.samplecache.max_bounces = bounces;
    o.samplecache.visibility.enabled = true;
    return t_render_image(g_ctx, scene, &o, f, NULL);
}

/* regions of the pane scene: through the pane onto its shadow, through the pane onto the lit
 * wall, the lit wall seen directly */
enum { R_SHADOW, R_THROUGH_LIT, R_DIRECT, R_COUNT };
static const char *const R_NAMES[R_COUNT] = {"through pane, its shadow", "through pane, lit",
                                             "wall, direct"};

/** Region of pixel (x, y) and its expected radiance (channel c), or -1 near an edge. */
static int pane_pixel(uint32_t x, uint32_t y, int c, double *out_want)
{
    double t = tan((double)T_HALF_FOV);
    double tx = (2.0 * (x + 0.5) / T_SIZE - 1.0) * t, ty = (2.0 * (y + 0.5) / T_SIZE - 1.0) * t;
    double ax = fabs(tx), ay = fabs(ty), g = T_GLASS_HALF, s = T_GLASS_HALF / 2.0;
    /* the pane at z = -1 covers |t| <= g; its (parallel) shadow on the wall at z = -2 covers
     * wall |x| <= g, seen at |t| <= g / 2 */
    if (fabs(ax - g) < T_MARGIN || fabs(ay - g) < T_MARGIN || fabs(ax - s) < T_MARGIN ||
        fabs(ay - s) < T_MARGIN)
        return -1;
    bool through = ax < g && ay < g, shadow = ax < s && ay < s;
    double cos_cam = 1.0 / sqrt(1.0 + tx * tx + ty * ty);
    double l = T_E * T_ALBEDO / T_PI;
    if (shadow)
        l *= (1.0 - t_fresnel(1.0, T_IOR)) * T_TINT[c];
    if (through)
        l *= (1.0 - t_fresnel(cos_cam, T_IOR)) * T_TINT[c];
    *out_want = l;
    return shadow ? R_SHADOW : through ? R_THROUGH_LIT : R_DIRECT;
}

static const char *pane_scene(void)
{
    static const float wall[12] = {-3, -3, -2, 3, -3, -2, 3, 3, -2, -3, 3, -2};
    const float g = (float)T_GLASS_HALF;
    const float pane[12] = {-g, -g, -1, g, -g, -1, g, g, -1, -g, g, -1};
    const float wl[3] = {-3, -3, -2}, wh[3] = {3, 3, -2};
    const float pl[3] = {-g, -g, -1}, ph[3] = {g, g, -1};
    char glass[512];
    snprintf(glass, sizeof glass,
             "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[%g,%g,%g,1],\"metallicFactor\":0,"
             "\"roughnessFactor\":0},\"doubleSided\":true,\"extensions\":{"
             "\"KHR_materials_transmission\":{\"transmissionFactor\":1},"
             "\"KHR_materials_ior\":{\"ior\":%g}}}",
             T_TINT[0], T_TINT[1], T_TINT[2], T_IOR);
    char ext[512];
    snprintf(ext, sizeof ext,
             "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"directional\","
             "\"intensity\":%g}]}},\"extensionsUsed\":[\"KHR_materials_ior\","
             "\"KHR_materials_transmission\",\"KHR_lights_punctual\"],",
             T_E);
    return quads_scene(
        "glass_pane.gltf", wall, pane, wl, wh, pl, ph,
        "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.5,0.5,1],\"metallicFactor\":0,"
        "\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_ior\":{\"ior\":1}}}",
        glass, "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}", ext);
}

/** Per region: the mean of got and of want (3 channels pooled as ratios got / want), and the
 *  standard error of the ratio. */
static void pane_regions(const float *px, double mean[R_COUNT], double se[R_COUNT],
                         uint32_t n[R_COUNT])
{
    double s1[R_COUNT] = {0}, s2[R_COUNT] = {0};
    for (int r = 0; r < R_COUNT; r++)
        n[r] = 0;
    for (uint32_t e = 0; e < 2; e++)
        for (uint32_t y = 0; y < T_SIZE; y++)
            for (uint32_t x = 0; x < T_SIZE; x++)
                for (int c = 0; c < 3; c++) {
                    double want;
                    int r = pane_pixel(x, y, c, &want);
                    if (r < 0)
                        continue;
                    double v = px[4 * ((e * T_SIZE + y) * T_SIZE + x) + c] / want;
                    s1[r] += v, s2[r] += v * v, n[r]++;
                }
    for (int r = 0; r < R_COUNT; r++) {
        mean[r] = n[r] ? s1[r] / n[r] : 0.0;
        se[r] = n[r] ? sqrt(fmax(s2[r] / n[r] - mean[r] * mean[r], 0.0) / n[r]) : 0.0;
    }
}

static void test_shadow_through_glass(void)
{
    xrsc_scene *scene = t_scene_load(g_ctx, pane_scene());
    if (!scene)
        return;
    static const float pos[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1};
    xrsc_frame f = t_frame_at(pos, q, T_HALF_FOV);
    float *px = render(scene, XRSC_METHOD_SPP, 1, 2, &f);
    float *sc = render(scene, XRSC_METHOD_SAMPLECACHE, 1, 2, &f);
    xrsc_scene_destroy(&scene);
    double mean[R_COUNT], se[R_COUNT], mean_sc[R_COUNT], se_sc[R_COUNT];
    uint32_t n[R_COUNT];
    if (px) {
        pane_regions(px, mean, se, n);
        for (int r = 0; r < R_COUNT; r++) {
            printf("  spp, %s: radiance / expected %.4f +- %.4f (%u values)\n", R_NAMES[r],
                   mean[r], se[r], n[r]);
            CHECK(n[r] > 50);
            CHECK_MSG(fabs(mean[r] - 1.0) <= T_SIGMAS * se[r] + T_REL_TOL, "%s: %.4f",
                      R_NAMES[r], mean[r]);
        }
    }
    if (px && sc) {
        pane_regions(sc, mean_sc, se_sc, n);
        for (int r = 0; r < R_COUNT; r++) {
            printf("  samplecache, %s: radiance / expected %.4f (spp %.4f)\n", R_NAMES[r],
                   mean_sc[r], mean[r]);
            CHECK_MSG(fabs(mean_sc[r] - mean[r]) <= T_SC_TOL * mean[r], "%s: %.4f vs %.4f",
                      R_NAMES[r], mean_sc[r], mean[r]);
        }
    }
    free(px);
    free(sc);
}

/** An emissive quad (1 x 1 m at y = 1 facing down, emission 2) with material `alpha` JSON
 *  over a 6 x 6 m Lambertian floor; the mean floor radiance seen from above and its standard
 *  error. Returns false when it did not render. */
static bool emitter_floor(const char *name, const char *alpha, double *out_mean,
                          double *out_se, double *out_max)
{
    static const float floor_q[12] = {-3, 0, -3, -3, 0, 3, 3, 0, 3, 3, 0, -3};
    /* counter-clockwise seen from below: the front faces -Y */
    static const float lamp[12] = {-0.5f, 1, -0.5f, 0.5f, 1, -0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f};
    const float fl[3] = {-3, 0, -3}, fh[3] = {3, 0, 3};
    const float ll[3] = {-0.5f, 1, -0.5f}, lh[3] = {0.5f, 1, 0.5f};
    char lamp_mat[512];
    snprintf(lamp_mat, sizeof lamp_mat,
             "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0,0,0,%s],\"metallicFactor\":0,"
             "\"roughnessFactor\":1},\"emissiveFactor\":[1,1,1],%s,"
             "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":2}}}",
             strstr(alpha, "OPAQUE") ? "1" : strstr(alpha, "MASK") ? "0" : "0.5", alpha);
    const char *path = quads_scene(
        name, floor_q, lamp, fl, fh, ll, lh,
        "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.5,0.5,1],\"metallicFactor\":0,"
        "\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_ior\":{\"ior\":1}}}",
        lamp_mat, NULL,
        "\"extensionsUsed\":[\"KHR_materials_ior\",\"KHR_materials_emissive_strength\"],");
    xrsc_scene *scene = t_scene_load(g_ctx, path);
    if (!scene)
        return false;
    /* looking straight down from 2 m (-Z turned to -Y about +X) */
    static const float pos[3] = {0, 2, 0}, q[4] = {-0.70710678f, 0, 0, 0.70710678f};
    xrsc_frame f = t_frame_at(pos, q, T_HALF_FOV);
    float *px = render(scene, XRSC_METHOD_SPP, 7, 0, &f);
    xrsc_scene_destroy(&scene);
    if (!px)
        return false;
    uint32_t n = 2 * T_SIZE * T_SIZE * 3;
    double s1 = 0.0, s2 = 0.0, mx = 0.0;
    for (uint32_t i = 0; i < 2 * T_SIZE * T_SIZE; i++)
        for (int c = 0; c < 3; c++) {
            double v = px[4 * i + c];
            s1 += v, s2 += v * v, mx = fmax(mx, fabs(v));
        }
    free(px);
    *out_mean = s1 / n;
    *out_se = sqrt(fmax(s2 / n - *out_mean * *out_mean, 0.0) / n);
    *out_max = mx;
    return true;
}

static void test_emitter_holes(void)
{
    double m_hole, se_hole, max_hole, m_opaque, se_opaque, max_opaque, m_blend, se_blend,
        max_blend;
    if (!emitter_floor("glass_lamp_mask.gltf", "\"alphaMode\":\"MASK\"", &m_hole, &se_hole,
                       &max_hole) ||
        !emitter_floor("glass_lamp_opaque.gltf", "\"alphaMode\":\"OPAQUE\"", &m_opaque,
                       &se_opaque, &max_opaque) ||
        !emitter_floor("glass_lamp_blend.gltf", "\"alphaMode\":\"BLEND\"", &m_blend, &se_blend,
                       &max_blend))
        return;
    printf("  floor under a lamp: OPAQUE mean %.5f +- %.5f; MASK alpha 0 max %.3g; BLEND 0.5 "
           "mean %.5f +- %.5f (ratio %.4f)\n",
           m_opaque, se_opaque, max_hole, m_blend, se_blend, m_blend / m_opaque);
    CHECK(m_opaque > 0.01);
    CHECK_MSG(max_hole == 0.0, "a lamp that is all hole lights the floor: max %g", max_hole);
    double se = sqrt(se_blend * se_blend + 0.25 * se_opaque * se_opaque);
    CHECK_MSG(fabs(m_blend - 0.5 * m_opaque) <= T_SIGMAS * se + T_REL_TOL * m_opaque,
              "BLEND 0.5: %.5f, half of OPAQUE %.5f", m_blend, 0.5 * m_opaque);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_shadow_through_glass);
    RUN(test_emitter_holes);
    t_context_close(&g_ctx);
    return t_finish();
}
