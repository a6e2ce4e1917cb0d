// SPDX-License-Identifier: MIT
/**
 * @file test_scene_bad_gltf.c
 * @brief Every class of bad glTF is rejected with its ::xrsc_result ID, field and (where the
 * loader promises it) line; a valid control file built the same way loads.
 */
#include "sc_scene.h"
#include "sc_test_util.h"
#include "testing.h"

#include <string.h>

/** 1-based line of the first occurrence of needle in text. */
static int line_of(const char *text, const char *needle)
{
    const char *p = strstr(text, needle);
    if (!p) return -1;
    int line = 1;
    for (const char *c = text; c < p; c++) line += *c == '\n';
    return line;
}

/** Loads text from a temp file and returns the result; diag is filled. */
static xrsc_result load_text(const char *file_name, const char *text, xrsc_diag *diag)
{
    memset(diag, 0, sizeof *diag);
    sc_scene *s = NULL;
    xrsc_result r = sc_scene_load(t_temp_file(file_name, text), NULL, &s, diag);
    if (r == XRSC_OK) {
        CHECK(s != NULL);
        CHECK(s->triangle_count > 0);
    } else {
        CHECK(s == NULL);
        char buf[1024];
        fprintf(stderr, "  (expected) %s\n", xrsc_diag_format(diag, buf, sizeof buf));
    }
    sc_scene_destroy(&s);
    CHECK(s == NULL);
    return r;
}

/** Loads text and checks that it is rejected with ID want, naming field; d keeps the diag. */
static void check_rejected(const char *file_name, const char *text, xrsc_result want,
                           const char *field, xrsc_diag *d)
{
    CHECK_EQ_INT(load_text(file_name, text, d), want);
    CHECK_MSG(strcmp(d->field, field) == 0, "field '%s', expected '%s'", d->field, field);
}

static void test_control_loads(void)
{
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 3);
    xrsc_diag d;
    CHECK_EQ_INT(load_text("control.gltf", g, &d), XRSC_OK);
    free(g);
}

static void test_missing_buffer(void)
{
    char *g = sct_triangle_gltf("no-such-file.bin", 4, "", 0, 1, 2, 3);
    xrsc_diag d;
    check_rejected("missing-bin.gltf", g, XRSC_ERROR_GLTF_MISSING_BUFFER, "buffers[0].uri", &d);
    CHECK_EQ_INT(d.line, line_of(g, "\"no-such-file.bin\""));
    CHECK(strstr(d.file, "missing-bin.gltf") != NULL);
    free(g);
}

static void test_missing_buffer_from_memory(void)
{
    /* No base folder: no file may be read, so an external uri is a missing buffer. */
    char *g = sct_triangle_gltf("model.bin", 4, "", 0, 1, 2, 3);
    xrsc_diag d = {0};
    sc_scene *s = NULL;
    CHECK_EQ_INT(sc_scene_load_memory("mem.gltf", g, strlen(g), NULL, NULL, &s, &d),
                 XRSC_ERROR_GLTF_MISSING_BUFFER);
    CHECK(s == NULL);
    CHECK(strcmp(d.field, "buffers[0].uri") == 0);
    free(g);
}

/* Issue 18: a missing image is no longer an error but a stand-in with a warning ID
 * (test_scene_fallbacks checks the ID and the stand-in); the file loads. */
static void test_missing_image(void)
{
    char *g = sct_triangle_gltf(
        NULL, 4,
        "\"images\": [{\"uri\": \"missing-texture.png\"}], \"textures\": [{\"source\": 0}],\n"
        "  \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}],",
        0, 1, 2, 3);
    xrsc_diag d;
    CHECK_EQ_INT(load_text("missing-png.gltf", g, &d), XRSC_OK);
    free(g);
}

static void test_required_extension(void)
{
    /* (KHR_draco_mesh_compression is decoded when built with libdraco: test_scene_viewers) */
    /* (EXT_meshopt_compression is decoded when built with libmeshoptimizer since issue 18:
     * test_scene_fallbacks) */
    char *g = sct_triangle_gltf(NULL, 4,
                                "\"extensionsUsed\": [\"EXT_xrsc_no_such_extension\"],\n"
                                "  \"extensionsRequired\": [\"EXT_xrsc_no_such_extension\"],",
                                0, 1, 2, 3);
    xrsc_diag d;
    check_rejected("unknown-ext.gltf", g, XRSC_ERROR_GLTF_UNSUPPORTED, "extensionsRequired", &d);
    CHECK_EQ_INT(d.line, line_of(g, "\"extensionsRequired\""));
    CHECK(strstr(d.message, "EXT_xrsc_no_such_extension") != NULL);
    free(g);

    /* A supported required extension is fine. */
    g = sct_triangle_gltf(NULL, 4, "\"extensionsRequired\": [\"KHR_materials_transmission\"],",
                          0, 1, 2, 3);
    CHECK_EQ_INT(load_text("req-ok.gltf", g, &d), XRSC_OK);
    free(g);
}

/* Issue 18: lines beside triangles are skipped with a warning (test_scene_fallbacks); a file
 * of lines alone has nothing to draw and is refused naming the primitive. */
static void test_lines_mode(void)
{
    char *g = sct_triangle_gltf(NULL, 1, "", 0, 1, 2, 3);
    xrsc_diag d;
    check_rejected("lines.gltf", g, XRSC_ERROR_GLTF_UNSUPPORTED, "meshes[0].primitives[0].mode",
                   &d);
    free(g);
}

/* A strip of 2 vertices has no triangle: a clear error, not a false "out of memory". */
static void test_no_triangle(void)
{
    char *g = sct_triangle_gltf(NULL, 5, "", 0, 1, 2, 3);
    char *c = strstr(g, "\"count\": 3, \"type\": \"SCALAR\"");
    CHECK(c != NULL);
    if (c)
        c[9] = '2';
    xrsc_diag d;
    check_rejected("no-triangle.gltf", g, XRSC_ERROR_GLTF_INVALID,
                   "meshes[0].primitives[0].indices", &d);
    CHECK(strstr(d.message, "no triangle") != NULL);
    free(g);
}

static void test_index_out_of_range(void)
{
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 3, 3);
    xrsc_diag d;
    check_rejected("index-range.gltf", g, XRSC_ERROR_GLTF_INVALID,
                   "meshes[0].primitives[0].indices", &d);
    free(g);
}

static void test_accessor_overrun(void)
{
    /* 4 positions do not fit in the 36-byte view. */
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 4);
    xrsc_diag d;
    check_rejected("overrun.gltf", g, XRSC_ERROR_GLTF_INVALID, "accessors[0]", &d);
    free(g);
}

static void test_view_overruns_buffer(void)
{
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 3);
    char *p = strstr(g, "\"byteOffset\": 36, \"byteLength\": 6");
    CHECK(p != NULL);
    if (p) p[strlen("\"byteOffset\": ")] = '4'; /* 36 -> 46 */
    xrsc_diag d;
    check_rejected("view-overrun.gltf", g, XRSC_ERROR_GLTF_INVALID, "bufferViews[1]", &d);
    free(g);
}

static void test_malformed_json(void)
{
    const char *text = "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"scenes\": [ {\"nodes\": [0]} \n"
                       "  \"nodes\": []\n}\n";
    xrsc_diag d;
    CHECK_EQ_INT(load_text("malformed.gltf", text, &d), XRSC_ERROR_GLTF_PARSE);
    CHECK_EQ_INT(d.line, 4);

    CHECK_EQ_INT(load_text("not-object.gltf", "[1, 2, 3]", &d), XRSC_ERROR_GLTF_PARSE);
    CHECK_EQ_INT(load_text("truncated.gltf", "{\"asset\": {\"vers", &d), XRSC_ERROR_GLTF_PARSE);
}

static void test_empty_scene(void)
{
    const char *text = "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],"
                       " \"nodes\": [{\"name\": \"empty\"}]}";
    xrsc_diag d;
    check_rejected("empty.gltf", text, XRSC_ERROR_GLTF_INVALID, "meshes", &d);
}

static void test_node_graph(void)
{
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 3);
    /* nodes 1 and 2 form a cycle (not reachable from the scene's root). */
    char *p = strstr(g, "\"nodes\": [{\"mesh\": 0}]");
    CHECK(p != NULL);
    size_t cap = strlen(g) + 256;
    char *h = malloc(cap);
    snprintf(h, cap, "%.*s\"nodes\": [{\"mesh\": 0}, {\"children\": [2]}, {\"children\": [1]}]%s",
             (int)(p - g), g, p + strlen("\"nodes\": [{\"mesh\": 0}]"));
    xrsc_diag d;
    CHECK_EQ_INT(load_text("cycle.gltf", h, &d), XRSC_ERROR_GLTF_INVALID);
    CHECK(strstr(d.field, "nodes[") == d.field);
    snprintf(h, cap, "%.*s\"nodes\": [{\"mesh\": 0, \"children\": [7]}]%s", (int)(p - g), g,
             p + strlen("\"nodes\": [{\"mesh\": 0}]"));
    check_rejected("bad-child.gltf", h, XRSC_ERROR_GLTF_INVALID, "nodes[0].children[0]", &d);
    free(h);
    free(g);
}

static void test_bad_references(void)
{
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 3);
    char *p = strstr(g, "\"nodes\": [{\"mesh\": 0}]");
    CHECK(p != NULL);
    p[strlen("\"nodes\": [{\"mesh\": ")] = '5';
    xrsc_diag d;
    check_rejected("bad-mesh.gltf", g, XRSC_ERROR_GLTF_INVALID, "nodes[0].mesh", &d);
    free(g);
}

static void test_glb(void)
{
    /* A GLB with the triangle in its BIN chunk loads; a truncated one is refused as truncated
     * (issue 18: its own ID, with expected and actual length). */
    uint8_t bin[44];
    sct_triangle_bytes(bin, 0, 1, 2);
    const char *json =
        "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0}],"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"},"
        " {\"bufferView\": 1, \"componentType\": 5123, \"count\": 3, \"type\": \"SCALAR\"}],"
        " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}, {\"buffer\": 0, \"byteOffset\": 36,"
        " \"byteLength\": 6}], \"buffers\": [{\"byteLength\": 44}]}";
    uint32_t jlen = (uint32_t)((strlen(json) + 3) & ~3u);
    uint32_t total = 12 + 8 + jlen + 8 + 44;
    uint8_t *glb = calloc(1, total);
    uint32_t hdr[3] = {0x46546C67u, 2, total};
    memcpy(glb, hdr, 12);
    uint32_t c0[2] = {jlen, 0x4E4F534Au};
    memcpy(glb + 12, c0, 8);
    memset(glb + 20, ' ', jlen);
    memcpy(glb + 20, json, strlen(json));
    uint32_t c1[2] = {44, 0x004E4942u};
    memcpy(glb + 20 + jlen, c1, 8);
    memcpy(glb + 28 + jlen, bin, 44);

    sc_scene *s = NULL;
    xrsc_diag d = {0};
    CHECK_EQ_INT(sc_scene_load_memory("tri.glb", glb, total, NULL, NULL, &s, &d), XRSC_OK);
    CHECK(s && s->triangle_count == 1);
    sc_scene_destroy(&s);
    CHECK_EQ_INT(sc_scene_load_memory("cut.glb", glb, 30, NULL, NULL, &s, &d),
                 XRSC_ERROR_GLB_TRUNCATED);
    CHECK(s == NULL);
    free(glb);
}

static void test_io_errors(void)
{
    sc_scene *s = NULL;
    xrsc_diag d = {0};
    CHECK_EQ_INT(sc_scene_load("/nonexistent/x.gltf", NULL, &s, &d), XRSC_ERROR_IO);
    CHECK(s == NULL);
    CHECK_EQ_INT(load_text("empty-file.gltf", "", &d), XRSC_ERROR_EMPTY_FILE);
    sc_scene_destroy(NULL);
}

int main(void)
{
    RUN(test_control_loads);
    RUN(test_missing_buffer);
    RUN(test_missing_buffer_from_memory);
    RUN(test_missing_image);
    RUN(test_required_extension);
    RUN(test_lines_mode);
    RUN(test_no_triangle);
    RUN(test_index_out_of_range);
    RUN(test_accessor_overrun);
    RUN(test_view_overruns_buffer);
    RUN(test_malformed_json);
    RUN(test_empty_scene);
    RUN(test_node_graph);
    RUN(test_bad_references);
    RUN(test_glb);
    RUN(test_io_errors);
    return t_finish();
}
