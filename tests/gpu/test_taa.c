// SPDX-License-Identifier: MIT
/**
 * @file test_taa.c
 * @brief The TAA post-pass ([YLS20] as seed 000 §5.1 uses it, seed 004 §4.2 weights) and
 *        method `taa`, under the validation layer (zero errors asserted).
 *
 * 1. Still view, method `taa`, 2 x 64 x 64, T_FRAMES frames (Cornell: T_CORNELL_FRAMES),
 *    against a T_REF_SPP x T_REF_FRAMES (Cornell: T_CORNELL_REF_FRAMES) `spp` reference
 *    (accumulated): relMSE (eps 1e-2, every pixel of both eyes) with TAA off, on and pfj23.
 *    - scenes/furnace.gltf: the sphere's radiance is exactly 0.5 and the background 1, so the
 *      only error is the edge coverage each frame's jitter samples (antialiasing). With
 *      alpha = 0.1 and a history that stays valid, the output is an exponential moving average
 *      of the frames; for i.i.d. frames its variance settles at alpha / (2 - alpha) = 0.053 of
 *      one frame's, and the 16 stratified Halton offsets do better than i.i.d. jitter.
 *      Asserted: relMSE(on) < T_ON_RATIO x relMSE(off), T_ON_RATIO = 0.1 (0.053 with room for
 *      the clipping bias at silhouettes and the reference's own error; measured 0.041, 0.031
 *      before the resolve moved to c / (1 + Y), issue 19).
 *    - scenes/cornell.gltf (1-spp path-tracing noise, heavy-tailed): asserted only that on and
 *      pfj23 lower the error; measured on 0.009 x off and pfj23 0.010 x off after 32 frames
 *      against 128 spp (0.034 x and 0.036 x after 64 frames against 512 spp; 0.46 x and
 *      0.065 x when the resolve was in linear radiance: YCoCg clipping with gamma = 1 kept
 *      clipping a converged history towards a noisy 3 x 3 box whose fireflies and light panel
 *      dominated it, TAA's weakness under Monte Carlo noise, seed 004 §2).
 *    Both: relMSE(pfj23) < relMSE(off).
 * 2. Reprojection exactness: `primary` (deterministic albedo), frame 0, then every eye turned
 *    by T_TURN_PX pixels' worth about its own vertical axis (and, second case, also moved
 *    T_SHIFT_M sideways): the reprojected history (debug image) equals a CPU reprojection of
 *    frame 0 (double precision: pixel centre at its depth -> frame 0's view, bilinear taps with
 *    the pass's surface test: same instance and depth near a tap) to T_EXACT_TOL, and equals
 *    the current frame where the taps are flat; the accept/reject decisions agree with the
 *    CPU's (those within 1e-3 of the threshold excepted, at most 0.5 % may differ).
 * 3. Disocclusion with instance motion: a quad moves in front of a wall between two frames;
 *    wall pixels the quad uncovered are rejected (output = current frame exactly), quad pixels
 *    are reprojected with the quad's motion (accepted, history = current colour).
 * 4. PFJ23: per-pixel weights finite and in [0, 1] on a still noisy view, history kept.
 * 5. No light ring (issue 19): after a turn and a move, white-wall pixels next to the Cornell
 *    light panel reproject a history of the wall's colour exactly (taps accepted through a
 *    neighbour's surface test read that neighbour, not the panel).
 * 6. A bright emitter under motion (issue 19): Cornell box, `spp` 8 spp per frame, 12 frames
 *    turning and moving: relMSE of the last frame with TAA on and pfj23 at most
 *    T_EMIT_RATIO x without (measured 0.09 x and 0.12 x; at 16 spp 0.21 x and 0.28 x, on
 *    0.29 x before the untrusted history alpha; 7.4 x and 5.1 x with the resolve in linear
 *    radiance, the light panel leaking into the ceiling beside it).
 * 7. Edges and texture under a slow pan (issue 19), `primary` (exact frames), 12 frames of a
 *    0.45 px/frame turn, relMSE of the TAA output against the current frame: over
 *    scenes/edges.gltf at most T_PAN_EDGE_MAX (history of another surface beside an edge
 *    weighs as XS_TF_UNTRUSTED_ALPHA says), over the textured scenes/disocclusion.gltf
 *    Catmull-Rom at most T_PAN_CR_RATIO x bilinear.
 * Also: first frame and after reset: no history (output = current); pass order tlas, trace,
 * taa, blend.
 */
#include "gpu_scene.h"
#include "mt_method.h"
#include "sc_scene.h"
#include "t_context.h"
#include "t_render.h"
#include "test_samplecache_util.h"
#include "testing.h"
#include "tf_taa.h"
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_math.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_W 64u
#define T_H 64u
#define T_FRAMES 64u  /* still-view frames of the convergence case (0.9^64 < 1e-3) */
#define T_REF_SPP 64u /* reference: T_REF_FRAMES x T_REF_SPP accumulated */
#define T_REF_FRAMES 8u
/* issue 22 (test time): the Cornell cases, whose path-traced reference was most of the test's
 * CPU time, use a 128-spp reference, and the still view 32 frames (0.9^32 = 0.03: only
 * on < off and pfj23 < off are asserted there); margins in tests/times.md */
#define T_CORNELL_REF_FRAMES 2u
#define T_CORNELL_FRAMES 32u
#define T_EMIT_REF_FRAMES 2u
#define T_ON_RATIO 0.1
#define T_TURN_PX 3.0   /* head turn between the two frames, pixels at the image centre */
#define T_SHIFT_M 0.05f /* sideways move of the translation case */
#define T_EXACT_TOL 1e-3
#define T_FLAT_TOL 1e-5
#define T_RING_TURN_PX 2.5   /* the light-ring case's turn: taps straddle the panel's rim */
#define T_RING_PX 2          /* the ring's width around the panel (the fault's 1-2 px) */
#define T_WALL_ALBEDO 0.75f  /* scenes/cornell.gltf: material "white" (ceiling) */
#define T_LIGHT_ALBEDO 0.78f /* material "light" (the panel's base colour) */
/* the emitter case: spp per frame (noise well below the leak's; issue 22: 8, was 16) */
#define T_EMIT_SPP 8u
#define T_EMIT_FRAMES 12u    /* frames in motion (history of ~10 frames at alpha 0.1) */
#define T_EMIT_TURN_PX 0.7   /* turn per frame, pixels at the image centre */
#define T_EMIT_SHIFT_M 0.01f /* sideways move per frame */
#define T_EMIT_RATIO 1.0     /* relMSE with a temporal filter <= this x without */
#define T_PAN_FRAMES 12u     /* the pan cases: frames of a slow head turn */
#define T_PAN_PX 0.45        /* turn per frame, pixels at the image centre (fraction ~0.5) */
#define T_PAN_EDGE_MAX 0.4   /* edges: relMSE bound (measured 0.25; 0.64 before the fix) */
#define T_PAN_CR_RATIO 0.85  /* texture: relMSE Catmull-Rom <= this x bilinear (0.75) */
#define T_PAN_MOTION_RATIO 0.4 /* texture: relMSE motion rule on <= this x off (0.18) */
#define T_PAN_ALPHA_TOL 0.05   /* the pan's mean alpha with the rule: XS_TF_MOTION_ALPHA +- */
#define T_STILL_ALPHA_TOL 1e-3 /* a still view's alpha with the rule: alpha +- */
#define T_EDGE_ALPHA_TOL 1e-5  /* motion rule "edges": its alpha against on's / off's */
#define T_EDGE_LUMA_MARGIN 1e-4 /* pixels this close to their neighbourhood's mean: not checked */
#define T_EDGE_MIN_PX 20u      /* dark-side edge pixels the rule must raise (both eyes) */
#define T_EDGE_RATIO 0.85 /* samplecache, Cornell in motion: relMSE edges <= this x off (0.60) */
#define T_BLEND_INST_RATIO 0.93 /* ... moments blend: instance test on <= this x off (0.86) */

/* ---- 1. still view through the public API ---- */

static double relmse(const float *x, const float *ref, size_t pixels)
{
    double s = 0.0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)x[4 * i + c] - ref[4 * i + c];
            s += d * d / ((double)ref[4 * i + c] * ref[4 * i + c] + XRSC_METRICS_RELMSE_EPSILON);
        }
    return s / (3.0 * (double)pixels);
}

/** Still view of scene_path: relMSE of method `taa` with TAA off, on and pfj23 against the
 *  reference; on must stay below on_ratio x off (0: only below off), pfj23 below off. */
static void still_view_case(const char *scene_path, double on_ratio, uint32_t ref_frames,
                            uint32_t frames)
{
    xrsc_context *ctx = t_context_open();
    CHECK(ctx != NULL);
    xrsc_scene *scene = ctx ? t_scene_load(ctx, t_source_path(scene_path)) : NULL;
    if (!scene) {
        xrsc_context_destroy(&ctx);
        return;
    }
    xrsc_frame f = tsc_viewpoint_frame(scene);
    size_t pixels = 2u * T_W * T_H;
    float *ref = calloc(pixels * 4, sizeof(float)), *img = calloc(pixels * 4, sizeof(float));

    xrsc_renderer_options ro = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SPP};
    ro.spp.samples_per_pixel = T_REF_SPP;
    ro.spp.accumulate = true;
    bool ok = t_render(ctx, scene, &ro, &f, &(t_render_job){.frames = ref_frames}, ref);

    static const xrsc_taa_mode modes[] = {XRSC_TAA_OFF, XRSC_TAA_DEFAULT, XRSC_TAA_PFJ23};
    static const char *const names[] = {"off", "on (default)", "pfj23"};
    double err[3] = {0};
    for (int k = 0; k < 3 && ok; k++) {
        xrsc_renderer_options to = {.width = T_W, .height = T_H, .method = XRSC_METHOD_TAA};
        to.taa.mode = modes[k];
        xrsc_pass_timing tm[XRSC_MAX_PASSES];
        t_render_job job = {.frames = frames, .timings = tm};
        ok = t_render(ctx, scene, &to, &f, &job, img);
        uint32_t n = job.timing_count;
        err[k] = relmse(img, ref, pixels);
        printf("  %s: taa %-12s relMSE %.5f after %u frames (reference %u spp)\n", scene_path,
               names[k], err[k], frames, T_REF_SPP * ref_frames);
        /* passes: tlas, trace, then taa unless off */
        CHECK_EQ_INT(n, k == 0 ? 2 : 3);
        if (n == 3)
            CHECK(strcmp(tm[2].name, TF_PASS_TAA) == 0);
    }
    if (ok) {
        printf("  relMSE on / off = %.3f (bound %.2f; EMA of i.i.d. frames %.3f), pfj23 / off "
               "= %.3f\n",
               err[1] / err[0], on_ratio > 0.0 ? on_ratio : 1.0, 0.1 / 1.9, err[2] / err[0]);
        CHECK(err[1] < (on_ratio > 0.0 ? on_ratio : 1.0) * err[0]);
        CHECK(err[2] < err[0]);
    }

    /* TAA after another method, then the stereo blend: pass order */
    xrsc_renderer_options po = {
        .width = T_W, .height = T_H, .method = XRSC_METHOD_PRIMARY, .blend = XRSC_BLEND_PFJ23};
    po.taa.mode = XRSC_TAA_ON;
    xrsc_pass_timing tm[XRSC_MAX_PASSES];
    t_render_job job = {.frames = 2, .timings = tm};
    if (t_render(ctx, scene, &po, &f, &job, img)) {
        uint32_t n = job.timing_count;
        CHECK_EQ_INT(n, 4);
        if (n == 4)
            CHECK(!strcmp(tm[1].name, "trace") && !strcmp(tm[2].name, TF_PASS_TAA) &&
                  !strcmp(tm[3].name, "blend"));
    }
    /* options out of range */
    xrsc_renderer *bad = NULL;
    xrsc_diag diag = {0};
    po.taa.alpha = 1.5f;
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &po, &bad, &diag), XRSC_ERROR_INVALID_ARGUMENT);
    po.taa.alpha = 0.0f;
    po.taa.mode = (xrsc_taa_mode)7;
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &po, &bad, &diag), XRSC_ERROR_INVALID_ARGUMENT);
    po.taa.mode = XRSC_TAA_ON;
    po.taa.motion_alpha = 1.5f;
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &po, &bad, &diag), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(!strcmp(diag.field, "taa.motion"));
    CHECK(bad == NULL);

    free(ref);
    free(img);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}

static void test_still_view_furnace(void)
{
    still_view_case("scenes/furnace.gltf", T_ON_RATIO, T_REF_FRAMES, T_FRAMES);
}
static void test_still_view_cornell(void)
{
    still_view_case("scenes/cornell.gltf", 0.0, T_CORNELL_REF_FRAMES, T_CORNELL_FRAMES);
}

/* ---- internal rig: a method + the TAA pass with its debug images ---- */

typedef struct t_rig {
    gpu_context *gpu;
    sc_scene *cpu;
    gpu_scene *gs;
    mt_method *m;
    tf_taa *taa;
    mt_post post;
} t_rig;

static void rig_post(void *user, VkCommandBuffer cmd, gpu_timer *timer, const xs_frame *xf)
{
    tf_taa_cmd_record((tf_taa *)user, cmd, timer, xf);
}

static bool rig_open_set(t_rig *r, const char *scene_path, xrsc_method method,
                         const tf_settings *set_in)
{
    memset(r, 0, sizeof(*r));
    gpu_context_options go = {.validation = true};
    xrsc_diag diag = {0};
    xrsc_result res = gpu_context_create(&go, &r->gpu, &diag);
    if (res == XRSC_OK)
        res = sc_scene_load(scene_path, NULL, &r->cpu, &diag);
    if (res == XRSC_OK)
        res = gpu_scene_create(r->gpu, r->cpu, &r->gs, &diag);
    mt_env env = {.gpu = r->gpu,
                  .scene = r->gs,
                  .cpu_scene = r->cpu,
                  .width = T_W,
                  .height = T_H,
                  .post = &r->post};
    if (res == XRSC_OK)
        res = method == XRSC_METHOD_TAA ? mt_taa_create(&env, NULL, &r->m, &diag)
                                        : mt_primary_create(&env, &r->m, &diag);
    if (res == XRSC_OK) {
        tf_settings set = *set_in;
        set.debug = true;
        tf_images imgs = {mt_method_output_image(r->m, XRSC_OUTPUT_COLOR),
                          mt_method_output_image(r->m, XRSC_OUTPUT_DEPTH),
                          mt_method_output_image(r->m, XRSC_OUTPUT_HIT_ID)};
        res = tf_taa_create(r->gpu, r->gs, r->cpu->instance_count, T_W, T_H, &set, &imgs, &r->taa,
                            &diag);
    }
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK) {
        tsc_print_diag(&diag);
        return false;
    }
    CHECK(r->gpu->validation);
    r->post = (mt_post){.record = rig_post, .user = r->taa};
    return true;
}

static bool rig_open_with(t_rig *r, const char *scene_path, xrsc_method method, xrsc_taa_mode mode,
                          xrsc_taa_history history)
{
    tf_settings set = {.mode = mode, .history = history};
    return rig_open_set(r, scene_path, method, &set);
}

static bool rig_open(t_rig *r, const char *scene_path, xrsc_method method, xrsc_taa_mode mode)
{
    return rig_open_with(r, scene_path, method, mode, XRSC_TAA_HISTORY_DEFAULT);
}

static void rig_close(t_rig *r)
{
    tf_taa_destroy(&r->taa);
    mt_method_destroy(&r->m);
    if (r->gs)
        gpu_scene_destroy(r->gpu, &r->gs);
    sc_scene_destroy(&r->cpu);
    if (r->gpu) {
        CHECK_EQ_INT(r->gpu->validation_errors, 0);
        gpu_context_destroy(&r->gpu);
    }
}

static bool rig_render(t_rig *r, const xrsc_frame *f)
{
    xrsc_diag diag = {0};
    xrsc_result res = mt_method_render(r->m, f, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    return res == XRSC_OK;
}

/** One eye of the last frame: the method's output (after TAA) or a TAA image. */
typedef struct t_eye {
    float out[T_W * T_H * 4], src[T_W * T_H * 4], aux[T_W * T_H * 4], reproj[T_W * T_H * 4];
    float depth[T_W * T_H];
    uint32_t hitid[T_W * T_H * 4];
} t_eye;

static bool rig_read(t_rig *r, uint32_t eye, t_eye *out)
{
    xrsc_diag diag = {0};
    xrsc_result res =
        mt_method_read(r->m, eye, XRSC_OUTPUT_COLOR, out->out, sizeof(out->out), &diag);
    if (res == XRSC_OK)
        res = mt_method_read(r->m, eye, XRSC_OUTPUT_DEPTH, out->depth, sizeof(out->depth), &diag);
    if (res == XRSC_OK)
        res = mt_method_read(r->m, eye, XRSC_OUTPUT_HIT_ID, out->hitid, sizeof(out->hitid), &diag);
    if (res == XRSC_OK)
        res = tf_taa_read(r->taa, eye, TF_IMAGE_SRC, out->src, sizeof(out->src), &diag);
    if (res == XRSC_OK)
        res = tf_taa_read(r->taa, eye, TF_IMAGE_AUX, out->aux, sizeof(out->aux), &diag);
    if (res == XRSC_OK)
        res = tf_taa_read(r->taa, eye, TF_IMAGE_REPROJ, out->reproj, sizeof(out->reproj), &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    return res == XRSC_OK;
}

/** The output equals the current frame wherever the status is not "blended". */
static uint32_t count_status(const t_eye *e, float status, bool check_current)
{
    uint32_t n = 0;
    for (uint32_t p = 0; p < T_W * T_H; p++) {
        if (e->aux[4 * p + 3] != status)
            continue;
        n++;
        if (check_current)
            CHECK(memcmp(&e->out[4 * p], &e->src[4 * p], 4 * sizeof(float)) == 0);
    }
    return n;
}

/** Whether the current 3 x 3 neighbourhood of p (inside the image) has one colour. */
static bool flat3(const t_eye *e, uint32_t p)
{
    int x = (int)(p % T_W), y = (int)(p / T_W);
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++) {
            int qx = x + i, qy = y + j;
            if (qx < 0 || qy < 0 || qx >= (int)T_W || qy >= (int)T_H ||
                memcmp(&e->src[4 * ((uint32_t)qy * T_W + (uint32_t)qx)], &e->src[4 * p],
                       3 * sizeof(float)) != 0)
                return false;
        }
    return true;
}

/* ---- CPU reprojection (double) ---- */

typedef struct t_cam {
    double view[16], view_inv[16]; /* from the same float matrices as the GPU's */
    double tan[4];                 /* left, right, up, down */
} t_cam;

static t_cam make_cam(const xrsc_view *v)
{
    t_cam c;
    float m[16];
    xrsc_pose_view_matrix(v->pose, m);
    for (int i = 0; i < 16; i++)
        c.view[i] = m[i];
    xrsc_pose_to_matrix(v->pose, m);
    for (int i = 0; i < 16; i++)
        c.view_inv[i] = m[i];
    c.tan[0] = tanf(v->fov.angleLeft);
    c.tan[1] = tanf(v->fov.angleRight);
    c.tan[2] = tanf(v->fov.angleUp);
    c.tan[3] = tanf(v->fov.angleDown);
    return c;
}

static void xform(const double m[16], const double p[3], double w, double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r] * w;
}

/**
 * Where the point (hit, w = 1) or direction (miss, w = 0) seen at pixel p's centre of cam1 at
 * depth d lies in cam0's image (pixels), moved back by -shift (the instance's motion) first;
 * *d_exp its depth there. False behind cam0.
 */
static bool cpu_reproject(const t_cam *c1, const t_cam *c0, uint32_t p, float d, bool hit,
                          const double shift[3], double pos[2], double *d_exp)
{
    double u = ((p % T_W) + 0.5) / T_W, v = ((p / T_W) + 0.5) / T_H;
    double de[3] = {c1->tan[0] + (c1->tan[1] - c1->tan[0]) * u,
                    c1->tan[2] + (c1->tan[3] - c1->tan[2]) * v, -1.0};
    double w[3], q[3];
    if (hit) {
        double pe[3] = {de[0] * d, de[1] * d, de[2] * d};
        xform(c1->view_inv, pe, 1.0, w);
        for (int i = 0; i < 3; i++)
            w[i] -= shift[i];
    } else {
        xform(c1->view_inv, de, 0.0, w);
    }
    xform(c0->view, w, hit ? 1.0 : 0.0, q);
    if (!(q[2] < 0.0))
        return false;
    pos[0] = (q[0] / -q[2] - c0->tan[0]) / (c0->tan[1] - c0->tan[0]) * T_W;
    pos[1] = (q[1] / -q[2] - c0->tan[2]) / (c0->tan[3] - c0->tan[2]) * T_H;
    *d_exp = -q[2];
    return true;
}

static uint32_t inst_at(const t_eye *e, uint32_t p)
{
    return e->depth[p] > 0.0f ? e->hitid[4 * p] : XS_MISS_INSTANCE;
}

/** taa.comp's depth tolerance at pixel p of the current frame for an expected depth d_exp. */
static double cpu_tolerance(const t_eye *cur, uint32_t p, double d_exp)
{
    uint32_t inst = inst_at(cur, p), x = p % T_W, y = p / T_W;
    double slope = 0.0;
    const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
    for (int k = 0; k < 4; k++) {
        int qx = (int)x + dx[k], qy = (int)y + dy[k];
        if (qx < 0 || qy < 0 || qx >= (int)T_W || qy >= (int)T_H)
            continue;
        uint32_t q = (uint32_t)qy * T_W + (uint32_t)qx;
        if (inst_at(cur, q) == inst)
            slope = fmax(slope, fabs((double)cur->depth[q] - cur->depth[p]));
    }
    return XS_TF_DEPTH_TOLERANCE * d_exp + XS_TF_SLOPE_PX * slope;
}

/** Whether the last frame's pixel (x, y) showed instance inst at depth d_exp +- tol. */
static bool cpu_same_surface(const t_eye *prev, int x, int y, uint32_t inst, double d_exp,
                             double tol)
{
    if (x < 0 || y < 0 || x >= (int)T_W || y >= (int)T_H)
        return false;
    uint32_t q = (uint32_t)y * T_W + (uint32_t)x;
    return inst_at(prev, q) == inst &&
           (inst == XS_MISS_INSTANCE || fabs(prev->depth[q] - d_exp) <= tol);
}

/** YCoCg luma of c, floored at 0 (taa.comp's resolve space). */
static double resolve_luma(const double c[3])
{
    return fmax(0.25 * c[0] + 0.5 * c[1] + 0.25 * c[2], 0.0);
}

/** The pass's validation and bilinear history on the CPU (taa.comp step 2: a tap counts when
 *  the surface was at it or one of its 8 neighbours, and is read where it was unless its
 *  footprint holds pos; the mean is taken over c / (1 + Y) and inverted, XS_TF_TONEMAP_FLOOR);
 *  returns the accepted weight and (when
 *  > 0) the history in out[3]; *all4 when every tap was accepted, *flat when they all have
 *  the same colour. */
static double cpu_history(const t_eye *prev, const double pos[2], uint32_t inst, double d_exp,
                          double tol, double out[3], bool *all4, bool *flat)
{
    double bx = pos[0] - 0.5, by = pos[1] - 0.5;
    int x0 = (int)floor(bx), y0 = (int)floor(by);
    double fx = bx - x0, fy = by - y0, wsum = 0.0;
    out[0] = out[1] = out[2] = 0.0;
    *all4 = true;
    *flat = true;
    const float *first = NULL;
    for (int k = 0; k < 4; k++) {
        int ox = k & 1, oy = k >> 1, x = x0 + ox, y = y0 + oy;
        double w = (ox ? fx : 1.0 - fx) * (oy ? fy : 1.0 - fy);
        bool ok = x >= 0 && y >= 0 && x < (int)T_W && y < (int)T_H;
        /* the tap itself first, then its neighbours in row order; the history is read where
         * the surface was found, or at the tap when its footprint holds pos */
        bool near = ok && cpu_same_surface(prev, x, y, inst, d_exp, tol);
        bool home = x == (int)floor(pos[0]) && y == (int)floor(pos[1]);
        int sx = x, sy = y;
        for (int n = 0; n < 9 && ok && !near; n++) {
            int qx = x + n % 3 - 1, qy = y + n / 3 - 1;
            near = n != 4 && cpu_same_surface(prev, qx, qy, inst, d_exp, tol);
            if (near && !home) {
                sx = qx;
                sy = qy;
            }
        }
        if (!ok || !near) {
            *all4 = false;
            continue;
        }
        const float *c = &prev->out[4 * ((uint32_t)sy * T_W + (uint32_t)sx)];
        if (first && memcmp(first, c, 3 * sizeof(float)) != 0)
            *flat = false;
        first = first ? first : c;
        double cd[3] = {c[0], c[1], c[2]}, lum = resolve_luma(cd);
        for (int i = 0; i < 3; i++)
            out[i] += w * cd[i] / (1.0 + lum);
        wsum += w;
    }
    if (wsum > 0.0) {
        for (int i = 0; i < 3; i++)
            out[i] /= wsum;
        double yt = resolve_luma(out), inv = fmax(1.0 - yt, XS_TF_TONEMAP_FLOOR);
        for (int i = 0; i < 3; i++)
            out[i] /= inv;
    }
    return wsum;
}

/* ---- 2. reprojection exactness for a known camera motion ---- */

static void check_first_frame(const t_eye *e)
{
    CHECK_EQ_INT(count_status(e, XS_TF_STATUS_NO_HISTORY, true), T_W * T_H);
}

/** Frame 1: frame 0 with every eye turned by turn_px pixels' worth about its own vertical
 *  axis, then moved shift_m sideways. */
static xrsc_frame moved_frame(const xrsc_frame *f0, double turn_px, float shift_m)
{
    xrsc_frame f1 = *f0;
    f1.frame_index = f0->frame_index + 1;
    for (int e = 0; e < 2; e++) {
        const XrFovf *fov = &f0->views[e].fov;
        double px_tan = (tan(fov->angleRight) - tan(fov->angleLeft)) / T_W;
        float turn = (float)atan(turn_px * px_tan);
        XrPosef *p = &f1.views[e].pose;
        p->orientation = xrsc_quat_normalize(
            xrsc_quat_mul(p->orientation, xrsc_quat_from_axis_angle((XrVector3f){0, 1, 0}, turn)));
        XrVector3f side = xrsc_quat_rotate(p->orientation, (XrVector3f){shift_m, 0, 0});
        p->position.x += side.x;
        p->position.y += side.y;
        p->position.z += side.z;
    }
    return f1;
}

static void camera_motion_case(bool translate)
{
    t_rig r;
    if (!rig_open(&r, t_source_path("scenes/cornell.gltf"), XRSC_METHOD_PRIMARY, XRSC_TAA_ON)) {
        rig_close(&r);
        return;
    }
    XrPosef head = tsc_viewpoint(r.cpu);
    xrsc_frame f0 = tsc_headset_frame(head, 0);
    xrsc_frame f1 = moved_frame(&f0, T_TURN_PX, translate ? T_SHIFT_M : 0.0f);
    t_eye *prev = calloc(2, sizeof(t_eye)), *cur = calloc(2, sizeof(t_eye));
    bool ok = rig_render(&r, &f0) && rig_read(&r, 0, &prev[0]) && rig_read(&r, 1, &prev[1]);
    if (ok) {
        check_first_frame(&prev[0]);
        check_first_frame(&prev[1]);
    }
    ok = ok && rig_render(&r, &f1) && rig_read(&r, 0, &cur[0]) && rig_read(&r, 1, &cur[1]);
    uint32_t compared = 0, flat = 0, decided = 0, disagree = 0, rejected = 0;
    double max_err = 0.0, max_flat_err = 0.0;
    static const double no_shift[3] = {0, 0, 0};
    for (int e = 0; e < 2 && ok; e++) {
        t_cam c0 = make_cam(&f0.views[e]), c1 = make_cam(&f1.views[e]);
        const t_eye *a = &prev[e], *b = &cur[e];
        for (uint32_t p = 0; p < T_W * T_H; p++) {
            uint32_t inst = inst_at(b, p);
            double pos[2], d_exp = 0.0, h[3] = {0};
            bool all4 = false, is_flat = false;
            double w = 0.0;
            if (cpu_reproject(&c1, &c0, p, b->depth[p], inst != XS_MISS_INSTANCE, no_shift, pos,
                              &d_exp))
                w = cpu_history(a, pos, inst, d_exp, cpu_tolerance(b, p, d_exp), h, &all4,
                                &is_flat);
            bool gpu_blended = b->aux[4 * p + 3] == XS_TF_STATUS_BLENDED;
            rejected += b->aux[4 * p + 3] == XS_TF_STATUS_REJECTED;
            /* decisions near the threshold may flip with float rounding */
            if (fabs(w - XS_TF_MIN_WEIGHT) > 1e-3) {
                decided++;
                disagree += gpu_blended != (w >= XS_TF_MIN_WEIGHT);
            }
            if (!gpu_blended || !all4)
                continue;
            compared++;
            for (int i = 0; i < 3; i++)
                max_err = fmax(max_err, fabs(b->reproj[4 * p + i] - h[i]));
            if (is_flat) {
                flat++;
                for (int i = 0; i < 3; i++)
                    max_flat_err =
                        fmax(max_flat_err, fabs(b->reproj[4 * p + i] - b->src[4 * p + i]));
            }
        }
        count_status(b, XS_TF_STATUS_REJECTED, true);
    }
    printf("  %s: %u px compared (%u flat), max |GPU - CPU| %.2g, max |history - current| on "
           "flat taps %.2g, %u/%u decisions differ, %u rejected\n",
           translate ? "turn + move" : "turn", compared, flat, max_err, max_flat_err, disagree,
           decided, rejected);
    CHECK(compared > 2u * T_W * T_H * 7u / 10u);
    CHECK(flat > 2u * T_W * T_H / 4u);
    CHECK(max_err <= T_EXACT_TOL);
    CHECK(max_flat_err <= T_FLAT_TOL);
    CHECK(disagree <= decided / 200u);
    CHECK(rejected > 0); /* the image border the turn brought in */
    /* reset: no history again */
    tf_taa_reset(r.taa);
    if (ok && rig_render(&r, &f1) && rig_read(&r, 0, &cur[0]))
        check_first_frame(&cur[0]);
    free(prev);
    free(cur);
    rig_close(&r);
}

static void test_reprojection_turn(void)
{
    camera_motion_case(false);
}
static void test_reprojection_turn_and_move(void)
{
    camera_motion_case(true);
}

/* ---- 3. disocclusion with a moving instance ---- */

/** A glTF of a wall and a quad in front of it that moves right by `move` over 1 s. */
static const char *moving_quad_scene(void)
{
    /* buffer: per quad 4 positions + 4 normals (96 B), u16 indices (12 B), times (8 B),
     * translations at t = 0 and 1 (24 B) */
    enum { QUADS = 2 };
    static const float half[QUADS] = {4.0f, 0.3f};
    static const float pos[QUADS][3] = {{0, 0, -4}, {-0.3f, 0, -1.5f}};
    static const float col[QUADS][3] = {{0.2f, 0.4f, 0.6f}, {0.9f, 0.1f, 0.1f}};
    uint8_t buf[QUADS * 96 + 12 + 8 + 24];
    size_t off = 0;
    for (int i = 0; i < QUADS; i++) {
        float h = half[i];
        float p[12] = {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0};
        float n[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
        memcpy(buf + off, p, 48);
        memcpy(buf + off + 48, n, 48);
        off += 96;
    }
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    memcpy(buf + off, idx, 12);
    const float times[2] = {0.0f, 1.0f};
    memcpy(buf + off + 12, times, 8);
    const float tr[6] = {pos[1][0], pos[1][1], pos[1][2], pos[1][0] + 0.6f, pos[1][1], pos[1][2]};
    memcpy(buf + off + 20, tr, 24);
    char *uri = t_data_uri(buf, sizeof(buf));
    char *json = malloc(8192 + strlen(uri));
    snprintf(
        json, 8192 + strlen(uri),
        "{\"asset\":{\"version\":\"2.0\"},\"extras\":{\"xrsc_environment\":[0.5,0.5,0.5]},"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0,\"translation\":[%g,%g,%g]},"
        "{\"mesh\":1,\"translation\":[%g,%g,%g]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},"
        "\"indices\":4,\"material\":0}]},{\"primitives\":[{\"attributes\":{\"POSITION\":2,"
        "\"NORMAL\":3},\"indices\":4,\"material\":1}]}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[%g,%g,%g,1],"
        "\"metallicFactor\":0}},{\"pbrMetallicRoughness\":{\"baseColorFactor\":[%g,%g,%g,1],"
        "\"metallicFactor\":0}}],"
        "\"accessors\":["
        "{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
        "\"min\":[%g,%g,0],\"max\":[%g,%g,0]},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
        "\"min\":[%g,%g,0],\"max\":[%g,%g,0]},"
        "{\"bufferView\":3,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
        "{\"bufferView\":4,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"},"
        "{\"bufferView\":5,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\","
        "\"min\":[0],\"max\":[1]},"
        "{\"bufferView\":6,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":144,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":192,\"byteLength\":12},"
        "{\"buffer\":0,\"byteOffset\":204,\"byteLength\":8},"
        "{\"buffer\":0,\"byteOffset\":212,\"byteLength\":24}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
        "\"animations\":[{\"samplers\":[{\"input\":5,\"output\":6,\"interpolation\":\"LINEAR\"}],"
        "\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"translation\"}}]}]}",
        pos[0][0], pos[0][1], pos[0][2], pos[1][0], pos[1][1], pos[1][2], col[0][0], col[0][1],
        col[0][2], col[1][0], col[1][1], col[1][2], -half[0], -half[0], half[0], half[0], -half[1],
        -half[1], half[1], half[1], sizeof(buf), uri);
    const char *path = t_temp_file("taa_moving_quad.gltf", json);
    free(json);
    free(uri);
    return path;
}

static void set_time(t_rig *r, double t_s)
{
    sc_scene_evaluate(r->cpu, t_s);
    xrsc_diag diag = {0};
    CHECK_EQ_INT(gpu_scene_stage_instances(r->gpu, r->gs, r->cpu, &diag), XRSC_OK);
}

static void test_disocclusion_moving_instance(void)
{
    t_rig r;
    if (!rig_open(&r, moving_quad_scene(), XRSC_METHOD_PRIMARY, XRSC_TAA_ON)) {
        rig_close(&r);
        return;
    }
    uint32_t mover = UINT32_MAX;
    for (uint32_t i = 0; i < r.cpu->instance_count; i++)
        if (r.cpu->instances[i].animated)
            mover = i;
    CHECK(mover != UINT32_MAX && r.cpu->instance_count == 2);
    XrPosef head = {.orientation = {0, 0, 0, 1}, .position = {0, 0, 0}};
    xrsc_frame f0 = tsc_headset_frame(head, 0), f1 = tsc_headset_frame(head, 1);
    t_eye *prev = calloc(2, sizeof(t_eye)), *cur = calloc(2, sizeof(t_eye));
    double w0[3], w1[3];
    set_time(&r, 0.0);
    for (int i = 0; i < 3; i++)
        w0[i] = r.cpu->instances[mover].world[12 + i];
    bool ok = rig_render(&r, &f0) && rig_read(&r, 0, &prev[0]) && rig_read(&r, 1, &prev[1]);
    set_time(&r, 0.5); /* the quad moves 0.3 m right: ~8 px at 1.5 m */
    for (int i = 0; i < 3; i++)
        w1[i] = r.cpu->instances[mover].world[12 + i];
    double shift[3] = {w1[0] - w0[0], w1[1] - w0[1], w1[2] - w0[2]};
    CHECK(shift[0] > 0.25);
    ok = ok && rig_render(&r, &f1) && rig_read(&r, 0, &cur[0]) && rig_read(&r, 1, &cur[1]);
    static const double no_shift[3] = {0, 0, 0};
    uint32_t uncovered = 0, uncovered_ok = 0, on_mover = 0, mover_ok = 0;
    for (int e = 0; e < 2 && ok; e++) {
        t_cam c = make_cam(&f0.views[e]);
        const t_eye *a = &prev[e], *b = &cur[e];
        for (uint32_t p = 0; p < T_W * T_H; p++) {
            uint32_t inst = inst_at(b, p);
            if (inst == XS_MISS_INSTANCE)
                continue;
            double pos[2], d_exp, h[3];
            bool all4, flat;
            if (!cpu_reproject(&c, &c, p, b->depth[p], true, inst == mover ? shift : no_shift, pos,
                               &d_exp))
                continue;
            int nx = (int)floor(pos[0]), ny = (int)floor(pos[1]);
            if (nx < 1 || ny < 1 || nx >= (int)T_W - 1 || ny >= (int)T_H - 1)
                continue;
            double w =
                cpu_history(a, pos, inst, d_exp, cpu_tolerance(b, p, d_exp), h, &all4, &flat);
            float status = b->aux[4 * p + 3];
            if (inst != mover && w == 0.0) {
                /* wall the quad covered in frame 0 */
                uncovered++;
                uncovered_ok += status == XS_TF_STATUS_REJECTED &&
                                memcmp(&b->out[4 * p], &b->src[4 * p], 16) == 0;
            } else if (inst == mover && all4 && flat) {
                on_mover++;
                bool good = status == XS_TF_STATUS_BLENDED;
                for (int c = 0; c < 3; c++) {
                    good = good && fabsf(b->reproj[4 * p + c] - b->src[4 * p + c]) <= T_FLAT_TOL;
                    /* the output too where clipping cannot touch it (flat 3 x 3) */
                    good = good && (!flat3(b, p) ||
                                    fabsf(b->out[4 * p + c] - b->src[4 * p + c]) <= T_FLAT_TOL);
                }
                mover_ok += good;
            }
        }
        count_status(b, XS_TF_STATUS_REJECTED, true);
    }
    printf("  uncovered wall: %u/%u rejected (= current); moving quad: %u/%u follow its "
           "motion\n",
           uncovered_ok, uncovered, mover_ok, on_mover);
    CHECK(uncovered >= 40u);
    CHECK_EQ_INT(uncovered_ok, uncovered);
    CHECK(on_mover >= 40u);
    CHECK_EQ_INT(mover_ok, on_mover);
    free(prev);
    free(cur);
    rig_close(&r);
}

/* ---- 4. PFJ23 weights ---- */

static void test_pfj23_weights(void)
{
    t_rig r;
    if (!rig_open(&r, t_source_path("scenes/cornell.gltf"), XRSC_METHOD_TAA, XRSC_TAA_PFJ23)) {
        rig_close(&r);
        return;
    }
    XrPosef head = tsc_viewpoint(r.cpu);
    t_eye *e = calloc(1, sizeof(t_eye));
    bool ok = true;
    for (uint32_t i = 0; i < 16 && ok; i++) {
        xrsc_frame f = tsc_headset_frame(head, i);
        ok = rig_render(&r, &f);
    }
    uint32_t blended = 0, bad = 0;
    double mean_alpha = 0.0;
    for (uint32_t eye = 0; eye < 2 && ok && rig_read(&r, eye, e); eye++) {
        blended += count_status(e, XS_TF_STATUS_BLENDED, false);
        count_status(e, XS_TF_STATUS_REJECTED, true);
        for (uint32_t p = 0; p < T_W * T_H; p++)
            for (int c = 0; c < 3; c++) {
                float a = e->aux[4 * p + c];
                bad += !(a >= 0.0f && a <= 1.0f);
                mean_alpha += a;
            }
    }
    mean_alpha /= 2.0 * 3.0 * T_W * T_H;
    printf("  pfj23: %u px blended, mean weight of the current frame %.3f, %u out of [0, 1]\n",
           blended, mean_alpha, bad);
    CHECK_EQ_INT(bad, 0);
    CHECK(blended >= 2u * T_W * T_H * 99u / 100u); /* a still view keeps its history */
    CHECK(mean_alpha < 0.5);                       /* and averages over frames */
    free(e);
    rig_close(&r);
}

/* ---- 5. no light ring: history read where the surface test found the surface ---- */

/** Whether pixel p of e is within T_RING_PX pixels of a light-panel pixel (colour = its albedo). */
static bool near_light(const t_eye *e, uint32_t p)
{
    int x = (int)(p % T_W), y = (int)(p / T_W);
    for (int j = -T_RING_PX; j <= T_RING_PX; j++)
        for (int i = -T_RING_PX; i <= T_RING_PX; i++) {
            int qx = x + i, qy = y + j;
            if (qx >= 0 && qy >= 0 && qx < (int)T_W && qy < (int)T_H &&
                fabsf(e->src[4 * ((uint32_t)qy * T_W + (uint32_t)qx)] - T_LIGHT_ALBEDO) < 1e-6f)
                return true;
        }
    return false;
}

/**
 * Cornell box, `primary` (colour = albedo: white walls T_WALL_ALBEDO, the light panel
 * T_LIGHT_ALBEDO), TAA on, a turn of T_RING_TURN_PX pixels and a sideways move: every
 * accepted white-wall pixel within T_RING_PX of the panel whose point lies, in frame 0, in a
 * pixel that showed the wall has a history of the wall's albedo exactly (to T_FLAT_TOL). A
 * tap on the panel accepted through a wall neighbour's surface test but read from the tap
 * itself (the fault) gives a history between the two. (Where the point lies in a panel
 * pixel, that pixel straddled the rim and its own history is read, as at any edge.)
 */
static void test_no_light_ring(void)
{
    t_rig r;
    if (!rig_open(&r, t_source_path("scenes/cornell.gltf"), XRSC_METHOD_PRIMARY, XRSC_TAA_ON)) {
        rig_close(&r);
        return;
    }
    XrPosef head = tsc_viewpoint(r.cpu);
    xrsc_frame f0 = tsc_headset_frame(head, 0);
    xrsc_frame f1 = moved_frame(&f0, T_RING_TURN_PX, T_SHIFT_M);
    t_eye *prev = calloc(2, sizeof(t_eye)), *cur = calloc(2, sizeof(t_eye));
    uint32_t ring = 0, rim = 0, blended = 0;
    double max_err = 0.0;
    static const double no_shift[3] = {0, 0, 0};
    bool ok = rig_render(&r, &f0) && rig_read(&r, 0, &prev[0]) && rig_read(&r, 1, &prev[1]) &&
              rig_render(&r, &f1) && rig_read(&r, 0, &cur[0]) && rig_read(&r, 1, &cur[1]);
    for (uint32_t e = 0; e < 2 && ok; e++) {
        t_cam c0 = make_cam(&f0.views[e]), c1 = make_cam(&f1.views[e]);
        const t_eye *a = &prev[e], *b = &cur[e];
        for (uint32_t p = 0; p < T_W * T_H; p++) {
            if (fabsf(b->src[4 * p] - T_WALL_ALBEDO) > 1e-6f || !near_light(b, p))
                continue;
            ring++;
            double pos[2], d_exp;
            if (b->aux[4 * p + 3] != XS_TF_STATUS_BLENDED ||
                !cpu_reproject(&c1, &c0, p, b->depth[p], true, no_shift, pos, &d_exp))
                continue;
            int hx = (int)floor(pos[0]), hy = (int)floor(pos[1]);
            if (hx < 0 || hy < 0 || hx >= (int)T_W || hy >= (int)T_H ||
                inst_at(a, (uint32_t)hy * T_W + (uint32_t)hx) != inst_at(b, p)) {
                rim++;
                continue;
            }
            blended++;
            for (int i = 0; i < 3; i++)
                max_err = fmax(max_err, fabs(b->reproj[4 * p + i] - b->src[4 * p + i]));
        }
    }
    printf("  %u white-wall px within %d px of the light panel: %u blended from wall pixels, "
           "max |history - wall| %.3g; %u from the rim's panel pixels\n",
           ring, T_RING_PX, blended, max_err, rim);
    CHECK(ok);
    CHECK(blended > 2u * T_W / 4u); /* the panel's rim, both eyes */
    CHECK(max_err <= T_FLAT_TOL);
    free(prev);
    free(cur);
    rig_close(&r);
}

/* ---- 6. a bright emitter under camera motion (issue 19) ---- */

/** Renders `frames` frames with ro from f0, each turned T_EMIT_TURN_PX and moved T_EMIT_SHIFT_M
 *  from the last (moved_frame), and reads the last frame's colour (both eyes) into out;
 *  *out_last = that frame. */
static bool render_moving(xrsc_context *ctx, xrsc_scene *scene, const xrsc_renderer_options *ro,
                          xrsc_frame f0, uint32_t frames, float *out, xrsc_frame *out_last)
{
    xrsc_renderer *r = NULL;
    xrsc_diag diag = {0};
    char buf[1400];
    xrsc_result res = xrsc_renderer_create(ctx, scene, ro, &r, &diag);
    CHECK_MSG(res == XRSC_OK, "renderer: %s", xrsc_diag_format(&diag, buf, sizeof buf));
    if (res != XRSC_OK)
        return false;
    xrsc_frame f = f0;
    for (uint32_t i = 0; i < frames && res == XRSC_OK; i++) {
        if (i > 0)
            f = moved_frame(&f, T_EMIT_TURN_PX, T_EMIT_SHIFT_M);
        res = xrsc_renderer_render(r, &f);
    }
    size_t layer = (size_t)T_W * T_H * 4;
    for (uint32_t e = 0; e < 2 && res == XRSC_OK; e++)
        res = xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, out + e * layer, layer * sizeof(float));
    CHECK_EQ_INT(res, XRSC_OK);
    xrsc_renderer_destroy(&r);
    *out_last = f;
    return res == XRSC_OK;
}

/**
 * Cornell box (its light panel ~250 x the ceiling's radiance beside it), `spp` at
 * T_EMIT_SPP spp per frame, T_EMIT_FRAMES frames turning and moving sideways every frame:
 * relMSE of the last frame against a still T_REF_SPP x T_EMIT_REF_FRAMES reference of its views
 * with TAA off, on and pfj23. A temporal filter must not raise the error:
 * relMSE(on), relMSE(pfj23) <= T_EMIT_RATIO x relMSE(off). Resolving in linear radiance
 * (before issue 19's fix) leaked the panel into the ceiling around it through the bilinear
 * history and the clipping box that holds the panel too: measured on 7.4 x, pfj23 5.1 x off
 * at 16 spp (then 0.29 x and 0.28 x; 0.21 x and 0.28 x after issue 19's untrusted history alpha;
 * now, at 8 spp, 0.09 x and 0.12 x: off's noise, 0.38, is still well below the leak's ~0.9).
 */
static void test_emitter_motion(void)
{
    xrsc_context *ctx = t_context_open();
    CHECK(ctx != NULL);
    xrsc_scene *scene = ctx ? t_scene_load(ctx, t_source_path("scenes/cornell.gltf")) : NULL;
    if (!scene) {
        xrsc_context_destroy(&ctx);
        return;
    }
    xrsc_frame f0 = tsc_viewpoint_frame(scene), last = f0;
    size_t pixels = 2u * T_W * T_H;
    float *ref = calloc(pixels * 4, sizeof(float)), *img = calloc(pixels * 4, sizeof(float));
    static const xrsc_taa_mode modes[] = {XRSC_TAA_OFF, XRSC_TAA_ON, XRSC_TAA_PFJ23};
    static const char *const names[] = {"off", "on", "pfj23"};
    double err[3] = {0};
    bool ok = true;
    for (int k = 0; k < 3 && ok; k++) {
        xrsc_renderer_options ro = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SPP};
        ro.spp.samples_per_pixel = T_EMIT_SPP;
        ro.taa.mode = modes[k];
        ok = render_moving(ctx, scene, &ro, f0, T_EMIT_FRAMES, img, &last);
        if (ok && k == 0) { /* the reference of the last frame's views */
            xrsc_renderer_options rf = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SPP};
            rf.spp.samples_per_pixel = T_REF_SPP;
            rf.spp.accumulate = true;
            ok = t_render(ctx, scene, &rf, &last, &(t_render_job){.frames = T_EMIT_REF_FRAMES},
                          ref);
        }
        err[k] = relmse(img, ref, pixels);
        printf("  emitter, %u frames in motion: taa %-5s relMSE %.5f\n", T_EMIT_FRAMES, names[k],
               err[k]);
    }
    CHECK(ok);
    if (ok) {
        printf("  relMSE on / off = %.3f, pfj23 / off = %.3f (bound %.2f)\n", err[1] / err[0],
               err[2] / err[0], T_EMIT_RATIO);
        CHECK(err[1] <= T_EMIT_RATIO * err[0]);
        CHECK(err[2] <= T_EMIT_RATIO * err[0]);
    }
    free(ref);
    free(img);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}

/* ---- 7. edges and texture under a slow pan (issue 19) ---- */

/** Mean relMSE over both eyes of the TAA output (mode ON) against the current frame
 *  (`primary`: deterministic albedo at pixel centres, the exact image) after T_PAN_FRAMES
 *  frames of a head turn of T_PAN_PX pixels per frame over scene (a path under the source
 *  tree), with the given history filter; -1 on failure. */
/** Mean alpha (aux rgb) of the blended pixels of e. */
static double mean_blended_alpha(const t_eye *e)
{
    double sum = 0.0;
    uint32_t n = 0;
    for (uint32_t p = 0; p < T_W * T_H; p++)
        if (e->aux[4 * p + 3] == XS_TF_STATUS_BLENDED) {
            sum += e->aux[4 * p];
            n++;
        }
    return n ? sum / n : -1.0;
}

/** A slow pan of T_PAN_FRAMES frames over scene with the `primary` method (exact, noise-free
 *  input) and TAA set: the output's relMSE against the exact frame (both eyes' mean), and in
 *  out_alpha (optional) the mean alpha over the last frame's blended pixels. */
static double pan_error_set(const char *scene, const tf_settings *set, double *out_alpha)
{
    t_rig r;
    if (!rig_open_set(&r, t_source_path(scene), XRSC_METHOD_PRIMARY, set)) {
        rig_close(&r);
        return -1.0;
    }
    t_eye *e = calloc(1, sizeof(t_eye));
    xrsc_frame f0 = tsc_headset_frame(tsc_viewpoint(r.cpu), 0);
    bool ok = e != NULL;
    for (uint32_t k = 0; k < T_PAN_FRAMES && ok; k++) {
        xrsc_frame f = moved_frame(&f0, T_PAN_PX * k, 0.0f);
        f.frame_index = k;
        ok = rig_render(&r, &f);
    }
    double err = 0.0, alpha = 0.0;
    for (uint32_t eye = 0; eye < 2 && ok; eye++) {
        ok = rig_read(&r, eye, e);
        /* all but the column the turn brings in keep their history */
        CHECK(count_status(e, XS_TF_STATUS_BLENDED, false) > T_W * T_H * 9u / 10u);
        err += 0.5 * relmse(e->out, e->src, T_W * T_H);
        alpha += 0.5 * mean_blended_alpha(e);
    }
    CHECK(ok);
    free(e);
    rig_close(&r);
    if (out_alpha)
        *out_alpha = alpha;
    return ok ? err : -1.0;
}

static double pan_error(const char *scene, xrsc_taa_history history)
{
    tf_settings set = {.mode = XRSC_TAA_ON, .history = history};
    return pan_error_set(scene, &set, NULL);
}

/** scenes/edges.gltf (thin black bars in front of a white wall): an edge tap accepted through
 *  a neighbour and read at itself is the last frame's colour of the other surface; at
 *  alpha 0.1 the bars' rims smeared a pixel a frame (relMSE 0.64 against the exact frame
 *  before issue 19's fix). Such history now takes the current frame at
 *  XS_TF_UNTRUSTED_ALPHA: the error must stay below T_PAN_EDGE_MAX. */
static void test_pan_edges(void)
{
    double err = pan_error("scenes/edges.gltf", XRSC_TAA_HISTORY_DEFAULT);
    printf("  edges, pan of %u frames at %.2f px/frame: relMSE vs exact frame %.4f (bound %.2f)\n",
           T_PAN_FRAMES, T_PAN_PX, err, T_PAN_EDGE_MAX);
    CHECK(err >= 0.0 && err <= T_PAN_EDGE_MAX);
}

/** scenes/disocclusion.gltf (textured surfaces): the bilinear history fetch low-pass filters
 *  the history again every frame of sub-pixel motion; Catmull-Rom keeps the texture: its
 *  error against the exact frame is at most T_PAN_CR_RATIO x the bilinear fetch's. */
static void test_pan_texture_catmull_rom(void)
{
    double bil = pan_error("scenes/disocclusion.gltf", XRSC_TAA_HISTORY_BILINEAR);
    double cr = pan_error("scenes/disocclusion.gltf", XRSC_TAA_HISTORY_CATMULL_ROM);
    printf("  texture, pan: relMSE vs exact frame bilinear %.4f, catmull-rom %.4f (%.2f x, "
           "bound %.2f)\n",
           bil, cr, cr / bil, T_PAN_CR_RATIO);
    CHECK(bil > 0.0 && cr >= 0.0);
    CHECK(cr <= T_PAN_CR_RATIO * bil);
}

/** The motion rule (XRSC_TAA_MOTION_ON, XS_TF_MOTION_*; issue 19): a still view keeps alpha
 *  (the reprojected point on the pixel's centre: no resampling blur); under the pan of
 *  T_PAN_PX a frame (bilinear fraction ~0.45, blur ~0.25 px^2) the current frame's weight
 *  rises to about XS_TF_MOTION_ALPHA, and the textured pan's error against the exact frame
 *  falls to at most T_PAN_MOTION_RATIO x the rule's off (the default). */
static void test_pan_motion_rule(void)
{
    xrsc_taa_motion m = XRSC_TAA_MOTION_DEFAULT;
    CHECK(xrsc_taa_motion_from_name("on", &m) == XRSC_OK && m == XRSC_TAA_MOTION_ON);
    CHECK(xrsc_taa_motion_from_name("fast", &m) == XRSC_ERROR_INVALID_ARGUMENT);

    tf_settings on = {.mode = XRSC_TAA_ON, .motion = XRSC_TAA_MOTION_ON};
    tf_settings off = {.mode = XRSC_TAA_ON}; /* XRSC_TAA_MOTION_DEFAULT: off */
    /* still view: two frames at one pose */
    t_rig r;
    if (rig_open_set(&r, t_source_path("scenes/disocclusion.gltf"), XRSC_METHOD_PRIMARY, &on)) {
        t_eye *e = calloc(1, sizeof(t_eye));
        xrsc_frame f0 = tsc_headset_frame(tsc_viewpoint(r.cpu), 0), f1 = f0;
        f1.frame_index = 1;
        if (e && rig_render(&r, &f0) && rig_render(&r, &f1) && rig_read(&r, 0, e)) {
            uint32_t blended = 0, kept = 0;
            for (uint32_t p = 0; p < T_W * T_H; p++) {
                if (e->aux[4 * p + 3] != XS_TF_STATUS_BLENDED)
                    continue;
                blended++;
                kept += fabs(e->aux[4 * p] - XS_TF_DEFAULT_ALPHA) <= T_STILL_ALPHA_TOL;
            }
            printf("  still view: %u of %u blended pixels at alpha %.2f\n", kept, blended,
                   (double)XS_TF_DEFAULT_ALPHA);
            CHECK(blended > T_W * T_H * 9u / 10u);
            CHECK_EQ_INT(kept, blended);
        }
        free(e);
    }
    rig_close(&r);

    double a_on = 0.0, a_off = 0.0;
    double e_on = pan_error_set("scenes/disocclusion.gltf", &on, &a_on);
    double e_off = pan_error_set("scenes/disocclusion.gltf", &off, &a_off);
    printf("  texture, pan: relMSE vs exact frame, motion rule on %.4f (mean alpha %.3f), off "
           "%.4f (%.3f); %.2f x, bound %.2f\n",
           e_on, a_on, e_off, a_off, e_on / e_off, T_PAN_MOTION_RATIO);
    CHECK(e_on >= 0.0 && e_off > 0.0);
    CHECK(e_on <= T_PAN_MOTION_RATIO * e_off);
    CHECK(a_on >= XS_TF_MOTION_ALPHA - T_PAN_ALPHA_TOL &&
          a_on <= XS_TF_MOTION_ALPHA + T_PAN_ALPHA_TOL);
    CHECK(a_off < a_on);
}

/* ---- 8. the motion rule on the dark side of edges (issue 19, Cornell) ---- */

/** Whether taa.comp's rule "edges" applies at pixel p of e: its 3 x 3 neighbourhood (clamped
 *  at the border) shows another instance, and the pixel's resolve-space luma Y / (1 + Y) is
 *  below the neighbourhood's mean; *out_clear = false when the luma is within
 *  T_EDGE_LUMA_MARGIN of the mean (float rounding could decide either way). */
static bool cpu_dark_edge(const t_eye *e, uint32_t p, bool *out_clear)
{
    int x = (int)(p % T_W), y = (int)(p / T_W);
    bool other = false;
    double mean = 0.0, self = 0.0;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++) {
            int qx = x + i < 0 ? 0 : x + i >= (int)T_W ? (int)T_W - 1 : x + i;
            int qy = y + j < 0 ? 0 : y + j >= (int)T_H ? (int)T_H - 1 : y + j;
            uint32_t q = (uint32_t)qy * T_W + (uint32_t)qx;
            other = other || inst_at(e, q) != inst_at(e, p);
            double c[3] = {e->src[4 * q], e->src[4 * q + 1], e->src[4 * q + 2]};
            double l = resolve_luma(c) / (1.0 + resolve_luma(c));
            mean += l / 9.0;
            if (q == p)
                self = l;
        }
    *out_clear = !other || fabs(self - mean) > T_EDGE_LUMA_MARGIN;
    return other && self < mean;
}

/** The last frame's eyes of a slow pan (pan_error_set's) over Cornell, `primary`, TAA set. */
static bool pan_eyes(const tf_settings *set, t_eye out[2])
{
    t_rig r;
    bool ok = rig_open_set(&r, t_source_path("scenes/cornell.gltf"), XRSC_METHOD_PRIMARY, set);
    xrsc_frame f0 = ok ? tsc_headset_frame(tsc_viewpoint(r.cpu), 0) : (xrsc_frame){0};
    for (uint32_t k = 0; k < T_PAN_FRAMES && ok; k++) {
        xrsc_frame f = moved_frame(&f0, T_PAN_PX * k, 0.0f);
        f.frame_index = k;
        ok = rig_render(&r, &f);
    }
    ok = ok && rig_read(&r, 0, &out[0]) && rig_read(&r, 1, &out[1]);
    rig_close(&r);
    return ok;
}

/**
 * Cornell in motion (render_moving, T_EMIT_FRAMES) rendered with `base` and a rule `set` off
 * (err[0]) and on (err[1]): relMSE of each against a T_REF_SPP reference of the last frame's
 * views. Fails on a validation error of its context.
 */
static bool cornell_rule_errors(xrsc_renderer_options base,
                                void (*set)(xrsc_renderer_options *, bool), double err[2])
{
    xrsc_context *ctx = t_context_open();
    CHECK(ctx != NULL);
    xrsc_scene *scene = ctx ? t_scene_load(ctx, t_source_path("scenes/cornell.gltf")) : NULL;
    if (!scene) {
        xrsc_context_destroy(&ctx);
        return false;
    }
    xrsc_frame f0 = tsc_viewpoint_frame(scene), last = f0;
    size_t pixels = 2u * T_W * T_H;
    float *ref = calloc(pixels * 4, sizeof(float)), *img = calloc(pixels * 4, sizeof(float));
    bool ok = ref && img;
    for (int k = 0; k < 2 && ok; k++) {
        xrsc_renderer_options ro = base;
        ro.width = T_W;
        ro.height = T_H;
        set(&ro, k == 1);
        ok = render_moving(ctx, scene, &ro, f0, T_EMIT_FRAMES, img, &last);
        if (ok && k == 0) {
            xrsc_renderer_options rf = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SPP};
            rf.spp.samples_per_pixel = T_REF_SPP;
            rf.spp.accumulate = true;
            ok = t_render(ctx, scene, &rf, &last, &(t_render_job){.frames = T_EMIT_REF_FRAMES},
                          ref);
        }
        err[k] = ok ? relmse(img, ref, pixels) : -1.0;
    }
    free(ref);
    free(img);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
    return ok;
}

static void set_motion_edges(xrsc_renderer_options *ro, bool on)
{
    ro->taa.motion = on ? XRSC_TAA_MOTION_EDGES : XRSC_TAA_MOTION_DEFAULT;
}

static void set_blend_instances(xrsc_renderer_options *ro, bool on)
{
    ro->blend_instance_test = on;
}

/**
 * Motion rule "edges" (XRSC_TAA_MOTION_EDGES): under a pan over Cornell (`primary`: exact
 * input, alpha depends on geometry alone) every blended pixel's alpha equals the rule's
 * (XRSC_TAA_MOTION_ON) on the dark side of an edge between instances and the rule-free
 * alpha elsewhere; the rule must raise alpha at T_EDGE_MIN_PX or more of those pixels (and
 * `on` must differ from `edges` somewhere inside surfaces). Then the default pipeline's
 * method (samplecache, TAA on) in motion over Cornell, whose light panel (~15) sits beside
 * a ceiling of ~0.05: relMSE against a reference with the rule <= T_EDGE_RATIO x without
 * (the panel's smeared rim was half of the default's relMSE on the Cornell orbit,
 * bench/results/issue19-cornell/).
 */
static void test_motion_edges(void)
{
    xrsc_taa_motion m = XRSC_TAA_MOTION_DEFAULT;
    CHECK(xrsc_taa_motion_from_name("edges", &m) == XRSC_OK && m == XRSC_TAA_MOTION_EDGES);
    CHECK(!strcmp(xrsc_taa_motion_name(XRSC_TAA_MOTION_EDGES), "edges"));
    tf_settings set[3] = {{.mode = XRSC_TAA_ON},
                          {.mode = XRSC_TAA_ON, .motion = XRSC_TAA_MOTION_ON},
                          {.mode = XRSC_TAA_ON, .motion = XRSC_TAA_MOTION_EDGES}};
    t_eye *e = calloc(6, sizeof(t_eye)); /* [setting][eye] */
    bool ok = e && pan_eyes(&set[0], e) && pan_eyes(&set[1], e + 2) && pan_eyes(&set[2], e + 4);
    uint32_t dark = 0, raised = 0, inside_raised = 0, bad = 0;
    for (uint32_t eye = 0; eye < 2 && ok; eye++) {
        const t_eye *off = &e[eye], *on = &e[2 + eye], *ed = &e[4 + eye];
        for (uint32_t p = 0; p < T_W * T_H; p++) {
            if (ed->aux[4 * p + 3] != XS_TF_STATUS_BLENDED)
                continue;
            bool clear, rule = cpu_dark_edge(ed, p, &clear);
            if (!clear)
                continue;
            float want = rule ? on->aux[4 * p] : off->aux[4 * p];
            bad += fabsf(ed->aux[4 * p] - want) > T_EDGE_ALPHA_TOL;
            bool up = on->aux[4 * p] > off->aux[4 * p] + T_PAN_ALPHA_TOL;
            dark += rule;
            raised += rule && up;
            inside_raised += !rule && up;
        }
    }
    printf("  edges rule, Cornell pan: %u dark-side edge px (%u raised), %u other px raised by "
           "`on`; %u px off the rule's alpha\n",
           dark, raised, inside_raised, bad);
    CHECK(ok);
    CHECK_EQ_INT(bad, 0);
    CHECK(raised >= T_EDGE_MIN_PX);
    CHECK(inside_raised > 0);
    free(e);

    xrsc_renderer_options base = {.method = XRSC_METHOD_SAMPLECACHE};
    base.taa.mode = XRSC_TAA_ON;
    double err[2] = {0};
    ok = cornell_rule_errors(base, set_motion_edges, err);
    printf("  samplecache + TAA, Cornell in motion: relMSE rule off %.5f, edges %.5f (%.2f x, "
           "bound %.2f)\n",
           err[0], err[1], err[0] > 0.0 ? err[1] / err[0] : 0.0, T_EDGE_RATIO);
    CHECK(ok && err[0] > 0.0 && err[1] >= 0.0);
    CHECK(err[1] <= T_EDGE_RATIO * err[0]);
}

/**
 * The stereo blend's instance test (xrsc_renderer_options.blend_instance_test; issue 19): the
 * sample cache with the moments blend and TAA, in motion over Cornell, against a reference of
 * the last frame's views. The depth test alone (5 %) takes the light panel, 1 cm below the
 * ceiling, for the ceiling, so the other eye's bilinear taps mixed the panel's radiance into
 * the ceiling beside it; with the test relMSE <= T_BLEND_INST_RATIO x without.
 */
static void test_blend_instances(void)
{
    xrsc_renderer_options base = {.method = XRSC_METHOD_SAMPLECACHE,
                                  .blend = XRSC_BLEND_MOMENTS};
    base.taa.mode = XRSC_TAA_ON;
    double err[2] = {0};
    bool ok = cornell_rule_errors(base, set_blend_instances, err);
    printf("  samplecache + moments blend + TAA, Cornell in motion: relMSE instance test off "
           "%.5f, on %.5f (%.2f x, bound %.2f)\n",
           err[0], err[1], err[0] > 0.0 ? err[1] / err[0] : 0.0, T_BLEND_INST_RATIO);
    CHECK(ok && err[0] > 0.0 && err[1] >= 0.0);
    CHECK(err[1] <= T_BLEND_INST_RATIO * err[0]);
}

int main(void)
{
    RUN(test_motion_edges);
    RUN(test_blend_instances);
    RUN(test_pan_motion_rule);
    RUN(test_pan_edges);
    RUN(test_pan_texture_catmull_rom);
    RUN(test_emitter_motion);
    RUN(test_no_light_ring);
    RUN(test_reprojection_turn);
    RUN(test_reprojection_turn_and_move);
    RUN(test_disocclusion_moving_instance);
    RUN(test_pfj23_weights);
    RUN(test_still_view_furnace);
    RUN(test_still_view_cornell);
    return t_finish();
}
