// SPDX-License-Identifier: MIT
/**
 * @file sc_hdr.c
 * @brief Radiance `.hdr` (RGBE) decoding: header, resolution line, flat / old RLE / adaptive
 *        RLE scanlines (format as documented with Radiance's picture file format).
 */
#include "sc_hdr.h"

#include "u_diag.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Header lines longer than this are refused (Radiance writes short ones). */
#define HDR_MAX_LINE 1024
/** Files over this are refused before reading. */
#define HDR_MAX_FILE_BYTES (1ull << 30)
/** The adaptive RLE is used only for widths in [8, 0x7fff] (its 15-bit width field). */
#define HDR_RLE_MIN_WIDTH 8u
#define HDR_RLE_MAX_WIDTH 0x7fffu
/** RGBE exponent bias: value = (mantissa + 0.5) x 2^(e - 128 - 8). */
#define HDR_EXP_BIAS 136

typedef struct hdr_reader {
    const char *name;
    const uint8_t *p, *end;
    int line; /* header lines read so far */
    xrsc_diag *diag;
} hdr_reader;

/** Next header line (without '\n') into buf; false at the end of data or when too long. */
static bool next_line(hdr_reader *r, char *buf, size_t cap, bool *too_long)
{
    *too_long = false;
    if (r->p >= r->end)
        return false;
    const uint8_t *nl = memchr(r->p, '\n', (size_t)(r->end - r->p));
    if (!nl)
        return false;
    size_t n = (size_t)(nl - r->p);
    if (n >= cap) {
        *too_long = true;
        return false;
    }
    memcpy(buf, r->p, n);
    buf[n] = '\0';
    if (n > 0 && buf[n - 1] == '\r')
        buf[n - 1] = '\0';
    r->p = nl + 1;
    r->line++;
    return true;
}

static xrsc_result header_error(hdr_reader *r, xrsc_result code, const char *field,
                                const char *msg)
{
    return u_diag_set(r->diag, code, r->name, r->line, field, "%s", msg);
}

/** Magic line, variables, empty line; *exposure = product of EXPOSURE values. */
static xrsc_result read_header(hdr_reader *r, double *exposure)
{
    char line[HDR_MAX_LINE];
    bool too_long;
    if (!next_line(r, line, sizeof line, &too_long) ||
        (strcmp(line, "#?RADIANCE") != 0 && strcmp(line, "#?RGBE") != 0)) {
        r->line = 1;
        return header_error(r, XRSC_ERROR_BAD_HEADER, "magic",
                            "not a Radiance picture: the first line must be #?RADIANCE or "
                            "#?RGBE");
    }
    *exposure = 1.0;
    for (;;) {
        if (!next_line(r, line, sizeof line, &too_long)) {
            r->line++;
            return header_error(r, too_long ? XRSC_ERROR_BAD_HEADER : XRSC_ERROR_TRUNCATED_LINE,
                                "header",
                                too_long ? "header line too long"
                                         : "the header ends before its empty line");
        }
        if (line[0] == '\0')
            return XRSC_OK;
        if (!strncmp(line, "FORMAT=", 7)) {
            if (strcmp(line + 7, "32-bit_rle_rgbe") != 0)
                return u_diag_set(r->diag, XRSC_ERROR_BAD_HEADER, r->name, r->line, "FORMAT",
                                  "unsupported pixel format '%.64s' (only 32-bit_rle_rgbe)",
                                  line + 7);
        } else if (!strncmp(line, "EXPOSURE=", 9)) {
            char *e;
            double v = strtod(line + 9, &e);
            while (*e == ' ' || *e == '\t') e++;
            if (e == line + 9 || *e != '\0' || !(v > 0.0) || !isfinite(v))
                return u_diag_set(r->diag, XRSC_ERROR_BAD_NUMBER, r->name, r->line, "EXPOSURE",
                                  "'%.64s' is not a positive number", line + 9);
            *exposure *= v;
        }
    }
}

/** The resolution line: -Y H +X W (top down) or +Y H +X W (bottom up). */
static xrsc_result read_resolution(hdr_reader *r, uint32_t *w, uint32_t *h, bool *bottom_up)
{
    char line[HDR_MAX_LINE], ys[3], xs[3], tail;
    bool too_long;
    long hh = 0, ww = 0;
    if (!next_line(r, line, sizeof line, &too_long)) {
        r->line++;
        return header_error(r, XRSC_ERROR_TRUNCATED_LINE, "resolution",
                            "missing resolution line");
    }
    if (sscanf(line, "%2s %ld %2s %ld %c", ys, &hh, xs, &ww, &tail) != 4 ||
        (strcmp(ys, "-Y") != 0 && strcmp(ys, "+Y") != 0) || strcmp(xs, "+X") != 0)
        return u_diag_set(r->diag, XRSC_ERROR_BAD_HEADER, r->name, r->line, "resolution",
                          "'%.64s': expected -Y H +X W or +Y H +X W", line);
    if (hh < 1 || ww < 1)
        return u_diag_set(r->diag, XRSC_ERROR_BAD_HEADER, r->name, r->line, "resolution",
                          "%ld x %ld pixels: an empty picture", ww, hh);
    if ((unsigned long)hh > SC_HDR_MAX_SIDE ||
        (unsigned long)ww > SC_HDR_MAX_SIDE ||
        (unsigned long long)hh * (unsigned long long)ww > SC_HDR_MAX_PIXELS)
        return u_diag_set(r->diag, XRSC_ERROR_FILE_TOO_LARGE, r->name, r->line, "resolution",
                          "%ld x %ld pixels: sides must be 1..%u and at most %u pixels", ww, hh,
                          SC_HDR_MAX_SIDE, SC_HDR_MAX_PIXELS);
    *w = (uint32_t)ww;
    *h = (uint32_t)hh;
    *bottom_up = ys[0] == '+';
    return XRSC_OK;
}

static xrsc_result scan_error(hdr_reader *r, uint32_t row, const char *msg)
{
    return u_diag_set(r->diag, XRSC_ERROR_TRUNCATED_LINE, r->name, (int)row + 1, "scanline",
                      "%s", msg);
}

/** One scanline in the adaptive RLE (after its 4-byte marker): 4 channel planes of runs. */
static xrsc_result read_rle(hdr_reader *r, uint32_t row, uint32_t w, uint8_t *rgbe)
{
    for (int c = 0; c < 4; c++) {
        uint32_t x = 0;
        while (x < w) {
            if (r->p >= r->end)
                return scan_error(r, row, "data ends inside the scanline");
            uint32_t n = *r->p++;
            if (n > 128) {
                n -= 128;
                if (n > w - x || r->p >= r->end)
                    return scan_error(r, row, "a run overruns the scanline");
                uint8_t v = *r->p++;
                for (uint32_t i = 0; i < n; i++) rgbe[(x + i) * 4 + c] = v;
            } else {
                if (n == 0 || n > w - x || (size_t)(r->end - r->p) < n)
                    return scan_error(r, row, "a literal run is empty or overruns the scanline");
                for (uint32_t i = 0; i < n; i++) rgbe[(x + i) * 4 + c] = r->p[i];
                r->p += n;
            }
            x += n;
        }
    }
    return XRSC_OK;
}

/** One scanline flat, with old-style runs: (1,1,1,n) repeats the previous pixel n << shift
 *  times, shift growing by 8 for consecutive run pixels. */
static xrsc_result read_flat(hdr_reader *r, uint32_t row, uint32_t w, uint8_t *rgbe)
{
    uint32_t x = 0, shift = 0;
    while (x < w) {
        if (r->end - r->p < 4)
            return scan_error(r, row, "data ends inside the scanline");
        const uint8_t *q = r->p;
        r->p += 4;
        if (q[0] == 1 && q[1] == 1 && q[2] == 1) {
            if (x == 0 || shift > 16)
                return scan_error(r, row, "a run has no pixel to repeat");
            uint64_t n = (uint64_t)q[3] << shift;
            if (n > w - x)
                return scan_error(r, row, "a run overruns the scanline");
            for (uint32_t i = 0; i < (uint32_t)n; i++)
                memcpy(&rgbe[(x + i) * 4], &rgbe[(x - 1) * 4], 4);
            x += (uint32_t)n;
            shift += 8;
        } else {
            memcpy(&rgbe[x * 4], q, 4);
            x++;
            shift = 0;
        }
    }
    return XRSC_OK;
}

static xrsc_result read_scanline(hdr_reader *r, uint32_t row, uint32_t w, uint8_t *rgbe)
{
    if (w >= HDR_RLE_MIN_WIDTH && w <= HDR_RLE_MAX_WIDTH && r->end - r->p >= 4 &&
        r->p[0] == 2 && r->p[1] == 2 && !(r->p[2] & 0x80)) {
        uint32_t mark = ((uint32_t)r->p[2] << 8) | r->p[3];
        if (mark != w)
            return scan_error(r, row, "the run-length scanline's width differs from the "
                                      "resolution line");
        r->p += 4;
        return read_rle(r, row, w, rgbe);
    }
    return read_flat(r, row, w, rgbe);
}

static void rgbe_to_float(const uint8_t *rgbe, uint32_t n, double scale, float *rgb)
{
    for (uint32_t i = 0; i < n; i++) {
        const uint8_t *q = &rgbe[i * 4];
        if (q[3] == 0) {
            rgb[i * 3] = rgb[i * 3 + 1] = rgb[i * 3 + 2] = 0.0f;
            continue;
        }
        double f = ldexp(1.0, (int)q[3] - HDR_EXP_BIAS) * scale;
        for (int c = 0; c < 3; c++) rgb[i * 3 + c] = (float)((q[c] + 0.5) * f);
    }
}

xrsc_result sc_hdr_decode(const char *name, const uint8_t *data, size_t size, sc_hdr_image *out,
                          xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    if (!name) name = "";
    if (!data || size == 0)
        return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, name, 0, "", "the file is empty");
    hdr_reader r = {.name = name, .p = data, .end = data + size, .diag = diag};
    double exposure;
    uint32_t w, h;
    bool bottom_up;
    xrsc_result res = read_header(&r, &exposure);
    if (res == XRSC_OK)
        res = read_resolution(&r, &w, &h, &bottom_up);
    if (res != XRSC_OK)
        return res;
    uint8_t *rgbe = malloc((size_t)w * 4);
    float *rgb = malloc((size_t)w * h * 3 * sizeof(float));
    if (!rgbe || !rgb) {
        free(rgbe);
        free(rgb);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "", "out of memory");
    }
    for (uint32_t y = 0; y < h && res == XRSC_OK; y++) {
        res = read_scanline(&r, y, w, rgbe);
        uint32_t row = bottom_up ? h - 1 - y : y;
        if (res == XRSC_OK)
            rgbe_to_float(rgbe, w, 1.0 / exposure, &rgb[(size_t)row * w * 3]);
    }
    free(rgbe);
    if (res != XRSC_OK) {
        free(rgb);
        return res;
    }
    out->width = w;
    out->height = h;
    out->rgb = rgb;
    return XRSC_OK;
}

xrsc_result sc_hdr_load(const char *path, sc_hdr_image *out, xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    if (!path)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "path", "NULL");
    FILE *f = fopen(path, "rb");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot open: %s", strerror(errno));
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0) n = ftell(f);
    if (n < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot read the file");
    }
    if ((unsigned long long)n > HDR_MAX_FILE_BYTES) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, path, 0, "",
                          "%ld bytes: larger than 1 GiB", n);
    }
    uint8_t *data = malloc(n > 0 ? (size_t)n : 1);
    if (!data) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "out of memory");
    }
    size_t got = fread(data, 1, (size_t)n, f);
    fclose(f);
    xrsc_result res = got == (size_t)n
                          ? sc_hdr_decode(path, data, (size_t)n, out, diag)
                          : u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot read the file");
    free(data);
    return res;
}

void sc_hdr_image_free(sc_hdr_image *img)
{
    if (!img) return;
    free(img->rgb);
    memset(img, 0, sizeof(*img));
}
