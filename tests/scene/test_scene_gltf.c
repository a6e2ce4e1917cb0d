// SPDX-License-Identifier: MIT
/**
 * @file test_scene_gltf.c
 * @brief glTF → sc_scene: the real scenes in shared/, the project's own scenes, the Morton
 * sort, node transforms and animation evaluation.
 */
#include "sc_scene.h"
#include "sc_test_util.h"
#include "testing.h"

#include <math.h>
#include <string.h>
#include <time.h>

#define SCT_PI 3.14159265358979323846

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static sc_scene *load(const char *path, const sc_load_options *opt)
{
    sc_scene *s = NULL;
    xrsc_diag d = {0};
    double t0 = now_ms();
    xrsc_result r = sc_scene_load(path, opt, &s, &d);
    double t1 = now_ms();
    char buf[1024];
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    if (s)
        printf("loaded %s: %llu triangles, %u instances, %u materials, %u textures, %u emitters in "
               "%.1f ms\n",
               path, (unsigned long long)s->triangle_count, s->instance_count, s->material_count,
               s->texture_count, s->emitter_count, t1 - t0);
    return s;
}

static const sc_material *material_named(const sc_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->material_count; i++)
        if (strcmp(s->materials[i].name, name) == 0) return &s->materials[i];
    return NULL;
}

static const sc_node *node_named(const sc_scene *s, const char *name, uint32_t *out_index)
{
    for (uint32_t i = 0; i < s->node_count; i++)
        if (strcmp(s->nodes[i].name, name) == 0) {
            if (out_index) *out_index = i;
            return &s->nodes[i];
        }
    return NULL;
}

/** Checks structural invariants every loaded scene must satisfy. */
static void check_invariants(const sc_scene *s)
{
    uint64_t tris = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        CHECK(s->instances[i].mesh < s->mesh_count);
        CHECK(s->instances[i].node < s->node_count);
        tris += s->meshes[s->instances[i].mesh].index_count / 3;
    }
    CHECK_EQ_INT(tris, s->triangle_count);
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        const sc_mesh *mesh = &s->meshes[m];
        CHECK(mesh->index_count % 3 == 0);
        CHECK(mesh->first_index + mesh->index_count <= s->index_count);
        CHECK(mesh->material < s->material_count);
        for (uint32_t k = 0; k < mesh->index_count; k++) {
            uint32_t v = s->indices[mesh->first_index + k];
            if (v < mesh->first_vertex || v >= mesh->first_vertex + mesh->vertex_count) {
                CHECK_MSG(0, "mesh %u index %u = %u outside its vertex range", m, k, v);
                break;
            }
        }
    }
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        const float *n = s->vertices[v].normal;
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (fabsf(len - 1.0f) > 1e-3f) {
            CHECK_MSG(0, "vertex %u normal length %g", v, len);
            break;
        }
    }
    for (uint32_t e = 0; e < s->emitter_count; e++) {
        CHECK(s->emitters[e].instance < s->instance_count);
        /* emitters of one instance are contiguous, in triangle order */
        if (e > 0 && s->emitters[e].instance == s->emitters[e - 1].instance)
            CHECK_EQ_INT(s->emitters[e].primitive, s->emitters[e - 1].primitive + 1);
    }
    for (uint32_t t = 0; t < s->texture_count; t++) {
        CHECK(s->textures[t].width > 0 && s->textures[t].height > 0);
        CHECK(s->textures[t].rgba8 != NULL);
    }
    for (int a = 0; a < 3; a++) CHECK(s->bounds_min[a] <= s->bounds_max[a]);
}

static void test_real_cornell(void)
{
    sc_scene *s = load(t_shared_path("scenes/cornellBox_Vinc3r/cornellBox-2.80-Eevee-gltf.gltf"),
                       NULL);
    if (!s) return;
    check_invariants(s);
    CHECK_EQ_INT(s->triangle_count, 4410);
    const sc_material *suz = material_named(s, "suzanne.000");
    CHECK(suz != NULL);
    if (suz) {
        CHECK_NEAR(suz->metallic, 0.5, 1e-6);
        CHECK_NEAR(suz->roughness, 0.25, 1e-6);
        CHECK_NEAR(suz->base_color[0], 0.8, 1e-6);
    }
    const sc_material *bloc = material_named(s, "bloc.000");
    CHECK(bloc && bloc->base_color_tex != SC_NO_TEXTURE);
    if (bloc && bloc->base_color_tex != SC_NO_TEXTURE)
        CHECK(s->textures[bloc->base_color_tex].srgb);
    /* The lamp: emissive triangles, all from the light.000 material. */
    CHECK(s->emitter_count > 0);
    uint32_t light = (uint32_t)(material_named(s, "light.000") - s->materials);
    double power = 0.0;
    for (uint32_t e = 0; e < s->emitter_count; e++) {
        const sc_instance *in = &s->instances[s->emitters[e].instance];
        CHECK_EQ_INT(s->meshes[in->mesh].material, light);
        power += s->emitters[e].power;
    }
    CHECK(power > 0.0);
    /* No camera in this file (the "Camera" node has none): the documented default. */
    CHECK(!s->has_camera);
    CHECK_NEAR(s->viewpoint_orientation[3], 1.0, 1e-6);
    CHECK(s->viewpoint_position[2] > s->bounds_max[2]);
    CHECK(!s->sun.present);
    /* no directional light, no extras: the built-in studio environment, emissive lamp
     * notwithstanding (issue 11: a glTF model without lights expects image-based lighting) */
    CHECK(s->env_studio);
    CHECK_EQ_INT(s->env_map.width, SC_STUDIO_WIDTH);
    sc_scene_destroy(&s);
    CHECK(s == NULL);
}

static void test_real_candle_holder(void)
{
    sc_scene *s = load(
        t_shared_path("scenes/GlassHurricaneCandleHolder/GlassHurricaneCandleHolder.gltf"), NULL);
    if (!s) return;
    check_invariants(s);
    CHECK_EQ_INT(s->triangle_count, 4126);
    const sc_material *glass = material_named(s, "GlassHurricaneCandleHolder-glass");
    const sc_material *opaque = material_named(s, "GlassHurricaneCandleHolder-opaque");
    CHECK(glass && opaque);
    if (glass && opaque) {
        CHECK_NEAR(glass->transmission, 1.0, 0.0);
        CHECK_NEAR(glass->ior, 1.5, 0.0);
        CHECK_NEAR(opaque->transmission, 0.0, 0.0);
        CHECK(opaque->base_color_tex != SC_NO_TEXTURE);
        CHECK(opaque->metal_rough_tex != SC_NO_TEXTURE);
        if (opaque->metal_rough_tex != SC_NO_TEXTURE)
            CHECK(!s->textures[opaque->metal_rough_tex].srgb);
    }
    CHECK_EQ_INT(s->emitter_count, 0);
    /* no sun, nothing emissive: the studio environment, its mean as the constant */
    CHECK(s->env_studio && s->env_map.sampling);
    CHECK_NEAR(s->environment[1], s->env_map.mean_radiance[1], 0.0);
    sc_scene_destroy(&s);
}

static void test_furnace(void)
{
    sc_scene *s = load(t_source_path("scenes/furnace.gltf"), NULL);
    if (!s) return;
    check_invariants(s);
    CHECK_EQ_INT(s->instance_count, 1);
    CHECK_EQ_INT(s->triangle_count, 64 * (2 * 32 - 2));
    const sc_material *m = &s->materials[s->meshes[s->instances[0].mesh].material];
    CHECK_NEAR(m->base_color[0], 0.5, 0.0);
    CHECK_NEAR(m->metallic, 0.0, 0.0);
    CHECK_NEAR(m->roughness, 1.0, 0.0);
    CHECK_NEAR(m->ior, 1.0, 0.0); /* pure Lambertian: no dielectric specular layer */
    for (int a = 0; a < 3; a++) {
        CHECK_NEAR(s->environment[a], 1.0, 0.0);
        CHECK_NEAR(s->bounds_min[a], -1.0, 1e-5);
        CHECK_NEAR(s->bounds_max[a], 1.0, 1e-5);
    }
    CHECK(s->has_camera);
    CHECK_NEAR(s->viewpoint_position[2], 3.0, 1e-6);
    CHECK_NEAR(s->viewpoint_orientation[3], 1.0, 1e-6);
    CHECK_EQ_INT(s->emitter_count, 0);
    CHECK(!s->sun.present);
    /* round: every vertex on the unit sphere */
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        const float *p = s->vertices[v].position;
        CHECK_NEAR(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 1.0, 1e-5);
    }
    /* an environment override wins over extras */
    sc_load_options opt = {.env_set = true, .environment = {0.25f, 0.5f, 0.75f}};
    sc_scene *o = load(t_source_path("scenes/furnace.gltf"), &opt);
    if (o) CHECK_NEAR(o->environment[2], 0.75, 0.0);
    sc_scene_destroy(&o);
    sc_scene_destroy(&s);
}

static void test_cornell(void)
{
    sc_scene *s = load(t_source_path("scenes/cornell.gltf"), NULL);
    if (!s) return;
    check_invariants(s);
    const sc_material *light = material_named(s, "light");
    const sc_material *metal = material_named(s, "metal");
    const sc_material *glass = material_named(s, "glass");
    const sc_material *red = material_named(s, "red");
    CHECK(light && metal && glass && red);
    if (!light || !metal || !glass || !red) {
        sc_scene_destroy(&s);
        return;
    }
    CHECK_NEAR(light->emission[0], 15.0, 1e-6);
    CHECK_NEAR(metal->metallic, 1.0, 0.0);
    CHECK_NEAR(metal->roughness, 0.2, 1e-6);
    CHECK_NEAR(metal->base_color[1], 0.9, 1e-6);
    CHECK_NEAR(glass->transmission, 1.0, 0.0);
    CHECK_NEAR(glass->ior, 1.5, 0.0);
    CHECK_NEAR(glass->roughness, 0.0, 0.0);
    CHECK(red->base_color[0] > 3 * red->base_color[1]);
    /* the 0.5 m x 0.5 m panel: 2 triangles, power = luminance(15,15,15) x 0.25 m^2 */
    CHECK_EQ_INT(s->emitter_count, 2);
    double power = 0.0;
    for (uint32_t e = 0; e < s->emitter_count; e++) power += s->emitters[e].power;
    CHECK_NEAR(power, 15.0 * 0.25, 1e-4);
    CHECK_NEAR(s->environment[0], 0.0, 0.0);
    CHECK(s->has_camera);
    CHECK_NEAR(s->viewpoint_position[1], 1.0, 1e-6);
    CHECK(s->viewpoint_position[2] > 1.0); /* in front of the opening at z = 1 */
    CHECK_NEAR(s->bounds_max[1], 2.0, 1e-5);
    CHECK_NEAR(s->bounds_min[0], -1.0, 1e-5);
    sc_scene_destroy(&s);
}

static void test_triangles(void)
{
    sc_scene *s = load(t_source_path("scenes/triangles.gltf"), NULL);
    if (!s) return;
    check_invariants(s);
    CHECK_EQ_INT(s->triangle_count, 7);
    CHECK_EQ_INT(s->instance_count, 3);
    CHECK(s->triangle_count < 50);
    const sc_material *ds = material_named(s, "green-double-sided");
    CHECK(ds && ds->double_sided);
    CHECK(!material_named(s, "grey")->double_sided);
    CHECK(s->has_camera);
    CHECK_NEAR(s->viewpoint_position[2], 2.0, 1e-6);
    /* the double-sided triangle has no normals in the file: a flat one facing -Z */
    uint32_t ni = 0;
    CHECK(node_named(s, "double-sided", &ni) != NULL);
    for (uint32_t i = 0; i < s->instance_count; i++)
        if (s->instances[i].node == ni) {
            const sc_mesh *m = &s->meshes[s->instances[i].mesh];
            CHECK_EQ_INT(m->index_count, 3);
            CHECK_NEAR(s->vertices[s->indices[m->first_index]].normal[2], -1.0, 1e-6);
        }
    /* the tetrahedron's node: world = T R S of the file */
    const sc_node *t = node_named(s, "tetrahedron", NULL);
    CHECK(t != NULL);
    if (t) {
        CHECK_NEAR(t->world[12], 0.8, 1e-6);
        CHECK_NEAR(t->world[14], -3.0, 1e-6);
        float sy = sqrtf(t->world[4] * t->world[4] + t->world[5] * t->world[5] +
                         t->world[6] * t->world[6]);
        CHECK_NEAR(sy, 1.2, 1e-5);
        CHECK(fabsf(t->world[8]) > 0.1f); /* rotated: local +Z has an x component */
    }
    CHECK(s->env_studio); /* no light: the studio environment */
    sc_scene_destroy(&s);
}

/** Triangles as 9-float tuples, sorted, for multiset comparison. */
static int cmp9(const void *a, const void *b) { return memcmp(a, b, 9 * sizeof(float)); }

static float *triangle_tuples(const sc_scene *s, uint32_t mesh)
{
    const sc_mesh *m = &s->meshes[mesh];
    uint32_t n = m->index_count / 3;
    float *t = malloc(sizeof(float) * 9 * (n ? n : 1));
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            memcpy(&t[9 * i + 3 * k], s->vertices[s->indices[m->first_index + 3 * i + k]].position,
                   3 * sizeof(float));
    return t;
}

/** Sum of distances between consecutive triangle centroids (small = spatially coherent). */
static double path_length(const float *t, uint32_t n)
{
    double sum = 0.0;
    for (uint32_t i = 1; i < n; i++) {
        double d2 = 0.0;
        for (int a = 0; a < 3; a++) {
            double c0 = (t[9 * (i - 1) + a] + t[9 * (i - 1) + 3 + a] + t[9 * (i - 1) + 6 + a]) / 3;
            double c1 = (t[9 * i + a] + t[9 * i + 3 + a] + t[9 * i + 6 + a]) / 3;
            d2 += (c1 - c0) * (c1 - c0);
        }
        sum += sqrt(d2);
    }
    return sum;
}

static void test_morton_sort(void)
{
    sc_load_options keep = {.keep_triangle_order = true};
    const char *path = t_shared_path("scenes/cornellBox_Vinc3r/cornellBox-2.80-Eevee-gltf.gltf");
    sc_scene *a = load(path, &keep), *b = load(path, NULL);
    if (!a || !b) {
        sc_scene_destroy(&a);
        sc_scene_destroy(&b);
        return;
    }
    CHECK_EQ_INT(a->mesh_count, b->mesh_count);
    bool any_reordered = false;
    double len_file = 0.0, len_sorted = 0.0;
    for (uint32_t m = 0; m < a->mesh_count && m < b->mesh_count; m++) {
        uint32_t n = a->meshes[m].index_count / 3;
        CHECK_EQ_INT(b->meshes[m].index_count / 3, n);
        float *ta = triangle_tuples(a, m), *tb = triangle_tuples(b, m);
        if (memcmp(ta, tb, sizeof(float) * 9 * n) != 0) any_reordered = true;
        len_file += path_length(ta, n);
        len_sorted += path_length(tb, n);
        qsort(ta, n, 9 * sizeof(float), cmp9);
        qsort(tb, n, 9 * sizeof(float), cmp9);
        CHECK_MSG(memcmp(ta, tb, sizeof(float) * 9 * n) == 0, "mesh %u triangle sets differ", m);
        free(ta);
        free(tb);
    }
    CHECK(any_reordered);
    printf("centroid path length: file order %.1f m, Morton order %.1f m\n", len_file, len_sorted);
    CHECK(len_sorted < len_file);
    sc_scene_destroy(&a);
    sc_scene_destroy(&b);

    /* A shuffled 8x8x8 grid of tiny triangles: sorted, the first is at the minimum corner and
     * consecutive ones are neighbours most of the time. */
    enum { N = 8, T = N * N * N };
    sc_vertex *v = calloc(3 * T, sizeof(sc_vertex));
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * T);
    uint32_t order[T];
    for (uint32_t i = 0; i < T; i++) order[i] = i;
    uint32_t rng = 12345;
    for (uint32_t i = T - 1; i > 0; i--) {
        rng = rng * 1664525u + 1013904223u;
        uint32_t j = rng % (i + 1), tmp = order[i];
        order[i] = order[j];
        order[j] = tmp;
    }
    for (uint32_t i = 0; i < T; i++) {
        uint32_t c = order[i];
        float x = (float)(c % N), y = (float)(c / N % N), z = (float)(c / (N * N)) * 10.0f;
        for (int k = 0; k < 3; k++) {
            v[3 * i + k].position[0] = x + (k == 1 ? 0.1f : 0.0f);
            v[3 * i + k].position[1] = y + (k == 2 ? 0.1f : 0.0f);
            v[3 * i + k].position[2] = z;
            idx[3 * i + k] = 3 * i + k;
        }
    }
    CHECK(sc_morton_sort_triangles(v, idx, 3 * T));
    const float *p0 = v[idx[0]].position;
    CHECK(p0[0] == 0.0f && p0[1] == 0.0f && p0[2] == 0.0f);
    uint32_t near = 0;
    bool seen[T] = {false};
    for (uint32_t i = 0; i < T; i++) {
        CHECK(idx[3 * i] % 3 == 0 && idx[3 * i + 1] == idx[3 * i] + 1);
        seen[idx[3 * i] / 3] = true;
        if (i > 0) {
            const float *p = v[idx[3 * i]].position, *q = v[idx[3 * (i - 1)]].position;
            if (fabsf(p[0] - q[0]) + fabsf(p[1] - q[1]) + fabsf(p[2] - q[2]) <= 1.0f) near++;
        }
    }
    for (uint32_t i = 0; i < T; i++) CHECK(seen[i]);
    /* z is stretched 10x: with one uniform scale the curve finishes each z layer first. */
    CHECK(near > T / 2);
    free(v);
    free(idx);
}

static void test_node_transforms(void)
{
    uint8_t bytes[44];
    sct_triangle_bytes(bytes, 0, 1, 2);
    char *uri = t_data_uri(bytes, sizeof bytes);
    char json[2048];
    /* parent: T (1,2,3), R 90 deg about +Y, S (2,1,1); child: T (1,0,0) with the triangle;
     * second child: the same as a matrix (translation (0,0,-1)). */
    float h = sqrtf(0.5f);
    snprintf(json, sizeof json,
             "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": [0]}],"
             " \"nodes\": [{\"name\": \"parent\", \"translation\": [1, 2, 3], \"rotation\": [0, %.9g, 0, %.9g],"
             " \"scale\": [2, 1, 1], \"children\": [1, 2]},"
             " {\"name\": \"child\", \"translation\": [1, 0, 0], \"mesh\": 0},"
             " {\"name\": \"matrix-child\", \"matrix\": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,-1,1], \"mesh\": 0}],"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"},"
             " {\"bufferView\": 1, \"componentType\": 5123, \"count\": 3, \"type\": \"SCALAR\"}],"
             " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}, {\"buffer\": 0, \"byteOffset\": 36,"
             " \"byteLength\": 6}], \"buffers\": [{\"byteLength\": 44, \"uri\": \"%s\"}]}",
             h, h, uri);
    free(uri);
    sc_scene *s = load(t_temp_file("hierarchy.gltf", json), NULL);
    if (!s) return;
    uint32_t ci = 0, mi = 0;
    const sc_node *child = node_named(s, "child", &ci);
    const sc_node *mchild = node_named(s, "matrix-child", &mi);
    CHECK(child && mchild);
    CHECK_EQ_INT(child->parent, 0);
    /* child origin: parent-local (1,0,0) -> scaled (2,0,0) -> rotated (0,0,-2) -> (1,2,1) */
    CHECK_NEAR(child->world[12], 1.0, 1e-5);
    CHECK_NEAR(child->world[13], 2.0, 1e-5);
    CHECK_NEAR(child->world[14], 1.0, 1e-5);
    /* matrix child origin: (0,0,-1) -> scaled (0,0,-1) -> rotated (-1,0,0) -> (0,2,3) */
    CHECK_NEAR(mchild->world[12], 0.0, 1e-5);
    CHECK_NEAR(mchild->world[13], 2.0, 1e-5);
    CHECK_NEAR(mchild->world[14], 3.0, 1e-5);
    /* child's local +X axis (world column 0) = R S (1,0,0) = (0,0,-2) */
    CHECK_NEAR(child->world[0], 0.0, 1e-5);
    CHECK_NEAR(child->world[2], -2.0, 1e-5);
    /* instance transforms follow their nodes; bounds are in world space: vertex (0,1,0) of the
     * child lands at (1,3,1) */
    for (uint32_t i = 0; i < s->instance_count; i++)
        CHECK(memcmp(s->instances[i].world, s->nodes[s->instances[i].node].world,
                     sizeof s->instances[i].world) == 0);
    CHECK_NEAR(s->bounds_max[1], 3.0, 1e-5);
    CHECK_EQ_INT(s->instance_count, 2);
    CHECK(!s->has_camera);
    sc_scene_destroy(&s);
}

static void test_animation(void)
{
    /* times [0,1,2]; translation LINEAR (0,0,0) (2,0,0) (2,4,0); rotation LINEAR identity ->
     * 90 deg about Z -> same; scale CUBICSPLINE keys at 0 and 2: x 1->3 with zero tangents,
     * y 1->3 with tangents 1 (a straight line), z 1. Node 1 (a child) gets STEP translation. */
    float data[3 + 9 + 12 + 2 + 18 + 6];
    float *p = data;
    const float times[3] = {0, 1, 2};
    const float tr[9] = {0, 0, 0, 2, 0, 0, 2, 4, 0};
    float s45 = sinf((float)SCT_PI / 4), c45 = cosf((float)SCT_PI / 4);
    const float rot[12] = {0, 0, 0, 1, 0, 0, s45, c45, 0, 0, s45, c45};
    const float times2[2] = {0, 2};
    const float sc[18] = {0, 0, 0, 1, 1, 1, 0, 1, 0, /* key 0: in, value, out */
                          0, 1, 0, 3, 3, 1, 0, 0, 0};
    const float step[6] = {0, 0, 0, 0, 5, 0};
    memcpy(p, times, sizeof times), p += 3;
    memcpy(p, tr, sizeof tr), p += 9;
    memcpy(p, rot, sizeof rot), p += 12;
    memcpy(p, times2, sizeof times2), p += 2;
    memcpy(p, sc, sizeof sc), p += 18;
    memcpy(p, step, sizeof step);
    uint8_t tri[44];
    sct_triangle_bytes(tri, 0, 1, 2);
    uint8_t all[sizeof data + 44];
    memcpy(all, tri, 44);
    memcpy(all + 44, data, sizeof data);
    char *uri = t_data_uri(all, sizeof all);
    static char json[8192];
    snprintf(json, sizeof json,
             "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": [0, 2]}],"
             " \"nodes\": [{\"name\": \"mover\", \"mesh\": 0, \"children\": [1]},"
             " {\"name\": \"stepper\", \"mesh\": 0}, {\"name\": \"still\", \"mesh\": 0}],"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"},"
             " {\"bufferView\": 1, \"componentType\": 5123, \"count\": 3, \"type\": \"SCALAR\"},"
             " {\"bufferView\": 2, \"byteOffset\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"SCALAR\"},"
             " {\"bufferView\": 2, \"byteOffset\": 12, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"},"
             " {\"bufferView\": 2, \"byteOffset\": 48, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC4\"},"
             " {\"bufferView\": 2, \"byteOffset\": 96, \"componentType\": 5126, \"count\": 2, \"type\": \"SCALAR\"},"
             " {\"bufferView\": 2, \"byteOffset\": 104, \"componentType\": 5126, \"count\": 6, \"type\": \"VEC3\"},"
             " {\"bufferView\": 2, \"byteOffset\": 176, \"componentType\": 5126, \"count\": 2, \"type\": \"VEC3\"}],"
             " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}, {\"buffer\": 0, \"byteOffset\": 36,"
             " \"byteLength\": 6}, {\"buffer\": 0, \"byteOffset\": 44, \"byteLength\": %zu}],"
             " \"buffers\": [{\"byteLength\": %zu, \"uri\": \"%s\"}],"
             " \"animations\": [{\"samplers\": [{\"input\": 2, \"output\": 3},"
             " {\"input\": 2, \"output\": 4, \"interpolation\": \"LINEAR\"},"
             " {\"input\": 5, \"output\": 6, \"interpolation\": \"CUBICSPLINE\"},"
             " {\"input\": 5, \"output\": 7, \"interpolation\": \"STEP\"}],"
             " \"channels\": [{\"sampler\": 0, \"target\": {\"node\": 0, \"path\": \"translation\"}},"
             " {\"sampler\": 1, \"target\": {\"node\": 0, \"path\": \"rotation\"}},"
             " {\"sampler\": 2, \"target\": {\"node\": 0, \"path\": \"scale\"}},"
             " {\"sampler\": 3, \"target\": {\"node\": 1, \"path\": \"translation\"}}]}]}",
             sizeof data, sizeof all, uri);
    free(uri);
    sc_scene *s = load(t_temp_file("anim.gltf", json), NULL);
    if (!s) return;
    CHECK_EQ_INT(s->channel_count, 4);
    CHECK_NEAR(s->animation_duration_s, 2.0, 0.0);
    for (uint32_t i = 0; i < s->instance_count; i++) {
        bool expect = strcmp(s->nodes[s->instances[i].node].name, "still") != 0;
        CHECK_EQ_INT(s->instances[i].animated, expect);
    }
    sc_node *n = &s->nodes[0];
    sc_node *c = &s->nodes[1];

    sc_scene_evaluate(s, 0.5);
    CHECK_NEAR(n->translation[0], 1.0, 1e-6);
    CHECK_NEAR(n->translation[1], 0.0, 1e-6);
    /* slerp halfway to 90 deg about Z = 45 deg */
    CHECK_NEAR(n->rotation[2], sin(SCT_PI / 8), 1e-5);
    CHECK_NEAR(n->rotation[3], cos(SCT_PI / 8), 1e-5);
    /* cubic: u = 0.25 of [0, 2]; zero tangents give 1 + 2 (3u^2 - 2u^3); unit tangents a line */
    CHECK_NEAR(n->scale[0], 1.0 + 2.0 * (3 * 0.0625 - 2 * 0.015625), 1e-5);
    CHECK_NEAR(n->scale[1], 1.5, 1e-5);
    CHECK_NEAR(n->scale[2], 1.0, 1e-6);
    CHECK_NEAR(c->translation[1], 0.0, 0.0); /* STEP holds key 0 until t = 2 */

    sc_scene_evaluate(s, 1.0);
    CHECK_NEAR(n->translation[0], 2.0, 1e-6);
    CHECK_NEAR(n->rotation[2], sin(SCT_PI / 4), 1e-5);
    CHECK_NEAR(n->scale[0], 2.0, 1e-5);

    sc_scene_evaluate(s, 1.5);
    CHECK_NEAR(n->translation[1], 2.0, 1e-6);
    CHECK_NEAR(n->rotation[2], sin(SCT_PI / 4), 1e-5);
    CHECK_NEAR(c->translation[1], 0.0, 0.0);
    /* the child's world = parent's world x child's local: world origin of the child */
    CHECK_NEAR(c->world[12], n->world[12], 1e-5);
    CHECK_NEAR(n->world[12], 2.0, 1e-5);
    CHECK_NEAR(n->world[13], 2.0, 1e-5);

    sc_scene_evaluate(s, 2.0); /* the end of the loop: the last keys */
    CHECK_NEAR(n->translation[1], 4.0, 1e-6);
    CHECK_NEAR(n->scale[0], 3.0, 1e-5);
    CHECK_NEAR(c->translation[1], 5.0, 0.0);
    /* c's world origin: parent T (2,4,0), R 90 deg about Z, S (3,3,1): local (0,5,0) ->
     * scaled (0,15,0) -> rotated (-15,0,0) -> (-13,4,0) */
    CHECK_NEAR(c->world[12], -13.0, 1e-4);
    CHECK_NEAR(c->world[13], 4.0, 1e-4);
    for (uint32_t i = 0; i < s->instance_count; i++)
        if (s->instances[i].node == 1) CHECK_NEAR(s->instances[i].world[12], -13.0, 1e-4);

    sc_scene_evaluate(s, 2.5); /* loops: same as 0.5 */
    CHECK_NEAR(n->translation[0], 1.0, 1e-5);
    CHECK_NEAR(n->scale[1], 1.5, 1e-5);
    sc_scene_evaluate(s, 0.0);
    CHECK_NEAR(n->translation[0], 0.0, 0.0);
    CHECK_NEAR(n->rotation[3], 1.0, 1e-6);
    sc_scene_destroy(&s);
}

static void test_sparse_no_scene_no_normals(void)
{
    /* A sparse accessor moves vertex 1 from (1,0,0) to (2,0,0); no scenes: root nodes are
     * drawn; no indices and no normals: flat normal +Z. */
    uint8_t bytes[52];
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, val[3] = {2, 0, 0};
    const uint16_t si[2] = {1, 0};
    memcpy(bytes, pos, 36);
    memcpy(bytes + 36, si, 4);
    memcpy(bytes + 40, val, 12);
    char *uri = t_data_uri(bytes, sizeof bytes);
    char json[1024];
    snprintf(json, sizeof json,
             "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [{\"mesh\": 0}],"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}],"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3,"
             " \"type\": \"VEC3\", \"sparse\": {\"count\": 1, \"indices\": {\"bufferView\": 1,"
             " \"componentType\": 5123}, \"values\": {\"bufferView\": 2}}}],"
             " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}, {\"buffer\": 0,"
             " \"byteOffset\": 36, \"byteLength\": 2}, {\"buffer\": 0, \"byteOffset\": 40,"
             " \"byteLength\": 12}], \"buffers\": [{\"byteLength\": 52, \"uri\": \"%s\"}]}",
             uri);
    free(uri);
    sc_scene *s = load(t_temp_file("sparse.gltf", json), NULL);
    if (!s) return;
    CHECK_EQ_INT(s->triangle_count, 1);
    CHECK_NEAR(s->bounds_max[0], 2.0, 0.0);
    CHECK_NEAR(s->vertices[0].normal[2], 1.0, 1e-6);
    /* no material: the glTF default material (white, metallic 1, roughness 1) */
    const sc_material *m = &s->materials[s->meshes[0].material];
    CHECK_NEAR(m->metallic, 1.0, 0.0);
    CHECK_NEAR(m->base_color[0], 1.0, 0.0);
    sc_scene_destroy(&s);
}

int main(void)
{
    RUN(test_real_cornell);
    RUN(test_real_candle_holder);
    RUN(test_furnace);
    RUN(test_cornell);
    RUN(test_triangles);
    RUN(test_morton_sort);
    RUN(test_node_transforms);
    RUN(test_animation);
    RUN(test_sparse_no_scene_no_normals);
    return t_finish();
}
