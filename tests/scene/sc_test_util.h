// SPDX-License-Identifier: MIT
/**
 * @file sc_test_util.h
 * @brief Helpers for the scene tests: a minimal one-triangle glTF (data URIs: t_data_uri).
 */
#pragma once

#include "testing.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** 44 bytes: 3 float3 positions of a triangle in the z = 0 plane, then u16 indices
 *  (first, second, third) and 2 bytes of padding. */
static inline void sct_triangle_bytes(uint8_t out[44], uint16_t i0, uint16_t i1, uint16_t i2)
{
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t idx[4] = {i0, i1, i2, 0};
    memcpy(out, pos, 36);
    memcpy(out + 36, idx, 8);
}

/**
 * A one-triangle glTF. uri NULL means the triangle bytes as a data URI. mode is the primitive
 * mode, extra_top is inserted as top-level members (e.g. "\"extensionsRequired\": [...],"),
 * idx are the three indices. Returns a malloc'd string.
 */
static inline char *sct_triangle_gltf(const char *uri, int mode, const char *extra_top,
                                      uint16_t i0, uint16_t i1, uint16_t i2, int pos_count)
{
    uint8_t bytes[44];
    sct_triangle_bytes(bytes, i0, i1, i2);
    char *data = t_data_uri(bytes, sizeof bytes);
    const char *u = uri ? uri : data;
    size_t cap = strlen(u) + strlen(extra_top) + 2048;
    char *s = malloc(cap);
    snprintf(s, cap,
             "{\n"
             "  \"asset\": {\"version\": \"2.0\"},\n"
             "  %s\n"
             "  \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],\n"
             "  \"nodes\": [{\"mesh\": 0}],\n"
             "  \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1, "
             "\"mode\": %d}]}],\n"
             "  \"accessors\": [\n"
             "    {\"bufferView\": 0, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\"},\n"
             "    {\"bufferView\": 1, \"componentType\": 5123, \"count\": 3, \"type\": \"SCALAR\"}],\n"
             "  \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 36},\n"
             "                  {\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 6}],\n"
             "  \"buffers\": [{\"byteLength\": 44,\n"
             "               \"uri\": \"%s\"}]\n"
             "}\n",
             extra_top, mode, pos_count, u);
    free(data);
    return s;
}
