// SPDX-License-Identifier: MIT
/**
 * @file bench_primary.c
 * @brief Primary-ray throughput (Mrays/s from the GPU time of the "trace" pass) and BLAS build
 *        time per scene. Prints, never asserts.
 *
 * Usage: bench_primary [-s size_px] [-n frames] [-d device] scene.gltf...
 * Default: 512 x 512 per eye, 5 frames after 1 warm-up frame, the scenes of the test suite.
 */
#include "xrsc/xrsc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BENCH_DEFAULT_SIZE_PX 512u
#define BENCH_DEFAULT_FRAMES 5u

static int bench_scene(xrsc_context *ctx, const char *path, uint32_t size, uint32_t frames)
{
    xrsc_diag diag;
    char buf[1024];
    xrsc_scene *scene = NULL;
    if (xrsc_scene_load(ctx, path, NULL, &scene, &diag) != XRSC_OK) {
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        return 1;
    }
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = size, .height = size};
    xrsc_renderer *r = NULL;
    if (xrsc_renderer_create(ctx, scene, &ro, &r, &diag) != XRSC_OK) {
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        xrsc_scene_destroy(&scene);
        return 1;
    }
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    XrPosef eyes[2];
    xrsc_headset_eye_poses(&hs, info.viewpoint, eyes);
    xrsc_frame frame = {0};
    for (int e = 0; e < 2; e++) {
        frame.views[e].pose = eyes[e];
        frame.views[e].fov = hs.fov[e];
    }
    double best = 1e30, sum = 0.0;
    uint64_t rays = 0;
    int rc = 0;
    for (uint32_t f = 0; f <= frames; f++) {
        frame.frame_index = f;
        if (xrsc_renderer_render(r, &frame) != XRSC_OK) {
            fprintf(stderr, "%s: render failed\n", path);
            rc = 1;
            break;
        }
        xrsc_pass_timing tm[XRSC_MAX_PASSES];
        uint32_t n = xrsc_renderer_timings(r, tm, XRSC_MAX_PASSES);
        double ms = 0.0;
        for (uint32_t i = 0; i < n; i++)
            if (!strcmp(tm[i].name, "trace"))
                ms = tm[i].gpu_ms;
        rays = xrsc_renderer_rays_last_frame(r);
        if (f == 0)
            continue; /* warm-up */
        sum += ms;
        if (ms < best)
            best = ms;
    }
    if (rc == 0 && frames > 0) {
        double mean = sum / frames;
        printf("%-40s tris %9llu  blas %8.2f ms  trace %8.2f ms (best %8.2f)  %6.2f Mrays/s "
               "(best %6.2f)  rays/frame %llu\n",
               strrchr(path, '/') ? strrchr(path, '/') + 1 : path,
               (unsigned long long)info.triangle_count, info.blas_build_ms, mean, best,
               (double)rays / (mean * 1e3), (double)rays / (best * 1e3),
               (unsigned long long)rays);
    }
    xrsc_renderer_destroy(&r);
    xrsc_scene_destroy(&scene);
    return rc;
}

int main(int argc, char **argv)
{
    uint32_t size = BENCH_DEFAULT_SIZE_PX, frames = BENCH_DEFAULT_FRAMES;
    const char *device = NULL;
    int first = 1;
    for (; first < argc && argv[first][0] == '-'; first++) {
        if (!strcmp(argv[first], "-s") && first + 1 < argc)
            size = (uint32_t)strtoul(argv[++first], NULL, 10);
        else if (!strcmp(argv[first], "-n") && first + 1 < argc)
            frames = (uint32_t)strtoul(argv[++first], NULL, 10);
        else if (!strcmp(argv[first], "-d") && first + 1 < argc)
            device = argv[++first];
        else {
            fprintf(stderr, "usage: %s [-s size_px] [-n frames] [-d device] scene.gltf...\n",
                    argv[0]);
            return 2;
        }
    }
    xrsc_context_options o = {.device = device};
    xrsc_context *ctx = NULL;
    xrsc_diag diag;
    char buf[1024];
    if (xrsc_context_create(&o, &ctx, &diag) != XRSC_OK) {
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        return 1;
    }
    printf("device: %s, %u x %u per eye x 2 eyes, %u frames\n", xrsc_context_device_name(ctx),
           size, size, frames);
    int rc = 0;
    if (first == argc) {
        static const char *const defaults[] = {
            XRSC_SHARED_DIR "/scenes/cornellBox_Vinc3r/cornellBox-2.80-Eevee-gltf.gltf",
            XRSC_SHARED_DIR "/scenes/GlassHurricaneCandleHolder/GlassHurricaneCandleHolder.gltf",
            XRSC_SOURCE_DIR "/scenes/cornell.gltf",
            XRSC_SOURCE_DIR "/scenes/furnace.gltf",
            XRSC_SOURCE_DIR "/scenes/triangles.gltf",
        };
        for (size_t i = 0; i < sizeof(defaults) / sizeof(defaults[0]); i++)
            rc |= bench_scene(ctx, defaults[i], size, frames);
    }
    for (int i = first; i < argc; i++)
        rc |= bench_scene(ctx, argv[i], size, frames);
    xrsc_context_destroy(&ctx);
    return rc;
}
