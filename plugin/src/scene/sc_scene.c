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
#include "u_exr.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

/** Files larger than this are refused (tinygltf takes 32-bit lengths). */
#define SC_MAX_FILE_BYTES (2ull << 30)
/** More vertices or indices than this in one scene are refused (32-bit indices, GPU limits). */
#define SC_MAX_ELEMENTS (1u << 28)
/** Accessors without a bufferView (zeros, perhaps with sparse values) may have at most this
 *  many elements: their size is not bounded by the file's size. */
#define SC_MAX_ZERO_ELEMENTS (1u << 16)
/** More mesh instances than this are refused (EXT_mesh_gpu_instancing can ask for many): it
 *  bounds the memory a small file can claim (~150 bytes per instance on the CPU, more on the
 *  GPU) and stays below the 24 bits of a TLAS instance's instanceCustomIndex. */
#define SC_MAX_INSTANCES (1u << 22)
/** Rec. 709 luminance weights, for emitter power. */
#define SC_LUMA_R 0.2126f
#define SC_LUMA_G 0.7152f
#define SC_LUMA_B 0.0722f
/* KHR_lights_punctual: a spot's outer cone angle is at most pi/2. */
#define SC_HALF_PI 1.57079632679489662f
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

/** Makes room for n items in all (exactly, when more than now): sizes known up front spare
 *  the doubling's slack and its copies (a 1M-triangle mesh's vertices are ~150 MB). */
static bool vec_reserve(sc_vec *v, size_t n)
{
    if (n <= v->cap) return true;
    void *p = realloc(v->data, n * v->item);
    if (!p) return false;
    v->data = p;
    v->cap = n;
    return true;
}

/** State of one load. */
typedef struct sc_build {
    const char *name;
    sc_gltf_doc *doc;
    xrsc_diag *diag;
    const sc_load_options *opt;
    sc_scene *s;
    sc_vec vertices, indices, meshes, textures, instances, emitters;
    sc_vec influences, deltas; /**< sc_skin_influence, sc_morph_delta (sc_mesh) */
    sc_vec camera_nodes;      /**< int32_t: perspective camera nodes in walk order */
    uint32_t *prim_mesh;      /**< doc primitive → sc mesh, SC_SKIPPED when skipped */
    int32_t *tex_map;         /**< doc texture * 2 + srgb → sc texture, -1 unused */
    bool *image_warned;       /**< per doc image: its stand-in was warned about */
    uint32_t skipped_prims;   /**< points/lines primitives skipped */
    char skipped_field[96];   /**< the first of them */
} sc_build;

/** prim_mesh value of a primitive that is not drawn (points, lines). */
#define SC_SKIPPED UINT32_MAX

#define FIELD(buf, ...) snprintf(buf, sizeof buf, __VA_ARGS__)

/** Counts a printed warning and records its ID once (sc_scene.warning_ids). */
static void record_warning(sc_scene *s, xrsc_result id)
{
    s->warning_count++;
    for (uint32_t i = 0; i < s->warning_id_count; i++)
        if (s->warning_ids[i] == id) return;
    if (s->warning_id_count < SC_MAX_WARNING_IDS) s->warning_ids[s->warning_id_count++] = id;
}

/** Logs "file: field: message [ID]" as a warning and records the ID. */
static void sc_warn(sc_build *b, xrsc_result id, const char *field, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static void sc_warn(sc_build *b, xrsc_result id, const char *field, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    U_LOG_W("%s: %s%s%s [%s]", b->name, field, field[0] ? ": " : "", msg, xrsc_result_name(id));
    record_warning(b->s, id);
}

bool sc_scene_warned(const sc_scene *scene, xrsc_result id)
{
    for (uint32_t i = 0; scene && i < scene->warning_id_count; i++)
        if (scene->warning_ids[i] == id) return true;
    return false;
}

/** Monotonic wall clock in ms, for sc_scene.load_timing. */
static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

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
    double *pos, *nrm, *tan, *uv, *uv1, *idx; /**< uv1: TEXCOORD_1 */
    size_t vcount, ncount, tcount, uvcount, uv1count, icount;
} sc_prim_data;

static void prim_data_free(sc_prim_data *pd)
{
    free(pd->pos);
    free(pd->nrm);
    free(pd->tan);
    free(pd->uv);
    free(pd->uv1);
    free(pd->idx);
}

/** Where one primitive's vertices and indices went in the scene-wide arrays. */
typedef struct sc_prim_out {
    sc_vertex *verts;
    uint32_t *inds;
    size_t vcount, icount;
    uint32_t first_vertex, first_index;
} sc_prim_out;

/** glTF modes 0-3: POINTS, LINES, LINE_LOOP, LINE_STRIP (skipped with one warning). */
#define SC_GLTF_MODE_LAST_NON_TRIANGLE 3

/** Rejects unknown modes, a missing POSITION and a material that does not exist. */
static xrsc_result check_primitive(sc_build *b, uint32_t m, uint32_t p, const sc_gltf_primitive *pr)
{
    char field[96];
    if (pr->mode != SC_GLTF_MODE_TRIANGLES && pr->mode != SC_GLTF_MODE_TRIANGLE_STRIP &&
        pr->mode != SC_GLTF_MODE_TRIANGLE_FAN) {
        FIELD(field, "meshes[%u].primitives[%u].mode", m, p);
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "mode %d is not a glTF primitive mode (0-6)", pr->mode);
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

/** Reads POSITION, NORMAL, TEXCOORD_0, TEXCOORD_1 and TANGENT into pd and checks that their
 *  counts agree. */
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
    if (r == XRSC_OK && pr->texcoord1 >= 0) {
        FIELD(field, "meshes[%u].primitives[%u].attributes.TEXCOORD_1", m, p);
        r = read_accessor(b, pr->texcoord1, 2, field, &pd->uv1, &pd->uv1count);
        if (r == XRSC_OK && pd->uv1count != pd->vcount)
            r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                           "TEXCOORD_1 has %zu elements, POSITION %zu", pd->uv1count, pd->vcount);
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

/** The uv sets of file vertex src: TEXCOORD_0 ((0,0) when absent) and TEXCOORD_1 (a copy of
 *  set 0 when absent, so that a texture that names set 1 still gets a mapping). */
static void fill_uv(const sc_prim_data *pd, size_t src, sc_vertex *v)
{
    if (pd->uv) v->uv[0] = (float)pd->uv[src * 2], v->uv[1] = (float)pd->uv[src * 2 + 1];
    const double *uv1 = pd->uv1 ? pd->uv1 + src * 2 : NULL;
    v->uv1[0] = uv1 ? (float)uv1[0] : v->uv[0];
    v->uv1[1] = uv1 ? (float)uv1[1] : v->uv[1];
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
        fill_uv(pd, i, v);
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
            fill_uv(pd, src, v);
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
    mesh->deform_node = SC_NO_DEFORM;
    b->prim_mesh[gp] = (uint32_t)(b->meshes.count - 1);
    return XRSC_OK;
}

/* ---------------------------------------------------------------- skins, morph targets -- */

/** The file vertex that vertex i of the primitive came from (without NORMAL the triangles
 *  are unwelded: fill_flat_vertices). */
static size_t source_vertex(const sc_prim_data *pd, size_t i)
{
    return pd->nrm ? i : pd->idx ? (size_t)pd->idx[i] : i;
}

/** Reads a per-vertex accessor (comps per element) and checks its count against POSITION. */
static xrsc_result read_per_vertex(sc_build *b, int32_t idx, uint32_t comps, const char *field,
                                   const sc_prim_data *pd, double **out)
{
    size_t n = 0;
    xrsc_result r = read_accessor(b, idx, comps, field, out, &n);
    if (r == XRSC_OK && n != pd->vcount)
        r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                       "%zu elements, POSITION has %zu", n, pd->vcount);
    return r;
}

/** Every JOINTS_n / WEIGHTS_n pair of the primitive into b->influences (the last mesh). */
static xrsc_result read_skin_sets(sc_build *b, uint32_t m, uint32_t p,
                                  const sc_gltf_primitive *pr, const sc_prim_data *pd)
{
    sc_mesh *mesh = (sc_mesh *)b->meshes.data + b->meshes.count - 1;
    char field[96];
    mesh->first_influence = (uint32_t)b->influences.count;
    for (int k = 0; k < SC_GLTF_MAX_JOINT_SETS; k++) {
        if (pr->joints[k] < 0 || pr->weights[k] < 0) continue;
        double *j = NULL, *w = NULL;
        FIELD(field, "meshes[%u].primitives[%u].attributes.JOINTS_%d", m, p, k);
        xrsc_result r = read_per_vertex(b, pr->joints[k], 4, field, pd, &j);
        FIELD(field, "meshes[%u].primitives[%u].attributes.WEIGHTS_%d", m, p, k);
        if (r == XRSC_OK) r = read_per_vertex(b, pr->weights[k], 4, field, pd, &w);
        sc_skin_influence *in = r == XRSC_OK ? vec_push(&b->influences, mesh->vertex_count) : NULL;
        if (r == XRSC_OK && !in)
            r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
        for (uint32_t v = 0; r == XRSC_OK && v < mesh->vertex_count; v++) {
            size_t src = source_vertex(pd, v);
            for (int c = 0; c < 4; c++) {
                double jv = j[src * 4 + c];
                in[v].joints[c] = jv >= 0.0 && jv < (double)UINT32_MAX ? (uint32_t)jv : UINT32_MAX;
                in[v].weights[c] = (float)w[src * 4 + c];
            }
        }
        free(j);
        free(w);
        if (r != XRSC_OK) return r;
        mesh->skin_sets++;
    }
    return XRSC_OK;
}

/** The primitive's morph targets (POSITION / NORMAL / TANGENT deltas) into b->deltas. */
static xrsc_result read_targets(sc_build *b, uint32_t m, uint32_t p, const sc_gltf_primitive *pr,
                                const sc_prim_data *pd)
{
    static const char *const names[3] = {"POSITION", "NORMAL", "TANGENT"};
    const sc_gltf_doc *d = b->doc;
    sc_mesh *mesh = (sc_mesh *)b->meshes.data + b->meshes.count - 1;
    char field[112];
    if (pr->first_target > d->target_count || pr->target_count > d->target_count - pr->first_target)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "meshes",
                          "internal: bad morph target range");
    mesh->first_delta = (uint32_t)b->deltas.count;
    for (uint32_t t = 0; t < pr->target_count; t++) {
        const sc_gltf_target *gt = &d->targets[pr->first_target + t];
        const int32_t acc[3] = {gt->position, gt->normal, gt->tangent};
        if (!vec_push(&b->deltas, mesh->vertex_count))
            return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
        sc_morph_delta *dl = (sc_morph_delta *)b->deltas.data + b->deltas.count - mesh->vertex_count;
        for (int a = 0; a < 3; a++) {
            if (acc[a] < 0) continue;
            double *v = NULL;
            FIELD(field, "meshes[%u].primitives[%u].targets[%u].%s", m, p, t, names[a]);
            xrsc_result r = read_per_vertex(b, acc[a], 3, field, pd, &v);
            if (r != XRSC_OK) return r;
            for (uint32_t i = 0; i < mesh->vertex_count; i++) {
                float *dst = a == 0 ? dl[i].position : a == 1 ? dl[i].normal : dl[i].tangent;
                for (int c = 0; c < 3; c++) dst[c] = (float)v[source_vertex(pd, i) * 3 + c];
            }
            free(v);
        }
        mesh->target_count++;
    }
    return XRSC_OK;
}

/** Builds the sc_mesh of document primitive gp (mesh m, primitive p). */
static xrsc_result build_primitive(sc_build *b, uint32_t m, uint32_t p, uint32_t gp)
{
    const sc_gltf_primitive *pr = &b->doc->primitives[gp];
    if (pr->mode >= 0 && pr->mode <= SC_GLTF_MODE_LAST_NON_TRIANGLE) {
        /* Points and lines have no surface for a ray to hit: skipped (one warning). */
        if (b->skipped_prims++ == 0)
            FIELD(b->skipped_field, "meshes[%u].primitives[%u].mode", m, p);
        b->prim_mesh[gp] = SC_SKIPPED;
        return XRSC_OK;
    }
    xrsc_result r = check_primitive(b, m, p, pr);
    if (r != XRSC_OK)
        return r;
    sc_prim_data pd = {0};
    sc_prim_out o = {0};
    sc_load_timing *t = &b->s->load_timing;
    double t0 = now_ms();
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
        double t1 = now_ms();
        t->geometry_ms += t1 - t0;
        r = finish_tangents(b, &pd, &o);
        t0 = now_ms();
        t->tangents_ms += t0 - t1;
    }
    if (r == XRSC_OK && !b->opt->keep_triangle_order &&
        !sc_morton_sort_triangles((const sc_vertex *)b->vertices.data, o.inds, (uint32_t)o.icount))
        r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    t->morton_ms += now_ms() - t0;
    if (r == XRSC_OK)
        r = add_mesh(b, pr, gp, &o);
    if (r == XRSC_OK)
        r = read_skin_sets(b, m, p, pr, &pd);
    if (r == XRSC_OK)
        r = read_targets(b, m, p, pr, &pd);
    prim_data_free(&pd);
    return r;
}

/* ---------------------------------------------------------------- materials ------------ */

/** glTF sampler values → sc_sampler (unknown values: the defaults). */
static sc_sampler sampler_of(const sc_gltf_texture *t)
{
    sc_sampler sm = {0};
    const int32_t wraps[2] = {t->wrap_s, t->wrap_t};
    sc_wrap *dst[2] = {&sm.wrap_u, &sm.wrap_v};
    for (int k = 0; k < 2; k++)
        *dst[k] = wraps[k] == SC_GLTF_WRAP_CLAMP_TO_EDGE     ? SC_WRAP_CLAMP_TO_EDGE
                  : wraps[k] == SC_GLTF_WRAP_MIRRORED_REPEAT ? SC_WRAP_MIRRORED_REPEAT
                                                             : SC_WRAP_REPEAT;
    /* 9728 NEAREST, 9984 NEAREST_MIPMAP_NEAREST, 9986 NEAREST_MIPMAP_LINEAR: nearest texels. */
    sm.mag_nearest = t->mag_filter == SC_GLTF_FILTER_NEAREST;
    sm.min_nearest = t->min_filter == SC_GLTF_FILTER_NEAREST || t->min_filter == 9984 ||
                     t->min_filter == 9986;
    return sm;
}

/** The decoded image of a texture reference, or NULL after warning (once per image) that
 *  the slot is stood in for (treated as absent). */
static const sc_gltf_image *texture_image(sc_build *b, sc_gltf_texref ref, const char *field)
{
    sc_gltf_doc *d = b->doc;
    int32_t img = d->textures[ref.texture].image;
    if (img < 0 || (uint32_t)img >= d->image_count) {
        sc_gltf_note(d, "textures without a PNG/JPEG source");
        return NULL;
    }
    const sc_gltf_image *im = &d->images[img];
    if (im->rgba8) return im;
    if (!b->image_warned[img]) {
        b->image_warned[img] = true;
        if (im->missing)
            sc_warn(b, XRSC_WARN_GLTF_IMAGE_MISSING, field,
                    "images[%d] file '%s' is missing; the texture is left out (white base "
                    "colour, flat normal: the factors alone)",
                    img, im->uri);
        else
            sc_warn(b, XRSC_WARN_GLTF_IMAGE_UNDECODABLE, field,
                    "images[%d] ('%s') cannot be decoded (xrsc reads PNG, JPEG and what "
                    "stb_image reads, up to 8k x 8k); the texture is left out",
                    img, im->uri[0] ? im->uri : "bufferView");
    }
    return NULL;
}

/** Appends a texture with a copy of (or, when px_owned, ownership of) the pixels. */
static xrsc_result push_texture(sc_build *b, uint32_t w, uint32_t h, const uint8_t *px,
                                uint8_t *px_owned, bool srgb, sc_sampler sm, uint32_t *out)
{
    sc_texture *t = vec_push(&b->textures, 1);
    size_t bytes = (size_t)w * h * 4;
    uint8_t *copy = px_owned ? px_owned : t ? malloc(bytes) : NULL;
    if (!t || !copy) {
        if (t) b->textures.count--;
        free(px_owned);
        if (!px_owned) free(copy);
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    }
    if (!px_owned) memcpy(copy, px, bytes);
    *t = (sc_texture){.width = w, .height = h, .rgba8 = copy, .srgb = srgb, .sampler = sm};
    *out = (uint32_t)(b->textures.count - 1);
    return XRSC_OK;
}

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
    if (ref.tex_coord > 1) return XRSC_OK; /* noted by sc_gltf.cpp */
    const sc_gltf_image *im = texture_image(b, ref, field);
    if (!im) return XRSC_OK;
    int32_t *slot = &b->tex_map[(size_t)ref.texture * 2 + (srgb ? 1 : 0)];
    if (*slot < 0) {
        uint32_t idx;
        xrsc_result r = push_texture(b, im->width, im->height, im->rgba8, NULL, srgb,
                                     sampler_of(&d->textures[ref.texture]), &idx);
        if (r != XRSC_OK) return r;
        *slot = (int32_t)idx;
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

/* KHR_materials_pbrSpecularGlossiness → metal/rough, with the conversion published beside
 * the extension (KhronosGroup/glTF, extensions/2.0/Archived/KHR_materials_pbrSpecularGlossiness,
 * examples/convert-between-workflows, three.pbrUtilities.js): metallic solved from the
 * perceived brightness of diffuse and specular against a dielectric's F0, the base colour
 * blended between the diffuse and the specular estimate by metallic^2, roughness =
 * 1 - glossiness. */
#define SC_DIELECTRIC_F0 0.04f
#define SC_SG_EPSILON 1e-6f

static float clamp01(float v) { return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v; }

static float perceived_brightness(const float c[3])
{
    return sqrtf(0.299f * c[0] * c[0] + 0.587f * c[1] * c[1] + 0.114f * c[2] * c[2]);
}

static float solve_metallic(float diffuse, float specular, float one_minus_specular_strength)
{
    if (specular < SC_DIELECTRIC_F0) return 0.0f;
    float a = SC_DIELECTRIC_F0;
    float bq = diffuse * one_minus_specular_strength / (1.0f - SC_DIELECTRIC_F0) + specular -
               2.0f * SC_DIELECTRIC_F0;
    float c = SC_DIELECTRIC_F0 - specular;
    float disc = fmaxf(bq * bq - 4.0f * a * c, 0.0f);
    return clamp01((-bq + sqrtf(disc)) / (2.0f * a));
}

static float max3(const float c[3]) { return fmaxf(c[0], fmaxf(c[1], c[2])); }

/** Converts spec-gloss factors: base colour (rgb), metallic and roughness. */
static void spec_gloss_factors(const float diffuse[3], const float specular[3], float gloss,
                               float base[3], float *metallic, float *roughness)
{
    float oms = 1.0f - max3(specular);
    float m = solve_metallic(perceived_brightness(diffuse), perceived_brightness(specular), oms);
    for (int c = 0; c < 3; c++) {
        float from_d = diffuse[c] * oms / (1.0f - SC_DIELECTRIC_F0) / fmaxf(1.0f - m, SC_SG_EPSILON);
        float from_s = (specular[c] - SC_DIELECTRIC_F0 * (1.0f - m)) / fmaxf(m, SC_SG_EPSILON);
        base[c] = clamp01(from_d + (from_s - from_d) * m * m);
    }
    *metallic = m;
    *roughness = clamp01(1.0f - gloss);
}

static float srgb_to_linear(float v)
{
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

/** specularGlossinessTexture alone → a metal/rough texture (G roughness, B metallic), per
 *  texel with the factors applied; metallic is solved against the diffuse *factor* (the
 *  approximation used when the diffuse texture does not pair up with it). */
static xrsc_result spec_gloss_texture(sc_build *b, const sc_gltf_material *g, const char *field,
                                      uint32_t *out)
{
    *out = SC_NO_TEXTURE;
    sc_gltf_texref ref = g->spec_gloss_tex;
    if (ref.texture < 0) return XRSC_OK;
    if ((uint32_t)ref.texture >= b->doc->texture_count)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                          "texture %d does not exist", ref.texture);
    if (ref.tex_coord > 1) return XRSC_OK;
    const sc_gltf_image *im = texture_image(b, ref, field);
    if (!im) return XRSC_OK;
    size_t n = (size_t)im->width * im->height;
    uint8_t *px = malloc(n * 4);
    if (!px) return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, field, "out of memory");
    float lut[256], diffuse_b = perceived_brightness(g->diffuse);
    for (int i = 0; i < 256; i++) lut[i] = srgb_to_linear(i / 255.0f);
    for (size_t i = 0; i < n; i++) {
        const uint8_t *t = im->rgba8 + 4 * i;
        float spec[3];
        for (int c = 0; c < 3; c++) spec[c] = lut[t[c]] * g->sg_specular[c];
        float m = solve_metallic(diffuse_b, perceived_brightness(spec), 1.0f - max3(spec));
        float rough = clamp01(1.0f - t[3] / 255.0f * g->glossiness);
        px[4 * i] = 255;
        px[4 * i + 1] = (uint8_t)lrintf(rough * 255.0f);
        px[4 * i + 2] = (uint8_t)lrintf(m * 255.0f);
        px[4 * i + 3] = 255;
    }
    return push_texture(b, im->width, im->height, NULL, px, false,
                        sampler_of(&b->doc->textures[ref.texture]), out);
}

/** Entries of the linear → 8-bit sRGB table of spec_gloss_per_texel. */
#define SC_SRGB_LUT 4096

static bool same_mapping(const sc_gltf_texref *a, const sc_gltf_texref *b)
{
    return a->tex_coord == b->tex_coord && a->offset[0] == b->offset[0] &&
           a->offset[1] == b->offset[1] && a->rotation_rad == b->rotation_rad &&
           a->scale[0] == b->scale[0] && a->scale[1] == b->scale[1];
}

/**
 * The exact conversion per texel when the diffuse and the specular-glossiness textures pair
 * up (both decoded, same size, same UV mapping, as exporters write them): a new base colour
 * texture (sRGB, alpha = diffuse alpha) and a metal/rough texture; the factors become 1.
 * *done false (nothing changed) when they do not pair up.
 */
static xrsc_result spec_gloss_per_texel(sc_build *b, const sc_gltf_material *g,
                                        const char *field, sc_material *mt, bool *done)
{
    *done = false;
    const sc_gltf_texref *dr = &g->diffuse_tex, *sr = &g->spec_gloss_tex;
    uint32_t tc = b->doc->texture_count;
    if (dr->texture < 0 || sr->texture < 0 || (uint32_t)dr->texture >= tc ||
        (uint32_t)sr->texture >= tc || dr->tex_coord > 1 || !same_mapping(dr, sr))
        return XRSC_OK;
    const sc_gltf_image *di = texture_image(b, *dr, field), *si = texture_image(b, *sr, field);
    if (!di || !si || di->width != si->width || di->height != si->height) return XRSC_OK;
    size_t n = (size_t)di->width * di->height;
    uint8_t *base = malloc(n * 4), *mr = malloc(n * 4), enc[SC_SRGB_LUT];
    if (!base || !mr) {
        free(base);
        free(mr);
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, field, "out of memory");
    }
    float lut[256];
    for (int k = 0; k < 256; k++) lut[k] = srgb_to_linear(k / 255.0f);
    for (int k = 0; k < SC_SRGB_LUT; k++) {
        float v = (float)k / (SC_SRGB_LUT - 1);
        v = v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
        enc[k] = (uint8_t)lrintf(clamp01(v) * 255.0f);
    }
    for (size_t i = 0; i < n; i++) {
        const uint8_t *dt = di->rgba8 + 4 * i, *st = si->rgba8 + 4 * i;
        float dif[3], spec[3], out[3], m, r;
        for (int c = 0; c < 3; c++)
            dif[c] = lut[dt[c]] * g->diffuse[c], spec[c] = lut[st[c]] * g->sg_specular[c];
        spec_gloss_factors(dif, spec, st[3] / 255.0f * g->glossiness, out, &m, &r);
        for (int c = 0; c < 3; c++) base[4 * i + c] = enc[lrintf(out[c] * (SC_SRGB_LUT - 1))];
        base[4 * i + 3] = (uint8_t)lrintf(clamp01(dt[3] / 255.0f * g->diffuse[3]) * 255.0f);
        mr[4 * i] = 255;
        mr[4 * i + 1] = (uint8_t)lrintf(r * 255.0f);
        mr[4 * i + 2] = (uint8_t)lrintf(m * 255.0f);
        mr[4 * i + 3] = 255;
    }
    xrsc_result res = push_texture(b, di->width, di->height, NULL, base, true,
                                   sampler_of(&b->doc->textures[dr->texture]), &mt->base_color_tex);
    if (res == XRSC_OK)
        res = push_texture(b, si->width, si->height, NULL, mr, false,
                           sampler_of(&b->doc->textures[sr->texture]), &mt->metal_rough_tex);
    else
        free(mr);
    if (res != XRSC_OK) return res;
    for (int c = 0; c < 4; c++) mt->base_color[c] = 1.0f;
    mt->metallic = mt->roughness = 1.0f;
    *done = true;
    return XRSC_OK;
}

/** A KHR_materials_pbrSpecularGlossiness material as metal/rough (see above): exact per
 *  texel when its two textures pair up, else the factors converted, the diffuse texture as
 *  the base colour texture and the spec-gloss texture converted alone (spec_gloss_texture). */
static xrsc_result convert_spec_gloss(sc_build *b, uint32_t i, const sc_gltf_material *g,
                                      sc_material *mt)
{
    char field[96];
    FIELD(field, "materials[%u].extensions.KHR_materials_pbrSpecularGlossiness", i);
    uv_transform(&g->diffuse_tex, mt->uv_transform[SC_TEX_BASE]);
    uv_transform(&g->spec_gloss_tex, mt->uv_transform[SC_TEX_METAL_ROUGH]);
    bool done;
    xrsc_result pr = spec_gloss_per_texel(b, g, field, mt, &done);
    if (pr != XRSC_OK || done) return pr;
    spec_gloss_factors(g->diffuse, g->sg_specular, g->glossiness, mt->base_color, &mt->metallic,
                       &mt->roughness);
    mt->base_color[3] = g->diffuse[3];
    FIELD(field, "materials[%u].extensions.KHR_materials_pbrSpecularGlossiness.diffuseTexture", i);
    xrsc_result r = map_texture(b, g->diffuse_tex, true, field, &mt->base_color_tex);
    if (r != XRSC_OK) return r;
    FIELD(field,
          "materials[%u].extensions.KHR_materials_pbrSpecularGlossiness.specularGlossinessTexture",
          i);
    r = spec_gloss_texture(b, g, field, &mt->metal_rough_tex);
    if (r == XRSC_OK && mt->metal_rough_tex != SC_NO_TEXTURE)
        mt->metallic = mt->roughness = 1.0f; /* the texture carries the converted values */
    return r;
}

/** The KHR_materials_specular / _clearcoat / _sheen / _volume values and the transmission
 *  texture of material i. */
static xrsc_result build_material_extensions(sc_build *b, uint32_t i, sc_material *mt)
{
    const sc_gltf_material *g = &b->doc->materials[i];
    mt->specular = g->specular;
    mt->clearcoat = g->clearcoat;
    mt->clearcoat_roughness = g->clearcoat_roughness;
    mt->sheen_roughness = g->sheen_roughness;
    mt->thickness = g->thickness;
    for (int c = 0; c < 3; c++) {
        mt->specular_color[c] = g->specular_color[c];
        mt->sheen_color[c] = g->sheen_color[c];
        /* Beer-Lambert: transmittance attenuationColor after attenuationDistance metres */
        float ac = g->attenuation_color[c];
        float ad = g->attenuation_distance;
        mt->sigma_a[c] = ad > 0.0f && ac < 1.0f ? -logf(fmaxf(ac, 1e-6f)) / ad : 0.0f;
    }
    static const struct {
        size_t ref, out;
        bool srgb;
        const char *name;
    } tex[] = {
        {offsetof(sc_gltf_material, transmission_tex), offsetof(sc_material, transmission_tex),
         false, "KHR_materials_transmission.transmissionTexture"},
        {offsetof(sc_gltf_material, specular_tex), offsetof(sc_material, specular_tex), false,
         "KHR_materials_specular.specularTexture"},
        {offsetof(sc_gltf_material, specular_color_tex),
         offsetof(sc_material, specular_color_tex), true,
         "KHR_materials_specular.specularColorTexture"},
        {offsetof(sc_gltf_material, clearcoat_tex), offsetof(sc_material, clearcoat_tex), false,
         "KHR_materials_clearcoat.clearcoatTexture"},
        {offsetof(sc_gltf_material, clearcoat_rough_tex),
         offsetof(sc_material, clearcoat_rough_tex), false,
         "KHR_materials_clearcoat.clearcoatRoughnessTexture"},
        {offsetof(sc_gltf_material, sheen_color_tex), offsetof(sc_material, sheen_color_tex),
         true, "KHR_materials_sheen.sheenColorTexture"},
        {offsetof(sc_gltf_material, sheen_rough_tex), offsetof(sc_material, sheen_rough_tex),
         false, "KHR_materials_sheen.sheenRoughnessTexture"},
    };
    for (size_t k = 0; k < sizeof tex / sizeof tex[0]; k++) {
        char field[128];
        FIELD(field, "materials[%u].extensions.%s.index", i, tex[k].name);
        const sc_gltf_texref *ref = (const sc_gltf_texref *)((const char *)g + tex[k].ref);
        uint32_t *out = (uint32_t *)((char *)mt + tex[k].out);
        xrsc_result r = map_texture(b, *ref, tex[k].srgb, field, out);
        if (r != XRSC_OK)
            return r;
    }
    return XRSC_OK;
}

/** sc_material.uv1_mask: the textures drawn whose texCoord is 1 (spec-gloss's diffuse and
 *  specular-glossiness textures fill the base colour and metal/rough slots). */
static uint32_t uv1_mask(const sc_gltf_material *g, const sc_material *mt)
{
    const struct {
        const sc_gltf_texref *ref;
        uint32_t tex, bit;
    } t[] = {
        {g->spec_gloss ? &g->diffuse_tex : &g->base_color_tex, mt->base_color_tex, SC_TEX_BASE},
        {g->spec_gloss ? &g->spec_gloss_tex : &g->metal_rough_tex, mt->metal_rough_tex,
         SC_TEX_METAL_ROUGH},
        {&g->emissive_tex, mt->emission_tex, SC_TEX_EMISSION},
        {&g->normal_tex, mt->normal_tex, SC_TEX_NORMAL},
        {&g->transmission_tex, mt->transmission_tex, SC_UV1_TRANSMISSION},
        {&g->specular_tex, mt->specular_tex, SC_UV1_SPECULAR},
        {&g->specular_color_tex, mt->specular_color_tex, SC_UV1_SPECULAR_COLOR},
        {&g->clearcoat_tex, mt->clearcoat_tex, SC_UV1_CLEARCOAT},
        {&g->clearcoat_rough_tex, mt->clearcoat_rough_tex, SC_UV1_CLEARCOAT_ROUGH},
        {&g->sheen_color_tex, mt->sheen_color_tex, SC_UV1_SHEEN_COLOR},
        {&g->sheen_rough_tex, mt->sheen_rough_tex, SC_UV1_SHEEN_ROUGH},
    };
    uint32_t mask = 0;
    for (size_t k = 0; k < sizeof t / sizeof t[0]; k++)
        if (t[k].tex != SC_NO_TEXTURE && t[k].ref->tex_coord == 1) mask |= 1u << t[k].bit;
    return mask;
}

static xrsc_result build_materials(sc_build *b)
{
    sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    s->material_count = d->material_count + 1; /* + the glTF default material */
    s->materials = calloc(s->material_count, sizeof(sc_material));
    b->tex_map = malloc(sizeof(int32_t) * 2 * (d->texture_count + 1));
    b->image_warned = calloc(d->image_count + 1, sizeof(bool));
    if (!s->materials || !b->tex_map || !b->image_warned)
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
        if (g->spec_gloss && (r = convert_spec_gloss(b, i, g, mt)) != XRSC_OK) return r;
        if ((r = build_material_extensions(b, i, mt)) != XRSC_OK)
            return r;
        mt->uv1_mask = uv1_mask(g, mt);
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
    def->specular = 1.0f;
    for (int c = 0; c < 3; c++) def->specular_color[c] = 1.0f;
    def->transmission_tex = def->specular_tex = def->specular_color_tex = SC_NO_TEXTURE;
    def->clearcoat_tex = def->clearcoat_rough_tex = SC_NO_TEXTURE;
    def->sheen_color_tex = def->sheen_rough_tex = SC_NO_TEXTURE;
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

/** The glTF skins: joint nodes and inverse bind matrices (identity when absent). */
static xrsc_result build_skins(sc_build *b)
{
    const sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    char field[96];
    s->skins = calloc(d->skin_count ? d->skin_count : 1, sizeof(sc_skin));
    s->skin_joints = calloc(d->skin_joint_count ? d->skin_joint_count : 1, sizeof(uint32_t));
    s->inverse_binds = calloc((d->skin_joint_count ? d->skin_joint_count : 1) * 16, sizeof(float));
    if (!s->skins || !s->skin_joints || !s->inverse_binds)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    s->skin_count = d->skin_count;
    s->skin_joint_total = d->skin_joint_count;
    for (uint32_t k = 0; k < d->skin_count; k++) {
        const sc_gltf_skin *g = &d->skins[k];
        s->skins[k] = (sc_skin){g->first_joint, g->joint_count};
        for (uint32_t j = 0; j < g->joint_count; j++) {
            int32_t node = d->skin_joints[g->first_joint + j];
            FIELD(field, "skins[%u].joints[%u]", k, j);
            if (node < 0 || (uint32_t)node >= d->node_count)
                return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                                  "node %d does not exist", node);
            s->skin_joints[g->first_joint + j] = (uint32_t)node;
            sc_mat4_identity(&s->inverse_binds[16 * (g->first_joint + j)]);
        }
        if (g->inverse_bind_matrices < 0) continue;
        double *ibm = NULL;
        size_t n = 0;
        FIELD(field, "skins[%u].inverseBindMatrices", k);
        xrsc_result r = read_accessor(b, g->inverse_bind_matrices, 16, field, &ibm, &n);
        if (r == XRSC_OK && n < g->joint_count)
            r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                           "%zu matrices for %u joints", n, g->joint_count);
        for (size_t i = 0; r == XRSC_OK && i < 16 * (size_t)g->joint_count; i++)
            s->inverse_binds[16 * (size_t)g->first_joint + i] = (float)ibm[i];
        free(ibm);
        if (r != XRSC_OK) return r;
    }
    return XRSC_OK;
}

/** Morph targets of document mesh `mesh` (the most over its primitives); 0 when invalid. */
static uint32_t mesh_target_count(const sc_gltf_doc *d, int32_t mesh)
{
    uint32_t n = 0;
    if (mesh < 0 || (uint32_t)mesh >= d->mesh_count) return 0;
    const sc_gltf_mesh *gm = &d->meshes[mesh];
    for (uint32_t p = 0; p < gm->primitive_count && gm->first_primitive + p < d->primitive_count; p++)
        if (d->primitives[gm->first_primitive + p].target_count > n)
            n = d->primitives[gm->first_primitive + p].target_count;
    return n;
}

/** Each node's skin and morph weights: node.weights, else its mesh's weights, else 0. */
static xrsc_result build_node_deform(sc_build *b)
{
    const sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    char field[96];
    size_t total = 0;
    for (uint32_t i = 0; i < d->node_count; i++) total += mesh_target_count(d, d->nodes[i].mesh);
    s->node_weights = calloc(total ? total : 1, sizeof(float));
    if (!s->node_weights)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    for (uint32_t i = 0; i < d->node_count; i++) {
        const sc_gltf_node *g = &d->nodes[i];
        sc_node *n = &s->nodes[i];
        n->skin = -1;
        if (g->skin >= 0 && g->mesh >= 0) {
            FIELD(field, "nodes[%u].skin", i);
            if ((uint32_t)g->skin >= d->skin_count)
                return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                                  "skin %d does not exist", g->skin);
            n->skin = g->skin;
        }
        uint32_t count = mesh_target_count(d, g->mesh);
        n->first_weight = s->node_weight_count;
        n->weight_count = count;
        const sc_gltf_mesh *gm = count ? &d->meshes[g->mesh] : NULL;
        uint32_t from = g->weight_count == count   ? g->first_weight
                        : gm && gm->weight_count == count ? gm->first_weight
                                                          : UINT32_MAX;
        for (uint32_t k = 0; k < count; k++)
            s->node_weights[n->first_weight + k] = from != UINT32_MAX ? d->weights[from + k] : 0.0f;
        s->node_weight_count += count;
    }
    return XRSC_OK;
}

/** Marks node ni as the deforming node of the mesh of instance inst (the first node wins). */
static void note_deform(sc_build *b, int32_t ni, sc_instance *inst)
{
    sc_mesh *mesh = (sc_mesh *)b->meshes.data + inst->mesh;
    bool skinned = mesh->skin_sets && b->s->nodes[ni].skin >= 0;
    if (!skinned && mesh->target_count == 0) return;
    /* A morph-only mesh moves when its node's weights play (anim_below, as T/R/S); a skinned
     * one whenever the clip that plays moves anything (its joints may be anywhere). */
    if (skinned)
        inst->animated = inst->animated || b->s->animation_duration_s > 0.0f;
    if (mesh->deform_node == SC_NO_DEFORM)
        mesh->deform_node = (uint32_t)ni;
    else if (mesh->deform_node != (uint32_t)ni)
        sc_gltf_note(b->doc, "a skinned or morphed mesh on several nodes (all show the first's "
                             "pose)");
}

/** Checks the joints of mesh m's influences and places its pose in the pose arrays. */
static xrsc_result finish_mesh_deform(sc_build *b, sc_mesh *mesh, uint32_t *nm, uint32_t *nw)
{
    sc_scene *s = b->s;
    char field[96];
    const sc_node *n = &s->nodes[mesh->deform_node];
    if (n->skin < 0) mesh->skin_sets = 0;
    mesh->skin_joint_count = mesh->skin_sets ? s->skins[n->skin].joint_count : 0;
    /* NULL when no mesh of the file is skinned (morph targets only): no offset from it */
    sc_skin_influence *in = mesh->skin_sets ? s->influences + mesh->first_influence : NULL;
    for (size_t i = 0; i < (size_t)mesh->skin_sets * mesh->vertex_count; i++)
        for (int c = 0; c < 4; c++) {
            if (in[i].weights[c] == 0.0f) in[i].joints[c] = 0;
            if (in[i].joints[c] < mesh->skin_joint_count) continue;
            FIELD(field, "nodes[%u].skin", mesh->deform_node);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "a JOINTS_n value %u is not below the skin's %u joints",
                              in[i].joints[c], mesh->skin_joint_count);
        }
    mesh->first_pose_matrix = *nm;
    mesh->first_pose_weight = *nw;
    *nm += mesh->skin_joint_count;
    *nw += mesh->target_count;
    return XRSC_OK;
}

/** After the instances: every deformed mesh's pose slots (sc_mesh, sc_scene.pose_*). */
static xrsc_result finish_deform(sc_build *b)
{
    sc_scene *s = b->s;
    uint32_t nm = 0, nw = 0;
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        sc_mesh *mesh = &s->meshes[m];
        if (mesh->deform_node == SC_NO_DEFORM) continue;
        xrsc_result r = finish_mesh_deform(b, mesh, &nm, &nw);
        if (r != XRSC_OK) return r;
        if (mesh->skin_sets == 0 && mesh->target_count == 0)
            mesh->deform_node = SC_NO_DEFORM;
        else
            s->deform_mesh_count++;
    }
    s->pose_matrices = calloc((size_t)(nm ? nm : 1) * 16, sizeof(float));
    s->pose_weights = calloc(nw ? nw : 1, sizeof(float));
    if (!s->pose_matrices || !s->pose_weights)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    s->pose_matrix_count = nm;
    s->pose_weight_count = nw;
    return XRSC_OK;
}

/* ---------------------------------------------------------------- animation ------------ */

/** The file's clips (names, channel counts, durations) and the one that plays
 *  (sc_load_options.animation). A clip whose inputs cannot be read gets the duration of the
 *  rest; only the clip that plays must be valid (build_channels). */
static xrsc_result build_clips(sc_build *b)
{
    sc_gltf_doc *d = b->doc;
    sc_scene *s = b->s;
    s->clips = calloc(d->clip_count ? d->clip_count : 1, sizeof(sc_clip));
    if (!s->clips)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    s->clip_count = d->clip_count;
    xrsc_diag scratch = {0}, *diag = b->diag;
    b->diag = &scratch; /* a clip's unreadable input is not an error here */
    for (uint32_t i = 0; i < d->clip_count; i++) {
        const sc_gltf_clip *g = &d->clips[i];
        sc_clip *c = &s->clips[i];
        snprintf(c->name, sizeof c->name, "%s", g->name);
        c->channel_count = g->channel_count;
        for (uint32_t k = g->first_channel;
             k < g->first_channel + g->channel_count && k < d->channel_count; k++) {
            double *times = NULL;
            size_t n = 0;
            if (read_accessor(b, d->channels[k].input, 1, "input", &times, &n) == XRSC_OK &&
                n > 0 && times[n - 1] > c->duration_s)
                c->duration_s = (float)times[n - 1];
            free(times);
        }
    }
    b->diag = diag;
    return sc_clip_resolve(s->clips, s->clip_count, b->opt->animation, b->name,
                           &s->clip_playing, b->diag);
}

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
        /* Only the chosen clip's channels play (issue 21; --animation). */
        if (s->clip_playing != SC_CLIP_ALL && (int64_t)g->animation != s->clip_playing) continue;
        FIELD(field, "animations[%u].channels[%u]", g->animation, g->channel);
        if (g->node < 0) continue; /* no target node: ignored per spec (extensions may use it) */
        if ((uint32_t)g->node >= d->node_count)
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "target node %d does not exist", g->node);
        bool weights = g->path == SC_GLTF_PATH_WEIGHTS;
        if (g->path == SC_GLTF_PATH_OTHER || (weights && s->nodes[g->node].weight_count == 0)) {
            sc_gltf_note(d, weights ? "weights animation of a node without morph targets"
                                    : "animation paths other than T/R/S/weights");
            continue;
        }
        if (g->input < 0 || g->interp == SC_GLTF_INTERP_OTHER) {
            FIELD(field, "animations[%u].channels[%u].sampler", g->animation, g->channel);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "sampler is missing or has an unknown interpolation");
        }
        uint32_t nc = weights ? s->nodes[g->node].weight_count
                      : g->path == SC_GLTF_PATH_ROTATION ? 4 : 3;
        /* weights outputs are SCALAR, nc per key (glTF §3.11.2) */
        uint32_t acc_comps = weights ? 1 : nc;
        size_t per_elem = weights ? nc : 1;
        double *times = NULL, *vals = NULL;
        size_t tcount = 0, vcount = 0;
        FIELD(field, "animations[%u].samplers.input", g->animation);
        xrsc_result r = read_accessor(b, g->input, 1, field, &times, &tcount);
        FIELD(field, "animations[%u].samplers.output", g->animation);
        if (r == XRSC_OK) r = read_accessor(b, g->output, acc_comps, field, &vals, &vcount);
        size_t per_key = (g->interp == SC_GLTF_INTERP_CUBICSPLINE ? 3 : 1) * per_elem;
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
            ch->values = malloc(vcount * acc_comps * sizeof(float));
            s->channel_count++; /* counted now so that destroy frees partial arrays */
            if (!ch->times || !ch->values)
                r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
        }
        if (r == XRSC_OK) {
            ch->node = (uint32_t)g->node;
            ch->path = g->path == SC_GLTF_PATH_TRANSLATION ? SC_ANIM_TRANSLATION
                       : g->path == SC_GLTF_PATH_ROTATION  ? SC_ANIM_ROTATION
                       : weights                           ? SC_ANIM_WEIGHTS
                                                           : SC_ANIM_SCALE;
            ch->components = nc;
            ch->interp = g->interp == SC_GLTF_INTERP_LINEAR ? SC_INTERP_LINEAR
                         : g->interp == SC_GLTF_INTERP_STEP ? SC_INTERP_STEP
                                                            : SC_INTERP_CUBICSPLINE;
            ch->key_count = (uint32_t)tcount;
            for (size_t k = 0; k < tcount; k++) ch->times[k] = (float)times[k];
            for (size_t k = 0; k < vcount * acc_comps; k++) ch->values[k] = (float)vals[k];
            if (ch->times[tcount - 1] > s->animation_duration_s)
                s->animation_duration_s = ch->times[tcount - 1];
            node_animated[g->node] = true;
            /* An animated node uses TRS (the spec forbids animating matrix nodes). */
            if (!weights) s->nodes[g->node].has_matrix = false;
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

/** The EXT_mesh_gpu_instancing attributes of node ni as one TRS matrix per instance
 *  (*out_local, malloc'd, *out_count entries). */
static xrsc_result read_gpu_instances(sc_build *b, int32_t ni, float **out_local,
                                      size_t *out_count)
{
    const sc_gltf_node *g = &b->doc->nodes[ni];
    const int32_t acc[3] = {g->inst_translation, g->inst_rotation, g->inst_scale};
    static const uint32_t comps[3] = {3, 4, 3};
    static const char *const names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    double *v[3] = {NULL, NULL, NULL};
    size_t n[3] = {0, 0, 0}, count = 0;
    bool have = false;
    char field[128];
    xrsc_result r = XRSC_OK;
    for (int k = 0; k < 3 && r == XRSC_OK; k++) {
        if (acc[k] < 0) continue;
        FIELD(field, "nodes[%d].extensions.EXT_mesh_gpu_instancing.attributes.%s", ni, names[k]);
        r = read_accessor(b, acc[k], comps[k], field, &v[k], &n[k]);
        if (r == XRSC_OK && have && n[k] != count)
            r = u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                           "%zu elements, the other attributes have %zu", n[k], count);
        count = n[k], have = true;
    }
    float *local = r == XRSC_OK ? malloc((count ? count : 1) * 16 * sizeof(float)) : NULL;
    if (r == XRSC_OK && !local)
        r = u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    for (size_t i = 0; r == XRSC_OK && i < count; i++) {
        float t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, sc[3] = {1, 1, 1};
        for (int c = 0; c < 3; c++) {
            if (v[0]) t[c] = (float)v[0][i * 3 + c];
            if (v[2]) sc[c] = (float)v[2][i * 3 + c];
        }
        for (int c = 0; v[1] && c < 4; c++) q[c] = (float)v[1][i * 4 + c];
        sc_mat4_from_trs(t, q, sc, local + 16 * i);
    }
    for (int k = 0; k < 3; k++) free(v[k]);
    if (r != XRSC_OK) {
        free(local);
        return r;
    }
    *out_local = local;
    *out_count = count;
    return XRSC_OK;
}

/** One instance per drawn primitive of node ni's mesh (and per EXT_mesh_gpu_instancing
 *  instance: local = that instance's TRS). */
static xrsc_result add_node_instances(sc_walk *w, int32_t ni, const sc_gltf_mesh *gm)
{
    sc_build *b = w->b;
    float *local = NULL;
    size_t copies = 1;
    bool gpu = b->doc->nodes[ni].instanced;
    if (gpu) {
        xrsc_result r = read_gpu_instances(b, ni, &local, &copies);
        if (r != XRSC_OK) return r;
    }
    for (size_t c = 0; c < copies; c++) {
        for (uint32_t p = 0; p < gm->primitive_count; p++) {
            uint32_t mesh = b->prim_mesh[gm->first_primitive + p];
            if (mesh == SC_SKIPPED) continue;
            if (b->instances.count >= SC_MAX_INSTANCES) {
                free(local);
                return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "nodes",
                                  "more than %u mesh instances", SC_MAX_INSTANCES);
            }
            sc_instance *inst = vec_push(&b->instances, 1);
            if (!inst) {
                free(local);
                return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "",
                                  "out of memory");
            }
            inst->mesh = mesh;
            inst->node = (uint32_t)ni;
            inst->animated = w->anim_below[ni];
            inst->has_local = gpu;
            if (gpu) memcpy(inst->local, local + 16 * c, sizeof inst->local);
            note_deform(b, ni, inst);
        }
    }
    free(local);
    return XRSC_OK;
}

/** Keeps the first perspective camera (node ni's) as the viewpoint and lists every one (in
 *  walk order: sc_scene.cameras). */
static xrsc_result note_camera(sc_walk *w, int32_t ni, const sc_gltf_node *g)
{
    sc_gltf_doc *d = w->b->doc;
    if (!d->cameras[g->camera].perspective) {
        sc_gltf_note(d, "orthographic cameras");
        return XRSC_OK;
    }
    if (*w->out_camera_node < 0) *w->out_camera_node = ni;
    int32_t *c = vec_push(&w->b->camera_nodes, 1);
    if (!c) return u_diag_set(w->b->diag, XRSC_ERROR_OUT_OF_MEMORY, w->b->name, 0, "", "out of memory");
    *c = ni;
    return XRSC_OK;
}

/** Light l of the file on node ni as an ::sc_light: cone angles clamped to glTF's bounds
 *  (0 <= inner < outer <= pi/2) with a warning naming the field. */
static xrsc_result add_light(sc_walk *w, int32_t ni, int32_t li)
{
    sc_build *b = w->b;
    sc_scene *s = b->s;
    const sc_gltf_light *l = &b->doc->lights[li];
    sc_light *grown = realloc(s->lights, (s->light_count + 1) * sizeof(*grown));
    if (!grown)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    s->lights = grown;
    sc_light *o = &s->lights[s->light_count++];
    memset(o, 0, sizeof(*o));
    o->type = l->type == SC_GLTF_LIGHT_DIRECTIONAL ? SC_LIGHT_DIRECTIONAL
              : l->type == SC_GLTF_LIGHT_POINT     ? SC_LIGHT_POINT
                                                   : SC_LIGHT_SPOT;
    o->node = (uint32_t)ni;
    o->animated = w->anim_below[ni];
    for (int c = 0; c < 3; c++) o->intensity[c] = fmaxf(l->color[c] * l->intensity, 0.0f);
    o->range_m = l->range > 0.0f ? l->range : 0.0f;
    float outer = fminf(fmaxf(l->outer_cone_rad, 0.0f), SC_HALF_PI);
    float inner = fminf(fmaxf(l->inner_cone_rad, 0.0f), outer);
    if (o->type == SC_LIGHT_SPOT &&
        (outer != l->outer_cone_rad || inner != l->inner_cone_rad || inner == outer)) {
        U_LOG_W("%s: lights[%d].spot: innerConeAngle %g, outerConeAngle %g outside 0 <= inner "
                "< outer <= pi/2 (KHR_lights_punctual); clamped to %g, %g",
                b->name, li, (double)l->inner_cone_rad, (double)l->outer_cone_rad,
                (double)inner, (double)outer);
        s->warning_count++;
    }
    o->inner_cone_rad = inner;
    o->outer_cone_rad = outer;
    return XRSC_OK;
}

/** Keeps the first directional light (node ni's) as the sun; the others go to the scene's
 *  punctual lights. */
static xrsc_result note_light(sc_walk *w, int32_t ni, const sc_gltf_node *g)
{
    sc_gltf_doc *d = w->b->doc;
    sc_gltf_light_type t = d->lights[g->light].type;
    if (t == SC_GLTF_LIGHT_DIRECTIONAL && *w->out_sun_node < 0) {
        *w->out_sun_node = ni;
        *w->out_sun_light = g->light;
    } else if (t == SC_GLTF_LIGHT_OTHER) {
        sc_gltf_note(d, "unknown light types");
    } else {
        return add_light(w, ni, g->light);
    }
    return XRSC_OK;
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
        xrsc_result rc = note_camera(w, ni, g);
        if (rc != XRSC_OK) return rc;
    }
    if (g->light >= 0) {
        if ((uint32_t)g->light >= d->light_count) {
            FIELD(field, "nodes[%d].extensions.KHR_lights_punctual.light", ni);
            return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, field,
                              "light %d does not exist", g->light);
        }
        xrsc_result rl = note_light(w, ni, g);
        if (rl != XRSC_OK)
            return rl;
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

/** sc_scene.cameras from the perspective camera nodes of the walk, at time 0. */
static xrsc_result set_cameras(sc_build *b)
{
    sc_scene *s = b->s;
    size_t n = b->camera_nodes.count;
    s->cameras = calloc(n ? n : 1, sizeof(sc_camera));
    if (!s->cameras)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    for (size_t i = 0; i < n; i++) {
        int32_t node = ((const int32_t *)b->camera_nodes.data)[i];
        const float *w = s->nodes[node].world;
        sc_camera *c = &s->cameras[i];
        c->node = (uint32_t)node;
        c->yfov_rad = b->doc->cameras[b->doc->nodes[node].camera].yfov_rad;
        memcpy(c->position, &w[12], sizeof c->position);
        world_rotation(w, c->orientation);
    }
    s->camera_count = (uint32_t)n;
    return XRSC_OK;
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
    for (uint32_t i = 0; !lit && i < s->light_count; i++)
        lit = luminance(s->lights[i].intensity) > 0.0f;
    lit = lit || s->environment[0] > 0.0f || s->environment[1] > 0.0f ||
          s->environment[2] > 0.0f;
    for (uint32_t i = 0; !lit && i < s->instance_count; i++)
        lit = s->materials[s->meshes[s->instances[i].mesh].material].unlit;
    if (lit) return;
    U_LOG_W("%s: the scene has no light (no emissive material with power, no punctual "
            "light, environment 0): frames will be black; give it an environment, e.g. "
            "--env 0.8,0.8,0.8",
            b->name);
    s->warning_count++;
}

/** Drops the directional lights from the scene's punctual lights (the sky's sun stands for
 *  all of them); point and spot lights stay. */
static void drop_directional_lights(sc_scene *s)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->light_count; i++)
        if (s->lights[i].type != SC_LIGHT_DIRECTIONAL) s->lights[k++] = s->lights[i];
    s->light_count = k;
}

/** The sky of --sky: bakes the Preetham map and replaces the file's directional lights with
 *  the sky's disk sun (direction: the option, else the file's first directional light, else
 *  SC_DEFAULT_SUN_DIRECTION). */
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
    drop_directional_lights(s);
    return XRSC_OK;
}

/** True when the scene has no light of its own and no environment from the options or the
 *  file: it gets the built-in studio environment. Emissive materials do not count (a glTF
 *  model's emissive details expect image-based lighting around them: issue 11). */
static bool wants_studio(const sc_build *b, int32_t scene_index)
{
    const sc_load_options *o = b->opt;
    if (o->env_map_path || o->sky || o->env_set || b->s->sun.present) return false;
    return !(scene_index >= 0 && b->doc->scenes[scene_index].has_environment);
}

/** The four bytes every OpenEXR file starts with (20000630 little-endian). */
static const uint8_t exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};

/** True when path names an OpenEXR file: a `.exr` suffix (any case), so that a cut or garbage
 *  .exr gets the EXR reader's error, or the EXR magic (an EXR under another name). */
static bool is_exr_path(const char *path)
{
    size_t len = strlen(path);
    const char *ext = len >= 4 ? path + len - 4 : "";
    if (ext[0] == '.' && (ext[1] | 0x20) == 'e' && (ext[2] | 0x20) == 'x' &&
        (ext[3] | 0x20) == 'r')
        return true;
    uint8_t head[4] = {0};
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(head, 1, sizeof head, f) : 0;
    if (f) fclose(f);
    return n == sizeof head && memcmp(head, exr_magic, sizeof head) == 0;
}

/** An equirectangular map file, OpenEXR (u_exr.h: R, G, B; alpha dropped) or Radiance .hdr,
 *  as RGB floats; the .hdr reader's pixel limit holds for both. */
static xrsc_result load_env_image(const char *path, sc_hdr_image *out, xrsc_diag *diag)
{
    if (!is_exr_path(path)) return sc_hdr_load(path, out, diag);
    memset(out, 0, sizeof(*out));
    u_exr_options opt = {.max_pixels = SC_HDR_MAX_PIXELS};
    u_exr_image img;
    xrsc_result r = u_exr_read(path, &opt, &img, diag);
    if (r != XRSC_OK) return r;
    size_t n = (size_t)img.width * img.height;
    for (size_t i = 0; i < n; i++) /* RGBA to RGB in place: i*3 never passes i*4 */
        for (int k = 0; k < 3; k++) img.rgba[i * 3 + k] = img.rgba[i * 4 + k];
    *out = (sc_hdr_image){img.width, img.height, img.rgba};
    return XRSC_OK;
}

/** A map (--env-map, else --sky, else the studio) into s->env_map, scaled, rotated. */
static xrsc_result set_env_map(sc_build *b)
{
    sc_scene *s = b->s;
    const sc_load_options *o = b->opt;
    sc_hdr_image img = {0};
    float *baked = NULL;
    uint32_t w = SC_SKY_WIDTH, h = SC_SKY_HEIGHT;
    xrsc_result r;
    if (o->env_map_path) {
        r = load_env_image(o->env_map_path, &img, b->diag);
        w = img.width, h = img.height;
    } else if (o->sky) {
        r = set_sky(b, &baked);
    } else {
        r = sc_studio_bake(&baked, b->diag);
        w = SC_STUDIO_WIDTH, h = SC_STUDIO_HEIGHT;
        s->env_studio = true;
    }
    if (r == XRSC_OK) {
        float k = o->env_intensity > 0.0f ? o->env_intensity : 1.0f;
        if (!o->env_map_path && o->sky) /* the sky's sun with its sky */
            for (int c = 0; c < 3; c++) s->sun.radiance[c] *= k;
        r = sc_env_map_build(baked ? baked : img.rgb, w, h, k, &s->env_map, b->diag);
    }
    free(baked);
    sc_hdr_image_free(&img);
    if (r != XRSC_OK) return r;
    if (o->env_no_importance) s->env_map.sampling = false;
    s->env_rotation_rad = o->env_rotation_deg * (float)(3.14159265358979323846 / 180.0);
    memcpy(s->environment, s->env_map.mean_radiance, sizeof s->environment);
    return XRSC_OK;
}

/** Environment: a map (--env-map, else --sky, else the studio of a lightless scene) or the
 *  constant of sc_load_options, else the file's extras.xrsc_environment, else 0 (a sun). */
static xrsc_result set_environment(sc_build *b, int32_t scene_index)
{
    sc_scene *s = b->s;
    const sc_gltf_doc *d = b->doc;
    const sc_load_options *o = b->opt;
    if (o->env_map_path || o->sky || wants_studio(b, scene_index)) return set_env_map(b);
    if (o->env_set)
        memcpy(s->environment, o->environment, sizeof s->environment);
    else if (scene_index >= 0 && d->scenes[scene_index].has_environment)
        memcpy(s->environment, d->scenes[scene_index].environment, sizeof s->environment);
    else /* the scene's directional light is its lighting */
        s->environment[0] = s->environment[1] = s->environment[2] = 0.0f;
    return XRSC_OK;
}

/** Element count of accessor idx when it exists, else 0 (errors come later, in place). */
static size_t accessor_count(const sc_gltf_doc *d, int32_t idx)
{
    return idx >= 0 && (uint32_t)idx < d->accessor_count ? d->accessors[idx].count : 0;
}

/** Reserves the scene-wide vertex and index arrays for all primitives at once (the counts
 *  build_primitive will push; a wrong guess only costs the usual growth). */
static bool reserve_all_geometry(sc_build *b)
{
    const sc_gltf_doc *d = b->doc;
    size_t nv = 0, ni = 0;
    for (uint32_t p = 0; p < d->primitive_count; p++) {
        const sc_gltf_primitive *pr = &d->primitives[p];
        size_t vc = accessor_count(d, pr->position);
        size_t ic = pr->indices >= 0 ? accessor_count(d, pr->indices) : vc;
        if (pr->mode == SC_GLTF_MODE_TRIANGLE_STRIP || pr->mode == SC_GLTF_MODE_TRIANGLE_FAN)
            ic = ic >= 3 ? (ic - 2) * 3 : 0;
        nv += pr->normal >= 0 ? vc : ic;
        ni += ic;
    }
    if (nv > SC_MAX_ELEMENTS || ni > SC_MAX_ELEMENTS) return true; /* refused later, in place */
    return vec_reserve(&b->vertices, nv) && vec_reserve(&b->indices, ni);
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
    if (!reserve_all_geometry(b))
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
    if (b->skipped_prims)
        sc_warn(b, XRSC_WARN_GLTF_PRIMITIVE_SKIPPED, b->skipped_field,
                "%u points/lines primitive(s) skipped (xrsc ray traces triangles only)",
                b->skipped_prims);

    if ((r = build_skins(b)) != XRSC_OK || (r = build_node_deform(b)) != XRSC_OK) return r;
    bool *node_animated = calloc(d->node_count ? d->node_count : 1, sizeof(bool));
    if (!node_animated)
        return u_diag_set(b->diag, XRSC_ERROR_OUT_OF_MEMORY, b->name, 0, "", "out of memory");
    s->facts = (sc_file_facts){.node_count = d->node_count, .mesh_count = d->mesh_count,
                               .image_count = d->image_count,
                               .material_count = d->material_count,
                               .skin_count = d->facts.skin_count,
                               .morph_target_count = d->facts.morph_target_count,
                               .morph_mesh_count = d->facts.morph_mesh_count};
    memcpy(s->facts.extensions_used, d->facts.extensions_used, sizeof s->facts.extensions_used);
    memcpy(s->facts.extensions_required, d->facts.extensions_required,
           sizeof s->facts.extensions_required);
    r = build_clips(b);
    if (r == XRSC_OK) r = build_channels(b, node_animated);
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
    s->influences = b->influences.data, s->influence_count = (uint32_t)b->influences.count;
    s->deltas = b->deltas.data, s->delta_count = (uint32_t)b->deltas.count;
    b->influences.data = b->deltas.data = NULL;
    if ((r = finish_deform(b)) != XRSC_OK) return r;

    for (uint32_t i = 0; i < s->instance_count; i++)
        s->triangle_count += s->meshes[s->instances[i].mesh].index_count / 3;
    if (s->triangle_count == 0 && b->skipped_prims)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_UNSUPPORTED, b->name, 0, b->skipped_field,
                          "the scene has only points or lines, which xrsc does not draw "
                          "(it ray traces triangles)");
    if (s->triangle_count == 0)
        return u_diag_set(b->diag, XRSC_ERROR_GLTF_INVALID, b->name, 0, "meshes",
                          "the scene has no triangles to render");

    sc_scene_evaluate(s, 0.0);
    compute_bounds(s);
    if ((r = build_emitters(b)) != XRSC_OK) return r;
    set_sun(s, d, sun_node, sun_light);
    set_viewpoint(s, camera_node);
    if ((r = set_cameras(b)) != XRSC_OK) return r;
    if (camera_node >= 0) {
        const sc_gltf_camera *cam = &d->cameras[d->nodes[camera_node].camera];
        s->camera_yfov_rad = cam->yfov_rad;
        s->camera_aspect_ratio = cam->aspect_ratio > 0.0f ? cam->aspect_ratio : 0.0f;
    }

    if ((r = set_environment(b, scene_index)) != XRSC_OK) return r;
    warn_if_no_light(b);
    return XRSC_OK;
}

/** One warning per optional extension that is ignored (sc_gltf_doc.ignored_extensions). */
static void warn_ignored_extensions(sc_build *b)
{
    const char *p = b->doc->ignored_extensions;
    while (*p) {
        const char *end = strstr(p, ", ");
        size_t len = end ? (size_t)(end - p) : strlen(p);
        sc_warn(b, XRSC_WARN_GLTF_EXTENSION_IGNORED, "extensionsUsed",
                "optional extension %.*s is not supported by xrsc; drawn without it", (int)len,
                p);
        p += len + (end ? 2 : 0);
    }
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

/** sc_scene_load_memory; *free_after_parse (when not NULL) is freed and set to NULL as soon
 *  as the file is parsed (tinygltf holds its own copies of the buffers by then). */
static xrsc_result load_memory(const char *name, const void *data, size_t size,
                               const char *base_dir, const sc_load_options *opt, sc_scene **out,
                               xrsc_diag *diag, uint8_t **free_after_parse)
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
    b.camera_nodes.item = sizeof(int32_t);
    b.influences.item = sizeof(sc_skin_influence);
    b.deltas.item = sizeof(sc_morph_delta);

    double t0 = now_ms();
    xrsc_result r = sc_gltf_parse(name, data, size, base_dir, &b.doc, diag);
    if (free_after_parse) {
        free(*free_after_parse);
        *free_after_parse = NULL;
    }
    if (r != XRSC_OK) return r;
    double t1 = now_ms();
    b.s = calloc(1, sizeof(sc_scene));
    if (!b.s) r = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    if (r == XRSC_OK) {
        snprintf(b.s->path, sizeof b.s->path, "%s", name);
        b.s->load_timing.parse_ms = t1 - t0;
        r = build_scene(&b);
        b.s->load_timing.build_ms = now_ms() - t1;
    }
    if (r == XRSC_OK && b.doc->unsupported[0]) {
        U_LOG_W("%s: ignored (not supported by xrsc): %s", name, b.doc->unsupported);
        b.s->warning_count++;
    }
    if (r == XRSC_OK) warn_ignored_extensions(&b);

    /* Whatever was not handed to the scene. */
    for (size_t i = 0; i < b.textures.count; i++) free(((sc_texture *)b.textures.data)[i].rgba8);
    free(b.vertices.data);
    free(b.indices.data);
    free(b.meshes.data);
    free(b.textures.data);
    free(b.instances.data);
    free(b.emitters.data);
    free(b.camera_nodes.data);
    free(b.influences.data);
    free(b.deltas.data);
    free(b.prim_mesh);
    free(b.tex_map);
    free(b.image_warned);
    sc_gltf_doc_destroy(&b.doc);
    if (r != XRSC_OK) {
        sc_scene_destroy(&b.s);
        return r;
    }
    *out = b.s;
    return XRSC_OK;
}

xrsc_result sc_scene_load_memory(const char *name, const void *data, size_t size,
                                 const char *base_dir, const sc_load_options *opt,
                                 sc_scene **out, xrsc_diag *diag)
{
    return load_memory(name, data, size, base_dir, opt, out, diag, NULL);
}

xrsc_result sc_scene_load(const char *path, const sc_load_options *opt, sc_scene **out,
                          xrsc_diag *diag)
{
    if (out) *out = NULL;
    if (!path || !out)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0, "",
                          "path and out must not be NULL");
    double t0 = now_ms();
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
    double t1 = now_ms();
    xrsc_result r = load_memory(path, data, (size_t)size, dir, opt, out, diag, &data);
    free(data);
    if (r == XRSC_OK) (*out)->load_timing.read_ms = t1 - t0;
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
    free(s->lights);
    free(s->cameras);
    free(s->channels);
    free(s->skins);
    free(s->skin_joints);
    free(s->inverse_binds);
    free(s->influences);
    free(s->deltas);
    free(s->node_weights);
    free(s->pose_matrices);
    free(s->pose_weights);
    free(s->clips);
    sc_env_map_free(&s->env_map);
    free(s);
    *pscene = NULL;
}
