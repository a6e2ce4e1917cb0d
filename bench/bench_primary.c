// SPDX-License-Identifier: MIT
/**
 * @file bench_primary.c
 * @brief Primary-ray throughput and BLAS build time per scene, as one table from one run.
 *        Prints, never asserts (not a test: speed is never checked).
 *
 * Usage: bench_primary [-s size_px] [-n frames] [-d device] [-S shared_dir] [-U] [scene...]
 * Default: 512 x 512 per eye (both eyes in one trace), 5 frames after 1 warm-up frame, the
 * scenes scenes/furnace.gltf, scenes/cornell.gltf and the two shared scenes (under the shared
 * folder: the compile definition XRSC_SHARED_DIR unless -S; missing files are skipped).
 *
 * Per scene: Mrays/s = rays of the frame / GPU time of its "trace" pass (timestamp queries,
 * mean and best over the frames), the GPU time of the BLAS builds at load, the hit fraction,
 * the wall time of xrsc_renderer_render, the ratio of Mrays/s to the first scene's, and (unless
 * -U) the same scene loaded with keep_triangle_order (no Morton sort): its BLAS ms, Mrays/s and
 * the sort's speed-up (sorted / unsorted Mrays/s).
 */
#include "xrsc/xrsc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define BENCH_DEFAULT_SIZE_PX 512u
#define BENCH_DEFAULT_FRAMES 5u
#define BENCH_MAX_SCENES 32

typedef struct bench_result {
    bool ok;
    uint64_t triangles;
    double blas_ms;
    double trace_ms_mean, trace_ms_best;
    double wall_ms_mean;
    double mrays_mean, mrays_best;
    double hit_fraction;
    uint64_t rays;
} bench_result;

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

static bench_result bench_scene(xrsc_context *ctx, const char *path, bool keep_order,
                                uint32_t size, uint32_t frames)
{
    bench_result br = {0};
    xrsc_diag diag;
    char buf[1024];
    xrsc_scene *scene = NULL;
    xrsc_scene_options so = {.keep_triangle_order = keep_order};
    if (xrsc_scene_load(ctx, path, &so, &scene, &diag) != XRSC_OK) {
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        return br;
    }
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = size, .height = size};
    xrsc_renderer *r = NULL;
    if (xrsc_renderer_create(ctx, scene, &ro, &r, &diag) != XRSC_OK) {
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        xrsc_scene_destroy(&scene);
        return br;
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
    double best = 1e30, sum = 0.0, wall = 0.0;
    bool ok = true;
    for (uint32_t f = 0; f <= frames; f++) {
        frame.frame_index = f;
        double t0 = now_ms();
        if (xrsc_renderer_render(r, &frame) != XRSC_OK) {
            fprintf(stderr, "%s: render failed\n", path);
            ok = false;
            break;
        }
        double t1 = now_ms();
        xrsc_pass_timing tm[XRSC_MAX_PASSES];
        uint32_t n = xrsc_renderer_timings(r, tm, XRSC_MAX_PASSES);
        double ms = 0.0;
        for (uint32_t i = 0; i < n; i++)
            if (!strcmp(tm[i].name, "trace"))
                ms = tm[i].gpu_ms;
        br.rays = xrsc_renderer_rays_last_frame(r);
        if (f == 0)
            continue; /* warm-up */
        sum += ms;
        wall += t1 - t0;
        if (ms < best)
            best = ms;
    }
    /* Hit fraction of the last frame (both eyes). */
    size_t bytes = xrsc_renderer_output_size(r, XRSC_OUTPUT_HIT_ID);
    uint32_t *hit = malloc(bytes);
    uint64_t hits = 0, px = 0;
    for (uint32_t e = 0; ok && hit && e < 2; e++) {
        if (xrsc_renderer_read(r, e, XRSC_OUTPUT_HIT_ID, hit, bytes) != XRSC_OK)
            break;
        for (size_t p = 0; p < bytes / 16; p++, px++)
            hits += hit[4 * p] != UINT32_MAX;
    }
    free(hit);
    if (ok && frames > 0) {
        br.ok = true;
        br.triangles = info.triangle_count;
        br.blas_ms = info.blas_build_ms;
        br.trace_ms_mean = sum / frames;
        br.trace_ms_best = best;
        br.wall_ms_mean = wall / frames;
        br.mrays_mean = br.trace_ms_mean > 0.0 ? (double)br.rays / (br.trace_ms_mean * 1e3) : 0.0;
        br.mrays_best = best > 0.0 ? (double)br.rays / (best * 1e3) : 0.0;
        br.hit_fraction = px ? (double)hits / (double)px : 0.0;
    }
    xrsc_renderer_destroy(&r);
    xrsc_scene_destroy(&scene);
    return br;
}

static bool file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int main(int argc, char **argv)
{
    uint32_t size = BENCH_DEFAULT_SIZE_PX, frames = BENCH_DEFAULT_FRAMES;
    const char *device = NULL, *shared = XRSC_SHARED_DIR;
    bool unsorted = true;
    int first = 1;
    for (; first < argc && argv[first][0] == '-'; first++) {
        if (!strcmp(argv[first], "-s") && first + 1 < argc)
            size = (uint32_t)strtoul(argv[++first], NULL, 10);
        else if (!strcmp(argv[first], "-n") && first + 1 < argc)
            frames = (uint32_t)strtoul(argv[++first], NULL, 10);
        else if (!strcmp(argv[first], "-d") && first + 1 < argc)
            device = argv[++first];
        else if (!strcmp(argv[first], "-S") && first + 1 < argc)
            shared = argv[++first];
        else if (!strcmp(argv[first], "-U"))
            unsorted = false;
        else {
            fprintf(stderr,
                    "usage: %s [-s size_px] [-n frames] [-d device] [-S shared_dir] [-U] "
                    "[scene.gltf...]\n"
                    "  -U: skip the unsorted (keep_triangle_order) comparison\n",
                    argv[0]);
            return 2;
        }
    }
    if (size == 0 || frames == 0) {
        fprintf(stderr, "size and frames must be > 0\n");
        return 2;
    }

    static char paths[BENCH_MAX_SCENES][1024];
    int n = 0;
    if (first == argc) {
        snprintf(paths[n++], sizeof(paths[0]), "%s/scenes/furnace.gltf", XRSC_SOURCE_DIR);
        snprintf(paths[n++], sizeof(paths[0]), "%s/scenes/cornell.gltf", XRSC_SOURCE_DIR);
        snprintf(paths[n++], sizeof(paths[0]),
                 "%s/scenes/cornellBox_Vinc3r/cornellBox-2.80-Eevee-gltf.gltf", shared);
        snprintf(paths[n++], sizeof(paths[0]),
                 "%s/scenes/GlassHurricaneCandleHolder/GlassHurricaneCandleHolder.gltf", shared);
    }
    for (int i = first; i < argc && n < BENCH_MAX_SCENES; i++)
        snprintf(paths[n++], sizeof(paths[0]), "%s", argv[i]);

    xrsc_context_options o = {.device = device};
    xrsc_context *ctx = NULL;
    xrsc_diag diag;
    char buf[1024];
    if (xrsc_context_create(&o, &ctx, &diag) != XRSC_OK) {
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        return 1;
    }
    printf("device: %s; method primary, %u x %u per eye x 2 eyes = %llu rays/frame; "
           "%u frames after 1 warm-up\n",
           xrsc_context_device_name(ctx), size, size, 2ull * size * size, frames);

    bench_result sorted[BENCH_MAX_SCENES] = {0}, plain[BENCH_MAX_SCENES] = {0};
    int rc = 0;
    for (int i = 0; i < n; i++) {
        if (!file_exists(paths[i])) {
            fprintf(stderr, "skipped (not found): %s\n", paths[i]);
            continue;
        }
        sorted[i] = bench_scene(ctx, paths[i], false, size, frames);
        if (!sorted[i].ok)
            rc = 1;
        else if (unsorted)
            plain[i] = bench_scene(ctx, paths[i], true, size, frames);
    }

    int ref = -1;
    for (int i = 0; i < n && ref < 0; i++)
        if (sorted[i].ok)
            ref = i;
    printf("\n%-36s %8s %5s %8s %9s %9s %8s %8s %7s", "scene", "tris", "hit%", "BLAS ms",
           "trace ms", "(best)", "Mrays/s", "(best)", "wall ms");
    if (ref >= 0)
        printf(" %7s", "x ref");
    if (unsorted)
        printf(" | %12s %13s %9s", "unsorted BLAS", "unsorted Mr/s", "sort gain");
    printf("\n");
    for (int i = 0; i < n; i++) {
        const bench_result *b = &sorted[i];
        if (!b->ok)
            continue;
        printf("%-36.36s %8llu %5.1f %8.2f %9.2f %9.2f %8.2f %8.2f %7.1f", base_name(paths[i]),
               (unsigned long long)b->triangles, 100.0 * b->hit_fraction, b->blas_ms,
               b->trace_ms_mean, b->trace_ms_best, b->mrays_mean, b->mrays_best,
               b->wall_ms_mean);
        printf(" %7.2f", sorted[ref].mrays_mean > 0.0 ? b->mrays_mean / sorted[ref].mrays_mean
                                                      : 0.0);
        if (unsorted && plain[i].ok)
            printf(" | %12.2f %13.2f %8.2fx", plain[i].blas_ms, plain[i].mrays_mean,
                   plain[i].mrays_mean > 0.0 ? b->mrays_mean / plain[i].mrays_mean : 0.0);
        printf("\n");
    }
    if (ref >= 0)
        printf("x ref: Mrays/s relative to %s. trace/BLAS ms: GPU timestamps; wall ms: "
               "xrsc_renderer_render (submit + wait)\n",
               base_name(paths[ref]));
    xrsc_context_destroy(&ctx);
    return rc;
}
