// SPDX-License-Identifier: MIT
/**
 * @file t_gltf.h
 * @brief Small glTF scenes written by the GPU tests: the JSON a test gives, with its one
 *        buffer appended as a data URI, into a temporary file.
 */
#pragma once

#include "testing.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/**
 * Writes a glTF to the temporary file `name` (t_temp_file) and returns its path, NULL when out
 * of memory: fmt and its arguments (printf) give the JSON object up to its last member,
 * without the closing brace; "buffers" follows, one buffer of bytes[0..n) as a data URI.
 */
static inline const char *t_gltf_write(const char *name, const void *bytes, size_t n,
                                       const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *uri = t_data_uri(bytes, n);
    size_t cap = (len > 0 ? (size_t)len : 0) + (uri ? strlen(uri) : 0) + 64;
    char *json = uri && len >= 0 ? malloc(cap) : NULL;
    const char *path = NULL;
    if (json) {
        va_start(ap, fmt);
        vsnprintf(json, cap, fmt, ap);
        va_end(ap);
        snprintf(json + len, cap - (size_t)len,
                 ",\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}]}", n, uri);
        path = t_temp_file(name, json);
    }
    CHECK_MSG(path != NULL, "%s: out of memory", name);
    free(uri);
    free(json);
    return path;
}
