// SPDX-License-Identifier: MIT
/**
 * @file sc_morton.c
 * @brief Morton (Z-order) sort of a mesh's triangles by centroid, before the BLAS build.
 *
 * lavapipe's BVH builder splits triangles in input order without a spatial sort; sorting
 * along a Morton curve first was measured at 2-3x ray throughput on 100k-1M triangles
 * (DESIGN.md, Platform). The scale is uniform over the three axes (the largest extent of the
 * mesh's bounding box), so flat meshes are not stretched into a different curve order.
 */
#include "sc_scene.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/** Bits per axis: 3 x 21 = 63 bits of Morton code. */
#define SC_MORTON_BITS 21u
#define SC_MORTON_MAX ((1u << SC_MORTON_BITS) - 1u)

typedef struct sc_morton_key {
    uint64_t code;
    uint32_t triangle;
} sc_morton_key;

/** Spreads the low 21 bits of v so that there are two zero bits between consecutive bits. */
static uint64_t spread_bits(uint64_t v)
{
    v &= 0x1fffffull;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

/** Bits per pass of the radix sort: 8 passes of 8 bits cover the 63-bit codes. */
#define RADIX_BITS 8u
#define RADIX_SIZE (1u << RADIX_BITS)

/**
 * Sorts keys by code, ties in triangle order, with a stable LSD radix sort (tmp: n keys of
 * scratch): the same order as comparing (code, triangle), in O(n) instead of qsort's
 * O(n log n) with a comparison call per step (the sort was the largest CPU stage of a
 * 1M-triangle load). Passes whose byte is the same for every key are skipped.
 */
static void radix_sort_keys(sc_morton_key *keys, sc_morton_key *tmp, uint32_t n)
{
    for (uint32_t shift = 0; shift < 64; shift += RADIX_BITS) {
        uint32_t count[RADIX_SIZE] = {0};
        for (uint32_t i = 0; i < n; i++) count[(keys[i].code >> shift) & (RADIX_SIZE - 1)]++;
        if (count[(keys[0].code >> shift) & (RADIX_SIZE - 1)] == n) continue;
        uint32_t sum = 0;
        for (uint32_t b = 0; b < RADIX_SIZE; b++) {
            uint32_t c = count[b];
            count[b] = sum;
            sum += c;
        }
        for (uint32_t i = 0; i < n; i++)
            tmp[count[(keys[i].code >> shift) & (RADIX_SIZE - 1)]++] = keys[i];
        memcpy(keys, tmp, (size_t)n * sizeof(*keys));
    }
}

static uint32_t quantise(float v, float lo, float scale)
{
    float q = (v - lo) * scale;
    if (!(q > 0.0f)) return 0; /* also NaN */
    if (q >= (float)SC_MORTON_MAX) return SC_MORTON_MAX;
    return (uint32_t)q;
}

bool sc_morton_sort_triangles(const sc_vertex *vertices, uint32_t *indices, uint32_t index_count)
{
    uint32_t tri_count = index_count / 3;
    if (tri_count < 2) return true;

    float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (uint32_t i = 0; i < tri_count * 3; i++) {
        const float *p = vertices[indices[i]].position;
        for (int a = 0; a < 3; a++) {
            lo[a] = fminf(lo[a], p[a]);
            hi[a] = fmaxf(hi[a], p[a]);
        }
    }
    float extent = fmaxf(fmaxf(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
    float scale = extent > 0.0f ? (float)SC_MORTON_MAX / extent : 0.0f;

    sc_morton_key *keys = malloc(sizeof(*keys) * tri_count);
    sc_morton_key *tmp = malloc(sizeof(*tmp) * tri_count);
    uint32_t *sorted = malloc(sizeof(*sorted) * tri_count * 3);
    if (!keys || !tmp || !sorted) {
        free(keys);
        free(tmp);
        free(sorted);
        return false;
    }
    for (uint32_t t = 0; t < tri_count; t++) {
        const float *p0 = vertices[indices[3 * t]].position;
        const float *p1 = vertices[indices[3 * t + 1]].position;
        const float *p2 = vertices[indices[3 * t + 2]].position;
        uint64_t code = 0;
        for (int a = 0; a < 3; a++) {
            float c = (p0[a] + p1[a] + p2[a]) * (1.0f / 3.0f);
            code |= spread_bits(quantise(c, lo[a], scale)) << a;
        }
        keys[t].code = code;
        keys[t].triangle = t;
    }
    radix_sort_keys(keys, tmp, tri_count); /* keys start in triangle order: ties stay so */
    free(tmp);
    for (uint32_t t = 0; t < tri_count; t++)
        memcpy(&sorted[3 * t], &indices[3 * keys[t].triangle], 3 * sizeof(uint32_t));
    memcpy(indices, sorted, tri_count * 3 * sizeof(uint32_t));
    free(keys);
    free(sorted);
    return true;
}
