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
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI_F 3.14159265358979f
/* The solid glass spheres (radius 0.35 m) of cornell and specular: KHR_materials_volume makes
 * them refracting volumes (without it glTF transmission is a thin wall), clear (no attenuation). */
#define GLASS_VOLUME "\"KHR_materials_volume\": {\"thicknessFactor\": 0.7}"

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
    str lights, anim_channels, anim_samplers, images, textures; /**< written only when used */
    int n_lights, n_anim_channels, n_images, n_textures;
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
    str_add(&g->views, "{\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu", off, bytes);
    /* target 0: animation keys and images, which glTF gives no buffer target */
    if (target) str_add(&g->views, ", \"target\": %d", target);
    str_add(&g->views, "}");
    return g->n_views++;
}

/** Float accessor (SCALAR or VECn) with min/max, in a view of the given target (0: none). */
static int add_float_accessor_t(gltf *g, const float *v, int count, int n, const char *type,
                                int target)
{
    int view = add_view(g, v, sizeof(float) * (size_t)count * (size_t)n, target);
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

/** Float VECn vertex accessor with min/max. */
static int add_float_accessor(gltf *g, const float *v, int count, int n, const char *type)
{
    return add_float_accessor_t(g, v, count, n, type, 34962);
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
    if (g->n_lights)
        str_add(&j, "  \"extensions\": {\"KHR_lights_punctual\": {\"lights\": [%s\n  ]}},\n",
                g->lights.s);
    if (g->n_anim_channels)
        str_add(&j, "  \"animations\": [{\"channels\": [%s\n  ], \"samplers\": [%s\n  ]}],\n",
                g->anim_channels.s, g->anim_samplers.s);
    if (g->n_textures)
        str_add(&j, "  \"samplers\": [{}],\n  \"textures\": [%s\n  ],\n  \"images\": [%s\n  ],\n",
                g->textures.s, g->images.s);
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
    free(g->lights.s);
    free(g->anim_channels.s);
    free(g->anim_samplers.s);
    free(g->images.s);
    free(g->textures.s);
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
                                 "\"KHR_materials_ior\": {\"ior\": 1.5}, " GLASS_VOLUME "}");

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
                      "\"KHR_materials_ior\", \"KHR_materials_volume\"",
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

/* ---- helpers of the stability scenes (issue 9): boxes, flat triangles, a sun, a camera node,
 *      node animation, an embedded PNG texture ---- */

/** Appends an axis-aligned box with outward normals: min corner lo, size sz. */
static void box(geom *m, const float lo[3], const float sz[3])
{
    float x0 = lo[0], y0 = lo[1], z0 = lo[2], x1 = lo[0] + sz[0], y1 = lo[1] + sz[1],
          z1 = lo[2] + sz[2];
    quad(m, (float[]){x0, y0, z1}, (float[]){sz[0], 0, 0}, (float[]){0, sz[1], 0});  /* +Z */
    quad(m, (float[]){x1, y0, z0}, (float[]){-sz[0], 0, 0}, (float[]){0, sz[1], 0}); /* -Z */
    quad(m, (float[]){x1, y0, z1}, (float[]){0, 0, -sz[2]}, (float[]){0, sz[1], 0}); /* +X */
    quad(m, (float[]){x0, y0, z0}, (float[]){0, 0, sz[2]}, (float[]){0, sz[1], 0});  /* -X */
    quad(m, (float[]){x0, y1, z1}, (float[]){sz[0], 0, 0}, (float[]){0, 0, -sz[2]}); /* +Y */
    quad(m, (float[]){x0, y0, z0}, (float[]){sz[0], 0, 0}, (float[]){0, 0, sz[2]});  /* -Y */
}

/** Appends one triangle with its own three vertices and flat normal (counter-clockwise). */
static void flat_tri(geom *m, const float a[3], const float b[3], const float tip[3])
{
    m->pos = realloc(m->pos, sizeof(float) * 3 * (size_t)(m->nv + 3));
    m->nrm = realloc(m->nrm, sizeof(float) * 3 * (size_t)(m->nv + 3));
    m->uv = realloc(m->uv, sizeof(float) * 2 * (size_t)(m->nv + 3));
    m->idx = realloc(m->idx, sizeof(uint32_t) * (size_t)(m->ni + 3));
    if (!m->pos || !m->nrm || !m->uv || !m->idx)
        abort();
    float u[3], v[3];
    for (int c = 0; c < 3; c++)
        u[c] = b[c] - a[c], v[c] = tip[c] - a[c];
    float n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const float *p[3] = {a, b, tip};
    for (int k = 0; k < 3; k++) {
        for (int i = 0; i < 3; i++) {
            m->pos[3 * (m->nv + k) + i] = p[k][i];
            m->nrm[3 * (m->nv + k) + i] = n[i] / len;
        }
        m->uv[2 * (m->nv + k)] = m->uv[2 * (m->nv + k) + 1] = 0.0f;
        m->idx[m->ni + k] = (uint32_t)(m->nv + k);
    }
    m->nv += 3;
    m->ni += 3;
}

/** Adds a directional light (KHR_lights_punctual) and its node. to_sun points from the scene
 *  towards the sun (need not be unit, must not be -Z); the light shines along its node's -Z,
 *  so the node's rotation takes -Z onto -to_sun (shortest arc). */
static int add_sun(gltf *g, const float to_sun[3], const float color[3], float intensity)
{
    float l = sqrtf(to_sun[0] * to_sun[0] + to_sun[1] * to_sun[1] + to_sun[2] * to_sun[2]);
    float t[3] = {-to_sun[0] / l, -to_sun[1] / l, -to_sun[2] / l};
    /* (0, 0, -1) x t = (t.y, -t.x, 0); w = 1 + (0, 0, -1) . t */
    float q[4] = {t[1], -t[0], 0.0f, 1.0f - t[2]};
    float ql = sqrtf(q[0] * q[0] + q[1] * q[1] + q[3] * q[3]);
    sep(&g->lights, g->n_lights);
    str_add(&g->lights,
            "{\"name\": \"sun\", \"type\": \"directional\", \"color\": [%.9g, %.9g, %.9g], "
            "\"intensity\": %.9g}",
            color[0], color[1], color[2], intensity);
    return add_node(g,
                    "\"name\": \"sun\", \"rotation\": [%.9g, %.9g, 0, %.9g], "
                    "\"extensions\": {\"KHR_lights_punctual\": {\"light\": %d}}",
                    q[0] / ql, q[1] / ql, q[3] / ql, g->n_lights++);
}

/** Adds a perspective camera (yfov 1 rad) and its node at pos, turned by yaw about +Y
 *  (positive = left) then pitched about +X (positive = up), in degrees. */
static int add_camera_node(gltf *g, const float pos[3], float yaw_deg, float pitch_deg)
{
    int cam = add_camera(g, 1.0f, 0.05f);
    float hy = 0.5f * yaw_deg * PI_F / 180.0f, hp = 0.5f * pitch_deg * PI_F / 180.0f;
    /* q = q_yaw * q_pitch */
    float q[4] = {cosf(hy) * sinf(hp), sinf(hy) * cosf(hp), -sinf(hy) * sinf(hp),
                  cosf(hy) * cosf(hp)};
    return add_node(g,
                    "\"name\": \"camera\", \"camera\": %d, \"translation\": [%.9g, %.9g, %.9g], "
                    "\"rotation\": [%.9g, %.9g, %.9g, %.9g]",
                    cam, pos[0], pos[1], pos[2], q[0], q[1], q[2], q[3]);
}

/** Adds one LINEAR animation channel on node's path ("translation" or "rotation"): n keys at
 *  times (s), values of 3 or 4 floats. All channels go into one animation. */
static void add_channel(gltf *g, int node, const char *path, const float *times,
                        const float *values, int n)
{
    int comps = strcmp(path, "rotation") == 0 ? 4 : 3;
    int in = add_float_accessor_t(g, times, n, 1, "SCALAR", 0);
    int out = add_float_accessor_t(g, values, n, comps, comps == 4 ? "VEC4" : "VEC3", 0);
    sep(&g->anim_channels, g->n_anim_channels);
    str_add(&g->anim_channels, "{\"sampler\": %d, \"target\": {\"node\": %d, \"path\": \"%s\"}}",
            g->n_anim_channels, node, path);
    sep(&g->anim_samplers, g->n_anim_channels);
    str_add(&g->anim_samplers, "{\"input\": %d, \"output\": %d, \"interpolation\": \"LINEAR\"}", in,
            out);
    g->n_anim_channels++;
}

static uint32_t crc32_png(uint32_t crc, const uint8_t *p, size_t n)
{
    crc = ~crc;
    for (size_t i = 0; i < n; i++) {
        crc ^= p[i];
        for (int k = 0; k < 8; k++)
            crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24), p[1] = (uint8_t)(v >> 16), p[2] = (uint8_t)(v >> 8),
    p[3] = (uint8_t)v;
}

/** Appends a PNG chunk (length, type, data, CRC of type + data) to buf at *len. */
static void png_chunk(uint8_t *buf, size_t *len, const char type[4], const uint8_t *d, size_t n)
{
    put_be32(buf + *len, (uint32_t)n);
    memcpy(buf + *len + 4, type, 4);
    if (n)
        memcpy(buf + *len + 8, d, n);
    put_be32(buf + *len + 8 + n, crc32_png(0, buf + *len + 4, n + 4));
    *len += 12 + n;
}

/** Encodes an 8-bit RGB image as PNG with uncompressed (stored) deflate blocks: no zlib needed,
 *  and any PNG reader (stb_image in the loader) decodes it. Returns a malloc'ed buffer. */
static uint8_t *png_rgb(const uint8_t *rgb, int w, int h, size_t *out_len)
{
    size_t raw_n = (size_t)h * (size_t)(1 + 3 * w); /* filter byte 0 (None) per row */
    uint8_t *raw = malloc(raw_n);
    size_t blocks = raw_n / 65535 + 1, z_n = 2 + raw_n + 5 * blocks + 4;
    uint8_t *z = malloc(z_n), *png = malloc(8 + 25 + 12 + z_n + 12);
    if (!raw || !z || !png)
        abort();
    for (int y = 0; y < h; y++) {
        raw[(size_t)y * (size_t)(1 + 3 * w)] = 0;
        memcpy(raw + (size_t)y * (size_t)(1 + 3 * w) + 1, rgb + (size_t)y * 3 * (size_t)w,
               3 * (size_t)w);
    }
    size_t zl = 0;
    z[zl++] = 0x78, z[zl++] = 0x01; /* zlib header: deflate, 32 KiB window, no dictionary */
    uint32_t a = 1, b = 0;          /* Adler-32 of the raw data */
    for (size_t off = 0; off < raw_n || off == 0;) {
        size_t n = raw_n - off < 65535 ? raw_n - off : 65535;
        z[zl++] = off + n == raw_n ? 1 : 0; /* BFINAL, BTYPE 00 (stored) */
        z[zl++] = (uint8_t)n, z[zl++] = (uint8_t)(n >> 8);
        z[zl++] = (uint8_t)~n, z[zl++] = (uint8_t)(~n >> 8);
        memcpy(z + zl, raw + off, n);
        for (size_t i = 0; i < n; i++)
            a = (a + raw[off + i]) % 65521u, b = (b + a) % 65521u;
        zl += n;
        off += n;
        if (off == raw_n)
            break;
    }
    put_be32(z + zl, b << 16 | a);
    zl += 4;
    static const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    size_t len = 8;
    memcpy(png, sig, 8);
    uint8_t ihdr[13] = {0};
    put_be32(ihdr, (uint32_t)w);
    put_be32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8, ihdr[9] = 2; /* 8 bits, truecolour; deflate, filter 0, no interlace */
    png_chunk(png, &len, "IHDR", ihdr, 13);
    png_chunk(png, &len, "IDAT", z, zl);
    png_chunk(png, &len, "IEND", NULL, 0);
    free(raw);
    free(z);
    *out_len = len;
    return png;
}

/** Adds a PNG image (in the binary buffer) and a texture of it with the default sampler. */
static int add_png_texture(gltf *g, const uint8_t *png, size_t n)
{
    int view = add_view(g, png, n, 0);
    sep(&g->images, g->n_images);
    str_add(&g->images, "{\"bufferView\": %d, \"mimeType\": \"image/png\"}", view);
    sep(&g->textures, g->n_textures);
    str_add(&g->textures, "{\"sampler\": 0, \"source\": %d}", g->n_images++);
    return g->n_textures++;
}

/** "0, 1, ..., n-1": every node of the file (the stability scenes have only root nodes). */
static const char *all_nodes(const gltf *g, char *buf, size_t cap)
{
    size_t len = 0;
    buf[0] = 0;
    for (int i = 0; i < g->n_nodes && len + 8 < cap; i++)
        len += (size_t)snprintf(buf + len, cap - len, "%s%d", i ? ", " : "", i);
    return buf;
}

/** Writes dir/name.gltf with every node in the scene and the given environment radiance. */
static int write_scene(gltf *g, const char *dir, const char *name, const char *extensions_used,
                       float env)
{
    char nodes[512], body[768], path[1024];
    snprintf(body, sizeof body,
             "\"name\": \"%s\", \"nodes\": [%s], \"extras\": {\"xrsc_environment\": "
             "[%.9g, %.9g, %.9g]}",
             name, all_nodes(g, nodes, sizeof nodes), env, env, 1.2f * env);
    snprintf(path, sizeof path, "%s/%s.gltf", dir, name);
    return write_gltf(g, path, extensions_used, body);
}

/** A diffuse material body (base colour rgb, metallic 0, roughness 1). */
static int add_diffuse(gltf *g, const char *name, float r, float gr, float b, bool double_sided)
{
    char body[320];
    snprintf(body, sizeof body,
             "\"name\": \"%s\", %s\"pbrMetallicRoughness\": {\"baseColorFactor\": "
             "[%.9g, %.9g, %.9g, 1], \"metallicFactor\": 0, \"roughnessFactor\": 1}",
             name, double_sided ? "\"doubleSided\": true, " : "", r, gr, b);
    return add_material(g, body);
}

static int mesh_of(gltf *g, const char *name, geom *m, int material)
{
    int mesh = add_mesh(g, name, add_geom(g, m, 5125), material);
    geom_free(m);
    return mesh;
}

/** A small deterministic generator (LCG, Numerical Recipes constants) for strand jitter. */
static float lcg01(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (float)(*s >> 8) / 16777216.0f;
}

/* The sun of the stability scenes: white-yellow, irradiance 3 on a surface facing it. */
static const float SUN_COLOR[3] = {1.0f, 0.95f, 0.85f};
#define SUN_INTENSITY 3.0f
#define SUN_EXT "\"KHR_lights_punctual\""

/* ---- strands (seed 000 Fig. 8): thin geometry, aliasing and flicker ---- */

#define STRAND_ROWS 3
#define STRAND_PER_ROW 49
#define STRAND_WIDTH_M 0.0015f /**< 0.1 px at 128 x 128, 0.2 px at 256 x 256 from the camera */
#define STRAND_SPACING_M 0.05f
#define STRAND_HEIGHT_M 1.4f
#define STRAND_LEAN_M 0.1f /**< top offset from the root, uniform in +-, fixed seed */

/** Three rows of hair-thin vertical quads (1.5 mm x 1.4 m, leaning a little) in front of a dark
 *  wall, under one sun: nearly every strand pixel is partly covered, so a pixel's colour
 *  depends on where its samples land (aliasing), which is what flickers under motion. */
static int make_strands(const char *dir)
{
    gltf g = {0};
    /* Lambertian (IOR 1: no specular layer to pick stochastically) under a delta sun and a black
     * environment: with direct lighting only (max_bounces 1) the shading of a hit is exact, and
     * all that varies between frames is where the pixel's samples land (Fig. 8's setting) */
    int hair =
        add_material(&g, "\"name\": \"strand\", \"doubleSided\": true, "
                         "\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.85, 0.8, 0.7, 1], "
                         "\"metallicFactor\": 0, \"roughnessFactor\": 1}, "
                         "\"extensions\": {\"KHR_materials_ior\": {\"ior\": 1.0}}");
    int dark =
        add_material(&g, "\"name\": \"dark-wall\", \"pbrMetallicRoughness\": "
                         "{\"baseColorFactor\": [0.05, 0.05, 0.06, 1], \"metallicFactor\": 0, "
                         "\"roughnessFactor\": 1}, "
                         "\"extensions\": {\"KHR_materials_ior\": {\"ior\": 1.0}}");
    geom st = {0}, wall = {0};
    uint32_t seed = 9u;
    for (int r = 0; r < STRAND_ROWS; r++)
        for (int i = 0; i < STRAND_PER_ROW; i++) {
            float x = ((float)i - 0.5f * (STRAND_PER_ROW - 1) + (float)r / STRAND_ROWS) *
                      STRAND_SPACING_M;
            float z = -1.0f - 0.2f * (float)r;
            float lx = STRAND_LEAN_M * (2.0f * lcg01(&seed) - 1.0f);
            float lz = STRAND_LEAN_M * (2.0f * lcg01(&seed) - 1.0f);
            quad(&st, (float[]){x, 0.2f, z}, (float[]){STRAND_WIDTH_M, 0, 0},
                 (float[]){lx, STRAND_HEIGHT_M, lz});
        }
    quad(&wall, (float[]){-6, -5, -3}, (float[]){12, 0, 0}, (float[]){0, 11, 0});
    int m_st = mesh_of(&g, "strands", &st, hair);
    int m_wall = mesh_of(&g, "wall", &wall, dark);
    add_node(&g, "\"name\": \"strands\", \"mesh\": %d", m_st);
    add_node(&g, "\"name\": \"wall\", \"mesh\": %d", m_wall);
    add_sun(&g, (float[]){0.3f, 0.6f, 0.75f}, SUN_COLOR, SUN_INTENSITY);
    add_camera_node(&g, (float[]){0, 0.9f, 0.5f}, 0, 0);
    return write_scene(&g, dir, "strands", SUN_EXT ", \"KHR_materials_ior\"", 0.0f);
}

/* ---- headturn (seed 000 Fig. 12): a 90 deg yaw that invalidates the cache ---- */

/** An open-top 6 x 6 m room (2.5 m walls) with a differently coloured wall each way and an
 *  object near each, lit by a high sun and a sky: every yaw sees its own geometry. */
static int make_headturn(const char *dir)
{
    gltf g = {0};
    int floor_m = add_diffuse(&g, "floor", 0.5f, 0.5f, 0.5f, false);
    int front_m = add_diffuse(&g, "front-white", 0.75f, 0.75f, 0.7f, false);
    int left_m = add_diffuse(&g, "left-red", 0.7f, 0.15f, 0.1f, false);
    int right_m = add_diffuse(&g, "right-green", 0.15f, 0.6f, 0.15f, false);
    int back_m = add_diffuse(&g, "back-blue", 0.15f, 0.25f, 0.7f, false);
    int obj_m = add_diffuse(&g, "objects", 0.8f, 0.6f, 0.3f, false);
    geom fl = {0}, fr = {0}, le = {0}, ri = {0}, bk = {0}, ob = {0};
    quad(&fl, (float[]){-3, 0, 3}, (float[]){6, 0, 0}, (float[]){0, 0, -6});    /* +Y */
    quad(&fr, (float[]){-3, 0, -3}, (float[]){6, 0, 0}, (float[]){0, 2.5f, 0}); /* +Z */
    quad(&le, (float[]){-3, 0, 3}, (float[]){0, 0, -6}, (float[]){0, 2.5f, 0}); /* +X */
    quad(&ri, (float[]){3, 0, -3}, (float[]){0, 0, 6}, (float[]){0, 2.5f, 0});  /* -X */
    quad(&bk, (float[]){3, 0, 3}, (float[]){-6, 0, 0}, (float[]){0, 2.5f, 0});  /* -Z */
    box(&ob, (float[]){0.3f, 0, -2.3f}, (float[]){0.6f, 0.6f, 0.6f});           /* front */
    box(&ob, (float[]){-2.4f, 0, 0.0f}, (float[]){0.4f, 1.2f, 0.4f});           /* left pillar */
    box(&ob, (float[]){2.0f, 0, -1.0f}, (float[]){0.5f, 0.5f, 0.5f});           /* right */
    box(&ob, (float[]){-0.8f, 0, 2.0f}, (float[]){0.8f, 0.8f, 0.5f});           /* back */
    box(&ob, (float[]){-1.2f, 0.9f, -2.9f}, (float[]){0.6f, 0.4f, 0.2f}); /* shelf, front wall */
    int meshes[6] = {mesh_of(&g, "floor", &fl, floor_m),    mesh_of(&g, "wall-front", &fr, front_m),
                     mesh_of(&g, "wall-left", &le, left_m), mesh_of(&g, "wall-right", &ri, right_m),
                     mesh_of(&g, "wall-back", &bk, back_m), mesh_of(&g, "objects", &ob, obj_m)};
    for (int i = 0; i < 6; i++)
        add_node(&g, "\"name\": \"part-%d\", \"mesh\": %d", i, meshes[i]);
    add_sun(&g, (float[]){0.4f, 0.8f, 0.3f}, SUN_COLOR, SUN_INTENSITY);
    add_camera_node(&g, (float[]){0, 1.6f, 0.5f}, 0, -5);
    return write_scene(&g, dir, "headturn", SUN_EXT, 0.3f);
}

/* ---- edges (seed 000 Fig. 7): high-contrast geometric edges under a pan ---- */

/** Black bars (1.6 m) and white cubes (1 m) in front of a white wall (4 m), under a sun from
 *  behind the camera: every bar and cube edge is a black/white step with a depth step behind
 *  it, near enough for a sideways head motion to uncover and cover pixels every frame. */
static int make_edges(const char *dir)
{
    gltf g = {0};
    int white = add_diffuse(&g, "white", 0.8f, 0.8f, 0.8f, false);
    int black = add_diffuse(&g, "black", 0.02f, 0.02f, 0.02f, false);
    geom wall = {0}, bars = {0}, cubes = {0};
    quad(&wall, (float[]){-7, -7, -4}, (float[]){14, 0, 0}, (float[]){0, 14, 0});
    for (int i = 0; i < 11; i++)
        box(&bars, (float[]){-2.5f + 0.5f * (float)i - 0.075f, -4, -1.6f},
            (float[]){0.15f, 8, 0.1f});
    static const float cube_xy[6][2] = {{-1.3f, 0.3f}, {-0.6f, 1.4f}, {-0.2f, 0.6f},
                                        {0.5f, 1.1f},  {0.9f, 0.2f},  {1.4f, 1.6f}};
    for (int i = 0; i < 6; i++)
        box(&cubes, (float[]){0.5f * cube_xy[i][0], 0.5f * cube_xy[i][1] + 0.4f, -1.0f},
            (float[]){0.15f, 0.15f, 0.15f});
    int m_wall = mesh_of(&g, "wall", &wall, white);
    int m_bars = mesh_of(&g, "bars", &bars, black);
    int m_cubes = mesh_of(&g, "cubes", &cubes, white);
    add_node(&g, "\"name\": \"wall\", \"mesh\": %d", m_wall);
    add_node(&g, "\"name\": \"bars\", \"mesh\": %d", m_bars);
    add_node(&g, "\"name\": \"cubes\", \"mesh\": %d", m_cubes);
    add_sun(&g, (float[]){0.25f, 0.35f, 1.0f}, SUN_COLOR, SUN_INTENSITY);
    add_camera_node(&g, (float[]){0, 1, 0}, 0, 0);
    return write_scene(&g, dir, "edges", SUN_EXT, 0.0f);
}

/* ---- specular (seed 000 App. C, Fig. 18): metal and glass under an orbit ---- */

/** A glossy gold-coloured metal sphere and a glass sphere on a grey floor, with a red and a
 *  blue box behind them to reflect and refract, under a sun and a sky. */
static int make_specular(const char *dir)
{
    gltf g = {0};
    int floor_m = add_diffuse(&g, "floor", 0.5f, 0.5f, 0.5f, false);
    int red = add_diffuse(&g, "red", 0.7f, 0.1f, 0.08f, false);
    int blue = add_diffuse(&g, "blue", 0.1f, 0.2f, 0.7f, false);
    int metal = add_material(&g, "\"name\": \"glossy-metal\", \"pbrMetallicRoughness\": "
                                 "{\"baseColorFactor\": [0.95, 0.8, 0.5, 1], "
                                 "\"metallicFactor\": 1, \"roughnessFactor\": 0.15}");
    int glass = add_material(&g, "\"name\": \"glass\", \"pbrMetallicRoughness\": "
                                 "{\"baseColorFactor\": [1, 1, 1, 1], \"metallicFactor\": 0, "
                                 "\"roughnessFactor\": 0}, \"extensions\": "
                                 "{\"KHR_materials_transmission\": {\"transmissionFactor\": 1}, "
                                 "\"KHR_materials_ior\": {\"ior\": 1.5}, " GLASS_VOLUME "}");
    geom fl = {0}, rb = {0}, bb = {0};
    quad(&fl, (float[]){-3, 0, 1}, (float[]){6, 0, 0}, (float[]){0, 0, -6});
    box(&rb, (float[]){-0.9f, 0, -2.6f}, (float[]){0.6f, 0.7f, 0.3f});
    box(&bb, (float[]){0.3f, 0, -2.5f}, (float[]){0.5f, 0.9f, 0.3f});
    int m_floor = mesh_of(&g, "floor", &fl, floor_m);
    int m_red = mesh_of(&g, "box-red", &rb, red);
    int m_blue = mesh_of(&g, "box-blue", &bb, blue);
    geom s = make_sphere(48, 24);
    geom_acc sa = add_geom(&g, &s, 5123);
    geom_free(&s);
    int m_metal = add_mesh(&g, "sphere-metal", sa, metal);
    int m_glass = add_mesh(&g, "sphere-glass", sa, glass);
    add_node(&g, "\"name\": \"floor\", \"mesh\": %d", m_floor);
    add_node(&g, "\"name\": \"box-red\", \"mesh\": %d", m_red);
    add_node(&g, "\"name\": \"box-blue\", \"mesh\": %d", m_blue);
    add_node(&g,
             "\"name\": \"sphere-metal\", \"mesh\": %d, \"translation\": [-0.45, 0.35, -1.5], "
             "\"scale\": [0.35, 0.35, 0.35]",
             m_metal);
    add_node(&g,
             "\"name\": \"sphere-glass\", \"mesh\": %d, \"translation\": [0.45, 0.35, -1.5], "
             "\"scale\": [0.35, 0.35, 0.35]",
             m_glass);
    add_sun(&g, (float[]){-0.5f, 0.7f, 0.5f}, SUN_COLOR, SUN_INTENSITY);
    /* looks at (0, 0.35, -1.5), the point between the spheres: 0.45 m down over 1.5 m */
    add_camera_node(&g, (float[]){0, 0.8f, 0}, 0, -16.7f);
    return write_scene(&g, dir, "specular",
                       SUN_EXT ", \"KHR_materials_transmission\", \"KHR_materials_ior\", "
                               "\"KHR_materials_volume\"",
                       0.25f);
}

/* ---- moving (seed 000 App. D, Fig. 19): a rotating cone under a sun ---- */

#define CONE_FACETS 12
#define CONE_TURN_S 4.0f /**< one full turn about +Y */

/** A flat-shaded 12-facet cone turning about its vertical axis on a plane under a low sun: its
 *  facets turn towards and away from the sun, so its shading changes every frame although its
 *  silhouette barely does (a smooth cone would look static). */
static int make_moving(const char *dir)
{
    gltf g = {0};
    int floor_m = add_diffuse(&g, "plane", 0.6f, 0.6f, 0.6f, false);
    int cone_m = add_diffuse(&g, "cone-orange", 0.85f, 0.45f, 0.15f, false);
    geom fl = {0}, cone = {0};
    quad(&fl, (float[]){-3, 0, 1}, (float[]){6, 0, 0}, (float[]){0, 0, -6});
    const float r = 0.4f, h = 0.9f;
    for (int i = 0; i < CONE_FACETS; i++) {
        float a0 = 2.0f * PI_F * (float)i / CONE_FACETS,
              a1 = 2.0f * PI_F * (float)(i + 1) / CONE_FACETS;
        flat_tri(&cone, (float[]){r * sinf(a0), 0, r * cosf(a0)},
                 (float[]){r * sinf(a1), 0, r * cosf(a1)}, (float[]){0, h, 0});
    }
    int m_floor = mesh_of(&g, "plane", &fl, floor_m);
    int m_cone = mesh_of(&g, "cone", &cone, cone_m);
    add_node(&g, "\"name\": \"plane\", \"mesh\": %d", m_floor);
    int cone_node =
        add_node(&g, "\"name\": \"cone\", \"mesh\": %d, \"translation\": [0, 0, -1.8]", m_cone);
    /* five keys a quarter turn apart: LINEAR (slerp) rotation at a constant 90 deg/s */
    float times[5], rot[20];
    for (int k = 0; k < 5; k++) {
        float half = 0.5f * 2.0f * PI_F * (float)k / 4.0f;
        times[k] = CONE_TURN_S * (float)k / 4.0f;
        rot[4 * k] = 0, rot[4 * k + 1] = sinf(half), rot[4 * k + 2] = 0,
                rot[4 * k + 3] = cosf(half);
    }
    add_channel(&g, cone_node, "rotation", times, rot, 5);
    add_sun(&g, (float[]){0.8f, 0.45f, 0.4f}, SUN_COLOR, SUN_INTENSITY);
    /* looks at the cone's middle (0, 0.45, -1.8): 0.45 m down over 1.8 m */
    add_camera_node(&g, (float[]){0, 0.9f, 0}, 0, -14.0f);
    return write_scene(&g, dir, "moving", SUN_EXT, 0.2f);
}

/* ---- disocclusion: a box sliding in front of a textured wall ---- */

#define CHECKER_PX 128
#define CHECKER_CELL_PX 8
#define SLIDE_X_M 0.9f     /**< the box's centre moves between -SLIDE_X_M and +SLIDE_X_M */
#define SLIDE_HALF_S 0.75f /**< one way (2.4 m/s), then back: a 1.5 s loop */

/** A 4-colour checker (each cell's colour from a hash of its coordinates), so every uncovered
 *  wall pixel has detail that a wrong or blurred history shows. */
static uint8_t *checker_png(size_t *out_len)
{
    static const uint8_t pal[4][3] = {{230, 225, 210}, {40, 40, 45}, {200, 70, 50}, {60, 110, 190}};
    uint8_t *rgb = malloc(3 * CHECKER_PX * CHECKER_PX);
    if (!rgb)
        abort();
    for (int y = 0; y < CHECKER_PX; y++)
        for (int x = 0; x < CHECKER_PX; x++) {
            uint32_t cx = (uint32_t)(x / CHECKER_CELL_PX), cy = (uint32_t)(y / CHECKER_CELL_PX);
            /* odd cells dark; even cells light, red or blue by a hash of the cell */
            static const uint32_t even[3] = {0u, 2u, 3u};
            uint32_t h = (cx * 73856093u) ^ (cy * 19349663u);
            uint32_t k = (cx + cy) & 1u ? 1u : even[(h >> 4) % 3u];
            memcpy(rgb + 3 * (y * CHECKER_PX + x), pal[k], 3);
        }
    uint8_t *png = png_rgb(rgb, CHECKER_PX, CHECKER_PX, out_len);
    free(rgb);
    return png;
}

static int make_disocclusion(const char *dir)
{
    gltf g = {0};
    size_t png_n;
    uint8_t *png = checker_png(&png_n);
    int tex = add_png_texture(&g, png, png_n);
    free(png);
    char body[256];
    snprintf(body, sizeof body,
             "\"name\": \"checker-wall\", \"pbrMetallicRoughness\": {\"baseColorTexture\": "
             "{\"index\": %d}, \"metallicFactor\": 0, \"roughnessFactor\": 1}",
             tex);
    int wall_m = add_material(&g, body);
    int box_m = add_diffuse(&g, "box-grey", 0.45f, 0.45f, 0.45f, false);
    geom wall = {0}, bx = {0};
    quad(&wall, (float[]){-4, -4, -3}, (float[]){8, 0, 0}, (float[]){0, 8, 0});
    /* 2 repeats each way over the 8 x 8 m wall: cells of 25 cm (~3 px at 128 x 128) */
    for (int v = 0; v < 2 * wall.nv; v++)
        wall.uv[v] *= 2.0f;
    box(&bx, (float[]){-0.3f, -0.3f, -0.15f}, (float[]){0.6f, 0.6f, 0.3f});
    int m_wall = mesh_of(&g, "wall", &wall, wall_m);
    int m_box = mesh_of(&g, "box", &bx, box_m);
    add_node(&g, "\"name\": \"wall\", \"mesh\": %d", m_wall);
    int box_node = add_node(&g, "\"name\": \"box\", \"mesh\": %d, \"translation\": [%.9g, 1, -1.5]",
                            m_box, -SLIDE_X_M);
    float times[3] = {0, SLIDE_HALF_S, 2 * SLIDE_HALF_S};
    float tr[9] = {-SLIDE_X_M, 1, -1.5f, SLIDE_X_M, 1, -1.5f, -SLIDE_X_M, 1, -1.5f};
    add_channel(&g, box_node, "translation", times, tr, 3);
    add_sun(&g, (float[]){0.3f, 0.5f, 1.0f}, SUN_COLOR, SUN_INTENSITY);
    add_camera_node(&g, (float[]){0, 1, 0}, 0, 0);
    return write_scene(&g, dir, "disocclusion", SUN_EXT, 0.2f);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
        return 2;
    }
    int fails = make_furnace(argv[1]) + make_cornell(argv[1]) + make_triangles(argv[1]) +
                make_glossy(argv[1]);
    /* issue 9: one scene per failure case of the stability suite (scenes/README.md) */
    fails += make_strands(argv[1]) + make_headturn(argv[1]) + make_edges(argv[1]) +
             make_specular(argv[1]) + make_moving(argv[1]) + make_disocclusion(argv[1]);
    return fails ? 1 : 0;
}
