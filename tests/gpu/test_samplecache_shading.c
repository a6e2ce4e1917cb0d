// SPDX-License-Identifier: MIT
/**
 * @file test_samplecache_shading.c
 * @brief Shading of the sample cache (seed 000 §3.3, §3.5): adaptive shading's rate and
 *        preference, convergence of a still view to the path-traced reference, and the cache's
 *        memory per pixel.
 *
 * - test_adaptive_rate: scenes/cornell.gltf, 2 x 32 x 32, a still view, shade adaptive at rates
 *   25 %, 50 %, 100 %. For every frame from the third on, both eyes, from the snapshots of this
 *   frame and the previous one (pre-shading c_s of each candidate = the previous frame's c_s of
 *   the same first hit, 0 for new samples; the histogram and the previous frame's importance
 *   bounds from the statistics), the test rebuilds sc_shade_select.comp's choice in C: the
 *   base-rate sample (one per 4 x 4 block, the same hash) is shaded, every sample in a bucket
 *   above the threshold bucket is shaded, the threshold bucket's with probability p, none
 *   below. It asserts
 *   * no sample outside that rule is shaded and every certain one is (exact);
 *   * the count is within 4 binomial sigmas of its expectation (+1);
 *   * |count - rate x pixels| <= 4 sqrt(pixels p (1 - p)) + the base-rate shadings (both eyes);
 *   * low c_s is preferred: the mean pre-shading c_s of the shaded samples is below the mean of
 *     all candidates (rates < 100 %), and samples with c_s = 0 are shaded at least as often as
 *     those with the highest c_s.
 * - test_variance_rate: the same with variance-guided importance (adaptive-variance, rates 25 %
 *   and 50 %): w = xs_sc_variance_importance(v, c_s), v the pixel's relative variance from its
 *   candidates' pre-shading records (xs_sc_pixel_variance); exact rule, count, and the shaded
 *   samples' mean importance above all candidates'. Also: plan.w holds each pixel's candidates'
 *   bucket range (XS_SC_PLAN_RANGE_*, exact), and some pixels are decided by it alone (the
 *   selection's shortcut is used; the exact rule above checks its choices).
 * - test_convergence: scenes/cornell.gltf, 2 x 48 x 48, defaults, a still view, public API:
 *   relMSE (xrsc_metrics_error) of the colour against an `spp` reference of T_REF_SPP samples
 *   per pixel falls: relMSE(frame 32) < 0.5 relMSE(frame 4), and relMSE(frame 32) <
 *   T_FINAL_RELMSE (both eyes).
 * - test_bytes_per_pixel: prints the cache's bytes per pixel per eye (defaults; 2-pass with
 *   adaptive shading); asserts that the resident part matches the layout of
 *   xs_samplecache.h and that the defaults' total is at most 400 B (issue 19).
 */
#include "test_samplecache_util.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>

/* ---- adaptive shading: C twin of sc_shade_select.comp ---- */

#define T_W 32u
#define T_H 32u
#define T_FRAMES 10u
#define T_SIGMAS 4.0

static uint32_t pcg_permute(uint32_t state)
{
    uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
static uint32_t xs_hash_c(uint32_t v)
{
    return pcg_permute(v * 747796405u + 2891336453u);
}

/** sc_round_robin: the first set bit at or after start, cyclically over n slots. */
static int round_robin(uint32_t bits, uint32_t start, uint32_t n)
{
    if (bits == 0u)
        return -1;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t s = (start + i) % n;
        if (bits >> s & 1u)
            return (int)s;
    }
    return -1;
}

static float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, 4);
    return f;
}

typedef struct t_shade_stats {
    double expected, variance, observed;
    uint32_t impossible, missed_certain, base;
    double c_sum_shaded, c_sum_all;
    uint32_t n_shaded, n_all;
    uint32_t c0_all, c0_shaded, chi_all, chi_shaded; /* c = 0 and c >= the highest seen */
    double v_sum_all, v_shaded; /* sums of the importance of all candidates, of shaded ones */
    /* variance-guided: pixels whose plan.w bucket range differs from the candidates', and
     * pixels that range decides without coins (all buckets above or below k) */
    uint32_t range_bad, range_decided;
} t_shade_stats;

/** Pre-shading L_s, c_s of a sample: the previous frame's record of the same first hit, else
 *  0 (a new sample). */
static void prev_record(const mt_sc_snapshot *prev, const uint32_t fh[4], uint32_t pix,
                        float out[4])
{
    memset(out, 0, 16);
    uint32_t w = prev->width, h = prev->height;
    int x0 = (int)(pix % w), y0 = (int)(pix / w);
    /* a still view: the sample was in this pixel or (at a border) a neighbour */
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            int x = x0 + dx, y = y0 + dy;
            if (x < 0 || y < 0 || x >= (int)w || y >= (int)h)
                continue;
            uint32_t p = (uint32_t)y * w + (uint32_t)x;
            for (uint32_t s = 0; s < prev->slots; s++)
                if ((tsc_occ(prev, p) >> s & 1u) && !memcmp(tsc_fh(prev, s, p), fh, 16)) {
                    memcpy(out, tsc_rad(prev, s, p), 16);
                    return;
                }
        }
}

/** sc_pixel_variance: the pixel's relative variance from its candidates' pre-shading records
 *  (in slot order, as the shader sums them). */
static float pixel_variance(const float rec[][4], uint32_t cand, uint32_t n)
{
    float k = 0.0f, sc = 0.0f, scl = 0.0f, scl2 = 0.0f;
    for (uint32_t s = 0; s < n; s++) {
        if (!(cand >> s & 1u) || !(rec[s][3] > 0.0f))
            continue;
        float l = rec[s][0] * 0.2126f + rec[s][1] * 0.7152f + rec[s][2] * 0.0722f;
        k += 1.0f;
        sc += rec[s][3];
        scl += rec[s][3] * l;
        scl2 += rec[s][3] * l * l;
    }
    return xs_sc_pixel_variance(k, sc, scl, scl2);
}

/** Variance-guided shading: plan.w holds the candidates' bucket range (XS_SC_PLAN_RANGE_*,
 *  from sc_shade_importance.comp), which sc_shade_select.comp uses to decide a pixel without
 *  its coins when the whole range lies above or below threshold bucket k. */
static void check_range(uint32_t range, uint32_t cand, int lo, int hi, int k, t_shade_stats *st)
{
    uint32_t want =
        cand ? XS_SC_PLAN_RANGE_SET | (uint32_t)lo | (uint32_t)hi << XS_SC_PLAN_RANGE_HI_SHIFT : 0u;
    st->range_bad += range != want;
    st->range_decided += cand != 0u && (lo > k || hi < k);
}

static void check_selection(const mt_sc_snapshot *prev, const mt_sc_snapshot *cur, uint32_t eye,
                            uint32_t frame_index, const xrsc_samplecache_options *o, float c_high,
                            t_shade_stats *st)
{
    uint32_t w = cur->width, h = cur->height, n = cur->slots, b = o->block;
    /* the previous frame's bounds (sc_prev_bounds) */
    float w_min = bits_float(~prev->stats.w_min_inv), w_max = bits_float(prev->stats.w_max);
    bool bounded = prev->stats.w_min_inv != 0u && prev->stats.w_max != 0u;
    /* the threshold bucket k and probability p of this frame's histogram */
    uint32_t base_count = ((w + b - 1) / b) * ((h + b - 1) / b);
    float budget = o->shade_rate * (float)(w * h) - (float)base_count;
    budget = budget > 0.0f ? budget : 0.0f;
    int k = -1;
    float p = 1.0f, above = 0.0f;
    for (int j = (int)XS_SC_BUCKETS - 1; j >= 0; j--) {
        float hj = (float)cur->stats.hist[j];
        if (above + hj >= budget) {
            k = j;
            p = hj > 0.0f ? (budget - above) / hj : 0.0f;
            break;
        }
        above += hj;
    }
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            uint32_t pix = y * w + x;
            uint32_t cand = 0;
            for (uint32_t s = 0; s < n; s++)
                if ((tsc_occ(cur, pix) & tsc_vis(cur, pix)) >> s & 1u &&
                    tsc_fh(cur, s, pix)[3] != XS_SC_BACKGROUND)
                    cand |= 1u << s;
            uint32_t shaded = cur->plan[pix * 4 + 2];
            if (shaded & ~cand)
                st->impossible += tsc_popcount(shaded & ~cand);
            int rr = round_robin(cand, (frame_index + 1u) % n, n);
            uint32_t local = (x % b) + (y % b) * b;
            uint32_t pick =
                (frame_index + xs_hash_c(xs_hash_c(x / b + eye + 1u) + y / b)) % (b * b);
            uint32_t base_bit = (local == pick && rr >= 0) ? 1u << rr : 0u;
            st->base += base_bit != 0u;
            /* the samples' pre-shading records: previous frame's, found by first hit */
            float rec[XS_SC_MAX_SLOTS][4];
            for (uint32_t s = 0; s < n; s++)
                if (cand >> s & 1u)
                    prev_record(prev, tsc_fh(cur, s, pix), pix, rec[s]);
            bool by_variance = o->shade == XRSC_SC_SHADE_ADAPTIVE_VARIANCE;
            float v = by_variance ? pixel_variance(rec, cand, n) : 0.0f;
            int lo = (int)XS_SC_BUCKETS, hi = -1; /* the candidates' bucket range */
            for (uint32_t s = 0; s < n; s++) {
                if (!(cand >> s & 1u))
                    continue;
                float c = rec[s][3];
                float wi = by_variance ? xs_sc_variance_importance(v, c) : xs_sc_importance(c);
                st->v_sum_all += wi;
                st->v_shaded += (shaded >> s & 1u) ? wi : 0.0;
                int bucket = bounded ? (int)xs_sc_bucket(wi, w_min, w_max) : (int)XS_SC_BUCKETS - 1;
                lo = bucket < lo ? bucket : lo;
                hi = bucket > hi ? bucket : hi;
                double prob = (base_bit >> s & 1u) ? 1.0 : bucket > k ? 1.0 : bucket == k ? p : 0.0;
                bool sh = shaded >> s & 1u;
                st->expected += prob;
                st->variance += prob * (1.0 - prob);
                st->observed += sh;
                if (sh && prob == 0.0)
                    st->impossible++;
                if (!sh && prob == 1.0)
                    st->missed_certain++;
                st->c_sum_all += c;
                st->n_all++;
                if (sh) {
                    st->c_sum_shaded += c;
                    st->n_shaded++;
                }
                if (c == 0.0f) {
                    st->c0_all++;
                    st->c0_shaded += sh;
                }
                if (c >= c_high) {
                    st->chi_all++;
                    st->chi_shaded += sh;
                }
            }
            if (by_variance)
                check_range(cur->plan[pix * 4 + 3], cand, lo, hi, k, st);
        }
}

static void run_rate(float rate, xrsc_sc_shade mode)
{
    xrsc_samplecache_options o = {.shade = mode, .shade_rate = rate};
    tsc_rig rig;
    if (!tsc_open(&rig, t_source_path("scenes/cornell.gltf"), T_W, T_H, &o)) {
        tsc_close(&rig);
        return;
    }
    const xrsc_samplecache_options *opt = mt_samplecache_options(rig.m);
    xrsc_frame f = tsc_headset_frame(tsc_viewpoint(rig.cpu), 0);
    mt_sc_snapshot prev[2] = {0}, cur[2] = {0};
    t_shade_stats total = {0};
    uint32_t bad_frames = 0, rate_bad = 0;
    double px = 2.0 * T_W * T_H;
    for (uint32_t k = 0; k < T_FRAMES; k++) {
        f.frame_index = k;
        if (!tsc_render(rig.m, &f))
            break;
        for (uint32_t e = 0; e < 2; e++)
            if (!tsc_snapshot(rig.m, e, &cur[e]))
                goto done;
        if (k >= 2) {
            /* the highest pre-shading c_s of this frame (the previous frame's maximum) */
            float c_high = 0.0f;
            for (uint32_t e = 0; e < 2; e++)
                for (uint32_t p = 0; p < T_W * T_H; p++)
                    for (uint32_t s = 0; s < prev[e].slots; s++)
                        if (tsc_occ(&prev[e], p) >> s & 1u)
                            c_high = fmaxf(c_high, tsc_rad(&prev[e], s, p)[3]);
            t_shade_stats st = {0};
            for (uint32_t e = 0; e < 2; e++)
                check_selection(&prev[e], &cur[e], e, k, opt, c_high, &st);
            /* the shade list agrees with the per-pixel choice */
            CHECK_EQ_INT(cur[1].shade_count, (uint32_t)st.observed);
            double tol = T_SIGMAS * sqrt(st.variance) + 1.0;
            if (fabs(st.observed - st.expected) > tol) {
                fprintf(stderr, "  rate %.2f frame %u: %g shaded, expected %.1f +- %.1f\n", rate, k,
                        st.observed, st.expected, tol);
                bad_frames++;
            }
            /* against the nominal rate: binomial spread + the base-rate shadings */
            double nominal = rate * px;
            double rate_tol = T_SIGMAS * sqrt(px * fmin(rate, 1.0) * (1.0 - fmin(rate, 1.0))) +
                              2.0 * (T_W / opt->block) * (T_H / opt->block);
            if (fabs(st.observed - nominal) > rate_tol) {
                fprintf(stderr, "  rate %.2f frame %u: %g shaded, nominal %.0f +- %.1f\n", rate, k,
                        st.observed, nominal, rate_tol);
                rate_bad++;
            }
            total.expected += st.expected;
            total.observed += st.observed;
            total.variance += st.variance;
            total.impossible += st.impossible;
            total.missed_certain += st.missed_certain;
            total.base += st.base;
            total.c_sum_all += st.c_sum_all;
            total.c_sum_shaded += st.c_sum_shaded;
            total.n_all += st.n_all;
            total.n_shaded += st.n_shaded;
            total.c0_all += st.c0_all;
            total.c0_shaded += st.c0_shaded;
            total.chi_all += st.chi_all;
            total.chi_shaded += st.chi_shaded;
            total.v_sum_all += st.v_sum_all;
            total.v_shaded += st.v_shaded;
            total.range_bad += st.range_bad;
            total.range_decided += st.range_decided;
        }
        for (uint32_t e = 0; e < 2; e++) {
            mt_sc_snapshot_free(&prev[e]);
            prev[e] = cur[e];
            memset(&cur[e], 0, sizeof(cur[e]));
        }
    }
    uint32_t frames = T_FRAMES - 2;
    double mean_shaded = total.n_shaded ? total.c_sum_shaded / total.n_shaded : 0.0;
    double mean_all = total.n_all ? total.c_sum_all / total.n_all : 0.0;
    double p0 = total.c0_all ? (double)total.c0_shaded / total.c0_all : 0.0;
    double phi = total.chi_all ? (double)total.chi_shaded / total.chi_all : 0.0;
    double w_shaded = total.n_shaded ? total.v_shaded / total.n_shaded : 0.0;
    double w_all = total.n_all ? total.v_sum_all / total.n_all : 0.0;
    printf("  %s rate %3.0f %%: %.1f shaded per frame (nominal %.0f, expected %.1f, sigma %.1f), "
           "%.1f base-rate; mean c_s shaded %.2f vs all %.2f; P(shade | c=0) %.2f, "
           "P(shade | c max) %.2f; mean importance shaded %.4g vs all %.4g\n",
           mode == XRSC_SC_SHADE_ADAPTIVE ? "adaptive" : "adaptive-variance", rate * 100.0,
           total.observed / frames, rate * px, total.expected / frames,
           sqrt(total.variance / frames), (double)total.base / frames, mean_shaded, mean_all, p0,
           phi, w_shaded, w_all);
    CHECK_EQ_INT(total.impossible, 0);
    CHECK_EQ_INT(total.missed_certain, 0);
    if (mode == XRSC_SC_SHADE_ADAPTIVE_VARIANCE) { /* the range shortcut is exact and used */
        printf("  adaptive-variance rate %3.0f %%: %.1f of %.0f pixels decided by their bucket "
               "range per frame\n",
               rate * 100.0, (double)total.range_decided / frames, px);
        CHECK_EQ_INT(total.range_bad, 0);
        CHECK(total.range_decided > 0);
    }
    CHECK_EQ_INT(bad_frames, 0);
    CHECK_EQ_INT(rate_bad, 0);
    CHECK(total.n_shaded > 0);
    if (rate < 1.0f) {
        CHECK_MSG(w_shaded > w_all, "mean importance of shaded %.4g <= of all %.4g", w_shaded,
                  w_all);
        if (mode == XRSC_SC_SHADE_ADAPTIVE)
            CHECK_MSG(mean_shaded < mean_all, "mean c_s of shaded %.3f >= of all %.3f",
                      mean_shaded, mean_all);
    }
    if (mode == XRSC_SC_SHADE_ADAPTIVE)
        CHECK_MSG(p0 >= phi, "P(shade | c=0) %.3f < P(shade | c max) %.3f", p0, phi);
done:
    for (uint32_t e = 0; e < 2; e++) {
        mt_sc_snapshot_free(&prev[e]);
        mt_sc_snapshot_free(&cur[e]);
    }
    tsc_close(&rig);
}

static void test_adaptive_rate(void)
{
    run_rate(0.25f, XRSC_SC_SHADE_ADAPTIVE);
    run_rate(0.5f, XRSC_SC_SHADE_ADAPTIVE);
    run_rate(1.0f, XRSC_SC_SHADE_ADAPTIVE);
}

/* Variance-guided importance (issue 12): the same C twin with w = v / (1 + c_s), v from the
 * pixel's pre-shading records (sc_pixel_variance): the choice follows the rule exactly, the
 * count the rate, and the shaded samples have the higher importance. */
static void test_variance_rate(void)
{
    run_rate(0.25f, XRSC_SC_SHADE_ADAPTIVE_VARIANCE);
    run_rate(0.5f, XRSC_SC_SHADE_ADAPTIVE_VARIANCE);
}

/* ---- convergence to the path-traced reference ---- */

#define T_CONV_W 48u
#define T_CONV_FRAMES 32u
#define T_REF_SPP 256u
#define T_REF_FRAMES 1u /* issue 22: 256 samples per pixel (was 4 x 256; tests/times.md) */
#define T_FINAL_RELMSE 0.06

static void test_convergence(void)
{
    static const uint32_t at[] = {1, 2, 4, 8, 16, 32};
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SAMPLECACHE, .seed = 7};
    double rel[T_CONV_FRAMES + 1] = {0};
    tsc_convergence(&ro, T_CONV_W, T_CONV_FRAMES, at, 6, T_REF_SPP, T_REF_FRAMES, rel);
    CHECK_MSG(rel[32] < 0.5 * rel[4], "relMSE at frame 32 %.4f vs at frame 4 %.4f", rel[32],
              rel[4]);
    CHECK_MSG(rel[32] < T_FINAL_RELMSE, "final relMSE %.4f", rel[32]);
    CHECK(rel[8] < rel[4] && rel[16] < rel[8]);
}

/* ---- memory ---- */

static void bytes_for(const char *label, const xrsc_samplecache_options *o)
{
    tsc_rig rig;
    if (!tsc_open(&rig, t_source_path("scenes/cornell.gltf"), 64, 64, o)) {
        tsc_close(&rig);
        return;
    }
    double resident, working;
    mt_samplecache_bytes_per_pixel(rig.m, &resident, &working);
    uint32_t n = mt_samplecache_options(rig.m)->slots;
    printf("  %s: %.0f B/pixel/eye resident (N = %u) + %.1f B working = %.1f B/pixel/eye "
           "(%.2f MiB per eye at 2064 x 2208)\n",
           label, resident, n, working, resident + working,
           (resident + working) * 2064.0 * 2208.0 / 1048576.0);
    /* two copies of mask 4 B + a 4-byte pool address per slot; one pool of K entries of fh
     * 16 B + rad XS_SC_RAD_BYTES (four halves), and its 4-byte word of taken entries */
    double k = ceil(XS_SC_POOL_PER_TARGET * mt_samplecache_options(rig.m)->n_target);
    k = fmin(fmax(k, XS_SC_POOL_MIN_PER_PX), n);
    CHECK_NEAR(resident, 2.0 * (4.0 + 4.0 * n) + k * (16.0 + XS_SC_RAD_BYTES) + 4.0, 0.0);
    /* issue 19: the defaults fit in 400 B per pixel per eye */
    if (o->slots == 0 && o->reproject != XRSC_SC_REPROJECT_2PASS)
        CHECK_MSG(resident + working <= 400.0, "%.1f B/pixel/eye", resident + working);
    tsc_close(&rig);
}

static void test_bytes_per_pixel(void)
{
    xrsc_samplecache_options d = {0};
    bytes_for("defaults", &d);
    xrsc_samplecache_options a = {.reproject = XRSC_SC_REPROJECT_2PASS,
                                  .shade = XRSC_SC_SHADE_ADAPTIVE};
    bytes_for("2-pass, adaptive shading", &a);
}

int main(void)
{
    RUN(test_adaptive_rate);
    RUN(test_variance_rate);
    RUN(test_convergence);
    RUN(test_bytes_per_pixel);
    return t_finish();
}
