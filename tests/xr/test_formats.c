// SPDX-License-Identifier: MIT
/**
 * @file test_formats.c
 * @brief Issue 11 item 6 end to end: `--write exr` on both replay paths read back with
 *        OpenEXR's library (RGB bit-identical to the PFMs of the same run, depth equal to a
 *        `primary` renderer's depth output: at pixel centres), a headset's per-eye FOVs
 *        reaching the OpenXR path's views, and `--video` through a stand-in ffmpeg (the frames piped are the side-by-side stream),
 *        a failing one, and a missing one (a warning, the run still succeeds).
 */
#include "hs_exr.h"
#include "hs_image.h"
#include "hs_replay.h"
#include "hs_xr_replay.h"
#include "t_frames.h"
#include "testing.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define SCENE XRSC_SOURCE_DIR "/scenes/cornell.gltf"
#define POSES XRSC_SOURCE_DIR "/poses/orbit_cornell.xrpose"
#define EYE_PX 32u
#define FRAMES 2u

static const char *const eye_name[2] = {"left", "right"};

static hs_replay_options base_options(const char *out_dir, t_captured *cap)
{
    char cmd[700];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", out_dir); /* a fresh folder for each run */
    if (system(cmd) != 0)
        fprintf(stderr, "cannot empty %s\n", out_dir);
    hs_replay_options o = {
        .scene_path = SCENE,
        .poses_path = POSES,
        .out_dir = out_dir,
        .frames = FRAMES,
        .write_linear = true,
        .write_exr = true,
        .on_frame = t_capture_frame,
        .on_frame_user = cap,
        .renderer = {.method = XRSC_METHOD_SPP,
                     .width = EYE_PX,
                     .height = EYE_PX,
                     .spp = {.samples_per_pixel = 1}},
    };
    o.context.validation = getenv("XRSC_VALIDATION") != NULL;
    xrsc_headset_default(&o.headset);
    return o;
}

static int bit_diffs(const float *a, size_t sa, const float *b, size_t sb, size_t n)
{
    int d = 0;
    for (size_t i = 0; i < n; i++)
        d += memcmp(&a[i * sa], &b[i * sb], sizeof(float)) != 0;
    return d;
}

/* The EXR of frame k, eye e equals the PFM of the same run in R, G, B bit for bit and has a
 * Z channel; returns the depth (malloc'ed) or NULL. */
static float *check_exr_against_pfm(const char *dir, uint32_t k, int e)
{
    char exr[600], pfm[600];
    snprintf(exr, sizeof(exr), "%s/frame_%05u_%s.exr", dir, k, eye_name[e]);
    snprintf(pfm, sizeof(pfm), "%s/frame_%05u_%s.pfm", dir, k, eye_name[e]);
    float *a = NULL, *b = NULL, *z = NULL;
    uint32_t aw = 0, ah = 0, bw = 0, bh = 0;
    xrsc_diag diag = {0};
    CHECK_MSG(hs_read_exr(exr, &a, &z, &aw, &ah, &diag) == XRSC_OK, "%s: %s", exr, diag.message);
    CHECK_MSG(hs_read_pfm(pfm, &b, &bw, &bh, &diag) == XRSC_OK, "%s: %s", pfm, diag.message);
    CHECK_MSG(z != NULL, "%s has no Z channel", exr);
    if (a && b && aw == bw && ah == bh && aw == EYE_PX && ah == EYE_PX) {
        int diffs = 0;
        for (int c = 0; c < 3; c++)
            diffs += bit_diffs(a + c, 4, b + c, 4, (size_t)aw * ah);
        CHECK_MSG(diffs == 0, "%s: %d values differ from the PFM", exr, diffs);
        double sum = 0.0;
        for (size_t i = 0; i < (size_t)aw * ah * 4; i++)
            sum += i % 4 == 3 ? 0.0 : a[i];
        CHECK_MSG(sum > 0.0, "%s is black", exr);
    } else {
        CHECK_MSG(false, "%s / %s: sizes %ux%u / %ux%u", exr, pfm, aw, ah, bw, bh);
    }
    free(a);
    free(b);
    return z;
}

static void test_exr_direct(void)
{
    const char *dir = XRSC_TEST_OUT "/formats_direct";
    t_captured cap = {0};
    hs_replay_options o = base_options(dir, &cap);
    hs_replay_stats st;
    xrsc_diag diag = {0};
    CHECK_MSG(hs_replay_run(&o, &st, &diag) == XRSC_OK, "%s", diag.message);
    CHECK_EQ_INT(st.validation_errors, 0);
    CHECK_EQ_INT(cap.count, FRAMES);

    /* The same frames again on a `primary` renderer: its depth (at pixel centres, hs_views.h)
     * is what Z must hold, bit for bit. */
    xrsc_context *ctx = NULL;
    xrsc_scene *scene = NULL;
    xrsc_renderer *r = NULL;
    CHECK(xrsc_context_create(&o.context, &ctx, &diag) == XRSC_OK);
    CHECK(ctx && xrsc_scene_load(ctx, SCENE, &o.scene, &scene, &diag) == XRSC_OK);
    const xrsc_renderer_options dro = {
        .method = XRSC_METHOD_PRIMARY, .width = EYE_PX, .height = EYE_PX};
    CHECK(scene && xrsc_renderer_create(ctx, scene, &dro, &r, &diag) == XRSC_OK);
    float depth[EYE_PX * EYE_PX];
    for (uint32_t k = 0; r && k < cap.count; k++) {
        CHECK(xrsc_renderer_render(r, &cap.frames[k]) == XRSC_OK);
        for (int e = 0; e < 2; e++) {
            float *z = check_exr_against_pfm(dir, k, e);
            CHECK(xrsc_renderer_read(r, (uint32_t)e, XRSC_OUTPUT_DEPTH, depth, sizeof(depth)) ==
                  XRSC_OK);
            if (z) {
                CHECK_MSG(bit_diffs(z, 1, depth, 1, EYE_PX * EYE_PX) == 0,
                          "frame %u %s: Z differs from the depth output", k, eye_name[e]);
                int hits = 0;
                for (uint32_t i = 0; i < EYE_PX * EYE_PX; i++)
                    hits += z[i] > 0.0f && z[i] < 100.0f;
                CHECK_MSG(hits > (int)(EYE_PX * EYE_PX / 2), "only %d pixels with depth", hits);
            }
            free(z);
        }
    }
    xrsc_renderer_destroy(&r);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}

static bool fov_equal(XrFovf a, XrFovf b)
{
    return a.angleLeft == b.angleLeft && a.angleRight == b.angleRight && a.angleUp == b.angleUp &&
           a.angleDown == b.angleDown;
}

/* Through OpenXR: the EXRs the program writes carry the runtime's frame numbers and equal the
 * runtime's PFMs (the submitted pixels); a headset's FOVs (not the default's) reach
 * xrLocateViews through XRSC_RT_FOV_DEG exactly. */
static void test_exr_openxr_and_headset_fov(void)
{
    const char *dir = XRSC_TEST_OUT "/formats_xr";
    setenv("XR_RUNTIME_JSON", XRSC_RUNTIME_JSON, 1);
    t_captured cap = {0};
    hs_replay_options o = base_options(dir, &cap);
    const XrFovf left = {-0.95f, 0.71f, 0.83f, -0.88f}, right = {-0.70f, 0.96f, 0.82f, -0.89f};
    o.headset.fov[0] = left;
    o.headset.fov[1] = right;
    hs_replay_stats st;
    xrsc_diag diag = {0};
    CHECK_MSG(hs_xr_replay_run(&o, &st, &diag) == XRSC_OK, "%s", diag.message);
    CHECK_EQ_INT(st.validation_errors, 0);
    CHECK_EQ_INT(cap.count, FRAMES);
    for (uint32_t i = 0; i < cap.count; i++) {
        CHECK_MSG(fov_equal(cap.frames[i].views[0].fov, left), "frame %u left FOV", i);
        CHECK_MSG(fov_equal(cap.frames[i].views[1].fov, right), "frame %u right FOV", i);
        for (int e = 0; e < 2; e++)
            free(check_exr_against_pfm(dir, cap.frames[i].frame_index, e));
    }
}

/* A stand-in for ffmpeg: stores its stdin in its last argument (the output file). */
static const char *fake_ffmpeg(const char *name, const char *body)
{
    static char path[2][600];
    static int next;
    char *p = path[next++ % 2];
    snprintf(p, sizeof(path[0]), "%s/%s", XRSC_TEST_OUT, name);
    FILE *f = fopen(p, "w");
    if (f) {
        fprintf(f, "#!/bin/sh\n%s\n", body);
        fclose(f);
    }
    chmod(p, 0755);
    return p;
}

static bool exists(const char *path)
{
    struct stat s;
    return stat(path, &s) == 0;
}

static void test_video(void)
{
    const char *dir = XRSC_TEST_OUT "/formats_video";
    char video[600], partial[600];
    snprintf(video, sizeof(video), "%s/sbs.mp4", XRSC_TEST_OUT);
    snprintf(partial, sizeof(partial), "%s/sbs.partial.mp4", XRSC_TEST_OUT);
    remove(video);
    t_captured cap = {0};
    hs_replay_options o = base_options(dir, &cap);
    o.write_exr = false;
    o.video_path = video;
    hs_replay_stats st;
    xrsc_diag diag = {0};

    /* ffmpeg missing: the run succeeds without a video (and warns on stderr). */
    setenv("XRSC_FFMPEG", XRSC_TEST_OUT "/no-such-ffmpeg", 1);
    CHECK_MSG(hs_replay_run(&o, &st, &diag) == XRSC_OK, "%s", diag.message);
    CHECK(!exists(video) && !exists(partial));

    /* A stand-in that keeps the raw frames: they are the tone-mapped side-by-side stream. */
    setenv("XRSC_FFMPEG", fake_ffmpeg("fake-ffmpeg", "for a; do out=$a; done; exec cat > \"$out\""),
           1);
    cap.count = 0;
    CHECK_MSG(hs_replay_run(&o, &st, &diag) == XRSC_OK, "%s", diag.message);
    CHECK(!exists(partial));
    size_t size = 0;
    uint8_t *raw = t_read_file(video, &size);
    const size_t frame_bytes = (size_t)EYE_PX * 2 * EYE_PX * 3;
    CHECK_EQ_INT(size, FRAMES * frame_bytes);
    uint8_t ldr[2][EYE_PX * EYE_PX * 3], sbs[EYE_PX * 2 * EYE_PX * 3];
    hs_autoexposure ae = {0}; /* exposure 0: automatic, as the _sbs.png (hs_image.h) */
    for (uint32_t k = 0; raw && size == FRAMES * frame_bytes && k < FRAMES; k++) {
        float *rgba[2] = {NULL, NULL};
        for (int e = 0; e < 2; e++) {
            char pfm[600];
            snprintf(pfm, sizeof(pfm), "%s/frame_%05u_%s.pfm", dir, k, eye_name[e]);
            uint32_t w = 0, h = 0;
            CHECK(hs_read_pfm(pfm, &rgba[e], &w, &h, &diag) == XRSC_OK);
            CHECK(w == EYE_PX && h == EYE_PX);
        }
        if (!rgba[0] || !rgba[1]) {
            free(rgba[0]);
            free(rgba[1]);
            break;
        }
        const float *eyes[2] = {rgba[0], rgba[1]};
        hs_tonemap tm = {.exposure = hs_autoexposure_update(&ae, eyes, 2, EYE_PX, EYE_PX)};
        for (int e = 0; e < 2; e++) {
            hs_tonemap_rgba(&tm, rgba[e], EYE_PX, EYE_PX, ldr[e]);
            free(rgba[e]);
        }
        hs_side_by_side(ldr[0], ldr[1], EYE_PX, EYE_PX, sbs);
        CHECK_MSG(memcmp(raw + k * frame_bytes, sbs, frame_bytes) == 0, "video frame %u", k);
    }
    free(raw);
    remove(video);

    /* Through OpenXR the program writes the same stream (one frame per rendered frame). */
    setenv("XR_RUNTIME_JSON", XRSC_RUNTIME_JSON, 1);
    CHECK_MSG(hs_xr_replay_run(&o, &st, &diag) == XRSC_OK, "%s", diag.message);
    raw = t_read_file(video, &size);
    CHECK_EQ_INT(size, FRAMES * frame_bytes);
    free(raw);
    remove(video);

    /* An ffmpeg that fails at once: an error naming --video, no video, no SIGPIPE death. */
    setenv("XRSC_FFMPEG", fake_ffmpeg("failing-ffmpeg", "exit 3"), 1);
    xrsc_result r = hs_replay_run(&o, &st, &diag);
    CHECK_EQ_INT(r, XRSC_ERROR_IO);
    CHECK(strcmp(diag.field, "--video") == 0);
    CHECK(!exists(video) && !exists(partial));
    unsetenv("XRSC_FFMPEG");
}

/* With a real ffmpeg on PATH: a non-empty video in place of the partial one. Skipped (and
 * said so) without ffmpeg, which is never a dependency. */
static void test_video_real_ffmpeg(void)
{
    if (system("command -v ffmpeg >/dev/null 2>&1") != 0) {
        printf("test_video_real_ffmpeg: skipped (ffmpeg is not installed)\n");
        return;
    }
    char video[600];
    snprintf(video, sizeof(video), "%s/real.mp4", XRSC_TEST_OUT);
    remove(video);
    t_captured cap = {0};
    hs_replay_options o = base_options(XRSC_TEST_OUT "/formats_real_video", &cap);
    o.write_exr = o.write_linear = false;
    o.video_path = video;
    hs_replay_stats st;
    xrsc_diag diag = {0};
    CHECK_MSG(hs_replay_run(&o, &st, &diag) == XRSC_OK, "%s", diag.message);
    struct stat s;
    CHECK(stat(video, &s) == 0 && s.st_size > 0);
    remove(video);
}

int main(void)
{
    mkdir(XRSC_TEST_OUT, 0755);
    RUN(test_exr_direct);
    RUN(test_exr_openxr_and_headset_fov);
    RUN(test_video);
    RUN(test_video_real_ffmpeg);
    return t_finish();
}
