// SPDX-License-Identifier: MIT
/**
 * @file test_librnr.c
 * @brief Unit tests of the librnr importer (poses/README.md, "Importer: librnr"): view pairs
 *        with per-eye FOV, head space records, detection, lookup, anchoring, bad input.
 */
#include "hs_pose_stream.h"
#include "testing.h"

#include <string.h>

static hs_pose_stream *parse(const char *text, hs_pose_format format, xrsc_diag *diag)
{
    hs_pose_stream *s = NULL;
    memset(diag, 0, sizeof(*diag));
    xrsc_result r = hs_pose_stream_parse("t.txt", text, strlen(text), format, &s, diag);
    if (r != XRSC_OK) {
        char msg[1400];
        fprintf(stderr, "  (expected or not) %s\n", xrsc_diag_format(diag, msg, sizeof(msg)));
    }
    return s;
}

/* Two eyes 64 mm apart at 1.6 m height looking down -Z, then turned; FOV up right down left. */
static const char *const k_views =
    "0 v XR_REFERENCE_SPACE_TYPE_LOCAL 0 0 0 1 -0.032 1.6 0 0.8 0.7 -0.9 -0.75 2 0\n"
    "0 v XR_REFERENCE_SPACE_TYPE_LOCAL 0 0 0 1 0.032 1.6 0 0.8 0.75 -0.9 -0.7 2 1\n"
    "5000000 b /user/hand/left/input/select/click 1 1 4000000 1\n"
    "5000000 s /user/hand/left/input/grip/pose 0 0 0 1 0.2 1.0 -0.3 XR_REFERENCE_SPACE_TYPE_LOCAL\n"
    "10000000 v XR_REFERENCE_SPACE_TYPE_LOCAL 0 0.7071068 0 0.7071068 -0.032 1.6 0.1 0.6 0.5 -0.7 -0.55 2 0\n"
    "10000000 v XR_REFERENCE_SPACE_TYPE_LOCAL 0 0.7071068 0 0.7071068 0.032 1.6 0.1 0.6 0.55 -0.7 -0.5 2 1\n"
    "12000000 f /user/hand/right/input/trigger/value 1 1 12000000 0.5\n";

static void test_views(void)
{
    xrsc_diag d;
    hs_pose_stream *s = parse(k_views, HS_POSE_FORMAT_AUTO, &d);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK(s->format == HS_POSE_FORMAT_LIBRNR);
    CHECK_EQ_INT(s->count, 2);
    CHECK(s->views != NULL);
    CHECK(!s->orientation_only);
    CHECK_EQ_INT(s->samples[0].time_ns, 0);
    CHECK_EQ_INT(s->samples[1].time_ns, 10000000);
    /* Head at the eyes' midpoint. */
    CHECK_NEAR(s->samples[0].pose.position.x, 0.0, 1e-7);
    CHECK_NEAR(s->samples[0].pose.position.y, 1.6, 1e-6);
    CHECK_NEAR(s->samples[1].pose.position.z, 0.1, 1e-7);
    CHECK_NEAR(s->samples[1].pose.orientation.y, 0.7071068, 1e-6);
    /* FOV: the file's order is up right down left. */
    const XrFovf *l = &s->views[0].fov[0], *r = &s->views[0].fov[1];
    CHECK_NEAR(l->angleUp, 0.8, 1e-7);
    CHECK_NEAR(l->angleRight, 0.7, 1e-7);
    CHECK_NEAR(l->angleDown, -0.9, 1e-7);
    CHECK_NEAR(l->angleLeft, -0.75, 1e-7);
    CHECK_NEAR(r->angleRight, 0.75, 1e-7);
    CHECK_NEAR(r->angleLeft, -0.7, 1e-7);
    CHECK_NEAR(s->views[0].pose[0].position.x, -0.032, 1e-7);
    CHECK_NEAR(s->views[0].pose[1].position.x, 0.032, 1e-7);

    /* Lookup halfway: FOV angles linear, eye positions linear. */
    hs_view_sample v;
    CHECK(hs_pose_stream_sample_views(s, 5000000, &v) == HS_LOOKUP_INTERPOLATED);
    CHECK_NEAR(v.fov[0].angleUp, 0.7, 1e-6);
    CHECK_NEAR(v.fov[1].angleLeft, -0.6, 1e-6);
    CHECK_NEAR(v.pose[1].position.z, 0.05, 1e-6);
    CHECK(hs_pose_stream_sample_views(s, 0, &v) == HS_LOOKUP_EXACT);
    CHECK(hs_pose_stream_sample_views(s, 20000000, &v) == HS_LOOKUP_CLAMPED);
    CHECK_NEAR(v.fov[0].angleUp, 0.6, 1e-7);

    /* Anchoring moves the eyes with the head. */
    XrPosef vp = {.orientation = {0, 0, 0, 1}, .position = {1, 2, 3}};
    hs_pose_stream_anchor(s, vp);
    CHECK_NEAR(s->samples[0].pose.position.x, 1.0, 1e-6);
    CHECK_NEAR(s->samples[0].pose.position.y, 2.0, 1e-6);
    CHECK_NEAR(s->views[0].pose[0].position.x, 1.0 - 0.032, 1e-6);
    CHECK_NEAR(s->views[0].pose[1].position.y, 2.0, 1e-6);
    hs_pose_stream_destroy(&s);
    CHECK(s == NULL);
}

static void test_head_spaces(void)
{
    /* No view records: the head's space records make the stream; controllers are skipped. */
    const char *text =
        "0 s /user/head 0 0 0 1 0 1.7 0 XR_REFERENCE_SPACE_TYPE_STAGE\n"
        "1000 s /user/hand/right/input/aim/pose 0 0 0 1 0.3 1.1 -0.2 XR_REFERENCE_SPACE_TYPE_STAGE\n"
        "2000 s /user/head 0 0.3826834 0 0.9238795 0.1 1.7 0 XR_REFERENCE_SPACE_TYPE_STAGE\n"
        "4000 s XR_REFERENCE_SPACE_TYPE_VIEW 0 0 0 1 0.2 1.7 0 XR_REFERENCE_SPACE_TYPE_STAGE\n"
        "5000 s /user/head 0 0 0 1 9 9 9 XR_REFERENCE_SPACE_TYPE_LOCAL\n";
    xrsc_diag d;
    hs_pose_stream *s = parse(text, HS_POSE_FORMAT_LIBRNR, &d);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK_EQ_INT(s->count, 3); /* the LOCAL-based record is another base space: skipped */
    CHECK(s->views == NULL);
    CHECK_EQ_INT(s->samples[2].time_ns, 4000);
    CHECK_NEAR(s->samples[1].pose.orientation.y, 0.3826834, 1e-7);
    CHECK_NEAR(s->samples[2].pose.position.x, 0.2, 1e-7);
    hs_view_sample v = {0};
    CHECK(hs_pose_stream_sample_views(s, 0, &v) == HS_LOOKUP_CLAMPED);
    hs_pose_stream_destroy(&s);

    /* With views present, head space records are not used. */
    char both[2048];
    snprintf(both, sizeof(both), "%s%s", "0 s /user/head 0 0 0 1 5 5 5 XR_REFERENCE_SPACE_TYPE_LOCAL\n",
             k_views);
    s = parse(both, HS_POSE_FORMAT_AUTO, &d);
    CHECK(s != NULL);
    if (s) {
        CHECK_EQ_INT(s->count, 2);
        CHECK(s->views != NULL);
        CHECK_NEAR(s->samples[0].pose.position.x, 0.0, 1e-7);
    }
    hs_pose_stream_destroy(&s);
}

static void test_pairs(void)
{
    /* An eye without its partner is dropped; views of another space are skipped; a repeated
     * pair at the same time replaces the earlier one. */
    const char *text =
        "0 v XR_REFERENCE_SPACE_TYPE_STAGE 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n"
        "0 v XR_REFERENCE_SPACE_TYPE_STAGE 0 0 0 1 0.03 1 0 0.8 0.7 -0.9 -0.7 2 1\n"
        "100 v XR_REFERENCE_SPACE_TYPE_STAGE 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n"
        "200 v XR_REFERENCE_SPACE_TYPE_LOCAL 0 0 0 1 -0.03 2 0 0.8 0.7 -0.9 -0.7 2 0\n"
        "200 v XR_REFERENCE_SPACE_TYPE_LOCAL 0 0 0 1 0.03 2 0 0.8 0.7 -0.9 -0.7 2 1\n"
        "300 v XR_REFERENCE_SPACE_TYPE_STAGE 0 0 0 1 -0.03 1 1 0.8 0.7 -0.9 -0.7 2 0\n"
        "300 v XR_REFERENCE_SPACE_TYPE_STAGE 0 0 0 1 0.03 1 1 0.8 0.7 -0.9 -0.7 2 1\n"
        "300 v XR_REFERENCE_SPACE_TYPE_STAGE 0 0 0 1 -0.03 1 2 0.8 0.7 -0.9 -0.7 2 0\n"
        "300 v XR_REFERENCE_SPACE_TYPE_STAGE 0 0 0 1 0.03 1 2 0.8 0.7 -0.9 -0.7 2 1\n";
    xrsc_diag d;
    hs_pose_stream *s = parse(text, HS_POSE_FORMAT_AUTO, &d);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK_EQ_INT(s->count, 2);
    CHECK_EQ_INT(s->samples[1].time_ns, 300);
    CHECK_NEAR(s->samples[1].pose.position.z, 2.0, 1e-7);
    CHECK_NEAR(s->views[1].pose[0].position.z, 2.0, 1e-7);
    CHECK(s->dropped_duplicates >= 1);
    hs_pose_stream_destroy(&s);
}

typedef struct bad_case {
    const char *text;
    xrsc_result code;
    int line;
    const char *field;
} bad_case;

static void test_bad_input(void)
{
    static const char v0[] = "0 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n";
    static const bad_case cases[] = {
        {"0 x L 1 2 3\n", XRSC_ERROR_BAD_HEADER, 1, "header"}, /* auto: not librnr at all */
        {"0 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n0 q L\n", XRSC_ERROR_UNKNOWN_COLUMN,
         2, "type"},
        {"0 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2\n", XRSC_ERROR_TRUNCATED_LINE, 1, "index"},
        {"0 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0 7\n", XRSC_ERROR_UNKNOWN_COLUMN, 1,
         "field 17"},
        {"0 v L 0 0 0 1 nan 1 0 0.8 0.7 -0.9 -0.7 2 0\n", XRSC_ERROR_NAN, 1, "px"},
        {"0 v L 0 0 0 1 -0.03 1 0 0.8 abc -0.9 -0.7 2 0\n", XRSC_ERROR_BAD_NUMBER, 1, "right"},
        {"0 v L 0 0 0 2 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n", XRSC_ERROR_QUAT_NOT_UNIT, 1,
         "ox oy oz ow"},
        {"0 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 1 0\n", XRSC_ERROR_UNKNOWN_COLUMN, 1, "type"},
        {"0 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 2\n", XRSC_ERROR_BAD_NUMBER, 1, "index"},
        {"0 v L 0 0 0 1 -0.03 1 0 -0.9 0.7 0.8 -0.7 2 0\n", XRSC_ERROR_BAD_NUMBER, 1,
         "up right down left"},
        {"0 v L 0 0 0 1 -0.03 1 0 1.6 0.7 -0.9 -0.7 2 0\n", XRSC_ERROR_BAD_NUMBER, 1, "up"},
        {"10 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n"
         "5 v L 0 0 0 1 0.03 1 0 0.8 0.7 -0.9 -0.7 2 1\n",
         XRSC_ERROR_TIME_BACKWARDS, 2, "timestamp"},
        {"0 s /user/head 0 0 0 1 0 1 0\n", XRSC_ERROR_TRUNCATED_LINE, 1, "basespace"},
        {"0 s /user/hand/left 0 0 0 1 0 1 0 X\n", XRSC_ERROR_EMPTY_FILE, 0, ""},
        {"0 v L\n", XRSC_ERROR_TRUNCATED_LINE, 1, "ox"},
        {"1.5 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n", XRSC_ERROR_BAD_HEADER, 1,
         "header"}, /* auto: a fractional time is not a librnr record */
        {v0, XRSC_ERROR_EMPTY_FILE, 0, ""}, /* one eye only: no pair */
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        xrsc_diag d;
        hs_pose_stream *s = parse(cases[i].text, HS_POSE_FORMAT_AUTO, &d);
        CHECK_MSG(s == NULL, "case %zu parsed", i);
        hs_pose_stream_destroy(&s);
        CHECK_MSG(d.code == cases[i].code, "case %zu: %d, expected %d", i, (int)d.code,
                  (int)cases[i].code);
        CHECK_MSG(d.line == cases[i].line, "case %zu: line %d, expected %d", i, d.line,
                  cases[i].line);
        CHECK_MSG(strcmp(d.field, cases[i].field) == 0, "case %zu: field '%s', expected '%s'", i,
                  d.field, cases[i].field);
    }
    /* Forced format: a line of another format is a truncated/unknown librnr record. */
    xrsc_diag d;
    hs_pose_stream *s = parse("timestamp,x,y,z,qx,qy,qz,qw\n", HS_POSE_FORMAT_LIBRNR, &d);
    CHECK(s == NULL);
    CHECK(d.code == XRSC_ERROR_TRUNCATED_LINE);
    s = parse("\n\n", HS_POSE_FORMAT_LIBRNR, &d);
    CHECK(s == NULL);
    CHECK(d.code == XRSC_ERROR_EMPTY_FILE);
    /* A NUL byte as the record type is unknown, not a view record (the text holds the NUL). */
    static const char nul[] = "0 v L 0 0 0 1 -0.03 1 0 0.8 0.7 -0.9 -0.7 2 0\n"
                              "0 \0 L 0 0 0 1 0.03 1 0 0.8 0.7 -0.9 -0.7 2 1\n";
    memset(&d, 0, sizeof(d));
    s = NULL;
    CHECK(hs_pose_stream_parse("t.txt", nul, sizeof(nul) - 1, HS_POSE_FORMAT_LIBRNR, &s, &d) ==
          XRSC_ERROR_UNKNOWN_COLUMN);
    CHECK(s == NULL);
    CHECK(d.line == 2 && strcmp(d.field, "type") == 0);
}

/* hs_pose_stream_eyes: what the replay and the runtime's xrLocateViews render with. A stream
 * with recorded views gives them (poses and the recorded asymmetric FOVs, not the headset's);
 * a head-only stream gives the headset's eyes (±IPD/2 along the head's +X) and FOVs. */
static void test_eyes(void)
{
    xrsc_diag d;
    hs_pose_stream *s = parse(k_views, HS_POSE_FORMAT_AUTO, &d);
    CHECK(s != NULL);
    if (!s)
        return;
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    hs.ipd_m = 0.1f; /* not the recording's 64 mm: must not be used */
    hs_view_sample e;
    CHECK(hs_pose_stream_eyes(s, &hs, 0, &e) == HS_LOOKUP_EXACT);
    CHECK(memcmp(&e, &s->views[0], sizeof(e)) == 0);
    CHECK_NEAR(e.fov[0].angleLeft, -0.75, 1e-7);
    CHECK_NEAR(e.fov[0].angleRight, 0.7, 1e-7);
    CHECK_NEAR(e.fov[1].angleLeft, -0.7, 1e-7);
    CHECK_NEAR(e.fov[1].angleRight, 0.75, 1e-7);
    CHECK_NEAR(e.pose[1].position.x - e.pose[0].position.x, 0.064, 1e-6);
    CHECK(hs_pose_stream_eyes(s, &hs, 10000000, &e) == HS_LOOKUP_EXACT);
    CHECK(memcmp(&e, &s->views[1], sizeof(e)) == 0);
    /* Between samples: the views' interpolation (hs_pose_stream_sample_views). */
    hs_view_sample v;
    CHECK(hs_pose_stream_eyes(s, &hs, 2500000, &e) == HS_LOOKUP_INTERPOLATED);
    hs_pose_stream_sample_views(s, 2500000, &v);
    CHECK(memcmp(&e, &v, sizeof(e)) == 0);
    CHECK_NEAR(e.fov[0].angleUp, 0.75, 1e-6);
    hs_pose_stream_destroy(&s);

    /* Head only: the headset's eyes and FOVs. */
    const char *text = "0 s /user/head 0 0.3826834 0 0.9238795 1 1.7 2 XR_REFERENCE_SPACE_TYPE_STAGE\n"
                       "1000 s /user/head 0 0 0 1 1 1.7 2 XR_REFERENCE_SPACE_TYPE_STAGE\n";
    s = parse(text, HS_POSE_FORMAT_LIBRNR, &d);
    CHECK(s != NULL && s->views == NULL);
    if (!s)
        return;
    CHECK(hs_pose_stream_eyes(s, &hs, 0, &e) == HS_LOOKUP_EXACT);
    XrPosef want[2];
    xrsc_headset_eye_poses(&hs, s->samples[0].pose, want);
    for (int k = 0; k < 2; k++) {
        CHECK(memcmp(&e.pose[k], &want[k], sizeof(XrPosef)) == 0);
        CHECK(memcmp(&e.fov[k], &hs.fov[k], sizeof(XrFovf)) == 0);
    }
    CHECK_NEAR(e.pose[1].position.x - e.pose[0].position.x, 0.1 * 0.7071068, 1e-6);
    CHECK(hs_pose_stream_eyes(s, &hs, 5000, &e) == HS_LOOKUP_CLAMPED);
    hs_pose_stream_destroy(&s);
}

static void test_format_name(void)
{
    CHECK(strcmp(hs_pose_format_name(HS_POSE_FORMAT_LIBRNR), "librnr") == 0);
}

int main(void)
{
    RUN(test_views);
    RUN(test_head_spaces);
    RUN(test_pairs);
    RUN(test_bad_input);
    RUN(test_eyes);
    RUN(test_format_name);
    return t_finish();
}
