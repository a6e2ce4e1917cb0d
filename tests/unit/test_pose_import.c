// SPDX-License-Identifier: MIT
/**
 * @file test_pose_import.c
 * @brief Unit tests of the column importer (--pose-columns, poses/README.md "Import by
 *        columns"): column lists, delimiters, header and index-column detection, time units,
 *        Unity handedness, and errors that name the line and column.
 */
#include "hs_pose_stream.h"
#include "testing.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static hs_pose_stream *import(const char *text, const char *spec, const char *unit,
                              const char *hand, xrsc_diag *d)
{
    hs_pose_columns c;
    xrsc_result r = hs_pose_columns_parse(spec, unit, hand, &c, d);
    CHECK_EQ_INT(r, XRSC_OK);
    if (r != XRSC_OK)
        return NULL;
    hs_pose_stream *s = NULL;
    hs_pose_stream_parse_columns("mem.csv", text, strlen(text), &c, &s, d);
    return s;
}

/** The same two samples in every layout: t = 0 and 0.5 s, (1, 2, 3), 90 deg about y. */
static void check_two(const hs_pose_stream *s)
{
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK_EQ_INT(s->count, 2);
    CHECK_EQ_INT(s->format, HS_POSE_FORMAT_COLUMNS);
    CHECK_EQ_INT(s->samples[0].time_ns, 0);
    CHECK_EQ_INT(s->samples[1].time_ns, 500000000);
    CHECK_NEAR(s->samples[1].pose.position.x, 1.0, 1e-6);
    CHECK_NEAR(s->samples[1].pose.position.y, 2.0, 1e-6);
    CHECK_NEAR(s->samples[1].pose.position.z, 3.0, 1e-6);
    CHECK_NEAR(s->samples[1].pose.orientation.y, 0.70710678, 1e-6);
    CHECK_NEAR(s->samples[1].pose.orientation.w, 0.70710678, 1e-6);
}

static void test_layouts(void)
{
    xrsc_diag d;
    hs_pose_stream *s;
    /* comma, header, xyz-first order */
    s = import("t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n0.5,1,2,3,0,0.70710678,0,0.70710678\n",
               "t,x,y,z,qx,qy,qz,qw", NULL, NULL, &d);
    check_two(s);
    hs_pose_stream_destroy(&s);
    /* tab-separated, qw first, no header */
    s = import("0\t1\t0\t0\t0\t0\t0\t0\n0.5\t0.70710678\t0\t0.70710678\t0\t1\t2\t3\n",
               "t,qw,qx,qy,qz,x,y,z", NULL, NULL, &d);
    check_two(s);
    hs_pose_stream_destroy(&s);
    /* semicolons and a pandas index column (empty header field), milliseconds */
    s = import(";time;px;py;pz;qx;qy;qz;qw\n0;0;0;0;0;0;0;0;1\n1;500;1;2;3;0;0.70710678;0;0.70710678\n",
               "t,x,y,z,qx,qy,qz,qw", "ms", NULL, &d);
    check_two(s);
    hs_pose_stream_destroy(&s);
    /* runs of spaces, a skipped column, integer nanoseconds, a comment */
    s = import("# capture\n0  7 0 0 0 0 0 0 1\n500000000  7 1 2 3 0 0.70710678 0 0.70710678\n",
               "t,_,x,y,z,qx,qy,qz,qw", "ns", NULL, &d);
    check_two(s);
    hs_pose_stream_destroy(&s);
    /* .NET ticks */
    s = import("100,0,0,0,0,0,0,1\n5000100,1,2,3,0,0.70710678,0,0.70710678\n",
               "t,x,y,z,qx,qy,qz,qw", "ticks", NULL, &d);
    check_two(s);
    hs_pose_stream_destroy(&s);
    /* microseconds */
    s = import("10,0,0,0,0,0,0,1\n500010,1,2,3,0,0.70710678,0,0.70710678\n",
               "t,x,y,z,qx,qy,qz,qw", "us", NULL, &d);
    check_two(s);
    hs_pose_stream_destroy(&s);
}

static void test_unity_handedness(void)
{
    xrsc_diag d;
    /* Unity: left-handed, +Z forward; as the pred6dof importer: z, qx, qy negated. */
    hs_pose_stream *s = import("0,1,2,3,0.1,0.2,0.3,0.92736185\n", "t,x,y,z,qx,qy,qz,qw", NULL,
                               "left-unity", &d);
    CHECK(s != NULL);
    if (s) {
        CHECK_NEAR(s->samples[0].pose.position.z, -3.0, 1e-6);
        CHECK_NEAR(s->samples[0].pose.orientation.x, -0.1, 1e-6);
        CHECK_NEAR(s->samples[0].pose.orientation.y, -0.2, 1e-6);
        CHECK_NEAR(s->samples[0].pose.orientation.z, 0.3, 1e-6);
        CHECK(!s->orientation_only);
    }
    hs_pose_stream_destroy(&s);
    /* orientation only */
    s = import("0,0,0,0,1\n1,0,0,0,1\n", "t,qx,qy,qz,qw", NULL, NULL, &d);
    CHECK(s != NULL && s->orientation_only && s->count == 2);
    hs_pose_stream_destroy(&s);
}

static void test_bad_specs(void)
{
    hs_pose_columns c;
    xrsc_diag d;
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qx,qy,qz", NULL, NULL, &c, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(!strcmp(d.field, "--pose-columns"));
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qx,qy,qz,qw,qw", NULL, NULL, &c, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,qx,qy,qz,qw", NULL, NULL, &c, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qx,qy,qz,w", NULL, NULL, &c, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(hs_pose_columns_parse("", NULL, NULL, &c, &d), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qx,qy,qz,qw", "h", NULL, &c, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(!strcmp(d.field, "--pose-time-unit"));
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qx,qy,qz,qw", NULL, "left", &c, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(!strcmp(d.field, "--pose-handedness"));
    CHECK_EQ_INT(hs_pose_columns_parse("T, X, Y, Z, QX, QY, QZ, QW", "s", "right", &c, &d),
                 XRSC_OK);
    hs_pose_stream *s = NULL;
    CHECK_EQ_INT(hs_pose_stream_parse_columns("m", "0,0,0,0,0,0,0,1\n", 16, NULL, &s, &d),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(s == NULL);
}

static void test_bad_files(void)
{
    hs_pose_columns c;
    xrsc_diag d;
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qx,qy,qz,qw", NULL, NULL, &c, &d), XRSC_OK);
    struct {
        const char *text;
        xrsc_result code;
        int line;
        const char *field;
    } cases[] = {
        {"t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n1,0,0,0,0,0,0\n", XRSC_ERROR_TRUNCATED_LINE, 3,
         "qw (column 8)"},
        {"0,0,0,0,0,0,0,1,9,9\n", XRSC_ERROR_UNKNOWN_COLUMN, 1, "field 9"},
        {"0,0,0,0,0,0,0,1\n1,0,abc,0,0,0,0,1\n", XRSC_ERROR_BAD_NUMBER, 2, "y (column 3)"},
        {"0,0,0,0,0,0,0,1\n1,0,0,0,0,0,0,2\n", XRSC_ERROR_QUAT_NOT_UNIT, 2, "qx qy qz qw"},
        {"1,0,0,0,0,0,0,1\n0.5,0,0,0,0,0,0,1\n", XRSC_ERROR_TIME_BACKWARDS, 2, "t (column 1)"},
        {"0,0,0,nan,0,0,0,1\n", XRSC_ERROR_NAN, 1, "z (column 4)"},
        {"t,x,y,z,qx,qy,qz,qw\n", XRSC_ERROR_EMPTY_FILE, 0, ""},
        {"0,1e300,0,0,0,0,0,1\n", XRSC_ERROR_NAN, 1, "x (column 2)"},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        hs_pose_stream *s = NULL;
        memset(&d, 0, sizeof(d));
        xrsc_result r = hs_pose_stream_parse_columns("bad.csv", cases[i].text,
                                                     strlen(cases[i].text), &c, &s, &d);
        CHECK_MSG(r == cases[i].code, "case %zu: %d", i, (int)r);
        CHECK_MSG(d.line == cases[i].line, "case %zu: line %d", i, d.line);
        CHECK_MSG(!strcmp(d.field, cases[i].field), "case %zu: field '%s'", i, d.field);
        CHECK(!strcmp(d.file, "bad.csv"));
        CHECK(s == NULL);
    }
}

static void test_load_file_and_folder(void)
{
    hs_pose_columns c;
    xrsc_diag d;
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qx,qy,qz,qw", NULL, NULL, &c, &d), XRSC_OK);
    const char *path = t_temp_file("import.csv", "t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n"
                                                 "0.5,1,2,3,0,0.70710678,0,0.70710678\n");
    hs_pose_stream *s = NULL;
    CHECK_EQ_INT(hs_pose_stream_load_columns(path, &c, &s, &d), XRSC_OK);
    check_two(s);
    hs_pose_stream_destroy(&s);
    /* a folder: XRSC_ERROR_IO saying so, for both loaders */
    CHECK_EQ_INT(hs_pose_stream_load_columns("/tmp", &c, &s, &d), XRSC_ERROR_IO);
    CHECK(strstr(d.message, "folder") != NULL);
    CHECK_EQ_INT(hs_pose_stream_load("/tmp", HS_POSE_FORMAT_AUTO, &s, &d), XRSC_ERROR_IO);
    CHECK(s == NULL);
}

int main(void)
{
    RUN(test_layouts);
    RUN(test_unity_handedness);
    RUN(test_bad_specs);
    RUN(test_bad_files);
    RUN(test_load_file_and_folder);
    return t_finish();
}
