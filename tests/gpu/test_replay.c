// SPDX-License-Identifier: MIT
/**
 * @file test_replay.c
 * @brief The host's replay loop (hs_replay.h) end to end with the validation layer on: files
 *        written, display times on the simulated clock, stereo parallax, real captures, and
 *        the error IDs of its failure paths.
 */
#include "hs_image.h"
#include "hs_replay.h"
#include "t_frames.h"
#include "testing.h"

#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define REFRESH_HZ 90.0
#define NS_PER_S 1e9

/* ---- helpers ---- */

static const char *g_tmp_root;

/* A fresh, empty folder under the test's temporary root (static buffer, 4 in rotation). */
static const char *fresh_dir(const char *name)
{
    static char buf[4][1024];
    static int next;
    char *b = buf[next++ % 4];
    snprintf(b, sizeof(buf[0]), "%s/%s", g_tmp_root, name);
    return b;
}

static void remove_tree(const char *path)
{
    DIR *d = opendir(path);
    if (d) {
        struct dirent *e;
        char child[2048];
        while ((e = readdir(d)) != NULL) {
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
                continue;
            snprintf(child, sizeof(child), "%s/%s", path, e->d_name);
            remove_tree(child);
        }
        closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

static bool file_exists(const char *dir, const char *name)
{
    char path[2048];
    struct stat sb;
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > 0;
}

static bool png_size(const char *dir, const char *name, uint32_t *w, uint32_t *h)
{
    char path[2048];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return false;
    *w = img.width;
    *h = img.height;
    png_image_free(&img);
    return true;
}

static float *read_pfm(const char *dir, const char *name, uint32_t *w, uint32_t *h)
{
    char path[2048];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    float *img = NULL;
    if (hs_read_pfm(path, &img, w, h, NULL) != XRSC_OK)
        return NULL;
    return img;
}

/* Mean of the RGB channels, each clamped to [0, 1] so that a single 1-spp firefly does not
 * dominate the mean of a small image. */
static double clamped_mean(const float *rgba, uint32_t w, uint32_t h)
{
    double sum = 0.0;
    size_t n = (size_t)w * h;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            float v = rgba[i * 4 + c];
            sum += v > 1.0f ? 1.0 : (v > 0.0f ? v : 0.0);
        }
    return sum / (3.0 * (double)n);
}

static hs_replay_options base_options(const char *out_dir)
{
    hs_replay_options opt = {
        .scene_path = t_source_path("scenes/cornell.gltf"),
        .poses_path = t_source_path("poses/orbit_cornell.xrpose"),
        .out_dir = out_dir,
        .context = {.validation = true},
        .renderer = {.method = XRSC_METHOD_SPP, .width = 32, .height = 32,
                     .spp = {.samples_per_pixel = 1}},
        .frames = 4,
    };
    xrsc_headset_default(&opt.headset);
    return opt;
}

/* ---- cases ---- */

static void test_replay_writes_all_files(void)
{
    const char *dir = fresh_dir("orbit");
    hs_replay_options opt = base_options(dir);
    opt.write_eyes = opt.write_sbs = opt.write_linear = true;
    hs_replay_stats st;
    xrsc_diag diag = {0};
    xrsc_result res = hs_replay_run(&opt, &st, &diag);
    char msg[1400];
    CHECK_MSG(res == XRSC_OK, "%s", xrsc_diag_format(&diag, msg, sizeof(msg)));
    CHECK_EQ_INT(st.frames, 4);
    CHECK_EQ_INT(st.validation_errors, 0);
    CHECK(st.device[0] != '\0');
    CHECK(st.pass_count >= 1);
    CHECK(st.rays_per_frame >= 2.0 * 32 * 32); /* at least one primary ray per pixel and eye */
    if (res != XRSC_OK)
        return;

    static const char *const suffix[] = {"left.png", "right.png", "sbs.png", "left.pfm",
                                         "right.pfm"};
    char name[256];
    for (int k = 0; k < 4; k++)
        for (int s = 0; s < 5; s++) {
            snprintf(name, sizeof(name), "frame_%05d_%s", k, suffix[s]);
            CHECK_MSG(file_exists(dir, name), "%s/%s missing", dir, name);
        }
    CHECK(!file_exists(dir, "frame_00004_left.png")); /* exactly the frames asked for */

    uint32_t w = 0, h = 0;
    CHECK(png_size(dir, "frame_00000_left.png", &w, &h) && w == 32 && h == 32);
    CHECK(png_size(dir, "frame_00003_sbs.png", &w, &h) && w == 64 && h == 32);

    /* frames.csv: a header, then one row per frame at t_k = k / 90 Hz (rounded to ns). */
    char path[2048];
    snprintf(path, sizeof(path), "%s/frames.csv", dir);
    FILE *f = fopen(path, "r");
    CHECK(f != NULL);
    if (!f)
        return;
    char line[1024];
    CHECK(fgets(line, sizeof(line), f) && !strncmp(line, "frame,display_time_ns,lookup,", 29));
    int rows = 0;
    while (fgets(line, sizeof(line), f)) {
        unsigned idx = 99;
        long long t_ns = -1;
        CHECK_EQ_INT(sscanf(line, "%u,%lld,", &idx, &t_ns), 2);
        CHECK_EQ_INT(idx, rows);
        CHECK_EQ_INT(t_ns, llround(rows * NS_PER_S / REFRESH_HZ));
        rows++;
    }
    fclose(f);
    CHECK_EQ_INT(rows, 4);
    CHECK_EQ_INT(llround(3 * NS_PER_S / REFRESH_HZ), 33333333); /* the arithmetic itself */

    /* The two eyes see the same box from 63 mm apart: different images, similar brightness.
     * Means over all four frames, so that 1-spp noise averages out. */
    double mean[2] = {0, 0};
    int differing = 0;
    for (int k = 0; k < 4; k++) {
        float *img[2];
        uint32_t iw[2] = {0, 0}, ih[2] = {0, 0};
        for (int e = 0; e < 2; e++) {
            snprintf(name, sizeof(name), "frame_%05d_%s.pfm", k, e ? "right" : "left");
            img[e] = read_pfm(dir, name, &iw[e], &ih[e]);
            CHECK(img[e] && iw[e] == 32 && ih[e] == 32);
        }
        if (img[0] && img[1] && iw[0] == 32 && iw[1] == 32 && ih[0] == 32 && ih[1] == 32) {
            differing += memcmp(img[0], img[1], 32 * 32 * 4 * sizeof(float)) != 0;
            for (int e = 0; e < 2; e++)
                mean[e] += clamped_mean(img[e], 32, 32) / 4.0;
        }
        free(img[0]);
        free(img[1]);
    }
    CHECK_EQ_INT(differing, 4);
    CHECK_MSG(mean[0] > 0.01 && mean[1] > 0.01, "means %g %g", mean[0], mean[1]);
    CHECK_MSG(fabs(mean[0] - mean[1]) <= 0.25 * fmax(mean[0], mean[1]), "means %g %g", mean[0],
              mean[1]);
}

/* Counts pixels whose colour differs between two RGBA float images. */
static int count_differing(const float *a, const float *b, size_t n)
{
    int d = 0;
    for (size_t i = 0; i < n; i++)
        d += memcmp(a + i * 4, b + i * 4, 3 * sizeof(float)) != 0;
    return d;
}

/*
 * Parallax isolated from noise: the primary method is deterministic, and with the same FOV in
 * both eyes the images are identical at IPD 0 and differ only because of the IPD at 63 mm.
 */
static void test_replay_parallax_from_ipd(void)
{
    int differing[2] = {-1, -1};
    const float ipd_m[2] = {0.0f, 0.063f};
    for (int run = 0; run < 2; run++) {
        const char *dir = fresh_dir(run ? "ipd63" : "ipd0");
        hs_replay_options opt = base_options(dir);
        opt.renderer.method = XRSC_METHOD_PRIMARY;
        opt.frames = 1;
        opt.write_linear = true;
        opt.headset.ipd_m = ipd_m[run];
        opt.headset.fov[1] = opt.headset.fov[0];
        hs_replay_stats st;
        CHECK_EQ_INT(hs_replay_run(&opt, &st, NULL), XRSC_OK);
        CHECK_EQ_INT(st.validation_errors, 0);
        uint32_t w[2], h[2];
        float *l = read_pfm(dir, "frame_00000_left.pfm", &w[0], &h[0]);
        float *r = read_pfm(dir, "frame_00000_right.pfm", &w[1], &h[1]);
        CHECK(l && r);
        if (l && r && w[0] == w[1] && h[0] == h[1])
            differing[run] = count_differing(l, r, (size_t)w[0] * h[0]);
        free(l);
        free(r);
    }
    CHECK_EQ_INT(differing[0], 0);
    CHECK_MSG(differing[1] > 0, "%d pixels differ at 63 mm", differing[1]);
}

/* Anchoring at the replay level: the first frame's eyes of an anchored replay are the scene's
 * viewpoint ± IPD/2 along its +X (with its orientation); --no-anchor keeps the stream's own
 * coordinates (the headset's eyes at the stream's poses at 0 and 1 / refresh). */
static void test_replay_anchoring(void)
{
    hs_replay_options opt = base_options(NULL);
    opt.renderer.method = XRSC_METHOD_PRIMARY;
    opt.renderer.width = opt.renderer.height = 16;
    opt.frames = 2;
    opt.headset.ipd_m = 0.071f;

    /* The scene's viewpoint, as the replay gets it. */
    xrsc_context *ctx = NULL;
    xrsc_scene *scene = NULL;
    xrsc_scene_info info = {0};
    CHECK_EQ_INT(xrsc_context_create(&opt.context, &ctx, NULL), XRSC_OK);
    CHECK_EQ_INT(xrsc_scene_load(ctx, opt.scene_path, NULL, &scene, NULL), XRSC_OK);
    if (scene)
        xrsc_scene_get_info(scene, &info);
    xrsc_scene_destroy(&scene);
    xrsc_context_destroy(&ctx);
    hs_pose_stream *stream = NULL;
    CHECK_EQ_INT(hs_pose_stream_load(opt.poses_path, HS_POSE_FORMAT_AUTO, &stream, NULL), XRSC_OK);
    if (!stream)
        return;
    /* Meaningful only if the stream does not already start at the viewpoint. */
    CHECK(!t_pose_near(stream->samples[0].pose, info.viewpoint, 1e-3f));

    t_captured seen = {0};
    opt.on_frame = t_capture_frame;
    opt.on_frame_user = &seen;
    CHECK_EQ_INT(hs_replay_run(&opt, NULL, NULL), XRSC_OK);
    CHECK_EQ_INT(seen.count, 2);
    const XrPosef vp = info.viewpoint;
    for (int e = 0; e < 2; e++) {
        float side = e ? 0.5f : -0.5f;
        XrVector3f off = xrsc_quat_rotate(vp.orientation, (XrVector3f){side * 0.071f, 0, 0});
        XrPosef want = {.orientation = vp.orientation,
                        .position = {vp.position.x + off.x, vp.position.y + off.y,
                                     vp.position.z + off.z}};
        const XrPosef got = seen.frames[0].views[e].pose;
        CHECK_MSG(t_pose_near(got, want, 2e-5f),
                  "anchored eye %d at (%g %g %g), want (%g %g %g)", e, got.position.x,
                  got.position.y, got.position.z, want.position.x, want.position.y,
                  want.position.z);
        CHECK(memcmp(&seen.frames[0].views[e].fov, &opt.headset.fov[e], sizeof(XrFovf)) == 0);
    }
    XrVector3f a = seen.frames[1].views[0].pose.position, b = seen.frames[1].views[1].pose.position;
    XrVector3f d = {b.x - a.x, b.y - a.y, b.z - a.z};
    CHECK_NEAR(sqrtf(d.x * d.x + d.y * d.y + d.z * d.z), 0.071, 1e-5);

    /* --no-anchor: the stream's coordinates as they are. */
    seen.count = 0;
    opt.no_anchor = true;
    CHECK_EQ_INT(hs_replay_run(&opt, NULL, NULL), XRSC_OK);
    CHECK_EQ_INT(seen.count, 2);
    for (uint32_t k = 0; k < seen.count; k++) {
        XrPosef head, eyes[2];
        hs_pose_stream_sample(stream, (int64_t)(k * NS_PER_S / REFRESH_HZ + 0.5), &head);
        xrsc_headset_eye_poses(&opt.headset, head, eyes);
        for (int e = 0; e < 2; e++)
            CHECK_MSG(memcmp(&seen.frames[k].views[e].pose, &eyes[e], sizeof(XrPosef)) == 0,
                      "unanchored frame %u eye %d moved", k, e);
    }
    hs_pose_stream_destroy(&stream);
}

static void test_replay_real_captures(void)
{
    static const char *const captures[] = {"poses/pred6dof-hololens/1.csv",
                                           "poses/360video-orientation/user1_quaternion.txt"};
    for (int i = 0; i < 2; i++) {
        hs_replay_options opt = base_options(fresh_dir(i ? "360" : "hololens"));
        opt.poses_path = t_shared_path(captures[i]);
        opt.frames = 2;
        opt.write_eyes = true;
        hs_replay_stats st;
        xrsc_diag diag = {0};
        xrsc_result res = hs_replay_run(&opt, &st, &diag);
        char msg[1400];
        CHECK_MSG(res == XRSC_OK, "%s: %s", captures[i],
                  xrsc_diag_format(&diag, msg, sizeof(msg)));
        CHECK_EQ_INT(st.frames, 2);
        CHECK_EQ_INT(st.validation_errors, 0);
        CHECK(file_exists(opt.out_dir, "frame_00001_right.png"));
        CHECK(!file_exists(opt.out_dir, "frame_00000_sbs.png")); /* not asked for */
    }
}

/* Zero-initialised renderer size and headset mean the documented defaults (256 px, the
 * default headset); stats may be NULL; NULL out_dir writes nothing. */
static void test_replay_defaults(void)
{
    const char *dir = fresh_dir("defaults");
    hs_replay_options opt = base_options(dir);
    opt.renderer.method = XRSC_METHOD_PRIMARY;
    opt.renderer.width = opt.renderer.height = 0;
    memset(&opt.headset, 0, sizeof(opt.headset));
    opt.frames = 1;
    opt.write_eyes = true;
    CHECK_EQ_INT(hs_replay_run(&opt, NULL, NULL), XRSC_OK);
    uint32_t w = 0, h = 0;
    CHECK(png_size(dir, "frame_00000_left.png", &w, &h) && w == 256 && h == 256);

    hs_replay_options quiet = base_options(NULL);
    quiet.frames = 1;
    quiet.write_eyes = true;
    hs_replay_stats st;
    CHECK_EQ_INT(hs_replay_run(&quiet, &st, NULL), XRSC_OK);
    CHECK_EQ_INT(st.frames, 1);
}

static void test_replay_error_paths(void)
{
    hs_replay_stats st;
    xrsc_diag diag;

    hs_replay_options opt = base_options(fresh_dir("err_poses"));
    opt.poses_path = t_source_path("poses/no_such_stream.xrpose");
    memset(&diag, 0, sizeof(diag));
    CHECK_EQ_INT(hs_replay_run(&opt, &st, &diag), XRSC_ERROR_IO);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_IO);
    CHECK(strstr(diag.file, "no_such_stream.xrpose") != NULL);
    CHECK_EQ_INT(st.frames, 0);

    opt = base_options(fresh_dir("err_scene"));
    opt.scene_path = t_source_path("scenes/no_such_scene.gltf");
    memset(&diag, 0, sizeof(diag));
    xrsc_result res = hs_replay_run(&opt, &st, &diag);
    CHECK_MSG(res < 0, "bad scene gave %s", xrsc_result_name(res));
    CHECK_EQ_INT(diag.code, res);
    CHECK_EQ_INT(st.frames, 0);
    CHECK_EQ_INT(st.validation_errors, 0); /* the context was made and torn down cleanly */

    opt = base_options(fresh_dir("err_device"));
    opt.context.device = "no-such-vulkan-device-xyzzy";
    memset(&diag, 0, sizeof(diag));
    CHECK_EQ_INT(hs_replay_run(&opt, &st, &diag), XRSC_ERROR_DEVICE_NOT_FOUND);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_DEVICE_NOT_FOUND);

    /* An output folder that cannot be created (its parent is a regular file). */
    const char *blocker = t_temp_file("replay-blocker", "x");
    char out[1100];
    snprintf(out, sizeof(out), "%s/sub", blocker);
    opt = base_options(out);
    opt.frames = 1;
    opt.write_eyes = true;
    memset(&diag, 0, sizeof(diag));
    CHECK_EQ_INT(hs_replay_run(&opt, &st, &diag), XRSC_ERROR_IO);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_IO);
    unlink(blocker);

    opt = base_options("");
    CHECK_EQ_INT(hs_replay_run(&opt, &st, NULL), XRSC_ERROR_INVALID_ARGUMENT);
    opt = base_options(NULL);
    opt.scene_path = NULL;
    CHECK_EQ_INT(hs_replay_run(&opt, &st, NULL), XRSC_ERROR_INVALID_ARGUMENT);
}

int main(void)
{
    const char *tmp = getenv("TMPDIR");
    char root[1024];
    snprintf(root, sizeof(root), "%s/xrsc-test-replay-XXXXXX", tmp ? tmp : "/tmp");
    g_tmp_root = mkdtemp(root);
    if (!g_tmp_root) {
        fprintf(stderr, "cannot create a temporary folder\n");
        return 1;
    }
    RUN(test_replay_writes_all_files);
    RUN(test_replay_parallax_from_ipd);
    RUN(test_replay_anchoring);
    RUN(test_replay_real_captures);
    RUN(test_replay_defaults);
    RUN(test_replay_error_paths);
    int rc = t_finish();
    if (rc == 0)
        remove_tree(g_tmp_root); /* kept for inspection when something failed */
    else
        fprintf(stderr, "output kept in %s\n", g_tmp_root);
    return rc;
}
