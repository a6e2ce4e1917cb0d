// SPDX-License-Identifier: MIT
/**
 * @file test_animation_clips.c
 * @brief --animation picks the clip (issue 21): a generated glTF with two clips, "walk" (moves
 *        node A along x) and "idle" (moves node B, never A); by name, by index, first (the
 *        default), all and none, the nodes that move between two display times are exactly the
 *        chosen clip's; unknown names and indices are XRSC_ERROR_ANIMATION_UNKNOWN; the file's
 *        clips, durations and channel counts as xrsc_file_inspect reads them.
 *
 * Runs under the validation layer; fails if it reported any error.
 */
#include "t_context.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 32u
/** Display times of the two frames compared: walk moves A by 1 m between them (x -0.5 to
 *  +0.5 at 3 m, about 7.8 px at 32 px over tan(0.6)), idle moves B by 0.5 m (about 3.9 px). */
#define T_TIME0_NS 250000000
#define T_TIME1_NS 750000000
/** A node moved when its hit centroid shifts more than this (px); it stood still when less
 *  than T_STILL_PX (the same rays hit the same triangle: the centroid is bit-identical). */
#define T_MOVED_PX 2.0
#define T_STILL_PX 1e-9

static xrsc_context *g_ctx;

/** One triangle (mesh 0) drawn by node A (instance 0, y = +0.35) and node B (instance 1,
 *  y = -0.35) at z = -3. "walk" moves A from x = -1 to +1 over 1 s; "idle" moves B from
 *  x = +1 to -1 over 2 s. */
static const char *write_two_clips(void)
{
    float data[25] = {-0.25f, -0.2f,  -3.0f, 0.25f, -0.2f,  -3.0f, 0.0f, 0.2f, -3.0f, /* POSITION */
                      0.0f,   1.0f,                                                   /* walk t */
                      -1.0f,  0.35f,  0.0f,  1.0f,  0.35f,  0.0f,                     /* walk T */
                      0.0f,   2.0f,                                                   /* idle t */
                      1.0f,   -0.35f, 0.0f,  -1.0f, -0.35f, 0.0f};                    /* idle T */
    char *uri = t_data_uri(data, sizeof(data));
    if (!uri)
        return NULL;
    static char json[4096];
    snprintf(json, sizeof(json),
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
             "\"nodes\":[{\"name\":\"A\",\"mesh\":0,\"translation\":[-1,0.35,0]},"
             "{\"name\":\"B\",\"mesh\":0,\"translation\":[1,-0.35,0]}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
             "\"accessors\":["
             "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[-0.25,-0.2,-3],\"max\":[0.25,0.2,-3]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\","
             "\"min\":[0],\"max\":[1]},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"},"
             "{\"bufferView\":3,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\","
             "\"min\":[0],\"max\":[2]},"
             "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":8},"
             "{\"buffer\":0,\"byteOffset\":44,\"byteLength\":24},"
             "{\"buffer\":0,\"byteOffset\":68,\"byteLength\":8},"
             "{\"buffer\":0,\"byteOffset\":76,\"byteLength\":24}],"
             "\"buffers\":[{\"byteLength\":100,\"uri\":\"%s\"}],"
             "\"animations\":["
             "{\"name\":\"walk\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,"
             "\"path\":\"translation\"}}],\"samplers\":[{\"input\":1,\"output\":2}]},"
             "{\"name\":\"idle\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,"
             "\"path\":\"translation\"}}],\"samplers\":[{\"input\":3,\"output\":4}]}]}",
             uri);
    free(uri);
    return t_temp_file("two_clips.gltf", json);
}

/** Mean x (pixels) of the left eye's pixels whose first hit is instance inst; -1 if none. */
static double centroid_x(xrsc_renderer *r, uint32_t inst)
{
    size_t size = xrsc_renderer_output_size(r, XRSC_OUTPUT_HIT_ID);
    uint32_t *hit = malloc(size);
    double sum = 0.0;
    uint32_t n = 0;
    if (hit && xrsc_renderer_read(r, 0, XRSC_OUTPUT_HIT_ID, hit, size) == XRSC_OK)
        for (uint32_t p = 0; p < T_SIZE * T_SIZE; p++)
            if (hit[4 * p] == inst) {
                sum += p % T_SIZE;
                n++;
            }
    free(hit);
    return n ? sum / n : -1.0;
}

/** What one --animation value makes move: dx of A and B between the two display times. */
typedef struct clip_run {
    xrsc_result load;
    xrsc_scene_info info;
    uint8_t flags[2]; /**< xrsc_scene_instance_flags */
    double dx[2];
} clip_run;

static void render_two_times(xrsc_scene *scene, clip_run *out)
{
    xrsc_renderer *rend = NULL;
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = T_SIZE, .height = T_SIZE};
    CHECK_EQ_INT(xrsc_renderer_create(g_ctx, scene, &ro, &rend, NULL), XRSC_OK);
    if (!rend)
        return;
    xrsc_frame f = {0};
    for (int e = 0; e < 2; e++) {
        f.views[e].pose = xrsc_pose_identity();
        f.views[e].fov = (XrFovf){-0.6f, 0.6f, 0.6f, -0.6f};
    }
    double x[2][2];
    static const int64_t times_ns[2] = {T_TIME0_NS, T_TIME1_NS};
    for (uint32_t k = 0; k < 2; k++) {
        f.display_time_ns = times_ns[k];
        f.frame_index = k;
        CHECK_EQ_INT(xrsc_renderer_render(rend, &f), XRSC_OK);
        for (uint32_t i = 0; i < 2; i++) {
            x[k][i] = centroid_x(rend, i);
            CHECK_MSG(x[k][i] >= 0.0, "instance %u not seen at frame %u", i, k);
        }
    }
    for (uint32_t i = 0; i < 2; i++)
        out->dx[i] = x[1][i] - x[0][i];
    xrsc_renderer_destroy(&rend);
}

static clip_run run_clip(const char *path, const char *animation)
{
    clip_run out = {0};
    xrsc_scene_options so = {.animation = animation};
    xrsc_scene *scene = NULL;
    xrsc_diag diag = {0};
    out.load = xrsc_scene_load(g_ctx, path, &so, &scene, &diag);
    if (!scene)
        return out;
    xrsc_scene_get_info(scene, &out.info);
    CHECK_EQ_INT(xrsc_scene_instance_flags(scene, out.flags, 2), 2);
    render_two_times(scene, &out);
    printf("--animation %s: playing %d, duration %.2f s, dx A %.3f px, B %.3f px\n",
           animation ? animation : "(default)", out.info.clip_playing,
           (double)out.info.animation_duration_s, out.dx[0], out.dx[1]);
    xrsc_scene_destroy(&scene);
    return out;
}

/** Checks which of A and B moved (and are flagged as moving objects) for one value. */
static void expect_moves(const char *path, const char *animation, int32_t playing,
                         double duration_s, bool a_moves, bool b_moves)
{
    clip_run r = run_clip(path, animation);
    CHECK_EQ_INT(r.load, XRSC_OK);
    CHECK_EQ_INT(r.info.clip_count, 2);
    CHECK_EQ_INT(r.info.clip_playing, playing);
    CHECK_NEAR(r.info.animation_duration_s, duration_s, 1e-6);
    const bool moves[2] = {a_moves, b_moves};
    for (int i = 0; i < 2; i++) {
        if (moves[i])
            CHECK_MSG(fabs(r.dx[i]) > T_MOVED_PX, "%s: node %c should move (dx %.3f px)",
                      animation ? animation : "default", 'A' + i, r.dx[i]);
        else
            CHECK_MSG(fabs(r.dx[i]) < T_STILL_PX, "%s: node %c should stand (dx %.3f px)",
                      animation ? animation : "default", 'A' + i, r.dx[i]);
        CHECK_EQ_INT((r.flags[i] & XRSC_INSTANCE_FLAG_OBJECT) != 0, moves[i]);
    }
    /* walk moves A to +x, idle moves B to -x */
    if (a_moves)
        CHECK(r.dx[0] > 0.0);
    if (b_moves)
        CHECK(r.dx[1] < 0.0);
}

static void test_clip_choice(void)
{
    const char *path = write_two_clips();
    CHECK(path != NULL);
    if (!path)
        return;
    expect_moves(path, NULL, 0, 1.0, true, false); /* the default: the first clip */
    expect_moves(path, "first", 0, 1.0, true, false);
    expect_moves(path, "walk", 0, 1.0, true, false);
    expect_moves(path, "0", 0, 1.0, true, false);
    expect_moves(path, "idle", 1, 2.0, false, true);
    expect_moves(path, "1", 1, 2.0, false, true);
    expect_moves(path, "all", XRSC_CLIP_ALL, 2.0, true, true);
    expect_moves(path, "none", XRSC_CLIP_NONE, 0.0, false, false);
}

static void test_unknown_clip(void)
{
    const char *path = write_two_clips();
    if (!path)
        return;
    static const char *const bad[] = {"run", "2", "Walk", "-1", "0x1"};
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); k++) {
        xrsc_scene_options so = {.animation = bad[k]};
        xrsc_scene *scene = NULL;
        xrsc_diag diag = {0};
        CHECK_EQ_INT(xrsc_scene_load(g_ctx, path, &so, &scene, &diag),
                     XRSC_ERROR_ANIMATION_UNKNOWN);
        CHECK(scene == NULL);
        CHECK_EQ_INT(diag.code, XRSC_ERROR_ANIMATION_UNKNOWN);
        CHECK(!strcmp(diag.field, "animation"));
    }
    /* A file without clips: all and none are fine, a name is not. */
    xrsc_file_info *fi = calloc(1, sizeof(*fi));
    xrsc_scene_options so = {.animation = "all"};
    CHECK(fi != NULL);
    if (!fi)
        return;
    const char *cornell = t_source_path("scenes/cornell.gltf");
    CHECK_EQ_INT(xrsc_file_inspect(cornell, &so, fi, NULL), XRSC_OK);
    CHECK_EQ_INT(fi->scene.clip_playing, XRSC_CLIP_NONE);
    so.animation = "walk";
    CHECK_EQ_INT(xrsc_file_inspect(cornell, &so, fi, NULL), XRSC_ERROR_ANIMATION_UNKNOWN);
    free(fi);
}

static void test_file_inspect(void)
{
    const char *path = write_two_clips();
    xrsc_file_info *fi = calloc(1, sizeof(*fi));
    CHECK(path && fi);
    if (!path || !fi) {
        free(fi);
        return;
    }
    CHECK_EQ_INT(xrsc_file_inspect(path, NULL, fi, NULL), XRSC_OK);
    CHECK_EQ_INT(fi->clip_count, 2);
    CHECK(!strcmp(fi->clips[0].name, "walk") && !strcmp(fi->clips[1].name, "idle"));
    CHECK_NEAR(fi->clips[0].duration_s, 1.0, 1e-6);
    CHECK_NEAR(fi->clips[1].duration_s, 2.0, 1e-6);
    CHECK_EQ_INT(fi->clips[0].channel_count, 1);
    CHECK_EQ_INT(fi->clips[1].channel_count, 1);
    CHECK_EQ_INT(fi->scene.clip_playing, 0);
    CHECK_EQ_INT(fi->node_count, 2);
    CHECK_EQ_INT(fi->mesh_count, 1);
    CHECK_EQ_INT(fi->scene.instance_count, 2);
    CHECK_EQ_INT(fi->scene.triangle_count, 2);
    CHECK_EQ_INT(fi->skin_count, 0);
    free(fi);
}

int main(void)
{
    if (!(g_ctx = t_context_open()))
        return 1;
    RUN(test_file_inspect);
    RUN(test_clip_choice);
    RUN(test_unknown_clip);
    t_context_close(&g_ctx);
    return t_finish();
}
