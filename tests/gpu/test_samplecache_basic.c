// SPDX-License-Identifier: MIT
/**
 * @file test_samplecache_basic.c
 * @brief Method `samplecache` (seed 000 §3): Listing 1 round trip and the Eq. 1 / Eq. 2
 *        formulas on the device against their C build, and the cache invariants over a few
 *        frames of the bundled replay (poses/orbit_cornell.xrpose on scenes/cornell.gltf).
 *
 * Invariants, checked on the CPU from mt_samplecache_snapshot after every frame, both eyes:
 * - the mask uses only bits of slots < N, and v_s implies o_s (no pixel holds more than N);
 * - every pixel keeps >= 1 visible sample (Cornell's background pixels hold background
 *   samples, so this covers "every pixel seeing geometry");
 * - the mask agrees with the stored samples: each occupied slot decodes to a valid first hit
 *   (instance, primitive, material in range, barycentrics inside the triangle) or a unit
 *   background direction, and its world position (current transforms) projects into this
 *   frame's view of the eye INSIDE the pixel that holds it (TSC_PIXEL_MARGIN);
 * - the sample pool (issue 19): every occupied slot of both eyes refers to a pool entry of its
 *   own (no two slots share one, so no sample can overwrite another's), and the pool refused
 *   no new sample (sc_pool_full = 0) even at this replay's 4-frame steps;
 * - the pass names and order, zero validation errors.
 * Runs for 1-pass and 2-pass reprojection and for the multi trace mode. test_albedo_on_read:
 * the albedo made in the frame and the albedo made when it is read (issue 19) are the same
 * bits, and the read leaves the colour as TAA and the blend left it.
 */
#include "gpu_scene.h"
#include "hs_pose_stream.h"
#include "mt_samplecache.h"
#include "sc_scene.h"
#include "test_samplecache_util.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xs_sc_math.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define T_W 64u
#define T_H 64u
#define T_FRAMES 6u
/* Display frames between rendered frames (90 Hz clock): more motion per frame. */
#define T_FRAME_STRIDE 4u
#define T_REFRESH_HZ 90.0
/* Listing 1: the barycentric quantisation error bound (xs_sc_math.h). */
#define T_BARY_TOL (1.0 / 16777216.0)
#define T_SELFTEST_COUNT 4096u
/* Adaptive shading: shadings per pixel vs the rate (coin tosses, 4096 pixels). */
#define T_SHADE_RATE_TOL 0.1
/* Eq. 1 on the device vs C, relative to t (1 - cos/cos cancels: Delta itself can carry a
 * large relative error when tiny; Eq. 2 compares it with distances). */
#define T_DELTA_REL_TOL 1e-5

static uint32_t rng_state = 12345u;
static uint32_t rnd(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state ^ (rng_state >> 16);
}
static float rndf(void)
{
    return (float)(rnd() >> 8) * (1.0f / 16777216.0f);
}

static gpu_context *new_gpu(void)
{
    gpu_context_options go = {.validation = true};
    gpu_context *gpu = NULL;
    xrsc_diag diag = {0};
    xrsc_result r = gpu_context_create(&go, &gpu, &diag);
    CHECK_EQ_INT(r, XRSC_OK);
    if (r != XRSC_OK) {
        char msg[1400];
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
    }
    return gpu;
}

/* ---- Listing 1, Eq. 1, Eq. 2: device vs C build of xs_sc_math.h ---- */

static void test_formulas_on_device(void)
{
    gpu_context *gpu = new_gpu();
    if (!gpu)
        return;
    xs_sc_selftest_io *io = calloc(T_SELFTEST_COUNT, sizeof(*io));
    static const float special[] = {
        0.0f,   1.0f,      0.5f,         1.0f - 1.0f / 33554432.0f, 1.0f / 33554432.0f,
        1e-30f, 0.999999f, 0.25f + 1e-7f};
    const uint32_t n_special = sizeof(special) / sizeof(special[0]);
    for (uint32_t i = 0; i < T_SELFTEST_COUNT; i++) {
        xs_sc_selftest_io *r = &io[i];
        r->bary_u = i < n_special ? special[i] : rndf();
        r->bary_v = i < n_special ? special[n_special - 1 - i] : rndf() * (1.0f - r->bary_u);
        r->instance = i == 1 ? 0xFFFFFFFEu : rnd();
        r->primitive = i == 2 ? 0xFFFFFFFFu : rnd();
        r->material = i == 3 ? 0xFFFFu : rnd() % XS_SC_MAX_MATERIALS;
        r->t = 0.1f + 10.0f * rndf();
        r->cos_theta = i == 4 ? 0.0f : (i == 5 ? 1.0f : rndf());
        r->phi = 1e-4f + 0.02f * rndf();
        r->t_min = r->t;
        r->t_max = r->t * (1.0f + 0.2f * rndf());
        r->eps1 = (float)XS_SC_DEFAULT_EPS1;
    }
    xrsc_diag diag = {0};
    CHECK_EQ_INT(mt_sc_selftest_run(gpu, io, T_SELFTEST_COUNT, &diag), XRSC_OK);
    uint32_t bad_ids = 0, bad_bary = 0, bad_bits = 0, bad_delta = 0, bad_test = 0;
    double max_err = 0.0, max_delta_err = 0.0;
    for (uint32_t i = 0; i < T_SELFTEST_COUNT; i++) {
        const xs_sc_selftest_io *r = &io[i];
        /* ids exact */
        if (r->out_instance != r->instance || r->out_primitive != r->primitive ||
            r->out_material != r->material)
            bad_ids++;
        /* barycentrics within 2^-24 */
        double eu = fabs((double)r->out_u - (double)r->bary_u);
        double ev = fabs((double)r->out_v - (double)r->bary_v);
        max_err = fmax(max_err, fmax(eu, ev));
        if (eu > T_BARY_TOL || ev > T_BARY_TOL)
            bad_bary++;
        /* the C build packs the same bits */
        uint32_t x = xs_sc_pack_x(r->bary_u, r->material);
        uint32_t y = xs_sc_pack_y(r->bary_v, r->material);
        if (x != r->packed.x || y != r->packed.y || xs_sc_unpack_bary(x) != r->out_u ||
            xs_sc_unpack_material(x, y) != r->out_material)
            bad_bits++;
        float d = xs_sc_slope(r->t, r->cos_theta, r->phi);
        if (fabs(d - r->out_delta) > T_DELTA_REL_TOL * r->t) {
            if (bad_delta < 5)
                fprintf(stderr, "  Eq. 1: t %g cos %g phi %g: C %.9g device %.9g\n", r->t,
                        r->cos_theta, r->phi, d, r->out_delta);
            bad_delta++;
        }
        max_delta_err = fmax(max_delta_err, fabs(d - r->out_delta) / r->t);
        /* Eq. 2 with the device's Delta: identical decision */
        if ((uint32_t)xs_sc_consistent(r->t_min, r->t_max, r->out_delta, r->eps1) !=
            r->out_consistent)
            bad_test++;
    }
    printf("  listing 1: max barycentric error %.3g (2^-24 = %.3g)\n", max_err, T_BARY_TOL);
    printf("  Eq. 1: max |Delta_device - Delta_C| / t = %.3g\n", max_delta_err);
    CHECK_EQ_INT(bad_ids, 0);
    CHECK_EQ_INT(bad_bary, 0);
    CHECK_EQ_INT(bad_bits, 0);
    CHECK_EQ_INT(bad_delta, 0);
    CHECK_EQ_INT(bad_test, 0);
    free(io);
    CHECK_EQ_INT(gpu->validation_errors, 0);
    gpu_context_destroy(&gpu);
}

/* Eq. 1 / Eq. 2 on synthetic neighbourhoods (C build of the shader source). */
static void test_edge_test_synthetic(void)
{
    const float phi = 0.01f, t = 2.0f, eps1 = (float)XS_SC_DEFAULT_EPS1;
    /* fronto-parallel surface: Delta ~ 0, equal distances are consistent */
    float d0 = xs_sc_slope(t, 1.0f, phi);
    CHECK(d0 < 1e-3f * t);
    CHECK(xs_sc_consistent(t, t, d0, eps1));
    /* a step edge: twice the distance fails */
    CHECK(!xs_sc_consistent(t, 2.0f * t, d0, eps1));
    /* an oblique plane seen at 80 degrees: distances spread by about 2 Delta in 3 x 3 (App.
     * A) stay consistent, a 3x larger spread does not */
    float c80 = cosf(80.0f * 3.14159265f / 180.0f);
    float d80 = xs_sc_slope(t, c80, phi);
    CHECK(d80 > d0);
    CHECK(xs_sc_consistent(t, t + 1.9f * d80, d80, eps1));
    CHECK(!xs_sc_consistent(t, t + 6.0f * d80, d80, eps1));
    /* grazing: bounded (theta - phi < pi / 2) */
    float d90 = xs_sc_slope(t, 0.0f, phi);
    CHECK(isfinite(d90) && d90 > d80);
    /* background (infinite t_max) next to a surface is an edge */
    CHECK(!xs_sc_consistent(t, INFINITY, d0, eps1));
}

/* ---- invariants over the replay ---- */

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/** Occupied slots of snapshot sn without a pool address (out_missing), and their addresses
 *  appended to list (*count entries so far). */
static void pool_addresses(const mt_sc_snapshot *sn, uint32_t *list, size_t *count,
                           uint32_t *out_missing)
{
    size_t px = (size_t)sn->width * sn->height;
    for (size_t s = 0; s < sn->slots; s++)
        for (size_t p = 0; p < px; p++) {
            if (!(sn->mask[p] >> s & 1u))
                continue;
            uint32_t a = sn->addr[s * px + p];
            if (a == XS_SC_POOL_NONE)
                (*out_missing)++;
            else
                list[(*count)++] = a;
        }
}

/** Pool addresses held by more than one slot (list sorted in place). */
static uint32_t shared_addresses(uint32_t *list, size_t count)
{
    qsort(list, count, sizeof(uint32_t), cmp_u32);
    uint32_t shared = 0;
    for (size_t i = 1; i < count; i++)
        shared += list[i] == list[i - 1];
    return shared;
}

typedef struct t_counts {
    uint32_t samples, visible, background;
    uint32_t shaded, traced; /* last frame, left eye */
    uint32_t shaded_both;    /* last frame, both eyes */
} t_counts;

static void run_replay(const char *label, const xrsc_samplecache_options *opt)
{
    printf("  %s\n", label);
    gpu_context *gpu = new_gpu();
    if (!gpu)
        return;
    sc_scene *cpu = NULL;
    gpu_scene *gs = NULL;
    mt_method *m = NULL;
    hs_pose_stream *stream = NULL;
    xrsc_diag diag = {0};
    xrsc_result r = sc_scene_load(t_source_path("scenes/cornell.gltf"), NULL, &cpu, &diag);
    CHECK_EQ_INT(r, XRSC_OK);
    if (r == XRSC_OK)
        r = gpu_scene_create(gpu, cpu, &gs, &diag);
    if (r == XRSC_OK) {
        mt_env env = {.gpu = gpu, .scene = gs, .cpu_scene = cpu, .width = T_W, .height = T_H};
        r = mt_samplecache_create(&env, opt, &m, &diag);
    }
    if (r == XRSC_OK)
        r = hs_pose_stream_load(t_source_path("poses/orbit_cornell.xrpose"), HS_POSE_FORMAT_AUTO,
                                &stream, &diag);
    CHECK_EQ_INT(r, XRSC_OK);
    if (r != XRSC_OK) {
        char msg[1400];
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        goto done;
    }
    XrPosef viewpoint = tsc_viewpoint(cpu);
    hs_pose_stream_anchor(stream, viewpoint);
    xrsc_headset hs;
    xrsc_headset_default(&hs);

    t_counts total = {0};
    /* both eyes' pool addresses of one frame (at most N per pixel) */
    uint32_t *addr = malloc(2u * T_W * T_H * XS_SC_MAX_SLOTS * sizeof(uint32_t));
    CHECK(addr != NULL);
    if (!addr)
        goto done;
    for (uint32_t k = 0; k < T_FRAMES; k++) {
        int64_t t_ns = (int64_t)(k * T_FRAME_STRIDE * 1e9 / T_REFRESH_HZ);
        XrPosef head, eyes[2];
        hs_pose_stream_sample(stream, t_ns, &head);
        xrsc_headset_eye_poses(&hs, head, eyes);
        xrsc_frame frame = {.display_time_ns = t_ns, .frame_index = k};
        for (int e = 0; e < 2; e++) {
            frame.views[e].pose = eyes[e];
            frame.views[e].fov = hs.fov[e];
        }
        CHECK_EQ_INT(mt_method_render(m, &frame, &diag), XRSC_OK);
        size_t n_addr = 0;
        uint32_t missing = 0;
        for (uint32_t e = 0; e < 2; e++) {
            mt_sc_snapshot sn;
            if (mt_samplecache_snapshot(m, e, &sn, &diag) != XRSC_OK) {
                CHECK(false);
                continue;
            }
            pool_addresses(&sn, addr, &n_addr, &missing);
            CHECK_MSG(sn.pool_full == 0, "frame %u: the pool refused %u new samples", k,
                      sn.pool_full);
            tsc_view v;
            tsc_make_view(&frame.views[e], T_W, T_H, &v);
            tsc_invariants c = {0};
            tsc_check_invariants(&sn, cpu, &v, &c);
            CHECK_MSG(c.bad_bits == 0 && c.vis_not_occ == 0,
                      "frame %u eye %u: %u masks with bits >= N, %u v without o", k, e, c.bad_bits,
                      c.vis_not_occ);
            CHECK_MSG(c.no_visible == 0, "frame %u eye %u: %u pixels without a visible sample", k,
                      e, c.no_visible);
            CHECK_MSG(c.bad_hit == 0, "frame %u eye %u: %u samples that decode to no valid hit", k,
                      e, c.bad_hit);
            CHECK_MSG(c.outside == 0, "frame %u eye %u: %u samples outside their pixel", k, e,
                      c.outside);
            if (k == T_FRAMES - 1) {
                for (uint32_t p = 0; p < T_W * T_H; p++) {
                    uint32_t sh = (uint32_t)__builtin_popcount(sn.plan[p * 4 + 2]);
                    total.shaded_both += sh;
                    if (e == 0) {
                        total.shaded += sh;
                        total.traced +=
                            (uint32_t)__builtin_popcount(sn.plan[p * 4] | sn.plan[p * 4 + 1]);
                    }
                }
                if (e == 1) /* the shade list holds every chosen sample of both eyes */
                    CHECK_EQ_INT(sn.shade_count, total.shaded_both);
            }
            total.samples += c.samples;
            total.visible += c.visible;
            total.background += c.background;
            mt_sc_snapshot_free(&sn);
        }
        CHECK_MSG(missing == 0, "frame %u: %u occupied slots without a pool entry", k, missing);
        uint32_t shared = shared_addresses(addr, n_addr);
        CHECK_MSG(shared == 0, "frame %u: %u pool entries held by two slots", k, shared);
    }
    free(addr);
    double px = 2.0 * T_W * T_H * T_FRAMES;
    printf("    %.2f samples/pixel (%.2f visible, %.2f background), rays last frame %llu\n",
           total.samples / px, total.visible / px, total.background / px,
           (unsigned long long)mt_method_rays_last_frame(m));
    double resident, working;
    mt_samplecache_bytes_per_pixel(m, &resident, &working);
    printf("    last frame, left eye: %.3f traced and %.3f shaded samples per pixel; cache %.0f + "
           "%.0f B/pixel/eye\n",
           (double)total.traced / (T_W * T_H), (double)total.shaded / (T_W * T_H), resident,
           working);
    if (mt_samplecache_options(m)->shade == XRSC_SC_SHADE_ADAPTIVE) {
        /* §3.5: the shading rate is met in expectation (here 100 %: one per pixel) */
        double rate = mt_samplecache_options(m)->shade_rate;
        CHECK_NEAR((double)total.shaded / (T_W * T_H), rate, T_SHADE_RATE_TOL * rate);
    }

    /* the trace mask is part of "reproject" (sc_copy.comp, issue 19) */
    static const char *const names[] = {"tlas",  "reproject", "density",
                                        "trace", "shade",     "reconstruct"};
    xrsc_pass_timing tm[XRSC_MAX_PASSES];
    uint32_t np = mt_method_timings(m, tm, XRSC_MAX_PASSES);
    CHECK_EQ_INT(np, 6);
    for (uint32_t i = 0; i < np && i < 6; i++)
        CHECK_MSG(!strcmp(tm[i].name, names[i]), "pass %u is %s", i, tm[i].name);

    /* the outputs are finite and the moments consistent (mu_2 >= mu_1^2) */
    size_t bytes = mt_method_output_size(m, XRSC_OUTPUT_MU1);
    CHECK_EQ_INT(bytes, (size_t)T_W * T_H * 16);
    float *color = malloc(bytes), *mu1 = malloc(bytes), *mu2 = malloc(bytes);
    CHECK_EQ_INT(mt_method_read(m, 0, XRSC_OUTPUT_COLOR, color, bytes, &diag), XRSC_OK);
    CHECK_EQ_INT(mt_method_read(m, 0, XRSC_OUTPUT_MU1, mu1, bytes, &diag), XRSC_OK);
    CHECK_EQ_INT(mt_method_read(m, 0, XRSC_OUTPUT_MU2, mu2, bytes, &diag), XRSC_OK);
    uint32_t bad = 0;
    for (size_t i = 0; i < (size_t)T_W * T_H * 4; i++) {
        if (!isfinite(color[i]) || !isfinite(mu1[i]) || !isfinite(mu2[i]))
            bad++;
        else if (i % 4 != 3 && mu2[i] < mu1[i] * mu1[i] * (1.0f - 1e-4f) - 1e-6f)
            bad++;
    }
    CHECK_EQ_INT(bad, 0);
    free(color);
    free(mu1);
    free(mu2);
done:
    mt_method_destroy(&m);
    hs_pose_stream_destroy(&stream);
    if (gs)
        gpu_scene_destroy(gpu, &gs);
    sc_scene_destroy(&cpu);
    CHECK_EQ_INT(gpu->validation_errors, 0);
    gpu_context_destroy(&gpu);
}

static void test_replay_1pass(void)
{
    xrsc_samplecache_options o = {0};
    run_replay("defaults (adaptive trace, 1-pass, uniform shading)", &o);
}

static void test_replay_2pass_adaptive_shading(void)
{
    xrsc_samplecache_options o = {.reproject = XRSC_SC_REPROJECT_2PASS,
                                  .shade = XRSC_SC_SHADE_ADAPTIVE};
    run_replay("2-pass reprojection, adaptive shading", &o);
}

static void test_replay_multi_no_cache(void)
{
    xrsc_samplecache_options o = {
        .trace = XRSC_SC_TRACE_MULTI, .no_shading_cache = true, .slots = 6};
    run_replay("multi trace, no shading cache, N = 6", &o);
}

static void test_replay_single_fixed_alpha(void)
{
    xrsc_samplecache_options o = {.trace = XRSC_SC_TRACE_SINGLE, .alpha = XRSC_SC_ALPHA_FIXED};
    run_replay("single trace, fixed alpha", &o);
}

/* Through the public API, the white furnace (scenes/furnace.gltf): every path from the sphere
 * (albedo 0.5, convex, environment 1) returns exactly 0.5, so a still view must reconstruct
 * 0.5 on the sphere, 1 on the background and their mix on silhouette pixels only: checks the
 * demodulation/remodulation, the blend and the background samples exactly. */
#define T_STILL_FRAMES 8u
#define T_STILL_SIZE 32u
#define T_FURNACE_ALBEDO 0.5
#define T_FURNACE_TOL 1e-4
/* the sphere covers ~86 of the 32 x 32 pixels under the default headset FOV */
#define T_MIN_SPHERE_PIXELS 64u

static void test_furnace_exact(void)
{
    xrsc_context *ctx = NULL;
    xrsc_scene *scene = NULL;
    xrsc_renderer *r = NULL;
    xrsc_context_options co = {.validation = true};
    CHECK_EQ_INT(xrsc_context_create(&co, &ctx, NULL), XRSC_OK);
    if (!ctx)
        return;
    CHECK_EQ_INT(xrsc_scene_load(ctx, t_source_path("scenes/furnace.gltf"), NULL, &scene, NULL),
                 XRSC_OK);
    xrsc_renderer_options ro = {
        .method = XRSC_METHOD_SAMPLECACHE, .width = T_STILL_SIZE, .height = T_STILL_SIZE};
    if (scene)
        CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &ro, &r, NULL), XRSC_OK);
    if (r) {
        xrsc_scene_info info;
        xrsc_scene_get_info(scene, &info);
        xrsc_headset hs;
        xrsc_headset_default(&hs);
        XrPosef eyes[2];
        xrsc_headset_eye_poses(&hs, info.viewpoint, eyes);
        xrsc_frame f = {0};
        for (int e = 0; e < 2; e++) {
            f.views[e].pose = eyes[e];
            f.views[e].fov = hs.fov[e];
        }
        for (uint32_t k = 0; k < T_STILL_FRAMES; k++) {
            f.frame_index = k;
            CHECK_EQ_INT(xrsc_renderer_render(r, &f), XRSC_OK);
        }
        size_t n = (size_t)T_STILL_SIZE * T_STILL_SIZE;
        float *c = malloc(n * 16), *depth = malloc(n * 4), *mu1 = malloc(n * 16);
        CHECK_EQ_INT(xrsc_renderer_read(r, 0, XRSC_OUTPUT_COLOR, c, n * 16), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, 0, XRSC_OUTPUT_DEPTH, depth, n * 4), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, 0, XRSC_OUTPUT_MU1, mu1, n * 16), XRSC_OK);
        uint32_t out_of_range = 0, sphere = 0, exact = 0, background = 0;
        for (size_t i = 0; i < n; i++) {
            float v = c[i * 4];
            if (v < T_FURNACE_ALBEDO - T_FURNACE_TOL || v > 1.0 + T_FURNACE_TOL)
                out_of_range++;
            if (depth[i] > 0.0f) {
                sphere++;
                exact += fabs(v - T_FURNACE_ALBEDO) <= T_FURNACE_TOL;
            } else {
                background++;
                CHECK_NEAR(v, 1.0, T_FURNACE_TOL);
            }
            /* pixels whose samples all agree: the moments agree with the colour */
            if (fabs(v - T_FURNACE_ALBEDO) <= T_FURNACE_TOL || fabs(v - 1.0) <= T_FURNACE_TOL)
                CHECK_NEAR(mu1[i * 4], v, T_FURNACE_TOL);
        }
        printf("  furnace: %u sphere pixels, %u of them exactly 0.5; %u background\n", sphere,
               exact, background);
        CHECK_EQ_INT(out_of_range, 0);
        CHECK(sphere >= T_MIN_SPHERE_PIXELS && background > 0);
        CHECK(exact > sphere * 3 / 4); /* the rest: silhouette pixels, mixed */
        free(c);
        free(depth);
        free(mu1);
    }
    xrsc_renderer_destroy(&r);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}

#define T_ALBEDO_SIZE 32u
#define T_ALBEDO_FRAMES 4u
#define T_ALBEDO_STEP_M 0.01f /* sideways head step per frame */

/** Renders T_ALBEDO_FRAMES frames of the Cornell box with TAA and the moments blend (the
 *  replay's defaults); every_frame: reads the albedo after each frame (so the frames after
 *  the first make it in their reconstruction). Then reads both eyes' albedo and colour. */
static void render_albedo(xrsc_context *ctx, xrsc_scene *scene, bool every_frame, float *albedo,
                          float *color)
{
    size_t n = (size_t)T_ALBEDO_SIZE * T_ALBEDO_SIZE, bytes = n * 16;
    xrsc_renderer *r = NULL;
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SAMPLECACHE,
                                .width = T_ALBEDO_SIZE,
                                .height = T_ALBEDO_SIZE,
                                .blend = XRSC_BLEND_MOMENTS,
                                .taa = {.mode = XRSC_TAA_ON}};
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &ro, &r, NULL), XRSC_OK);
    if (!r)
        return;
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    for (uint32_t k = 0; k < T_ALBEDO_FRAMES; k++) {
        XrPosef head = info.viewpoint, eyes[2];
        head.position.x += T_ALBEDO_STEP_M * (float)k;
        xrsc_headset_eye_poses(&hs, head, eyes);
        xrsc_frame f = {.frame_index = k};
        for (int e = 0; e < 2; e++)
            f.views[e] = (xrsc_view){.pose = eyes[e], .fov = hs.fov[e]};
        CHECK_EQ_INT(xrsc_renderer_render(r, &f), XRSC_OK);
        if (every_frame && k + 1 < T_ALBEDO_FRAMES)
            CHECK_EQ_INT(xrsc_renderer_read(r, 0, XRSC_OUTPUT_ALBEDO, albedo, bytes), XRSC_OK);
    }
    for (uint32_t e = 0; e < 2; e++) { /* the albedo first: the colour must stay the frame's */
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_ALBEDO, albedo + e * n * 4, bytes),
                     XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, color + e * n * 4, bytes),
                     XRSC_OK);
    }
    xrsc_renderer_destroy(&r);
}

/* Issue 19: the frame's reconstruction leaves the albedo out unless it was read after the
 * frame before; a read of it then runs the reconstruction for the albedo alone. Both ways
 * must give the same bits, and the later pass must not touch the colour (TAA and the blend
 * changed it after the reconstruction). */
static void test_albedo_on_read(void)
{
    xrsc_context *ctx = NULL;
    xrsc_scene *scene = NULL;
    xrsc_context_options co = {.validation = true};
    CHECK_EQ_INT(xrsc_context_create(&co, &ctx, NULL), XRSC_OK);
    if (!ctx)
        return;
    CHECK_EQ_INT(xrsc_scene_load(ctx, t_source_path("scenes/cornell.gltf"), NULL, &scene, NULL),
                 XRSC_OK);
    size_t floats = 2u * T_ALBEDO_SIZE * T_ALBEDO_SIZE * 4u;
    float *a_frame = calloc(floats, 4), *c_frame = calloc(floats, 4);
    float *a_read = calloc(floats, 4), *c_read = calloc(floats, 4);
    if (scene && a_frame && c_frame && a_read && c_read) {
        render_albedo(ctx, scene, true, a_frame, c_frame);
        render_albedo(ctx, scene, false, a_read, c_read);
        uint32_t in_range = 0, positive = 0;
        for (size_t i = 0; i < floats; i++) {
            in_range += a_read[i] >= 0.0f && a_read[i] <= 1.0f;
            positive += a_read[i] > 0.0f;
        }
        printf("  albedo: %u of %zu floats in [0, 1], %u positive\n", in_range, floats, positive);
        CHECK(in_range == floats);
        CHECK(positive > floats / 2); /* an image, not the cleared one */
        CHECK(memcmp(a_frame, a_read, floats * 4) == 0);
        CHECK(memcmp(c_frame, c_read, floats * 4) == 0);
    }
    free(a_frame);
    free(c_frame);
    free(a_read);
    free(c_read);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}

int main(void)
{
    RUN(test_edge_test_synthetic);
    RUN(test_formulas_on_device);
    RUN(test_replay_1pass);
    RUN(test_replay_2pass_adaptive_shading);
    RUN(test_replay_multi_no_cache);
    RUN(test_replay_single_fixed_alpha);
    RUN(test_furnace_exact);
    RUN(test_albedo_on_read);
    return t_finish();
}
