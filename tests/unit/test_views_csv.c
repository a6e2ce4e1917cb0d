// SPDX-License-Identifier: MIT
/**
 * @file test_views_csv.c
 * @brief views.csv (hs_views_csv.h): rows written and read back bit for bit, columns by name,
 *        each kind of bad input refused with its ID and line/column; and `xrsc metrics
 *        --stereo` on synthetic EXR + views.csv files equals the library's metrics.
 */
#include "hs_exr.h"
#include "hs_metrics_cmd.h"
#include "hs_views_csv.h"
#include "testing.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const XrFovf FOV = {-0.9f, 0.8f, 0.7f, -0.75f};

static void round_trip(void)
{
    const char *path = t_temp_file("views_rt.csv", "");
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (!f)
        return;
    hs_views_csv_header(f);
    XrPosef p[2] = {{{0.1f, 0.2f, 0.3f, 0.9f}, {1.0f / 3.0f, 1.5f, -2.25e-7f}},
                    {{0.0f, 0.0f, 0.0f, 1.0f}, {0.0315f, 1.0f, 2.05f}}};
    /* a unit quaternion in float: normalise the first */
    float l = sqrtf(0.01f + 0.04f + 0.09f + 0.81f);
    p[0].orientation = (XrQuaternionf){0.1f / l, 0.2f / l, 0.3f / l, 0.9f / l};
    hs_views_csv_row(f, 7, 1, 123, &p[1], &FOV, 48, 32); /* written out of order */
    hs_views_csv_row(f, 7, 0, 123, &p[0], &FOV, 48, 32);
    fclose(f);
    hs_views_table t;
    xrsc_diag d = {0};
    CHECK_EQ_INT(hs_views_csv_read(path, &t, &d), XRSC_OK);
    CHECK_EQ_INT(t.count, 2);
    const hs_view_row *r0 = hs_views_find(&t, 7, 0), *r1 = hs_views_find(&t, 7, 1);
    CHECK(r0 && r1 && !hs_views_find(&t, 6, 0));
    if (r0 && r1) {
        CHECK(memcmp(&r0->camera.pose, &p[0], sizeof(XrPosef)) == 0); /* bit for bit */
        CHECK(memcmp(&r1->camera.pose, &p[1], sizeof(XrPosef)) == 0);
        CHECK(memcmp(&r0->camera.fov, &FOV, sizeof(XrFovf)) == 0);
        CHECK_EQ_INT(r1->camera.width, 48);
        CHECK_EQ_INT(r1->camera.height, 32);
    }
    hs_views_table_free(&t);
    remove(path);
}

/* Columns by name in any order, extra ones ignored, no size columns, comments and CRLF. */
static void by_name(void)
{
    const char *path =
        t_temp_file("views_names.csv", "# another engine\r\n"
                                       "eye,qw,qx,qy,qz,extra,pz,py,px,frame,angle_up,angle_down,"
                                       "angle_left,angle_right\r\n"
                                       "right,1,0,0,0,x,2,1,0.5,3,0.5,-0.5,-0.6,0.6\r\n");
    hs_views_table t;
    CHECK_EQ_INT(hs_views_csv_read(path, &t, NULL), XRSC_OK);
    const hs_view_row *r = hs_views_find(&t, 3, 1);
    CHECK(r != NULL);
    if (r) {
        CHECK_NEAR(r->camera.pose.position.x, 0.5, 0);
        CHECK_NEAR(r->camera.pose.position.z, 2.0, 0);
        CHECK_NEAR(r->camera.fov.angleLeft, -0.6f, 0);
        CHECK_EQ_INT(r->camera.width, 0); /* the image's size is taken */
    }
    hs_views_table_free(&t);
    remove(path);
}

typedef struct bad_case {
    const char *text;
    xrsc_result id;
    int line;
    const char *field;
} bad_case;

#define HDR "frame,eye,px,py,pz,qx,qy,qz,qw,angle_left,angle_right,angle_up,angle_down\n"
#define ROW "0,left,0,0,0,0,0,0,1,-0.5,0.5,0.5,-0.5\n"

static void bad_input(void)
{
    static const bad_case cases[] = {
        {"", XRSC_ERROR_EMPTY_FILE, 0, ""},
        {HDR, XRSC_ERROR_EMPTY_FILE, 1, ""},
        {"frame,eye,px,py,pz,qx,qy,qz,qw,angle_left,angle_right,angle_up\n" ROW,
         XRSC_ERROR_UNKNOWN_COLUMN, 1, "angle_down"},
        {HDR "0,left,0,0,0,0,0,0,1,-0.5,0.5\n", XRSC_ERROR_TRUNCATED_LINE, 2, "angle_up"},
        {HDR ROW "1,left,0,abc,0,0,0,0,1,-0.5,0.5,0.5,-0.5\n", XRSC_ERROR_BAD_NUMBER, 3, "py"},
        {HDR "0,middle,0,0,0,0,0,0,1,-0.5,0.5,0.5,-0.5\n", XRSC_ERROR_BAD_NUMBER, 2, "eye"},
        {HDR "1.5,left,0,0,0,0,0,0,1,-0.5,0.5,0.5,-0.5\n", XRSC_ERROR_BAD_NUMBER, 2, "frame"},
        {HDR "0,left,0,0,nan,0,0,0,1,-0.5,0.5,0.5,-0.5\n", XRSC_ERROR_NAN, 2, "pz"},
        {HDR "0,left,0,0,0,0,0,0,2,-0.5,0.5,0.5,-0.5\n", XRSC_ERROR_QUAT_NOT_UNIT, 2, "qw"},
        {HDR "0,left,0,0,0,0,0,0,1,0.5,-0.5,0.5,-0.5\n", XRSC_ERROR_INVALID_ARGUMENT, 2,
         "angle_right"},
        {HDR "0,left,0,0,0,0,0,0,1,-1.6,0.5,0.5,-0.5\n", XRSC_ERROR_INVALID_ARGUMENT, 2,
         "angle_left"},
        {HDR ROW ROW, XRSC_ERROR_INVALID_ARGUMENT, 0, "frame"},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        const char *path = t_temp_file("views_bad.csv", cases[i].text);
        hs_views_table t;
        xrsc_diag d = {0};
        CHECK_EQ_INT(hs_views_csv_read(path, &t, &d), cases[i].id);
        CHECK_EQ_INT(d.code, cases[i].id);
        CHECK_MSG(d.line == cases[i].line, "case %zu: line %d", i, d.line);
        CHECK_MSG(!strcmp(d.field, cases[i].field), "case %zu: field '%s'", i, d.field);
        CHECK(t.rows == NULL && t.count == 0);
        remove(path);
    }
    hs_views_table t;
    CHECK_EQ_INT(hs_views_csv_read("/nonexistent/views.csv", &t, NULL), XRSC_ERROR_IO);
}

/* ---- xrsc metrics --stereo on synthetic files ---- */

#define W 24
#define H 20
#define FRAMES 3

/* A sloped, textured wall: colour and depth of eye e at frame k, camera moving along +x. */
static void synth(uint32_t k, int e, float *rgba, float *depth, xrsc_metrics_camera *cam)
{
    cam->pose = (XrPosef){{0, 0, 0, 1}, {(e ? 0.032f : -0.032f) + 0.01f * (float)k, 0, 0}};
    cam->fov = FOV;
    cam->width = W;
    cam->height = H;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            depth[i] = x < 3 ? 0.0f : 2.0f + 0.02f * (float)x; /* background column */
            float v = (float)((x * 7 + y * 3 + k * 5 + (uint32_t)e * 11) % 13) / 13.0f;
            rgba[4 * i + 0] = v;
            rgba[4 * i + 1] = 0.5f * v;
            rgba[4 * i + 2] = 1.0f - v;
            rgba[4 * i + 3] = 1.0f;
        }
}

/* The expected values through the library, with the bench's arithmetic. */
static void expected(double *temporal, double *stereo)
{
    static float rgba[2][2][W * H * 4], depth[2][2][W * H];
    xrsc_metrics_camera cam[2][2];
    double tsum = 0, ssum = 0;
    for (uint32_t k = 0; k < FRAMES; k++) {
        uint32_t c = k & 1, p = c ^ 1u;
        for (int e = 0; e < 2; e++)
            synth(k, e, rgba[c][e], depth[c][e], &cam[c][e]);
        xrsc_metrics_view v[2], pv[2];
        for (int e = 0; e < 2; e++) {
            v[e] = (xrsc_metrics_view){rgba[c][e], depth[c][e], cam[c][e]};
            pv[e] = (xrsc_metrics_view){rgba[p][e], depth[p][e], cam[p][e]};
        }
        xrsc_reproj_diff d;
        xrsc_metrics_stereo_discrepancy(&v[1], &v[0], NULL, &d, NULL, NULL);
        ssum += d.mean_sq_diff;
        if (k == 0)
            continue;
        double s = 0;
        uint64_t n = 0;
        for (int e = 0; e < 2; e++) {
            xrsc_metrics_temporal_diff(&v[e], &pv[e], NULL, &d, NULL, NULL);
            s += d.mean_sq_diff * (double)d.valid_count;
            n += d.valid_count;
        }
        tsum += s / (double)n;
    }
    *temporal = tsum / (FRAMES - 1);
    *stereo = ssum / FRAMES;
}

static int run_metrics(const char *const *args, int n)
{
    char *argv[16];
    argv[0] = "metrics";
    for (int i = 0; i < n; i++)
        argv[i + 1] = (char *)args[i];
    fflush(stdout);
    return hs_metrics_main(n + 1, argv);
}

/* A CSV field of `row` (1 = first data row) and column (0-based). */
static double csv_cell(const char *path, int row, int col)
{
    FILE *f = fopen(path, "r");
    char line[512];
    double v = NAN;
    for (int r = 0; f && fgets(line, sizeof(line), f); r++) {
        if (r != row)
            continue;
        char *p = line;
        for (int c = 0; c < col && p; c++)
            p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
        v = p && *p != ',' ? strtod(p, NULL) : NAN;
    }
    if (f)
        fclose(f);
    return v;
}

static void stereo_command(void)
{
    char dir[1024], path[1200], csv[1200];
    snprintf(dir, sizeof(dir), "%s", t_temp_file("stereo_dir", ""));
    remove(dir);
    CHECK(mkdir(dir, 0755) == 0);
    snprintf(path, sizeof(path), "%s/" HS_VIEWS_CSV, dir);
    FILE *vf = fopen(path, "w");
    CHECK(vf != NULL);
    if (!vf)
        return;
    hs_views_csv_header(vf);
    static float rgba[W * H * 4], depth[W * H];
    for (uint32_t k = 0; k < FRAMES; k++)
        for (int e = 0; e < 2; e++) {
            xrsc_metrics_camera cam;
            synth(k, e, rgba, depth, &cam);
            hs_views_csv_row(vf, k + 1, (uint32_t)e, 0, &cam.pose, &cam.fov, W, H);
            snprintf(path, sizeof(path), "%s/frame_%05u_%s.exr", dir, k + 1, e ? "right" : "left");
            CHECK_EQ_INT(hs_write_exr(path, rgba, depth, W, H, NULL), XRSC_OK);
        }
    fclose(vf);
    double t, s;
    expected(&t, &s);
    snprintf(csv, sizeof(csv), "%s/st.csv", dir);
    const char *ok[] = {"--stereo", dir, "--csv", csv, "--quiet"};
    CHECK_EQ_INT(run_metrics(ok, 5), 0);
    double tm = 0, sm = 0;
    for (int r = 1; r <= FRAMES; r++) {
        sm += csv_cell(csv, r, 3);
        tm += r > 1 ? csv_cell(csv, r, 1) : 0.0;
    }
    CHECK(isnan(csv_cell(csv, 1, 1)));          /* no temporal value on the first frame */
    CHECK_NEAR(csv_cell(csv, 1, 0), 1, 0);      /* frames start at the lowest number, 1 */
    CHECK(s > 1e-4 && t > 1e-4);                /* the synthetic frames do differ */
    CHECK_NEAR(tm / (FRAMES - 1), t, 1e-8 * t); /* %.9g in the CSV */
    CHECK_NEAR(sm / FRAMES, s, 1e-8 * s);

    const char *both[] = {"--stereo", dir, "--ref", dir};
    CHECK_EQ_INT(run_metrics(both, 4), 2);
    const char *not_exr[] = {"--stereo", dir, "--pattern", "frame_%05u_left.pfm"};
    CHECK_EQ_INT(run_metrics(not_exr, 4), 2);
    const char *no_views[] = {"--stereo", dir, "--views", "/nonexistent/views.csv", "--quiet"};
    CHECK_EQ_INT(run_metrics(no_views, 5), 1);
    const char *too_many[] = {"--stereo", dir, "--frames", "4", "--quiet"};
    CHECK_EQ_INT(run_metrics(too_many, 5), 1);
    /* a frame missing from views.csv */
    snprintf(path, sizeof(path), "%s/short.csv", dir);
    vf = fopen(path, "w");
    if (vf) {
        fputs(HDR "1,left,0,0,0,0,0,0,1,-0.5,0.5,0.5,-0.5\n", vf);
        fclose(vf);
    }
    const char *short_views[] = {"--stereo", dir, "--views", path, "--quiet"};
    CHECK_EQ_INT(run_metrics(short_views, 5), 1);
    /* wrong image size in views.csv */
    snprintf(path, sizeof(path), "%s/size.csv", dir);
    vf = fopen(path, "w");
    if (vf) {
        hs_views_csv_header(vf);
        for (int e = 0; e < 2; e++)
            hs_views_csv_row(vf, 1, (uint32_t)e, 0, &(XrPosef){{0, 0, 0, 1}, {0, 0, 0}}, &FOV,
                             W + 1, H);
        fclose(vf);
    }
    const char *bad_size[] = {"--stereo", dir, "--views", path, "--frames", "1", "--quiet"};
    CHECK_EQ_INT(run_metrics(bad_size, 7), 1);
    const char *warm_only[] = {"--ref", dir, "--test", dir, "--warmup", "1"};
    CHECK_EQ_INT(run_metrics(warm_only, 6), 2);
    static const char *const made[] = {HS_VIEWS_CSV, "st.csv", "short.csv", "size.csv"};
    for (size_t i = 0; i < sizeof(made) / sizeof(made[0]); i++) {
        snprintf(path, sizeof(path), "%s/%s", dir, made[i]);
        remove(path);
    }
    for (uint32_t k = 0; k < 2 * FRAMES; k++) {
        snprintf(path, sizeof(path), "%s/frame_%05u_%s.exr", dir, k / 2 + 1,
                 k & 1 ? "right" : "left");
        remove(path);
    }
    CHECK(rmdir(dir) == 0);
}

int main(void)
{
    RUN(round_trip);
    RUN(by_name);
    RUN(bad_input);
    RUN(stereo_command);
    return t_finish();
}
