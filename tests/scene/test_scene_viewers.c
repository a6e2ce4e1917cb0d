// SPDX-License-Identifier: MIT
/**
 * @file test_scene_viewers.c
 * @brief Issue 13, glTF as viewers accept it (CPU side): scene lists naming child nodes load
 *        with one warning, generated tangents and their handedness, KHR_materials_unlit,
 *        KHR_texture_transform, normalTexture, the camera's yfov/aspect, the no-light
 *        warning, a folder as the scene path, and the Draco error naming the extension.
 */
#include "sc_scene.h"
#include "sc_test_util.h"
#include "testing.h"

#include <math.h>
#include <string.h>

/* A 1x1 RGBA PNG (a widely used test image), as a data URI. */
#define T_PNG_URI                                                                          \
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk"    \
    "YPhfDwAChwGA60e6kgAAAABJRU5ErkJggg=="

/** Buffer: positions of the triangle (0,0,0), (1,0,0), (0,1,0), then its uv (float2 x 3),
 *  then u16 indices 0 1 2 + padding: 36 + 24 + 8 = 68 bytes. */
static char *tri_uv_uri(const float uv[6])
{
    uint8_t b[68];
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t idx[4] = {0, 1, 2, 0};
    memcpy(b, pos, 36);
    memcpy(b + 36, uv, 24);
    memcpy(b + 60, idx, 8);
    return t_data_uri(b, sizeof b);
}

/** A one-triangle glTF with TEXCOORD_0, material 0 = `material`, scene/nodes as given. */
static char *tri_gltf(const float uv[6], const char *material, const char *scenes_nodes,
                      const char *extra_top)
{
    char *uri = tri_uv_uri(uv);
    size_t cap = 8192 + strlen(material) + strlen(scenes_nodes) + strlen(extra_top);
    char *s = malloc(cap);
    snprintf(s, cap,
             "{\"asset\": {\"version\": \"2.0\"}, %s %s,"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1},"
             " \"indices\": 2, \"material\": 0}]}],"
             " \"materials\": [%s],"
             " \"images\": [{\"uri\": \"" T_PNG_URI "\"}], \"textures\": [{\"source\": 0}],"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"},"
             " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC2\"},"
             " {\"bufferView\": 2, \"componentType\": 5123, \"count\": 3, \"type\": \"SCALAR\"}],"
             " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}, {\"buffer\": 0, \"byteOffset\": 36,"
             " \"byteLength\": 24}, {\"buffer\": 0, \"byteOffset\": 60, \"byteLength\": 6}],"
             " \"buffers\": [{\"byteLength\": 68, \"uri\": \"%s\"}]}",
             extra_top, scenes_nodes, material, uri);
    free(uri);
    return s;
}

static const float k_uv_plain[6] = {0, 1, 1, 1, 0, 0};    /* u along +x, v down (= -y) */
static const float k_uv_mirrored[6] = {1, 1, 0, 1, 1, 0}; /* u along -x */
static const char *k_one_node = "\"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0}]";

static sc_scene *load_text(const char *name, const char *json, const sc_load_options *opt,
                           xrsc_result expect, xrsc_diag *d)
{
    sc_scene *s = NULL;
    memset(d, 0, sizeof(*d));
    xrsc_result r = sc_scene_load(t_temp_file(name, json), opt, &s, d);
    char buf[1024];
    CHECK_MSG(r == expect, "%s: %s", name, xrsc_diag_format(d, buf, sizeof buf));
    return s;
}

static void test_child_in_scene_list(void)
{
    /* scenes[0].nodes lists the root 0, its child 1 and the root again: drawn once each, one
     * warning. */
    static const char *nodes =
        "\"scenes\": [{\"nodes\": [0, 1, 0]}], \"nodes\": [{\"mesh\": 0, \"children\": [1]},"
        " {\"mesh\": 0, \"translation\": [2, 0, 0]}]";
    char *json = tri_gltf(k_uv_plain, "{}", nodes, "");
    xrsc_diag d;
    sc_scene *s = load_text("child_listed.gltf", json, NULL, XRSC_OK, &d);
    free(json);
    if (!s)
        return;
    CHECK_EQ_INT(s->instance_count, 2);
    CHECK_EQ_INT(s->warning_count, 1);
    CHECK_NEAR(s->bounds_max[0], 3.0, 1e-6);
    sc_scene_destroy(&s);
    /* a scene listing only the child: its root (and so both nodes) is drawn */
    json = tri_gltf(k_uv_plain, "{}",
                    "\"scenes\": [{\"nodes\": [1]}], \"nodes\": [{\"mesh\": 0, \"children\": [1]},"
                    " {\"mesh\": 0, \"translation\": [2, 0, 0]}]",
                    "");
    s = load_text("only_child.gltf", json, NULL, XRSC_OK, &d);
    free(json);
    if (s)
        CHECK_EQ_INT(s->instance_count, 2);
    sc_scene_destroy(&s);
}

static void test_generated_tangents(void)
{
    xrsc_diag d;
    char *json = tri_gltf(k_uv_plain, "{}", k_one_node, "");
    sc_scene *s = load_text("tangent.gltf", json, NULL, XRSC_OK, &d);
    free(json);
    for (uint32_t i = 0; s && i < s->vertex_count; i++) {
        /* dP/du = +x; bitangent -dP/dv = +y = cross(n, t) with n = +z: w = +1 */
        CHECK_NEAR(s->vertices[i].tangent[0], 1.0, 1e-6);
        CHECK_NEAR(s->vertices[i].tangent[1], 0.0, 1e-6);
        CHECK_NEAR(s->vertices[i].tangent[3], 1.0, 0.0);
    }
    sc_scene_destroy(&s);
    json = tri_gltf(k_uv_mirrored, "{}", k_one_node, "");
    s = load_text("tangent_mirrored.gltf", json, NULL, XRSC_OK, &d);
    free(json);
    for (uint32_t i = 0; s && i < s->vertex_count; i++) {
        /* u runs along -x while v still runs down: the mirrored chart has w = -1 */
        CHECK_NEAR(s->vertices[i].tangent[0], -1.0, 1e-6);
        CHECK_NEAR(s->vertices[i].tangent[3], -1.0, 0.0);
    }
    sc_scene_destroy(&s);
}

static void test_unlit_transform_normal_map(void)
{
    static const char *mat =
        "{\"name\": \"m\", \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.2, 0.4, 0.6, 1],"
        " \"baseColorTexture\": {\"index\": 0, \"extensions\": {\"KHR_texture_transform\":"
        " {\"offset\": [0.5, 0.25], \"rotation\": 1.5707963267948966, \"scale\": [2, 3]}}}},"
        " \"normalTexture\": {\"index\": 0, \"scale\": 0.5},"
        " \"occlusionTexture\": {\"index\": 0},"
        " \"extensions\": {\"KHR_materials_unlit\": {}}}";
    char *json = tri_gltf(
        k_uv_plain, mat, k_one_node,
        "\"extensionsUsed\": [\"KHR_materials_unlit\", \"KHR_texture_transform\"],"
        " \"extensionsRequired\": [\"KHR_materials_unlit\", \"KHR_texture_transform\"],");
    xrsc_diag d;
    sc_scene *s = load_text("unlit.gltf", json, NULL, XRSC_OK, &d);
    free(json);
    if (!s)
        return;
    const sc_material *m = &s->materials[0];
    CHECK(m->unlit);
    CHECK(m->base_color_tex != SC_NO_TEXTURE);
    CHECK(m->normal_tex != SC_NO_TEXTURE);
    CHECK_NEAR(m->normal_scale, 0.5, 0.0);
    /* T(0.5, 0.25) R(90 deg) S(2, 3): rows (c sx, s sy, ox), (-s sx, c sy, oy) */
    const float *t = m->uv_transform[SC_TEX_BASE];
    CHECK_NEAR(t[0], 0.0, 1e-6);
    CHECK_NEAR(t[1], 3.0, 1e-6);
    CHECK_NEAR(t[2], 0.5, 0.0);
    CHECK_NEAR(t[3], -2.0, 1e-6);
    CHECK_NEAR(t[4], 0.0, 1e-6);
    CHECK_NEAR(t[5], 0.25, 0.0);
    /* other slots: identity */
    const float *n = m->uv_transform[SC_TEX_NORMAL];
    CHECK(n[0] == 1.0f && n[1] == 0.0f && n[2] == 0.0f && n[3] == 0.0f && n[4] == 1.0f &&
          n[5] == 0.0f);
    /* nothing ignored (occlusion is documented as ignored, without a warning); an unlit
     * material counts as light, so no no-light warning either */
    CHECK_EQ_INT(s->warning_count, 0);
    sc_scene_destroy(&s);
}

static void test_camera_fov(void)
{
    static const char *nodes =
        "\"scenes\": [{\"nodes\": [0, 1]}], \"nodes\": [{\"mesh\": 0},"
        " {\"camera\": 0, \"translation\": [0, 0, 5]}],"
        " \"cameras\": [{\"type\": \"perspective\", \"perspective\": {\"yfov\": 0.3,"
        " \"aspectRatio\": 1.5, \"znear\": 0.1}}]";
    char *json = tri_gltf(k_uv_plain, "{}", nodes, "");
    xrsc_diag d;
    sc_scene *s = load_text("camera.gltf", json, NULL, XRSC_OK, &d);
    free(json);
    if (!s)
        return;
    CHECK(s->has_camera);
    CHECK_NEAR(s->camera_yfov_rad, 0.3, 1e-7);
    CHECK_NEAR(s->camera_aspect_ratio, 1.5, 1e-7);
    CHECK_NEAR(s->viewpoint_position[2], 5.0, 1e-6);
    sc_scene_destroy(&s);
}

static void test_no_light_warning(void)
{
    char *json = tri_gltf(k_uv_plain, "{}", k_one_node, "");
    xrsc_diag d;
    sc_load_options dark = {.env_set = true};
    sc_scene *s = load_text("dark.gltf", json, &dark, XRSC_OK, &d);
    if (s)
        CHECK_EQ_INT(s->warning_count, 1);
    sc_scene_destroy(&s);
    sc_load_options lit = {.env_set = true, .environment = {0.8f, 0.8f, 0.8f}};
    s = load_text("lit.gltf", json, &lit, XRSC_OK, &d);
    if (s)
        CHECK_EQ_INT(s->warning_count, 0);
    sc_scene_destroy(&s);
    free(json);
}

static void test_folder_and_draco(void)
{
    sc_scene *s = NULL;
    xrsc_diag d;
    CHECK_EQ_INT(sc_scene_load("/tmp", NULL, &s, &d), XRSC_ERROR_IO);
    CHECK(strstr(d.message, "folder") != NULL);
    CHECK(s == NULL);
    char *json = tri_gltf(k_uv_plain, "{}", k_one_node,
                          "\"extensionsUsed\": [\"KHR_draco_mesh_compression\"],"
                          " \"extensionsRequired\": [\"KHR_draco_mesh_compression\"],");
#ifdef XRSC_HAVE_DRACO
    /* built with libdraco: the extension is accepted; a real Draco file decodes when Debian's
     * assimp-testmodels is installed */
    s = load_text("draco.gltf", json, NULL, XRSC_OK, &d);
    free(json);
    sc_scene_destroy(&s);
    static const char *k_draco = "/usr/share/assimp/models/glTF2/draco/2CylinderEngine.gltf";
    if (sc_scene_load(k_draco, NULL, &s, &d) != XRSC_ERROR_IO) {
        CHECK(s != NULL);
        if (s) {
            printf("Draco: %s: %llu triangles\n", k_draco, (unsigned long long)s->triangle_count);
            CHECK(s->triangle_count > 1000);
        }
        sc_scene_destroy(&s);
    }
#else
    s = load_text("draco.gltf", json, NULL, XRSC_ERROR_GLTF_UNSUPPORTED, &d);
    free(json);
    CHECK(s == NULL);
    CHECK(!strcmp(d.field, "extensionsRequired"));
    CHECK(strstr(d.message, "KHR_draco_mesh_compression") != NULL);
#endif
}

static void test_strip_and_fan(void)
{
    /* glTF §3.7.2.1: strip triangle 0 = (p0, p1, p2); fan triangle 0 = (p1, p2, p0): both keep
     * the counter-clockwise winding (+Z normal). A file of lines alone is refused (nothing to
     * draw; lines beside triangles are skipped with a warning: test_scene_fallbacks). */
    const int modes[2] = {5, 6};
    for (int k = 0; k < 2; k++) {
        char *g = sct_triangle_gltf(NULL, modes[k], "", 0, 1, 2, 3);
        xrsc_diag d;
        sc_scene *s = load_text(k ? "fan.gltf" : "strip.gltf", g, NULL, XRSC_OK, &d);
        free(g);
        if (!s)
            continue;
        CHECK_EQ_INT(s->triangle_count, 1);
        const uint32_t *ix = s->indices + s->meshes[0].first_index;
        const float *p0 = s->vertices[ix[0]].position, *p1 = s->vertices[ix[1]].position,
                    *p2 = s->vertices[ix[2]].position;
        double nz = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]);
        CHECK(nz > 0.0);
        sc_scene_destroy(&s);
    }
    char *g = sct_triangle_gltf(NULL, 3, "", 0, 1, 2, 3);
    xrsc_diag d;
    sc_scene *s = load_text("line_strip.gltf", g, NULL, XRSC_ERROR_GLTF_UNSUPPORTED, &d);
    free(g);
    CHECK(s == NULL);
}

int main(void)
{
    RUN(test_strip_and_fan);
    RUN(test_child_in_scene_list);
    RUN(test_generated_tangents);
    RUN(test_unlit_transform_normal_map);
    RUN(test_camera_fov);
    RUN(test_no_light_warning);
    RUN(test_folder_and_draco);
    return t_finish();
}
