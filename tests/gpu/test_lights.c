// SPDX-License-Identifier: MIT
/**
 * @file test_lights.c
 * @brief KHR_lights_punctual on the GPU (issue 18, item 3), under the validation layer: a
 *        Lambertian plane (albedo 0.5, ior 1: no specular layer) seen from straight above,
 *        lit only by the file's lights (environment 0), rendered with method `spp` at pixel
 *        centres. The irradiance E = L pi / albedo of each pixel must equal the analytic one:
 *  - a spot light 1 m above the plane pointing down (inner 0.3, outer 0.6 rad, range 2 m):
 *    E = I cos / d^2 x spot x window (glTF's smoothstep-like cone ramp of the spec's
 *    implementation note, and its recommended range window clamp(1 - (d / range)^4, 0, 1)),
 *    inside the inner cone, in the transition band and outside the outer cone (0);
 *  - a point light: the inverse-square law E = I h / d^3;
 *  - two directional lights add (sun + one light of XS_BIND_LIGHTS: E1 cos1 + E2 cos2 in
 *    every pixel), and three (two picked by power per vertex: the image mean within
 *    T_SIGMAS standard errors of the sum);
 *  - method samplecache with the visibility cache renders the spot's image as spp does.
 * Only the delta light's next-event estimate reaches the camera here (bounce rays escape into
 * a black environment), so each pixel of a one-light case is exact up to float rounding:
 * tolerance T_REL_TOL relative + T_ABS_TOL absolute.
 */
#include "t_context.h"
#include "t_frames.h"
#include "t_gltf.h"
#include "t_render.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 32u
#define T_SPP 4u
#define T_HALF_FOV 0.5f /* rad: the view spans r <= 2 tan(0.5) = 1.09 m (edges) on the plane */
#define T_CAMERA_Y 2.0  /* m above the plane */
#define T_LIGHT_Y 1.0   /* m above the plane */
#define T_ALBEDO 0.5
#define T_PI 3.14159265358979323846
#define T_REL_TOL 0.01
#define T_ABS_TOL 1e-4
#define T_SIGMAS 4.0
/* the spot: intensity (W/sr), cone angles (rad), range (m) */
#define T_SPOT_I 5.0
#define T_SPOT_INNER 0.3
#define T_SPOT_OUTER 0.6
#define T_SPOT_RANGE 2.0
#define T_POINT_I 3.0

static xrsc_context *g_ctx;

/* Quaternions (x, y, z, w) that turn a light's -Z down to -Y, and 30 / 60 degrees short of
 * it (about +X): the light's direction makes 0, 60 and 30 degrees with the plane's normal. */
#define T_ROT_DOWN "[-0.70710678,0,0,0.70710678]"
#define T_ROT_60 "[-0.25881905,0,0,0.96592583]"
#define T_ROT_30 "[-0.5,0,0,0.8660254]"

/** A 6 x 6 m plane at y = 0 facing +Y, environment 0, the given lights (JSON array) on the
 *  given light nodes (JSON objects, comma-separated, after the plane's node 0). */
static const char *plane_scene(const char *name, const char *lights, const char *light_nodes,
                               uint32_t light_node_count)
{
    static const float pos[12] = {-3, 0, -3, -3, 0, 3, 3, 0, 3, 3, 0, -3};
    static const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    uint8_t bytes[48 + 12];
    memcpy(bytes, pos, 48);
    memcpy(bytes + 48, idx, 12);
    char roots[256] = "0";
    for (uint32_t i = 0; i < light_node_count; i++)
        snprintf(roots + strlen(roots), sizeof roots - strlen(roots), ",%u", i + 1);
    return t_gltf_write(
        name, bytes, sizeof bytes,
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[%s],"
        "\"extras\":{\"xrsc_environment\":[0,0,0]}}],"
        "\"nodes\":[{\"mesh\":0},%s],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,"
        "\"material\":0}]}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.5,0.5,1],"
        "\"metallicFactor\":0,\"roughnessFactor\":1},"
        "\"extensions\":{\"KHR_materials_ior\":{\"ior\":1}}}],"
        "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":%s}},"
        "\"extensionsUsed\":[\"KHR_materials_ior\",\"KHR_lights_punctual\"],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":12}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":"
        "\"VEC3\",\"min\":[-3,0,-3],\"max\":[3,0,3]},"
        "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]",
        roots, light_nodes, lights);
}

/** Renders both eyes at (0, T_CAMERA_Y, 0) looking straight down (method spp at pixel
 *  centres, or samplecache with the visibility cache); returns 2 * T_SIZE^2 RGBA floats
 *  (malloc'ed) or NULL. */
static float *render(xrsc_scene *scene, xrsc_method method, uint32_t seed)
{
    static const float pos[3] = {0, (float)T_CAMERA_Y, 0}, q[4] = {-0.70710678f, 0, 0, 0.70710678f};
    xrsc_frame f = t_frame_at(pos, q, T_HALF_FOV);
    xrsc_renderer_options o = {.method = method, .width = T_SIZE, .height = T_SIZE, .seed = seed};
    o.spp.samples_per_pixel = T_SPP;
    o.spp.no_jitter = true;
    o.samplecache.visibility.enabled = true;
    return t_render_image(g_ctx, scene, &o, &f, NULL);
}

/** Distance on the plane from below the camera of pixel (x, y)'s centre ray. */
static double pixel_radius(uint32_t x, uint32_t y)
{
    double t = tan((double)T_HALF_FOV);
    double tx = (2.0 * (x + 0.5) / T_SIZE - 1.0) * t, ty = (2.0 * (y + 0.5) / T_SIZE - 1.0) * t;
    return T_CAMERA_Y * sqrt(tx * tx + ty * ty);
}

/** Measured irradiance E = L pi / albedo (green channel) of pixel i of both eyes' images. */
static double irradiance(const float *px, uint32_t i)
{
    return px[4 * i + 1] * T_PI / T_ALBEDO;
}

/** glTF's spot ramp and range window for a light at height T_LIGHT_Y pointing down. */
static double spot_expected(double r)
{
    double d2 = r * r + T_LIGHT_Y * T_LIGHT_Y, d = sqrt(d2);
    double cd = T_LIGHT_Y / d; /* cos to the axis = cos of incidence */
    double ci = cos(T_SPOT_INNER), co = cos(T_SPOT_OUTER);
    double a = fmin(fmax((cd - co) / fmax(0.001, ci - co), 0.0), 1.0);
    double q = (d / T_SPOT_RANGE) * (d / T_SPOT_RANGE);
    double window = fmin(fmax(1.0 - q * q, 0.0), 1.0);
    return T_SPOT_I * cd / d2 * a * a * window;
}

static double point_expected(double r)
{
    double d2 = r * r + T_LIGHT_Y * T_LIGHT_Y;
    return T_POINT_I * T_LIGHT_Y / (d2 * sqrt(d2));
}

/** Compares every pixel with expect(r); counts pixels per region (0 inside the inner cone,
 *  1 transition, 2 outside the outer cone) of the angle from the light's axis. */
static void check_pixels(const char *what, const float *px, double (*expect)(double),
                         uint32_t counts[3])
{
    double worst = 0.0;
    uint32_t bad = 0;
    for (uint32_t e = 0; e < 2; e++)
        for (uint32_t y = 0; y < T_SIZE; y++)
            for (uint32_t x = 0; x < T_SIZE; x++) {
                double r = pixel_radius(x, y);
                double want = expect(r);
                double got = irradiance(px, (e * T_SIZE + y) * T_SIZE + x);
                double err = fabs(got - want);
                double angle = atan(r / T_LIGHT_Y);
                counts[angle < T_SPOT_INNER ? 0 : angle < T_SPOT_OUTER ? 1 : 2]++;
                if (want == 0.0 ? got != 0.0 : err > T_REL_TOL * want + T_ABS_TOL) {
                    if (bad++ < 4)
                        printf("  %s: eye %u pixel (%u, %u), r %.3f m: E %.5f, expected %.5f\n",
                               what, e, x, y, r, got, want);
                }
                if (want > 0.0)
                    worst = fmax(worst, err / want);
            }
    printf("  %s: worst relative error %.2e over the lit pixels; %u inner, %u band, %u outside\n",
           what, worst, counts[0], counts[1], counts[2]);
    CHECK_MSG(bad == 0, "%s: %u pixels off", what, bad);
}

static const char *spot_scene(void)
{
    char lights[256];
    snprintf(lights, sizeof lights,
             "[{\"type\":\"spot\",\"color\":[1,1,1],\"intensity\":%g,\"range\":%g,"
             "\"spot\":{\"innerConeAngle\":%g,\"outerConeAngle\":%g}}]",
             T_SPOT_I, T_SPOT_RANGE, T_SPOT_INNER, T_SPOT_OUTER);
    return plane_scene("lights_spot.gltf", lights,
                       "{\"translation\":[0,1,0],\"rotation\":" T_ROT_DOWN
                       ",\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}",
                       1);
}

static void test_spot_cone_falloff(void)
{
    xrsc_scene *scene = t_scene_load(g_ctx, spot_scene());
    if (!scene)
        return;
    float *px = render(scene, XRSC_METHOD_SPP, 1);
    float *sc = render(scene, XRSC_METHOD_SAMPLECACHE, 1);
    xrsc_scene_destroy(&scene);
    if (px) {
        uint32_t counts[3] = {0, 0, 0};
        check_pixels("spot", px, spot_expected, counts);
        CHECK(counts[0] > 20 && counts[1] > 100 && counts[2] > 100);
    }
    /* the sample cache's shading with the visibility cache (its light end: the spot's
     * position) sees the same light: the same image mean within T_REL_TOL */
    if (px && sc) {
        double a = 0.0, b = 0.0;
        for (uint32_t i = 0; i < 2 * T_SIZE * T_SIZE; i++)
            a += irradiance(px, i), b += irradiance(sc, i);
        printf("  spot: mean E spp %.5f, samplecache + visibility cache %.5f\n",
               a / (2 * T_SIZE * T_SIZE), b / (2 * T_SIZE * T_SIZE));
        CHECK_MSG(fabs(a - b) <= T_REL_TOL * a, "means %.5f %.5f", a, b);
    }
    free(px);
    free(sc);
}

static void test_point_inverse_square(void)
{
    char lights[128];
    snprintf(lights, sizeof lights, "[{\"type\":\"point\",\"color\":[1,1,1],\"intensity\":%g}]",
             T_POINT_I);
    xrsc_scene *scene = t_scene_load(
        g_ctx,
        plane_scene(
            "lights_point.gltf", lights,
            "{\"translation\":[0,1,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}", 1));
    if (!scene)
        return;
    float *px = render(scene, XRSC_METHOD_SPP, 2);
    xrsc_scene_destroy(&scene);
    if (!px)
        return;
    uint32_t counts[3] = {0, 0, 0};
    check_pixels("point", px, point_expected, counts);
    /* the law itself: E(r = 0.5) / E(r = 1) = ((1 + 1) / (1 + 0.25))^(3/2) */
    CHECK_NEAR(point_expected(0.5) / point_expected(1.0), pow(2.0 / 1.25, 1.5), 1e-12);
    free(px);
}

/* Directional lights: intensities 2 (straight down), 3 (60 deg off), 1 (30 deg off). */
#define T_DIR_E2 (2.0 + 3.0 * 0.5)
#define T_DIR_E3 (T_DIR_E2 + 1.0 * 0.86602540)

static double dir2_expected(double r)
{
    return (void)r, T_DIR_E2;
}

static void test_directional_lights_add(void)
{
    const char *lights = "[{\"type\":\"directional\",\"intensity\":2},"
                         "{\"type\":\"directional\",\"intensity\":3},"
                         "{\"type\":\"directional\",\"intensity\":1}]";
    const char *nodes2 =
        "{\"rotation\":" T_ROT_DOWN ",\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
        "{\"rotation\":" T_ROT_60 ",\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}}";
    char nodes3[512];
    snprintf(nodes3, sizeof nodes3,
             "%s,{\"rotation\":" T_ROT_30
             ",\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}}",
             nodes2);
    /* two: the sun and one buffer light, both deterministic: every pixel exact */
    xrsc_scene *scene = t_scene_load(g_ctx, plane_scene("lights_dir2.gltf", lights, nodes2, 2));
    if (!scene)
        return;
    float *px = render(scene, XRSC_METHOD_SPP, 3);
    xrsc_scene_destroy(&scene);
    if (px) {
        uint32_t counts[3] = {0, 0, 0};
        check_pixels("two directional", px, dir2_expected, counts);
    }
    free(px);
    /* three: two in the buffer, one picked per vertex: the mean within T_SIGMAS errors */
    scene = t_scene_load(g_ctx, plane_scene("lights_dir3.gltf", lights, nodes3, 3));
    if (!scene)
        return;
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    CHECK_EQ_INT(info.light_count, 3); /* the sun and two in XS_BIND_LIGHTS */
    px = render(scene, XRSC_METHOD_SPP, 4);
    xrsc_scene_destroy(&scene);
    if (!px)
        return;
    uint32_t n = 2 * T_SIZE * T_SIZE;
    double sum = 0.0, sum2 = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        double v = irradiance(px, i);
        sum += v, sum2 += v * v;
    }
    double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / n);
    printf("  three directional: mean E %.5f +- %.5f, expected %.5f\n", mean, se, T_DIR_E3);
    CHECK_MSG(fabs(mean - T_DIR_E3) <= T_SIGMAS * se + T_ABS_TOL, "mean %.5f", mean);
    CHECK(se > 0.0); /* a pick per vertex: the pixels vary (else the estimator is not one) */
    free(px);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_spot_cone_falloff);
    RUN(test_point_inverse_square);
    RUN(test_directional_lights_add);
    t_context_close(&g_ctx);
    return t_finish();
}
