// SPDX-License-Identifier: MIT
/**
 * @file test_hdr_env.c
 * @brief Issue 11 (lighting), CPU side: the Radiance .hdr reader (flat and adaptive RLE
 *        through stb_image, bottom-up, EXPOSURE, no FORMAT line; truncated, garbage and
 *        CVE-2021-42715 files give errors naming file, line and field; every cut of a file is
 *        refused and trailing bytes are not), the environment map's sampling tables (pdf integrates to 1 over the sphere
 *        and follows luminance x sin theta), the Preetham sky, and the default environment
 *        of a scene without lights (emissive materials notwithstanding) through the loader.
 */
#include "sc_env.h"
#include "sc_hdr.h"
#include "sc_scene.h"
#include "testing.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_PI 3.14159265358979323846

/* ---- writing test pictures ---- */

typedef struct t_buf {
    uint8_t data[65536];
    size_t n;
} t_buf;

static void put(t_buf *b, const void *p, size_t n)
{
    if (b->n + n > sizeof b->data) return;
    memcpy(b->data + b->n, p, n);
    b->n += n;
}

static void put_s(t_buf *b, const char *s) { put(b, s, strlen(s)); }

/** RGBE of one pixel value (Radiance's float2rgbe: mantissa x 256, truncated). */
static void rgbe_of(const float c[3], uint8_t out[4])
{
    float m = fmaxf(c[0], fmaxf(c[1], c[2]));
    if (m < 1e-32f) {
        memset(out, 0, 4);
        return;
    }
    int e;
    float f = frexpf(m, &e) * 256.0f / m;
    for (int k = 0; k < 3; k++) out[k] = (uint8_t)(c[k] * f);
    out[3] = (uint8_t)(e + 128);
}

/** Decoded value of RGBE byte pair (mantissa byte, exponent byte), as the reader decodes it
 *  (stb_image: m x 2^(e - 136), without Radiance's +0.5; exact in float). */
static double decoded(uint8_t m, uint8_t e) { return e ? m * ldexp(1.0, e - 136) : 0.0; }

/** A test pattern: a smooth gradient with one bright texel. */
static void pattern(uint32_t x, uint32_t y, uint32_t w, uint32_t h, float c[3])
{
    c[0] = 0.1f + (float)x / w;
    c[1] = 0.2f + (float)y / h;
    c[2] = 0.05f + 0.01f * (float)((x * 7 + y * 3) % 11);
    if (x == w / 3 && y == h / 4) c[0] = c[1] = c[2] = 500.0f;
}

static void header(t_buf *b, uint32_t w, uint32_t h, const char *extra, const char *ydir)
{
    char s[256];
    put_s(b, "#?RADIANCE\n# made by test_hdr_env\nFORMAT=32-bit_rle_rgbe\n");
    put_s(b, extra);
    snprintf(s, sizeof s, "\n%sY %u +X %u\n", ydir, h, w);
    put_s(b, s);
}

/** Flat scanlines of pattern(). */
static void write_flat(t_buf *b, uint32_t w, uint32_t h)
{
    header(b, w, h, "", "-");
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            float c[3];
            uint8_t q[4];
            pattern(x, y, w, h, c);
            rgbe_of(c, q);
            put(b, q, 4);
        }
}

/** Adaptive RLE scanlines of pattern(): each channel plane as runs (for repeats of 3 or more)
 *  and literals, as Radiance's writer does. */
static void write_rle(t_buf *b, uint32_t w, uint32_t h, bool bottom_up)
{
    header(b, w, h, "", bottom_up ? "+" : "-");
    uint8_t *row = malloc((size_t)w * 4);
    for (uint32_t yy = 0; yy < h; yy++) {
        uint32_t y = bottom_up ? h - 1 - yy : yy;
        for (uint32_t x = 0; x < w; x++) {
            float c[3];
            pattern(x, y, w, h, c);
            if (x >= w / 2) c[1] = 0.5f; /* a long run in the green plane */
            rgbe_of(c, &row[x * 4]);
        }
        uint8_t mark[4] = {2, 2, (uint8_t)(w >> 8), (uint8_t)(w & 0xff)};
        put(b, mark, 4);
        for (int ch = 0; ch < 4; ch++) {
            uint32_t x = 0;
            while (x < w) {
                uint32_t run = 1;
                while (x + run < w && run < 127 && row[(x + run) * 4 + ch] == row[x * 4 + ch]) run++;
                if (run >= 3) {
                    uint8_t r[2] = {(uint8_t)(128 + run), row[x * 4 + ch]};
                    put(b, r, 2);
                    x += run;
                } else {
                    uint32_t lit = 0;
                    while (x + lit < w && lit < 128) lit++;
                    /* stop literals where a run of 3 starts */
                    for (uint32_t k = 0; k + 2 < lit; k++) {
                        uint8_t v = row[(x + k) * 4 + ch];
                        if (row[(x + k + 1) * 4 + ch] == v && row[(x + k + 2) * 4 + ch] == v) {
                            lit = k ? k : 1;
                            break;
                        }
                    }
                    uint8_t n = (uint8_t)lit;
                    put(b, &n, 1);
                    for (uint32_t k = 0; k < lit; k++) put(b, &row[(x + k) * 4 + ch], 1);
                    x += lit;
                }
            }
        }
    }
    free(row);
}

/** The expected decoded pattern value of pixel (x, y), channel k (with the green run when
 *  green_run). */
static double expected(uint32_t x, uint32_t y, uint32_t w, uint32_t h, int k, bool green_run)
{
    float c[3];
    uint8_t q[4];
    pattern(x, y, w, h, c);
    if (green_run && x >= w / 2) c[1] = 0.5f;
    rgbe_of(c, q);
    return decoded(q[k], q[3]);
}

static void check_pattern(const sc_hdr_image *img, uint32_t w, uint32_t h, bool green_run,
                          double scale)
{
    CHECK_EQ_INT(img->width, w);
    CHECK_EQ_INT(img->height, h);
    if (!img->rgb) return;
    int bad = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            for (int k = 0; k < 3; k++) {
                double e = expected(x, y, w, h, k, green_run) * scale;
                double v = img->rgb[((size_t)y * w + x) * 3 + k];
                if (fabs(v - e) > 1e-6 * fmax(1.0, e)) bad++;
            }
    CHECK_MSG(bad == 0, "%d values differ from the written ones", bad);
}

/* ---- the reader ---- */

static void test_flat(void)
{
    static t_buf b;
    b.n = 0;
    write_flat(&b, 5, 3); /* width < 8: never RLE */
    sc_hdr_image img;
    xrsc_diag d = {0};
    CHECK_EQ_INT(sc_hdr_decode("flat.hdr", b.data, b.n, &img, &d), XRSC_OK);
    check_pattern(&img, 5, 3, false, 1.0);
    sc_hdr_image_free(&img);
    CHECK(img.rgb == NULL);
}

static void test_rle(void)
{
    static t_buf b;
    b.n = 0;
    write_rle(&b, 300, 4, false); /* 300: runs longer than 127 split, literals of 128 */
    sc_hdr_image img;
    xrsc_diag d = {0};
    CHECK_MSG(sc_hdr_decode("rle.hdr", b.data, b.n, &img, &d) == XRSC_OK, "%s", d.message);
    check_pattern(&img, 300, 4, true, 1.0);
    sc_hdr_image_free(&img);
    /* bottom-up (+Y): rows come back top to bottom */
    b.n = 0;
    write_rle(&b, 16, 6, true);
    CHECK_MSG(sc_hdr_decode("up.hdr", b.data, b.n, &img, &d) == XRSC_OK, "%s", d.message);
    check_pattern(&img, 16, 6, true, 1.0);
    sc_hdr_image_free(&img);
}

static void test_exposure_and_old_rle(void)
{
    static t_buf b;
    b.n = 0;
    header(&b, 10, 1, "EXPOSURE=2\nEXPOSURE=4\nGAMMA=1\n", "-");
    uint8_t px[4] = {128, 64, 32, 129}, run[4] = {1, 1, 1, 9};
    for (int i = 0; i < 10; i++) put(&b, i == 9 ? run : px, 4);
    sc_hdr_image img;
    xrsc_diag d = {0};
    CHECK_MSG(sc_hdr_decode("exposure.hdr", b.data, b.n, &img, &d) == XRSC_OK, "%s", d.message);
    CHECK_EQ_INT(img.width, 10);
    if (img.rgb) {
        CHECK_NEAR(img.rgb[0], decoded(128, 129) / 8.0, 1e-7); /* EXPOSURE 2 x 4 */
        CHECK_NEAR(img.rgb[8 * 3 + 2], decoded(32, 129) / 8.0, 1e-7);
        /* old-style runs (1,1,1,n) are not recognised: stb_image reads them as a pixel */
        CHECK_NEAR(img.rgb[9 * 3], decoded(1, 9) / 8.0, 1e-30);
    }
    sc_hdr_image_free(&img);
    /* a file of old-style runs is shorter than any encoding stb_image reads: refused */
    b.n = 0;
    header(&b, 10, 1, "", "-");
    put(&b, px, 4);
    put(&b, run, 4);
    CHECK_EQ_INT(sc_hdr_decode("old.hdr", b.data, b.n, &img, &d), XRSC_ERROR_TRUNCATED_LINE);
    /* no FORMAT line (Radiance's default) and CRLF lines: accepted, though stb_image itself
     * refuses both (the reader hands it a header of its own) */
    b.n = 0;
    put_s(&b, "#?RADIANCE\r\n# no format\r\n\r\n-Y 1 +X 2\r\n");
    put(&b, px, 4);
    put(&b, px, 4);
    CHECK_MSG(sc_hdr_decode("noformat.hdr", b.data, b.n, &img, &d) == XRSC_OK, "%s", d.message);
    if (img.rgb) CHECK_NEAR(img.rgb[3 + 1], decoded(64, 129), 0.0);
    sc_hdr_image_free(&img);
}

/** Decoding fails with code, at line, naming field. */
static void expect_error(const char *what, const uint8_t *data, size_t n, xrsc_result code,
                         int line, const char *field)
{
    sc_hdr_image img;
    xrsc_diag d = {0};
    xrsc_result r = sc_hdr_decode("bad.hdr", data, n, &img, &d);
    CHECK_MSG(r == code, "%s: %s, expected %s (%s)", what, xrsc_result_name(r),
              xrsc_result_name(code), d.message);
    CHECK_MSG(d.line == line, "%s: line %d, expected %d", what, d.line, line);
    CHECK_MSG(!strcmp(d.field, field), "%s: field '%s', expected '%s'", what, d.field, field);
    CHECK(!strcmp(d.file, "bad.hdr"));
    CHECK(img.rgb == NULL && img.width == 0);
}

static void test_bad_files(void)
{
    static t_buf b, g;
    b.n = 0;
    write_rle(&b, 32, 8, false);
    expect_error("empty", b.data, 0, XRSC_ERROR_EMPTY_FILE, 0, "");
    const char *png = "\x89PNG\r\n\x1a\n garbage";
    expect_error("garbage", (const uint8_t *)png, strlen(png), XRSC_ERROR_BAD_HEADER, 1, "magic");
    /* truncated in the pixel data (stb_image does not say where: line 0) */
    size_t header_bytes = (size_t)(strstr((const char *)b.data, "+X 32\n") - (char *)b.data) + 6;
    expect_error("truncated", b.data, b.n - 10, XRSC_ERROR_TRUNCATED_LINE, 0, "pixels");
    expect_error("no pixels", b.data, header_bytes, XRSC_ERROR_TRUNCATED_LINE, 0, "pixels");
    expect_error("header cut", b.data, 20, XRSC_ERROR_TRUNCATED_LINE, 2, "header");
    /* a run that overruns its scanline (first channel: a run of 40 > 32) */
    memcpy(g.data, b.data, b.n);
    g.n = b.n;
    g.data[header_bytes + 4] = 128 + 40;
    expect_error("overrun", g.data, g.n, XRSC_ERROR_TRUNCATED_LINE, 0, "pixels");
    /* a scanline marker whose width differs */
    memcpy(g.data, b.data, b.n);
    g.data[header_bytes + 3] = 31;
    expect_error("width", g.data, g.n, XRSC_ERROR_TRUNCATED_LINE, 0, "pixels");
    /* header fields */
    const char *xyz = "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\1\1\1\1";
    expect_error("xyze", (const uint8_t *)xyz, strlen(xyz), XRSC_ERROR_BAD_HEADER, 2, "FORMAT");
    const char *ex = "#?RGBE\n# c\nEXPOSURE=abc\n\n-Y 1 +X 1\n\1\1\1\1";
    expect_error("exposure", (const uint8_t *)ex, strlen(ex), XRSC_ERROR_BAD_NUMBER, 3,
                 "EXPOSURE");
    const char *rot = "#?RADIANCE\n\n+X 4 -Y 4\n";
    expect_error("rotated", (const uint8_t *)rot, strlen(rot), XRSC_ERROR_BAD_HEADER, 3,
                 "resolution");
    const char *huge = "#?RADIANCE\n\n-Y 100000 +X 100000\n";
    expect_error("huge", (const uint8_t *)huge, strlen(huge), XRSC_ERROR_FILE_TOO_LARGE, 3,
                 "resolution");
    const char *zero = "#?RADIANCE\n\n-Y 0 +X 4\n";
    expect_error("zero", (const uint8_t *)zero, strlen(zero), XRSC_ERROR_BAD_HEADER, 3,
                 "resolution");
    /* a header asking for 16 Mpixel over a few bytes: refused before anything is allocated */
    const char *big = "#?RADIANCE\n\n-Y 4096 +X 4096\n\2\2\20\0\377\1";
    expect_error("big, no data", (const uint8_t *)big, strlen(big), XRSC_ERROR_TRUNCATED_LINE, 0,
                 "pixels");
    /* CVE-2021-42715: a zero count in an adaptive-RLE scanline, and a scanline cut after its
     * marker, make stb_image 2.27 (Debian's libstb-dev) loop forever when it reads them
     * itself; refused here (sc_hdr.c) */
    memcpy(g.data, b.data, b.n);
    g.data[header_bytes + 4] = 0;
    expect_error("zero count", g.data, g.n, XRSC_ERROR_TRUNCATED_LINE, 0, "pixels");
    expect_error("cut after marker", b.data, header_bytes + 5, XRSC_ERROR_TRUNCATED_LINE, 0,
                 "pixels");
    /* a missing file */
    sc_hdr_image img;
    xrsc_diag d = {0};
    CHECK_EQ_INT(sc_hdr_load("/nonexistent/x.hdr", &img, &d), XRSC_ERROR_IO);
    CHECK(!strcmp(d.file, "/nonexistent/x.hdr"));
}

/** The two CVE-2021-42715 cases with enough bytes to pass the reader's size check, so that
 *  stb_image decodes them (both hang stbi_loadf of Debian's libstb 2.27): an 8 x 4 picture
 *  whose last scanline is 8 zero counts, and an 8 x 2 one cut inside a literal run. */
static void test_stb_hangs(void)
{
    static t_buf b;
    const uint8_t mark[4] = {2, 2, 0, 8}, runs[8] = {0x88, 100, 0x88, 80, 0x88, 60, 0x88, 129};
    const uint8_t zeros[8] = {0}, lit[9] = {8, 1, 2, 3, 4, 5, 6, 7, 8};
    b.n = 0;
    header(&b, 8, 4, "", "-");
    for (int y = 0; y < 3; y++) put(&b, mark, 4), put(&b, runs, 8);
    put(&b, mark, 4);
    put(&b, zeros, 8);
    expect_error("zero counts", b.data, b.n, XRSC_ERROR_TRUNCATED_LINE, 0, "pixels");
    b.n = 0;
    header(&b, 8, 2, "", "-");
    put(&b, mark, 4);
    for (int c = 0; c < 4; c++) put(&b, lit, 9);
    put(&b, mark, 4);
    put(&b, lit, 5);
    expect_error("cut literal", b.data, b.n, XRSC_ERROR_TRUNCATED_LINE, 0, "pixels");
}

/** Every cut of a file inside its pixel data is refused, and bytes after the last scanline
 *  (1..300 of them, so every remainder of stb_image's 128-byte reads) change nothing: the
 *  reader's padding (sc_hdr.c) counts exactly the bytes stb_image needed past the end. */
static void test_every_cut(void)
{
    static t_buf b;
    for (int rle = 0; rle < 2; rle++) {
        b.n = 0;
        if (rle) write_rle(&b, 40, 6, false);
        else write_flat(&b, 6, 5);
        size_t head = (size_t)(strstr((const char *)b.data, rle ? "+X 40\n" : "+X 6\n") -
                               (char *)b.data) + (rle ? 6 : 5);
        sc_hdr_image ref, img;
        xrsc_diag d = {0};
        CHECK_EQ_INT(sc_hdr_decode("ref.hdr", b.data, b.n, &ref, &d), XRSC_OK);
        int accepted = 0, differ = 0;
        for (size_t cut = head; cut < b.n; cut++) {
            accepted += sc_hdr_decode("cut.hdr", b.data, cut, &img, &d) != XRSC_ERROR_TRUNCATED_LINE;
            sc_hdr_image_free(&img);
        }
        CHECK_MSG(accepted == 0, "%s: %d of %zu cuts not refused as truncated",
                  rle ? "rle" : "flat", accepted, b.n - head);
        size_t n = b.n;
        for (size_t extra = 1; extra <= 300 && ref.rgb; extra++) {
            b.n = n;
            for (size_t k = 0; k < extra; k++) put(&b, &(uint8_t){(uint8_t)(k * 37 + 2)}, 1);
            xrsc_result r = sc_hdr_decode("extra.hdr", b.data, b.n, &img, &d);
            differ += r != XRSC_OK ||
                      memcmp(img.rgb, ref.rgb, sizeof(float) * 3 * ref.width * ref.height) != 0;
            sc_hdr_image_free(&img);
        }
        CHECK_MSG(differ == 0, "%s: %d of 300 trailing lengths change the picture",
                  rle ? "rle" : "flat", differ);
        sc_hdr_image_free(&ref);
    }
}

/* ---- the map's sampling tables ---- */

static double lum(const float *c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static void test_env_pdf(void)
{
    const uint32_t w = 32, h = 16;
    float *rgb = malloc((size_t)w * h * 3 * sizeof(float));
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) pattern(x, y, w, h, &rgb[((size_t)y * w + x) * 3]);
    sc_env_map m;
    CHECK_EQ_INT(sc_env_map_build(rgb, w, h, 2.0f, &m, NULL), XRSC_OK);
    CHECK(m.sampling);
    CHECK_NEAR(m.texels[4 * 5], 2.0f * rgb[15], 1e-6); /* intensity applied */
    /* The pdf integrates to 1 over the sphere (midpoint rule on a grid finer than the map),
     * for two rotations. */
    for (int rot = 0; rot < 2; rot++) {
        float rho = rot ? 1.1f : 0.0f;
        const int nu = 256, nv = 128;
        double sum = 0.0;
        for (int j = 0; j < nv; j++) {
            double theta = T_PI * (j + 0.5) / nv;
            for (int i = 0; i < nu; i++) {
                double phi = 2.0 * T_PI * (i + 0.5) / nu;
                float d[3] = {(float)(sin(theta) * sin(phi)), (float)cos(theta),
                              (float)(-sin(theta) * cos(phi))};
                sum += sc_env_pdf(&m, rho, d) * sin(theta) * (2.0 * T_PI / nu) * (T_PI / nv);
            }
        }
        CHECK_MSG(fabs(sum - 1.0) < 2e-3, "pdf integrates to %.6f (rotation %g)", sum, rho);
    }
    /* texel probability proportional to luminance x sin(theta): compare two texels */
    uint32_t a = 3 * w + 7, b = 10 * w + 20;
    double sa = sin(T_PI * 3.5 / h), sb = sin(T_PI * 10.5 / h);
    CHECK_NEAR(m.texels[4 * a + 3] / m.texels[4 * b + 3],
               lum(&rgb[3 * a]) * sa / (lum(&rgb[3 * b]) * sb), 1e-4);
    /* the cdfs end at 1 and never decrease */
    CHECK_NEAR(m.marginal_cdf[h - 1], 1.0, 0.0);
    bool monotone = true;
    for (uint32_t y = 0; y < h; y++) {
        monotone &= y == 0 || m.marginal_cdf[y] >= m.marginal_cdf[y - 1];
        for (uint32_t x = 1; x < w; x++)
            monotone &= m.conditional_cdf[y * w + x] >= m.conditional_cdf[y * w + x - 1];
    }
    CHECK(monotone);
    /* the direction convention: u = 0.5 is -Z, u = 0.75 is +X, v = 0 is +Y */
    float d[3];
    sc_env_direction(0.5f, 0.5f, 0.0f, d);
    CHECK(d[2] < -0.999f);
    sc_env_direction(0.75f, 0.5f, 0.0f, d);
    CHECK(d[0] > 0.999f);
    sc_env_direction(0.5f, 0.0f, 0.0f, d);
    CHECK(d[1] > 0.999f);
    sc_env_map_free(&m);
    /* a black map has nothing to sample */
    memset(rgb, 0, (size_t)w * h * 3 * sizeof(float));
    CHECK_EQ_INT(sc_env_map_build(rgb, w, h, 1.0f, &m, NULL), XRSC_OK);
    CHECK(!m.sampling);
    sc_env_map_free(&m);
    free(rgb);
}

/* ---- the Preetham sky ---- */

static void test_sky(void)
{
    sc_sky_options o = {.sun_direction = {0.0f, 0.5f, -0.8660254f}, .turbidity = 3.0f};
    float *rgb = NULL, e_sun[3];
    CHECK_EQ_INT(sc_sky_bake(&o, &rgb, e_sun, NULL), XRSC_OK);
    if (!rgb) return;
    const uint32_t w = SC_SKY_WIDTH, h = SC_SKY_HEIGHT;
    /* blue sky: at the zenith blue > red; near the sun brighter than opposite it */
    const float *zen = &rgb[((size_t)0 * w + w / 2) * 3];
    CHECK(zen[2] > zen[0]);
    uint32_t y30 = (uint32_t)(h * (60.0 / 180.0)); /* 30 degrees up */
    const float *near = &rgb[((size_t)y30 * w + w / 2) * 3]; /* towards -Z, the sun's side */
    const float *away = &rgb[((size_t)y30 * w + 0) * 3];     /* towards +Z */
    CHECK(lum(near) > 2.0 * lum(away));
    /* everything finite and >= 0; the ground below the horizon is uniform */
    bool ok = true;
    for (size_t i = 0; i < (size_t)w * h * 3; i++) ok &= isfinite(rgb[i]) && rgb[i] >= 0.0f;
    CHECK(ok);
    CHECK_NEAR(rgb[((size_t)(h - 1) * w + 3) * 3], rgb[((size_t)(h / 2) * w + 100) * 3], 1e-6);
    /* the sun after the atmosphere: reddened (R > B), about 100 klux x SC_SKY_UNIT_SCALE */
    CHECK(e_sun[0] > e_sun[2]);
    CHECK(lum(e_sun) > 1.0 && lum(e_sun) < 3.2);
    free(rgb);
    /* sun below the horizon: refused */
    sc_sky_options below = {.sun_direction = {0.0f, -0.2f, -1.0f}};
    xrsc_diag d = {0};
    CHECK_EQ_INT(sc_sky_bake(&below, &rgb, e_sun, &d), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(rgb == NULL);
}

/* ---- the default environment through the loader ---- */

/** A quad with an emissive material, no lights, extras as given. */
static sc_scene *load_emissive(const char *scene_extras, const sc_load_options *opt)
{
    static const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    static const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    uint8_t bytes[60];
    memcpy(bytes, pos, 48);
    memcpy(bytes + 48, idx, 12);
    char *uri = t_data_uri(bytes, sizeof bytes);
    char *json = malloc(4096 + strlen(uri));
    sprintf(json,
            "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]%s}],"
            "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":"
            "{\"POSITION\":0},\"indices\":1,\"material\":0}]}],"
            "\"materials\":[{\"emissiveFactor\":[1,0.5,0.2]}],"
            "\"buffers\":[{\"byteLength\":60,\"uri\":\"%s\"}],"
            "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},"
            "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":12}],"
            "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,"
            "\"type\":\"VEC3\",\"min\":[-1,-1,0],\"max\":[1,1,0]},"
            "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]}",
            scene_extras, uri);
    sc_scene *s = NULL;
    xrsc_diag d = {0};
    xrsc_result r = sc_scene_load_memory("emissive.gltf", json, strlen(json), NULL, opt, &s, &d);
    CHECK_MSG(r == XRSC_OK, "%s", d.message);
    free(json);
    free(uri);
    return s;
}

static void test_default_environment(void)
{
    /* no lights, no environment, an emissive material: the studio environment (issue 18;
     * emissive materials notwithstanding, issue 11) */
    sc_scene *s = load_emissive("", NULL);
    if (s) {
        CHECK(s->emitter_count > 0);
        CHECK(s->env_studio);
        CHECK_EQ_INT(s->env_map.width, SC_STUDIO_WIDTH);
        CHECK(s->env_map.sampling);
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(s->environment[c], s->env_map.mean_radiance[c], 0.0);
    }
    sc_scene_destroy(&s);
    /* --env 1,1,1: the grey of earlier versions, no map */
    sc_load_options grey = {.env_set = true, .environment = {1.0f, 1.0f, 1.0f}};
    s = load_emissive("", &grey);
    if (s) {
        CHECK(!s->env_studio);
        CHECK_EQ_INT(s->env_map.width, 0);
        for (int c = 0; c < 3; c++) CHECK_NEAR(s->environment[c], 1.0, 0.0);
    }
    sc_scene_destroy(&s);
    /* --env-intensity scales the studio too */
    sc_load_options half = {.env_intensity = 0.5f};
    s = load_emissive("", &half);
    if (s) CHECK(s->env_studio && s->environment[1] > 0.0f);
    sc_scene *full = load_emissive("", NULL);
    if (s && full) CHECK_NEAR(s->environment[1], 0.5 * full->environment[1], 1e-6);
    sc_scene_destroy(&full);
    sc_scene_destroy(&s);
    /* an explicit black environment in the file stays black */
    s = load_emissive(",\"extras\":{\"xrsc_environment\":[0,0,0]}", NULL);
    if (s) CHECK_NEAR(s->environment[1], 0.0, 0.0);
    sc_scene_destroy(&s);
    /* --sky: a map, the mean radiance as the constant, a disk sun */
    sc_load_options o = {.sky = true};
    s = load_emissive("", &o);
    if (s) {
        CHECK_EQ_INT(s->env_map.width, SC_SKY_WIDTH);
        CHECK(s->env_map.sampling);
        CHECK(s->sun.present && s->sun.angular_radius_rad > 0.0f);
        CHECK(s->environment[2] > 0.0f);
    }
    sc_scene_destroy(&s);
    /* --env-map with a file that is not there: the loader's error names it */
    sc_load_options m = {.env_map_path = "/nonexistent/env.hdr"};
    sc_scene *bad = NULL;
    xrsc_diag d = {0};
    CHECK_EQ_INT(sc_scene_load_memory("x.gltf", "{}", 2, NULL, &m, &bad, &d) < 0, 1);
    CHECK(bad == NULL);
    s = NULL;
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
        CHECK_EQ_INT(sc_scene_load_memory("x.gltf", json, strlen(json), NULL, &m, &s, &d),
                     XRSC_ERROR_IO);
        CHECK(!strcmp(d.file, "/nonexistent/env.hdr"));
        CHECK(s == NULL);
    }
}

/** Radiance of the studio map towards unit d (nearest texel, rotation 0; sc_env.h). */
static const float *studio_texel(const sc_env_map *m, const double d[3])
{
    double u = 0.5 + atan2(d[0], -d[2]) / (2.0 * T_PI), v = acos(d[1]) / T_PI;
    u -= floor(u);
    uint32_t x = (uint32_t)(u * m->width), y = (uint32_t)(v * m->height);
    if (x >= m->width) x = m->width - 1;
    if (y >= m->height) y = m->height - 1;
    return &m->texels[((size_t)y * m->width + x) * 4];
}

static double luma(const float *c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/** The studio environment (issue 18): a white Lambertian plane facing up reads about
 *  SC_STUDIO_UP_RADIANCE (irradiance / pi, integrated here on a finer grid than the map's);
 *  the key light is much brighter than the ground, warm, and lights a plane facing it more
 *  than one facing away; the fill side is brighter than the opposite side. */
static void test_studio(void)
{
    float *rgb = NULL;
    CHECK_EQ_INT(sc_studio_bake(&rgb, NULL), XRSC_OK);
    if (!rgb) return;
    sc_env_map m;
    CHECK_EQ_INT(sc_env_map_build(rgb, SC_STUDIO_WIDTH, SC_STUDIO_HEIGHT, 1.0f, &m, NULL), XRSC_OK);
    free(rgb);
    const uint32_t nu = 4 * SC_STUDIO_WIDTH, nv = 4 * SC_STUDIO_HEIGHT;
    static const float key_f[3] = SC_STUDIO_KEY_DIRECTION, fill_f[3] = SC_STUDIO_FILL_DIRECTION;
    double key[3], fill[3], lk = 0, lf = 0;
    for (int a = 0; a < 3; a++) lk += key_f[a] * key_f[a], lf += fill_f[a] * fill_f[a];
    for (int a = 0; a < 3; a++) key[a] = key_f[a] / sqrt(lk), fill[a] = fill_f[a] / sqrt(lf);
    double e_up = 0, e_key = 0, e_away = 0, dw = (2 * T_PI / nu) * (T_PI / nv);
    for (uint32_t y = 0; y < nv; y++)
        for (uint32_t x = 0; x < nu; x++) {
            double th = T_PI * (y + 0.5) / nv, ph = 2 * T_PI * ((x + 0.5) / nu - 0.5);
            double d[3] = {sin(th) * sin(ph), cos(th), -sin(th) * cos(ph)};
            double l = luma(studio_texel(&m, d)) * sin(th) * dw;
            double ck = d[0] * key[0] + d[1] * key[1] + d[2] * key[2];
            if (d[1] > 0) e_up += l * d[1];
            if (ck > 0) e_key += l * ck;
            else e_away -= l * ck;
        }
    printf("  studio: white plane facing up %.3f, facing the key %.3f, away %.3f\n",
           e_up / T_PI, e_key / T_PI, e_away / T_PI);
    CHECK_NEAR(e_up / T_PI, SC_STUDIO_UP_RADIANCE, 0.02);
    CHECK(e_key > 2.0 * e_away);
    const double down[3] = {0, -1, 0}, anti_fill[3] = {-fill[0], fill[1], -fill[2]};
    const float *k = studio_texel(&m, key);
    CHECK(luma(k) > 10.0 * luma(studio_texel(&m, down)));
    CHECK(k[0] > k[2]); /* warm */
    CHECK(luma(studio_texel(&m, fill)) > luma(studio_texel(&m, anti_fill)));
    CHECK(m.sampling);
    sc_env_map_free(&m);
}

int main(void)
{
    RUN(test_studio);
    RUN(test_flat);
    RUN(test_rle);
    RUN(test_exposure_and_old_rle);
    RUN(test_bad_files);
    RUN(test_stb_hangs);
    RUN(test_every_cut);
    RUN(test_env_pdf);
    RUN(test_sky);
    RUN(test_default_environment);
    return t_finish();
}
