// SPDX-License-Identifier: MIT
/**
 * @file test_exr.c
 * @brief OpenEXR output (hs_exr.h): float RGB and Z written and read back with OpenEXR's own
 *        library bit for bit, the file's channel list and compression as documented, no
 *        temporary file left behind, and errors for files that are not EXRs.
 */
#include "hs_exr.h"
#include "testing.h"

#include <float.h>
#include <openexr.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { W = 7, H = 37 }; /* taller than one ZIP chunk (16 lines): three chunks, the last short */

static void fill(float *rgba, float *depth)
{
    /* Values a lossy or half-float path would change: denormal, -0, huge, 1/3, inf. */
    static const float special[] = {0.0f, -0.0f, 1e-40f, FLT_MAX, -3.5f, 0.1f, 1.0f / 3.0f};
    for (int i = 0; i < W * H; i++) {
        int x = i % W, y = i / W;
        rgba[i * 4 + 0] = (float)(100 * y + x) + 0.25f; /* encodes the position */
        rgba[i * 4 + 1] = special[i % 7];
        rgba[i * 4 + 2] = (float)i * 1.0e-3f;
        rgba[i * 4 + 3] = 0.5f;                                    /* alpha is not written */
        depth[i] = (i % 5 == 0) ? 0.0f : 0.5f + (float)i * 0.013f; /* 0 = no hit */
    }
    rgba[4 * 4 + 2] = INFINITY;
}

static int count_bit_diffs(const float *a, size_t stride_a, const float *b, size_t stride_b,
                           size_t n)
{
    int diffs = 0;
    for (size_t i = 0; i < n; i++)
        diffs += memcmp(&a[i * stride_a], &b[i * stride_b], sizeof(float)) != 0;
    return diffs;
}

static void test_round_trip_bit_exact(void)
{
    float rgba[W * H * 4], depth[W * H];
    fill(rgba, depth);
    const char *path = t_temp_file("rt.exr", "");
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_write_exr(path, rgba, depth, W, H, &diag), XRSC_OK);
    char tmp[1300];
    snprintf(tmp, sizeof(tmp), "%s.tmp", path);
    CHECK_MSG(access(tmp, F_OK) != 0, "%s left behind", tmp);

    float *back = NULL, *zback = NULL;
    uint32_t w = 0, h = 0;
    CHECK_EQ_INT(hs_read_exr(path, &back, &zback, &w, &h, &diag), XRSC_OK);
    CHECK_EQ_INT(w, W);
    CHECK_EQ_INT(h, H);
    if (back && zback && w == W && h == H) {
        for (int c = 0; c < 3; c++)
            CHECK_EQ_INT(count_bit_diffs(rgba + c, 4, back + c, 4, W * H), 0);
        CHECK_EQ_INT(count_bit_diffs(depth, 1, zback, 1, W * H), 0);
        CHECK(back[3] == 1.0f);                  /* no A channel: alpha reads 1 */
        CHECK(back[(5 * W + 3) * 4] == 503.25f); /* row 5, column 3: rows stay top to bottom */
    }
    free(back);
    free(zback);
    remove(path);
}

/* The header as tools see it: one scanline part, float B, G, R, Z, ZIP, linear channels. */
static void test_header_channels(void)
{
    float rgba[W * H * 4], depth[W * H];
    fill(rgba, depth);
    const char *path = t_temp_file("hdr.exr", "");
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_write_exr(path, rgba, depth, W, H, &diag), XRSC_OK);
    exr_context_t ctx = NULL;
    CHECK_EQ_INT(exr_start_read(&ctx, path, NULL), EXR_ERR_SUCCESS);
    int parts = 0;
    exr_get_count(ctx, &parts);
    CHECK_EQ_INT(parts, 1);
    exr_compression_t comp = EXR_COMPRESSION_LAST_TYPE;
    exr_get_compression(ctx, 0, &comp);
    CHECK_EQ_INT(comp, EXR_COMPRESSION_ZIP);
    const exr_attr_chlist_t *cl = NULL;
    exr_get_channels(ctx, 0, &cl);
    static const char *const names[4] = {"B", "G", "R", "Z"}; /* sorted, as EXR requires */
    CHECK(cl && cl->num_channels == 4);
    for (int i = 0; cl && i < cl->num_channels && i < 4; i++) {
        CHECK_MSG(strcmp(cl->entries[i].name.str, names[i]) == 0, "channel %d is %s", i,
                  cl->entries[i].name.str);
        CHECK_EQ_INT(cl->entries[i].pixel_type, EXR_PIXEL_FLOAT);
        CHECK_EQ_INT(cl->entries[i].p_linear, 1);
    }
    exr_finish(&ctx);
    remove(path);
}

static void test_without_depth(void)
{
    float rgba[W * H * 4], depth[W * H];
    fill(rgba, depth);
    const char *path = t_temp_file("rgb.exr", "");
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_write_exr(path, rgba, NULL, W, H, &diag), XRSC_OK);
    float *back = NULL, *zback = (float *)1;
    uint32_t w = 0, h = 0;
    CHECK_EQ_INT(hs_read_exr(path, &back, &zback, &w, &h, &diag), XRSC_OK);
    CHECK(zback == NULL);
    if (back)
        CHECK_EQ_INT(count_bit_diffs(rgba, 4, back, 4, W * H), 0);
    free(back);
    remove(path);
}

static void test_bad_files(void)
{
    xrsc_diag diag = {0};
    float *back = NULL, *zback = NULL;
    uint32_t w, h;
    const char *not_exr = t_temp_file("text.exr", "PF\n1 1\n-1.0\nxxxxxxxxxxxx");
    CHECK_EQ_INT(hs_read_exr(not_exr, &back, &zback, &w, &h, &diag), XRSC_ERROR_BAD_HEADER);
    CHECK(back == NULL && zback == NULL);
    CHECK_EQ_INT(hs_read_exr("/nonexistent/x.exr", &back, &zback, &w, &h, &diag), XRSC_ERROR_IO);
    /* A truncated EXR: header fine, pixel chunks cut off. */
    float rgba[W * H * 4], depth[W * H];
    fill(rgba, depth);
    const char *path = t_temp_file("cut.exr", "");
    CHECK_EQ_INT(hs_write_exr(path, rgba, depth, W, H, &diag), XRSC_OK);
    size_t size = 0;
    unsigned char *bytes = t_read_file(path, &size);
    CHECK(bytes && size > 400);
    if (bytes && size > 400) {
        FILE *f = fopen(path, "wb");
        fwrite(bytes, 1, size - 200, f);
        fclose(f);
        xrsc_result r = hs_read_exr(path, &back, &zback, &w, &h, &diag);
        CHECK(r != XRSC_OK);
        CHECK(back == NULL && zback == NULL);
    }
    free(bytes);
    remove(path);
    remove(not_exr);
    /* Unwritable target: an error naming it, nothing created. */
    CHECK_EQ_INT(hs_write_exr("/nonexistent/dir/x.exr", rgba, depth, W, H, &diag), XRSC_ERROR_IO);
}

int main(void)
{
    RUN(test_round_trip_bit_exact);
    RUN(test_header_channels);
    RUN(test_without_depth);
    RUN(test_bad_files);
    return t_finish();
}
