// SPDX-License-Identifier: MIT
/**
 * @file test_hashcache.c
 * @brief `hashcache` and `hybrid` (seed 000 §4) under the validation layer: the white furnace
 *        converges to rho L, a tiny table (forced collisions and evictions) stays within what
 *        was written and counts its evictions, hybrid's visibility equals the sample cache's
 *        for the same seed, and hybrid on the furnace converges to rho L too.
 */
#include "mt_hashcache.h"
#include "mt_hctable.h"
#include "xs_hashcache.h"
#include "test_samplecache_util.h"

/* The white furnace (scenes/furnace.gltf): a convex diffuse sphere of albedo 0.5 under a
 * constant environment of 1, so a path from the sphere returns 0.5 (demodulated: 1) and the
 * background is 1. Rarely a path returns 0 instead: on the tessellated sphere a bounce
 * direction sampled around the shading normal can fall below the geometric one, which ends
 * the path (xs_side_ok), so a voxel mean can lie below 0.5, never above. The checks: every
 * sphere pixel finite and within [0, 0.5], at least T_EXACT_SHARE of them within
 * T_FURNACE_TOL of 0.5, their mean within T_MEAN_TOL of 0.5, the background exactly 1. Any
 * value the cache returned that was not written for the furnace (rad[]'s NaN fill, another
 * voxel's garbage) fails the first. */
#define T_FURNACE_RHO 0.5
#define T_FURNACE_TOL 1e-4
#define T_EXACT_SHARE 0.97
#define T_MEAN_TOL 0.01
#define T_SIZE 48u
#define T_FRAMES 6u
/* the sphere covers about 190 of the 48 x 48 pixels under the default headset FOV */
#define T_MIN_SPHERE_PIXELS 120u
/* 64 entries (4 tiles of 4 x 4): far fewer than the voxels in view, so inserts collide, probe
 * to the limit, fail, and (max_age 1) overwrite entries not touched in the last frame */
#define T_TINY_TABLE 64u
#define T_TINY_MAX_AGE 1u
#define T_TINY_FRAMES 8u
/* Cornell box (lamp emission 15): colours must be finite and non-negative; single-path
 * estimates (pixels whose insert failed are shaded uncached) can exceed 15 near the lamp, so
 * the bound only catches garbage (rad[]'s NaN fill, bits of another type); the table self-test
 * checks values exactly */
#define T_CORNELL_MAX_RADIANCE 1e3
/* hybrid vs samplecache: frames compared */
#define T_VIS_FRAMES 4u

typedef struct t_rig {
    xrsc_context *ctx;
    xrsc_scene *scene;
    xrsc_renderer *r;
    xrsc_frame f;
} t_rig;

static bool t_open(t_rig *t, const char *scene, const xrsc_renderer_options *ro)
{
    memset(t, 0, sizeof(*t));
    xrsc_context_options co = {.validation = true};
    CHECK_EQ_INT(xrsc_context_create(&co, &t->ctx, NULL), XRSC_OK);
    if (!t->ctx)
        return false;
    CHECK_EQ_INT(xrsc_scene_load(t->ctx, t_source_path(scene), NULL, &t->scene, NULL), XRSC_OK);
    if (!t->scene)
        return false;
    xrsc_diag diag = {0};
    xrsc_result res = xrsc_renderer_create(t->ctx, t->scene, ro, &t->r, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK) {
        tsc_print_diag(&diag);
        return false;
    }
    xrsc_scene_info info;
    xrsc_scene_get_info(t->scene, &info);
    t->f = tsc_headset_frame(info.viewpoint, 0);
    return true;
}

static void t_close(t_rig *t)
{
    xrsc_renderer_destroy(&t->r);
    xrsc_scene_destroy(&t->scene);
    if (t->ctx)
        CHECK_EQ_INT(xrsc_context_validation_errors(t->ctx), 0);
    xrsc_context_destroy(&t->ctx);
}

/** The counter called name of the last frame (NAN when absent). */
static double t_counter(const xrsc_renderer *r, const char *name)
{
    xrsc_counter c[XRSC_MAX_COUNTERS];
    uint32_t n = xrsc_renderer_counters(r, c, XRSC_MAX_COUNTERS);
    for (uint32_t i = 0; i < n; i++)
        if (!strcmp(c[i].name, name))
            return c[i].value;
    return NAN;
}

/** Furnace check of both eyes: surface pixels (depth > 0) exactly rho, background 1. */
static void t_check_furnace(xrsc_renderer *r, const char *what)
{
    size_t n = (size_t)T_SIZE * T_SIZE;
    float *c = malloc(n * 16), *depth = malloc(n * 4);
    for (uint32_t e = 0; e < 2 && c && depth; e++) {
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, c, n * 16), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_DEPTH, depth, n * 4), XRSC_OK);
        uint32_t sphere = 0, exact = 0, background_ok = 0, background = 0, bad = 0;
        double worst = 0.0, sum = 0.0;
        for (size_t i = 0; i < n; i++) {
            double v = c[i * 4];
            if (depth[i] > 0.0f) {
                sphere++;
                double err = fabs(v - T_FURNACE_RHO);
                exact += err <= T_FURNACE_TOL;
                worst = err > worst || isnan(err) ? err : worst;
                bad += !(v >= 0.0 && v <= T_FURNACE_RHO + T_FURNACE_TOL);
                sum += v;
            } else {
                background++;
                background_ok += fabs(v - 1.0) <= T_FURNACE_TOL;
            }
        }
        double mean = sphere ? sum / sphere : 0.0;
        printf("  %s eye %u: %u sphere pixels, mean %.5f, %u within %.0e of 0.5 (worst %.3g); "
               "%u/%u background = 1\n",
               what, e, sphere, mean, exact, T_FURNACE_TOL, worst, background_ok, background);
        CHECK(sphere >= T_MIN_SPHERE_PIXELS);
        /* 1 spp first hits: a pixel is either sphere or background this frame, never mixed */
        CHECK_EQ_INT(bad, 0);
        CHECK(exact >= T_EXACT_SHARE * sphere);
        CHECK_NEAR(mean, T_FURNACE_RHO, T_MEAN_TOL);
        CHECK_EQ_INT(background_ok, background);
    }
    free(c);
    free(depth);
}

static void render_frames(t_rig *t, uint32_t count)
{
    for (uint32_t k = 0; k < count; k++) {
        t->f.frame_index = k;
        CHECK_EQ_INT(xrsc_renderer_render(t->r, &t->f), XRSC_OK);
    }
}

/* hashcache on the white furnace: rho L on every sphere pixel, with both LoD modes; the
 * distance-normal LoD uses coarser voxels towards the silhouette, so fewer entries */
static void test_furnace(void)
{
    double occupancy[2] = {0.0, 0.0};
    for (int mode = 0; mode < 2; mode++) {
        t_rig t;
        xrsc_renderer_options ro = {
            .method = XRSC_METHOD_HASHCACHE,
            .width = T_SIZE,
            .height = T_SIZE,
            .taa.mode = XRSC_TAA_OFF,
            .hashcache.lod = mode ? XRSC_HC_LOD_DISTANCE_NORMAL : XRSC_HC_LOD_DISTANCE,
        };
        if (t_open(&t, "scenes/furnace.gltf", &ro)) {
            render_frames(&t, T_FRAMES);
            t_check_furnace(t.r, mode ? "distance-normal" : "distance");
            double occ = t_counter(t.r, "hc_occupancy");
            double lookups = t_counter(t.r, "hc_lookups");
            double traced = t_counter(t.r, "hc_traced");
            printf("  occupancy %.3g, lookups %.0f, traced %.0f, probe mean %.3f max %.0f\n", occ,
                   lookups, traced, t_counter(t.r, "hc_probe_mean"),
                   t_counter(t.r, "hc_probe_max"));
            CHECK_NEAR(t_counter(t.r, "hc_table_bytes"), 24.0 * XS_HC_DEFAULT_TABLE_ENTRIES, 0);
            CHECK(occ > 0.0 && occ < 1.0);
            occupancy[mode] = occ;
            CHECK(lookups > 2.0 * T_MIN_SPHERE_PIXELS);
            /* one path per reserved voxel: nearby pixels share (seed 000 §5.1) */
            CHECK(traced > 0.0 && traced <= lookups);
            CHECK_EQ_INT(t_counter(t.r, "hc_failed_inserts"), 0);
        }
        t_close(&t);
    }
    CHECK(occupancy[1] < occupancy[0]);
}

/** Colours of both eyes finite and within [0, max_radiance]. */
static void t_check_bounded(xrsc_renderer *r, uint32_t size, double max_radiance)
{
    size_t n = (size_t)size * size;
    float *c = malloc(n * 16);
    uint32_t bad = 0;
    for (uint32_t e = 0; e < 2 && c; e++) {
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, c, n * 16), XRSC_OK);
        for (size_t i = 0; i < n * 4; i++)
            bad += !(c[i] >= 0.0f && c[i] <= max_radiance);
    }
    CHECK_EQ_INT(bad, 0);
    free(c);
}

/* A 64-entry table: collisions, failed inserts and evictions every frame; the furnace stays
 * within its bounds (every value read was written for the furnace: never rad[]'s NaN fill)
 * and the counters agree with each other. Then the Cornell box with the same table: finite,
 * non-negative colours (T_CORNELL_MAX_RADIANCE). */
static void test_tiny_table(void)
{
    static const char *const scenes[] = {"scenes/furnace.gltf", "scenes/cornell.gltf"};
    for (int sc = 0; sc < 2; sc++) {
        t_rig t;
        xrsc_renderer_options ro = {
            .method = XRSC_METHOD_HASHCACHE,
            .width = T_SIZE,
            .height = T_SIZE,
            .taa.mode = XRSC_TAA_OFF,
            .hashcache = {.table_entries = T_TINY_TABLE, .max_age = T_TINY_MAX_AGE},
        };
        if (!t_open(&t, scenes[sc], &ro)) {
            t_close(&t);
            continue;
        }
        double evictions = 0.0, inserts = 0.0, failed = 0.0;
        for (uint32_t k = 0; k < T_TINY_FRAMES; k++) {
            t.f.frame_index = k;
            CHECK_EQ_INT(xrsc_renderer_render(t.r, &t.f), XRSC_OK);
            double ev = t_counter(t.r, "hc_evictions"), in = t_counter(t.r, "hc_inserts");
            double fa = t_counter(t.r, "hc_failed_inserts");
            double lookups = t_counter(t.r, "hc_lookups");
            double occ = t_counter(t.r, "hc_occupancy");
            /* evictions are inserts into stale entries; at most one insert per entry and
             * frame; every lookup either found, inserted or failed */
            CHECK(ev <= in && in <= T_TINY_TABLE);
            CHECK(in + fa <= lookups);
            CHECK(occ >= 0.0 && occ <= 1.0);
            CHECK(t_counter(t.r, "hc_probe_max") <= XS_HC_MAX_PROBE);
            evictions += ev;
            inserts += in;
            failed += fa;
            if (sc == 0)
                t_check_furnace(t.r, "tiny table");
            else
                t_check_bounded(t.r, T_SIZE, T_CORNELL_MAX_RADIANCE);
        }
        printf("  %s, %u entries: %.0f inserts, %.0f evictions, %.0f failed in %u frames\n",
               scenes[sc], T_TINY_TABLE, inserts, evictions, failed, T_TINY_FRAMES);
        CHECK(evictions > 0.0);
        CHECK(failed > 0.0);
        CHECK_NEAR(t_counter(t.r, "hc_table_bytes"), 24.0 * T_TINY_TABLE, 0);
        t_close(&t);
    }
}

/* hybrid on the furnace: rho L on every pixel whose visible samples all hit the sphere */
static void test_hybrid_furnace(void)
{
    t_rig t;
    xrsc_renderer_options ro = {
        .method = XRSC_METHOD_HYBRID, .width = T_SIZE, .height = T_SIZE, .taa.mode = XRSC_TAA_OFF};
    if (t_open(&t, "scenes/furnace.gltf", &ro)) {
        render_frames(&t, T_FRAMES);
        size_t n = (size_t)T_SIZE * T_SIZE;
        float *c = malloc(n * 16);
        uint32_t exact = 0, background = 0, out_of_range = 0, below = 0;
        for (uint32_t e = 0; e < 2 && c; e++) {
            CHECK_EQ_INT(xrsc_renderer_read(t.r, e, XRSC_OUTPUT_COLOR, c, n * 16), XRSC_OK);
            for (size_t i = 0; i < n; i++) {
                double v = c[i * 4];
                exact += fabs(v - T_FURNACE_RHO) <= T_FURNACE_TOL;
                background += fabs(v - 1.0) <= T_FURNACE_TOL;
                /* silhouette pixels mix sphere and background samples: within [rho, 1]; below
                 * rho only where a voxel saw a path that ended early (see T_FURNACE_RHO) */
                out_of_range += !(v >= 0.0 && v <= 1.0 + T_FURNACE_TOL);
                below += v < T_FURNACE_RHO - T_FURNACE_TOL;
            }
        }
        printf("  hybrid: %u pixels exactly 0.5, %u background, %u below 0.5, %u out of "
               "[0, 1]\n",
               exact, background, below, out_of_range);
        CHECK(exact >= 2 * T_MIN_SPHERE_PIXELS);
        CHECK(below <= (1.0 - T_EXACT_SHARE) * exact);
        CHECK(background > 0);
        CHECK_EQ_INT(out_of_range, 0);
        CHECK(t_counter(t.r, "hc_traced") > 0.0);
        free(c);
    }
    t_close(&t);
}

/* hybrid's visibility (masks, first hits, depth and hit-id outputs) equals samplecache's for
 * the same seed, options and frames: the hash cache changes only the radiance */
static void test_hybrid_visibility(void)
{
    tsc_rig rig;
    xrsc_samplecache_options so = {0};
    if (!tsc_open(&rig, t_source_path("scenes/cornell.gltf"), T_SIZE, T_SIZE, &so)) {
        tsc_close(&rig);
        return;
    }
    mt_env env = {
        .gpu = rig.gpu, .scene = rig.gs, .cpu_scene = rig.cpu, .width = T_SIZE, .height = T_SIZE};
    mt_method *hy = NULL;
    xrsc_diag diag = {0};
    xrsc_result res = mt_hybrid_create(&env, &so, NULL, &hy, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    XrPosef head = tsc_viewpoint(rig.cpu);
    size_t n = (size_t)T_SIZE * T_SIZE;
    float *d0 = malloc(n * 4), *d1 = malloc(n * 4);
    uint32_t *h0 = malloc(n * 16), *h1 = malloc(n * 16);
    for (uint32_t k = 0; hy && k < T_VIS_FRAMES; k++) {
        /* a small head turn per frame: reprojection, retracing and density control all act */
        XrPosef p = head;
        p.orientation = tsc_quat_axis(0, 1, 0, 0.01 * k);
        xrsc_frame f = tsc_headset_frame(p, k);
        if (!tsc_render(rig.m, &f) || !tsc_render(hy, &f))
            break;
        for (uint32_t e = 0; e < 2; e++) {
            mt_sc_snapshot a, b;
            if (tsc_snapshot(rig.m, e, &a) && tsc_snapshot(mt_hybrid_samplecache(hy), e, &b)) {
                CHECK(!memcmp(a.mask, b.mask, n * 4));
                CHECK(!memcmp(a.fh, b.fh, n * a.slots * 16));
            }
            mt_sc_snapshot_free(&a);
            mt_sc_snapshot_free(&b);
            CHECK_EQ_INT(mt_method_read(rig.m, e, XRSC_OUTPUT_DEPTH, d0, n * 4, NULL), XRSC_OK);
            CHECK_EQ_INT(mt_method_read(hy, e, XRSC_OUTPUT_DEPTH, d1, n * 4, NULL), XRSC_OK);
            CHECK_EQ_INT(mt_method_read(rig.m, e, XRSC_OUTPUT_HIT_ID, h0, n * 16, NULL), XRSC_OK);
            CHECK_EQ_INT(mt_method_read(hy, e, XRSC_OUTPUT_HIT_ID, h1, n * 16, NULL), XRSC_OK);
            CHECK(!memcmp(d0, d1, n * 4));
            CHECK(!memcmp(h0, h1, n * 16));
        }
    }
    xrsc_counter c[XRSC_MAX_COUNTERS];
    CHECK(hy && mt_method_counters(hy, c, XRSC_MAX_COUNTERS) > 0);
    free(d0);
    free(d1);
    free(h0);
    free(h1);
    mt_method_destroy(&hy);
    tsc_close(&rig);
}

/* The table alone (hc_selftest.comp): 256 keys (pairs differing only in the normal's sign)
 * stored 64 per frame (batches overlapping by half), each twice, into a 64-entry table with
 * max_age 1; after each store frame a lookup frame reads that batch back (older keys age and
 * get evicted), and at the end every key is read: a value read is always the one stored for
 * that very key (never another key's, never rad[]'s NaN fill), one record per key reserves it,
 * and inserts, evictions and failures are counted consistently. */
#define T_ST_KEYS 256u
#define T_ST_BATCH 64u
#define T_ST_FRAMES 8u
#define T_ST_LOD (-4)

static xs_hc_selftest_io t_st_key(uint32_t j, uint32_t mode)
{
    xs_hc_selftest_io r = {0};
    r.cx = (j >> 1) % 8u; /* 8 x 16 voxels: 2 x 4 tiles of 4 x 4, all in-tile positions */
    r.cy = (j >> 1) / 8u;
    r.cz = (uint32_t)-2;
    r.lod = (uint32_t)T_ST_LOD;
    r.axis6 = 4u + (j & 1u); /* +z or -z: the same voxel seen from either side */
    r.mode = mode;
    r.value = (float)(j + 1);
    return r;
}

static void test_table_selftest(void)
{
    gpu_context *gpu = NULL;
    gpu_context_options go = {.validation = true};
    xrsc_diag diag = {0};
    CHECK_EQ_INT(gpu_context_create(&go, &gpu, &diag), XRSC_OK);
    if (!gpu)
        return;
    mt_hctable t;
    xrsc_hashcache_options o = {.table_entries = T_TINY_TABLE, .max_age = T_TINY_MAX_AGE};
    CHECK_EQ_INT(mt_hctable_init(&t, gpu, &o, &diag), XRSC_OK);
    xrsc_frame f = {0};
    xs_hc_selftest_io st[2 * T_ST_BATCH], lk[T_ST_KEYS];
    double evictions = 0.0, failed = 0.0;
    uint32_t wrong = 0, double_reserved = 0, read_ok = 0;
    for (uint32_t fr = 0; t.gpu && fr < T_ST_FRAMES; fr++) {
        for (uint32_t i = 0; i < T_ST_BATCH; i++) { /* each key twice, far apart */
            uint32_t j = (fr * T_ST_BATCH / 2 + i) % T_ST_KEYS;
            st[i] = st[i + T_ST_BATCH] = t_st_key(j, XS_HC_SELFTEST_STORE);
        }
        mt_hctable_frame_begin(&t, &f, 1, 1);
        CHECK_EQ_INT(mt_hctable_selftest_run(&t, st, 2 * T_ST_BATCH, &diag), XRSC_OK);
        for (uint32_t i = 0; i < T_ST_BATCH; i++)
            double_reserved += st[i].reserved && st[i + T_ST_BATCH].reserved;
        xrsc_counter c[MT_HCTABLE_COUNTER_COUNT];
        CHECK_EQ_INT(mt_hctable_counters(&t, c, MT_HCTABLE_COUNTER_COUNT),
                     MT_HCTABLE_COUNTER_COUNT);
        /* hc_lookups, hc_inserts, hc_evictions, hc_failed_inserts (mt_hctable.h order) */
        CHECK_EQ_INT(c[4].value, 2 * T_ST_BATCH);
        CHECK(c[6].value <= c[5].value && c[5].value <= T_TINY_TABLE);
        CHECK(c[5].value + c[7].value <= c[4].value);
        CHECK(c[3].value <= XS_HC_MAX_PROBE);
        evictions += c[6].value;
        failed += c[7].value;

        bool last = fr + 1 == T_ST_FRAMES; /* then every key, else this batch */
        uint32_t n = last ? T_ST_KEYS : T_ST_BATCH;
        for (uint32_t i = 0; i < n; i++)
            lk[i] = last ? t_st_key(i, XS_HC_SELFTEST_LOOKUP)
                         : t_st_key((fr * T_ST_BATCH / 2 + i) % T_ST_KEYS, XS_HC_SELFTEST_LOOKUP);
        mt_hctable_frame_begin(&t, &f, 1, 1);
        CHECK_EQ_INT(mt_hctable_selftest_run(&t, lk, n, &diag), XRSC_OK);
        for (uint32_t j = 0; j < n; j++) {
            if (!(lk[j].read_count > 0.0f))
                continue;
            read_ok++;
            wrong += lk[j].read != lk[j].value;
        }
    }
    printf("  table self-test: %u values read back, %u wrong; %.0f evictions, %.0f failed "
           "inserts\n",
           read_ok, wrong, evictions, failed);
    CHECK_EQ_INT(wrong, 0);
    CHECK_EQ_INT(double_reserved, 0);
    CHECK(read_ok >= T_ST_FRAMES * T_TINY_TABLE / 2);
    CHECK(evictions > 0.0 && failed > 0.0);
    mt_hctable_fini(&t);
    CHECK_EQ_INT(gpu->validation_errors, 0);
    gpu_context_destroy(&gpu);
}

int main(void)
{
    RUN(test_table_selftest);
    RUN(test_furnace);
    RUN(test_tiny_table);
    RUN(test_hybrid_furnace);
    RUN(test_hybrid_visibility);
    return t_finish();
}
