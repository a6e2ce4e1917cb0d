// SPDX-License-Identifier: MIT
/**
 * @file sc_scene.c
 * @brief glTF document (sc_gltf.h) → ::sc_scene: validation, geometry, materials, instances,
 * lights, camera, animation, emitters, bounds and the default environment.
 *
 * Every index and byte range from the file is checked here before use; errors name the JSON
 * field (e.g. `meshes[2].primitives[0].mode`). Ignored features are collected and named in
 * one warning per load.
 */
#include "sc_gltf.h"
#include "sc_hdr.h"
#include "sc_scene.h"
#include "sc_xform.h"
#include "u_diag.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/** Files larger than this are refused (tinygltf takes 32-bit lengths). */
#define SC_MAX_FILE_BYTES (2ull << 30)
/** More vertices or indices than this in one scene are refused (32-bit indices, GPU limits). */
#define SC_MAX_ELEMENTS (1u << 28)
/** Accessors without a bufferView (zeros, perhaps with sparse values) may have at most this
 *  many elements: their size is not bounded by the file's size. */
#define SC_MAX_ZERO_ELEMENTS (1u << 16)
/** Rec. 709 luminance weights, for emitter power. */
#define SC_LUMA_R 0.2126f
#define SC_LUMA_G 0.7152f
#define SC_LUMA_B 0.0722f
/** Default viewpoint distance factor (sc_scene.h: max_z + 1.2 * max(half_x, half_y)). */
#define SC_DEFAULT_VIEW_DISTANCE 1.2f

/** Growable array of fixed-size items. */
typedef struct sc_vec {
    void *data;
    size_t count, cap, item;
} sc_vec;

/** Appends n zeroed items; NULL only when out of memory (n = 0 still gives a valid pointer). */
static void *vec_push(sc_vec *v, size_t n)
{
    if (!v->data || v->count + n > v->cap) {
        size_t cap = v->cap ? v->cap : 64;
        while (cap < v->count + n) cap *= 2;
        void *p = realloc(v->data, cap * v->item);
        if (!p) return NULL;
        v->data = p;
        v->cap = cap;
    }
    void *at = (char *)v->data + v->count * v->item;
    memset(at, 0, n * v->item);
    v->count += n;
    return at;
}

/** State of one load. */
typedef struct sc_build {
    const char *name;
    sc_gltf_doc *doc;
    xrsc_diag *diag;
    const sc_load_options *opt;
    sc_scene *s;
    sc_vec vertices, indices, meshes, textures, instances, emitters;
    uint32_t *prim_mesh;      /**< doc primitive → sc mesh */
    int32_t *tex_map;         /**< doc texture * 2 + srgb → sc texture, -1 unused */
} sc_build;

#define FIELD(buf, ...) snprintf(buf, sizeof buf, __VA_ARGS__)

/* ---------------------------------------------------------------- accessors ------------ */

static size_t component_size(int32_t type)
{
    switch (type) {
    case SC_GLTF_BYTE:
    case SC_GLTF_UNSIGNED_BYTE: return 1;
    case SC_GLTF_SHORT:
    case SC_GLTF_UNSIGNED_SHORT: return 2;
    case SC_GLTF_UNSIGNED_INT:
    case SC_GLTF_FLOAT: return 4;
    default: return 0;
    }
}

/** One component as double (exact for every glTF component type), normalised if asked
 *  (glTF §3.11 "normalized": signed values clamp at -1). */
static double read_component(const uint8_t *p, int32_t type, bool normalized)
{
    switch (type) {
    case SC_GLTF_BYTE: {
        int8_t v;
        memcpy(&v, p, 1);
        return normalized ? fmax(v / 127.0, -1.0) : v;
    }
    case SC_GLTF_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case SC_GLTF_SHORT: {
        int16_t v;
        memcpy(&v, p, 2);
        return normalized ? fmax(v / 32767.0, -1.0) : v;
    }
    case SC_GLTF_UNSIGNED_SHORT: {
        uint16_t v;
        memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
    }
    case SC_GLTF_UNSIGNED_INT: {
        uint32_t v;
        memcpy(&v, p, 4);
        return normalized ? v / 4294967295.0 : v;
    }
    default: {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    }
}

/**
 * Resolves bytes [offset, offset + stride*(count-1) + elem) of buffer view `view`, checking
 * every range. Returns the first byte, or NULL after filling diag.
 */
static const uint8_t *view_range(sc_build *b, int32_t view, size_t offset, size_t count,
                                 size_t elem, size_t *inout_stride, const char *field)
{
    sc_gltf_doc *d = b->doc;
    if (view < 0 || (uint32_t)view >= d->view_count) {
        u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                   "bufferView %d does not exist", view);
        return NULL;
    }
    const sc_gltf_view *v = &d->views[view];
    if (v->buffer < 0 || (uint32_t)v->buffer >= d->buffer_count) {
        u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                   "bufferViews[%d].buffer %d does not exist", view, v->buffer);
        return NULL;
    }
    const sc_gltf_buffer *buf = &d->buffers[v->buffer];
    if (v->offset > buf->size || v->length > buf->size - v->offset) {
        u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                   "bufferViews[%d] overruns buffer %d (%zu bytes)", view, v->buffer, buf->size);
        return NULL;
    }
    size_t stride = *inout_stride ? *inout_stride : (v->stride ? v->stride : elem);
    if (stride < elem) {
        u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                   "bufferViews[%d].byteStride %zu is smaller than an element (%zu bytes)", view,
                   stride, elem);
        return NULL;
    }
    *inout_stride = stride;
    if (count == 0) return buf->data ? buf->data + v->offset : (const uint8_t *)"";
    if (offset > v->length || elem > v->length - offset ||
        (count - 1) > (v->length - offset - elem) / stride) {
        u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                   "%zu elements of %zu bytes (stride %zu) from byte %zu overrun bufferViews[%d] "
                   "of %zu bytes",
                   count, elem, stride, offset, view, v->length);
        return NULL;
    }
    return buf->data + v->offset + offset;
}

/**
 * Reads accessor idx as `comps` components per element into a new double array (*out, count
 * elements), applying normalisation and sparse substitution. Returns XRSC_OK or fills diag.
 */
static xrsc_result read_accessor(sc_build *b, int32_t idx, uint32_t comps, const char *use,
                                 double **out, size_t *out_count)
{
    char field[96];
    *out = NULL;
    *out_count = 0;
    sc_gltf_doc *d = b->doc;
    if (idx < 0 || (uint32_t)idx >= d->accessor_count)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, use,
                          "accessor %d does not exist", idx);
    const sc_gltf_accessor *a = &d->accessors[idx];
    FIELD(field, "accessors[%d]", idx);
    size_t cs = component_size(a->component_type);
    if (cs == 0)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "componentType %d is not a glTF component type (used as %s)",
                          a->component_type, use);
    if (a->components != comps)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "has %u components per element, %s needs %u", a->components, use,
                          comps);
    if (a->count > SC_MAX_ELEMENTS)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "count %zu is more than xrsc accepts (%u)", a->count, SC_MAX_ELEMENTS);
    if (a->view < 0 && a->count > SC_MAX_ZERO_ELEMENTS)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "count %zu without a bufferView is more than xrsc accepts (%u)",
                          a->count, SC_MAX_ZERO_ELEMENTS);
    size_t elem = cs * comps, stride = 0;
    /* Check the byte range before allocating, so the allocation is bounded by the file. */
    const uint8_t *p = NULL;
    if (a->view >= 0 &&
        !(p = view_range(b, a->view, a->offset, a->count, elem, &stride, field)))
        return b->diag ? b->diag->code : XRSC_ERROR_GLTF_INVALID;
    double *v = calloc(a->count ? a->count * comps : 1, sizeof(double));
    if (!v) return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, field, "out of memory");
    if (p) {
        for (size_t i = 0; i < a->count; i++)
            for (uint32_t c = 0; c < comps; c++)
                v[i * comps + c] = read_component(p + i * stride + c * cs, a->component_type,
                                                  a->normalized);
    }
    if (a->sparse) {
        char sfield[96];
        FIELD(sfield, "accessors[%d].sparse", idx);
        size_t n = a->sparse_count, ics = component_size(a->sparse_indices_type);
        if (n > a->count || ics == 0 || a->sparse_indices_type == SC_GLTF_BYTE ||
            a->sparse_indices_type == SC_GLTF_SHORT || a->sparse_indices_type == SC_GLTF_FLOAT) {
            free(v);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, sfield,
                              "sparse count %zu or index componentType %d is invalid", n,
                              a->sparse_indices_type);
        }
        size_t istride = 0, vstride = 0;
        const uint8_t *ip = view_range(b, a->sparse_indices_view, a->sparse_indices_offset, n,
                                       ics, &istride, sfield);
        const uint8_t *vp = ip ? view_range(b, a->sparse_values_view, a->sparse_values_offset,
                                            n, elem, &vstride, sfield)
                               : NULL;
        if (!ip || !vp) {
            free(v);
            return b->diag ? b->diag->code : XRSC_ERROR_GLTF_INVALID;
        }
        /* Sparse indices and values are tightly packed (glTF §3.6.2.3). */
        for (size_t k = 0; k < n; k++) {
            double di = read_component(ip + k * ics, a->sparse_indices_type, false);
            if (!(di >= 0.0 && di < (double)a->count)) {
                free(v);
                return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, sfield,
                                  "sparse index %.0f is out of range (count %zu)", di, a->count);
            }
            size_t i = (size_t)di;
            for (uint32_t c = 0; c < comps; c++)
                v[i * comps + c] = read_component(vp + k * elem + c * cs, a->component_type,
                                                  a->normalized);
        }
    }
    for (size_t i = 0; i < a->count * comps; i++)
        if (!isfinite(v[i]) || fabs(v[i]) > FLT_MAX) {
            free(v);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "element %zu is NaN or infinite (used as %s)", i / comps, use);
        }
    *out = v;
    *out_count = a->count;
    return XRSC_OK;
}

/* ---------------------------------------------------------------- geometry ------------- */

static void normalize3(float v[3], const float fallback[3])
{
    float n = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 1e-20f && isfinite(n)) {
        v[0] /= n, v[1] /= n, v[2] /= n;
    } else {
        v[0] = fallback[0], v[1] = fallback[1], v[2] = fallback[2];
    }
}

static void face_normal(const float a[3], const float b[3], const float c[3], float n[3])
{
    float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    static const float up[3] = {0.0f, 1.0f, 0.0f};
    normalize3(n, up);
}

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/** Angle at corner a of triangle (a, b, c), radians. */
static float corner_angle(const float a[3], const float b[3], const float c[3])
{
    float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    float uv = sqrtf(dot3(u, u) * dot3(v, v));
    return uv > 0.0f ? acosf(fmaxf(-1.0f, fminf(1.0f, dot3(u, v) / uv))) : 0.0f;
}

/**
 * Generates per-vertex tangents for glTF normal maps when the file has no TANGENT, following
 * the conventions of MikkTSpace (which glTF 2.0 §3.7.2.1 names): per triangle, the tangent is
 * dP/du and the bitangent -dP/dv (glTF's v grows downwards in the image, and its normal maps
 * are +Y up), solved from the UV derivatives of the triangle's edges; both are normalised and
 * summed at each corner weighted by the corner's angle; each vertex then gets its tangent made
 * orthogonal to its normal (Gram-Schmidt) and handedness w = sign(dot(cross(n, t), b)).
 * Unlike MikkTSpace, vertices are never split where the handedness or UV charts disagree:
 * such a vertex keeps the average. Triangles with degenerate UVs add nothing; a vertex with
 * no tangent gets one perpendicular to its normal (w = 1).
 */
static bool generate_tangents(sc_vertex *v, size_t vcount, const uint32_t *inds, size_t icount,
                              uint32_t first_vertex)
{
    float *acc = calloc(vcount ? vcount * 6 : 1, sizeof(float)); /* t xyz, b xyz */
    if (!acc) return false;
    for (size_t t = 0; t + 2 < icount; t += 3) {
        const sc_vertex *c[3];
        size_t vi[3];
        for (int k = 0; k < 3; k++) vi[k] = inds[t + k] - first_vertex, c[k] = &v[vi[k]];
        float e1[3], e2[3], tt[3], bb[3];
        for (int a = 0; a < 3; a++)
            e1[a] = c[1]->position[a] - c[0]->position[a],
            e2[a] = c[2]->position[a] - c[0]->position[a];
        float du1 = c[1]->uv[0] - c[0]->uv[0], dv1 = c[1]->uv[1] - c[0]->uv[1];
        float du2 = c[2]->uv[0] - c[0]->uv[0], dv2 = c[2]->uv[1] - c[0]->uv[1];
        float det = du1 * dv2 - du2 * dv1;
        if (!(fabsf(det) > 1e-20f)) continue;
        for (int a = 0; a < 3; a++) {
            tt[a] = (e1[a] * dv2 - e2[a] * dv1) / det;
            bb[a] = -(e2[a] * du1 - e1[a] * du2) / det;
        }
        static const float zero[3] = {0.0f, 0.0f, 0.0f};
        normalize3(tt, zero);
        normalize3(bb, zero);
        for (int k = 0; k < 3; k++) {
            float w = corner_angle(c[k]->position, c[(k + 1) % 3]->position,
                                   c[(k + 2) % 3]->position);
            for (int a = 0; a < 3; a++)
                acc[vi[k] * 6 + a] += w * tt[a], acc[vi[k] * 6 + 3 + a] += w * bb[a];
        }
    }
    for (size_t i = 0; i < vcount; i++) {
        const float *n = v[i].normal;
        float t[3] = {0.0f, 0.0f, 0.0f}, b[3] = {0.0f, 0.0f, 0.0f};
        memcpy(t, acc + i * 6, sizeof t), memcpy(b, acc + i * 6 + 3, sizeof b);
        float d = dot3(n, t);
        for (int a = 0; a < 3; a++) t[a] -= d * n[a];
        /* fallback: an axis made perpendicular to n */
        float perp[3] = {fabsf(n[0]) < 0.9f ? 1.0f : 0.0f, fabsf(n[0]) < 0.9f ? 0.0f : 1.0f,
                         0.0f};
        float dp = dot3(n, perp), nb[3];
        for (int a = 0; a < 3; a++) perp[a] -= dp * n[a];
        normalize3(perp, n);
        normalize3(t, perp);
        cross3(n, t, nb);
        memcpy(v[i].tangent, t, sizeof t);
        v[i].tangent[3] = dot3(nb, b) < 0.0f ? -1.0f : 1.0f;
    }
    free(acc);
    return true;
}

/**
 * TRIANGLE_STRIP / TRIANGLE_FAN → a triangle list, with glTF 2.0 §3.7.2.1's vertex order
 * (strip triangle i: p_i, p_{i+1+i%2}, p_{i+2-i%2}; fan triangle i: p_{i+1}, p_{i+2}, p_0),
 * which keeps every triangle's winding. *idx NULL means the vertices in order (0..n-1).
 * Replaces *idx and *icount; false when out of memory.
 */
static bool strip_or_fan_to_list(int32_t mode, double **idx, size_t *icount)
{
    size_t n = *icount, tris = n >= 3 ? n - 2 : 0;
    double *out = malloc((tris ? tris * 3 : 1) * sizeof(double));
    if (!out) return false;
    const double *in = *idx;
    for (size_t i = 0; i < tris; i++) {
        size_t a, b, c;
        if (mode == SC_GLTF_MODE_TRIANGLE_STRIP)
            a = i, b = i + 1 + i % 2, c = i + 2 - i % 2;
        else
            a = i + 1, b = i + 2, c = 0;
        out[3 * i] = in ? in[a] : (double)a;
        out[3 * i + 1] = in ? in[b] : (double)b;
        out[3 * i + 2] = in ? in[c] : (double)c;
    }
    free(*idx);
    *idx = out;
    *icount = tris * 3;
    return true;
}

/** Attribute and index arrays of one primitive as read from the file; prim_data_free frees. */
typedef struct sc_prim_data {
    double *pos, *nrm, *tan, *uv, *idx;
    size_t vcount, ncount, tcount, uvcount, icount;
} sc_prim_data;

static void prim_data_free(sc_prim_data *pd)
{
    free(pd->pos);
    free(pd->nrm);
    free(pd->tan);
    free(pd->uv);
    free(pd->idx);
}

/** Where one primitive's vertices and indices went in the scene-wide arrays. */
typedef struct sc_prim_out {
    sc_vertex *verts;
    uint32_t *inds;
    size_t vcount, icount;
    uint32_t first_vertex, first_index;
} sc_prim_out;

/** Rejects non-triangle modes, a missing POSITION and a material that does not exist. */
static xrsc_result check_primitive(sc_build *b, uint32_t m, uint32_t p, const sc_gltf_primitive *pr)
{
    char field[96];
    if (pr->mode != SC_GLTF_MODE_TRIANGLES && pr->mode != SC_GLTF_MODE_TRIANGLE_STRIP &&
        pr->mode != SC_GLTF_MODE_TRIANGLE_FAN) {
        FIELD(field, "meshes[%u].primitives[%u].mode", m, p);
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_UNSUPPORTED, b->name, 0, field,
                          "mode %d (points or lines) is not a triangle mode (4, 5, 6); xrsc "
                          "renders triangles only",
                          pr->mode);
    }
    if (pr->position < 0) {
        FIELD(field, "meshes[%u].primitives[%u].attributes.POSITION", m, p);
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "POSITION is required");
    }
    if (pr->material >= 0 && (uint32_t)pr->material >= b->doc->material_count) {
        FIELD(field, "meshes[%u].primitives[%u].material", m, p);
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "material %d does not exist", pr->material);
    }
    return XRSC_OK;
}

/** Reads POSITION, NORMAL, TEXCOORD_0 and TANGENT into pd and checks that their counts agree. */
static xrsc_result read_attributes(sc_build *b, uint32_t m, uint32_t p, const sc_gltf_primitive *pr,
                                   sc_prim_data *pd)
{
    char field[96];
    FIELD(field, "meshes[%u].primitives[%u].attributes.POSITION", m, p);
    xrsc_result r = read_accessor(b, pr->position, 3, field, &pd->pos, &pd->vcount);
    if (r == XRSC_OK && pr->normal >= 0) {
        FIELD(field, "meshes[%u].primitives[%u].attributes.NORMAL", m, p);
        r = read_accessor(b, pr->normal, 3, field, &pd->nrm, &pd->ncount);
    }
    if (r == XRSC_OK && pr->texcoord0 >= 0) {
        FIELD(field, "meshes[%u].primitives[%u].attributes.TEXCOORD_0", m, p);
        r = read_accessor(b, pr->texcoord0, 2, field, &pd->uv, &pd->uvcount);
    }
    /* TANGENT is only used with NORMAL (glTF §3.7.2.1: without normals, tangents are ignored). */
    if (r == XRSC_OK && pd->nrm && pr->tangent >= 0) {
        FIELD(field, "meshes[%u].primitives[%u].attributes.TANGENT", m, p);
        r = read_accessor(b, pr->tangent, 4, field, &pd->tan, &pd->tcount);
        if (r == XRSC_OK && pd->tcount != pd->vcount)
            r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                           "TANGENT has %zu elements, POSITION %zu", pd->tcount, pd->vcount);
    }
    if (r == XRSC_OK &&
        ((pd->nrm && pd->ncount != pd->vcount) || (pd->uv && pd->uvcount != pd->vcount))) {
        FIELD(field, "meshes[%u].primitives[%u].attributes", m, p);
        r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                       "attribute counts differ (POSITION %zu, NORMAL %zu, TEXCOORD_0 %zu)",
                       pd->vcount, pd->ncount, pd->uvcount);
    }
    return r;
}

/**
 * Reads the indices into pd (none: the vertices in order), turns a strip or fan into a
 * triangle list and checks every index against the vertex count.
 */
static xrsc_result read_indices(sc_build *b, uint32_t m, uint32_t p, const sc_gltf_primitive *pr,
                                sc_prim_data *pd)
{
    sc_gltf_doc *d = b->doc;
    char field[96];
    xrsc_result r = XRSC_OK;
    if (pr->indices >= 0) {
        FIELD(field, "meshes[%u].primitives[%u].indices", m, p);
        int32_t ct = pr->indices < (int32_t)d->accessor_count && pr->indices >= 0
                         ? d->accessors[pr->indices].component_type
                         : SC_GLTF_UNSIGNED_INT;
        if (ct != SC_GLTF_UNSIGNED_BYTE && ct != SC_GLTF_UNSIGNED_SHORT &&
            ct != SC_GLTF_UNSIGNED_INT)
            r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                           "index componentType %d is not an unsigned integer type", ct);
        else
            r = read_accessor(b, pr->indices, 1, field, &pd->idx, &pd->icount);
    } else {
        pd->icount = pd->vcount;
    }
    if (r == XRSC_OK && pr->mode != SC_GLTF_MODE_TRIANGLES &&
        !strip_or_fan_to_list(pr->mode, &pd->idx, &pd->icount))
        r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    if (r == XRSC_OK && pd->icount % 3 != 0) {
        FIELD(field, "meshes[%u].primitives[%u].indices", m, p);
        r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                       "%zu indices is not a multiple of 3 (TRIANGLES)", pd->icount);
    }
    if (r == XRSC_OK && pd->icount == 0) { /* a strip or fan of fewer than 3 vertices */
        FIELD(field, "meshes[%u].primitives[%u].indices", m, p);
        r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                       "the primitive has no triangle (mode %d)", pr->mode);
    }
    if (r == XRSC_OK && pd->idx) {
        for (size_t i = 0; i < pd->icount; i++)
            if (pd->idx[i] >= (double)pd->vcount) {
                FIELD(field, "meshes[%u].primitives[%u].indices", m, p);
                r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                               "index %.0f at position %zu is out of range (%zu vertices)",
                               pd->idx[i], i, pd->vcount);
                break;
            }
    }
    return r;
}

/** Appends room for the primitive's vertices and indices to the scene-wide arrays (o). */
static xrsc_result reserve_geometry(sc_build *b, const sc_prim_data *pd, sc_prim_out *o)
{
    /* Without normals the triangles are unwelded and get flat normals (glTF §3.7.2.1). */
    o->vcount = pd->nrm ? pd->vcount : pd->icount;
    o->icount = pd->icount;
    if (b->vertices.count + o->vcount > SC_MAX_ELEMENTS ||
        b->indices.count + o->icount > SC_MAX_ELEMENTS)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "meshes",
                          "more than %u vertices or indices", SC_MAX_ELEMENTS);
    o->first_vertex = (uint32_t)b->vertices.count;
    o->first_index = (uint32_t)b->indices.count;
    o->verts = vec_push(&b->vertices, o->vcount);
    o->inds = o->verts ? vec_push(&b->indices, o->icount) : NULL;
    if (!o->verts || !o->inds)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    return XRSC_OK;
}

/** With NORMAL: one vertex per file vertex, the file's indices. */
static void fill_smooth_vertices(const sc_prim_data *pd, sc_prim_out *o)
{
    static const float up[3] = {0.0f, 1.0f, 0.0f};
    for (size_t i = 0; i < pd->vcount; i++) {
        sc_vertex *v = &o->verts[i];
        for (int c = 0; c < 3; c++) {
            v->position[c] = (float)pd->pos[i * 3 + c];
            v->normal[c] = (float)pd->nrm[i * 3 + c];
        }
        normalize3(v->normal, up);
        if (pd->uv)
            v->uv[0] = (float)pd->uv[i * 2], v->uv[1] = (float)pd->uv[i * 2 + 1];
        if (pd->tan) {
            for (int c = 0; c < 3; c++)
                v->tangent[c] = (float)pd->tan[i * 4 + c];
            v->tangent[3] = pd->tan[i * 4 + 3] < 0.0 ? -1.0f : 1.0f;
        }
    }
    for (size_t i = 0; i < o->icount; i++)
        o->inds[i] = o->first_vertex + (uint32_t)(pd->idx ? pd->idx[i] : (double)i);
}

/** Without NORMAL: three vertices per triangle, each with the triangle's face normal. */
static void fill_flat_vertices(const sc_prim_data *pd, sc_prim_out *o)
{
    sc_vertex *verts = o->verts;
    for (size_t t = 0; t < o->icount / 3; t++) {
        for (int k = 0; k < 3; k++) {
            size_t src = pd->idx ? (size_t)pd->idx[3 * t + k] : 3 * t + k;
            sc_vertex *v = &verts[3 * t + k];
            for (int c = 0; c < 3; c++)
                v->position[c] = (float)pd->pos[src * 3 + c];
            if (pd->uv)
                v->uv[0] = (float)pd->uv[src * 2], v->uv[1] = (float)pd->uv[src * 2 + 1];
        }
        float n[3];
        face_normal(verts[3 * t].position, verts[3 * t + 1].position, verts[3 * t + 2].position, n);
        for (int k = 0; k < 3; k++)
            memcpy(verts[3 * t + k].normal, n, sizeof n);
    }
    for (size_t i = 0; i < o->icount; i++)
        o->inds[i] = o->first_vertex + (uint32_t)i;
}

/** The file's tangents made orthonormal to the normal; missing or degenerate: generated. */
static xrsc_result finish_tangents(sc_build *b, const sc_prim_data *pd, sc_prim_out *o)
{
    bool generate = true;
    if (pd->tan) {
        bool degenerate = false;
        for (size_t i = 0; i < o->vcount; i++) {
            float *t = o->verts[i].tangent, d = dot3(o->verts[i].normal, t);
            for (int c = 0; c < 3; c++)
                t[c] -= d * o->verts[i].normal[c];
            float len = sqrtf(dot3(t, t));
            if (!(len > 1e-12f))
                degenerate = true;
            else
                for (int c = 0; c < 3; c++)
                    t[c] /= len;
        }
        generate = degenerate;
    }
    if (generate && !generate_tangents(o->verts, o->vcount, o->inds, o->icount, o->first_vertex))
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    return XRSC_OK;
}

/** Records the sc_mesh of document primitive gp, whose geometry is o. */
static xrsc_result add_mesh(sc_build *b, const sc_gltf_primitive *pr, uint32_t gp,
                            const sc_prim_out *o)
{
    sc_mesh *mesh = vec_push(&b->meshes, 1);
    if (!mesh)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    mesh->first_vertex = o->first_vertex;
    mesh->vertex_count = (uint32_t)o->vcount;
    mesh->first_index = o->first_index;
    mesh->index_count = (uint32_t)o->icount;
    mesh->material = pr->material >= 0 ? (uint32_t)pr->material : b->doc->material_count;
    b->prim_mesh[gp] = (uint32_t)(b->meshes.count - 1);
    return XRSC_OK;
}

/** Builds the sc_mesh of document primitive gp (mesh m, primitive p). */
static xrsc_result build_primitive(sc_build *b, uint32_t m, uint32_t p, uint32_t gp)
{
    const sc_gltf_primitive *pr = &b->doc->primitives[gp];
    xrsc_result r = check_primitive(b, m, p, pr);
    if (r != XRSC_OK)
        return r;
    sc_prim_data pd = {0};
    sc_prim_out o = {0};
    r = read_attributes(b, m, p, pr, &pd);
    if (r == XRSC_OK)
        r = read_indices(b, m, p, pr, &pd);
    if (r == XRSC_OK)
        r = reserve_geometry(b, &pd, &o);
    if (r == XRSC_OK) {
        if (pd.nrm)
            fill_smooth_vertices(&pd, &o);
        else
            fill_flat_vertices(&pd, &o);
        r = finish_tangents(b, &pd, &o);
    }
    if (r == XRSC_OK && !b->opt->keep_triangle_order &&
        !sc_morton_sort_triangles((const sc_vertex *)b->vertices.data, o.inds, (uint32_t)o.icount))
        r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    if (r == XRSC_OK)
        r = add_mesh(b, pr, gp, &o);
    prim_data_free(&pd);
    return r;
}

/* ---------------------------------------------------------------- materials ------------ */

/** sc texture index for a material's texture reference, creating it on first use. */
static xrsc_result map_texture(sc_build *b, sc_gltf_texref ref, bool srgb, const char *field,
                               uint32_t *out)
{
    sc_gltf_doc *d = b->doc;
    *out = SC_NO_TEXTURE;
    if (ref.texture < 0) return XRSC_OK;
    if ((uint32_t)ref.texture >= d->texture_count)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "texture %d does not exist", ref.texture);
    if (ref.tex_coord != 0) return XRSC_OK; /* noted by sc_gltf.cpp */
    int32_t img = d->textures[ref.texture].image;
    if (img < 0 || (uint32_t)img >= d->image_count) {
        sc_gltf_note(d, "textures without a PNG/JPEG source");
        return XRSC_OK;
    }
    const sc_gltf_image *im = &d->images[img];
    if (!im->rgba8) return XRSC_OK; /* undecodable: noted by sc_gltf.cpp */
    int32_t *slot = &b->tex_map[(size_t)ref.texture * 2 + (srgb ? 1 : 0)];
    if (*slot < 0) {
        sc_texture *t = vec_push(&b->textures, 1);
        size_t bytes = (size_t)im->width * im->height * 4;
        uint8_t *px = t ? malloc(bytes) : NULL;
        if (!px) {
            if (t) b->textures.count--;
            return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, field,
                              "out of memory");
        }
        memcpy(px, im->rgba8, bytes);
        t->width = im->width;
        t->height = im->height;
        t->rgba8 = px;
        t->srgb = srgb;
        *slot = (int32_t)(b->textures.count - 1);
    }
    *out = (uint32_t)*slot;
    return XRSC_OK;
}

/** KHR_texture_transform as the rows of a 2x3 matrix: T(offset) R(rotation) S(scale), with
 *  R = [cos sin; -sin cos] (the extension's definition, rotation counter-clockwise in UV). */
static void uv_transform(const sc_gltf_texref *ref, float m[6])
{
    float c = cosf(ref->rotation_rad), s = sinf(ref->rotation_rad);
    m[0] = c * ref->scale[0], m[1] = s * ref->scale[1], m[2] = ref->offset[0];
    m[3] = -s * ref->scale[0], m[4] = c * ref->scale[1], m[5] = ref->offset[1];
}

static void uv_identity(sc_material *mt)
{
    static const float id[6] = {1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};
    for (int k = 0; k < SC_TEX_SLOTS; k++) memcpy(mt->uv_transform[k], id, sizeof id);
}

static xrsc_result build_materials(sc_build *b)
{
    sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    s->material_count = d->material_count + 1; /* + the glTF default material */
    s->materials = calloc(s->material_count, sizeof(sc_material));
    b->tex_map = malloc(sizeof(int32_t) * 2 * (d->texture_count + 1));
    if (!s->materials || !b->tex_map)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    for (uint32_t i = 0; i < 2 * (d->texture_count + 1); i++) b->tex_map[i] = -1;
    for (uint32_t i = 0; i < d->material_count; i++) {
        const sc_gltf_material *g = &d->materials[i];
        sc_material *mt = &s->materials[i];
        char field[96];
        memcpy(mt->base_color, g->base_color, sizeof mt->base_color);
        mt->metallic = g->metallic;
        mt->roughness = g->roughness;
        for (int c = 0; c < 3; c++) mt->emission[c] = g->emissive[c] * g->emissive_strength;
        mt->transmission = g->transmission;
        mt->ior = g->ior;
        mt->double_sided = g->double_sided;
        mt->alpha_mode = g->alpha_mode == SC_GLTF_ALPHA_MASK    ? SC_ALPHA_MASK
                         : g->alpha_mode == SC_GLTF_ALPHA_BLEND ? SC_ALPHA_BLEND
                                                                : SC_ALPHA_OPAQUE;
        mt->alpha_cutoff = g->alpha_cutoff;
        mt->unlit = g->unlit;
        mt->normal_scale = g->normal_scale;
        uv_transform(&g->base_color_tex, mt->uv_transform[SC_TEX_BASE]);
        uv_transform(&g->metal_rough_tex, mt->uv_transform[SC_TEX_METAL_ROUGH]);
        uv_transform(&g->emissive_tex, mt->uv_transform[SC_TEX_EMISSION]);
        uv_transform(&g->normal_tex, mt->uv_transform[SC_TEX_NORMAL]);
        snprintf(mt->name, sizeof mt->name, "%s", g->name);
        xrsc_result r;
        FIELD(field, "materials[%u].pbrMetallicRoughness.baseColorTexture.index", i);
        if ((r = map_texture(b, g->base_color_tex, true, field, &mt->base_color_tex)) != XRSC_OK)
            return r;
        FIELD(field, "materials[%u].pbrMetallicRoughness.metallicRoughnessTexture.index", i);
        if ((r = map_texture(b, g->metal_rough_tex, false, field, &mt->metal_rough_tex)) !=
            XRSC_OK)
            return r;
        FIELD(field, "materials[%u].emissiveTexture.index", i);
        if ((r = map_texture(b, g->emissive_tex, true, field, &mt->emission_tex)) != XRSC_OK)
            return r;
        FIELD(field, "materials[%u].normalTexture.index", i);
        if ((r = map_texture(b, g->normal_tex, false, field, &mt->normal_tex)) != XRSC_OK)
            return r;
    }
    /* The glTF default material (§3.9.6): white, metallic 1, roughness 1. */
    sc_material *def = &s->materials[d->material_count];
    for (int c = 0; c < 4; c++) def->base_color[c] = 1.0f;
    def->metallic = 1.0f;
    def->roughness = 1.0f;
    def->base_color_tex = def->metal_rough_tex = def->emission_tex = SC_NO_TEXTURE;
    def->normal_tex = SC_NO_TEXTURE;
    def->normal_scale = 1.0f;
    uv_identity(def);
    def->ior = 1.5f;
    snprintf(def->name, sizeof def->name, "xrsc-default");
    return XRSC_OK;
}

/* ---------------------------------------------------------------- nodes ---------------- */

/** Parents from children lists; rejects bad indices, two parents and cycles. */
static xrsc_result build_nodes(sc_build *b)
{
    sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    char field[96];
    s->node_count = d->node_count;
    s->nodes = calloc(d->node_count ? d->node_count : 1, sizeof(sc_node));
    s->node_order = calloc(d->node_count ? d->node_count : 1, sizeof(uint32_t));
    if (!s->nodes || !s->node_order)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    for (uint32_t i = 0; i < d->node_count; i++) {
        const sc_gltf_node *g = &d->nodes[i];
        sc_node *n = &s->nodes[i];
        n->parent = -1;
        snprintf(n->name, sizeof n->name, "%s", g->name);
        if (g->has_matrix) {
            n->has_matrix = true;
            memcpy(n->matrix, g->matrix, sizeof n->matrix);
            sc_mat4_decompose(g->matrix, n->translation, n->rotation, n->scale);
        } else {
            memcpy(n->translation, g->translation, sizeof n->translation);
            memcpy(n->rotation, g->rotation, sizeof n->rotation);
            memcpy(n->scale, g->scale, sizeof n->scale);
        }
    }
    for (uint32_t i = 0; i < d->node_count; i++) {
        const sc_gltf_node *g = &d->nodes[i];
        if (g->first_child > d->children_count || g->child_count > d->children_count - g->first_child)
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "nodes",
                              "internal: bad child range");
        for (uint32_t k = 0; k < g->child_count; k++) {
            int32_t c = d->children[g->first_child + k];
            FIELD(field, "nodes[%u].children[%u]", i, k);
            if (c < 0 || (uint32_t)c >= d->node_count)
                return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                                  "node %d does not exist", c);
            if (s->nodes[c].parent >= 0 || (uint32_t)c == i)
                return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                                  "node %d has more than one parent (the node graph must be a "
                                  "forest)",
                                  c);
            s->nodes[c].parent = (int32_t)i;
        }
    }
    /* Parents-first order: depth of each node by walking up; a walk longer than the node
     * count is a cycle. Then counting sort by depth. */
    uint32_t *depth = calloc(d->node_count ? d->node_count : 1, sizeof(uint32_t));
    uint32_t *start = calloc((size_t)d->node_count + 1, sizeof(uint32_t));
    if (!depth || !start) {
        free(depth);
        free(start);
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    }
    for (uint32_t i = 0; i < d->node_count; i++) {
        uint32_t steps = 0;
        int32_t p = s->nodes[i].parent;
        while (p >= 0 && steps <= d->node_count) {
            steps++;
            p = s->nodes[p].parent;
        }
        if (steps > d->node_count) {
            free(depth);
            free(start);
            FIELD(field, "nodes[%u].children", (uint32_t)s->nodes[i].parent);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "the node hierarchy has a cycle");
        }
        depth[i] = steps;
        start[steps]++;
    }
    uint32_t sum = 0;
    for (uint32_t k = 0; k <= d->node_count; k++) {
        uint32_t c = start[k];
        start[k] = sum;
        sum += c;
    }
    for (uint32_t i = 0; i < d->node_count; i++) s->node_order[start[depth[i]]++] = i;
    free(depth);
    free(start);
    return XRSC_OK;
}

/* ---------------------------------------------------------------- animation ------------ */

static xrsc_result build_channels(sc_build *b, bool *node_animated)
{
    sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    char field[96];
    s->channels = calloc(d->channel_count ? d->channel_count : 1, sizeof(sc_anim_channel));
    if (!s->channels)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    for (uint32_t c = 0; c < d->channel_count; c++) {
        const sc_gltf_channel *g = &d->channels[c];
        FIELD(field, "animations[%u].channels[%u]", g->animation, g->channel);
        if (g->node < 0) continue; /* no target node: ignored per spec (extensions may use it) */
        if ((uint32_t)g->node >= d->node_count)
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "target node %d does not exist", g->node);
        if (g->path == SC_GLTF_PATH_WEIGHTS || g->path == SC_GLTF_PATH_OTHER) {
            sc_gltf_note(d, g->path == SC_GLTF_PATH_WEIGHTS ? "morph target animation"
                                                            : "animation paths other than T/R/S");
            continue;
        }
        if (g->input < 0 || g->interp == SC_GLTF_INTERP_OTHER) {
            FIELD(field, "animations[%u].channels[%u].sampler", g->animation, g->channel);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "sampler is missing or has an unknown interpolation");
        }
        uint32_t nc = g->path == SC_GLTF_PATH_ROTATION ? 4 : 3;
        double *times = NULL, *vals = NULL;
        size_t tcount = 0, vcount = 0;
        FIELD(field, "animations[%u].samplers.input", g->animation);
        xrsc_result r = read_accessor(b, g->input, 1, field, &times, &tcount);
        FIELD(field, "animations[%u].samplers.output", g->animation);
        if (r == XRSC_OK) r = read_accessor(b, g->output, nc, field, &vals, &vcount);
        size_t per_key = g->interp == SC_GLTF_INTERP_CUBICSPLINE ? 3 : 1;
        if (r == XRSC_OK && (tcount == 0 || vcount != tcount * per_key))
            r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                           "%zu output values for %zu keys (%zu per key expected)", vcount, tcount,
                           per_key);
        for (size_t k = 1; r == XRSC_OK && k < tcount; k++)
            if (!(times[k] >= times[k - 1])) {
                FIELD(field, "animations[%u].samplers.input", g->animation);
                r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                               "key times decrease at key %zu", k);
            }
        sc_anim_channel *ch = &s->channels[s->channel_count];
        if (r == XRSC_OK) {
            ch->times = malloc(tcount * sizeof(float));
            ch->values = malloc(vcount * nc * sizeof(float));
            s->channel_count++; /* counted now so that destroy frees partial arrays */
            if (!ch->times || !ch->values)
                r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
        }
        if (r == XRSC_OK) {
            ch->node = (uint32_t)g->node;
            ch->path = g->path == SC_GLTF_PATH_TRANSLATION ? SC_ANIM_TRANSLATION
                       : g->path == SC_GLTF_PATH_ROTATION  ? SC_ANIM_ROTATION
                                                           : SC_ANIM_SCALE;
            ch->interp = g->interp == SC_GLTF_INTERP_LINEAR ? SC_INTERP_LINEAR
                         : g->interp == SC_GLTF_INTERP_STEP ? SC_INTERP_STEP
                                                            : SC_INTERP_CUBICSPLINE;
            ch->key_count = (uint32_t)tcount;
            for (size_t k = 0; k < tcount; k++) ch->times[k] = (float)times[k];
            for (size_t k = 0; k < vcount * nc; k++) ch->values[k] = (float)vals[k];
            if (ch->times[tcount - 1] > s->animation_duration_s)
                s->animation_duration_s = ch->times[tcount - 1];
            node_animated[g->node] = true;
            /* An animated node uses TRS (the spec forbids animating matrix nodes). */
            s->nodes[g->node].has_matrix = false;
        }
        free(times);
        free(vals);
        if (r != XRSC_OK) return r;
    }
    return XRSC_OK;
}

/* ---------------------------------------------------------------- instances ------------ */

/** State of the walk over the chosen scene's nodes (build_instances). */
typedef struct sc_walk {
    sc_build *b;
    int32_t *stack;     /**< nodes still to visit, at most node_count */
    uint32_t top;       /**< entries on stack */
    bool *seen;         /**< node visited */
    bool *anim_below;   /**< node or an ancestor animated */
    bool cameras_extra; /**< a perspective camera after the first one */
    int32_t *out_camera_node, *out_sun_node, *out_sun_light;
    char nonroot_field[96]; /**< the first scene list entry that is not a root, or "" */
    int32_t nonroot_node;   /**< the node it names */
} sc_walk;

/**
 * The chosen scene's list of root nodes, or every node without a parent when the file has
 * no scenes (then *out_all_roots holds the list and the caller frees it).
 */
static xrsc_result scene_roots(sc_build *b, int32_t scene_index, const int32_t **out_roots,
                               uint32_t *out_count, int32_t **out_all_roots)
{
    sc_gltf_doc *d = b->doc;
    if (scene_index >= 0) {
        const sc_gltf_scene *sc = &d->scenes[scene_index];
        if (sc->first_root > d->roots_count || sc->root_count > d->roots_count - sc->first_root)
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "scenes",
                              "internal: bad root range");
        *out_roots = sc->root_count ? d->roots + sc->first_root : NULL;
        *out_count = sc->root_count;
        return XRSC_OK;
    }
    /* No scenes: every root node is drawn. */
    int32_t *all_roots = calloc(d->node_count ? d->node_count : 1, sizeof(int32_t));
    if (!all_roots)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    uint32_t nroots = 0;
    for (uint32_t i = 0; i < d->node_count; i++)
        if (b->s->nodes[i].parent < 0)
            all_roots[nroots++] = (int32_t)i;
    *out_roots = *out_all_roots = all_roots;
    *out_count = nroots;
    return XRSC_OK;
}

/** One instance per primitive of node ni's mesh. */
static xrsc_result add_node_instances(sc_walk *w, int32_t ni, const sc_gltf_mesh *gm)
{
    sc_build *b = w->b;
    for (uint32_t p = 0; p < gm->primitive_count; p++) {
        sc_instance *inst = vec_push(&b->instances, 1);
        if (!inst)
            return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
        inst->mesh = b->prim_mesh[gm->first_primitive + p];
        inst->node = (uint32_t)ni;
        inst->animated = w->anim_below[ni];
    }
    return XRSC_OK;
}

/** Keeps the first perspective camera (node ni's); notes the others. */
static void note_camera(sc_walk *w, int32_t ni, const sc_gltf_node *g)
{
    sc_gltf_doc *d = w->b->doc;
    if (!d->cameras[g->camera].perspective)
        sc_gltf_note(d, "orthographic cameras");
    else if (*w->out_camera_node < 0)
        *w->out_camera_node = ni;
    else
        w->cameras_extra = true;
}

/** Keeps the first directional light (node ni's) as the sun; notes the others. */
static void note_light(sc_walk *w, int32_t ni, const sc_gltf_node *g)
{
    sc_gltf_doc *d = w->b->doc;
    sc_gltf_light_type t = d->lights[g->light].type;
    if (t == SC_GLTF_LIGHT_DIRECTIONAL && *w->out_sun_node < 0) {
        *w->out_sun_node = ni;
        *w->out_sun_light = g->light;
    } else if (t == SC_GLTF_LIGHT_DIRECTIONAL) {
        sc_gltf_note(d, "directional lights beyond the first");
    } else {
        sc_gltf_note(d, t == SC_GLTF_LIGHT_OTHER ? "unknown light types" : "point and spot lights");
    }
}

/**
 * Visits node ni: its instances, camera and light, then pushes its children. A failure to
 * add an instance still lets the camera and light be checked (their errors take precedence).
 */
static xrsc_result visit_node(sc_walk *w, int32_t ni)
{
    sc_build *b = w->b;
    sc_gltf_doc *d = b->doc;
    char field[96];
    xrsc_result r = XRSC_OK;
    w->seen[ni] = true;
    const sc_gltf_node *g = &d->nodes[ni];
    if (g->mesh >= 0) {
        if ((uint32_t)g->mesh >= d->mesh_count) {
            FIELD(field, "nodes[%d].mesh", ni);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "mesh %d does not exist", g->mesh);
        }
        r = add_node_instances(w, ni, &d->meshes[g->mesh]);
    }
    if (g->camera >= 0) {
        if ((uint32_t)g->camera >= d->camera_count) {
            FIELD(field, "nodes[%d].camera", ni);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "camera %d does not exist", g->camera);
        }
        note_camera(w, ni, g);
    }
    if (g->light >= 0) {
        if ((uint32_t)g->light >= d->light_count) {
            FIELD(field, "nodes[%d].extensions.KHR_lights_punctual.light", ni);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "light %d does not exist", g->light);
        }
        note_light(w, ni, g);
    }
    /* Push children in reverse so that they are visited in file order. */
    for (uint32_t k = g->child_count; k-- > 0;) {
        int32_t c = d->children[g->first_child + k];
        if (w->top < d->node_count)
            w->stack[w->top++] = c;
    }
    return r;
}

/** Walks the tree under root depth-first. */
static xrsc_result walk_root(sc_walk *w, int32_t root)
{
    xrsc_result r = XRSC_OK;
    w->top = 0;
    w->stack[w->top++] = root;
    while (r == XRSC_OK && w->top > 0)
        r = visit_node(w, w->stack[--w->top]);
    return r;
}

/** animated = node or an ancestor animated; node_order has parents first. */
static void mark_animated(const sc_scene *s, const bool *node_animated, bool *anim_below)
{
    for (uint32_t k = 0; k < s->node_count; k++) {
        uint32_t i = s->node_order[k];
        anim_below[i] = node_animated[i] ||
                        (s->nodes[i].parent >= 0 && anim_below[s->nodes[i].parent]);
    }
}

/** Walks the tree of each root that the scene's node list reaches, each root once. */
static xrsc_result walk_scene(sc_walk *w, int32_t scene_index, const int32_t *roots,
                              uint32_t nroots)
{
    sc_build *b = w->b;
    const sc_scene *s = b->s;
    char field[96];
    for (uint32_t ri = 0; ri < nroots; ri++) {
        int32_t root = roots[ri];
        FIELD(field, "scenes[%d].nodes[%u]", scene_index, ri);
        if (root < 0 || (uint32_t)root >= b->doc->node_count)
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "node %d does not exist", root);
        /* Viewers (Blender, three.js, cgltf) accept scene lists that also name non-root
         * nodes (glTF 2.0 §3.5.2 says they must be roots): draw the root each one belongs
         * to, each root once, and say so in one warning. build_nodes rejected cycles. */
        int32_t listed = root;
        while (s->nodes[root].parent >= 0) root = s->nodes[root].parent;
        if (root != listed || w->seen[root]) {
            if (!w->nonroot_field[0]) {
                snprintf(w->nonroot_field, sizeof w->nonroot_field, "%s", field);
                w->nonroot_node = listed;
            }
            if (w->seen[root])
                continue;
        }
        xrsc_result r = walk_root(w, root);
        if (r != XRSC_OK)
            return r;
    }
    return XRSC_OK;
}

/** Walks the chosen scene depth-first: instances, first perspective camera, first sun. */
static xrsc_result build_instances(sc_build *b, int32_t scene_index, const bool *node_animated,
                                   int32_t *out_camera_node, int32_t *out_sun_node,
                                   int32_t *out_sun_light)
{
    sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    *out_camera_node = *out_sun_node = *out_sun_light = -1;
    uint32_t nroots = 0;
    const int32_t *roots = NULL;
    int32_t *all_roots = NULL;
    xrsc_result r = scene_roots(b, scene_index, &roots, &nroots, &all_roots);
    if (r != XRSC_OK)
        return r;
    /* Each node has at most one parent and there are no cycles, so the stack never holds
     * more than node_count entries, and each node is visited at most once per root listing. */
    size_t n = d->node_count ? d->node_count : 1;
    sc_walk w = {.b = b,
                 .stack = calloc(n, sizeof(int32_t)),
                 .seen = calloc(n, sizeof(bool)),
                 .anim_below = calloc(n, sizeof(bool)),
                 .out_camera_node = out_camera_node,
                 .out_sun_node = out_sun_node,
                 .out_sun_light = out_sun_light,
                 .nonroot_node = -1};
    if (!w.stack || !w.seen || !w.anim_below)
        r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    if (r == XRSC_OK) {
        mark_animated(s, node_animated, w.anim_below);
        r = walk_scene(&w, scene_index, roots, nroots);
    }
    if (w.cameras_extra)
        sc_gltf_note(d, "cameras beyond the first");
    if (r == XRSC_OK && w.nonroot_field[0]) {
        U_LOG_W("%s: %s: node %d is not a root or is listed twice (glTF 2.0 §3.5.2); drawing "
                "the root nodes the scene's list reaches, each once",
                b->name, w.nonroot_field, w.nonroot_node);
        s->warning_count++;
    }
    free(w.stack);
    free(w.seen);
    free(w.anim_below);
    free(all_roots);
    return r;
}

/* ---------------------------------------------------------------- whole scene ---------- */

static float luminance(const float c[3])
{
    return SC_LUMA_R * c[0] + SC_LUMA_G * c[1] + SC_LUMA_B * c[2];
}

static bool emits(const sc_material *m)
{
    return m->emission[0] > 0.0f || m->emission[1] > 0.0f || m->emission[2] > 0.0f;
}

static xrsc_result build_emitters(sc_build *b)
{
    sc_scene *s = b->s;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const sc_instance *inst = &s->instances[i];
        const sc_mesh *m = &s->meshes[inst->mesh];
        const sc_material *mt = &s->materials[m->material];
        if (!emits(mt)) continue;
        float lum = luminance(mt->emission);
        uint32_t tris = m->index_count / 3;
        sc_emitter *e = vec_push(&b->emitters, tris);
        if (!e && tris)
            return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
        for (uint32_t t = 0; t < tris; t++) {
            float p[3][3];
            for (int k = 0; k < 3; k++)
                sc_mat4_point(inst->world, s->vertices[s->indices[m->first_index + 3 * t + k]].position,
                              p[k]);
            float e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
            float e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
            float c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                          e1[0] * e2[1] - e1[1] * e2[0]};
            float area = 0.5f * sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
            e[t].instance = i;
            e[t].primitive = t;
            e[t].power = isfinite(area) ? lum * area : 0.0f;
        }
    }
    s->emitters = b->emitters.data;
    s->emitter_count = (uint32_t)b->emitters.count;
    b->emitters.data = NULL;
    return XRSC_OK;
}

static void compute_bounds(sc_scene *s)
{
    for (int a = 0; a < 3; a++) {
        s->bounds_min[a] = FLT_MAX;
        s->bounds_max[a] = -FLT_MAX;
    }
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const sc_instance *inst = &s->instances[i];
        const sc_mesh *m = &s->meshes[inst->mesh];
        for (uint32_t k = 0; k < m->index_count; k++) {
            float p[3];
            sc_mat4_point(inst->world, s->vertices[s->indices[m->first_index + k]].position, p);
            for (int a = 0; a < 3; a++) {
                s->bounds_min[a] = fminf(s->bounds_min[a], p[a]);
                s->bounds_max[a] = fmaxf(s->bounds_max[a], p[a]);
            }
        }
    }
    if (s->bounds_min[0] > s->bounds_max[0])
        for (int a = 0; a < 3; a++) s->bounds_min[a] = s->bounds_max[a] = 0.0f;
}

/** Rotation of a world matrix (scale removed) as a quaternion. */
static void world_rotation(const float m[16], float q[4])
{
    float c[3][3];
    static const float axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 3; k++) c[i][k] = m[i * 4 + k];
        normalize3(c[i], axes[i]);
    }
    sc_quat_from_columns(c[0], c[1], c[2], q);
}

static void set_viewpoint(sc_scene *s, int32_t camera_node)
{
    if (camera_node >= 0) {
        const float *w = s->nodes[camera_node].world;
        s->has_camera = true;
        s->viewpoint_position[0] = w[12];
        s->viewpoint_position[1] = w[13];
        s->viewpoint_position[2] = w[14];
        world_rotation(w, s->viewpoint_orientation);
        return;
    }
    float hx = 0.5f * (s->bounds_max[0] - s->bounds_min[0]);
    float hy = 0.5f * (s->bounds_max[1] - s->bounds_min[1]);
    s->has_camera = false;
    s->viewpoint_position[0] = 0.5f * (s->bounds_min[0] + s->bounds_max[0]);
    s->viewpoint_position[1] = 0.5f * (s->bounds_min[1] + s->bounds_max[1]);
    s->viewpoint_position[2] = s->bounds_max[2] + SC_DEFAULT_VIEW_DISTANCE * fmaxf(hx, hy);
    s->viewpoint_orientation[0] = s->viewpoint_orientation[1] = s->viewpoint_orientation[2] = 0.0f;
    s->viewpoint_orientation[3] = 1.0f;
}

static void set_sun(sc_scene *s, const sc_gltf_doc *d, int32_t node, int32_t light)
{
    if (node < 0) return;
    const float *w = s->nodes[node].world;
    /* A directional light shines along its node's -Z; the sun is the other way (+Z). */
    float dir[3] = {w[8], w[9], w[10]};
    static const float z[3] = {0.0f, 0.0f, 1.0f};
    normalize3(dir, z);
    const sc_gltf_light *l = &d->lights[light];
    s->sun.present = true;
    memcpy(s->sun.direction, dir, sizeof dir);
    for (int c = 0; c < 3; c++) s->sun.radiance[c] = l->color[c] * l->intensity;
}

/** Warns once when nothing in the scene gives light: no emissive triangle with power, no
 *  sun, a black environment, and no KHR_materials_unlit material drawn; every frame would
 *  then be black. */
static void warn_if_no_light(sc_build *b)
{
    sc_scene *s = b->s;
    bool lit = s->sun.present && luminance(s->sun.radiance) > 0.0f;
    for (uint32_t i = 0; !lit && i < s->emitter_count; i++) lit = s->emitters[i].power > 0.0f;
    lit = lit || s->environment[0] > 0.0f || s->environment[1] > 0.0f ||
          s->environment[2] > 0.0f;
    for (uint32_t i = 0; !lit && i < s->instance_count; i++)
        lit = s->materials[s->meshes[s->instances[i].mesh].material].unlit;
    if (lit) return;
    U_LOG_W("%s: the scene has no light (no emissive material with power, no directional "
            "light, environment 0): frames will be black; give it an environment, e.g. "
            "--env 0.8,0.8,0.8",
            b->name);
    s->warning_count++;
}

/** The sky of --sky: bakes the Preetham map and replaces the file's sun with the sky's disk
 *  sun (direction: the option, else the file's sun, else SC_DEFAULT_SUN_DIRECTION). */
static xrsc_result set_sky(sc_build *b, float **out_rgb)
{
    sc_scene *s = b->s;
    static const float default_sun[3] = SC_DEFAULT_SUN_DIRECTION;
    sc_sky_options so = {.turbidity = b->opt->sky_turbidity};
    const float *dir = b->opt->sun_direction_set ? b->opt->sun_direction
                       : s->sun.present         ? s->sun.direction
                                                : default_sun;
    memcpy(so.sun_direction, dir, sizeof so.sun_direction);
    normalize3(so.sun_direction, default_sun);
    float e_sun[3];
    xrsc_result r = sc_sky_bake(&so, out_rgb, e_sun, b->diag);
    if (r != XRSC_OK) return r;
    s->sun.present = true;
    memcpy(s->sun.direction, so.sun_direction, sizeof s->sun.direction);
    memcpy(s->sun.radiance, e_sun, sizeof s->sun.radiance);
    s->sun.angular_radius_rad = SC_SUN_ANGULAR_RADIUS_RAD;
    return XRSC_OK;
}

/** Environment: a map (--env-map, else --sky) or the constant of sc_load_options. */
static xrsc_result set_environment(sc_build *b, int32_t scene_index)
{
    sc_scene *s = b->s;
    const sc_gltf_doc *d = b->doc;
    const sc_load_options *o = b->opt;
    if (o->env_map_path || o->sky) {
        sc_hdr_image img = {0};
        float *sky = NULL;
        xrsc_result r = o->env_map_path ? sc_hdr_load(o->env_map_path, &img, b->diag)
                                        : set_sky(b, &sky);
        if (r == XRSC_OK) {
            float k = o->env_intensity > 0.0f ? o->env_intensity : 1.0f;
            if (sky) /* the sky's sun with its sky */
                for (int c = 0; c < 3; c++) s->sun.radiance[c] *= k;
            r = sky ? sc_env_map_build(sky, SC_SKY_WIDTH, SC_SKY_HEIGHT, k, &s->env_map, b->diag)
                    : sc_env_map_build(img.rgb, img.width, img.height, k, &s->env_map, b->diag);
        }
        free(sky);
        sc_hdr_image_free(&img);
        if (r != XRSC_OK) return r;
        if (o->env_no_importance) s->env_map.sampling = false;
        s->env_rotation_rad = o->env_rotation_deg * (float)(3.14159265358979323846 / 180.0);
        memcpy(s->environment, s->env_map.mean_radiance, sizeof s->environment);
    } else if (o->env_set) {
        memcpy(s->environment, o->environment, sizeof s->environment);
    } else if (scene_index >= 0 && d->scenes[scene_index].has_environment) {
        memcpy(s->environment, d->scenes[scene_index].environment, sizeof s->environment);
    } else {
        /* No environment given: a neutral grey unless a directional light is the scene's
         * lighting. Emissive materials do not count (a glTF model's emissive details expect
         * image-based lighting around them: issue 11). */
        float grey = s->sun.present ? 0.0f : SC_DEFAULT_ENVIRONMENT;
        s->environment[0] = s->environment[1] = s->environment[2] = grey;
    }
    return XRSC_OK;
}

static xrsc_result build_scene(sc_build *b)
{
    sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    xrsc_result r;
    int32_t scene_index = -1;
    if (d->default_scene >= 0) {
        if ((uint32_t)d->default_scene >= d->scene_count)
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "scene",
                              "scene %d does not exist", d->default_scene);
        scene_index = d->default_scene;
    } else if (d->scene_count > 0) {
        scene_index = 0;
    }

    if ((r = build_materials(b)) != XRSC_OK) return r;
    if ((r = build_nodes(b)) != XRSC_OK) return r;

    b->prim_mesh = calloc(d->primitive_count ? d->primitive_count : 1, sizeof(uint32_t));
    if (!b->prim_mesh)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    for (uint32_t m = 0; m < d->mesh_count; m++) {
        const sc_gltf_mesh *gm = &d->meshes[m];
        if (gm->first_primitive > d->primitive_count ||
            gm->primitive_count > d->primitive_count - gm->first_primitive)
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "meshes",
                              "internal: bad primitive range");
        for (uint32_t p = 0; p < gm->primitive_count; p++)
            if ((r = build_primitive(b, m, p, gm->first_primitive + p)) != XRSC_OK) return r;
    }

    bool *node_animated = calloc(d->node_count ? d->node_count : 1, sizeof(bool));
    if (!node_animated)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    r = build_channels(b, node_animated);
    int32_t camera_node = -1, sun_node = -1, sun_light = -1;
    if (r == XRSC_OK)
        r = build_instances(b, scene_index, node_animated, &camera_node, &sun_node, &sun_light);
    free(node_animated);
    if (r != XRSC_OK) return r;

    /* Hand the growable arrays to the scene. */
    s->vertices = b->vertices.data, s->vertex_count = (uint32_t)b->vertices.count;
    s->indices = b->indices.data, s->index_count = (uint32_t)b->indices.count;
    s->meshes = b->meshes.data, s->mesh_count = (uint32_t)b->meshes.count;
    s->textures = b->textures.data, s->texture_count = (uint32_t)b->textures.count;
    s->instances = b->instances.data, s->instance_count = (uint32_t)b->instances.count;
    b->vertices.data = b->indices.data = b->meshes.data = b->textures.data = NULL;
    b->instances.data = NULL;
    b->vertices.count = b->indices.count = b->meshes.count = b->textures.count = 0;
    b->instances.count = 0;

    for (uint32_t i = 0; i < s->instance_count; i++)
        s->triangle_count += s->meshes[s->instances[i].mesh].index_count / 3;
    if (s->triangle_count == 0)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "meshes",
                          "the scene has no triangles to render");

    sc_scene_evaluate(s, 0.0);
    compute_bounds(s);
    if ((r = build_emitters(b)) != XRSC_OK) return r;
    set_sun(s, d, sun_node, sun_light);
    set_viewpoint(s, camera_node);
    if (camera_node >= 0) {
        const sc_gltf_camera *cam = &d->cameras[d->nodes[camera_node].camera];
        s->camera_yfov_rad = cam->yfov_rad;
        s->camera_aspect_ratio = cam->aspect_ratio > 0.0f ? cam->aspect_ratio : 0.0f;
    }

    if ((r = set_environment(b, scene_index)) != XRSC_OK) return r;
    warn_if_no_light(b);
    return XRSC_OK;
}

/** Directory part of path ("" for a bare file name), into buf. */
static void dir_of(const char *path, char *buf, size_t cap)
{
    const char *slash = strrchr(path, '/');
    if (!slash) {
        buf[0] = '\0';
        return;
    }
    size_t n = (size_t)(slash - path);
    if (n == 0) n = 1; /* "/file.gltf" */
    if (n >= cap) n = cap - 1;
    memcpy(buf, path, n);
    buf[n] = '\0';
}

xrsc_result sc_scene_load_memory(const char *name, const void *data, size_t size,
                                 const char *base_dir, const sc_load_options *opt,
                                 sc_scene **out, xrsc_diag *diag)
{
    if (out) *out = NULL;
    if (!out || (!data && size))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, name ? name : "", 0, "",
                          "out and data must not be NULL");
    if (!name) name = "(memory)";
    static const sc_load_options defaults = {0};
    sc_build b = {.name = name, .diag = diag, .opt = opt ? opt : &defaults};
    b.vertices.item = sizeof(sc_vertex);
    b.indices.item = sizeof(uint32_t);
    b.meshes.item = sizeof(sc_mesh);
    b.textures.item = sizeof(sc_texture);
    b.instances.item = sizeof(sc_instance);
    b.emitters.item = sizeof(sc_emitter);

    xrsc_result r = sc_gltf_parse(name, data, size, base_dir, &b.doc, diag);
    if (r != XRSC_OK) return r;
    b.s = calloc(1, sizeof(sc_scene));
    if (!b.s) r = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    if (r == XRSC_OK) {
        snprintf(b.s->path, sizeof b.s->path, "%s", name);
        r = build_scene(&b);
    }
    if (r == XRSC_OK && b.doc->unsupported[0]) {
        U_LOG_W("%s: ignored (not supported by xrsc): %s", name, b.doc->unsupported);
        b.s->warning_count++;
    }

    /* Whatever was not handed to the scene. */
    for (size_t i = 0; i < b.textures.count; i++) free(((sc_texture *)b.textures.data)[i].rgba8);
    free(b.vertices.data);
    free(b.indices.data);
    free(b.meshes.data);
    free(b.textures.data);
    free(b.instances.data);
    free(b.emitters.data);
    free(b.prim_mesh);
    free(b.tex_map);
    sc_gltf_doc_destroy(&b.doc);
    if (r != XRSC_OK) {
        sc_scene_destroy(&b.s);
        return r;
    }
    *out = b.s;
    return XRSC_OK;
}

xrsc_result sc_scene_load(const char *path, const sc_load_options *opt, sc_scene **out,
                          xrsc_diag *diag)
{
    if (out) *out = NULL;
    if (!path || !out)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0, "",
                          "path and out must not be NULL");
    FILE *f = fopen(path, "rb");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "",
                          "is a folder, not a .gltf or .glb file");
    }
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0) size = ftell(f);
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot read: %s", strerror(errno));
    }
    if ((unsigned long long)size > SC_MAX_FILE_BYTES) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, path, 0, "",
                          "%ld bytes is more than %llu", size, SC_MAX_FILE_BYTES);
    }
    if (size == 0) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, path, 0, "", "file is empty");
    }
    uint8_t *data = malloc((size_t)size);
    if (!data) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "out of memory");
    }
    size_t got = fread(data, 1, (size_t)size, f);
    fclose(f);
    if (got != (size_t)size) {
        free(data);
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "short read");
    }
    char dir[512];
    dir_of(path, dir, sizeof dir);
    xrsc_result r = sc_scene_load_memory(path, data, (size_t)size, dir, opt, out, diag);
    free(data);
    return r;
}

void sc_scene_destroy(sc_scene **pscene)
{
    if (!pscene || !*pscene) return;
    sc_scene *s = *pscene;
    for (uint32_t i = 0; i < s->texture_count; i++) free(s->textures[i].rgba8);
    for (uint32_t i = 0; i < s->channel_count; i++) {
        free(s->channels[i].times);
        free(s->channels[i].values);
    }
    free(s->vertices);
    free(s->indices);
    free(s->meshes);
    free(s->materials);
    free(s->textures);
    free(s->nodes);
    free(s->node_order);
    free(s->instances);
    free(s->emitters);
    free(s->channels);
    sc_env_map_free(&s->env_map);
    free(s);
    *pscene = NULL;
}
