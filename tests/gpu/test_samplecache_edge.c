// SPDX-License-Identifier: MIT
/**
 * @file test_samplecache_edge.c
 * @brief The edge test of the sample cache, Eq. 2 with the slope Delta of Eq. 1 (seed 000
 *        §3.4, App. A), on synthetic neighbourhoods (device and C builds of xs_sc_math.h) and
 *        in the trace mask (sc_copy.comp, pass "reproject").
 *
 * - test_synthetic_neighbourhoods: 3 x 3 pixels of the default headset's left eye (2064 x 2208,
 *   phi = the pixel diagonal's angle, as mt_samplecache.c computes it), T_SPP samples at
 *   random positions in each pixel, ray distances to a plane computed in double. t_min, t_max
 *   and the closest sample's cos(theta) go through sc_selftest.comp (device) and through the C
 *   build; both must decide the same, and:
 *   * a plane facing the centre ray (0 degrees) is never marked;
 *   * a plane tilted 70 degrees from the centre ray (any tilt direction) is never marked;
 *   * a depth step (a 1 % and a 5 % farther second plane over the right column) is always
 *     marked;
 *   at the image centre and near a corner, T_TRIALS random neighbourhoods each. Other tilts
 *   are printed (not asserted).
 * - test_trace_mask_step: a quad in front of a plane (written by the test), 2 x 32 x 32, still
 *   view: the pass's decision in every pixel equals the C build of Eq. 2 over that frame's
 *   depth words (snapshot): marked pixels retrace every sample, the others at most one (base
 *   rate); every pixel whose 3 x 3 neighbourhood holds samples of both surfaces is marked.
 */
#include "test_samplecache_util.h"

#define T_TRIALS 64u
#define T_SPP 4u

static uint32_t rng_state = 987654321u;
static double rnd(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (double)((rng_state ^ (rng_state >> 16)) >> 8) * (1.0 / 16777216.0);
}

/** mt_samplecache.c's phi: angle subtended by the diagonal of the centre pixel. */
static double pixel_phi(const XrFovf *fov, uint32_t w, uint32_t h)
{
    double dx = (tan(fov->angleRight) - tan(fov->angleLeft)) / w;
    double dy = (tan(fov->angleUp) - tan(fov->angleDown)) / h;
    return atan(sqrt(dx * dx + dy * dy));
}

static void normalize(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l, v[1] /= l, v[2] /= l;
}

/** Eye-space unit direction through image position (x, y) (pixels), xs_camera_ray's. */
static void ray_dir(const XrFovf *fov, uint32_t w, uint32_t h, double x, double y, double d[3])
{
    double tl = tan(fov->angleLeft), tr = tan(fov->angleRight);
    double tu = tan(fov->angleUp), td = tan(fov->angleDown);
    d[0] = tl + (tr - tl) * x / w;
    d[1] = tu + (td - tu) * y / h;
    d[2] = -1.0;
    normalize(d);
}

/**
 * One synthetic neighbourhood: 3 x 3 pixels around (cx, cy), a plane through the point 2 m
 * along the centre pixel's ray whose normal is tilted `tilt` rad from that ray towards
 * azimuth `az`; samples of column +1 are pushed `step` times farther (1 = no step). Fills
 * the Eq. 1 / Eq. 2 inputs of io.
 */
static void neighbourhood(const XrFovf *fov, uint32_t w, uint32_t h, uint32_t cx, uint32_t cy,
                          double tilt, double az, double step, double phi, xs_sc_selftest_io *io)
{
    double r[3];
    ray_dir(fov, w, h, cx + 0.5, cy + 0.5, r);
    /* basis around r */
    double a[3] = {0, 1, 0};
    double u[3] = {r[1] * a[2] - r[2] * a[1], r[2] * a[0] - r[0] * a[2], r[0] * a[1] - r[1] * a[0]};
    normalize(u);
    double v[3] = {r[1] * u[2] - r[2] * u[1], r[2] * u[0] - r[0] * u[2], r[0] * u[1] - r[1] * u[0]};
    double n[3], p0[3];
    for (int i = 0; i < 3; i++) {
        n[i] = -cos(tilt) * r[i] + sin(tilt) * (cos(az) * u[i] + sin(az) * v[i]);
        p0[i] = 2.0 * r[i];
    }
    double tmin = INFINITY, tmax = 0.0, cos_min = 1.0;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++)
            for (uint32_t k = 0; k < T_SPP; k++) {
                double d[3];
                ray_dir(fov, w, h, cx + i + rnd(), cy + j + rnd(), d);
                double dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                double t = (p0[0] * n[0] + p0[1] * n[1] + p0[2] * n[2]) / dn;
                if (i == 1)
                    t *= step;
                if (t < tmin) {
                    tmin = t;
                    cos_min = fabs(dn);
                }
                tmax = fmax(tmax, t);
            }
    memset(io, 0, sizeof(*io));
    io->t = (float)tmin;
    io->cos_theta = (float)cos_min;
    io->phi = (float)phi;
    io->t_min = (float)tmin;
    io->t_max = (float)tmax;
    io->eps1 = (float)XS_SC_DEFAULT_EPS1;
}

typedef struct t_case {
    const char *name;
    double tilt_deg, step;
    int expect; /* 1 consistent (not marked), 0 marked, -1 report only */
} t_case;

static void test_synthetic_neighbourhoods(void)
{
    static const t_case cases[] = {
        {"plane at 0 deg", 0.0, 1.0, 1},
        {"plane at 70 deg", 70.0, 1.0, 1},
        {"depth step 1 %", 0.0, 1.01, 0},
        {"depth step 5 %", 0.0, 1.05, 0},
        {"depth step 1 % at 70 deg", 70.0, 1.01, -1},
        {"plane at 45 deg", 45.0, 1.0, -1},
        {"plane at 60 deg", 60.0, 1.0, -1},
        {"plane at 75 deg", 75.0, 1.0, -1},
        {"plane at 80 deg", 80.0, 1.0, -1},
        {"plane at 85 deg", 85.0, 1.0, -1},
    };
    const uint32_t n_cases = sizeof(cases) / sizeof(cases[0]);
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    const XrFovf *fov = &hs.fov[0];
    uint32_t w = hs.width_px, h = hs.height_px;
    double phi = pixel_phi(fov, w, h);
    const uint32_t centres[2][2] = {{w / 2, h / 2}, {40, 40}};
    uint32_t count = n_cases * 2 * T_TRIALS;
    xs_sc_selftest_io *io = calloc(count, sizeof(*io));
    for (uint32_t c = 0; c < n_cases; c++)
        for (uint32_t at = 0; at < 2; at++)
            for (uint32_t k = 0; k < T_TRIALS; k++)
                neighbourhood(fov, w, h, centres[at][0], centres[at][1],
                              cases[c].tilt_deg * TSC_PI / 180.0, 2.0 * TSC_PI * rnd(),
                              cases[c].step, phi, &io[(c * 2 + at) * T_TRIALS + k]);

    gpu_context_options go = {.validation = true};
    gpu_context *gpu = NULL;
    xrsc_diag diag = {0};
    xrsc_result res = gpu_context_create(&go, &gpu, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res == XRSC_OK)
        CHECK(gpu->validation);
    if (res == XRSC_OK)
        res = mt_sc_selftest_run(gpu, io, count, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK) {
        tsc_print_diag(&diag);
        goto done;
    }
    printf("  default headset, left eye %ux%u, phi = %.3g rad, eps1 = %g, %u samples per pixel\n",
           w, h, phi, XS_SC_DEFAULT_EPS1, T_SPP);
    for (uint32_t c = 0; c < n_cases; c++)
        for (uint32_t at = 0; at < 2; at++) {
            uint32_t marked = 0, disagree = 0;
            for (uint32_t k = 0; k < T_TRIALS; k++) {
                const xs_sc_selftest_io *r = &io[(c * 2 + at) * T_TRIALS + k];
                float delta = xs_sc_slope(r->t, r->cos_theta, r->phi);
                bool c_ok = xs_sc_consistent(r->t_min, r->t_max, delta, r->eps1);
                disagree += (uint32_t)c_ok != r->out_consistent;
                marked += r->out_consistent == 0u;
            }
            printf("    %-26s %-6s: marked %3u of %u (device and C disagree: %u)\n", cases[c].name,
                   at == 0 ? "centre" : "corner", marked, T_TRIALS, disagree);
            CHECK_EQ_INT(disagree, 0);
            if (cases[c].expect == 1)
                CHECK_MSG(marked == 0, "%s (%s) marked %u times", cases[c].name,
                          at == 0 ? "centre" : "corner", marked);
            else if (cases[c].expect == 0)
                CHECK_MSG(marked == T_TRIALS, "%s (%s) missed %u times", cases[c].name,
                          at == 0 ? "centre" : "corner", T_TRIALS - marked);
        }
done:
    free(io);
    if (gpu) {
        CHECK_EQ_INT(gpu->validation_errors, 0);
        gpu_context_destroy(&gpu);
    }
}

/* ---- the pass ---- */

#define T_W 32u
#define T_FRAMES 4u

static void test_trace_mask_step(void)
{
    /* plane at z = 0, a quad at z = 0.4 covering x < 0 (the left half of the view) */
    tsc_quad quads[2] = {
        {.half = 2.0f, .color = {0.5f, 0.5f, 0.5f}},
        {.half = 1.0f, .pos = {-1.0f, 0.0f, 0.4f}, .color = {0.2f, 0.6f, 0.2f}},
    };
    const char *path = tsc_quads_gltf("sc_step.gltf", quads, 2, 0.0, 1.0f);
    xrsc_samplecache_options o = {0};
    tsc_rig rig;
    if (!tsc_open(&rig, path, T_W, T_W, &o)) {
        tsc_close(&rig);
        return;
    }
    const xrsc_samplecache_options *opt = mt_samplecache_options(rig.m);
    xrsc_frame f = {0};
    for (int e = 0; e < 2; e++) {
        f.views[e].pose.orientation.w = 1.0f;
        f.views[e].pose.position.x = e == 0 ? -0.1f : 0.1f;
        f.views[e].pose.position.z = 2.0f;
        float a = (float)atan(0.5);
        f.views[e].fov = (XrFovf){-a, a, a, -a};
    }
    uint32_t bad = 0, marked = 0, straddle = 0, straddle_missed = 0, unmarked = 0;
    for (uint32_t k = 0; k < T_FRAMES; k++) {
        f.frame_index = k;
        if (!tsc_render(rig.m, &f))
            break;
        if (k == 0)
            continue; /* frame 0 has no reprojected samples (no depth words) */
        for (uint32_t e = 0; e < 2; e++) {
            mt_sc_snapshot sn;
            if (!tsc_snapshot(rig.m, e, &sn))
                continue;
            for (uint32_t y = 0; y < T_W; y++)
                for (uint32_t x = 0; x < T_W; x++) {
                    /* Eq. 2 in C over the pass's own inputs */
                    uint64_t dmin = UINT64_MAX;
                    uint32_t dmax = 0;
                    bool front = false, back = false;
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int xx = (int)x + dx, yy = (int)y + dy;
                            if (xx < 0 || yy < 0 || xx >= (int)T_W || yy >= (int)T_W)
                                continue;
                            uint32_t q = (uint32_t)yy * T_W + (uint32_t)xx;
                            dmin = sn.depth_min[q] < dmin ? sn.depth_min[q] : dmin;
                            dmax = sn.depth_max[q] > dmax ? sn.depth_max[q] : dmax;
                            for (uint32_t s = 0; s < sn.slots; s++)
                                if (tsc_vis(&sn, q) >> s & 1u) {
                                    uint32_t inst = tsc_fh(&sn, s, q)[3];
                                    front |= inst == 1u;
                                    back |= inst == 0u;
                                }
                        }
                    bool consistent = true;
                    if (dmin != UINT64_MAX) {
                        uint32_t hi = (uint32_t)(dmin >> 32), lo = (uint32_t)dmin;
                        float t_min, delta, t_max;
                        memcpy(&t_min, &hi, 4);
                        memcpy(&delta, &lo, 4);
                        memcpy(&t_max, &dmax, 4);
                        consistent = xs_sc_consistent(t_min, t_max, delta, opt->eps1);
                    }
                    uint32_t p = y * T_W + x;
                    uint32_t traced = sn.plan[p * 4], fresh = sn.plan[p * 4 + 1];
                    uint32_t all = tsc_occ(&sn, p) & ~fresh;
                    bool ok = consistent ? tsc_popcount(traced) <= 1u : traced == all;
                    if (!ok) {
                        if (bad < 5)
                            fprintf(stderr,
                                    "  frame %u eye %u (%u,%u): C says %s, traced %x of %x\n", k, e,
                                    x, y, consistent ? "flat" : "edge", traced, all);
                        bad++;
                    }
                    marked += !consistent;
                    unmarked += consistent;
                    if (front && back) {
                        straddle++;
                        straddle_missed += consistent;
                    }
                }
            mt_sc_snapshot_free(&sn);
        }
    }
    printf("  step 0.4 m at 1.6 m: %u pixel-frames marked, %u not; %u straddle both surfaces, %u "
           "of those missed; %u disagree with C\n",
           marked, unmarked, straddle, straddle_missed, bad);
    CHECK_EQ_INT(bad, 0);
    CHECK(straddle >= 2u * (T_FRAMES - 1) * T_W); /* a column pair per eye and frame at least */
    CHECK_EQ_INT(straddle_missed, 0);
    tsc_close(&rig);
}

int main(void)
{
    RUN(test_synthetic_neighbourhoods);
    RUN(test_trace_mask_step);
    return t_finish();
}
