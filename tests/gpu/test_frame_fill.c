// SPDX-License-Identifier: MIT
/**
 * @file test_frame_fill.c
 * @brief Issue 18: --frame (hs_view_frame, with the IPD hs_frame_ipd_m gives) puts the 7.5 mm
 *        MetalRoughSpheresNoTextures grid in the middle of the default (asymmetric) headset's
 *        view and makes it fill it: in each eye its hit pixels span at least T_FILL_FRACTION
 *        of the image on one axis, the middle of their vertical extent lies within
 *        T_CENTRE_FRACTION of the image's middle, and their horizontal middles lie symmetric
 *        about it (each eye's image is wider towards its temple, so one head pose cannot
 *        centre the grid in both images: it is centred between them).
 *
 * Primary rays (exact hits, depth output), 64 x 64 per eye, under the validation layer. The
 * bounding-sphere fit this replaces, on the eyes' axes, left the grid at about half the image
 * (the sphere of a flat grid is 1.4 times its half-width) and 5 % of the image above the
 * middle (the view reaches 53 degrees down, 47 up).
 */
#include "hs_view.h"
#include "t_context.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_math.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#define T_SIZE 64u
/** The grid's hits span at least this fraction of the image on one axis: it fills the view. */
#define T_FILL_FRACTION 0.68
/** The middle of its extent within this fraction of the image size from the image's middle. */
#define T_CENTRE_FRACTION 0.03

static void test_tiny_model_fills_and_centres(void)
{
    xrsc_context *ctx = t_context_open();
    if (!ctx)
        return;
    const char *path = t_shared_path(
        "scenes/khronos/MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb");
    char buf[1024];
    xrsc_diag d;
    xrsc_scene *scene = NULL;
    xrsc_renderer *rend = NULL;
    xrsc_result r = xrsc_scene_load(ctx, path, NULL, &scene, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = T_SIZE, .height = T_SIZE};
    if (r == XRSC_OK)
        r = xrsc_renderer_create(ctx, scene, &ro, &rend, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    float *depth = malloc(T_SIZE * T_SIZE * sizeof(float));
    double mx_sum = 0.0;
    if (r == XRSC_OK && depth) {
        xrsc_scene_info info;
        xrsc_scene_get_info(scene, &info);
        xrsc_headset hs;
        xrsc_headset_default(&hs);
        hs.ipd_m = (float)hs_frame_ipd_m(&info, hs.fov, hs.ipd_m);
        XrPosef eyes[2];
        xrsc_headset_eye_poses(&hs, hs_view_frame(&info, hs.fov, hs.ipd_m), eyes);
        xrsc_frame frame = {0};
        for (int e = 0; e < 2; e++)
            frame.views[e] = (xrsc_view){.pose = eyes[e], .fov = hs.fov[e]};
        CHECK_EQ_INT(xrsc_renderer_render(rend, &frame), XRSC_OK);
        for (uint32_t e = 0; e < 2; e++) {
            CHECK_EQ_INT(xrsc_renderer_read(rend, e, XRSC_OUTPUT_DEPTH, depth,
                                            T_SIZE * T_SIZE * sizeof(float)),
                         XRSC_OK);
            int x0 = T_SIZE, x1 = -1, y0 = T_SIZE, y1 = -1;
            for (int y = 0; y < (int)T_SIZE; y++)
                for (int x = 0; x < (int)T_SIZE; x++)
                    if (depth[y * T_SIZE + x] > 0.0f) {
                        x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
                        y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
                    }
            double mx = 0.5 * (x0 + x1 + 1) / T_SIZE - 0.5, my = 0.5 * (y0 + y1 + 1) / T_SIZE - 0.5;
            printf("eye %u: hits x %d..%d, y %d..%d of %u; middle off by %.3f, %.3f\n", e, x0, x1,
                   y0, y1, T_SIZE, mx, my);
            CHECK(x1 >= x0);
            int span = x1 - x0 > y1 - y0 ? x1 - x0 + 1 : y1 - y0 + 1;
            CHECK(span >= T_FILL_FRACTION * T_SIZE);
            CHECK(fabs(my) <= T_CENTRE_FRACTION);
            mx_sum += mx;
        }
        CHECK(fabs(0.5 * mx_sum) <= T_CENTRE_FRACTION);
    }
    free(depth);
    xrsc_renderer_destroy(&rend);
    xrsc_scene_destroy(&scene);
    t_context_close(&ctx);
}

int main(void)
{
    RUN(test_tiny_model_fills_and_centres);
    return t_finish();
}
