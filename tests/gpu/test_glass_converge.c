// SPDX-License-Identifier: MIT
/**
 * @file test_glass_converge.c
 * @brief Transmission that converges (issue 18, item 3), on the GPU under the validation layer:
 *        light through two thin glass walls against its analytic value, in `spp` and in the
 *        sample cache, and the sample cache's glass pixels converging under a still view.
 *
 * Scene: a Lambertian wall (albedo T_ALBEDO, IOR 1) at z = -3 and two smooth thin-walled glass
 * panes (KHR_materials_transmission 1, IOR 1.5, tint T_TINT, doubleSided) at z = -1 and z =
 * -1.5, one directional light of irradiance T_E shining along the view (-Z), environment 0,
 * max_bounces 1: the camera ray's straight passes through the two panes are not bounces
 * (xs_path.glsl), so the path reaches the wall, samples the light there and traces one
 * bounce ray whose hit adds no emission (no indirect light; counted as bounces, the passes
 * would leave the wall unreached: black). Glass is thin: straight through, weight
 * (1 - F(cos)) tint per wall (F the exact dielectric Fresnel, seen at the same cosine on both
 * panes). A wall pixel seen through both panes has radiance E albedo / pi x prod over the panes
 * whose shadow it is in of (1 - F(1)) tint (the shadow ray passes each, xs_path.glsl) x ((1 -
 * F(cos)) tint)^2. Without the shadow rule it is black, with one wall's weight or a lost tint it is
 * off by 4 % or more per channel; `spp` (16 spp x 2 eyes) must match within T_SIGMAS
 * standard errors + T_REL_TOL per region.
 *
 * Sample cache, still view: the only noise on those pixels is the camera path's Fresnel choice
 * at each pane (reflection: black). App. C's clamp (alpha >= 0.5 for smooth glass) would keep
 * a two-frame history for ever; it now follows the view's motion (xs_sc_view_motion), so a
 * still view accumulates. Asserted: the relMSE of the glass pixels against the analytic value
 * after T_LATE frames is below T_CONVERGE times that after T_EARLY frames (a running mean
 * gives about T_EARLY / T_LATE; the clamp about 1), and the region means match the analytic
 * value within T_SC_TOL; and that relMSE is below T_VS_CLAMP times that of the same run with
 * the old behaviour (alpha fixed at App. C's 0.5 for smooth glass). The rule itself
 * (xs_sc_view_motion, xs_sc_alpha_min_glass) is checked on the CPU first: no clamp on glass under a
 * still view, App. C's in full from XS_SC_VIEW_MOTION_PIXELS of a pixel per frame, metal's clamp
 * untouched.
 */
#include "t_context.h"
#include "t_optics.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xs_sc_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 32u
#define T_SPP 16u
#define T_HALF_FOV 0.3f /* rad */
#define T_PI 3.14159265358979323846
#define T_ALBEDO 0.5
#define T_E 2.0 /* the directional light's irradiance */
#define T_IOR 1.5
#define T_WALL_Z 3.0   /* the wall's distance */
#define T_MARGIN 0.015 /* pixels whose ray is this close (tan units) to an edge are skipped */
#define T_SIGMAS 5.0
#define T_REL_TOL 0.01
#define T_SC_TOL 0.05
#define T_EARLY 2u
#define T_LATE 32u
#define T_SLOTS 4u /* few slots, so each is shaded often enough for its history to matter */
#define T_CONVERGE 0.5
#define T_VS_CLAMP 0.7
#define T_PANES 2
static const double T_TINT[3] = {0.9, 0.6, 0.3};
/* the panes: distance and half size; the near one bounds what is seen through both */
static const double T_PANE_Z[T_PANES] = {1.0, 1.5}, T_PANE_HALF[T_PANES] = {0.25, 0.45};

static xrsc_context *g_ctx;

/* regions: seen through both panes, with the shadow of none, one (the far pane's, larger) or
 * both on the wall there */
enum { R_LIT, R_ONE_SHADOW, R_TWO_SHADOWS, R_COUNT };
static const char *const R_NAMES[R_COUNT] = {"through both, lit", "through both, one shadow",
                                             "through both, two shadows"};

/** True when |a| is within T_MARGIN of the edge at e. */
static bool near_edge(double a, double e)
{
    return fabs(a - e) < T_MARGIN;
}

/** Region of pixel (x, y) and its expected radiance in channel c; -1 for pixels not seen
 *  through both panes or near an edge (a pane's or a shadow's). */
static int pixel_want(uint32_t x, uint32_t y, int c, double *out_want)
{
    double t = tan((double)T_HALF_FOV);
    double tx = (2.0 * (x + 0.5) / T_SIZE - 1.0) * t, ty = (2.0 * (y + 0.5) / T_SIZE - 1.0) * t;
    double ax = fabs(tx), ay = fabs(ty), cos_cam = 1.0 / sqrt(1.0 + tx * tx + ty * ty);
    double l = T_E * T_ALBEDO / T_PI;
    int shadows = 0;
    for (int k = 0; k < T_PANES; k++) {
        double through = T_PANE_HALF[k] / T_PANE_Z[k], shadow = T_PANE_HALF[k] / T_WALL_Z;
        if (near_edge(ax, through) || near_edge(ay, through) || near_edge(ax, shadow) ||
            near_edge(ay, shadow) || ax > through || ay > through)
            return -1;
        l *= (1.0 - t_fresnel(cos_cam, T_IOR)) * T_TINT[c];
        if (ax < shadow && ay < shadow) {
            l *= (1.0 - t_fresnel(1.0, T_IOR)) * T_TINT[c];
            shadows++;
        }
    }
    *out_want = l;
    return shadows; /* R_LIT, R_ONE_SHADOW, R_TWO_SHADOWS */
}

/** Appends quad k (4 corners at depth -z, half sizes hx, hy) to the vertex and index data. */
static void put_quad(float *pos, uint16_t *idx, int k, double z, double h)
{
    static const int sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    static const uint16_t tri[6] = {0, 1, 2, 0, 2, 3};
    for (int v = 0; v < 4; v++) {
        pos[12 * k + 3 * v + 0] = (float)(sx[v] * h);
        pos[12 * k + 3 * v + 1] = (float)(sy[v] * h);
        pos[12 * k + 3 * v + 2] = (float)-z;
    }
    for (int i = 0; i < 6; i++)
        idx[6 * k + i] = tri[i];
}

/** The wall and the two panes as one glTF (written to a temporary file). */
static const char *scene_path(void)
{
    enum { QUADS = 1 + T_PANES };
    float pos[QUADS * 12];
    uint16_t idx[QUADS * 6];
    put_quad(pos, idx, 0, T_WALL_Z, 3.0);
    for (int k = 0; k < T_PANES; k++)
        put_quad(pos, idx, 1 + k, T_PANE_Z[k], T_PANE_HALF[k]);
    uint8_t bytes[sizeof pos + sizeof idx];
    memcpy(bytes, pos, sizeof pos);
    memcpy(bytes + sizeof pos, idx, sizeof idx);
    char *uri = t_data_uri(bytes, sizeof bytes);
    size_t cap = strlen(uri) + 8192, n = 0;
    char *json = malloc(cap);
    n += (size_t)snprintf(
        json + n, cap - n,
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1,2,3],"
        "\"extras\":{\"xrsc_environment\":[0,0,0]}}],"
        "\"nodes\":[{\"mesh\":0},{\"mesh\":1},{\"mesh\":2},"
        "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}],"
        "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"directional\","
        "\"intensity\":%g}]}},\"extensionsUsed\":[\"KHR_materials_ior\","
        "\"KHR_materials_transmission\",\"KHR_lights_punctual\"],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[%g,%g,%g,1],"
        "\"metallicFactor\":0,\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_ior\":"
        "{\"ior\":1}}},{\"pbrMetallicRoughness\":{\"baseColorFactor\":[%g,%g,%g,1],"
        "\"metallicFactor\":0,\"roughnessFactor\":0},\"doubleSided\":true,\"extensions\":{"
        "\"KHR_materials_transmission\":{\"transmissionFactor\":1},\"KHR_materials_ior\":"
        "{\"ior\":%g}}}],\"meshes\":[",
        T_E, T_ALBEDO, T_ALBEDO, T_ALBEDO, T_TINT[0], T_TINT[1], T_TINT[2], T_IOR);
    for (int k = 0; k < QUADS; k++)
        n += (size_t)snprintf(json + n, cap - n,
                              "%s{\"primitives\":[{\"attributes\":{\"POSITION\":%d},\"indices\":"
                              "%d,\"material\":%d}]}",
                              k ? "," : "", 2 * k, 2 * k + 1, k ? 1 : 0);
    n += (size_t)snprintf(json + n, cap - n,
                          "],\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],\"bufferViews\":[",
                          sizeof bytes, uri);
    for (int k = 0; k < QUADS; k++)
        n += (size_t)snprintf(json + n, cap - n,
                              "%s{\"buffer\":0,\"byteOffset\":%d,\"byteLength\":48},"
                              "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":12}",
                              k ? "," : "", 48 * k, sizeof pos + 12u * (size_t)k);
    n += (size_t)snprintf(json + n, cap - n, "],\"accessors\":[");
    for (int k = 0; k < QUADS; k++) {
        const float *p = &pos[12 * k];
        n += (size_t)snprintf(json + n, cap - n,
                              "%s{\"bufferView\":%d,\"componentType\":5126,\"count\":4,\"type\":"
                              "\"VEC3\",\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]},"
                              "{\"bufferView\":%d,\"componentType\":5123,\"count\":6,"
                              "\"type\":\"SCALAR\"}",
                              k ? "," : "", 2 * k, p[0], p[1], p[2], p[6], p[7], p[8], 2 * k + 1);
    }
    snprintf(json + n, cap - n, "]}");
    free(uri);
    const char *path = t_temp_file("glass_two_panes.gltf", json);
    free(json);
    return path;
}

/** Both eyes at the origin looking down -Z with a symmetric square frustum. */
static xrsc_frame make_frame(void)
{
    xrsc_frame f;
    memset(&f, 0, sizeof(f));
    for (int e = 0; e < 2; e++) {
        f.views[e].pose.orientation.w = 1.0f;
        f.views[e].fov.angleLeft = f.views[e].fov.angleDown = -T_HALF_FOV;
        f.views[e].fov.angleRight = f.views[e].fov.angleUp = T_HALF_FOV;
    }
    return f;
}

/** Per region: the mean of got / want over channels and pixels, its standard error, and the
 *  mean of (got / want - 1)^2 (the relMSE against the analytic value). */
static void regions(const float *px, double mean[R_COUNT], double se[R_COUNT],
                    double rel_mse[R_COUNT], uint32_t n[R_COUNT])
{
    double s1[R_COUNT] = {0}, s2[R_COUNT] = {0}, e2[R_COUNT] = {0};
    memset(n, 0, sizeof(uint32_t) * R_COUNT);
    for (uint32_t e = 0; e < 2; e++)
        for (uint32_t y = 0; y < T_SIZE; y++)
            for (uint32_t x = 0; x < T_SIZE; x++)
                for (int c = 0; c < 3; c++) {
                    double want;
                    int r = pixel_want(x, y, c, &want);
                    if (r < 0)
                        continue;
                    double v = px[4 * ((e * T_SIZE + y) * T_SIZE + x) + c] / want;
                    s1[r] += v, s2[r] += v * v, e2[r] += (v - 1.0) * (v - 1.0), n[r]++;
                }
    for (int r = 0; r < R_COUNT; r++) {
        mean[r] = n[r] ? s1[r] / n[r] : 0.0;
        se[r] = n[r] ? sqrt(fmax(s2[r] / n[r] - mean[r] * mean[r], 0.0) / n[r]) : 0.0;
        rel_mse[r] = n[r] ? e2[r] / n[r] : 0.0;
    }
}

/** Renders `frames` frames of the still view; reads both eyes after frame `early` into
 *  early_px (when not NULL) and after the last into the returned buffer (malloc'ed). */
static float *render(xrsc_scene *scene, xrsc_method method, uint32_t frames, uint32_t early,
                     float *early_px, float alpha_fixed)
{
    xrsc_renderer_options o = {0};
    o.method = method;
    o.width = o.height = T_SIZE;
    o.seed = 3;
    o.spp.samples_per_pixel = T_SPP;
    o.spp.no_jitter = true; /* the analytic value is the pixel centre's */
    o.spp.max_bounces = 1;
    o.samplecache.max_bounces = 1;
    o.samplecache.slots = T_SLOTS;
    if (alpha_fixed > 0.0f) { /* App. C's clamp of smooth glass on every sample, as before */
        o.samplecache.alpha = XRSC_SC_ALPHA_FIXED;
        o.samplecache.alpha_fixed = alpha_fixed;
    }
    xrsc_renderer *r = NULL;
    xrsc_diag d = {0};
    xrsc_result res = xrsc_renderer_create(g_ctx, scene, &o, &r, &d);
    CHECK_MSG(res == XRSC_OK, "renderer: %s", d.message);
    if (res != XRSC_OK)
        return NULL;
    size_t bytes = (size_t)T_SIZE * T_SIZE * 4 * sizeof(float);
    float *px = malloc(2 * bytes);
    xrsc_frame f = make_frame();
    for (uint32_t i = 1; i <= frames && res == XRSC_OK; i++) {
        f.frame_index = i; /* a new random stream per frame */
        res = xrsc_renderer_render(r, &f);
        float *dst = i == frames ? px : i == early ? early_px : NULL;
        for (uint32_t e = 0; e < 2 && res == XRSC_OK && dst; e++)
            res = xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, (char *)dst + e * bytes, bytes);
    }
    CHECK_EQ_INT(res, XRSC_OK);
    xrsc_renderer_destroy(&r);
    if (res != XRSC_OK) {
        free(px);
        return NULL;
    }
    return px;
}

static void test_two_panes(void)
{
    xrsc_scene *scene = NULL;
    xrsc_diag d = {0};
    const char *path = scene_path();
    xrsc_result r = xrsc_scene_load(g_ctx, path, NULL, &scene, &d);
    CHECK_MSG(r == XRSC_OK, "load %s: %s (%s)", path, xrsc_result_name(r), d.message);
    if (r != XRSC_OK)
        return;
    size_t bytes = 2 * (size_t)T_SIZE * T_SIZE * 4 * sizeof(float);
    float *early = malloc(bytes), *early_clamp = malloc(bytes);
    float *spp = render(scene, XRSC_METHOD_SPP, 1, 0, NULL, 0.0f);
    float *sc = render(scene, XRSC_METHOD_SAMPLECACHE, T_LATE, T_EARLY, early, 0.0f);
    float *clamp = render(scene, XRSC_METHOD_SAMPLECACHE, T_LATE, T_EARLY, early_clamp,
                          (float)XS_SC_ALPHA_MIN_SMOOTH);
    xrsc_scene_destroy(&scene);
    double mean[R_COUNT], se[R_COUNT], mse[R_COUNT];
    uint32_t n[R_COUNT];
    if (spp) {
        regions(spp, mean, se, mse, n);
        for (int k = 0; k < R_COUNT; k++) {
            printf("  spp, %s: radiance / expected %.4f +- %.4f (%u values)\n", R_NAMES[k], mean[k],
                   se[k], n[k]);
            CHECK(n[k] >= 24);
            CHECK_MSG(fabs(mean[k] - 1.0) <= T_SIGMAS * se[k] + T_REL_TOL, "%s: %.4f", R_NAMES[k],
                      mean[k]);
        }
    }
    if (sc) {
        double m_early[R_COUNT], se_early[R_COUNT], mse_early[R_COUNT];
        regions(early, m_early, se_early, mse_early, n);
        regions(sc, mean, se, mse, n);
        double all_early = 0.0, all_late = 0.0, all_n = 0.0; /* relMSE sums, values */
        for (int k = 0; k < R_COUNT; k++) {
            printf("  samplecache, %s: radiance / expected %.4f; relMSE frame %u %.5f, frame %u "
                   "%.5f\n",
                   R_NAMES[k], mean[k], T_EARLY, mse_early[k], T_LATE, mse[k]);
            CHECK_MSG(fabs(mean[k] - 1.0) <= T_SC_TOL, "%s: %.4f", R_NAMES[k], mean[k]);
            all_early += mse_early[k] * n[k], all_late += mse[k] * n[k], all_n += n[k];
        }
        printf("  samplecache, glass pixels: relMSE frame %u / frame %u = %.3f (limit %.2f)\n",
               T_LATE, T_EARLY, all_late / all_early, T_CONVERGE);
        CHECK(all_early > 0.0);
        CHECK_MSG(all_late < T_CONVERGE * all_early, "glass pixels do not converge: %.5f -> %.5f",
                  all_early, all_late);
        if (clamp) {
            double m_c[R_COUNT], se_c[R_COUNT], mse_c[R_COUNT], clamp_late = 0.0;
            regions(clamp, m_c, se_c, mse_c, n);
            for (int k = 0; k < R_COUNT; k++)
                clamp_late += mse_c[k] * n[k];
            printf("  samplecache, glass pixels at frame %u: relMSE %.5f; with App. C's clamp "
                   "(alpha >= %.2f) whatever the view does %.5f (ratio %.3f, limit %.2f)\n",
                   T_LATE, all_late / all_n, XS_SC_ALPHA_MIN_SMOOTH, clamp_late / all_n,
                   all_late / clamp_late, T_VS_CLAMP);
            CHECK_MSG(all_late < T_VS_CLAMP * clamp_late, "still view: %.5f, clamped %.5f",
                      all_late, clamp_late);
        }
    }
    free(early);
    free(early_clamp);
    free(clamp);
    free(spp);
    free(sc);
}

static void test_view_motion_rule(void)
{
    const float phi = 0.01f, step = (float)XS_SC_VIEW_MOTION_PIXELS * phi;
    CHECK_NEAR(xs_sc_view_motion(0.0f, phi), 0.0, 1e-7);
    CHECK_NEAR(xs_sc_view_motion(0.5f * step, phi), 0.5, 1e-6);
    CHECK_NEAR(xs_sc_view_motion(step, phi), 1.0, 1e-6);
    CHECK_NEAR(xs_sc_view_motion(100.0f * step, phi), 1.0, 1e-7);
    CHECK_NEAR(xs_sc_view_motion(0.0f, 0.0f), 1.0, 1e-7); /* no pixel size: App. C in full */
    /* smooth glass: 0 when still, App. C's 0.5 when moving */
    CHECK_NEAR(xs_sc_alpha_min_glass(0.0f, 1.0f, 0.0f, 0.0f), 0.0, 1e-7);
    CHECK_NEAR(xs_sc_alpha_min_glass(0.0f, 1.0f, 0.0f, 1.0f),
               xs_sc_alpha_min_material(0.0f, 1.0f, 0.0f), 1e-7);
    CHECK_NEAR(xs_sc_alpha_min_material(0.0f, 1.0f, 0.0f), XS_SC_ALPHA_MIN_SMOOTH, 1e-7);
    /* metal keeps its clamp whatever the view does; half metal half glass keeps the metal half */
    CHECK_NEAR(xs_sc_alpha_min_glass(1.0f, 0.0f, 0.3f, 0.0f),
               xs_sc_alpha_min_material(1.0f, 0.0f, 0.3f), 1e-7);
    CHECK_NEAR(xs_sc_alpha_min_glass(0.5f, 1.0f, 0.0f, 0.0f), 0.5 * XS_SC_ALPHA_MIN_SMOOTH, 1e-7);
}

int main(void)
{
    RUN(test_view_motion_rule);
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_two_panes);
    t_context_close(&g_ctx);
    return t_finish();
}
