// SPDX-License-Identifier: MIT
/**
 * @file sc_hdr.c
 * @brief Radiance `.hdr` (RGBE) decoding: the header and resolution line here, the scanlines
 *        (flat or adaptive RLE) by stb_image's stbi_loadf_from_callbacks (Debian's libstb).
 */
#include "sc_hdr.h"

#include "u_diag.h"

#include <stb_image.h>

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
/** stb_image reads adaptive-RLE scanlines only for widths in [8, 0x7fff] (15-bit field). */
#define HDR_RLE_MIN_WIDTH 8u
#define HDR_RLE_MAX_WIDTH 0x7fffu

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

/* ---- pixel data: stb_image ----
 *
 * The pixels are decoded by Debian's stb_image (libstb, v2.27) through
 * stbi_loadf_from_callbacks, over a stream of bytes served by hdr_stream: a header of our own
 * (below), then the file's bytes after its resolution line, then pad bytes 0xFF without end.
 * The read callback never reports the end of data, because stb_image 2.27 loops forever when
 * it does (CVE-2021-42715: stbi__get8 then returns 0 for ever, and a count byte 0 in an
 * adaptive-RLE scanline is a literal run of no pixels). As stream_read never returns 0,
 * stbi__get8 never takes that branch. Why every loop of stbi__hdr_load ends:
 *  - the header loops (stbi__hdr_test_core, stbi__hdr_gettoken and its flush loop, the
 *    variable loop until an empty line, the resolution line) read only the header this file
 *    writes: whole '\n'-ended lines under 256 bytes, so they never reach the file's bytes or
 *    the padding. (Over padding they would not end: each stbi__refill_buffer serves 128 more
 *    pad bytes, so stbi__hdr_gettoken never returns the empty line; that is why the file's own
 *    header is read by read_header above and never shown to stb_image.)
 *  - a scanline's marker (2, 2, hi, lo) read over padding is 0xFF..., not a marker: stb_image
 *    then reads flat pixels, loops bounded by width x height (bounded by SC_HDR_MAX_PIXELS).
 *  - the RLE loop `while ((nleft = width - i) > 0)`: every pass takes one count byte; a count
 *    of 0 makes no progress, but only the file's own bytes can hold one (finitely many); over
 *    padding every count is 0xFF, a run of 127 pixels, which either fits (progress) or trips
 *    stb_image's "count > nleft" error ("bad RLE data").
 * Afterwards a picture for which any pad byte was served is refused as truncated. That is
 * exact because the header is lengthened (a comment line of spaces) until header + file bytes
 * are a multiple of HDR_STB_REFILL: stb_image's refills then start at multiples of it, so a
 * refill can reach past the file's bytes only when stb_image needs a byte there, and
 * stbi__getn's direct reads (flat pixels) take all they are served. test_every_cut
 * (tests/scene/test_hdr_env.c) fails if this stops holding (another stb_image refill size). */

/** Bytes per stbi__refill_buffer (sizeof stbi__context.buffer_start in stb_image 2.27). */
#define HDR_STB_REFILL 128
/** Served after the file's bytes: an RLE count of 0xFF is a run of 127 (see above). */
#define HDR_PAD_BYTE 0xFF

typedef struct hdr_stream {
    char head[256]; /* the header handed to stb_image */
    size_t head_size;
    const uint8_t *data; /* the file's bytes after its resolution line */
    size_t data_size;
    size_t pos;     /* bytes served */
    size_t padding; /* pad bytes served */
} hdr_stream;

/** Fills all size bytes (never a short read, never 0): header, file, then padding. */
static int stream_read(void *user, char *out, int size)
{
    hdr_stream *s = user;
    for (size_t n = 0, want = size > 0 ? (size_t)size : 0, chunk; n < want; n += chunk) {
        size_t off = s->pos - s->head_size;
        if (s->pos < s->head_size) {
            chunk = s->head_size - s->pos < want - n ? s->head_size - s->pos : want - n;
            memcpy(out + n, s->head + s->pos, chunk);
        } else if (off < s->data_size) {
            chunk = s->data_size - off < want - n ? s->data_size - off : want - n;
            memcpy(out + n, s->data + off, chunk);
        } else {
            chunk = want - n;
            memset(out + n, HDR_PAD_BYTE, chunk);
            s->padding += chunk;
        }
        s->pos += chunk;
    }
    return size;
}

/** stbi__hdr_load never skips; kept consistent with stream_read anyway. */
static void stream_skip(void *user, int n)
{
    if (n > 0) ((hdr_stream *)user)->pos += (size_t)n;
}

static int stream_eof(void *user) { return ((hdr_stream *)user)->padding > 0; }

/** The header stb_image reads: what it accepts (FORMAT present, -Y H +X W), padded with a
 *  comment line of spaces so that header + data_size is a multiple of HDR_STB_REFILL. */
static void stream_init(hdr_stream *s, uint32_t w, uint32_t h, const uint8_t *data,
                        size_t data_size)
{
    static const char fmt[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n#%*s\n\n-Y %u +X %u\n";
    memset(s, 0, sizeof(*s));
    int len = snprintf(s->head, sizeof s->head, fmt, 0, "", h, w);
    int spaces = (int)((HDR_STB_REFILL - ((size_t)len + data_size) % HDR_STB_REFILL) %
                       HDR_STB_REFILL);
    s->head_size = (size_t)snprintf(s->head, sizeof s->head, fmt, spaces, "", h, w);
    s->data = data;
    s->data_size = data_size;
}

/** Fewest bytes one scanline of width w takes in any file stb_image decodes: 4 per pixel
 *  flat, or in the adaptive RLE (widths 8..0x7fff) a 4-byte marker and, per channel, pieces
 *  of at least 2 bytes that cover at most 127 pixels each (128 for literals of 129 bytes). */
static uint64_t min_scanline_bytes(uint32_t w)
{
    if (w < HDR_RLE_MIN_WIDTH || w > HDR_RLE_MAX_WIDTH) return 4ull * w;
    return 4 + 4 * 2 * (((uint64_t)w + 126) / 127);
}

/** The pixel data after the resolution line as w x h RGB floats, top row first in the file;
 *  a file too short for them is refused before stb_image allocates the picture. */
static xrsc_result decode_pixels(hdr_reader *r, uint32_t w, uint32_t h, float **out_rgb)
{
    size_t n = (size_t)(r->end - r->p);
    if (n < min_scanline_bytes(w) * h)
        return u_diag_set(r->diag, XRSC_ERROR_TRUNCATED_LINE, r->name, 0, "pixels",
                          "the pixel data (%zu bytes) is shorter than any encoding of %u x %u "
                          "pixels",
                          n, w, h);
    hdr_stream s;
    stream_init(&s, w, h, r->p, n);
    stbi_io_callbacks io = {stream_read, stream_skip, stream_eof};
    int x = 0, y = 0, comp = 0;
    float *rgb = stbi_loadf_from_callbacks(&io, &s, &x, &y, &comp, 3);
    if (rgb && !s.padding && (uint32_t)x == w && (uint32_t)y == h) {
        *out_rgb = rgb;
        return XRSC_OK;
    }
    const char *why = rgb ? "unexpected size" : stbi_failure_reason();
    stbi_image_free(rgb);
    if (s.padding)
        return u_diag_set(r->diag, XRSC_ERROR_TRUNCATED_LINE, r->name, 0, "pixels",
                          "the pixel data ends before its last scanline");
    if (why && !strcmp(why, "outofmem"))
        return u_diag_set(r->diag, XRSC_ERROR_OUT_OF_MEMORY, r->name, 0, "pixels",
                          "out of memory for %u x %u pixels", w, h);
    return u_diag_set(r->diag, XRSC_ERROR_TRUNCATED_LINE, r->name, 0, "pixels",
                      "bad pixel data (stb_image: %s): a run overruns its scanline or a "
                      "scanline's width differs from the resolution line",
                      why ? why : "no reason given");
}

/** +Y pictures store the bottom row first: turn them top down. */
static void flip_rows(float *rgb, uint32_t w, uint32_t h)
{
    size_t n = (size_t)w * 3;
    for (uint32_t y = 0; y < h / 2; y++) {
        float *a = &rgb[y * n], *b = &rgb[(h - 1 - y) * n];
        for (size_t i = 0; i < n; i++) {
            float t = a[i];
            a[i] = b[i];
            b[i] = t;
        }
    }
}

xrsc_result sc_hdr_decode(const char *name, const uint8_t *data, size_t size, sc_hdr_image *out,
                          xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    if (!name) name = "";
    if (!data || size == 0)
        return u_diag_set(diag, XRSC_ERROR_EMPTY_FILE, name, 0, "", "the file is empty");
    if (size > HDR_MAX_FILE_BYTES) /* stb_image counts bytes read in an int */
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, name, 0, "",
                          "%zu bytes: larger than 1 GiB", size);
    hdr_reader r = {.name = name, .p = data, .end = data + size, .diag = diag};
    double exposure;
    uint32_t w, h;
    bool bottom_up;
    float *rgb = NULL;
    xrsc_result res = read_header(&r, &exposure);
    if (res == XRSC_OK) res = read_resolution(&r, &w, &h, &bottom_up);
    if (res == XRSC_OK) res = decode_pixels(&r, w, h, &rgb);
    if (res != XRSC_OK) return res;
    if (bottom_up) flip_rows(rgb, w, h);
    const double scale = 1.0 / exposure;
    if (exposure != 1.0)
        for (size_t i = 0; i < (size_t)w * h * 3; i++) rgb[i] = (float)(rgb[i] * scale);
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
