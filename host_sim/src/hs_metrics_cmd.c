// SPDX-License-Identifier: MIT
/**
 * @file hs_metrics_cmd.c
 * @brief `xrsc metrics`: compares a test image sequence with a reference sequence (linear colour
 *        PFM) frame by frame with the metrics of xrsc_metrics.h and prints or writes the values.
 */
#include "hs_metrics_cmd.h"

#include "hs_args.h"
#include "hs_image.h"
#include "xrsc/xrsc_metrics.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_PATTERN "frame_%05u_left.pfm"
#define PATH_MAX_LEN 4096

/* clang-format off */
static void usage(FILE *f)
{
    fprintf(f,
"usage: xrsc metrics --ref DIR --test DIR [options]\n"
"\n"
"Compares two image sequences frame by frame: linear colour PFM files as `xrsc --write linear`\n"
"writes them. Per frame: relMSE, RMSE and mean SSIM of the test frame against the\n"
"reference frame, and the CPBD sharpness of both; then the means over the sequence.\n"
"\n"
"  --ref DIR           reference frames (e.g. `spp` with many samples per pixel)\n"
"  --test DIR          frames to evaluate (same names and sizes)\n"
"  --pattern FMT       file name with one %%u, zero padding allowed   [%s]\n"
"  --first N           first frame number                             [0]\n"
"  --frames N          N frames, an error if fewer exist (0 = until a reference frame is\n"
"                      missing)                                       [0]\n"
"  --csv PATH          also write the per-frame values as CSV\n"
"  --relmse-eps E      relMSE epsilon: (x - r)^2 / (r^2 + E)           [0.01]\n"
"  --range L           display range: luminance clamped to [0, L] for SSIM and CPBD [1]\n"
"  --cpbd-linear       CPBD on linear instead of sRGB-encoded luminance\n"
"  --quiet             print only the mean line\n"
"  -h, --help          this help\n"
"\n"
"The temporal (frame-to-frame reprojected) difference and the stereo discrepancy need each\n"
"frame's depth and eye poses, which the replay does not write yet; they are in the library\n"
"(xrsc_metrics.h) but not in this command.\n",
            DEFAULT_PATTERN);
}
/* clang-format on */

static int bad_arg(const char *flag, const char *value, const char *why)
{
    return hs_bad_arg("xrsc metrics", flag, value, why);
}

/* A number in (0, 1e30]. */
static bool parse_positive(const char *s, double *out)
{
    double v;
    if (!hs_parse_f(s, &v) || !(v > 0.0) || v > 1e30)
        return false;
    *out = v;
    return true;
}

/* A file-name pattern split around its one "%[0][width]u" (the user's text is never used as a
 * printf format; "%%" stands for "%"). */
typedef struct name_pattern {
    char prefix[512], suffix[512];
    bool zero_pad;
    int width;
} name_pattern;

static bool append_char(char *buf, size_t size, size_t *len, char c)
{
    if (*len + 1 >= size)
        return false;
    buf[(*len)++] = c;
    buf[*len] = '\0';
    return true;
}

static bool parse_pattern(const char *fmt, name_pattern *out)
{
    memset(out, 0, sizeof(*out));
    size_t plen = 0, slen = 0;
    int conversions = 0;
    for (const char *p = fmt; *p; p++) {
        char *buf = conversions ? out->suffix : out->prefix;
        size_t *len = conversions ? &slen : &plen;
        if (*p != '%') {
            if (!append_char(buf, sizeof(out->prefix), len, *p))
                return false;
            continue;
        }
        p++;
        if (*p == '%') {
            if (!append_char(buf, sizeof(out->prefix), len, '%'))
                return false;
            continue;
        }
        if (*p == '0') {
            out->zero_pad = true;
            p++;
        }
        while (*p >= '0' && *p <= '9') {
            out->width = out->width * 10 + (*p - '0');
            if (out->width > 20)
                return false;
            p++;
        }
        if (*p != 'u' || ++conversions > 1)
            return false;
    }
    return conversions == 1;
}

static bool frame_path(const char *dir, const name_pattern *pat, uint32_t frame, char *out,
                       size_t size)
{
    int n =
        pat->zero_pad
            ? snprintf(out, size, "%s/%s%0*u%s", dir, pat->prefix, pat->width, frame, pat->suffix)
            : snprintf(out, size, "%s/%s%*u%s", dir, pat->prefix, pat->width, frame, pat->suffix);
    return n > 0 && (size_t)n < size;
}

static bool file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    fclose(f);
    return true;
}

typedef struct frame_values {
    xrsc_error_metrics err;
    double ssim;
    xrsc_cpbd cpbd_test, cpbd_ref;
} frame_values;

/* Reads and compares one frame pair; returns 0, or 1 after printing the error. */
static int compare_frame(const char *ref_path, const char *test_path,
                         const xrsc_metrics_options *mo, frame_values *out)
{
    float *ref = NULL, *test = NULL;
    uint32_t rw = 0, rh = 0, tw = 0, th = 0;
    xrsc_diag diag = {0};
    char msg[1400];
    int rc = 1;
    if (hs_read_pfm(ref_path, &ref, &rw, &rh, &diag) != XRSC_OK ||
        hs_read_pfm(test_path, &test, &tw, &th, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc metrics: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        goto done;
    }
    if (rw != tw || rh != th) {
        fprintf(stderr, "xrsc metrics: error: %s is %ux%u but %s is %ux%u\n", test_path, tw, th,
                ref_path, rw, rh);
        goto done;
    }
    xrsc_result res = xrsc_metrics_error(test, ref, tw, th, mo, &out->err);
    if (res == XRSC_OK)
        res = xrsc_metrics_ssim(test, ref, tw, th, mo, &out->ssim, NULL);
    if (res == XRSC_OK)
        res = xrsc_metrics_cpbd(test, tw, th, mo, &out->cpbd_test);
    if (res == XRSC_OK)
        res = xrsc_metrics_cpbd(ref, rw, rh, mo, &out->cpbd_ref);
    if (res != XRSC_OK) {
        fprintf(stderr, "xrsc metrics: error: %s vs %s: %s [%s]\n", test_path, ref_path,
                xrsc_result_text(res), xrsc_result_name(res));
        goto done;
    }
    rc = 0;
done:
    free(ref);
    free(test);
    return rc;
}

int hs_metrics_main(int argc, char **argv)
{
    const char *ref_dir = NULL, *test_dir = NULL, *csv_path = NULL;
    const char *pattern = DEFAULT_PATTERN;
    uint32_t first = 0, max_frames = 0;
    bool quiet = false;
    xrsc_metrics_options mo = {0};

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        }
        if (!strcmp(a, "--quiet")) {
            quiet = true;
            continue;
        }
        if (!strcmp(a, "--cpbd-linear")) {
            mo.cpbd_linear = true;
            continue;
        }
        static const char *const with_value[] = {"--ref",    "--test", "--pattern",    "--first",
                                                 "--frames", "--csv",  "--relmse-eps", "--range"};
        if (!hs_arg_in(a, with_value, sizeof(with_value) / sizeof(with_value[0])))
            return bad_arg(a, NULL, a[0] == '-' ? "unknown option" : "unexpected argument");
        if (i + 1 >= argc)
            return bad_arg(a, NULL, "needs a value");
        const char *v = argv[++i];
        if (!strcmp(a, "--ref")) {
            ref_dir = v;
        } else if (!strcmp(a, "--test")) {
            test_dir = v;
        } else if (!strcmp(a, "--pattern")) {
            pattern = v;
        } else if (!strcmp(a, "--first")) {
            if (!hs_parse_u32(v, &first))
                return bad_arg(a, v, "expected a frame number");
        } else if (!strcmp(a, "--frames")) {
            if (!hs_parse_u32(v, &max_frames))
                return bad_arg(a, v, "expected a count");
        } else if (!strcmp(a, "--csv")) {
            csv_path = v;
        } else if (!strcmp(a, "--relmse-eps")) {
            if (!parse_positive(v, &mo.relmse_epsilon))
                return bad_arg(a, v, "expected a positive number");
        } else if (!strcmp(a, "--range")) {
            if (!parse_positive(v, &mo.display_range))
                return bad_arg(a, v, "expected a positive number");
        }
    }
    if (!ref_dir || !test_dir)
        return bad_arg(ref_dir ? "--test" : "--ref", NULL, "is required");
    name_pattern pat;
    if (!parse_pattern(pattern, &pat))
        return bad_arg("--pattern", pattern, "expected one %u (e.g. frame_%05u_left.pfm)");

    FILE *csv = NULL;
    if (csv_path) {
        csv = fopen(csv_path, "w");
        if (!csv) {
            fprintf(stderr, "xrsc metrics: error: cannot write %s\n", csv_path);
            return 1;
        }
        fprintf(csv, "frame,relmse,rmse,mse,ssim,cpbd_test,cpbd_ref,cpbd_test_edges,"
                     "cpbd_ref_edges\n");
    }
    if (!quiet)
        printf("%6s %12s %12s %9s %7s %7s\n", "frame", "relMSE", "RMSE", "SSIM", "CPBD", "CPBDref");

    double sum_rel = 0.0, sum_rmse = 0.0, sum_ssim = 0.0, sum_ct = 0.0, sum_cr = 0.0;
    uint32_t count = 0;
    int rc = 0;
    char ref_path[PATH_MAX_LEN], test_path[PATH_MAX_LEN];
    for (uint64_t f = first; f <= UINT32_MAX && (max_frames == 0 || count < max_frames); f++) {
        if (!frame_path(ref_dir, &pat, (uint32_t)f, ref_path, sizeof(ref_path)) ||
            !frame_path(test_dir, &pat, (uint32_t)f, test_path, sizeof(test_path))) {
            fprintf(stderr, "xrsc metrics: error: path too long\n");
            rc = 1;
            break;
        }
        if (!file_exists(ref_path)) {
            if (count == 0 || max_frames != 0) {
                fprintf(stderr, "xrsc metrics: error: reference frame %s is missing\n", ref_path);
                rc = 1;
            }
            break;
        }
        frame_values fv;
        if ((rc = compare_frame(ref_path, test_path, &mo, &fv)) != 0)
            break;
        if (!quiet)
            printf("%6u %12.6g %12.6g %9.6f %7.4f %7.4f\n", (uint32_t)f, fv.err.relmse, fv.err.rmse,
                   fv.ssim, fv.cpbd_test.cpbd, fv.cpbd_ref.cpbd);
        if (csv)
            fprintf(csv, "%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%llu,%llu\n", (uint32_t)f, fv.err.relmse,
                    fv.err.rmse, fv.err.mse, fv.ssim, fv.cpbd_test.cpbd, fv.cpbd_ref.cpbd,
                    (unsigned long long)fv.cpbd_test.edge_count,
                    (unsigned long long)fv.cpbd_ref.edge_count);
        sum_rel += fv.err.relmse;
        sum_rmse += fv.err.rmse;
        sum_ssim += fv.ssim;
        sum_ct += fv.cpbd_test.cpbd;
        sum_cr += fv.cpbd_ref.cpbd;
        count++;
    }
    if (csv && fclose(csv) != 0 && rc == 0) {
        fprintf(stderr, "xrsc metrics: error: cannot write %s\n", csv_path);
        rc = 1;
    }
    if (rc == 0 && count > 0)
        printf("%6s %12.6g %12.6g %9.6f %7.4f %7.4f  (%u frames)\n", "mean", sum_rel / count,
               sum_rmse / count, sum_ssim / count, sum_ct / count, sum_cr / count, count);
    return rc;
}
