// SPDX-License-Identifier: MIT
/**
 * @file t_xr_frames.h
 * @brief The frames that the OpenXR path and the direct path wrote (frame_NNNNN_EYE.pfm in two
 *        folders) must be the same files, byte for byte.
 */
#pragma once

#include "testing.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Checks frames first .. first + count - 1, both eyes: present in dir_xr and dir_direct, equal,
 *  and larger than min_bytes (a linear RGB float32 PFM of the eye size). tag names the pair in
 *  failures. */
static inline void t_check_same_frames(const char *tag, const char *dir_xr, const char *dir_direct,
                                       uint32_t first, uint32_t count, size_t min_bytes)
{
    for (uint32_t k = first; k < first + count; k++) {
        for (int e = 0; e < 2; e++) {
            char a[600], b[600];
            const char *eye = e ? "right" : "left";
            snprintf(a, sizeof(a), "%s/frame_%05u_%s.pfm", dir_xr, k, eye);
            snprintf(b, sizeof(b), "%s/frame_%05u_%s.pfm", dir_direct, k, eye);
            size_t na = 0, nb = 0;
            char *fa = t_read_file(a, &na), *fb = t_read_file(b, &nb);
            CHECK_MSG(fa && fb, "missing %s or %s", a, b);
            if (fa && fb) {
                CHECK_MSG(na == nb && memcmp(fa, fb, na) == 0, "%s frame %u %s differs", tag, k,
                          eye);
                CHECK(na > min_bytes);
            }
            free(fa);
            free(fb);
        }
    }
}
