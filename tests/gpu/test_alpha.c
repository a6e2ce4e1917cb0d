// SPDX-License-Identifier: MIT
/**
 * @file test_alpha.c
 * @brief Issue 18 item 1 on the GPU: glTF alphaMode MASK and BLEND (any-hit shader on every
 *        ray type) and doubleSided (single-sided back faces culled for camera rays).
 *
 * Scene (written here): a 2 m square at z = -2 in front of a 20 m wall at z = -4, both facing
 * +Z, seen from the origin (both eyes at the origin, symmetric FOV of half-angle tangent
 * T_TAN); a directional light shining along -Z (from behind the camera); environment 0;
 * IOR-1 dielectrics (pure Lambertian, xs_bsdf.glsl). The square's alpha is a 4 x 4
 * checkerboard texture (MASK, cutoff 0.5) or its base colour factor's alpha 0.5 (BLEND).
 * Each pixel is classified on the CPU from its camera ray: where it meets the square (in a
 * solid cell or a hole) and whether the wall point it sees is in the square's shadow (the
 * sun's ray from it crosses the square in a solid cell); pixels within T_EDGE_MARGIN of a cell
 * edge (in cell units) are left out (texture filtering, sub-pixel coverage).
 *
 * Checks: `primary` shows the wall exactly behind every hole and the square's colour exactly
 * elsewhere; turned around, the single-sided square is culled and the double-sided one shows;
 * `spp` (1 spp through pixel centres, direct light only) has the shadow with the holes, exact;
 * the sample cache after T_SC_FRAMES frames equals a T_REF_SPP-spp reference within T_SC_TOL per
 * region; BLEND with coverage 0.5 converges to the 50 % mix (primary averaged over frames,
 * and spp with the wall's half shadow), within the tolerances stated at each check.
 * Runs under the validation layer.
 */
#include "t_context.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <png.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_W 48u
#define T_H 48u
#define T_TAN 0.75 /* tan of the FOV's half-angle, all four sides */
#define T_QUAD_Z 2.0
#define T_WALL_Z 4.0
#define T_CELLS 4
#define T_EDGE_MARGIN 0.15 /* cell units */
#define T_SUN_LUX 3.0
#define T_PI 3.14159265358979323846
#define T_SC_FRAMES 16u
#define T_BLEND_FRAMES 64u
#define T_REF_SPP 128u /* samples per pixel of the spp references */

static const double k_quad[3] = {0.2, 0.8, 0.3};
static const double k_wall[3] = {0.8, 0.3, 0.2};
static xrsc_context *g_ctx;

/** Where a pixel's camera ray goes. */
typedef enum { PX_EDGE, PX_SOLID, PX_HOLE, PX_OUTSIDE } px_kind;

/** Cell of point (x, y) on the square (quad spans [-1, 1]^2, u = (x + 1) / 2, v = (1 - y) / 2):
 *  PX_SOLID / PX_HOLE by checkerboard parity, PX_OUTSIDE, or PX_EDGE near a cell edge. */
static px_kind cell_at(double x, double y, bool mirrored)
{
    if (mirrored)
        x = -x;
    double cu = (x + 1.0) * 0.5 * T_CELLS, cv = (1.0 - y) * 0.5 * T_CELLS;
    double fu = cu - floor(cu), fv = cv - floor(cv);
    if (cu > -T_EDGE_MARGIN && cu < T_CELLS + T_EDGE_MARGIN && cv > -T_EDGE_MARGIN &&
        cv < T_CELLS + T_EDGE_MARGIN &&
        (fu < T_EDGE_MARGIN || fu > 1.0 - T_EDGE_MARGIN || fv < T_EDGE_MARGIN ||
         fv > 1.0 - T_EDGE_MARGIN))
        return PX_EDGE;
    if (cu < 0.0 || cu >= T_CELLS || cv < 0.0 || cv >= T_CELLS)
        return PX_OUTSIDE;
    return (((int)cu + (int)cv) & 1) ? PX_SOLID : PX_HOLE; /* texel alpha 255 where odd */
}

/** Pixel (x, y): what the camera ray meets at the square, and (wall) whether the wall point it
 *  sees is shadowed by a solid cell (PX_SOLID), lit through a hole or past the square. */
static px_kind classify(uint32_t x, uint32_t y, bool mirrored, px_kind *wall)
{
    double dx = T_TAN * (2.0 * (x + 0.5) / T_W - 1.0), dy = T_TAN * (1.0 - 2.0 * (y + 0.5) / T_H);
    *wall = cell_at(T_WALL_Z * dx, T_WALL_Z * dy, mirrored);
    return cell_at(T_QUAD_Z * dx, T_QUAD_Z * dy, mirrored);
}

/** Writes the 4 x 4 RGBA checkerboard (white, alpha 0 / 255) with libpng. */
static bool write_checker_png(const char *path)
{
    uint8_t px[T_CELLS][T_CELLS * 4];
    for (int j = 0; j < T_CELLS; j++)
        for (int i = 0; i < T_CELLS; i++) {
            memset(&px[j][4 * i], 255, 3);
            px[j][4 * i + 3] = ((i + j) & 1) ? 255 : 0;
        }
    FILE *f = fopen(path, "wb");
    if (!f)
        return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    bool ok = png && info && !setjmp(png_jmpbuf(png));
    if (ok) {
        png_init_io(png, f);
        png_set_IHDR(png, info, T_CELLS, T_CELLS, 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        png_write_info(png, info);
        for (int j = 0; j < T_CELLS; j++)
            png_write_row(png, px[j]);
        png_write_end(png, NULL);
    }
    png_destroy_write_struct(&png, &info);
    fclose(f);
    return ok;
}

/** The unit square's buffer: 4 positions (z = 0), 4 uvs, 6 u16 indices + 4 bytes padding. */
static char *quad_uri(void)
{
    uint8_t b[96];
    const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const uint16_t idx[8] = {0, 1, 2, 0, 2, 3, 0, 0};
    memcpy(b, pos, 48);
    memcpy(b + 48, uv, 32);
    memcpy(b + 80, idx, 16);
    return t_data_uri(b, sizeof b);
}

/** Writes the scene: square material `mat` (JSON), turned to show its back when `turned`. */
static const char *write_scene(const char *name, const char *mat, bool turned)
{
    static char json[8192];
    char *uri = quad_uri();
    const char *png = t_temp_file("checker.png", "");
    const char *png_name = strrchr(png, '/') ? strrchr(png, '/') + 1 : png;
    CHECK(write_checker_png(png));
    snprintf(
        json, sizeof json,
        "{\"asset\": {\"version\": \"2.0\"},"
        " \"extensionsUsed\": [\"KHR_lights_punctual\", \"KHR_materials_ior\"],"
        " \"extensions\": {\"KHR_lights_punctual\": {\"lights\": [{\"type\": \"directional\","
        " \"intensity\": %.17g}]}},"
        " \"scenes\": [{\"nodes\": [0, 1, 2]}],"
        " \"nodes\": [{\"mesh\": 1, \"translation\": [0, 0, %g], \"scale\": [10, 10, 1]},"
        " {\"mesh\": 0, \"translation\": [0, 0, %g]%s},"
        " {\"extensions\": {\"KHR_lights_punctual\": {\"light\": 0}}}],"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1},"
        " \"indices\": 2, \"material\": 0}]},"
        " {\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 2, \"material\": "
        "1}]}],"
        " \"materials\": [%s, {\"pbrMetallicRoughness\": {\"baseColorFactor\": [%g, %g, %g, 1],"
        " \"metallicFactor\": 0, \"roughnessFactor\": 1},"
        " \"extensions\": {\"KHR_materials_ior\": {\"ior\": 1.0}}}],"
        " \"images\": [{\"uri\": \"%s\"}], \"textures\": [{\"source\": 0}],"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": "
        "\"VEC3\","
        " \"min\": [-1, -1, 0], \"max\": [1, 1, 0]},"
        " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
        " {\"bufferView\": 2, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}],"
        " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": "
        "48,"
        " \"byteLength\": 32}, {\"buffer\": 0, \"byteOffset\": 80, \"byteLength\": 12}],"
        " \"buffers\": [{\"byteLength\": 96, \"uri\": \"%s\"}]}",
        T_SUN_LUX, -T_WALL_Z, -T_QUAD_Z, turned ? ", \"rotation\": [0, 1, 0, 0]" : "", mat,
        k_wall[0], k_wall[1], k_wall[2], png_name, uri);
    free(uri);
    return t_temp_file(name, json);
}

/** The square's material: MASK (checkerboard alpha) or BLEND (factor alpha 0.5). */
static const char *square_material(bool blend, bool double_sided)
{
    static char m[1024];
    snprintf(m, sizeof m,
             "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [%g, %g, %g, %s],%s"
             " \"metallicFactor\": 0, \"roughnessFactor\": 1}, \"alphaMode\": \"%s\","
             " \"doubleSided\": %s, \"extensions\": {\"KHR_materials_ior\": {\"ior\": 1.0}}}",
             k_quad[0], k_quad[1], k_quad[2], blend ? "0.5" : "1",
             blend ? "" : " \"baseColorTexture\": {\"index\": 0},", blend ? "BLEND" : "MASK",
             double_sided ? "true" : "false");
    return m;
}

/** Renders `frames` frames of `path` with options ro (size set here) and returns eye 0's
 *  colour (RGBA floats, malloc'ed): the last frame's, or with `average` the mean of all. */
static float *render(const char *path, xrsc_renderer_options ro, uint32_t frames, bool average)
{
    char buf[1024];
    xrsc_diag d;
    xrsc_scene *scene = NULL;
    xrsc_result r = xrsc_scene_load(g_ctx, path, NULL, &scene, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    if (r != XRSC_OK)
        return NULL;
    ro.width = T_W;
    ro.height = T_H;
    xrsc_renderer *rend = NULL;
    r = xrsc_renderer_create(g_ctx, scene, &ro, &rend, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    size_t n = (size_t)T_W * T_H * 4;
    float *img = calloc(n, sizeof(float)), *c = malloc(n * sizeof(float));
    bool ok = r == XRSC_OK && img && c;
    xrsc_frame frame;
    memset(&frame, 0, sizeof frame);
    for (int e = 0; e < 2; e++) {
        frame.views[e].pose = xrsc_pose_identity();
        frame.views[e].fov = (XrFovf){-atanf((float)T_TAN), atanf((float)T_TAN),
                                      atanf((float)T_TAN), -atanf((float)T_TAN)};
    }
    for (uint32_t f = 0; ok && f < frames; f++) {
        frame.frame_index = f;
        ok = xrsc_renderer_render(rend, &frame) == XRSC_OK &&
             xrsc_renderer_read(rend, 0, XRSC_OUTPUT_COLOR, c, n * sizeof(float)) == XRSC_OK;
        for (size_t i = 0; ok && i < n; i++)
            img[i] = average ? img[i] + c[i] / (float)frames : c[i];
    }
    CHECK(ok);
    free(c);
    xrsc_renderer_destroy(&rend);
    xrsc_scene_destroy(&scene);
    if (!ok) {
        free(img);
        return NULL;
    }
    return img;
}

/** Largest |img - want| over channels 0..2 of pixel p. */
static double px_err(const float *img, uint32_t p, const double want[3])
{
    double e = 0.0;
    for (int k = 0; k < 3; k++)
        e = fmax(e, fabs(img[4 * p + k] - want[k]));
    return e;
}

static xrsc_renderer_options primary_options(void)
{
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY};
    return ro;
}

/** MASK in `primary`: the wall's colour exactly behind every hole (and past the square), the
 *  square's colour exactly on every solid cell. */
static void test_mask_primary(void)
{
    float *img = render(write_scene("mask.gltf", square_material(false, false), false),
                        primary_options(), 1, false);
    if (!img)
        return;
    uint32_t holes = 0, solid = 0, bad = 0;
    double worst = 0.0;
    for (uint32_t y = 0; y < T_H; y++)
        for (uint32_t x = 0; x < T_W; x++) {
            px_kind wall, k = classify(x, y, false, &wall);
            if (k == PX_EDGE)
                continue;
            double e = px_err(img, y * T_W + x, k == PX_SOLID ? k_quad : k_wall);
            holes += k == PX_HOLE;
            solid += k == PX_SOLID;
            bad += e > 1e-6;
            worst = fmax(worst, e);
        }
    printf("mask primary: %u hole pixels show the wall, %u solid pixels the square; %u differ "
           "(largest difference %.3g)\n",
           holes, solid, bad, worst);
    CHECK(holes > 50 && solid > 50);
    CHECK_EQ_INT(bad, 0);
    free(img);
}

/** doubleSided: the square turned around (its back to the camera) is culled when single-sided
 *  (the wall shows everywhere) and shows its checkerboard when double-sided. */
static void test_double_sided(void)
{
    for (int ds = 0; ds < 2; ds++) {
        float *img = render(write_scene(ds ? "turned_ds.gltf" : "turned.gltf",
                                        square_material(false, ds != 0), true),
                            primary_options(), 1, false);
        if (!img)
            return;
        uint32_t solid = 0, bad = 0;
        for (uint32_t y = 0; y < T_H; y++)
            for (uint32_t x = 0; x < T_W; x++) {
                px_kind wall, k = classify(x, y, true, &wall);
                if (k == PX_EDGE)
                    continue;
                solid += k == PX_SOLID;
                bad += px_err(img, y * T_W + x, ds && k == PX_SOLID ? k_quad : k_wall) > 1e-6;
            }
        printf("turned square, doubleSided %s: %u pixels differ from the expected (of %u solid "
               "cell pixels)\n",
               ds ? "true" : "false", bad, solid);
        CHECK(solid > 50);
        CHECK_EQ_INT(bad, 0);
        free(img);
    }
}

/** Expected direct-light radiance (Lambertian, sun at normal incidence) of colour c. */
static void lit(const double c[3], double scale, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = scale * c[k] / T_PI * T_SUN_LUX;
}

/** MASK in `spp`, 1 spp through pixel centres, direct light only (deterministic): the
 *  square's shadow on the wall has the holes, every classified pixel exact. */
static float *test_mask_shadow_spp(const char *path)
{
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SPP};
    ro.spp.samples_per_pixel = 1;
    ro.spp.no_jitter = true;
    ro.spp.max_bounces = 1;
    float *img = render(path, ro, 1, false);
    if (!img)
        return NULL;
    uint32_t through_holes = 0, shadowed = 0, bad = 0;
    double worst = 0.0, quad_lit[3], wall_lit[3], zero[3] = {0, 0, 0};
    lit(k_quad, 1.0, quad_lit);
    lit(k_wall, 1.0, wall_lit);
    for (uint32_t y = 0; y < T_H; y++)
        for (uint32_t x = 0; x < T_W; x++) {
            px_kind wall, k = classify(x, y, false, &wall);
            if (k == PX_EDGE || (k != PX_SOLID && wall == PX_EDGE))
                continue;
            const double *want = k == PX_SOLID ? quad_lit : wall == PX_SOLID ? zero : wall_lit;
            through_holes += k != PX_SOLID && wall == PX_HOLE;
            shadowed += k != PX_SOLID && wall == PX_SOLID;
            double e = px_err(img, y * T_W + x, want);
            bad += e > 1e-4 * wall_lit[0];
            worst = fmax(worst, e);
        }
    printf("mask spp: %u wall pixels lit through holes of the shadow, %u in shadow; %u differ "
           "(largest difference %.3g)\n",
           through_holes, shadowed, bad, worst);
    CHECK(through_holes >= 10 && shadowed >= 10);
    CHECK_EQ_INT(bad, 0);
    return img;
}

/** Per-region means (sum of rgb) of an image: 0 square, 1 wall lit through holes, 2 wall in
 *  the square's shadow, 3 wall past the square. */
static void region_means(const float *img, double mean[4])
{
    double sum[4] = {0}, n[4] = {0};
    for (uint32_t y = 0; y < T_H; y++)
        for (uint32_t x = 0; x < T_W; x++) {
            px_kind wall, k = classify(x, y, false, &wall);
            if (k == PX_EDGE || (k != PX_SOLID && wall == PX_EDGE))
                continue;
            int r = k == PX_SOLID ? 0 : wall == PX_HOLE ? 1 : wall == PX_SOLID ? 2 : 3;
            const float *c = &img[4 * (y * T_W + x)];
            sum[r] += c[0] + c[1] + c[2];
            n[r]++;
        }
    for (int r = 0; r < 4; r++)
        mean[r] = n[r] > 0 ? sum[r] / n[r] : -1.0;
}

/* Sample cache vs spp reference, per region mean (sum of rgb), as a fraction of the lit
 * wall's value: the cache's own noise after T_SC_FRAMES frames is a few 0.1 % here. */
#define T_SC_TOL 0.03

/** The sample cache (default options, T_SC_FRAMES still frames) equals a T_REF_SPP-spp reference
 *  (full path tracing, jittered) within T_SC_TOL per region. */
static void test_mask_samplecache(const char *path)
{
    xrsc_renderer_options rs = {.method = XRSC_METHOD_SPP};
    rs.spp.samples_per_pixel = T_REF_SPP;
    xrsc_renderer_options rc = {.method = XRSC_METHOD_SAMPLECACHE};
    float *ref = render(path, rs, 1, false);
    float *sc = render(path, rc, T_SC_FRAMES, false);
    if (ref && sc) {
        double mr[4], ms[4], wall_lit[3];
        lit(k_wall, 1.0, wall_lit);
        double scale = wall_lit[0] + wall_lit[1] + wall_lit[2];
        region_means(ref, mr);
        region_means(sc, ms);
        for (int r = 0; r < 4; r++) {
            printf("region %d: spp %.5f, samplecache %.5f (difference %.2f %% of the lit wall)\n",
                   r, mr[r], ms[r], 100.0 * fabs(mr[r] - ms[r]) / scale);
            CHECK(mr[r] >= 0.0);
            CHECK(fabs(mr[r] - ms[r]) <= T_SC_TOL * scale);
        }
        CHECK(mr[1] > 0.5 * scale && mr[2] < 0.1 * scale); /* light through holes, shadow */
    }
    free(ref);
    free(sc);
}

static void test_mask_spp_and_samplecache(void)
{
    const char *path = write_scene("mask_lit.gltf", square_material(false, false), false);
    free(test_mask_shadow_spp(path));
    test_mask_samplecache(path);
}

/** BLEND, coverage 0.5, in `primary` averaged over T_BLEND_FRAMES frames: each frame shows the
 *  square or the wall at random, the mean converges to the 50 % mix: region mean within 0.01,
 *  every pixel within 5 sigma of a binomial mean (sigma = 0.5 |square - wall| / sqrt(frames)). */
static void test_blend_primary(const char *path)
{
    float *img = render(path, primary_options(), T_BLEND_FRAMES, true);
    if (!img)
        return;
    double sum[3] = {0}, worst_sigma = 0.0, lo = 1e30, hi = -1e30;
    uint32_t n = 0, bad_outside = 0;
    for (uint32_t y = 0; y < T_H; y++)
        for (uint32_t x = 0; x < T_W; x++) {
            px_kind wall, k = classify(x, y, false, &wall);
            uint32_t p = y * T_W + x;
            if (k == PX_OUTSIDE)
                bad_outside += px_err(img, p, k_wall) > 1e-6;
            if (k != PX_SOLID && k != PX_HOLE)
                continue;
            for (int c = 0; c < 3; c++) {
                double want = 0.5 * (k_quad[c] + k_wall[c]);
                double sigma = 0.5 * fabs(k_quad[c] - k_wall[c]) / sqrt((double)T_BLEND_FRAMES);
                sum[c] += img[4 * p + c];
                worst_sigma = fmax(worst_sigma, fabs(img[4 * p + c] - want) / sigma);
            }
            lo = fmin(lo, img[4 * p]);
            hi = fmax(hi, img[4 * p]);
            n++;
        }
    printf("blend primary: %u pixels, mean %.4f %.4f %.4f (50 %% mix %.4f %.4f %.4f), worst "
           "pixel %.2f sigma, red from %.3f to %.3f\n",
           n, sum[0] / n, sum[1] / n, sum[2] / n, 0.5 * (k_quad[0] + k_wall[0]),
           0.5 * (k_quad[1] + k_wall[1]), 0.5 * (k_quad[2] + k_wall[2]), worst_sigma, lo, hi);
    CHECK(n > 200);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(sum[c] / n, 0.5 * (k_quad[c] + k_wall[c]), 0.01);
    CHECK(worst_sigma <= 5.0);
    CHECK(hi - lo > 0.05); /* stochastic per pixel, not one decision for all */
    CHECK_EQ_INT(bad_outside, 0);
    free(img);
}

/** Expected direct light of a pixel on the BLEND square (coverage 0.5): half the lit square,
 *  half the wall behind it, which the square's half shadow halves again. */
static double blend_expected(px_kind wall, int c)
{
    double behind = wall == PX_SOLID || wall == PX_HOLE ? 0.5 : 1.0;
    return (0.5 * k_quad[c] + 0.5 * behind * k_wall[c]) / T_PI * T_SUN_LUX;
}

/* Region mean of a T_REF_SPP-spp or sample-cache image vs blend_expected, relative. */
#define T_BLEND_SPP_TOL 0.015
#define T_BLEND_SC_TOL 0.05

/** Mean over the pixels on the square of img / expected - 1 (rgb summed). */
static double blend_rel_error(const float *img)
{
    double got = 0.0, want = 0.0;
    for (uint32_t y = 0; y < T_H; y++)
        for (uint32_t x = 0; x < T_W; x++) {
            px_kind wall, k = classify(x, y, false, &wall);
            if ((k != PX_SOLID && k != PX_HOLE) || wall == PX_EDGE)
                continue;
            for (int c = 0; c < 3; c++) {
                got += img[4 * (y * T_W + x) + c];
                want += blend_expected(wall, c);
            }
        }
    return got / want - 1.0;
}

/** BLEND in `spp` (T_REF_SPP spp, direct light) and in the sample cache (T_SC_FRAMES frames, direct
 *  light): both converge to the blend, shadows included. */
static void test_blend_lit(const char *path)
{
    xrsc_renderer_options rs = {.method = XRSC_METHOD_SPP};
    rs.spp.samples_per_pixel = T_REF_SPP;
    rs.spp.max_bounces = 1;
    xrsc_renderer_options rc = {.method = XRSC_METHOD_SAMPLECACHE};
    rc.samplecache.max_bounces = 1;
    float *ref = render(path, rs, 1, false);
    float *sc = render(path, rc, T_SC_FRAMES, false);
    if (ref && sc) {
        double es = blend_rel_error(ref), ec = blend_rel_error(sc);
        printf("blend lit: spp %+.2f %%, samplecache %+.2f %% from the blended expectation\n",
               100.0 * es, 100.0 * ec);
        CHECK(fabs(es) <= T_BLEND_SPP_TOL);
        CHECK(fabs(ec) <= T_BLEND_SC_TOL);
    }
    free(ref);
    free(sc);
}

static void test_blend(void)
{
    const char *path = write_scene("blend.gltf", square_material(true, false), false);
    test_blend_primary(path);
    test_blend_lit(path);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_mask_primary);
    RUN(test_double_sided);
    RUN(test_mask_spp_and_samplecache);
    RUN(test_blend);
    t_context_close(&g_ctx);
    return t_finish();
}
