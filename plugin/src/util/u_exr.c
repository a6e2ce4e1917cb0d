// SPDX-License-Identifier: MIT
/**
 * @file u_exr.c
 * @brief OpenEXR reader (u_exr.h) on OpenEXRCore's chunk decode pipeline.
 */
#include "u_exr.h"

#include "u_diag.h"
#include "u_exr_common.h"

#include <openexr.h>

#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/** One read: the library's last error message and, for u_exr_decode, the bytes (the
 *  context's user data, seen by the error handler and the read callbacks; msg first, as
 *  u_exr_on_error expects). */
typedef struct exr_src {
    u_exr_msg msg;
    const uint8_t *data;
    size_t size;
} exr_src;
_Static_assert(offsetof(exr_src, msg) == 0, "u_exr_on_error writes the user data's start");

static int64_t mem_read(exr_const_context_t ctxt, void *ud, void *buffer, uint64_t sz,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt, (void)error_cb;
    const exr_src *s = ud;
    if (offset >= s->size)
        return 0;
    uint64_t n = s->size - offset < sz ? s->size - offset : sz;
    memcpy(buffer, s->data + offset, (size_t)n);
    return (int64_t)n;
}

static int64_t mem_size(exr_const_context_t ctxt, void *ud)
{
    (void)ctxt;
    return (int64_t)((const exr_src *)ud)->size;
}

/* Points each channel of a chunk at its rows in the caller's buffers (start row y0); channels
 * not asked for go to planes[nplanes], a scratch plane: OpenEXRCore 3.1 dereferences the NULL
 * pointer that should skip a channel on some damaged files (found by fuzz_exr). */
static void bind_channels(exr_coding_channel_info_t *ch, int16_t count, const u_exr_plane *planes,
                          int nplanes, int32_t y0)
{
    for (int16_t c = 0; c < count; c++) {
        const u_exr_plane *p = u_exr_find_plane(planes, nplanes, ch[c].channel_name);
        if (!p)
            p = &planes[nplanes];
        ch[c].user_bytes_per_element = 4;
        ch[c].user_data_type = EXR_PIXEL_FLOAT;
        ch[c].user_pixel_stride = p->pixel_stride;
        ch[c].user_line_stride = p->line_stride;
        ch[c].decode_to_ptr = p->base + (size_t)y0 * (size_t)p->line_stride;
    }
}

static exr_result_t read_chunks(exr_context_t ctx, const exr_attr_box2i_t *dw,
                                const u_exr_plane *planes, int nplanes)
{
    int32_t lines = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int32_t y = dw->min.y; rv == EXR_ERR_SUCCESS && y <= dw->max.y; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_read_scanline_chunk_info(ctx, 0, y, &ci);
        if (rv == EXR_ERR_SUCCESS)
            rv = started ? exr_decoding_update(ctx, 0, &ci, &dec)
                         : exr_decoding_initialize(ctx, 0, &ci, &dec);
        if (rv != EXR_ERR_SUCCESS)
            break;
        started = true;
        bind_channels(dec.channels, dec.channel_count, planes, nplanes, ci.start_y - dw->min.y);
        rv = exr_decoding_choose_default_routines(ctx, 0, &dec);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_run(ctx, 0, &dec);
    }
    if (started)
        exr_decoding_destroy(ctx, &dec);
    return rv;
}

static bool has_channel(const exr_attr_chlist_t *cl, const char *name)
{
    for (int i = 0; i < cl->num_channels; i++)
        if (strcmp(cl->entries[i].name.str, name) == 0)
            return true;
    return false;
}

/** The first part's size and channels checked against the limits; w, h set on success. */
static xrsc_result check_header(exr_context_t ctx, const char *name, const u_exr_options *opt,
                                exr_attr_box2i_t *dw, const exr_attr_chlist_t **cl, int64_t *w,
                                int64_t *h, xrsc_diag *diag)
{
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    memset(dw, 0, sizeof(*dw));
    dw->max.x = dw->max.y = -1; /* empty unless the header says otherwise */
    *cl = NULL;
    exr_get_storage(ctx, 0, &storage);
    exr_get_data_window(ctx, 0, dw);
    exr_get_channels(ctx, 0, cl);
    *w = (int64_t)dw->max.x - dw->min.x + 1, *h = (int64_t)dw->max.y - dw->min.y + 1;
    if (storage != EXR_STORAGE_SCANLINE || !*cl || *w < 1 || *h < 1 || *w > U_EXR_MAX_SIDE ||
        *h > U_EXR_MAX_SIDE)
        return u_diag_set(diag, XRSC_ERROR_BAD_HEADER, name, 0, "exr",
                          "only scanline EXRs with sides 1..%d are read", U_EXR_MAX_SIDE);
    if (opt->max_pixels && (uint64_t)*w * (uint64_t)*h > opt->max_pixels)
        return u_diag_set(diag, XRSC_ERROR_FILE_TOO_LARGE, name, 0, "exr",
                          "%lld x %lld pixels: more than %llu", (long long)*w, (long long)*h,
                          (unsigned long long)opt->max_pixels);
    return XRSC_OK;
}

/** Decodes the first part of an opened context into *out (the context is finished here). */
static xrsc_result read_image(exr_context_t ctx, const char *name, const u_exr_options *opt,
                              const exr_src *src, u_exr_image *out, xrsc_diag *diag)
{
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *cl;
    int64_t w, h;
    xrsc_result r = check_header(ctx, name, opt, &dw, &cl, &w, &h, diag);
    if (r != XRSC_OK) {
        exr_finish(&ctx);
        return r;
    }
    size_t n = (size_t)w * (size_t)h;
    bool want_z = opt->want_depth && has_channel(cl, "Z");
    /* Decoded into planes and interleaved here: OpenEXRCore 3.1's interleaving fast path for
     * four half channels decodes A, B, G, R into R, G, B, A (reversed; test_exr_env.c). */
    float *planar = calloc(n * 5, sizeof(float)); /* R, G, B, A and the scratch plane */
    float *rgba = malloc(n * 4 * sizeof(float));
    float *depth = want_z ? malloc(n * sizeof(float)) : NULL;
    if (!planar || !rgba || (want_z && !depth)) {
        free(planar);
        free(rgba);
        free(depth);
        exr_finish(&ctx);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, name, 0, "exr", "out of memory");
    }
    if (!has_channel(cl, "A"))
        for (size_t i = 0; i < n; i++)
            planar[3 * n + i] = 1.0f;
    const int32_t px = sizeof(float), line = (int32_t)w * px;
    u_exr_plane planes[6] = {
        {"R", (uint8_t *)planar, px, line},
        {"G", (uint8_t *)(planar + n), px, line},
        {"B", (uint8_t *)(planar + 2 * n), px, line},
        {"A", (uint8_t *)(planar + 3 * n), px, line},
        {"Z", (uint8_t *)depth, px, line},
        {"", (uint8_t *)(planar + 4 * n), px, line}, /* channels not read */
    };
    exr_result_t rv = read_chunks(ctx, &dw, planes, 5);
    exr_finish(&ctx);
    for (size_t i = 0; i < n && rv == EXR_ERR_SUCCESS; i++)
        for (int c = 0; c < 4; c++)
            rgba[i * 4 + c] = planar[(size_t)c * n + i];
    free(planar);
    if (rv != EXR_ERR_SUCCESS) {
        free(rgba);
        free(depth);
        return u_exr_fail(diag, XRSC_ERROR_IO, name, "reading failed", rv, &src->msg);
    }
    *out = (u_exr_image){(uint32_t)w, (uint32_t)h, rgba, depth};
    return XRSC_OK;
}

/** Opens with init (its user data is src) and reads; path NULL: from src's bytes. */
static xrsc_result read_any(const char *name, const char *path, exr_src *src,
                            const u_exr_options *opt, u_exr_image *out, xrsc_diag *diag)
{
    static const u_exr_options defaults = {0};
    memset(out, 0, sizeof(*out));
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = u_exr_on_error;
    init.user_data = src;
    if (!path) {
        init.read_fn = mem_read;
        init.size_fn = mem_size;
    }
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_read(&ctx, path ? path : name, &init);
    if (rv != EXR_ERR_SUCCESS) {
        xrsc_result code = rv == EXR_ERR_FILE_ACCESS ? XRSC_ERROR_IO : XRSC_ERROR_BAD_HEADER;
        exr_finish(&ctx);
        return u_exr_fail(diag, code, name, "not a readable EXR", rv, &src->msg);
    }
    return read_image(ctx, name, opt ? opt : &defaults, src, out, diag);
}

xrsc_result u_exr_read(const char *path, const u_exr_options *opt, u_exr_image *out,
                       xrsc_diag *diag)
{
    exr_src src = {{{0}}, NULL, 0};
    return read_any(path, path, &src, opt, out, diag);
}

xrsc_result u_exr_decode(const char *name, const uint8_t *data, size_t size,
                         const u_exr_options *opt, u_exr_image *out, xrsc_diag *diag)
{
    exr_src src = {{{0}}, data, size};
    return read_any(name, NULL, &src, opt, out, diag);
}

void u_exr_image_free(u_exr_image *img)
{
    if (!img)
        return;
    free(img->rgba);
    free(img->depth);
    memset(img, 0, sizeof(*img));
}
