// SPDX-License-Identifier: MIT
/**
 * @file test_exr_env.c
 * @brief Issue 22 item 1: OpenEXR environment maps. A small equirectangular map written with
 *        OpenEXRCore (float and half, and half RGB with an extra channel) and as a Radiance .hdr is
 * loaded through the scene's env-map path (sc_load_options.env_map_path, as --env-map): the EXR's
 * texels are its pixels exactly, half equals float (the values are exact in half), the .hdr twin
 * gives the same map within RGBE rounding; truncated and garbage .exr files give errors naming the
 * file, an EXR under another name is known by its magic; the shared reader (u_exr.h) reads memory
 * as files and keeps its pixel limit.
 */
#include "sc_scene.h"
#include "testing.h"
#include "u_exr.h"
#include "u_half.h"

#include <openexr.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 16
#define H 8

/** Pattern values k/64 * 2^j with k < 64, j < 4: exact in half, so half and float files
 *  hold the same numbers; alpha (c 3) is 0.25 and an extra channel X (c 4) is 9: the loader
 *  must ignore both. */
static float pattern(int x, int y, int c)
{
    if (c == 3)
        return 0.25f;
    if (c == 4)
        return 9.0f;
    return (float)((x * 7 + y * 13 + c * 5) % 61 + 1) / 64.0f * (float)(1 << (y % 4));
}

/** Half bits of a float that is a normal half or 0 (all pattern values are). */
static uint16_t half_of(float v)
{
    uint32_t b;
    memcpy(&b, &v, sizeof b);
    if (v == 0.0f)
        return 0;
    return (uint16_t)(((b >> 16) & 0x8000u) | ((((b >> 23) & 0xffu) - 112u) << 10) |
                      ((b >> 13) & 0x3ffu));
}

/** Writes the pattern's channels chans (of "RGBAX"; float or half) with compression comp; 0 on
 *  success. */
static int write_exr(const char *path, int half, const char *chans, exr_compression_t comp)
{
    static float f[W * H * 5];
    static uint16_t hb[W * H * 5];
    for (int i = 0; i < W * H * 5; i++) {
        f[i] = pattern((i / 5) % W, (i / 5) / W, i % 5);
        hb[i] = half_of(f[i]);
    }
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t ctx = NULL;
    int part = 0;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_part(ctx, "env", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctx, part, W, H, comp);
    for (const char *c = chans; *c && rv == EXR_ERR_SUCCESS; c++) {
        char name[2] = {*c, 0};
        rv = exr_add_channel(ctx, part, name, half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LINEAR, 1, 1);
    }
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctx);
    int32_t lines = 1;
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    int32_t bytes = half ? 2 : 4;
    uint8_t *base = half ? (uint8_t *)hb : (uint8_t *)f;
    for (int32_t y = 0; rv == EXR_ERR_SUCCESS && y < H; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(ctx, 0, y, &ci);
        if (rv == EXR_ERR_SUCCESS)
            rv = started ? exr_encoding_update(ctx, 0, &ci, &enc)
                         : exr_encoding_initialize(ctx, 0, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS)
            break;
        started = 1;
        for (int16_t c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            static const char order[] = "RGBAX";
            int k = (int)(strchr(order, ch->channel_name[0]) - order);
            ch->user_bytes_per_element = (int8_t)bytes;
            ch->user_data_type = half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
            ch->user_pixel_stride = 5 * bytes;
            ch->user_line_stride = W * 5 * bytes;
            ch->encode_from_ptr = base + ((size_t)ci.start_y * W * 5 + (size_t)k) * bytes;
        }
        rv = exr_encoding_choose_default_routines(ctx, 0, &enc);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(ctx, 0, &enc);
    }
    if (started)
        exr_encoding_destroy(ctx, &enc);
    exr_result_t fin = exr_finish(&ctx);
    return rv == EXR_ERR_SUCCESS && fin == EXR_ERR_SUCCESS ? 0 : -1;
}

/** RGBE of one pixel (Radiance's float2rgbe, as test_hdr_env.c). */
static void rgbe_of(const float c[3], uint8_t out[4])
{
    float m = fmaxf(c[0], fmaxf(c[1], c[2]));
    int e;
    float k = frexpf(m, &e) * 256.0f / m;
    for (int i = 0; i < 3; i++)
        out[i] = (uint8_t)(c[i] * k);
    out[3] = (uint8_t)(e + 128);
}

/** The pattern as a flat (unencoded) .hdr; 0 on success. */
static int write_hdr(const char *path)
{
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return -1;
    fprintf(fp, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", H, W);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float c[3] = {pattern(x, y, 0), pattern(x, y, 1), pattern(x, y, 2)};
            uint8_t e[4];
            rgbe_of(c, e);
            fwrite(e, 1, 4, fp);
        }
    return fclose(fp) == 0 ? 0 : -1;
}

/** One triangle, no lights: the environment comes from the options. */
static xrsc_result load(const char *env, sc_scene **s, xrsc_diag *d)
{
    static const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    char *uri = t_data_uri(pos, sizeof pos);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":"
             "[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}"
             "],\"buffers\":[{\"byteLength\":36,\"uri\":\"%s\"}],\"bufferViews\":[{\"buffer"
             "\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,\"componentType\":"
             "5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}]}",
             uri);
    free(uri);
    sc_load_options o = {.env_map_path = env};
    *s = NULL;
    memset(d, 0, sizeof(*d));
    return sc_scene_load_memory("x.gltf", json, strlen(json), NULL, &o, s, d);
}

static char exr_f[1024], exr_h[1024], exr_x[1024], hdr[1024];

static void make_files(void)
{
    snprintf(exr_f, sizeof exr_f, "%s", t_temp_file("env_float.exr", ""));
    snprintf(exr_h, sizeof exr_h, "%s", t_temp_file("env_half.exr", ""));
    snprintf(hdr, sizeof hdr, "%s", t_temp_file("env.hdr", ""));
    snprintf(exr_x, sizeof exr_x, "%s", t_temp_file("env_extra.exr", ""));
    CHECK_EQ_INT(write_exr(exr_f, 0, "RGBA", EXR_COMPRESSION_NONE), 0);
    CHECK_EQ_INT(write_exr(exr_h, 1, "RGBA", EXR_COMPRESSION_NONE), 0);
    /* an extra channel and RLE: OpenEXRCore 3.1 crashed when asked to skip the channel */
    CHECK_EQ_INT(write_exr(exr_x, 1, "BGRX", EXR_COMPRESSION_RLE), 0);
    CHECK_EQ_INT(write_hdr(hdr), 0);
}

/** The float EXR's texels are its pixels; the half files (RGBA; RGB with an extra channel,
 *  RLE) give the same map. */
static void test_exr_map(void)
{
    sc_scene *sf = NULL, *sh = NULL, *sx = NULL;
    xrsc_diag d;
    CHECK_MSG(load(exr_f, &sf, &d) == XRSC_OK, "%s", d.message);
    CHECK_MSG(load(exr_h, &sh, &d) == XRSC_OK, "%s", d.message);
    CHECK_MSG(load(exr_x, &sx, &d) == XRSC_OK, "%s", d.message);
    if (!sf || !sh || !sx)
        goto done;
    CHECK_EQ_INT(sf->env_map.width, W);
    CHECK_EQ_INT(sf->env_map.height, H);
    CHECK(sf->env_map.sampling);
    int bad = 0, bad_half = 0, bad_extra = 0;
    for (int i = 0; i < W * H; i++)
        for (int k = 0; k < 3; k++) {
            bad += sf->env_map.texels[i * 4 + k] != pattern(i % W, i / W, k);
            bad_half += sh->env_map.texels[i * 4 + k] != sf->env_map.texels[i * 4 + k];
            bad_extra += sx->env_map.texels[i * 4 + k] != sf->env_map.texels[i * 4 + k];
        }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(bad_half, 0);
    CHECK_EQ_INT(bad_extra, 0);
    /* row 5, column 3 in the file is row 5, column 3 of the map (top to bottom) */
    CHECK(sf->env_map.texels[(5 * W + 3) * 4 + 1] == pattern(3, 5, 1));
    for (int c = 0; c < 3; c++)
        CHECK(sf->env_map.mean_radiance[c] == sh->env_map.mean_radiance[c]);
done:
    sc_scene_destroy(&sf);
    sc_scene_destroy(&sh);
    sc_scene_destroy(&sx);
}

/** The .hdr twin gives the same environment within RGBE rounding (<= max channel / 256). */
static void test_same_as_hdr(void)
{
    sc_scene *se = NULL, *sr = NULL;
    xrsc_diag d;
    CHECK_MSG(load(exr_h, &se, &d) == XRSC_OK, "%s", d.message);
    CHECK_MSG(load(hdr, &sr, &d) == XRSC_OK, "%s", d.message);
    if (!se || !sr)
        goto done;
    CHECK_EQ_INT(sr->env_map.width, W);
    CHECK_EQ_INT(sr->env_map.height, H);
    double worst = 0.0;
    for (int i = 0; i < W * H; i++) {
        const float *a = &se->env_map.texels[i * 4], *b = &sr->env_map.texels[i * 4];
        double m = fmax(a[0], fmax(a[1], a[2]));
        for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(a[k] - b[k]) / m);
    }
    CHECK_MSG(worst <= 1.0 / 256.0 + 1e-6, "worst relative difference %g", worst);
    for (int y = 0; y < H; y++)
        CHECK_NEAR(se->env_map.marginal_cdf[y], sr->env_map.marginal_cdf[y], 0.01);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(se->env_map.mean_radiance[c], sr->env_map.mean_radiance[c],
                   se->env_map.mean_radiance[c] / 256.0);
done:
    sc_scene_destroy(&se);
    sc_scene_destroy(&sr);
}

/** A cut or garbage .exr is refused by the loader with an error naming the file. */
static void test_bad_exr(void)
{
    size_t n = 0;
    uint8_t *bytes = t_read_file(exr_f, &n);
    CHECK(bytes && n > 1000);
    if (!bytes)
        return;
    char cut[1024];
    snprintf(cut, sizeof cut, "%s", t_temp_file("cut.exr", ""));
    FILE *fp = fopen(cut, "wb");
    CHECK(fp != NULL);
    if (fp) { /* header and offset table kept, pixel data cut in the middle */
        fwrite(bytes, 1, n - 700, fp);
        fclose(fp);
    }
    sc_scene *s = NULL;
    xrsc_diag d;
    CHECK_EQ_INT(load(cut, &s, &d), XRSC_ERROR_IO);
    CHECK(s == NULL && !strcmp(d.file, cut));
    /* cut inside the header: not an EXR to the library (the magic still says EXR) */
    fp = fopen(cut, "wb");
    if (fp) {
        fwrite(bytes, 1, 40, fp);
        fclose(fp);
    }
    CHECK_EQ_INT(load(cut, &s, &d), XRSC_ERROR_BAD_HEADER);
    CHECK(s == NULL && !strcmp(d.file, cut));
    /* no magic, .exr name: the EXR reader's error, not the .hdr reader's */
    const char *junk = t_temp_file("junk.EXR", "#?RADIANCE? no, junk");
    CHECK_EQ_INT(load(junk, &s, &d), XRSC_ERROR_BAD_HEADER);
    CHECK(s == NULL && !strcmp(d.file, junk) && !strcmp(d.field, "exr"));
    /* an EXR under another name is known by its magic */
    char other[1024];
    snprintf(other, sizeof other, "%s", t_temp_file("env.map", ""));
    fp = fopen(other, "wb");
    if (fp) {
        fwrite(bytes, 1, n, fp);
        fclose(fp);
    }
    CHECK_MSG(load(other, &s, &d) == XRSC_OK, "%s", d.message);
    CHECK(s && s->env_map.width == W && s->env_map.texels[4] == pattern(1, 0, 0));
    sc_scene_destroy(&s);
    remove(other);
    remove(cut);
    remove(junk);
    free(bytes);
}

/** The shared reader: memory reads as the file does; max_pixels refuses before allocating. */
static void test_reader(void)
{
    size_t n = 0;
    uint8_t *bytes = t_read_file(exr_h, &n);
    CHECK(bytes != NULL);
    if (!bytes)
        return;
    u_exr_image a, b;
    xrsc_diag d = {0};
    CHECK_EQ_INT(u_exr_read(exr_h, NULL, &a, &d), XRSC_OK);
    CHECK_EQ_INT(u_exr_decode("mem.exr", bytes, n, NULL, &b, &d), XRSC_OK);
    CHECK(a.rgba && b.rgba && a.width == W && b.height == H && a.depth == NULL);
    if (a.rgba && b.rgba) {
        CHECK(!memcmp(a.rgba, b.rgba, (size_t)W * H * 4 * sizeof(float)));
        CHECK(a.rgba[3] == 0.25f && u_half_to_float(half_of(a.rgba[0])) == a.rgba[0]);
    }
    u_exr_image_free(&a);
    u_exr_image_free(&b);
    u_exr_options small = {.max_pixels = W * H - 1};
    CHECK_EQ_INT(u_exr_decode("mem.exr", bytes, n, &small, &a, &d), XRSC_ERROR_FILE_TOO_LARGE);
    CHECK(a.rgba == NULL && !strcmp(d.file, "mem.exr"));
    CHECK_EQ_INT(u_exr_decode("mem.exr", bytes, n / 2, NULL, &a, &d), XRSC_ERROR_IO);
    CHECK(a.rgba == NULL);
    free(bytes);
}

int main(void)
{
    RUN(make_files);
    RUN(test_exr_map);
    RUN(test_same_as_hdr);
    RUN(test_bad_exr);
    RUN(test_reader);
    remove(exr_f);
    remove(exr_h);
    remove(exr_x);
    remove(hdr);
    return t_finish();
}
