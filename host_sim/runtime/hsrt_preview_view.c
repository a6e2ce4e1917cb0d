// SPDX-License-Identifier: MIT
/**
 * @file hsrt_preview_view.c
 * @brief The preview window's picture: eyes scaled into panes, the depth-compensated stereo
 *        difference and the reference error as heat maps with their scale, and the overlay
 *        text in the bitmap font of hs_font.h (hsrt_preview_view.h).
 */
#include "hsrt_preview_view.h"

#include "hs_font.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Depth at which a background pixel (nothing hit: the environment) is reprojected: far
 *  enough that the eyes' baseline moves it by far less than a pixel, i.e. by direction. */
#define PV_INFINITY_M 1e6
/** Overlay text is drawn twice as large in windows at least this wide. */
#define PV_LARGE_TEXT_MIN_W 640u
/** Height of the colour scale bar in font pixels. */
#define PV_SCALE_BAR 6u
/** Colour of pixels that have nothing to compare with (outside the other eye, occluded). */
static const uint8_t k_no_data[3] = {56, 0, 72};
static const uint8_t k_text[3] = {255, 255, 255};
static const uint8_t k_bar[3] = {20, 20, 20};
static const uint8_t k_divider[3] = {128, 128, 128};

typedef struct pv_rect {
    int32_t x, y;
    uint32_t w, h;
} pv_rect;

/** The largest rect of a src_w x src_h image's aspect centred in a pane. */
static pv_rect fit_rect(uint32_t src_w, uint32_t src_h, pv_rect pane)
{
    double s = fmin((double)pane.w / src_w, (double)pane.h / src_h);
    pv_rect r;
    r.w = (uint32_t)lround(src_w * s);
    r.h = (uint32_t)lround(src_h * s);
    r.w = r.w < 1 ? 1 : (r.w > pane.w ? pane.w : r.w);
    r.h = r.h < 1 ? 1 : (r.h > pane.h ? pane.h : r.h);
    r.x = pane.x + (int32_t)(pane.w - r.w) / 2;
    r.y = pane.y + (int32_t)(pane.h - r.h) / 2;
    return r;
}

/** Bilinear taps along one axis: destination pixel d of n maps to source (d+0.5)*src/n-0.5. */
typedef struct pv_tap {
    uint32_t i0, i1;
    float f;
} pv_tap;

static void make_taps(uint32_t src, uint32_t n, pv_tap *taps)
{
    for (uint32_t d = 0; d < n; d++) {
        float s = ((float)d + 0.5f) * (float)src / (float)n - 0.5f;
        if (s < 0.0f)
            s = 0.0f;
        if (s > (float)(src - 1))
            s = (float)(src - 1);
        uint32_t i0 = (uint32_t)s;
        taps[d].i0 = i0;
        taps[d].i1 = i0 + 1 < src ? i0 + 1 : i0;
        taps[d].f = s - (float)i0;
    }
}

static float bilerp(const hsrt_eye_image *img, const pv_tap *tx, const pv_tap *ty, int c)
{
    const uint8_t *p = img->rgb;
    size_t w = img->w;
    float a = p[(ty->i0 * w + tx->i0) * 3 + c], b = p[(ty->i0 * w + tx->i1) * 3 + c];
    float d = p[(ty->i1 * w + tx->i0) * 3 + c], e = p[(ty->i1 * w + tx->i1) * 3 + c];
    float top = a + (b - a) * tx->f, bot = d + (e - d) * tx->f;
    return top + (bot - top) * ty->f;
}

static uint8_t to_u8(float v)
{
    return v <= 0.0f ? 0 : v >= 255.0f ? 255 : (uint8_t)lrintf(v);
}

/** The output image and its byte order. */
typedef struct pv_canvas {
    uint8_t *px;
    uint32_t w, h;
    bool bgra;
    uint32_t s; /**< text scale */
} pv_canvas;

/**
 * Draws `a` (and `b` for the raw difference) bilinearly scaled into rect r (the display
 * bytes; |a - b| x HSRT_PREVIEW_DIFF_GAIN with b).
 */
static bool draw_pane(const hsrt_eye_image *a, const hsrt_eye_image *b, pv_rect r,
                      const pv_canvas *cv)
{
    pv_tap *tx[2] = {malloc(r.w * sizeof(pv_tap)), malloc(r.w * sizeof(pv_tap))};
    pv_tap *ty[2] = {malloc(r.h * sizeof(pv_tap)), malloc(r.h * sizeof(pv_tap))};
    bool ok = tx[0] && tx[1] && ty[0] && ty[1];
    if (ok) {
        make_taps(a->w, r.w, tx[0]);
        make_taps(a->h, r.h, ty[0]);
        if (b) {
            make_taps(b->w, r.w, tx[1]);
            make_taps(b->h, r.h, ty[1]);
        }
        for (uint32_t y = 0; y < r.h; y++) {
            int32_t oy = r.y + (int32_t)y;
            if (oy < 0 || (uint32_t)oy >= cv->h)
                continue;
            for (uint32_t x = 0; x < r.w; x++) {
                int32_t ox = r.x + (int32_t)x;
                if (ox < 0 || (uint32_t)ox >= cv->w)
                    continue;
                uint8_t rgb[3];
                for (int c = 0; c < 3; c++) {
                    float v = bilerp(a, &tx[0][x], &ty[0][y], c);
                    if (b)
                        v = fabsf(v - bilerp(b, &tx[1][x], &ty[1][y], c)) * HSRT_PREVIEW_DIFF_GAIN;
                    rgb[c] = to_u8(v);
                }
                uint8_t *o = cv->px + ((size_t)oy * cv->w + (size_t)ox) * 4;
                o[0] = cv->bgra ? rgb[2] : rgb[0];
                o[1] = rgb[1];
                o[2] = cv->bgra ? rgb[0] : rgb[2];
                o[3] = 255;
            }
        }
    }
    for (int i = 0; i < 2; i++) {
        free(tx[i]);
        free(ty[i]);
    }
    return ok;
}

/* ---- overlay primitives ---- */

static void colour_of(const pv_canvas *cv, const uint8_t rgb[3], uint8_t out[3])
{
    out[0] = cv->bgra ? rgb[2] : rgb[0];
    out[1] = rgb[1];
    out[2] = cv->bgra ? rgb[0] : rgb[2];
}

static void fill(const pv_canvas *cv, int32_t x, int32_t y, uint32_t w, uint32_t h,
                 const uint8_t rgb[3])
{
    uint8_t c[3];
    colour_of(cv, rgb, c);
    hs_font_fill(cv->px, cv->w, cv->h, 4, x, y, w, h, c);
}

static void text(const pv_canvas *cv, int32_t x, int32_t y, const char *t)
{
    uint8_t c[3];
    colour_of(cv, k_text, c);
    hs_font_draw(cv->px, cv->w, cv->h, 4, x, y, cv->s, t, c);
}

/** A label on a dark box at (x, y). */
static void label(const pv_canvas *cv, int32_t x, int32_t y, const char *t)
{
    fill(cv, x, y, hs_font_text_width(t, cv->s) + 2 * cv->s, (HS_FONT_H + 2) * cv->s, k_bar);
    text(cv, x + (int32_t)cv->s, y + (int32_t)cv->s, t);
}

static uint32_t bar_height(const pv_canvas *cv)
{
    return (2 * HS_FONT_LINE + 1) * cv->s;
}

static uint32_t scale_height(const pv_canvas *cv)
{
    return (PV_SCALE_BAR + HS_FONT_LINE + 2) * cv->s;
}

/* The bottom strip: a caption on the left, the colour scale 0..full on the right. */
static void scale_strip(const pv_canvas *cv, const char *caption, double full)
{
    uint32_t sh = scale_height(cv);
    int32_t y0 = (int32_t)(cv->h - sh);
    fill(cv, 0, y0, cv->w, sh, k_bar);
    uint32_t bw = cv->w / 4, bx = cv->w - bw - 4 * cv->s;
    char cap[256];
    snprintf(cap, sizeof(cap), "%s", caption);
    for (size_t n = strlen(cap); n && hs_font_text_width(cap, cv->s) + 4 * cv->s > bx; n--)
        cap[n - 1] = '\0'; /* what does not fit left of the scale is cut */
    text(cv, (int32_t)cv->s, y0 + (int32_t)(PV_SCALE_BAR * cv->s + cv->s), cap);
    for (uint32_t x = 0; x < bw; x++) {
        uint8_t c[3];
        hs_heat_colour((float)x / (float)(bw - 1), c);
        fill(cv, (int32_t)(bx + x), y0 + (int32_t)cv->s, 1, (PV_SCALE_BAR - 1) * cv->s, c);
    }
    char t[32];
    snprintf(t, sizeof(t), "%.3g", full);
    int32_t ty = y0 + (int32_t)((PV_SCALE_BAR + 1) * cv->s);
    text(cv, (int32_t)bx, ty, "0");
    text(cv, (int32_t)(bx + bw - hs_font_text_width(t, cv->s)), ty, t);
}

/* The top bar: frame, stream time, ms, method, blend, R; then the passes and the state. */
static void top_bar(const pv_canvas *cv, const hsrt_preview_frame *f, const hsrt_view_state *vs)
{
    fill(cv, 0, 0, cv->w, bar_height(cv), k_bar);
    char l1[256], ms[32] = "-- MS/FRAME", rr[32] = "";
    const hsrt_preview_run_info *run = vs->run;
    if (vs->info && vs->info->has)
        snprintf(ms, sizeof(ms), "%.1f MS/FRAME", vs->info->ms);
    if (run && run->has && !strcmp(run->blend, "moments"))
        snprintf(rr, sizeof(rr), "  R %g", run->r);
    snprintf(l1, sizeof(l1), "FRAME %llu  T %.3f S  %s  METHOD %s  BLEND %s%s",
             (unsigned long long)f->frame, (double)f->stream_time_ns * 1e-9, ms,
             run && run->has ? run->method : "?", run && run->has ? run->blend : "?", rr);
    text(cv, (int32_t)cv->s, (int32_t)cv->s, l1);
    char state[64], back[32] = "";
    if (vs->back)
        snprintf(back, sizeof(back), ", %u BACK", vs->back);
    snprintf(state, sizeof(state), "%s%s",
             !strcmp(vs->state, "ended") ? "ENDED (ESC/Q CLOSES)" : vs->state, back);
    uint32_t state_w = hs_font_text_width(state, cv->s);
    int32_t y2 = (int32_t)((HS_FONT_LINE + 1) * cv->s);
    text(cv, (int32_t)(cv->w - state_w - cv->s), y2, state);
    char l2[512] = "MS/PASS";
    size_t n = strlen(l2);
    uint32_t room = cv->w > state_w + 8 * cv->s ? cv->w - state_w - 8 * cv->s : 0;
    for (uint32_t p = 0; vs->info && vs->info->has && p < vs->info->pass_count; p++) {
        char item[64];
        snprintf(item, sizeof(item), " %s %.2f", vs->info->pass_name[p], vs->info->pass_ms[p]);
        if (n + strlen(item) >= sizeof(l2))
            break;
        memcpy(l2 + n, item, strlen(item) + 1);
        if (hs_font_text_width(l2, cv->s) > room) {
            l2[n] = '\0';
            break;
        }
        n += strlen(item);
    }
    text(cv, (int32_t)cv->s, y2, l2);
}

/* ---- views ---- */

/** A w x h RGB picture of per-pixel values v: heat colour of v / full, k_no_data where < 0. */
static bool heat_image(const float *v, uint32_t w, uint32_t h, double full, hsrt_eye_image *out)
{
    out->w = w;
    out->h = h;
    out->rgba = NULL;
    out->rgb = malloc((size_t)w * h * 3);
    if (!out->rgb)
        return false;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        if (v[i] < 0.0f)
            memcpy(out->rgb + i * 3, k_no_data, 3);
        else
            hs_heat_colour((float)(v[i] / full), out->rgb + i * 3);
    }
    return true;
}

/* Bilinear read of the right eye at (x, y) (pixel centres at k + 0.5) where every tap is
 * background; false otherwise. */
static bool read_background(const hsrt_eye_image *img, const float *depth, double x, double y,
                            double out_rgb[3])
{
    double fx = x - 0.5, fy = y - 0.5;
    double bx = floor(fx), by = floor(fy), ax = fx - bx, ay = fy - by;
    out_rgb[0] = out_rgb[1] = out_rgb[2] = 0.0;
    for (int j = 0; j < 2; j++) {
        for (int i = 0; i < 2; i++) {
            double px = fmin(fmax(bx + i, 0.0), img->w - 1.0);
            double py = fmin(fmax(by + j, 0.0), img->h - 1.0);
            size_t k = (size_t)py * img->w + (size_t)px;
            double wgt = (i ? ax : 1.0 - ax) * (j ? ay : 1.0 - ay);
            if (wgt == 0.0)
                continue;
            if (depth[k] > 0.0f)
                return false;
            for (int c = 0; c < 3; c++)
                out_rgb[c] += wgt * img->rgba[k * 4 + c];
        }
    }
    return true;
}

bool hsrt_view_stereo_diff(const hsrt_preview_frame *f, float *out_rms, double *out_mean,
                           double *out_valid)
{
    const hsrt_eye_image *L = &f->eyes[0], *R = &f->eyes[1];
    if (!f->depth_m[0] || !f->depth_m[1] || !L->rgba || !R->rgba)
        return false;
    size_t n = (size_t)L->w * L->h;
    uint8_t *status = malloc(n);
    float *sq = malloc(n * sizeof(float));
    xrsc_metrics_view lv = {L->rgba, f->depth_m[0], {f->pose[0], f->fov[0], L->w, L->h}};
    xrsc_metrics_view rv = {R->rgba, f->depth_m[1], {f->pose[1], f->fov[1], R->w, R->h}};
    xrsc_reproj_diff res;
    bool ok = status && sq &&
              xrsc_metrics_stereo_discrepancy(&lv, &rv, NULL, &res, status, sq) == XRSC_OK;
    double sum = 0.0;
    size_t valid = 0;
    for (size_t i = 0; ok && i < n; i++) {
        out_rms[i] = -1.0f;
        if (status[i] == XRSC_REPROJ_VALID) {
            out_rms[i] = sqrtf(sq[i]);
        } else if (status[i] == XRSC_REPROJ_BACKGROUND) {
            /* The environment is at infinity: reproject by direction (seed 004 compares the
             * eyes after disparity compensation; at infinity the disparity is the FOVs'). */
            double x = (double)(i % L->w) + 0.5, y = (double)(i / L->w) + 0.5, sx, sy, sd;
            double rgb[3];
            if (xrsc_metrics_reproject(&lv.camera, x, y, PV_INFINITY_M, &rv.camera, &sx, &sy,
                                       &sd) &&
                sx >= 0.0 && sx <= R->w && sy >= 0.0 && sy <= R->h &&
                read_background(R, f->depth_m[1], sx, sy, rgb)) {
                double s = 0.0;
                for (int c = 0; c < 3; c++)
                    s += (L->rgba[i * 4 + c] - rgb[c]) * (L->rgba[i * 4 + c] - rgb[c]);
                out_rms[i] = (float)sqrt(s / 3.0);
            }
        }
        if (out_rms[i] >= 0.0f) {
            sum += out_rms[i];
            valid++;
        }
    }
    free(status);
    free(sq);
    *out_mean = valid ? sum / (double)valid : 0.0;
    *out_valid = n ? (double)valid / (double)n : 0.0;
    return ok;
}

/* Per-pixel sqrt of the relMSE term (t - r)^2 / (r^2 + eps), mean over R, G, B; the frame's
 * relMSE into out_relmse. -1 where the sizes differ (nothing drawn). */
static void ref_error(const hsrt_eye_image *t, const hsrt_eye_image *r, float *out,
                      double *out_relmse)
{
    size_t n = (size_t)t->w * t->h;
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        double s = 0.0;
        for (int c = 0; c < 3; c++) {
            double d = (double)t->rgba[i * 4 + c] - r->rgba[i * 4 + c];
            s += d * d /
                 ((double)r->rgba[i * 4 + c] * r->rgba[i * 4 + c] + XRSC_METRICS_RELMSE_EPSILON);
        }
        sum += s;
        out[i] = (float)sqrt(s / 3.0);
    }
    *out_relmse = n ? sum / (3.0 * (double)n) : 0.0;
}

/* Pane geometry: the area between the bars (the whole window without the overlay). */
static pv_rect pane_area(const pv_canvas *cv, const hsrt_view_state *vs, bool scale)
{
    uint32_t top = vs->overlay ? bar_height(cv) : 0;
    uint32_t bottom = vs->overlay && scale ? scale_height(cv) : 0;
    pv_rect a = {0, (int32_t)top, cv->w, cv->h > top + bottom + 1 ? cv->h - top - bottom : 1};
    return a;
}

static pv_rect half(pv_rect a, int side)
{
    uint32_t hw = a.w / 2;
    pv_rect r = {a.x + (side ? (int32_t)hw : 0), a.y, side ? a.w - hw : hw, a.h};
    return r;
}

/* Two panes (image k in half k) with labels and the divider. */
static bool two_panes(const pv_canvas *cv, const hsrt_view_state *vs, pv_rect area,
                      const hsrt_eye_image *img[2], const char *const names[2])
{
    bool ok = true;
    for (int k = 0; k < 2 && ok; k++) {
        pv_rect r = fit_rect(img[k]->w, img[k]->h, half(area, k));
        ok = draw_pane(img[k], NULL, r, cv);
        if (vs->overlay)
            label(cv, r.x + 2 * (int32_t)cv->s, r.y + 2 * (int32_t)cv->s, names[k]);
    }
    if (vs->overlay)
        fill(cv, (int32_t)(area.w / 2) - (int32_t)cv->s, area.y, 2 * cv->s, area.h, k_divider);
    return ok;
}

void hsrt_view_cache_free(hsrt_view_cache *c)
{
    if (!c)
        return;
    free(c->rms);
    memset(c, 0, sizeof(*c));
}

/* The stereo difference of f from the cache, or computed into it (a local one without). */
static const hsrt_view_cache *stereo_diff_cached(const hsrt_preview_frame *f,
                                                 hsrt_view_cache *cache, hsrt_view_cache *local)
{
    hsrt_view_cache *c = cache ? cache : local;
    const hsrt_eye_image *L = &f->eyes[0];
    if (c->valid && c->frame == f->frame && c->w == L->w && c->h == L->h)
        return c;
    float *rms = realloc(c->rms, (size_t)L->w * L->h * sizeof(float));
    if (!rms)
        return NULL;
    c->rms = rms;
    c->depth = hsrt_view_stereo_diff(f, c->rms, &c->mean, &c->compared);
    c->valid = true;
    c->frame = f->frame;
    c->w = L->w;
    c->h = L->h;
    return c;
}

static bool view_stereo_diff(const pv_canvas *cv, const hsrt_preview_frame *f,
                             const hsrt_view_state *vs)
{
    const hsrt_eye_image *L = &f->eyes[0];
    hsrt_view_cache local = {0};
    const hsrt_view_cache *c = stereo_diff_cached(f, vs->cache, &local);
    bool depth = c && c->depth;
    double mean = depth ? c->mean : 0.0, valid = depth ? c->compared : 0.0;
    pv_rect area = pane_area(cv, vs, true);
    pv_rect r = fit_rect(L->w, L->h, area);
    bool ok = true;
    char cap[160];
    if (depth) {
        hsrt_eye_image heat;
        ok = heat_image(c->rms, L->w, L->h, HSRT_PREVIEW_STEREO_SCALE, &heat) &&
             draw_pane(&heat, NULL, r, cv);
        free(heat.rgb);
        snprintf(cap, sizeof(cap), "STEREO DIFF BY DEPTH: MEAN %.4f, %.0f%% COMPARED", mean,
                 valid * 100.0);
    } else {
        ok = draw_pane(&f->eyes[0], &f->eyes[1], r, cv);
        snprintf(cap, sizeof(cap), "RAW L-R X%d: NO DEPTH LAYER, PARALLAX NOT COMPENSATED",
                 HSRT_PREVIEW_DIFF_GAIN);
    }
    hsrt_view_cache_free(&local);
    if (vs->overlay) {
        label(cv, r.x + 2 * (int32_t)cv->s, r.y + 2 * (int32_t)cv->s,
              depth ? "LEFT - RIGHT (REPROJECTED)" : "LEFT - RIGHT");
        if (depth)
            scale_strip(cv, cap, HSRT_PREVIEW_STEREO_SCALE);
        else
            label(cv, 0, (int32_t)(cv->h - (HS_FONT_H + 2) * cv->s), cap);
    }
    return ok;
}

static bool view_ref_error(const pv_canvas *cv, const hsrt_preview_frame *f,
                           const hsrt_view_state *vs)
{
    pv_rect area = pane_area(cv, vs, true);
    if (!vs->reference) {
        if (vs->overlay)
            label(cv, 4 * (int32_t)cv->s, area.y + (int32_t)(area.h / 2),
                  vs->has_reference ? "NO REFERENCE FRAME OF THIS NUMBER (OR OF ANOTHER SIZE)"
                                    : "NO REFERENCE: --preview-reference DIR");
        return true;
    }
    hsrt_eye_image heat[2] = {{0}};
    const hsrt_eye_image *img[2] = {&heat[0], &heat[1]};
    char names[2][64];
    double rel[2] = {0.0, 0.0};
    bool ok = true;
    for (int e = 0; e < 2 && ok; e++) {
        const hsrt_eye_image *t = &f->eyes[e];
        float *v = malloc((size_t)t->w * t->h * sizeof(float));
        ok = v != NULL;
        if (ok) {
            ref_error(t, &vs->reference[e], v, &rel[e]);
            ok = heat_image(v, t->w, t->h, HSRT_PREVIEW_REF_SCALE, &heat[e]);
        }
        free(v);
        snprintf(names[e], sizeof(names[e]), "%s VS REF: RELMSE %.4g", e ? "RIGHT" : "LEFT",
                 rel[e]);
    }
    const char *const nm[2] = {names[0], names[1]};
    ok = ok && two_panes(cv, vs, area, img, nm);
    free(heat[0].rgb);
    free(heat[1].rgb);
    if (vs->overlay)
        scale_strip(cv, "ERROR VS REFERENCE: SQRT((T-R)^2/(R^2+0.01))", HSRT_PREVIEW_REF_SCALE);
    return ok;
}

bool hsrt_view_compose(const hsrt_preview_frame *f, const hsrt_view_state *vs, uint8_t *out,
                       uint32_t w, uint32_t h, bool bgra)
{
    pv_canvas cv = {out, w, h, bgra, w >= PV_LARGE_TEXT_MIN_W ? 2u : 1u};
    memset(out, 0, (size_t)w * h * 4);
    for (size_t i = 0; i < (size_t)w * h; i++)
        out[i * 4 + 3] = 255;
    if (!f || !f->eyes[0].rgb || !f->eyes[1].rgb)
        return true;
    bool ok = true;
    pv_rect area = pane_area(&cv, vs, false);
    switch (vs->view) {
    case HSRT_VIEW_LEFT:
    case HSRT_VIEW_RIGHT: {
        int e = vs->view == HSRT_VIEW_RIGHT;
        pv_rect r = fit_rect(f->eyes[e].w, f->eyes[e].h, area);
        ok = draw_pane(&f->eyes[e], NULL, r, &cv);
        if (vs->overlay)
            label(&cv, r.x + 2 * (int32_t)cv.s, r.y + 2 * (int32_t)cv.s, e ? "RIGHT" : "LEFT");
        break;
    }
    case HSRT_VIEW_STEREO_DIFF:
        ok = view_stereo_diff(&cv, f, vs);
        break;
    case HSRT_VIEW_REF_ERROR:
        ok = view_ref_error(&cv, f, vs);
        break;
    default: {
        int l = vs->swapped ? 1 : 0;
        const hsrt_eye_image *img[2] = {&f->eyes[l], &f->eyes[1 - l]};
        const char *const names[2] = {l ? "RIGHT" : "LEFT", l ? "LEFT" : "RIGHT"};
        ok = two_panes(&cv, vs, area, img, names);
        break;
    }
    }
    if (vs->overlay)
        top_bar(&cv, f, vs);
    return ok;
}

const char *hsrt_view_name(const hsrt_preview_frame *f, const hsrt_view_state *vs)
{
    switch (vs->view) {
    case HSRT_VIEW_LEFT:
        return "left eye";
    case HSRT_VIEW_RIGHT:
        return "right eye";
    case HSRT_VIEW_STEREO_DIFF:
        return f && f->depth_m[0] && f->depth_m[1] ? "stereo difference" : "difference x4";
    case HSRT_VIEW_REF_ERROR:
        return "reference error";
    default:
        return vs->swapped ? "right|left" : "left|right";
    }
}
