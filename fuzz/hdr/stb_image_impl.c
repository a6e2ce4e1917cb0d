// SPDX-License-Identifier: MIT
/**
 * @file stb_image_impl.c
 * @brief stb_image compiled from Debian's header (libstb-dev, the same 2.27 source as libstb)
 *        into fuzz_hdr, so that libFuzzer's coverage and ASan/UBSan reach the scanline decoder
 *        that sc_hdr.c drives (xrsc_scene links libstb itself).
 */
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
