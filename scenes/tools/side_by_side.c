// SPDX-License-Identifier: MIT
/**
 * @file side_by_side.c
 * @brief xrsc_side_by_side: puts images (PNG, JPEG, BMP, GIF's first frame: what Debian's
 *        stb_image reads) next to each other, each scaled to one height, into one PNG.
 *
 * For scripts/khronos-compare.sh (a render beside the screenshot a sample model ships), so that
 * the comparison needs no image tool outside the project's own dependencies (libstb-dev).
 * Usage: xrsc_side_by_side OUT.png HEIGHT_PX IN1 [IN2 ...]; a grey gap of GAP_PX between images.
 * Exit status 0, or 1 when an image cannot be read or the output written (the reason on stderr).
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#include <stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

#define MAX_INPUTS 8
#define GAP_PX 8
#define GAP_GREY 128
#define MAX_HEIGHT_PX 4096

typedef struct image {
    int w, h; /**< as read */
    int sw;   /**< width once scaled to the output height */
    uint8_t *rgb;
} image;

/** Box-filtered sample of the source area that output pixel (x, y) of an sw x oh image covers. */
static void sample(const image *im, int oh, int x, int y, uint8_t out[3])
{
    int x0 = (int)((int64_t)x * im->w / im->sw), x1 = (int)((int64_t)(x + 1) * im->w / im->sw);
    int y0 = (int)((int64_t)y * im->h / oh), y1 = (int)((int64_t)(y + 1) * im->h / oh);
    if (x1 <= x0)
        x1 = x0 + 1;
    if (y1 <= y0)
        y1 = y0 + 1;
    uint32_t sum[3] = {0, 0, 0}, n = 0;
    for (int sy = y0; sy < y1 && sy < im->h; sy++)
        for (int sx = x0; sx < x1 && sx < im->w; sx++, n++)
            for (int c = 0; c < 3; c++)
                sum[c] += im->rgb[3 * ((size_t)sy * im->w + sx) + c];
    for (int c = 0; c < 3; c++)
        out[c] = (uint8_t)(n ? (sum[c] + n / 2) / n : GAP_GREY);
}

int main(int argc, char **argv)
{
    if (argc < 4 || argc - 3 > MAX_INPUTS) {
        fprintf(stderr, "usage: %s OUT.png HEIGHT_PX IN1 [IN2 ...] (up to %d images)\n", argv[0],
                MAX_INPUTS);
        return 1;
    }
    int oh = atoi(argv[2]), n = argc - 3, ow = 0, status = 0;
    if (oh <= 0 || oh > MAX_HEIGHT_PX) {
        fprintf(stderr, "%s: HEIGHT_PX must be 1..%d\n", argv[0], MAX_HEIGHT_PX);
        return 1;
    }
    image im[MAX_INPUTS] = {{0}};
    for (int i = 0; i < n; i++) {
        int comp;
        im[i].rgb = stbi_load(argv[3 + i], &im[i].w, &im[i].h, &comp, 3);
        if (!im[i].rgb) {
            fprintf(stderr, "%s: cannot read %s: %s\n", argv[0], argv[3 + i],
                    stbi_failure_reason());
            status = 1;
            goto done;
        }
        im[i].sw = (int)(((int64_t)im[i].w * oh + im[i].h / 2) / im[i].h);
        if (im[i].sw < 1)
            im[i].sw = 1;
        ow += im[i].sw + (i ? GAP_PX : 0);
    }
    uint8_t *out = malloc((size_t)ow * oh * 3);
    if (!out) {
        fprintf(stderr, "%s: out of memory\n", argv[0]);
        status = 1;
        goto done;
    }
    memset(out, GAP_GREY, (size_t)ow * oh * 3);
    for (int i = 0, x0 = 0; i < n; x0 += im[i].sw + GAP_PX, i++)
        for (int y = 0; y < oh; y++)
            for (int x = 0; x < im[i].sw; x++)
                sample(&im[i], oh, x, y, out + 3 * ((size_t)y * ow + x0 + x));
    if (!stbi_write_png(argv[1], ow, oh, 3, out, ow * 3)) {
        fprintf(stderr, "%s: cannot write %s\n", argv[0], argv[1]);
        status = 1;
    }
    free(out);
done:
    for (int i = 0; i < n; i++)
        stbi_image_free(im[i].rgb);
    return status;
}
