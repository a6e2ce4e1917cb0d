// SPDX-License-Identifier: MIT
/**
 * @file hs_bench.c
 * @brief `xrsc bench` run: references, then every setting over the same frames, one CSV row per
 *        frame and setting (hs_bench.h). The summary and charts are in hs_bench_report.c.
 */
#include "hs_bench.h"

#include "hs_args.h"
#include "hs_bench_columns.h"
#include "hs_bench_report.h"
#include "hs_image.h"
#include "u_diag.h"
#include "xrsc/xrsc_metrics.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define NS_PER_S 1000000000.0
#define DEFAULT_EYE_SIZE_PX 128u
#define DEFAULT_REF_SPP 256u
#define DEFAULT_REFRESH_HZ 90.0
/** Seed of the references: independent of the benchmarked settings' noise. */
#define REF_SEED_XOR 0x9E3779B9u
/** Seed of the second reference (--ref-floor): independent of both. */
#define REF_FLOOR_SEED_XOR 0x85EBCA6Bu
/** Accumulation passes of a reference use frame indices REF_FRAME_STRIDE apart per frame. */
#define REF_FRAME_STRIDE 65536u
/** Progress lines without a terminal: one per this many seconds. */
#define PROGRESS_LOG_PERIOD_S 10.0

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* ---- progress ---- */

typedef struct progress {
    bool on, tty;
    double started, last;
} progress;

static void progress_line(progress *p, bool final, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void progress_line(progress *p, bool final, const char *fmt, ...)
{
    if (!p->on)
        return;
    double t = now_s();
    if (!final && ((p->tty && t - p->last < 0.1) || (!p->tty && t - p->last < PROGRESS_LOG_PERIOD_S)))
        return;
    p->last = t;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof(line), fmt, ap);
    va_end(ap);
    fprintf(stderr, "%s%s  elapsed %.0f s%s", p->tty ? "\r\033[K" : "", line, t - p->started,
            p->tty && !final ? "" : "\n");
    fflush(stderr);
}

/* ---- the run's fixed state ---- */

typedef struct bench_run {
    const hs_bench_options *opt;
    uint32_t w, h, frames, warmup, score_every, ref_spp;
    xrsc_headset headset;
    xrsc_frame *frame; /**< [frames]: views, display time, frame index */
    xrsc_context *ctx;
    xrsc_scene *scene;
    xrsc_renderer *depth_r; /**< `primary`: depth at pixel centres for the reprojections */
    char config[2048];      /**< everything a setting's rows depend on */
    char ref_config[1600];  /**< everything a reference depends on */
    char ref_dir[HS_BENCH_PATH_MAX - 64];
    progress prog;
    uint32_t metric_failures;
    double ref_floor_relmse; /**< --ref-floor: relMSE between the two references; else NaN */
    uint32_t floor_frame;
    /** [frame * 2 + eye]: the colour of the --baseline setting's scored frames, kept for the
     *  other settings' base_energy (seed 002 §5.1), NULL where not rendered in this run */
    float **base_color;
} bench_run;

/* suffix: "" for the reference, "_floor" for the second one of --ref-floor. */
#define REF_FILE_NAME "frame_%05u_%s%s.pfm"

static void ref_path_s(const bench_run *b, uint32_t k, int eye, const char *suffix, char *out,
                       size_t cap)
{
    snprintf(out, cap, "%s/" REF_FILE_NAME, b->ref_dir, k, eye ? "right" : "left", suffix);
}

void hs_bench_ref_path(const char *out_dir, uint32_t k, int eye, char *out, size_t cap)
{
    snprintf(out, cap, "%s/ref/" REF_FILE_NAME, out_dir, k, eye ? "right" : "left", "");
}

/* Head pose at t of the anchored stream; eye views from the recorded views when the stream
 * has them, else from the simulated headset. */
static void make_frame(const bench_run *b, const hs_pose_stream *stream, uint32_t k,
                       int64_t start_ns, double period_ns, xrsc_frame *out)
{
    int64_t t_ns = start_ns + (int64_t)(k * period_ns + 0.5);
    memset(out, 0, sizeof(*out));
    out->display_time_ns = t_ns - start_ns;
    out->frame_index = k;
    hs_view_sample vs;
    if (stream->views && hs_pose_stream_sample_views(stream, t_ns, &vs) != HS_LOOKUP_CLAMPED) {
        for (int e = 0; e < 2; e++) {
            out->views[e].pose = vs.pose[e];
            out->views[e].fov = vs.fov[e];
        }
        return;
    }
    XrPosef head, eyes[2];
    hs_pose_stream_sample(stream, t_ns, &head);
    xrsc_headset_eye_poses(&b->headset, head, eyes);
    for (int e = 0; e < 2; e++) {
        out->views[e].pose = eyes[e];
        out->views[e].fov = b->headset.fov[e];
    }
}

static bool read_file_line(const char *path, char *out, size_t cap)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    bool ok = fgets(out, (int)cap, f) != NULL;
    fclose(f);
    if (ok)
        out[strcspn(out, "\n")] = '\0';
    return ok;
}

/* path + ".tmp.PID": the temporary name of a file before its rename, this process's own, so
 * that processes sharing a folder (sweep units) never write into one another's file. */
static void tmp_name(const char *path, char *out, size_t cap)
{
    snprintf(out, cap, "%s.tmp.%ld", path, (long)getpid());
}

static xrsc_result write_text_atomic(const char *path, const char *text, xrsc_diag *diag)
{
    char tmp[HS_BENCH_PATH_MAX + 64];
    tmp_name(path, tmp, sizeof(tmp));
    FILE *f = fopen(tmp, "w");
    if (!f || fputs(text, f) < 0 || fclose(f) != 0 || rename(tmp, path) != 0)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot write: %s", strerror(errno));
    return XRSC_OK;
}

/* ---- references ---- */

/* Reads both eyes of frame k's reference (suffix: ref_path_s); false when missing, unreadable
 * or of another size. */
static bool ref_load_s(const bench_run *b, uint32_t k, const char *suffix, float *out[2])
{
    for (int e = 0; e < 2; e++) {
        char path[HS_BENCH_PATH_MAX];
        ref_path_s(b, k, e, suffix, path, sizeof(path));
        float *px = NULL;
        uint32_t w = 0, h = 0;
        xrsc_diag d = {0};
        if (hs_read_pfm(path, &px, &w, &h, &d) != XRSC_OK)
            return false;
        if (w != b->w || h != b->h) {
            free(px);
            return false;
        }
        if (out) {
            memcpy(out[e], px, (size_t)w * h * 4 * sizeof(float));
        }
        free(px);
    }
    return true;
}

static bool ref_load(const bench_run *b, uint32_t k, float *out[2])
{
    return ref_load_s(b, k, "", out);
}

/* Largest power of two <= 64 dividing n: samples per accumulation pass. */
static uint32_t ref_chunk(uint32_t n)
{
    uint32_t c = 64;
    while (c > 1 && n % c)
        c /= 2;
    return c;
}

/* Renders frame k's reference (ref_spp samples accumulated with renderer r) into both eyes'
 * ref_path_s(suffix) files. px: w*h*4 floats of scratch. */
static xrsc_result render_reference(bench_run *b, xrsc_renderer *r, uint32_t k,
                                    const char *suffix, float *px, double t0, uint32_t done,
                                    uint32_t todo, xrsc_diag *diag)
{
    uint32_t chunk = ref_chunk(b->ref_spp), passes = b->ref_spp / chunk;
    size_t n = (size_t)b->w * b->h;
    xrsc_result res = XRSC_OK;
    xrsc_frame f = b->frame[k];
    for (uint32_t p = 0; p < passes && res == XRSC_OK; p++) {
        f.frame_index = k * REF_FRAME_STRIDE + p;
        if ((res = xrsc_renderer_render(r, &f)) != XRSC_OK)
            u_diag_set(diag, res, b->opt->scene_path, 0, "", "reference of frame %u failed", k);
        double per = (now_s() - t0) / (done + (p + 1.0) / passes);
        progress_line(&b->prog, false, "reference%s %u/%u (frame %u)  %u/%u spp  left ~%.0f s",
                      suffix, done + 1, todo, k, (p + 1) * chunk, b->ref_spp,
                      per * (todo - done - (p + 1.0) / passes));
    }
    for (int e = 0; e < 2 && res == XRSC_OK; e++) {
        char path[HS_BENCH_PATH_MAX], tmp[HS_BENCH_PATH_MAX + 32];
        ref_path_s(b, k, e, suffix, path, sizeof(path));
        tmp_name(path, tmp, sizeof(tmp));
        if ((res = xrsc_renderer_read(r, (uint32_t)e, XRSC_OUTPUT_COLOR, px,
                                      n * 4 * sizeof(float))) != XRSC_OK)
            u_diag_set(diag, res, "", 0, "", "reading reference of frame %u", k);
        else if ((res = hs_write_pfm(tmp, px, b->w, b->h, diag)) == XRSC_OK &&
                 rename(tmp, path) != 0)
            res = u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "rename: %s", strerror(errno));
    }
    return res;
}

/* The reference cache: kept when it belongs to this configuration (config.txt), else
 * emptied, so that another configuration's references are never taken for this one's. A part
 * of a sweep (opt->part) shares it with other processes: it never empties it, and another
 * configuration's cache is an error. */
static xrsc_result ref_cache_check(bench_run *b, xrsc_diag *diag)
{
    char cfg_path[HS_BENCH_PATH_MAX + 16], old[sizeof(b->ref_config)];
    snprintf(cfg_path, sizeof(cfg_path), "%s/config.txt", b->ref_dir);
    bool have = read_file_line(cfg_path, old, sizeof(old));
    if (have && strcmp(old, b->ref_config) == 0 && !(b->opt->fresh && !b->opt->part))
        return XRSC_OK;
    if (have && b->opt->part) /* shared with other processes: never emptied */
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, cfg_path, 1, "--out",
                          "the references there are of another configuration (%s), not %s",
                          old, b->ref_config);
    for (uint32_t k = 0; k < b->frames && !b->opt->part; k++)
        for (int e = 0; e < 2; e++)
            for (int s = 0; s < 2; s++) {
                char path[HS_BENCH_PATH_MAX];
                ref_path_s(b, k, e, s ? "_floor" : "", path, sizeof(path));
                unlink(path);
            }
    char text[sizeof(b->ref_config) + 2];
    snprintf(text, sizeof(text), "%s\n", b->ref_config);
    return write_text_atomic(cfg_path, text, diag);
}

/* Frame k's reference is this run's to render or read: scored, and with --part ref the one
 * frame asked for. */
static bool ref_wanted(const bench_run *b, uint32_t k)
{
    return hs_bench_is_scored(k, b->warmup, b->score_every) &&
           (b->opt->part != HS_BENCH_PART_REF || k == b->opt->part_frame);
}

/* Renders the references still missing (pass 0) and --ref-floor's second reference of the
 * first scored frame with another seed (pass 1); all = how many, for the progress line. */
static xrsc_result render_references(bench_run *b, bool refs_todo, bool floor_todo,
                                     uint32_t all, float *px, xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    xrsc_result res = XRSC_OK;
    double t0 = now_s();
    uint32_t done = 0;
    for (int pass = 0; pass < 2 && res == XRSC_OK; pass++) {
        if ((pass == 0 && !refs_todo) || (pass == 1 && !floor_todo))
            continue;
        uint32_t chunk = ref_chunk(b->ref_spp);
        xrsc_renderer_options ro = {
            .method = XRSC_METHOD_SPP, .width = b->w, .height = b->h,
            .seed = opt->seed ^ (pass ? REF_FLOOR_SEED_XOR : REF_SEED_XOR),
            .spp = {.samples_per_pixel = chunk, .accumulate = true}};
        xrsc_renderer *r = NULL;
        if ((res = xrsc_renderer_create(b->ctx, b->scene, &ro, &r, diag)) != XRSC_OK)
            break;
        for (uint32_t k = 0; k < b->frames && res == XRSC_OK; k++) {
            if (pass == 1 ? k != b->floor_frame : !ref_wanted(b, k) || ref_load(b, k, NULL))
                continue;
            res = render_reference(b, r, k, pass ? "_floor" : "", px, t0, done, all, diag);
            done++;
        }
        xrsc_renderer_destroy(&r);
    }
    if (all)
        progress_line(&b->prog, true, "references: %u rendered", done);
    return res;
}

/* The noise floor: relMSE of the second reference of the floor frame against the first, as
 * a setting's would be measured. */
static xrsc_result measure_floor(bench_run *b, float *px, xrsc_diag *diag)
{
    size_t n = (size_t)b->w * b->h;
    float *ra[2] = {malloc(n * 4 * sizeof(float)), malloc(n * 4 * sizeof(float))};
    float *rb[2] = {px, malloc(n * 4 * sizeof(float))};
    const xrsc_metrics_options mo = {0};
    xrsc_result res = XRSC_OK;
    if (!ra[0] || !ra[1] || !rb[1]) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "reference images");
    } else if (!ref_load(b, b->floor_frame, ra) ||
               !ref_load_s(b, b->floor_frame, "_floor", rb)) {
        res = u_diag_set(diag, XRSC_ERROR_IO, b->ref_dir, 0, "--ref-floor",
                         "references of frame %u are missing or unreadable", b->floor_frame);
    } else {
        double sum = 0;
        for (int e = 0; e < 2; e++) {
            xrsc_error_metrics em;
            sum += xrsc_metrics_error(rb[e], ra[e], b->w, b->h, &mo, &em) == XRSC_OK
                       ? 0.5 * em.relmse
                       : NAN;
        }
        b->ref_floor_relmse = sum;
    }
    free(ra[0]);
    free(ra[1]);
    free(rb[1]);
    return res;
}

static xrsc_result make_references(bench_run *b, xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    if (opt->timing_only)
        return XRSC_OK; /* nothing is scored */
    xrsc_result res = ref_cache_check(b, diag);
    if (res != XRSC_OK)
        return res;
    uint32_t todo = 0, scored = 0;
    bool have_floor_frame = false;
    if (opt->part == HS_BENCH_PART_REF && !ref_wanted(b, opt->part_frame))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--part",
                          "frame %u is not a scored frame of %u frames (warm-up %u, every %u)",
                          opt->part_frame, b->frames, b->warmup, b->score_every);
    for (uint32_t k = 0; k < b->frames; k++)
        if (ref_wanted(b, k)) {
            if (!have_floor_frame) {
                b->floor_frame = k;
                have_floor_frame = true;
            }
            scored++;
            if (!ref_load(b, k, NULL))
                todo++;
        }
    bool floor_todo = opt->ref_floor && have_floor_frame &&
                      !ref_load_s(b, b->floor_frame, "_floor", NULL);
    if (opt->progress)
        fprintf(stderr,
                "xrsc bench: %u scored frames, %u references to render (%u spp), %u cached%s\n",
                scored, todo, b->ref_spp, scored - todo,
                !opt->ref_floor ? ""
                : floor_todo    ? "; +1 for --ref-floor"
                                : "; --ref-floor's cached");
    float *px = malloc((size_t)b->w * b->h * 4 * sizeof(float));
    if (!px)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "reference image");
    res = render_references(b, todo > 0, floor_todo, todo + (floor_todo ? 1u : 0u), px, diag);
    if (res == XRSC_OK && opt->ref_floor && have_floor_frame)
        res = measure_floor(b, px, diag);
    free(px);
    return res;
}

/* ---- one setting ---- */

typedef struct eye_images {
    float *color[2], *depth[2];
} eye_images;

static void eye_images_free(eye_images *im)
{
    for (int e = 0; e < 2; e++) {
        free(im->color[e]);
        free(im->depth[e]);
    }
}

static bool eye_images_alloc(eye_images *im, size_t n)
{
    memset(im, 0, sizeof(*im));
    for (int e = 0; e < 2; e++) {
        im->color[e] = malloc(n * 4 * sizeof(float));
        im->depth[e] = malloc(n * sizeof(float));
        if (!im->color[e] || !im->depth[e])
            return false;
    }
    return true;
}

static xrsc_metrics_view metrics_view(const bench_run *b, const eye_images *im, uint32_t k, int e)
{
    xrsc_metrics_view v = {
        .rgba = im->color[e],
        .depth_m = im->depth[e],
        .camera = {.pose = b->frame[k].views[e].pose, .fov = b->frame[k].views[e].fov,
                   .width = b->w, .height = b->h},
    };
    return v;
}

static void put_num(FILE *f, double v, bool have)
{
    if (!have)
        fputs(",", f);
    else if (!isfinite(v))
        fputs(",nan", f);
    else
        fprintf(f, ",%.6g", v);
}

static bool metric_ok(bench_run *b, xrsc_result r)
{
    if (r == XRSC_OK)
        return true;
    b->metric_failures++;
    return false;
}

/* Renders frame k with r and reads its colour, and the depth at pixel centres (the same
 * for every setting) for the reprojections, into cur. */
static xrsc_result render_frame(bench_run *b, const hs_bench_setting *s, xrsc_renderer *r,
                                uint32_t k, eye_images *cur, double *out_wall_ms,
                                xrsc_diag *diag)
{
    const xrsc_frame *f = &b->frame[k];
    size_t n = (size_t)b->w * b->h;
    double w0 = now_s();
    xrsc_result res = xrsc_renderer_render(r, f);
    if (res != XRSC_OK)
        return u_diag_set(diag, res, "", 0, "", "setting %s: frame %u failed", s->name, k);
    *out_wall_ms = (now_s() - w0) * 1e3;
    if (b->opt->timing_only)
        return XRSC_OK; /* no image is measured */
    for (int e = 0; e < 2; e++)
        if ((res = xrsc_renderer_read(r, (uint32_t)e, XRSC_OUTPUT_COLOR, cur->color[e],
                                      n * 4 * sizeof(float))) != XRSC_OK)
            return u_diag_set(diag, res, "", 0, "", "setting %s: reading frame %u", s->name, k);
    if ((res = xrsc_renderer_render(b->depth_r, f)) != XRSC_OK)
        return res;
    for (int e = 0; e < 2; e++)
        if ((res = xrsc_renderer_read(b->depth_r, (uint32_t)e, XRSC_OUTPUT_DEPTH, cur->depth[e],
                                      n * sizeof(float))) != XRSC_OK)
            return res;
    return XRSC_OK;
}

/* The CSV's header: the fixed columns, the passes' times, the method's counters. */
static void csv_header(FILE *csv, const xrsc_pass_timing *pass, uint32_t np,
                       const xrsc_counter *counter, uint32_t nc)
{
    for (uint32_t c = 0; c < HS_BENCH_COLUMN_COUNT; c++)
        fprintf(csv, "%s%s", c ? "," : "", hs_bench_columns[c]);
    for (uint32_t p = 0; p < np; p++)
        fprintf(csv, ",gpu_%s_ms", pass[p].name);
    for (uint32_t c = 0; c < nc; c++)
        fprintf(csv, "," HS_BENCH_COUNTER_PREFIX "%s", counter[c].name);
    fputc('\n', csv);
}

/* relmse, rmse, ssim against the reference (scored frames; empty otherwise), cpbd of the
 * frame, ref_cpbd of the reference; ref is loaded here on scored frames. */
static xrsc_result put_error_columns(bench_run *b, FILE *csv, const eye_images *cur, uint32_t k,
                                     bool scored, float *ref[2], xrsc_diag *diag)
{
    const xrsc_metrics_options mo = {0};
    double relmse = 0, rmse = 0, ssim = 0, ref_cpbd = 0;
    if (scored) {
        if (!ref_load(b, k, ref))
            return u_diag_set(diag, XRSC_ERROR_IO, b->ref_dir, 0, "",
                              "reference of frame %u is missing or unreadable", k);
        for (int e = 0; e < 2; e++) {
            xrsc_error_metrics em;
            double ms;
            xrsc_cpbd cp;
            if (metric_ok(b, xrsc_metrics_error(cur->color[e], ref[e], b->w, b->h, &mo, &em))) {
                relmse += 0.5 * em.relmse;
                rmse += 0.5 * em.rmse;
            } else {
                relmse = rmse = NAN;
            }
            ssim += metric_ok(b, xrsc_metrics_ssim(cur->color[e], ref[e], b->w, b->h, &mo, &ms,
                                                   NULL))
                        ? 0.5 * ms
                        : NAN;
            ref_cpbd += metric_ok(b, xrsc_metrics_cpbd(ref[e], b->w, b->h, &mo, &cp))
                            ? 0.5 * cp.cpbd
                            : NAN;
        }
        /* RMSE of both eyes together: sqrt of the mean MSE. */
        if (isfinite(rmse)) {
            double mse = 0;
            for (int e = 0; e < 2; e++) {
                xrsc_error_metrics em;
                if (xrsc_metrics_error(cur->color[e], ref[e], b->w, b->h, &mo, &em) == XRSC_OK)
                    mse += 0.5 * em.mse;
            }
            rmse = sqrt(mse);
        }
    }
    put_num(csv, relmse, scored);
    put_num(csv, rmse, scored);
    put_num(csv, ssim, scored);
    double cpbd = 0;
    for (int e = 0; e < 2; e++) {
        xrsc_cpbd cp;
        cpbd += metric_ok(b, xrsc_metrics_cpbd(cur->color[e], b->w, b->h, &mo, &cp))
                    ? 0.5 * cp.cpbd
                    : NAN;
    }
    put_num(csv, cpbd, true);
    put_num(csv, ref_cpbd, scored);
    return XRSC_OK;
}

/* temporal_msd, temporal_valid: this frame against the previous one reprojected by depth,
 * per eye, weighted by the valid pixels (empty on frame 0). */
static void put_temporal_columns(bench_run *b, FILE *csv, const eye_images *cur,
                                 const eye_images *prev, uint32_t k)
{
    if (k == 0) {
        fputs(",,", csv);
        return;
    }
    const xrsc_metrics_options mo = {0};
    double sum = 0;
    uint64_t valid = 0;
    bool ok = true;
    for (int e = 0; e < 2; e++) {
        xrsc_metrics_view vc = metrics_view(b, cur, k, e), vp = metrics_view(b, prev, k - 1, e);
        xrsc_reproj_diff d;
        if (metric_ok(b, xrsc_metrics_temporal_diff(&vc, &vp, &mo, &d, NULL, NULL))) {
            sum += d.mean_sq_diff * (double)d.valid_count;
            valid += d.valid_count;
        } else {
            ok = false;
        }
    }
    put_num(csv, ok && valid ? sum / (double)valid : NAN, true);
    fprintf(csv, ",%llu", (unsigned long long)valid);
}

/* stereo_msd, stereo_valid: the right eye against the left reprojected into it (seed 000
 * Fig. 15); ref_stereo_msd: the reference's own (scored frames), not zero where shading is
 * view-dependent, the level a blend should reach rather than zero. */
static void put_stereo_columns(bench_run *b, FILE *csv, const eye_images *cur, uint32_t k,
                               bool scored, float *const ref[2])
{
    const xrsc_metrics_options mo = {0};
    xrsc_metrics_view vr = metrics_view(b, cur, k, 1), vl = metrics_view(b, cur, k, 0);
    xrsc_reproj_diff d;
    if (metric_ok(b, xrsc_metrics_stereo_discrepancy(&vr, &vl, &mo, &d, NULL, NULL))) {
        put_num(csv, d.valid_count ? d.mean_sq_diff : NAN, true);
        fprintf(csv, ",%llu", (unsigned long long)d.valid_count);
    } else {
        fputs(",nan,0", csv);
    }
    if (!scored) {
        fputc(',', csv);
        return;
    }
    eye_images rim = *cur;
    rim.color[0] = ref[0];
    rim.color[1] = ref[1];
    vr = metrics_view(b, &rim, k, 1);
    vl = metrics_view(b, &rim, k, 0);
    put_num(csv,
            metric_ok(b, xrsc_metrics_stereo_discrepancy(&vr, &vl, &mo, &d, NULL, NULL)) &&
                    d.valid_count
                ? d.mean_sq_diff
                : NAN,
            true);
}

/* base_energy (scored frames, with --baseline listed before): seed 002 §5.1's change of
 * energy against the baseline's image of the same frame, sum |I - I_base| / sum I_base over
 * the rgb of both eyes. Every setting renders the same views with the same random numbers,
 * so between a cache on and off it is the error the cache alone adds. */
static void put_base_column(bench_run *b, const hs_bench_setting *s, FILE *csv,
                            const eye_images *cur, uint32_t k, bool scored)
{
    const char *base = b->opt->baseline;
    size_t n = (size_t)b->w * b->h * 4;
    double diff = 0.0, total = 0.0;
    bool have = scored && base && b->base_color;
    for (int e = 0; have && e < 2; e++) {
        float **keep = &b->base_color[2 * k + (uint32_t)e];
        if (!strcmp(s->name, base) && !*keep && (*keep = malloc(n * sizeof(float))))
            memcpy(*keep, cur->color[e], n * sizeof(float));
        have = *keep != NULL;
        for (size_t i = 0; have && i < n; i++)
            if (i % 4 != 3) {
                diff += fabs((double)cur->color[e][i] - (*keep)[i]);
                total += fabs((double)(*keep)[i]);
            }
    }
    put_num(csv, total > 0.0 ? diff / total : NAN, have);
}

/* --keep-frames: scored frame k's two eyes as OUT/frames/NAME/frame_K_EYE.pfm. */
static xrsc_result keep_frame(bench_run *b, const hs_bench_setting *s, const eye_images *cur,
                              uint32_t k, xrsc_diag *diag)
{
    char dir[HS_BENCH_PATH_MAX], path[HS_BENCH_PATH_MAX + 64];
    snprintf(dir, sizeof(dir), "%s/frames/%s", b->opt->out_dir, s->name);
    xrsc_result res = hs_make_dirs(dir, "--keep-frames", diag);
    for (int e = 0; e < 2 && res == XRSC_OK; e++) {
        snprintf(path, sizeof(path), "%s/" REF_FILE_NAME, dir, k, e ? "right" : "left", "");
        res = hs_write_pfm(path, cur->color[e], b->w, b->h, diag);
    }
    return res;
}

/* One frame of setting s: rendered, measured, its CSV row written. */
static xrsc_result bench_frame(bench_run *b, const hs_bench_setting *s, xrsc_renderer *r,
                               uint32_t k, eye_images im[2], float *ref[2], FILE *csv,
                               xrsc_diag *diag)
{
    eye_images *cur = &im[k & 1], *prev = &im[(k + 1) & 1];
    double wall_ms = 0.0;
    xrsc_result res = render_frame(b, s, r, k, cur, &wall_ms, diag);
    if (res != XRSC_OK)
        return res;
    xrsc_pass_timing pass[XRSC_MAX_PASSES];
    uint32_t np = xrsc_renderer_timings(r, pass, XRSC_MAX_PASSES);
    uint64_t rays = xrsc_renderer_rays_last_frame(r);
    xrsc_counter counter[XRSC_MAX_COUNTERS];
    uint32_t nc = xrsc_renderer_counters(r, counter, XRSC_MAX_COUNTERS);
    if (k == 0)
        csv_header(csv, pass, np, counter, nc);
    double gpu_ms = 0.0;
    for (uint32_t p = 0; p < np; p++)
        gpu_ms += pass[p].gpu_ms;
    bool scored = !b->opt->timing_only && hs_bench_is_scored(k, b->warmup, b->score_every);
    fprintf(csv, "%s,%s,%u,%lld,%d,%d,%.4f,%.4f,%llu,%.5f", s->name,
            xrsc_method_name(s->renderer.method), k, (long long)b->frame[k].display_time_ns,
            k < b->warmup, scored, wall_ms, gpu_ms, (unsigned long long)rays,
            (double)rays / (2.0 * (double)b->w * b->h));
    if (b->opt->timing_only) { /* the image metrics' columns, empty */
        for (uint32_t c = BENCH_FIRST_METRIC_COLUMN; c < HS_BENCH_COLUMN_COUNT; c++)
            fputc(',', csv);
    } else {
        if ((res = put_error_columns(b, csv, cur, k, scored, ref, diag)) != XRSC_OK)
            return res;
        put_temporal_columns(b, csv, cur, prev, k);
        put_stereo_columns(b, csv, cur, k, scored, ref);
        put_base_column(b, s, csv, cur, k, scored);
        if (scored && b->opt->keep_frames && (res = keep_frame(b, s, cur, k, diag)) != XRSC_OK)
            return res;
    }
    for (uint32_t p = 0; p < np; p++)
        fprintf(csv, ",%.4f", pass[p].gpu_ms);
    for (uint32_t c = 0; c < nc; c++)
        fprintf(csv, ",%.6g", counter[c].value);
    fputc('\n', csv);
    return XRSC_OK;
}

static xrsc_result run_setting(bench_run *b, const hs_bench_setting *s, uint32_t index,
                               xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    char path[HS_BENCH_PATH_MAX], part[HS_BENCH_PATH_MAX + 32];
    hs_bench_setting_csv_path(opt->out_dir, s->name, path, sizeof(path));
    if (opt->part)
        snprintf(part, sizeof(part), "%s.part.%ld", path, (long)getpid());
    else
        snprintf(part, sizeof(part), "%s.part", path);
    char first_line[sizeof(b->config) + HS_BENCH_SPEC_MAX + 32];
    snprintf(first_line, sizeof(first_line), "# xrsc-bench %s | setting %s", b->config, s->spec);
    if (!opt->fresh) {
        char old[sizeof(first_line)];
        if (read_file_line(path, old, sizeof(old)) && strcmp(old, first_line) == 0) {
            if (opt->progress)
                fprintf(stderr, "xrsc bench: setting %u/%u %s: complete in %s, skipped\n",
                        index + 1, opt->setting_count, s->name, path);
            return XRSC_OK;
        }
    }

    xrsc_renderer_options ro = s->renderer;
    ro.width = b->w;
    ro.height = b->h;
    ro.seed = opt->seed;
    xrsc_renderer *r = NULL;
    xrsc_result res = xrsc_renderer_create(b->ctx, b->scene, &ro, &r, diag);
    if (res != XRSC_OK) {
        u_diag_set(diag, res, "", 0, "--settings", "setting %s (%s): renderer creation failed",
                   s->name, s->spec);
        return res;
    }
    size_t n = (size_t)b->w * b->h;
    size_t color_bytes = n * 4 * sizeof(float);
    eye_images im[2]; /* [k & 1]: this frame and the previous one */
    float *ref[2] = {malloc(color_bytes), malloc(color_bytes)};
    FILE *csv = NULL;
    bool ok_alloc = eye_images_alloc(&im[0], n) & eye_images_alloc(&im[1], n);
    if (!ok_alloc || !ref[0] || !ref[1]) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "image buffers");
        goto done;
    }
    csv = fopen(part, "w");
    if (!csv) {
        res = u_diag_set(diag, XRSC_ERROR_IO, part, 0, "", "cannot create: %s", strerror(errno));
        goto done;
    }
    fprintf(csv, "%s\n", first_line);

    double t0 = now_s();
    for (uint32_t k = 0; k < b->frames; k++) {
        if ((res = bench_frame(b, s, r, k, im, ref, csv, diag)) != XRSC_OK)
            goto done;
        double per = (now_s() - t0) / (k + 1);
        progress_line(&b->prog, k + 1 == b->frames,
                      "setting %u/%u %-22s frame %u/%u  %.2f s/frame  left ~%.0f s", index + 1,
                      opt->setting_count, s->name, k + 1, b->frames, per,
                      per * (b->frames - k - 1) +
                          per * b->frames * (opt->setting_count - index - 1));
    }
    if (fclose(csv) != 0) {
        csv = NULL;
        res = u_diag_set(diag, XRSC_ERROR_IO, part, 0, "", "writing failed");
        goto done;
    }
    csv = NULL;
    if (rename(part, path) != 0)
        res = u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "rename: %s", strerror(errno));

done:
    if (csv)
        fclose(csv);
    eye_images_free(&im[0]);
    eye_images_free(&im[1]);
    free(ref[0]);
    free(ref[1]);
    xrsc_renderer_destroy(&r);
    return res;
}

static bool headset_is_zero(const xrsc_headset *hs)
{
    static const xrsc_headset zero;
    return memcmp(hs, &zero, sizeof(zero)) == 0;
}

static void fov_text(const XrFovf *f, char *out, size_t cap)
{
    snprintf(out, cap, "%.6g/%.6g/%.6g/%.6g", f->angleLeft, f->angleRight, f->angleUp,
             f->angleDown);
}

/* The frame count: --frames, else the stream from --start to its end. */
static xrsc_result frame_count(bench_run *b, const hs_pose_stream *stream, double period_ns,
                               xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    int64_t start_ns = (int64_t)(opt->start_s * NS_PER_S);
    int64_t span_ns = hs_pose_stream_duration_ns(stream) - start_ns;
    if (span_ns < 0)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, opt->poses_path, 0, "--start",
                          "the stream ends at %.3f s, before --start %.3f s",
                          hs_pose_stream_duration_ns(stream) / NS_PER_S, opt->start_s);
    b->frames = opt->frames ? opt->frames : (uint32_t)(span_ns / period_ns) + 1;
    return XRSC_OK;
}

/* Every setting's frames: the frame count (--frames, else the stream from --start to its
 * end), the stream anchored (--anchor), the views of each frame on the simulated clock. */
static xrsc_result bench_frames(bench_run *b, hs_pose_stream *stream,
                                const xrsc_scene_info *info, xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    double period_ns =
        NS_PER_S / (b->headset.refresh_hz > 0 ? b->headset.refresh_hz : DEFAULT_REFRESH_HZ);
    int64_t start_ns = (int64_t)(opt->start_s * NS_PER_S);
    xrsc_result res = frame_count(b, stream, period_ns, diag);
    if (res != XRSC_OK)
        return res;
    if (opt->anchor == HS_BENCH_ANCHOR_FIRST) {
        hs_pose_stream_anchor(stream, info->viewpoint);
    } else if (opt->anchor == HS_BENCH_ANCHOR_START && stream->count > 0) {
        /* viewpoint * inverse(pose at start) * p, through hs_pose_stream_anchor's
         * viewpoint' * inverse(first) * p with viewpoint' = viewpoint * inverse(at) * first. */
        XrPosef at;
        hs_pose_stream_sample(stream, start_ns, &at);
        XrPosef first = stream->samples[0].pose;
        hs_pose_stream_anchor(stream, xrsc_pose_mul(xrsc_pose_mul(info->viewpoint,
                                                                  xrsc_pose_inverse(at)),
                                                    first));
    }
    b->frame = calloc(b->frames, sizeof(*b->frame));
    if (!b->frame)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "--frames", "%u frames",
                          b->frames);
    for (uint32_t k = 0; k < b->frames; k++)
        make_frame(b, stream, k, start_ns, period_ns, &b->frame[k]);
    return XRSC_OK;
}

/* The configuration texts: what the references depend on (ref_config, ref/config.txt), and
 * what a setting's CSV depends on besides its spec (config, its first line). */
static void bench_config(bench_run *b, const char *device)
{
    const hs_bench_options *opt = b->opt;
    static const char *const anchor_name[] = {"start", "first", "none"};
    char fov0[96], fov1[96], env[96] = "scene";
    fov_text(&b->headset.fov[0], fov0, sizeof(fov0));
    fov_text(&b->headset.fov[1], fov1, sizeof(fov1));
    if (opt->scene.env_set)
        snprintf(env, sizeof(env), "%g/%g/%g", opt->scene.environment[0],
                 opt->scene.environment[1], opt->scene.environment[2]);
    snprintf(b->ref_config, sizeof(b->ref_config),
             "scene=%s poses=%s format=%s anchor=%s start=%.9g res=%ux%u ref_spp=%u seed=%u "
             "ipd=%g refresh=%g fov=%s,%s env=%s",
             opt->scene_path, opt->poses_path, hs_pose_format_name(opt->pose_format),
             anchor_name[opt->anchor], opt->start_s, b->w, b->h, b->ref_spp, opt->seed,
             b->headset.ipd_m, b->headset.refresh_hz, fov0, fov1, env);
    if (opt->scene.animation) { /* the clip changes every frame's image (issue 21) */
        size_t at = strlen(b->ref_config);
        snprintf(b->ref_config + at, sizeof(b->ref_config) - at, " animation=%s",
                 opt->scene.animation);
    }
    /* columns=: CSVs written with other columns are rendered again, not reused. */
    snprintf(b->config, sizeof(b->config),
             "%s frames=%u warmup=%u score_every=%u device=%s columns=%u%s", b->ref_config,
             b->frames, b->warmup, b->score_every, device,
             HS_BENCH_COLUMN_COUNT, opt->timing_only ? " timing-only" : "");
    if (opt->scene.blas_update) { /* the blas pass's cost differs (issue 21 item 4) */
        size_t at = strlen(b->config);
        snprintf(b->config + at, sizeof(b->config) - at, " blas_update=%s",
                 opt->scene.blas_update == XRSC_BLAS_UPDATE_REFIT ? "refit" : "rebuild");
    }
}

/** The run's sizes and defaults from the options. */
static void bench_init(bench_run *b, const hs_bench_options *opt)
{
    *b = (bench_run){.opt = opt, .ref_floor_relmse = NAN};
    b->prog.on = opt->progress;
    b->prog.tty = isatty(STDERR_FILENO);
    b->prog.started = now_s();
    b->w = opt->width ? opt->width : DEFAULT_EYE_SIZE_PX;
    b->h = opt->height ? opt->height : DEFAULT_EYE_SIZE_PX;
    b->warmup = opt->warmup;
    b->score_every = opt->score_every ? opt->score_every : 1;
    b->ref_spp = opt->ref_spp ? opt->ref_spp : DEFAULT_REF_SPP;
    b->headset = opt->headset;
    if (headset_is_zero(&b->headset))
        xrsc_headset_default(&b->headset);
}

/** The ref/ and frames/ folders under --out, and the run's first progress line. */
static xrsc_result bench_dirs(bench_run *b, xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    char dir[HS_BENCH_PATH_MAX];
    snprintf(b->ref_dir, sizeof(b->ref_dir), "%s/ref", opt->out_dir);
    snprintf(dir, sizeof(dir), "%s/frames", opt->out_dir);
    xrsc_result res;
    if ((res = hs_make_dirs(b->ref_dir, "--out", diag)) != XRSC_OK ||
        (res = hs_make_dirs(dir, "--out", diag)) != XRSC_OK)
        return res;
    if (opt->progress)
        fprintf(stderr,
                "xrsc bench: %u settings x %u frames (%u warm-up, every %u scored), %ux%u per "
                "eye, on %s\n",
                opt->setting_count, b->frames, b->warmup, b->score_every, b->w, b->h,
                xrsc_context_device_name(b->ctx));
    return XRSC_OK;
}

/** The references, then every setting (with the depth renderer the temporal and stereo
 *  metrics reproject by), then warnings on failed metrics and validation errors. */
static xrsc_result bench_settings(bench_run *b, xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    xrsc_result res;
    if ((res = make_references(b, diag)) != XRSC_OK || opt->part == HS_BENCH_PART_REF)
        return res;
    xrsc_renderer_options dro = {.method = XRSC_METHOD_PRIMARY, .width = b->w, .height = b->h};
    if ((res = xrsc_renderer_create(b->ctx, b->scene, &dro, &b->depth_r, diag)) != XRSC_OK)
        return res;
    for (uint32_t i = 0; i < opt->setting_count; i++)
        if ((res = run_setting(b, &opt->settings[i], i, diag)) != XRSC_OK)
            return res;
    if (b->metric_failures)
        fprintf(stderr,
                "xrsc bench: warning: %u metric evaluations failed (NaN/inf pixels); "
                "their cells are nan\n",
                b->metric_failures);
    uint32_t verr = xrsc_context_validation_errors(b->ctx);
    if (verr)
        fprintf(stderr, "xrsc bench: warning: the Vulkan validation layer reported %u errors\n",
                verr);
    return XRSC_OK;
}

/** Frees what hs_bench_run made (NULL members are skipped). */
static void bench_free(bench_run *b)
{
    xrsc_renderer_destroy(&b->depth_r);
    xrsc_scene_destroy(&b->scene);
    xrsc_context_destroy(&b->ctx);
    for (uint32_t i = 0; b->base_color && i < 2 * b->frames; i++)
        free(b->base_color[i]);
    free(b->base_color);
    free(b->frame);
}

/* The device a setting's CSV was rendered on: its first line's "device=..." up to
 * " columns=". False when the file is missing or has no such line. */
static bool csv_device(const char *path, char *first, size_t cap, char *device, size_t dcap)
{
    if (!read_file_line(path, first, cap))
        return false;
    const char *d = strstr(first, " device="), *c = d ? strstr(d, " columns=") : NULL;
    if (!c)
        return false;
    d += strlen(" device=");
    snprintf(device, dcap, "%.*s", (int)(c - d), d);
    return true;
}

/* Each setting's CSV is complete and of this configuration; the names of those that are
 * not complete listed in diag. */
static xrsc_result check_settings(bench_run *b, const char *device, xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    char missing[512] = "";
    size_t used = 0;
    for (uint32_t i = 0; i < opt->setting_count; i++) {
        const hs_bench_setting *st = &opt->settings[i];
        char path[HS_BENCH_PATH_MAX], first[sizeof(b->config) + HS_BENCH_SPEC_MAX + 32];
        char want[sizeof(first)], dev[256];
        hs_bench_setting_csv_path(opt->out_dir, st->name, path, sizeof(path));
        snprintf(want, sizeof(want), "# xrsc-bench %s | setting %s", b->config, st->spec);
        if (!csv_device(path, first, sizeof(first), dev, sizeof(dev))) {
            int n = snprintf(missing + used, sizeof(missing) - used, "%s%s", used ? ", " : "",
                             st->name);
            used = n > 0 && used + (size_t)n < sizeof(missing) ? used + (size_t)n
                                                                : sizeof(missing) - 1;
        } else if (strcmp(first, want) != 0) {
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path, 1, "--settings",
                              "setting %s was rendered with another configuration (on %s; "
                              "this report's device is %s)", st->name, dev, device);
        }
    }
    if (used)
        return u_diag_set(diag, XRSC_ERROR_IO, opt->out_dir, 0, "--part",
                          "settings not complete in frames/: %s", missing);
    return XRSC_OK;
}

/* --part report: no device, no rendering; the frame count from the stream, the device from
 * the first complete setting's CSV, every setting checked (check_settings), then the report. */
static xrsc_result report_only(bench_run *b, const hs_pose_stream *stream, FILE *summary,
                               xrsc_diag *diag)
{
    const hs_bench_options *opt = b->opt;
    double period_ns =
        NS_PER_S / (b->headset.refresh_hz > 0 ? b->headset.refresh_hz : DEFAULT_REFRESH_HZ);
    xrsc_result res = frame_count(b, stream, period_ns, diag);
    char device[256] = "", path[HS_BENCH_PATH_MAX], first[sizeof(b->config) + HS_BENCH_SPEC_MAX + 32];
    for (uint32_t i = 0; i < opt->setting_count && !device[0]; i++) {
        hs_bench_setting_csv_path(opt->out_dir, opt->settings[i].name, path, sizeof(path));
        csv_device(path, first, sizeof(first), device, sizeof(device));
    }
    if (res != XRSC_OK)
        return res;
    bench_config(b, device);
    if ((res = check_settings(b, device, diag)) != XRSC_OK)
        return res;
    hs_bench_report_info ri = {
        .frames = b->frames, .warmup = b->warmup, .score_every = b->score_every,
        .ref_spp = b->ref_spp, .width = b->w, .height = b->h, .device = device,
        .ref_floor_relmse = NAN,
    };
    return hs_bench_report(opt, &ri, summary, diag);
}

xrsc_result hs_bench_scored_frames(const hs_bench_options *opt, uint32_t *out, uint32_t cap,
                                   uint32_t *count, xrsc_diag *diag)
{
    bench_run b;
    bench_init(&b, opt);
    *count = 0;
    hs_pose_stream *stream = NULL;
    xrsc_result res = hs_pose_stream_load(opt->poses_path, opt->pose_format, &stream, diag);
    double period_ns =
        NS_PER_S / (b.headset.refresh_hz > 0 ? b.headset.refresh_hz : DEFAULT_REFRESH_HZ);
    if (res == XRSC_OK)
        res = frame_count(&b, stream, period_ns, diag);
    for (uint32_t k = 0; res == XRSC_OK && k < b.frames; k++)
        if (hs_bench_is_scored(k, b.warmup, b.score_every)) {
            if (*count == cap)
                res = u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, opt->poses_path, 0,
                                 "--frames", "more than %u scored frames", cap);
            else
                out[(*count)++] = k;
        }
    hs_pose_stream_destroy(&stream);
    return res;
}

xrsc_result hs_bench_run(const hs_bench_options *opt, FILE *summary, xrsc_diag *diag)
{
    if (!opt || !opt->scene_path || !opt->poses_path || !opt->out_dir || !opt->out_dir[0] ||
        !opt->settings || opt->setting_count == 0)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "",
                          "bench needs a scene, a pose stream, an output folder and settings");
    bench_run b;
    bench_init(&b, opt);
    hs_pose_stream *stream = NULL;
    xrsc_result res;
    if ((res = hs_pose_stream_load(opt->poses_path, opt->pose_format, &stream, diag)) != XRSC_OK)
        goto done;
    if (opt->part == HS_BENCH_PART_REPORT) {
        res = report_only(&b, stream, summary, diag);
        goto done;
    }
    if ((res = xrsc_context_create(&opt->context, &b.ctx, diag)) != XRSC_OK)
        goto done;
    if ((res = xrsc_scene_load(b.ctx, opt->scene_path, &opt->scene, &b.scene, diag)) != XRSC_OK)
        goto done;
    xrsc_scene_info info;
    xrsc_scene_get_info(b.scene, &info);
    if ((res = bench_frames(&b, stream, &info, diag)) != XRSC_OK)
        goto done;
    bench_config(&b, xrsc_context_device_name(b.ctx));
    b.base_color = calloc(2 * (size_t)b.frames, sizeof(float *)); /* NULL: no base_energy */
    if ((res = bench_dirs(&b, diag)) != XRSC_OK || (res = bench_settings(&b, diag)) != XRSC_OK ||
        opt->part != HS_BENCH_PART_ALL)
        goto done;
    hs_bench_report_info ri = {
        .frames = b.frames, .warmup = b.warmup, .score_every = b.score_every, .ref_spp = b.ref_spp,
        .width = b.w, .height = b.h, .device = xrsc_context_device_name(b.ctx),
        .ref_floor_relmse = b.ref_floor_relmse, .floor_frame = b.floor_frame,
    };
    res = hs_bench_report(opt, &ri, summary, diag);
done:
    bench_free(&b);
    hs_pose_stream_destroy(&stream);
    return res;
}
