// SPDX-License-Identifier: MIT
/**
 * @file test_order.c
 * @brief The sample cache and its shadow visibility cache give bit-identical results whatever
 *        order the invocations of a pass run in (a GPU runs them in no fixed order).
 *
 * lavapipe runs a dispatch's invocations in a fixed order, so a result that depends on that
 * order looks reproducible there. XRSC_DEBUG_PERMUTE=1 (mt_samplecache.c) makes the reproject,
 * density, trace, shade importance, shade select and shade launches take their work items in
 * reverse order (so the sample pool hands its free entries out in another order too: issue
 * 19); each case renders the same frames (the head sliding sideways, so reprojection piles
 * several samples onto some pixels, and the visibility cache on) with the identity and the
 * reversed order and asserts the same colour bits and the same visibility cache counters.
 * Before the order-independent reservation (sc_reproject.comp) and insertion
 * (xs_viscache.glsl), every case failed (the commit that added this test: 2757 of 8192 floats
 * differed with default options at 32 x 32, and the visibility cache's counters differed from
 * frame 0 on). The size is not a multiple of the 8 x 8 workgroups, so the reversed order also
 * hands workgroups pixels that straddle two of them (a pass that shares data within a
 * workgroup must place it where sc_work_item puts the group).
 */
#include "test_samplecache_util.h"

#include <stdlib.h>

#define T_W 26u /* 3 workgroups and 2 pixels */
#define T_FRAMES 3u
/* sideways head step per frame, m: a few pixels of parallax at the Cornell box's depth */
#define T_STEP_M 0.02f
#define T_PERMUTE_ENV "XRSC_DEBUG_PERMUTE"

/** One run: the colour of both eyes after T_FRAMES frames, and the cache counters per frame. */
typedef struct run_out {
    float *color;
    size_t floats;
    double queries[T_FRAMES], cached[T_FRAMES], shadow_rays[T_FRAMES];
} run_out;

static bool run(tsc_rig *rig, const xrsc_samplecache_options *o, bool permute, run_out *out)
{
    memset(out, 0, sizeof(*out));
    if (permute)
        setenv(T_PERMUTE_ENV, "1", 1); /* read when the method is created */
    mt_method *m = tsc_new_method(rig, o);
    unsetenv(T_PERMUTE_ENV);
    if (!m)
        return false;
    XrPosef head = tsc_viewpoint(rig->cpu);
    bool ok = true;
    for (uint32_t k = 0; ok && k < T_FRAMES; k++) {
        XrPosef hk = head;
        hk.position.x += (float)k * T_STEP_M;
        xrsc_frame f = tsc_headset_frame(hk, k);
        f.display_time_ns = 0;
        ok = tsc_render(m, &f);
        out->queries[k] = tsc_counter(m, "vc_queries");
        out->cached[k] = tsc_counter(m, "vc_cached");
        out->shadow_rays[k] = tsc_counter(m, "vc_shadow_rays");
    }
    size_t eye_bytes = mt_method_output_size(m, XRSC_OUTPUT_COLOR);
    out->floats = 2 * eye_bytes / sizeof(float);
    out->color = malloc(2 * eye_bytes);
    xrsc_diag diag = {0};
    for (uint32_t e = 0; ok && out->color && e < 2; e++)
        ok = mt_method_read(m, e, XRSC_OUTPUT_COLOR, (uint8_t *)out->color + e * eye_bytes,
                            eye_bytes, &diag) == XRSC_OK;
    mt_method_destroy(&m);
    return ok && out->color;
}

static size_t floats_differing(const run_out *a, const run_out *b)
{
    size_t n = 0;
    for (size_t i = 0; i < a->floats && i < b->floats; i++)
        n += memcmp(&a->color[i], &b->color[i], sizeof(float)) != 0;
    return n + (a->floats != b->floats);
}

/** Renders case `name` in both orders and compares. */
static void check_case(tsc_rig *rig, const char *name, const xrsc_samplecache_options *o,
                       bool cache_on)
{
    run_out id = {0}, rev = {0};
    bool ok = run(rig, o, false, &id) && run(rig, o, true, &rev);
    CHECK_MSG(ok, "%s: render failed", name);
    if (ok) {
        size_t differ = floats_differing(&id, &rev);
        printf("  %s: %zu of %zu floats differ; cached %.0f / %.0f (identity), %.0f / %.0f "
               "(reversed) in the last frame\n",
               name, differ, id.floats, id.cached[T_FRAMES - 1], id.queries[T_FRAMES - 1],
               rev.cached[T_FRAMES - 1], rev.queries[T_FRAMES - 1]);
        CHECK_MSG(differ == 0, "%s: %zu floats differ between the orders", name, differ);
        for (uint32_t k = 0; k < T_FRAMES; k++) {
            CHECK_MSG(id.queries[k] == rev.queries[k] && id.cached[k] == rev.cached[k] &&
                          id.shadow_rays[k] == rev.shadow_rays[k],
                      "%s frame %u: cache counters differ (cached %.0f vs %.0f)", name, k,
                      id.cached[k], rev.cached[k]);
        }
        /* power: the cache must answer something, else the counters prove nothing */
        if (cache_on)
            CHECK_MSG(id.cached[T_FRAMES - 1] > 0.0, "%s: nothing cached", name);
    }
    free(id.color);
    free(rev.color);
}

static void test_order(void)
{
    tsc_rig rig;
    xrsc_samplecache_options off = {0};
    if (!tsc_open(&rig, t_source_path("scenes/cornell.gltf"), T_W, T_W, &off)) {
        tsc_close(&rig);
        return;
    }
    /* cross-eye reuse adds the copies from the other eye to the reservation */
    xrsc_samplecache_options cross = {.cross_eye = true};
    xrsc_samplecache_options vis = {.visibility = {.enabled = true}};
    check_case(&rig, "cross-eye", &cross, false);
    check_case(&rig, "visibility cache", &vis, true);
    /* variance-guided shading (issue 19): the importance pass sums each pixel's histogram
     * counts before its atomics and hands candidates and variance to the selection */
    xrsc_samplecache_options var = {.shade = XRSC_SC_SHADE_ADAPTIVE_VARIANCE, .shade_rate = 0.3f};
    check_case(&rig, "variance-guided shading", &var, false);
    tsc_close(&rig);
}

int main(void)
{
    RUN(test_order);
    return t_finish();
}
