// SPDX-License-Identifier: MIT
/**
 * @file test_viewpoint.c
 * @brief Issue 18 in the replay, under the validation layer: --frame shows a 7 mm model
 *        (../shared MetalRoughSpheresNoTextures) and a 10 km box without the first-frame hint
 *        and with less than T_MAX_BACKGROUND of background; without --frame the 7 mm model
 *        gets a hint that says --frame; --viewpoint inside a closed, unlit box gets the
 *        inside-geometry hint; --viewpoint x,y,z:yaw and camera:N place the stream's first pose
 *        there; a camera that does not exist is an error naming --viewpoint.
 * 2 x 24 x 24, one frame each; hint IDs and fractions from hs_replay_stats.
 */
#include "hs_replay.h"
#include "testing.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_SIZE 24u
/* "Not mostly background": below the hint's threshold with room to spare. */
#define T_MAX_BACKGROUND 0.9

/** A closed box of side size_m centred at the origin (12 triangles, no normals: flat), with
 *  nodes for `cameras` perspective cameras at (0, 0, z_k), z_k = size_m * (k + 1). */
/* A closed box, double-sided (a room or sky box is seen from inside; a single-sided box is
 * culled there for camera rays, as glTF viewers cull back faces). */
static const char *box_scene(const char *name, double size_m, int cameras)
{
    float h = (float)(0.5 * size_m);
    const float pos[24] = {-h, -h, -h, h, -h, -h, h, h, -h, -h, h, -h,
                           -h, -h, h,  h, -h, h,  h, h, h,  -h, h, h};
    static const uint16_t idx[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                     3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    uint8_t bytes[96 + 72];
    memcpy(bytes, pos, 96);
    memcpy(bytes + 96, idx, 72);
    char *uri = t_data_uri(bytes, sizeof bytes);
    char nodes[512] = "{\"mesh\":0}", roots[64] = "0";
    for (int k = 0; k < cameras; k++) {
        size_t n = strlen(nodes), r = strlen(roots);
        snprintf(nodes + n, sizeof nodes - n, ",{\"camera\":0,\"translation\":[0,0,%g]}",
                 size_m * (k + 1));
        snprintf(roots + r, sizeof roots - r, ",%d", k + 1);
    }
    size_t cap = strlen(uri) + 4096;
    char *json = malloc(cap);
    snprintf(json, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[%s]}],"
             "\"nodes\":[%s],\"cameras\":[{\"type\":\"perspective\",\"perspective\":"
             "{\"yfov\":1.0,\"znear\":0.01}}],"
             "\"materials\":[{\"doubleSided\":true}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,"
             "\"material\":0}]}],"
             "\"buffers\":[{\"byteLength\":168,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":96},"
             "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":72}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":8,\"type\":"
             "\"VEC3\",\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]},"
             "{\"bufferView\":1,\"componentType\":5123,\"count\":36,\"type\":\"SCALAR\"}]}",
             roots, nodes, uri, -h, -h, -h, h, h, h);
    free(uri);
    const char *path = t_temp_file(name, json);
    free(json);
    return path;
}

typedef struct first_views {
    uint32_t count;
    xrsc_view views[2];
} first_views;

static void on_frame(void *user, const xrsc_frame *frame)
{
    first_views *f = user;
    if (f->count++ == 0) memcpy(f->views, frame->views, sizeof f->views);
}

/** One frame of scene with method m; *st filled; returns the result. */
static xrsc_result run(const char *scene, xrsc_method m, bool frame, const char *viewpoint,
                       hs_replay_stats *st, first_views *fv, xrsc_diag *d)
{
    hs_replay_options opt = {.scene_path = scene,
                             .poses_path = t_source_path("poses/orbit_cornell.xrpose"),
                             .frames = 1,
                             .frame_bounds = frame,
                             .on_frame = on_frame,
                             .on_frame_user = fv};
    opt.context.validation = true;
    opt.renderer.method = m;
    opt.renderer.width = opt.renderer.height = T_SIZE;
    opt.renderer.spp.samples_per_pixel = 1;
    if (viewpoint) CHECK_EQ_INT(hs_viewpoint_parse(viewpoint, &opt.viewpoint, d), XRSC_OK);
    memset(st, 0, sizeof *st);
    xrsc_result r = hs_replay_run(&opt, st, d);
    if (r == XRSC_OK) CHECK_EQ_INT(st->validation_errors, 0);
    return r;
}

static void test_frame_tiny_and_huge(void)
{
    const char *tiny = t_shared_path(
        "scenes/khronos/MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb");
    const char *huge = box_scene("box10km.gltf", 1e4, 0);
    const char *const scenes[2] = {tiny, huge};
    for (int i = 0; i < 2; i++) {
        hs_replay_stats st;
        first_views fv = {0};
        xrsc_diag d = {0};
        char buf[1024];
        xrsc_result r = run(scenes[i], XRSC_METHOD_PRIMARY, true, NULL, &st, &fv, &d);
        CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
        if (r != XRSC_OK) continue;
        printf("  --frame %s: %.1f %% background, hint %s\n", i ? "10 km box" : "7 mm model",
               100.0 * st.first_frame_background, hs_hint_name(st.first_frame_hint));
        CHECK_EQ_INT(st.first_frame_hint, HS_HINT_NONE);
        CHECK(st.first_frame_background < T_MAX_BACKGROUND);
    }
    /* the 7 mm model without --frame: a hint that says --frame */
    hs_replay_stats st;
    first_views fv = {0};
    xrsc_diag d = {0};
    if (run(tiny, XRSC_METHOD_PRIMARY, false, NULL, &st, &fv, &d) == XRSC_OK) {
        printf("  7 mm model, default view: %.1f %% background, hint %s\n",
               100.0 * st.first_frame_background, hs_hint_name(st.first_frame_hint));
        CHECK(st.first_frame_hint == HS_HINT_VIEW_MISSES_SCENE ||
              st.first_frame_hint == HS_HINT_SCENE_TOO_SMALL);
    }
}

static void test_inside_closed_box(void)
{
    hs_replay_stats st;
    first_views fv = {0};
    xrsc_diag d = {0};
    char buf[1024];
    /* a closed 4 m box: the studio light outside never reaches the inside */
    xrsc_result r = run(box_scene("room.gltf", 4.0, 0), XRSC_METHOD_SPP, false, "inside", &st,
                        &fv, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    if (r != XRSC_OK) return;
    printf("  inside a closed box: %.1f %% background, hint %s\n",
           100.0 * st.first_frame_background, hs_hint_name(st.first_frame_hint));
    CHECK_EQ_INT(st.first_frame_hint, HS_HINT_INSIDE_GEOMETRY);
    CHECK_NEAR(0.5 * (fv.views[0].pose.position.x + fv.views[1].pose.position.x), 0.0, 1e-4);
}

static void test_viewpoint_places_stream(void)
{
    const char *two = box_scene("two_cameras.gltf", 1.0, 2);
    hs_replay_stats st;
    first_views fv = {0};
    xrsc_diag d = {0};
    char buf[1024];
    xrsc_result r = run(two, XRSC_METHOD_PRIMARY, false, "1,2,3:90", &st, &fv, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    if (r == XRSC_OK) {
        /* the head (between the eyes) at (1, 2, 3); yaw 90: the eyes sit along z */
        const XrVector3f *a = &fv.views[0].pose.position, *b = &fv.views[1].pose.position;
        CHECK_NEAR(0.5 * (a->x + b->x), 1.0, 1e-4);
        CHECK_NEAR(0.5 * (a->y + b->y), 2.0, 1e-4);
        CHECK_NEAR(0.5 * (a->z + b->z), 3.0, 1e-4);
        CHECK_NEAR(a->x, b->x, 1e-4);
        CHECK(fabsf(a->z - b->z) > 0.05f);
    }
    fv.count = 0;
    r = run(two, XRSC_METHOD_PRIMARY, false, "camera:1", &st, &fv, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    if (r == XRSC_OK) /* camera 1's node: (0, 0, 2) */
        CHECK_NEAR(0.5 * (fv.views[0].pose.position.z + fv.views[1].pose.position.z), 2.0, 1e-4);
    memset(&d, 0, sizeof d);
    CHECK_EQ_INT(run(two, XRSC_METHOD_PRIMARY, false, "camera:2", &st, &fv, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(!strcmp(d.field, "--viewpoint"));
}

int main(void)
{
    RUN(test_frame_tiny_and_huge);
    RUN(test_inside_closed_box);
    RUN(test_viewpoint_places_stream);
    return t_finish();
}
