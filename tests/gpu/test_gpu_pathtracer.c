// SPDX-License-Identifier: MIT
/**
 * @file test_gpu_pathtracer.c
 * @brief Correctness of the `spp` path tracer on the GPU: white furnaces with known answers,
 * bounce counting and Russian roulette, sample-count consistency, accumulation, determinism.
 *
 * Every case runs under the validation layer; the program fails if it reported any error.
 * Furnace spheres are generated here as flat-shaded glTF files (base64 data URI): with flat
 * normals a convex Lambertian sphere under a constant environment L has the exact radiance
 * rho L everywhere, and a closed Lambertian emitter seen from inside has exactly
 * Le (1 + rho + ... + rho^B) after B bounce rays, whatever the tessellation.
 *
 * Statistical tolerances: a pixel's value is a mean over n independent paths; the image mean
 * over P interior pixels (independent, same expectation) has standard error std(pixels) /
 * sqrt(P). Means are checked within T_SIGMAS standard errors plus a float allowance.
 */
#include "testing.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Standard errors allowed between a measured mean and its expectation (two-sided p ~ 6e-5). */
#define T_SIGMAS 4.0
/* |z| above which one pixel counts as an outlier, and the fraction of outliers allowed:
 * path-traced pixel values are skewed (rare long paths), so a few more than a normal
 * distribution's 6e-7 are expected; a wrong eye, stuck or NaN pixels give far more. */
#define T_OUTLIER_Z 5.0
#define T_OUTLIER_FRACTION 0.005
/* Float allowance of sums of many float samples (relative). */
#define T_FLOAT_REL 1e-3
/* Pixels within this many pixels of a silhouette are left out of surface/background masks. */
#define T_MASK_MARGIN 2
#define T_MISS 0xFFFFFFFFu
#define T_PI 3.14159265358979323846
/* Rays one path may trace per bounce: the bounce ray and two shadow rays (sun, emitter). */
#define T_RAYS_PER_BOUNCE 3

#define FURNACE_RHO 0.5
#define FURNACE_L 1.0

static xrsc_context *g_ctx;

/* ---------------------------------------------------------------------------------------- */
/* generated furnace spheres                                                                  */

typedef struct sphere_spec {
    const char *name; /* temp file name */
    float base[3];
    float metallic, roughness, transmission, ior;
    float emission; /* grey emissive factor, 0 = none */
    bool inward;    /* normals (and front faces) point to the centre */
    int rings, segments;
    float radius;
} sphere_spec;

static void sphere_point(float r, double theta, double phi, float out[3])
{
    out[0] = (float)(r * sin(theta) * cos(phi));
    out[1] = (float)(r * sin(theta) * sin(phi));
    out[2] = (float)(r * cos(theta));
}

/** Writes a flat-shaded UV sphere (poles on the z axis) as a .gltf file; returns its path. */
static const char *write_sphere_gltf(const sphere_spec *s)
{
    size_t max_tris = (size_t)s->rings * (size_t)s->segments * 2;
    float *pos = malloc(max_tris * 9 * sizeof(float));
    float *nrm = malloc(max_tris * 9 * sizeof(float));
    uint32_t vcount = 0;
    for (int i = 0; i < s->rings; i++) {
        double t0 = T_PI * i / s->rings, t1 = T_PI * (i + 1) / s->rings;
        for (int j = 0; j < s->segments; j++) {
            double p0 = 2 * T_PI * j / s->segments, p1 = 2 * T_PI * (j + 1) / s->segments;
            float q[4][3];
            sphere_point(s->radius, t0, p0, q[0]);
            sphere_point(s->radius, t1, p0, q[1]);
            sphere_point(s->radius, t1, p1, q[2]);
            sphere_point(s->radius, t0, p1, q[3]);
            const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (int k = 0; k < 2; k++) {
                const float *a = q[tri[k][0]], *b = q[tri[k][1]], *c = q[tri[k][2]];
                double e1[3], e2[3], n[3], cen[3];
                for (int d = 0; d < 3; d++) {
                    e1[d] = b[d] - a[d];
                    e2[d] = c[d] - a[d];
                    cen[d] = a[d] + b[d] + c[d];
                }
                n[0] = e1[1] * e2[2] - e1[2] * e2[1];
                n[1] = e1[2] * e2[0] - e1[0] * e2[2];
                n[2] = e1[0] * e2[1] - e1[1] * e2[0];
                double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                if (len < 1e-12)
                    continue; /* degenerate triangle at a pole */
                double outward = n[0] * cen[0] + n[1] * cen[1] + n[2] * cen[2];
                bool flip = (outward < 0) != s->inward;
                const float *v[3] = {a, flip ? c : b, flip ? b : c};
                double sign = flip ? -1.0 : 1.0;
                for (int m = 0; m < 3; m++) {
                    for (int d = 0; d < 3; d++) {
                        pos[vcount * 3 + d] = v[m][d];
                        nrm[vcount * 3 + d] = (float)(sign * n[d] / len);
                    }
                    vcount++;
                }
            }
        }
    }
    size_t pos_bytes = (size_t)vcount * 12, idx_bytes = (size_t)vcount * 4;
    size_t total = 2 * pos_bytes + idx_bytes;
    unsigned char *buf = malloc(total);
    memcpy(buf, pos, pos_bytes);
    memcpy(buf + pos_bytes, nrm, pos_bytes);
    for (uint32_t i = 0; i < vcount; i++)
        memcpy(buf + 2 * pos_bytes + 4 * (size_t)i, &i, 4);
    char *b64 = t_data_uri(buf, total);

    size_t json_cap = strlen(b64) + 4096;
    char *json = malloc(json_cap);
    float r = s->radius;
    snprintf(json, json_cap,
             "{\"asset\":{\"version\":\"2.0\"},"
             "\"extensionsUsed\":[\"KHR_materials_ior\",\"KHR_materials_transmission\"],"
             "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},"
             "\"indices\":2,\"material\":0}]}],"
             "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[%g,%g,%g,1],"
             "\"metallicFactor\":%g,\"roughnessFactor\":%g},\"emissiveFactor\":[%g,%g,%g],"
             "\"extensions\":{\"KHR_materials_ior\":{\"ior\":%g},"
             "\"KHR_materials_transmission\":{\"transmissionFactor\":%g}}}],"
             "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu,\"target\":34962},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34962},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34963}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\","
             "\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\"},"
             "{\"bufferView\":2,\"componentType\":5125,\"count\":%u,\"type\":\"SCALAR\"}]}\n",
             s->base[0], s->base[1], s->base[2], s->metallic, s->roughness, s->emission,
             s->emission, s->emission, s->ior, s->transmission, total, b64, pos_bytes, pos_bytes,
             pos_bytes, 2 * pos_bytes, idx_bytes, vcount, -r, -r, -r, r, r, r, vcount, vcount);
    const char *path = t_temp_file(s->name, json);
    free(json);
    free(b64);
    free(buf);
    free(pos);
    free(nrm);
    return path;
}

/* ---------------------------------------------------------------------------------------- */
/* rendering helpers                                                                          */

static xrsc_scene *load_scene(const char *path, bool env_set, float env)
{
    xrsc_scene_options so = {0};
    so.env_set = env_set;
    so.environment[0] = so.environment[1] = so.environment[2] = env;
    xrsc_scene *scene = NULL;
    xrsc_diag diag = {0};
    xrsc_result r = xrsc_scene_load(g_ctx, path, &so, &scene, &diag);
    CHECK_MSG(r == XRSC_OK, "load %s: %s (%s)", path, xrsc_result_name(r), diag.message);
    return r == XRSC_OK ? scene : NULL;
}

static xrsc_renderer *make_spp(xrsc_scene *scene, uint32_t size, uint32_t spp, uint32_t bounces,
                               bool accumulate, uint32_t seed)
{
    xrsc_renderer_options o = {0};
    o.method = XRSC_METHOD_SPP;
    o.width = o.height = size;
    o.seed = seed;
    o.spp.samples_per_pixel = spp;
    o.spp.max_bounces = bounces;
    o.spp.accumulate = accumulate;
    xrsc_renderer *r = NULL;
    xrsc_diag diag = {0};
    xrsc_result res = xrsc_renderer_create(g_ctx, scene, &o, &r, &diag);
    CHECK_MSG(res == XRSC_OK, "renderer: %s (%s)", xrsc_result_name(res), diag.message);
    return res == XRSC_OK ? r : NULL;
}

/** Two eyes looking down -Z from (x +- half_ipd, y, z), symmetric field of view. */
static xrsc_frame make_frame(float x, float y, float z, float half_ipd, float half_fov,
                             uint32_t frame_index)
{
    xrsc_frame f;
    memset(&f, 0, sizeof(f));
    for (int e = 0; e < 2; e++) {
        f.views[e].pose.orientation.w = 1.0f;
        f.views[e].pose.position.x = x + (e == 0 ? -half_ipd : half_ipd);
        f.views[e].pose.position.y = y;
        f.views[e].pose.position.z = z;
        f.views[e].fov.angleLeft = -half_fov;
        f.views[e].fov.angleRight = half_fov;
        f.views[e].fov.angleUp = half_fov;
        f.views[e].fov.angleDown = -half_fov;
    }
    f.frame_index = frame_index;
    return f;
}

/** A frame at the scene's viewpoint (both eyes there). */
static xrsc_frame viewpoint_frame(const xrsc_scene *scene, float half_fov, uint32_t frame_index)
{
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    xrsc_frame f = make_frame(0, 0, 0, 0, half_fov, frame_index);
    f.views[0].pose = f.views[1].pose = info.viewpoint;
    return f;
}

static bool render(xrsc_renderer *r, const xrsc_frame *f)
{
    xrsc_result res = xrsc_renderer_render(r, f);
    CHECK_MSG(res == XRSC_OK, "render: %s", xrsc_result_name(res));
    return res == XRSC_OK;
}

static bool read_out(xrsc_renderer *r, uint32_t eye, xrsc_output out, void *dst, size_t size)
{
    CHECK_EQ_INT(xrsc_renderer_output_size(r, out), size);
    xrsc_result res = xrsc_renderer_read(r, eye, out, dst, size);
    CHECK_MSG(res == XRSC_OK, "read eye %u output %d: %s", eye, (int)out, xrsc_result_name(res));
    return res == XRSC_OK;
}

/** Per-pixel running mean and variance (Welford) of one scalar per pixel over frames. */
typedef struct pix_stats {
    uint32_t count; /* pixels */
    uint32_t n;     /* frames added */
    double *mean, *m2;
} pix_stats;

static void stats_init(pix_stats *s, uint32_t count)
{
    s->count = count;
    s->n = 0;
    s->mean = calloc(count, sizeof(double));
    s->m2 = calloc(count, sizeof(double));
}

static void stats_free(pix_stats *s)
{
    free(s->mean);
    free(s->m2);
}

static void stats_add(pix_stats *s, const double *v)
{
    s->n++;
    for (uint32_t i = 0; i < s->count; i++) {
        double d = v[i] - s->mean[i];
        s->mean[i] += d / s->n;
        s->m2[i] += d * (v[i] - s->mean[i]);
    }
}

/** Variance of one frame's value of pixel i (unbiased). */
static double stats_var(const pix_stats *s, uint32_t i)
{
    return s->n > 1 ? s->m2[i] / (s->n - 1) : 0.0;
}

static double grey(const float *rgba)
{
    return (rgba[0] + rgba[1] + rgba[2]) / 3.0;
}

/** Everything one rendered stereo image pair gives the furnace checks. */
typedef struct furnace_run {
    uint32_t size, pixels; /* per eye */
    pix_stats st;          /* grey value over frames, both eyes: index eye * pixels + p */
    uint32_t *hit_inst;    /* first frame's hit instance */
    float *depth, *albedo; /* first frame's depth and grey albedo */
    bool any_nonfinite;
    uint64_t rays_last;
} furnace_run;

static bool furnace_render(xrsc_scene *scene, uint32_t size, uint32_t spp, uint32_t bounces,
                           uint32_t frames, const xrsc_frame *view, furnace_run *out)
{
    memset(out, 0, sizeof(*out));
    out->size = size;
    out->pixels = size * size;
    uint32_t pixels = out->pixels;
    xrsc_renderer *r = make_spp(scene, size, spp, bounces, false, 1234u);
    if (!r)
        return false;
    stats_init(&out->st, 2 * pixels);
    out->hit_inst = calloc(2 * (size_t)pixels, sizeof(uint32_t));
    out->depth = calloc(2 * (size_t)pixels, sizeof(float));
    out->albedo = calloc(2 * (size_t)pixels, sizeof(float));
    float *rgba = malloc((size_t)pixels * 16);
    uint32_t *ids = malloc((size_t)pixels * 16);
    double *v = malloc(2 * (size_t)pixels * sizeof(double));
    bool ok = true;
    for (uint32_t k = 0; k < frames && ok; k++) {
        xrsc_frame f = *view;
        f.frame_index = k;
        ok = render(r, &f);
        for (uint32_t e = 0; e < 2 && ok; e++) {
            ok = read_out(r, e, XRSC_OUTPUT_COLOR, rgba, (size_t)pixels * 16);
            for (uint32_t p = 0; ok && p < pixels; p++) {
                if (!isfinite(rgba[4 * p]) || !isfinite(rgba[4 * p + 1]) ||
                    !isfinite(rgba[4 * p + 2]))
                    out->any_nonfinite = true;
                v[e * pixels + p] = grey(rgba + 4 * p);
            }
            if (ok && k == 0) {
                ok = read_out(r, e, XRSC_OUTPUT_HIT_ID, ids, (size_t)pixels * 16) &&
                     read_out(r, e, XRSC_OUTPUT_DEPTH, out->depth + e * pixels,
                              (size_t)pixels * 4) &&
                     read_out(r, e, XRSC_OUTPUT_ALBEDO, rgba, (size_t)pixels * 16);
                for (uint32_t p = 0; ok && p < pixels; p++) {
                    out->hit_inst[e * pixels + p] = ids[4 * p];
                    out->albedo[e * pixels + p] = (float)grey(rgba + 4 * p);
                }
            }
        }
        if (ok)
            stats_add(&out->st, v);
    }
    out->rays_last = xrsc_renderer_rays_last_frame(r);
    free(rgba);
    free(ids);
    free(v);
    xrsc_renderer_destroy(&r);
    CHECK(r == NULL);
    return ok;
}

static void furnace_free(furnace_run *f)
{
    stats_free(&f->st);
    free(f->hit_inst);
    free(f->depth);
    free(f->albedo);
}

/** Pixel p of eye e is hit (want_hit) or missed in a whole (2 margin + 1)^2 neighbourhood. */
static bool in_mask(const furnace_run *f, uint32_t e, uint32_t p, bool want_hit)
{
    int s = (int)f->size, x = (int)(p % f->size), y = (int)(p / f->size);
    for (int dy = -T_MASK_MARGIN; dy <= T_MASK_MARGIN; dy++)
        for (int dx = -T_MASK_MARGIN; dx <= T_MASK_MARGIN; dx++) {
            int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= s || yy >= s)
                return false;
            bool hit = f->hit_inst[e * f->pixels + (uint32_t)(yy * s + xx)] != T_MISS;
            if (hit != want_hit)
                return false;
        }
    return true;
}

typedef struct mask_summary {
    uint32_t count;
    double mean;      /* mean over the masked pixels of their per-pixel means */
    double sigma;     /* std of the pixel means (pooled: all pixels estimate the same value) */
    double se;        /* standard error of the mean: sigma / sqrt(count) */
    double max_abs_z; /* max over pixels of |mean_p - expect| / (sigma + floor) */
    uint32_t outliers; /* |z| > T_OUTLIER_Z */
    double min, max;
} mask_summary;

/**
 * Summarises the masked pixels (surface when want_hit, else background). Every pixel mean is
 * an independent estimate of the same expectation, so the spread of the pixel means is their
 * standard deviation (pooled over the pixels: far steadier than each pixel's own variance
 * from a few frames); floor_tol keeps z finite for noiseless images.
 */
static mask_summary summarize(const furnace_run *f, bool want_hit, double expect, double floor_tol)
{
    mask_summary m = {0};
    m.min = 1e30;
    m.max = -1e30;
    double sum = 0, sum2 = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (uint32_t e = 0; e < 2; e++)
            for (uint32_t p = 0; p < f->pixels; p++) {
                if (!in_mask(f, e, p, want_hit))
                    continue;
                double x = f->st.mean[e * f->pixels + p];
                if (pass == 0) {
                    m.count++;
                    sum += x;
                    sum2 += x * x;
                    m.min = fmin(m.min, x);
                    m.max = fmax(m.max, x);
                    continue;
                }
                double z = fabs(x - expect) / (m.sigma + floor_tol);
                m.max_abs_z = isfinite(z) ? fmax(m.max_abs_z, z) : INFINITY;
                if (!(z <= T_OUTLIER_Z))
                    m.outliers++;
            }
        if (pass == 0 && m.count > 1) {
            m.mean = sum / m.count;
            double var = fmax(0.0, (sum2 - m.count * m.mean * m.mean) / (m.count - 1));
            m.sigma = sqrt(var);
            m.se = m.sigma / sqrt((double)m.count);
        }
    }
    return m;
}

static void print_summary(const char *what, const mask_summary *m, double expect)
{
    printf("  %-34s pixels %5u  mean %.6f (expect %.6f, se %.2e)  sigma %.2e min %.4f "
           "max %.4f  max|z| %.2f outliers %u\n",
           what, m->count, m->mean, expect, m->se, m->sigma, m->min, m->max, m->max_abs_z,
           m->outliers);
}

/** Checks the surface mean against expect within T_SIGMAS standard errors + allowance. */
static void check_surface(const char *what, const mask_summary *m, double expect, double allow)
{
    print_summary(what, m, expect);
    CHECK_MSG(m->count >= 100, "%s: only %u interior pixels", what, m->count);
    double tol = T_SIGMAS * m->se + allow;
    CHECK_MSG(fabs(m->mean - expect) <= tol, "%s: mean %.6f, expected %.6f +- %.2e", what, m->mean,
              expect, tol);
    CHECK_MSG(m->outliers <= (uint32_t)(T_OUTLIER_FRACTION * m->count), "%s: %u of %u pixels |z|>%g",
              what, m->outliers, m->count, T_OUTLIER_Z);
}

/* Camera of the outside-furnace cases: (0, 0, 3) looking at a unit sphere at the origin. */
#define FURNACE_CAM_Z 3.0f
#define FURNACE_HALF_FOV 0.45f
#define FURNACE_HALF_IPD 0.032f
#define FURNACE_SIZE 64u

static furnace_run run_outside_furnace(const sphere_spec *spec, uint32_t spp, uint32_t frames)
{
    furnace_run f;
    memset(&f, 0, sizeof(f));
    const char *path = write_sphere_gltf(spec);
    xrsc_scene *scene = load_scene(path, true, (float)FURNACE_L);
    remove(path);
    if (!scene)
        return f;
    xrsc_frame view = make_frame(0, 0, FURNACE_CAM_Z, FURNACE_HALF_IPD, FURNACE_HALF_FOV, 0);
    CHECK(furnace_render(scene, FURNACE_SIZE, spp, 0, frames, &view, &f));
    xrsc_scene_destroy(&scene);
    return f;
}

/* ---------------------------------------------------------------------------------------- */
/* cases                                                                                      */

/** A flat-shaded Lambertian sphere (rho 0.5, IOR 1 = no specular layer) in a furnace of L = 1:
 *  every path returns exactly rho L, so any normalisation error of the diffuse lobe, its pdf
 *  or the camera shows. */
static void test_furnace_diffuse_flat(void)
{
    if (!g_ctx)
        return;
    sphere_spec s = {"furnace_diffuse.gltf", {0.5f, 0.5f, 0.5f}, 0, 1, 0, 1.0f, 0, false, 24, 48, 1};
    furnace_run f = run_outside_furnace(&s, 16, 4);
    if (!f.hit_inst)
        return;
    CHECK(!f.any_nonfinite);
    mask_summary sm = summarize(&f, true, FURNACE_RHO * FURNACE_L, 1e-4);
    check_surface("diffuse sphere (rho L)", &sm, FURNACE_RHO * FURNACE_L, 2e-4);
    mask_summary bg = summarize(&f, false, FURNACE_L, 1e-5);
    print_summary("background (L)", &bg, FURNACE_L);
    CHECK(bg.count >= 100);
    CHECK_NEAR(bg.min, FURNACE_L, 1e-5);
    CHECK_NEAR(bg.max, FURNACE_L, 1e-5);
    /* auxiliary outputs of the first frame (albedo is the mean over the pixel's samples,
     * depth and hit id are the first sample's: compare away from the silhouette) */
    uint32_t c = FURNACE_SIZE / 2, bad_albedo = 0, bad_depth = 0;
    for (uint32_t e = 0; e < 2; e++) {
        for (uint32_t p = 0; p < f.pixels; p++) {
            uint32_t i = e * f.pixels + p;
            if (in_mask(&f, e, p, true)) {
                bad_albedo += fabs(f.albedo[i] - FURNACE_RHO) > 1e-5;
                bad_depth += !(f.depth[i] > FURNACE_CAM_Z - 1.0f - 1e-4f && f.depth[i] < FURNACE_CAM_Z);
            } else if (in_mask(&f, e, p, false)) {
                bad_albedo += fabs(f.albedo[i] - 1.0) > 1e-6;
                bad_depth += f.depth[i] != 0.0f;
            }
            if (f.hit_inst[i] == T_MISS)
                bad_depth += f.depth[i] != 0.0f;
        }
        /* near the pole facing the camera the depth is camera z - radius (flat facets: a bit more) */
        float d = f.depth[e * f.pixels + c * FURNACE_SIZE + c];
        CHECK_MSG(d >= FURNACE_CAM_Z - 1.0f - 1e-4f && d < FURNACE_CAM_Z - 1.0f + 0.02f,
                  "centre depth %.5f", d);
    }
    CHECK_EQ_INT(bad_albedo, 0);
    CHECK_EQ_INT(bad_depth, 0);
    uint64_t camera_rays = 2ull * f.pixels * 16;
    printf("  rays last frame %llu (camera rays %llu)\n", (unsigned long long)f.rays_last,
           (unsigned long long)camera_rays);
    CHECK(f.rays_last >= camera_rays);
    CHECK(f.rays_last <= camera_rays * (1 + T_RAYS_PER_BOUNCE * 3));
    furnace_free(&f);
}

/** A closed Lambertian emitter (Le = 1, rho = 0.5, normals inward) seen from its centre:
 *  exactly Le * sum_{k=0..B} rho^k after B bounce rays. Exercises light sampling of the
 *  emissive triangles, MIS of emission hit by BSDF rays, bounce counting and (B >= 2)
 *  Russian roulette: at the 2nd bounce the throughput is rho = 0.5, so survival is 0.5 and a
 *  roulette that forgets to divide loses ~10 %. */
/* issue 22 (test time): 32 x 32 per eye (was 48 x 48): the per-pixel statistics (16 spp x 4
 * frames) are as before, the image mean's standard error ~1.5 x larger (tests/times.md) */
#define CLOSED_SIZE 32u
static void test_furnace_closed_emitter(void)
{
    if (!g_ctx)
        return;
    sphere_spec s = {"furnace_closed.gltf", {0.5f, 0.5f, 0.5f}, 0, 1, 0, 1.0f, 1.0f, true, 16, 32, 1};
    const char *path = write_sphere_gltf(&s);
    xrsc_scene *scene = load_scene(path, true, 0.0f);
    remove(path);
    if (!scene)
        return;
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    CHECK(info.emitter_count > 100);
    const uint32_t bounces[] = {1, 0 /* default: 3 */, 5};
    for (size_t b = 0; b < sizeof(bounces) / sizeof(bounces[0]); b++) {
        uint32_t nb = bounces[b] ? bounces[b] : 3;
        double expect = 0, rk = 1;
        for (uint32_t k = 0; k <= nb; k++, rk *= FURNACE_RHO)
            expect += rk;
        xrsc_frame view = make_frame(0, 0, 0, 0.05f, 0.6f, 0);
        furnace_run f;
        if (!furnace_render(scene, CLOSED_SIZE, 16, bounces[b], 4, &view, &f)) {
            furnace_free(&f);
            continue;
        }
        CHECK(!f.any_nonfinite);
        char what[64];
        snprintf(what, sizeof(what), "closed emitter, %u bounces", nb);
        mask_summary sm = summarize(&f, true, expect, 1e-4);
        check_surface(what, &sm, expect, T_FLOAT_REL * expect);
        furnace_free(&f);
    }
    xrsc_scene_destroy(&scene);
}

/** Metal, glass and plastic spheres in the furnace. Single-scattering GGX loses energy (a
 *  metal of roughness 0.5, alpha 0.25, returns ~0.91 at normal and ~0.86 at grazing
 *  incidence: numeric integration of xs_bsdf.glsl), glass loses only the paths still inside
 *  after the last bounce; neither may create energy (<= L). glTF's opaque dielectric
 *  (fresnel_mix: diffuse weighted by 1 - F(v.h)) is not strictly energy conserving: a white
 *  base gains up to ~14 % at grazing angles (~1 % averaged over the sphere), so it gets an
 *  upper bound of PLASTIC_MAX_GAIN instead. */
#define PLASTIC_MAX_GAIN 1.03
/* issue 22 (test time): 2 frames of 16 spp (was 4): only the mean is asserted, within ranges
 * far wider than its standard error (tests/times.md) */
#define METAL_GLASS_FRAMES 2u
/* cases[first .. first + count - 1] of the table below (issue 22: two test cases of two spheres
 * each, which ctest can run as separate entries: each sphere's pipelines compile for ~20 s on
 * an empty Mesa shader cache) */
static void furnace_materials(size_t first, size_t count)
{
    if (!g_ctx)
        return;
    struct {
        sphere_spec s;
        double lo, hi; /* plausible range of the mean */
    } cases[] = {
        {{"furnace_metal.gltf", {1, 1, 1}, 1, 0.5f, 0, 1.5f, 0, false, 24, 48, 1}, 0.85, 1.0},
        {{"furnace_glass.gltf", {1, 1, 1}, 0, 0.0f, 1, 1.5f, 0, false, 24, 48, 1}, 0.97, 1.0},
        {{"furnace_rough_glass.gltf", {1, 1, 1}, 0, 0.3f, 1, 1.5f, 0, false, 24, 48, 1}, 0.85, 1.0},
        {{"furnace_plastic.gltf", {1, 1, 1}, 0, 0.4f, 0, 1.5f, 0, false, 24, 48, 1}, 0.95,
         PLASTIC_MAX_GAIN},
    };
    for (size_t i = first; i < first + count && i < sizeof(cases) / sizeof(cases[0]); i++) {
        furnace_run f = run_outside_furnace(&cases[i].s, 16, METAL_GLASS_FRAMES);
        if (!f.hit_inst)
            continue;
        CHECK(!f.any_nonfinite);
        mask_summary sm = summarize(&f, true, FURNACE_L, 1e-4);
        print_summary(cases[i].s.name, &sm, FURNACE_L);
        double tol = T_SIGMAS * sm.se + T_FLOAT_REL;
        CHECK_MSG(sm.mean <= cases[i].hi * FURNACE_L + tol, "%s creates energy: %.5f",
                  cases[i].s.name, sm.mean);
        CHECK_MSG(sm.mean >= cases[i].lo, "%s loses too much: %.5f", cases[i].s.name, sm.mean);
        furnace_free(&f);
    }
}
static void test_furnace_metal_glass(void)
{
    furnace_materials(0, 2);
}
static void test_furnace_rough_glass_plastic(void)
{
    furnace_materials(2, 2);
}

/** scenes/furnace.gltf (helper-made: diffuse sphere rho 0.5, environment 1, IOR 1) gives
 *  rho L on the sphere and L around it. Smooth normals on a tessellated sphere lose a little
 *  energy to rays leaving below the facets (rejected): allowed up to 1 % of rho L. */
#define FURNACE_FILE_ALLOW 0.01
static void test_furnace_scene_file(void)
{
    if (!g_ctx)
        return;
    xrsc_scene *scene = load_scene(t_source_path("scenes/furnace.gltf"), false, 0);
    if (!scene)
        return;
    xrsc_frame view = make_frame(0, 0, FURNACE_CAM_Z, FURNACE_HALF_IPD, FURNACE_HALF_FOV, 0);
    furnace_run f;
    if (furnace_render(scene, FURNACE_SIZE, 16, 0, 4, &view, &f)) {
        CHECK(!f.any_nonfinite);
        mask_summary sm = summarize(&f, true, FURNACE_RHO * FURNACE_L, 1e-3);
        check_surface("scenes/furnace.gltf sphere", &sm, FURNACE_RHO * FURNACE_L,
                      FURNACE_FILE_ALLOW * FURNACE_RHO * FURNACE_L);
        mask_summary bg = summarize(&f, false, FURNACE_L, 1e-5);
        print_summary("scenes/furnace.gltf background", &bg, FURNACE_L);
        CHECK(bg.count >= 100);
        CHECK_NEAR(bg.mean, FURNACE_L, 1e-5);
    }
    furnace_free(&f);
    xrsc_scene_destroy(&scene);
}

/* Cornell-box cases: 48 x 48 per eye at the scene's viewpoint. */
#define CORNELL_SIZE 48u
#define CORNELL_HALF_FOV 0.5f

static double luminance(const float *c)
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

/* Blocks of pixels for region statistics (48 / 8 = 6 x 6 blocks per eye). */
#define CORNELL_BLOCK 8u
/* N: samples per pixel of the N-spp frames; CORNELL_REPEATS independent N-spp frames are
 * compared with CORNELL_REPEATS * N independent 1-spp frames (both sides then carry their own
 * variance estimate: path-traced pixels are skewed, and a variance taken from one side only
 * misses the rare bright paths the other side happened to draw). */
#define CORNELL_SPP 16u
#define CORNELL_REPEATS 4u
/* Per-pixel |z| beyond T_OUTLIER_Z allowed for this fraction (few samples per pixel). */
#define CORNELL_PIXEL_OUTLIERS 0.02

/** Renders frames frame0 .. frame0 + count - 1 and adds each one's luminance to st. */
static bool add_frames(xrsc_renderer *r, const xrsc_scene *scene, uint32_t frame0, uint32_t count,
                       pix_stats *st)
{
    const uint32_t px = CORNELL_SIZE * CORNELL_SIZE;
    float *rgba = malloc((size_t)px * 16);
    double *v = malloc(2 * (size_t)px * sizeof(double));
    bool ok = r != NULL;
    for (uint32_t k = 0; k < count && ok; k++) {
        xrsc_frame f = viewpoint_frame(scene, CORNELL_HALF_FOV, frame0 + k);
        ok = render(r, &f);
        for (uint32_t e = 0; e < 2 && ok; e++) {
            ok = read_out(r, e, XRSC_OUTPUT_COLOR, rgba, (size_t)px * 16);
            for (uint32_t p = 0; ok && p < px; p++)
                v[e * px + p] = luminance(rgba + 4 * p);
        }
        if (ok)
            stats_add(st, v);
    }
    free(rgba);
    free(v);
    return ok;
}

/**
 * The mean of independent 1-spp frames and N-spp frames estimate the same image (same number
 * of samples per pixel on both sides). Per 8 x 8 block: z = (A - B) / sqrt(Var A + Var B) with
 * each variance the sum of its pixels' sample variances / frames / P^2; blocks average 1024
 * samples per side, so z is close to normal: every |z| <= T_OUTLIER_Z, the mean z within
 * 6 / sqrt(blocks), the whole image within T_SIGMAS. Per pixel: |z| <= T_OUTLIER_Z for all
 * but CORNELL_PIXEL_OUTLIERS.
 */
static void test_frames_vs_spp(void)
{
    if (!g_ctx)
        return;
    xrsc_scene *scene = load_scene(t_source_path("scenes/cornell.gltf"), false, 0);
    if (!scene)
        return;
    const uint32_t size = CORNELL_SIZE, px = size * size, n = CORNELL_SPP;
    const uint32_t na = CORNELL_REPEATS * n, nb = CORNELL_REPEATS;
    xrsc_renderer *one = make_spp(scene, size, 1, 0, false, 7u);
    xrsc_renderer *many = make_spp(scene, size, n, 0, false, 7u);
    pix_stats sa, sb;
    stats_init(&sa, 2 * px);
    stats_init(&sb, 2 * px);
    bool ok = add_frames(one, scene, 100, na, &sa) && add_frames(many, scene, 5000, nb, &sb);
    if (ok) {
        uint32_t nonfinite = 0, pix_out = 0, pix_noisy = 0, blocks = 0, block_out = 0;
        double zsum = 0, zmax = 0, img_a = 0, img_b = 0, img_var = 0;
        const uint32_t nbk = size / CORNELL_BLOCK;
        for (uint32_t e = 0; e < 2; e++)
            for (uint32_t by = 0; by < nbk; by++)
                for (uint32_t bx = 0; bx < nbk; bx++) {
                    double ta = 0, tb = 0, var = 0;
                    for (uint32_t y = by * CORNELL_BLOCK; y < (by + 1) * CORNELL_BLOCK; y++)
                        for (uint32_t x = bx * CORNELL_BLOCK; x < (bx + 1) * CORNELL_BLOCK; x++) {
                            uint32_t i = e * px + y * size + x;
                            double a = sa.mean[i], b = sb.mean[i];
                            if (!isfinite(a) || !isfinite(b)) {
                                nonfinite++;
                                continue;
                            }
                            double vp = stats_var(&sa, i) / na + stats_var(&sb, i) / nb;
                            ta += a;
                            tb += b;
                            var += vp;
                            if (vp > 0) {
                                pix_noisy++;
                                if (fabs(a - b) / sqrt(vp) > T_OUTLIER_Z)
                                    pix_out++;
                            } else if (fabs(a - b) > 1e-4 * (1 + fabs(b))) {
                                pix_out++; /* noiseless pixel (background): must agree */
                            }
                        }
                    img_a += ta;
                    img_b += tb;
                    img_var += var;
                    double z = var > 0 ? (ta - tb) / sqrt(var) : 0;
                    blocks++;
                    zsum += z;
                    zmax = fmax(zmax, fabs(z));
                    if (fabs(z) > T_OUTLIER_Z) {
                        block_out++;
                        printf("  block eye %u (%u,%u): 1 spp %.5f, %u spp %.5f, z %.2f\n", e, bx,
                               by, ta / (CORNELL_BLOCK * CORNELL_BLOCK), n,
                               tb / (CORNELL_BLOCK * CORNELL_BLOCK), z);
                    }
                }
        double zmean = zsum / blocks;
        double z_img = img_var > 0 ? (img_a - img_b) / sqrt(img_var) : 0;
        printf("  cornell %u x 1 spp vs %u x %u spp: image means %.5f / %.5f (z %.2f); %u "
               "blocks, mean z %.3f, max |z| %.2f; %u noisy pixels, %u with |z| > %g\n",
               na, nb, n, img_a / (2 * px), img_b / (2 * px), z_img, blocks, zmean, zmax,
               pix_noisy, pix_out, T_OUTLIER_Z);
        CHECK_EQ_INT(nonfinite, 0);
        CHECK(pix_noisy > px);
        CHECK_MSG(fabs(z_img) <= T_SIGMAS, "image z %.3f", z_img);
        CHECK_EQ_INT(block_out, 0);
        CHECK_MSG(fabs(zmean) <= 6.0 / sqrt((double)blocks), "mean block z %.3f", zmean);
        CHECK_MSG(pix_out <= (uint32_t)(CORNELL_PIXEL_OUTLIERS * 2 * px), "%u pixel outliers",
                  pix_out);
    }
    stats_free(&sa);
    stats_free(&sb);
    xrsc_renderer_destroy(&one);
    xrsc_renderer_destroy(&many);
    xrsc_scene_destroy(&scene);
}

/**
 * Accumulation over K frames equals the mean of the same K frames rendered separately
 * (frame_index selects the random stream: the caller varies it per accumulated frame).
 */
#define ACCUM_FRAME_INDEX 40u
static void test_accumulate(void)
{
    if (!g_ctx)
        return;
    xrsc_scene *scene = load_scene(t_source_path("scenes/cornell.gltf"), false, 0);
    if (!scene)
        return;
    const uint32_t k_frames = 4, spp = 2, px = CORNELL_SIZE * CORNELL_SIZE;
    xrsc_renderer *acc = make_spp(scene, CORNELL_SIZE, spp, 0, true, 3u);
    xrsc_renderer *sep = make_spp(scene, CORNELL_SIZE, spp, 0, false, 3u);
    float *rgba = malloc((size_t)px * 16);
    double *sum = calloc(2 * (size_t)px * 3, sizeof(double));
    bool ok = acc && sep;
    for (uint32_t k = 0; k < k_frames && ok; k++) {
        xrsc_frame f = viewpoint_frame(scene, CORNELL_HALF_FOV, ACCUM_FRAME_INDEX + k);
        ok = render(acc, &f) && render(sep, &f);
        for (uint32_t e = 0; e < 2 && ok; e++) {
            ok = read_out(sep, e, XRSC_OUTPUT_COLOR, rgba, (size_t)px * 16);
            for (uint32_t p = 0; ok && p < px; p++)
                for (int c = 0; c < 3; c++)
                    sum[(e * px + p) * 3 + c] += rgba[4 * p + c];
        }
    }
    double max_err = 0;
    for (uint32_t e = 0; e < 2 && ok; e++) {
        ok = read_out(acc, e, XRSC_OUTPUT_COLOR, rgba, (size_t)px * 16);
        for (uint32_t p = 0; ok && p < px; p++)
            for (int c = 0; c < 3; c++) {
                double want = sum[(e * px + p) * 3 + c] / k_frames;
                double err = fabs(rgba[4 * p + c] - want) / (1.0 + fabs(want));
                max_err = isfinite(err) ? fmax(err, max_err) : INFINITY;
            }
    }
    printf("  accumulate: max relative difference to the mean of %u frames %.3g\n", k_frames,
           max_err);
    CHECK(ok);
    CHECK_MSG(max_err <= 1e-5, "accumulated mean differs by %.3g", max_err);
    free(rgba);
    free(sum);
    xrsc_renderer_destroy(&acc);
    xrsc_renderer_destroy(&sep);
    xrsc_scene_destroy(&scene);
}

/** Same frame_index and seed: bit-identical colour; another frame_index or seed: other noise. */
static void test_determinism(void)
{
    if (!g_ctx)
        return;
    xrsc_scene *scene = load_scene(t_source_path("scenes/cornell.gltf"), false, 0);
    if (!scene)
        return;
    const uint32_t px = CORNELL_SIZE * CORNELL_SIZE;
    const size_t bytes = (size_t)px * 16;
    xrsc_renderer *r = make_spp(scene, CORNELL_SIZE, 1, 0, false, 11u);
    xrsc_renderer *r2 = make_spp(scene, CORNELL_SIZE, 1, 0, false, 12u);
    float *a = malloc(2 * bytes), *b = malloc(2 * bytes), *c = malloc(2 * bytes),
          *d = malloc(2 * bytes);
    bool ok = r && r2;
    xrsc_frame f7 = viewpoint_frame(scene, CORNELL_HALF_FOV, 7);
    xrsc_frame f8 = viewpoint_frame(scene, CORNELL_HALF_FOV, 8);
    float *dst[4] = {a, b, c, d};
    for (int run = 0; run < 4 && ok; run++) {
        xrsc_renderer *rr = run == 3 ? r2 : r;
        ok = render(rr, run == 2 ? &f8 : &f7);
        for (uint32_t e = 0; e < 2 && ok; e++)
            ok = read_out(rr, e, XRSC_OUTPUT_COLOR, dst[run] + e * px * 4, bytes);
    }
    if (ok) {
        CHECK_MSG(memcmp(a, b, 2 * bytes) == 0, "same frame_index and seed differ");
        uint32_t diff_frame = 0, diff_seed = 0, eyes_differ = 0;
        for (uint32_t i = 0; i < 2 * px; i++) {
            if (memcmp(a + 4 * i, c + 4 * i, 12) != 0)
                diff_frame++;
            if (memcmp(a + 4 * i, d + 4 * i, 12) != 0)
                diff_seed++;
        }
        for (uint32_t i = 0; i < px; i++)
            if (memcmp(a + 4 * i, a + 4 * (px + i), 12) != 0)
                eyes_differ++;
        printf("  determinism: %u/%u pixels differ with another frame_index, %u with another "
               "seed, %u between the eyes\n",
               diff_frame, 2 * px, diff_seed, eyes_differ);
        CHECK(diff_frame > px / 2);
        CHECK(diff_seed > px / 2);
        CHECK(eyes_differ > px / 4); /* both eyes share the pose: only their noise differs */
    }
    free(a);
    free(b);
    free(c);
    free(d);
    xrsc_renderer_destroy(&r);
    xrsc_renderer_destroy(&r2);
    xrsc_scene_destroy(&scene);
}

int main(void)
{
    xrsc_context_options co = {0};
    co.validation = true;
    xrsc_diag diag = {0};
    xrsc_result r = xrsc_context_create(&co, &g_ctx, &diag);
    CHECK_MSG(r == XRSC_OK, "context: %s (%s)", xrsc_result_name(r), diag.message);
    if (g_ctx)
        printf("device: %s\n", xrsc_context_device_name(g_ctx));
    RUN(test_furnace_diffuse_flat);
    RUN(test_furnace_closed_emitter);
    RUN(test_furnace_metal_glass);
    RUN(test_furnace_rough_glass_plastic);
    RUN(test_furnace_scene_file);
    RUN(test_frames_vs_spp);
    RUN(test_accumulate);
    RUN(test_determinism);
    if (g_ctx) {
        uint32_t errors = xrsc_context_validation_errors(g_ctx);
        CHECK_EQ_INT(errors, 0);
        xrsc_context_destroy(&g_ctx);
        CHECK(g_ctx == NULL);
    }
    return t_finish();
}
