// SPDX-License-Identifier: MIT
/**
 * @file fuzz_hdr.c
 * @brief libFuzzer target: bytes → sc_hdr_decode (Radiance .hdr), then an environment map
 *        built from the picture (sampling tables) when it decodes.
 */
#include "sc_env.h"
#include "sc_hdr.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sc_hdr_image img;
    xrsc_diag diag;
    if (sc_hdr_decode("fuzz.hdr", data, size, &img, &diag) == XRSC_OK) {
        sc_env_map map;
        if (sc_env_map_build(img.rgb, img.width, img.height, 1.0f, &map, &diag) == XRSC_OK) {
            const float up[3] = {0.0f, 1.0f, 0.0f};
            (void)sc_env_pdf(&map, 0.3f, up);
            sc_env_map_free(&map);
        }
        sc_hdr_image_free(&img);
    }
    return 0;
}
