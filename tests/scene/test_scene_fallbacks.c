// SPDX-License-Identifier: MIT
/**
 * @file test_scene_fallbacks.c
 * @brief Issue 18 (loader): what can be drawn is drawn, with a warning ID for the rest
 *        (missing/undecodable image, points and lines, optional extensions), bad files get
 *        their own error IDs before tinygltf sees them (not glTF, glTF 1.0, GLB magic, truncated
 *        GLB), KHR_texture_basisu is refused by name only when required, EXT_meshopt_compression
 *        gives the triangles of its uncompressed twin, EXT_mesh_gpu_instancing gives one
 *        instance per element, spec-gloss materials are converted to metal/rough, and sampler
 *        wrap modes and filters reach sc_texture. Every file is written by the test.
 */
#include "sc_scene.h"
#include "sc_test_util.h"
#include "testing.h"

#ifdef XRSC_HAVE_MESHOPT
#include <meshoptimizer.h>
#endif

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

/** Writes an RGBA8 PNG (rows top to bottom); XRSC_OK or XRSC_ERROR_IO. */
static xrsc_result write_png_rgba(const char *path, const uint8_t *rgba, int w, int h)
{
    return stbi_write_png(path, w, h, 4, rgba, w * 4) ? XRSC_OK : XRSC_ERROR_IO;
}

/** Loads text from a temp file; want is the expected result. Returns the scene (or NULL). */
static sc_scene *load_text(const char *file_name, const char *text, xrsc_result want,
                           xrsc_diag *diag)
{
    memset(diag, 0, sizeof *diag);
    sc_scene *s = NULL;
    xrsc_result r = sc_scene_load(t_temp_file(file_name, text), NULL, &s, diag);
    char buf[1024];
    CHECK_MSG(r == want, "%s: %s (expected %s)", file_name, xrsc_diag_format(diag, buf, sizeof buf),
              xrsc_result_name(want));
    if (r != XRSC_OK) {
        fprintf(stderr, "  (expected) %s\n", xrsc_diag_format(diag, buf, sizeof buf));
        CHECK(s == NULL);
    }
    return s;
}

/** Writes bytes to a temp file and loads it; returns the result. */
static xrsc_result load_bytes(const char *file_name, const void *data, size_t size,
                              xrsc_diag *diag)
{
    const char *path = t_temp_file(file_name, "");
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f) return XRSC_ERROR_IO;
    fwrite(data, 1, size, f);
    fclose(f);
    memset(diag, 0, sizeof *diag);
    sc_scene *s = NULL;
    xrsc_result r = sc_scene_load(path, NULL, &s, diag);
    char buf[1024];
    fprintf(stderr, "  %s: %s\n", file_name,
            r == XRSC_OK ? "loaded" : xrsc_diag_format(diag, buf, sizeof buf));
    sc_scene_destroy(&s);
    return r;
}

/** A GLB of the JSON text (no BIN chunk): 12-byte header + JSON chunk. *out_size set. */
static uint8_t *make_glb(const char *json, size_t *out_size)
{
    size_t n = strlen(json), padded = (n + 3) & ~(size_t)3, total = 20 + padded;
    uint8_t *b = malloc(total);
    memcpy(b, "glTF", 4);
    uint32_t h[4] = {2, (uint32_t)total, (uint32_t)padded, 0x4E4F534Au};
    memcpy(b + 4, h, 16);
    memset(b + 20, ' ', padded);
    memcpy(b + 20, json, n);
    *out_size = total;
    return b;
}

static void test_missing_image_stand_in(void)
{
    char *g = sct_triangle_gltf(
        NULL, 4,
        "\"images\": [{\"uri\": \"missing-texture.png\"}], \"textures\": [{\"source\": 0}],\n"
        "  \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.2, 0.4, 0.6, 1],"
        " \"baseColorTexture\": {\"index\": 0}}, \"normalTexture\": {\"index\": 0}}],",
        0, 1, 2, 3);
    xrsc_diag d;
    sc_scene *s = load_text("missing-png.gltf", g, XRSC_OK, &d);
    free(g);
    if (!s) return;
    CHECK(sc_scene_warned(s, XRSC_WARN_GLTF_IMAGE_MISSING));
    CHECK(!sc_scene_warned(s, XRSC_WARN_GLTF_IMAGE_UNDECODABLE));
    CHECK_EQ_INT(s->materials[0].base_color_tex, SC_NO_TEXTURE); /* white stand-in */
    CHECK_EQ_INT(s->materials[0].normal_tex, SC_NO_TEXTURE);     /* flat normal */
    CHECK_NEAR(s->materials[0].base_color[1], 0.4, 1e-7);
    CHECK_EQ_INT(s->texture_count, 0);
    sc_scene_destroy(&s);
}

static void test_undecodable_image(void)
{
    char *g = sct_triangle_gltf(
        NULL, 4,
        "\"images\": [{\"uri\": \"data:image/png;base64,iVBORw0KGgoAAAAAAAAAAAAA\"}],"
        " \"textures\": [{\"source\": 0}],\n"
        "  \"materials\": [{\"emissiveTexture\": {\"index\": 0}}],",
        0, 1, 2, 3);
    xrsc_diag d;
    sc_scene *s = load_text("bad-png.gltf", g, XRSC_OK, &d);
    free(g);
    if (!s) return;
    CHECK(sc_scene_warned(s, XRSC_WARN_GLTF_IMAGE_UNDECODABLE));
    CHECK_EQ_INT(s->materials[0].emission_tex, SC_NO_TEXTURE);
    sc_scene_destroy(&s);
}

static void test_lines_skipped(void)
{
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 3);
    /* A second primitive of LINES (and a third of POINTS) beside the triangle. */
    const char *at = "\"mode\": 4}";
    char *p = strstr(g, at);
    CHECK(p != NULL);
    if (!p) {
        free(g);
        return;
    }
    const char *add = ", {\"attributes\": {\"POSITION\": 0}, \"mode\": 1},"
                      " {\"attributes\": {\"POSITION\": 0}, \"mode\": 0}";
    size_t head = (size_t)(p - g) + strlen(at);
    char *m = malloc(strlen(g) + strlen(add) + 1);
    memcpy(m, g, head);
    strcpy(m + head, add);
    strcat(m, g + head);
    xrsc_diag d;
    sc_scene *s = load_text("lines.gltf", m, XRSC_OK, &d);
    if (s) {
        CHECK(sc_scene_warned(s, XRSC_WARN_GLTF_PRIMITIVE_SKIPPED));
        CHECK_EQ_INT(s->triangle_count, 1);
        CHECK_EQ_INT(s->instance_count, 1);
        sc_scene_destroy(&s);
    }
    free(m);
    free(g);
    /* Lines alone: nothing to draw is refused, naming the primitive. */
    g = sct_triangle_gltf(NULL, 1, "", 0, 1, 2, 3);
    s = load_text("lines-only.gltf", g, XRSC_ERROR_GLTF_UNSUPPORTED, &d);
    CHECK(strcmp(d.field, "meshes[0].primitives[0].mode") == 0);
    free(g);
}

static void test_optional_extensions_warn_each(void)
{
    xrsc_diag d;
    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 3);
    sc_scene *control = load_text("ext-control.gltf", g, XRSC_OK, &d);
    free(g);
    g = sct_triangle_gltf(NULL, 4,
                          "\"extensionsUsed\": [\"EXT_xrsc_made_up_a\", \"EXT_xrsc_made_up_b\","
                          " \"KHR_materials_transmission\"],",
                          0, 1, 2, 3);
    sc_scene *s = load_text("ext-optional.gltf", g, XRSC_OK, &d);
    free(g);
    if (s && control) {
        CHECK(sc_scene_warned(s, XRSC_WARN_GLTF_EXTENSION_IGNORED));
        CHECK(!sc_scene_warned(control, XRSC_WARN_GLTF_EXTENSION_IGNORED));
        CHECK_EQ_INT(s->warning_count, control->warning_count + 2); /* one per extension */
    }
    sc_scene_destroy(&s);
    sc_scene_destroy(&control);
}

static void test_basisu(void)
{
    xrsc_diag d;
    char *g = sct_triangle_gltf(NULL, 4,
                                "\"extensionsUsed\": [\"KHR_texture_basisu\"],"
                                " \"extensionsRequired\": [\"KHR_texture_basisu\"],",
                                0, 1, 2, 3);
    load_text("basisu-required.gltf", g, XRSC_ERROR_GLTF_UNSUPPORTED, &d);
    CHECK(strcmp(d.field, "extensionsRequired") == 0);
    CHECK(strstr(d.message, "KHR_texture_basisu") != NULL);
    free(g);

    /* Optional, with a PNG fallback source: drawn with the PNG, one warning. */
    const char *png = t_temp_file("basisu-fallback.png", "");
    static const uint8_t texel[4] = {200, 100, 50, 255};
    CHECK_EQ_INT(write_png_rgba(png, texel, 1, 1), XRSC_OK);
    const char *base = strrchr(png, '/');
    char extra[1024];
    snprintf(extra, sizeof extra,
             "\"extensionsUsed\": [\"KHR_texture_basisu\"],"
             " \"images\": [{\"uri\": \"%s\"}, {\"uri\": \"not-here.ktx2\"}],"
             " \"textures\": [{\"source\": 0, \"extensions\": {\"KHR_texture_basisu\":"
             " {\"source\": 1}}}],"
             " \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}],",
             base ? base + 1 : png);
    g = sct_triangle_gltf(NULL, 4, extra, 0, 1, 2, 3);
    sc_scene *s = load_text("basisu-optional.gltf", g, XRSC_OK, &d);
    free(g);
    if (!s) return;
    CHECK(sc_scene_warned(s, XRSC_WARN_GLTF_EXTENSION_IGNORED));
    CHECK(!sc_scene_warned(s, XRSC_WARN_GLTF_IMAGE_MISSING)); /* the KTX2 is not used */
    CHECK(s->materials[0].base_color_tex != SC_NO_TEXTURE);
    if (s->texture_count == 1) CHECK_EQ_INT(s->textures[0].rgba8[0], 200);
    sc_scene_destroy(&s);
}

static void test_bad_files(void)
{
    xrsc_diag d;
    const char *obj = "# Blender v2.93 OBJ File\nmtllib cube.mtl\no Cube\nv 1.0 1.0 -1.0\n";
    CHECK_EQ_INT(load_bytes("cube.gltf", obj, strlen(obj), &d), XRSC_ERROR_GLTF_NOT_GLTF);
    CHECK(strstr(d.message, "OBJ") != NULL);
    CHECK_EQ_INT(load_bytes("cube.obj", obj, strlen(obj), &d), XRSC_ERROR_GLTF_NOT_GLTF);
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 3\n";
    CHECK_EQ_INT(load_bytes("mesh.gltf", ply, strlen(ply), &d), XRSC_ERROR_GLTF_NOT_GLTF);
    static const uint8_t junk[8] = {0x00, 0x01, 0x02, 0xfe, 0x10, 0x20, 0x30, 0x40};
    CHECK_EQ_INT(load_bytes("junk.gltf", junk, sizeof junk, &d), XRSC_ERROR_GLTF_NOT_GLTF);

    /* glTF 1.0, as JSON and as a version-1 GLB. */
    const char *v1 = "{\"asset\": {\"version\": \"1.0\"},\n \"meshes\": {\"m\": {}}}";
    CHECK_EQ_INT(load_bytes("v1.gltf", v1, strlen(v1), &d), XRSC_ERROR_GLTF_VERSION);
    CHECK(strcmp(d.field, "asset.version") == 0);
    CHECK_EQ_INT(d.line, 1);
    const char *v1_noversion = "{\"meshes\": {\"m\": {}}, \"nodes\": {}}";
    CHECK_EQ_INT(load_bytes("v1b.gltf", v1_noversion, strlen(v1_noversion), &d),
                 XRSC_ERROR_GLTF_VERSION);

    char *g = sct_triangle_gltf(NULL, 4, "", 0, 1, 2, 3);
    size_t n;
    uint8_t *glb = make_glb(g, &n);
    free(g);
    CHECK_EQ_INT(load_bytes("good.glb", glb, n, &d), XRSC_OK); /* the control */
    glb[4] = 1;
    CHECK_EQ_INT(load_bytes("v1.glb", glb, n, &d), XRSC_ERROR_GLTF_VERSION);
    glb[4] = 2;
    /* Truncated: the header promises n bytes. */
    CHECK_EQ_INT(load_bytes("cut.glb", glb, n - 100, &d), XRSC_ERROR_GLB_TRUNCATED);
    CHECK(strcmp(d.field, "header.length") == 0);
    CHECK_EQ_INT(load_bytes("cut-header.glb", glb, 9, &d), XRSC_ERROR_GLB_TRUNCATED);
    /* Header length consistent, chunk longer than the file. */
    uint32_t total = (uint32_t)(n - 100);
    memcpy(glb + 8, &total, 4);
    CHECK_EQ_INT(load_bytes("cut-chunk.glb", glb, n - 100, &d), XRSC_ERROR_GLB_TRUNCATED);
    CHECK(strcmp(d.field, "JSON chunk") == 0);
    /* Wrong magic in a .glb. */
    total = (uint32_t)n;
    memcpy(glb + 8, &total, 4);
    memcpy(glb, "GLTF", 4);
    CHECK_EQ_INT(load_bytes("magic.glb", glb, n, &d), XRSC_ERROR_GLB_MAGIC);
    CHECK(strcmp(d.field, "header.magic") == 0);
    free(glb);
}

/** The meshopt twin's geometry: an n x n grid in z = 0 (positions on a 1/8 grid, so the
 *  exponential filter reproduces them exactly), normals +Z tilted, two triangles per cell. */
#define T_GRID 6
#define T_VERTS (T_GRID * T_GRID)
#define T_TRIS (2 * (T_GRID - 1) * (T_GRID - 1))

static void grid(float pos[T_VERTS][3], float nrm[T_VERTS][3], uint32_t idx[T_TRIS * 3])
{
    for (int y = 0, v = 0; y < T_GRID; y++)
        for (int x = 0; x < T_GRID; x++, v++) {
            pos[v][0] = x * 0.125f, pos[v][1] = y * 0.25f, pos[v][2] = (x * y % 3) * 0.125f;
            float l = sqrtf(0.04f * x * x + 1.0f);
            nrm[v][0] = 0.2f * x / l, nrm[v][1] = 0.0f, nrm[v][2] = 1.0f / l;
        }
    int t = 0;
    for (int y = 0; y + 1 < T_GRID; y++)
        for (int x = 0; x + 1 < T_GRID; x++) {
            uint32_t a = (uint32_t)(y * T_GRID + x), b = a + 1, c = a + T_GRID, e = c + 1;
            uint32_t q[6] = {a, b, e, a, e, c};
            memcpy(idx + 6 * t++, q, sizeof q);
        }
}

static char *grid_json(const char *ext_used, const char *views, const char *buffers,
                       const char *pos_ct, const char *nrm_acc)
{
    char *j = malloc(1 << 16);
    snprintf(j, 1 << 16,
             "{\"asset\": {\"version\": \"2.0\"}, %s \"scenes\": [{\"nodes\": [0]}],"
             " \"nodes\": [{\"mesh\": 0}],"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"NORMAL\": 1},"
             " \"indices\": 2}]}],"
             " \"accessors\": [{\"bufferView\": 0, %s, \"count\": %d, \"type\": \"VEC3\"},"
             " {\"bufferView\": 1, %s, \"count\": %d, \"type\": \"VEC3\"},"
             " {\"bufferView\": 2, \"componentType\": 5125, \"count\": %d, \"type\": \"SCALAR\"}],"
             " \"bufferViews\": [%s], \"buffers\": [%s]}",
             ext_used, pos_ct, T_VERTS, nrm_acc, T_VERTS, T_TRIS * 3, views, buffers);
    return j;
}

/** A triangle's indices rotated so that the smallest comes first (same winding). */
static void canonical_triangle(const uint32_t *in, uint32_t out[3])
{
    int k = in[1] < in[0] && in[1] <= in[2] ? 1 : in[2] < in[0] && in[2] < in[1] ? 2 : 0;
    for (int i = 0; i < 3; i++) out[i] = in[(k + i) % 3];
}

static void test_meshopt_twin(void)
{
#ifndef XRSC_HAVE_MESHOPT
    printf("  skipped: built without libmeshoptimizer\n");
#else
    float pos[T_VERTS][3], nrm[T_VERTS][3];
    uint32_t idx[T_TRIS * 3];
    grid(pos, nrm, idx);
    /* The plain twin. */
    uint8_t plain[sizeof pos + sizeof nrm + sizeof idx];
    memcpy(plain, pos, sizeof pos);
    memcpy(plain + sizeof pos, nrm, sizeof nrm);
    memcpy(plain + sizeof pos + sizeof nrm, idx, sizeof idx);
    char *uri = t_data_uri(plain, sizeof plain), views[1024], *buffers = malloc(strlen(uri) + 64);
    snprintf(views, sizeof views,
             "{\"buffer\": 0, \"byteLength\": %zu, \"byteStride\": 12},"
             " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu, \"byteStride\": 12},"
             " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu}",
             sizeof pos, sizeof pos, sizeof nrm, sizeof pos + sizeof nrm, sizeof idx);
    sprintf(buffers, "{\"byteLength\": %zu, \"uri\": \"%s\"}", sizeof plain, uri);
    free(uri);
    char *json = grid_json("", views, buffers, "\"componentType\": 5126",
                           "\"componentType\": 5126");
    xrsc_diag d;
    sc_load_options o = {.keep_triangle_order = true};
    sc_scene *twin = NULL, *packed = NULL;
    CHECK_EQ_INT(sc_scene_load(t_temp_file("twin.gltf", json), &o, &twin, &d), XRSC_OK);
    free(json);
    free(buffers);

    /* The compressed file: positions with the exponential filter, normals octahedral (int8
     * x4, normalised), indices as a triangle stream; the fallback buffer has no uri. */
    uint32_t pos_exp[T_VERTS][3];
    int8_t nrm_oct[T_VERTS][4];
    meshopt_encodeFilterExp(pos_exp, T_VERTS, 12, 24, &pos[0][0]);
    float nrm4[T_VERTS][4];
    for (int v = 0; v < T_VERTS; v++)
        nrm4[v][0] = nrm[v][0], nrm4[v][1] = nrm[v][1], nrm4[v][2] = nrm[v][2], nrm4[v][3] = 0;
    meshopt_encodeFilterOct(nrm_oct, T_VERTS, 4, 8, &nrm4[0][0]);
    size_t cap = meshopt_encodeVertexBufferBound(T_VERTS, 12) +
                 meshopt_encodeVertexBufferBound(T_VERTS, 4) +
                 meshopt_encodeIndexBufferBound(T_TRIS * 3, T_VERTS) + 16;
    uint8_t *enc = malloc(cap);
    size_t n0 = meshopt_encodeVertexBuffer(enc, cap, pos_exp, T_VERTS, 12);
    size_t p1 = (n0 + 3) & ~(size_t)3;
    size_t n1 = meshopt_encodeVertexBuffer(enc + p1, cap - p1, nrm_oct, T_VERTS, 4);
    size_t p2 = (p1 + n1 + 3) & ~(size_t)3;
    size_t n2 = meshopt_encodeIndexBuffer(enc + p2, cap - p2, idx, T_TRIS * 3);
    size_t total = (p2 + n2 + 3) & ~(size_t)3;
    CHECK(n0 > 0 && n1 > 0 && n2 > 0);
    uri = t_data_uri(enc, total);
    buffers = malloc(strlen(uri) + 256);
    sprintf(buffers,
            "{\"byteLength\": %zu, \"uri\": \"%s\"}, {\"byteLength\": %zu, \"extensions\":"
            " {\"EXT_meshopt_compression\": {\"fallback\": true}}}",
            total, uri, sizeof plain);
    free(uri);
    const char *mx = "\"extensions\": {\"EXT_meshopt_compression\": {\"buffer\": 0,";
    snprintf(views, sizeof views,
             "{\"buffer\": 1, \"byteLength\": %zu, \"byteStride\": 12, %s \"byteOffset\": 0,"
             " \"byteLength\": %zu, \"byteStride\": 12, \"count\": %d, \"mode\": \"ATTRIBUTES\","
             " \"filter\": \"EXPONENTIAL\"}}},"
             " {\"buffer\": 1, \"byteOffset\": %zu, \"byteLength\": %d, \"byteStride\": 4, %s"
             " \"byteOffset\": %zu, \"byteLength\": %zu, \"byteStride\": 4, \"count\": %d,"
             " \"mode\": \"ATTRIBUTES\", \"filter\": \"OCTAHEDRAL\"}}},"
             " {\"buffer\": 1, \"byteOffset\": %zu, \"byteLength\": %zu, %s \"byteOffset\": %zu,"
             " \"byteLength\": %zu, \"byteStride\": 4, \"count\": %d, \"mode\": \"TRIANGLES\"}}}",
             sizeof pos, mx, n0, T_VERTS, sizeof pos, T_VERTS * 4, mx, p1, n1, T_VERTS,
             sizeof pos + T_VERTS * 4, sizeof idx, mx, p2, n2, T_TRIS * 3);
    json = grid_json("\"extensionsUsed\": [\"EXT_meshopt_compression\"],"
                     " \"extensionsRequired\": [\"EXT_meshopt_compression\"],",
                     views, buffers, "\"componentType\": 5126",
                     "\"componentType\": 5120, \"normalized\": true");
    /* NORMAL as VEC3 of normalised bytes with stride 4 (the octahedral filter's layout). */
    CHECK_EQ_INT(sc_scene_load(t_temp_file("packed.gltf", json), &o, &packed, &d), XRSC_OK);
    char buf[1024];
    if (!packed) fprintf(stderr, "%s\n", xrsc_diag_format(&d, buf, sizeof buf));
    free(json);
    free(buffers);
    /* The same as a GLB (gltfpack's layout): the compressed bytes in the BIN chunk, buffer 1
     * the fallback without data (xrsc rewrites the JSON chunk for tinygltf). */
    char glb_buffers[256];
    snprintf(glb_buffers, sizeof glb_buffers,
             "{\"byteLength\": %zu}, {\"byteLength\": %zu, \"extensions\":"
             " {\"EXT_meshopt_compression\": {\"fallback\": true}}}",
             total, sizeof plain);
    json = grid_json("\"extensionsUsed\": [\"EXT_meshopt_compression\"],"
                     " \"extensionsRequired\": [\"EXT_meshopt_compression\"],",
                     views, glb_buffers, "\"componentType\": 5126",
                     "\"componentType\": 5120, \"normalized\": true");
    size_t jn = strlen(json), jp = (jn + 3) & ~(size_t)3, glb_size = 28 + jp + total;
    uint8_t *glb = calloc(1, glb_size);
    uint32_t hdr[5] = {0x46546C67u, 2, (uint32_t)glb_size, (uint32_t)jp, 0x4E4F534Au};
    memcpy(glb, hdr, 20);
    memset(glb + 20, ' ', jp);
    memcpy(glb + 20, json, jn);
    uint32_t bin_hdr[2] = {(uint32_t)total, 0x004E4942u};
    memcpy(glb + 20 + jp, bin_hdr, 8);
    memcpy(glb + 28 + jp, enc, total);
    sc_scene *packed_glb = NULL;
    CHECK_EQ_INT(sc_scene_load_memory("packed.glb", glb, glb_size, NULL, &o, &packed_glb, &d),
                 XRSC_OK);
    if (packed && packed_glb) {
        CHECK_EQ_INT(packed_glb->index_count, packed->index_count);
        CHECK(packed_glb->vertex_count == packed->vertex_count &&
              !memcmp(packed_glb->vertices, packed->vertices,
                      packed->vertex_count * sizeof(sc_vertex)));
    }
    sc_scene_destroy(&packed_glb);
    free(glb);
    free(json);
    free(enc);
    if (twin && packed) {
        CHECK_EQ_INT(packed->vertex_count, twin->vertex_count);
        CHECK_EQ_INT(packed->index_count, twin->index_count);
        CHECK_EQ_INT(packed->triangle_count, T_TRIS);
        /* The index codec may rotate a triangle's corners (winding kept): compare each
         * triangle with its smallest index first. */
        bool same_idx = packed->index_count == twin->index_count;
        for (uint32_t t = 0; same_idx && t < twin->index_count / 3; t++) {
            uint32_t a[3], b[3];
            canonical_triangle(twin->indices + 3 * t, a);
            canonical_triangle(packed->indices + 3 * t, b);
            same_idx = !memcmp(a, b, sizeof a);
        }
        CHECK(same_idx);
        double max_pos = 0.0, max_nrm = 0.0;
        for (uint32_t v = 0; v < twin->vertex_count && v < packed->vertex_count; v++)
            for (int c = 0; c < 3; c++) {
                max_pos = fmax(max_pos, fabs(packed->vertices[v].position[c] -
                                             twin->vertices[v].position[c]));
                max_nrm = fmax(max_nrm, fabs(packed->vertices[v].normal[c] -
                                             twin->vertices[v].normal[c]));
            }
        printf("  meshopt twin: %u triangles, max position difference %g, normal %g\n",
               (unsigned)packed->triangle_count, max_pos, max_nrm);
        CHECK(max_pos == 0.0);
        CHECK(max_nrm < 0.02); /* 8-bit octahedral normals */
    }
    sc_scene_destroy(&twin);
    sc_scene_destroy(&packed);
#endif
}

/** The one-triangle file of sc_test_util.h with a second buffer (uri1), more accessors and
 *  views (appended after the triangle's two), a node extension and extensionsUsed. */
static char *triangle_plus(const char *ext_used, const char *node_ext, const char *view0_ext,
                           const char *more_accessors, const char *more_views, size_t len1,
                           const char *uri1)
{
    uint8_t tri[44];
    sct_triangle_bytes(tri, 0, 1, 2);
    char *uri0 = t_data_uri(tri, sizeof tri);
    size_t cap = strlen(uri0) + strlen(uri1) + 8192;
    char *j = malloc(cap);
    snprintf(j, cap,
             "{\"asset\": {\"version\": \"2.0\"}, %s \"scenes\": [{\"nodes\": [0]}],"
             " \"nodes\": [{\"mesh\": 0 %s}],"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3,"
             " \"type\": \"VEC3\"}, {\"bufferView\": 1, \"componentType\": 5123, \"count\": 3,"
             " \"type\": \"SCALAR\"} %s],"
             " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36 %s},"
             " {\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 6} %s],"
             " \"buffers\": [{\"byteLength\": 44, \"uri\": \"%s\"},"
             " {\"byteLength\": %zu, \"uri\": \"%s\"}]}",
             ext_used, node_ext, more_accessors, view0_ext, more_views, uri0, len1, uri1);
    free(uri0);
    return j;
}

static void test_meshopt_corrupt(void)
{
#ifdef XRSC_HAVE_MESHOPT
    /* A view whose compressed bytes are garbage: a named error, not a crash. */
    static const uint8_t junk[16] = {0xa0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    char *uri = t_data_uri(junk, sizeof junk);
    char *json = triangle_plus("\"extensionsUsed\": [\"EXT_meshopt_compression\"],", "",
                               ", \"byteStride\": 12, \"extensions\": {\"EXT_meshopt_compression\":"
                               " {\"buffer\": 1, \"byteLength\": 16, \"byteStride\": 12,"
                               " \"count\": 3, \"mode\": \"ATTRIBUTES\"}}",
                               "", "", sizeof junk, uri);
    xrsc_diag d;
    load_text("meshopt-junk.gltf", json, XRSC_ERROR_GLTF_INVALID, &d);
    CHECK(strcmp(d.field, "bufferViews[0].extensions.EXT_meshopt_compression") == 0);
    free(uri);
    free(json);
#endif
}

static void test_instancing(void)
{
    /* Three instances of the triangle: translations along x, the 2nd rotated, the 3rd scaled. */
    const float inst[3 * 3 + 3 * 4 + 3 * 3] = {
        -2, 0, 0, 0, 1, 0, 5, 0, 0,                             /* TRANSLATION */
        0, 0, 0, 1, 0, 0, 0.70710678f, 0.70710678f, 0, 0, 0, 1, /* ROTATION */
        1, 1, 1, 1, 1, 1, 2, 2, 2};                             /* SCALE */
    char *uri = t_data_uri(inst, sizeof inst);
    char *json = triangle_plus(
        "\"extensionsUsed\": [\"EXT_mesh_gpu_instancing\"],",
        ", \"extensions\": {\"EXT_mesh_gpu_instancing\": {\"attributes\":"
        " {\"TRANSLATION\": 2, \"ROTATION\": 3, \"SCALE\": 4}}}",
        "",
        ", {\"bufferView\": 2, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"},"
        " {\"bufferView\": 3, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC4\"},"
        " {\"bufferView\": 4, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\"}",
        ", {\"buffer\": 1, \"byteLength\": 36}, {\"buffer\": 1, \"byteOffset\": 36,"
        " \"byteLength\": 48}, {\"buffer\": 1, \"byteOffset\": 84, \"byteLength\": 36}",
        sizeof inst, uri);
    free(uri);
    xrsc_diag d;
    sc_scene *s = load_text("instanced.gltf", json, XRSC_OK, &d);
    free(json);
    if (s) {
        CHECK_EQ_INT(s->instance_count, 3);
        CHECK_EQ_INT(s->triangle_count, 3);
        CHECK(!sc_scene_warned(s, XRSC_WARN_GLTF_EXTENSION_IGNORED));
        if (s->instance_count == 3) {
            const float *w0 = s->instances[0].world, *w1 = s->instances[1].world,
                        *w2 = s->instances[2].world;
            CHECK_NEAR(w0[12], -2.0, 1e-6);
            CHECK_NEAR(w1[13], 1.0, 1e-6);
            CHECK_NEAR(w1[1], 1.0, 1e-6); /* x axis rotated 90 degrees about z onto +y */
            CHECK_NEAR(w2[12], 5.0, 1e-6);
            CHECK_NEAR(w2[0], 2.0, 1e-6);
            CHECK_NEAR(s->bounds_max[0], 7.0, 1e-5); /* 5 + 2 x the triangle's width */
        }
        sc_scene_destroy(&s);
    }

    /* The Khronos sample: a 5 x 5 x 5 grid of cubes. */
    const char *path =
        t_shared_path("scenes/khronos/SimpleInstancing/glTF-Binary/SimpleInstancing.glb");
    if (path) {
        CHECK_EQ_INT(sc_scene_load(path, NULL, &s, &d), XRSC_OK);
        if (s) {
            printf("  SimpleInstancing: %u instances, %llu triangles\n", s->instance_count,
                   (unsigned long long)s->triangle_count);
            CHECK_EQ_INT(s->instance_count, 125);
            CHECK_EQ_INT(s->triangle_count, 125 * 12);
        }
        sc_scene_destroy(&s);
    }
}

/** A material JSON with KHR_materials_pbrSpecularGlossiness. */
static sc_scene *load_spec_gloss(const char *name, const char *sg, const char *images)
{
    char extra[2048];
    snprintf(extra, sizeof extra,
             "\"extensionsUsed\": [\"KHR_materials_pbrSpecularGlossiness\"], %s"
             " \"materials\": [{\"extensions\": {\"KHR_materials_pbrSpecularGlossiness\": {%s}}}],",
             images, sg);
    char *g = sct_triangle_gltf(NULL, 4, extra, 0, 1, 2, 3);
    xrsc_diag d;
    sc_scene *s = load_text(name, g, XRSC_OK, &d);
    free(g);
    return s;
}

static void test_spec_gloss(void)
{
    /* A dielectric: specular 0.04 grey: metallic 0, base colour = diffuse (x (1 - 0.04)/0.96). */
    sc_scene *s = load_spec_gloss("sg-plastic.gltf",
                                  "\"diffuseFactor\": [0.5, 0.25, 0.1, 0.8], \"specularFactor\":"
                                  " [0.04, 0.04, 0.04], \"glossinessFactor\": 0.75",
                                  "");
    if (s) {
        const sc_material *m = &s->materials[0];
        CHECK(!sc_scene_warned(s, XRSC_WARN_GLTF_EXTENSION_IGNORED));
        CHECK_NEAR(m->metallic, 0.0, 1e-6);
        CHECK_NEAR(m->roughness, 0.25, 1e-6);
        CHECK_NEAR(m->base_color[0], 0.5, 1e-5);
        CHECK_NEAR(m->base_color[1], 0.25, 1e-5);
        CHECK_NEAR(m->base_color[3], 0.8, 1e-6);
        sc_scene_destroy(&s);
    }
    /* A metal: black diffuse, coloured specular: metallic 1, base colour = specular. */
    s = load_spec_gloss("sg-gold.gltf",
                        "\"diffuseFactor\": [0, 0, 0, 1], \"specularFactor\": [1.0, 0.8, 0.4],"
                        " \"glossinessFactor\": 1",
                        "");
    if (s) {
        const sc_material *m = &s->materials[0];
        CHECK_NEAR(m->metallic, 1.0, 1e-3);
        CHECK_NEAR(m->roughness, 0.0, 1e-6);
        CHECK_NEAR(m->base_color[0], 1.0, 1e-3);
        CHECK_NEAR(m->base_color[1], 0.8, 1e-3);
        CHECK_NEAR(m->base_color[2], 0.4, 1e-3);
        sc_scene_destroy(&s);
    }
    /* Textured, the two textures paired (same size and mapping): converted per texel.
     * Texel 0: a dielectric (dark specular), glossy: metal 0, rough 0, base ~ diffuse, alpha
     * kept. Texel 1: black diffuse, coloured specular, glossiness 128/255: metal 1, base =
     * specular (sRGB 255 204 102), rough 127. */
    static const uint8_t diffuse[8] = {128, 64, 32, 200, 0, 0, 0, 255};
    static const uint8_t sg[8] = {10, 10, 10, 255, 255, 204, 102, 128};
    static const uint8_t sg_small[4] = {10, 10, 10, 255};
    char names[3][256];
    const uint8_t *px[3] = {diffuse, sg, sg_small};
    for (int k = 0; k < 3; k++) {
        static const char *files[3] = {"sg-diffuse.png", "sg.png", "sg-small.png"};
        const char *png = t_temp_file(files[k], "");
        CHECK_EQ_INT(write_png_rgba(png, px[k], k == 2 ? 1 : 2, 1), XRSC_OK);
        const char *slash = strrchr(png, '/');
        snprintf(names[k], sizeof names[k], "%s", slash ? slash + 1 : png);
    }
    char images[1024];
    snprintf(images, sizeof images,
             "\"images\": [{\"uri\": \"%s\"}, {\"uri\": \"%s\"}, {\"uri\": \"%s\"}],"
             " \"textures\": [{\"source\": 0}, {\"source\": 1}, {\"source\": 2}],",
             names[0], names[1], names[2]);
    s = load_spec_gloss("sg-textured.gltf",
                        "\"diffuseTexture\": {\"index\": 0}, \"specularGlossinessTexture\":"
                        " {\"index\": 1}",
                        images);
    if (s) {
        const sc_material *m = &s->materials[0];
        CHECK_NEAR(m->metallic, 1.0, 0.0);
        CHECK_NEAR(m->roughness, 1.0, 0.0);
        CHECK_NEAR(m->base_color[0], 1.0, 0.0);
        CHECK(m->base_color_tex < s->texture_count && m->metal_rough_tex < s->texture_count);
        if (m->metal_rough_tex < s->texture_count && m->base_color_tex < s->texture_count) {
            const uint8_t *mr = s->textures[m->metal_rough_tex].rgba8;
            const uint8_t *bc = s->textures[m->base_color_tex].rgba8;
            CHECK(!s->textures[m->metal_rough_tex].srgb && s->textures[m->base_color_tex].srgb);
            printf("  per texel: base %u %u %u %u | %u %u %u; rough/metal %u %u | %u %u\n", bc[0],
                   bc[1], bc[2], bc[3], bc[4], bc[5], bc[6], mr[1], mr[2], mr[5], mr[6]);
            CHECK(mr[1] == 0 && mr[2] == 0);
            CHECK(abs(mr[5] - 127) <= 1 && mr[6] == 255);
            CHECK(bc[0] >= 128 && bc[0] <= 134 && bc[3] == 200);
            CHECK(abs(bc[4] - 255) <= 1 && abs(bc[5] - 204) <= 1 && abs(bc[6] - 102) <= 1);
        }
        sc_scene_destroy(&s);
    }
    /* Textures that do not pair up (different sizes): the factors converted, the diffuse
     * texture used as it is, the spec-gloss texture converted alone. */
    s = load_spec_gloss("sg-unpaired.gltf",
                        "\"diffuseTexture\": {\"index\": 0}, \"specularGlossinessTexture\":"
                        " {\"index\": 2}",
                        images);
    if (s) {
        const sc_material *m = &s->materials[0];
        if (m->metal_rough_tex < s->texture_count && m->base_color_tex < s->texture_count) {
            const uint8_t *bc = s->textures[m->base_color_tex].rgba8;
            const uint8_t *mr = s->textures[m->metal_rough_tex].rgba8;
            CHECK(bc[0] == 128 && bc[4] == 0); /* the diffuse texels unchanged */
            CHECK(mr[1] == 0 && mr[2] == 0);
            CHECK_NEAR(m->metallic, 1.0, 0.0);
        } else {
            CHECK(false);
        }
        sc_scene_destroy(&s);
    }
}

static void test_sampler_modes(void)
{
    const char *png = t_temp_file("sampler.png", "");
    static const uint8_t texel[4] = {255, 255, 255, 255};
    xrsc_diag d;
    CHECK_EQ_INT(write_png_rgba(png, texel, 1, 1), XRSC_OK);
    const char *base = strrchr(png, '/');
    char extra[1024];
    snprintf(extra, sizeof extra,
             "\"images\": [{\"uri\": \"%s\"}],"
             " \"samplers\": [{\"wrapS\": 33071, \"wrapT\": 33648, \"magFilter\": 9728,"
             " \"minFilter\": 9986}, {}],"
             " \"textures\": [{\"source\": 0, \"sampler\": 0}, {\"source\": 0, \"sampler\": 1}],"
             " \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0},"
             " \"metallicRoughnessTexture\": {\"index\": 1}}}],",
             base ? base + 1 : png);
    char *g = sct_triangle_gltf(NULL, 4, extra, 0, 1, 2, 3);
    sc_scene *s = load_text("sampler.gltf", g, XRSC_OK, &d);
    free(g);
    if (!s) return;
    const sc_material *m = &s->materials[0];
    if (m->base_color_tex < s->texture_count && m->metal_rough_tex < s->texture_count) {
        sc_sampler a = s->textures[m->base_color_tex].sampler;
        sc_sampler b = s->textures[m->metal_rough_tex].sampler;
        CHECK_EQ_INT(a.wrap_u, SC_WRAP_CLAMP_TO_EDGE);
        CHECK_EQ_INT(a.wrap_v, SC_WRAP_MIRRORED_REPEAT);
        CHECK(a.mag_nearest && a.min_nearest);
        CHECK_EQ_INT(b.wrap_u, SC_WRAP_REPEAT);
        CHECK_EQ_INT(b.wrap_v, SC_WRAP_REPEAT);
        CHECK(!b.mag_nearest && !b.min_nearest);
    } else {
        CHECK(false);
    }
    sc_scene_destroy(&s);
}

int main(void)
{
    RUN(test_missing_image_stand_in);
    RUN(test_undecodable_image);
    RUN(test_lines_skipped);
    RUN(test_optional_extensions_warn_each);
    RUN(test_basisu);
    RUN(test_bad_files);
    RUN(test_meshopt_twin);
    RUN(test_meshopt_corrupt);
    RUN(test_instancing);
    RUN(test_spec_gloss);
    RUN(test_sampler_modes);
    return t_finish();
}
