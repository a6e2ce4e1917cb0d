// SPDX-License-Identifier: MIT
/**
 * @file fuzz_exr.c
 * @brief libFuzzer target: bytes → u_exr_decode (the shared OpenEXR reader that environment
 *        maps and the host use), then an environment map built from the picture when it
 *        decodes, as the scene's env-map path does (RGBA to RGB, sc_env.h).
 */
#include "sc_env.h"
#include "u_exr.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/** The environment loader's pixel limit (SC_HDR_MAX_PIXELS), lowered to keep runs fast. */
#define FUZZ_MAX_PIXELS (1u << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    u_exr_options opt = {.want_depth = 1, .max_pixels = FUZZ_MAX_PIXELS};
    u_exr_image img;
    xrsc_diag diag;
    if (u_exr_decode("fuzz.exr", data, size, &opt, &img, &diag) != XRSC_OK)
        return 0;
    size_t n = (size_t)img.width * img.height;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            img.rgba[i * 3 + k] = img.rgba[i * 4 + k];
    sc_env_map map;
    if (sc_env_map_build(img.rgba, img.width, img.height, 1.0f, &map, &diag) == XRSC_OK) {
        const float up[3] = {0.0f, 1.0f, 0.0f};
        (void)sc_env_pdf(&map, 0.3f, up);
        sc_env_map_free(&map);
    }
    u_exr_image_free(&img);
    return 0;
}
