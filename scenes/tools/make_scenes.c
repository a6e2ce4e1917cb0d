// SPDX-License-Identifier: MIT
/**
 * @file make_scenes.c
 * @brief Writes the project's own test scenes (scenes/NAME.gltf, binary data embedded as base64).
 *
 * Usage: xrsc_make_scenes <output folder>   (normally the repository's scenes/ folder).
 * The generated files are committed; this program is not run at build time. Each scene
 * models only what its test needs (see scenes/README.md). Units are metres, +Y up, -Z forward.
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI_F 3.14159265358979f

/** A growable string. */
typedef struct str {
    char *s;
    size_t len, cap;
} str;

static void str_vadd(str *b, const char *fmt, va_list ap)
{
    va_list ap2;
    va_copy(ap2, ap);
    int n = vsnprintf(NULL, 0, fmt, ap2);
    va_end(ap2);
    if (n < 0) abort();
    if (b->len + (size_t)n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 256;
        while (cap < b->len + (size_t)n + 1) cap *= 2;
        b->s = realloc(b->s, cap);
        if (!b->s) abort();
        b->cap = cap;
    }
    vsnprintf(b->s + b->len, (size_t)n + 1, fmt, ap);
    b->len += (size_t)n;
}

static void str_add(str *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    str_vadd(b, fmt, ap);
    va_end(ap);
}

/** One glTF file being assembled: a binary blob and the JSON arrays as text. */
typedef struct gltf {
    uint8_t *bin;
    size_t bin_len, bin_cap;
    str views, accessors, meshes, materials, nodes, cameras;
    int n_views, n_accessors, n_meshes, n_materials, n_nodes, n_cameras;
    const char *extensions; /**< top-level "extensions" object body, or NULL (none) */
} gltf;

static void sep(str *s, int count) { str_add(s, count ? ",\n    " : "\n    "); }

static int add_view(gltf *g, const void *data, size_t bytes, int target)
{
    size_t off = (g->bin_len + 3) & ~(size_t)3; /* 4-byte alignment (glTF §3.6.2.4) */
    if (off + bytes > g->bin_cap) {
        size_t cap = g->bin_cap ? g->bin_cap : 4096;
        while (cap < off + bytes) cap *= 2;
        g->bin = realloc(g->bin, cap);
        if (!g->bin) abort();
        g->bin_cap = cap;
    }
    memset(g->bin + g->bin_len, 0, off - g->bin_len);
    memcpy(g->bin + off, data, bytes);
    g->bin_len = off + bytes;
    sep(&g->views, g->n_views);
    str_add(&g->views, "{\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu, \"target\": %d}",
            off, bytes, target);
    return g->n_views++;
}

/** Float VECn accessor with min/max. */
static int add_float_accessor(gltf *g, const float *v, int count, int n, const char *type)
{
    int view = add_view(g, v, sizeof(float) * (size_t)count * (size_t)n, 34962);
    float lo[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    float hi[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < count; i++)
        for (int c = 0; c < n; c++) {
            lo[c] = fminf(lo[c], v[i * n + c]);
            hi[c] = fmaxf(hi[c], v[i * n + c]);
        }
    sep(&g->accessors, g->n_accessors);
    str_add(&g->accessors,
            "{\"bufferView\": %d, \"componentType\": 5126, \"count\": %d, \"type\": \"%s\", "
            "\"min\": [",
            view, count, type);
    for (int c = 0; c < n; c++) str_add(&g->accessors, "%s%.9g", c ? ", " : "", lo[c]);
    str_add(&g->accessors, "], \"max\": [");
    for (int c = 0; c < n; c++) str_add(&g->accessors, "%s%.9g", c ? ", " : "", hi[c]);
    str_add(&g->accessors, "]}");
    return g->n_accessors++;
}

/** Index accessor with componentType 5121 (u8), 5123 (u16) or 5125 (u32). */
static int add_index_accessor(gltf *g, const uint32_t *idx, int count, int component_type)
{
    size_t cs = component_type == 5121 ? 1 : component_type == 5123 ? 2 : 4;
    uint8_t *packed = malloc(cs * (size_t)count);
    if (!packed) abort();
    for (int i = 0; i < count; i++) {
        uint32_t v = idx[i];
        memcpy(packed + cs * (size_t)i, &v, cs); /* little-endian host */
    }
    int view = add_view(g, packed, cs * (size_t)count, 34963);
    free(packed);
    sep(&g->accessors, g->n_accessors);
    str_add(&g->accessors,
            "{\"bufferView\": %d, \"componentType\": %d, \"count\": %d, \"type\": \"SCALAR\"}",
            view, component_type, count);
    return g->n_accessors++;
}

/** Vertex data of one triangle mesh (normals and uvs optional). */
typedef struct geom {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    int nv, ni;
} geom;

static void geom_free(geom *m)
{
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

/** Accessor indices of a geometry, to share between meshes. */
typedef struct geom_acc {
    int pos, nrm, uv, idx;
} geom_acc;

static geom_acc add_geom(gltf *g, const geom *m, int index_type)
{
    geom_acc a = {-1, -1, -1, -1};
    a.pos = add_float_accessor(g, m->pos, m->nv, 3, "VEC3");
    if (m->nrm) a.nrm = add_float_accessor(g, m->nrm, m->nv, 3, "VEC3");
    if (m->uv) a.uv = add_float_accessor(g, m->uv, m->nv, 2, "VEC2");
    if (m->idx) a.idx = add_index_accessor(g, m->idx, m->ni, index_type);
    return a;
}

static int add_mesh(gltf *g, const char *name, geom_acc a, int material)
{
    sep(&g->meshes, g->n_meshes);
    str_add(&g->meshes, "{\"name\": \"%s\", \"primitives\": [{\"attributes\": {\"POSITION\": %d",
            name, a.pos);
    if (a.nrm >= 0) str_add(&g->meshes, ", \"NORMAL\": %d", a.nrm);
    if (a.uv >= 0) str_add(&g->meshes, ", \"TEXCOORD_0\": %d", a.uv);
    str_add(&g->meshes, "}");
    if (a.idx >= 0) str_add(&g->meshes, ", \"indices\": %d", a.idx);
    str_add(&g->meshes, ", \"material\": %d}]}", material);
    return g->n_meshes++;
}

/** Adds a material from a JSON object body (without braces). */
static int add_material(gltf *g, const char *body)
{
    sep(&g->materials, g->n_materials);
    str_add(&g->materials, "{%s}", body);
    return g->n_materials++;
}

/** Adds a node from a JSON object body (without braces), printf-style. */
static int add_node(gltf *g, const char *fmt, ...)
{
    sep(&g->nodes, g->n_nodes);
    va_list ap;
    va_start(ap, fmt);
    str_add(&g->nodes, "{");
    str_vadd(&g->nodes, fmt, ap);
    str_add(&g->nodes, "}");
    va_end(ap);
    return g->n_nodes++;
}

static int add_camera(gltf *g, float yfov, float znear)
{
    sep(&g->cameras, g->n_cameras);
    str_add(&g->cameras,
            "{\"type\": \"perspective\", \"perspective\": {\"yfov\": %.9g, \"znear\": %.9g}}", yfov,
            znear);
    return g->n_cameras++;
}

static void base64(str *out, const uint8_t *p, size_t n)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16;
        if (i + 1 < n) v |= (uint32_t)p[i + 1] << 8;
        if (i + 2 < n) v |= p[i + 2];
        char q[5] = {tab[v >> 18 & 63], tab[v >> 12 & 63], i + 1 < n ? tab[v >> 6 & 63] : '=',
                     i + 2 < n ? tab[v & 63] : '=', 0};
        str_add(out, "%s", q);
    }
}

/** Writes the file. extensions_used is the extensionsUsed list body (may be ""); scene_body goes
 *  into the one scene object. */
static int write_gltf(gltf *g, const char *path, const char *extensions_used, const char *scene_body)
{
    str j = {0};
    str_add(&j, "{\n  \"asset\": {\"version\": \"2.0\", \"generator\": \"xrsc make_scenes.c\"},\n");
    if (extensions_used && *extensions_used)
        str_add(&j, "  \"extensionsUsed\": [%s],\n", extensions_used);
    str_add(&j, "  \"scene\": 0,\n  \"scenes\": [{%s}],\n", scene_body);
    str_add(&j, "  \"nodes\": [%s\n  ],\n", g->nodes.s);
    if (g->n_cameras) str_add(&j, "  \"cameras\": [%s\n  ],\n", g->cameras.s);
    if (g->extensions) str_add(&j, "  \"extensions\": {%s},\n", g->extensions);
    str_add(&j, "  \"meshes\": [%s\n  ],\n", g->meshes.s);
    str_add(&j, "  \"materials\": [%s\n  ],\n", g->materials.s);
    str_add(&j, "  \"accessors\": [%s\n  ],\n", g->accessors.s);
    str_add(&j, "  \"bufferViews\": [%s\n  ],\n", g->views.s);
    str_add(&j, "  \"buffers\": [{\"byteLength\": %zu, \"uri\": \"data:application/octet-stream;base64,",
            g->bin_len);
    base64(&j, g->bin, g->bin_len);
    str_add(&j, "\"}]\n}\n");
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(j.s, 1, j.len, f) != j.len || fclose(f) != 0) {
        fprintf(stderr, "make_scenes: cannot write %s\n", path);
        free(j.s);
        return 1;
    }
    printf("wrote %s (%zu bytes)\n", path, j.len);
    free(j.s);
    free(g->bin);
    free(g->views.s);
    free(g->accessors.s);
    free(g->meshes.s);
    free(g->materials.s);
    free(g->nodes.s);
    free(g->cameras.s);
    memset(g, 0, sizeof *g);
    return 0;
}

/** UV sphere of radius 1 at the origin: seg longitudes, rings latitudes, no degenerate
 *  triangles at the poles. */
static geom make_sphere(int seg, int rings)
{
    geom m = {0};
    m.nv = (seg + 1) * (rings + 1);
    m.pos = malloc(sizeof(float) * 3 * (size_t)m.nv);
    m.nrm = malloc(sizeof(float) * 3 * (size_t)m.nv);
    m.uv = malloc(sizeof(float) * 2 * (size_t)m.nv);
    m.idx = malloc(sizeof(uint32_t) * 6 * (size_t)seg * (size_t)rings);
    if (!m.pos || !m.nrm || !m.uv || !m.idx) abort();
    for (int j = 0; j <= rings; j++) {
        float theta = PI_F * (float)j / (float)rings; /* from +Y down */
        for (int i = 0; i <= seg; i++) {
            float phi = 2.0f * PI_F * (float)i / (float)seg;
            int v = j * (seg + 1) + i;
            float p[3] = {sinf(theta) * sinf(phi), cosf(theta), sinf(theta) * cosf(phi)};
            if (j == 0 || j == rings) p[0] = p[2] = 0.0f;
            memcpy(&m.pos[3 * v], p, sizeof p);
            memcpy(&m.nrm[3 * v], p, sizeof p);
            m.uv[2 * v] = (float)i / (float)seg;
            m.uv[2 * v + 1] = (float)j / (float)rings;
        }
    }
    for (int j = 0; j < rings; j++)
        for (int i = 0; i < seg; i++) {
            uint32_t a = (uint32_t)(j * (seg + 1) + i), b = a + 1;
            uint32_t c = a + (uint32_t)(seg + 1), d = c + 1;
            /* counter-clockwise seen from outside */
            if (j != 0) {
                m.idx[m.ni++] = a;
                m.idx[m.ni++] = c;
                m.idx[m.ni++] = b;
            }
            if (j != rings - 1) {
                m.idx[m.ni++] = b;
                m.idx[m.ni++] = c;
                m.idx[m.ni++] = d;
            }
        }
    return m;
}

/** Appends an axis-aligned quad (4 vertices, 2 triangles, counter-clockwise seen from the
 *  side its normal points to) with corners o, o+u, o+u+v, o+v. */
static void quad(geom *m, const float o[3], const float u[3], const float v[3])
{
    int base = m->nv;
    m->pos = realloc(m->pos, sizeof(float) * 3 * (size_t)(m->nv + 4));
    m->nrm = realloc(m->nrm, sizeof(float) * 3 * (size_t)(m->nv + 4));
    m->uv = realloc(m->uv, sizeof(float) * 2 * (size_t)(m->nv + 4));
    m->idx = realloc(m->idx, sizeof(uint32_t) * (size_t)(m->ni + 6));
    if (!m->pos || !m->nrm || !m->uv || !m->idx) abort();
    float n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int c = 0; c < 3; c++) n[c] /= len;
    static const float st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; k++) {
        for (int c = 0; c < 3; c++) {
            m->pos[3 * (base + k) + c] = o[c] + st[k][0] * u[c] + st[k][1] * v[c];
            m->nrm[3 * (base + k) + c] = n[c];
        }
        m->uv[2 * (base + k)] = st[k][0];
        m->uv[2 * (base + k) + 1] = st[k][1];
    }
    static const uint32_t t[6] = {0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 6; k++) m->idx[m->ni + k] = (uint32_t)base + t[k];
    m->nv += 4;
    m->ni += 6;
}

/* ------------------------------------------------------------------------------------------ */

/** White furnace: a diffuse sphere of albedo 0.5 under a uniform environment of 1. A convex
 *  sphere never sees itself, so every reflected ray escapes and a correct path tracer shows
 *  the sphere at exactly rho * L = 0.5 for any bounce limit >= 1. IOR 1 removes glTF's
 *  dielectric specular layer (F0 = 0.04 at IOR 1.5), leaving a pure Lambertian. */
static int make_furnace(const char *dir)
{
    gltf g = {0};
    geom s = make_sphere(64, 32);
    geom_acc a = add_geom(&g, &s, 5123);
    geom_free(&s);
    int mat = add_material(&g, "\"name\": \"albedo-0.5\", \"pbrMetallicRoughness\": "
                               "{\"baseColorFactor\": [0.5, 0.5, 0.5, 1], \"metallicFactor\": 0, "
                               "\"roughnessFactor\": 1}, "
                               "\"extensions\": {\"KHR_materials_ior\": {\"ior\": 1.0}}");
    int mesh = add_mesh(&g, "sphere", a, mat);
    int cam = add_camera(&g, 1.0f, 0.05f);
    add_node(&g, "\"name\": \"sphere\", \"mesh\": %d", mesh);
    add_node(&g, "\"name\": \"camera\", \"camera\": %d, \"translation\": [0, 0, 3]", cam);
    char path[1024];
    snprintf(path, sizeof path, "%s/furnace.gltf", dir);
    return write_gltf(&g, path, "\"KHR_materials_ior\"",
                      "\"name\": \"furnace\", \"nodes\": [0, 1], "
                      "\"extras\": {\"xrsc_environment\": [1, 1, 1]}");
}

/** Cornell box, 2 m, open towards +Z, with an emissive ceiling panel, a metal and a glass
 *  sphere. */
static int make_cornell(const char *dir)
{
    gltf g = {0};
    int white = add_material(&g, "\"name\": \"white\", \"pbrMetallicRoughness\": "
                                 "{\"baseColorFactor\": [0.75, 0.75, 0.75, 1], "
                                 "\"metallicFactor\": 0, \"roughnessFactor\": 1}");
    int red = add_material(&g, "\"name\": \"red\", \"pbrMetallicRoughness\": "
                               "{\"baseColorFactor\": [0.63, 0.065, 0.05, 1], "
                               "\"metallicFactor\": 0, \"roughnessFactor\": 1}");
    int green = add_material(&g, "\"name\": \"green\", \"pbrMetallicRoughness\": "
                                 "{\"baseColorFactor\": [0.14, 0.45, 0.091, 1], "
                                 "\"metallicFactor\": 0, \"roughnessFactor\": 1}");
    int light = add_material(&g, "\"name\": \"light\", \"pbrMetallicRoughness\": "
                                 "{\"baseColorFactor\": [0.78, 0.78, 0.78, 1], "
                                 "\"metallicFactor\": 0, \"roughnessFactor\": 1}, "
                                 "\"emissiveFactor\": [1, 1, 1], \"extensions\": "
                                 "{\"KHR_materials_emissive_strength\": {\"emissiveStrength\": 15}}");
    int metal = add_material(&g, "\"name\": \"metal\", \"pbrMetallicRoughness\": "
                                 "{\"baseColorFactor\": [0.9, 0.9, 0.9, 1], "
                                 "\"metallicFactor\": 1, \"roughnessFactor\": 0.2}");
    int glass = add_material(&g, "\"name\": \"glass\", \"pbrMetallicRoughness\": "
                                 "{\"baseColorFactor\": [1, 1, 1, 1], \"metallicFactor\": 0, "
                                 "\"roughnessFactor\": 0}, \"extensions\": "
                                 "{\"KHR_materials_transmission\": {\"transmissionFactor\": 1}, "
                                 "\"KHR_materials_ior\": {\"ior\": 1.5}}");

    /* Box: x in [-1, 1], y in [0, 2], z in [-1, 1]; normals point into the box. */
    geom w = {0}, r = {0}, gr = {0}, l = {0};
    quad(&w, (float[]){-1, 0, 1}, (float[]){2, 0, 0}, (float[]){0, 0, -2});  /* floor, +Y */
    quad(&w, (float[]){-1, 2, -1}, (float[]){2, 0, 0}, (float[]){0, 0, 2});  /* ceiling, -Y */
    quad(&w, (float[]){-1, 0, -1}, (float[]){2, 0, 0}, (float[]){0, 2, 0});  /* back, +Z */
    quad(&r, (float[]){-1, 0, 1}, (float[]){0, 0, -2}, (float[]){0, 2, 0});  /* left, +X */
    quad(&gr, (float[]){1, 0, -1}, (float[]){0, 0, 2}, (float[]){0, 2, 0});  /* right, -X */
    /* Ceiling light 0.5 x 0.5 m, 1 cm below the ceiling, facing down. */
    quad(&l, (float[]){-0.25f, 1.99f, -0.25f}, (float[]){0.5f, 0, 0}, (float[]){0, 0, 0.5f});
    int m_white = add_mesh(&g, "walls-white", add_geom(&g, &w, 5123), white);
    int m_red = add_mesh(&g, "wall-red", add_geom(&g, &r, 5123), red);
    int m_green = add_mesh(&g, "wall-green", add_geom(&g, &gr, 5123), green);
    int m_light = add_mesh(&g, "light", add_geom(&g, &l, 5123), light);
    geom_free(&w);
    geom_free(&r);
    geom_free(&gr);
    geom_free(&l);
    /* One unit sphere geometry shared by two meshes with different materials. */
    geom s = make_sphere(48, 24);
    geom_acc sa = add_geom(&g, &s, 5123);
    geom_free(&s);
    int m_metal = add_mesh(&g, "sphere-metal", sa, metal);
    int m_glass = add_mesh(&g, "sphere-glass", sa, glass);
    int cam = add_camera(&g, 1.0f, 0.05f);

    add_node(&g, "\"name\": \"walls-white\", \"mesh\": %d", m_white);
    add_node(&g, "\"name\": \"wall-red\", \"mesh\": %d", m_red);
    add_node(&g, "\"name\": \"wall-green\", \"mesh\": %d", m_green);
    add_node(&g, "\"name\": \"light\", \"mesh\": %d", m_light);
    add_node(&g,
             "\"name\": \"sphere-metal\", \"mesh\": %d, \"translation\": [-0.45, 0.35, -0.35], "
             "\"scale\": [0.35, 0.35, 0.35]",
             m_metal);
    add_node(&g,
             "\"name\": \"sphere-glass\", \"mesh\": %d, \"translation\": [0.45, 0.35, 0.25], "
             "\"scale\": [0.35, 0.35, 0.35]",
             m_glass);
    add_node(&g, "\"name\": \"camera\", \"camera\": %d, \"translation\": [0, 1, 2.05]", cam);
    char path[1024];
    snprintf(path, sizeof path, "%s/cornell.gltf", dir);
    return write_gltf(&g, path,
                      "\"KHR_materials_emissive_strength\", \"KHR_materials_transmission\", "
                      "\"KHR_materials_ior\"",
                      "\"name\": \"cornell\", \"nodes\": [0, 1, 2, 3, 4, 5, 6], "
                      "\"extras\": {\"xrsc_environment\": [0, 0, 0]}");
}

/** A few triangles for the exact primary-hit test: three instances at different depths, one
 *  under a rotated, non-uniformly scaled, translated node, one double-sided triangle facing
 *  away from the camera. u8, u16 and no indices; one mesh without normals. */
static int make_triangles(const char *dir)
{
    gltf g = {0};
    int grey = add_material(&g, "\"name\": \"grey\", \"pbrMetallicRoughness\": "
                                "{\"baseColorFactor\": [0.5, 0.5, 0.5, 1], "
                                "\"metallicFactor\": 0, \"roughnessFactor\": 1}");
    int blue = add_material(&g, "\"name\": \"blue\", \"pbrMetallicRoughness\": "
                                "{\"baseColorFactor\": [0.1, 0.2, 0.8, 1], "
                                "\"metallicFactor\": 0, \"roughnessFactor\": 0.5}");
    int green = add_material(&g, "\"name\": \"green-double-sided\", \"doubleSided\": true, "
                                 "\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.1, 0.8, 0.1, 1], "
                                 "\"metallicFactor\": 0, \"roughnessFactor\": 1}");

    /* Back quad at z = -5 facing the camera, not indexed. */
    geom q = {0};
    quad(&q, (float[]){-2, -1.5f, -5}, (float[]){4, 0, 0}, (float[]){0, 3, 0});
    geom qn = {q.pos, q.nrm, q.uv, NULL, 6, 0};
    float pos6[18], nrm6[18], uv6[12];
    for (int k = 0; k < 6; k++) {
        memcpy(&pos6[3 * k], &q.pos[3 * q.idx[k]], 3 * sizeof(float));
        memcpy(&nrm6[3 * k], &q.nrm[3 * q.idx[k]], 3 * sizeof(float));
        memcpy(&uv6[2 * k], &q.uv[2 * q.idx[k]], 2 * sizeof(float));
    }
    qn.pos = pos6, qn.nrm = nrm6, qn.uv = uv6;
    int m_back = add_mesh(&g, "back-quad", add_geom(&g, &qn, 5123), grey);
    geom_free(&q);

    /* A small tetrahedron-like fan of 4 triangles around the local origin, u16 indices. */
    float tp[] = {0, 0.5f, 0, -0.5f, -0.4f, 0.3f, 0.5f, -0.4f, 0.3f, 0, -0.4f, -0.5f};
    float tn[12];
    for (int v = 0; v < 4; v++) {
        float len = sqrtf(tp[3 * v] * tp[3 * v] + tp[3 * v + 1] * tp[3 * v + 1] +
                          tp[3 * v + 2] * tp[3 * v + 2]);
        for (int c = 0; c < 3; c++) tn[3 * v + c] = tp[3 * v + c] / len;
    }
    uint32_t ti[] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    geom t = {tp, tn, NULL, ti, 4, 12};
    int m_tet = add_mesh(&g, "tetrahedron", add_geom(&g, &t, 5123), blue);

    /* One triangle whose front faces -Z (away from the camera), no normals, u8 indices. */
    float dp[] = {-1.2f, -0.8f, -2, -0.4f, -0.8f, -2, -0.8f, 0.0f, -2};
    uint32_t di[] = {0, 2, 1};
    geom d = {dp, NULL, NULL, di, 3, 3};
    int m_ds = add_mesh(&g, "double-sided-triangle", add_geom(&g, &d, 5121), green);
    int cam = add_camera(&g, 1.0f, 0.05f);

    add_node(&g, "\"name\": \"back\", \"mesh\": %d", m_back);
    /* rotation: 30 degrees about the unit axis (0.267, 0.891, 0.367) */
    float ax[3] = {0.3f, 1.0f, 0.2f}, al = sqrtf(0.09f + 1.0f + 0.04f), half = PI_F / 12.0f;
    add_node(&g,
             "\"name\": \"tetrahedron\", \"mesh\": %d, \"translation\": [0.8, 0.3, -3], "
             "\"rotation\": [%.9g, %.9g, %.9g, %.9g], \"scale\": [0.5, 1.2, 0.8]",
             m_tet, ax[0] / al * sinf(half), ax[1] / al * sinf(half), ax[2] / al * sinf(half),
             cosf(half));
    add_node(&g, "\"name\": \"double-sided\", \"mesh\": %d", m_ds);
    add_node(&g, "\"name\": \"camera\", \"camera\": %d, \"translation\": [0, 0, 2]", cam);
    char path[1024];
    snprintf(path, sizeof path, "%s/triangles.gltf", dir);
    return write_gltf(&g, path, "", "\"name\": \"triangles\", \"nodes\": [0, 1, 2, 3]");
}

/** Stereo test scene (seed 000 §5.2, seed 004 Fig. 2): a diffuse sphere and a rough metal
 *  box over a glossy metal floor (roughness 0.45), lit by one emissive ceiling panel behind and
 *  left of the objects and a dim sky-blue environment. The panel's broad glossy highlight on the
 *  floor (left of the sphere) and the objects' reflections in it move with the eye (view-
 *  dependent: a real stereo difference) but at moderate intensity, so that at low sample counts
 *  the eyes' discrepancy is dominated by Monte Carlo noise, the regime of seed 000 §5.2 (see
 *  scenes/README.md: an earlier version with a low delta sun over a roughness-0.35 floor was
 *  dominated by its real sun streak instead). */
static int make_glossy(const char *dir)
{
    gltf g = {0};
    int floor_mat = add_material(&g, "\"name\": \"glossy-floor\", \"pbrMetallicRoughness\": "
                                     "{\"baseColorFactor\": [0.8, 0.8, 0.8, 1], "
                                     "\"metallicFactor\": 1, \"roughnessFactor\": 0.45}");
    int ball = add_material(&g, "\"name\": \"orange\", \"pbrMetallicRoughness\": "
                                "{\"baseColorFactor\": [0.8, 0.35, 0.1, 1], "
                                "\"metallicFactor\": 0, \"roughnessFactor\": 0.6}");
    int box_mat = add_material(&g, "\"name\": \"blue-metal\", \"pbrMetallicRoughness\": "
                                   "{\"baseColorFactor\": [0.3, 0.45, 0.9, 1], "
                                   "\"metallicFactor\": 1, \"roughnessFactor\": 0.25}");
    int panel_mat = add_material(&g, "\"name\": \"panel\", \"pbrMetallicRoughness\": "
                                     "{\"baseColorFactor\": [0, 0, 0, 1], \"metallicFactor\": 0, "
                                     "\"roughnessFactor\": 1}, "
                                     "\"emissiveFactor\": [1, 0.95, 0.85], \"extensions\": "
                                     "{\"KHR_materials_emissive_strength\": "
                                     "{\"emissiveStrength\": 4}}");
    geom fl = {0}, bx = {0}, pl = {0};
    quad(&fl, (float[]){-3, 0, 1}, (float[]){6, 0, 0}, (float[]){0, 0, -6}); /* floor, +Y */
    /* a 0.5 m cube standing on the floor, outward normals */
    const float h = 0.25f;
    quad(&bx, (float[]){-h, 0, h}, (float[]){2 * h, 0, 0}, (float[]){0, 2 * h, 0});   /* +Z */
    quad(&bx, (float[]){h, 0, -h}, (float[]){-2 * h, 0, 0}, (float[]){0, 2 * h, 0});  /* -Z */
    quad(&bx, (float[]){h, 0, h}, (float[]){0, 0, -2 * h}, (float[]){0, 2 * h, 0});   /* +X */
    quad(&bx, (float[]){-h, 0, -h}, (float[]){0, 0, 2 * h}, (float[]){0, 2 * h, 0});  /* -X */
    quad(&bx, (float[]){-h, 2 * h, h}, (float[]){2 * h, 0, 0}, (float[]){0, 0, -2 * h}); /* +Y */
    /* a 1.5 x 1.5 m panel 2 m up, centred at (-1.2, 2, -5), facing down (u x v = -Y): the camera
     * sees its mirror image (-1.2, -2, -5) through the floor at (-0.37, 0, -1.14), in front of
     * and left of the sphere */
    quad(&pl, (float[]){-1.95f, 2, -5.75f}, (float[]){1.5f, 0, 0}, (float[]){0, 0, 1.5f});
    int m_floor = add_mesh(&g, "floor", add_geom(&g, &fl, 5123), floor_mat);
    int m_box = add_mesh(&g, "box", add_geom(&g, &bx, 5123), box_mat);
    int m_panel = add_mesh(&g, "panel", add_geom(&g, &pl, 5123), panel_mat);
    geom_free(&fl);
    geom_free(&bx);
    geom_free(&pl);
    geom s = make_sphere(48, 24);
    int m_ball = add_mesh(&g, "sphere", add_geom(&g, &s, 5123), ball);
    geom_free(&s);
    int cam = add_camera(&g, 1.0f, 0.05f);

    add_node(&g, "\"name\": \"floor\", \"mesh\": %d", m_floor);
    add_node(&g,
             "\"name\": \"sphere\", \"mesh\": %d, \"translation\": [-0.3, 0.4, -1.6], "
             "\"scale\": [0.4, 0.4, 0.4]",
             m_ball);
    /* the box turned 30 degrees about +Y */
    add_node(&g,
             "\"name\": \"box\", \"mesh\": %d, \"translation\": [0.55, 0, -1.2], "
             "\"rotation\": [0, %.9g, 0, %.9g]",
             m_box, sinf(PI_F / 12.0f), cosf(PI_F / 12.0f));
    add_node(&g, "\"name\": \"panel\", \"mesh\": %d", m_panel);
    /* camera 0.9 m up, looking down by 15 degrees towards the objects */
    float pitch = -PI_F / 12.0f;
    add_node(&g,
             "\"name\": \"camera\", \"camera\": %d, \"translation\": [0, 0.9, 0.6], "
             "\"rotation\": [%.9g, 0, 0, %.9g]",
             cam, sinf(pitch * 0.5f), cosf(pitch * 0.5f));
    char path[1024];
    snprintf(path, sizeof path, "%s/glossy.gltf", dir);
    return write_gltf(&g, path, "\"KHR_materials_emissive_strength\"",
                      "\"name\": \"glossy\", \"nodes\": [0, 1, 2, 3, 4], "
                      "\"extras\": {\"xrsc_environment\": [0.175, 0.225, 0.3]}");
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
        return 2;
    }
    int fails = make_furnace(argv[1]) + make_cornell(argv[1]) + make_triangles(argv[1]) +
                make_glossy(argv[1]);
    return fails ? 1 : 0;
}
