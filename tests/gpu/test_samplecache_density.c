// SPDX-License-Identifier: MIT
/**
 * @file test_samplecache_density.c
 * @brief Density control of the sample cache (seed 000 §3.2) and the cache invariants after
 *        every frame, on scenes/cornell.gltf at 2 x 48 x 48 (and 2 x 45 x 37).
 *
 * A replay: T_MOVE_FRAMES frames of the head backing away fast (T_BACK_STEP per frame: the
 * reprojected samples crowd together, up to N per pixel) and turning, then T_STILL_FRAMES of a
 * still view. After EVERY frame, both eyes (tsc_check_invariants):
 * - no mask bit of a slot >= N, v_s implies o_s (so no pixel holds more than N samples);
 * - every pixel keeps >= 1 visible sample (Cornell's background pixels hold background
 *   samples, so this covers every pixel that sees geometry);
 * - every occupied slot decodes to a valid first hit (or unit background direction) whose
 *   position projects into the pixel that holds it (the mask agrees with the stored samples).
 * On the still view, from T_SETTLE frames after it starts on, EVERY pixel's 3 x 3 mean of
 * visible samples lies in [n_target - delta, n_target + delta] (the neighbourhood clipped to
 * the image, as sc_density.comp measures it). Run with the defaults (4 +- 1) and with
 * n_target 2.5 +- 0.5, N = 6; and with the defaults at a size that leaves workgroups partly
 * outside the image.
 */
#include "test_samplecache_util.h"

#define T_W 48u
#define T_H 48u
#define T_ODD_W 45u
#define T_ODD_H 37u
#define T_MOVE_FRAMES 4u
#define T_STILL_FRAMES 12u
#define T_BACK_STEP 0.12f /* m per frame, backwards */
#define T_TURN_STEP 0.03  /* rad per frame about the vertical */
/* Frames of the still view after which every 3 x 3 mean is inside the band. */
#define T_SETTLE 6u

static void run_density(const char *label, const xrsc_samplecache_options *opt, uint32_t w,
                        uint32_t h)
{
    printf("  %s\n", label);
    tsc_rig rig;
    if (!tsc_open(&rig, t_source_path("scenes/cornell.gltf"), w, h, opt)) {
        tsc_close(&rig);
        return;
    }
    const xrsc_samplecache_options *o = mt_samplecache_options(rig.m);
    double lo = o->n_target - o->delta, hi = o->n_target + o->delta;
    XrPosef start = tsc_viewpoint(rig.cpu);
    uint32_t total = T_MOVE_FRAMES + T_STILL_FRAMES;
    uint32_t *vis = malloc(w * h * sizeof(uint32_t));
    for (uint32_t k = 0; k < total; k++) {
        uint32_t m = k < T_MOVE_FRAMES ? k : T_MOVE_FRAMES;
        XrPosef head = start;
        /* backwards along the view's +z (the viewpoint looks down -z) and a turn */
        head.position.z += T_BACK_STEP * (float)m;
        XrPosef turn = {.orientation = tsc_quat_axis(0, 1, 0, T_TURN_STEP * m)};
        head.orientation =
            xrsc_pose_mul((XrPosef){.orientation = start.orientation}, turn).orientation;
        xrsc_frame f = tsc_headset_frame(head, k);
        if (!tsc_render(rig.m, &f))
            break;
        uint32_t out_of_band = 0, max_samples = 0;
        double min_mean = 1e9, max_mean = 0.0;
        for (uint32_t e = 0; e < 2; e++) {
            mt_sc_snapshot sn;
            if (!tsc_snapshot(rig.m, e, &sn))
                continue;
            tsc_view v;
            tsc_make_view(&f.views[e], w, h, &v);
            tsc_invariants c = {0};
            tsc_check_invariants(&sn, rig.cpu, &v, &c);
            CHECK_MSG(c.bad_bits == 0 && c.vis_not_occ == 0,
                      "frame %u eye %u: %u masks with bits >= N, %u v without o", k, e, c.bad_bits,
                      c.vis_not_occ);
            CHECK_MSG(c.no_visible == 0, "frame %u eye %u: %u pixels without a visible sample", k,
                      e, c.no_visible);
            CHECK_MSG(c.bad_hit == 0, "frame %u eye %u: %u samples decode to no valid hit", k, e,
                      c.bad_hit);
            CHECK_MSG(c.outside == 0, "frame %u eye %u: %u samples outside their pixel", k, e,
                      c.outside);
            for (uint32_t p = 0; p < w * h; p++) {
                vis[p] = tsc_popcount(tsc_vis(&sn, p));
                uint32_t occ = tsc_popcount(tsc_occ(&sn, p));
                max_samples = occ > max_samples ? occ : max_samples;
            }
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++) {
                    uint32_t sum = 0, n = 0;
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int xx = (int)x + dx, yy = (int)y + dy;
                            if (xx < 0 || yy < 0 || xx >= (int)w || yy >= (int)h)
                                continue;
                            sum += vis[yy * w + xx];
                            n++;
                        }
                    double mean = (double)sum / n;
                    min_mean = fmin(min_mean, mean);
                    max_mean = fmax(max_mean, mean);
                    out_of_band += mean < lo || mean > hi;
                }
            mt_sc_snapshot_free(&sn);
        }
        printf("    frame %2u (%s): 3x3 mean %.2f..%.2f, %4u of %u pixels outside [%.1f, %.1f], "
               "at most %u samples in a pixel\n",
               k, k < T_MOVE_FRAMES ? "moving" : "still ", min_mean, max_mean, out_of_band,
               2 * w * h, lo, hi, max_samples);
        if (k >= T_MOVE_FRAMES + T_SETTLE)
            CHECK_MSG(out_of_band == 0, "frame %u: %u pixels' 3x3 mean outside the band", k,
                      out_of_band);
    }
    free(vis);
    tsc_close(&rig);
}

static void test_density_defaults(void)
{
    xrsc_samplecache_options o = {0};
    run_density("defaults: N = 12, n_target 4 +- 1", &o, T_W, T_H);
}

/* A size that is no multiple of the 8 x 8 workgroups: partly filled workgroups at the right
 * and bottom measure their neighbourhoods as the others do. */
static void test_density_odd_size(void)
{
    xrsc_samplecache_options o = {0};
    run_density("defaults at 2 x 45 x 37", &o, T_ODD_W, T_ODD_H);
}

static void test_density_low(void)
{
    xrsc_samplecache_options o = {.slots = 6, .n_target = 2.5f, .delta = 0.5f};
    run_density("N = 6, n_target 2.5 +- 0.5", &o, T_W, T_H);
}

int main(void)
{
    RUN(test_density_defaults);
    RUN(test_density_low);
    RUN(test_density_odd_size);
    return t_finish();
}
