// SPDX-License-Identifier: MIT
/**
 * @file test_skin.c
 * @brief Skins and morph targets posed on the GPU (deform.comp) against the CPU reference
 *        (sc_scene_posed_vertex), a morph target at weight 0.5, and the sample cache following
 *        a skinned surface (validation with synchronization validation on).
 */
#include "mt_hashcache.h"
#include "mt_method.h"
#include "test_samplecache_util.h"
#include "tf_taa.h"
#include "xrsc_shared.h"

#define T_FOX "scenes/khronos/Fox/glTF-Binary/Fox.glb"
#define T_CESIUM_MAN "scenes/khronos/CesiumMan/glTF-Binary/CesiumMan.glb"
/** Issue 21: GPU and CPU poses agree within this many metres (world space). */
#define T_SKIN_TOL_M 1e-5

/** A scene on a validated GPU context, without a method. */
typedef struct t_gpu {
    gpu_context *gpu;
    sc_scene *cpu;
    gpu_scene *gs;
} t_gpu;

static bool t_open(t_gpu *t, const char *path, const char *json)
{
    memset(t, 0, sizeof *t);
    gpu_context_options go = {.validation = true};
    xrsc_diag diag = {0};
    xrsc_result r = gpu_context_create(&go, &t->gpu, &diag);
    if (r == XRSC_OK)
        r = json
                ? sc_scene_load_memory("morph.gltf", json, strlen(json), NULL, NULL, &t->cpu, &diag)
                : sc_scene_load(path, NULL, &t->cpu, &diag);
    if (r == XRSC_OK)
        r = gpu_scene_create(t->gpu, t->cpu, &t->gs, &diag);
    CHECK_EQ_INT(r, XRSC_OK);
    if (r != XRSC_OK)
        tsc_print_diag(&diag);
    return r == XRSC_OK;
}

static void t_close(t_gpu *t)
{
    if (t->gs)
        gpu_scene_destroy(t->gpu, &t->gs);
    sc_scene_destroy(&t->cpu);
    if (t->gpu) {
        CHECK_EQ_INT(t->gpu->validation_errors, 0);
        gpu_context_destroy(&t->gpu);
    }
}

/** Largest world-space distance between the GPU's posed vertices of instance i's mesh and the
 *  CPU reference; *out_moved: largest distance of the reference from the rest pose. */
static double max_pose_error(t_gpu *t, uint32_t i, double *out_moved)
{
    const sc_instance *in = &t->cpu->instances[i];
    const sc_mesh *mesh = &t->cpu->meshes[in->mesh];
    xs_vertex *v = malloc((size_t)mesh->vertex_count * sizeof(*v));
    xrsc_diag diag = {0};
    double worst = INFINITY;
    *out_moved = 0.0;
    if (v && gpu_scene_download_vertices(t->gpu, t->gs, mesh->first_vertex, mesh->vertex_count, v,
                                         &diag) == XRSC_OK) {
        worst = 0.0;
        for (uint32_t k = 0; k < mesh->vertex_count; k++) {
            float ref[3], gpu[3] = {v[k].position_u.x, v[k].position_u.y, v[k].position_u.z};
            float wr[3], wg[3], wrest[3];
            sc_scene_posed_vertex(t->cpu, in->mesh, mesh->first_vertex + k, ref, NULL);
            /* world space, through the instance transform */
            for (int r = 0; r < 3; r++) {
                wr[r] = wg[r] = wrest[r] = in->world[12 + r];
                for (int c = 0; c < 3; c++) {
                    wr[r] += in->world[4 * c + r] * ref[c];
                    wg[r] += in->world[4 * c + r] * gpu[c];
                    wrest[r] +=
                        in->world[4 * c + r] * t->cpu->vertices[mesh->first_vertex + k].position[c];
                }
            }
            double d = 0.0, m = 0.0;
            for (int r = 0; r < 3; r++) {
                d = fmax(d, fabs((double)wr[r] - wg[r]));
                m = fmax(m, fabs((double)wr[r] - wrest[r]));
            }
            worst = fmax(worst, d);
            *out_moved = fmax(*out_moved, m);
        }
    }
    free(v);
    return worst;
}

/** Every vertex of a skinned Khronos model at three times: GPU = CPU within 1e-5 m. */
static void check_model(const char *rel)
{
    t_gpu t;
    if (!t_open(&t, t_shared_path(rel), NULL)) {
        t_close(&t);
        return;
    }
    CHECK(t.cpu->deform_mesh_count >= 1);
    CHECK(!sc_scene_warned(t.cpu, XRSC_WARN_GLTF_EXTENSION_IGNORED));
    CHECK(gpu_scene_deform_mesh_count(t.gs) == t.cpu->deform_mesh_count);
    const double times[3] = {0.25, 0.6, 1.1};
    for (int k = 0; k < 3; k++) {
        sc_scene_evaluate(t.cpu, times[k]);
        xrsc_diag diag = {0};
        CHECK_EQ_INT(gpu_scene_update_instances(t.gpu, t.gs, t.cpu, &diag), XRSC_OK);
        for (uint32_t i = 0; i < t.cpu->instance_count; i++) {
            if (t.cpu->meshes[t.cpu->instances[i].mesh].deform_node == SC_NO_DEFORM)
                continue;
            double moved = 0.0, err = max_pose_error(&t, i, &moved);
            printf("  %s t=%.2f s instance %u: max |GPU - CPU| %.3g m, pose moved up to %.3f m\n",
                   rel, times[k], i, err, moved);
            CHECK_MSG(err <= T_SKIN_TOL_M, "GPU pose off by %g m", err);
            CHECK_MSG(moved > 0.01, "the pose did not move (%g m)", moved);
        }
    }
    uint32_t rebuilds = 0, refits = 0;
    gpu_scene_blas_update_counts(t.gs, &rebuilds, &refits);
    printf("  %s: %u BLAS rebuilds, %u refits (drift rule)\n", rel, rebuilds, refits);
    CHECK_EQ_INT(rebuilds + refits, 3);
    t_close(&t);
}

static void test_fox(void)
{
    check_model(T_FOX);
}
static void test_cesium_man(void)
{
    check_model(T_CESIUM_MAN);
}

/** One triangle with one morph target that moves vertex 0 by +1 m in y; mesh weight w0 and a
 *  LINEAR `weights` channel from 0 (t = 0) to 1 (t = 1). */
static char *morph_gltf(float w0)
{
    struct {
        float pos[9], dpos[9], times[2], weights[2];
    } b = {{0, 0, 0, 1, 0, 0, 0, 0, 1}, {0, 1, 0, 0, 0, 0, 0, 0, 0}, {0, 1}, {0, 1}};
    char *uri = t_data_uri(&b, sizeof b);
    char *json = malloc(4096);
    snprintf(
        json, 4096,
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
        "\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"weights\":[%g],\"primitives\":[{\"attributes\":{\"POSITION\":0},"
        "\"targets\":[{\"POSITION\":1}]}]}],"
        "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
        "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":36},"
        "{\"buffer\":0,\"byteOffset\":72,\"byteLength\":8},"
        "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":8}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[1,0,1]},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\","
        "\"min\":[0],\"max\":[1]},"
        "{\"bufferView\":3,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\"}],"
        "\"animations\":[%s]}",
        w0, sizeof b, uri,
        w0 < 0.0f ? "{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":"
                    "\"weights\"}}],\"samplers\":[{\"input\":2,\"output\":3}]}"
                  : "");
    free(uri);
    return json;
}

/** Vertex 0's y on the GPU. */
static double gpu_y0(t_gpu *t)
{
    xs_vertex v;
    xrsc_diag diag = {0};
    const sc_mesh *mesh = &t->cpu->meshes[0];
    CHECK_EQ_INT(gpu_scene_download_vertices(t->gpu, t->gs, mesh->first_vertex, 1, &v, &diag),
                 XRSC_OK);
    return v.position_u.y;
}

static void test_morph_half(void)
{
    /* the mesh's default weight 0.5, no animation */
    char *json = morph_gltf(0.5f);
    t_gpu t;
    if (t_open(&t, NULL, json)) {
        CHECK_EQ_INT(t.cpu->deform_mesh_count, 1);
        double y = gpu_y0(&t);
        printf("  weight 0.5: vertex 0 at y = %.6f (rest 0, target +1)\n", y);
        CHECK_NEAR(y, 0.5, 1e-6);
    }
    t_close(&t);
    free(json);
    /* an animated weights channel 0 -> 1 over 1 s: halfway at 0.5 s, a quarter at 0.25 s */
    json = morph_gltf(-1.0f);
    if (t_open(&t, NULL, json)) {
        const double times[2] = {0.5, 0.25};
        for (int k = 0; k < 2; k++) {
            sc_scene_evaluate(t.cpu, times[k]);
            xrsc_diag diag = {0};
            CHECK_EQ_INT(gpu_scene_update_instances(t.gpu, t.gs, t.cpu, &diag), XRSC_OK);
            double y = gpu_y0(&t);
            printf("  animated weight at t=%.2f s: vertex 0 at y = %.6f\n", times[k], y);
            CHECK_NEAR(y, times[k], 1e-6);
        }
    }
    t_close(&t);
    free(json);
}

/* ---- the sample cache follows a skinned surface ---- */

#define T_RP_W 48u
#define T_RP_T0 0.3 /* s: the frames that fill the cache */
#define T_RP_T1 0.5 /* s: the frame whose reprojection is checked */

/** World position of first hit fh on the CPU reference pose (sc_scene_posed_vertex). */
static void posed_hit_world(const sc_scene *s, const uint32_t fh[4], double out[3])
{
    const sc_instance *in = &s->instances[fh[3]];
    const sc_mesh *mesh = &s->meshes[in->mesh];
    double u = xs_sc_unpack_bary(fh[0]), v = xs_sc_unpack_bary(fh[1]);
    double wt[3] = {1.0 - u - v, u, v};
    out[0] = out[1] = out[2] = 0.0;
    for (int c = 0; c < 3; c++) {
        float p[3];
        sc_scene_posed_vertex(s, in->mesh, s->indices[mesh->first_index + 3 * fh[2] + c], p, NULL);
        for (int r = 0; r < 3; r++)
            out[r] += wt[c] * ((double)in->world[r] * p[0] + (double)in->world[4 + r] * p[1] +
                               (double)in->world[8 + r] * p[2] + (double)in->world[12 + r]);
    }
}

/** Skinned-surface samples after reprojection, and how many project outside their pixel (by
 *  more than TSC_PIXEL_MARGIN) on the CPU pose, i.e. off a fresh trace's surface point. */
static void count_skinned(const mt_sc_snapshot *sn, const sc_scene *s, const tsc_view *v,
                          uint32_t *out_n, uint32_t *out_off, double *out_max_px)
{
    for (uint32_t p = 0; p < sn->width * sn->height; p++)
        for (uint32_t k = 0; k < sn->slots; k++) {
            const uint32_t *fh = tsc_fh(sn, k, p);
            if (!(tsc_occ(sn, p) >> k & 1u) || fh[3] >= s->instance_count ||
                s->meshes[s->instances[fh[3]].mesh].deform_node == SC_NO_DEFORM)
                continue;
            double w[3], pos[2] = {-1e9, -1e9};
            posed_hit_world(s, fh, w);
            tsc_project(v, w, 1.0, pos);
            /* distance from the pixel's centre, per axis */
            double d =
                fmax(fabs(pos[0] - (p % sn->width + 0.5)), fabs(pos[1] - (p / sn->width + 0.5)));
            *out_max_px = fmax(*out_max_px, d);
            (*out_n)++;
            *out_off += d > 0.5 + TSC_PIXEL_MARGIN;
        }
}

/** Renders at T_RP_T0 twice, then at T_RP_T1 up to the reprojection; *out_off of *out_n
 *  skinned samples land off their pixel. deform: the GPU poses the mesh (else frozen). */
static void run_reprojection(bool deform, uint32_t *out_n, uint32_t *out_off, double *out_max)
{
    xrsc_samplecache_options o = {0};
    tsc_rig rig;
    *out_n = *out_off = 0;
    *out_max = 0.0;
    if (!tsc_open(&rig, t_shared_path(T_CESIUM_MAN), T_RP_W, T_RP_W, &o)) {
        tsc_close(&rig);
        return;
    }
    for (uint32_t k = 0; k < 2; k++) {
        xrsc_frame f = tsc_viewpoint_stereo(rig.cpu, k, T_RP_T0);
        tsc_set_time(&rig, T_RP_T0);
        if (!tsc_render(rig.m, &f))
            goto done;
    }
    gpu_scene_set_deform_enabled(rig.gs, deform);
    xrsc_frame g = tsc_viewpoint_stereo(rig.cpu, 2, T_RP_T1);
    tsc_set_time(&rig, T_RP_T1);
    CHECK_EQ_INT(mt_samplecache_debug_stop_after(rig.m, MT_SC_PASS_REPROJECT, NULL), XRSC_OK);
    if (!tsc_render(rig.m, &g))
        goto done;
    for (uint32_t e = 0; e < 2; e++) {
        mt_sc_snapshot sn;
        if (!tsc_snapshot(rig.m, e, &sn))
            continue;
        tsc_view v;
        tsc_make_view(&g.views[e], T_RP_W, T_RP_W, &v);
        count_skinned(&sn, rig.cpu, &v, out_n, out_off, out_max);
        mt_sc_snapshot_free(&sn);
    }
done:
    tsc_close(&rig);
}

static void test_reprojection_follows_skin(void)
{
    uint32_t n = 0, off = 0, n_frozen = 0, off_frozen = 0;
    double max_px = 0.0, max_frozen = 0.0;
    run_reprojection(true, &n, &off, &max_px);
    run_reprojection(false, &n_frozen, &off_frozen, &max_frozen);
    printf("  CesiumMan %.1f -> %.1f s: %u of %u skinned samples off their pixel (max %.3f px "
           "from its centre); with GPU skinning off: %u of %u (max %.3f px)\n",
           T_RP_T0, T_RP_T1, off, n, max_px, off_frozen, n_frozen, max_frozen);
    CHECK_MSG(n > 50, "only %u skinned samples", n);
    CHECK_MSG(off == 0, "%u skinned samples more than 0.5 px off", off);
    /* the control: without the GPU pose the cache does not follow the figure */
    CHECK_MSG(off_frozen > n_frozen / 10, "skinning off: only %u of %u off", off_frozen, n_frozen);
}

/* ---- TAA's history follows a skinned surface (last frame's posed positions) ---- */

static void taa_post(void *user, VkCommandBuffer cmd, gpu_timer *timer, const xs_frame *xf)
{
    tf_taa_cmd_record((tf_taa *)user, cmd, timer, xf);
}

/** Primary rays + TAA on CesiumMan: frames at T_RP_T0 (twice) then T_RP_T1. Over the figure's
 *  pixels of eye 0: the fraction whose history was accepted and the mean |history - current|
 *  of those (the primary method is noise-free, so a right reprojection finds the same texel). */
static void run_taa(bool follow, double *out_blended, double *out_err)
{
    tsc_rig r = {.width = T_RP_W, .height = T_RP_W};
    tf_taa *taa = NULL;
    mt_post post = {0};
    xrsc_diag diag = {0};
    gpu_context_options go = {.validation = true};
    xrsc_result res = gpu_context_create(&go, &r.gpu, &diag);
    if (res == XRSC_OK)
        res = sc_scene_load(t_shared_path(T_CESIUM_MAN), NULL, &r.cpu, &diag);
    if (res == XRSC_OK)
        res = gpu_scene_create(r.gpu, r.cpu, &r.gs, &diag);
    mt_env env = {.gpu = r.gpu,
                  .scene = r.gs,
                  .cpu_scene = r.cpu,
                  .width = T_RP_W,
                  .height = T_RP_W,
                  .post = &post};
    if (res == XRSC_OK)
        res = mt_primary_create(&env, &r.m, &diag);
    if (res == XRSC_OK) {
        tf_settings set = {.mode = XRSC_TAA_ON, .debug = true, .no_deform_motion = !follow};
        tf_images imgs = {mt_method_output_image(r.m, XRSC_OUTPUT_COLOR),
                          mt_method_output_image(r.m, XRSC_OUTPUT_DEPTH),
                          mt_method_output_image(r.m, XRSC_OUTPUT_HIT_ID)};
        res = tf_taa_create(r.gpu, r.gs, r.cpu->instance_count, T_RP_W, T_RP_W, &set, &imgs, &taa,
                            &diag);
    }
    CHECK_EQ_INT(res, XRSC_OK);
    post = (mt_post){.record = taa_post, .user = taa};
    const double times[3] = {T_RP_T0, T_RP_T0, T_RP_T1};
    for (uint32_t k = 0; res == XRSC_OK && k < 3; k++) {
        xrsc_frame f = tsc_viewpoint_stereo(r.cpu, k, times[k]);
        tsc_set_time(&r, times[k]);
        res = tsc_render(r.m, &f) ? XRSC_OK : XRSC_ERROR_VULKAN;
    }
    size_t n = (size_t)T_RP_W * T_RP_W;
    float *aux = malloc(n * 16), *src = malloc(n * 16), *rep = malloc(n * 16);
    uint32_t *hit = malloc(n * 16), figure = 0, blended = 0;
    double err = 0.0;
    if (res == XRSC_OK && aux && src && rep && hit &&
        tf_taa_read(taa, 0, TF_IMAGE_AUX, aux, n * 16, &diag) == XRSC_OK &&
        tf_taa_read(taa, 0, TF_IMAGE_SRC, src, n * 16, &diag) == XRSC_OK &&
        tf_taa_read(taa, 0, TF_IMAGE_REPROJ, rep, n * 16, &diag) == XRSC_OK &&
        mt_method_read(r.m, 0, XRSC_OUTPUT_HIT_ID, hit, n * 16, &diag) == XRSC_OK)
        for (size_t p = 0; p < n; p++) {
            if (hit[4 * p] >= r.cpu->instance_count ||
                r.cpu->meshes[r.cpu->instances[hit[4 * p]].mesh].deform_node == SC_NO_DEFORM)
                continue;
            figure++;
            if (aux[4 * p + 3] != XS_TF_STATUS_BLENDED)
                continue;
            blended++;
            for (int c = 0; c < 3; c++)
                err += fabs(rep[4 * p + c] - src[4 * p + c]) / 3.0;
        }
    *out_blended = figure ? (double)blended / figure : 0.0;
    *out_err = blended ? err / blended : INFINITY;
    CHECK_MSG(figure > 50, "only %u figure pixels", figure);
    free(aux), free(src), free(rep), free(hit);
    tf_taa_destroy(&taa);
    tsc_close(&r);
}

static void test_taa_follows_skin(void)
{
    double blended = 0, err = 0, blended_rigid = 0, err_rigid = 0;
    run_taa(true, &blended, &err);
    run_taa(false, &blended_rigid, &err_rigid);
    printf("  TAA on CesiumMan %.1f -> %.1f s: history kept on %.1f %% of the figure, mean "
           "|history - current| %.4f; reprojected as rigid: %.1f %%, %.4f\n",
           T_RP_T0, T_RP_T1, 100.0 * blended, err, 100.0 * blended_rigid, err_rigid);
    CHECK(blended > blended_rigid);
    CHECK(err < err_rigid);
}

/* ---- the hash cache follows the walking figure (issue 21 item 3) ---- */

#define T_HC_SCENE "scenes/character.gltf"
#define T_HC_W 32u
#define T_HC_FRAMES 6u
#define T_HC_DT (1.0 / 30.0) /* s per frame: the figure walks 1 m/s */

/** `hashcache` on character.gltf (walk), T_HC_FRAMES frames from 0.3 s: over the frames after
 *  the first, the share of the figure's cache lookups whose voxel holds earlier frames'
 *  samples (mt_hashcache_deform_stats); follow false: the test-only switch off. */
static double run_hashcache(bool follow)
{
    tsc_rig r = {.width = T_HC_W, .height = T_HC_W};
    xrsc_diag diag = {0};
    gpu_context_options go = {.validation = true};
    xrsc_result res = gpu_context_create(&go, &r.gpu, &diag);
    if (res == XRSC_OK)
        res = sc_scene_load(t_source_path(T_HC_SCENE), NULL, &r.cpu, &diag);
    if (res == XRSC_OK)
        res = gpu_scene_create(r.gpu, r.cpu, &r.gs, &diag);
    mt_env env = {.gpu = r.gpu, .scene = r.gs, .cpu_scene = r.cpu, .width = T_HC_W,
                  .height = T_HC_W};
    xrsc_hashcache_options o = {.table_entries = 1u << 16};
    if (res == XRSC_OK)
        res = mt_hashcache_create(&env, &o, &r.m, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    else
        mt_hashcache_set_deform_follow(r.m, follow);
    uint64_t lookups = 0, history = 0;
    for (uint32_t k = 0; res == XRSC_OK && k < T_HC_FRAMES; k++) {
        double t = 0.3 + k * T_HC_DT;
        xrsc_frame f = tsc_viewpoint_stereo(r.cpu, k, t);
        tsc_set_time(&r, t);
        res = tsc_render(r.m, &f) ? XRSC_OK : XRSC_ERROR_VULKAN;
        uint32_t l = 0, h = 0;
        if (res == XRSC_OK && k > 0) {
            mt_hashcache_deform_stats(r.m, &l, &h);
            lookups += l, history += h;
        }
    }
    CHECK_MSG(lookups > 100, "only %llu lookups on the figure", (unsigned long long)lookups);
    tsc_close(&r);
    return lookups ? (double)history / lookups : 0.0;
}

static void test_hashcache_follows_skin(void)
{
    double on = run_hashcache(true), off = run_hashcache(false);
    printf("  hashcache on %s (walk): figure lookups finding history %.1f %% following the "
           "skin, %.1f %% keyed by this frame's position only\n",
           T_HC_SCENE, 100.0 * on, 100.0 * off);
    CHECK(on > off + 0.1);
}

/* ---- every JOINTS_n / WEIGHTS_n set; bad joints refused ---- */

/** One triangle skinned by two sets: JOINTS_0 = joint 0 (identity) with weight 0.5, JOINTS_1 =
 *  joint `j1` (translated +2 m in y) with 0.5, so the pose lifts it by 1 m. */
static char *two_set_gltf(uint8_t j1)
{
    struct {
        float pos[9];
        uint8_t j0[12];
        float w0[12];
        uint8_t j1[12];
        float w1[12];
    } b = {{0, 0, 0, 1, 0, 0, 0, 0, 1},
           {0},
           {0.5f, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0, 0, 0},
           {j1, 0, 0, 0, j1, 0, 0, 0, j1, 0, 0, 0},
           {0.5f, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0, 0, 0}};
    _Static_assert(sizeof b == 156, "packed test buffer");
    char *uri = t_data_uri(&b, sizeof b);
    char *json = malloc(4096);
    snprintf(
        json, 4096,
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1,2]}],"
        "\"nodes\":[{\"mesh\":0,\"skin\":0},{},{\"translation\":[0,2,0]}],"
        "\"skins\":[{\"joints\":[1,2]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"JOINTS_0\":1,"
        "\"WEIGHTS_0\":2,\"JOINTS_1\":3,\"WEIGHTS_1\":4}}]}],"
        "\"buffers\":[{\"byteLength\":156,\"uri\":\"%s\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
        "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":12},"
        "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},"
        "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":12},"
        "{\"buffer\":0,\"byteOffset\":108,\"byteLength\":48}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[1,0,1]},"
        "{\"bufferView\":1,\"componentType\":5121,\"count\":3,\"type\":\"VEC4\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":3,\"type\":\"VEC4\"},"
        "{\"bufferView\":3,\"componentType\":5121,\"count\":3,\"type\":\"VEC4\"},"
        "{\"bufferView\":4,\"componentType\":5126,\"count\":3,\"type\":\"VEC4\"}]}",
        uri);
    free(uri);
    return json;
}

static void test_two_joint_sets(void)
{
    char *json = two_set_gltf(1);
    t_gpu t;
    if (t_open(&t, NULL, json)) {
        CHECK_EQ_INT(t.cpu->meshes[0].skin_sets, 2);
        float cpu[3];
        sc_scene_posed_vertex(t.cpu, 0, t.cpu->meshes[0].first_vertex, cpu, NULL);
        double y = gpu_y0(&t);
        printf("  two sets (0.5 at rest, 0.5 lifted 2 m): vertex 0 at y = %.6f (CPU %.6f)\n", y,
               cpu[1]);
        CHECK_NEAR(y, 1.0, 1e-6);
        CHECK_NEAR(cpu[1], 1.0, 1e-6);
    }
    t_close(&t);
    free(json);
    /* a joint index past the skin's two joints (with weight) is refused, naming the node */
    json = two_set_gltf(5);
    sc_scene *s = NULL;
    xrsc_diag diag = {0};
    CHECK_EQ_INT(sc_scene_load_memory("bad.gltf", json, strlen(json), NULL, NULL, &s, &diag),
                 XRSC_ERROR_GLTF_INVALID);
    CHECK(strstr(diag.field, "nodes[0].skin") != NULL);
    CHECK(s == NULL);
    free(json);
}

int main(void)
{
    RUN(test_fox);
    RUN(test_cesium_man);
    RUN(test_morph_half);
    RUN(test_two_joint_sets);
    RUN(test_reprojection_follows_skin);
    RUN(test_taa_follows_skin);
    RUN(test_hashcache_follows_skin);
    return t_finish();
}
