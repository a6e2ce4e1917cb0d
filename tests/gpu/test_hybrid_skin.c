// SPDX-License-Identifier: MIT
/**
 * @file test_hybrid_skin.c
 * @brief `hybrid` follows a deforming surface (issue 21 item 3): on the project's walking
 *        figure (scenes/character.gltf) more of the reconstruction's lookups on the figure find
 *        a voxel holding earlier frames' samples when its voxels follow the skin (xs_hashcache.h,
 *        hc_deform.glsl) than keyed by this frame's position only, validation layer on.
 */
#include "mt_hashcache.h"
#include "mt_method.h"
#include "test_samplecache_util.h"

#define T_SCENE "scenes/character.gltf"
#define T_W 32u
#define T_FRAMES 8u
#define T_FIRST_SCORED 2u   /**< frames before it fill the sample cache and the table */
#define T_T0_S 0.3          /**< clip time of the first frame (mid-stride) */
#define T_DT_S (1.0 / 30.0) /**< s per frame: the figure walks 1 m/s, ~3 cm a frame */
#define T_MIN_LOOKUPS 100u  /**< the figure is on screen */
#define T_MIN_GAIN 0.1      /**< history share gained by following (measured: see README) */

/** `hybrid` on the walking figure, T_FRAMES frames from T_T0_S: the share of the figure's
 *  reconstruction lookups whose radiance holds earlier frames' samples over the frames from
 *  T_FIRST_SCORED on (mt_hybrid_deform_stats); follow false: the test-only switch off. */
static double run_hybrid(bool follow)
{
    tsc_rig r = {.width = T_W, .height = T_W};
    xrsc_diag diag = {0};
    gpu_context_options go = {.validation = true};
    xrsc_result res = gpu_context_create(&go, &r.gpu, &diag);
    if (res == XRSC_OK)
        res = sc_scene_load(t_source_path(T_SCENE), NULL, &r.cpu, &diag);
    if (res == XRSC_OK)
        res = gpu_scene_create(r.gpu, r.cpu, &r.gs, &diag);
    mt_env env = {.gpu = r.gpu, .scene = r.gs, .cpu_scene = r.cpu, .width = T_W, .height = T_W};
    xrsc_samplecache_options so = {0};
    xrsc_hashcache_options ho = {.table_entries = 1u << 16};
    if (res == XRSC_OK)
        res = mt_hybrid_create(&env, &so, &ho, &r.m, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    else
        mt_hybrid_set_deform_follow(r.m, follow);
    uint64_t lookups = 0, history = 0;
    for (uint32_t k = 0; res == XRSC_OK && k < T_FRAMES; k++) {
        double t = T_T0_S + k * T_DT_S;
        xrsc_frame f = tsc_viewpoint_stereo(r.cpu, k, t);
        tsc_set_time(&r, t);
        res = tsc_render(r.m, &f) ? XRSC_OK : XRSC_ERROR_VULKAN;
        uint32_t l = 0, h = 0;
        if (res == XRSC_OK && k >= T_FIRST_SCORED) {
            mt_hybrid_deform_stats(r.m, &l, &h);
            lookups += l, history += h;
        }
    }
    CHECK_MSG(lookups > T_MIN_LOOKUPS, "only %llu lookups on the figure",
              (unsigned long long)lookups);
    tsc_close(&r);
    return lookups ? (double)history / lookups : 0.0;
}

static void test_hybrid_follows_skin(void)
{
    double on = run_hybrid(true), off = run_hybrid(false);
    printf("  hybrid on %s (walk): figure lookups finding history %.1f %% following the skin, "
           "%.1f %% keyed by this frame's position only\n",
           T_SCENE, 100.0 * on, 100.0 * off);
    CHECK(on > off + T_MIN_GAIN);
}

int main(void)
{
    RUN(test_hybrid_follows_skin);
    return t_finish();
}
